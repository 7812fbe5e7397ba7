/* MotionConsole.h - the stepper sketches' serial protocol on Steppers (Stepper.h): what a sketch
 * calls in loop() to be driven from the Serial Monitor, every command carried out through the
 * public calls of its Steppers and StepperGroup (moveTo, stop, forceStop, the setters, the
 * queries), as your own sketch would:
 *
 *   Stepper x(Stepper::X);
 *   MotionConsole console(x);
 *   setup():  the Stepper's parameters and begin(); console.begin(F("SketchName"));
 *   loop():   console.poll();
 *
 * Serial at 9600 baud, lines ending in CR, LF or CRLF (MotionSerial); replies through a
 * SerialOutQueue, so printing never blocks loop(). With one axis:
 *
 *   <integer>            absolute target (any int32): "OK <from> <to>", later "DONE <position>".
 *                        While moving, the move continues from its current speed to the new target
 *                        (no speed jump; a target behind, or closer than the stopping distance,
 *                        makes it decelerate, reverse and approach); "from" is where the new plan
 *                        starts (Stepper::planStart); the replaced move gets no DONE, the new one
 *                        does. If every step of the move is already queued (it is about to end at
 *                        rest), the move keeps its DONE and the new one starts from its target
 *                        after it: "OK <old target> <to> (after DONE <old target>)", "DONE <old
 *                        target>", later "DONE <to>".
 *   stop                 decelerate to rest: "OK stop", then "DONE <position>"
 *   !                    halt now, no further step: "OK halt", then "DONE <position>"
 *                        (either while idle: "OK stop (not moving)" / "OK halt (not moving)")
 *   ?                    one line: pos= target= state=idle|accel|cruise|decel algo= v0= vmax= accel=
 *                        tick_hz= max_sps= [sigmoid: flex= len= hold= accel_steps= accel_time_s=
 *                        cruise_sps=] underruns= late= mode=timer|loop
 *   set <key> <value>    v0, vmax or accel (the sigmoid: v0 = fmin, vmax = fmax, flex, len, hold;
 *                        accel follows from them): "OK <key>=<value>"; while moving the reply adds
 *                        " (from the next plan)" (the move in progress keeps its parameters)
 *   READY <SketchName>   printed once by begin()
 * (MultiAxisStepper's three-axis protocol is still MotionBoard's MultiAxisConsole.) Anything else
 * gets "ERR <reason>" and changes nothing. Every accepted move ends in exactly one DONE
 * unless a later target replaces it; the DONE of a move that ended just before a new line is printed
 * before that line's reply. docs/serial.md has the whole protocol.
 */
#ifndef MOTION_STEPPER_MOTION_CONSOLE_H
#define MOTION_STEPPER_MOTION_CONSOLE_H

#include <Arduino.h>

#include "Stepper.h" /* first: MotionBoard's headers through it */

#include <MotionSerial.h>
#include <SerialOutQueue.h>

class MotionConsole {
public:
    /* Also makes the planner run from loop() (BackgroundPlanner::planInLoop(): poll() plans), so make
     * it a global, as the sketches do (before setup() and the Stepper's begin()). */
    explicit MotionConsole(Stepper &x);

    /* After the Stepper's begin(): Serial at 9600 baud, the LED mirror (X: STEPPER_LED_MIRROR),
     * the sketches' lead (StepperPins.h); prints "READY <name>". */
    void begin(const __FlashStringHelper *sketch_name);

    /* Call on every pass of loop(): reads and answers command lines, reports each move's end. */
    void poll();

private:
    void handle(const char *line);
    void handle_target(const char *word);
    void handle_stop(const char *cursor, bool halt);
    void handle_set(const char *cursor);
    void print_status();
    void print_param(Print &out, const char *key);
    bool collect_done(); /* false: the output queue has no room for a DONE line now */
    bool finish_ok();    /* the OK of a target once it is planned; false: not yet */

    Stepper &x_;
    bool status_pending_; /* the `?` line waits for room in the output queue */
    bool ok_pending_;     /* a target's OK waits for its plan */
    int32_t ok_target_;
    SerialOutQueue queue_;   /* before serial_, which is built on it */
    MotionSerial serial_;
};

#endif
