/* MotionPID.cpp - PID_v1's interface over pidv1_ctrl.c (see MotionPID.h). */
#include "MotionPID.h"

#ifdef ARDUINO
/* The board's default clock: Arduino's millis() (declared here, not through Arduino.h, which lib/
 * does not include). Weak, so a program may define its own motion_clock_ms(). */
extern "C" unsigned long millis(void);
extern "C" __attribute__((weak)) uint32_t motion_clock_ms(void)
{
    return (uint32_t)millis();
}
#endif

MotionPID::MotionPID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd, int POn,
                     int ControllerDirection)
    : clock_(0)
{
    (void)pid_init(&c_, Input, Output, Setpoint, Kp, Ki, Kd, POn, ControllerDirection, now());
}

MotionPID::MotionPID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd,
                     int ControllerDirection)
    : clock_(0)
{
    (void)pid_init(&c_, Input, Output, Setpoint, Kp, Ki, Kd, P_ON_E, ControllerDirection, now());
}

uint32_t MotionPID::now() const
{
    return clock_ != 0 ? clock_() : motion_clock_ms();
}

void MotionPID::SetClock(ClockFn now_ms)
{
    clock_ = now_ms;
}

void MotionPID::SetMode(int Mode)
{
    pid_set_mode(&c_, Mode);
}

bool MotionPID::Compute()
{
    /* like PID_v1, the clock is read only in AUTOMATIC */
    if (!c_.in_auto)
        return false;
    return pid_compute(&c_, now()) != 0;
}

void MotionPID::SetOutputLimits(double Min, double Max)
{
    (void)pid_set_output_limits(&c_, Min, Max);
}

void MotionPID::SetTunings(double Kp, double Ki, double Kd)
{
    (void)pid_set_tunings(&c_, Kp, Ki, Kd);
}

void MotionPID::SetTunings(double Kp, double Ki, double Kd, int POn)
{
    (void)pid_set_tunings_pon(&c_, Kp, Ki, Kd, POn);
}

void MotionPID::SetControllerDirection(int Direction)
{
    pid_set_direction(&c_, Direction);
}

void MotionPID::SetSampleTime(int NewSampleTime)
{
    (void)pid_set_sample_time(&c_, NewSampleTime);
}

double MotionPID::GetKp()
{
    return pid_get_kp(&c_);
}

double MotionPID::GetKi()
{
    return pid_get_ki(&c_);
}

double MotionPID::GetKd()
{
    return pid_get_kd(&c_);
}

int MotionPID::GetMode()
{
    return (int)pid_get_mode(&c_);
}

int MotionPID::GetDirection()
{
    return (int)pid_get_direction(&c_);
}
