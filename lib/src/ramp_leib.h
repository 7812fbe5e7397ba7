/* ramp_leib.h - the Leib ramp: constant acceleration by one multiply-add chain per step, no
 * division (A. Eiderman, "Real Time Stepper Motor Linear Ramping Just by Addition and
 * Multiplication", eqs. 17-22), exactly as the lab's steps 1-6 (the lab handout §4.3.3):
 *   S = (v^2 - v0^2)/(2a), v = vmax; if 2S > D: v = sqrt(v0^2 + a*D), S = floor(D/2)  (ramp_common)
 *   p1 = F/sqrt(v0^2 + 2a)   ps = F/v   R = a/F^2                      (eqs. 6, 7, 8)
 *   per step: m = -R (accel) / 0 (cruise) / +R (decel); q = m*p*p; p = p*(1 + q + 1.5*q*q);
 *   p never above p1                                                   (eqs. 9-13)
 * Units: p, p1, ps in timer ticks; F ticks/s. Everything is float, as on the Mega, so the host and
 * the AVR perform the same IEEE single-precision operations in the same order.
 * One addition to the lab: p1 is never shorter than ps (only when S = 0, e.g. a one-step move or
 * a = huge, would F/sqrt(v0^2 + 2a) exceed the peak speed).
 * Accuracy (the published peer comparison, checked in test_ramp_leib): step 1 is 50 % short (p1 is the speed after
 * one step, not the mean over it); steps 11-100 within 5.8 %, 101-1000 within 0.59 %, beyond 0.06 %.
 * Cost on the AVR (16 MHz, float): about 1,080 cycles per accel/decel update, none in cruise.
 */
#ifndef RAMP_LEIB_H
#define RAMP_LEIB_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    float p;              /* interval of the current step, ticks */
    float p1;             /* first and longest interval, ticks */
    float ps;             /* cruise interval F/v, ticks */
    float r;              /* R = a/F^2, 1/ticks^2 */
    float peak_sps;       /* v: vmax, or lower for a short move */
    uint32_t accel_steps; /* S */
} ramp_leib_t;

/* Plans a move of steps_total steps (lab steps 1-5). Checks the parameters (ramp_params_check)
 * and that p1 fits 32 bits (MS_ERR_INTERVAL_TOO_LONG); on error *l is untouched. Afterwards
 * l->p = p1, the interval of step 1. The peak level for ramp_level is S. */
motion_status_t ramp_leib_plan(ramp_leib_t *l, const ramp_params_t *params, uint32_t steps_total);

/* Lab step 6: one update of p for a step in phase RAMP_ACCEL (m = -R), RAMP_DECEL (m = +R) or
 * anything else (m = 0: p unchanged). Returns the new p. */
float ramp_leib_update(ramp_leib_t *l, ramp_phase_t phase);

#ifdef __cplusplus
}
#endif

#endif
