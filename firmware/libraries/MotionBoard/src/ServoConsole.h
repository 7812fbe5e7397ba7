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
 *
 * Output never blocks (the control loop must not wait for the 9600-baud port): every line goes
 * into a SerialOutQueue that poll() feeds to Serial only as fast as its transmit buffer accepts.
 *  - A command line is read only when the queue has room for the longest reply
 *    (REPLY_MAX_BYTES); otherwise its bytes wait, unread, in Serial's receive buffer
 *    (back-pressure: a host that sends faster than the replies can leave waits for them).
 *  - The status line is deferred, never dropped: queueStatus() snapshots the state with its
 *    scheduled time, and poll() writes it as soon as STATUS_MAX_BYTES are free; until then no
 *    command is read, so commands cannot starve it. Only if the next one fell due while it was
 *    still waiting (the queue short of 86 free bytes for a whole second) would it be replaced.
 * The text of every line is the same as when it was printed directly.
 */
#ifndef SERVO_CONSOLE_H
#define SERVO_CONSOLE_H

#include <Arduino.h>

#include "MotionSerial.h"
#include "SerialOutQueue.h"

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

    /* The longest lines, CR LF included, from the formats above: the '?' state line with
     * setpoint "-1000000" (8 characters), position and error as any int32 (11), duty "-99.99"
     * (6), three gains "999.999939" (10):  9+8 + 10+11 + 7+11 + 6+6 + 3 x (4+10) + 2 = 112;
     * every OK/ERR reply is shorter (the longest ERR, a setpoint's "ERR number out of range:
     * setpoint: whole counts -1000000..1000000", is 67). The status line: 5+10 + 1 + 17+21+18+12
     * + 2 = 86 ("t_ms=" and a uint32). The queue (SERIAL_OUT_QUEUE_BYTES, 256) holds both. */
    static const uint16_t REPLY_MAX_BYTES = 112;
    static const uint16_t STATUS_MAX_BYTES = 86;

    /* The console owns the output queue and the line reader on `port` (Serial), wired together
     * with REPLY_MAX_BYTES as the reader's reserve, so the two cannot disagree. */
    ServoConsole(Stream &port, Kind kind)
        : queue_(port), serial_(port, queue_, REPLY_MAX_BYTES), kind_(kind), status_pending_(false),
          status_t_ms_(0)
    {
    }

    /* Where a sketch prints its own lines (queued like every reply, e.g. a WARN at start-up). */
    Print &out() { return queue_; }

    /* "READY <name>" (queued) */
    void ready(const __FlashStringHelper *sketch_name);
    /* Call on every pass of loop(): moves queued output to Serial; then either writes the
     * pending status line (when it fits) or handles at most one complete command line (when
     * its reply surely fits): one line of formatting per pass at most. On SETPOINT_CHANGED or GAINS_CHANGED the new value is already in s and the sketch
     * applies it (e.g. SetTunings). Never waits for the port. */
    Event poll(ServoState &s);
    /* The print loop's line for scheduled time t_ms, with s as it is now (a snapshot): written
     * by the next poll() that finds room for it (see above). */
    void queueStatus(uint32_t t_ms, const ServoState &s);
    /* A real number with up to `decimals` decimals, trailing zeros dropped ("0.02", "1", "-3.5"). */
    static void printReal(Print &out, float v, uint8_t decimals);

private:
    Event handleGain(const char *name, const char *value, const char *rest, ServoState &s);
    Event handleLine(const char *line, ServoState &s);
    void printState(const ServoState &s);
    void flushStatus();
    SerialOutQueue queue_; /* before serial_, which is built on it */
    MotionSerial serial_;
    Kind kind_;
    bool status_pending_;
    uint32_t status_t_ms_;
    ServoState status_state_; /* snapshot for the deferred status line */
};

#endif
