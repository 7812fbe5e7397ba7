#!/usr/bin/env python3
"""tools/profiles.py - run the standard scenarios of every capability (what `make profiles` runs).

  profiles.py [--motionsim build/motionsim] [--out build/profiles] [--only NAME_PREFIX]

Scenarios are listed in tools/scenarios/*.json, one file per capability. Each scenario is
  {"name": "ramp_leib_0_50",                  file stem, also the spreadsheet sheet name
   "title": "Leib ramp, 0 -> 50 steps",       plot and chart title
   "args": ["ramp", "--algo", "leib", ...],   motionsim arguments (CSV on stdout)
   "overlay": ["ramp_exact_0_50"],            optional: scenarios drawn dashed on the same axes
   "note": "Why it levels off at ...",        optional: printed under the plot (and on the index sheet)
   "x": "t_s",                                optional: the x column (default from the header)
   "panels": [[["speed_sps"], "step rate (steps/s)"],                       optional plot layout:
              [["interval_ticks"], "timer period (ticks)", "step", "step number"]]}
                                              y columns, y label[, own x column[, x label]]

For each scenario it writes <out>/<name>.csv and <out>/<name>.png, and then one workbook
<out>/profiles.xlsx with an index sheet and, per scenario, a sheet with the data and native Excel
charts (see write_workbook): a line chart first (over the rows' own times when they are evenly
spaced, over a uniform resampling grid for a ramp's uneven step times), then for a ramp XY
scatters at the exact step times; a table with a label column (`ramp --compare`) gets a column
chart per deviation instead.
"""
import argparse
import bisect
import glob
import json
import math
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


ALGO_LABELS = {"exact": "exact", "leib": "Leib", "simplistic": "simplistic", "sigmoid": "S-curve"}
KIND_LABELS = {"ma": "moving average", "ma2": "two-stage S-curve", "exp": "exponential"}


def arg_value(args, name, default=None):
    return args[args.index(name) + 1] if name in args and args.index(name) + 1 < len(args) else default


def scenario_label(s):
    """What a scenario's data is, for legends: its "label", else from its motionsim arguments: the
    ramp's algorithm ("exact", "Leib"), the filter ("moving average, tau = 9 s") or the controller
    and its gains ("P, Kp = 0.02")."""
    if "label" in s:
        return s["label"]
    args = s["args"]
    cmd = args[0] if args else ""
    if cmd == "ramp":
        return ALGO_LABELS.get(arg_value(args, "--algo"), arg_value(args, "--algo", "ramp"))
    if cmd == "filter":
        kind = arg_value(args, "--kind", "ma")
        text = f"{KIND_LABELS.get(kind, kind)}, tau = {arg_value(args, '--tau', '?')} s"
        return text + (f", tau2 = {arg_value(args, '--tau2', '?')} s" if kind == "ma2" else "")
    if cmd == "servo":
        if arg_value(args, "--ctrl") == "pid":
            return (f"PID, Kp = {arg_value(args, '--kp', '?')}, Ki = {arg_value(args, '--ki', '0')}, "
                    f"Kd = {arg_value(args, '--kd', '0')}")
        return f"P, Kp = {arg_value(args, '--kp', '?')}"
    return s["name"]


def layout_of(s, data):
    x, panels = motionplot.default_layout(data.header)
    if "x" in s:
        x = s["x"]
    if "panels" in s:
        panels = [tuple(p) for p in s["panels"]]
    return x, panels


def sheet_name(name, used):
    base = "".join("_" if c in "[]:*?/\\" else c for c in name)[:31].strip("'") or "sheet"
    n, cand = 1, base
    while cand in used:
        n += 1
        suffix = f"~{n}"
        cand = base[:31 - len(suffix)] + suffix
    used.add(cand)
    return cand


# ---- the workbook's charts -----------------------------------------------------------------
# Excel's line chart (c:lineChart) spaces its points evenly along a category axis, whatever the
# category values are. That is to scale only when the rows are evenly spaced in time: the filter
# (one row per Ts) and the servo (one row per control period) are drawn as line charts over their
# own t_s column. A ramp has one row per step and its steps are unevenly spaced, so its step rate
# is first resampled on a uniform time grid (GRID_MAX points at most) and that is the line chart;
# an XY scatter at the exact step times follows it.
GRID_MAX = 500           # grid points at most (the step is the smallest 1, 2 or 5 x 10^k that fits)
MAX_LABELS = 12          # category-axis labels at most


def uniform_spacing(xs):
    """The spacing of xs if they are evenly spaced (every difference within 1 ppm of the mean),
    else None."""
    if len(xs) < 2 or any(math.isnan(v) for v in xs):
        return None
    dt = (xs[-1] - xs[0]) / (len(xs) - 1)
    if not dt > 0:
        return None
    for a, b in zip(xs, xs[1:]):
        if not abs((b - a) - dt) <= 1e-6 * dt:
            return None
    return dt


def nice_step(span, max_points):
    """The smallest step of the form 1, 2 or 5 x 10^k with span/step <= max_points."""
    e = math.floor(math.log10(span / max_points))
    for k in (e - 1, e, e + 1):
        for m in (1, 2, 5):
            step = float(f"{m}e{k}")
            if span / step <= max_points:
                return step
    return float(f"1e{e + 2}")


def time_grid(t_end):
    """(dt, [t_j = j*dt for t_j < t_end]): at most GRID_MAX points, at least GRID_MAX/2.5."""
    dt = nice_step(t_end, GRID_MAX)
    times = [round(j * dt, 10) for j in range(math.ceil(t_end / dt) + 1)]
    return dt, [t for t in times if t < t_end]


def held_step_rate(step_times, speeds, t):
    """The step rate at time t by sample-and-hold: row i's speed_sps (F / interval_ticks, the mean
    speed of its interval) for t in [t_(i-1), t_i), where t_0 = 0 is the start of the move; None
    from the last step on (the move is over). step_times must be non-decreasing."""
    i = bisect.bisect_right(step_times, t)
    return speeds[i] if i < len(step_times) else None


def is_ramp(data):
    cols = motionplot.KNOWN[0][0]
    return tuple(data.header[:len(cols)]) == cols


def category_axis(name, n, dt):
    """Line-chart x axis over n evenly spaced times dt apart: a label (and tick) every m points,
    m from 1, 2, 5, 10, 20, 50, ... so that at most MAX_LABELS labels show, with as many decimals
    as m*dt needs."""
    m = 1
    while math.ceil(n / m) > MAX_LABELS:
        m = m * 5 // 2 if str(m)[0] == "2" else m * 2
    label_step = m * dt
    decimals = 0
    while decimals < 9 and abs(round(label_step, decimals) - label_step) > 1e-9 * label_step:
        decimals += 1
    return {"name": name, "interval_unit": m, "interval_tick": m, "position_axis": "on_tick",
            "num_format": "0" if decimals == 0 else "0." + "0" * decimals,
            "major_gridlines": {"visible": True, "line": {"color": "#D9D9D9"}}}


SHEET_ROWS = 250        # a sheet holds at most this many rows of a CSV (the full table stays in the CSV file)


class Thinned:
    """Rows 0, k, 2k, ... of a CsvData (k = ceil(rows / SHEET_ROWS), so at most SHEET_ROWS rows;
    evenly spaced rows stay evenly spaced): what a workbook sheet holds and its charts draw. The
    full table is the CSV file itself; k is shown on the index sheet."""

    def __init__(self, data, max_rows=None):
        max_rows = max_rows or SHEET_ROWS
        n = len(data)
        self.every = max(1, math.ceil(n / max_rows)) if data.labels is None else 1
        self.path, self.header, self.labels, self.full_rows = data.path, data.header, data.labels, n
        self.columns = {h: v[::self.every] for h, v in data.columns.items()}

    def __len__(self):
        return len(self.columns[self.header[0]]) if self.header else 0


def write_workbook(path, done, source_note=None, compare=None):
    """Writes the workbook: an index sheet, then per scenario a sheet with its CSV columns (A...),
    the extra columns its line chart needs (after one blank column) and its charts to the right:
      evenly spaced rows (filter, servo): a line chart per panel over the t_s column; overlays on
          the same time base are copied beside the data as '<column> (<overlay>)';
      a ramp: a line chart of the step rate on a uniform grid ('t_s (grid)', 'speed_sps (grid)'
          and 'speed_sps (grid, <overlay>)', sample-and-hold, see held_step_rate), then an XY
          scatter per panel at the exact step times (overlays drawn from their own sheets);
      a label table (ramp --compare): a column chart per deviation.
    A scenario with "sheet": False gets no sheet of its own (and no index row): it is only an
    overlay (tools/workbook: X.motionsim.csv given with X.csv). Where it is not on the time base
    of the sheet it is drawn over, its columns are written into that sheet (after its own, headed
    '<column> (<overlay>)') and the sheet's charts are XY scatters that read them.
    compare: names of two or more ramps (tools/workbook) to set side by side on a last sheet, "compare"
    (write_ramp_compare)."""
    import xlsxwriter  # in .venv (requirements.txt)

    wb = xlsxwriter.Workbook(path, {"strings_to_numbers": False, "nan_inf_to_errors": True})
    bold = wb.add_format({"bold": True})
    index = wb.add_worksheet("index")
    full = {s["name"]: data for s, data in done}
    done = [(s, Thinned(data)) for s, data in done]
    index.write_row(0, 0, ["scenario", "title", "rows", "charts", source_note or "motionsim command",
                           "rows in the sheet"], bold)
    index.set_column(5, 5, 40)
    index.set_column(0, 0, 30)
    index.set_column(1, 1, 60)
    index.set_column(3, 3, 50)
    index.set_column(4, 4, 90)
    used = {"index"}
    sheets = {}
    for sc, _ in done:
        sc.setdefault("_label", scenario_label(sc))
    labels = {sc["name"]: sc["_label"] for sc, _ in done}
    for sc, _ in done:
        sc["_overlay_labels"] = {o: labels.get(o, o) for o in sc.get("overlay", [])}
    for s, data in done:
        if s.get("sheet", True):
            sheets[s["name"]] = sheet_name(s["name"], used)
    by_name = {s["name"]: (s, data) for s, data in done}

    for row, (s, data) in enumerate([(s, d) for s, d in done if s["name"] in sheets], start=1):
        sh = sheets[s["name"]]
        ws = wb.add_worksheet(sh)
        ws.write_row(0, 0, data.header, bold)
        for c, h in enumerate(data.header):
            ws.write_column(1, c, data.columns[h])
        ws.freeze_panes(1, 0)
        n = len(data)
        col_of = {h: i for i, h in enumerate(data.header)}
        free_col = len(data.header) + 1          # first column of the extra block
        if data.labels is not None:
            what = write_compare_charts(wb, ws, sh, s, data, col_of)
        else:
            x, panels = layout_of(s, data)
            specs = [motionplot.panel_spec(p, x) for p in panels]
            overlays = [(o, by_name[o][1]) for o in s.get("overlay", []) if o in by_name]
            dt = uniform_spacing(data.columns[x]) if all(px == x for _, _, px, _ in specs) else None
            inline = [(o, od) for o, od in overlays if o not in sheets]
            if dt is not None and any(not same_time_base(data, od, x, dt) for _, od in inline):
                dt = None   # an overlay without a sheet on other times: XY scatters read it from this sheet
            charts, what, end_col = [], "", free_col
            inline_cols = {}
            if dt is None and inline:
                free_col, inline_cols = write_inline_overlays(ws, s, specs, inline, free_col, bold)
                end_col = free_col
            if dt is not None:
                charts, what, end_col = uniform_line_charts(wb, ws, sh, s, data, specs, overlays, col_of,
                                                            free_col, dt, bold)
            elif is_ramp(data) and n > 0:
                # the grid is resampled from the full CSV, not from the sheet's rows
                charts, what, end_col = ramp_grid_chart(wb, ws, sh, s, full[s["name"]],
                                                        [(o, full[o]) for o, _ in overlays], free_col, bold)
            elif is_move_path(data) and n > 0:
                charts, what, end_col = move_grid_chart(wb, ws, sh, s, full[s["name"]], free_col, bold)
            if dt is None:
                charts += scatter_charts(wb, sh, s, data, specs, overlays, col_of, sheets, first=not charts,
                                         inline_cols=inline_cols)
                what += ("; " if what else "") + "XY scatter per panel at the exact " + \
                    ("step times" if is_ramp(data) else "x values")
            for i, chart in enumerate(charts):
                ws.insert_chart(1 + i * 17, end_col + 1, chart)
        index.write_url(row, 0, f"internal:'{sh}'!A1", string=s["name"])
        index.write(row, 1, s["title"] + (f" Note: {s['note']}" if s.get("note") else ""))
        index.write_number(row, 2, data.full_rows)
        index.write(row, 3, what)
        index.write(row, 4, s.get("source") or "motionsim " + " ".join(s["args"]))
        index.write(row, 5, "all" if data.every == 1 else
                    f"every {data.every}th row ({len(data)}); the full table: {s['name']}.csv")
    if compare and len(compare) >= 2:
        cname = sheet_name("compare", used)
        what = write_ramp_compare(wb, bold, cname, [(by_name[n][0], full[n], sheets.get(n)) for n in compare])
        row = len(sheets) + 1
        index.write_url(row, 0, f"internal:'{cname}'!A1", string="compare")
        index.write(row, 1, "The ramps side by side: " + ", ".join(by_name[n][0]["_label"] for n in compare))
        index.write_number(row, 2, len(compare))
        index.write(row, 3, what)
        index.write(row, 4, "computed from the sheets above")
        index.write(row, 5, "all")
    wb.close()


def write_ramp_compare(wb, bold, sh, ramps):
    """The sheet `sh` comparing ramps [(scenario, CsvData, its sheet name)]: one row per ramp with its
    label, steps, move time, top step rate, first interval and its move time against the first ramp's;
    below it their step rates on one uniform time grid (held_step_rate, sample-and-hold) drawn in one
    line chart, and an XY scatter of each ramp's step rate at its exact step times (from its own sheet)."""
    ws = wb.add_worksheet(sh)
    first = ramps[0][0]["_label"]
    header = ["ramp", "steps", "move time (s)", "top step rate (steps/s)", "first interval (ticks)",
              f"move time against {first} (%)"]
    ws.write_row(0, 0, header, bold)
    t_first = ramps[0][1].columns["t_s"][-1] if len(ramps[0][1]) else math.nan
    for i, (s, d, _) in enumerate(ramps, start=1):
        t = d.columns["t_s"][-1] if len(d) else math.nan
        ws.write(i, 0, s["_label"])
        ws.write_number(i, 1, len(d))
        ws.write_number(i, 2, t)
        ws.write_number(i, 3, max(d.columns["speed_sps"]) if len(d) else math.nan)
        ws.write_number(i, 4, d.columns["interval_ticks"][0] if len(d) else math.nan)
        ws.write_number(i, 5, 100.0 * (t - t_first) / t_first if t_first > 0 else math.nan)
    ws.set_column(0, 0, 24)
    ws.set_column(1, len(header), 18)
    top = len(ramps) + 3                      # the grid below the table
    t_end = max((d.columns["t_s"][-1] for _, d, _ in ramps if len(d)), default=0.0)
    charts = []
    if t_end > 0:
        dt, grid = time_grid(t_end)
        ws.write(top, 0, "t_s (grid)", bold)
        ws.write_column(top + 1, 0, grid)
        line = wb.add_chart({"type": "line"})
        for k, (s, d, _) in enumerate(ramps, start=1):
            ws.write(top, k, f"speed_sps (grid, {s['_label']})", bold)
            for j, t in enumerate(grid):
                v = held_step_rate(d.columns["t_s"], d.columns["speed_sps"], t) if len(d) else None
                if v is not None:
                    ws.write_number(top + 1 + j, k, v)
            line.add_series({"name": s["_label"], "categories": [sh, top + 1, 0, top + len(grid), 0],
                             "values": [sh, top + 1, k, top + len(grid), k],
                             "line": {"width": 1.5 if k == 1 else 1.2}})
        line.set_title({"name": "Step rate: " + ", ".join(s["_label"] for s, _, _ in ramps), "name_font": {"size": 11}})
        line.set_x_axis(category_axis(f"time (s), uniform grid every {dt:g} s", len(grid), dt))
        line.set_y_axis({"name": "step rate (steps/s)"})
        line.set_legend({"position": "bottom"})
        line.set_size({"width": 760, "height": 330})
        charts.append(line)
    scatter = wb.add_chart({"type": "scatter", "subtype": "straight"})
    for s, d, osh in ramps:
        if osh is None or not len(d):
            continue
        n = math.ceil(len(d) / Thinned(d).every)
        scatter.add_series({"name": s["_label"], "categories": [osh, 1, d.header.index("t_s"), n, d.header.index("t_s")],
                            "values": [osh, 1, d.header.index("speed_sps"), n, d.header.index("speed_sps")],
                            "line": {"width": 1.3}})
    scatter.set_title({"name": "Step rate at the exact step times", "name_font": {"size": 11}})
    scatter.set_x_axis({"name": "time (s)", "major_gridlines": {"visible": True}})
    scatter.set_y_axis({"name": "step rate (steps/s)"})
    scatter.set_legend({"position": "bottom"})
    scatter.set_size({"width": 760, "height": 330})
    charts.append(scatter)
    for i, chart in enumerate(charts):
        ws.insert_chart(1 + i * 17, len(header) + 1, chart)
    return "a row per ramp; line chart of their step rates on one grid; XY scatter at the exact step times"


def own_series_label(y, s, ycols):
    """The legend of a sheet's own column: as in the PNGs (motionplot.plot), a reference column
    (the setpoint, the filter's input) among others is just what it is, the same for every data set."""
    if y in motionplot.REFERENCE_COLUMNS and len(ycols) > 1:
        return motionplot.SERIES_NAMES.get(y, y)
    return motionplot.series_label(y, s["_label"], len(ycols))


def same_time_base(data, od, x, dt):
    """True if the overlay's x column runs on data's times (its first rows equal data's within 1 ppm
    of dt): uniform_line_charts then copies it beside data's columns."""
    ox = od.columns.get(x)
    m = min(len(data), len(od)) if ox is not None else 0
    return m > 0 and all(abs(a - b) <= 1e-6 * dt for a, b in zip(data.columns[x][:m], ox[:m]))


def write_inline_overlays(ws, s, specs, inline, free_col, bold):
    """The columns of overlays without a sheet of their own that the panels draw (x and y), written
    into this sheet from free_col on, '<column> (<overlay>)'. Returns (the next free column,
    {overlay: {column: (sheet column, rows)}})."""
    cols = {}
    for oname, od in inline:
        label = s["_overlay_labels"].get(oname, oname)
        cols[oname] = {}
        wanted = []
        for ycols, _, px, _ in specs:
            for c in [px] + list(ycols):
                if c in od.columns and c not in wanted:
                    wanted.append(c)
        for c in wanted:
            ws.write(0, free_col, f"{c} ({label})", bold)
            ws.write_column(1, free_col, od.columns[c])
            cols[oname][c] = (free_col, len(od))
            free_col += 1
    return free_col + 1, cols


def write_compare_charts(wb, ws, sh, s, data, col_of):
    """A label file (ramp --compare): one column chart per deviation, one bar per label, below the table."""
    n = len(data)
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
    return "column chart per deviation"


def uniform_line_charts(wb, ws, sh, s, data, specs, overlays, col_of, free_col, dt, bold):
    """Evenly spaced rows: a line chart per panel over the x column. An overlay whose x column runs
    on the same times (its first rows equal ours within 1 ppm of dt) is copied into this sheet,
    at most as many rows as ours, and drawn dashed; others are left out of the line chart."""
    n = len(data)
    xs = data.columns[specs[0][2]]
    charts = []
    for p_i, (ycols, ylabel, px, xlabel) in enumerate(specs):
        chart = wb.add_chart({"type": "line"})
        for y in ycols:
            chart.add_series({"name": own_series_label(y, s, ycols),
                              "categories": [sh, 1, col_of[px], n, col_of[px]],
                              "values": [sh, 1, col_of[y], n, col_of[y]], "line": {"width": 1.5}})
        for oname, od in overlays:
            ox = od.columns.get(px)
            if ox is None:
                continue
            m = min(n, len(od))
            if m == 0 or any(not abs(a - b) <= 1e-6 * dt for a, b in zip(xs[:m], ox[:m])):
                continue
            for y in ycols:
                if y not in od.columns:
                    continue
                if y in motionplot.REFERENCE_COLUMNS and motionplot.same_series(
                        od.columns[px][:m], od.columns[y][:m], xs[:m], data.columns[y][:m]):
                    continue   # the same setpoint / input: drawn once
                ws.write(0, free_col, f"{y} ({oname})", bold)
                ws.write_column(1, free_col, od.columns[y][:m])
                chart.add_series({"name": motionplot.series_label(y, s["_overlay_labels"].get(oname, oname), len(ycols)),
                                  "categories": [sh, 1, col_of[px], n, col_of[px]],
                                  "values": [sh, 1, free_col, m, free_col],
                                  "line": {"width": 1.0, "dash_type": "dash"}})
                free_col += 1
        chart.set_title({"name": s["title"] if p_i == 0 else ylabel, "name_font": {"size": 11}})
        chart.set_x_axis(category_axis(xlabel, n, dt))
        chart.set_y_axis({"name": ylabel})
        chart.set_legend({"position": "bottom"})
        chart.set_size({"width": 760, "height": 330})
        charts.append(chart)
    return charts, "line chart per panel (rows are evenly spaced in time)", free_col


def ramp_grid_chart(wb, ws, sh, s, data, overlays, free_col, bold):
    """A ramp: its step rate (and each ramp overlay's) resampled on one uniform time grid from 0
    to the end of the longest move (held_step_rate), written beside the data and drawn as a line chart."""
    series = [("speed_sps (grid)", data)] + \
             [(f"speed_sps (grid, {o})", od) for o, od in overlays if is_ramp(od) and len(od) > 0]
    series = [(name, d) for name, d in series
              if all(a <= b for a, b in zip(d.columns["t_s"], d.columns["t_s"][1:]))]
    if not series or series[0][1] is not data:
        return [], "", free_col
    series_names = [None] + [next((o for o, od in overlays if od is d), None) for _, d in series[1:]]
    t_end = max(d.columns["t_s"][-1] for _, d in series)
    if not t_end > 0:
        return [], "", free_col
    dt, grid = time_grid(t_end)
    g0 = free_col
    ws.write(0, g0, "t_s (grid)", bold)
    ws.write_column(1, g0, grid)
    ws.write_comment(0, g0 + 1,
                     f"Step rate on a uniform {dt:g} s grid, sample-and-hold: at grid time t, the "
                     "speed_sps of the step whose interval [t_(i-1), t_i) contains t (t_0 = 0, the "
                     "start of the move); empty once the move is over.", {"x_scale": 2, "y_scale": 1.5})
    chart = wb.add_chart({"type": "line"})
    for k, (name, d) in enumerate(series):
        c = g0 + 1 + k
        ws.write(0, c, name, bold)
        ts, vs = d.columns["t_s"], d.columns["speed_sps"]
        for j, t in enumerate(grid):
            v = held_step_rate(ts, vs, t)
            if v is not None:
                ws.write_number(1 + j, c, v)
        chart.add_series({"name": (s["_label"] if k == 0 else s["_overlay_labels"].get(series_names[k], name)),
                          "categories": [sh, 1, g0, len(grid), g0],
                          "values": [sh, 1, c, len(grid), c],
                          "line": {"width": 1.5} if k == 0 else {"width": 1.0, "dash_type": "dash"}})
    ws.set_column(g0, g0 + len(series), 14)
    chart.set_title({"name": s["title"], "name_font": {"size": 11}})
    chart.set_x_axis(category_axis(f"time (s), uniform grid every {dt:g} s", len(grid), dt))
    chart.set_y_axis({"name": "step rate (steps/s)"})
    chart.set_legend({"position": "bottom"})
    chart.set_size({"width": 760, "height": 330})
    return [chart], f"line chart of step rate on a {dt:g} s grid (sample-and-hold)", g0 + len(series) + 1


MOVE_PATH_COLUMNS = ("t_s", "x_pos", "y_pos", "z_pos", "x_speed_sps", "y_speed_sps", "z_speed_sps")


def is_move_path(data):
    """`motionsim move --path`: one row per tick with an edge of any axis (unevenly spaced)"""
    return tuple(data.header[:len(MOVE_PATH_COLUMNS)]) == MOVE_PATH_COLUMNS


def move_grid_chart(wb, ws, sh, s, data, free_col, bold):
    """A coordinated move: each moving axis's step rate resampled on a uniform time grid (sample and
    hold: at grid time t, the axis's speed in the last row at or before t, i.e. over its last interval
    completed by then), written beside the data and drawn as a line chart."""
    ts = data.columns["t_s"]
    axes = [a for a in "xyz" if any(v != 0 for v in data.columns[f"{a}_speed_sps"])]
    if not axes or not ts[-1] > 0:
        return [], "", free_col
    dt, grid = time_grid(ts[-1])
    g0 = free_col
    ws.write(0, g0, "t_s (grid)", bold)
    ws.write_column(1, g0, grid)
    ws.write_comment(0, g0 + 1,
                     f"Each axis's step rate on a uniform {dt:g} s grid, sample-and-hold: at grid time t, "
                     "its speed in the last row at or before t (F over its last interval completed by then).",
                     {"x_scale": 2, "y_scale": 1.5})
    chart = wb.add_chart({"type": "line"})
    for k, a in enumerate(axes):
        c = g0 + 1 + k
        ws.write(0, c, f"speed_sps (grid): {a.upper()}", bold)
        vs = data.columns[f"{a}_speed_sps"]
        for j, t in enumerate(grid):
            i = bisect.bisect_right(ts, t) - 1
            ws.write_number(1 + j, c, vs[i] if i >= 0 else 0.0)
        chart.add_series({"name": f"{a.upper()} step rate, {s['_label']}", "categories": [sh, 1, g0, len(grid), g0],
                          "values": [sh, 1, c, len(grid), c], "line": {"width": 1.5}})
    ws.set_column(g0, g0 + len(axes), 14)
    chart.set_title({"name": s["title"], "name_font": {"size": 11}})
    chart.set_x_axis(category_axis(f"time (s), uniform grid every {dt:g} s", len(grid), dt))
    chart.set_y_axis({"name": "step rate (steps/s)"})
    chart.set_legend({"position": "bottom"})
    chart.set_size({"width": 760, "height": 330})
    return [chart], f"line chart of each axis's step rate on a {dt:g} s grid (sample-and-hold)", g0 + len(axes) + 1


def scatter_charts(wb, sh, s, data, specs, overlays, col_of, sheets, first, inline_cols=None):
    """An XY scatter with straight lines per panel: x to scale whatever its spacing. Overlays are
    drawn dashed from their own sheets, or (inline_cols, see write_inline_overlays) from the
    columns written into this sheet. A reference column (the setpoint) equal in value to the
    data's wherever both are defined is drawn once (motionplot.same_series)."""
    inline_cols = inline_cols or {}
    n = len(data)
    charts = []
    for p_i, (ycols, ylabel, px, xlabel) in enumerate(specs):
        chart = wb.add_chart({"type": "scatter", "subtype": "straight"})
        for y in ycols:
            chart.add_series({"name": own_series_label(y, s, ycols), "categories": [sh, 1, col_of[px], n, col_of[px]],
                              "values": [sh, 1, col_of[y], n, col_of[y]], "line": {"width": 1.5}})
        for oname, od in overlays:
            if oname in inline_cols:
                osh, loc = sh, {c: ci for c, (ci, _) in inline_cols[oname].items()}
            elif oname in sheets:
                osh, loc = sheets[oname], {h: i for i, h in enumerate(od.header)}
            else:
                continue
            for y in ycols:
                if y in loc and px in loc:
                    if y in motionplot.REFERENCE_COLUMNS and motionplot.same_series(
                            od.columns[px], od.columns[y], data.columns[px], data.columns[y]):
                        continue
                    chart.add_series({"name": motionplot.series_label(y, s["_overlay_labels"].get(oname, oname),
                                                                      len(ycols)),
                                      "categories": [osh, 1, loc[px], len(od), loc[px]],
                                      "values": [osh, 1, loc[y], len(od), loc[y]],
                                      "line": {"width": 1.0, "dash_type": "dash"}})
        title = s["title"] if first and p_i == 0 else f"{ylabel} by {xlabel}"
        chart.set_title({"name": title, "name_font": {"size": 11}})
        chart.set_x_axis({"name": xlabel, "major_gridlines": {"visible": True}})
        chart.set_y_axis({"name": ylabel})
        chart.set_legend({"position": "bottom"})
        chart.set_size({"width": 760, "height": 330})
        charts.append(chart)
    return charts


def main(argv):
    ap = argparse.ArgumentParser(prog="tools/profiles.py", description=__doc__.splitlines()[0])
    ap.add_argument("--motionsim", default=os.path.join(ROOT, "build", "motionsim"))
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "profiles"))
    ap.add_argument("--only", help="run only scenarios whose name starts with this (and the scenarios they overlay)")
    a = ap.parse_args(argv)
    if not os.access(a.motionsim, os.X_OK):
        print(f"profiles: {a.motionsim} not found: run 'make sim' first", file=sys.stderr)
        return 1
    os.makedirs(a.out, exist_ok=True)
    every = load_scenarios()
    scenarios = [s for s in every if not a.only or s["name"].startswith(a.only)]
    # --only keeps each chosen scenario's overlays (and theirs): they are run too
    names = {s["name"] for s in scenarios}
    grew = True
    while grew:
        extra = [s for s in every if s["name"] not in names and
                 any(s["name"] in c.get("overlay", []) for c in every if c["name"] in names)]
        grew = bool(extra)
        names |= {s["name"] for s in extra}
    scenarios = [s for s in every if s["name"] in names]
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
    by_name = {s["name"]: (s, d) for s, d in done}
    for s, data in done:
        x, panels = layout_of(s, data) if data.labels is None else (None, None)
        overlays = [(scenario_label(by_name[o][0]), by_name[o][1]) for o in s.get("overlay", []) if o in by_name]
        motionplot.plot(data, os.path.join(a.out, s["name"] + ".png"), title=s["title"], x=x, panels=panels,
                        overlays=overlays, label=scenario_label(s), note=s.get("note"))
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
