/* ramp_exact.h - the ideal the other ramps approximate: step times of true constant acceleration
 * (the lab handout §4.3.1: "uniform acceleration, constant speed and uniform deceleration"), so the
 * velocity is exactly linear in time.
 *   position x(t) = v0 t + a t^2/2 until x_a = min((vmax^2 - v0^2)/(2a), D/2); then cruise at
 *   v_peak = sqrt(v0^2 + 2 a x_a) (= vmax unless the move is short); deceleration mirrors it.
 *   Step n (n <= x_a) happens at t_n = (sqrt(v0^2 + 2 a n) - v0)/a, computed as
 *   2n/(sqrt(v0^2 + 2 a n) + v0), which has no cancellation; later steps follow the cruise line
 *   and the mirror t(D - x) = T - t(x). Intervals are computed piecewise from the same closed
 *   forms (never as a difference of two large times), so each is accurate to a few ulp.
 * Units: s, steps, steps/s. Double precision: on the host every t_n is within 1e-12 relative of
 * the formula (the issue asks 1e-9). On the AVR double is float (about 1e-7 relative), and each
 * step costs two square roots and a division: the sketches use Leib instead.
 */
#ifndef RAMP_EXACT_H
#define RAMP_EXACT_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double v0_sps;
    double accel_sps2;
    double peak_sps;      /* v_peak */
    double x_accel;       /* x_a, steps (not necessarily whole) */
    double t_accel_s;     /* time to reach x_a */
    double t_total_s;     /* T: time of the last step */
    double tick_hz;       /* F */
    uint32_t steps_total; /* D */
} ramp_exact_t;

/* Plans a move of steps_total steps; checks the parameters and that no interval exceeds 2^32 - 1
 * ticks. On error *e is untouched. */
motion_status_t ramp_exact_plan(ramp_exact_t *e, const ramp_params_t *params, uint32_t steps_total);

/* t_n: time of step n after the start of the move, s (n = 0..D; t_0 = 0, t_D = T). */
double ramp_exact_time_s(const ramp_exact_t *e, uint32_t n);

/* t_n - t_(n-1) for 1 <= n <= D, s. */
double ramp_exact_interval_s(const ramp_exact_t *e, uint32_t n);

/* Phase of step n by its mid position n - 1/2: accel below x_a, decel above D - x_a. */
ramp_phase_t ramp_exact_phase(const ramp_exact_t *e, uint32_t n);

#ifdef __cplusplus
}
#endif

#endif
