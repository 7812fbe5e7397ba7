"""Issue 11, item 7: both Arduino libraries carry real metadata in the fields the Arduino library
specification (library.properties, rev. 2.2) requires, and lib/ installs as a library with an
example sketch of a user's own that uses a ramp (built by `make test`'s firmware suite and run by
the emulator's RampIntervals check)."""
import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FILES = {"MotionCore": os.path.join(ROOT, "lib", "library.properties"),
         "MotionBoard": os.path.join(ROOT, "firmware", "libraries", "MotionBoard", "library.properties")}
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


def test_both_libraries_have_the_specifications_fields_filled_consistently():
    seen = {}
    for name, path in FILES.items():
        p = props(path)
        seen[name] = p
        assert p["name"] == name
        assert re.fullmatch(r"\d+\.\d+\.\d+", p["version"]), p["version"]
        for k in ("author", "maintainer", "sentence", "paragraph", "architectures"):
            assert p.get(k), (name, k)
        assert p["category"] in CATEGORIES, (name, p["category"])
        text = open(path, encoding="utf-8").read()
        assert "example.invalid" not in text and "TODO" not in text, name
        # the paragraph adds to the sentence, it does not repeat it
        assert not p["paragraph"].startswith(p["sentence"]), name
    assert seen["MotionCore"]["author"] == seen["MotionBoard"]["author"]
    assert seen["MotionCore"]["maintainer"] == seen["MotionBoard"]["maintainer"]
    assert seen["MotionBoard"]["depends"] == "MotionCore"
    assert seen["MotionCore"]["includes"] and all(
        os.path.isfile(os.path.join(ROOT, "lib", "src", h.strip())) for h in seen["MotionCore"]["includes"].split(","))


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
