#!/usr/bin/env python3
"""tools/emu/emulate.py - what `make emulate SKETCH=<name> [INPUT=<file>] [LIVE=1]` runs.

Runs the sketch's ELF (build/firmware/<S>/<S>.ino.elf) in the ATmega2560 emulator with an INPUT
script (default: the sketch family's standard scenario; a sketch that gives no `?` reply at boot
gets the family's command without waiting for replies), printing the serial conversation as it
happens ("[   0.168 s] < OK 0 50"), or with --live as an interactive board: real time, UART0 on a
pseudo-terminal whose path it prints (motionemu --pty), until the monitor closes it or Ctrl-C. The
CSVs come from the pins, whatever the sketch prints (a stepper that prints no `OK <from> <to>`: one
move per DIR change or host line, from its STEP/DIR edges; overlays only where the parameters are
known). Then it writes into the output folder:
  <S>.input.emu     the script that ran
  <S>.log           the harness's event log (every serial line, pin edge, motor sample, cycle-exact)
  <S>.csv           the firmware's behaviour in motionsim's CSV format, from its real pins/port:
                    stepper  step,position,t_s,interval_ticks,speed_sps,accel_sps2  (STEP/DIR edges;
                             one file per move: <S>.csv, <S>-2.csv, ...; position is where the
                             axis is, counted from the pulses and DIR since boot. A new target while
                             moving: the new file starts after the target's arrival, its first
                             interval and acceleration continue from the previous step)
                    filter   k,t_s,u,y      (the sketch's serial stream)
                    servo    t_s,setpoint,position_counts,error_counts,duty_pct (encoder count of the
                             emulated motor and the duty measured on the PWM/DIR pins, every 1 ms)
                    one file per setpoint: <S>.csv, <S>-2.csv, ... (t = 0 when the command arrived)
  <S>.motionsim.csv motionsim for the parameters in force (the sketch's defaults - its own `?` reply
                    at boot, asked in a short run of its own, so the script needs no `?` - replaced
                    by the script's last `?` reply and updated by the `OK key=value` replies before
                    the move or setpoint; a new target while moving: `motionsim ramp --queue
                    --retarget-at` of the whole chain from rest, replanned where the OK's "from"
                    says, placed on the firmware's first edge, the rows of this move's steps; a move
                    replaced so: as far as its steps went), and <S>.png: the firmware's CSV with
                    motionsim's overlaid, titled with the move, filter or setpoint and gains it
                    shows (one PNG per move or setpoint). Servo segments after the first get an overlay only when
                    motionsim can start where the firmware was: motor at rest, controller without
                    memory (P, or PID with Ki = Kd = 0); motionsim then runs the step from 0 and is
                    shifted by the position at the start. motionsim's t = 0 (its first sample) is
                    placed at the firmware's first encoder read that drove a new duty.
A library example (lib/examples/<S>, firmware/libraries/<Lib>/examples/<S>; sketches.example_dirs)
is no console: it is not asked `?`, its default script lets it run by itself for 5 s (or what
sketches.EXAMPLE_INPUTS gives it, e.g. StopOnSwitch's switches), and its RAMPS X, Y, Z pins give the
multiaxis CSV and plot (t_s,axis,step,position; <S>.positions.csv). A sketch of your own under
firmware/ on our libraries (marker line `// motion-sketch: library`) runs the same way.
Earlier outputs of the same sketch are deleted first. Exit status: 0 ok, 1 the firmware or
motionsim failed, 2 bad SKETCH or INPUT.
"""
import argparse
import glob
import os
import re
import signal
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import emulog  # noqa: E402
import sketches  # noqa: E402
from emulog import F_CPU  # noqa: E402


def write_csv(path, header, rows):
    with open(path, "w") as f:
        f.write(header + "\n")
        for r in rows:
            f.write(",".join(fmt(v) for v in r) + "\n")


def fmt(v):
    if isinstance(v, float):
        return repr(round(v, 9)) if v != int(v) or abs(v) > 1e15 else str(int(v))
    return str(v)


QUERY_KEY = {"stepper": "pos", "filter": "kind", "servo": "setpoint", "multiaxis": "x pos"}   # the first field of each `?` reply


def params_before(log, key, cycle, defaults=None):
    """The parameters in force before `cycle`: the sketch's defaults (its `?` reply at boot, see
    sketch_defaults), replaced by the fields of the last `?` reply of the run (a line starting with
    `key=`) if there is one, and updated by every later `OK name=value` reply to a `set`/gain command."""
    q = dict(defaults or {})
    for l in log.rx:
        if l.cycle >= cycle:
            break
        if l.text.startswith(key + "="):
            q = emulog.query_fields(l.text)
        else:
            m = re.match(r"^OK (\w+)=(\S+)$", l.text)
            if m and (q or defaults is not None):
                q[m.group(1)] = m.group(2)
    return q


def sketch_defaults(elf, fam, hargs):
    """The sketch's parameters at boot: its own `?` reply, from a short emulation of its own (so the
    user's script needs no `?` for the motionsim overlay). {} if the sketch does not answer."""
    return probe(elf, fam, hargs)[1]


def probe(elf, fam, hargs):
    """(ready, defaults): whether the sketch prints a `READY <name>` line within 3 s of power-on, and
    its parameters at boot (its `?` reply, {} if it gives none within 3 s): two short emulations of
    their own, before the real run."""
    key = QUERY_KEY[fam]
    log = emulog.run(elf, f"timeout 3000\nwait ^READY [^ ]+$\nsend ?\nwait ^{key}=\n", **hargs)
    ready = log.first(r"^READY [^ ]+$") is not None
    if not ready:   # no banner: ask anyway, once the sketch has had a second to start
        log = emulog.run(elf, f"until 1000\nsend ?\ntimeout 3000\nwait ^{key}=\n", **hargs)
    line = log.first(r"^" + key + "=")
    return ready, (emulog.query_fields(line.text) if line else {})


# The default scripts of a sketch that does not answer `?` (a user's own sketch with its own replies,
# or none): the family's standard command sent without waiting for any reply, then time to act.
BLIND_INPUT = {
    "stepper": "send 50\nrun 15000\n",
    "multiaxis": "send x 2000\nrun 15000\n",
    "servo": "send 1000\nrun 3000\n",
    "filter": "@100 u 5\n@20100 u 0\nuntil 35000\n",
}


def blind_input(sketch, fam, ready):
    """The default script for a sketch that gives no `?` reply: after its READY line (or 1 s), the
    family's standard command (the lab's move 0 -> 50, setpoint 1000, ...), then its time to act
    (every pin is logged whatever the sketch prints)"""
    head = f"# {sketch}: no `?` reply at boot, so the standard command is sent without waiting for replies\n"
    head += "wait ^READY [^ ]+$\n" if ready else "until 1000\n"
    return head + BLIND_INPUT[fam]


def host_lines(log):
    """[(cycle, text)]: every line the host sent to the firmware, in order (a script's send/@ lines,
    raw bytes, or what was typed on the pty, however it came in pieces), with the cycle at which its
    line end (CR, LF or CR LF) had arrived: the bytes of each piece arrive one frame apart from one
    frame after it was queued, behind the bytes queued before them (emu_uart.c)."""
    fc = frame_cycles(log)
    out, free_at, cur, prev = [], 0, bytearray(), None
    for cycle, tag, rest in log.events:
        if tag == "tx":
            data = emulog.unescape(rest) + b"\r\n"
        elif tag == "txraw":
            data = emulog.unescape(rest)
        elif tag == "txrepeat":
            n, _, text = rest.partition(" ")
            data = emulog.unescape(text) * int(n) if n.isdigit() else b""
        else:
            continue
        for b in data:
            arrive = max(cycle, free_at) + fc
            free_at = arrive
            if b == 10 and prev == 13:
                out[-1] = (arrive, out[-1][1])   # CR LF: the line ends at its LF
            elif b in (10, 13):
                out.append((arrive, cur.decode("latin-1")))
                cur = bytearray()
            else:
                cur.append(b)
            prev = b
    return out


def arrival_of(lines, text, before):
    """the cycle at which the last host line equal to `text` (blanks aside) arrived before `before`, or None"""
    ends = [c for c, t in lines if c < before and t.strip() == text]
    return ends[-1] if ends else None


def frame_cycles(log):
    for cycle, tag, rest in log.events:
        if tag == "uart":
            for w in rest.split():
                if w.startswith("cycles_per_byte="):
                    return int(w.split("=")[1])
    return 16640


# ---- stepper ---------------------------------------------------------------------------------

OK_MOVE_RE = r"^OK (-?\d+) (-?\d+)( \(after DONE (-?\d+)\))?$"


def stepper_moves(log):
    """[(from, to, t0_cycle, [rising edge cycles], ok_cycle, continues)] per 'OK <from> <to>' reply.
    t0: the command's line end has arrived (a move from rest: its first interval counts from there);
    "OK <a> <b> (after DONE <a>)" starts at that DONE. continues: the move took over a moving axis
    (a new target while moving, no DONE in between): its first edges are the old plan's queued ones."""
    moves = []
    sent = host_lines(log)
    oks = log.lines_matching(OK_MOVE_RE)
    rises = log.rising("STEP")
    starts, stops, after = [], [], []
    for i, ok in enumerate(oks):
        m = re.match(OK_MOVE_RE, ok.text)
        b = int(m.group(2))
        t0 = arrival_of(sent, str(b), ok.cycle) or ok.cycle
        if m.group(3):
            d = log.first(r"^DONE " + m.group(4) + "$", ok.cycle)
            t0 = d.cycle if d else ok.cycle
        starts.append(t0)
        after.append(bool(m.group(3)))
    cont = []
    for i, ok in enumerate(oks):
        nxt = oks[i + 1].cycle if i + 1 < len(oks) else None
        if i + 1 < len(oks) and after[i + 1]:
            done = log.first(r"^DONE ", ok.cycle)  # this move keeps its DONE, printed after the next OK
        else:
            done = log.first(r"^DONE ", ok.cycle, nxt)
        stops.append(done.cycle if done else nxt)
        cont.append(i > 0 and not after[i] and log.first(r"^DONE ", oks[i - 1].cycle, ok.cycle) is None)
    for i, ok in enumerate(oks):
        a, b = (int(x) for x in re.match(OK_MOVE_RE, ok.text).groups()[:2])
        # a move replaced by a new target owns its edges up to that target's arrival, the new one after
        stop = starts[i + 1] if i + 1 < len(oks) and cont[i + 1] else stops[i]
        edges = [c for c in rises if c >= starts[i] and (stop is None or c < stop)]
        moves.append((a, b, starts[i], edges, ok.cycle, cont[i]))
    return moves


def edge_moves(log):
    """The moves of a sketch that prints no `OK <from> <to>` (a user's own): its STEP edges, split where
    DIR changes and where a host line arrived between two edges, in stepper_moves' form
    (from, to, t0, edges, first edge, False); t0 is the arrival of the line that started the move,
    else the previous move's last edge, else its own first edge."""
    rises = log.rising("STEP")
    if not rises:
        return []
    pos = step_positions(log)
    arrivals = [c for c, t in host_lines(log) if t.strip()]
    groups = [[rises[0]]]
    for prev, c in zip(rises, rises[1:]):
        turned = log.level_before("DIR", c) != log.level_before("DIR", prev)
        told = any(prev < a < c for a in arrivals)
        if turned or told:
            groups.append([c])
        else:
            groups[-1].append(c)
    moves = []
    for i, g in enumerate(groups):
        lo = groups[i - 1][-1] if i else -1
        before = [a for a in arrivals if lo < a < g[0]]
        t0 = before[-1] if before else (lo if i else g[0])
        forward = log.level_before("DIR", g[0]) == 1
        moves.append((pos[g[0]] + (-1 if forward else 1), pos[g[-1]], t0, g, g[0], False))
    return moves


def step_positions(log):
    """{rising edge cycle: position after that step}, counted from 0 at boot by the DIR level at each
    edge: where the axis really is, whatever a reply's planned "from" says"""
    pos, out = 0, {}
    for c in log.rising("STEP"):
        pos += 1 if log.level_before("DIR", c) == 1 else -1
        out[c] = pos
    return out


def stepper_rows(t0, edges, positions, tick_hz, v0, before=None):
    """One row per edge. A move from rest: step 1's interval counts from t0 (the command), its
    acceleration from v0. A move that took over a moving axis (before = the two edges that preceded
    it): step 1's interval counts from the previous edge and its acceleration from that edge's speed."""
    cyc_per_tick = F_CPU / tick_hz
    rows = []
    prev_c, prev_dt, prev_v = t0, 0.0, v0
    if before and len(before) >= 1:
        prev_c = before[-1]
        if len(before) >= 2:
            prev_dt = (before[-1] - before[-2]) / F_CPU
            prev_v = 1.0 / prev_dt if prev_dt > 0 else 0.0
    for n, c in enumerate(edges, 1):
        interval = (c - prev_c) / cyc_per_tick
        dt = interval / tick_hz
        speed = tick_hz / interval if interval > 0 else 0.0
        accel = (speed - prev_v) / ((dt + prev_dt) / 2.0) if (dt + prev_dt) > 0 else 0.0
        rows.append((n, positions[c], (c - t0) / F_CPU, interval, speed, accel))
        prev_c, prev_dt, prev_v = c, dt, speed
    return rows


def read_rows(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return lines[0], [l.split(",") for l in lines[1:] if l]


def chain_overlay(env, q, moves, i, out):
    """The motionsim overlay of move i, which took over a moving axis: the chain from the last move
    from rest, replanned at each new target (motionsim ramp --queue --retarget-at N:TARGET, N found
    so that the plan's "from" is the OK's), the rows of move i's edges, timed like the firmware's
    (motionsim's edges placed on the firmware's first edge of the chain). None, or why not."""
    s = i
    while s > 0 and moves[s][5]:
        s -= 1
    a0, b0, _, edges0, _, _ = moves[s]
    if not edges0:
        return "the first move of the chain made no step"
    base = [x for x in stepper_sim_args(q, a0, b0) if x not in ("--queue", "--integer-ticks")] + ["--queue"]
    pairs = []
    tmp_cmds = out + ".commands.csv"
    for j in range(s + 1, i + 1):
        frm = moves[j][0]
        args = base + (["--retarget-at", ",".join(f"{n}:{t}" for n, t in pairs)] if pairs else [])
        p = subprocess.run([env.motionsim, *args, "--commands", tmp_cmds, "-o", os.devnull], capture_output=True,
                           text=True)
        if p.returncode != 0:
            return f"motionsim: {p.stderr.strip()}"
        _, cmds = read_rows(tmp_cmds)
        pos, found = a0, None
        last_n = pairs[-1][0] if pairs else 0
        for c in cmds:
            first, count, flags = int(c[1]), int(c[2]), c[5] if len(c) > 5 else ""
            pos += -count if "reverse" in flags else count
            if first > last_n and pos == frm:
                found = first
                break
        if found is None:
            return f"no step command of the plan ends at {frm}, where the new target took over"
        pairs.append((found, moves[j][1]))
    os.remove(tmp_cmds)
    args = base + ["--retarget-at", ",".join(f"{n}:{t}" for n, t in pairs)]
    p = subprocess.run([env.motionsim, *args, "-o", out], capture_output=True, text=True)
    if p.returncode != 0:
        return f"motionsim: {p.stderr.strip()}"
    header, rows = read_rows(out)
    # the chain's k-th edge is motionsim's row k: move i's edges are rows [r, r + its edges)
    first_k = sum(len(moves[j][3]) for j in range(s, i))
    fw_edges = moves[i][3]
    mine = rows[first_k:first_k + len(fw_edges)]
    if not mine:
        return "motionsim's chain ends before this move's steps"
    offset = edges0[0] - float(rows[0][2]) * F_CPU  # cycles: motionsim's t = 0 on the firmware's timeline
    t0 = moves[i][2]
    with open(out, "w") as f:
        f.write(header + "\n")
        for n, r in enumerate(mine, 1):
            t = (float(r[2]) * F_CPU + offset - t0) / F_CPU
            f.write(",".join([str(n), r[1], fmt(t)] + r[3:]) + "\n")
    return None


OVERLAY_MAX_STEPS = 1000000  # motionsim's default --max-rows: a longer move is drawn without an overlay


def stepper_sim_args(q, a, b):
    algo = q.get("algo", "leib")
    if algo == "sigmoid":
        return ["ramp", "--algo", "sigmoid", "--from", str(a), "--to", str(b), "--len", q["len"], "--fmin", q["v0"],
                "--fmax", q["vmax"], "--flex", q["flex"], "--timer-hz", q["tick_hz"], "--hold", q["hold"],
                "--integer-ticks"]
    # the exact ramp runs on the step engine's commands: --queue rebuilds its step table from them
    return ["ramp", "--algo", algo, "--from", str(a), "--to", str(b), "--v0", q["v0"], "--vmax", q["vmax"],
            "--accel", q["accel"], "--tick-hz", q["tick_hz"], "--queue" if algo == "exact" else "--integer-ticks"]


def stepper_params_text(q):
    if q.get("algo") == "sigmoid":
        return (f"S-curve, {q.get('v0')} -> {q.get('vmax')} steps/s, table of {q.get('len')} held "
                f"{q.get('hold')} steps, flex {q.get('flex')}")
    return (f"{ALGO_NAMES.get(q.get('algo'), q.get('algo', '?'))}, v0 {q.get('v0')}, vmax {q.get('vmax')} steps/s, "
            f"a {q.get('accel')} steps/s²")


ALGO_NAMES = {"leib": "Leib", "exact": "exact", "simplistic": "simplistic", "sigmoid": "S-curve"}
FILTER_NAMES = {"ma": "moving average", "ma2": "two-stage S-curve", "exp": "exponential"}


def filter_params_text(q, rows):
    kind = q.get("kind", "ma")
    text = f"{FILTER_NAMES.get(kind, kind)}, tau = {q.get('tau', '?')} s"
    if kind == "ma2":
        text += f", tau2 = {q.get('tau2', '?')} s"
    if rows:
        text += f", {rows[-1][1] - rows[0][1]:.2f} s of input"
    return text


def servo_gains_text(q):
    if "ki" in q:
        return f"PID, Kp = {q.get('kp')}, Ki = {q.get('ki')}, Kd = {q.get('kd')}"
    return f"P, Kp = {q.get('kp')}"


# ---- servo -----------------------------------------------------------------------------------

def servo_segments(log):
    """[(setpoint, t0 cycle, ok cycle, rows)] per 'OK setpoint=' reply: rows (t_s from the command's
    arrival, setpoint, counts, error, duty) from the motor samples up to the next command's arrival"""
    sent = host_lines(log)
    changes = []  # (arrival cycle, setpoint, ok cycle)
    for ok in log.lines_matching(r"^OK setpoint=-?\d+$"):
        sp = int(ok.text.split("=")[1])
        changes.append((arrival_of(sent, str(sp), ok.cycle) or ok.cycle, sp, ok.cycle))
    if not changes:
        # a sketch that does not confirm setpoints: each number sent is taken as one, from its arrival
        # (none sent: one segment from power-on, setpoint unknown)
        changes = [(c, int(t.strip()), c) for c, t in sent if re.fullmatch(r"-?\d+", t.strip())] or \
            [(0, None, 0)]
    segs = []
    for i, (t0, sp, okc) in enumerate(changes):
        t1 = changes[i + 1][0] if i + 1 < len(changes) else None
        rows = [((c - t0) / F_CPU, "" if sp is None else sp, counts, "" if sp is None else sp - counts, duty)
                for c, duty, counts in log.motor if c >= t0 and (t1 is None or c < t1)]
        segs.append((sp, t0, okc, rows))
    return segs


def servo_sim_args(q, setpoint, duration_s):
    args = ["servo", "--ctrl", "pid" if "ki" in q else "p", "--kp", q.get("kp", "0.02"), "--setpoint", str(setpoint),
            "--duration", f"{max(0.02, duration_s):.3f}"]
    if "ki" in q:
        args += ["--ki", q["ki"], "--kd", q.get("kd", "0")]
    return args


def servo_overlay_start(log, q, t0, first):
    """None if motionsim can replay a segment starting at t0 (shifted by the position then), else why not"""
    if first:
        return None
    if "ki" in q and (float(q.get("ki", "0")) != 0 or float(q.get("kd", "0")) != 0):
        return "the PID's integral/derivative carry state from the previous setpoint"
    before = [(c, n) for c, d, n in log.motor if t0 - 0.1 * F_CPU <= c <= t0]
    if not before or len({n for _, n in before}) != 1:
        return "the motor was still moving when the setpoint changed"
    return None


def first_sample_s(log, t0, t1):
    """seconds from t0 to the encoder read (chip select falling) of the control period that first
    drove a new duty after t0 (before t1): motionsim's t = 0 is its first sample"""
    d0 = next((d for c, d, n in log.motor if c >= t0), None)
    first = next((c for c, d, n in log.motor if c >= t0 and (t1 is None or c < t1) and abs(d - d0) > 0.01), None)
    reads = [c for c, lv in log.pins.get("CS", []) if lv == 0 and t0 <= c < (first or 0)]
    return (reads[-1] - t0) / F_CPU if reads else 0.0


def shift_csv(path, offset, dt):
    """motionsim servo CSV: offset added to the setpoint and position columns, dt to the time"""
    with open(path) as f:
        lines = f.read().splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        r = line.split(",")
        if len(r) >= 3:
            r[0] = fmt(float(r[0]) + dt)
            r[1] = fmt(float(r[1]) + offset)
            r[2] = fmt(float(r[2]) + offset)
        out.append(",".join(r))
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def shown(path):
    """a path as the user would type it: relative to the current folder when it lies below it"""
    rel = os.path.relpath(path)
    return path if rel.startswith("..") else rel


def has_commands(script):
    return any(l.strip() and not l.strip().startswith("#") for l in script.splitlines())


def remove_old_outputs(out, sketch):
    """build/emulate/<S>.* and <S>-<n>.* of an earlier run (not another sketch's files)"""
    for path in glob.glob(os.path.join(out, glob.escape(sketch) + ".*")) + \
            glob.glob(os.path.join(out, glob.escape(sketch) + "-*")):
        rest = os.path.basename(path)[len(sketch):]
        if rest.startswith(".") or re.match(r"^-\d+\.", rest):
            os.remove(path)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sketch")
    ap.add_argument("--input")
    ap.add_argument("--out", default=os.path.join(emulog.ROOT, "build", "emulate"))
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--live", action="store_true", help="an interactive board: the sketch in real time, its "
                    "serial port a pseudo-terminal (make monitor PORT=<its path>); outputs when it ends")
    ap.add_argument("--source-dir", help="another checkout's firmware/, build/firmware and motionsim")
    a = ap.parse_args(argv)
    env = sketches.Env(source_dir=a.source_dir)
    names = env.sketch_names()
    examples = sketches.example_dirs(env)
    example = a.sketch not in names and a.sketch in examples
    own = ("a sketch of your own: copy its folder to firmware/<Name>/ (<Name>.ino inside, "
           "'// motion-sketch: library' at its top) and give SKETCH=<Name>")
    if a.sketch and ("/" in a.sketch or os.sep in a.sketch):
        print(f"make emulate: SKETCH is a sketch's name under firmware/ or a library example's, not a path "
              f"('{a.sketch}'); {own}", file=sys.stderr)
        return 2
    if not a.sketch or (a.sketch not in names and not example):
        folder = os.path.join(env.source_dir, "firmware", a.sketch or "")
        inos = sorted(f for f in os.listdir(folder) if f.endswith(".ino")) if a.sketch and os.path.isdir(folder) else []
        if len(inos) == 1:
            print(f"make emulate: firmware/{a.sketch} holds {inos[0]}, not {a.sketch}.ino: rename it to {a.sketch}.ino "
                  "(a sketch's .ino must be named like its folder)", file=sys.stderr)
            return 2
        what = f"unknown ('{a.sketch}')" if a.sketch else "missing"
        print(f"make emulate: SKETCH=<name> is {what}; sketches: {' '.join(names)}; library examples: "
              f"{' '.join(sorted(examples))}; {own}", file=sys.stderr)
        return 2
    s = a.sketch
    try:
        # a sketch of your own on our libraries (`// motion-sketch: library`) runs as an example does
        example = example or sketches.family_of(env, s) == "library"
        if example:  # a library example: the RAMPS axes' pins, no console to ask
            fam = sketches.EXAMPLE_FAMILY
            elf = env.elf(s)
            hargs = {"pins": sketches.multiaxis_pins(env)}
        else:
            fam = sketches.family_of(env, s)
            elf = env.elf(s)
            hargs = sketches.harness_args(env, s)
    except sketches.SketchError as e:
        print(f"make emulate: {e}", file=sys.stderr)
        return 2
    if a.live and a.input:
        print("make emulate: LIVE=1 and INPUT= do not go together (with LIVE=1 you type the commands)",
              file=sys.stderr)
        return 2
    if a.input:
        try:
            with open(a.input, encoding="utf-8") as f:
                script = f.read()
        except UnicodeDecodeError as e:
            print(f"make emulate: INPUT '{a.input}' is not a text script (byte {e.start} is not UTF-8)",
                  file=sys.stderr)
            return 2
        except OSError as e:
            print(f"make emulate: cannot read INPUT '{a.input}': {e.strerror}", file=sys.stderr)
            return 2
        if "\x00" in script:
            print(f"make emulate: INPUT '{a.input}' is not a text script (it holds NUL bytes)", file=sys.stderr)
            return 2
        if not has_commands(script):
            print(f"make emulate: INPUT '{a.input}' holds no commands (only blank lines and # comments)",
                  file=sys.stderr)
            return 2
    os.makedirs(a.out, exist_ok=True)
    remove_old_outputs(a.out, s)
    base = os.path.join(a.out, s)
    if example:
        print(f"emulating {s} ({shown(elf)}), {'the example ' + examples[s] if s in examples and s not in names else 'a sketch on our libraries'}: "
              "it runs by itself (no `?` asked); its X, Y and Z pins are logged and plotted", flush=True)
        ready, defaults = True, {}
    else:
        print(f"emulating {s} ({shown(elf)}): asking it `?` at boot ...", flush=True)
        ready, defaults = probe(elf, fam, hargs)
    if not defaults and not example:
        print(f"  {s} did not answer `?` at boot: its parameters are unknown (overlays need a `?` reply); "
              "its pins are logged and plotted all the same")
    if a.live:
        log = run_live(elf, base, hargs)
        script = None
    else:
        if not a.input:
            script = sketches.example_input(s) if example else \
                sketches.default_input(env, s) if defaults else blind_input(s, fam, ready)
        with open(base + ".input.emu", "w") as f:
            f.write(script)
        print(f"  running {a.input or 'the default input (' + shown(base) + '.input.emu)'}; "
              "the serial conversation ('>' to the board, '<' from it, emulated time):", flush=True)
        # the harness reads the user's file itself, so its messages name that file and line
        log = emulog.run(elf, input_path=a.input or base + ".input.emu", log_path=base + ".log",
                         extra=["--echo"], echo=lambda line: print("  " + line, flush=True), **hargs)
    if log.rc == 2:
        msg = " / ".join(l for l in log.stderr.strip().splitlines() if l.strip())
        print(f"make emulate: the harness refused to run: {msg}", file=sys.stderr)
        for ext in (".input.emu", ".log"):
            if os.path.exists(base + ext):
                os.remove(base + ext)
        return 2
    for c, k, t in log.fails:
        print(f"FAIL {k} at {c / F_CPU:.4f} s: {t}")
    print(f"  {len(log.rx)} serial lines, {sum(len(v) for v in log.pins.values())} pin edges, "
          f"{log.end.get('t_s', '?')} s emulated in {log.end.get('wall_s', '?')} s")
    outputs = []   # (firmware csv, motionsim csv or None)
    if fam == "stepper":
        moves = stepper_moves(log)
        from_pins = not moves
        if from_pins:
            moves = edge_moves(log)
            print(f"  no `OK <from> <to>` reply: {len(moves)} move(s) taken from the STEP/DIR pins alone")
            if not moves:
                write_csv(base + ".csv", "step,position,t_s,interval_ticks,speed_sps,accel_sps2", [])
                outputs.append((base + ".csv", None, "no STEP pulse"))
        positions = step_positions(log)
        rises = log.rising("STEP")
        for i, (fr, to, t0, edges, okc, continues) in enumerate(moves):
            chain = i
            while chain > 0 and moves[chain][5]:
                chain -= 1
            # the parameters in force: those of the plan from rest (a new target while moving keeps them)
            q = params_before(log, "pos", moves[chain][4], defaults)
            path = base + (".csv" if i == 0 else f"-{i + 1}.csv")
            tick = float(q.get("tick_hz", "2000000"))
            before = [c for c in rises if c < edges[0]][-2:] if continues and edges else None
            write_csv(path, "step,position,t_s,interval_ticks,speed_sps,accel_sps2",
                      stepper_rows(t0, edges, positions, tick, float(q.get("v0", "0")), before))
            sim = path[:-4] + ".motionsim.csv"
            what = f"move {fr} -> {to} steps" + (" (a new target while moving)" if continues else "") + \
                (" (from the STEP/DIR pins)" if from_pins else "")
            if not q:
                print(f"  no `?` reply before move {fr} -> {to}: no motionsim overlay (send ? first)")
                outputs.append((path, None, what))
                continue
            what += " (" + stepper_params_text(q) + ")"
            if continues:
                why = chain_overlay(env, q, moves, i, sim)
                if why:
                    print(f"  {os.path.basename(path)}: no motionsim overlay ({why})")
                outputs.append((path, None if why else sim, what))
                continue
            if abs(to - fr) > OVERLAY_MAX_STEPS:
                # motionsim's table of the whole move would be millions of rows (its --max-rows)
                print(f"  {os.path.basename(path)}: no motionsim overlay (a move of {abs(to - fr):,} steps, more "
                      f"than the {OVERLAY_MAX_STEPS:,} motionsim tabulates by default)")
                outputs.append((path, None, what))
                continue
            ok = run_motionsim(env, stepper_sim_args(q, fr, to), sim)
            if ok and i + 1 < len(moves) and moves[i + 1][5]:
                # replaced by a new target while moving: the overlay as far as the firmware went
                header, rows = read_rows(sim)
                with open(sim, "w") as f:
                    f.write("\n".join([header] + [",".join(r) for r in rows[:len(edges)]]) + "\n")
            outputs.append((path, sim if ok else None, what))
    elif fam == "multiaxis":
        # every STEP edge of every axis in time order, in motionsim move's columns (t from the first
        # edge; position counted from the pulses and DIR), no overlay: compare with `motionsim move`
        rows, pos = [], {}
        events = sorted((c, ax) for ax in "XYZ" for c in log.rising(ax + "STEP"))
        t0 = events[0][0] if events else 0
        steps = {}
        for c, ax in events:
            fwd = log.level_before(ax + "DIR", c) == 1
            pos[ax] = pos.get(ax, 0) + (1 if fwd else -1)
            steps[ax] = steps.get(ax, 0) + 1
            rows.append(((c - t0) / F_CPU, ax.lower(), steps[ax], pos[ax]))
        write_csv(base + ".csv", "t_s,axis,step,position", rows)
        if rows:
            print(f"  {base}.csv: {len(rows)} edges ({', '.join(f'{k.lower()} {v}' for k, v in sorted(steps.items()))}); "
                  "compare with `motionsim move` (docs/multi-axis.md)")
        else:
            print(f"  {base}.csv: no STEP edge on X, Y or Z")
        # the three positions after every edge, for the plot
        cur, prows = {"x": 0, "y": 0, "z": 0}, []
        for t, ax, _, p in rows:
            cur[ax] = p
            prows.append((t, cur["x"], cur["y"], cur["z"]))
        write_csv(base + ".positions.csv", "t_s,x_position,y_position,z_position", prows)
        if not a.no_plot and prows:
            cmd = [os.path.join(emulog.ROOT, "tools", "plot"), base + ".positions.csv", "--x", "t_s", "--y",
                   "x_position,y_position,z_position", "--title", f"{s} in the emulator: X, Y, Z positions (steps)",
                   "--label", "firmware (emulated)", "-o", base + ".png"]
            p = subprocess.run(cmd, capture_output=True, text=True)
            print(f"  {p.stdout.strip()}" if p.returncode == 0 else f"  plot failed: {p.stderr.strip()}")
        a.no_plot = True
    elif fam == "filter":
        rows = []
        for l in log.rx:
            m = re.match(r"^(\d+),(\d+\.\d+),(-?\d+\.\d+)$", l.text)
            if m:
                t_ms = int(m.group(1))
                rows.append((t_ms // 10, t_ms / 1000.0, float(m.group(2)), float(m.group(3))))
        write_csv(base + ".csv", "k,t_s,u,y", rows)
        q = params_before(log, "kind", float("inf"), defaults)  # updated by later `OK tau=` etc.
        stream = base + ".stream.csv"
        with open(stream, "w") as f:
            f.write("t_ms,u,y\n")
            for k, t, u, y in rows:
                f.write(f"{k * 10},{u:.3f},{y:.6f}\n")
        sim = base + ".motionsim.csv"
        kind = q.get("kind", "ma")
        args = ["filter", "--kind", kind, "--tau", q.get("tau", "9"), "--ts", q.get("ts", "0.01"),
                "--input", f"csv:{stream}"]
        if kind == "ma2":
            args += ["--tau2", q.get("tau2", "3")]
        what = filter_params_text(q, rows)
        outputs.append((base + ".csv", sim if rows and run_motionsim(env, args, sim) else None, what))
    else:
        segs = servo_segments(log)
        if not segs:
            write_csv(base + ".csv", "t_s,setpoint,position_counts,error_counts,duty_pct", [])
            outputs.append((base + ".csv", None, "no setpoint sent"))
        for i, (sp, t0, okc, rows) in enumerate(segs):
            path = base + (".csv" if i == 0 else f"-{i + 1}.csv")
            write_csv(path, "t_s,setpoint,position_counts,error_counts,duty_pct", rows)
            if sp is None:
                print(f"  {os.path.basename(path)}: no setpoint sent or confirmed: the motor and encoder alone")
                outputs.append((path, None, "no setpoint"))
                continue
            q = params_before(log, "setpoint", okc, defaults)
            what = f"setpoint {sp} counts" + (f" from {rows[0][2]}" if i and rows else "") + \
                (f" ({servo_gains_text(q)})" if q else "")
            why = servo_overlay_start(log, q, t0, i == 0) if q else "no `?` reply before this setpoint"
            if why or not rows:
                print(f"  {os.path.basename(path)}: no motionsim overlay ({why or 'no samples'})")
                outputs.append((path, None, what))
                continue
            p0 = rows[0][2] if i else 0
            sim = path[:-4] + ".motionsim.csv"
            dt = first_sample_s(log, t0, segs[i + 1][1] if i + 1 < len(segs) else None)
            if run_motionsim(env, servo_sim_args(q, sp - p0, rows[-1][0] - dt), sim):
                shift_csv(sim, p0, dt)
                outputs.append((path, sim, what))
            else:
                outputs.append((path, None, what))
    print(f"outputs in {shown(a.out)}/:", flush=True)
    for csv, sim, what in outputs:
        print(f"  {shown(csv)}" + (f"  (motionsim: {shown(sim)})" if sim else "  (no overlay)"))
        if not a.no_plot:
            cmd = [os.path.join(emulog.ROOT, "tools", "plot"), csv, "--title", f"{s} in the emulator: {what}",
                   "--label", "firmware (emulated)"]
            if sim:
                cmd += ["--overlay", f"motionsim={sim}"]
            p = subprocess.run(cmd, capture_output=True, text=True)
            print(f"  {shown(p.stdout.strip())}" if p.returncode == 0 else f"  plot failed: {p.stderr.strip()}")
    print(f"  {shown(base)}.log (event log)" +
          (f", {shown(base)}.input.emu (the script)" if script is not None else ""))
    return 1 if log.fails or MOTIONSIM_FAILURES else 0


MOTIONSIM_FAILURES = []


def run_live(elf, base, hargs):
    """The sketch as an interactive board (motionemu --pty): in real time, its UART0 on a pseudo-terminal
    whose path is printed for a monitor; the conversation shown as it happens; Ctrl-C (or the monitor
    closing the port) ends it, and this process goes on to write the outputs."""
    def show(line):
        if line.startswith("pty "):
            path = line[4:].strip()
            print(f"  the emulated Mega's serial port: {path}\n"
                  f"  talk to it as to a board:  make monitor PORT={path}   (or picocom {path}, or pyserial)\n"
                  "  it starts when the port is opened (a Mega resets then) and runs in real time; it ends when\n"
                  "  the monitor closes the port or on Ctrl-C here, and then the CSV and plots are written.",
                  flush=True)
        else:
            print("  " + line, flush=True)
    # Ctrl-C reaches the whole process group: the harness ends its run on it, this process carries on
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    return emulog.run(elf, log_path=base + ".log", extra=["--pty", "--echo"], timeout=None, echo=show, **hargs)


def run_motionsim(env, args, out):
    p = subprocess.run([env.motionsim, *args, "-o", out], capture_output=True, text=True)
    if p.returncode != 0:
        print(f"FAIL motionsim {' '.join(args)}: {p.stderr.strip()}")
        MOTIONSIM_FAILURES.append(args)
        return False
    return True


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
