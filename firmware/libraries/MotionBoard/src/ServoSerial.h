/* ServoSerial.h - the serial port of the two servo sketches: it reads a command line, checks it,
 * answers it, and turns the sketch's values into the status line and the `?` line. It holds no
 * setpoint, gain or position: the sketch owns those and its loops, and applies each ServoCommand
 * readCommand() hands it. 9600 baud; lines end in CR, LF or CRLF (MotionSerial). Commands:
 *
 *   <integer>       position setpoint in encoder counts, -1000000..1000000 -> "OK setpoint=<n>"
 *                   (a step: the setpoint jumps, the handout's behaviour)
 *   move <integer>  the same range; the setpoint follows the filter-shaped move there
 *                   (lib/src/smooth_move.h, smooth_setpoint_*)                -> "OK move=<n>"
 *   kp <value>      retune live, 0..1000 (% duty per count)                -> "OK kp=<v>"
 *   ki <value>      PIDClosedLoop only, 0..1000 (% per count-second)       -> "OK ki=<v>"
 *   kd <value>      PIDClosedLoop only, 0..1000 (% per count/s)            -> "OK kd=<v>"
 *   ?               one line of state: "setpoint=<n> position=<n> error=<n> duty=<pct> kp=<v>
 *                   [ki=<v> kd=<v>]" (same keys every time; the sketch calls replyState())
 * Anything else gets "ERR <reason>[: <detail>]" here and never reaches the sketch: a setpoint that
 * is not a whole number or out of range, a negative gain ("gains must not be negative"), a gain
 * above 1000, a missing or extra word, an unknown command, a line over 40 characters, binary bytes.
 * Every second the print loop writes, without OK/ERR/READY in front:
 *   t_ms=<scheduled time> setpoint=<counts> position=<counts> error=<counts> duty=<pct, 2 decimals>
 * Limits come from lib/src/pctrl.h (SERVO_SETPOINT_MAX_COUNTS, SERVO_GAIN_MAX).
 *
 * Output never blocks (the control loop must not wait for the 9600-baud port): every line goes
 * into a SerialOutQueue that readCommand() feeds to Serial only as fast as its transmit buffer
 * accepts (docs/servo.md, "Serial output never makes the control loop wait").
 *  - A command line is read only when the queue has room for the longest reply
 *    (REPLY_MAX_BYTES); otherwise its bytes wait, unread, in the input ring (SerialRx).
 *  - The status line is deferred, never dropped: printStatus() snapshots the values with their
 *    scheduled time, and readCommand() writes it as soon as STATUS_MAX_BYTES are free; until then
 *    no command is read, so commands cannot starve it.
 *  - A pass of loop() formats at most one line.
 */
#ifndef SERVO_SERIAL_H
#define SERVO_SERIAL_H

#include <Arduino.h>

#include "MotionSerial.h"
#include "SerialOutQueue.h"

/* `move <counts>`'s shaped setpoint: the sketch keeps a smooth_setpoint_t and calls
 * smooth_setpoint_move/_at/_jump (lib/src/smooth_move.h) */
#include <smooth_move.h>

/* One checked command, already answered "OK ..." (except QUERY, which the sketch answers). */
struct ServoCommand {
    enum What { SETPOINT, KP, KI, KD, QUERY, MOVE };
    What what;
    int32_t setpoint; /* SETPOINT, MOVE: counts, -1000000..1000000 */
    float gain;       /* KP, KI, KD: 0..1000 */
    ServoCommand() : what(QUERY), setpoint(0), gain(0) {}
};

class ServoSerial {
public:
    /* Which gains the sketch has: ki and kd are refused by a KP_ONLY sketch. */
    enum Gains { KP_ONLY, KP_KI_KD };

    /* The longest lines, CR LF included: the '?' line with setpoint "-1000000" (8 characters),
     * position and error as any int32 (11), duty "-99.99" (6), three gains "999.999939" (10):
     * 9+8 + 10+11 + 7+11 + 6+6 + 3 x (4+10) + 2 = 112; every OK/ERR reply is shorter (the longest,
     * "ERR unknown command: try <setpoint>, move <counts>, kp|ki|kd <value>, ?", is 73). The status
     * line: 5+10 + 1 + 17+21+18+12 + 2 = 86. The queue (SERIAL_OUT_QUEUE_BYTES, 256) holds both. */
    static const uint16_t REPLY_MAX_BYTES = 112;
    static const uint16_t STATUS_MAX_BYTES = 86;

    ServoSerial(Stream &port, Gains gains)
        : queue_(port), lines_(port, queue_, REPLY_MAX_BYTES), gains_(gains), status_pending_(false),
          status_t_ms_(0), status_setpoint_(0), status_position_(0), status_duty_(0)
    {
    }

    /* Call on every pass of loop(). Moves queued output on to Serial, then either writes the
     * pending status line (when it fits) or reads one command line (when its reply surely fits).
     * Returns true with `command` filled in for a valid command, for the sketch to apply; a bad
     * line has been answered ERR and returns false. Never waits for the port. */
    bool readCommand(ServoCommand &command);

    /* The reply to `?` (P sketch: kp only; PID sketch: kp, ki, kd). */
    void replyState(int32_t setpoint, int32_t position, float duty, float kp);
    void replyState(int32_t setpoint, int32_t position, float duty, float kp, float ki, float kd);

    /* The print loop's line for scheduled time t_ms, with the values as they are now (a
     * snapshot), written by the next readCommand() that finds room for it. */
    void printStatus(uint32_t t_ms, int32_t setpoint, int32_t position, float duty);

    /* Where the sketch prints its own lines ("READY ...", "WARN ..."), queued like every reply. */
    Print &out() { return queue_; }

private:
    bool parseLine(const char *line, ServoCommand &command);
    bool parseGain(const char *word, const char *value, const char *rest, ServoCommand &command);
    bool parseMove(const char *value, const char *rest, ServoCommand &command);
    void printPosition(int32_t setpoint, int32_t position, float duty);
    void flushStatus();

    SerialOutQueue queue_; /* before lines_, which is built on it */
    MotionSerial lines_;
    Gains gains_;
    bool status_pending_;
    uint32_t status_t_ms_;
    int32_t status_setpoint_, status_position_;
    float status_duty_;
};

#endif
