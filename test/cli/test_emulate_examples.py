"""`make emulate SKETCH=<Example>` for the libraries' examples (issue 23): firmware/libraries/<Lib>/
examples/<X> and lib/examples/<X>, built by tools/build_firmware.sh like the sketches.

- MoveAndBack, as its .ino and docs/library.md describe it (the RAMPS X axis to 10000 and back to 0):
  built alone, it runs by itself (no `?` asked); the conversation shows `READY MoveAndBack`,
  `moveTo 10000`, `DONE 10000 ...`, `moveTo 0`, `DONE 0 ...` in that order with emulated times; the
  CSV from the pins (t_s,axis,step,position, the multiaxis columns) has 20,000 X edges, the position
  rising to 10000 and back to 0 as the DIR pin says.
- Builds only the example: make's dry run (`make -n -W FILE`, which touches nothing) plans
  `tools/build_firmware.sh <the example's folder>` when its .ino or a library source changed, and
  nothing when another example changed or nothing did; a lib/examples one likewise.
- A name that is no sketch and no example is refused in one line listing both; a glob is no name.
"""
import csv
import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PY = sys.executable
EMULATE = os.path.join(ROOT, "tools", "emu", "emulate.py")
MOTIONSIM = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))
MOVE_AND_BACK = "firmware/libraries/MotionStepper/examples/MoveAndBack"


@pytest.fixture(scope="module")
def built():
    for path in (os.path.join(ROOT, "build", "motionemu"), MOTIONSIM):
        if not os.access(path, os.X_OK):
            pytest.fail(f"{path} is not built (make test builds it)")


def make(*args, timeout=600):
    return subprocess.run(["make", *args], cwd=ROOT, capture_output=True, text=True, timeout=timeout)


def test_make_emulate_runs_a_library_example(built, tmp_path):
    p = make("-s", "emulate", "SKETCH=MoveAndBack", f"EMULATE_OUT={tmp_path}")
    assert p.returncode == 0, p.stdout + p.stderr
    said = [(float(m.group(1)), m.group(2)) for m in re.finditer(r"^\s*\[\s*(\d+\.\d{3}) s\] ([<>] .*)$",
                                                                   p.stdout, re.M)]
    texts = [t for _, t in said]
    want = ["< READY MoveAndBack", "< moveTo 10000", "< DONE 10000", "< moveTo 0", "< DONE 0 "]
    at = [next((i for i, t in enumerate(texts) if t.startswith(w) or t == w.strip()), None) for w in want]
    assert None not in at and at == sorted(at), texts
    assert not any(t.startswith(">") for t in texts), "an example is not asked anything"
    times = [t for t, _ in said]
    assert times == sorted(times)
    with open(tmp_path / "MoveAndBack.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["t_s", "axis", "step", "position"]
    pos = [int(r[3]) for r in rows[1:]]
    assert {r[1] for r in rows[1:]} == {"x"}
    assert len(pos) == 20000
    assert max(pos) == 10000 and pos[9999] == 10000 and pos[-1] == 0
    assert pos[:10000] == list(range(1, 10001))      # out: one step up each
    assert pos[10000:] == list(range(9999, -1, -1))  # back
    assert (tmp_path / "MoveAndBack.png").exists() and (tmp_path / "MoveAndBack.input.emu").exists()


def dry_run(sketch, *what_if):
    args = ["-n", "emulate", f"SKETCH={sketch}"]
    for f in what_if:
        args += ["-W", f]
    p = make(*args, timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
    return p.stdout


def builds(plan):
    """what build_firmware.sh is given, and whether a test-only build (make test's) is planned"""
    return re.findall(r"build_firmware\.sh ([^ >]*)", plan), any(
        t in plan for t in ("firmware.stamp", "emu/timed", "emu/nodir", "pid_v1_avr", "text_parse_avr"))


def test_make_emulate_builds_only_the_example(built):
    for name, folder in (("MoveAndBack", MOVE_AND_BACK), ("RampIntervals", "lib/examples/RampIntervals")):
        elf = os.path.join("build", "firmware", name, name + ".ino.elf")
        p = make("-s", f"SKETCH={name}", elf)  # up to date first
        assert p.returncode == 0, p.stdout + p.stderr
        assert builds(dry_run(name)) == ([], False), name
        assert builds(dry_run(name, f"{folder}/{name}.ino")) == ([folder], False), name
        assert builds(dry_run(name, "lib/src/step_exact.c")) == ([folder], False), name
    # another example's source: nothing to build for this one
    assert builds(dry_run("MoveAndBack", "firmware/libraries/MotionStepper/examples/TwoAxesLine/TwoAxesLine.ino")) \
        == ([], False)


def test_an_unknown_name_lists_the_sketches_and_the_examples(built, tmp_path):
    p = subprocess.run([PY, EMULATE, "--sketch", "MoveAndBac", "--out", str(tmp_path)], cwd=ROOT,
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert "unknown ('MoveAndBac')" in p.stderr and "LeibRampStepper" in p.stderr
    assert re.search(r"library examples: .*\bMoveAndBack\b", p.stderr), p.stderr
    # a glob is no name: nothing is built, emulate.py refuses it
    assert builds(dry_run("*")) == ([], False)
    p = make("-s", "emulate", "SKETCH=Move*", f"EMULATE_OUT={tmp_path}", timeout=120)
    assert p.returncode == 2 and "unknown ('Move*')" in p.stderr, p.stdout + p.stderr
