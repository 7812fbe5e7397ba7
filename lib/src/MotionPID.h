/* MotionPID.h - the C++ face of pidv1_ctrl.h for sketches: the public interface and constants
 * of the Arduino PID library PID_v1 1.2.1 (class PID) under a name that cannot collide with it
 * (neither the class nor the header file, even on a case-insensitive file system), so the lab's
 * code (the lab handout section 4.2) reads the same with MotionPID in place of PID:
 *
 *   double Input, Output, Setpoint;
 *   MotionPID myPID(&Input, &Output, &Setpoint, Kp, Ki, Kd, DIRECT);
 *   myPID.SetOutputLimits(-100, 100); myPID.SetSampleTime(20); myPID.SetMode(AUTOMATIC);
 *   ... Input = position; myPID.Compute(); ... use Output ...
 *
 * Behaviour is PID_v1's, bit for bit (see pidv1_ctrl.h). On the AVR double is float, exactly as
 * the real library runs there. The constants AUTOMATIC, MANUAL, DIRECT, REVERSE, P_ON_E, P_ON_M are
 * the same macros with the same values as PID_v1.h (identical redefinitions are legal, so both
 * headers may even be included together).
 *
 * Switching existing PID_v1 code over takes one line after the include:
 *
 *   #include <MotionPID.h>
 *   typedef MotionPID PID;        // PID myPID(&Input, &Output, &Setpoint, 2, 5, 1, DIRECT); as before
 *
 * The declarations match PID_v1.h too: the getters are not const (so member pointers of PID_v1's
 * types bind) and LIBRARY_VERSION is 1.2.1 (docs/pid_v1.md lists what is and is not the same).
 *
 * Time: where PID_v1 calls millis(), MotionPID calls its clock. The default clock is the
 * function motion_clock_ms(); on the board MotionPID.cpp defines it (weak) as Arduino's millis(),
 * so a sketch that includes only this header builds and runs; a host program defines its own.
 * SetClock() (an extension) gives one controller another clock, e.g. the scheduled start of the
 * current control period. No Arduino.h here.
 */
#ifndef MOTION_PID_H
#define MOTION_PID_H

#include <stdint.h>

#include "pidv1_ctrl.h"

#ifndef AUTOMATIC
#define AUTOMATIC 1
#endif
#ifndef MANUAL
#define MANUAL 0
#endif
#ifndef DIRECT
#define DIRECT 0
#endif
#ifndef REVERSE
#define REVERSE 1
#endif
#ifndef P_ON_M
#define P_ON_M 0
#endif
#ifndef P_ON_E
#define P_ON_E 1
#endif
#ifndef LIBRARY_VERSION
#define LIBRARY_VERSION 1.2.1
#endif

/* Milliseconds, wrapping at 2^32: the default clock of every MotionPID. On the board (ARDUINO
 * defined) MotionPID.cpp provides millis() as a weak definition a program may replace; elsewhere
 * the program provides it. */
extern "C" uint32_t motion_clock_ms(void);

class MotionPID {
public:
    typedef uint32_t (*ClockFn)(void);

    /* PID_v1's constructors: starts in MANUAL, limits 0..255, 100 ms sample time. */
    MotionPID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd, int POn,
              int ControllerDirection);
    MotionPID(double *Input, double *Output, double *Setpoint, double Kp, double Ki, double Kd,
              int ControllerDirection);

    void SetMode(int Mode);
    bool Compute();
    void SetOutputLimits(double Min, double Max);
    void SetTunings(double Kp, double Ki, double Kd);
    void SetTunings(double Kp, double Ki, double Kd, int POn);
    void SetControllerDirection(int Direction);
    void SetSampleTime(int NewSampleTime);

    /* Not const, exactly as PID_v1 declares them. */
    double GetKp();
    double GetKi();
    double GetKd();
    int GetMode();
    int GetDirection();

    /* Extensions (not in PID_v1). */
    void SetClock(ClockFn now_ms);          /* NULL restores motion_clock_ms */
    const pid_ctrl_t &State() const { return c_; } /* internal state, read-only */

private:
    uint32_t now() const;
    pid_ctrl_t c_;
    ClockFn clock_;
};

#endif
