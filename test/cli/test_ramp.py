"""`motionsim ramp`: the step table, its column definitions, --integer-ticks, --compare, the sigmoid
table, -o, and every kind of bad input (exit 2, one line, nothing on stdout).

Expected values are recomputed here from the sources' formulas (the lab handout §4.3, the S-curve article), never
recorded from motionsim itself."""
import csv
import io
import math
import os
import struct
import subprocess

import pytest

HEADER = ["step", "position", "t_s", "interval_ticks", "speed_sps", "accel_sps2"]
LAB = ["--from", "0", "--to", "50", "--v0", "1", "--vmax", "20", "--accel", "10", "--tick-hz", "1000"]


def table(r):
    assert r.rc == 0, r.err
    rows = list(csv.reader(io.StringIO(r.out)))
    assert rows[0] == HEADER
    return [dict(zip(HEADER, map(float, row))) for row in rows[1:]]


def exact_t(n, v0, vmax, a, d):
    """t_n of the exact ramp: (sqrt(v0^2 + 2 a n) - v0)/a, cruise at vmax, mirrored end."""
    s = (vmax * vmax - v0 * v0) / (2 * a)
    xa = d / 2 if 2 * s >= d else s
    vp = math.sqrt(v0 * v0 + 2 * a * xa)
    ta = (vp - v0) / a
    total = 2 * ta + (d - 2 * xa) / vp
    acc = lambda x: (math.sqrt(v0 * v0 + 2 * a * x) - v0) / a  # noqa: E731
    if n <= xa:
        return acc(n)
    if n <= d - xa:
        return ta + (n - xa) / vp
    return total - acc(d - n)


def test_lab_checkpoint_through_the_cli(motionsim):
    # the lab handout §4.3.3 step 8: "218.218, 188.528 and 157.245 ticks (here representing milliseconds)"
    rows = table(motionsim("ramp", "--algo", "leib", *LAB))
    assert len(rows) == 50
    assert [round(r["interval_ticks"], 3) for r in rows[:3]] == [218.218, 188.528, 157.245]


@pytest.mark.parametrize("algo", ["simplistic", "leib", "exact"])
def test_rows_positions_and_column_definitions(motionsim, algo):
    rows = table(motionsim("ramp", "--algo", algo, "--from", "10", "--to", "-30", "--v0", "1", "--vmax", "20",
                           "--accel", "10", "--tick-hz", "1000"))
    assert [r["step"] for r in rows] == list(range(1, 41))
    assert [r["position"] for r in rows] == list(range(9, -31, -1))
    t = 0.0
    prev = None
    for r in rows:
        t += r["interval_ticks"] / 1000
        # t_s: the time of this step's pulse, the first one interval after the start
        assert r["t_s"] == pytest.approx(t, rel=1e-6)
        # speed_sps: F / interval (Leib's and simplistic's float intervals are printed to float precision)
        assert r["speed_sps"] == pytest.approx(1000 / r["interval_ticks"], rel=1e-7)
        # accel_sps2: change of speed between mid-interval times; row 1 from v0 at t = 0
        dt = r["interval_ticks"] / 1000
        if prev is None:
            want = (r["speed_sps"] - 1.0) / (dt / 2)
        else:
            want = (r["speed_sps"] - prev["speed_sps"]) / ((dt + prev["interval_ticks"] / 1000) / 2)
        assert r["accel_sps2"] == pytest.approx(want, rel=1e-6, abs=1e-9)
        prev = r


def test_exact_ramp_times_and_constant_acceleration(motionsim):
    v0, vmax, a, d = 100.0, 1000.0, 1000.0, 2000
    rows = table(motionsim("ramp", "--algo", "exact", "--to", d, "--v0", v0, "--vmax", vmax, "--accel", a,
                           "--tick-hz", "2000000"))
    for r in rows:
        assert r["t_s"] == pytest.approx(exact_t(int(r["step"]), v0, vmax, a, d), rel=1e-9)
    # S = (1000^2 - 100^2)/2000 = 495 steps: +a while accelerating, 0 cruising, -a decelerating
    for r in rows[1:494]:
        assert r["accel_sps2"] == pytest.approx(a, rel=1e-6)
    for r in rows[497:1503]:
        assert abs(r["accel_sps2"]) < 1e-6 * a
    for r in rows[1507:]:
        assert r["accel_sps2"] == pytest.approx(-a, rel=1e-6)
    assert rows[0]["accel_sps2"] == pytest.approx(a, rel=1e-9)  # row 1, from v0 at t = 0


def test_simplistic_steps_by_fixed_amount(motionsim):
    # the lab handout §4.3.2 eqs. 1-2 with the lab's defaults: dp = (1000 - 50)/19 = 50 ms per step
    rows = table(motionsim("ramp", "--algo", "simplistic", *LAB))
    assert [r["interval_ticks"] for r in rows[:5]] == [1000, 950, 900, 850, 800]
    assert rows[19]["interval_ticks"] == 50 and rows[30]["interval_ticks"] == 50
    assert rows[-1]["interval_ticks"] == 1000
    assert rows[-1]["t_s"] == pytest.approx(21.5)


def test_integer_ticks_are_the_rounded_intervals(motionsim):
    args = ["--algo", "leib", "--to", "300", "--v0", "3", "--vmax", "700", "--accel", "900", "--tick-hz", "2000000"]
    real = table(motionsim("ramp", *args))
    whole = table(motionsim("ramp", *args, "--integer-ticks"))
    total = 0
    for r, w in zip(real, whole):
        assert w["interval_ticks"] == math.floor(r["interval_ticks"] + 0.5)
        total += int(w["interval_ticks"])
        assert w["t_s"] == pytest.approx(total / 2e6, rel=1e-12)


def test_output_file_equals_stdout(motionsim, tmp_path):
    out = tmp_path / "leib.csv"
    r = motionsim("ramp", *LAB, "-o", out)
    assert r.rc == 0 and r.out == ""
    assert out.read_text() == motionsim("ramp", *LAB).out
    bad = motionsim("ramp", *LAB, "-o", tmp_path / "no" / "such" / "dir.csv")
    assert bad.rc == 1 and len(bad.err.strip().splitlines()) == 1


def test_compare_reports_deviation_from_exact(motionsim):
    r = motionsim("ramp", "--compare", *LAB)
    assert r.rc == 0, r.err
    rows = {row["algo"]: row for row in csv.DictReader(io.StringIO(r.out))}
    assert list(rows) == ["exact", "simplistic", "leib"]
    assert float(rows["exact"]["interval_max_dev_pct"]) == 0
    assert float(rows["exact"]["accel_rms_dev_sps2"]) == 0
    # recompute the Leib and simplistic figures from the two step tables
    ex = table(motionsim("ramp", "--algo", "exact", *LAB))
    for algo in ("leib", "simplistic"):
        al = table(motionsim("ramp", "--algo", algo, *LAB))
        dev = [100 * (a["interval_ticks"] - e["interval_ticks"]) / e["interval_ticks"] for a, e in zip(al, ex)]
        worst = max(dev, key=abs)
        assert float(rows[algo]["interval_max_dev_pct"]) == pytest.approx(worst, rel=1e-6)
        assert int(float(rows[algo]["interval_max_dev_step"])) == dev.index(worst) + 1
        rms = math.sqrt(sum(d * d for d in dev) / len(dev))
        assert float(rows[algo]["interval_rms_dev_pct"]) == pytest.approx(rms, rel=1e-6)
        da = [a["accel_sps2"] - e["accel_sps2"] for a, e in zip(al, ex)]
        assert abs(float(rows[algo]["accel_max_dev_sps2"])) == pytest.approx(max(map(abs, da)), rel=1e-6)
        assert float(rows[algo]["move_time_s"]) == pytest.approx(al[-1]["t_s"], rel=1e-9)
        assert float(rows[algo]["step_time_max_dev_s"]) == pytest.approx(
            max(abs(a["t_s"] - e["t_s"]) for a, e in zip(al, ex)), rel=1e-6)
    # the lab's question answered: Leib's step 1 is the speed after one step (39 % short here)
    assert float(rows["leib"]["interval_max_dev_pct"]) == pytest.approx(
        100 * (1000 / math.sqrt(21) - 1000 * (math.sqrt(21) - 1) / 10) / (1000 * (math.sqrt(21) - 1) / 10), rel=1e-5)
    assert float(rows["simplistic"]["move_time_s"]) == pytest.approx(21.5)


def test_compare_without_simplistic_when_v0_is_zero(motionsim):
    r = motionsim("ramp", "--compare", "--to", "100", "--v0", "0", "--vmax", "20", "--accel", "10")
    assert r.rc == 0
    assert [row["algo"] for row in csv.DictReader(io.StringIO(r.out))] == ["exact", "leib"]
    assert "simplistic left out" in r.err and "v0 > 0" in r.err


def test_compare_rows_left_out_carry_their_own_reason(motionsim):
    # F/v0 = 1e6/1e-4 = 1e10 ticks: too long for simplistic's first interval, while the exact ramp's
    # first step takes 2/(sqrt(v0^2 + 2a) + v0) = 0.447 s and Leib's F/sqrt(v0^2 + 2a) as long
    r = motionsim("ramp", "--compare", "--to", "100", "--v0", "1e-4", "--vmax", "20", "--accel", "10",
                  "--tick-hz", "1000000")
    assert r.rc == 0, r.err
    assert [row["algo"] for row in csv.DictReader(io.StringIO(r.out))] == ["exact", "leib"]
    assert r.err.strip().splitlines() == [
        "motionsim ramp: simplistic left out of the comparison: a step interval would exceed 2^32-1 timer ticks"]
    # an acceleration beyond float: simplistic and Leib (float, as on the Mega) each say so, exact runs
    r = motionsim("ramp", "--compare", "--to", "5", "--accel", "1e39")
    assert r.rc == 0, r.err
    assert [row["algo"] for row in csv.DictReader(io.StringIO(r.out))] == ["exact"]
    lines = r.err.strip().splitlines()
    assert len(lines) == 2
    for line, algo in zip(lines, ["simplistic", "leib"]):
        assert line.startswith(f"motionsim ramp: {algo} left out of the comparison: --accel: ")
        assert f"{algo} computes in float" in line


def test_compare_exits_2_when_the_exact_ramp_refuses(motionsim, tmp_path):
    # v0 = 0, a = 1e-9: the exact ramp's first step takes sqrt(2/a) = 44721 s = 8.9e10 ticks at 2 MHz
    out = tmp_path / "cmp.csv"
    for extra in ([], ["-o", out]):
        r = motionsim("ramp", "--compare", "--v0", "0", "--accel", "1e-9", "--tick-hz", "2000000", *extra)
        assert r.rc == 2 and r.out == ""
        lines = r.err.strip().splitlines()
        assert len(lines) == 1
        assert lines[0].startswith("motionsim ramp: a step interval would exceed 2^32-1 timer ticks")
        assert "exact ramp" in lines[0]
    assert not out.exists()


def test_compare_refuses_algo(motionsim):
    for args in (["--compare", "--algo", "leib"], ["--algo", "exact", "--compare"]):
        r = motionsim("ramp", *args)
        assert r.rc == 2 and r.out == ""
        assert r.err.strip().splitlines() == [
            "motionsim ramp: --algo and --compare cannot be combined: --compare runs every algorithm"]


def compare_from_tables(motionsim, args, whole):
    """--compare's figures recomputed step by step from the three step tables."""
    extra = ["--integer-ticks"] if whole else []
    ex = table(motionsim("ramp", "--algo", "exact", *args))
    out = {}
    for algo in ("exact", "simplistic", "leib"):
        al = table(motionsim("ramp", "--algo", algo, *args, *extra))
        if algo != "exact" and not whole:
            # printed as the shortest text that reads back as the same float: read it as a float
            for row in al:
                row["interval_ticks"] = struct.unpack("f", struct.pack("f", row["interval_ticks"]))[0]
        dev = [100 * (a["interval_ticks"] - e["interval_ticks"]) / e["interval_ticks"] for a, e in zip(al, ex)]
        da = [a["accel_sps2"] - e["accel_sps2"] for a, e in zip(al, ex)]
        out[algo] = {
            "interval_max_dev_pct": max(dev, key=abs),
            "interval_rms_dev_pct": math.sqrt(sum(d * d for d in dev) / len(dev)),
            "accel_max_dev_sps2": max(da, key=abs),
            "accel_rms_dev_sps2": math.sqrt(sum(d * d for d in da) / len(da)),
            "step_time_max_dev_s": max(abs(a["t_s"] - e["t_s"]) for a, e in zip(al, ex)),
            "move_time_s": al[-1]["t_s"],
        }
    return out


@pytest.mark.parametrize("whole", [False, True], ids=["float", "integer-ticks"])
def test_compare_summing_the_cruise_equals_stepping_through(motionsim, whole):
    # 20000 steps, about 19750 of them cruising: --compare accounts for the cruise in one go
    args = ["--to", "20000", "--v0", "10", "--vmax", "500", "--accel", "1000", "--tick-hz", "1000000"]
    r = motionsim("ramp", "--compare", *args, *(["--integer-ticks"] if whole else []))
    assert r.rc == 0, r.err
    got = {row["algo"]: row for row in csv.DictReader(io.StringIO(r.out))}
    want = compare_from_tables(motionsim, args, whole)
    for algo, w in want.items():
        for key, value in w.items():
            assert float(got[algo][key]) == pytest.approx(value, rel=1e-9, abs=1e-12), (algo, key)


def test_compare_of_the_longest_move_is_fast(motionsim):
    # INT32_MIN -> INT32_MAX (2^32 - 1 steps) used to take about 25 minutes; the exact move time is
    # 2 t_a + (D - 2 x_a)/vmax with x_a = (vmax^2 - v0^2)/2a, t_a = (vmax - v0)/a
    v0, vmax, a, d = 100.0, 1000.0, 1000.0, 2 ** 32 - 1
    r = motionsim("ramp", "--compare", "--from", "-2147483648", "--to", "2147483647", "--v0", v0, "--vmax", vmax,
                  "--accel", a, "--tick-hz", "2000000", timeout=10)
    assert r.rc == 0, r.err
    rows = {row["algo"]: row for row in csv.DictReader(io.StringIO(r.out))}
    assert list(rows) == ["exact", "simplistic", "leib"]
    xa = (vmax * vmax - v0 * v0) / (2 * a)
    assert float(rows["exact"]["move_time_s"]) == pytest.approx(2 * (vmax - v0) / a + (d - 2 * xa) / vmax,
                                                                rel=1e-12)
    for algo in ("simplistic", "leib"):
        assert int(rows[algo]["steps"]) == d
        # the cruise dominates: the move time is within 0.1 % of the exact one
        assert float(rows[algo]["move_time_dev_pct"]) == pytest.approx(0, abs=0.1)


def test_simplistic_reaches_vmax_in_one_step_when_s_is_0(motionsim):
    # S = int((4^2 - 1^2)/(2*10)) = 0: one step at F/v0 = 1000, then F/vmax = 250, the last at F/v0
    rows = table(motionsim("ramp", "--algo", "simplistic", "--v0", "1", "--vmax", "4", "--accel", "10", "--to", "5"))
    assert [r["interval_ticks"] for r in rows] == [1000, 250, 250, 250, 1000]


def test_write_error_stops_at_once(motionsim):
    # 10^8 rows would take half an hour to compute; the first failed write ends the run
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    r = motionsim("ramp", "--to", "100000000", "-o", "/dev/full", timeout=10)
    assert r.rc == 1 and r.out == ""
    assert r.err.strip().splitlines() == ["motionsim ramp: writing '/dev/full' failed: No space left on device"]


def sigmoid_period(i, length, fmin, fmax, flex, timer_hz):
    half = length / 2
    f = fmin + (fmax - fmin) / (1 + math.exp(-flex * (i - half) / half))
    return timer_hz / f


def test_sigmoid_table_holds_and_mirrors(motionsim):
    # the S-curve article's orange curve (1000, 64000, 500, 8) at its 10 MHz timer, each entry held 4 times
    rows = table(motionsim("ramp", "--algo", "sigmoid", "--to", "10000", "--len", "1000", "--fmin", "500",
                           "--fmax", "64000", "--flex", "8", "--timer-hz", "10000000", "--hold", "4"))
    assert len(rows) == 10000
    for n, r in enumerate(rows, start=1):
        k = min(n, 10001 - n)
        i = min((k - 1) // 4, 999)
        want = sigmoid_period(i, 1000, 500, 64000, 8, 1e7)
        assert abs(r["interval_ticks"] - math.floor(want)) <= (1 if abs(want - round(want)) < 1e-6 * want else 0)
    assert rows[3999]["interval_ticks"] == 156  # the S-curve article: "10000000/64000 = 156"


def test_sigmoid_article_parameter_sets_run(motionsim):
    for fmax, fmin, flex in [(56000, 16000, 4), (64000, 500, 8), (64000, 500, 15), (40000, 500, 5)]:
        rows = table(motionsim("ramp", "--algo", "sigmoid", "--to", "8000", "--len", "1000", "--fmin", fmin,
                               "--fmax", fmax, "--flex", flex, "--timer-hz", "10000000", "--hold", "4"))
        assert len(rows) == 8000
        assert all(1 <= r["interval_ticks"] <= 65535 for r in rows)
        assert rows[0]["interval_ticks"] == math.floor(sigmoid_period(0, 1000, fmin, fmax, flex, 1e7))


def test_extreme_positions(motionsim):
    rows = table(motionsim("ramp", "--from", "2147483600", "--to", "2147483647"))
    assert rows[-1]["position"] == 2147483647 and len(rows) == 47
    rows = table(motionsim("ramp", "--from", "-2147483600", "--to", "-2147483648"))
    assert rows[-1]["position"] == -2147483648 and len(rows) == 48


def test_zero_length_move_is_just_the_header(motionsim):
    r = motionsim("ramp", "--from", "7", "--to", "7")
    assert r.rc == 0 and r.out == ",".join(HEADER) + "\n"


def test_help_defines_the_columns(motionsim):
    r = motionsim("ramp", "--help")
    assert r.rc == 0
    for word in ["t_s", "interval_ticks", "speed_sps", "accel_sps2", "--integer-ticks", "--compare", "--hold",
                 "--timer-hz", "-o FILE"]:
        assert word in r.out


BAD = [
    (["--accel", "0"], "acceleration must be greater than 0"),
    (["--accel", "-3"], "acceleration must be greater than 0"),
    (["--v0", "-1"], "v0 must not be negative"),
    (["--vmax", "0.5"], "vmax must be greater than minimum speed v0"),
    (["--tick-hz", "0"], "tick rate F must be greater than 0"),
    (["--vmax", "5000"], "must not exceed the tick rate"),
    (["--accel", "nan"], "--accel: 'nan' is not a finite number"),
    (["--vmax", "inf"], "--vmax: 'inf' is not a finite number"),
    (["--vmax", "1e-320"], "--vmax: '1e-320' is out of range: it underflows a double"),
    (["--vmax", "1e400"], "--vmax: '1e400' is out of range: it overflows a double"),
    (["--algo", "sigmoid", "--fmax", "1e39"], "--fmax: 1e+39 is out of range for a float (magnitude above 3.4e38)"),
    (["--algo", "sigmoid", "--flex", "1e-39"], "--flex: 1e-39 underflows a float"),
    (["--algo", "sigmoid", "--fmin", "-1e39"], "--fmin: -1e+39 is out of range for a float"),
    (["--algo", "leib", "--accel", "1e39"], "--accel: 1e+39 is out of range for a float"),
    (["--algo", "simplistic", "--v0", "1e-40"], "--v0: 1e-40 underflows a float"),
    (["--to", "0x10"], "--to: '0x10' is not a whole number"),
    (["--tick-hz", "0x10"], "--tick-hz: '0x10' is not a whole number"),
    (["--to", "5", "--to", "6"], "--to given twice"),
    (["--compare", "--compare"], "--compare given twice"),
    (["--accel", "1e-9", "--v0", "0", "--tick-hz", "4000000000"], "would exceed 2^32-1 timer ticks"),
    (["--algo", "simplistic", "--v0", "0"], "simplistic ramp needs v0 > 0"),
    (["--to", "2147483648"], "--to: '2147483648' is not a whole number"),
    (["--from", "-2147483649"], "--from: '-2147483649' is not a whole number"),
    (["--to", "12abc"], "--to: '12abc' is not a whole number"),
    (["--tick-hz", "-5"], "--tick-hz: '-5' is not a whole number"),
    (["--algo", "trapezoid"], "--algo: 'trapezoid' is not one of simplistic|leib|exact|sigmoid"),
    (["--len", "10"], "--len applies to --algo sigmoid only"),
    (["--algo", "sigmoid", "--v0", "3"], "--v0 does not apply to --algo sigmoid"),
    (["--algo", "sigmoid", "--compare"], "--algo and --compare cannot be combined"),
    (["--algo", "sigmoid", "--len", "1"], "table length must be at least 2"),
    (["--algo", "sigmoid", "--len", "70000"], "--len: 70000 is more than 65535"),
    (["--algo", "sigmoid", "--hold", "0"], "held for at least 1 timer period"),
    (["--algo", "sigmoid", "--hold", "65536"], "--hold: 65536 is more than 65535"),
    (["--algo", "sigmoid", "--fmin", "152"], "fmin is below timer_hz/65535"),
    (["--algo", "sigmoid", "--fmax", "400"], "fmax must be greater than fmin"),
    (["--algo", "sigmoid", "--flex", "0"], "flexibility must be greater than 0"),
    (["--algo", "sigmoid", "--fmax", "2e7"], "a timer period is outside 1..65535 ticks"),
    (["--algo", "sigmoid", "--timer-hz", "0"], "tick rate F must be greater than 0"),
    (["--frobnicate"], "unknown option '--frobnicate'"),
    (["--compare", "extra"], "unexpected argument 'extra'"),
    (["--v0"], "option --v0 needs a value"),
    (["--compare=1"], "option --compare takes no value"),
]


@pytest.mark.parametrize("args,message", BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_input_exits_2_with_one_line(motionsim, args, message):
    r = motionsim("ramp", *args)
    assert r.rc == 2
    assert r.out == ""
    lines = r.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("motionsim ramp: ")
    assert message in lines[0]


SKETCH_LIMITS = {
    # sketch: [(line sent, the ERR line expected)], limits from StepperPins.h/StepperRamps.h (timer mode)
    "LeibRampStepper": [
        ("set vmax 5001", "ERR number out of range: vmax at most 5000 steps/s on this sketch"),
        ("set v0 1e39", "ERR number out of range: v0 at most 5000 steps/s on this sketch"),
        ("set accel 2e7", "ERR number out of range: accel at most 10000000 steps/s^2 on this sketch"),
        ("set v0 -1e39", "ERR minimum speed v0 must not be negative"),
        ("set accel -2e7", "ERR acceleration must be greater than 0 steps/s^2"),
    ],
    "SimplisticRampStepper": [
        ("set vmax 8001", "ERR number out of range: vmax at most 8000 steps/s on this sketch"),
    ],
    "SCurveStepper": [
        ("set vmax 10001", "ERR number out of range: vmax at most 10000 steps/s on this sketch"),
        ("set len 1001", "ERR number out of range: len at most 1000 entries on this sketch"),
        ("set hold 65536", "ERR number out of range: hold at most 65535 steps per entry on this sketch"),
        ("set flex 1001", "ERR number out of range: flex at most 1000 on this sketch"),
        ("set len -3", "ERR table length must be at least 2"),
        ("set hold -1", "ERR each table entry must be held for at least 1 timer period"),
    ],
}


@pytest.mark.parametrize("sketch", sorted(SKETCH_LIMITS))
def test_sketch_names_the_limit_of_an_out_of_range_set(sketch, tmp_path):
    """The stepper sketches, run in the emulator: `set` above the sketch's limit says the limit
    after the module's sentence; a value too negative to parse gets the sentence for negatives."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    emu = os.path.join(root, "build", "motionemu")
    elf = os.path.join(root, "build", "firmware", sketch, f"{sketch}.ino.elf")
    if not (os.access(emu, os.X_OK) and os.path.exists(elf)):
        pytest.skip("needs build/motionemu and the firmware (make test builds both)")
    cases = SKETCH_LIMITS[sketch]
    script = tmp_path / "limits.emu"
    lines = [f"wait ^READY {sketch}$"]
    for sent, _ in cases:
        lines += [f"send {sent}", "wait ^ERR "]
    script.write_text("\n".join(lines) + "\n")
    log = tmp_path / "limits.log"
    p = subprocess.run([emu, elf, "-i", str(script), "-o", str(log)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    got = [line.split(" ", 2)[2] for line in log.read_text().splitlines() if line.startswith("rx ")]
    assert got[1:] == [want for _, want in cases]
