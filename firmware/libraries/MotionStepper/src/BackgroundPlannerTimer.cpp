/* BackgroundPlannerTimer.cpp - Timer3's compare interrupt, 1 kHz, that runs BackgroundPlanner::tick()
 * with interrupts enabled (see BackgroundPlanner.h). Its own file, in the library's archive: it is
 * linked only into a sketch whose code names planner_timer_start (MotionStepper.h does), so the stepper
 * sketches' console, which plans in loop() and includes MotionConsole.h alone, carries none of it
 * (about 500 bytes of flash). */
#include <avr/interrupt.h>
#include <util/atomic.h>

#include <MultiStepEngine.h>

#include "BackgroundPlanner.h"

/* BackgroundPlanner::begin(), once, unless it plans from loop() */
bool planner_timer_start()
{
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
    return true;
}

/* A tick that finds a lock held returns and leaves itself to the unlock, which brings the interrupt
 * back two counts (8 us) later: the call that held the lock returns first (a tick may plan for
 * milliseconds: a group's move from rest, 40 ms of lead, took 13.6 ms, and TwoAxesLine's moveTo then
 * "returned" after it). If that tick meets a lock again, and the next too, the third unlock runs
 * it in the caller: a loop() that takes locks all the time (polling three Steppers) does not starve
 * the planner. (Not TIMSK3: the match that comes while the interrupt is masked would wait for the
 * unmask on the chip, but libsimavr drops it.) The count is changed by loop() and, around its own
 * changes, by the tick, which leaves it as it found it: no atomic block needed. */
void planner_timer_unlocked()
{
    bool inline_tick = false;
    /* with interrupts off: a tick that came between the count's decrement and here would otherwise
     * reset planner_irq.deferrals under this read-modify-write */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (planner_irq.deferred && !planner_irq.in_tick) {
            planner_irq.deferred = 0;
            if (planner_irq.deferrals < 2U) {
                planner_irq.deferrals = planner_irq.deferrals + 1U;
                if (TCNT3 < OCR3A - 2U)
                    TCNT3 = OCR3A - 2U;
            } else {
                planner_irq.deferrals = 0;
                planner_irq.retry = MOTION_STEPPER_RETRY_COUNTS;
                planner_irq.in_tick = 1;
                inline_tick = true;
            }
        }
    }
    if (inline_tick) {
        BackgroundPlanner::tick();
        planner_irq.in_tick = 0;
    }
}

/* BackgroundPlanner::kick(): the next tick within about 50 us (MOTION_STEPPER_KICK_COUNTS) */
void planner_timer_kick()
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        /* the match MOTION_STEPPER_KICK_COUNTS counts from now, unless it comes sooner anyway;
         * under a PlannerLock the unlock brings it */
        if (planner_irq.locks)
            planner_irq.deferred = 1;
        else if (!planner_irq.in_tick && TCNT3 < OCR3A - MOTION_STEPPER_KICK_COUNTS)
            TCNT3 = OCR3A - MOTION_STEPPER_KICK_COUNTS;
    }
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
 * all told). Otherwise it marks the tick under way (planner_irq.in_tick), enables interrupts and jumps to
 * __vector_planner_tick, whose register saving, last check and tick run with interrupts on: a step
 * edge due meanwhile nests. Until 2026-12-05 one ISR() did it all, with interrupts off for its
 * prologue of 22 registers and its checks (about 250 cycles when it retried, 150 before a tick): a
 * step interrupt it had interrupted, or an edge due then, waited that long, and a Stepper at 60,000
 * steps/s had edges 310 cycles late (90,000: 510; the sketches' bound is 260); now under 140 (make
 * bench, "The MotionStepper library, one Stepper"). __vector_planner_tick: a step interrupt the
 * vector cannot see (its C path without STEP, a coordinated move's master: in_step_interrupt, which
 * reads Timer1 in one snapshot) retries as the vector does; otherwise the tick runs, the step
 * interrupts and the core's millis and serial interrupts nesting in it. Its end clears planner_irq.in_tick with
 * interrupts off; its epilogue restores the SREG its prologue saved (interrupts on) before the last
 * two pops, where a tick that came just then finds the frame all but gone. */
extern "C" void __vector_planner_tick(void) __attribute__((signal, used, externally_visible));
void __vector_planner_tick(void)
{
    /* planner_irq.in_tick: set by the vector (no other tick can start from here on) */
    if (step_isr_active()) {
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
        {
            TCNT3 = OCR3A - planner_irq.retry; /* see the vector below */
        }
        if (planner_irq.retry < 62U)
            planner_irq.retry = planner_irq.retry * 2U < 62U ? (uint8_t)(planner_irq.retry * 2U) : 62U;
        planner_irq.in_tick = 0;
        return;
    }
    planner_irq.retry = MOTION_STEPPER_RETRY_COUNTS;
    planner_irq.deferrals = 0;
#if MOTION_STEPPER_TRACE == 1
    PORTG |= _BV(5); /* D4 high while the tick runs (sbi: atomic) */
#endif
    BackgroundPlanner::tick();
    cli();
#if MOTION_STEPPER_TRACE == 1
    PORTG &= (uint8_t)~_BV(5);
#endif
    planner_irq.in_tick = 0;
}

/* The vector: a tick under way -> return (no frame of __vector_planner_tick on top of a tick's: with
 * two Steppers the stack has little to spare: test/emu/ThreeSteppers overflowed it without this);
 * a PlannerLock held -> the unlock brings the tick (planner_irq.deferred); a step interrupt under way -> the
 * retry; else planner_irq.in_tick, sei and on to __vector_planner_tick. Under way: the STEP pin of an axis
 * that has a Stepper high (planner_irq.step_mask: from a step interrupt's first instructions to its end, the
 * common path, a master raising its followers' pins, and the C path of a step; also the window
 * between its sei and its arming, where a tick that was pending while it entered lands, Timer1's
 * vectors coming first; the other axes' STEP pins are the sketch's), or a common-path step interrupt
 * in its masked stretch (ANY clear and OCIE1x clear: STEP may be low already at its end, `again`).
 * TCNT3 = 249 - (planner_irq.retry + 0..3 counts: TCNT0's low bits, so that the retries do not lock onto a
 * cruise whose step period divides theirs) (OCR3A is 249: begin()); planner_irq.retry doubles up to 62, as
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
          [ociec] "I"(OCIE1C), [retry] "i"(&planner_irq.retry), [tcnth] "i"(_SFR_MEM_ADDR(TCNT3H)),
          [tcntl] "i"(_SFR_MEM_ADDR(TCNT3L)), [tcnt0] "I"(_SFR_IO_ADDR(TCNT0)),
          [xport] "i"(_SFR_MEM_ADDR(MULTI_X_STEP_PORT)), [yport] "i"(_SFR_MEM_ADDR(MULTI_Y_STEP_PORT)),
          [zport] "i"(_SFR_MEM_ADDR(MULTI_Z_STEP_PORT)), [maskx] "i"(&planner_irq.step_mask[0]), [masky] "i"(&planner_irq.step_mask[1]),
          [maskz] "i"(&planner_irq.step_mask[2]), [intick] "i"(&planner_irq.in_tick), [locks] "i"(&planner_irq.locks),
          [deferred] "i"(&planner_irq.deferred));
}
