/* MultiStepEngineTimer.cpp - the step interrupts' rarer path in C (slow steps and a slow command's
 * start, wraps to count, the end, an underrun) and the Timer1 side of starting, stopping and
 * watching an axis; see MultiStepEngine.h. The common path, new fast commands and late edges
 * included, is MultiStepEngineIsr.inc. Not in timed-loop mode (MULTI_TIMED_LOOP: MultiStepEngineLoop.cpp). */
#include "MultiStepEngineInternal.h"

#if !MULTI_TIMED_LOOP

#include <util/atomic.h>

namespace mse {
inline void write_ocr(uint8_t axis, uint16_t v)
{
    if (axis == 0)
        OCR1A = v;
    else if (axis == 1)
        OCR1B = v;
    else
        OCR1C = v;
}

inline uint16_t read_ocr(uint8_t axis)
{
    return axis == 0 ? OCR1A : axis == 1 ? OCR1B : OCR1C;
}

inline uint8_t ocf_bit(uint8_t axis)
{
    return axis == 0 ? _BV(OCF1A) : axis == 1 ? _BV(OCF1B) : _BV(OCF1C);
}

inline uint8_t ocie_bit(uint8_t axis)
{
    return axis == 0 ? _BV(OCIE1A) : axis == 1 ? _BV(OCIE1B) : _BV(OCIE1C);
}

/* Arms the next step of the current command by the executor's rule, counting a slow interval's wraps; a first
 * match already missed counts as passed, a step already due fires 2 us later; sets the mode bits SLOW
 * and WAITING. `prev` (the edge the interval starts from) may lie ahead of TCNT1 at a move's start:
 * nothing has elapsed then, and a match before prev is one more to let pass. A fast command's step
 * is then looked ahead (ahead form, MultiStepEngine.h): the step after it computed into acc (the next
 * slot taken if the command is used up), which the asm path arms at this edge's match; when that step
 * cannot be computed so (no next slot laid out yet, a slow one, a turn) the SLOW bit sends the match
 * to this C path (PEND). The arithmetic runs with interrupts on, the arming with them off. In a step
 * interrupt (in_isr) the axis's own compare interrupt is masked at the arming, as the asm path does,
 * and interrupts come back on after it: its next match, armed here, may come at once (a late edge) and
 * waits for the end of this interrupt, while the other axes' edges wait only for the arming. At a
 * start (start_axis) they stay off from the arming on (cli, not restored). */
/* axes whose own compare interrupt arm_step masked in their C path: unmasked at its end, with
 * interrupts off, just before the reti (multi_cold_x/y/z) */
static volatile uint8_t s_own_masked;

__attribute__((always_inline)) inline void arm_step(uint8_t axis, AxisState &s, bool in_isr)
{
    uint16_t prev = (uint16_t)(s.acc >> 16), elapsed, edge;
    uint32_t interval, first;
    int16_t since;
    uint8_t set = 0, clear = 0;
    bool slow = (s.flags & _BV(AXIS_SLOT_SLOW)) != 0, pend = false;
    if (s.flags & _BV(AXIS_SLOT_WIDE)) {
        interval = s.rate;
        s.acc += s.rate << 16;
    } else {
        uint32_t acc0 = s.acc;
        s.rate += (uint32_t)s.add; /* the rate was laid out less add */
        s.acc += s.rate;
        interval = (uint16_t)((s.acc >> 16) - (acc0 >> 16));
        if (interval == 0)
            interval = 0x10000UL;
    }
    edge = (uint16_t)(s.acc >> 16);
    s.wraps = (uint16_t)((interval - 1U) >> 16);
    first = ((interval - 1U) & 0xFFFFUL) + 1U;
    if (!slow) {
        /* ahead form: the step after this one */
        if (s.left != 0) {
            s.left = s.left - 1U;
        } else {
            AxisSlot *next = s.cur->other;
            if (next->ready && !(next->flags & (_BV(AXIS_SLOT_SLOW) | _BV(AXIS_SLOT_TURN))))
                load_slot(s, *next);
            else
                pend = true;
        }
        if (!pend) {
            s.rate += (uint32_t)s.add;
            s.acc += s.rate;
        }
    }
    cli();
    if (in_isr) {
        /* its own match (maybe due at once: a late edge) waits for the end of this interrupt, so
         * the rest of the C path can run with interrupts on: another axis's edge then waits only
         * for this arming, not for the whole path back to the reti (with them off to the reti, a Z
         * C path nested in X's interrupt held an X edge 279 cycles: the halt check) */
        TIMSK1 &= (uint8_t)~ocie_bit(axis);
        s_own_masked = s_own_masked | (uint8_t)_BV(axis);
    }
    write_ocr(axis, edge);
    if (!in_isr) {
        /* a start: a flag still set is a match of the old compare value (after an underrun the axis's
         * interrupt is masked, and its last edge comes round again a wrap later). Cleared here, right
         * after the new value is written, not after the check below: with it set, the check took a
         * first edge already passed for one that had matched, start_axis then cleared the flag, and
         * the edge waited a whole wrap (then the re-arming of catch_missed_match; found on a smooth
         * move at 50,000 steps/s, check_smooth_stall) */
        TIFR1 = ocf_bit(axis);
        /* and the axis's interrupt unmasked before the late test below: a first edge already passed
         * is armed again a few ticks ahead, and libsimavr drops a match that comes while its
         * interrupt is masked (the chip keeps the flag): with the unmask after it, at start_axis's
         * end, a start delayed by other interrupts lost that match, the edge waited for
         * catch_missed_match (17,028 cycles: run_fuzz --kinds multi seed 7, a restart after an
         * underrun) and the queued edges, all behind, followed 131 cycles apart */
        TIMSK1 |= ocie_bit(axis);
    }
    since = (int16_t)(TCNT1 - prev);
    if (since < 0) {
        /* prev (a move's start) is still ahead, by d ticks: the compare value comes round once before
         * prev when first + d reaches past a wrap; that match is not this step's, let it pass too */
        if (first > 0x10000UL - (uint16_t)-since)
            s.wraps = s.wraps + 1U;
    } else {
        elapsed = (uint16_t)since;
        if (elapsed >= first && !(TIFR1 & ocf_bit(axis))) {
            if (s.wraps != 0) {
                s.wraps = s.wraps - 1U;
            } else {
                write_ocr(axis, TCNT1 + s.late_ticks);
                s.late = s.late + 1U;
            }
        }
    }
    if (s.wraps != 0)
        set |= _BV(AXIS_MODE_WAITING);
    else
        clear |= _BV(AXIS_MODE_WAITING);
    if (slow || pend)
        set |= _BV(AXIS_MODE_SLOW);
    else
        clear |= _BV(AXIS_MODE_SLOW);
    change_mode(s, set, clear);
    if (in_isr) {
        /* the window: a pending edge of another axis is taken after the instruction that follows
         * sei on the chip, after the second one in libsimavr (docs/emulator.md), so the window is
         * two nops (with one the emulator never took an edge here, and one waited 276 cycles for the
         * rest of this path: the halt check). Another interrupt may take the window (the serial
         * one) and an edge match while it runs: after its reti one instruction runs on the chip (two
         * in libsimavr) before the edge's interrupt, and a cli there held the edge for the rest of
         * this path (a Y edge 287 cycles after its plan, `run_fuzz.py --seed 6 --kinds multi`; with
         * a third nop, 268 cycles at seed 7). So with interrupts off again the window is opened
         * once more while another running axis's match is pending (its flag set, its interrupt
         * enabled: this axis's own is masked here): the edge is taken at once, whatever came first */
        do {
            sei();
            __asm__ __volatile__("nop\n\tnop" ::: "memory");
            cli();
        } while (TIFR1 & TIMSK1); /* (Timer1's other interrupts are never enabled; one would be taken too) */
    }
}

/* the C path of one axis: a wrap to count, a slow command's step, or a step the asm path left to it
 * (PEND: the command used up without a ready fast slot that keeps the direction). Called with
 * interrupts on (its STEP raised by the asm path): other axes' edges do not wait for it; shared
 * registers (TIMSK1, GPIOR0, a port's read-modify-write) are written with them off. From the arming
 * of the next edge (arm_step) its own compare interrupt is masked until multi_cold_x/y/z unmask it just
 * before the reti; its match cannot come before the arming: OCR1x still holds the edge that has just
 * matched (the state is in normal form here). */
__attribute__((always_inline)) inline void cold_path(uint8_t axis)
{
    AxisState &s = state(axis);
    AxisSlot *cur = s.cur, *next;
    if (s.mode & _BV(AXIS_MODE_DEFER)) {
        /* the C path of the step made at an earlier match, put off (MultiStepEngineIsr.inc): now */
        ATOMIC_BLOCK(ATOMIC_FORCEON)
        {
            change_mode(s, 0, AXIS_MODE_DEFER_ALL);
        }
    }
    if (!s.running) {
        /* a match after a halt (none should come): nothing to step */
        cli();
        TIMSK1 &= (uint8_t)~ocie_bit(axis);
        step_low(axis);
        return;
    }
    if (s.mode & _BV(AXIS_MODE_WAITING)) {
        cli();
        s.wraps = s.wraps - 1U;
        if (s.wraps == 0)
            change_mode(s, 0, _BV(AXIS_MODE_WAITING));
        return;
    }
    /* STEP is high: this match made a step */
    if (axis == 0 && (GPIOR0 & _BV(MULTI_G_LED_X)))
        MULTI_LED_PIN = _BV(MULTI_LED_BIT); /* the LED mirror (the asm path mirrors its own steps) */
    if (s.left != 0) {
        s.left = s.left - 1U;
    } else {
        next = cur->other;
        if (!next->ready) {
            ATOMIC_BLOCK(ATOMIC_FORCEON)
            {
                TIMSK1 &= (uint8_t)~ocie_bit(axis);
            }
            /* the books with interrupts on (this axis's interrupt is masked now; the planner, which reads
             * them, runs once this returns); only the running flag, the shared registers and STEP low
             * with interrupts off (all of it so held a Z edge 277 cycles after its match, the bound
             * being 260: make bench of 2026-12-07, independent x+y+z at 15,000 steps/s with a `?`) */
            stop_books(s, *cur);
            __builtin_avr_delay_cycles(32); /* the STEP pulse: >= 2 us */
            cli();
            s.running = 0;
            sync_g0(s);
            step_low(axis);
            return;
        }
        load_slot(s, *next);
        if (next->flags & _BV(AXIS_SLOT_TURN)) {
            /* DIR while STEP is still high (>= 1.5 us after the rising edge of the old direction's
             * last step: the interrupt's entry and this call took longer), before the arming:
             * interrupts are off only for the port write, not after the arming with the rest of the
             * stretch (a Z turn there held an X edge 267 cycles, `make fuzz`; the bound is 260) */
            ATOMIC_BLOCK(ATOMIC_FORCEON)
            {
                set_dir(axis, next->flags & _BV(AXIS_SLOT_FORWARD));
            }
        }
    }
    arm_step(axis, s, true); /* one copy for both (it returns with interrupts off: its window) */
    step_low(axis);
}

/* takes the first laid-out slot and arms its first step from t = base. Called from loop() with
 * interrupts on (this axis's interrupt is off): the other axes keep stepping while it plans its
 * arithmetic; the arming and the shared registers (a port's read-modify-write, TIFR1, TIMSK1,
 * GPIOR0) run with interrupts off. */
void start_axis(uint8_t axis, uint32_t base)
{
    AxisState &s = state(axis);
    AxisSlot *t = s.cur->other;
    uint8_t sreg;
    if (!t->ready)
        return;
    load_slot(s, *t);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        set_dir(axis, t->flags & _BV(AXIS_SLOT_FORWARD)); /* DIR is set here, before the first step */
    }
    s.acc = base;
    s.wraps = 0;
    /* running before the arming, so that arm_step's change_mode syncs it too: the stretch with
     * interrupts off from the arming to `SREG = sreg` below is what other axes' edges wait for (242 cycles with a
     * second sync_g0: a Z edge 274 cycles after its match, the halt check; about 180 now, as long as
     * a C path's own arming); the axis's interrupt stays off until arm_step unmasks it */
    s.running = 1;
    sreg = SREG;
    arm_step(axis, s, false); /* interrupts off from its arming on; clears the axis's stale match flag and
                                 unmasks its interrupt */
    SREG = sreg;
    s_feed[axis].held = 0;
    s_feed[axis].started = 1;
}

/* t = 0 a little ahead of now, half a tick into it (edges at round(F t)) */
uint32_t base_ahead(uint16_t ticks)
{
    uint16_t now;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        now = TCNT1; /* through TEMP, which the step interrupts use too */
    }
    return ((uint32_t)(uint16_t)(now + ticks) << 16) | 0x8000UL;
}

/* A compare match that never came (libsimavr dropped some, after a timer wrap, until the harness
 * modelled the chip there: tools/emu/emu_timer.c; kept as a safety net): the armed edge lies well
 * in the past, no match is pending and the interrupt has not moved on. Fire it now and count it as
 * late, instead of waiting a whole wrap. A first look with interrupts on (a torn read only costs the careful look below), so the
 * check, made on every service() call of every axis, does not delay step edges. */
/* The armed edge lies 65 to 16384 ticks in the past (16-bit times: 4 us to 1 ms at 16 MHz, 32 us to
 * 8 ms at 2 MHz): a match missed not long ago. Not
 * "any amount up to half a wrap": a move's first edge may be armed more than 32768 ticks ahead (a
 * coordinated start is 256 us ahead, 4096 or 512 ticks, plus a first interval of up to 32767), which in 16 bits
 * looks like the past; taking it for a missed match fired the first step at once, a whole interval
 * early (found by `make fuzz`: x stepped twice within 201 cycles at a coordinated start). */
inline bool missed_by(uint16_t now, uint16_t edge)
{
    return (uint16_t)(now - edge) - 65U < 16320U;
}

/* Arms OCR1x margin ticks after TCNT1 and makes sure that this match still lies ahead once the value
 * is written (interrupts off). The time from reading TCNT1 to the write can exceed 2 us at 16 MHz (48
 * cycles seen for a run-time axis), and a compare value written behind the counter matches only a
 * whole wrap later; the next look then found it missed again and re-armed it behind again, every
 * time: the axis stood still for good, still "moving" (found on a smooth move at 50,000 steps/s).
 * So the margin doubles until the value is ahead (or the match has come meanwhile). */
static void rearm_ahead(uint8_t axis, uint8_t margin)
{
    uint16_t m = margin;
    for (;;) {
        uint16_t v = (uint16_t)(TCNT1 + m);
        write_ocr(axis, v);
        if ((TIFR1 & ocf_bit(axis)) || (uint16_t)(v - TCNT1) - 1U < 0x8000U)
            return;
        m = (uint16_t)(m * 2U);
    }
}

void catch_missed_match(uint8_t axis)
{
    AxisState &s = state(axis);
    if (!s.running || (s.mode & _BV(AXIS_MODE_WAITING)) || (s.flags & _BV(AXIS_SLOT_SLOW)) ||
        (TIFR1 & ocf_bit(axis)) || !missed_by(TCNT1, read_ocr(axis)))
        return;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (s.running && !(s.mode & _BV(AXIS_MODE_WAITING)) && !(s.flags & _BV(AXIS_SLOT_SLOW)) &&
            !(TIFR1 & ocf_bit(axis))) {
            /* OCR1x: the edge armed (in ahead form acc is the one after it); a re-arming by an earlier
             * look lies ahead */
            if (missed_by(TCNT1, read_ocr(axis))) {
                rearm_ahead(axis, s.late_ticks);
                s.late = s.late + 1U;
            }
        }
    }
}

/* MultiStepEngine::in_step_interrupt's window: an armed edge at most this far behind TCNT1 is a
 * match whose interrupt may still be in its C path */
#define MULTI_ISR_WINDOW 4000U

void hw_begin(uint32_t tick_hz)
{
    /* 2 MHz (prescaler 8: the lab ramps' ticks) or 16 MHz (prescaler 1) */
    s_tick_hz = tick_hz == 2000000UL ? 2000000UL : 16000000UL;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        /* the Arduino core leaves Timer1 in 8-bit PWM mode for analogWrite(): take it over */
        TIMSK1 = 0;
        TCCR1A = 0;
        TCCR1C = 0;
        TCCR1B = s_tick_hz == 16000000UL ? _BV(CS10) : _BV(CS11); /* normal mode, prescaler 1 or 8 */
        TIFR1 = _BV(OCF1A) | _BV(OCF1B) | _BV(OCF1C) | _BV(TOV1);
    }
}

void hw_stop(uint8_t axis)
{
    TIMSK1 &= (uint8_t)~ocie_bit(axis);
}

bool may_plan(uint8_t)
{
    return true;
}
} // namespace mse

using namespace mse;

bool MultiStepEngine::in_step_interrupt()
{
    uint8_t on, flags;
    uint16_t now;
    /* one snapshot, with interrupts off: TCNT1's read goes through Timer1's TEMP byte, which a step
     * interrupt nesting between its two halves would overwrite (its OCR1x write). The rest may run
     * with interrupts on: an interrupt that nests from here on ends before this goes on, and one that
     * this has interrupted stands still. */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        on = TIMSK1;
        flags = TIFR1;
        now = TCNT1;
    }
    for (uint8_t a = 0; a < MULTI_AXES; a++) {
        const AxisState *s = s_state[a];
        if (!s || !s->running)
            continue;
        if (!(on & ocie_bit(a)) || (s->mode & _BV(AXIS_MODE_DEFER)))
            return true; /* its asm path (its own match masked until the end), or its C path put off */
        if (!(flags & ocf_bit(a)) && (uint16_t)(now - read_ocr(a)) < MULTI_ISR_WINDOW)
            return true; /* its C path, before the arming */
    }
    return false;
}

/* The C path of each axis, called by its step interrupt (MultiStepEngineIsr.inc) with interrupts on;
 * returns with them off. */
extern "C" void multi_cold_x(void);
extern "C" void multi_cold_y(void);
extern "C" void multi_cold_z(void);
/* the C path, then the axis's own compare interrupt unmasked if its arming masked it (interrupts off:
 * cold_path returns so, whatever its path; one read of s_own_masked) */
__attribute__((always_inline)) inline void cold_exit(uint8_t axis)
{
    cold_path(axis);
    uint8_t m = s_own_masked;
    if (m & _BV(axis)) {
        s_own_masked = m & (uint8_t)~_BV(axis);
        TIMSK1 |= ocie_bit(axis);
    }
}
void multi_cold_x(void)
{
    cold_exit(0);
}
void multi_cold_y(void)
{
    cold_exit(1);
}
void multi_cold_z(void)
{
    cold_exit(2);
}


#endif
