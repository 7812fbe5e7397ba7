"""Harness self-tests: the emulator must be right before it may judge the sketches.

They run build/emu/emu_selftest.elf (test/emu/selftest/emu_selftest.c, plain avr-libc) whose
timing follows from the ATmega2560 datasheet, so every expected number below is computed here
from first principles, never recorded from the harness:
  - 10 PF1 toggles exactly 1000 cycles apart (sbi = 2 cycles + __builtin_avr_delay_cycles(998));
  - Timer1 CTC clk/8, OCR1A = 1999: OC1A toggles every 8 * 2000 = 16000 cycles;
  - UART0 9600 baud 8N1 with U2X0, UBRR0 = 207: a byte is 10 bits * 8 * 208 = 16640 cycles;
  - SPI clk/16: a byte is 8 * 16 = 128 cycles;
  - ADC: code = floor(V * 1024 / 5 V);
  - Timer3 phase-correct 8-bit PWM clk/64: period 510 * 64 = 32640 cycles, high 2 * OCR * 64.
And a broken firmware must be reported: reset, watchdog, halt, a store outside the data space, a
call into erased flash, a stack overflow, a reply that never comes, an ELF that is not for the
ATmega2560.
"""
import os
import subprocess

import emulog
from emulog import F_CPU

ROOT = emulog.ROOT
SELFTEST = os.path.join(ROOT, "build", "emu", "emu_selftest.elf")
WRONG_MCU = os.path.join(ROOT, "build", "emu", "wrong_mcu.elf")

UART_BYTE = 10 * 8 * 208   # cycles per 8N1 byte at UBRR0 = 207, U2X0 = 1
SPI_BYTE = 8 * 16          # cycles per SPI byte at fosc/16
PWM_PERIOD = 510 * 64      # phase-correct 8-bit, clk/64
MAX_INSN = 5               # longest AVR instruction (cycles): edges land on instruction boundaries


class CheckResult:
    def __init__(self, ok, summary, details=()):
        self.ok = ok
        self.summary = summary
        self.details = list(details)


def _fails(log, problems):
    for c, k, t in log.fails:
        problems.append(f"harness reported {k} at {c / F_CPU:.4f} s: {t}")


def check_pins_and_timers():
    log = emulog.run(SELFTEST, "wait ^READY\nrun 20\n", pins={"BURST": "D55", "OC1A": "D11", "ISR": "D54"})
    problems = []
    _fails(log, problems)
    burst = [c for c, _ in log.pins.get("BURST", [])]
    if len(burst) != 10:
        problems.append(f"PF1 toggled {len(burst)} times, the program toggles it 10 times")
    gaps = [b - a for a, b in zip(burst, burst[1:])]
    if any(g != 1000 for g in gaps):
        problems.append(f"PF1 toggles should be exactly 1000 cycles apart, got {sorted(set(gaps))}")
    oc = [c for c, _ in log.pins.get("OC1A", [])]
    oc_gaps = [b - a for a, b in zip(oc, oc[1:])]
    worst = max((abs(g - 16000) for g in oc_gaps), default=None)
    if len(oc) < 10:
        problems.append(f"OC1A toggled only {len(oc)} times in 20 ms (expected one per 1 ms)")
    elif worst > MAX_INSN:
        problems.append(f"OC1A toggle intervals off 16000 cycles by up to {worst} (bound {MAX_INSN})")
    elif abs((oc[-1] - oc[0]) - 16000 * (len(oc) - 1)) > MAX_INSN:
        problems.append(f"OC1A drifts: {oc[-1] - oc[0]} cycles for {len(oc) - 1} intervals of 16000")
    isr = [c for c, _ in log.pins.get("ISR", [])]
    lat = [i - o for o, i in zip(oc, isr)]
    summary = (f"PF1 burst {len(gaps)} gaps of exactly {gaps[0] if gaps else '?'} cycles; OC1A {len(oc_gaps)} "
               f"intervals 16000 +/- {worst} cycles; compare ISR latency {min(lat, default=0)}-{max(lat, default=0)} "
               f"cycles")
    return CheckResult(not problems, summary, problems)


def check_pin_direction():
    """'dir': PF2 (D56) changes every 1000 cycles with interrupts off: output low, input, pull-up on,
    output high, output low. The log must show each direction change (ddr) and each level change
    (pin) at its cycle, and nothing for the changes that leave the level alone."""
    log = emulog.run(SELFTEST, "wait ^READY\nsend dir\nwait ^OK dir$\n", pins={"P": "D56"})
    problems = []
    _fails(log, problems)
    events = sorted([(c, "ddr", v) for c, v in log.ddr.get("P", [])] + [(c, "pin", v) for c, v in log.pins.get("P", [])])
    want = [(0, "ddr", 1), (1000, "ddr", 0), (2000, "pin", 1), (3000, "ddr", 1), (4000, "pin", 0)]
    got = [(c - events[0][0], kind, v) for c, kind, v in events] if events else []
    if got != want:
        problems.append(f"PF2 events (cycle from the first, kind, value) {got}, the program makes {want}")
    ok = log.first(r"^OK dir$")
    if ok and (log.output_before("P", ok.cycle) != 1 or log.level_before("P", ok.cycle) != 0):
        problems.append("at the end PF2 should be an output driven low")
    before = log.output_before("P", events[0][0]) if events else None
    if before != 0:
        problems.append(f"PF2 should be an input before the first change (reset state), got {before}")
    summary = "PF2 output-low, input, pull-up, output-high, output-low logged as " + (
        ", ".join(f"{k} {v} @+{c}" for c, k, v in got) if got else "nothing")
    return CheckResult(not problems, summary, problems)


def check_serial():
    script = ("wait ^READY EmuSelfTest$\nmark ping\nsend ping\nwait ^OK pong$\nmark burst\nsend burst\n"
              "wait ^0123456789$\nwait ^0123456789$\nsend nonsense\nwait ^ERR unknown$\nsend ?\nwait ^n=\n")
    log = emulog.run(SELFTEST, script)
    problems = []
    _fails(log, problems)
    ready = log.first(r"^READY EmuSelfTest$")
    if not ready:
        problems.append("no READY EmuSelfTest line")
    burst = log.lines_matching(r"^0123456789$")
    gap = burst[1].cycle - burst[0].cycle if len(burst) == 2 else None
    # 12 bytes ("0123456789\r\n") between the two LF writes, each one frame. simavr has no
    # transmit double buffer: each byte also waits for the polling loop to see UDRE0 (a few
    # cycles), so allow up to 16 cycles per byte on top of the frame.
    if gap is None:
        problems.append("burst lines missing")
    elif not (12 * UART_BYTE <= gap <= 12 * (UART_BYTE + 16)):
        problems.append(f"12 bytes took {gap} cycles, expected 12 * {UART_BYTE} = {12 * UART_BYTE} "
                        f"(+ <= 16 per byte; simavr's own 11-bit frames would give {12 * 11 * 8 * 208})")
    ping_tx = [t for t in log.tx if t.text == "ping"]
    pong = log.first(r"^OK pong$")
    rtt = None
    if ping_tx and pong:
        rtt = pong.cycle - ping_tx[0].cycle
        # "ping\r\n" = 6 bytes arriving one frame apart from one frame after queueing, then
        # "OK pong\r\n" = 9 bytes sent: the LF is written after 8 frames of the reply
        expected = 6 * UART_BYTE + 8 * UART_BYTE
        if not (expected - 100 <= rtt <= expected + 2000):
            problems.append(f"ping -> pong took {rtt} cycles, expected about {expected}")
    else:
        problems.append("no reply to ping")
    if not log.first(r"^n=4$"):  # ping, burst, nonsense and ? itself
        problems.append(f"'?' should report n=4 (its own line is the 4th), got "
                        f"{[l.text for l in log.lines_matching('^n=')]}")
    summary = (f"9600 baud byte = {gap / 12 if gap else 0:.1f} cycles incl. UDRE polling (datasheet frame "
               f"{UART_BYTE}); ping round trip {rtt} cycles")
    return CheckResult(not problems, summary, problems)


def check_ls7366r_spi():
    script = ("wait ^READY\nencoder 12345\nsend enc\nwait ^OK enc\nencoder -5\nsend enc\nwait ^OK enc\n"
              "send enc2\nwait ^OK enc2\nsend mdr\nwait ^OK mdr\nsend spi\nwait ^OK spi\n")
    log = emulog.run(SELFTEST, script, ls7366r="CS=D53")
    problems = []
    _fails(log, problems)
    got = [l.text for l in log.lines_matching(r"^OK ")]
    want = ["OK enc 12345", "OK enc -5", "OK enc2 65531 otr -5", "OK mdr0=3 mdr1=0"]
    # -5 in the 2-byte mode is 0x10000 - 5 = 65531; LOAD OTR copies CNTR (-5) to OTR
    for w in want:
        if w not in got:
            problems.append(f"expected reply '{w}', got {got}")
    spi = log.first(r"^OK spi ")
    cycles = int(spi.text.split()[2]) if spi else None
    # measured by the firmware with Timer4 at clk/1 around SPDR write .. SPIF poll
    if cycles is None or not (SPI_BYTE <= cycles <= SPI_BYTE + 16):
        problems.append(f"an SPI byte at fosc/16 took {cycles} cycles by Timer4, expected {SPI_BYTE}..{SPI_BYTE + 16}")
    summary = f"counter reads 12345, -5, 2-byte 65531; SPI byte {cycles} cycles incl. polling (datasheet {SPI_BYTE})"
    return CheckResult(not problems, summary, problems)


def check_adc_pwm():
    script = ("wait ^READY\nadc 0 2.5\nsend adc\nwait ^OK adc\nadc 0 1.2345\nsend adc\nwait ^OK adc\n"
              "adc 0 5\nsend adc\nwait ^OK adc\nsend pwm 64\nwait ^OK pwm\nrun 20\nmark p200\nsend pwm 200\n"
              "wait ^OK pwm\nrun 20\nmark p255\nsend pwm 255\nwait ^OK pwm\nrun 20\n")
    log = emulog.run(SELFTEST, script, pins={"PWM": "D3"})
    problems = []
    _fails(log, problems)
    codes = [int(l.text.split()[2]) for l in log.lines_matching(r"^OK adc ")]
    want = [int(2.5 * 1024 / 5), int(1.2345 * 1024 / 5), 1023]
    if codes != want:
        problems.append(f"ADC codes {codes}, datasheet floor(V * 1024 / 5) gives {want}")
    worst = 0.0
    for label, ocr, a, b in (("64", 64, log.mark("p200") - 10 * PWM_PERIOD, log.mark("p200")),
                             ("200", 200, log.mark("p255") - 10 * PWM_PERIOD, log.mark("p255"))):
        edges = [(c, lv) for c, lv in log.pins.get("PWM", []) if a <= c < b]
        rises = [c for c, lv in edges if lv]
        falls = [c for c, lv in edges if not lv]
        periods = [y - x for x, y in zip(rises, rises[1:])]
        highs = [f - r for r in rises for f in falls if 0 < f - r < PWM_PERIOD][:len(periods)]
        if len(periods) < 5:
            problems.append(f"PWM {label}: only {len(periods)} periods seen")
            continue
        for p in periods:
            if p != PWM_PERIOD:
                problems.append(f"PWM {label}: period {p} cycles, datasheet {PWM_PERIOD}")
                break
        for h in highs:  # emulated timer edges carry their exact compare-match cycle
            err = abs(h - 2 * ocr * 64)
            worst = max(worst, err)
            if err > 0:
                problems.append(f"PWM {label}: high for {h} cycles, datasheet 2 * {ocr} * 64 = {2 * ocr * 64}")
                break
    ok255 = log.first(r"^OK pwm 255$")
    after255 = [c for c, lv in log.pins.get("PWM", []) if ok255 and c > ok255.cycle + 2 * PWM_PERIOD]
    if not ok255 or after255 or log.level_before("PWM", log.end_cycle() + 1) != 1:
        problems.append("PWM 255 should hold the pin high without edges")
    summary = f"ADC codes {codes}; PWM period {PWM_PERIOD} cycles, high time within {worst:.0f} cycles of 2*OCR*64"
    return CheckResult(not problems, summary, problems)


def check_failure_detection():
    problems = []
    seen = []
    # wild: a store to 0x8000, beyond the data space (simavr's crash state); void: a call into
    # erased flash; recurse: recursion without end (SP below __heap_start, reported once); heapdig: 5,000
    # bytes of heap, then a bounded recursion into it, far above __heap_start (the MotionStepper library's
    # step rings are on the heap: a stack reaching them must fail the run too)
    for cmd, kind in (("reset", "reset"), ("wdt", "reset"), ("halt", "halt"), ("wild", "crash"), ("void", "crash"),
                      ("recurse", "stack"), ("heapdig", "stack")):
        log = emulog.run(SELFTEST, f"wait ^READY\nsend {cmd}\nwait ^OK\nrun 100\n")
        kinds = [k for _, k, _ in log.fails]
        seen.append(f"{cmd}->{','.join(kinds) or 'nothing'}")
        if log.rc != 1 or not kinds or kinds[0] != kind:
            problems.append(f"'{cmd}' should be reported first as {kind} with exit status 1: got {kinds}, rc={log.rc}")
        if kind == "stack" and kinds.count("stack") != 1:
            problems.append(f"a stack overflow should be reported once, got {kinds.count('stack')} 'stack' failures")
        if kind == "crash" and log.end.get("reason") != "crash":
            problems.append(f"'{cmd}': the run should end with reason crash, got {log.end.get('reason')}")
    # the heap grown over where the stack once was: no overflow (the emulator once compared only new
    # lowest stack pointers with the heap's end, so this reported a negative stack_min_free); digging
    # into it later, above that lowest point, is one (which that emulator missed)
    log = emulog.run(SELFTEST, "wait ^READY\nsend pastdig\nwait ^OK heap\nrun 100\n")
    kinds = [k for _, k, _ in log.fails]
    free = int(log.end.get("stack_min_free", "-1"))
    seen.append(f"pastdig->{','.join(kinds) or 'nothing'} (stack_min_free {free})")
    if log.rc != 0 or kinds or free < 0:
        problems.append(f"'pastdig' should pass with stack_min_free >= 0: got {kinds}, rc={log.rc}, "
                        f"stack_min_free={free}")
    log = emulog.run(SELFTEST, "wait ^READY\nsend latedig\nwait ^OK heap\nrun 100\n")
    kinds = [k for _, k, _ in log.fails]
    seen.append(f"latedig->{','.join(kinds) or 'nothing'}")
    if log.rc != 1 or kinds.count("stack") != 1 or kinds[0] != "stack":
        problems.append(f"'latedig' should be reported once as stack with exit status 1: got {kinds}, rc={log.rc}")
    log = emulog.run(SELFTEST, "wait ^READY\ntimeout 50\nwait ^never$\n")
    kinds = [k for _, k, _ in log.fails]
    seen.append(f"silent->{','.join(kinds) or 'nothing'}")
    if log.rc != 1 or "timeout" not in kinds:
        problems.append(f"a reply that never comes should fail with 'timeout': got {kinds}, rc={log.rc}")
    log = emulog.run(SELFTEST, "wait ^READY\nsend ping\nwait ^OK pong$\n")
    if log.rc != 0 or log.fails:
        problems.append(f"a healthy run must pass: rc={log.rc}, fails={log.fails}")
    return CheckResult(not problems, "detected: " + " ".join(seen), problems)


def check_elf_validation():
    problems = []
    for path, why in ((os.path.join(ROOT, "test", "emu", "selftest", "emu_selftest.c"), "not an ELF"),
                      (WRONG_MCU, "an ATmega328P (avr5) ELF")):
        p = subprocess.run([emulog.MOTIONEMU, path, "--duration", "1"], capture_output=True, text=True)
        if p.returncode != 2 or not p.stderr.strip():
            problems.append(f"{why} must be refused with exit status 2 and a message: rc={p.returncode}")
    p = subprocess.run([emulog.MOTIONEMU, SELFTEST, "--pin", "X=D99", "--duration", "1"], capture_output=True,
                       text=True)
    if p.returncode != 2:
        problems.append(f"--pin X=D99 (no such pin) must be refused: rc={p.returncode}")
    p = subprocess.run([emulog.MOTIONEMU, SELFTEST, "-e", "frobnicate 3"], capture_output=True, text=True)
    if p.returncode != 2 or "unknown command" not in p.stderr:
        problems.append(f"an unknown script command must be refused: rc={p.returncode} {p.stderr.strip()}")
    for extra in ([], ["--motor", "PWM=D3,DIR=D12,CS=D53"]):
        p = subprocess.run([emulog.MOTIONEMU, SELFTEST, "-e", "encoder 5", *extra], capture_output=True, text=True)
        if p.returncode != 2 or len(p.stderr.strip().splitlines()) != 1 or "--ls7366r" not in p.stderr:
            problems.append(f"'encoder' without --ls7366r ({' '.join(extra) or 'no device'}) must be refused in one "
                            f"line naming --ls7366r: rc={p.returncode} {p.stderr.strip()!r}")
    return CheckResult(not problems, "non-ELF, avr5 ELF, bad pin, bad script command, 'encoder' without --ls7366r "
                       "all refused", problems)


def check_motor_coupling():
    """PWM 128/255 on D3 with DIR low (DIRPOS=0: low = positive): the plant must see exactly
    100 * 128 / 255 = 50.196 %, and the LS7366R must count what the plant turned."""
    script = ("wait ^READY\nsend pwm 128\nwait ^OK pwm\nrun 300\nmark read\nsend enc\nwait ^OK enc\n"
              "send pwm 0\nwait ^OK pwm\nrun 300\n"
              # analogWrite(255) (PORT high, OC3C off), PWM again, then a reversal's analogWrite(0) +
              # analogWrite(64): the pin follows PORT for a few cycles (a glitch) before OC3C is back
              "mark dig1\nsend dig1\nwait ^OK dig1\nrun 20\nsend pwm 200\nwait ^OK pwm 200\nrun 20\n"
              "mark rev\nsend rev 64\nwait ^OK rev 64\nrun 30\n")
    log = emulog.run(SELFTEST, script, motor="PWM=D3,DIR=D12,CS=D53,DIRPOS=0")
    problems = []
    _fails(log, problems)
    want = 100.0 * 128 / 255
    ok = log.first(r"^OK pwm 128$")
    run = [(c, d, n) for c, d, n in log.motor if ok and ok.cycle + 3 * PWM_PERIOD < c < log.mark("read")]
    worst = max((abs(d - want) for _, d, _ in run), default=None)
    if not run or worst > 1e-3:
        problems.append(f"duty seen by the plant off {want:.4f} % by {worst}")
    counts = [n for _, _, n in run]
    if any(b < a for a, b in zip(counts, counts[1:])) or not counts or counts[-1] <= 0:
        problems.append("the motor should turn forward at 50 % duty, counts rising")
    enc = log.first(r"^OK enc ")
    tx = next((t.cycle for t in log.tx if t.text == "enc"), None)
    if enc and tx:
        # the count was read between the command's arrival and the reply
        lo = [n for c, d, n in log.motor if c <= tx]
        hi = [n for c, d, n in log.motor if c >= enc.cycle]
        got = int(enc.text.split()[2])
        if not (lo and hi and lo[-1] <= got <= hi[0]):
            problems.append(f"LS7366R read {got}, plant count was {lo[-1:]}..{hi[:1]} around the read")
    else:
        problems.append("no encoder reply")
    stop = log.first(r"^OK pwm 0$")
    after = [d for c, d, n in log.motor if stop and c > stop.cycle + 3 * PWM_PERIOD and c < log.mark("dig1")]
    if not after or any(d != 0 for d in after):
        problems.append("after pwm 0 the plant must see 0 %")
    # each phase from two PWM periods after its reply: 100 % (pin held high), 200/255, then 64/255
    # exactly (the glitch lies more than a period back)
    # (a phase ends when the next command is sent: it cannot act before it was sent)
    for label, start, nxt, want_pct in (("dig1", r"^OK dig1$", "pwm 200", 100.0),
                                        ("pwm 200", r"^OK pwm 200$", "rev 64", 100.0 * 200 / 255),
                                        ("rev 64", r"^OK rev 64$", None, 100.0 * 64 / 255)):
        a = log.first(start)
        b = next((t.cycle for t in log.tx if t.text == nxt), None) if nxt else None
        ds = [d for c, d, n in log.motor if a and c > a.cycle + 2 * PWM_PERIOD and (b is None or c < b)]
        if not ds or max(abs(d - want_pct) for d in ds) > 1e-3:
            problems.append(f"after {label} the plant should see {want_pct:.3f} %, saw {sorted(set(ds))[:6]}")
    summary = (f"plant saw {run[-1][1] if run else '?'} % for OCR 128 (exact {want:.4f} %); encoder read "
               f"{enc.text.split()[2] if enc else '?'} counts after 0.3 s; 100 %, 200/255 and 64/255 after a "
               f"reversal's PORT glitch")
    return CheckResult(not problems, summary, problems)


def check_timer_wrap():
    """A compare register armed late in a timer period for the first ticks of the next one matches
    there (the ATmega2560's comparators run in hardware; libsimavr 1.6 alone would drop the match of
    k = 0..3 and fire it one wrap, 65,536 cycles, later: tools/emu/emu_timer.c). From first
    principles: the write happens at TCNT5 >= 65000, so the ISR's toggle of PF3 comes at most
    65536 - 65000 + k cycles after the write's toggle, plus the write-to-toggle and ISR entry cycles
    (bounded here by 100)."""
    ks = [k for k in (0, 1, 2, 3, 4, 7, 100) for _ in range(8)]
    phases = [p for _ in (0, 1, 2, 3, 4, 7, 100) for p in range(8)]
    script = "wait ^READY\n" + "".join(f"send wrap {k} {p}\nwait ^OK wrap {k}$\n" for k, p in zip(ks, phases))
    log = emulog.run(SELFTEST, script, pins={"WRAP": "D57"})
    problems = []
    _fails(log, problems)
    tg = [c for c, _ in log.pins.get("WRAP", [])]
    if len(tg) != 2 * len(ks):
        problems.append(f"PF3 toggled {len(tg)} times, the program toggles it {2 * len(ks)} times")
    gaps = [b - a for a, b in zip(tg[0::2], tg[1::2])]
    for k, g in zip(ks, gaps):
        if not 0 < g <= 65536 - 65000 + k + 100:
            problems.append(f"OCR5A = {k} armed before the wrap matched {g} cycles after the write "
                            f"(bound {65536 - 65000 + k + 100})")
    return CheckResult(not problems, f"OCR5A = k armed at TCNT5 >= 65000, k in {sorted(set(ks))}, each at 8 "
                                     f"phases of the wrap: matched {min(gaps, default=0)}..{max(gaps, default=0)} "
                                     "cycles after the write", problems)


def check_timer_rewrap():
    """A compare value of the first ticks of a period, written once, matches at every wrap (the chip's
    comparator sees TCNT pass k each period; libsimavr 1.6 alone schedules each period's match at its
    overflow only if it still lies ahead when the overflow is handled, a few cycles after the wrap
    inside a long instruction, and skipped the match of k = 0..3 for that period: a step engine counting
    the wraps of a long interval stepped one wrap, 65,536 cycles, late; tools/emu/emu_timer.c, fix 3).
    From first principles: the compare B interrupt toggles PF3 once a period, 65,536 cycles apart
    (give or take the instruction it waits for and the harness's correction of 16 cycles at most), and
    counts as many matches as toggles."""
    ks = (0, 1, 2, 3, 4, 7, 100)
    script = "wait ^READY\n" + "".join(f"send rewrap {k}\nwait ^OK rewrap {k} [0-9]+$\n" for k in ks)
    log = emulog.run(SELFTEST, script, pins={"WRAP": "D57"})
    problems = []
    _fails(log, problems)
    tg = [c for c, _ in log.pins.get("WRAP", [])]
    oks = log.lines_matching(r"^OK rewrap ")
    worst, n_gaps = 0, 0
    for k, ok in zip(ks, oks):
        start = next((t.cycle for t in log.tx if t.text == f"rewrap {k}"), 0)
        mine = [c for c in tg if start < c <= ok.cycle]
        if len(mine) != int(ok.text.split()[3]) or len(mine) < 10:
            problems.append(f"rewrap {k}: {len(mine)} toggles of PF3, the ISR counted {ok.text.split()[3]} "
                            "(at least 10 wraps)")
        for a, b in zip(mine, mine[1:]):
            n_gaps += 1
            worst = max(worst, abs(b - a - 65536))
            if abs(b - a - 65536) > 30:
                problems.append(f"rewrap {k}: matches {b - a} cycles apart (a wrap is 65536)")
                break
    if len(oks) != len(ks):
        problems.append(f"{len(oks)} of {len(ks)} rewrap replies")
    return CheckResult(not problems, f"OCR5B = k written once, k in {list(ks)}: {n_gaps} matches a wrap apart "
                                     f"within {worst} cycles", problems)


def check_tifr_write():
    """Writing TIFRn clears the flags written as 1 and leaves the others pending (ATmega2560
    datasheet, TIFRn: a flag is cleared by writing a logic one to it): with OCF5A and OCF5B both
    pending, TIFR5 = OCF5B, then interrupts on, the compare A interrupt runs at once (libsimavr 1.6
    alone clears every pending flag of the timer: tools/emu/emu_timer.c)."""
    log = emulog.run(SELFTEST, "wait ^READY\nsend tifr\nwait ^OK tifr$\n", pins={"WRAP": "D57"})
    problems = []
    _fails(log, problems)
    tg = [c for c, _ in log.pins.get("WRAP", [])]
    if len(tg) != 2:
        problems.append(f"PF3 toggled {len(tg)} times: the compare A interrupt, still pending after "
                        "TIFR5 = OCF5B, should toggle it once more")
    elif not 0 < tg[1] - tg[0] <= 100:
        problems.append(f"the pending compare A interrupt ran {tg[1] - tg[0]} cycles after interrupts were on "
                        "(bound 100)")
    gap = tg[1] - tg[0] if len(tg) == 2 else None
    return CheckResult(not problems, f"TIFR5 = OCF5B with OCF5A and OCF5B pending: compare A's interrupt ran "
                                     f"{gap} cycles after sei", problems)


def check_udre_after_txen():
    """UDRE0 is set whenever the transmit buffer is empty (ATmega2560 datasheet, UCSRnA: initial
    value 1), whatever TXEN0 did: after UCSR0B = 0 and the transmitter on again, nothing being sent,
    it reads 1, so a sketch that polls it can send (the stepper consoles' SerialOutQueue does:
    libsimavr 1.6 alone clears it with TXEN0 and sets it again only after a byte has gone out:
    tools/emu/emu_uart.c)."""
    log = emulog.run(SELFTEST, "wait ^READY\nsend udre\nwait ^OK udre\n")
    problems = []
    _fails(log, problems)
    got = log.first(r"^OK udre ")
    if not got:
        problems.append("no reply to 'udre'")
    elif got.text != "OK udre 1":
        problems.append(f"'{got.text}': UDRE0 read 0 after the transmitter was switched off and on")
    return CheckResult(not problems, f"UDRE0 after UCSR0B = 0 and TXEN0 on again: {got.text if got else '-'}",
                       problems)


CHECKS = [
    ("harness self-test: pin edges and timer timing from first principles", check_pins_and_timers),
    ("harness self-test: pin direction (DDR) and level changes at their cycles", check_pin_direction),
    ("harness self-test: UART0 frames, lines and replies", check_serial),
    ("harness self-test: LS7366R on SPI and SPI byte time", check_ls7366r_spi),
    ("harness self-test: ADC codes and phase-correct PWM waveform", check_adc_pwm),
    ("harness self-test: PWM duty -> DC-motor plant -> LS7366R count", check_motor_coupling),
    ("harness self-test: reset, watchdog, halt, crash, stack overflow and timeout are failures", check_failure_detection),
    ("harness self-test: ELF and argument validation", check_elf_validation),
    ("harness self-test: a compare match armed for the first ticks after a timer wrap comes there",
     check_timer_wrap),
    ("harness self-test: a TIFRn write clears only the flags written as 1", check_tifr_write),
    ("harness self-test: UDRE0 set while nothing is sent, after the transmitter was off", check_udre_after_txen),
    ("harness self-test: a compare value right after the wrap matches at every wrap", check_timer_rewrap),
]
