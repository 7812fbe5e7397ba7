/* ramp_common.c - shared move geometry and parameter checks of the stepper ramps (see ramp_common.h). */
#include "ramp_common.h"

#include <math.h>

/* True for finite x: x - x is 0 for every finite value and NaN for NaN and +-inf. */
static int ramp_is_finite(double x)
{
    return (x - x) == 0.0;
}

const char *ramp_phase_name(ramp_phase_t phase)
{
    switch (phase) {
    case RAMP_ACCEL: return "accel";
    case RAMP_CRUISE: return "cruise";
    case RAMP_DECEL: return "decel";
    default: return "idle";
    }
}

motion_status_t ramp_params_check(const ramp_params_t *p)
{
    if (p == 0)
        return MS_ERR_NULL;
    if (!ramp_is_finite(p->v0_sps) || !ramp_is_finite(p->vmax_sps) || !ramp_is_finite(p->accel_sps2))
        return MS_ERR_NOT_FINITE;
    if (!(p->accel_sps2 > 0.0))
        return MS_ERR_ACCEL_NOT_POSITIVE;
    if (p->v0_sps < 0.0)
        return MS_ERR_V0_NEGATIVE;
    if (!(p->vmax_sps > p->v0_sps))
        return MS_ERR_VMAX_NOT_ABOVE_V0;
    if (p->tick_hz == 0)
        return MS_ERR_TICK_HZ_ZERO;
    if (p->vmax_sps > (double)p->tick_hz)
        return MS_ERR_VMAX_ABOVE_TICK_HZ;
    return MS_OK;
}

uint32_t ramp_distance(int32_t from, int32_t to)
{
    /* modulo-2^32 difference of the two's-complement bit patterns: exact for any pair */
    return to >= from ? (uint32_t)to - (uint32_t)from : (uint32_t)from - (uint32_t)to;
}

int8_t ramp_direction(int32_t from, int32_t to)
{
    return to > from ? 1 : (to < from ? -1 : 0);
}

int32_t ramp_position_after(int32_t from, int8_t dir, uint32_t n)
{
    uint32_t u = (uint32_t)from;
    u = dir < 0 ? u - n : (dir > 0 ? u + n : u);
    /* the result lies between from and to, so it is a valid int32: convert without overflow */
    return u <= (uint32_t)INT32_MAX ? (int32_t)u : -(int32_t)(~u) - 1;
}

uint32_t ramp_level(uint32_t steps_total, uint32_t peak_level, uint32_t n)
{
    uint32_t from_end = steps_total - n + 1U; /* n >= 1, so no wrap even for D = 2^32 - 1 */
    uint32_t c = n < from_end ? n : from_end;
    return c < peak_level ? c : peak_level;
}

ramp_phase_t ramp_phase_label(uint32_t steps_total, uint32_t accel_steps, uint32_t n)
{
    uint32_t a = accel_steps < steps_total / 2U ? accel_steps : steps_total / 2U;
    if (n <= a)
        return RAMP_ACCEL;
    if (n > steps_total - a)
        return RAMP_DECEL;
    return RAMP_CRUISE;
}

void ramp_accel_steps(float v0_sps, float vmax_sps, float accel_sps2, uint32_t steps_total,
                      float *peak_sps, uint32_t *accel_steps)
{
    /* step 1: eq. (3) */
    float s = (vmax_sps * vmax_sps - v0_sps * v0_sps) / (2.0f * accel_sps2);
    float total = (float)steps_total;
    if (2.0f * s > total) {
        /* step 2: eqs. (4) and (5) */
        *peak_sps = sqrtf(v0_sps * v0_sps + accel_sps2 * total);
        *accel_steps = steps_total / 2U;
    } else {
        uint32_t whole = (uint32_t)s; /* s <= D/2 < 2^31 here: the lab's (long) conversion */
        *peak_sps = vmax_sps;
        /* float rounding of D cannot push S past D/2 */
        *accel_steps = whole < steps_total / 2U ? whole : steps_total / 2U;
    }
}

uint32_t ramp_ticks_from_float(float interval_ticks)
{
    /* Round half up, from the IEEE bit pattern alone (a float add and conversion cost about 235
     * cycles on the AVR, this about 60): for positive floats the patterns order like the values.
     * A float in [0.5, 2^23) is m * 2^(e - 150) with the 24-bit mantissa m and the biased exponent
     * e in 126..149; rounding it is ((m >> (149 - e)) + 1) >> 1, the shift done by bytes first. */
    union {
        float f;
        uint32_t u;
    } v;
    uint32_t m;
    uint8_t k;
    v.f = interval_ticks;
    if ((int32_t)v.u < (int32_t)0x3F000000L)
        return 0; /* below 0.5, zero or negative */
    if (v.u >= 0x4B000000UL)
        return v.u >= 0x4F800000UL ? UINT32_MAX : (uint32_t)interval_ticks; /* whole; >= 2^32, inf, NaN */
    m = (v.u & 0x007FFFFFUL) | 0x00800000UL;
    /* the exponent from the top two bytes (a 23-bit shift would be a 23-pass loop on the AVR) */
    k = (uint8_t)(149U - (uint8_t)(((uint8_t)(v.u >> 24) << 1) | ((uint8_t)(v.u >> 16) >> 7)));
    if (k >= 16U) {
        m >>= 16;
        k = (uint8_t)(k - 16U);
    }
    if (k >= 8U) {
        m >>= 8;
        k = (uint8_t)(k - 8U);
    }
    while (k-- != 0U)
        m >>= 1;
    return (m + 1U) >> 1;
}
