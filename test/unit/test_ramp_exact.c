/* Unit tests: the exact constant-acceleration ramp (lib/src/ramp_exact.h).
 * The reference is the closed form of the issue, t_n = (sqrt(v0^2 + 2 a n) - v0)/a, with a cruise
 * at vmax and a mirrored deceleration, evaluated here in long double independently of the module. */
#include "cmocka_all.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ramp.h"

/* reference time of step n (long double), same profile definition as the issue */
static long double ref_time(long double v0, long double vmax, long double a, unsigned long d, long double n)
{
    long double s = (vmax * vmax - v0 * v0) / (2.0L * a), xa, vp, ta, t_total;
    xa = 2.0L * s >= (long double)d ? (long double)d / 2.0L : s;
    vp = sqrtl(v0 * v0 + 2.0L * a * xa);
    ta = (vp - v0) / a;
    t_total = 2.0L * ta + ((long double)d - 2.0L * xa) / vp;
    if (n <= xa)
        return (sqrtl(v0 * v0 + 2.0L * a * n) - v0) / a;
    if (n <= (long double)d - xa)
        return ta + (n - xa) / vp;
    return t_total - (sqrtl(v0 * v0 + 2.0L * a * ((long double)d - n)) - v0) / a;
}

static void check_against_formula(const ramp_params_t *p, uint32_t d, uint32_t stride)
{
    ramp_exact_t e;
    uint32_t n;
    double worst = 0.0;
    assert_int_equal(ramp_exact_plan(&e, p, d), MS_OK);
    for (n = 1; n <= d; n += (n < 1000 ? 1 : stride)) {
        long double want = ref_time(p->v0_sps, p->vmax_sps, p->accel_sps2, d, (long double)n);
        double rel = (double)fabsl(((long double)ramp_exact_time_s(&e, n) - want) / want);
        if (rel > worst)
            worst = rel;
    }
    /* the issue: each step time within 1e-9 relative of the formula on the host */
    assert_true(worst < 1e-9);
}

static void step_times_match_the_closed_form(void **state)
{
    const ramp_params_t sets[] = {
        {1.0, 20.0, 10.0, 1000},          /* the lab's move */
        {0.0, 1000.0, 100.0, 1000000},    /* from rest */
        {100.0, 1000.0, 1000.0, 2000000}, /* the long profile scenario */
        {5000.0, 5001.0, 0.5, 16000000},  /* v0 >> 2an: the naive formula would cancel */
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof sets / sizeof sets[0]; i++) {
        check_against_formula(&sets[i], 50, 1);
        check_against_formula(&sets[i], 2000, 1);
        check_against_formula(&sets[i], 1000000, 997);
    }
}

/* Velocity exactly linear in time: the mean speed over each interval, placed at the interval's
 * mid-time, rises by a per second in acceleration, is vmax in cruise, falls by a in deceleration. */
static void velocity_is_linear_in_time(void **state)
{
    const ramp_params_t p = {100.0, 1000.0, 1000.0, 2000000};
    ramp_exact_t e;
    uint32_t n, d = 2000; /* x_a = 495 */
    double prev_speed = 0, prev_mid = 0;
    (void)state;
    assert_int_equal(ramp_exact_plan(&e, &p, d), MS_OK);
    for (n = 1; n <= d; n++) {
        double dt = ramp_exact_interval_s(&e, n);
        double mid = ramp_exact_time_s(&e, n) - dt / 2.0;
        double speed = 1.0 / dt;
        if (n >= 2 && n <= 495)
            assert_true(fabs((speed - prev_speed) / (mid - prev_mid) - 1000.0) < 1e-6 * 1000.0);
        if (n >= 497 && n <= 1504)
            assert_true(fabs(speed - 1000.0) < 1e-9 * 1000.0);
        if (n >= 1507)
            assert_true(fabs((speed - prev_speed) / (mid - prev_mid) + 1000.0) < 1e-6 * 1000.0);
        prev_speed = speed;
        prev_mid = mid;
    }
    /* the move time: two ramps of (vmax - v0)/a plus the cruise (D - 2 S)/vmax */
    assert_true(fabs(ramp_exact_time_s(&e, d) - (2.0 * 0.9 + (2000.0 - 990.0) / 1000.0)) < 1e-12);
}

/* Symmetry, exact: interval n equals interval D + 1 - n; intervals sum to the move time. */
static void deceleration_mirrors_acceleration(void **state)
{
    const ramp_params_t p = {1.0, 20.0, 10.0, 1000};
    const uint32_t lengths[] = {1, 2, 3, 7, 39, 40, 50, 2001};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
        ramp_exact_t e;
        uint32_t n, d = lengths[i];
        double sum = 0.0;
        assert_int_equal(ramp_exact_plan(&e, &p, d), MS_OK);
        for (n = 1; n <= d; n++) {
            double a = ramp_exact_interval_s(&e, n), b = ramp_exact_interval_s(&e, d + 1 - n);
            assert_true(fabs(a - b) <= 1e-13 * a);
            sum += a;
        }
        assert_true(fabs(sum - ramp_exact_time_s(&e, d)) <= 1e-12 * sum);
    }
}

/* A short move peaks half-way at v = sqrt(v0^2 + a D) (no cruise); one step takes
 * 2 (sqrt(v0^2 + a) - v0)/a: half a step up, half a step down. */
static void short_moves(void **state)
{
    const ramp_params_t p = {1.0, 20.0, 10.0, 1000};
    ramp_exact_t e;
    (void)state;
    assert_int_equal(ramp_exact_plan(&e, &p, 30), MS_OK);
    assert_true(fabs(e.peak_sps - sqrt(301.0)) < 1e-12);
    assert_true(fabs(ramp_exact_time_s(&e, 15) - (sqrt(301.0) - 1.0) / 10.0) < 1e-12);
    assert_true(fabs(ramp_exact_time_s(&e, 30) - 2.0 * (sqrt(301.0) - 1.0) / 10.0) < 1e-12);
    assert_int_equal(ramp_exact_plan(&e, &p, 1), MS_OK);
    assert_true(fabs(ramp_exact_interval_s(&e, 1) - 2.0 * (sqrt(11.0) - 1.0) / 10.0) < 1e-12);
    assert_int_equal(ramp_exact_plan(&e, &p, 0), MS_OK);
    assert_true(ramp_exact_time_s(&e, 0) == 0.0);
}

/* Through the planner: the lab's move step by step, ticks = seconds * F, phases in order. */
static void planner_gives_exact_intervals_and_phases(void **state)
{
    const ramp_params_t p = {1.0, 20.0, 10.0, 1000};
    ramp_t r;
    ramp_step_t s;
    int order = RAMP_ACCEL;
    (void)state;
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_EXACT, &p, 10, -40), MS_OK);
    while (ramp_next(&r, &s)) {
        long double t1 = ref_time(1, 20, 10, 50, s.step), t0 = ref_time(1, 20, 10, 50, s.step - 1);
        assert_true(fabsl((long double)s.interval_ticks - (t1 - t0) * 1000.0L) < 1e-9L);
        assert_int_equal(s.whole_ticks, (uint32_t)floorl((t1 - t0) * 1000.0L + 0.5L));
        assert_int_equal(s.position, 10 - (int32_t)s.step);
        assert_true((int)s.phase >= order); /* accel, then cruise, then decel */
        order = (int)s.phase;
    }
    assert_int_equal(order, RAMP_DECEL);
    /* S = 19.95 steps: steps 1..20 (mid-points 0.5..19.5) accelerate, 31..50 decelerate */
    assert_int_equal(ramp_exact_phase(&r.u.exact, 20), RAMP_ACCEL);
    assert_int_equal(ramp_exact_phase(&r.u.exact, 21), RAMP_CRUISE);
    assert_int_equal(ramp_exact_phase(&r.u.exact, 30), RAMP_CRUISE);
    assert_int_equal(ramp_exact_phase(&r.u.exact, 31), RAMP_DECEL);
}

/* INT32_MIN -> INT32_MAX: 2^32 - 1 steps; the last step mirrors the first, t_D is the move time. */
static void extreme_distance(void **state)
{
    const ramp_params_t p = {100.0, 1000.0, 1000.0, 2000000};
    ramp_t r;
    ramp_step_t s;
    uint32_t d = 4294967295UL;
    long double t_total = 2.0L * 0.9L + ((long double)d - 990.0L) / 1000.0L;
    (void)state;
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_EXACT, &p, INT32_MIN, INT32_MAX), MS_OK);
    assert_true(fabsl((long double)ramp_exact_time_s(&r.u.exact, d) - t_total) < 1e-9L * t_total);
    assert_true(fabs(ramp_exact_interval_s(&r.u.exact, d) - ramp_exact_interval_s(&r.u.exact, 1)) < 1e-12);
    assert_int_equal(ramp_next(&r, &s), 1);
    assert_int_equal(s.position, INT32_MIN + 1);
    for (uint32_t i = 2; i <= 600; i++)
        assert_int_equal(ramp_next(&r, &s), 1);
    assert_true(ramp_skip_cruise(&r) > 0);
    while (ramp_next(&r, &s))
        assert_true(s.step <= d);
    assert_int_equal(s.step, d);
    assert_int_equal(s.position, INT32_MAX);
    assert_true(fabs(s.interval_ticks - ramp_exact_interval_s(&r.u.exact, 1) * 2e6) < 1e-6);
}

static void bad_parameters_are_rejected(void **state)
{
    const struct {
        ramp_params_t p;
        motion_status_t want;
    } cases[] = {
        {{1, 20, 0, 1000}, MS_ERR_ACCEL_NOT_POSITIVE},  {{-0.5, 20, 10, 1000}, MS_ERR_V0_NEGATIVE},
        {{5, 4, 10, 1000}, MS_ERR_VMAX_NOT_ABOVE_V0},   {{1, 20, 10, 0}, MS_ERR_TICK_HZ_ZERO},
        {{1, 20, -INFINITY, 1000}, MS_ERR_NOT_FINITE},  {{1, 1001, 10, 1000}, MS_ERR_VMAX_ABOVE_TICK_HZ},
        {{0, 20, 1e-6, 4000000000UL}, MS_ERR_INTERVAL_TOO_LONG},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ramp_exact_t e, before;
        memset(&e, 0x33, sizeof e);
        before = e;
        assert_int_equal(ramp_exact_plan(&e, &cases[i].p, 50), cases[i].want);
        assert_memory_equal(&e, &before, sizeof e);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(step_times_match_the_closed_form),
        cmocka_unit_test(velocity_is_linear_in_time),
        cmocka_unit_test(deceleration_mirrors_acceleration),
        cmocka_unit_test(short_moves),
        cmocka_unit_test(planner_gives_exact_intervals_and_phases),
        cmocka_unit_test(extreme_distance),
        cmocka_unit_test(bad_parameters_are_rejected),
    };
    return cmocka_run_group_tests_name("ramp_exact", tests, NULL, NULL);
}
