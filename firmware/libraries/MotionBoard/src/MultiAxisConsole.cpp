/* MultiAxisConsole.cpp - MultiAxisStepper's serial protocol (see MultiAxisConsole.h). */
#include "MultiAxisConsole.h"

#include <line_reader.h>
#include <text_parse.h>

static const char AXIS_NAME[MULTI_AXES] = {'x', 'y', 'z'};

static MultiAxisConsole *s_fed; /* the console stepper_print_hook keeps feeding */
static void keep_fed()
{
    s_fed->feed();
}

/* the two kinds of command source: an axis's own planner, or its part of the coordinated move */
static uint8_t planner_next(void *ctx, step_cmd_t *c)
{
    return step_planner_next(static_cast<step_planner_t *>(ctx), c);
}
static uint8_t planner_busy(void *ctx)
{
    return step_planner_busy(static_cast<step_planner_t *>(ctx));
}
static uint8_t coord_next(void *ctx, step_cmd_t *c)
{
    AxisCoordRef *r = static_cast<AxisCoordRef *>(ctx);
    if (r->repeats != 0xFF)
        return 0; /* it follows another axis's interrupt: no commands of its own */
    return step_coord_next(r->coord, r->axis, c);
}
static uint8_t coord_busy(void *ctx)
{
    AxisCoordRef *r = static_cast<AxisCoordRef *>(ctx);
    return step_coord_busy(r->coord, r->repeats != 0xFF ? r->repeats : r->axis);
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

MultiAxisConsole::MultiAxisConsole(TrapezoidRamp &x, TrapezoidRamp &y, TrapezoidRamp &z)
    : coord_named_(0), coord_mask_(0), coord_own_(0), coord_done_(0), coord_starting_(false), status_pending_(0), queue_(Serial),
      serial_(Serial, queue_, 240)
{
    ramp_[0] = &x;
    ramp_[1] = &y;
    ramp_[2] = &z;
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        coord_ctx_[i].coord = &coord_;
        coord_ctx_[i].axis = i;
        coord_ctx_[i].repeats = 0xFF;
        coord_ctx_[i].clones = 0;
        has_next_[i] = false;
        next_target_[i] = 0;
        coord_end_[i] = 0;
    }
}

void MultiAxisConsole::begin(const __FlashStringHelper *sketch_name)
{
    s_fed = this;
    stepper_print_hook = keep_fed;
    Serial.begin(9600);
    serial_.set_rx_interrupt(false); /* poll() drains the input on every pass (SerialRx.h) */
    MultiStepEngine::begin();
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        (void)ramp_[i]->setup(planner_[i], MultiStepEngine::position(i));
    serial_.out().print(F("READY "));
    serial_.out().println(sketch_name);
}

AxisSource MultiAxisConsole::source(uint8_t axis)
{
    AxisSource s;
    if (coord_mask_ & (1U << axis)) {
        s.next = coord_next;
        s.busy = coord_busy;
        s.ctx = &coord_ctx_[axis];
    } else {
        s.next = planner_next;
        s.busy = planner_busy;
        s.ctx = &planner_[axis];
    }
    return s;
}

void MultiAxisConsole::feed()
{
    /* one command at a time to the axis whose queue reaches least far ahead (at the end of a
     * coordinated move every axis needs many at once), a bounded number per call */
    uint8_t dry = 0; /* axes whose planner has nothing to hand out now */
    for (uint8_t k = 0; k < 12; k++) {
        uint32_t best = UINT32_MAX, most = 0;
        uint8_t pick = MULTI_AXES, start = MULTI_AXES;
        for (uint8_t i = 0; i < MULTI_AXES; i++) {
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
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        (void)MultiStepEngine::service(i, source(i), 0); /* starts and ends */
    if (coord_starting_) {
        bool all = true;
        for (uint8_t i = 0; i < MULTI_AXES; i++)
            if ((coord_own_ & (1U << i)) && !MultiStepEngine::ready_to_start(i, source(i)))
                all = false;
        if (all) {
            MultiStepEngine::start_together(coord_own_);
            coord_starting_ = false;
        }
    }
}

/* " x <a> [<b>] y ..." for the axes in `named` (b: none when 0) */
static void print_axes(Print &out, uint8_t named, const int32_t *a, const int32_t *b)
{
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        if (!(named & (1U << i)))
            continue;
        out.print(' ');
        out.print(AXIS_NAME[i]);
        out.print(' ');
        out.print(a[i]);
        if (b) {
            out.print(' ');
            out.print(b[i]);
        }
    }
}

void MultiAxisConsole::print_coord_positions(Print &out, bool with_from)
{
    if (with_from)
        print_axes(out, coord_named_, coord_.from, coord_.to);
    else
        print_axes(out, coord_named_, coord_end_, 0);
}

void MultiAxisConsole::report_done(uint8_t axis, int32_t position)
{
    Print &out = serial_.out();
    if (coord_mask_ & (1U << axis)) {
        /* one axis of the coordinated move has ended: the move's DONE once all have */
        coord_end_[axis] = position;
        coord_done_ |= (uint8_t)(1U << axis);
        for (uint8_t i = 0; i < MULTI_AXES; i++) {
            if (coord_ctx_[axis].clones & (1U << i)) {
                /* its followers made as many steps, each in its own direction */
                coord_end_[i] = follower_position(i, position);
                MultiStepEngine::set_rest_position(i, coord_end_[i]);
                coord_done_ |= (uint8_t)(1U << i);
            }
        }
        if (coord_ctx_[axis].clones)
            MultiStepEngine::unfollow(axis);
        if (coord_done_ != coord_mask_)
            return;
        out.print(F("DONE move"));
        print_coord_positions(out, false);
        out.println();
        for (uint8_t i = 0; i < MULTI_AXES; i++) {
            if (coord_mask_ & (1U << i))
                step_planner_halt(&planner_[i], coord_end_[i]); /* at rest there, alone again */
            coord_ctx_[i].repeats = 0xFF;
            coord_ctx_[i].clones = 0;
        }
        coord_mask_ = 0;
        coord_own_ = 0;
        coord_named_ = 0;
        coord_done_ = 0;
        coord_starting_ = false;
        return;
    }
    out.print(F("DONE "));
    out.print(AXIS_NAME[axis]);
    out.print(' ');
    out.println(position);
    step_planner_halt(&planner_[axis], position);
    if (has_next_[axis]) {
        /* the target accepted while the last steps ran: its move starts now, from rest */
        has_next_[axis] = false;
        if (step_planner_move(&planner_[axis], next_target_[axis]) == MS_OK)
            MultiStepEngine::open_move(axis, false);
    }
}

void MultiAxisConsole::collect_done()
{
    int32_t at;
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        if (MultiStepEngine::take_done(i, at))
            report_done(i, at);
}

void MultiAxisConsole::poll()
{
    const char *line;
    feed();
    collect_done();
    queue_.pump();
    if (status_pending_ != 0) {
        /* the `?` lines, one at a time as the output queue has room (each about 140 bytes) */
        serial_.drain_input(); /* no line is read meanwhile, but input must not pile up in the core */
        for (uint8_t i = 0; i < MULTI_AXES; i++) {
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

void MultiAxisConsole::handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1];
    int8_t axis;
    int n = text_next_word(&cursor, word, sizeof word);
    if (n == 0)
        return; /* a line of blanks: nothing to do */
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes no arguments"));
        else
            status_pending_ = (uint8_t)((1U << MULTI_AXES) - 1U);
    } else if (text_word_is(word, "set")) {
        char a[LINE_READER_MAX + 1];
        if (text_next_word(&cursor, a, sizeof a) <= 0 || (axis = axis_of(a)) < 0)
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set <x|y|z> <v0|vmax|accel> <value>"));
        else
            handle_set((uint8_t)axis, cursor);
    } else if (text_word_is(word, "stop") || text_word_is(word, "!")) {
        handle_stop(cursor, word[0] == '!');
    } else if (text_word_is(word, "move")) {
        handle_move(cursor);
    } else if ((axis = axis_of(word)) >= 0) {
        char t[LINE_READER_MAX + 1];
        if (text_next_word(&cursor, t, sizeof t) <= 0)
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("<axis> <target>: the target is missing"));
        else if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target((uint8_t)axis, t);
    } else {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND,
                            F("try x|y|z <target>, move x<t> y<t> z<t>, stop [axis], ! [axis], ?, set <axis> <key> <value>"));
    }
}

void MultiAxisConsole::handle_target(uint8_t axis, const char *word)
{
    int32_t to, from, ended;
    motion_status_t st = text_parse_whole(word, INT32_MIN, INT32_MAX, &to);
    step_planner_t &pl = planner_[axis];
    Print &out = serial_.out();
    MultiStepEngine::Continuation c;
    if (st != MS_OK) {
        serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
        return;
    }
    if (coord_mask_ & (1U << axis)) {
        serial_.reply_error(MS_ERR_BUSY, F("the axis is in a coordinated move (stop it first, or wait for its DONE)"));
        return;
    }
    if (MultiStepEngine::moving(axis) && !step_planner_busy(&pl)) {
        /* every step of the move is queued: it ends at its target with its DONE, the new move follows */
        from = step_planner_target(&pl);
        has_next_[axis] = true;
        next_target_[axis] = to;
        out.print(F("OK "));
        out.print(AXIS_NAME[axis]);
        out.print(' ');
        out.print(from);
        out.print(' ');
        out.print(to);
        out.print(F(" (after DONE "));
        out.print(AXIS_NAME[axis]);
        out.print(' ');
        out.print(from);
        out.println(')');
        return;
    }
    c = MultiStepEngine::extend(axis, ended);
    if (c == MultiStepEngine::ENDED) {
        report_done(axis, ended); /* the move that just ended gets its DONE before the new OK */
        c = MultiStepEngine::AT_REST;
    }
    if (c == MultiStepEngine::AT_REST)
        step_planner_halt(&pl, MultiStepEngine::position(axis));
    st = step_planner_move(&pl, to);
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    if (c == MultiStepEngine::AT_REST)
        MultiStepEngine::open_move(axis, false);
    from = step_planner_position(&pl);
    out.print(F("OK "));
    out.print(AXIS_NAME[axis]);
    out.print(' ');
    out.print(from);
    out.print(' ');
    out.println(to);
    feed();
}

void MultiAxisConsole::handle_move(const char *cursor)
{
    char word[LINE_READER_MAX + 1];
    int32_t from[MULTI_AXES], to[MULTI_AXES];
    ramp_params_t p[MULTI_AXES];
    uint8_t named = 0, mask = 0;
    int n;
    motion_status_t st;
    while ((n = text_next_word(&cursor, word, sizeof word)) != 0) {
        int8_t axis = -1;
        int32_t t;
        for (uint8_t i = 0; n > 1 && i < MULTI_AXES; i++)
            if (word[0] == AXIS_NAME[i])
                axis = (int8_t)i;
        if (n < 0 || axis < 0) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("move x<target> y<target> z<target>, e.g. move x1000 y-500"));
            return;
        }
        if (named & (1U << axis)) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("an axis is named twice"));
            return;
        }
        st = text_parse_whole(word + 1, INT32_MIN, INT32_MAX, &t);
        if (st != MS_OK) {
            serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
            return;
        }
        named |= (uint8_t)(1U << axis);
        to[axis] = t;
    }
    if (named == 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("move what? move x<target> y<target> z<target>"));
        return;
    }
    collect_done(); /* a move that has just ended reports first */
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        if ((named & (1U << i)) && (MultiStepEngine::moving(i) || (coord_mask_ & (1U << i)))) {
            Print &e = serial_.begin_error(MS_ERR_BUSY);
            e.print(AXIS_NAME[i]);
            e.println(F(" is moving (stop it or wait for its DONE)"));
            return;
        }
    }
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        from[i] = MultiStepEngine::position(i);
        if (!(named & (1U << i)))
            to[i] = from[i]; /* not in this move: it sets no limit and is not touched */
        p[i] = planner_[i].params;
        if (to[i] != from[i])
            mask |= (uint8_t)(1U << i);
    }
    if (mask == 0) {
        /* every named axis is there already: nothing moves, and the move is done at once (as `x 0` at 0) */
        Print &out = serial_.out();
        out.print(F("OK move"));
        print_axes(out, named, from, to);
        out.println();
        out.print(F("DONE move"));
        print_axes(out, named, from, 0);
        out.println();
        return;
    }
    st = step_coord_plan(&coord_, MULTI_AXES, p, from, to);
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    coord_named_ = named;
    coord_mask_ = mask;
    coord_done_ = 0;
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        /* an axis moving as far as the master repeats the master's commands (planned once) */
        uint8_t m = coord_.master;
        coord_ctx_[i].repeats = (i != m && (mask & (1U << i)) && coord_.d[i] == coord_.d[m]) ? m : 0xFF;
        coord_ctx_[i].clones = 0;
    }
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        if (coord_ctx_[i].repeats != 0xFF)
            coord_ctx_[coord_ctx_[i].repeats].clones |= (uint8_t)(1U << i);
    coord_own_ = 0; /* the axes of the move with an interrupt of their own */
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        if ((mask & (1U << i)) && coord_ctx_[i].repeats == 0xFF)
            coord_own_ |= (uint8_t)(1U << i);
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        coord_end_[i] = from[i];
        if (!(mask & (1U << i)))
            continue;
        has_next_[i] = false;
        if (coord_ctx_[i].repeats != 0xFF)
            MultiStepEngine::follow(coord_ctx_[i].repeats, i, to[i] > from[i]); /* its master pulses it */
        else
            MultiStepEngine::open_move(i, true);
    }
    coord_starting_ = true;
    serial_.out().print(F("OK move"));
    print_coord_positions(serial_.out(), true);
    serial_.out().println();
    feed();
}

void MultiAxisConsole::handle_stop(const char *cursor, bool halt)
{
    char word[LINE_READER_MAX + 1];
    uint8_t mask = (uint8_t)((1U << MULTI_AXES) - 1U), running = 0;
    Print &out = serial_.out();
    int n = text_next_word(&cursor, word, sizeof word);
    if (n != 0) {
        int8_t axis = n > 0 ? axis_of(word) : -1;
        if (axis < 0 || !text_at_end(cursor)) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("stop [x|y|z], ! [x|y|z]"));
            return;
        }
        mask = (uint8_t)(1U << axis);
    }
    collect_done(); /* moves that have just ended report first */
    if (mask & coord_mask_)
        mask |= coord_mask_; /* an axis of the coordinated move stops the whole move */
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        if (!(mask & (1U << i)))
            continue;
        has_next_[i] = false; /* a target waiting for the move's end is dropped */
        if (MultiStepEngine::moving(i))
            running |= (uint8_t)(1U << i);
    }
    if (running == 0) {
        out.println(halt ? F("OK halt (not moving)") : F("OK stop (not moving)"));
        return;
    }
    if (halt) {
        for (uint8_t i = 0; i < MULTI_AXES; i++) {
            if (!(running & (1U << i)))
                continue;
            MultiStepEngine::halt(i);
            if (coord_mask_ & (1U << i))
                step_coord_halt(&coord_, i, MultiStepEngine::position(i));
            else
                step_planner_halt(&planner_[i], MultiStepEngine::position(i));
        }
        coord_starting_ = false;
        out.println(F("OK halt"));
        collect_done();
        return;
    }
    if (running & coord_mask_) {
        if (coord_starting_) {
            /* not started yet: nothing has stepped, stand still */
            for (uint8_t i = 0; i < MULTI_AXES; i++)
                if (coord_mask_ & (1U << i)) {
                    MultiStepEngine::halt(i);
                    step_coord_halt(&coord_, i, MultiStepEngine::position(i));
                }
            coord_starting_ = false;
        } else {
            uint8_t m = coord_.master;
            bool back[MULTI_AXES];
            for (uint8_t i = 0; i < MULTI_AXES; i++)
                back[i] = coord_.to[i] < coord_.from[i];
            step_coord_stop(&coord_);
            /* a follower stops with its master, as far */
            for (uint8_t i = 0; i < MULTI_AXES; i++) {
                if (coord_ctx_[i].repeats == m) {
                    int32_t k = coord_.to[m] - coord_.from[m];
                    if (k < 0)
                        k = -k;
                    coord_.to[i] = back[i] ? coord_.from[i] - k : coord_.from[i] + k;
                }
            }
        }
    }
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        int32_t ended;
        if (!(running & (1U << i)) || (coord_mask_ & (1U << i)))
            continue;
        if (MultiStepEngine::extend(i, ended) == MultiStepEngine::CONTINUES)
            step_planner_stop(&planner_[i]);
        else
            report_done(i, ended);
    }
    out.println(F("OK stop"));
    collect_done();
}

void MultiAxisConsole::handle_set(uint8_t axis, const char *cursor)
{
    char key[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1];
    motion_status_t st;
    bool moving = MultiStepEngine::moving(axis);
    Print &out = serial_.out();
    TrapezoidRamp &r = *ramp_[axis];
    if (text_next_word(&cursor, key, sizeof key) <= 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set <axis> what? set <x|y|z> <v0|vmax|accel> <value>"));
        return;
    }
    if (text_next_word(&cursor, value, sizeof value) <= 0) {
        serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("set <axis> <parameter> <value>: the value is missing"));
        return;
    }
    if (!text_at_end(cursor)) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set takes one axis, one parameter and one value"));
        return;
    }
    st = r.set(key, value);
    if (st == MS_ERR_UNKNOWN_COMMAND) {
        serial_.reply_error(st, F("no such parameter (v0, vmax, accel)"));
        return;
    }
    if (st == MS_ERR_OUT_OF_RANGE) {
        r.print_limit(serial_.begin_error(st), key);
        out.println();
        return;
    }
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    (void)r.apply(planner_[axis], moving);
    out.print(F("OK "));
    out.print(AXIS_NAME[axis]);
    out.print(' ');
    r.print_param(out, key);
    if (moving)
        out.print(F(" (from the next plan)"));
    out.println();
}

int32_t MultiAxisConsole::follower_position(uint8_t axis, int32_t master_pos)
{
    uint8_t m = coord_ctx_[axis].repeats;
    int32_t k = master_pos - coord_.from[m];
    if (k < 0)
        k = -k;
    return coord_.to[axis] < coord_.from[axis] ? coord_.from[axis] - k : coord_.from[axis] + k;
}

int32_t MultiAxisConsole::position_of(uint8_t axis)
{
    if ((coord_mask_ & (1U << axis)) && coord_ctx_[axis].repeats != 0xFF)
        return follower_position(axis, MultiStepEngine::position(coord_ctx_[axis].repeats));
    return MultiStepEngine::position(axis);
}

void MultiAxisConsole::print_status(uint8_t axis)
{
    Print &out = serial_.out();
    bool moving = MultiStepEngine::moving(axis);
    bool in_move = (coord_mask_ & (1U << axis)) != 0;
    uint8_t phase = MultiStepEngine::phase(axis);
    out.print(AXIS_NAME[axis]);
    out.print(F(" pos="));
    out.print(position_of(axis));
    out.print(F(" target="));
    out.print(in_move ? step_coord_target(&coord_, axis)
                      : (has_next_[axis] ? next_target_[axis] : step_planner_target(&planner_[axis])));
    out.print(F(" state="));
    out.print(ramp_phase_name(moving && phase != 0 ? (ramp_phase_t)phase : (moving ? RAMP_ACCEL : RAMP_IDLE)));
    out.print(F(" mode="));
    out.print(in_move ? F("move") : (moving ? F("alone") : F("idle")));
    ramp_[axis]->print_params(out);
    out.print(F(" underruns="));
    out.print(MultiStepEngine::underruns(axis));
    out.print(F(" late="));
    out.println(MultiStepEngine::late_edges(axis));
}
