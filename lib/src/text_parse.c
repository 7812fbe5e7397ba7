/* text_parse.c - strict word and number parsing (see text_parse.h). */
#include "text_parse.h"

#include <float.h>
#include <stdlib.h>

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

int text_next_word(const char **cursor, char *word, size_t n)
{
    const char *p = *cursor;
    size_t len = 0;
    int fits = 1;
    while (is_blank(*p))
        p++;
    while (*p != '\0' && !is_blank(*p)) {
        if (len + 1 < n)
            word[len++] = *p;
        else
            fits = 0;
        p++;
    }
    if (n > 0)
        word[len] = '\0';
    *cursor = p;
    if (!fits)
        return -1;
    return (int)len;
}

int text_at_end(const char *cursor)
{
    while (is_blank(*cursor))
        cursor++;
    return *cursor == '\0';
}

motion_status_t text_parse_int32(const char *word, int32_t lo, int32_t hi, int32_t *out)
{
    const char *p = word;
    int negative = 0;
    uint32_t mag = 0;
    /* the largest magnitude allowed for this sign: 2^31 for negative, 2^31-1 for positive */
    uint32_t limit;
    int32_t value;
    if (*p == '+' || *p == '-') {
        negative = (*p == '-');
        p++;
    }
    if (!is_digit(*p))
        return MS_ERR_NOT_A_NUMBER;
    limit = negative ? 2147483648UL : 2147483647UL;
    for (; *p != '\0'; p++) {
        uint32_t d;
        if (!is_digit(*p))
            return MS_ERR_NOT_A_NUMBER;
        d = (uint32_t)(*p - '0');
        if (mag > (limit - d) / 10U) {
            /* too large for 32 bits; keep checking that the rest is digits */
            for (p++; *p != '\0'; p++)
                if (!is_digit(*p))
                    return MS_ERR_NOT_A_NUMBER;
            return MS_ERR_OUT_OF_RANGE;
        }
        mag = mag * 10U + d;
    }
    if (negative)
        value = (mag == 2147483648UL) ? INT32_MIN : -(int32_t)mag;
    else
        value = (int32_t)mag;
    if (value < lo || value > hi)
        return MS_ERR_OUT_OF_RANGE;
    *out = value;
    return MS_OK;
}

motion_status_t text_parse_uint32(const char *word, uint32_t lo, uint32_t hi, uint32_t *out)
{
    const char *p = word;
    uint32_t mag = 0;
    int too_big = 0;
    if (*p == '+')
        p++;
    if (!is_digit(*p))
        return MS_ERR_NOT_A_NUMBER;
    for (; *p != '\0'; p++) {
        uint32_t d;
        if (!is_digit(*p))
            return MS_ERR_NOT_A_NUMBER;
        d = (uint32_t)(*p - '0');
        if (too_big || mag > (4294967295UL - d) / 10U)
            too_big = 1;
        else
            mag = mag * 10U + d;
    }
    if (too_big || mag < lo || mag > hi)
        return MS_ERR_OUT_OF_RANGE;
    *out = mag;
    return MS_OK;
}

/* Powers of ten that are exact in a float (5^10 < 2^24) and so in any double. */
static const double exact_pow10[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10};
#define EXACT_POW10_MAX 10
#define EXACT_MANTISSA_MAX 16777216UL /* 2^24: every integer up to it is exact in a float */

/* The correctly rounded value of a validated decimal word when its significant digits fit in 2^24
 * and its decimal exponent in +-10: both operands of one multiplication or division are then
 * exact, so IEEE arithmetic rounds once, correctly, in float (AVR) as in double (host).
 * avr-libc's strtod is not correctly rounded ("0.05" gives 0x3D4CCCCC, one unit below the
 * nearest float 0x3D4CCCCD; so do 0.15, 0.9, 1.234, 7.7), which would make the board run other
 * parameters than motionsim. Returns 0 when the word is outside that range (strtod then). */
static int parse_short_decimal(const char *word, double *out)
{
    const char *p = word;
    int negative = 0, exp10 = 0, exp_negative = 0;
    int pending_zeros = 0; /* zeros not yet multiplied into the mantissa */
    uint32_t mantissa = 0;
    long exp_value = 0;
    double v;
    if (*p == '+' || *p == '-')
        negative = (*p++ == '-');
    for (int fraction = 0;; p++) {
        if (*p == '.' && !fraction) {
            fraction = 1;
            continue;
        }
        if (!is_digit(*p))
            break;
        if (fraction)
            exp10--;
        if (*p == '0') {
            pending_zeros++; /* trailing zeros of the fraction need not enter the mantissa */
            continue;
        }
        for (; pending_zeros > 0; pending_zeros--) {
            if (mantissa > EXACT_MANTISSA_MAX / 10U)
                return 0;
            mantissa *= 10U;
        }
        /* mantissa * 10 + d <= 2^24, with constants only (a 32-bit division per digit is slow on the AVR) */
        if (mantissa > EXACT_MANTISSA_MAX / 10U ||
            (mantissa == EXACT_MANTISSA_MAX / 10U && (uint32_t)(*p - '0') > EXACT_MANTISSA_MAX % 10U))
            return 0;
        mantissa = mantissa * 10U + (uint32_t)(*p - '0');
    }
    /* zeros left over are worth 10^pending_zeros: fold them into the exponent */
    exp10 += pending_zeros;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            exp_negative = (*p++ == '-');
        for (; is_digit(*p); p++) {
            if (exp_value > 1000)
                return 0;
            exp_value = exp_value * 10 + (*p - '0');
        }
        exp10 += exp_negative ? -(int)exp_value : (int)exp_value;
    }
    if (mantissa == 0) {
        *out = negative ? -0.0 : 0.0;
        return 1;
    }
    if (exp10 < -EXACT_POW10_MAX || exp10 > EXACT_POW10_MAX)
        return 0;
    v = (double)mantissa;
    v = exp10 < 0 ? v / exact_pow10[-exp10] : v * exact_pow10[exp10];
    *out = negative ? -v : v;
    return 1;
}

/* Validates the shape of a decimal word: returns a pointer to its end (the NUL) or NULL. Sets
 * *nonzero when a mantissa digit is not 0. */
static const char *real_shape(const char *word, int *nonzero)
{
    const char *p = word;
    int digits = 0;
    *nonzero = 0;
    if (*p == '+' || *p == '-')
        p++;
    for (; is_digit(*p) || (*p == '.'); p++) {
        if (*p == '.') {
            /* only one point: the rest of the mantissa must be digits */
            for (p++; is_digit(*p); p++) {
                digits++;
                *nonzero |= (*p != '0');
            }
            break;
        }
        digits++;
        *nonzero |= (*p != '0');
    }
    if (digits == 0)
        return NULL;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            p++;
        if (!is_digit(*p))
            return NULL;
        while (is_digit(*p))
            p++;
    }
    return *p == '\0' ? p : NULL;
}

/* The whole part of |word| for a validated decimal word, exactly, in *whole (with *over set instead
 * when it reaches 2^32), and *frac set when a nonzero fraction follows it. The word's mantissa digits
 * (the point left out) are read in order: those before the point, moved by the exponent, are the
 * whole part's, the rest the fraction's; whole digits past the mantissa are zeros. */
static void decimal_floor(const char *word, uint32_t *whole, int *over, int *frac)
{
    const char *p = word, *q;
    long before = 0, e = 0, k = 0;
    int e_negative = 0;
    uint32_t v = 0;
    *over = 0;
    *frac = 0;
    if (*p == '+' || *p == '-')
        p++;
    for (q = p; is_digit(*q); q++)
        before++;
    while (is_digit(*q) || *q == '.')
        q++;
    if (*q == 'e' || *q == 'E') {
        q++;
        if (*q == '+' || *q == '-')
            e_negative = (*q++ == '-');
        for (; is_digit(*q); q++)
            if (e < 100000L) /* saturated: far beyond a uint32's 10 digits either way */
                e = e * 10 + (*q - '0');
    }
    before += e_negative ? -e : e;
    for (; is_digit(*p) || *p == '.'; p++) {
        uint32_t d = (uint32_t)(*p - '0');
        if (*p == '.')
            continue;
        if (k++ >= before)
            *frac |= d != 0;
        else if (*over || v > (4294967295UL - d) / 10U)
            *over = 1;
        else
            v = v * 10U + d;
    }
    for (; k < before && v != 0 && !*over; k++) {
        if (v > 4294967295UL / 10U)
            *over = 1;
        v *= 10U;
    }
    *whole = v;
}

/* The whole number a validated decimal word stands for, exactly, in integers: see text_parse.h. */
motion_status_t text_parse_whole(const char *word, int32_t lo, int32_t hi, int32_t *out)
{
    int nonzero, over, frac;
    uint32_t mag;
    int32_t value;
    if (real_shape(word, &nonzero) == NULL)
        return MS_ERR_NOT_A_NUMBER;
    decimal_floor(word, &mag, &over, &frac);
    if (frac)
        return TEXT_PARSE_NOT_WHOLE; /* a fraction, whatever the size */
    if (over || mag > (word[0] == '-' ? 2147483648UL : 2147483647UL))
        return MS_ERR_OUT_OF_RANGE;
    value = word[0] == '-' ? (mag == 2147483648UL ? INT32_MIN : -(int32_t)mag) : (int32_t)mag;
    if (value < lo || value > hi)
        return MS_ERR_OUT_OF_RANGE;
    *out = value;
    return MS_OK;
}

motion_status_t text_scan_real(const char *word, double *out)
{
    char *end = 0;
    int nonzero;
    double v;
    const char *p = real_shape(word, &nonzero);
    /* the shape first, so strtod's extras (hex, inf, nan, blanks) never get in */
    if (p == NULL)
        return MS_ERR_NOT_A_NUMBER;
    if (!parse_short_decimal(word, &v)) {
        v = strtod(word, &end);
        if (end != p)
            return MS_ERR_NOT_A_NUMBER;
    }
    if (!(v >= -DBL_MAX && v <= DBL_MAX))
        return MS_ERR_OUT_OF_RANGE; /* overflow: +-HUGE_VAL */
    if (nonzero && v < DBL_MIN && v > -DBL_MIN)
        return MS_ERR_UNDERFLOW; /* 0 or a subnormal for a word that is not 0 */
    *out = v;
    return MS_OK;
}

/* Sign of |word| - mag for a validated decimal word and a whole number mag, exactly (the word's
 * digits are compared, not its rounded value). */
static int compare_magnitude(const char *word, uint32_t mag)
{
    uint32_t whole;
    int over, frac;
    decimal_floor(word, &whole, &over, &frac);
    if (over || whole > mag)
        return 1;
    if (whole < mag)
        return -1;
    return frac;
}

/* 1 when limit is a whole number below 2^31 in magnitude, with its magnitude in *mag. */
static int whole_limit(double limit, uint32_t *mag)
{
    if (!(limit > -2147483648.0 && limit < 2147483648.0))
        return 0;
    if ((double)(int32_t)limit != limit || limit == 0)
        return 0;
    *mag = limit < 0 ? (uint32_t)(-(int32_t)limit) : (uint32_t)limit;
    return 1;
}

motion_status_t text_parse_real(const char *word, double lo, double hi, double *out)
{
    double v;
    uint32_t mag;
    motion_status_t st = text_scan_real(word, &v);
    if (st != MS_OK)
        return st;
    /* NaN limits fail both comparisons */
    if (!(v >= lo && v <= hi))
        return MS_ERR_OUT_OF_RANGE;
    /* rounded onto a limit: the decimal itself may lie beyond it */
    if (v == hi && whole_limit(hi, &mag) && (hi > 0 ? compare_magnitude(word, mag) > 0 : compare_magnitude(word, mag) < 0))
        return MS_ERR_OUT_OF_RANGE;
    if (v == lo && whole_limit(lo, &mag) && (lo < 0 ? compare_magnitude(word, mag) > 0 : compare_magnitude(word, mag) < 0))
        return MS_ERR_OUT_OF_RANGE;
    *out = v;
    return MS_OK;
}

int text_word_is(const char *word, const char *name)
{
    while (*word != '\0' && *word == *name) {
        word++;
        name++;
    }
    return *word == '\0' && *name == '\0';
}
