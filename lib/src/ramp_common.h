/* ramp_common.h - what every stepper ramp shares: the move parameters and their checks, the
 * phases, where a move's acceleration, cruise and deceleration steps fall, the lab's choice of
 * the number of acceleration steps (the lab handout §4.3.3 steps 1-2), and real interval -> timer ticks.
 *
 * Conventions of every ramp module (lib/src/ramp_*.h):
 *  - A move of D = |to - from| steps starts at t = 0; step n (1..D) happens at t_n; the interval
 *    of step n is t_n - t_(n-1) in timer ticks (F ticks per second), so step 1 comes one interval
 *    after the start. Speeds in steps/s (sps), acceleration in steps/s^2 (sps2).
 *  - Symmetric placement: a planner with a peak level K gives step n the level
 *    c(n) = min(n, D + 1 - n, K); the interval shrinks where the level rises (acceleration),
 *    grows where it falls (deceleration) and stays where it is flat (cruise), so the last step
 *    mirrors the first. D may be anything up to 2^32 - 1 (INT32_MIN -> INT32_MAX) without overflow.
 * Cost on the AVR: a few 32-bit compares per step (ramp_level); the rest runs once per move.
 */
#ifndef RAMP_COMMON_H
#define RAMP_COMMON_H

#include <stdint.h>

#include "motion_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The constant-acceleration move parameters (simplistic, Leib and exact ramps). On the AVR
 * double is the same 32-bit type as float. */
typedef struct {
    double v0_sps;     /* minimum (start/stop) speed, >= 0 */
    double vmax_sps;   /* maximum permissible speed ("slew speed"), > v0, <= tick_hz */
    double accel_sps2; /* acceleration and deceleration, > 0 */
    uint32_t tick_hz;  /* F: timer ticks per second, > 0 */
} ramp_params_t;

typedef enum { RAMP_IDLE = 0, RAMP_ACCEL, RAMP_CRUISE, RAMP_DECEL } ramp_phase_t;

/* "idle", "accel", "cruise", "decel" (plain strings, also on the AVR: they are short). */
const char *ramp_phase_name(ramp_phase_t phase);

/* Checks what every constant-acceleration ramp needs, in this order: finite values
 * (MS_ERR_NOT_FINITE), accel > 0, v0 >= 0, vmax > v0, tick_hz > 0, vmax <= tick_hz. */
motion_status_t ramp_params_check(const ramp_params_t *p);

/* |to - from| as an unsigned count (up to 2^32 - 1) and the direction +1 / -1 / 0. */
uint32_t ramp_distance(int32_t from, int32_t to);
int8_t ramp_direction(int32_t from, int32_t to);

/* Position after n steps of a move from `from` in direction dir (wraps nothing: exact for any
 * n <= the move's distance). */
int32_t ramp_position_after(int32_t from, int8_t dir, uint32_t n);

/* c(n) = min(n, D + 1 - n, K) for 1 <= n <= D: the symmetric placement rule above. */
uint32_t ramp_level(uint32_t steps_total, uint32_t peak_level, uint32_t n);

/* Phase label of step n when the first `accel_steps` steps accelerate and the last as many
 * decelerate (accel_steps is capped at D/2 here): n <= A accel, n > D - A decel, else cruise. */
ramp_phase_t ramp_phase_label(uint32_t steps_total, uint32_t accel_steps, uint32_t n);

/* Lab steps 1-2 (the lab handout §4.3.3, Eiderman eqs. 4-5), in float as on the Mega:
 * S = (v^2 - v0^2)/(2a) with v = vmax, truncated to a whole step count; if 2S exceeds the move's
 * D steps, v = sqrt(v0^2 + a*D) and S = floor(D/2). Gives the peak speed v (sps) and S. */
void ramp_accel_steps(float v0_sps, float vmax_sps, float accel_sps2, uint32_t steps_total,
                      float *peak_sps, uint32_t *accel_steps);

/* A real interval (ticks) as the whole number of ticks a timer counts: rounded to nearest,
 * halves up (exact for every float from 0.5 to 2^32 - 256; values >= 2^23 are already whole).
 * This is the one conversion the firmware uses. Cost: integer work on the float's bits, about 60
 * cycles on the AVR (a float add and conversion would take about 235). */
uint32_t ramp_ticks_from_float(float interval_ticks);

/* A table of functions that lives in flash on the AVR (no SRAM; each call reads its pointer with
 * pgm_read_word, a few cycles) and in ordinary memory on the host: ramp.c's algorithm tables and
 * step_planner.c's halves. Declare `static const struct T name RAMP_TABLE_MEM = {...}`; call
 * RAMP_TABLE_FN(table_ptr, member)(args). */
#ifdef __AVR__
#include <avr/pgmspace.h>
#define RAMP_TABLE_MEM PROGMEM
#define RAMP_TABLE_FN(t, f) ((__typeof__((t)->f))pgm_read_word(&(t)->f))
#else
#define RAMP_TABLE_MEM
#define RAMP_TABLE_FN(t, f) ((t)->f)
#endif

#ifdef __cplusplus
}
#endif

#endif
