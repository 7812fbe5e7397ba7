/* step_exact.c - exact constant-acceleration step commands in integer arithmetic (see step_exact.h). */
#include "step_exact.h"

#include <math.h>
#include <string.h>

#define SEG_B 7U           /* a quadratic command spans at most 2^SEG_B steps */
_Static_assert(SEG_B == 7U, "emit32's |add| test: 2^(14 - 2b) = (2^(SEG_B - b))^2");
#define CRUISE_MAX 4096U   /* steps one cruise command may span (rate rounding <= 2^-17 tick per step) */
/* (L s)^3 <= FIT_GAIN y^2 keeps a quadratic command within 0.0234 FIT_GAIN u (0.37 tick) of the
 * time law (the span rule below). Not more: an edge may come at most half a tick early (the
 * timeline starts half a tick in), or step_coord's path bound, D s(T + 1 tick), fails. */
#define FIT_GAIN 4000.0f
#define FIT_K 0.0157739336f /* (8 FIT_GAIN)^(-2/5) */
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

/* the bits of a float: for floats >= 0 their order is that of the floats (a cheap comparison) */
static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
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
 * estimate corrected once by the exact residual q - m y^2 (once per profile). */
static uint64_t root(uint64_t q, float qf, uint8_t m)
{
    float yf = sqrtf(m == 2 ? qf * 0.5f : qf), inv;
    uint64_t y0, sq;
    int64_t r;
    float corr;
    if (!(yf >= 1.0f))
        return q != 0 ? 1U : 0U;
    y0 = (uint64_t)yf;
    sq = square64(y0);
    if (m == 2)
        sq <<= 1;
    r = (int64_t)(q - sq);
    inv = 1.0f / yf;
    corr = (float)r * inv * (m == 2 ? 0.25f : 0.5f);
    return y0 + (int64_t)(corr >= 0.0f ? corr + 0.5f : corr - 0.5f);
}

/* The per-command root: y = sqrt(q), the float estimate corrected once by the exact residual
 * (the correction truncated: y within about one u), and *ih = 128/y (float): the slope is C *ih. */
static uint64_t root_ih(uint64_t q, float qf, float *ih)
{
    float yf = sqrtf(qf), h, corr;
    uint64_t y0, sq;
    int64_t r;
    uint32_t lo;
    if (!(yf >= 1.0f)) {
        *ih = 0.0f;
        return q != 0 ? 1U : 0U;
    }
    if (yf < 4294967040.0f) {
        lo = (uint32_t)yf;
        y0 = lo;
        sq = mul32x32(lo, lo);
    } else {
        y0 = (uint64_t)yf;
        sq = square64(y0);
    }
    r = (int64_t)(q - sq);
    h = 128.0f / yf;
    *ih = h;
    h *= 0.00390625f; /* 0.5/y (exactly: a power of two) */
    if (r == (int32_t)r)
        corr = (float)(int32_t)r * h;
    else
        corr = (float)r * h;
    if (corr < 2.0e9f && corr > -2.0e9f) {
        return y0 + (uint64_t)(int64_t)(int32_t)corr;
    }
    return y0 + (uint64_t)(int64_t)corr;
}

/* a * b exactly, for a signed 32-bit a and an unsigned 32-bit b */
static int64_t mul_s32_u32(int32_t a, uint32_t b)
{
    return a >= 0 ? (int64_t)mul32x32((uint32_t)a, b) : -(int64_t)mul32x32((uint32_t)-a, b);
}

/* x = (ua^2 - ub^2)/C for ua >= ub, as n + r/C with 0 <= r < C; n saturates at 2^32 - 1. */
static uint32_t steps_between(const step_exact_consts_t *k, uint64_t ua, uint64_t ub, uint64_t *r)
{
    float xf;
    int64_t n, rr, adj;
    uint64_t dif, sq;
    if (ua == ub) {
        /* what the arithmetic below gives then (x = 0, no remainder), without its cost */
        *r = 0;
        return 0;
    }
    /* ua^2 - ub^2 = (ua - ub)(ua + ub), modulo 2^64 as the result: one product of 64 by 32 bits when
     * ua - ub fits 32 bits (the common case: a stop, a profile's regions) */
    dif = ua - ub;
    sq = (dif >> 32) == 0 ? mul64x32(ua + ub, (uint32_t)dif) : square64(ua) - square64(ub);
    if (sq < k->cu && ((dif | (ua + ub)) >> 32) == 0) {
        /* less than a step (both factors below 2^32: sq is the product itself, not its remainder
         * modulo 2^64), as a profile's peak just above its start (a stop while accelerating): what
         * the float estimate and the loops below give, without their cost */
        *r = sq;
        return 0;
    }
    xf = ((float)ua - (float)ub) * ((float)ua + (float)ub) / k->cu_f;
    if (xf >= 4.0e9f) {
        *r = 0;
        return UINT32_MAX;
    }
    n = (int64_t)xf;
    rr = (int64_t)(sq - mul64x32(k->cu, (uint32_t)n));
    /* the float quotient is within a step or so below 2^22 steps: the loops below finish it; a float
     * correction (a division and a 64-bit product) only when it is farther off (the quotient and the
     * remainder are unique: the same result either way) */
    if (rr < -(int64_t)k->cu || rr >= 2 * (int64_t)k->cu) {
        adj = (int64_t)((float)rr / k->cu_f);
        n += adj;
        rr -= adj * (int64_t)k->cu;
    }
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

/* the constants of p, checked (step_exact_set_params' checks, without an object) */
static motion_status_t exact_consts(const ramp_params_t *p, step_exact_consts_t *out)
{
    motion_status_t st = ramp_params_check(p);
    step_exact_consts_t k;
    float a, vmax, v0;
    int ev, e0;
    uint32_t mv, m0;
    uint64_t f = p ? p->tick_hz : 0;
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
    /* the cruise's interval F/vmax below 2^32 ticks (k.p32 holds it in 2^-32 ticks) */
    if (!((float)f < vmax * 4294967296.0f))
        return MS_ERR_INTERVAL_TOO_LONG;
    mv = float_mant(vmax, &ev);
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
    *out = k;
    return MS_OK;
}

motion_status_t step_exact_check(const ramp_params_t *p)
{
    step_exact_consts_t k;
    return exact_consts(p, &k);
}

motion_status_t step_exact_set_params(step_exact_t *e, const ramp_params_t *p)
{
    step_exact_consts_t k;
    motion_status_t st;
    if (e == 0)
        return MS_ERR_NULL;
    st = exact_consts(p, &k);
    if (st != MS_OK)
        return st;
    e->k = k;
    e->zfit_cu = 0.0f; /* setup_profile works zfit out again */
    if (e->max_cmd_ticks == 0)
        e->max_cmd_ticks = (uint32_t)(k.tick_hz / 250U); /* 4 ms */
    return MS_OK;
}

/* flags */
#define F_ERR 0x01U    /* err holds acc16 - T(n) */
#define F_SMALL 0x02U  /* every y of the profile is below 2^31 (then its radicand converts exactly) */
#define F_CFAST 0x04U  /* a full cruise command fits 32 bits */
#define F_SLOPE 0x08U  /* slope_i is that of step n */
#define F_IN_D 0x10U   /* region D has started (its first y is known) */

void step_exact_reset(step_exact_t *e, int32_t pos)
{
    e->pos = pos;
    e->dir = 0;
    e->d = 0;
    e->n = 0;
    e->n1 = e->n2 = 0;
    e->acc16 = 0;
    e->y = 0;
    e->moving = 0;
    e->zfit_cu = 0.0f; /* (an object set up by hand: zfit is worked out at its first profile) */
}

/* the speed after the last emitted step, u (0 at rest) */
static uint64_t speed_u(const step_exact_t *e)
{
    if (!e->moving)
        return 0;
    return e->y != 0 ? e->y : e->up; /* y is 0 in the cruise */
}

static float p16_f(const step_exact_t *e)
{
    return (float)e->k.p32 * (1.0f / 65536.0f);
}

/* ---- the span rule ---------------------------------------------------------------------------
 * The quadratic of a command (rate, add) follows the time law T = +-(y - y_0) between two exact
 * points l steps apart, with the slopes of both ends; it deviates from it by at most about
 * 0.008 |T^(3)| l^3 = 0.0234 (l s)^3 / y^2 u (s = C/(2y): the interval in u per step; y in u, at
 * the end of the span where y is smallest). So l fits when (l s)^3 <= FIT_GAIN y^2; with s put in,
 * when y^2 >= zfit l^(6/5), zfit = C^(6/5) (8 FIT_GAIN)^(-2/5): a threshold on the radicand q = y^2,
 * which is linear in the step number. Each span 2^j thus has a step from which it fits
 * (accelerating) or up to which it fits (decelerating), found with a few float operations when the
 * span changes; per command the rule is an integer comparison. */

/* 2^j, for j up to SEG_B (a lookup: the AVR shifts one bit at a time) */
static const uint8_t pow2_8[SEG_B + 1U] = {1, 2, 4, 8, 16, 32, 64, 128};
#define SPAN(b) ((uint32_t)pow2_8[b])

/* 2^(6j/5): l^(6/5) for l = 2^j */
static const float span_pow[SEG_B + 1U] = {1.0f, 2.29739671f, 5.27803164f, 12.1257325f,
                                           27.857618f, 64.0f, 147.033389f, 337.794025f};

/* x^(1/5) for x >= 1, to about 3e-5 (Newton's method on the mantissa from a two-piece line;
 * + - * / only: the same bits everywhere) */
static float root5(float x)
{
    int ex, j, i;
    float m = frexpf(x, &ex), t; /* x = m 2^ex */
    j = ex / 5;
    m = ldexpf(m, ex - 5 * j); /* 0.5 <= m < 16 */
    t = m < 4.0f ? 0.84f + 0.1334f * m : 1.2f + 0.03584f * m; /* within 4.2 % */
    for (i = 0; i < 2; i++) {
        float t2 = t * t;
        t = 0.8f * t + 0.2f * m / (t2 * t2);
    }
    return ldexpf(t, j);
}

/* the radicand at the start (A) or the end (D) as a float */
static float qbase_f(const step_exact_t *e)
{
    float u = (float)((e->flags & F_IN_D) ? e->ue : e->us);
    return u * u;
}

/* float steps -> uint32, saturating */
static uint32_t steps_u32(float x)
{
    if (!(x > 0.0f))
        return 0;
    if (x >= 4.0e9f)
        return UINT32_MAX;
    return (uint32_t)x;
}

/* The thresholds, ic = 1/C (one division for a run of span changes). */

/* region A accelerating: the step from which the next span fits */
static uint32_t thr_grow(const step_exact_t *e, float ic)
{
    float x;
    uint32_t t;
    if (e->span_b >= SEG_B)
        return UINT32_MAX;
    x = (e->zfit * span_pow[e->span_b + 1U] - qbase_f(e)) * ic;
    if (!(x > 0.0f))
        return 0;
    t = steps_u32(x);
    return t < UINT32_MAX ? t + 1U : t;
}

/* region A decelerating (from above vmax): the span fits while n + span < thr */
static uint32_t thr_a_down(const step_exact_t *e, float ic)
{
    return steps_u32((qbase_f(e) - e->zfit * span_pow[e->span_b]) * ic);
}

/* region D: the span fits while m (steps left) >= thr */
static uint32_t thr_d(const step_exact_t *e, float ic)
{
    uint32_t x = steps_u32((e->zfit * span_pow[e->span_b] - qbase_f(e)) * ic);
    return x >= UINT32_MAX - (1UL << SEG_B) - 1U ? UINT32_MAX : x + 1U + SPAN(e->span_b);
}

/* the largest b with 2^b <= lim (lim >= 1), at most SEG_B */
static uint8_t b_at_most(uint32_t lim)
{
    uint8_t b = SEG_B;
    while (SPAN(b) > lim)
        b--;
    return b;
}

/* ---- setting up a profile ------------------------------------------------------------------ */

/* 1 when a stop from us (u0 <= us < vmax: a profile of d = ceil(D) steps, D = (us^2 - u0^2)/C)
 * has no cruise because vmax lies two steps or more above us, A = (vu^2 - us^2)/C >= 2: then
 * floor(A) + floor(A + D) > 2A + D - 2 >= D + 1 >= d, the test setup_profile_n3 makes with two
 * divisions (a stop while accelerating cost four, 16,000 cycles on the AVR). Exact, in integers, where
 * both factors are below 2^32 (else 0: the divisions decide). */
static uint8_t stop_no_cruise(const step_exact_consts_t *k, uint64_t us)
{
    uint64_t dv = k->vu - us, sv = k->vu + us;
    if (us >= k->vu || us < k->u0 || ((dv | sv) >> 32) != 0)
        return 0;
    return mul64x32(sv, (uint32_t)dv) >= 2U * k->cu;
}

/* sets up a profile of d steps in direction dir from speed us (d >= the stopping distance) */
/* have_n3: the caller has steps_between(k, vu, u0) already (n3k, r3k: a stop from vmax); stop: d is
 * the stopping distance from us (step_exact_stop) */
static void setup_profile_n3(step_exact_t *e, int8_t dir, uint32_t d, uint64_t us, uint8_t have_n3, uint32_t n3k,
                             uint64_t r3k, uint8_t stop)
{
    const step_exact_consts_t *k = &e->k;
    uint64_t ue = k->u0, vu = k->vu, r1 = 0, r3 = 0, up;
    uint32_t n1, n3, by_time;
    uint8_t trapezoid;
    float p16 = p16_f(e), bt, ic;
    e->dir = dir;
    e->d = d;
    e->n = 0;
    e->acc16 = 0;
    e->us = us;
    e->y = us;
    e->ue = ue;
    e->qr = 0;
    e->a_down = us > vu;
    if (stop && !have_n3 && stop_no_cruise(k, us)) {
        trapezoid = 0; /* (n1 follows from the peak below) */
        n1 = 0;
    } else {
        if (have_n3) {
            n3 = n3k;
            r3 = r3k;
        } else {
            n3 = steps_between(k, vu, ue, &r3);
        }
        if (e->a_down) {
            n1 = steps_between(k, us, vu, &r1);
            trapezoid = 1;
        } else {
            n1 = steps_between(k, vu, us, &r1);
            if (n1 == UINT32_MAX || n3 == UINT32_MAX || (uint64_t)n1 + n3 > d)
                trapezoid = 0;
            else if ((uint64_t)n1 + n3 + 2U <= d)
                trapezoid = 1;
            else if ((uint64_t)n1 + n3 + 1U == d)
                trapezoid = r1 <= k->cu - r3;
            else
                trapezoid = r1 == 0 && r3 == 0;
        }
    }
    if (trapezoid) {
        uint32_t m;
        float f;
        up = vu;
        e->n2 = d - n3 - (r3 > 0 ? 1U : 0U);
        m = d - n3 - n1;
        f = ((float)r1 + (float)r3) / k->cu_f;
        e->t_end16 = (int64_t)((e->a_down ? us - up : up - us) << 8) + (int64_t)mulshr16(m, k->p32) -
                     (int64_t)(f * p16) + (int64_t)((up - ue) << 8);
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
    e->up = up;
    e->flags = F_ERR; /* T(0) = 0 = acc16 */
    if ((us >> 31) == 0 && (up >> 31) == 0)
        e->flags |= F_SMALL;
    e->err = 0;
    /* a function of C alone (a float root and a division): worked out again only when C changed
     * (set_params, or step_coord scaling the constants) */
    if (fbits(e->zfit_cu) != fbits(k->cu_f)) {
        e->zfit = k->cu_f * root5(k->cu_f) * FIT_K;
        e->zfit_cu = k->cu_f;
    }
    /* region A */
    e->q = square64(us);
    ic = 1.0f / k->cu_f;
    if (n1 == 0U) {
        /* no region A (a stop while accelerating: its peak is where it starts): no span to find */
        e->span_b = 0;
        e->thr = 0;
    } else if (e->a_down) {
        e->span_b = SEG_B;
        e->thr = thr_a_down(e, ic);
    } else {
        /* from rest one step; when already moving, the span that fits there: the first whose
         * threshold (thr_grow) is not already passed, the radicand at the start converted once.
         * The test is monotone in b (span_pow grows, float rounding keeps the order): the first is
         * found by bisection, three tests (a stop, or a move continued from speed) instead of seven */
        float qb = qbase_f(e);
        uint8_t b = 0, hi = SEG_B;
        while (b < hi) {
            uint8_t mid = (uint8_t)((b + hi) / 2U);
            if ((e->zfit * span_pow[mid + 1U] - qb) * ic > 0.0f)
                hi = mid;
            else
                b = (uint8_t)(mid + 1U);
        }
        e->span_b = b;
        e->thr = thr_grow(e, ic);
    }
    /* cruise: T(n) = +-((up - us) << 8) - f1p + (n - n1) F/vmax */
    e->f1p = (float)r1 * ic * p16;
    bt = (float)e->max_cmd_ticks * 65536.0f / p16;
    by_time = bt < (float)CRUISE_MAX ? (uint32_t)bt : CRUISE_MAX;
    e->ccap = (uint16_t)(by_time > 0U ? by_time : 1U);
    {
        uint64_t cstep = mul64x32(k->p32, e->ccap); /* below max_cmd_ticks 2^32 */
        uint64_t clr = mul32x32((uint32_t)(k->p32 >> 16), e->ccap);
        e->cst_hi = (uint32_t)(cstep >> 16);
        e->cst_lo = (uint16_t)cstep;
        e->clr = (uint32_t)clr;
        if (e->ccap > 1U && (k->p32 >> 48) == 0U && (cstep >> 48) == 0U && (clr >> 32) == 0U)
            e->flags |= F_CFAST;
    }
}

static void setup_profile(step_exact_t *e, int8_t dir, uint32_t d, uint64_t us)
{
    setup_profile_n3(e, dir, d, us, 0, 0, 0, 0);
}

motion_status_t step_exact_change_params(step_exact_t *e, const ramp_params_t *p)
{
    uint64_t u, cu_old;
    float uf;
    motion_status_t st;
    if (e == 0)
        return MS_ERR_NULL;
    if (!e->moving)
        return step_exact_set_params(e, p);
    u = speed_u(e);
    cu_old = e->k.cu;
    st = step_exact_set_params(e, p);
    if (st != MS_OK)
        return st;
    /* U = v F/a and C = 2F^2/a are both proportional to 1/a: U' = U C'/C keeps v */
    if (e->k.cu != cu_old) {
        uf = (float)u * ((float)e->k.cu / (float)cu_old);
        u = uf >= 1.0f ? (uint64_t)uf : 1U;
    }
    e->y = u;  /* speed_u() reads y, or up in the cruise (y = 0): both hold the speed now */
    e->up = u;
    e->d = e->n; /* the old profile is over: its constants are gone (step_exact_stop keeps none) */
    return MS_OK;
}

motion_status_t step_exact_plan(step_exact_t *e, int32_t to)
{
    uint32_t d = ramp_distance(e->pos, to);
    int8_t dir = ramp_direction(e->pos, to);
    if (e->moving) {
        if (dir != e->dir || step_exact_stop_steps(e) > d)
            return MS_ERR_BUSY;
        setup_profile(e, dir, d, speed_u(e));
    } else {
        setup_profile(e, dir, d, e->k.u0);
    }
    return MS_OK;
}

uint32_t step_exact_stop_steps(const step_exact_t *e)
{
    uint64_t r, u = speed_u(e);
    uint32_t n;
    if (u <= e->k.u0)
        return 0;
    n = steps_between(&e->k, u, e->k.u0, &r);
    return n + (r > 0 && n < UINT32_MAX ? 1U : 0U);
}

uint32_t step_exact_decel_cmds(const step_exact_t *e, float v_sps)
{
    /* U = v F / a = v C / (2F) ticks: in u (C in u^2 = 2^16 ticks^2, U in u = 2^-8 ticks) v cu / (512 F) */
    const float cu = e->k.cu_f, u0 = (float)e->k.u0, ic = 1.0f / cu, u02 = u0 * u0;
    const float us = v_sps * cu / (512.0f * (float)e->k.tick_hz);
    const float zfit = fbits(e->zfit_cu) == fbits(cu) ? e->zfit : cu * root5(cu) * FIT_K;
    /* below the speed whose interval C/(2y) is the longest a span may have (RATE_LIMIT: 65535 ticks,
     * 2^8 u each), every step is a command */
    const float uw = cu * (0.5f / (float)(RATE_LIMIT >> 8)), mw = (uw * uw - u02) * ic;
    float m = (us * us - u02) * ic, low = 0.0f, cmds = (float)(SEG_B + 1U);
    uint8_t b;
    if (!(m > 0.0f))
        return 0;
    if (m > 4.0e9f)
        return UINT32_MAX;
    if (mw > 0.0f) {
        low = mw < m ? mw : m;
        cmds += low;
    }
    /* span 2^b fits while the steps left are at least thr_d's threshold: from there on the steps to
     * the threshold of 2^(b+1) go 2^b a command (and each change of span, and the end, break the
     * steps left into powers of two: SEG_B + 1 commands more at most, counted above) */
    const float zic = zfit * ic, base = 1.0f - u02 * ic;
    float per = 1.0f; /* a command's share of the span's steps, 2^-(b-1) (a multiplication: the AVR's
                         float division costs some 500 cycles; no table: a table of floats is SRAM) */
    for (b = 1; b <= SEG_B && low < m; b++, per *= 0.5f) {
        float thr = zic * span_pow[b] + (base + (float)SPAN(b));
        if (thr > m)
            thr = m;
        if (thr > low) {
            cmds += (thr - low) * per;
            low = thr;
        }
    }
    if (low < m)
        cmds += (m - low) * (1.0f / (float)SPAN(SEG_B));
    return cmds < 4.0e9f ? (uint32_t)cmds + 1U : UINT32_MAX;
}

void step_exact_stop(step_exact_t *e)
{
    /* step_exact_stop_steps, keeping its steps_between: from vmax it is the profile's n3 too */
    uint64_t r = 0, u = speed_u(e);
    uint32_t n = 0, ds = 0;
    if (u > e->k.u0) {
        n = steps_between(&e->k, u, e->k.u0, &r);
        ds = n + (r > 0 && n < UINT32_MAX ? 1U : 0U);
    }
    if (!e->moving) {
        e->d = e->n = 0;
        return;
    }
    if (ds == 0) {
        e->d = e->n = 0;
        e->moving = 0;
        return;
    }
    /* already decelerating to the target at least as soon (the stopping distance is rounded up to
     * whole steps): keep that profile, so that a stop never passes the target */
    if (e->n < e->d && ds >= e->d - e->n)
        return;
    setup_profile_n3(e, e->dir, ds, u, u == e->k.vu, n, r, 1);
}

float step_exact_speed_sps(const step_exact_t *e)
{
    /* v = U a / F = U 2F / (C) (U in u, C in u^2): v = 2 F U / (256 C / 256) */
    if (!e->moving)
        return 0.0f;
    return 2.0f * (float)e->k.tick_hz * (float)speed_u(e) * 256.0f / e->k.cu_f;
}

/* ---- emitting commands ------------------------------------------------------------------------ */

static int64_t t16_y(const step_exact_t *e, uint64_t y)
{
    if (e->flags & F_IN_D)
        return e->t_end16 - (int64_t)((y - e->ue) << 8);
    return (int64_t)((e->a_down ? e->us - y : y - e->us) << 8);
}

/* the slope at step n as a float, 16.16 per step */
static float slope_f(const step_exact_t *e)
{
    if (e->slope_i < 0x40000000UL)
        return (float)e->slope_i;
    return e->y > 0 ? e->k.cu_f * 128.0f / (float)e->y : 0.0f;
}

/* a float slope (>= 0) as an integer, 0x40000000 when not below that */
static uint32_t slope_int(float s)
{
    return fbits(s) < 0x4E800000UL ? (uint32_t)s : 0x40000000UL; /* 0x4E800000: 2^30 */
}

/* one command of 2^b steps ending at target time t16, intervals from slope s0 to s1 (16.16 per
 * step), in 64 bits. Returns 0 (nothing changed) when a span of l > 1 would need an interval
 * outside 1..65535 ticks: the caller then emits one step (a single step may be WIDE). */
static uint8_t emit(step_exact_t *e, step_cmd_t *c, uint8_t b, int64_t t16, float s0, float s1)
{
    uint32_t l = SPAN(b);
    int64_t dt = t16 - e->acc16;
    c->flags = e->dir < 0 ? STEP_CMD_REVERSE : 0;
    c->count = (uint16_t)l;
    c->add = 0;
    if (l > 1U) {
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
    } else if (dt <= (int64_t)RATE_LIMIT) {
        c->rate = (uint32_t)(dt > 0 ? dt : 1);
        e->acc16 += (int64_t)c->rate;
    } else {
        uint32_t w = (uint32_t)((dt + 0x8000) >> 16);
        c->flags |= STEP_CMD_WIDE;
        c->rate = w;
        e->acc16 += (int64_t)w << 16;
    }
    return 1;
}

/* the same for 0 <= dt < 2^32 (16.16 ticks) with the slopes as integers, all in 32 bits; updates
 * acc16 and err. Returns 1, 0 (as emit) or 2 (not for this path: the caller uses emit). */
static uint8_t emit32(step_exact_t *e, step_cmd_t *c, uint8_t b, uint32_t dt, uint32_t s1i)
{
    uint32_t l = SPAN(b);
    int32_t errn;
    c->flags = e->dir < 0 ? STEP_CMD_REVERSE : 0;
    c->count = (uint16_t)l;
    c->add = 0;
    if (l > 1U) {
        int32_t add, d2, dl;
        uint32_t v, rate;
        if ((s1i | e->slope_i) >= 0x40000000UL)
            return 2;
        add = ((int32_t)(s1i - e->slope_i) + (int32_t)(l >> 1)) >> b; /* round((s1 - s0) / l) */
        {
            /* |add| >= 2^(30 - 2b), i.e. |add l^2/2| from 2^29: the high half against 2^(14 - 2b) =
             * (2^(SEG_B - b))^2 (a byte product; the 32-bit shift by 30 - 2b is a loop on the AVR
             * that took some 140 cycles of every ramp command) */
            uint16_t hi = (uint16_t)((uint32_t)(add < 0 ? -add : add) >> 16);
            uint8_t p2 = pow2_8[SEG_B - b];
            if (hi >= (uint16_t)((uint16_t)p2 * p2))
                return 2;
        }
        dl = (int32_t)((uint32_t)add << b) - add;                      /* add (l - 1) */
        d2 = (int32_t)(l >> 1) - (int32_t)((uint32_t)dl << (b - 1U)); /* l/2 - add l (l - 1)/2 */
        v = dt + (uint32_t)d2;
        if (d2 >= 0 ? v < dt : v > dt)
            return 2; /* beyond 2^32 (or below 0) */
        rate = v >> b;
        if (rate == 0U || rate > (uint32_t)RATE_LIMIT ||
            (dl < 0 ? rate <= (uint32_t)-dl : rate > (uint32_t)RATE_LIMIT - (uint32_t)dl))
            return 0;
        c->rate = rate;
        c->add = add;
        /* acc + rate l + tri = acc + dt + l/2 - (v mod l) */
        errn = (int32_t)(l >> 1) - (int32_t)(v & (l - 1U));
    } else {
        if (dt > (uint32_t)RATE_LIMIT)
            return 2;
        c->rate = dt > 0U ? dt : 1U;
        errn = (int32_t)(c->rate - dt);
    }
    e->acc16 += (int64_t)dt + errn;
    e->err = errn;
    return 1;
}

/* one command of 2^b steps in region A or D (down: y falls), nn the step (A) or the steps left (D)
 * at its end: y there exactly, then the quadratic between the slopes. 0: the span needs intervals
 * outside 1..65535 ticks (nothing changed). */
static uint8_t ramp_cmd(step_exact_t *e, step_cmd_t *c, uint8_t b, uint8_t down, uint32_t nn)
{
    uint64_t cl = e->k.cu << b, q = down ? e->q - cl : e->q + cl, y1 = 0;
    float ih, s1 = 0.0f;
    uint32_t s1i = 0;
    uint8_t have = 0;
    if (e->flags & F_SMALL) {
        /* y below 2^31: root_ih's integers with the cheap conversions, and the time in 32 bits */
        float yf = sqrtf((float)q);
        if (fbits(yf) >= 0x3F800000UL) { /* yf >= 1 */
            uint32_t y0 = (uint32_t)yf, y1l;
            int64_t rr = (int64_t)(q - mul32x32(y0, y0));
            float corr;
            ih = 128.0f / yf;
            corr = (rr == (int32_t)rr ? (float)(int32_t)rr : (float)rr) * ih; /* 256 times the correction */
            if ((fbits(corr) & 0x7FFFFFFFUL) < 0x4F000000UL) { /* |corr| < 2^31 */
                uint32_t dy, t, y0l = (uint32_t)e->y;
                int32_t ci = (int32_t)corr;
                y1l = y0 + (ci >= 0 ? (uint32_t)ci >> 8 : 0U - ((uint32_t)-ci >> 8)); /* truncated, as root_ih */
                y1 = y1l;
                s1 = (y1l != 0U || !(e->flags & F_IN_D)) ? e->k.cu_f * ih : slope_f(e);
                s1i = slope_int(s1);
                have = 1;
                dy = down ? y0l - y1l : y1l - y0l;
                t = dy << 8;
                /* dt = T(y1) - acc16 = 256 dy - err */
                if ((e->flags & F_ERR) && y1l != 0U && dy < 0x1000000UL &&
                    (e->err >= 0 ? t >= (uint32_t)e->err : t - (uint32_t)e->err >= t)) {
                    uint8_t r = emit32(e, c, b, t - (uint32_t)e->err, s1i);
                    if (r == 0U)
                        return 0;
                    if (r == 1U)
                        goto done;
                }
            }
        }
    }
    if (!have) {
        /* the general way (the same y, in 64 bits) */
        float qf;
        if (e->flags & F_SMALL) {
            qf = (float)q;
        } else {
            float cn = e->k.cu_f * (float)nn;
            qf = ((e->flags & F_IN_D) || !e->a_down) ? qbase_f(e) + cn : qbase_f(e) - cn;
        }
        y1 = root_ih(q, qf, &ih);
        s1 = (y1 > 0U || !(e->flags & F_IN_D)) ? e->k.cu_f * ih : slope_f(e);
        s1i = slope_int(s1);
    }
    {
        int64_t t16 = t16_y(e, y1), er;
        if (!emit(e, c, b, t16, slope_f(e), s1))
            return 0;
        er = e->acc16 - t16;
        e->err = (int32_t)er;
        e->flags = (uint8_t)((e->flags & ~F_ERR) | (er == (int64_t)e->err ? F_ERR : 0U));
    }
done:
    e->q = q;
    e->y = y1;
    e->slope_i = s1i;
    return 1;
}

/* a full cruise command (ccap steps) in 32 bits from err = acc16 - T(n): rate = round(dt / l) from
 * floor(F/vmax) by at most three corrections; 0 when that does not apply (nothing changed) */
static uint8_t cruise_fast(step_exact_t *e, step_cmd_t *c)
{
    uint32_t f = (uint32_t)e->cfrac + e->cst_lo, delta = e->cst_hi + (f >> 16), l = e->ccap, half = l >> 1;
    uint32_t rate0 = (uint32_t)(e->k.p32 >> 16), rate = rate0, used = e->clr;
    int32_t rem = (int32_t)(delta - used) - e->err; /* dt - l rate, dt = delta - err (both near l F/vmax) */
    uint8_t i;
    for (i = 0; i < 3U; i++) {
        if (rem >= (int32_t)(l - half)) {
            rem -= (int32_t)l;
            rate++;
            used += l;
        } else if (rem < -(int32_t)half) {
            rem += (int32_t)l;
            rate--;
            used -= l;
        } else {
            break;
        }
    }
    if (i == 3U || rate == 0U || rate > (uint32_t)RATE_LIMIT || (rate > rate0 && used < e->clr))
        return 0;
    c->flags = e->dir < 0 ? STEP_CMD_REVERSE : 0;
    c->count = (uint16_t)l;
    c->rate = rate;
    c->add = 0;
    e->acc16 += used;
    e->err = -rem;
    e->cfrac = (uint16_t)f;
    return 1;
}

/* a flat cruise command of l > 1 steps (l <= CRUISE_MAX) to t16: rate = round(dt / l), found from
 * floor(F/vmax) by at most three corrections (no division); 0 when that does not apply */
static uint8_t emit_flat(step_exact_t *e, step_cmd_t *c, uint32_t l, int64_t t16)
{
    int64_t x;
    int32_t rem;
    uint32_t rate, half = l >> 1;
    uint8_t i;
    if ((e->k.p32 >> 48) != 0U)
        return 0; /* an interval beyond 65535 ticks */
    rate = (uint32_t)(e->k.p32 >> 16);
    x = t16 - e->acc16 - (int64_t)mul32x32(rate, l);
    if (x != (int32_t)x)
        return 0;
    rem = (int32_t)x; /* dt - l rate */
    for (i = 0; i < 3U; i++) {
        if (rem >= (int32_t)(l - half)) {
            rem -= (int32_t)l;
            rate++;
        } else if (rem < -(int32_t)half) {
            rem += (int32_t)l;
            rate--;
        } else {
            break;
        }
    }
    if (i == 3U || rate == 0U || rate > (uint32_t)RATE_LIMIT)
        return 0;
    c->flags = e->dir < 0 ? STEP_CMD_REVERSE : 0;
    c->count = (uint16_t)l;
    c->rate = rate;
    c->add = 0;
    e->acc16 = t16 - rem;
    return 1;
}

/* a cruise command from step n; returns its steps. T(n) = acc16 - err from step n1 + 1 on. */
static uint32_t cruise_cmd(step_exact_t *e, step_cmd_t *c, uint32_t n)
{
    uint32_t lim = e->n2 - n, l = lim < e->ccap ? lim : e->ccap;
    int64_t t0;
    uint64_t x;
    if (n == e->n1) {
        /* the step that straddles the end of region A; T(n1) = +-(up - us) - (x1 - n1) F/vmax */
        l = 1;
        e->cfrac = 0;
        t0 = (int64_t)((e->a_down ? e->us - e->up : e->up - e->us) << 8) - (int64_t)e->f1p;
        e->y = 0;
        e->flags &= (uint8_t)~F_SLOPE;
    } else {
        if (l == e->ccap && (e->flags & F_CFAST) && cruise_fast(e, c))
            return l;
        t0 = e->acc16 - e->err;
    }
    x = mul64x32(e->k.p32, l) + e->cfrac;
    if (l == 1U || !emit_flat(e, c, l, t0 + (int64_t)(x >> 16))) {
        float p = p16_f(e);
        if (l > 1U) {
            /* the general way: a power of two (shift instead of division) */
            uint8_t b = b_at_most(l);
            l = SPAN(b);
            x = mul64x32(e->k.p32, l) + e->cfrac;
            if (!emit(e, c, b, t0 + (int64_t)(x >> 16), p, p))
                l = 1;
        }
        if (l == 1U) {
            x = e->k.p32 + e->cfrac;
            (void)emit(e, c, 0, t0 + (int64_t)(x >> 16), p, p);
        }
    }
    e->cfrac = (uint16_t)x;
    e->err = (int32_t)(e->acc16 - (t0 + (int64_t)(x >> 16))); /* within half a tick */
    return l;
}

uint8_t step_exact_next(step_exact_t *e, step_cmd_t *c)
{
    uint32_t n = e->n, l;
    uint8_t phase;
    if (n >= e->d) {
        if (e->d != 0)
            e->moving = 0;
        return 0;
    }
    if (n < e->n1) {
        /* region A */
        uint32_t lim = e->n1 - n;
        uint8_t b = 0;
        if (!(e->flags & F_SLOPE)) {
            e->slope_i = slope_int(e->y > 0 ? e->k.cu_f * 128.0f / (float)e->y : 0.0f);
            e->flags |= F_SLOPE;
        }
        if (e->y != 0) {
            if (e->a_down) {
                if (e->span_b > 0U && !(n + SPAN(e->span_b) < e->thr)) {
                    float ic = 1.0f / e->k.cu_f;
                    do {
                        e->span_b--;
                        e->thr = thr_a_down(e, ic);
                    } while (e->span_b > 0U && !(n + SPAN(e->span_b) < e->thr));
                }
            } else if (e->span_b < SEG_B && n >= e->thr) {
                e->span_b++;
                e->thr = thr_grow(e, 1.0f / e->k.cu_f);
            }
            b = SPAN(e->span_b) > lim ? b_at_most(lim) : e->span_b;
        }
        while (!ramp_cmd(e, c, b, e->a_down, n + SPAN(b))) {
            b = 0;
            e->span_b = 0; /* intervals too long for a span: single steps, growing again */
            e->thr = e->a_down ? UINT32_MAX : n + 1U;
        }
        l = SPAN(b);
        phase = e->a_down ? RAMP_DECEL : RAMP_ACCEL;
    } else if (n < e->n2) {
        l = cruise_cmd(e, c, n);
        phase = RAMP_CRUISE;
    } else {
        /* region D */
        uint32_t m = e->d - n;
        uint8_t b = 0;
        if (n == e->n2 || !(e->flags & F_IN_D)) {
            float ih, f;
            int64_t er;
            e->flags |= F_IN_D;
            e->q = square64(e->k.u0) + e->qr + mul64x32(e->k.cu, m);
            f = qbase_f(e) + e->k.cu_f * (float)m;
            e->y = root_ih(e->q, (e->flags & F_SMALL) ? (float)e->q : f, &ih);
            e->slope_i = slope_int(e->k.cu_f * ih);
            er = e->acc16 - t16_y(e, e->y);
            e->err = (int32_t)er;
            e->flags = (uint8_t)((e->flags & ~F_ERR) | (er == (int64_t)e->err ? F_ERR : 0U));
            e->span_b = SEG_B; /* the largest span is at the start of the deceleration */
            e->thr = thr_d(e, 1.0f / e->k.cu_f);
        }
        if (n != e->n2) {
            if (e->span_b > 0U && m < e->thr) {
                float ic = 1.0f / e->k.cu_f;
                do {
                    e->span_b--;
                    e->thr = thr_d(e, ic);
                } while (e->span_b > 0U && m < e->thr);
            }
            b = SPAN(e->span_b) > m ? b_at_most(m) : e->span_b;
        }
        while (!ramp_cmd(e, c, b, 1, m - SPAN(b))) {
            b = 0;
            e->span_b = 0; /* spans only shrink here */
            e->thr = 0;
        }
        l = SPAN(b);
        phase = RAMP_DECEL;
    }
    c->flags |= (uint8_t)(phase << STEP_CMD_PHASE_SHIFT); /* the emitters leave the phase bits 0 */
    e->n = n + l;
    e->pos = ramp_position_after(e->pos, e->dir, l);
    e->moving = 1;
    if (e->n >= e->d)
        e->moving = 0;
    return 1;
}

/* ---- back to an earlier command boundary (step_exact_rewind) ---------------------------------- */

int64_t step_exact_cmd_time16(const step_cmd_t *c)
{
    uint32_t l = c->count;
    if (c->flags & STEP_CMD_WIDE)
        return (int64_t)(mul32x32(c->rate, l) << 16);
    /* sum of rate + (j - 1) add for j = 1..count */
    return (int64_t)mul32x32(c->rate, l) + mul_s32_u32(c->add, l * (l - 1U) / 2U);
}

/* |acc16 - T(n)| the executor's timeline can be from the time law at a boundary: the planner keeps
 * it within about a tick; more means n or acc16 is not one of the profile's boundaries */
#define REWIND_ERR_MAX 0x100000L /* 16 ticks */

/* y at a boundary of region A (nn: the step) or D (nn: the steps left) from its exact radicand q,
 * as ramp_cmd works it out (the same float estimate, the same correction: the same bits) */
static __attribute__((noinline)) uint64_t y_at(const step_exact_t *s, uint64_t q, uint32_t nn, float *ih)
{
    float qf;
    if (s->flags & F_SMALL) {
        qf = (float)q;
    } else {
        float cn = s->k.cu_f * (float)nn;
        qf = ((s->flags & F_IN_D) || !s->a_down) ? qbase_f(s) + cn : qbase_f(s) - cn;
    }
    return root_ih(q, qf, ih);
}

/* the span step_exact_next's loop arrives at, at step p of region A decelerating (the span fits
 * while p + span < thr; the spans that fit only shrink as p grows, so it is the largest that fits) */
static void fit_a_down(step_exact_t *s, uint32_t p, float ic)
{
    s->span_b = SEG_B;
    s->thr = thr_a_down(s, ic);
    while (s->span_b > 0U && !(p + SPAN(s->span_b) < s->thr)) {
        s->span_b--;
        s->thr = thr_a_down(s, ic);
    }
}

/* the same in region D with m steps left (the span fits while m >= thr) */
static __attribute__((noinline)) void fit_d(step_exact_t *s, uint32_t m, float ic)
{
    s->span_b = SEG_B;
    s->thr = thr_d(s, ic);
    while (s->span_b > 0U && m < s->thr) {
        s->span_b--;
        s->thr = thr_d(s, ic);
    }
}

/* log2 of a count of 1..2^SEG_B steps; SEG_B + 1 when it is no such power of two */
static uint8_t span_of(uint16_t count)
{
    uint8_t b;
    for (b = 0; b <= SEG_B; b++)
        if (SPAN(b) == count)
            return b;
    return SEG_B + 1U;
}

/* the radicand region A left behind at step at (<= n1) */
static __attribute__((noinline)) uint64_t q_a(const step_exact_t *s, uint32_t at)
{
    uint64_t cl = mul64x32(s->k.cu, at), u2 = square64(s->us);
    return s->a_down ? u2 - cl : u2 + cl;
}

uint8_t step_exact_profile_intact(const step_exact_t *e)
{
    step_exact_t s;
    if (e == 0 || e->d == 0)
        return 0;
    /* the profile's constants again from its start (dir, d, us) */
    s = *e;
    setup_profile(&s, e->dir, e->d, e->us);
    return s.n1 == e->n1 && s.n2 == e->n2 && s.up == e->up && s.t_end16 == e->t_end16 && s.a_down == e->a_down &&
           fbits(s.zfit) == fbits(e->zfit) && fbits(s.f1p) == fbits(e->f1p) && s.ccap == e->ccap &&
           s.clr == e->clr && s.cst_hi == e->cst_hi && s.cst_lo == e->cst_lo &&
           (s.flags & (F_SMALL | F_CFAST)) == (e->flags & (F_SMALL | F_CFAST));
}

motion_status_t step_exact_rewind(step_exact_t *e, uint32_t n, int64_t acc16, uint16_t last_count)
{
    step_exact_t s;
    uint32_t p;
    uint8_t base, b;
    uint64_t q_now;
    int64_t t, er;
    float ic, ih;
    if (e == 0)
        return MS_ERR_NULL;
    if (e->d == 0 || (e->moving && e->n >= e->d) || n == 0 || n > e->n || last_count == 0 || last_count > n)
        return MS_ERR_OUT_OF_RANGE;
    s = *e;
    base = (uint8_t)(s.flags & (F_SMALL | F_CFAST));
    /* C (and v0) exactly as planned: the radicand of the state now */
    if (e->flags & F_IN_D)
        q_now = square64(e->k.u0) + e->qr + mul64x32(e->k.cu, e->d - e->n);
    else
        q_now = q_a(e, e->n < e->n1 ? e->n : e->n1);
    if (q_now != e->q)
        return MS_ERR_OUT_OF_RANGE;
    /* the state after the command of last_count steps from step p to step n */
    p = n - last_count;
    b = span_of(last_count);
    if (p < s.n1) {
        /* region A: y, its slope and the span at step n */
        if (n > s.n1 || last_count > SPAN(SEG_B))
            return MS_ERR_OUT_OF_RANGE;
        ic = 1.0f / s.k.cu_f;
        s.flags = (uint8_t)(base | F_SLOPE | F_ERR);
        s.q = q_a(&s, n);
        s.y = y_at(&s, s.q, n, &ih);
        s.slope_i = slope_int(s.k.cu_f * ih);
        if (s.a_down) {
            uint32_t lim = s.n1 - p;
            uint8_t want;
            fit_a_down(&s, p, ic);
            want = SPAN(s.span_b) > lim ? b_at_most(lim) : s.span_b;
            if (b != want && !(last_count > 1U && last_count < SPAN(want))) {
                if (b != 0U)
                    return MS_ERR_OUT_OF_RANGE;
                s.span_b = 0; /* the span did not fit the intervals: single steps from here on */
                s.thr = UINT32_MAX;
            }
            /* (the first last_count steps of that command, the rest cut: the span fitted at p, which
             * the next command shrinks as it needs) */
        } else {
            /* the span grows by one a command at most, and a command has the span (or, near n1,
             * fewer steps: then every later command of region A is as short as n1 - n allows,
             * whatever the span; after a span that did not fit, 0 and growing again). The first
             * last_count steps of a longer command (the rest cut: no power of two): the largest span
             * within them, which fits at n as it did at p (the spans that fit only grow here) */
            s.span_b = b <= SEG_B ? b : b_at_most(last_count);
            s.thr = thr_grow(&s, ic);
        }
        t = t16_y(&s, s.y);
    } else if (p < s.n2) {
        /* the cruise: T(n) = T(n1) + (n - n1) F/vmax, the fraction below 2^-16 ticks in cfrac */
        if (n > s.n2 || last_count > s.ccap || (p == s.n1 && last_count != 1U))
            return MS_ERR_OUT_OF_RANGE;
        s.flags = (uint8_t)(base | F_ERR);
        /* q_a(&s, s.n1): the state's own radicand (checked above) unless it is already in region D */
        s.q = (e->flags & F_IN_D) ? q_a(&s, s.n1) : q_now;
        s.y = 0;
        s.cfrac = (uint16_t)mul64x32(s.k.p32, n - s.n1);
        t = (int64_t)((s.a_down ? s.us - s.up : s.up - s.us) << 8) - (int64_t)s.f1p +
            (int64_t)mulshr16(n - s.n1, s.k.p32);
        /* span_b, thr and slope_i are not read in the cruise: region D sets its own */
    } else {
        /* region D */
        uint32_t m = s.d - n, mp = s.d - p;
        if (last_count > SPAN(SEG_B))
            return MS_ERR_OUT_OF_RANGE;
        ic = 1.0f / s.k.cu_f;
        s.flags = (uint8_t)(base | F_IN_D | F_ERR);
        s.q = square64(s.k.u0) + s.qr + mul64x32(s.k.cu, m);
        s.y = y_at(&s, s.q, m, &ih);
        s.slope_i = slope_int(s.k.cu_f * ih);
        if (p == s.n2) {
            /* region D's first command: one step, the largest span next */
            if (b != 0U)
                return MS_ERR_OUT_OF_RANGE;
            s.span_b = SEG_B;
            s.thr = thr_d(&s, ic);
        } else {
            uint8_t want;
            fit_d(&s, mp, ic);
            want = SPAN(s.span_b) > mp ? b_at_most(mp) : s.span_b;
            /* (the first last_count steps of that command, the rest cut: as in region A decelerating) */
            if (b != want && !(last_count > 1U && last_count < SPAN(want))) {
                if (b != 0U)
                    return MS_ERR_OUT_OF_RANGE;
                s.span_b = 0; /* as step_exact_next after a span that did not fit */
                s.thr = 0;
            }
        }
        t = t16_y(&s, s.y);
    }
    er = acc16 - t;
    if (er > REWIND_ERR_MAX || er < -REWIND_ERR_MAX)
        return MS_ERR_OUT_OF_RANGE;
    s.err = (int32_t)er;
    s.acc16 = acc16;
    s.n = n;
    s.pos = ramp_position_after(e->pos, (int8_t)-e->dir, e->n - n);
    s.moving = n < s.d;
    *e = s;
    return MS_OK;
}

/* ---- a stop while accelerating (from rest or a speed), begun with the acceleration reversed ---- */

uint8_t step_exact_mirror_ok(const step_exact_t *e, uint32_t n)
{
    /* region A accelerating (a move from rest, or one continued from speed), n at least two steps
     * before its end (the stop from there is a profile of its own: it never keeps this one's
     * deceleration) */
    return e != 0 && e->moving && e->d != 0 && !e->a_down && e->us >= e->k.u0 && n >= 4U && n <= e->n &&
           n + 2U <= e->n1;
}

__attribute__((noinline)) motion_status_t step_exact_stop_mirrored(step_exact_t *e, uint32_t n, uint32_t steps,
                                                                   int64_t time16)
{
    step_exact_t s;
    float ic, ih;
    int64_t er;
    uint64_t r, qe;
    uint32_t m, d;
    if (!step_exact_mirror_ok(e, n) || steps == 0 || steps + 2U > n)
        return MS_ERR_OUT_OF_RANGE;
    s = *e;
    /* the speed at step n, as the rewind works it out in region A (the radicand us^2 + n C exactly) */
    s.flags = (uint8_t)(e->flags & (F_SMALL | F_CFAST));
    s.q = q_a(&s, n);
    s.y = y_at(&s, s.q, n, &ih);
    s.pos = ramp_position_after(e->pos, (int8_t)-e->dir, e->n - n);
    /* the stop from there passes the acceleration's radicands us^2 + j C again, j = n, n - 1, ..., and
     * those below its start, down to the last one at or above u0^2: u0^2 + r, r < C, after
     * d = n + floor((us^2 - u0^2) / C) steps (from rest: n steps, r = 0). A profile whose peak is
     * where it starts, its deceleration on those radicands: it ends at sqrt(u0^2 + r), within a step's
     * speed change above v0 (a stop planned from a speed rounds its distance up to whole steps
     * instead, with a peak a little above its start) */
    d = steps_between(&s.k, s.us, s.k.u0, &r);
    if (d >= UINT32_MAX - n)
        return MS_ERR_OUT_OF_RANGE;
    d += n;
    setup_profile_n3(&s, e->dir, d, s.y, 0, 0, 0, 1);
    qe = square64(s.k.u0) + r; /* the radicand at the end, modulo 2^64 */
    if (r != 0) {
        float u0f = (float)s.k.u0;
        s.qr = r;
        s.ue = root(qe, u0f * u0f + (float)r, 1); /* (its size as a float) */
        s.t_end16 = (int64_t)(((s.up - s.us) + (s.up - s.ue)) << 8);
    }
    /* after its first `steps` steps (the acceleration's last ones reversed, time16 in the executor's
     * time): region D with m steps left, as step_exact_rewind builds it there */
    m = d - steps;
    ic = 1.0f / s.k.cu_f;
    s.flags = (uint8_t)((s.flags & (F_SMALL | F_CFAST)) | F_IN_D | F_ERR);
    s.q = qe + mul64x32(s.k.cu, m);
    s.y = y_at(&s, s.q, m, &ih);
    s.slope_i = slope_int(s.k.cu_f * ih);
    fit_d(&s, m, ic);
    er = time16 - t16_y(&s, s.y);
    s.err = (int32_t)er;
    if (er != (int64_t)s.err)
        s.flags &= (uint8_t)~F_ERR;
    s.acc16 = time16;
    s.n = steps;
    s.pos = ramp_position_after(s.pos, s.dir, steps);
    s.moving = 1;
    *e = s;
    return MS_OK;
}
