/* ramp.h - the move planner every stepper sketch and `motionsim ramp` use: give it the start and
 * target positions and an algorithm (simplistic, Leib, exact: ramp_params_t; sigmoid S-curve:
 * an S-curve article table), then ask it step by step for the interval to the next step and the phase.
 *
 *   ramp_t r; ramp_step_t s;
 *   if (ramp_plan(&r, RAMP_ALGO_LEIB, &params, from, to) != MS_OK) ... reject, nothing changed
 *   while (ramp_next(&r, &s)) ... wait s.whole_ticks timer ticks, then step (s.position)
 *
 * Each step reports the algorithm's own interval (float for simplistic and Leib, as the Mega
 * computes it; double for exact; the integer period for sigmoid) and whole_ticks, the interval as
 * a timer counts it (ramp_ticks_from_float: nearest whole tick). Distances up to 2^32 - 1 steps
 * (INT32_MIN -> INT32_MAX); see ramp_common.h for the step-time convention and the symmetric
 * placement of acceleration and deceleration. Cost on the AVR: that of the algorithm plus about
 * 350 cycles of bookkeeping per step (level, phase label, position; a cruise step of simplistic or
 * Leib reuses its interval and whole ticks and does no float work).
 */
#ifndef RAMP_H
#define RAMP_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp_common.h"
#include "ramp_exact.h"
#include "ramp_leib.h"
#include "ramp_sigmoid.h"
#include "ramp_simplistic.h"

#ifdef __cplusplus
extern "C" {
#endif

struct ramp_algo_ops; /* ramp.c: an algorithm's part of the planner */

/* RAMP_ALGO_SMOOTH: the filter-shaped, jerk-limited move of smooth_move.h; planned only by the step
 * planner (step_planner_init_smooth), not by ramp_plan (which refuses it like any other value). */
typedef enum { RAMP_ALGO_SIMPLISTIC = 0, RAMP_ALGO_LEIB, RAMP_ALGO_EXACT, RAMP_ALGO_SIGMOID, RAMP_ALGO_SMOOTH } ramp_algo_t;

/* "simplistic", "leib", "exact", "sigmoid" ("?" for anything else, RAMP_ALGO_SMOOTH too: the sketches
 * that print the name plan none of it, and its string would cost them SRAM). */
const char *ramp_algo_name(ramp_algo_t algo);

typedef struct {
    uint32_t step;         /* n, 1..D */
    int32_t position;      /* position after this step */
    double interval_ticks; /* t_n - t_(n-1) as the algorithm computes it, ticks */
    uint32_t whole_ticks;  /* the same, rounded to the nearest whole tick: what a timer counts */
    ramp_phase_t phase;
} ramp_step_t;

/* The lab's two places to edit, for a sketch that brings its own (the lab handout §4.3.3: the
 * "pre-computation code", steps 1-5, and computeNewSpeed(), step 6): functions with the
 * signatures of ramp_leib_plan/ramp_leib_update and ramp_simplistic_plan/ramp_simplistic_update,
 * called instead of them (a NULL member, or no hooks: lib's own; ramp_plan_hooked). The planner calls the
 * pre-computation once per plan (also to check parameters) and the update once per accelerating
 * or decelerating step, in loop(), never in the step interrupt. */
typedef struct ramp_hooks {
    motion_status_t (*leib_plan)(ramp_leib_t *l, const ramp_params_t *params, uint32_t steps_total);
    float (*leib_update)(ramp_leib_t *l, ramp_phase_t phase);
    motion_status_t (*simplistic_plan)(ramp_simplistic_t *s, const ramp_params_t *params, uint32_t steps_total);
    float (*simplistic_update)(ramp_simplistic_t *s, ramp_phase_t phase);
} ramp_hooks_t;

typedef struct {
    ramp_algo_t algo;
    int32_t from;
    int32_t to;
    int8_t dir;            /* +1, -1, or 0 for a zero-length move */
    uint32_t steps_total;  /* D */
    uint32_t steps_done;   /* steps handed out so far */
    uint32_t peak_level;   /* K of ramp_level (Leib S, simplistic S + 1) */
    uint32_t level;        /* c(n) of the last step handed out */
    uint32_t accel_steps;  /* steps labelled "accel" (and as many "decel") */
    uint32_t whole_ticks;  /* whole_ticks of the last step (reused while cruising) */
    uint32_t start_level;  /* level before step 1: 0 from rest, else that of the move continued */
    uint32_t label_accel;  /* min(accel_steps, D/2): ramp_phase_label's bound, divided once per plan */
    const ramp_hooks_t *hooks; /* the plan's (ramp_plan_hooked, _lab, _leib, _simplistic), or NULL */
    union {
        ramp_simplistic_t simplistic;
        ramp_leib_t leib;
        ramp_exact_t exact;
        ramp_sigmoid_t sigmoid;
    } u;
    /* the algorithm's part of ramp.c, chosen by the plan (ramp.c); last, so that the fields above keep
     * the offsets the AVR reaches in one instruction (ldd: 63 bytes) */
    const struct ramp_algo_ops *ops;
} ramp_t;

/* Plans a move with the simplistic, Leib or exact ramp. On error (bad parameters, an algorithm
 * that is not one of these three) *r is untouched. A zero-length move is valid: it has no steps. */
motion_status_t ramp_plan(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, int32_t from, int32_t to);

/* ramp_plan with a sketch's own pre-computation and update (hooks, may be NULL); a move continued
 * from this one (ramp_plan_continue) keeps them. */
motion_status_t ramp_plan_hooked(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, const ramp_hooks_t *hooks,
                                 int32_t from, int32_t to);

/* ramp_plan_hooked for the lab's two ramps only (simplistic, Leib; any other algorithm:
 * MS_ERR_UNKNOWN_COMMAND): a firmware that plans through this one, and never through ramp_plan or
 * ramp_plan_hooked, links neither the exact ramp nor the sigmoid (each algorithm's code is reached
 * only from the plans that choose it). */
motion_status_t ramp_plan_lab(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, const ramp_hooks_t *hooks,
                              int32_t from, int32_t to);

/* ramp_plan_lab for one of them only (algo must be that one, else MS_ERR_UNKNOWN_COMMAND): a firmware
 * that plans only through ramp_plan_leib links no other algorithm's code (LeibRampStepper). */
motion_status_t ramp_plan_leib(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, const ramp_hooks_t *hooks,
                               int32_t from, int32_t to);
motion_status_t ramp_plan_simplistic(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params,
                                     const ramp_hooks_t *hooks, int32_t from, int32_t to);

/* Plans a move through a sigmoid table filled by ramp_sigmoid_fill (table_len entries, at
 * least p->len). The table must stay unchanged until the move ends. */
motion_status_t ramp_plan_sigmoid(ramp_t *r, const ramp_sigmoid_params_t *p, const uint16_t *table,
                                  uint16_t table_len, int32_t from, int32_t to);

/* Continues `moving` (simplistic, Leib or sigmoid) from its last handed-out step without a speed
 * jump: the new move starts at that position, level and interval, towards `to`, with the level
 * rule c(n) = min(L0 + n, D + 1 - n, max(K, L0 - n)) (L0: the level reached, K: the peak of the
 * parameters, now possibly changed: params, or NULL for sigmoid, which keeps its table). `to` must
 * lie ahead in the same direction and at least ramp_stop_steps(moving) steps away, else
 * MS_ERR_BUSY and *r is untouched (stop first, then plan a move from rest). *r may be moving. */
motion_status_t ramp_plan_continue(ramp_t *r, const ramp_t *moving, const ramp_params_t *params, int32_t to);

/* Steps a continued move needs to come to rest from `moving`'s last step (its level - 1). */
uint32_t ramp_stop_steps(const ramp_t *moving);

/* The same under the parameters a replan would use (simplistic, Leib: a new accel or v0 makes the
 * speed reached another level, so another stopping distance); NULL or the sigmoid: ramp_stop_steps. */
uint32_t ramp_stop_steps_under(const ramp_t *moving, const ramp_params_t *params);

/* Position after the steps handed out so far. */
int32_t ramp_position(const ramp_t *r);

/* Hands out the next step: 1 and *s filled, or 0 when the move is complete. */
uint8_t ramp_next(ramp_t *r, ramp_step_t *s);

/* The step planner's per-step call, without the table lookup of each ramp_next_ticks (about 2 % of a
 * Leib step on the AVR): fetch the algorithm's step once (ramp_step_fn), then ramp_next_ticks_with it,
 * the same state and results as ramp_next_ticks. The ramp must have been planned. */
typedef ramp_phase_t (*ramp_step_fn_t)(ramp_t *r, uint32_t n);
ramp_step_fn_t ramp_step_fn(const ramp_t *r);
static inline uint8_t ramp_next_ticks_with(ramp_t *r, ramp_step_fn_t step, uint32_t *whole_ticks,
                                           ramp_phase_t *phase)
{
    if (r->steps_done >= r->steps_total)
        return 0;
    *phase = step(r, ++r->steps_done);
    *whole_ticks = r->whole_ticks;
    return 1;
}

/* ramp_next as the step planner needs it, without the step's position and real interval (the
 * per-step cost on the AVR is the algorithm's own arithmetic and little more): the whole ticks
 * and the phase of the next step; 0 when the move is complete. */
uint8_t ramp_next_ticks(ramp_t *r, uint32_t *whole_ticks, ramp_phase_t *phase);

/* After a step was handed out: hands out at once the steps that follow it with the same whole
 * ticks and phase, at most max_steps, and returns how many (0 when there are none or this ramp
 * cannot tell without stepping). Today the sigmoid, from rest or continued: the rest of a table entry's hold
 * while the move accelerates or decelerates. The same state as ramp_next_ticks step by step. */
uint32_t ramp_take_same(ramp_t *r, uint32_t max_steps);

/* Steps still to come. */
uint32_t ramp_steps_left(const ramp_t *r);

/* When the move is in its cruise, jumps over all cruise steps but the last (they all have the
 * same interval), so a long move's deceleration can be examined without stepping through the
 * cruise. Returns the number of steps skipped (0 when not in cruise). For tests and summaries;
 * a sketch steps every step. */
uint32_t ramp_skip_cruise(ramp_t *r);

/* How many steps ramp_skip_cruise would skip now (0 when not in cruise), without skipping. They
 * are all cruise steps with one interval and whole-tick count; for simplistic, Leib and sigmoid
 * also those of the step just handed out and of the step after them (the exact ramp's cruise
 * ends may straddle the end of its acceleration or the start of its deceleration). */
uint32_t ramp_cruise_skippable(const ramp_t *r);

/* ramp_skip_cruise, but skipping at most max_steps steps (e.g. to keep two ramps in step). */
uint32_t ramp_skip_cruise_at_most(ramp_t *r, uint32_t max_steps);

#ifdef __cplusplus
}
#endif

#endif
