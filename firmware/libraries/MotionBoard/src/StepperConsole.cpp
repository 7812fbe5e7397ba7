/* StepperConsole.cpp - the stepper sketches' serial protocol (see StepperConsole.h). */
#include "StepperConsole.h"

#include <line_reader.h>
#include <text_parse.h>

static step_planner_t *s_fed; /* the planner stepper_print_hook keeps feeding */
static void keep_fed()
{
    StepEngine::service(*s_fed);
}

void StepperConsole::begin(const __FlashStringHelper *sketch_name)
{
    s_fed = &planner_;
    stepper_print_hook = keep_fed;
    Serial.begin(9600);
    serial_.set_rx_interrupt(false); /* poll() drains the input on every pass (SerialRx.h) */
    StepEngine::begin(ramp_.tick_hz(), ramp_.lead_ms());
    (void)ramp_.setup(planner_, StepEngine::position());
#if STEPPER_TIMED_LOOP
    /* one step per command: each planner call is one ramp step (about 100 us), so the planner
     * fits between two deadlines of loop()'s stepping */
    planner_.max_cmd_ticks = 1;
    planner_.exact.max_cmd_ticks = 1;
#endif
    serial_.out().print(F("READY "));
    serial_.out().println(sketch_name);
}

void StepperConsole::report_done(int32_t position)
{
    Print &out = serial_.out();
    out.print(F("DONE "));
    out.println(position);
    ramp_.at_rest(planner_, position);
}

void StepperConsole::poll()
{
    int32_t done_at;
    const char *line;
    bool refilling;
    StepEngine::poll();
    StepEngine::service(planner_);
    if (StepEngine::take_done(done_at)) {
        report_done(done_at);
        next_due_ = has_next_;
    }
    queue_.pump();
    /* the S-curve table's refill, a slice per pass: a target waits for it (handle_target), and so
     * do the lines after it (a `?` then tells where that move has got, as it would without a refill) */
    refilling = ramp_.busy(planner_);
    if (refilling && next_due_) {
        serial_.drain_input();
        queue_.pump();
        return;
    }
    if (next_due_) {
        /* the target accepted while the last steps ran (or during the refill): it starts now, from rest */
        next_due_ = false;
        has_next_ = false;
        step_planner_halt(&planner_, StepEngine::position());
        if (step_planner_move(&planner_, next_target_) == MS_OK)
            StepEngine::open_move();
    }
    line = serial_.poll();
    if (line != NULL)
        handle(line);
    StepEngine::service(planner_);
    queue_.pump();
}

void StepperConsole::handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1];
    int n = text_next_word(&cursor, word, sizeof word);
    if (n == 0)
        return; /* a line of blanks: nothing to do */
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes no arguments"));
        else
            reply_status();
    } else if (text_word_is(word, "set")) {
        handle_set(cursor);
    } else if (text_word_is(word, "stop") || text_word_is(word, "!")) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("stop and ! take no arguments"));
        else
            handle_stop(word[0] == '!');
    } else if ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+') {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target(word);
    } else {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <target>, stop, !, ?, set v0|vmax|accel <value>"));
    }
}

void StepperConsole::handle_target(const char *word)
{
    int32_t to, from, ended;
    motion_status_t st = text_parse_whole(word, INT32_MIN, INT32_MAX, &to);
    StepEngine::Continuation c;
    if (st != MS_OK) {
        serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
        return;
    }
    if (StepEngine::moving() && !step_planner_busy(&planner_)) {
        /* every step of the move is queued: it ends at rest at its target, with its DONE; the new
         * move follows from there (a target sent meanwhile replaces this one, with no DONE) */
        from = step_planner_target(&planner_);
        has_next_ = true;
        next_target_ = to;
        serial_.out().print(F("OK "));
        serial_.out().print(from);
        serial_.out().print(' ');
        serial_.out().print(to);
        serial_.out().print(F(" (after DONE "));
        serial_.out().print(from);
        serial_.out().println(')');
        return;
    }
    c = StepEngine::extend(ended);
    if (c == StepEngine::ENDED) {
        report_done(ended); /* the move that just ended gets its DONE before the new OK */
        c = StepEngine::AT_REST;
    }
    if (c == StepEngine::AT_REST && ramp_.busy(planner_)) {
        /* the move that just ended started a refill of the S-curve table: this move starts from
         * here when the table is ready (poll()), a few passes from now */
        has_next_ = true;
        next_due_ = true;
        next_target_ = to;
        from = StepEngine::position();
        serial_.out().print(F("OK "));
        serial_.out().print(from);
        serial_.out().print(' ');
        serial_.out().println(to);
        return;
    }
    if (c == StepEngine::AT_REST)
        step_planner_halt(&planner_, StepEngine::position()); /* at rest where the axis is */
    st = step_planner_move(&planner_, to);
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    if (c == StepEngine::AT_REST)
        StepEngine::open_move();
    /* where the new plan starts: the position after the steps already handed to the queue */
    from = step_planner_position(&planner_);
    serial_.out().print(F("OK "));
    serial_.out().print(from);
    serial_.out().print(' ');
    serial_.out().println(to);
    StepEngine::service(planner_);
}

void StepperConsole::handle_stop(bool halt)
{
    int32_t ended;
    Print &out = serial_.out();
    StepEngine::Continuation c;
    has_next_ = false; /* a target waiting for the move's end is dropped */
    next_due_ = false;
    c = StepEngine::extend(ended);
    if (c == StepEngine::ENDED)
        report_done(ended);
    if (c != StepEngine::CONTINUES) {
        out.println(halt ? F("OK halt (not moving)") : F("OK stop (not moving)"));
        return;
    }
    if (halt) {
        StepEngine::halt();
        step_planner_halt(&planner_, StepEngine::position());
        out.println(F("OK halt"));
        if (StepEngine::take_done(ended))
            report_done(ended);
    } else {
        step_planner_stop(&planner_);
        out.println(F("OK stop"));
    }
}

void StepperConsole::handle_set(const char *cursor)
{
    char key[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1];
    motion_status_t st;
    bool moving = StepEngine::moving();
    Print &out = serial_.out();
    if (text_next_word(&cursor, key, sizeof key) <= 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set what? set <parameter> <value>"));
        return;
    }
    if (text_next_word(&cursor, value, sizeof value) <= 0) {
        serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("set <parameter> <value>: the value is missing"));
        return;
    }
    if (!text_at_end(cursor)) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set takes one parameter and one value"));
        return;
    }
    st = ramp_.set(key, value);
    if (st == MS_ERR_UNKNOWN_COMMAND) {
        serial_.reply_error(st, F("no such parameter (see ?)"));
        return;
    }
    if (st == MS_ERR_OUT_OF_RANGE) {
        /* "ERR number out of range: vmax at most 5000 steps/s on this sketch" */
        ramp_.print_limit(serial_.begin_error(st), key);
        out.println();
        return;
    }
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    (void)ramp_.apply(planner_, moving);
    out.print(F("OK "));
    ramp_.print_param(out, key);
    if (moving)
        out.print(F(" (from the next plan)"));
    out.println();
}

void StepperConsole::reply_status()
{
    Print &out = serial_.out();
    bool moving = StepEngine::moving();
    uint8_t phase = StepEngine::phase();
    out.print(F("pos="));
    out.print(StepEngine::position());
    out.print(F(" target="));
    out.print(has_next_ ? next_target_ : step_planner_target(&planner_));
    out.print(F(" state="));
    out.print(ramp_phase_name(moving && phase != 0 ? (ramp_phase_t)phase : (moving ? RAMP_ACCEL : RAMP_IDLE)));
    ramp_.print_params(out);
    out.print(F(" underruns="));
    out.print(StepEngine::underruns());
    out.print(F(" late="));
    out.print(StepEngine::late_edges());
#if STEPPER_TIMED_LOOP
    out.println(F(" mode=loop"));
#else
    out.println(F(" mode=timer"));
#endif
}
