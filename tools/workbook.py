#!/usr/bin/env python3
"""tools/workbook.py - a spreadsheet with native charts from your own CSV files (run as tools/workbook).

  tools/workbook FILE.csv [FILE.csv ...] -o BOOK.xlsx [--label NAME ...]

Any CSV that motionsim or `make emulate` writes (ramp, filter, servo, pid-replay, ramp --compare,
or any table of numbers under a header) becomes one sheet with its charts, laid out as in
`make profiles`' profiles.xlsx: line charts over evenly spaced times, a ramp's step rate on a
uniform time grid plus XY scatters at the exact step times, bars for a table with a label column.
--label names the files, in order, as tools/plot's --label does (the first --label the first file, ...):
a sheet is named after its label (a file without one: after its name, e.g. `table`), and its charts'
legends say it. Two or more ramps (motionsim ramp, or the emulated move of a stepper) also get a sheet
`compare`: a row per ramp (steps, move time, top step rate, first interval, move time against the
first), their step rates on one time grid in one chart, and each at its exact step times.
An index sheet lists the files by name (never a full path). A file X.motionsim.csv given with X.csv (what `make emulate`
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
    ap.add_argument("--label", action="append", default=[],
                    help="what a file is (e.g. simplistic, Leib): the first --label names the first file, and so "
                    "on; its sheet and legends are named so (default: the file's name)")
    a = ap.parse_args(argv)
    if not a.output.endswith(".xlsx"):
        print(f"workbook: the output '{a.output}' must end in .xlsx", file=sys.stderr)
        return 2
    if len(a.label) > len(a.csv):
        print(f"workbook: {len(a.label)} --label for {len(a.csv)} file(s): one --label per file, in order",
              file=sys.stderr)
        return 2
    for lab in a.label:
        if not lab.strip() or any(c in lab for c in "[]:*?/\\") or len(lab) > 31:
            print(f"workbook: --label '{lab}' cannot name a sheet (1 to 31 characters, none of [ ] : * ? / \\)",
                  file=sys.stderr)
            return 2
    if len(set(a.label)) != len(a.label):
        print("workbook: two files have the same --label", file=sys.stderr)
        return 2
    labels = dict(zip(a.csv, a.label))
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
    name_of = {stem: labels.get(path) or stem for path, stem, _ in done}
    items = []
    for path, stem, data in done:
        lab = labels.get(path)
        if lab and lab != stem and lab in stems:
            print(f"workbook: --label '{lab}' is the name of another file", file=sys.stderr)
            return 2
        # the index names each file by its name only: a workbook carries no path of the machine it was made on
        s = {"name": lab or stem, "title": stem if not lab else f"{lab} ({stem}.csv)", "args": [],
             "source": os.path.basename(path),
             "label": lab or ("motionsim" if stem.endswith(".motionsim") else
                              ("firmware (emulated)" if stem + ".motionsim" in stems else stem))}
        if stem + ".motionsim" in stems:
            s["overlay"] = [name_of[stem + ".motionsim"]]
            s["title"] = f"{lab or stem}: the firmware in the emulator, motionsim dashed"
            other = next(p for p, st, _ in done if st == stem + ".motionsim")
            s["source"] += f" (dashed over it: {os.path.basename(other)})"
        if stem.endswith(".motionsim") and stem[:-len(".motionsim")] in stems:
            s["sheet"] = False   # already drawn over its firmware file's sheet, whose columns it joins
        items.append((s, data))
    ramps = [s["name"] for s, data in items if s.get("sheet", True) and profiles.is_ramp(data)]
    try:
        profiles.write_workbook(a.output, items, source_note="file", compare=ramps if len(ramps) >= 2 else None)
    except OSError as e:
        print(f"workbook: cannot write {a.output}: {e.strerror}", file=sys.stderr)
        return 2
    print(f"{a.output}: {sum(1 for s, _ in items if s.get('sheet', True))} sheet(s) with charts"
          f"{', a sheet comparing the ramps' if len(ramps) >= 2 else ''}, and an index")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
