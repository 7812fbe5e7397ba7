"""`make emulate` (tools/emu/emulate.py): one short run per sketch family, and its refusals.

Each run must exit 0 and write the firmware's CSV with exactly the header motionsim writes for that
family (asked of motionsim itself), the motionsim overlay and the PNG. The overlay must use the
parameters in force for each move or setpoint: the stepper's second move runs with parameters set
over serial, and its overlay must equal `motionsim ramp` run here with the values this script sent;
the servo's second setpoint starts from rest and gets its own overlay. The scripts send no `?`:
the overlays come from the sketch's defaults and its OK replies. Bad SKETCH, a missing, empty
or binary INPUT are refused with one line on stderr and exit status 2.
"""
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PY = sys.executable
EMULATE = os.path.join(ROOT, "tools", "emu", "emulate.py")
MOTIONSIM = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))

STEPPER_INPUT = """\
# the lab's defaults for 20 steps (no `?`: the overlay must use the sketch's defaults), then
# parameters set over serial (the overlay must follow the OK replies) for a move back to -30
wait ^READY LeibRampStepper$
send 20
wait ^DONE 20$
send set vmax 400
wait ^OK vmax=
send set v0 50
wait ^OK v0=
send set accel 800
wait ^OK accel=
send -30
wait ^DONE -30$
"""

FILTER_INPUT = """\
wait ^READY MovingAverageFilter$
send tau 0.5
wait ^OK tau=
send ?
wait ^kind=
@200 u 5
wait ^OK u=
until 1200
"""

SERVO_INPUT = """\
wait ^READY ProportionalClosedLoop$
send kp 0.3
wait ^OK kp=
send 1000
wait ^OK setpoint=1000$
run 700
send 500
wait ^OK setpoint=500$
run 700
"""


def emulate(*args, out=None):
    cmd = [PY, EMULATE, *args]
    if out is not None:
        cmd += ["--out", str(out)]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=300)


def motionsim_header(*args):
    p = subprocess.run([MOTIONSIM, *args], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    return p.stdout.splitlines()[0]


def lines(path):
    with open(path) as f:
        return f.read().splitlines()


@pytest.fixture(scope="module")
def built():
    for path in (os.path.join(ROOT, "build", "motionemu"), MOTIONSIM):
        if not os.access(path, os.X_OK):
            pytest.fail(f"{path} is not built (make test builds it)")


def test_stepper_run_one_csv_per_move_with_the_parameters_in_force(built, tmp_path):
    script = tmp_path / "moves.emu"
    script.write_text(STEPPER_INPUT)
    out = tmp_path / "out"
    out.mkdir()
    (out / "LeibRampStepper-7.csv").write_text("stale\n")     # an earlier run's output: removed
    (out / "LeibRampStepperX.csv").write_text("other\n")      # not this sketch's: kept
    p = emulate("--sketch", "LeibRampStepper", "--input", str(script), out=out)
    assert p.returncode == 0, p.stdout + p.stderr
    header = motionsim_header("ramp", "--to", "3")
    for stem in ("LeibRampStepper", "LeibRampStepper-2"):
        assert lines(out / f"{stem}.csv")[0] == header
        assert (out / f"{stem}.motionsim.csv").exists()
        assert (out / f"{stem}.png").stat().st_size > 0
    assert len(lines(out / "LeibRampStepper.csv")) == 1 + 20
    assert len(lines(out / "LeibRampStepper-2.csv")) == 1 + 50
    assert not (out / "LeibRampStepper-7.csv").exists()
    assert (out / "LeibRampStepperX.csv").exists()
    # the overlays: the defaults for move 1 (the lab handout's: v0 1, vmax 20, accel 10), the values sent
    # for move 2, at the sketch's 2 MHz timer
    for stem, a, b, v0, vmax, accel in (("LeibRampStepper", 0, 20, 1, 20, 10),
                                        ("LeibRampStepper-2", 20, -30, 50, 400, 800)):
        want = subprocess.run([MOTIONSIM, "ramp", "--algo", "leib", "--from", str(a), "--to", str(b), "--v0", str(v0),
                               "--vmax", str(vmax), "--accel", str(accel), "--tick-hz", "2000000",
                               "--integer-ticks"], capture_output=True, text=True).stdout.splitlines()
        assert lines(out / f"{stem}.motionsim.csv") == want, stem


RETARGET_INPUT = """\
# a new target while moving: 0 -> 1000, and after 600 ms (cruising at vmax 400 steps/s since
# (400 - 50) / 800 = 0.44 s) 2000, which the move continues to without stopping
wait ^READY LeibRampStepper$
timeout 20000
send set vmax 400
wait ^OK vmax=
send set v0 50
wait ^OK v0=
send set accel 800
wait ^OK accel=
send 1000
wait ^OK 0 1000$
run 600
send 2000
wait ^OK [0-9]+ 2000$
wait ^DONE 2000$
"""


def csv_rows(path):
    return [[float(x) for x in l.split(",")] for l in lines(path)[1:]]


def test_stepper_new_target_while_moving_position_overlay_and_acceleration(built, tmp_path):
    """The plot of a move that took over a moving axis: its position column is where the axis
    really is (continuing the first move's, ending at the DONE), its motionsim overlay continues
    at the speed the axis had (vmax, by the ramp's formula above) instead of restarting from rest,
    and its first acceleration is measured from the previous step, not from the command."""
    script = tmp_path / "retarget.emu"
    script.write_text(RETARGET_INPUT)
    out = tmp_path / "out"
    p = emulate("--sketch", "LeibRampStepper", "--input", str(script), out=out)
    assert p.returncode == 0, p.stdout + p.stderr
    first, second = csv_rows(out / "LeibRampStepper.csv"), csv_rows(out / "LeibRampStepper-2.csv")
    sim = csv_rows(out / "LeibRampStepper-2.motionsim.csv")
    ok_from = int(next(l for l in lines(out / "LeibRampStepper.log") if " OK " in l and l.endswith(" 2000")).split()[-2])
    assert ok_from > first[-1][1] + 1        # steps were queued: the OK's "from" lies ahead of the axis
    assert [r[1] for r in first] == list(range(1, len(first) + 1))
    assert [r[1] for r in second] == list(range(len(first) + 1, 2001))   # one step each, to the DONE
    assert abs(second[0][4] - 400) < 4 and abs(sim[0][4] - 400) < 4      # both still at vmax
    assert [r[1] for r in sim] == [r[1] for r in second]
    assert max(abs(a - b) for a, b in zip((r[2] for r in sim), (r[2] for r in second))) < 1e-4
    assert max(abs(r[5]) for r in second) < 2 * 800                     # no spike: |accel| near 800 at most


def test_filter_run(built, tmp_path):
    script = tmp_path / "step.emu"
    script.write_text(FILTER_INPUT)
    p = emulate("--sketch", "MovingAverageFilter", "--input", str(script), out=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
    fw = lines(tmp_path / "MovingAverageFilter.csv")
    assert fw[0] == motionsim_header("filter", "--duration", "0.02")
    assert len(fw) > 100       # 100 samples a second for about 1.2 s
    assert (tmp_path / "MovingAverageFilter.motionsim.csv").exists()
    assert (tmp_path / "MovingAverageFilter.png").stat().st_size > 0


def test_servo_run_one_csv_per_setpoint(built, tmp_path):
    script = tmp_path / "two.emu"
    script.write_text(SERVO_INPUT)
    p = emulate("--sketch", "ProportionalClosedLoop", "--input", str(script), out=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
    header = motionsim_header("servo", "--duration", "0.02")
    for stem, sp in (("ProportionalClosedLoop", 1000), ("ProportionalClosedLoop-2", 500)):
        fw = [r.split(",") for r in lines(tmp_path / f"{stem}.csv")]
        assert ",".join(fw[0]) == header
        assert {r[1] for r in fw[1:]} == {str(sp)}
        sim = [r.split(",") for r in lines(tmp_path / f"{stem}.motionsim.csv")]
        assert ",".join(sim[0]) == header
        assert (tmp_path / f"{stem}.png").stat().st_size > 0
        # Kp 0.3 settles within 0.4 s (motionsim): both end within 2 % of the step of each other
        assert abs(float(fw[-1][2]) - float(sim[-1][2])) <= 20, (stem, fw[-1], sim[-1])
    # the first overlay is motionsim with the Kp the script sent (no `?` was sent: kp came from OK kp=)
    want = subprocess.run([MOTIONSIM, "servo", "--ctrl", "p", "--kp", "0.3", "--setpoint", "1000", "--duration", "0.3"],
                          capture_output=True, text=True).stdout.splitlines()[1:]
    got = lines(tmp_path / "ProportionalClosedLoop.motionsim.csv")[1:]
    assert [r.split(",")[2] for r in got[:len(want)]] == [r.split(",")[2] for r in want]


def one_line_refusal(p):
    assert p.returncode == 2, p.stdout + p.stderr
    assert len(p.stderr.strip().splitlines()) == 1, p.stderr
    return p.stderr


def test_bad_sketch_and_inputs_are_refused(built, tmp_path):
    assert "unknown ('Nope')" in one_line_refusal(emulate("--sketch", "Nope", out=tmp_path))
    assert "missing" in one_line_refusal(emulate(out=tmp_path))
    err = one_line_refusal(emulate("--sketch", "LeibRampStepper", "--input", str(tmp_path / "none.emu"), out=tmp_path))
    assert "none.emu" in err
    empty = tmp_path / "empty.emu"
    empty.write_text("# only a comment\n\n   \n")
    assert "no commands" in one_line_refusal(emulate("--sketch", "LeibRampStepper", "--input", str(empty),
                                                     out=tmp_path))
    binary = tmp_path / "binary.emu"
    binary.write_bytes(bytes(range(256)) * 4)
    assert "not a text script" in one_line_refusal(emulate("--sketch", "LeibRampStepper", "--input", str(binary),
                                                           out=tmp_path))
    # the harness's script errors name the user's file and line, not a temporary copy
    bad = tmp_path / "bad.emu"
    bad.write_text("wait ^READY\nfrobnicate 3\n")
    assert f"{bad}:2: unknown command" in one_line_refusal(emulate("--sketch", "LeibRampStepper", "--input", str(bad),
                                                                   out=tmp_path))
    # nothing was written for a refused run
    assert not list(tmp_path.glob("LeibRampStepper*"))


def test_a_wait_that_times_out_names_the_users_input(built, tmp_path):
    script = tmp_path / "silent.emu"
    script.write_text("wait ^READY LeibRampStepper$\ntimeout 50\nwait ^never$\n")
    p = emulate("--sketch", "LeibRampStepper", "--input", str(script), "--no-plot", out=tmp_path)
    assert p.returncode == 1, p.stdout + p.stderr
    assert f"{script}:3: no line matching" in p.stdout


def test_make_emulate(built, tmp_path):
    p = subprocess.run(["make", "-s", "emulate", "SKETCH=LeibRampStepper", f"EMULATE_OUT={tmp_path}"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    assert lines(tmp_path / "LeibRampStepper.csv")[0] == motionsim_header("ramp", "--to", "3")
    assert len(lines(tmp_path / "LeibRampStepper.csv")) == 1 + 50     # the lab's 0 -> 50
    assert (tmp_path / "LeibRampStepper.motionsim.csv").exists() and (tmp_path / "LeibRampStepper.png").exists()
    p = subprocess.run(["make", "-s", "emulate", "SKETCH=Nope", f"EMULATE_OUT={tmp_path}"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 2
    assert "make emulate: SKETCH=<name> is unknown ('Nope')" in p.stderr
    assert "copy its folder to firmware/<Name>/" in p.stderr, p.stderr  # where a sketch of your own goes
    # a path is not a name: until 2026-12-07 SKETCH=/tmp/x/MySketch was told to rename its .ino to
    # /tmp/x/MySketch.ino (a fresh-clone review)
    own = tmp_path / "mine" / "MySketch"
    own.mkdir(parents=True)
    (own / "MySketch.ino").write_text("// motion-sketch: library\nvoid setup() {}\nvoid loop() {}\n")
    p = subprocess.run(["make", "-s", "emulate", f"SKETCH={own}", f"EMULATE_OUT={tmp_path}"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 2, p.stdout + p.stderr
    assert "not a path" in p.stderr and "copy its folder to firmware/<Name>/" in p.stderr, p.stderr
    assert "rename" not in p.stderr, p.stderr


def test_a_move_longer_than_motionsim_tabulates_is_plotted_without_an_overlay(built, tmp_path):
    """A move of 3,000,000 steps, halted after 200 ms: motionsim refuses a table of more than its
    default --max-rows (1,000,000) rows, so the emulated move is drawn alone, with a note, and the
    run succeeds (it failed with a FAIL line once the bound came in)."""
    script = tmp_path / "big.emu"
    script.write_text("wait ^READY\ntimeout 5000\nsend ?\nwait ^pos=\nsend 3000000\nwait ^OK\nrun 200\n"
                      "send !\nwait ^DONE\n")
    out = tmp_path / "out"
    p = emulate("--sketch", "ExactRampStepper", "--input", str(script), out=out)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "FAIL" not in p.stdout
    assert "no motionsim overlay (a move of 3,000,000 steps" in p.stdout
    rows = csv_rows(out / "ExactRampStepper.csv")
    assert len(rows) > 1000 and (out / "ExactRampStepper.png").exists()
