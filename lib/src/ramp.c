/* ramp.c - the move planner: hands each step to the chosen ramp algorithm through its table (see ramp.h). */
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

/* Each algorithm's part of the planner, reached only through r->ops (set by the plan), so that a
 * firmware links only the algorithms it plans: ramp_plan_lab the lab's simplistic and Leib,
 * ramp_plan_leib / _simplistic one of them, ramp_plan_sigmoid the sigmoid, ramp_plan and
 * ramp_plan_hooked (motionsim, the tests) simplistic, Leib and exact. */
struct ramp_algo_ops {
    /* fills n->u, accel_steps and peak_level for n->steps_total steps (n->hooks set) */
    motion_status_t (*plan)(ramp_t *n, const ramp_params_t *params);
    /* hands out step n: r->whole_ticks (and level) updated; returns the step's phase */
    ramp_phase_t (*next)(ramp_t *r, uint32_t n);
    /* the interval of step n, just handed out, as the algorithm computes it (ticks) */
    double (*interval)(const ramp_t *r, uint32_t n);
    /* the level a continuation under params (probe: a plan of one step under them) starts at
     * (NULL: the level reached) */
    uint32_t (*level_under)(const ramp_t *m, const ramp_params_t *params, const ramp_t *probe);
    /* the algorithm's part of ramp_plan_continue: n from m at *l0 (NULL: it cannot continue) */
    motion_status_t (*resume)(ramp_t *n, const ramp_t *m, const ramp_params_t *params, int32_t from, int32_t to,
                              uint32_t *l0);
    /* ramp_skip_cruise's target step, or 0 */
    uint32_t (*cruise_target)(const ramp_t *r);
    /* the state at step `target` after a cruise skip (NULL: nothing per step to set) */
    void (*skip_to)(ramp_t *r, uint32_t target);
    /* ramp_take_same (NULL: 0) */
    uint32_t (*take_same)(ramp_t *r, uint32_t max_steps);
};

static const struct ramp_algo_ops SIMPLISTIC_RAMP RAMP_TABLE_MEM, LEIB_RAMP RAMP_TABLE_MEM;
static const struct ramp_algo_ops EXACT_RAMP RAMP_TABLE_MEM, SIGMOID_RAMP RAMP_TABLE_MEM;

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

static motion_status_t plan_with(ramp_t *r, ramp_algo_t algo, const struct ramp_algo_ops *ops,
                                 const ramp_params_t *params, const ramp_hooks_t *hooks, int32_t from, int32_t to)
{
    ramp_t n;
    motion_status_t st;
    if (r == 0 || params == 0)
        return MS_ERR_NULL;
    if (ops == 0)
        return MS_ERR_UNKNOWN_COMMAND;
    plan_geometry(&n, algo, from, to);
    n.hooks = hooks;
    n.ops = ops;
    st = RAMP_TABLE_FN(ops, plan)(&n, params);
    if (st != MS_OK)
        return st;
    set_label_bound(&n);
    *r = n;
    return MS_OK;
}

/* the lab's ramps only: a firmware that plans them (the step planner's stepwise half) links no other */
static const struct ramp_algo_ops *lab_ops(ramp_algo_t algo)
{
    return algo == RAMP_ALGO_SIMPLISTIC ? &SIMPLISTIC_RAMP : algo == RAMP_ALGO_LEIB ? &LEIB_RAMP : 0;
}

motion_status_t ramp_plan(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, int32_t from, int32_t to)
{
    return ramp_plan_hooked(r, algo, params, 0, from, to);
}

motion_status_t ramp_plan_hooked(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, const ramp_hooks_t *hooks,
                                 int32_t from, int32_t to)
{
    return plan_with(r, algo, algo == RAMP_ALGO_EXACT ? &EXACT_RAMP : lab_ops(algo), params, hooks, from, to);
}

motion_status_t ramp_plan_lab(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, const ramp_hooks_t *hooks,
                              int32_t from, int32_t to)
{
    return plan_with(r, algo, lab_ops(algo), params, hooks, from, to);
}

motion_status_t ramp_plan_leib(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params, const ramp_hooks_t *hooks,
                               int32_t from, int32_t to)
{
    return plan_with(r, algo, algo == RAMP_ALGO_LEIB ? &LEIB_RAMP : 0, params, hooks, from, to);
}

motion_status_t ramp_plan_simplistic(ramp_t *r, ramp_algo_t algo, const ramp_params_t *params,
                                     const ramp_hooks_t *hooks, int32_t from, int32_t to)
{
    return plan_with(r, algo, algo == RAMP_ALGO_SIMPLISTIC ? &SIMPLISTIC_RAMP : 0, params, hooks, from, to);
}

motion_status_t ramp_plan_sigmoid(ramp_t *r, const ramp_sigmoid_params_t *p, const uint16_t *table,
                                  uint16_t table_len, int32_t from, int32_t to)
{
    ramp_t n;
    motion_status_t st;
    if (r == 0 || p == 0)
        return MS_ERR_NULL;
    plan_geometry(&n, RAMP_ALGO_SIGMOID, from, to);
    n.ops = &SIGMOID_RAMP;
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
    if (params == 0 || RAMP_TABLE_FN(m->ops, level_under) == 0 ||
        plan_with(&probe, m->algo, m->ops, params, m->hooks, 0, 1) != MS_OK)
        return m->level;
    return RAMP_TABLE_FN(m->ops, level_under)(m, params, &probe);
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
    motion_status_t st;
    if (r == 0 || m == 0)
        return MS_ERR_NULL;
    from = ramp_position(m);
    if (m->steps_done == 0 && m->start_level == 0) {
        /* nothing handed out yet: a fresh plan from rest */
        if (m->algo == RAMP_ALGO_SIGMOID)
            return MS_ERR_BUSY;
        return plan_with(r, m->algo, m->ops, params, m->hooks, from, to);
    }
    if (ramp_distance(from, to) < ramp_stop_steps_under(m, m->algo == RAMP_ALGO_SIGMOID ? 0 : params) ||
        (to != from && ramp_direction(from, to) != m->dir))
        return MS_ERR_BUSY;
    l0 = continued_level(m, m->algo == RAMP_ALGO_SIGMOID ? 0 : params);
    if (RAMP_TABLE_FN(m->ops, resume) == 0) {
        /* the exact ramp: planned under params first, so that a NULL or refused set gets its status */
        st = plan_with(&n, m->algo, m->ops, params, m->hooks, from, to);
        return st != MS_OK ? st : MS_ERR_UNKNOWN_COMMAND;
    }
    st = RAMP_TABLE_FN(m->ops, resume)(&n, m, params, from, to, &l0);
    if (st != MS_OK)
        return st;
    n.whole_ticks = m->whole_ticks;
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

/* a stepwise ramp's phase of step n: the label from rest, else the level change of a continuation */
static ramp_phase_t stepwise_phase(const ramp_t *r, uint32_t n, ramp_phase_t change)
{
    return r->start_level == 0 ? phase_label(r, n) : change;
}

uint8_t ramp_next_ticks(ramp_t *r, uint32_t *whole_ticks, ramp_phase_t *phase)
{
    uint32_t n;
    if (r->steps_done >= r->steps_total)
        return 0;
    n = ++r->steps_done;
    *phase = RAMP_TABLE_FN(r->ops, next)(r, n);
    *whole_ticks = r->whole_ticks;
    return 1;
}

ramp_step_fn_t ramp_step_fn(const ramp_t *r)
{
    return RAMP_TABLE_FN(r->ops, next);
}

uint32_t ramp_take_same(ramp_t *r, uint32_t max_steps)
{
    if (r->ops == 0 || RAMP_TABLE_FN(r->ops, take_same) == 0)
        return 0U; /* never planned, or not the sigmoid */
    return RAMP_TABLE_FN(r->ops, take_same)(r, max_steps);
}

uint8_t ramp_next(ramp_t *r, ramp_step_t *s)
{
    if (!ramp_next_ticks(r, &s->whole_ticks, &s->phase))
        return 0;
    s->interval_ticks = RAMP_TABLE_FN(r->ops, interval)(r, r->steps_done);
    s->step = r->steps_done;
    s->position = ramp_position_after(r->from, r->dir, r->steps_done);
    return 1;
}

uint32_t ramp_cruise_skippable(const ramp_t *r)
{
    uint32_t target = r->ops != 0 ? RAMP_TABLE_FN(r->ops, cruise_target)(r) : 0U; /* 0: never planned */
    return target > r->steps_done ? target - r->steps_done : 0;
}

uint32_t ramp_skip_cruise_at_most(ramp_t *r, uint32_t max_steps)
{
    uint32_t n = ramp_cruise_skippable(r), target;
    if (n > max_steps)
        n = max_steps;
    if (n == 0)
        return 0;
    target = r->steps_done + n;
    if (RAMP_TABLE_FN(r->ops, skip_to) != 0)
        RAMP_TABLE_FN(r->ops, skip_to)(r, target);
    /* simplistic/Leib: the level stays K and the interval p; exact: stateless per step */
    r->steps_done = target;
    return n;
}

uint32_t ramp_skip_cruise(ramp_t *r)
{
    return ramp_skip_cruise_at_most(r, UINT32_MAX);
}

/* ---- simplistic and Leib (the lab's ramps; a sketch's hooks replace lib's functions) ---- */

static motion_status_t simplistic_plan_state(const ramp_hooks_t *h, const ramp_params_t *params,
                                             ramp_simplistic_t *s, uint32_t steps_total)
{
    if (h != 0 && h->simplistic_plan != 0)
        return h->simplistic_plan(s, params, steps_total);
    return ramp_simplistic_plan(s, params, steps_total);
}

static motion_status_t simplistic_plan(ramp_t *n, const ramp_params_t *params)
{
    motion_status_t st = simplistic_plan_state(n->hooks, params, &n->u.simplistic, n->steps_total);
    n->accel_steps = n->u.simplistic.accel_steps;
    n->peak_level = n->accel_steps + 1U;
    return st;
}

static motion_status_t leib_plan(ramp_t *n, const ramp_params_t *params)
{
    const ramp_hooks_t *h = n->hooks;
    motion_status_t st = h != 0 && h->leib_plan != 0 ? h->leib_plan(&n->u.leib, params, n->steps_total)
                                                      : ramp_leib_plan(&n->u.leib, params, n->steps_total);
    n->accel_steps = n->u.leib.accel_steps;
    n->peak_level = n->accel_steps;
    return st;
}

/* the interval of the next step (kept in u.leib.p / u.simplistic.p), its whole ticks
 * (r->whole_ticks) and the level change; update: the algorithm's (or the hook's) step 6 */
static inline __attribute__((always_inline)) ramp_phase_t next_stepwise(ramp_t *r, uint32_t n, float p1,
                                                                     float (*update)(ramp_t *r, ramp_phase_t change))
{
    ramp_phase_t change;
    float p;
    /* step 1 takes the planned first interval; later steps update it by the level change,
     * and a cruise step keeps both the interval and its whole ticks (no float work at all) */
    if (n == 1 && r->start_level == 0) {
        r->level = ramp_level(r->steps_total, r->peak_level, 1);
        p = p1;
        change = RAMP_ACCEL;
    } else {
        change = level_change(r, n);
        if (change == RAMP_CRUISE)
            return stepwise_phase(r, n, change);
        p = update(r, change);
    }
    r->whole_ticks = ramp_ticks_from_float(p);
    return stepwise_phase(r, n, change);
}

static float leib_update(ramp_t *r, ramp_phase_t change)
{
    const ramp_hooks_t *h = r->hooks;
    return h != 0 && h->leib_update != 0 ? h->leib_update(&r->u.leib, change) : ramp_leib_update(&r->u.leib, change);
}

static float simplistic_update(ramp_t *r, ramp_phase_t change)
{
    const ramp_hooks_t *h = r->hooks;
    return h != 0 && h->simplistic_update != 0 ? h->simplistic_update(&r->u.simplistic, change)
                                               : ramp_simplistic_update(&r->u.simplistic, change);
}

static ramp_phase_t leib_next(ramp_t *r, uint32_t n)
{
    return next_stepwise(r, n, r->u.leib.p, leib_update);
}

static ramp_phase_t simplistic_next(ramp_t *r, uint32_t n)
{
    return next_stepwise(r, n, r->u.simplistic.p, simplistic_update);
}

static double leib_interval(const ramp_t *r, uint32_t n)
{
    (void)n;
    return r->u.leib.p;
}

static double simplistic_interval(const ramp_t *r, uint32_t n)
{
    (void)n;
    return r->u.simplistic.p;
}

static uint32_t leib_level_under(const ramp_t *m, const ramp_params_t *params, const ramp_t *probe)
{
    float v, v0 = (float)params->v0_sps;
    if (probe->u.leib.r == m->u.leib.r && probe->u.leib.p1 == m->u.leib.p1)
        return m->level;
    v = (float)params->tick_hz / m->u.leib.p;
    return level_from((v * v - v0 * v0) / (2.0f * (float)params->accel_sps2));
}

static uint32_t simplistic_level_under(const ramp_t *m, const ramp_params_t *params, const ramp_t *probe)
{
    ramp_simplistic_t sp;
    (void)probe; /* S and dp are those of an unlimited move, not of one step */
    if (simplistic_plan_state(m->hooks, params, &sp, UINT32_MAX) != MS_OK ||
        (sp.dp == m->u.simplistic.dp && sp.p_max == m->u.simplistic.p_max))
        return m->level;
    return level_from((sp.p_max - m->u.simplistic.p) / sp.dp);
}

static motion_status_t leib_resume(ramp_t *n, const ramp_t *m, const ramp_params_t *params, int32_t from, int32_t to,
                                   uint32_t *l0)
{
    float v;
    uint32_t s;
    motion_status_t st = plan_with(n, m->algo, m->ops, params, m->hooks, from, to);
    (void)l0;
    if (st != MS_OK)
        return st;
    /* the peak of the parameters, not limited by this move's length (the level rule does) */
    ramp_accel_steps((float)params->v0_sps, (float)params->vmax_sps, (float)params->accel_sps2, UINT32_MAX, &v, &s);
    n->peak_level = s;
    n->u.leib.p = m->u.leib.p;
    return MS_OK;
}

static motion_status_t simplistic_resume(ramp_t *n, const ramp_t *m, const ramp_params_t *params, int32_t from,
                                         int32_t to, uint32_t *l0)
{
    motion_status_t st = plan_with(n, m->algo, m->ops, params, m->hooks, from, to);
    (void)l0;
    if (st != MS_OK)
        return st;
    /* S and dp of the parameters, not of this move's length */
    st = simplistic_plan_state(m->hooks, params, &n->u.simplistic, UINT32_MAX);
    if (st != MS_OK)
        return st;
    n->accel_steps = n->u.simplistic.accel_steps;
    n->peak_level = n->u.simplistic.accel_steps + 1U;
    n->u.simplistic.p = m->u.simplistic.p;
    return MS_OK;
}

/* flat region: the steps whose level is K, i.e. K <= n <= D + 1 - K (all steps if K = 0) */
static uint32_t stepwise_cruise_target(const ramp_t *r)
{
    uint32_t d = r->steps_total, done = r->steps_done, k = r->peak_level;
    if (done == 0 || r->level != k || (r->start_level == 0 && (k > d / 2U || done < k)))
        return 0;
    return d - k; /* the next step, D + 1 - K, is the last flat one */
}

static const struct ramp_algo_ops SIMPLISTIC_RAMP RAMP_TABLE_MEM = {
    simplistic_plan, simplistic_next, simplistic_interval, simplistic_level_under, simplistic_resume,
    stepwise_cruise_target, 0, 0
};
static const struct ramp_algo_ops LEIB_RAMP RAMP_TABLE_MEM = {
    leib_plan, leib_next, leib_interval, leib_level_under, leib_resume, stepwise_cruise_target, 0, 0
};

/* ---- exact (ramp_exact.h: exact times; no continuation here, step_exact.h plans those) ---- */

static motion_status_t exact_plan(ramp_t *n, const ramp_params_t *params)
{
    n->accel_steps = 0; /* phases come from the exact positions (ramp_exact_phase) */
    n->peak_level = 0;
    return ramp_exact_plan(&n->u.exact, params, n->steps_total);
}

static double exact_interval(const ramp_t *r, uint32_t n)
{
    return ramp_exact_interval_s(&r->u.exact, n) * r->u.exact.tick_hz;
}

static ramp_phase_t exact_next(ramp_t *r, uint32_t n)
{
    r->whole_ticks = ticks_from_double(exact_interval(r, n));
    return ramp_exact_phase(&r->u.exact, n);
}

static uint32_t exact_cruise_target(const ramp_t *r)
{
    double last_cruise = (double)r->steps_total - r->u.exact.x_accel + 0.5; /* largest n with n - 1/2 <= D - x_a */
    uint32_t done = r->steps_done;
    if (done == 0 || ramp_exact_phase(&r->u.exact, done) != RAMP_CRUISE || last_cruise < 1.0)
        return 0;
    return (uint32_t)last_cruise - 1U;
}

static const struct ramp_algo_ops EXACT_RAMP RAMP_TABLE_MEM = {
    exact_plan, exact_next, exact_interval, 0, 0, exact_cruise_target, 0, 0
};

/* ---- the sigmoid (ramp_sigmoid.h: an S-curve article table) ---- */

/* the sigmoid's next step: its period (also in r->whole_ticks) and level change */
static ramp_phase_t sigmoid_next(ramp_t *r, uint32_t n)
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
    return stepwise_phase(r, n, move > 0 ? RAMP_ACCEL : (move < 0 ? RAMP_DECEL : RAMP_CRUISE));
}

static double sigmoid_interval(const ramp_t *r, uint32_t n)
{
    (void)n;
    return (double)r->whole_ticks;
}

static motion_status_t sigmoid_resume(ramp_t *n, const ramp_t *m, const ramp_params_t *params, int32_t from,
                                      int32_t to, uint32_t *l0)
{
    (void)params;
    *n = *m;
    plan_geometry(n, RAMP_ALGO_SIGMOID, from, to);
    if (*l0 > m->accel_steps)
        *l0 = m->accel_steps;
    if (*l0 < 1U)
        *l0 = 1U;
    (void)ramp_sigmoid_set_k(&n->u.sigmoid, *l0);
    n->accel_steps = m->accel_steps;
    n->peak_level = m->accel_steps;
    return MS_OK;
}

static uint32_t sigmoid_cruise_target(const ramp_t *r)
{
    /* cruise: the steps after the len*hold accelerating ones and before as many decelerating */
    uint32_t d = r->steps_total, done = r->steps_done, a = r->accel_steps;
    if (r->start_level != 0) {
        /* continued (sigmoid_next): k stays at the table's top A while D + 1 - n >= A; once it is
         * there, the steps up to D - A are cruise (the next, D + 1 - A, the last at the top) */
        if (done == 0 || r->u.sigmoid.k != a || done + a >= d)
            return 0;
        return d - a;
    }
    if (done == 0 || done < a || done + 1U >= d - a || a > d / 2U) /* the division last: rarely reached */
        return 0;
    return d - a - 1U; /* the next step, D - A, is the last cruise step */
}

static void sigmoid_skip_to(ramp_t *r, uint32_t target)
{
    if (r->start_level == 0) { /* continued: k stays at the top */
        uint32_t from_end = r->steps_total + 1U - target;
        (void)ramp_sigmoid_set_k(&r->u.sigmoid, target < from_end ? target : from_end);
    }
}

static uint32_t sigmoid_take_same(ramp_t *r, uint32_t max_steps)
{
    ramp_sigmoid_t *g = &r->u.sigmoid;
    uint32_t n = r->steps_done, d = r->steps_total, j, lim;
    uint8_t rising;
    if (n == 0 || n >= d)
        return 0;
    if (r->start_level != 0) {
        /* continued (sigmoid_next): k = min(L0 + n, D + 1 - n), held at the table's top A */
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

static const struct ramp_algo_ops SIGMOID_RAMP RAMP_TABLE_MEM = {
    0, sigmoid_next, sigmoid_interval, 0, sigmoid_resume, sigmoid_cruise_target, sigmoid_skip_to, sigmoid_take_same
};
