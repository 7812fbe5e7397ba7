/* StepperConsole.h - the serial protocol shared by the stepper sketches (9600 baud, lines ending in
 * CR, LF or CRLF, through MotionSerial; replies through a SerialOutQueue, so printing never holds
 * up the planner):
 *
 *   <integer>            absolute target (any int32): "OK <from> <to>", later "DONE <position>".
 *                        While moving, the move continues from its current speed to the new target
 *                        (no speed jump; a target behind, or closer than the stopping distance,
 *                        makes it decelerate, reverse and approach); "from" is where the new plan
 *                        starts; the replaced move gets no DONE, the new one does. If every
 *                        step of the move is already queued (it is about to end at rest), the
 *                        move keeps its DONE and the new one starts from its target after it:
 *                        "OK <old target> <to> (after DONE <old target>)", "DONE <old target>",
 *                        later "DONE <to>".
 *   stop                 decelerate at accel to rest: "OK stop", then "DONE <position>"
 *   !                    halt now, no further step: "OK halt", then "DONE <position>"
 *                        (either while idle: "OK stop (not moving)" / "OK halt (not moving)")
 *   ?                    one line: pos= target= state=idle|accel|cruise|decel algo= v0= vmax= accel=
 *                        tick_hz= max_sps= [sigmoid: flex= len= hold= accel_steps= accel_time_s=
 *                        cruise_sps=] underruns= late= mode=timer|loop
 *   set <key> <value>    "OK <key>=<value>" (keys: v0 vmax accel; SCurveStepper: v0 = fmin,
 *                        vmax = fmax, flex, len, hold; accel is derived there). While moving the
 *                        reply adds " (from the next plan)": the move in progress keeps its
 *                        parameters, the next target or stop uses the new ones (SCurveStepper: the
 *                        next move from rest, since its table is refilled then).
 *   READY <SketchName>   printed once at the end of setup
 * Anything else gets "ERR <reason>" and changes nothing. Every accepted move (an OK to a target)
 * ends in exactly one DONE unless a later target replaces it; the DONE of a move that ended just
 * before a new target is printed before that target's OK.
 */
#ifndef STEPPER_CONSOLE_H
#define STEPPER_CONSOLE_H

#include <Arduino.h>

#include <step_planner.h>

#include "MotionSerial.h"
#include "SerialOutQueue.h"
#include "StepEngine.h"
#include "StepperRamps.h"

class StepperConsole {
public:
    explicit StepperConsole(StepperRamp &ramp)
        : ramp_(ramp), queue_(Serial), serial_(Serial, queue_, 240), has_next_(false), next_due_(false),
          next_target_(0)
    {
    }

    /* Serial at 9600 baud, the engine's pins and timer, the planner; prints "READY <name>". */
    void begin(const __FlashStringHelper *sketch_name);

    /* Call on every pass of loop(): feeds the step queue, reports DONE, handles command lines. */
    void poll();

    step_planner_t &planner() { return planner_; }

private:
    void handle(const char *line);
    void handle_target(const char *word);
    void handle_stop(bool halt);
    void handle_set(const char *cursor);
    void reply_status();
    void report_done(int32_t position);

    StepperRamp &ramp_;
    step_planner_t planner_;
    SerialOutQueue queue_; /* before serial_, which is built on it */
    MotionSerial serial_;
    bool has_next_;       /* a target accepted while the move's last steps were queued */
    bool next_due_;       /* ... whose move starts as soon as nothing is in the way (poll()) */
    int32_t next_target_;
};

#endif
