/* MultiAxisConsole.cpp - MultiAxisStepper's coordinated move (see MultiAxisConsole.h); the rest of
 * its protocol is StepConsole.cpp. */
#include "MultiAxisConsole.h"

#include <line_reader.h>
#include <text_parse.h>

static const char AXIS_NAME[MULTI_AXES] = {'x', 'y', 'z'};

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

MultiAxisCoord::MultiAxisCoord() : own_(0), done_(0), starting_(false)
{
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        ctx_[i].coord = &coord_;
        ctx_[i].axis = i;
        ctx_[i].repeats = 0xFF;
        ctx_[i].clones = 0;
        end_[i] = 0;
    }
}

AxisSource MultiAxisCoord::source(uint8_t axis)
{
    AxisSource s;
    s.next = coord_next;
    s.busy = coord_busy;
    s.ctx = &ctx_[axis];
    return s;
}

void MultiAxisCoord::start_if_ready()
{
    bool all = true;
    if (!starting_)
        return;
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        if ((own_ & (1U << i)) && !MultiStepEngine::ready_to_start(i, source(i)))
            all = false;
    if (all) {
        MultiStepEngine::start_together(own_);
        starting_ = false;
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

void MultiAxisCoord::print_positions(Print &out, bool with_from)
{
    if (with_from)
        print_axes(out, named, coord_.from, coord_.to);
    else
        print_axes(out, named, end_, 0);
}

void MultiAxisCoord::axis_done(StepConsole &c, uint8_t axis, int32_t position)
{
    Print &out = c.serial_.out();
    /* one axis of the coordinated move has ended: the move's DONE once all have */
    end_[axis] = position;
    done_ |= (uint8_t)(1U << axis);
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        if (ctx_[axis].clones & (1U << i)) {
            /* its followers made as many steps, each in its own direction */
            end_[i] = follower_position(i, position);
            MultiStepEngine::set_rest_position(i, end_[i]);
            done_ |= (uint8_t)(1U << i);
        }
    }
    if (ctx_[axis].clones)
        MultiStepEngine::unfollow(axis);
    if (done_ != mask)
        return;
    out.print(F("DONE move"));
    print_positions(out, false);
    out.println();
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        if (mask & (1U << i))
            step_planner_halt(&c.pl_[i], end_[i]); /* at rest there, alone again */
        ctx_[i].repeats = 0xFF;
        ctx_[i].clones = 0;
    }
    mask = 0;
    own_ = 0;
    named = 0;
    done_ = 0;
    starting_ = false;
}

void MultiAxisCoord::handle_move(StepConsole &c, const char *cursor)
{
    char word[LINE_READER_MAX + 1];
    int32_t from[MULTI_AXES], to[MULTI_AXES];
    ramp_params_t p[MULTI_AXES];
    uint8_t names = 0, moving = 0;
    int n;
    motion_status_t st;
    MotionSerial &serial = c.serial_;
    while ((n = text_next_word(&cursor, word, sizeof word)) != 0) {
        int8_t axis = -1;
        int32_t t;
        for (uint8_t i = 0; n > 1 && i < MULTI_AXES; i++)
            if (word[0] == AXIS_NAME[i])
                axis = (int8_t)i;
        if (n < 0 || axis < 0) {
            serial.reply_error(MS_ERR_UNKNOWN_COMMAND, F("move x<target> y<target> z<target>, e.g. move x1000 y-500"));
            return;
        }
        if (names & (1U << axis)) {
            serial.reply_error(MS_ERR_UNKNOWN_COMMAND, F("an axis is named twice"));
            return;
        }
        st = text_parse_whole(word + 1, INT32_MIN, INT32_MAX, &t);
        if (st != MS_OK) {
            serial.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
            return;
        }
        names |= (uint8_t)(1U << axis);
        to[axis] = t;
    }
    if (names == 0) {
        serial.reply_error(MS_ERR_UNKNOWN_COMMAND, F("move what? move x<target> y<target> z<target>"));
        return;
    }
    c.collect_done(); /* a move that has just ended reports first */
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        if ((names & (1U << i)) && (MultiStepEngine::moving(i) || (named & (1U << i)))) {
            Print &e = serial.begin_error(MS_ERR_BUSY);
            e.print(AXIS_NAME[i]);
            e.println(F(" is moving (stop it or wait for its DONE)"));
            return;
        }
    }
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        from[i] = MultiStepEngine::position(i);
        if (!(names & (1U << i)))
            to[i] = from[i]; /* not in this move: it sets no limit and is not touched */
        p[i] = c.pl_[i].params;
        if (to[i] != from[i])
            moving |= (uint8_t)(1U << i);
    }
    if (moving == 0) {
        /* every named axis is there already: nothing moves, and the move is done at once (as `x 0` at 0) */
        Print &out = serial.out();
        out.print(F("OK move"));
        print_axes(out, names, from, to);
        out.println();
        out.print(F("DONE move"));
        print_axes(out, names, from, 0);
        out.println();
        return;
    }
    st = step_coord_plan(&coord_, MULTI_AXES, p, from, to);
    if (st != MS_OK) {
        serial.reply_error(st);
        return;
    }
    named = names;
    mask = moving;
    done_ = 0;
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        /* an axis moving as far as the master repeats the master's commands (planned once) */
        uint8_t m = coord_.master;
        ctx_[i].repeats = (i != m && (moving & (1U << i)) && coord_.d[i] == coord_.d[m]) ? m : 0xFF;
        ctx_[i].clones = 0;
    }
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        if (ctx_[i].repeats != 0xFF)
            ctx_[ctx_[i].repeats].clones |= (uint8_t)(1U << i);
    own_ = 0; /* the axes of the move with an interrupt of their own */
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        if ((moving & (1U << i)) && ctx_[i].repeats == 0xFF)
            own_ |= (uint8_t)(1U << i);
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        end_[i] = from[i];
        if (!(moving & (1U << i)))
            continue;
        c.has_next_[i] = false;
        c.next_due_[i] = false;
        if (ctx_[i].repeats != 0xFF)
            MultiStepEngine::follow(ctx_[i].repeats, i, to[i] > from[i]); /* its master pulses it */
        else
            MultiStepEngine::open_move(i, true);
    }
    starting_ = true;
    serial.out().print(F("OK move"));
    print_positions(serial.out(), true);
    serial.out().println();
    c.feed();
}

void MultiAxisCoord::stop(StepConsole &c, bool halt)
{
    (void)c;
    if (halt || starting_) {
        /* halt, or not started yet (nothing has stepped): stand still */
        for (uint8_t i = 0; i < MULTI_AXES; i++) {
            if (!(mask & (1U << i)) || (halt && !MultiStepEngine::moving(i)))
                continue;
            MultiStepEngine::halt(i);
            step_coord_halt(&coord_, i, MultiStepEngine::position(i));
        }
        starting_ = false;
        return;
    }
    uint8_t m = coord_.master;
    bool back[MULTI_AXES];
    for (uint8_t i = 0; i < MULTI_AXES; i++)
        back[i] = coord_.to[i] < coord_.from[i];
    step_coord_stop(&coord_);
    /* a follower stops with its master, as far */
    for (uint8_t i = 0; i < MULTI_AXES; i++) {
        if (ctx_[i].repeats == m) {
            int32_t k = coord_.to[m] - coord_.from[m];
            if (k < 0)
                k = -k;
            coord_.to[i] = back[i] ? coord_.from[i] - k : coord_.from[i] + k;
        }
    }
}

int32_t MultiAxisCoord::follower_position(uint8_t axis, int32_t master_pos)
{
    uint8_t m = ctx_[axis].repeats;
    int32_t k = master_pos - coord_.from[m];
    if (k < 0)
        k = -k;
    return coord_.to[axis] < coord_.from[axis] ? coord_.from[axis] - k : coord_.from[axis] + k;
}

int32_t MultiAxisCoord::position_of(uint8_t axis)
{
    if (ctx_[axis].repeats != 0xFF)
        return follower_position(axis, MultiStepEngine::position(ctx_[axis].repeats));
    return MultiStepEngine::position(axis);
}

int32_t MultiAxisCoord::target_of(uint8_t axis)
{
    return step_coord_target(&coord_, axis);
}
