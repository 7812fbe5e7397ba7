"""tools/emu/sketches.py - what the emulator harness needs to know about each sketch.

A sketch is recognised by what it is, not by its name: the marker line `// motion-sketch: <family>`
in its .ino (stepper, filter or servo), so a renamed copy (firmware/LeibRampStepperABC/...) is
emulated and checked like its original. The default scripts wait for any `READY <name>` banner
(a copy may keep its original's banner).

The pins are read from where the sketches define them: the family's header in
firmware/libraries/MotionBoard/src (StepperPins.h, FilterPins.h), or for the servo sketches the
sketch's own .ino (its pin constants, so a copy with other pins is followed); a changed pin is
followed, and a missing one is an error rather than a silently unwatched pin. Each family also has a default INPUT script (what
`make emulate SKETCH=<name>` runs without INPUT=) and the conversion of an emulator log into the
same CSV that motionsim writes.
"""
import os
import re

import emulog

ROOT = emulog.ROOT

# A sketch says what it is in a marker line of its .ino (any line, normally the first):
#     // motion-sketch: stepper
# The family decides which pins the harness watches, the default INPUT script and the checks; a
# copy of a sketch under another name is the same family. A new sketch of a known family needs
# only the marker; a new family needs its entry here (pins, script) and its checks.
MARKER = "// motion-sketch: <family>"
MARKER_RE = re.compile(r"^[ \t]*//[ \t]*motion-sketch:[ \t]*([A-Za-z0-9_-]*)[ \t]*$", re.M)
# "library": a sketch of your own on our libraries (MotionStepper's Stepper, ...): no console, it
# runs by itself as the libraries' examples do (below), on the RAMPS X, Y and Z pins
FAMILIES = ("stepper", "filter", "servo", "multiaxis", "library")

# None: the pins are constants in the sketch's .ino itself
PIN_HEADERS = {"stepper": "StepperPins.h", "filter": "FilterPins.h", "servo": None,
               "multiaxis": "MultiAxisPins.h", "library": "MultiAxisPins.h"}


class SketchError(Exception):
    pass


class Env:
    """Where the firmware, the sources and motionsim are (all in this tree unless told)."""

    def __init__(self, firmware_dir=None, source_dir=None, motionsim=None):
        self.source_dir = source_dir or ROOT
        self.firmware_dir = firmware_dir or os.path.join(self.source_dir, "build", "firmware")
        self.motionsim = motionsim or os.path.join(self.source_dir, "build", "motionsim")

    def sketch_names(self):
        fw = os.path.join(self.source_dir, "firmware")
        if not os.path.isdir(fw):
            return []
        return sorted(d for d in os.listdir(fw) if os.path.isfile(os.path.join(fw, d, d + ".ino")))

    def ino(self, sketch):
        return os.path.join(self.source_dir, "firmware", sketch, sketch + ".ino")

    def family(self, sketch):
        """The family named by the sketch's marker line; SketchError (one line) if it has none,
        several, or one the emulator does not know."""
        path = self.ino(sketch)
        rel = os.path.relpath(path, self.source_dir)
        try:
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
        except OSError as e:
            raise SketchError(f"cannot read the sketch {rel}: {e.strerror}")
        found = MARKER_RE.findall(text)
        if not found:
            raise SketchError(f"{rel} has no marker line '{MARKER}' (one of: {', '.join(FAMILIES)}): "
                              f"add it at the top so the tools know what the sketch is")
        if len(set(found)) > 1:
            raise SketchError(f"{rel} has {len(found)} marker lines naming different families "
                              f"({', '.join(found)}): keep one '{MARKER}'")
        fam = found[0]
        if fam not in FAMILIES:
            raise SketchError(f"{rel}: the marker '// motion-sketch: {fam}' names a family the emulator does not "
                              f"know (known: {', '.join(FAMILIES)})")
        return fam

    def elf(self, sketch):
        path = os.path.join(self.firmware_dir, sketch, sketch + ".ino.elf")
        if not os.path.isfile(path):
            raise SketchError(f"{path} is missing: build the sketch first (make firmware)")
        return path

    def header_text(self, family, sketch=None):
        """The text that defines the family's pins: its MotionBoard header, or (servo) the sketch."""
        if PIN_HEADERS[family] is None:
            if sketch is None:
                raise SketchError(f"the {family} sketches define their pins themselves: name the sketch")
            path = self.ino(sketch)
        else:
            path = os.path.join(self.source_dir, "firmware", "libraries", "MotionBoard", "src", PIN_HEADERS[family])
        try:
            with open(path, encoding="utf-8") as f:
                return f.read()
        except OSError as e:
            raise SketchError(f"cannot read the pin definitions {path}: {e}")

    def header_int(self, family, name, sketch=None):
        """An integer constant of the pin header (or sketch): '#define NAME 22' or 'const uint8_t NAME = 22;'."""
        text = self.header_text(family, sketch)
        m = re.search(r"^\s*#\s*define\s+" + re.escape(name) + r"\s+\(?\s*(\d+)[uUlL]*\s*\)?", text, re.M) or \
            re.search(r"\b" + re.escape(name) + r"\s*=\s*(\d+)[uUlL]*\s*;", text)
        if not m:
            where = PIN_HEADERS[family] or os.path.basename(self.ino(sketch))
            raise SketchError(f"{where} does not define {name} (the emulator reads the pin from there)")
        return int(m.group(1))


def family_of(env, sketch):
    return env.family(sketch)


# ---- pins per family -------------------------------------------------------------------------

def filter_pins(env):
    return {"STROBE": f"D{env.header_int('filter', 'FILTER_STROBE_PIN')}",
            "PWM": f"D{env.header_int('filter', 'FILTER_PWM_PIN')}"}


def filter_adc_channel(env):
    return env.header_int("filter", "FILTER_INPUT_ADC_CHANNEL")


def filter_pwm_top(env):
    return env.header_int("filter", "FILTER_PWM_TOP")


def servo_motor_spec(env, sketch):
    g = lambda n: env.header_int("servo", n, sketch)  # noqa: E731
    # DIR high = positive duty = counts increase; BRAKE high = braking (the sketch's pins, L298P shield)
    return (f"PWM=D{g('SERVO_PIN_PWM')},DIR=D{g('SERVO_PIN_DIR')},BRAKE=D{g('SERVO_PIN_BRAKE')},"
            f"CS=D{g('SERVO_PIN_ENCODER_CS')},DIRPOS=1,BRAKEON=1")


def servo_pins(env, sketch):
    g = lambda n: env.header_int("servo", n, sketch)  # noqa: E731
    return {"PWM": f"D{g('SERVO_PIN_PWM')}", "DIR": f"D{g('SERVO_PIN_DIR')}", "BRAKE": f"D{g('SERVO_PIN_BRAKE')}",
            "CS": f"D{g('SERVO_PIN_ENCODER_CS')}"}


# ---- default INPUT scripts -------------------------------------------------------------------

FILTER_DEFAULT_INPUT = """\
# {sketch}: the moving-average-filter note's scenario: a 5 V step held 20 s, then back to 0 V (tau = 9 s)
wait ^READY [^ ]+$
send ?
wait ^kind=
@100 u 5
wait ^OK u=
@20100 u 0
wait ^OK u=
until 35000
send ?
wait ^kind=
"""

SERVO_DEFAULT_INPUT = """\
# {sketch}: the lab's step, setpoint 1000 counts with the default gains, for 3 s
wait ^READY [^ ]+$
send ?
wait ^setpoint=
mark setpoint
send 1000
wait ^OK setpoint=1000$
run 3000
send ?
wait ^setpoint=
"""

MULTIAXIS_DEFAULT_INPUT = """\
# {sketch}: X alone, then X, Y and Z together on a straight line, with the default parameters
wait ^READY [^ ]+$
send ?
wait ^z pos
mark move
send x 2000
wait ^OK
timeout 60000
wait ^DONE x
send move x0 y1000 z-500
wait ^OK move
wait ^DONE move
send ?
wait ^z pos
"""

STEPPER_DEFAULT_INPUT = """\
# {sketch}: the lab's move 0 -> 50 steps with the default parameters
wait ^READY [^ ]+$
send ?
wait ^pos
mark move
send 50
wait ^OK
timeout 60000
wait ^DONE
send ?
wait ^pos
"""


def default_input(env, sketch):
    fam = family_of(env, sketch)
    if fam == "filter":
        return FILTER_DEFAULT_INPUT.format(sketch=sketch)
    if fam == "servo":
        return SERVO_DEFAULT_INPUT.format(sketch=sketch)
    if fam == "multiaxis":
        return MULTIAXIS_DEFAULT_INPUT.format(sketch=sketch)
    if fam == "library":
        return example_input(sketch)
    return STEPPER_DEFAULT_INPUT.format(sketch=sketch)


def harness_args(env, sketch):
    """pins / motor for emulog.run()"""
    fam = family_of(env, sketch)
    if fam == "filter":
        return {"pins": filter_pins(env)}
    if fam == "servo":
        return {"motor": servo_motor_spec(env, sketch), "pins": servo_pins(env, sketch)}
    if fam in ("multiaxis", "library"):
        return {"pins": multiaxis_pins(env)}
    return {"pins": stepper_pins(env)}


def stepper_pins(env):
    """StepperPins.h names port/bit pairs: STEPPER_STEP_PORT PORTF + STEPPER_STEP_BIT 0 -> PF0"""
    text = env.header_text("stepper")
    pins = {}
    for name, sig, reg in (("STEP", "STEP", "PORT"), ("DIR", "DIR", "PORT"), ("ENABLE", "ENABLE", "PORT"),
                           ("LED", "LED", "PIN")):
        mp = re.search(r"^\s*#\s*define\s+STEPPER_" + sig + r"_" + reg + r"\s+" + reg + r"([A-L])\b", text, re.M)
        if not mp:
            raise SketchError(f"StepperPins.h does not define STEPPER_{sig}_{reg} {reg}<x>")
        pins[name] = f"P{mp.group(1)}{env.header_int('stepper', f'STEPPER_{sig}_BIT')}"
    if env.header_int("stepper", "STEPPER_LED_MIRROR") != 1:
        del pins["LED"]  # the LED mirrors steps only when built with STEPPER_LED_MIRROR = 1
    return pins


MULTIAXIS_AXES = ("X", "Y", "Z")


def multiaxis_pins(env):
    """MultiAxisPins.h names port/bit pairs per axis: MULTI_Y_STEP_PORT PORTF + MULTI_Y_STEP_BIT 6 -> YSTEP PF6"""
    text = env.header_text("multiaxis")
    pins = {}
    for ax in MULTIAXIS_AXES:
        for sig in ("STEP", "DIR", "ENABLE"):
            mp = re.search(r"^\s*#\s*define\s+MULTI_" + ax + "_" + sig + r"_PORT\s+PORT([A-L])\b", text, re.M)
            if not mp:
                raise SketchError(f"MultiAxisPins.h does not define MULTI_{ax}_{sig}_PORT PORT<x>")
            pins[ax + sig] = f"P{mp.group(1)}{env.header_int('multiaxis', f'MULTI_{ax}_{sig}_BIT')}"
    return pins


# ---- library examples ------------------------------------------------------------------------
# The examples of our Arduino libraries (lib/examples/<Name> for MotionCore, firmware/libraries/<Lib>/
# examples/<Name>), built by tools/build_firmware.sh into build/firmware/<Name>/ like the sketches.
# They need no marker line: they are not consoles (no `?`, no protocol) but programs that run by
# themselves; the harness watches the RAMPS X, Y and Z pins (MultiAxisPins.h, the MotionStepper
# library's axes) and `make emulate` draws their positions as for the multiaxis family.
EXAMPLE_PARENTS = ("lib/examples", "firmware/libraries/*/examples")
EXAMPLE_FAMILY = "multiaxis"

# What `make emulate SKETCH=<Example>` runs without INPUT=: the example's first 5 s (every shipped
# example but SmoothMove has ended or shown its moves by then), unless it needs more (below).
EXAMPLE_DEFAULT_INPUT = """\
# {sketch}: the example runs by itself; its first 5 s of emulated time
until 5000
"""

# StopOnSwitch reads its switches on the RAMPS X endstop pins (D3 X-min STOP, D2 X-max HALT, closed =
# low: the pull-up holds an open one high): open them both, then close STOP while the axis runs, then
# HALT on the way back.
EXAMPLE_INPUTS = {
    "StopOnSwitch": """\
# StopOnSwitch: both switches open, STOP (D3) closed 600 ms into the first move (stop()), HALT (D2)
# 300 ms into the move back (forceStop())
pin D3 1
pin D2 1
wait ^READY
wait ^MOVE towards
run 600
pin D3 0
timeout 20000
wait ^DONE
pin D3 1
wait ^MOVE towards
run 300
pin D2 0
wait ^DONE
pin D2 1
wait ^MOVE towards
run 200
""",
    # FollowTarget takes targets over serial (115200 baud, one a line) and answers MOVE <target>;
    # a replaced move has no DONE, only the move that comes to rest
    "FollowTarget": """\
# FollowTarget: 20000, then, 600 ms in (cruising at 20,000 steps/s), 5000 behind: it stops on its
# ramp and comes back to 5000; then 40000, and 700 ms in 25000 ahead: it slows down sooner
wait ^READY
send 20000
wait ^MOVE 20000
run 600
send 5000
timeout 20000
wait ^DONE
send 40000
wait ^MOVE 40000
run 700
send 25000
wait ^DONE
run 100
""",
    # SmoothMove: its legs take 18 s of emulated time (the stop, the new targets, the forceStop()); the run
    # ends at its FINISHED line
    "SmoothMove": """\
# SmoothMove: every leg, up to its FINISHED line (about 18 s of emulated time)
timeout 40000
wait ^FINISHED
""",
    # SmoothConsole: the stepper sketches' commands and `set jerk` for the smooth ramp (115200 baud)
    "SmoothConsole": """\
# SmoothConsole: `set jerk 0` refused, jerk 400000, out to 20000, then back towards -5000 and
# stopped 300 ms later (the stop acts after the smooth ramp's lead, up to 0.15 s)
wait ^READY
send set jerk 0
wait ^(OK|ERR)
send set jerk 400000
wait ^(OK|ERR)
send 20000
timeout 20000
wait ^DONE
send -5000
wait ^(OK|ERR)
run 300
send stop
wait ^DONE
send ?
wait ^pos=
""",
}


def example_dirs(env):
    """{name: folder relative to the source tree} of every library example (<folder>/<name>.ino)"""
    import glob
    out = {}
    for parent in EXAMPLE_PARENTS:
        for d in sorted(glob.glob(os.path.join(env.source_dir, parent, "*", ""))):
            name = os.path.basename(os.path.dirname(d))
            if os.path.isfile(os.path.join(d, name + ".ino")):
                out.setdefault(name, os.path.relpath(os.path.dirname(d), env.source_dir))
    return out


def example_input(sketch):
    return EXAMPLE_INPUTS.get(sketch, EXAMPLE_DEFAULT_INPUT.format(sketch=sketch))
