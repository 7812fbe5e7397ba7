"""Issue 11, item 7 and issue 23: our three Arduino libraries (MotionCore = lib/, MotionBoard and
MotionStepper in firmware/libraries) carry real metadata in the fields the Arduino library
specification (library.properties, rev. 2.2) requires, and lib/ installs as a library with an
example sketch of a user's own that uses a ramp (built by `make test`'s firmware suite and run by
the emulator's RampIntervals check). Between the files: one author and maintainer; `depends` names
our own libraries only, those whose code the library includes; `includes` names headers the library
has; the examples the paragraph names are the library's examples, every one of them. MotionStepper
has issue 23's examples (MoveAndBack, TwoAxesLine, StopOnSwitch, BlockingLoop), each a sketch of a
user's own: it includes <MotionStepper.h> and none of MotionBoard's headers (the engine's insides)."""
import os
import re

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FILES = {"MotionCore": os.path.join(ROOT, "lib", "library.properties"),
         "MotionBoard": os.path.join(ROOT, "firmware", "libraries", "MotionBoard", "library.properties"),
         "MotionStepper": os.path.join(ROOT, "firmware", "libraries", "MotionStepper", "library.properties")}
STEPPER_EXAMPLES = ("MoveAndBack", "TwoAxesLine", "StopOnSwitch", "BlockingLoop")  # issue 23, item 6
# the specification's categories
CATEGORIES = {"Display", "Communication", "Signal Input/Output", "Sensors", "Device Control", "Timing",
              "Data Storage", "Data Processing", "Other"}


def props(path):
    out = {}
    for line in open(path, encoding="utf-8").read().splitlines():
        if line.strip() and not line.startswith("#"):
            k, _, v = line.partition("=")
            out[k.strip()] = v.strip()
    return out


def headers(folder):
    return {f for f in os.listdir(os.path.join(folder, "src")) if f.endswith(".h")}


def needs(name):
    """our other libraries whose headers the sources of `name` include (what `depends` must say)"""
    folder = os.path.dirname(FILES[name])
    included = set()
    for f in os.listdir(os.path.join(folder, "src")):
        if f.endswith((".h", ".c", ".cpp", ".S")):
            text = open(os.path.join(folder, "src", f), encoding="utf-8").read()
            included |= set(re.findall(r"^\s*#\s*include\s*[<\"]([^>\"]+)[>\"]", text, re.M))
    return {other for other, path in FILES.items()
            if other != name and included & headers(os.path.dirname(path))}


def names(field):
    return [w.strip() for w in field.split(",") if w.strip()]


def problems_of(name, path):
    """what is wrong with the library.properties at path for our library `name` (its folder: path's)"""
    out = []
    p = props(path)
    text = open(path, encoding="utf-8").read()
    folder = os.path.dirname(path)
    if p.get("name") != name:
        out.append(f"name={p.get('name')}, not {name}")
    if not re.fullmatch(r"\d+\.\d+\.\d+", p.get("version", "")):
        out.append(f"version {p.get('version')!r} is not MAJOR.MINOR.PATCH")
    for k in ("author", "maintainer", "sentence", "paragraph", "architectures"):
        if not p.get(k):
            out.append(f"{k} missing or empty")
    if p.get("category") not in CATEGORIES:
        out.append(f"category {p.get('category')!r} is not one of the specification's")
    if "example.invalid" in text or "TODO" in text:
        out.append("placeholder text")
    if p.get("paragraph", "").startswith(p.get("sentence", "\0")):
        out.append("the paragraph repeats the sentence")  # it adds to it
    for dep in names(p.get("depends", "")):
        if dep not in FILES:
            out.append(f"depends on {dep}, which is not one of our libraries")
    if set(names(p.get("depends", ""))) != needs(name):
        out.append(f"depends={p.get('depends')}, but its sources include headers of {sorted(needs(name))}")
    for h in names(p.get("includes", "")):
        if not os.path.isfile(os.path.join(folder, "src", h)):
            out.append(f"includes {h}, which src/ does not have")
    # the examples the paragraph names ("Example: X ..." / "Examples: X, Y, Z.") are the library's, all
    m = re.search(r"Examples?: ([A-Za-z0-9_, ]+?)(?:\.| prints| shows|$)", p.get("paragraph", ""))
    named = names(m.group(1)) if m else []
    ex_dir = os.path.join(folder, "examples")
    have = sorted(d for d in os.listdir(ex_dir) if os.path.isfile(os.path.join(ex_dir, d, d + ".ino"))) \
        if os.path.isdir(ex_dir) else []
    if sorted(named) != have:
        out.append(f"the paragraph names the examples {sorted(named)}, examples/ holds {have}")
    return out


def test_every_library_has_the_specifications_fields_filled_consistently():
    seen = {}
    for name, path in FILES.items():
        assert problems_of(name, path) == [], name
        seen[name] = props(path)
    assert len({p["author"] for p in seen.values()}) == 1
    assert len({p["maintainer"] for p in seen.values()}) == 1
    assert seen["MotionCore"]["includes"]
    assert seen["MotionStepper"]["includes"] == "MotionStepper.h"
    assert seen["MotionStepper"]["architectures"] == "avr"  # Timer1/Timer3 registers, RAMPS pins


@pytest.mark.parametrize("line,new,why", [
    ("depends=MotionCore, MotionBoard", "depends=MotionCore", "depends=MotionCore, but its sources include"),
    ("depends=MotionCore, MotionBoard", "depends=MotionCore, MotionBoard, AccelStepper", "not one of our"),
    ("includes=MotionStepper.h", "includes=Stepper2.h", "src/ does not have"),
    ("version=0.1.0", "version=1", "MAJOR.MINOR.PATCH"),
    ("category=Device Control", "category=Motors", "not one of the specification's"),
    ("Examples: MoveAndBack, TwoAxesLine,", "Examples: MoveAndBack,", "the paragraph names the examples"),
    ("name=MotionStepper", "name=Stepper", "not MotionStepper"),
])
def test_a_wrong_field_is_found(tmp_path, line, new, why):
    """the check above can fail: MotionStepper's file with one field spoiled, in a copy of its folder"""
    src = os.path.dirname(FILES["MotionStepper"])
    text = open(FILES["MotionStepper"], encoding="utf-8").read()
    assert line in text
    dst = tmp_path / "MotionStepper"
    dst.mkdir()
    os.symlink(os.path.join(src, "src"), dst / "src")
    os.symlink(os.path.join(src, "examples"), dst / "examples")
    (dst / "library.properties").write_text(text.replace(line, new, 1))
    found = problems_of("MotionStepper", str(dst / "library.properties"))
    assert any(why in f for f in found), found


def test_motionstepper_has_issue_23s_examples_each_using_the_library_alone():
    ex = os.path.join(os.path.dirname(FILES["MotionStepper"]), "examples")
    board = headers(os.path.dirname(FILES["MotionBoard"]))
    for name in STEPPER_EXAMPLES:
        ino = os.path.join(ex, name, name + ".ino")
        assert os.path.isfile(ino), name
        includes = set(re.findall(r"^\s*#\s*include\s*[<\"]([^>\"]+)[>\"]", open(ino, encoding="utf-8").read(), re.M))
        assert "MotionStepper.h" in includes and not includes & board, (name, includes)


def test_lib_has_an_example_sketch_that_uses_a_ramp():
    ex = os.path.join(ROOT, "lib", "examples")
    found = []
    for d in sorted(os.listdir(ex)):
        ino = os.path.join(ex, d, d + ".ino")
        if os.path.isfile(ino):
            text = open(ino, encoding="utf-8").read()
            if re.search(r"^#include <ramp[a-z_]*\.h>", text, re.M) and "ramp_plan" in text:
                found.append(d)
    assert found, "no example under lib/examples uses a ramp"
