/* Unit tests: coordinated moves (lib/src/step_coord.h).
 * Golden data: the definition of the coordinated move in issue 13 ("position_i = floor(D_i s(t))
 * with one s(t) running from 0 to 1"), with s(t) the closed form of constant acceleration of the
 * profile, x(t) = v0 t + a t^2/2, the cruise line and the mirrored deceleration (the lab handout's
 * "uniform acceleration, constant speed and uniform deceleration"), computed here in long double
 * independently of lib/; the profile's limits are the minima of each axis's own limits scaled by
 * D_m/D_i (computed here too). Every command is run through step_queue.h's executor (the functions
 * the step interrupt calls). */
#include "cmocka_all.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "step_coord.h"
#include "step_queue.h"

#define TEST_RNG_SEED 0x9E3779B97F4A7C15ULL
#include "closed_form.h" /* the closed form, urand/lrand */

/* ---- the closed form of s(t) (closed_form.h), of the parameters as the planner holds them:
 * floats, as on the AVR ------------------------------------------------------------------- */
typedef closed_t profile_t;

static profile_t profile_of(double v0, double vmax, double a, uint32_t d)
{
    return closed_plan((float)v0, (float)vmax, (float)a, d);
}

/* time at which the profile has covered x master steps */
static long double time_at(const profile_t *c, long double x)
{
    return closed_time(c, x);
}

/* s(t) in [0, 1] */
static long double s_at(const profile_t *c, long double t)
{
    long double x;
    if (t <= 0.0L)
        return 0.0L;
    if (t >= c->tt)
        return 1.0L;
    if (t <= c->ta)
        x = c->v0 * t + 0.5L * c->a * t * t;
    else if (t <= c->tt - c->ta)
        x = c->xa + c->vp * (t - c->ta);
    else {
        long double u = c->tt - t;
        x = c->d - (c->v0 * u + 0.5L * c->a * u * u);
    }
    return x / c->d;
}

/* ---- running the commands ----------------------------------------------------------------- */
typedef struct {
    uint64_t *t; /* t[1..n]: whole-tick edge times */
    uint32_t n, cap;
    int8_t dir;
} axis_trace_t;

static void run_axis(step_coord_t *c, uint8_t i, axis_trace_t *tr)
{
    step_exec_t x;
    step_cmd_t cmd;
    uint64_t abs16 = 0x8000U; /* t = 0 at half a tick: edge ticks are round(F t) */
    tr->cap = c->d[i] + 1U;
    tr->t = calloc(tr->cap + 1U, sizeof *tr->t);
    assert_non_null(tr->t);
    tr->n = 0;
    tr->dir = 0;
    step_exec_init(&x, 0x8000U);
    while (step_coord_next(c, i, &cmd)) {
        assert_true(cmd.count >= 1U);
        step_exec_load(&x, &cmd);
        tr->dir = (cmd.flags & STEP_CMD_REVERSE) ? -1 : 1;
        while (x.left > 0U) {
            uint16_t edge;
            abs16 += (x.flags & STEP_CMD_WIDE) ? (uint64_t)x.rate << 16 : x.rate;
            edge = step_exec_next(&x);
            assert_int_equal(edge, (uint16_t)(abs16 >> 16));
            tr->n++;
            assert_true(tr->n <= tr->cap);
            tr->t[tr->n] = abs16 >> 16;
        }
    }
}

/* steps of tr made by tick T (edges at ticks <= T) */
static uint32_t steps_by(const axis_trace_t *tr, uint64_t T, uint32_t *hint)
{
    uint32_t k = *hint;
    while (k < tr->n && tr->t[k + 1U] <= T)
        k++;
    *hint = k;
    return k;
}

typedef struct {
    uint32_t axes_checked, edges;
    double worst_tick, worst_path; /* worst |edge - round(F t_k)|; worst |p - D s| */
} coord_result_t;

/* Plans, runs and checks one coordinated move: counts and directions, every edge of every axis
 * within 1 tick of round(F t) with D_i s(t) = k, the last edges on one tick (v0 = 0), and the path
 * bound at every edge of any axis: floor(D_j s(T - 1 tick)) <= p_j(T) <= floor(D_j s(T + 1 tick)). */
static coord_result_t check_move(uint8_t n, const ramp_params_t p[], const int32_t from[], const int32_t to[])
{
    step_coord_t c;
    axis_trace_t tr[STEP_COORD_MAX_AXES];
    profile_t pr;
    coord_result_t res = {0, 0, 0.0, 0.0};
    uint32_t d[STEP_COORD_MAX_AXES], dm = 0;
    double v0 = 0, vmax = 0, a = 0, F = (double)p[0].tick_hz;
    uint8_t i, j, first = 1;
    uint64_t last = 0;
    for (i = 0; i < n; i++) {
        d[i] = ramp_distance(from[i], to[i]);
        if (d[i] > dm)
            dm = d[i];
    }
    /* the profile's limits, from issue 13's rule: each axis's limits hold */
    for (i = 0; i < n; i++) {
        double k;
        if (d[i] == 0)
            continue;
        k = (double)dm / d[i];
        if (first || p[i].v0_sps * k < v0)
            v0 = p[i].v0_sps * k;
        if (first || p[i].vmax_sps * k < vmax)
            vmax = p[i].vmax_sps * k;
        if (first || p[i].accel_sps2 * k < a)
            a = p[i].accel_sps2 * k;
        first = 0;
    }
    {
        motion_status_t st = step_coord_plan(&c, n, p, from, to);
        if (st != MS_OK) {
            for (i = 0; i < n; i++)
                fprintf(stderr, "axis %u: %ld -> %ld v0 %g vmax %g accel %g\n", i, (long)from[i], (long)to[i],
                        p[i].v0_sps, p[i].vmax_sps, p[i].accel_sps2);
        }
        assert_int_equal(st, MS_OK);
    }
    assert_true(fabs(c.profile.vmax_sps - vmax) <= 1e-9 * vmax);
    assert_true(fabs(c.profile.accel_sps2 - a) <= 1e-9 * a);
    assert_true(fabs(c.profile.v0_sps - v0) <= 1e-9 * (v0 + 1.0));
    pr = profile_of(v0, vmax, a, dm);
    for (i = 0; i < n; i++) {
        uint32_t k;
        run_axis(&c, i, &tr[i]);
        assert_int_equal(tr[i].n, d[i]);
        assert_int_equal(step_coord_position(&c, i), to[i]);
        if (d[i] == 0)
            continue;
        assert_int_equal(tr[i].dir, to[i] > from[i] ? 1 : -1);
        for (k = 1; k <= d[i]; k++) {
            long double t = time_at(&pr, (long double)k * dm / d[i]);
            double err = (double)((long double)tr[i].t[k] - roundl(t * F));
            if (fabs(err) > fabs(res.worst_tick))
                res.worst_tick = err;
            if (fabs(err) > 1.0) {
                fprintf(stderr, "axis %u step %u of %u: edge %llu, round(F t) %.0Lf (D_m %u)\n", i, k, d[i],
                        (unsigned long long)tr[i].t[k], roundl(t * F), dm);
                fail();
            }
            if (k > 1)
                assert_true(tr[i].t[k] > tr[i].t[k - 1]);
        }
        if (v0 == 0.0) {
            if (last == 0)
                last = tr[i].t[d[i]];
            assert_int_equal(tr[i].t[d[i]], last); /* every axis ends on the same tick */
        }
        res.axes_checked++;
    }
    /* the path bound at every edge of any axis */
    for (i = 0; i < n; i++) {
        uint32_t hint[STEP_COORD_MAX_AXES] = {0, 0, 0}, k;
        for (k = 1; k <= tr[i].n; k++) {
            uint64_t T = tr[i].t[k];
            long double sl = s_at(&pr, ((long double)T - 1.0L) / F), sh = s_at(&pr, ((long double)T + 1.0L) / F);
            long double s = s_at(&pr, (long double)T / F);
            res.edges++;
            for (j = 0; j < n; j++) {
                uint32_t pj = steps_by(&tr[j], T, &hint[j]);
                long double lo = floorl(d[j] * sl), hi = floorl(d[j] * sh);
                double dev = (double)((long double)pj - d[j] * s);
                if (fabs(dev) > fabs(res.worst_path))
                    res.worst_path = dev;
                if ((long double)pj < lo || (long double)pj > hi) {
                    fprintf(stderr, "edge %u of axis %u at tick %llu: axis %u at %u, line says %.3Lf..%.3Lf\n", k, i,
                            (unsigned long long)T, j, pj, d[j] * sl, d[j] * sh);
                    fail();
                }
            }
        }
    }
    for (i = 0; i < n; i++)
        free(tr[i].t);
    return res;
}

static ramp_params_t params(double v0, double vmax, double a)
{
    ramp_params_t p;
    p.v0_sps = v0;
    p.vmax_sps = vmax;
    p.accel_sps2 = a;
    p.tick_hz = 16000000UL;
    return p;
}

/* ---- tests -------------------------------------------------------------------------------- */

/* issue 13's example: move x1000 y500; y's lower vmax (5,000) limits the profile to 10,000 master
 * steps/s, its accel (20,000) to 40,000 master steps/s^2 */
static void profile_takes_each_axis_limit(void **state)
{
    ramp_params_t p[2] = {params(0, 20000, 50000), params(0, 5000, 20000)}, q;
    uint32_t d[2] = {1000, 500};
    (void)state;
    assert_int_equal(step_coord_profile(2, p, d, &q), MS_OK);
    assert_true(q.vmax_sps == 10000.0);
    assert_true(q.accel_sps2 == 40000.0);
    assert_true(q.v0_sps == 0.0);
    /* an axis that does not move sets no limit */
    d[1] = 0;
    assert_int_equal(step_coord_profile(2, p, d, &q), MS_OK);
    assert_true(q.vmax_sps == 20000.0 && q.accel_sps2 == 50000.0);
}

static void example_moves(void **state)
{
    ramp_params_t p[3] = {params(0, 20000, 50000), params(0, 20000, 50000), params(0, 20000, 50000)};
    int32_t from[3] = {0, 0, 0}, to[3] = {1000, 500, 0};
    coord_result_t r;
    (void)state;
    r = check_move(2, p, from, to);
    assert_int_equal(r.axes_checked, 2);
    to[2] = -333;
    r = check_move(3, p, from, to);
    assert_int_equal(r.axes_checked, 3);
    /* the diagonal: both axes on the same ticks */
    to[0] = 20000;
    to[1] = -20000;
    to[2] = 7;
    (void)check_move(3, p, from, to);
    /* a long move at the bench's speed */
    p[0] = p[1] = p[2] = params(0, 50000, 250000);
    to[0] = 400000;
    to[1] = 150001;
    to[2] = -399999;
    r = check_move(3, p, from, to);
    assert_true(fabs(r.worst_tick) <= 1.0);
}

static void random_moves(void **state)
{
    int k;
    double worst_tick = 0, worst_path = 0;
    (void)state;
    for (k = 0; k < 400; k++) {
        ramp_params_t p[3];
        int32_t from[3], to[3];
        uint8_t i, n = (uint8_t)(1 + (k % 3));
        int zero_v0 = k % 4 != 3;
        coord_result_t r;
        for (i = 0; i < n; i++) {
            double vmax = lrand(500, 60000), a = lrand(2000, 500000);
            p[i] = params(zero_v0 ? 0.0 : urand(0, 0.5) * vmax, vmax, a);
            from[i] = (int32_t)urand(-1e6, 1e6);
            to[i] = from[i] + (int32_t)(urand(-1, 1) * lrand(1, k < 380 ? 30000 : 300000));
        }
        if (ramp_distance(from[0], to[0]) == 0)
            to[0] = from[0] + 1;
        /* keep the axes' ratio within what the plan accepts (C_i = 2 F^2 65536 / a_p * D_m / D_i
         * below 2^62 u^2, step_coord.h; the refusal is tested separately) */
        for (;;) {
            uint32_t dm = 0, j, bad = n;
            double ap = 0;
            for (j = 0; j < n; j++)
                if (ramp_distance(from[j], to[j]) > dm)
                    dm = ramp_distance(from[j], to[j]);
            for (j = 0; j < n; j++) {
                uint32_t dj = ramp_distance(from[j], to[j]);
                if (dj != 0 && (ap == 0 || p[j].accel_sps2 * dm / dj < ap))
                    ap = p[j].accel_sps2 * dm / dj;
            }
            for (j = 0; j < n; j++) {
                uint32_t dj = ramp_distance(from[j], to[j]);
                if (dj != 0 && 2.0 * 16e6 * 16e6 * 65536.0 / ap * dm / dj >= 0.98 * 4611686018427387904.0)
                    bad = j;
            }
            if (bad == n)
                break;
            to[bad] = from[bad];
        }
        r = check_move(n, p, from, to);
        if (fabs(r.worst_tick) > fabs(worst_tick))
            worst_tick = r.worst_tick;
        if (fabs(r.worst_path) > fabs(worst_path))
            worst_path = r.worst_path;
    }
    print_message("random coordinated moves: worst edge %+.0f tick, worst path %+.4f step\n", worst_tick, worst_path);
    assert_true(fabs(worst_path) < 1.01);
}

/* a test that can fail: the path check catches axes that do not share s(t) (y planned on its own) */
static void path_check_sees_an_uncoordinated_axis(void **state)
{
    ramp_params_t p[2] = {params(0, 20000, 50000), params(0, 20000, 50000)};
    step_coord_t c;
    int32_t from[2] = {0, 0}, to[2] = {1000, 500};
    profile_t pr = profile_of(0, 20000, 50000, 1000);
    step_exact_t alone;
    step_cmd_t cmd;
    step_exec_t x;
    uint64_t abs16 = 0x8000U;
    uint32_t k = 0, off = 0;
    (void)state;
    assert_int_equal(step_coord_plan(&c, 2, p, from, to), MS_OK);
    /* y as an independent move (its own full vmax and accel) breaks the line */
    alone.max_cmd_ticks = 0;
    assert_int_equal(step_exact_set_params(&alone, &p[1]), MS_OK);
    step_exact_reset(&alone, 0);
    assert_int_equal(step_exact_plan(&alone, 500), MS_OK);
    step_exec_init(&x, 0x8000U);
    while (step_exact_next(&alone, &cmd)) {
        step_exec_load(&x, &cmd);
        while (x.left > 0U) {
            abs16 += x.rate;
            (void)step_exec_next(&x);
            k++;
            if (fabsl((long double)k - 500.0L * s_at(&pr, (long double)(abs16 >> 16) / 16e6L)) > 1.01L)
                off++;
        }
    }
    assert_true(off > 100U);
}

/* MultiAxisStepper pulses an axis that moves as far as the master from the master's interrupt: that is
 * right only if its commands are the master's, but for the direction */
static void equal_distance_axes_get_the_masters_commands(void **state)
{
    ramp_params_t p[3] = {params(0, 30000, 90000), params(0, 30000, 90000), params(0, 30000, 90000)};
    step_coord_t c;
    int32_t from[3] = {100, -5, 7}, to[3] = {20100, -20005, 10007};
    step_cmd_t a, b;
    uint32_t n = 0;
    (void)state;
    assert_int_equal(step_coord_plan(&c, 3, p, from, to), MS_OK);
    assert_int_equal(c.master, 0);
    for (;;) {
        uint8_t ka = step_coord_next(&c, 0, &a), kb = step_coord_next(&c, 1, &b);
        assert_int_equal(ka, kb);
        if (!ka)
            break;
        assert_int_equal(a.rate, b.rate);
        assert_int_equal(a.add, b.add);
        assert_int_equal(a.count, b.count);
        assert_int_equal(a.flags ^ b.flags, STEP_CMD_REVERSE);
        n++;
    }
    assert_true(n > 100U);
}

static void too_unequal_refused(void **state)
{
    ramp_params_t p[2] = {params(0, 20000, 50000), params(0, 20000, 50000)};
    step_coord_t c;
    int32_t from[2] = {0, 0}, to[2] = {100000, 1};
    (void)state;
    /* C_y = C_x 100000 >= 2^62 u^2 at 50,000 steps/s^2 (the limit is about 6,870:1) */
    assert_int_equal(step_coord_plan(&c, 2, p, from, to), MS_ERR_COORD_RATIO);
    to[0] = 6800;
    (void)check_move(2, p, from, to);
    to[0] = 6900;
    assert_int_equal(step_coord_plan(&c, 2, p, from, to), MS_ERR_COORD_RATIO);
    assert_string_not_equal(motion_status_text(MS_ERR_COORD_RATIO), "unknown status");
}

static void bad_input_refused(void **state)
{
    ramp_params_t p[3] = {params(0, 20000, 50000), params(0, 20000, 50000), params(0, 20000, 50000)}, q;
    step_coord_t c;
    int32_t from[3] = {5, 6, 7}, to[3] = {5, 6, 7};
    uint32_t d[3] = {1, 1, 1};
    (void)state;
    assert_int_equal(step_coord_plan(&c, 3, p, from, to), MS_ERR_OUT_OF_RANGE); /* nothing moves */
    assert_int_equal(step_coord_plan(&c, 0, p, from, to), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(step_coord_plan(&c, 4, p, from, to), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(step_coord_plan(NULL, 3, p, from, to), MS_ERR_NULL);
    to[0] = 100;
    p[1].tick_hz = 2000000UL; /* one timeline for all axes */
    assert_int_equal(step_coord_plan(&c, 3, p, from, to), MS_ERR_OUT_OF_RANGE);
    p[1].tick_hz = 16000000UL;
    p[2].accel_sps2 = -1.0;
    assert_int_equal(step_coord_plan(&c, 3, p, from, to), MS_ERR_ACCEL_NOT_POSITIVE);
    assert_int_equal(step_coord_profile(3, p, d, &q), MS_ERR_ACCEL_NOT_POSITIVE);
}

/* stop: every axis decelerates to rest and ends where step_coord_target says */
static void stop_decelerates_every_axis(void **state)
{
    ramp_params_t p[3] = {params(0, 20000, 50000), params(0, 20000, 50000), params(0, 20000, 50000)};
    step_coord_t c;
    int32_t from[3] = {0, 0, 0}, to[3] = {100000, 50000, -25000};
    step_cmd_t cmd;
    uint8_t i;
    int k;
    (void)state;
    assert_int_equal(step_coord_plan(&c, 3, p, from, to), MS_OK);
    for (k = 0; k < 40; k++)
        for (i = 0; i < 3; i++)
            assert_int_equal(step_coord_next(&c, i, &cmd), 1);
    step_coord_stop(&c);
    for (i = 0; i < 3; i++) {
        int32_t tgt = step_coord_target(&c, i);
        assert_true(i == 2 ? (tgt < 0 && tgt > to[2]) : (tgt > 0 && tgt < to[i]));
        while (step_coord_next(&c, i, &cmd))
            ;
        assert_int_equal(step_coord_position(&c, i), tgt);
        assert_int_equal(step_coord_busy(&c, i), 0);
    }
    /* at rest on the line: y = x / 2, z = -x / 4, within a step */
    assert_true(labs((long)step_coord_position(&c, 1) - step_coord_position(&c, 0) / 2) <= 1);
    assert_true(labs((long)step_coord_position(&c, 2) + step_coord_position(&c, 0) / 4) <= 1);
    /* halt: an axis forgets the rest of its part at once */
    assert_int_equal(step_coord_plan(&c, 3, p, from, to), MS_OK);
    assert_int_equal(step_coord_next(&c, 1, &cmd), 1);
    step_coord_halt(&c, 1, 3);
    assert_int_equal(step_coord_busy(&c, 1), 0);
    assert_int_equal(step_coord_next(&c, 1, &cmd), 0);
    assert_int_equal(step_coord_position(&c, 1), 3);
    assert_int_equal(step_coord_target(&c, 1), 3);
    assert_int_equal(step_coord_busy(&c, 0), 1);
}

/* A stop after any number of commands, during the deceleration too, leaves every axis at rest at or
 * before its target, never past it (the sketch's `stop` of `move x1000 y500 z250` ended at x 1001
 * when an axis's rounded-up stopping distance exceeded its steps left). */
static void stop_never_passes_a_target(void **state)
{
    ramp_params_t p[3] = {params(0, 10000, 10000), params(0, 10000, 10000), params(0, 10000, 10000)};
    int32_t from[3] = {0, 0, 0}, to[3] = {1000, 500, -250};
    int k;
    (void)state;
    for (k = 1; k < 400; k++) {
        step_coord_t c;
        step_cmd_t cmd;
        uint8_t i;
        int j;
        assert_int_equal(step_coord_plan(&c, 3, p, from, to), MS_OK);
        for (j = 0; j < k; j++)
            for (i = 0; i < 3; i++)
                (void)step_coord_next(&c, i, &cmd);
        step_coord_stop(&c);
        for (i = 0; i < 3; i++) {
            int32_t at;
            while (step_coord_next(&c, i, &cmd))
                ;
            at = step_coord_position(&c, i);
            if (to[i] > 0 ? at > to[i] : at < to[i])
                fail_msg("stop after %d commands: axis %u at %d, past its target %d", k, i, at, to[i]);
        }
    }
}

/* step_coord_rewind (a StepperGroup's stop at a cut of its queues): every axis taken back from
 * further on to a command boundary and then stopped gives the same commands, bit for bit, and the
 * same targets as a coordinated move that had handed out only the kept commands and stopped there
 * (the reference: step_coord_stop on the plain planner, no rewind). Random moves of 2 and 3 axes,
 * cuts in the acceleration, the cruise and the deceleration. */
#define REWIND_MAX_CMDS 4000
typedef struct {
    step_cmd_t cmd[REWIND_MAX_CMDS];
    uint32_t n;
} cmd_list_t;

static void hand_out_until(step_coord_t *c, uint8_t i, int64_t t16, cmd_list_t *l)
{
    step_cmd_t cmd;
    while (step_coord_horizon16(c, i) < t16 && step_coord_next(c, i, &cmd)) {
        assert_true(l->n < REWIND_MAX_CMDS);
        l->cmd[l->n++] = cmd;
    }
}

static void rest_of(step_coord_t *c, uint8_t i, cmd_list_t *l)
{
    step_cmd_t cmd;
    l->n = 0;
    while (step_coord_next(c, i, &cmd)) {
        assert_true(l->n < REWIND_MAX_CMDS);
        l->cmd[l->n++] = cmd;
    }
}

static void rewind_then_stop_is_the_stop_at_the_boundary(void **state)
{
    static cmd_list_t kept[STEP_COORD_MAX_AXES], more[STEP_COORD_MAX_AXES], ra, rb;
    int trial, cuts = 0;
    (void)state;
    for (trial = 0; trial < 60; trial++) {
        uint8_t n = (uint8_t)(2 + trial % 2), i;
        ramp_params_t p[STEP_COORD_MAX_AXES];
        int32_t from[STEP_COORD_MAX_AXES], to[STEP_COORD_MAX_AXES];
        step_coord_t a, b;
        double vmax = lrand(2000.0, 40000.0);
        for (i = 0; i < n; i++) {
            p[i] = params(0, vmax * urand(0.5, 1.0), lrand(5000.0, 200000.0));
            from[i] = (int32_t)urand(-1000.0, 1000.0);
            to[i] = from[i] + (int32_t)(urand(0.0, 1.0) < 0.5 ? -1 : 1) * (int32_t)lrand(200.0, 40000.0);
        }
        if (step_coord_plan(&a, n, p, from, to) != MS_OK)
            continue;
        {
            /* the cut at a random time of the move, and 1-30 ms of commands beyond it dropped */
            int64_t t_end = a.ax[a.master].t_end16;
            int64_t t_cut = (int64_t)(urand(0.02, 0.95) * (double)t_end);
            int64_t t_more = t_cut + (int64_t)(urand(1.0, 30.0) * 16000.0 * 65536.0);
            b = a;
            for (i = 0; i < n; i++) {
                kept[i].n = more[i].n = 0;
                hand_out_until(&a, i, t_cut, &kept[i]);
                hand_out_until(&b, i, t_more, &more[i]);
            }
            for (i = 0; i < n; i++) {
                uint32_t k, steps = 0;
                int64_t t16 = 0;
                motion_status_t st;
                /* b handed out what a did, and then some */
                assert_true(more[i].n >= kept[i].n);
                for (k = 0; k < kept[i].n; k++)
                    assert_memory_equal(&kept[i].cmd[k], &more[i].cmd[k], sizeof(step_cmd_t));
                if (more[i].n == kept[i].n || kept[i].n == 0)
                    continue;
                for (k = kept[i].n; k < more[i].n; k++) {
                    steps += more[i].cmd[k].count;
                    t16 += step_exact_cmd_time16(&more[i].cmd[k]);
                }
                st = step_coord_rewind(&b, i, steps, t16, kept[i].cmd[kept[i].n - 1U].count);
                if (st != MS_OK)
                    fail_msg("trial %d axis %u: rewind of %u steps refused (%d)", trial, i, (unsigned)steps, (int)st);
                cuts++;
                assert_int_equal(step_coord_position(&b, i), step_coord_position(&a, i));
            }
            step_coord_stop(&a);
            step_coord_stop(&b);
            for (i = 0; i < n; i++) {
                uint32_t k;
                assert_int_equal(step_coord_target(&b, i), step_coord_target(&a, i));
                rest_of(&a, i, &ra);
                rest_of(&b, i, &rb);
                if (ra.n != rb.n)
                    fail_msg("trial %d axis %u: %u commands after the stop, %u after rewind and stop", trial, i,
                             (unsigned)ra.n, (unsigned)rb.n);
                for (k = 0; k < ra.n; k++)
                    assert_memory_equal(&ra.cmd[k], &rb.cmd[k], sizeof(step_cmd_t));
            }
        }
    }
    /* the refusals: no axis, more steps than handed out */
    {
        ramp_params_t p[2] = {params(0, 10000, 50000), params(0, 10000, 50000)};
        int32_t from[2] = {0, 0}, to[2] = {5000, 2000};
        step_coord_t c;
        step_cmd_t cmd;
        assert_int_equal(step_coord_plan(&c, 2, p, from, to), MS_OK);
        assert_int_equal(step_coord_next(&c, 0, &cmd), 1);
        assert_int_equal(step_coord_rewind(&c, 2, 1, 0, 1), MS_ERR_OUT_OF_RANGE);
        assert_int_equal(step_coord_rewind(&c, 0, cmd.count, step_exact_cmd_time16(&cmd), 1), MS_ERR_OUT_OF_RANGE);
        assert_int_equal(step_coord_position(&c, 0), (int32_t)cmd.count);
    }
    assert_true(cuts > 60);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(profile_takes_each_axis_limit),
        cmocka_unit_test(example_moves),
        cmocka_unit_test(random_moves),
        cmocka_unit_test(path_check_sees_an_uncoordinated_axis),
        cmocka_unit_test(equal_distance_axes_get_the_masters_commands),
        cmocka_unit_test(too_unequal_refused),
        cmocka_unit_test(stop_never_passes_a_target),
        cmocka_unit_test(bad_input_refused),
        cmocka_unit_test(stop_decelerates_every_axis),
        cmocka_unit_test(rewind_then_stop_is_the_stop_at_the_boundary),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
