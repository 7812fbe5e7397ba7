#!/usr/bin/env python3
"""tools/profiles.py - run the standard scenarios of every capability (what `make profiles` runs).

  profiles.py [--motionsim build/motionsim] [--out build/profiles] [--only NAME_PREFIX]

Scenarios are listed in tools/scenarios/*.json, one file per capability. Each scenario is
  {"name": "ramp_leib_0_50",                  file stem, also the spreadsheet sheet name
   "title": "Leib ramp, 0 -> 50 steps",       plot and chart title
   "args": ["ramp", "--algo", "leib", ...],   motionsim arguments (CSV on stdout)
   "overlay": ["ramp_exact_0_50"],            optional: scenarios drawn dashed on the same axes
   "x": "t_s", "panels": [[["speed_sps"], "step rate (steps/s)"], ...]}   optional plot layout

For each scenario it writes <out>/<name>.csv and <out>/<name>.png, and then one workbook
<out>/profiles.xlsx with an index sheet and, per scenario, a sheet holding the data and a native
Excel chart of each plotted panel (XY scatter with straight lines, so time is to scale even when
steps are unevenly spaced), with the overlays as extra series; a table with a label column
(`ramp --compare`) gets a column chart per deviation instead.
"""
import argparse
import glob
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import motionplot  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load_scenarios():
    scenarios = []
    seen = set()
    for path in sorted(glob.glob(os.path.join(ROOT, "tools", "scenarios", "*.json"))):
        with open(path) as f:
            try:
                items = json.load(f)
            except json.JSONDecodeError as e:
                raise SystemExit(f"profiles: {path}: {e}")
        for s in items:
            for key in ("name", "title", "args"):
                if key not in s:
                    raise SystemExit(f"profiles: {path}: a scenario lacks {key!r}")
            if s["name"] in seen:
                raise SystemExit(f"profiles: duplicate scenario name {s['name']!r}")
            seen.add(s["name"])
            scenarios.append(s)
    return scenarios


def layout_of(s, data):
    x, panels = motionplot.default_layout(data.header)
    if "x" in s:
        x = s["x"]
    if "panels" in s:
        panels = [(p[0], p[1]) for p in s["panels"]]
    return x, panels


def sheet_name(name, used):
    base = name[:31]
    n, cand = 1, base
    while cand in used:
        n += 1
        suffix = f"~{n}"
        cand = base[:31 - len(suffix)] + suffix
    used.add(cand)
    return cand


def write_workbook(path, done):
    import xlsxwriter  # in .venv (requirements.txt)

    wb = xlsxwriter.Workbook(path, {"strings_to_numbers": False, "nan_inf_to_errors": True})
    bold = wb.add_format({"bold": True})
    index = wb.add_worksheet("index")
    index.write_row(0, 0, ["scenario", "title", "rows", "motionsim command"], bold)
    index.set_column(0, 0, 30)
    index.set_column(1, 1, 60)
    index.set_column(3, 3, 90)
    used = {"index"}
    sheets = {}
    for s, data in done:
        sheets[s["name"]] = sheet_name(s["name"], used)
    for row, (s, data) in enumerate(done, start=1):
        sh = sheets[s["name"]]
        index.write_url(row, 0, f"internal:'{sh}'!A1", string=s["name"])
        index.write(row, 1, s["title"])
        index.write_number(row, 2, len(data))
        index.write(row, 3, "motionsim " + " ".join(s["args"]))

    by_name = {s["name"]: (s, data) for s, data in done}
    for s, data in done:
        sh = sheets[s["name"]]
        ws = wb.add_worksheet(sh)
        ws.write_row(0, 0, data.header, bold)
        for c, h in enumerate(data.header):
            ws.write_column(1, c, data.columns[h])
        ws.freeze_panes(1, 0)
        n = len(data)
        col_of = {h: i for i, h in enumerate(data.header)}
        anchor_col = len(data.header) + 1
        if data.labels is not None:
            # a label file (ramp --compare): one column chart per deviation, one bar per label
            cols = [c for c in motionplot.COMPARE_COLUMNS if c[0] in col_of] or \
                   [(h, h) for h in data.header if h != data.labels]
            for p_i, (col, ylabel) in enumerate(cols):
                chart = wb.add_chart({"type": "column"})
                chart.add_series({
                    "name": ylabel,
                    "categories": [sh, 1, col_of[data.labels], n, col_of[data.labels]],
                    "values": [sh, 1, col_of[col], n, col_of[col]],
                    "data_labels": {"value": True, "num_format": "0.###"},
                })
                chart.set_title({"name": s["title"] if p_i == 0 else ylabel, "name_font": {"size": 11}})
                chart.set_y_axis({"name": ylabel})
                chart.set_legend({"none": True})
                chart.set_size({"width": 620, "height": 260})
                ws.insert_chart(n + 3 + p_i * 14, 0, chart)
            continue
        x, panels = layout_of(s, data)
        for p_i, (ycols, ylabel) in enumerate(panels):
            chart = wb.add_chart({"type": "scatter", "subtype": "straight"})
            for y in ycols:
                chart.add_series({
                    "name": y,
                    "categories": [sh, 1, col_of[x], n, col_of[x]],
                    "values": [sh, 1, col_of[y], n, col_of[y]],
                    "line": {"width": 1.5},
                })
            for other_name in s.get("overlay", []):
                if other_name not in by_name:
                    continue
                os_, od = by_name[other_name]
                ocol = {h: i for i, h in enumerate(od.header)}
                for y in ycols:
                    if y in ocol and x in ocol:
                        chart.add_series({
                            "name": f"{y} ({other_name})",
                            "categories": [sheets[other_name], 1, ocol[x], len(od), ocol[x]],
                            "values": [sheets[other_name], 1, ocol[y], len(od), ocol[y]],
                            "line": {"width": 1.0, "dash_type": "dash"},
                        })
            chart.set_title({"name": s["title"] if p_i == 0 else ylabel, "name_font": {"size": 11}})
            chart.set_x_axis({"name": motionplot.AXIS_LABELS.get(x, x), "major_gridlines": {"visible": True}})
            chart.set_y_axis({"name": ylabel})
            chart.set_legend({"position": "bottom"})
            chart.set_size({"width": 760, "height": 330})
            ws.insert_chart(1 + p_i * 17, anchor_col, chart)
    wb.close()


def main(argv):
    ap = argparse.ArgumentParser(prog="tools/profiles.py", description=__doc__.splitlines()[0])
    ap.add_argument("--motionsim", default=os.path.join(ROOT, "build", "motionsim"))
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "profiles"))
    ap.add_argument("--only", help="run only scenarios whose name starts with this")
    a = ap.parse_args(argv)
    if not os.access(a.motionsim, os.X_OK):
        print(f"profiles: {a.motionsim} not found: run 'make sim' first", file=sys.stderr)
        return 1
    os.makedirs(a.out, exist_ok=True)
    scenarios = [s for s in load_scenarios() if not a.only or s["name"].startswith(a.only)]
    if not scenarios:
        print("profiles: no scenarios found in tools/scenarios/*.json", file=sys.stderr)
        return 1
    done, failed = [], []
    for s in scenarios:
        csv_path = os.path.join(a.out, s["name"] + ".csv")
        with open(csv_path, "w") as out:
            p = subprocess.run([a.motionsim] + s["args"], stdout=out, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            failed.append(s["name"])
            print(f"FAIL {s['name']}: motionsim {' '.join(s['args'])}: {p.stderr.strip()}", file=sys.stderr)
            continue
        done.append((s, motionplot.CsvData(csv_path)))
    by_name = {s["name"]: d for s, d in done}
    for s, data in done:
        x, panels = layout_of(s, data) if data.labels is None else (None, None)
        overlays = [(o, by_name[o]) for o in s.get("overlay", []) if o in by_name]
        motionplot.plot(data, os.path.join(a.out, s["name"] + ".png"), title=s["title"], x=x, panels=panels,
                        overlays=overlays)
        print(f"  {s['name']:34s} {len(data):6d} rows  {s['title']}")
    if done:
        write_workbook(os.path.join(a.out, "profiles.xlsx"), done)
    rel = os.path.relpath(a.out, os.getcwd())
    print(f"profiles: {len(done)} scenarios -> {rel}/<name>.csv and <name>.png, workbook {rel}/profiles.xlsx")
    if failed:
        print(f"profiles: {len(failed)} scenario(s) failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
