#!/usr/bin/env python3
"""tools/fuzz/run_fuzz.py - the fuzz campaign: every sketch's serial console in the emulator and
motionsim's command line under ASan+UBSan (tools/fuzz/serial_fuzz.py, motionsim_fuzz.py).

  run_fuzz.py --tap                  the short run of `make test` (deterministic: seed 1)
  run_fuzz.py --lines N --seed S     `make fuzz FUZZ_LINES=N FUZZ_SEED=S`: N lines over all sketches,
                                     --sim-runs motionsim runs (default N / 20)
  run_fuzz.py --selftest             only the oracles' self-test (fuzz_selftest.py)

Every sketch under firmware/ with a `// motion-sketch:` marker (tools/emu/sketches.py) is fuzzed
with each kind that applies to it: random lines (serial_fuzz.py) and fuzz_scenarios.py's floods,
fast moves, set while moving, MultiAxisStepper at speed; its limits are asked from the sketch
first (fuzz_scenarios.Limits.probe). A sketch's lines of a kind are split into chunks of --chunk
lines, each on a fresh boot, run in parallel (--jobs, default the CPU count). Prints per sketch
and kind: lines sent, replies, steps and intervals checked, findings; with --tap one TAP line
per sketch, else a report; --summary FILE writes the report as Markdown (make fuzz:
docs/fuzz-summary.md). A failing chunk's INPUT script is kept in --keep (default
build/fuzz/failures) to reproduce it:
  build/motionemu build/firmware/<Sketch>/<Sketch>.ino.elf --input <kept script> --matches
Exit status 1 on any finding.
"""
import argparse
import concurrent.futures
import datetime
import os
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))

import fuzz_scenarios  # noqa: E402
import fuzz_selftest  # noqa: E402
import motionsim_fuzz  # noqa: E402
import serial_fuzz  # noqa: E402
import sketches  # noqa: E402

# make test's short run: lines per sketch of each kind and motionsim invocations, for ~40 s wall on 2 cores
TAP_LINES = {"lines": 100, "flood": 25, "fast": 10, "setmove": 10, "multi": 24}
TAP_SIM_RUNS = 1000
# the long run: the share of a sketch's lines each kind gets (of the kinds that apply to it)
KIND_WEIGHT = {"lines": 4, "flood": 2, "fast": 2, "setmove": 2, "multi": 4}
KIND_TEXT = {"lines": "random lines, one per reply", "flood": "floods (lines sent without waiting)",
             "fast": "fast moves, retargets, stop and ! at speed", "setmove": "set v0|vmax|accel while moving",
             "multi": "three axes at speed, coordinated moves"}
COUNTERS = ("lines", "replies", "blank", "flood_lines", "overrun_lines", "accepted_moves", "done", "steps",
            "pairs", "reversals", "queries")


def split_lines(total, kinds):
    w = sum(KIND_WEIGHT[k] for k in kinds)
    out = {k: total * KIND_WEIGHT[k] // w for k in kinds}
    out[kinds[0]] += total - sum(out.values())
    return out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tap", action="store_true", help="TAP output (make test)")
    ap.add_argument("--lines", type=int, default=None, help="lines over all sketches (default 10000)")
    ap.add_argument("--sim-runs", type=int, default=None, help="motionsim invocations")
    ap.add_argument("--seed", default="1")
    ap.add_argument("--chunk", type=int, default=None, help="lines per boot (default 500; --tap: all in one)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--only", default="", help="only sketches whose name contains this ('motionsim': that part)")
    ap.add_argument("--kinds", default="", help="only these kinds (comma-separated: lines,flood,fast,setmove,multi)")
    ap.add_argument("--summary", default=None, help="write the report as Markdown to this file")
    ap.add_argument("--selftest", action="store_true", help="only the oracles' self-test")
    ap.add_argument("--motionsim-san", default=os.path.join(ROOT, "build", "motionsim-san"))
    ap.add_argument("--keep", default=os.path.join(ROOT, "build", "fuzz", "failures"))
    a = ap.parse_args(argv)
    for name in ("lines", "sim_runs", "chunk", "jobs"):
        v = getattr(a, name)
        if v is not None and v < (0 if name == "sim_runs" else 1):
            ap.error(f"--{name.replace('_', '-')} must be {'0 or more' if name == 'sim_runs' else 'at least 1'}, not {v}")
    kinds_only = [k for k in a.kinds.split(",") if k]
    for k in kinds_only:
        if k not in ("lines",) + tuple(fuzz_scenarios.KINDS):
            ap.error(f"--kinds: unknown kind '{k}' (lines, {', '.join(fuzz_scenarios.KINDS)})")
    st_problems, st_count = fuzz_selftest.run()
    if a.selftest:
        for p in st_problems:
            print(f"selftest: {p}")
        print(f"oracle self-test: {st_count} synthetic cases, {len(st_problems)} failures")
        return 1 if st_problems else 0
    if a.lines is None:
        a.lines = 10000
    if a.sim_runs is None:
        a.sim_runs = TAP_SIM_RUNS if a.tap else max(1, a.lines // 20)
    if a.chunk is None:
        a.chunk = 10 ** 9 if a.tap else 500
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
    fuzz_sim = a.sim_runs > 0 and (not a.only or a.only in "motionsim") and (not kinds_only)
    if fuzz_sim and not os.access(a.motionsim_san, os.X_OK):
        print(f"run_fuzz: {a.motionsim_san} is not built (make build/motionsim-san)", file=sys.stderr)
        return 2

    # each sketch's limits, from the sketch itself
    limits = {}
    for s in names:
        try:
            limits[s] = fuzz_scenarios.Limits.probe(env, s)
        except RuntimeError as e:
            print(f"run_fuzz: {e}", file=sys.stderr)
            return 1
    # jobs: (kind, sketch, fuzz kind, chunk index, lines) and motionsim parts of at most 250 runs
    jobs = []
    per_sketch = max(1, a.lines // max(1, len(names)))
    for s in names:
        kinds = ["lines"] + fuzz_scenarios.kinds_for(env.family(s))
        if kinds_only:
            kinds = [k for k in kinds if k in kinds_only]
        if not kinds:
            continue
        counts = {k: TAP_LINES[k] for k in kinds} if a.tap else split_lines(per_sketch, kinds)
        for kind, n_kind in counts.items():
            left, k = n_kind, 0
            while left > 0:
                n = min(a.chunk, left)
                jobs.append(("emu", s, kind, k, n))
                left -= n
                k += 1
    if fuzz_sim:
        left, k = a.sim_runs, 0
        while left > 0:
            n = min(250, left)
            jobs.append(("sim", "motionsim", "runs", k, n))
            left -= n
            k += 1
    lock = threading.Lock()
    t0 = time.monotonic()
    done = [0]

    def run(job):
        what, name, kind, k, n = job
        seed = f"{a.seed}.{k}" if k else a.seed
        t = time.monotonic()
        if what == "emu":
            try:
                o, items, script = serial_fuzz.run_chunk(env, name, seed, n, kind, lim=limits[name])
                res = {c: getattr(o, c) for c in COUNTERS}
                res["problems"] = o.problems
            except RuntimeError as e:   # the harness itself ran over its wall-time limit
                res, script = {"lines": 0, "problems": [f"{kind}: {e}"]}, ""
            res["script"] = script
        else:
            o = motionsim_fuzz.fuzz(a.motionsim_san, seed, n, keep_dir=a.keep)
            res = {"runs": o.runs, "exits": o.exits,
                   "problems": [f"motionsim {' '.join(argv)[:300]}: {'; '.join(p)}" for argv, p, _ in o.failures]}
        res["seconds"] = time.monotonic() - t
        with lock:
            done[0] += 1
            print(f"# progress: {done[0]}/{len(jobs)} {name} {kind} part {k + 1} ({n} "
                  f"{'lines' if what == 'emu' else 'runs'}): {len(res['problems'])} findings [{res['seconds']:.1f} s]",
                  flush=True)
        if res["problems"] and what == "emu":
            os.makedirs(a.keep, exist_ok=True)
            path = os.path.join(a.keep, f"{name}-{kind}-seed{seed}.emu")
            with open(path, "w") as f:
                f.write(f"# run_fuzz --seed {a.seed}: {name}, {kind}, part {k + 1}: {len(res['problems'])} findings\n"
                        + "".join("".join(f"#   {line}\n" for line in p.splitlines() or [""])
                                  for p in res["problems"][:20]) + res["script"])
            res["kept"] = path
        return job, res

    # longest first: the emulator's chunks, then the rest
    order = sorted(jobs, key=lambda j: (j[0] != "emu", -j[4]))
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        results = list(pool.map(run, order))

    by_name = {}
    for (what, name, kind, k, n), res in results:
        agg = by_name.setdefault(name, {"what": what, "problems": [], "kept": [], "kinds": {}})
        kagg = agg["kinds"].setdefault(kind, {})
        for key, v in res.items():
            if key == "problems":
                agg["problems"] += [f"{kind}: {p}" if what == "emu" else p for p in v]
                kagg["findings"] = kagg.get("findings", 0) + len(v)
            elif key == "kept":
                agg["kept"].append(v)
            elif key == "exits":
                e = agg.setdefault("exits", {})
                for rc, c in v.items():
                    e[rc] = e.get(rc, 0) + c
            elif isinstance(v, (int, float)):
                agg[key] = agg.get(key, 0) + v
                kagg[key] = kagg.get(key, 0) + v
    order_names = [s for s in names if s in by_name] + (["motionsim"] if "motionsim" in by_name else [])
    wall = time.monotonic() - t0
    total_fail = len(st_problems)
    tot = {c: 0 for c in COUNTERS}
    if a.tap:
        print(f"1..{len(order_names) + 1}")
        print(f"{'ok' if not st_problems else 'not ok'} 1 - the fuzz oracles fail on synthetic bad traces and pass good ones")
        for p in st_problems:
            print(f"# {p}")
        print(f"# summary: oracle self-test: {st_count} synthetic cases, {len(st_problems)} failures")
    for i, name in enumerate(order_names, 2):
        g = by_name[name]
        nfail = len(g["problems"])
        total_fail += nfail
        if g["what"] == "emu":
            for c in COUNTERS:
                tot[c] += g.get(c, 0)
            fam = env.family(name)
            moving = fam in ("stepper", "multiaxis")
            per_kind = ", ".join(f"{k} {v.get('lines', 0)}" for k, v in g["kinds"].items())
            what = (f"{name}: {g['lines']} lines ({per_kind})"
                    f": {g['replies']} replies, {g['flood_lines']} sent in floods ({g['overrun_lines']} counted lost)"
                    + (f", {g['accepted_moves']} moves, {g['done']} DONE, {g['steps']} steps, {g['pairs']} interval "
                       f"pairs and {g['reversals']} reversals checked, {g['queries']} `?` with underruns=0"
                       if moving else "")
                    + f", {nfail} findings")
            title = f"{name}: fuzzed serial conversations: one reply each, no reset/crash/hang, floods accounted" + \
                    (", STEP/DIR = OK/DONE/?, speed law" if moving else "")
        else:
            exits = ", ".join(f"exit {rc}: {c}" for rc, c in sorted(g["exits"].items(), key=lambda e: str(e[0])))
            what = f"motionsim (ASan+UBSan): {g['runs']} fuzzed invocations ({exits}), {nfail} findings"
            title = "motionsim: fuzzed invocations under ASan+UBSan: exit 0/1/2, one-line errors, no sanitizer report"
        if a.tap:
            print(f"{'ok' if not nfail else 'not ok'} {i} - {title}")
            for p in g["problems"][:15]:
                print(f"# {p}")
            for p in g["kept"]:
                print(f"# reproduce: build/motionemu {os.path.relpath(env.elf(name), ROOT)} --input "
                      f"{os.path.relpath(p, ROOT)} --matches")
            print(f"# summary: {what} [{g['seconds']:.1f} s]")
        else:
            print(what)
            for p in g["problems"][:15]:
                print(f"    {p}")
            for p in g["kept"]:
                print(f"    reproduce: build/motionemu {os.path.relpath(env.elf(name), ROOT)} --input "
                      f"{os.path.relpath(p, ROOT)} --matches")
    sim = by_name.get("motionsim")
    line = (f"fuzz (seed {a.seed}): {tot['lines']} lines sent to {len(names)} sketches, {tot['replies']} replies, "
            f"{tot['steps']} steps; {sim['runs'] if sim else 0} motionsim invocations; {total_fail} findings; "
            f"{wall:.1f} s wall on {a.jobs} jobs")
    print(f"# summary: {line}" if a.tap else line)
    if total_fail and sim and sim["problems"] and not a.tap:
        print(f"    failing motionsim invocations kept in {os.path.relpath(a.keep, ROOT)}/motionsim-*")
    if a.summary:
        write_summary(a, env, names, order_names, by_name, tot, total_fail, st_count, st_problems, wall)
    return 1 if total_fail else 0


def git(*args):
    try:
        return subprocess.run(["git", "-C", ROOT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                              text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def write_summary(a, env, names, order_names, by_name, tot, total_fail, st_count, st_problems, wall):
    commit = git("rev-parse", "--short=12", "HEAD") or "unknown"
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", "firmware", "lib", "tools/fuzz", "tools/emu")
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = ["# Fuzz summary", "",
           "Generated by `make fuzz` (tools/fuzz/run_fuzz.py --summary); do not edit: the next run rewrites it.", "",
           f"- command: `make fuzz FUZZ_LINES={a.lines} FUZZ_SEED={a.seed}` ({a.chunk} lines per boot, {a.jobs} jobs)",
           f"- commit: {commit}" + (" with local changes in firmware/, lib/ or tools/" if dirty else ""),
           f"- date: {now}; {wall / 60:.1f} min wall",
           f"- lines sent: {tot['lines']} to {len(names)} sketches; replies {tot['replies']}; "
           f"lines sent in floods {tot['flood_lines']} ({tot['overrun_lines']} counted lost in `ERR input overrun`)",
           f"- steps checked: {tot['steps']} STEP edges against OK/DONE/`?`; {tot['pairs']} consecutive interval pairs "
           f"against the ramp's law; {tot['reversals']} reversals; {tot['queries']} `?` replies with underruns=0",
           f"- oracle self-test: {st_count} synthetic cases, {len(st_problems)} failures",
           f"- **findings: {total_fail}**", "",
           "| sketch | kind | lines | replies | flood lines (lost) | steps | interval pairs | findings |",
           "|---|---|---:|---:|---:|---:|---:|---:|"]
    for name in order_names:
        g = by_name[name]
        if g["what"] != "emu":
            continue
        for kind, k in g["kinds"].items():
            out.append(f"| {name} | {kind}: {KIND_TEXT[kind]} | {k.get('lines', 0)} | {k.get('replies', 0)} | "
                       f"{k.get('flood_lines', 0)} ({k.get('overrun_lines', 0)}) | {k.get('steps', 0)} | "
                       f"{k.get('pairs', 0)} | {k.get('findings', 0)} |")
    sim = by_name.get("motionsim")
    if sim:
        exits = ", ".join(f"exit {rc}: {c}" for rc, c in sorted(sim["exits"].items(), key=lambda e: str(e[0])))
        out += ["", f"motionsim under ASan+UBSan: {sim['runs']} invocations ({exits}), {len(sim['problems'])} findings."]
    if total_fail:
        out += ["", "## Findings", ""]
        for name in order_names:
            for p in by_name[name]["problems"][:20]:
                out.append(f"- {name}: {p}")
            if len(by_name[name]["problems"]) > 20:
                out.append(f"- {name}: … and {len(by_name[name]['problems']) - 20} more")
        for p in st_problems:
            out.append(f"- oracle self-test: {p}")
    os.makedirs(os.path.dirname(os.path.abspath(a.summary)), exist_ok=True)
    with open(a.summary, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
