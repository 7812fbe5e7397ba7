"""motionsim's top level: help, unknown commands and options, malformed numbers, options given
twice, write errors (issue: foundation)."""
import os
import re

import pytest

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data", "pid_v1")

COMMANDS = ["ramp", "filter", "servo", "pid-replay", "move"]


def one_line(text):
    return len(text.strip().splitlines()) == 1


def test_help_lists_every_subcommand(motionsim):
    r = motionsim("--help")
    assert r.rc == 0
    for c in COMMANDS:
        assert f"\n  {c} " in r.out


def test_no_arguments_is_a_usage_error(motionsim):
    r = motionsim()
    assert r.rc == 2
    assert "usage: motionsim" in r.err
    # one line like every exit-2 error (the fuzzer's rule, tools/fuzz/motionsim_fuzz.py)
    assert len(r.err.splitlines()) == 1 and "command is missing" in r.err, r.err
    assert r.out == ""


def test_unknown_command_exits_2_with_one_line(motionsim):
    r = motionsim("frobnicate")
    assert r.rc == 2
    assert one_line(r.err) and "unknown command 'frobnicate'" in r.err
    assert r.out == ""


def test_every_subcommand_has_help_with_options(motionsim):
    for c in COMMANDS:
        r = motionsim(c, "--help")
        assert r.rc == 0, c
        assert r.out.startswith(f"usage: motionsim {c}"), c
        assert "options:" in r.out and "--help" in r.out, c


def test_unknown_option_exits_2_with_one_line(motionsim):
    for c in COMMANDS:
        r = motionsim(c, "--no-such-option", "1")
        assert r.rc == 2, c
        assert one_line(r.err) and "unknown option '--no-such-option'" in r.err, (c, r.err)
        assert r.out == "", c


# one option with a value and one flag per subcommand, and the arguments each needs to run
REPEATABLE = {
    "ramp": (["--to", "5", "--to", "6"], "--to given twice"),
    "filter": (["--tau", "9", "--tau", "3"], "--tau given twice"),
    "servo": (["--kp", "0.02", "--kp", "0.05"], "--kp given twice"),
    "pid-replay": (["--float", "--float", "x.csv"], "--float given twice"),
    "move": (["--x", "5", "--x", "6"], "--x given twice"),
}


def test_an_option_given_twice_is_refused(motionsim, tmp_path):
    """A second value used to replace the first without a word; now exit 2 with one line."""
    for c, (args, message) in REPEATABLE.items():
        r = motionsim(c, *args)
        assert r.rc == 2 and r.out == "", c
        assert r.err.strip().splitlines() == [f"motionsim {c}: {message}"], (c, r.err)
        r = motionsim(c, "-o", tmp_path / "a.csv", "-o", tmp_path / "b.csv", "x.csv" if c == "pid-replay" else "-h")
        assert r.rc == 2 and r.err.strip().splitlines() == [f"motionsim {c}: -o given twice"], (c, r.err)
        assert not (tmp_path / "a.csv").exists() and not (tmp_path / "b.csv").exists()


def test_help_descriptions_never_run_into_the_option(motionsim):
    """Every option's description starts in one column, two blanks or more after the option; an
    option too wide for the column (ramp's --algo choices) has its description on the next line."""
    for c in COMMANDS:
        lines = motionsim(c, "--help").out.split("\n")
        opts = lines[lines.index("options:") + 1:]
        opts = [line for line in opts if line]
        col = None
        i = 0
        while i < len(opts):
            line = opts[i]
            assert line.startswith("  -"), (c, line)
            m = re.match(r"  (\S.*?)  +(\S.*)$", line)
            if m is None:
                # the option alone; its description on the next line, indented to the column
                nxt = opts[i + 1]
                here = len(nxt) - len(nxt.lstrip())
                i += 2
            else:
                here = m.start(2)
                i += 1
            col = here if col is None else col
            assert here == col, (c, line)
    algo = motionsim("ramp", "--help").out.split("\n")
    k = algo.index("  --algo simplistic|leib|exact|sigmoid")
    assert algo[k + 1].strip() == "ramp algorithm (default leib)"


def test_integer_options_refuse_hex_and_doubles_say_why_they_are_out_of_range(motionsim):
    cases = [
        ("ramp", ["--to", "0x5"], "--to: '0x5' is not a whole number"),
        ("ramp", ["--tick-hz", "0X10"], "--tick-hz: '0X10' is not a whole number"),
        ("servo", ["--setpoint", "0x10"], "--setpoint: '0x10'"),
        ("servo", ["--kp", "1e-320"], "--kp: '1e-320' is out of range: it underflows a double"),
        ("filter", ["--tau", "1e999"], "--tau: '1e999' is out of range: it overflows a double"),
    ]
    for c, args, message in cases:
        r = motionsim(c, *args)
        assert r.rc == 2 and r.out == "", (c, args)
        assert one_line(r.err) and message in r.err, (c, args, r.err)


def test_a_write_error_is_reported_in_one_line(motionsim):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    runs = {"ramp": [], "filter": [], "servo": [], "pid-replay": [os.path.join(DATA, "a_p_only.csv")],
            "move": ["--x", "100"]}
    for c, args in runs.items():
        r = motionsim(c, *args, "-o", "/dev/full")
        assert r.rc == 1, (c, r.err)
        assert r.err.strip().splitlines() == [f"motionsim {c}: writing '/dev/full' failed: No space left on device"]


def test_a_write_error_stops_a_long_run_at_once(motionsim):
    # each command stops at the first failed row instead of computing the rest (seconds of work)
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    runs = {"filter": ["--duration", "20000", "--max-rows", "2000001"], "servo": ["--duration", "3600", "--period-ms", "1", "--latency-us", "500"],
            "ramp": ["--to", "100000000", "--max-rows", "100000000"],
            "move": ["--x", "100000000", "--y", "50000000", "--max-rows", "150000000"]}
    for c, args in runs.items():
        r = motionsim(c, *args, "-o", "/dev/full", timeout=5)
        assert r.rc == 1, (c, r.err)
        assert one_line(r.err) and r.err.startswith(f"motionsim {c}: writing '/dev/full' failed"), (c, r.err)


# Options are parsed by getopt_long(3) (issue 12); what it would add by default is decided here.
def test_abbreviated_options_are_refused_with_the_whole_name(motionsim):
    """getopt_long accepts a unique prefix ("--acc" for "--accel"); motionsim does not, so that a
    script keeps its meaning when an option is added: one line naming the whole option."""
    cases = [
        ("ramp", ["--acc", "5"], "option '--acc' is abbreviated: write --accel (abbreviations are not accepted)"),
        ("ramp", ["--compar"], "option '--compar' is abbreviated: write --compare"),
        ("servo", ["--metric"], "option '--metric' is abbreviated: write --metrics"),
        ("filter", ["--str=1"], "option '--str' is abbreviated: write --stream"),
        ("ramp", ["--hel"], "option '--hel' is abbreviated: write --help"),
        # a prefix of several options is simply unknown
        ("ramp", ["--t", "5"], "unknown option '--t'"),
    ]
    for c, args, message in cases:
        r = motionsim(c, *args)
        assert r.rc == 2 and r.out == "", (c, args, r.out)
        assert one_line(r.err) and r.err.startswith(f"motionsim {c}: ") and message in r.err, (c, args, r.err)


def test_unknown_short_options_and_option_values(motionsim):
    cases = [
        ("ramp", ["-x"], "unknown option '-x'"),
        ("ramp", ["-5"], "unknown option '-5'"),          # where an option stands, -5 is not a number
        ("servo", ["--frob=3"], "unknown option '--frob'"),
        ("ramp", ["-o"], "option -o needs a value (FILE)"),
        ("ramp", ["--help=1"], "option --help takes no value"),
        ("ramp", ["--metrics"], "unknown option '--metrics'"),
    ]
    for c, args, message in cases:
        r = motionsim(c, *args)
        assert r.rc == 2 and r.out == "", (c, args)
        assert one_line(r.err) and message in r.err, (c, args, r.err)


def test_negative_numbers_are_option_values(motionsim):
    """A value that starts with '-' is still the option's value, in both spellings, and reaches the
    range check (getopt_long takes the next argument for an option that needs one)."""
    for args in (["--v0", "-5"], ["--v0=-5"]):
        r = motionsim("ramp", *args)
        assert r.rc == 2 and r.err.strip() == "motionsim ramp: minimum speed v0 must not be negative", (args, r.err)
    r = motionsim("ramp", "--from", "-3", "--to", "-1", "--v0", "1", "--vmax", "2", "--accel", "1")
    assert r.rc == 0, r.err
    assert [int(row["position"]) for row in r.rows()[1]] == [-2, -1]


def test_double_dash_ends_the_options(motionsim, tmp_path):
    vector = os.path.join(DATA, "a_p_only.csv")
    plain = motionsim("pid-replay", vector)
    after = motionsim("pid-replay", "--", vector)
    assert plain.rc == 0 and after.rc == 0 and after.out == plain.out, after.err
    r = motionsim("ramp", "--to", "5", "--", "--compare")
    assert r.rc == 2 and one_line(r.err) and "unexpected argument '--compare'" in r.err, r.err


def test_short_option_spellings(motionsim, tmp_path):
    """-o FILE, -oFILE and -o=FILE (the old parser's spelling) write the same file."""
    want = motionsim("ramp", "--to", "4").out
    for k, args in enumerate((["-o", tmp_path / "a.csv"], [f"-o{tmp_path / 'b.csv'}"], [f"-o={tmp_path / 'c.csv'}"])):
        r = motionsim("ramp", "--to", "4", *args)
        assert r.rc == 0 and r.out == "", (args, r.err)
        assert (tmp_path / "abc"[k]).with_suffix(".csv").read_text() == want
