#!/usr/bin/env python3
"""tools/emu/emulate.py - what `make emulate SKETCH=<name> [INPUT=<file>]` runs.

Runs the sketch's ELF (build/firmware/<S>/<S>.ino.elf) in the ATmega2560 emulator with an INPUT
script (default: the sketch family's standard scenario), then writes into the output folder:
  <S>.input.emu     the script that ran
  <S>.log           the harness's event log (every serial line, pin edge, motor sample, cycle-exact)
  <S>.csv           the firmware's behaviour in motionsim's CSV format, from its real pins/port:
                    stepper  step,position,t_s,interval_ticks,speed_sps,accel_sps2  (STEP/DIR edges;
                             one file per move: <S>.csv, <S>-2.csv, ...)
                    filter   k,t_s,u,y      (the sketch's serial stream)
                    servo    t_s,setpoint,position_counts,error_counts,duty_pct (encoder count of the
                             emulated motor and the duty measured on the PWM/DIR pins, every 1 ms)
  <S>.motionsim.csv motionsim for the same parameters (read from the sketch's `?` replies and the
                    commands sent), and <S>.png: the firmware's CSV with motionsim's overlaid.
"""
import argparse
import os
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


def last_query(log, key):
    lines = log.lines_matching("^" + key + "=")
    return emulog.query_fields(lines[-1].text) if lines else {}


def frame_cycles(log):
    for cycle, tag, rest in log.events:
        if tag == "uart":
            for w in rest.split():
                if w.startswith("cycles_per_byte="):
                    return int(w.split("=")[1])
    return 16640


# ---- stepper ---------------------------------------------------------------------------------

def stepper_moves(log):
    """[(from, to, t0_cycle, [rising edge cycles])] per 'OK <from> <to>' reply"""
    moves = []
    fc = frame_cycles(log)
    oks = log.lines_matching(r"^OK -?\d+ -?\d+$")
    rises = log.rising("STEP")
    for i, ok in enumerate(oks):
        a, b = (int(x) for x in ok.text.split()[1:3])
        tx = [t for t in log.tx if t.cycle < ok.cycle and t.text.strip() == str(b)]
        # t = 0: the command's line end has arrived (its last byte, one frame per byte)
        t0 = tx[-1].cycle + (len(tx[-1].text) + 2) * fc if tx else ok.cycle
        end = oks[i + 1].cycle if i + 1 < len(oks) else None
        done = log.first(r"^DONE ", ok.cycle, end)
        stop = done.cycle if done else end
        edges = [c for c in rises if c >= t0 and (stop is None or c <= stop)]
        moves.append((a, b, t0, edges))
    return moves


def stepper_rows(a, b, t0, edges, tick_hz, v0):
    cyc_per_tick = F_CPU / tick_hz
    rows = []
    prev_c, prev_dt, prev_v = t0, 0.0, v0
    d = 1 if b >= a else -1
    for n, c in enumerate(edges, 1):
        interval = (c - prev_c) / cyc_per_tick
        dt = interval / tick_hz
        speed = tick_hz / interval if interval > 0 else 0.0
        accel = (speed - prev_v) / ((dt + prev_dt) / 2.0) if (dt + prev_dt) > 0 else 0.0
        rows.append((n, a + d * n, (c - t0) / F_CPU, interval, speed, accel))
        prev_c, prev_dt, prev_v = c, dt, speed
    return rows


def stepper_sim_args(q, a, b):
    algo = q.get("algo", "leib")
    if algo == "sigmoid":
        return ["ramp", "--algo", "sigmoid", "--from", str(a), "--to", str(b), "--len", q["len"], "--fmin", q["v0"],
                "--fmax", q["vmax"], "--flex", q["flex"], "--timer-hz", q["tick_hz"], "--hold", q["hold"],
                "--integer-ticks"]
    return ["ramp", "--algo", algo, "--from", str(a), "--to", str(b), "--v0", q["v0"], "--vmax", q["vmax"],
            "--accel", q["accel"], "--tick-hz", q["tick_hz"], "--integer-ticks"]


# ---- servo -----------------------------------------------------------------------------------

def servo_rows(log):
    fc = frame_cycles(log)
    changes = []  # (effective cycle, setpoint)
    for ok in log.lines_matching(r"^OK setpoint=-?\d+$"):
        sp = int(ok.text.split("=")[1])
        tx = [t for t in log.tx if t.cycle < ok.cycle and t.text.strip() == str(sp)]
        changes.append((tx[-1].cycle + (len(tx[-1].text) + 2) * fc if tx else ok.cycle, sp))
    t0 = changes[0][0] if changes else 0
    rows, sp, i = [], 0, 0
    for c, duty, counts in log.motor:
        while i < len(changes) and changes[i][0] <= c:
            sp = changes[i][1]
            i += 1
        if c >= t0:
            rows.append(((c - t0) / F_CPU, sp, counts, sp - counts, duty))
    return rows, changes


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sketch")
    ap.add_argument("--input")
    ap.add_argument("--out", default=os.path.join(emulog.ROOT, "build", "emulate"))
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--source-dir", help="another checkout's firmware/, build/firmware and motionsim")
    a = ap.parse_args(argv)
    env = sketches.Env(source_dir=a.source_dir)
    names = env.sketch_names()
    if not a.sketch or a.sketch not in names:
        what = f"unknown ('{a.sketch}')" if a.sketch else "missing"
        print(f"make emulate: SKETCH=<name> is {what}; sketches: {' '.join(names)}", file=sys.stderr)
        return 2
    s = a.sketch
    try:
        fam = sketches.family_of(s)
        elf = env.elf(s)
        hargs = sketches.harness_args(env, s)
    except sketches.SketchError as e:
        print(f"make emulate: {e}", file=sys.stderr)
        return 2
    if a.input:
        try:
            script = open(a.input, encoding="utf-8").read()
        except OSError as e:
            print(f"make emulate: cannot read INPUT '{a.input}': {e}", file=sys.stderr)
            return 2
    else:
        script = sketches.default_input(s)
    os.makedirs(a.out, exist_ok=True)
    base = os.path.join(a.out, s)
    with open(base + ".input.emu", "w") as f:
        f.write(script)
    print(f"emulating {s} ({elf}) with {a.input or 'the default input'} ...", flush=True)
    log = emulog.run(elf, script, log_path=base + ".log", **hargs)
    if log.rc == 2:
        print(f"make emulate: the harness refused to run: {log.stderr.strip()}", file=sys.stderr)
        return 2
    for c, k, t in log.fails:
        print(f"FAIL {k} at {c / F_CPU:.4f} s: {t}")
    print(f"  {len(log.rx)} serial lines, {sum(len(v) for v in log.pins.values())} pin edges, "
          f"{log.end.get('t_s', '?')} s emulated in {log.end.get('wall_s', '?')} s")
    outputs = []   # (firmware csv, motionsim csv or None)
    if fam == "stepper":
        q = {}
        for l in log.rx:
            if l.text.startswith("pos="):
                q = emulog.query_fields(l.text)
                break
        for i, (fr, to, t0, edges) in enumerate(stepper_moves(log)):
            path = base + (".csv" if i == 0 else f"-{i + 1}.csv")
            tick = float(q.get("tick_hz", "2000000"))
            write_csv(path, "step,position,t_s,interval_ticks,speed_sps,accel_sps2",
                      stepper_rows(fr, to, t0, edges, tick, float(q.get("v0", "0"))))
            sim = path[:-4] + ".motionsim.csv"
            outputs.append((path, sim if run_motionsim(env, stepper_sim_args(q, fr, to), sim) else None))
    elif fam == "filter":
        import re
        rows = []
        for l in log.rx:
            m = re.match(r"^(\d+),(\d+\.\d+),(-?\d+\.\d+)$", l.text)
            if m:
                t_ms = int(m.group(1))
                rows.append((t_ms // 10, t_ms / 1000.0, float(m.group(2)), float(m.group(3))))
        write_csv(base + ".csv", "k,t_s,u,y", rows)
        q = last_query(log, "kind")
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
        outputs.append((base + ".csv", sim if rows and run_motionsim(env, args, sim) else None))
    else:
        rows, changes = servo_rows(log)
        write_csv(base + ".csv", "t_s,setpoint,position_counts,error_counts,duty_pct", rows)
        q = last_query(log, "setpoint")
        sim = base + ".motionsim.csv"
        args = ["servo", "--ctrl", "pid" if "ki" in q else "p", "--kp", q.get("kp", "0.02"),
                "--setpoint", str(changes[0][1] if changes else 0),
                "--duration", f"{max(0.02, rows[-1][0] if rows else 1.0):.3f}"]
        if "ki" in q:
            args += ["--ki", q["ki"], "--kd", q.get("kd", "0")]
        outputs.append((base + ".csv", sim if changes and run_motionsim(env, args, sim) else None))
    for csv, sim in outputs:
        print(f"  {csv}" + (f"  (motionsim: {sim})" if sim else ""))
        if not a.no_plot:
            cmd = [os.path.join(emulog.ROOT, "tools", "plot"), csv, "--title", f"{s}: firmware in the emulator"]
            if sim:
                cmd += ["--overlay", f"motionsim={sim}"]
            p = subprocess.run(cmd, capture_output=True, text=True)
            print(f"  {p.stdout.strip()}" if p.returncode == 0 else f"  plot failed: {p.stderr.strip()}")
    print(f"  {base}.log (event log), {base}.input.emu (the script)")
    return 1 if log.fails or MOTIONSIM_FAILURES else 0


MOTIONSIM_FAILURES = []


def run_motionsim(env, args, out):
    p = subprocess.run([env.motionsim, *args, "-o", out], capture_output=True, text=True)
    if p.returncode != 0:
        print(f"FAIL motionsim {' '.join(args)}: {p.stderr.strip()}")
        MOTIONSIM_FAILURES.append(args)
        return False
    return True


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
