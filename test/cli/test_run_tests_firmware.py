"""tools/run_tests.py's firmware suite (what `make test` runs for "firmware build"): every build of
tools/build_firmware.sh is one test, the sketches (firmware/<S>/<S>.ino) and the libraries'
examples alike (lib/examples/<X>, firmware/libraries/<Lib>/examples/<X>, as build_firmware.sh names
them); each success gives a size note, each failure names the build.

The list expected is found here from the tree itself (a glob of the folders holding <name>/<name>.ino),
and a stand-in for build_firmware.sh records what it was given, prints a size row like the real
script's and fails for one chosen example, so the test needs no compiler and takes a second.
"""
import glob
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RUN_TESTS = os.path.join(ROOT, "tools", "run_tests.py")

FAKE = """#!/usr/bin/env bash
echo "$1" >> "$FAKE_LOG"
n=$(basename "$1")
printf '%-24s %8d %6.1f%% %8d %6.1f%%\\n' "$n" 1000 0.4 100 1.2
[ "$n" != "$FAKE_FAIL" ]
"""


def expected_builds():
    def with_ino(pattern):
        return sorted(os.path.relpath(os.path.dirname(p), ROOT) for p in glob.glob(os.path.join(ROOT, pattern))
                      if os.path.basename(p) == os.path.basename(os.path.dirname(p)) + ".ino")
    sketches = [os.path.basename(d) for d in with_ino("firmware/*/*.ino")]
    return sketches, with_ino("lib/examples/*/*.ino") + with_ino("firmware/libraries/*/examples/*/*.ino")


def test_every_sketch_and_every_library_example_is_one_build(tmp_path):
    fake = tmp_path / "build.sh"
    fake.write_text(FAKE)
    log = tmp_path / "given.txt"
    env = dict(os.environ, FAKE_LOG=str(log), FAKE_FAIL="MoveAndBack")
    p = subprocess.run([sys.executable, RUN_TESTS, f"fw|firmware|{fake}"], cwd=ROOT, env=env, capture_output=True,
                       text=True, timeout=120)
    sketches, examples = expected_builds()
    assert "firmware/libraries/MotionStepper/examples/MoveAndBack" in examples  # the tree has them
    given = log.read_text().split()
    assert sorted(given) == sorted(sketches + examples)
    assert p.returncode == 1, p.stdout + p.stderr   # the one failed build
    n = len(sketches) + len(examples)
    assert f"fw: {n - 1} passed, 1 failed" in p.stdout, p.stdout
    assert "FAIL [fw] build firmware/libraries/MotionStepper/examples/MoveAndBack" in p.stdout
    for ex in examples:
        name = os.path.basename(ex)
        if name != "MoveAndBack":
            assert f"[fw] size: {name} 1000 0.4% 100 1.2%" in p.stdout, name
