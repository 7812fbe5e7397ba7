"""test/emu/text_parse_avr/gen_real_words.py: the expected floats of the AVR number-parser check
must themselves be right. Oracles: binary32 values worked out by hand from the IEEE layout, and
Python's float (correctly rounded to double) then struct's rounding to float, which equals the
exact answer except when the double lands on a float tie."""
import os
import random
import struct
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GEN_DIR = os.path.join(ROOT, "test", "emu", "text_parse_avr")
sys.path.insert(0, GEN_DIR)
import gen_real_words as g  # noqa: E402


def via_double(word):
    return struct.unpack("<I", struct.pack("<f", float(word)))[0]


def test_hand_worked_values():
    # 0.05 = 0x1.99999Ap-5 rounded up (the next bit of ...999 is 1, then more ones)
    assert g.f32_bits("0.05") == 0x3D4CCCCD
    assert g.f32_bits("-0.05") == 0xBD4CCCCD
    assert g.f32_bits("1") == 0x3F800000
    assert g.f32_bits("-0") == 0x80000000 and g.f32_bits("0e5") == 0
    # 2^24 + 1 lies half-way between 2^24 and 2^24 + 2: to even (2^24); 2^24 + 3: to 2^24 + 4
    assert g.f32_bits("16777217") == 0x4B800000
    assert g.f32_bits("16777219") == 0x4B800002
    # 3e10 = 29296875 * 2^10, 29296875 odd with 25 bits: a tie, to the even mantissa 29296876 / 2
    assert g.f32_bits("3e10") == (127 + 34) << 23 | (29296876 // 2 - 2 ** 23)
    # just above the 2^24 + 1 tie: up; a double rounds this word onto the tie (and then down)
    assert g.f32_bits("16777217.0000000001") == 0x4B800001
    assert via_double("16777217.0000000001") == 0x4B800000
    # the smallest subnormal 2^-149 = 1.401e-45; half of it rounds to even (0), a bit more to it
    assert g.f32_bits("1.4e-45") == 1
    assert g.f32_bits("7.006492321624085e-46") == 0  # below half
    assert g.f32_bits("7.1e-46") == 1
    # FLT_MAX, and the half-way point to 2^128 (3.4028235677973366e38) and above: infinity
    assert g.f32_bits("3.4028235e38") == 0x7F7FFFFF
    assert g.f32_bits("3.40282357e38") == 0x7F800000


def test_agrees_with_the_double_route_on_random_words():
    rng = random.Random(7)
    for _ in range(5000):
        digits = str(rng.randint(1, 10 ** rng.randint(1, 12)))
        word = f"{rng.choice(['', '-'])}{digits}e{rng.randint(-40, 26)}"
        assert g.f32_bits(word) == via_double(word), word


def test_class_follows_text_parse_h():
    exact = ["0.05", "16777216", "1e10", "1e-10", "100e8", "0.00000000010", "12345678", "-0", "0e99", "1.6777216e7"]
    fallback = ["16777217", "1e11", "100e9", "0.00000000001", "123456789", "12345678e-11", "99999999", "1e20"]
    for w in exact:
        assert g.word_class(w) == "exact", w
    for w in fallback:
        assert g.word_class(w) == "fallback", w


def test_table_holds_the_words_strtod_got_wrong_and_is_deterministic():
    rows = g.generate()
    assert rows == g.generate()
    cls = {w: c for c, w, _ in rows}
    for w in ["0.05", "0.15", "0.9", "1.234", "7.7", "0.0005"]:
        assert cls.get(w) == "exact"
    assert len({w for _, w, _ in rows}) == len(rows)
    assert sum(c == "exact" for c in cls.values()) >= 400 and sum(c == "fallback" for c in cls.values()) >= 100
    assert all(len(w) <= g.WORD_MAX for w in cls)


def test_command_line():
    out = subprocess.run([sys.executable, os.path.join(GEN_DIR, "gen_real_words.py"), "--list"],
                         capture_output=True, text=True, check=True).stdout.splitlines()
    assert out[0] == "exact 0.05 0x3d4ccccd"
    bad = subprocess.run([sys.executable, os.path.join(GEN_DIR, "gen_real_words.py"), "--nope"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and bad.stderr.startswith("usage:")
