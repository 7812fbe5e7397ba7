/* MultiStepEngine.cpp - the step interrupts' rarer path (slow steps and a slow command's start,
 * wraps to count, the end, an underrun), each axis's queue on the loop() side, and the timer
 * set-up; see MultiStepEngine.h. The common path, new fast commands and late edges included, is
 * MultiStepEngineIsr.inc. */
#include "MultiStepEngineInternal.h"

#include "BoardHeap.h"

#include <ramp_common.h> /* the ramp phases of the commands (cut_mirror) */
#include <stddef.h>
#include <stdlib.h>
#include <util/atomic.h>
#ifdef MULTI_TEST_CUT_FIND_WAIT_US
#include <util/delay.h>
#endif

using namespace mse;

/* multi_axis_x, _y, _z are reserved in MultiStepEngineX.S, Y.S, Z.S (plain object files, so that the
 * library links as an archive with LTO) */
static_assert(sizeof(AxisState) == MULTI_AXIS_STATE_BYTES, "MultiStepEngineX.S, Y.S, Z.S reserve this size");

static_assert(offsetof(AxisState, acc) == 0 && offsetof(AxisState, rate) == 4 && offsetof(AxisState, add) == 8 &&
                  offsetof(AxisState, left) == 12 && offsetof(AxisState, flags) == 14 &&
                  offsetof(AxisState, mode) == 15 && offsetof(AxisState, cur) == 16 && offsetof(AxisState, late) == 18 &&
                  offsetof(AxisState, late_ticks) == 20 && offsetof(AxisState, mask_f) == 21 &&
                  offsetof(AxisState, mask_l) == 22 &&
                  offsetof(AxisSlot, rate) == 0 && offsetof(AxisSlot, add) == 4 && offsetof(AxisSlot, left) == 8 &&
                  offsetof(AxisSlot, flags) == 10 && offsetof(AxisSlot, ready) == 11 && offsetof(AxisSlot, other) == 12,
              "MultiStepEngineIsr.inc reads these offsets");

volatile uint8_t multi_running_ocie;
volatile uint8_t multi_in_cold;

namespace mse {
AxisFeed s_feed[MULTI_AXES];
AxisState *s_state[MULTI_AXES];
uint8_t s_axes;
uint32_t s_lead_ticks;
uint32_t s_tick_hz = MULTI_TICK_HZ; /* begin(): 16 MHz or 2 MHz */
MultiStepEngine::DirectionHook s_dir_hook[MULTI_AXES]; /* set_direction_hook: the sketch sets DIR */
}

namespace {
/* A slot's duration, for the lead and the cut: its steps' ticks (its first interval's, times its
 * count) in units of 16 ticks (1 us at 16 MHz), rounded down, at most 0xFFFF units (65 ms at 16 MHz,
 * 0.5 s at 2 MHz). In whole ticks, capped at 65,535 (4 ms at 16 MHz), the slots of a slow move (20
 * steps a second) each counted 4 ms: they filled the whole ring, nearly 5 s of steps, before the lead
 * (100 ms) looked reached, and a stop or a new target waited that long (make fuzz, seed 23). Rounded
 * down, the time ahead of a cut is never overestimated (the cut only lands farther). */
#define DUR_SHIFT 4
uint16_t duration_ticks(const step_cmd_t &c)
{
    uint32_t d;
    if (c.flags & STEP_CMD_WIDE) {
        uint64_t w = ((uint64_t)c.rate * c.count) >> DUR_SHIFT;
        return w > 0xFFFFU ? 0xFFFFU : (uint16_t)w;
    }
    /* whole ticks of a 16.16 rate times the count: 16 x 16 bits (a 64-bit product cost some 300
     * cycles of every command laid out) */
    d = ((uint32_t)(uint16_t)(c.rate >> 16) * c.count) >> DUR_SHIFT;
    return d > 0xFFFFU ? 0xFFFFU : (uint16_t)d;
}

/* the ticks a slot's stored duration stands for */
static inline uint32_t lead_weight(uint16_t d)
{
    return (uint32_t)d << DUR_SHIFT;
}

void retire_consumed(AxisState &s, AxisFeed &f)
{
    uint8_t cur = cur_index(s);
    while (f.ready > 0 && !s.slot[f.seen].ready && (f.seen != cur || !s.running)) {
        f.queued_ticks -= lead_weight(f.duration[f.seen]);
        f.seen = next_slot(f, f.seen);
        f.ready--;
    }
}

/* WIDE, or an interval of 32768 ticks or more at some step (the late test is a signed 16-bit
 * difference): the C path steps it */
bool is_slow(const step_cmd_t &c)
{
    uint32_t last;
    if (c.flags & STEP_CMD_WIDE)
        return true;
    last = c.rate + (uint32_t)c.add * (uint32_t)(c.count - 1U);
    return ((c.rate | last) & 0x80000000UL) != 0;
}

/* a command's slot flags but TURN (which depends on the command before it) */
static uint8_t slot_flags(const step_cmd_t &c)
{
    uint8_t fl = 0;
    if (c.add != 0)
        fl |= _BV(AXIS_SLOT_HAS_ADD);
    if (c.add >= -32768L && c.add <= 32767L)
        fl |= _BV(AXIS_SLOT_ADD16);
    if (is_slow(c))
        fl |= _BV(AXIS_SLOT_SLOW);
    if (c.flags & STEP_CMD_WIDE)
        fl |= _BV(AXIS_SLOT_WIDE);
    fl |= (uint8_t)(STEP_CMD_PHASE(c.flags) << AXIS_SLOT_PHASE_SHIFT);
    if (!(c.flags & STEP_CMD_REVERSE))
        fl |= _BV(AXIS_SLOT_FORWARD);
    return fl;
}

void lay_out(AxisFeed &f, AxisSlot &t, const step_cmd_t &c)
{
    uint8_t fl = slot_flags(c);
    bool forward = (fl & _BV(AXIS_SLOT_FORWARD)) != 0;
    /* the interrupt adds add to rate before it uses it: laid out less add (WIDE: whole ticks, no add) */
    t.rate = (c.flags & STEP_CMD_WIDE) ? c.rate : c.rate - (uint32_t)c.add;
    t.add = c.add;
    t.left = c.count - 1U; /* the first step is armed when the slot is taken */
    t.p_start = f.next_p_start;
    if ((uint8_t)forward != f.last_forward)
        fl |= _BV(AXIS_SLOT_TURN);
    t.flags = fl;
    f.last_forward = forward;
    f.next_p_start += forward ? (int32_t)c.count : -(int32_t)c.count;
}

} // namespace

/* the last step of slot t is made and nothing follows: the move's end or an underrun. Its books (the
 * axis's own fields, which only its interrupt and, after it, the planner touch) may be made with
 * interrupts on once the axis's interrupt is masked; the running flag and the registers shared with
 * the other axes (sync_g0) with interrupts off. */
void mse::stop_books(AxisState &s, const AxisSlot &t)
{
    int32_t made = (int32_t)t.left + 1;
    s.pos_rest = t.p_start + ((t.flags & _BV(AXIS_SLOT_FORWARD)) ? made : -made);
    if (s.finishing) {
        s.finishing = 0;
        s.done = 1;
    } else {
        s.underruns = s.underruns + 1U;
    }
}

void mse::stop_after(AxisState &s, const AxisSlot &t)
{
    stop_books(s, t);
    s.running = 0;
    sync_g0(s);
}

void MultiStepEngine::attach(uint8_t axis, AxisState &s)
{
    static const uint8_t g_any[MULTI_AXES] = {_BV(MULTI_G_ANY_X), _BV(MULTI_G_ANY_Y), _BV(MULTI_G_ANY_Z)};
    static const uint8_t g_off[MULTI_AXES] = {_BV(MULTI_G_OWNOFF_X), _BV(MULTI_G_OWNOFF_Y), _BV(MULTI_G_OWNOFF_Z)};
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        hw_stop(axis);
        s.g_any = g_any[axis];
        s.g_off = g_off[axis];
        s_state[axis] = &s;
    }
}

/* Each registered axis's ring and its durations, from the heap (BoardHeap.h), once: x_alone
 * commands when X is the only axis, MULTI_SLOTS each otherwise. False: no room for one of them
 * (those taken are kept, and a later call takes only the others). */
static bool alloc_rings(uint8_t x_alone)
{
    uint8_t n = (s_state[0] && !s_state[1] && !s_state[2]) ? x_alone : MULTI_SLOTS;
    for (uint8_t a = 0; a < MULTI_AXES; a++) {
        if (!s_state[a] || s_state[a]->slot)
            continue;
        AxisSlot *ring = static_cast<AxisSlot *>(board_take(n * (sizeof(AxisSlot) + sizeof(uint16_t))));
        if (!ring)
            return false;
        s_state[a]->slot = ring;
        s_feed[a].duration = reinterpret_cast<uint16_t *>(ring + n);
        s_feed[a].nslots = n;
    }
    return true;
}

/* an axis's pins as outputs: STEP low, DIR high (forward), ENABLE low (on); interrupts are off */
static void axis_pins(uint8_t axis)
{
    if (axis == 0) {
        DDRF |= _BV(MULTI_X_STEP_BIT) | _BV(MULTI_X_DIR_BIT);
        PORTF = (uint8_t)((PORTF & ~_BV(MULTI_X_STEP_BIT)) | _BV(MULTI_X_DIR_BIT));
        MULTI_X_ENABLE_DDR |= _BV(MULTI_X_ENABLE_BIT);
        MULTI_X_ENABLE_PORT &= (uint8_t)~_BV(MULTI_X_ENABLE_BIT);
    } else if (axis == 1) {
        DDRF |= _BV(MULTI_Y_STEP_BIT) | _BV(MULTI_Y_DIR_BIT);
        PORTF = (uint8_t)((PORTF & ~_BV(MULTI_Y_STEP_BIT)) | _BV(MULTI_Y_DIR_BIT));
        MULTI_Y_ENABLE_DDR |= _BV(MULTI_Y_ENABLE_BIT);
        MULTI_Y_ENABLE_PORT &= (uint8_t)~_BV(MULTI_Y_ENABLE_BIT);
    } else {
        DDRL |= _BV(MULTI_Z_STEP_BIT) | _BV(MULTI_Z_DIR_BIT);
        PORTL = (uint8_t)((PORTL & ~_BV(MULTI_Z_STEP_BIT)) | _BV(MULTI_Z_DIR_BIT));
        MULTI_Z_ENABLE_DDR |= _BV(MULTI_Z_ENABLE_BIT);
        MULTI_Z_ENABLE_PORT &= (uint8_t)~_BV(MULTI_Z_ENABLE_BIT);
    }
#if MULTI_TRACE
    MULTI_TRACE_DDR |= axis == 0 ? _BV(MULTI_TRACE_X_BIT) : axis == 1 ? _BV(MULTI_TRACE_Y_BIT) : _BV(MULTI_TRACE_Z_BIT);
#endif
}

bool MultiStepEngine::begin_axes(uint32_t tick_hz, uint8_t x_alone)
{
    if (x_alone < 3U || !alloc_rings(x_alone))
        return false;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        s_axes = 0;
        for (uint8_t a = 0; a < MULTI_AXES; a++) {
            if (!s_state[a])
                continue;
            AxisState &s = state(a);
            AxisFeed &f = s_feed[a];
            s_axes |= (uint8_t)(1U << a);
            axis_pins(a);
            for (uint8_t i = 0; i < f.nslots; i++) {
                s.slot[i].other = &s.slot[next_slot(f, i)];
                s.slot[i].ready = 0;
            }
            s.cur = &s.slot[0];
            s.mode = 0;
            s.running = 0;
            s.pos_rest = 0;
            own_masks(a);
            f.next_p_start = 0;
            f.last_forward = 1;
            f.head = 1;
            f.seen = 1;
            f.ready = 0;
            f.queued_ticks = 0;
            f.open = 0;
            f.held = 0;
            f.keep = 0;
        }
        /* none running (sync_g0); the LED mirror as set */
        GPIOR0 = (uint8_t)((GPIOR0 & _BV(MULTI_G_LED_X)) | _BV(MULTI_G_OWNOFF_X) | _BV(MULTI_G_OWNOFF_Y) |
                           _BV(MULTI_G_OWNOFF_Z) | _BV(MULTI_G_ANY_X) | _BV(MULTI_G_ANY_Y) | _BV(MULTI_G_ANY_Z));
    }
    hw_begin(tick_hz); /* the executor's time base (s_tick_hz) and timer */
    for (uint8_t a = 0; a < MULTI_AXES; a++)
        if (s_state[a])
            state(a).late_ticks = (uint8_t)(s_tick_hz / 500000UL); /* 2 us: 32 or 4 ticks */
    s_lead_ticks = s_tick_hz / 1000UL * MULTI_LEAD_MS;
    return true;
}

uint32_t MultiStepEngine::tick_hz()
{
    return s_tick_hz;
}

static bool has_room(AxisState &s, AxisFeed &f)
{
    return !s.slot[f.head].ready && !(s.running && f.head == cur_index(s)) && f.ready < ring_cap(f);
}

static void lay_one(uint8_t axis, AxisState &s, AxisFeed &f, const step_cmd_t &c)
{
    AxisSlot &t = s.slot[f.head];
    if (f.ready == 0 && !s.running) {
        /* the first command of a run: it starts where the axis stands */
        f.next_p_start = s.pos_rest;
        f.last_forward = dir_level(axis);
    }
    lay_out(f, t, c);
    if (s_dir_hook[axis] && (t.flags & _BV(AXIS_SLOT_TURN)))
        t.flags |= _BV(AXIS_SLOT_SLOW); /* the C path turns it: through the hook */
    f.duration[f.head] = duration_ticks(c);
    f.queued_ticks += lead_weight(f.duration[f.head]);
    f.ready++;
    __asm__ __volatile__("" ::: "memory"); /* the fields stored before the flag */
    t.ready = 1; /* one byte, written last: the interrupt sees a complete slot */
    f.head = next_slot(f, f.head);
}

uint8_t MultiStepEngine::service(uint8_t axis, const AxisSource &src, uint8_t max_cmds)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    step_cmd_t c;
    uint8_t laid = 0;
    poll(); /* timed-loop mode: the steps due (loop()'s calls into the engine are its chances) */
    catch_missed_match(axis);
    retire_consumed(s, f);
    while (laid < max_cmds && (f.ready < 2U || f.queued_ticks < s_lead_ticks)) {
        if (!has_room(s, f) || !may_plan(axis))
            break;
        if (!src.next(src.ctx, &c))
            break;
        lay_one(axis, s, f, c);
        laid++;
    }
    /* enough laid out for the first steps (the costliest to plan), or all there is: start */
    if (f.open && !f.held && !s.running && !s.done && s.cur->other->ready &&
        (f.started || MultiStepEngine::ready_to_start(axis, src)))
        start_axis(axis, base_ahead(64));
    /* the planner has handed out its last command: the move ends after the queued ones. Marked as
     * soon as that is so, not only once the interrupt steps the last one (a last command of one
     * step is over in a fraction of a millisecond, and loop() may be planning another axis then: the
     * end would be counted as an underrun, found by `make fuzz`) */
    if (f.open && !f.held && !src.busy(src.ctx) && !s.finishing && !s.done) {
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
        {
            if (s.running)
                s.finishing = 1;
            else if (!s.cur->other->ready)
                s.done = 1; /* nothing was left to step */
        }
    }
    return laid;
}

/* what the interrupt's current command has already stepped of the time the books count for it
 * (f.queued_ticks counts a command whole until it is done: the rest of it is about its steps not armed
 * yet times its interval), ticks; 0 when the books do not begin at it, or for a WIDE one. An estimate
 * for the planner's choice of the axis to feed, read without turning interrupts off (a cli of some
 * 40 cycles at every pick put a Stepper's edges at 90,000 steps/s late: make bench) */
static uint32_t current_spent(AxisState &s, const AxisFeed &f)
{
    if (!s.running || (s.flags & _BV(AXIS_SLOT_WIDE)) || cur_index(s) != f.seen)
        return 0;
    uint16_t left = s.left;
    while (left != s.left) /* (two bytes the interrupt may change between them) */
        left = s.left;
    const uint16_t per = reinterpret_cast<volatile const uint16_t *>(&s.rate)[1]; /* the interval's ticks */
    const uint32_t whole = lead_weight(f.duration[f.seen]), rest = (uint32_t)left * per;
    return rest < whole ? whole - rest : 0U;
}

uint32_t MultiStepEngine::queued_ticks(uint8_t axis, bool rest)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    poll();
    retire_consumed(s, f);
    if (!(f.ready < 2U || f.queued_ticks < s_lead_ticks) || f.ready >= ring_cap(f) ||
        s.slot[f.head].ready || (s.running && f.head == cur_index(s)))
        return UINT32_MAX;
    /* rest: what is left to step; a slow axis's commands last long (Z's at a few hundred steps/s,
     * some 10 ms each), and counted whole its queue looked deeper than the others' while it ran dry
     * (three Steppers at 15,000 steps/s stopped as a group 175 ms into the move: Z paused 1.7 ms) */
    return rest ? f.queued_ticks - current_spent(s, f) : f.queued_ticks;
}

bool MultiStepEngine::paused(uint8_t axis)
{
    return !state(axis).running && s_feed[axis].open && s_feed[axis].started;
}

uint32_t MultiStepEngine::interval_ticks(uint8_t axis)
{
    const AxisState &s = state(axis);
    if (s.flags & _BV(AXIS_SLOT_WIDE))
        return s.rate; /* whole ticks (a torn read is off for one choice) */
    return reinterpret_cast<volatile const uint16_t *>(&s.rate)[1]; /* 16.16: the ticks */
}

void MultiStepEngine::follow(uint8_t master, uint8_t axis, bool forward)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        AxisState &m = state(master), &a = state(axis);
        set_dir(axis, forward);
        m.mask_f |= a.mask_f;
        m.mask_l |= a.mask_l;
        change_mode(m, _BV(AXIS_MODE_MASKED), 0);
    }
}

void MultiStepEngine::unfollow(uint8_t master)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        own_masks(master);
        change_mode(state(master), 0, _BV(AXIS_MODE_MASKED));
    }
}

void MultiStepEngine::set_rest_position(uint8_t axis, int32_t pos)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        state(axis).pos_rest = pos;
    }
}

/* Another axis is stepping a move (or paused in it by an underrun): its queue must not wait for
 * this axis's planning. */
static bool others_stepping(uint8_t axis)
{
    for (uint8_t a = 0; a < MULTI_AXES; a++)
        if (a != axis && s_feed[a].open && s_feed[a].started)
            return true;
    return false;
}

static uint8_t s_start_full; /* bit i: axis i starts with its ring full (set_start_full) */

void MultiStepEngine::set_start_full(uint8_t axis, bool full)
{
    if (axis >= MULTI_AXES)
        return;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (full)
            s_start_full |= (uint8_t)_BV(axis);
        else
            s_start_full &= (uint8_t)~_BV(axis);
    }
}

bool MultiStepEngine::ready_to_start(uint8_t axis, const AxisSource &src)
{
    AxisFeed &f = s_feed[axis];
    /* alone, the first MULTI_START_SLOTS commands suffice: the CPU plans the rest faster than they are
     * stepped; while other axes step, it shares the CPU with their planning, so it starts with its
     * ring full (or its lead laid out) */
    uint8_t want = (others_stepping(axis) || (s_start_full & _BV(axis))) ? ring_cap(f) : (uint8_t)MULTI_START_SLOTS;
    return f.ready >= want || f.ready >= ring_cap(f) || !src.busy(src.ctx) || f.queued_ticks >= s_lead_ticks;
}

bool MultiStepEngine::stepping(uint8_t axis)
{
    return s_feed[axis].open && s_feed[axis].started;
}

void MultiStepEngine::start_together(uint8_t mask)
{
    /* far enough ahead (256 us) for three first steps to be armed (a few hundred cycles each, with
     * interrupts on: other axes moving meanwhile keep stepping): 4096 ticks at 16 MHz, 512 at 2 MHz */
    uint32_t base = base_ahead((uint16_t)(s_tick_hz / 3906UL));
    mask &= s_axes;
    for (uint8_t a = 0; a < MULTI_AXES; a++) {
        if (!(mask & (1U << a)))
            continue;
        if (state(a).cur->other->ready)
            start_axis(a, base);
        else
            s_feed[a].held = 0; /* nothing to step: service() marks it done */
    }
}

/* the move has ended: closed, its final position handed out (interrupts off: inlined, so that the
 * stretch stays a few cycles) */
__attribute__((always_inline)) static inline bool take_end(uint8_t axis, int32_t &at)
{
    AxisState &s = state(axis);
    if (!s.done)
        return false;
    s.done = 0;
    s_feed[axis].open = 0;
    at = s.pos_rest;
    return true;
}

MultiStepEngine::Continuation MultiStepEngine::extend(uint8_t axis, int32_t &ended_at)
{
    AxisState &s = state(axis);
    Continuation r = CONTINUES;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (take_end(axis, ended_at)) {
            r = ENDED;
        } else if (!s_feed[axis].open) {
            r = AT_REST;
        } else {
            s.finishing = 0;
        }
    }
    return r;
}

void MultiStepEngine::open_move(uint8_t axis, bool held, uint8_t keep)
{
    const uint8_t most = (uint8_t)(s_feed[axis].nslots / 4U);
    s_feed[axis].keep = keep < most ? keep : most;
    s_feed[axis].open = 1;
    s_feed[axis].held = held ? 1 : 0;
    s_feed[axis].started = 0;
}

static int32_t position_now(AxisState &s)
{
    const AxisSlot *t = s.cur;
    int32_t made;
    if (!s.running)
        return s.pos_rest;
    /* the steps of the current command armed or computed, less the armed one not made yet (in ahead
     * form also the one computed after it: -1 when that is the command's first, the step armed being
     * the last of the one before, in the same direction) */
    made = (int32_t)(uint16_t)(t->left - s.left) - (looked_ahead(s) ? 1 : 0);
    return t->p_start + ((t->flags & _BV(AXIS_SLOT_FORWARD)) ? made : -made);
}

void MultiStepEngine::halt(uint8_t axis)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    int32_t at;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        hw_stop(axis);
    }
    /* its interrupt is off (it cannot be running: loop() is): its state stays as it is, so its
     * position is worked out with interrupts on, and the stretch below (which other axes' edges wait
     * for, as the core's interrupts that may come just before it) stays short */
    at = position_now(s);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        s.pos_rest = at;
        s.running = 0;
        s.finishing = 0;
        s.wraps = 0;
        change_mode(s, 0, _BV(AXIS_MODE_WAITING) | _BV(AXIS_MODE_SLOW) | AXIS_MODE_DEFER_ALL);
        if (f.open)
            s.done = 1;
        f.held = 0;
        step_low(axis);
    }
    /* its interrupt is off now, so nothing reads its slots: emptied with interrupts on (done inside
     * the block above, the loop held the other axes' edges back by up to 1,300 cycles: the fuzzer's
     * late edges at every `!`) */
    for (uint8_t i = 0; i < f.nslots; i++)
        s.slot[i].ready = 0;
    f.head = next_slot(f, cur_index(s));
    f.seen = f.head;
    f.ready = 0;
    f.queued_ticks = 0;
}

bool MultiStepEngine::moving(uint8_t axis)
{
    return s_feed[axis].open != 0;
}

bool MultiStepEngine::held(uint8_t axis)
{
    return s_feed[axis].held != 0;
}

int32_t MultiStepEngine::position(uint8_t axis)
{
    int32_t p;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        p = position_now(state(axis));
    }
    return p;
}

uint8_t MultiStepEngine::phase(uint8_t axis)
{
    uint8_t ph = 0;
    AxisState &s = state(axis);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        if (s.running)
            ph = (uint8_t)((s.cur->flags >> AXIS_SLOT_PHASE_SHIFT) & 3U);
    }
    return ph;
}

uint16_t MultiStepEngine::underruns(uint8_t axis)
{
    uint16_t n;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        n = state(axis).underruns;
    }
    return n;
}

uint16_t MultiStepEngine::late_edges(uint8_t axis)
{
    uint16_t n;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        n = state(axis).late;
    }
    return n;
}

bool MultiStepEngine::done_pending(uint8_t axis)
{
    poll(); /* as take_done: the timed-loop build steps here */
    return state(axis).done != 0;
}

bool MultiStepEngine::take_done(uint8_t axis, int32_t &position)
{
    bool done;
    poll();
    if (!state(axis).done)
        return false; /* one byte, read with interrupts on: loop() asks on every pass */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        done = take_end(axis, position);
    }
    return done;
}

void MultiStepEngine::set_direction_hook(uint8_t axis, DirectionHook hook)
{
    if (axis >= MULTI_AXES)
        return;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        s_dir_hook[axis] = hook;
    }
}

void MultiStepEngine::set_led_mirror(bool on)
{
    if (on) {
        MULTI_LED_DDR |= _BV(MULTI_LED_BIT);
        GPIOR0 |= _BV(MULTI_G_LED_X); /* sbi: one instruction, atomic */
    } else {
        GPIOR0 &= (uint8_t)~_BV(MULTI_G_LED_X);
    }
}

void MultiStepEngine::set_lead_ms(uint16_t ms)
{
    uint32_t t = s_tick_hz / 1000UL * (ms ? ms : 1U);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        s_lead_ticks = t;
    }
}

float MultiStepEngine::speed(uint8_t axis)
{
    AxisState &s = state(axis);
    uint32_t rate;
    uint8_t flags, running;
    float v;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        rate = s.rate;
        flags = s.flags;
        running = s.running;
    }
    if (!running || rate == 0)
        return 0.0f;
    /* rate: the interval armed last, 16.16 ticks (WIDE: whole ticks) */
    v = (flags & _BV(AXIS_SLOT_WIDE)) ? (float)s_tick_hz / (float)rate : (float)s_tick_hz * 65536.0f / (float)rate;
    return (flags & _BV(AXIS_SLOT_FORWARD)) ? v : -v;
}

/* ---- cutting the queue (see MultiStepEngine.h) ---- */
namespace {

inline uint32_t slot_count(const AxisSlot &t)
{
    return (uint32_t)t.left + 1U;
}

/* a b exactly: in 32 bits when it fits there (a command's time is below 65536 ticks as a rule),
 * avr-gcc's 64-bit multiplication (several hundred cycles) otherwise */
uint64_t mul32x32(uint32_t a, uint32_t b)
{
    if (b < 0x10000UL && ((a >> 16) + 1U) * b <= 0x10000UL)
        return a * b; /* a < ((a >> 16) + 1) 2^16: below 2^32 */
    return (uint64_t)a * b;
}

/* the time slot t's command takes in the executor, 2^-16 ticks (step_exec_next adds rate, then add,
 * count times: count rate + add count (count - 1)/2; WIDE: count whole intervals) */
int64_t slot_time16(const AxisSlot &t)
{
    uint32_t l = slot_count(t), tri;
    int64_t sum;
    if (t.flags & _BV(AXIS_SLOT_WIDE))
        return (int64_t)(mul32x32(t.rate, l) << 16);
    /* laid out less add: the command's rate is t.rate + add */
    sum = (int64_t)mul32x32(t.rate + (uint32_t)t.add, l);
    if (t.add != 0) {
        tri = l * (l - 1U) / 2U;
        if (t.add > 0)
            sum += (int64_t)mul32x32((uint32_t)t.add, tri);
        else
            sum -= (int64_t)mul32x32(0U - (uint32_t)t.add, tri);
    }
    return sum;
}

/* a b, both below 2^16, in four hardware multiplications (some 20 cycles: avr-gcc made this
 * product, after inlining, a call of its 32-bit __mulsi3, some 60) */
inline uint32_t mul16(uint16_t a, uint16_t b)
{
    uint32_t p;
    __asm__("mul %A1, %A2\n\t"
            "movw %A0, r0\n\t"
            "mul %B1, %B2\n\t"
            "movw %C0, r0\n\t"
            "mul %B1, %A2\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "clr __zero_reg__\n\t"
            "adc %D0, __zero_reg__\n\t"
            "mul %A1, %B2\n\t"
            "add %B0, r0\n\t"
            "adc %C0, r1\n\t"
            "clr __zero_reg__\n\t"
            "adc %D0, __zero_reg__"
            : "=&r"(p)
            : "r"(a), "r"(b));
    return p;
}

/* the time slots from..to (not to) take in the executor, 2^-16 ticks: slot_time16's sum, from 16-bit
 * products and 32-bit sums (ticks, and what lies below them with its carries moved up); a WIDE slot,
 * one of 65536 steps and a ramp's of more than 361 (its count (count - 1)/2 beyond 16 bits) through
 * slot_time16. slot_time16's 64-bit products and sums over the queue dropped at a cut (some 50 ramp
 * commands of a slow acceleration under a 100 ms lead) cost about 2.5 ms per axis: three Steppers'
 * group stop at 10,000 steps/s then left the planner some 1.5 ms of queue to catch up with the stop's
 * commands, and it ran dry. Exact while the sum stays below 2^32 ticks (the lead holds 100 ms, one
 * command at most some 2^28 ticks). */
int64_t queue_time16(const AxisState &s, const AxisFeed &f, uint8_t from, uint8_t to)
{
    uint32_t ticks = 0, below = 0;
    int64_t big = 0;
    for (uint8_t i = from; i != to; i = next_slot(f, i)) {
        const AxisSlot &t = s.slot[i];
        const uint16_t n1 = t.left; /* count - 1 */
        const int32_t add = t.add;
        if ((t.flags & _BV(AXIS_SLOT_WIDE)) || n1 == 0xFFFFU || (add != 0 && n1 > 361U)) {
            big += slot_time16(t);
            continue;
        }
        const uint16_t l = (uint16_t)(n1 + 1U);
        const uint32_t r = t.rate + (uint32_t)add; /* laid out less add */
        const uint32_t p = mul16((uint16_t)r, l);
        ticks += mul16((uint16_t)(r >> 16), l);
        below += p;
        if (below < p)
            ticks += 0x10000UL;
        if (add != 0) {
            const uint16_t tri = (uint16_t)(mul16(l, n1) >> 1);
            const uint32_t m = add > 0 ? (uint32_t)add : 0U - (uint32_t)add;
            const uint32_t lo = mul16((uint16_t)m, tri), hi = mul16((uint16_t)(m >> 16), tri);
            if (add > 0) {
                ticks += hi;
                below += lo;
                if (below < lo)
                    ticks += 0x10000UL;
            } else {
                ticks -= hi;
                if (below < lo)
                    ticks -= 0x10000UL;
                below -= lo;
            }
        }
    }
    /* the sum of whole commands is not negative: ticks (modulo 2^32) then its whole ticks */
    ticks += below >> 16;
    return ((int64_t)ticks << 16) + (int64_t)(below & 0xFFFFUL) + big;
}
} // namespace

/* the time from the edge armed now to the first step of slot `to`, ticks (UINT32_MAX: not before it,
 * or the interrupt has taken it already); cur: its current slot */
static __attribute__((noinline)) uint32_t ticks_until(uint8_t axis, uint8_t to)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    uint8_t curi, i, running;
    uint32_t left;
    uint32_t rate, per, ahead;
    bool wide;
    AxisSlot *cp;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        cp = s.cur; /* its index (slot_index) with interrupts on */
        left = (uint32_t)s.left + (looked_ahead(s) ? 1U : 0U); /* ahead form: one computed, not armed */
        rate = s.rate + (uint32_t)s.add; /* the next interval */
        wide = (s.flags & _BV(AXIS_SLOT_WIDE)) != 0;
        running = s.running && !f.held && s.slot[to].ready;
    }
    if (!running)
        return UINT32_MAX;
    curi = slot_index(s, cp);
    /* the current command's steps not armed yet, then the slots between */
    per = wide ? rate : (rate >> 16);
    /* (slow steps: a whole interval or more counts as far, but none left is none: the next slot
     * then starts one interval after the armed edge, and at 100 steps/s a cut there raced the
     * interrupt: make fuzz seed 8, a step 6 ms late) */
    ahead = left == 0 ? 0 : per > 0xFFFFUL ? 0xFFFFFFUL : left * per;
    for (i = next_slot(f, curi); i != to; i = next_slot(f, i))
        ahead += lead_weight(f.duration[i]);
    return ahead;
}

/* the modes in which the current slot is not split: its steps are not made by the common path */
#define SPLIT_MODES (_BV(AXIS_MODE_SLOW) | _BV(AXIS_MODE_WAITING) | _BV(AXIS_MODE_DEFER) | _BV(AXIS_MODE_MASKED))

/* a / b, b > 0: in 16 bits when a fits there (a cut's distance in ticks and an interval as a rule; a
 * 32-bit division costs the AVR some 570 cycles, a 16-bit one some 220, and a cut's search and
 * check take one each before the cut comes off) */
static inline uint32_t div_by(uint32_t a, uint32_t b)
{
    if (a <= 0xFFFFUL && b <= 0xFFFFUL)
        return (uint16_t)a / (uint16_t)b;
    return a / b;
}

/* the smallest interval of slot t's first `kept` steps, whole ticks (its intervals change linearly: the
 * first one's or the last one's; a split slot is not WIDE) */
static uint32_t split_per(const AxisSlot &t, uint32_t kept)
{
    uint32_t first = t.rate + (uint32_t)t.add, last = t.rate + (uint32_t)t.add * kept;
    return (first < last ? first : last) >> 16;
}

/* cut_find's split: how many steps of slot p to drop (0: none), so that its first step dropped lies
 * beyond min_ticks ahead of the edge armed now, p's j-th step lying `before` + the sum of its first j
 * intervals ahead (before = 0: p is the current slot, whose j-th step not armed is the j-th counted).
 * A slot stepped by the interrupt's common path (not slow, not WIDE) in a build with step interrupts:
 * a cruise's (constant intervals) and, since 2026-12-06, a ramp's (rate and add: lib's
 * step_exact_rewind takes back to any of its steps; until then a stop while accelerating was cut at
 * the next command's start, up to 128 steps farther); the current one only in ahead form and on the
 * common path, keeping at least the step computed already. */
static __attribute__((noinline)) uint16_t split_at(uint8_t axis, uint8_t p, uint32_t before, uint32_t min_ticks)
{
    AxisState &s = state(axis);
    const AxisSlot &t = s.slot[p];
    uint32_t n, per, keep, rate;
    /* (before == min_ticks: the step before p lies exactly at the cut's distance, as when 600 us are six
     * intervals at 10,000 steps/s and six steps are left of the one before; p is split after its first
     * step then: until 2026-12-06 it was not split, and the stop waited for the next 4 ms command) */
    if (MULTI_TIMED_LOOP || (t.flags & (_BV(AXIS_SLOT_SLOW) | _BV(AXIS_SLOT_WIDE))) || min_ticks < before)
        return 0;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        rate = t.rate; /* the interval before its first step's, 16.16 (laid out less add) */
        if (s.cur == &t) {
            n = (looked_ahead(s) && !(s.mode & SPLIT_MODES)) ? (uint32_t)s.left + 1U : 0U; /* the steps not armed */
            rate = s.rate - (uint32_t)t.add; /* the step computed already has s.rate */
        } else {
            n = t.ready ? slot_count(t) : 0U;
        }
    }
    if (t.flags & _BV(AXIS_SLOT_HAS_ADD)) {
        /* the steps whose intervals add up to at most min_ticks - before (a ramp's: up to 128) */
        uint32_t lim = min_ticks - before;
        for (keep = 0; keep < n; keep++) {
            rate += (uint32_t)t.add;
            if ((rate >> 16) > lim)
                break;
            lim -= rate >> 16;
        }
    } else {
        per = t.rate >> 16;
        if (per == 0)
            return 0;
        keep = div_by(min_ticks - before, per);
    }
    if (keep == 0)
        keep = 1;
    n = keep < n ? n - keep : 0U; /* the steps to drop */
    /* a ramp's command keeps two steps at least: lib's rewind takes a command kept to its first step as
     * one whose span did not fit (single steps from there on; make fuzz seed 31, MultiAxisStepper: a
     * deceleration in one-step commands, 107 underruns) */
    if ((t.flags & _BV(AXIS_SLOT_HAS_ADD)) && n + 2U > slot_count(t))
        n = slot_count(t) >= 2U ? slot_count(t) - 2U : 0U;
    return (uint16_t)n;
}

uint8_t MultiStepEngine::cut_find(uint8_t axis, uint32_t min_ticks_ahead, uint32_t max_steps, Cut &r, bool time16,
                                  bool split)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    uint8_t curi, i, first;
    uint32_t ahead, steps;
    r.steps = 0;
    r.time16 = 0;
    r.last_count = 0;
    r.split = 0;
    r.cmds = 0;
    r.first = 0;
    if (axis >= MULTI_AXES)
        return 0;
    retire_consumed(s, f);
    curi = cur_index(s);
    i = next_slot(f, curi);
    if (i == f.head)
        return 0; /* nothing queued after the current slot (one the interrupt took meanwhile: below) */
    /* The steps of every slot after the current one first, along the ring's links (an index walk
     * over a ring of 40 commands took 0.6 ms with two Steppers at 20,000 steps/s stepping
     * meanwhile: the link walk takes a third of that, and a running count kept by every lay-out
     * cost more flash than SCurveStepper's bound left): the cut is chosen after this loop, so that
     * the time from its choice to cut_apply's check of it stays short (a cut 600 us ahead, checked
     * 200 us before it, never came off: test/emu/ThreeSteppers). The slots the interrupt takes
     * meanwhile are before the cut, which lies beyond them. */
    steps = 0;
    for (const AxisSlot *t = &s.slot[i], *h = &s.slot[f.head]; t != h; t = t->other)
        steps += slot_count(*t);
    first = i;
    for (uint8_t again = 0;; again++) {
        /* less the slots the interrupt has taken meanwhile (their steps are not dropped) */
        i = next_slot(f, cur_index(s));
        for (; first != i; first = next_slot(f, first)) {
            if (first == f.head)
                return 0; /* it has taken every slot */
            steps -= slot_count(s.slot[first]);
        }
        if (i == f.head)
            return 0;
#ifdef MULTI_TEST_CUT_FIND_WAIT_US
        if (again == 0) /* a test build's wait (tools/emu/emu.mk, two-20k-race): the interrupt takes slot i */
            _delay_us(MULTI_TEST_CUT_FIND_WAIT_US);
#endif
        /* the time to slot i's first step; UINT32_MAX: not running, or the interrupt took slot i
         * since (it switches slots every millisecond or so in a cruise; a slot it took is no longer
         * ready, and cur_index may have been read just before it switched): then once more from the
         * slot after it (until 2026-12-06 such a search gave up, and a stop planned ahead with it:
         * with two Steppers at 20,000 steps/s and every first cut too close, a layout of the Stepper's
         * fields, then one of the heap, made it come at every stop's second try, and every stop waited
         * for the 40 ms lead) */
        ahead = s.slot[i].ready ? ticks_until(axis, i) : UINT32_MAX;
        if (ahead != UINT32_MAX)
            break;
        if (again != 0 || !s.running)
            return 0;
    }
    /* the first slot whose first step lies beyond min_ticks_ahead; before: the time to the step
     * before the slot ahead of it (0: that slot is the current one) */
    uint32_t before = 0;
    while (ahead <= min_ticks_ahead) {
        before = ahead;
        ahead += lead_weight(f.duration[i]);
        steps -= slot_count(s.slot[i]);
        i = next_slot(f, i);
        if (i == f.head) {
            if (!split)
                return 0;
            break; /* the last slot may still be split */
        }
    }
    if (split)
        r.split = split_at(axis, prev_slot(f, i), before, min_ticks_ahead);
    steps += r.split;
    if (steps > max_steps) {
        steps -= r.split; /* whole commands only */
        r.split = 0;
    }
    first = i;
    /* at most max_steps steps: keep more from the front */
    while (first != f.head && steps > max_steps) {
        steps -= slot_count(s.slot[first]);
        first = next_slot(f, first);
    }
    if (first == f.head && r.split == 0)
        return 0;
    r.cmds = (uint8_t)(f.head >= first ? f.head - first : f.head + f.nslots - first);
    if (time16)
        r.time16 = queue_time16(s, f, first, f.head);
    const AxisSlot &p = s.slot[prev_slot(f, first)];
    if (r.split && time16) {
        /* the steps dropped of p, kept + 1 to count: split rate + add (kept + 1 + count) split / 2 (a
         * whole number: a sum of the step numbers) */
        uint32_t count = slot_count(p), sum = count - r.split + 1U + count, tri;
        tri = (r.split & 1U) ? r.split * (sum / 2U) : (r.split / 2U) * sum; /* (a ramp's: up to 128 steps) */
        r.time16 += (int64_t)mul32x32(p.rate, r.split);
        if (p.add > 0)
            r.time16 += (int64_t)mul32x32((uint32_t)p.add, tri);
        else if (p.add < 0)
            r.time16 -= (int64_t)mul32x32(0U - (uint32_t)p.add, tri);
    }
    r.steps = steps;
    r.last_count = (uint16_t)(slot_count(p) - r.split);
    r.first = first;
    return (uint8_t)(r.cmds + (r.split ? 1U : 0U));
}

/* cut_find's cut moved later, to where exactly `drop` steps are dropped (a StepperGroup's stop in the
 * cruise: each axis is cut where its own stop from the cruise ends on the line): the slots kept whole
 * up to the one that holds that point, which is split there (a cruise's: not slow, not WIDE, no add).
 * 0 when the first cut beyond min_ticks_ahead drops fewer steps (the point lies too close) or the
 * point lies in a slot that cannot be split. No time sum (time16 = 0). */
uint8_t MultiStepEngine::cut_find_at(uint8_t axis, uint32_t min_ticks_ahead, uint32_t drop, Cut &r, bool ramp)
{
    const uint8_t no_split = (uint8_t)(_BV(AXIS_SLOT_SLOW) | _BV(AXIS_SLOT_WIDE) | (ramp ? 0U : _BV(AXIS_SLOT_HAS_ADD)));
    if (drop == 0 || cut_find(axis, min_ticks_ahead, UINT32_MAX, r, false, true) == 0 || r.steps < drop)
        return 0;
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    uint32_t excess = r.steps - drop;
    if (excess != 0 && r.split != 0) {
        /* keep more of the slot split */
        uint16_t less = excess < r.split ? (uint16_t)excess : r.split;
        r.split = (uint16_t)(r.split - less);
        r.last_count = (uint16_t)(r.last_count + less);
        excess -= less;
    }
    while (excess != 0) {
        /* keep slot `first` whole, or its first `excess` steps */
        if (r.first == f.head || r.cmds == 0)
            return 0;
        const AxisSlot &q = s.slot[r.first];
        uint32_t c = slot_count(q);
        r.first = next_slot(f, r.first);
        r.cmds--;
        if (c > excess) {
            if (q.flags & no_split)
                return 0;
            r.split = (uint16_t)(c - excess);
            r.last_count = (uint16_t)excess;
            excess = 0;
        } else {
            r.split = 0;
            r.last_count = (uint16_t)c;
            excess -= c;
        }
    }
    r.steps = drop;
    return (uint8_t)(r.cmds + (r.split ? 1U : 0U));
}

__attribute__((noinline)) uint8_t MultiStepEngine::cut_mirror(uint8_t axis, const Cut &r, step_cmd_t *c, uint8_t max, uint32_t max_steps,
                                    uint32_t min_ticks, uint32_t &steps)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    const uint8_t accel = (uint8_t)(RAMP_ACCEL << AXIS_SLOT_PHASE_SHIFT), ph_mask = (uint8_t)(3U << AXIS_SLOT_PHASE_SHIFT);
    uint8_t i, k = 0;
    uint32_t ticks = 0, count = r.last_count;
    int32_t start;
    steps = 0;
    if (axis >= MULTI_AXES || (r.cmds == 0 && r.split == 0) || MULTI_TIMED_LOOP)
        return 0;
    i = prev_slot(f, r.first); /* the last slot kept, of which r.last_count steps */
    start = s.slot[i].p_start;
    for (;;) {
        const AxisSlot &t = s.slot[i];
        uint32_t last, per;
        /* the acceleration's commands only, in one direction (a slot the ring has reused, or one of a
         * move before, breaks the chain of positions below, or the phase) */
        if ((t.flags & ph_mask) != accel || steps + count > max_steps)
            break;
        step_cmd_t &m = c[k];
        m.count = (uint16_t)count;
        m.flags = (uint8_t)(((t.flags & _BV(AXIS_SLOT_FORWARD)) ? 0U : STEP_CMD_REVERSE) |
                            ((uint8_t)RAMP_DECEL << STEP_CMD_PHASE_SHIFT));
        if (t.flags & _BV(AXIS_SLOT_WIDE)) {
            m.flags |= STEP_CMD_WIDE;
            m.rate = t.rate; /* whole ticks, every interval the same */
            m.add = 0;
            per = t.rate;
        } else {
            /* the intervals t.rate + j add, j = 1..count (laid out less add), from the last */
            last = t.rate + (uint32_t)t.add * count;
            m.rate = last;
            m.add = -t.add;
            /* the mean interval, ticks: (last >> 17) + (first >> 17), each as its upper half shifted
             * once (a 32-bit shift by 17 is a loop of 17 on the AVR: 120 cycles) */
            per = (uint32_t)((uint16_t)(last >> 16) >> 1) + ((uint16_t)((t.rate + (uint32_t)t.add) >> 16) >> 1);
        }
        ticks += per * count;
        steps += count;
        k++;
        if (ticks >= min_ticks || k == max)
            break;
        /* the command before: the slot before in the ring, if it is the one laid out before this one
         * (its positions end where this one's start; a split slot counts what it kept) */
        uint8_t b = prev_slot(f, i);
        if (b == f.head)
            break;
        const AxisSlot &u = s.slot[b];
        count = slot_count(u);
        if (u.p_start + ((u.flags & _BV(AXIS_SLOT_FORWARD)) ? (int32_t)count : -(int32_t)count) != start)
            break;
        start = u.p_start;
        i = b;
    }
    if (ticks < min_ticks) {
        steps = 0;
        return 0; /* not enough to plan the rest meanwhile */
    }
    return k;
}

/* a slot's command (its ready flag and ring link stay) */
static inline void copy_slot(AxisSlot &t, const AxisSlot &c)
{
    t.rate = c.rate;
    t.add = c.add;
    t.left = c.left;
    t.flags = c.flags;
    t.p_start = c.p_start;
}

/* cut_apply's switch, with interrupts off (kept short: an edge due meanwhile waits for it; its own
 * function, so that its few values are in registers, not in cut_apply's frame): slot t becomes
 * c[0] (img0) if the interrupt has not taken it (cmds dropped from it on: it is ready; none: it
 * is the free slot after the last one), after it the slot `after` stops being ready (more than one
 * dropped); with split, slot q (the last kept) first loses its last split steps: if it is the
 * current one, only if the interrupt's count is still at least lim and it steps on the common
 * path (ahead form). Returns whether it was done (else nothing changed). */
static __attribute__((noinline)) uint8_t cut_switch(AxisState &s, AxisSlot &t, AxisSlot &q, AxisSlot &after,
                                                    const AxisSlot &img0, uint8_t cmds, uint16_t split, uint16_t lim)
{
    uint8_t ok;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        ok = cmds ? t.ready : (uint8_t)(!t.ready && &t != s.cur);
        if (ok && split) {
            if (s.cur == &q) {
                ok = s.running && !(s.mode & SPLIT_MODES) && s.left >= lim;
                if (ok)
                    s.left = (uint16_t)(s.left - split);
            } else {
                ok = q.ready;
            }
            if (ok)
                q.left = (uint16_t)(q.left - split);
        }
        if (ok) {
            copy_slot(t, img0);
            if (cmds > 1U)
                after.ready = 0;
            if (cmds == 0)
                t.ready = 1; /* a slot after the last one (written with interrupts off: no fence needed) */
            s.finishing = 0; /* the move goes on with c */
        }
    }
    return ok;
}

uint32_t MultiStepEngine::make_image(const step_cmd_t &c, SlotImage &m, int32_t &p_off)
{
    m.rate = (c.flags & STEP_CMD_WIDE) ? c.rate : c.rate - (uint32_t)c.add; /* as lay_out */
    m.add = c.add;
    m.left = c.count - 1U;
    m.flags = slot_flags(c);
    m.dur = duration_ticks(c);
    m.p_off = p_off;
    p_off += (c.flags & STEP_CMD_REVERSE) ? -(int32_t)c.count : (int32_t)c.count;
    return ((c.flags & STEP_CMD_WIDE) ? c.rate : (c.rate >> 16)) * c.count;
}

/* slot t gets image m: its first step after position pos0 + m.p_off, turning if its direction is not
 * that of the command before (forward: that one's; then: m's) */
static inline void put_image(AxisSlot &t, const MultiStepEngine::SlotImage &m, int32_t pos0, uint8_t &forward, bool hook)
{
    uint8_t fl = m.flags, fw = (fl & _BV(AXIS_SLOT_FORWARD)) ? 1U : 0U;
    if (fw != forward)
        fl |= hook ? (uint8_t)(_BV(AXIS_SLOT_TURN) | _BV(AXIS_SLOT_SLOW)) : (uint8_t)_BV(AXIS_SLOT_TURN); /* hook: the C path turns it */
    forward = fw;
    t.rate = m.rate;
    t.add = m.add;
    t.left = m.left;
    t.flags = fl;
    t.p_start = pos0 + m.p_off;
}

bool MultiStepEngine::cut_fits(uint8_t axis, const Cut &r, uint8_t n)
{
    if (axis >= MULTI_AXES)
        return false;
    const AxisFeed &f = s_feed[axis];
    return (uint16_t)(f.ready - r.cmds + n) < f.nslots - 1U;
}

/* cut_apply's first half: img[0..n-1] switched in at the cut (made off the ring, before the check; the
 * ring's room checked for n_all commands); tail: what finish_cut, the second half, needs */
static __attribute__((noinline)) bool apply_cut(uint8_t axis, const MultiStepEngine::Cut &r, uint32_t min_ticks_left,
                                                const MultiStepEngine::SlotImage *img, uint8_t n, uint8_t n_all,
                                                MultiStepEngine::CutTail &tail)
{
    if (axis >= MULTI_AXES || (r.cmds == 0 && r.split == 0) || n == 0)
        return false;
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    const bool hook = s_dir_hook[axis] != 0;
    AxisSlot img0;
    uint8_t k, i, ok, forward;
    uint32_t left;
    const uint8_t p = prev_slot(f, r.first); /* the last slot kept (split: what is kept of it) */
    AxisSlot &q = s.slot[p];
    /* (a split slot is not slow: an interval below 2^15 ticks, and a count below 2^16; with an add, its
     * smallest interval of the kept steps: the time left and the steps kept for the margin reckoned
     * with it are at most the true ones) */
    const uint16_t kept = (uint16_t)(slot_count(q) - r.split), per = (uint16_t)split_per(q, kept);
    /* the images' slots follow the kept ones: their positions and direction go on from there. The
     * images were made off the ring first: the switch below is then a copy of a few bytes, done
     * where the interrupt cannot come between (laying the commands out in place took up to 4,000
     * cycles after the margin was checked, and the interrupt, reaching the cut meanwhile, found the
     * first new slot not ready: `make fuzz` seed 23, ExactRampStepper, a step 8.1 ms late after a
     * reversal cut at 7,300 steps/s) */
    const uint8_t fw_kept = (q.flags & _BV(AXIS_SLOT_FORWARD)) ? 1U : 0U;
    const int32_t pos0 = r.split == 0 ? s.slot[r.first].p_start : q.p_start + (fw_kept ? (int32_t)kept : -(int32_t)kept);
    forward = fw_kept;
    put_image(img0, img[0], pos0, forward, hook);
    /* the interrupt must still be that far from the cut: else the planning took too long, and the
     * queue stays as it was */
    if (r.split == 0) {
        left = ticks_until(axis, r.first);
    } else {
        /* the time to the first step dropped of slot p: checked again below if it is the current one */
        left = s.cur == &q ? 0U : ticks_until(axis, p);
        if (left == UINT32_MAX && s.cur == &q)
            left = 0U; /* the interrupt has taken it since */
        left = left == UINT32_MAX ? left : left + (uint32_t)kept * per;
    }
    if (left == UINT32_MAX || left < min_ticks_left || !MultiStepEngine::cut_fits(axis, r, n_all))
        return false;
    /* a split of the current slot: the interrupt's count must still be at least lim (the dropped steps,
     * and enough kept before them for min_ticks_left), worked out here: the switch below is short */
    uint32_t lim = 0;
    if (r.split) {
        uint32_t kmin = div_by(min_ticks_left + per - 1U, per); /* steps kept, at least the one computed */
        lim = (uint32_t)r.split + (kmin ? kmin : 1U) - 1U;
        if (lim > 0xFFFFU)
            lim = 0xFFFFU;
    }
    const uint16_t lim16 = (uint16_t)lim;
    AxisSlot &t0 = s.slot[r.first];
    /* the switch: the first dropped slot becomes img[0] in one piece if the interrupt has not taken it
     * (then it has taken none after it either), and the slot after it stops being ready. From then
     * on the ready slots after the cut are the images' alone: each next slot is made not ready before
     * the one before it becomes ready with its command, img[1] first (a one-step img[0] gives the
     * interrupt two intervals before it must take img[1]) */
    i = next_slot(f, r.first);
    ok = cut_switch(s, t0, q, s.slot[i], img0, r.cmds, r.split, lim16);
    if (!ok)
        return false; /* nothing changed */
    for (k = 1; k < n; k++, i = next_slot(f, i)) {
        if ((uint8_t)(k + 1U) < r.cmds)
            s.slot[next_slot(f, i)].ready = 0;
        put_image(s.slot[i], img[k], pos0, forward, hook);
        __asm__ __volatile__("" ::: "memory"); /* the fields stored before the flag */
        s.slot[i].ready = 1; /* one byte, written last */
    }
    /* the rest (cut_finish): the slot at i, after the images, is not ready, so the interrupt stops
     * there at the latest, and the other dropped slots beyond it wait */
    const MultiStepEngine::SlotImage &last = img[n - 1U];
    tail.first = r.first;
    tail.cmds = r.cmds;
    tail.n = n;
    tail.next = i;
    tail.forward = forward;
    tail.dur_p = 0xFFFFU;
    if (r.split) {
        uint32_t d = ((uint32_t)kept * per) >> DUR_SHIFT;
        tail.dur_p = d > 0xFFFEU ? 0xFFFEU : (uint16_t)d;
    }
    tail.pos_end = pos0 + last.p_off + ((last.flags & _BV(AXIS_SLOT_FORWARD)) ? (int32_t)last.left + 1 : -(int32_t)last.left - 1);
    return true;
}

/* the second half of a cut: the dropped slots beyond the images made not ready, the engine's books
 * without them and with the images' (img: the ones the switch put in, tail.n of them) */
static void finish_cut(uint8_t axis, const MultiStepEngine::CutTail &tail, const MultiStepEngine::SlotImage *img)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    uint8_t k, i;
    uint32_t ticks = 0;
    /* the other dropped slots (none can be taken now: the one at tail.next is not ready), along the
     * ring's links (a lead of 100 ms holds tens of them) */
    AxisSlot *d = &s.slot[tail.next];
    for (k = tail.n + 1U; k < tail.cmds; k++) {
        d = d->other;
        d->ready = 0;
    }
    /* what the slots before the cut hold (a few; the ring's dropped slots are not walked) */
    for (i = f.seen; i != tail.first; i = next_slot(f, i))
        ticks += lead_weight(f.duration[i]);
    if (tail.dur_p != 0xFFFFU) {
        const uint8_t p = prev_slot(f, tail.first); /* split: what is kept of it */
        ticks -= lead_weight(f.duration[p]);
        f.duration[p] = tail.dur_p;
        ticks += lead_weight(f.duration[p]);
    }
    for (k = 0, i = tail.first; k < tail.n; k++, i = next_slot(f, i)) {
        f.duration[i] = img[k].dur;
        ticks += lead_weight(img[k].dur);
    }
    f.queued_ticks = ticks;
    f.ready = (uint8_t)(f.ready - tail.cmds + tail.n);
    f.head = i;
    f.next_p_start = tail.pos_end;
    f.last_forward = tail.forward;
}

bool MultiStepEngine::cut_apply(uint8_t axis, const Cut &r, uint32_t min_ticks_left, const step_cmd_t *c, uint8_t n)
{
    /* the first MULTI_CUT_MAX_CMDS made into images before the check (the switch puts them in place) */
    SlotImage img[MULTI_CUT_MAX_CMDS];
    CutTail tail;
    const uint8_t m = n < MULTI_CUT_MAX_CMDS ? n : (uint8_t)MULTI_CUT_MAX_CMDS;
    int32_t off = 0;
    for (uint8_t k = 0; k < m; k++)
        (void)make_image(c[k], img[k], off);
    if (!apply_cut(axis, r, min_ticks_left, img, m, n, tail))
        return false;
    finish_cut(axis, tail, img);
    /* the commands beyond the images, after the ones just made ready (the ring has room: apply_cut) */
    AxisState &s = state(axis);
    for (uint8_t k = m; k < n; k++)
        lay_one(axis, s, s_feed[axis], c[k]);
    return true;
}

bool MultiStepEngine::cut_apply(uint8_t axis, const Cut &r, uint32_t min_ticks_left, const SlotImage *img, uint8_t n,
                                uint8_t now, CutTail &tail)
{
    if (axis >= MULTI_AXES || now == 0)
        return false;
    return apply_cut(axis, r, min_ticks_left, img, now < n ? now : n, n, tail);
}

void MultiStepEngine::cut_finish(uint8_t axis, const CutTail &tail, const SlotImage *img, uint8_t n)
{
    finish_cut(axis, tail, img);
    if (n > tail.n)
        append_images(axis, img + tail.n, (uint8_t)(n - tail.n));
}

void MultiStepEngine::append_images(uint8_t axis, const SlotImage *img, uint8_t n)
{
    AxisState &s = state(axis);
    AxisFeed &f = s_feed[axis];
    const bool hook = s_dir_hook[axis] != 0;
    uint8_t forward = f.last_forward;
    if (n == 0)
        return;
    const int32_t pos0 = f.next_p_start - img[0].p_off; /* they go on where the queue ends */
    for (uint8_t k = 0; k < n; k++) {
        AxisSlot &t = s.slot[f.head];
        put_image(t, img[k], pos0, forward, hook);
        f.duration[f.head] = img[k].dur;
        f.queued_ticks += lead_weight(img[k].dur);
        f.ready++;
        __asm__ __volatile__("" ::: "memory"); /* the fields stored before the flag */
        t.ready = 1; /* one byte, written last */
        f.head = next_slot(f, f.head);
    }
    const SlotImage &last = img[n - 1U];
    f.next_p_start = pos0 + last.p_off + ((last.flags & _BV(AXIS_SLOT_FORWARD)) ? (int32_t)last.left + 1 : -(int32_t)last.left - 1);
    f.last_forward = forward;
}
