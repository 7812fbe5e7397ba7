/* step_exact.h - exact constant-acceleration step times as step commands (step_queue.h), in
 * integer arithmetic that gives the same bits on the host and on the AVR, fast enough for the
 * planner to keep 100,000 steps/s queued.
 *
 * The motion (the lab handout's "uniform acceleration, constant speed and uniform deceleration"):
 * a profile of D steps starts at speed u_s, accelerates (or decelerates, if u_s > vmax) at `accel`
 * to the peak u_p = min(vmax, what D allows), cruises, and decelerates to v0 on the last step.
 * In timer ticks, with C = 2F^2/a and U = v F / a ("the time to stop from v"):
 *   accelerating from U_s:  T(n) = sqrt(U_s^2 + C n) - U_s
 *   cruising at U_p:        T(n) = T(x1) + (n - x1) F / vmax
 *   decelerating to U_e:    T(n) = T_end - (sqrt(U_e^2 + C (D - n)) - U_e)
 * where x1 = (U_p^2 - U_s^2)/C is the (real) end of the acceleration; from rest (u_s = v0) this
 * is the closed form t_n = (sqrt(v0^2 + 2 a n) - v0)/a of ramp_exact.h, step for step.
 * How: the constants are exact 64-bit fixed point (1/256 tick) computed from the float parameters'
 * mantissas; each square root is a float estimate corrected once by its exact 64-bit residual
 * (Q - y^2 modulo 2^64), so no error accumulates, however long the move. Between exact points
 * the commands follow the time law as quadratics (rate + add per step, 16.16 ticks), the slopes of
 * both ends, over 2^j steps (1 to 128). The span rule, (l s)^3 <= 4000 y^2 at the tighter end
 * (s the interval, y the time to stop, both in 1/256 tick), keeps the interpolation within 0.37
 * tick, so an edge is never half a tick early (step_coord's path bound needs that); with s = C/(2y)
 * it is a threshold on y^2, which is linear in the step number, so each span's first step
 * (accelerating: spans only grow) or last step (decelerating: they only shrink) is worked out when
 * the span changes, and a command only compares integers. The cruise goes in commands of
 * max_cmd_ticks (at most 4096 steps, any count), rate = round(dt / count) found from floor(F/vmax)
 * without a division. The executor's time is predicted exactly, so the next command absorbs every
 * rounding. Every step edge floor(acc) is within 1 tick of round(F t_n) (test_step_planner:
 * thousands of random moves).
 * Limits (step_exact_set_params refuses others, each with its own status): tick_hz <= 2^25;
 * accel >= 8 steps/s^2 at 16 MHz (8 (F/16 MHz)^2 in general, and >= 0.5: C below 2^46 ticks^2);
 * vmax/accel (the time to reach vmax from rest) at most 2^34 ticks (1073 s at 16 MHz); the cruise's
 * interval F/vmax below 2^32 ticks (vmax above 0.0038 steps/s at 16 MHz: MS_ERR_INTERVAL_TOO_LONG);
 * parameters that overflow a float are refused as not finite.
 * Cost on the AVR: an accelerating or decelerating command takes one square root, one float
 * division and a few float multiplications and conversions; the rest is 32-bit integer work while
 * the time to stop stays below 2^23 ticks and the command below 65536 ticks (64-bit otherwise). A
 * cruise command is 32-bit integer work only; the first command of a deceleration and a change of
 * span add a few float operations (`make bench` measures it all).
 */
#ifndef STEP_EXACT_H
#define STEP_EXACT_H

#include <stdint.h>

#include "motion_status.h"
#include "ramp_common.h"
#include "step_queue.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The parameter set in exact fixed point (u = 1/256 tick). */
typedef struct {
    uint64_t cu;  /* C = 2F^2/a, u^2 per step */
    uint64_t vu;  /* vmax F/a, u */
    uint64_t u0;  /* v0 F/a, u */
    uint64_t p32; /* F/vmax, 2^-32 ticks per step */
    float cu_f;   /* the same as floats, for estimates */
    uint32_t tick_hz;
} step_exact_consts_t;

typedef struct {
    step_exact_consts_t k;
    uint32_t max_cmd_ticks; /* longest time one command may cover (stop latency), ticks */
    /* the profile being emitted */
    int32_t pos;      /* position after the last step emitted */
    int8_t dir;       /* +1 / -1 of this profile */
    uint32_t d;       /* steps of the profile */
    uint32_t n;       /* steps emitted */
    uint32_t n1;      /* steps 1..n1: region A (to the peak); n1 < n <= n2: cruise; after: decel */
    uint32_t n2;
    uint8_t a_down;   /* region A decelerates (u_s above vmax) */
    uint8_t moving;   /* the speed after step n is a real speed (not at rest) */
    uint8_t flags;    /* step_exact.c's F_* */
    uint8_t span_b;   /* the fit allows a quadratic command of 2^span_b steps here */
    uint64_t us, up;  /* speeds at the start and at the peak, u */
    uint64_t ue, qr;  /* the speed at the end, u, and its radicand less k.u0^2 (exact): k.u0 and 0,
                         but a little above it in a stop begun mirrored (step_exact_stop_mirrored) */
    int64_t t_end16;  /* T_end, 2^-16 ticks */
    int64_t acc16;    /* predicted executor time of step n, 2^-16 ticks from the profile start */
    uint64_t y;       /* sqrt(...) at step n in regions A and D (the speed there, u); 0 in the cruise */
    uint64_t q;       /* its radicand, exact modulo 2^64 */
    uint32_t thr;     /* where the span changes: the step (A accelerating: grow at n >= thr; A
                         decelerating: shrink unless n + span < thr) or the steps left (D: shrink
                         while m < thr) */
    int32_t err;      /* acc16 - T(n), 2^-16 ticks (the cruise: always; A and D: when F_ERR) */
    uint32_t slope_i; /* the interval at step n, 16.16 ticks per step (0x40000000: that or more) */
    float zfit;       /* the span rule's scale: y^2 (u^2) from which one step fits (step_exact.c) */
    float zfit_cu;    /* the k.cu_f zfit was worked out from (0: none yet): it is kept while that stays */
    float f1p;        /* (x1 - n1) F/vmax, 2^-16 ticks: where the cruise's line starts */
    uint32_t clr;     /* ccap floor(F/vmax), 16.16 */
    uint32_t cst_hi;  /* ccap F/vmax in 2^-16 ticks, and the fraction below */
    uint16_t cst_lo;
    uint16_t ccap;    /* steps of a full cruise command */
    uint16_t cfrac;   /* (n - n1) F/vmax below 2^-16 ticks, in 2^-32 ticks */
} step_exact_t;

/* Converts and checks a parameter set (ramp_params_check, then the limits above). On error
 * nothing changes. Call before the first profile; a change applies to the next profile. */
motion_status_t step_exact_set_params(step_exact_t *e, const ramp_params_t *p);

/* step_exact_set_params' checks alone: its status for p, without an object (a setter's check, with
 * little stack: a whole planner on the stack cost a Stepper's setters some 500 bytes more). */
motion_status_t step_exact_check(const ramp_params_t *p);

/* New parameters while moving (a replan follows): converts and checks them as
 * step_exact_set_params and carries the current speed over into the new constants (a speed is
 * held as U = v F/a, so a new accel would otherwise scale it by new/old accel: a jump). The
 * profile in progress ends here: plan a move (step_exact_plan) or a stop (step_exact_stop) next,
 * which then start from the current speed under the new limits. At rest it is
 * step_exact_set_params. On error nothing changes. */
motion_status_t step_exact_change_params(step_exact_t *e, const ramp_params_t *p);

/* At rest at position pos (no profile). */
void step_exact_reset(step_exact_t *e, int32_t pos);

/* Starts a profile from the current state (position and speed after the last emitted step) to
 * `to`. When moving and `to` is behind or closer than the stopping distance, returns
 * MS_ERR_BUSY and changes nothing: plan step_exact_stop first, then the move from rest. */
motion_status_t step_exact_plan(step_exact_t *e, int32_t to);

/* Replaces the profile by the shortest stop from the current speed (decelerating at accel to
 * v0); at rest it plans nothing. A profile that already ends as soon (decelerating to its target)
 * is kept: a stop never passes the target. */
void step_exact_stop(step_exact_t *e);

/* Steps needed to stop from the current state (0 at rest). */
uint32_t step_exact_stop_steps(const step_exact_t *e);

/* About how many commands (step_exact_next) a deceleration from v_sps steps/s to v0 under e's
 * constants takes: the steps of each span of the span rule (its thresholds, as a stop works them
 * out) over the span, in a few float operations per span, nothing planned. A planner's estimate of
 * the work a stop will ask of it (the MotionStepper library's StepperGroup chooses how far ahead it
 * cuts its queues from it); test_step_exact_seek checks it against stops planned and handed out.
 * 0 at or below v0. */
uint32_t step_exact_decel_cmds(const step_exact_t *e, float v_sps);

/* The next command of the profile: 1 and *c, or 0 when the profile is complete (then at rest). */
uint8_t step_exact_next(step_exact_t *e, step_cmd_t *c);

/* Speed after the last emitted step, steps/s (0 at rest). */
float step_exact_speed_sps(const step_exact_t *e);

/* The time command c takes in the executor (step_exec_next), 2^-16 ticks: count rate +
 * add count (count - 1)/2, or for a WIDE command count rate 2^16 (exact below 2^47 ticks). The
 * planner's acc16 grows by exactly this per command, from 0 at the profile's start. */
int64_t step_exact_cmd_time16(const step_cmd_t *c);

/* Back to an earlier command boundary of the profile in progress: the state right after the
 * command that ended at step n of the profile (steps counted from its step_exact_plan or stop),
 * as if the commands after it had never been emitted. acc16: the executor's time of step n from
 * the profile's start, 2^-16 ticks = the sum of step_exact_cmd_time16 over the profile's commands
 * up to step n = e->acc16 minus that sum over the commands dropped; last_count: the count of the
 * command that ends at step n. From there step_exact_next, _stop, _plan and _change_params give
 * the same commands, bit for bit, as on a planner that emitted only those commands: the state
 * (y, the span, the error of the timeline...) is worked out from n in closed form, with one
 * square root corrected by its exact residual (no replay). 1 <= last_count <= n <= e->n; n must
 * be a command boundary of this profile. Refused, nothing changed (MS_ERR_OUT_OF_RANGE): no
 * profile; n or last_count out of range or not a boundary the profile could have had; acc16 more
 * than 16 ticks off the time law there; the profile ended by step_exact_change_params; C or v0
 * not those it was planned with (checked exactly on the radicand). The constants must be the
 * profile's: after a step_exact_set_params that may have changed them (a completed profile),
 * ask step_exact_profile_intact first. A cut before the profile's first command boundary cannot
 * be rewound here. Cost: one corrected square root (a float square root and division), one more
 * float division, the span's thresholds (up to 8 of 2 float multiplications) and a few 64-bit
 * products. */
motion_status_t step_exact_rewind(step_exact_t *e, uint32_t n, int64_t acc16, uint16_t last_count);

/* A stop while accelerating, begun with the acceleration's own last steps reversed (the deceleration
 * from the speed of step n passes the acceleration's speeds again in reverse: on the law, the same
 * intervals): a step engine that still holds the commands that ended at step n can lay them out
 * reversed (each command's intervals in the opposite order: rate + (count - 1) add, -add) at once,
 * without a plan, and ask the planner for the rest afterwards. step_exact_mirror_ok: 1 when the
 * profile in progress allows it at step n (its acceleration, from rest or from a speed, n at least two
 * steps before its end; n <= e->n). step_exact_stop_mirrored: the state after `steps` steps of the
 * stop from step n (1 <= steps <= n - 2) that were so laid out, taking time16 in the executor's time
 * (the sum of step_exact_cmd_time16 over the reversed commands): the stop profile on the
 * acceleration's own radicands (us^2 + j C for j = n, n - 1, ... and on below its start while they
 * stay at or above v0's: n steps from rest, the exact stopping distance; from a speed us, n +
 * floor((us^2 - u0^2) / C) steps, ending within a step's speed change above v0), in its deceleration
 * with the rest of its steps left; step_exact_next then hands out the rest of it.
 * MS_ERR_OUT_OF_RANGE (nothing changed) otherwise. */
uint8_t step_exact_mirror_ok(const step_exact_t *e, uint32_t n);
motion_status_t step_exact_stop_mirrored(step_exact_t *e, uint32_t n, uint32_t steps, int64_t time16);

/* 1 when the profile's constants (from e->k) are still those it was planned with: it is planned
 * again from its start on a copy and compared (the cost of a step_exact_plan: about 10 float
 * divisions). 0 without a profile. */
uint8_t step_exact_profile_intact(const step_exact_t *e);

#ifdef __cplusplus
}
#endif

#endif
