/* Unit tests: the DC gearmotor + encoder plant (sim/plant_dcmotor.c) against its own analytic
 * solutions, written out here from the model's equations (not from the code):
 *   steady speed from the torque balance  k i = b w + Tc,  i = (V - k w)/R
 *     -> w_ss = (k V/R - Tc) / (k^2/R + b)
 *   first-order approach with tau = J / (k^2/R + b)
 *   dead zone on the duty, breakaway at |k V/R| = Ts, coasting stop time
 *     t_stop = tau ln(1 + w0 (k^2/R + b) / Tc)
 * and against the motor's datasheet (Pololu 37D 30:1 12 V: 330 rpm free-run, 5.5 A stall).
 */
#include "cmocka_all.h"

#include <math.h>
#include <string.h>

#include "plant_dcmotor.h"

#define TWO_PI 6.283185307179586476925

static void assert_close(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: got %.12g, want %.12g (tolerance %.3g)", what, got, want, tol);
}

static double damping(const plant_dcmotor_params_t *p)
{
    return p->k_v_s_per_rad * p->k_v_s_per_rad / p->resistance_ohm + p->viscous_nm_s_per_rad;
}

/* V for a duty from the dead-zone formula (independent of the code's helper). */
static double volts(const plant_dcmotor_params_t *p, double duty)
{
    double m = fabs(duty) > 100 ? 100 : fabs(duty);
    double eff = m <= p->deadband_pct ? 0 : (m - p->deadband_pct) * 100 / (100 - p->deadband_pct);
    return (duty < 0 ? -eff : eff) / 100 * (p->supply_v - p->bridge_drop_v);
}

static double steady_speed(const plant_dcmotor_params_t *p, double duty)
{
    double v = volts(p, duty);
    double drive = p->k_v_s_per_rad * v / p->resistance_ohm;
    if (fabs(drive) <= p->static_nm)
        return 0;
    return (drive - (drive > 0 ? p->coulomb_nm : -p->coulomb_nm)) / damping(p);
}

/* Datasheet check: with 12 V straight on the motor (no bridge drop, no dead zone) the defaults
 * give the published free-run speed 330 rpm x 30 = 9900 rpm and stall current 12 V / R = 5.5 A. */
static void defaults_match_the_datasheet(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t m;
    (void)state;
    plant_dcmotor_default_params(&p);
    assert_null(plant_dcmotor_check_params(&p));
    assert_close(p.supply_v / p.resistance_ohm, 5.5, 1e-12, "stall current (A)");
    p.bridge_drop_v = 0;
    p.deadband_pct = 0;
    assert_int_equal(plant_dcmotor_init(&m, &p), 0);
    plant_dcmotor_advance(&m, 100, 2.0); /* ~60 time constants */
    assert_close(plant_dcmotor_output_rpm(&m), 330.0, 330.0 * 1e-9, "free-run output speed (rpm)");
    assert_close(plant_dcmotor_current_a(&m), 0.15, 1e-9, "free-run current (A)");
    assert_close(p.counts_per_rev * p.gear_ratio, 1920, 0, "counts per output revolution");
}

/* The documented limitation (plant_dcmotor.h, README "Servo control"): no current limit, so the
 * model exceeds the L298P's 2 A per channel. From the model's equations: at 100 % duty from rest
 * i = (V - k w)/R starts at V/R = 10 V / (12/5.5) ohm and falls below 2 A when w = (V - 2 A R)/k,
 * reached at t = -tau ln(1 - w/w_ss); at standstill 2 A needs V = 2 A R, i.e. a duty of
 * db + (2 A R / (12 V - 2 V)) (100 - db). */
static void current_is_not_limited_to_the_bridge_rating(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t m;
    double v, w_2a, t_2a, duty_2a;
    (void)state;
    plant_dcmotor_default_params(&p);
    v = p.supply_v - p.bridge_drop_v;
    w_2a = (v - 2.0 * p.resistance_ohm) / p.k_v_s_per_rad;
    t_2a = -p.inertia_kg_m2 / damping(&p) * log(1 - w_2a / steady_speed(&p, 100));
    duty_2a = p.deadband_pct + 2.0 * p.resistance_ohm / v * (100 - p.deadband_pct);
    assert_close(v / p.resistance_ohm, 4.58, 5e-3, "start current at 100 % (A), documented as 4.58 A");
    assert_close(t_2a, 0.0296, 1e-4, "time above 2 A at 100 % (s), documented as 30 ms");
    assert_close(duty_2a, 44.8, 0.05, "duty for 2 A at standstill (%), documented as 44.8 %");
    plant_dcmotor_init(&m, &p);
    plant_dcmotor_advance(&m, 100, 1e-9);
    assert_close(plant_dcmotor_current_a(&m), v / p.resistance_ohm, 1e-5, "current just after the start (A)");
    plant_dcmotor_init(&m, &p);
    plant_dcmotor_advance(&m, 100, t_2a);
    assert_close(plant_dcmotor_current_a(&m), 2.0, 1e-6, "current when the run-up reaches 2 A (A)");
}

static void constant_duty_reaches_torque_balance_speed(void **state)
{
    static const double duties[] = {100, 50, 20, 7, -30, -100, 150, -150};
    plant_dcmotor_params_t p;
    size_t i;
    (void)state;
    plant_dcmotor_default_params(&p);
    for (i = 0; i < sizeof duties / sizeof duties[0]; i++) {
        plant_dcmotor_t m;
        double want = steady_speed(&p, duties[i]);
        int32_t c0, c1;
        plant_dcmotor_init(&m, &p);
        plant_dcmotor_advance(&m, duties[i], 1.5);
        assert_close(plant_dcmotor_speed_rad_s(&m), want, fabs(want) * 1e-9 + 1e-12, "steady speed (rad/s)");
        /* the encoder then counts w * 64 / 2pi per second, to within one count */
        c0 = plant_dcmotor_count(&m);
        plant_dcmotor_advance(&m, duties[i], 1.0);
        c1 = plant_dcmotor_count(&m);
        assert_close((double)(c1 - c0), want * p.counts_per_rev / TWO_PI, 1.0, "counts in one second");
    }
}

/* Speed after one time constant from rest: w_ss (1 - 1/e); and the position from the integral
 * of w: theta(t) = w_ss (t - tau (1 - e^(-t/tau))). */
static void step_response_is_first_order(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t m;
    double tau, w_ss, theta;
    (void)state;
    plant_dcmotor_default_params(&p);
    plant_dcmotor_init(&m, &p);
    tau = p.inertia_kg_m2 / damping(&p);
    w_ss = steady_speed(&p, 60);
    plant_dcmotor_advance(&m, 60, tau);
    assert_close(plant_dcmotor_speed_rad_s(&m), w_ss * (1 - exp(-1.0)), w_ss * 1e-12, "speed at t = tau");
    theta = w_ss * (tau - tau * (1 - exp(-1.0))) * p.counts_per_rev / TWO_PI;
    assert_close(m.theta_counts, theta, 1e-9, "angle at t = tau (counts)");
}

/* Any split of the time into steps gives the same trajectory (exact integration). */
static void result_does_not_depend_on_step_size(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t a, b, c;
    int i;
    (void)state;
    plant_dcmotor_default_params(&p);
    plant_dcmotor_init(&a, &p);
    plant_dcmotor_init(&b, &p);
    plant_dcmotor_init(&c, &p);
    /* 0.2 s at 40 %, then 0.3 s at -25 % (through a reversal with a Coulomb stop) */
    plant_dcmotor_advance(&a, 40, 0.2);
    plant_dcmotor_advance(&a, -25, 0.3);
    for (i = 0; i < 200000; i++)
        plant_dcmotor_advance(&b, 40, 1e-6);
    for (i = 0; i < 300000; i++)
        plant_dcmotor_advance(&b, -25, 1e-6);
    for (i = 0; i < 10; i++)
        plant_dcmotor_advance(&c, 40, 0.02);
    for (i = 0; i < 15; i++)
        plant_dcmotor_advance(&c, -25, 0.02);
    assert_close(b.theta_counts, a.theta_counts, 1e-6, "1 us steps vs one step (counts)");
    assert_close(c.theta_counts, a.theta_counts, 1e-9, "20 ms steps vs one step (counts)");
    assert_close(b.omega_rad_s, a.omega_rad_s, 1e-6, "1 us steps vs one step (rad/s)");
    assert_true(a.omega_rad_s < 0); /* it did reverse */
}

/* Without friction, the dead zone alone decides: no voltage at |duty| <= db, and above it the
 * speed grows as (|duty| - db) 100/(100 - db). */
static void dead_band_gives_no_drive(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t m;
    double db, k, w_hi;
    (void)state;
    plant_dcmotor_default_params(&p);
    p.coulomb_nm = p.static_nm = 0;
    db = p.deadband_pct;
    plant_dcmotor_init(&m, &p);
    plant_dcmotor_advance(&m, db, 1.0);
    assert_true(m.omega_rad_s == 0 && plant_dcmotor_count(&m) == 0);
    plant_dcmotor_advance(&m, -db, 1.0);
    assert_true(m.omega_rad_s == 0);
    plant_dcmotor_advance(&m, db + 1.0, 1.0);
    k = p.k_v_s_per_rad;
    w_hi = k * (1.0 * 100 / (100 - db) / 100 * (p.supply_v - p.bridge_drop_v)) / p.resistance_ohm / damping(&p);
    assert_close(m.omega_rad_s, w_hi, w_hi * 1e-9, "speed 1 % above the dead band");
}

/* Breakaway: at rest the motor stays put while k V / R <= Ts, and starts just above it. */
static void coulomb_friction_breakaway(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t m;
    double v_break, duty_break;
    (void)state;
    plant_dcmotor_default_params(&p);
    v_break = p.static_nm * p.resistance_ohm / p.k_v_s_per_rad;
    duty_break = p.deadband_pct + v_break / (p.supply_v - p.bridge_drop_v) * 100 * (100 - p.deadband_pct) / 100;
    assert_close(duty_break, 5.8, 0.05, "breakaway duty (%), documented in the header");
    plant_dcmotor_init(&m, &p);
    plant_dcmotor_advance(&m, duty_break * 0.999, 2.0);
    plant_dcmotor_advance(&m, -duty_break * 0.999, 2.0);
    assert_true(m.omega_rad_s == 0 && m.theta_counts == 0);
    plant_dcmotor_advance(&m, duty_break * 1.001, 1.0);
    assert_true(m.omega_rad_s > 0);
    assert_close(m.omega_rad_s, steady_speed(&p, duty_break * 1.001), 1e-6, "speed just above breakaway");
    /* once turning, it keeps turning below breakaway down to the Coulomb level (3.9 %) */
    plant_dcmotor_advance(&m, 4.5, 1.0);
    assert_true(m.omega_rad_s > 0);
    assert_true(steady_speed(&p, 4.5) == 0); /* 4.5 % could not start it from rest */
    assert_close(m.omega_rad_s, (p.k_v_s_per_rad * volts(&p, 4.5) / p.resistance_ohm - p.coulomb_nm) / damping(&p),
                 1e-9, "speed at 4.5 % after breakaway");
}

/* Coasting at 0 % from speed w0: Coulomb friction stops it in finite time
 * t_stop = tau ln(1 + w0 D / Tc); afterwards it stays stopped. */
static void coasting_stops_in_finite_time(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t m;
    double w0, tau, t_stop;
    int32_t c;
    (void)state;
    plant_dcmotor_default_params(&p);
    plant_dcmotor_init(&m, &p);
    plant_dcmotor_advance(&m, 30, 1.0);
    w0 = m.omega_rad_s;
    tau = p.inertia_kg_m2 / damping(&p);
    t_stop = tau * log(1 + w0 * damping(&p) / p.coulomb_nm);
    plant_dcmotor_advance(&m, 0, t_stop * 0.999);
    assert_true(m.omega_rad_s > 0);
    plant_dcmotor_advance(&m, 0, t_stop * 0.002);
    assert_true(m.omega_rad_s == 0);
    c = plant_dcmotor_count(&m);
    plant_dcmotor_advance(&m, 0, 5.0);
    assert_int_equal(plant_dcmotor_count(&m), c);
}

/* The count is floor(angle + 1/2) and wraps like the LS7366R's 32-bit counter. */
static void count_rounds_and_wraps_at_32_bits(void **state)
{
    plant_dcmotor_params_t p;
    plant_dcmotor_t m;
    int32_t prev;
    int wraps = 0, i;
    (void)state;
    plant_dcmotor_default_params(&p);
    plant_dcmotor_init(&m, &p);
    plant_dcmotor_set_position_counts(&m, 0.49);
    assert_int_equal(plant_dcmotor_count(&m), 0);
    plant_dcmotor_set_position_counts(&m, 0.5);
    assert_int_equal(plant_dcmotor_count(&m), 1);
    plant_dcmotor_set_position_counts(&m, -0.51);
    assert_int_equal(plant_dcmotor_count(&m), -1);
    plant_dcmotor_set_position_counts(&m, 2147483647.0 - 200.0);
    prev = plant_dcmotor_count(&m);
    for (i = 0; i < 200; i++) {
        int32_t c;
        plant_dcmotor_advance(&m, 100, 0.001);
        c = plant_dcmotor_count(&m);
        /* successive counts differ by a few counts modulo 2^32 */
        assert_true((uint32_t)c - (uint32_t)prev < 20U);
        wraps += c < 0 && prev > 0;
        prev = c;
    }
    assert_int_equal(wraps, 1);
    plant_dcmotor_set_position_counts(&m, -2147483648.0 - 1.0);
    assert_int_equal(plant_dcmotor_count(&m), 2147483647);
}

static void bad_parameters_are_refused(void **state)
{
    plant_dcmotor_params_t p, q;
    plant_dcmotor_t m;
    (void)state;
    plant_dcmotor_default_params(&p);
    plant_dcmotor_init(&m, &p);
    q = p;
    q.resistance_ohm = 0;
    assert_non_null(plant_dcmotor_check_params(&q));
    assert_int_equal(plant_dcmotor_init(&m, &q), -1);
    assert_true(m.p.resistance_ohm == p.resistance_ohm); /* untouched */
    q = p;
    q.static_nm = q.coulomb_nm / 2;
    assert_non_null(plant_dcmotor_check_params(&q));
    q = p;
    q.deadband_pct = 100;
    assert_non_null(plant_dcmotor_check_params(&q));
    q = p;
    q.inertia_kg_m2 = NAN;
    assert_non_null(plant_dcmotor_check_params(&q));
    /* NaN duty counts as 0; dt <= 0 or NaN does nothing */
    plant_dcmotor_advance(&m, NAN, 1.0);
    assert_true(m.omega_rad_s == 0);
    plant_dcmotor_advance(&m, 100, -1.0);
    plant_dcmotor_advance(&m, 100, NAN);
    assert_true(m.omega_rad_s == 0 && m.t_s == 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(defaults_match_the_datasheet),
        cmocka_unit_test(constant_duty_reaches_torque_balance_speed),
        cmocka_unit_test(step_response_is_first_order),
        cmocka_unit_test(result_does_not_depend_on_step_size),
        cmocka_unit_test(dead_band_gives_no_drive),
        cmocka_unit_test(coulomb_friction_breakaway),
        cmocka_unit_test(coasting_stops_in_finite_time),
        cmocka_unit_test(count_rounds_and_wraps_at_32_bits),
        cmocka_unit_test(bad_parameters_are_refused),
        cmocka_unit_test(current_is_not_limited_to_the_bridge_rating),
    };
    return cmocka_run_group_tests_name("plant_dcmotor", tests, NULL, NULL);
}
