/* StepCut.h - a stop or a new target that acts within milliseconds instead of after the queued
 * lead: the axis's queue is cut a few milliseconds ahead (MultiStepEngine::cut_find), the planner
 * goes back to where the kept commands end (lib's step_planner_rewind: bit for bit as if it had
 * planned only those), plans the stop or the new move from there, and its first commands take the
 * place of the dropped ones (MultiStepEngine::cut_apply) if the step interrupt has not come too
 * close meanwhile. The exact ramp and the smooth move (lib's smooth_move_rewind; the lab's ramps
 * cannot be rewound), for the MotionStepper library's Stepper (which every stepper sketch uses).
 * docs/stepper-engine.md "Cutting the queue" has the rule and the measured latencies.
 */
#ifndef STEP_CUT_H
#define STEP_CUT_H

#include <stdint.h>

#include <step_planner.h>

/* The cut lands on the first command whose first step lies more than this many microseconds
 * ahead: the time the plan may take (a stop from the cruise; MOTION_STEPPER_CUT_SLOW_US for a stop
 * while the speed changes, or a new target, which cost up to twice as much; but a stop or a target
 * behind while accelerating takes step_cut_mirror's cut instead, below). 0: no cut at all. */
#ifndef MOTION_STEPPER_CUT_US
#define MOTION_STEPPER_CUT_US 4000UL
#endif
#ifndef MOTION_STEPPER_CUT_SLOW_US
#define MOTION_STEPPER_CUT_SLOW_US 5000UL
#endif
/* the plan must be ready this long before the step where the cut lands, else it is discarded */
#ifndef MOTION_STEPPER_CUT_MARGIN_US
#define MOTION_STEPPER_CUT_MARGIN_US 200UL
#endif
/* At the cut, the new plan's first commands are laid out together, at least this many microseconds
 * of steps (at most MOTION_STEPPER_CUT_CMDS commands), so that the queue holds enough for the
 * planner to plan the next one: a stop's first command is a single step. */
#ifndef MOTION_STEPPER_CUT_NEW_US
#define MOTION_STEPPER_CUT_NEW_US 1000UL
#endif
#ifndef MOTION_STEPPER_CUT_CMDS
#define MOTION_STEPPER_CUT_CMDS 4U
#endif
/* A stop while accelerating (from rest, or after a new target while moving) needs no plan before its
 * cut: its first steps are the acceleration's last ones reversed (MultiStepEngine::cut_mirror, lib's
 * step_exact_stop_mirrored), laid out at a cut this many microseconds ahead, at least
 * MOTION_STEPPER_MIRROR_MIN_US of them (the planner plans the rest of the stop while they run); a new
 * target behind is that stop and the move back after it. Where the ring does not hold that much of
 * the acceleration, they are planned at the slow cut. 0: no such cut. */
#ifndef MOTION_STEPPER_CUT_MIRROR_US
#define MOTION_STEPPER_CUT_MIRROR_US 800UL
#endif
#ifndef MOTION_STEPPER_MIRROR_MIN_US
#define MOTION_STEPPER_MIRROR_MIN_US 4000UL
#endif
/* at most this many commands reversed (on the planner interrupt's stack, 11 bytes each): with three
 * Steppers at 25,000 steps/s an axis still accelerating needs some 26 ms of them (StepperCut.cpp's
 * plan_at_cut), and its last 8 (as until 2026-12-07) covered 27.6 ms at one moment and less at
 * another: that stop fell to the plan at a cut, 23 ms after the call, and ran dry in its deceleration */
#define STEP_CUT_MIRROR_CMDS 12U
/* A target behind (a stop, then a move from rest) is cut only if its stop lasts this long
 * (docs/stepper-engine.md says why). */
#ifndef MOTION_STEPPER_CUT_THEN_MIN_US
#define MOTION_STEPPER_CUT_THEN_MIN_US 65000U
#endif
/* A cut whose plan is not ready in time is tried again farther ahead, up to this many cuts in all
 * (while the queue reaches that far); then the stop or the target acts after the queued lead. */
#ifndef STEP_CUT_TRIES
#define STEP_CUT_TRIES 4U
#endif
/* the most first commands any caller asks for */
#define STEP_CUT_MAX_CMDS 4U

/* The cut's timing, microseconds (the Stepper's: MOTION_STEPPER_CUT_* with the planner interrupt,
 * MOTION_STEPPER_LOOP_CUT_* planned from loop(), where a Stepper alone steps up to 100,000 steps/s and
 * the step interrupt leaves half the processor to the planner). */
struct StepCutTiming {
    uint8_t ticks_per_us; /* the step timer's */
    uint16_t ahead_us;     /* a stop from the cruise: the cut lands at least this far ahead */
    uint16_t ahead_slow_us; /* a stop while the speed changes, a new target */
    uint16_t margin_us;    /* the plan is laid out only if the interrupt is still this far from the cut */
    uint16_t new_us;       /* the new plan's first commands cover at least this much */
    uint8_t max_cmds;      /* ... in at most this many commands (<= STEP_CUT_MAX_CMDS) */
    uint16_t then_min_us;  /* a target behind (a stop, then a move from rest) is cut only if the
                              stop lasts this long: the move from rest is planned meanwhile (the
                              exact ramp; the smooth move's stop lasts tau1 + tau2 at least) */
    uint16_t ahead_smooth_us; /* the smooth move's stop or new target (its plans cost tens of
                                 milliseconds); 0: no cut of a smooth move */
    uint16_t ahead_mirror_us; /* a stop, or a target behind, while accelerating (MOTION_STEPPER_CUT_MIRROR_US); 0: none */
};

/* A stop (stop true) or a move to target (engine coordinates) of axis, whose planner pl is in an
 * exact or smooth move that the engine is stepping, planned from a cut of its queue, timed by t
 * (a smooth move only with t.ahead_smooth_us and a backup, step_cut_smooth_backup); the new
 * plan's first t.new_us of steps are laid out at the cut (the queue then holds that much while the
 * planner plans on). True: done (pl plans on from the new plan's first commands, already laid out; *from:
 * the position where the new plan starts). False: nothing changed (no exact move, parameters set
 * since it was planned, not that much queued, the planner refuses, or the plan came too late) and
 * the caller plans after the queued steps as without a cut, or, when *retry_us is not 0 (the plan
 * came too late), may call again later (its next pass: the other axes fed meanwhile) with that
 * *retry_us, a cut farther ahead (STEP_CUT_TRIES calls in all). *retry_us: in, 0 for a first try;
 * *missed counts a retry that found nothing queued that far, or a rewind refused. Call it
 * where the axis's commands are laid out (nothing else may lay out commands for it meanwhile). */
bool step_cut_plan(uint8_t axis, step_planner_t *pl, bool stop, int32_t target, const StepCutTiming &t,
                   int32_t *from, uint16_t *missed, uint32_t *retry_us);

/* A stop of axis while it accelerates (its planner pl in the acceleration of an exact move), at a cut
 * t.ahead_mirror_us ahead (a second try twice as far if cut_apply refuses the first) with no plan
 * before it: the acceleration's last commands reversed
 * (MultiStepEngine::cut_mirror), at least min_us of them, are laid out there. then: a new target `to`
 * behind the cut, the move to it from rest after the stop (only where the stop lasts t.then_min_us,
 * as step_cut_plan's reversals). True: done (*from: the position at the cut); the planner must then
 * take the rest of the stop, step_cut_mirror_rest(pl, *rest), before it hands out its next command
 * (while the reversed commands run: the other axes' queues may be fed first, as the planner is left
 * as it was until then). False: nothing changed (not accelerating there, the ring does not hold
 * min_us of the acceleration, a target that is not behind the cut, a stop shorter than
 * t.then_min_us before a move back, or the interrupt came too close at both tries):
 * plan it with step_cut_plan. */
struct StepCutMirror {
    uint32_t back, steps; /* the steps dropped, the steps laid out reversed */
    int64_t time16;       /* the executor's time of those */
    bool then;            /* the move to `to` from rest after the stop */
    int32_t to;
};
bool step_cut_mirror(uint8_t axis, step_planner_t *pl, const StepCutTiming &t, uint32_t min_us, bool then, int32_t to,
                     int32_t *from, StepCutMirror *rest);
void step_cut_mirror_rest(step_planner_t *pl, const StepCutMirror &rest);

/* The first commands of the plan in pl, at least new_us of steps (a stop's first is one step), into
 * c[0..max_cmds-1]: the planner then has that long to plan the next. */
uint8_t step_cut_first_cmds(step_planner_t *pl, step_cmd_t *c, uint8_t ticks_per_us, uint16_t new_us,
                            uint8_t max_cmds);

/* A planner for the cut's work, one for all (the cut is planned for one axis at a time); the same
 * memory as STEP_CUT_SCRATCH_CMDS commands (step_cut_cmds: a group's stop while accelerating reverses
 * each axis's commands there, off the planner interrupt's stack), for one use at a time. */
step_planner_t &step_cut_scratch();
static const uint8_t STEP_CUT_SCRATCH_CMDS = (uint8_t)(sizeof(step_planner_t) / sizeof(step_cmd_t));
step_cmd_t *step_cut_cmds();

/* Where step_cut_plan keeps a smooth move's state while it cuts (put back if the cut does not come
 * off): one for all axes, about 1 KB, given by the MotionStepper library when a Stepper first takes
 * the smooth ramp. Without it a smooth move is not cut. */
void step_cut_smooth_backup(step_smooth_t *backup);

/* MOTION_STEPPER_TRACE = 2: D4 (PG5) high while a cut is planned (the MotionStepper library's
 * BackgroundPlanner.h) */
void step_cut_trace(bool on);

#endif
