/* duty_pwm.h - PWM duty in percent -> the 8-bit analogWrite value and the polarity an H-bridge
 * needs (sign-magnitude drive, as on the Arduino Motor Shield R3: PWM on the enable pin, DIR
 * selects the polarity). Shared by the sketches and motionsim, so the simulated motor sees the
 * same 1/255 duty steps as the real one.
 *
 *   pwm = round(min(|duty|, 100) x 255 / 100)   (0..255, half up; NaN counts as 0)
 *   forward = duty >= 0 (DIR high)               applied duty = +-pwm x 100 / 255 %
 * analogWrite(pin, pwm) on the Mega's 490 Hz phase-correct timers gives exactly pwm/255 high
 * time (0 = always low, 255 = always high). Float arithmetic on every platform.
 * Cost on the ATmega2560: two float multiply/divides and a conversion (~100 us worst case).
 */
#ifndef DUTY_PWM_H
#define DUTY_PWM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define DUTY_PWM_MAX 255

typedef struct {
    uint8_t pwm;     /* 0..255: analogWrite value on the bridge's enable (PWM) pin */
    uint8_t forward; /* 1: DIR high (positive duty, counts increase); 0: DIR low */
} duty_pwm_t;

duty_pwm_t duty_pwm_from_pct(float duty_pct);

/* The mean duty the bridge applies for p, in % (-100..+100): what the motor sees. */
float duty_pwm_applied_pct(duty_pwm_t p);

#ifdef __cplusplus
}
#endif

#endif
