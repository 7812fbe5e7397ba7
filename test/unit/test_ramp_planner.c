/* Unit tests: what all ramps share (lib/src/ramp_common.h) and the planner (lib/src/ramp.h):
 * move geometry at the 32-bit extremes, the symmetric placement rule, rounding to whole ticks,
 * zero-length and one-step moves, phase order, and skipping a cruise. */
#include "cmocka_all.h"

#include <math.h>
#include <string.h>

#include "ramp.h"

static const ramp_params_t LAB = {1.0, 20.0, 10.0, 1000};

static void distances_directions_and_positions_at_the_extremes(void **state)
{
    (void)state;
    assert_int_equal(ramp_distance(0, 50), 50);
    assert_int_equal(ramp_distance(50, 0), 50);
    assert_int_equal(ramp_distance(-7, -7), 0);
    assert_int_equal(ramp_distance(INT32_MIN, INT32_MAX), 4294967295UL);
    assert_int_equal(ramp_distance(INT32_MAX, INT32_MIN), 4294967295UL);
    assert_int_equal(ramp_distance(-2147483647, 2147483647), 4294967294UL);
    assert_int_equal(ramp_direction(INT32_MIN, INT32_MAX), 1);
    assert_int_equal(ramp_direction(INT32_MAX, INT32_MIN), -1);
    assert_int_equal(ramp_direction(3, 3), 0);
    assert_int_equal(ramp_position_after(INT32_MIN, 1, 4294967295UL), INT32_MAX);
    assert_int_equal(ramp_position_after(INT32_MAX, -1, 4294967295UL), INT32_MIN);
    assert_int_equal(ramp_position_after(INT32_MIN, 1, 2147483648UL), 0);
    assert_int_equal(ramp_position_after(-5, 1, 10), 5);
    assert_int_equal(ramp_position_after(5, -1, 10), -5);
    assert_int_equal(ramp_position_after(9, 0, 0), 9);
}

/* c(n) = min(n, D + 1 - n, K) */
static void level_rule(void **state)
{
    (void)state;
    assert_int_equal(ramp_level(10, 3, 1), 1);
    assert_int_equal(ramp_level(10, 3, 3), 3);
    assert_int_equal(ramp_level(10, 3, 5), 3);
    assert_int_equal(ramp_level(10, 3, 9), 2);
    assert_int_equal(ramp_level(10, 3, 10), 1);
    assert_int_equal(ramp_level(10, 0, 4), 0);
    assert_int_equal(ramp_level(4294967295UL, 100, 1), 1);
    assert_int_equal(ramp_level(4294967295UL, 100, 4294967295UL), 1);
    assert_int_equal(ramp_level(4294967295UL, 4294967295UL, 2147483648UL), 2147483648UL);
    assert_int_equal(ramp_phase_label(10, 3, 3), RAMP_ACCEL);
    assert_int_equal(ramp_phase_label(10, 3, 4), RAMP_CRUISE);
    assert_int_equal(ramp_phase_label(10, 3, 7), RAMP_CRUISE);
    assert_int_equal(ramp_phase_label(10, 3, 8), RAMP_DECEL);
    assert_int_equal(ramp_phase_label(5, 9, 3), RAMP_CRUISE); /* capped at D/2: the middle step */
    assert_int_equal(ramp_phase_label(4, 9, 2), RAMP_ACCEL);
    assert_int_equal(ramp_phase_label(4, 9, 3), RAMP_DECEL);
}

/* The bit-pattern rounding against double arithmetic (floor(x + 0.5), exact for every float
 * below 2^32): every 97th float pattern from 0.25 to 2^32, and the neighbours of each half. */
static void whole_ticks_match_double_rounding(void **state)
{
    union {
        float f;
        uint32_t u;
    } v;
    uint32_t u;
    (void)state;
    for (u = 0x3E800000UL; u < 0x4F800000UL; u += 97U) {
        v.u = u;
        assert_int_equal(ramp_ticks_from_float(v.f), v.f < 0.5f ? 0U : (uint32_t)floor((double)v.f + 0.5));
    }
    for (u = 1; u < 200000U; u++) {
        float h = (float)u - 0.5f, lo = nextafterf(h, 0.0f), hi = nextafterf(h, 1e30f);
        assert_int_equal(ramp_ticks_from_float(h), u);
        assert_int_equal(ramp_ticks_from_float(lo), u - 1U);
        assert_int_equal(ramp_ticks_from_float(hi), u);
    }
}

/* Round half up, as a timer can count: checked against the integers and halves around them. */
static void whole_ticks_round_to_nearest(void **state)
{
    (void)state;
    assert_int_equal(ramp_ticks_from_float(0.5f), 1);
    assert_int_equal(ramp_ticks_from_float(1.0f), 1);
    assert_int_equal(ramp_ticks_from_float(1.4999999f), 1);
    assert_int_equal(ramp_ticks_from_float(1.5f), 2);
    assert_int_equal(ramp_ticks_from_float(218.21788f), 218);
    assert_int_equal(ramp_ticks_from_float(436435.78f), 436436);
    assert_int_equal(ramp_ticks_from_float(1023.99994f), 1024); /* just below a power of two */
    assert_int_equal(ramp_ticks_from_float(8388607.5f), 8388608);
    assert_int_equal(ramp_ticks_from_float(8388609.0f), 8388609);
    assert_int_equal(ramp_ticks_from_float(16777218.0f), 16777218);
    assert_int_equal(ramp_ticks_from_float(4294967040.0f), 4294967040UL); /* the largest float < 2^32 */
    assert_int_equal(ramp_ticks_from_float(0.0f), 0);
    assert_int_equal(ramp_ticks_from_float(-3.0f), 0);
    assert_int_equal(ramp_ticks_from_float(-0.0f), 0);
    assert_int_equal(ramp_ticks_from_float(4294967296.0f), UINT32_MAX); /* 2^32: no longer fits */
    assert_int_equal(ramp_ticks_from_float(INFINITY), UINT32_MAX);
    assert_int_equal(ramp_ticks_from_float(NAN), UINT32_MAX);
    {
        /* every k + 0.25 and k + 0.75 for k up to 2^22 */
        uint32_t k;
        for (k = 1; k < 4194304UL; k += 997) {
            assert_int_equal(ramp_ticks_from_float((float)k + 0.25f), k);
            assert_int_equal(ramp_ticks_from_float((float)k + 0.75f), k + 1);
        }
    }
}

/* Every algorithm: zero-length moves have no steps, one-step moves one, and every move hands out
 * exactly D steps ending on the target, with phases in the order accel, cruise, decel. */
static void every_algorithm_counts_steps_exactly(void **state)
{
    static uint16_t table[200];
    const ramp_sigmoid_params_t sp = {200, 2, 500.0f, 5000.0f, 5.0f, 2000000UL};
    const int32_t ends[][2] = {{0, 0}, {0, 1}, {0, -1}, {3, 5}, {-20, 30}, {30, -20}, {0, 2000}, {1000, -1001}};
    int algo;
    size_t e;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&sp, table, 200), MS_OK);
    for (algo = RAMP_ALGO_SIMPLISTIC; algo <= RAMP_ALGO_SIGMOID; algo++) {
        for (e = 0; e < sizeof ends / sizeof ends[0]; e++) {
            ramp_t r;
            ramp_step_t s;
            uint32_t count = 0;
            int order = RAMP_ACCEL;
            int32_t last = ends[e][0];
            if (algo == RAMP_ALGO_SIGMOID)
                assert_int_equal(ramp_plan_sigmoid(&r, &sp, table, 200, ends[e][0], ends[e][1]), MS_OK);
            else
                assert_int_equal(ramp_plan(&r, (ramp_algo_t)algo, &LAB, ends[e][0], ends[e][1]), MS_OK);
            while (ramp_next(&r, &s)) {
                count++;
                assert_int_equal(s.step, count);
                assert_int_equal(s.position - last, ends[e][1] > ends[e][0] ? 1 : -1);
                last = s.position;
                assert_true(s.whole_ticks >= 1);
                assert_true(s.interval_ticks > 0.0);
                assert_true((int)s.phase >= order);
                order = (int)s.phase;
            }
            assert_int_equal(count, ramp_distance(ends[e][0], ends[e][1]));
            assert_int_equal(last, ends[e][1]);
            assert_int_equal(ramp_next(&r, &s), 0); /* and stays finished */
            assert_int_equal(ramp_steps_left(&r), 0);
        }
    }
}

static void unknown_algorithm_and_null_are_rejected(void **state)
{
    ramp_t r, before;
    (void)state;
    memset(&r, 0x42, sizeof r);
    before = r;
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_SIGMOID, &LAB, 0, 10), MS_ERR_UNKNOWN_COMMAND);
    assert_int_equal(ramp_plan(&r, (ramp_algo_t)17, &LAB, 0, 10), MS_ERR_UNKNOWN_COMMAND);
    assert_int_equal(ramp_plan(&r, RAMP_ALGO_LEIB, NULL, 0, 10), MS_ERR_NULL);
    assert_int_equal(ramp_plan(NULL, RAMP_ALGO_LEIB, &LAB, 0, 10), MS_ERR_NULL);
    assert_memory_equal(&r, &before, sizeof r);
    assert_int_equal(ramp_params_check(NULL), MS_ERR_NULL);
}

/* ramp_plan_lab (the lab's ramps only, so that a firmware planning through it links no other):
 * the same steps as ramp_plan for simplistic and Leib; every other algorithm refused, r untouched */
static void the_lab_planner_plans_only_the_lab_ramps(void **state)
{
    static const ramp_algo_t lab[] = {RAMP_ALGO_SIMPLISTIC, RAMP_ALGO_LEIB};
    static const ramp_algo_t others[] = {RAMP_ALGO_EXACT, RAMP_ALGO_SIGMOID, RAMP_ALGO_SMOOTH, (ramp_algo_t)17};
    ramp_t a, b, before;
    ramp_step_t sa, sb;
    unsigned i, n;
    (void)state;
    for (i = 0; i < sizeof lab / sizeof lab[0]; i++) {
        assert_int_equal(ramp_plan(&a, lab[i], &LAB, -3, 40), MS_OK);
        assert_int_equal(ramp_plan_lab(&b, lab[i], &LAB, NULL, -3, 40), MS_OK);
        for (n = 0; ramp_next(&a, &sa); n++) {
            assert_true(ramp_next(&b, &sb));
            assert_int_equal(sa.whole_ticks, sb.whole_ticks);
            assert_true(sa.interval_ticks == sb.interval_ticks);
            assert_int_equal(sa.phase, sb.phase);
            assert_int_equal(sa.position, sb.position);
        }
        assert_int_equal(n, 43);
        assert_false(ramp_next(&b, &sb));
    }
    memset(&b, 0x42, sizeof b);
    before = b;
    for (i = 0; i < sizeof others / sizeof others[0]; i++)
        assert_int_equal(ramp_plan_lab(&b, others[i], &LAB, NULL, 0, 10), MS_ERR_UNKNOWN_COMMAND);
    assert_int_equal(ramp_plan_lab(&b, RAMP_ALGO_LEIB, NULL, NULL, 0, 10), MS_ERR_NULL);
    /* each lab ramp alone: the other refused */
    assert_int_equal(ramp_plan_leib(&b, RAMP_ALGO_SIMPLISTIC, &LAB, NULL, 0, 10), MS_ERR_UNKNOWN_COMMAND);
    assert_int_equal(ramp_plan_simplistic(&b, RAMP_ALGO_LEIB, &LAB, NULL, 0, 10), MS_ERR_UNKNOWN_COMMAND);
    assert_memory_equal(&b, &before, sizeof b);
    assert_int_equal(ramp_plan_leib(&a, RAMP_ALGO_LEIB, &LAB, NULL, 0, 10), MS_OK);
    assert_int_equal(ramp_plan_simplistic(&a, RAMP_ALGO_SIMPLISTIC, &LAB, NULL, 0, 10), MS_OK);
    assert_memory_equal(&b, &before, sizeof b);
}

/* The exact ramp is not continued (step_exact.h plans its continuations): NULL parameters get MS_ERR_NULL,
 * a set the exact ramp refuses its own status (as ramp_plan gives it), a valid one MS_ERR_UNKNOWN_COMMAND;
 * a ramp never planned (zeroed) has nothing to skip or take */
static void the_exact_ramp_is_not_continued(void **state)
{
    static const ramp_params_t EXACT = {10.0, 1000.0, 5000.0, 16000000U};
    static const ramp_params_t BAD = {10.0, 1000.0, 0.0, 16000000U};
    ramp_t m, n, bad;
    ramp_step_t st;
    (void)state;
    assert_int_equal(ramp_plan(&m, RAMP_ALGO_EXACT, &EXACT, 0, 1000), MS_OK);
    assert_true(ramp_next(&m, &st) && ramp_next(&m, &st));
    assert_int_equal(ramp_plan_continue(&n, &m, NULL, 2000), MS_ERR_NULL);
    assert_int_not_equal(ramp_plan(&bad, RAMP_ALGO_EXACT, &BAD, 0, 1000), MS_OK);
    assert_int_equal(ramp_plan_continue(&n, &m, &BAD, 2000), ramp_plan(&bad, RAMP_ALGO_EXACT, &BAD, 0, 1000));
    assert_int_equal(ramp_plan_continue(&n, &m, &EXACT, 2000), MS_ERR_UNKNOWN_COMMAND);
    memset(&n, 0, sizeof n);
    assert_int_equal(ramp_take_same(&n, 10), 0);
    assert_int_equal(ramp_cruise_skippable(&n), 0);
    assert_int_equal(ramp_skip_cruise(&n), 0);
    assert_false(ramp_next(&n, &st));
}

static void names(void **state)
{
    (void)state;
    assert_string_equal(ramp_algo_name(RAMP_ALGO_SIMPLISTIC), "simplistic");
    assert_string_equal(ramp_algo_name(RAMP_ALGO_LEIB), "leib");
    assert_string_equal(ramp_algo_name(RAMP_ALGO_EXACT), "exact");
    assert_string_equal(ramp_algo_name(RAMP_ALGO_SIGMOID), "sigmoid");
    assert_string_equal(ramp_phase_name(RAMP_IDLE), "idle");
    assert_string_equal(ramp_phase_name(RAMP_ACCEL), "accel");
    assert_string_equal(ramp_phase_name(RAMP_CRUISE), "cruise");
    assert_string_equal(ramp_phase_name(RAMP_DECEL), "decel");
    /* the sentences the sketches and motionsim print exist and differ */
    assert_string_not_equal(motion_status_text(MS_ERR_V0_ZERO_SIMPLISTIC), motion_status_text(MS_ERR_V0_NEGATIVE));
    assert_string_not_equal(motion_status_text(MS_ERR_DERIVED_PARAM), "unknown status");
}

/* Skipping the cruise changes nothing that follows: the remaining steps equal those of a full run. */
static void skipping_the_cruise_is_invisible(void **state)
{
    static uint16_t table[50];
    const ramp_sigmoid_params_t sp = {50, 3, 500.0f, 5000.0f, 5.0f, 2000000UL};
    const ramp_params_t p = {100.0, 1000.0, 1000.0, 2000000};
    int algo;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&sp, table, 50), MS_OK);
    for (algo = RAMP_ALGO_SIMPLISTIC; algo <= RAMP_ALGO_SIGMOID; algo++) {
        ramp_t full, skip;
        ramp_step_t a, b;
        uint32_t i, skipped;
        if (algo == RAMP_ALGO_SIGMOID) {
            assert_int_equal(ramp_plan_sigmoid(&full, &sp, table, 50, 0, 5000), MS_OK);
        } else {
            assert_int_equal(ramp_plan(&full, (ramp_algo_t)algo, &p, 0, 5000), MS_OK);
        }
        skip = full;
        assert_int_equal(ramp_skip_cruise(&skip), 0); /* not yet in cruise */
        for (i = 0; i < 700; i++) {
            assert_int_equal(ramp_next(&full, &a), 1);
            assert_int_equal(ramp_next(&skip, &b), 1);
        }
        skipped = ramp_skip_cruise(&skip);
        assert_true(skipped > 3000);
        for (i = 0; i < skipped; i++) {
            assert_int_equal(ramp_next(&full, &a), 1);
            assert_int_equal(a.phase, RAMP_CRUISE);
        }
        assert_int_equal(ramp_skip_cruise(&skip), 0); /* nothing left to skip */
        while (ramp_next(&full, &a)) {
            assert_int_equal(ramp_next(&skip, &b), 1);
            assert_int_equal(a.step, b.step);
            assert_int_equal(a.position, b.position);
            assert_true(a.interval_ticks == b.interval_ticks);
            assert_int_equal(a.phase, b.phase);
        }
        assert_int_equal(ramp_next(&skip, &b), 0);
    }
}

/* Skipping part of a cruise (ramp_skip_cruise_at_most, as motionsim ramp --compare does to keep
 * two ramps in step): ramp_cruise_skippable says how many steps the full skip would take, without
 * moving; a partial skip of m steps jumps exactly m, and every step after it equals a full run. */
static void skipping_part_of_the_cruise_is_invisible(void **state)
{
    static uint16_t table[50];
    const ramp_sigmoid_params_t sp = {50, 3, 500.0f, 5000.0f, 5.0f, 2000000UL};
    const ramp_params_t p = {100.0, 1000.0, 1000.0, 2000000};
    int algo;
    (void)state;
    assert_int_equal(ramp_sigmoid_fill(&sp, table, 50), MS_OK);
    for (algo = RAMP_ALGO_SIMPLISTIC; algo <= RAMP_ALGO_SIGMOID; algo++) {
        ramp_t full, skip, probe;
        ramp_step_t a, b;
        uint32_t i, can, cruise_left = 0;
        if (algo == RAMP_ALGO_SIGMOID)
            assert_int_equal(ramp_plan_sigmoid(&full, &sp, table, 50, 0, 5000), MS_OK);
        else
            assert_int_equal(ramp_plan(&full, (ramp_algo_t)algo, &p, 0, 5000), MS_OK);
        for (i = 0; i < 700; i++)
            assert_int_equal(ramp_next(&full, &a), 1);
        skip = full;
        probe = full;
        can = ramp_cruise_skippable(&skip);
        assert_memory_equal(&skip, &full, sizeof skip); /* asking moved nothing */
        assert_int_equal(ramp_skip_cruise(&probe), can);
        /* by stepping: the skippable steps are cruise steps with one interval, and they end at the
         * last cruise step or one before it (Leib's flat level lasts one step into its decel label) */
        probe = full;
        assert_int_equal(ramp_next(&probe, &b), 1);
        cruise_left = 1;
        for (i = 1; i < can; i++) {
            double iv = b.interval_ticks;
            assert_int_equal(b.phase, RAMP_CRUISE);
            assert_int_equal(ramp_next(&probe, &b), 1);
            assert_true(b.interval_ticks == iv);
            cruise_left++;
        }
        while (ramp_next(&probe, &b) && b.phase == RAMP_CRUISE)
            cruise_left++;
        assert_true(cruise_left == can || cruise_left == can + 1U);
        assert_true(can > 3000);
        assert_int_equal(ramp_skip_cruise_at_most(&skip, 1000), 1000);
        assert_int_equal(ramp_cruise_skippable(&skip), can - 1000U);
        assert_int_equal(ramp_skip_cruise_at_most(&skip, 0), 0);
        for (i = 0; i < 1000; i++) {
            assert_int_equal(ramp_next(&full, &a), 1);
            assert_int_equal(a.phase, RAMP_CRUISE);
        }
        while (ramp_next(&full, &a)) {
            assert_int_equal(ramp_next(&skip, &b), 1);
            assert_int_equal(a.step, b.step);
            assert_int_equal(a.position, b.position);
            assert_true(a.interval_ticks == b.interval_ticks);
            assert_int_equal(a.whole_ticks, b.whole_ticks);
            assert_int_equal(a.phase, b.phase);
        }
        assert_int_equal(ramp_next(&skip, &b), 0);
        assert_int_equal(ramp_skip_cruise_at_most(&skip, 5), 0); /* nothing left */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(distances_directions_and_positions_at_the_extremes),
        cmocka_unit_test(level_rule),
        cmocka_unit_test(whole_ticks_round_to_nearest),
        cmocka_unit_test(whole_ticks_match_double_rounding),
        cmocka_unit_test(every_algorithm_counts_steps_exactly),
        cmocka_unit_test(unknown_algorithm_and_null_are_rejected),
        cmocka_unit_test(the_lab_planner_plans_only_the_lab_ramps),
        cmocka_unit_test(the_exact_ramp_is_not_continued),
        cmocka_unit_test(names),
        cmocka_unit_test(skipping_the_cruise_is_invisible),
        cmocka_unit_test(skipping_part_of_the_cruise_is_invisible),
    };
    return cmocka_run_group_tests_name("ramp_planner", tests, NULL, NULL);
}
