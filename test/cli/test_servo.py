"""motionsim servo and pid-replay from the command line (issue: closed-loop servo control).

Expectations come from the lab handout (section 4.1: duty = Kp x (setpoint - measured), Kp = 0.02,
clamped to +-100 %), from the plant's documented friction figures (breakaway at 5.8 % duty), from
step-response definitions (README "motionsim servo") re-implemented here, and from the PID_v1 reference vectors in
test/data/pid_v1/ (recorded from the real library).
"""
import csv
import io
import math
import os
import re
import struct

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VECTORS = os.path.join(ROOT, "test", "data", "pid_v1")
NAMES = ["a_p_only", "b_pid_windup", "e_manual_auto", "g_irregular_calls", "h_invalid_args"]
HEADER = ["t_s", "setpoint", "position_counts", "error_counts", "duty_pct"]
BREAKAWAY_DUTY_PCT = 5.8  # sim/plant_dcmotor.h: the default motor starts at 5.8 % duty


def one_line(text):
    return len(text.strip().splitlines()) == 1


def parse_metrics(err):
    m = re.search(r"^metrics: (.*)$", err, re.M)
    assert m, err
    return {k: float(v) for k, v in (kv.split("=") for kv in m.group(1).split())}


SETTLE_SAMPLES = 10  # README "motionsim servo": settled = the last 10 samples within the band


def step_metrics(t, y, setpoint):
    """The README's definitions, written independently: overshoot beyond the setpoint in the
    step's direction over |step|; steady-state error setpoint - yf; settled when the last 10
    samples lie within 2 % of |yf - y0| of yf; then settling time (first time after which the
    trace stays in that band) and rise time 10-90 % of yf - y0, else both nan."""
    y0, yf = y[0], y[-1]
    step = setpoint - y0
    sign = 1 if step >= 0 else -1
    overshoot = max(0.0, max(sign * (v - setpoint) for v in y)) / abs(step) * 100 if step else math.nan
    band = 0.02 * abs(yf - y0)
    outside = [i for i, v in enumerate(y) if abs(v - yf) > band]
    settled = len(y) > SETTLE_SAMPLES and (not outside or outside[-1] < len(y) - SETTLE_SAMPLES)
    rise = settle = math.nan
    if settled:
        settle = t[outside[-1] + 1] - t[0] if outside else 0.0
        if yf != y0:
            frac = [(v - y0) / (yf - y0) for v in y]

            def cross(level):
                for i, f in enumerate(frac):
                    if f >= level:
                        if i == 0:
                            return t[0]
                        return t[i - 1] + (level - frac[i - 1]) / (f - frac[i - 1]) * (t[i] - t[i - 1])
                return math.nan
            rise = cross(0.9) - cross(0.1)
    return {"rise_time_s": rise,
            "overshoot_pct": overshoot,
            "settling_time_s": settle,
            "steady_state_error_counts": setpoint - yf,
            "final_position_counts": yf,
            "peak_position_counts": max(y, key=lambda v: sign * (v - y0)),
            "settled": 1.0 if settled else 0.0}


# ---------------------------------------------------------------- servo
def test_p_loop_csv_follows_the_lab_formula(motionsim):
    r = motionsim("servo", "--ctrl", "p", "--kp", "0.02", "--setpoint", "1000", "--duration", "3")
    assert r.rc == 0, r.err
    assert r.err == ""
    header, rows = r.rows()
    assert header == HEADER
    assert len(rows) == 151  # 0, 0.02, ..., 3.00 s
    for i, row in enumerate(rows):
        assert row["t_s"] == pytest.approx(i * 0.02, abs=1e-12)
        assert row["setpoint"] == 1000
        assert row["error_counts"] == row["setpoint"] - row["position_counts"]
        want = max(-100.0, min(100.0, 0.02 * row["error_counts"]))
        assert row["duty_pct"] == pytest.approx(want, rel=1e-6, abs=1e-6)
    assert rows[0]["position_counts"] == 0 and rows[0]["duty_pct"] == pytest.approx(20.0)
    # friction leaves a P loop short of the setpoint: it stops once Kp x error cannot keep it turning
    final = rows[-1]
    assert 0 < final["error_counts"] <= (BREAKAWAY_DUTY_PCT + 0.2) / 0.02
    assert max(r_["position_counts"] for r_ in rows) <= 1000


def test_duty_saturates_at_100_percent(motionsim):
    r = motionsim("servo", "--kp", "0.5", "--setpoint", "-5000", "--duration", "0.5")
    assert r.rc == 0, r.err
    _, rows = r.rows()
    assert rows[0]["duty_pct"] == -100
    assert all(-100 <= row["duty_pct"] <= 100 for row in rows)
    assert rows[-1]["position_counts"] < -1000  # a negative setpoint drives it backwards


METRIC_RUNS = [
    ["--ctrl", "p"],
    ["--ctrl", "p", "--kp", "0.1"],
    ["--ctrl", "pid", "--kp", "0.1", "--ki", "0.1", "--kd", "0.002", "--duration", "5"],
    # ends 5.5 % past the setpoint, held there by friction: overshoot measured against the
    # setpoint, not against the last sample (which would give 0)
    ["--ctrl", "pid", "--kp", "0.02", "--ki", "0.01", "--duration", "3"],
    # still moving at the end: not settled, so no settling or rise time
    ["--ctrl", "p", "--duration", "0.5"],
    ["--ctrl", "p", "--kp", "0.5", "--setpoint", "-3000", "--duration", "2"],  # a negative step
    ["--ctrl", "p", "--setpoint", "50"],  # below breakaway: never moves
    ["--ctrl", "p", "--setpoint", "0"],   # no step: overshoot undefined
]


def same(a, b):
    return (math.isnan(a) and math.isnan(b)) or a == pytest.approx(b, abs=1e-3)


@pytest.mark.parametrize("args", METRIC_RUNS, ids=lambda a: " ".join(a))
def test_metrics_on_stderr_match_their_definitions(motionsim, args):
    r = motionsim("servo", *args, "--metrics")
    assert r.rc == 0, r.err
    plain = motionsim("servo", *args)
    assert r.out == plain.out  # stdout stays the same pure CSV
    assert one_line(r.err)
    got = parse_metrics(r.err)
    _, rows = r.rows()
    want = step_metrics([x["t_s"] for x in rows], [x["position_counts"] for x in rows], rows[0]["setpoint"])
    assert set(got) == set(want)
    for k, v in want.items():
        assert same(got[k], v), (k, got[k], v)


def test_metrics_counterexamples(motionsim):
    # the two runs that the old final-value definitions got wrong, with the figures read off
    # their CSV by hand: the PID ends at 1055 (55 counts = 5.5 % past 1000) ...
    m = parse_metrics(motionsim("servo", "--ctrl", "pid", "--kp", "0.02", "--ki", "0.01", "--duration", "3",
                                "--metrics").err)
    assert m["final_position_counts"] == 1055 and m["overshoot_pct"] == pytest.approx(5.5)
    assert m["steady_state_error_counts"] == -55 and m["settled"] == 1
    # ... and the P loop is still climbing at 0.5 s (about 14 counts per period)
    r = motionsim("servo", "--ctrl", "p", "--duration", "0.5", "--metrics")
    m = parse_metrics(r.err)
    _, rows = r.rows()
    assert rows[-1]["position_counts"] - rows[-2]["position_counts"] > 10
    assert m["settled"] == 0 and math.isnan(m["settling_time_s"]) and math.isnan(m["rise_time_s"])
    assert m["steady_state_error_counts"] == 1000 - rows[-1]["position_counts"]


def test_pid_removes_the_friction_error(motionsim):
    r = motionsim("servo", "--ctrl", "pid", "--kp", "0.1", "--ki", "0.1", "--kd", "0.002", "--duration", "5", "--metrics")
    assert r.rc == 0, r.err
    m = parse_metrics(r.err)
    assert abs(m["steady_state_error_counts"]) <= 2
    assert 0 < m["overshoot_pct"] < 20
    assert m["settling_time_s"] < 4.0
    p = parse_metrics(motionsim("servo", "--ctrl", "p", "--kp", "0.1", "--metrics").err)
    assert p["steady_state_error_counts"] > 10  # P alone stops short


def test_pid_with_ki_kd_zero_is_the_p_controller(motionsim):
    # PID_v1 with Ki = Kd = 0 started from Output 0: output = Kp x error, the P controller's law
    a = motionsim("servo", "--ctrl", "pid", "--kp", "0.02")
    b = motionsim("servo", "--ctrl", "p", "--kp", "0.02")
    assert a.rc == 0 and b.rc == 0
    assert a.out == b.out


def test_double_precision_pid_stays_close_to_float(motionsim):
    args = ["servo", "--ctrl", "pid", "--kp", "0.05", "--ki", "0.02", "--duration", "1"]
    f = motionsim(*args).rows()[1]
    d = motionsim(*args, "--precision", "double").rows()[1]
    assert len(f) == len(d)
    # the first sample is identical; both reach the same region
    assert f[0]["duty_pct"] == pytest.approx(d[0]["duty_pct"], rel=1e-6)
    assert abs(f[-1]["position_counts"] - d[-1]["position_counts"]) <= 5


@pytest.mark.parametrize("args, words", [
    (["--kp", "-0.02"], "gains must not be negative"),
    (["--ctrl", "pid", "--ki", "-1"], "gains must not be negative"),
    (["--ctrl", "pid", "--kd", "-1"], "gains must not be negative"),
    (["--kp", "1e308"], "--kp: gains must be at most 1000"),
    (["--ctrl", "pid", "--ki", "1001"], "--ki: gains must be at most 1000"),
    (["--ctrl", "pid", "--kd", "1e4"], "--kd: gains must be at most 1000"),
    (["--ki", "0.1"], "--ki needs --ctrl pid"),
    # options the P controller would ignore are refused, whatever their value
    (["--ctrl", "p", "--ki", "0"], "--ki needs --ctrl pid"),
    (["--ctrl", "p", "--kd", "0.001"], "--kd needs --ctrl pid"),
    (["--kd", "0"], "--kd needs --ctrl pid"),
    (["--ctrl", "p", "--precision", "double"], "--precision needs --ctrl pid"),
    (["--precision", "float"], "--precision needs --ctrl pid"),
    (["--kp", "5000"], "at most"),
    (["--setpoint", "2000000"], "outside"),
    (["--setpoint", "12.5"], "whole number"),
    (["--duration", "0"], "--duration"),
    (["--duration", "abc"], "not a finite number"),
    (["--duration", "nan"], "not a finite number"),
    (["--ctrl", "pi"], "not one of p|pid"),
    (["--period-ms", "0"], "--period-ms"),
    (["--latency-us", "30000"], "--latency-us"),
    (["--precision", "half"], "float|double"),
])
def test_bad_servo_input_exits_2_with_one_line(motionsim, args, words):
    r = motionsim("servo", *args)
    assert r.rc == 2, (args, r.err)
    assert one_line(r.err) and words in r.err, r.err
    assert r.out == ""


def test_unwritable_output_is_a_runtime_error(motionsim, tmp_path):
    r = motionsim("servo", "-o", str(tmp_path / "no" / "such" / "dir.csv"))
    assert r.rc == 1 and one_line(r.err)


# ---------------------------------------------------------------- pid-replay
def f32(x):
    return struct.unpack("f", struct.pack("f", float(x)))[0]


def read_vector(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("name", NAMES)
def test_pid_replay_double_equals_the_reference(motionsim, name):
    path = os.path.join(VECTORS, name + ".csv")
    r = motionsim("pid-replay", path)
    assert r.rc == 0, r.err
    got = list(csv.DictReader(io.StringIO(r.out)))
    ref = read_vector(path)
    assert r.out.splitlines()[0] == "t_ms,computed,output"
    assert len(got) == len(ref)
    for g, w in zip(got, ref):
        assert g["t_ms"] == w["t_ms"] and g["computed"] == w["computed"]
        assert float(g["output"]) == float(w["output"]), (w["t_ms"], g["output"], w["output"])
        assert g["output"] == w["output"]  # same shortest round-trip text


@pytest.mark.parametrize("name", NAMES)
def test_pid_replay_float_equals_the_float32_reference(motionsim, name):
    path = os.path.join(VECTORS, "float32", name + ".csv")
    r = motionsim("pid-replay", "--float", path)
    assert r.rc == 0, r.err
    got = list(csv.DictReader(io.StringIO(r.out)))
    ref = read_vector(path)
    assert len(got) == len(ref)
    for g, w in zip(got, ref):
        assert g["t_ms"] == w["t_ms"] and g["computed"] == w["computed"]
        assert f32(g["output"]) == f32(w["output"]), (w["t_ms"], g["output"], w["output"])
        assert g["output"] == w["output"]  # the shortest text for the float, as the vector has it


def test_pid_replay_double_of_float_vector_differs(motionsim):
    # the float32 vectors really are float: replaying one in double does not reproduce it
    path = os.path.join(VECTORS, "float32", "b_pid_windup.csv")
    r = motionsim("pid-replay", path)
    assert r.rc == 0
    got = [row["output"] for row in csv.DictReader(io.StringIO(r.out))]
    ref = [row["output"] for row in read_vector(path)]
    assert sum(1 for a, b in zip(got, ref) if float(a) != float(b)) > 10


def write_vector(tmp_path, rows, json_text=None, name="v"):
    ref = read_vector(os.path.join(VECTORS, "a_p_only.csv"))
    cols = ["t_ms", "input", "setpoint", "command", "computed", "output"]
    lines = [",".join(cols)]
    for i, cmd in enumerate(rows):
        r = ref[i]
        lines.append(",".join([r["t_ms"], r["input"], r["setpoint"], cmd, r["computed"], r["output"]]))
    (tmp_path / f"{name}.csv").write_text("\n".join(lines) + "\n")
    if json_text is None:
        with open(os.path.join(VECTORS, "a_p_only.json")) as f:
            json_text = f.read()
    (tmp_path / f"{name}.json").write_text(json_text)
    return str(tmp_path / f"{name}.csv")


def test_pid_replay_accepts_every_documented_command(motionsim, tmp_path):
    cmds = ["SetMode(AUTOMATIC)", "SetTunings(0.5 1 0.05)", "SetTunings(0.5 1 0.05 P_ON_M)", "SetSampleTime(50)",
            "SetOutputLimits(-50 50)", "SetControllerDirection(REVERSE)", "Output:=3.5;SetMode(MANUAL)",
            "SetMode(2);SetTunings(1 2 3 7);SetControllerDirection(2)", ""]
    r = motionsim("pid-replay", write_vector(tmp_path, cmds))
    assert r.rc == 0, r.err
    assert len(r.out.strip().splitlines()) == 1 + len(cmds)


@pytest.mark.parametrize("cmd, words", [
    ("SetMode(AUTO)", "SetMode(AUTO)"),
    ("SetTunings(1 2)", "3 or 4 arguments"),
    ("SetTunings(1 x 2)", "not a finite number"),
    ("SetSampleTime(2.5)", "not an integer"),
    ("SetOutputLimits(1)", "2 arguments"),
    ("Compute()", "unknown call"),
    ("Output:=abc", "not a finite number"),
    ("SetMode(AUTOMATIC);", "empty call"),
    ("SetMode AUTOMATIC", "not a call"),
    ("SetTunings(1  2 3)", "one space"),
])
def test_pid_replay_bad_command_names_file_and_line(motionsim, tmp_path, cmd, words):
    path = write_vector(tmp_path, ["SetMode(AUTOMATIC)", cmd])
    r = motionsim("pid-replay", path)
    assert r.rc == 2
    assert one_line(r.err) and words in r.err and ":3:" in r.err, r.err
    assert r.out == ""


@pytest.mark.parametrize("json_text, words", [
    ('{"kp": 1, "ki": 0, "kd": 0, "pon": "P_ON_E", "direction": "DIRECT", "t0_ms": 0, "input0": 0, '
     '"output0": 0, "setpoint0": 0, "setup": [],}', "line 1"),
    ('{"kp": 1, "ki": 0, "kd": 0, "pon": "P_ON_E", "direction": "DIRECT", "t0_ms": 0, "input0": 0, '
     '"output0": 0, "setpoint0": 0, "setup": [], "extra": 1}', 'unknown key "extra"'),
    ('{"kp": 1, "ki": 0, "kd": 0, "pon": "P_ON_E", "direction": "DIRECT", "t0_ms": 0, "input0": 0, '
     '"output0": 0, "setup": []}', '"setpoint0" is missing'),
    ('{"kp": {"a": 1}}', "expected a number"),
    ('{"kp": true}', "expected a number"),
    ('{"kp": 1 2}', "line 1 column 10: not valid JSON (near '2}')"),
    ('{"kp": 1, "kp": 2}', "duplicate key"),
    ('{"kp": 1, "ki": 0, "kd": 0, "pon": "P_ON_X", "direction": "DIRECT", "t0_ms": 0, "input0": 0, '
     '"output0": 0, "setpoint0": 0, "setup": []}', '"pon"'),
    ('{"kp": 1, "ki": 0, "kd": 0, "pon": "P_ON_E", "direction": "DIRECT", "t0_ms": -5, "input0": 0, '
     '"output0": 0, "setpoint0": 0, "setup": []}', '"t0_ms"'),
    ('{"kp": 1, "ki": 0, "kd": 0, "pon": "P_ON_E", "direction": "DIRECT", "t0_ms": 0, "input0": 0, '
     '"output0": 0, "setpoint0": 0, "setup": [1, 2]}', "only strings"),
    ('{"kp": 1, "ki": 0, "kd": 0, "pon": "P_ON_E", "direction": "DIRECT", "t0_ms": 0, "input0": 0, '
     '"output0": 0, "setpoint0": 0, "setup": ["SetFoo(1)"]}', "unknown call"),
    ('{"kp": 1} trailing', "line 1 column 11: not valid JSON (near 'trailing')"),
    ('', "line 1 column 1: not valid JSON"),
    ('[1, 2]', "must be one JSON object"),
    ('{"kp": 1,\n "ki": }', "line 2 column 8: not valid JSON"),
    # found by the fuzzer: the text near the error holds a line end, tab or control byte; the message
    # stays one line (they are written \\n \\t \\xNN)
    ('{"kp": 1 2\n}', "line 1 column 10: not valid JSON (near '2\\n}')"),
    ('{\n "kp": 0.5,\n "ki"\t: x}', "line 3 column 9: not valid JSON (near 'x}')"),
    ('{"kp": 1 x\t\x01\r\n}', "line 1 column 10: not valid JSON (near 'x\\t\\x01\\r\\n}')"),
])
def test_pid_replay_bad_json_is_refused(motionsim, tmp_path, json_text, words):
    path = write_vector(tmp_path, ["SetMode(AUTOMATIC)"], json_text=json_text)
    r = motionsim("pid-replay", path)
    assert r.rc == 2
    assert one_line(r.err) and words in r.err, r.err
    assert r.out == ""


SETUP = ('{{"kp": {kp}, "ki": {ki}, "kd": {kd}, "pon": "P_ON_E", "direction": "DIRECT", "t0_ms": 0, '
         '"input0": 0, "output0": 0, "setpoint0": 0, "setup": ["SetMode(AUTOMATIC)"]}}')


@pytest.mark.parametrize("gains, key", [((-1, 0, 0), "kp"), ((1, -0.5, 0), "ki"), ((1, 0, -1e-9), "kd")])
def test_pid_replay_refuses_a_negative_gain_at_construction(motionsim, tmp_path, gains, key):
    # reference README, "Construction": with a negative gain PID_v1's constructor rejects the
    # tunings and its working gains stay indeterminate: the library has no behaviour to replay
    kp, ki, kd = gains
    path = write_vector(tmp_path, ["", ""], json_text=SETUP.format(kp=kp, ki=ki, kd=kd))
    r = motionsim("pid-replay", path)
    assert r.rc == 2 and one_line(r.err), r.err
    assert f'"{key}" is negative' in r.err and "constructor" in r.err, r.err
    assert r.out == ""


def test_pid_replay_negative_gains_later_are_ignored_as_pid_v1_does(motionsim, tmp_path):
    # SetTunings with a negative gain after construction is well defined (ignored, vector h):
    # the replay accepts it and the output is the same as without the call
    plain = motionsim("pid-replay", write_vector(tmp_path, ["", "", ""], json_text=SETUP.format(kp=1, ki=0, kd=0)))
    with_bad = motionsim("pid-replay", write_vector(tmp_path, ["", "SetTunings(-1 0 0)", ""],
                                                    json_text=SETUP.format(kp=1, ki=0, kd=0), name="w"))
    assert plain.rc == 0 and with_bad.rc == 0, with_bad.err
    assert plain.out == with_bad.out


def test_pid_replay_refuses_a_header_naming_a_column_twice(motionsim, tmp_path):
    # issue 12 item 8: the first `input` was used; now refused, as `motionsim filter` does
    path = write_vector(tmp_path, ["SetMode(AUTOMATIC)", ""])
    text = open(path).read().splitlines()
    text[0] = text[0] + ",input"
    text[1:] = [t + ",5" for t in text[1:]]
    open(path, "w").write("\n".join(text) + "\n")
    r = motionsim("pid-replay", path)
    assert r.rc == 2 and one_line(r.err), r.err
    assert ":1: the header names column 'input' twice" in r.err, r.err
    assert r.out == ""


def test_pid_replay_refuses_a_nul_byte_naming_its_line_and_reads_crlf(motionsim, tmp_path):
    """The one CSV reader (sim/csv_read.c, shared with `motionsim filter`): a NUL byte in a row is
    refused with the row's line; CR LF line ends read as LF ones (the same replay)."""
    path = write_vector(tmp_path, ["SetMode(AUTOMATIC)", "", ""])
    plain = motionsim("pid-replay", path)
    assert plain.rc == 0, plain.err
    text = open(path, "rb").read()
    open(path, "wb").write(text.replace(b"\n", b"\r\n"))
    crlf = motionsim("pid-replay", path)
    assert crlf.rc == 0 and crlf.out == plain.out, crlf.err
    lines = text.split(b"\n")
    lines[2] = lines[2][:3] + b"\x00" + lines[2][3:]
    open(path, "wb").write(b"\n".join(lines))
    r = motionsim("pid-replay", path)
    assert r.rc == 2 and one_line(r.err) and r.out == "", r.err
    assert f"{path}:3: contains a NUL byte (not a text file)" in r.err, r.err


def test_pid_replay_file_problems(motionsim, tmp_path):
    r = motionsim("pid-replay")
    assert r.rc == 2 and one_line(r.err) and "VECTOR.csv" in r.err
    r = motionsim("pid-replay", "a.csv", "b.csv")
    assert r.rc == 2 and one_line(r.err)
    # a missing vector is "cannot read", with or without a .json beside it
    r = motionsim("pid-replay", str(tmp_path / "missing.csv"))
    assert r.rc == 2 and one_line(r.err) and "cannot read" in r.err and "missing.csv" in r.err, r.err
    # a vector without its set-up
    (tmp_path / "alone.csv").write_text(open(os.path.join(VECTORS, "a_p_only.csv")).read())
    r = motionsim("pid-replay", str(tmp_path / "alone.csv"))
    assert r.rc == 2 and one_line(r.err) and "no set-up file" in r.err
    r = motionsim("pid-replay", str(tmp_path / "vector.txt"))
    assert r.rc == 2 and one_line(r.err) and ".csv" in r.err
    # a .json but no .csv
    (tmp_path / "lonely.json").write_text(open(os.path.join(VECTORS, "a_p_only.json")).read())
    r = motionsim("pid-replay", str(tmp_path / "lonely.csv"))
    assert r.rc == 2 and one_line(r.err) and "cannot read" in r.err
    # a row with a missing field, and a header without the input columns
    path = write_vector(tmp_path, ["SetMode(AUTOMATIC)", ""])
    text = open(path).read().splitlines()
    text[2] = text[2].rsplit(",", 1)[0]
    open(path, "w").write("\n".join(text) + "\n")
    r = motionsim("pid-replay", path)
    # the counts in the message: the row has 5 fields, the header (written above) 6
    assert r.rc == 2 and one_line(r.err) and ":3: 5 fields, the header has 6" in r.err, r.err
    # a bad cell is quoted as it was in the file
    text[2] = "12x," + text[1].split(",", 1)[1]
    open(path, "w").write("\n".join(text) + "\n")
    r = motionsim("pid-replay", path)
    assert r.rc == 2 and one_line(r.err) and ":3: t_ms '12x' is not a whole number" in r.err, r.err
    open(path, "w").write("t_ms,computed\n0,1\n")
    r = motionsim("pid-replay", path)
    assert r.rc == 2 and one_line(r.err) and "t_ms, input, setpoint and command" in r.err
    # a binary file
    open(path, "wb").write(b"t_ms,input\x00,setpoint,command\n")
    r = motionsim("pid-replay", path)
    assert r.rc == 2 and one_line(r.err)
