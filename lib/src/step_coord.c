/* step_coord.c - coordinated moves: one profile, each axis its own exact ramp (see step_coord.h). */
#include "step_coord.h"

#define CU_LIMIT (1ULL << 62) /* step_exact's bound on C (u^2 per step) */

/* round(a * b / c) for c > 0; 0 when the result does not fit 63 bits. 96-bit product by 32-bit
 * words, then long division by 64/32-bit steps (no 128-bit type on the AVR). */
static uint8_t muldiv_u64(uint64_t a, uint32_t b, uint32_t c, uint64_t *out)
{
    uint64_t lo = (uint64_t)(uint32_t)a * b, hi = (a >> 32) * (uint64_t)b, mid, cur, r, q1, q0, q2;
    uint32_t w0, w1, w2;
    w0 = (uint32_t)lo;
    mid = (lo >> 32) + (uint32_t)hi;
    w1 = (uint32_t)mid;
    w2 = (uint32_t)((hi >> 32) + (mid >> 32));
    q2 = w2 / c;
    r = w2 % c;
    cur = (r << 32) | w1;
    q1 = cur / c;
    r = cur % c;
    cur = (r << 32) | w0;
    q0 = cur / c;
    r = cur % c;
    if (q2 != 0 || q1 >= 0x80000000ULL)
        return 0;
    *out = (q1 << 32) + q0 + (2U * r >= c ? 1U : 0U);
    return 1;
}

motion_status_t step_coord_profile(uint8_t n_axes, const ramp_params_t p[], const uint32_t d[], ramp_params_t *profile)
{
    uint8_t i, m = 0, any = 0;
    ramp_params_t q;
    motion_status_t st;
    if (p == 0 || d == 0 || profile == 0)
        return MS_ERR_NULL;
    if (n_axes == 0 || n_axes > STEP_COORD_MAX_AXES)
        return MS_ERR_OUT_OF_RANGE;
    for (i = 0; i < n_axes; i++) {
        st = ramp_params_check(&p[i]);
        if (st != MS_OK)
            return st;
        if (p[i].tick_hz != p[0].tick_hz)
            return MS_ERR_OUT_OF_RANGE;
        if (d[i] > d[m])
            m = i;
        if (d[i] > 0)
            any = 1;
    }
    if (!any)
        return MS_ERR_OUT_OF_RANGE;
    q.tick_hz = p[0].tick_hz;
    q.v0_sps = q.vmax_sps = q.accel_sps2 = 0.0;
    for (i = 0; i < n_axes; i++) {
        double k, v0, vmax, a;
        if (d[i] == 0)
            continue;
        k = (double)d[m] / (double)d[i]; /* 1 / r_i */
        v0 = p[i].v0_sps * k;
        vmax = p[i].vmax_sps * k;
        a = p[i].accel_sps2 * k;
        if (q.vmax_sps == 0.0 || v0 < q.v0_sps)
            q.v0_sps = v0;
        if (q.vmax_sps == 0.0 || a < q.accel_sps2)
            q.accel_sps2 = a;
        if (q.vmax_sps == 0.0 || vmax < q.vmax_sps)
            q.vmax_sps = vmax;
    }
    *profile = q;
    return MS_OK;
}

motion_status_t step_coord_plan(step_coord_t *c, uint8_t n_axes, const ramp_params_t p[], const int32_t from[],
                                const int32_t to[])
{
    uint32_t d[STEP_COORD_MAX_AXES];
    uint8_t i, m = 0;
    motion_status_t st;
    step_exact_t master;
    if (c == 0 || p == 0 || from == 0 || to == 0)
        return MS_ERR_NULL;
    if (n_axes == 0 || n_axes > STEP_COORD_MAX_AXES)
        return MS_ERR_OUT_OF_RANGE;
    for (i = 0; i < n_axes; i++) {
        d[i] = ramp_distance(from[i], to[i]);
        if (d[i] > d[m])
            m = i;
    }
    st = step_coord_profile(n_axes, p, d, &c->profile);
    if (st != MS_OK)
        return st;
    master.max_cmd_ticks = 0;
    st = step_exact_set_params(&master, &c->profile);
    if (st != MS_OK)
        return st;
    c->n_axes = n_axes;
    c->master = m;
    for (i = 0; i < n_axes; i++) {
        step_exact_t *e = &c->ax[i];
        c->from[i] = from[i];
        c->to[i] = to[i];
        c->d[i] = d[i];
        e->k = master.k;
        e->max_cmd_ticks = master.max_cmd_ticks;
        if (d[i] != 0 && d[i] != d[m]) {
            /* C_i = C_m D_m / D_i, (F/vmax)_i = (F/vmax)_m D_m / D_i */
            uint64_t cu, p32;
            if (!muldiv_u64(master.k.cu, d[m], d[i], &cu) || cu >= CU_LIMIT ||
                !muldiv_u64(master.k.p32, d[m], d[i], &p32))
                return MS_ERR_COORD_RATIO;
            e->k.cu = cu;
            e->k.cu_f = (float)cu;
            e->k.p32 = p32;
        }
        step_exact_reset(e, from[i]);
        st = step_exact_plan(e, to[i]);
        if (st != MS_OK)
            return st;
    }
    /* one end for all: the master's T_end (the others' agree with it far below a tick; taking the
     * same value puts every axis's last step on the same tick) */
    for (i = 0; i < n_axes; i++)
        if (d[i] != 0)
            c->ax[i].t_end16 = c->ax[m].t_end16;
    return MS_OK;
}

uint8_t step_coord_next(step_coord_t *c, uint8_t axis, step_cmd_t *cmd)
{
    step_exact_t *e;
    int64_t before;
    if (axis >= c->n_axes)
        return 0;
    e = &c->ax[axis];
    before = e->acc16;
    if (!step_exact_next(e, cmd))
        return 0;
    if ((cmd->flags & STEP_CMD_WIDE) && e->n >= e->d && e->d == c->d[axis]) {
        /* the last step, a WIDE one: step_exact rounds its whole interval and leaves the timeline's
         * fraction as it was; put the edge on the tick of T_end itself (the timeline starts half a
         * tick into a tick, as the executor's and the engine's do), so every axis ends on it */
        int64_t half = 0x8000;
        int64_t w = ((half + e->t_end16) >> 16) - ((half + before) >> 16);
        if (w > 0xFFFF) {
            cmd->rate = (uint32_t)w;
            e->acc16 = before + (w << 16);
        }
    }
    return 1;
}

uint8_t step_coord_busy(const step_coord_t *c, uint8_t axis)
{
    if (axis >= c->n_axes)
        return 0;
    return c->ax[axis].n < c->ax[axis].d;
}

int32_t step_coord_position(const step_coord_t *c, uint8_t axis)
{
    return c->ax[axis].pos;
}

int64_t step_coord_horizon16(const step_coord_t *c, uint8_t axis)
{
    return c->ax[axis].acc16;
}

/* steps from the start to where axis i can come to rest soonest (its position if not moving) */
static uint32_t soonest_rest(const step_coord_t *c, uint8_t i)
{
    const step_exact_t *e = &c->ax[i];
    uint32_t made = ramp_distance(c->from[i], e->pos);
    if (e->moving && e->n < e->d)
        made += step_exact_stop_steps(e);
    return made < c->d[i] ? made : c->d[i];
}

void step_coord_stop(step_coord_t *c)
{
    uint8_t i, k = c->master;
    uint32_t kk = 0, soonest[STEP_COORD_MAX_AXES];
    /* the axis that can stop on the line furthest along it (the largest s) sets the point where all
     * come to rest: s* = k_k / D_k; every other axis can still reach round(D_i s*) (each axis's
     * soonest rest worked out once: a stopping distance costs 64-bit arithmetic, a millisecond or so
     * of the AVR's for two axes, and a StepperGroup's stop at a cut of its queues waits for it) */
    for (i = 0; i < c->n_axes; i++) {
        if (c->d[i] == 0)
            continue;
        soonest[i] = soonest_rest(c, i);
        if ((uint64_t)soonest[i] * c->d[k] > (uint64_t)kk * c->d[i]) {
            k = i;
            kk = soonest[i];
        }
    }
    for (i = 0; i < c->n_axes; i++) {
        step_exact_t *e = &c->ax[i];
        uint32_t ki;
        int32_t want;
        if (c->d[i] == 0)
            continue;
        ki = (uint32_t)(((uint64_t)c->d[i] * kk + c->d[k] / 2U) / c->d[k]);
        if (ki < soonest[i])
            ki = soonest[i]; /* rounding: never short of where it can stop */
        want = ramp_position_after(c->from[i], ramp_direction(c->from[i], c->to[i]), ki);
        if (e->moving && e->n < e->d) {
            if (step_exact_plan(e, want) != MS_OK)
                step_exact_stop(e);
        } else {
            step_exact_reset(e, e->pos);
            if (want == e->pos || step_exact_plan(e, want) != MS_OK)
                e->d = e->n = 0;
        }
        c->to[i] = e->d > e->n ? ramp_position_after(e->pos, e->dir, e->d - e->n) : e->pos;
    }
}

motion_status_t step_coord_rewind(step_coord_t *c, uint8_t axis, uint32_t steps, int64_t time16, uint16_t last_count)
{
    step_exact_t *e;
    if (axis >= c->n_axes)
        return MS_ERR_OUT_OF_RANGE;
    e = &c->ax[axis];
    if (!e->moving || steps >= e->n)
        return MS_ERR_OUT_OF_RANGE;
    return step_exact_rewind(e, e->n - steps, e->acc16 - time16, last_count);
}

int32_t step_coord_target(const step_coord_t *c, uint8_t axis)
{
    return c->to[axis];
}

void step_coord_halt(step_coord_t *c, uint8_t axis, int32_t pos)
{
    if (axis >= c->n_axes)
        return;
    step_exact_reset(&c->ax[axis], pos);
    c->to[axis] = pos;
}
