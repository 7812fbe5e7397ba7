"""The sketch checks of the emulator suite: each sketch under firmware/ runs on the emulated
ATmega2560 and is compared with motionsim and with its documented behaviour.

Expectations come from outside the firmware under test: motionsim (the host build of the same
lib/ code, with its own timing model), the ATmega2560 datasheet (timer and UART arithmetic), and
the sketches' documented protocol (READY/OK/ERR/?). Nothing is compared with a recording of the
firmware itself.
"""
import bisect
import os
import sys
import re
import subprocess
import tempfile

import emulate
import emulog
import sketches
from checks_selftest import CheckResult
from emulog import F_CPU

# ----------------------------------------------------------------------------------------------
# helpers


def motionsim(env, *args):
    p = subprocess.run([env.motionsim, *args], capture_output=True, text=True, timeout=120)
    if p.returncode != 0:
        raise RuntimeError(f"motionsim {' '.join(args)} failed ({p.returncode}): {p.stderr.strip()}")
    return p.stdout, p.stderr


def fails_of(log, problems):
    for c, k, t in log.fails:
        problems.append(f"harness: {k} at {c / F_CPU:.4f} s: {t}")
    if log.rc not in (0, 1):
        problems.append(f"motionemu exit status {log.rc}: {log.stderr.strip()[-500:]}")


def query_reply(log, key, after=0, before=None):
    """The `?` reply (a line starting with `key=`) after a cycle, as a dict."""
    line = log.first(r"^" + re.escape(key) + "=", after, before)
    return (emulog.query_fields(line.text), line) if line else (None, None)


# ----------------------------------------------------------------------------------------------
# bad input, common to every sketch (check 4 of the issue)

def bad_input_script(sketch, key, ready_extra, bad_lines, while_busy=None):
    """A script that sends each bad input and waits for its ERR, with `?` before and after.
    bad_lines: (label, script command) pairs; each must draw exactly one ERR line.
    while_busy: (start command, its OK regex, busy bad commands, end regex) for 'while moving'."""
    s = ["wait ^READY [^ ]+$", ready_extra, "timeout 3000", "send ?", f"wait ^{key}=", "mark bad-start"]
    for label, cmd, *after in bad_lines:
        s += [f"mark bad {label}", cmd, "wait ^ERR "] + list(after)
    s += ["mark bad-end", "send ?", f"wait ^{key}="]
    if while_busy:
        start, ok_re, busy_cmds, end_re, end_timeout = while_busy
        s += ["mark busy-start", start, f"wait {ok_re}", "send ?", f"wait ^{key}="]
        for label, cmd in busy_cmds:
            s += [f"mark busy {label}", cmd, "wait ^ERR "]
        s += ["send ?", f"wait ^{key}=", "mark busy-end", f"timeout {end_timeout}", f"wait {end_re}", "timeout 3000",
              "send ?", f"wait ^{key}="]
    return "\n".join(x for x in s if x) + "\n"


# the inputs every sketch must refuse (labels are shown in failures)
COMMON_BAD = [
    ("junk", "send hello world"),
    ("binary", "raw \\x01\\x02\\xfe\\xff\\x80\\r\\n"),
    # ERR as soon as the line is too long; its end (sent after the ERR) draws no second ERR
    ("1 KB line without newline", "repeat 1024 x", "raw \\r\\n"),
]


def check_bad_input(env, sketch, key, ready_extra, bad_lines, while_busy=None, dynamic=(), pins=None, motor=None,
                    step_total=None):
    """Every bad line gets exactly one ERR, no reset or crash, `?` is the same before and after:
    every key while idle; while busy, the keys in `dynamic` change by themselves and are left out.
    step_total: the STEP rising edges the whole run must have (the busy move's steps: no stray
    pulse during bad input or after DONE)."""
    script = bad_input_script(sketch, key, ready_extra, bad_lines, while_busy)
    log = emulog.run(env.elf(sketch), script, pins=pins, motor=motor)
    problems = []
    fails_of(log, problems)
    start, end = log.mark("bad-start"), log.mark("bad-end")
    n_bad = len(bad_lines)
    errs = []
    if start is not None and end is not None:
        errs = log.lines_matching(r"^ERR ", start, end)
        marks = [m for m in log.marks if m.text.startswith("bad ")]
        for i, m in enumerate(marks):
            nxt = marks[i + 1].cycle if i + 1 < len(marks) else end
            got = log.lines_matching(r"^ERR ", m.cycle, nxt)
            if len(got) != 1:
                problems.append(f"'{m.text[4:]}' drew {len(got)} ERR lines (want exactly 1): {[g.text for g in got]}")
        oks = log.lines_matching(r"^OK", start, end)
        if oks:
            problems.append(f"bad input was accepted: {[o.text for o in oks]}")
        before, _ = query_reply(log, key, 0, start)
        after, _ = query_reply(log, key, end)
        if before is None or after is None:
            problems.append("no `?` reply before/after the bad input")
        else:
            if after != before:
                problems.append(f"state changed by bad input: before {before}, after {after}")
    elif not problems:
        problems.append("the bad-input section did not run")
    busy_note = ""
    if while_busy and not problems:
        bs, be = log.mark("busy-start"), log.mark("busy-end")
        marks = [m for m in log.marks if m.text.startswith("busy ")]
        for i, m in enumerate(marks):
            nxt = marks[i + 1].cycle if i + 1 < len(marks) else be
            got = log.lines_matching(r"^ERR ", m.cycle, nxt)
            if len(got) != 1:
                problems.append(f"'{m.text[5:]}' while busy drew {len(got)} ERR lines: {[g.text for g in got]}")
        b1, _ = query_reply(log, key, bs)
        b2, _ = query_reply(log, key, marks[-1].cycle if marks else bs)
        if b1 and b2:
            b = {k: v for k, v in b1.items() if k not in dynamic}
            a = {k: v for k, v in b2.items() if k not in dynamic}
            if a != b:
                problems.append(f"state changed by bad input while busy: before {b}, after {a}")
        busy_note = f"; {len(marks)} refused while busy"
        errs = errs + log.lines_matching(r"^ERR ", bs, be)
    step_note = ""
    if step_total is not None:
        n_steps = len(log.rising("STEP"))
        step_note = f"; {n_steps} STEP pulses in the whole run (the move's {step_total})"
        if n_steps != step_total:
            problems.append(f"{n_steps} STEP rising edges in the whole run, want exactly the busy move's {step_total} "
                            f"(a stray pulse during bad input or after DONE)")
    resets = [k for _, k, _ in log.fails if k in ("reset", "crash", "halt", "stack")]
    verdict = "no reset/crash, `?` unchanged" if not problems else (
        f"FAILED ({', '.join(sorted(set(resets))) or 'see above'})")
    summary = (f"{n_bad} bad inputs -> {len(log.lines_matching('^ERR ', start or 0, end))} ERR{busy_note}{step_note}, "
               f"{verdict}; e.g. '{errs[0].text if errs else '-'}'")
    res = CheckResult(not problems, summary, problems)
    res.log = log
    return res


# ----------------------------------------------------------------------------------------------
# MovingAverageFilter (check 2)

FILTER_SCRIPT = """\
# 60 emulated seconds: A0 input at 1.234 V, a 5 V constant step, back to 0 V, then A0 at 3.3 V
adc {ch} 1.234
wait ^READY [^ ]+$
send ?
wait ^kind=
@10000 u 5
wait ^OK u=5.000$
@30000 u 0
wait ^OK u=0.000$
@45000 a0
adc {ch} 3.3
wait ^OK input=a0$
until 60050
send ?
wait ^kind=
"""
STREAM_RE = re.compile(r"^(\d+),(\d+\.\d{3}),(-?\d+\.\d{6})$")
TIMER1_TICK = 256        # cycles: Timer1 at clk/256 (FilterPins.h)
SAMPLE_CYCLES = 160000   # 10 ms


def strobe_edges(log):
    return [c for c, _ in log.pins.get("STROBE", [])]


def check_filter(env, sketch):
    ch = sketches.filter_adc_channel(env)
    log = emulog.run(env.elf(sketch), FILTER_SCRIPT.format(ch=ch), pins=sketches.filter_pins(env))
    problems = []
    fails_of(log, problems)
    rows = []
    for l in log.rx:
        m = STREAM_RE.match(l.text)
        if m:
            rows.append((int(m.group(1)), m.group(2), m.group(3), l.cycle))
    if len(rows) < 5900:
        problems.append(f"only {len(rows)} stream lines in 60 s (100 Hz expected)")
        return CheckResult(False, f"{len(rows)} samples", problems)
    gaps = [(a[0], b[0]) for a, b in zip(rows, rows[1:]) if b[0] - a[0] != 10]
    if rows[0][0] != 0 or gaps:
        problems.append(f"stream not every 10 ms from t_ms=0: first {rows[0][0]}, gaps {gaps[:5]}")
    # 1. the stream equals motionsim filter fed with the same input sequence
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write("t_ms,u,y\n")
        for t, u, y, _ in rows:
            f.write(f"{t},{u},{y}\n")
        path = f.name
    try:
        out, _ = motionsim(env, "filter", "--kind", "ma", "--tau", "9", "--ts", "0.01", "--input", f"csv:{path}",
                           "--stream")
    finally:
        os.unlink(path)
    sim = [l for l in out.splitlines()[1:] if l]
    mism = [(r[0], f"{r[0]},{r[1]},{r[2]}", s) for r, s in zip(rows, sim) if f"{r[0]},{r[1]},{r[2]}" != s]
    if len(sim) < len(rows):
        problems.append(f"motionsim gave {len(sim)} rows for {len(rows)} samples")
    if mism:
        problems.append(f"{len(mism)} of {len(rows)} stream lines differ from motionsim, first: firmware "
                        f"'{mism[0][1]}' motionsim '{mism[0][2]}'")
    # 2. the input it used: constants exactly, A0 within one ADC step (5 V / 1024 = 4.9 mV)
    by_t = {t: (float(u), float(y)) for t, u, y, _ in rows}
    okc = {l.text: l.cycle for l in log.lines_matching(r"^OK ")}
    # (the sample clock starts with READY, a few ms after power-on: keep 100 ms off the switches)
    for label, volts, t_lo, t_hi in (("A0 1.234 V", 1.234, 0, 9900), ("u 5", 5.0, 10100, 29900),
                                     ("u 0", 0.0, 30100, 44900), ("A0 3.3 V", 3.3, 45100, 59990)):
        us = [by_t[t][0] for t in range(t_lo, t_hi + 1, 10) if t in by_t]
        tol = 0.0049 if label.startswith("A0") else 0.0
        bad = [u for u in us if abs(u - volts) > tol + 1e-9]
        if not us or bad:
            problems.append(f"{label}: input u off by more than {tol * 1000:.1f} mV in {len(bad)} samples "
                            f"(e.g. {bad[:3]})")
    # the step reaches 5 V exactly tau = 9 s (900 samples) after its first sample (the moving-average-filter note)
    first5 = next((t for t, u, y, _ in rows if u == "5.000"), None)
    if first5 is not None:
        y_end = by_t.get(first5 + 9000, (None, None))[1]
        if y_end is None or abs(y_end - 5.0) > 1e-6:
            problems.append(f"y should reach 5 V 9 s after the step (t_ms={first5 + 9000}), got {y_end}")
        # the new input acts from the first sample after the command was answered
        k5 = first5 // 10
        if "OK u=5.000" in okc and len(strobe_edges(log)) > k5:
            lag = strobe_edges(log)[k5] - okc["OK u=5.000"]
            if not (0 < lag <= 2 * SAMPLE_CYCLES):
                problems.append(f"u 5 took effect {lag / F_CPU * 1000:.1f} ms after its OK (want within 2 samples)")
    # 3. the sample clock on the strobe pin: every 10 ms +/- one Timer1 tick, no drift
    strobe = strobe_edges(log)
    iv = [b - a for a, b in zip(strobe, strobe[1:])]
    jitter = max((abs(i - SAMPLE_CYCLES) for i in iv), default=None)
    drift = max((abs((c - strobe[0]) - k * SAMPLE_CYCLES) for k, c in enumerate(strobe)), default=None)
    if len(strobe) < len(rows):
        problems.append(f"{len(strobe)} strobe edges for {len(rows)} samples")
    elif jitter > TIMER1_TICK:
        problems.append(f"sample interval off 160000 cycles by up to {jitter} (> one Timer1 tick = {TIMER1_TICK})")
    elif drift > TIMER1_TICK:
        problems.append(f"sample clock drifts: edge k is up to {drift} cycles from edge 0 + k * 10 ms")
    # 4. the PWM output: duty * 5 V = y (1 mV steps, OCR4A = y in mV from the tick after the sample)
    top = sketches.filter_pwm_top(env)
    pwm = log.pins.get("PWM", [])
    pwm_c = [c for c, _ in pwm]
    worst_mv, checked, worst_at = 0.0, 0, None
    for k in range(1, min(len(rows), len(strobe) - 1)):
        t, u, y, _ = rows[k]
        a, b = strobe[k] + 4 * top, strobe[k + 1]   # skip the period in which OCR4A is latched
        i = bisect.bisect_left(pwm_c, a)
        # the last complete period (rise .. rise) before b, or a constant level
        rises = [c for c, lv in pwm[i:bisect.bisect_left(pwm_c, b)] if lv]
        falls = [c for c, lv in pwm[i:bisect.bisect_left(pwm_c, b)] if not lv]
        if len(rises) >= 2:
            r0, r1 = rises[-2], rises[-1]
            f = [x for x in falls if r0 < x < r1]
            if not f:
                continue
            mv = (f[0] - r0) / (r1 - r0) * 5000.0
        else:
            lvl = log.level_before("PWM", b)
            mv = 5000.0 if lvl else 0.0
        want = round(float(y) * 1000.0)
        if abs(mv - want) > worst_mv:
            worst_mv, worst_at = abs(mv - want), (t, y, mv)
        checked += 1
    if checked < len(rows) - 10:
        problems.append(f"PWM checked in only {checked} of {len(rows)} samples")
    if worst_mv > 1.0:
        problems.append(f"PWM duty * 5 V differs from y by up to {worst_mv:.2f} mV (one PWM step is 1 mV): at t_ms, y, "
                        f"PWM mV = {worst_at}")
    q, _ = query_reply(log, "kind", log.mark("end") or rows[-1][3])
    q = q or query_reply(log, "kind", rows[-1][3] - SAMPLE_CYCLES * 10)[0]
    if q and (q.get("drops") != "0" or q.get("late") != "0"):
        problems.append(f"the sketch reports drops={q.get('drops')} late={q.get('late')} (want 0)")
    summary = (f"{len(rows)} samples over {rows[-1][0] / 1000:.2f} s; loop period 160000 +/- {jitter} cycles "
               f"(1 Timer1 tick = {TIMER1_TICK}), drift {drift} cycles; stream == motionsim filter on "
               f"{len(rows) - len(mism)}/{len(rows)} lines; PWM = y within {worst_mv:.2f} mV in {checked} samples")
    return CheckResult(not problems, summary, problems)


# Every kind, restarts and `every`, a few emulated seconds: each command that restarts the filter
# (kind, tau, tau2, reset) starts a segment that motionsim replays from rest with the segment's
# parameters and the input the stream shows, line for line.
FILTER_KINDS_SCRIPT = """\
wait ^READY [^ ]+$
send ?
wait ^kind=
{restart}kind ma2
wait ^OK kind=ma2$
{restart}tau 0.5
wait ^OK tau=
{restart}tau2 0.2
wait ^OK tau2=
send u 5
wait ^OK u=5.000$
run 900
{restart}tau 0.3
wait ^OK tau=
run 250
{restart}tau2 0.1
wait ^OK tau2=
send u 2
wait ^OK u=2.000$
run 250
{restart}reset
wait ^OK reset$
run 250
{restart}kind exp
wait ^OK kind=exp$
run 100
{restart}tau 0.2
wait ^OK tau=
run 300
send u 4
wait ^OK u=4.000$
run 300
{restart}reset
wait ^OK reset$
run 200
send every 10
wait ^OK every=10$
run 800
send ?
wait ^kind=
""".replace("{restart}", "wait ^[0-9]+,\nsend ")
# (each restarting command is sent just after a stream line, a few ms after its sample's tick, so
# that it is handled well before the next one: the segment boundaries below are then unambiguous)
# the sketch's documented boot state (README, The MovingAverageFilter sketch)
FILTER_BOOT = {"kind": "ma", "tau": "9", "tau2": "3"}
RESTARTS = ("kind", "tau", "tau2", "reset")


def filter_replay(env, prm, inputs):
    """motionsim filter --stream lines (without the header) for a segment from rest"""
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write("u\n" + "\n".join(inputs) + "\n")
        path = f.name
    try:
        args = ["filter", "--kind", prm["kind"], "--tau", prm["tau"], "--ts", "0.01", "--input", f"csv:{path}",
                "--stream"]
        if prm["kind"] == "ma2":
            args += ["--tau2", prm["tau2"]]
        out, _ = motionsim(env, *args)
    finally:
        os.unlink(path)
    return out.splitlines()[1:]


def check_filter_kinds(env, sketch):
    """Each command that restarts the filter (kind, tau, tau2, reset) starts a segment; motionsim
    replays each segment from rest with the parameters sent so far and the input the stream shows,
    and every streamed line must be identical (its t_ms counted from the segment's first sample)."""
    log = emulog.run(env.elf(sketch), FILTER_KINDS_SCRIPT, pins=sketches.filter_pins(env))
    problems = []
    fails_of(log, problems)
    if problems:
        return CheckResult(False, "emulation failed", problems)
    rows = {}
    for l in log.rx:
        m = STREAM_RE.match(l.text)
        if m:
            rows[int(m.group(1)) // 10] = (m.group(2), m.group(3))
    strobe = strobe_edges(log)
    fc = emulate.frame_cycles(log)
    if not rows or max(rows) >= len(strobe):
        return CheckResult(False, f"{len(rows)} stream lines, {len(strobe)} strobe edges",
                           ["the stream or the strobe is missing"])
    # the input of every sample from the stream; `every 10` leaves gaps, in which u is constant
    # (the script sends no `u` then), so a gap carries the u of the line before it
    last_k = max(rows)
    ev = next((t for t in log.tx if t.text == "every 10"), None)
    ev_k = bisect.bisect_left(strobe, ev.cycle) if ev else last_k + 1
    us, u = [], None
    for k in range(last_k + 1):
        if k in rows:
            u = rows[k][0]
        elif k < ev_k:
            problems.append(f"sample {k} (t_ms={10 * k}) missing from the stream before `every 10`")
            return CheckResult(False, "stream incomplete", problems)
        us.append(u)
    after = sorted(k for k in rows if k > ev_k + 10)
    gaps = {b - a for a, b in zip(after, after[1:])}
    if gaps != {10} or len({rows[k][0] for k in after}) != 1:
        problems.append(f"after `every 10` the stream should come every 10 samples with u constant: gaps {gaps}")
    # segment starts: the first sample whose ADC interrupt ran after the command was handled: the
    # first tick after the command's arrival, or (if its OK came after that tick) possibly the next
    params = dict(FILTER_BOOT)
    segs = [([0], dict(params), "boot")]
    ambiguous = 0
    for t in log.tx:
        word, _, arg = t.text.partition(" ")
        if word not in RESTARTS:
            continue
        if word != "reset":
            params[word] = arg
        arrival = t.cycle + (len(t.text) + 2) * fc
        ok = log.first(r"^OK " + re.escape(word), t.cycle)
        k_a = bisect.bisect_left(strobe, arrival)
        cands = [k_a] if ok and ok.cycle < strobe[k_a] else [k_a, k_a + 1]
        ambiguous += len(cands) > 1
        segs.append((cands, dict(params), t.text))
    # pass 1: pick each start among its candidates by the lines that surely belong to the segment
    starts = []
    for i, (cands, prm, label) in enumerate(segs):
        nxt_min = segs[i + 1][0][0] if i + 1 < len(segs) else last_k + 1
        score = []
        for k0 in cands:
            ks = [k for k in range(k0, nxt_min) if k in rows]
            sim = filter_replay(env, prm, us[k0:nxt_min]) if ks else []
            bad = sum(1 for k in ks if k - k0 >= len(sim) or sim[k - k0] != f"{(k - k0) * 10},{rows[k][0]},{rows[k][1]}")
            score.append((bad, k0))
        starts.append(min(score)[1])
    # pass 2: every line of every segment, with the chosen starts
    checked = identical = 0
    notes = []
    for i, (cands, prm, label) in enumerate(segs):
        k0 = starts[i]
        k1 = starts[i + 1] if i + 1 < len(starts) else last_k + 1
        ks = [k for k in range(k0, k1) if k in rows]
        if not ks:
            notes.append(f"{label} (superseded)")
            continue
        sim = filter_replay(env, prm, us[k0:k1])
        bad = [k for k in ks if k - k0 >= len(sim) or sim[k - k0] != f"{(k - k0) * 10},{rows[k][0]},{rows[k][1]}"]
        checked += len(ks)
        identical += len(ks) - len(bad)
        if label != "boot":
            notes.append(f"{label} @{10 * k0} ms")
        if bad:
            k = bad[0]
            problems.append(f"segment '{label}' ({prm['kind']} tau {prm['tau']}"
                            f"{' tau2 ' + prm['tau2'] if prm['kind'] == 'ma2' else ''}) from t_ms={10 * k0}: "
                            f"{len(bad)} of {len(ks)} lines differ from motionsim, first at t_ms={10 * k}: firmware "
                            f"u,y '{rows[k][0]},{rows[k][1]}', motionsim "
                            f"'{sim[k - k0].split(',', 1)[1] if k - k0 < len(sim) else None}'")
    q, _ = query_reply(log, "kind", ev.cycle if ev else 0)
    want = {"kind": "exp", "tau": "0.20", "every": "10", "drops": "0", "late": "0"}
    if not q or any(q.get(k) != v for k, v in want.items()):
        problems.append(f"`?` at the end should report {want}: {q}")
    summary = (f"{len(segs)} segments ({'; '.join(notes)}) replayed from rest by motionsim filter --stream: "
               f"{identical}/{checked} lines identical; {ambiguous} boundary(ies) needed the next sample tried; "
               f"`every 10`: a line every 100 ms; `?` then {want}")
    return CheckResult(not problems, summary, problems)


def check_filter_bad_input(env, sketch):
    return check_bad_input(
        env, sketch, "kind", "", COMMON_BAD + [
            ("u above 5 V", "send u 5.5"), ("negative u", "send u -1"), ("u not a number", "send u five"),
            ("tau below Ts", "send tau 0.005"), ("tau not whole samples", "send tau 9.005"),
            ("tau too long for the buffer", "send tau 60"), ("unknown kind", "send kind median"),
            ("every 0", "send every 0"), ("every above 1000", "send every 1001"), ("extra word", "send reset now"),
            # kind ma: tau2 is kept for ma2 and checked as ma2 would use it (9 s + 25 s > 2000 taps)
            ("tau2 too long for ma2's buffer, kind ma", "send tau2 25"),
            # issue 12 item 6: above the limit as a decimal although it rounds to it in float; underflow
            ("u just above 5 V", "send u 5.0000001"), ("u underflows", "send u 1e-400"),
        ], pins=sketches.filter_pins(env))


# ----------------------------------------------------------------------------------------------
# servo sketches (check 3)

SERVO_SCRIPT = """\
wait ^READY [^ ]+$
{gains}
send ?
wait ^setpoint=
mark setpoint
send {setpoint}
wait ^OK setpoint={setpoint}$
run {run_ms}
send ?
wait ^setpoint=
"""


def settle_time(ts, ps, final, band):
    """first time after which the position stays within `band` of `final`"""
    t_in = None
    for t, p in zip(ts, ps):
        if abs(p - final) > band:
            t_in = None
        elif t_in is None:
            t_in = t
    return t_in


# A Kp with which `motionsim servo --ctrl p` ends within 2 % of a 1000-count step and settles
# (0.3: 992 counts, 15 % overshoot, settled in 0.36 s). The lab's 0.02 stops at 798 counts: the
# duty 0.02 x 202 = 4.04 % then drives too little current to overcome the plant's static friction.
P_TUNED_KP = 0.3
SERVO_PWM_PERIOD_MS = 510 * 64 / 16000.0   # analogWrite on Timer3: phase correct, clk/64 (2.04 ms)
SERVO_REACT_MAX_MS = 20.0 + 1.0 + 2 * SERVO_PWM_PERIOD_MS + 1.0


# The gains the servo sketches as shipped report at boot: the lab handout's Kp = 0.02 % duty per
# count; PIDClosedLoop starts as the same proportional loop, Ki = Kd = 0 (docs/servo.md). A copy's
# come from its own `?` reply.
SERVO_HANDOUT_GAINS = {"ProportionalClosedLoop": {"kp": 0.02}, "PIDClosedLoop": {"kp": 0.02, "ki": 0.0, "kd": 0.0}}
SERVO_GAIN_KEYS = ("kp", "ki", "kd")


def seconds_or_unsettled(t):
    return "unsettled" if t is None else f"{t:.2f} s"


def check_servo(env, sketch, ctrl, gains, setpoint=1000, run_ms=3000, tol_counts=None, must_reach=False):
    """gains: (key, value) pairs sent over serial first (none: the sketch's defaults). motionsim runs
    with the gains the sketch's own `?` reply reports just before the setpoint (the gains in force,
    printed to 6 decimals), which must be those sent; the servo sketches as shipped must report
    the handout's gains (SERVO_HANDOUT_GAINS) when none are sent."""
    gains_cmds = "\n".join(f"send {k} {v}\nwait ^OK {k}=" for k, v in gains)
    script = SERVO_SCRIPT.format(sketch=sketch, gains=gains_cmds, setpoint=setpoint, run_ms=run_ms)
    cs_pin = f"D{env.header_int('servo', 'SERVO_PIN_ENCODER_CS', sketch)}"
    log = emulog.run(env.elf(sketch), script, motor=sketches.servo_motor_spec(env, sketch), pins={"CS": cs_pin})
    problems = []
    fails_of(log, problems)
    if problems:
        return CheckResult(False, "emulation failed", problems)
    g = dict(gains)
    ok = log.first(rf"^OK setpoint={setpoint}$")
    q0, _ = query_reply(log, "setpoint", 0, ok.cycle if ok else None)
    if not q0 or "kp" not in q0:
        return CheckResult(False, "no `?` reply", [f"no `?` reply with kp= before the setpoint: {q0}"])
    in_force = {k: q0[k] for k in SERVO_GAIN_KEYS if k in q0}
    if ("ki" in in_force) != (ctrl == "pid"):
        problems.append(f"`?` reports {in_force}: not the gains of a {ctrl.upper()} sketch")
    want = {k: float(v) for k, v in g.items()}
    if not gains and is_original(sketch):
        want = dict(SERVO_HANDOUT_GAINS.get(sketch, {}))
    wrong = {k: in_force.get(k) for k, v in want.items()
             if in_force.get(k) is None or abs(float(in_force[k]) - v) > 5e-7 + 1e-6 * abs(v)}
    if wrong:
        problems.append(f"`?` before the setpoint reports {wrong}, want {want}"
                        + (" (the lab handout's gains)" if not gains else " (the gains sent)"))
    args = ["servo", "--ctrl", ctrl, "--setpoint", str(setpoint), "--duration", str(run_ms / 1000.0 - 0.1)]
    for k, v in in_force.items():
        args += [f"--{k}", v]
    out, _ = motionsim(env, *args)
    sim = [r.split(",") for r in out.splitlines()[1:] if r]
    sim_t = [float(r[0]) for r in sim]
    sim_p = [int(float(r[2])) for r in sim]
    # The reaction is bounded from the command's arrival (its last byte received by the sketch):
    # the next 20 ms control period uses the new setpoint (1 ms more for millis()' 1.024 ms steps
    # and the loop's own work), its OCR value reaches the pin at the end of the running PWM period,
    # the pin's duty is averaged over one PWM period and sampled every 1 ms. A firmware that sits on
    # a new setpoint for a control period or more fails here.
    fc = emulate.frame_cycles(log)
    tx = next((t for t in log.tx if t.text == str(setpoint)), None)
    if tx is None or ok is None:
        return CheckResult(False, "no setpoint reply", [f"the setpoint was not sent or not answered 'OK setpoint="
                                                        f"{setpoint}'"])
    arrival = tx.cycle + (len(tx.text) + 2) * fc
    mot = [(c, d, n) for c, d, n in log.motor if c >= tx.cycle]
    d0 = mot[0][1] if mot else 0.0
    first = next((c for c, d, n in mot if abs(d - d0) > 0.01), None)
    if first is None:
        return CheckResult(False, "the motor never moved", ["no duty change after the setpoint"])
    react_ms = (first - arrival) / F_CPU * 1000.0
    if not (0 <= react_ms <= SERVO_REACT_MAX_MS):
        problems.append(f"the first duty change came {react_ms:.2f} ms after the setpoint arrived (bound: one "
                        f"control period + 1 ms + 2 PWM periods + 1 ms sampling = {SERVO_REACT_MAX_MS:.2f} ms)")
    # t = 0 of the firmware trace: the encoder read (chip select falling) of the control period that
    # first drove the new duty, i.e. the last read before the first duty change; motionsim's t = 0 is
    # its first sample too, so the sketch's real sample-to-motor latency is part of what is compared.
    reads = [c for c, lv in log.pins.get("CS", []) if lv == 0 and c < first]
    if not reads:
        return CheckResult(False, "no encoder read seen", [f"no chip select edge on {cs_pin} before the duty change"])
    sample = reads[-1]
    t0 = sample / F_CPU
    mot = [(c, d, n) for c, d, n in mot if c >= sample]
    fw_t = [c / F_CPU - t0 for c, d, n in mot]
    fw_p = [n for c, d, n in mot]

    def fw_at(t):
        i = bisect.bisect_left(fw_t, t)
        if i <= 0:
            return fw_p[0]
        if i >= len(fw_t):
            return fw_p[-1]
        return fw_p[i - 1] + (fw_p[i] - fw_p[i - 1]) * (t - fw_t[i - 1]) / (fw_t[i] - fw_t[i - 1])

    devs = [(abs(fw_at(t) - p), t) for t, p in zip(sim_t, sim_p) if t <= fw_t[-1]]
    worst, worst_t = max(devs) if devs else (None, None)
    tol = tol_counts if tol_counts is not None else max(10, 0.02 * abs(setpoint))
    if worst is None or worst > tol:
        problems.append(f"position differs from motionsim servo by up to {worst} counts at t={worst_t} s "
                        f"(tolerance {tol:.0f})")
    band = 0.02 * abs(setpoint)
    fw_final, sim_final = fw_p[-1], sim_p[-1]
    # both traces into the same band (around motionsim's final position): with a band around each
    # trace's own final value, a slow tail a few counts apart moves the crossing by tenths of a second
    st_fw = settle_time(fw_t, fw_p, sim_final, band)
    st_sim = settle_time(sim_t, sim_p, sim_final, band)
    if abs(fw_final - sim_final) > tol:
        problems.append(f"final position {fw_final} vs motionsim {sim_final}")
    if (st_fw is None) != (st_sim is None) or (st_fw is not None and abs(st_fw - st_sim) > 0.1):
        problems.append(f"2 % settling time {seconds_or_unsettled(st_fw)} vs motionsim {seconds_or_unsettled(st_sim)} "
                        "(tolerance 0.1 s)")
    if must_reach and abs(fw_final - setpoint) > band:
        problems.append(f"the setpoint {setpoint} is not reached: final position {fw_final} (band {band:.0f})")
    q, _ = query_reply(log, "setpoint", ok.cycle + 1)
    if not q or int(q.get("setpoint", "0")) != setpoint or abs(int(q.get("position", "0")) - fw_final) > 2:
        problems.append(f"`?` after the run should report setpoint={setpoint} position~{fw_final}: {q}")
    gains_text = " ".join(f"{k}={v}" for k, v in in_force.items())
    summary = (f"setpoint {setpoint}, gains {'sent' if gains else 'at boot'} as `?` reports them: {gains_text}: "
               f"final {fw_final} counts (motionsim {sim_final}), settling (2 %) {seconds_or_unsettled(st_fw)} "
               f"(motionsim {seconds_or_unsettled(st_sim)}), trace within "
               f"{'-' if worst is None else f'{worst:.1f}'} counts of motionsim (tolerance {tol:.0f}); "
               f"first duty change {react_ms:.1f} ms after the "
               f"setpoint arrived (bound {SERVO_REACT_MAX_MS:.1f}); {log.end.get('speed')} real time")
    return CheckResult(not problems, summary, problems)


def servo_ctrl(env, sketch):
    """'pid' or 'p', from the sketch's own `?` reply at boot (a short emulation): a PID sketch
    reports ki= and kd=, the P sketch only kp="""
    log = emulog.run(env.elf(sketch), "wait ^READY [^ ]+$\nsend ?\nwait ^setpoint=\n",
                     motor=sketches.servo_motor_spec(env, sketch))
    q, _ = query_reply(log, "setpoint")
    if not q or "kp" not in q:
        raise RuntimeError(f"no `?` reply with kp= from {sketch}: {[l.text for l in log.rx]}")
    return "pid" if "ki" in q else "p"


def check_servo_defaults(env, sketch):
    return check_servo(env, sketch, servo_ctrl(env, sketch), [])


def check_servo_tuned(env, sketch):
    """P: Kp retuned; PID: all three gains set; either must reach the setpoint"""
    if servo_ctrl(env, sketch) == "p":
        return check_servo(env, sketch, "p", [("kp", P_TUNED_KP)], run_ms=2000, must_reach=True)
    return check_servo(env, sketch, "pid", [("kp", 0.05), ("ki", 0.05), ("kd", 0.001)], run_ms=4000,
                       must_reach=True)


# `move <counts>` (the filter-shaped setpoint, lib/src/smooth_move.h): the gains of the emulator's
# tuned P run and of `make profiles`' PID run, the move of the other servo checks.
SERVO_MOVE_GAINS = {"p": [("kp", P_TUNED_KP)], "pid": [("kp", 0.1), ("ki", 0.1), ("kd", 0.002)]}
SERVO_MOVE_QUERIES = 12      # `?` every SERVO_MOVE_QUERY_MS while the setpoint travels
SERVO_MOVE_QUERY_MS = 50


def check_servo_move(env, sketch, target=1000, run_ms=2500):
    """`move <target>`: answered `OK move=<target>`, no ERR; the setpoint (from `?` replies during
    the move) rises through intermediate values, each one of the setpoints motionsim servo
    --profile smooth computes for its 20 ms periods (the same integer law), and ends at the target;
    the position trace follows motionsim's within the tolerance of the other servo checks, aligned
    at the first control period after the command (motionsim's t = 20 ms: the move starts at the
    sketch's last period)."""
    ctrl = servo_ctrl(env, sketch)
    gains = SERVO_MOVE_GAINS[ctrl]
    gains_cmds = "\n".join(f"send {k} {v}\nwait ^OK {k}=" for k, v in gains)
    queries = "\n".join(f"run {SERVO_MOVE_QUERY_MS}\nsend ?\nwait ^setpoint=" for _ in range(SERVO_MOVE_QUERIES))
    script = (f"wait ^READY [^ ]+$\n{gains_cmds}\nsend move {target}\nwait ^OK move={target}$\n{queries}\n"
              f"run {run_ms}\nsend ?\nwait ^setpoint=\n")
    cs_pin = f"D{env.header_int('servo', 'SERVO_PIN_ENCODER_CS', sketch)}"
    log = emulog.run(env.elf(sketch), script, motor=sketches.servo_motor_spec(env, sketch), pins={"CS": cs_pin})
    problems = []
    fails_of(log, problems)
    if problems:
        return CheckResult(False, "emulation failed", problems)
    errs = log.lines_matching(r"^ERR")
    if errs:
        problems.append(f"ERR lines: {[l.text for l in errs]}")
    ok = log.first(rf"^OK move={target}$")
    tx = next((t for t in log.tx if t.text == f"move {target}"), None)
    if ok is None or tx is None:
        return CheckResult(False, "no move reply", problems + [f"'move {target}' not sent or not answered"])
    args = ["servo", "--ctrl", ctrl, "--setpoint", str(target), "--duration", str(run_ms / 1000.0),
            "--profile", "smooth"]
    for k, v in gains:
        args += [f"--{k}", str(v)]
    out, _ = motionsim(env, *args)
    sim = [r.split(",") for r in out.splitlines()[1:] if r]
    sim_t = [float(r[0]) for r in sim]
    sim_sp = [int(r[1]) for r in sim]
    sim_p = [int(float(r[2])) for r in sim]
    replies = [emulog.query_fields(l.text) for l in log.lines_matching(r"^setpoint=", ok.cycle)]
    sps = [int(q["setpoint"]) for q in replies]
    mid = [v for v in sps[:-1] if 0 < v < target]
    if len(sps) != SERVO_MOVE_QUERIES + 1:
        problems.append(f"{len(sps)} `?` replies after the move, want {SERVO_MOVE_QUERIES + 1}")
    if any(b < a for a, b in zip(sps, sps[1:])):
        problems.append(f"the setpoint went back: {sps}")
    if len(set(mid)) < 3:
        problems.append(f"the setpoint did not travel (fewer than 3 values between 0 and {target}): {sps}")
    stray = sorted(set(v for v in sps if v not in sim_sp))
    if stray:
        problems.append(f"setpoints not in motionsim servo --profile smooth's sequence: {stray}")
    if not sps or sps[-1] != target:
        problems.append(f"the setpoint ends at {sps[-1] if sps else None}, want {target}")
    # the trace: t = 0.02 s of motionsim at the first control period after the command arrived. That
    # period's read comes late when the command's handling (the move's plan) runs into it, so the
    # alignment is taken from the next period's read, on the 20 ms schedule: t = 0.04 s there
    # (until 2026-12-05 from the first read, which made the check move with the plan's cost: a
    # change of 2 ms in it moved the PID trace's deviation from 19.8 to 24.8 counts)
    fc = emulate.frame_cycles(log)
    arrival = tx.cycle + (len(tx.text) + 2) * fc
    reads = [c for c, lv in log.pins.get("CS", []) if lv == 0 and c > arrival]
    periods = [c for i, c in enumerate(reads) if i == 0 or c - reads[i - 1] > F_CPU // 200]  # a burst's first read
    if len(periods) < 2:
        return CheckResult(False, "no encoder read after the move", problems)
    t0 = periods[1] / F_CPU - 0.04
    mot = [(c / F_CPU - t0, n) for c, d, n in log.motor if c >= reads[0]]
    fw_t = [t for t, _ in mot]
    fw_p = [n for _, n in mot]

    def fw_at(t):
        i = bisect.bisect_left(fw_t, t)
        if i <= 0:
            return fw_p[0]
        if i >= len(fw_t):
            return fw_p[-1]
        return fw_p[i - 1] + (fw_p[i] - fw_p[i - 1]) * (t - fw_t[i - 1]) / (fw_t[i] - fw_t[i - 1])

    devs = [(abs(fw_at(t) - p), t) for t, p in zip(sim_t, sim_p) if fw_t and fw_t[0] <= t <= fw_t[-1]]
    worst, worst_t = max(devs) if devs else (None, None)
    tol = max(10, 0.02 * abs(target))
    if worst is None or worst > tol:
        problems.append(f"position differs from motionsim servo --profile smooth by up to {worst} counts at "
                        f"t={worst_t} s (tolerance {tol:.0f})")
    summary = (f"move {target} with {' '.join(f'{k}={v}' for k, v in gains)}: `?` setpoints {sps}; "
               f"final position {fw_p[-1] if fw_p else None} (motionsim {sim_p[-1]}); trace within "
               f"{'-' if worst is None else f'{worst:.1f}'} counts of motionsim (tolerance {tol:.0f})")
    return CheckResult(not problems, summary, problems)


def check_servo_move_bad_input(env, sketch):
    """`move` with a missing, non-whole, out-of-range or extra word: one ERR each, `?` unchanged"""
    bad = [("move without a target", "send move"), ("move not whole", "send move 12.5"),
           ("move above 1000000", "send move 1000001"), ("move below -1000000", "send move -1000001"),
           ("move with an extra word", "send move 5 6"), ("move of a word", "send move far")]
    return check_bad_input(env, sketch, "setpoint", "", bad, motor=sketches.servo_motor_spec(env, sketch))


def check_smooth_move_avr(env):
    """lib/src/smooth_move.c built for the ATmega2560 and for the host from
    test/emu/smooth_avr/smooth_move_avr.c: the commands of whole reference moves (one stopped, two
    sent to new targets) and the servo's setpoints must have the same checksums (integer work and
    IEEE single-precision float work on both); the cycles per command and per step, the planner's
    load and the lead it needs are reported."""
    src = os.path.join(env.source_dir, "test", "emu", "smooth_avr", "smooth_move_avr.c")
    libs = [os.path.join(env.source_dir, "lib", "src", f) for f in ("smooth_move.c", "motion_status.c")]
    inc = ["-I" + os.path.join(env.source_dir, "lib", "src"), "-I" + os.path.join(env.source_dir, "test", "emu")]
    with tempfile.TemporaryDirectory() as d:
        elf, host = os.path.join(d, "smooth_move_avr.elf"), os.path.join(d, "smooth_move_host")
        for cmd in (["avr-gcc", "-mmcu=atmega2560", "-DF_CPU=16000000UL", "-Os", "-std=gnu11", "-ffunction-sections",
                     "-fdata-sections", "-flto", "-fuse-linker-plugin", "-Wl,--gc-sections", "-Wall", "-Wextra",
                     "-Werror", *inc, src, *libs, "-o", elf, "-lm"],
                    ["cc", "-std=gnu11", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-Werror", *inc, src, *libs,
                     "-o", host, "-lm"]):
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
            if p.returncode != 0:
                return CheckResult(False, "build failed", [" ".join(cmd[:2]), p.stderr.strip()[-800:]])
        log = emulog.run(elf, "timeout 120000\nwait ^end$\n")
        problems = []
        fails_of(log, problems)
        avr = [l.text for l in log.rx if l.text.startswith(("smooth ", "setpoint "))]
        out = subprocess.run([host], capture_output=True, text=True, timeout=120).stdout.splitlines()
        hst = [l for l in out if l.startswith(("smooth ", "setpoint "))]

    def sums(lines):
        return [re.search(r"sum=(\w+)", l).group(1) if "sum=" in l else None for l in lines]
    if len(avr) != 6 or len(hst) != 6:
        problems.append(f"lines: AVR {avr}, host {hst}")
    elif sums(avr) != sums(hst):
        problems.append(f"checksums differ: AVR {sums(avr)}, host {sums(hst)}")
    summary = "; ".join(avr) + " (cycles on the AVR; checksums equal to the host's)" if not problems else str(avr)
    return CheckResult(not problems, summary, problems)


def check_servo_bad_input(env, sketch, pid=None):
    if pid is None:
        pid = servo_ctrl(env, sketch) == "pid"
    extra = [("setpoint above 1000000", "send 1000001"), ("setpoint not whole", "send 12.5"),
             ("negative kp", "send kp -1"), ("kp above 1000", "send kp 1001"), ("kp without value", "send kp"),
             ("extra word", "send kp 1 2"),
             # issue 12 item 6: above 1000 as a decimal although it rounds to 1000 in float; underflow
             ("kp just above 1000", "send kp 1000.00001"), ("kp underflows", "send kp 1e-46")]
    if not pid:
        extra.append(("ki on the P sketch", "send ki 1"))
    busy = [("junk while moving", "send go faster"), ("setpoint out of range while moving", "send -2000000"),
            ("negative gain while moving", "send kd -0.5" if pid else "send kp -0.5")]
    return check_bad_input(
        env, sketch, "setpoint", "", COMMON_BAD + extra,
        while_busy=("send 1000", r"^OK setpoint=1000$", busy, r"^t_ms=3000 ", 5000),
        dynamic=("position", "error", "duty"), motor=sketches.servo_motor_spec(env, sketch))


# ----------------------------------------------------------------------------------------------
# stepper sketches (check 1)

# A long move with a cruise, and a negative move, need parameters that fit a short emulation:
# trapezoid ramps go from 100 to 2000 steps/s at 4000 steps/s^2 (about 500 steps of
# acceleration; the simplistic ramp's linear interval change from v0 = 1 step/s would take
# minutes), the S-curve gets a 100-entry table held 2 steps per entry (200 steps of acceleration).
STEPPER_FAST = {"sigmoid": [("len", "100"), ("hold", "2")],
                "trapezoid": [("vmax", "2000"), ("accel", "4000"), ("v0", "100")],   # vmax > v0 at every step
                "exact": [("vmax", "2000"), ("accel", "4000"), ("v0", "100")]}
# the move during which commands are sent must outlast them (about 0.5 s of serial traffic)
# The parameters `?` must report at boot: the lab handout's defaults for its ramps (minimum speed
# 1 step/s, maximum 20 steps/s, acceleration 10 steps/s^2); the S-curve's documented table (len 250,
# 200 -> 4000 steps/s, flex 5, each entry held 4 steps).
STEPPER_DEFAULTS = {"trapezoid": {"v0": 1, "vmax": 20, "accel": 10},
                    # ExactRampStepper's documented defaults (its header and docs/stepper-engine.md)
                    "exact": {"v0": 0, "vmax": 20000, "accel": 50000},
                    "sigmoid": {"v0": 200, "vmax": 4000, "flex": 5, "len": 250, "hold": 4}}
STEPPER_BUSY_TARGET = {"sigmoid": 1000, "trapezoid": 50, "exact": 20000}
# The sketches as shipped, whose boot `?` must report the documented defaults above (by their
# ramp shape) or, for the servo sketches, the lab handout's gains. Any other sketch of the family
# is a student's copy (the handout's XXX naming, e.g. LeibRampStepperABC), perhaps with edited
# values: its expectations come from its own `?` reply at boot (docs/emulator.md).
ORIGINAL_SKETCHES = ("LeibRampStepper", "SimplisticRampStepper", "ExactRampStepper", "SCurveStepper",
                     "ProportionalClosedLoop", "PIDClosedLoop")


def is_original(sketch):
    return sketch in ORIGINAL_SKETCHES


def ramp_shape(algo):
    """What the expectations depend on: the S-curve's table (algo=sigmoid) or a trapezoid ramp
    (v0, vmax, accel: leib, simplistic, exact and any other), from the sketch's own `?` reply."""
    if algo in ("sigmoid", "exact"):
        return algo
    return "trapezoid"


STEPPER_MOVES = [(0, 50, "the lab's 0 -> 50, default parameters"), (50, 3050, "long move with cruise"),
                 (3050, -200, "negative move with cruise")]


def stepper_script(sketch, algo):
    s = ["wait ^READY [^ ]+$", "timeout 5000", "send ?", "wait ^pos="]
    for i, (a, b, _) in enumerate(STEPPER_MOVES):
        if i == 1:
            for k, v in STEPPER_FAST[ramp_shape(algo)]:
                s += [f"send set {k} {v}", f"wait ^OK {k}="]
            s += ["send ?", "wait ^pos="]
        s += [f"mark move {a} {b}", f"send {b}", f"wait ^OK {a} {b}$", "timeout 60000", f"wait ^DONE {b}$",
              "timeout 5000", "send ?", "wait ^pos="]
    return "\n".join(s) + "\n"


def stepper_algo(env, sketch, elf=None):
    """the algorithm, from the sketch's `?` at boot (a short emulation)"""
    log = emulog.run(elf or env.elf(sketch), "wait ^READY [^ ]+$\nsend ?\nwait ^pos=\n")
    q, _ = query_reply(log, "pos")
    if not q or "algo" not in q:
        raise RuntimeError(f"no `?` reply with algo= from {sketch}: {[l.text for l in log.rx]}")
    return q["algo"]


def sim_intervals(env, q, a, b):
    """motionsim ramp's whole-tick intervals for the parameters in the `?` reply q"""
    # tools/emu/emulate.py: the same argument mapping `make emulate` uses
    out, _ = motionsim(env, *emulate.stepper_sim_args(q, a, b))
    rows = [r.split(",") for r in out.splitlines()[1:] if r]
    return [float(r[3]) for r in rows], [int(r[1]) for r in rows]


# The step interrupt makes each edge in software, so an edge whose compare match meets another
# interrupt waits for it: Timer0's millis (about 94 cycles), the USART's receive (79) and transmit
# (128), one after another at worst, and our own short interrupts-off sections.
STEPPER_OTHER_ISR_CYCLES = 260


def check_stepper(env, sketch, elf=None, bound_ticks=None, mode="timer"):
    """bound_ticks: the largest interval error, drift and spread of the edges around the ideal
    timeline, in ticks (the timer mode: one tick, at least 8 cycles = 0.5 us, the step engine's
    target; the timed-loop mode: see STEPPER_LOOP_BOUND_US)."""
    algo = stepper_algo(env, sketch, elf)
    pins = sketches.stepper_pins(env)
    log = emulog.run(elf or env.elf(sketch), stepper_script(sketch, algo), pins=pins)
    problems = []
    fails_of(log, problems)
    fc = 10 * 8 * 208  # 9600 baud frame (StepperConsole)
    rises = log.rising("STEP")
    led = [c for c, _ in log.pins.get("LED", [])]
    dir_edges = log.pins.get("DIR", [])
    figures = []
    worst_all = 0.0
    ticks_seen = set()
    cpt = None
    # the parameters at boot: an original sketch's documented defaults; a copy's own `?` reply
    shape = ramp_shape(algo)
    boot_line = log.first("^pos=")
    boot_q = emulog.query_fields(boot_line.text) if boot_line else {}
    if is_original(sketch):
        boot_want = dict(STEPPER_DEFAULTS[shape])
    else:
        boot_want = {k: boot_q.get(k) for k in STEPPER_DEFAULTS[shape]}
        missing = [k for k, v in boot_want.items() if v is None]
        if missing:
            problems.append(f"`?` at boot does not report {', '.join(missing)}: {boot_q}")
            return CheckResult(False, f"algo={algo}: no parameters", problems)
    for a, b, label in STEPPER_MOVES:
        m = log.mark(f"move {a} {b}")
        if m is None:
            problems.append(f"{label}: not reached")
            break
        q = emulog.query_fields(log.lines_matching("^pos=", 0, m)[-1].text)
        # the parameters in force: the defaults at boot, then the values `set` sent
        want_q = dict(boot_want)
        if a != 0:
            want_q.update(STEPPER_FAST[shape])
        wrong = {k: q.get(k) for k, v in want_q.items() if q.get(k) is None or float(q[k]) != float(v)}
        if wrong:
            problems.append(f"{label}: `?` before the move reports {wrong}, want {want_q}")
        if q.get("mode") != mode:
            problems.append(f"{label}: `?` reports mode={q.get('mode')}, want {mode}")
        tick_hz = float(q["tick_hz"])
        ticks_seen.add(q["tick_hz"])
        cpt = F_CPU / tick_hz
        if bound_ticks is None:
            bound_ticks = max(1.0, 8.0 / cpt)
        ok = log.first(rf"^OK {a} {b}$", m)
        done = log.first(rf"^DONE {b}$", m)
        if not ok or not done:
            problems.append(f"{label}: replies OK {a} {b} / DONE {b} missing")
            continue
        tx = next(t for t in log.tx if t.cycle >= m and t.text == str(b))
        t0 = tx.cycle + (len(tx.text) + 2) * fc  # the line end has arrived
        edges = [c for c in rises if t0 <= c <= done.cycle]
        n = abs(b - a)
        if len(edges) != n:
            problems.append(f"{label}: {len(edges)} steps, want exactly {n}")
            continue
        # DIR: right level before the first step, unchanged until the last
        want_dir = 1 if b > a else 0
        if log.level_before("DIR", edges[0]) != want_dir:
            problems.append(f"{label}: DIR is {log.level_before('DIR', edges[0])} at the first step, want {want_dir}")
        moved = [c for c, _ in dir_edges if edges[0] <= c <= edges[-1]]
        if moved:
            problems.append(f"{label}: DIR changed during the move at {moved[:3]}")
        last_dir = max((c for c, _ in dir_edges if c < edges[0]), default=None)
        # DIR setup time, when this move changed DIR (it may also hold from an earlier move)
        setup_us = (edges[0] - last_dir) / 16 if last_dir is not None and last_dir >= t0 - fc else None
        # STEP, DIR and ENABLE are outputs (DDRx bit set) at step 1 and stay so to the last step;
        # ENABLE (active low) is driven low throughout: an input pin reads 0 too, hence the DDR test
        for sig in ("STEP", "DIR", "ENABLE"):
            if not log.output_before(sig, edges[0]):
                problems.append(f"{label}: {sig} is not an output at the first step (its DDR bit was never set)")
        if log.level_before("ENABLE", edges[0]) != 0:
            problems.append(f"{label}: ENABLE (active low) is high at the first step: the driver is off")
        for sig, moves in (("ENABLE", log.changes_between("ENABLE", edges[0], edges[-1])),
                           ("STEP", [c for c, _ in log.ddr.get("STEP", []) if edges[0] <= c <= edges[-1]]),
                           ("DIR", [c for c, _ in log.ddr.get("DIR", []) if edges[0] <= c <= edges[-1]])):
            if moves:
                problems.append(f"{label}: {sig} changed level or direction during the move at cycles {moves[:3]}")
        # intervals vs motionsim ramp --integer-ticks
        want, pos = sim_intervals(env, q, a, b)
        if len(want) != n or pos[-1] != b:
            problems.append(f"{label}: motionsim planned {len(want)} steps ending at {pos[-1:]}")
            continue
        got = [(y - x) / cpt for x, y in zip(edges, edges[1:])]
        errs = [g - w for g, w in zip(got, want[1:])]
        worst = max((abs(e) for e in errs), default=0.0)
        worst_at = max(range(len(errs)), key=lambda i: abs(errs[i])) + 2 if errs else 0
        worst_all = max(worst_all, worst)
        interval_bound = bound_ticks if mode == "loop" else bound_ticks + STEPPER_OTHER_ISR_CYCLES / cpt
        if worst > interval_bound:
            problems.append(f"{label}: step {worst_at} interval {got[worst_at - 2]:.3f} ticks, motionsim "
                            f"{want[worst_at - 1]:.0f} (error {errs[worst_at - 2]:+.3f} > {interval_bound:g} tick)")
        drift = (edges[-1] - edges[0]) / cpt - sum(want[1:])
        if abs(drift) > interval_bound:
            problems.append(f"{label}: last step {drift:+.2f} ticks off the sum of the intervals (drift)")
        # every edge on the ideal timeline (first edge + motionsim's intervals): within one tick,
        # except edges whose compare match met another interrupt (the core's millis and serial
        # interrupts hold the CPU up to about 130 cycles; STEPPER_OTHER_ISR_CYCLES), and those few
        ideal, offs = edges[0], []
        for e, w in zip(edges, [0.0] + want[1:]):
            ideal += w * cpt
            offs.append(e - ideal)
        base = min(offs)
        late = [o - base for o in offs]
        delayed = [x for x in late if x > bound_ticks * cpt]
        spread = max(late)
        if mode == "loop":
            if spread > bound_ticks * cpt:
                problems.append(f"{label}: step edges spread over {spread:.0f} cycles around the ideal timeline "
                                f"(more than {bound_ticks:g} tick = {bound_ticks * cpt:.0f} cycles)")
        else:
            if spread > STEPPER_OTHER_ISR_CYCLES:
                problems.append(f"{label}: an edge {spread:.0f} cycles late on the ideal timeline (more than another "
                                f"interrupt can hold it: {STEPPER_OTHER_ISR_CYCLES} cycles)")
            if len(delayed) > max(2, 0.03 * n):
                problems.append(f"{label}: {len(delayed)} of {n} edges more than one tick off the timeline "
                                f"(at most 3 % may meet another interrupt)")
        lat_us = ((edges[0] - t0) / cpt - want[0]) / tick_hz * 1e6
        if not (0 <= lat_us <= 40000):
            problems.append(f"{label}: first step {lat_us:.0f} us after its interval from the command's arrival")
        if done.cycle < edges[-1]:
            problems.append(f"{label}: DONE before the last step")
        after = emulog.query_fields(log.first("^pos=", done.cycle).text) if log.first("^pos=", done.cycle) else {}
        if after.get("pos") != str(b) or after.get("state") != "idle":
            problems.append(f"{label}: `?` after DONE says pos={after.get('pos')} state={after.get('state')}")
        if led:
            toggles = len([c for c in led if t0 <= c <= done.cycle])
            if toggles != n:
                problems.append(f"{label}: LED toggled {toggles} times for {n} steps (mirror on)")
        figures.append(f"{label}: {n} steps, worst interval error {worst:.3f} ticks, drift {drift:+.3f} ticks, "
                       f"edges within a {spread:.0f}-cycle window of the ideal timeline "
                       f"({len(delayed)} beyond one tick), "
                       f"first step {lat_us:.0f} us after its interval from the command, DIR "
                       + (f"set {setup_us:.0f} us before step 1" if setup_us is not None else "already right"))
    # every STEP pulse of the run belongs to a move: none between moves, none after DONE
    want_total = sum(abs(b - a) for a, b, _ in STEPPER_MOVES)
    if len(rises) != want_total:
        problems.append(f"{len(rises)} STEP rising edges in the whole run, want exactly {want_total} (the moves' steps)")
    ticks = ", ".join(sorted(ticks_seen)) or "?"
    drive = [p for p in problems if "output" in p or "ENABLE" in p or "direction" in p]
    defaults = ("the documented defaults" if is_original(sketch) else
                "the copy's own (" + " ".join(f"{k}={v}" for k, v in boot_want.items()) + ")")
    summary = (f"algo={algo} tick_hz={ticks} (1 tick = {cpt:g} cycles); `?` parameters = {defaults} at boot, then "
               f"the values set; {len(rises)} STEP pulses in the run; "
               + ("" if drive else "STEP/DIR/ENABLE outputs (DDR set) and ENABLE driven low from step 1 to the last "
                  "of every move; ") if cpt else f"algo={algo}; ") + "; ".join(figures)
    return CheckResult(not problems, summary, problems)


# The timed-loop mode (StepperPins.h, docs/stepper-engine.md): loop() compares micros() with each
# deadline, so a step is late by 0 to 4 us (micros() counts in 4 us) plus the longest pass of loop()
# in progress (serial interrupts and one call of the step planner, which plans only when the next
# deadline is at least 400 us away); the deadlines themselves do not drift. Asserted: 80 us for the
# window, each interval and the drift (the summary line shows the window measured).
STEPPER_LOOP_BOUND_US = 80


def check_stepper_timed_loop(env):
    elf = os.path.join(env.source_dir, "build", "emu", "timed", "LeibRampStepper", "LeibRampStepper.ino.elf")
    if not os.path.isfile(elf):
        return CheckResult(False, "no timed-loop build", [f"{elf} is missing: make test builds it (tools/emu/emu.mk)"])
    # tick_hz is 1 MHz in this mode: one tick = 1 us
    return check_stepper(env, "LeibRampStepper", elf=elf, bound_ticks=STEPPER_LOOP_BOUND_US, mode="loop")


# The ramp tables a stepper sketch may link, by the algorithm its `?` names (lib/src/ramp.c's
# algorithm tables, lib/src/step_planner.c's halves): each algorithm's code is reached only through
# its table, so a table's symbol in the ELF says that algorithm's code is in the flash.
RAMP_TABLES = {"SIMPLISTIC_RAMP", "LEIB_RAMP", "EXACT_RAMP", "SIGMOID_RAMP", "EXACT_OPS", "LAB_OPS", "LEIB_OPS",
               "SIMPLISTIC_OPS", "SIGMOID_OPS", "SMOOTH_OPS", "Stepper::setSigmoid"}
RAMP_TABLES_OF = {"leib": {"LEIB_RAMP", "LEIB_OPS"},
                  "simplistic": {"SIMPLISTIC_RAMP", "SIMPLISTIC_OPS"},
                  "sigmoid": {"SIGMOID_RAMP", "SIGMOID_OPS", "Stepper::setSigmoid"},
                  "exact": {"EXACT_OPS"}}


def linked_symbols(elf):
    """the names of an ELF's symbols (avr-nm -C), a `.lto_priv.N` or `.part.N` suffix dropped"""
    out = subprocess.run(["avr-nm", "-C", elf], capture_output=True, text=True, check=True).stdout
    names = set()
    for line in out.splitlines():
        parts = line.split(None, 2)
        if len(parts) == 3:
            names.add(re.sub(r"(\.(lto_priv|part|constprop|isra)\.\d+)+$", "", parts[2].split("(")[0]))
    return names


def check_stepper_links_its_ramp(env, sketch):
    """a stepper sketch links its own ramp's code and no other's (the flash the others would take)"""
    algo = stepper_algo(env, sketch)
    if algo not in RAMP_TABLES_OF:
        return CheckResult(False, f"algo={algo}", [f"{sketch}: no expectation for algo={algo}"])
    have = linked_symbols(env.elf(sketch)) & RAMP_TABLES
    want = RAMP_TABLES_OF[algo]
    problems = [f"{sketch} (algo={algo}) links {t}" for t in sorted(have - want)]
    problems += [f"{sketch} (algo={algo}) does not link {t}: its own ramp's table" for t in sorted(want - have)]
    return CheckResult(not problems, f"algo={algo}: linked {', '.join(sorted(have))}", problems)


def check_stepper_bad_input(env, sketch):
    algo = stepper_algo(env, sketch)
    fast = STEPPER_FAST[ramp_shape(algo)]
    extra = [("target beyond int32", "send 99999999999"), ("target not whole", "send 12.5"),
             ("two targets", "send 10 20"), ("unknown parameter", "send set speed 5"),
             ("negative parameter", f"send set {fast[0][0]} -1"), ("parameter not a number", "send set v0 fast"),
             ("set without value", f"send set {fast[0][0]}"), ("? with an argument", "send ? now")]
    if ramp_shape(algo) == "trapezoid":
        extra += [("accel 0", "send set accel 0"), ("vmax above max_sps", "send set vmax 1000000")]
    # a new target and `set` while moving are accepted (check_stepper_motion); junk is not
    busy = [("junk while moving", "send ???"), ("stop with an argument", "send stop now"),
            ("set of no parameter", "send set speed 5")]
    tgt = STEPPER_BUSY_TARGET[ramp_shape(algo)]
    return check_bad_input(env, sketch, "pos", "", COMMON_BAD + extra,
                           while_busy=(f"send {tgt}", rf"^OK 0 {tgt}$", busy, rf"^DONE {tgt}$", 60000),
                           dynamic=("pos", "state"), pins=sketches.stepper_pins(env), step_total=tgt)


# The step engine at speed (make bench measures the whole ladder; this is its short, deterministic
# part): the benchmark's reference move at a rate within every sketch's limit, with a `?` during
# the move; all steps, no underrun, no late edge, every edge on its plan within 8 cycles except
# those meeting another interrupt (at most 3 %, each within STEPPER_OTHER_ISR_CYCLES).
ENGINE_RATE = {"exact": 80000, "leib": 7000, "simplistic": 12000, "sigmoid": 50000}


def check_engine_at_speed(env, sketch):
    sys.path.insert(0, os.path.join(env.source_dir, "tools", "bench"))
    import bench  # tools/bench/bench.py: the same measurement as `make bench`
    algo = stepper_algo(env, sketch)
    rate = ENGINE_RATE.get(algo, 10000)
    res = bench.run_one(env.elf(sketch), env.motionsim, sketch, algo, rate, sketches.stepper_pins(env))
    problems = list(res["problems"])
    if "vs_plan" not in res:
        return CheckResult(False, f"{algo} at {rate} steps/s", problems or ["no measurement"])
    summary = (f"{algo} at {rate:,} steps/s, {res['steps']:,} steps: worst edge vs plan {res['vs_plan']:+.2f} ticks, "
               f"{res['beyond8']} edges beyond 8 cycles (worst {res['worst_cycles']:.0f} cycles), "
               f"underruns {res['underruns']}, late {res['late']}"
               + (f", worst vs the closed form {res['vs_exact']:+.2f} ticks" if "vs_exact" in res else ""))
    if "vs_exact" in res and abs(res["vs_exact"]) * (F_CPU / 16e6) > STEPPER_OTHER_ISR_CYCLES:
        problems.append(f"an edge {res['vs_exact']:+.1f} ticks off the closed form")
    return CheckResult(not problems, summary, problems)


STOP_DONE_RE = "^DONE -?[0-9]+$"


def check_stepper_motion(env, sketch):
    """stop, ! and a new target while moving (the step engine's motion commands): each accepted move
    ends in exactly one DONE at the position the STEP pulses reach, a replaced move gets none, a
    stop decelerates (no reversal, fewer steps than the target), a halt makes no further step,
    stop/! while idle move nothing; DIR follows every reversal."""
    algo = stepper_algo(env, sketch)
    shape = ramp_shape(algo)
    fast = STEPPER_FAST[shape]
    s = ["wait ^READY [^ ]+$", "timeout 5000"]
    for k, v in fast:
        s += [f"send set {k} {v}", f"wait ^OK {k}="]
    s += ["mark stop", "send 5000", "wait ^OK 0 5000$", "run 400", "send stop", "wait ^OK stop$",
          "timeout 20000", f"wait {STOP_DONE_RE}", "timeout 5000", "send ?", "wait ^pos=",
          "mark retarget", "send 0", "wait ^OK -?[0-9]+ 0$", "run 300", "send 2000", "wait ^OK -?[0-9]+ 2000( \\(after DONE -?[0-9]+\\))?$",
          "timeout 20000", "wait ^DONE 2000$", "timeout 5000",
          "mark halt", "send 6000", "wait ^OK 2000 6000$", "run 300", "send !", "wait ^OK halt$",
          f"wait {STOP_DONE_RE}", "run 200", "send ?", "wait ^pos=",
          "mark idle", "send stop", "wait ^OK stop \\(not moving\\)$", "send !", "wait ^OK halt \\(not moving\\)$",
          "send ?", "wait ^pos=", "mark end"]
    log = emulog.run(env.elf(sketch), "\n".join(s) + "\n", pins=sketches.stepper_pins(env))
    problems = []
    fails_of(log, problems)
    rises = log.rising("STEP")
    dir_edges = log.pins.get("DIR", [])

    def position_at(cycle):
        pos = 0
        for c in rises:
            if c > cycle:
                break
            pos += 1 if log.level_before("DIR", c) == 1 else -1
        return pos

    marks = {m: log.mark(m) for m in ("stop", "retarget", "halt", "idle", "end")}
    if any(v is None for v in marks.values()):
        problems.append(f"the script did not reach every part: {[k for k, v in marks.items() if v is None]}")
        return CheckResult(False, "motion commands", problems)
    figures = []
    # stop: one DONE, where the pulses end, short of 5000, no reversal
    d = log.first(STOP_DONE_RE, marks["stop"], marks["retarget"])
    dones = log.lines_matching(r"^DONE ", marks["stop"], marks["retarget"])
    if d is None or len(dones) != 1:
        problems.append(f"stop: {len(dones)} DONE lines, want 1")
    else:
        p = int(d.text.split()[1])
        if not (0 < p < 5000) or position_at(d.cycle) != p:
            problems.append(f"stop: DONE {p}, pulses reach {position_at(d.cycle)} (want equal, between 0 and 5000)")
        if [c for c, _ in dir_edges if marks["stop"] < c < d.cycle and c > rises[0]]:
            problems.append("stop: DIR changed while stopping")
        figures.append(f"stop at {p}")
    # a new target while moving: the first move's DONE never comes, the second's once (unless every
    # step of the first was already queued: then the OK says "(after DONE <its target>)" and it comes)
    dones = log.lines_matching(r"^DONE ", marks["retarget"], marks["halt"])
    ok2 = log.first(r"^OK -?\d+ 2000", marks["retarget"], marks["halt"])
    after = re.search(r"\(after DONE (-?\d+)\)$", ok2.text) if ok2 else None
    want_dones = ([f"DONE {after.group(1)}"] if after else []) + ["DONE 2000"]
    if [x.text for x in dones] != want_dones:
        problems.append(f"new target while moving: DONE lines {[x.text for x in dones]}, want {want_dones}")
    elif position_at(dones[0].cycle) != 2000:
        problems.append(f"new target: pulses reach {position_at(dones[0].cycle)}, DONE says 2000")
    else:
        figures.append("0 replaced by 2000 while moving: one DONE 2000")
    # halt: DONE at once, no pulse after it
    d = log.first(STOP_DONE_RE, marks["halt"], marks["idle"])
    if d is None:
        problems.append("halt: no DONE")
    else:
        p = int(d.text.split()[1])
        after = [c for c in rises if d.cycle < c]
        if after:
            problems.append(f"halt: {len(after)} STEP pulses after DONE {p}")
        if position_at(d.cycle) != p:
            problems.append(f"halt: DONE {p}, pulses reach {position_at(d.cycle)}")
        figures.append(f"halt at {p}")
    # idle: nothing moves
    idle = [c for c in rises if marks["idle"] < c < marks["end"]]
    if idle:
        problems.append(f"stop/! while idle made {len(idle)} steps")
    summary = f"algo={algo}: " + "; ".join(figures) + f"; {len(rises)} STEP pulses in all"
    return CheckResult(not problems, summary, problems)


def check_back_to_back(env, sketch):
    """A move sent right after the previous one's DONE (within one wrap of Timer1, when its compare
    flag may still be clear): its first step must wait its whole first interval after the move is
    armed, as motionsim plans it, never fire at once or a timer wrap early; and at most 40 ms of
    planning later. The arming is after the DONE line, so DONE -> first step >= the interval."""
    import emulate  # tools/emu: the argument mapping `make emulate` uses
    s = ["wait ^READY [^ ]+$", "timeout 20000", "send ?", "wait ^pos=", "send 3", "wait ^OK 0 3$",
         "wait ^DONE 3$", "send 0", "wait ^OK 3 0$", "wait ^DONE 0$", "send 3", "wait ^OK 0 3$", "wait ^DONE 3$"]
    log = emulog.run(env.elf(sketch), "\n".join(s) + "\n", pins=sketches.stepper_pins(env))
    problems = []
    fails_of(log, problems)
    if problems:
        return CheckResult(False, "back-to-back moves", problems)
    q = emulog.query_fields(log.first("^pos=").text)
    cpt = F_CPU / float(q["tick_hz"])
    rises = log.rising("STEP")
    figures = []
    for k, (done, a, b) in enumerate(((log.first("^DONE 3$"), 3, 0), (log.first("^DONE 0$"), 0, 3))):
        r = subprocess.run([env.motionsim] + emulate.stepper_sim_args(q, a, b), stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            return CheckResult(False, "back-to-back moves", [f"motionsim: {r.stderr.strip()}"])
        first_ticks = int(float(r.stdout.splitlines()[1].split(",")[3]))
        nxt = [c for c in rises if c > done.cycle]
        if not nxt:
            problems.append(f"move {a} -> {b}: no step after DONE {a}")
            continue
        gap = (nxt[0] - done.cycle) / cpt
        if gap < first_ticks:
            problems.append(f"move {a} -> {b}: first step {gap:.0f} ticks after DONE {a}, before its first "
                            f"interval of {first_ticks} ticks")
        elif gap > first_ticks + 0.040 * float(q["tick_hz"]):
            problems.append(f"move {a} -> {b}: first step {gap:.0f} ticks after DONE {a}, more than 40 ms beyond "
                            f"its first interval of {first_ticks} ticks")
        figures.append(f"{a} -> {b}: first step {(gap - first_ticks) / float(q['tick_hz']) * 1e3:.1f} ms after "
                       f"DONE + its first interval ({first_ticks} ticks)")
    if len(rises) != 9:
        problems.append(f"{len(rises)} STEP pulses, want 9")
    return CheckResult(not problems, f"algo={q.get('algo')}: " + "; ".join(figures), problems)


# ----------------------------------------------------------------------------------------------
# The lab's moveOneStep() (the lab handout, step 11): in LeibRampStepper and SimplisticRampStepper
# DIR is written by the sketch's moveOneStep(), which the engine calls at a move's first step and
# at a reversal. The same sketch with its two direction lines replaced by `(void)direction;`
# (built by tools/emu/emu.mk into build/emu/nodir) must run the motor one way only: DIR never
# changes after READY, although the moves go both ways and every reply is the same.

DIR_HOOK_SKETCHES = ("LeibRampStepper", "SimplisticRampStepper")
DIR_HOOK_DONES = ["DONE 100", "DONE 40", "DONE -50", "DONE 0"]


def dir_hook_script():
    s = ["wait ^READY [^ ]+$", "timeout 20000", "send set vmax 400", "wait ^OK vmax=", "send set v0 50",
         "wait ^OK v0=", "send set accel 4000",
         "wait ^OK accel=", "send 100", "wait ^OK 0 100$", "wait ^DONE 100$", "send 40", "wait ^OK 100 40$",
         "wait ^DONE 40$",
         # a reversal while moving: toward 300, then -50 (decelerate, reverse: the C path's turn)
         "send 300", "wait ^OK 40 300$", "run 150", "send -50", "wait ^OK -?[0-9]+ -50", "wait ^DONE -50$",
         "send 0", "wait ^OK -50 0$", "wait ^DONE 0$", "mark end"]
    return "\n".join(s) + "\n"


def check_direction_hook(env, sketch):
    problems = []
    src = os.path.join(env.source_dir, "firmware", sketch, f"{sketch}.ino")
    var_src = os.path.join(env.source_dir, "build", "emu", "nodir-src", sketch, f"{sketch}.ino")
    var_elf = os.path.join(env.source_dir, "build", "emu", "nodir", sketch, f"{sketch}.ino.elf")
    if not os.path.isfile(var_elf) or not os.path.isfile(var_src):
        return CheckResult(False, "no variant build", [f"{var_elf} is missing: make test builds it (tools/emu/emu.mk)"])
    with open(src) as f:
        a = f.read().splitlines()
    with open(var_src) as f:
        b = f.read().splitlines()
    differ = [(x.strip(), y.strip()) for x, y in zip(a, b) if x != y]
    if len(a) != len(b) or len(differ) != 2 or not all("digitalWrite(dirPin" in x for x, _ in differ):
        problems.append(f"the variant should differ from {sketch}.ino in moveOneStep's two dirPin lines only; "
                        f"differing lines: {differ[:4]}")
    pins = sketches.stepper_pins(env)
    runs = {}
    for name, elf in (("sketch", env.elf(sketch)), ("without the two lines", var_elf)):
        log = emulog.run(elf, dir_hook_script(), pins=pins)
        fails_of(log, problems)
        ready = log.first("^READY ")
        end = log.mark("end")
        if ready is None or end is None:
            problems.append(f"{name}: the script did not finish")
            continue
        dones = [l.text for l in log.lines_matching("^DONE ", ready.cycle)]
        if dones != DIR_HOOK_DONES:
            problems.append(f"{name}: DONE lines {dones}, want {DIR_HOOK_DONES}")
        rises = [c for c in log.rising("STEP") if c > ready.cycle]
        signed = sum(1 if log.level_before("DIR", c) == 1 else -1 for c in rises)
        dir_changes = [c for c, _ in log.pins.get("DIR", []) if ready.cycle < c <= end]
        runs[name] = (len(rises), signed, len(dir_changes))
    if len(runs) == 2:
        (n1, s1, d1), (n2, s2, d2) = runs["sketch"], runs["without the two lines"]
        # the moves: 0 -> 100 -> 40 -> (toward 300) -> -50 -> 0, net zero, both ways
        if s1 != 0 or d1 < 3:
            problems.append(f"sketch: {n1} steps counted by DIR end at {s1} (want 0) with {d1} DIR changes (want >= 3)")
        if d2 != 0:
            problems.append(f"without the two lines: DIR changed {d2} times after READY: something else drives DIR")
        # the same moves and DONEs; where the move toward 300 turns may differ by a step or two (the
        # variant's hook is shorter, so its loop() runs a little differently), not more
        if abs(n2 - n1) > 4 or s2 != n2:
            problems.append(f"without the two lines: {n2} steps, {s2} of them forwards; want {n1} (within 4), "
                            "all forwards")
    summary = ", ".join(f"{k}: {v[0]} steps, net {v[1]:+d} by DIR, {v[2]} DIR changes" for k, v in runs.items())
    return CheckResult(not problems, summary or "not run", problems)


# ----------------------------------------------------------------------------------------------

# ----------------------------------------------------------------------------------------------
# lib's Arduino example (lib/examples/RampIntervals): a user's own sketch on MotionCore's ramp

EXAMPLE_ROW_RE = re.compile(r"^(\d+),(-?\d+),(-?\d+\.\d{3}),(\d+),(accel|cruise|decel)$")


def check_ramp_example(env):
    """The example prints the lab's Leib move 0 -> 50 at boot and a move to a target sent over
    serial; every step's interval (3 decimals) and whole ticks must equal motionsim ramp's, the
    handout's checkpoint (218.218, 188.528, 157.245 ticks) included."""
    elf = os.path.join(env.firmware_dir, "RampIntervals", "RampIntervals.ino.elf")
    if not os.path.isfile(elf):
        return CheckResult(False, "not built", [f"{elf} is missing: make test builds it (tools/build_firmware.sh)"])
    log = emulog.run(elf, "timeout 20000\nwait ^DONE$\nsend -20\nwait ^DONE$\n")
    problems = []
    fails_of(log, problems)
    moves, cur = [], None
    for l in log.rx:
        if l.text.startswith("move "):
            cur = []
            moves.append(cur)
        m = EXAMPLE_ROW_RE.match(l.text)
        if m and cur is not None:
            cur.append(m.groups())
    notes = []
    for (a, b), rows in zip(((0, 50), (50, -20)), moves + [[]] * 2):
        base = ["ramp", "--algo", "leib", "--from", str(a), "--to", str(b), "--v0", "1", "--vmax", "20", "--accel",
                "10", "--tick-hz", "1000"]
        exact = [r.split(",") for r in motionsim(env, *base)[0].splitlines()[1:] if r]
        whole = [r.split(",") for r in motionsim(env, *base, "--integer-ticks")[0].splitlines()[1:] if r]
        if len(rows) != abs(b - a) or len(exact) != len(rows):
            problems.append(f"move {a} -> {b}: {len(rows)} step lines printed, motionsim plans {len(exact)}")
            continue
        bad = [(r, e[3], w[3]) for r, e, w in zip(rows, exact, whole)
               if r[1] != e[1] or abs(float(r[2]) - float(e[3])) > 0.0005 + 1e-9 or int(r[3]) != int(float(w[3]))]
        if bad:
            problems.append(f"move {a} -> {b}: {len(bad)} of {len(rows)} steps differ from motionsim ramp, first: "
                            f"printed {','.join(bad[0][0])}, motionsim interval {bad[0][1]} whole {bad[0][2]}")
        notes.append(f"{a} -> {b}: {len(rows)} steps, first intervals {', '.join(r[2] for r in rows[:3])} ticks")
    if len(moves) < 2:
        problems.append(f"{len(moves)} of 2 moves printed")
    return CheckResult(not problems, "; ".join(notes) + " == motionsim ramp --algo leib", problems)


def checks_for(env):
    """The checks of every sketch under firmware/, chosen by its family (the marker line of its
    .ino, tools/emu/sketches.py); the expectations that differ within a family come from the
    sketch's own `?` reply (the stepper's algo, the servo's gains), not from its name."""
    checks = []
    names = env.sketch_names()
    family, problems = {}, []
    for n in names:
        try:
            family[n] = env.family(n)
        except sketches.SketchError as e:
            problems.append(str(e))

    def every_sketch_known():
        return CheckResult(not problems, "sketches: " + (", ".join(f"{n} ({family[n]})" for n in family) or "none"),
                           problems)
    checks.append(("emulator: every sketch under firmware/ names its family (// motion-sketch: ...)",
                   every_sketch_known))
    for st in (n for n in names if family.get(n) == "stepper"):
        checks.append((f"{st}: 0->50, long and negative moves: steps, DIR, intervals == motionsim ramp",
                       lambda st=st: check_stepper(env, st)))
        checks.append((f"{st}: bad input, also while moving, gets ERR, state unchanged",
                       lambda st=st: check_stepper_bad_input(env, st)))
        checks.append((f"{st}: links its own ramp's code (lib's ramp and planner tables) and no other ramp's",
                       lambda st=st: check_stepper_links_its_ramp(env, st)))
        checks.append((f"{st}: stop, ! and a new target while moving: one DONE per move, where the pulses end",
                       lambda st=st: check_stepper_motion(env, st)))
        checks.append((f"{st}: the step engine at speed: the reference move, every edge on its plan",
                       lambda st=st: check_engine_at_speed(env, st)))
        checks.append((f"{st}: a move right after the last one's DONE waits its whole first interval",
                       lambda st=st: check_back_to_back(env, st)))
    for st in (n for n in DIR_HOOK_SKETCHES if family.get(n) == "stepper"):
        checks.append((f"{st}: DIR is moveOneStep()'s: with its two dirPin lines deleted DIR never changes, the "
                       "motor runs one way", lambda st=st: check_direction_hook(env, st)))
    # the timed-loop build (tools/emu/emu.mk) is of the lab's Leib sketch only: one build of the mode
    if family.get("LeibRampStepper") == "stepper":
        checks.append(("LeibRampStepper built with STEPPER_TIMED_LOOP=1: moves, intervals == motionsim ramp within "
                       f"{STEPPER_LOOP_BOUND_US} us", lambda: check_stepper_timed_loop(env)))
    for f in (n for n in names if family.get(n) == "filter"):
        checks.append((f"{f}: 60 s at 100 Hz, strobe timing, stream == motionsim filter, PWM == y",
                       lambda f=f: check_filter(env, f)))
        checks.append((f"{f}: ma2, exp, tau/tau2 changes, reset and every 10 == motionsim filter",
                       lambda f=f: check_filter_kinds(env, f)))
        checks.append((f"{f}: bad input gets ERR, state unchanged", lambda f=f: check_filter_bad_input(env, f)))
    for sv in (n for n in names if family.get(n) == "servo"):
        checks.append((f"{sv}: closes the loop on LS7366R + motor with its default gains, trace == motionsim servo",
                       lambda sv=sv: check_servo_defaults(env, sv)))
        checks.append((f"{sv}: gains set over serial (Kp for P; Kp, Ki, Kd for PID, as `?` shows) reach the "
                       "setpoint, trace == motionsim servo", lambda sv=sv: check_servo_tuned(env, sv)))
        checks.append((f"{sv}: bad input gets ERR, state unchanged", lambda sv=sv: check_servo_bad_input(env, sv)))
        checks.append((f"{sv}: move <counts>: the setpoint follows the filter-shaped move (== motionsim servo "
                       "--profile smooth), no ERR, trace == motionsim", lambda sv=sv: check_servo_move(env, sv)))
        checks.append((f"{sv}: bad move <counts> gets ERR, state unchanged",
                       lambda sv=sv: check_servo_move_bad_input(env, sv)))
    checks.append(("smooth_move on the AVR: the same step commands and servo setpoints as on the host, cycles per "
                   "call", lambda: check_smooth_move_avr(env)))
    if os.path.isfile(os.path.join(env.source_dir, "lib", "examples", "RampIntervals", "RampIntervals.ino")):
        checks.append(("lib/examples/RampIntervals (MotionCore in a user's sketch): printed step intervals == "
                       "motionsim ramp", lambda: check_ramp_example(env)))
    return checks
