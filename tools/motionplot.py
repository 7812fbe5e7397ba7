"""tools/motionplot.py - read motionsim CSV files and plot them (used by tools/plot and tools/profiles.py).

Every CSV that motionsim (or the emulator harness) writes has one header line and numeric rows.
The kind of file is recognised from its header and gets the plot a user expects:

  ramp        step,position,t_s,interval_ticks,speed_sps,accel_sps2  -> step rate and acceleration vs time
  filter      k,t_s,u,y                                              -> input and output voltage vs time (one panel)
  filter --stream  t_ms,u,y (the MovingAverageFilter sketch's lines) -> the same, vs time in ms
  servo       t_s,setpoint,position_counts,error_counts,duty_pct     -> position/setpoint and duty vs time
  pid-replay  t_ms,computed,output                                   -> controller output vs time
  ramp --compare  algo,steps,move_time_s,...                         -> bars of each algorithm's deviations
  anything else                                                      -> every column vs the first one
A file whose first column holds text (labels, like `ramp --compare`'s algorithm names) is drawn
as bars, one panel per numeric column; text anywhere else is an error. A header with no rows
(a zero-step move) is valid and gets empty axes marked "0 rows"; a file that is not UTF-8 text
(or holds NUL bytes) is refused as "not a text CSV file".
"""
import bisect
import csv
import io
import math
import os
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# header columns -> (x column, [panels: (y columns, axis label)])
KNOWN = [
    (("step", "position", "t_s", "interval_ticks", "speed_sps", "accel_sps2"),
     ("t_s", [(["speed_sps"], "step rate (steps/s)"), (["accel_sps2"], "acceleration (steps/s²)")])),
    (("k", "t_s", "u", "y"),
     ("t_s", [(["u", "y"], "voltage (V)")])),
    (("t_s", "setpoint", "position_counts", "error_counts", "duty_pct"),
     ("t_s", [(["setpoint", "position_counts"], "position (encoder counts)"), (["duty_pct"], "PWM duty (%)")])),
    (("t_ms", "u", "y"),
     ("t_ms", [(["u", "y"], "voltage (V)")])),
    (("t_ms", "computed", "output"),
     ("t_ms", [(["output"], "controller output")])),
]

# bar panels for label files: ramp --compare shows the deviations a user asks about
COMPARE_COLUMNS = [("move_time_dev_pct", "move time vs exact (%)"),
                   ("interval_max_dev_pct", "largest interval error (%)"),
                   ("interval_rms_dev_pct", "RMS interval error (%)"),
                   ("accel_max_dev_pct", "largest acceleration error (% of a)")]

# what a column is, for legends (a legend names the series, never the CSV column)
SERIES_NAMES = {"speed_sps": "step rate", "accel_sps2": "acceleration", "interval_ticks": "timer period",
                "u": "input u", "y": "output y", "setpoint": "setpoint", "position_counts": "position",
                "error_counts": "error", "duty_pct": "duty", "output": "output", "computed": "computed",
                "y_pos": "path (Y against X)", "x_speed_sps": "X step rate", "y_speed_sps": "Y step rate",
                "z_speed_sps": "Z step rate", "path_err_steps": "distance from the line",
                "x_position": "X position", "y_position": "Y position", "z_position": "Z position"}
# columns that are inputs rather than results: drawn once, not again for each overlay that has the same
REFERENCE_COLUMNS = ("setpoint", "u")
# a panel with more rows than this, whose values jump back and forth, also gets its moving mean
MOVING_MEAN_MIN_ROWS = 200

AXIS_LABELS = {"t_s": "time (s)", "t_ms": "time (ms)", "step": "step number", "k": "sample k"}


class CsvData:
    """Columns of a motionsim CSV as lists of floats (empty cells become NaN).
    A header with no rows is valid (e.g. `motionsim ramp --from 5 --to 5`, a move of zero steps)."""

    def __init__(self, path):
        self.path = path
        try:
            with open(path, newline="", encoding="utf-8") as f:
                text = f.read()
        except UnicodeDecodeError:
            raise ValueError(f"{path}: not a text CSV file (not UTF-8 text)") from None
        if "\x00" in text:
            raise ValueError(f"{path}: not a text CSV file (it holds NUL bytes)")
        try:
            rows = list(csv.reader(io.StringIO(text, newline="")))
        except csv.Error as e:
            raise ValueError(f"{path}: not a text CSV file ({e})") from None
        if not rows or not any(h.strip() for h in rows[0]):
            raise ValueError(f"{path}: empty file (no header line)")
        self.header = [h.strip() for h in rows[0]]
        self.columns = {h: [] for h in self.header}
        body = [r for r in rows[1:] if r]
        # a first column of text is a label column (e.g. ramp --compare's algorithm names)
        self.labels = None
        if body and self.header:
            try:
                [float(r[0]) for r in body if r[0].strip() != ""]
            except ValueError:
                self.labels = self.header[0]
        for lineno, row in enumerate(rows[1:], start=2):
            if not row:
                continue
            if len(row) != len(self.header):
                raise ValueError(f"{path}:{lineno}: {len(row)} fields, the header has {len(self.header)}")
            for h, cell in zip(self.header, row):
                if h == self.labels:
                    self.columns[h].append(cell.strip())
                    continue
                try:
                    self.columns[h].append(float(cell) if cell.strip() != "" else math.nan)
                except ValueError:
                    raise ValueError(f"{path}:{lineno}: column {h}: {cell!r} is not a number") from None

    def __len__(self):
        return len(self.columns[self.header[0]]) if self.header else 0


def panel_spec(panel, x):
    """A panel is (y columns, y label) drawn against the figure's x column, or
    (y columns, y label, x column[, x label]) with its own x (e.g. the sigmoid's period by step).
    Returns (y columns, y label, x column, x label)."""
    ycols, ylabel = panel[0], panel[1]
    px = panel[2] if len(panel) > 2 and panel[2] else x
    xlabel = panel[3] if len(panel) > 3 and panel[3] else AXIS_LABELS.get(px, px)
    return list(ycols), ylabel, px, xlabel


def default_layout(header):
    """(x column, panels) for a header: a known motionsim kind, or every column vs the first."""
    for cols, layout in KNOWN:
        if tuple(header[:len(cols)]) == cols:
            return layout
    return header[0], [([h for h in header[1:]], "value")]


def plot_bars(data, out_png, title=None, columns=None):
    """One bar panel per numeric column, one bar per label (row)."""
    if columns is None:
        known = [(c, l) for c, l in COMPARE_COLUMNS if c in data.columns]
        columns = known or [(h, h) for h in data.header if h != data.labels]
    labels = data.columns[data.labels]
    fig, axes = plt.subplots(len(columns), 1, figsize=(8, 2.2 * len(columns) + 0.6), squeeze=False)
    for ax, (col, ylabel) in zip(axes[:, 0], columns):
        if col not in data.columns or col == data.labels:
            raise ValueError(f"{data.path}: no numeric column {col!r} (columns: {', '.join(data.header)})")
        values = data.columns[col]
        bars = ax.bar(range(len(labels)), values, color="tab:blue")
        ax.bar_label(bars, labels=[f"{v:.3g}" for v in values], fontsize="small")
        ax.set_xticks(range(len(labels)), labels)
        ax.set_ylabel(ylabel, fontsize="small")
        ax.grid(True, axis="y", alpha=0.35)
        ax.margins(y=0.2)
    fig.suptitle(textwrap.fill(title or os.path.basename(data.path), 100))
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)


def series_label(column, label, n_columns):
    """The legend text of one line: the data set's label (e.g. "Leib", "P, Kp = 0.02", "motionsim"),
    with what the column is when the panel has several columns ("setpoint", "position, motionsim")."""
    name = SERIES_NAMES.get(column, column)
    if n_columns == 1:
        return label or name
    return f"{name}, {label}" if label else name


def same_series(xa, ya, xb, yb):
    """True if two series agree in value wherever both are defined: over the x range they share,
    every point of each equals the other's value there (between two of its points, either one:
    a setpoint that steps between them). E.g. the same setpoint over 3 s and over 5 s, or sampled
    every 1 ms by the emulator and every 20 ms by motionsim. Series whose x values are not sorted
    must be identical where both have points (the shorter a prefix of the longer)."""
    a = [(x, y) for x, y in zip(xa, ya) if not math.isnan(x)]
    b = [(x, y) for x, y in zip(xb, yb) if not math.isnan(x)]
    if not a or not b:
        return False

    def eq(p, q):
        return p == q or (math.isnan(p) and math.isnan(q))

    def ascending(pts):
        return all(p[0] <= q[0] for p, q in zip(pts, pts[1:]))
    if not (ascending(a) and ascending(b)):
        m = min(len(xa), len(xb))
        return all(eq(p, q) for p, q in zip(xa[:m], xb[:m])) and all(eq(p, q) for p, q in zip(ya[:m], yb[:m]))
    lo, hi = max(a[0][0], b[0][0]), min(a[-1][0], b[-1][0])
    if lo > hi:
        return False

    def agrees(pts, other):
        ox = [x for x, _ in other]
        for x, y in pts:
            if x < lo or x > hi:
                continue
            i = bisect.bisect_left(ox, x)
            if i < len(ox) and ox[i] == x:
                near = [v for u, v in other[i:bisect.bisect_right(ox, x)]]
            else:
                near = [other[j][1] for j in (i - 1, i) if 0 <= j < len(other)]
            if not any(eq(y, v) for v in near):
                return False
        return True
    return agrees(a, b) and agrees(b, a)


def is_jumpy(ys):
    """True for a long series that jumps back and forth (e.g. an S-curve's acceleration per step,
    near 0 within a table entry and a spike at the next): as a line it fills a solid block, so its
    moving mean is drawn over it. Measure: the path up and down is over 40 times its range."""
    v = [y for y in ys if not math.isnan(y)]
    if len(v) < MOVING_MEAN_MIN_ROWS:
        return False
    span = max(v) - min(v)
    travel = sum(abs(b - a) for a, b in zip(v, v[1:]))
    return span > 0 and travel > 40 * span


def moving_mean(ys, window):
    out, acc, q = [], 0.0, []
    for y in ys:
        y = 0.0 if math.isnan(y) else y
        q.append(y)
        acc += y
        if len(q) > window:
            acc -= q.pop(0)
        out.append(acc / len(q))
    # centred: shift back by half the window
    h = window // 2
    return out[h:] + [out[-1]] * h if len(out) > h else out


def what_it_shows(data):
    """(what, seconds) a CSV's own rows show: a ramp's move ("move 0 -> 50 steps", from the first
    step's position and the direction of the last) and its time, a servo run's setpoint ("setpoint
    1000 counts") and its length; (None, None) for any other file."""
    cols = data.columns
    if len(data) == 0 or data.labels is not None:
        return None, None
    if tuple(data.header[:6]) == KNOWN[0][0]:
        pos = [p for p in cols["position"] if not math.isnan(p)]
        if pos and all(b - a in (1, -1) for a, b in zip(pos, pos[1:])) and \
                len({b - a for a, b in zip(pos, pos[1:])}) <= 1:
            sign = -1 if len(pos) > 1 and pos[1] < pos[0] else 1
            return f"move {pos[0] - sign:g} -> {pos[-1]:g} steps", cols["t_s"][-1]
    if tuple(data.header[:5]) == KNOWN[2][0]:
        sps = {v for v in cols["setpoint"] if not math.isnan(v)}
        if len(sps) == 1:
            return f"setpoint {sps.pop():g} counts", cols["t_s"][-1] - cols["t_s"][0]
    return None, None


def default_title(data, overlays=(), label=None):
    """What the CSV shows, said by its own rows: a ramp's move ("move 0 -> 50 steps, 5.47 s", see
    what_it_shows), a servo run's setpoint ("setpoint 1000 counts, 3 s"), then the file's name; for
    any other file its name. With overlays (a plot of several files) every file is named, with its
    time: "move 0 -> 50 steps: simplistic 11.2 s (table.csv), Leib 5.47 s (leib.csv)" when they show
    the same move or setpoint, else each file's own title joined by "; "."""
    def one(d):
        what, secs = what_it_shows(d)
        name = os.path.basename(d.path)
        return what, (f"{secs:.3g} s ({name})" if what else name)
    if not overlays:
        what, rest = one(data)
        return f"{what}, {rest}" if what else rest
    items = [(label or os.path.splitext(os.path.basename(data.path))[0], data)] + list(overlays)
    parts = [(lab,) + one(d) for lab, d in items]
    whats = {w for _, w, _ in parts}
    if len(whats) == 1 and None not in whats:
        return f"{parts[0][1]}: " + ", ".join(f"{lab} {rest}" for lab, _, rest in parts)
    return "; ".join(f"{lab}: {w + ', ' if w else ''}{rest}" for lab, w, rest in parts)


def legend_hides_data(ax, legend, renderer):
    """True if a line of the panel (any segment, not only its points) runs under the legend's box."""
    from matplotlib.path import Path
    box = legend.get_window_extent(renderer)
    for line in ax.get_lines():
        xy = [p for p in line.get_xydata() if not (math.isnan(p[0]) or math.isnan(p[1]))]
        if not xy:
            continue
        disp = ax.transData.transform(xy)
        if len(disp) == 1:
            if box.contains(*disp[0]):
                return True
        elif Path(disp).intersects_bbox(box, filled=False):
            return True
    return False


def place_legends(fig, axes):
    """Each panel's legend where matplotlib finds room ("best"); a legend that would still hide
    data (a panel filled edge to edge, e.g. a square wave and its filtered outputs) goes outside
    the panel, to its right, and the figure is widened by the legend's width."""
    renderer = fig.canvas.get_renderer()   # no full draw: the legends' "best" places are found on demand
    widest = 0.0
    for ax in axes:
        leg = ax.get_legend()
        if leg is None or not legend_hides_data(ax, leg, renderer):
            continue
        leg.remove()
        leg = ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize="small")
        widest = max(widest, leg.get_window_extent(renderer).width / fig.dpi)
    if widest:
        w, h = fig.get_size_inches()
        fig.set_size_inches(w + widest + 0.2, h)


def note_height(note):
    """the share of the figure's height that a note under the panels takes (its wrapped lines)"""
    return 0.03 + 0.022 * len(textwrap.wrap(note, 150))


def plot(data, out_png, title=None, x=None, panels=None, overlays=(), label=None, note=None):
    """Plots `data` into out_png. overlays: [(label, CsvData)] drawn dashed on the same panels
    (e.g. the exact ramp under the Leib ramp, or the simulator under the firmware).
    label: what `data` is, for the legends (e.g. "Leib", "firmware (emulated)"); legends name the
    series (series_label), never the CSV columns. A reference column (the setpoint, the filter's
    input) that an overlay has equal in value to an earlier line of the same column wherever both
    are defined (same_series: also when sampled at other times) is not drawn twice. A long series that
    jumps back and forth at every point (an S-curve's acceleration) is drawn thin and pale with its
    moving mean over it.
    panels: [(y columns, y label[, x column[, x label]])] (see panel_spec); x: the default x column.
    A file with a label column is drawn as bars (plot_bars); a file with a header and no rows
    gets its usual (empty) axes with the note "0 rows". Without a title, default_title says what the
    rows show (a ramp's move, a servo's setpoint); without a label but with overlays, `data` is
    named by its file (e.g. "table" for table.csv), as an overlay given without LABEL= is; a plot with
    overlays is titled with every file and its time. note: a few sentences printed under the panels
    (e.g. why a ramp levels off below its vmax; a scenario's "note").
    Returns the legend texts, one list per panel."""
    if data.labels is not None:
        cols = [(y, p[1]) for p in panels for y in p[0]] if panels else None
        plot_bars(data, out_png, title=title, columns=cols)
        return []
    if label is None and overlays:
        label = os.path.splitext(os.path.basename(data.path))[0]
    dx, dpanels = default_layout(data.header)
    x = x or dx
    specs = [panel_spec(p, x) for p in (panels or dpanels)]
    shared = len({px for _, _, px, _ in specs}) == 1
    fig, axes = plt.subplots(len(specs), 1, figsize=(9, 2.9 * len(specs) + 0.6), sharex=shared, squeeze=False)
    legends = []
    for i, (ax, (ycols, ylabel, px, xlabel)) in enumerate(zip(axes[:, 0], specs)):
        if px not in data.columns:
            raise ValueError(f"{data.path}: no column {px!r} (columns: {', '.join(data.header)})")
        drawn = []   # (column, x values, y values) already on this panel
        n_lines = 0
        for y in ycols:
            if y not in data.columns:
                raise ValueError(f"{data.path}: no column {y!r} (columns: {', '.join(data.header)})")
        for j, (dlabel, d, style) in enumerate([(label, data, "-")] + [(ol, od, "--") for ol, od in overlays]):
            if px not in d.columns:
                continue
            for y in ycols:
                if y not in d.columns:
                    continue
                xs, ys = d.columns[px], d.columns[y]
                if j > 0 and y in REFERENCE_COLUMNS and any(c == y and same_series(xs, ys, a, b)
                                                            for c, a, b in drawn):
                    continue
                text = series_label(y, dlabel if (j > 0 or overlays or label) else None, len(ycols))
                if y in REFERENCE_COLUMNS and len(ycols) > 1 and j == 0:
                    text = SERIES_NAMES.get(y, y)   # the input is the same for every data set
                if is_jumpy(ys):
                    w = max(5, len(ys) // 50)
                    line, = ax.plot(xs, ys, style, linewidth=0.5, alpha=0.3)
                    ax.plot(xs, moving_mean(ys, w), style, linewidth=1.4, color=line.get_color(),
                            label=f"{text} (moving mean of {w} steps; raw pale)")
                else:
                    # a jerk is piecewise constant (the filter-shaped move's law: it changes at the
                    # knots, between two step times): held between the samples, not sloped
                    ax.plot(xs, ys, style, linewidth=1.4 if j == 0 else 1.1, label=text,
                            drawstyle="steps-mid" if y == "jerk_sps3" else "default")
                drawn.append((y, xs, ys))
                n_lines += 1
        if len(data) == 0:
            ax.text(0.5, 0.5, "0 rows", transform=ax.transAxes, ha="center", va="center", color="grey")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.35)
        if n_lines > 1 or label or overlays:
            ax.legend(loc="best", fontsize="small")
        legends.append([ln.get_label() for ln in ax.get_lines() if not ln.get_label().startswith("_")])
        if not shared or i == len(specs) - 1:
            ax.set_xlabel(xlabel)
    fig.suptitle(textwrap.fill(title or default_title(data, overlays, label), 100))
    if note:
        fig.text(0.01, 0.005, textwrap.fill(note, 150), fontsize="small", va="bottom", ha="left", color="0.25")
    fig.tight_layout(rect=(0, note_height(note), 1, 1) if note else None)
    place_legends(fig, axes[:, 0])
    fig.tight_layout(rect=(0, note_height(note), 1, 1) if note else None)
    fig.savefig(out_png, dpi=110)
    plt.close(fig)
    return legends
