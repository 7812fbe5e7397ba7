/* StepConsole.cpp - the stepper sketches' console for one to three axes (see StepConsole.h). */
#include "StepConsole.h"

#include <line_reader.h>
#include <StepCut.h>
#include <text_parse.h>

/* The cut's timing on the sketches (StepCut.h; the library's is MOTION_STEPPER_CUT_*, for up to 25,000
 * steps/s). Here an axis steps up to max_sps (60,000 steps/s on ExactRampStepper), where the step
 * interrupt takes half the processor: the cut is made only if the interrupt is still
 * 200 us + 15 us per 1,000 steps/s from it (dropping the old commands and laying out the first new
 * one takes a few thousand cycles, and the interrupt slows them down; with 200 us alone it reached
 * the cut first at 60,000 steps/s, accel 1e6, checks_reliability.py's corners: an underrun); and the
 * new plan's first 3 ms of steps (at most 4 commands) are laid out at once: loop() may be busy that
 * long elsewhere before it feeds the axis again (with 1 ms, `make fuzz` seed 7 found a step 1 ms late
 * on MultiAxisStepper after a cut at 5,000 steps/s). A target behind is cut only if its stop lasts
 * 65 ms or more: with three axes stepping fast (x 25,000 steps/s, y 8,000, z 4,000 at accels of
 * 100,000-300,000) a reversal of z whose stop lasted 38 ms was followed by edges of every axis up to
 * 0.7 ms late (make fuzz seed 9; not understood yet: docs/stepper-engine.md "Cutting the queue"). */
/* No cut above this speed (steps/s): the stop or the new target acts after the queued lead, as
 * before. Up to it `make fuzz` found nothing (seeds 7-10 at ExactRampStepper's former 60,000 limit);
 * at 89,000 steps/s a target behind cut the queue and the axis stalled 12.6 ms (seed 11), where the
 * step interrupt leaves the planner a quarter of the processor and the queue's lead is what keeps
 * it ahead. */
#ifndef STEP_CONSOLE_CUT_MAX_SPS
#define STEP_CONSOLE_CUT_MAX_SPS 60000.0f
#endif
#ifndef STEP_CONSOLE_CUT_THEN_MIN_US
#define STEP_CONSOLE_CUT_THEN_MIN_US MOTION_STEPPER_CUT_THEN_MIN_US
#endif
/* the margin's fixed part, us (a check builds it with 0: cut_apply must then refuse or switch
 * cleanly however close the interrupt has come) */
#ifndef STEP_CONSOLE_CUT_MARGIN_US
#define STEP_CONSOLE_CUT_MARGIN_US 200U
#endif
/* how far ahead the cut lands, us: a stop from the cruise; a stop while the speed changes or a new
 * target 1 ms farther */
#ifndef STEP_CONSOLE_CUT_AHEAD_US
#define STEP_CONSOLE_CUT_AHEAD_US 5000U
#endif
static const StepCutTiming CONSOLE_CUT = {16, STEP_CONSOLE_CUT_AHEAD_US, STEP_CONSOLE_CUT_AHEAD_US + 1000U, STEP_CONSOLE_CUT_MARGIN_US, 3000, 4, STEP_CONSOLE_CUT_THEN_MIN_US, 0};

static const char AXIS_NAME[MULTI_AXES] = {'x', 'y', 'z'};

static StepConsole *s_fed; /* the console stepper_print_hook keeps feeding */
static void keep_fed()
{
    s_fed->feed();
}

/* an axis's own planner as a command source */
static uint8_t planner_next(void *ctx, step_cmd_t *c)
{
    return step_planner_next(static_cast<step_planner_t *>(ctx), c);
}
static uint8_t planner_busy(void *ctx)
{
    return step_planner_busy(static_cast<step_planner_t *>(ctx));
}

/* "x" -> 0 ... ; -1 for anything else */
static int8_t axis_of(const char *word)
{
    if (word[0] == '\0' || word[1] != '\0')
        return -1;
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        if (word[0] == AXIS_NAME[i])
            return (int8_t)i;
    return -1;
}

StepConsole::StepConsole(uint8_t axes, StepperRamp **ramps, step_planner_t *planners, StepConsoleCoord *coord)
    : n_(axes), ramp_(ramps), pl_(planners), co_(coord), status_pending_(0), cuts_missed_(0), queue_(Serial), serial_(Serial, queue_, 240)
{
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        has_next_[i] = false;
        next_due_[i] = false;
        next_target_[i] = 0;
    }
}

void StepConsole::begin_console(const __FlashStringHelper *sketch_name)
{
    s_fed = this;
    stepper_print_hook = keep_fed;
    Serial.begin(9600);
    serial_.set_rx_interrupt(false); /* poll() drains the input on every pass (SerialRx.h) */
    MultiStepEngine::set_lead_ms(ramp_[0]->lead_ms());
    MultiStepEngine::set_led_mirror(n_ == 1 && STEPPER_LED_MIRROR);
    for (uint8_t i = 0; i < n_; i++) {
        (void)ramp_[i]->setup(pl_[i], MultiStepEngine::position(i));
#if STEPPER_TIMED_LOOP
        /* one step per command: each planner call is one ramp step (about 100 us), so the planner
         * fits between two deadlines of loop()'s stepping */
        pl_[i].max_cmd_ticks = 1;
        if (pl_[i].algo == RAMP_ALGO_EXACT)
            pl_[i].exact.max_cmd_ticks = 1;
#endif
    }
    serial_.out().print(F("READY "));
    serial_.out().println(sketch_name);
}

AxisSource StepConsole::source(uint8_t axis)
{
    AxisSource s;
    if (coord_mask() & (1U << axis))
        return co_->source(axis);
    s.next = planner_next;
    s.busy = planner_busy;
    s.ctx = &pl_[axis];
    return s;
}

void StepConsole::feed()
{
    uint8_t dry = 0; /* axes whose planner has nothing to hand out now */
    if (n_ == 1) {
        /* one axis: as many commands as its queue needs, up to a move's start-up batch per call (the
         * lab's ramps plan every step, near their top rate with little time to spare) */
        (void)MultiStepEngine::service(0, source(0), MULTI_START_SLOTS);
        return;
    }
    /* one command at a time to the axis whose queue reaches least far ahead (at the end of a
     * coordinated move every axis needs many at once), a bounded number per call */
    for (uint8_t k = 0; k < 12U; k++) {
        uint32_t best = UINT32_MAX, most = 0;
        uint8_t pick = MULTI_AXES, start = MULTI_AXES;
        MultiStepEngine::poll(); /* the timed-loop build steps here, between two plans */
        for (uint8_t i = 0; i < n_; i++) {
            uint32_t q;
            if ((dry & (1U << i)) || !MultiStepEngine::moving(i))
                continue;
            q = MultiStepEngine::queued_ticks(i);
            if (q == UINT32_MAX)
                continue; /* needs nothing now */
            if (MultiStepEngine::stepping(i)) {
                if (q < best) {
                    best = q;
                    pick = i;
                }
            } else if (start == MULTI_AXES || q > most) {
                most = q;
                start = i;
            }
        }
        /* a move being started (the one nearest its start first) only when no stepping axis needs a
         * command: starting a move never starves one that runs */
        if (pick == MULTI_AXES)
            pick = start;
        if (pick == MULTI_AXES)
            break;
        if (MultiStepEngine::service(pick, source(pick), 1) == 0)
            dry |= (uint8_t)(1U << pick);
    }
    for (uint8_t i = 0; i < n_; i++)
        (void)MultiStepEngine::service(i, source(i), 0); /* starts and ends */
    if (co_)
        co_->start_if_ready();
}

void StepConsole::print_axis(Print &out, uint8_t axis)
{
    if (n_ == 1)
        return;
    out.print(AXIS_NAME[axis]);
    out.print(' ');
}

void StepConsole::print_ok(uint8_t axis, int32_t from, int32_t to)
{
    Print &out = serial_.out();
    out.print(F("OK "));
    print_axis(out, axis);
    out.print(from);
    out.print(' ');
    out.print(to);
}

void StepConsole::report_done(uint8_t axis, int32_t position)
{
    Print &out = serial_.out();
    if (coord_mask() & (1U << axis)) {
        co_->axis_done(*this, axis, position);
        return;
    }
    out.print(F("DONE "));
    print_axis(out, axis);
    out.println(position);
    step_planner_halt(&pl_[axis], position);
    ramp_[axis]->at_rest(pl_[axis], position); /* the S-curve table's refill, if a `set` waits for it */
    next_due_[axis] = has_next_[axis];
}

/* Room the DONE lines of one pass need in the output queue: "DONE move x -2147483648 y -2147483648
 * z -2147483648" and CR LF is 53 bytes, three "DONE x -2147483648" lines 60, a two-axis move's and
 * the third axis's 59. A DONE whose line would not fit waits in the engine (make fuzz seed 23: a
 * DONE move taken while three `?` lines filled the queue lost its last 14 bytes, and the `OK` of
 * the next line was glued to it). */
#define STEP_CONSOLE_DONE_ROOM 64U

bool StepConsole::collect_done()
{
    int32_t at;
    if (queue_.room() < STEP_CONSOLE_DONE_ROOM) {
        for (uint8_t i = 0; i < n_; i++)
            if (MultiStepEngine::done_pending(i))
                return false; /* it waits for the queue: no `?` line or command is taken before it */
        return true;
    }
    for (uint8_t i = 0; i < n_; i++)
        if (MultiStepEngine::take_done(i, at))
            report_done(i, at);
    return true;
}

bool StepConsole::cut_plan(uint8_t axis, bool stop, int32_t target, int32_t &from)
{
    StepperRamp::CutFn f = ramp_[axis]->cut();
    StepCutTiming t = CONSOLE_CUT; /* the exact ramp, the one that cuts, steps at 16 MHz */
    float v = fabs(MultiStepEngine::speed(axis));
    if (!f || v > STEP_CONSOLE_CUT_MAX_SPS)
        return false;
#if STEP_CONSOLE_CUT_MARGIN_US
    t.margin_us = (uint16_t)(t.margin_us + v * 0.015f);
#endif
    return f(axis, &pl_[axis], stop, target, t, &from, &cuts_missed_);
}

/* the target accepted while the last steps ran (or during a refill): its move starts now, from rest */
void StepConsole::start_next(uint8_t axis)
{
    next_due_[axis] = false;
    has_next_[axis] = false;
    step_planner_halt(&pl_[axis], MultiStepEngine::position(axis));
    if (step_planner_move(&pl_[axis], next_target_[axis]) == MS_OK)
        MultiStepEngine::open_move(axis, false);
}

void StepConsole::poll()
{
    const char *line;
    bool waiting = false;
    feed();
    if (!collect_done()) {
        serial_.drain_input();
        queue_.pump();
        return;
    }
    queue_.pump();
    /* the S-curve table's refill, a slice per pass: a target waits for it (handle_target), and so
     * do the lines after it (a `?` then tells where that move has got, as it would without a refill) */
    for (uint8_t i = 0; i < n_; i++) {
        if (ramp_[i]->busy(pl_[i])) {
            if (next_due_[i])
                waiting = true;
        } else if (next_due_[i]) {
            start_next(i);
        }
    }
    if (waiting) {
        serial_.drain_input();
        queue_.pump();
        return;
    }
    if (status_pending_ != 0) {
        /* the `?` lines, one at a time as the output queue has room (each about 140 bytes) */
        serial_.drain_input(); /* no line is read meanwhile, but input must not pile up in the core */
        for (uint8_t i = 0; i < n_; i++) {
            if ((status_pending_ & (1U << i)) && queue_.room() >= 160U) {
                print_status(i);
                status_pending_ &= (uint8_t)~(1U << i);
            }
            if (status_pending_ & (1U << i))
                break;
        }
    } else {
        line = serial_.poll();
        if (line != NULL)
            handle(line);
    }
    feed();
    queue_.pump();
}

void StepConsole::handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1];
    int8_t axis = 0;
    int n = text_next_word(&cursor, word, sizeof word);
    if (n == 0)
        return; /* a line of blanks: nothing to do */
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes no arguments"));
        else
            status_pending_ = (uint8_t)((1U << n_) - 1U);
    } else if (text_word_is(word, "set")) {
        char a[LINE_READER_MAX + 1];
        if (n_ > 1 && (text_next_word(&cursor, a, sizeof a) <= 0 || (axis = axis_of(a)) < 0))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set <x|y|z> <v0|vmax|accel> <value>"));
        else
            handle_set((uint8_t)axis, cursor); /* one axis: no axis word */
    } else if (text_word_is(word, "stop") || text_word_is(word, "!")) {
        handle_stop(cursor, word[0] == '!');
    } else if (co_ && text_word_is(word, "move")) {
        co_->handle_move(*this, cursor);
    } else if (n_ == 1 && ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+')) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target(0, word);
    } else if (n_ > 1 && (axis = axis_of(word)) >= 0) {
        char t[LINE_READER_MAX + 1];
        if (text_next_word(&cursor, t, sizeof t) <= 0)
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("<axis> <target>: the target is missing"));
        else if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target((uint8_t)axis, t);
    } else if (n_ == 1) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <target>, stop, !, ?, set v0|vmax|accel <value>"));
    } else {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND,
                            F("try x|y|z <target>, move x<t> y<t> z<t>, stop [axis], ! [axis], ?, set <axis> <key> <value>"));
    }
}

void StepConsole::handle_target(uint8_t axis, const char *word)
{
    int32_t to, from, ended;
    motion_status_t st = text_parse_whole(word, INT32_MIN, INT32_MAX, &to);
    step_planner_t &pl = pl_[axis];
    Print &out = serial_.out();
    MultiStepEngine::Continuation c;
    if (st != MS_OK) {
        serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
        return;
    }
    if (coord_named() & (1U << axis)) {
        serial_.reply_error(MS_ERR_BUSY, F("the axis is in a coordinated move (stop it first, or wait for its DONE)"));
        return;
    }
    if (MultiStepEngine::moving(axis) && cut_plan(axis, false, to, from)) {
        /* the move continues into the new plan from a cut a few milliseconds ahead */
        has_next_[axis] = false;
        next_due_[axis] = false;
        print_ok(axis, from, to);
        out.println();
        feed();
        return;
    }
    if (MultiStepEngine::moving(axis) && !step_planner_busy(&pl)) {
        /* every step of the move is queued: it ends at rest at its target, with its DONE; the new
         * move follows from there (a target sent meanwhile replaces this one, with no DONE) */
        from = step_planner_target(&pl);
        has_next_[axis] = true;
        next_due_[axis] = false;
        next_target_[axis] = to;
        print_ok(axis, from, to);
        out.print(F(" (after DONE "));
        print_axis(out, axis);
        out.print(from);
        out.println(')');
        return;
    }
    c = MultiStepEngine::extend(axis, ended);
    if (c == MultiStepEngine::ENDED) {
        report_done(axis, ended); /* the move that just ended gets its DONE before the new OK */
        c = MultiStepEngine::AT_REST;
    }
    if (c == MultiStepEngine::AT_REST && ramp_[axis]->busy(pl)) {
        /* the move that just ended started a refill of the S-curve table: this move starts from
         * here when the table is ready (poll()), a few passes from now */
        has_next_[axis] = true;
        next_due_[axis] = true;
        next_target_[axis] = to;
        from = MultiStepEngine::position(axis);
    } else {
        has_next_[axis] = false; /* a move that ended replaces the one that waited for it */
        next_due_[axis] = false;
        if (c == MultiStepEngine::AT_REST)
            step_planner_halt(&pl, MultiStepEngine::position(axis)); /* at rest where the axis is */
        st = step_planner_move(&pl, to);
        if (st != MS_OK) {
            serial_.reply_error(st);
            return;
        }
        if (c == MultiStepEngine::AT_REST)
            MultiStepEngine::open_move(axis, false);
        /* where the new plan starts: the position after the steps already handed to the queue */
        from = step_planner_position(&pl);
    }
    print_ok(axis, from, to);
    out.println();
    feed();
}

void StepConsole::handle_stop(const char *cursor, bool halt)
{
    char word[LINE_READER_MAX + 1];
    uint8_t mask = (uint8_t)((1U << n_) - 1U), running = 0, stopping = 0;
    Print &out = serial_.out();
    int n = text_next_word(&cursor, word, sizeof word);
    if (n != 0 && n_ == 1) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("stop and ! take no arguments"));
        return;
    }
    if (n != 0) {
        int8_t axis = n > 0 ? axis_of(word) : -1;
        if (axis < 0 || !text_at_end(cursor)) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("stop [x|y|z], ! [x|y|z]"));
            return;
        }
        mask = (uint8_t)(1U << axis);
    }
    collect_done(); /* moves that have just ended report first */
    if (mask & coord_named())
        mask |= coord_mask(); /* an axis of the coordinated move stops the whole move */
    for (uint8_t i = 0; i < n_; i++) {
        if (!(mask & (1U << i)))
            continue;
        has_next_[i] = false; /* a target waiting for the move's end is dropped */
        next_due_[i] = false;
        if (MultiStepEngine::moving(i))
            running |= (uint8_t)(1U << i);
    }
    if (running & coord_mask()) {
        co_->stop(*this, halt);
        stopping |= coord_mask();
    }
    for (uint8_t i = 0; i < n_; i++) {
        int32_t ended;
        if (!(running & (1U << i)) || (coord_mask() & (1U << i)))
            continue;
        if (halt) {
            MultiStepEngine::halt(i);
            step_planner_halt(&pl_[i], MultiStepEngine::position(i));
            stopping |= (uint8_t)(1U << i);
        } else if (MultiStepEngine::extend(i, ended) == MultiStepEngine::CONTINUES) {
            int32_t from;
            if (!cut_plan(i, true, 0, from)) /* decelerating from a cut a few ms ahead, else after the lead */
                step_planner_stop(&pl_[i]);
            stopping |= (uint8_t)(1U << i);
        } else {
            report_done(i, ended); /* it ended just now */
        }
    }
    if (stopping == 0)
        out.println(halt ? F("OK halt (not moving)") : F("OK stop (not moving)"));
    else
        out.println(halt ? F("OK halt") : F("OK stop"));
    collect_done();
}

void StepConsole::handle_set(uint8_t axis, const char *cursor)
{
    char key[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1];
    motion_status_t st;
    bool moving = MultiStepEngine::moving(axis);
    Print &out = serial_.out();
    StepperRamp &r = *ramp_[axis];
    if (text_next_word(&cursor, key, sizeof key) <= 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, n_ == 1 ? F("set what? set <parameter> <value>")
                                                            : F("set <axis> what? set <x|y|z> <v0|vmax|accel> <value>"));
        return;
    }
    if (text_next_word(&cursor, value, sizeof value) <= 0) {
        serial_.reply_error(MS_ERR_NOT_A_NUMBER, n_ == 1 ? F("set <parameter> <value>: the value is missing")
                                                         : F("set <axis> <parameter> <value>: the value is missing"));
        return;
    }
    if (!text_at_end(cursor)) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, n_ == 1 ? F("set takes one parameter and one value")
                                                            : F("set takes one axis, one parameter and one value"));
        return;
    }
    st = r.set(key, value);
    if (st == MS_ERR_UNKNOWN_COMMAND) {
        serial_.reply_error(st, n_ == 1 ? F("no such parameter (see ?)") : F("no such parameter (v0, vmax, accel)"));
        return;
    }
    if (st == MS_ERR_OUT_OF_RANGE) {
        /* "ERR number out of range: vmax at most 5000 steps/s on this sketch" */
        r.print_limit(serial_.begin_error(st), key);
        out.println();
        return;
    }
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    (void)r.apply(pl_[axis], moving);
    out.print(F("OK "));
    print_axis(out, axis);
    r.print_param(out, key);
    if (moving)
        out.print(F(" (from the next plan)"));
    out.println();
}

void StepConsole::print_status(uint8_t axis)
{
    Print &out = serial_.out();
    bool moving = MultiStepEngine::moving(axis);
    bool in_move = (coord_named() & (1U << axis)) != 0;
    uint8_t phase = MultiStepEngine::phase(axis);
    print_axis(out, axis);
    out.print(F("pos="));
    out.print(in_move ? co_->position_of(axis) : MultiStepEngine::position(axis));
    out.print(F(" target="));
    out.print(in_move ? co_->target_of(axis) : (has_next_[axis] ? next_target_[axis] : step_planner_target(&pl_[axis])));
    out.print(F(" state="));
    out.print(ramp_phase_name(moving && phase != 0 ? (ramp_phase_t)phase : (moving ? RAMP_ACCEL : RAMP_IDLE)));
    if (n_ > 1) {
        out.print(F(" mode="));
        out.print(in_move ? F("move") : (moving ? F("alone") : F("idle")));
    }
    ramp_[axis]->print_params(out);
    out.print(F(" underruns="));
    out.print(MultiStepEngine::underruns(axis));
    out.print(F(" late="));
    out.print(MultiStepEngine::late_edges(axis));
    if (n_ == 1)
        out.print(STEPPER_TIMED_LOOP ? F(" mode=loop") : F(" mode=timer"));
    out.println();
}
