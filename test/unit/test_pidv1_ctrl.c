/* Unit tests: pidv1_ctrl against the PID_v1 1.2.1 reference vectors (the lab handout section 4.2 asks for
 * "PID by Brett Beauregard"; the vectors in test/data/pid_v1/ were recorded from that library,
 * see the README there), in double (pid_*) and in float (pidf_*), every row bit for bit:
 * computed, output, and the internal state columns (output_sum, last_input, last_time_ms, working
 * and user gains, sample time, limits, mode, direction, POn). Then every argument PID_v1
 * rejects, one by one: the call returns its status and changes nothing.
 *
 * The vector reader (sim/pid_vector.c and its CSV reader sim/csv_read.c, with Debian's cJSON) is compiled in from sim/, since the test
 * programs link only libmotion.a. Data folder: $PID_V1_DATA, else test/data/pid_v1 (the tests
 * run from the repository root).
 */
#include "cmocka_all.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../sim/csv_read.c"
#include "../../sim/pid_vector.c"
#include "pidv1_ctrl.h"

static const char *data_dir(void)
{
    const char *d = getenv("PID_V1_DATA");
    return d != NULL ? d : "test/data/pid_v1";
}

/* ---- comparing one replayed row with the vector's columns ---- */
typedef struct {
    const pv_vector_t *v;
    const char *name;
    size_t mismatches;
    char first[512]; /* the first mismatch, for the failure message */
} check_t;

static void mismatch(check_t *k, size_t row, const char *col, const char *want, const char *got)
{
    if (k->mismatches++ == 0)
        snprintf(k->first, sizeof k->first, "%s row %zu (t_ms=%lu) column %s: vector %s, ours %s", k->name, row + 2,
                 (unsigned long)k->v->rows[row].t_ms, col, want, got);
}

/* Bitwise equality (0 and -0 differ; the vectors print -0 where the library produced it). */
static void check_d(check_t *k, size_t row, const char *col, double got)
{
    const char *cell = pv_cell(k->v, row, col);
    double want;
    char *end;
    char buf[40];
    if (cell == NULL || cell[0] == '\0') /* column absent, or value uninitialised in PID_v1 */
        return;
    want = strtod(cell, &end);
    if (*end != '\0' || memcmp(&want, &got, sizeof want) != 0) {
        snprintf(buf, sizeof buf, "%.17g", got);
        mismatch(k, row, col, cell, buf);
    }
}

static void check_f(check_t *k, size_t row, const char *col, float got)
{
    const char *cell = pv_cell(k->v, row, col);
    float want;
    char *end;
    char buf[40];
    if (cell == NULL || cell[0] == '\0')
        return;
    want = strtof(cell, &end);
    if (*end != '\0' || memcmp(&want, &got, sizeof want) != 0) {
        snprintf(buf, sizeof buf, "%.9g", (double)got);
        mismatch(k, row, col, cell, buf);
    }
}

/* Integers; last_time_ms is compared modulo 2^32 (our clock is 32-bit; a 64-bit-clock vector
 * differs only before the first computation, where it holds 2^64 - 100 instead of 2^32 - 100). */
static void check_u(check_t *k, size_t row, const char *col, long long got, int mod32)
{
    const char *cell = pv_cell(k->v, row, col);
    unsigned long long want;
    char *end;
    char buf[40];
    if (cell == NULL || cell[0] == '\0')
        return;
    if (cell[0] == '-')
        want = (unsigned long long)strtoll(cell, &end, 10);
    else
        want = strtoull(cell, &end, 10);
    if (mod32)
        want &= 0xFFFFFFFFULL;
    if (*end != '\0' || want != (unsigned long long)got) {
        snprintf(buf, sizeof buf, "%lld", got);
        mismatch(k, row, col, cell, buf);
    }
}

#define CHECK_STATE(CHECK_REAL, c)                                                       \
    do {                                                                               \
        CHECK_REAL(k, row, "output_sum", (c)->output_sum);                             \
        CHECK_REAL(k, row, "last_input", (c)->last_input);                             \
        check_u(k, row, "last_time_ms", (long long)(c)->last_time_ms, 1);              \
        CHECK_REAL(k, row, "kp", (c)->kp);                                             \
        CHECK_REAL(k, row, "ki", (c)->ki);                                             \
        CHECK_REAL(k, row, "kd", (c)->kd);                                             \
        CHECK_REAL(k, row, "disp_kp", (c)->disp_kp);                                   \
        CHECK_REAL(k, row, "disp_ki", (c)->disp_ki);                                   \
        CHECK_REAL(k, row, "disp_kd", (c)->disp_kd);                                   \
        check_u(k, row, "sample_time_ms", (long long)(c)->sample_time_ms, 0);          \
        CHECK_REAL(k, row, "out_min", (c)->out_min);                                   \
        CHECK_REAL(k, row, "out_max", (c)->out_max);                                   \
        check_u(k, row, "direction", (long long)(c)->direction, 0);                    \
        check_u(k, row, "p_on", (long long)(c)->p_on, 0);                              \
        check_u(k, row, "p_on_e", (long long)(c)->p_on_e, 0);                          \
    } while (0)

static void row_double(void *user, size_t row, int computed, double output, const pid_ctrl_t *c)
{
    check_t *k = user;
    check_u(k, row, "computed", computed, 0);
    check_d(k, row, "output", output);
    check_u(k, row, "mode", pid_get_mode(c), 0);
    CHECK_STATE(check_d, c);
    /* the getters return the user gains */
    check_d(k, row, "disp_kp", pid_get_kp(c));
    check_d(k, row, "disp_ki", pid_get_ki(c));
    check_d(k, row, "disp_kd", pid_get_kd(c));
    check_u(k, row, "direction", pid_get_direction(c), 0);
}

static void row_float(void *user, size_t row, int computed, float output, const pidf_ctrl_t *c)
{
    check_t *k = user;
    check_u(k, row, "computed", computed, 0);
    check_f(k, row, "output", output);
    check_u(k, row, "mode", pidf_get_mode(c), 0);
    CHECK_STATE(check_f, c);
    check_f(k, row, "disp_kp", pidf_get_kp(c));
    check_f(k, row, "disp_ki", pidf_get_ki(c));
    check_f(k, row, "disp_kd", pidf_get_kd(c));
    check_u(k, row, "direction", pidf_get_direction(c), 0);
}

/* state: "d:PATH" or "f:PATH" */
static void replay_vector(void **state)
{
    const char *spec = *state;
    int is_float = spec[0] == 'f';
    const char *path = spec + 2;
    static pv_vector_t v;
    check_t k;
    char err[512];
    size_t cols_checked = 0, i;
    motion_status_t st;
    static const char *const needed[] = {"computed", "output", "output_sum", "kp", "ki", "kd", "mode"};
    if (pv_load(&v, path, err, sizeof err) != 0)
        fail_msg("%s", err);
    /* a vector without its result columns would pass vacuously */
    for (i = 0; i < sizeof needed / sizeof needed[0]; i++)
        cols_checked += pv_cell(&v, 0, needed[i]) != NULL;
    if (cols_checked != sizeof needed / sizeof needed[0]) {
        pv_free(&v);
        fail_msg("%s: the vector lacks result columns", path);
    }
    memset(&k, 0, sizeof k);
    k.v = &v;
    k.name = path;
    st = is_float ? pv_replay_float(&v, row_float, &k) : pv_replay_double(&v, row_double, &k);
    if (st != MS_OK) {
        pv_free(&v);
        fail_msg("%s: the constructor refused the set-up (%s)", path, motion_status_text(st));
    }
    print_message("# %s (%s): %zu rows, %zu mismatches\n", path, is_float ? "float" : "double", v.n_rows, k.mismatches);
    pv_free(&v);
    if (k.mismatches != 0)
        fail_msg("%zu mismatching values; first: %s", k.mismatches, k.first);
}

/* ---- rejected arguments (reference README "Summary of what is rejected"; vector h) ---- */
typedef struct {
    double in, out, sp;
    pid_ctrl_t c;
} fixture_t;

static void fixture_auto(fixture_t *f)
{
    f->in = 30;
    f->out = 0;
    f->sp = 60;
    assert_int_equal(pid_init(&f->c, &f->in, &f->out, &f->sp, 0.5, 1, 0.05, PID_P_ON_E, PID_DIRECT, 0), MS_OK);
    assert_int_equal(pid_set_output_limits(&f->c, -100, 100), MS_OK);
    assert_int_equal(pid_set_sample_time(&f->c, 20), MS_OK);
    pid_set_mode(&f->c, PID_AUTOMATIC);
    assert_int_equal(pid_compute(&f->c, 0), 1);
    f->in = 40;
    assert_int_equal(pid_compute(&f->c, 20), 1);
}

static void expect_unchanged(const fixture_t *before, const fixture_t *after)
{
    assert_memory_equal(&before->c, &after->c, sizeof before->c);
    assert_memory_equal(&before->out, &after->out, sizeof before->out);
}

static void rejects_negative_gains_whole_call(void **state)
{
    static const double gains[][3] = {{-1, 1, 0.05}, {0.5, -1, 0.05}, {0.5, 1, -0.05}, {-0.0001, -1, -2}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof gains / sizeof gains[0]; i++) {
        fixture_t f, g;
        fixture_auto(&f);
        g = f;
        assert_int_equal(pid_set_tunings(&g.c, gains[i][0], gains[i][1], gains[i][2]), MS_ERR_GAIN_NEGATIVE);
        expect_unchanged(&f, &g);
        /* the 4-argument form: POn is ignored too (reference README, h at 200..400) */
        assert_int_equal(pid_set_tunings_pon(&g.c, gains[i][0], gains[i][1], gains[i][2], PID_P_ON_M),
                         MS_ERR_GAIN_NEGATIVE);
        expect_unchanged(&f, &g);
    }
}

static void zero_gains_are_accepted(void **state)
{
    fixture_t f;
    (void)state;
    fixture_auto(&f);
    assert_int_equal(pid_set_tunings(&f.c, 0, 0, 0), MS_OK);
    assert_true(f.c.kp == 0 && f.c.ki == 0 && f.c.kd == 0);
}

static void rejects_limits_min_not_below_max(void **state)
{
    static const double lim[][2] = {{50, 50}, {60, -60}, {0, 0}, {-1, -2}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof lim / sizeof lim[0]; i++) {
        fixture_t f, g;
        fixture_auto(&f);
        g = f;
        assert_int_equal(pid_set_output_limits(&g.c, lim[i][0], lim[i][1]), MS_ERR_LIMITS_ORDER);
        expect_unchanged(&f, &g);
    }
}

static void rejects_sample_time_not_positive(void **state)
{
    static const int32_t ms[] = {0, -20, -1, INT32_MIN};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof ms / sizeof ms[0]; i++) {
        fixture_t f, g;
        fixture_auto(&f);
        g = f;
        assert_int_equal(pid_set_sample_time(&g.c, ms[i]), MS_ERR_SAMPLE_TIME);
        expect_unchanged(&f, &g);
    }
}

static void float_build_rejects_the_same(void **state)
{
    float in = 30, out = 0, sp = 60;
    pidf_ctrl_t c, d;
    (void)state;
    assert_int_equal(pidf_init(&c, &in, &out, &sp, 0.5f, 1, 0.05f, PID_P_ON_E, PID_DIRECT, 0), MS_OK);
    pidf_set_mode(&c, PID_AUTOMATIC);
    d = c;
    assert_int_equal(pidf_set_tunings(&c, 0.5f, -1, 0), MS_ERR_GAIN_NEGATIVE);
    assert_int_equal(pidf_set_output_limits(&c, 5, 5), MS_ERR_LIMITS_ORDER);
    assert_int_equal(pidf_set_sample_time(&c, 0), MS_ERR_SAMPLE_TIME);
    assert_memory_equal(&c, &d, sizeof c);
}

static void init_rejects_null_and_negative_gains(void **state)
{
    double in = 0, out = 0, sp = 0;
    pid_ctrl_t c;
    (void)state;
    assert_int_equal(pid_init(&c, NULL, &out, &sp, 1, 1, 1, PID_P_ON_E, PID_DIRECT, 0), MS_ERR_NULL);
    assert_int_equal(pid_init(&c, &in, NULL, &sp, 1, 1, 1, PID_P_ON_E, PID_DIRECT, 0), MS_ERR_NULL);
    assert_int_equal(pid_init(&c, &in, &out, NULL, 1, 1, 1, PID_P_ON_E, PID_DIRECT, 0), MS_ERR_NULL);
    assert_int_equal(pid_init(NULL, &in, &out, &sp, 1, 1, 1, PID_P_ON_E, PID_DIRECT, 0), MS_ERR_NULL);
    /* PID_v1 leaves the gains indeterminate here; ours are defined as 0 (documented) */
    assert_int_equal(pid_init(&c, &in, &out, &sp, 1, -1, 1, PID_P_ON_E, PID_DIRECT, 0), MS_ERR_GAIN_NEGATIVE);
    assert_true(c.kp == 0 && c.ki == 0 && c.kd == 0 && pid_get_kp(&c) == 0);
    assert_int_equal(pid_get_mode(&c), PID_MANUAL);
}

/* A negative gain in the constructor: PID_v1's SetTunings returns before it stores POn, so pOn
 * keeps the value of a zero-initialised (global) object, 0 = P_ON_M, and a later 3-argument
 * SetTunings (which reuses the stored pOn) computes proportional-on-measurement (reference
 * README: "SetTunings ... If any gain is negative, the whole call is ignored, including the POn
 * argument"; "The 3-argument form reuses the stored POn"). Such a controller must compute exactly
 * like one constructed with P_ON_M. */
static void negative_constructor_gain_leaves_pon_as_p_on_m(void **state)
{
    double in_a = 30, out_a = 0, sp_a = 60, in_b = 30, out_b = 0, sp_b = 60;
    pid_ctrl_t a, b;
    int k;
    (void)state;
    assert_int_equal(pid_init(&a, &in_a, &out_a, &sp_a, -1, 1, 0.05, PID_P_ON_E, PID_DIRECT, 0), MS_ERR_GAIN_NEGATIVE);
    assert_int_equal(pid_init(&b, &in_b, &out_b, &sp_b, 0.5, 1, 0.05, PID_P_ON_M, PID_DIRECT, 0), MS_OK);
    assert_int_equal(a.p_on, PID_P_ON_M);
    assert_int_equal(a.p_on_e, 0);
    assert_int_equal(pid_set_tunings(&a, 0.5, 1, 0.05), MS_OK);
    pid_set_output_limits(&a, -100, 100);
    pid_set_output_limits(&b, -100, 100);
    pid_set_mode(&a, PID_AUTOMATIC);
    pid_set_mode(&b, PID_AUTOMATIC);
    for (k = 1; k <= 20; k++) {
        in_a = in_b = 30 + 2 * k;
        assert_int_equal(pid_compute(&a, (uint32_t)(100 * k)), pid_compute(&b, (uint32_t)(100 * k)));
        assert_memory_equal(&out_a, &out_b, sizeof out_a);
    }
    /* on error it would differ from the first computation: kp * error = 0.5 * 28 alone is 14 */
    assert_true(out_a < 14);
}

/* Not rejected by PID_v1, so not by us: mode 2 means MANUAL, direction 2 and POn 7 are stored
 * (reference README, h at 900, 1600, 2000). */
static void unvalidated_values_behave_as_pid_v1(void **state)
{
    fixture_t f;
    (void)state;
    fixture_auto(&f);
    pid_set_mode(&f.c, 2);
    assert_int_equal(pid_get_mode(&f.c), PID_MANUAL);
    pid_set_mode(&f.c, PID_AUTOMATIC);
    pid_set_direction(&f.c, 2);
    assert_int_equal(pid_get_direction(&f.c), 2);
    assert_true(f.c.kp == -0.5); /* flipped: 2 differs from the stored DIRECT while AUTOMATIC */
    assert_int_equal(pid_set_tunings_pon(&f.c, 0.5, 1, 0.05, 7), MS_OK);
    assert_true(f.c.kp == 0.5); /* only 1 counts as REVERSE */
    assert_int_equal(f.c.p_on, 7);
    assert_int_equal(f.c.p_on_e, 0);
}

/* 32-bit millis() wrap: gating uses unsigned differences (reference README, vector j). */
static void clock_wraps_without_a_gap(void **state)
{
    double in = 0, out = 0, sp = 10;
    pid_ctrl_t c;
    uint32_t t = 0xFFFFFFFFUL - 30UL;
    int i, computed = 0;
    (void)state;
    assert_int_equal(pid_init(&c, &in, &out, &sp, 1, 0, 0, PID_P_ON_E, PID_DIRECT, t), MS_OK);
    assert_int_equal(pid_set_sample_time(&c, 20), MS_OK);
    pid_set_mode(&c, PID_AUTOMATIC);
    for (i = 0; i < 10; i++, t += 21U)
        computed += pid_compute(&c, t);
    assert_int_equal(computed, 10);
    assert_int_equal(pid_compute(&c, t - 21U + 19U), 0);
}

/* ---- behaviours of the held-back vectors d, f and i, from the reference README's facts ----
 * test/data/pid_v1/README.md describes scenarios whose CSVs
 * are held back. Each test below builds the situation and checks the README's statement, with
 * expectations worked out by hand from its "One computation, in order" and "Gain scaling"
 * sections (Kp 2, Ki 5, Kd 1, SetSampleTime(20): |kp| = 2, |ki| = 5 x 0.1 x 0.2 = 0.1,
 * |kd| = 1 / 0.1 / 0.2 = 50). Generated for double (pid_*) and float (pidf_*); the tolerance
 * covers float rounding only, never a sign or a missing clamp. */
#define NEAR(got, want) assert_true(fabs((double)(got) - (double)(want)) < 1e-4)

#define HELD_BACK_TESTS(real, P, T, SUFFIX)                                                          \
    /* "SetControllerDirection(d) ... In MANUAL the gains are not negated (i). The direction is    \
     * stored, but the controller stays direct-acting after going back to AUTOMATIC ... The       \
     * reverse sign only takes effect when SetTunings is called (at 2000)." */                    \
    static void direction_in_manual_waits_for_set_tunings_##SUFFIX(void **state)                    \
    {                                                                                              \
        real in = 60, out = 0, sp = 50;                                                            \
        T c;                                                                                       \
        (void)state;                                                                               \
        assert_int_equal(P##init(&c, &in, &out, &sp, 2, 5, 1, PID_P_ON_E, PID_DIRECT, 0), MS_OK);  \
        assert_int_equal(P##set_output_limits(&c, 0, 100), MS_OK);                                 \
        assert_int_equal(P##set_sample_time(&c, 20), MS_OK);                                       \
        P##set_direction(&c, PID_REVERSE); /* MANUAL: stored, gains untouched */                   \
        assert_int_equal(P##get_direction(&c), PID_REVERSE);                                       \
        NEAR(c.kp, 2);                                                                             \
        NEAR(c.ki, 0.1);                                                                           \
        NEAR(c.kd, 50);                                                                            \
        out = 50;                                                                                  \
        P##set_mode(&c, PID_AUTOMATIC); /* Initialize: output_sum = 50, last_input = 60 */         \
        assert_int_equal(P##compute(&c, 0), 1);                                                    \
        /* still direct-acting: sum = 50 + 0.1 x (-10) = 49; out = 2 x (-10) + 49 = 29 */          \
        NEAR(c.output_sum, 49);                                                                    \
        NEAR(out, 29);                                                                             \
        /* SetTunings applies the stored REVERSE: all three working gains negative */              \
        assert_int_equal(P##set_tunings(&c, 2, 5, 1), MS_OK);                                      \
        NEAR(c.kp, -2);                                                                            \
        NEAR(c.ki, -0.1);                                                                          \
        NEAR(c.kd, -50);                                                                           \
        NEAR(P##get_kp(&c), 2); /* the getters keep the user's values */                           \
        assert_int_equal(P##compute(&c, 20), 1);                                                   \
        /* reverse-acting: sum = 49 + (-0.1)(-10) = 50; out = (-2)(-10) + 50 = 70 */                \
        NEAR(c.output_sum, 50);                                                                    \
        NEAR(out, 70);                                                                             \
    }                                                                                              \
                                                                                                   \
    /* d_reverse: "REVERSE, limits 0..100; direction switched to DIRECT and back while AUTOMATIC". \
     * "Applies the tunings, which also computes the working gains ... and negates them for        \
     * REVERSE"; "If AUTOMATIC and d differs from the stored direction, it negates kp, ki and kd.  \
     * It always stores d. outputSum is not negated." */                                           \
    static void reverse_and_direction_changes_in_automatic_##SUFFIX(void **state)                   \
    {                                                                                              \
        real in = 60, out = 50, sp = 50;                                                           \
        T c;                                                                                       \
        (void)state;                                                                               \
        assert_int_equal(P##init(&c, &in, &out, &sp, 2, 5, 1, PID_P_ON_E, PID_REVERSE, 0), MS_OK); \
        NEAR(c.kp, -2); /* at the default 100 ms: ki = -5 x 0.1, kd = -1 / 0.1 */                  \
        NEAR(c.ki, -0.5);                                                                          \
        NEAR(c.kd, -10);                                                                           \
        assert_int_equal(P##set_output_limits(&c, 0, 100), MS_OK);                                 \
        assert_int_equal(P##set_sample_time(&c, 20), MS_OK);                                       \
        NEAR(c.ki, -0.1);                                                                          \
        NEAR(c.kd, -50);                                                                           \
        P##set_mode(&c, PID_AUTOMATIC);                                                            \
        assert_int_equal(P##compute(&c, 0), 1);                                                    \
        /* input above setpoint raises a reverse-acting output: sum = 50 + (-0.1)(-10) = 51,      \
         * out = (-2)(-10) + 51 = 71 */                                                            \
        NEAR(c.output_sum, 51);                                                                    \
        NEAR(out, 71);                                                                             \
        P##set_direction(&c, PID_DIRECT); /* AUTOMATIC and different: every gain flips */          \
        NEAR(c.kp, 2);                                                                             \
        NEAR(c.ki, 0.1);                                                                           \
        NEAR(c.kd, 50);                                                                            \
        NEAR(c.output_sum, 51); /* not negated */                                                  \
        assert_int_equal(P##get_direction(&c), PID_DIRECT);                                        \
        NEAR(P##get_kp(&c), 2);                                                                    \
        NEAR(P##get_ki(&c), 5);                                                                    \
        NEAR(P##get_kd(&c), 1);                                                                    \
        P##set_direction(&c, PID_DIRECT); /* the same direction again: nothing flips */            \
        NEAR(c.kp, 2);                                                                             \
        in = 62; /* dInput = 2: the derivative term is -kd x 2 = -100 */                           \
        assert_int_equal(P##compute(&c, 20), 1);                                                   \
        /* sum = 51 + 0.1 x (-12) = 49.8; out = 2 x (-12) + (49.8 - 100) = -74.2 -> clamp 0 */     \
        NEAR(c.output_sum, 49.8);                                                                  \
        NEAR(out, 0);                                                                              \
        P##set_direction(&c, PID_REVERSE); /* and back */                                          \
        NEAR(c.kp, -2);                                                                            \
        NEAR(c.ki, -0.1);                                                                          \
        NEAR(c.kd, -50);                                                                           \
        NEAR(c.output_sum, 49.8);                                                                  \
        in = 61; /* dInput = -1: -kd x (-1) = -50 */                                               \
        assert_int_equal(P##compute(&c, 40), 1);                                                   \
        /* sum = 49.8 + (-0.1)(-11) = 50.9; out = (-2)(-11) + (50.9 - 50) = 22.9 */               \
        NEAR(c.output_sum, 50.9);                                                                  \
        NEAR(out, 22.9);                                                                           \
    }                                                                                              \
                                                                                                   \
    /* "SetOutputLimits(min, max): ... If AUTOMATIC, it immediately clamps both the Output        \
     * variable and outputSum. f at 2500 shows this on a row without a computation: output        \
     * 60.61->50 and outputSum 54.01->50. In MANUAL nothing is clamped: e at 3200: Output stays   \
     * at 10, below the new minimum of 20; outputSum is clamped at the next Initialize (e at      \
     * 3500); Output is clamped at the next computation." */                                      \
    static void set_output_limits_clamps_at_once_only_in_automatic_##SUFFIX(void **state)           \
    {                                                                                              \
        real in = 0, out = 0, sp = 6;                                                              \
        T c;                                                                                       \
        (void)state;                                                                               \
        assert_int_equal(P##init(&c, &in, &out, &sp, 1, 0, 0, PID_P_ON_E, PID_DIRECT, 0), MS_OK);  \
        assert_int_equal(P##set_output_limits(&c, -100, 100), MS_OK);                              \
        assert_int_equal(P##set_sample_time(&c, 20), MS_OK);                                      \
        out = 54;                                                                                  \
        P##set_mode(&c, PID_AUTOMATIC); /* output_sum = 54 */                                      \
        assert_int_equal(P##compute(&c, 0), 1);                                                    \
        NEAR(out, 60); /* 1 x 6 + 54 */                                                            \
        NEAR(c.output_sum, 54);                                                                    \
        assert_int_equal(P##set_output_limits(&c, 0, 50), MS_OK); /* no computation follows */    \
        NEAR(out, 50);                                                                             \
        NEAR(c.output_sum, 50);                                                                    \
        assert_int_equal(P##set_output_limits(&c, 55, 80), MS_OK); /* and from below */           \
        NEAR(out, 55);                                                                             \
        NEAR(c.output_sum, 55);                                                                    \
        /* MANUAL: the limits are stored, nothing is clamped */                                   \
        P##set_mode(&c, PID_MANUAL);                                                               \
        out = 10;                                                                                  \
        assert_int_equal(P##set_output_limits(&c, 20, 90), MS_OK);                                 \
        NEAR(out, 10);                                                                             \
        NEAR(c.output_sum, 55);                                                                    \
        NEAR(c.out_min, 20);                                                                       \
        assert_int_equal(P##set_output_limits(&c, -100, 30), MS_OK);                               \
        NEAR(c.output_sum, 55); /* above the new max: still not clamped in MANUAL */               \
        out = 35;                                                                                  \
        P##set_mode(&c, PID_AUTOMATIC); /* Initialize: sum = clamp(35) = 30; Output stays 35 */    \
        NEAR(c.output_sum, 30);                                                                    \
        NEAR(out, 35);                                                                             \
        sp = 0; /* error 0: the computation only clamps */                                         \
        assert_int_equal(P##compute(&c, 20), 1);                                                   \
        NEAR(out, 30);                                                                             \
    }

HELD_BACK_TESTS(double, pid_, pid_ctrl_t, double)
HELD_BACK_TESTS(float, pidf_, pidf_ctrl_t, float)

#define MAX_VECTORS 64

static int add_dir(const char *dir, char kind, struct CMUnitTest *tests, char specs[][600], size_t *n)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int found = 0;
    if (d == NULL)
        return 0;
    while ((e = readdir(d)) != NULL && *n < MAX_VECTORS) {
        size_t len = strlen(e->d_name);
        if (len > 4 && strcmp(e->d_name + len - 4, ".csv") == 0) {
            snprintf(specs[*n], 600, "%c:%s/%s", kind, dir, e->d_name);
            tests[*n].name = specs[*n];
            tests[*n].test_func = replay_vector;
            tests[*n].setup_func = NULL;
            tests[*n].teardown_func = NULL;
            tests[*n].initial_state = specs[*n];
            (*n)++;
            found++;
        }
    }
    closedir(d);
    return found;
}

/* The five shared scenarios must all be here in both precisions (a missing data folder must
 * fail, not pass with zero replays). */
static void vector_set_is_complete(void **state)
{
    static const char *const names[] = {"a_p_only", "b_pid_windup", "e_manual_auto", "g_irregular_calls", "h_invalid_args"};
    size_t i;
    char path[600];
    (void)state;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        FILE *f;
        snprintf(path, sizeof path, "%s/%s.csv", data_dir(), names[i]);
        f = fopen(path, "r");
        if (f == NULL)
            fail_msg("missing %s", path);
        fclose(f);
        snprintf(path, sizeof path, "%s/float32/%s.csv", data_dir(), names[i]);
        f = fopen(path, "r");
        if (f == NULL)
            fail_msg("missing %s", path);
        fclose(f);
    }
}

static int by_name(const void *a, const void *b)
{
    return strcmp(((const struct CMUnitTest *)a)->name, ((const struct CMUnitTest *)b)->name);
}

int main(void)
{
    static struct CMUnitTest tests[MAX_VECTORS + 24];
    static char specs[MAX_VECTORS][600];
    char f32[600];
    size_t n = 0;
    const struct CMUnitTest fixed[] = {
        cmocka_unit_test(vector_set_is_complete),
        cmocka_unit_test(rejects_negative_gains_whole_call),
        cmocka_unit_test(zero_gains_are_accepted),
        cmocka_unit_test(rejects_limits_min_not_below_max),
        cmocka_unit_test(rejects_sample_time_not_positive),
        cmocka_unit_test(float_build_rejects_the_same),
        cmocka_unit_test(init_rejects_null_and_negative_gains),
        cmocka_unit_test(negative_constructor_gain_leaves_pon_as_p_on_m),
        cmocka_unit_test(unvalidated_values_behave_as_pid_v1),
        cmocka_unit_test(clock_wraps_without_a_gap),
        cmocka_unit_test(direction_in_manual_waits_for_set_tunings_double),
        cmocka_unit_test(direction_in_manual_waits_for_set_tunings_float),
        cmocka_unit_test(reverse_and_direction_changes_in_automatic_double),
        cmocka_unit_test(reverse_and_direction_changes_in_automatic_float),
        cmocka_unit_test(set_output_limits_clamps_at_once_only_in_automatic_double),
        cmocka_unit_test(set_output_limits_clamps_at_once_only_in_automatic_float),
    };
    size_t i;
    add_dir(data_dir(), 'd', tests, specs, &n);
    snprintf(f32, sizeof f32, "%s/float32", data_dir());
    add_dir(f32, 'f', tests, specs, &n);
    qsort(tests, n, sizeof tests[0], by_name);
    for (i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        tests[n++] = fixed[i];
    return _cmocka_run_group_tests("pidv1_ctrl", tests, n, NULL, NULL);
}
