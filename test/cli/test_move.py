"""motionsim move: coordinated moves of X, Y and Z (issue 13: several axes on one Mega).

Golden data: issue 13's definition of a coordinated move, position_i = floor(D_i s(t)) with one s(t)
from 0 to 1, where s(t) is the closed form of constant acceleration ("uniform acceleration, constant
speed and uniform deceleration", the lab handout) of the profile whose v0/vmax/accel are the minima
of every axis's limits scaled by D_max/D_i; all computed here in Python, independently of lib/.
"""
import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "emu"))
from coord_profile import profile  # noqa: E402  (test/emu: the same reference as the emulator checks)

F = 16_000_000


def limits(d, lim):
    """issue 13: each axis's vmax and accel hold -> the profile's, in master steps"""
    dm = max(d.values())
    moving = [k for k in d if d[k] > 0]
    return (min(lim[k][0] * dm / d[k] for k in moving), min(lim[k][1] * dm / d[k] for k in moving),
            min(lim[k][2] * dm / d[k] for k in moving))


def rows_of(r):
    lines = r.out.splitlines()
    assert lines[0] == "t_s,axis,step,position,path_err_steps"
    out = []
    for line in lines[1:]:
        t, ax, step, pos, err = line.split(",")
        out.append((float(t), ax, int(step), int(pos), float(err)))
    return out


CASES = [
    ({"x": 1000, "y": 500}, {}),
    ({"x": 1000, "y": 500, "z": -333}, {}),
    ({"x": -3000, "y": 2999, "z": 1}, {"--y-vmax": 5000, "--z-accel": 20000}),
    ({"x": 20000, "y": 20000, "z": 20000}, {"--vmax": 50000, "--accel": 250000}),
    ({"y": 7}, {"--v0": 100}),
    ({"x": 40000, "z": 12345}, {"--x-vmax": 30000, "--v0": 200, "--z-v0": 50}),
]


@pytest.mark.parametrize("targets,opts", CASES)
def test_every_edge_on_the_line_and_all_end_together(motionsim, targets, opts):
    args = ["move"]
    for k, v in targets.items():
        args += [f"--{k}", v]
    for k, v in opts.items():
        args += [k, v]
    r = motionsim(*args, "--summary")
    assert r.rc == 0, r.err
    rows = rows_of(r)
    d = {k: abs(v) for k, v in targets.items()}
    lim = {}
    for k in d:
        v0 = float(opts.get(f"--{k}-v0", opts.get("--v0", 0)))
        vmax = float(opts.get(f"--{k}-vmax", opts.get("--vmax", 20000)))
        acc = float(opts.get(f"--{k}-accel", opts.get("--accel", 50000)))
        lim[k] = (v0, vmax, acc)
    v0, vmax, a = limits(d, lim)
    s_at, tt = profile(max(d.values()), v0, vmax, a)
    pos = {k: 0 for k in "xyz"}
    last = {}
    steps = {k: 0 for k in "xyz"}
    times = [row[0] for row in rows]
    assert times == sorted(times)
    # positions after every edge of a tick (rows of one tick share the tick)
    i = 0
    while i < len(rows):
        t = rows[i][0]
        j = i
        while j < len(rows) and rows[j][0] == t:
            _, ax, step, p, _ = rows[j]
            steps[ax] += 1
            assert step == steps[ax]
            assert p == pos[ax] + (1 if targets[ax] > 0 else -1)
            pos[ax] = p
            last[ax] = t
            j += 1
        # the path bound: floor(D s(t - 1 tick)) <= |p| <= floor(D s(t + 1 tick)), every axis
        lo, hi = s_at(t - 1.0 / F), s_at(t + 1.0 / F)
        for k in d:
            assert math.floor(d[k] * lo) - 1e-9 <= abs(pos[k]) <= math.floor(d[k] * hi + 1e-9), (t, k, pos[k], d[k] * lo)
        # the path_err column: the distance of the tool from the line, recomputed here
        dd = sum(targets.get(k, 0) ** 2 for k in "xyz")
        pd = sum(pos[k] * targets.get(k, 0) for k in "xyz")
        lam = pd / dd
        dist = math.sqrt(sum((pos[k] - lam * targets.get(k, 0)) ** 2 for k in "xyz"))
        for row in rows[i:j]:
            assert row[4] == pytest.approx(dist, abs=1e-9)
        i = j
    for k in d:
        assert steps[k] == d[k] and pos[k] == targets[k]
    # all axes take their last step on one tick (v0 = 0) and at the closed form's end
    ends = set(last.values())
    if v0 == 0:
        assert len(ends) == 1
    for e in ends:
        assert abs(e - tt) <= 1.5 / F
    summary = r.err.strip()
    assert summary.startswith("summary:") and "last_edge_spread_ticks=" in summary


def test_issue_example_values(motionsim):
    # 1000/500 steps, vmax 20,000, accel 50,000: a triangle, t = 2 sqrt(1000 / 50000) s
    r = motionsim("move", "--x", 1000, "--y", 500, "--summary")
    assert r.rc == 0
    f = dict(kv.split("=") for kv in r.err.split()[1:])
    assert f["steps_x"] == "1000" and f["steps_y"] == "500" and f["steps_z"] == "0"
    assert float(f["time_s"]) == pytest.approx(2 * math.sqrt(1000 / 50000), abs=1.5 / F)
    assert f["last_edge_spread_ticks"] == "0"
    assert float(f["max_path_err_steps"]) < 1.0
    # y's limits scaled by D_x/D_y = 2 bound the profile
    r = motionsim("move", "--x", 1000, "--y", 500, "--y-vmax", 4000, "--y-accel", 10000, "--summary")
    f = dict(kv.split("=") for kv in r.err.split()[1:])
    assert float(f["profile_vmax_sps"]) == 8000 and float(f["profile_accel_sps2"]) == 20000


@pytest.mark.parametrize("args,message", [
    ([], "no axis moves"),
    (["--x", "0", "--y", "0"], "no axis moves"),
    (["--x", "5", "--from-x", "5"], "no axis moves"),
    (["--x", "100000", "--y", "1"], "axes too unequal for a coordinated move"),
    (["--x", "10", "--y-accel", "-1"], "y axis: acceleration must be greater than 0"),
    (["--x", "10", "--vmax", "0"], "maximum speed vmax must be greater than minimum speed v0"),
    (["--x", "10", "--z-vmax", "1e39"], "z axis: a limit does not fit a float"),
    (["--x", "10", "--vmax", "20000000"], "must not exceed the tick rate"),
    (["--x", "ten"], "--x: 'ten' is not a whole number"),
    (["--x", "1", "--w", "1"], "unknown option '--w'"),
])
def test_bad_input_one_line_exit_2(motionsim, args, message):
    r = motionsim("move", *args)
    assert r.rc == 2 and r.out == ""
    assert len(r.err.strip().splitlines()) == 1 and message in r.err, r.err


def test_path_rows_agree_with_the_edge_rows(motionsim):
    """--path: one row per tick with an edge, positions after that tick, each axis's speed F over its last
    interval (held), and the same path error as the edge rows"""
    a = motionsim("move", "--x", 3000, "--y", -1200, "--z", 50)
    b = motionsim("move", "--x", 3000, "--y", -1200, "--z", 50, "--path")
    assert a.rc == 0 and b.rc == 0
    lines = b.out.splitlines()
    assert lines[0] == "t_s,x_pos,y_pos,z_pos,x_speed_sps,y_speed_sps,z_speed_sps,path_err_steps"
    path = [list(map(float, l.split(","))) for l in lines[1:]]
    edges = rows_of(a)
    ticks = sorted({e[0] for e in edges})
    assert [p[0] for p in path] == ticks
    pos = {"x": 0, "y": 0, "z": 0}
    last = {"x": 0.0, "y": 0.0, "z": 0.0}
    speed = {"x": 0.0, "y": 0.0, "z": 0.0}
    by_t = {}
    for t, ax, _, p, err in edges:
        by_t.setdefault(t, []).append((ax, p, err))
    for row in path:
        for ax, p, err in by_t[row[0]]:
            speed[ax] = F / round((row[0] - last[ax]) * F)
            last[ax] = row[0]
            pos[ax] = p
            assert row[7] == pytest.approx(err, abs=1e-12)
        assert row[1:4] == [pos["x"], pos["y"], pos["z"]]
        assert row[4:7] == pytest.approx([speed["x"], speed["y"], speed["z"]], rel=1e-9)
