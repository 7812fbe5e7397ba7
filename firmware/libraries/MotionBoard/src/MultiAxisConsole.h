/* MultiAxisConsole.h - MultiAxisStepper's serial protocol (9600 baud, lines ending in CR, LF or
 * CRLF, through MotionSerial; replies through a SerialOutQueue, so printing never holds up the
 * planners). The axes are x, y and z; <a> below is one of them.
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

#include <Arduino.h>

#include <step_coord.h>
#include <step_planner.h>

#include "MotionSerial.h"
#include "MultiStepEngine.h"
#include "SerialOutQueue.h"
#include "StepperRamps.h"

/* An axis's part of the coordinated move, as a command source's context. */
struct AxisCoordRef {
    step_coord_t *coord;
    uint8_t axis;
    uint8_t repeats; /* the master this axis follows (it moves as far: same step times), or 0xFF */
    uint8_t clones;  /* master: the axes that follow it (bit i: axis i) */
};

class MultiAxisConsole {
public:
    MultiAxisConsole(TrapezoidRamp &x, TrapezoidRamp &y, TrapezoidRamp &z);

    /* Serial at 9600 baud, the engine's pins and timer, the planners; prints "READY <name>". */
    void begin(const __FlashStringHelper *sketch_name);

    /* Call on every pass of loop(): feeds the step queues, reports DONEs, handles command lines. */
    void poll();

    /* Lays out step commands for every axis (what poll() does first; also called while slow
     * replies are formatted). */
    void feed();

private:
    AxisSource source(uint8_t axis);
    void handle(const char *line);
    void handle_target(uint8_t axis, const char *word);
    void handle_move(const char *cursor);
    void handle_stop(const char *cursor, bool halt);
    void handle_set(uint8_t axis, const char *cursor);
    void print_status(uint8_t axis);
    void report_done(uint8_t axis, int32_t position);
    void collect_done();
    void print_coord_positions(Print &out, bool with_from);
    int32_t follower_position(uint8_t axis, int32_t master_pos);
    int32_t position_of(uint8_t axis);

    TrapezoidRamp *ramp_[MULTI_AXES];
    step_planner_t planner_[MULTI_AXES];
    step_coord_t coord_;
    AxisCoordRef coord_ctx_[MULTI_AXES];
    uint8_t coord_named_;   /* axes named in the coordinated move (reported in OK/DONE) */
    uint8_t coord_mask_;    /* of those, the axes that move (fed from coord_) */
    uint8_t coord_own_;     /* of those, the axes stepped by their own interrupt (the others follow one) */
    uint8_t coord_done_;    /* axes of the move that have ended */
    bool coord_starting_;   /* held, waiting for every axis's first commands */
    int32_t coord_end_[MULTI_AXES];
    bool has_next_[MULTI_AXES];
    int32_t next_target_[MULTI_AXES];
    uint8_t status_pending_; /* axes whose `?` line is still to print */
    SerialOutQueue queue_;   /* before serial_, which is built on it */
    MotionSerial serial_;
};

#endif
