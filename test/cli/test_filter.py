"""`motionsim filter` (issue 4): the moving-average-filter note's checkpoint for every kind from the command line, the
input syntax, the sketch's stream format, CSV round trips, and every kind of bad input (exit 2,
one line, no output). Expected values come from the continuous-time formulas, not from the code."""
import math
import re

import pytest

TS = 0.01


def ideal_ma(t, amp=5.0, tau=9.0, t0=0.0):
    """The moving-average-filter note: the moving average's step response is a straight ramp reaching amp at t0 + tau."""
    return amp * min(max(t - t0, 0.0), tau) / tau


def ideal_s_curve(t, amp=5.0, t1=9.0, t2=3.0):
    r = lambda x: x * x / 2 if x > 0 else 0.0  # noqa: E731
    return amp * (r(t) - r(t - t1) - r(t - t2) + r(t - t1 - t2)) / (t1 * t2)


def ideal_exp(t, amp=5.0, tau=9.0):
    return amp * -math.expm1(-t / tau)


def one_line(text):
    return len(text.strip().splitlines()) == 1


# ---- the moving-average-filter note's checkpoint ------------------------------------------------------------------

def test_note_moving_average_reaches_5v_exactly_9s_after_the_step(motionsim):
    """The moving-average-filter note ("It is successfully accelerated in 9 seconds"): tau = 9 s, Ts = 10 ms, 5 V step
    held 20 s. y rises linearly, is 2.5 V half-way, 5 V at exactly t = 9 s (the step is sample 0
    at t = 0; the one-sample ZOH delay shows as y = 0 at k = 0), within 1e-6 V of the ramp."""
    r = motionsim("filter", "--kind", "ma", "--tau", 9, "--ts", TS, "--input", "step:5", "--duration", 20)
    assert r.rc == 0, r.err
    header, rows = r.rows()
    assert header == ["k", "t_s", "u", "y"]
    assert len(rows) == 2001
    for i, row in enumerate(rows):
        assert row["k"] == i
        assert abs(row["t_s"] - i * TS) < 1e-12
        assert row["u"] == 5.0
        assert abs(row["y"] - ideal_ma(row["t_s"])) <= 1e-6
    assert rows[0]["y"] == 0.0 and rows[1]["y"] > 0.0
    assert abs(rows[450]["y"] - 2.5) <= 1e-12
    assert rows[899]["y"] < 5.0 and rows[900]["y"] == 5.0 and rows[900]["t_s"] == 9.0


def test_note_two_stage_is_the_s_curve_and_ends_at_tau1_plus_tau2(motionsim):
    r = motionsim("filter", "--kind", "ma2", "--tau", 9, "--tau2", 3, "--input", "step:5", "--duration", 20)
    assert r.rc == 0, r.err
    _, rows = r.rows()
    for row in rows:
        assert abs(row["y"] - ideal_s_curve(row["t_s"])) <= 1e-6
    assert abs(rows[600]["y"] - 2.5) <= 1e-12
    assert rows[1199]["y"] < 5.0 and rows[1200]["y"] == 5.0


def test_note_exponential_matches_its_closed_form(motionsim):
    r = motionsim("filter", "--kind", "exp", "--tau", 9, "--input", "step:5", "--duration", 20)
    assert r.rc == 0, r.err
    _, rows = r.rows()
    for row in rows:
        assert abs(row["y"] - ideal_exp(row["t_s"])) <= 1e-6
    assert abs(rows[900]["y"] - 5 * (1 - math.exp(-1))) <= 1e-6


# ---- inputs -----------------------------------------------------------------------------------

def test_delayed_step_starts_at_the_first_sample_at_or_after_t_start(motionsim):
    r = motionsim("filter", "--input", "step:2.5:1.23", "--duration", 12)
    assert r.rc == 0, r.err
    _, rows = r.rows()
    assert all(row["u"] == 0.0 for row in rows[:123]) and all(row["u"] == 2.5 for row in rows[123:])
    for row in rows:
        assert abs(row["y"] - ideal_ma(row["t_s"], amp=2.5, t0=1.23)) <= 1e-6
    assert rows[123 + 900]["y"] == 2.5 and rows[123 + 899]["y"] < 2.5


def test_square_wave_is_high_for_the_first_half_of_each_period(motionsim):
    r = motionsim("filter", "--input", "square:5:30", "--duration", 60)
    assert r.rc == 0, r.err
    _, rows = r.rows()
    assert len(rows) == 6001
    for row in rows:
        phase = (row["k"] % 3000)
        assert row["u"] == (5.0 if phase < 1500 else 0.0)
    # decelerates like it accelerates: 9 s after the falling edge at 15 s it is back at 0
    assert rows[1500]["y"] == 5.0 and rows[2400]["y"] == 0.0 and abs(rows[1950]["y"] - 2.5) < 1e-12


def test_inputs_are_quantised_to_the_quantum(motionsim, tmp_path):
    # step/square amplitudes must be whole quanta (like the sketch's `u`); csv samples are rounded
    r = motionsim("filter", "--input", "step:1.234", "--duration", 0.02)
    assert r.rc == 0, r.err
    assert [row["u"] for row in r.rows()[1]] == [1.234, 1.234, 1.234]
    r = motionsim("filter", "--input", "step:1.23", "--quantum", 0.01, "--duration", 0.01)
    assert r.rc == 0, r.err
    assert [row["u"] for row in r.rows()[1]] == [1.23, 1.23]
    r = motionsim("filter", "--input", "step:1.2346", "--quantum", 0.01, "--duration", 0.01)
    assert r.rc == 2 and "whole number of input quanta" in r.err, r.err
    src = tmp_path / "u.csv"
    src.write_text("u\n1.2344\n1.2346\n-1.2345\n")
    r = motionsim("filter", "--input", f"csv:{src}")
    assert r.rc == 0, r.err
    assert [row["u"] for row in r.rows()[1]] == [1.234, 1.235, -1.235]  # halves away from zero


def test_csv_input_replays_the_u_column_and_round_trips(motionsim, tmp_path):
    out = tmp_path / "sq.csv"
    r = motionsim("filter", "--kind", "ma2", "--input", "square:5:30", "--duration", 40, "-o", out)
    assert r.rc == 0 and r.out == "", r.err
    again = motionsim("filter", "--kind", "ma2", "--input", f"csv:{out}")
    assert again.rc == 0, again.err
    assert again.out == out.read_text()
    single = tmp_path / "single.csv"
    single.write_text("volts\n0\n1\n1\n1\n")
    r = motionsim("filter", "--tau", 0.02, "--input", f"csv:{single}")
    assert r.rc == 0, r.err
    assert [row["y"] for row in r.rows()[1]] == [0.0, 0.0, 0.5, 1.0]


def test_stream_is_the_sketch_format_and_agrees_with_the_csv(motionsim, tmp_path):
    """--stream: t_ms,u,y with t_ms = 10 k, u with 3 decimals, y rounded to 6 decimals."""
    plain = motionsim("filter", "--kind", "exp", "--input", "step:5:0.5", "--duration", 12)
    stream = motionsim("filter", "--kind", "exp", "--input", "step:5:0.5", "--duration", 12, "--stream")
    assert plain.rc == 0 and stream.rc == 0
    lines = stream.out.splitlines()
    assert lines[0] == "t_ms,u,y"
    _, rows = plain.rows()
    assert len(lines) == len(rows) + 1
    for line, row in zip(lines[1:], rows):
        assert re.fullmatch(r"\d+,-?\d+\.\d{3},-?\d+\.\d{6}", line), line
        t_ms, u, y = line.split(",")
        assert int(t_ms) == round(row["t_s"] * 1000)
        assert float(u) == row["u"]
        assert abs(float(y) - row["y"]) <= 0.5e-6 + 1e-12
    # one tau after the step at 0.5 s: 5 V (1 - 1/e) = 3.1606028 V, printed to the microvolt
    assert lines[1 + 950] == "9500,5.000,%.6f" % (5 * (1 - math.exp(-1)))
    # a capture of the stream replays into the identical stream
    cap = tmp_path / "capture.csv"
    cap.write_text(stream.out)
    again = motionsim("filter", "--kind", "exp", "--input", f"csv:{cap}", "--stream")
    assert again.rc == 0, again.err
    assert again.out == stream.out


def test_help_defines_the_input_syntax_and_the_delay_convention(motionsim):
    r = motionsim("filter", "--help")
    assert r.rc == 0
    for text in ("step:AMPLITUDE[:T_START]", "square:AMPLITUDE:PERIOD", "csv:FILE", "column named u",
                 "Delay convention", "--stream", "--quantum"):
        assert text in r.out, text


# ---- bad input: exit 2, one line, nothing on stdout --------------------------------------------

BAD = [
    (["--tau", "9.005"], "tau/Ts must be a whole number"),
    (["--tau", "0.005"], "at least one sample time"),
    (["--tau", "-9"], "at least one sample time"),
    (["--tau", "700"], "more taps"),
    (["--ts", "0"], "Ts must be greater than 0"),
    (["--ts", "-0.01"], "Ts must be greater than 0"),
    (["--tau", "nan"], "not a finite number"),
    (["--ts", "inf"], "not a finite number"),
    (["--tau2", "3"], "--kind ma2 only"),
    (["--kind", "ma2", "--tau2", "3.005"], "whole number"),
    (["--kind", "ma2", "--tau2", "0"], "at least one sample time"),
    (["--kind", "ma2", "--tau", "400", "--tau2", "300"], "more taps"),
    (["--kind", "exp", "--tau", "1.234"], "whole number"),
    (["--kind", "lowpass"], "not one of ma|ma2|exp"),
    (["--input", "step"], "expected step:AMPLITUDE"),
    (["--input", "step:"], "not a number of volts"),
    (["--input", "step:5V"], "not a number of volts"),
    (["--input", "step:5:-1"], "T_START"),
    (["--input", "step:5:1:2"], "expected step:AMPLITUDE"),
    (["--input", "step:40"], "outside the filter's range"),
    (["--input", "step:0.0005"], "whole number of input quanta"),
    (["--input", "step:1e-4"], "whole number of input quanta"),
    (["--input", "square:2.0004:1"], "whole number of input quanta"),
    (["--input", "step:0x5"], "not a number of volts"),
    (["--input", "step:5:2e17"], "beyond the longest run"),
    (["--input", "step:5:1e300"], "beyond the longest run"),
    (["--tau", "0x9"], "not a finite number"),
    (["--input", "square:5"], "expected step:AMPLITUDE"),
    (["--input", "square:5:0"], "PERIOD"),
    (["--input", "square:5:0.015"], "whole number of samples"),
    (["--input", "ramp:5"], "expected step:AMPLITUDE"),
    (["--input", "csv:"], "no file name"),
    (["--input", "csv:/nonexistent/x.csv"], "cannot read"),
    (["--quantum", "0"], "quantum must be greater than 0"),
    (["--quantum", "-1"], "quantum must be greater than 0"),
    (["--quantum", "0.002", "--stream"], "--quantum 0.001"),
    (["--duration", "-1"], "0 s or more"),
    (["--duration", "1e12"], "more than"),
    (["--duration"], "needs a value"),
]


@pytest.mark.parametrize("args,message", BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_arguments_exit_2_with_one_line(motionsim, args, message):
    r = motionsim("filter", *args)
    assert r.rc == 2, (args, r.err)
    assert one_line(r.err) and message in r.err, (args, r.err)
    assert r.out == ""


CSV_BAD = [
    ("", "no samples"),
    ("u\n", "no samples"),
    ("a,b\n1,2\n", "no column named u"),
    ("u,u\n1,2\n", "names column 'u' twice"),
    ("t_ms,u,t_ms\n0,1,0\n", "names column 't_ms' twice"),
    ("u\n1\nx\n", "'x' is not a number"),
    ("u\n1\nnan\n", "is not a number"),
    ("u,t_ms\n1,0\n1,10\n1\n", "fields"),
    ("t_ms,u,y\n0,1,0\n10,1,0\n30,1,0\n", "consecutive samples"),
    ("k,t_s,u,y\n0,0,1,0\n2,0.02,1,0\n", "consecutive samples"),
    ("u\n99\n", "outside the filter's range"),
    # issue 12 item 8: a NUL byte is refused, not read as a blank row or as the end of a number
    ("u\n1\n\x009\n2\n", "line 3: contains a NUL byte (not a text file)"),
    ("u\n1\n2\x009\n", "line 3: contains a NUL byte (not a text file)"),
    ("u\x00\n1\n", "line 1: contains a NUL byte (not a text file)"),
]


@pytest.mark.parametrize("content,message", CSV_BAD, ids=[c for _, c in CSV_BAD])
def test_bad_csv_input_exits_2_with_one_line(motionsim, tmp_path, content, message):
    f = tmp_path / "in.csv"
    f.write_text(content)
    r = motionsim("filter", "--input", f"csv:{f}")
    assert r.rc == 2, r.err
    assert one_line(r.err) and message in r.err, r.err
    assert r.out == ""


def test_csv_line_ends_blanks_and_blank_lines(motionsim, tmp_path):
    """CR LF line ends, blanks around fields and blank lines read as the plain file does."""
    plain, odd = tmp_path / "plain.csv", tmp_path / "odd.csv"
    plain.write_text("t_ms,u\n0,1\n10,2\n20,3\n")
    odd.write_bytes(b"\r\n t_ms , u\t\r\n0,1\r\n   \r\n10 ,\t2\r\n\n20,3")
    want = motionsim("filter", "--tau", 0.02, "--input", f"csv:{plain}")
    got = motionsim("filter", "--tau", 0.02, "--input", f"csv:{odd}")
    assert want.rc == 0 and got.rc == 0, got.err
    assert got.out == want.out and len(want.out.splitlines()) == 4


def test_duration_longer_than_the_csv_is_refused(motionsim, tmp_path):
    f = tmp_path / "in.csv"
    f.write_text("u\n1\n2\n3\n")
    r = motionsim("filter", "--tau", 0.02, "--input", f"csv:{f}", "--duration", 0.05)
    assert r.rc == 2 and one_line(r.err) and "holds 3" in r.err and r.out == ""
    r = motionsim("filter", "--tau", 0.02, "--input", f"csv:{f}", "--duration", 0.02)
    assert r.rc == 0 and len(r.rows()[1]) == 3
