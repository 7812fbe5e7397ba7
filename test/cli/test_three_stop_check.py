"""test/emu/checks_library.py's three_stop, the ThreeSteppers stop check, on step edges made here from
the constant-acceleration law (t_k = sqrt(2k/a) from rest; to rest, the same mirrored): an axis still
accelerating at the switch must be found decelerating from its own speed, and a velocity jump at the
start of its deceleration must be reported."""
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "test", "emu"))
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))
import checks_library  # noqa: E402

F = 16_000_000
A = 50_000.0  # steps/s^2
V = 25_000.0  # the Steppers' vmax: this axis never reaches it


class Line:
    def __init__(self, cycle, text):
        self.cycle, self.text = cycle, text


class FakeLog:
    """what three_stop reads of an emulator log: the replies, the switch, X's STEP rises"""

    def __init__(self, edges, switch, end):
        self.edges = edges
        self.events = [(switch, "input", "D3 = 0")]
        made = len(edges)
        self.rx = [Line(1000, "ROUND 3 0 u=0"), Line(end, f"DONE {made} underruns=0"),
                   Line(end + 10, f"AT {made} u=0")]

    def rising(self, pin):
        return list(self.edges) if pin == "XSTEP" else []


def run(k_up, n_down):
    """k_up steps from rest, then n_down steps to rest starting one interval later (n_down = k_up:
    the same speed, no jump); the switch 3 ms before the deceleration starts"""
    t0 = 2000
    up = [t0 + round(F * math.sqrt(2 * k / A)) for k in range(1, k_up + 1)]
    v_s = math.sqrt(2 * A * n_down)
    start = up[-1] + round(F * (math.sqrt(2 * k_up / A) - math.sqrt(2 * (k_up - 1) / A)))
    down = [start + round(F * (v_s / A - math.sqrt(2 * (n_down - j) / A))) for j in range(1, n_down + 1)]
    edges = up + [start] + down
    switch = start - 3 * F // 1000
    problems = []
    lats = checks_library.three_stop(FakeLog(edges, switch, edges[-1] + 1000), problems, "fake", 1, V, A)
    return lats, problems


def test_accelerating_axis_decelerates_from_its_own_speed():
    lats, problems = run(4000, 4000)
    assert problems == []
    # the deceleration's first edge, 3 ms after the switch: found at the top speed to within a few steps
    # (0.25 ms: 5 intervals there, about 22,000 steps/s)
    assert lats is not None and abs(lats[0] - 3.0) < 0.25


def test_velocity_jump_is_reported():
    # the deceleration starts from 80 % of the speed reached: 0.64 of the steps to rest
    lats, problems = run(4000, 2560)
    assert any("velocity jump" in p for p in problems), problems
