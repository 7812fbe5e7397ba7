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
    v = strtod(word, &end);
    if (end != p)
        return MS_ERR_NOT_A_NUMBER;
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
