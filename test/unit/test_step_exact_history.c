/* Unit tests: the exact planner's commands depend on the profile alone, not on the planner's
 * history (lib/src/step_exact.c keeps the span rule's scale zfit, a function of C = 2F^2/a, from
 * one profile to the next while C stays, to make a stop cheaper on the AVR). Expected values: the
 * commands of a fresh planner given the same constants, position and plan: whatever the planner
 * did before with other constants must not show in them. And a stop from the cruise is one
 * profile wherever it starts (what the MotionStepper library's planned-ahead stop relies on). */
#include "cmocka_all.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "step_exact.h"
#include "step_planner.h"

#include "closed_form.h" /* urand/lrand */

#define MAX_CMDS 20000U

typedef struct {
    step_cmd_t c[MAX_CMDS];
    uint32_t n;
} cmds_t;

static cmds_t got, want;

static void params(ramp_params_t *p, double vmax, double accel)
{
    p->tick_hz = 16000000UL;
    p->v0_sps = 0.0;
    p->vmax_sps = vmax;
    p->accel_sps2 = accel;
}

/* every command left, then a stop after `stop_after` commands (0: none) */
static void drain(step_planner_t *pl, cmds_t *out, uint32_t stop_after)
{
    step_cmd_t c;
    out->n = 0;
    while (out->n < MAX_CMDS && step_planner_next(pl, &c)) {
        out->c[out->n++] = c;
        if (stop_after != 0U && out->n == stop_after)
            step_planner_stop(pl);
    }
    assert_true(out->n < MAX_CMDS);
}

static void same(const cmds_t *a, const cmds_t *b, const char *what)
{
    uint32_t i;
    if (a->n != b->n)
        fail_msg("%s: %u commands, a fresh planner %u", what, (unsigned)a->n, (unsigned)b->n);
    for (i = 0; i < a->n; i++)
        if (a->c[i].rate != b->c[i].rate || a->c[i].add != b->c[i].add || a->c[i].count != b->c[i].count ||
            a->c[i].flags != b->c[i].flags)
            fail_msg("%s: command %u is (%lu %ld %u %02x), a fresh planner's (%lu %ld %u %02x)", what, (unsigned)i,
                     (unsigned long)a->c[i].rate, (long)a->c[i].add, a->c[i].count, a->c[i].flags,
                     (unsigned long)b->c[i].rate, (long)b->c[i].add, b->c[i].count, b->c[i].flags);
}

/* a move (and a stop in it) after a move and a stop at other parameters, against a fresh planner */
static void one_case(double vmax1, double accel1, double vmax2, double accel2, int32_t d1, int32_t d2, uint32_t stop1,
                     uint32_t stop2, const char *what)
{
    step_planner_t a, b;
    ramp_params_t p1, p2;
    int32_t pos;
    params(&p1, vmax1, accel1);
    params(&p2, vmax2, accel2);
    assert_int_equal(step_planner_init_trapezoid(&a, RAMP_ALGO_EXACT, &p1, 0), MS_OK);
    assert_int_equal(step_planner_move(&a, d1), MS_OK);
    drain(&a, &got, stop1);
    pos = step_planner_position(&a);
    assert_int_equal(step_planner_set_params(&a, &p2), MS_OK);
    assert_int_equal(step_planner_move(&a, pos + d2), MS_OK);
    drain(&a, &got, stop2);
    assert_int_equal(step_planner_init_trapezoid(&b, RAMP_ALGO_EXACT, &p2, pos), MS_OK);
    assert_int_equal(step_planner_move(&b, pos + d2), MS_OK);
    drain(&b, &want, stop2);
    same(&got, &want, what);
}

static void new_accel_after_a_stop(void **state)
{
    (void)state;
    /* the second move's spans are those of its own C: 50,000 -> 400,000 steps/s^2 */
    one_case(20000.0, 50000.0, 20000.0, 400000.0, 100000, 30000, 40, 0, "accel 50,000 then 400,000");
    one_case(20000.0, 400000.0, 20000.0, 50000.0, 100000, 30000, 40, 0, "accel 400,000 then 50,000");
    /* and a stop in the second move, from its cruise (the stop's spans from the new C) */
    one_case(25000.0, 50000.0, 25000.0, 300000.0, 100000, 60000, 40, 60, "a stop at the new accel");
}

static void random_histories(void **state)
{
    uint32_t i;
    char what[120];
    (void)state;
    for (i = 0; i < 200U; i++) {
        double v1 = urand(2000.0, 32000.0), a1 = lrand(5000.0, 400000.0);
        double v2 = urand(2000.0, 32000.0), a2 = lrand(5000.0, 400000.0);
        int32_t d1 = (int32_t)urand(50.0, 50000.0), d2 = (int32_t)urand(50.0, 50000.0);
        uint32_t s1 = (uint32_t)urand(0.0, 30.0), s2 = (uint32_t)urand(0.0, 30.0);
        if (urand(0.0, 1.0) < 0.5)
            d2 = -d2;
        snprintf(what, sizeof what, "case %u: %.0f/%.0f then %.0f/%.0f, %ld then %ld, stops after %u/%u", (unsigned)i,
                 v1, a1, v2, a2, (long)d1, (long)d2, (unsigned)s1, (unsigned)s2);
        one_case(v1, a1, v2, a2, d1, d2, s1, s2, what);
    }
}

/* The MotionStepper library plans the stop from the cruise once and, at a stop, lays it out moved to
 * where its queue is cut (Stepper::stop_in_cruise): that needs a stop from the cruise to be the same
 * profile wherever it starts. Expected: the commands of a stop at one cruise boundary (the planner
 * as it stands) equal those of a stop at another (the planner rewound there), command by command,
 * and the positions differ by the boundaries' distance. */
static void stop_from_the_cruise_is_one_profile(void **state)
{
    static step_cmd_t hist[4000];
    uint32_t i, tried = 0;
    (void)state;
    for (i = 0; i < 300U; i++) {
        step_planner_t a, b;
        ramp_params_t p;
        uint32_t k = 0, drop, steps = 0, j;
        int64_t t16 = 0;
        int32_t shift;
        params(&p, urand(1000.0, 40000.0), lrand(1000.0, 300000.0));
        if (urand(0.0, 1.0) < 0.3)
            p.v0_sps = urand(0.0, 500.0);
        assert_int_equal(step_planner_init_trapezoid(&a, RAMP_ALGO_EXACT, &p, (int32_t)urand(-1000.0, 1000.0)), MS_OK);
        a.max_cmd_ticks = a.exact.max_cmd_ticks = urand(0.0, 1.0) < 0.5 ? 16000U : 64000U;
        assert_int_equal(step_planner_move(&a, a.pos + (urand(0.0, 1.0) < 0.5 ? 1 : -1) * (int32_t)urand(200000.0, 300000.0)),
                         MS_OK);
        /* into the cruise, then some commands more */
        while (k < 3900U && !(a.exact.y == 0 && a.exact.n > a.exact.n1 + 10U) && step_planner_next(&a, &hist[k]))
            k++;
        for (j = 0; j < 30U && k < 4000U && step_planner_next(&a, &hist[k]); j++)
            k++;
        if (!(a.exact.y == 0 && a.exact.n > a.exact.n1 + 10U && a.exact.n < a.exact.n2))
            continue; /* no cruise there (a triangle, or a long acceleration) */
        /* b: back to an earlier cruise boundary */
        drop = 1U + (uint32_t)urand(0.0, 20.0);
        for (j = k - drop; j < k; j++) {
            steps += hist[j].count;
            t16 += step_exact_cmd_time16(&hist[j]);
        }
        b = a;
        if (step_planner_rewind(&b, steps, t16, hist[k - drop - 1U].count) != MS_OK || b.exact.y != 0 ||
            b.exact.n <= b.exact.n1)
            continue;
        tried++;
        shift = a.pos - b.pos;
        step_planner_stop(&a);
        step_planner_stop(&b);
        assert_int_equal(a.target - b.target, shift);
        drain(&a, &got, 0);
        drain(&b, &want, 0);
        same(&got, &want, "a stop from the cruise at two boundaries");
        assert_int_equal(a.pos - b.pos, shift);
    }
    assert_true(tried > 150U);
}

/* step_exact_check (a setter's check without an object) gives the status the documented limits give
 * (step_exact.h, ramp_common.h: expected per case below, written from those limits), and the same as
 * step_exact_set_params and the planner's init, over those cases and random parameter sets */
static void check_gives_set_params_status(void **state)
{
    static const struct {
        double tick_hz, v0, vmax, accel;
        motion_status_t want;
    } cases[] = {
        {16e6, 0.0, 20000.0, 50000.0, MS_OK},
        {16e6, 100.0, 20000.0, 50000.0, MS_OK},
        {16e6, 0.0, 20000.0, 7.9, MS_ERR_ACCEL_TOO_LOW},          /* below 8 steps/s^2 at 16 MHz */
        {16e6, 0.0, 20000.0, 0.0, MS_ERR_ACCEL_NOT_POSITIVE},
        {16e6, 0.0, 0.0, 50000.0, MS_ERR_VMAX_NOT_ABOVE_V0},
        {16e6, 500.0, 400.0, 50000.0, MS_ERR_VMAX_NOT_ABOVE_V0},
        {16e6, -1.0, 400.0, 50000.0, MS_ERR_V0_NEGATIVE},
        {16e6, 0.0, 1e9, 8.0, MS_ERR_VMAX_ABOVE_TICK_HZ},
        {0.0, 0.0, 20000.0, 50000.0, MS_ERR_TICK_HZ_ZERO},
        {4e7, 0.0, 20000.0, 50000.0, MS_ERR_OUT_OF_RANGE},        /* tick_hz above 2^25 */
        {2e6, 0.0, 20000.0, 0.2, MS_ERR_ACCEL_TOO_LOW},           /* below 0.5 steps/s^2 */
        {2e6, 0.0, 100.0, 0.49, MS_ERR_ACCEL_TOO_LOW},            /* the status's sentence: 0.5 at 2 MHz */
        {2e6, 0.0, 100.0, 0.5, MS_OK},
        {16e6, 0.0, 100.0, 8.0, MS_OK},                           /* 8 at a 16 MHz tick */
        {16e6, 0.0, 1e39, 50000.0, MS_ERR_VMAX_ABOVE_TICK_HZ},
        {16e6, 0.0, 20000.0, 1e39, MS_ERR_NOT_FINITE},            /* no float holds it */
        {16e6, 0.0, 16e6, 1e6, MS_OK},
        {16e6, 0.0, 1.0, 8.0, MS_OK},
        {16e6, 0.0, 1e6, 8.0, MS_ERR_ACCEL_PHASE_TOO_LONG},      /* vmax/a F = 2e12 ticks > 2^34 */
        {16e6, 0.0, 0.0037, 10000.0, MS_ERR_INTERVAL_TOO_LONG},  /* F/vmax = 4.32e9 ticks > 2^32 - 1 */
        {16e6, 0.0, 0.0038, 10000.0, MS_OK},                     /* F/vmax = 4.21e9 ticks */
        {2e6, 0.0, 0.00046, 1.0, MS_ERR_INTERVAL_TOO_LONG},      /* F/vmax = 4.35e9 ticks */
        {2e6, 0.0, 0.00047, 1.0, MS_OK},                         /* F/vmax = 4.26e9 ticks */
    };
    const unsigned n_cases = sizeof cases / sizeof cases[0];
    unsigned i;
    step_planner_t pl;
    (void)state;
    for (i = 0; i < n_cases + 2000U; i++) {
        ramp_params_t p;
        step_exact_t e;
        motion_status_t want_st;
        if (i < n_cases) {
            p.tick_hz = (uint32_t)cases[i].tick_hz;
            p.v0_sps = cases[i].v0;
            p.vmax_sps = cases[i].vmax;
            p.accel_sps2 = cases[i].accel;
        } else {
            p.tick_hz = urand(0.0, 1.0) < 0.5 ? 16000000UL : 2000000UL;
            p.vmax_sps = lrand(10.0, 1e6);
            p.v0_sps = urand(0.0, 1.0) < 0.5 ? 0.0 : urand(0.0, 1.2) * p.vmax_sps;
            p.accel_sps2 = lrand(1.0, 1e8);
        }
        memset(&e, 0, sizeof e);
        want_st = step_exact_set_params(&e, &p);
        if (i < n_cases)
            assert_int_equal(want_st, cases[i].want);
        assert_int_equal(step_exact_check(&p), want_st);
        assert_int_equal(step_planner_init_exact(&pl, &p, 0), want_st);
    }
    assert_int_equal(step_exact_check(NULL), MS_ERR_NULL);
    assert_int_equal(step_planner_init_exact(&pl, NULL, 0), MS_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(new_accel_after_a_stop),
        cmocka_unit_test(check_gives_set_params_status),
        cmocka_unit_test(random_histories),
        cmocka_unit_test(stop_from_the_cruise_is_one_profile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
