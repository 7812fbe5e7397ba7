/* exp_filter.h - exponential acceleration/deceleration filter (the moving-average-filter note, kind 1: the RC circuit):
 * the exact zero-order-hold discretisation of G(s) = 1/(tau s + 1),
 *
 *     y[k] = a y[k-1] + (1 - a) u[k-1],   a = e^(-Ts/tau) = e^(-1/N),  N = tau/Ts (whole, as for
 *     the moving averages, so one tau is valid for every kind)
 *
 * Step response at the samples: y[k] = A (1 - a^k) for a step of A at k = 0. Same delay convention
 * as ma_filter.h: y[k] depends on u[k-1], u[k-2], ..., not on u[k].
 *
 * Fixed point, bit-identical on the Mega and the host: y is an int32 count of q/65536
 * (q = input quantum), the gain c = 1 - a is round(2^31 (1 - e^(-1/N))), computed from N with
 * integer arithmetic only, and each update y += c (u - y) keeps the remainder of its division
 * (error feedback), so rounding never accumulates and never stalls: y stays within one
 * q/65536 of the exact recurrence with gain c, and settles on a constant input exactly.
 * |c - (1 - a)| <= 2^-32 adds at most A N / (e 2^32) (0.4 uV for the filter note's 5 V, N = 900).
 * AVR cost: one 64-bit multiply, about 870 cycles per sample through accdec_step() (simavr, -Os);
 * exp_filter_gain_q31() about 10,000 cycles (only when tau changes).
 */
#ifndef EXP_FILTER_H
#define EXP_FILTER_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define EXP_FILTER_FRAC_BITS 16 /* y = q * y_frac / 65536 */

typedef struct {
    int32_t y_frac;    /* y[k] in q/65536 */
    uint32_t rem;      /* remainder of the last update, in 2^-31 of q/65536 */
    uint32_t gain_q31; /* c = 1 - e^(-1/N), in 2^-31 */
} exp_filter_t;

/* round(2^31 (1 - e^(-1/N))) by an integer series (no floating point, same result everywhere).
 * MS_ERR_NULL, MS_ERR_TAU_BELOW_TS (taps = 0), or MS_OK. */
motion_status_t exp_filter_gain_q31(uint16_t taps, uint32_t *gain_q31);

/* Starts at rest (y = 0) with a gain from exp_filter_gain_q31. MS_ERR_NULL, MS_ERR_OUT_OF_RANGE
 * (gain 0 or above the N = 1 value), or MS_OK; *f untouched on error. */
motion_status_t exp_filter_init(exp_filter_t *f, uint32_t gain_q31);

/* Back to rest. */
void exp_filter_reset(exp_filter_t *f);

/* y[k] in q/65536 for the current instant k (before u[k] is given). */
int32_t exp_filter_frac(const exp_filter_t *f);

/* One sample: returns y[k] in q/65536, then takes u = u[k]. */
int32_t exp_filter_step(exp_filter_t *f, int16_t u);

#ifdef __cplusplus
}
#endif

#endif
