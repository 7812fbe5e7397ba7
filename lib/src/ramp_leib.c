/* ramp_leib.c - the lab's Leib ramp in float (see ramp_leib.h). */
#include "ramp_leib.h"

#include <math.h>

motion_status_t ramp_leib_plan(ramp_leib_t *l, const ramp_params_t *params, uint32_t steps_total)
{
    motion_status_t st;
    ramp_leib_t n;
    float v0, a, f;
    if (l == 0)
        return MS_ERR_NULL;
    st = ramp_params_check(params);
    if (st != MS_OK)
        return st;
    v0 = (float)params->v0_sps;
    a = (float)params->accel_sps2;
    f = (float)params->tick_hz;
    /* steps 1-2 */
    ramp_accel_steps(v0, (float)params->vmax_sps, a, steps_total, &n.peak_sps, &n.accel_steps);
    /* steps 3-5: eqs. (6), (7), (8) */
    n.p1 = f / sqrtf(v0 * v0 + 2.0f * a);
    n.ps = f / n.peak_sps;
    if (n.p1 < n.ps)
        n.p1 = n.ps;
    n.r = a / (f * f);
    /* the longest interval must fit a 32-bit tick count (as a float below 2^32) */
    if (!(n.p1 < 4294967296.0f))
        return MS_ERR_INTERVAL_TOO_LONG;
    n.p = n.p1;
    *l = n;
    return MS_OK;
}

/* the IEEE pattern of a float as a signed integer: for finite floats, of which at least one is
 * positive, a < b exactly when float_bits(a) < float_bits(b); an integer compare costs a tenth of a
 * float compare on the AVR */
static int32_t float_bits(float x)
{
    union {
        float f;
        int32_t i;
    } v;
    v.f = x;
    return v.i;
}

float ramp_leib_update(ramp_leib_t *l, ramp_phase_t phase)
{
    float m, q, p;
    if (phase == RAMP_ACCEL)
        m = -l->r; /* eq. (9) */
    else if (phase == RAMP_DECEL)
        m = l->r; /* eq. (10) */
    else
        return l->p; /* eq. (11): m = 0 leaves p as it is */
    p = l->p;
    q = m * p * p;                          /* eq. (12) */
    p = p * (1.0f + q + 1.5f * q * q);      /* eq. (13) */
    if (float_bits(p) > float_bits(l->p1)) /* step 6d: p > p1 (both positive: the bit patterns order alike) */
        p = l->p1;
    l->p = p;
    return p;
}
