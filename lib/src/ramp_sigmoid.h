/* ramp_sigmoid.h - the sigmoid S-curve speed table of the S-curve article (CalculateSModelLine): a logistic
 * curve stretched from fmin to fmax over len entries,
 *   freq[i]   = fmin + (fmax - fmin) / (1 + exp(-flex * (i - len/2) / (len/2))),   i in [0, len)
 *   period[i] = (uint16_t)(timer_hz / freq[i])   (truncated, as the S-curve article does; must fit 16 bits)
 * Each entry is held for `hold` timer periods, i.e. `hold` steps (the article's ISR loads the next
 * entry on every 4th interrupt: hold = 4); deceleration walks the table backwards. flex sets the
 * shape: near 0 almost linear in i, 4-6 the article's "ideal", larger a steeper middle.
 * Acceleration takes len*hold steps and hold * sum(period)/timer_hz seconds. A move of D steps
 * uses entry min((k-1)/hold, len-1) for step n, k = min(n, D+1-n), so short moves stop climbing
 * the table half-way and the last step always mirrors the first; between the two ramps the
 * speed stays at the last entry (cruise). Units: Hz = steps/s, periods in timer ticks.
 * Float arithmetic as in the article, with one change: exp() is our own ramp_sigmoid_exp (built from
 * +, -, *, / only), because libm's expf and avr-libc's exp differ in the last bit and that moved
 * truncated periods by a tick; now the host and the Mega compute the same table, bit for bit.
 * Cost on the AVR: filling the table ~6,500 cycles per entry (once per parameter change);
 * per step an index update and a table read (integer only).
 */
#ifndef RAMP_SIGMOID_H
#define RAMP_SIGMOID_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint16_t len;      /* table entries, >= 2 */
    uint16_t hold;     /* steps (timer periods) per entry, >= 1 */
    float fmin_hz;     /* start/stop frequency, >= timer_hz/65535 */
    float fmax_hz;     /* > fmin, <= timer_hz */
    float flex;        /* > 0 */
    uint32_t timer_hz; /* timer ticks per second, > 0 (the article: 10 MHz) */
} ramp_sigmoid_params_t;

/* Checks, in this order: finite values, len >= 2, hold >= 1, flex > 0, timer_hz > 0,
 * fmax > fmin, fmin >= timer_hz/65535 (MS_ERR_FMIN_TOO_LOW: the article's "fre_min can't be less
 * than 152" at 10 MHz), and every period[i] within 1..65535 (MS_ERR_PERIOD_OUT_OF_RANGE). */
motion_status_t ramp_sigmoid_check(const ramp_sigmoid_params_t *p);

/* e^x in float from IEEE +, -, *, / only (same bits on every IEEE platform), within 2 ulp of the
 * true value for normal results; +inf above 88.5, 0 below -87. */
float ramp_sigmoid_exp(float x);

/* freq[i] by the article's formula, Hz (no checks). */
float ramp_sigmoid_freq_hz(const ramp_sigmoid_params_t *p, uint16_t i);

/* period[i] = timer_hz/freq[i] truncated to an integer (no checks; may exceed 16 bits when the
 * parameters are bad: that is what ramp_sigmoid_check looks at). */
uint32_t ramp_sigmoid_period_ticks(const ramp_sigmoid_params_t *p, uint16_t i);

/* Fills period[0..len) after ramp_sigmoid_check; MS_ERR_BUFFER_TOO_SMALL if capacity < len.
 * On error the table is untouched. */
motion_status_t ramp_sigmoid_fill(const ramp_sigmoid_params_t *p, uint16_t *period, uint16_t capacity);

/* Steps of one acceleration ramp: len * hold. */
uint32_t ramp_sigmoid_accel_steps(const ramp_sigmoid_params_t *p);

/* Duration of one acceleration ramp through a filled table: hold * sum(period) / timer_hz, s. */
double ramp_sigmoid_accel_time_s(const ramp_sigmoid_params_t *p, const uint16_t *period);

/* Stepping through a table (used by ramp.h). */
typedef struct {
    const uint16_t *period; /* the caller's table, len entries; must outlive the move */
    uint16_t len;
    uint16_t hold;
    uint32_t k;     /* min(n, D + 1 - n) of the current step */
    uint32_t entry; /* (k - 1) / hold, kept without dividing */
    uint16_t phase; /* (k - 1) % hold */
} ramp_sigmoid_t;

/* Prepares stepping through `period` (checked parameters, filled table). */
motion_status_t ramp_sigmoid_plan(ramp_sigmoid_t *s, const ramp_sigmoid_params_t *p, const uint16_t *period,
                                  uint16_t table_len);

/* Moves k one step up (+1) or down (-1) and returns the period of the new entry. */
uint16_t ramp_sigmoid_move_k(ramp_sigmoid_t *s, int8_t dk);

/* Sets k directly (for jumps), returns the period of its entry. k >= 1. */
uint16_t ramp_sigmoid_set_k(ramp_sigmoid_t *s, uint32_t k);

#ifdef __cplusplus
}
#endif

#endif
