/* Unit tests: smooth_move - the filter-shaped move (the moving-average-filter note's velocity command through its
 * two moving averages, "S-curve acceleration"), its step times and step commands.
 * Golden data, derived here independently of lib/: a step of the command by c at time s moves
 * the position by c P(t - s), P the unit step through the two moving averages integrated once,
 *   P(t) = [r(t) - r(t - tau1) - r(t - tau2) + r(t - tau1 - tau2)] / (tau1 tau2),  r(x) = max(x,0)^3/6
 * (the note's filters are convolutions with boxes of unit area; three integrations of a box
 * difference), in long double, and step n's time by bisection on it. The velocity of the law is
 * also checked against ma2_filter's samples of the same command (the sampled filter, exact at
 * the samples, tested on its own in test_ma2_filter.c). The rectangle for a distance R is the
 * documented rule (smooth_move.h); the bounds (distance R, acceleration <= accel, jerk <= jerk,
 * reached for long moves) are checked on the closed form and on the lib's law. */
#include "cmocka_all.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ma2_filter.h"
#include "smooth_move.h"
#include "step_exact.h" /* step_exact_cmd_time16: a command's time in the executor's sums, as an engine counts what it drops */
#include "step_queue.h"

#include "closed_form.h" /* urand/lrand */

/* ---- the closed form ---- */

/* quadruple precision where the compiler has it: near the end of a move the position
 * approaches its target as the cube of the time left, so finding the last step's time to a tick
 * needs the position to about 1e-20 of the distance */
#if defined(__SIZEOF_FLOAT128__)
__extension__ typedef __float128 q_t;
#else
typedef long double q_t;
#endif

#define MAXC 8
typedef struct {
    q_t tau1, tau2;       /* s */
    q_t s[MAXC], c[MAXC]; /* command changes: at s (s) by c (steps/s); the area h T of a
                             rectangle must be exact to ~1e-30 for the last step's time */
    int n;
} model_t;

/* d-th derivative (0..3) of r(x) = max(x,0)^3/6 */
static q_t rd(int d, q_t x)
{
    if (x <= 0)
        return 0;
    return d == 0 ? x * x * x / 6 : d == 1 ? x * x / 2 : d == 2 ? x : 1;
}

/* the d-th derivative of P; past t1 + t2 in the form without cancellation (position
 * t - (t1 + t2)/2, velocity 1, acceleration and jerk 0: the box difference integrated) */
static q_t kern(int d, q_t t, q_t t1, q_t t2)
{
    if (t >= t1 + t2)
        return d == 0 ? t - (t1 + t2) / 2 : d == 1 ? 1 : 0;
    return (rd(d, t) - rd(d, t - t1) - rd(d, t - t2) + rd(d, t - t1 - t2)) / (t1 * t2);
}

static q_t m_der(const model_t *m, int d, q_t t)
{
    q_t p = 0;
    int i;
    for (i = 0; i < m->n; i++)
        p += m->c[i] * kern(d, t - m->s[i], m->tau1, m->tau2);
    return p;
}
static long double m_pos(const model_t *m, long double t) { return (long double)m_der(m, 0, t); }
static long double m_vel(const model_t *m, long double t) { return (long double)m_der(m, 1, t); }
static long double m_acc(const model_t *m, long double t) { return (long double)m_der(m, 2, t); }
static long double m_jerk(const model_t *m, long double t) { return (long double)m_der(m, 3, t); }
static q_t m_endq(const model_t *m)
{
    q_t e = 0;
    int i;
    for (i = 0; i < m->n; i++)
        if (m->s[i] + m->tau1 + m->tau2 > e)
            e = m->s[i] + m->tau1 + m->tau2;
    return e;
}
static long double m_end(const model_t *m) { return (long double)m_endq(m); }

/* the first time after lo (where the position is below n) at which it reaches n: Newton,
 * bisection when a step leaves the bracket, to 1e-16 s */
static long double m_time_of(const model_t *m, long double n, long double lo_in)
{
    q_t lo = lo_in, hi = m_endq(m), t, f, v, tn;
    int i;
    if (m_der(m, 0, hi) <= (q_t)n)
        return (long double)hi;
    v = m_der(m, 1, lo);
    t = v > 0 ? lo + ((q_t)n - m_der(m, 0, lo)) / v : (lo + hi) / 2;
    if (!(t > lo && t < hi))
        t = (lo + hi) / 2;
    for (i = 0; i < 400; i++) {
        f = m_der(m, 0, t) - (q_t)n;
        if (f >= 0)
            hi = t;
        else
            lo = t;
        v = m_der(m, 1, t);
        tn = v > 0 ? t - f / v : (lo + hi) / 2;
        if (!(tn > lo && tn < hi))
            tn = (lo + hi) / 2;
        if ((tn > t ? tn - t : t - tn) < (q_t)1e-16L || hi - lo < (q_t)1e-16L)
            return (long double)tn;
        t = tn;
    }
    return (long double)t;
}

/* the documented rectangle for distance r */
static void rule(q_t vmax, q_t t1, q_t t2, q_t r, q_t *h, q_t *len)
{
    if (r >= vmax * (t1 + t2) || r <= vmax * (t1 - t2)) {
        *h = vmax;
        *len = r / vmax;
    } else {
        *len = t1 + t2;
        *h = r / (t1 + t2);
    }
}

/* The largest |jerk| of the model after time a: its value on each piece between the windows' ends
 * (a change at s: +c/(tau1 tau2) on [s, s + tau2), -c/(tau1 tau2) on [s + tau1, s + tau1 + tau2)). */
static q_t m_jerk_max_after(const model_t *m, q_t a)
{
    q_t pts[4 * MAXC + 2], worst = 0, d[4];
    int n = 0, i, k, j;
    d[0] = 0;
    d[1] = m->tau2;
    d[2] = m->tau1;
    d[3] = m->tau1 + m->tau2;
    pts[n++] = a;
    for (i = 0; i < m->n; i++)
        for (k = 0; k < 4; k++)
            if (m->s[i] + d[k] > a)
                pts[n++] = m->s[i] + d[k];
    for (i = 1; i < n; i++) /* insertion sort */
        for (j = i; j > 0 && pts[j - 1] > pts[j]; j--) {
            q_t t = pts[j];
            pts[j] = pts[j - 1];
            pts[j - 1] = t;
        }
    pts[n] = pts[n - 1] + 1;
    for (i = 0; i < n; i++) {
        q_t v;
        if (!(pts[i + 1] - pts[i] > (q_t)1e-7L))
            continue; /* windows that meet, a rounding apart (smooth_move.c does not judge those either) */
        v = m_der(m, 3, (pts[i] + pts[i + 1]) / 2);
        if (v < 0)
            v = -v;
        if (v > worst)
            worst = v;
    }
    return worst;
}

/* The model's stop or new target at ts, as smooth_move.h states it (written here from that text):
 * the changes after ts dropped; the new change(s) at the earliest of ts and the ends of the kept
 * changes' windows after ts from which |jerk| stays within J = vmax/(tau1 tau2) (else at ts); a new
 * target's rectangle for the distance from where a stop at that time comes to rest. goal < 0: a
 * stop. Returns 0 (nothing changed) when the target is behind the rest point of a stop at ts, could
 * only start once the plan has come to rest, or no time keeps it within J (the planner then stops
 * and moves from rest). */
static int m_event(model_t *m, q_t ts, q_t vmax, q_t goal)
{
    q_t u = 0, cand[3 * MAXC + 1], d[3], lim = vmax / (m->tau1 * m->tau2) * (1 + 0x1p-20L);
    model_t kept = *m, trial, first;
    int i, k, nc = 0, j, have_first = 0;
    kept.n = 0;
    for (i = 0; i < m->n; i++)
        if (m->s[i] <= ts) {
            u += m->c[i];
            kept.s[kept.n] = m->s[i];
            kept.c[kept.n++] = m->c[i];
        }
    d[0] = m->tau2;
    d[1] = m->tau1;
    d[2] = m->tau1 + m->tau2;
    cand[nc++] = ts;
    for (i = 0; i < kept.n; i++)
        for (k = 0; k < 3; k++)
            if (kept.s[i] + d[k] > ts)
                cand[nc++] = kept.s[i] + d[k];
    for (i = 2; i < nc; i++) /* sort the ends (ts stays first) */
        for (j = i; j > 1 && cand[j - 1] > cand[j]; j--) {
            q_t t = cand[j];
            cand[j] = cand[j - 1];
            cand[j - 1] = t;
        }
    for (k = 0; k < nc; k++) {
        q_t e = cand[k];
        if (goal >= 0 && u == 0 && k > 0 && e >= m_endq(&kept) * (1 - 1e-15L))
            return 0; /* only once the plan has come to rest: a move from rest after it */
        trial = kept;
        if (u != 0) {
            trial.s[trial.n] = e;
            trial.c[trial.n++] = -u;
        }
        if (goal >= 0) {
            q_t r = goal - m_der(&trial, 0, m_endq(&trial)), h, len;
            if (r < 0) {
                if (k == 0)
                    return 0;
                continue;
            }
            rule(vmax, m->tau1, m->tau2, r, &h, &len);
            trial = kept;
            if (h != u) {
                trial.s[trial.n] = e;
                trial.c[trial.n++] = h - u;
            }
            if (h != 0) {
                trial.s[trial.n] = e + len;
                trial.c[trial.n++] = -h;
            }
        }
        if (!have_first) {
            first = trial;
            have_first = 1;
        }
        if (m_jerk_max_after(&trial, ts) <= lim) {
            *m = trial;
            return 1;
        }
    }
    if (goal >= 0)
        return 0; /* no time keeps the new target within J: a stop, then a move from rest */
    *m = first;
    return 1;
}

/* The command's level at ts: the sum of the changes at or before it. */
static q_t m_level(const model_t *m, q_t ts)
{
    q_t u = 0;
    int i;
    for (i = 0; i < m->n; i++)
        if (m->s[i] <= ts)
            u += m->c[i];
    return u;
}

/* Where a stop at ts comes to rest if it acts at ts (the changes after ts dropped, the level to 0
 * there): what a new target is measured from. */
static q_t m_stop_point(const model_t *m, q_t ts)
{
    model_t st = *m;
    q_t u = m_level(m, ts);
    int i;
    st.n = 0;
    for (i = 0; i < m->n; i++)
        if (m->s[i] <= ts) {
            st.s[st.n] = m->s[i];
            st.c[st.n++] = m->c[i];
        }
    if (u != 0) {
        st.s[st.n] = ts;
        st.c[st.n++] = -u;
    }
    return m_der(&st, 0, m_endq(&st));
}

/* The model's stop at ts (m_event's rule) for a move of d steps; returns where it comes to rest
 * (a stop after the command has gone to 0 changes nothing: the move ends at d). */
static long double m_stop(model_t *m, q_t ts, q_t vmax, long double d)
{
    q_t u = m_level(m, ts);
    (void)m_event(m, ts, vmax, -1);
    return u == 0 ? d : m_pos(m, m_end(m));
}

/* a long double as the lib's smx_t (m x 2^e, 2^61 <= |m| < 2^62) */
static smx_t smx_from_double_ticks(long double t)
{
    smx_t x;
    int e = 0;
    long double fm = frexpl(t, &e);
    if (t == 0)
        return smx_from_i64(0);
    x.m = (int64_t)ldexpl(fm, 62);
    x.e = (int16_t)(e - 62);
    return x;
}

/* The last whole step of a stop that comes to rest at `rest`: floor(rest), or the whole step it is
 * on within 2^-50 of its size (smooth_move.c counts such a rest as on that step: its own arithmetic
 * cannot tell them apart). */
static long double whole_steps(long double rest)
{
    long double n = roundl(rest);
    return fabsl(rest - n) <= fabsl(rest) * 0x1p-50L ? n : floorl(rest);
}

/* ---- running the planner through the executor ---- */

/* |acc - F t_n| allowed: the planner's budget (0.9 tick) and the terms beyond its quartic bound, which
 * its Newton check keeps to a few hundredths; below 1, so every edge is within 1 tick of round(F t_n) */
#define CONT_MAX 0.95L

typedef struct {
    int64_t acc16; /* absolute 2^-16 ticks */
    uint32_t steps;
    long double worst; /* |edge - round(F t_n)| in ticks */
    long double worst_cont; /* |acc - F t_n| in ticks (acc before the floor) of the steps of normal
                               commands: the planner's budget is 0.9 (below 1, which keeps the edge
                               within 1 tick of round(F t_n): the engine's timeline starts half a tick
                               in, so the edge is floor(acc + 1/2)); WIDE steps are rounded to the
                               nearest whole tick (1/2 at most) */
    uint32_t checked, commands;
    int32_t pos;
} run_t;

/* executes c: checks step edges against the model (frame steps n0+1..), every step when
 * check_all, else the first, middle and last of the command (their times by the executor's
 * own sums in closed form: acc_j = acc_0 + j rate + j (j - 1)/2 add) */
static void check_edge(run_t *r, int64_t acc16, const model_t *m, long double f, uint32_t n, long double t_off,
                       long double *t_prev, int wide)
{
    long double tn = m_time_of(m, (long double)n, *t_prev);
    long double want = roundl(f * (tn + t_off));
    long double d = fabsl((long double)((acc16 + 0x8000) >> 16) - want); /* the edge, half a tick in */
    long double dc = fabsl((long double)acc16 / 65536.0L - f * (tn + t_off));
    if (wide)
        dc -= 0.05L + 1.0L / 2048; /* rounded to whole ticks from a time solved to 2^-12 tick */
    if (dc > CONT_MAX && getenv("SMDEBUG"))
        printf("# step %u: |acc - F t_n| %.6Lf tick%s\n", n, dc, wide ? " (WIDE, less 0.05)" : "");
    if (dc > r->worst_cont)
        r->worst_cont = dc;
    if (d > 1 && getenv("SMDEBUG"))
        printf("# step %u edge %lld want %.1Lf tn %.9Lf\n", n, (long long)((acc16 + 0x8000) >> 16), want, tn);
    if (d > r->worst)
        r->worst = d;
    r->checked++;
    *t_prev = tn;
}

static void run_cmd(run_t *r, const step_cmd_t *c, const model_t *m, long double f, uint32_t n0, long double t_off,
                    int check_all, long double *t_prev)
{
    uint32_t j;
    int64_t rate = c->rate, add = c->add;
    int dir = (c->flags & STEP_CMD_REVERSE) ? -1 : 1;
    if (c->flags & STEP_CMD_WIDE) {
        r->acc16 += rate << 16;
        check_edge(r, r->acc16, m, f, n0 + 1, t_off, t_prev, 1);
    } else if (check_all) {
        for (j = 1; j <= c->count; j++) {
            r->acc16 += rate;
            rate += add;
            check_edge(r, r->acc16, m, f, n0 + j, t_off, t_prev, 0);
        }
    } else {
        uint32_t pick[3];
        int q;
        int64_t cnt = c->count;
        pick[0] = 1;
        pick[1] = c->count / 2 ? c->count / 2 : 1;
        pick[2] = c->count;
        for (q = 0; q < 3; q++) {
            int64_t jj = pick[q];
            if (q > 0 && pick[q] == pick[q - 1])
                continue;
            check_edge(r, r->acc16 + jj * rate + jj * (jj - 1) / 2 * add, m, f, n0 + pick[q], t_off, t_prev, 0);
        }
        r->acc16 += cnt * rate + cnt * (cnt - 1) / 2 * add;
    }
    r->pos += dir * (int32_t)c->count;
    r->steps += c->count;
    r->commands++;
}

static smooth_params_t params(double vmax, double accel, double jerk, uint32_t f)
{
    smooth_params_t p;
    /* through volatile floats: gcc 12 -O2 dropped the (float) rounding of these doubles here */
    volatile float v = (float)vmax, a = (float)accel, j = (float)jerk;
    p.vmax_sps = v;
    p.accel_sps2 = a;
    p.jerk_sps3 = j;
    p.tick_hz = f;
    return p;
}

static void model_move(model_t *m, const smooth_params_t *p, long double d)
{
    q_t vmax = (float)p->vmax_sps, a = (float)p->accel_sps2, j = (float)p->jerk_sps3, h, len;
    m->tau1 = vmax / a;
    m->tau2 = a / j;
    rule(vmax, m->tau1, m->tau2, d, &h, &len);
    m->n = 2;
    m->s[0] = 0;
    m->c[0] = h;
    m->s[1] = len;
    m->c[1] = -h;
}

/* A move of d steps (its sign: the direction) from `from`, which s stands at: the model's law, a
 * clear run at `from`, and the move asked of s (which must take it). */
static void start_move(smooth_move_t *s, model_t *m, run_t *r, const smooth_params_t *p, int32_t from, int64_t d)
{
    model_move(m, p, (long double)(d < 0 ? -d : d));
    memset(r, 0, sizeof *r);
    r->pos = from;
    assert_int_equal(smooth_move_to(s, (int32_t)(from + d)), MS_OK);
}

/* ---- tests ---- */

/* The law's velocity at t = k Ts equals ma2_filter's y[k] for the same rectangle (tau1 = 50 Ts,
 * tau2 = 25 Ts, a 1000 steps/s command held 200 samples): the note's filter, sampled. */
static void law_velocity_is_the_ma2_filter_s_output(void **state)
{
    smooth_params_t p = params(1000, 2000, 8000, 1000); /* tau1 0.5 s, tau2 0.25 s, F = 1 kHz: Ts = 10 ticks */
    smooth_law_t law;
    ma2_filter_t f;
    int16_t buf[75];
    int k;
    (void)state;
    assert_int_equal(smooth_law_set_params(&law, &p), MS_OK);
    smooth_law_reset(&law, 0);
    assert_int_equal(smooth_law_start(&law, 2000), MS_OK); /* 2000 steps at 1000 steps/s: 2 s = 200 samples */
    assert_int_equal(ma2_filter_init(&f, buf, 75, 50, 25), MS_OK);
    for (k = 0; k < 300; k++) {
        double v;
        int64_t num = ma2_filter_step(&f, (int16_t)(k < 200 ? 1000 : 0));
        double y = (double)num / ma2_filter_den(&f);
        smooth_law_eval(&law, smx_from_i64(10 * k), NULL, &v, NULL, NULL);
        assert_true(fabs(v - y) <= 1e-9 * 1000);
    }
}

/* Distance, peak acceleration and jerk on the lib's law and the closed form: long moves reach
 * accel and jerk and never exceed them; short ones (all three rectangle cases) stay below. */
static void distance_and_peaks(void **state)
{
    int trial;
    (void)state;
    for (trial = 0; trial < 200; trial++) {
        double vmax = lrand(10, 40000), accel = lrand(vmax / 20, vmax * 20);
        double jerk = lrand(accel * accel / vmax, accel * accel / vmax * 50);
        smooth_params_t p = params(vmax, accel, jerk, 16000000);
        smooth_law_t law;
        model_t m;
        long double d, end, amax = 0, jmax = 0, vpk = 0, t;
        int i, reached;
        if (smooth_law_set_params(&law, &p) != MS_OK)
            continue;
        d = floorl(lrand(1, 3e6));
        model_move(&m, &p, d);
        smooth_law_reset(&law, 0);
        assert_int_equal(smooth_law_start(&law, (int32_t)d), MS_OK);
        end = m_end(&m);
        for (i = 0; i <= 1000; i++) {
            double pl, vl, al, jl;
            t = end * i / 1000;
            smooth_law_eval(&law, smx_from_double_ticks(t * 16e6L), &pl, &vl, &al, &jl);
            assert_true(fabsl(pl - m_pos(&m, t)) <= 1e-6 * (1 + d));
            assert_true(fabsl(vl - m_vel(&m, t)) <= 1e-6 * vmax);
                if (fabsl(m_acc(&m, t)) > amax)
                amax = fabsl(m_acc(&m, t));
            if (fabsl(al) > amax)
                amax = fabsl(al);
            if (fabsl(m_jerk(&m, t)) > jmax)
                jmax = fabsl(m_jerk(&m, t));
            if (m_vel(&m, t) > vpk)
                vpk = m_vel(&m, t);
        }
        assert_true(fabsl(m_pos(&m, end) - d) <= 1e-9L * d);
        assert_true(amax <= p.accel_sps2 * (1 + 1e-6));
        assert_true(jmax <= p.jerk_sps3 * (1 + 1e-6));
        if (!(vpk <= p.vmax_sps * (1 + 1e-9)))
            printf("# vpk %.12Lg vmax %.12g d %.0Lf accel %.9g jerk %.9g h %.12Lg T %.12Lg\n", vpk, (double)p.vmax_sps, d, accel, jerk, (long double)m.c[0], (long double)m.s[1]);
        assert_true(vpk <= p.vmax_sps * (1 + 1e-9));
        reached = d >= (long double)p.vmax_sps * (long double)(m.tau1 + m.tau2) + 1;
        if (reached) { /* at t = tau1 (acceleration) and tau2/2 (jerk), from the law */
            double al, jl;
            smooth_law_eval(&law, smx_from_double_ticks(m.tau1 * 16e6L), NULL, NULL, &al, NULL);
            smooth_law_eval(&law, smx_from_double_ticks(m.tau2 * 8e6L), NULL, NULL, NULL, &jl);
            if (fabsl(m_acc(&m, m.tau1)) > amax)
                amax = fabsl(m_acc(&m, m.tau1));
            if (fabsl(m_jerk(&m, m.tau2 / 2)) > jmax)
                jmax = fabsl(m_jerk(&m, m.tau2 / 2));
            assert_true(fabs(al - p.accel_sps2) <= 1e-6 * p.accel_sps2);
            assert_true(fabs(jl - p.jerk_sps3) <= 1e-6 * p.jerk_sps3);
            assert_true(amax >= p.accel_sps2 * (1 - 1e-6));
            assert_true(jmax >= p.jerk_sps3 * (1 - 1e-6));
        }
        {
            double pe;
            smooth_law_eval(&law, smx_from_double_ticks(end * 16e6L + 1), &pe, NULL, NULL, NULL);
            assert_true(pe == d);
        }
    }
}

/* Every step edge within 1 tick of round(F t_n), random moves of 1 .. 3 million steps. */
static void every_edge_within_one_tick(void **state)
{
    int trial;
    long double worst = 0, worst_cont = 0;
    (void)state;
    for (trial = 0; trial < 70; trial++) {
        double vmax = lrand(50, 60000), accel = lrand(vmax / 10, vmax * 40);
        double jerk = lrand(accel * accel / vmax, accel * accel / vmax * 100);
        smooth_params_t p = params(vmax, accel, jerk, 16000000);
        smooth_move_t s;
        step_cmd_t c;
        model_t m;
        run_t r;
        long double tp = 0;
        int32_t d = trial < 10 ? trial + 1 : (int32_t)lrand(1, trial < 60 ? 5000 : fmin(3e6, vmax * 60)); /* <= 60 s */
        int32_t from = (int32_t)urand(-1000, 1000);
        int dir = trial % 3 == 0 ? -1 : 1;
        if (smooth_move_init(&s, &p, from) != MS_OK)
            continue;
        start_move(&s, &m, &r, &p, from, (int64_t)dir * d);
        while (smooth_move_next(&s, &c)) {
            assert_true(c.count >= 1);
            assert_int_equal((c.flags & STEP_CMD_REVERSE) != 0, dir < 0);
            run_cmd(&r, &c, &m, 16e6L, r.steps, 0, d <= 5000, &tp);
        }
        assert_int_equal(r.steps, (uint32_t)d);
        assert_int_equal(r.pos, from + dir * d);
        assert_int_equal(smooth_move_position(&s), from + dir * d);
        assert_false(smooth_move_busy(&s));
        if (r.worst > worst)
            worst = r.worst;
        if (r.worst > 1 || r.worst_cont > CONT_MAX)
            printf("# vmax %.9g accel %.9g jerk %.9g d %d: %.3Lf tick\n", vmax, accel, jerk, d, r.worst_cont);
        assert_true(r.worst <= 1);
        assert_true(r.worst_cont <= CONT_MAX);
        if (r.worst_cont > worst_cont)
            worst_cont = r.worst_cont;
    }
    printf("# every_edge_within_one_tick: worst %.0Lf tick, |acc - F t_n| up to %.3Lf tick\n", worst, worst_cont);
}

/* The longest move, 2^31 - 1 steps: commands stay within 1 tick (checked at each command's first,
 * middle and last step), the last step is the target. */
static void longest_move(void **state)
{
    smooth_params_t p = params(50000, 200000, 2e6, 16000000);
    smooth_move_t s;
    step_cmd_t c;
    model_t m;
    run_t r;
    long double tp = 0;
    (void)state;
    assert_int_equal(smooth_move_init(&s, &p, INT32_MIN / 2), MS_OK);
    s.max_cmd_ticks = 1UL << 24; /* 1 s per command: spans up to 32768 steps, to keep the test short (the reviewer of 2026-12-05 ran every edge of it with the 4 ms commands: none beyond 1 tick) */
    start_move(&s, &m, &r, &p, INT32_MIN / 2, INT32_MAX);
    /* every edge of the first and the last 20,000 steps (where the law bends most and commands are
     * short), three of each command in between */
    while (smooth_move_next(&s, &c))
        run_cmd(&r, &c, &m, 16e6L, r.steps, 0, r.steps < 20000U || r.steps > 2147483647U - 20000U - c.count, &tp);
    assert_int_equal(r.steps, 2147483647U);
    assert_true(r.worst <= 1);
    assert_true(r.worst_cont <= CONT_MAX);
    printf("# longest_move: %u commands, worst %.0Lf tick, |acc - F t_n| up to %.3Lf tick\n", r.commands, r.worst,
           r.worst_cont);
}

/* Stop: the command goes to 0 at the last step handed out; the steps after it follow the
 * closed form of that command (every edge within 1 tick), the motion ends at the last whole step
 * before where the closed form comes to rest, and never exceeds accel or jerk. */
static void stop_follows_the_zeroed_command(void **state)
{
    int trial;
    (void)state;
    for (trial = 0; trial < 50; trial++) {
        double vmax = lrand(100, 30000), accel = lrand(vmax / 5, vmax * 20);
        double jerk = lrand(accel * accel / vmax, accel * accel / vmax * 20);
        smooth_params_t p = params(vmax, accel, jerk, 16000000);
        smooth_move_t s;
        step_cmd_t c;
        model_t m;
        run_t r;
        long double tp = 0, ts, rest, t;
        int32_t d = (int32_t)lrand(10, 5000);
        uint32_t stop_after;
        int i;
        if (smooth_move_init(&s, &p, 0) != MS_OK)
            continue;
        start_move(&s, &m, &r, &p, 0, d);
        stop_after = (uint32_t)urand(1, d);
        while (r.steps < stop_after && smooth_move_next(&s, &c))
            run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
        if (r.steps >= (uint32_t)d)
            continue;
        ts = m_time_of(&m, r.steps, 0); /* the last step handed out */
        /* the model: future changes dropped, the level to 0 (at ts or when that keeps the jerk within J) */
        rest = m_stop(&m, ts, (float)p.vmax_sps, d);
        smooth_move_stop(&s);
        assert_int_equal(smooth_move_target(&s), (int32_t)whole_steps(rest));
        while (smooth_move_next(&s, &c))
            run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
        assert_true(r.worst <= 1);
        assert_true(r.worst_cont <= CONT_MAX);
        assert_int_equal(r.steps, (uint32_t)whole_steps(rest));
        for (i = 0; i <= 2000; i++) {
            t = m_end(&m) * i / 2000;
            assert_true(fabsl(m_acc(&m, t)) <= p.accel_sps2 * (1 + 1e-9));
            assert_true(m_vel(&m, t) >= -1e-9);
        }
        /* a stop keeps the jerk within its limit wherever it comes (the model follows the edges) */
        assert_true(m_jerk_max_after(&m, 0) <= (q_t)p.jerk_sps3 * (1 + 1e-6L));
    }
}

/* A stop in the cruise comes to rest vmax (tau1 + tau2)/2 steps beyond the step where it is given
 * (the command's area still in the filters): when that is a whole number, the rest is a whole step,
 * and the stop makes that step, at the end of the law (the reviewer's case of 2026-12-05: 50,000
 * steps/s, stopped at step 5039, rest 8164, ended at 8163 because the law's arithmetic put the rest
 * 2e-15 step below it). */
static void stop_on_a_whole_step_makes_it(void **state)
{
    static const double cases[][4] = {/* vmax, accel, jerk, steps before the stop */
                                      {50000, 500000, 20000000, 5000}, {20000, 40000, 400000, 12000},
                                      {1000, 2000, 8000, 1500}, {50000, 400000, 3200000, 30000}};
    unsigned k;
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        smooth_params_t p = params(cases[k][0], cases[k][1], cases[k][2], 16000000);
        long double beyond = (long double)p.vmax_sps * (p.vmax_sps / p.accel_sps2 + p.accel_sps2 / p.jerk_sps3) / 2;
        smooth_move_t s;
        step_cmd_t c;
        int32_t n;
        assert_int_equal(smooth_move_init(&s, &p, 0), MS_OK);
        assert_int_equal(smooth_move_to(&s, 1000000), MS_OK);
        while (smooth_move_position(&s) < (int32_t)cases[k][3])
            assert_true(smooth_move_next(&s, &c));
        n = smooth_move_position(&s);
        assert_true(fabsl(beyond - roundl(beyond)) < 1e-9L); /* whole: the case is what it says */
        smooth_move_stop(&s);
        assert_int_equal(smooth_move_target(&s), n + (int32_t)roundl(beyond));
        while (smooth_move_next(&s, &c))
            ;
        assert_int_equal(smooth_move_position(&s), n + (int32_t)roundl(beyond));
    }
}

/* New target while moving: ahead of the stopping point, the command's future is a new rectangle
 * from now (the rule for the distance left beyond the stopping point): edges within 1 tick of
 * that closed form, the target reached exactly, acceleration within accel; behind it: a stop,
 * then a move from rest back to it. */
static void new_target_continues_from_the_filter_state(void **state)
{
    int trial, reversed = 0, ahead = 0;
    (void)state;
    for (trial = 0; trial < 80; trial++) {
        double vmax = lrand(100, 30000), accel = lrand(vmax / 5, vmax * 20);
        double jerk = lrand(accel * accel / vmax, accel * accel / vmax * 20);
        smooth_params_t p = params(vmax, accel, jerk, 16000000);
        smooth_move_t s;
        step_cmd_t c;
        model_t m;
        run_t r;
        long double tp = 0, ts;
        q_t stop_at;
        int32_t d = (int32_t)lrand(10, 5000), d2;
        uint32_t at;
        int i;
        if (smooth_move_init(&s, &p, 0) != MS_OK)
            continue;
        start_move(&s, &m, &r, &p, 0, d);
        at = (uint32_t)urand(1, d);
        while (r.steps < at && smooth_move_next(&s, &c))
            run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
        if (r.steps >= (uint32_t)d)
            continue;
        ts = m_time_of(&m, r.steps, 0);
        stop_at = m_stop_point(&m, ts);
        d2 = (int32_t)(trial % 4 == 0 ? urand(-1000, (double)stop_at - 1) : ceill((long double)stop_at) + lrand(1, 6000));
        assert_int_equal(smooth_move_to(&s, d2), MS_OK);
        assert_int_equal(smooth_move_target(&s), d2);
        if (d2 < stop_at || !m_event(&m, ts, (float)p.vmax_sps, d2)) { /* stop, then (back) from rest */
            reversed++;
            while (smooth_move_next(&s, &c))
                r.pos += (c.flags & STEP_CMD_REVERSE) ? -(int32_t)c.count : (int32_t)c.count;
            assert_int_equal(r.pos, d2);
            assert_int_equal(smooth_move_position(&s), d2);
            continue;
        }
        ahead++;
        while (smooth_move_next(&s, &c))
            run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
        if (r.worst > 1 || r.worst_cont > CONT_MAX)
            printf("# vmax %.9g accel %.9g jerk %.9g d %d at %u d2 %d: %.3Lf tick\n", p.vmax_sps, p.accel_sps2,
                   p.jerk_sps3, d, at, d2, r.worst_cont);
        assert_true(r.worst <= 1);
        assert_true(r.worst_cont <= CONT_MAX);
        assert_int_equal(r.steps, (uint32_t)d2);
        assert_true(fabsl(m_pos(&m, m_end(&m)) - d2) < 1e-6);
        for (i = 0; i <= 2000; i++) {
            long double t = m_end(&m) * i / 2000;
            assert_true(fabsl(m_acc(&m, t)) <= p.accel_sps2 * (1 + 1e-9));
            assert_true(m_vel(&m, t) <= p.vmax_sps * (1 + 1e-9));
        }
        /* a new target keeps the jerk within its limit (else it is a stop and a move from rest) */
        assert_true(m_jerk_max_after(&m, 0) <= (q_t)p.jerk_sps3 * (1 + 1e-6L));
    }
    printf("# new targets: %d ahead, %d by a stop and a move from rest\n", ahead, reversed);
    assert_true(reversed > 5 && ahead > 30);
}

/* A cut of the queue (smooth_move_rewind): commands handed out beyond a point are taken back, and
 * the stop, the new target or nothing (the move continues) is planned from the step where the kept
 * commands end. Every edge, kept and new, is then within a tick of the law of a planner that handed
 * out only the kept commands and did the same there (the model's stop or new target at that step's
 * time, as in the two tests above), the move ends where that law comes to rest, and the jerk stays
 * within its limit. */
static void rewind_then_stop_new_target_or_nothing(void **state)
{
    int trial, done[3] = {0, 0, 0};
    (void)state;
    for (trial = 0; trial < 90; trial++) {
        double vmax = lrand(100, 30000), accel = lrand(vmax / 5, vmax * 20);
        double jerk = lrand(accel * accel / vmax, accel * accel / vmax * 20);
        smooth_params_t p = params(vmax, accel, jerk, 16000000);
        smooth_move_t s;
        step_cmd_t c, dropped[64];
        model_t m;
        run_t r;
        long double tp = 0, ts, rest;
        int32_t d = (int32_t)lrand(50, 20000), goal = 0;
        uint32_t at, steps = 0;
        int64_t t16 = 0;
        int i, nd = 0, what = trial % 3; /* 0: stop, 1: new target, 2: nothing */
        if (smooth_move_init(&s, &p, 0) != MS_OK)
            continue;
        if (trial % 2)
            s.max_cmd_ticks = 16000; /* 1 ms commands; else lib's 4 ms, which the MotionStepper library keeps */
        start_move(&s, &m, &r, &p, 0, d);
        at = (uint32_t)urand(2, d);
        while (r.steps < at && smooth_move_next(&s, &c))
            run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
        /* handed out, then dropped: up to 40 commands more */
        nd = (int)urand(1, 40);
        for (i = 0; i < nd && smooth_move_next(&s, &dropped[i]); i++) {
            steps += dropped[i].count;
            t16 += step_exact_cmd_time16(&dropped[i]);
        }
        nd = i;
        if (nd == 0 || r.steps >= (uint32_t)d || !smooth_move_busy(&s))
            continue;
        assert_true(smooth_move_rewindable(&s) >= steps);
        {
            smooth_move_t before;
            memcpy(&before, &s, sizeof s);
            /* a time that is not the dropped commands': refused, nothing changed */
            assert_int_equal(smooth_move_rewind(&s, steps, t16 + 3 * 65536), MS_ERR_OUT_OF_RANGE);
            assert_int_equal(smooth_move_rewind(&s, smooth_move_rewindable(&s) + 1, t16), MS_ERR_OUT_OF_RANGE);
            assert_int_equal(smooth_move_rewind(&s, 0, 0), MS_ERR_OUT_OF_RANGE);
            assert_memory_equal(&s, &before, sizeof s);
        }
        assert_int_equal(smooth_move_rewind(&s, steps, t16), MS_OK);
        assert_int_equal(smooth_move_position(&s), (int32_t)r.steps);
        ts = m_time_of(&m, r.steps, 0); /* the last step kept */
        if (what == 0) {
            rest = m_stop(&m, ts, (float)p.vmax_sps, d);
            smooth_move_stop(&s);
            goal = (int32_t)whole_steps(rest);
        } else if (what == 1) {
            goal = (int32_t)ceill((long double)m_stop_point(&m, ts)) + (int32_t)lrand(1, 6000);
            if (!m_event(&m, ts, (float)p.vmax_sps, goal))
                continue; /* a stop and a move from rest: new_target_continues_from_the_filter_state's */
            assert_int_equal(smooth_move_to(&s, goal), MS_OK);
        } else {
            goal = d;
        }
        assert_int_equal(smooth_move_target(&s), goal);
        while (smooth_move_next(&s, &c))
            run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
        if (r.worst > 1 || r.worst_cont > CONT_MAX)
            printf("# rewind %d: vmax %.9g accel %.9g jerk %.9g d %d at %u dropped %u: %.3Lf tick\n", what, p.vmax_sps,
                   p.accel_sps2, p.jerk_sps3, d, at, steps, r.worst_cont);
        assert_true(r.worst <= 1);
        assert_true(r.worst_cont <= CONT_MAX);
        assert_int_equal(r.steps, (uint32_t)goal);
        assert_true(m_jerk_max_after(&m, 0) <= (q_t)p.jerk_sps3 * (1 + 1e-6L));
        done[what]++;
    }
    printf("# rewinds: %d stops, %d new targets, %d moves continued\n", done[0], done[1], done[2]);
    assert_true(done[0] > 15 && done[1] > 10 && done[2] > 15);
}

/* A stop given at the very step of a new target (no command handed out between) whose rectangle
 * started from a command already at 0 (in the final deceleration): the stop cancels that start, and
 * the move comes to rest where the old plan did, its last step at the law's time (the review of
 * 2026-12-05: the cancelled change's knots stayed, the law "ended" tau1 + tau2 later, and the last
 * step, on a whole rest, came 17 s late). */
static void stop_at_the_step_of_a_new_target(void **state)
{
    smooth_params_t p = params(555.187378, 29.7960758, 356.329437, 16000000);
    smooth_move_t s;
    step_cmd_t c;
    model_t m;
    run_t r;
    long double tp = 0, ts;
    (void)state;
    assert_int_equal(smooth_move_init(&s, &p, 0), MS_OK);
    s.max_cmd_ticks = 16000;
    start_move(&s, &m, &r, &p, 0, 3556);
    while (r.steps < 3527 && smooth_move_next(&s, &c))
        run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
    ts = m_time_of(&m, r.steps, 0);
    assert_int_equal(smooth_move_to(&s, 3558), MS_OK);
    assert_true(m_event(&m, ts, (float)p.vmax_sps, 3558));
    smooth_move_stop(&s);
    (void)m_event(&m, ts, (float)p.vmax_sps, -1);
    assert_int_equal(smooth_move_target(&s), 3556);
    while (smooth_move_next(&s, &c))
        run_cmd(&r, &c, &m, 16e6L, r.steps, 0, 1, &tp);
    assert_int_equal(r.steps, 3556);
    assert_true(r.worst <= 1); /* the last step too: at the model's time of step 3556 */
}

/* A rewind never reaches back before the law's last change: after a stop, only the steps handed out
 * since (less one) can be taken back, and at rest none. */
static void rewind_stays_after_the_last_change(void **state)
{
    smooth_params_t p = params(20000, 40000, 400000, 16000000);
    smooth_move_t s, before;
    step_cmd_t c;
    uint32_t since = 0;
    int64_t t16 = 0;
    int i;
    (void)state;
    assert_int_equal(smooth_move_init(&s, &p, 0), MS_OK);
    assert_int_equal(smooth_move_rewindable(&s), 0);
    assert_int_equal(smooth_move_rewind(&s, 1, 0), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(smooth_move_to(&s, 100000), MS_OK);
    for (i = 0; i < 50; i++)
        assert_true(smooth_move_next(&s, &c));
    smooth_move_stop(&s);
    assert_int_equal(smooth_move_rewindable(&s), 0);
    for (i = 0; i < 3; i++) {
        assert_true(smooth_move_next(&s, &c));
        since += c.count;
        t16 += step_exact_cmd_time16(&c);
    }
    assert_int_equal(smooth_move_rewindable(&s), since - 1);
    memcpy(&before, &s, sizeof s);
    assert_int_equal(smooth_move_rewind(&s, since, t16), MS_ERR_OUT_OF_RANGE);
    assert_memory_equal(&s, &before, sizeof s);
    while (smooth_move_next(&s, &c))
        ;
    assert_int_equal(smooth_move_rewindable(&s), 0);
}

/* Bad parameters: each refused with its own status, nothing changed. */
static void bad_parameters_refused(void **state)
{
    smooth_move_t s, before;
    smooth_params_t good = params(1000, 5000, 100000, 16000000), p;
    (void)state;
    assert_int_equal(smooth_move_init(&s, &good, 7), MS_OK);
    before = s;
    p = good;
    p.jerk_sps3 = 0;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_JERK_NOT_POSITIVE);
    p.jerk_sps3 = -5;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_JERK_NOT_POSITIVE);
    p.jerk_sps3 = NAN;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_NOT_FINITE);
    p = good;
    p.accel_sps2 = INFINITY;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_NOT_FINITE);
    p = good;
    p.jerk_sps3 = 5000.0 * 5000.0 / 1000.0 * 0.99; /* tau2 = 1.01 tau1 */
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_JERK_TOO_LOW);
    p.jerk_sps3 = 5000.0 * 5000.0 / 1000.0; /* tau2 = tau1: allowed */
    assert_int_equal(smooth_move_init(&before, &p, 7), MS_OK);
    p = good;
    p.accel_sps2 = 0;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_ACCEL_NOT_POSITIVE);
    p = good;
    p.vmax_sps = 0;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_VMAX_NOT_ABOVE_V0);
    p = good;
    p.vmax_sps = 2e7;
    p.jerk_sps3 = 1e12;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_VMAX_ABOVE_TICK_HZ);
    p = good;
    p.tick_hz = 0;
    assert_int_equal(smooth_move_set_params(&s, &p), MS_ERR_TICK_HZ_ZERO);
    p = params(1000, 1e-6, 1e-6, 16000000); /* tau1 = 1e9 s */
    assert_int_equal(smooth_move_init(&s, &p, 0), MS_ERR_ACCEL_PHASE_TOO_LONG);
    assert_int_equal(smooth_move_init(NULL, &good, 0), MS_ERR_NULL);
    assert_int_equal(smooth_move_position(&s), 7);
    /* while moving, new parameters wait for rest */
    assert_int_equal(smooth_move_init(&s, &good, 0), MS_OK);
    assert_int_equal(smooth_move_to(&s, 1000), MS_OK);
    {
        step_cmd_t c;
        assert_true(smooth_move_next(&s, &c));
    }
    assert_int_equal(smooth_move_set_params(&s, &good), MS_ERR_BUSY);
    assert_string_equal(motion_status_text(MS_ERR_JERK_TOO_LOW),
                        "jerk too low: tau2 = accel/jerk exceeds tau1 = vmax/accel (jerk must be at least accel^2/vmax)");
}

/* The servo's setpoint: a move from the setpoint in force, a new target behind it while moving
 * (stop, then back from rest), a jump; the setpoint never moves faster than vmax (+1 count of
 * rounding per sample) and ends exactly at each target. */
static void servo_setpoint_moves_stops_and_jumps(void **state)
{
    smooth_setpoint_t sp;
    smooth_params_t p = params(3000, 20000, 400000, 1000000);
    int32_t prev = 0, v = 0;
    uint32_t t;
    int reversed = 0;
    (void)state;
    assert_int_equal(smooth_setpoint_init(&sp, &p, 0), MS_OK);
    p.tick_hz = 1000;
    assert_int_equal(smooth_setpoint_init(&sp, &p, 0), MS_ERR_OUT_OF_RANGE);
    assert_int_equal(smooth_setpoint_at(&sp, 5), 0);
    assert_int_equal(smooth_setpoint_move(&sp, 10, 1000), MS_OK);
    for (t = 10; t <= 2000; t++) {
        if (t == 200)
            assert_int_equal(smooth_setpoint_move(&sp, t, -500), MS_OK); /* behind: stop, then back */
        v = smooth_setpoint_at(&sp, t);
        assert_true(abs(v - prev) <= 4); /* 3000 counts/s x 1 ms + rounding */
        if (v < prev)
            reversed = 1;
        prev = v;
    }
    assert_true(reversed);
    assert_int_equal(v, -500);
    assert_false(smooth_setpoint_moving(&sp));
    smooth_setpoint_jump(&sp, 777);
    assert_int_equal(smooth_setpoint_at(&sp, 2100), 777);
    assert_int_equal(smooth_setpoint_move(&sp, 2100, 777), MS_OK); /* already there: nothing to do */
    assert_false(smooth_setpoint_moving(&sp));
    assert_int_equal(smooth_setpoint_at(&sp, 2200), 777);
}

/* The smx arithmetic: exact for integers and dyadic values, 62-bit relative precision otherwise. */
static void smx_arithmetic(void **state)
{
    int i;
    (void)state;
    assert_true(smx_to_double(smx_from_i64(123456789)) == 123456789.0);
    assert_true(smx_round(smx_div(smx_from_i64(7), smx_from_i64(2))) == 4);
    assert_true(smx_round(smx_div(smx_from_i64(-7), smx_from_i64(2))) == -4);
    assert_true(smx_to_double(smx_from_float(0.1f)) == (double)0.1f);
    for (i = 0; i < 10000; i++) {
        int64_t a = (int64_t)urand(-2e9, 2e9), b = (int64_t)urand(1, 2e9);
        long double q = (long double)a / b;
        smx_t x = smx_div(smx_from_i64(a), smx_from_i64(b));
        assert_true(smx_round(smx_mul(smx_from_i64(a), smx_from_i64(b))) == a * b);
        assert_true(fabsl((long double)smx_to_double(x) - q) <= 1e-15L * fabsl(q) + 1e-300L);
        assert_true(smx_round(smx_add(smx_from_i64(a), smx_from_i64(b))) == a + b);
        assert_true(smx_cmp(smx_from_i64(a), smx_from_i64(b)) == (a > b) - (a < b));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(smx_arithmetic),
        cmocka_unit_test(law_velocity_is_the_ma2_filter_s_output),
        cmocka_unit_test(distance_and_peaks),
        cmocka_unit_test(every_edge_within_one_tick),
        cmocka_unit_test(longest_move),
        cmocka_unit_test(stop_follows_the_zeroed_command),
        cmocka_unit_test(stop_on_a_whole_step_makes_it),
        cmocka_unit_test(new_target_continues_from_the_filter_state),
        cmocka_unit_test(rewind_then_stop_new_target_or_nothing),
        cmocka_unit_test(rewind_stays_after_the_last_change),
        cmocka_unit_test(stop_at_the_step_of_a_new_target),
        cmocka_unit_test(bad_parameters_refused),
        cmocka_unit_test(servo_setpoint_moves_stops_and_jumps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
