"""`make emulate SKETCH=X` for a user (issue 25): it builds X alone, shows the serial conversation as
it happens with emulated time, says where the outputs are, and plots any sketch, whatever it prints.

- Builds only X: make's own dry run (`make -n -W FILE`, "what if FILE had changed", which touches
  nothing) must plan X's build (tools/build_firmware.sh X) when X's .ino or a library source changed,
  and nothing of the other sketches' or the test-only builds (build/emu/firmware.stamp, timed, nodir,
  the AVR test programs) whatever changed; with nothing changed (X just built), no build at all.
- The conversation: the standard run of LeibRampStepper shows `> 50`, `< OK 0 50`, `< DONE 50` (the
  documented protocol, docs/serial.md) in that order, each stamped `[  t.ttt s]` with non-decreasing
  emulated times, then the folder of the outputs and each CSV and PNG.
- Any sketch: test/cli/sketches/MyOwnStepper (our own sketch written for this test: 5 ms a step to
  each number typed, no READY, no OK/DONE, no `?` reply) gets a CSV and a PNG from its STEP/DIR pins
  with the default input (the lab's 50: 50 rows, positions 1..50) and with a script of two moves
  (0 -> 30 -> -20: two CSVs, the positions one step apart, as the DIR pin says), and no overlay (its
  parameters are unknown).
"""
import os
import re
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PY = sys.executable
EMULATE = os.path.join(ROOT, "tools", "emu", "emulate.py")
MOTIONSIM = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))
OWN = os.path.join(ROOT, "test", "cli", "sketches", "MyOwnStepper")
LEIB_ELF = os.path.join(ROOT, "build", "firmware", "LeibRampStepper", "LeibRampStepper.ino.elf")


@pytest.fixture(scope="module")
def built():
    for path in (os.path.join(ROOT, "build", "motionemu"), MOTIONSIM, LEIB_ELF):
        if not os.path.exists(path):
            pytest.fail(f"{path} is not built (make test builds it)")


def dry_run(*what_if, sketch="LeibRampStepper"):
    """the commands `make emulate SKETCH=<sketch>` would run if the files what_if had changed"""
    args = ["make", "-n", "emulate", f"SKETCH={sketch}"]
    for f in what_if:
        args += ["-W", f]
    p = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
    return p.stdout


TEST_ONLY = ("firmware.stamp", "emu/timed", "emu/nodir", "pid_v1_avr", "text_parse_avr", "emu_selftest",
             "wrong_mcu", "step_planner_avr")


def builds(plan):
    """the sketch builds and the test-only builds a dry run plans"""
    sketches = re.findall(r"build_firmware\.sh( [A-Za-z0-9_ ]*)?", plan)
    return [s.strip() for s in sketches], [t for t in TEST_ONLY if t in plan]


def test_make_emulate_builds_only_the_sketch_and_only_when_its_sources_changed(built):
    # bring X's ELF up to date first (make test has built everything; a tree being edited may not have)
    p = subprocess.run(["make", "-s", "SKETCH=LeibRampStepper", os.path.relpath(LEIB_ELF, ROOT)], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    assert builds(dry_run()) == ([], [])
    for changed in ("firmware/LeibRampStepper/LeibRampStepper.ino", "lib/src/ramp_leib.c",
                    "firmware/libraries/MotionBoard/src/StepperPins.h"):
        assert builds(dry_run(changed)) == (["LeibRampStepper"], []), changed
    # another sketch's source: nothing to build for this one
    assert builds(dry_run("firmware/ExactRampStepper/ExactRampStepper.ino")) == ([], [])


def test_make_emulate_shows_the_conversation_and_where_the_outputs_are(built, tmp_path):
    p = subprocess.run(["make", "-s", "emulate", "SKETCH=LeibRampStepper", f"EMULATE_OUT={tmp_path}"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    said = [(float(m.group(1)), m.group(2)) for m in re.finditer(r"^\s*\[\s*(\d+\.\d{3}) s\] ([<>] .*)$",
                                                                   p.stdout, re.M)]
    texts = [t for _, t in said]
    order = [texts.index(x) for x in ("> 50", "< OK 0 50", "< DONE 50")]
    assert order == sorted(order), texts
    times = [t for t, _ in said]
    assert times == sorted(times) and times[-1] > 0
    # README.md and docs/emulator.md quote this conversation with its times: as measured now
    shown = {t: f"[{w:8.3f} s] {t}" for w, t in said if t in ("> 50", "< OK 0 50", "< DONE 50")}
    for doc in ("README.md", os.path.join("docs", "emulator.md")):
        with open(os.path.join(ROOT, doc), encoding="utf-8") as f:
            text = re.sub(r"\s+", " ", f.read())
        for t, line in shown.items():
            assert re.sub(r"\s+", " ", line) in text, f"{doc} does not quote '{line}' (the run shows it so)"
    rest = p.stdout[p.stdout.index("< DONE 50"):]
    assert f"outputs in {tmp_path}/" in rest
    for name in ("LeibRampStepper.csv", "LeibRampStepper.motionsim.csv", "LeibRampStepper.png",
                 "LeibRampStepper.log"):
        assert os.path.join(str(tmp_path), name) in rest, name


@pytest.fixture(scope="module")
def own_tree(tmp_path_factory, built):
    """a tree with MyOwnStepper in firmware/ (this tree's board library and motionsim), built"""
    tree = tmp_path_factory.mktemp("own")
    fw = tree / "firmware"
    fw.mkdir()
    os.symlink(os.path.join(ROOT, "firmware", "libraries"), fw / "libraries")
    shutil.copytree(OWN, fw / "MyOwnStepper")
    (tree / "build").mkdir()
    os.symlink(MOTIONSIM, tree / "build" / "motionsim")
    env = dict(os.environ, FIRMWARE_SRC=str(fw), FIRMWARE_OUT=str(tree / "build" / "firmware"))
    p = subprocess.run(["bash", os.path.join(ROOT, "tools", "build_firmware.sh"), "MyOwnStepper"], cwd=ROOT,
                       env=env, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    return tree


def positions(path):
    rows = open(path).read().splitlines()
    assert rows[0] == "step,position,t_s,interval_ticks,speed_sps,accel_sps2"
    return [int(r.split(",")[1]) for r in rows[1:]]


def test_a_sketch_that_never_answers_gets_its_csv_and_plot_from_the_pins(own_tree, tmp_path):
    p = subprocess.run([PY, EMULATE, "--sketch", "MyOwnStepper", "--source-dir", str(own_tree), "--out",
                        str(tmp_path)], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    assert re.search(r"\] > 50$", p.stdout, re.M) and re.search(r"\] < there$", p.stdout, re.M), p.stdout
    assert positions(tmp_path / "MyOwnStepper.csv") == list(range(1, 51))
    assert (tmp_path / "MyOwnStepper.png").stat().st_size > 1000
    assert not (tmp_path / "MyOwnStepper.motionsim.csv").exists()


def test_a_sketch_that_never_answers_one_csv_per_move_of_a_script(own_tree, tmp_path):
    script = tmp_path / "two.emu"
    script.write_text("wait ^hello\nsend 30\nwait ^there\nsend -20\nwait ^there\n")
    p = subprocess.run([PY, EMULATE, "--sketch", "MyOwnStepper", "--source-dir", str(own_tree), "--input",
                        str(script), "--out", str(tmp_path)], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    assert positions(tmp_path / "MyOwnStepper.csv") == list(range(1, 31))
    assert positions(tmp_path / "MyOwnStepper-2.csv") == list(range(29, -21, -1))
    for stem in ("MyOwnStepper", "MyOwnStepper-2"):
        assert (tmp_path / f"{stem}.png").stat().st_size > 1000
