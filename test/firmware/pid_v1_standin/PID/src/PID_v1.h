/* PID_v1.h (stand-in) - the public interface of the Arduino PID library PID_v1 1.2.1, forwarding
 * to lib/src/pidv1_ctrl.c; for the compile check of PIDClosedLoop's USE_REAL_PID_V1 switch only. */
#ifndef PID_v1_h
#define PID_v1_h
#define LIBRARY_VERSION 1.2.1

#include <pidv1_ctrl.h>

#define AUTOMATIC 1
#define MANUAL 0
#define DIRECT 0
#define REVERSE 1
#define P_ON_M 0
#define P_ON_E 1

class PID {
public:
    PID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd, int POn, int ControllerDirection);
    PID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd, int ControllerDirection);
    void SetMode(int Mode);
    bool Compute();
    void SetOutputLimits(double Min, double Max);
    void SetTunings(double Kp, double Ki, double Kd);
    void SetTunings(double Kp, double Ki, double Kd, int POn);
    void SetControllerDirection(int Direction);
    void SetSampleTime(int NewSampleTime);
    double GetKp();
    double GetKi();
    double GetKd();
    int GetMode();
    int GetDirection();

private:
    pid_ctrl_t c_;
};
#endif
