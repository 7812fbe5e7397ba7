/* filter_stream.c - stream line formatting and ADC scaling (see filter_stream.h). */
#include "filter_stream.h"

int16_t fstream_adc10_to_mv(uint16_t code)
{
    if (code > 1023u)
        code = 1023u;
    /* 1023 is odd and 10000 * code even, so code * 5000 / 1023 is never exactly halfway. */
    return (int16_t)(((uint32_t)code * 5000u + 511u) / 1023u);
}

static const uint32_t pow10_table[10] = {1000000000ul, 100000000ul, 10000000ul, 1000000ul, 100000ul,
                                         10000ul,      1000ul,      100ul,      10ul,      1ul};

/* Writes mag in decimal with at least decimals + 1 digits and, when decimals > 0, a '.' before
 * the last `decimals` of them. Digits by repeated subtraction: no 32-bit division, which costs
 * about 600 cycles each on the AVR (the whole line is then about 1,500 cycles instead of 12,000). */
static uint8_t put_digits(char *p, uint32_t mag, uint8_t decimals)
{
    uint8_t n = 0, i, started = 0;
    for (i = 0; i < 10; i++) {
        uint8_t left = (uint8_t)(10 - i); /* digits from this one to the end */
        char d = '0';
        while (mag >= pow10_table[i]) {
            mag -= pow10_table[i];
            d++;
        }
        if (d != '0' || left <= decimals + 1)
            started = 1;
        if (!started)
            continue;
        if (decimals > 0 && left == decimals)
            p[n++] = '.';
        p[n++] = d;
    }
    return n;
}

static uint8_t put_signed(char *p, int32_t value, uint8_t decimals)
{
    uint8_t n = 0;
    uint32_t mag = (uint32_t)value;
    if (value < 0) {
        p[n++] = '-';
        mag = (uint32_t)0 - mag;
    }
    return (uint8_t)(n + put_digits(p + n, mag, decimals));
}

uint8_t fstream_format(char *buf, uint32_t t_ms, int16_t u_mv, int32_t y_uv)
{
    uint8_t n = put_digits(buf, t_ms, 0);
    buf[n++] = ',';
    n = (uint8_t)(n + put_signed(buf + n, u_mv, 3));
    buf[n++] = ',';
    n = (uint8_t)(n + put_signed(buf + n, y_uv, 6));
    buf[n] = '\0';
    return n;
}
