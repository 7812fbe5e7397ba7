#!/usr/bin/env python3
"""test/emu/pid_avr/gen_pid_vectors.py DATA_DIR > pid_vectors.h

Turns the PID_v1 float32 reference vectors (DATA_DIR/float32/NAME.csv with the set-up
DATA_DIR/NAME.json, see DATA_DIR/README.md) into a C header of PROGMEM tables for
test/emu/pid_avr/pid_v1_avr.c, which replays them on the emulated ATmega2560 (double = float
there) and compares every row.

Numbers become IEEE binary32 bit patterns, rounded here exactly from the decimal text (the
nearest float, ties to even, as strtof does), never through a host float computation. The
command language is the one of sim/pid_vector.h: calls separated by ';', arguments by one space:
Output:=v, SetMode(AUTOMATIC|MANUAL|n), SetTunings(Kp Ki Kd[ POn]), SetSampleTime(n),
SetOutputLimits(min max), SetControllerDirection(DIRECT|REVERSE|n).

Checked per row: computed, mode, last_time_ms (modulo 2^32: the AVR clock is 32-bit), and the
float columns in REAL_COLS; an empty cell (a value PID_v1 leaves uninitialised) is not checked.
With --count the script prints "<rows> <values>" (what the AVR program must report) instead.
"""
import csv
import json
import os
import re
import struct
import sys
from fractions import Fraction

NAMES = ["a_p_only", "b_pid_windup", "e_manual_auto", "g_irregular_calls", "h_invalid_args"]
REAL_COLS = ["output", "output_sum", "last_input", "kp", "ki", "kd"]
OPS = {"Output:=": 0, "SetMode": 1, "SetTunings": 2, "SetTunings4": 3, "SetSampleTime": 4, "SetOutputLimits": 5,
       "SetControllerDirection": 6}
SYMBOLS = {"SetMode": ("MANUAL", "AUTOMATIC"), "pon": ("P_ON_M", "P_ON_E"),
           "SetControllerDirection": ("DIRECT", "REVERSE")}
NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


class VectorError(Exception):
    pass


def f32_bits(text):
    """IEEE binary32 bits of the float nearest to the decimal `text` (ties to even)."""
    if not NUMBER.fullmatch(text):
        raise VectorError(f"'{text}' is not a decimal number")
    exact = Fraction(text)
    try:  # through a double: within one ulp of the answer, which the exact comparison then picks
        approx = struct.unpack("<I", struct.pack("<f", float(text)))[0]
    except OverflowError:
        raise VectorError(f"'{text}' is beyond the float range") from None
    best = None
    for cand in (approx - 1, approx, approx + 1):
        if not 0 <= cand <= 0xFFFFFFFF or (cand & 0x7FFFFFFF) >= 0x7F800000:
            continue  # outside the patterns, or inf/NaN
        if (exact < 0 and not cand & 0x80000000) or (exact > 0 and cand & 0x80000000):
            continue  # the other sign
        value = Fraction(struct.unpack("<f", struct.pack("<I", cand))[0])
        key = (abs(value - exact), cand & 1)  # nearest, then the even mantissa
        if best is None or key < best[0]:
            best = (key, cand)
    if best is None:
        raise VectorError(f"'{text}' is not a finite float")
    return best[1]


def int_arg(text, symbols=None):
    if symbols and text in symbols:
        return symbols.index(text)
    if not re.fullmatch(r"[+-]?\d+", text):
        raise VectorError(f"'{text}' is not an integer{' or ' + '/'.join(symbols) if symbols else ''}")
    v = int(text)
    if not -2**31 <= v < 2**31:
        raise VectorError(f"{text} does not fit int32")
    return v


def parse_call(text):
    """one call -> (op, n, [x0, x1, x2] float bits)"""
    if text.startswith("Output:="):
        return OPS["Output:="], 0, [f32_bits(text[8:]), 0, 0]
    m = re.fullmatch(r"(\w+)\((.*)\)", text)
    if not m:
        raise VectorError(f"'{text}' is not a call NAME(ARGS) or Output:=VALUE")
    name, args = m.group(1), m.group(2).split(" ") if m.group(2) else []
    want = {"SetMode": [1], "SetTunings": [3, 4], "SetSampleTime": [1], "SetOutputLimits": [2],
            "SetControllerDirection": [1]}
    if name not in want:
        raise VectorError(f"unknown call '{name}()'")
    if len(args) not in want[name]:
        raise VectorError(f"{name}() takes {' or '.join(map(str, want[name]))} arguments, got {len(args)}")
    if name == "SetTunings":
        x = [f32_bits(a) for a in args[:3]]
        if len(args) == 4:
            return OPS["SetTunings4"], int_arg(args[3], SYMBOLS["pon"]), x
        return OPS["SetTunings"], 0, x
    if name == "SetOutputLimits":
        return OPS[name], 0, [f32_bits(args[0]), f32_bits(args[1]), 0]
    return OPS[name], int_arg(args[0], SYMBOLS.get(name)), [0, 0, 0]


def parse_commands(text):
    return [parse_call(c) for c in text.split(";")] if text else []


def load(data_dir, name):
    """(set-up dict, [row dicts]) of one vector"""
    with open(os.path.join(data_dir, name + ".json"), encoding="utf-8") as f:
        setup = json.load(f, parse_float=str, parse_int=str)  # numbers as their text
    with open(os.path.join(data_dir, "float32", name + ".csv"), encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    need = {"t_ms", "input", "setpoint", "command", "computed", "mode", "last_time_ms", *REAL_COLS}
    if not rows or need - set(rows[0]):
        raise VectorError(f"float32/{name}.csv: no rows, or columns missing: {sorted(need - set(rows[0] or {}))}")
    return setup, rows


def generate(data_dir):
    cmds, rows, vecs = [], [], []
    n_values = 0
    for name in NAMES:
        setup, vrows = load(data_dir, name)
        where = f"{name}.json"
        try:
            sc = [parse_call(c) for c in setup["setup"]]
            head = dict(kp=f32_bits(setup["kp"]), ki=f32_bits(setup["ki"]), kd=f32_bits(setup["kd"]),
                        input0=f32_bits(setup["input0"]), output0=f32_bits(setup["output0"]),
                        setpoint0=f32_bits(setup["setpoint0"]), pon=int_arg(setup["pon"], SYMBOLS["pon"]),
                        direction=int_arg(setup["direction"], SYMBOLS["SetControllerDirection"]),
                        t0_ms=int(setup["t0_ms"]))
            if not 0 <= head["t0_ms"] <= 0xFFFFFFFF:
                raise VectorError(f"t0_ms {head['t0_ms']} is not a 32-bit clock value")
        except (KeyError, TypeError, ValueError, VectorError) as e:
            raise VectorError(f"{where}: {e}") from None
        head.update(name=name, setup_first=len(cmds), n_setup=len(sc), row_first=len(rows), n_rows=len(vrows))
        cmds += sc
        vecs.append(head)
        for i, r in enumerate(vrows, 2):
            try:
                rc = parse_commands(r["command"])
                have, expect = 0, []
                for k, col in enumerate(REAL_COLS):
                    if r[col] != "":
                        have |= 1 << k
                        expect.append(f32_bits(r[col]))
                        n_values += 1
                    else:
                        expect.append(0)
                n_values += 3  # computed, mode, last_time_ms
                t_ms = int(r["t_ms"])
                if not 0 <= t_ms <= 0xFFFFFFFF:
                    raise VectorError(f"t_ms {t_ms} is not a 32-bit clock value")
                rows.append(dict(t_ms=t_ms,
                                 input=f32_bits(r["input"]), setpoint=f32_bits(r["setpoint"]), cmd_first=len(cmds),
                                 n_cmds=len(rc), computed=int(r["computed"]), mode=int(r["mode"]), have=have,
                                 expect=expect, last_time_ms=int(r["last_time_ms"]) & 0xFFFFFFFF))
                cmds += rc
            except (ValueError, VectorError) as e:
                raise VectorError(f"float32/{name}.csv:{i}: {e}") from None
    return cmds, rows, vecs, n_values


def header(cmds, rows, vecs, n_values, data_dir):
    out = [f"/* pid_vectors.h - generated by test/emu/pid_avr/gen_pid_vectors.py from {data_dir}: do not edit.",
           " * Floats are IEEE binary32 bit patterns (the nearest float to the vectors' decimal text). */",
           "#include <avr/pgmspace.h>", "#include <stdint.h>", "",
           f"#define PV_N_VECTORS {len(vecs)}", f"#define PV_N_ROWS {len(rows)}", f"#define PV_N_VALUES {n_values}UL",
           f"#define PV_N_REAL {len(REAL_COLS)}",
           "static const char *const pv_real_names[PV_N_REAL] = {" + ", ".join(f'"{c}"' for c in REAL_COLS) + "};",
           "enum { PV_OUTPUT_SET, PV_SET_MODE, PV_SET_TUNINGS, PV_SET_TUNINGS_PON, PV_SET_SAMPLE_TIME,",
           "       PV_SET_OUTPUT_LIMITS, PV_SET_DIRECTION };",
           "typedef struct { uint8_t op; int32_t n; uint32_t x[3]; } pv_cmd_t;",
           "typedef struct {",
           "    uint32_t t_ms, input, setpoint;",
           "    uint16_t cmd_first;",
           "    uint8_t n_cmds, computed, mode, have; /* have: bit k = expect[k] is given */",
           "    uint32_t expect[PV_N_REAL];",
           "    uint32_t last_time_ms;",
           "} pv_row_t;",
           "typedef struct {",
           "    char name[24];",
           "    uint32_t kp, ki, kd, input0, output0, setpoint0, t0_ms;",
           "    int32_t pon, direction;",
           "    uint16_t setup_first, n_setup, n_rows;",
           "} pv_vec_t;", ""]
    out.append("static const pv_cmd_t pv_cmds[] PROGMEM = {")
    out += [f"    {{{op}, {n}L, {{0x{x[0]:08x}UL, 0x{x[1]:08x}UL, 0x{x[2]:08x}UL}}}}," for op, n, x in cmds]
    if not cmds:
        out.append("    {0, 0, {0, 0, 0}},")
    out.append("};")
    # one row table per vector: an AVR object is at most 32 KiB
    for vi, v in enumerate(vecs):
        out.append(f"static const pv_row_t pv_rows_{vi}[] PROGMEM = {{ /* {v['name']} */")
        for r in rows[v["row_first"]:v["row_first"] + v["n_rows"]]:
            ex = ", ".join(f"0x{x:08x}UL" for x in r["expect"])
            out.append(f"    {{{r['t_ms']}UL, 0x{r['input']:08x}UL, 0x{r['setpoint']:08x}UL, {r['cmd_first']}, "
                       f"{r['n_cmds']}, {r['computed']}, {r['mode']}, 0x{r['have']:02x}, {{{ex}}}, "
                       f"{r['last_time_ms']}UL}},")
        out.append("};")
    out.append("/* far address of row i of vector vi (the tables may lie above 64 KiB) */")
    out.append("static uint_farptr_t pv_row_addr(uint8_t vi, uint16_t i)")
    out.append("{")
    out.append("    uint_farptr_t base;")
    out.append("    switch (vi) {")
    for vi in range(len(vecs)):
        out.append(f"    case {vi}: base = pgm_get_far_address(pv_rows_{vi}); break;")
    out.append("    default: return 0;")
    out.append("    }")
    out.append("    return base + (uint32_t)i * sizeof(pv_row_t);")
    out.append("}")
    out.append("static const pv_vec_t pv_vecs[PV_N_VECTORS] PROGMEM = {")
    for v in vecs:
        out.append(f"    {{\"{v['name']}\", 0x{v['kp']:08x}UL, 0x{v['ki']:08x}UL, 0x{v['kd']:08x}UL, "
                   f"0x{v['input0']:08x}UL, 0x{v['output0']:08x}UL, 0x{v['setpoint0']:08x}UL, {v['t0_ms']}UL, "
                   f"{v['pon']}L, {v['direction']}L, {v['setup_first']}, {v['n_setup']}, {v['n_rows']}}},")
    out.append("};")
    return "\n".join(out) + "\n"


def main(argv):
    args = [a for a in argv if a != "--count"]
    if len(args) != 1:
        print("usage: gen_pid_vectors.py [--count] DATA_DIR   (e.g. test/data/pid_v1)", file=sys.stderr)
        return 2
    try:
        cmds, rows, vecs, n_values = generate(args[0])
    except (OSError, VectorError, json.JSONDecodeError) as e:
        print(f"gen_pid_vectors: {e}", file=sys.stderr)
        return 1
    if "--count" in argv:
        print(len(rows), n_values)
    else:
        sys.stdout.write(header(cmds, rows, vecs, n_values, args[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
