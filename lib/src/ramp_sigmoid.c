/* ramp_sigmoid.c - the S-curve article's sigmoid S-curve period table and stepping through it (see ramp_sigmoid.h). */
#include "ramp_sigmoid.h"


static int sig_is_finite(float x)
{
    return (x - x) == 0.0f;
}

float ramp_sigmoid_exp(float x)
{
    /* e^x = 2^k e^r with k = round(x/ln 2) and r = x - k ln 2 (Cody-Waite: ln 2 split so that
     * k*LN2_HI is exact), |r| <= 0.35, e^r by its Taylor series to r^7 (remainder < 6e-9) */
    const float ln2_hi = 0.693145751953125f, ln2_lo = 1.42860677e-06f;
    float n, r, e;
    int16_t k;
    union {
        float f;
        uint32_t u;
    } scale;
    if (x > 88.5f)
        return 3.0e38f * 10.0f; /* overflows to +inf, as expf does */
    if (x < -87.0f)
        return 0.0f; /* below the normal range */
    n = x * 1.44269504f;
    k = (int16_t)(n >= 0.0f ? n + 0.5f : n - 0.5f);
    r = (x - (float)k * ln2_hi) - (float)k * ln2_lo;
    e = 1.0f + r * (1.0f + r * (0.5f + r * (1.0f / 6.0f + r * (1.0f / 24.0f +
        r * (1.0f / 120.0f + r * (1.0f / 720.0f + r * (1.0f / 5040.0f)))))));
    scale.u = (uint32_t)(k + 127) << 23; /* 2^k, exact; k is within -126..128 here */
    if (k > 127)
        return e * 2.0f * 1.70141183e38f; /* 2^128 does not fit one float */
    return e * scale.f;
}

float ramp_sigmoid_freq_hz(const ramp_sigmoid_params_t *p, uint16_t i)
{
    /* the S-curve article's order of operations, in float: melo = flexible*(i - len/2)/(len/2) */
    float len = (float)p->len;
    float half = len / 2.0f;
    float melo = p->flex * ((float)i - half) / half;
    float deno = 1.0f / (1.0f + ramp_sigmoid_exp(-melo));
    return (p->fmax_hz - p->fmin_hz) * deno + p->fmin_hz;
}

uint32_t ramp_sigmoid_period_ticks(const ramp_sigmoid_params_t *p, uint16_t i)
{
    float period = (float)p->timer_hz / ramp_sigmoid_freq_hz(p, i);
    if (!(period >= 0.0f && period < 4294967296.0f))
        return UINT32_MAX; /* NaN, negative or too long: out of any timer's range */
    return (uint32_t)period;
}

motion_status_t ramp_sigmoid_check(const ramp_sigmoid_params_t *p)
{
    uint32_t first, last;
    if (p == 0)
        return MS_ERR_NULL;
    if (!sig_is_finite(p->fmin_hz) || !sig_is_finite(p->fmax_hz) || !sig_is_finite(p->flex))
        return MS_ERR_NOT_FINITE;
    if (p->len < 2)
        return MS_ERR_LEN_TOO_SHORT;
    if (p->hold < 1)
        return MS_ERR_HOLD_ZERO;
    if (!(p->flex > 0.0f))
        return MS_ERR_FLEX_NOT_POSITIVE;
    if (p->timer_hz == 0)
        return MS_ERR_TICK_HZ_ZERO;
    if (!(p->fmax_hz > p->fmin_hz))
        return MS_ERR_FMAX_NOT_ABOVE_FMIN;
    if (p->fmin_hz < (float)p->timer_hz / 65535.0f)
        return MS_ERR_FMIN_TOO_LOW;
    /* freq rises with i, so the periods fall: the first is the longest, the last the shortest */
    first = ramp_sigmoid_period_ticks(p, 0);
    last = ramp_sigmoid_period_ticks(p, (uint16_t)(p->len - 1U));
    if (first > 65535UL || last < 1UL)
        return MS_ERR_PERIOD_OUT_OF_RANGE;
    return MS_OK;
}

motion_status_t ramp_sigmoid_fill(const ramp_sigmoid_params_t *p, uint16_t *period, uint16_t capacity)
{
    motion_status_t st = ramp_sigmoid_check(p);
    uint16_t i;
    if (st != MS_OK)
        return st;
    if (period == 0)
        return MS_ERR_NULL;
    if (capacity < p->len)
        return MS_ERR_BUFFER_TOO_SMALL;
    for (i = 0; i < p->len; i++)
        period[i] = (uint16_t)ramp_sigmoid_period_ticks(p, i);
    return MS_OK;
}

uint32_t ramp_sigmoid_accel_steps(const ramp_sigmoid_params_t *p)
{
    return (uint32_t)p->len * (uint32_t)p->hold;
}

double ramp_sigmoid_accel_time_s(const ramp_sigmoid_params_t *p, const uint16_t *period)
{
    uint32_t sum = 0; /* at most 65535 entries of at most 65535 ticks: fits 32 bits */
    uint16_t i;
    for (i = 0; i < p->len; i++)
        sum += period[i];
    return (double)p->hold * (double)sum / (double)p->timer_hz;
}

motion_status_t ramp_sigmoid_plan(ramp_sigmoid_t *s, const ramp_sigmoid_params_t *p, const uint16_t *period,
                                  uint16_t table_len)
{
    motion_status_t st;
    if (s == 0)
        return MS_ERR_NULL;
    st = ramp_sigmoid_check(p);
    if (st != MS_OK)
        return st;
    if (period == 0 || table_len < p->len)
        return MS_ERR_TABLE_MISSING;
    s->period = period;
    s->len = p->len;
    s->hold = p->hold;
    s->k = 0;
    s->entry = 0;
    s->phase = 0;
    return MS_OK;
}

static uint16_t entry_period(const ramp_sigmoid_t *s)
{
    return s->period[s->entry < s->len ? s->entry : (uint32_t)s->len - 1U];
}

uint16_t ramp_sigmoid_move_k(ramp_sigmoid_t *s, int8_t dk)
{
    if (dk > 0) {
        if (s->k == 0) {
            s->k = 1; /* entry 0, phase 0 */
        } else {
            s->k++;
            if (++s->phase == s->hold) {
                s->phase = 0;
                s->entry++;
            }
        }
    } else if (dk < 0 && s->k > 1) {
        s->k--;
        if (s->phase == 0) {
            s->phase = (uint16_t)(s->hold - 1U);
            s->entry--;
        } else {
            s->phase--;
        }
    }
    return entry_period(s);
}

uint16_t ramp_sigmoid_set_k(ramp_sigmoid_t *s, uint32_t k)
{
    s->k = k;
    s->entry = (k - 1U) / s->hold;
    s->phase = (uint16_t)((k - 1U) % s->hold);
    return entry_period(s);
}
