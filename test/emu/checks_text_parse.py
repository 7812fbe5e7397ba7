"""text_parse_real on the real target: build/emu/text_parse_avr.elf (test/emu/text_parse_avr/) is
lib/src/text_parse.c compiled by avr-gcc for the ATmega2560 (double = float, avr-libc's strtod and
float arithmetic), fed the decimal words of gen_real_words.py together with the nearest float of
each (computed exactly from the decimal in Python). It prints every word whose float differs.

Required: every word accepted, and every word of the class text_parse.h promises to round
correctly (at most 8 significant digits, <= 2^24, decimal exponent within +-10) bit for bit equal
to the nearest float. The other words go through avr-libc's strtod, which is not correctly
rounded: their differences are counted in the summary and do not fail the check. The word counts
are taken here from the generator, so a program that skipped words fails as well.
"""
import os
import re
import sys

import emulog
from checks_selftest import CheckResult

ROOT = emulog.ROOT
ELF = os.path.join(ROOT, "build", "emu", "text_parse_avr.elf")
sys.path.insert(0, os.path.join(ROOT, "test", "emu", "text_parse_avr"))
import gen_real_words  # noqa: E402

# the words avr-libc's strtod alone was seen to get one unit low
SEEN_WRONG = ["0.05", "0.15", "0.9", "1.234", "7.7", "0.0005"]


def status_number(name):
    """The value of a motion_status_t name: its place in lib/src/motion_status.h's X-list."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    with open(os.path.join(root, "lib", "src", "motion_status.h"), encoding="utf-8") as f:
        names = re.findall(r"^\s*X\((MS_[A-Z0-9_]+),", f.read(), re.M)
    return names.index(name)


def check_text_parse_real_on_avr():
    if not os.path.isfile(ELF):
        return CheckResult(False, "no ELF", [f"{ELF} is missing: make test builds it (tools/emu/emu.mk)"])
    rows = gen_real_words.generate()
    n_exact = sum(1 for c, _, _ in rows if c == "exact")
    n_fallback = len(rows) - n_exact
    problems = []
    for w in SEEN_WRONG:
        if ("exact", w) not in {(c, x) for c, x, _ in rows}:
            problems.append(f"the table should hold '{w}' as a word of the exact class")
    log = emulog.run(ELF, "timeout 5000\nwait ^DONE \n")
    for c, k, t in log.fails:
        problems.append(f"harness: {k} at {c / emulog.F_CPU:.4f} s: {t}")
    done = log.first(r"^DONE ")
    total = emulog.query_fields(done.text) if done else {}
    cyc = log.first(r"^CYCLES ")
    cycles = emulog.query_fields(cyc.text) if cyc else {}
    if not done:
        problems.append("no DONE line")
    elif (total.get("words"), total.get("exact"), total.get("fallback")) != (str(len(rows)), str(n_exact),
                                                                            str(n_fallback)):
        problems.append(f"the program parsed {total.get('words')} words ({total.get('exact')} exact, "
                        f"{total.get('fallback')} fallback), the generator has {len(rows)} ({n_exact}, {n_fallback})")
    exact_bad, fallback_bad, to_inf = [], [], []
    for line in log.lines_matching(r"^MISMATCH "):
        w = line.text.split()
        # MISMATCH <class> <index> <word> want 0x.. got 0x.. status <n>
        if len(w) != 10 or not w[2].isdigit() or int(w[2]) >= len(rows):
            problems.append(f"unreadable line: {line.text}")
            continue
        cls, word, want = rows[int(w[2])]
        if (w[1], w[3], int(w[5], 16)) != (cls, word, want):
            problems.append(f"the program's table differs from the generator at word {w[2]}: {line.text}")
        if w[9] == str(status_number("MS_ERR_OUT_OF_RANGE")) and cls == "fallback":
            # MS_ERR_OUT_OF_RANGE: avr-libc's strtod overflowed to infinity (e.g. 3.4028235e38, whose
            # nearest float is FLT_MAX); text_parse_real refuses an infinite result as overflow
            fallback_bad.append(word)
            to_inf.append(word)
        elif w[9] != "0":
            problems.append(f"'{word}' rejected (status {w[9]}): {line.text}")
        elif cls == "exact":
            exact_bad.append(line.text)
        else:
            fallback_bad.append(word)
            if int(w[7], 16) & 0x7F800000 == 0x7F800000:
                to_inf.append(word)
    problems += exact_bad
    if done and total.get("exact_mismatches") != str(len(exact_bad)):
        problems.append(f"the program counts {total.get('exact_mismatches')} exact-class mismatches, "
                        f"{len(exact_bad)} lines came")
    if done and total.get("rejected") != str(len(to_inf)):
        problems.append(f"the program reports {total.get('rejected')} rejected words")
    # limits compared with the decimal before rounding, and underflow refused (issue 12 item 6)
    lim = log.first(r"^LIMITS ")
    limits = emulog.query_fields(lim.text) if lim else {}
    if not lim:
        problems.append("no LIMITS line")
    elif limits.get("mismatches") != "0":
        problems.append(f"limit/underflow cases: {lim.text}")
    problems += [line.text for line in log.lines_matching(r"^LIMIT ")]
    inf_note = (f"; {', '.join(to_inf)} refused as overflow (avr-libc's strtod gives infinity)" if to_inf
                else "")
    summary = (f"{total.get('words', 0)}/{len(rows)} words through lib/src/text_parse.c built by avr-gcc -Os for "
               f"the ATmega2560 (double = float): {n_exact} of the exact class (<= 2^24 significant, exponent "
               f"within +-10; {', '.join(SEEN_WRONG)} among them) with {len(exact_bad)} differing from the nearest "
               f"float; {n_fallback} beyond it (avr-libc strtod, not required): {len(fallback_bad)} differ, by up to "
               f"{total.get('fallback_max_ulps', '?')} ulp{inf_note}; "
               f"cycles per call: exact mean {cycles.get('exact_mean', '?')} max {cycles.get('exact_max', '?')}, "
               f"fallback mean {cycles.get('fallback_mean', '?')} max {cycles.get('fallback_max', '?')}; "
               f"limits and underflow: {limits.get('cases', '?')} cases, {limits.get('mismatches', '?')} wrong; "
               f"{log.end_cycle() / emulog.F_CPU:.2f} s emulated")
    return CheckResult(not problems, summary, problems)


CHECKS = [
    ("text_parse_real on the ATmega2560: short decimals (<= 8 digits, exponent +-10) give the nearest float "
     "bit for bit",
     check_text_parse_real_on_avr),
]
