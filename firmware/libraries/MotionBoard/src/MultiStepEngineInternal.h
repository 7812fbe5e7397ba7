/* MultiStepEngineInternal.h - what the step engine's files share (not for sketches): loop()'s side of
 * each axis's queue, the pin and mode helpers, and the few functions each variant of the executor
 * defines: the step interrupts (MultiStepEngineTimer.cpp) or, in timed-loop mode (MULTI_TIMED_LOOP),
 * loop()'s polling of micros() (MultiStepEngineLoop.cpp). MultiStepEngine.cpp, the queues and the
 * public calls, is the same for both. */
#ifndef MULTI_STEP_ENGINE_INTERNAL_H
#define MULTI_STEP_ENGINE_INTERNAL_H

#include "MultiStepEngine.h"

/* bit axis + 1 (OCIE1A/B/C's place in TIMSK1): the axis is running (sync_g0); read by the step
 * interrupts' C path entry (MultiStepEngineIsr.inc: another running axis's own match masked) */
extern "C" volatile uint8_t multi_running_ocie;
/* bit axis: the axis's C path is running (MultiStepEngineIsr.inc) */
extern "C" volatile uint8_t multi_in_cold;

namespace mse {
/* loop()'s side of one axis's queue */
struct AxisFeed {
    uint16_t *duration; /* each slot's command's ticks / 16, at most 0xFFFF (MultiStepEngine.cpp duration_ticks) */
    uint8_t nslots;     /* the ring's slots (attach) */
    uint32_t queued_ticks;
    uint8_t head;  /* the next slot loop() lays out */
    uint8_t seen;  /* the oldest slot still counted in queued_ticks */
    uint8_t ready; /* slots laid out and counted */
    int32_t next_p_start;
    uint8_t last_forward;
    uint8_t open; /* a move is being fed (accepted, not yet reported done) */
    uint8_t held; /* its start waits for start_together */
    uint8_t started; /* the move has stepped (after an underrun it resumes at once) */
    uint8_t keep;    /* slots the planner leaves to the commands stepped last (open_move) */
};
extern AxisFeed s_feed[MULTI_AXES];
extern AxisState *s_state[MULTI_AXES]; /* the axes begun (attach), NULL for the others */
extern uint8_t s_axes;                 /* their mask (bit i: axis i) */
extern uint32_t s_lead_ticks;
extern uint32_t s_tick_hz; /* begin(): 16 MHz or 2 MHz (timed-loop mode: 1 MHz) */
extern MultiStepEngine::DirectionHook s_dir_hook[MULTI_AXES]; /* set_direction_hook: the sketch sets DIR */

/* the most slots the planner fills: the ring's, less one (the interrupt's own) and those it keeps */
inline uint8_t ring_cap(const AxisFeed &f)
{
    return (uint8_t)(f.nslots - 1U - f.keep);
}

inline AxisState &state(uint8_t axis)
{
    return *s_state[axis];
}

/* Pin writes: X and Y are in PORTF (I/O space: one instruction each); Z's PORTL is
 * read-modify-written, so only with interrupts off (every caller here runs with them off). */
inline void write_dir(uint8_t axis, bool forward)
{
    if (axis == 0) {
        if (forward)
            MULTI_X_DIR_PORT |= _BV(MULTI_X_DIR_BIT);
        else
            MULTI_X_DIR_PORT &= (uint8_t)~_BV(MULTI_X_DIR_BIT);
    } else if (axis == 1) {
        if (forward)
            MULTI_Y_DIR_PORT |= _BV(MULTI_Y_DIR_BIT);
        else
            MULTI_Y_DIR_PORT &= (uint8_t)~_BV(MULTI_Y_DIR_BIT);
    } else {
        if (forward)
            MULTI_Z_DIR_PORT |= _BV(MULTI_Z_DIR_BIT);
        else
            MULTI_Z_DIR_PORT &= (uint8_t)~_BV(MULTI_Z_DIR_BIT);
    }
}

/* DIR for the steps that follow: the sketch's hook if it set one, else the pin */
inline void set_dir(uint8_t axis, bool forward)
{
    if (s_dir_hook[axis])
        s_dir_hook[axis](forward);
    else
        write_dir(axis, forward);
}

inline bool dir_level(uint8_t axis)
{
    if (axis == 0)
        return (MULTI_X_DIR_PORT & _BV(MULTI_X_DIR_BIT)) != 0;
    if (axis == 1)
        return (MULTI_Y_DIR_PORT & _BV(MULTI_Y_DIR_BIT)) != 0;
    return (MULTI_Z_DIR_PORT & _BV(MULTI_Z_DIR_BIT)) != 0;
}

/* STEP low: the interrupt's pins (its axis's and its followers'); interrupts are off */
inline void step_low(uint8_t axis)
{
    AxisState &s = state(axis);
    PORTF &= (uint8_t)~s.mask_f;
    if (s.mask_l)
        PORTL &= (uint8_t)~s.mask_l;
}

inline void own_masks(uint8_t axis)
{
    AxisState &s = state(axis);
    s.mask_f = axis == 0 ? _BV(MULTI_X_STEP_BIT) : axis == 1 ? _BV(MULTI_Y_STEP_BIT) : 0;
    s.mask_l = axis == 2 ? _BV(MULTI_Z_STEP_BIT) : 0;
}

inline uint8_t next_slot(const AxisFeed &f, uint8_t i)
{
    return (uint8_t)(i + 1U == f.nslots ? 0U : i + 1U);
}

inline uint8_t prev_slot(const AxisFeed &f, uint8_t i)
{
    return (uint8_t)(i == 0U ? f.nslots - 1U : i - 1U);
}

/* the interrupt's current slot, read twice until both agree (it changes at most once per command) */
inline AxisSlot *cur_slot(AxisState &s)
{
    AxisSlot *a, *b;
    do {
        a = s.cur;
        b = s.cur;
    } while (a != b);
    return a;
}

/* slot p's index in the ring: the byte distance over 18, as a multiplication (18 = 2 x 9, and
 * 0x8E39 is 9's inverse modulo 2^16: exact for a multiple of 18), not the division pointer arithmetic
 * compiles to (~200 cycles; loop() asks several times a pass, and in timed-loop mode each pass
 * delays a step) */
static_assert(sizeof(AxisSlot) == 18, "slot_index divides by 18");
inline uint8_t slot_index(const AxisState &s, const AxisSlot *p)
{
    uint16_t d = (uint16_t)((const uint8_t *)p - (const uint8_t *)s.slot);
    return (uint8_t)((uint16_t)(d >> 1) * 0x8E39U);
}

inline uint8_t cur_index(AxisState &s)
{
    return slot_index(s, cur_slot(s));
}

/* The GPIOR0 copies of an axis's mode (MultiAxisPins.h), after a change of its mode or of its running
 * (interrupts off): ANY = mode not zero, or not running (a match then takes the C path, which does
 * nothing); OWNOFF = OWN_OFF, or not running. */
inline void sync_g0(AxisState &s)
{
    uint8_t any = s.g_any, off = s.g_off, bits;
    bits = (uint8_t)(((s.mode || !s.running) ? any : 0) |
                     (((s.mode & _BV(AXIS_MODE_OWN_OFF)) || !s.running) ? off : 0));
    GPIOR0 = (uint8_t)((GPIOR0 & (uint8_t)~(any | off)) | bits);
    /* the running axes' compare interrupt bits (any is bit `axis`, OCIE1A/B/C bit axis + 1) */
    multi_running_ocie = (uint8_t)((multi_running_ocie & (uint8_t)~(any << 1)) | (s.running ? (any << 1) : 0));
}

/* Sets and clears mode bits (interrupts off), keeping OWN_OFF = WAITING, MASKED or DEFER. */
inline void change_mode(AxisState &s, uint8_t set, uint8_t clear)
{
    uint8_t m = (uint8_t)((s.mode | set) & (uint8_t)~clear) & (uint8_t)~_BV(AXIS_MODE_OWN_OFF);
    if (m & (_BV(AXIS_MODE_WAITING) | _BV(AXIS_MODE_MASKED) | _BV(AXIS_MODE_DEFER)))
        m |= _BV(AXIS_MODE_OWN_OFF);
    s.mode = m;
    sync_g0(s);
}

/* The axis's state is in ahead form (MultiStepEngine.h): acc, cur, left, rate and flags belong to
 * the step after the one armed. So while a fast command steps with the interrupts; not with a slow
 * one, nor when the C path makes the next step (PEND: the SLOW bit), nor in timed-loop mode. */
inline bool looked_ahead(const AxisState &s)
{
    return !MULTI_TIMED_LOOP && s.running && !(s.mode & _BV(AXIS_MODE_SLOW));
}

/* Makes slot t the interrupt's current command: its fields into the state (the interrupt's own
 * match cannot come before arm_step arms the next one). */
__attribute__((always_inline)) inline void load_slot(AxisState &s, AxisSlot &t)
{
    t.ready = 0;
    s.cur = &t;
    s.rate = t.rate;
    s.add = t.add;
    s.left = t.left;
    s.flags = t.flags;
    /* its SLOW mode bit: arm_step */
}

/* the last step of slot t is made and nothing follows: the move's end or an underrun (interrupts off);
 * stop_books: its books alone (the axis's interrupt masked; interrupts may be on: MultiStepEngine.cpp) */
void stop_after(AxisState &s, const AxisSlot &t);
void stop_books(AxisState &s, const AxisSlot &t);

/* The executor's variant (MultiStepEngineTimer.cpp or MultiStepEngineLoop.cpp): */
/* begin()'s last step, after the states are reset: s_tick_hz set from tick_hz, the timer (if any) started */
void hw_begin(uint32_t tick_hz);
/* the axis's executor stops at once (interrupts off) */
void hw_stop(uint8_t axis);
/* takes the first laid-out slot and arms its first step from t = base (16.16 ticks) */
void start_axis(uint8_t axis, uint32_t base);
/* t = 0 that many ticks ahead of now */
uint32_t base_ahead(uint16_t ticks);
/* service()'s safety net for a compare match that never came */
void catch_missed_match(uint8_t axis);
/* service() may plan one more command now (timed-loop mode: only between deadlines) */
bool may_plan(uint8_t axis);
} // namespace mse

#endif
