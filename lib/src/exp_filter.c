/* exp_filter.c - first-order lag in fixed point with error feedback (see exp_filter.h). */
#include "exp_filter.h"

/* The update divides by 2^31 rounding down; gcc and avr-gcc shift signed values arithmetically
 * (documented implementation-defined behaviour). Refuse to compile anywhere else. */
typedef char exp_filter_needs_arithmetic_shift[((-3) >> 1) == -2 ? 1 : -1];

#define Q62_ONE ((uint64_t)1 << 62)

motion_status_t exp_filter_gain_q31(uint16_t taps, uint32_t *gain_q31)
{
    /* 1 - e^(-x) = x - x^2/2! + x^3/3! - ...  with x = 1/N, in Q62 (2^62 = 1). Each term is the
     * previous one divided by N*i (truncated: < 1 unit of 2^-62 lost per term, about 20 terms at
     * most), far below the 2^-32 of the final rounding. */
    uint64_t term, sum;
    uint32_t i;
    int add = 0;
    if (gain_q31 == NULL)
        return MS_ERR_NULL;
    if (taps == 0)
        return MS_ERR_TAU_BELOW_TS;
    term = Q62_ONE / taps;
    sum = term;
    for (i = 2; term != 0; i++, add = !add) {
        term /= (uint64_t)taps * i;
        sum = add ? sum + term : sum - term; /* alternating, decreasing: stays in [0, 2^62] */
    }
    *gain_q31 = (uint32_t)((sum + ((uint64_t)1 << 30)) >> 31);
    return MS_OK;
}

motion_status_t exp_filter_init(exp_filter_t *f, uint32_t gain_q31)
{
    if (f == NULL)
        return MS_ERR_NULL;
    /* gain < 2^31 (c < 1) keeps |d| * gain + rem below 2^63 in exp_filter_step. */
    if (gain_q31 == 0 || gain_q31 >= ((uint32_t)1 << 31))
        return MS_ERR_OUT_OF_RANGE;
    f->gain_q31 = gain_q31;
    exp_filter_reset(f);
    return MS_OK;
}

void exp_filter_reset(exp_filter_t *f)
{
    f->y_frac = 0;
    f->rem = 0;
}

int32_t exp_filter_frac(const exp_filter_t *f)
{
    return f->y_frac;
}

int32_t exp_filter_step(exp_filter_t *f, int16_t u)
{
    int32_t y_now = f->y_frac;
    /* d = u - y in q/65536: |d| < 2^32. p = c d in 2^-31 units plus the carried remainder. */
    int64_t d = (int64_t)u * 65536 - f->y_frac;
    int64_t p = d * (int64_t)f->gain_q31 + (int64_t)f->rem;
    /* y += floor(p / 2^31); rem = p mod 2^31 in [0, 2^31). The step never passes u: for d >= 0,
     * 0 <= c d + rem' < d + 1 (c < 1, rem' < 1), so 0 <= step <= d; for d < 0, d <= c d + rem' < 1,
     * so d <= step <= 0. y stays between its inputs (int16 * 65536), so the new y fits int32
     * (the step alone may not: up to 0.63 * 2^32 for N = 1). */
    f->y_frac = (int32_t)((int64_t)f->y_frac + (p >> 31));
    f->rem = (uint32_t)(p & 0x7FFFFFFF);
    return y_now;
}
