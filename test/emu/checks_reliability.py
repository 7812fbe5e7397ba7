"""Issue 22's reproducers, checked on the emulated ATmega2560 against the documented rules
(docs/serial.md "Input overrun", docs/stepper-engine.md "Stop and redirect a move"):

- `set accel` (or vmax) while moving, then a new target: the replan starts from the speed reached.
  Oracle: the law of constant acceleration itself. Over two consecutive windows of W steps lasting
  T1 and T2, the average speeds differ by at most a_max (T1 + T2)/2 (for constant acceleration the
  average speed over a window is the speed at its middle time), a_max the larger of the two accels;
  the edges on the pin may wait for another interrupt by up to STEP_LATE_CYCLES (the documented
  single-axis bound), which moves a window's speed by at most v 2 late / T. No window is faster than
  the larger vmax by more than that. `?` afterwards: underruns=0 late=0.
- A flood of lines sent at once (the issue's `100000`, then 80 x `?`, -7777, `?`, 9999): no line that
  lost a byte is executed (every OK names a value that was sent), every line sent gets one reply or
  is counted in an `ERR input overrun: N line(s) lost` reply (exactly: replies + sum N = lines
  sent), those replies come without waiting for a later line, and the sketch answers afterwards.
"""
import math
import os
import re
import sys

import emulog
import sketches
from checks_selftest import CheckResult
from emulog import F_CPU

STEP_LATE_CYCLES = 260  # docs/stepper-engine.md: an edge is at most this late after its compare match
WINDOW = 8

OVERRUN_RE = re.compile(r"^ERR input overrun: (\d+) lines? lost$")


def fails_of(log, problems):
    for c, k, t in log.fails:
        problems.append(f"harness: {k} at {c / F_CPU:.4f} s: {t}")


def speed_law_problems(edges, dirs, a_max, v_max, label):
    """edges: rising STEP cycles; dirs: the DIR level at each. Windows of WINDOW steps within one
    direction; returns (problems, windows checked, largest jump / allowed)."""
    problems, checked, worst = [], 0, 0.0
    runs, cur = [], [edges[0]] if edges else []
    for i in range(1, len(edges)):
        if dirs[i] != dirs[i - 1]:
            runs.append(cur)
            cur = []
        cur.append(edges[i])
    if cur:
        runs.append(cur)
    late = STEP_LATE_CYCLES / F_CPU
    for run in runs:
        wins = []
        for k in range(0, len(run) - WINDOW, WINDOW):
            t = (run[k + WINDOW] - run[k]) / F_CPU
            wins.append((run[k] / F_CPU, t, WINDOW / t))
        for (t0, T1, v1), (_, T2, v2) in zip(wins, wins[1:]):
            checked += 1
            allowed = a_max * (T1 + T2) / 2 * 1.01 + max(v1, v2) * 2 * late / min(T1, T2)
            jump = abs(v2 - v1)
            worst = max(worst, jump / allowed)
            if jump > allowed and len(problems) < 3:
                problems.append(f"{label}: speed {v1:.0f} -> {v2:.0f} steps/s in {(T1 + T2) / 2 * 1e3:.2f} ms at "
                                f"{t0:.4f} s (the law allows {allowed:.0f} at {a_max:.0f} steps/s^2)")
        for t0, T, v in wins:
            if v > v_max * (1 + 2 * late / T) + 1 and len(problems) < 6:
                problems.append(f"{label}: {v:.0f} steps/s at {t0:.4f} s, above vmax {v_max:.0f}")
    return problems, checked, worst


def replan_script(prefix, set_cmd, accel1, accel2, vmax, far, back, key):
    return "\n".join([
        "wait ^READY [^ ]+$", "timeout 60000", f"send set {prefix}vmax {vmax}", "wait ^OK",
        f"send set {prefix}accel {accel1}", "wait ^OK", f"send {far}", "wait ^OK", "run 300",
        f"send set {prefix}accel {accel2}", "wait ^OK", f"send {back}", "wait ^OK", "wait ^DONE",
        "send ?", f"wait ^{key}",
    ]) + "\n"


# (accel before, accel after): the 50,000 -> 200,000 (4x vmax before the fix) and
# -> 1,000 (5,000 -> 95 steps/s), and a low accel raised while moving
REPLAN_CASES = [(50000, 200000), (50000, 1000), (1000, 50000)]


def check_replan_keeps_speed(env, sketch):
    fam = env.family(sketch)
    multi = fam == "multiaxis"
    prefix, step, dirp = ("x ", "XSTEP", "XDIR") if multi else ("", "STEP", "DIR")
    far, back = ("x 100000", "x 0") if multi else ("100000", "0")
    key = "x pos=" if multi else "pos="
    pins = sketches.multiaxis_pins(env) if multi else sketches.stepper_pins(env)
    problems, summary = [], []
    for a1, a2 in REPLAN_CASES:
        log = emulog.run(env.elf(sketch), replan_script(prefix, "set", a1, a2, 5000, far, back, key), pins=pins)
        fails_of(log, problems)
        edges = log.rising(step)
        if len(edges) < 100:
            problems.append(f"accel {a1} -> {a2}: only {len(edges)} steps")
            continue
        dirs = [log.level_before(dirp, c + 1) for c in edges]
        p, n, worst = speed_law_problems(edges, dirs, max(a1, a2), 5000, f"accel {a1} -> {a2}")
        problems += p
        q = log.first("^" + key)
        fields = emulog.query_fields(q.text) if q else {}
        if not q or fields.get("underruns") != "0" or fields.get("late") != "0" or fields.get("pos") != "0":
            problems.append(f"accel {a1} -> {a2}: the `?` after DONE says {q.text if q else None}")
        summary.append(f"{a1}->{a2}: {len(edges)} steps, {n} windows, worst {worst:.2f} of the law")
    return CheckResult(not problems, "set accel while moving, then a target behind: " + "; ".join(summary), problems)


# family: (first line, the two values, regex of an OK to a value (group 1: the value), reply key,
# lines that are no reply: DONE, the servo's status, the filter's stream, the other axes' lines)
FLOOD = {
    "stepper": ("100000", ("-7777", "9999"), r"^OK -?\d+ (-?\d+)( \(after DONE -?\d+\))?$", "pos=",
                r"^(DONE|WARN)"),
    "servo": ("100000", ("-7777", "9999"), r"^OK setpoint=(-?\d+)$", "setpoint=", r"^t_ms="),
    "multiaxis": ("x 100000", ("x -7777", "x 9999"), r"^OK x -?\d+ (-?\d+)( \(after DONE .*\))?$", "x pos=",
                  r"^(DONE|WARN|[yz] pos=)"),
    "filter": ("u 1", ("u 2.5", "u 1.25"), r"^OK u=(-?[\d.]+)$", "kind=", r"^(-?\d|t_ms,)"),
}
FLOOD_REPEATS = 80


def check_flood_accounting(env, sketch):
    fam = env.family(sketch)
    first, (a, b), ok_re, key, not_reply = FLOOD[fam]
    ok_re, not_reply = re.compile(ok_re), re.compile(not_reply)
    sent = 1 + 4 * FLOOD_REPEATS
    script = "\n".join([
        "wait ^READY [^ ]+$", "timeout 60000", "mark flood", f"raw {first}\\r\\n",
        f"repeat {FLOOD_REPEATS} ?\\r\\n{a}\\r\\n?\\r\\n{b}\\r\\n", "drain", "run 6000", "mark flood-end",
        "send ?", "run 1500", "mark end",
    ]) + "\n"
    kw = {}
    if fam == "servo":
        kw["motor"] = sketches.servo_motor_spec(env, sketch)
    elif fam == "filter":
        kw["pins"] = sketches.filter_pins(env)
    log = emulog.run(env.elf(sketch), script, **kw)
    problems = []
    fails_of(log, problems)
    start, end, last = log.mark("flood"), log.mark("flood-end"), log.mark("end")
    if None in (start, end, last):
        return CheckResult(False, "did not run", problems + ["the script did not run"])
    lines = [l.text for l in log.lines_matching(".", start, end) if not not_reply.match(l.text)]
    overruns = [int(m.group(1)) for m in (OVERRUN_RE.match(t) for t in lines) if m]
    states = [t for t in lines if t.startswith(key)]
    oks = [t for t in lines if t.startswith("OK")]
    other = [t for t in lines if not OVERRUN_RE.match(t) and t not in states and t not in oks]
    values = {v.split()[-1] for v in (first, a, b)}
    bad = [t for t in oks if not ok_re.match(t) or ok_re.match(t).group(1) not in values
           and str(float(ok_re.match(t).group(1))) not in {str(float(v)) for v in values}]
    if bad:
        problems.append(f"lines that lost bytes were executed: {bad[:5]}")
    if other:
        problems.append(f"unexpected replies: {other[:5]}")
    if not overruns:
        problems.append("no ERR input overrun although the flood overflowed the input")
    answered = len(states) + len(oks)
    if answered + sum(overruns) != sent:
        problems.append(f"{sent} lines sent, {answered} answered + {sum(overruns)} counted lost by the overrun "
                        f"replies before the next line was sent: want exactly {sent}")
    after = [l.text for l in log.lines_matching(".", end, last) if not not_reply.match(l.text)]
    if len(after) != 1 or not after[0].startswith(key):
        problems.append(f"the `?` after the flood drew {after}, want one state line")
    return CheckResult(not problems, f"{sent} lines at once: {len(states)} `?` answered, {len(oks)} OK, "
                       f"{len(overruns)} overrun replies counting {sum(overruns)} lines; the `?` after answered",
                       problems)


def checks_for(env):
    checks = []
    for s in env.sketch_names():
        try:
            fam = env.family(s)
        except sketches.SketchError:
            continue
        checks.append((f"{s}: {1 + 4 * FLOOD_REPEATS} lines at once: none half-executed, every line answered or "
                       f"counted in an overrun reply", lambda s=s: check_flood_accounting(env, s)))
        if fam == "multiaxis" or (fam == "stepper" and "RAMP_ALGO_EXACT" in open(env.ino(s)).read()):
            checks.append((f"{s}: set accel while moving then a new target keeps the speed (the law of "
                           f"constant acceleration, from the STEP edges)", lambda s=s: check_replan_keeps_speed(env, s)))
        if fam == "stepper" and "RAMP_ALGO_EXACT" in open(env.ino(s)).read():
            checks.append((f"{s}: at the corners of its limits (max_sps, the largest accel): no underrun, every "
                           f"edge within the bound", lambda s=s: check_exact_corners(env, s)))
            checks.append((f"{s}: a stop while stepping slowly (20 steps/s) acts within the lead",
                           lambda s=s: check_slow_stop(env, s)))
        if fam == "multiaxis" or (fam == "stepper" and "RAMP_ALGO_EXACT" in open(env.ino(s)).read()):
            bound = SERIAL_CUT_MS if fam == "multiaxis" else SERIAL_CUT_ALONE_MS
            checks.append((f"{s}: a serial stop or a target behind acts within {bound:g} ms of its line "
                           f"(the queue is cut), the deceleration on the law", lambda s=s: check_serial_cut(env, s)))
        if s == "ExactRampStepper":
            checks.append((f"{s}: {CUT_RACE_TARGETS} new targets whose cut lands as the step interrupt comes (a "
                           f"build with no margin): every cut whole or none, no underrun, no pause",
                           lambda s=s: check_cut_race(env, s)))
        if whole_line_scripts(s):
            checks.append((f"{s}: fuzz replays of lines cut in the output queue ({len(whole_line_scripts(s))} "
                           f"script): every reply a whole line of its own", lambda s=s: check_whole_lines(env, s)))
        if replay_scripts(s):
            checks.append((f"{s}: fuzz replays ({len(replay_scripts(s))} scripts of test/data/fuzz-replays): no "
                           f"underrun" + (", no edge late after its match" if fam == "multiaxis" else ""),
                           lambda s=s: check_fuzz_replays(env, s)))
        # a trapezoid ramp: a Stepper's lab or exact ramp
        if fam == "stepper" and any(w in open(env.ino(s)).read() for w in
                                    ("RAMP_ALGO_LEIB", "RAMP_ALGO_SIMPLISTIC", "RAMP_ALGO_EXACT")):
            checks.append((f"{s}: a long ramp just below max_sps (v0 near vmax, a small accel): the planner keeps "
                           f"up, no underrun", lambda s=s: check_long_ramp_at_limit(env, s)))
        if fam == "multiaxis":
            checks.append((f"{s}: a coordinated start whose first step lies more than half a timer wrap ahead: "
                           f"every first edge on its plan", lambda s=s: check_far_first_step(env, s)))
        if fam == "multiaxis":
            checks.append((f"{s}: a halt of one axis holds no other axis's edge beyond the bound",
                           lambda s=s: check_multiaxis_halt_latency(env, s)))
        if fam == "stepper" and any(w in open(env.ino(s)).read() for w in ("SCurveRamp", "RAMP_ALGO_SIGMOID")):
            checks.append((f"{s}: one line per reply around the table's refills: no line lost or damaged",
                           lambda s=s: check_scurve_one_line_per_reply(env, s)))
    return checks


# SCurveStepper, a host that sends one line per reply (docs/serial.md "Flow control"): the table's
# refill (len 1000: about 0.4 s of arithmetic) no longer stops loop(), and no line is lost or damaged
# around it: a line after a blank line, `set len` at rest and while moving, a retarget storm. Each
# entry: the line, the regex its one reply must match.
SCURVE_LINES = [
    ("set len 1000", r"^OK len=1000$"), ("?", r"^pos=0 .* len=1000 "), ("", None), ("100", r"^OK 0 100$"),
    ("set len 250", r"^OK len=250( \(from the next plan\))?$"), ("?", r"^pos="), ("523", r"^OK -?\d+ 523"),
    ("-38", r"^OK -?\d+ -38"), ("522", r"^OK -?\d+ 522"), ("", None), ("-38", r"^OK -?\d+ -38"),
    ("set hold 5", r"^OK hold=5"), ("0", r"^OK -?\d+ 0"), ("?", r"^pos="), ("set len 1000", r"^OK len=1000"),
]


def check_scurve_one_line_per_reply(env, sketch):
    lines = ["wait ^READY [^ ]+$", "timeout 20000", "mark start"]
    for text, want in SCURVE_LINES:
        lines.append(f"send {text}" if text else "raw \\r\\n")
        if want:
            lines.append("wait ^(OK|ERR|pos=)")
    # the refill to len 1000 runs at the DONE: lines right after it, one per reply, a blank among them
    lines += ["wait ^DONE 0$", "mark refill", "send ?", "wait ^pos=", "raw \\r\\n", "send 60", "wait ^OK", "send ?",
              "wait ^pos=", "wait ^DONE 60$", "send 0", "wait ^OK", "wait ^DONE 0$", "send ?", "wait ^pos=", "mark end"]
    log = emulog.run(env.elf(sketch), "\n".join(lines) + "\n", pins=sketches.stepper_pins(env))
    problems = []
    fails_of(log, problems)
    start, end = log.mark("start"), log.mark("end")
    if start is None or end is None:
        return CheckResult(False, "did not run", problems + ["the script did not run"])
    replies = [l.text for l in log.lines_matching(r"^(OK|ERR|pos=)", start)]
    wants = [w for _, w in SCURVE_LINES if w] + [r"^pos=0 .* len=1000 ", r"^OK 0 60$", r"^pos=",
                                                 r"^OK 60 0$", r"^pos=0 target=0 state=idle .* underruns=0 late=0( |$)"]
    if len(replies) != len(wants):
        problems.append(f"{len(replies)} replies to {len(wants)} lines: {replies}")
    for r, w in zip(replies, wants):
        if not re.search(w, r):
            problems.append(f"reply {r!r}, want /{w}/")
    # the `?` sent as the refill to len 1000 starts: answered while it runs, not after it (about
    # 1000 x 6,500 cycles = 0.41 s): its reply ends within its own transmission time (11 bits a
    # byte in the emulator, 9600 baud) plus the 2 bytes sent and 50 ms
    # the DONE that starts the refill is printed when the last step is made, not after the refill
    # (before: 0.4 s later): within its own transmission time + 50 ms
    done = log.first(r"^DONE 0$", start)
    last_step = max((c for c in log.rising("STEP") if done and c < done.cycle), default=None)
    if done is None or last_step is None:
        problems.append("no DONE 0 after steps")
    else:
        done_late = (done.cycle - last_step) / F_CPU - (len(done.text) + 2) * 11 / 9600
        if done_late > 0.05:
            problems.append(f"DONE 0 came {done_late * 1e3:.0f} ms after the last step and its transmission time: "
                            "loop() stopped for the table refill")
    refill = log.mark("refill")
    q = log.first(r"^pos=", refill) if refill is not None else None
    late_s = None
    if q is not None:
        late_s = (q.cycle - refill) / F_CPU - (len(q.text) + 2 + 2) * 11 / 9600
        if late_s > 0.05:
            problems.append(f"the `?` during the table refill was answered {late_s * 1e3:.0f} ms after its "
                            "transmission time: loop() stopped reading")
    return CheckResult(not problems, f"{len(wants)} lines, one per reply, around table refills: every one answered "
                       f"as sent; DONE 0; underruns=0 late=0; `?` during a refill answered "
                       f"{(late_s or 0) * 1e3:.0f} ms after its transmission time", problems)


# MultiAxisStepper: a halt of one axis (`! y`) while the others step must not hold their edges back
# beyond the single-axis bound (the fuzzer found 494-1,316 cycles at every `!`: the halted axis's 64
# slots were emptied with interrupts off). Oracle: each STEP edge against its channel's compare match.
# The restarts put a move's first, slow steps (the step interrupts' C path) among the other axes'
# steps; where they fall moves with the pauses, so the script runs with three of them (`run 450`,
# 461, 463 ms): the engine of 2026-12-05 held an edge 356 and 328 cycles at the last two (a C path
# that nested above another axis's step, whose own next match was masked meanwhile), 419 at the first
# in another build.
HALT_PAUSES_MS = (450, 461, 463)


def _halt_script(pause_ms=450):
    """three axes to 25,000 steps/s, each halted (`! <axis>`) and restarted four times while the
    others step, then `!`"""
    lines = ["wait ^READY [^ ]+$", "timeout 20000"]
    for ax in "xyz":
        lines += [f"send set {ax} vmax 25000", "wait ^OK", f"send set {ax} accel 90000", "wait ^OK"]
    lines += ["send x 1000000", "wait ^OK", "send y 1000000", "wait ^OK", "send z 1000000", "wait ^OK",
              f"run {pause_ms + 50}"]
    for k in range(4):
        for ax in "yzx":
            lines += [f"send ! {ax}", "wait ^DONE", f"send {ax} {-1000000 if k % 2 == 0 else 1000000}", "wait ^OK",
                      f"run {pause_ms}"]
    return "\n".join(lines + ["send !", "wait ^OK", "run 200"]) + "\n"


HALT_SCRIPT = _halt_script()


def check_multiaxis_halt_latency(env, sketch):
    import bisect
    problems = []
    worst, edges = {"X": 0, "Y": 0, "Z": 0}, 0
    for pause in HALT_PAUSES_MS:
        log = emulog.run(env.elf(sketch), _halt_script(pause), pins=sketches.multiaxis_pins(env), extra=["--matches"])
        fails_of(log, problems)
        for ax, ch in (("X", "OC1A"), ("Y", "OC1B"), ("Z", "OC1C")):
            m = log.matches.get(ch, [])
            w = 0
            for c in log.rising(ax + "STEP"):
                i = bisect.bisect_right(m, c) - 1
                if i >= 0:
                    w = max(w, c - m[i])
                edges += 1
            worst[ax] = max(worst[ax], w)
            if w > STEP_LATE_CYCLES:
                problems.append(f"{ax}: an edge {w} cycles after its compare match (bound {STEP_LATE_CYCLES}), "
                                f"pauses of {pause} ms")
    if edges < 1000 * len(HALT_PAUSES_MS):
        problems.append(f"only {edges} steps")
    return CheckResult(not problems, f"three axes at 25,000 steps/s, each halted and restarted 4 times while the others "
                       f"step, then `!`, with pauses of {', '.join(map(str, HALT_PAUSES_MS))} ms: {edges} edges, the "
                       f"latest after its match: " + ", ".join(f"{k} {v} cycles" for k, v in worst.items()), problems)


# ExactRampStepper at the corners of its own limits (max_sps from `?`, the largest accel and v0 from
# the `set` refusals' "at most N"): moves from rest, a reversal at speed and a retarget, v0 0 and the
# largest v0: no underrun (docs: underruns= stays 0 within the limits), every edge within
# the documented bound of its compare match. Before the accel limit (1e7 then) the fuzzer found
# underruns=40 at accel 6.8e6 near 80,000 steps/s.
def check_exact_corners(env, sketch):
    import bisect
    probe = emulog.run(env.elf(sketch), "wait ^READY [^ ]+$\nsend ?\nwait ^pos=\nsend set accel 1e30\nwait ^ERR\n"
                       "send set v0 1e30\nwait ^ERR\n")
    q = probe.first("^pos=")
    err = probe.first(r"^ERR number out of range: accel at most ")
    err0 = probe.first(r"^ERR number out of range: v0 at most ")
    if q is None or err is None or err0 is None:
        return CheckResult(False, "no limits", [f"`?`, `set accel 1e30`, `set v0 1e30` drew {[l.text for l in probe.rx]}"])
    vmax = float(emulog.query_fields(q.text)["max_sps"])
    amax = float(re.search(r"at most ([\d.e+]+)", err.text).group(1))
    v0max = float(re.search(r"at most ([\d.e+]+)", err0.text).group(1))
    problems, figures = [], []
    algo = emulog.query_fields(q.text).get("algo")
    for v0 in (0.0 if algo == "exact" else 1.0, v0max):  # the simplistic ramp needs v0 > 0
        script = "\n".join(["wait ^READY [^ ]+$", "timeout 30000", f"send set vmax {vmax:g}", "wait ^OK",
                            f"send set accel {amax:g}", "wait ^OK", f"send set v0 {v0:g}", "wait ^OK",
                            "send 40000", "wait ^OK", "wait ^DONE", "send -40000", "wait ^OK", "run 150",
                            "send 20000", "wait ^OK", "run 100", "send -10000", "wait ^OK", "wait ^DONE -10000$",
                            "send ?", "wait ^pos="]) + "\n"
        log = emulog.run(env.elf(sketch), script, pins=sketches.stepper_pins(env), extra=["--matches"])
        fails_of(log, problems)
        f = emulog.query_fields(log.lines_matching("^pos=")[-1].text) if log.lines_matching("^pos=") else {}
        m = log.matches.get("OC1A", [])
        worst = 0
        for c in log.rising("STEP"):
            i = bisect.bisect_right(m, c) - 1
            if i >= 0:
                worst = max(worst, c - m[i])
        if f.get("underruns") != "0" or f.get("pos") != "-10000":
            problems.append(f"v0 {v0:g}: the `?` at the end says {f}")
        if worst > STEP_LATE_CYCLES:
            problems.append(f"v0 {v0:g}: an edge {worst} cycles after its compare match (bound {STEP_LATE_CYCLES})")
        figures.append(f"v0 {v0:g}: {len(log.rising('STEP'))} steps, underruns={f.get('underruns')} "
                       f"late={f.get('late')}, latest edge {worst} cycles after its match")
    return CheckResult(not problems, f"vmax {vmax:g} and accel {amax:g} (the limits): " + "; ".join(figures),
                       problems)


# A trapezoid sketch's planner runs its ramp arithmetic for every step of an acceleration (the lab's
# ramps: the sketch's computeNewSpeed()), so the longest ramp near vmax is its hardest load: v0 a
# little below max_sps (at most the largest v0 `set` accepts), vmax = max_sps and the smallest
# accel that still ramps within the move, 60,000 steps all fast. The limit promises underruns=0
# (docs/serial.md); before the lab ramps' limits were lowered (simplistic 40,000 -> 12,000, Leib
# 10,000 -> 7,000 steps/s) `make fuzz` found such ramps running dry: simplistic v0 15,000 ->
# 18,000 at accel 2,000 gave 10 underruns, stalls of up to 90 ms.
def check_long_ramp_at_limit(env, sketch):
    probe = emulog.run(env.elf(sketch), "wait ^READY [^ ]+$\nsend ?\nwait ^pos=\nsend set v0 1e30\nwait ^ERR\n")
    q = probe.first("^pos=")
    err0 = probe.first(r"^ERR number out of range: v0 at most ")
    if q is None or err0 is None:
        return CheckResult(False, "no limits", [f"`?`, `set v0 1e30` drew {[l.text for l in probe.rx]}"])
    vmax = float(emulog.query_fields(q.text)["max_sps"])
    v0 = min(float(re.search(r"at most ([\d.e+]+)", err0.text).group(1)), vmax * 0.95)
    steps = 60000
    # accel so that the ramp v0 -> vmax takes about the whole move: (vmax^2 - v0^2) / (2 a) = steps
    accel = max(10.0, (vmax * vmax - v0 * v0) / (2.0 * steps))
    script = "\n".join(["wait ^READY [^ ]+$", "timeout 60000", f"send set vmax {vmax:g}", "wait ^OK",
                        f"send set v0 {v0:g}", "wait ^OK", f"send set accel {accel:.0f}", "wait ^OK",
                        f"send {steps}", "wait ^OK", f"wait ^DONE {steps}$", "send ?", "wait ^pos="]) + "\n"
    log = emulog.run(env.elf(sketch), script, pins=sketches.stepper_pins(env))
    problems = []
    fails_of(log, problems)
    f = emulog.query_fields(log.lines_matching("^pos=")[-1].text) if log.lines_matching("^pos=") else {}
    edges = len(log.rising("STEP"))
    if f.get("underruns") != "0":
        problems.append(f"the `?` after the move says underruns={f.get('underruns')}")
    if edges != steps:
        problems.append(f"{edges} STEP edges, want {steps}")
    return CheckResult(not problems, f"v0 {v0:g} -> vmax {vmax:g} at accel {accel:.0f}: {edges} steps, "
                       f"underruns={f.get('underruns')}", problems)


# A stop while stepping slowly acts within the lead (docs/stepper-engine.md: STEP_ENGINE_LEAD_MS, at
# least two commands): at 16 MHz a step of 20 steps/s is 800,000 ticks, beyond the 65,535 a slot's
# duration holds; counted as 65,535 they filled the whole ring (96 steps, nearly 5 s of them) before
# the lead looked reached, and a `stop` acted that late (make fuzz, seed 23, found its trace). The
# steps after the `stop` line: those queued (at most the lead or two commands, three at 20 steps/s)
# plus the deceleration's v^2/2a, each rounded up.
SLOW_VMAX, SLOW_ACCEL = 20.0, 100.0


def check_slow_stop(env, sketch):
    script = "\n".join(["wait ^READY [^ ]+$", "timeout 20000", f"send set vmax {SLOW_VMAX:g}", "wait ^OK",
                        f"send set accel {SLOW_ACCEL:g}", "wait ^OK", "send 100000", "wait ^OK", "run 3000",
                        "mark stop", "send stop", "wait ^OK stop", "wait ^DONE", "send ?", "wait ^pos="]) + "\n"
    log = emulog.run(env.elf(sketch), script, pins=sketches.stepper_pins(env))
    problems = []
    fails_of(log, problems)
    m = log.mark("stop")
    done = log.first("^DONE ")
    if m is None or done is None:
        return CheckResult(False, "no stop", problems + [f"lines {[l.text for l in log.rx][-6:]}"])
    after = len([c for c in log.rising("STEP") if c > m])
    lead_steps = max(2, math.ceil(SLOW_VMAX * 0.1)) + 1
    bound = lead_steps + math.ceil(SLOW_VMAX * SLOW_VMAX / (2 * SLOW_ACCEL)) + 2
    if after > bound:
        problems.append(f"{after} steps after the `stop` line at {SLOW_VMAX:g} steps/s, accel {SLOW_ACCEL:g}: "
                        f"more than the lead and the deceleration allow ({bound})")
    return CheckResult(not problems, f"a stop at {SLOW_VMAX:g} steps/s (accel {SLOW_ACCEL:g}): {after} steps after "
                       f"the line (at most {bound}), {done.text}", problems)


# A coordinated move starts 4096 ticks ahead; the axis that moves least has its first step one of its
# intervals later, here 31,300 ticks: its first compare lies more than 32,768 ticks ahead, which in
# 16-bit times looks like the past. The engine's watch for missed matches took it for one and fired
# the step at once (`make fuzz`, seed 22: x stepped twice 201 cycles apart, its first step 32,580
# cycles early). The plan: `motionsim move` of the same move (lib's step_coord, the same commands).
FAR_FIRST = {"x": -13915, "y": -32618}
FAR_FIRST_LIMITS = {"x": (5895, 23567, 200000), "y": (1128, 1225, 90000)}


def check_far_first_step(env, sketch):
    import subprocess
    lines = ["wait ^READY [^ ]+$", "timeout 20000"]
    args = [env.motionsim, "move", "--max-rows", "100000", "-o", "-"]
    for ax, (v0, vmax, acc) in FAR_FIRST_LIMITS.items():
        lines += [f"send set {ax} v0 {v0}", "wait ^OK", f"send set {ax} vmax {vmax}", "wait ^OK",
                  f"send set {ax} accel {acc}", "wait ^OK"]
        args += [f"--{ax}", str(FAR_FIRST[ax]), f"--{ax}-v0", str(v0), f"--{ax}-vmax", str(vmax),
                 f"--{ax}-accel", str(acc)]
    lines += ["send move " + " ".join(f"{ax}{d}" for ax, d in FAR_FIRST.items()), "wait ^OK move", "run 60",
              "send !", "wait ^OK halt"]
    log = emulog.run(env.elf(sketch), "\n".join(lines) + "\n", pins=sketches.multiaxis_pins(env))
    problems = []
    fails_of(log, problems)
    r = subprocess.run(args, capture_output=True, text=True, timeout=120)
    plan = {"x": [], "y": []}
    for row in r.stdout.splitlines()[1:]:
        w = row.split(",")
        if w[1] in plan and len(plan[w[1]]) < 12:
            plan[w[1]].append(round(float(w[0]) * F_CPU))
    got = {ax: log.rising(ax.upper() + "STEP")[:12] for ax in plan}
    if r.returncode != 0 or any(len(plan[ax]) < 12 or len(got[ax]) < 12 for ax in plan):
        return CheckResult(False, "no edges", [f"motionsim exit {r.returncode}: {r.stderr.strip()[:200]}; edges "
                                               f"{ {ax: len(v) for ax, v in got.items()} }"])
    t0 = got["y"][0] - plan["y"][0]  # the plan's t = 0 on the board's timeline, from y's first edge
    worst = 0
    for ax in plan:
        for k, (p, g) in enumerate(zip(plan[ax], got[ax])):
            off = g - t0 - p
            worst = max(worst, abs(off))
            # on its planned tick, or after it by no more than the pin bound (an edge may wait for the
            # core's serial and millis interrupts, docs/serial.md); never early
            if (off < -8 or off > STEP_LATE_CYCLES) and len(problems) < 4:
                problems.append(f"{ax} step {k + 1}: {off:+d} cycles off its plan")
    return CheckResult(not problems, f"x's first step {plan['x'][0]} ticks after the start (more than 32,768 with "
                       f"the start's 4096): the first 12 edges of x and y within {worst} cycles of the plan (never early, at most {STEP_LATE_CYCLES} late)", problems)


# A `stop` or a target behind, on a sketch whose ramp is exact, acts within milliseconds of its line
# (issue 23: "stop and retarget within milliseconds ... of the call (the serial line)"): the console
# cuts the step queue a few milliseconds ahead (StepCut.h) instead of letting the lead (100 ms of
# steps) run out. From the cruise at vmax: the steps after the line's last byte are the cruise up
# to the deceleration and the deceleration's v^2/2a, whose edges follow t(n) = T - sqrt(2 (N - n)/a)
# (no velocity jump: every edge within the late bound of the law). Before the cut, 100 ms of cruise
# came first (2,000 steps at 20,000 steps/s). The bound: 5 ms ahead (6 ms for a target) plus one
# command of the planner (4 ms), plus a step (docs/serial.md "Stop and new targets"): MultiAxisStepper,
# whose three Steppers plan a stop at the cut. A Stepper alone (ExactRampStepper) has its stop from the
# cruise planned ahead (Stepper::prepare_stop) and cuts 450 us ahead and more with the speed: 2 ms, the
# issue's bound, at three moments (until 2026-12-06 it took the 5 ms cut: 5.60 ms, a target behind 10.53 ms).
SERIAL_CUT_MS = 11.0
SERIAL_CUT_ALONE_MS = 2.0
SERIAL_CUT_ALONE_MOMENTS = (0.0, 0.35, 0.7)  # ms added to the 700 ms of cruise before each line


def _decel_check(rises, end, done_cycle, v, a, what, problems):
    """the edges after a line's end up to its move's end: cruise at v, then the deceleration's v^2/2a
    steps on the law; returns the ms from the line's end to the deceleration's start"""
    after = [c for c in rises if end < c <= done_cycle]
    n_dec = int(round(v * v / (2 * a)))
    if len(after) < n_dec + 2:
        problems.append(f"{what}: {len(after)} steps after the line, fewer than the deceleration's {n_dec}")
        return None
    start = after[-n_dec - 1]
    worst = 0.0
    for n, c in enumerate(after[-n_dec:], start=1):
        t = (v / a - math.sqrt(2 * (n_dec - n) / a)) * F_CPU
        worst = max(worst, abs((c - start) - t))
    if worst > STEP_LATE_CYCLES + 2 + F_CPU / v:
        problems.append(f"{what}: a deceleration edge {worst:.0f} cycles off the law from v = {v:g} at a = {a:g}")
    cruise = [q - p for p, q in zip(after, after[1:len(after) - n_dec])]
    if cruise and max(abs(c - F_CPU / v) for c in cruise) > STEP_LATE_CYCLES + 2:
        problems.append(f"{what}: intervals {min(cruise)}..{max(cruise)} before the deceleration, not the "
                        f"cruise's {F_CPU / v:.0f}")
    return (start - end) * 1000.0 / F_CPU


def check_serial_cut(env, sketch):
    multi = env.family(sketch) == "multiaxis"
    problems, figures = [], []
    for off in ((0.0,) if multi else SERIAL_CUT_ALONE_MOMENTS):
        serial_cut_run(env, sketch, multi, off, problems, figures)
    return CheckResult(not problems, "at 20000 steps/s, accel 50000: " + "; ".join(figures), problems)


def serial_cut_run(env, sketch, multi, off, problems, figures):
    ax = "x " if multi else ""
    v, a = 20000.0, 50000.0
    setv = [f"send set {ax}vmax {v:g}", "wait ^OK", f"send set {ax}accel {a:g}", "wait ^OK"]
    script = ["wait ^READY [^ ]+$", "timeout 20000"] + setv + [
        f"send {ax}1000000", "wait ^OK", f"run {700 + off:g}", "mark stop", f"send {'stop x' if multi else 'stop'}",
        "wait ^OK stop", "wait ^DONE", f"send {ax}1000000", "wait ^OK", f"run {700 + off:g}", "mark back",
        f"send {ax}0", "wait ^OK", "wait ^DONE", "send ?", "wait ^(x )?pos="]
    pins = sketches.multiaxis_pins(env) if multi else sketches.stepper_pins(env)
    log = emulog.run(env.elf(sketch), "\n".join(script) + "\n", pins=pins)
    fails_of(log, problems)
    step = "XSTEP" if multi else "STEP"
    rises = log.rising(step)
    uart = [r for c, t, r in log.events if t == "uart"]
    byte = int(re.search(r"cycles_per_byte=(\d+)", uart[0]).group(1)) if uart else 16640
    bound = SERIAL_CUT_MS if multi else SERIAL_CUT_ALONE_MS
    for mark, line, bound in (("stop", "stop x" if multi else "stop", bound),
                              ("back", f"{ax}0", bound + 1.0 if multi else bound)):
        m = log.mark(mark)
        if m is None:
            problems.append(f"no '{mark}' in the run: lines {[l.text for l in log.rx][-6:]}")
            continue
        sent = next((t.cycle for t in log.tx if t.cycle >= m and t.text == line), m)
        end = sent + byte * (len(line) + 2)  # the line's last byte (CR LF included)
        if mark == "stop":
            d = log.first("^DONE ", after=m)
            done = d.cycle if d else max(rises)
            ms = _decel_check(rises, end, done, v, a, "stop from the cruise", problems)
        else:
            # the target behind: the deceleration to the reversal point is the stop's, then the way back
            ups = [c for c in rises if c > end and log.level_before("XDIR" if multi else "DIR", c)]
            ms = _decel_check(rises, end, ups[-1] if ups else end, v, a, f"target 0 behind", problems)
        if ms is not None:
            figures.append(f"{mark} (+{off:g} ms): deceleration {ms:.2f} ms after the line")
            if ms > bound:
                problems.append(f"{mark} (+{off:g} ms): the deceleration began {ms:.2f} ms after the line's end "
                                f"(bound {bound:g} ms)")
    q = log.lines_matching("^(x )?pos=")
    f = emulog.query_fields(q[-1].text) if q else {}
    if f.get("pos") != "0" or f.get("underruns") != "0":
        problems.append(f"the `?` at the end says {f}")


# A cut laid out as the step interrupt reaches it (make fuzz seed 23 at the 80,000 limit: a target
# behind at 7,300 steps/s was followed by a step 8.1 ms late, an underrun). The cut's margin alone
# kept the interrupt away: laying the new commands out in place took up to 4,000 cycles after the
# margin was checked, and an interrupt that came meanwhile found the first new slot not ready.
# Here a build whose cut lands 1.5 ms ahead with no margin (tools/emu/emu.mk, EMU_CUTRACE_ELF)
# takes 300 new targets ahead while cruising, each a little nearer than the last (a target beyond the
# plan's needs no cut: Stepper::beyond_plan), sent at random moments: many of its cuts are laid out
# just as the interrupt comes. Every cut must come off whole or not at all: no underrun, no pause.
# With the cut laid out in place (before 2026-12-04) the same runs counted 12, 6 and 2 underruns
# (and 12, 9 and 2 pauses). First, one target beyond the plan's: no cut for it.
CUT_RACE_CASES = ((20000, 50000, 1), (50000, 200000, 2), (8000, 20000, 3))
CUT_RACE_TARGETS = 300


def cut_race_script(vmax, accel, seed):
    import random
    rnd = random.Random(seed)
    lines = ["wait ^READY [^ ]+$", "timeout 20000", f"send set vmax {vmax}", "wait ^OK", f"send set accel {accel}",
             "wait ^OK", "send 2000000000", "wait ^OK", "run 1500", "send 2000000500", "wait ^OK", "run 100"]
    for i in range(CUT_RACE_TARGETS):
        lines += [f"send {1000000 - 7 * i}", "wait ^(OK|ERR)",
                  f"run {rnd.choice([0, 1, 2, 3, 4, 5, 7, 9, 11])}.{rnd.randint(0, 999):03d}"]
    return "\n".join(lines + ["send ?", "wait ^pos="]) + "\n"


def check_cut_race(env, sketch):
    elf = os.path.join(env.source_dir, "build", "emu", "cutrace", sketch, sketch + ".ino.elf")
    if not os.path.isfile(elf):
        return CheckResult(False, "no cut-race build", [f"{elf} is missing: make test builds it (tools/emu/emu.mk)"])
    problems, figures = [], []
    for vmax, accel, seed in CUT_RACE_CASES:
        log = emulog.run(elf, cut_race_script(vmax, accel, seed), pins=sketches.stepper_pins(env))
        fails_of(log, problems)
        rises = log.rising("STEP")
        oks = log.lines_matching(r"^OK \d+ (99\d{4}|1000000)$")
        cuts = 0
        for ok in oks:
            # a cut: the new plan starts within 20 ms of steps of where the axis was at the reply
            pos = sum(1 for c in rises if c <= ok.cycle)
            if int(ok.text.split()[1]) - pos < vmax * 0.020:
                cuts += 1
        # the target beyond the plan's (2000000500 while cruising to 2000000000): planned after the queued
        # steps, with no cut (Stepper::beyond_plan): its OK starts the new plan more than 20 ms ahead
        beyond = log.lines_matching(r"^OK \d+ 2000000500$")
        if not beyond:
            problems.append(f"vmax {vmax}: no OK for the target beyond the plan's")
        elif int(beyond[0].text.split()[1]) - sum(1 for c in rises if c <= beyond[0].cycle) < vmax * 0.020:
            problems.append(f"vmax {vmax}: the target beyond the plan's cut the queue ({beyond[0].text})")
        cruise = F_CPU / vmax
        gaps = [(b, b - a) for a, b in zip(rises, rises[1:]) if a > rises[0] + F_CPU and b - a > 2.5 * cruise]
        q = log.lines_matching("^pos=")
        f = emulog.query_fields(q[-1].text) if q else {}
        tag = f"vmax {vmax}, accel {accel}"
        if len(oks) != CUT_RACE_TARGETS:
            problems.append(f"{tag}: {len(oks)} of {CUT_RACE_TARGETS} targets answered OK")
        if cuts < CUT_RACE_TARGETS // 3:
            problems.append(f"{tag}: only {cuts} targets cut the queue (the check needs many cuts)")
        # (late edges, a few microseconds each, are reported, not failed: with no margin the switch may
        # come just as the interrupt looks for the next slot, which then takes the slower C path)
        if f.get("underruns") != "0":
            problems.append(f"{tag}: the `?` at the end says underruns={f.get('underruns')}")
        if gaps:
            problems.append(f"{tag}: {len(gaps)} pauses in the cruise, the first {gaps[0][1]} cycles at cycle {gaps[0][0]}")
        figures.append(f"{tag}: {cuts} of {len(oks)} targets cut the queue, {len(rises)} steps, "
                       f"underruns={f.get('underruns')}, late={f.get('late')}, {len(gaps)} pauses")
    return CheckResult(not problems, "; ".join(figures), problems)


# Fuzz replays (test/data/fuzz-replays/README.md): the scripts of `make fuzz` runs that found a bug,
# replayed on the sketch they were written for: the run must end normally and every `?` must say
# underruns=0 (each failed so on the firmware before its fix); on MultiAxisStepper, as the fuzzer
# requires too, every STEP edge comes at most STEP_LATE_CYCLES after a compare match (its own
# channel's, or another's for an axis that follows it on a diagonal).
REPLAY_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "fuzz-replays")
def late_edge_problems(env, log, name):
    """the STEP edges of every axis more than the fuzzer's bound after a compare match (its own
    oracle and pin/channel table, tools/fuzz)"""
    path = os.path.join(env.source_dir, "tools", "fuzz")
    if path not in sys.path:
        sys.path.insert(0, path)
    import fuzz_conversation as fc
    import fuzz_oracles as fo
    every = sorted(c for v in log.matches.values() for c in v)
    out = []
    for ax in "xyz":
        step, _, ch = fc.PINS[ax]
        _, bad = fo.planned_cycles(log.rising(step), log.matches.get(ch, []), every)
        out += [f"{name}: {ax} edge late: {b}" for b in bad]
    return out


def replay_scripts(sketch):
    if not os.path.isdir(REPLAY_DIR):
        return []
    return sorted(f for f in os.listdir(REPLAY_DIR) if f.startswith(sketch + "-") and f.endswith(".emu"))


def check_fuzz_replays(env, sketch):
    problems, figures = [], []
    for name in replay_scripts(sketch):
        text = open(os.path.join(REPLAY_DIR, name)).read()
        script = "".join(l for l in text.splitlines(True) if not l.startswith("#"))
        multi = env.family(sketch) == "multiaxis"
        log = emulog.run(env.elf(sketch), script,
                         pins=sketches.multiaxis_pins(env) if multi else sketches.stepper_pins(env),
                         extra=["--matches"] if multi else None)
        fails_of(log, problems)
        if multi:
            problems += late_edge_problems(env, log, name)
        qs = log.lines_matching(r"(^|\s)underruns=")
        # a replay from the three-axis overload (docs/multi-axis.md, Known limit) has that limit's
        # underruns: it is held to the edges' oracle alone (test/data/fuzz-replays/README.md)
        bad = [] if "-overload-" in name else [l.text for l in qs if not re.search(r"underruns=0\b", l.text)]
        if not qs:
            problems.append(f"{name}: no `?` reply")
        if bad:
            problems.append(f"{name}: {len(bad)} `?` replies with underruns: {bad[0][:160]}")
        figures.append(f"{name}: {len(qs)} `?` replies, {len(log.rising('XSTEP' if multi else 'STEP'))} x steps")
    return CheckResult(not problems, "; ".join(figures), problems)


# Replies whole (test/data/fuzz-replays/README.md, files whole-lines-<Sketch>-*.emu): a DONE produced while
# the output queue is nearly full waits for room instead of losing its end. The script must run to
# its end (each `wait` met: a reply glued to a cut line matches none) and every line the sketch sent
# must be a whole reply of the protocol (docs/multi-axis.md).
REPLY_LINE = re.compile(r"^(READY \S+|OK( .*)?|ERR .+|DONE( move)?( [xyz] -?\d+)+|[xyz] pos=-?\d+ target=-?\d+ state=\w+ .*"
                        r" underruns=\d+ late=\d+)$")


def whole_line_scripts(sketch):
    if not os.path.isdir(REPLAY_DIR):
        return []
    return sorted(f for f in os.listdir(REPLAY_DIR) if f.startswith("whole-lines-" + sketch + "-") and f.endswith(".emu"))


def check_whole_lines(env, sketch):
    problems, figures = [], []
    for name in whole_line_scripts(sketch):
        text = open(os.path.join(REPLAY_DIR, name)).read()
        script = "".join(l for l in text.splitlines(True) if not l.startswith("#"))
        log = emulog.run(env.elf(sketch), script, pins=sketches.multiaxis_pins(env))
        fails_of(log, problems)
        lines = [l.text for l in log.lines_matching(r".")]
        bad = [t for t in lines if not REPLY_LINE.match(t)]
        if bad:
            problems.append(f"{name}: {len(bad)} lines that are no whole reply, e.g. {bad[0][:120]!r}")
        dones = [t for t in lines if t.startswith("DONE")]
        if not any(t.startswith("OK halt") for t in lines):
            problems.append(f"{name}: the `!` drew no `OK halt` line of its own")
        figures.append(f"{name}: {len(lines)} lines, {len(bad)} not whole; {len(dones)} DONE lines, the last {dones[-1] if dones else None!r}")
    return CheckResult(not problems, "; ".join(figures), problems)
