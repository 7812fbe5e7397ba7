"""motionsim servo --profile smooth: the servo sketches' `move <counts>` on the plant model, and
the figures of docs/servo-move.md (tools/servo_move.py).

The setpoints are checked against the filter-shaped move's closed form, written here in exact
rational arithmetic: the command (height h = vmax, length T = distance/vmax, as the rule of
lib/src/smooth_move.h gives for a 1000-count move at the default vmax 3000, accel 20000, jerk
400000) through the two moving averages tau1 = vmax/accel, tau2 = accel/jerk:
    p(t) = h [P(t) - P(t - T)],  P(t) = [r(t) - r(t - tau1) - r(t - tau2) + r(t - tau1 - tau2)] / (tau1 tau2),
    r(x) = max(x, 0)^3 / 6; the setpoint of period k is p(k x 20 ms) rounded to the nearest count."""
import os
import re
import subprocess
import sys
from fractions import Fraction as Fr

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def r3(x):
    return x * x * x / 6 if x > 0 else Fr(0)


def shaped(t, d=1000, vmax=3000, accel=20000, jerk=400000):
    t1, t2 = Fr(vmax, accel), Fr(accel, jerk)
    h, T = Fr(vmax), Fr(d, vmax)
    assert d >= vmax * (t1 + t2)  # the rule's first case: full height

    def P(x):
        return (r3(x) - r3(x - t1) - r3(x - t2) + r3(x - t1 - t2)) / (t1 * t2)
    return h * (P(t) - P(t - T))


def round_half_away(x):
    return int(x + Fr(1, 2)) if x >= 0 else -int(-x + Fr(1, 2))


def test_setpoint_follows_the_closed_form(motionsim):
    r = motionsim("servo", "--ctrl", "p", "--kp", "0.3", "--setpoint", "1000", "--duration", "1", "--profile", "smooth")
    assert r.rc == 0, r.err
    _, rows = r.rows()
    want = [round_half_away(shaped(Fr(20 * k, 1000))) for k in range(len(rows))]
    got = [int(x["setpoint"]) for x in rows]
    assert got == want
    assert got[0] == 0 and got[-1] == 1000 and len(set(got)) > 20
    # the error column is against the setpoint in force
    assert all(x["error_counts"] == x["setpoint"] - x["position_counts"] for x in rows)


def test_step_profile_is_today_s_output(motionsim):
    base = motionsim("servo", "--ctrl", "p", "--kp", "0.3", "--duration", "1")
    step = motionsim("servo", "--ctrl", "p", "--kp", "0.3", "--duration", "1", "--profile", "step", "--metrics")
    assert base.out == step.out
    m = dict(kv.split("=") for kv in re.search(r"^metrics: (.*)$", step.err, re.M).group(1).split())
    assert float(m["peak_tracking_error_counts"]) == 1000  # the whole step at t = 0
    assert float(m["peak_duty_pct"]) == 100


def test_figures_in_docs_are_current_and_the_overshoot_is_halved():
    """docs/servo-move.md is what tools/servo_move.py writes now (exit 1 on drift, or when the
    standard move's overshoot is not at least halved)."""
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "servo_move.py"), "--check"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    with open(os.path.join(ROOT, "docs", "servo-move.md")) as f:
        text = f.read()
    m = re.search(r"overshoot ([\d.]+) % with the step, ([\d.]+) % with `move`", text)
    assert m and float(m.group(2)) <= float(m.group(1)) / 2


@pytest.mark.parametrize("args,msg", [
    (["--vmax", "2000"], "--vmax needs --profile smooth"),
    (["--profile", "step", "--jerk", "1e6"], "--jerk needs --profile smooth"),
    (["--profile", "smooth", "--jerk", "100"], "jerk too low"),
    (["--profile", "smooth", "--jerk", "0"], "jerk must be greater than 0 counts/s^3"),
    (["--profile", "smooth", "--accel", "-1"], "acceleration must be greater than 0"),
    (["--profile", "ramp"], "--profile"),
])
def test_bad_input(motionsim, args, msg):
    r = motionsim("servo", *args)
    assert r.rc == 2 and r.out == ""
    assert r.err.startswith("motionsim servo: ") and msg in r.err and r.err.count("\n") == 1


def test_docs_quote_the_sketches_constants(motionsim):
    """docs/servo.md's move constants are the sketches' and motionsim's defaults."""
    want = {"moveVmax": 3000, "moveAccel": 20000, "moveJerk": 400000}
    for sk in ("ProportionalClosedLoop", "PIDClosedLoop"):
        with open(os.path.join(ROOT, "firmware", sk, sk + ".ino")) as f:
            src = f.read()
        for name, v in want.items():
            m = re.search(rf"const float {name} = (\d+);", src)
            assert m and int(m.group(1)) == v, (sk, name)
    help_text = motionsim("servo", "--help").out
    for opt, v in (("--vmax", 3000), ("--accel", 20000), ("--jerk", 400000)):
        assert re.search(rf"{opt} \S+ .*\(default {v}\)", help_text), opt
    with open(os.path.join(ROOT, "docs", "servo.md")) as f:
        doc = f.read()
    assert "`moveVmax` 3000 counts/s" in doc and "`moveAccel` 20000 counts/s²" in doc
    assert "`moveJerk` 400000 counts/s³" in doc and "τ1 = 0.15 s, τ2 = 0.05 s" in doc
