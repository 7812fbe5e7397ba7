/* StepEngine.cpp - the step interrupt's rarer path (a new command, slow steps, the end, an
 * underrun, a late edge), the queue's loop() side and the timer set-up; see StepEngine.h. The
 * common path is StepEngineIsr.S. */
#include "StepEngine.h"

#include <stddef.h>
#include <util/atomic.h>
#include <util/delay.h>

StepEngineState step_engine;

static_assert(offsetof(StepEngineState, acc) == 0 && offsetof(StepEngineState, cur) == 4 &&
                  offsetof(StepEngineState, waiting) == 6 && offsetof(StepEngineState, late) == 7 &&
                  offsetof(StepEngineState, late_ticks) == 9 && offsetof(StepSlot, rate) == 0 &&
                  offsetof(StepSlot, add) == 4 && offsetof(StepSlot, left) == 8 && offsetof(StepSlot, flags) == 10 &&
                  offsetof(StepSlot, ready) == 11 && offsetof(StepSlot, other) == 12,
              "StepEngineIsr.S reads these offsets");

namespace {
uint32_t s_tick_hz;
uint8_t s_open;                      /* a move is being fed (accepted, not yet reported done) */
uint32_t s_duration[STEP_ENGINE_SLOTS]; /* ticks of each slot's command (loop() side only) */
uint32_t s_queued_ticks;
uint8_t s_head;                      /* the next slot loop() lays out */
uint8_t s_seen;                      /* the oldest slot still counted in s_queued_ticks */
uint8_t s_ready;                     /* slots laid out and counted */
uint32_t s_lead_ticks;
int32_t s_next_p_start;              /* position before the next command to be laid out */
uint8_t s_last_forward;              /* direction of the last command laid out */
StepEngine::DirectionHook s_dir_hook; /* the sketch's moveOneStep(), or none: write_dir */
#if STEPPER_TIMED_LOOP
uint32_t s_deadline_us;
#endif

inline void write_dir(bool forward)
{
    if (forward)
        STEPPER_DIR_PORT |= _BV(STEPPER_DIR_BIT);
    else
        STEPPER_DIR_PORT &= (uint8_t)~_BV(STEPPER_DIR_BIT);
}

/* The direction of the steps that follow: the sketch's hook sets DIR if it registered one (the lab
 * sketches' moveOneStep()), else the engine does. Called before the first step of a move from rest
 * (loop() side) and, at a reversal, by the C path of the step interrupt after STEP has fallen: never
 * on the assembly path, never per step. */
void set_direction(bool forward)
{
    if (s_dir_hook)
        s_dir_hook(forward);
    else
        write_dir(forward);
}

inline void step_low()
{
    STEPPER_STEP_PORT &= (uint8_t)~_BV(STEPPER_STEP_BIT);
#if STEPPER_TRACE
    STEPPER_TRACE_PORT &= (uint8_t)~_BV(STEPPER_TRACE_BIT);
#endif
}

uint32_t duration_ticks(const step_cmd_t &c)
{
    uint32_t per = (c.flags & STEP_CMD_WIDE) ? c.rate : (c.rate >> 16);
    return per * c.count;
}

inline uint8_t next_slot(uint8_t i)
{
    return (uint8_t)((i + 1U) % STEP_ENGINE_SLOTS);
}

/* the interrupt's current slot: a two-byte pointer it may change at any time, so read with
 * care (a torn read would point anywhere) */
inline StepSlot *cur_slot()
{
    /* read twice until both agree: the interrupt changes it at most once per command, so this
     * never disables interrupts (which would delay a step edge) */
    StepSlot *a, *b;
    do {
        a = step_engine.cur;
        b = step_engine.cur;
    } while (a != b);
    return a;
}

inline uint8_t cur_index()
{
    return (uint8_t)(cur_slot() - step_engine.slot);
}

/* the slots the interrupt has taken since the last look no longer count as queued (the one it
 * is stepping counts until it moves on) */
void retire_consumed()
{
    uint8_t cur = cur_index();
    while (s_ready > 0 && !step_engine.slot[s_seen].ready && (s_seen != cur || !step_engine.running)) {
        s_queued_ticks -= s_duration[s_seen];
        s_seen = next_slot(s_seen);
        s_ready--;
    }
}

/* A command the assembly path cannot step: WIDE, or an interval of 32768 ticks or more at some
 * step (its late test is a signed 16-bit difference). */
bool is_slow(const step_cmd_t &c)
{
    uint32_t last;
    if (c.flags & STEP_CMD_WIDE)
        return true;
    last = c.rate + (uint32_t)c.add * (uint32_t)(c.count - 1U);
    return ((c.rate | last) & 0x80000000UL) != 0;
}

/* Lays the command out in slot t (which the interrupt is not using). */
void lay_out(StepSlot &t, const step_cmd_t &c)
{
    bool forward = !(c.flags & STEP_CMD_REVERSE);
    uint8_t f = 0;
    t.rate = c.rate;
    t.add = c.add;
    t.left = c.count - 1U; /* the first step is armed when the slot is taken */
    t.count = c.count;
    t.cmd_flags = c.flags;
    t.p_start = s_next_p_start;
    if (c.add != 0)
        f |= _BV(STEP_SLOT_HAS_ADD);
    if (is_slow(c))
        f |= _BV(STEP_SLOT_SLOW);
    if (forward)
        f |= _BV(STEP_SLOT_FORWARD);
    if ((uint8_t)forward != s_last_forward)
        f |= _BV(STEP_SLOT_TURN);
    t.flags = f;
    s_last_forward = forward;
    s_next_p_start += forward ? (int32_t)c.count : -(int32_t)c.count;
}

/* The last step of slot t is made and nothing is laid out after it: the move's end (when the
 * planner has marked it) or an underrun. The axis rests where t's steps took it. */
void stop_after(const StepSlot &t)
{
    StepEngineState &s = step_engine;
    s.pos_rest = t.p_start + ((t.flags & _BV(STEP_SLOT_FORWARD)) ? (int32_t)t.count : -(int32_t)t.count);
    s.running = 0;
    if (s.finishing) {
        s.finishing = 0;
        s.done = 1;
    } else {
        s.starved = 1;
        s.underruns = s.underruns + 1U;
    }
}

#if !STEPPER_TIMED_LOOP
/* Arms the next step of a slot by the executor's rule (step_queue.h), counting a slow interval's
 * wraps; a first match already missed counts as passed, and a step already due fires 2 us later. */
void arm_step(StepSlot &t)
{
    StepEngineState &s = step_engine;
    uint16_t prev = (uint16_t)(s.acc >> 16), elapsed;
    uint32_t interval, first;
    if (t.cmd_flags & STEP_CMD_WIDE) {
        interval = t.rate;
        s.acc += t.rate << 16;
    } else {
        uint32_t acc0 = s.acc;
        s.acc += t.rate;
        t.rate += (uint32_t)t.add;
        interval = (uint16_t)((s.acc >> 16) - (acc0 >> 16));
        if (interval == 0)
            interval = 0x10000UL;
    }
    OCR1A = (uint16_t)(s.acc >> 16);
    s.wraps = (uint16_t)((interval - 1U) >> 16);
    first = ((interval - 1U) & 0xFFFFUL) + 1U;
    /* ticks since the edge the interval counts from: small, or negative at a move's start, where
     * that reference lies a few ticks ahead (start_stepping): then nothing has elapsed, and if the
     * compare value comes round before the reference (first + the lead past a wrap) that match is
     * one more to let pass */
    elapsed = TCNT1 - prev;
    if ((int16_t)elapsed < 0) {
        if (first > 0x10000UL - (uint16_t)-(int16_t)elapsed)
            s.wraps = s.wraps + 1U;
        elapsed = 0;
    }
    if (elapsed >= first && !(TIFR1 & _BV(OCF1A))) {
        if (s.wraps != 0) {
            s.wraps = s.wraps - 1U;
        } else {
            OCR1A = TCNT1 + s.late_ticks;
            s.late = s.late + 1U;
        }
    }
    s.waiting = s.wraps != 0;
}
#endif
} // namespace

#if !STEPPER_TIMED_LOOP
/* Entered from StepEngineIsr.S with the registers as at the interrupt's entry: a wrap to count,
 * a slow command's step, or the current slot used up without a ready fast one to switch to. */
extern "C" void __vector_step_engine_cold(void) __attribute__((signal, used));
void __vector_step_engine_cold(void)
{
    StepEngineState &s = step_engine;
    StepSlot *cur = s.cur, *next;
    if (s.waiting) {
        s.wraps = s.wraps - 1U;
        if (s.wraps == 0)
            s.waiting = 0;
        return;
    }
    /* STEP is high: this match made a step */
    if ((cur->flags & _BV(STEP_SLOT_SLOW)) && cur->left != 0) {
        cur->left = cur->left - 1U;
        arm_step(*cur);
        step_low();
        return;
    }
    next = cur->other;
    if (!next->ready) {
        /* nothing laid out: the move's end, or an underrun */
        TIMSK1 &= (uint8_t)~_BV(OCIE1A);
        stop_after(*cur);
        __builtin_avr_delay_cycles(32); /* the STEP pulse: >= 2 us */
        step_low();
        return;
    }
    next->ready = 0;
    s.cur = next;
    arm_step(*next);
    step_low();
    if (next->flags & _BV(STEP_SLOT_TURN))
        set_direction(next->flags & _BV(STEP_SLOT_FORWARD)); /* a reversal: the assembly path sent it here */
}
#endif

void StepEngine::begin(uint32_t tick_hz, uint16_t lead_ms)
{
    STEPPER_STEP_DDR |= _BV(STEPPER_STEP_BIT);
    STEPPER_STEP_PORT &= (uint8_t)~_BV(STEPPER_STEP_BIT);
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
    for (uint8_t i = 0; i < STEP_ENGINE_SLOTS; i++) {
        step_engine.slot[i].other = &step_engine.slot[next_slot(i)];
        step_engine.slot[i].ready = 0;
    }
    step_engine.cur = &step_engine.slot[0];
    step_engine.pos_rest = 0;
    s_next_p_start = 0;
    s_last_forward = 1;
    s_head = 1; /* the slot after the current one */
    s_seen = 1;
    s_ready = 0;
    s_queued_ticks = 0;
#if STEPPER_TIMED_LOOP
    (void)tick_hz;
    s_tick_hz = 1000000UL;
#else
    s_tick_hz = tick_hz == 16000000UL ? 16000000UL : 2000000UL;
    step_engine.late_ticks = (uint8_t)(s_tick_hz / 500000UL);
    /* The Arduino core leaves Timer1 in 8-bit PWM mode for analogWrite(): take it over. */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        TIMSK1 = 0;
        TCCR1A = 0;
        TCCR1C = 0;
        TCCR1B = s_tick_hz == 16000000UL ? _BV(CS10) : _BV(CS11); /* normal mode, prescaler 1 or 8 */
        TIFR1 = _BV(OCF1A) | _BV(OCF1B) | _BV(OCF1C) | _BV(TOV1);
    }
#endif
    s_lead_ticks = s_tick_hz / 1000UL * lead_ms;
}

void StepEngine::set_direction_hook(DirectionHook hook)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        s_dir_hook = hook;
    }
}

uint32_t StepEngine::tick_hz()
{
    return s_tick_hz;
}

static void start_stepping()
{
    StepEngineState &s = step_engine;
    StepSlot *t = s.cur->other;
    if (!t->ready)
        return;
    t->ready = 0;
    s.cur = t;
    set_direction(t->flags & _BV(STEP_SLOT_FORWARD));
    t->flags &= (uint8_t)~_BV(STEP_SLOT_TURN); /* DIR is set here, before the first step */
#if STEPPER_TIMED_LOOP
    s.acc = 0x8000UL;
    {
        uint16_t prev = 0, edge;
        uint32_t acc0 = s.acc;
        if (t->cmd_flags & STEP_CMD_WIDE) {
            s.acc += t->rate << 16;
            s_deadline_us = micros() + t->rate;
        } else {
            s.acc += t->rate;
            t->rate += (uint32_t)t->add;
            edge = (uint16_t)(s.acc >> 16);
            s_deadline_us = micros() + (uint16_t)(edge - prev);
        }
        (void)acc0;
    }
    s.starved = 0;
    s.running = 1;
#else
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        /* t = 0 a few ticks from now, so that even a one-tick first interval lies ahead */
        s.acc = ((uint32_t)(uint16_t)(TCNT1 + 64U) << 16) | 0x8000UL;
        s.waiting = 0;
        s.wraps = 0;
        arm_step(*t);
        TIFR1 = _BV(OCF1A);
        s.starved = 0;
        s.running = 1;
        TIMSK1 |= _BV(OCIE1A);
    }
#endif
}

#if !STEPPER_TIMED_LOOP
/* A compare match that never came (libsimavr dropped some, after a timer wrap, until the harness
 * modelled the chip there: tools/emu/emu_timer.c; kept as a safety net): the armed edge lies well
 * in the past, no match is pending and the interrupt has not moved on. Fire it now and count it as
 * late, instead of waiting a whole wrap. Checked every 8th call, briefly with interrupts off. */
/* The armed edge lies 65 to 16384 ticks in the past (16-bit times): a match missed not long ago. A
 * move's first edge may be armed up to 32831 ticks ahead (64 plus a first interval below 32768),
 * which in 16 bits can look like the past: it must not be fired at once. */
static inline bool missed_by(uint16_t now, uint16_t edge)
{
    return (uint16_t)(now - edge) - 65U < 16320U;
}

static void catch_missed_match()
{
    static uint8_t every;
    StepEngineState &s = step_engine;
    if ((++every & 7U) != 0)
        return;
    /* a first look with interrupts on (a torn read only costs the careful look below): interrupts
     * stay on unless a match really seems missed, so this check does not delay step edges */
    if (!s.running || s.waiting || (TIFR1 & _BV(OCF1A)) || !missed_by(TCNT1, (uint16_t)(s.acc >> 16)))
        return;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (s.running && !s.waiting && !(s.cur->flags & _BV(STEP_SLOT_SLOW)) && !(TIFR1 & _BV(OCF1A))) {
            uint16_t now = TCNT1;
            if (missed_by(now, (uint16_t)(s.acc >> 16))) {
                OCR1A = now + s.late_ticks;
                s.late = s.late + 1U;
            }
        }
    }
}
#endif

void StepEngine::service(step_planner_t &planner)
{
    StepEngineState &s = step_engine;
    step_cmd_t c;
#if !STEPPER_TIMED_LOOP
    catch_missed_match();
#endif
    retire_consumed();
    /* lay out commands while the slot at s_head is free (not ready, not the current one) */
    while (s_ready < 2U || s_queued_ticks < s_lead_ticks) {
        StepSlot &t = s.slot[s_head];
#if STEPPER_TIMED_LOOP
        /* loop() makes the steps here: plan only in the gaps, never across a deadline */
        poll();
        if (s.running && s_ready >= 2U && (int32_t)(s_deadline_us - micros()) < 400)
            break;
#endif
        if (t.ready || (s.running && s_head == cur_index()) || s_ready >= STEP_ENGINE_SLOTS - 1U)
            break;
        if (!step_planner_next(&planner, &c))
            break;
        if (s_ready == 0 && !s.running) {
            /* the first command of a run: it starts where the axis stands */
            s_next_p_start = s.pos_rest;
            s_last_forward = (STEPPER_DIR_PORT & _BV(STEPPER_DIR_BIT)) != 0;
        }
        lay_out(t, c);
        s_duration[s_head] = duration_ticks(c);
        s_queued_ticks += s_duration[s_head];
        s_ready++;
        t.ready = 1; /* one byte, written last: the interrupt sees a complete slot */
        s_head = next_slot(s_head);
        if (s_open && !s.running && !s.done && s_ready >= STEP_ENGINE_START_SLOTS)
            start_stepping(); /* enough lead for the first steps, the costliest to plan */
    }
    /* a short move (nothing more to plan), the lead reached, or every slot full: start */
    if (s_open && !s.running && !s.done && s.cur->other->ready)
        start_stepping();
    /* the planner has handed out its last command: the move ends after the queued ones (marked at
     * once: waiting until the interrupt steps the last one left a window of one short command, and
     * a loop() busy then had the end counted as an underrun) */
    if (s_open && !step_planner_busy(&planner) && !s.finishing && !s.done) {
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
        {
            if (s.running)
                s.finishing = 1;
            else if (!s.cur->other->ready)
                s.done = 1; /* nothing was left to step (a zero-length move) */
        }
    }
}

StepEngine::Continuation StepEngine::extend(int32_t &ended_at)
{
    StepEngineState &s = step_engine;
    Continuation r = CONTINUES;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (s.done) {
            s.done = 0;
            s_open = 0;
            ended_at = s.pos_rest;
            r = ENDED;
        } else if (!s_open) {
            r = AT_REST;
        } else {
            s.finishing = 0; /* still running (the interrupt sets done when it stops) */
        }
    }
    return r;
}

void StepEngine::open_move()
{
    s_open = 1;
}

/* position with interrupts off: the steps made of the current command added to its start */
static int32_t position_now()
{
    StepEngineState &s = step_engine;
    const StepSlot *t = s.cur;
    uint16_t made;
    if (!s.running)
        return s.pos_rest;
    made = t->count - 1U - t->left;
    return t->p_start + ((t->flags & _BV(STEP_SLOT_FORWARD)) ? (int32_t)made : -(int32_t)made);
}

void StepEngine::halt()
{
    StepEngineState &s = step_engine;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
#if !STEPPER_TIMED_LOOP
        TIMSK1 &= (uint8_t)~_BV(OCIE1A);
#endif
        s.pos_rest = position_now();
        s.running = 0;
        s.finishing = 0;
        s.starved = 0;
        s.wraps = 0;
        s.waiting = 0;
        for (uint8_t i = 0; i < STEP_ENGINE_SLOTS; i++)
            s.slot[i].ready = 0;
        if (s_open)
            s.done = 1;
    }
    step_low();
    s_head = next_slot(cur_index());
    s_seen = s_head;
    s_ready = 0;
    s_queued_ticks = 0;
}

bool StepEngine::moving()
{
    return s_open != 0;
}

int32_t StepEngine::position()
{
    int32_t p;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        p = position_now();
    }
    return p;
}

uint8_t StepEngine::phase()
{
    uint8_t ph = RAMP_IDLE;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (step_engine.running)
            ph = STEP_CMD_PHASE(step_engine.cur->cmd_flags);
    }
    return ph;
}

uint16_t StepEngine::underruns()
{
    uint16_t n;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        n = step_engine.underruns;
    }
    return n;
}

uint16_t StepEngine::late_edges()
{
    uint16_t n;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        n = step_engine.late;
    }
    return n;
}

bool StepEngine::take_done(int32_t &position)
{
    bool done = false;
    if (!step_engine.done)
        return false; /* one byte, read with interrupts on: loop() asks on every pass */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (step_engine.done) {
            step_engine.done = 0;
            s_open = 0;
            position = step_engine.pos_rest;
            done = true;
        }
    }
    return done;
}

void StepEngine::poll()
{
#if STEPPER_TIMED_LOOP
    StepEngineState &s = step_engine;
    StepSlot *t;
    uint32_t acc0;
    if (!s.running || (int32_t)(micros() - s_deadline_us) < 0)
        return;
    STEPPER_STEP_PORT |= _BV(STEPPER_STEP_BIT);
#if STEPPER_LED_MIRROR
    STEPPER_LED_PIN = _BV(STEPPER_LED_BIT);
#endif
    t = s.cur;
    if (t->left != 0) {
        t->left = t->left - 1U;
    } else {
        StepSlot *next = t->other;
        if (!next->ready) {
            stop_after(*t);
            _delay_us(2);
            step_low();
            return;
        }
        next->ready = 0;
        s.cur = t = next;
    }
    acc0 = s.acc;
    if (t->cmd_flags & STEP_CMD_WIDE) {
        s.acc += t->rate << 16;
        s_deadline_us += t->rate;
    } else {
        s.acc += t->rate;
        t->rate += (uint32_t)t->add;
        s_deadline_us += (uint16_t)((s.acc >> 16) - (acc0 >> 16)); /* the deadline: no drift */
    }
    _delay_us(2);
    step_low();
    if (t->flags & _BV(STEP_SLOT_TURN))
        set_direction(t->flags & _BV(STEP_SLOT_FORWARD));
#endif
}
