"""motionsim's top level: help, unknown commands and options, malformed numbers (issue: foundation)."""

COMMANDS = ["ramp", "filter", "servo", "pid-replay"]


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
