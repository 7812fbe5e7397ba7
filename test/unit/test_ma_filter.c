/* Unit tests: ma_filter - the moving-average acc/dec filter of the moving-average-filter note (N = tau/Ts taps, exact
 * ZOH discretisation of G(s) = (1/tau)(1 - e^(-tau s))/s, integer accumulator).
 * Expectations come from the continuous-time formula (the ideal ramp), from the note's own
 * delay state-space route re-derived below, and from the direct mean of the last N samples. */
#include "cmocka_all.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "filter_param.h"
#include "filter_testutil.h"
#include "ma_filter.h"

#define Q_V 0.001 /* the quantum used by motionsim and the sketch: 1 mV */

static double volts(int32_t sum, uint16_t taps)
{
    return (double)sum * Q_V / taps;
}

/* ---- the moving-average-filter note checkpoint ------------------------------------------------------------------- */

/* the moving-average-filter note ("Matlab simulation", "It is successfully accelerated in 9 seconds"): tau = 9 s,
 * Ts = 10 ms, a 5 V step held for 20 s. The continuous output is the ideal ramp
 * y(t) = 5 V * t / 9 s for 0 <= t <= 9 s, then 5 V. With the documented convention (the step is
 * sample k = 0 at t = 0; y[k] is the output at t = k Ts) every sample must lie within 1e-6 V of
 * that ramp, y is 2.5 V half-way (t = 4.5 s), first moves at k = 1 (the one-sample ZOH delay),
 * and reaches 5 V at exactly t = 9 s (k = 900), not one sample earlier. */
static void note_000_step_5v_tau_9s_ramps_linearly_to_5v_in_9s(void **state)
{
    int16_t buf[900];
    ma_filter_t f;
    uint16_t taps = 0;
    uint32_t k;
    int16_t u5 = 0;
    (void)state;
    assert_int_equal(filt_taps(9.0, 0.01, &taps), MS_OK);
    assert_int_equal(taps, 900);
    assert_int_equal(filt_quantise(5.0, Q_V, &u5), MS_OK);
    assert_int_equal(u5, 5000); /* 5 V is exact in the quantum */
    assert_int_equal(ma_filter_init(&f, buf, 900, taps), MS_OK);
    for (k = 0; k <= 2000; k++) {
        double t = k * 0.01;
        double ideal = t < 9.0 ? 5.0 * t / 9.0 : 5.0;
        double y = volts(ma_filter_step(&f, u5), taps);
        assert_true(fabs(y - ideal) <= 1e-6);
        if (k == 0)
            assert_true(y == 0.0);
        if (k == 1)
            assert_true(y > 0.0 && fabs(y - 5.0 / 900.0) <= 1e-12);
        if (k == 450)
            assert_true(fabs(y - 2.5) <= 1e-12);
        if (k == 899)
            assert_true(y < 5.0 - 0.005);
        if (k >= 900)
            assert_true(y == 5.0);
    }
}

/* The same, with the step at t0 = 1.23 s: the output stays 0 up to and including the step's
 * sample and reaches 5 V exactly 9 s after it. */
static void step_later_reaches_final_value_exactly_tau_after_the_step(void **state)
{
    int16_t buf[900];
    ma_filter_t f;
    uint32_t k, k0 = 123;
    (void)state;
    assert_int_equal(ma_filter_init(&f, buf, 900, 900), MS_OK);
    for (k = 0; k <= 1200; k++) {
        int32_t s = ma_filter_step(&f, tu_step(5000, k0, k));
        if (k <= k0)
            assert_int_equal(s, 0);
        else if (k < k0 + 900)
            assert_int_equal(s, 5000 * (int32_t)(k - k0)); /* y = 5 V (t - t0) / 9 s */
        else
            assert_int_equal(s, 5000 * 900);
    }
}

/* ---- the note's own route: getDelayModel(c2d(G, Ts, 'zoh')) and its state-space loop -------- */

/* Derivation of the matrices (the moving-average-filter note, "Represent discrete transfer function H as a difference
 * equation", getDelayModel):
 *
 * MATLAB builds G = 1/tau1*(1-exp(-tau1*s))/s as a series connection: the integrator 1/s acts on
 * u first, then (1 - e^(-tau s))/tau. As a state-space model with one internal delay, in the LFT
 * form getDelayModel returns (dx/dt = A x + B1 u + B2 w, y = C1 x + D11 u + D12 w,
 * z = C2 x + D21 u + D22 w, w(t) = z(t - tau)):
 *     dx/dt = u,   y = (x - w)/tau,   z = x,   w(t) = x(t - tau)
 * so y(t) = (x(t) - x(t - tau))/tau = (1/tau) * integral_{t-tau}^{t} u, the note's f_out.
 * c2d(.., Ts, 'zoh'): u is constant over each sample, so x[k+1] = e^(0 Ts) x[k] + (int_0^Ts 1 ds) u[k]
 * = x[k] + Ts u[k]; tau = N Ts is a whole number of samples, so the delay stays an internal delay
 * of N samples (w[k] = z[k-N]) and the static output equations are unchanged:
 *     A = 1, B1 = Ts, B2 = 0,  C1 = 1/tau, D11 = 0, D12 = -1/tau,  C2 = 1, D21 = 0, D22 = 0,  tau = N.
 * (MATLAB may scale the state differently; the input-output map is the same.) Check: y[k] =
 * (x[k] - x[k-N])/tau = (Ts/tau) (u[k-1] + ... + u[k-N]), the moving average of ma_filter.h.
 *
 * The note's loop is run below exactly as written, 1-based, except for the delay line: getDelayModel
 * defines w[k] = z[k - tau], i.e. w(k+1) = z(k+1-tau); the slide's z(max(1, k-tau)) delays by
 * tau + 1 samples (it would average N + 1 samples and settle at 5*901/900 V). Indices below 1 are
 * clamped to 1 as in the note: z(1) = C2 x(1) = 0 is the zero history. MATLAB's y(k) is the
 * output at sample k-1 of ours (MATLAB counts from 1). */
static void delay_model_loop(const double *u, double *y, int kmax, double tau_s, double ts_s, int tau)
{
    const double A = 1.0, B1 = ts_s, B2 = 0.0;
    const double C1 = 1.0 / tau_s, D11 = 0.0, D12 = -1.0 / tau_s;
    const double C2 = 1.0, D21 = 0.0, D22 = 0.0;
    /* 1-based like the note: x(1..kmax+1), z(1..kmax), w(1..kmax+1) */
    double *x = calloc((size_t)kmax + 2, sizeof *x);
    double *z = calloc((size_t)kmax + 2, sizeof *z);
    double *w = calloc((size_t)kmax + 2, sizeof *w);
    int k;
    assert_non_null(x);
    assert_non_null(z);
    assert_non_null(w);
    for (k = 1; k <= kmax; k++) {
        int idx = k + 1 - tau;
        x[k + 1] = A * x[k] + B1 * u[k] + B2 * w[k];
        y[k] = C1 * x[k] + D11 * u[k] + D12 * w[k];
        z[k] = C2 * x[k] + D21 * u[k] + D22 * w[k];
        w[k + 1] = z[idx < 1 ? 1 : idx];
    }
    free(x);
    free(z);
    free(w);
}

static void cross_check(int16_t (*input)(uint32_t k), int kmax)
{
    int16_t buf[900];
    ma_filter_t f;
    double *u = calloc((size_t)kmax + 2, sizeof *u);
    double *y = calloc((size_t)kmax + 2, sizeof *y);
    int k;
    assert_non_null(u);
    assert_non_null(y);
    for (k = 1; k <= kmax; k++)
        u[k] = input((uint32_t)(k - 1)) * Q_V;
    delay_model_loop(u, y, kmax, 9.0, 0.01, 900);
    assert_int_equal(ma_filter_init(&f, buf, 900, 900), MS_OK);
    for (k = 1; k <= kmax; k++) {
        double ours = volts(ma_filter_step(&f, input((uint32_t)(k - 1))), 900);
        assert_true(fabs(ours - y[k]) <= 1e-9);
    }
    free(u);
    free(y);
}

static int16_t note_input(uint32_t k)
{
    (void)k;
    return 5000; /* u = Vmax*ones(1, kmax), Vmax = 5 V */
}

static int16_t square_input(uint32_t k)
{
    return tu_square(5000, 1500, k); /* 5 V for 15 s, 0 V for 15 s */
}

/* the moving-average-filter note "Matlab simulation (1/2), (2/2)": tau1 = 9, sampling time 0.01, max simulation time
 * 20 s, Vmax = 5 V: the delay state-space loop and ma_filter give the same output at every
 * sample; also for a 30 s square wave over 60 s (deceleration too). */
static void note_000_delay_model_loop_gives_the_same_output(void **state)
{
    (void)state;
    cross_check(note_input, 2000); /* kmax = round(max simulation time / sampling time) */
    cross_check(square_input, 6000);
}

/* ---- no drift: 10^8 samples ------------------------------------------------------------------ */

/* Exact sum of the N samples before index k, regenerated from the generator (not the filter). */
static int64_t exact_sum(uint64_t seed, uint64_t k, uint16_t taps)
{
    int64_t s = 0;
    uint64_t j;
    for (j = 1; j <= taps && j <= k; j++)
        s += tu_sample(seed, k - j);
    return s;
}

/* After 10^8 full-scale pseudo-random samples (the worst bounded input: every sample anywhere in
 * -32767..32767 quanta) the output is still exactly the mean of the last N quantised inputs;
 * checked every 10^7 samples, and its value in volts within one quantum of that mean. */
static void no_drift_after_1e8_samples(void **state)
{
    static int16_t buf[900];
    ma_filter_t f;
    const uint64_t total = 100000000ull, every = 10000000ull;
    uint64_t k;
    (void)state;
    assert_int_equal(ma_filter_init(&f, buf, 900, 900), MS_OK);
    for (k = 0; k < total; k++) {
        int32_t s = ma_filter_step(&f, tu_sample(1, k));
        if (k % every == every - 1 || k == 12345) {
            int64_t e = exact_sum(1, k, 900);
            assert_int_equal(s, e);
            assert_true(fabs(volts(s, 900) - (double)e * Q_V / 900) <= Q_V);
        }
    }
    assert_int_equal(ma_filter_sum(&f), exact_sum(1, total, 900));
}

/* The check above has teeth, and it is why the note's route is not what runs on the Mega: there
 * double is float, and the delay model's integrator state x = Ts * (u[0] + u[1] + ...) grows
 * without bound, so its rounding error does too. The note's loop in float, fed 5 V for 10^6
 * samples (2.8 hours at 100 Hz), is off by more than one quantum; ma_filter is exact. */
static void note_delay_model_in_float_drifts_where_ma_filter_does_not(void **state)
{
    static float x_hist[901]; /* x[k-900..k]: the internal delay line w[k] = x[k-900] */
    static int16_t buf[900];
    ma_filter_t f;
    const float ts = 0.01f, tau = 9.0f;
    float x = 0.0f, worst = 0.0f;
    uint32_t k, head = 0;
    (void)state;
    assert_int_equal(ma_filter_init(&f, buf, 900, 900), MS_OK);
    for (k = 0; k < 1000000u; k++) {
        float w = x_hist[head];            /* x[k-900] (0 before the start) */
        float y = (x - w) / tau;           /* y = C1 x + D12 w */
        int32_t s = ma_filter_step(&f, 5000);
        x_hist[head] = x;
        head = (head + 1) % 901u;
        x = x + ts * 5.0f;                 /* x[k+1] = A x + B1 u */
        if (k >= 901u) {
            float e = fabsf(y - 5.0f);
            if (e > worst)
                worst = e;
            assert_int_equal(s, 900 * 5000);
        }
    }
    assert_true(worst > (float)Q_V);
}

/* ---- the definition, for several N ------------------------------------------------------------ */

/* y[k] = (u[k-1] + ... + u[k-N]) / N at every sample, for N = 1, 2, 7, 900 and 65535 (the
 * largest), over more than one wrap of the ring. */
static void output_is_the_mean_of_the_previous_n_samples(void **state)
{
    static int16_t buf[65535];
    const uint16_t taps_list[] = {1, 2, 7, 900, 65535};
    size_t t;
    (void)state;
    for (t = 0; t < sizeof taps_list / sizeof taps_list[0]; t++) {
        uint16_t n = taps_list[t];
        ma_filter_t f;
        int64_t window = 0; /* independent running window over int64 */
        uint64_t k, kmax = 3u * n + 100u;
        assert_int_equal(ma_filter_init(&f, buf, 65535, n), MS_OK);
        for (k = 0; k < kmax; k++) {
            int16_t u = tu_sample(7 + t, k);
            assert_int_equal(ma_filter_sum(&f), window);
            assert_int_equal(ma_filter_step(&f, u), window);
            window += u;
            if (k >= n)
                window -= tu_sample(7 + t, k - n);
        }
        if (n < 1000)
            assert_int_equal(window, exact_sum(7 + t, kmax, n));
    }
}

/* Extremes: N = 65535 taps all at +32767 (or -32767) quanta: the sum reaches +-2147385345 without
 * overflowing (UBSan build would report it) and is exact. */
static void full_scale_at_65535_taps_does_not_overflow(void **state)
{
    static int16_t buf[65535];
    ma_filter_t f;
    uint32_t k;
    (void)state;
    assert_int_equal(ma_filter_init(&f, buf, 65535, 65535), MS_OK);
    for (k = 0; k < 65535u; k++)
        (void)ma_filter_step(&f, 32767);
    assert_int_equal(ma_filter_sum(&f), 65535 * 32767);
    for (k = 0; k < 65535u; k++)
        (void)ma_filter_step(&f, -32767);
    assert_int_equal(ma_filter_sum(&f), -65535 * 32767);
}

static void reset_returns_to_rest(void **state)
{
    int16_t buf[10];
    ma_filter_t f;
    int i;
    (void)state;
    assert_int_equal(ma_filter_init(&f, buf, 10, 10), MS_OK);
    for (i = 0; i < 25; i++)
        (void)ma_filter_step(&f, 1000);
    assert_int_equal(ma_filter_sum(&f), 10000);
    ma_filter_reset(&f);
    assert_int_equal(ma_filter_sum(&f), 0);
    assert_int_equal(ma_filter_step(&f, 500), 0);
    assert_int_equal(ma_filter_step(&f, 500), 500);
}

/* ---- bad parameters: a status, and nothing changes --------------------------------------------- */
static void bad_parameters_are_rejected_and_change_nothing(void **state)
{
    int16_t buf[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    int16_t copy[8];
    ma_filter_t f, before;
    (void)state;
    memcpy(copy, buf, sizeof buf);
    memset(&f, 0x5A, sizeof f);
    before = f;
    assert_int_equal(ma_filter_init(NULL, buf, 8, 4), MS_ERR_NULL);
    assert_int_equal(ma_filter_init(&f, NULL, 8, 4), MS_ERR_NULL);
    assert_int_equal(ma_filter_init(&f, buf, 8, 0), MS_ERR_TAU_BELOW_TS);
    assert_int_equal(ma_filter_init(&f, buf, 8, 9), MS_ERR_TOO_MANY_TAPS); /* more taps than the buffer */
    assert_memory_equal(&f, &before, sizeof f);
    assert_memory_equal(buf, copy, sizeof buf);
    assert_int_equal(ma_filter_init(&f, buf, 8, 8), MS_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(note_000_step_5v_tau_9s_ramps_linearly_to_5v_in_9s),
        cmocka_unit_test(step_later_reaches_final_value_exactly_tau_after_the_step),
        cmocka_unit_test(note_000_delay_model_loop_gives_the_same_output),
        cmocka_unit_test(no_drift_after_1e8_samples),
        cmocka_unit_test(note_delay_model_in_float_drifts_where_ma_filter_does_not),
        cmocka_unit_test(output_is_the_mean_of_the_previous_n_samples),
        cmocka_unit_test(full_scale_at_65535_taps_does_not_overflow),
        cmocka_unit_test(reset_returns_to_rest),
        cmocka_unit_test(bad_parameters_are_rejected_and_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
