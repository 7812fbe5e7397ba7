"""motionsim ramp --algo smooth: the filter-shaped move (lib/src/smooth_move.h).

Expected values from the definition: the velocity command (a rectangle) through two moving
averages tau1 = vmax/accel and tau2 = accel/jerk: the move ends at exactly the target after
T + tau1 + tau2 (T = distance/vmax for long moves), the speed never exceeds vmax, the acceleration
never exceeds accel and the jerk never exceeds jerk; bad input is one line on stderr, exit 2."""
import csv
import io

import pytest

LONG = ["--from", "0", "--to", "2000", "--vmax", "2000", "--accel", "8000", "--jerk", "80000",
        "--tick-hz", "16000000"]


def test_table_reaches_the_target_within_the_limits(motionsim):
    r = motionsim("ramp", "--algo", "smooth", *LONG)
    assert r.rc == 0, r.err
    header, rows = r.rows()
    assert header == ["step", "position", "t_s", "interval_ticks", "speed_sps", "accel_sps2", "jerk_sps3"]
    assert len(rows) == 2000 and rows[-1]["position"] == 2000
    # T = 2000/2000 = 1 s, tau1 = 0.25 s, tau2 = 0.1 s: the last step at 1.35 s
    assert rows[-1]["t_s"] == pytest.approx(1.35, abs=1e-9)
    assert max(x["speed_sps"] for x in rows) <= 2000 * (1 + 1e-9)
    assert max(abs(x["accel_sps2"]) for x in rows) <= 8000 * (1 + 1e-9)
    assert max(abs(x["jerk_sps3"]) for x in rows) <= 80000 * (1 + 1e-9)
    # the cruise at vmax, accel and jerk reached
    assert max(abs(x["accel_sps2"]) for x in rows) >= 8000 * (1 - 1e-9)
    assert max(abs(x["jerk_sps3"]) for x in rows) >= 80000 * (1 - 1e-9)
    # times rise; step 1000 (half the distance) at half the time of the symmetric move
    assert all(b["t_s"] > a["t_s"] for a, b in zip(rows, rows[1:]))
    assert rows[999]["position"] == 1000 and rows[999]["t_s"] == pytest.approx(0.675, abs=1e-9)


def test_reverse_move_counts_down(motionsim):
    r = motionsim("ramp", "--algo", "smooth", "--from", "10", "--to", "-10", "--vmax", "20", "--accel", "10",
                  "--jerk", "40")
    assert r.rc == 0, r.err
    _, rows = r.rows()
    assert [x["position"] for x in rows] == list(range(9, -11, -1))


def test_queue_edges_match_the_exact_times(motionsim):
    exact = motionsim("ramp", "--algo", "smooth", *LONG).rows()[1]
    q = motionsim("ramp", "--algo", "smooth", "--queue", *LONG)
    assert q.rc == 0, q.err
    _, rows = q.rows()
    assert len(rows) == 2000
    for a, b in zip(exact, rows):
        # the executor starts at half a tick: its edge is floor(F t_n + 0.5) within 1 tick
        assert abs(round(b["t_s"] * 16e6) - round(a["t_s"] * 16e6)) <= 1  # the queue's edges are whole ticks


def test_queue_stop_and_retarget(motionsim):
    r = motionsim("ramp", "--algo", "smooth", "--queue", *LONG, "--retarget-at", "500:3000")
    assert r.rc == 0, r.err
    _, rows = r.rows()
    assert rows[-1]["position"] == 3000
    s = motionsim("ramp", "--algo", "smooth", "--queue", *LONG, "--stop-at", "800")
    assert s.rc == 0, s.err
    _, rows = s.rows()
    assert 800 < rows[-1]["position"] < 2000
    back = motionsim("ramp", "--algo", "smooth", "--queue", *LONG, "--retarget-at", "1000:100")
    assert back.rc == 0, back.err
    _, rows = back.rows()
    assert rows[-1]["position"] == 100


def test_compare_rows(motionsim):
    r = motionsim("ramp", "--algo", "smooth", "--compare", *LONG)
    assert r.rc == 0, r.err
    rows = list(csv.DictReader(io.StringIO(r.out)))
    assert [x["algo"] for x in rows] == ["trapezoid", "smooth", "sigmoid"]
    trap, smooth = rows[0], rows[1]
    assert float(trap["move_time_s"]) == pytest.approx(1.25, abs=1e-9)    # 1 s + vmax/accel
    assert float(smooth["move_time_s"]) == pytest.approx(1.35, abs=1e-9)  # 1 s + tau1 + tau2
    # measured from step times: the trapezoid's acceleration jumps, the smooth move's does not
    assert float(trap["peak_jerk_sps3"]) > 50 * float(smooth["peak_jerk_sps3"])


@pytest.mark.parametrize("args,msg", [
    (["--to", "20"], "needs --jerk"),
    (["--to", "20", "--jerk", "4"], "jerk too low"),
    (["--to", "20", "--jerk", "0"], "jerk must be greater than 0"),
    (["--to", "20", "--jerk", "-3"], "jerk must be greater than 0"),
    (["--to", "20", "--jerk", "nan"], "--jerk"),
    (["--to", "20", "--jerk", "40", "--stop-at", "5"], "needs --queue"),
    (["--to", "20", "--jerk", "40", "--queue", "--stop-at", "50"], "only"),
    (["--to", "20", "--jerk", "40", "--fmin", "5"], "--compare"),
])
def test_bad_input(motionsim, args, msg):
    r = motionsim("ramp", "--algo", "smooth", *args)
    assert r.rc == 2 and r.out == ""
    assert r.err.startswith("motionsim ramp: ") and msg in r.err and r.err.count("\n") == 1


def edge_kinematics(rows, w=16):
    """From the executor's edges alone: speed over windows of w steps (at the window's middle
    time), acceleration and jerk as differences of those w windows apart (each a smoothed
    derivative, so a true bound holds for it up to the edges' whole-tick rounding)."""
    pos = [r["position"] for r in rows]
    t = [r["t_s"] for r in rows]
    vs = [((t[i] + t[i + w]) / 2, (pos[i + w] - pos[i]) / (t[i + w] - t[i])) for i in range(len(t) - w)]
    acc = [((a[0] + b[0]) / 2, (b[1] - a[1]) / (b[0] - a[0])) for a, b in zip(vs, vs[w:])]
    jerk = [((a[0] + b[0]) / 2, (b[1] - a[1]) / (b[0] - a[0])) for a, b in zip(acc, acc[w:])]
    return max(abs(v) for _, v in vs), max(abs(a) for _, a in acc), max(abs(j) for _, j in jerk)


MOVE4000 = ["--from", "0", "--to", "4000", "--vmax", "2000", "--accel", "8000", "--jerk", "80000",
            "--tick-hz", "16000000"]


@pytest.mark.parametrize("events,end,jerk_factor", [
    ([], 4000, 1.05),
    (["--stop-at", "1500"], None, 1.05),             # stop in the cruise
    (["--stop-at", "200"], None, 1.05),              # stop while the acceleration ramps down: put off (it reached 2 J)
    (["--stop-at", "120"], None, 1.05),              # just before that ramp-down
    (["--retarget-at", "1500:6000"], 6000, 1.05),    # further, in the cruise
    (["--retarget-at", "3700:6000"], 6000, 1.05),    # further, while decelerating
    (["--retarget-at", "300:900"], 900, 1.05),       # nearer, while accelerating
    (["--retarget-at", "200:700"], 700, 1.05),       # nearer, within the ramp-down: put off
    (["--retarget-at", "300:100"], 100, 1.05),       # behind: stop (put off), then back from rest
])
def test_stop_and_retarget_measured_from_the_edges(motionsim, events, end, jerk_factor):
    """Through the step engine's commands: the speed never above vmax, the acceleration never
    above accel (+2 %) across stops and new targets, and the jerk within 5 % of the limit: a stop
    or a new target whose jerk window would meet one still running of the same sign is put off
    until that one ends (smooth-move.md; until 2026-12-05 they reached twice the limit)."""
    r = motionsim("ramp", "--algo", "smooth", "--queue", *MOVE4000, *events)
    assert r.rc == 0, r.err
    _, rows = r.rows()
    if end is not None:
        assert rows[-1]["position"] == end
    v, a, j = edge_kinematics(rows)
    assert v <= 2000 * 1.0001
    assert a <= 8000 * 1.02
    assert j <= 80000 * jerk_factor
