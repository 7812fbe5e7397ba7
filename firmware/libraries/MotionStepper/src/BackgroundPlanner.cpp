/* BackgroundPlanner.cpp - Timer3's interrupt keeps the step queues planned (see BackgroundPlanner.h). */
#include "BackgroundPlanner.h"

#include <avr/interrupt.h>
#include <util/atomic.h>

#include <MultiStepEngine.h>

#include "Stepper.h"
#include "StepperGroup.h"

Stepper *BackgroundPlanner::axes_[3];
uint8_t BackgroundPlanner::count_;
bool BackgroundPlanner::begun_;
uint16_t BackgroundPlanner::lead_ms_ = MOTION_STEPPER_LEAD_MS;
bool BackgroundPlanner::share_;

static volatile uint8_t s_in_tick;  /* the re-entrancy guard */
static volatile uint8_t s_locks;    /* PlannerLocks alive */
static volatile uint8_t s_deferred; /* a tick came while loop() held a lock */
static volatile uint8_t s_deferrals; /* ticks deferred by locks in a row */
static uint8_t s_retry = MOTION_STEPPER_RETRY_COUNTS; /* Timer3 counts to the next retry */
static_assert(MOTION_STEPPER_RETRY_COUNTS >= 1 && MOTION_STEPPER_RETRY_COUNTS <= 62,
              "MOTION_STEPPER_RETRY_COUNTS: 1 to 62 counts of Timer3 (OCR3A is 249; the retries double up to 62)");

/* A tick that finds a lock held returns and leaves itself to the unlock, which brings the interrupt
 * back two counts (8 us) later: the call that held the lock returns first (a tick may plan for
 * milliseconds: a group's move from rest, 40 ms of lead, took 13.6 ms, and TwoAxesLine's moveTo then
 * "returned" after it). If that tick meets a lock again, and the next too, the third unlock runs
 * it in the caller: a loop() that takes locks all the time (polling three Steppers) does not starve
 * the planner. (Not TIMSK3: the match that comes while the interrupt is masked would wait for the
 * unmask on the chip, but libsimavr drops it.) The count is changed by loop() and, around its own
 * changes, by the tick, which leaves it as it found it: no atomic block needed. */
PlannerLock::PlannerLock()
{
    s_locks = s_locks + 1U;
}

PlannerLock::~PlannerLock()
{
    bool inline_tick = false;
    s_locks = s_locks - 1U;
    if (s_locks != 0 || !s_deferred || s_in_tick)
        return;
    /* with interrupts off: a tick that came between the count's decrement and here would otherwise
     * reset s_deferrals under this read-modify-write */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (s_deferred && !s_in_tick) {
            s_deferred = 0;
            if (s_deferrals < 2U) {
                s_deferrals = s_deferrals + 1U;
                if (TCNT3 < OCR3A - 2U)
                    TCNT3 = OCR3A - 2U;
            } else {
                s_deferrals = 0;
                s_retry = MOTION_STEPPER_RETRY_COUNTS;
                s_in_tick = 1;
                inline_tick = true;
            }
        }
    }
    if (inline_tick) {
        BackgroundPlanner::tick();
        s_in_tick = 0;
    }
}

void BackgroundPlanner::kick()
{
    if (!begun_)
        return;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        /* the match two counts (8 us) from now, unless it comes sooner anyway; under a PlannerLock
         * the unlock brings it */
        if (s_locks)
            s_deferred = 1;
        else if (!s_in_tick && TCNT3 < OCR3A - 2U)
            TCNT3 = OCR3A - 2U;
    }
}

void BackgroundPlanner::begin()
{
    if (begun_)
        return;
    MultiStepEngine::begin_axes(MULTI_TICK_HZ); /* the axes of the Steppers made (their constructors) */
    apply_lead();
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        /* the core set Timer3 up for analogWrite(): take it over. CTC on OCR3A, 16 MHz / 64 / 250 = 1 kHz */
        TIMSK3 = 0;
        TCCR3A = 0;
        TCCR3B = 0;
        TCNT3 = 0;
        OCR3A = 249;
        TIFR3 = _BV(OCF3A) | _BV(OCF3B) | _BV(OCF3C) | _BV(TOV3) | _BV(ICF3);
        TCCR3B = _BV(WGM32) | _BV(CS31) | _BV(CS30);
        TIMSK3 = _BV(OCIE3A);
#if MOTION_STEPPER_TRACE
        DDRG |= _BV(5);
#endif
    }
    begun_ = true;
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
        if (begun_)
            apply_lead();
    }
    return true;
}

/* Commands to the stepping axis whose queue reaches least far ahead, MOTION_STEPPER_CMDS_PER_PICK at
 * a time (choosing costs about as much as laying one out); a move not yet started one at a time and
 * only when no stepping axis needs one (MultiAxisConsole::feed's rule). */
void BackgroundPlanner::feed()
{
    uint8_t dry = 0;
    /* with share_: the tick's start, and half the lead in ticks: above it a long tick leaves loop()
     * its turn (MOTION_STEPPER_TICK_US); without (no smooth ramp taken), nothing: the ticks as before */
    uint32_t t0 = share_ ? micros() : 0;
    uint32_t half = share_ ? (uint32_t)leadMs() * (MULTI_TICK_HZ / 2000UL) : 0;
    for (uint8_t k = 0; k < MOTION_STEPPER_CMDS_PER_TICK;) {
        uint8_t laid;
        uint32_t best = UINT32_MAX, most = 0;
        uint8_t pick = 3, start = 3, n = MOTION_STEPPER_CMDS_PER_PICK;
        for (uint8_t i = 0; i < 3; i++) {
            uint32_t q;
            if (!axes_[i] || (dry & (1U << i)) || !MultiStepEngine::moving(i))
                continue;
            q = MultiStepEngine::queued_ticks(i);
            if (q == UINT32_MAX)
                continue;
            if (MultiStepEngine::stepping(i)) {
                if (q < best) {
                    best = q;
                    pick = i;
                }
            } else if (start == 3 || q > most) {
                most = q;
                start = i;
            }
        }
        if (share_ && pick != 3 && best >= half && micros() - t0 >= MOTION_STEPPER_TICK_US)
            break; /* every stepping queue holds half the lead: the rest at the next tick */
        if (pick == 3) {
            pick = start;
            n = 1U; /* a move not started yet: one at a time */
        }
        if (pick == 3)
            break;
        laid = MultiStepEngine::service(pick, axes_[pick]->source(), n);
        if (laid == 0)
            dry |= (uint8_t)(1U << pick);
        k = (uint8_t)(k + (laid ? laid : 1U));
    }
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i])
            (void)MultiStepEngine::service(i, axes_[i]->source(), 0); /* starts and ends */
    for (uint8_t i = 0; i < 3; i++) {
        StepperGroup *g = axes_[i] ? axes_[i]->group_ : 0;
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

void BackgroundPlanner::tick()
{
    for (uint8_t i = 0; i < 3; i++) {
        if (!axes_[i])
            continue;
        axes_[i]->run_request();
        if (axes_[i]->group_)
            axes_[i]->group_->run_request();
    }
    feed();
    collect_done();
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i])
            axes_[i]->prepare_stop(); /* once a move cruises: its stop planned ahead */
}

/* A step interrupt is running (the engine's in_step_interrupt(): its own compare interrupt masked
 * while it computes its next step, or a match come and not yet served). The step interrupts enable
 * interrupts early so that the axes nest; the planner must not run inside one of them (its next edge
 * would wait for the whole tick). */
static bool step_isr_active()
{
    return MultiStepEngine::in_step_interrupt();
}

/* Timer3's compare match, 1 kHz. Entered with interrupts off for a few dozen cycles: a tick during a
 * tick returns; one while loop() holds a PlannerLock comes back 8 us after the unlock; a tick that has interrupted a step interrupt comes back 16 us later, then later and later (TCNT3 MOTION_STEPPER_RETRY_COUNTS counts
 * before the match); otherwise interrupts are enabled at once and the tick runs, the step interrupts
 * and the core's millis and serial interrupts nesting in it. */
ISR(TIMER3_COMPA_vect)
{
    if (s_in_tick)
        return;
    if (s_locks) {
        s_deferred = 1;
        return;
    }
    if (step_isr_active()) {
        /* back in 16, 32, 64, 128, then every 248 us while it keeps landing in step interrupts
         * (see MOTION_STEPPER_RETRY_COUNTS) */
        TCNT3 = OCR3A - s_retry;
        if (s_retry < 62U)
            s_retry = s_retry * 2U < 62U ? (uint8_t)(s_retry * 2U) : 62U;
        return;
    }
    s_retry = MOTION_STEPPER_RETRY_COUNTS;
    s_deferrals = 0;
    s_in_tick = 1;
#if MOTION_STEPPER_TRACE == 1
    PORTG |= _BV(5); /* D4 high while the tick runs */
#endif
    sei();
    BackgroundPlanner::tick();
    cli();
#if MOTION_STEPPER_TRACE == 1
    PORTG &= (uint8_t)~_BV(5);
#endif
    s_in_tick = 0;
}
