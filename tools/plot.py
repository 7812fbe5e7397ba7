#!/usr/bin/env python3
"""tools/plot.py - plot a motionsim CSV to PNG (normally run as tools/plot).

  tools/plot FILE.csv [-o OUT.png] [--title TEXT] [--x COL] [--y COL[,COL...]] [--label NAME] [--overlay LABEL=OTHER.csv ...]

Without -o the PNG goes beside the CSV (FILE.png). The columns to plot are chosen from the
CSV's header (ramp, filter, servo and pid-replay files each get their usual plot); --x/--y
override that. --overlay draws another CSV's same columns dashed on the same axes, e.g. the
exact ramp under the Leib ramp, or motionsim under the firmware's emulated output. Legends name
what each line is: --label names FILE.csv's data (e.g. "Leib"; default with overlays: the file's
name without .csv), LABEL each overlay's (e.g. "exact"); the setpoint or filter input that an
overlay repeats is drawn once. A motionsim CSV holds the rows only, not the algorithm or gains
that made them: say those with --label. Without --title the title says what the rows show: a
ramp's move ("move 0 -> 50 steps, 5.47 s (leib.csv)"), a servo run's setpoint, else the file name.
A CSV with a header and no rows (e.g. a zero-step move) is plotted as empty axes marked "0 rows"
(exit 0); a file that is not CSV text, a malformed row or a missing file is one line on stderr,
exit 2.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import motionplot  # noqa: E402


def main(argv):
    ap = argparse.ArgumentParser(prog="tools/plot", description="Plot a motionsim CSV file to PNG.")
    ap.add_argument("csv", help="CSV file written by motionsim or the emulator harness")
    ap.add_argument("-o", "--output", help="PNG file to write (default: beside the CSV)")
    ap.add_argument("--title", help="plot title (default: the move or setpoint the rows show, and the file name)")
    ap.add_argument("--x", help="column for the x axis")
    ap.add_argument("--y", help="comma-separated columns for a single panel")
    ap.add_argument("--label", help="what FILE.csv is, for the legends (e.g. Leib, 'P, Kp = 0.02'; "
                    "default with overlays: the file's name)")
    ap.add_argument("--overlay", action="append", default=[], metavar="LABEL=CSV",
                    help="draw another CSV's columns dashed on the same axes (repeatable)")
    a = ap.parse_args(argv)
    try:
        data = motionplot.CsvData(a.csv)
        overlays = []
        for spec in a.overlay:
            label, sep, path = spec.partition("=")
            if not sep:
                label, path = os.path.basename(spec), spec
            overlays.append((label, motionplot.CsvData(path)))
        panels = [(a.y.split(","), a.y)] if a.y else None
        out = a.output or os.path.splitext(a.csv)[0] + ".png"
        motionplot.plot(data, out, title=a.title, x=a.x, panels=panels, overlays=overlays, label=a.label)
    except (OSError, ValueError) as e:
        print(f"plot: {e}", file=sys.stderr)
        return 2
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
