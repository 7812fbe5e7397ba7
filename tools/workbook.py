#!/usr/bin/env python3
"""tools/workbook.py - a spreadsheet with native charts from your own CSV files (run as tools/workbook).

  tools/workbook FILE.csv [FILE.csv ...] -o BOOK.xlsx [--title TEXT]

Any CSV that motionsim or `make emulate` writes (ramp, filter, servo, pid-replay, ramp --compare,
or any table of numbers under a header) becomes one sheet with its charts, laid out as in
`make profiles`' profiles.xlsx: line charts over evenly spaced times, a ramp's step rate on a
uniform time grid plus XY scatters at the exact step times, bars for a table with a label column.
An index sheet lists the files. A file X.motionsim.csv given with X.csv (what `make emulate`
writes) is drawn dashed over X's charts and gets no sheet of its own: where its times differ from
X's (the emulated servo is sampled every 1 ms, motionsim every 20 ms) its columns join X's sheet
and X's charts are XY scatters; a setpoint equal in both is drawn once. A sheet holds at most 250 rows of a long CSV (every k-th
row, said on the index sheet; the CSV file keeps the full table), so a workbook stays small.
Exit status 0; a missing or malformed CSV is one line on stderr and exit 2.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import motionplot  # noqa: E402
import profiles  # noqa: E402


def main(argv):
    ap = argparse.ArgumentParser(prog="tools/workbook", description="Make an .xlsx workbook with native charts "
                                 "from motionsim / make emulate CSV files.")
    ap.add_argument("csv", nargs="+", help="CSV files written by motionsim or make emulate")
    ap.add_argument("-o", "--output", required=True, help="the workbook to write (.xlsx)")
    a = ap.parse_args(argv)
    if not a.output.endswith(".xlsx"):
        print(f"workbook: the output '{a.output}' must end in .xlsx", file=sys.stderr)
        return 2
    done, stems = [], set()
    try:
        for path in a.csv:
            stem = os.path.splitext(os.path.basename(path))[0]
            if stem in stems:
                print(f"workbook: two files are named {stem}.csv: rename one", file=sys.stderr)
                return 2
            stems.add(stem)
            done.append((path, stem, motionplot.CsvData(path)))
    except (OSError, ValueError) as e:
        print(f"workbook: {e}", file=sys.stderr)
        return 2
    items = []
    for path, stem, data in done:
        s = {"name": stem, "title": stem, "args": [], "source": os.path.abspath(path),
             "label": "motionsim" if stem.endswith(".motionsim") else
             ("firmware (emulated)" if stem + ".motionsim" in stems else stem)}
        if stem + ".motionsim" in stems:
            s["overlay"] = [stem + ".motionsim"]
            s["title"] = f"{stem}: the firmware in the emulator, motionsim dashed"
            other = next(p for p, st, _ in done if st == stem + ".motionsim")
            s["source"] += f" (dashed over it: {os.path.abspath(other)})"
        if stem.endswith(".motionsim") and stem[:-len(".motionsim")] in stems:
            s["sheet"] = False   # already drawn over its firmware file's sheet, whose columns it joins
        items.append((s, data))
    try:
        profiles.write_workbook(a.output, items, source_note="file")
    except OSError as e:
        print(f"workbook: cannot write {a.output}: {e.strerror}", file=sys.stderr)
        return 2
    print(f"{a.output}: {sum(1 for s, _ in items if s.get('sheet', True))} sheet(s) with charts, and an index")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
