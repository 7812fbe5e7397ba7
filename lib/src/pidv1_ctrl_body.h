/* pidv1_ctrl_body.h - the one implementation of pidv1_ctrl.h, included twice by pidv1_ctrl.c with
 *   PID_REAL  the number type (double or float)
 *   PID_FN(x) the function name for x (pid_##x or pidf_##x)
 *   PID_T     the state type (pid_ctrl_t or pidf_ctrl_t)
 * Not a header of its own: no include guard on purpose.
 *
 * Every expression follows PID_v1 1.2.1's order of evaluation, because the last bit depends on
 * it: P + (I - D) rather than (P + I) - D, and ki scaled by (Ki*0.1)*0.2 after SetSampleTime(20)
 * rather than Ki*0.02. Constants are written as integers so that they take PID_REAL's type.
 */

/* PID_v1's clamp: "greater than max -> max, else less than min -> min" (NaN passes through). */
static PID_REAL PID_FN(clamp_)(PID_REAL v, PID_REAL lo, PID_REAL hi)
{
    if (v > hi)
        return hi;
    if (v < lo)
        return lo;
    return v;
}

/* Initialize(): on a MANUAL -> AUTOMATIC transition. */
static void PID_FN(initialize_)(PID_T *c)
{
    c->output_sum = *c->output;
    c->last_input = *c->input;
    c->output_sum = PID_FN(clamp_)(c->output_sum, c->out_min, c->out_max);
}

motion_status_t PID_FN(set_tunings_pon)(PID_T *c, PID_REAL kp, PID_REAL ki, PID_REAL kd, int32_t p_on)
{
    PID_REAL sample_time_s;
    if (kp < 0 || ki < 0 || kd < 0)
        return MS_ERR_GAIN_NEGATIVE;
    c->p_on = p_on;
    c->p_on_e = (uint8_t)(p_on == PID_P_ON_E);
    c->disp_kp = kp;
    c->disp_ki = ki;
    c->disp_kd = kd;
    sample_time_s = ((PID_REAL)c->sample_time_ms) / 1000;
    c->kp = kp;
    c->ki = ki * sample_time_s;
    c->kd = kd / sample_time_s;
    if (c->direction == PID_REVERSE) {
        c->kp = (0 - c->kp);
        c->ki = (0 - c->ki);
        c->kd = (0 - c->kd);
    }
    return MS_OK;
}

motion_status_t PID_FN(set_tunings)(PID_T *c, PID_REAL kp, PID_REAL ki, PID_REAL kd)
{
    return PID_FN(set_tunings_pon)(c, kp, ki, kd, c->p_on);
}

void PID_FN(set_direction)(PID_T *c, int32_t direction)
{
    if (c->in_auto && direction != c->direction) {
        c->kp = (0 - c->kp);
        c->ki = (0 - c->ki);
        c->kd = (0 - c->kd);
    }
    c->direction = direction;
}

motion_status_t PID_FN(set_output_limits)(PID_T *c, PID_REAL out_min, PID_REAL out_max)
{
    if (out_min >= out_max)
        return MS_ERR_LIMITS_ORDER;
    c->out_min = out_min;
    c->out_max = out_max;
    if (c->in_auto) {
        *c->output = PID_FN(clamp_)(*c->output, c->out_min, c->out_max);
        c->output_sum = PID_FN(clamp_)(c->output_sum, c->out_min, c->out_max);
    }
    return MS_OK;
}

motion_status_t PID_FN(set_sample_time)(PID_T *c, int32_t sample_time_ms)
{
    PID_REAL ratio;
    if (sample_time_ms <= 0)
        return MS_ERR_SAMPLE_TIME;
    ratio = (PID_REAL)sample_time_ms / (PID_REAL)c->sample_time_ms;
    c->ki *= ratio;
    c->kd /= ratio;
    c->sample_time_ms = (uint32_t)sample_time_ms;
    return MS_OK;
}

void PID_FN(set_mode)(PID_T *c, int32_t mode)
{
    uint8_t new_auto = (uint8_t)(mode == PID_AUTOMATIC);
    if (new_auto && !c->in_auto)
        PID_FN(initialize_)(c);
    c->in_auto = new_auto;
}

motion_status_t PID_FN(init)(PID_T *c, PID_REAL *input, PID_REAL *output, PID_REAL *setpoint, PID_REAL kp,
                             PID_REAL ki, PID_REAL kd, int32_t p_on, int32_t direction, uint32_t now_ms)
{
    motion_status_t st;
    if (c == 0 || input == 0 || output == 0 || setpoint == 0)
        return MS_ERR_NULL;
    /* The values PID_v1's members have where its constructor leaves them unset, for an object
     * with static storage (zero-initialised, the usual global `PID myPID(...)`): all 0. They
     * matter when the constructor's gains are negative (its SetTunings then returns at once):
     * pOn stays 0 = P_ON_M, so a later 3-argument SetTunings computes on measurement. */
    c->disp_kp = c->disp_ki = c->disp_kd = 0;
    c->kp = c->ki = c->kd = 0;
    c->output_sum = 0;
    c->last_input = 0;
    c->p_on = PID_P_ON_M;
    c->p_on_e = 0;
    c->direction = PID_DIRECT;

    c->output = output;
    c->input = input;
    c->setpoint = setpoint;
    c->in_auto = 0;
    c->out_min = 0; /* SetOutputLimits(0, 255) while MANUAL: only stores */
    c->out_max = 255;
    c->sample_time_ms = 100;
    PID_FN(set_direction)(c, direction);
    st = PID_FN(set_tunings_pon)(c, kp, ki, kd, p_on);
    c->last_time_ms = now_ms - c->sample_time_ms;
    return st;
}

uint8_t PID_FN(compute)(PID_T *c, uint32_t now_ms)
{
    uint32_t time_change;
    PID_REAL input, error, d_input, output;
    if (!c->in_auto)
        return 0;
    time_change = now_ms - c->last_time_ms;
    if (time_change < c->sample_time_ms)
        return 0;
    input = *c->input;
    error = *c->setpoint - input;
    d_input = (input - c->last_input);
    c->output_sum += (c->ki * error);
    if (!c->p_on_e)
        c->output_sum -= c->kp * d_input;
    c->output_sum = PID_FN(clamp_)(c->output_sum, c->out_min, c->out_max);
    if (c->p_on_e)
        output = c->kp * error;
    else
        output = 0;
    output += c->output_sum - c->kd * d_input;
    output = PID_FN(clamp_)(output, c->out_min, c->out_max);
    *c->output = output;
    c->last_input = input;
    c->last_time_ms = now_ms;
    return 1;
}

PID_REAL PID_FN(get_kp)(const PID_T *c)
{
    return c->disp_kp;
}

PID_REAL PID_FN(get_ki)(const PID_T *c)
{
    return c->disp_ki;
}

PID_REAL PID_FN(get_kd)(const PID_T *c)
{
    return c->disp_kd;
}

int32_t PID_FN(get_mode)(const PID_T *c)
{
    return c->in_auto ? PID_AUTOMATIC : PID_MANUAL;
}

int32_t PID_FN(get_direction)(const PID_T *c)
{
    return c->direction;
}
