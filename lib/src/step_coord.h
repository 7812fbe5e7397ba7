/* step_coord.h - a coordinated move of several stepper axes: every axis follows the same normalised
 * profile s(t) from 0 to 1, so the tool moves on the straight line from start to end, all axes
 * start at t = 0 and take their last step at the same time T_end; each axis's step commands
 * (step_queue.h) come from its own exact constant-acceleration ramp (step_exact.h).
 *
 * The profile: axis i moves D_i = |to_i - from_i| steps; the master is the axis with the largest D_m;
 * with r_i = D_i / D_m the profile, counted in master steps, uses
 *     v0 = min_i v0_i / r_i,   vmax = min_i vmax_i / r_i,   accel = min_i accel_i / r_i
 * so every axis's own speed (r_i times the master's) and acceleration stay within its limits.
 * s(t) is the exact constant-acceleration motion of the master (the lab handout's "uniform
 * acceleration, constant speed and uniform deceleration"), and axis i is at D_i s(t): scaling a
 * move by r scales v0, vmax and accel by r and leaves its time law in s unchanged, so axis i's own
 * exact ramp has the constants of step_exact.h with C_i = C_m / r_i and F/vmax_i = (F/vmax_m) / r_i
 * (and the same vmax F/a and v0 F/a). They are derived here from the master's exact fixed-point
 * constants by an integer multiply-divide, not from rounded floats, so the time laws agree to far
 * below a tick however long the move; the deceleration's end T_end is the master's for every axis.
 * Hence step k of axis i lies within 1 tick of round(F t) where D_i s(t) = k (step_exact.h's bound)
 * and position_i(t) = floor(D_i s(t)) except within 1 tick of an edge: at every edge of any axis,
 * every axis is within 1 step (plus the distance it moves in one tick) of the line, and with v0 = 0
 * the last steps of all axes fall on the same tick (test_step_coord checks both, against the closed
 * form of s(t) computed independently).
 * Why not Bresenham on the master's steps (Grbl): a slave's step would fall on a master edge, so its
 * intervals jump between multiples of the master's (its instantaneous speed reaching the master's,
 * above its own vmax); here every axis has a smooth ramp of its own. On the Mega (MultiStepEngine.h)
 * each axis of a coordinated move has its own queue and compare channel, all started on one tick; an
 * axis that moves as far as the master has exactly the master's commands (same constants) and is
 * pulsed by the master's interrupt instead.
 * Limits: an axis moving far less than the master has a large C_i; it must stay below 2^62 u^2
 * (D_m / D_i below about 0.137 accel_m / (F / 16 MHz)^2 ... e.g. 6,870 at 50,000 steps/s^2): a
 * larger ratio is refused (MS_ERR_COORD_RATIO). A stop (step_coord_stop) brings every axis to rest
 * on the line (within a step, unless an axis was already too close to stop there); on the way the
 * axes leave the line by up to the steps one command covers, since each stops from the point its
 * own commands have reached. A halt keeps every step made.
 * Cost on the AVR: per plan, per axis, one 96-by-32-bit division in 64-bit steps (about 3 ms);
 * per command the cost of step_exact_next.
 */
#ifndef STEP_COORD_H
#define STEP_COORD_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp_common.h"
#include "step_exact.h"
#include "step_queue.h"

#ifdef __cplusplus
extern "C" {
#endif

#define STEP_COORD_MAX_AXES 3U

typedef struct {
    uint8_t n_axes;                      /* axes of the move (0..n_axes-1); D_i = 0: not moving */
    uint8_t master;                      /* the axis with the largest D */
    ramp_params_t profile;               /* the profile in master steps (see above) */
    int32_t from[STEP_COORD_MAX_AXES];
    int32_t to[STEP_COORD_MAX_AXES];
    uint32_t d[STEP_COORD_MAX_AXES];
    step_exact_t ax[STEP_COORD_MAX_AXES]; /* each axis's exact ramp */
} step_coord_t;

/* The profile's parameters (in master steps) for axes with limits p[i] moving d[i] steps: the
 * minima above over the axes with d[i] > 0. MS_ERR_OUT_OF_RANGE when no axis moves or the tick
 * rates differ; a parameter set's own error (ramp_params_check) as it is. */
motion_status_t step_coord_profile(uint8_t n_axes, const ramp_params_t p[], const uint32_t d[], ramp_params_t *profile);

/* Plans a coordinated move of n_axes axes (1..STEP_COORD_MAX_AXES) from rest at from[i] to to[i]
 * with limits p[i]. MS_OK, or the reason (nothing usable in *c then). */
motion_status_t step_coord_plan(step_coord_t *c, uint8_t n_axes, const ramp_params_t p[], const int32_t from[],
                                const int32_t to[]);

/* The next command of axis i: 1 and *cmd, or 0 when its part of the move is complete. */
uint8_t step_coord_next(step_coord_t *c, uint8_t axis, step_cmd_t *cmd);

/* Something of axis i is still to be handed out. */
uint8_t step_coord_busy(const step_coord_t *c, uint8_t axis);

/* Position of axis i after its last command handed out. */
int32_t step_coord_position(const step_coord_t *c, uint8_t axis);

/* Time (2^-16 ticks from the move's start) by which axis i's handed-out commands end. */
int64_t step_coord_horizon16(const step_coord_t *c, uint8_t axis);

/* Stops the move: the master decelerates to rest from the state its commands have reached, each
 * other axis goes from its own state to where the line puts it then (round(D_i k_m / D_m) steps,
 * k_m the master's), or, when that is closer than it can stop, stops as soon as it can. */
void step_coord_stop(step_coord_t *c);

/* Axis i back to an earlier boundary of the commands it has handed out (a step engine that cuts
 * its queue: the MotionStepper library's StepperGroup): `steps` steps dropped from the end, taking
 * time16 (the executor's time of the dropped commands, the sum of step_exact_cmd_time16 over them),
 * last_count the count of the last command kept. The axis then stands as if it had handed out only
 * the kept commands (step_exact_rewind: bit for bit), and step_coord_stop, after every moving axis
 * was taken back so, stops the move from there. MS_ERR_OUT_OF_RANGE (nothing changed): no such
 * axis, not moving, steps not fewer than the profile's steps handed out, or step_exact_rewind's
 * refusals (a boundary the profile could not have had). */
motion_status_t step_coord_rewind(step_coord_t *c, uint8_t axis, uint32_t steps, int64_t time16, uint16_t last_count);

/* Forgets what axis i has not handed out yet and stands it at rest at pos (after a halt). */
void step_coord_halt(step_coord_t *c, uint8_t axis, int32_t pos);

/* Where the move ends for axis i (after a stop: where that axis comes to rest). */
int32_t step_coord_target(const step_coord_t *c, uint8_t axis);

#ifdef __cplusplus
}
#endif

#endif
