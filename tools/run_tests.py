#!/usr/bin/env python3
"""tools/run_tests.py - run every test suite and print one summary line (what `make test` runs).

Usage: run_tests.py "NAME|KIND|TARGET" ...

KIND is one of
  tap-dir   every executable file in directory TARGET is a cmocka test program printing TAP
  tap       TARGET is a shell command printing TAP (the emulator harness does this)
  pytest    TARGET is a directory of pytest files (results read from a JUnit XML report)
  firmware  TARGET is tools/build_firmware.sh; each build is one test: the sketches (firmware/*), the
            libraries' examples (lib/examples/*, firmware/libraries/*/examples/*)

A suite line "NAME: P passed, F failed" is printed per suite, failing tests are listed with
their messages, and the last line is "N passed, N failed". While a suite runs, its progress is
shown (see Progress): each suite says what it has done at least every 15 s. The exit status is 1 on any failure
(a crash, a missing TAP plan or a missing test counts as a failure).
"""
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class Result:
    def __init__(self):
        self.passed = 0
        self.failed = 0
        self.failures = []  # (test name, detail text)
        self.notes = []     # summary lines worth showing (e.g. "# figures: ...")

    def ok(self):
        self.passed += 1

    def fail(self, name, detail=""):
        self.failed += 1
        self.failures.append((name, detail.strip()))


def parse_tap(text, prefix, res, rc):
    """Count TAP results; a missing plan, a short run or a non-zero exit without failures fail."""
    plan = None
    seen = 0
    fails_here = 0
    last_fail = None
    for line in text.splitlines():
        m = re.match(r'^1\.\.(\d+)', line)
        if m:
            plan = int(m.group(1))
            continue
        m = re.match(r'^(not )?ok\b\s*\d*\s*-?\s*(.*)$', line)
        if m:
            seen += 1
            name = f"{prefix}{m.group(2)}"
            if m.group(1):
                res.fail(name)
                last_fail = len(res.failures) - 1
                fails_here += 1
            else:
                res.ok()
                last_fail = None
            continue
        if line.startswith('# progress:'):
            continue
        if line.startswith('# ') and last_fail is not None:
            n, d = res.failures[last_fail]
            res.failures[last_fail] = (n, d + "\n" + line[2:])
        elif line.startswith('# summary:') or line.startswith('# figures:'):
            res.notes.append(line[2:])
    if plan is None:
        res.fail(f"{prefix}(no TAP plan: the program crashed or printed nothing)", text[-2000:])
    elif seen < plan:
        res.fail(f"{prefix}({plan - seen} of {plan} tests did not report: crash?)", text[-2000:])
    elif rc != 0 and fails_here == 0:
        res.fail(f"{prefix}(exit status {rc} with all tests passing)", text[-2000:])


class Progress:
    """Progress lines of the running suite, so that a long suite is never silent: what each step
    finished ("[NAME] 3/6 build LeibRampStepper ok (12 s)"), a program's own progress lines
    (pytest's percentages, the emulator's ok/not ok lines), and a line every HEARTBEAT_S seconds
    while nothing else was printed."""
    HEARTBEAT_S = 15.0

    def __init__(self, name):
        self.name = name
        self.t0 = time.monotonic()
        self.last = self.t0
        self.lock = threading.Lock()
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._beat, daemon=True)
        self.thread.start()

    def say(self, text):
        with self.lock:
            self.last = time.monotonic()
            print(f"  [{self.name}] {text} ({self.last - self.t0:.0f} s)", flush=True)

    def _beat(self):
        while not self.done.wait(1.0):
            if time.monotonic() - self.last >= self.HEARTBEAT_S:
                self.say("still running")

    def stop(self):
        self.done.set()
        self.thread.join()


PROGRESS = None   # the running suite's Progress


def say(text):
    if PROGRESS is not None:
        PROGRESS.say(text)


def run(cmd, timeout=900, env=None, cwd=ROOT, on_line=None):
    """(exit status, output) of cmd; on_line(line) is called for each output line as it comes."""
    try:
        p = subprocess.Popen(cmd, shell=isinstance(cmd, str), cwd=cwd, env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True, errors='replace')
    except OSError as e:
        return 127, f"cannot run {cmd}: {e}"
    out = []
    killed = []

    def kill():
        killed.append(True)
        p.kill()
    timer = threading.Timer(timeout, kill)
    timer.start()
    try:
        for line in p.stdout:
            out.append(line)
            if on_line:
                on_line(line.rstrip("\n"))
        rc = p.wait()
    finally:
        timer.cancel()
    text = "".join(out)
    if killed:
        return 124, text + f"\n(timed out after {timeout} s)"
    return rc, text


def suite_tap_dir(target, res):
    if not os.path.isdir(target):
        res.fail(f"{target} (directory missing: nothing was built)")
        return
    progs = sorted(f for f in os.listdir(target)
                   if os.path.isfile(os.path.join(target, f)) and os.access(os.path.join(target, f), os.X_OK))
    if not progs:
        res.fail(f"{target} (no test programs)")
    env = dict(os.environ, CMOCKA_MESSAGE_OUTPUT="TAP")
    t_last = time.monotonic()
    for i, p in enumerate(progs, 1):
        rc, out = run([os.path.join(target, p)], env=env)
        parse_tap(out, f"{p}: ", res, rc)
        if time.monotonic() - t_last > 3 or i == len(progs):
            say(f"{i}/{len(progs)} programs ({p})")
            t_last = time.monotonic()


def suite_tap(target, res):
    plan = [None]

    def on_line(line):
        m = re.match(r'^1\.\.(\d+)', line)
        if m:
            plan[0] = int(m.group(1))
        m = re.match(r'^(not ok|ok) (\d+) - (.*)$', line)
        if m:
            say(f"{m.group(2)}/{plan[0] or '?'} {m.group(1)} - {m.group(3)[:90]}")
        m = re.match(r'^# progress: (.*)$', line)   # a check finished (printed as it ends)
        if m:
            say(f"finished {m.group(1)[:110]}")
    rc, out = run(target, on_line=on_line)
    parse_tap(out, "", res, rc)


def suite_pytest(target, res):
    with tempfile.TemporaryDirectory() as tmp:
        xml_path = os.path.join(tmp, "junit.xml")
        last = [0.0]

        def on_line(line):
            # pytest -v: "test/cli/test_x.py::test_y PASSED   [ 37%]": say it every 5 s, and every failure
            m = re.match(r'^(.+?::.+?) (PASSED|FAILED|ERROR|SKIPPED)\s+\[\s*(\d+)%\]\s*$', line)
            if m and (m.group(2) != "PASSED" or time.monotonic() - last[0] >= 5):
                last[0] = time.monotonic()
                say(f"{m.group(3)} % done, {m.group(2).lower()}: {m.group(1)}")
        rc, out = run([sys.executable, "-m", "pytest", "-v", "-p", "no:cacheprovider",
                       f"--junitxml={xml_path}", target], on_line=on_line)
        if not os.path.exists(xml_path):
            res.fail(f"{target} (pytest produced no report)", out[-3000:])
            return
        root = ET.parse(xml_path).getroot()
        cases = root.iter('testcase')
        count = 0
        for c in cases:
            count += 1
            name = f"{c.get('classname', '')}.{c.get('name')}".lstrip('.')
            bad = c.find('failure') if c.find('failure') is not None else c.find('error')
            if bad is not None:
                res.fail(name, (bad.get('message') or '') + "\n" + (bad.text or '')[-1500:])
            elif c.find('skipped') is not None:
                res.fail(name, "skipped (a test that does not run cannot pass)")
            else:
                res.ok()
        if count == 0:
            res.fail(f"{target} (no tests collected)", out[-3000:])
        elif rc not in (0, 1):
            res.fail(f"{target} (pytest exit status {rc})", out[-3000:])


def firmware_builds(root=ROOT):
    """what tools/build_firmware.sh builds, one argument each: the sketches (firmware/<S>), then the
    libraries' Arduino examples, a user's own sketch using them: lib/examples/<X> (MotionCore) and
    firmware/libraries/<Lib>/examples/<X> (MotionStepper's, ...), as folders"""
    def with_ino(parent):
        path = os.path.join(root, parent)
        return sorted(d for d in os.listdir(path) if os.path.isfile(os.path.join(path, d, d + ".ino"))) \
            if os.path.isdir(path) else []
    builds = with_ino("firmware")
    libraries = os.path.join(root, "firmware", "libraries")
    parents = ["lib/examples"]
    if os.path.isdir(libraries):
        parents += [f"firmware/libraries/{lib}/examples" for lib in sorted(os.listdir(libraries))]
    for parent in parents:
        builds += [f"{parent}/{d}" for d in with_ino(parent)]
    return builds


def suite_firmware(target, res):
    sketches = firmware_builds()
    if not sketches:
        res.fail("firmware (no sketches)")
    for i, s in enumerate(sketches, 1):
        rc, out = run(["bash", target, s])
        say(f"{i}/{len(sketches)} build {s} {'ok' if rc == 0 else 'FAILED'}")
        if rc == 0:
            res.ok()
            row = [l for l in out.splitlines() if l.startswith(os.path.basename(s) + " ")]
            if row:
                res.notes.append("size: " + " ".join(row[0].split()))
        else:
            res.fail(f"build {s}", out[-3000:])


KINDS = {"tap-dir": suite_tap_dir, "tap": suite_tap, "pytest": suite_pytest, "firmware": suite_firmware}


def main(argv):
    if not argv:
        print(__doc__, file=sys.stderr)
        return 2
    total_p = total_f = 0
    lines = []
    for spec in argv:
        try:
            name, kind, target = spec.split("|", 2)
        except ValueError:
            print(f"run_tests: bad suite spec {spec!r} (want NAME|KIND|TARGET)", file=sys.stderr)
            return 2
        if kind not in KINDS:
            print(f"run_tests: unknown suite kind {kind!r} in {spec!r}", file=sys.stderr)
            return 2
        global PROGRESS
        res = Result()
        t0 = time.monotonic()
        print(f"{name}: running ...", flush=True)
        PROGRESS = Progress(name)
        try:
            KINDS[kind](target, res)
        finally:
            PROGRESS.stop()
            PROGRESS = None
        dt = time.monotonic() - t0
        for n, d in res.failures:
            print(f"FAIL [{name}] {n}")
            for l in d.splitlines()[-15:]:
                print(f"    {l}")
        for note in res.notes:
            print(f"  [{name}] {note}")
        line = f"{name}: {res.passed} passed, {res.failed} failed ({dt:.1f} s)"
        print(line, flush=True)
        lines.append(line)
        total_p += res.passed
        total_f += res.failed
    print(f"{total_p} passed, {total_f} failed")
    return 1 if total_f else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
