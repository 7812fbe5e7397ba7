"""tools/fuzz/serial_fuzz.py - fuzz a sketch's serial console in the ATmega2560 emulator: one boot.

Kind "lines": a seeded random.Random makes lines of every kind a host could send: the sketch
family's commands with good, bad and edge numbers, mutations of them (bytes flipped, dropped,
doubled), random bytes (NUL, 0x80-0xff, control characters), lines over 40 characters, blank
lines of spaces and tabs, CR, LF and CR LF endings, sent one line per reply as docs/serial.md
tells a host (a blank line draws no reply, so the next one follows at once). The other kinds
(floods, fast moves, set while moving, MultiAxisStepper at speed) are fuzz_scenarios.py's. The
same seed gives the same lines.

run_chunk() runs one conversation in motionemu and checks it (fuzz_conversation.py: replies,
overrun accounting, values executed, STEP/DIR against OK/DONE/`?` per axis; fuzz_oracles.py:
speed continuity, vmax, reversals, edge latency; underruns=/late= in every `?`).
"""
import os
import random
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))
sys.path.insert(0, HERE)

import emulog  # noqa: E402
import fuzz_conversation  # noqa: E402
import fuzz_scenarios  # noqa: E402
import sketches  # noqa: E402

MAX_LINE = 90   # longest line sent (over the 40-character limit, well under the 63-byte buffer + reading)

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




def run_chunk(env, sketch, seed, n_lines, kind="lines", lim=None, log_path=None):
    """Fuzz one fresh boot of `sketch` with n_lines lines of `kind` (random "lines", or one of
    fuzz_scenarios.KINDS) and seed `seed`; returns (Outcome, items, script text). lim: the
    sketch's fuzz_scenarios.Limits (probed if None and needed)."""
    family = env.family(sketch)
    if kind == "lines":
        items = [("line", line, end, None) for line, end in make_lines(seed, family, n_lines, sketch)]
    else:
        if lim is None:
            lim = fuzz_scenarios.Limits.probe(env, sketch)
        rng = random.Random(f"{seed}:{sketch}:{kind}")
        items = fuzz_scenarios.KINDS[kind](rng, family, lim, n_lines)
    if lim is None and family in ("stepper", "multiaxis"):
        lim = fuzz_scenarios.Limits.probe(env, sketch)
    items = fuzz_conversation.with_ending(items, family)
    script = fuzz_conversation.script_for(items, family)
    kw = sketches.harness_args(env, sketch)
    pins = dict(kw.get("pins", {}))
    extra = []
    if family == "stepper":
        pins = {k: v for k, v in pins.items() if k in ("STEP", "DIR")}  # only what the checks read
    if family in ("stepper", "multiaxis"):
        extra = ["--matches"]   # the compare matches: the planned time of each STEP edge
    log = emulog.run(env.elf(sketch), script, pins=pins, motor=kw.get("motor"), extra=extra,
                     max_ms=10 ** 8, log_path=log_path, timeout=3600)
    return fuzz_conversation.check(log, family, items, lim), items, script
