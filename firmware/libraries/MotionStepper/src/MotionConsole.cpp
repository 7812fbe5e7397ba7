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
#define MOTION_CONSOLE_STATUS_ROOM 230U

MotionConsole::MotionConsole(Stepper &x)
    : x_(x), status_pending_(false), ok_pending_(false), ok_target_(0), queue_(Serial), serial_(Serial, queue_, 240)
{
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
    (void)BackgroundPlanner::setLeadMs(x_.ramp() == RAMP_ALGO_LEIB ? STEP_ENGINE_LEAD_MS_LEIB : STEP_ENGINE_LEAD_MS);
    MultiStepEngine::set_led_mirror(STEPPER_LED_MIRROR && x_.axis() == Stepper::X);
    serial_.out().print(F("READY "));
    serial_.out().println(sketch_name);
}

/* planned from loop() (BackgroundPlanner::planInLoop, the timed-loop build): the planner's tick; with
 * the planner interrupt, nothing. Also called between the slow parts of a number's formatting. */
static void plan()
{
    BackgroundPlanner::poll();
}

bool MotionConsole::collect_done()
{
    long at;
    if (queue_.room() < MOTION_CONSOLE_DONE_ROOM)
        return false; /* no line is read before a DONE that may be waiting */
    if (!ok_pending_ && x_.takeDone(at)) { /* with an OK waiting, finish_ok orders its DONE */
        serial_.out().print(F("DONE "));
        serial_.out().println(at);
    }
    return true;
}

void MotionConsole::poll()
{
    const char *line;
    plan();
    if (!collect_done() || (ok_pending_ && !finish_ok())) {
        serial_.drain_input(); /* no line is read meanwhile, but input must not pile up in the core */
        queue_.pump();
        return;
    }
    if (status_pending_) {
        serial_.drain_input();
        if (queue_.room() >= MOTION_CONSOLE_STATUS_ROOM) {
            print_status();
            status_pending_ = false;
        }
    } else {
        line = serial_.poll();
        if (line != NULL) {
            handle(line);
            if (ok_pending_) {
                plan(); /* from loop(): the target is planned here, and its OK follows at once */
                (void)finish_ok();
            }
        }
    }
    queue_.pump();
}

void MotionConsole::handle(const char *line)
{
    const char *cursor = line;
    char word[LINE_READER_MAX + 1];
    if (text_next_word(&cursor, word, sizeof word) == 0)
        return; /* a line of blanks: nothing to do */
    if (text_word_is(word, "?")) {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("'?' takes no arguments"));
        else
            status_pending_ = true;
    } else if (text_word_is(word, "set")) {
        handle_set(cursor);
    } else if (text_word_is(word, "stop") || text_word_is(word, "!")) {
        handle_stop(cursor, word[0] == '!');
    } else if ((word[0] >= '0' && word[0] <= '9') || word[0] == '-' || word[0] == '+') {
        if (!text_at_end(cursor))
            serial_.reply_error(MS_ERR_NOT_A_NUMBER, F("one target per line"));
        else
            handle_target(word);
    } else {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("try <target>, stop, !, ?, set v0|vmax|accel <value>"));
    }
}

void MotionConsole::handle_target(const char *word)
{
    int32_t to;
    motion_status_t st = text_parse_whole(word, INT32_MIN, INT32_MAX, &to);
    if (st != MS_OK) {
        serial_.reply_error(st, F("a target is a whole number of steps, -2147483648..2147483647"));
        return;
    }
    st = x_.moveTo(to);
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    /* the planner plans it within microseconds (longer while it plans another move, or while the
     * sigmoid's table is refilled): its OK tells where the plan starts, so it waits for that (poll()
     * reads no line meanwhile) */
    ok_pending_ = true;
    ok_target_ = to;
    (void)finish_ok();
}

bool MotionConsole::finish_ok()
{
    Stepper::PlanStart p;
    Print &out = serial_.out();
    motion_status_t st;
    if (!x_.planStart(p))
        return false;
    ok_pending_ = false;
    st = x_.lastStatus();
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
    out.print(p.from);
    out.print(' ');
    out.print(ok_target_);
    if (p.afterDone) {
        /* the move in progress ends at its target first, with its DONE (still to come) */
        out.print(F(" (after DONE "));
        out.print(p.from);
        out.print(')');
    }
    out.println();
    return true;
}

void MotionConsole::handle_stop(const char *cursor, bool halt)
{
    char word[LINE_READER_MAX + 1];
    bool moving;
    motion_status_t st;
    if (text_next_word(&cursor, word, sizeof word) != 0) {
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("stop and ! take no arguments"));
        return;
    }
    (void)collect_done(); /* a move that has just ended reports first */
    st = halt ? x_.forceStop() : x_.stop();
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    /* after the call: a move asked for and not started yet (waiting for the sigmoid's refill) is
     * dropped by it and gets no DONE: "(not moving)"; a move stepping keeps running until its end */
    moving = x_.isRunning();
    if (!moving)
        serial_.out().println(halt ? F("OK halt (not moving)") : F("OK stop (not moving)"));
    else
        serial_.out().println(halt ? F("OK halt") : F("OK stop"));
}

void MotionConsole::handle_set(const char *cursor)
{
    char key[LINE_READER_MAX + 1], value[LINE_READER_MAX + 1];
    double v = 0.0, hi;
    motion_status_t st;
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
    bool sigmoid = x_.ramp() == RAMP_ALGO_SIGMOID;
    bool whole = sigmoid && (text_word_is(key, "len") || text_word_is(key, "hold"));
    const __FlashStringHelper *unit = F(" steps/s");
    if (text_word_is(key, "v0"))
        hi = x_.minSpeedLimit();
    else if (text_word_is(key, "vmax"))
        hi = x_.maxSpeedLimit();
    else if (text_word_is(key, "accel") && sigmoid) {
        serial_.reply_error(MS_ERR_DERIVED_PARAM); /* the table's shape gives it */
        return;
    } else if (text_word_is(key, "accel")) {
        hi = x_.accelerationLimit();
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
        serial_.reply_error(MS_ERR_UNKNOWN_COMMAND, F("no such parameter (see ?)"));
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
        st = text_word_is(key, "v0")      ? x_.setMinSpeed((float)v)
             : text_word_is(key, "vmax")  ? x_.setMaxSpeed((float)v)
             : text_word_is(key, "accel") ? x_.setAcceleration((float)v)
             : text_word_is(key, "flex")  ? x_.setSigmoid((float)v, x_.sigmoidLen(), x_.sigmoidHold())
             : text_word_is(key, "len")   ? x_.setSigmoid(x_.sigmoidFlex(), (uint16_t)v, x_.sigmoidHold())
                                          : x_.setSigmoid(x_.sigmoidFlex(), x_.sigmoidLen(), (uint16_t)v);
    if (st != MS_OK) {
        serial_.reply_error(st);
        return;
    }
    out.print(F("OK "));
    print_param(out, key);
    if (x_.isRunning())
        out.print(F(" (from the next plan)"));
    out.println();
}

void MotionConsole::print_param(Print &out, const char *key)
{
    out.print(key);
    out.print('=');
    if (text_word_is(key, "len"))
        out.print(x_.sigmoidLen());
    else if (text_word_is(key, "hold"))
        out.print(x_.sigmoidHold());
    else
        print_real_exact(out, text_word_is(key, "v0")     ? x_.minSpeed()
                              : text_word_is(key, "vmax") ? x_.maxSpeed()
                              : text_word_is(key, "flex") ? x_.sigmoidFlex()
                                                          : x_.acceleration(),
                         plan);
}

void MotionConsole::print_status()
{
    Print &out = serial_.out();
    Stepper::SigmoidFigures f;
    out.print(F("pos="));
    out.print(x_.currentPosition());
    out.print(F(" target="));
    out.print(x_.targetPosition());
    out.print(F(" state="));
    out.print(ramp_phase_name(x_.rampState()));
    out.print(F(" algo="));
    out.print(ramp_algo_name(x_.ramp()));
    out.print(' ');
    print_param(out, "v0");
    out.print(' ');
    print_param(out, "vmax");
    out.print(' ');
    print_param(out, "accel");
    out.print(F(" tick_hz="));
    out.print(Stepper::tickRate());
    out.print(F(" max_sps="));
    print_real_exact(out, x_.maxSpeedLimit(), plan);
    if (x_.sigmoidFigures(f)) {
        /* the S-curve's shape, and what its table in force gives */
        out.print(' ');
        print_param(out, "flex");
        out.print(' ');
        print_param(out, "len");
        out.print(' ');
        print_param(out, "hold");
        out.print(F(" accel_steps="));
        out.print(f.accelSteps);
        out.print(F(" accel_time_s="));
        print_real_exact(out, f.accelTimeS, plan);
        out.print(F(" cruise_sps="));
        print_real_exact(out, f.cruiseSps, plan);
    }
    out.print(F(" underruns="));
    out.print(x_.underruns());
    out.print(F(" late="));
    out.print(x_.lateEdges());
    out.println(STEPPER_TIMED_LOOP ? F(" mode=loop") : F(" mode=timer"));
}
