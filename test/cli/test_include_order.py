"""A maker's sketch that includes one of MotionBoard's headers before <MotionStepper.h>.

arduino-cli links the libraries in the order in which the sketch's #includes first name them, and
MotionBoard is an archive (a sketch links only the parts of it that it uses) that must come after
MotionStepper: in the other order the link failed with "undefined reference to `step_cut_plan'" and
the like, which says nothing of the cause. MotionStepper.h and MotionConsole.h now stop such a build
with an #error that says what to do; in the right order the same sketch builds.
"""
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(ROOT, "tools", "build_firmware.sh")

BODY = """
Stepper x(Stepper::X);
void setup() { x.begin(); x.moveTo(STEPPER_DIR_ARDUINO_PIN); }
void loop() {}
"""


def build(tmp_path, name, includes):
    sketch = tmp_path / name
    sketch.mkdir()
    (sketch / f"{name}.ino").write_text("".join(f"#include <{h}>\n" for h in includes) + BODY)
    env = dict(os.environ, FIRMWARE_OUT=str(tmp_path / "out"))
    p = subprocess.run(["bash", BUILD, str(sketch)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    log = tmp_path / "out" / f"{name}.log.clean"
    return p.returncode, p.stdout + p.stderr + (log.read_text() if log.exists() else "")


def test_a_board_header_first_is_refused_with_what_to_do(tmp_path):
    for first, api in (("StepperPins.h", "MotionStepper.h"), ("MotionSerial.h", "MotionConsole.h")):
        rc, out = build(tmp_path, f"Order{first[:-2]}", [first, api])
        assert rc != 0, out
        assert "#include <MotionStepper.h> or <MotionConsole.h> before MotionBoard's headers" in out, out
        assert "undefined reference" not in out, out


def test_the_api_header_first_builds(tmp_path):
    rc, out = build(tmp_path, "OrderGood", ["MotionStepper.h", "StepperPins.h"])
    assert rc == 0, out
    assert os.path.isfile(tmp_path / "out" / "OrderGood" / "OrderGood.ino.elf")
