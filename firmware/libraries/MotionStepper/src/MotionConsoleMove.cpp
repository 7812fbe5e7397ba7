/* MotionConsoleMove.cpp - MotionConsole's coordinated `move` of two or three axes (a StepperGroup):
 * the three-axis console, `move`, its OK and DONE, and a stop of its axes (see MotionConsole.h).
 * Kept apart so the one-axis sketches' console does not name StepperGroup. */
#include "MotionConsole.h"

#include "StepperGroup.h"

#include <line_reader.h>
#include <text_parse.h>

MotionConsole::MotionConsole(Stepper &x, Stepper &y, Stepper &z, StepperGroup &xyz) : MotionConsole(x)
{
    ax_[1] = &y;
    ax_[2] = &z;
    n_ = 3;
    group_ = &xyz;
    move_ = &MOVE_PARTS;
}

const MotionConsole::MoveParts MotionConsole::MOVE_PARTS = {&MotionConsole::handle_move, &MotionConsole::finish_move,
                                                            &MotionConsole::move_done, &MotionConsole::stop_move};

void MotionConsole::handle_move(const char *cursor)
{
    char word[LINE_READER_MAX + 1];
    uint8_t names = 0;
    int n;
    motion_status_t st;
    while ((n = text_next_word(&cursor, word, sizeof word)) != 0) {
        char name[2] = {word[0], '\0'};
        int8_t a = n > 1 ? axis_of(name) : -1;
        int32_t t;
        if (a < 0) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("move x<target> y<target> z<target>, e.g. move x1000 y-500"));
            return;
        }
        if (names & (1U << a)) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("an axis is named twice"));
            return;
        }
        st = text_parse_whole(word + 1, INT32_MIN, INT32_MAX, &t);
        if (st != MS_OK) {
            serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
            return;
        }
        names |= (uint8_t)(1U << a);
        move_to_[a] = t;
    }
    if (names == 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("move what? move x<target> y<target> z<target>"));
        return;
    }
    (void)collect_done(); /* a move that has just ended reports first */
    for (uint8_t i = 0; i < n_; i++) {
        if ((names & (1U << i)) && (ax_[i]->isRunning() || (named_ & (1U << i)))) {
            Print &e = serial_.begin_error(MS_ERR_BUSY);
            e.print(AXIS_NAME[i]);
            e.println(F(" is moving (stop it or wait for its DONE)"));
            return;
        }
        move_from_[i] = ax_[i]->currentPosition();
    }
    st = group_->moveTo(move_to_, names);
    if (st == MS_ERR_BUSY) {
        serial_.reply_error(st, F("a coordinated move is under way (stop it or wait for its DONE)"));
        return;
    }
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    /* planned by the planner within microseconds: a plan it refuses (an axis moving too few steps for
     * the longest) gets its ERR then, and nothing has moved */
    named_ = names;
    move_pending_ = true;
    (void)finish_move();
}

bool MotionConsole::finish_move()
{
    long at;
    Print &out = serial_.out();
    motion_status_t st;
    if (!group_->planned())
        return false;
    move_pending_ = false;
    st = group_->lastStatus();
    if (st != MS_OK) {
        (void)group_->takeDone(); /* the refused move ended at once, with no step */
        for (uint8_t i = 0; i < n_; i++)
            if (named_ & (1U << i))
                (void)ax_[i]->takeDone(at);
        named_ = 0;
        serial_.reply_error(st);
        return true;
    }
    out.print(F("OK move"));
    print_axes(out, move_from_, move_to_);
    out.println();
    (void)collect_done(); /* every named axis at its target already: its DONE at once */
    return true;
}

/* the DONE of the coordinated move, once the group reports its end (collect_done) */
void MotionConsole::move_done()
{
    long at, end[3];
    Print &out = serial_.out();
    if (!group_->takeDone())
        return;
    for (uint8_t i = 0; i < n_; i++) {
        if (!(named_ & (1U << i)))
            continue;
        end[i] = ax_[i]->currentPosition();
        (void)ax_[i]->takeDone(at); /* the group's end is each moving member's end too */
    }
    out.print(F("DONE move"));
    print_axes(out, end, 0);
    out.println();
    named_ = 0;
}

/* `stop` or `!` naming an axis of the coordinated move: the whole move (handle_stop) */
motion_status_t MotionConsole::stop_move(bool halt, bool &moving)
{
    motion_status_t st = halt ? group_->forceStop() : group_->stop();
    moving = group_->isRunning();
    return st;
}
