/* Stepper.cpp - one RAMPS axis behind the AccelStepper-like calls (see Stepper.h). The planner
 * (step_planner_t, exact ramp) is shared with the planner interrupt (BackgroundPlanner.cpp): every
 * change here runs under a PlannerLock. Positions are kept in the engine's coordinates (DIR high
 * counts up); an inverted axis shows the user their negation. */
#include "Stepper.h"

#include <stdlib.h>
#include <string.h>
#include <util/atomic.h>

#include <BoardHeap.h>


namespace {
const uint8_t ENABLE_PIN[3] = {38, 56, 62}; /* MultiAxisPins.h: PD7, PF2, PK0 */
const uint8_t MULTI_DIR_PIN[3] = {55, 61, 48}; /* MultiAxisPins.h: PF1, PF7, PL1 */

uint8_t planner_next(void *ctx, step_cmd_t *c)
{
    return step_planner_next(static_cast<step_planner_t *>(ctx), c);
}
uint8_t planner_busy(void *ctx)
{
    return step_planner_busy(static_cast<step_planner_t *>(ctx));
}

enum { P_VMAX, P_ACCEL, P_V0 };
} // namespace

/* the sigmoid ramp's table and its parameters (heap: set_ramp_sigmoid) */
struct Stepper::Sigmoid {
    ramp_sigmoid_params_t now;  /* the table's */
    ramp_sigmoid_params_t fill; /* the refill's */
    uint16_t fill_i;
    bool filling;
    bool stale; /* parameters set while moving: refilled at the move's end */
    float accel_time_s;
    uint16_t table[SCURVE_MAX_LEN];
};

uint8_t Stepper::made_;
motion_status_t (*Stepper::exact_init_)(step_planner_t *, const ramp_params_t *, int32_t);
motion_status_t (*Stepper::exact_check_)(const ramp_params_t *);
const Stepper::Cuts *Stepper::cuts_; /* CUTS: StepperCut.cpp */

Stepper::Stepper(Axis axis, int)
{
    /* every field 0 (false, none, MS_OK, REQ_NONE) in one loop, then the others: a mem-initializer
     * per field cost 4 bytes of flash each (the fields are plain data: no virtual function, no member
     * with a constructor) */
    memset(static_cast<void *>(this), 0, sizeof *this);
    axis_ = (uint8_t)axis;
    algo_ = RAMP_ALGO_EXACT;
    enabled_ = true;
    dir_pin_ = 0xFF;
    en_pin_ = ENABLE_PIN[axis > Z ? 0 : axis];
    jerk_ = (float)STEPPER_DEFAULT_JERK;
    sig_flex_ = 5.0f;
    sig_len_ = 250;
    sig_hold_ = 4;
    made_++;
    /* the MultiAxisStepper sketch's defaults */
    params_.v0_sps = 0.0;
    params_.vmax_sps = 10000.0;
    params_.accel_sps2 = 10000.0;
    params_.tick_hz = MULTI_TICK_HZ;
}

const __FlashStringHelper *Stepper::statusText(motion_status_t status)
{
    return reinterpret_cast<const __FlashStringHelper *>(motion_status_text(status));
}

motion_status_t Stepper::begin()
{
    motion_status_t st;
    if (begun_)
        return MS_OK;
    /* the planner held off meanwhile: its tick, nested on the parameters' conversion below (64-bit
     * divisions, deep on the stack), went 1,018 bytes deep in a sketch of three Steppers and a
     * StepperGroup (a review, 2026-12-07), beyond BOARD_STACK_RESERVE: the stack ran into the rings */
    PlannerLock lock;
    if (axis_ > Z)
        return MS_ERR_OUT_OF_RANGE;
    if (begin_status_ != MS_OK)
        return begin_status_; /* the constructor's refusal */
    if (params_.vmax_sps > vmax_limit() || params_.accel_sps2 > accelerationLimit())
        return MS_ERR_RAMP_LIMIT; /* a lab ramp taken by the constructor, the library's default vmax */
    if (algo_ == RAMP_ALGO_SIGMOID && !sig_)
        return MS_ERR_TABLE_MISSING; /* made with the sigmoid: setRamp(RAMP_ALGO_SIGMOID) fills its table */
    if (!BackgroundPlanner::inLoop() && !BackgroundPlanner::timerLinked())
        return MS_ERR_NO_PLANNER_TIMER; /* Stepper.h included, not MotionStepper.h */
    st = init_planner(0);
    if (st != MS_OK)
        return st;
    if (!BackgroundPlanner::begin())
        return MS_ERR_NO_MEMORY; /* no room on the heap for the step rings */
    /* the stop planned ahead's room (StepCut.cpp), where the heap still has it beside the stack's
     * reserve: a Stepper without it plans its stop from the cruise at a cut, milliseconds later (three
     * Steppers and a StepperGroup of the three in one sketch: until 2026-12-07 the third begin()
     * refused, 340 bytes short) */
    if (!BackgroundPlanner::inLoop() && !stop_)
        (void)stop_ahead_begin();
    if (!BackgroundPlanner::claim(axis_, this))
        return MS_ERR_AXIS_TAKEN;
    step_planner_halt(&planner_, MultiStepEngine::position(axis_));
    begun_ = true;
    write_enable(enabled_ && !auto_disable_);
    install_hook();
    return MS_OK;
}

/* set by set_ramp_smooth (null in a sketch that never asks for the smooth ramp) */
motion_status_t (*Stepper::smooth_check_)(const ramp_params_t *, double);
motion_status_t (*Stepper::smooth_init_)(step_planner_t *, const ramp_params_t *, double, step_smooth_t *, int32_t);
motion_status_t (*Stepper::smooth_jerk_)(step_planner_t *, double);

/* The planner for the ramp and parameters in force, at rest at pos, with the command length of
 * set_cmd_length: the queue then holds its lead in short pieces, and a stop waits for less. */
motion_status_t Stepper::init_planner(int32_t pos)
{
    params_.tick_hz = BackgroundPlanner::tickHz();
    motion_status_t st = algo_ == RAMP_ALGO_SIGMOID ? sigmoid_init_(&planner_, &sig_->now, sig_->table, SCURVE_MAX_LEN, pos)
                         : algo_ == RAMP_ALGO_SMOOTH ? smooth_init_(&planner_, &params_, (double)jerk_, smooth_, pos)
                         : algo_ == RAMP_ALGO_EXACT ? exact_init_(&planner_, &params_, pos)
                                                    : lab_init_(&planner_, algo_, &params_, ramp_hooks_, pos);
    if (st != MS_OK)
        return st;
    set_cmd_length();
    if (stop_)
        stop_ahead_reset(); /* no stop planned ahead for this planner yet */
    return MS_OK;
}

/* The longest command, for the next plan from rest: the exact ramp's cruise MOTION_STEPPER_CRUISE_MS
 * (a stop or a new target cuts inside such a command); the lab ramps' MOTION_STEPPER_CMD_MS, or
 * MOTION_STEPPER_CMD_MS_3 with three Steppers begun. The smooth ramp keeps lib's 4 ms: its commands
 * cost more (solves), and a stop is cut tens of milliseconds ahead anyway (MOTION_STEPPER_SMOOTH_CUT_US). */
void Stepper::set_cmd_length()
{
    static_assert(MOTION_STEPPER_CRUISE_MS <= 4U && MOTION_STEPPER_CMD_MS <= 4U && MOTION_STEPPER_CMD_MS_3 <= 4U,
                  "set_cmd_length: a command of at most 4 ms (64,000 ticks at 16 MHz)");
    uint8_t ms;
    if (MULTI_TIMED_LOOP)
        ms = 0; /* one step per command: it fits between two deadlines of loop() */
    else if (BackgroundPlanner::inLoop())
        ms = 4U; /* lib's 4 ms: a cut lands 5-6 ms ahead anyway, and at 100,000 steps/s the planner has a
                    quarter of the CPU */
    else if (planner_.algo == RAMP_ALGO_SMOOTH)
        return;
    else if (planner_.algo == RAMP_ALGO_EXACT)
        ms = MOTION_STEPPER_CRUISE_MS;
    else
        ms = BackgroundPlanner::steppers() >= 3 ? MOTION_STEPPER_CMD_MS_3 : MOTION_STEPPER_CMD_MS;
    planner_.max_cmd_ticks = ms ? (uint16_t)(BackgroundPlanner::ticksPerUs() * 1000U * ms) : 1U;
    if (planner_.algo == RAMP_ALGO_EXACT)
        planner_.exact.max_cmd_ticks = planner_.max_cmd_ticks;
}

/* Whether a ramp plans with these parameters: the exact planner checks the set as a whole (vmax >
 * v0, accel >= 8, ...); a lab ramp's one-step move has the longest first interval of all its moves,
 * so if it plans, every move does (as the sketches' `set` checks). */
motion_status_t Stepper::probe(ramp_algo_t algo, const ramp_hooks_t *hooks, const ramp_params_t &p) const
{
    if (algo == RAMP_ALGO_SMOOTH)
        return smooth_check_(&p, (double)jerk_); /* set with algo_ by set_ramp_smooth */
    if (algo == RAMP_ALGO_SIGMOID) {
        ramp_sigmoid_params_t s = sigmoid_params(p);
        return sigmoid_check_(&s); /* set with algo_ by set_ramp_sigmoid */
    }
    if (algo == RAMP_ALGO_EXACT)
        return exact_check_(&p); /* set with algo_ by the constructor or setRamp; its status is the planner's */
    ramp_t r;
    return lab_probe_(&r, algo, &p, hooks, 0, 1); /* set with algo_ by set_ramp */
}

float Stepper::accelerationLimit() const
{
    /* the lab's ramps plan each step alone: the sketches' limit (StepperPins.h) */
    return algo_ == RAMP_ALGO_LEIB || algo_ == RAMP_ALGO_SIMPLISTIC ? (float)STEPPER_MAX_ACCEL
                                                                    : (float)STEPPER_MAX_ACCEL_EXACT;
}

float Stepper::minSpeedLimit() const
{
    if (algo_ != RAMP_ALGO_EXACT && algo_ != RAMP_ALGO_SMOOTH)
        return vmax_limit(); /* the lab's ramps and the sigmoid start at v0 from their first step */
    return (float)STEPPER_MAX_V0_EXACT < vmax_limit() ? (float)STEPPER_MAX_V0_EXACT : vmax_limit();
}

motion_status_t Stepper::setTickRate(uint32_t ticks_per_s)
{
#if MULTI_TIMED_LOOP
    if (ticks_per_s != 1000000UL)
        return MS_ERR_OUT_OF_RANGE;
#else
    if (ticks_per_s != 16000000UL && ticks_per_s != 2000000UL)
        return MS_ERR_OUT_OF_RANGE;
#endif
    return BackgroundPlanner::setTickHz(ticks_per_s) ? MS_OK : MS_ERR_BUSY;
}

uint32_t Stepper::tickRate()
{
    return BackgroundPlanner::tickHz();
}

float Stepper::vmax_limit() const
{
    if (algo_ == RAMP_ALGO_LEIB)
        return (float)STEPPER_MAX_SPS_LEIB;
    if (algo_ == RAMP_ALGO_SIMPLISTIC)
        return (float)STEPPER_MAX_SPS_SIMPLISTIC;
    if (algo_ == RAMP_ALGO_SMOOTH)
        return (float)STEPPER_MAX_SPS_SMOOTH;
    if (algo_ == RAMP_ALGO_SIGMOID)
        return (float)STEPPER_MAX_SPS_SCURVE;
    /* a Stepper alone, planned from loop(): the ExactRampStepper sketch's limit, measured by make bench
     * on it (no planner interrupt comes between its step interrupts) */
    if (made_ == 1 && BackgroundPlanner::inLoop() && (float)STEPPER_MAX_SPS_EXACT > (float)MULTI_MAX_SPS)
        return (float)STEPPER_MAX_SPS_EXACT;
    return (float)MULTI_MAX_SPS;
}

motion_status_t Stepper::set_ramp(ramp_algo_t algo, const ramp_hooks_t *hooks)
{
    if (algo == RAMP_ALGO_SIGMOID)
        return set_ramp_sigmoid();
    if (algo != RAMP_ALGO_EXACT && algo != RAMP_ALGO_LEIB && algo != RAMP_ALGO_SIMPLISTIC)
        return MS_ERR_OUT_OF_RANGE;
    lab_init_ = step_planner_init_lab; /* both lab ramps (one function for every algorithm): a sketch */
    lab_probe_ = ramp_plan_lab;        /* that never calls setRamp() links only the ramp it was made with */
    return switch_ramp(algo, hooks);
}

motion_status_t Stepper::switch_ramp(ramp_algo_t algo, const ramp_hooks_t *hooks)
{
    motion_status_t st;
    if (isRunning())
        return MS_ERR_BUSY;
    {
        ramp_algo_t was = algo_;
        algo_ = algo; /* for the limits */
        params_.tick_hz = BackgroundPlanner::tickHz();
        st = params_.vmax_sps > vmax_limit() || params_.accel_sps2 > accelerationLimit() ? MS_ERR_RAMP_LIMIT
                                                                                       : probe(algo, hooks, params_);
        algo_ = was;
    }
    if (st != MS_OK)
        return st;
    PlannerLock lock;
    if (isRunning())
        return MS_ERR_BUSY; /* a move was asked meanwhile (from an interrupt?) */
    algo_ = algo;
    ramp_hooks_ = hooks;
    if (sig_) {
        sig_->filling = false; /* the sigmoid's table is no longer the ramp's: no refill */
        sig_->stale = false;
    }
    MultiStepEngine::set_start_full(axis_, algo == RAMP_ALGO_SMOOTH); /* its first commands cost more than they last */
    if (begun_)
        (void)init_planner(MultiStepEngine::position(axis_)); /* probed: plans */
    return MS_OK;
}

/* ---- parameters ---- */
motion_status_t Stepper::set_param(float value, float limit, uint8_t which)
{
    ramp_params_t p = params_;
    motion_status_t st;
    p.tick_hz = BackgroundPlanner::tickHz();
    if (isnan(value) || isinf(value))
        return MS_ERR_NOT_FINITE;
    if (value > limit)
        return MS_ERR_ABOVE_LIMIT; /* (the consoles check the limit first and name it) */
    if (value == (which == P_VMAX ? params_.vmax_sps : which == P_ACCEL ? params_.accel_sps2 : params_.v0_sps))
        return MS_OK; /* the value in force: nothing changes (a loop() that sets it on every pass, as
                         AccelStepper's users do, would otherwise replan each moveTo() and turn the
                         stop planned ahead off until the next plan) */
    if (which == P_VMAX)
        p.vmax_sps = value;
    else if (which == P_ACCEL)
        p.accel_sps2 = value;
    else
        p.v0_sps = value;
    /* (the check converts the parameters, deep on the stack: the planner's tick waits for it rather
     * than nest on it; begin() says why) */
    PlannerLock lock;
    st = probe(algo_, ramp_hooks_, p);
    if (st != MS_OK)
        return st;
    params_ = p;
    set_since_plan_ = true;
    if (begun_ && algo_ == RAMP_ALGO_SIGMOID)
        sigmoid_changed(); /* the table is refilled (at rest: now; while moving: at its end) */
    else if (begun_)
        (void)step_planner_set_params(&planner_, &params_); /* from its next plan */
    return MS_OK;
}

motion_status_t Stepper::setMaxSpeed(float steps_per_s)
{
    return set_param(steps_per_s, vmax_limit(), P_VMAX);
}

motion_status_t Stepper::setAcceleration(float steps_per_s2)
{
    if (algo_ == RAMP_ALGO_SIGMOID)
        return MS_ERR_DERIVED_PARAM; /* the table's shape gives it */
    return set_param(steps_per_s2, accelerationLimit(), P_ACCEL);
}

motion_status_t Stepper::setJerk(float steps_per_s3)
{
    motion_status_t st;
    if (isnan(steps_per_s3) || isinf(steps_per_s3))
        return MS_ERR_NOT_FINITE;
    if (!(steps_per_s3 > 0.0f))
        return MS_ERR_JERK_NOT_POSITIVE;
    if (smooth_check_)
        st = smooth_check_(&params_, (double)steps_per_s3); /* the law's own rule */
    else
        st = steps_per_s3 * params_.vmax_sps < params_.accel_sps2 * params_.accel_sps2 ? MS_ERR_JERK_TOO_LOW : MS_OK;
    if (st != MS_OK)
        return st;
    PlannerLock lock;
    jerk_ = steps_per_s3;
    if (begun_ && algo_ == RAMP_ALGO_SMOOTH)
        (void)smooth_jerk_(&planner_, (double)jerk_); /* checked: from its next move from rest */
    return MS_OK;
}

motion_status_t Stepper::setMinSpeed(float steps_per_s)
{
    return set_param(steps_per_s, minSpeedLimit(), P_V0);
}

/* ---- moves ----
 * A plan costs milliseconds on the AVR, so loop() only leaves a request and brings the planner
 * interrupt's next tick forward (kick); the tick carries it out (run_request) before it lays out
 * commands. */
motion_status_t Stepper::moveTo(long target)
{
    return move_to(target, false);
}

motion_status_t Stepper::move_to(long target, bool replan)
{
    if (!begun_)
        return MS_ERR_NOT_BEGUN;
    {
        PlannerLock lock;
        if (group_)
            return MS_ERR_BUSY;
        if (!reachable(target))
            return MS_ERR_OUT_OF_RANGE;
        int32_t to = to_engine(target);
        if (!replan) {
            /* the target in force while moving (targetPosition()), or where the axis rests: nothing
             * to plan (until 2026-12-07 every call replanned, some 0.8 ms of the planner interrupt
             * each while moving: a loop() calling moveTo(20000) on every pass got one pass in 0.5 ms,
             * and at rest each call was a move of no step, so one that called it until isRunning()
             * went false never left; test/emu/SameTarget) */
            if (MultiStepEngine::moving(axis_) ? req_ != REQ_STOP && !set_since_plan_ &&
                                                     to == (req_ == REQ_MOVE ? req_target_
                                                            : has_next_      ? next_target_
                                                                             : step_planner_target(&planner_))
                                               : req_ == REQ_NONE && !has_next_ && to == MultiStepEngine::position(axis_)) {
                if (req_ == REQ_NONE && MultiStepEngine::moving(axis_))
                    last_status_ = MS_OK; /* the target in force: accepted (an earlier refusal is past) */
                return MS_OK;
            }
        }
        req_target_ = to;
        req_ = REQ_MOVE;
        cut_retry_us_ = 0; /* a new request: its cut is tried afresh */
        cut_tries_ = 0;
        if (auto_disable_)
            write_enable(true);
    }
    BackgroundPlanner::kick(); /* planned within microseconds, not at the next tick */
    return MS_OK;
}

motion_status_t Stepper::move(long distance)
{
    if (!begun_)
        return MS_ERR_NOT_BEGUN;
    /* (in 64 bits: near the end of a long's range the sum wrapped round, and the axis went the
     * other way; found by a review, 2026-12-07) */
    const int64_t to = (int64_t)targetPosition() + distance;
    if (to < INT32_MIN || to > INT32_MAX)
        return MS_ERR_OUT_OF_RANGE;
    return moveTo((long)to);
}

bool Stepper::reachable(long user) const
{
    if (!fits_engine(user))
        return false; /* (before to_engine: its negation of LONG_MIN would overflow) */
    const int64_t d = (int64_t)to_engine(user) - MultiStepEngine::position(axis_);
    return d <= INT32_MAX && d >= -(int64_t)INT32_MAX;
}

motion_status_t Stepper::stop()
{
    if (!begun_)
        return MS_ERR_NOT_BEGUN;
    {
        PlannerLock lock;
        if (group_)
            return group_->stop();
        has_next_ = false; /* a target waiting for the move's end is dropped */
        if (!MultiStepEngine::moving(axis_))
            req_ = REQ_NONE; /* a move not started yet: it never starts */
        else
            req_ = REQ_STOP;
        cut_retry_us_ = 0;
        cut_tries_ = 0;
    }
    BackgroundPlanner::kick();
    return MS_OK;
}

motion_status_t Stepper::forceStop()
{
    if (!begun_)
        return MS_ERR_NOT_BEGUN;
    PlannerLock lock;
    if (group_)
        return group_->forceStop();
    has_next_ = false;
    req_ = REQ_NONE;
    if (!MultiStepEngine::moving(axis_))
        return MS_OK;
    MultiStepEngine::halt(axis_); /* its end is collected by the planner interrupt (or setCurrentPosition) */
    step_planner_halt(&planner_, MultiStepEngine::position(axis_));
    return MS_OK;
}

/* planner interrupt: the request loop() left */
bool Stepper::run_request()
{
    uint8_t r = req_;
    int32_t ended;
    MultiStepEngine::Continuation c;
    motion_status_t st;
    if (r == REQ_NONE)
        return false;
    if (r == REQ_MOVE && algo_ == RAMP_ALGO_SIGMOID && sig_ && sig_->filling && !MultiStepEngine::moving(axis_))
        return false; /* the sigmoid's table is being refilled: the move from rest waits for it */
    req_ = REQ_NONE;
    set_since_plan_ = false; /* the parameters in force go into this plan */
    if (r == REQ_STOP) {
        /* every step queued already: the stop can act only through a cut (cut_apply withdraws the
         * move's end mark when it comes off), so the mark stays while the cut is tried; withdrawn
         * meanwhile (extend), a stop that came as the last queued steps ran counted the move's end
         * as an underrun (make fuzz, seed 6: a `stop` within a millisecond of the end of a move at
         * 776,404 steps/s^2) */
        bool all_queued = !step_planner_busy(&planner_);
        /* (all queued: a move that ended meanwhile, or an axis at rest, has no queue to cut; its end
         * is collected as any other, BackgroundPlanner::collect_done) */
        c = all_queued ? MultiStepEngine::CONTINUES : MultiStepEngine::extend(axis_, ended);
        if (c == MultiStepEngine::CONTINUES) {
            /* (with two or three Steppers stopped at once the cuts come one after the other: the
             * tick feeds this one's queue a little before the next one's, BackgroundPlanner::tick;
             * the stop planned ahead lays out 10 ms of its steps at once) */
            if (cut_retry_us_ == 0 && cut_in_cruise(false, 0))
                return true;
            if (cut_plan(REQ_STOP, 0)) {
                /* the cut withdrew the move's end mark: a stop whose first commands are all of it (one
                 * that comes as the move's last steps run) marks it again at once, before the interrupt
                 * steps them out (else its end counted as an underrun: make fuzz's seed-6 replay) */
                (void)MultiStepEngine::service(axis_, source(), 0);
                return false;
            }
            if (cut_again())
                req_ = REQ_STOP; /* its cut is tried again at the next pass, farther ahead */
            else
                step_planner_stop(&planner_); /* after the steps already queued (all queued: nothing) */
        } else if (c == MultiStepEngine::ENDED)
            engine_done(ended); /* it had just ended: its end is reported */
        return false;
    }
    plan_after_done_ = false;
    plan_done_before_ = done_; /* an end not taken yet is an earlier move's */
    if (MultiStepEngine::moving(axis_) && !beyond_plan(req_target_)) {
        bool quick = cut_retry_us_ == 0 && cut_in_cruise(true, req_target_);
        if (quick || cut_plan(REQ_MOVE, req_target_)) {
            /* the move continues into the new plan from the cut (plan_from_: set there) */
            has_next_ = false;
            last_status_ = MS_OK;
            return quick;
        }
    }
    if (MultiStepEngine::moving(axis_) && cut_again()) {
        req_ = REQ_MOVE; /* its cut is tried again at the next pass, farther ahead (planStart: not yet) */
        return false;
    }
    if (MultiStepEngine::moving(axis_) && !step_planner_busy(&planner_)) {
        /* every step of the move is queued already: it ends at its target (with its end), and the
         * new move starts from rest there */
        has_next_ = true;
        next_target_ = req_target_;
        plan_from_ = step_planner_target(&planner_);
        plan_after_done_ = true;
        last_status_ = MS_OK;
        return false;
    }
    c = MultiStepEngine::extend(axis_, ended);
    if (c == MultiStepEngine::ENDED) {
        engine_done(ended);
        if (MultiStepEngine::moving(axis_)) /* a target waiting for that end has just started */
            c = MultiStepEngine::extend(axis_, ended);
        else
            c = MultiStepEngine::AT_REST;
    }
    if (c == MultiStepEngine::AT_REST) {
        step_planner_halt(&planner_, MultiStepEngine::position(axis_));
        set_cmd_length(); /* a Stepper begun since the last move may have changed it */
    }
    plan_done_before_ = done_; /* with the end of the move that ended just now */
    st = step_planner_move(&planner_, req_target_);
    last_status_ = st;
    plan_from_ = step_planner_position(&planner_); /* after the steps already handed to the queue */
    if (st != MS_OK) {
        /* a continuing move goes on as planned (service() marks its end again); from rest nothing moves */
        if (c == MultiStepEngine::AT_REST && auto_disable_)
            write_enable(false);
        return false;
    }
    has_next_ = false;
    if (c == MultiStepEngine::AT_REST) {
        if (!keep_done_)
            done_ = false; /* a new move clears an end not taken ... */
        keep_done_ = false; /* ... but not the end of the move this target waited for */
        MultiStepEngine::open_move(axis_, false);
    }
    return false;
}

/* A new target as far as the plan's or farther, in its direction, while the exact planner has handed
 * out only the acceleration and the cruise: every queued step is one the new plan makes too (it slows
 * down no sooner), so it is planned after them, with no cut. A cut would drop the queued commands and
 * plan the same steps again: with three Steppers planned from loop() at about 320,000 steps/s^2 that
 * rebanking, beside the other axes' moves near rest, starved every axis for 1-2 ms (make fuzz, seed 6:
 * test/data/fuzz-replays/MultiAxisStepper-retargets-high-accel-underruns.emu). */
bool Stepper::beyond_plan(int32_t to) const
{
    const step_exact_t &e = planner_.exact;
    if (planner_.algo != RAMP_ALGO_EXACT || !planner_.active || planner_.has_then || planner_.params_new || !e.moving ||
        e.a_down || e.n >= e.n2)
        return false;
    return e.dir > 0 ? to >= planner_.target : to <= planner_.target;
}

/* ---- state ---- */
/* one-byte reads: no lock, so that a loop() polling it leaves the planner interrupt alone */
bool Stepper::isRunning() const
{
    return req_ == REQ_MOVE || has_next_ || group_ != 0 || MultiStepEngine::moving(axis_);
}

/* The group the axis moves in, read whole (the planner interrupt clears it at the move's end). */
GroupMove *Stepper::group_now() const
{
    GroupMove *g;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        g = group_;
    }
    return g;
}

/* Polled calls take the PlannerLock only in a group's move: a loop() polling them alone never keeps
 * the planner interrupt waiting. */
long Stepper::currentPosition() const
{
    if (group_now()) {
        PlannerLock lock;
        if (group_)
            return to_user(group_->position_of(axis_));
    }
    return to_user(MultiStepEngine::position(axis_));
}

motion_status_t Stepper::setCurrentPosition(long position)
{
    if (!begun_)
        return MS_ERR_NOT_BEGUN;
    if (!fits_engine(position))
        return MS_ERR_OUT_OF_RANGE;
    int32_t p = to_engine(position), at;
    PlannerLock lock;
    if (req_ != REQ_NONE || has_next_ || group_)
        return MS_ERR_BUSY;
    /* a move whose last step is made, or that forceStop() halted, but whose end the planner interrupt
     * has not collected yet (up to a tick): collected here, as it would be there. Without it
     * `forceStop(); setCurrentPosition(0);` was refused 20 times in 20, and so was AccelStepper's
     * `if (distanceToGo() == 0) setCurrentPosition(0);` for some 0.4 ms after the last step (found by
     * a review, 2026-12-07) */
    if (MultiStepEngine::moving(axis_) && MultiStepEngine::take_done(axis_, at))
        engine_done(at);
    if (req_ != REQ_NONE || has_next_ || MultiStepEngine::moving(axis_))
        return MS_ERR_BUSY;
    MultiStepEngine::set_rest_position(axis_, p);
    step_planner_halt(&planner_, p);
    return MS_OK;
}

long Stepper::targetPosition() const
{
    int32_t t;
    if (!begun_)
        return 0;
    if (group_now()) {
        PlannerLock lock;
        if (group_)
            return to_user(group_->target_of(axis_));
    }
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        t = req_ == REQ_MOVE ? req_target_ : has_next_ ? next_target_ : step_planner_target(&planner_);
    }
    return to_user(t);
}

float Stepper::speed() const
{
    uint8_t a = axis_;
    float v;
    bool flip = false;
    if (!begun_)
        return 0.0f;
    if (group_now()) {
        PlannerLock lock;
        if (group_)
            a = group_->interrupt_of(axis_, flip);
    }
    v = MultiStepEngine::speed(a);
    if (flip)
        v = -v;
    return inverted_ ? -v : v;
}

bool Stepper::takeDone(long &position)
{
    if (!done_)
        return false; /* a one-byte read: polling needs no lock */
    PlannerLock lock;
    if (!done_)
        return false;
    done_ = false;
    position = to_user(done_pos_);
    return true;
}

uint16_t Stepper::underruns() const
{
    return begun_ ? MultiStepEngine::underruns(axis_) : 0;
}

uint16_t Stepper::lateEdges() const
{
    return begun_ ? MultiStepEngine::late_edges(axis_) : 0;
}

ramp_phase_t Stepper::rampState() const
{
    uint8_t phase;
    if (!MultiStepEngine::moving(axis_))
        /* at rest; a move asked for and not yet stepping counts as accelerating (a member of a
         * group's move at its target already: at rest) */
        return isRunning() && !group_now() ? RAMP_ACCEL : RAMP_IDLE;
    phase = MultiStepEngine::phase(axis_);
    return phase != 0 ? (ramp_phase_t)phase : RAMP_ACCEL;
}

bool Stepper::planStart(PlanStart &start) const
{
    if (req_ == REQ_MOVE)
        return false; /* a one-byte read: not planned yet */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        start.from = to_user(plan_from_);
        start.afterDone = plan_after_done_;
        start.doneBefore = plan_done_before_;
    }
    return true;
}

/* ---- enable and direction ---- */
void Stepper::write_enable(bool on)
{
    if (!begun_)
        return;
    pinMode(en_pin_, OUTPUT);
    digitalWrite(en_pin_, on == enable_high_ ? HIGH : LOW);
}

void Stepper::enableOutputs()
{
    PlannerLock lock;
    enabled_ = true;
    write_enable(true);
}

void Stepper::disableOutputs()
{
    PlannerLock lock;
    enabled_ = false;
    write_enable(false);
}

void Stepper::setAutoDisable(bool on)
{
    PlannerLock lock;
    auto_disable_ = on;
    if (begun_ && !isRunning())
        write_enable(!on && enabled_);
}

void Stepper::setEnableActiveHigh(bool active_high)
{
    PlannerLock lock;
    bool on = begun_ && (isRunning() || (enabled_ && !auto_disable_));
    enable_high_ = active_high;
    write_enable(on);
}

motion_status_t Stepper::setDirectionInverted(bool inverted)
{
    PlannerLock lock;
    if (begun_ && isRunning())
        return MS_ERR_BUSY;
    if (inverted != inverted_ && begun_) {
        /* the user's position stays: the engine's becomes its negation (LONG_MIN has none) */
        if (MultiStepEngine::position(axis_) == INT32_MIN)
            return MS_ERR_OUT_OF_RANGE;
        int32_t p = -MultiStepEngine::position(axis_);
        MultiStepEngine::set_rest_position(axis_, p);
        step_planner_halt(&planner_, p);
    }
    inverted_ = inverted;
    return MS_OK;
}

motion_status_t Stepper::setDirectionHook(DirectionHook hook)
{
    PlannerLock lock;
    if (begun_ && isRunning())
        return MS_ERR_BUSY;
    hook_ = hook;
    install_hook();
    return MS_OK;
}

/* the engine calls call_hook (through hook_x/y/z) while a hook or another DIR pin is set */
void Stepper::install_hook()
{
    if (begun_)
        MultiStepEngine::set_direction_hook(
            axis_, (hook_ || dir_pin_ != 0xFF) ? (axis_ == X ? hook_x : axis_ == Y ? hook_y : hook_z) : 0);
}

static bool is_pin(uint8_t pin)
{
    return pin < NUM_DIGITAL_PINS && digitalPinToPort(pin) != NOT_A_PIN;
}

motion_status_t Stepper::setDirectionPin(uint8_t pin)
{
    if (!is_pin(pin))
        return MS_ERR_OUT_OF_RANGE;
    PlannerLock lock;
    if (begun_ && isRunning())
        return MS_ERR_BUSY;
    dir_pin_ = pin == MULTI_DIR_PIN[axis_ > Z ? 0 : axis_] ? 0xFF : pin;
    if (dir_pin_ != 0xFF)
        pinMode(dir_pin_, OUTPUT);
    install_hook();
    return MS_OK;
}

uint8_t Stepper::directionPin() const
{
    return dir_pin_ != 0xFF ? dir_pin_ : MULTI_DIR_PIN[axis_ > Z ? 0 : axis_];
}

motion_status_t Stepper::setEnablePin(uint8_t pin)
{
    if (!is_pin(pin))
        return MS_ERR_OUT_OF_RANGE;
    PlannerLock lock;
    if (begun_ && isRunning())
        return MS_ERR_BUSY;
    en_pin_ = pin;
    write_enable(enabled_ && !auto_disable_);
    return MS_OK;
}

/* the engine's hook gets its own direction (DIR high); the user's counts in their sense; another
 * DIR pin takes the engine's */
void Stepper::call_hook(uint8_t axis, bool forward)
{
    Stepper *s = BackgroundPlanner::stepper(axis);
    if (!s)
        return;
    if (s->hook_)
        s->hook_(s->inverted_ ? !forward : forward);
    else if (s->dir_pin_ != 0xFF)
        digitalWrite(s->dir_pin_, forward ? HIGH : LOW);
}
void Stepper::hook_x(bool forward)
{
    call_hook(X, forward);
}
void Stepper::hook_y(bool forward)
{
    call_hook(Y, forward);
}
void Stepper::hook_z(bool forward)
{
    call_hook(Z, forward);
}

/* ---- the planner interrupt's side ---- */
__attribute__((noinline)) AxisSource Stepper::source()
{
    AxisSource s;
    if (group_)
        return group_->source_of(axis_);
    s.next = planner_next;
    s.busy = planner_busy;
    s.ctx = &planner_;
    return s;
}

void Stepper::record_done(int32_t engine_position)
{
    if (sig_ && sig_->stale)
        sigmoid_refill_start(); /* parameters set during the move (a group's ends here) */
    done_pos_ = engine_position;
    done_ = true;
    if (auto_disable_)
        write_enable(false);
}

void Stepper::engine_done(int32_t position)
{
    step_planner_halt(&planner_, position);
    if (sig_ && sig_->stale) {
        /* the sigmoid's parameters changed during the move: its table is refilled now, and a target
         * that waited for this end is planned once it is ready (run_request) */
        sigmoid_refill_start();
        if (has_next_) {
            has_next_ = false;
            req_target_ = next_target_;
            req_ = REQ_MOVE;
            keep_done_ = true;
            done_pos_ = position;
            done_ = true;
            return;
        }
    }
    if (has_next_) {
        /* the target accepted while the last steps ran: the move that ended keeps its end (planStart's
         * afterDone), and the new one starts now, from rest */
        has_next_ = false;
        set_cmd_length(); /* a Stepper begun since the last move may have changed it */
        done_pos_ = position;
        done_ = true;
        if (step_planner_move(&planner_, next_target_) == MS_OK) {
            MultiStepEngine::open_move(axis_, false);
            return;
        }
    }
    record_done(position);
}

/* ---- the sigmoid ramp (RAMP_ALGO_SIGMOID) ---- */
void (*Stepper::sigmoid_slice_)(Stepper &);
motion_status_t (*Stepper::sigmoid_check_)(const ramp_sigmoid_params_t *);
motion_status_t (*Stepper::sigmoid_shape_)(Stepper &, float, uint16_t, uint16_t);

motion_status_t Stepper::sigmoid_shape(Stepper &s, float flex, uint16_t len, uint16_t hold)
{
    return s.setSigmoid(flex, len, hold);
}
motion_status_t (*Stepper::sigmoid_init_)(step_planner_t *, const ramp_sigmoid_params_t *, const uint16_t *, uint16_t,
                                          int32_t);

ramp_sigmoid_params_t Stepper::sigmoid_params(const ramp_params_t &p, float flex, uint16_t len, uint16_t hold)
{
    ramp_sigmoid_params_t s;
    s.len = len;
    s.hold = hold;
    s.fmin_hz = (float)p.v0_sps;
    s.fmax_hz = (float)p.vmax_sps;
    s.flex = flex;
    s.timer_hz = BackgroundPlanner::tickHz();
    return s;
}

/* the table in force is now filled: what acceleration() and sigmoidFigures() tell of it */
static float table_accel(const ramp_sigmoid_params_t &p, const uint16_t *table, float &time_s)
{
    time_s = (float)ramp_sigmoid_accel_time_s(&p, table);
    return time_s > 0.0f ? ((float)p.timer_hz / table[p.len - 1U] - (float)p.timer_hz / table[0]) / time_s : 0.0f;
}

motion_status_t Stepper::set_ramp_sigmoid()
{
    ramp_params_t p = params_;
    ramp_sigmoid_params_t s;
    motion_status_t st;
    if (isRunning())
        return MS_ERR_BUSY;
    p.tick_hz = BackgroundPlanner::tickHz();
    s = sigmoid_params(p);
    if (p.vmax_sps > (float)STEPPER_MAX_SPS_SCURVE)
        return MS_ERR_RAMP_LIMIT;
    st = ramp_sigmoid_check(&s);
    if (st != MS_OK)
        return st;
    if (!sig_) {
        sig_ = static_cast<Sigmoid *>(board_take(sizeof(Sigmoid)));
        if (!sig_)
            return MS_ERR_NO_MEMORY; /* no room on the heap for its table */
        sig_->filling = false;
        sig_->stale = false;
        sig_->fill_i = 0;
    }
    sigmoid_slice_ = sigmoid_slice;
    sigmoid_init_ = step_planner_init_sigmoid;
    sigmoid_check_ = ramp_sigmoid_check;
    sigmoid_shape_ = sigmoid_shape;
    {
        PlannerLock lock;
        if (isRunning())
            return MS_ERR_BUSY;
        sig_->filling = false; /* a refill under way stops: the table is filled whole below */
        sig_->stale = false;
    }
    /* without the lock (0.1 s for 250 entries: other axes' planning must go on); this axis is at rest
     * and no refill runs, so nothing else writes the table meanwhile. Checked: it fills. */
    st = ramp_sigmoid_fill(&s, sig_->table, SCURVE_MAX_LEN);
    if (st != MS_OK)
        return st;
    PlannerLock lock;
    if (isRunning())
        return MS_ERR_BUSY; /* a move asked meanwhile (from an interrupt?): the ramp stays */
    sig_->now = s;
    sig_->filling = false;
    sig_->stale = false;
    params_ = p;
    params_.accel_sps2 = table_accel(s, sig_->table, sig_->accel_time_s);
    algo_ = RAMP_ALGO_SIGMOID;
    ramp_hooks_ = 0;
    MultiStepEngine::set_start_full(axis_, false);
    if (begun_)
        (void)init_planner(MultiStepEngine::position(axis_));
    return MS_OK;
}

motion_status_t Stepper::setSigmoid(float flex, uint16_t len, uint16_t hold)
{
    ramp_params_t p = params_;
    ramp_sigmoid_params_t s;
    motion_status_t st;
    if (isnan(flex) || isinf(flex))
        return MS_ERR_NOT_FINITE;
    if (flex > (float)STEPPER_MAX_FLEX || len > SCURVE_MAX_LEN)
        return MS_ERR_OUT_OF_RANGE;
    p.tick_hz = BackgroundPlanner::tickHz();
    s = sigmoid_params(p, flex, len, hold); /* the members change only once it is checked */
    st = ramp_sigmoid_check(&s);
    if (st != MS_OK)
        return st;
    PlannerLock lock;
    sig_flex_ = flex;
    sig_len_ = len;
    sig_hold_ = hold;
    if (begun_ && algo_ == RAMP_ALGO_SIGMOID)
        sigmoid_changed();
    return MS_OK;
}

bool Stepper::sigmoidFigures(SigmoidFigures &f) const
{
    if (algo_ != RAMP_ALGO_SIGMOID || !sig_)
        return false;
    PlannerLock lock; /* the table in force, not half a refill */
    const ramp_sigmoid_params_t &p = sig_->now;
    f.accelSteps = ramp_sigmoid_accel_steps(&p);
    f.accelTimeS = sig_->accel_time_s;
    f.cruiseSps = (float)p.timer_hz / sig_->table[p.len - 1U];
    return true;
}

/* under a PlannerLock or in the planner interrupt */
void Stepper::sigmoid_changed()
{
    if (MultiStepEngine::moving(axis_))
        sig_->stale = true; /* the move walks the table in force: refilled at its end */
    else
        sigmoid_refill_start();
}

void Stepper::sigmoid_refill_start()
{
    sig_->stale = false;
    sig_->fill = sigmoid_params(params_);
    sig_->fill_i = 0;
    sig_->filling = true;
}

/* planner interrupt (BackgroundPlanner::tick): two entries of the refill (about 13,000 cycles), then,
 * once all are in, the planner on the new table at rest */
void Stepper::sigmoid_slice(Stepper &s)
{
    Sigmoid &g = *s.sig_;
    for (uint8_t n = 0; n < 2U && g.fill_i < g.fill.len; n++, g.fill_i++)
        g.table[g.fill_i] = (uint16_t)ramp_sigmoid_period_ticks(&g.fill, g.fill_i);
    if (g.fill_i < g.fill.len)
        return;
    g.now = g.fill;
    g.filling = false;
    s.params_.accel_sps2 = table_accel(g.now, g.table, g.accel_time_s);
    (void)s.init_planner(MultiStepEngine::position(s.axis_));
}

void Stepper::refill_tick()
{
    if (algo_ == RAMP_ALGO_SIGMOID && sig_ && sig_->filling && sigmoid_slice_)
        sigmoid_slice_(*this);
}
