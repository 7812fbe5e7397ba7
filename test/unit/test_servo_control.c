/* Unit tests: the proportional controller (the lab handout section 4.1: "percentDutyCycle = Kp x error",
 * Kp = 0.02, duty -100..+100 %), the duty -> 8-bit PWM helper, and closed loops of each
 * controller around the DC-motor plant that must settle (the lab handout sections 4.1-4.2).
 */
#include "cmocka_all.h"

#include <math.h>
#include <string.h>

#include "duty_pwm.h"
#include "pctrl.h"
#include "pidv1_ctrl.h"
#include "plant_dcmotor.h"

/* ---- pctrl ---- */

/* the lab handout section 4.1: Kp = 0.02 and error = setpoint - measured; 1000 counts -> 20 %. */
static void p_duty_is_kp_times_error(void **state)
{
    pctrl_t c;
    (void)state;
    assert_int_equal(pctrl_init(&c, 0.02f), MS_OK);
    assert_true(pctrl_duty_pct(&c, 1000, 0) == 0.02f * 1000.0f);
    assert_true(fabsf(pctrl_duty_pct(&c, 1000, 0) - 20.0f) < 1e-5f);
    assert_true(fabsf(pctrl_duty_pct(&c, 0, 1000) + 20.0f) < 1e-5f); /* sign: setpoint - measured */
    assert_true(fabsf(pctrl_duty_pct(&c, 1500, 1250) - 5.0f) < 1e-5f);
    assert_true(pctrl_duty_pct(&c, 77, 77) == 0.0f);
}

static void p_duty_is_clamped_to_100_percent(void **state)
{
    pctrl_t c;
    (void)state;
    assert_int_equal(pctrl_init(&c, 0.02f), MS_OK);
    assert_true(pctrl_duty_pct(&c, 5000, 0) == 100.0f);      /* 0.02 x 5000 = 100 exactly at the limit */
    assert_true(pctrl_duty_pct(&c, 5001, 0) == 100.0f);
    assert_true(pctrl_duty_pct(&c, 1000000, -1000000) == 100.0f);
    assert_true(pctrl_duty_pct(&c, -1000000, 1000000) == -100.0f);
    assert_true(pctrl_duty_pct(&c, -4999, 1) == -100.0f);
    assert_true(pctrl_duty_pct(&c, 4999, 0) < 100.0f);
}

/* The LS7366R's 32-bit count wraps; the error is the wrapped difference, so a setpoint a few
 * counts past the wrap is a small positive error, not -4 billion. */
static void p_error_wraps_like_the_counter(void **state)
{
    pctrl_t c;
    (void)state;
    assert_int_equal(pctrl_error_counts(INT32_MIN + 3, INT32_MAX - 2), 6);
    assert_int_equal(pctrl_error_counts(INT32_MAX - 2, INT32_MIN + 3), -6);
    assert_int_equal(pctrl_error_counts(10, -10), 20);
    assert_int_equal(pctrl_init(&c, 1.0f), MS_OK);
    assert_true(pctrl_duty_pct(&c, INT32_MIN + 3, INT32_MAX - 2) == 6.0f);
}

/* ProportionalClosedLoop calls pctrl_kp_duty_pct(Kp, ...) with its own Kp; motionsim calls
 * pctrl_duty_pct(&c, ...): the same number for every gain and error. */
static void p_duty_with_the_gain_given_is_the_controllers(void **state)
{
    static const float gains[] = {0.0f, 0.02f, 0.3f, 1.0f, 1000.0f};
    static const int32_t errs[][2] = {{1000, 0}, {0, 1000}, {202, 0}, {5001, 0}, {INT32_MIN + 3, INT32_MAX - 2}};
    pctrl_t c;
    size_t i, j;
    (void)state;
    for (i = 0; i < sizeof gains / sizeof gains[0]; i++) {
        assert_int_equal(pctrl_init(&c, gains[i]), MS_OK);
        for (j = 0; j < sizeof errs / sizeof errs[0]; j++)
            assert_true(pctrl_kp_duty_pct(gains[i], errs[j][0], errs[j][1]) ==
                        pctrl_duty_pct(&c, errs[j][0], errs[j][1]));
    }
    assert_true(pctrl_kp_duty_pct(0.02f, 1000, 0) == 0.02f * 1000.0f);
    assert_true(pctrl_kp_duty_pct(0.02f, -5001, 0) == -100.0f);
}

static void p_rejects_negative_and_non_finite_gain(void **state)
{
    pctrl_t c;
    (void)state;
    assert_int_equal(pctrl_init(&c, 0.05f), MS_OK);
    assert_int_equal(pctrl_set_kp(&c, -0.01f), MS_ERR_GAIN_NEGATIVE);
    assert_true(c.kp_pct_per_count == 0.05f);
    assert_int_equal(pctrl_set_kp(&c, NAN), MS_ERR_NOT_FINITE);
    assert_int_equal(pctrl_set_kp(&c, INFINITY), MS_ERR_NOT_FINITE);
    assert_true(c.kp_pct_per_count == 0.05f);
    assert_int_equal(pctrl_set_kp(&c, 0.0f), MS_OK); /* zero is allowed (motor off) */
    assert_int_equal(pctrl_init(&c, -1.0f), MS_ERR_GAIN_NEGATIVE);
    assert_true(c.kp_pct_per_count == 0.0f);
    assert_int_equal(pctrl_init(NULL, 1.0f), MS_ERR_NULL);
}

/* ---- duty_pwm: pwm = round(|duty| x 255 / 100), forward = duty >= 0 ---- */
static void pwm_rounds_duty_to_8_bits(void **state)
{
    static const struct {
        float duty;
        uint8_t pwm, forward;
    } cases[] = {
        {0.0f, 0, 1},     {-0.0f, 0, 1},    {100.0f, 255, 1}, {-100.0f, 255, 0}, {150.0f, 255, 1},
        {-150.0f, 255, 0}, {50.0f, 128, 1}, /* 127.5 rounds up */
        {20.0f, 51, 1},   {-20.0f, 51, 0},  {0.19f, 0, 1},    /* 0.4845 */
        {0.2f, 1, 1},     /* 0.51 */        {4.06f, 10, 1},   /* 10.353 */
        {-4.0f, 10, 0},   /* 10.2 */        {99.9f, 255, 1},  /* 254.745 */
        {99.7f, 254, 1},  /* 254.235 */
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        duty_pwm_t p = duty_pwm_from_pct(cases[i].duty);
        if (p.pwm != cases[i].pwm || p.forward != cases[i].forward)
            fail_msg("duty %g: pwm %u forward %u, want %u %u", (double)cases[i].duty, p.pwm, p.forward, cases[i].pwm,
                     cases[i].forward);
    }
    assert_int_equal(duty_pwm_from_pct(NAN).pwm, 0);
}

static void pwm_applied_duty_is_pwm_over_255(void **state)
{
    duty_pwm_t p;
    (void)state;
    p.pwm = 51;
    p.forward = 1;
    assert_true(fabsf(duty_pwm_applied_pct(p) - 20.0f) < 1e-5f);
    p.forward = 0;
    assert_true(fabsf(duty_pwm_applied_pct(p) + 20.0f) < 1e-5f);
    p.pwm = 255;
    assert_true(duty_pwm_applied_pct(p) == -100.0f);
    p.pwm = 0;
    assert_true(duty_pwm_applied_pct(p) == 0.0f);
}

/* ---- closed loops around the plant (20 ms period, 8-bit PWM, sample-then-apply) ---- */
#define PERIOD_MS 20

static void apply(plant_dcmotor_t *m, float duty)
{
    plant_dcmotor_advance(m, duty_pwm_applied_pct(duty_pwm_from_pct(duty)), PERIOD_MS * 1e-3);
}

/* P only, Kp = 0.02, step 0 -> 1000 (the lab's exercise): with friction a P loop stops where the
 * duty Kp x error no longer keeps the motor turning: below the Coulomb level and, once stopped,
 * below breakaway. So it must end with 0 < error <= breakaway duty / Kp, without overshoot,
 * and settle there. */
static void p_loop_step_settles_short_of_setpoint(void **state)
{
    plant_dcmotor_params_t prm;
    plant_dcmotor_t m;
    pctrl_t c;
    int k;
    int32_t pos = 0, max_pos = 0, last = 0;
    double v_break, duty_break;
    (void)state;
    plant_dcmotor_default_params(&prm);
    plant_dcmotor_init(&m, &prm);
    pctrl_init(&c, 0.02f);
    for (k = 0; k < 10 * 1000 / PERIOD_MS; k++) { /* 10 s */
        pos = plant_dcmotor_count(&m);
        if (pos > max_pos)
            max_pos = pos;
        if (k == 8 * 1000 / PERIOD_MS)
            last = pos;
        apply(&m, pctrl_duty_pct(&c, 1000, pos));
    }
    v_break = prm.static_nm * prm.resistance_ohm / prm.k_v_s_per_rad;
    duty_break = prm.deadband_pct + v_break / (prm.supply_v - prm.bridge_drop_v) * 100 * (100 - prm.deadband_pct) / 100;
    assert_true(max_pos <= 1000);
    assert_true(1000 - pos > 0);
    assert_true(0.02 * (1000 - pos) <= duty_break + 0.2); /* + half a PWM step */
    /* settled: less than 1 % of the step in the last 2 s (it may still creep a few counts while
     * the quantised duty sits just above the Coulomb level) */
    assert_true(pos - last >= 0 && pos - last <= 10);
}

/* PID (PID_v1 behaviour, float as on the Mega), Kp 0.1, Ki 0.1, Kd 0.002: the integral removes
 * the friction error; the step must end within +-2 counts of the setpoint, and stay within
 * 2 % of the step after 3 s. */
static void pid_loop_step_settles_at_setpoint(void **state)
{
    plant_dcmotor_params_t prm;
    plant_dcmotor_t m;
    pidf_ctrl_t c;
    float in = 0, out = 0, sp = 1000;
    int k;
    int32_t pos = 0;
    (void)state;
    plant_dcmotor_default_params(&prm);
    plant_dcmotor_init(&m, &prm);
    assert_int_equal(pidf_init(&c, &in, &out, &sp, 0.1f, 0.1f, 0.002f, PID_P_ON_E, PID_DIRECT, 0), MS_OK);
    assert_int_equal(pidf_set_output_limits(&c, -100, 100), MS_OK);
    assert_int_equal(pidf_set_sample_time(&c, PERIOD_MS), MS_OK);
    pidf_set_mode(&c, PID_AUTOMATIC);
    for (k = 0; k < 8 * 1000 / PERIOD_MS; k++) {
        pos = plant_dcmotor_count(&m);
        in = (float)pos;
        assert_int_equal(pidf_compute(&c, (uint32_t)(k * PERIOD_MS)), 1); /* every period computes */
        if (k * PERIOD_MS >= 3000)
            assert_true(fabs(pos - 1000.0) <= 20.0);
        apply(&m, out);
    }
    assert_true(fabs(pos - 1000.0) <= 2.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(p_duty_is_kp_times_error),
        cmocka_unit_test(p_duty_is_clamped_to_100_percent),
        cmocka_unit_test(p_error_wraps_like_the_counter),
        cmocka_unit_test(p_duty_with_the_gain_given_is_the_controllers),
        cmocka_unit_test(p_rejects_negative_and_non_finite_gain),
        cmocka_unit_test(pwm_rounds_duty_to_8_bits),
        cmocka_unit_test(pwm_applied_duty_is_pwm_over_255),
        cmocka_unit_test(p_loop_step_settles_short_of_setpoint),
        cmocka_unit_test(pid_loop_step_settles_at_setpoint),
    };
    return cmocka_run_group_tests_name("servo_control", tests, NULL, NULL);
}
