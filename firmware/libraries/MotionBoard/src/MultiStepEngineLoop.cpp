/* MultiStepEngineLoop.cpp - timed-loop mode (MULTI_TIMED_LOOP, from STEPPER_TIMED_LOOP = 1: the lab's
 * original structure): no step interrupt; loop() calls MultiStepEngine::poll(), which makes X's steps
 * that are due by micros(), F = 1 MHz. The queues, the planner's side and every public call are
 * MultiStepEngine.cpp's, as with the interrupts (MultiStepEngineTimer.cpp, MultiStepEngineIsr.inc):
 * only the executor differs. Each edge's deadline lies on an absolute timeline (the deadline of the
 * last one plus the interval the executor's arithmetic gives: no drift), so a step is late by 0 to
 * 4 us (micros() counts in 4 us) plus the longest pass of loop(): a mode for comparison, not for
 * real motors. Only X steps (the one-axis sketches' axis); DIR, the direction hook, the LED mirror,
 * the end of a move and an underrun as with the interrupts. */
#include "MultiStepEngineInternal.h"

#if MULTI_TIMED_LOOP

#include <util/delay.h>

namespace {
uint32_t s_deadline_us; /* when X's next step is due (micros()) */

/* The next edge's interval by the executor's rule (step_exec_next: the rate laid out less add,
 * WIDE in whole ticks), its deadline moved on by it. */
void advance(AxisState &s)
{
    if (s.flags & _BV(AXIS_SLOT_WIDE)) {
        s.acc += s.rate << 16;
        s_deadline_us += s.rate;
    } else {
        uint32_t acc0 = s.acc;
        s.rate += (uint32_t)s.add;
        s.acc += s.rate;
        s_deadline_us += (uint16_t)((s.acc >> 16) - (acc0 >> 16));
    }
}
} // namespace

namespace mse {
void hw_begin(uint32_t)
{
    s_tick_hz = 1000000UL; /* micros() */
}

void hw_stop(uint8_t)
{
}

void start_axis(uint8_t axis, uint32_t)
{
    AxisState &s = state(axis);
    AxisSlot *t = s.cur->other;
    if (axis != 0 || !t->ready)
        return; /* X only */
    load_slot(s, *t);
    set_dir(axis, t->flags & _BV(AXIS_SLOT_FORWARD)); /* DIR is set here, before the first step */
    s.acc = 0x8000UL; /* half a tick in: edges at round(F t) */
    s.wraps = 0;
    s_deadline_us = micros();
    advance(s);
    s.running = 1;
    s_feed[axis].held = 0;
    s_feed[axis].started = 1;
}

uint32_t base_ahead(uint16_t)
{
    return 0;
}

void catch_missed_match(uint8_t)
{
}

/* loop() makes the steps: plan only in the gaps, never across a deadline (two commands queued at
 * least, so that the next step is always laid out) */
bool may_plan(uint8_t axis)
{
    MultiStepEngine::poll();
    return axis != 0 || !state(0).running || s_feed[0].ready < 2U ||
           (int32_t)(s_deadline_us - micros()) >= 400;
}
} // namespace mse

using namespace mse;

void MultiStepEngine::poll()
{
    AxisSlot *next;
    bool turn = false;
    if (!s_state[0])
        return; /* X not begun */
    AxisState &s = state(0);
    if (!s.running || (int32_t)(micros() - s_deadline_us) < 0)
        return;
    MULTI_X_STEP_PORT |= _BV(MULTI_X_STEP_BIT); /* sbi: I/O space */
    if (GPIOR0 & _BV(MULTI_G_LED_X))
        MULTI_LED_PIN = _BV(MULTI_LED_BIT); /* the LED mirror: toggles */
    if (s.left != 0) {
        s.left = s.left - 1U;
    } else {
        next = s.cur->other;
        if (!next->ready) {
            /* nothing laid out: the move's end, or an underrun */
            stop_after(s, *s.cur);
            _delay_us(2); /* the STEP pulse: >= 2 us */
            step_low(0);
            return;
        }
        load_slot(s, *next);
        turn = (s.flags & _BV(AXIS_SLOT_TURN)) != 0;
    }
    advance(s);
    _delay_us(2);
    step_low(0);
    if (turn)
        set_dir(0, s.flags & _BV(AXIS_SLOT_FORWARD)); /* after the old direction's last step */
}

#endif
