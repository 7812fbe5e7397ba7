"""motionemu's command line (tools/emu/motionemu.c, getopt_long(3), issue 12): every refusal is exit
status 2 with a message naming the problem, before any ELF is read; the choices getopt_long leaves
open are fixed as in motionsim (whole option names only, a non-repeatable option once, "--" ends
the options)."""
import os
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EMU = os.path.join(ROOT, "build", "motionemu")


@pytest.fixture(scope="module")
def emu():
    if not os.path.exists(EMU):
        subprocess.run(["make", "build/motionemu"], cwd=ROOT, check=True, capture_output=True)

    def run(*args):
        return subprocess.run([EMU, *map(str, args)], capture_output=True, text=True, timeout=60)
    return run


BAD = [
    (["x.elf", "--dur", "5"], "motionemu: option '--dur' is abbreviated: write --duration (abbreviations are not accepted)"),
    (["x.elf", "--inp=a"], "motionemu: option '--inp' is abbreviated: write --input (abbreviations are not accepted)"),
    (["x.elf", "--frobnicate"], "motionemu: unknown option '--frobnicate'"),
    (["x.elf", "-x"], "motionemu: unknown option '-x'"),
    (["x.elf", "--duration"], "motionemu: option --duration needs a value"),
    (["x.elf", "-d"], "motionemu: option -d needs a value"),
    (["x.elf", "--help=1"], "motionemu: option --help takes no value"),
    (["x.elf", "-i", "a", "--input", "b"], "motionemu: --input given twice"),
    (["x.elf", "-o", "a", "-o", "b"], "motionemu: --output given twice"),
    (["x.elf", "--motor", "A", "--motor", "B"], "motionemu: --motor given twice"),
    (["x.elf", "--ls7366r", "CS=D53", "--ls7366r", "CS=D52"], "motionemu: --ls7366r given twice"),
    (["x.elf", "-d", "5", "--duration", "6"], "motionemu: --duration given twice"),
    (["x.elf", "--max-ms", "5", "--max-ms", "6"], "motionemu: --max-ms given twice"),
    # a negative value is the option's value, refused by the range check
    (["x.elf", "--duration", "-5"], "motionemu: --duration wants milliseconds, not '-5'"),
    (["x.elf", "--max-ms=-1"], "motionemu: --max-ms wants milliseconds, not '-1'"),
    # numbers are lib's text_parse (as motionsim's and the sketches'): no hexadecimal, inf or blanks
    (["x.elf", "--duration", "0x10"], "motionemu: --duration wants milliseconds, not '0x10'"),
    (["x.elf", "--duration", "inf"], "motionemu: --duration wants milliseconds, not 'inf'"),
    (["x.elf", "--duration", " 5"], "motionemu: --duration wants milliseconds, not ' 5'"),
    # --trace-pc: FROM-TO in milliseconds, TO after FROM, at most 50 ms apart
    (["x.elf", "--trace-pc", "1"], "motionemu: --trace-pc wants FROM-TO in milliseconds, TO after FROM and at most "
                                   "50 ms later (e.g. 2586.5-2586.7), not '1'"),
    (["x.elf", "--trace-pc", "2-1"], "motionemu: --trace-pc wants FROM-TO in milliseconds, TO after FROM and at "
                                     "most 50 ms later (e.g. 2586.5-2586.7), not '2-1'"),
    (["x.elf", "--trace-pc=1-60"], "motionemu: --trace-pc wants FROM-TO in milliseconds, TO after FROM and at "
                                   "most 50 ms later (e.g. 2586.5-2586.7), not '1-60'"),
    (["x.elf", "--trace-pc", "1-2", "--trace-pc", "1-3"], "motionemu: --trace-pc given twice"),
    (["x.elf", "y.elf"], "motionemu: one firmware file only ('x.elf' and 'y.elf')"),
    (["x.elf", "--", "y.elf"], "motionemu: one firmware file only ('x.elf' and 'y.elf')"),
    ([], "motionemu: no firmware file given"),
]


@pytest.mark.parametrize("args,first_line", BAD, ids=[" ".join(a) or "(none)" for a, _ in BAD])
def test_bad_arguments_exit_2_naming_the_problem(emu, args, first_line):
    r = emu(*args)
    assert r.returncode == 2 and r.stdout == "", (args, r.stdout)
    assert r.stderr.splitlines()[0] == first_line, (args, r.stderr)


def test_repeatable_options_and_double_dash(emu, tmp_path):
    # --pin and --exec may be given many times: the run gets as far as the (missing) ELF
    r = emu("-p", "A=D1", "--pin", "B=D2", "-e", "wait 1", "--exec", "wait 2", "--", str(tmp_path / "none.elf"))
    assert r.returncode == 2 and r.stderr.startswith("motionemu: cannot open '"), r.stderr


def test_help(emu):
    r = emu("--help")
    assert r.returncode == 0 and r.stderr == ""
    assert r.stdout.startswith("usage: motionemu FIRMWARE.elf [options]\n")
    for option in ("--input", "--exec", "--output", "--pin", "--motor", "--ls7366r", "--duration", "--max-ms"):
        assert option in r.stdout
    assert emu("-h").stdout == r.stdout


def test_script_numbers_are_text_parse_numbers(emu):
    """An INPUT script's numbers go through lib's text_parse too: hexadecimal is refused naming the line."""
    elf = os.path.join(ROOT, "build", "emu", "emu_selftest.elf")
    if not os.path.exists(elf):
        subprocess.run(["make", "build/emu/emu_selftest.elf"], cwd=ROOT, check=True, capture_output=True)
    for cmd, what in (("run 0x10", "run time (ms) must be a number in 0..1e+09"),
                      ("timeout inf", "timeout (ms) must be a number in 1..1e+09")):
        r = emu(elf, "-e", cmd)
        word = cmd.split()[1]
        assert r.returncode == 2 and r.stdout == "", r.stderr
        assert r.stderr.splitlines() == [f"--exec:1: {what}, not '{word}'"], r.stderr
    r = emu(elf, "-e", "run 1e1")
    assert r.returncode == 0, r.stderr


def test_trace_pc_logs_each_instruction_in_the_span(emu):
    """--trace-pc 1-1.01: the self-test program's instructions from cycle 16,000 to 16,160, one line
    each, the cycle rising by 1 to 4 (an AVR instruction takes 1-4 cycles; 5 with an interrupt's
    entry), each address even and inside the program's flash"""
    root_make = subprocess.run(["make", "-s", "build/emu/emu_selftest.elf"], cwd=ROOT, capture_output=True, text=True)
    assert root_make.returncode == 0, root_make.stderr
    r = emu(os.path.join(ROOT, "build", "emu", "emu_selftest.elf"), "-d", "2", "--trace-pc", "1-1.01")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    flash = int(next(l for l in lines if l.startswith("boot ")).split("flash=")[1].split()[0])
    pcs = [l.split() for l in lines if l.startswith("pc ")]
    assert 32 <= len(pcs) <= 160, len(pcs)
    cycles = [int(p[1]) for p in pcs]
    assert 16000 <= cycles[0] <= 16004 and 16156 <= cycles[-1] <= 16160, (cycles[0], cycles[-1])
    assert all(1 <= b - a <= 5 for a, b in zip(cycles, cycles[1:]))
    for p in pcs:
        addr = int(p[2], 16)
        assert addr % 2 == 0 and addr < flash and p[3] in ("I=0", "I=1"), p
    # nothing outside the span
    assert not any(l.startswith("pc ") for l in emu(os.path.join(ROOT, "build", "emu", "emu_selftest.elf"),
                                                     "-d", "2").stdout.splitlines())
