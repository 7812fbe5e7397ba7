/* closed_form.h - what the step tests compare with, shared by them: constant acceleration from
 * v0 to a peak and back to v0 over d steps, in closed form (long double, seconds), and the tests'
 * deterministic random numbers (xorshift64; define TEST_RNG_SEED before including). */
#ifndef TEST_CLOSED_FORM_H
#define TEST_CLOSED_FORM_H

#include <math.h>
#include <stdint.h>

#ifndef TEST_RNG_SEED
#define TEST_RNG_SEED 88172645463325252ULL
#endif

static uint64_t rng_state = TEST_RNG_SEED;

/* uniform in [a, b) */
static inline double urand(double a, double b)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return a + (b - a) * (double)(rng_state >> 11) / 9007199254740992.0;
}

/* log-uniform in [a, b) */
static inline double lrand(double a, double b)
{
    return exp(urand(log(a), log(b)));
}

/* The move: x_a accelerating steps (as many decelerating), peak speed vp, t_a to reach it, tt in all. */
typedef struct {
    long double v0, a, vp, xa, ta, tt, d;
} closed_t;

static inline closed_t closed_plan(double v0, double vmax, double a, uint32_t d)
{
    closed_t c;
    long double s = ((long double)vmax * vmax - (long double)v0 * v0) / (2.0L * a);
    c.v0 = v0;
    c.a = a;
    c.d = d;
    if (2.0L * s >= (long double)d) {
        c.xa = d / 2.0L;
        c.vp = sqrtl(c.v0 * c.v0 + 2.0L * c.a * c.xa);
    } else {
        c.xa = s;
        c.vp = vmax;
    }
    c.ta = (c.vp - c.v0) / c.a;
    c.tt = 2.0L * c.ta + (c.d - 2.0L * c.xa) / c.vp;
    return c;
}

/* time to cover x steps from v0 at acceleration a */
static inline long double closed_accel_time(const closed_t *c, long double x)
{
    return (sqrtl(c->v0 * c->v0 + 2.0L * c->a * x) - c->v0) / c->a;
}

/* time at which the move has covered x steps */
static inline long double closed_time(const closed_t *c, long double x)
{
    if (x <= c->xa)
        return closed_accel_time(c, x);
    if (x <= c->d - c->xa)
        return c->ta + (x - c->xa) / c->vp;
    return c->tt - closed_accel_time(c, c->d - x);
}

#endif
