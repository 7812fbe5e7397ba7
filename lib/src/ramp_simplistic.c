/* ramp_simplistic.c - fixed interval decrement per step, lab eqs. 1-2 (see ramp_simplistic.h). */
#include "ramp_simplistic.h"

motion_status_t ramp_simplistic_plan(ramp_simplistic_t *s, const ramp_params_t *params, uint32_t steps_total)
{
    motion_status_t st;
    ramp_simplistic_t n;
    float v0, f;
    if (s == 0)
        return MS_ERR_NULL;
    st = ramp_params_check(params);
    if (st != MS_OK)
        return st;
    if (!(params->v0_sps > 0.0))
        return MS_ERR_V0_ZERO_SIMPLISTIC;
    v0 = (float)params->v0_sps;
    f = (float)params->tick_hz;
    ramp_accel_steps(v0, (float)params->vmax_sps, (float)params->accel_sps2, steps_total, &n.peak_sps,
                     &n.accel_steps);
    /* S = 0 (vmax is less than one step of acceleration above v0) would make dp = 0 and crawl at
     * v0 for the whole move: take S = 1 instead, one step from p_max to p_min, which needs only
     * (vmax^2 - v0^2)/2 < a. Not for a one-step move: it starts and stops at v0. */
    if (n.accel_steps == 0 && steps_total >= 2U)
        n.accel_steps = 1;
    n.p_max = f / v0;
    if (!(n.p_max < 4294967296.0f))
        return MS_ERR_INTERVAL_TOO_LONG;
    n.p_min = f / n.peak_sps;
    n.dp = n.accel_steps > 0 ? (n.p_max - n.p_min) / (float)n.accel_steps : 0.0f; /* eq. (1) */
    n.p = n.p_max;
    *s = n;
    return MS_OK;
}

float ramp_simplistic_update(ramp_simplistic_t *s, ramp_phase_t phase)
{
    if (phase == RAMP_ACCEL) {
        s->p = s->p - s->dp;
    } else if (phase == RAMP_DECEL) {
        s->p = s->p + s->dp;
        if (s->p > s->p_max)
            s->p = s->p_max;
    }
    return s->p;
}
