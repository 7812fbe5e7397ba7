/* ma2_filter.h - two-stage moving-average filter ("S-curve acceleration", the moving-average-filter note): two moving
 * averages in series, G(s) = G1(s) G2(s) with Gi(s) = (1/tau_i)(1 - e^(-tau_i s))/s, discretised
 * exactly with a zero-order hold (N1 = tau1/Ts, N2 = tau2/Ts taps). y is a velocity command in
 * the moving-average-filter note; a step of height A gives an S-shaped y: its slope (the acceleration) ramps linearly up
 * to A/max(tau1, tau2) and back, its second derivative (the jerk) is +-A/(tau1 tau2) or 0, and the
 * final value is reached tau1 + tau2 after the step.
 *
 * Exactness: stage 1's output y1 between samples is piecewise linear (a moving average of a held
 * input), so stage 2's integral over whole samples is the trapezoidal sum, exactly:
 *     y[k] = (1/N2) * sum_{i=1..N2} (y1[k-i] + y1[k-i+1]) / 2,   y1[k] = (1/N1) sum_{j=1..N1} u[k-j]
 * In integers: with S1[k] = N1*y1[k]/q and T[k] = S1[k-1] + ... + S1[k-N2],
 *     y[k] = q * (2 T[k] + S1[k] - S1[k-N2]) / (2 N1 N2)
 * kept by three running sums from one int16 ring buffer of the last N1 + N2 samples:
 *     T += S1[k] - S1[k-N2];  S1 += u[k] - u[k-N1];  S1[k-N2] += u[k-N2] - u[k-N1-N2].
 * Same delay convention as ma_filter.h (y[k] depends on u[k-1], u[k-2], ..., not on u[k]).
 * Never drifts (all sums are exact integers), O(1) per sample, 2 bytes per tap (N1 + N2 taps).
 * The order of the stages does not matter: (tau1, tau2) and (tau2, tau1) give the same output.
 * AVR cost: about 750 cycles per sample through accdec_step() (64-bit sums; simavr, -Os).
 */
#ifndef MA2_FILTER_H
#define MA2_FILTER_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int16_t *buf;    /* caller's ring buffer: the last N1 + N2 samples */
    uint16_t taps1;  /* N1 */
    uint16_t taps2;  /* N2 */
    uint16_t len;    /* N1 + N2 */
    uint16_t head;   /* index of the oldest sample, u[k-N1-N2] */
    int32_t s1;      /* S1[k]    = u[k-1] + ... + u[k-N1] */
    int32_t s1_old;  /* S1[k-N2] = u[k-N2-1] + ... + u[k-N2-N1] */
    int64_t t;       /* T[k]     = S1[k-1] + ... + S1[k-N2] */
} ma2_filter_t;

/* Starts at rest (all past samples 0) with N1 = taps1, N2 = taps2, using buf[0..N1+N2).
 * MS_ERR_NULL, MS_ERR_TAU_BELOW_TS (a tap count is 0), MS_ERR_TOO_MANY_TAPS (N1 + N2 > buf_len),
 * or MS_OK. *f and buf are untouched on error. */
motion_status_t ma2_filter_init(ma2_filter_t *f, int16_t *buf, uint16_t buf_len, uint16_t taps1, uint16_t taps2);

/* Back to rest. */
void ma2_filter_reset(ma2_filter_t *f);

/* 2 N1 N2 y[k] / q for the current instant k (before u[k] is given). */
int64_t ma2_filter_num(const ma2_filter_t *f);

/* The denominator 2 N1 N2 (< 2^31): y = q * num / den. */
uint32_t ma2_filter_den(const ma2_filter_t *f);

/* One sample: returns 2 N1 N2 y[k] / q, then takes u = u[k] into the history. */
int64_t ma2_filter_step(ma2_filter_t *f, int16_t u);

#ifdef __cplusplus
}
#endif

#endif
