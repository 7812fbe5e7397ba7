"""Timer3's planner interrupt is linked only into the sketches that plan with it.

MotionStepper is an archive (library.properties: dot_a_linkage) and Timer3's interrupt lives in its own
member, BackgroundPlannerTimer.cpp, which only MotionStepper.h names (a reference the linker must
resolve): a maker's sketch that includes MotionStepper.h plans in the background as before, while the
stepper sketches, which include only MotionConsole.h and plan in loop(), carry none of it (about
450 bytes of flash: SCurveStepper came under issue 23's bound so). A sketch that includes Stepper.h
alone and begins a Stepper planned by the interrupt gets a status that says which header to include
(MS_ERR_NO_PLANNER_TIMER), not a jump to a missing function.
"""
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(ROOT, "tools", "build_firmware.sh")
MOTIONEMU = os.path.join(ROOT, "build", "motionemu")

# begin()'s status sentence on the serial port, then a move's end (or nothing)
BODY = """
Stepper x(Stepper::X);
void setup()
{
    Serial.begin(115200);
    Serial.print(F("begin: "));
    Serial.println(Stepper::statusText(x.begin()));
    Serial.print(F("moveTo: "));
    Serial.println(Stepper::statusText(x.moveTo(200)));
}
void loop()
{
    static bool told;
    if (!told && x.currentPosition() == 200 && !x.isRunning()) {
        told = true;
        Serial.println(F("at 200"));
    }
}
"""


def build(tmp_path, name, includes):
    sketch = tmp_path / name
    sketch.mkdir()
    (sketch / f"{name}.ino").write_text("".join(f"#include <{h}>\n" for h in includes) + BODY)
    env = dict(os.environ, FIRMWARE_OUT=str(tmp_path / "out"))
    p = subprocess.run(["bash", BUILD, str(sketch)], cwd=ROOT, env=env, capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    return str(tmp_path / "out" / name / f"{name}.ino.elf")


def symbols(elf):
    out = subprocess.run(["avr-nm", "-C", elf], capture_output=True, text=True, check=True).stdout
    return {line.split(" ", 2)[-1] for line in out.splitlines() if " " in line}


def serial_lines(tmp_path, elf, ms=300):
    log = tmp_path / (os.path.basename(elf) + ".log")
    subprocess.run([MOTIONEMU, elf, "--duration", str(ms), "-o", str(log)], check=True, timeout=300)
    return [line.split(" ", 2)[2] for line in log.read_text().splitlines() if line.startswith("rx ")]


def test_motion_stepper_h_links_the_timer_and_the_stepper_moves(tmp_path):
    elf = build(tmp_path, "TimerLinked", ["MotionStepper.h"])
    assert "__vector_planner_tick" in symbols(elf)
    lines = serial_lines(tmp_path, elf)
    assert "begin: ok" in lines, lines
    assert "moveTo: ok" in lines, lines
    assert "at 200" in lines, lines


def test_stepper_h_alone_refuses_begin_with_the_header_to_include(tmp_path):
    elf = build(tmp_path, "TimerMissing", ["Stepper.h"])
    assert "__vector_planner_tick" not in symbols(elf)
    lines = serial_lines(tmp_path, elf)
    assert "begin: no planner interrupt: #include <MotionStepper.h>" in lines, lines
    # nothing moves without begin()
    assert "moveTo: begin() has not been called: nothing moves before it" in lines, lines
    assert "at 200" not in lines, lines


def test_the_stepper_sketches_carry_no_planner_interrupt():
    # the sketches' own ELFs (make firmware, before the tests): the console plans in loop()
    for name in ("LeibRampStepper", "SimplisticRampStepper", "SCurveStepper", "ExactRampStepper"):
        elf = os.path.join(ROOT, "build", "firmware", name, f"{name}.ino.elf")
        assert os.path.isfile(elf), elf
        assert "__vector_planner_tick" not in symbols(elf), name
        assert "planner_timer_start()" not in symbols(elf), name
