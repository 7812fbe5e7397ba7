#!/usr/bin/env python3
"""tools/fuzz/run_fuzz.py - the fuzz campaign: every sketch's serial console in the emulator and
motionsim's command line under ASan+UBSan (tools/fuzz/serial_fuzz.py, motionsim_fuzz.py).

  run_fuzz.py --tap                  the short run of `make test` (deterministic: seed 1)
  run_fuzz.py --lines N --seed S     `make fuzz FUZZ_LINES=N FUZZ_SEED=S`: N lines per sketch, a
                                     motionsim run per --sim-ratio lines (default: N / 4 runs)

Every sketch under firmware/ with a `// motion-sketch:` marker (tools/emu/sketches.py) is fuzzed;
a sketch's lines are split into chunks of --chunk lines, each on a fresh boot, run in parallel
(--jobs, default the CPU count). Prints per sketch and for motionsim: lines sent, replies,
failures; with --tap one TAP line each, else a report, and a failing chunk's INPUT script (or
invocation) is kept in --keep (default build/fuzz/failures) to reproduce it:
  build/motionemu build/firmware/<Sketch>/<Sketch>.ino.elf --input <kept script>
Exit status 1 on any failure.
"""
import argparse
import concurrent.futures
import os
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))

import motionsim_fuzz  # noqa: E402
import serial_fuzz  # noqa: E402
import sketches  # noqa: E402


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tap", action="store_true", help="TAP output (make test)")
    ap.add_argument("--lines", type=int, default=None, help="lines per sketch")
    ap.add_argument("--sim-runs", type=int, default=None, help="motionsim invocations")
    ap.add_argument("--seed", default="1")
    ap.add_argument("--chunk", type=int, default=None, help="lines per boot (default 2000; --tap: all in one)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--only", default="", help="only sketches whose name contains this ('motionsim': that part)")
    ap.add_argument("--motionsim-san", default=os.path.join(ROOT, "build", "motionsim-san"))
    ap.add_argument("--keep", default=os.path.join(ROOT, "build", "fuzz", "failures"))
    a = ap.parse_args(argv)
    for name in ("lines", "sim_runs", "chunk", "jobs"):
        v = getattr(a, name)
        if v is not None and v < (0 if name == "sim_runs" else 1):
            ap.error(f"--{name.replace('_', '-')} must be {'0 or more' if name == 'sim_runs' else 'at least 1'}, not {v}")
    if a.lines is None:
        a.lines = TAP_LINES if a.tap else 10000
    if a.sim_runs is None:
        a.sim_runs = TAP_SIM_RUNS if a.tap else max(1, a.lines // 4)
    if a.chunk is None:
        a.chunk = a.lines if a.tap else 2000
    env = sketches.Env()
    names = []
    for s in env.sketch_names():
        try:
            env.family(s)
            env.elf(s)
        except sketches.SketchError as e:
            print(f"run_fuzz: {e}", file=sys.stderr)
            return 2
        if a.only in s:
            names.append(s)
    fuzz_sim = a.sim_runs > 0 and (not a.only or a.only in "motionsim")
    if fuzz_sim and not os.access(a.motionsim_san, os.X_OK):
        print(f"run_fuzz: {a.motionsim_san} is not built (make build/motionsim-san)", file=sys.stderr)
        return 2

    # jobs: (sketch, chunk index, lines) and motionsim parts of at most 250 runs
    jobs = []
    for s in names:
        left, k = a.lines, 0
        while left > 0:
            n = min(a.chunk, left)
            jobs.append(("emu", s, k, n))
            left -= n
            k += 1
    if fuzz_sim:
        left, k = a.sim_runs, 0
        while left > 0:
            n = min(250, left)
            jobs.append(("sim", "motionsim", k, n))
            left -= n
            k += 1
    lock = threading.Lock()
    t0 = time.monotonic()
    done = [0]

    def run(job):
        kind, name, k, n = job
        seed = f"{a.seed}.{k}" if k else a.seed
        t = time.monotonic()
        if kind == "emu":
            o, lines, script = serial_fuzz.run_chunk(env, name, seed, n)
            res = {"lines": o.lines, "replies": o.replies, "blank": o.blank, "moves": o.accepted_moves,
                   "done": o.done, "steps": o.steps, "problems": o.problems, "script": script}
        else:
            o = motionsim_fuzz.fuzz(a.motionsim_san, seed, n, keep_dir=a.keep)
            res = {"runs": o.runs, "exits": o.exits,
                   "problems": [f"motionsim {' '.join(argv)[:300]}: {'; '.join(p)}" for argv, p, _ in o.failures]}
        res["seconds"] = time.monotonic() - t
        with lock:
            done[0] += 1
            print(f"# progress: {done[0]}/{len(jobs)} {name} part {k + 1} ({n} {'lines' if kind == 'emu' else 'runs'}): "
                  f"{len(res['problems'])} failures [{res['seconds']:.1f} s]", flush=True)
        if res["problems"] and kind == "emu":
            os.makedirs(a.keep, exist_ok=True)
            path = os.path.join(a.keep, f"{name}-seed{seed}.emu")
            with open(path, "w") as f:
                f.write(f"# run_fuzz --seed {a.seed}: {name}, part {k + 1}: {len(res['problems'])} failures\n"
                        + "".join(f"#   {p}\n" for p in res["problems"][:20]) + script)
            res["kept"] = path
        return job, res

    # longest first: the emulator's stepper chunks, then the rest
    order = sorted(jobs, key=lambda j: (j[0] != "emu", -j[3]))
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        results = list(pool.map(run, order))

    by_name = {}
    for (kind, name, k, n), res in results:
        agg = by_name.setdefault(name, {"kind": kind, "problems": [], "kept": []})
        for key, v in res.items():
            if key in ("problems",):
                agg["problems"] += v
            elif key == "kept":
                agg["kept"].append(v)
            elif key == "exits":
                e = agg.setdefault("exits", {})
                for rc, c in v.items():
                    e[rc] = e.get(rc, 0) + c
            elif isinstance(v, (int, float)):
                agg[key] = agg.get(key, 0) + v
    order_names = [s for s in names if s in by_name] + (["motionsim"] if "motionsim" in by_name else [])
    wall = time.monotonic() - t0
    total_fail = 0
    tot_lines = tot_replies = 0
    if a.tap:
        print(f"1..{len(order_names)}")
    for i, name in enumerate(order_names, 1):
        g = by_name[name]
        nfail = len(g["problems"])
        total_fail += nfail
        if g["kind"] == "emu":
            tot_lines += g["lines"]
            tot_replies += g["replies"]
            fam = env.family(name)
            what = (f"{name}: {g['lines']} fuzzed lines: {g['replies']} replies ({g['blank']} blank lines, no reply)"
                    + (f", {g['moves']} moves accepted, {g['done']} DONE, {g['steps']} steps" if fam == "stepper" else "")
                    + f", {nfail} failures")
            title = f"{name}: fuzzed serial lines: one reply each, no reset/crash/hang" + \
                    (", no stray STEP" if fam == "stepper" else "")
        else:
            exits = ", ".join(f"exit {rc}: {c}" for rc, c in sorted(g["exits"].items(), key=lambda e: str(e[0])))
            what = f"motionsim (ASan+UBSan): {g['runs']} fuzzed invocations ({exits}), {nfail} failures"
            title = "motionsim: fuzzed invocations under ASan+UBSan: exit 0/1/2, one-line errors, no sanitizer report"
        if a.tap:
            print(f"{'ok' if not nfail else 'not ok'} {i} - {title}")
            for p in g["problems"][:15]:
                print(f"# {p}")
            for p in g["kept"]:
                print(f"# reproduce: build/motionemu {os.path.relpath(env.elf(name), ROOT)} --input {os.path.relpath(p, ROOT)}")
            print(f"# summary: {what} [{g['seconds']:.1f} s]")
        else:
            print(what)
            for p in g["problems"][:15]:
                print(f"    {p}")
            for p in g["kept"]:
                print(f"    reproduce: build/motionemu {os.path.relpath(env.elf(name), ROOT)} --input {os.path.relpath(p, ROOT)}")
    sim = by_name.get("motionsim")
    line = (f"fuzz (seed {a.seed}): {tot_lines} lines sent to {len(names)} sketches, {tot_replies} replies; "
            f"{sim['runs'] if sim else 0} motionsim invocations; {total_fail} failures; {wall:.1f} s wall on {a.jobs} jobs")
    print(f"# summary: {line}" if a.tap else line)
    if total_fail and sim and sim["problems"] and not a.tap:
        print(f"    failing motionsim invocations kept in {os.path.relpath(a.keep, ROOT)}/motionsim-*")
    return 1 if total_fail else 0


# make test's short run: lines per sketch and motionsim invocations, chosen for ~60 s wall on 2 cores
TAP_LINES = 200
TAP_SIM_RUNS = 1000

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
