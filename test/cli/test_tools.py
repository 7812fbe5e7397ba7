"""The foundation's tools on their own: tools/plot on any motionsim-style CSV, the profiles
workbook, and the Makefile's refusals for a real board (issue 2, items 5 and 7)."""
import json
import os
import subprocess
import zipfile

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLOT = os.path.join(ROOT, "tools", "plot")


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, timeout=600, **kw)


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


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


def scenario_names():
    names = []
    d = os.path.join(ROOT, "tools", "scenarios")
    for f in sorted(os.listdir(d)):
        if f.endswith(".json"):
            with open(os.path.join(d, f)) as fh:
                names += [s["name"] for s in json.load(fh)]
    return names


def test_profiles_writes_csv_png_and_a_workbook_with_a_chart_per_scenario(tmp_path):
    names = scenario_names()
    assert names, "no scenarios in tools/scenarios"
    motionsim = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))
    r = run([os.path.join(ROOT, ".venv", "bin", "python"), "tools/profiles.py", "--motionsim", motionsim,
             "--out", str(tmp_path)])
    assert r.returncode == 0, r.stderr
    for n in names:
        csv_path = tmp_path / f"{n}.csv"
        assert csv_path.stat().st_size > 0, n
        assert len(csv_path.read_text().splitlines()) >= 3, n
        assert is_png(tmp_path / f"{n}.png"), n
    with zipfile.ZipFile(tmp_path / "profiles.xlsx") as z:
        files = z.namelist()
        sheets = [f for f in files if f.startswith("xl/worksheets/sheet")]
        charts = [f for f in files if f.startswith("xl/charts/chart")]
        workbook = z.read("xl/workbook.xml").decode()
        # index sheet + one per scenario, each scenario sheet with at least one native chart
        assert len(sheets) == len(names) + 1
        assert len(charts) >= len(names)
        for n in names:
            assert f'name="{n[:31]}"' in workbook, n
        for c in charts:
            xml = z.read(c).decode()
            assert "<c:scatterChart>" in xml or "<c:lineChart>" in xml or "<c:barChart>" in xml


def make(*args):
    return run(["make", "--no-print-directory"] + list(args))


def test_make_upload_without_sketch_lists_the_sketches():
    r = make("upload")
    assert r.returncode != 0
    line = [l for l in r.stderr.splitlines() if l.startswith("make upload:")]
    assert len(line) == 1 and "SKETCH=<name> is missing" in line[0]
    sketches = [d for d in os.listdir(os.path.join(ROOT, "firmware")) if d != "libraries"]
    for s in sketches:
        assert s in line[0]


def test_make_upload_unknown_sketch_and_missing_port():
    r = make("upload", "SKETCH=NoSuchSketch", "PORT=/dev/null")
    assert r.returncode != 0 and "unknown ('NoSuchSketch')" in r.stderr
    sketch = sorted(d for d in os.listdir(os.path.join(ROOT, "firmware")) if d != "libraries")[0]
    r = make("upload", f"SKETCH={sketch}")
    assert r.returncode != 0 and "PORT=<device> is missing" in r.stderr
    r = make("upload", f"SKETCH={sketch}", "PORT=/dev/no-such-tty")
    assert r.returncode != 0 and "does not exist" in r.stderr


def test_make_monitor_needs_a_port():
    r = make("monitor")
    assert r.returncode != 0 and "PORT=<device> is missing" in r.stderr
