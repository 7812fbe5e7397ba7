/* filter_stream.c - stream line formatting and ADC scaling (see filter_stream.h). */
#include "filter_stream.h"

int16_t fstream_adc10_to_mv(uint16_t code)
{
    if (code > 1023u)
        code = 1023u;
    /* 1023 is odd and 10000 * code even, so code * 5000 / 1023 is never exactly halfway. */
    return (int16_t)(((uint32_t)code * 5000u + 511u) / 1023u);
}

/* Writes v (>= 0) in decimal; returns the number of characters. */
static uint8_t put_uint(char *p, uint32_t v)
{
    char tmp[10];
    uint8_t n = 0, i;
    do {
        tmp[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0);
    for (i = 0; i < n; i++)
        p[i] = tmp[n - 1 - i];
    return n;
}

/* Writes value / 10^decimals with exactly `decimals` digits after the point. */
static uint8_t put_fixed(char *p, int32_t value, uint8_t decimals)
{
    uint32_t mag = value < 0 ? (uint32_t)0 - (uint32_t)value : (uint32_t)value;
    uint32_t scale = 1;
    uint8_t n = 0, i;
    for (i = 0; i < decimals; i++)
        scale *= 10u;
    if (value < 0)
        p[n++] = '-';
    n = (uint8_t)(n + put_uint(p + n, mag / scale));
    p[n++] = '.';
    mag %= scale;
    for (i = decimals; i > 0; i--) {
        p[n + i - 1] = (char)('0' + mag % 10u);
        mag /= 10u;
    }
    return (uint8_t)(n + decimals);
}

uint8_t fstream_format(char *buf, uint32_t t_ms, int16_t u_mv, int32_t y_uv)
{
    uint8_t n = put_uint(buf, t_ms);
    buf[n++] = ',';
    n = (uint8_t)(n + put_fixed(buf + n, u_mv, 3));
    buf[n++] = ',';
    n = (uint8_t)(n + put_fixed(buf + n, y_uv, 6));
    buf[n] = '\0';
    return n;
}
