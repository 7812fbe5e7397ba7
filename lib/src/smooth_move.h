/* smooth_move.h - the filter-shaped (jerk-limited) move: the velocity command of the
 * moving-average-filter note passed through its two moving averages (ma2_filter.h, the note's
 * "S-curve acceleration"), as a continuous-time position law, and its step times packed into step
 * commands (step_queue.h) like the exact ramp (step_exact.h).
 *
 * The law. The velocity command u(t) is piecewise constant: for a move of R steps from rest a
 * rectangle of height h and length T (h T = R); the velocity is v = u * b1 * b2, where bi is the
 * moving average of length taui (unit area), tau1 = vmax/accel, tau2 = accel/jerk, so
 *   a step of the command by c at time s adds c P(t - s) to the position, with
 *   P(t) = [r(t) - r(t - tau1) - r(t - tau2) + r(t - tau1 - tau2)] / (tau1 tau2),  r(x) = max(x,0)^3/6
 * (the integral of ma2_filter.h's S-curve): the position is piecewise cubic, its jerk changes by
 * +-c/(tau1 tau2) at the "knots" s, s + tau1, s + tau2, s + tau1 + tau2 and is constant between them.
 * The distance is exactly h T = R; the peak acceleration is h/tau1 <= accel and the jerk
 * h/(tau1 tau2) <= jerk (equal for h = vmax and T >= tau1 + tau2), velocity and acceleration
 * continuous.
 * The rectangle (the rule for R, "short moves"):
 *   R >= vmax (tau1 + tau2) or R <= vmax (tau1 - tau2):  h = vmax, T = R/vmax
 *   otherwise:                                          T = tau1 + tau2, h = R/(tau1 + tau2) < vmax
 * Why the middle band is lowered instead of shortened: the jerk is h/(tau1 tau2) times
 * [1 on (0, tau2)] - [1 on (T, T + tau2)] - [1 on (tau1, tau1 + tau2)] + [1 on (T + tau1, T + tau1 + tau2)],
 * so a rectangle with |T - tau1| < tau2 overlaps the two negative windows and the jerk reaches
 * 2 h/(tau1 tau2) (the end of the acceleration meets the start of the deceleration).
 * Stop: the command goes to 0 now (the time of the last step handed out; or later, see below, where
 * now would exceed the jerk limit); the filter's memory
 * carries the move on to where it comes to rest (a real position; the last step is the last whole
 * step at or before it: a rest within 2^-50 of its size from a whole step is on it). New target
 * while moving: the command's future is replaced from now on by a new rectangle (the rule above
 * for R = target - where a stop now would come to rest), continuing from the filter's state, so
 * velocity and acceleration stay continuous and |acceleration| <= accel. A target behind that rest
 * point (it would need to reverse) is reached by a stop, then a move from rest, as step_planner
 * does for the exact ramp. "Now" unless the change's jerk windows would add to a running one of
 * the same sign (a stop within tau2 of the end of the acceleration's ramp-down: 2 jerk): then the
 * change waits for the first end of a running window from which |jerk| <= jerk all along (at most
 * tau1 + tau2; a stop always finds one); a new target none keeps within it is a stop, then a move
 * from rest (replan() has the rule).
 *
 * The law's arithmetic: a small floating point of our own in integers (smx_t: 62-bit mantissa,
 * 16-bit exponent; +, -, x, / with fixed rounding): knots, stops, new targets and the servo's
 * setpoints. The last segment is expressed about its end (where the position is exactly the
 * target and v = a = 0), so the last step is at the end of the law.
 * Commands (the stepper planner): per command, one exact solve of the end step's time on its
 * segment's cubic, and the command's shape from the step series t(n + l) = t_n + l t1 + l^2 t2/2
 * + l^3 t3/6 (t1 = 1/v, t2 = -a/v^3, t3 = (3a^2 - v j)/v^5, from the segment's state at step n in
 * floats):
 *   - the span l: the longest (from a quarter more than the last one, at most to the segment's
 *     knot and 65535 steps) whose bound on |executor time - law time| stays within 0.9 tick (below
 *     1: the engine's timeline starts half a tick in, so the edge floor(acc) is the tick nearest
 *     the executor's time, within 1 tick of round(F t_n)): the offset at its
 *     start, the cubic term beyond the quadratic through its ends and middle (0.00802 |t3| l^3),
 *     the rounding of add (|add - ideal| l^2/8) and of rate (l 2^-17), the float error of the
 *     shape; and it covers at most max_cmd_ticks; intervals of 65536 ticks or more go into WIDE
 *     commands rounded to the nearest tick;
 *   - the end step's time: Newton from the series' guess on the segment's cubic held in 64-bit
 *     fixed point (Horner with 64 x 32-bit products, each level truncated to 2^-60 of a bound on
 *     it; local times in whole ticks below 2^30), the residual at a whole tick over dt/dn, to
 *     2^-12 tick; where that does not apply (near rest, or a segment too long for it) the smx
 *     Newton with bisection as safeguard;
 *   - the terms beyond the cubic: after the solve, 0.55 times the Newton correction from the
 *     series' end (a quartic error pinned at both ends moves the middle by at most 0.47 of its
 *     value at the end) must still fit in the budget, else the span is shortened and solved again;
 *   - add = the quadratic through the span's start, middle and end of the series (t2 + t3 l/2,
 *     2^-16 ticks), rate through the executor's predicted start and the exact end.
 * A cruise (a segment without jerk whose acceleration moves it by less than 2^-20 tick, or is
 * only rounding left by the knots) is a line: its commands come from the step after an exact
 * solve on it plus l x (ticks per step, 2^-48), with no solve, as long as the executor's offset
 * from the line plus l 2^-17 stays within the budget (else the exact solve). After a knot, the
 * first command is solved on the new segment (the step before it lies on the old one). The
 * executor's time is predicted exactly, so the next command absorbs every rounding: no drift.
 * Every edge (floor(acc), acc half a tick in) is within 1 tick of round(F t_n), |acc - F t_n| below 0.95 tick for normal
 * commands and 1/2 (+ the solve's 2^-12) for WIDE ones (test_smooth_move: random moves, stops and
 * new targets against the closed form in quadruple precision, and the move of 2^31 - 1 steps).
 * The host and the AVR compute the same commands: the float work is IEEE single precision
 * +, -, x, / and frexp/ldexp/sqrt on both (the emulator check compares checksums).
 * Limits (smooth_set_params refuses others, each with its own status): 0 < vmax <= tick_hz,
 * accel > 0, jerk > 0, tau2 <= tau1 (jerk >= accel^2/vmax), tau1 <= 2^34 ticks; a plan must end
 * within 2^46 ticks of the timeline's start (the timeline restarts at rest); moves of 1 to
 * 2^32 - 1 steps; at most SMOOTH_MAX_CHANGES changes of the command within tau1 + tau2.
 * Cost on the AVR: a command takes one fixed-point solve (three 64 x 32-bit products per Newton
 * step, usually one step), some 40 float operations and a few 64-bit ones; a cruise command on the
 * line no solve at all; the first few steps from rest and the last ones, and a stop or a new
 * target, smx solves. Memory: smooth_move_t is about 1000 bytes on the AVR (SMOOTH_MAX_CHANGES =
 * 6). The emulator check "smooth_move on the AVR" measures the cycles per command and per step,
 * the planner's load and the lead it needs on reference moves (and that the host computes the
 * same bits).
 */
#ifndef SMOOTH_MOVE_H
#define SMOOTH_MOVE_H

#include <stdint.h>

#include "motion_status.h"
#include "step_queue.h"

#ifdef __cplusplus
extern "C" {
#endif

/* m x 2^e; m = 0 or 2^61 <= |m| < 2^62. */
typedef struct {
    int64_t m;
    int16_t e;
} smx_t;

/* The parameters (on the AVR double is float; the host rounds them to float first, so both
 * compute with the same values). */
typedef struct {
    double vmax_sps;   /* the command's height, steps/s (the peak speed of long moves) */
    double accel_sps2; /* peak acceleration, steps/s^2: tau1 = vmax/accel */
    double jerk_sps3;  /* peak jerk, steps/s^3: tau2 = accel/jerk */
    uint32_t tick_hz;  /* F: timer ticks per second (the law's time unit is the tick) */
} smooth_params_t;

#ifndef SMOOTH_MAX_CHANGES
#define SMOOTH_MAX_CHANGES 6
#endif
#define SMOOTH_MAX_KNOTS (4 * SMOOTH_MAX_CHANGES)

typedef struct {
    smx_t t, c; /* the command changes by c (steps/tick) at time t (ticks) */
} smooth_change_t;

typedef struct {
    smx_t t, dj; /* the jerk changes by dj at time t */
} smooth_knot_t;

/* The motion at time t (ticks of the timeline), in the move's frame (steps from its origin, in
 * its direction): position, velocity (steps/tick), acceleration, jerk; knots before `next` are in. */
typedef struct {
    smx_t t, p, v, a, j;
    uint8_t next;
} smooth_cursor_t;

/* The continuous law: parameters, the command's changes, the cursor. */
typedef struct {
    smx_t tau1, tau2, vmax; /* ticks, ticks, steps/tick */
    smx_t inv_t1t2;         /* 1/(tau1 tau2) */
    uint32_t tick_hz;
    smooth_change_t chg[SMOOTH_MAX_CHANGES];
    smooth_knot_t knot[SMOOTH_MAX_KNOTS];
    uint8_t n_chg, n_knot;
    smooth_cursor_t cur; /* at a time at or before the last step handed out */
    smx_t p_final;       /* where the plan comes to rest (frame) */
    smx_t t_final;       /* when (the last knot) */
    smx_t u_old;         /* the command's changes already dropped (all their knots in the cursor) */
    int32_t origin;      /* the frame: absolute position = origin + dir x frame position */
    int8_t dir;
} smooth_law_t;

/* Checks a parameter set and converts it (tau1, tau2 in ticks). On error *law is untouched.
 * MS_ERR_NULL, MS_ERR_NOT_FINITE, MS_ERR_VMAX_NOT_ABOVE_V0 (vmax <= 0), MS_ERR_ACCEL_NOT_POSITIVE,
 * MS_ERR_JERK_NOT_POSITIVE, MS_ERR_TICK_HZ_ZERO, MS_ERR_VMAX_ABOVE_TICK_HZ, MS_ERR_JERK_TOO_LOW
 * (tau2 > tau1), MS_ERR_ACCEL_PHASE_TOO_LONG (tau1 > 2^34 ticks), or MS_OK. */
motion_status_t smooth_law_set_params(smooth_law_t *law, const smooth_params_t *p);

/* At rest at pos, the timeline at 0 (keeps the parameters). */
void smooth_law_reset(smooth_law_t *law, int32_t pos);

/* From rest at the law's origin: the move to `to` starting at t = 0. MS_OK (also for to = origin:
 * nothing to do), or MS_ERR_SMOOTH_TOO_LONG. */
motion_status_t smooth_law_start(smooth_law_t *law, int32_t to);

/* At time `now` (ticks, not before the cursor): replace the command's future so the plan ends
 * at `to` (MS_OK), or, when `to` is behind where a stop now would come to rest, change nothing
 * and return MS_ERR_SMOOTH_REVERSE. Also MS_ERR_SMOOTH_TOO_MANY, MS_ERR_SMOOTH_TOO_LONG. */
motion_status_t smooth_law_retarget(smooth_law_t *law, smx_t now, int32_t to);

/* At time `now`: the command goes to 0 (p_final: where the motion comes to rest). */
void smooth_law_stop(smooth_law_t *law, smx_t now);

/* The motion at time t (>= the cursor's time) in the frame: p (steps), v (steps/s), a
 * (steps/s^2), j (steps/s^3) as doubles (for tables and plots; any pointer may be NULL). */
void smooth_law_eval(const smooth_law_t *law, smx_t t, double *p, double *v, double *a, double *j);

/* The frame position at time t rounded to the nearest whole step (halves away from 0), and as
 * an absolute position: integer work only (the servo's setpoint). */
int32_t smooth_law_position_at(const smooth_law_t *law, smx_t t);

/* Moves the cursor to time t (applying the knots up to it). */
void smooth_law_advance(smooth_law_t *law, smx_t t);

/* Applies the knots up to time t, leaving the cursor on the last of them (no rounding added
 * between knots: the planner's steps are solved from there). */
void smooth_law_knots_to(smooth_law_t *law, smx_t t);

/* The exact time (ticks) when the frame position reaches n (0 < n <= p_final), solved from the
 * cursor on; *accel (may be NULL) gets the sign of the acceleration there (-1, 0, +1). */
smx_t smooth_law_time_of(const smooth_law_t *law, uint32_t n, int8_t *accel);

/* The plan is moving at or after time t (a knot is still ahead, or the velocity is not 0). */
uint8_t smooth_law_moving(const smooth_law_t *law);

/* smx_t helpers for callers (motionsim, the servo): exact from an integer, ticks to seconds. */
smx_t smx_from_i64(int64_t v);
smx_t smx_from_float(float f);
double smx_to_double(smx_t a);
smx_t smx_add(smx_t a, smx_t b);
smx_t smx_mul(smx_t a, smx_t b);
smx_t smx_div(smx_t a, smx_t b);
int smx_cmp(smx_t a, smx_t b);
/* round(a), halves away from 0; and round(a x 2^16) (a time in 16.16 ticks) */
int64_t smx_round(smx_t a);
int64_t smx_round_q16(smx_t a);

/* ---- the stepper planner: the law's step times as step commands ---- */
typedef struct {
    smooth_law_t law;
    uint32_t max_cmd_ticks; /* longest time one command may cover (stop latency), ticks */
    int32_t pos;            /* position after the last step handed out */
    uint32_t n;             /* frame steps handed out */
    uint32_t n_end;         /* the last step of the plan (frame) */
    int64_t acc16;          /* the executor's time of step n, 2^-16 ticks from the timeline's start */
    int64_t err16;          /* acc16 - (t16_a + y16): the executor's offset from the law at step n */
    uint16_t span;          /* steps of the last command (the next one tries a quarter more) */
    uint8_t probe;          /* after one step: commands of one step before two are tried again */
    uint8_t active;         /* a plan is being handed out */
    uint8_t has_then;       /* after the stop in progress: the move to then_target */
    int32_t then_target;
    /* the law's last change (a start, stop or new target) was made at step n_evt, time t_evt: the
     * law holds every knot after it, so smooth_move_rewind can go back to any step after it */
    uint32_t n_evt;
    smx_t t_evt;
    /* the last exact solve (step n_a at t_n) and, on a cruise, how far step n is past it */
    smx_t t_n;              /* the law's time of step n_a, ticks (exact; seg.t + x_a when tn_stale) */
    uint8_t tn_stale;
    smx_t x_a;              /* t_n - seg.t (xa16 2^-16 when xa_stale) */
    uint8_t xa_stale;
    uint32_t n_a;
    int64_t t16_a;          /* round(t_n x 2^16) */
    int64_t xa16;           /* round(x_a x 2^16) */
    int64_t y16;            /* on the cruise's line: step n's time after t_n, 2^-16 ticks */
    uint32_t y_lo;          /* and the fraction below that, 2^-48 ticks */
    float xf_a;             /* x_a as a float */
    uint8_t a_in_seg;       /* step n_a was solved on the segment's own polynomial (the cruise's
                               line starts only from there) */
    /* the segment of the law that holds step n + 1 (between two knots): a copy of the law's
     * cursor moved to its start, or for the last segment the polynomial about its end */
    smooth_cursor_t seg;
    smx_t seg_end;          /* the knot that ends it */
    smx_t seg_hi;           /* seg_end - seg.t */
    smx_t seg_ah, seg_j6;   /* a/2, j/6 of its polynomial */
    int64_t seg_t16;        /* round(seg.t x 2^16) */
    /* its polynomial in fixed point for whole-tick local times x (|x| < 2^30): Horner with
     * h3 = c3, h_k = c_k + (h_(k+1) x) 2^-fp_s[k], p(x) - m = (h0 - m 2^fp_m) 2^-fp_m */
    int64_t fp_c[4];
    uint8_t fp_s[3];
    uint8_t fp_m;
    uint8_t fp_ok;
    uint64_t inv48;         /* a cruise (a line): ticks per step x 2^48; else 0 */
    float f_v0, f_a0, f_j;  /* seg.v, seg.a, seg.j as floats (steps/tick, /tick^2, /tick^3) */
    float f_acc_eps;        /* below this acceleration a command is reported as cruise */
    uint32_t seg_last;      /* the last step inside it (frame) */
    uint8_t seg_ok;         /* seg is set up for the current plan */
    uint8_t seg_final;      /* it is the last segment (about t_final) */
    uint8_t final_whole;    /* the plan ends on a whole step (p_final = n_end) */
} smooth_move_t;

/* At rest at pos with parameters p (checked as smooth_law_set_params); max_cmd_ticks defaults to
 * F/250 (4 ms), like step_planner. On error *s is untouched. */
motion_status_t smooth_move_init(smooth_move_t *s, const smooth_params_t *p, int32_t pos);

/* New parameters (checked first): at rest they apply at once; while moving MS_ERR_BUSY (stop first). */
motion_status_t smooth_move_set_params(smooth_move_t *s, const smooth_params_t *p);

/* A move to `to` from the current state: from rest a new plan; while moving, a new target from
 * the last step handed out (or a stop, then a move from rest, if it would have to reverse).
 * MS_OK or the law's status (nothing changed). */
motion_status_t smooth_move_to(smooth_move_t *s, int32_t to);

/* The command goes to 0 at the last step handed out (no effect at rest); a pending move after
 * a stop is dropped. */
void smooth_move_stop(smooth_move_t *s);

/* Forgets everything not handed out and stands at pos (after a halt). */
void smooth_move_halt(smooth_move_t *s, int32_t pos);

/* Takes back the last `steps` steps handed out (the commands a step engine drops from its queue to
 * act sooner on a stop or a new target), as if only the commands kept had been handed out: then
 * smooth_move_stop, smooth_move_to and smooth_move_next plan from step k = n - steps, whose
 * executor time is the kept commands' (acc16 - time16: time16 is the dropped commands' time in the
 * executor's arithmetic, 2^-16 ticks). The law's cursor goes back across its knots to step k's time
 * (solved exactly there), so every later edge is within a tick of the law as before; the commands
 * that follow need not be those dropped, bit for bit (their spans start from the last one's).
 * Only within the law's current plan: k must come after the last start, stop or new target
 * (1 <= steps <= smooth_move_rewindable(s)), else MS_ERR_OUT_OF_RANGE; time16 must leave step k's time
 * within a tick of the law's (else MS_ERR_OUT_OF_RANGE: not the dropped commands' time). On error
 * nothing changes. Cost: an smx solve of step k's time (a few milliseconds on the AVR). */
motion_status_t smooth_move_rewind(smooth_move_t *s, uint32_t steps, int64_t time16);

/* How many of the steps handed out can be taken back now (0 at rest): those after the first one
 * after the last start, stop or new target. */
uint32_t smooth_move_rewindable(const smooth_move_t *s);

/* The next command: 1 and *c, or 0 when the plan is complete (at rest). */
uint8_t smooth_move_next(smooth_move_t *s, step_cmd_t *c);

/* Something is still to be handed out. */
uint8_t smooth_move_busy(const smooth_move_t *s);

/* Position after the last command handed out; where the plan ends (whole steps). */
int32_t smooth_move_position(const smooth_move_t *s);
int32_t smooth_move_target(const smooth_move_t *s);

/* ---- a servo's setpoint along the law (ProportionalClosedLoop, PIDClosedLoop, motionsim servo) ----
 * Time in milliseconds (the law's ticks are microseconds: tick_hz must be 1000000), positions in
 * encoder counts (vmax up to 10^6 counts/s). A
 * move starts from the setpoint in force, at the time it is given; the setpoint at time t is the
 * law's position rounded to the nearest count. A new target while moving continues from the
 * filter's state; one behind where a stop now comes to rest (or one more change than the law
 * holds within tau1 + tau2) stops first and starts from rest (at the whole count nearest to it)
 * when the stop has ended. Integer work only: the sketch and motionsim compute the same setpoints. */
typedef struct {
    smooth_law_t law;
    uint32_t t0_ms;   /* the timeline's start on the caller's millisecond clock */
    int32_t last;     /* the setpoint last handed out */
    uint8_t has_then; /* after the stop in progress: the move to then_target */
    int32_t then_target;
} smooth_setpoint_t;

/* At rest at pos. p->tick_hz must be 1000000 (else MS_ERR_OUT_OF_RANGE); the law's other
 * checks. On error *s is untouched. */
motion_status_t smooth_setpoint_init(smooth_setpoint_t *s, const smooth_params_t *p, int32_t pos);

/* New parameters at rest (MS_ERR_BUSY while moving). */
motion_status_t smooth_setpoint_set_params(smooth_setpoint_t *s, const smooth_params_t *p);

/* A move to `to` given at now_ms (MS_OK, or the law's status: nothing changed). */
motion_status_t smooth_setpoint_move(smooth_setpoint_t *s, uint32_t now_ms, int32_t to);

/* The setpoint jumps to `to` (a step; any move is forgotten). */
void smooth_setpoint_jump(smooth_setpoint_t *s, int32_t to);

/* The setpoint at now_ms (not before the last call's time). */
int32_t smooth_setpoint_at(smooth_setpoint_t *s, uint32_t now_ms);

/* A move is in progress. */
uint8_t smooth_setpoint_moving(const smooth_setpoint_t *s);

#ifdef __cplusplus
}
#endif

#endif
