/* ramp_simplistic.h - the lab's starting point, "a simplistic approach that nearly works"
 * (the lab handout §4.3.2, eqs. 1-2): the step interval changes by a fixed amount per step,
 *   dp = (p_max - p_min)/S,  p_max = F/v0 (first step, at the minimum speed),  p_min = F/v,
 *   p -= dp while accelerating, p += dp while decelerating, unchanged in cruise,
 * with S and v chosen as for the Leib ramp (lab steps 1-2, ramp_common), so both ramps accelerate
 * over the same steps. The speed F/p then rises hyperbolically, not linearly: gentle at first,
 * far too steep near vmax. That is the point of the exercise; `motionsim ramp --compare` measures it.
 * Intervals: step 1 is p_max, step S+1 reaches p_min (peak level S+1 for ramp_level); the last
 * step is p_max again. Float, as on the Mega. v0 must be > 0 (MS_ERR_V0_ZERO_SIMPLISTIC).
 * S < 1: eq. (1) divides by S, and the lab's S = int((v^2 - v0^2)/2a) is 0 when vmax is less than
 * one step of acceleration above v0 (e.g. v0 1, vmax 4, a 10: 0.75). Then S = 1: step 1 at
 * p_max, step 2 at p_min = F/vmax (dp = p_max - p_min), cruise, the last step at p_max again;
 * reaching vmax within one step is allowed, since it needs only (vmax^2 - v0^2)/2 < a (Leib, with
 * S = 0, runs at F/vmax from step 1). A one-step move keeps S = 0: its one interval is p_max;
 * a two-step move has S = 1 but no flat level above 1, so both steps are p_max.
 * Cost on the AVR: one float addition (~100 cycles) per accel/decel step.
 */
#ifndef RAMP_SIMPLISTIC_H
#define RAMP_SIMPLISTIC_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    float p;              /* interval of the current step, ticks */
    float p_max;          /* F/v0: first and longest interval, ticks */
    float p_min;          /* F/v: cruise interval, ticks */
    float dp;             /* eq. (1), ticks per step */
    float peak_sps;       /* v */
    uint32_t accel_steps; /* S */
} ramp_simplistic_t;

/* Plans a move of steps_total steps; checks the parameters, v0 > 0 and that F/v0 fits 32 bits.
 * On error *s is untouched. Afterwards s->p = p_max, the interval of step 1. */
motion_status_t ramp_simplistic_plan(ramp_simplistic_t *s, const ramp_params_t *params, uint32_t steps_total);

/* Eq. (2): p - dp (RAMP_ACCEL), p + dp (RAMP_DECEL, never above p_max), else p. Returns p. */
float ramp_simplistic_update(ramp_simplistic_t *s, ramp_phase_t phase);

#ifdef __cplusplus
}
#endif

#endif
