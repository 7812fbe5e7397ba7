/* Unit tests: MotionPID, the PID_v1-compatible C++ class the sketches use (the lab handout section 4.2:
 * "myPID.SetOutputLimits(...); myPID.SetSampleTime(...); myPID.SetMode(AUTOMATIC)"), replayed
 * through its PID_v1-style methods over the recorded PID_v1 1.2.1 vectors in test/data/pid_v1/
 * (host double): Output and Compute()'s return value for every row, plus the getters. The clock
 * comes from motion_clock_ms(), defined here; SetClock() is checked separately.
 */
/* cmocka 1.1's header has no extern "C" guard of its own */
extern "C" {
#include "cmocka_all.h"
}

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../sim/csv_read.c"
#include "../../sim/pid_vector.c"
#include "MotionPID.h"

static uint32_t g_now_ms;

extern "C" uint32_t motion_clock_ms(void)
{
    return g_now_ms;
}

static const char *data_dir(void)
{
    const char *d = getenv("PID_V1_DATA");
    return d != NULL ? d : "test/data/pid_v1";
}

static void apply(MotionPID &pid, double &out, const pv_cmd_t &c)
{
    switch (c.op) {
    case PV_OUTPUT_SET: out = c.x[0].d; break;
    case PV_SET_MODE: pid.SetMode(c.n); break;
    case PV_SET_TUNINGS: pid.SetTunings(c.x[0].d, c.x[1].d, c.x[2].d); break;
    case PV_SET_TUNINGS_PON: pid.SetTunings(c.x[0].d, c.x[1].d, c.x[2].d, c.n); break;
    case PV_SET_SAMPLE_TIME: pid.SetSampleTime(c.n); break;
    case PV_SET_OUTPUT_LIMITS: pid.SetOutputLimits(c.x[0].d, c.x[1].d); break;
    case PV_SET_DIRECTION: pid.SetControllerDirection(c.n); break;
    }
}

static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static void replay(void **state)
{
    const char *name = static_cast<const char *>(*state);
    char path[600], err[512];
    static pv_vector_t v;
    size_t r, k, bad = 0;
    snprintf(path, sizeof path, "%s/%s.csv", data_dir(), name);
    if (pv_load(&v, path, err, sizeof err) != 0)
        fail_msg("%s", err);
    double Input = v.input0.d, Output = v.output0.d, Setpoint = v.setpoint0.d;
    g_now_ms = v.t0_ms;
    /* the 7-argument constructor is P_ON_E; the 8-argument one takes POn */
    MotionPID pid(&Input, &Output, &Setpoint, v.kp.d, v.ki.d, v.kd.d, v.pon, v.direction);
    for (k = 0; k < v.n_setup; k++)
        apply(pid, Output, v.setup[k]);
    for (r = 0; r < v.n_rows; r++) {
        const pv_row_t &row = v.rows[r];
        g_now_ms = row.t_ms;
        Input = row.input.d;
        Setpoint = row.setpoint.d;
        for (k = 0; k < row.n_cmds; k++)
            apply(pid, Output, row.cmds[k]);
        bool computed = pid.Compute();
        double want_out = strtod(pv_cell(&v, r, "output"), NULL);
        int want_computed = atoi(pv_cell(&v, r, "computed"));
        if (computed != (want_computed == 1) || !same_bits(Output, want_out) ||
            !same_bits(pid.GetKp(), strtod(pv_cell(&v, r, "disp_kp"), NULL)) ||
            !same_bits(pid.GetKi(), strtod(pv_cell(&v, r, "disp_ki"), NULL)) ||
            !same_bits(pid.GetKd(), strtod(pv_cell(&v, r, "disp_kd"), NULL)) ||
            pid.GetMode() != atoi(pv_cell(&v, r, "mode")) || pid.GetDirection() != atoi(pv_cell(&v, r, "direction"))) {
            if (bad == 0)
                print_error("%s row %zu (t_ms=%lu): output %.17g (want %s), computed %d (want %d)\n", name, r + 2,
                            (unsigned long)row.t_ms, Output, pv_cell(&v, r, "output"), (int)computed, want_computed);
            bad++;
        }
    }
    print_message("# MotionPID %s: %zu rows, %zu mismatches\n", name, v.n_rows, bad);
    pv_free(&v);
    assert_int_equal(bad, 0);
}

/* The 7-argument constructor is P_ON_E, and the constants equal PID_v1's. */
static void constants_and_constructors(void **state)
{
    (void)state;
    assert_int_equal(AUTOMATIC, 1);
    assert_int_equal(MANUAL, 0);
    assert_int_equal(DIRECT, 0);
    assert_int_equal(REVERSE, 1);
    assert_int_equal(P_ON_E, 1);
    assert_int_equal(P_ON_M, 0);
    double in = 0, out = 0, sp = 0;
    g_now_ms = 1000;
    MotionPID a(&in, &out, &sp, 1, 2, 3, DIRECT);
    assert_int_equal(a.State().p_on_e, 1);
    assert_int_equal(a.State().last_time_ms, 900); /* now - 100 ms default sample time */
    assert_int_equal(a.GetMode(), MANUAL);
    MotionPID b(&in, &out, &sp, 1, 2, 3, P_ON_M, REVERSE);
    assert_int_equal(b.State().p_on_e, 0);
    assert_true(b.State().kp == -1.0 && b.GetKp() == 1.0);
}

/* PID_v1 parity of the declarations: its getters are not const, so member pointers of PID_v1's
 * types must bind; LIBRARY_VERSION as PID_v1.h defines it; `typedef MotionPID PID;` is the one
 * line that lets PID_v1 code compile unchanged. */
typedef MotionPID PID;
static void pid_v1_declarations(void **state)
{
    (void)state;
    double (PID::*kp)() = &PID::GetKp;
    double (PID::*ki)() = &PID::GetKi;
    double (PID::*kd)() = &PID::GetKd;
    int (PID::*mode)() = &PID::GetMode;
    int (PID::*dir)() = &PID::GetDirection;
    double in = 0, out = 0, sp = 0;
    PID pid(&in, &out, &sp, 1, 2, 3, P_ON_E, REVERSE);
    assert_true((pid.*kp)() == 1 && (pid.*ki)() == 2 && (pid.*kd)() == 3);
    assert_int_equal((pid.*mode)(), MANUAL);
    assert_int_equal((pid.*dir)(), REVERSE);
#define STR2(x) #x
#define STR(x) STR2(x)
    assert_string_equal(STR(LIBRARY_VERSION), "1.2.1");
}

/* Constructor with a negative gain, then SetTunings(Kp, Ki, Kd): computes as P_ON_M (PID_v1 leaves
 * pOn at the 0 of a global object; see test_pidv1_ctrl.c). */
static void negative_constructor_gain_then_set_tunings(void **state)
{
    (void)state;
    double in_a = 30, out_a = 0, sp_a = 60, in_b = 30, out_b = 0, sp_b = 60;
    g_now_ms = 0;
    MotionPID a(&in_a, &out_a, &sp_a, 0.5, -1, 0.05, DIRECT);
    MotionPID b(&in_b, &out_b, &sp_b, 0.5, 1, 0.05, P_ON_M, DIRECT);
    a.SetTunings(0.5, 1, 0.05);
    a.SetMode(AUTOMATIC);
    b.SetMode(AUTOMATIC);
    for (int k = 1; k <= 10; k++) {
        g_now_ms = 100u * (uint32_t)k;
        in_a = in_b = 30 + 3 * k;
        assert_int_equal(a.Compute(), b.Compute());
        assert_memory_equal(&out_a, &out_b, sizeof out_a);
    }
}

static uint32_t g_other_ms;
static uint32_t other_clock(void)
{
    return g_other_ms;
}

/* SetClock: Compute() reads the given clock instead of motion_clock_ms(). */
static void set_clock_replaces_the_default(void **state)
{
    (void)state;
    double in = 0, out = 0, sp = 100;
    g_now_ms = 0;
    MotionPID pid(&in, &out, &sp, 1, 0, 0, DIRECT);
    pid.SetOutputLimits(-100, 100);
    pid.SetSampleTime(20);
    pid.SetMode(AUTOMATIC);
    pid.SetClock(other_clock);
    g_other_ms = 0;
    assert_true(pid.Compute());
    g_now_ms = 5000; /* the default clock is no longer read */
    g_other_ms = 19;
    assert_false(pid.Compute());
    g_other_ms = 20;
    assert_true(pid.Compute());
    pid.SetClock(NULL);
    g_now_ms = 39;
    assert_false(pid.Compute()); /* back on motion_clock_ms(): 39 - 20 < 20 */
    g_now_ms = 40;
    assert_true(pid.Compute());
}

/* ---- the held-back vectors' behaviours (test/data/pid_v1/README.md),
 * through the class: the same situations as test_pidv1_ctrl.c, expectations worked out by hand
 * from the README (Kp 2, Ki 5, Kd 1 at 20 ms: |kp| 2, |ki| 0.1, |kd| 50). ---- */
static void near(double got, double want)
{
    if (fabs(got - want) >= 1e-9)
        fail_msg("got %.17g, want %.17g", got, want);
}

/* "In MANUAL the gains are not negated (i) ... The reverse sign only takes effect when
 * SetTunings is called." */
static void direction_in_manual_waits_for_set_tunings(void **state)
{
    (void)state;
    double in = 60, out = 0, sp = 50;
    g_now_ms = 0;
    MotionPID pid(&in, &out, &sp, 2, 5, 1, DIRECT);
    pid.SetOutputLimits(0, 100);
    pid.SetSampleTime(20);
    pid.SetControllerDirection(REVERSE); /* MANUAL */
    assert_int_equal(pid.GetDirection(), REVERSE);
    near(pid.State().kp, 2);
    out = 50;
    pid.SetMode(AUTOMATIC);
    assert_true(pid.Compute());
    near(out, 29); /* still direct-acting: 2 x (-10) + (50 + 0.1 x (-10)) */
    pid.SetTunings(2, 5, 1);
    near(pid.State().kp, -2);
    near(pid.State().ki, -0.1);
    near(pid.State().kd, -50);
    g_now_ms = 20;
    assert_true(pid.Compute());
    near(out, 70); /* now reverse-acting: (-2)(-10) + (49 + (-0.1)(-10)) */
}

/* d_reverse: REVERSE, limits 0..100, direction switched to DIRECT and back while AUTOMATIC;
 * "it negates kp, ki and kd ... outputSum is not negated." */
static void reverse_and_direction_changes_in_automatic(void **state)
{
    (void)state;
    double in = 60, out = 50, sp = 50;
    g_now_ms = 0;
    MotionPID pid(&in, &out, &sp, 2, 5, 1, P_ON_E, REVERSE);
    pid.SetOutputLimits(0, 100);
    pid.SetSampleTime(20);
    pid.SetMode(AUTOMATIC);
    assert_true(pid.Compute());
    near(out, 71); /* (-2)(-10) + (50 + (-0.1)(-10)) */
    pid.SetControllerDirection(DIRECT);
    near(pid.State().kp, 2);
    near(pid.State().ki, 0.1);
    near(pid.State().kd, 50);
    near(pid.State().output_sum, 51);
    pid.SetControllerDirection(DIRECT); /* unchanged direction: no flip */
    near(pid.State().kp, 2);
    in = 62;
    g_now_ms = 20;
    assert_true(pid.Compute());
    near(out, 0); /* 2 x (-12) + ((51 - 1.2) - 50 x 2) = -74.2, clamped to 0 */
    pid.SetControllerDirection(REVERSE);
    in = 61;
    g_now_ms = 40;
    assert_true(pid.Compute());
    near(out, 22.9); /* (-2)(-11) + ((49.8 + 1.1) - (-50)(-1)) */
    assert_int_equal(pid.GetDirection(), REVERSE);
    near(pid.GetKp(), 2);
}

/* "If AUTOMATIC, it immediately clamps both the Output variable and outputSum (f at 2500) ...
 * In MANUAL nothing is clamped (e at 3200)." */
static void set_output_limits_clamps_at_once_only_in_automatic(void **state)
{
    (void)state;
    double in = 0, out = 54, sp = 6;
    g_now_ms = 0;
    MotionPID pid(&in, &out, &sp, 1, 0, 0, DIRECT);
    pid.SetOutputLimits(-100, 100);
    pid.SetSampleTime(20);
    pid.SetMode(AUTOMATIC);
    assert_true(pid.Compute());
    near(out, 60);
    pid.SetOutputLimits(0, 50);
    near(out, 50);
    near(pid.State().output_sum, 50);
    pid.SetMode(MANUAL);
    out = 10;
    pid.SetOutputLimits(20, 40);
    near(out, 10);
    near(pid.State().output_sum, 50);
}

int main(void)
{
    static const char *const names[] = {"a_p_only", "b_pid_windup", "e_manual_auto", "g_irregular_calls", "h_invalid_args"};
    struct CMUnitTest tests[16];
    size_t n = 0, i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        tests[n].name = names[i];
        tests[n].test_func = replay;
        tests[n].setup_func = NULL;
        tests[n].teardown_func = NULL;
        tests[n].initial_state = const_cast<char *>(names[i]);
        n++;
    }
    const struct CMUnitTest fixed[] = {
        cmocka_unit_test(constants_and_constructors),
        cmocka_unit_test(pid_v1_declarations),
        cmocka_unit_test(negative_constructor_gain_then_set_tunings),
        cmocka_unit_test(set_clock_replaces_the_default),
        cmocka_unit_test(direction_in_manual_waits_for_set_tunings),
        cmocka_unit_test(reverse_and_direction_changes_in_automatic),
        cmocka_unit_test(set_output_limits_clamps_at_once_only_in_automatic),
    };
    for (i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        tests[n++] = fixed[i];
    return _cmocka_run_group_tests("MotionPID", tests, n, NULL, NULL);
}
