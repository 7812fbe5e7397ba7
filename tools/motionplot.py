"""tools/motionplot.py - read motionsim CSV files and plot them (used by tools/plot and tools/profiles.py).

Every CSV that motionsim (or the emulator harness) writes has one header line and numeric rows.
The kind of file is recognised from its header and gets the plot a user expects:

  ramp        step,position,t_s,interval_ticks,speed_sps,accel_sps2  -> step rate and acceleration vs time
  filter      k,t_s,u,y                                              -> input and output voltage vs time
  servo       t_s,setpoint,position_counts,error_counts,duty_pct     -> position/setpoint and duty vs time
  pid-replay  t_ms,computed,output                                   -> controller output vs time
  ramp --compare  algo,steps,move_time_s,...                         -> bars of each algorithm's deviations
  anything else                                                      -> every column vs the first one
A file whose first column holds text (labels, like `ramp --compare`'s algorithm names) is drawn
as bars, one panel per numeric column; text anywhere else is an error.
"""
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# header columns -> (x column, [panels: (y columns, axis label)])
KNOWN = [
    (("step", "position", "t_s", "interval_ticks", "speed_sps", "accel_sps2"),
     ("t_s", [(["speed_sps"], "step rate (steps/s)"), (["accel_sps2"], "acceleration (steps/s²)")])),
    (("k", "t_s", "u", "y"),
     ("t_s", [(["u"], "input voltage (V)"), (["y"], "output voltage (V)")])),
    (("t_s", "setpoint", "position_counts", "error_counts", "duty_pct"),
     ("t_s", [(["setpoint", "position_counts"], "position (encoder counts)"), (["duty_pct"], "PWM duty (%)")])),
    (("t_ms", "computed", "output"),
     ("t_ms", [(["output"], "controller output")])),
]

# bar panels for label files: ramp --compare shows the deviations a user asks about
COMPARE_COLUMNS = [("move_time_dev_pct", "move time vs exact (%)"),
                   ("interval_max_dev_pct", "largest interval error (%)"),
                   ("interval_rms_dev_pct", "RMS interval error (%)"),
                   ("accel_max_dev_pct", "largest acceleration error (% of a)")]

AXIS_LABELS = {"t_s": "time (s)", "t_ms": "time (ms)", "step": "step number", "k": "sample k"}


class CsvData:
    """Columns of a motionsim CSV as lists of floats (empty cells become NaN)."""

    def __init__(self, path):
        self.path = path
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        if not rows:
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
        if not any(self.columns.values()) and len(rows) < 2:
            raise ValueError(f"{path}: no data rows")

    def __len__(self):
        return len(self.columns[self.header[0]]) if self.header else 0


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
    fig.suptitle(title or os.path.basename(data.path))
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)


def plot(data, out_png, title=None, x=None, panels=None, overlays=()):
    """Plots `data` into out_png. overlays: [(label, CsvData)] drawn dashed on the same panels
    (e.g. the exact ramp under the Leib ramp, or the simulator under the firmware).
    A file with a label column is drawn as bars (plot_bars)."""
    if data.labels is not None:
        cols = [(y, label) for ys, label in panels for y in ys] if panels else None
        return plot_bars(data, out_png, title=title, columns=cols)
    dx, dpanels = default_layout(data.header)
    x = x or dx
    panels = panels or dpanels
    if x not in data.columns:
        raise ValueError(f"{data.path}: no column {x!r} (columns: {', '.join(data.header)})")
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 2.9 * len(panels) + 0.6), sharex=True, squeeze=False)
    for ax, (ycols, ylabel) in zip(axes[:, 0], panels):
        for y in ycols:
            if y not in data.columns:
                raise ValueError(f"{data.path}: no column {y!r} (columns: {', '.join(data.header)})")
            ax.plot(data.columns[x], data.columns[y], label=y if not overlays else f"{y}", linewidth=1.4)
        for label, other in overlays:
            for y in ycols:
                if y in other.columns and x in other.columns:
                    ax.plot(other.columns[x], other.columns[y], "--", linewidth=1.1, label=f"{y} ({label})")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.35)
        if len(ycols) > 1 or overlays:
            ax.legend(loc="best", fontsize="small")
    axes[-1, 0].set_xlabel(AXIS_LABELS.get(x, x))
    fig.suptitle(title or os.path.basename(data.path))
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)
