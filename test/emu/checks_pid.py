"""PID_v1 bit-exactness on the real target: build/emu/pid_v1_avr.elf (test/emu/pid_avr/) is lib's
PID module compiled by avr-gcc for the ATmega2560, where double is the 32-bit float, together with
the five float32 reference vectors of test/data/pid_v1 (recorded from the real PID_v1 library in
float, see the README there). It replays every row on the emulated CPU and prints each value that
differs; this check requires that every row ran and nothing differed.

The row and value counts are taken here from the CSV files, so a program that skipped rows or
columns fails as well.
"""
import csv
import os

import emulog
from checks_selftest import CheckResult

ROOT = emulog.ROOT
ELF = os.path.join(ROOT, "build", "emu", "pid_v1_avr.elf")
DATA = os.path.join(ROOT, "test", "data", "pid_v1")
NAMES = ["a_p_only", "b_pid_windup", "e_manual_auto", "g_irregular_calls", "h_invalid_args"]
# what the program compares per row (test/emu/pid_avr/gen_pid_vectors.py): computed, mode and
# last_time_ms always; these float columns where the cell is not empty
REAL_COLS = ["output", "output_sum", "last_input", "kp", "ki", "kd"]


def expected_counts():
    """{vector: (rows, values)} from the CSV files"""
    out = {}
    for name in NAMES:
        with open(os.path.join(DATA, "float32", name + ".csv"), encoding="utf-8", newline="") as f:
            rows = list(csv.DictReader(f))
        out[name] = (len(rows), sum(3 + sum(1 for c in REAL_COLS if r[c] != "") for r in rows))
    return out


def check_pid_vectors_on_avr():
    if not os.path.isfile(ELF):
        return CheckResult(False, "no ELF", [f"{ELF} is missing: make test builds it (tools/emu/emu.mk)"])
    want = expected_counts()
    log = emulog.run(ELF, "timeout 5000\nwait ^DONE \n")
    problems = []
    for c, k, t in log.fails:
        problems.append(f"harness: {k} at {c / emulog.F_CPU:.4f} s: {t}")
    got = {}
    for line in log.lines_matching(r"^VECTOR "):
        words = line.text.split()
        fields = emulog.query_fields(line.text)
        got[words[1]] = (int(fields["rows"]), int(fields["values"]), int(fields["mismatches"]))
    for name, (rows, values) in want.items():
        if name not in got:
            problems.append(f"{name}: not replayed")
        elif got[name][:2] != (rows, values):
            problems.append(f"{name}: replayed {got[name][0]} rows / {got[name][1]} values, the CSV has {rows} / "
                            f"{values}")
    for line in log.lines_matching(r"^MISMATCH "):
        problems.append(line.text)
    done = log.first(r"^DONE ")
    total = emulog.query_fields(done.text) if done else {}
    if not done:
        problems.append("no DONE line")
    elif total.get("mismatches") != "0" and not log.lines_matching(r"^MISMATCH "):
        problems.append(f"the program reports {total.get('mismatches')} mismatches")
    n_rows = sum(r for r, _ in want.values())
    n_values = sum(v for _, v in want.values())
    module = "lib/src/pidv1_ctrl.c"
    summary = (f"{total.get('rows', 0)}/{n_rows} rows of {len(NAMES)} float32 vectors, "
               f"{total.get('values', 0)}/{n_values} values (computed, mode, last_time_ms, {', '.join(REAL_COLS)}), "
               f"{total.get('mismatches', '?')} differing bit for bit; {module} built by avr-gcc -Os for the "
               f"ATmega2560 (double = float), {log.end_cycle() / emulog.F_CPU:.2f} s emulated")
    return CheckResult(not problems, summary, problems)


CHECKS = [
    ("PID_v1 float32 vectors on the ATmega2560: lib's PID module (avr-gcc) matches every row bit for bit",
     check_pid_vectors_on_avr),
]
