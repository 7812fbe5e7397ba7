"""tools/fuzz/serial_fuzz.py - fuzz a sketch's serial console in the ATmega2560 emulator.

A seeded random.Random makes lines of every kind a host could send: the sketch family's commands
with good, bad and edge numbers, mutations of them (bytes flipped, dropped, doubled), random
bytes (NUL, 0x80-0xff, control characters), lines over 40 characters, blank lines of spaces and
tabs, CR, LF and CR LF endings. They are sent the way docs/serial.md tells a host to: the next
line when the reply to the previous one has arrived (a blank line draws no reply, so the next one
follows at once). The same seed gives the same lines.

The properties (docs/serial.md, README's protocol table), checked on motionemu's event log:
  - no reset, crash, halt or stack overflow (motionemu's "fail" events), no hang: every reply
    arrives within REPLY_TIMEOUT_MS;
  - every non-blank line gets exactly one reply (OK ..., ERR ..., the `?` state line), a blank
    line none; nothing else is printed but the family's own unsolicited lines (a stepper's
    DONE, a servo's once-a-second t_ms= status, the filter's t_ms,u,y stream);
  - stepper: no STEP pulse unless a move was accepted ("OK <from> <to>") and its DONE has not
    come yet; every accepted move (and every stop/! of a moving axis) is followed by a DONE;
    no DONE without a move; the position counted from STEP/DIR equals every DONE <pos>.
"""
import os
import random
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))

import emulog  # noqa: E402
import sketches  # noqa: E402

REPLY_TIMEOUT_MS = 5000
STEPPER_BAUD = 9600   # StepperConsole::begin
MAX_LINE = 90   # longest line sent (over the 40-character limit, well under the 63-byte buffer + reading)

REPLY_RE = {
    "stepper": r"^(OK|ERR|pos=)",
    "servo": r"^(OK|ERR|setpoint=)",
    "filter": r"^(OK|ERR|kind=)",
    "multiaxis": r"^(OK|ERR|z pos=)",  # `?`: its last line
}
# lines a sketch prints without being asked
ASYNC_RE = {
    "stepper": re.compile(r"^DONE -?\d+$"),
    "servo": re.compile(r"^t_ms=\d+ "),
    "filter": re.compile(r"^(t_ms,u,y|\d+,-?\d+\.\d+,-?\d+\.\d+)$"),
    # a DONE of one axis or of a coordinated move; the `?` reply's lines before its last (z)
    "multiaxis": re.compile(r"^(DONE [xyz] -?\d+|DONE move( [xyz] -?\d+)+|[xy] pos=-?\d+ .*)$"),
}

# ---- the lines -------------------------------------------------------------------------------

EDGE_NUMBERS = ["0", "-0", "+0", "1", "-1", "+1", "00012", "1.", ".5", "-.5", "1e", "1e3", "1E3", "1e+3", "1e-3",
                "0x10", "0b1", "nan", "NaN", "inf", "-inf", "infinity", "1e-46", "1e-400", "1e38", "3.5e38", "1e400",
                "2147483647", "2147483648", "-2147483648", "-2147483649", "4294967296",
                "99999999999999999999999", "0.000000000000000000000000000000000000000000001",
                "5000", "5000.0001", "4999.9999", "1000", "1000.00001", "10000000", "10000000.1", "5", "5.0000001",
                "20", "20.01", "19.99", "1000000", "1000001", "-1000000", "-1000001", "1..2", "--1", "+-1", "1-",
                "1e1e1", "1,5", "12abc", "abc", "", " "]
JUNK_WORDS = ["?", "??", "!", "!!", "stop", "STOP", "Stop", "set", "SET", "reset", "a0", "cost", "kind", "tau", "tau2",
              "u", "every", "kp", "ki", "kd", "v0", "vmax", "accel", "flex", "len", "hold", "ma", "ma2", "exp",
              "help", "OK", "ERR", "DONE", "READY", "x", "-", "+", "=", "#", "\\", "\"", ";", "*", "%s", "%n", "%%"]
BLANKS = " \t"


def rand_number(rng):
    r = rng.random()
    if r < 0.35:
        return rng.choice(EDGE_NUMBERS)
    if r < 0.6:
        return str(rng.randint(-300, 300))
    if r < 0.75:
        return f"{rng.uniform(-100, 10000):.{rng.randint(0, 7)}f}"
    if r < 0.85:
        return f"{rng.uniform(-10, 10):.3g}e{rng.randint(-50, 50)}"
    if r < 0.95:
        return str(rng.randint(-2**33, 2**33))
    return "".join(rng.choice("0123456789.-+eE") for _ in range(rng.randint(1, 12)))


STEPPER_KEYS = ["v0", "vmax", "accel", "flex", "len", "hold"]
SERVO_KEYS = ["kp", "ki", "kd"]
FILTER_KINDS = ["ma", "ma2", "exp", "MA", "ma3", "", "expo"]


def stepper_command(rng, st):
    r = rng.random()
    if r < 0.30:
        # small moves around the position, so that moves end and new ones start (targets while
        # moving are accepted: the planner replans)
        return str(st["pos_guess"] + rng.randint(-40, 40)) if rng.random() < 0.8 else rand_number(rng)
    if r < 0.42:
        return rng.choice(["stop", "!"])
    if r < 0.52:
        return "?"
    key = rng.choice(STEPPER_KEYS)
    if rng.random() < 0.5:  # plausible values, so that set commands are accepted and moves differ
        val = {"v0": rng.choice(["0", "1", "5", "50", "200"]), "vmax": rng.choice(["20", "100", "400", "1000", "4000"]),
               "accel": rng.choice(["10", "100", "1000", "5000"]), "flex": rng.choice(["1", "5", "8"]),
               "len": rng.choice(["50", "250", "1000"]), "hold": rng.choice(["1", "4", "10"])}[key]
    else:
        val = rand_number(rng)
    return f"set {key} {val}"


def servo_command(rng, st):
    r = rng.random()
    if r < 0.4:
        return rand_number(rng) if rng.random() < 0.5 else str(rng.randint(-5000, 5000))
    if r < 0.55:
        return "?"
    key = rng.choice(SERVO_KEYS)
    val = rng.choice(["0", "0.02", "0.1", "1", "0.001"]) if rng.random() < 0.4 else rand_number(rng)
    return f"{key} {val}"


def filter_command(rng, st):
    r = rng.random()
    if r < 0.15:
        return "?"
    if r < 0.3:
        return f"u {rand_number(rng) if rng.random() < 0.5 else f'{rng.uniform(0, 5):.3f}'}"
    if r < 0.4:
        return f"kind {rng.choice(FILTER_KINDS)}"
    if r < 0.55:
        return f"{rng.choice(['tau', 'tau2'])} {rng.choice(['0.5', '1', '3', '9', '20']) if rng.random() < 0.4 else rand_number(rng)}"
    if r < 0.65:
        return rng.choice(["reset", "a0", "cost"])
    # mostly slow streams: a line every 0.1-10 s keeps the port free for the replies
    return f"every {rng.choice(['10', '100', '1000', '50']) if rng.random() < 0.7 else rand_number(rng)}"


def multiaxis_command(rng, st):
    r = rng.random()
    ax = rng.choice("xyz")
    if r < 0.25:
        return f"{ax} {rng.randint(-60, 60) if rng.random() < 0.8 else rand_number(rng)}"
    if r < 0.4:
        words = [f"{a}{rng.randint(-60, 60) if rng.random() < 0.85 else rand_number(rng)}"
                 for a in rng.sample("xyz", rng.randint(0, 3))]
        return " ".join(["move"] + words)
    if r < 0.52:
        return rng.choice(["stop", "!", f"stop {ax}", f"! {ax}", "stop q"])
    if r < 0.6:
        return "?"
    key = rng.choice(["v0", "vmax", "accel"])
    val = {"v0": rng.choice(["0", "5", "50"]), "vmax": rng.choice(["100", "1000", "4000"]),
           "accel": rng.choice(["100", "1000", "5000"])}[key] if rng.random() < 0.5 else rand_number(rng)
    return f"set {ax if rng.random() < 0.9 else 'w'} {key} {val}"


COMMANDS = {"stepper": stepper_command, "servo": servo_command, "filter": filter_command,
            "multiaxis": multiaxis_command}


def mutate(rng, text):
    b = bytearray(text.encode("latin-1"))
    for _ in range(rng.randint(1, 3)):
        op = rng.random()
        pos = rng.randint(0, len(b))
        if op < 0.3 and b:
            del b[min(pos, len(b) - 1)]
        elif op < 0.55:
            b[pos:pos] = bytes([rng.choice(b" \t0123456789.-+eExX?!abcdefghijklmnopqrstuvwxyz")])
        elif op < 0.7 and b:
            i = min(pos, len(b) - 1)
            b[i] ^= 1 << rng.randint(0, 7)
        elif op < 0.85 and b:
            i = min(pos, len(b) - 1)
            b[i:i] = b[i:i + rng.randint(1, 6)]
        else:
            b[pos:pos] = rng.choice(JUNK_WORDS).encode("latin-1")
    return bytes(b)


def random_bytes(rng, n):
    out = bytearray()
    for _ in range(n):
        c = rng.randint(0, 255) if rng.random() < 0.3 else rng.randint(0x20, 0x7e)
        out.append(c)
    return bytes(out)


def make_line(rng, family, st):
    """bytes of one line (no CR or LF inside)"""
    r = rng.random()
    if r < 0.45:
        line = COMMANDS[family](rng, st).encode("latin-1")
    elif r < 0.70:
        line = mutate(rng, COMMANDS[family](rng, st))
    elif r < 0.78:
        line = random_bytes(rng, rng.randint(1, 20))
    elif r < 0.83:
        line = "".join(rng.choice(BLANKS) for _ in range(rng.randint(0, 50))).encode()
    elif r < 0.90:
        words = [rng.choice(JUNK_WORDS + EDGE_NUMBERS) for _ in range(rng.randint(1, 6))]
        line = " ".join(words).encode("latin-1")
    elif r < 0.95:  # over the 40-character limit, or just at it
        n = rng.choice([39, 40, 41, 42, rng.randint(43, MAX_LINE)])
        base = COMMANDS[family](rng, st).encode("latin-1")
        line = (base + b" " + random_bytes(rng, MAX_LINE))[:n] if rng.random() < 0.5 else bytes(
            rng.choice(b"0123456789 ") for _ in range(n))
    else:  # leading / trailing blanks around a command
        c = COMMANDS[family](rng, st).encode("latin-1")
        lead = "".join(rng.choice(BLANKS) for _ in range(rng.randint(0, 45))).encode()
        trail = "".join(rng.choice(BLANKS) for _ in range(rng.randint(0, 5))).encode()
        line = lead + c + trail
    line = line.replace(b"\r", b"").replace(b"\n", b"")
    return line[:MAX_LINE]


def is_blank(line):
    return all(c in b" \t" for c in line)


def escape(b):
    """bytes -> the INPUT script's text escapes"""
    out = []
    for c in b:
        if c == 0x5C:
            out.append("\\\\")
        elif 0x21 <= c <= 0x7E or (c == 0x20):
            out.append(chr(c))
        else:
            out.append(f"\\x{c:02x}")
    return "".join(out)


def make_lines(seed, family, n, sketch=""):
    rng = random.Random(f"{seed}:{sketch or family}")
    st = {"pos_guess": 0}
    lines = []
    for _ in range(n):
        line = make_line(rng, family, st)
        m = re.fullmatch(rb"\s*(-?\d{1,6})\s*", line)
        if family == "stepper" and m:
            st["pos_guess"] = int(m.group(1))
        end = rng.choices([b"\r\n", b"\n", b"\r"], [0.7, 0.15, 0.15])[0]
        lines.append((line, end))
    return lines


def script_for(sketch, family, lines):
    """The INPUT script: READY, then each line and (unless blank) a wait for its reply; at the end
    a stepper is halted so that a move in progress reports its DONE."""
    rx = REPLY_RE[family]
    s = ["wait ^READY [^ ]+$", f"timeout {REPLY_TIMEOUT_MS}", "mark fuzz"]
    for line, end in lines:
        s.append("raw " + escape(line + end) if line + end else "send")
        if not is_blank(line):
            s.append(f"wait {rx}")
    s.append("mark fuzz-end")
    if family in ("stepper", "multiaxis"):
        s += ["send !", "wait ^OK halt", "run 300"]
    else:
        s += ["run 200"]
    return "\n".join(s) + "\n"


# ---- the checks ------------------------------------------------------------------------------

class Outcome:
    def __init__(self):
        self.lines = 0
        self.replies = 0
        self.blank = 0
        self.accepted_moves = 0
        self.done = 0
        self.steps = 0
        self.problems = []   # one sentence each
        self.first_bad_line = None  # index of the first line a problem was found at

    def bad(self, text, index=None):
        self.problems.append(text)
        if index is not None and (self.first_bad_line is None or index < self.first_bad_line):
            self.first_bad_line = index


def check_log(log, family, lines, env=None):
    o = Outcome()
    o.lines = len(lines)
    for c, k, t in log.fails:
        if k == "timeout":
            o.bad(f"hang: {t} (at {c / emulog.F_CPU:.3f} s)")
        else:
            o.bad(f"{k} at {c / emulog.F_CPU:.3f} s: {t}")
    if log.end.get("reason") not in ("done",):
        o.bad(f"the emulation ended '{log.end.get('reason')}' (rc {log.rc}): {log.stderr.strip()[:300]}")
    start = log.mark("fuzz")
    end = log.mark("fuzz-end")
    if start is None:
        o.bad("the sketch never said READY")
        return o
    sends = [t for t in log.tx if t.cycle >= start][:len(lines)]
    if len(sends) != len(lines) and end is not None:
        o.bad(f"{len(sends)} lines sent of {len(lines)}")
    async_re = ASYNC_RE[family]
    reply_re = re.compile(REPLY_RE[family])
    replies = []   # (cycle, text)
    asyncs = []
    for l in log.rx:
        if l.cycle < start:
            continue
        if async_re.match(l.text):
            asyncs.append(l)
        elif reply_re.match(l.text):
            replies.append(l)
        else:
            o.bad(f"an unexpected line from the sketch: {l.text!r} at {l.t_s:.3f} s")
    fuzz_replies = replies[:]
    # Map replies onto lines: the replies to line i come before line i+1 is sent (the host waits)
    tx_cycles = [t.cycle for t in sends]
    per_line = [[] for _ in sends]
    j = 0
    for i, c0 in enumerate(tx_cycles):
        c1 = tx_cycles[i + 1] if i + 1 < len(tx_cycles) else (end if end is not None else float("inf"))
        while j < len(fuzz_replies) and fuzz_replies[j].cycle < c0:
            j += 1
        while j < len(fuzz_replies) and fuzz_replies[j].cycle < c1:
            per_line[i].append(fuzz_replies[j])
            j += 1
    o.replies = sum(len(p) for p in per_line)
    for i, (line, endb) in enumerate(lines[:len(sends)]):
        want = 0 if is_blank(line) else 1
        o.blank += want == 0
        got = per_line[i]
        if len(got) != want:
            o.bad(f"line {i + 1} {line + endb!r} drew {len(got)} replies, want {want}: {[g.text for g in got]}", i)
        for g in got:
            if g.text == "ERR input overrun":
                o.bad(f"line {i + 1} {line!r}: ERR input overrun although the host sent one line per reply", i)
    if family == "stepper":
        check_steps(log, lines, sends, per_line, asyncs, o)
    return o


def check_steps(log, lines, sends, per_line, asyncs, o):
    """STEP pulses only inside [a line accepted as a move was sent, its DONE]; DONE only after a
    move; the pin-counted position at each DONE equals it. The firmware's lines are taken in the
    order it printed them (a DONE printed just before the OK of the next move belongs to the
    move before)."""
    ok_move = re.compile(r"^OK (-?\d+) (-?\d+)( \(after DONE -?\d+\))?$")
    line_of = {}
    for i, got in enumerate(per_line):
        for r in got:
            line_of[id(r)] = i
    seq = sorted([(r.cycle, r) for got in per_line for r in got] + [(l.cycle, l) for l in asyncs],
                 key=lambda e: e[0])
    windows = []
    done_at = []
    # the moves open (their targets): a target while moving replaces the move, except when every
    # step of it is already queued (docs/stepper-engine.md): then the reply ends "(after DONE
    # <from>)", the move keeps its DONE and the new one follows it; stop and ! drop a waiting move
    open_moves = []
    open_at = open_line = None
    for c, l in seq:
        if l.text.startswith("DONE"):
            p = int(l.text.split()[1])
            done_at.append((c, p))
            if not open_moves:
                o.bad(f"DONE {p} at {c / emulog.F_CPU:.3f} s without a move in progress")
            else:
                windows.append((open_at, c))
                open_moves.pop(0)
                open_at = c if open_moves else None
            continue
        i = line_of[id(l)]
        m = ok_move.match(l.text)
        if m:
            o.accepted_moves += 1
            frm, to = int(m.group(1)), int(m.group(2))
            if not open_moves:
                open_moves = [to]
                open_at, open_line = sends[i].cycle, i
            elif m.group(3):
                if len(open_moves) == 1:
                    open_moves.append(to)
                else:
                    open_moves[-1] = to
            else:
                open_moves[-1] = to
        elif l.text in ("OK halt", "OK stop"):
            if not open_moves:
                o.bad(f"line {i + 1} {lines[i][0]!r} was answered {l.text!r} (stopping a move) while none was in "
                      "progress", i)
            del open_moves[1:]
    o.done = len(done_at)
    if open_moves:
        o.bad(f"the move accepted at line {open_line + 1} {lines[open_line][0]!r} never reported DONE "
              f"(not even after the final `!`)", open_line)
        windows.append((open_at, float("inf")))
    merged = []
    for a, b in sorted(windows):
        if merged and a <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], b)
        else:
            merged.append([a, b])
    edges = log.rising("STEP")
    o.steps = len(edges)
    wi = 0
    stray = []
    for c in edges:
        while wi < len(merged) and merged[wi][1] < c:
            wi += 1
        if wi >= len(merged) or c < merged[wi][0]:
            stray.append(c)
    if stray:
        o.bad(f"{len(stray)} STEP pulses with no move accepted, the first at {stray[0] / emulog.F_CPU:.4f} s")
    # The DONE line is printed when the move has ended, but it reaches the host after up to a full
    # transmit buffer (64 bytes) and itself: the next move's first steps may come before its last
    # byte. So DONE <p> is right if the axis was at p at some moment of that span.
    byte = emulog.F_CPU * 10 // STEPPER_BAUD
    pos_after = []   # (cycle, position after the edge)
    pos = 0
    for c in edges:
        pos += 1 if log.level_before("DIR", c) == 1 else -1
        pos_after.append((c, pos))
    k = 0
    for c, p in done_at:
        lo = c - (64 + len(f"DONE {p}") + 2) * byte
        at_lo = 0
        while k < len(pos_after) and pos_after[k][0] <= lo:
            k += 1
        at_lo = pos_after[k - 1][1] if k else 0
        seen = {at_lo} | {q for e, q in pos_after[k:] if e <= c}
        if p not in seen:
            o.bad(f"DONE {p} at {c / emulog.F_CPU:.3f} s, but STEP/DIR had the axis at {sorted(seen)} "
                  f"over the {64 + len(f'DONE {p}') + 2} byte times before it")
            break


def run_chunk(env, sketch, seed, n_lines, log_path=None):
    """Fuzz one fresh boot of `sketch` with n_lines lines of seed `seed`; returns
    (Outcome, lines, script text)."""
    family = env.family(sketch)
    lines = make_lines(seed, family, n_lines, sketch)
    script = script_for(sketch, family, lines)
    kw = sketches.harness_args(env, sketch)
    pins = dict(kw.get("pins", {}))
    if family == "stepper":
        pins = {k: v for k, v in pins.items() if k in ("STEP", "DIR")}  # only what the checks read
    log = emulog.run(env.elf(sketch), script, pins=pins, motor=kw.get("motor"),
                     max_ms=10 ** 8, log_path=log_path, timeout=3600)
    return check_log(log, family, lines), lines, script
