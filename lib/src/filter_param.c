/* filter_param.c - tap count and input quantisation (see filter_param.h). */
#include "filter_param.h"

#include <math.h>

motion_status_t filt_taps(double tau_s, double ts_s, uint16_t *taps)
{
    double r, n;
    if (taps == NULL)
        return MS_ERR_NULL;
    if (!isfinite(tau_s) || !isfinite(ts_s))
        return MS_ERR_NOT_FINITE;
    if (!(ts_s > 0.0))
        return MS_ERR_TS_NOT_POSITIVE;
    r = tau_s / ts_s;
    if (!(r >= 1.0 - FILT_WHOLE_TOL)) /* also tau <= 0 */
        return MS_ERR_TAU_BELOW_TS;
    if (!(r < (double)FILT_MAX_TAPS + 0.5)) /* also r = inf when Ts is tiny */
        return MS_ERR_TOO_MANY_TAPS;
    n = floor(r + 0.5); /* r >= 0.999999: no halfway trap near zero */
    if (fabs(r - n) > FILT_WHOLE_TOL * n)
        return MS_ERR_TAU_NOT_MULTIPLE;
    *taps = (uint16_t)n;
    return MS_OK;
}

static motion_status_t quantise(double value, double quantum, int16_t *count, int whole_only)
{
    double r, n;
    if (count == NULL)
        return MS_ERR_NULL;
    if (!isfinite(value) || !isfinite(quantum))
        return MS_ERR_NOT_FINITE;
    if (!(quantum > 0.0))
        return MS_ERR_QUANTUM_NOT_POSITIVE;
    r = value / quantum;
    if (!(fabs(r) < (double)FILT_MAX_QUANTA + 0.5)) /* also r = inf */
        return MS_ERR_INPUT_OUT_OF_RANGE;
    n = round(r); /* halves away from zero */
    if (whole_only && fabs(r - n) > FILT_QUANTUM_TOL)
        return MS_ERR_NOT_WHOLE_QUANTUM;
    *count = (int16_t)n;
    return MS_OK;
}

motion_status_t filt_quantise(double value, double quantum, int16_t *count)
{
    return quantise(value, quantum, count, 0);
}

motion_status_t filt_quantise_whole(double value, double quantum, int16_t *count)
{
    return quantise(value, quantum, count, 1);
}
