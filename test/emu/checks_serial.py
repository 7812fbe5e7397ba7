"""The serial line rules every sketch follows (docs/serial.md), checked on the emulated ATmega2560.
The expectations are the documented rules, not recordings of the firmware:

- a blank line (empty, or only spaces and tabs, any length) is no line: no reply at all, on every
  sketch (the rule lives in lib/src/line_reader.c, which every console reads through
  MotionSerial, so the stepper sketches follow it without code of their own);
- input overrun (every sketch): a host that sends faster than the sketch reads fills its input
  (SerialRx's 128-byte ring); the lines hit are answered `ERR input overrun: N line(s) lost` and
  never executed, no half line is ever taken for a command, every line sent is answered or counted
  in such a reply, and afterwards the sketch answers again.
"""
import re

import emulog
import sketches
from checks_selftest import CheckResult
from emulog import F_CPU

# the `?` reply's first key per family
QUERY_KEY = {"stepper": "pos", "servo": "setpoint", "filter": "kind", "multiaxis": "z pos"}  # multiaxis: the last of its three lines


def fails_of(log, problems):
    for c, k, t in log.fails:
        problems.append(f"harness: {k} at {c / F_CPU:.4f} s: {t}")


def run_kwargs(env, sketch):
    fam = env.family(sketch)
    if fam == "servo":
        return {"motor": sketches.servo_motor_spec(env, sketch)}
    if fam == "filter":
        return {"pins": sketches.filter_pins(env)}
    return {}


BLANK_LINES = ["send", "send    ", "send \\t \\t", "raw \\r\\r\\n", "repeat 100 \\x20", "raw \\r\\n"]


def check_blank_lines(env, sketch):
    key = QUERY_KEY[env.family(sketch)]
    # any banner: a renamed copy may keep its original's (docs/emulator.md)
    script = "\n".join(["wait ^READY [^ ]+$", "timeout 3000", "send ?", f"wait ^{key}=", "mark blank"]
                       + BLANK_LINES + ["mark blank-end", "send ?", f"wait ^{key}="]) + "\n"
    log = emulog.run(env.elf(sketch), script, **run_kwargs(env, sketch))
    problems = []
    fails_of(log, problems)
    start, end = log.mark("blank"), log.mark("blank-end")
    if start is None or end is None:
        problems.append("the script did not run")
        return CheckResult(False, "did not run", problems)
    after = log.first(r"^" + key + "=", end)
    replies = [l for l in log.lines_matching(r"^(OK|ERR|DONE|WARN|" + key + "=)", start, after.cycle if after else None)]
    if replies:
        problems.append(f"blank lines drew replies: {[r.text for r in replies]}")
    if after is None:
        problems.append("no `?` reply after the blank lines")
    return CheckResult(not problems, f"{len(BLANK_LINES)} blank lines (empty, spaces, tabs, 100 spaces) -> "
                       f"{len(replies)} replies; `?` after them answered", problems)


# A burst far faster than a sketch reads: every `?` draws a reply of about 100 bytes (9600 baud; the
# filter's 115200 with its stream), so the sketch stops reading while it writes (the servo sketches:
# their output queue is full, back-pressure) and the receive buffer overflows. Between the `?`
# lines one command whose every shortened form is another command or an error: setpoint 12345,
# `set vmax 1234`, `u 1.234`. Per family: (command, its OK reply, the `?` reply's first key, what
# the `?` reply then says, lines that are neither: the servo status line, the filter's stream).
FLOOD_LINES = 24
OVERRUN = {
    "servo": ("12345", "OK setpoint=12345", "setpoint=", "setpoint=12345 ", re.compile(r"^t_ms=")),
    "stepper": ("set vmax 1234", "OK vmax=1234", "pos=", " vmax=1234 ", None),  # vmax: fmax on SCurveStepper
    "filter": ("u 1.234", "OK u=1.234", "kind=", " u=1.234 ", re.compile(r"^\d+,")),
    # three state lines per `?` (x, y, z): the first names the value set
    "multiaxis": ("set x vmax 1234", "OK x vmax=1234", "x pos=", " vmax=1234 ", re.compile(r"^[yz] pos=")),
}


def check_overrun(env, sketch):
    fam = env.family(sketch)
    cmd, ok_reply, key, state_after, other_lines = OVERRUN[fam]
    script = "\n".join([
        "wait ^READY [^ ]+$", "timeout 3000", "send ?", f"wait ^{key}", "run 500", "mark flood",
        f"repeat {FLOOD_LINES // 2} ?\\r\\n{cmd}\\r\\n", "drain", "run 8000", "mark flood-end",
        "send ?", "run 1000", "mark sync", "send ?", "run 1000",
    ]) + "\n"
    log = emulog.run(env.elf(sketch), script, **run_kwargs(env, sketch))
    problems = []
    fails_of(log, problems)
    start, end, sync = log.mark("flood"), log.mark("flood-end"), log.mark("sync")
    if start is None or end is None or sync is None:
        return CheckResult(False, "did not run", problems + ["the script did not run"])

    def replies(after, before=None):
        return [l.text for l in log.lines_matching(r".", after, before)
                if other_lines is None or not other_lines.match(l.text)]
    lines = replies(start, sync)
    overruns = [t for t in lines if re.match(r"^ERR input overrun: \d+ lines? lost$", t)]
    states = [t for t in lines if t.startswith(key)]
    oks = [t for t in lines if t.startswith("OK")]
    other = [t for t in lines if t not in overruns and t not in states and t not in oks]
    # (a sketch whose input keeps up with the burst has nothing to report: the servo sketches' ring
    # holds it; the accounting below holds either way, and checks_reliability's longer flood always
    # overflows)
    bad_ok = [t for t in oks if t != ok_reply]
    if bad_ok:
        problems.append(f"half lines were executed: {bad_ok}")
    if other:
        problems.append(f"replies other than the state line, {ok_reply} and ERR input overrun: {other}")
    counted = sum(int(t.split()[3]) for t in overruns)  # "ERR input overrun: N line(s) lost"
    if len(states) + len(oks) + counted != FLOOD_LINES + 1:  # the burst and the `?` after it
        problems.append(f"{len(states) + len(oks)} replies + {counted} lines counted lost, want the "
                        f"{FLOOD_LINES + 1} sent")
    after = replies(sync)
    if len(after) != 1 or not after[0].startswith(key):
        problems.append(f"the `?` after the burst drew {after}, want one state line")
    elif oks and state_after not in after[0] + " ":
        problems.append(f"after {ok_reply} the state says {after[0]}")
    summary = (f"{FLOOD_LINES} lines in one burst and one `?` after it: {len(states)} `?` replies, {len(oks)} "
               f"{ok_reply}, {len(overruns)} ERR input overrun, {FLOOD_LINES + 1 - len(lines)} lines lost whole, "
               f"{len(other) + len(bad_ok)} wrong; the next `?` answered")
    return CheckResult(not problems, summary, problems)


# issue 12 item 7: one rule for tau under every kind (at most the moving-average buffer), so that
# any kind can follow; before, `tau 100` was taken under exp and `kind ma` refused after it.
FILTER_TAU_SCRIPT = """\
wait ^READY [^ ]+$
timeout 3000
send kind exp
wait ^OK kind=exp$
mark tau
send tau 100
wait ^(OK|ERR)
send tau 20.01
wait ^(OK|ERR)
send tau 20
wait ^(OK|ERR)
send kind ma
wait ^(OK|ERR)
send ?
wait ^kind=
"""


def check_filter_tau_rule(env):
    log = emulog.run(env.elf("MovingAverageFilter"), FILTER_TAU_SCRIPT, pins=sketches.filter_pins(env))
    problems = []
    fails_of(log, problems)
    start = log.mark("tau")
    got = [l.text for l in log.lines_matching(r"^(OK|ERR|kind=)", start or 0)]
    want = [r"^ERR tau/Ts needs more taps than the buffer holds: tau and tau2 at most 20\.00 s each under every "
            r"kind \(ma2: tau \+ tau2\)$"] * 2 + [r"^OK tau=20\.00$", r"^OK kind=ma$", r"^kind=ma tau=20\.00 "]
    if len(got) != len(want) or not all(re.match(w, g) for w, g in zip(want, got)):
        problems.append(f"replies {got}, want {want}")
    return CheckResult(not problems, f"under exp: tau 100 and 20.01 refused, tau 20 then kind ma accepted: {got}",
                       problems)


# issue 22 item 4: a target is any number word whose value is whole (docs/serial.md), evaluated
# exactly on the board; a fraction and an overflow get their own ERR and change nothing.
TARGET_WORDS_SCRIPT = """\
wait ^READY [^ ]+$
timeout 10000
send ?
wait ^pos=
mark words
send 1e3
wait ^DONE
send 1.5
wait ^ERR
send 1e999
wait ^ERR
send ?
wait ^pos=
send 2.147483583e9
wait ^OK
send !
wait ^DONE
"""


def check_target_number_words(env, sketch="ExactRampStepper"):
    log = emulog.run(env.elf(sketch), TARGET_WORDS_SCRIPT)
    problems = []
    fails_of(log, problems)
    start = log.mark("words")
    if start is None:
        return CheckResult(False, "did not run", problems + ["the script did not run"])
    got = [l.text for l in log.lines_matching(r"^(OK|ERR|DONE|pos=)", start)]
    # 2147483583 = 2^31 - 65: no 32-bit float holds it (its neighbours are 2147483520 and 2147483648)
    want = [r"^OK 0 1000$", r"^DONE 1000$",
            r"^ERR [^:]+: a target is a whole number of steps",
            r"^ERR number out of range: .*-2147483648\.\.2147483647$",
            r"^pos=1000 target=1000 state=idle ",
            r"^OK 1000 2147483583$", r"^OK halt$", r"^DONE \d+$"]
    if len(got) != len(want) or not all(re.match(w, g) for w, g in zip(want, got)):
        problems.append(f"replies {got}, want {want}")
    return CheckResult(not problems, f"1e3, 1.5, 1e999, ?, 2.147483583e9, !: {got}", problems)


def checks_for(env):
    checks = []
    names = env.sketch_names()
    for s in names:
        try:
            env.family(s)
        except sketches.SketchError:
            continue  # checks_sketches reports a sketch without its marker
        if True:
            checks.append((f"{s}: blank lines (spaces, tabs, empty) get no reply (docs/serial.md)",
                           lambda s=s: check_blank_lines(env, s)))
    if "MovingAverageFilter" in names:
        checks.append(("MovingAverageFilter: tau is limited by the buffer under every kind, so kind ma works after exp",
                       lambda: check_filter_tau_rule(env)))
    if "ExactRampStepper" in names:
        checks.append(("ExactRampStepper: a target 1e3 moves to 1000; 1.5 and 1e999 get their own ERR and change "
                       "nothing; 2.147483583e9 is exact", lambda: check_target_number_words(env)))
    for s in names:
        try:
            env.family(s)
        except sketches.SketchError:
            continue
        checks.append((f"{s}: a burst that overflows the receive buffer gets ERR input overrun, no half line "
                       "is executed", lambda s=s: check_overrun(env, s)))
    return checks
