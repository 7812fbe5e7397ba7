/* StepConsole.h - the step engine's own serial console, for one to three axes, on the one step
 * engine (MultiStepEngine.h: X, Y, Z on Timer1's compare channels A, B, C). Serial at 9600 baud,
 * lines ending in CR, LF or CRLF through MotionSerial; replies through a SerialOutQueue, so printing
 * never holds up the planners. The MultiAxisStepper sketch makes the console built on it:
 *   MultiAxisConsole console(xRamp, yRamp, zRamp);  three axes: MultiAxisConsole.h (x|y|z <target>,
 *                                               move x<t> y<t> z<t>, stop [axis], ...)
 * and calls console.begin(F("SketchName")) in setup() and console.poll() on every pass of loop().
 * (The one-axis sketches speak their protocol through the MotionStepper library's MotionConsole, on
 * a Stepper, since 2026-12-05; StepperConsole, this class's one-axis form, is gone: its one-axis
 * branches here wait to go with the three-axis console, once MultiAxisStepper is on the library.)
 * The replies of both protocols (OK/DONE/ERR, the `?` lines) are in docs/serial.md and
 * docs/multi-axis.md; this class is what both do: parse a line, plan (lib's step_planner.h; for a
 * coordinated move step_coord.h, through the StepConsoleCoord part only the three-axis console
 * links), feed the engine's queues, report each move's end once.
 */
#ifndef STEP_CONSOLE_H
#define STEP_CONSOLE_H

#include <Arduino.h>

#include <step_planner.h>

#include "MotionSerial.h"
#include "MultiStepEngine.h"
#include "SerialOutQueue.h"
#include "StepperRamps.h"

class StepConsole;

/* The coordinated `move` of the three-axis console (MultiAxisConsole.cpp): reached only through
 * this interface, so a one-axis sketch links none of its code. named: the axes of the move in
 * progress (0: none), each reported in its DONE line, so none takes another target meanwhile, even
 * one that was at its target already; mask: of those, the ones that move. */
class StepConsoleCoord {
public:
    uint8_t named;
    uint8_t mask;
    /* where axis's commands come from while it is in the move */
    virtual AxisSource source(uint8_t axis) = 0;
    /* `move ...` */
    virtual void handle_move(StepConsole &c, const char *cursor) = 0;
    /* an axis of the move has ended at pos (its DONE line once all have) */
    virtual void axis_done(StepConsole &c, uint8_t axis, int32_t pos) = 0;
    /* stop (halt: at once) the move; running: the axes that are moving */
    virtual void stop(StepConsole &c, bool halt) = 0;
    /* feed(): starts the move's axes together once each has its first commands */
    virtual void start_if_ready() = 0;
    virtual int32_t position_of(uint8_t axis) = 0;
    virtual int32_t target_of(uint8_t axis) = 0;

protected:
    StepConsoleCoord() : named(0), mask(0) {}
};

class StepConsole {
public:
    /* Call on every pass of loop(): feeds the step queues, reports DONEs, handles command lines. */
    void poll();

    /* Lays out step commands for every axis (what poll() does first; also called while slow
     * replies are formatted). */
    void feed();

    step_planner_t &planner(uint8_t axis = 0) { return pl_[axis]; }

protected:
    StepConsole(uint8_t axes, StepperRamp **ramps, step_planner_t *planners, StepConsoleCoord *coord);
    /* begin() of the two consoles, after MultiStepEngine::begin() with their axes (a constant there,
     * so a one-axis sketch links one axis's interrupt and ring): Serial at 9600 baud, the lead, the
     * planners; prints "READY <name>". */
    void begin_console(const __FlashStringHelper *sketch_name);

private:
    friend class MultiAxisCoord;
    AxisSource source(uint8_t axis);
    void handle(const char *line);
    void handle_target(uint8_t axis, const char *word);
    void handle_stop(const char *cursor, bool halt);
    void handle_set(uint8_t axis, const char *cursor);
    void print_status(uint8_t axis);
    void report_done(uint8_t axis, int32_t position);
    bool collect_done(); /* false: a DONE waits for room in the output queue */
    void start_next(uint8_t axis);
    /* a stop or a new target from a cut of the queue (the ramp's cut(): StepCut.h); false: not
     * cut (then planned after the queued steps) */
    bool cut_plan(uint8_t axis, bool stop, int32_t target, int32_t &from);
    void print_axis(Print &out, uint8_t axis); /* "x " on three axes, nothing on one */
    void print_ok(uint8_t axis, int32_t from, int32_t to); /* "OK [x ]<from> <to>", no line end */
    uint8_t coord_mask() const { return co_ ? co_->mask : 0; }
    uint8_t coord_named() const { return co_ ? co_->named : 0; }

    uint8_t n_; /* axes: 1 (X) or 3 */
    StepperRamp **ramp_;
    step_planner_t *pl_;
    StepConsoleCoord *co_;
    bool has_next_[MULTI_AXES];  /* a target accepted while the move's last steps were queued */
    bool next_due_[MULTI_AXES];  /* ... whose move starts as soon as nothing is in the way (poll()) */
    int32_t next_target_[MULTI_AXES];
    uint8_t status_pending_; /* axes whose `?` line is still to print */
    uint16_t cuts_missed_;   /* cuts tried and given up (the plan took too long), all axes */
    SerialOutQueue queue_;   /* before serial_, which is built on it */
    MotionSerial serial_;
};

#endif
