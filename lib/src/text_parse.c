/* text_parse.c - strict word and number parsing (see text_parse.h). */
#include "text_parse.h"

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

motion_status_t text_parse_real(const char *word, double lo, double hi, double *out)
{
    const char *p = word;
    char *end = 0;
    int digits = 0;
    double v;
    /* validate the shape first, so strtod's extras (hex, inf, nan, blanks) never get in */
    if (*p == '+' || *p == '-')
        p++;
    while (is_digit(*p)) {
        p++;
        digits++;
    }
    if (*p == '.') {
        p++;
        while (is_digit(*p)) {
            p++;
            digits++;
        }
    }
    if (digits == 0)
        return MS_ERR_NOT_A_NUMBER;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            p++;
        if (!is_digit(*p))
            return MS_ERR_NOT_A_NUMBER;
        while (is_digit(*p))
            p++;
    }
    if (*p != '\0')
        return MS_ERR_NOT_A_NUMBER;
    if (!parse_short_decimal(word, &v)) {
        v = strtod(word, &end);
        if (end != p)
            return MS_ERR_NOT_A_NUMBER;
    }
    /* overflow gives +-HUGE_VAL; NaN fails both comparisons */
    if (!(v >= lo && v <= hi))
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
