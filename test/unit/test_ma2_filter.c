/* Unit tests: ma2_filter - two moving averages in series (the S-curve of the moving-average-filter note, "Two-stage
 * moving average acceleration"), exact at the sample instants. Expectations come from the
 * continuous-time step response of G1 G2 (piecewise quadratic), its superposition for arbitrary
 * held inputs, and direct sums of the definition. */
#include "cmocka_all.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "filter_param.h"
#include "filter_testutil.h"
#include "ma2_filter.h"

/* Unit-step response of (1/(t1 t2)) (1 - e^(-t1 s))(1 - e^(-t2 s)) / s^2 (the step is 1/s):
 *   S(t) = [r(t) - r(t - t1) - r(t - t2) + r(t - t1 - t2)] / (t1 t2),  r(t) = t^2/2 for t > 0. */
static long double r2(long double t)
{
    return t > 0 ? t * t / 2 : 0;
}

static long double s_curve(long double t, long double t1, long double t2)
{
    return (r2(t) - r2(t - t1) - r2(t - t2) + r2(t - t1 - t2)) / (t1 * t2);
}

static double volts(int64_t num, const ma2_filter_t *f)
{
    return (double)num * 0.001 / ma2_filter_den(f);
}

/* the moving-average-filter note scenario with the S-curve filter: tau1 = 9 s, tau2 = 3 s, Ts = 10 ms, a 5 V step held
 * 20 s. Every sample equals the continuous S-curve at t = k Ts within 1e-9 V; the output reaches
 * 5 V at exactly tau1 + tau2 = 12 s and not before; half-way (6 s) it is 2.5 V. */
static void note_000_step_gives_the_continuous_s_curve_at_every_sample(void **state)
{
    int16_t buf[1200];
    ma2_filter_t f;
    uint16_t n1 = 0, n2 = 0;
    uint32_t k;
    (void)state;
    assert_int_equal(filt_taps(9.0, 0.01, &n1), MS_OK);
    assert_int_equal(filt_taps(3.0, 0.01, &n2), MS_OK);
    assert_int_equal(ma2_filter_init(&f, buf, 1200, n1, n2), MS_OK);
    assert_int_equal(ma2_filter_den(&f), 2u * 900u * 300u);
    for (k = 0; k <= 2000; k++) {
        double y = volts(ma2_filter_step(&f, 5000), &f);
        double ideal = (double)(5.0L * s_curve(k * 0.01L, 9.0L, 3.0L));
        assert_true(fabs(y - ideal) <= 1e-9);
        if (k == 600)
            assert_true(fabs(y - 2.5) <= 1e-12);
        if (k == 1199)
            assert_true(y < 5.0);
        if (k >= 1200)
            assert_true(y == 5.0);
    }
}

/* Any held input, not just a step: by superposition the exact continuous output at t = k Ts is
 *   y(k Ts) = sum_j u[j] (S(k Ts - j Ts) - S(k Ts - (j+1) Ts)),
 * u[j] held on [j Ts, (j+1) Ts). The filter matches it to 1e-9 of full scale for random
 * full-scale input, with unequal stages (N1 = 50, N2 = 13) in both orders. */
static void any_held_input_gives_the_exact_continuous_output(void **state)
{
    static int16_t in[3000];
    int16_t buf1[63], buf2[63];
    ma2_filter_t a, b;
    const long double ts = 0.01L, t1 = 0.5L, t2 = 0.13L;
    int k, j;
    (void)state;
    for (k = 0; k < 3000; k++)
        in[k] = tu_sample(3, (uint64_t)k);
    assert_int_equal(ma2_filter_init(&a, buf1, 63, 50, 13), MS_OK);
    assert_int_equal(ma2_filter_init(&b, buf2, 63, 13, 50), MS_OK);
    for (k = 0; k < 3000; k++) {
        long double exact = 0; /* in quanta */
        int64_t na = ma2_filter_step(&a, in[k]);
        int64_t nb = ma2_filter_step(&b, in[k]);
        for (j = k - 64 < 0 ? 0 : k - 64; j < k; j++)
            exact += in[j] * (s_curve((k - j) * ts, t1, t2) - s_curve((k - j - 1) * ts, t1, t2));
        assert_true(fabsl((long double)na / ma2_filter_den(&a) - exact) <= 32767 * 1e-9L);
        assert_true(na == nb); /* the order of the stages does not matter, exactly */
    }
}

/* The S-curve's defining properties, in exact integer terms (y = q num / (2 N1 N2)). For a step of
 * A quanta (and a square wave whose half period exceeds tau1 + tau2, so edges never overlap):
 *  - continuous velocity: y never jumps; it changes per sample by at most the steepest slope,
 *    |y[k+1] - y[k]| <= A Ts / max(tau1, tau2), i.e. |d num| <= 2 A min(N1, N2);
 *  - bounded jerk: the second difference is at most A Ts^2 / (tau1 tau2) (jerk A/(tau1 tau2)),
 *    i.e. |d2 num| <= 2 A, and that bound is reached (the jerk phases).
 * A single moving average fails the jerk bound at its corners (second difference A/N per sample):
 * the check can tell the two apart. */
static void check_s_curve(uint16_t n1, uint16_t n2, int16_t amp, uint32_t half)
{
    static int16_t buf[4000];
    ma2_filter_t f;
    int64_t prev = 0, prev2 = 0, worst_d1 = 0, worst_d2 = 0;
    uint32_t k, kmax = 6u * half;
    const int64_t a = amp < 0 ? -(int64_t)amp : amp;
    const int64_t max_d1 = 2 * a * (n1 < n2 ? n1 : n2), max_d2 = 2 * a;
    assert_int_equal(ma2_filter_init(&f, buf, 4000, n1, n2), MS_OK);
    for (k = 0; k < kmax; k++) {
        int64_t y = ma2_filter_step(&f, tu_square(amp, half, k));
        if (k >= 1) {
            int64_t d1 = y - prev;
            if (llabs(d1) > worst_d1)
                worst_d1 = llabs(d1);
        }
        if (k >= 2) {
            int64_t d2 = y - 2 * prev + prev2;
            if (llabs(d2) > worst_d2)
                worst_d2 = llabs(d2);
        }
        prev2 = prev;
        prev = y;
    }
    assert_true(worst_d1 <= max_d1);
    assert_true(worst_d2 <= max_d2);
    if (n1 >= 2 && n2 >= 2) /* a jerk phase of min(tau1, tau2) >= 2 Ts contains whole second differences */
        assert_true(worst_d2 == max_d2); /* attained: the jerk phases are exactly +-A/(tau1 tau2) */
    if (n1 != n2)
        assert_true(worst_d1 == max_d1); /* constant-acceleration phase at A/max(tau) */
}

static void s_curve_has_continuous_velocity_and_bounded_jerk(void **state)
{
    (void)state;
    /* the moving-average-filter note scenario: 5 V square wave, 30 s period, tau1 = 9 s, tau2 = 3 s, Ts = 10 ms */
    check_s_curve(900, 300, 5000, 1500);
    check_s_curve(300, 900, 5000, 1500);
    check_s_curve(400, 400, -3210, 1000); /* equal stages: triangular acceleration */
    check_s_curve(1, 1, 32767, 3);        /* the shortest: tau1 = tau2 = Ts, full scale */
    check_s_curve(900, 1, 5000, 1500);    /* tau2 = Ts: jerk A/(tau1 Ts) during one sample only */
}

/* A plain moving average (N2 taps of nothing) would fail the jerk check: emulate it with the same
 * integer scale 2 N1 N2 and show the bound is violated at its corners. */
static void single_moving_average_fails_the_jerk_bound(void **state)
{
    const int64_t n1 = 900, n2 = 300, amp = 5000;
    int64_t prev = 0, prev2 = 0, worst = 0;
    int64_t k;
    (void)state;
    for (k = 0; k < 3000; k++) {
        /* ma output for a step at 0, scaled to num units: 2 N1 N2 * A min(k, N1)/N1 */
        int64_t y = 2 * n2 * amp * (k < n1 ? k : n1);
        if (k >= 2 && llabs(y - 2 * prev + prev2) > worst)
            worst = llabs(y - 2 * prev + prev2);
        prev2 = prev;
        prev = y;
    }
    assert_true(worst > 2 * amp); /* 2 N2 A = 300 times the S-curve's bound */
}

/* Direct recomputation from the definitions: S1[m] = u[m-1] + ... + u[m-N1],
 * num[k] = 2 (S1[k-1] + ... + S1[k-N2]) + S1[k] - S1[k-N2]. */
static int64_t s1_at(uint64_t seed, uint64_t m, uint16_t n1)
{
    int64_t s = 0;
    uint64_t j;
    for (j = 1; j <= n1 && j <= m; j++)
        s += tu_sample(seed, m - j);
    return s;
}

static int64_t num_at(uint64_t seed, uint64_t k, uint16_t n1, uint16_t n2)
{
    int64_t t = 0;
    uint64_t i;
    for (i = 1; i <= n2 && i <= k; i++)
        t += s1_at(seed, k - i, n1);
    return 2 * t + s1_at(seed, k, n1) - (k >= n2 ? s1_at(seed, k - n2, n1) : 0);
}

/* No drift: after 10^8 full-scale random samples (the moving-average-filter note's tau1 = 9 s, tau2 = 3 s) the output
 * is still exactly the definition recomputed from the inputs; checked every 2.5 * 10^7 samples. */
static void no_drift_after_1e8_samples(void **state)
{
    static int16_t buf[1200];
    ma2_filter_t f;
    const uint64_t total = 100000000ull, every = 25000000ull;
    uint64_t k;
    (void)state;
    assert_int_equal(ma2_filter_init(&f, buf, 1200, 900, 300), MS_OK);
    for (k = 0; k < total; k++) {
        int64_t num = ma2_filter_step(&f, tu_sample(5, k));
        if (k % every == every - 1 || k == 1500)
            assert_true(num == num_at(5, k, 900, 300));
    }
    assert_true(ma2_filter_num(&f) == num_at(5, total, 900, 300));
}

/* Largest configuration: N1 + N2 = 65535 taps at full scale: the 64-bit sum holds
 * 2 N1 N2 * 32767 exactly and the output is exactly 32767 quanta. */
static void largest_configuration_at_full_scale_is_exact(void **state)
{
    static int16_t buf[65535];
    ma2_filter_t f;
    uint32_t k;
    (void)state;
    assert_int_equal(ma2_filter_init(&f, buf, 65535, 32767, 32768), MS_OK);
    assert_int_equal(ma2_filter_den(&f), 2u * 32767u * 32768u);
    for (k = 0; k < 65535u; k++)
        (void)ma2_filter_step(&f, -32767);
    assert_true(ma2_filter_num(&f) == -(int64_t)ma2_filter_den(&f) * 32767);
    for (k = 0; k < 65535u; k++)
        (void)ma2_filter_step(&f, 32767);
    assert_true(ma2_filter_num(&f) == (int64_t)ma2_filter_den(&f) * 32767);
}

static void reset_returns_to_rest(void **state)
{
    int16_t buf[5];
    ma2_filter_t f;
    int i;
    (void)state;
    assert_int_equal(ma2_filter_init(&f, buf, 5, 3, 2), MS_OK);
    for (i = 0; i < 9; i++)
        (void)ma2_filter_step(&f, 100);
    assert_true(ma2_filter_num(&f) == 100 * 12);
    ma2_filter_reset(&f);
    assert_true(ma2_filter_num(&f) == 0);
    assert_true(ma2_filter_step(&f, 100) == 0);
    /* y[1] = (1/N2) * (y1[0] + y1[1])/2 = (0 + 100/3)/2/2 = 100/12: num = 2*3*2*100/12 = 100 */
    assert_true(ma2_filter_step(&f, 100) == 100);
}

static void bad_parameters_are_rejected_and_change_nothing(void **state)
{
    int16_t buf[8] = {1, 2, 3, 4, 5, 6, 7, 8}, copy[8];
    ma2_filter_t f, before;
    (void)state;
    memcpy(copy, buf, sizeof buf);
    memset(&f, 0xA5, sizeof f);
    before = f;
    assert_int_equal(ma2_filter_init(NULL, buf, 8, 4, 4), MS_ERR_NULL);
    assert_int_equal(ma2_filter_init(&f, NULL, 8, 4, 4), MS_ERR_NULL);
    assert_int_equal(ma2_filter_init(&f, buf, 8, 0, 4), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(ma2_filter_init(&f, buf, 8, 4, 0), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(ma2_filter_init(&f, buf, 8, 4, 5), MS_ERR_TOO_MANY_TAPS);
    assert_int_equal(ma2_filter_init(&f, buf, 65535, 65535, 65535), MS_ERR_TOO_MANY_TAPS);
    assert_memory_equal(&f, &before, sizeof f);
    assert_memory_equal(buf, copy, sizeof buf);
    assert_int_equal(ma2_filter_init(&f, buf, 8, 4, 4), MS_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(note_000_step_gives_the_continuous_s_curve_at_every_sample),
        cmocka_unit_test(any_held_input_gives_the_exact_continuous_output),
        cmocka_unit_test(s_curve_has_continuous_velocity_and_bounded_jerk),
        cmocka_unit_test(single_moving_average_fails_the_jerk_bound),
        cmocka_unit_test(no_drift_after_1e8_samples),
        cmocka_unit_test(largest_configuration_at_full_scale_is_exact),
        cmocka_unit_test(reset_returns_to_rest),
        cmocka_unit_test(bad_parameters_are_rejected_and_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
