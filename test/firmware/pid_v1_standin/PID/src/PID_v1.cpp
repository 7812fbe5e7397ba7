/* PID_v1.cpp (stand-in) - see PID_v1.h here. */
#include <Arduino.h>

#include "PID_v1.h"

PID::PID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd, int POn, int ControllerDirection)
{
    (void)pid_init(&c_, Input, Output, Setpoint, Kp, Ki, Kd, POn, ControllerDirection, millis());
}
PID::PID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd, int ControllerDirection)
{
    (void)pid_init(&c_, Input, Output, Setpoint, Kp, Ki, Kd, P_ON_E, ControllerDirection, millis());
}
void PID::SetMode(int Mode) { pid_set_mode(&c_, Mode); }
bool PID::Compute() { return pid_compute(&c_, millis()) != 0; }
void PID::SetOutputLimits(double Min, double Max) { (void)pid_set_output_limits(&c_, Min, Max); }
void PID::SetTunings(double Kp, double Ki, double Kd) { (void)pid_set_tunings(&c_, Kp, Ki, Kd); }
void PID::SetTunings(double Kp, double Ki, double Kd, int POn) { (void)pid_set_tunings_pon(&c_, Kp, Ki, Kd, POn); }
void PID::SetControllerDirection(int Direction) { pid_set_direction(&c_, Direction); }
void PID::SetSampleTime(int NewSampleTime) { (void)pid_set_sample_time(&c_, NewSampleTime); }
double PID::GetKp() { return pid_get_kp(&c_); }
double PID::GetKi() { return pid_get_ki(&c_); }
double PID::GetKd() { return pid_get_kd(&c_); }
int PID::GetMode() { return (int)pid_get_mode(&c_); }
int PID::GetDirection() { return (int)pid_get_direction(&c_); }
