/* smooth_move.c - the filter-shaped move and its step commands (see smooth_move.h). */
#include "smooth_move.h"

#include <math.h>
#include <string.h>

/* ---- smx_t: m x 2^e in integers ---- */

#define SMX_TOP (1ULL << 62)
#define SMX_BOT (1ULL << 61)

static smx_t smx_make(int neg, uint64_t a, int e)
{
    smx_t r;
    if (a == 0) {
        r.m = 0;
        r.e = 0;
        return r;
    }
    {
        int len = 64 - __builtin_clzll(a); /* bits of a */
        if (len > 62) {
            int sh = len - 62;
            a = (a >> sh) + ((a >> (sh - 1)) & 1U); /* rounded, halves up */
            e += sh;
            if (a >= SMX_TOP) {
                a >>= 1;
                e++;
            }
        } else if (len < 62) {
            a <<= 62 - len;
            e -= 62 - len;
        }
    }
    r.m = neg ? -(int64_t)a : (int64_t)a;
    r.e = (int16_t)e;
    return r;
}

static uint64_t smx_mag(smx_t a)
{
    return a.m < 0 ? (uint64_t)0 - (uint64_t)a.m : (uint64_t)a.m;
}

smx_t smx_from_i64(int64_t v)
{
    return v < 0 ? smx_make(1, (uint64_t)0 - (uint64_t)v, 0) : smx_make(0, (uint64_t)v, 0);
}

static smx_t smx_ldexp(smx_t a, int k);

smx_t smx_from_float(float f)
{
    int e = 0;
    double fm = frexp((double)f, &e);          /* f = fm 2^e, 0.5 <= |fm| < 1 */
    int32_t mi = (int32_t)(fm * 16777216.0);    /* exact: a float has 24 bits */
    return smx_ldexp(smx_from_i64(mi), e - 24);
}

double smx_to_double(smx_t a)
{
    return ldexp((double)a.m, a.e);
}

static smx_t smx_neg(smx_t a)
{
    a.m = -a.m;
    return a;
}

static smx_t smx_ldexp(smx_t a, int k)
{
    if (a.m != 0)
        a.e = (int16_t)(a.e + k);
    return a;
}

smx_t smx_add(smx_t a, smx_t b)
{
    int d;
    uint64_t bm;
    int64_t s;
    if (a.m == 0)
        return b;
    if (b.m == 0)
        return a;
    if (a.e < b.e) {
        smx_t t = a;
        a = b;
        b = t;
    }
    d = a.e - b.e;
    if (d > 63)
        return a;
    bm = smx_mag(b);
    bm = d == 0 ? bm : (bm >> d) + ((bm >> (d - 1)) & 1U); /* rounded, halves up in magnitude */
    s = a.m + (b.m < 0 ? -(int64_t)bm : (int64_t)bm);
    return s < 0 ? smx_make(1, (uint64_t)0 - (uint64_t)s, a.e) : smx_make(0, (uint64_t)s, a.e);
}

static smx_t smx_sub(smx_t a, smx_t b)
{
    return smx_add(a, smx_neg(b));
}

smx_t smx_mul(smx_t a, smx_t b)
{
    uint64_t x = smx_mag(a), y = smx_mag(b);
    uint32_t x0 = (uint32_t)x, x1 = (uint32_t)(x >> 32), y0 = (uint32_t)y, y1 = (uint32_t)(y >> 32);
    uint64_t p00, p01, p10, p11, mid, lo, hi;
    if (x == 0 || y == 0)
        return smx_from_i64(0);
    /* 32 x 32 -> 64-bit products (a widening multiply on the AVR, not a full 64-bit one) */
    p00 = (uint64_t)x0 * y0;
    p01 = (uint64_t)x0 * y1;
    p10 = (uint64_t)x1 * y0;
    p11 = (uint64_t)x1 * y1;
    mid = (p00 >> 32) + (uint32_t)p01 + (uint32_t)p10;
    lo = (mid << 32) | (uint32_t)p00;
    hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    /* product < 2^124: keep bits 62..123 (truncated) */
    return smx_make((a.m < 0) != (b.m < 0), (hi << 2) | (lo >> 62), a.e + b.e + 62);
}

smx_t smx_div(smx_t a, smx_t b)
{
    uint64_t r = smx_mag(a), d = smx_mag(b), q = 0;
    int i;
    if (r == 0 || d == 0)
        return smx_from_i64(0);
    for (i = 0; i < 62; i++) {
        q <<= 1;
        if (r >= d) {
            r -= d;
            q |= 1U;
        }
        r <<= 1;
    }
    return smx_make((a.m < 0) != (b.m < 0), q, a.e - b.e - 61);
}

static int smx_sign(smx_t a)
{
    return a.m > 0 ? 1 : a.m < 0 ? -1 : 0;
}

int smx_cmp(smx_t a, smx_t b)
{
    return smx_sign(smx_sub(a, b));
}

/* floor(|a| + 1/2) with a's sign; |a| < 2^62 */
int64_t smx_round(smx_t a)
{
    uint64_t m = smx_mag(a);
    if (m == 0)
        return 0;
    if (a.e >= 0)
        m <<= a.e; /* callers stay below 2^62: e >= 0 means a is 0 */
    else if (a.e < -63)
        m = 0;
    else
        m = (m >> -a.e) + ((m >> (-a.e - 1)) & 1U);
    return a.m < 0 ? -(int64_t)m : (int64_t)m;
}

int64_t smx_round_q16(smx_t a)
{
    return smx_round(smx_ldexp(a, 16));
}

static int64_t smx_floor(smx_t a)
{
    uint64_t m = smx_mag(a);
    if (m == 0 || a.e < -63)
        return a.m < 0 ? -1 : 0;
    if (a.e >= 0)
        return a.m < 0 ? -(int64_t)(m << a.e) : (int64_t)(m << a.e);
    if (a.m >= 0)
        return (int64_t)(m >> -a.e);
    return -(int64_t)((m + ((1ULL << -a.e) - 1U)) >> -a.e);
}

static smx_t smx_zero(void)
{
    return smx_from_i64(0);
}

/* ---- the law ---- */

static smx_t last_knot_of(const smooth_law_t *law, smx_t s)
{
    return smx_add(smx_add(s, law->tau1), law->tau2);
}

/* The law's parameters from p, checked (smooth_law_set_params' statuses), into the caller's
 * variables (the law itself is not needed: a check costs no copy of it). */
typedef struct {
    smx_t tau1, tau2, vmax, inv_t1t2;
} law_params_t;

static motion_status_t law_params(const smooth_params_t *p, law_params_t *out)
{
    float vmax, accel, jerk;
    smx_t f, t1, t2;
    vmax = (float)p->vmax_sps;
    accel = (float)p->accel_sps2;
    jerk = (float)p->jerk_sps3;
    if (!isfinite(vmax) || !isfinite(accel) || !isfinite(jerk))
        return MS_ERR_NOT_FINITE;
    if (!(accel > 0))
        return MS_ERR_ACCEL_NOT_POSITIVE;
    if (!(jerk > 0))
        return MS_ERR_JERK_NOT_POSITIVE;
    if (!(vmax > 0))
        return MS_ERR_VMAX_NOT_ABOVE_V0;
    if (p->tick_hz == 0)
        return MS_ERR_TICK_HZ_ZERO;
    if (vmax > (float)p->tick_hz)
        return MS_ERR_VMAX_ABOVE_TICK_HZ;
    f = smx_from_i64(p->tick_hz);
    t1 = smx_div(smx_mul(smx_from_float(vmax), f), smx_from_float(accel));
    t2 = smx_div(smx_mul(smx_from_float(accel), f), smx_from_float(jerk));
    if (smx_cmp(t2, t1) > 0)
        return MS_ERR_JERK_TOO_LOW;
    if (smx_cmp(t1, smx_from_i64((int64_t)1 << 34)) > 0)
        return MS_ERR_ACCEL_PHASE_TOO_LONG;
    out->tau1 = t1;
    out->tau2 = t2;
    out->vmax = smx_div(smx_from_float(vmax), f);
    out->inv_t1t2 = smx_div(smx_from_i64(1), smx_mul(t1, t2));
    return MS_OK;
}

static void law_params_set(smooth_law_t *law, const law_params_t *lp, uint32_t tick_hz)
{
    law->tau1 = lp->tau1;
    law->tau2 = lp->tau2;
    law->vmax = lp->vmax;
    law->inv_t1t2 = lp->inv_t1t2;
    law->tick_hz = tick_hz;
}

motion_status_t smooth_law_set_params(smooth_law_t *law, const smooth_params_t *p)
{
    law_params_t lp;
    motion_status_t st;
    if (law == NULL || p == NULL)
        return MS_ERR_NULL;
    st = law_params(p, &lp);
    if (st == MS_OK)
        law_params_set(law, &lp, p->tick_hz);
    return st;
}

void smooth_law_reset(smooth_law_t *law, int32_t pos)
{
    smx_t z = smx_zero();
    law->n_chg = 0;
    law->n_knot = 0;
    law->cur.t = law->cur.p = law->cur.v = law->cur.a = law->cur.j = z;
    law->cur.next = 0;
    law->p_final = z;
    law->t_final = z;
    law->u_old = z;
    law->origin = pos;
    law->dir = 1;
}

/* q(x) of cursor c: position, velocity, acceleration x later (without knots) */
static void cur_poly(const smooth_cursor_t *c, smx_t x, smx_t *p, smx_t *v, smx_t *a)
{
    static const smx_t sixth = {0x2AAAAAAAAAAAAAABLL, -64}; /* 1/6 to 62 bits */
    smx_t jx = smx_mul(c->j, x);
    smx_t a_half = smx_ldexp(c->a, -1);
    smx_t j_sixth = smx_mul(c->j, sixth);
    if (p != NULL) /* p + x (v + x (a/2 + x j/6)) */
        *p = smx_add(c->p, smx_mul(x, smx_add(c->v, smx_mul(x, smx_add(a_half, smx_mul(x, j_sixth))))));
    if (v != NULL) /* v + x (a + x j/2) */
        *v = smx_add(c->v, smx_mul(x, smx_add(c->a, smx_ldexp(jx, -1))));
    if (a != NULL)
        *a = smx_add(c->a, jx);
}

/* the cursor's state moved to time t (>= c->t, before the next knot) */
static void cur_move(smooth_cursor_t *c, smx_t t)
{
    smx_t x = smx_sub(t, c->t), p, v, a;
    if (x.m == 0) {
        c->t = t;
        return;
    }
    cur_poly(c, x, &p, &v, &a);
    c->p = p;
    c->v = v;
    c->a = a;
    c->t = t;
}

/* to time t, through the knots up to it (those at t included) */
static void cur_advance(smooth_cursor_t *c, const smooth_law_t *law, smx_t t)
{
    while (c->next < law->n_knot && smx_cmp(law->knot[c->next].t, t) <= 0) {
        cur_move(c, law->knot[c->next].t);
        c->j = smx_add(c->j, law->knot[c->next].dj);
        c->next++;
    }
    if (smx_cmp(t, c->t) > 0)
        cur_move(c, t);
}

void smooth_law_advance(smooth_law_t *law, smx_t t)
{
    cur_advance(&law->cur, law, t);
}

void smooth_law_knots_to(smooth_law_t *law, smx_t t)
{
    smooth_cursor_t *c = &law->cur;
    while (c->next < law->n_knot && smx_cmp(law->knot[c->next].t, t) <= 0) {
        cur_move(c, law->knot[c->next].t);
        c->j = smx_add(c->j, law->knot[c->next].dj);
        c->next++;
    }
}

/* The knots after the cursor's time from the changes, sorted; the cursor starts on them. */
static void rebuild_knots(smooth_law_t *law)
{
    uint8_t i, j, k, n = 0;
    for (i = 0; i < law->n_chg; i++) {
        smx_t s = law->chg[i].c, dj, t0 = law->chg[i].t;
        smx_t tt[4];
        smx_t dd[4];
        /* changes at one time act as their sum: a stop given at the step of a new target that
         * started from a command at 0 cancels its rectangle's start exactly (h - h), and has no
         * knots then (else the law ended tau1 + tau2 later with nothing moving, and a last step on
         * a whole rest waited that long: found by a review on 2026-12-05) */
        for (j = 0; j < i && smx_cmp(law->chg[j].t, t0) != 0; j++)
            ;
        if (j < i)
            continue; /* counted with the first change at that time */
        for (j = i + 1; j < law->n_chg; j++)
            if (smx_cmp(law->chg[j].t, t0) == 0)
                s = smx_add(s, law->chg[j].c);
        if (s.m == 0)
            continue;
        dj = smx_mul(s, law->inv_t1t2);
        tt[0] = t0;
        tt[1] = smx_add(t0, law->tau1);
        tt[2] = smx_add(t0, law->tau2);
        tt[3] = last_knot_of(law, t0);
        dd[0] = dj;
        dd[1] = dd[2] = smx_neg(dj);
        dd[3] = dj;
        for (k = 0; k < 4; k++) {
            uint8_t at;
            if (smx_cmp(tt[k], law->cur.t) <= 0)
                continue;
            at = n;
            while (at > 0 && smx_cmp(law->knot[at - 1].t, tt[k]) > 0) {
                law->knot[at] = law->knot[at - 1];
                at--;
            }
            law->knot[at].t = tt[k];
            law->knot[at].dj = dd[k];
            n++;
        }
    }
    law->n_knot = n;
    law->cur.next = 0;
    law->t_final = n > 0 ? law->knot[n - 1].t : law->cur.t;
}

/* command level at the cursor's time (changes at or before it) */
static smx_t level_now(const smooth_law_t *law)
{
    smx_t u = law->u_old;
    uint8_t i;
    for (i = 0; i < law->n_chg; i++)
        if (smx_cmp(law->chg[i].t, law->cur.t) <= 0)
            u = smx_add(u, law->chg[i].c);
    return u;
}

/* Keeps the changes whose knots are not all in the cursor (and, unless drop_future, those
 * after the cursor's time). */
static void drop_old_changes(smooth_law_t *law, uint8_t drop_future)
{
    uint8_t i, k = 0;
    for (i = 0; i < law->n_chg; i++) {
        int future = smx_cmp(law->chg[i].t, law->cur.t) > 0;
        if (future && drop_future)
            continue;
        if (!future && smx_cmp(last_knot_of(law, law->chg[i].t), law->cur.t) <= 0) {
            law->u_old = smx_add(law->u_old, law->chg[i].c); /* all its knots are in the cursor */
            continue;
        }
        law->chg[k++] = law->chg[i];
    }
    law->n_chg = k;
}

/* Adds a change at time t; a change at the cursor's time puts its first jerk step in at once. */
static void add_change(smooth_law_t *law, smx_t t, smx_t c)
{
    law->chg[law->n_chg].t = t;
    law->chg[law->n_chg].c = c;
    law->n_chg++;
    if (smx_cmp(t, law->cur.t) <= 0)
        law->cur.j = smx_add(law->cur.j, smx_mul(c, law->inv_t1t2));
}

/* position after the last knot, from the cursor */
static smx_t rest_position(const smooth_law_t *law)
{
    smooth_cursor_t c = law->cur;
    if (law->n_knot == 0)
        return c.p;
    cur_advance(&c, law, law->knot[law->n_knot - 1].t);
    return c.p;
}

/* The rectangle for a distance r > 0 (smooth_move.h): height *h, length *len. */
static void rectangle(const smooth_law_t *law, smx_t r, smx_t *h, smx_t *len)
{
    smx_t both = smx_add(law->tau1, law->tau2);
    smx_t full = smx_mul(law->vmax, both);
    smx_t lower = smx_mul(law->vmax, smx_sub(law->tau1, law->tau2));
    if (smx_cmp(r, full) >= 0 || smx_cmp(r, lower) <= 0) {
        *h = law->vmax;
        *len = smx_div(r, law->vmax);
    } else {
        *len = both;
        *h = smx_div(r, both);
    }
}

static const smx_t *limit_t(void)
{
    static smx_t lim;
    lim = smx_from_i64((int64_t)1 << 46);
    return &lim;
}

/* A rest point that is a whole step but for the rounding of the law's arithmetic (within 2^-50 of
 * its size; the error of its few dozen operations is some 2^-60) is that whole step, so that a stop
 * whose rest is exactly on a step makes that step, whatever the rounding (its last step is then at
 * the end of the law). */
static smx_t whole_if_on_it(smx_t p)
{
    int64_t n = smx_round(p);
    smx_t d = smx_sub(p, smx_from_i64(n));
    if (p.m != 0 && (d.m == 0 || d.e <= p.e - 51))
        return smx_from_i64(n);
    return p;
}

/* |jerk| of the law from the cursor's time on within J = vmax/(tau1 tau2) (+2^-20): the cursor's
 * piece and each knot's (after rebuild_knots, every knot is after the cursor). Pieces shorter than
 * a tick are not judged: two windows that meet (one ends where the other starts, as a rectangle of
 * length tau1 + tau2 makes them) fall a rounding apart, in either order. */
static uint8_t jerk_within(const smooth_law_t *law)
{
    smx_t lim = smx_mul(law->vmax, law->inv_t1t2), j = law->cur.j, one = smx_from_i64(1);
    uint8_t i;
    lim = smx_add(lim, smx_ldexp(lim, -20));
    for (i = 0;; i++) {
        uint8_t brief = i < law->n_knot &&
                        smx_cmp(smx_sub(law->knot[i].t, i ? law->knot[i - 1].t : law->cur.t), one) < 0;
        if (!brief && (smx_cmp(j, lim) > 0 || smx_cmp(smx_neg(j), lim) > 0))
            return 0;
        if (i >= law->n_knot)
            return 1;
        j = smx_add(j, law->knot[i].dj);
    }
}

/* The command from time e on (at or after the cursor's; its future changes already dropped, u its
 * level): to 0 (stop), or the rectangle to goal from where a stop at e comes to rest. n0, j0: the
 * changes and the cursor's jerk before (what the caller puts back to try another e). */
static motion_status_t plan_from(smooth_law_t *law, smx_t goal, uint8_t stop, smx_t u, smx_t e, uint8_t n0,
                                 smx_t j0)
{
    smx_t p_stop, r, h, len;
    if (u.m != 0)
        add_change(law, e, smx_neg(u));
    rebuild_knots(law);
    p_stop = whole_if_on_it(rest_position(law));
    if (stop) {
        law->p_final = p_stop;
        return MS_OK;
    }
    law->n_chg = n0;
    law->cur.j = j0;
    r = smx_sub(goal, p_stop);
    if (r.m < 0)
        return MS_ERR_SMOOTH_REVERSE;
    if (r.m == 0) {
        h = smx_zero();
        len = smx_zero();
    } else {
        rectangle(law, r, &h, &len);
    }
    if (law->n_chg + 2 > SMOOTH_MAX_CHANGES - 1) /* one is kept for a stop */
        return MS_ERR_SMOOTH_TOO_MANY;
    if (smx_cmp(h, u) != 0)
        add_change(law, e, smx_sub(h, u));
    if (h.m != 0)
        add_change(law, smx_add(e, len), smx_neg(h));
    rebuild_knots(law);
    if (smx_cmp(law->t_final, *limit_t()) > 0)
        return MS_ERR_SMOOTH_TOO_LONG;
    law->p_final = goal;
    return MS_OK;
}

/* Replaces the command from the cursor's time on: to `goal` (frame) or, with stop, to 0. In place:
 * on an error the law is left changed (its future changes dropped), so smooth_law_retarget works on
 * a copy; a stop cannot fail (smooth_law_start builds its law itself).
 * When: now (the cursor's time), unless the new change's jerk windows would add to a running window
 * of the same sign (a stop, or a lower command, within tau2 of the end of the acceleration's
 * ramp-down: the jerk would reach 2 J there); then at the first end of a running window from which
 * the jerk stays within J (+2^-20) all along: at most tau1 + tau2 after now (then the filters hold
 * the level alone, and any stop keeps it). A new target that no such time keeps within J (or that
 * such a time would put behind the rest point), or that could only start when the plan has come
 * to rest (the command already at 0), gets MS_ERR_SMOOTH_REVERSE: the callers then stop (within J)
 * and move from rest (solved there as any start: a change exactly at the rest, where the position
 * is flat to the third order, would leave that step's time ill-conditioned). */
static motion_status_t replan(smooth_law_t *law, smx_t goal, uint8_t stop)
{
    smx_t u, j0, cand[SMOOTH_MAX_KNOTS + 1];
    uint8_t n0, nc, k;
    motion_status_t st;
    drop_old_changes(law, 1);
    u = level_now(law);
    if (law->n_chg + 1 > SMOOTH_MAX_CHANGES)
        return MS_ERR_SMOOTH_TOO_MANY;
    n0 = law->n_chg;
    j0 = law->cur.j;
    rebuild_knots(law); /* the running windows' ends: the knots of the changes kept */
    cand[0] = law->cur.t;
    for (k = 0; k < law->n_knot; k++)
        cand[k + 1] = law->knot[k].t;
    nc = (uint8_t)(law->n_knot + 1);
    for (k = 0; k < nc; k++) {
        if (k > 0 && smx_cmp(cand[k], cand[k - 1]) == 0)
            continue;
        if (!stop && u.m == 0 && k > 0 && k == nc - 1)
            return MS_ERR_SMOOTH_REVERSE; /* only once the plan has come to rest: a move from rest after it */
        st = plan_from(law, goal, stop, u, cand[k], n0, j0);
        if (st == MS_OK && jerk_within(law))
            return MS_OK;
        if (k == 0 && st != MS_OK)
            return st;
        law->n_chg = n0;
        law->cur.j = j0;
    }
    if (!stop)
        return MS_ERR_SMOOTH_REVERSE; /* no time keeps it within J: a stop, then a move from rest */
    return plan_from(law, goal, stop, u, cand[0], n0, j0); /* not met: the last end keeps a stop within J */
}

motion_status_t smooth_law_start(smooth_law_t *law, int32_t to)
{
    int64_t d = (int64_t)to - law->origin;
    smx_t g = smx_from_i64(d < 0 ? -d : d), h, len, end;
    if (d != 0) { /* what replan makes of it from rest, checked before anything changes */
        rectangle(law, g, &h, &len);
        end = smx_add(smx_zero(), len);
        if (smx_cmp(last_knot_of(law, end), *limit_t()) > 0)
            return MS_ERR_SMOOTH_TOO_LONG;
    }
    smooth_law_reset(law, law->origin);
    law->dir = d < 0 ? -1 : 1;
    if (d == 0)
        return MS_OK;
    add_change(law, law->cur.t, h);
    add_change(law, end, smx_neg(h));
    rebuild_knots(law);
    law->p_final = g;
    return MS_OK;
}

motion_status_t smooth_law_retarget(smooth_law_t *law, smx_t now, int32_t to)
{
    smooth_law_t t = *law; /* replan changes it in place, also when it refuses */
    motion_status_t st;
    cur_advance(&t.cur, &t, now);
    st = replan(&t, smx_from_i64(((int64_t)to - law->origin) * law->dir), 0);
    if (st == MS_OK)
        *law = t;
    return st;
}

void smooth_law_stop(smooth_law_t *law, smx_t now)
{
    uint8_t i;
    cur_advance(&law->cur, law, now);
    for (i = 0; i < law->n_chg; i++)
        if (smx_cmp(law->chg[i].t, law->cur.t) > 0)
            break;
    if (i == law->n_chg && level_now(law).m == 0)
        return; /* already coming to rest where the plan ends */
    (void)replan(law, smx_zero(), 1); /* a stop needs at most one more change than the last plan */
}

/* ---- solving p(t) = n ---- */

typedef struct {
    smx_t t0, p, v, a, j; /* the polynomial around t0 */
} poly_t;

static void poly_at(const poly_t *q, smx_t x, smx_t *p, smx_t *v)
{
    smooth_cursor_t c;
    c.t = q->t0;
    c.p = q->p;
    c.v = q->v;
    c.a = q->a;
    c.j = q->j;
    cur_poly(&c, x, p, v, NULL);
}

/* x in [lo, hi] with p(x) = n (p rises on it), to 2^-20 tick: Newton, bisection when it leaves
 * the bracket or the slope is 0. */
static smx_t poly_solve(const poly_t *q, smx_t n, smx_t lo, smx_t hi)
{
    smx_t x = hi, eps = smx_ldexp(smx_from_i64(1), -20);
    int i;
    for (i = 0; i < 200; i++) {
        smx_t p, v, f, xn, dx;
        poly_at(q, x, &p, &v);
        f = smx_sub(p, n);
        if (f.m == 0)
            return x;
        if (f.m < 0)
            lo = x;
        else
            hi = x;
        xn = v.m > 0 ? smx_sub(x, smx_div(f, v)) : hi;
        if (v.m <= 0 || smx_cmp(xn, lo) <= 0 || smx_cmp(xn, hi) >= 0)
            xn = smx_ldexp(smx_add(lo, hi), -1);
        dx = smx_sub(xn, x);
        x = xn;
        if (smx_cmp(dx.m < 0 ? smx_neg(dx) : dx, eps) < 0)
            break;
        if (smx_cmp(smx_sub(hi, lo), eps) < 0)
            break;
    }
    return x;
}

static int8_t sign_of(smx_t a)
{
    return (int8_t)smx_sign(a);
}

smx_t smooth_law_time_of(const smooth_law_t *law, uint32_t n, int8_t *accel)
{
    smooth_cursor_t c = law->cur;
    smx_t target = smx_from_i64(n);
    poly_t q;
    for (;;) {
        if (c.next >= law->n_knot) { /* at rest: never (n is beyond the plan) */
            if (accel != NULL)
                *accel = 0;
            return c.t;
        }
        if (smx_cmp(law->knot[c.next].t, law->t_final) == 0) {
            /* the last segment, from its end: there p = p_final, v = a = 0 */
            smx_t x;
            q.t0 = law->t_final;
            q.p = law->p_final;
            q.v = q.a = smx_zero();
            q.j = c.j;
            if (c.j.m != 0) {
                x = poly_solve(&q, target, smx_sub(c.t, law->t_final), smx_zero());
                if (accel != NULL)
                    *accel = sign_of(smx_mul(c.j, x));
                return smx_add(law->t_final, x);
            }
            return law->t_final;
        }
        {
            smx_t xk = smx_sub(law->knot[c.next].t, c.t), pk;
            cur_poly(&c, xk, &pk, NULL, NULL);
            if (smx_cmp(pk, target) >= 0) {
                smx_t x, a;
                q.t0 = c.t;
                q.p = c.p;
                q.v = c.v;
                q.a = c.a;
                q.j = c.j;
                x = poly_solve(&q, target, smx_zero(), xk);
                cur_poly(&c, x, NULL, NULL, &a);
                if (accel != NULL)
                    *accel = sign_of(a);
                return smx_add(c.t, x);
            }
            cur_move(&c, law->knot[c.next].t);
            c.j = smx_add(c.j, law->knot[c.next].dj);
            c.next++;
        }
    }
}

void smooth_law_eval(const smooth_law_t *law, smx_t t, double *p, double *v, double *a, double *j)
{
    smooth_cursor_t c = law->cur;
    double f = (double)law->tick_hz;
    cur_advance(&c, law, t);
    if (c.next >= law->n_knot && law->n_knot > 0) /* at rest */
        c.p = law->p_final, c.v = c.a = c.j = smx_zero();
    if (p != NULL)
        *p = smx_to_double(c.p);
    if (v != NULL)
        *v = smx_to_double(c.v) * f;
    if (a != NULL)
        *a = smx_to_double(c.a) * f * f;
    if (j != NULL)
        *j = smx_to_double(c.j) * f * f * f;
}

int32_t smooth_law_position_at(const smooth_law_t *law, smx_t t)
{
    smooth_cursor_t c = law->cur;
    cur_advance(&c, law, t);
    if (c.next >= law->n_knot && law->n_knot > 0)
        c.p = law->p_final;
    return (int32_t)(law->origin + law->dir * smx_round(c.p));
}

uint8_t smooth_law_moving(const smooth_law_t *law)
{
    return law->cur.next < law->n_knot;
}

/* ---- the stepper planner ---- */

#define WIDE_ABOVE16 ((int64_t)65536 << 16) /* intervals of 65536 ticks or more go WIDE */
#define TOL_TICKS 0.9f /* |executor time - law time| allowed inside a command (below 1: the edge, floor(acc) half a tick in, within 1 tick of round(F t_n)) */
#define SPAN_MAX 65535U
#define SPAN_PROBE 3U /* after two steps were refused: commands of one step before two are tried again */
#define F2M16 1.52587890625e-05f /* 2^-16 */
#define F2M12 2.44140625e-04f
#define F2M21 4.76837158203125e-07f

/* the planner's own state at rest at pos (the law apart) */
static void fields_rest(smooth_move_t *s, int32_t pos)
{
    s->pos = pos;
    s->n = 0;
    s->n_end = 0;
    s->acc16 = 0;
    s->err16 = 0;
    s->span = 1;
    s->active = 0;
    s->has_then = 0;
    s->t_n = s->x_a = smx_zero();
    s->tn_stale = 0;
    s->xa_stale = 0;
    s->n_a = 0;
    s->t16_a = 0;
    s->xa16 = 0;
    s->y16 = 0;
    s->y_lo = 0;
    s->xf_a = 0;
    s->a_in_seg = 0;
    s->seg_ok = 0;
    s->probe = 0;
    s->n_evt = 0;
    s->t_evt = smx_zero();
}

static void move_rest(smooth_move_t *s, int32_t pos)
{
    smooth_law_reset(&s->law, pos);
    fields_rest(s, pos);
}

motion_status_t smooth_move_init(smooth_move_t *s, const smooth_params_t *p, int32_t pos)
{
    motion_status_t st;
    if (s == NULL || p == NULL)
        return MS_ERR_NULL;
    st = smooth_law_set_params(&s->law, p); /* changes nothing on error */
    if (st != MS_OK)
        return st;
    s->max_cmd_ticks = p->tick_hz / 250U;
    if (s->max_cmd_ticks == 0)
        s->max_cmd_ticks = 1;
    move_rest(s, pos);
    return MS_OK;
}

motion_status_t smooth_move_set_params(smooth_move_t *s, const smooth_params_t *p)
{
    law_params_t lp;
    motion_status_t st;
    if (s == NULL || p == NULL)
        return MS_ERR_NULL;
    st = law_params(p, &lp);
    if (st != MS_OK)
        return st;
    if (smooth_move_busy(s))
        return MS_ERR_BUSY;
    law_params_set(&s->law, &lp, p->tick_hz);
    s->max_cmd_ticks = p->tick_hz / 250U ? p->tick_hz / 250U : 1U;
    return MS_OK;
}

/* the last whole step of the plan: floor(p_final) */
static uint32_t plan_end(const smooth_law_t *law)
{
    int64_t e = smx_floor(law->p_final);
    return e < 0 ? 0 : (uint32_t)e;
}

static motion_status_t start_from_rest(smooth_move_t *s, int32_t to)
{
    int32_t origin = s->law.origin;
    motion_status_t st;
    s->law.origin = s->pos; /* the move's frame; smooth_law_start checks first, changes nothing on error */
    st = smooth_law_start(&s->law, to);
    if (st != MS_OK) {
        s->law.origin = origin;
        return st;
    }
    fields_rest(s, s->pos);
    s->n_end = plan_end(&s->law);
    s->active = s->n_end > 0;
    return MS_OK;
}

static smx_t smx_sub(smx_t a, smx_t b);
static void make_exact(smooth_move_t *s);
static void sync_tn(smooth_move_t *s);

motion_status_t smooth_move_to(smooth_move_t *s, int32_t to)
{
    motion_status_t st;
    if (s == NULL)
        return MS_ERR_NULL;
    if (!smooth_move_busy(s))
        return start_from_rest(s, to);
    if (s->has_then) { /* a stop is running: its move is replaced */
        s->then_target = to;
        return MS_OK;
    }
    make_exact(s);
    sync_tn(s);
    st = smooth_law_retarget(&s->law, s->t_n, to);
    if (st == MS_OK || st == MS_ERR_SMOOTH_REVERSE) {
        s->n_evt = s->n; /* the law's knots start after this step now */
        s->t_evt = s->t_n;
    }
    if (st == MS_ERR_SMOOTH_REVERSE) {
        smooth_law_stop(&s->law, s->t_n);
        s->n_end = plan_end(&s->law);
        if (s->n_end < s->n)
            s->n_end = s->n;
        s->has_then = 1;
        s->then_target = to;
        s->seg_ok = 0;
        return MS_OK;
    }
    if (st != MS_OK)
        return st;
    s->n_end = plan_end(&s->law);
    s->seg_ok = 0;
    return MS_OK;
}

void smooth_move_stop(smooth_move_t *s)
{
    if (s == NULL || !smooth_move_busy(s))
        return;
    s->has_then = 0;
    make_exact(s);
    sync_tn(s);
    smooth_law_stop(&s->law, s->t_n);
    s->n_evt = s->n;
    s->t_evt = s->t_n;
    s->n_end = plan_end(&s->law);
    if (s->n_end < s->n)
        s->n_end = s->n;
    s->seg_ok = 0;
}

void smooth_move_halt(smooth_move_t *s, int32_t pos)
{
    move_rest(s, pos);
}

uint32_t smooth_move_rewindable(const smooth_move_t *s)
{
    return s->active && s->n > s->n_evt + 1U ? s->n - s->n_evt - 1U : 0U;
}

/* The law's cursor back to a time at or before t (not before t_evt): across the knots it has
 * applied since the last change of the law, each undone on its own segment's polynomial (the
 * cursor is on a knot, or at t_evt before the first: smooth_law_knots_to moves it only so). */
static void cur_back(smooth_move_t *s, smx_t t)
{
    smooth_law_t *law = &s->law;
    smooth_cursor_t *c = &law->cur;
    while (c->next > 0 && smx_cmp(c->t, t) > 0) {
        c->next--;
        c->j = smx_sub(c->j, law->knot[c->next].dj); /* the jerk before that knot */
        cur_move(c, c->next > 0 ? law->knot[c->next - 1].t : s->t_evt);
    }
}

motion_status_t smooth_move_rewind(smooth_move_t *s, uint32_t steps, int64_t time16)
{
    smooth_cursor_t cur;
    smx_t t_k, lo;
    uint32_t k;
    int64_t acc16, d16;
    if (s == NULL)
        return MS_ERR_NULL;
    if (steps < 1 || steps > smooth_move_rewindable(s))
        return MS_ERR_OUT_OF_RANGE;
    k = s->n - steps;
    acc16 = s->acc16 - time16;
    /* a time two ticks before the executor's for step k (within a tick of the law's) */
    lo = smx_ldexp(smx_from_i64(acc16 - 2 * 65536), -16);
    if (smx_cmp(lo, s->t_evt) < 0)
        lo = s->t_evt;
    memcpy(&cur, &s->law.cur, sizeof cur); /* put back if time16 is not the dropped commands' */
    cur_back(s, lo);
    t_k = smooth_law_time_of(&s->law, k, NULL);
    d16 = acc16 - smx_round_q16(t_k);
    if (smx_cmp(t_k, s->t_evt) <= 0 || d16 > 65536 || d16 < -65536) {
        memcpy(&s->law.cur, &cur, sizeof cur); /* byte for byte, padding too */
        return MS_ERR_OUT_OF_RANGE;
    }
    smooth_law_knots_to(&s->law, t_k); /* on the last knot at or before it, as the planner leaves it */
    s->n = k;
    s->pos = (int32_t)(s->law.origin + s->law.dir * (int64_t)k);
    s->acc16 = acc16;
    s->t_n = t_k;
    s->tn_stale = 0;
    s->n_a = k;                  /* step k is exactly solved: the anchor */
    s->y16 = 0;
    s->y_lo = 0;
    s->err16 = d16;
    s->probe = 0;
    s->seg_ok = 0;               /* the segment that holds step k + 1, set up by the next call */
    return MS_OK;
}

uint8_t smooth_move_busy(const smooth_move_t *s)
{
    return s->active && (s->n < s->n_end || s->has_then);
}

int32_t smooth_move_position(const smooth_move_t *s)
{
    return s->pos;
}

int32_t smooth_move_target(const smooth_move_t *s)
{
    if (s->has_then)
        return s->then_target;
    return (int32_t)(s->law.origin + s->law.dir * (int64_t)s->n_end);
}

static int64_t div_round(int64_t a, int64_t b) /* b > 0 */
{
    return a >= 0 ? (a + b / 2) / b : -((-a + b / 2) / b);
}

static float smx_to_float(smx_t a)
{
    return (float)smx_to_double(a);
}

/* the segment's position at local time x: p + x (v + x (a/2 + x j/6)) */
static smx_t seg_pos(const smooth_move_t *s, smx_t x)
{
    return smx_add(s->seg.p, smx_mul(x, smx_add(s->seg.v, smx_mul(x, smx_add(s->seg_ah, smx_mul(x, s->seg_j6))))));
}

/* Velocity and acceleration of the segment at local time xf (floats) */
static void seg_va(const smooth_move_t *s, float xf, float *v, float *a)
{
    float ax = s->f_a0 * xf, jx = s->f_j * xf;
    *v = s->f_v0 + ax + 0.5f * jx * xf;
    *a = s->f_a0 + jx;
}

/* Bounds on the rounding errors of seg_va's v and a (the terms' magnitudes times 2^-21: x itself
 * is a float) */
static void seg_err(const smooth_move_t *s, float xf, float *dv, float *da)
{
    float ax = s->f_a0 * xf, jx = s->f_j * xf;
    *dv = F2M21 * (fabsf(s->f_v0) + fabsf(ax) + fabsf(0.5f * jx * xf));
    *da = F2M21 * (fabsf(s->f_a0) + fabsf(jx));
}

/* Step n exactly solved at local time x (smx) or x16 (2^-16 ticks; with x NULL): the anchor. */
static void set_anchor(smooth_move_t *s, const smx_t *x, int64_t x16)
{
    if (x != NULL) {
        s->x_a = *x;
        x16 = smx_round_q16(*x);
        s->xa_stale = 0;
    } else {
        s->xa_stale = 1; /* x_a = xa16 2^-16: worked out when an smx solve needs it */
    }
    s->xa16 = x16;
    s->n_a = s->n;
    s->tn_stale = 1; /* t_n = seg.t + x_a: worked out when a stop, a new target or the next segment needs it */
    s->t16_a = s->seg_t16 + x16;
    s->y16 = 0;
    s->y_lo = 0;
    s->xf_a = (float)x16 * F2M16;
    s->err16 = s->acc16 - s->t16_a;
    s->a_in_seg = 1;
}

static void sync_xa(smooth_move_t *s)
{
    if (s->xa_stale) {
        s->x_a = smx_ldexp(smx_from_i64(s->xa16), -16);
        s->xa_stale = 0;
    }
}

static void sync_tn(smooth_move_t *s)
{
    sync_xa(s);
    if (s->tn_stale) {
        s->t_n = smx_add(s->seg.t, s->x_a);
        s->tn_stale = 0;
    }
}

/* p(x) - m of the segment at whole tick x, in units of 2^-fp_m steps (fixed point, see fp_c) */
typedef union {
    uint64_t u;
    uint32_t w[2]; /* w[0] the low half: little-endian on the AVR and the hosts we build for */
} w64_t;

static int64_t mul_shr(int64_t h, int32_t x, uint8_t sh) /* h x / 2^sh toward 0; h x < 2^(sh + 61) */
{
    w64_t uh, pl;
    uint64_t ph, r;
    uint32_t ux = x < 0 ? (uint32_t)0 - (uint32_t)x : (uint32_t)x;
    uh.u = h < 0 ? (uint64_t)0 - (uint64_t)h : (uint64_t)h;
    ph = (uint64_t)uh.w[1] * ux;
    pl.u = (uint64_t)uh.w[0] * ux;
    if (sh >= 32)
        r = (ph + pl.w[1]) >> (sh - 32);
    else
        r = (ph << (32 - sh)) + (pl.u >> sh);
    return (h < 0) != (x < 0) ? -(int64_t)r : (int64_t)r;
}

/* v 2^16, and round(x 2^-16) for |x| < 2^46: the halves moved as words (a 64-bit shift is a loop
 * of library calls on the AVR) */
static int64_t shl16(int32_t v)
{
    w64_t u;
    u.w[0] = (uint32_t)v << 16;
    u.w[1] = (uint32_t)(v < 0 ? ~(~(uint32_t)v >> 16) : (uint32_t)v >> 16);
    return (int64_t)u.u;
}

static int32_t round_q16(int64_t x)
{
    w64_t u;
    u.u = (uint64_t)(x + 0x8000);
    return (int32_t)((u.w[1] << 16) | (u.w[0] >> 16));
}

static int64_t fp_resid(const smooth_move_t *s, int32_t x, uint32_t m)
{
    int64_t h = s->fp_c[3] == 0 ? s->fp_c[2] : s->fp_c[2] + mul_shr(s->fp_c[3], x, s->fp_s[2]);
    h = h == 0 ? s->fp_c[1] : s->fp_c[1] + mul_shr(h, x, s->fp_s[1]);
    h = s->fp_c[0] + mul_shr(h, x, s->fp_s[0]);
    return h - (int64_t)((uint64_t)m << s->fp_m);
}

/* The segment's polynomial in fixed point (fp_c) for local times up to X: each level's scale
 * from a bound on its values, 2^60 units (truncation: 2^-60 of the bound per level). */
static void fp_setup(smooth_move_t *s, float X)
{
    const smx_t *co[4];
    float mag[4];
    int e[4], k;
    s->fp_ok = 0;
    if (!(X < 1.0e9f))
        return;
    co[0] = &s->seg.p;
    co[1] = &s->seg.v;
    co[2] = &s->seg_ah;
    co[3] = &s->seg_j6;
    mag[3] = fabsf(smx_to_float(s->seg_j6));
    mag[2] = fabsf(smx_to_float(s->seg_ah)) + X * mag[3];
    mag[1] = fabsf(smx_to_float(s->seg.v)) + X * mag[2];
    mag[0] = fabsf(smx_to_float(s->seg.p)) + X * mag[1] + (float)s->n_end + 2;
    for (k = 3; k >= 0; k--) {
        int ex;
        if (!(mag[k] > 0)) {
            e[k] = k < 3 ? e[k + 1] : -4000;
            continue;
        }
        (void)frexpf(mag[k] * 1.01f, &ex); /* mag < 2^ex */
        e[k] = ex - 60;
    }
    if (e[3] == -4000)
        e[3] = e[2];
    for (k = 0; k < 3; k++) {
        int sh = e[k] - e[k + 1];
        if (sh < 0 || sh > 90)
            return;
        s->fp_s[k] = (uint8_t)sh;
    }
    if (e[0] > 0 || e[0] < -63)
        return;
    s->fp_m = (uint8_t)-e[0];
    for (k = 0; k < 4; k++)
        s->fp_c[k] = co[k]->m == 0 ? 0 : smx_round(smx_ldexp(*co[k], -e[k]));
    s->fp_ok = 1;
}

/* The local time (2^-16 ticks) where the segment's position is m, from the guess x16, in fixed
 * point: Newton steps from whole ticks (the residual exact to 2^-60 of its terms) times te, the
 * ticks per step there (1/velocity, from the series: its relative error is far below 2^-12), accepted when the
 * step is at most a tick (from a whole tick it is up to 1/2; its error is then |dx| times that
 * relative error plus (a/2v) dx^2, far below 2^-12 tick). 0 and *x16 untouched when it does not
 * settle in a few steps (then smx). */
static uint8_t fp_solve(const smooth_move_t *s, uint32_t m, int64_t *x16, float te, float *moved)
{
    int64_t x = *x16;
    int i;
    if (!(te > 0))
        return 0;
    for (i = 0; i < 3; i++) {
        int32_t xi = round_q16(x);
        float dx = ldexpf((float)fp_resid(s, xi, m), -(int)s->fp_m) * te;
        if (!(fabsf(dx) < 16384.0f))
            return 0;
        /* |dx| 2^16 < 2^30: a 32-bit conversion (the 64-bit one costs the AVR 3 times as much) */
        x = shl16(xi) - (int32_t)(dx * 65536.0f + (dx >= 0 ? 0.5f : -0.5f));
        if (fabsf(dx) <= 1.0f) {
            *moved = (float)(x - *x16) * F2M16;
            *x16 = x;
            return 1;
        }
    }
    return 0;
}

/* The segment starting at the copy of the cursor in s->seg (its next knot ends it); step n is
 * exactly solved (t_n). */
static void seg_setup(smooth_move_t *s)
{
    static const smx_t sixth = {0x2AAAAAAAAAAAAAABLL, -64};
    const smooth_law_t *law = &s->law;
    s->seg_final = 1;
    s->seg_last = s->n_end;
    s->inv48 = 0;
    if (s->seg.next < law->n_knot) {
        s->seg_end = law->knot[s->seg.next].t;
        if (smx_cmp(s->seg_end, law->t_final) == 0) { /* the last segment: about its end */
            s->seg.t = law->t_final;
            s->seg.p = law->p_final;
            s->seg.v = s->seg.a = smx_zero();
        } else {
            s->seg_final = 0;
        }
    } else { /* no knot ahead: at rest at p_final (not reached while steps are left) */
        s->seg_end = s->seg.t;
    }
    s->seg_ah = smx_ldexp(s->seg.a, -1);
    s->seg_j6 = smx_mul(s->seg.j, sixth);
    s->seg_hi = smx_sub(s->seg_end, s->seg.t);
    if (!s->seg_final) {
        int64_t e = smx_floor(seg_pos(s, s->seg_hi));
        s->seg_last = e < (int64_t)s->n ? s->n : e > (int64_t)s->n_end ? s->n_end : (uint32_t)e;
    }
    s->final_whole = s->seg_final && smx_cmp(law->p_final, smx_from_i64(s->n_end)) == 0;
    s->f_v0 = smx_to_float(s->seg.v);
    s->f_a0 = smx_to_float(s->seg.a);
    s->f_j = smx_to_float(s->seg.j);
    s->f_acc_eps = smx_to_float(law->vmax) / smx_to_float(law->tau1) * (1.0f / 1024.0f);
    s->seg_t16 = smx_round_q16(s->seg.t);
    {
        smx_t x = smx_sub(s->t_n, s->seg.t); /* step n, solved on the segment before (t_n in sync) */
        float xa = fabsf(smx_to_float(x)), len = fabsf(smx_to_float(s->seg_hi));
        if (!s->seg_final && s->seg.j.m == 0 && s->f_v0 * 32768.0f > 1.0f &&
            (fabsf(s->f_a0) * len * len <= s->f_v0 * 2 * 9.5367431640625e-07f ||
             fabsf(s->f_a0) <= s->f_acc_eps * 3.5527136788005e-15f)) {
            /* a cruise: a line while its acceleration moves it by less than 2^-20 tick, or
             * when that acceleration is only the rounding left by the knots (below 2^-38 of
             * accel: the law's is 0 there) */
            s->inv48 = (uint64_t)smx_round(smx_ldexp(smx_div(smx_from_i64(1), s->seg.v), 48));
            s->fp_ok = 0;
        } else {
            fp_setup(s, (xa > len ? xa : len) + 65536.0f);
        }
        /* its polynomial differs from this one there: the next command is solved exactly on
         * this one before the cruise's line starts */
        set_anchor(s, &x, 0);
        s->a_in_seg = 0;
    }
}

/* The local time x in [lo, hi] where the segment's position is m, from the guess x: Newton
 * steps of the exact residual over the float velocity (a good guess needs one), bisection when
 * a step leaves the bracket; *moved: the correction from the guess (1e30 after a bisection). */
static smx_t seg_solve(const smooth_move_t *s, smx_t m, smx_t x, float xf, smx_t lo, smx_t hi, float *moved)
{
    float tot = 0;
    uint8_t bis = 0, checked = 0;
    int i;
    for (i = 0; i < 200; i++) {
        smx_t f = smx_sub(seg_pos(s, x), m), xn;
        float v, a, dv, da, dx;
        if (f.m == 0)
            break;
        if (f.m < 0)
            lo = x;
        else
            hi = x;
        seg_va(s, xf, &v, &a);
        seg_err(s, xf, &dv, &da);
        if (v > 0) {
            dx = smx_to_float(f) / v;
            xn = smx_sub(x, smx_from_float(dx));
            /* a step of at most a tick from a guess of the series needs no bracket check */
            if ((checked == 0 && fabsf(dx) <= 1.0f) || (smx_cmp(xn, lo) > 0 && smx_cmp(xn, hi) < 0)) {
                float err = fabsf(dx) * ((dv + fabsf(a) * fabsf(dx)) / v + 2.4e-7f);
                x = xn;
                xf -= dx;
                tot -= dx;
                checked = 1;
                if (err < F2M12)
                    break;
                continue;
            }
        }
        checked = 1;
        bis = 1;
        x = smx_ldexp(smx_add(lo, hi), -1);
        xf = smx_to_float(x);
        if (smx_cmp(smx_sub(hi, lo), smx_ldexp(smx_from_i64(1), -20)) < 0)
            break;
    }
    *moved = bis ? 1e30f : tot;
    return x;
}

/* Step n's time solved exactly (after commands on the cruise's line): the anchor moves to step n. */
static void make_exact(smooth_move_t *s)
{
    float moved;
    smx_t x;
    if (s->n == s->n_a || !s->seg_ok)
        return;
    sync_xa(s);
    x = seg_solve(s, smx_from_i64(s->n), smx_add(s->x_a, smx_ldexp(smx_from_i64(s->y16), -16)),
                  s->xf_a + (float)s->y16 * F2M16, s->x_a, s->seg_final ? smx_zero() : s->seg_hi, &moved);
    set_anchor(s, &x, 0);
}

/* Sets up the segment that holds step n + 1. */
static void seg_find(smooth_move_t *s)
{
    if (!s->seg_ok) {
        sync_tn(s);
        s->seg = s->law.cur;
        seg_setup(s);
        s->seg_ok = 1;
    }
    while (!s->seg_final && s->n >= s->seg_last) { /* step n + 1 comes after the knot */
        make_exact(s);
        sync_tn(s);
        cur_move(&s->seg, s->seg_end);
        s->seg.j = smx_add(s->seg.j, s->law.knot[s->seg.next].dj);
        s->seg.next++;
        seg_setup(s);
        smooth_law_knots_to(&s->law, s->t_n);
    }
}

/* A float root of y (v + y (a/2 + y j/6)) = l on (0, ymax] (the position rises there): Newton,
 * bisection when a step leaves the bracket; for a first guess where the series in steps fails
 * (near rest). */
static float fsolve(float v, float a, float j, float l, float ymax)
{
    float lo = 0, hi = ymax, y;
    int i;
    if (v > 0)
        y = l / v;
    else if (a > 0)
        y = sqrtf(2 * l / a);
    else if (j > 0) { /* the cube root of 6 l / j */
        float q = 6 * l / j;
        int e;
        (void)frexpf(q, &e);
        y = ldexpf(1.0f, e / 3);
        for (i = 0; i < 8; i++)
            y = (2 * y + q / (y * y)) * (1.0f / 3.0f);
    } else
        y = 0.5f * hi;
    if (!(y > lo && y < hi))
        y = 0.5f * (lo + hi);
    for (i = 0; i < 60; i++) {
        float g = y * (v + y * (0.5f * a + y * j * (1.0f / 6.0f))) - l;
        float gp = v + y * (a + 0.5f * y * j), yn;
        if (g < 0)
            lo = y;
        else
            hi = y;
        yn = gp > 0 ? y - g / gp : lo - 1;
        if (!(yn > lo && yn < hi))
            yn = 0.5f * (lo + hi);
        if (fabsf(yn - y) <= 1e-6f * y)
            return yn;
        y = yn;
    }
    return y;
}

static void emit(smooth_move_t *s, step_cmd_t *c, uint32_t len, int64_t rate, int64_t add, int64_t quad, uint8_t wide,
                 uint8_t ph)
{
    c->count = (uint16_t)len;
    c->flags = (uint8_t)((s->law.dir < 0 ? STEP_CMD_REVERSE : 0U) | (ph << STEP_CMD_PHASE_SHIFT));
    c->rate = (uint32_t)rate;
    if (wide) {
        c->flags |= STEP_CMD_WIDE;
        c->add = 0;
        s->acc16 += rate << 16;
    } else {
        c->add = (int32_t)add;
        /* quad: len (len - 1)/2 add; rate < 2^32: a 32 x 32-bit product */
        s->acc16 += (int64_t)((uint64_t)len * (uint32_t)rate) + quad;
    }
    s->n += len;
    s->span = (uint16_t)len;
    s->pos = (int32_t)(s->law.origin + s->law.dir * (int64_t)s->n);
}

/* rate and quad (len (len - 1)/2 add) of a command of len >= 2 steps covering e_end (2^-16 ticks)
 * with add: 1 when its first and last intervals are normal (1 .. 65535 ticks) */
static uint8_t lay(int64_t e_end, uint32_t len, int32_t add, int64_t *rate, int64_t *quad)
{
    int64_t last, sum;
    /* len < 2^16: len (len - 1)/2 < 2^31, times a 32-bit add (32 x 32-bit products) */
    *quad = (int64_t)(int32_t)(((uint32_t)len * (len - 1U)) >> 1) * add;
    sum = e_end - *quad;
    if (sum >= 0 && sum < (int64_t)0xFFFFFFFFLL - len) /* a 32-bit division where it fits */
        *rate = (int64_t)(((uint32_t)sum + (uint32_t)(len / 2U)) / (uint32_t)len);
    else
        *rate = div_round(sum, len);
    last = *rate + (int64_t)(int32_t)(len - 1U) * add;
    return *rate >= 1 && *rate < WIDE_ABOVE16 && last >= 1 && last < WIDE_ABOVE16;
}

static uint8_t phase_of(const smooth_move_t *s, float a, float dur)
{
    float a_end = a + s->f_j * dur;
    return fabsf(a_end) <= s->f_acc_eps ? 2U : a_end > 0 ? 1U : 3U;
}

/* A command on the cruise's line: step n + l at y + l / v, in 2^-48 ticks (0: not possible). */
static uint8_t cruise_next(smooth_move_t *s, step_cmd_t *c, uint32_t cap)
{
    float e0 = fabsf((float)s->err16) * F2M16;
    float lf = ((float)s->max_cmd_ticks - e0 - 2) * s->f_v0;
    uint32_t l = lf >= (float)cap ? cap : lf < 1 ? 0 : (uint32_t)lf;
    uint64_t lo, hi, sum;
    int64_t y16, e_end, rate;
    if (l < 1 || e0 + (float)l * (0.5f * F2M16) > TOL_TICKS) /* rate rounded: l 2^-17 at most */
        return 0;
    lo = (uint64_t)l * (uint32_t)s->inv48;
    hi = (uint64_t)l * (uint32_t)(s->inv48 >> 32);
    sum = (uint64_t)s->y_lo + (uint32_t)lo;
    y16 = s->y16 + (int64_t)hi + (int64_t)(lo >> 32) + (int64_t)(sum >> 32);
    e_end = s->t16_a + y16 + ((uint32_t)sum >> 31) - s->acc16;
    rate = div_round(e_end, l);
    if (rate < 1 || rate >= WIDE_ABOVE16 || e_end > (int64_t)s->max_cmd_ticks << 16)
        return 0;
    s->y16 = y16;
    s->y_lo = (uint32_t)sum;
    emit(s, c, l, rate, 0, 0, 0, 2U);
    s->err16 = s->acc16 - (s->t16_a + y16 + ((uint32_t)sum >> 31));
    return 1;
}

uint8_t smooth_move_next(smooth_move_t *s, step_cmd_t *c)
{
    uint32_t cap, len;
    int64_t rate = 0, add = 0, e_end = 0, t16 = 0, x16 = 0, quad = 0;
    uint8_t wide = 0, fast = 0;
    int tries;
    float xf, v, a, e0, t1 = 0, t2 = 0, t3 = 0, t4 = 0, dur = 0;
    float q1 = 0, q2 = 0, q3 = 0, q4 = 0, budget = 0, tmax = 0, h2 = 0, h3 = 0, h4 = 0;
    uint8_t probed = 0;
    smx_t x_end = smx_zero();
    if (s == NULL || c == NULL)
        return 0;
    if (s->active && s->n >= s->n_end && s->has_then) {
        /* the stop has come to rest (at t_final): the move starts there */
        int32_t to = s->then_target;
        int64_t gap = smx_round_q16(s->law.t_final) - s->acc16;
        s->has_then = 0;
        s->active = 0;
        if (start_from_rest(s, to) != MS_OK) {
            move_rest(s, s->pos);
            return 0;
        }
        s->acc16 = gap > 0 ? -gap : 0;
        s->err16 = s->acc16;
    }
    if (!s->active || s->n >= s->n_end) {
        if (s->active) { /* at rest: the timeline starts again with the next move */
            s->active = 0;
            move_rest(s, s->pos);
        }
        return 0;
    }
    seg_find(s);
    cap = s->n_end - s->n;
    if (!s->seg_final && s->seg_last - s->n < cap)
        cap = s->seg_last - s->n;
    if (cap > SPAN_MAX)
        cap = SPAN_MAX;
    if (s->inv48 != 0 && s->a_in_seg && cruise_next(s, c, cap))
        return 1;
    make_exact(s);
    xf = s->xf_a;
    seg_va(s, xf, &v, &a);
    e0 = fabsf((float)s->err16) * F2M16;
    len = 1;
    if (v > 0) {
        float r2, r3, t1s, t1c, dv, da, relv;
        t1 = 1.0f / v;
        t1s = t1 * t1;
        t1c = t1s * t1;
        r2 = a * t1s;                          /* a / v^2: the relative change of the interval per step */
        t2 = -a * t1c;                         /* the derivatives of the time law in steps */
        r3 = s->f_j * t1c;                     /* j t1^3 = j / v^3 */
        t3 = t1 * (3 * r2 * r2 - r3);
        t4 = t1 * r2 * (10 * r3 - 15 * r2 * r2); /* (10 a j v - 15 a^3) / v^7 (a cubic law) */
        /* from a quarter more than the last span (spans change by a few per cent from one
         * command to the next; one that fits costs one evaluation of the bound); after two steps
         * were refused, SPAN_PROBE commands of one step follow without evaluating it (near rest,
         * where a command of one step costs more than the time it covers), then two are tried */
        if (s->span > 1 || s->probe == 0) {
            len = (uint32_t)s->span + s->span / 4U + 1U;
            if (len > cap)
                len = cap;
        } else {
            s->probe--;
        }
        if (len > 1) {
            /* the bound on |executor - law| inside a span of l steps (ticks): e0 decaying, plus
             * l (q1 + l (q2 + l (q3 + l q4))): the rate's rounding (q1), the float error of the
             * shape (q2, q3, q4), and the rounding of add (|add - ideal| l^2/8); the cubic and
             * quartic terms beyond the quadratic through the span's ends and middle (0.00802 |t3|
             * l^3 and 0.00460 |t4| l^4, the largest gaps of u^3/6 and u^4/24 to their quadratics
             * through u = 0, 1/2, 1); the terms beyond those are bounded after the solve by the
             * Newton correction from the series' end (0.55 times it: a quintic error pinned at
             * both ends moves the middle by at most 0.535 of its value at the end) */
            seg_err(s, xf, &dv, &da);
            relv = dv * t1;
            probed = 1;
            q1 = 0.5f * F2M16;
            q2 = 0.5f * relv * fabsf(t2) + da * t1c * 0.125f;
            q3 = (0.00802f + relv * (1.0f / 12)) * fabsf(t3);
            q4 = (0.00461f + relv * (1.0f / 16)) * fabsf(t4);
            budget = TOL_TICKS - e0;
            tmax = (float)s->max_cmd_ticks - e0 - 2;
            h2 = 0.5f * t2;
            h3 = t3 * (1.0f / 6.0f);
            h4 = t4 * (1.0f / 24.0f);
        }
    }
    for (tries = 0;; tries++) {
        float moved, lf = (float)len, e_pre = e0;
        int32_t addi = 0;
        /* the span: the longest (from a quarter more than the last one) within the budget and
         * max_cmd_ticks */
        if (len > 1) {
            int k;
            if ((float)len * t1 > tmax) { /* about the longest span within max_cmd_ticks */
                float l0 = tmax * v, d = 0.5f * l0 * (t2 + l0 * t3 * (1.0f / 3)) * v;
                /* tmax / (t1 (1 + d)) without dividing where |d| < 1/2: l0 (1 - d) is below it (for
                 * any d > -1; within 1 - d^2 of it) */
                float lt = (d > -0.5f && d < 0.5f ? l0 * (1 - d) : tmax / (t1 * (1 + d))) * 0.995f;
                if (lt < (float)len)
                    len = lt < 1 ? 1 : (uint32_t)lt;
                lf = (float)len;
            }
            for (k = 0; k < 16 && len > 1; k++) {
                float eb = lf * (q1 + lf * (q2 + lf * (q3 + lf * q4)));
                dur = eb <= budget ? lf * (t1 + lf * (h2 + lf * (h3 + lf * h4))) : 0;
                /* the last interval below 65000 ticks: only a slowing move's intervals grow */
                if (eb <= budget && dur <= tmax && (t2 <= 0 ? t1 < 65000.0f : t1 + t2 * lf < 65000.0f)) {
                    e_pre = e0 + eb;
                    break;
                }
                if (dur > tmax) {
                    uint32_t l = (uint32_t)(lf * tmax / dur * 0.99f);
                    len = l < len ? l : len - 1;
                } else if (eb > budget) {
                    float r = budget / eb;
                    /* 0.4286 + 0.5714 r: below r's cube root on [1/8, 1] */
                    uint32_t l = r < 0.125f ? len / 2 : (uint32_t)(lf * (0.4286f + 0.5714f * r));
                    len = l < len ? l : len - 1;
                } else {
                    len = len / 2;
                }
                if (len <= 1) {
                    len = 1;
                    break;
                }
                lf = (float)len;
            }
            if (k == 16 || t1 >= 65000.0f)
                len = 1;
            lf = (float)len;
            if (len > 1) {
                /* the second difference of that quadratic: t2 + t3 l/2 + 7 t4 l^2/48 */
                float addf = (t2 + lf * (0.5f * t3 + lf * t4 * (7.0f / 48.0f))) * 65536.0f;
                if (fabsf(addf) < 2.0e9f) {
                    float dq;
                    addi = (int32_t)(addf + (addf >= 0 ? 0.5f : -0.5f));
                    dq = fabsf((float)addi - addf) * lf * lf * (0.125f * F2M16);
                    e_pre += dq;
                    if (e_pre > TOL_TICKS) { /* shorter: the rounding of add shrinks as l^2 */
                        len = len * 3 / 4;
                        if (len < 1)
                            len = 1;
                        continue;
                    }
                } else {
                    len = 1;
                }
            }
        }
        /* the exact time of step n + len: from the series' guess (or a float root near rest),
         * in fixed point where the segment allows, else in smx */
        {
            uint8_t series = len > 1 || (v > 0 && fabsf(t2) * 0.5f + fabsf(t3) * 0.17f < 0.1f * t1);
            float y;
            if (series) {
                if (len == 1)
                    dur = t1 + 0.5f * t2 + t3 * (1.0f / 6.0f) + t4 * (1.0f / 24.0f);
                y = dur;
            } else {
                float ymax = s->seg_final ? -xf : smx_to_float(s->seg_hi) - xf;
                y = fsolve(v, a, s->f_j, 1.0f, ymax);
            }
            fast = 0;
            if (s->seg_final && s->final_whole && s->n + len == s->n_end) {
                x_end = smx_zero();
                moved = 0;
            } else {
                if (series && s->fp_ok) {
                    /* ticks per step at the span's end from the series: dt/dn */
                    float te = t1 + lf * (t2 + lf * (0.5f * t3 + lf * t4 * (1.0f / 6.0f)));
                    x16 = s->xa16 + (int64_t)(y * 65536.0f + 0.5f);
                    fast = fp_solve(s, s->n + len, &x16, te, &moved);
                }
                if (!fast) {
                    sync_xa(s);
                    x_end = seg_solve(s, smx_from_i64((int64_t)s->n + len), smx_add(s->x_a, smx_from_float(y)), xf + y,
                                      s->x_a, s->seg_final ? smx_zero() : s->seg_hi, &moved);
                }
            }
            if (!fast)
                x16 = smx_round_q16(x_end);
            t16 = s->seg_t16 + x16;
        }
        e_end = t16 - s->acc16;
        if (len == 1) {
            if (e_end >= WIDE_ABOVE16) {
                wide = 1;
                rate = (e_end + 0x8000) >> 16;
                if (rate > (int64_t)0xFFFFFFFFLL)
                    rate = 0xFFFFFFFFLL;
            } else {
                rate = e_end < 1 ? 1 : e_end;
            }
            add = 0;
            quad = 0;
            break;
        }
        add = addi;
        if (lay(e_end, len, addi, &rate, &quad) && e_end <= (int64_t)s->max_cmd_ticks << 16 &&
            e_pre + 0.55f * fabsf(moved) <= TOL_TICKS)
            break;
        {
            len = tries > 3 ? len / 2 : len - (len + 3) / 4;
            if (len < 1)
                len = 1;
        }
    }
    emit(s, c, len, rate, add, quad, wide, phase_of(s, a, dur));
    if (probed && len == 1)
        s->probe = SPAN_PROBE; /* two steps did not fit: one step for a while */
    if (fast)
        set_anchor(s, NULL, x16);
    else
        set_anchor(s, &x_end, 0);
    return 1;
}

/* ---- the servo's setpoint ---- */

static void setpoint_rest(smooth_setpoint_t *s, int32_t pos)
{
    smooth_law_reset(&s->law, pos);
    s->last = pos;
    s->has_then = 0;
    s->t0_ms = 0;
}

motion_status_t smooth_setpoint_init(smooth_setpoint_t *s, const smooth_params_t *p, int32_t pos)
{
    motion_status_t st;
    if (s == NULL || p == NULL)
        return MS_ERR_NULL;
    if (p->tick_hz != 1000000U)
        return MS_ERR_OUT_OF_RANGE;
    st = smooth_law_set_params(&s->law, p); /* changes nothing on error */
    if (st != MS_OK)
        return st;
    setpoint_rest(s, pos);
    return MS_OK;
}

motion_status_t smooth_setpoint_set_params(smooth_setpoint_t *s, const smooth_params_t *p)
{
    law_params_t lp;
    motion_status_t st;
    if (s == NULL || p == NULL)
        return MS_ERR_NULL;
    if (p->tick_hz != 1000000U)
        return MS_ERR_OUT_OF_RANGE;
    st = law_params(p, &lp);
    if (st != MS_OK)
        return st;
    if (smooth_setpoint_moving(s))
        return MS_ERR_BUSY;
    law_params_set(&s->law, &lp, p->tick_hz);
    return MS_OK;
}

uint8_t smooth_setpoint_moving(const smooth_setpoint_t *s)
{
    return smooth_law_moving(&s->law) || s->has_then;
}

void smooth_setpoint_jump(smooth_setpoint_t *s, int32_t to)
{
    setpoint_rest(s, to);
}

motion_status_t smooth_setpoint_move(smooth_setpoint_t *s, uint32_t now_ms, int32_t to)
{
    motion_status_t st;
    if (s == NULL)
        return MS_ERR_NULL;
    if (!smooth_setpoint_moving(s)) {
        int32_t origin = s->law.origin;
        s->law.origin = s->last; /* from the setpoint in force; smooth_law_start changes nothing on error */
        st = smooth_law_start(&s->law, to);
        if (st != MS_OK) {
            s->law.origin = origin;
            return st;
        }
        s->t0_ms = now_ms;
        return MS_OK;
    }
    if (s->has_then) {
        s->then_target = to;
        return MS_OK;
    }
    {
        smx_t now = smx_from_i64((int64_t)(uint32_t)(now_ms - s->t0_ms) * 1000);
        st = smooth_law_retarget(&s->law, now, to);
        if (st == MS_ERR_SMOOTH_REVERSE || st == MS_ERR_SMOOTH_TOO_MANY) {
            smooth_law_stop(&s->law, now);
            s->has_then = 1;
            s->then_target = to;
            return MS_OK;
        }
        return st;
    }
}

int32_t smooth_setpoint_at(smooth_setpoint_t *s, uint32_t now_ms)
{
    smx_t t;
    if (!smooth_law_moving(&s->law) && !s->has_then)
        return s->last;
    t = smx_from_i64((int64_t)(uint32_t)(now_ms - s->t0_ms) * 1000);
    smooth_law_knots_to(&s->law, t);
    s->last = smooth_law_position_at(&s->law, t);
    if (!smooth_law_moving(&s->law) && s->has_then) {
        int32_t to = s->then_target;
        s->has_then = 0;
        (void)smooth_setpoint_move(s, now_ms, to); /* from rest at the stop's whole count */
    }
    return s->last;
}
