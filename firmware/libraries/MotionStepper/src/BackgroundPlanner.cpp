/* BackgroundPlanner.cpp - the planner's tick, its locks and its axes (see BackgroundPlanner.h); Timer3's
 * interrupt that runs the tick is BackgroundPlannerTimer.cpp. */
#include "BackgroundPlanner.h"

#include <MultiStepEngine.h>
#include <math.h>

#include "Stepper.h"

Stepper *BackgroundPlanner::axes_[3];
uint8_t BackgroundPlanner::count_;
bool BackgroundPlanner::begun_;
uint16_t BackgroundPlanner::lead_ms_ = MOTION_STEPPER_LEAD_MS;
bool BackgroundPlanner::share_;
uint32_t BackgroundPlanner::tick_hz_ = MULTI_TIMED_LOOP ? 1000000UL : MULTI_TICK_HZ;
uint8_t BackgroundPlanner::tpu_ = (uint8_t)((MULTI_TIMED_LOOP ? 1000000UL : MULTI_TICK_HZ) / 1000000UL);
bool BackgroundPlanner::in_loop_ = MULTI_TIMED_LOOP;
uint16_t BackgroundPlanner::catch_ticks_;
uint8_t BackgroundPlanner::catch_mask_;
uint16_t BackgroundPlanner::group_bytes_;

PlannerIrqState planner_irq = {0, 0, 0, 0, {0, 0, 0}, MOTION_STEPPER_RETRY_COUNTS};
static_assert(MOTION_STEPPER_RETRY_COUNTS >= 1 && MOTION_STEPPER_RETRY_COUNTS <= 62,
              "MOTION_STEPPER_RETRY_COUNTS: 1 to 62 counts of Timer3 (OCR3A is 249; the retries double up to 62)");

/* Timer3's interrupt (BackgroundPlannerTimer.cpp), linked by MotionStepper.h's reference: a sketch
 * that includes only MotionConsole.h (its console plans in loop()) links none of it */
extern bool planner_timer_start() __attribute__((weak));
extern void planner_timer_unlocked() __attribute__((weak));
extern void planner_timer_kick() __attribute__((weak));

/* loop()'s locks (PlannerLock, BackgroundPlanner.h); a tick they deferred is brought back by the timer's
 * code (BackgroundPlannerTimer.cpp: only Timer3's interrupt defers one) */
PlannerLock::PlannerLock()
{
    planner_irq.locks = planner_irq.locks + 1U;
}

PlannerLock::~PlannerLock()
{
    planner_irq.locks = planner_irq.locks - 1U;
    if (planner_irq.locks == 0 && planner_irq.deferred && !planner_irq.in_tick)
        planner_timer_unlocked();
}

void BackgroundPlanner::kick()
{
    if (begun_ && !in_loop_)
        planner_timer_kick(); /* from loop(): the console's next poll() plans it */
}

bool BackgroundPlanner::begin()
{
    if (begun_)
        return true;
    /* the axes of the Steppers made (their constructors); a Stepper alone on X planned from loop()
     * (the stepper sketches) gets a deeper ring: the lab's ramps make about one command per step near
     * their top rate, and LeibRampStepper's 12,000 steps/s needs 96 banked (with 64 its queue ran
     * dry at the end of the acceleration); the others keep their SRAM (SmoothMove's stack) */
    if (!MultiStepEngine::begin_axes(tick_hz_, in_loop_ ? MULTI_X_ALONE_SLOTS : MULTI_SLOTS))
        return false;
    apply_lead();
    if (!in_loop_)
        planner_timer_start(); /* Timer3 (timerLinked(): Stepper::begin checked it) */
    begun_ = true; /* planned from loop(): no Timer3, poll() runs the tick */
    return true;
}

bool BackgroundPlanner::timerLinked()
{
    return planner_timer_start != 0;
}

bool BackgroundPlanner::setTickHz(uint32_t hz)
{
    if (begun_)
        return false;
    tick_hz_ = hz;
    tpu_ = (uint8_t)(hz / 1000000UL);
    return true;
}

bool BackgroundPlanner::planInLoop()
{
    if (begun_)
        return false;
    in_loop_ = true;
    return true;
}

void BackgroundPlanner::poll()
{
    MultiStepEngine::poll(); /* timed-loop mode: X's steps that are due; otherwise nothing */
    if (!in_loop_ || !begun_ || planner_irq.in_tick || planner_irq.locks)
        return;
    planner_irq.in_tick = 1;
    tick();
    planner_irq.in_tick = 0;
}

bool BackgroundPlanner::setLeadMs(uint16_t ms)
{
    if (ms < 1 || ms > 1000)
        return false;
    PlannerLock lock;
    lead_ms_ = ms;
    if (begun_)
        apply_lead();
    return true;
}

uint16_t BackgroundPlanner::leadMs()
{
    uint16_t floor = count_ >= 3 ? MOTION_STEPPER_LEAD_MS_3 : count_ == 2 ? MOTION_STEPPER_LEAD_MS_2 : 0U;
    return lead_ms_ > floor ? lead_ms_ : floor;
}

float BackgroundPlanner::stepRate()
{
    float sum = 0.0f;
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i])
            sum += fabs(MultiStepEngine::speed(i));
    return sum;
}

void BackgroundPlanner::apply_lead()
{
    MultiStepEngine::set_lead_ms(leadMs());
}

bool BackgroundPlanner::claim(uint8_t axis, Stepper *s)
{
    PlannerLock lock;
    if (axis >= 3 || (axes_[axis] && axes_[axis] != s))
        return false;
    if (!axes_[axis]) {
        axes_[axis] = s;
        count_++;
        planner_irq.step_mask[axis] = (uint8_t)_BV(axis == 0 ? MULTI_X_STEP_BIT : axis == 1 ? MULTI_Y_STEP_BIT : MULTI_Z_STEP_BIT);
        if (begun_)
            apply_lead();
    }
    return true;
}

/* Commands to the stepping axis whose queue reaches least far ahead, MOTION_STEPPER_CMDS_PER_PICK at
 * a time (choosing costs about as much as laying one out); a move not yet started one at a time and
 * only when no stepping axis needs one (a move started never starves one that runs). up_to (ticks;
 * UINT32_MAX: the lead): a stepping queue that holds that much is left as it is. */

void BackgroundPlanner::feed(uint32_t up_to, uint8_t except)
{
    uint8_t dry = 0;
    /* with share_: the tick's start, and half the lead in ticks: above it a long tick leaves loop()
     * its turn (MOTION_STEPPER_TICK_US); without (no smooth ramp taken), nothing: the ticks as before */
    uint32_t t0 = share_ ? micros() : 0;
    uint32_t half = share_ ? (uint32_t)leadMs() * (tick_hz_ / 2000UL) : 0;
    finishCuts(); /* a stop cut in the cruise: its rest first */
    /* with two axes or more stepping, each queue is reckoned from what is left of the command running
     * now (queued_ticks' rest: a slow axis's long command counted whole made its queue look deeper
     * than it was); with one, nothing to choose between, and no cycles spent on it */
    uint8_t n_step = 0;
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i] && i != except && MultiStepEngine::stepping(i))
            n_step++;
    const bool rest = n_step >= 2U;
    const uint32_t low = (uint32_t)tpu_ * (MOTION_STEPPER_LOW_MS * 1000UL);
    for (uint16_t k = 0;;) { /* (up to twice LOW_TICKS times the tick's commands: 16 bits) */
        if (k >= MOTION_STEPPER_CMDS_PER_TICK && catch_ticks_ == 0)
            break; /* (no catch-up: no look at the queues past the tick's commands) */
        uint8_t laid;
        uint32_t least = UINT32_MAX, most = 0, q_of[3];
        uint8_t pick = 3, start = 3, n = MOTION_STEPPER_CMDS_PER_PICK;
        bool overrun = false;
        for (uint8_t i = 0; i < 3; i++) {
            uint32_t q;
            q_of[i] = UINT32_MAX;
            if (!axes_[i] || i == except || (dry & (1U << i)) || !MultiStepEngine::moving(i) ||
                (k >= MOTION_STEPPER_CMDS_PER_TICK && !(catch_mask_ & (1U << i))))
                continue; /* (past the tick's commands: only the axes catching up) */
            q = MultiStepEngine::queued_ticks(i, rest);
            if (q == UINT32_MAX)
                continue;
            if (MultiStepEngine::stepping(i)) {
                if (q < up_to) {
                    q_of[i] = q;
                    if (q < least) {
                        least = q;
                        pick = i;
                    }
                    overrun = overrun || (rest && MultiStepEngine::paused(i));
                }
            } else if (start == 3 || q > most) {
                most = q;
                start = i;
            }
        }
        /* the least queue first. Only while a queue has run dry (the planner cannot keep up), the one
         * whose next step past its queue is due soonest: its queue plus its interval. When two
         * Steppers at 25,000 steps/s and 200,000 steps/s^2 stopped steeply at once beside a third
         * cruising at that rate, the least queue alone fed the two near rest, always least, and the
         * third stood still for 20-33 ms (found by a review, 2026-12-07); a step near rest waits an
         * interval of milliseconds anyway, a cruising one 40 us. (Otherwise the choice is as before:
         * the interval in it moved a StepperGroup's stop timing) */
        if (overrun) {
            uint32_t due_best = UINT32_MAX;
            for (uint8_t i = 0; i < 3; i++)
                if (q_of[i] != UINT32_MAX) {
                    const uint32_t due = q_of[i] + MultiStepEngine::interval_ticks(i);
                    if (due < due_best) {
                        due_best = due;
                        pick = i;
                    }
                }
        }
        if (share_ && pick != 3 && least >= half && micros() - t0 >= MOTION_STEPPER_TICK_US)
            break; /* every stepping queue holds half the lead: the rest at the next tick */
        if (k >= MOTION_STEPPER_CMDS_PER_TICK &&
            (pick == 3 || least >= low || (k >= MOTION_STEPPER_LOW_TICKS * MOTION_STEPPER_CMDS_PER_TICK && least >= low / 2U) ||
             k >= 2U * MOTION_STEPPER_LOW_TICKS * MOTION_STEPPER_CMDS_PER_TICK))
            break; /* (below the low mark, up to three times as many: a planner that cannot keep up stops
                    * there, unless a queue would run dry before the next tick, and at twice that at the most:
                    * loop() and the other requests get their turn) */
        if (pick == 3) {
            pick = start;
            n = 1U; /* a move not started yet: one at a time */
        }
        if (pick == 3)
            break;
        laid = MultiStepEngine::service(pick, axes_[pick]->source(), n);
        if (laid == 0)
            dry |= (uint8_t)(1U << pick);
        k = (uint16_t)(k + (laid ? laid : 1U));
    }
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i] && i != except)
            (void)MultiStepEngine::service(i, axes_[i]->source(), 0); /* starts and ends */
    for (uint8_t i = 0; i < 3; i++) {
        GroupMove *g = axes_[i] ? axes_[i]->group_ : 0;
        if (g)
            g->poll_start();
    }
}

void BackgroundPlanner::collect_done()
{
    int32_t at = 0;
    for (uint8_t i = 0; i < 3; i++) {
        Stepper *s = axes_[i];
        if (!s || !MultiStepEngine::take_done(i, at))
            continue;
        if (s->group_)
            s->group_->axis_done(i, at);
        else
            s->engine_done(at);
    }
}

void BackgroundPlanner::finishCuts()
{
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i])
            axes_[i]->cut_second_half();
}

void BackgroundPlanner::feedBeforePlan(uint8_t except)
{
    if (count_ >= 2)
        feed((uint32_t)tpu_ * (MOTION_STEPPER_PLAN_SAFE_MS * 1000UL), except);
}

void BackgroundPlanner::tick()
{
    uint8_t i = 0;
    bool any = false;
    do {
        /* the requests of the axes from i on; a stop or a new target cut an axis's queue a few
         * milliseconds ahead: with two or three Steppers the queues are fed before the next axis's
         * request, whose cut search and plan may take milliseconds more (two Steppers stopped at
         * once, the second one's searches slow: the first one's queue, a few milliseconds after its
         * cut, ran dry; test/emu/ThreeSteppers, two-20k-race), but from the first request on only
         * up to MOTION_STEPPER_URGENT_MS: the tick then returns, loop() may ask for the next axis's
         * stop, and the next tick feeds them up to the lead (planned from loop(), the tick is
         * loop()'s own: no such turn to give, and the queues are fed as before; MultiAxisStepper's
         * coordinated and independent moves lost a rung of make bench with it) */
        bool asked = false;
        for (; i < 3 && !asked; i++) {
            if (!axes_[i])
                continue;
            axes_[i]->refill_tick(); /* the sigmoid's table, a slice at a time */
            asked = axes_[i]->req_ != Stepper::REQ_NONE && count_ >= 2;
            any = any || asked;
            /* (a stop at a cut in the cruise lays out 10 ms of the stop planned ahead and plans
             * nothing: the next axis's request comes at once, not after a feed: with three Steppers
             * at 10,000 steps/s that feed put 0.4 ms between one axis's cut and the next's; the
             * feed after them is the urgent one all the same) */
            if (axes_[i]->run_request())
                asked = false;
            if (axes_[i]->group_)
                axes_[i]->group_->run_request();
        }
        feed(any && !in_loop_ ? (uint32_t)tpu_ * (MOTION_STEPPER_URGENT_MS * 1000UL) : UINT32_MAX);
    } while (i < 3);
    collect_done();
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i])
            axes_[i]->plan_stop_ahead(); /* once a move cruises: its stop planned ahead */
    if (catch_ticks_ != 0)
        catch_ticks_--;
}

void BackgroundPlanner::catchUp(uint16_t ms, uint8_t axes)
{
    catch_mask_ = catch_ticks_ != 0 ? (uint8_t)(catch_mask_ | axes) : axes;
    if (ms > catch_ticks_)
        catch_ticks_ = ms;
}
