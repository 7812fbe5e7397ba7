/* ramp_exact.c - step times of true constant acceleration, double precision (see ramp_exact.h). */
#include "ramp_exact.h"

#include <math.h>

/* speed after x steps of acceleration from v0 */
static double speed_at(const ramp_exact_t *e, double x)
{
    return sqrt(e->v0_sps * e->v0_sps + 2.0 * e->accel_sps2 * x);
}

/* time to accelerate from x1 to x2 (0 <= x1 <= x2 <= x_a): (s2 - s1)/a = 2 (x2 - x1)/(s1 + s2) */
static double accel_duration(const ramp_exact_t *e, double x1, double x2)
{
    double sum = speed_at(e, x1) + speed_at(e, x2);
    return sum > 0.0 ? 2.0 * (x2 - x1) / sum : 0.0;
}

/* time from position x1 to x2 (0 <= x1 <= x2 <= D), piece by piece */
static double duration(const ramp_exact_t *e, double x1, double x2)
{
    double d = (double)e->steps_total;
    double cruise_end = d - e->x_accel;
    double total = 0.0, lo, hi;
    hi = x2 < e->x_accel ? x2 : e->x_accel;
    if (hi > x1)
        total += accel_duration(e, x1, hi);
    lo = x1 > e->x_accel ? x1 : e->x_accel;
    hi = x2 < cruise_end ? x2 : cruise_end;
    if (hi > lo)
        total += (hi - lo) / e->peak_sps;
    lo = x1 > cruise_end ? x1 : cruise_end;
    if (x2 > lo)
        total += accel_duration(e, d - x2, d - lo); /* the mirror image of the acceleration */
    return total;
}

motion_status_t ramp_exact_plan(ramp_exact_t *e, const ramp_params_t *params, uint32_t steps_total)
{
    motion_status_t st;
    ramp_exact_t n;
    double s_full, d = (double)steps_total;
    if (e == 0)
        return MS_ERR_NULL;
    st = ramp_params_check(params);
    if (st != MS_OK)
        return st;
    n.v0_sps = params->v0_sps;
    n.accel_sps2 = params->accel_sps2;
    n.tick_hz = (double)params->tick_hz;
    n.steps_total = steps_total;
    s_full = (params->vmax_sps * params->vmax_sps - params->v0_sps * params->v0_sps) / (2.0 * params->accel_sps2);
    if (2.0 * s_full >= d) {
        n.x_accel = d / 2.0;
        n.peak_sps = speed_at(&n, n.x_accel);
    } else {
        n.x_accel = s_full;
        n.peak_sps = params->vmax_sps;
    }
    n.t_accel_s = accel_duration(&n, 0.0, n.x_accel);
    n.t_total_s = 2.0 * n.t_accel_s;
    if (d > 2.0 * n.x_accel)
        n.t_total_s += (d - 2.0 * n.x_accel) / n.peak_sps;
    /* the longest interval is the first (= the last, by symmetry) */
    if (steps_total > 0 && !(duration(&n, 0.0, 1.0) * n.tick_hz <= 4294967295.0))
        return MS_ERR_INTERVAL_TOO_LONG;
    *e = n;
    return MS_OK;
}

double ramp_exact_time_s(const ramp_exact_t *e, uint32_t n)
{
    double x = (double)n, d = (double)e->steps_total;
    if (n == 0)
        return 0.0;
    if (x <= e->x_accel)
        return 2.0 * x / (speed_at(e, x) + e->v0_sps); /* t_n = (sqrt(v0^2 + 2an) - v0)/a */
    if (x <= d - e->x_accel)
        return e->t_accel_s + (x - e->x_accel) / e->peak_sps;
    return e->t_total_s - duration(e, x, d);
}

double ramp_exact_interval_s(const ramp_exact_t *e, uint32_t n)
{
    return duration(e, (double)n - 1.0, (double)n);
}

ramp_phase_t ramp_exact_phase(const ramp_exact_t *e, uint32_t n)
{
    double mid = (double)n - 0.5;
    if (mid < e->x_accel)
        return RAMP_ACCEL;
    if (mid > (double)e->steps_total - e->x_accel)
        return RAMP_DECEL;
    return RAMP_CRUISE;
}
