/* StepCut.cpp - a stop or a new target from a cut of the queue (see StepCut.h). */
#include "StepCut.h"

#include <Arduino.h> /* micros */
#include <avr/io.h>
#include <math.h>
#include <util/atomic.h>

#include "MultiStepEngine.h"

#ifndef MOTION_STEPPER_TRACE
#define MOTION_STEPPER_TRACE 0
#endif

static_assert(STEP_CUT_MAX_CMDS <= MultiStepEngine::MULTI_CUT_MAX_CMDS, "cut_apply takes at most MULTI_CUT_MAX_CMDS commands");

/* the cut's scratch: a planner, or a stop's reversed commands (StepperGroup::stop_mirrored), never both
 * at once (each is used within one call of the planner interrupt) */
static union {
    step_planner_t planner;
    step_cmd_t cmds[STEP_CUT_SCRATCH_CMDS];
} s_scratch_u;
static step_planner_t &s_scratch = s_scratch_u.planner;
static step_smooth_t *s_smooth_backup;

step_planner_t &step_cut_scratch()
{
    return s_scratch;
}

step_cmd_t *step_cut_cmds()
{
    return s_scratch_u.cmds;
}

void step_cut_smooth_backup(step_smooth_t *backup)
{
    s_smooth_backup = backup;
}

#if MOTION_STEPPER_CUT_US
/* the planner as it was before the cut (saved: the planner, and a smooth move's own state) */
static void put_back(step_planner_t *pl, const step_planner_t &saved)
{
    *pl = saved;
    if (pl->algo == RAMP_ALGO_SMOOTH)
        *pl->smooth = *s_smooth_backup;
}
#endif

void step_cut_trace(bool on)
{
#if MOTION_STEPPER_TRACE == 2
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        DDRG |= _BV(5); /* the MotionStepper library's planner sets it too; the console does not */
        if (on)
            PORTG |= _BV(5);
        else
            PORTG &= (uint8_t)~_BV(5);
    }
#else
    (void)on;
#endif
}

__attribute__((noinline)) uint8_t step_cut_first_cmds(step_planner_t *pl, step_cmd_t *c, uint8_t ticks_per_us, uint16_t new_us,
                            uint8_t max_cmds)
{
    uint32_t ticks = 0;
    uint8_t n = 0;
    while (n < max_cmds && ticks < (uint32_t)ticks_per_us * new_us &&
           step_planner_next(pl, &c[n])) {
        uint32_t per = (c[n].flags & STEP_CMD_WIDE) ? c[n].rate : (c[n].rate >> 16);
        ticks += per * c[n].count;
        n++;
    }
    return n;
}

/* kept out of step_cut_plan (no inlining): its locals are not on the stack beside the plan's (the
 * sketches' stack is a few hundred bytes deep at most: MultiAxisStepper) */
#if MOTION_STEPPER_CUT_US
static __attribute__((noinline)) motion_status_t rewind_to(step_planner_t *pl, const MultiStepEngine::Cut &cut)
{
    return step_planner_rewind(pl, cut.steps, cut.time16, cut.last_count);
}
#endif

bool step_cut_mirror(uint8_t axis, step_planner_t *pl, const StepCutTiming &t, uint32_t min_us, bool then, int32_t to,
                     int32_t *from, StepCutMirror *rest)
{
#if MOTION_STEPPER_CUT_US && MOTION_STEPPER_CUT_MIRROR_US
    MultiStepEngine::Cut cut;
    step_cmd_t c[STEP_CUT_MIRROR_CMDS];
    uint32_t steps, n;
    uint8_t k, i;
    int32_t at;
    float v = fabs(MultiStepEngine::speed(axis));
    /* a profile with an acceleration (the planner may be in its cruise already, the lead ahead of the
     * axis): the axis may still be accelerating at the cut */
    if (pl->algo != RAMP_ALGO_EXACT || t.ahead_mirror_us == 0 || pl->exact.n1 == 0 || pl->exact.n < 2U ||
        !(v < 0.98f * pl->params.vmax_sps) || /* cruising: no search */
        /* a reversal: the move back from rest is planned when the stop's commands run out, and costs
         * milliseconds (step_cut_plan's rule) */
        (then && (v - pl->params.v0_sps) < pl->params.accel_sps2 * (float)t.then_min_us * 1e-6f))
        return false;
    /* a cut the interrupt came too close to (cut_apply refused it) is tried once more twice as far
     * ahead: the search, the reversal and the lay-out cost a few tenths of a millisecond, where the
     * stop planned instead would take the slow cut */
    for (uint8_t tries = 0;; tries++) {
        if (tries == 2 ||
            MultiStepEngine::cut_find(axis, ((uint32_t)t.ticks_per_us * t.ahead_mirror_us) << tries, pl->exact.n - 1U,
                                      cut, false, true) == 0 ||
            !step_planner_mirror_ok(pl, cut.steps))
            return false;
        at = ramp_position_after(pl->pos, (int8_t)-pl->exact.dir, cut.steps); /* the position at the cut */
        if (then && (pl->exact.dir > 0 ? to >= at : to <= at))
            return false; /* a target ahead of the cut: a plan of its own */
        n = pl->exact.n - cut.steps; /* the step of the profile where the cut lands */
        k = MultiStepEngine::cut_mirror(axis, cut, c, STEP_CUT_MIRROR_CMDS, n - 2U, (uint32_t)t.ticks_per_us * min_us,
                                        steps);
        if (k == 0)
            return false;
        step_cut_trace(true);
        if (MultiStepEngine::cut_apply(axis, cut, (uint32_t)t.ticks_per_us * t.margin_us, c, k))
            break;
        step_cut_trace(false);
    }
    step_cut_trace(false);
    rest->back = cut.steps;
    rest->steps = steps;
    rest->time16 = 0;
    for (i = 0; i < k; i++)
        rest->time16 += step_exact_cmd_time16(&c[i]);
    rest->then = then;
    rest->to = to;
    *from = at;
    return true;
#else
    (void)axis;
    (void)pl;
    (void)t;
    (void)min_us;
    (void)then;
    (void)to;
    (void)from;
    (void)rest;
    return false;
#endif
}

void step_cut_mirror_rest(step_planner_t *pl, const StepCutMirror &rest)
{
    /* (not refused: step_cut_mirror checked step_planner_mirror_ok, and steps <= n - 2) */
    (void)step_planner_stop_mirrored(pl, rest.back, rest.steps, rest.time16);
    if (rest.then) {
        /* the move to the target behind, from rest after the stop (as step_planner_move plans a reversal) */
        pl->target = rest.to;
        pl->has_then = 1;
        pl->then_target = rest.to;
    }
}

bool step_cut_plan(uint8_t axis, step_planner_t *pl, bool stop, int32_t target, const StepCutTiming &t,
                   int32_t *from, uint16_t *missed, uint32_t *retry_us)
{
#if MOTION_STEPPER_CUT_US
    step_planner_t &saved = s_scratch;
    MultiStepEngine::Cut cut;
    step_cmd_t first[STEP_CUT_MAX_CMDS];
    uint8_t n;
    uint32_t ahead_us;
    int32_t at;
    uint32_t reach;
    uint32_t asked = *retry_us; /* a try asked for again (its plan was late before), or 0 */
    *retry_us = 0;               /* set again below only when this try comes too late */
    if (pl->params_new)
        return false; /* new parameters: converting them costs milliseconds more (after the lead then) */
    if (pl->algo == RAMP_ALGO_EXACT) {
        if (pl->exact.n < 2U)
            return false;

        reach = pl->exact.n - 1U; /* all but the profile's first step (step_planner_rewindable) */
        /* a stop from the cruise (y = 0) is the cheapest plan; a stop while the speed changes, or a
         * new target (a move plan, maybe a reversal), costs up to twice as much */
        ahead_us = (stop && pl->exact.y == 0) ? t.ahead_us : t.ahead_slow_us;
    } else if (pl->algo == RAMP_ALGO_SMOOTH && s_smooth_backup && t.ahead_smooth_us) {
        reach = step_planner_rewindable(pl); /* the steps the planner can take back */
        if (reach == 0)
            return false;
        ahead_us = t.ahead_smooth_us;
    } else {
        return false;
    }
    /* the distance of a try asked for again (its plan was late before): farther than the first */
    bool again = asked > ahead_us;
    if (again)
        ahead_us = asked; /* farther than the first */
    uint32_t t0 = micros();
    step_cut_trace(true);
    /* the exact ramp goes back to any step of its cruise: the cut may land inside a cruise command
     * (MultiStepEngine::cut_find's split); elsewhere only between commands (a split there is
     * refused by the rewind: then the cut at the next command) */
    bool split = pl->algo == RAMP_ALGO_EXACT;
    if (MultiStepEngine::cut_find(axis, (uint32_t)t.ticks_per_us * ahead_us, reach, cut, true, split) == 0) {
        if (again)
            (*missed)++; /* a try again found nothing queued that far: it acts after the queued lead */
        step_cut_trace(false);
        return false;
    }
    saved = *pl; /* planned in place: put back if the cut does not come off */
    if (pl->algo == RAMP_ALGO_SMOOTH)
        *s_smooth_backup = *pl->smooth;
    motion_status_t st = rewind_to(pl, cut);
    if (st != MS_OK && cut.split != 0 &&
        MultiStepEngine::cut_find(axis, (uint32_t)t.ticks_per_us * ahead_us, reach, cut) != 0)
        st = rewind_to(pl, cut);
    if (st != MS_OK) {
        (*missed)++;
        step_cut_trace(false);
        return false; /* nothing changed */
    }
    at = step_planner_position(pl);
    if (stop)
        step_planner_stop(pl);
    else if (step_planner_move(pl, target) != MS_OK) {
        put_back(pl, saved); /* planned again the usual way, which reports the status */
        step_cut_trace(false);
        return false;
    }
    if (pl->has_then) {
        /* a reversal: the move from rest is planned when the stop's commands run out, and costs
         * milliseconds; a stop shorter than then_min_us (a high v0: it ends at v0 at once) would
         * leave the queue dry meanwhile (make fuzz seed 8: a 14 ms pause at a reversal at v0 200).
         * Such a target acts after the queued lead instead, as without a cut. */
        float v = fabs(MultiStepEngine::speed(axis));
        float a = pl->params.accel_sps2;
        if (!(a > 0.0f) || (v - (float)pl->params.v0_sps) < a * (float)t.then_min_us * 1e-6f) {
            put_back(pl, saved);
            step_cut_trace(false);
            return false;
        }
    }
    n = step_cut_first_cmds(pl, first, t.ticks_per_us, t.new_us, t.max_cmds < STEP_CUT_MAX_CMDS ? t.max_cmds : STEP_CUT_MAX_CMDS);
    if (n == 0) {
        put_back(pl, saved); /* no command to lay out: planned after the queued steps instead */
        step_cut_trace(false);
        return false;
    }
    if (!MultiStepEngine::cut_apply(axis, cut, (uint32_t)t.ticks_per_us * t.margin_us, first, n)) {
        /* too late: the interrupt came too close to the cut. The caller may try again (at its next
         * pass, the other axes fed meanwhile) at a cut twice as far ahead, and at least twice as far
         * as this try took plus the margin (two Steppers at 20,000 steps/s: such a plan took 4.5-5.5
         * ms, measured with MOTION_STEPPER_TRACE=2; until 2026-12-05 a stop whose 4 ms cut missed
         * waited for the 40 ms lead). */
        put_back(pl, saved);
        step_cut_trace(false);
        t0 = 2U * (micros() - t0) + t.margin_us;
        *retry_us = 2U * ahead_us > t0 ? 2U * ahead_us : t0;
        return false;
    }
    step_cut_trace(false);
    *from = at;
    return true;
#else
    (void)axis;
    (void)pl;
    (void)stop;
    (void)target;
    (void)t;
    (void)from;
    (void)missed;
    *retry_us = 0;
    return false;
#endif
}
