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
 * Anything else gets "ERR <reason>" and changes nothing. Every accepted move ends in exactly one DONE
 * unless a later target replaces it; the DONE of a move that ended just before a new line is printed
 * before that line's reply.
 *
 * With three axes (MultiAxisStepper: MotionConsole console(x, y, z, xyz), xyz a StepperGroup of the
 * three in that order: StepperGroup xyz(x, y, z)) every line names its axis, x, y or z (<a> below), and the replies do too:
 *
 *   <a> <integer>        that axis alone: "OK <a> <from> <to>", later "DONE <a> <position>" (the rules
 *                        above, "(after DONE <a> <old target>)"); the others may move meanwhile
 *   move <a><t> ...      the named axes together on the straight line (StepperGroup: e.g. "move x1000
 *                        y-500"): "OK move x <from> <to> y <from> <to>", later one "DONE move x <pos>
 *                        y <pos>". "ERR busy" while a named axis moves or another `move` runs
 *                        (one coordinated move at a time); axes not named may move alone.
 *                        Every named axis belongs to the move until that DONE (a target for it gets
 *                        "ERR busy", `stop <it>` stops the whole move); all at their targets already:
 *                        "OK move ..." and "DONE move ..." at once.
 *   stop [<a>] | ! [<a>] every axis, or one (one of a move: the whole move)
 *   ?                    one line per axis: "<a> pos= target= state= mode=idle|alone|move algo= ..."
 *   set <a> <key> <val>  "OK <a> <key>=<value>"
 * docs/serial.md has the whole protocol.
 */
#ifndef MOTION_STEPPER_MOTION_CONSOLE_H
#define MOTION_STEPPER_MOTION_CONSOLE_H

#include "IncludedFirst.h" /* first: MotionBoard's headers must come after (it says why) */

#include <Arduino.h>

#include "Stepper.h" /* first: MotionBoard's headers through it */

#include <MotionSerial.h>
#include <SerialOutQueue.h>

class StepperGroup; /* StepperGroup.h: only MotionConsoleMove.cpp, the `move` part, uses it */

class MotionConsole {
public:
    /* Also makes the planner run from loop() (BackgroundPlanner::planInLoop(): poll() plans), so make
     * it a global, as the sketches do (before setup() and the Stepper's begin()). */
    explicit MotionConsole(Stepper &x);
    /* Three axes named x, y, z, and their StepperGroup for `move` (StepperGroup xyz(x, y, z)). */
    MotionConsole(Stepper &x, Stepper &y, Stepper &z, StepperGroup &xyz);

    /* After the Stepper's begin(): Serial at 9600 baud, the LED mirror (X: STEPPER_LED_MIRROR),
     * the sketches' lead (StepperPins.h); prints "READY <name>". */
    void begin(const __FlashStringHelper *sketch_name);

    /* Call on every pass of loop(): reads and answers command lines, reports each move's end. */
    void poll();

private:
    void handle(const char *line);
    void handle_target(uint8_t a, const char *word);
    void handle_move(const char *cursor);
    void handle_stop(const char *cursor, bool halt);
    void handle_set(uint8_t a, const char *cursor);
    void print_status(uint8_t a);
    void print_param(Print &out, uint8_t a, const char *key);
    void print_axis(Print &out, uint8_t a); /* "x " with three axes, nothing with one */
    void print_axes(Print &out, const long *from, const long *to);
    bool collect_done(); /* false: the output queue has no room for a DONE line now */
    bool finish_ok();    /* the OK of a target once it is planned; false: not yet */
    bool finish_move();  /* the OK of a `move` once it is planned; false: not yet */
    void move_done();    /* the DONE of a `move` once its group reports the end */
    motion_status_t stop_move(bool halt, bool &moving); /* stop or ! of a `move`'s axis */
    static int8_t axis_of(const char *word); /* "x" -> 0 ...; -1 for anything else */
    static const char AXIS_NAME[3];

    /* the `move` part (MotionConsoleMove.cpp), reached only through this table, which only the
     * three-axis constructor names: a one-axis sketch links none of it, nor StepperGroup's moves */
    struct MoveParts {
        void (MotionConsole::*handle)(const char *cursor);
        bool (MotionConsole::*finish)();
        void (MotionConsole::*done)();
        motion_status_t (MotionConsole::*stop)(bool halt, bool &moving);
    };
    static const MoveParts MOVE_PARTS;

    Stepper *ax_[3];
    uint8_t n_;
    StepperGroup *group_;
    const MoveParts *move_; /* &MOVE_PARTS with three axes, else none */
    uint8_t named_;         /* the axes of the `move` whose DONE is still to come (bit i: axis i) */
    uint8_t status_pending_; /* the `?` lines that wait for room in the output queue (bit i: axis i) */
    bool ok_pending_;     /* a target's OK waits for its plan */
    bool move_pending_;   /* a `move`'s OK waits for its plan */
    uint8_t ok_axis_;
    int32_t ok_target_;
    long move_from_[3], move_to_[3];
    SerialOutQueue queue_;   /* before serial_, which is built on it */
    MotionSerial serial_;
};

#endif
