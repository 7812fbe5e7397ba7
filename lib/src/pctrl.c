/* pctrl.c - proportional position controller (see pctrl.h). */
#include "pctrl.h"

motion_status_t pctrl_set_kp(pctrl_t *c, float kp_pct_per_count)
{
    if (c == 0)
        return MS_ERR_NULL;
    /* x - x is 0 for finite x and NaN for NaN or infinity */
    if (!(kp_pct_per_count - kp_pct_per_count == 0.0f))
        return MS_ERR_NOT_FINITE;
    if (kp_pct_per_count < 0.0f)
        return MS_ERR_GAIN_NEGATIVE;
    c->kp_pct_per_count = kp_pct_per_count;
    return MS_OK;
}

motion_status_t pctrl_init(pctrl_t *c, float kp_pct_per_count)
{
    if (c == 0)
        return MS_ERR_NULL;
    c->kp_pct_per_count = 0.0f;
    return pctrl_set_kp(c, kp_pct_per_count);
}

int32_t pctrl_error_counts(int32_t setpoint_counts, int32_t measured_counts)
{
    uint32_t d = (uint32_t)setpoint_counts - (uint32_t)measured_counts;
    /* two's complement reinterpretation without implementation-defined conversion */
    if (d <= (uint32_t)INT32_MAX)
        return (int32_t)d;
    return -(int32_t)(~d) - 1;
}

float pctrl_duty_pct(const pctrl_t *c, int32_t setpoint_counts, int32_t measured_counts)
{
    return pctrl_kp_duty_pct(c->kp_pct_per_count, setpoint_counts, measured_counts);
}

float pctrl_kp_duty_pct(float kp_pct_per_count, int32_t setpoint_counts, int32_t measured_counts)
{
    float duty = kp_pct_per_count * (float)pctrl_error_counts(setpoint_counts, measured_counts);
    if (duty > PCTRL_DUTY_MAX_PCT)
        return PCTRL_DUTY_MAX_PCT;
    if (duty < -PCTRL_DUTY_MAX_PCT)
        return -PCTRL_DUTY_MAX_PCT;
    return duty;
}
