/* Unit tests: accdec_filter - the one interface motionsim and the sketch use for the three filter
 * kinds: names, validation (every bad parameter, nothing changed), the same outputs as the
 * modules themselves, and the integer rounding of the output to thousandths of a quantum. */
#include "cmocka_all.h"

#include <math.h>
#include <string.h>

#include "accdec_filter.h"
#include "filter_testutil.h"

static void kinds_have_names_and_only_those(void **state)
{
    accdec_kind_t k = ACCDEC_EXP;
    (void)state;
    assert_string_equal(accdec_kind_name(ACCDEC_MA), "ma");
    assert_string_equal(accdec_kind_name(ACCDEC_MA2), "ma2");
    assert_string_equal(accdec_kind_name(ACCDEC_EXP), "exp");
    assert_null(accdec_kind_name(ACCDEC_KIND_COUNT));
    assert_int_equal(accdec_kind_parse("ma2", &k), MS_OK);
    assert_int_equal(k, ACCDEC_MA2);
    assert_int_equal(accdec_kind_parse("ma", &k), MS_OK);
    assert_int_equal(k, ACCDEC_MA);
    assert_int_equal(accdec_kind_parse("exp", &k), MS_OK);
    assert_int_equal(k, ACCDEC_EXP);
    assert_int_equal(accdec_kind_parse("MA", &k), MS_ERR_FILTER_KIND);
    assert_int_equal(accdec_kind_parse("ma3", &k), MS_ERR_FILTER_KIND);
    assert_int_equal(accdec_kind_parse("m", &k), MS_ERR_FILTER_KIND);
    assert_int_equal(accdec_kind_parse("", &k), MS_ERR_FILTER_KIND);
    assert_int_equal(accdec_kind_parse("exp ", &k), MS_ERR_FILTER_KIND);
    assert_int_equal(accdec_kind_parse(NULL, &k), MS_ERR_NULL);
    assert_int_equal(k, ACCDEC_EXP);
}

/* The moving-average-filter note's parameters for each kind: tau = 9 s (tau2 = 3 s for ma2), Ts = 10 ms. */
static void note_000_configurations(void **state)
{
    accdec_config_t c;
    uint32_t g = 0;
    (void)state;
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 9.0, 3.0, 0.01, 2000), MS_OK);
    assert_int_equal(c.taps1, 900);
    assert_int_equal(accdec_buffer_taps(&c), 900);
    assert_int_equal(accdec_den(&c), 900);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 9.0, 3.0, 0.01, 2000), MS_OK);
    assert_int_equal(c.taps1, 900);
    assert_int_equal(c.taps2, 300);
    assert_int_equal(accdec_buffer_taps(&c), 1200);
    assert_int_equal(accdec_den(&c), 540000);
    assert_int_equal(accdec_configure(&c, ACCDEC_EXP, 9.0, NAN, 0.01, 0), MS_OK); /* tau2, buffer unused */
    assert_int_equal(exp_filter_gain_q31(900, &g), MS_OK);
    assert_int_equal(c.gain_q31, g);
    assert_int_equal(accdec_buffer_taps(&c), 0);
    assert_int_equal(accdec_den(&c), 65536);
}

static void every_bad_parameter_gets_its_status_and_changes_nothing(void **state)
{
    accdec_config_t c, before;
    (void)state;
    memset(&c, 0x77, sizeof c);
    before = c;
    assert_int_equal(accdec_configure(NULL, ACCDEC_MA, 9.0, 3.0, 0.01, 2000), MS_ERR_NULL);
    assert_int_equal(accdec_configure(&c, ACCDEC_KIND_COUNT, 9.0, 3.0, 0.01, 2000), MS_ERR_FILTER_KIND);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, NAN, 3.0, 0.01, 2000), MS_ERR_NOT_FINITE);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 9.0, 3.0, INFINITY, 2000), MS_ERR_NOT_FINITE);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 9.0, 3.0, 0.0, 2000), MS_ERR_TS_NOT_POSITIVE);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 0.005, 3.0, 0.01, 2000), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 9.005, 3.0, 0.01, 2000), MS_ERR_TAU_NOT_MULTIPLE);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 9.0, 3.0, 0.01, 899), MS_ERR_TOO_MANY_TAPS);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 9.0, 3.0, 0.01, 1199), MS_ERR_TOO_MANY_TAPS);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 9.0, 0.001, 0.01, 2000), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 9.0, 3.001, 0.01, 2000), MS_ERR_TAU_NOT_MULTIPLE);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 9.0, NAN, 0.01, 2000), MS_ERR_NOT_FINITE);
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 400.0, 400.0, 0.01, 65535), MS_ERR_TOO_MANY_TAPS);
    assert_int_equal(accdec_configure(&c, ACCDEC_EXP, 9.005, 3.0, 0.01, 0), MS_ERR_TAU_NOT_MULTIPLE);
    assert_int_equal(accdec_configure(&c, ACCDEC_EXP, 0.0, 3.0, 0.01, 0), MS_ERR_TAU_BELOW_TS);
    assert_memory_equal(&c, &before, sizeof c);
}

/* Through the interface each kind gives exactly what its module gives, and peek() is the value
 * the next step() returns. */
static void each_kind_matches_its_module(void **state)
{
    static int16_t buf_a[1200], buf_b[1200];
    accdec_config_t c;
    accdec_filter_t f;
    ma_filter_t ma;
    ma2_filter_t ma2;
    exp_filter_t ex;
    uint32_t k;
    (void)state;
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 0.5, 0.2, 0.01, 1200), MS_OK);
    assert_int_equal(accdec_start(&f, &c, buf_a, 1200), MS_OK);
    assert_int_equal(ma_filter_init(&ma, buf_b, 1200, 50), MS_OK);
    for (k = 0; k < 500; k++) {
        int16_t u = tu_sample(21, k);
        int64_t peek = accdec_peek(&f);
        assert_true(accdec_step(&f, u) == peek);
        assert_true(peek == ma_filter_step(&ma, u));
    }
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 0.5, 0.2, 0.01, 1200), MS_OK);
    assert_int_equal(accdec_start(&f, &c, buf_a, 1200), MS_OK);
    assert_int_equal(ma2_filter_init(&ma2, buf_b, 1200, 50, 20), MS_OK);
    for (k = 0; k < 500; k++) {
        int16_t u = tu_sample(22, k);
        int64_t peek = accdec_peek(&f);
        assert_true(accdec_step(&f, u) == peek);
        assert_true(peek == ma2_filter_step(&ma2, u));
    }
    assert_int_equal(accdec_configure(&c, ACCDEC_EXP, 0.5, 0.2, 0.01, 0), MS_OK);
    assert_int_equal(accdec_start(&f, &c, NULL, 0), MS_OK);
    assert_int_equal(exp_filter_init(&ex, c.gain_q31), MS_OK);
    for (k = 0; k < 500; k++) {
        int16_t u = tu_sample(23, k);
        int64_t peek = accdec_peek(&f);
        assert_true(accdec_step(&f, u) == peek);
        assert_true(peek == exp_filter_step(&ex, u));
    }
    accdec_reset(&f);
    assert_true(accdec_peek(&f) == 0);
}

static void start_checks_the_buffer(void **state)
{
    static int16_t buf[1200];
    accdec_config_t c;
    accdec_filter_t f;
    (void)state;
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 9.0, 3.0, 0.01, 1200), MS_OK);
    assert_int_equal(accdec_start(&f, &c, buf, 1199), MS_ERR_TOO_MANY_TAPS);
    assert_int_equal(accdec_start(&f, &c, NULL, 1200), MS_ERR_NULL);
    assert_int_equal(accdec_start(NULL, &c, buf, 1200), MS_ERR_NULL);
    assert_int_equal(accdec_start(&f, NULL, buf, 1200), MS_ERR_NULL);
    assert_int_equal(accdec_start(&f, &c, buf, 1200), MS_OK);
}

/* round(1000 num / den), halves away from zero, exact integers. */
static void milli_quanta_rounding(void **state)
{
    (void)state;
    assert_int_equal(accdec_milli_quanta(1, 3), 333);
    assert_int_equal(accdec_milli_quanta(2, 3), 667);
    assert_int_equal(accdec_milli_quanta(-2, 3), -667);
    assert_int_equal(accdec_milli_quanta(1, 2000), 1);   /* 0.5 -> 1 */
    assert_int_equal(accdec_milli_quanta(-1, 2000), -1); /* -0.5 -> -1 */
    assert_int_equal(accdec_milli_quanta(1, 2001), 0);
    assert_int_equal(accdec_milli_quanta(0, 7), 0);
    assert_int_equal(accdec_milli_quanta(5000LL * 900, 900), 5000000);
    assert_int_equal(accdec_milli_quanta(32767LL * 2147418112LL, 2147418112u), 32767000);
    assert_int_equal(accdec_milli_quanta(-32767LL * 2147418112LL, 2147418112u), -32767000);
}

/* The moving-average-filter note checkpoint through the interface, in the stream's units (uV with q = 1 mV): the moving
 * average is 2.5 V half-way (4.5 s) and 5 V at 9 s; the two-stage filter 2.5 V at 6 s, 5 V at 12 s. */
static void note_000_in_microvolts(void **state)
{
    static int16_t buf[1200];
    accdec_config_t c;
    accdec_filter_t f;
    uint32_t k;
    (void)state;
    assert_int_equal(accdec_configure(&c, ACCDEC_MA, 9.0, 3.0, 0.01, 1200), MS_OK);
    assert_int_equal(accdec_start(&f, &c, buf, 1200), MS_OK);
    for (k = 0; k <= 900; k++) {
        int32_t uv = accdec_milli_quanta(accdec_step(&f, 5000), accdec_den(&c));
        assert_int_equal(uv, (int32_t)((5000000LL * k * 2 + 900) / 1800)); /* round(5e6 k / 900) */
    }
    assert_int_equal(accdec_configure(&c, ACCDEC_MA2, 9.0, 3.0, 0.01, 1200), MS_OK);
    assert_int_equal(accdec_start(&f, &c, buf, 1200), MS_OK);
    for (k = 0; k <= 1200; k++) {
        int32_t uv = accdec_milli_quanta(accdec_step(&f, 5000), accdec_den(&c));
        if (k == 600)
            assert_int_equal(uv, 2500000);
        if (k == 1200)
            assert_int_equal(uv, 5000000);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(kinds_have_names_and_only_those),
        cmocka_unit_test(note_000_configurations),
        cmocka_unit_test(every_bad_parameter_gets_its_status_and_changes_nothing),
        cmocka_unit_test(each_kind_matches_its_module),
        cmocka_unit_test(start_checks_the_buffer),
        cmocka_unit_test(milli_quanta_rounding),
        cmocka_unit_test(note_000_in_microvolts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
