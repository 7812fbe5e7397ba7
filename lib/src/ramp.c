/* ramp.c - the move planner: dispatches each step to the chosen ramp algorithm (see ramp.h). */
#include "ramp.h"

const char *ramp_algo_name(ramp_algo_t algo)
{
    switch (algo) {
    case RAMP_ALGO_SIMPLISTIC: return "simplistic";
    case RAMP_ALGO_LEIB: return "leib";
    case RAMP_ALGO_EXACT: return "exact";
    case RAMP_ALGO_SIGMOID: return "sigmoid";
    default: return "?";
    }
}

/* ramp_phase_label with its bound computed at plan time (a 32-bit division costs about 600
 * cycles on the AVR: once per move, not once per step) */
static void set_label_bound(ramp_t *r)
{
    uint32_t half = r->steps_total / 2U;
    r->label_accel = r->accel_steps < half ? r->accel_steps : half;
}

static ramp_phase_t phase_label(const ramp_t *r, uint32_t n)
{
    if (n <= r->label_accel)
        return RAMP_ACCEL;
    if (n > r->steps_total - r->label_accel)
        return RAMP_DECEL;
    return RAMP_CRUISE;
}

/* the simplistic pre-computation: the sketch's (hooks) or lib's */
static motion_status_t simplistic_plan(const ramp_hooks_t *h, const ramp_params_t *params, ramp_simplistic_t *s,
                                       uint32_t steps_total)
{
    if (h != 0 && h->simplistic_plan != 0)
        return h->simplistic_plan(s, params, steps_total);
    return ramp_simplistic_plan(s, params, steps_total);
}

static void plan_geometry(ramp_t *r, ramp_algo_t algo, int32_t from, int32_t to)
{
    r->algo = algo;
    r->from = from;
    r->to = to;
    r->dir = ramp_direction(from, to);
    r->steps_total = ramp_distance(from, to);
    r->steps_done = 0;
    r->level = 0;
    r->whole_ticks = 0;
    r->start_level = 0;
    r->hooks = 0;
}

motion_status_t ramp_plan(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, int32_t from, int32_t to)
{
    return ramp_plan_hooked(r, algo, params, 0, from, to);
}

motion_status_t ramp_plan_hooked(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, const ramp_hooks_t *hooks,
                                 int32_t from, int32_t to)
{
    ramp_t n;
    motion_status_t st;
    if (r == 0 || params == 0)
        return MS_ERR_NULL;
    plan_geometry(&n, algo, from, to);
    switch (algo) {
    case RAMP_ALGO_SIMPLISTIC:
        st = simplistic_plan(hooks, params, &n.u.simplistic, n.steps_total);
        n.accel_steps = n.u.simplistic.accel_steps;
        n.peak_level = n.accel_steps + 1U;
        break;
    case RAMP_ALGO_LEIB:
        st = hooks != 0 && hooks->leib_plan != 0 ? hooks->leib_plan(&n.u.leib, params, n.steps_total)
                                                 : ramp_leib_plan(&n.u.leib, params, n.steps_total);
        n.accel_steps = n.u.leib.accel_steps;
        n.peak_level = n.accel_steps;
        break;
    case RAMP_ALGO_EXACT:
        st = ramp_exact_plan(&n.u.exact, params, n.steps_total);
        n.accel_steps = 0; /* phases come from the exact positions (ramp_exact_phase) */
        n.peak_level = 0;
        break;
    default:
        return MS_ERR_UNKNOWN_COMMAND;
    }
    if (st != MS_OK)
        return st;
    n.hooks = hooks;
    set_label_bound(&n);
    *r = n;
    return MS_OK;
}

motion_status_t ramp_plan_sigmoid(ramp_t *r, const ramp_sigmoid_params_t *p, const uint16_t *table,
                                  uint16_t table_len, int32_t from, int32_t to)
{
    ramp_t n;
    motion_status_t st;
    if (r == 0 || p == 0)
        return MS_ERR_NULL;
    plan_geometry(&n, RAMP_ALGO_SIGMOID, from, to);
    st = ramp_sigmoid_plan(&n.u.sigmoid, p, table, table_len);
    if (st != MS_OK)
        return st;
    n.accel_steps = ramp_sigmoid_accel_steps(p);
    n.peak_level = 0;
    set_label_bound(&n);
    *r = n;
    return MS_OK;
}

uint32_t ramp_steps_left(const ramp_t *r)
{
    return r->steps_total - r->steps_done;
}

/* c(n) = min(L0 + n, D + 1 - n, max(K, L0 - n)); from rest (L0 = 0) this is ramp_level */
static uint32_t level_of(const ramp_t *r, uint32_t n)
{
    uint32_t l0 = r->start_level, from_end, c, k;
    if (l0 == 0)
        return ramp_level(r->steps_total, r->peak_level, n);
    from_end = r->steps_total - n + 1U;
    c = l0 + n < from_end ? l0 + n : from_end;
    k = n < l0 && l0 - n > r->peak_level ? l0 - n : r->peak_level;
    return c < k ? c : k;
}

int32_t ramp_position(const ramp_t *r)
{
    return ramp_position_after(r->from, r->dir, r->steps_done);
}

uint32_t ramp_stop_steps(const ramp_t *m)
{
    uint32_t lv = m->level;
    if (m->steps_done == 0 && m->start_level == 0)
        return 0;
    if (m->algo == RAMP_ALGO_SIGMOID && lv > m->accel_steps)
        lv = m->accel_steps; /* k keeps counting through the cruise; the table's top is len*hold */
    return lv > 1U ? lv - 1U : 0U;
}

/* a level from a float count of steps, rounded up, at least 1: the continuation then has at most
 * the steps of acceleration left that reach its vmax, never one more (a level rounded down left up
 * to one level too many: past vmax by up to a simplistic dp, 126 ticks at v0 20, vmax 12,000) */
static uint32_t level_from(float lf)
{
    uint32_t k;
    if (!(lf > 0.0f))
        return 1U;
    if (!(lf < 4.0e9f))
        return UINT32_MAX - 1U;
    k = (uint32_t)lf;
    if ((float)k < lf)
        k++;
    return k + 1U;
}

/* The level a continuation of the moving m under params starts at. A level counts steps from v0
 * at the move's accel, so with a new accel or v0 the same speed is another level: Leib, from
 * v^2 = v0^2 + 2 a (level - 1) (the handout's eq. 3) with v = F/p; simplistic, from its own line
 * p = p_max - (level - 1) dp (eq. 1). Unchanged parameters keep m's level. */
static uint32_t continued_level(const ramp_t *m, const ramp_params_t *params)
{
    ramp_t probe;
    if (params == 0 || m->algo == RAMP_ALGO_SIGMOID || ramp_plan_hooked(&probe, m->algo, params, m->hooks, 0, 1) != MS_OK)
        return m->level;
    if (m->algo == RAMP_ALGO_LEIB) {
        float v, v0 = (float)params->v0_sps;
        if (probe.u.leib.r == m->u.leib.r && probe.u.leib.p1 == m->u.leib.p1)
            return m->level;
        v = (float)params->tick_hz / m->u.leib.p;
        return level_from((v * v - v0 * v0) / (2.0f * (float)params->accel_sps2));
    }
    if (m->algo == RAMP_ALGO_SIMPLISTIC) {
        ramp_simplistic_t sp;
        if (simplistic_plan(m->hooks, params, &sp, UINT32_MAX) != MS_OK ||
            (sp.dp == m->u.simplistic.dp && sp.p_max == m->u.simplistic.p_max))
            return m->level;
        return level_from((sp.p_max - m->u.simplistic.p) / sp.dp);
    }
    return m->level;
}

uint32_t ramp_stop_steps_under(const ramp_t *m, const ramp_params_t *params)
{
    uint32_t lv;
    if (m->steps_done == 0 && m->start_level == 0)
        return 0;
    if (m->algo == RAMP_ALGO_SIGMOID)
        return ramp_stop_steps(m);
    lv = continued_level(m, params);
    return lv > 1U ? lv - 1U : 0U;
}

motion_status_t ramp_plan_continue(ramp_t *r, const ramp_t *m, const ramp_params_t *params, int32_t to)
{
    ramp_t n;
    int32_t from;
    uint32_t l0;
    if (r == 0 || m == 0)
        return MS_ERR_NULL;
    from = ramp_position(m);
    if (m->steps_done == 0 && m->start_level == 0) {
        /* nothing handed out yet: a fresh plan from rest */
        if (m->algo == RAMP_ALGO_SIGMOID)
            return MS_ERR_BUSY;
        return ramp_plan_hooked(r, m->algo, params, m->hooks, from, to);
    }
    if (ramp_distance(from, to) < ramp_stop_steps_under(m, m->algo == RAMP_ALGO_SIGMOID ? 0 : params) ||
        (to != from && ramp_direction(from, to) != m->dir))
        return MS_ERR_BUSY;
    l0 = continued_level(m, m->algo == RAMP_ALGO_SIGMOID ? 0 : params);
    if (m->algo == RAMP_ALGO_SIGMOID) {
        n = *m;
        plan_geometry(&n, RAMP_ALGO_SIGMOID, from, to);
        if (l0 > m->accel_steps)
            l0 = m->accel_steps;
        if (l0 < 1U)
            l0 = 1U;
        (void)ramp_sigmoid_set_k(&n.u.sigmoid, l0);
        n.accel_steps = m->accel_steps;
        n.peak_level = m->accel_steps;
        n.whole_ticks = m->whole_ticks;
    } else {
        motion_status_t st;
        if (params == 0)
            return MS_ERR_NULL;
        st = ramp_plan_hooked(&n, m->algo, params, m->hooks, from, to);
        if (st != MS_OK)
            return st;
        /* the peak of the parameters, not limited by this move's length (the level rule does) */
        if (m->algo == RAMP_ALGO_LEIB) {
            float v;
            uint32_t s;
            ramp_accel_steps((float)params->v0_sps, (float)params->vmax_sps, (float)params->accel_sps2, UINT32_MAX,
                             &v, &s);
            n.peak_level = s;
            n.u.leib.p = m->u.leib.p;
        } else if (m->algo == RAMP_ALGO_SIMPLISTIC) {
            /* S and dp of the parameters, not of this move's length */
            st = simplistic_plan(m->hooks, params, &n.u.simplistic, UINT32_MAX);
            if (st != MS_OK)
                return st;
            n.accel_steps = n.u.simplistic.accel_steps;
            n.peak_level = n.u.simplistic.accel_steps + 1U;
            n.u.simplistic.p = m->u.simplistic.p;
        } else {
            return MS_ERR_UNKNOWN_COMMAND;
        }
        n.whole_ticks = m->whole_ticks;
    }
    n.start_level = l0;
    n.level = l0;
    n.dir = m->dir;
    set_label_bound(&n);
    *r = n;
    return MS_OK;
}

/* whether the level rose, fell or stayed: the phase of the interval update */
static ramp_phase_t level_change(ramp_t *r, uint32_t n)
{
    uint32_t lv = level_of(r, n);
    ramp_phase_t ph = lv > r->level ? RAMP_ACCEL : (lv < r->level ? RAMP_DECEL : RAMP_CRUISE);
    r->level = lv;
    return ph;
}

static uint32_t ticks_from_double(double t)
{
    if (!(t > 0.0))
        return 0;
    if (t >= 4294967295.0)
        return UINT32_MAX;
    return (uint32_t)(t + 0.5);
}

/* simplistic and Leib: the next step's interval (kept in u.leib.p / u.simplistic.p), its whole
 * ticks (r->whole_ticks) and the level change */
static ramp_phase_t next_trapezoid(ramp_t *r, uint32_t n)
{
    ramp_phase_t change;
    float p;
    /* step 1 takes the planned first interval; later steps update it by the level change,
     * and a cruise step keeps both the interval and its whole ticks (no float work at all) */
    if (n == 1 && r->start_level == 0) {
        r->level = ramp_level(r->steps_total, r->peak_level, 1);
        p = r->algo == RAMP_ALGO_LEIB ? r->u.leib.p : r->u.simplistic.p;
        change = RAMP_ACCEL;
    } else {
        change = level_change(r, n);
        if (change == RAMP_CRUISE)
            return change;
        const ramp_hooks_t *h = r->hooks;
        if (r->algo == RAMP_ALGO_LEIB)
            p = h != 0 && h->leib_update != 0 ? h->leib_update(&r->u.leib, change)
                                              : ramp_leib_update(&r->u.leib, change);
        else
            p = h != 0 && h->simplistic_update != 0 ? h->simplistic_update(&r->u.simplistic, change)
                                                    : ramp_simplistic_update(&r->u.simplistic, change);
    }
    r->whole_ticks = ramp_ticks_from_float(p);
    return change;
}

/* the sigmoid's next step: its period (also in r->whole_ticks) and level change */
static ramp_phase_t next_sigmoid(ramp_t *r, uint32_t n)
{
    uint32_t from_end = r->steps_total - n + 1U;
    uint32_t k = r->start_level + n < from_end ? r->start_level + n : from_end;
    uint32_t kold = r->u.sigmoid.k;
    int8_t move;
    if (r->start_level != 0 && k > r->accel_steps)
        k = r->accel_steps > kold ? r->accel_steps : kold; /* continued: hold at the table's top */
    move = k > kold ? 1 : (k < kold ? -1 : 0);
    r->whole_ticks = ramp_sigmoid_move_k(&r->u.sigmoid, move);
    r->level = r->u.sigmoid.k; /* for ramp_stop_steps and ramp_plan_continue */
    return move > 0 ? RAMP_ACCEL : (move < 0 ? RAMP_DECEL : RAMP_CRUISE);
}

uint8_t ramp_next_ticks(ramp_t *r, uint32_t *whole_ticks, ramp_phase_t *phase)
{
    uint32_t n;
    ramp_phase_t change;
    if (r->steps_done >= r->steps_total)
        return 0;
    n = ++r->steps_done;
    switch (r->algo) {
    case RAMP_ALGO_SIMPLISTIC:
    case RAMP_ALGO_LEIB:
        change = next_trapezoid(r, n);
        break;
    case RAMP_ALGO_SIGMOID:
        change = next_sigmoid(r, n);
        break;
    case RAMP_ALGO_EXACT:
        *whole_ticks = ticks_from_double(ramp_exact_interval_s(&r->u.exact, n) * r->u.exact.tick_hz);
        *phase = ramp_exact_phase(&r->u.exact, n);
        return 1;
    default:
        *whole_ticks = 0;
        *phase = RAMP_IDLE;
        return 1;
    }
    *whole_ticks = r->whole_ticks;
    *phase = r->start_level == 0 ? phase_label(r, n) : change;
    return 1;
}

uint32_t ramp_take_same(ramp_t *r, uint32_t max_steps)
{
    ramp_sigmoid_t *g = &r->u.sigmoid;
    uint32_t n = r->steps_done, d = r->steps_total, j, lim;
    uint8_t rising;
    if (r->algo != RAMP_ALGO_SIGMOID || n == 0 || n >= d)
        return 0;
    if (r->start_level != 0) {
        /* continued (next_sigmoid): k = min(L0 + n, D + 1 - n), held at the table's top A */
        uint32_t l0 = r->start_level, a = r->accel_steps;
        if (g->k == l0 + n && g->k < a) {
            /* rising: while k stays below the top and below D + 1 - n (L0 + n + j <= D + 1 - n - j) */
            uint32_t room = d + 1U - n >= l0 + n ? (d + 1U - n - (l0 + n)) / 2U : 0U;
            rising = 1;
            lim = a - g->k < room ? a - g->k : room;
        } else if (g->k == d + 1U - n && g->k < l0 + n && g->k > 1U) {
            rising = 0; /* falling with the steps left */
            lim = g->k - 1U;
        } else {
            return 0;
        }
    } else if (g->k == n && n <= r->label_accel && 2U * n < d) {
        /* accelerating (k = n): while k still rises (2(n + j) <= D + 1) and the steps are still
         * labelled accel */
        rising = 1;
        lim = r->label_accel - n < (d + 1U) / 2U - n ? r->label_accel - n : (d + 1U) / 2U - n;
    } else if (g->k == d + 1U - n && n > d - r->label_accel && g->k > 1U) {
        rising = 0; /* decelerating (k = D + 1 - n) */
        lim = g->k - 1U;
    } else {
        return 0;
    }
    /* the rest of the entry's hold (rising), or down to its first phase (falling; k stays >= 1) */
    j = rising ? (uint32_t)(g->hold - 1U - g->phase) : g->phase;
    if (j > lim)
        j = lim;
    if (j > max_steps)
        j = max_steps;
    g->k = rising ? g->k + j : g->k - j;
    g->phase = (uint16_t)(rising ? g->phase + j : g->phase - j);
    r->level = g->k;
    r->steps_done = n + j;
    return j;
}

uint8_t ramp_next(ramp_t *r, ramp_step_t *s)
{
    if (r->algo == RAMP_ALGO_EXACT) {
        uint32_t n;
        if (r->steps_done >= r->steps_total)
            return 0;
        n = ++r->steps_done;
        s->interval_ticks = ramp_exact_interval_s(&r->u.exact, n) * r->u.exact.tick_hz;
        s->whole_ticks = ticks_from_double(s->interval_ticks);
        s->phase = ramp_exact_phase(&r->u.exact, n);
    } else {
        if (!ramp_next_ticks(r, &s->whole_ticks, &s->phase))
            return 0;
        switch (r->algo) {
        case RAMP_ALGO_LEIB: s->interval_ticks = r->u.leib.p; break;
        case RAMP_ALGO_SIMPLISTIC: s->interval_ticks = r->u.simplistic.p; break;
        default: s->interval_ticks = (double)s->whole_ticks; break;
        }
    }
    s->step = r->steps_done;
    s->position = ramp_position_after(r->from, r->dir, r->steps_done);
    return 1;
}

/* The step ramp_skip_cruise jumps to (it hands out the step after it next), or 0 when the move is
 * not in a cruise that can be skipped. */
static uint32_t cruise_skip_target(const ramp_t *r)
{
    uint32_t d = r->steps_total, done = r->steps_done, target;
    switch (r->algo) {
    case RAMP_ALGO_SIMPLISTIC:
    case RAMP_ALGO_LEIB: {
        uint32_t k = r->peak_level;
        /* flat region: the steps whose level is K, i.e. K <= n <= D + 1 - K (all steps if K = 0) */
        if (done == 0 || r->level != k || (r->start_level == 0 && (k > d / 2U || done < k)))
            return 0;
        target = d - k; /* the next step, D + 1 - K, is the last flat one */
        break;
    }
    case RAMP_ALGO_EXACT: {
        double last_cruise = (double)d - r->u.exact.x_accel + 0.5; /* largest n with n - 1/2 <= D - x_a */
        uint32_t nc;
        if (done == 0 || ramp_exact_phase(&r->u.exact, done) != RAMP_CRUISE || last_cruise < 1.0)
            return 0;
        nc = (uint32_t)last_cruise;
        target = nc - 1U;
        break;
    }
    case RAMP_ALGO_SIGMOID: {
        /* cruise: the steps after the len*hold accelerating ones and before as many decelerating */
        uint32_t a = r->accel_steps;
        if (r->start_level != 0) {
            /* continued (next_sigmoid): k stays at the table's top A while D + 1 - n >= A; once it is
             * there, the steps up to D - A are cruise (the next, D + 1 - A, the last at the top) */
            if (done == 0 || r->u.sigmoid.k != a || done + a >= d)
                return 0;
            target = d - a;
            break;
        }
        if (done == 0 || done < a || done + 1U >= d - a || a > d / 2U) /* the division last: rarely reached */
            return 0;
        target = d - a - 1U; /* the next step, D - A, is the last cruise step */
        break;
    }
    default:
        return 0;
    }
    return target > done ? target : 0;
}

uint32_t ramp_cruise_skippable(const ramp_t *r)
{
    uint32_t target = cruise_skip_target(r);
    return target != 0 ? target - r->steps_done : 0;
}

uint32_t ramp_skip_cruise_at_most(ramp_t *r, uint32_t max_steps)
{
    uint32_t n = ramp_cruise_skippable(r), target;
    if (n > max_steps)
        n = max_steps;
    if (n == 0)
        return 0;
    target = r->steps_done + n;
    if (r->algo == RAMP_ALGO_SIGMOID && r->start_level == 0) { /* continued: k stays at the top */
        uint32_t from_end = r->steps_total + 1U - target;
        (void)ramp_sigmoid_set_k(&r->u.sigmoid, target < from_end ? target : from_end);
    }
    /* simplistic/Leib: the level stays K and the interval p; exact: stateless per step */
    r->steps_done = target;
    return n;
}

uint32_t ramp_skip_cruise(ramp_t *r)
{
    return ramp_skip_cruise_at_most(r, UINT32_MAX);
}
