/* step_planner.h - the planner of the step engine: turns moves (to a target, a stop, a new target
 * while moving) of any of our ramps into step commands (step_queue.h) for the step interrupt.
 * It runs outside the interrupt (the sketch's loop(); motionsim), one command per call.
 *
 *   step_planner_t pl;  step_cmd_t c;
 *   step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &params, 0);   (or _sigmoid)
 *   step_planner_move(&pl, 20000);                      -> MS_OK, the move starts at pl's position
 *   while (step_planner_next(&pl, &c)) push c;          (in the sketch: while the queue has room)
 *
 * Algorithms: RAMP_ALGO_EXACT is planned by step_exact.h (exact times, fixed point, no per-step
 * work); simplistic, Leib and sigmoid step through ramp.h as before, and their whole-tick intervals
 * are packed into commands without any rounding: a run of intervals changing by a constant whole
 * number of ticks is one command (rate, add), so every reconstructed step time equals the sum
 * of the algorithm's own whole-tick intervals exactly (`motionsim ramp --integer-ticks`); their
 * cruise is one command per `max_cmd_ticks`.
 * A new target while moving continues from the speed reached by the last command handed out:
 * ahead and beyond the stopping distance, the move is replanned from there; otherwise the planner
 * stops (decelerating at the set acceleration), then moves from rest to the target. step_planner_stop
 * decelerates to rest. Parameter changes take effect at the next plan (move or stop).
 * Cost on the AVR: exact, one command per call (see step_exact.h); the others, their own cost per
 * step plus about 100 cycles of packing (`make bench` measures both).
 * RAMP_ALGO_SMOOTH (step_planner_init_smooth) is planned by smooth_move.h in a step_smooth_t the
 * caller provides (about 1 KB on the AVR, so it is not in every planner): a new target while moving
 * continues from the filter's state (one behind: its stop, then the move from rest), a stop sends
 * the velocity command to 0 at the last step handed out; v0 is not used (a smooth move starts and
 * ends at rest). Parameters set while moving take effect at the next move from rest (smooth_move
 * keeps one set per move). Its rewind is smooth_move_rewind's (to a step after the law's last start,
 * stop or new target; step_planner_rewindable). A firmware that
 * never calls step_planner_init_smooth does not link smooth_move.
 */
#ifndef STEP_PLANNER_H
#define STEP_PLANNER_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp.h"
#include "smooth_move.h"
#include "step_exact.h"
#include "step_queue.h"

#ifdef __cplusplus
extern "C" {
#endif

struct step_planner_ops; /* step_planner.c: the exact ramp's, the stepwise ramps' or the smooth move's part */

/* The smooth move's state, kept outside the planner (step_planner_init_smooth). */
typedef struct {
    smooth_move_t move;
    double jerk_sps3;       /* the jerk in force for the next move from rest */
    uint8_t params_pending; /* parameters set while moving, for the next move from rest (kept here:
                               step_planner_halt, at a move's end, clears the planner's own flag) */
} step_smooth_t;

typedef struct {
    const struct step_planner_ops *ops;
    ramp_algo_t algo;
    const ramp_hooks_t *hooks;       /* a sketch's pre-computation and update (ramp.h), or NULL */
    ramp_params_t params;            /* trapezoid algorithms: in force for the next plan */
    ramp_sigmoid_params_t sig;       /* sigmoid: its parameters and table */
    const uint16_t *table;
    uint16_t table_len;
    uint32_t max_cmd_ticks;          /* longest time one command may cover (stop latency), ticks */
    union {                          /* one half's state: the ops in use say which (the other is */
        step_exact_t exact;          /* never read; a planner of one kind stays of it until */
        ramp_t ramp;                 /* its next init) */
        step_smooth_t *smooth;       /* smooth: the caller's state */
    };
    uint8_t active;                  /* a profile is being handed out */
    uint8_t params_new;              /* exact: params set after the profile in progress was planned
                                        (its constants are older: the next plan converts them) */
    uint8_t has_carry;               /* a step taken from the ramp, not yet in a command */
    ramp_step_t carry;
    uint8_t has_ready;               /* a command waiting to be handed out first */
    step_cmd_t ready;
    uint8_t has_then;                /* after the stop in progress: the move to this target */
    int32_t then_target;
    int32_t pos;                     /* position after the last command handed out */
    int32_t target;                  /* where the current plan ends */
} step_planner_t;

/* A planner for simplistic, Leib or exact at rest at position pos. Checks the parameters (for
 * exact also step_exact_set_params' limits); on error *pl is untouched. */
motion_status_t step_planner_init_trapezoid(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                            int32_t pos);

/* The same, with a sketch's own pre-computation and per-step update for simplistic or Leib
 * (ramp_hooks_t; NULL members: lib's), used for every plan from here on. */
motion_status_t step_planner_init_hooked(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                         const ramp_hooks_t *hooks, int32_t pos);

/* The same for one kind only: a firmware that plans only the exact ramp (or only the lab's) links
 * only that half of the planner (the two above link both). _lab: simplistic or Leib
 * (MS_ERR_UNKNOWN_COMMAND for any other algorithm), planned by ramp_plan_lab: neither the exact ramp
 * nor the sigmoid is linked through it. */
motion_status_t step_planner_init_exact(step_planner_t *pl, const ramp_params_t *params, int32_t pos);
motion_status_t step_planner_init_lab(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                      const ramp_hooks_t *hooks, int32_t pos);
/* _lab for one of the two only (algo must be it, else MS_ERR_UNKNOWN_COMMAND), planned by
 * ramp_plan_leib / ramp_plan_simplistic: the other's code is not linked through them. */
motion_status_t step_planner_init_leib(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                       const ramp_hooks_t *hooks, int32_t pos);
motion_status_t step_planner_init_simplistic(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                             const ramp_hooks_t *hooks, int32_t pos);

/* A sigmoid planner over a filled table (it must stay unchanged while a move runs). */
motion_status_t step_planner_init_sigmoid(step_planner_t *pl, const ramp_sigmoid_params_t *p, const uint16_t *table,
                                          uint16_t table_len, int32_t pos);

/* A planner for the smooth (filter-shaped, jerk-limited) move of smooth_move.h at rest at pos, its
 * state in *store (which must live as long as the planner is used): params' vmax, accel and tick_hz
 * (v0 is not used) and jerk_sps3, checked as smooth_law_set_params checks them (its statuses, e.g.
 * MS_ERR_JERK_TOO_LOW when jerk < accel^2/vmax); on error *pl and *store are untouched. */
motion_status_t step_planner_init_smooth(step_planner_t *pl, const ramp_params_t *params, double jerk_sps3,
                                         step_smooth_t *store, int32_t pos);

/* Whether vmax, accel, tick_hz of params and jerk_sps3 make a valid smooth move (MS_OK or
 * smooth_law_set_params' status). */
motion_status_t step_planner_smooth_check(const ramp_params_t *params, double jerk_sps3);

/* A smooth planner's new jerk (checked with its parameters in force), from its next move from
 * rest; MS_ERR_NOT_SUPPORTED for another algorithm. On error nothing changes. */
motion_status_t step_planner_set_jerk(step_planner_t *pl, double jerk_sps3);

/* New parameters for the next plan (checked first; on error nothing changes). */
motion_status_t step_planner_set_params(step_planner_t *pl, const ramp_params_t *params);

/* Plans a move to `to` from the current state (see above). MS_OK, or the ramp module's status
 * (nothing changed). */
motion_status_t step_planner_move(step_planner_t *pl, int32_t to);

/* Decelerates to rest from the current state (no effect at rest). */
void step_planner_stop(step_planner_t *pl);

/* Forgets everything planned and not handed out and stands at pos (after a halt). */
void step_planner_halt(step_planner_t *pl, int32_t pos);

/* The next command: 1 and *c, or 0 when nothing more is planned (the axis will be at rest). */
uint8_t step_planner_next(step_planner_t *pl, step_cmd_t *c);

/* Takes back the last `steps` steps handed out (the commands a step engine drops from its queue
 * to act sooner on a stop or a new target), as if they had never been: then step_planner_stop,
 * step_planner_move and step_planner_next give the same commands, bit for bit, as on a planner
 * that handed out only the commands kept. time16: the time the dropped commands take in the
 * executor, the sum of step_exact_cmd_time16 over them; last_count: the count of the last
 * command kept. The exact ramp (step_exact_rewind, which says what it refuses) and the smooth move
 * (smooth_move_rewind: not bit for bit, every edge still within a tick of the law; last_count not
 * used); the others return MS_ERR_NOT_SUPPORTED for now. The commands dropped must all be of the current profile
 * and at least one of its commands must stay (steps < the profile's steps handed out): else
 * MS_ERR_OUT_OF_RANGE, as when the profile has been handed out to its end and a set has changed
 * the parameters since (step_exact_profile_intact). On error nothing changes. */
motion_status_t step_planner_rewind(step_planner_t *pl, uint32_t steps, int64_t time16, uint16_t last_count);

/* A stop while accelerating (from rest or from a speed), its first steps the acceleration's last
 * ones reversed (step_exact_stop_mirrored; the exact ramp only): step_planner_mirror_ok tells whether the step
 * `steps_back` steps before the last handed out allows it; step_planner_stop_mirrored then takes the
 * planner back there and to the stop's state after `steps` steps laid out so (time16: their executor
 * time), as step_planner_rewind and step_planner_stop would, the rest of the stop to hand out. */
uint8_t step_planner_mirror_ok(const step_planner_t *pl, uint32_t steps_back);
motion_status_t step_planner_stop_mirrored(step_planner_t *pl, uint32_t steps_back, uint32_t steps, int64_t time16);

/* The most steps step_planner_rewind can take back now (0: none; the exact ramp: all but the
 * profile's first; the smooth move: smooth_move_rewindable; the stepwise ramps: 0). */
uint32_t step_planner_rewindable(const step_planner_t *pl);

/* Something is still to be handed out. */
uint8_t step_planner_busy(const step_planner_t *pl);

/* Position after the last command handed out; the end of the current plan. */
int32_t step_planner_position(const step_planner_t *pl);
int32_t step_planner_target(const step_planner_t *pl);

#ifdef __cplusplus
}
#endif

#endif
