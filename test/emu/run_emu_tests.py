#!/usr/bin/env python3
"""test/emu/run_emu_tests.py - the emulator suite of `make test`: every check as one TAP line.

Each check runs build/motionemu on a firmware ELF (the harness self-test program, lib's PID module
with the PID_v1 float32 vectors, lib's number parser with decimal words and their nearest floats,
then every sketch under firmware/ and the MotionStepper library's examples), compares what the firmware's pins and serial port did with motionsim
and the sketches' documented behaviour, and prints
    ok N - <check>            (or "not ok N - <check>" followed by "# <problem>" lines)
    # summary: <check>: <figures>
Checks run in parallel (one emulator process each, as many at a time as there are CPUs).

Options (for development; `make test` passes none):
  --tap                      TAP output (default)
  --only SUBSTRING           run only checks whose name contains SUBSTRING
  --firmware-dir DIR         take <DIR>/<Sketch>/<Sketch>.ino.elf instead of build/firmware
  --source-dir DIR           read firmware/ (sketch list, pin headers) from DIR instead of this tree
  --motionsim PATH           motionsim to compare with (default build/motionsim)
  --list                     print the check names
"""
import argparse
import concurrent.futures
import os
import sys
import threading
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))
sys.path.insert(0, HERE)

import sketches  # noqa: E402  (tools/emu/sketches.py)
import checks_pid  # noqa: E402
import checks_selftest  # noqa: E402
import checks_text_parse  # noqa: E402
import checks_sketches  # noqa: E402
import checks_multiaxis  # noqa: E402
import checks_serial  # noqa: E402
import checks_reliability  # noqa: E402
import checks_library  # noqa: E402


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tap", action="store_true")
    ap.add_argument("--only", default="")
    ap.add_argument("--firmware-dir", default=None)
    ap.add_argument("--source-dir", default=None)
    ap.add_argument("--motionsim", default=None)
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    a = ap.parse_args(argv)
    env = sketches.Env(firmware_dir=a.firmware_dir, source_dir=a.source_dir, motionsim=a.motionsim)

    checks = (list(checks_selftest.CHECKS) + list(checks_pid.CHECKS) + list(checks_text_parse.CHECKS)
              + checks_sketches.checks_for(env) + checks_multiaxis.checks_for(env) + checks_serial.checks_for(env)
              + checks_reliability.checks_for(env) + checks_library.checks_for(env))
    checks = [(n, f) for n, f in checks if a.only in n]
    if a.list:
        for n, _ in checks:
            print(n)
        return 0
    print(f"1..{len(checks)}", flush=True)
    t0 = time.monotonic()

    def run_one(fn):
        t = time.monotonic()
        try:
            res = fn()
        except Exception:  # a crash of a check is a failure of that check, with its traceback
            res = checks_selftest.CheckResult(False, "the check itself crashed",
                                              traceback.format_exc().splitlines()[-12:])
        res.seconds = time.monotonic() - t
        return res

    finished = [0]
    lock = threading.Lock()

    def emit(lines):
        """whole lines, one block at a time: the workers' progress lines never split a result's"""
        with lock:
            sys.stdout.write("".join(line + "\n" for line in lines))
            sys.stdout.flush()

    def run_and_report(name, fn):
        res = run_one(fn)
        with lock:
            finished[0] += 1
            n = finished[0]
        # results print in list order; this line says at once that a check is done
        emit([f"# progress: {n}/{len(checks)} {'ok' if res.ok else 'FAILED'} - {name} [{res.seconds:.1f} s]"])
        return res

    # Long checks first so that two CPUs stay busy to the end (results are printed in list order).
    def weight(name):
        return 0 if "60 s" in name else 1 if "moves" in name else 2
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        order = sorted(range(len(checks)), key=lambda i: weight(checks[i][0]))
        by_index = {i: pool.submit(run_and_report, checks[i][0], checks[i][1]) for i in order}
        futures = [by_index[i] for i in range(len(checks))]
        failed = 0
        for i, ((name, _), fut) in enumerate(zip(checks, futures), 1):
            res = fut.result()
            block = [f"ok {i} - {name}" if res.ok else f"not ok {i} - {name}"]
            if not res.ok:
                failed += 1
                block += [f"# {line}" for d in res.details[:25] for line in str(d).splitlines()]
            block.append(f"# summary: {name}: {res.summary} [{res.seconds:.1f} s]")
            emit(block)
    print(f"# summary: emulator suite: {len(checks)} checks, {failed} failed, {time.monotonic() - t0:.1f} s wall "
          f"on {a.jobs} workers; sketches checked: {', '.join(env.sketch_names()) or 'none'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
