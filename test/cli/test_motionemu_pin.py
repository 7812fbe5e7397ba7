"""motionemu's script command `pin <pin> <0|1>` (tools/emu/emu_script.c, emu_pins.c emu_pin_input):
the outside world drives a digital input, as a switch or an endstop does.

The firmware that reads it back is the harness's self-test program (test/emu/selftest/emu_selftest.c,
plain avr-libc): its `pins` command replies `OK pins d2=<PINE4> d18=<PIND3> int4=<n>`, D2 = PE4 an
input with its pull-up on, D18 = PD3 an input without, n the falling edges of D2 counted by the INT4
interrupt (falling edge only). The expectations are the ATmega2560's (datasheet, I/O ports and
external interrupts):
  - nothing driven: the pull-up reads 1; the pin without one reads the harness's reset level 0;
  - driven: PINx reads the level given, also against the pull-up (a switch to GND beats it), also
    when the level was set before the program turned its pull-up on;
  - every falling edge given, and only those, is one INT4 interrupt;
  - the edge is at the cycle the script reached the command (`run 1` apart: 16,000 cycles, up to
    one instruction later);
  - a bad pin or level is refused (exit 2) with one line naming the script line.
"""
import os
import re
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EMU = os.path.join(ROOT, "build", "motionemu")
SELFTEST = os.path.join(ROOT, "build", "emu", "emu_selftest.elf")
MAX_INSN = 5  # cycles of the longest AVR instruction: the script runs between instructions


@pytest.fixture(scope="module")
def built():
    p = subprocess.run(["make", "-s", "build/motionemu", "build/emu/emu_selftest.elf"], cwd=ROOT,
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr


def run(script, *args):
    """the self-test program under the script, D2 watched as SW; the event log on stdout"""
    path = os.path.join(ROOT, "build", "emu", f"pin_test_{os.getpid()}.emu")
    with open(path, "w") as f:
        f.write(script)
    try:
        p = subprocess.run([EMU, SELFTEST, "--input", path, "-p", "SW=D2", *args], capture_output=True, text=True,
                           timeout=60)
    finally:
        os.remove(path)
    return p


def replies(log):
    return re.findall(r"^rx \d+ (OK pins .*)$", log, re.M)


def events(log, tag):
    return [(int(m.group(1)), m.group(2)) for m in re.finditer(r"^" + tag + r" (\d+) (.*)$", log, re.M)]


def test_a_driven_input_reads_the_level_given_and_its_falls_interrupt(built):
    p = run("wait ^READY\nsend pins\nwait ^OK pins\n"
            "pin D2 0\npin PD3 1\nsend pins\nwait ^OK pins\n"      # both driven: the pull-up loses
            "pin E4 1\nsend pins\nwait ^OK pins\n"                 # a rise: no interrupt
            "pin D2 0\nrun 1\npin D2 1\nrun 1\npin D2 0\nsend pins\nwait ^OK pins\n")
    assert p.returncode == 0, p.stdout + p.stderr
    assert replies(p.stdout) == ["OK pins d2=1 d18=0 int4=0", "OK pins d2=0 d18=1 int4=1",
                                 "OK pins d2=1 d18=1 int4=1", "OK pins d2=0 d18=1 int4=3"]
    inputs = events(p.stdout, "input")
    assert [t for _, t in inputs] == ["D2 PE4 0", "PD3 PD3 1", "E4 PE4 1", "D2 PE4 0", "D2 PE4 1", "D2 PE4 0"]
    # the watched pin's edges come at the commands' cycles
    edges = [(c, t) for c, t in events(p.stdout, "pin") if t.startswith("SW ")]
    after_boot = [e for e in edges if e[0] >= inputs[0][0]]
    assert after_boot == [(c, "SW " + t[-1]) for c, t in inputs if t.startswith(("D2", "E4"))]
    gaps = [b - a for (a, _), (b, _) in zip(inputs[3:], inputs[4:])]
    assert all(16000 <= g <= 16000 + MAX_INSN for g in gaps), gaps


def test_a_level_set_before_the_pull_up_is_turned_on_holds(built):
    p = run("pin D2 0\nwait ^READY\nsend pins\nwait ^OK pins\npin D2 1\nsend pins\nwait ^OK pins\n")
    assert p.returncode == 0, p.stdout + p.stderr
    assert replies(p.stdout) == ["OK pins d2=0 d18=0 int4=0", "OK pins d2=1 d18=0 int4=0"]
    # D2 never rose before the script let it go: the program's pull-up did not override the switch
    ups = [c for c, t in events(p.stdout, "pin") if t == "SW 1"]
    assert len(ups) == 1 and ups[0] == events(p.stdout, "input")[1][0]


def test_an_output_pin_keeps_its_port_level(built):
    # D3 = PE5 is the program's OC3C output (driven low by PORTE5): the command is logged as met by an
    # output and the pin's level stays the firmware's
    p = run("wait ^READY\npin D3 1\nrun 1\n", "-p", "OC3C=D3")
    assert p.returncode == 0, p.stdout + p.stderr
    assert [t for _, t in events(p.stdout, "input")] == ["D3 PE5 1 output"]
    assert not [t for _, t in events(p.stdout, "pin") if t.startswith("OC3C ")]


@pytest.mark.parametrize("line", ["pin D99 0", "pin D2 2", "pin D2", "pin", "pin D2 0 1", "pin PZ1 1", "pin D2 01",
                                  "pin A16 0"])
def test_a_bad_pin_or_level_is_refused(built, line):
    p = subprocess.run([EMU, SELFTEST, "-e", line], capture_output=True, text=True, timeout=60)
    assert p.returncode == 2, p.stdout + p.stderr
    err = p.stderr.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("--exec:1: pin wants a pin (D3, A0, PE5 or E5) and a level 0 or 1"), err
