/* step_exact.c - exact constant-acceleration step commands in integer arithmetic (see step_exact.h). */
#include "step_exact.h"

#include <math.h>

#define SEG_MAX 128U       /* steps one quadratic command may span */
#define CRUISE_MAX 4096U   /* steps one cruise command may span (rate rounding <= 2^-17 tick per step) */
#define FIT_GAIN 4000.0f   /* (L s)^3 <= FIT_GAIN y^2 keeps the quadratic within about 0.4 tick (test_step_planner) */
#define RATE_LIMIT 0xFFFF0000ULL /* largest normal rate (16.16): 65535 ticks */

/* ---- exact fixed-point helpers ------------------------------------------------------------ */

/* x = m * 2^e with m a 24-bit integer (x > 0, finite). */
static uint32_t float_mant(float x, int *e)
{
    int ex;
    float f = frexpf(x, &ex); /* x = f 2^ex, 0.5 <= f < 1 */
    *e = ex - 24;
    return (uint32_t)ldexpf(f, 24);
}

/* round(num * 2^shift / den) for den > 0; 0 on overflow (the callers' limits exclude it). */
static uint64_t ratio64(uint64_t num, float den, int shift)
{
    int ed, z = 0;
    uint32_t md = float_mant(den, &ed);
    uint64_t q, rem;
    if (num == 0)
        return 0;
    while (!(num & 0x4000000000000000ULL)) {
        num <<= 1;
        z++;
    }
    q = num / md;
    rem = num % md;
    shift -= ed + z;
    if (shift >= 0) {
        if (shift > 0 && (q >> (64 - shift)) != 0)
            return 0;
        return q << shift;
    }
    if (shift <= -64)
        return 0;
    {
        uint64_t half = (uint64_t)1 << (-shift - 1);
        (void)rem;
        return (q + half) >> (-shift);
    }
}

/* 64-bit arithmetic by 32-bit halves (the AVR has no 64-bit multiply; this keeps it to 32 x 32). */
typedef union {
    uint64_t u;
    uint32_t w[2]; /* little-endian on the AVR and the host: w[0] is the low half */
} u64w_t;

static uint64_t mul32x32(uint32_t a, uint32_t b)
{
    return (uint64_t)a * b;
}

/* a * b modulo 2^64 */
static uint64_t mul64x32(uint64_t a, uint32_t b)
{
    u64w_t x, r;
    x.u = a;
    r.u = mul32x32(x.w[0], b);
    r.w[1] += x.w[1] * b;
    return r.u;
}

/* y^2 modulo 2^64 */
static uint64_t square64(uint64_t y)
{
    u64w_t x, r;
    x.u = y;
    r.u = mul32x32(x.w[0], x.w[0]);
    r.w[1] += (x.w[1] * x.w[0]) << 1;
    return r.u;
}

/* (m * p) >> 16 for a 32-bit m and a 64-bit p (the product below 2^80). */
static uint64_t mulshr16(uint32_t m, uint64_t p)
{
    u64w_t x;
    uint64_t hi, lo;
    x.u = p;
    hi = mul32x32(m, x.w[1]);
    lo = mul32x32(m, x.w[0]);
    return (hi << 16) + (lo >> 16);
}

/* y = sqrt(q / m) (m = 1 or 2), q known exactly modulo 2^64 and approximately as qf: a float
 * estimate corrected once by the exact residual q - m y^2. *inv gets about 1/y (for slopes). */
static float s_inv; /* 1/y of the last root() (one division serves the correction and the slope) */
static uint64_t root(uint64_t q, float qf, uint8_t m)
{
    float yf = sqrtf(m == 2 ? qf * 0.5f : qf), inv;
    uint64_t y0, sq;
    int64_t r;
    float corr;
    if (!(yf >= 1.0f)) {
        s_inv = 0.0f;
        return q != 0 ? 1U : 0U;
    }
    y0 = (uint64_t)yf;
    sq = square64(y0);
    if (m == 2)
        sq <<= 1;
    r = (int64_t)(q - sq);
    inv = 1.0f / yf;
    s_inv = inv;
    corr = (float)r * inv * (m == 2 ? 0.25f : 0.5f);
    return y0 + (int64_t)(corr >= 0.0f ? corr + 0.5f : corr - 0.5f);
}

/* a * b exactly, for a signed 32-bit a and an unsigned 32-bit b */
static int64_t mul_s32_u32(int32_t a, uint32_t b)
{
    return a >= 0 ? (int64_t)mul32x32((uint32_t)a, b) : -(int64_t)mul32x32((uint32_t)-a, b);
}

/* x = (ua^2 - ub^2)/C for ua >= ub, as n + r/C with 0 <= r < C; n saturates at 2^32 - 1. */
static uint32_t steps_between(const step_exact_consts_t *k, uint64_t ua, uint64_t ub, uint64_t *r)
{
    float xf = ((float)ua - (float)ub) * ((float)ua + (float)ub) / k->cu_f;
    int64_t n, rr, adj;
    if (xf >= 4.0e9f) {
        *r = 0;
        return UINT32_MAX;
    }
    n = (int64_t)xf;
    rr = (int64_t)(square64(ua) - square64(ub) - mul64x32(k->cu, (uint32_t)n));
    adj = (int64_t)((float)rr / k->cu_f);
    n += adj;
    rr -= adj * (int64_t)k->cu;
    while (rr < 0) {
        n--;
        rr += (int64_t)k->cu;
    }
    while (rr >= (int64_t)k->cu) {
        n++;
        rr -= (int64_t)k->cu;
    }
    if (n < 0) {
        n = 0;
        rr = 0;
    }
    if (n >= (int64_t)UINT32_MAX) {
        *r = 0;
        return UINT32_MAX;
    }
    *r = (uint64_t)rr;
    return (uint32_t)n;
}

/* ---- parameters and state ----------------------------------------------------------------- */

motion_status_t step_exact_set_params(step_exact_t *e, const ramp_params_t *p)
{
    motion_status_t st = ramp_params_check(p);
    step_exact_consts_t k;
    float a, vmax, v0;
    int ev, e0, ea;
    uint32_t mv, m0, ma;
    uint64_t f = p ? p->tick_hz : 0;
    if (e == 0)
        return MS_ERR_NULL;
    if (st != MS_OK)
        return st;
    a = (float)p->accel_sps2;
    vmax = (float)p->vmax_sps;
    v0 = (float)p->v0_sps;
    /* finite as doubles (checked above) but maybe not as the floats the board holds */
    if (!isfinite(a) || !isfinite(vmax) || !isfinite(v0) || !(vmax > 0.0f))
        return MS_ERR_NOT_FINITE;
    if (f > (1UL << 25))
        return MS_ERR_OUT_OF_RANGE;
    /* C = 2F^2/a below 2^46 ticks^2 */
    if (!(a >= 8.0f * ((float)f / 16.0e6f) * ((float)f / 16.0e6f)) || !(a >= 0.5f))
        return MS_ERR_ACCEL_TOO_LOW;
    /* time to reach vmax from rest, at most 2^34 ticks */
    if (!(vmax / a * (float)f <= 17179869184.0f))
        return MS_ERR_ACCEL_PHASE_TOO_LONG;
    mv = float_mant(vmax, &ev);
    (void)ea;
    ma = float_mant(a, &ea);
    (void)ma;
    k.tick_hz = (uint32_t)f;
    k.cu = ratio64(2U * f * f, a, 16);          /* 2 F^2 / a, u^2 */
    k.vu = ratio64((uint64_t)mv * f, a, ev + 8);  /* vmax F / a, u */
    if (v0 > 0.0f) {
        m0 = float_mant(v0, &e0);
        k.u0 = ratio64((uint64_t)m0 * f, a, e0 + 8);
    } else {
        k.u0 = 0;
    }
    k.p32 = ratio64(f, vmax, 32); /* F / vmax, 2^-32 ticks */
    if (k.cu == 0 || k.cu >= (1ULL << 62) || k.vu == 0 || k.vu >= (1ULL << 42) || k.p32 == 0)
        return MS_ERR_OUT_OF_RANGE;
    k.cu_f = (float)k.cu;
    e->k = k;
    if (e->max_cmd_ticks == 0)
        e->max_cmd_ticks = (uint32_t)(f / 250U); /* 4 ms */
    return MS_OK;
}

void step_exact_reset(step_exact_t *e, int32_t pos)
{
    e->pos = pos;
    e->dir = 0;
    e->d = 0;
    e->n = 0;
    e->n1 = e->n2 = 0;
    e->acc16 = 0;
    e->y = 0;
    e->u_now = 0;
    e->moving = 0;
}

static float p16_f(const step_exact_t *e)
{
    return (float)e->k.p32 * (1.0f / 65536.0f);
}

/* sets up a profile of d steps in direction dir from speed us (d >= the stopping distance) */
static void setup_profile(step_exact_t *e, int8_t dir, uint32_t d, uint64_t us)
{
    const step_exact_consts_t *k = &e->k;
    uint64_t ue = k->u0, vu = k->vu, r1 = 0, r3 = 0, up;
    uint32_t n1, n3;
    uint8_t trapezoid;
    e->dir = dir;
    e->d = d;
    e->n = 0;
    e->acc16 = 0;
    e->us = us;
    e->ue = ue;
    e->us2 = square64(us);
    e->ue2 = square64(ue);
    e->y = us;
    e->a_down = us > vu;
    e->span = e->a_down ? SEG_MAX : 1U;
    e->slope_ok = 0;
    e->in_d = 0;
    if (e->a_down) {
        n1 = steps_between(k, us, vu, &r1);
        n3 = steps_between(k, vu, ue, &r3);
        trapezoid = 1;
    } else {
        n1 = steps_between(k, vu, us, &r1);
        n3 = steps_between(k, vu, ue, &r3);
        if (n1 == UINT32_MAX || n3 == UINT32_MAX || (uint64_t)n1 + n3 > d)
            trapezoid = 0;
        else if ((uint64_t)n1 + n3 + 2U <= d)
            trapezoid = 1;
        else if ((uint64_t)n1 + n3 + 1U == d)
            trapezoid = r1 <= k->cu - r3;
        else
            trapezoid = r1 == 0 && r3 == 0;
    }
    if (trapezoid) {
        uint32_t m;
        float f;
        up = vu;
        e->n2 = d - n3 - (r3 > 0 ? 1U : 0U);
        m = d - n3 - n1;
        f = ((float)r1 + (float)r3) / k->cu_f;
        e->t_end16 = (int64_t)((e->a_down ? us - up : up - us) << 8) + (int64_t)mulshr16(m, k->p32) -
                     (int64_t)(f * p16_f(e)) + (int64_t)((up - ue) << 8);
    } else {
        float qf = (float)k->cu * (float)d + (float)us * (float)us + (float)ue * (float)ue;
        up = root(mul64x32(k->cu, d) + square64(us) + square64(ue), qf, 2);
        if (up < us)
            up = us;
        n1 = steps_between(k, up, us, &r1);
        if (n1 > d)
            n1 = d;
        e->n2 = n1;
        e->t_end16 = (int64_t)(((up - us) + (up - ue)) << 8);
    }
    e->n1 = n1;
    e->r1 = r1;
    e->up = up;
}

motion_status_t step_exact_plan(step_exact_t *e, int32_t to)
{
    uint32_t d = ramp_distance(e->pos, to);
    int8_t dir = ramp_direction(e->pos, to);
    if (e->moving) {
        if (dir != e->dir || step_exact_stop_steps(e) > d)
            return MS_ERR_BUSY;
        setup_profile(e, dir, d, e->u_now);
    } else {
        setup_profile(e, dir, d, e->k.u0);
    }
    return MS_OK;
}

uint32_t step_exact_stop_steps(const step_exact_t *e)
{
    uint64_t r;
    uint32_t n;
    if (!e->moving || e->u_now <= e->k.u0)
        return 0;
    n = steps_between(&e->k, e->u_now, e->k.u0, &r);
    return n + (r > 0 && n < UINT32_MAX ? 1U : 0U);
}

void step_exact_stop(step_exact_t *e)
{
    uint32_t ds = step_exact_stop_steps(e);
    if (!e->moving) {
        e->d = e->n = 0;
        return;
    }
    if (ds == 0) {
        e->d = e->n = 0;
        e->moving = 0;
        return;
    }
    setup_profile(e, e->dir, ds, e->u_now);
}

float step_exact_speed_sps(const step_exact_t *e)
{
    /* v = U a / F = U 2F / (C) (U in u, C in u^2): v = 2 F U / (256 C / 256) */
    if (!e->moving)
        return 0.0f;
    return 2.0f * (float)e->k.tick_hz * (float)e->u_now * 256.0f / e->k.cu_f;
}

/* ---- the time law ---------------------------------------------------------------------------- */

/* region A: y at step n (sqrt(us^2 +- C n)) */
static uint64_t y_a(const step_exact_t *e, uint32_t n)
{
    uint64_t q;
    float qf = (float)e->us * (float)e->us;
    float cn = e->k.cu_f * (float)n;
    if (e->a_down) {
        q = e->us2 - mul64x32(e->k.cu, n);
        qf -= cn;
    } else {
        q = e->us2 + mul64x32(e->k.cu, n);
        qf += cn;
    }
    return root(q, qf, 1);
}

/* region D: y at m steps before the end (sqrt(ue^2 + C m)) */
static uint64_t y_d(const step_exact_t *e, uint32_t m)
{
    float qf = (float)e->ue * (float)e->ue + e->k.cu_f * (float)m;
    return root(e->ue2 + mul64x32(e->k.cu, m), qf, 1);
}

static int64_t t16_a(const step_exact_t *e, uint64_t y)
{
    return (int64_t)((e->a_down ? e->us - y : y - e->us) << 8);
}

static int64_t t16_cruise(const step_exact_t *e, uint32_t n)
{
    float f1p = (float)e->r1 / e->k.cu_f * p16_f(e);
    return (int64_t)((e->a_down ? e->us - e->up : e->up - e->us) << 8) + (int64_t)mulshr16(n - e->n1, e->k.p32) -
           (int64_t)f1p;
}

static int64_t t16_d(const step_exact_t *e, uint64_t y)
{
    return e->t_end16 - (int64_t)((y - e->ue) << 8);
}

/* whether the quadratic over l steps stays within about 0.4 tick: (l s)^3 <= gain y^2
 * (s: interval in u per step, y in u, at the tighter end of the span) */
static uint8_t span_fits(uint32_t l, float s, float y, float gain)
{
    float ls = (float)l * s;
    return ls * ls * ls <= gain * y * y;
}

static uint32_t pow2_at_most(uint32_t lim)
{
    uint32_t l = SEG_MAX;
    while (l > lim)
        l >>= 1;
    return l;
}

/* accelerating: the allowed span only grows, so try twice the last one */
static uint32_t span_growing(step_exact_t *e, float s, float y, uint32_t lim)
{
    uint32_t l = e->span, cap = pow2_at_most(lim);
    if (l > cap)
        l = cap;
    if (l < cap && span_fits(l * 2U, s, y, FIT_GAIN))
        l *= 2U;
    if (l < 1U)
        l = 1U;
    e->span = l;
    return l;
}

/* slowing down: the allowed span only shrinks; the bound is taken at the span's end, where y is
 * smallest (y^2 there is y^2 - C l, in region D and in a deceleration to vmax alike) */
static uint32_t span_shrinking(step_exact_t *e, float y, uint32_t remain)
{
    uint32_t l = e->span, cap = pow2_at_most(remain);
    if (l > cap)
        l = cap;
    while (l > 1U) {
        float q_end = y * y - e->k.cu_f * (float)l;
        float ye = q_end > 0.0f ? sqrtf(q_end) : 0.0f;
        if (ye > 0.0f && span_fits(l, e->k.cu_f * 0.5f / ye, ye, FIT_GAIN))
            break;
        l >>= 1;
    }
    e->span = l;
    return l;
}

static uint8_t log2u(uint32_t l)
{
    uint8_t b = 0;
    while (l > 1U) {
        l >>= 1;
        b++;
    }
    return b;
}

/* one command of l steps ending at target time t16, intervals from slope s0 to s1 (16.16/step).
 * Returns 0 (nothing changed) when a span of l > 1 would need an interval outside 1..65535 ticks:
 * the caller then emits one step (a single step may be WIDE). */
static uint8_t emit(step_exact_t *e, step_cmd_t *c, uint32_t l, int64_t t16, float s0, float s1)
{
    int64_t dt = t16 - e->acc16;
    c->flags = e->dir < 0 ? STEP_CMD_REVERSE : 0;
    c->count = (uint16_t)l;
    if (l > 1U) {
        uint8_t b = log2u(l);
        float addf = ldexpf(s1 - s0, -(int)b);
        int32_t add;
        int64_t tri, rate, last;
        if (!(addf < 2.0e9f && addf > -2.0e9f))
            return 0;
        add = (int32_t)(addf >= 0.0f ? addf + 0.5f : addf - 0.5f);
        tri = mul_s32_u32(add, l * (l - 1U) / 2U);
        rate = (dt - tri + (int64_t)(l >> 1)) >> b;
        last = rate + mul_s32_u32(add, l - 1U);
        if (!(rate > 0 && last > 0 && rate <= (int64_t)RATE_LIMIT && last <= (int64_t)RATE_LIMIT))
            return 0;
        c->rate = (uint32_t)rate;
        c->add = add;
        e->acc16 += (rate << b) + tri;
        return 1;
    }
    c->count = 1;
    if (dt <= (int64_t)RATE_LIMIT) {
        c->rate = (uint32_t)(dt > 0 ? dt : 1);
        c->add = 0;
        e->acc16 += (int64_t)c->rate;
    } else {
        uint32_t w = (uint32_t)((dt + 0x8000) >> 16);
        c->flags |= STEP_CMD_WIDE;
        c->rate = w;
        c->add = 0;
        e->acc16 += (int64_t)w << 16;
    }
    return 1;
}

uint8_t step_exact_next(step_exact_t *e, step_cmd_t *c)
{
    uint32_t n = e->n, l;
    const float k16 = 256.0f; /* u per step -> 16.16 per step */
    if (n >= e->d) {
        if (e->d != 0)
            e->moving = 0;
        return 0;
    }
    if (n < e->n1) {
        /* region A */
        float yf = (float)e->y, s;
        uint64_t y1;
        uint32_t lim = e->n1 - n;
        if (!e->slope_ok)
            e->slope = yf > 0.0f ? e->k.cu_f * 0.5f / yf : 0.0f;
        s = e->slope;
        if (yf <= 0.0f)
            l = 1;
        else if (e->a_down)
            l = span_shrinking(e, yf, lim);
        else
            l = span_growing(e, s, yf, lim);
        for (;;) {
            y1 = y_a(e, n + l);
            e->slope = e->k.cu_f * 0.5f * s_inv;
            if (emit(e, c, l, t16_a(e, y1), s * k16, e->slope * k16))
                break;
            l = 1;
            e->span = 1;
        }
        e->slope_ok = 1;
        e->y = y1;
        e->u_now = y1;
    } else if (n < e->n2) {
        /* cruise */
        float p = p16_f(e);
        uint32_t lim = e->n2 - n, cap = CRUISE_MAX;
        uint32_t by_time = (uint32_t)((float)e->max_cmd_ticks * 65536.0f / p);
        if (by_time < cap)
            cap = by_time > 0 ? by_time : 1U;
        l = lim < cap ? lim : cap;
        if (n == e->n1)
            l = 1; /* the step that straddles the end of the acceleration */
        if (l > 1U && (l & (l - 1U)) != 0) {
            /* quadratic commands need a power of two (shift instead of division); a flat run
             * may take any count: rate = round(dt / l) by the same rule */
            uint32_t pw = 1;
            while (pw * 2U <= l)
                pw *= 2U;
            l = pw;
        }
        if (!emit(e, c, l, t16_cruise(e, n + l), p, p)) {
            l = 1;
            (void)emit(e, c, 1, t16_cruise(e, n + 1), p, p);
        }
        e->u_now = e->up;
        e->y = 0;
        e->slope_ok = 0;
    } else {
        /* region D */
        uint32_t m = e->d - n;
        float yf, s;
        uint64_t y1;
        if (e->y == 0 || n == e->n2 || !e->in_d) {
            e->y = y_d(e, m);
            e->slope = e->k.cu_f * 0.5f * s_inv;
            e->span = SEG_MAX; /* the largest span is at the start of the deceleration */
            e->in_d = 1;
        }
        yf = (float)e->y;
        s = e->slope;
        l = n == e->n2 ? 1U : span_shrinking(e, yf, m);
        for (;;) {
            y1 = y_d(e, m - l);
            e->slope = y1 > 0 ? e->k.cu_f * 0.5f * s_inv : s;
            if (emit(e, c, l, t16_d(e, y1), s * k16, e->slope * k16))
                break;
            l = 1;
        }
        e->y = y1;
        e->u_now = y1;
    }
    c->flags = (uint8_t)((c->flags & (uint8_t)~STEP_CMD_PHASE_MASK) |
                         ((uint8_t)(n < e->n1 ? (e->a_down ? RAMP_DECEL : RAMP_ACCEL)
                                              : (n < e->n2 ? RAMP_CRUISE : RAMP_DECEL))
                          << STEP_CMD_PHASE_SHIFT));
    e->n = n + l;
    e->pos = ramp_position_after(e->pos, e->dir, l);
    e->moving = 1;
    if (e->n >= e->d) {
        e->moving = 0;
        e->u_now = 0;
    }
    return 1;
}
