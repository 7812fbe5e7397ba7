/* Unit tests: filter_param - N = tau/Ts as a whole number of taps (tolerant of binary floating
 * point, never silently rounding a real fraction) and the quantisation of volts into samples. */
#include "cmocka_all.h"

#include <math.h>

#include "filter_param.h"

/* The moving-average-filter note: tau = 9 s, Ts = 10 ms gives N = 900 taps, also from the Mega's float (9.0f/0.01f is
 * about 900.00002). Quotients that binary floating point does not give as whole numbers
 * (2.3/0.01 = 229.99999999999997, 0.07/0.01 = 7.000000000000001) are still whole numbers of taps. */
static void note_000_tau_9s_ts_10ms_is_900_taps(void **state)
{
    uint16_t n = 0;
    volatile double tau = 2.3, ts = 0.01;
    (void)state;
    assert_true(tau / ts != 230.0); /* the trap this module exists for */
    assert_int_equal(filt_taps(2.3, 0.01, &n), MS_OK);
    assert_int_equal(n, 230);
    assert_int_equal(filt_taps(0.07, 0.01, &n), MS_OK);
    assert_int_equal(n, 7);
    assert_int_equal(filt_taps(9.0, 0.01, &n), MS_OK);
    assert_int_equal(n, 900);
    assert_int_equal(filt_taps((double)9.0f, (double)0.01f, &n), MS_OK); /* the Mega's numbers */
    assert_int_equal(n, 900);
    assert_int_equal(filt_taps(3.0, 0.01, &n), MS_OK); /* the two-stage filter's tau2 */
    assert_int_equal(n, 300);
    assert_int_equal(filt_taps(0.01, 0.01, &n), MS_OK); /* tau = Ts: one tap */
    assert_int_equal(n, 1);
    assert_int_equal(filt_taps(655.35, 0.01, &n), MS_OK); /* the largest */
    assert_int_equal(n, 65535);
    assert_int_equal(filt_taps(0.7, 0.1, &n), MS_OK); /* 6.999999999999999 */
    assert_int_equal(n, 7);
}

/* Within 1 ppm of a whole number is that number; anything further is refused, not rounded. */
static void a_fraction_of_a_sample_is_refused(void **state)
{
    uint16_t n = 1234;
    (void)state;
    assert_int_equal(filt_taps(9.005, 0.01, &n), MS_ERR_TAU_NOT_MULTIPLE);  /* 900.5 */
    assert_int_equal(filt_taps(9.001, 0.01, &n), MS_ERR_TAU_NOT_MULTIPLE);  /* 900.1 */
    assert_int_equal(filt_taps(9.00001, 0.01, &n), MS_ERR_TAU_NOT_MULTIPLE); /* 1.1 ppm off */
    assert_int_equal(filt_taps(0.015, 0.01, &n), MS_ERR_TAU_NOT_MULTIPLE);  /* 1.5 */
    assert_int_equal(n, 1234);
    assert_int_equal(filt_taps(9.000001, 0.01, &n), MS_OK); /* 0.11 ppm off: 900 */
    assert_int_equal(n, 900);
}

/* Every bad parameter, in the documented order, and *taps untouched. */
static void bad_tap_parameters_get_their_status(void **state)
{
    uint16_t n = 77;
    (void)state;
    assert_int_equal(filt_taps(9.0, 0.01, NULL), MS_ERR_NULL);
    assert_int_equal(filt_taps(NAN, 0.01, &n), MS_ERR_NOT_FINITE);
    assert_int_equal(filt_taps(9.0, NAN, &n), MS_ERR_NOT_FINITE);
    assert_int_equal(filt_taps(INFINITY, 0.01, &n), MS_ERR_NOT_FINITE);
    assert_int_equal(filt_taps(9.0, -INFINITY, &n), MS_ERR_NOT_FINITE);
    assert_int_equal(filt_taps(9.0, 0.0, &n), MS_ERR_TS_NOT_POSITIVE);
    assert_int_equal(filt_taps(9.0, -0.01, &n), MS_ERR_TS_NOT_POSITIVE);
    assert_int_equal(filt_taps(0.0099, 0.01, &n), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(filt_taps(0.0, 0.01, &n), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(filt_taps(-9.0, 0.01, &n), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(filt_taps(655.36, 0.01, &n), MS_ERR_TOO_MANY_TAPS);
    assert_int_equal(filt_taps(9.0, 1e-310, &n), MS_ERR_TOO_MANY_TAPS); /* tau/Ts = inf */
    assert_int_equal(n, 77);
}

static void volts_are_rounded_to_the_nearest_quantum(void **state)
{
    int16_t c = 0;
    (void)state;
    assert_int_equal(filt_quantise(5.0, 0.001, &c), MS_OK);
    assert_int_equal(c, 5000);
    assert_int_equal(filt_quantise(2.5, 0.001, &c), MS_OK);
    assert_int_equal(c, 2500);
    assert_int_equal(filt_quantise(0.0014, 0.001, &c), MS_OK);
    assert_int_equal(c, 1);
    assert_int_equal(filt_quantise(0.0016, 0.001, &c), MS_OK);
    assert_int_equal(c, 2);
    assert_int_equal(filt_quantise(0.5, 1.0, &c), MS_OK); /* halves away from zero */
    assert_int_equal(c, 1);
    assert_int_equal(filt_quantise(-0.5, 1.0, &c), MS_OK);
    assert_int_equal(c, -1);
    assert_int_equal(filt_quantise(32.767, 0.001, &c), MS_OK);
    assert_int_equal(c, 32767);
    assert_int_equal(filt_quantise(-32.767, 0.001, &c), MS_OK);
    assert_int_equal(c, -32767);
    assert_int_equal(filt_quantise(5.0, 5.0 / 1023, &c), MS_OK); /* an ADC quantum */
    assert_int_equal(c, 1023);
}

static void bad_quantisation_gets_its_status_and_changes_nothing(void **state)
{
    int16_t c = 99;
    (void)state;
    assert_int_equal(filt_quantise(1.0, 0.001, NULL), MS_ERR_NULL);
    assert_int_equal(filt_quantise(NAN, 0.001, &c), MS_ERR_NOT_FINITE);
    assert_int_equal(filt_quantise(1.0, INFINITY, &c), MS_ERR_NOT_FINITE);
    assert_int_equal(filt_quantise(1.0, 0.0, &c), MS_ERR_QUANTUM_NOT_POSITIVE);
    assert_int_equal(filt_quantise(1.0, -0.001, &c), MS_ERR_QUANTUM_NOT_POSITIVE);
    assert_int_equal(filt_quantise(32.768, 0.001, &c), MS_ERR_INPUT_OUT_OF_RANGE);
    assert_int_equal(filt_quantise(32767.5, 1.0, &c), MS_ERR_INPUT_OUT_OF_RANGE); /* -> 32768 */
    assert_int_equal(filt_quantise(-32.768, 0.001, &c), MS_ERR_INPUT_OUT_OF_RANGE);
    assert_int_equal(filt_quantise(1e300, 1e-300, &c), MS_ERR_INPUT_OUT_OF_RANGE); /* ratio inf */
    assert_int_equal(filt_quantise_whole(2.0005, 0.001, &c), MS_ERR_NOT_WHOLE_QUANTUM);
    assert_int_equal(filt_quantise_whole(2.0001, 0.001, &c), MS_ERR_NOT_WHOLE_QUANTUM);
    assert_int_equal(c, 99);
}

/* Every 3-decimal voltage 0.000 .. 5.000 V is a whole number of millivolts, also when the decimal
 * was first rounded to the Mega's float (as the sketch's "u 4.999" is); the count is exact. */
static void every_millivolt_value_is_whole_also_from_float(void **state)
{
    int mv;
    (void)state;
    for (mv = 0; mv <= 5000; mv++) {
        int16_t a = -1, b = -1;
        double v = mv / 1000.0;
        assert_int_equal(filt_quantise_whole(v, 0.001, &a), MS_OK);
        assert_int_equal(a, mv);
        assert_int_equal(filt_quantise_whole((double)(float)v, (double)0.001f, &b), MS_OK);
        assert_int_equal(b, mv);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(note_000_tau_9s_ts_10ms_is_900_taps),
        cmocka_unit_test(a_fraction_of_a_sample_is_refused),
        cmocka_unit_test(bad_tap_parameters_get_their_status),
        cmocka_unit_test(volts_are_rounded_to_the_nearest_quantum),
        cmocka_unit_test(bad_quantisation_gets_its_status_and_changes_nothing),
        cmocka_unit_test(every_millivolt_value_is_whole_also_from_float),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
