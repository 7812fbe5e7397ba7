/* BackgroundPlanner.cpp - Timer3's interrupt keeps the step queues planned (see BackgroundPlanner.h). */
#include "BackgroundPlanner.h"

#include <avr/interrupt.h>
#include <util/atomic.h>

#include <MultiStepEngine.h>

#include "Stepper.h"

Stepper *BackgroundPlanner::axes_[3];
uint8_t BackgroundPlanner::count_;
bool BackgroundPlanner::begun_;
uint16_t BackgroundPlanner::lead_ms_ = MOTION_STEPPER_LEAD_MS;
bool BackgroundPlanner::share_;
uint32_t BackgroundPlanner::tick_hz_ = MULTI_TIMED_LOOP ? 1000000UL : MULTI_TICK_HZ;
uint8_t BackgroundPlanner::tpu_ = (uint8_t)((MULTI_TIMED_LOOP ? 1000000UL : MULTI_TICK_HZ) / 1000000UL);
bool BackgroundPlanner::in_loop_ = MULTI_TIMED_LOOP;

static volatile uint8_t s_in_tick;  /* the re-entrancy guard */
static volatile uint8_t s_locks;    /* PlannerLocks alive */
static volatile uint8_t s_deferred; /* a tick came while loop() held a lock */
static volatile uint8_t s_deferrals; /* ticks deferred by locks in a row */
/* each claimed axis's STEP bit in its port (0: no Stepper on that axis): the vector's test of a step
 * interrupt under way looks at these alone, so that a sketch may drive the other axes' STEP pins */
static volatile uint8_t s_step_mask[3];
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
    if (!begun_ || in_loop_)
        return; /* from loop(): the console's next poll() plans it */
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
    if (in_loop_) {
        begun_ = true; /* no Timer3: poll() runs the tick from loop() */
        return true;
    }
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        /* the core set Timer3 up for analogWrite(): take it over. CTC on OCR3A, 16 MHz / 64 / 250 = 1 kHz */
        TIMSK3 = 0;
        TCCR3A = 0;
        TCCR3B = 0;
        TCNT3 = 0;
        OCR3A = 249; /* the vector's retry counts from 249 */
        TIFR3 = _BV(OCF3A) | _BV(OCF3B) | _BV(OCF3C) | _BV(TOV3) | _BV(ICF3);
        TCCR3B = _BV(WGM32) | _BV(CS31) | _BV(CS30);
        TIMSK3 = _BV(OCIE3A);
#if MOTION_STEPPER_TRACE
        DDRG |= _BV(5);
#endif
    }
    begun_ = true;
    return true;
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
    if (!in_loop_ || !begun_ || s_in_tick || s_locks)
        return;
    s_in_tick = 1;
    tick();
    s_in_tick = 0;
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
        s_step_mask[axis] = (uint8_t)_BV(axis == 0 ? MULTI_X_STEP_BIT : axis == 1 ? MULTI_Y_STEP_BIT : MULTI_Z_STEP_BIT);
        if (begun_)
            apply_lead();
    }
    return true;
}

/* Commands to the stepping axis whose queue reaches least far ahead, MOTION_STEPPER_CMDS_PER_PICK at
 * a time (choosing costs about as much as laying one out); a move not yet started one at a time and
 * only when no stepping axis needs one (a move started never starves one that runs). */
void BackgroundPlanner::feed()
{
    uint8_t dry = 0;
    /* with share_: the tick's start, and half the lead in ticks: above it a long tick leaves loop()
     * its turn (MOTION_STEPPER_TICK_US); without (no smooth ramp taken), nothing: the ticks as before */
    uint32_t t0 = share_ ? micros() : 0;
    uint32_t half = share_ ? (uint32_t)leadMs() * (tick_hz_ / 2000UL) : 0;
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

void BackgroundPlanner::tick()
{
    for (uint8_t i = 0; i < 3; i++) {
        if (!axes_[i])
            continue;
        axes_[i]->refill_tick(); /* the sigmoid's table, a slice at a time */
        axes_[i]->run_request();
        if (axes_[i]->group_)
            axes_[i]->group_->run_request();
    }
    feed();
    collect_done();
    for (uint8_t i = 0; i < 3; i++)
        if (axes_[i])
            axes_[i]->plan_stop_ahead(); /* once a move cruises: its stop planned ahead */
}

/* A step interrupt is running (the engine's in_step_interrupt(): its own compare interrupt masked
 * while it computes its next step, or a match come and not yet served). The step interrupts enable
 * interrupts early so that the axes nest; the planner must not run inside one of them (its next edge
 * would wait for the whole tick). */
static bool step_isr_active()
{
    return MultiStepEngine::in_step_interrupt();
}

/* Timer3's compare match, 1 kHz, in two parts. The vector itself (naked, below) runs with interrupts
 * off for about 35 cycles: it saves r24, SREG and r25 only, returns at once during a tick or a
 * PlannerLock, and comes back later when a step interrupt is under way (the retry, about 50 cycles
 * all told). Otherwise it marks the tick under way (s_in_tick), enables interrupts and jumps to
 * __vector_planner_tick, whose register saving, last check and tick run with interrupts on: a step
 * edge due meanwhile nests. Until 2026-12-05 one ISR() did it all, with interrupts off for its
 * prologue of 22 registers and its checks (about 250 cycles when it retried, 150 before a tick): a
 * step interrupt it had interrupted, or an edge due then, waited that long, and a Stepper at 60,000
 * steps/s had edges 310 cycles late (90,000: 510; the sketches' bound is 260); now under 140 (make
 * bench, "The MotionStepper library, one Stepper"). __vector_planner_tick: a step interrupt the
 * vector cannot see (its C path without STEP, a coordinated move's master: in_step_interrupt, which
 * reads Timer1 in one snapshot) retries as the vector does; otherwise the tick runs, the step
 * interrupts and the core's millis and serial interrupts nesting in it. Its end clears s_in_tick with
 * interrupts off; its epilogue restores the SREG its prologue saved (interrupts on) before the last
 * two pops, where a tick that came just then finds the frame all but gone. */
extern "C" void __vector_planner_tick(void) __attribute__((signal, used, externally_visible));
void __vector_planner_tick(void)
{
    /* s_in_tick: set by the vector (no other tick can start from here on) */
    if (step_isr_active()) {
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
        {
            TCNT3 = OCR3A - s_retry; /* see the vector below */
        }
        if (s_retry < 62U)
            s_retry = s_retry * 2U < 62U ? (uint8_t)(s_retry * 2U) : 62U;
        s_in_tick = 0;
        return;
    }
    s_retry = MOTION_STEPPER_RETRY_COUNTS;
    s_deferrals = 0;
#if MOTION_STEPPER_TRACE == 1
    PORTG |= _BV(5); /* D4 high while the tick runs (sbi: atomic) */
#endif
    BackgroundPlanner::tick();
    cli();
#if MOTION_STEPPER_TRACE == 1
    PORTG &= (uint8_t)~_BV(5);
#endif
    s_in_tick = 0;
}

/* The vector: a tick under way -> return (no frame of __vector_planner_tick on top of a tick's: with
 * two Steppers the stack has little to spare: test/emu/ThreeSteppers overflowed it without this);
 * a PlannerLock held -> the unlock brings the tick (s_deferred); a step interrupt under way -> the
 * retry; else s_in_tick, sei and on to __vector_planner_tick. Under way: the STEP pin of an axis
 * that has a Stepper high (s_step_mask: from a step interrupt's first instructions to its end, the
 * common path, a master raising its followers' pins, and the C path of a step; also the window
 * between its sei and its arming, where a tick that was pending while it entered lands, Timer1's
 * vectors coming first; the other axes' STEP pins are the sketch's), or a common-path step interrupt
 * in its masked stretch (ANY clear and OCIE1x clear: STEP may be low already at its end, `again`).
 * TCNT3 = 249 - (s_retry + 0..3 counts: TCNT0's low bits, so that the retries do not lock onto a
 * cruise whose step period divides theirs) (OCR3A is 249: begin()); s_retry doubles up to 62, as
 * the C part's retry. */
ISR(TIMER3_COMPA_vect, ISR_NAKED)
{
    asm volatile(
        "push r24\n\t"
        "in r24, __SREG__\n\t"
        "push r24\n\t"
        "push r25\n\t"
        "lds r24, %[intick]\n\t"
        "tst r24\n\t"
        "breq 8f\n\t"
        "rjmp 6f\n\t" /* (6 is beyond a branch's reach) */
        "8: lds r24, %[locks]\n\t"
        "tst r24\n\t"
        "breq 7f\n\t"
        "ldi r24, 1\n\t"
        "sts %[deferred], r24\n\t"
        "rjmp 6f\n\t"
        "7: lds r24, %[xport]\n\t"
        "lds r25, %[maskx]\n\t"
        "and r24, r25\n\t"
        "brne 4f\n\t"
        "lds r24, %[yport]\n\t"
        "lds r25, %[masky]\n\t"
        "and r24, r25\n\t"
        "brne 4f\n\t"
        "lds r24, %[zport]\n\t"
        "lds r25, %[maskz]\n\t"
        "and r24, r25\n\t"
        "brne 4f\n\t"
        "lds r24, %[timsk]\n\t"
        "sbic %[g0], %[anyx]\n\t"
        "rjmp 1f\n\t"
        "sbrs r24, %[ociea]\n\t"
        "rjmp 4f\n\t"
        "1: sbic %[g0], %[anyy]\n\t"
        "rjmp 2f\n\t"
        "sbrs r24, %[ocieb]\n\t"
        "rjmp 4f\n\t"
        "2: sbic %[g0], %[anyz]\n\t"
        "rjmp 3f\n\t"
        "sbrs r24, %[ociec]\n\t"
        "rjmp 4f\n\t"
        "3: ldi r24, 1\n\t"
        "sts %[intick], r24\n\t"
        "pop r25\n\t"
        "pop r24\n\t"
        "out __SREG__, r24\n\t"
        "pop r24\n\t"
        "sei\n\t"
        "jmp __vector_planner_tick\n\t"
        "4: lds r25, %[retry]\n\t"
        "ldi r24, 0\n\t"
        "sts %[tcnth], r24\n\t"
        "in r24, %[tcnt0]\n\t"
        "andi r24, 3\n\t"
        "add r24, r25\n\t"
        "subi r24, 249\n\t"
        "neg r24\n\t"
        "sts %[tcntl], r24\n\t"
        "lsl r25\n\t"
        "cpi r25, 62\n\t"
        "brlo 5f\n\t"
        "ldi r25, 62\n\t"
        "5: sts %[retry], r25\n\t"
        "6: pop r25\n\t"
        "pop r24\n\t"
        "out __SREG__, r24\n\t"
        "pop r24\n\t"
        "reti\n\t"
        :
        : [timsk] "i"(_SFR_MEM_ADDR(TIMSK1)), [g0] "I"(_SFR_IO_ADDR(GPIOR0)), [anyx] "I"(MULTI_G_ANY_X),
          [anyy] "I"(MULTI_G_ANY_Y), [anyz] "I"(MULTI_G_ANY_Z), [ociea] "I"(OCIE1A), [ocieb] "I"(OCIE1B),
          [ociec] "I"(OCIE1C), [retry] "i"(&s_retry), [tcnth] "i"(_SFR_MEM_ADDR(TCNT3H)),
          [tcntl] "i"(_SFR_MEM_ADDR(TCNT3L)), [tcnt0] "I"(_SFR_IO_ADDR(TCNT0)),
          [xport] "i"(_SFR_MEM_ADDR(MULTI_X_STEP_PORT)), [yport] "i"(_SFR_MEM_ADDR(MULTI_Y_STEP_PORT)),
          [zport] "i"(_SFR_MEM_ADDR(MULTI_Z_STEP_PORT)), [maskx] "i"(&s_step_mask[0]), [masky] "i"(&s_step_mask[1]),
          [maskz] "i"(&s_step_mask[2]), [intick] "i"(&s_in_tick), [locks] "i"(&s_locks),
          [deferred] "i"(&s_deferred));
}
