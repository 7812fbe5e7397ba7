"""The foundation's tools on their own: tools/plot on any motionsim-style CSV, the profiles
workbook (read back with openpyxl), and the Makefile's refusals for a real board (issue 2, items 5
and 7)."""
import csv
import json
import math
import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLOT = os.path.join(ROOT, "tools", "plot")


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, timeout=600, **kw)


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n" and os.path.getsize(path) > 1000


def test_plot_works_alone_on_an_unknown_csv(tmp_path):
    src = tmp_path / "any.csv"
    src.write_text("x,a,b\n0,1,2\n1,2,4\n2,3,8\n")
    r = run([PLOT, str(src)])
    assert r.returncode == 0, r.stderr
    assert is_png(tmp_path / "any.png")


def test_plot_with_overlay_and_output(tmp_path):
    a = tmp_path / "a.csv"
    b = tmp_path / "b.csv"
    a.write_text("k,t_s,u,y\n0,0,5,0\n1,0.01,5,0.1\n")
    b.write_text("k,t_s,u,y\n0,0,5,0\n1,0.01,5,0.2\n")
    out = tmp_path / "o.png"
    r = run([PLOT, str(a), "-o", str(out), "--overlay", f"sim={b}"])
    assert r.returncode == 0, r.stderr
    assert is_png(out)


@pytest.mark.parametrize("content,why", [
    ("", "empty"),
    ("t_s,y\n0,abc\n", "not a number"),
    ("t_s,y\n0,1,2\n", "fields"),
])
def test_plot_rejects_bad_csv_with_one_line(tmp_path, content, why):
    src = tmp_path / "bad.csv"
    src.write_text(content)
    r = run([PLOT, str(src)])
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and why in r.stderr


def test_plot_draws_label_tables_as_bars(tmp_path, motionsim):
    """`motionsim ramp --compare` starts with a text column (the algorithm): plotted as bars."""
    r = motionsim("ramp", "--compare", "--to", "200", "--v0", "10", "--vmax", "100", "--accel", "100")
    assert r.rc == 0, r.err
    src = tmp_path / "cmp.csv"
    src.write_text(r.out)
    r = run([PLOT, str(src)])
    assert r.returncode == 0, r.stderr
    assert is_png(tmp_path / "cmp.png")


def test_plot_missing_file(tmp_path):
    r = run([PLOT, str(tmp_path / "nope.csv")])
    assert r.returncode == 2 and "nope.csv" in r.stderr


def test_plot_header_only_csv_draws_empty_axes(tmp_path, motionsim):
    """A zero-step move is a valid motionsim output: a header and no rows."""
    src = tmp_path / "e.csv"
    r = motionsim("ramp", "--from", "5", "--to", "5", "-o", src)
    assert r.rc == 0, r.err
    assert src.read_text().strip().count("\n") == 0
    r = run([PLOT, str(src)])
    assert r.returncode == 0, r.stderr
    assert is_png(tmp_path / "e.png")


@pytest.mark.parametrize("content", [
    open(os.path.join(ROOT, "docs", "img", "ramp_leib_0_50.png"), "rb").read(),  # binary, not UTF-8
    b"t_s,y\n0,1\x00\n",                                                           # NUL byte
    "t_s,y\n0,1\n".encode("utf-16"),
], ids=["png", "nul", "utf16"])
def test_plot_refuses_a_binary_file_with_one_line(tmp_path, content):
    src = tmp_path / "bin.csv"
    src.write_bytes(content)
    r = run([PLOT, str(src)])
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "not a text CSV file" in lines[0], r.stderr
    assert not (tmp_path / "bin.png").exists()


PID_VECTOR = os.path.join(ROOT, "test", "data", "pid_v1", "b_pid_windup.csv")
PID_VECTOR_F = os.path.join(ROOT, "test", "data", "pid_v1", "float32", "b_pid_windup.csv")
RAMP = ["--v0", "10", "--vmax", "100", "--accel", "100", "--tick-hz", "1000000"]
SIGMOID = ["--algo", "sigmoid", "--len", "50", "--fmin", "500", "--fmax", "4000", "--flex", "5",
           "--timer-hz", "2000000", "--hold", "2"]
# every kind of CSV motionsim writes, generated live
OUTPUTS = {
    "ramp_exact": ["ramp", "--algo", "exact", "--to", "300"] + RAMP,
    "ramp_simplistic": ["ramp", "--algo", "simplistic", "--to", "300"] + RAMP,
    "ramp_leib": ["ramp", "--algo", "leib", "--to", "300"] + RAMP,
    "ramp_sigmoid": ["ramp", "--to", "400"] + SIGMOID,
    "ramp_leib_integer": ["ramp", "--algo", "leib", "--to", "300", "--integer-ticks"] + RAMP,
    "ramp_sigmoid_integer": ["ramp", "--to", "400", "--integer-ticks"] + SIGMOID,
    "ramp_negative": ["ramp", "--algo", "leib", "--from", "300", "--to", "-20"] + RAMP,
    "ramp_one_step": ["ramp", "--algo", "leib", "--from", "7", "--to", "8"] + RAMP,
    "ramp_zero_length": ["ramp", "--algo", "leib", "--from", "7", "--to", "7"] + RAMP,
    "ramp_compare": ["ramp", "--compare", "--to", "300"] + RAMP,
    "filter_ma": ["filter", "--kind", "ma", "--tau", "1", "--duration", "3"],
    "filter_ma2": ["filter", "--kind", "ma2", "--tau", "1", "--tau2", "0.5", "--duration", "3"],
    "filter_exp": ["filter", "--kind", "exp", "--tau", "1", "--input", "square:5:2", "--duration", "4"],
    "filter_stream": ["filter", "--kind", "ma", "--tau", "1", "--duration", "3", "--stream"],
    "servo_p": ["servo", "--ctrl", "p", "--duration", "1"],
    "servo_pid": ["servo", "--ctrl", "pid", "--kp", "0.1", "--ki", "0.1", "--kd", "0.002", "--duration", "1"],
    "servo_pid_double_metrics": ["servo", "--ctrl", "pid", "--kp", "0.1", "--precision", "double",
                                 "--duration", "1", "--metrics"],
    "pid_replay": ["pid-replay", PID_VECTOR],
    "pid_replay_float": ["pid-replay", "--float", PID_VECTOR_F],
}


@pytest.mark.parametrize("kind", sorted(OUTPUTS))
def test_plot_works_on_every_motionsim_output(tmp_path, motionsim, kind):
    src = tmp_path / f"{kind}.csv"
    r = motionsim(*OUTPUTS[kind], "-o", src)
    assert r.rc == 0, r.err
    assert src.read_text().count("\n") >= (1 if kind == "ramp_zero_length" else 2)
    out = tmp_path / "plot.png"
    r = run([PLOT, str(src), "-o", str(out)])
    assert r.returncode == 0, r.stderr
    assert is_png(out)


# ---- make profiles: CSV, PNG and the workbook, read back ------------------------------------

sys.path.insert(0, os.path.join(ROOT, "tools"))


def scenarios():
    items = []
    d = os.path.join(ROOT, "tools", "scenarios")
    for f in sorted(os.listdir(d)):
        if f.endswith(".json"):
            with open(os.path.join(d, f)) as fh:
                items += json.load(fh)
    return items


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def col_values(ws, col_letter, first, last):
    return [ws[f"{col_letter}{r}"].value for r in range(first, last + 1)]


REF = re.compile(r"^'?(.+?)'?!\$([A-Z]+)\$(\d+):\$([A-Z]+)\$(\d+)$")


def parse_ref(ref):
    m = REF.match(ref)
    assert m, ref
    sheet, c1, r1, c2, r2 = m.groups()
    assert c1 == c2, f"{ref}: not one column"
    return sheet, c1, int(r1), int(r2)


def series_refs(chart):
    """[(categories or x ref, values ref)] of a chart's series, whatever its type."""
    out = []
    for s in chart.series:
        if s.xVal is not None:     # scatter
            out.append((s.xVal.numRef.f, s.yVal.numRef.f))
        else:
            cat = s.cat.numRef.f if s.cat.numRef is not None else s.cat.strRef.f
            out.append((cat, s.val.numRef.f))
    return out


@pytest.fixture(scope="module")
def profiles(tmp_path_factory):
    out = tmp_path_factory.mktemp("profiles")
    motionsim = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))
    r = run([os.path.join(ROOT, ".venv", "bin", "python"), "tools/profiles.py", "--motionsim", motionsim,
             "--out", str(out)])
    assert r.returncode == 0, r.stderr
    import openpyxl
    return out, openpyxl.load_workbook(out / "profiles.xlsx")


def test_standard_workbook_is_well_under_1_mb(profiles):
    out, _ = profiles
    assert (out / "profiles.xlsx").stat().st_size < 700_000


def test_profiles_writes_csv_and_png_per_scenario(profiles):
    out, _ = profiles
    items = scenarios()
    assert items, "no scenarios in tools/scenarios"
    for s in items:
        csv_path = out / f"{s['name']}.csv"
        assert len(csv_path.read_text().splitlines()) >= 3, s["name"]
        assert is_png(out / f"{s['name']}.png"), s["name"]


def test_ramp_plots_are_against_time():
    """README: the ramps' step rate is drawn against time (the sigmoid's period by step is a second panel)."""
    import motionplot
    import profiles as prof
    for s in scenarios():
        if s["args"][0] != "ramp" or "--compare" in s["args"]:
            continue
        header = list(motionplot.KNOWN[0][0])
        x, panels = prof.layout_of(s, type("D", (), {"header": header})())
        ycols, _, px, _ = motionplot.panel_spec(panels[0], x)
        assert ycols == ["speed_sps"] and px == "t_s", s["name"]


def test_workbook_has_a_sheet_per_scenario_with_a_line_chart_first(profiles):
    from openpyxl.chart import BarChart, LineChart, ScatterChart
    _, wb = profiles
    items = scenarios()
    assert len(wb.sheetnames) == len(items) + 1 and wb.sheetnames[0] == "index"
    for s in items:
        assert len(s["name"]) <= 31 and s["name"] in wb.sheetnames, s["name"]
        charts = wb[s["name"]]._charts
        assert charts, s["name"]
        if "--compare" in s["args"]:
            assert all(isinstance(c, BarChart) and c.barDir == "col" for c in charts), s["name"]
        else:
            assert isinstance(charts[0], LineChart), s["name"]
        if s["args"][0] == "ramp" and "--compare" not in s["args"]:
            # the grid line chart, then an XY scatter at the exact step times per panel
            assert all(isinstance(c, ScatterChart) for c in charts[1:]) and len(charts) >= 2, s["name"]


def test_workbook_chart_series_point_at_the_sheets_columns(profiles):
    """Every series reads whole columns: line and column charts this sheet's own cells (its CSV
    columns, overlay columns copied beside them, or the ramp's grid block); an XY scatter's overlay
    series another scenario's sheet, named in the scenario's overlay list."""
    from openpyxl.chart import LineChart, ScatterChart
    out, wb = profiles
    for s in scenarios():
        name = s["name"]
        header, rows = read_csv(out / f"{name}.csv")
        rows = kept(rows)
        for chart in wb[name]._charts:
            for cat, val in series_refs(chart):
                csheet, ccol, cr1, cr2 = parse_ref(cat)
                vsheet, vcol, vr1, vr2 = parse_ref(val)
                assert csheet == vsheet and cr1 == vr1 == 2, (name, cat, val)
                ws = wb[csheet]
                chead, vhead = ws[f"{ccol}1"].value, ws[f"{vcol}1"].value
                if csheet != name:
                    assert isinstance(chart, ScatterChart) and csheet in s.get("overlay", []), (name, cat)
                    oheader, orows = read_csv(out / f"{csheet}.csv")
                    orows = kept(orows)
                    assert chead in oheader and vhead in oheader and cr2 == vr2 == len(orows) + 1, (name, cat)
                    continue
                if chead == "t_s (grid)":
                    assert isinstance(chart, LineChart) and vhead.startswith("speed_sps (grid"), (name, vhead)
                    assert vr2 == cr2 and ws[f"{ccol}{cr2 + 1}"].value is None, (name, cat)
                    continue
                # the CSV's own x column (time, or the labels of a compare table), every row
                assert chead in header and cr2 == len(rows) + 1, (name, cat)
                assert ws[f"{ccol}{cr2 + 1}"].value is None
                if vhead in header:
                    assert vr2 == cr2, (name, val)
                    continue
                # an overlay copied beside the data: "<column> (<overlay>)", rows that share our times
                base, _, rest = vhead.partition(" (")
                other = rest[:-1]
                assert isinstance(chart, LineChart) and base in header and other in s.get("overlay", []), vhead
                oheader, orows = read_csv(out / f"{other}.csv")
                orows = kept(orows)
                assert vr2 == min(len(rows), len(orows)) + 1, (name, val)
                want = [float(r[oheader.index(base)]) for r in orows[:vr2 - 1]]
                assert col_values(ws, vcol, 2, vr2) == pytest.approx(want, rel=2e-15), (name, vhead)
                ot = [float(r[oheader.index(chead)]) for r in orows[:vr2 - 1]]
                assert col_values(ws, ccol, 2, vr2) == pytest.approx(ot, rel=1e-6, abs=1e-9), (name, vhead)


def test_line_charts_over_the_rows_own_times_only_when_they_are_evenly_spaced(profiles):
    """A category axis spaces points evenly: a line chart over t_s is to scale only if t_s is."""
    out, wb = profiles
    for s in scenarios():
        if "--compare" in s["args"]:
            continue
        ws = wb[s["name"]]
        header, rows = read_csv(out / f"{s['name']}.csv")
        cat = series_refs(ws._charts[0])[0][0]
        _, ccol, _, _ = parse_ref(cat)
        if ws[f"{ccol}1"].value == "t_s (grid)":
            continue
        t = [float(r[header.index(ws[f"{ccol}1"].value)]) for r in rows]
        dt = (t[-1] - t[0]) / (len(t) - 1)
        assert all(abs((b - a) - dt) <= 1e-6 * dt for a, b in zip(t, t[1:])), s["name"]
        assert s["args"][0] in ("filter", "servo"), s["name"]


def test_workbook_cells_equal_the_csv(profiles):
    """A sheet's cells are the CSV's kept rows (at most 250); the CSV keeps the full table."""
    out, wb = profiles
    for s in scenarios():
        ws = wb[s["name"]]
        header, rows = read_csv(out / f"{s['name']}.csv")
        rows = kept(rows)
        assert len(rows) <= SHEET_ROWS
        assert [c.value for c in ws[1]][:len(header)] == header
        for j, h in enumerate(header):
            got = [ws.cell(row=2 + i, column=1 + j).value for i in range(len(rows))]
            try:
                want = [float(r[j]) for r in rows]
            except ValueError:
                assert got == [r[j] for r in rows], (s["name"], h)
                continue
            # the cell keeps 16 significant digits (XlsxWriter writes %.16G)
            assert got == pytest.approx(want, rel=2e-15), (s["name"], h)
        assert ws.cell(row=2 + len(rows), column=1).value is None


SHEET_ROWS = 250   # README / docs/plots.md: a sheet holds at most 250 rows of a CSV


def kept(rows):
    """The rows a sheet holds (docs/plots.md): rows 0, k, 2k, ... with k = ceil(n / 250)."""
    k = max(1, math.ceil(len(rows) / SHEET_ROWS))
    return rows[::k]


def held(step_times, speeds, t):
    """The README's rule, written out independently: the speed of step i where
    t_(i-1) <= t < t_i (t_0 = 0, the start of the move); None from the last step on."""
    for ti, v in zip(step_times, speeds):
        if t < ti:
            return v
    return None


def test_ramp_grid_is_the_sample_and_hold_step_rate(profiles):
    out, wb = profiles
    checked = 0
    for s in scenarios():
        if s["args"][0] != "ramp" or "--compare" in s["args"]:
            continue
        ws = wb[s["name"]]
        heads = {c.value: c.column_letter for c in ws[1] if c.value is not None}
        gcol = heads["t_s (grid)"]
        grid = []
        r = 2
        while ws[f"{gcol}{r}"].value is not None:
            grid.append(ws[f"{gcol}{r}"].value)
            r += 1
        sources = {"speed_sps (grid)": s["name"]}
        for o in s.get("overlay", []):
            sources[f"speed_sps (grid, {o})"] = o
        ends = []
        for col_name, src in sources.items():
            assert col_name in heads, (s["name"], col_name)
            header, rows = read_csv(out / f"{src}.csv")
            ts = [float(row[header.index("t_s")]) for row in rows]
            vs = [float(row[header.index("speed_sps")]) for row in rows]
            ends.append(ts[-1])
            got = col_values(ws, heads[col_name], 2, 1 + len(grid))
            want = [held(ts, vs, t) for t in grid]
            assert [g is None for g in got] == [w is None for w in want], (s["name"], col_name)
            assert [g for g in got if g is not None] == \
                pytest.approx([w for w in want if w is not None], rel=2e-15), (s["name"], col_name)
            checked += 1
        # the grid: 0, dt, 2 dt, ... with dt = 1, 2 or 5 x 10^k, 200..1000 points, up to the last step
        dt = grid[1] - grid[0]
        assert grid[0] == 0 and 200 <= len(grid) <= 1000, s["name"]
        assert all(abs(t - j * dt) <= 1e-9 for j, t in enumerate(grid)), s["name"]
        mant = dt / 10 ** math.floor(math.log10(dt))
        assert min(abs(mant - m) for m in (1, 2, 5)) < 1e-6, (s["name"], dt)
        assert grid[-1] < max(ends) <= grid[-1] + dt + 1e-12, s["name"]
    assert checked >= 10


# ---- make upload / make monitor: each refusal is one line, exit 2 ---------------------------

def make(*args, cwd=None):
    cmd = ["make", "--no-print-directory"]
    if cwd:
        cmd += ["-f", os.path.join(ROOT, "Makefile"), "-C", str(cwd)]
    return subprocess.run(cmd + list(args), capture_output=True, text=True, cwd=ROOT, timeout=120)


def one_line_refusal(r, *fragments):
    """Exactly one line on stderr (make's $(error) line), nothing on stdout, exit 2."""
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and r.stdout.strip() == "", r.stderr + r.stdout
    for f in fragments:
        assert f in lines[0], lines[0]
    return lines[0]


def sketch_names():
    return sorted(d for d in os.listdir(os.path.join(ROOT, "firmware")) if d != "libraries")


def test_make_upload_without_sketch_lists_the_sketches():
    line = one_line_refusal(make("upload"), "make upload: SKETCH=<name> is missing")
    for s in sketch_names():
        assert s in line


@pytest.mark.parametrize("bad", ["NoSuchSketch", "libraries", "LeibRampStepper SCurveStepper",
                                 "LeibRampStepper%", "%"])
def test_make_upload_unknown_sketch(bad):
    line = one_line_refusal(make("upload", f"SKETCH={bad}", "PORT=/dev/null"), f"unknown ('{bad}')")
    for s in sketch_names():
        assert s in line


def test_make_upload_port_missing_or_absent():
    sketch = sketch_names()[0]
    line = one_line_refusal(make("upload", f"SKETCH={sketch}"), "PORT=<device> is missing")
    for s in sketch_names():
        assert s in line
    one_line_refusal(make("upload", f"SKETCH={sketch}", "PORT=/dev/no-such-tty"), "does not exist")


def test_make_monitor_refusals():
    one_line_refusal(make("monitor"), "make monitor: PORT=<device> is missing")
    one_line_refusal(make("monitor", "PORT=/dev/no-such-tty"), "'/dev/no-such-tty' does not exist")
    one_line_refusal(make("monitor", "PORT=/dev/null", "BAUD=1200"), "BAUD '1200' is not one of")


def test_make_monitor_and_upload_without_setup_say_run_make_setup(tmp_path):
    """A checkout without .venv (the Makefile run in an empty folder with one sketch)."""
    (tmp_path / "firmware" / "Blink").mkdir(parents=True)
    (tmp_path / "firmware" / "Blink" / "Blink.ino").write_text("void setup() {}\nvoid loop() {}\n")
    one_line_refusal(make("monitor", "PORT=/dev/null", cwd=tmp_path), "run 'make setup' first")
    one_line_refusal(make("upload", "SKETCH=Blink", "PORT=/dev/null", cwd=tmp_path), "run 'make setup' first")


def test_targets_that_need_the_toolchain_say_run_make_setup_in_one_line(tmp_path):
    """make test/firmware/profiles in a checkout without .venv and arduino-cli."""
    (tmp_path / "firmware" / "Blink").mkdir(parents=True)
    (tmp_path / "firmware" / "Blink" / "Blink.ino").write_text("void setup() {}\nvoid loop() {}\n")
    for target in ("test", "firmware", "profiles"):
        one_line_refusal(make(target, cwd=tmp_path), "run 'make setup' first")


def test_make_upload_failure_ends_with_a_one_line_hint():
    """avrdude cannot flash /dev/null (it exists, but is no Mega): after avrdude's own errors the
    last line of ours is the hint (make's "*** ... Error 1" trailer may follow it)."""
    if not os.access(os.path.join(ROOT, ".tools", "arduino-cli"), os.X_OK):
        pytest.fail("arduino-cli is not installed (make setup)")
    r = make("upload", f"SKETCH={sketch_names()[0]}", "PORT=/dev/null")
    assert r.returncode != 0
    ours = [l for l in r.stderr.strip().splitlines() if not re.match(r"^make(\[\d+\])?: \*\*\*", l)]
    hint = ours[-1]
    assert hint.startswith("make upload: avrdude could not flash"), r.stderr[-2000:]
    for fragment in ("/dev/null", "port", "Serial Monitor", "Mega 2560"):
        assert fragment in hint, hint


def test_run_tests_shows_each_suites_progress_while_it_runs(tmp_path):
    """make test's runner: a suite says what it has done as it goes (here a TAP command whose two
    checks come 1 s apart, and a pytest directory), before its summary line."""
    (tmp_path / "test_two.py").write_text("def test_a():\n    pass\n\n\ndef test_b():\n    assert 1 == 2\n")
    tap = "echo 1..2; echo ok 1 - first check; sleep 1; echo 'not ok 2 - second check'"
    r = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "run_tests.py"), f"slow|tap|{tap}",
                        f"py|pytest|{tmp_path}"], capture_output=True, text=True, timeout=120, cwd=ROOT)
    out = r.stdout.splitlines()
    assert r.returncode == 1
    first = next(i for i, l in enumerate(out) if l.startswith("  [slow] 1/2 ok - first check"))
    second = next(i for i, l in enumerate(out) if l.startswith("  [slow] 2/2 not ok - second check"))
    summary = out.index(next(l for l in out if l.startswith("slow: 1 passed, 1 failed")))
    assert first < second < summary
    assert any(l.startswith("  [py] ") and "failed" in l and "test_b" in l for l in out), out
    assert out[-1] == "2 passed, 2 failed"
