"""tools/emu/emulog.py - run build/motionemu and read its event log.

The log has one event per line, "<tag> <cycle> <fields>" (cycles of the 16 MHz CPU since
power-on). `run()` runs the harness and returns an `EmuLog`; `EmuLog.parse()` reads a saved log.
"""
import os
import re
import subprocess
import tempfile
import threading

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MOTIONEMU = os.environ.get("MOTIONEMU") or os.path.join(ROOT, "build", "motionemu")
F_CPU = 16_000_000


def unescape(text):
    """The log's escaping back to bytes: \\\\ -> \\, \\xNN -> byte."""
    out = bytearray()
    i = 0
    while i < len(text):
        c = text[i]
        if c == "\\" and i + 1 < len(text):
            if text[i + 1] == "\\":
                out.append(0x5C)
                i += 2
                continue
            if text[i + 1] == "x" and re.fullmatch(r"[0-9a-f]{2}", text[i + 2:i + 4]):
                out.append(int(text[i + 2:i + 4], 16))
                i += 4
                continue
        out.extend(c.encode("latin-1", "replace"))
        i += 1
    return bytes(out)


class Line:
    __slots__ = ("cycle", "text")

    def __init__(self, cycle, text):
        self.cycle = cycle
        self.text = text

    @property
    def t_s(self):
        return self.cycle / F_CPU

    def __repr__(self):
        return f"Line({self.cycle}, {self.text!r})"


class EmuLog:
    def __init__(self):
        self.rx = []          # Line: lines from the firmware
        self.tx = []          # Line: what the script sent (text as written)
        self.pins = {}        # name -> [(cycle, level)]
        self.ddr = {}         # name -> [(cycle, 1 output / 0 input)]: the pin's DDRx bit
        self.matches = {}     # "OC1A".. -> [cycle]: Timer1's compare matches (run(..., extra=["--matches"]))
        self.motor = []       # (cycle, duty_pct, counts)
        self.marks = []       # Line
        self.fails = []       # (cycle, kind, text)
        self.warns = []       # Line
        self.simavr = []      # Line: simavr's own warnings/errors
        self.end = {}         # key -> value from the end line, plus 'reason'
        self.events = []      # (cycle, tag, rest) in order, for sectioning
        self.raw = ""
        self.rc = None
        self.stderr = ""

    @classmethod
    def parse(cls, text):
        log = cls()
        log.raw = text
        for row in text.splitlines():
            parts = row.split(" ", 2)
            if len(parts) < 2 or not parts[1].isdigit():
                continue
            tag, cycle = parts[0], int(parts[1])
            rest = parts[2] if len(parts) > 2 else ""
            log.events.append((cycle, tag, rest))
            if tag == "rx":
                log.rx.append(Line(cycle, unescape(rest).decode("latin-1")))
            elif tag in ("tx", "txraw"):
                log.tx.append(Line(cycle, unescape(rest).decode("latin-1")))
            elif tag == "pin":
                name, level = rest.split()
                log.pins.setdefault(name, []).append((cycle, int(level)))
            elif tag == "match":
                log.matches.setdefault(rest.strip(), []).append(cycle)
            elif tag == "ddr":
                name, out = rest.split()
                log.ddr.setdefault(name, []).append((cycle, int(out)))
            elif tag == "motor":
                duty, counts = rest.split()
                log.motor.append((cycle, float(duty), int(counts)))
            elif tag == "mark":
                log.marks.append(Line(cycle, rest))
            elif tag == "fail":
                kind, _, msg = rest.partition(" ")
                log.fails.append((cycle, kind, msg))
            elif tag == "warn":
                log.warns.append(Line(cycle, rest))
            elif tag == "simavr":
                log.simavr.append(Line(cycle, rest))
            elif tag == "end":
                words = rest.split()
                log.end["reason"] = words[0] if words else ""
                log.end["cycle"] = cycle
                for w in words[1:]:
                    k, _, v = w.partition("=")
                    log.end[k] = v
        return log

    # ---- queries ----
    def rising(self, pin):
        return [c for c, lv in self.pins.get(pin, []) if lv == 1]

    def level_before(self, pin, cycle, default=0):
        """Level of a pin just before `cycle` (the last edge strictly earlier)."""
        level = default
        for c, lv in self.pins.get(pin, []):
            if c >= cycle:
                break
            level = lv
        return level

    def output_before(self, pin, cycle):
        """1 if the pin was an output (DDRx bit set) just before `cycle`; 0 (input: the reset state)
        if the firmware never made it one."""
        out = 0
        for c, o in self.ddr.get(pin, []):
            if c >= cycle:
                break
            out = o
        return out

    def changes_between(self, pin, a, b):
        """cycles in [a, b] at which the pin's level or direction changed"""
        return sorted(c for c, _ in self.pins.get(pin, []) + self.ddr.get(pin, []) if a <= c <= b)

    def lines_matching(self, pattern, after=0, before=None):
        rx = re.compile(pattern)
        return [l for l in self.rx if l.cycle >= after and (before is None or l.cycle < before) and rx.search(l.text)]

    def first(self, pattern, after=0, before=None):
        m = self.lines_matching(pattern, after, before)
        return m[0] if m else None

    def mark(self, text):
        for m in self.marks:
            if m.text == text:
                return m.cycle
        return None

    def section(self, start_mark, end_mark=None):
        """(first cycle, last cycle) between two marks (end: next mark or the end)."""
        a = self.mark(start_mark)
        if a is None:
            return None
        b = self.mark(end_mark) if end_mark else None
        if b is None:
            later = [m.cycle for m in self.marks if m.cycle > a]
            b = min(later) if later else None
        return a, b

    def end_cycle(self):
        return self.end.get("cycle", self.events[-1][0] if self.events else 0)

    def failure_text(self):
        return "; ".join(f"{k} at {c / F_CPU:.4f} s: {t}" for c, k, t in self.fails)


def run(elf, script_text=None, pins=None, motor=None, ls7366r=None, duration_ms=None, max_ms=None,
        log_path=None, extra=None, timeout=600, input_path=None, echo=None):
    """Runs motionemu on `elf` with an INPUT script given as text (or as a file: input_path, which
    the harness's messages then name); returns the parsed EmuLog. A run over `timeout` seconds of
    wall time raises RuntimeError naming the script (timeout None: no limit).
    echo: a function called with each line motionemu prints on stdout while it runs (with
    extra=["--echo"]: the conversation, "[  0.512 s] > 50"; with "--pty": first "pty <path>")."""
    args = [MOTIONEMU, elf]
    tmp = None
    if input_path is not None:
        args += ["--input", input_path]
    elif script_text is not None:
        tmp = tempfile.NamedTemporaryFile("w", suffix=".emu", delete=False)
        tmp.write(script_text)
        tmp.close()
        args += ["--input", tmp.name]
    for name, pin in (pins or {}).items():
        args += ["--pin", f"{name}={pin}"]
    if motor:
        args += ["--motor", motor]
    if ls7366r:
        args += ["--ls7366r", ls7366r]
    if duration_ms is not None:
        args += ["--duration", str(duration_ms)]
    if max_ms is not None:
        args += ["--max-ms", str(max_ms)]
    args += list(extra or [])
    out_path = log_path or tempfile.mktemp(suffix=".log")
    args += ["-o", out_path]
    try:
        try:
            if echo is None:
                p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
            else:
                p = run_echoing(args, echo, timeout)
        except subprocess.TimeoutExpired:
            raise RuntimeError(f"motionemu ran over {timeout} s of wall time on {elf} with "
                               f"{input_path or 'its script'}") from None
        text = open(out_path, encoding="latin-1").read() if os.path.exists(out_path) else ""
        log = EmuLog.parse(text)
        log.rc = p.returncode
        log.stderr = p.stderr
        return log
    finally:
        if tmp:
            os.unlink(tmp.name)
        if not log_path and os.path.exists(out_path):
            os.unlink(out_path)


def run_echoing(args, echo, timeout):
    """subprocess.run with each stdout line handed to echo(line) as it comes (stderr collected aside)"""
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, bufsize=1,
                            errors="replace")
    err = []
    drain = threading.Thread(target=lambda: err.append(proc.stderr.read()), daemon=True)
    drain.start()
    timer, fired = None, []
    if timeout is not None:
        timer = threading.Timer(timeout, lambda: (fired.append(1), proc.kill()))
        timer.start()
    try:
        for line in proc.stdout:
            echo(line.rstrip("\n"))
        rc = proc.wait()
    finally:
        if timer:
            timer.cancel()
    drain.join()
    if fired:
        raise subprocess.TimeoutExpired(args, timeout)
    return subprocess.CompletedProcess(args, rc, "", "".join(err))


def query_fields(line_text):
    """'pos=3 state=idle v0=1' -> {'pos': '3', ...} (the sketches' `?` reply)."""
    fields = {}
    for word in line_text.split():
        k, sep, v = word.partition("=")
        if sep:
            fields[k] = v
    return fields
