/* Unit tests: the Leib ramp (lib/src/ramp_leib.h through the planner ramp.h).
 * Expectations come from the lab (the lab handout §4.3.3), Eiderman's equations recomputed here, the
 * accuracy figures in the peer figures gathered for this project (measured side by side) and the exact constant-acceleration step
 * times t_n = (sqrt(v0^2 + 2 a n) - v0)/a computed here in long double. */
#include "cmocka_all.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ramp.h"

static const ramp_params_t LAB = {1.0, 20.0, 10.0, 1000}; /* v0, vmax, a, F: the lab's defaults */

/* All intervals of a move (index 1..D), float values as the Mega computes them. */
static float *leib_intervals(const ramp_params_t *p, int32_t from, int32_t to, uint32_t *count)
{
    ramp_t r;
    ramp_step_t s;
    uint32_t d = ramp_distance(from, to);
    float *iv = calloc(d + 2, sizeof *iv);
    assert_non_null(iv);
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_LEIB, p, from, to), MS_OK);
    *count = 0;
    while (ramp_next(&r, &s)) {
        (*count)++;
        assert_int_equal(s.step, *count);
        iv[s.step] = (float)s.interval_ticks;
    }
    return iv;
}

/* exact interval of accelerating step n from rest-or-v0 (no cruise), seconds */
static long double exact_accel_interval(long double v0, long double a, unsigned long n)
{
    long double t1 = (sqrtl(v0 * v0 + 2.0L * a * (long double)n) - v0) / a;
    long double t0 = (sqrtl(v0 * v0 + 2.0L * a * (long double)(n - 1)) - v0) / a;
    return t1 - t0;
}

/* the lab handout §4.3.3 step 8: "the first ... values of step time (p) should be 218.218, 188.528 and
 * 157.245 ticks (here representing milliseconds)" for 0 -> 50, v0 = 1, vmax = 20, a = 10, F = 1000. */
static void lab_checkpoint_first_three_intervals(void **state)
{
    uint32_t n;
    float *iv = leib_intervals(&LAB, 0, 50, &n);
    (void)state;
    assert_int_equal(n, 50);
    assert_true(fabs(iv[1] - 218.218) < 0.0005);
    assert_true(fabs(iv[2] - 188.528) < 0.0005);
    assert_true(fabs(iv[3] - 157.245) < 0.0005);
    free(iv);
}

/* Lab steps 1-5 recomputed: S = int((400 - 1)/20) = 19 (2S = 39.9 < 50), p1 = 1000/sqrt(21),
 * ps = 1000/20 = 50, R = 10/1000^2. */
static void lab_precomputation(void **state)
{
    ramp_leib_t l;
    (void)state;
    assert_int_equal(ramp_leib_plan(&l, &LAB, 50), MS_OK);
    assert_int_equal(l.accel_steps, 19);
    assert_true(fabs(l.p1 - 1000.0 / sqrt(21.0)) < 1e-4);
    assert_true(fabs(l.ps - 50.0) < 1e-5);
    assert_true(fabs(l.r - 1e-5) < 1e-12);
    assert_true(fabs(l.peak_sps - 20.0) < 1e-6);
    assert_true(l.p == l.p1);
}

/* Lab step 2: a move too short to reach vmax: 2S = 39.9 > 30 steps, so v = sqrt(1 + 10*30) and
 * S = int(30/2) = 15. */
static void short_move_recomputes_peak_speed(void **state)
{
    ramp_leib_t l;
    uint32_t n, i;
    float *iv;
    (void)state;
    assert_int_equal(ramp_leib_plan(&l, &LAB, 30), MS_OK);
    assert_int_equal(l.accel_steps, 15);
    assert_true(fabs(l.peak_sps - sqrt(301.0)) < 1e-4);
    assert_true(fabs(l.ps - 1000.0 / sqrt(301.0)) < 1e-3);
    iv = leib_intervals(&LAB, 0, 30, &n);
    assert_int_equal(n, 30);
    /* accelerates for steps 1..15, the two middle steps share the peak, then decelerates */
    for (i = 2; i <= 15; i++)
        assert_true(iv[i] < iv[i - 1]);
    assert_true(iv[16] == iv[15]);
    for (i = 17; i <= 30; i++)
        assert_true(iv[i] >= iv[i - 1]);
    free(iv);
}

/* Lab step 6 recomputed in float, operation by operation, the way the Mega does it: the planner
 * must give bit-identical values (no double promotion anywhere). */
static void update_is_the_lab_formula_in_float(void **state)
{
    uint32_t n, i;
    float *iv = leib_intervals(&LAB, 0, 50, &n);
    float r = 10.0f / (1000.0f * 1000.0f);
    float p1 = 1000.0f / sqrtf(1.0f * 1.0f + 2.0f * 10.0f);
    float p = p1;
    (void)state;
    assert_true(iv[1] == p1);
    for (i = 2; i <= 19; i++) { /* accelerating: m = -R */
        float m = -r, q = m * p * p;
        p = p * (1.0f + q + 1.5f * q * q);
        assert_true(iv[i] == p);
    }
    for (i = 20; i <= 32; i++) /* cruise: m = 0, p unchanged */
        assert_true(iv[i] == p);
    for (i = 33; i <= 50; i++) { /* decelerating: m = +R, never above p1 */
        float m = r, q = m * p * p;
        p = p * (1.0f + q + 1.5f * q * q);
        if (p > p1)
            p = p1;
        assert_true(iv[i] == p);
    }
    free(iv);
}

/* The published accuracy of "Leib with 1.5 q^2 (the lab's version)" (docs/ramps.md): error of step 1 -50 %; max interval error
 * steps 11-100 5.8 %, steps 101-1000 0.59 %, beyond 1000 0.059 % (from rest). Checked to the
 * precision the table gives; deceleration (mirrored) must do no worse. */
static void interval_errors_by_step_band_match_the_published_figures(void **state)
{
    ramp_params_t p = {0.0, 1000.0, 100.0, 1000000};
    const uint32_t d = 20000; /* S = 5000: steps 1..5000 accelerate */
    uint32_t n, k;
    double worst_acc[3] = {0, 0, 0}, worst_dec[3] = {0, 0, 0}, first;
    float *iv = leib_intervals(&p, 0, (int32_t)d, &n);
    (void)state;
    first = 100.0 * (iv[1] / 1e6 - (double)exact_accel_interval(0, 100, 1)) / (double)exact_accel_interval(0, 100, 1);
    assert_true(fabs(first - (-50.0)) < 0.05);
    for (k = 11; k <= 5000; k++) {
        double ex = (double)exact_accel_interval(0, 100, k);
        double ea = fabs(100.0 * (iv[k] / 1e6 - ex) / ex);
        double ed = fabs(100.0 * (iv[d + 1 - k] / 1e6 - ex) / ex);
        int b = k <= 100 ? 0 : (k <= 1000 ? 1 : 2);
        if (ea > worst_acc[b])
            worst_acc[b] = ea;
        if (ed > worst_dec[b])
            worst_dec[b] = ed;
    }
    assert_true(fabs(worst_acc[0] - 5.8) <= 0.05);
    assert_true(fabs(worst_acc[1] - 0.59) <= 0.005);
    assert_true(fabs(worst_acc[2] - 0.059) <= 0.0005);
    assert_true(worst_dec[0] <= 5.85);
    assert_true(worst_dec[1] <= 0.595);
    assert_true(worst_dec[2] <= 0.0595);
    free(iv);
}

/* Symmetry: the deceleration mirrors the acceleration (step n vs step D + 1 - n). Leib's decel
 * update is not the exact inverse of its accel update (both are 2nd-order Taylor series of
 * 1/sqrt(1 -+ 2q)), so the mirror holds to the third-order term: within 16 % over the first 10
 * steps from either end (q up to 0.5 there), then far closer; the last step is clamped to p1. */
static void deceleration_mirrors_acceleration(void **state)
{
    ramp_params_t p = {0.0, 1000.0, 100.0, 1000000};
    uint32_t n, k, d = 20000;
    float *iv = leib_intervals(&p, 0, (int32_t)d, &n);
    (void)state;
    assert_true(iv[d] == iv[1]); /* clamped at p1 */
    for (k = 1; k <= d / 2; k++) {
        double rel = fabs(iv[k] - iv[d + 1 - k]) / iv[k];
        if (k <= 10)
            assert_true(rel < 0.16);
        else if (k <= 100)
            assert_true(rel < 0.03);
        else
            assert_true(rel < 0.003);
    }
    free(iv);
    iv = leib_intervals(&LAB, 0, 50, &n); /* and the lab's own move */
    assert_true(iv[50] == iv[1]);
    for (k = 1; k <= 25; k++)
        assert_true(fabs(iv[k] - iv[51 - k]) / iv[k] < 0.16);
    free(iv);
}

/* Zero, one and two steps, and a negative move (direction only; same intervals). */
static void tiny_and_negative_moves(void **state)
{
    ramp_t r;
    ramp_step_t s;
    uint32_t n, i;
    float *fwd, *bwd;
    (void)state;
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_LEIB, &LAB, 7, 7), MS_OK);
    assert_int_equal(ramp_next(&r, &s), 0);
    /* one step: v = sqrt(v0^2 + a) (lab step 2 with D = 1), S = 0, p1 raised to ps = F/v */
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_LEIB, &LAB, 0, 1), MS_OK);
    assert_int_equal(ramp_next(&r, &s), 1);
    assert_true(fabs(s.interval_ticks - 1000.0 / sqrt(11.0)) < 1e-3);
    assert_int_equal(s.position, 1);
    assert_int_equal(ramp_next(&r, &s), 0);
    /* two steps: v = sqrt(1 + 20) so p1 = ps, both steps at the same interval */
    fwd = leib_intervals(&LAB, 0, 2, &n);
    assert_int_equal(n, 2);
    assert_true(fabs(fwd[1] - 1000.0 / sqrt(21.0)) < 1e-3);
    assert_true(fwd[2] == fwd[1]);
    free(fwd);
    fwd = leib_intervals(&LAB, 100, 150, &n);
    bwd = leib_intervals(&LAB, 100, 50, &n);
    for (i = 1; i <= 50; i++)
        assert_true(fwd[i] == bwd[i]);
    free(fwd);
    free(bwd);
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_LEIB, &LAB, 100, 50), MS_OK);
    for (i = 1; ramp_next(&r, &s); i++)
        assert_int_equal(s.position, 100 - (int32_t)i);
    assert_int_equal(i - 1, 50);
}

/* Every bad parameter gets its own status and leaves the ramp as it was. */
static void bad_parameters_are_rejected(void **state)
{
    const struct {
        ramp_params_t p;
        motion_status_t want;
    } cases[] = {
        {{1, 20, 0, 1000}, MS_ERR_ACCEL_NOT_POSITIVE},
        {{1, 20, -10, 1000}, MS_ERR_ACCEL_NOT_POSITIVE},
        {{-1, 20, 10, 1000}, MS_ERR_V0_NEGATIVE},
        {{20, 20, 10, 1000}, MS_ERR_VMAX_NOT_ABOVE_V0},
        {{30, 20, 10, 1000}, MS_ERR_VMAX_NOT_ABOVE_V0},
        {{1, 20, 10, 0}, MS_ERR_TICK_HZ_ZERO},
        {{1, 2000, 10, 1000}, MS_ERR_VMAX_ABOVE_TICK_HZ},
        {{NAN, 20, 10, 1000}, MS_ERR_NOT_FINITE},
        {{1, INFINITY, 10, 1000}, MS_ERR_NOT_FINITE},
        {{1, 20, NAN, 1000}, MS_ERR_NOT_FINITE},
        /* p1 = 4e9 / sqrt(2e-6) is about 2.8e12 ticks: more than 32 bits */
        {{0, 20, 1e-6, 4000000000UL}, MS_ERR_INTERVAL_TOO_LONG},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ramp_t r, before;
        memset(&r, 0x5a, sizeof r);
        before = r;
        assert_int_equal(ramp_plan(&r, RAMP_ALGO_LEIB, &cases[i].p, 0, 50), cases[i].want);
        assert_memory_equal(&r, &before, sizeof r);
    }
}

/* 32-bit extremes: INT32_MIN -> INT32_MAX is 2^32 - 1 steps; -2147483647 -> 2147483647 is 2^32 - 2.
 * The plan and every counter stay exact; after the cruise (skipped: its intervals are all equal)
 * the deceleration ends exactly at the target with the same intervals as a short move's end. */
static void extreme_distances_do_not_overflow(void **state)
{
    const ramp_params_t p = {100.0, 1000.0, 1000.0, 2000000};
    const int32_t ends[][2] = {{INT32_MIN, INT32_MAX}, {INT32_MAX, INT32_MIN}, {-2147483647, 2147483647},
                               {2147483647, -2147483647}};
    size_t c;
    float *ref;
    uint32_t nref, s_ref;
    ramp_leib_t lref;
    (void)state;
    /* a 2000-step move has the same S (495) and so the same first and last 495 intervals */
    assert_int_equal(ramp_leib_plan(&lref, &p, 2000), MS_OK);
    s_ref = lref.accel_steps;
    ref = leib_intervals(&p, 0, 2000, &nref);
    for (c = 0; c < sizeof ends / sizeof ends[0]; c++) {
        ramp_t r;
        ramp_step_t s;
        uint32_t d = ramp_distance(ends[c][0], ends[c][1]), i, skipped;
        int32_t last = 0;
        assert_int_equal(d, c < 2 ? 4294967295UL : 4294967294UL);
        assert_int_equal(ramp_plan(&r, RAMP_ALGO_LEIB, &p, ends[c][0], ends[c][1]), MS_OK);
        assert_int_equal(r.steps_total, d);
        assert_int_equal(r.accel_steps, s_ref);
        for (i = 1; i <= s_ref + 5; i++) {
            assert_int_equal(ramp_next(&r, &s), 1);
            assert_true(s.interval_ticks == (i <= s_ref ? ref[i] : ref[s_ref]));
            assert_int_equal(s.position, (int32_t)((int64_t)ends[c][0] + (ends[c][1] > ends[c][0] ? 1 : -1) * (int64_t)i));
        }
        skipped = ramp_skip_cruise(&r);
        assert_int_equal(skipped, d - s_ref - (s_ref + 5));
        i = 0;
        while (ramp_next(&r, &s)) {
            i++;
            /* the last s_ref steps equal the 2000-step move's last s_ref steps */
            if (s.step > d - s_ref)
                assert_true(s.interval_ticks == ref[2000 - (d - s.step)]);
            last = s.position;
            assert_true(s.step <= d);
        }
        assert_int_equal(i, s_ref); /* the last flat step, then S - 1 decelerating ones */
        assert_int_equal(last, ends[c][1]);
    }
    free(ref);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lab_checkpoint_first_three_intervals),
        cmocka_unit_test(lab_precomputation),
        cmocka_unit_test(short_move_recomputes_peak_speed),
        cmocka_unit_test(update_is_the_lab_formula_in_float),
        cmocka_unit_test(interval_errors_by_step_band_match_the_published_figures),
        cmocka_unit_test(deceleration_mirrors_acceleration),
        cmocka_unit_test(tiny_and_negative_moves),
        cmocka_unit_test(bad_parameters_are_rejected),
        cmocka_unit_test(extreme_distances_do_not_overflow),
    };
    return cmocka_run_group_tests_name("ramp_leib", tests, NULL, NULL);
}
