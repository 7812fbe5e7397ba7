"""`motionsim ramp`: the step table, its column definitions, --integer-ticks, --compare, the sigmoid
table, -o, and every kind of bad input (exit 2, one line, nothing on stdout).

Expected values are recomputed here from the sources' formulas (the lab handout §4.3, the S-curve article), never
recorded from motionsim itself."""
import csv
import io
import math
import os
import re
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
    r = motionsim("ramp", "--to", "100000000", "--max-rows", "100000000", "-o", "/dev/full", timeout=10)
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


def _pins_limit(name):
    """A sketch's speed limit as StepperPins.h defines it (timer mode): the documented limit."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    text = open(os.path.join(root, "firmware", "libraries", "MotionBoard", "src", "StepperPins.h")).read()
    timer = text[text.index("#else", text.index("#if STEPPER_TIMED_LOOP\n#ifndef STEPPER_MAX_SPS")):]
    m = re.search(r"#define " + name + r" ([0-9.]+)", timer)
    return int(float(m.group(1)))


LEIB, SIMPLISTIC, SCURVE, EXACT = (_pins_limit(n) for n in ("STEPPER_MAX_SPS_LEIB", "STEPPER_MAX_SPS_SIMPLISTIC",
                                                            "STEPPER_MAX_SPS_SCURVE", "STEPPER_MAX_SPS_EXACT"))
SKETCH_LIMITS = {
    # sketch: [(line sent, the ERR line expected)], limits from StepperPins.h (timer mode)
    "LeibRampStepper": [
        (f"set vmax {LEIB + 1}", f"ERR number out of range: vmax at most {LEIB} steps/s on this sketch"),
        (f"set vmax {LEIB}.0001", f"ERR number out of range: vmax at most {LEIB} steps/s on this sketch"),
        ("set v0 1e39", f"ERR number out of range: v0 at most {LEIB} steps/s on this sketch"),
        ("set accel 2e7", "ERR number out of range: accel at most 10000000 steps/s^2 on this sketch"),
        ("set v0 -1e39", "ERR minimum speed v0 must not be negative"),
        ("set accel -2e7", "ERR acceleration must be greater than 0 steps/s^2"),
    ],
    "SimplisticRampStepper": [
        (f"set vmax {SIMPLISTIC + 1}", f"ERR number out of range: vmax at most {SIMPLISTIC} steps/s on this sketch"),
    ],
    "ExactRampStepper": [
        (f"set vmax {EXACT + 1}", f"ERR number out of range: vmax at most {EXACT} steps/s on this sketch"),
        ("set accel 2e7", "ERR number out of range: accel at most 1000000 steps/s^2 on this sketch"),
        ("set accel 1000001", "ERR number out of range: accel at most 1000000 steps/s^2 on this sketch"),
        ("set v0 10001", "ERR number out of range: v0 at most 10000 steps/s on this sketch"),
        ("set accel 1", "ERR acceleration too low for the exact planner: at least 8 steps/s^2 at a 16 MHz tick "
                        "(0.5 at 2 MHz; 8 (tick rate / 16 MHz)^2, and at least 0.5)"),
        ("set vmax 2e-50", "ERR number too close to 0 (underflow)"),
    ],
    "SCurveStepper": [
        (f"set vmax {SCURVE + 1}", f"ERR number out of range: vmax at most {SCURVE} steps/s on this sketch"),
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


# ---- ramp --queue: the move through the step engine (step_planner -> the interrupt's executor) ----
# Golden data: the closed form of constant acceleration computed here in 50-digit decimal arithmetic,
# the executor's rule (lib/src/step_queue.h) re-implemented here in Python integers, and for the
# stepwise ramps their own whole-tick table (`--integer-ticks`, ramp.h stepped without the queue).

import decimal  # noqa: E402

CMD_HEADER = ["cmd", "first_step", "count", "rate_ticks", "add_ticks", "flags"]


def f32(x):
    """x as the float the board (and step_exact) holds."""
    return struct.unpack("f", struct.pack("f", float(x)))[0]


def closed_ticks(v0, vmax, a, d, f):
    """round(F t_n) for n = 1..d: t_n = (sqrt(v0^2 + 2 a n) - v0)/a while accelerating, the cruise line at
    the peak speed, the deceleration mirrored (t_total - t(d - n)); 50 significant digits."""
    D = decimal.Decimal
    with decimal.localcontext() as ctx:
        ctx.prec = 50
        v0, vmax, a, f = D(f32(v0)), D(f32(vmax)), D(f32(a)), D(f)
        s = (vmax * vmax - v0 * v0) / (2 * a)
        xa = D(d) / 2 if 2 * s >= d else s
        vp = (v0 * v0 + 2 * a * xa).sqrt()
        ta = (vp - v0) / a
        total = 2 * ta + (D(d) - 2 * xa) / vp

        def acc(x):
            return ((v0 * v0 + 2 * a * x).sqrt() - v0) / a

        out = []
        for n in range(1, d + 1):
            if n <= xa:
                t = acc(D(n))
            elif n <= d - xa:
                t = ta + (D(n) - xa) / vp
            else:
                t = total - acc(D(d - n))
            out.append(int((t * f + D("0.5")).to_integral_value(rounding=decimal.ROUND_FLOOR)))
        return out


def queue_run(motionsim, tmp_path, *args):
    """(step table rows, command rows) of `ramp --queue ARGS --commands FILE`."""
    cmds = tmp_path / "commands.csv"
    r = motionsim("ramp", "--queue", *args, "--commands", cmds)
    rows = table(r)
    with open(cmds, newline="") as fh:
        c = list(csv.reader(fh))
    assert c[0] == CMD_HEADER
    return rows, [dict(zip(CMD_HEADER, row)) for row in c[1:]]


def execute(commands, start=0x8000):
    """The executor's rule (step_queue.h), in Python integers: acc starts at half a tick (1/65536 ticks);
    each step of a normal command acc += rate, rate += add; of a WIDE one acc += rate << 16; the edge is
    at whole tick floor(acc / 65536). Returns [(edge tick, direction)] for every step."""
    acc = start
    out = []
    for c in commands:
        wide = "wide" in c["flags"].split()
        rev = "reverse" in c["flags"].split()
        assert set(c["flags"].split()) <= {"wide", "reverse"}
        rate = round(float(c["rate_ticks"]) * (1 if wide else 65536))
        add = round(float(c["add_ticks"]) * 65536)
        assert int(c["first_step"]) == len(out) + 1
        count = int(c["count"])
        assert 1 <= count <= 65535
        if wide:
            assert add == 0 and rate > 65535  # only where a normal command cannot hold the interval
        for _ in range(count):
            if wide:
                acc += rate << 16
            else:
                assert 0 < rate <= 0xFFFFFFFF  # the executor's uint32 rate never wraps
                acc += rate
                rate += add
            out.append((acc >> 16, -1 if rev else 1))
    return out


def edge_ticks(rows, f):
    """each row's whole-tick edge: t_s * F (t_s is printed to round-trip a double)"""
    return [round(r["t_s"] * f) for r in rows]


EXACT_MOVES = [
    # v0, vmax, accel, F, from, to
    (0, 100000, 1e6, 16000000, 0, 20000),  # the reference: 5,000 steps up, 10,000 cruising, 5,000 down
    (0, 100000, 1e6, 16000000, 0, 3001),  # a triangle: the peak is never reached
    (500, 20000, 50000, 16000000, 1000, -19000),  # from v0 > 0, backwards
    (10, 200, 100, 16000000, 0, 600),  # slow steps: WIDE commands (F/10 = 1.6e6 ticks)
    (100, 1000, 1000, 2000000, -5, 2000),
]


@pytest.mark.parametrize("v0,vmax,a,f,frm,to", EXACT_MOVES, ids=[f"{m[0]}-{m[1]}-{m[2]:g}-{m[3]}-{m[5]}"
                                                                  for m in EXACT_MOVES])
def test_queue_exact_every_step_within_a_tick_of_the_closed_form(motionsim, tmp_path, v0, vmax, a, f, frm, to):
    rows, cmds = queue_run(motionsim, tmp_path, "--algo", "exact", "--from", frm, "--to", to, "--v0", v0,
                           "--vmax", vmax, "--accel", a, "--tick-hz", f)
    d = abs(to - frm)
    assert len(rows) == d
    want = closed_ticks(v0, vmax, a, d, f)
    got = edge_ticks(rows, f)
    worst = max(range(d), key=lambda i: abs(got[i] - want[i]))
    assert abs(got[worst] - want[worst]) <= 1, f"step {worst + 1}: {got[worst]} ticks, closed form {want[worst]}"
    step = 1 if to > frm else -1
    assert [int(r["position"]) for r in rows] == list(range(frm + step, to + step, step))
    # the columns: whole-tick intervals summing to the edges, speed F/interval
    prev = 0
    for r, t in zip(rows, got):
        assert r["interval_ticks"] == t - prev
        assert r["speed_sps"] == pytest.approx(f / r["interval_ticks"], rel=1e-12)
        prev = t
    # the commands re-executed by the executor's rule give the same edges
    assert [t for t, _ in execute(cmds)] == got
    if v0 == 10:
        assert any("wide" in c["flags"] for c in cmds)
    else:
        assert len(cmds) < d / 2 or d < 100  # packed: fewer commands than steps


def queue_args_stepwise(algo):
    if algo == "sigmoid":
        return ["--algo", "sigmoid", "--len", "400", "--fmin", "500", "--fmax", "30000", "--flex", "6",
                "--timer-hz", "2000000", "--hold", "3"]
    return ["--algo", algo, "--v0", "200", "--vmax", "20000", "--accel", "50000", "--tick-hz", "2000000"]


@pytest.mark.parametrize("algo", ["leib", "simplistic", "sigmoid"])
@pytest.mark.parametrize("frm,to", [(0, 30000), (70, -5000), (3, 4), (0, 9)])
def test_queue_stepwise_ramps_equal_their_integer_ticks(motionsim, tmp_path, algo, frm, to):
    args = [*queue_args_stepwise(algo), "--from", frm, "--to", to]
    rows, cmds = queue_run(motionsim, tmp_path, *args)
    want = table(motionsim("ramp", *args, "--integer-ticks"))
    assert len(rows) == len(want) == abs(to - frm)
    for i, (g, w) in enumerate(zip(rows, want)):
        assert g == w, f"step {i + 1}"
    # and the commands, re-executed here, give those times
    f = 2000000
    assert [t for t, _ in execute(cmds)] == edge_ticks(rows, f)
    if abs(to - frm) > 10000:
        # the cruise (here more than half the steps) is packed; simplistic's float dp changes its whole
        # ticks unevenly, so its ramps are mostly one command a step
        assert len(cmds) < len(rows) / 2


def test_queue_commands_to_stdout_and_table_to_a_file(motionsim, tmp_path):
    args = ["--algo", "exact", "--to", "-3000", "--v0", "0", "--vmax", "20000", "--accel", "50000",
            "--tick-hz", "16000000"]
    out = tmp_path / "table.csv"
    r = motionsim("ramp", "--queue", *args, "-o", out, "--commands", "-")
    assert r.rc == 0, r.err
    c = list(csv.reader(io.StringIO(r.out)))
    assert c[0] == CMD_HEADER
    cmds = [dict(zip(CMD_HEADER, row)) for row in c[1:]]
    assert all("reverse" in cm["flags"].split() for cm in cmds)
    steps = execute(cmds)
    assert len(steps) == 3000 and all(d == -1 for _, d in steps)
    assert out.read_text() == motionsim("ramp", "--queue", *args).out  # -o holds the table stdout would
    rows = table(motionsim("ramp", "--queue", *args))
    assert [t for t, _ in steps] == edge_ticks(rows, 16000000)


def test_queue_zero_length_move_is_just_the_headers(motionsim, tmp_path):
    r = motionsim("ramp", "--queue", "--from", "7", "--to", "7", "--commands", tmp_path / "c.csv")
    assert r.rc == 0 and r.out == ",".join(HEADER) + "\n"
    assert (tmp_path / "c.csv").read_text() == ",".join(CMD_HEADER) + "\n"


def check_motion(rows, cmds, f, a, v0, from_pos, extra_ticks=0.0):
    """Positions from the executor's directions agree with the table; the speed never jumps: between two
    steps in one direction 1/interval changes by at most what the acceleration allows over them (plus a
    tick's rounding at each end; `extra_ticks`: the simplistic ramp's constant interval step), except
    in the first two steps from rest. Returns the number of reversals."""
    steps = execute(cmds)
    assert [t for t, _ in steps] == edge_ticks(rows, f)
    pos = from_pos
    run = 0
    reversals = 0
    a_t = a / (f * f)  # steps/tick^2
    for i, ((t, d), r) in enumerate(zip(steps, rows)):
        pos += d
        assert r["position"] == pos
        if i > 0 and d != steps[i - 1][1]:
            reversals += 1
            run = 1
            # a reversal happens at rest: both steps around it are at most the speed a couple of steps
            # from rest allows
            slow = math.sqrt(v0 * v0 + 2 * a * 2) * 1.01
            assert rows[i - 1]["speed_sps"] <= slow and r["speed_sps"] <= slow, f"step {i + 1}"
        else:
            run += 1
        if run > 2 and i >= 2:
            i1 = steps[i - 1][0] - steps[i - 2][0]
            i2 = t - steps[i - 1][0]
            dv = abs(1 / i2 - 1 / i1)
            allowed = 2 * a_t * (i1 + i2) / 2 + (2 + extra_ticks) / (i1 * i2)
            assert dv <= allowed, f"speed jump at step {i + 1}: intervals {i1} then {i2} ticks"
    return reversals


def simplistic_dp(v0, vmax, a, f):
    """the simplistic ramp's interval step dp = (F/v0 - F/vmax)/S, S = (vmax^2 - v0^2)/(2a) (lab eq. 1)"""
    return (f / v0 - f / vmax) / math.floor((vmax * vmax - v0 * v0) / (2 * a))


def trapezoid(algo):
    """the unit tests' retarget parameters: 20,000 steps/s at 50,000 steps/s^2 (4,000 steps to stop)"""
    f = 16000000 if algo == "exact" else 2000000
    v0 = 0 if algo == "exact" else 200
    return f, v0, ["--algo", algo, "--v0", v0, "--vmax", "20000", "--accel", "50000", "--tick-hz", f]


@pytest.mark.parametrize("algo", ["exact", "leib", "simplistic"])
def test_queue_stop_at_decelerates_to_rest(motionsim, tmp_path, algo):
    f, v0, args = trapezoid(algo)
    rows, cmds = queue_run(motionsim, tmp_path, *args, "--to", "100000", "--stop-at", "6000")
    # the stop comes after the command holding step 6000 (at full speed by then); from 20,000 steps/s at
    # 50,000 steps/s^2 it takes v^2/2a = 4,000 steps
    holder = next(c for c in cmds if int(c["first_step"]) <= 6000 < int(c["first_step"]) + int(c["count"]))
    stop_from = int(holder["first_step"]) + int(holder["count"]) - 1
    assert abs(len(rows) - stop_from - 4000) <= 2
    assert rows[-1]["position"] == len(rows)
    extra = simplistic_dp(v0, 20000, 50000, f) if algo == "simplistic" else 0
    assert check_motion(rows, cmds, f, 50000, v0, 0, extra) == 0
    assert rows[-1]["speed_sps"] <= math.sqrt(v0 * v0 + 2 * 50000 * 2) * 1.01  # the last step is slow


RETARGETS = [
    # --retarget-at, final position, reversals
    ("6000:60000", 60000, 0),  # ahead, beyond the stopping distance
    ("6000:8000", 8000, 1),  # ahead but too close: overshoot, return
    ("6000:-5000", -5000, 1),  # behind: stop, reverse, approach
    ("2000:2500", 2500, 1),  # while still accelerating
    ("6000:1000,12000:30000", 30000, 2),  # back, then (moving backwards) forward again
]


@pytest.mark.parametrize("algo", ["exact", "leib", "simplistic"])
@pytest.mark.parametrize("spec,final,reversals", RETARGETS, ids=[r[0] for r in RETARGETS])
def test_queue_retarget_while_moving(motionsim, tmp_path, algo, spec, final, reversals):
    f, v0, args = trapezoid(algo)
    rows, cmds = queue_run(motionsim, tmp_path, *args, "--to", "100000", "--retarget-at", spec)
    assert rows[-1]["position"] == final
    # simplistic's interval step depends on each move's length: the speed check covers every ramp but it
    extra = simplistic_dp(v0, 20000, 50000, f) if algo == "simplistic" else 0
    if algo == "simplistic":
        # its dp is set per move: check only that positions, reversals and the edges agree
        steps = execute(cmds)
        assert [t for t, _ in steps] == edge_ticks(rows, f)
        got = sum(1 for i in range(1, len(steps)) if steps[i][1] != steps[i - 1][1])
        assert got == reversals
        assert sum(d for _, d in steps) == final
    else:
        assert check_motion(rows, cmds, f, 50000, v0, 0, extra) == reversals


def max_speed_ratio(rows):
    return max(max(a["speed_sps"], b["speed_sps"]) / min(a["speed_sps"], b["speed_sps"])
               for a, b in zip(rows, rows[1:]))


def test_queue_sigmoid_stop_and_retarget(motionsim, tmp_path):
    args = queue_args_stepwise("sigmoid")
    # a new target ahead: the speed changes between steps no more than along the table itself
    plain, _ = queue_run(motionsim, tmp_path, *args, "--to", "40000")
    rows, _ = queue_run(motionsim, tmp_path, *args, "--to", "40000", "--retarget-at", "5000:20000")
    assert rows[-1]["position"] == 20000
    assert max_speed_ratio(rows) <= max_speed_ratio(plain) * (1 + 1e-9)
    rows, cmds = queue_run(motionsim, tmp_path, *args, "--to", "40000", "--retarget-at", "5000:-300")
    assert rows[-1]["position"] == -300
    steps = execute(cmds)
    assert [t for t, _ in steps] == edge_ticks(rows, 2000000)
    assert sum(1 for i in range(1, len(steps)) if steps[i][1] != steps[i - 1][1]) == 1
    # the sigmoid's rate at a reversal is its table's first entry (fmin), never the cruise's
    for i in range(1, len(steps)):
        if steps[i][1] != steps[i - 1][1]:
            assert rows[i - 1]["speed_sps"] <= 600 and rows[i]["speed_sps"] <= 600
    rows, cmds = queue_run(motionsim, tmp_path, *args, "--to", "40000", "--stop-at", "5000")
    # the S-curve is symmetric: stopping at full speed takes as many steps as reaching it
    # (400 entries held 3 steps each = 1,200 steps)
    holder = next(c for c in cmds if int(c["first_step"]) <= 5000 < int(c["first_step"]) + int(c["count"]))
    stop_from = int(holder["first_step"]) + int(holder["count"]) - 1
    assert abs(len(rows) - stop_from - 1200) <= 3
    assert all(d == 1 for _, d in execute(cmds))


QUEUE_BAD = [
    (["--queue", "--compare"], "--queue and --compare cannot be combined"),
    (["--stop-at", "5"], "--stop-at needs --queue"),
    (["--retarget-at", "5:1"], "--retarget-at needs --queue"),
    (["--commands", "c.csv"], "--commands needs --queue"),
    (["--queue", "--retarget-at", "5"], "--retarget-at: '5' is not N:TARGET"),
    (["--queue", "--retarget-at", "5:1,"], "--retarget-at: '' is not N:TARGET"),
    (["--queue", "--retarget-at", "a:5"], "--retarget-at: the step number 'a' in 'a:5' is not a whole number"),
    (["--queue", "--retarget-at", "0:5"], "the step number '0' in '0:5' is not a whole number in 1..4294967295"),
    (["--queue", "--retarget-at", "5:"], "--retarget-at: the target '' in '5:' is not a whole number"),
    (["--queue", "--retarget-at", "5:1e3"], "the target '1e3' in '5:1e3' is not a whole number"),
    (["--queue", "--retarget-at", "5:2147483648"], "the target '2147483648' in '5:2147483648'"),
    (["--queue", "--retarget-at", "9:1,3:2"], "the step numbers must increase: 3:2 comes after 9:1"),
    (["--queue", "--retarget-at", "5:1", "--retarget-at", "6:1"], "--retarget-at given twice"),
    (["--queue", "--stop-at", "0"], "--stop-at: 0 is not a step number"),
    (["--queue", "--stop-at", "-3"], "--stop-at: '-3' is not a whole number"),
    (["--queue", "--stop-at", "51"], "--stop-at 51: the move has only 50 steps"),
    (["--queue", "--from", "5", "--to", "5", "--stop-at", "1"], "--stop-at 1: the move has only 0 steps"),
    (["--queue", "--retarget-at", "10:100,200:0"], "--retarget-at 200:0: the move has only 100 steps by then"),
    (["--queue", "--stop-at", "5", "--retarget-at", "5:1"], "--stop-at 5 and --retarget-at 5:1 fall on the same step"),
    (["--queue", "--commands", "-"], "--commands -: the step table goes to stdout already: give it -o FILE"),
    (["--queue", "--algo", "exact", "--accel", "1e39"],
     "--accel: 1e+39 is out of range for a float (magnitude above 3.4e38); the step engine's exact planner"),
    (["--queue", "--algo", "exact", "--tick-hz", "40000000"],
     "number out of range: --tick-hz 40000000 is above 33554432 (2^25), the limit of --queue --algo exact"),
    (["--queue", "--algo", "exact", "--tick-hz", "16000000", "--vmax", "100000", "--accel", "10"],
     "reaching vmax from rest would take more than 2^34 timer ticks: raise accel or lower vmax (vmax/accel = 10000 s"),
    (["--queue", "--algo", "exact", "--tick-hz", "16000000", "--vmax", "20", "--accel", "5"],
     "acceleration too low for the exact planner: at least 8 steps/s^2 at a 16 MHz tick (0.5 at 2 MHz; 8 "
     "(tick rate / 16 MHz)^2, and at least 0.5)"),
    (["--queue", "--algo", "exact", "--accel", "0"], "acceleration must be greater than 0"),
    (["--queue", "--algo", "simplistic", "--v0", "0"], "simplistic ramp needs v0 > 0"),
    (["--queue", "--algo", "sigmoid", "--fmax", "400"], "fmax must be greater than fmin"),
]


@pytest.mark.parametrize("args,message", QUEUE_BAD, ids=[" ".join(a) for a, _ in QUEUE_BAD])
def test_queue_bad_input_exits_2_with_one_line(motionsim, tmp_path, args, message):
    out, cmds = tmp_path / "t.csv", tmp_path / "c.csv"
    # and again with both outputs going to files (not for the case that is about the outputs)
    for extra in ([], [] if "--commands" in args else ["-o", out, "--commands", cmds]):
        r = motionsim("ramp", *args, *extra)
        assert r.rc == 2, r.err
        assert r.out == ""
        lines = r.err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("motionsim ramp: ")
        assert message in lines[0]
    assert not out.exists() and not cmds.exists()  # nothing is written before the input is known good


def test_queue_same_file_twice_refused(motionsim, tmp_path):
    out = tmp_path / "x.csv"
    r = motionsim("ramp", "--queue", "-o", out, "--commands", out)
    assert r.rc == 2 and r.out == "" and not out.exists()
    assert r.err.strip().splitlines() == [f"motionsim ramp: --commands and -o name the same file '{out}'"]


def test_queue_write_error_stops_at_once(motionsim, tmp_path):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    r = motionsim("ramp", "--queue", "--to", "100000000", "--max-rows", "100000000", "-o", "/dev/full", timeout=10)
    assert r.rc == 1 and r.out == ""
    assert r.err.strip().splitlines() == ["motionsim ramp: writing '/dev/full' failed: No space left on device"]
    r = motionsim("ramp", "--queue", "--to", "100000000", "--max-rows", "100000000", "-o", tmp_path / "t.csv",
                  "--commands", "/dev/full",
                  timeout=10)
    assert r.rc == 1
    lines = r.err.strip().splitlines()
    # (the reason is known only when the last flush fails too: cli_close_output)
    assert len(lines) == 1 and lines[0].startswith("motionsim ramp: writing '/dev/full' failed")


def test_queue_help(motionsim):
    r = motionsim("ramp", "--help")
    assert r.rc == 0
    for word in ["--queue", "--commands FILE", "--stop-at N", "--retarget-at N:TARGET", "step_exec_next",
                 "cmd,first_step,count,rate_ticks,add_ticks,flags", "round(x * 65536)"]:
        assert word in r.out
