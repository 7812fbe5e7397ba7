/* Unit tests: the simplistic ramp (lib/src/ramp_simplistic.h), the lab handout §4.3.2 eqs. 1-2:
 * dp = (p_max - p_min)/S, p -= dp accelerating, p += dp decelerating. */
#include "cmocka_all.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ramp.h"

static const ramp_params_t LAB = {1.0, 20.0, 10.0, 1000};

static double *intervals(const ramp_params_t *p, int32_t from, int32_t to, uint32_t *count)
{
    ramp_t r;
    ramp_step_t s;
    double *iv = calloc(ramp_distance(from, to) + 2, sizeof *iv);
    assert_non_null(iv);
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_SIMPLISTIC, p, from, to), MS_OK);
    *count = 0;
    while (ramp_next(&r, &s))
        iv[++*count] = s.interval_ticks;
    return iv;
}

/* The lab's move with the lab's defaults (§4.3.2: 0 -> 50, 1 step/s, 20 steps/s, 10 steps/s^2):
 * p_max = F/v0 = 1000 ms, p_min = F/vmax = 50 ms, S = 19 (as for Leib), so eq. (1) gives
 * dp = 950/19 = 50 ms: 1000, 950, ..., 100, then 50 ms from step 20, and back up to 1000. */
static void lab_move_steps_down_by_fixed_amount(void **state)
{
    uint32_t n, i;
    double *iv = intervals(&LAB, 0, 50, &n), total = 0.0;
    (void)state;
    assert_int_equal(n, 50);
    for (i = 1; i <= 20; i++)
        assert_true(fabs(iv[i] - (1000.0 - 50.0 * (i - 1))) < 1e-3);
    for (i = 20; i <= 31; i++)
        assert_true(fabs(iv[i] - 50.0) < 1e-3);
    for (i = 32; i <= 50; i++)
        assert_true(fabs(iv[i] - (50.0 + 50.0 * (i - 31))) < 1e-3);
    for (i = 1; i <= 50; i++)
        total += iv[i];
    /* 2 * (1000 + 950 + ... + 100) + 12 * 50 = 2 * 10450 + 600 ms */
    assert_true(fabs(total - 21500.0) < 0.01);
    free(iv);
}

/* "It starts very slowly then builds up to an unrealistically large acceleration as the desired
 * speed is approached" (§4.3.1): with speeds F/p the speed gain per second of the first step is
 * far below a = 10 and that of the last accelerating step far above it. */
static void acceleration_is_far_from_constant(void **state)
{
    uint32_t n;
    double *iv = intervals(&LAB, 0, 50, &n);
    /* speed change between consecutive steps divided by the time between their mid-points */
    double first = (1000.0 / iv[2] - 1000.0 / iv[1]) / ((iv[1] + iv[2]) / 2000.0);
    double last = (1000.0 / iv[20] - 1000.0 / iv[19]) / ((iv[19] + iv[20]) / 2000.0);
    (void)state;
    assert_true(first < 0.1);   /* 1 -> 1.053 steps/s in 0.975 s: about 0.054 steps/s^2 */
    assert_true(last > 100.0);  /* 10 -> 20 steps/s in 0.075 s: about 133 steps/s^2 */
    free(iv);
}

/* Symmetric: step n and step D + 1 - n have the same interval (float rounding of the repeated
 * additions aside), for long and short moves, odd and even. */
static void deceleration_mirrors_acceleration(void **state)
{
    const int32_t targets[] = {1, 2, 3, 38, 39, 40, 41, 50, 2000};
    size_t t;
    (void)state;
    for (t = 0; t < sizeof targets / sizeof targets[0]; t++) {
        uint32_t n, i;
        double *iv = intervals(&LAB, 0, targets[t], &n);
        assert_int_equal(n, (uint32_t)targets[t]);
        for (i = 1; i <= n; i++)
            assert_true(fabs(iv[i] - iv[n + 1 - i]) <= 1e-4 * iv[i]);
        assert_true(fabs(iv[1] - 1000.0) < 1e-9); /* always starts at F/v0 */
        free(iv);
    }
}

/* A short move: 2S = 39.9 > 31, so v = sqrt(1 + 10*31), S = 15 and dp = (1000 - 1000/v)/15. */
static void short_move(void **state)
{
    uint32_t n, i;
    double *iv = intervals(&LAB, 0, 31, &n);
    double p_min = 1000.0 / sqrt(1.0 + 10.0 * 31.0), dp = (1000.0 - p_min) / 15.0;
    (void)state;
    for (i = 1; i <= 16; i++)
        assert_true(fabs(iv[i] - (1000.0 - dp * (i - 1))) < 1e-3);
    assert_true(fabs(iv[16] - p_min) < 1e-3); /* the peak, reached at step S + 1 */
    free(iv);
}

/* S = int((vmax^2 - v0^2)/2a) = 0 (v0 1, vmax 4, a 10: 15/20 = 0.75) would make eq. (1)'s
 * dp = 0/0 or, as before, 0: a move crawling at v0. Instead S = 1: one step at p_max = F/v0 =
 * 1000, then p_min = F/vmax = 250 (allowed: reaching 4 steps/s from 1 within one step needs only
 * (16 - 1)/2 = 7.5 steps/s^2 < a), and the last step at F/v0 again. */
static void vmax_within_one_step_of_v0_is_reached_in_one_step(void **state)
{
    const ramp_params_t p = {1.0, 4.0, 10.0, 1000};
    const struct {
        int32_t to;
        double want[6];
    } cases[] = {
        {1, {1000}},                         /* one step: starts and stops at v0 */
        {2, {1000, 1000}},                   /* two steps: no step between the two ends */
        {3, {1000, 250, 1000}},
        {5, {1000, 250, 250, 250, 1000}},
        {-6, {1000, 250, 250, 250, 250, 1000}},
    };
    size_t c;
    (void)state;
    for (c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        uint32_t n, i;
        double *iv = intervals(&p, 0, cases[c].to, &n);
        assert_int_equal(n, ramp_distance(0, cases[c].to));
        for (i = 1; i <= n; i++)
            assert_true(fabs(iv[i] - cases[c].want[i - 1]) < 1e-9);
        free(iv);
    }
    /* a long move cruises at vmax: every step but the first and the last at F/vmax */
    {
        uint32_t n, i;
        ramp_t r;
        double *iv = intervals(&p, 0, 1000, &n);
        for (i = 2; i < n; i++)
            assert_true(iv[i] == 250.0);
        assert_true(iv[1] == 1000.0 && iv[n] == 1000.0);
        free(iv);
        assert_int_equal(ramp_plan(&r, RAMP_ALGO_SIMPLISTIC, &p, 0, 1000), MS_OK);
        assert_int_equal(r.accel_steps, 1);
    }
    /* continuity: S just at 1 by the lab's formula (vmax 5: 24/20 = 1.2) gives the same shape */
    {
        const ramp_params_t p5 = {1.0, 5.0, 10.0, 1000};
        uint32_t n;
        double *iv = intervals(&p5, 0, 4, &n);
        assert_true(iv[1] == 1000.0 && iv[2] == 200.0 && iv[3] == 200.0 && iv[4] == 1000.0);
        free(iv);
    }
}

static void bad_parameters_are_rejected(void **state)
{
    const struct {
        ramp_params_t p;
        motion_status_t want;
    } cases[] = {
        {{0, 20, 10, 1000}, MS_ERR_V0_ZERO_SIMPLISTIC}, /* p_max = F/v0 would be infinite */
        {{1, 20, 0, 1000}, MS_ERR_ACCEL_NOT_POSITIVE},  {{-1, 20, 10, 1000}, MS_ERR_V0_NEGATIVE},
        {{1, 1, 10, 1000}, MS_ERR_VMAX_NOT_ABOVE_V0},   {{1, 20, 10, 0}, MS_ERR_TICK_HZ_ZERO},
        {{1, 20, NAN, 1000}, MS_ERR_NOT_FINITE},        {{1, 2e3, 10, 1000}, MS_ERR_VMAX_ABOVE_TICK_HZ},
        {{1e-4, 20, 10, 1000000}, MS_ERR_INTERVAL_TOO_LONG}, /* F/v0 = 1e10 ticks */
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ramp_t r, before;
        memset(&r, 0x77, sizeof r);
        before = r;
        assert_int_equal(ramp_plan(&r, RAMP_ALGO_SIMPLISTIC, &cases[i].p, 0, 50), cases[i].want);
        assert_memory_equal(&r, &before, sizeof r);
    }
}

/* From -2147483647 to 2147483647 (2^32 - 2 steps) and back: exact counts and end positions. */
static void extreme_distances(void **state)
{
    const ramp_params_t p = {100.0, 1000.0, 1000.0, 2000000};
    int dir;
    (void)state;
    for (dir = 0; dir < 2; dir++) {
        ramp_t r;
        ramp_step_t s;
        int32_t from = dir ? 2147483647 : -2147483647, to = -from;
        uint32_t i, left;
        assert_int_equal(ramp_plan(&r, RAMP_ALGO_SIMPLISTIC, &p, from, to), MS_OK);
        assert_int_equal(r.steps_total, 4294967294UL);
        for (i = 0; i < 600; i++)
            assert_int_equal(ramp_next(&r, &s), 1);
        /* cruising at F/vmax, up to the float rounding of 495 subtractions (half an ulp of 20000 each) */
        assert_true(fabs(s.interval_ticks - 2000.0) < 495 * 0.5 * 0.001953125);
        assert_true(ramp_skip_cruise(&r) > 4294960000UL);
        left = ramp_steps_left(&r);
        assert_int_equal(left, r.accel_steps + 1);
        while (ramp_next(&r, &s))
            ;
        assert_int_equal(s.position, to);
        assert_int_equal(s.step, 4294967294UL);
        assert_true(fabs(s.interval_ticks - 20000.0) < 0.5); /* the last step is F/v0 again */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lab_move_steps_down_by_fixed_amount),
        cmocka_unit_test(acceleration_is_far_from_constant),
        cmocka_unit_test(deceleration_mirrors_acceleration),
        cmocka_unit_test(short_move),
        cmocka_unit_test(vmax_within_one_step_of_v0_is_reached_in_one_step),
        cmocka_unit_test(bad_parameters_are_rejected),
        cmocka_unit_test(extreme_distances),
    };
    return cmocka_run_group_tests_name("ramp_simplistic", tests, NULL, NULL);
}
