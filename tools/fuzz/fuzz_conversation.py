"""tools/fuzz/fuzz_conversation.py - a conversation (fuzz_scenarios.py items) as an INPUT script for
motionemu, and every check of its event log against the documented rules (docs/serial.md,
docs/stepper-engine.md, docs/multi-axis.md):

  replies    a line sent one per reply gets exactly one reply (a blank line none) and never
             `ERR input overrun`; a flood's lines are each answered or counted in an
             `ERR input overrun: N lines lost` reply (answered + N = the non-blank lines sent; a
             blank line lost among them may be counted too), all before the host's next line
             (the overrun is reported at once); nothing else is printed but the family's own
             unsolicited lines; no reset, crash or hang
  values     no line that lost a byte is executed: every OK of a flood names a target or value
             that was sent whole in it, and the `?` after it reports a target that was sent
  steps      per axis: no STEP pulse outside an accepted move (its OK .. its DONE); a DONE for
             every move and none without one; DONE's position is where STEP/DIR had the axis;
             every idle `?` says the position STEP/DIR counted
  speed      (fuzz_oracles.speed_law) on the compare-match times of the STEP edges: the exact
             ramp's constant-acceleration law between consecutive intervals, no interval above
             the largest vmax in force, reversals from rest; every edge within STEP_LATE_CYCLES
             after its match
  status     `underruns=` 0 in every `?` reply (every command is within the limits the sketch
             itself accepts); `late=` may count edges fired 2 us late: each edge is checked
             against its compare match above
"""
import re

import emulog
import fuzz_oracles as fo

REPLY_TIMEOUT_MS = 5000
REPLY_RE = {
    "stepper": r"^(OK|ERR|pos=)",
    "servo": r"^(OK|ERR|setpoint=)",
    "filter": r"^(OK|ERR|kind=)",
    "multiaxis": r"^(OK|ERR|z pos=)",  # `?`: its last line
}
ASYNC_RE = {
    "stepper": re.compile(r"^DONE -?\d+$"),
    "servo": re.compile(r"^t_ms=\d+ "),
    "filter": re.compile(r"^(t_ms,u,y|\d+,-?\d+\.\d+,-?\d+\.\d+)$"),
    "multiaxis": re.compile(r"^(DONE [xyz] -?\d+|DONE move( [xyz] -?\d+)+|[xy] pos=-?\d+ .*)$"),
}
OVERRUN_RE = re.compile(r"^ERR input overrun(?:: (\d+) lines? lost)?$")
AXES = {"stepper": [""], "multiaxis": ["x", "y", "z"]}
PINS = {"": ("STEP", "DIR", "OC1A"), "x": ("XSTEP", "XDIR", "OC1A"), "y": ("YSTEP", "YDIR", "OC1B"),
        "z": ("ZSTEP", "ZDIR", "OC1C")}
OUT_QUEUE_BYTES = 256 + 64   # SerialOutQueue (SERIAL_OUT_QUEUE_BYTES) + the core's transmit buffer


def is_blank(data):
    return all(c in b" \t" for c in data)


def escape(b):
    """bytes -> the INPUT script's text escapes"""
    out = []
    for c in b:
        if c == 0x5C:
            out.append("\\\\")
        elif 0x20 <= c <= 0x7E:
            out.append(chr(c))
        else:
            out.append(f"\\x{c:02x}")
    return "".join(out)


def with_ending(items, family):
    """the conversation and its end: a stepper is halted (a move in progress reports its DONE) and
    asked `?` (the position it reports against the pins)"""
    if family in ("stepper", "multiaxis"):
        return list(items) + [("line", b"!", b"\r\n", None), ("run", 300), ("line", b"?", b"\r\n", None)]
    return list(items) + [("run", 200)]


def script_for(items, family):
    rx = REPLY_RE[family]
    s = ["wait ^READY [^ ]+$", f"timeout {REPLY_TIMEOUT_MS}", "mark fuzz"]
    for it in items:
        if it[0] == "line":
            data, end, group = it[1], it[2], it[3]
            s.append("raw " + escape(data + end))
            if group is None and not is_blank(data):
                s.append(f"wait {it[4] if len(it) > 4 else rx}")
        elif it[0] == "settle":
            s += ["drain", f"run {it[1]}"]
        elif it[0] == "run":
            if it[1] > 0:
                s.append(f"run {it[1]}")
    s += ["mark fuzz-end", "run 100"]
    return "\n".join(s) + "\n"


class Outcome:
    def __init__(self):
        self.lines = 0
        self.replies = 0
        self.blank = 0
        self.flood_lines = 0
        self.overrun_lines = 0
        self.accepted_moves = 0
        self.done = 0
        self.steps = 0
        self.pairs = 0          # consecutive intervals checked against the law
        self.reversals = 0
        self.queries = 0        # `?` lines whose underruns=/late= were checked
        self.worst_law = 0.0
        self.problems = []
        self.first_bad_line = None

    def bad(self, text, index=None):
        self.problems.append(text)
        if index is not None and (self.first_bad_line is None or index < self.first_bad_line):
            self.first_bad_line = index


# ---- what an OK executed ---------------------------------------------------------------------

NUM = r"[-+]?[0-9.]+(?:[eE][-+]?\d+)?"


def sent_values(text):
    """what a line asks for, normalised: ('target', axis, value) or (axis, key, value); None"""
    t = text.strip()
    m = re.fullmatch(r"(?:([xyz]) )?(-?\d+)", t)
    if m:
        return ("target", m.group(1) or "", float(m.group(2)))
    m = re.fullmatch(r"set (?:([xyz]) )?(\w+) (" + NUM + ")", t)
    if m:
        return (m.group(1) or "", m.group(2), float(m.group(3)))
    m = re.fullmatch(r"(kp|ki|kd|u|tau|tau2|every) (" + NUM + ")", t)
    if m:
        return ("", m.group(1), float(m.group(2)))
    return None


def ok_values(text):
    """what an OK says was executed, normalised as sent_values; None for OK stop/halt etc."""
    m = re.match(r"^OK (?:([xyz]) )?(-?\d+) (-?\d+)", text)
    if m:
        return ("target", m.group(1) or "", float(m.group(3)))
    m = re.match(r"^OK setpoint=(-?\d+)", text)
    if m:
        return ("target", "", float(m.group(1)))
    m = re.match(r"^OK (?:([xyz]) )?(\w+)=(" + NUM + ")", text)
    if m:
        return (m.group(1) or "", m.group(2), float(m.group(3)))
    return None


def same_value(a, b):
    """the same key and value; a value read back from the board's float32 (kp=95.900002 for 95.9)"""
    return a[:2] == b[:2] and abs(a[2] - b[2]) <= 1e-6 * max(1.0, abs(b[2]))


# ---- the check -------------------------------------------------------------------------------

def check(log, family, items, lim=None):
    o = Outcome()
    lines = [it for it in items if it[0] == "line"]
    o.lines = len(lines)
    for c, k, t in log.fails:
        o.bad(f"hang: {t} (at {c / emulog.F_CPU:.3f} s)" if k == "timeout" else f"{k} at {c / emulog.F_CPU:.3f} s: {t}")
    if log.end.get("reason") != "done":
        o.bad(f"the emulation ended '{log.end.get('reason')}' (rc {log.rc}): {log.stderr.strip()[:300]}")
    start, end = log.mark("fuzz"), log.mark("fuzz-end")
    if start is None:
        o.bad("the sketch never said READY")
        return o
    sends = [t for t in log.tx if t.cycle >= start][:len(lines)]
    if len(sends) != len(lines) and end is not None:
        o.bad(f"{len(sends)} lines sent of {len(lines)}")
    async_re, reply_re = ASYNC_RE[family], re.compile(REPLY_RE[family])
    replies, asyncs = [], []
    for l in log.rx:
        if l.cycle < start:
            continue
        if async_re.match(l.text):
            asyncs.append(l)
        elif reply_re.match(l.text):
            replies.append(l)
        else:
            o.bad(f"an unexpected line from the sketch: {l.text!r} at {l.t_s:.3f} s")
    # groups: a solo line alone, a flood's lines together; each owns the replies that arrive from
    # its first byte queued to the next group's
    groups = []   # [first line index, last line index, flood?]
    for i, g in enumerate(it[3] for it in lines[:len(sends)]):
        if g is not None and groups and groups[-1][2] == g:
            groups[-1][1] = i
        else:
            groups.append([i, i, g])
    per_group = [[] for _ in groups]
    j = 0
    for gi, (a, b, g) in enumerate(groups):
        c0 = sends[a].cycle
        c1 = sends[groups[gi + 1][0]].cycle if gi + 1 < len(groups) else (end if end is not None else float("inf"))
        while j < len(replies) and replies[j].cycle < c0:
            j += 1
        while j < len(replies) and replies[j].cycle < c1:
            per_group[gi].append(replies[j])
            j += 1
    o.replies = sum(len(p) for p in per_group)
    owner = {}   # id(reply) -> (group index)
    prev_target = {}
    for gi, ((a, b, g), got) in enumerate(zip(groups, per_group)):
        for r in got:
            owner[id(r)] = gi
        if g is None:
            data, end_b = lines[a][1], lines[a][2]
            want = 0 if is_blank(data) else 1
            o.blank += want == 0
            if len(got) != want:
                o.bad(f"line {a + 1} {data + end_b!r} drew {len(got)} replies, want {want}: "
                      f"{[x.text for x in got][:6]}", a)
            for x in got:
                if OVERRUN_RE.match(x.text):
                    o.bad(f"line {a + 1} {data!r}: {x.text!r} although the host sent one line per reply", a)
            if data.strip() == b"?" and got:
                check_query_target(log, family, got[-1], gi, groups, lines, prev_target, o, a)
            continue
        # a flood
        flood = lines[a:b + 1]
        nonblank = sum(1 for it in flood if not is_blank(it[1]))
        blanks = len(flood) - nonblank
        o.flood_lines += len(flood)
        o.blank += blanks
        lost = 0
        answered = 0
        for x in got:
            m = OVERRUN_RE.match(x.text)
            if m:
                lost += int(m.group(1) or 1)
            else:
                answered += 1
        o.overrun_lines += lost
        if not (nonblank <= answered + lost <= nonblank + blanks):
            o.bad(f"flood of {len(flood)} lines (lines {a + 1}-{b + 1}, {nonblank} non-blank): {answered} replies "
                  f"+ {lost} lines counted lost before the host's next line; want {nonblank}"
                  + (f"..{nonblank + blanks}" if blanks else ""), a)
        sent = {sent_values(it[1].decode("latin-1")) for it in flood} - {None}
        for x in got:
            v = ok_values(x.text)
            if x.text.startswith("OK") and v is not None and not any(same_value(v, w) for w in sent):
                o.bad(f"flood at line {a + 1}: {x.text!r} executes a value no line of the flood had whole "
                      f"(a line that lost bytes was executed)", a)
                break
        prev_target["flood"] = {v[1:] for v in sent if v[0] == "target"}
    if family in AXES:
        check_axes(log, family, lines, sends, groups, per_group, owner, asyncs, lim, o)
    for l in log.rx:
        if l.cycle >= start and re.match(r"^(?:[xyz] )?pos=", l.text):
            o.queries += 1
            p = fo.status_problems(emulog.query_fields(l.text), f"at {l.t_s:.3f} s")
            if p:
                o.bad(p[0] + f": {l.text}")
                break
    return o


def query_lines(log, family, reply):
    """the lines of a `?` reply: the one line, or MultiAxisStepper's x, y, z lines ending at reply"""
    if family != "multiaxis":
        return [reply]
    before = [l for l in log.rx if l.cycle <= reply.cycle and re.match(r"^[xyz] pos=", l.text)]
    return before[-3:]


def check_query_target(log, family, reply, gi, groups, lines, prev_target, o, index):
    """the `?` right after a flood: each target it reports was sent whole (in the flood, or before it)"""
    if family == "filter":
        return
    ql = query_lines(log, family, reply)
    now = {}
    for l in ql:
        m = re.match(r"^(?:([xyz]) )?pos=-?\d+ target=(-?\d+)", l.text) or re.match(r"^setpoint=(-?\d+)()", l.text)
        if m:
            if family == "servo":
                now[""] = float(m.group(1))
            else:
                now[m.group(1) or ""] = float(m.group(2))
    after_flood = gi > 0 and groups[gi - 1][2] is not None
    if after_flood and "flood" in prev_target:
        ok = prev_target["flood"] | {(ax, v) for ax, v in prev_target.get("query", {}).items()}
        for ax, v in now.items():
            if (ax, v) not in ok:
                o.bad(f"line {index + 1}: the `?` after a flood says {'setpoint' if family == 'servo' else 'target'} "
                      f"{ax + ' ' if ax else ''}{v:.0f}, which no line sent whole asked for", index)
                break
    prev_target["query"] = now


def check_axes(log, family, lines, sends, groups, per_group, owner, asyncs, lim, o):
    axes = AXES[family]
    seq = sorted([(r.cycle, r) for got in per_group for r in got] + [(l.cycle, l) for l in asyncs], key=lambda e: e[0])
    open_moves = {ax: [] for ax in axes}
    open_at = {ax: None for ax in axes}
    open_line = {ax: None for ax in axes}
    windows = {ax: [] for ax in axes}
    dones = {ax: [] for ax in axes}
    halts = {ax: [] for ax in axes}
    sets = {ax: [] for ax in axes}
    # when a plan took the parameters in force (a target's or a stop's line sent); SCurveStepper's
    # table (its vmax and accel) changes only for a move from rest, so there only such moves count
    plans = {ax: [] for ax in axes}
    table = lim is not None and lim.algo == "sigmoid"
    # when each line has arrived whole at the sketch: a flood's lines are all sent at one cycle and
    # come in one after the other at 9600 baud, so their order in time is their order in the flood
    byte_cycles = emulog.F_CPU * 10 // 9600
    arrive, queued, last_send = [], 0, None
    for i, snd in enumerate(sends):
        queued = queued if snd.cycle == last_send else 0
        queued += len(lines[i][1])
        last_send = snd.cycle
        arrive.append(snd.cycle + queued * byte_cycles)
    used = set()

    def line_of(gi, pattern, value):
        """the line of group gi a reply answers: a solo line is its group; in a flood, the first
        line not yet matched whose text is pattern with this number (else the flood's first)"""
        a, b, g = groups[gi]
        if g is None:
            return a
        for i in range(a, b + 1):
            if i in used:
                continue
            m = re.fullmatch(pattern, lines[i][1].decode("latin-1").strip())
            if m:
                try:
                    if float(m.group(1)) == value:
                        used.add(i)
                        return i
                except ValueError:
                    continue
        return a

    def close(ax, p, c):
        dones[ax].append((c, p))
        if not open_moves[ax]:
            o.bad(f"DONE {ax + ' ' if ax else ''}{p} at {c / emulog.F_CPU:.3f} s without a move in progress")
            return
        windows[ax].append((open_at[ax], c))
        open_moves[ax].pop(0)
        open_at[ax] = c if open_moves[ax] else None

    def move(ax, frm, to, chained, gi):
        o.accepted_moves += 1
        if not table or not open_moves[ax] or chained:
            pat = (r"(?:[xyz] )?(" + NUM + ")") if family == "multiaxis" else "(" + NUM + ")"
            # (arrived, answered, where the plan starts: its OK's `from`)
            plans[ax].append((arrive[line_of(gi, pat, float(to))], c, frm))
        if not open_moves[ax]:
            open_moves[ax] = [to]
            open_at[ax], open_line[ax] = sends[groups[gi][0]].cycle, groups[gi][0]
        elif chained and len(open_moves[ax]) == 1:
            open_moves[ax].append(to)
        else:
            open_moves[ax][-1] = to

    for c, l in seq:
        t = l.text
        if t.startswith("DONE"):
            w = t.split()
            if family == "stepper":
                close("", int(w[1]), c)
            elif w[1] == "move":
                for k in range(2, len(w), 2):
                    close(w[k], int(w[k + 1]), c)
            else:
                close(w[1], int(w[2]), c)
            continue
        if id(l) not in owner:
            continue
        gi = owner[id(l)]
        a = groups[gi][0]
        sent = lines[a][1].decode("latin-1").strip() if groups[gi][2] is None else None
        m = re.match(r"^OK (?:([xyz]) )?(-?\d+) (-?\d+)( \(after DONE [^)]*\))?$", t)
        if m and (family == "stepper") == (m.group(1) is None):
            move(m.group(1) or "", int(m.group(2)), int(m.group(3)), bool(m.group(4)), gi)
            continue
        m = re.match(r"^OK move((?: [xyz] -?\d+ -?\d+)+)$", t)
        if m and family == "multiaxis":
            w = m.group(1).split()
            for k in range(0, len(w), 3):
                move(w[k], int(w[k + 1]), int(w[k + 2]), False, gi)
            continue
        m = re.match(r"^OK (?:([xyz]) )?(v0|vmax|accel)=(" + NUM + ")", t)
        if m:
            # in force from when the sketch read the line, before its reply went out (a move the
            # sketch plans meanwhile, a target waiting for a DONE, already has it): at some moment
            # between the line's arrival and its reply (Params)
            when = min(c, arrive[line_of(gi, r"set (?:[xyz] )?" + m.group(2) + r"\s+(" + NUM + r")",
                                         float(m.group(3)))])
            for ax in ([m.group(1)] if m.group(1) else axes):
                sets[ax].append((when, c, m.group(2), float(m.group(3))))
            continue
        if t in ("OK halt", "OK stop"):
            if sent is not None and re.fullmatch(r"(stop|!) [xyz]", sent):
                which = [sent[-1]]
            else:
                which = axes
            for ax in which:
                if t == "OK halt":
                    halts[ax].append(c)
                elif not table:
                    plans[ax].append((min(c, arrive[a]), c))
                if family == "stepper" and not open_moves[ax]:
                    o.bad(f"line {a + 1} {sent!r} was answered {t!r} (stopping a move) while none was in progress", a)
                del open_moves[ax][1:]
    o.done = sum(len(d) for d in dones.values())
    solo_queries = []
    for gi, (a, b, g) in enumerate(groups):
        if g is None and lines[a][1].strip() == b"?" and per_group[gi]:
            solo_queries += query_lines(log, family, per_group[gi][-1])
    byte = emulog.F_CPU * 10 // 9600
    matches_all = sorted(c for v in log.matches.values() for c in v)
    for ax in axes:
        step, dirp, ch = PINS[ax]
        name = f"{ax} " if ax else ""
        if open_moves[ax]:
            ol = open_line[ax]
            o.bad(f"the {name}move accepted at line {ol + 1} {lines[ol][1]!r} never reported DONE (not even after "
                  f"the final `!`)", ol)
            windows[ax].append((open_at[ax], float("inf")))
        edges = fo.edges_with_dir(log.pins, step, dirp)
        cyc = [e[0] for e in edges]
        o.steps += len(edges)
        merged = []
        for x0, x1 in sorted(windows[ax]):
            if merged and x0 <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], x1)
            else:
                merged.append([x0, x1])
        wi, stray = 0, []
        for c in cyc:
            while wi < len(merged) and merged[wi][1] < c:
                wi += 1
            if wi >= len(merged) or c < merged[wi][0]:
                stray.append(c)
        if stray:
            o.bad(f"{len(stray)} {name}STEP pulses with no move accepted, the first at {stray[0] / emulog.F_CPU:.4f} s")
        pos_after = fo.positions(edges)
        for c, p in dones[ax]:
            span = (OUT_QUEUE_BYTES + len(f"DONE {name}{p}") + 2) * byte
            if not fo.position_seen(pos_after, c, p, span):
                o.bad(f"DONE {name}{p} at {c / emulog.F_CPU:.3f} s, but STEP/DIR never had the axis there over "
                      f"the {OUT_QUEUE_BYTES} byte times before it")
                break
        # every idle `?` sent one line per reply (nothing moves while it is printed) says the pin count
        for l in solo_queries:
            m = re.match(r"^" + (ax + " " if ax else "") + r"pos=(-?\d+) target=-?\d+ state=idle", l.text)
            if m:
                want = fo.position_at(pos_after, l.cycle)
                if int(m.group(1)) != want:
                    o.bad(f"`?` at {l.t_s:.3f} s says {name}pos={m.group(1)} (idle), STEP/DIR counted {want}")
                    break
        if lim is None or not cyc or not log.matches:
            continue
        own = log.matches.get(ch, [])
        planned, late = fo.planned_cycles(cyc, own, matches_all)
        for p in late:
            o.bad(f"{name}edge late: {p}")
        splits = fo.done_splits(pos_after, dones[ax] + [(h, fo.position_at(pos_after, h)) for h in halts[ax]])
        if table:
            # SCurveStepper: a move from rest takes the table in force when the last move ended (a
            # `set` while moving waits for rest; one sent after that end counts through the bound's
            # largest-value rule), whatever targets continued it (docs/serial.md)
            plans[ax] = [0] + [d[0] for d in dones[ax]] + list(halts[ax])
        params = fo.Params(lim.axes.get(ax, {}), sets[ax])
        tick = int(round(emulog.F_CPU / lim.tick_hz))
        probs, pairs, worst, rev = fo.speed_law(planned, [e[1] for e in edges], splits, params, tick, lim.exact,
                                               f"{name}speed" if name else "speed",
                                               reversals=lim.algo != "sigmoid", plans=plans[ax], pins=cyc,
                                               positions=[q for _, q in pos_after])
        o.pairs += pairs
        o.reversals += rev
        o.worst_law = max(o.worst_law, worst)
        for p in probs:
            o.bad(p)
