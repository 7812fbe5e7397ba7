/* filter_param.h - the two numbers every acceleration/deceleration filter starts from (the moving-average-filter note):
 * the tap count N = tau/Ts, and the input quantum q that turns a voltage into an integer sample.
 *
 *   N = tau/Ts must be a whole number >= 1 (the moving-average-filter note: tau = 9 s, Ts = 10 ms -> N = 900). Because
 *   binary floating point rarely divides decimals exactly (2.3/0.01 = 229.99999999999997 in double,
 *   9/0.01 = 900.00002 in the Mega's float), the test is tolerant: tau/Ts is accepted when it lies within 1 ppm of a whole number, which is
 *   then used exactly. Nothing is silently rounded: tau = 9.005 s at Ts = 10 ms is rejected.
 *   Checks in this order: NaN/inf, Ts <= 0, tau < Ts, N > 65535, not whole.
 *
 *   A sample is an int16_t count of quanta in -32767..32767 (u = count * q). The host default and
 *   the MovingAverageFilter sketch use q = 1 mV, so 5 V is exactly 5000 and |u| <= 32.767 V.
 *   Rounding is to the nearest quantum, halves away from zero.
 *
 * Cost on the AVR: one float division and a few comparisons (only when parameters change).
 */
#ifndef FILTER_PARAM_H
#define FILTER_PARAM_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define FILT_MAX_TAPS 65535u       /* N fits uint16_t */
#define FILT_MAX_QUANTA 32767      /* |sample| limit, symmetric */
#define FILT_WHOLE_TOL 1e-6        /* relative tolerance of the whole-number test on tau/Ts */
#define FILT_QUANTUM_TOL 0.01      /* filt_quantise_whole: |value/q - n| allowed, in quanta */

/* N = tau/Ts. MS_ERR_NULL, MS_ERR_NOT_FINITE, MS_ERR_TS_NOT_POSITIVE, MS_ERR_TAU_BELOW_TS,
 * MS_ERR_TOO_MANY_TAPS (N > 65535), MS_ERR_TAU_NOT_MULTIPLE, or MS_OK. *taps untouched on error. */
motion_status_t filt_taps(double tau_s, double ts_s, uint16_t *taps);

/* value/quantum rounded to the nearest whole count (halves away from zero).
 * MS_ERR_NULL, MS_ERR_NOT_FINITE, MS_ERR_QUANTUM_NOT_POSITIVE, MS_ERR_INPUT_OUT_OF_RANGE
 * (|count| > 32767), or MS_OK. *count untouched on error. */
motion_status_t filt_quantise(double value, double quantum, int16_t *count);

/* As filt_quantise, but value must already be a whole number of quanta (within
 * FILT_QUANTUM_TOL quanta, which absorbs the float rounding of a decimal such as "4.999"),
 * else MS_ERR_NOT_WHOLE_QUANTUM: e.g. "u 2.0005" is refused when q = 1 mV. */
motion_status_t filt_quantise_whole(double value, double quantum, int16_t *count);

#ifdef __cplusplus
}
#endif

#endif
