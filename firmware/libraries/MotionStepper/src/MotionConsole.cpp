/* MotionConsole.cpp - the stepper sketches' serial protocol on a Stepper (see MotionConsole.h). */
#include "MotionConsole.h"

#include <line_reader.h>
#include <text_parse.h>

#include <PrintReal.h>
#include <StepperPins.h> /* STEPPER_LED_MIRROR, STEP_ENGINE_LEAD_MS(_LEIB), STEPPER_TIMED_LOOP */

/* Room a DONE line needs in the output queue ("DONE -2147483648" and CR LF: 18 bytes; a DONE that
 * would not fit waits, and no line is read before it); a `?` line about 140 bytes, the sigmoid's
 * about 220 (the queue holds 256: the DONE after it waits for the queue to drain). */
#define MOTION_CONSOLE_DONE_ROOM 24U
/* with three axes, what one pass may print: three "DONE x -2147483648" lines (20 bytes each with
 * CR LF), or two and a one-axis "DONE move x -2147483648" (25), or "DONE move x -2147483648
 * y -2147483648 z -2147483648" (53) */
#define MOTION_CONSOLE_DONE_ROOM_3 68U
#define MOTION_CONSOLE_STATUS_ROOM 230U

const char MotionConsole::AXIS_NAME[3] = {'x', 'y', 'z'};

/* "x" -> 0 ... ; -1 for anything else */
int8_t MotionConsole::axis_of(const char *word)
{
    for (uint8_t i = 0; word[0] != '\0' && word[1] == '\0' && i < 3; i++)
        if (word[0] == AXIS_NAME[i])
            return (int8_t)i;
    return -1;
}


MotionConsole::MotionConsole(Stepper &x)
    : n_(1), group_(0), move_(0), named_(0), status_pending_(0), ok_pending_(false), move_pending_(false), ok_axis_(0),
      ok_target_(0), queue_(Serial), serial_(Serial, queue_, 240)
{
    ax_[0] = &x;
    ax_[1] = ax_[2] = 0;
    /* loop() is the console's alone and never blocks: the planner runs there, on every poll(), as
     * the sketches' consoles always planned (a sketch's global, made before setup() and the
     * Stepper's begin()). In Timer3's interrupt the lab's ramps, which plan every step, reached
     * less: LeibRampStepper 8,000 steps/s clean instead of 12,000 (make bench). */
    (void)BackgroundPlanner::planInLoop();
}

void MotionConsole::begin(const __FlashStringHelper *sketch_name)
{
    Serial.begin(9600);
    serial_.set_rx_interrupt(false); /* poll() drains the input on every pass (SerialRx.h) */
    /* the lead the stepper sketches always had (StepperPins.h: the Leib ramp's float update costs
     * nearly a step's time near its top rate; the exact ramp's stop and new targets cut the queue,
     * so its lead costs them no latency) */
    (void)BackgroundPlanner::setLeadMs(ax_[0]->ramp() == RAMP_ALGO_LEIB ? STEP_ENGINE_LEAD_MS_LEIB : STEP_ENGINE_LEAD_MS);
    MultiStepEngine::set_led_mirror(STEPPER_LED_MIRROR && n_ == 1 && ax_[0]->axis() == Stepper::X);
    /* a Stepper whose begin() the sketch called and that refused (a sketch adapted until its SRAM no
     * longer holds the rings and the stack's reserve): said once, before READY, with its reason (begin()
     * again: MS_OK once begun, its reason otherwise); its moves then answer MS_ERR_NOT_BEGUN's line */
    for (uint8_t a = 0; a < n_; a++) {
        motion_status_t st = ax_[a]->begin();
        if (st != MS_OK) {
            /* straight to Serial (it waits for room): three such lines overflow the reply queue */
            Serial.print(F("ERR "));
            print_axis(Serial, a);
            Serial.print(F("begin(): "));
            Serial.println(Stepper::statusText(st));
        }
    }
    serial_.out().print(F("READY "));
    serial_.out().println(sketch_name);
}

/* planned from loop() (BackgroundPlanner::planInLoop, the timed-loop build): the planner's tick; with
 * the planner interrupt, nothing. Also called between the slow parts of a number's formatting. */
static void plan()
{
    BackgroundPlanner::poll();
}

void MotionConsole::print_axis(Print &out, uint8_t a)
{
    if (n_ == 1)
        return;
    out.print(AXIS_NAME[a]);
    out.print(' ');
}

/* " x <from> [<to>] y ..." for the axes of the `move` (to: none when 0) */
void MotionConsole::print_axes(Print &out, const long *from, const long *to)
{
    for (uint8_t i = 0; i < n_; i++) {
        if (!(named_ & (1U << i)))
            continue;
        out.print(' ');
        print_axis(out, i);
        out.print(from[i]);
        if (to) {
            out.print(' ');
            out.print(to[i]);
        }
    }
}

bool MotionConsole::collect_done()
{
    long at;
    Print &out = serial_.out();
    if (queue_.room() < (n_ == 1 ? MOTION_CONSOLE_DONE_ROOM : MOTION_CONSOLE_DONE_ROOM_3))
        return false; /* no line is read before a DONE that may be waiting */
    for (uint8_t i = 0; i < n_; i++) {
        /* with an OK waiting, finish_ok orders its DONE; an axis of the `move` reports with it */
        if ((ok_pending_ && i == ok_axis_) || (named_ & (1U << i)) || !ax_[i]->takeDone(at))
            continue;
        out.print(F("DONE "));
        print_axis(out, i);
        out.println(at);
    }
    if (named_ && !move_pending_)
        (this->*move_->done)();
    return true;
}

void MotionConsole::poll()
{
    const char *line;
    bool stepping = false;
    plan();
    /* while an axis steps, the replies go out without the transmit interrupt, which would nest in the
     * step interrupts (SerialOutQueue.h); at rest through it, so that a long pass of loop() (a table
     * refill) does not hold the reply back byte by byte */
    for (uint8_t i = 0; i < n_; i++)
        stepping = stepping || MultiStepEngine::moving(ax_[i]->axis());
    queue_.set_direct(stepping);
    if (!collect_done() || (ok_pending_ && !finish_ok()) || (move_pending_ && !(this->*move_->finish)())) {
        serial_.drain_input(); /* no line is read meanwhile, but input must not pile up in the core */
        queue_.pump();
        return;
    }
    if (status_pending_) {
        /* the `?` lines, one at a time as the output queue has room */
        serial_.drain_input();
        for (uint8_t i = 0; i < n_; i++) {
            if (!(status_pending_ & (1U << i)))
                continue;
            if (queue_.room() >= MOTION_CONSOLE_STATUS_ROOM) {
                print_status(i);
                status_pending_ &= (uint8_t)~(1U << i);
            }
            break;
        }
    } else {
        line = serial_.poll();
        if (line != NULL) {
            handle(line);
            if (ok_pending_ || move_pending_) {
                plan(); /* from loop(): the target is planned here, and its OK follows at once */
                (void)(ok_pending_ ? finish_ok() : (this->*move_->finish)());
            }
        }
    }
    queue_.pump();
}

void MotionConsole::handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1];
    int8_t a = 0;
    if (text_next_word(&cursor, word, sizeof word) == 0)
        return; /* a line of blanks: nothing to do */
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes no arguments"));
        else
            status_pending_ = (uint8_t)((1U << n_) - 1U);
    } else if (text_word_is(word, "set")) {
        char w[LINE_READER_MAX + 1];
        if (n_ > 1 && (text_next_word(&cursor, w, sizeof w) <= 0 || (a = axis_of(w)) < 0))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("set <x|y|z> <v0|vmax|accel> <value>"));
        else
            handle_set((uint8_t)a, cursor); /* one axis: no axis word */
    } else if (text_word_is(word, "stop") || text_word_is(word, "!")) {
        handle_stop(cursor, word[0] == '!');
    } else if (move_ && text_word_is(word, "move")) {
        (this->*move_->handle)(cursor);
    } else if (n_ == 1 && ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+')) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target(0, word);
    } else if (n_ > 1 && (a = axis_of(word)) >= 0) {
        if (text_next_word(&cursor, word, sizeof word) <= 0)
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("<axis> <target>: the target is missing"));
        else if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target((uint8_t)a, word);
    } else if (n_ == 1) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <target>, stop, !, ?, set v0|vmax|accel <value>"));
    } else {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND,
                            F("try x|y|z <target>, move x<t> y<t> z<t>, stop [axis], ! [axis], ?, set <axis> <key> <value>"));
    }
}

void MotionConsole::handle_target(uint8_t a, const char *word)
{
    int32_t to = 0; /* (set by the parse; gcc cannot tell) */
    motion_status_t st = text_parse_whole(word, INT32_MIN, INT32_MAX, &to);
    if (st != MS_OK) {
        serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
        return;
    }
    if (named_ & (1U << a)) {
        serial_.reply_error(MS_ERR_BUSY, F("the axis is in a coordinated move (stop it first, or wait for its DONE)"));
        return;
    }
    st = ax_[a]->move_to(to, true); /* planned even to the target in force: its OK and DONE come */
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    /* the planner plans it within microseconds (longer while it plans another move, or while the
     * sigmoid's table is refilled): its OK tells where the plan starts, so it waits for that (poll()
     * reads no line meanwhile) */
    ok_pending_ = true;
    ok_axis_ = a;
    ok_target_ = to;
    (void)finish_ok();
}



bool MotionConsole::finish_ok()
{
    Stepper::PlanStart p;
    Print &out = serial_.out();
    motion_status_t st;
    Stepper &x = *ax_[ok_axis_];
    if (!x.planStart(p))
        return false;
    ok_pending_ = false;
    st = x.lastStatus();
    if (st != MS_OK) {
        /* nothing moves (from rest), or the move in progress goes on as planned */
        (void)collect_done();
        serial_.reply_error(st);
        return true;
    }
    if (p.doneBefore && !p.afterDone)
        (void)collect_done(); /* a move that ended just before this target: its DONE first (an end
                                 recorded since is this move's: a move of no step ends at once) */
    out.print(F("OK "));
    print_axis(out, ok_axis_);
    out.print(p.from);
    out.print(' ');
    out.print(ok_target_);
    if (p.afterDone) {
        /* the move in progress ends at its target first, with its DONE (still to come) */
        out.print(F(" (after DONE "));
        print_axis(out, ok_axis_);
        out.print(p.from);
        out.print(')');
    }
    out.println();
    return true;
}

void MotionConsole::handle_stop(const char *cursor, bool halt)
{
    char word[LINE_READER_MAX + 1];
    bool moving = false;
    uint8_t mask = (uint8_t)((1U << n_) - 1U);
    motion_status_t st = MS_OK;
    int n = text_next_word(&cursor, word, sizeof word);
    if (n != 0 && n_ == 1) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("stop and ! take no arguments"));
        return;
    }
    if (n != 0) {
        int8_t a = n > 0 ? axis_of(word) : -1;
        if (a < 0 || !text_at_end(cursor)) {
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("stop [x|y|z], ! [x|y|z]"));
            return;
        }
        mask = (uint8_t)(1U << a);
    }
    (void)collect_done(); /* a move that has just ended reports first */
    if (mask & named_) {
        /* an axis of the coordinated move stops the whole move */
        st = (this->*move_->stop)(halt, moving);
        mask &= (uint8_t)~named_;
    }
    for (uint8_t i = 0; st == MS_OK && i < n_; i++) {
        if (!(mask & (1U << i)))
            continue;
        st = halt ? ax_[i]->forceStop() : ax_[i]->stop();
        /* after the call: a move asked for and not started yet (waiting for the sigmoid's refill) is
         * dropped by it and gets no DONE: "(not moving)"; a move stepping keeps running until its end */
        moving = moving || ax_[i]->isRunning();
    }
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    if (!moving)
        serial_.out().println(halt ? F("OK halt (not moving)") : F("OK stop (not moving)"));
    else
        serial_.out().println(halt ? F("OK halt") : F("OK stop"));
}

void MotionConsole::handle_set(uint8_t a, const char *cursor)
{
    Stepper &x = *ax_[a];
    char key[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1];
    double v = 0.0, hi;
    motion_status_t st;
    Print &out = serial_.out();
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
    bool sigmoid = x.ramp() == RAMP_ALGO_SIGMOID;
    bool whole = sigmoid && (text_word_is(key, "len") || text_word_is(key, "hold"));
    const __FlashStringHelper *unit = F(" steps/s");
    if (text_word_is(key, "v0"))
        hi = x.minSpeedLimit();
    else if (text_word_is(key, "vmax"))
        hi = x.maxSpeedLimit();
    else if (text_word_is(key, "accel") && sigmoid) {
        serial_.reply_error(MS_ERR_DERIVED_PARAM); /* the table's shape gives it */
        return;
    } else if (text_word_is(key, "accel")) {
        hi = x.accelerationLimit();
        unit = F(" steps/s^2");
    } else if (sigmoid && text_word_is(key, "flex")) {
        hi = STEPPER_MAX_FLEX;
        unit = F("");
    } else if (text_word_is(key, "len") && sigmoid) {
        hi = SCURVE_MAX_LEN;
        unit = F(" entries");
    } else if (text_word_is(key, "hold") && sigmoid) {
        hi = 65535.0;
        unit = F(" steps per entry");
    } else {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, n_ == 1 ? F("no such parameter (see ?)") : F("no such parameter (v0, vmax, accel)"));
        return;
    }
    if (whole) {
        int32_t n = 0;
        st = text_parse_int32(value, 0, (int32_t)hi, &n);
        v = (double)n;
    } else {
        st = text_parse_real(value, -1e7, hi, &v);
    }
    if (st == MS_ERR_OUT_OF_RANGE && value[0] == '-') {
        v = whole ? 0.0 : -1.0; /* the Stepper's check of the set names the problem with negative values */
        st = MS_OK;
    }
    if (st == MS_ERR_OUT_OF_RANGE) {
        /* "ERR number out of range: vmax at most 7000 steps/s on this sketch" */
        Print &e = serial_.begin_error(st);
        e.print(key);
        e.print(F(" at most "));
        print_real_exact(e, hi, plan);
        e.print(unit);
        e.println(F(" on this sketch"));
        return;
    }
    if (st == MS_OK)
        st = text_word_is(key, "v0")      ? x.setMinSpeed((float)v)
             : text_word_is(key, "vmax")  ? x.setMaxSpeed((float)v)
             : text_word_is(key, "accel") ? x.setAcceleration((float)v)
             : text_word_is(key, "flex")  ? x.set_sigmoid_in_use((float)v, x.sigmoidLen(), x.sigmoidHold())
             : text_word_is(key, "len")   ? x.set_sigmoid_in_use(x.sigmoidFlex(), (uint16_t)v, x.sigmoidHold())
                                          : x.set_sigmoid_in_use(x.sigmoidFlex(), x.sigmoidLen(), (uint16_t)v);
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    out.print(F("OK "));
    print_axis(out, a);
    print_param(out, a, key);
    if (x.isRunning())
        out.print(F(" (from the next plan)"));
    out.println();
}

void MotionConsole::print_param(Print &out, uint8_t a, const char *key)
{
    const Stepper &x = *ax_[a];
    out.print(key);
    out.print('=');
    if (text_word_is(key, "len"))
        out.print(x.sigmoidLen());
    else if (text_word_is(key, "hold"))
        out.print(x.sigmoidHold());
    else
        print_real_exact(out, text_word_is(key, "v0")     ? x.minSpeed()
                              : text_word_is(key, "vmax") ? x.maxSpeed()
                              : text_word_is(key, "flex") ? x.sigmoidFlex()
                                                          : x.acceleration(),
                         plan);
}

void MotionConsole::print_status(uint8_t a)
{
    Print &out = serial_.out();
    Stepper::SigmoidFigures f;
    Stepper &x = *ax_[a];
    print_axis(out, a);
    out.print(F("pos="));
    out.print(x.currentPosition());
    out.print(F(" target="));
    out.print(x.targetPosition());
    out.print(F(" state="));
    out.print(ramp_phase_name(x.rampState()));
    if (n_ > 1) {
        out.print(F(" mode="));
        out.print((named_ & (1U << a)) ? F("move") : (x.isRunning() ? F("alone") : F("idle")));
    }
    out.print(F(" algo="));
    out.print(ramp_algo_name(x.ramp()));
    out.print(' ');
    print_param(out, a, "v0");
    out.print(' ');
    print_param(out, a, "vmax");
    out.print(' ');
    print_param(out, a, "accel");
    out.print(F(" tick_hz="));
    out.print(Stepper::tickRate());
    out.print(F(" max_sps="));
    print_real_exact(out, x.maxSpeedLimit(), plan);
    if (x.sigmoidFigures(f)) {
        /* the S-curve's shape, and what its table in force gives */
        out.print(' ');
        print_param(out, a, "flex");
        out.print(' ');
        print_param(out, a, "len");
        out.print(' ');
        print_param(out, a, "hold");
        out.print(F(" accel_steps="));
        out.print(f.accelSteps);
        out.print(F(" accel_time_s="));
        print_real_exact(out, f.accelTimeS, plan);
        out.print(F(" cruise_sps="));
        print_real_exact(out, f.cruiseSps, plan);
    }
    out.print(F(" underruns="));
    out.print(x.underruns());
    out.print(F(" late="));
    out.print(x.lateEdges());
    if (n_ == 1)
        out.print(STEPPER_TIMED_LOOP ? F(" mode=loop") : F(" mode=timer"));
    out.println();
}
