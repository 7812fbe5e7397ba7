"""The small items of issue 25 (tools/plot, tools/workbook, the Leib plateau, the servo scenarios).

- A plot of two files is titled with both: each file's name and its own time (the last t_s of each
  CSV, read here), under the move they share.
- tools/workbook --label names the sheets (and legends) like tools/plot's --label; two ramps get a
  sheet `compare` whose rows are each CSV's steps, move time, top step rate and first interval (read
  from the CSVs here) and move time against the first; no cell of the workbook holds a path of this
  machine (the files are given by absolute path here, so an absolute path would show).
- The Leib ramp of the lab levels off below vmax: the handout's S = int((vmax² - v0²)/2a) and its
  eqs. (12)-(13), computed here in Python from the handout's formulas, give the interval the ramp
  cruises on; motionsim's cruise must be it (float32 against float64: within 1e-5), and the figures
  docs/ramps.md and the plot's note quote must be those computed here.
- A scenario's overlay covers the same time as the scenario (servo_pid's P curve ran to 3 s, PID to 5 s).
"""
import json
import math
import os
import re
import subprocess
import sys

import openpyxl
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import motionplot  # noqa: E402

LAB = ["--from", "0", "--to", "50", "--v0", "1", "--vmax", "20", "--accel", "10", "--tick-hz", "1000"]


def sim(motionsim, path, *args):
    r = motionsim(*args)
    assert r.rc == 0, r.err
    path.write_text(r.out)
    return motionplot.CsvData(str(path))


def test_a_two_file_plot_is_titled_with_both_files_and_their_times(tmp_path, motionsim):
    table = sim(motionsim, tmp_path / "table.csv", "ramp", "--algo", "simplistic", *LAB)
    leib = sim(motionsim, tmp_path / "leib.csv", "ramp", "--algo", "leib", *LAB)
    title = motionplot.default_title(table, overlays=[("Leib", leib)], label="simplistic")
    assert title.startswith("move 0 -> 50 steps: ")
    for label, name, data in (("simplistic", "table.csv", table), ("Leib", "leib.csv", leib)):
        assert f"{label} {data.columns['t_s'][-1]:.3g} s ({name})" in title, title
    # different moves: each file's own
    back = sim(motionsim, tmp_path / "back.csv", "ramp", "--algo", "leib", "--from", "50", "--to", "0",
               "--v0", "1", "--vmax", "20", "--accel", "10", "--tick-hz", "1000")
    title = motionplot.default_title(table, overlays=[("back", back)])
    assert "table: move 0 -> 50 steps" in title and "back: move 50 -> 0 steps" in title, title
    # and tools/plot still writes the PNG
    p = subprocess.run([os.path.join(ROOT, "tools", "plot"), str(tmp_path / "table.csv"), "--label", "simplistic",
                        "--overlay", f"Leib={tmp_path / 'leib.csv'}", "-o", str(tmp_path / "r.png")],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def workbook(*args):
    return subprocess.run([os.path.join(ROOT, "tools", "workbook"), *map(str, args)], capture_output=True, text=True)


def test_workbook_labels_a_compare_sheet_and_no_path(tmp_path, motionsim):
    table = sim(motionsim, tmp_path / "table.csv", "ramp", "--algo", "simplistic", *LAB)
    leib = sim(motionsim, tmp_path / "leib.csv", "ramp", "--algo", "leib", *LAB)
    out = tmp_path / "lab.xlsx"
    p = workbook(tmp_path / "table.csv", tmp_path / "leib.csv", "--label", "simplistic", "--label", "Leib", "-o", out)
    assert p.returncode == 0, p.stderr
    wb = openpyxl.load_workbook(out)
    assert wb.sheetnames == ["index", "simplistic", "Leib", "compare"]
    ws = wb["compare"]
    rows = {r[0]: r for r in ws.iter_rows(min_row=2, max_row=3, values_only=True)}
    for label, d in (("simplistic", table), ("Leib", leib)):
        _, steps, t, top, first, _ = rows[label]
        assert steps == len(d) == 50
        assert t == pytest.approx(d.columns["t_s"][-1], rel=1e-12)
        assert top == pytest.approx(max(d.columns["speed_sps"]), rel=1e-12)
        assert first == pytest.approx(d.columns["interval_ticks"][0], rel=1e-12)
    assert rows["Leib"][5] == pytest.approx(100 * (leib.columns["t_s"][-1] / table.columns["t_s"][-1] - 1), rel=1e-9)
    assert ws._charts, "no chart on the compare sheet"
    home = str(tmp_path)
    for sheet in wb.worksheets:
        for row in sheet.iter_rows(values_only=True):
            for v in row:
                assert not (isinstance(v, str) and (home in v or v.startswith("/"))), (sheet.title, v)
    # one label, two files: the second is named by its file
    p = workbook(tmp_path / "table.csv", tmp_path / "leib.csv", "--label", "simplistic", "-o", out)
    assert p.returncode == 0, p.stderr
    assert openpyxl.load_workbook(out).sheetnames == ["index", "simplistic", "leib", "compare"]


@pytest.mark.parametrize("labels,why", [(["a", "b", "c"], "3 --label for 2 file(s)"),
                                        (["x", "x"], "the same --label"),
                                        (["a/b"], "cannot name a sheet")])
def test_workbook_refuses_bad_labels(tmp_path, motionsim, labels, why):
    sim(motionsim, tmp_path / "table.csv", "ramp", "--algo", "simplistic", *LAB)
    sim(motionsim, tmp_path / "leib.csv", "ramp", "--algo", "leib", *LAB)
    args = [tmp_path / "table.csv", tmp_path / "leib.csv"]
    for lab in labels:
        args += ["--label", lab]
    p = workbook(*args, "-o", tmp_path / "x.xlsx")
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and why in p.stderr, p.stderr
    assert p.stderr.startswith("workbook: ")
    assert not (tmp_path / "x.xlsx").exists()


def leib_by_the_handout(v0=1.0, vmax=20.0, a=10.0, f=1000.0):
    """The handout's steps 1-6 (float64 here): S = int((vmax² - v0²)/2a), p1 = F/sqrt(v0² + 2a),
    then S - 1 times p <- p(1 + q + 1.5q²), q = -(a/F²)p². Returns S, the exact quotient, p1, p_S."""
    quotient = (vmax * vmax - v0 * v0) / (2 * a)
    s = int(quotient)
    p = p1 = f / math.sqrt(v0 * v0 + 2 * a)
    for _ in range(s - 1):
        q = -(a / (f * f)) * p * p
        p = p * (1 + q + 1.5 * q * q)
    return s, quotient, p1, p


def test_the_leib_plateau_is_explained_with_the_figures_it_has(motionsim):
    s, quotient, p1, ps = leib_by_the_handout()
    r = motionsim("ramp", "--algo", "leib", *LAB)
    _, rows = r.rows()
    cruise = [row["interval_ticks"] for row in rows if s < row["step"] <= 50 - s]   # between the two ramps
    assert cruise and all(c == pytest.approx(ps, rel=1e-5) for c in cruise)
    assert rows[s - 1]["interval_ticks"] == pytest.approx(ps, rel=1e-5)      # the S-th step's interval, held
    figures = {"S": f"int({quotient:.2f}) = {s}", "p1": f"{p1:.3f} ticks", "pS": f"p{s} = {ps:.3f} ticks",
               "rate": f"{1000 / ps:.3f} steps/s", "rounded": f"{1000 / ps:.2f} steps/s",
               "exact": f"sqrt(1 + 2·10·{s}) = {math.sqrt(1 + 20 * s):.2f} steps/s"}
    with open(os.path.join(ROOT, "docs", "ramps.md"), encoding="utf-8") as f:
        doc = f.read()
    section = doc[doc.index("### Why the Leib ramp levels off"):]
    section = section[:section.index("\n## ")] if "\n## " in section else section
    with open(os.path.join(ROOT, "tools", "scenarios", "ramp.json"), encoding="utf-8") as f:
        note = next(x for x in json.load(f) if x["name"] == "ramp_leib_0_50")["note"]
    for key, text in figures.items():
        assert text in section.replace("√", "sqrt"), (key, text)
        if key != "rounded":
            assert text.replace("√", "sqrt") in note.replace("√", "sqrt"), (key, text, note)
    assert f"at {1000 / ps:.2f} steps/s" in note


def test_every_overlay_covers_the_same_time_as_its_scenario():
    scenarios = {}
    for name in ("servo.json", "filter.json"):
        with open(os.path.join(ROOT, "tools", "scenarios", name), encoding="utf-8") as f:
            for s in json.load(f):
                scenarios[s["name"]] = s

    def duration(s):
        return float(s["args"][s["args"].index("--duration") + 1])
    pairs = [(s, scenarios[o]) for s in scenarios.values() for o in s.get("overlay", [])]
    assert any(s["name"] == "servo_pid" for s, _ in pairs)
    for s, o in pairs:
        assert duration(o) == duration(s), (s["name"], o["name"])
