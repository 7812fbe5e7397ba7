"""motionsim's bound on the rows of a table (issue 22, item 4): --max-rows N, default 1,000,000.

The row counts expected here come from the documented rule, not from motionsim: one row per step,
|to - from| steps for `ramp` (plain, --integer-ticks, sigmoid, --queue), the sum of |to - from| over
the axes for `move`, floor(duration/Ts) + 1 samples for `filter`. Where the rule gives no count up front (--queue with a new target, move
--path), the bound is checked against the table motionsim writes without it: exactly that many
rows pass, one fewer is refused. Every refusal is exit 2, one line on stderr, nothing on stdout
and no -o file. On the code before the bound, the first tests run for minutes (the timeout fails
them).
"""
import json
import os

import pytest

from conftest import ROOT

QUICK = 20  # seconds: a refusal is immediate; the old code writes billions of rows
DEFAULT = 1_000_000


def refused(r, cmd):
    assert r.rc == 2, (r.rc, r.err)
    assert r.out == ""
    lines = r.err.splitlines()
    assert len(lines) == 1, r.err
    assert lines[0].startswith(f"motionsim {cmd}: "), r.err
    return lines[0]


def rows_line(cmd, rows, bound):
    return f"motionsim {cmd}: the table would have {rows} rows, more than --max-rows {bound}: "


@pytest.mark.parametrize("extra", [[], ["--integer-ticks"], ["--queue"], ["--algo", "exact"],
                                   ["--algo", "exact", "--queue", "--v0", "0", "--vmax", "20000", "--accel", "50000",
                                    "--tick-hz", "16000000"]])
def test_ramp_to_int32_max_is_refused_at_once(motionsim, extra, tmp_path):
    out = tmp_path / "t.csv"
    r = motionsim("ramp", "--to", 2147483647, *extra, "-o", out, timeout=QUICK)
    line = refused(r, "ramp")
    assert line.startswith(rows_line("ramp", 2147483647, DEFAULT)), line
    assert "raise --max-rows" in line
    assert not out.exists()


def test_ramp_full_int32_span_counts_2_to_the_32_minus_1(motionsim):
    r = motionsim("ramp", "--from", -2147483648, "--to", 2147483647, timeout=QUICK)
    assert refused(r, "ramp").startswith(rows_line("ramp", 2**32 - 1, DEFAULT))


def test_sigmoid_is_bounded(motionsim):
    r = motionsim("ramp", "--algo", "sigmoid", "--from", 5, "--to", 2_000_005, timeout=QUICK)
    assert refused(r, "ramp").startswith(rows_line("ramp", 2_000_000, DEFAULT))


@pytest.mark.parametrize("frm,to", [(0, 1000), (300, -700)])
def test_ramp_bound_is_inclusive(motionsim, frm, to):
    n = abs(to - frm)
    for extra in ([], ["--queue"]):
        ok = motionsim("ramp", "--from", frm, "--to", to, "--max-rows", n, *extra)
        assert ok.rc == 0, ok.err
        assert len(ok.out.splitlines()) == n + 1  # the header and one row per step
        r = motionsim("ramp", "--from", frm, "--to", to, "--max-rows", n - 1, *extra)
        assert refused(r, "ramp").startswith(rows_line("ramp", n, n - 1))


def test_ramp_queue_retarget_to_int32_min_is_refused_before_writing(motionsim, tmp_path):
    out, cmds = tmp_path / "t.csv", tmp_path / "c.csv"
    r = motionsim("ramp", "--to", 2147483647, "--queue", "--retarget-at", "50:-2147483648", "-o", out,
                  "--commands", cmds, timeout=QUICK)
    line = refused(r, "ramp")
    assert line.startswith(f"motionsim ramp: the table would have more than --max-rows {DEFAULT} rows: "), line
    assert "--retarget-at" in line and "raise --max-rows" in line
    assert not out.exists() and not cmds.exists()


def test_ramp_queue_with_events_bound_matches_the_table(motionsim):
    args = ["ramp", "--queue", "--algo", "leib", "--v0", 200, "--vmax", 20000, "--accel", 50000, "--tick-hz",
            2000000, "--to", 30000, "--retarget-at", "6000:1000,12000:20000"]
    full = motionsim(*args)
    assert full.rc == 0, full.err
    n = len(full.out.splitlines()) - 1
    assert n > 20000  # the detour: more steps than the final |to - from|
    same = motionsim(*args, "--max-rows", n)
    assert same.rc == 0 and same.out == full.out
    line = refused(motionsim(*args, "--max-rows", n - 1), "ramp")
    assert line.startswith(f"motionsim ramp: the table would have more than --max-rows {n - 1} rows: ")


def test_compare_without_cruise_is_bounded_and_with_cruise_is_not(motionsim):
    # accel 1 steps/s^2 to 1e6 steps/s: no cruise anywhere in 2^32 - 1 steps
    r = motionsim("ramp", "--compare", "--from", -2147483648, "--to", 2147483647, "--v0", 1, "--vmax", 1e6,
                  "--accel", 1, "--tick-hz", 2000000, timeout=QUICK)
    line = refused(r, "ramp")
    assert f"--compare would compare more than --max-rows {DEFAULT} steps one by one" in line
    # the lab's parameters cruise for most of the span: summed in one go, no bound needed
    ok = motionsim("ramp", "--compare", "--from", -2147483648, "--to", 2147483647, timeout=QUICK)
    assert ok.rc == 0, ok.err
    assert len(ok.out.splitlines()) == 4


def test_compare_bound_per_algorithm(motionsim):
    # no cruise (vmax never reached in 1000 steps): each algorithm is compared step by step, 1000 steps
    args = ["ramp", "--compare", "--to", 1000, "--v0", 1, "--vmax", 1e5, "--accel", 10, "--tick-hz", 2000000]
    ok = motionsim(*args, "--max-rows", 1000)
    assert ok.rc == 0, ok.err
    assert len(ok.out.splitlines()) == 4
    refused(motionsim(*args, "--max-rows", 999), "ramp")


@pytest.mark.parametrize("cmd", ["ramp", "move", "filter"])
def test_max_rows_zero_and_help(motionsim, cmd):
    base = ["--x", 10] if cmd == "move" else []
    line = refused(motionsim(cmd, *base, "--max-rows", 0), cmd)
    assert "--max-rows" in line
    h = motionsim(cmd, "--help")
    assert h.rc == 0 and "--max-rows N" in h.out and "default 1000000" in h.out


@pytest.mark.parametrize("axes,rows", [({"x": 2147483647}, 2147483647),
                                       ({"x": 2147483647, "y": -2147483648}, 2**32 - 1),
                                       ({"x": 600000, "y": 500000}, 1_100_000)])
def test_move_is_bounded_by_the_steps_of_every_axis(motionsim, axes, rows, tmp_path):
    out = tmp_path / "m.csv"
    args = [a for k, v in axes.items() for a in (f"--{k}", v)]
    line = refused(motionsim("move", *args, "-o", out, timeout=QUICK), "move")
    assert line.startswith(rows_line("move", rows, DEFAULT)), line
    assert not out.exists()


def test_move_rows_bound(motionsim):
    ok = motionsim("move", "--x", 4000, "--y", -1500, "--max-rows", 5500)
    assert ok.rc == 0, ok.err
    assert len(ok.out.splitlines()) == 5501
    line = refused(motionsim("move", "--x", 4000, "--y", -1500, "--max-rows", 5499), "move")
    assert line.startswith(rows_line("move", 5500, 5499))


def test_move_path_bound_matches_the_table(motionsim):
    args = ["move", "--x", 6000, "--y", 4000, "--path"]
    full = motionsim(*args)
    assert full.rc == 0, full.err
    n = len(full.out.splitlines()) - 1
    assert 6000 <= n <= 10000  # one row per tick with an edge: at least the longest axis, at most all
    assert motionsim(*args, "--max-rows", n).out == full.out
    line = refused(motionsim(*args, "--max-rows", n - 1), "move")
    assert line.startswith(f"motionsim move: the table would have more than --max-rows {n - 1} rows"), line
    # the longest axis alone is over the bound: known without counting
    line = refused(motionsim(*args, "--max-rows", 5999), "move")
    assert line.startswith(rows_line("move", 6000, 5999)), line


def test_filter_rows_are_samples_0_to_duration_over_ts(motionsim, tmp_path):
    # docs/motionsim.md: rows k = 0 .. floor(duration/Ts); at Ts = 10 ms, 9999.99 s is 1000000 rows
    ok = motionsim("filter", "--duration", 9999.99, "-o", tmp_path / "f.csv")
    assert ok.rc == 0, ok.err
    out = tmp_path / "g.csv"
    line = refused(motionsim("filter", "--duration", 10000, "-o", out, timeout=QUICK), "filter")
    assert line.startswith(rows_line("filter", 1_000_001, DEFAULT)), line
    assert not out.exists()
    # a csv input of 5 samples is 5 rows
    src = tmp_path / "in.csv"
    src.write_text("u\n1\n1\n1\n1\n1\n")
    assert motionsim("filter", "--input", f"csv:{src}", "--max-rows", 5).rc == 0
    line = refused(motionsim("filter", "--input", f"csv:{src}", "--max-rows", 4), "filter")
    assert line.startswith(rows_line("filter", 5, 4)), line


def test_every_scenario_fits_the_default_bound():
    """tools/scenarios: each ramp/move scenario's rows by the rule, well under the default."""
    for f in sorted(os.listdir(os.path.join(ROOT, "tools", "scenarios"))):
        with open(os.path.join(ROOT, "tools", "scenarios", f)) as fh:
            for s in json.load(fh):
                a = s["args"]
                if a[0] == "ramp" and "--compare" not in a:
                    frm = int(a[a.index("--from") + 1]) if "--from" in a else 0
                    to = int(a[a.index("--to") + 1]) if "--to" in a else 50
                    assert abs(to - frm) <= DEFAULT // 10, s["name"]
                elif a[0] == "filter":
                    d = float(a[a.index("--duration") + 1]) if "--duration" in a else 20
                    ts = float(a[a.index("--ts") + 1]) if "--ts" in a else 0.01
                    assert d / ts + 1 <= DEFAULT // 10, s["name"]
                elif a[0] == "move":
                    n = sum(abs(int(a[a.index(k) + 1])) for k in ("--x", "--y", "--z") if k in a)
                    assert n <= DEFAULT // 10, s["name"]
