/* Unit tests: exp_filter - the exponential acc/dec filter of the moving-average-filter note (kind 1, "equivalent to RC
 * circuit"): exact ZOH discretisation of 1/(tau s + 1), in fixed point with error feedback.
 * Expectations: the closed-form step response A (1 - e^(-t/tau)) at the sample instants, the
 * recurrence y[k] = a y[k-1] + (1 - a) u[k-1] evaluated in long double, and expm1(). */
#include "cmocka_all.h"

#include <math.h>
#include <string.h>

#include "exp_filter.h"
#include "filter_param.h"
#include "filter_testutil.h"

#define LSB (1.0L / 65536) /* one q/65536, in quanta */

static double volts(int32_t frac)
{
    return (double)frac * 0.001 / 65536.0;
}

/* The gain is round(2^31 (1 - e^(-1/N))), same as computed from expm1 in long double, for every
 * N from 1 to 5000 and some large ones. */
static void gain_is_the_rounded_exact_value(void **state)
{
    uint32_t n;
    const uint32_t big[] = {9000, 30000, 65534, 65535};
    size_t i;
    (void)state;
    for (n = 1; n <= 5000; n++) {
        uint32_t g = 0;
        long double exact = -expm1l(-1.0L / n) * 2147483648.0L;
        assert_int_equal(exp_filter_gain_q31((uint16_t)n, &g), MS_OK);
        assert_true(fabsl((long double)g - exact) <= 0.5L + 1e-6L);
    }
    for (i = 0; i < sizeof big / sizeof big[0]; i++) {
        uint32_t g = 0;
        long double exact = -expm1l(-1.0L / big[i]) * 2147483648.0L;
        assert_int_equal(exp_filter_gain_q31((uint16_t)big[i], &g), MS_OK);
        assert_true(fabsl((long double)g - exact) <= 0.5L + 1e-6L);
    }
}

/* the moving-average-filter note's scenario with the exponential filter: tau = 9 s, Ts = 10 ms, 5 V step at t = 0 held
 * 20 s. At every sample y[k] = 5 V (1 - e^(-k Ts / tau)) within 1e-6 V; y[0] = 0 and
 * y[1] = 5 V (1 - a) (the one-sample ZOH delay); after one tau (k = 900) 63.2 % of 5 V. */
static void note_000_step_matches_the_closed_form_at_the_samples(void **state)
{
    exp_filter_t f;
    uint32_t g = 0, k;
    uint16_t n = 0;
    (void)state;
    assert_int_equal(filt_taps(9.0, 0.01, &n), MS_OK);
    assert_int_equal(exp_filter_gain_q31(n, &g), MS_OK);
    assert_int_equal(exp_filter_init(&f, g), MS_OK);
    for (k = 0; k <= 2000; k++) {
        double y = volts(exp_filter_step(&f, 5000));
        double ideal = 5.0 * -expm1(-(k * 0.01) / 9.0);
        assert_true(fabs(y - ideal) <= 1e-6);
        if (k == 0)
            assert_true(y == 0.0);
        if (k == 1)
            assert_true(fabs(y - 5.0 * -expm1(-1.0 / 900)) <= 1e-7);
        if (k == 900)
            assert_true(fabs(y - 5.0 * (1.0 - exp(-1.0))) <= 1e-6);
    }
}

/* On a constant input the output settles exactly on it (no rounding stall), from below and from
 * above, and stays there. */
static void settles_exactly_on_a_constant_input(void **state)
{
    exp_filter_t f;
    uint32_t g = 0, k;
    (void)state;
    assert_int_equal(exp_filter_gain_q31(900, &g), MS_OK);
    assert_int_equal(exp_filter_init(&f, g), MS_OK);
    for (k = 0; k < 60000u; k++)
        (void)exp_filter_step(&f, 5000);
    assert_int_equal(exp_filter_frac(&f), 5000 * 65536);
    for (k = 0; k < 60000u; k++)
        (void)exp_filter_step(&f, 1234);
    assert_int_equal(exp_filter_frac(&f), 1234 * 65536);
    for (k = 0; k < 1000u; k++)
        assert_int_equal(exp_filter_step(&f, 1234), 1234 * 65536);
}

/* Error feedback: for any input the fixed-point output stays within one q/65536 of the exact
 * recurrence y[k+1] = y[k] + c (u[k] - y[k]) with the same gain c = gain/2^31 (computed in long
 * double), here over 10^7 full-scale random samples with N = 900 and 10^6 with N = 1 and 7. */
static void stays_within_one_lsb_of_the_exact_recurrence(void **state)
{
    const uint16_t taps[] = {900, 1, 7};
    const uint32_t count[] = {10000000u, 1000000u, 1000000u};
    size_t t;
    (void)state;
    for (t = 0; t < 3; t++) {
        exp_filter_t f;
        uint32_t g = 0, k;
        long double x = 0, c, worst = 0;
        assert_int_equal(exp_filter_gain_q31(taps[t], &g), MS_OK);
        assert_int_equal(exp_filter_init(&f, g), MS_OK);
        c = (long double)g / 2147483648.0L;
        for (k = 0; k < count[t]; k++) {
            int16_t u = tu_sample(11 + t, k);
            long double e = fabsl((long double)exp_filter_step(&f, u) * LSB - x);
            if (e > worst)
                worst = e;
            x = x + c * ((long double)u - x);
        }
        assert_true(worst < LSB * 1.0001L);
    }
}

/* Full-scale swings, -32768 to +32767 and back, with the fastest gain (N = 1): no overflow (the
 * UBSan build checks) and the output never passes its input. */
static void full_scale_swings_never_overshoot(void **state)
{
    exp_filter_t f;
    uint32_t g = 0;
    int i;
    (void)state;
    assert_int_equal(exp_filter_gain_q31(1, &g), MS_OK);
    assert_int_equal(exp_filter_init(&f, g), MS_OK);
    for (i = 0; i < 200; i++) {
        int16_t u = (i / 20) % 2 ? -32768 : 32767;
        (void)exp_filter_step(&f, u);
        assert_true(exp_filter_frac(&f) >= -32768L * 65536 && exp_filter_frac(&f) <= 32767L * 65536);
    }
}

static void reset_returns_to_rest(void **state)
{
    exp_filter_t f;
    uint32_t g = 0;
    (void)state;
    assert_int_equal(exp_filter_gain_q31(10, &g), MS_OK);
    assert_int_equal(exp_filter_init(&f, g), MS_OK);
    (void)exp_filter_step(&f, 1000);
    assert_true(exp_filter_frac(&f) > 0);
    exp_filter_reset(&f);
    assert_int_equal(exp_filter_frac(&f), 0);
    assert_int_equal(exp_filter_step(&f, 1000), 0);
}

static void bad_parameters_are_rejected_and_change_nothing(void **state)
{
    exp_filter_t f, before;
    uint32_t g = 42;
    (void)state;
    memset(&f, 0x3C, sizeof f);
    before = f;
    assert_int_equal(exp_filter_gain_q31(0, &g), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(exp_filter_gain_q31(900, NULL), MS_ERR_NULL);
    assert_int_equal(g, 42);
    assert_int_equal(exp_filter_init(NULL, 1000), MS_ERR_NULL);
    assert_int_equal(exp_filter_init(&f, 0), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(exp_filter_init(&f, 0x80000000u), MS_ERR_OUT_OF_RANGE);
    assert_memory_equal(&f, &before, sizeof f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gain_is_the_rounded_exact_value),
        cmocka_unit_test(note_000_step_matches_the_closed_form_at_the_samples),
        cmocka_unit_test(settles_exactly_on_a_constant_input),
        cmocka_unit_test(stays_within_one_lsb_of_the_exact_recurrence),
        cmocka_unit_test(full_scale_swings_never_overshoot),
        cmocka_unit_test(reset_returns_to_rest),
        cmocka_unit_test(bad_parameters_are_rejected_and_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
