/* StepperDriver.cpp - Timer1 compare interrupt (or micros() loop) stepping one axis; see StepperDriver.h
 * and StepperPins.h for the timing scheme.
 *
 * Timeline of one step in timer mode (ticks of 0.5 us):
 *   edge - STEPPER_EARLY_TICKS   compare match: the interrupt starts (after any interrupt already
 *                                running) and spins until TCNT1 == edge
 *   edge                         STEP high (and the LED toggles); position += dir
 *   edge + a few                 compare armed for the next edge, computed one step ago
 *   edge + STEPPER_PULSE_TICKS   STEP low
 *   then                         ramp_next(): the interval after the next one (float for Leib)
 * An interval longer than 65535 ticks is counted out in chunks of 32768 ticks by short extra
 * compare interrupts before the final early one; all chunks end on the same absolute timeline.
 */
#include "StepperDriver.h"

#include <Arduino.h>
#include <util/atomic.h>
#include <util/delay.h>

/* The shortest interval the driver will arm: the early wake-up plus the few ticks between an edge
 * and the write of the next compare. The sketches' speed limits keep every planned interval far
 * above it (they must: the ramp update has to finish before the next edge), so it never acts. */
#define STEPPER_MIN_ARM_TICKS (STEPPER_EARLY_TICKS + 16U)

namespace {
ramp_t s_ramp;             /* the move; owned by the interrupt while s_moving */
volatile uint8_t s_moving;
volatile uint8_t s_done;
volatile int32_t s_position;
volatile uint8_t s_phase;  /* ramp_phase_t of the last step made */
int8_t s_dir;
/* the armed step */
uint8_t s_armed_phase;
#if STEPPER_TIMED_LOOP
uint32_t s_last_us;        /* deadline of the previous step, micros() */
uint32_t s_armed_ticks;    /* interval of the armed step, us */
#else
uint16_t s_edge;           /* TCNT1 at its edge */
uint32_t s_wait;           /* ticks still to count before the final (early) compare match */
#endif
/* the step after it, computed one step ahead; 0 ticks: the armed step is the last */
uint32_t s_following_ticks;
uint8_t s_following_phase;

inline void step_high()
{
    STEPPER_STEP_PORT |= _BV(STEPPER_STEP_BIT);
#if STEPPER_LED_MIRROR
    STEPPER_LED_PIN = _BV(STEPPER_LED_BIT);
#endif
}

inline void step_low()
{
    STEPPER_STEP_PORT &= (uint8_t)~_BV(STEPPER_STEP_BIT);
}

void compute_following()
{
    ramp_step_t st;
    if (ramp_next(&s_ramp, &st)) {
        s_following_ticks = st.whole_ticks != 0 ? st.whole_ticks : 1;
        s_following_phase = (uint8_t)st.phase;
    } else {
        s_following_ticks = 0;
    }
}

#if !STEPPER_TIMED_LOOP
/* Schedules the edge `interval` ticks after `edge` (both on TCNT1's modulo-2^16 timeline). */
inline void arm(uint16_t edge, uint32_t interval)
{
    uint32_t early;
    if (interval < STEPPER_MIN_ARM_TICKS)
        interval = STEPPER_MIN_ARM_TICKS;
    early = interval - STEPPER_EARLY_TICKS;
    s_edge = edge + (uint16_t)interval;
    if (early > 0xFFFFUL) {
        OCR1A = edge + 0x8000U;
        s_wait = early - 0x8000UL;
    } else {
        OCR1A = edge + (uint16_t)early;
        s_wait = 0;
    }
}
#endif
} // namespace

#if !STEPPER_TIMED_LOOP
void StepperDriver::on_compare_match()
{
    if (s_wait != 0) {
        /* a long interval: count out another chunk (every chunk is >= 32768 ticks) */
        uint16_t chunk = s_wait > 0xFFFFUL ? 0x8000U : (uint16_t)s_wait;
        OCR1A += chunk;
        s_wait -= chunk;
        return;
    }
    const uint16_t edge = s_edge;
    if ((int16_t)(TCNT1 - edge) < 0) {
        /* at most STEPPER_EARLY_TICKS (< 128) before the edge: the low byte alone tells, and a
         * one-byte read makes the tightest loop (5-6 cycles), so the edge lands within 6 cycles
         * of its tick (a late start, which only an overload could cause, skips the wait) */
        const uint8_t edge_lo = (uint8_t)edge;
        while ((int8_t)(TCNT1L - edge_lo) < 0) {
        }
    }
    step_high();
#if STEPPER_TRACE
    STEPPER_TRACE_PORT |= _BV(STEPPER_TRACE_BIT);
#endif
    s_position += s_dir;
    s_phase = s_armed_phase;
    if (s_following_ticks != 0) {
        arm(edge, s_following_ticks);
        s_armed_phase = s_following_phase;
    } else {
        TIMSK1 &= (uint8_t)~_BV(OCIE1A);
        s_moving = 0;
        s_phase = RAMP_IDLE;
        s_done = 1;
    }
    while ((uint16_t)(TCNT1 - edge) < STEPPER_PULSE_TICKS) {
    }
    step_low();
    if (s_moving)
        compute_following();
#if STEPPER_TRACE
    STEPPER_TRACE_PORT &= (uint8_t)~_BV(STEPPER_TRACE_BIT);
#endif
}
#endif

void StepperDriver::begin()
{
    STEPPER_STEP_DDR |= _BV(STEPPER_STEP_BIT);
    step_low();
    STEPPER_DIR_DDR |= _BV(STEPPER_DIR_BIT);
    STEPPER_DIR_PORT |= _BV(STEPPER_DIR_BIT);
    STEPPER_ENABLE_DDR |= _BV(STEPPER_ENABLE_BIT);
    STEPPER_ENABLE_PORT &= (uint8_t)~_BV(STEPPER_ENABLE_BIT);
#if STEPPER_LED_MIRROR
    STEPPER_LED_DDR |= _BV(STEPPER_LED_BIT);
#endif
#if STEPPER_TRACE
    STEPPER_TRACE_DDR |= _BV(STEPPER_TRACE_BIT);
#endif
#if !STEPPER_TIMED_LOOP
    /* The Arduino core leaves Timer1 in 8-bit PWM mode for analogWrite(): take it over. */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        TIMSK1 = 0;
        TCCR1A = 0;
        TCCR1C = 0;
        TCCR1B = _BV(CS11); /* normal mode, prescaler 8: 2 MHz */
        TIFR1 = _BV(OCF1A) | _BV(OCF1B) | _BV(OCF1C) | _BV(TOV1);
    }
#endif
}

bool StepperDriver::start(const ramp_t &plan)
{
    ramp_step_t first, second;
    uint8_t more;
    if (s_moving)
        return false;
    s_ramp = plan;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        s_position = plan.from;
    }
    if (!ramp_next(&s_ramp, &first)) {
        s_done = 1; /* zero-length move */
        return true;
    }
    more = ramp_next(&s_ramp, &second);
    s_dir = plan.dir;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (plan.dir > 0)
            STEPPER_DIR_PORT |= _BV(STEPPER_DIR_BIT);
        else
            STEPPER_DIR_PORT &= (uint8_t)~_BV(STEPPER_DIR_BIT);
        s_following_ticks = more ? (second.whole_ticks != 0 ? second.whole_ticks : 1) : 0;
        s_following_phase = (uint8_t)second.phase;
        s_armed_phase = (uint8_t)first.phase;
        s_phase = (uint8_t)first.phase;
        s_done = 0;
        s_moving = 1;
#if STEPPER_TIMED_LOOP
        s_armed_ticks = first.whole_ticks;
        s_last_us = micros();
#else
        arm(TCNT1, first.whole_ticks);
        TIFR1 = _BV(OCF1A);
        TIMSK1 |= _BV(OCIE1A);
#endif
    }
    return true;
}

void StepperDriver::poll()
{
#if STEPPER_TIMED_LOOP
    if (!s_moving || (uint32_t)(micros() - s_last_us) < s_armed_ticks)
        return;
    step_high();
    s_last_us += s_armed_ticks; /* the deadline, not the time we noticed it: no drift */
    s_position += s_dir;
    s_phase = s_armed_phase;
    if (s_following_ticks != 0) {
        s_armed_ticks = s_following_ticks;
        s_armed_phase = s_following_phase;
    } else {
        s_moving = 0;
        s_phase = RAMP_IDLE;
        s_done = 1;
    }
    _delay_us(2);
    step_low();
    if (s_moving)
        compute_following();
#endif
}

bool StepperDriver::busy()
{
    return s_moving != 0;
}

int32_t StepperDriver::position()
{
    int32_t p;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        p = s_position;
    }
    return p;
}

ramp_phase_t StepperDriver::phase()
{
    uint8_t ph, moving;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        ph = s_phase;
        moving = s_moving;
    }
    return moving ? (ramp_phase_t)ph : RAMP_IDLE;
}

bool StepperDriver::take_done(int32_t &position)
{
    bool done = false;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (s_done) {
            s_done = 0;
            position = s_position;
            done = true;
        }
    }
    return done;
}
