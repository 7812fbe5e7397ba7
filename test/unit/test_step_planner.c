/* Unit tests: the step engine's pure parts (lib/src/step_queue.h, step_exact.h, step_planner.h).
 * Golden data: the closed form of constant acceleration, t_n = (sqrt(v0^2 + 2 a n) - v0)/a with the
 * cruise line and the mirrored deceleration (the lab handout's "uniform acceleration, constant
 * speed and uniform deceleration"), computed here in long double independently of lib/; for the
 * other ramps, their own whole-tick intervals from ramp_next (what `motionsim ramp --integer-ticks`
 * prints), which the commands must reproduce exactly; the lab handout's Leib checkpoint. */
#include "cmocka_all.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "ramp.h"
#include "step_planner.h"
#include "step_queue.h"

#include "closed_form.h" /* the closed form, urand/lrand */

/* two step commands the same, field by field */
static void assert_cmd_equal(const step_cmd_t *a, const step_cmd_t *b)
{
    assert_int_equal(a->rate, b->rate);
    assert_int_equal(a->add, b->add);
    assert_int_equal(a->count, b->count);
    assert_int_equal(a->flags, b->flags);
}

/* ---- helpers ------------------------------------------------------------------------------ */

/* Runs commands through the executor (the same functions the step interrupt calls). Records the
 * absolute whole-tick time of every step (64-bit) and its direction. */
typedef struct {
    uint64_t *t;   /* t[1..n] */
    int8_t *dir;
    uint32_t n, cap;
    uint32_t commands;
    step_exec_t x;
    uint64_t abs16; /* absolute time, 2^-16 ticks */
} trace_t;

static void trace_init(trace_t *tr, uint32_t cap)
{
    tr->t = calloc(cap + 2U, sizeof *tr->t);
    tr->dir = calloc(cap + 2U, sizeof *tr->dir);
    assert_non_null(tr->t);
    assert_non_null(tr->dir);
    tr->n = 0;
    tr->cap = cap;
    tr->commands = 0;
    step_exec_init(&tr->x, 0x8000U);
    tr->abs16 = 0x8000U;
}

static void trace_free(trace_t *tr)
{
    free(tr->t);
    free(tr->dir);
}

static void trace_cmd(trace_t *tr, const step_cmd_t *c)
{
    assert_true(c->count >= 1U);
    tr->commands++;
    step_exec_load(&tr->x, c);
    while (tr->x.left > 0U) {
        uint64_t before = tr->x.acc;
        uint16_t edge;
        if (tr->x.flags & STEP_CMD_WIDE) {
            assert_true(c->rate > 0xFFFFU); /* WIDE only where a normal command cannot hold it */
            tr->abs16 += (uint64_t)tr->x.rate << 16;
        } else {
            tr->abs16 += tr->x.rate;
        }
        edge = step_exec_next(&tr->x);
        (void)before;
        assert_int_equal(edge, (uint16_t)(tr->abs16 >> 16)); /* the 16-bit view agrees */
        tr->n++;
        assert_true(tr->n <= tr->cap);
        tr->t[tr->n] = tr->abs16 >> 16;
        tr->dir[tr->n] = (c->flags & STEP_CMD_REVERSE) ? -1 : 1;
    }
}

/* hands commands to the trace until it holds at least `steps` steps */
static void drain_steps(step_planner_t *pl, trace_t *tr, uint32_t steps)
{
    step_cmd_t c;
    while (tr->n < steps && step_planner_next(pl, &c))
        trace_cmd(tr, &c);
    assert_true(tr->n >= steps);
}

static uint32_t drain(step_planner_t *pl, trace_t *tr, uint32_t max_cmds)
{
    step_cmd_t c;
    uint32_t k = 0;
    while (k < max_cmds && step_planner_next(pl, &c)) {
        trace_cmd(tr, &c);
        k++;
    }
    return k;
}

/* ---- the queue ---------------------------------------------------------------------------- */

static void queue_fifo_full_empty(void **state)
{
    step_queue_t q;
    step_cmd_t c = {0, 0, 1, 0}, o;
    uint32_t i;
    (void)state;
    step_queue_init(&q);
    assert_int_equal(step_queue_used(&q), 0);
    assert_int_equal(step_queue_pop(&q, &o), 0);
    for (i = 0; i < STEP_QUEUE_LEN - 1U; i++) {
        c.rate = i;
        assert_int_equal(step_queue_push(&q, &c), 1);
    }
    assert_int_equal(step_queue_free(&q), 0);
    assert_int_equal(step_queue_push(&q, &c), 0); /* full: refused, nothing overwritten */
    for (i = 0; i < STEP_QUEUE_LEN - 1U; i++) {
        assert_int_equal(step_queue_pop(&q, &o), 1);
        assert_int_equal(o.rate, i);
    }
    assert_int_equal(step_queue_pop(&q, &o), 0);
    /* wrap-around many times */
    for (i = 0; i < 1000U; i++) {
        c.rate = i;
        assert_int_equal(step_queue_push(&q, &c), 1);
        assert_int_equal(step_queue_pop(&q, &o), 1);
        assert_int_equal(o.rate, i);
    }
    assert_int_equal(step_queue_push(&q, &c), 1);
    step_queue_clear(&q);
    assert_int_equal(step_queue_used(&q), 0);
}

/* rate + add per step, in 16.16: 2.5, 3.75, 5.0 ticks -> edges at floor(0.5 + sums) */
static void executor_follows_its_formula(void **state)
{
    step_exec_t x;
    step_cmd_t c = {0x28000U, 0x14000, 3, 0};
    (void)state;
    step_exec_init(&x, 0x8000U);
    step_exec_load(&x, &c);
    assert_int_equal(step_exec_next(&x), 3);  /* 0.5 + 2.5 */
    assert_int_equal(step_exec_next(&x), 6);  /* 3.0 + 3.75 = 6.75 */
    assert_int_equal(step_exec_next(&x), 11); /* 6.75 + 5.0 = 11.75 */
    assert_int_equal(x.left, 0);
    c.rate = 100000U; /* WIDE: whole ticks, the fraction stays */
    c.add = 0;
    c.count = 1;
    c.flags = STEP_CMD_WIDE;
    step_exec_load(&x, &c);
    assert_int_equal(step_exec_next(&x), (uint16_t)(11U + 100000U));
}

/* ---- exact: the closed form, every step --------------------------------------------------- */

/* every step of tr (d steps) within one tick of the closed form of (v0, vmax, a) as the board holds
 * them (floats); the worst error, in ticks, into *worst_out (may be 0) */
static void check_closed_form(const trace_t *tr, double v0, double vmax, double a, uint32_t tick_hz, uint32_t d,
                              uint32_t *worst_out)
{
    closed_t cf = closed_plan((float)v0, (float)vmax, (float)a, d);
    uint32_t n;
    for (n = 1; n <= d; n++) {
        long double want = floorl(closed_time(&cf, n) * tick_hz + 0.5L);
        long double err = (long double)tr->t[n] - (long double)want;
        if (fabsl(err) > 1.0L)
            fail_msg("v0 %g vmax %g a %g F %u D %u: step %u at %llu ticks, closed form %.0Lf", v0, vmax, a, tick_hz, d, n,
                     (unsigned long long)tr->t[n], want);
        if (worst_out && fabsl(err) > *worst_out)
            *worst_out = (uint32_t)fabsl(err);
    }
}

static void check_exact_move(double v0, double vmax, double a, uint32_t tick_hz, uint32_t d, int32_t from,
                             uint32_t *worst_out)
{
    ramp_params_t p = {(float)v0, (float)vmax, (float)a, tick_hz};
    step_planner_t pl;
    trace_t tr;
    uint32_t n;
    int32_t to = (int32_t)((int64_t)from + (from > 0 ? -(int64_t)d : (int64_t)d));
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, from), MS_OK);
    assert_int_equal(step_planner_move(&pl, to), MS_OK);
    trace_init(&tr, d);
    drain(&pl, &tr, UINT32_MAX);
    assert_int_equal(tr.n, d);
    assert_int_equal(step_planner_position(&pl), to);
    check_closed_form(&tr, v0, vmax, a, tick_hz, d, worst_out);
    for (n = 1; n <= d; n++)
        assert_int_equal(tr.dir[n], to > from ? 1 : -1);
    trace_free(&tr);
}

static void exact_reference_moves_every_step(void **state)
{
    /* the benchmark's reference move: 20,000 steps, accel vmax^2/10,000 (5,000-step ramps) */
    const double rates[] = {5000, 20000, 50000, 70000, 100000, 160000};
    uint32_t i, worst = 0;
    (void)state;
    for (i = 0; i < sizeof rates / sizeof rates[0]; i++)
        check_exact_move(0, rates[i], rates[i] * rates[i] / 10000.0, 16000000, 20000, 0, &worst);
    /* the sketch's defaults, and moves of 1, 2, 3 steps */
    check_exact_move(0, 20000, 50000, 16000000, 20000, 0, &worst);
    for (i = 1; i <= 3; i++)
        check_exact_move(0, 20000, 50000, 16000000, i, 0, &worst);
    assert_true(worst <= 1U);
}

static void exact_random_moves_every_step(void **state)
{
    uint32_t i, worst = 0;
    (void)state;
    for (i = 0; i < 3000U; i++) {
        uint32_t f = (i % 3U) == 0 ? 2000000U : 16000000U;
        double a = lrand(50, 3e6);
        double vmax = lrand(20, 160000);
        double v0 = (i % 4U) == 0 ? 0.0 : vmax * urand(0, 0.6);
        uint32_t d = (uint32_t)lrand(1, 60000);
        ramp_params_t p = {(float)v0, (float)vmax, (float)a, f};
        step_planner_t pl;
        if (step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0) != MS_OK)
            continue; /* outside step_exact's stated limits */
        check_exact_move(v0, vmax, a, f, d, (i & 1U) ? 0 : 1000, &worst);
    }
    assert_true(worst <= 1U);
}

/* The timeline itself (before the executor's flooring): every edge of a normal command lies less
 * than half a tick from the closed form (F t_n, on a timeline that starts half a tick in). Half a
 * tick is what an edge may be early for step_coord's path bound, D s(T + 1 tick); the span rule
 * (step_exact.c's FIT_GAIN) keeps the quadratics well inside it. */
static void exact_timeline_within_half_a_tick(void **state)
{
    uint64_t saved = rng_state;
    long double worst = 0.0L;
    uint32_t i;
    (void)state;
    rng_state = 0x9E3779B97F4A7C15ULL;
    for (i = 0; i < 1500U; i++) {
        uint32_t f = (i % 3U) == 0 ? 2000000U : 16000000U;
        double a = lrand(50, 3e6);
        double vmax = lrand(20, 160000);
        double v0 = (i % 4U) == 0 ? 0.0 : vmax * urand(0, 0.6);
        uint32_t d = (uint32_t)lrand(1, 60000), n = 0;
        ramp_params_t p = {(float)v0, (float)vmax, (float)a, f};
        step_planner_t pl;
        step_cmd_t c;
        closed_t cf;
        uint64_t abs16 = 0x8000U;
        if (step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0) != MS_OK)
            continue;
        assert_int_equal(step_planner_move(&pl, (int32_t)d), MS_OK);
        cf = closed_plan((float)v0, (float)vmax, (float)a, d);
        while (step_planner_next(&pl, &c)) {
            uint32_t rate = c.rate, k;
            for (k = 0; k < c.count; k++) {
                long double err;
                n++;
                if (c.flags & STEP_CMD_WIDE) {
                    abs16 += (uint64_t)rate << 16; /* whole ticks: rounded by design */
                    continue;
                }
                abs16 += rate;
                rate += (uint32_t)c.add;
                err = (long double)abs16 / 65536.0L - (closed_time(&cf, n) * f + 0.5L);
                if (fabsl(err) > worst)
                    worst = fabsl(err);
                if (fabsl(err) >= 0.5L)
                    fail_msg("v0 %g vmax %g a %g F %u D %u: step %u %.3Lf ticks from the closed form", v0, vmax, a, f, d,
                             n, err);
            }
        }
        assert_int_equal(n, d);
    }
    rng_state = saved;
    assert_true(worst > 0.0L);
}

/* 2^31 - 1 steps: every acceleration and deceleration step, and the cruise at every command's end
 * and at random steps in between (no drift over 2 billion steps). */
static void exact_longest_move_no_drift(void **state)
{
    ramp_params_t p = {0.0f, 100000.0f, 1000000.0f, 16000000};
    step_planner_t pl;
    step_cmd_t c;
    step_exec_t x;
    closed_t cf;
    uint64_t abs16 = 0x8000U, n = 0, checked = 0;
    const uint32_t d = 2147483647U;
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, INT32_MIN), MS_OK);
    assert_int_equal(step_planner_move(&pl, -1), MS_OK);
    cf = closed_plan(0, 100000, 1000000, d);
    step_exec_init(&x, 0x8000U);
    while (step_planner_next(&pl, &c)) {
        uint8_t ramping = n < 6000U || n + 6000U > d;
        uint64_t end;
        if (!ramping && !(c.flags & STEP_CMD_WIDE) && c.add == 0) {
            /* cruise: jump to the command's end in one go */
            abs16 += (uint64_t)c.rate * c.count;
            n += c.count;
            end = abs16 >> 16;
            if (fabsl((long double)end - floorl(closed_time(&cf, (uint32_t)n) * 16e6L + 0.5L)) > 1.0L)
                fail_msg("cruise step %llu at %llu ticks", (unsigned long long)n, (unsigned long long)end);
            checked++;
            continue;
        }
        step_exec_load(&x, &c);
        while (x.left > 0U) {
            abs16 += (x.flags & STEP_CMD_WIDE) ? (uint64_t)x.rate << 16 : x.rate;
            (void)step_exec_next(&x);
            n++;
            if (fabsl((long double)(abs16 >> 16) - floorl(closed_time(&cf, (uint32_t)n) * 16e6L + 0.5L)) > 1.0L)
                fail_msg("step %llu at %llu ticks", (unsigned long long)n, (unsigned long long)(abs16 >> 16));
            checked++;
        }
    }
    assert_true(n == d);
    assert_int_equal(step_planner_position(&pl), -1);
    assert_true(checked > 12000U);
}

/* ---- simplistic, Leib, sigmoid: the algorithm's own whole ticks, exactly ------------------ */

static void check_stepwise_move(step_planner_t *pl, ramp_t *ref, uint32_t d)
{
    trace_t tr;
    ramp_step_t s;
    uint64_t t = 0;
    uint32_t n = 0;
    trace_init(&tr, d);
    drain(pl, &tr, UINT32_MAX);
    assert_int_equal(tr.n, d);
    while (ramp_next(ref, &s)) {
        n++;
        t += s.whole_ticks != 0 ? s.whole_ticks : 1U;
        if (tr.t[n] != t)
            fail_msg("step %u: commands give %llu ticks, the ramp %llu", n, (unsigned long long)tr.t[n],
                     (unsigned long long)t);
    }
    assert_int_equal(n, d);
    trace_free(&tr);
}

static void stepwise_random_moves_exact_ticks(void **state)
{
    uint32_t i;
    static uint16_t table[400];
    (void)state;
    for (i = 0; i < 3000U; i++) {
        step_planner_t pl;
        ramp_t ref;
        uint32_t d = (uint32_t)lrand(1, 30000);
        int32_t from = (int32_t)urand(-1e6, 1e6), to = (i & 1U) ? from + (int32_t)d : from - (int32_t)d;
        if (i % 3U == 2U) {
            ramp_sigmoid_params_t sp;
            sp.len = (uint16_t)urand(2, 400);
            sp.hold = (uint16_t)urand(1, 6);
            sp.timer_hz = 2000000;
            sp.fmin_hz = (float)urand(40, 1000);
            sp.fmax_hz = sp.fmin_hz + (float)lrand(10, 30000);
            sp.flex = (float)urand(0.5, 10);
            if (ramp_sigmoid_fill(&sp, table, 400) != MS_OK)
                continue;
            assert_int_equal(step_planner_init_sigmoid(&pl, &sp, table, sp.len, from), MS_OK);
            assert_int_equal(ramp_plan_sigmoid(&ref, &sp, table, sp.len, from, to), MS_OK);
        } else {
            ramp_algo_t algo = (i % 3U) == 0 ? RAMP_ALGO_LEIB : RAMP_ALGO_SIMPLISTIC;
            double vmax = lrand(20, 30000);
            ramp_params_t p = {(float)(vmax * urand(0.01, 0.5)), (float)vmax, (float)lrand(10, 1e6), 2000000};
            if (step_planner_init_trapezoid(&pl, algo, &p, from) != MS_OK)
                continue;
            assert_int_equal(ramp_plan(&ref, algo, &p, from, to), MS_OK);
        }
        assert_int_equal(step_planner_move(&pl, to), MS_OK);
        check_stepwise_move(&pl, &ref, d);
        assert_int_equal(step_planner_position(&pl), to);
    }
}

/* The longest moves (2^31 - 1 steps, both ways, across zero) of simplistic, Leib and sigmoid:
 * every step of the ramps and the end of every cruise command lands on the algorithm's own
 * whole-tick time (ramp_next stepped alongside, its cruise skipped as far as the command's),
 * so nothing drifts over 2^31 steps and the position ends exactly on the target. The commands
 * may cover any time here (max_cmd_ticks raised), to keep the test's command count small. */
static void stepwise_longest_moves_no_drift(void **state)
{
    static uint16_t table[300];
    unsigned c;
    (void)state;
    for (c = 0; c < 6U; c++) {
        step_planner_t pl;
        ramp_t ref;
        step_cmd_t cmd;
        step_exec_t x;
        uint64_t abs16 = 0x8000U, t = 0, n = 0, checked = 0;
        const uint32_t d = 2147483647U;
        int32_t from = (c & 1U) ? -1 : INT32_MIN, to = (c & 1U) ? INT32_MIN : -1;
        if (c / 2U == 2U) {
            ramp_sigmoid_params_t sp = {300, 3, 500.0f, 20000.0f, 5.0f, 2000000};
            assert_int_equal(ramp_sigmoid_fill(&sp, table, 300), MS_OK);
            assert_int_equal(step_planner_init_sigmoid(&pl, &sp, table, 300, from), MS_OK);
            assert_int_equal(ramp_plan_sigmoid(&ref, &sp, table, 300, from, to), MS_OK);
        } else {
            ramp_algo_t algo = c / 2U == 0U ? RAMP_ALGO_LEIB : RAMP_ALGO_SIMPLISTIC;
            ramp_params_t p = {200.0f, 20000.0f, 100000.0f, 2000000};
            assert_int_equal(step_planner_init_trapezoid(&pl, algo, &p, from), MS_OK);
            assert_int_equal(ramp_plan(&ref, algo, &p, from, to), MS_OK);
        }
        pl.max_cmd_ticks = UINT32_MAX;
        assert_int_equal(step_planner_move(&pl, to), MS_OK);
        step_exec_init(&x, 0x8000U);
        while (step_planner_next(&pl, &cmd)) {
            uint32_t skip = ramp_cruise_skippable(&ref);
            ramp_step_t s;
            assert_true((cmd.flags & STEP_CMD_REVERSE) ? (c & 1U) : !(c & 1U));
            if (cmd.add == 0 && !(cmd.flags & STEP_CMD_WIDE) && skip >= cmd.count) {
                /* a cruise command: its end against the reference's cruise skipped as far */
                uint32_t w = ref.whole_ticks != 0 ? ref.whole_ticks : 1U;
                assert_int_equal(ramp_skip_cruise_at_most(&ref, cmd.count), cmd.count);
                t += (uint64_t)w * cmd.count;
                abs16 += (uint64_t)cmd.rate * cmd.count;
                n += cmd.count;
                if ((abs16 >> 16) != t)
                    fail_msg("case %u: cruise to step %llu at %llu ticks, the ramp %llu", c, (unsigned long long)n,
                             (unsigned long long)(abs16 >> 16), (unsigned long long)t);
                checked++;
                continue;
            }
            step_exec_load(&x, &cmd);
            while (x.left > 0U) {
                abs16 += (x.flags & STEP_CMD_WIDE) ? (uint64_t)x.rate << 16 : x.rate;
                (void)step_exec_next(&x);
                assert_int_equal(ramp_next(&ref, &s), 1);
                t += s.whole_ticks != 0 ? s.whole_ticks : 1U;
                n++;
                if ((abs16 >> 16) != t)
                    fail_msg("case %u: step %llu at %llu ticks, the ramp %llu", c, (unsigned long long)n,
                             (unsigned long long)(abs16 >> 16), (unsigned long long)t);
                checked++;
            }
        }
        assert_true(n == d);
        assert_int_equal(ramp_steps_left(&ref), 0);
        assert_int_equal(step_planner_position(&pl), to);
        assert_true(checked > 2000U);
    }
}

/* The lab handout's checkpoint (Leib, 0 -> 50, v0 1, vmax 20, a 10, F 1000 ticks/s): the first
 * intervals 218.218, 188.528 and 157.245 ticks, i.e. 218, 189 and 157 whole ticks in the queue. */
static void leib_lab_checkpoint_through_the_queue(void **state)
{
    ramp_params_t lab = {1.0, 20.0, 10.0, 1000};
    step_planner_t pl;
    trace_t tr;
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_LEIB, &lab, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 50), MS_OK);
    trace_init(&tr, 50);
    drain(&pl, &tr, UINT32_MAX);
    assert_int_equal(tr.n, 50);
    assert_int_equal(tr.t[1], 218);
    assert_int_equal(tr.t[2] - tr.t[1], 189);
    assert_int_equal(tr.t[3] - tr.t[2], 157);
    trace_free(&tr);
}

/* ---- stop and new targets while moving ---------------------------------------------------- */

/* steps -> positions; checks that the speed never jumps: between two steps in one direction the
 * speed 1/interval changes by at most twice what the acceleration allows over them (the first
 * steps of a run from rest are left out: there v0 and the ramp's first step set the speed; the
 * simplistic ramp changes its interval by a constant dp ticks instead: extra_ticks, and since its dp
 * depends on each move's length it is checked only around the replanning: check_from..check_to) */
static int32_t replay_positions(const trace_t *tr, int32_t from, double accel_sps2, double tick_hz,
                                double extra_ticks, uint32_t check_from, uint32_t check_to, uint32_t *reversals)
{
    int32_t pos = from;
    uint32_t n, run = 0;
    double a = accel_sps2 / (tick_hz * tick_hz); /* steps/tick^2 */
    *reversals = 0;
    for (n = 1; n <= tr->n; n++) {
        pos += tr->dir[n];
        run = (n >= 2U && tr->dir[n] != tr->dir[n - 1]) ? 1U : run + 1U;
        if (run == 1U && n >= 2U)
            (*reversals)++;
        if (run > 10U && n >= check_from && n <= check_to) {
            double i1 = (double)(tr->t[n - 1] - tr->t[n - 2]), i2 = (double)(tr->t[n] - tr->t[n - 1]);
            double dv = fabs(1.0 / i2 - 1.0 / i1), allowed = 2.0 * a * (i1 + i2) / 2.0 + (2.0 + extra_ticks) / (i1 * i2);
            if (dv > allowed)
                fail_msg("speed jump at step %u: intervals %.0f then %.0f ticks", n, i1, i2);
        }
    }
    return pos;
}

/* the simplistic ramp's interval step dp = (F/v0 - F/vmax)/S, S = (vmax^2 - v0^2)/(2a) (the lab's eq. 1) */
static double simplistic_dp(ramp_algo_t algo, const ramp_params_t *p)
{
    double s = (p->vmax_sps * p->vmax_sps - p->v0_sps * p->v0_sps) / (2.0 * p->accel_sps2);
    if (algo != RAMP_ALGO_SIMPLISTIC)
        return 0.0;
    return (p->tick_hz / p->v0_sps - p->tick_hz / p->vmax_sps) / floor(s);
}

static void retarget_case(ramp_algo_t algo, uint32_t tick_hz, int32_t first, uint32_t after_steps, int32_t second,
                          uint32_t want_reversals)
{
    ramp_params_t p = {algo == RAMP_ALGO_EXACT ? 0.0f : 200.0f, 20000.0f, 50000.0f, tick_hz};
    step_planner_t pl;
    trace_t tr;
    uint32_t rev;
    assert_int_equal(step_planner_init_trapezoid(&pl, algo, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, first), MS_OK);
    trace_init(&tr, 400000);
    drain_steps(&pl, &tr, after_steps);
    assert_int_equal(step_planner_move(&pl, second), MS_OK);
    assert_int_equal(step_planner_target(&pl), second);
    drain(&pl, &tr, UINT32_MAX);
    assert_false(step_planner_busy(&pl));
    assert_int_equal(replay_positions(&tr, 0, p.accel_sps2, tick_hz, simplistic_dp(algo, &p),
                                     algo == RAMP_ALGO_SIMPLISTIC ? after_steps - 3U : 0U,
                                     algo == RAMP_ALGO_SIMPLISTIC ? after_steps + 5U : UINT32_MAX, &rev),
                    second);
    assert_int_equal(step_planner_position(&pl), second);
    assert_int_equal(rev, want_reversals);
    trace_free(&tr);
}

static void new_target_while_moving(void **state)
{
    const ramp_algo_t algos[] = {RAMP_ALGO_EXACT, RAMP_ALGO_LEIB, RAMP_ALGO_SIMPLISTIC};
    uint32_t i;
    (void)state;
    for (i = 0; i < 3U; i++) {
        uint32_t f = algos[i] == RAMP_ALGO_EXACT ? 16000000U : 2000000U;
        /* at full speed after 6,000 steps (4,000 of acceleration); stopping distance 4,000 steps */
        retarget_case(algos[i], f, 100000, 6000, 60000, 0);  /* ahead, beyond the stopping distance */
        retarget_case(algos[i], f, 100000, 6000, 120000, 0); /* further */
        retarget_case(algos[i], f, 100000, 6000, 8000, 1);   /* ahead but too close: overshoot, return */
        retarget_case(algos[i], f, 100000, 6000, 1000, 1);   /* behind: stop, reverse, approach */
        retarget_case(algos[i], f, 100000, 6000, -5000, 1);
        retarget_case(algos[i], f, 100000, 6000, 0, 1);      /* back to where it started */
        retarget_case(algos[i], f, 100000, 2000, 50000, 0);  /* while still accelerating */
        retarget_case(algos[i], f, 100000, 2000, 2500, 1);
    }
}

/* issue 22: `set accel` (or vmax) while moving, then a new target or a stop. The replan starts from
 * the speed the move has reached: no interval outside the ramp's law (replay_positions, with the
 * larger of the two accelerations), and never faster than the larger of that speed and the new
 * vmax. Before the fix the exact ramp's speed became old speed x new accel / old accel in one step
 * (5,000 -> 20,000 steps/s with 50,000 -> 200,000 steps/s^2). Reference: the closed form's own
 * bound, |1/i2 - 1/i1| <= a (i1 + i2)/2 per step (constant acceleration a, intervals i1, i2). */
static void replan_case(ramp_algo_t algo, double a1, double a2, double vmax2, int32_t second, int stop)
{
    uint32_t f = algo == RAMP_ALGO_EXACT ? 16000000U : 2000000U;
    ramp_params_t p = {algo == RAMP_ALGO_EXACT ? 0.0f : 200.0f, 5000.0f, a1, f};
    ramp_params_t q = p;
    step_planner_t pl;
    trace_t tr;
    uint32_t rev, n0, n;
    double v_at, vmax_seen = 0.0, amax = a1 > a2 ? a1 : a2;
    q.accel_sps2 = a2;
    q.vmax_sps = vmax2;
    assert_int_equal(step_planner_init_trapezoid(&pl, algo, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 100000), MS_OK);
    trace_init(&tr, 400000);
    drain_steps(&pl, &tr, 3000); /* cruising at 5,000 steps/s by then (a1 >= 8,000: 1,563 steps or fewer) */
    n0 = tr.n;
    v_at = (double)f / (double)(tr.t[n0] - tr.t[n0 - 1]);
    assert_int_equal(step_planner_set_params(&pl, &q), MS_OK);
    if (stop)
        step_planner_stop(&pl);
    else
        assert_int_equal(step_planner_move(&pl, second), MS_OK);
    drain(&pl, &tr, UINT32_MAX);
    assert_false(step_planner_busy(&pl));
    (void)replay_positions(&tr, 0, amax, f, simplistic_dp(algo, &q), algo == RAMP_ALGO_SIMPLISTIC ? n0 + 1U : 0U,
                           algo == RAMP_ALGO_SIMPLISTIC ? n0 : UINT32_MAX, &rev);
    for (n = n0 + 1U; n <= tr.n; n++) {
        double v = (double)f / (double)(tr.t[n] - tr.t[n - 1]);
        if (v > vmax_seen)
            vmax_seen = v;
    }
    if (vmax_seen > (v_at > vmax2 ? v_at : vmax2) * 1.001 + 1.0)
        fail_msg("%s: %.0f steps/s after the replan (speed then %.0f, new vmax %.0f)", ramp_algo_name(algo), vmax_seen,
                 v_at, vmax2);
    if (!stop)
        assert_int_equal(step_planner_position(&pl), second);
    trace_free(&tr);
}

/* Parameters set while moving, then a halt (forceStop) and a move from rest: the move is on the new
 * parameters' closed form, every step. The exact planner converts its constants at a move from rest
 * only when parameters were set while moving (params_new), so the halt must keep that mark: with it
 * cleared (as before 2026-12-06, when every move from rest converted) this move ran on the old accel. */
static void params_set_while_moving_apply_after_a_halt(void **state)
{
    ramp_params_t p = {0.0f, 20000.0f, 50000.0f, 16000000U};
    ramp_params_t q = {0.0f, 8000.0f, 120000.0f, 16000000U};
    step_planner_t pl;
    trace_t tr;
    uint32_t d = 3000;
    int32_t at;
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 100000), MS_OK);
    trace_init(&tr, 100000);
    drain_steps(&pl, &tr, 2000);
    assert_int_equal(step_planner_set_params(&pl, &q), MS_OK);
    at = step_planner_position(&pl);
    step_planner_halt(&pl, at);
    trace_free(&tr);
    assert_int_equal(step_planner_move(&pl, at + (int32_t)d), MS_OK);
    trace_init(&tr, d);
    drain(&pl, &tr, UINT32_MAX);
    assert_int_equal(tr.n, d);
    check_closed_form(&tr, 0.0, 8000.0, 120000.0, 16000000U, d, 0); /* the new parameters' */
    trace_free(&tr);
}

static void replan_with_new_params_keeps_speed(void **state)
{
    (void)state;
    /* the reproducers: 50,000 -> 200,000 and -> 1,000 steps/s^2, then back to 0 */
    replan_case(RAMP_ALGO_EXACT, 50000.0, 200000.0, 5000.0, 0, 0);
    replan_case(RAMP_ALGO_EXACT, 50000.0, 1000.0, 5000.0, 0, 0);
    replan_case(RAMP_ALGO_EXACT, 8000.0, 50000.0, 5000.0, 0, 0);
    /* ahead, far enough to keep going; and ahead but too close */
    replan_case(RAMP_ALGO_EXACT, 50000.0, 200000.0, 5000.0, 60000, 0);
    replan_case(RAMP_ALGO_EXACT, 50000.0, 1000.0, 5000.0, 60000, 0);
    replan_case(RAMP_ALGO_EXACT, 50000.0, 200000.0, 5000.0, 3100, 0);
    /* a new vmax as well: above and below the speed */
    replan_case(RAMP_ALGO_EXACT, 50000.0, 200000.0, 8000.0, 60000, 0);
    replan_case(RAMP_ALGO_EXACT, 50000.0, 20000.0, 2000.0, 60000, 0);
    /* a stop after set accel decelerates at the new accel, from the speed reached */
    replan_case(RAMP_ALGO_EXACT, 50000.0, 200000.0, 5000.0, 0, 1);
    replan_case(RAMP_ALGO_EXACT, 50000.0, 1000.0, 5000.0, 0, 1);
    replan_case(RAMP_ALGO_LEIB, 50000.0, 200000.0, 5000.0, 0, 0);
    replan_case(RAMP_ALGO_LEIB, 50000.0, 10000.0, 5000.0, 60000, 0);
    replan_case(RAMP_ALGO_LEIB, 50000.0, 200000.0, 5000.0, 0, 1);
    replan_case(RAMP_ALGO_SIMPLISTIC, 50000.0, 200000.0, 5000.0, 0, 0);
    replan_case(RAMP_ALGO_SIMPLISTIC, 50000.0, 10000.0, 5000.0, 60000, 0);
}

/* A continued Leib or simplistic move under new parameters (a new v0 or accel: `set` while moving,
 * then a target) starts at the level of its speed under them, and never runs faster than vmax: the
 * level rounded to the nearest left the ramp up to half a level too many steps, and a simplistic
 * level is dp = (F/v0 - F/vmax)/S ticks of interval (126 ticks at v0 20, vmax 12,000, accel 90,824:
 * make fuzz found 12,500 steps/s at vmax 12,000). Random parameter changes at random steps of the
 * acceleration; every interval after the change at least F/vmax less the half tick of rounding. */
static uint32_t lcg_next(uint32_t *x)
{
    *x = *x * 1664525U + 1013904223U;
    return *x >> 8;
}

static double log_uniform(uint32_t *x, double lo, double hi)
{
    return lo * pow(hi / lo, (double)(lcg_next(x) & 0xFFFFU) / 65535.0);
}

static void continued_ramp_never_above_vmax(void **state)
{
    const ramp_algo_t algos[] = {RAMP_ALGO_SIMPLISTIC, RAMP_ALGO_LEIB};
    uint32_t x = 12345U, i, trial, bad = 0, cases = 0;
    (void)state;
    for (i = 0; i < 2U; i++) {
        for (trial = 0; trial < 120U; trial++) {
            ramp_params_t p, q;
            step_planner_t pl;
            trace_t tr;
            uint32_t k, n, n0;
            double pmin;
            p.tick_hz = q.tick_hz = 2000000U;
            p.vmax_sps = q.vmax_sps = (float)log_uniform(&x, 2000.0, 12000.0);
            p.v0_sps = (float)log_uniform(&x, 1.0, 1500.0);
            q.v0_sps = trial == 0 ? 20.0f : (float)log_uniform(&x, 1.0, 1500.0);
            p.accel_sps2 = (float)log_uniform(&x, 2000.0, 1e6);
            q.accel_sps2 = (float)log_uniform(&x, 2000.0, 1e6);
            if (trial == 0) {
                /* the fuzz case */
                p.vmax_sps = q.vmax_sps = 12000.0f;
                p.v0_sps = 500.0f;
                p.accel_sps2 = q.accel_sps2 = 90824.0f;
            }
            if (step_planner_init_trapezoid(&pl, algos[i], &p, 0) != MS_OK)
                continue;
            assert_int_equal(step_planner_move(&pl, 300000), MS_OK);
            trace_init(&tr, 400000);
            k = 1U + lcg_next(&x) % 1500U;
            drain_steps(&pl, &tr, k);
            n0 = tr.n;
            if (step_planner_set_params(&pl, &q) != MS_OK || step_planner_move(&pl, 350000) != MS_OK) {
                trace_free(&tr);
                continue;
            }
            drain(&pl, &tr, UINT32_MAX);
            cases++;
            pmin = (double)q.tick_hz / (double)q.vmax_sps;
            for (n = n0 + 1U; n <= tr.n; n++) {
                uint64_t w = tr.t[n] - tr.t[n - 1];
                if ((double)w < pmin - 0.5 - 1e-6) {
                    if (bad++ < 3)
                        print_message("%s: v0 %g -> %g, accel %g -> %g, vmax %g, changed after step %u: step %u "
                                      "at %llu ticks, below F/vmax = %.2f\n",
                                      ramp_algo_name(algos[i]), (double)p.v0_sps, (double)q.v0_sps,
                                      (double)p.accel_sps2, (double)q.accel_sps2, (double)q.vmax_sps, n0, n,
                                      (unsigned long long)w, pmin);
                    break;
                }
            }
            trace_free(&tr);
        }
    }
    assert_true(cases > 150U);
    assert_int_equal(bad, 0);
}

static void stop_decelerates_to_rest(void **state)
{
    const ramp_algo_t algos[] = {RAMP_ALGO_EXACT, RAMP_ALGO_LEIB, RAMP_ALGO_SIMPLISTIC};
    uint32_t i;
    (void)state;
    for (i = 0; i < 3U; i++) {
        ramp_params_t p = {algos[i] == RAMP_ALGO_EXACT ? 0.0f : 200.0f, 20000.0f, 50000.0f,
                           algos[i] == RAMP_ALGO_EXACT ? 16000000U : 2000000U};
        step_planner_t pl;
        trace_t tr;
        uint32_t rev, before;
        int32_t end;
        assert_int_equal(step_planner_init_trapezoid(&pl, algos[i], &p, 0), MS_OK);
        assert_int_equal(step_planner_move(&pl, 1000000), MS_OK);
        trace_init(&tr, 1000000);
        drain_steps(&pl, &tr, 6000); /* at full speed by now (4,000 steps of acceleration) */
        before = tr.n;
        step_planner_stop(&pl);
        drain(&pl, &tr, UINT32_MAX);
        end = replay_positions(&tr, 0, p.accel_sps2, p.tick_hz, simplistic_dp(algos[i], &p), 0, UINT32_MAX, &rev);
        assert_int_equal(rev, 0);
        assert_int_equal(end, step_planner_position(&pl));
        /* stopping distance from 20,000 steps/s at 50,000 steps/s^2: v^2/2a = 4,000 steps */
        if (abs((int)(tr.n - before) - 4000) > 2)
            fail_msg("%s: stopped in %u steps, want 4000 +- 2", ramp_algo_name(algos[i]), tr.n - before);
        trace_free(&tr);
    }
}

/* A stop after any command of a move (as `motionsim ramp --stop-at`), during its deceleration too,
 * ends at rest at or before the move's target, never past it, and not behind where it was. The
 * stopping distance rounds up to whole steps, so in the deceleration it can exceed the steps left by
 * one: the move then keeps its own end (before, it stopped one step past the target). */
static void stop_never_passes_the_target(void **state)
{
    const ramp_params_t p = {0.0f, 10000.0f, 10000.0f, 16000000U};
    const int32_t target = 1000;
    uint32_t k, passed = 0, first_bad = 0;
    (void)state;
    for (k = 1; k < (uint32_t)target; k += 3U) {
        step_planner_t pl;
        trace_t tr;
        int32_t end;
        assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0), MS_OK);
        assert_int_equal(step_planner_move(&pl, target), MS_OK);
        trace_init(&tr, 2000);
        drain_steps(&pl, &tr, k);
        step_planner_stop(&pl);
        drain(&pl, &tr, UINT32_MAX);
        end = step_planner_position(&pl);
        assert_int_equal(end, (int32_t)tr.n);
        if (end > target && passed++ == 0)
            first_bad = k;
        if (end < (int32_t)k)
            fail_msg("stop after step %u ended at %d, behind where it was", k, end);
        trace_free(&tr);
    }
    if (passed)
        fail_msg("%u of the stops passed the target %d (the first after step %u)", passed, target, first_bad);
}

/* The sigmoid walks its table: the interval of a step with level k is period[(k - 1)/hold]
 * (the last entry beyond the table). A stop, a target further on and a target behind, taken
 * after M accelerating steps (k = M), against the level the S-curve article's stepping gives:
 * stop: k = M - 1 ... 1; further on to T: k = min(M + j, T - M - j + 1, len * hold) for the j-th
 * step after; behind: the stop, then a move from rest to the target, k = min(i, D + 1 - i). */
static uint32_t sigmoid_period(const uint16_t *table, const ramp_sigmoid_params_t *sp, uint32_t k)
{
    uint32_t e = (k - 1U) / sp->hold;
    return table[e < sp->len ? e : sp->len - 1U];
}

/* A retarget continues the sigmoid from its level (start_level != 0); once it is at the table's top
 * its cruise is skipped in whole commands, as a move's from rest is, not stepped one step at a time
 * (issue 22: per-step planning at 20,000 steps/s left the console no time and the queue ran dry).
 * The intervals themselves are sigmoid_stop_and_retarget's. */
static void sigmoid_continued_cruise_is_skipped(void **state)
{
    static uint16_t table[300];
    ramp_sigmoid_params_t sp = {300, 3, 500.0f, 20000.0f, 5.0f, 2000000};
    step_planner_t pl;
    trace_t tr;
    uint32_t a = (uint32_t)sp.len * sp.hold;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&sp, table, 300), MS_OK);
    assert_int_equal(step_planner_init_sigmoid(&pl, &sp, table, sp.len, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 20000), MS_OK);
    trace_init(&tr, 60000);
    drain_steps(&pl, &tr, 500);
    assert_int_equal(step_planner_move(&pl, 30000), MS_OK);
    assert_true(pl.ramp.start_level != 0);
    drain_steps(&pl, &tr, a + 100U); /* at the top by now */
    assert_int_equal(pl.ramp.u.sigmoid.k, a);
    /* the rest of the cruise up to D - A of the continued move, A before its end */
    assert_int_equal(ramp_cruise_skippable(&pl.ramp), pl.ramp.steps_total - a - pl.ramp.steps_done);
    drain(&pl, &tr, UINT32_MAX);
    assert_int_equal(step_planner_position(&pl), 30000);
    trace_free(&tr);
}

/* ramp_take_same on a continued sigmoid (a retarget: rising to the top, falling with the steps left)
 * hands out exactly the steps ramp_next_ticks would, one by one: same whole ticks, same end state. */
static void sigmoid_take_same_continued_equals_stepping(void **state)
{
    static uint16_t table[300];
    ramp_sigmoid_params_t sp = {300, 3, 500.0f, 20000.0f, 5.0f, 2000000};
    const uint32_t firsts[] = {1, 2, 5, 100, 450, 899, 900, 1500};
    const int32_t seconds[] = {3, 40, 700, 1800, 2100, 5000};
    unsigned i, k, taken = 0;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&sp, table, 300), MS_OK);
    for (i = 0; i < sizeof firsts / sizeof firsts[0]; i++) {
        for (k = 0; k < sizeof seconds / sizeof seconds[0]; k++) {
            ramp_t m, a, b;
            uint32_t w = 0, wb = 0, s;
            ramp_phase_t ph;
            assert_int_equal(ramp_plan_sigmoid(&m, &sp, table, sp.len, 0, 100000), MS_OK);
            for (s = 0; s < firsts[i]; s++)
                assert_true(ramp_next_ticks(&m, &w, &ph));
            if (ramp_plan_continue(&a, &m, 0, (int32_t)firsts[i] + seconds[k]) != MS_OK)
                continue; /* closer than the stopping distance */
            b = a;
            while (ramp_next_ticks(&b, &wb, &ph)) {
                uint32_t more = ramp_take_same(&b, 65535U), j;
                assert_true(ramp_next_ticks(&a, &w, &ph));
                assert_int_equal(w, wb);
                for (j = 0; j < more; j++) {
                    assert_true(ramp_next_ticks(&a, &w, &ph));
                    if (w != wb)
                        fail_msg("first %u then +%d: step %u of a run taken at once has %u ticks, stepping gives %u",
                                 firsts[i], seconds[k], a.steps_done, wb, w);
                }
                taken += more;
                assert_int_equal(a.steps_done, b.steps_done);
                assert_int_equal(a.u.sigmoid.k, b.u.sigmoid.k);
            }
            assert_false(ramp_next_ticks(&a, &w, &ph));
        }
    }
    assert_true(taken > 1000U); /* the runs were taken at once, not one by one */
}

static void sigmoid_stop_and_retarget(void **state)
{
    static uint16_t table[300];
    ramp_sigmoid_params_t sp = {300, 3, 500.0f, 20000.0f, 5.0f, 2000000};
    unsigned c;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&sp, table, 300), MS_OK);
    for (c = 0; c < 3U; c++) {
        step_planner_t pl;
        trace_t tr;
        uint32_t m, n, a = (uint32_t)sp.len * sp.hold;
        int32_t pos = 0, target;
        assert_int_equal(step_planner_init_sigmoid(&pl, &sp, table, sp.len, 0), MS_OK);
        assert_int_equal(step_planner_move(&pl, 20000), MS_OK);
        trace_init(&tr, 60000);
        drain_steps(&pl, &tr, 500);
        m = pl.ramp.steps_done; /* steps taken from the ramp (one may not be in a command yet): the
                                   new plan starts after them */
        assert_true(m == tr.n || m == tr.n + 1U);
        assert_true(m < a);
        if (c == 0U) {
            step_planner_stop(&pl);
            target = (int32_t)(2U * m - 1U);
        } else if (c == 1U) {
            target = 9000;
            assert_int_equal(step_planner_move(&pl, target), MS_OK);
        } else {
            target = (int32_t)m - 300;
            assert_int_equal(step_planner_move(&pl, target), MS_OK);
        }
        assert_int_equal(step_planner_target(&pl), target);
        drain(&pl, &tr, UINT32_MAX);
        for (n = 1; n <= tr.n; n++) {
            uint32_t k, got = (uint32_t)(tr.t[n] - tr.t[n - 1]);
            if (n <= m) {
                k = n;
            } else if (c == 0U || (c == 2U && n < 2U * m)) {
                k = 2U * m - n; /* decelerating to rest at 2M - 1 */
            } else if (c == 1U) {
                uint32_t j = n - m, up = m + j, down = (uint32_t)target - m - j + 1U;
                k = up < down ? up : down;
                if (k > a)
                    k = a;
            } else {
                uint32_t i = n - (2U * m - 1U), dd = 2U * m - 1U - (uint32_t)target;
                k = i < dd + 1U - i ? i : dd + 1U - i;
            }
            if (got != sigmoid_period(table, &sp, k))
                fail_msg("case %u step %u: %u ticks, the table at level %u has %u", c, n, got, k,
                         sigmoid_period(table, &sp, k));
            pos += tr.dir[n];
            if (c == 2U && n >= 2U * m)
                assert_int_equal(tr.dir[n], -1);
            else
                assert_int_equal(tr.dir[n], 1);
        }
        assert_int_equal(pos, target);
        assert_int_equal(step_planner_position(&pl), target);
        assert_false(step_planner_busy(&pl));
        trace_free(&tr);
    }
}

/* A sketch's own pre-computation and computeNewSpeed() (ramp_hooks_t): hooks that call lib's
 * functions give the very commands lib's own do, through a move, a new target and a stop, and are
 * called (once per plan, once per accelerating or decelerating step); a different update is what
 * the steps then follow (here: p never changes, so every interval is the first, F/sqrt(v0^2 + 2a)). */
static unsigned hook_plans, hook_updates;
static motion_status_t counting_leib_plan(ramp_leib_t *l, const ramp_params_t *p, uint32_t steps_total)
{
    hook_plans++;
    return ramp_leib_plan(l, p, steps_total);
}
static float counting_leib_update(ramp_leib_t *l, ramp_phase_t phase)
{
    hook_updates++;
    return ramp_leib_update(l, phase);
}
static motion_status_t counting_simplistic_plan(ramp_simplistic_t *s, const ramp_params_t *p, uint32_t steps_total)
{
    hook_plans++;
    return ramp_simplistic_plan(s, p, steps_total);
}
static float counting_simplistic_update(ramp_simplistic_t *s, ramp_phase_t phase)
{
    hook_updates++;
    return ramp_simplistic_update(s, phase);
}
static float constant_leib_update(ramp_leib_t *l, ramp_phase_t phase)
{
    (void)phase;
    return l->p;
}

static void sketch_hooks_are_what_runs(void **state)
{
    const ramp_hooks_t counting = {counting_leib_plan, counting_leib_update, counting_simplistic_plan,
                                   counting_simplistic_update};
    const ramp_hooks_t constant = {0, constant_leib_update, 0, 0};
    const ramp_algo_t algos[] = {RAMP_ALGO_LEIB, RAMP_ALGO_SIMPLISTIC};
    ramp_params_t p = {200.0f, 20000.0f, 50000.0f, 2000000};
    unsigned i;
    (void)state;
    for (i = 0; i < 2U; i++) {
        step_planner_t a, b;
        step_cmd_t ca, cb;
        unsigned k = 0;
        hook_plans = hook_updates = 0;
        assert_int_equal(step_planner_init_trapezoid(&a, algos[i], &p, 0), MS_OK);
        assert_int_equal(step_planner_init_hooked(&b, algos[i], &p, &counting, 0), MS_OK);
        assert_int_equal(step_planner_move(&a, 30000), MS_OK);
        assert_int_equal(step_planner_move(&b, 30000), MS_OK);
        for (;;) {
            uint8_t ma = step_planner_next(&a, &ca), mb = step_planner_next(&b, &cb);
            assert_int_equal(ma, mb);
            if (!ma)
                break;
            assert_cmd_equal(&ca, &cb);
            if (++k == 40U) {
                assert_int_equal(step_planner_move(&a, 12000), MS_OK);
                assert_int_equal(step_planner_move(&b, 12000), MS_OK);
            }
            if (k == 200U) {
                step_planner_stop(&a);
                step_planner_stop(&b);
            }
        }
        assert_int_equal(step_planner_position(&a), step_planner_position(&b));
        assert_true(hook_plans >= 3U);    /* the move, the new target, the stop (and the checks) */
        assert_true(hook_updates > 100U); /* every step of the ramps */
    }
    {
        step_planner_t c;
        trace_t tr;
        uint32_t n, p1 = (uint32_t)floor(2000000.0 / sqrt(200.0 * 200.0 + 2.0 * 50000.0) + 0.5);
        assert_int_equal(step_planner_init_hooked(&c, RAMP_ALGO_LEIB, &p, &constant, 0), MS_OK);
        assert_int_equal(step_planner_move(&c, 500), MS_OK);
        trace_init(&tr, 500);
        drain(&c, &tr, UINT32_MAX);
        assert_int_equal(tr.n, 500);
        for (n = 1; n <= 500U; n++)
            assert_int_equal(tr.t[n] - tr.t[n - 1], p1);
        trace_free(&tr);
    }
}

static void stop_at_rest_does_nothing(void **state)
{
    ramp_params_t p = {0.0f, 20000.0f, 50000.0f, 16000000U};
    step_planner_t pl;
    step_cmd_t c;
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 7), MS_OK);
    step_planner_stop(&pl);
    assert_int_equal(step_planner_next(&pl, &c), 0);
    assert_int_equal(step_planner_position(&pl), 7);
    assert_false(step_planner_busy(&pl));
}

static void bad_parameters_refused(void **state)
{
    step_planner_t pl;
    ramp_params_t bad = {0.0f, 20000.0f, 0.0f, 16000000U};
    ramp_params_t slow = {0.0f, 100000.0f, 1.0f, 16000000U}; /* vmax/accel beyond 2^34 ticks */
    ramp_params_t ok = {0.0f, 20000.0f, 50000.0f, 16000000U};
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &bad, 0), MS_ERR_ACCEL_NOT_POSITIVE);
    assert_int_not_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &slow, 0), MS_OK);
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &ok, 0), MS_OK);
    assert_int_not_equal(step_planner_set_params(&pl, &bad), MS_OK);
    assert_true(pl.params.accel_sps2 == 50000.0); /* unchanged */
}

/* step_planner_init_exact / _lab (one half of the planner each, for the firmware) plan what
 * step_planner_init_hooked plans, command for command, through a move, a new target and a stop;
 * each refuses the other's algorithms */
static void one_kind_inits_plan_the_same(void **state)
{
    /* the last two: the lab's ramps through step_planner_init_leib / _simplistic */
    const ramp_algo_t algos[] = {RAMP_ALGO_EXACT, RAMP_ALGO_LEIB, RAMP_ALGO_SIMPLISTIC, RAMP_ALGO_LEIB,
                                 RAMP_ALGO_SIMPLISTIC};
    ramp_params_t p = {100.0f, 4000.0f, 8000.0f, 2000000U};
    (void)state;
    for (unsigned k = 0; k < 5; k++) {
        step_planner_t a, b;
        step_cmd_t ca, cb;
        uint32_t n = 0;
        int phase;
        p.tick_hz = algos[k] == RAMP_ALGO_EXACT ? 16000000U : 2000000U;
        assert_int_equal(step_planner_init_hooked(&a, algos[k], &p, 0, -7), MS_OK);
        if (algos[k] == RAMP_ALGO_EXACT)
            assert_int_equal(step_planner_init_exact(&b, &p, -7), MS_OK);
        else if (k < 3)
            assert_int_equal(step_planner_init_lab(&b, algos[k], &p, 0, -7), MS_OK);
        else if (algos[k] == RAMP_ALGO_LEIB)
            assert_int_equal(step_planner_init_leib(&b, algos[k], &p, 0, -7), MS_OK);
        else
            assert_int_equal(step_planner_init_simplistic(&b, algos[k], &p, 0, -7), MS_OK);
        for (phase = 0; phase < 3; phase++) {
            if (phase == 0) {
                assert_int_equal(step_planner_move(&a, 5000), MS_OK);
                assert_int_equal(step_planner_move(&b, 5000), MS_OK);
            } else if (phase == 1) {
                assert_int_equal(step_planner_move(&a, 800), MS_OK);
                assert_int_equal(step_planner_move(&b, 800), MS_OK);
            } else {
                step_planner_stop(&a);
                step_planner_stop(&b);
            }
            for (unsigned i = 0; i < (phase == 2 ? 100000U : 40U); i++) {
                uint8_t ra = step_planner_next(&a, &ca), rb = step_planner_next(&b, &cb);
                assert_int_equal(ra, rb);
                if (!ra)
                    break;
                assert_cmd_equal(&ca, &cb);
                n += ca.count;
            }
            assert_int_equal(step_planner_position(&a), step_planner_position(&b));
            assert_int_equal(step_planner_target(&a), step_planner_target(&b));
        }
        assert_true(n > 40U);
    }
    {
        step_planner_t c;
        p.tick_hz = 16000000U;
        assert_int_equal(step_planner_init_lab(&c, RAMP_ALGO_EXACT, &p, 0, 0), MS_ERR_UNKNOWN_COMMAND);
        assert_int_equal(step_planner_init_lab(&c, RAMP_ALGO_SIGMOID, &p, 0, 0), MS_ERR_UNKNOWN_COMMAND);
        assert_int_equal(step_planner_init_leib(&c, RAMP_ALGO_SIMPLISTIC, &p, 0, 0), MS_ERR_UNKNOWN_COMMAND);
        assert_int_equal(step_planner_init_leib(&c, RAMP_ALGO_EXACT, &p, 0, 0), MS_ERR_UNKNOWN_COMMAND);
        assert_int_equal(step_planner_init_simplistic(&c, RAMP_ALGO_LEIB, &p, 0, 0), MS_ERR_UNKNOWN_COMMAND);
        assert_int_equal(step_planner_init_simplistic(&c, RAMP_ALGO_SIGMOID, &p, 0, 0), MS_ERR_UNKNOWN_COMMAND);
        assert_int_equal(step_planner_init_exact(0, &p, 0), MS_ERR_NULL);
    }
}

/* The smooth planner hands out smooth_move's own commands, bit for bit (the same calls on a bare
 * smooth_move_t: its own tests hold them against the closed form), through a move from rest, a new
 * target ahead, one behind (its stop, then the move back), a stop; parameters and jerk refused as
 * smooth_law_set_params refuses them, nothing changed then. */
/* The planner and smooth_move hand out the same commands, bit for bit: up to max of them, or until
 * both end together; returns their steps. */
static uint32_t same_smooth_commands(step_planner_t *pl, smooth_move_t *m, uint32_t max)
{
    step_cmd_t ca, cb;
    uint32_t i, steps = 0;
    for (i = 0; i < max; i++) {
        uint8_t ra = step_planner_next(pl, &ca), rb = smooth_move_next(m, &cb);
        assert_int_equal(ra, rb);
        if (!ra)
            break;
        assert_cmd_equal(&ca, &cb);
        steps += ca.count;
    }
    return steps;
}

static void smooth_planner_is_smooth_move(void **state)
{
    ramp_params_t p = {0.0f, 10000.0f, 20000.0f, 16000000U};
    smooth_params_t sp = {10000.0, 20000.0, 200000.0, 16000000U};
    step_smooth_t store;
    smooth_move_t m;
    step_planner_t pl;
    step_cmd_t ca, cb;
    uint32_t total = 0;
    int phase;
    (void)state;
    assert_int_equal(step_planner_init_smooth(&pl, &p, 200000.0, &store, 100), MS_OK);
    assert_int_equal(smooth_move_init(&m, &sp, 100), MS_OK);
    pl.max_cmd_ticks = 16000U; /* 1 ms, as the MotionStepper library's */
    m.max_cmd_ticks = 16000U;
    assert_int_equal(pl.algo, RAMP_ALGO_SMOOTH);
    for (phase = 0; phase < 5; phase++) {
        unsigned cmds = phase == 4 ? 100000U : 60U;
        if (phase == 0) {
            assert_int_equal(step_planner_move(&pl, 20100), MS_OK);
            assert_int_equal(smooth_move_to(&m, 20100), MS_OK);
        } else if (phase == 1) {
            assert_int_equal(step_planner_move(&pl, 9000), MS_OK); /* ahead */
            assert_int_equal(smooth_move_to(&m, 9000), MS_OK);
        } else if (phase == 2) {
            assert_int_equal(step_planner_move(&pl, -3000), MS_OK); /* behind: stop, then back */
            assert_int_equal(smooth_move_to(&m, -3000), MS_OK);
            assert_int_equal(step_planner_target(&pl), -3000);
            cmds = 1000U; /* the stop below on the way back (at 1200 it was put off, acting at once exceeding the jerk, until the move back had come to -3000 by itself) */
        } else if (phase == 3) {
            step_planner_stop(&pl);
            smooth_move_stop(&m);
        }
        total += same_smooth_commands(&pl, &m, cmds);
        assert_int_equal(step_planner_position(&pl), smooth_move_position(&m));
        assert_int_equal(step_planner_target(&pl), smooth_move_target(&m));
        assert_int_equal(step_planner_busy(&pl), smooth_move_busy(&m));
    }
    assert_false(step_planner_busy(&pl));
    assert_true(total > 3000U);
    /* stopped on the way back */
    assert_true(step_planner_position(&pl) < 0 && step_planner_position(&pl) > -3000);
    /* at rest nothing can be taken back */
    assert_int_equal(step_planner_rewindable(&pl), 0);
    assert_int_equal(step_planner_rewind(&pl, 1, 0, 1), MS_ERR_OUT_OF_RANGE);
    /* moving: the planner's rewind is smooth_move_rewind's (the same commands after it) */
    {
        step_cmd_t kept[6];
        int i;
        int64_t t16 = 0;
        uint32_t steps = 0;
        assert_int_equal(step_planner_move(&pl, 5000), MS_OK);
        assert_int_equal(smooth_move_to(&m, 5000), MS_OK);
        for (i = 0; i < 6; i++) {
            assert_true(step_planner_next(&pl, &kept[i]));
            assert_true(smooth_move_next(&m, &cb));
            assert_cmd_equal(&kept[i], &cb);
        }
        for (i = 4; i < 6; i++) { /* the last two dropped: their time in the executor's sums */
            steps += kept[i].count;
            t16 += step_exact_cmd_time16(&kept[i]);
        }
        assert_int_equal(step_planner_rewindable(&pl), smooth_move_rewindable(&m));
        assert_int_equal(step_planner_rewind(&pl, steps, t16, kept[3].count), MS_OK);
        assert_int_equal(smooth_move_rewind(&m, steps, t16), MS_OK);
        assert_int_equal(step_planner_position(&pl), smooth_move_position(&m));
        step_planner_stop(&pl);
        smooth_move_stop(&m);
        (void)same_smooth_commands(&pl, &m, UINT32_MAX);
        assert_int_equal(step_planner_position(&pl), smooth_move_position(&m));
    }
    /* refusals: nothing changes */
    assert_int_equal(step_planner_set_jerk(&pl, 0.0), MS_ERR_JERK_NOT_POSITIVE);
    assert_int_equal(step_planner_set_jerk(&pl, -5.0), MS_ERR_JERK_NOT_POSITIVE);
    assert_int_equal(step_planner_set_jerk(&pl, NAN), MS_ERR_NOT_FINITE);
    assert_int_equal(step_planner_set_jerk(&pl, INFINITY), MS_ERR_NOT_FINITE);
    assert_int_equal(step_planner_set_jerk(&pl, 39999.0), MS_ERR_JERK_TOO_LOW); /* accel^2/vmax = 40000 */
    assert_true(store.jerk_sps3 == 200000.0);
    assert_int_equal(step_planner_set_jerk(&pl, 40000.0), MS_OK);
    assert_true(store.jerk_sps3 == 40000.0);
    assert_int_equal(step_planner_smooth_check(&p, 39999.0), MS_ERR_JERK_TOO_LOW);
    {
        step_planner_t q;
        step_smooth_t st2;
        assert_int_equal(step_planner_init_smooth(&q, &p, 1000.0, &st2, 0), MS_ERR_JERK_TOO_LOW);
        assert_int_equal(step_planner_init_smooth(&q, &p, 1e5, 0, 0), MS_ERR_NULL);
        assert_int_equal(step_planner_init_exact(&q, &p, 0), MS_OK);
        assert_int_equal(step_planner_set_jerk(&q, 1e5), MS_ERR_NOT_SUPPORTED);
    }
    /* a new jerk at rest: the next move is that of smooth_move with it */
    sp.jerk_sps3 = 40000.0;
    assert_int_equal(smooth_move_set_params(&m, &sp), MS_OK);
    m.max_cmd_ticks = 16000U; /* set_params puts back its default */
    assert_int_equal(step_planner_move(&pl, 0), MS_OK);
    assert_int_equal(smooth_move_to(&m, 0), MS_OK);
    for (;;) {
        uint8_t ra = step_planner_next(&pl, &ca), rb = smooth_move_next(&m, &cb);
        assert_int_equal(ra, rb);
        if (!ra)
            break;
        assert_cmd_equal(&ca, &cb);
    }
    assert_int_equal(step_planner_position(&pl), 0);
}

/* Parameters set while a smooth move runs take effect at the next move from rest, also when that
 * move ended with step_planner_halt (what the step engine's end of a move calls: it dropped them once,
 * so the new vmax never applied; found by a review of the SmoothConsole example): the next move is
 * smooth_move's with the new vmax and jerk, and it never steps faster than the new vmax. */
static void smooth_planner_keeps_parameters_set_while_moving(void **state)
{
    ramp_params_t p = {0.0f, 10000.0f, 20000.0f, 16000000U}, slow = {0.0f, 5000.0f, 20000.0f, 16000000U};
    smooth_params_t sp = {5000.0, 20000.0, 300000.0, 16000000U};
    step_smooth_t store;
    smooth_move_t m;
    step_planner_t pl;
    step_cmd_t ca, cb;
    uint32_t min_rate = UINT32_MAX;
    (void)state;
    assert_int_equal(step_planner_init_smooth(&pl, &p, 200000.0, &store, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 20000), MS_OK);
    assert_int_equal(step_planner_next(&pl, &ca), 1);
    /* while moving: kept for the next move from rest */
    assert_int_equal(step_planner_set_params(&pl, &slow), MS_OK);
    assert_int_equal(step_planner_set_jerk(&pl, 300000.0), MS_OK);
    while (step_planner_next(&pl, &ca))
        ;
    step_planner_halt(&pl, step_planner_position(&pl)); /* the engine's end of the move */
    assert_int_equal(step_planner_position(&pl), 20000);
    assert_int_equal(smooth_move_init(&m, &sp, 20000), MS_OK);
    m.max_cmd_ticks = pl.max_cmd_ticks;
    assert_int_equal(step_planner_move(&pl, 0), MS_OK);
    assert_int_equal(smooth_move_to(&m, 0), MS_OK);
    for (;;) {
        uint8_t ra = step_planner_next(&pl, &ca), rb = smooth_move_next(&m, &cb);
        assert_int_equal(ra, rb);
        if (!ra)
            break;
        assert_cmd_equal(&ca, &cb);
        if (!(ca.flags & STEP_CMD_WIDE) && ca.rate < min_rate)
            min_rate = ca.rate;
    }
    /* 5,000 steps/s at 16 MHz: 3,200 ticks a step (2^-16 ticks in rate), within the law's rounding */
    assert_true(min_rate >= (uint32_t)(3199.0 * 65536.0));
    assert_int_equal(step_planner_position(&pl), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(one_kind_inits_plan_the_same),
        cmocka_unit_test(smooth_planner_is_smooth_move),
        cmocka_unit_test(smooth_planner_keeps_parameters_set_while_moving),
        cmocka_unit_test(queue_fifo_full_empty),
        cmocka_unit_test(executor_follows_its_formula),
        cmocka_unit_test(exact_reference_moves_every_step),
        cmocka_unit_test(exact_random_moves_every_step),
        cmocka_unit_test(exact_timeline_within_half_a_tick),
        cmocka_unit_test(exact_longest_move_no_drift),
        cmocka_unit_test(stepwise_random_moves_exact_ticks),
        cmocka_unit_test(stepwise_longest_moves_no_drift),
        cmocka_unit_test(sigmoid_stop_and_retarget),
        cmocka_unit_test(sigmoid_continued_cruise_is_skipped),
        cmocka_unit_test(sigmoid_take_same_continued_equals_stepping),
        cmocka_unit_test(sketch_hooks_are_what_runs),
        cmocka_unit_test(leib_lab_checkpoint_through_the_queue),
        cmocka_unit_test(new_target_while_moving),
        cmocka_unit_test(replan_with_new_params_keeps_speed),
        cmocka_unit_test(params_set_while_moving_apply_after_a_halt),
        cmocka_unit_test(continued_ramp_never_above_vmax),
        cmocka_unit_test(stop_decelerates_to_rest),
        cmocka_unit_test(stop_never_passes_the_target),
        cmocka_unit_test(stop_at_rest_does_nothing),
        cmocka_unit_test(bad_parameters_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
