/* HBridge.cpp - see HBridge.h. */
#include "HBridge.h"

void HBridge::begin()
{
    pinMode(brake_, OUTPUT);
    digitalWrite(brake_, LOW);
    pinMode(dir_, OUTPUT);
    digitalWrite(dir_, HIGH);
    pinMode(pwm_, OUTPUT);
    analogWrite(pwm_, 0);
    last_.pwm = 0;
    last_.forward = 1;
}

duty_pwm_t HBridge::setDuty(float duty_pct)
{
    duty_pwm_t p = duty_pwm_from_pct(duty_pct);
    if (p.forward != last_.forward) {
        analogWrite(pwm_, 0);
        digitalWrite(dir_, p.forward ? HIGH : LOW);
    }
    analogWrite(pwm_, p.pwm);
    last_ = p;
    return p;
}
