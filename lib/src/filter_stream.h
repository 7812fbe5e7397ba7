/* filter_stream.h - the numbers of the MovingAverageFilter sketch's serial stream, shared with
 * `motionsim filter --stream` so that a firmware capture and the simulator can be compared byte
 * for byte. Pure formatting, no stdio: integers in, text out.
 *
 *   line:  t_ms,u,y        e.g. "4500,5.000,2.500000"
 *     t_ms  k * 10: the scheduled time of sample k in ms since the first sample (not millis())
 *     u     the input sample the filter used, in volts with 3 decimals (exact: q = 1 mV)
 *     y     the output y[k] in volts with 6 decimals: round(1e6 * y) in integers (accdec_milli_quanta)
 *   A0:    ADC code 0..1023 -> mV = round(code * 5000 / 1023) (code 1023 = 5.000 V, AVcc = 5 V)
 * Cost on the AVR: about 1,600 cycles per line (digits by subtraction, no division).
 */
#ifndef FILTER_STREAM_H
#define FILTER_STREAM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FSTREAM_LINE_MAX 31 /* "4294967295,-32.767,-32.767000" is 29 characters */
#define FSTREAM_HEADER "t_ms,u,y"

/* mV for a 10-bit ADC code referred to 5 V (codes above 1023 count as 1023). */
int16_t fstream_adc10_to_mv(uint16_t code);

/* Writes "t_ms,u,y" for one sample into buf (at least FSTREAM_LINE_MAX + 1 bytes, NUL-terminated,
 * no line end) and returns its length. */
uint8_t fstream_format(char *buf, uint32_t t_ms, int16_t u_mv, int32_t y_uv);

#ifdef __cplusplus
}
#endif

#endif
