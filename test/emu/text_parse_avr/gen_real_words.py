#!/usr/bin/env python3
"""test/emu/text_parse_avr/gen_real_words.py > real_words.h

The decimal words that test/emu/text_parse_avr/text_parse_avr.c feeds to lib's text_parse_real on
the emulated ATmega2560, each with the IEEE binary32 bits of the float nearest to it (ties to
even), computed here exactly from the decimal as a fraction: no host float takes part, so double
rounding (decimal -> double -> float, which can land on the wrong side of a tie) cannot creep in.

Each word is classed as text_parse.h promises:
  exact     at most 8 significant digits with a value below or at 2^24 and a decimal exponent
            within +-10 once the trailing zeros are folded into it (d * 10^e, d <= 2^24,
            |e| <= 10), or zero: text_parse_real must give the nearest float, bit for bit;
  fallback  everything else (9 or more significant digits, d > 2^24, |e| > 10): strtod's result,
            which on avr-libc is not always the nearest float; counted, not required.

The words: the ones avr-libc's strtod was seen to get wrong (0.05, 0.15, 0.9, 1.234, 7.7,
0.0005), exact-path ties (d * 10^e exactly half-way between two floats), and words generated from
a fixed seed with varied shapes (1-8 digits, the point anywhere, leading and trailing zeros,
signs, exponents -12..12 written e/E, with or without '+' and leading zeros), then words beyond
the exact path (9-12 digits, exponents up to +-20, d just above 2^24, decimal ties that a double
rounds onto a float tie). With --list the script prints "class word bits" lines instead.
"""
import random
import sys
from fractions import Fraction

WORD_MAX = 27            # characters; the C table holds char[WORD_MAX + 1]
EXACT_MANTISSA_MAX = 2 ** 24
EXACT_EXP10_MAX = 10
SEED = 20261122
N_EXACT_RANDOM = 420
N_FALLBACK_RANDOM = 120

# seen wrong from avr-libc 2.0's strtod alone (one unit low), in the shapes a user types them
KNOWN_BAD = ["0.05", "0.15", "0.9", "1.234", "7.7", "0.0005", "-0.05", "+0.15", ".05", "5e-2", "0.050",
             "0.90", "1234e-3", "77E-1", "5E-4", "-7.7", "0.001", "0.1", "0.3", "2.0004"]
# what the sketches' own commands send
SKETCH_WORDS = ["1", "20", "10", "0.3", "0.02", "1000", "-200", "3050", "4000", "0.2", "0.5", "5", "9.005", "60",
                "1001", "-1", "-0.5"]
EDGES = ["0", "-0", "+0", "0.0", "0e5", "000.0100", "1e+3", "16777216", "1.6777216e7", "0.16777216e8",
         "1e10", "1e-10", "1E+10", "-1e-010", "9.999999e10", "1.0000000e-3", "00000001", "1.", ".1", "-.5e1"]


def decimal_parts(word):
    """(negative, d, e) with |value| = d * 10^e and d free of trailing zeros (d = 0 for zero)"""
    w = word
    negative = w[:1] == "-"
    if w[:1] in "+-":
        w = w[1:]
    exp = 0
    for mark in "eE":
        if mark in w:
            w, _, tail = w.partition(mark)
            exp = int(tail)
    whole, _, frac = w.partition(".")
    d = int((whole + frac) or "0")
    e = exp - len(frac)
    if d == 0:
        return negative, 0, 0
    while d % 10 == 0:
        d //= 10
        e += 1
    return negative, d, e


def word_class(word):
    _, d, e = decimal_parts(word)
    return "exact" if d == 0 or (d <= EXACT_MANTISSA_MAX and -EXACT_EXP10_MAX <= e <= EXACT_EXP10_MAX) else "fallback"


def f32_bits(word):
    """binary32 bits of the float nearest to the decimal word, ties to even; exactly, by integers"""
    negative, d, e = decimal_parts(word)
    sign = 0x80000000 if negative else 0
    if d == 0:
        return sign
    x = Fraction(d) * Fraction(10) ** e
    # k with 2^k <= x < 2^(k+1)
    k = x.numerator.bit_length() - x.denominator.bit_length()
    if x < Fraction(2) ** k:
        k -= 1
    q = max(k, -126) - 23              # the weight of the last mantissa bit (subnormals: 2^-149)
    scaled = x / Fraction(2) ** q
    n = scaled.numerator // scaled.denominator
    rest = scaled - n
    if rest > Fraction(1, 2) or (rest == Fraction(1, 2) and n % 2 == 1):
        n += 1
    if n == 2 ** 24:                   # rounded up to the next binade
        n, q = 2 ** 23, q + 1
    if n >= 2 ** 23:
        biased = q + 23 + 127
        if biased >= 255:
            return sign | 0x7F800000   # beyond the largest float: infinity
        return sign | (biased << 23) | (n - 2 ** 23)
    return sign | n                    # subnormal (q = -149)


def exact_ties():
    """words d * 10^e (e = 1..10, d <= 2^24) exactly half-way between two floats: the odd part of
    d * 5^e has 25 bits, so a single correctly rounded multiplication must round it to even"""
    out = []
    for e in range(1, EXACT_EXP10_MAX + 1):
        five = 5 ** e
        found = 0
        odd = 1
        while found < 2 and odd <= EXACT_MANTISSA_MAX:
            if (odd * five).bit_length() == 25 and odd % 5 != 0:
                out.append(f"{odd}e{e}")
                found += 1
            odd += 2
    return out


def shaped_word(rng, digits, exp10, shape):
    """a word for the value digits * 10^exp10 (digits: a string without leading zeros), in a
    random spelling: point position, leading/trailing zeros, sign, exponent form"""
    s = digits + "0" * rng.choice([0, 0, 0, 1, 2, 3])      # trailing zeros that are significant text
    exp10 -= len(s) - len(digits)
    # split the value into "mantissa text with a point" and "written exponent"
    written_exp = 0
    if shape == "plain":
        point = len(s) + exp10                              # digits left of the point
    else:
        written_exp = rng.randint(-12, 12)
        point = len(s) + exp10 - written_exp
    if point <= 0:
        text = "0." + "0" * (-point) + s
    elif point >= len(s):
        text = s + "0" * (point - len(s))
        if rng.random() < 0.3:
            text += "." + "0" * rng.randint(0, 2)
    else:
        text = s[:point] + "." + s[point:]
    if text.startswith("0.") and rng.random() < 0.2:
        text = text[1:]                                     # ".05"
    elif rng.random() < 0.1:
        text = "0" * rng.randint(1, 3) + text               # "007.5"
    if shape != "plain":
        e = rng.choice(["e", "E"])
        if written_exp >= 0 and rng.random() < 0.3:
            e += "+"
        e += str(written_exp) if rng.random() < 0.8 else ("-" if written_exp < 0 else "") + f"{abs(written_exp):03d}"
        text += e
    sign = rng.choice(["", "", "", "-", "+"])
    return sign + text


def generate():
    """[(class, word, bits)] in the order of the table"""
    rng = random.Random(SEED)
    words = list(dict.fromkeys(KNOWN_BAD + SKETCH_WORDS + EDGES + exact_ties()))
    seen = set(words)
    n_exact = n_fallback = 0
    # varied shapes: 1-8 significant digits, value exponent so that the word stays in the exact
    # path most of the time; the ones that leave it (exponent beyond +-10) go to the fallback count
    while n_exact < N_EXACT_RANDOM:
        n = rng.randint(1, 8)
        digits = str(rng.randint(10 ** (n - 1), 10 ** n - 1))
        exp10 = rng.randint(-12, 12) - (len(digits) - 1 if rng.random() < 0.7 else 0)
        w = shaped_word(rng, digits, exp10, rng.choice(["plain", "plain", "exp"]))
        if len(w) > WORD_MAX or w in seen:
            continue
        seen.add(w)
        words.append(w)
        if word_class(w) == "exact":
            n_exact += 1
    # beyond the exact path: long words, large exponents, d above 2^24
    fixed_fallback = ["16777217", "16777218", "16777219", "33554435", "99999999", "123456789", "0.123456789",
                      "3.14159265358979", "99999999999", "1e11", "1e-11", "1.5e-11", "1e20", "-1e-20", "7e19",
                      "3.4028235e38", "1.17549435e-38", "0.1000000001", "2.718281828459045",
                      "16777217.0000000001", "8388609.50000000001", "0.30000000000000004"]
    for w in fixed_fallback:
        if w not in seen:
            seen.add(w)
            words.append(w)
    while n_fallback < N_FALLBACK_RANDOM:
        n = rng.randint(9, 12) if rng.random() < 0.6 else rng.randint(1, 8)
        digits = str(rng.randint(10 ** (n - 1), 10 ** n - 1))
        exp10 = rng.randint(-20, 20) - (len(digits) - 1)
        w = shaped_word(rng, digits, exp10, rng.choice(["plain", "exp"]))
        if len(w) > WORD_MAX or w in seen or word_class(w) != "fallback":
            continue
        seen.add(w)
        words.append(w)
        n_fallback += 1
    out = []
    for w in words:
        if len(w) > WORD_MAX:
            raise ValueError(f"'{w}' is longer than {WORD_MAX} characters")
        out.append((word_class(w), w, f32_bits(w)))
    return out


def header(rows):
    n_exact = sum(1 for c, _, _ in rows if c == "exact")
    out = ["/* real_words.h - generated by test/emu/text_parse_avr/gen_real_words.py: do not edit.",
           " * Decimal words and the binary32 bits of the nearest float (ties to even), exact from the decimal. */",
           "#include <avr/pgmspace.h>", "#include <stdint.h>", "",
           f"#define RW_WORD_MAX {WORD_MAX}", f"#define RW_N_WORDS {len(rows)}", f"#define RW_N_EXACT {n_exact}",
           "typedef struct { char word[RW_WORD_MAX + 1]; uint32_t bits; uint8_t exact; } rw_entry_t;", "",
           "static const rw_entry_t rw_words[RW_N_WORDS] PROGMEM = {"]
    for cls, w, bits in rows:
        out.append(f"    {{\"{w}\", 0x{bits:08x}UL, {1 if cls == 'exact' else 0}}},")
    out.append("};")
    return "\n".join(out) + "\n"


def main(argv):
    if argv not in ([], ["--list"]):
        print("usage: gen_real_words.py [--list] > real_words.h", file=sys.stderr)
        return 2
    rows = generate()
    if argv == ["--list"]:
        for cls, w, bits in rows:
            print(f"{cls} {w} 0x{bits:08x}")
    else:
        sys.stdout.write(header(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
