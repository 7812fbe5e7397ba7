#!/usr/bin/env python3
"""tools/bench/bench.py - what `make bench` runs: the step engine measured in the emulator.

Every stepper sketch under firmware/ (found by its `// motion-sketch: stepper` marker) is built
once more with its speed limit lifted and the TRACE pin on (STEPPER_TRACE=1: D40 high while the
step interrupt runs), then runs the reference move at a ladder of rates: 20,000 steps from rest,
acceleration vmax^2/10,000 steps/s^2 (5,000-step ramps), a `?` sent during the move. For each
run it measures, from the emulated pins (cycle-exact):
  steps      STEP rising edges (must be 20,000) and underruns / late edges from the sketch's `?`
  vs plan    every edge against the algorithm's own whole-tick step times (motionsim ramp:
             --queue for exact, --integer-ticks for the others), aligned at step 1, in ticks:
             the worst error, and how many edges are more than 8 CPU cycles (0.5 us) off
  vs exact   the same against the closed form of constant acceleration, in ticks (exact only)
  ISR        cycles the step interrupt holds the CPU per step (TRACE high, plus the 43 cycles of
             entry, jumps, register saving and return that TRACE cannot see): min / mean / max
  CPU left   the share of the move's time the interrupt leaves to loop() (planner, serial)
A run is clean when all steps come, with no underrun, and every edge is within 8 cycles of its
plan except those that met another interrupt (at most 3 %, each within STEPPER_OTHER_ISR_CYCLES);
errors are taken against the best alignment (the median edge), since the first edge may itself
have met another interrupt. Late edges are counted and shown. The highest clean rate of each sketch is its ceiling; the planner's
own cost per command and per step comes from test/emu/step_avr (lib's planner on the AVR).
Writes build/bench/bench.md (the one home of these figures) and prints it.
"""
import argparse
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))
import emulog  # noqa: E402
import sketches  # noqa: E402

F_CPU = 16_000_000
MOVE = 20000
# What TRACE cannot see of each step interrupt (StepEngineIsr.S): before it rises, the vector's and the
# naked ISR's jumps (3 + 3), push/in/push (5), the waiting test (5) and STEP's sbi (2); after it falls,
# six pops, out and pop (15) and reti (5); and the chip's own 5 cycles of interrupt entry, which
# simavr does not charge: 43 cycles in all, added to every traced interval.
ENTRY_CYCLES = 43
OTHER_ISR_CYCLES = 260     # the bound checks_sketches uses for edges that meet another interrupt
LADDER = {"exact": [20000, 50000, 70000, 80000, 90000, 100000],
          "leib": [5000, 8000, 10000, 12000, 14000],
          "simplistic": [10000, 20000, 30000, 40000, 50000, 60000],
          "sigmoid": [10000, 20000, 30000, 40000, 50000, 60000, 70000]}
LIFT = ("-DSTEPPER_MAX_SPS_EXACT=200000 -DSTEPPER_MAX_SPS_LEIB=100000 -DSTEPPER_MAX_SPS_SIMPLISTIC=100000 "
        "-DSTEPPER_MAX_SPS_SCURVE=100000 -DSTEPPER_TRACE=1")


def build(out_dir, names):
    env = dict(os.environ, FIRMWARE_DEFINES=LIFT, FIRMWARE_OUT=out_dir)
    r = subprocess.run(["bash", os.path.join(ROOT, "tools", "build_firmware.sh")] + names, env=env,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit("bench: building the traced sketches failed:\n" + r.stdout[-2000:])


def params_for(algo, v):
    a = v * v / 10000.0
    if algo == "sigmoid":
        # a table of 1000 entries held 5 steps = 5,000 steps of acceleration, fmin = vmax/20
        return [("len", "1000"), ("hold", "5"), ("v0", f"{v / 20:g}"), ("vmax", f"{v:g}"), ("flex", "5")]
    v0 = v / 10.0 if algo == "simplistic" else 0.0  # the simplistic ramp needs v0 > 0 (F/v0)
    # order: vmax first when it rises (v0 < vmax at every step), accel, v0
    return [("vmax", f"{v:g}"), ("accel", f"{a:g}"), ("v0", f"{v0:g}")]


def script(name, prm):
    s = ["wait ^READY ", "timeout 20000"]
    for k, val in prm:
        s += [f"send set {k} {val}", f"wait ^(OK|ERR) "]
    s += ["send ?", "wait ^pos=", "mark move", f"send {MOVE}", f"wait ^OK 0 {MOVE}$", "send ?", "wait ^pos=",
          "timeout 120000", f"wait ^DONE ", "timeout 5000", "send ?", "wait ^pos="]
    return "\n".join(s) + "\n"


def plan_ticks(motionsim, q):
    """the algorithm's own whole-tick step times (absolute, step 1..D) from motionsim"""
    import emulate  # tools/emu: the argument mapping `make emulate` uses
    args = emulate.stepper_sim_args(q, 0, MOVE)
    r = subprocess.run([motionsim] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"motionsim {' '.join(args)}: {r.stderr.strip()}")
    t, out = 0, []
    for row in r.stdout.splitlines()[1:]:
        if row:
            t += int(float(row.split(",")[3]))
            out.append(t)
    return out


def exact_ticks(q):
    f = float(q["tick_hz"])
    v0, vmax, a, d = float(q["v0"]), float(q["vmax"]), float(q["accel"]), MOVE
    s = (vmax * vmax - v0 * v0) / (2 * a)
    xa = min(s, d / 2)
    vp = vmax if s < d / 2 else math.sqrt(v0 * v0 + 2 * a * xa)
    ta = (vp - v0) / a
    tt = 2 * ta + (d - 2 * xa) / vp

    def acc_t(x):
        return (math.sqrt(v0 * v0 + 2 * a * x) - v0) / a

    def t(n):
        if n <= xa:
            return acc_t(n)
        if n <= d - xa:
            return ta + (n - xa) / vp
        return tt - acc_t(d - n)
    return [round(t(n) * f) for n in range(1, d + 1)]


def run_one(elf, motionsim, name, algo, v, pins):
    prm = params_for(algo, v)
    log = emulog.run(elf, script(name, prm), pins=pins, timeout=900)
    res = {"sketch": name, "algo": algo, "rate": v, "problems": []}
    errs = [l.text for l in log.rx if l.text.startswith("ERR")]
    if errs:
        res["problems"].append("refused: " + "; ".join(errs))
    for c, k, t in log.fails:
        res["problems"].append(f"harness {k}: {t}")
    m = log.mark("move")
    qs = [emulog.query_fields(l.text) for l in log.lines_matching("^pos=", m or 0)]
    q_before = emulog.query_fields(log.lines_matching("^pos=", 0, m)[-1].text) if m else {}
    q_after = qs[-1] if qs else {}
    rises = [c for c in log.rising("STEP") if m is None or c > m]
    res["steps"] = len(rises)
    res["underruns"] = int(q_after.get("underruns", -1))
    res["late"] = int(q_after.get("late", -1))
    tr = log.pins.get("TRACE", [])
    isr = [b[0] - a[0] + ENTRY_CYCLES for a, b in zip(tr, tr[1:]) if a[1] == 1 and b[1] == 0 and (m is None or a[0] > m)]
    res["isr"] = (min(isr), sum(isr) / len(isr), max(isr)) if isr else (0, 0, 0)
    if rises:
        span = rises[-1] - rises[0]
        res["cpu_left"] = 1.0 - sum(isr) / span if span > 0 else 0.0
    if len(rises) != MOVE or not q_before:
        res["problems"].append(f"{len(rises)} steps of {MOVE}")
        return res
    cpt = F_CPU / float(q_before["tick_hz"])
    plan = plan_ticks(motionsim, q_before)
    got = [(c - rises[0]) / cpt for c in rises]

    def compare(ref):
        # aligned at the median edge: the first edge may itself have met another interrupt
        e = [g - (r - ref[0]) for g, r in zip(got, ref)]
        med = sorted(e)[len(e) // 2]
        e = [x - med for x in e]
        worst = max(e, key=abs)
        beyond = sum(1 for x in e if abs(x) * cpt > 8)
        return worst, beyond, max(abs(x) for x in e) * cpt
    res["vs_plan"], res["beyond8"], res["worst_cycles"] = compare(plan)
    if algo == "exact":
        res["vs_exact"], _, _ = compare(exact_ticks(q_before))
    # late edges (fired 2 us after an armed edge was found in the past) are reported; a run is clean
    # when every edge still lands within the bound for edges that meet another interrupt
    clean = (res["underruns"] == 0 and res["beyond8"] <= 0.03 * MOVE and res["worst_cycles"] <= OTHER_ISR_CYCLES)
    if not clean:
        res["problems"].append("not clean")
    return res


def fmt(res):
    if "vs_plan" not in res:
        return (f"| {res['sketch']} | {res['algo']} | {res['rate']:,} | {res['steps']:,} | - | - | - | "
                f"{res.get('underruns', '-')} | {res.get('late', '-')} | - | - | {'; '.join(res['problems'])} |")
    ex = f"{res['vs_exact']:+.2f}" if "vs_exact" in res else "-"
    mn, me, mx = res["isr"]
    verdict = "clean" if not res["problems"] else "; ".join(res["problems"])
    return (f"| {res['sketch']} | {res['algo']} | {res['rate']:,} | {res['steps']:,} | {res['vs_plan']:+.2f} | "
            f"{res['beyond8']} ({res['worst_cycles']:.0f} cyc) | {ex} | {res['underruns']} | {res['late']} | "
            f"{mn} / {me:.0f} / {mx} | {100 * res.get('cpu_left', 0):.0f} % | {verdict} |")


def planner_costs(elf):
    if not elf or not os.path.isfile(elf):
        return []
    log = emulog.run(elf, "timeout 600000\nwait ^end\n", max_ms=600000, timeout=900)
    return [l.text for l in log.rx if l.text.startswith("move ")]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--motionsim", default=os.path.join(ROOT, "build", "motionsim"))
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "bench"))
    ap.add_argument("--planner-elf", default=os.path.join(ROOT, "build", "emu", "step_planner_avr.elf"))
    ap.add_argument("--only", default="", help="sketches whose name contains this")
    a = ap.parse_args(argv)
    env = sketches.Env(source_dir=ROOT)
    names = [n for n in env.sketch_names() if a.only in n and env.family(n) == "stepper"]
    if not names:
        sys.exit("bench: no stepper sketch to measure")
    fw = os.path.join(a.out, "firmware")
    build(fw, names)
    pins = sketches.stepper_pins(env)
    pins["TRACE"] = "D40"
    rows, best = [], {}
    for n in names:
        elf = os.path.join(fw, n, n + ".ino.elf")
        algo = emulog.query_fields(next(l.text for l in emulog.run(elf, "wait ^READY \nsend ?\nwait ^pos=\n").rx
                                        if l.text.startswith("pos=")))["algo"]
        for v in LADDER.get(algo, []):
            res = run_one(elf, a.motionsim, n, algo, v, pins)
            rows.append(res)
            print(fmt(res), flush=True)
            if not res["problems"]:
                best[n] = max(best.get(n, 0), v)
    lines = ["# Step engine benchmark (`make bench`)", "",
             "Generated by tools/bench/bench.py in the ATmega2560 emulator (16 MHz, cycle-exact): the reference move "
             f"of {MOVE:,} steps from rest with acceleration vmax^2/10,000 steps/s^2, a `?` sent during the move, "
             "each sketch built with its speed limit lifted. Errors are in timer ticks (16 MHz for exact, 2 MHz for "
             "the others), aligned at the median edge; 'beyond 8 cycles' counts edges more than 0.5 us off their "
             "plan (those that met another interrupt), with the worst in CPU cycles. ISR cycles include the 43 the "
             "TRACE pin cannot see (entry, jumps, register saving, return).", "",
             "| sketch | algorithm | steps/s | steps | worst vs plan (ticks) | beyond 8 cycles | worst vs exact (ticks) "
             "| underruns | late | ISR cycles min / mean / max | CPU left | verdict |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lines += [fmt(r) for r in rows]
    lines += ["", "Highest clean rate per sketch: " + (", ".join(f"{k} {v:,} steps/s" for k, v in best.items()) or "none"),
              ""]
    pc = planner_costs(a.planner_elf)
    if pc:
        lines += ["Planner on the AVR (lib/src/step_planner.c, test/emu/step_avr): cycles per command and per step of "
                  "the reference move", "", "```"] + pc + ["```", ""]
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "bench.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines))
    print("\n".join(lines[-6:]))
    print(f"written: {os.path.relpath(os.path.join(a.out, 'bench.md'), ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
