"""Emulator checks of the multiaxis family (MultiAxisStepper: issue 13, several axes on one Mega).

The expectations come from outside the firmware:
  - motionsim (the same lib/ planners on the host, run through the step interrupt's executor):
    `motionsim ramp --algo exact --queue` for an axis alone, `motionsim move` for a coordinated
    move; every STEP edge of every axis is compared with its planned tick;
  - issue 13's definition of a coordinated move: position_i = floor(D_i s(t)) with one s(t) from 0
    to 1, s(t) the closed form of constant acceleration of the profile (v0/vmax/accel the minima of
    the axes' limits scaled by D_max/D_i), computed here in Python;
  - the documented protocol (MotionConsole.h): replies, one DONE per move, ERR for bad input
    with nothing moving.
Edges: the three axes' step interrupts nest (MultiStepEngineIsr.inc), so an edge never waits for
another axis's step; it waits for the core's millis and serial interrupts, which do not nest, and
for the few dozen cycles another axis's interrupt runs with interrupts off. An edge is "exact"
within 1 tick of its plan; the others must be late (never early) by at most OTHER_ISR_CYCLES, the
single-axis engine's bound (checks_sketches.STEPPER_OTHER_ISR_CYCLES), and are counted in the
summary.
"""
import math
import os
import re
import subprocess
import sys

import coord_profile
import emulog
import sketches
from checks_selftest import CheckResult
from emulog import F_CPU

AXES = "xyz"
DEFAULTS = (0.0, 10000.0, 10000.0)  # v0, vmax, accel: MultiAxisStepper.ino
# the longest an edge may wait: the single-axis engine's bound for an edge that meets the core's
# interrupts (checks_sketches.STEPPER_OTHER_ISR_CYCLES, tools/bench's OTHER_ISR_CYCLES); before the
# step interrupts nested, edges waited for other axes' whole steps (several hundred cycles)
OTHER_ISR_CYCLES = 260


def profile_s(d, lim):
    """s(t) of a coordinated move (d: axis -> steps, lim: axis -> (v0, vmax, accel))"""
    dm = max(d.values())
    moving = [k for k in d if d[k] > 0]
    v0 = min(lim[k][0] * dm / d[k] for k in moving)
    vmax = min(lim[k][1] * dm / d[k] for k in moving)
    a = min(lim[k][2] * dm / d[k] for k in moving)
    return coord_profile.profile(dm, v0, vmax, a)[0]


def sim(env, args):
    r = subprocess.run([env.motionsim] + [str(a) for a in args], capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        raise RuntimeError(f"motionsim {' '.join(map(str, args))}: {r.stderr.strip()}")
    return r.stdout


def plan_alone(env, frm, to, lim):
    """whole-tick edge times of an axis alone (motionsim ramp --queue: t_s, the 3rd column, is the edge tick / F)"""
    out = sim(env, ["ramp", "--algo", "exact", "--tick-hz", 16000000, "--queue", "--from", frm, "--to", to,
                    "--v0", lim[0], "--vmax", lim[1], "--accel", lim[2]])
    return [round(float(row.split(",")[2]) * 16e6) for row in out.splitlines()[1:] if row]


def plan_move(env, frm, to, lim):
    """{axis: [ticks]} of a coordinated move (motionsim move)"""
    args = ["move"]
    for ax in AXES:
        if ax in to:
            args += [f"--{ax}", to[ax], f"--from-{ax}", frm[ax], f"--{ax}-v0", lim[ax][0], f"--{ax}-vmax", lim[ax][1],
                     f"--{ax}-accel", lim[ax][2]]
    out = sim(env, args)
    plan = {}
    for row in out.splitlines()[1:]:
        if row:
            t, ax, _, _, _ = row.split(",")
            plan.setdefault(ax, []).append(round(float(t) * 16e6))
    return plan


class EdgeStats:
    def __init__(self):
        self.edges = self.exact = self.late = 0
        self.worst_late = 0
        self.early = []

    def add(self, err, where):
        self.edges += 1
        if abs(err) <= 1:
            self.exact += 1
        elif 0 < err <= OTHER_ISR_CYCLES:
            self.late += 1
            self.worst_late = max(self.worst_late, err)
        else:
            self.early.append(f"{where}: {err:+d} cycles from its plan (bound -1..{OTHER_ISR_CYCLES})")

    def text(self):
        return (f"{self.edges} edges: {self.exact} within 1 tick of motionsim, {self.late} late behind an "
                f"interrupt (worst {self.worst_late} cycles)")


def compare(stats, got, plan, where, t0=None):
    """edges (cycles) against planned ticks (one tick = one cycle), aligned at t0 or at the best offset (the
    smallest one: an edge is late, never early)"""
    if t0 is None:
        t0 = min(g - p for g, p in zip(got, plan))
    for i, (g, p) in enumerate(zip(got, plan)):
        stats.add(g - t0 - p, f"{where} step {i + 1}")
    return t0


def edges_between(log, pin, a, b):
    return [c for c in log.rising(pin) if a < c and (b is None or c < b)]


def dir_ok(log, pin_dir, first_edge, forward):
    return log.level_before(pin_dir, first_edge) == (1 if forward else 0)


def query_lines(log, after=0):
    """the last `?` reply's three lines after `after`: {axis: fields}"""
    out = {}
    for ax in AXES:
        ls = log.lines_matching(rf"^{ax} pos=", after)
        if ls:
            out[ax] = emulog.query_fields(ls[-1].text[2:])
    return out


def run(env, sketch, script, matches=False):
    return emulog.run(env.elf(sketch), script, pins=sketches.multiaxis_pins(env), timeout=600,
                      extra=["--matches"] if matches else None)


def match_errors(log, got, plan):
    """got, plan: {axis: [cycles]}, one move on one timeline: each edge's compare match (motionemu
    --matches, tools/bench's step_matches) against its planned tick, aligned at the earliest"""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "bench"))
    import bench
    mt = bench.step_matches(log, got)
    e = [(c - p, ax, i) for ax in got for i, (c, p) in enumerate(zip(mt[ax], plan[ax]))]
    t0 = min(x for x, _, _ in e)
    return [(x - t0, ax, i) for x, ax, i in e]


def check_moves(env, sketch):
    """Independent moves overlapping in time, then coordinated moves of two and three axes."""
    script = "\n".join([
        "wait ^READY [^ ]+$", "timeout 20000",
        "mark alone", "send x 3000", "wait ^OK x 0 3000$", "send y -1500", "wait ^OK y 0 -1500$",
        "send z 700", "wait ^OK z 0 700$", "timeout 60000",
        "wait ^DONE [xyz] ", "wait ^DONE [xyz] ", "wait ^DONE [xyz] ",
        "send set y vmax 8000", "wait ^OK y vmax=8000$",
        "mark move1", "send move x-1000 y500", "wait ^OK move x 3000 -1000 y -1500 500$", "wait ^DONE move ",
        "mark move2", "send move x0 y0 z0", "wait ^OK move ", "wait ^DONE move ",
        "mark end", "send ?", "wait ^z pos=",
        "mark zero", "send move x0 y0", "wait ^DONE move ", "run 100",
    ]) + "\n"
    log = run(env, sketch, script, matches=True)
    problems = []
    for c, k, t in log.fails:
        problems.append(f"harness reported {k} at {c / F_CPU:.4f} s: {t}")
    marks = [log.mark(m) for m in ("alone", "move1", "move2", "end", "zero")]
    timer = []  # each edge's compare match against its plan (ticks)
    if None in marks:
        return CheckResult(False, "the script did not run to its end", problems +
                           [l.text for l in log.rx[-8:]])
    st = EdgeStats()
    lim = {ax: DEFAULTS for ax in AXES}
    # 1. alone, overlapping
    for ax, to in (("x", 3000), ("y", -1500), ("z", 700)):
        got = edges_between(log, ax.upper() + "STEP", marks[0], marks[1])
        plan = plan_alone(env, 0, to, lim[ax])
        if len(got) != abs(to):
            problems.append(f"{ax} alone: {len(got)} steps, want {abs(to)}")
            continue
        if not dir_ok(log, ax.upper() + "DIR", got[0], to > 0):
            problems.append(f"{ax} alone: DIR not set for the direction before the first step")
        compare(st, got, plan, f"{ax} alone")
        timer += [(x, f"{ax} alone step {i + 1}") for x, _, i in match_errors(log, {ax: got}, {ax: plan})]
    lim["y"] = (DEFAULTS[0], 8000.0, DEFAULTS[2])
    # 2. coordinated: one timeline for all axes (aligned at the earliest offset over all axes)
    worst_path = 0.0
    pos = {"x": 3000, "y": -1500, "z": 700}
    for k, (to, mk) in enumerate(((({"x": -1000, "y": 500}), 1), ({"x": 0, "y": 0, "z": 0}, 2))):
        frm = {ax: pos[ax] for ax in to}
        plan = plan_move(env, frm, to, lim)
        got = {ax: edges_between(log, ax.upper() + "STEP", marks[mk], marks[mk + 1]) for ax in AXES}
        d = {ax: abs(to[ax] - frm[ax]) for ax in to}
        for ax in AXES:
            want = d.get(ax, 0)
            if len(got[ax]) != want:
                problems.append(f"move {k + 1}: {ax} made {len(got[ax])} steps, want {want}")
        if problems:
            continue
        t0 = min(min(g - p for g, p in zip(got[ax], plan[ax])) for ax in plan)
        for ax in plan:
            if not dir_ok(log, ax.upper() + "DIR", got[ax][0], to[ax] > frm[ax]):
                problems.append(f"move {k + 1}: {ax}'s DIR not set before its first step")
            compare(st, got[ax], plan[ax], f"move {k + 1} {ax}", t0)
        timer += [(x, f"move {k + 1} {ax} step {i + 1}")
                  for x, ax, i in match_errors(log, {ax: got[ax] for ax in plan}, plan)]
        # the path bound at every edge of any axis: floor(D s(T - L)) <= |p - from| <= floor(D s(T + L)),
        # L the lateness the edge may have met (OTHER_ISR_CYCLES)
        s_at = profile_s(d, lim)
        events = sorted((c, ax) for ax in plan for c in got[ax])
        made = {ax: 0 for ax in plan}
        i = 0
        while i < len(events):
            c = events[i][0]
            while i < len(events) and events[i][0] == c:
                made[events[i][1]] += 1
                i += 1
            t = (c - t0) / F_CPU
            lo, hi = s_at(t - OTHER_ISR_CYCLES / F_CPU), s_at(t + 1 / F_CPU)
            for ax in plan:
                worst_path = max(worst_path, abs(made[ax] - d[ax] * s_at(t)))
                if not (math.floor(d[ax] * lo) <= made[ax] <= math.floor(d[ax] * hi + 1e-9)):
                    problems.append(f"move {k + 1} at {t:.6f} s: {ax} at {made[ax]} of {d[ax]}, the line says "
                                    f"{d[ax] * s_at(t):.2f}")
                    break
            if len(problems) > 5:
                break
        ends = [got[ax][-1] - t0 - plan[ax][-1] for ax in plan]
        if max(ends) - min(ends) > OTHER_ISR_CYCLES:
            problems.append(f"move {k + 1}: the axes' last edges are {max(ends) - min(ends)} cycles apart")
        for ax in to:
            pos[ax] = to[ax]
    problems += st.early[:10]
    # a move to where the axes are already: accepted (as `x 0` at 0), done at once, nothing moves
    zero = [l.text for l in log.lines_matching(r"^(OK|ERR|DONE)", marks[4])]
    if zero != ["OK move x 0 0 y 0 0", "DONE move x 0 y 0"]:
        problems.append(f"`move x0 y0` at (0, 0): {zero}, want OK move x 0 0 y 0 0, DONE move x 0 y 0")
    if any(edges_between(log, ax.upper() + "STEP", marks[4], None) for ax in AXES):
        problems.append("`move x0 y0` at (0, 0) made steps")
    problems += [f"{w}: its compare match {x:+d} ticks from its plan" for x, w in timer if not -1 <= x <= 1][:10]
    q = query_lines(log, marks[3])
    for ax in AXES:
        f = q.get(ax, {})
        if f.get("pos") != "0" or f.get("underruns") != "0":
            problems.append(f"`?` after the moves: {ax} pos={f.get('pos')} underruns={f.get('underruns')} "
                            "(want 0 and 0)")
    return CheckResult(not problems, f"x, y, z alone at once; move x y; move x y z: {len(timer)} compare matches, "
                       f"{sum(1 for x, _ in timer if -1 <= x <= 1)} within 1 tick of motionsim; on the pins {st.text()}; "
                       f"path: worst |p - D s(t)| = {worst_path:.3f} step", problems)


BAD = [
    ("x", r"^ERR not a number: <axis> <target>: the target is missing$"),
    ("x abc", r"^ERR not a number: a target is a whole number"),
    ("y 1 2", r"^ERR not a number: one target per line$"),
    ("z 2147483648", r"^ERR number out of range: a target is a whole number"),
    ("w 5", r"^ERR unknown command: try "),
    ("move", r"^ERR unknown command: move what\?"),
    ("move x", r"^ERR unknown command: move x<target>"),
    ("move q5", r"^ERR unknown command: move x<target>"),
    ("move x1 x2", r"^ERR unknown command: an axis is named twice$"),
    ("move x1.5", r"^ERR not a number: a target is a whole number"),
    ("move x100000 y1", r"^ERR axes too unequal for a coordinated move"),
    ("set x", r"^ERR unknown command: set <axis> what\?"),
    ("set x vmax", r"^ERR not a number: set <axis> <parameter> <value>: the value is missing$"),
    ("set x vmax 1e9", r"^ERR number out of range: vmax at most \d+ steps/s on this sketch$"),
    ("set x foo 5", r"^ERR unknown command: no such parameter"),
    ("set w vmax 5", r"^ERR unknown command: set <x\|y\|z>"),
    ("set y accel -5", r"^ERR "),
    ("stop q", r"^ERR unknown command: stop \[x\|y\|z\]"),
    ("? 1", r"^ERR unknown command: '\?' takes no arguments$"),
]


def check_bad_input(env, sketch):
    """Bad lines get their ERR and move nothing; a coordinated move of a moving axis, and a target of an
    axis in a coordinated move, are refused (busy) and change nothing."""
    s = ["wait ^READY [^ ]+$", "timeout 5000", "mark bad"]
    for line, _ in BAD:
        s += [f"send {line}", "wait ^(OK|ERR)"]
    s += ["mark busy", "send x 30000", "wait ^OK x 0 30000$", "send move x0 y10", "wait ^(OK|ERR)",
          "send !", "wait ^OK halt", "wait ^DONE x ", "send move y20000 z10000", "wait ^OK move ",
          "send z 5", "wait ^(OK|ERR)", "send move x5 y5", "wait ^(OK|ERR)", "send ! y", "wait ^OK halt",
          "wait ^DONE move ", "mark end", "send ?", "wait ^z pos=",
          # a named axis already at its target belongs to the move too: no target of its own meanwhile
          "mark named", "send x 0", "wait ^DONE x 0$", "send move y0 x0", "wait ^OK move ", "send x 500",
          "wait ^(OK|ERR)", "wait ^DONE move ", "mark named_end"]
    log = run(env, sketch, "\n".join(s) + "\n")
    problems = []
    for c, k, t in log.fails:
        problems.append(f"harness reported {k} at {c / F_CPU:.4f} s: {t}")
    mb, mbusy, me = log.mark("bad"), log.mark("busy"), log.mark("end")
    if None in (mb, mbusy, me):
        return CheckResult(False, "the script did not run to its end", problems + [l.text for l in log.rx[-8:]])
    replies = [l.text for l in log.lines_matching(r"^(OK|ERR|DONE)", mb, mbusy)]
    if len(replies) != len(BAD):
        problems.append(f"{len(replies)} replies to {len(BAD)} bad lines: {replies}")
    for (line, want), got in zip(BAD, replies):
        if not re.match(want, got):
            problems.append(f"{line!r} -> {got!r}, want /{want}/")
    for ax in AXES:
        n = len(edges_between(log, ax.upper() + "STEP", mb, mbusy))
        if n:
            problems.append(f"{n} {ax} steps during the bad lines")
    busy = [l.text for l in log.lines_matching(r"^(OK|ERR|DONE)", mbusy, me)]
    want = [r"^OK x 0 30000$", r"^ERR busy: a move is in progress: x is moving", r"^OK halt$", r"^DONE x \d+$",
            r"^OK move y 0 20000 z 0 10000$", r"^ERR busy: a move is in progress: the axis is in a coordinated move",
            r"^ERR busy: a move is in progress: y is moving", r"^OK halt$", r"^DONE move y \d+ z \d+$"]
    if len(busy) != len(want) or not all(re.match(w, g) for w, g in zip(want, busy)):
        problems.append(f"busy replies {busy}")
    else:
        x_done = int(busy[3].split()[2])
        yz = busy[8].split()
        counted = {ax: len(edges_between(log, ax.upper() + "STEP", mbusy, me)) for ax in AXES}
        if counted["x"] != x_done or counted["y"] != int(yz[3]) or counted["z"] != int(yz[5]):
            problems.append(f"DONE positions {busy[3]}, {busy[8]} but pulses {counted}")
        if int(yz[3]) == 0 or abs(int(yz[3]) - 2 * int(yz[5])) > 1:
            problems.append(f"the halted coordinated move is off its line (y = 2 z within a step): {busy[8]}")
    q = query_lines(log, me)
    if q.get("x", {}).get("state") != "idle" or q.get("z", {}).get("mode") != "idle":
        problems.append(f"after the halts: {q}")
    mn, mne = log.mark("named"), log.mark("named_end")
    named = [l.text for l in log.lines_matching(r"^(OK|ERR|DONE)", mn, mne)] if None not in (mn, mne) else []
    want = [r"^OK x -?\d+ 0$", r"^DONE x 0$", r"^OK move x 0 0 y \d+ 0$",
            r"^ERR busy: a move is in progress: the axis is in a coordinated move", r"^DONE move x 0 y 0$"]
    if len(named) != len(want) or not all(re.match(w, g) for w, g in zip(want, named)):
        problems.append(f"a target for x, named at its target in a coordinated move: replies {named}, "
                        "expected ERR busy and 'DONE move x 0 y 0'")
    elif edges_between(log, "XSTEP", log.lines_matching(r"^OK move x 0 0", mn, mne)[0].cycle, mne):
        problems.append("x stepped while named in a coordinated move at its target")
    return CheckResult(not problems, f"{len(BAD)} bad lines -> {len(replies)} ERR, no step; busy cases refused; "
                       f"halt of a coordinated move keeps it on its line", problems)


def check_stop(env, sketch):
    """stop decelerates (a coordinated move's axes stop together), `stop x` stops one axis; one DONE per
    move, at the pulses counted."""
    s = ["wait ^READY [^ ]+$", "timeout 20000", "mark a",
         "send move x40000 y20000", "wait ^OK move ", "run 300", "send stop", "wait ^OK stop$", "wait ^DONE move ",
         "mark b", "send x 30000", "wait ^OK x ", "send z -10000", "wait ^OK z ", "run 200", "send stop x",
         "wait ^OK stop$", "wait ^DONE x ", "wait ^DONE z -10000$", "send stop", "wait ^OK stop \\(not moving\\)$",
         "mark c", "send ?", "wait ^z pos="]
    log = run(env, sketch, "\n".join(s) + "\n")
    problems = []
    for c, k, t in log.fails:
        problems.append(f"harness reported {k} at {c / F_CPU:.4f} s: {t}")
    ma, mb, mc = log.mark("a"), log.mark("b"), log.mark("c")
    if None in (ma, mb, mc):
        return CheckResult(False, "the script did not run to its end", problems + [l.text for l in log.rx[-8:]])
    done = log.first(r"^DONE move ", ma, mb).text.split()
    px, py = int(done[3]), int(done[5])
    cx = len(edges_between(log, "XSTEP", ma, mb))
    cy = len(edges_between(log, "YSTEP", ma, mb))
    if (px, py) != (cx, cy):
        problems.append(f"{' '.join(done)} but pulses x {cx} y {cy}")
    if not (0 < px < 40000 and abs(px - 2 * py) <= 2):
        problems.append(f"the stopped coordinated move: x {px} y {py} (want 0 < x < 40000, x = 2 y within 2)")
    dx = int(log.first(r"^DONE x ", mb, mc).text.split()[2])
    if not px < dx < 30000 or dx - px != len(edges_between(log, "XSTEP", mb, mc)):
        problems.append(f"stop x: DONE x {dx} from {px}, pulses {len(edges_between(log, 'XSTEP', mb, mc))}")
    q = query_lines(log, mc)
    if q.get("x", {}).get("pos") != str(dx) or q.get("z", {}).get("pos") != "-10000":
        problems.append(f"`?` after the stops: {q}")
    return CheckResult(not problems, f"stop of move x40000 y20000 at x {px} y {py}; x {px} -> 30000 stopped at {dx} "
                       "while z went on "
                       "to -10000", problems)


# Issue 13's case, in make test's short form (make bench measures the whole ladder): three
# independent moves at once, every axis accelerating to the shipped limit (max_sps in `?`,
# MultiAxisPins.h's MULTI_MAX_SPS; the reference move: 20,000 steps, acceleration vmax^2/10,000),
# each target after the OK of the one before, with a `?` during the move; every step, no underrun, no
# late edge, every edge on its own plan (motionsim ramp --queue) within 1 tick or late behind an
# interrupt by at most OTHER_ISR_CYCLES (tools/bench aligns each axis at its earliest edge).


def bench_module(env):
    """tools/bench/bench.py, imported"""
    path = os.path.join(env.source_dir, "tools", "bench")
    if path not in sys.path:
        sys.path.insert(0, path)
    import bench
    return bench


def bench_run(env, sketch, mode, rate, timing="ok"):
    """tools/bench's run of one case on the sketch (the same run as `make bench`; timing: how the
    host sends independent targets, bench.MULTI_TIMINGS): its result and the problems every at-speed
    check asserts (a step missing, underruns, an edge beyond OTHER_ISR_CYCLES, a compare match off its
    plan)"""
    bench = bench_module(env)
    pins = {k: v for k, v in sketches.multiaxis_pins(env).items() if k.endswith("STEP")}
    res = bench.run_multi(env.elf(sketch), env.motionsim, mode, AXES, rate, pins, timing)
    problems = [p for p in res["problems"] if p != "not clean"]
    if res.get("underruns") != 0:
        problems.append(f"underruns: {res.get('underruns')}")
    if "worst" in res and not -1 <= res["worst"] <= OTHER_ISR_CYCLES:
        problems.append(f"an edge {res['worst']:+d} cycles from its plan (bound -1..{OTHER_ISR_CYCLES})"
                        + (f"; the axes' last edges {res['end_spread']} cycles apart" if "end_spread" in res else ""))
    if "match_worst" in res and res["match_worst"] > 1:
        problems.append(f"a compare match {res['match_worst']:+d} ticks from its plan (bound 1)")
    return res, problems


def check_three_axes_at_speed(env, sketch):
    v = shipped_limit(env, sketch)
    res, problems = bench_run(env, sketch, "independent", v)
    if res.get("late") != 0:
        problems.append(f"late edges: {res.get('late')}")
    summary = (f"x, y, z each to {v:,} steps/s (the shipped limit) at once: {res.get('steps', 0):,} steps per axis, "
               f"underruns {res.get('underruns')}, late {res.get('late')}, every compare match within "
               f"{res.get('match_worst', '-')} tick(s) of its plan, STEP {res.get('pin_latency', ('-', '-'))[0]} to "
               f"{res.get('pin_latency', ('-', '-'))[1]} cycles after it, worst edge {res.get('worst', '-')} cycles "
               f"from its plan, {res.get('beyond8', '-')} edges beyond 8 cycles")
    return CheckResult(not problems, summary, problems)


# A coordinated move of unequal axes from rest, slow enough that each axis's first interval spans
# several timer wraps (tools/bench's `unequal` case at 5,000 steps/s: x 20,000, y 15,000, z 10,000
# steps, acceleration 2,500 steps/s^2): the axes are armed from one start tick a little ahead of the
# timer, and an axis whose first compare value comes round before that tick must let that match pass
# (y's does: its first interval ends 1,688 ticks short of a whole number of wraps). Every edge on the
# plan (motionsim move, one alignment for all axes) within OTHER_ISR_CYCLES, no underrun.
UNEQUAL_SLOW_SPS = 5000


def check_unequal_slow_start(env, sketch):
    res, problems = bench_run(env, sketch, "unequal", UNEQUAL_SLOW_SPS)
    import bench  # bench_run put tools/bench on the path
    summary = (f"move x{bench.UNEQUAL['x']} y{bench.UNEQUAL['y']} z{bench.UNEQUAL['z']} at {UNEQUAL_SLOW_SPS:,} "
               f"steps/s: worst edge {res.get('worst', '-')} cycles from its plan, last edges "
               f"{res.get('end_spread', '-')} cycles apart, underruns {res.get('underruns')}")
    return CheckResult(not problems, summary, problems)


# Issue 26: three targets at the shipped limit sent back to back underran (the planning of the later
# axes' first commands starved the running axes' queues: x, y and z paused mid-acceleration). The
# issue's reproducer, at the limit the sketch reports (`max_sps` in `?`) with the issue's acceleration
# (90,000 steps/s^2, v0 0), must end with every step, its DONE and underruns=0 on every axis in both
# `?` replies; and the bench's independent three-axis move at that limit, its targets sent at every
# other timing of the bench's sweep (back to back, 1, 5 and 20 ms apart, a `?` or a `set` between
# them; tools/bench MULTI_TIMINGS), must be as clean as with each target after the OK of the one
# before (the check above): every step, no underrun, every compare match on its plan except at most
# LATE_FEW late edges, each within the single-axis bound (docs/serial.md's promise for `late=`).
ISSUE26_ACCEL = 90000
LATE_FEW = 3  # late edges a sweep case may count at the shipped limit (docs/serial.md: "at most a few")


def shipped_limit(env, sketch):
    """max_sps, what the sketch as built reports in `?` (MultiAxisPins.h's MULTI_MAX_SPS)"""
    log = run(env, sketch, "wait ^READY [^ ]+$\nsend ?\nwait ^z pos=\n")
    q = query_lines(log)
    return int(float(q["x"]["max_sps"]))


def check_targets_any_timing(env, sketch):
    problems = []
    v = shipped_limit(env, sketch)
    s = ["wait ^READY [^ ]+$", "timeout 20000"]
    for ax in AXES:
        for k, val in (("vmax", v), ("accel", ISSUE26_ACCEL), ("v0", 0)):
            s += [f"send set {ax} {k} {val}", f"wait ^(OK|ERR) "]
    s += ["mark go", "send x 20000", "send y 20000", "send z 20000", "run 300", "mark q1", "send ?",
          "timeout 60000", "wait ^DONE z ", "mark q2", "send ?", "wait ^z pos=", "run 100"]
    log = run(env, sketch, "\n".join(s) + "\n")
    for c, k, t in log.fails:
        problems.append(f"harness reported {k} at {c / F_CPU:.4f} s: {t}")
    go, q1, q2 = log.mark("go"), log.mark("q1"), log.mark("q2")
    if None in (go, q1, q2):
        return CheckResult(False, "the reproducer did not run to its end", problems + [l.text for l in log.rx[-8:]])
    errs = [l.text for l in log.rx if l.text.startswith("ERR")]
    if errs:
        problems.append(f"refused: {errs}")
    replies = [l.text for l in log.lines_matching(r"^(OK|DONE) [xyz] ", go)]
    want = [f"OK {ax} 0 20000" for ax in AXES]
    if replies[:3] != want or sorted(replies[3:]) != [f"DONE {ax} 20000" for ax in AXES]:
        problems.append(f"replies {replies}, want {want} and a DONE <axis> 20000 each")
    steps = {ax: len(edges_between(log, ax.upper() + "STEP", go, None)) for ax in AXES}
    if any(n != 20000 for n in steps.values()):
        problems.append(f"steps {steps}, want 20000 per axis")
    under = {}
    for name, after in (("300 ms after the targets", q1), ("after DONE z", q2)):
        q = query_lines(log, after)
        under[name] = {ax: q.get(ax, {}).get("underruns") for ax in AXES}
        if any(u != "0" for u in under[name].values()):
            problems.append(f"`?` {name}: underruns {under[name]} (want 0 on every axis)")
    sweep = []
    timings = [t for t in bench_module(env).MULTI_TIMINGS if t != "ok"]
    for timing in timings:
        res, p = bench_run(env, sketch, "independent", v, timing)
        late = res.get("late")
        if late is not None and 0 < late <= LATE_FEW:
            # docs/serial.md: at the shipped limit `late=` counts at most a few edges, each within the
            # bound (a step interrupt nested in another holds the outer one's next arming: at some
            # timings one edge, 108 cycles); such an edge's compare match is off its plan by as much
            p = [x for x in p if not x.startswith("a compare match")]
            if res.get("match_worst", 0) > OTHER_ISR_CYCLES:
                p.append(f"a compare match {res['match_worst']:+d} ticks from its plan (bound {OTHER_ISR_CYCLES} "
                         f"for a late edge)")
        elif late != 0:
            p.append(f"late edges: {late} (at most {LATE_FEW}, each within the bound)")
        problems += [f"targets `{timing}`: {x}" for x in p]
        sweep.append(f"{timing} {'clean' if not p and not late else ('within the bound, late ' + str(late) if not p else 'NOT clean')}")
    summary = (f"x, y, z 20000 back to back at the shipped limit {v:,} steps/s (accel {ISSUE26_ACCEL:,}): steps "
               f"{steps}, underruns {under.get('after DONE z')}; the reference move with its targets "
               + ", ".join(sweep))
    return CheckResult(not problems, summary, problems)


def checks_for(env):
    checks = []
    for n in env.sketch_names():
        try:
            fam = env.family(n)
        except sketches.SketchError:
            continue  # checks_sketches reports a sketch without its marker
        if fam != "multiaxis":
            continue
        checks.append((f"{n}: x, y, z alone and coordinated moves: steps, DIR, every compare match and edge "
                       "against motionsim, the path bound", lambda n=n: check_moves(env, n)))
        checks.append((f"{n}: bad input gets ERR and moves nothing; busy axes refused",
                       lambda n=n: check_bad_input(env, n)))
        checks.append((f"{n}: stop, stop <axis>: one DONE per move, where the pulses end",
                       lambda n=n: check_stop(env, n)))
        checks.append((f"{n}: three independent axes at the shipped limit (max_sps) each: every step, no underrun",
                       lambda n=n: check_three_axes_at_speed(env, n)))
        checks.append((f"{n}: a slow coordinated move of unequal axes starts every axis on its plan",
                       lambda n=n: check_unequal_slow_start(env, n)))
        checks.append((f"{n}: three targets at the shipped limit, back to back or at any timing: no underrun "
                       "(issue 26)", lambda n=n: check_targets_any_timing(env, n)))
    return checks
