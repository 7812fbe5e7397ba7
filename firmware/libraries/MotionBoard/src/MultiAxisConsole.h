/* MultiAxisConsole.h - MultiAxisStepper's serial protocol (the console itself is StepConsole.h; this
 * file adds the coordinated move). 9600 baud, lines ending
 * in CR, LF or CRLF, through MotionSerial; replies through a SerialOutQueue, so printing never
 * holds up the planners. The axes are x, y and z; <a> below is one of them.
 *
 *   <a> <integer>        independent move of one axis to an absolute target: "OK <a> <from> <to>",
 *                        later "DONE <a> <position>"; other axes may move meanwhile. While the axis
 *                        moves on its own, a new target continues from its speed, as on the single-
 *                        axis sketches (docs/serial.md): the replaced move gets no DONE; if every step
 *                        is already queued: "OK <a> <old target> <to> (after DONE <a> <old target>)".
 *   move <a><t> ...      coordinated move of the named axes (each once, e.g. "move x1000 y-500 z20"):
 *                        all start on one tick and end on one tick on the straight line
 *                        (lib/src/step_coord.h); each axis's vmax and accel hold. "OK move x <from> <to>
 *                        y <from> <to> ...", later one "DONE move x <pos> y <pos> ...". Refused
 *                        ("ERR busy ...") while a named axis is moving; axes not named may move.
 *                        Every named axis belongs to the move until its DONE, one already at its
 *                        target too: a target for it meanwhile gets "ERR busy", `stop <it>` stops the move.
 *                        Every named axis at its target already: "OK move ..." and "DONE move ..." at
 *                        once, nothing moves (as "x 0" at 0).
 *   stop | !             every axis: decelerate to rest / halt at once: "OK stop" / "OK halt", then
 *                        the DONE of each move that was running ("OK stop (not moving)" when none)
 *   stop <a> | ! <a>     one axis; an axis of a coordinated move stops the whole move (all its axes)
 *   ?                    one line per axis: "<a> pos= target= state=idle|accel|cruise|decel
 *                        mode=idle|alone|move algo= v0= vmax= accel= tick_hz= max_sps= underruns= late="
 *   set <a> <key> <val>  "OK <a> <key>=<value>" (keys v0 vmax accel; vmax up to max_sps); while the
 *                        axis moves: " (from the next plan)"
 *   READY <SketchName>   printed once at the end of setup
 * Anything else gets "ERR <reason>" and changes nothing (no axis moves).
 */
#ifndef MULTI_AXIS_CONSOLE_H
#define MULTI_AXIS_CONSOLE_H

#include <step_coord.h>

#include "StepConsole.h"

/* An axis's part of the coordinated move, as a command source's context. */
struct AxisCoordRef {
    step_coord_t *coord;
    uint8_t axis;
    uint8_t repeats; /* the master this axis follows (it moves as far: same step times), or 0xFF */
    uint8_t clones;  /* master: the axes that follow it (bit i: axis i) */
};

/* The coordinated move (`move x<t> y<t> z<t>`): lib's step_coord.h plans it, every axis starts on
 * one tick (MultiStepEngine::start_together), an axis moving as far as the master follows it. */
class MultiAxisCoord : public StepConsoleCoord {
public:
    MultiAxisCoord();
    AxisSource source(uint8_t axis) override;
    void handle_move(StepConsole &c, const char *cursor) override;
    void axis_done(StepConsole &c, uint8_t axis, int32_t pos) override;
    void stop(StepConsole &c, bool halt) override;
    void start_if_ready() override;
    int32_t position_of(uint8_t axis) override;
    int32_t target_of(uint8_t axis) override;

private:
    void print_positions(Print &out, bool with_from);
    int32_t follower_position(uint8_t axis, int32_t master_pos);

    step_coord_t coord_;
    AxisCoordRef ctx_[MULTI_AXES];
    uint8_t own_;     /* of those, the axes stepped by their own interrupt (the others follow one) */
    uint8_t done_;    /* axes of the move that have ended */
    bool starting_;   /* held, waiting for every axis's first commands */
    int32_t end_[MULTI_AXES];
};

class MultiAxisConsole : public StepConsole {
public:
    MultiAxisConsole(StepperRamp &x, StepperRamp &y, StepperRamp &z) : StepConsole(MULTI_AXES, ramps_, planners_, &coord_)
    {
        ramps_[0] = &x;
        ramps_[1] = &y;
        ramps_[2] = &z;
    }

    /* Serial at 9600 baud, the engine (X, Y, Z at 16 MHz), the planners; prints "READY <name>". */
    void begin(const __FlashStringHelper *sketch_name)
    {
        MultiStepEngine::begin(MULTI_TICK_HZ, MULTI_AXES_ALL);
        begin_console(sketch_name);
    }

private:
    StepperRamp *ramps_[MULTI_AXES];
    step_planner_t planners_[MULTI_AXES];
    MultiAxisCoord coord_;
};

#endif
