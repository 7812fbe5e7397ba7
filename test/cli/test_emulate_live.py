"""`make emulate SKETCH=X LIVE=1` (tools/emu/emulate.py --live, motionemu --pty): the emulated Mega as
an interactive board on a pseudo-terminal.

A client talks to the printed path exactly as to a Mega's /dev/ttyACM0: pyserial opens it (at any baud
setting: here 115200, while the sketch runs its own 9600), reads the sketch's READY banner (the board
starts when the port is opened, as a Mega resets then), sends the lab's move `50`, gets `OK 0 50` and
`DONE 50` (the sketches' documented protocol, docs/serial.md); closing the port ends the run, and the
outputs are those of a scripted run: the log holds exactly 50 STEP rising edges (|50 - 0| steps), the
CSV 50 rows, and the PNG. Ctrl-C (SIGINT to the process group, as a terminal sends it) ends a run too,
with its outputs written. The terminal side is raw: a plain open() sees no echo and no line editing,
and bytes written without any termios set-up reach the sketch unchanged.

No timing is asserted: the waits below only keep a broken run from hanging the test suite.
"""
import os
import queue
import re
import select
import signal
import subprocess
import sys
import termios
import threading

import pytest
import serial

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "emu"))
import emulog  # noqa: E402

PY = sys.executable
EMULATE = os.path.join(ROOT, "tools", "emu", "emulate.py")
GUARD_S = 120   # a hang guard, not a timing requirement


@pytest.fixture(scope="module")
def built():
    for path in (os.path.join(ROOT, "build", "motionemu"), os.path.join(ROOT, "build", "motionsim"),
                 os.path.join(ROOT, "build", "firmware", "LeibRampStepper", "LeibRampStepper.ino.elf")):
        if not os.path.exists(path):
            pytest.fail(f"{path} is not built (make test builds it)")


class Live:
    """emulate.py --live in its own process group (so that a SIGINT reaches it as from a terminal),
    its stdout read line by line in a thread"""

    def __init__(self, out, sketch="LeibRampStepper"):
        self.p = subprocess.Popen([PY, EMULATE, "--sketch", sketch, "--live", "--out", str(out)], cwd=ROOT,
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                  start_new_session=True)
        self.lines = queue.Queue()
        self.seen = []
        threading.Thread(target=self._read, daemon=True).start()
        self.path = self.wait_for(r"serial port: (/\S+)").group(1)

    def _read(self):
        for line in self.p.stdout:
            self.lines.put(line.rstrip("\n"))
        self.lines.put(None)

    def wait_for(self, pattern):
        while True:
            try:
                line = self.lines.get(timeout=GUARD_S)
            except queue.Empty:
                raise AssertionError(f"no line matching {pattern!r}; so far:\n" + "\n".join(self.seen)) from None
            if line is None:
                raise AssertionError(f"emulate.py ended before {pattern!r}:\n" + "\n".join(self.seen))
            self.seen.append(line)
            m = re.search(pattern, line)
            if m:
                return m

    def finish(self):
        try:
            rc = self.p.wait(timeout=GUARD_S)
        except subprocess.TimeoutExpired:
            os.killpg(self.p.pid, signal.SIGKILL)
            raise AssertionError("the live run did not end:\n" + "\n".join(self.seen)) from None
        while True:
            line = self.lines.get(timeout=GUARD_S)
            if line is None:
                break
            self.seen.append(line)
        return rc


def read_until(port, pattern):
    got = []
    while True:
        raw = port.readline()
        assert raw, f"no line matching {pattern!r} from the board; got {got}"
        line = raw.decode("latin-1").rstrip("\r\n")
        got.append(line)
        if re.search(pattern, line):
            return line


def test_pyserial_talks_to_the_emulated_board_as_to_a_mega(built, tmp_path):
    live = Live(tmp_path)
    port = serial.Serial(live.path, 115200, timeout=GUARD_S)   # any baud setting: the sketch keeps its 9600
    assert read_until(port, r"^READY ") == "READY LeibRampStepper"
    port.write(b"50\r\n")
    assert read_until(port, r"^(OK|ERR)") == "OK 0 50"
    assert read_until(port, r"^(DONE|ERR)") == "DONE 50"
    port.close()                                                # the monitor closes: the run ends
    assert live.finish() == 0, "\n".join(live.seen)
    log = emulog.EmuLog.parse(open(tmp_path / "LeibRampStepper.log", encoding="latin-1").read())
    assert log.end["reason"] == "closed"
    assert len(log.rising("STEP")) == 50
    rows = open(tmp_path / "LeibRampStepper.csv").read().splitlines()
    assert len(rows) == 1 + 50 and rows[-1].split(",")[1] == "50"
    assert (tmp_path / "LeibRampStepper.png").stat().st_size > 1000
    # the conversation was shown as it happened, with emulated time
    assert any(re.fullmatch(r"\s*\[\s*\d+\.\d{3} s\] > 50", l) for l in live.seen), live.seen
    assert any(re.fullmatch(r"\s*\[\s*\d+\.\d{3} s\] < DONE 50", l) for l in live.seen), live.seen


def test_the_port_is_raw_and_ctrl_c_ends_the_run_with_its_outputs(built, tmp_path):
    live = Live(tmp_path)
    fd = os.open(live.path, os.O_RDWR | os.O_NOCTTY)            # no termios set-up at all, as `cat` would
    try:
        attrs = termios.tcgetattr(fd)
        lflag, iflag, oflag = attrs[3], attrs[0], attrs[1]
        assert not lflag & (termios.ICANON | termios.ECHO | termios.ISIG)
        assert not iflag & (termios.ICRNL | termios.IXON) and not oflag & termios.OPOST
        buf = b""

        def until(text):
            nonlocal buf
            while text not in buf:
                r, _, _ = select.select([fd], [], [], GUARD_S)
                assert r, buf
                buf += os.read(fd, 256)
        until(b"READY LeibRampStepper\r\n")   # bytes sent before it are lost, as on a Mega starting up
        os.write(fd, b"-7\r")                  # a CR alone ends a line (docs/serial.md)
        until(b"DONE -7\r\n")
        assert b"OK 0 -7\r\n" in buf
        os.killpg(live.p.pid, signal.SIGINT)                    # Ctrl-C in the terminal
        assert live.finish() == 0, "\n".join(live.seen)
    finally:
        os.close(fd)
    log = emulog.EmuLog.parse(open(tmp_path / "LeibRampStepper.log", encoding="latin-1").read())
    assert log.end["reason"] == "interrupted"
    assert len(log.rising("STEP")) == 7
    rows = open(tmp_path / "LeibRampStepper.csv").read().splitlines()
    assert [r.split(",")[1] for r in rows[1:]] == [str(-k) for k in range(1, 8)]
    assert (tmp_path / "LeibRampStepper.png").stat().st_size > 1000


def test_live_and_a_script_do_not_go_together(built, tmp_path):
    script = tmp_path / "x.emu"
    script.write_text("send 5\n")
    p = subprocess.run([PY, EMULATE, "--sketch", "LeibRampStepper", "--live", "--input", str(script),
                        "--out", str(tmp_path)], cwd=ROOT, capture_output=True, text=True, timeout=GUARD_S)
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert "LIVE=1 and INPUT=" in p.stderr
