"""tools/fuzz/fuzz_scenarios.py - the fuzzer's conversations other than random lines (serial_fuzz.py):
what a host does to a sketch at speed. Each generator returns a list of items:

  ("line", bytes, end, group)   a line; group None: sent when the previous reply has arrived (one
                                line per reply, docs/serial.md), the host waits for its reply;
                                group k: part of flood k, sent at once with the rest of the flood
  ("run", ms)                   the host waits ms (the motion goes on)
  ("settle", ms)                after a flood: the time the sketch gets to answer it

Kinds (seeded random.Random, so a seed gives the same conversation):
  flood    bursts of lines sent without waiting for replies: the issue's `100000` then k x
           `?`, `-7777`, `?`, `9999`, and random mixes of targets, `?`, `set`, blank lines
  fast     moves tens of thousands of steps long at the sketch's own vmax limit (read from `?` and
           its ERR texts: Limits.probe), retargets mid-move, reversals, `stop` and `!` at speed
  setmove  `set v0|vmax|accel` while moving, then retargets
  multi    MultiAxisStepper: independent axes and coordinated `move` lines at speed, set while
           moving, per-axis stop and halt
"""
import re

import emulog

BAUD = {"filter": 115200}
DEFAULT_BAUD = 9600


class Limits:
    """What a sketch accepts and starts with, asked from the sketch itself: its `?` reply (vmax, v0,
    accel, max_sps, tick_hz, algo) and the ERR texts of out-of-range `set`s ("vmax at most N")."""

    def __init__(self, family):
        self.family = family
        self.axes = {}         # axis ("" single, "x".."z") -> {v0, vmax, accel}
        self.max_sps = None
        self.accel_max = None
        self.v0_max = None
        self.tick_hz = None
        self.algo = None
        self.query_len = 140   # bytes of a `?` reply (the longest line of it)

    @property
    def exact(self):
        return self.algo == "exact"

    @property
    def baud(self):
        return BAUD.get(self.family, DEFAULT_BAUD)

    @classmethod
    def probe(cls, env, sketch):
        fam = env.family(sketch)
        lim = cls(fam)
        if fam not in ("stepper", "multiaxis"):
            return lim
        pre = "x " if fam == "multiaxis" else ""
        last = "^z pos=" if fam == "multiaxis" else "^pos="
        script = "\n".join(["wait ^READY [^ ]+$", "timeout 20000", "send ?", f"wait {last}",
                            f"send set {pre}vmax 1e12", "wait ^(OK|ERR)", f"send set {pre}accel 1e12",
                            "wait ^(OK|ERR)", f"send set {pre}v0 1e12", "wait ^(OK|ERR)"]) + "\n"
        log = emulog.run(env.elf(sketch), script, timeout=120)
        for l in log.rx:
            m = re.match(r"^(?:([xyz]) )?pos=", l.text)
            if m:
                f = emulog.query_fields(l.text)
                lim.axes[m.group(1) or ""] = {k: float(f[k]) for k in ("v0", "vmax", "accel")}
                lim.max_sps = float(f["max_sps"])
                lim.tick_hz = float(f["tick_hz"])
                lim.algo = f["algo"]
                lim.query_len = max(lim.query_len, len(l.text) + 40)
            m = re.search(r"\b(vmax|accel|v0) at most (\d+)", l.text)
            if m:
                setattr(lim, {"vmax": "max_sps", "accel": "accel_max", "v0": "v0_max"}[m.group(1)], float(m.group(2)))
        if not lim.axes or lim.max_sps is None:
            raise RuntimeError(f"{sketch}: the probe's `?` was not answered: {log.failure_text() or log.stderr[:200]}")
        if lim.algo == "sigmoid":
            lim.accel_max = None   # SCurveStepper refuses set accel (it follows from its table)
        return lim


def L(text, group=None, end=b"\r\n"):
    return ("line", text.encode("latin-1") if isinstance(text, str) else text, end, group)


def far_target(rng, pos, lim):
    """tens of thousands of steps away (a few at the lab's slow defaults)"""
    d = rng.choice([rng.randint(10000, 100000), rng.randint(1000, 10000), rng.randint(100, 1000)])
    return pos + d * rng.choice([1, -1])


def reply_bytes(line, lim):
    t = line.strip()
    if t in (b"?",):
        return lim.query_len * (3 if lim.family == "multiaxis" else 1)
    return 120   # the longest ERR text


def settle_ms(lines, lim):
    """Time to let the sketch answer a flood after its last byte: the output queue (256 bytes) and
    the core's transmit buffer (64), plus the replies to what the input ring (128) and the core's
    receive buffer (63) can still hold, an overrun reply, and 300 ms."""
    tail, nbytes = [], 0
    for _, data, end, _ in reversed(lines):
        if nbytes > 128 + 63:
            break
        nbytes += len(data) + len(end)
        tail.append(data)
    out = 256 + 64 + sum(reply_bytes(d, lim) for d in tail) + 2 * 40
    return int(out * 10 * 1000 / lim.baud) + 300


# ---- flood -----------------------------------------------------------------------------------

def flood_values(rng, fam, lim):
    """a target/setpoint/value line whose value is hard to make by losing bytes of another"""
    if fam == "stepper":
        return str(rng.choice([1, -1]) * rng.randint(1000, 99999))
    if fam == "multiaxis":
        return f"{rng.choice('xyz')} {rng.choice([1, -1]) * rng.randint(1000, 99999)}"
    if fam == "servo":
        return str(rng.choice([1, -1]) * rng.randint(1000, 99999))
    return f"u {rng.randint(1, 4)}.{rng.randint(100, 999)}"


def flood_set(rng, fam, lim):
    if fam == "stepper" and lim.max_sps:
        return f"set vmax {rng.randint(100, int(lim.max_sps))}" if lim.algo != "sigmoid" else \
            f"set vmax {rng.randint(1000, int(lim.max_sps))}"
    if fam == "multiaxis":
        return f"set {rng.choice('xyz')} vmax {rng.randint(100, int(lim.max_sps))}"
    if fam == "servo":
        return f"kp {rng.randint(1, 99)}.{rng.randint(1, 9)}"
    return f"tau {rng.randint(1, 20)}"


def sync_line(rng, fam, lim):
    """The host's first line after a flood: one whose reply no other line draws (a `set` of a fresh
    value), so the script's wait skips any reply still outstanding (the check then sees it came
    late) and the conversation stays in step."""
    if fam == "stepper":
        v = rng.randint(int(lim.max_sps) // 2, int(lim.max_sps))
        text, rx = f"set vmax {v}", f"^OK vmax={v}( |$)"
    elif fam == "multiaxis":
        v = rng.randint(int(lim.max_sps) // 2, int(lim.max_sps))
        text, rx = f"set x vmax {v}", f"^OK x vmax={v}( |$)"
    elif fam == "servo":
        v = f"0.02{rng.choice([d for d in range(11, 100) if d % 10])}"   # no trailing 0: read back as sent
        text, rx = f"kp {v}", f"^OK kp={v}$"
    else:
        v = rng.randint(100, 1000)
        text, rx = f"every {v}", f"^OK every={v}$"
    return ("line", text.encode(), b"\r\n", None, rx)


def gen_flood(rng, fam, lim, n_lines):
    items = []
    group = 0
    sent = 0
    while sent < n_lines:
        # a line or two one per reply between floods (the sketch answers normally)
        items.append(L("?"))
        sent += 1
        group += 1
        flood = []
        if rng.random() < 0.4:   # the pattern
            a, b = flood_values(rng, fam, lim), flood_values(rng, fam, lim)
            k = rng.randint(3, max(3, min(80, (n_lines - sent) // 4)))
            flood.append(L(flood_values(rng, fam, lim), group))
            for _ in range(k):
                flood += [L("?", group), L(a, group), L("?", group), L(b, group)]
        else:
            k = rng.randint(10, max(10, min(300, n_lines - sent)))
            for _ in range(k):
                r = rng.random()
                if r < 0.45:
                    text = flood_values(rng, fam, lim)
                elif r < 0.7:
                    text = "?"
                elif r < 0.85:
                    text = flood_set(rng, fam, lim)
                elif r < 0.92:
                    text = ""
                else:
                    text = rng.choice(["bogus", "1e999", "12abc", "x" * rng.randint(41, 60)])
                flood.append(L(text, group, rng.choice([b"\r\n", b"\n", b"\r"])))
        items += flood
        sent += len(flood)
        items.append(("settle", settle_ms(flood, lim)))
        items.append(sync_line(rng, fam, lim))
        items.append(L("?"))
        sent += 1
        if fam in ("stepper", "multiaxis"):
            items.append(L("!"))
            sent += 1
            items.append(("run", 50))
    return items


# ---- fast moves, retargets, set while moving -------------------------------------------------

def speed_for(rng, lim):
    top = lim.max_sps
    return int(rng.choice([top, top, top * rng.uniform(0.3, 1.0), rng.uniform(100, top)]))


def accel_for(rng, lim, vmax):
    """from a ramp of about a second to one of a few ms (at most the sketch's own limit)"""
    lo, hi = max(8.0, vmax / 2.0), min(lim.accel_max or 1e7, vmax * 400.0)
    return int(min(hi, max(lo, lo * (hi / lo) ** rng.random())))


def gen_fast(rng, fam, lim, n_lines, setmove=False):
    items = []
    pos = 0
    sent = 0
    sig = lim.algo == "sigmoid"
    while sent < n_lines:
        lines = []
        vmax = speed_for(rng, lim)
        lines.append(f"set vmax {vmax}")
        if sig:
            lines.append(f"set v0 {rng.choice([200, 500, 1000])}")
            lines.append(f"set len {rng.choice([50, 250, 1000])}")
        else:
            lines.append(f"set accel {accel_for(rng, lim, vmax)}")
            if not lim.exact:   # the lab's ramps start at v0 (1 steps/s by default: a second a step)
                lines.append(f"set v0 {rng.choice([20, 100, 500, int(vmax * rng.uniform(0.01, 0.3)) + 1])}")
            elif rng.random() < 0.3:
                lines.append(f"set v0 {rng.choice([0, 1, 50, int(vmax * rng.uniform(0, 0.3))])}")
        for t in lines:
            items.append(L(t))
        sent += len(lines)
        pos = far_target(rng, pos, lim)
        items.append(L(str(pos)))
        sent += 1
        for _ in range(rng.randint(2, 6)):
            items.append(("run", rng.choice([5, 20, 50, 100, 200, 400])))
            r = rng.random()
            if setmove and r < 0.45:
                key = rng.choice(["vmax", "v0"] if sig else ["vmax", "accel", "accel", "v0"])
                if key == "vmax":
                    val = speed_for(rng, lim)
                elif key == "accel":
                    val = accel_for(rng, lim, lim.max_sps)
                else:
                    val = rng.choice([0, 1, 50, 500]) if lim.exact else rng.choice([20, 200, 500])
                items.append(L(f"set {key} {val}"))
                sent += 1
                if rng.random() < 0.8:   # and a new target, so the new value takes effect at speed
                    pos = far_target(rng, pos, lim) if rng.random() < 0.7 else pos + rng.randint(-300, 300)
                    items.append(L(str(pos)))
                    sent += 1
            elif r < 0.6:
                pos = far_target(rng, pos, lim) if rng.random() < 0.7 else pos + rng.randint(-300, 300)
                items.append(L(str(pos)))
                sent += 1
            elif r < 0.72:
                items.append(L("?"))
                sent += 1
            elif r < 0.86:
                items.append(L("stop"))
                sent += 1
                break
            else:
                items.append(L("!"))
                sent += 1
                break
        items.append(L("!"))
        items.append(L("?"))
        sent += 2
    return items


def gen_multi(rng, fam, lim, n_lines):
    items = []
    sent = 0
    top = int(lim.max_sps)
    while sent < n_lines:
        for ax in rng.sample("xyz", rng.randint(1, 3)):
            v = rng.choice([top, top, rng.randint(1000, top)])
            items.append(L(f"set {ax} vmax {v}"))
            items.append(L(f"set {ax} accel {rng.choice([10000, 50000, 90000, 200000, rng.randint(1000, 400000)])}"))
            sent += 2
        if rng.random() < 0.5:
            # a coordinated move from rest
            axes = rng.sample("xyz", rng.randint(1, 3))
            words = [f"{a}{rng.choice([1, -1]) * rng.randint(2000, 40000)}" for a in axes]
            items.append(L("move " + " ".join(words)))
            sent += 1
            for _ in range(rng.randint(1, 3)):
                items.append(("run", rng.choice([20, 100, 300])))
                r = rng.random()
                if r < 0.3:
                    items.append(L("?"))
                elif r < 0.5:
                    items.append(L(rng.choice(["stop", "!", f"stop {rng.choice(axes)}", f"! {rng.choice(axes)}"])))
                elif r < 0.75:
                    items.append(L(f"set {rng.choice(axes)} {rng.choice(['vmax', 'accel'])} "
                                   f"{rng.randint(1000, top)}"))
                else:
                    free = [a for a in "xyz" if a not in axes]
                    if free:   # another axis alone meanwhile
                        items.append(L(f"{rng.choice(free)} {rng.choice([1, -1]) * rng.randint(1000, 30000)}"))
                    else:
                        items.append(L("?"))
                sent += 1
        else:
            # independent axes, retargeted at speed, set while moving
            for _ in range(rng.randint(2, 6)):
                ax = rng.choice("xyz")
                r = rng.random()
                if r < 0.55:
                    items.append(L(f"{ax} {rng.choice([1, -1]) * rng.randint(100, 60000)}"))
                elif r < 0.7:
                    items.append(L(f"set {ax} {rng.choice(['accel', 'vmax', 'v0'])} "
                                   f"{rng.choice([rng.randint(1000, 300000), rng.randint(1000, top)])}"))
                    items.append(L(f"{ax} {rng.choice([1, -1]) * rng.randint(100, 60000)}"))
                    sent += 1
                elif r < 0.8:
                    items.append(L(rng.choice([f"stop {ax}", f"! {ax}"])))
                else:
                    items.append(L("?"))
                sent += 1
                items.append(("run", rng.choice([0, 5, 30, 100, 250])))
        items.append(L("!"))
        items.append(L("?"))
        sent += 2
    return items


KINDS = {"flood": gen_flood, "fast": gen_fast, "setmove": lambda rng, fam, lim, n: gen_fast(rng, fam, lim, n, True),
         "multi": gen_multi}


def kinds_for(family):
    """the scenario kinds that apply to a family (besides serial_fuzz's random lines)"""
    if family == "stepper":
        return ["flood", "fast", "setmove"]
    if family == "multiaxis":
        return ["flood", "multi"]
    return ["flood"]


def count_lines(items):
    return sum(1 for it in items if it[0] == "line")
