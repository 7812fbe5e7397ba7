"""Plots for people (docs/plots.md): legends name the algorithm, the filter or the gains, never a
CSV column; an input or setpoint is drawn once; a panel that would be a solid block gets its moving
mean; `tools/workbook` makes a workbook from one's own CSV files; `profiles.py --only` keeps a
scenario's overlays; no "seed 00x" wording in plot titles, --help texts or tool output.

The expected legend texts are written here from the scenarios' motionsim arguments (the algorithm
and gains a person asked for), not read back from the plotting code.
"""
import json
import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import motionplot  # noqa: E402
import profiles  # noqa: E402

PY = sys.executable
COLUMNS = {"speed_sps", "accel_sps2", "interval_ticks", "position_counts", "error_counts", "duty_pct",
           "t_s", "t_ms"}


def sim(motionsim, path, *args):
    r = motionsim(*args)
    assert r.rc == 0, r.err
    path.write_text(r.out)
    return motionplot.CsvData(str(path))


def no_column_names(legends):
    for panel in legends:
        for text in panel:
            words = set(re.split(r"[ ,()]+", text))
            assert not (words & COLUMNS), text


def test_ramp_legends_name_the_algorithms(tmp_path, motionsim):
    base = ["--from", "0", "--to", "50", "--v0", "1", "--vmax", "20", "--accel", "10", "--tick-hz", "1000"]
    leib = sim(motionsim, tmp_path / "leib.csv", "ramp", "--algo", "leib", *base)
    exact = sim(motionsim, tmp_path / "exact.csv", "ramp", "--algo", "exact", *base)
    legends = motionplot.plot(leib, str(tmp_path / "p.png"), label="Leib", overlays=[("exact", exact)])
    assert legends == [["Leib", "exact"], ["Leib", "exact"]]


def test_servo_setpoint_is_drawn_once_and_gains_name_the_lines(tmp_path, motionsim):
    pid = sim(motionsim, tmp_path / "pid.csv", "servo", "--ctrl", "pid", "--kp", "0.1", "--ki", "0.1", "--kd",
              "0.002", "--setpoint", "1000", "--duration", "5")
    p = sim(motionsim, tmp_path / "p.csv", "servo", "--ctrl", "p", "--kp", "0.02", "--setpoint", "1000",
            "--duration", "3")
    legends = motionplot.plot(pid, str(tmp_path / "s.png"), label="PID, Kp = 0.1, Ki = 0.1, Kd = 0.002",
                              overlays=[("P, Kp = 0.02", p)])
    pos = legends[0]
    assert sum("setpoint" in t for t in pos) == 1, pos
    assert "position, PID, Kp = 0.1, Ki = 0.1, Kd = 0.002" in pos and "position, P, Kp = 0.02" in pos
    no_column_names(legends)


def servo_csv_every_ms(path, setpoints, seconds=3.0):
    """A servo CSV as `make emulate` writes it: one row per 1 ms; setpoints: [(from t, counts)]"""
    rows = ["t_s,setpoint,position_counts,error_counts,duty_pct"]
    for k in range(int(seconds * 1000)):
        t = k / 1000.0
        sp = [c for t0, c in setpoints if t >= t0][-1]
        rows.append(f"{t},{sp},{min(sp, k)},{sp - min(sp, k)},5")
    path.write_text("\n".join(rows) + "\n")
    return motionplot.CsvData(str(path))


@pytest.mark.parametrize("fw_setpoint, drawn", [(1000, 1), (500, 2)])
def test_a_setpoint_sampled_at_other_times_is_drawn_once_if_equal(tmp_path, motionsim, fw_setpoint, drawn):
    """`make emulate`'s servo plot: the firmware sampled every 1 ms, motionsim every 20 ms (from
    another t = 0). The same setpoint (1000 counts in both) is drawn once; another setpoint is
    a second line."""
    fw = servo_csv_every_ms(tmp_path / "fw.csv", [(0.0, fw_setpoint)])
    ms = sim(motionsim, tmp_path / "ms.csv", "servo", "--ctrl", "p", "--kp", "0.02", "--setpoint", "1000",
             "--duration", "2.9")
    ms.columns["t_s"] = [t + 0.0047 for t in ms.columns["t_s"]]   # motionsim's t = 0 at the firmware's first read
    legends = motionplot.plot(fw, str(tmp_path / "s.png"), label="firmware (emulated)",
                              overlays=[("motionsim", ms)])
    assert sum("setpoint" in t for t in legends[0]) == drawn, legends[0]


def test_a_setpoint_that_steps_is_the_same_series_whatever_the_sampling():
    """1000 counts until 1 s, then 500: sampled every 1 ms and every 20 ms from 0.0047 s, both are
    that setpoint (the step falls between two 20 ms samples); a step at another time is not."""
    fine_t = [k / 1000.0 for k in range(2000)]
    coarse_t = [0.0047 + k * 0.02 for k in range(99)]

    def sp(t, at=1.0):
        return 1000.0 if t < at else 500.0
    assert motionplot.same_series(fine_t, [sp(t) for t in fine_t], coarse_t, [sp(t) for t in coarse_t])
    assert not motionplot.same_series(fine_t, [sp(t) for t in fine_t], coarse_t, [sp(t, 1.5) for t in coarse_t])


def test_filter_plot_is_one_useful_panel(tmp_path, motionsim):
    ma = sim(motionsim, tmp_path / "ma.csv", "filter", "--kind", "ma", "--tau", "9", "--ts", "0.01", "--input",
             "step:5", "--duration", "20")
    legends = motionplot.plot(ma, str(tmp_path / "f.png"), label="moving average, tau = 9 s")
    assert len(legends) == 1                    # input and output on one panel, not a flat 5 V panel
    assert legends[0] == ["input u", "output y, moving average, tau = 9 s"]


def test_s_curve_acceleration_is_a_moving_mean_not_a_block(tmp_path, motionsim):
    d = sim(motionsim, tmp_path / "sig.csv", "ramp", "--algo", "sigmoid", "--from", "0", "--to", "3000", "--len", "250",
            "--fmin", "200", "--fmax", "4000", "--flex", "5", "--hold", "4", "--timer-hz", "2000000")
    legends = motionplot.plot(d, str(tmp_path / "sig.png"), label="S-curve")
    assert legends[0] == ["S-curve"]
    assert len(legends[1]) == 1 and "moving mean" in legends[1][0]
    # a smooth ramp's acceleration is drawn as it is
    e = sim(motionsim, tmp_path / "e.csv", "ramp", "--algo", "exact", "--from", "0", "--to", "2000", "--v0", "100",
            "--vmax", "1000", "--accel", "1000", "--tick-hz", "2000000")
    assert motionplot.plot(e, str(tmp_path / "e.png"), label="exact")[1] == ["exact"]


def test_scenario_labels_come_from_what_was_asked():
    assert profiles.scenario_label({"name": "x", "args": ["ramp", "--algo", "leib"]}) == "Leib"
    assert profiles.scenario_label({"name": "x", "args": ["ramp", "--algo", "exact"]}) == "exact"
    assert profiles.scenario_label({"name": "x", "args": ["servo", "--ctrl", "p", "--kp", "0.02"]}) == "P, Kp = 0.02"
    assert profiles.scenario_label({"name": "x", "args": ["filter", "--kind", "ma2", "--tau", "9", "--tau2", "3"]}) \
        == "two-stage S-curve, tau = 9 s, tau2 = 3 s"


def test_profiles_only_keeps_the_scenarios_overlays(tmp_path):
    motionsim = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))
    r = subprocess.run([PY, "tools/profiles.py", "--motionsim", motionsim, "--out", str(tmp_path), "--only",
                        "ramp_leib_0_50"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "ramp_leib_0_50.png").exists() and (tmp_path / "ramp_exact_0_50.csv").exists()
    import openpyxl
    wb = openpyxl.load_workbook(tmp_path / "profiles.xlsx")
    assert set(wb.sheetnames) == {"index", "ramp_leib_0_50", "ramp_exact_0_50"}


def test_workbook_from_ones_own_csv_files(tmp_path, motionsim):
    from openpyxl import load_workbook
    from openpyxl.chart import LineChart
    # what make emulate writes for a move: X.csv and X.motionsim.csv; and a long filter run
    sim(motionsim, tmp_path / "Move.csv", "ramp", "--algo", "leib", "--to", "200", "--v0", "10", "--vmax", "100",
        "--accel", "100", "--tick-hz", "2000000", "--integer-ticks")
    sim(motionsim, tmp_path / "Move.motionsim.csv", "ramp", "--algo", "exact", "--to", "200", "--v0", "10", "--vmax",
        "100", "--accel", "100", "--tick-hz", "2000000", "--integer-ticks")
    sim(motionsim, tmp_path / "long.csv", "filter", "--kind", "ma", "--tau", "9", "--ts", "0.01", "--input",
        "square:5:30", "--duration", "120")
    book = tmp_path / "book.xlsx"
    r = subprocess.run([os.path.join(ROOT, "tools", "workbook"), str(tmp_path / "Move.csv"),
                        str(tmp_path / "Move.motionsim.csv"), str(tmp_path / "long.csv"), "-o", str(book)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    wb = load_workbook(book)
    # the motionsim file is an overlay, not a sheet of its own
    assert wb.sheetnames == ["index", "Move", "long"]
    assert isinstance(wb["Move"]._charts[0], LineChart) and isinstance(wb["long"]._charts[0], LineChart)
    # the motionsim file is drawn over the firmware's: a scatter series reads its columns, in Move's sheet
    head = [c.value for c in wb["Move"][1]]
    assert "t_s (motionsim)" in head and "speed_sps (motionsim)" in head, head
    refs = [s.xVal.numRef.f for c in wb["Move"]._charts[1:] for s in c.series if s.xVal is not None]
    col = chr(ord("A") + head.index("t_s (motionsim)"))
    assert any(f.startswith(f"Move!${col}$") for f in refs), refs
    # 12001 rows: the sheet holds at most 250, the index says so
    assert wb["long"].max_row <= 251
    assert any("every 49th row" in str(c.value) for row in wb["index"].iter_rows() for c in row)
    assert book.stat().st_size < 200_000


def test_workbook_of_an_emulated_servo_run_draws_the_setpoint_once(tmp_path, motionsim):
    """`make emulate`'s servo files: the firmware every 1 ms, motionsim every 20 ms, the same
    setpoint. One sheet (the motionsim file joins it), the setpoint once, motionsim's position dashed."""
    from openpyxl import load_workbook
    servo_csv_every_ms(tmp_path / "Servo.csv", [(0.0, 1000)])
    sim(motionsim, tmp_path / "Servo.motionsim.csv", "servo", "--ctrl", "p", "--kp", "0.02", "--setpoint", "1000",
        "--duration", "2.9")
    book = tmp_path / "emu.xlsx"
    r = subprocess.run([os.path.join(ROOT, "tools", "workbook"), str(tmp_path / "Servo.csv"),
                        str(tmp_path / "Servo.motionsim.csv"), "-o", str(book)], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    wb = load_workbook(book)
    assert wb.sheetnames == ["index", "Servo"]
    names = [s.tx.strRef.f if s.tx.strRef is not None else s.tx.v for s in wb["Servo"]._charts[0].series]
    assert sum("setpoint" in n for n in names) == 1, names
    assert "position, motionsim" in names, names


@pytest.mark.parametrize("args, why", [(["nope.csv", "-o", "b.xlsx"], "nope.csv"),
                                       (["x.csv", "-o", "b.txt"], ".xlsx")])
def test_workbook_refuses_bad_input_in_one_line(tmp_path, args, why):
    (tmp_path / "x.csv").write_text("a,b\n1,2\n")
    r = subprocess.run([os.path.join(ROOT, "tools", "workbook"), *args], cwd=tmp_path, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and why in r.stderr, r.stderr


def test_no_seed_wording_in_titles_help_or_output(tmp_path):
    texts = []
    for path in sorted(os.listdir(os.path.join(ROOT, "tools", "scenarios"))):
        with open(os.path.join(ROOT, "tools", "scenarios", path)) as f:
            for s in json.load(f):
                texts += [s["name"], s["title"], json.dumps(s.get("panels", []))]
    for tool in (["tools/plot"], ["tools/workbook"], [PY, "tools/profiles.py"], [PY, "tools/emu/emulate.py"]):
        r = subprocess.run([*tool, "--help"], cwd=ROOT, capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, (tool, r.stderr)
        texts.append(r.stdout)
    with open(os.path.join(ROOT, "tools", "emu", "sketches.py")) as f:
        texts.append(f.read())          # the default emulator scripts are copied into build/emulate
    for t in texts:
        assert not re.search(r"\bseed\b", t, re.I), t[:200]


@pytest.mark.parametrize("frm,to", [(0, 50), (10, -5)])
def test_a_ramp_plot_is_titled_by_its_move_and_names_its_file_by_default(tmp_path, motionsim, frm, to):
    """README's step 3 without --title: the title says the move motionsim was asked for (from the
    CSV's positions), and with an overlay the file's series is named by the file, not "step rate"."""
    args = ["--from", str(frm), "--to", str(to), "--v0", "1", "--vmax", "20", "--accel", "10", "--tick-hz", "1000"]
    table = sim(motionsim, tmp_path / "table.csv", "ramp", "--algo", "simplistic", *args)
    leib = sim(motionsim, tmp_path / "leib.csv", "ramp", "--algo", "leib", *args)
    assert motionplot.default_title(table).startswith(f"move {frm} -> {to} steps, ")
    legends = motionplot.plot(table, str(tmp_path / "r.png"), overlays=[("Leib", leib)])
    assert legends == [["table", "Leib"], ["table", "Leib"]]


def test_a_servo_plot_is_titled_by_its_setpoint(tmp_path, motionsim):
    run = sim(motionsim, tmp_path / "p.csv", "servo", "--ctrl", "p", "--kp", "0.02", "--setpoint", "750",
              "--duration", "2")
    assert motionplot.default_title(run).startswith("setpoint 750 counts, ")


def legend_covers_a_line(ax, renderer):
    """Independent of motionplot: does any drawn segment cross the legend's box?"""
    from matplotlib.path import Path
    box = ax.get_legend().get_window_extent(renderer)
    for line in ax.get_lines():
        xy = [p for p in line.get_xydata() if p[0] == p[0] and p[1] == p[1]]
        if len(xy) > 1 and Path(ax.transData.transform(xy)).intersects_bbox(box, filled=False):
            return True
    return False


@pytest.mark.parametrize("name", ["filter_ma_square", "filter_ma2_square", "filter_ma_step", "ramp_leib_0_50"])
def test_no_legend_hides_data(tmp_path, motionsim, monkeypatch, name):
    """The square-wave filter plots fill their panel edge to edge; the legend must not sit over a line
    (checked on the drawn figure: no line segment crosses the legend's box)."""
    items = {s["name"]: s for s in profiles.load_scenarios()}
    s = items[name]
    data = sim(motionsim, tmp_path / f"{name}.csv", *s["args"])
    overlays = []
    for o in s.get("overlay", []):
        overlays.append((profiles.scenario_label(items[o]), sim(motionsim, tmp_path / f"{o}.csv", *items[o]["args"])))
    figs = []
    monkeypatch.setattr(motionplot.plt, "close", lambda fig: figs.append(fig))
    motionplot.plot(data, str(tmp_path / "p.png"), title=s["title"], overlays=overlays, label=profiles.scenario_label(s))
    fig = figs[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        if ax.get_legend() is not None:
            assert not legend_covers_a_line(ax, renderer), (name, ax.get_ylabel())
