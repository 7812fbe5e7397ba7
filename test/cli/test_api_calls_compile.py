"""The calls a maker writes first, as written: they must compile against MotionStepper.

- `xy.moveTo(0, 0)`, MultiStepper's "go home": with the members' form taking a pointer, a literal 0 was
  also a null pointer and the call was ambiguous (a fresh-clone review, 2026-12-06). The members'
  form takes an array now, whose size bounds the mask.
- `xyz.moveTo(targets, 5)` with `long targets[3]`, and `moveTo(a, b, c)` with int, long and literal
  arguments mixed.
"""
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(ROOT, "tools", "build_firmware.sh")

SKETCH = """#include <MotionStepper.h>

Stepper x(Stepper::X), y(Stepper::Y), z(Stepper::Z);
StepperGroup xy(x, y), xyz(x, y, z);

void setup()
{
    long targets[3] = {100, 200, 300};
    int n = 5;
    x.begin();
    y.begin();
    z.begin();
    (void)xy.moveTo(0, 0);
    (void)xyz.moveTo(0, 0, 0);
    (void)xyz.moveTo(n, 2L, 3);
    (void)xyz.moveTo(targets, 5);
    (void)x.moveTo(0);
    (void)x.move(-1);
}

void loop() {}
"""


def test_the_first_calls_compile(tmp_path):
    sketch = tmp_path / "FirstCalls"
    sketch.mkdir()
    (sketch / "FirstCalls.ino").write_text(SKETCH)
    env = dict(os.environ, FIRMWARE_OUT=str(tmp_path / "out"))
    p = subprocess.run(["bash", BUILD, str(sketch)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    log = tmp_path / "out" / "FirstCalls.log.clean"
    out = p.stdout + p.stderr + (log.read_text() if log.exists() else "")
    assert p.returncode == 0, out
    assert "ambiguous" not in out, out


def test_a_warning_in_a_sketch_outside_the_tree_fails_its_build(tmp_path):
    """docs/library.md: `bash tools/build_firmware.sh path/to/MySketch` builds a sketch of your own with
    warnings as errors, as for ours; until 2026-12-07 only paths under firmware/ and lib/ counted as ours,
    so a sketch outside the tree built with its warnings unreported (a fresh-clone review)"""
    sketch = tmp_path / "Warned"
    sketch.mkdir()
    (sketch / "Warned.ino").write_text("#include <MotionStepper.h>\n\nStepper x(Stepper::X);\n\n"
                                       "void setup()\n{\n    int unused_here;\n    x.begin();\n}\n\nvoid loop() {}\n")
    env = dict(os.environ, FIRMWARE_OUT=str(tmp_path / "out"))
    p = subprocess.run(["bash", BUILD, str(sketch)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    out = p.stdout + p.stderr
    assert p.returncode != 0, out
    assert "FAIL Warned: warnings in our code:" in out and "unused_here" in out, out
