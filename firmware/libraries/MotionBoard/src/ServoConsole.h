/* ServoConsole.h - the serial protocol shared by the two servo sketches, so they are not copies
 * of each other. 9600 baud; lines end in CR, LF or CRLF (MotionSerial). Commands:
 *
 *   <integer>       position setpoint in encoder counts, -1000000..1000000 -> "OK setpoint=<n>"
 *   kp <value>      retune live, 0..1000 (% duty per count)                -> "OK kp=<v>"
 *   ki <value>      PIDClosedLoop only, 0..1000 (% per count-second)       -> "OK ki=<v>"
 *   kd <value>      PIDClosedLoop only, 0..1000 (% per count/s)            -> "OK kd=<v>"
 *   ?               one line of state: "setpoint=<n> position=<n> error=<n> duty=<pct> kp=<v>
 *                   [ki=<v> kd=<v>]" (same keys every time)
 * Anything else gets "ERR <reason>[: <detail>]" and changes nothing: a setpoint that is not a
 * whole number or out of range, a negative gain ("gains must not be negative"), a gain above
 * 1000, a missing or extra word, an unknown command, a line over 40 characters, binary bytes.
 * At boot: "READY <SketchName>" (after a line "WARN encoder ..." if the LS7366R did not answer).
 * Every second the print loop writes, without OK/ERR/READY in front:
 *   t_ms=<scheduled time> setpoint=<counts> position=<counts> error=<counts> duty=<pct, 2 decimals>
 * Limits come from lib/src/pctrl.h (SERVO_SETPOINT_MAX_COUNTS, SERVO_GAIN_MAX).
 */
#ifndef SERVO_CONSOLE_H
#define SERVO_CONSOLE_H

#include <Arduino.h>

#include "MotionSerial.h"

/* What the sketch shows and what the console may change. */
struct ServoState {
    int32_t setpoint_counts;
    int32_t position_counts;
    float duty_pct;
    float kp, ki, kd;
};

class ServoConsole {
public:
    enum Event { NOTHING = 0, SETPOINT_CHANGED, GAINS_CHANGED };
    enum Kind { P_ONLY = 0, PID_GAINS = 1 };

    ServoConsole(MotionSerial &serial, Kind kind) : serial_(serial), kind_(kind) {}

    /* "READY <name>" */
    void ready(const __FlashStringHelper *sketch_name);
    /* Handles at most one complete command line; on SETPOINT_CHANGED or GAINS_CHANGED the new
     * value is already in s and the sketch applies it (e.g. SetTunings). */
    Event poll(ServoState &s);
    /* The print loop's line. */
    void printStatus(uint32_t t_ms, const ServoState &s);
    /* A real number with up to `decimals` decimals, trailing zeros dropped ("0.02", "1", "-3.5"). */
    static void printReal(Print &out, float v, uint8_t decimals);

private:
    Event handleGain(const char *name, const char *value, const char *rest, ServoState &s);
    void printState(const ServoState &s);
    MotionSerial &serial_;
    Kind kind_;
};

#endif
