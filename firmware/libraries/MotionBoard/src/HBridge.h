/* HBridge.h - a DC motor on one channel of an L298-type H-bridge in sign-magnitude drive, as the
 * Arduino Motor Shield R3 wires it: PWM on the channel's enable pin, DIR selects the polarity,
 * BRAKE held low. setDuty() takes -100..+100 % and goes through duty_pwm_from_pct() (lib/), the
 * same 8-bit quantisation motionsim applies to its motor model. Pins: the servo sketches define them.
 * Cost: the float duty -> PWM conversion (~50 us) plus digitalWrite/analogWrite (~10 us).
 */
#ifndef HBRIDGE_H
#define HBRIDGE_H

#include <Arduino.h>

#include <duty_pwm.h>

class HBridge {
public:
    HBridge(uint8_t pwm_pin, uint8_t dir_pin, uint8_t brake_pin) : pwm_(pwm_pin), dir_(dir_pin), brake_(brake_pin)
    {
        last_.pwm = 0;
        last_.forward = 1;
    }

    /* Outputs, brake off, motor off (PWM 0, DIR high). */
    void begin();
    /* Drives duty_pct (-100..+100, saturated; NaN = 0); returns the PWM value and polarity written.
     * On a change of polarity the PWM is set to 0 before DIR changes. */
    duty_pwm_t setDuty(float duty_pct);
    duty_pwm_t last() const { return last_; }

private:
    uint8_t pwm_, dir_, brake_;
    duty_pwm_t last_;
};

#endif
