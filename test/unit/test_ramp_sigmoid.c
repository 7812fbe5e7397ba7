/* Unit tests: the sigmoid S-curve table of the S-curve article (lib/src/ramp_sigmoid.h) and stepping through it.
 * Reference: the S-curve article's formula freq[i] = fmin + (fmax - fmin)/(1 + exp(-flex (i - len/2)/(len/2))),
 * period[i] = timer_hz/freq[i] truncated to 16 bits, evaluated here in double. */
#include "cmocka_all.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ramp.h"

/* the S-curve article's four curves: CalculateSModelLine(Freq, Period, len, fre_max, fre_min, flexible) with
 * (1000, 56000, 16000, 4), (1000, 64000, 500, 8), (1000, 64000, 500, 15), (1000, 40000, 500, 5) at
 * its 10 MHz timer; hold = 4 as its ISR loads a new period every 4th interrupt. */
static const ramp_sigmoid_params_t ARTICLE[4] = {
    {1000, 4, 16000.0f, 56000.0f, 4.0f, 10000000UL},
    {1000, 4, 500.0f, 64000.0f, 8.0f, 10000000UL},
    {1000, 4, 500.0f, 64000.0f, 15.0f, 10000000UL},
    {1000, 4, 500.0f, 40000.0f, 5.0f, 10000000UL},
};

static double ref_freq(const ramp_sigmoid_params_t *p, int i)
{
    double half = p->len / 2.0;
    return p->fmin_hz + (p->fmax_hz - p->fmin_hz) / (1.0 + exp(-p->flex * (i - half) / half));
}

/* Our exp (the same bits on the host and the AVR) against the C library's double exp: within
 * 2 ulp (2.4e-7 relative) wherever the result is a normal float; overflow and underflow ends. */
static void exp_is_accurate(void **state)
{
    float x;
    double worst = 0.0;
    (void)state;
    for (x = -87.0f; x <= 88.5f; x += 0.0013f) {
        double want = exp((double)x);
        double rel = fabs((double)ramp_sigmoid_exp(x) - want) / want;
        if (rel > worst)
            worst = rel;
    }
    assert_true(worst < 2.4e-7);
    assert_true(ramp_sigmoid_exp(0.0f) == 1.0f);
    assert_true(isinf(ramp_sigmoid_exp(89.0f)));
    assert_true(ramp_sigmoid_exp(-90.0f) == 0.0f);
    assert_true(fabs(ramp_sigmoid_exp(1.0f) - 2.718281828) < 3e-7);
}

static void table_follows_the_article_formula(void **state)
{
    size_t c;
    (void)state;
    for (c = 0; c < 4; c++) {
        uint16_t table[1000];
        int i;
        assert_int_equal(ramp_sigmoid_fill(&ARTICLE[c], table, 1000), MS_OK);
        for (i = 0; i < 1000; i++) {
            double f = ref_freq(&ARTICLE[c], i);
            double period = 1e7 / f;
            assert_true(fabs(ramp_sigmoid_freq_hz(&ARTICLE[c], (uint16_t)i) - f) <= 1e-6 * f);
            /* float arithmetic (a few ulp, < 1e-6 relative) may put a period that lies within a hair
             * of an integer on either side of it; everywhere else the truncation must agree */
            assert_true(fabs((double)table[i] - floor(period)) <= 1.0);
            if (fabs(period - floor(period + 0.5)) > 1e-6 * period)
                assert_int_equal(table[i], (uint16_t)floor(period));
            assert_true(table[i] >= 1);
            if (i > 0)
                assert_true(table[i] <= table[i - 1]); /* speeds up monotonically */
        }
    }
}

/* the S-curve article's worked example, (1000, 64000, 500, 8): "the last point is 10000000/64000 = 156"; the
 * first is below its "10000000/500 = 20000" because the curve starts at fmin + (fmax - fmin)/(1 + e^8). */
static void article_example_end_points(void **state)
{
    uint16_t table[1000];
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&ARTICLE[1], table, 1000), MS_OK);
    assert_int_equal(table[999], 156);
    assert_int_equal(table[0], (uint16_t)floor(1e7 / (500.0 + 63500.0 / (1.0 + exp(8.0)))));
    assert_true(table[0] < 20000);
}

/* "mind: 10000000/65535 = 152, so fre_min can't be less than 152" (the S-curve article): the bound is
 * timer_hz/65535 = 152.59 Hz, so 152 is refused and 153 accepted, with its period inside 16 bits. */
static void fmin_bound_of_the_article(void **state)
{
    ramp_sigmoid_params_t p = ARTICLE[1];
    uint16_t table[1000];
    (void)state;
    p.fmin_hz = 152.0f;
    assert_int_equal(ramp_sigmoid_check(&p), MS_ERR_FMIN_TOO_LOW);
    p.fmin_hz = 153.0f;
    assert_int_equal(ramp_sigmoid_fill(&p, table, 1000), MS_OK);
    assert_int_equal(table[0], (uint16_t)floor(1e7 / ref_freq(&p, 0)));
}

static void bad_parameters_are_rejected(void **state)
{
    struct {
        ramp_sigmoid_params_t p;
        motion_status_t want;
    } cases[] = {
        {{1, 4, 500.0f, 64000.0f, 8.0f, 10000000UL}, MS_ERR_LEN_TOO_SHORT},
        {{0, 4, 500.0f, 64000.0f, 8.0f, 10000000UL}, MS_ERR_LEN_TOO_SHORT},
        {{1000, 0, 500.0f, 64000.0f, 8.0f, 10000000UL}, MS_ERR_HOLD_ZERO},
        {{1000, 4, 500.0f, 64000.0f, 0.0f, 10000000UL}, MS_ERR_FLEX_NOT_POSITIVE},
        {{1000, 4, 500.0f, 64000.0f, -3.0f, 10000000UL}, MS_ERR_FLEX_NOT_POSITIVE},
        {{1000, 4, 500.0f, 64000.0f, 8.0f, 0UL}, MS_ERR_TICK_HZ_ZERO},
        {{1000, 4, 500.0f, 500.0f, 8.0f, 10000000UL}, MS_ERR_FMAX_NOT_ABOVE_FMIN},
        {{1000, 4, 64000.0f, 500.0f, 8.0f, 10000000UL}, MS_ERR_FMAX_NOT_ABOVE_FMIN},
        {{1000, 4, 100.0f, 64000.0f, 8.0f, 10000000UL}, MS_ERR_FMIN_TOO_LOW},
        {{1000, 4, -5.0f, 64000.0f, 8.0f, 10000000UL}, MS_ERR_FMIN_TOO_LOW},
        /* the fastest entries would need periods below one tick of a 10 MHz timer */
        {{1000, 4, 500.0f, 2.0e7f, 8.0f, 10000000UL}, MS_ERR_PERIOD_OUT_OF_RANGE},
        {{1000, 4, NAN, 64000.0f, 8.0f, 10000000UL}, MS_ERR_NOT_FINITE},
        {{1000, 4, 500.0f, INFINITY, 8.0f, 10000000UL}, MS_ERR_NOT_FINITE},
        {{1000, 4, 500.0f, 64000.0f, NAN, 10000000UL}, MS_ERR_NOT_FINITE},
    };
    size_t i;
    uint16_t table[1000], before[1000];
    ramp_t r, rb;
    (void)state;
    memset(table, 0xab, sizeof table);
    memcpy(before, table, sizeof table);
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        assert_int_equal(ramp_sigmoid_check(&cases[i].p), cases[i].want);
        assert_int_equal(ramp_sigmoid_fill(&cases[i].p, table, 1000), cases[i].want);
        assert_memory_equal(table, before, sizeof table);
    }
    /* a table too small for len, and a plan without a (long enough) table */
    assert_int_equal(ramp_sigmoid_fill(&ARTICLE[0], table, 999), MS_ERR_BUFFER_TOO_SMALL);
    assert_memory_equal(table, before, sizeof table);
    memset(&r, 0x11, sizeof r);
    rb = r;
    assert_int_equal(ramp_plan_sigmoid(&r, &ARTICLE[0], NULL, 1000, 0, 100), MS_ERR_TABLE_MISSING);
    assert_int_equal(ramp_plan_sigmoid(&r, &ARTICLE[0], table, 500, 0, 100), MS_ERR_TABLE_MISSING);
    assert_int_equal(ramp_plan_sigmoid(&r, &cases[0].p, table, 1000, 0, 100), MS_ERR_LEN_TOO_SHORT);
    assert_memory_equal(&r, &rb, sizeof r);
}

/* Stepping: step n uses entry min((k - 1)/hold, len - 1) with k = min(n, D + 1 - n): each entry
 * for `hold` steps, the top entry through the cruise, the table backwards to decelerate. */
static void steps_walk_the_table_and_back(void **state)
{
    const uint32_t lengths[] = {1, 2, 7, 8, 9, 3999, 4000, 8000, 8001, 12345};
    const uint16_t holds[] = {1, 4};
    size_t li, hi;
    uint16_t table[1000];
    (void)state;
    for (hi = 0; hi < 2; hi++) {
        ramp_sigmoid_params_t p = ARTICLE[1];
        p.hold = holds[hi];
        assert_int_equal(ramp_sigmoid_fill(&p, table, 1000), MS_OK);
        assert_int_equal(ramp_sigmoid_accel_steps(&p), 1000U * p.hold);
        for (li = 0; li < sizeof lengths / sizeof lengths[0]; li++) {
            ramp_t r;
            ramp_step_t s;
            uint32_t d = lengths[li], count = 0;
            assert_int_equal(ramp_plan_sigmoid(&r, &p, table, 1000, 5, 5 + (int32_t)d), MS_OK);
            while (ramp_next(&r, &s)) {
                uint32_t n = s.step, k = n < d + 1 - n ? n : d + 1 - n, e = (k - 1) / p.hold;
                count++;
                assert_int_equal(n, count);
                assert_int_equal(s.whole_ticks, table[e < 999 ? e : 999]);
                assert_true(s.interval_ticks == (double)s.whole_ticks);
                assert_int_equal(s.position, 5 + (int32_t)n);
            }
            assert_int_equal(count, d);
        }
    }
}

/* ramp_take_same (the planner's bulk step) hands out only steps that stepping one by one would
 * give the same whole ticks and phase, and leaves the ramp where those steps would: checked
 * against the formula above (k = min(n, D + 1 - n), entry (k - 1)/hold) for every step. */
static void bulk_steps_equal_single_steps(void **state)
{
    const uint32_t lengths[] = {1, 2, 3, 9, 10, 41, 3999, 8000, 8001, 12345};
    const uint16_t holds[] = {1, 4, 7};
    const uint32_t caps[] = {1, 3, 65534};
    size_t li, hi, ci;
    uint16_t table[1000];
    (void)state;
    for (hi = 0; hi < 3; hi++) {
        ramp_sigmoid_params_t p = ARTICLE[1];
        p.hold = holds[hi];
        assert_int_equal(ramp_sigmoid_fill(&p, table, 1000), MS_OK);
        for (li = 0; li < sizeof lengths / sizeof lengths[0]; li++) {
            for (ci = 0; ci < 3; ci++) {
                ramp_t r, single;
                uint32_t d = lengths[li], w, n = 0, bulk = 0;
                ramp_phase_t ph;
                assert_int_equal(ramp_plan_sigmoid(&r, &p, table, 1000, 0, (int32_t)d), MS_OK);
                while (ramp_next_ticks(&r, &w, &ph)) {
                    uint32_t j, more;
                    n++;
                    single = r;
                    more = ramp_take_same(&r, caps[ci]);
                    assert_true(more <= caps[ci]);
                    bulk += more;
                    for (j = 0; j < more; j++) {
                        uint32_t w2, k, e;
                        ramp_phase_t ph2;
                        assert_int_equal(ramp_next_ticks(&single, &w2, &ph2), 1);
                        n++;
                        k = n < d + 1 - n ? n : d + 1 - n;
                        e = (k - 1) / p.hold;
                        assert_int_equal(w2, w);
                        assert_int_equal(w2, table[e < 999 ? e : 999]);
                        assert_int_equal(ph2, ph);
                    }
                    assert_int_equal(r.steps_done, single.steps_done);
                    assert_int_equal(r.level, single.level);
                    assert_int_equal(r.u.sigmoid.k, single.u.sigmoid.k);
                    assert_int_equal(r.u.sigmoid.entry, single.u.sigmoid.entry);
                    assert_int_equal(r.u.sigmoid.phase, single.u.sigmoid.phase);
                }
                assert_int_equal(n, d);
                if (p.hold > 1 && d >= 40 && caps[ci] > 1)
                    assert_true(bulk > d / 4); /* it does take steps in bulk */
            }
        }
    }
}

/* The acceleration's duration is hold * sum(period)/timer_hz; the S-curve article's hold of 4 takes four
 * times as long as a hold of 1 and covers 4 * len steps (its "1.8 deg * 1000 steps / 4" per len). */
static void acceleration_time_and_distance(void **state)
{
    uint16_t table[1000];
    ramp_sigmoid_params_t p = ARTICLE[1];
    uint32_t i, sum = 0;
    double t4, t1;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&p, table, 1000), MS_OK);
    for (i = 0; i < 1000; i++)
        sum += table[i];
    t4 = ramp_sigmoid_accel_time_s(&p, table);
    assert_true(fabs(t4 - 4.0 * sum / 1e7) < 1e-12);
    p.hold = 1;
    t1 = ramp_sigmoid_accel_time_s(&p, table);
    assert_true(fabs(t4 - 4.0 * t1) < 1e-12);
    assert_int_equal(ramp_sigmoid_accel_steps(&p), 1000);
    /* the time of the first ramp of a long move is exactly this sum */
    {
        ramp_t r;
        ramp_step_t s;
        double t = 0.0;
        assert_int_equal(ramp_plan_sigmoid(&r, &p, table, 1000, 0, 5000), MS_OK);
        for (i = 0; i < 1000; i++) {
            assert_int_equal(ramp_next(&r, &s), 1);
            assert_int_equal(s.phase, RAMP_ACCEL);
            t += s.interval_ticks / 1e7;
        }
        assert_true(fabs(t - t1) < 1e-12);
        assert_int_equal(ramp_next(&r, &s), 1);
        assert_int_equal(s.phase, RAMP_CRUISE);
    }
}

/* INT32_MAX -> INT32_MIN: 2^32 - 1 steps backwards; the cruise is skipped, the deceleration walks
 * the table back down to entry 0 and ends exactly on the target. */
static void extreme_distance(void **state)
{
    uint16_t table[1000];
    ramp_t r;
    ramp_step_t s;
    uint32_t i;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&ARTICLE[2], table, 1000), MS_OK);
    assert_int_equal(ramp_plan_sigmoid(&r, &ARTICLE[2], table, 1000, INT32_MAX, INT32_MIN), MS_OK);
    assert_int_equal(r.steps_total, 4294967295UL);
    for (i = 0; i < 4100; i++)
        assert_int_equal(ramp_next(&r, &s), 1);
    assert_int_equal(s.whole_ticks, table[999]);
    assert_int_equal(s.position, INT32_MAX - 4100);
    assert_true(ramp_skip_cruise(&r) > 4294900000UL);
    assert_int_equal(ramp_steps_left(&r), 4001); /* the last cruise step and 1000 * 4 decelerating */
    i = 0;
    while (ramp_next(&r, &s)) {
        uint32_t k = 4294967295UL - s.step + 1, e = (k - 1) / 4;
        assert_int_equal(s.whole_ticks, table[e < 999 ? e : 999]);
        i++;
    }
    assert_int_equal(i, 4001);
    assert_int_equal(s.position, INT32_MIN);
    assert_int_equal(s.whole_ticks, table[0]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(exp_is_accurate),
        cmocka_unit_test(table_follows_the_article_formula),
        cmocka_unit_test(article_example_end_points),
        cmocka_unit_test(fmin_bound_of_the_article),
        cmocka_unit_test(bad_parameters_are_rejected),
        cmocka_unit_test(steps_walk_the_table_and_back),
        cmocka_unit_test(bulk_steps_equal_single_steps),
        cmocka_unit_test(acceleration_time_and_distance),
        cmocka_unit_test(extreme_distance),
    };
    return cmocka_run_group_tests_name("ramp_sigmoid", tests, NULL, NULL);
}
