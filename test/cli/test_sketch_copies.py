"""Any copy of a sketch works with every tool: a sketch is recognised by its marker line
`// motion-sketch: <family>`, not by its name (tools/emu/sketches.py, tools/build_firmware.sh,
test/emu/checks_sketches.py, tools/emu/emulate.py).

A copy of LeibRampStepper under the lab's XXX naming (LeibRampStepperABC) in a temporary tree is
recognised as a stepper, gets the stepper checks, is built, emulated with a motionsim overlay and
passes the stepper check its original passes; a sketch without the marker is refused in one line
that names the marker, by each tool. Edited copies (LeibRampStepperABC with maxPermisSpeed 15,
ProportionalClosedLoopABC with Kp 0.05, PIDClosedLoopABC with Kp 0.05 and Ki 0.01) pass their
emulator checks, which take the parameters from the copy's own `?` reply; the originals' names
keep their defaults checked against the documentation.
"""
import os
import re
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))
sys.path.insert(0, os.path.join(ROOT, "test", "emu"))
import sketches  # noqa: E402
import checks_sketches  # noqa: E402

MOTIONSIM = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))
MARKER = "// motion-sketch: <family>"


def copy_tree(tmp_path, copies, bare=()):
    """tmp_path/firmware with copies {new name: original} (each .ino renamed, text unchanged),
    marker-less sketches `bare`, and this tree's board library (the pin headers)."""
    fw = tmp_path / "firmware"
    fw.mkdir()
    os.symlink(os.path.join(ROOT, "firmware", "libraries"), fw / "libraries")
    for new, orig in copies.items():
        (fw / new).mkdir()
        shutil.copy(os.path.join(ROOT, "firmware", orig, orig + ".ino"), fw / new / f"{new}.ino")
    for name in bare:
        (fw / name).mkdir()
        (fw / name / f"{name}.ino").write_text("void setup() {}\nvoid loop() {}\n")
    (tmp_path / "build").mkdir()
    os.symlink(MOTIONSIM, tmp_path / "build" / "motionsim")
    return sketches.Env(source_dir=str(tmp_path))


def test_every_sketch_here_has_a_marker_naming_a_known_family():
    env = sketches.Env()
    names = env.sketch_names()
    assert names
    for n in names:
        assert env.family(n) in sketches.FAMILIES


def test_a_renamed_copy_is_recognised_and_gets_its_originals_checks(tmp_path):
    env = copy_tree(tmp_path, {"LeibRampStepperABC": "LeibRampStepper", "MyFilter": "MovingAverageFilter",
                               "MyServo": "PIDClosedLoop"})
    assert env.family("LeibRampStepperABC") == "stepper"
    assert env.family("MyFilter") == "filter"
    assert env.family("MyServo") == "servo"
    checks = checks_sketches.checks_for(env)
    names = [n for n, _ in checks]
    assert any(n.startswith("LeibRampStepperABC: 0->50") for n in names), names
    assert any(n.startswith("LeibRampStepperABC: bad input") for n in names), names
    assert any(n.startswith("MyFilter: 60 s") for n in names), names
    assert any(n.startswith("MyServo: closes the loop") for n in names), names
    known = dict(checks)["emulator: every sketch under firmware/ names its family (// motion-sketch: ...)"]()
    assert known.ok, known.details
    # the default emulator script does not insist on the original's READY banner
    script = sketches.default_input(env, "LeibRampStepperABC")
    assert "wait ^READY [^ ]+$" in script and "READY LeibRampStepper" not in script


def test_a_servo_sketchs_pins_are_read_from_the_sketch_itself(tmp_path):
    """The servo sketches define their pins (issue 11: a student follows them in five files); the
    harness wires the emulated motor to the pins of the sketch it runs, so a copy with another
    PWM pin is emulated with it, and a sketch without a pin constant is refused naming it."""
    env = copy_tree(tmp_path, {"MyServo": "ProportionalClosedLoop", "Bare": "PIDClosedLoop"})
    assert sketches.servo_motor_spec(env, "MyServo") == "PWM=D3,DIR=D12,BRAKE=D9,CS=D53,DIRPOS=1,BRAKEON=1"
    ino = tmp_path / "firmware" / "MyServo" / "MyServo.ino"
    text = ino.read_text()
    assert text.count("const uint8_t SERVO_PIN_PWM = 3;") == 1
    ino.write_text(text.replace("const uint8_t SERVO_PIN_PWM = 3;", "const uint8_t SERVO_PIN_PWM = 5;"))
    assert sketches.servo_motor_spec(env, "MyServo").startswith("PWM=D5,DIR=D12,")
    assert sketches.servo_pins(env, "MyServo")["PWM"] == "D5"
    bare = tmp_path / "firmware" / "Bare" / "Bare.ino"
    bare.write_text(bare.read_text().replace("SERVO_PIN_BRAKE = 9;", "SERVO_PIN_BRAKE_X = 9;"))
    with pytest.raises(sketches.SketchError, match="Bare.ino does not define SERVO_PIN_BRAKE"):
        sketches.servo_motor_spec(env, "Bare")


def test_a_servo_sketch_is_followed_end_to_end_in_five_files():
    """Issue 11: the .ino plus each header (with its source) it includes from MotionBoard and lib."""
    ours = set(os.listdir(os.path.join(ROOT, "firmware", "libraries", "MotionBoard", "src"))) | \
        set(os.listdir(os.path.join(ROOT, "lib", "src")))
    for name in ("ProportionalClosedLoop", "PIDClosedLoop"):
        text = open(os.path.join(ROOT, "firmware", name, name + ".ino")).read()
        includes = re.findall(r"^#include <([^>]+)>", text, re.M)
        # PIDClosedLoop's USE_REAL_PID_V1 build includes PID_v1.h instead of MotionPID.h: one of the two
        mine = sorted(h for h in includes if h in ours)
        assert 1 + len(mine) <= 5, (name, mine)
        assert "ServoPins.h" not in includes, name


def test_a_lab_stepper_sketch_is_followed_to_the_step_pin_in_five_files():
    """Issue 11: LeibRampStepper's top comment lists the files from setup()/loop() to the STEP pin;
    at most 5, each in the tree, and the path they describe is there: the console calls the sketch's
    Stepper (issue 23: the sketches are users of the MotionStepper library), the Stepper plans in the
    planner interrupt and that feeds the engine, the planner calls the sketch's ramp functions through
    ramp_next_ticks, the engine calls the sketch's moveOneStep through its hook, the assembly routine
    raises STEP."""
    name = "LeibRampStepper"
    text = open(os.path.join(ROOT, "firmware", name, name + ".ino")).read()
    listed = re.findall(r"^ \*   \d\. (\S+)", text, re.M)
    assert 1 <= len(listed) <= 5, listed
    libs = os.path.join(ROOT, "firmware", "libraries")
    where = {f: p for d in (os.path.join(ROOT, "firmware", name), os.path.join(ROOT, "lib", "src"),
                            os.path.join(libs, "MotionBoard", "src"), os.path.join(libs, "MotionStepper", "src"))
             for f in os.listdir(d) for p in [os.path.join(d, f)]}
    assert all(f in where for f in listed), listed
    body = {f: open(where[f]).read() for f in listed}
    assert "ax_[a]->move_to(" in body["MotionConsole.cpp"] and "x.moveTo(target)" in text
    assert "return move_to(target, false);" in body["Stepper.cpp"]  # moveTo is move_to without its replan
    assert "step_planner_move" in body["Stepper.cpp"] and "bool Stepper::run_request" in body["Stepper.cpp"]
    # the glue entry 3 names: the tick runs the request and feeds X's queue through the engine's service
    assert "BackgroundPlanner.cpp" in text and "MultiStepEngine::service" in text
    planner = open(where["BackgroundPlanner.cpp"]).read()
    assert "run_request()" in planner and "MultiStepEngine::service(" in planner
    assert "ramp_next_ticks" in body["step_planner.c"]
    # the direction hook is called by the engine's glue the list names in its fifth entry
    assert "MultiStepEngineInternal.h" in text
    assert "s_dir_hook[axis](forward)" in open(where["MultiStepEngineInternal.h"]).read()
    assert "sbi \\step_port, \\step_bit" in body["MultiStepEngineIsr.inc"]
    assert "x.setDirectionHook(moveOneStep)" in text


def test_a_sketch_without_the_marker_is_refused_in_one_line_naming_the_marker(tmp_path):
    env = copy_tree(tmp_path, {"LeibRampStepperABC": "LeibRampStepper"}, bare=["Blink"])
    with pytest.raises(sketches.SketchError) as e:
        env.family("Blink")
    msg = str(e.value)
    assert "\n" not in msg and MARKER in msg and "Blink.ino" in msg
    checks = dict(checks_sketches.checks_for(env))
    res = checks["emulator: every sketch under firmware/ names its family (// motion-sketch: ...)"]()
    assert not res.ok and any(MARKER in d for d in res.details)
    # a marker naming no known family
    (tmp_path / "firmware" / "Blink" / "Blink.ino").write_text("// motion-sketch: blinker\nvoid setup() {}\n")
    with pytest.raises(sketches.SketchError, match="blinker"):
        env.family("Blink")


def test_build_firmware_refuses_a_sketch_without_the_marker(tmp_path):
    copy_tree(tmp_path, {}, bare=["Blink"])
    if not os.access(os.path.join(ROOT, ".tools", "arduino-cli"), os.X_OK):
        pytest.fail("arduino-cli is not installed (make setup)")
    p = subprocess.run(["bash", os.path.join(ROOT, "tools", "build_firmware.sh"), "Blink"], capture_output=True,
                       text=True, env=dict(os.environ, FIRMWARE_SRC=str(tmp_path / "firmware"),
                                           FIRMWARE_OUT=str(tmp_path / "out")), timeout=300)
    assert p.returncode != 0
    err = p.stderr.strip().splitlines()
    assert len(err) == 1 and MARKER in err[0] and "Blink.ino" in err[0], p.stderr


def test_a_renamed_copy_is_built_emulated_and_checked_like_its_original(tmp_path):
    env = copy_tree(tmp_path, {"LeibRampStepperABC": "LeibRampStepper"})
    out = tmp_path / "build" / "firmware"
    p = subprocess.run(["bash", os.path.join(ROOT, "tools", "build_firmware.sh", ), "LeibRampStepperABC"],
                       capture_output=True, text=True, timeout=600,
                       env=dict(os.environ, FIRMWARE_SRC=str(tmp_path / "firmware"), FIRMWARE_OUT=str(out)))
    assert p.returncode == 0, p.stdout + p.stderr
    assert (out / "LeibRampStepperABC" / "LeibRampStepperABC.ino.elf").exists()
    # make emulate's script, its default input (the lab's 0 -> 50) and the motionsim overlay
    emu_out = tmp_path / "emulate"
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "emu", "emulate.py"), "--sketch",
                        "LeibRampStepperABC", "--source-dir", str(tmp_path), "--out", str(emu_out)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    assert len((emu_out / "LeibRampStepperABC.csv").read_text().splitlines()) == 1 + 50
    want = subprocess.run([MOTIONSIM, "ramp", "--algo", "leib", "--from", "0", "--to", "50", "--v0", "1", "--vmax",
                           "20", "--accel", "10", "--tick-hz", "2000000", "--integer-ticks"],
                          capture_output=True, text=True).stdout.splitlines()
    assert (emu_out / "LeibRampStepperABC.motionsim.csv").read_text().splitlines() == want
    # the emulator suite's stepper check, as for the original
    res = checks_sketches.check_stepper(env, "LeibRampStepperABC")
    assert res.ok, res.details
    # and the serial rules' checks, which a copy keeping its original's READY banner must pass too
    import checks_serial  # test/emu, next to checks_sketches
    for check in (checks_serial.check_blank_lines, checks_serial.check_overrun):
        res = check(env, "LeibRampStepperABC")
        assert res.ok, (check.__name__, res.details)


def test_a_folder_copy_with_the_old_ino_name_gets_a_rename_hint(tmp_path):
    """cp -r LeibRampStepper LeibRampStepperABC alone: both tools say to rename the .ino"""
    shutil.copytree(os.path.join(ROOT, "firmware", "LeibRampStepper"), tmp_path / "firmware" / "LeibRampStepperABC")
    p = subprocess.run(["bash", os.path.join(ROOT, "tools", "build_firmware.sh"), "LeibRampStepperABC"],
                       capture_output=True, text=True, timeout=120,
                       env=dict(os.environ, FIRMWARE_SRC=str(tmp_path / "firmware"), FIRMWARE_OUT=str(tmp_path / "o")))
    assert p.returncode != 0
    assert "holds LeibRampStepper.ino, not LeibRampStepperABC.ino: rename it" in p.stderr, p.stderr
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "emu", "emulate.py"), "--sketch",
                        "LeibRampStepperABC", "--source-dir", str(tmp_path), "--out", str(tmp_path / "e")],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2
    assert "holds LeibRampStepper.ino, not LeibRampStepperABC.ino: rename it" in p.stderr, p.stderr


# ---- edited copies (the handout's XXX naming, with the student's own values) -------------------
# Each edit is one line of the sketch; the expected values are the edit itself (what the student
# typed), which the sketch must report in its `?` reply and the checks must plan motionsim with.
EDITS = {
    "LeibRampStepperABC": ("LeibRampStepper", "const float maxPermisSpeed = 20.0;",
                           "const float maxPermisSpeed = 15.0;"),
    "ProportionalClosedLoopABC": ("ProportionalClosedLoop", "float Kp = 0.02; ", "float Kp = 0.05; "),
    "PIDClosedLoopABC": ("PIDClosedLoop", "double Kp = 0.02, Ki = 0, Kd = 0;", "double Kp = 0.05, Ki = 0.01, Kd = 0;"),
    # an original's name with an edited value: its defaults are still checked against the documentation
    "LeibRampStepper": ("LeibRampStepper", "const float maxPermisSpeed = 20.0;", "const float maxPermisSpeed = 15.0;"),
    "ProportionalClosedLoop": ("ProportionalClosedLoop", "float Kp = 0.02; ", "float Kp = 0.05; "),
}


@pytest.fixture(scope="module")
def edited(tmp_path_factory):
    """A tree with the EDITS built (one build_firmware.sh run): its sketches.Env."""
    tmp = tmp_path_factory.mktemp("edited")
    env = copy_tree(tmp, {new: orig for new, (orig, _, _) in EDITS.items()})
    for new, (_, old, repl) in EDITS.items():
        ino = tmp / "firmware" / new / f"{new}.ino"
        text = ino.read_text()
        assert text.count(old) == 1, (new, old)
        ino.write_text(text.replace(old, repl))
    p = subprocess.run(["bash", os.path.join(ROOT, "tools", "build_firmware.sh"), *EDITS], capture_output=True,
                       text=True, timeout=900, env=dict(os.environ, FIRMWARE_SRC=str(tmp / "firmware"),
                                                        FIRMWARE_OUT=str(tmp / "build" / "firmware")))
    assert p.returncode == 0, p.stdout + p.stderr
    return env


def test_an_edited_stepper_copy_passes_its_checks_with_its_own_parameters(edited):
    """LeibRampStepperABC with maxPermisSpeed = 15: the check takes vmax 15 from the copy's `?` and
    plans motionsim with it (the handout's 20 would be wrong for this copy)."""
    res = checks_sketches.check_stepper(edited, "LeibRampStepperABC")
    assert res.ok, res.details
    assert "vmax=15" in res.summary, res.summary


def test_an_edited_original_still_has_its_defaults_checked(edited):
    """The sketches as shipped must report the handout's v0 1, vmax 20, accel 10 and Kp 0.02."""
    res = checks_sketches.check_stepper(edited, "LeibRampStepper")
    assert not res.ok
    assert any("reports {'vmax': '15'}" in d and "'vmax': 20" in d for d in res.details), res.details
    res = checks_sketches.check_servo_defaults(edited, "ProportionalClosedLoop")
    assert not res.ok
    assert any("kp" in d and "0.02" in d for d in res.details), res.details


@pytest.mark.parametrize("sketch,gains", [("ProportionalClosedLoopABC", {"kp": 0.05}),
                                          ("PIDClosedLoopABC", {"kp": 0.05, "ki": 0.01, "kd": 0.0})])
def test_an_edited_servo_copy_passes_its_checks_with_its_own_gains(edited, sketch, gains):
    res = checks_sketches.check_servo_defaults(edited, sketch)
    assert res.ok, res.details
    for k, v in gains.items():
        assert f"{k}={v:g}" in res.summary, res.summary


def test_a_servo_check_that_does_not_settle_says_unsettled_and_does_not_crash(edited, monkeypatch):
    """motionsim run with the handout's Kp 0.02 against the copy's Kp 0.05 (what the check did
    before it read the copy's gains): the traces part, the firmware never settles into motionsim's
    band; the check fails and says "unsettled" rather than crashing on a missing settling time."""
    real = checks_sketches.motionsim

    def handout_gains(env, *args):
        args = list(args)
        if "--kp" in args:
            args[args.index("--kp") + 1] = "0.02"
        return real(env, *args)
    monkeypatch.setattr(checks_sketches, "motionsim", handout_gains)
    res = checks_sketches.check_servo_defaults(edited, "ProportionalClosedLoopABC")
    assert not res.ok
    assert "unsettled" in res.summary and any("unsettled" in d for d in res.details), (res.summary, res.details)


MY_SKETCH = """#include <MotionStepper.h>
Stepper x(Stepper::X);
void setup() { Serial.begin(9600); x.setMaxSpeed(5000); x.setAcceleration(20000); x.begin(); x.moveTo(300); }
void loop() { long at; if (x.takeDone(at)) Serial.println(at); }
"""


def test_a_makers_own_sketch_builds_from_any_folder_and_is_a_library_sketch_under_firmware(tmp_path):
    """docs/library.md 'Your own sketch': tools/build_firmware.sh takes the path of any folder
    <Name>/<Name>.ino (no marker needed there); under firmware/ the marker `library` makes it a known
    family that the emulator runs as a library example (the RAMPS axes' pins, no console)"""
    own = tmp_path / "elsewhere" / "MySketch"
    own.mkdir(parents=True)
    (own / "MySketch.ino").write_text(MY_SKETCH)
    env = dict(os.environ, FIRMWARE_OUT=str(tmp_path / "fw"))
    p = subprocess.run(["bash", "tools/build_firmware.sh", str(own)], cwd=ROOT, env=env, capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    assert (tmp_path / "fw" / "MySketch" / "MySketch.ino.elf").is_file()
    (tmp_path / "t").mkdir()
    tree = copy_tree(tmp_path / "t", {})
    (tmp_path / "t" / "firmware" / "MySketch").mkdir()
    (tmp_path / "t" / "firmware" / "MySketch" / "MySketch.ino").write_text("// motion-sketch: library\n" + MY_SKETCH)
    assert tree.family("MySketch") == "library"
    assert set(sketches.harness_args(tree, "MySketch")["pins"]) >= {"XSTEP", "XDIR", "YSTEP", "ZSTEP"}
    assert "until 5000" in sketches.default_input(tree, "MySketch")
