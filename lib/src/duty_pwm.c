/* duty_pwm.c - duty % -> 8-bit PWM value + polarity (see duty_pwm.h). */
#include "duty_pwm.h"

duty_pwm_t duty_pwm_from_pct(float duty_pct)
{
    duty_pwm_t p;
    float m = duty_pct < 0.0f ? -duty_pct : duty_pct;
    p.forward = (uint8_t)!(duty_pct < 0.0f);
    if (!(m > 0.0f)) /* 0 and NaN */
        m = 0.0f;
    if (m > 100.0f)
        m = 100.0f;
    p.pwm = (uint8_t)(m * 255.0f / 100.0f + 0.5f);
    return p;
}

float duty_pwm_applied_pct(duty_pwm_t p)
{
    float d = (float)p.pwm * 100.0f / 255.0f;
    return p.forward ? d : -d;
}
