/* ma_filter.h - moving-average acceleration/deceleration filter ("linear acceleration", the moving-average-filter note):
 * the exact zero-order-hold discretisation of G(s) = (1/tau)(1 - e^(-tau s))/s with N = tau/Ts taps,
 *
 *     y[k] = y[k-1] + (u[k-1] - u[k-1-N]) / N  =  (1/N) * (u[k-1] + u[k-2] + ... + u[k-N])
 *
 * Delay convention (the same in every filter module, motionsim and the MovingAverageFilter sketch):
 * sample k is taken at t = k*Ts and u[k] is held until (k+1)*Ts; y[k] is the exact output of G(s)
 * at the instant k*Ts, so it depends on u[k-1], u[k-2], ... and not on u[k]. A step at sample k0
 * first moves y at k0+1 and reaches its final value at exactly k0+N, tau after the step.
 *
 * Never drifts: samples are integer counts of a quantum q (filter_param.h), the state is the exact
 * integer sum of the last N samples (int32), so y = q * sum / N is the exact mean after any number
 * of samples. O(1) per sample: one add, one subtract, one store. The caller owns the ring buffer
 * (2 bytes per tap: N = 900 -> 1800 bytes). AVR cost: about 190 cycles per sample through
 * accdec_step() (simavr, -Os; see README).
 */
#ifndef MA_FILTER_H
#define MA_FILTER_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int16_t *buf;   /* caller's ring buffer: the last N samples */
    uint16_t taps;  /* N */
    uint16_t head;  /* index of the oldest sample, u[k-N] */
    int32_t sum;    /* u[k-1] + ... + u[k-N] = N * y[k] / q, exact */
} ma_filter_t;

/* Starts the filter at rest (all past samples 0) with N = taps (see filt_taps), using
 * buf[0..taps). MS_ERR_NULL, MS_ERR_TAU_BELOW_TS (taps = 0), MS_ERR_TOO_MANY_TAPS
 * (taps > buf_len), or MS_OK. *f and buf are untouched on error. */
motion_status_t ma_filter_init(ma_filter_t *f, int16_t *buf, uint16_t buf_len, uint16_t taps);

/* Back to rest: every past sample 0, y = 0. */
void ma_filter_reset(ma_filter_t *f);

/* N * y[k] / q for the current instant k (before u[k] is given). */
int32_t ma_filter_sum(const ma_filter_t *f);

/* One sample: returns N * y[k] / q (which does not depend on u), then takes u = u[k] into the
 * history, so the next call returns N * y[k+1] / q. */
int32_t ma_filter_step(ma_filter_t *f, int16_t u);

#ifdef __cplusplus
}
#endif

#endif
