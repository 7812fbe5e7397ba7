/* step_planner.c - moves, stops and new targets of any ramp as step commands (see step_planner.h). */
#include "step_planner.h"

#define WIDE_ABOVE 65535U /* whole ticks: longer intervals go into WIDE commands */

static void clear_state(step_planner_t *pl, int32_t pos)
{
    pl->active = 0;
    pl->params_new = 0;
    pl->has_carry = 0;
    pl->has_ready = 0;
    pl->has_then = 0;
    pl->pos = pos;
    pl->target = pos;
}

/* The halves of the planner: the exact ramp's (step_exact.h), the stepwise ramps' (ramp.h: the lab's
 * simplistic and Leib, and the sigmoid, each with its own table) and the smooth move's. A planner
 * reaches its half only through ops (in flash on the AVR: RAMP_TABLE_MEM), so a firmware that
 * initialises only one kind (step_planner_init_exact, _lab, _sigmoid, _smooth) links only that half. */
struct step_planner_ops {
    motion_status_t (*set_params)(step_planner_t *pl, const ramp_params_t *params);
    uint8_t (*left)(const step_planner_t *pl);                /* active: something left to hand out */
    motion_status_t (*from_rest)(step_planner_t *pl, int32_t to); /* the plan's own part of plan_from_rest */
    motion_status_t (*move)(step_planner_t *pl, int32_t to);
    void (*stop)(step_planner_t *pl);
    uint8_t (*next)(step_planner_t *pl, step_cmd_t *c);       /* a command of the active plan */
    void (*reset)(step_planner_t *pl);                        /* at rest at pl->pos */
    /* step_planner_rewind's own part and how far it reaches (NULL: no rewind) */
    motion_status_t (*rewind)(step_planner_t *pl, uint32_t steps, int64_t time16, uint16_t last_count);
    uint32_t (*rewindable)(const step_planner_t *pl);
};
static const struct step_planner_ops EXACT_OPS RAMP_TABLE_MEM;
static const struct step_planner_ops LAB_OPS RAMP_TABLE_MEM;
static const struct step_planner_ops LEIB_OPS RAMP_TABLE_MEM;
static const struct step_planner_ops SIMPLISTIC_OPS RAMP_TABLE_MEM;
static const struct step_planner_ops SIGMOID_OPS RAMP_TABLE_MEM;
static const struct step_planner_ops SMOOTH_OPS RAMP_TABLE_MEM;

static motion_status_t init_kind(step_planner_t *pl, const struct step_planner_ops *ops, ramp_algo_t algo,
                                 const ramp_params_t *params, const ramp_hooks_t *hooks, int32_t pos)
{
    step_planner_t n;
    motion_status_t st;
    if (pl == 0 || params == 0)
        return MS_ERR_NULL;
    n.ops = ops;
    n.algo = algo;
    n.hooks = hooks;
    n.exact.max_cmd_ticks = 0;
    n.table = 0;
    n.table_len = 0;
    clear_state(&n, pos);
    st = step_planner_set_params(&n, params);
    if (st != MS_OK)
        return st;
    n.max_cmd_ticks = params->tick_hz / 250U; /* 4 ms */
    if (algo == RAMP_ALGO_EXACT)
        n.exact.max_cmd_ticks = n.max_cmd_ticks;
    clear_state(&n, pos);
    RAMP_TABLE_FN(n.ops, reset)(&n);
    *pl = n;
    return MS_OK;
}

motion_status_t step_planner_init_exact(step_planner_t *pl, const ramp_params_t *params, int32_t pos)
{
    return init_kind(pl, &EXACT_OPS, RAMP_ALGO_EXACT, params, 0, pos);
}

motion_status_t step_planner_init_lab(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                      const ramp_hooks_t *hooks, int32_t pos)
{
    if (algo != RAMP_ALGO_SIMPLISTIC && algo != RAMP_ALGO_LEIB)
        return pl == 0 || params == 0 ? MS_ERR_NULL : MS_ERR_UNKNOWN_COMMAND;
    return init_kind(pl, &LAB_OPS, algo, params, hooks, pos);
}

motion_status_t step_planner_init_leib(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                       const ramp_hooks_t *hooks, int32_t pos)
{
    if (algo != RAMP_ALGO_LEIB)
        return pl == 0 || params == 0 ? MS_ERR_NULL : MS_ERR_UNKNOWN_COMMAND;
    return init_kind(pl, &LEIB_OPS, algo, params, hooks, pos);
}

motion_status_t step_planner_init_simplistic(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                             const ramp_hooks_t *hooks, int32_t pos)
{
    if (algo != RAMP_ALGO_SIMPLISTIC)
        return pl == 0 || params == 0 ? MS_ERR_NULL : MS_ERR_UNKNOWN_COMMAND;
    return init_kind(pl, &SIMPLISTIC_OPS, algo, params, hooks, pos);
}

motion_status_t step_planner_init_trapezoid(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                            int32_t pos)
{
    return step_planner_init_hooked(pl, algo, params, 0, pos);
}

motion_status_t step_planner_init_hooked(step_planner_t *pl, ramp_algo_t algo, const ramp_params_t *params,
                                         const ramp_hooks_t *hooks, int32_t pos)
{
    if (algo == RAMP_ALGO_EXACT)
        return init_kind(pl, &EXACT_OPS, algo, params, hooks, pos);
    return step_planner_init_lab(pl, algo, params, hooks, pos);
}

motion_status_t step_planner_init_sigmoid(step_planner_t *pl, const ramp_sigmoid_params_t *p, const uint16_t *table,
                                          uint16_t table_len, int32_t pos)
{
    ramp_t probe;
    motion_status_t st;
    if (pl == 0 || p == 0)
        return MS_ERR_NULL;
    st = ramp_plan_sigmoid(&probe, p, table, table_len, pos, pos);
    if (st != MS_OK)
        return st;
    pl->ops = &SIGMOID_OPS;
    pl->algo = RAMP_ALGO_SIGMOID;
    pl->hooks = 0;
    pl->sig = *p;
    pl->table = table;
    pl->table_len = table_len;
    pl->max_cmd_ticks = p->timer_hz / 250U;
    clear_state(pl, pos);
    return MS_OK;
}

static motion_status_t exact_set_params(step_planner_t *pl, const ramp_params_t *params)
{
    step_exact_t e = pl->exact;
    motion_status_t st = step_exact_set_params(&e, params);
    if (st != MS_OK)
        return st;
    /* the profile in progress keeps its constants until the next plan */
    if (!pl->active && !pl->has_then)
        pl->exact.k = e.k;
    else
        pl->params_new = 1;
    return MS_OK;
}

static motion_status_t lab_set_params(step_planner_t *pl, const ramp_params_t *params)
{
    ramp_t probe;
    return ramp_plan_lab(&probe, pl->algo, params, pl->hooks, 0, 1);
}

static motion_status_t leib_set_params(step_planner_t *pl, const ramp_params_t *params)
{
    ramp_t probe;
    return ramp_plan_leib(&probe, pl->algo, params, pl->hooks, 0, 1);
}

static motion_status_t simplistic_set_params(step_planner_t *pl, const ramp_params_t *params)
{
    ramp_t probe;
    return ramp_plan_simplistic(&probe, pl->algo, params, pl->hooks, 0, 1);
}

static motion_status_t sigmoid_set_params(step_planner_t *pl, const ramp_params_t *params)
{
    (void)pl;
    (void)params;
    return MS_ERR_UNKNOWN_COMMAND; /* its parameters are its table's (step_planner_init_sigmoid) */
}

motion_status_t step_planner_set_params(step_planner_t *pl, const ramp_params_t *params)
{
    motion_status_t st;
    if (pl == 0 || params == 0)
        return MS_ERR_NULL;
    st = RAMP_TABLE_FN(pl->ops, set_params)(pl, params);
    if (st != MS_OK)
        return st;
    pl->params = *params;
    return MS_OK;
}

uint8_t step_planner_busy(const step_planner_t *pl)
{
    if (pl->has_ready || pl->has_then || pl->has_carry)
        return 1;
    if (!pl->active)
        return 0;
    /* active, but nothing left to hand out: done (so the engine can mark the end at once) */
    return RAMP_TABLE_FN(pl->ops, left)(pl);
}

static uint8_t exact_left(const step_planner_t *pl)
{
    return pl->exact.n < pl->exact.d;
}

static uint8_t ramp_left(const step_planner_t *pl)
{
    return ramp_steps_left(&pl->ramp) > 0;
}

int32_t step_planner_position(const step_planner_t *pl)
{
    return pl->pos;
}

int32_t step_planner_target(const step_planner_t *pl)
{
    return pl->target;
}

/* params_new survives the halt: parameters set while moving are not in the exact ramp's constants
 * yet, and its next move from rest converts them (exact_from_rest; the others plan from pl->params) */
void step_planner_halt(step_planner_t *pl, int32_t pos)
{
    uint8_t params_new = pl->params_new;
    clear_state(pl, pos);
    pl->params_new = params_new;
    RAMP_TABLE_FN(pl->ops, reset)(pl);
}

static void exact_reset(step_planner_t *pl)
{
    step_exact_reset(&pl->exact, pl->pos);
}

static void ramp_reset(step_planner_t *pl)
{
    (void)pl; /* the ramp is planned afresh from pl->pos */
}

static uint32_t nonzero(uint32_t w)
{
    return w != 0 ? w : 1U;
}

/* the carried step becomes a one-step command handed out next (so a replan starts after it) */
static void flush_carry(step_planner_t *pl)
{
    uint32_t w;
    if (!pl->has_carry)
        return;
    w = nonzero(pl->carry.whole_ticks);
    pl->ready.count = 1;
    pl->ready.add = 0;
    pl->ready.flags = (uint8_t)((pl->ramp.dir < 0 ? STEP_CMD_REVERSE : 0) | (w > WIDE_ABOVE ? STEP_CMD_WIDE : 0) |
                                ((uint8_t)pl->carry.phase << STEP_CMD_PHASE_SHIFT));
    pl->ready.rate = w > WIDE_ABOVE ? w : w << 16;
    pl->has_ready = 1;
    pl->has_carry = 0;
    pl->pos = ramp_position_after(pl->pos, pl->ramp.dir, 1);
}

/* A move from rest: the constants are converted again only when parameters were set while moving
 * (unchanged parameters give the same constants; the conversion's 64-bit divisions cost about 1.5 ms
 * of the AVR with three axes stepping) */
static motion_status_t exact_from_rest(step_planner_t *pl, int32_t to)
{
    step_exact_t e = pl->exact;
    motion_status_t st;
    if (pl->params_new) {
        st = step_exact_set_params(&e, &pl->params);
        if (st != MS_OK)
            return st;
    }
    step_exact_reset(&e, pl->pos);
    st = step_exact_plan(&e, to);
    if (st != MS_OK)
        return st;
    pl->exact = e;
    pl->params_new = 0;
    return MS_OK;
}

static motion_status_t lab_from_rest(step_planner_t *pl, int32_t to)
{
    return ramp_plan_lab(&pl->ramp, pl->algo, &pl->params, pl->hooks, pl->pos, to);
}

static motion_status_t leib_from_rest(step_planner_t *pl, int32_t to)
{
    return ramp_plan_leib(&pl->ramp, pl->algo, &pl->params, pl->hooks, pl->pos, to);
}

static motion_status_t simplistic_from_rest(step_planner_t *pl, int32_t to)
{
    return ramp_plan_simplistic(&pl->ramp, pl->algo, &pl->params, pl->hooks, pl->pos, to);
}

static motion_status_t sigmoid_from_rest(step_planner_t *pl, int32_t to)
{
    return ramp_plan_sigmoid(&pl->ramp, &pl->sig, pl->table, pl->table_len, pl->pos, to);
}

static motion_status_t plan_from_rest(step_planner_t *pl, int32_t to)
{
    motion_status_t st = RAMP_TABLE_FN(pl->ops, from_rest)(pl, to);
    if (st != MS_OK)
        return st;
    pl->active = 1;
    pl->target = to;
    return MS_OK;
}

/* moving: the ramp has steps left (the speed is not that of rest) */
static uint8_t ramp_moving(const step_planner_t *pl)
{
    return pl->active && (pl->has_carry || ramp_steps_left(&pl->ramp) > 0);
}

static motion_status_t stop_ramp(step_planner_t *pl)
{
    ramp_t n;
    uint32_t ds;
    motion_status_t st;
    flush_carry(pl);
    ds = ramp_stop_steps_under(&pl->ramp, pl->algo == RAMP_ALGO_SIGMOID ? 0 : &pl->params);
    st = ramp_plan_continue(&n, &pl->ramp, pl->algo == RAMP_ALGO_SIGMOID ? 0 : &pl->params,
                            ramp_position_after(pl->pos, pl->ramp.dir, ds));
    if (st != MS_OK)
        return st;
    pl->ramp = n;
    pl->target = n.to;
    return MS_OK;
}

static motion_status_t exact_move(step_planner_t *pl, int32_t to)
{
    motion_status_t st;
    {
        step_exact_t e = pl->exact;
        if (!e.moving || !pl->active)
            return (pl->has_then = 0, plan_from_rest(pl, to));
        if (pl->params_new) {
            /* the speed carried into set's new values (several 64-bit divisions: only when there are
             * new values, so that a stop or a new target is planned fast) */
            st = step_exact_change_params(&e, &pl->params);
            if (st != MS_OK)
                return st;
        }
        pl->params_new = 0;
        if (step_exact_plan(&e, to) == MS_OK) {
            pl->exact = e;
            pl->has_then = 0;
            pl->target = to;
            return MS_OK;
        }
        step_exact_stop(&e);
        pl->exact = e;
        pl->has_then = 1;
        pl->then_target = to;
        pl->target = to;
        return MS_OK;
    }
}

static motion_status_t ramp_move(step_planner_t *pl, int32_t to)
{
    motion_status_t st;
    if (!ramp_moving(pl)) {
        pl->has_then = 0;
        return plan_from_rest(pl, to);
    }
    flush_carry(pl);
    {
        ramp_t n;
        st = ramp_plan_continue(&n, &pl->ramp, pl->algo == RAMP_ALGO_SIGMOID ? 0 : &pl->params, to);
        if (st == MS_OK) {
            pl->ramp = n;
            pl->has_then = 0;
            pl->target = to;
            return MS_OK;
        }
        if (st != MS_ERR_BUSY)
            return st;
        st = stop_ramp(pl);
        if (st != MS_OK)
            return st;
        pl->has_then = 1;
        pl->then_target = to;
        pl->target = to;
        return MS_OK;
    }
}

motion_status_t step_planner_move(step_planner_t *pl, int32_t to)
{
    return RAMP_TABLE_FN(pl->ops, move)(pl, to);
}

static void exact_stop(step_planner_t *pl)
{
    if (pl->active && pl->exact.moving) {
        /* a stop is a plan: it decelerates at the accel in force now (set while moving) */
        if (pl->params_new) {
            step_exact_t e = pl->exact; /* (a copy of 160 bytes: only then) */
            if (step_exact_change_params(&e, &pl->params) == MS_OK) {
                if (e.k.cu != pl->exact.k.cu || e.k.u0 != pl->exact.k.u0 || e.k.vu != pl->exact.k.vu)
                    pl->exact = e; /* unchanged: the profile stays (a stop then never passes the target) */
                pl->params_new = 0;
            }
        }
        step_exact_stop(&pl->exact);
        pl->target = ramp_position_after(pl->exact.pos, pl->exact.dir, pl->exact.d - pl->exact.n);
    }
}

static void ramp_stop(step_planner_t *pl)
{
    if (ramp_moving(pl))
        (void)stop_ramp(pl);
}

void step_planner_stop(step_planner_t *pl)
{
    pl->has_then = 0;
    RAMP_TABLE_FN(pl->ops, stop)(pl);
}

/* whether the ramp may have reached a cruise to skip: a cheap test first (simplistic and Leib
 * cruise only at their peak level), the full one (ramp_cruise_skippable) only then */
static uint8_t may_skip(const ramp_t *r)
{
    if ((r->algo == RAMP_ALGO_SIMPLISTIC || r->algo == RAMP_ALGO_LEIB) && r->level != r->peak_level)
        return 0;
    if (r->algo == RAMP_ALGO_SIGMOID &&
        (r->start_level != 0 ? r->u.sigmoid.k != r->accel_steps : r->steps_done < r->accel_steps))
        return 0; /* the sigmoid's cruise: after its accel_steps, or (continued) at the table's top */
    return ramp_cruise_skippable(r) != 0;
}

/* one command from the ramp's steps: a run of whole-tick intervals with a constant difference */
static uint8_t next_from_ramp(step_planner_t *pl, step_cmd_t *c)
{
    ramp_t *r = &pl->ramp;
    uint32_t w, w1, last, count = 1, dur;
    int32_t add = 0;
    uint8_t wide;
    ramp_phase_t phase, ph;
    if (!pl->has_carry) {
        uint32_t skip = may_skip(r) ? ramp_cruise_skippable(r) : 0;
        if (skip > 0) {
            /* the cruise: whole commands of one interval */
            uint32_t cap;
            w = nonzero(r->whole_ticks);
            cap = pl->max_cmd_ticks / w;
            if (cap < 1U)
                cap = 1U;
            if (cap > 65535U)
                cap = 65535U;
            if (skip > cap)
                skip = cap;
            skip = ramp_skip_cruise_at_most(r, skip);
            c->count = (uint16_t)skip;
            c->add = 0;
            c->flags = (uint8_t)((r->dir < 0 ? STEP_CMD_REVERSE : 0) | (w > WIDE_ABOVE ? STEP_CMD_WIDE : 0) |
                                 ((uint8_t)RAMP_CRUISE << STEP_CMD_PHASE_SHIFT));
            c->rate = w > WIDE_ABOVE ? w : w << 16;
            pl->pos = ramp_position_after(pl->pos, r->dir, skip);
            return 1;
        }
        if (!ramp_next_ticks(r, &w1, &phase))
            return 0;
    } else {
        w1 = pl->carry.whole_ticks;
        phase = pl->carry.phase;
        pl->has_carry = 0;
    }
    w1 = nonzero(w1);
    wide = w1 > WIDE_ABOVE;
    last = w1;
    dur = w1;
    if (r->algo == RAMP_ALGO_SIGMOID && !wide) {
        /* a table entry's held steps at once: one interval, add 0 (the 4 ms bound of a command may
         * be passed by one entry's hold) */
        uint32_t more = ramp_take_same(r, 65534U);
        count += more;
        dur += more * w1;
    }
    /* the per-step loop: the algorithm's arithmetic (its step, fetched once) and a few integer tests */
    ramp_step_fn_t step = ramp_step_fn(r);
    while (count < 65535U && dur < pl->max_cmd_ticks && !may_skip(r)) {
        int32_t d;
        if (!ramp_next_ticks_with(r, step, &w, &ph))
            break;
        w = nonzero(w);
        d = (int32_t)(w - last);
        if ((w > WIDE_ABOVE) != wide || (wide && w != last) || d > 32767 || d < -32767 ||
            (count >= 2U && d != add) || ph != phase) {
            pl->carry.whole_ticks = w;
            pl->carry.phase = ph;
            pl->has_carry = 1;
            break;
        }
        if (count == 1U)
            add = d;
        count++;
        last = w;
        dur += w;
        if (add == 0 && r->algo == RAMP_ALGO_SIGMOID && !wide && dur < pl->max_cmd_ticks) {
            uint32_t more = ramp_take_same(r, 65535U - count);
            count += more;
            dur += more * w;
        }
    }
    c->count = (uint16_t)count;
    c->flags = (uint8_t)((r->dir < 0 ? STEP_CMD_REVERSE : 0) | (wide ? STEP_CMD_WIDE : 0) |
                         ((uint8_t)phase << STEP_CMD_PHASE_SHIFT));
    c->rate = wide ? w1 : w1 << 16;
    c->add = wide ? 0 : (int32_t)((uint32_t)add << 16);
    pl->pos = ramp_position_after(pl->pos, r->dir, count);
    return 1;
}

static uint8_t exact_next(step_planner_t *pl, step_cmd_t *c)
{
    if (!step_exact_next(&pl->exact, c))
        return 0;
    pl->pos = pl->exact.pos;
    return 1;
}

static motion_status_t exact_rewind(step_planner_t *pl, uint32_t steps, int64_t time16, uint16_t last_count)
{
    motion_status_t st;
    /* k stays the profile's while it is handed out; after its last command a set may have changed it */
    if (steps >= pl->exact.n || (!pl->active && !step_exact_profile_intact(&pl->exact)))
        return MS_ERR_OUT_OF_RANGE;
    st = step_exact_rewind(&pl->exact, pl->exact.n - steps, pl->exact.acc16 - time16, last_count);
    if (st != MS_OK)
        return st;
    pl->pos = pl->exact.pos;
    pl->active = 1; /* the profile has commands to hand out again (or ends at the next call) */
    return MS_OK;
}

static uint32_t exact_rewindable(const step_planner_t *pl)
{
    return pl->exact.n >= 2U ? pl->exact.n - 1U : 0U;
}

static const struct step_planner_ops EXACT_OPS RAMP_TABLE_MEM = {
    exact_set_params, exact_left, exact_from_rest, exact_move, exact_stop, exact_next, exact_reset, exact_rewind,
    exact_rewindable
};
/* the stepwise ramps: the lab's two (ramp_plan_lab), each of them alone, and the sigmoid, apart so that
 * each links only its own */
static const struct step_planner_ops LAB_OPS RAMP_TABLE_MEM = {
    lab_set_params, ramp_left, lab_from_rest, ramp_move, ramp_stop, next_from_ramp, ramp_reset, 0, 0
};
static const struct step_planner_ops LEIB_OPS RAMP_TABLE_MEM = {
    leib_set_params, ramp_left, leib_from_rest, ramp_move, ramp_stop, next_from_ramp, ramp_reset, 0, 0
};
static const struct step_planner_ops SIMPLISTIC_OPS RAMP_TABLE_MEM = {
    simplistic_set_params, ramp_left, simplistic_from_rest, ramp_move, ramp_stop, next_from_ramp, ramp_reset, 0, 0
};
static const struct step_planner_ops SIGMOID_OPS RAMP_TABLE_MEM = {
    sigmoid_set_params, ramp_left, sigmoid_from_rest, ramp_move, ramp_stop, next_from_ramp, ramp_reset, 0, 0
};

uint8_t step_planner_next(step_planner_t *pl, step_cmd_t *c)
{
    if (pl->has_ready) {
        *c = pl->ready;
        pl->has_ready = 0;
        return 1;
    }
    for (;;) {
        if (!pl->active) {
            if (!pl->has_then)
                return 0;
            pl->has_then = 0;
            RAMP_TABLE_FN(pl->ops, reset)(pl);
            if (plan_from_rest(pl, pl->then_target) != MS_OK)
                return 0;
        }
        if (RAMP_TABLE_FN(pl->ops, next)(pl, c))
            return 1;
        pl->active = 0;
    }
}

/* ---- the smooth move (smooth_move.h), its state in the caller's step_smooth_t ---- */
static void smooth_params_of(smooth_params_t *sp, const ramp_params_t *p, double jerk_sps3)
{
    sp->vmax_sps = p->vmax_sps;
    sp->accel_sps2 = p->accel_sps2;
    sp->jerk_sps3 = jerk_sps3;
    sp->tick_hz = p->tick_hz;
}

motion_status_t step_planner_smooth_check(const ramp_params_t *params, double jerk_sps3)
{
    smooth_law_t law;
    smooth_params_t sp;
    if (params == 0)
        return MS_ERR_NULL;
    smooth_params_of(&sp, params, jerk_sps3);
    return smooth_law_set_params(&law, &sp);
}

motion_status_t step_planner_init_smooth(step_planner_t *pl, const ramp_params_t *params, double jerk_sps3,
                                         step_smooth_t *store, int32_t pos)
{
    smooth_params_t sp;
    motion_status_t st;
    if (pl == 0 || params == 0 || store == 0)
        return MS_ERR_NULL;
    smooth_params_of(&sp, params, jerk_sps3);
    st = smooth_move_init(&store->move, &sp, pos);
    if (st != MS_OK)
        return st;
    store->jerk_sps3 = jerk_sps3;
    store->params_pending = 0;
    pl->ops = &SMOOTH_OPS;
    pl->algo = RAMP_ALGO_SMOOTH;
    pl->hooks = 0;
    pl->params = *params;
    pl->table = 0;
    pl->table_len = 0;
    pl->max_cmd_ticks = params->tick_hz / 250U; /* 4 ms */
    pl->smooth = store;
    clear_state(pl, pos);
    store->move.max_cmd_ticks = pl->max_cmd_ticks;
    return MS_OK;
}

/* the parameters (pl->params, or params) and the jerk in force: now at rest (here, outside the
 * step interrupt's planner tick when the caller is loop()), else from the next move from rest */
static motion_status_t smooth_apply(step_planner_t *pl, const ramp_params_t *params, double jerk_sps3)
{
    smooth_params_t sp;
    motion_status_t st = step_planner_smooth_check(params, jerk_sps3);
    if (st != MS_OK)
        return st;
    pl->smooth->jerk_sps3 = jerk_sps3;
    smooth_params_of(&sp, params, jerk_sps3);
    if (!pl->active && !pl->has_then && !smooth_move_busy(&pl->smooth->move) &&
        smooth_move_set_params(&pl->smooth->move, &sp) == MS_OK) {
        pl->params_new = 0;
        pl->smooth->params_pending = 0;
        return MS_OK;
    }
    pl->params_new = 1;
    pl->smooth->params_pending = 1; /* survives the halt at the move's end (found by a review of the
                                       SmoothConsole example: a vmax set while moving never applied) */
    return MS_OK;
}

static motion_status_t smooth_set_params(step_planner_t *pl, const ramp_params_t *params)
{
    return smooth_apply(pl, params, pl->smooth->jerk_sps3);
}

motion_status_t step_planner_set_jerk(step_planner_t *pl, double jerk_sps3)
{
    if (pl == 0)
        return MS_ERR_NULL;
    if (pl->algo != RAMP_ALGO_SMOOTH)
        return MS_ERR_NOT_SUPPORTED;
    return smooth_apply(pl, &pl->params, jerk_sps3);
}

static uint8_t smooth_left(const step_planner_t *pl)
{
    return smooth_move_busy(&pl->smooth->move);
}

static motion_status_t smooth_from_rest(step_planner_t *pl, int32_t to)
{
    smooth_move_t *m = &pl->smooth->move;
    if (pl->params_new || pl->smooth->params_pending) {
        smooth_params_t sp;
        motion_status_t st;
        smooth_params_of(&sp, &pl->params, pl->smooth->jerk_sps3);
        smooth_move_halt(m, pl->pos);
        st = smooth_move_set_params(m, &sp);
        if (st != MS_OK)
            return st;
        pl->params_new = 0;
        pl->smooth->params_pending = 0;
    }
    m->max_cmd_ticks = pl->max_cmd_ticks;
    smooth_move_halt(m, pl->pos);
    return smooth_move_to(m, to);
}

static motion_status_t smooth_move_op(step_planner_t *pl, int32_t to)
{
    motion_status_t st;
    if (!pl->active || !smooth_move_busy(&pl->smooth->move)) {
        pl->has_then = 0;
        return plan_from_rest(pl, to);
    }
    /* continuing from the filter's state; a target behind: its stop, then the move from rest */
    st = smooth_move_to(&pl->smooth->move, to);
    if (st == MS_OK)
        pl->target = smooth_move_target(&pl->smooth->move);
    return st;
}

static void smooth_stop(step_planner_t *pl)
{
    if (pl->active && smooth_move_busy(&pl->smooth->move)) {
        smooth_move_stop(&pl->smooth->move);
        pl->target = smooth_move_target(&pl->smooth->move);
    }
}

static uint8_t smooth_next(step_planner_t *pl, step_cmd_t *c)
{
    if (!smooth_move_next(&pl->smooth->move, c))
        return 0;
    pl->pos = smooth_move_position(&pl->smooth->move);
    return 1;
}

static void smooth_reset(step_planner_t *pl)
{
    smooth_move_halt(&pl->smooth->move, pl->pos);
}

static motion_status_t smooth_rewind(step_planner_t *pl, uint32_t steps, int64_t time16, uint16_t last_count)
{
    motion_status_t st;
    (void)last_count;
    if (!pl->active)
        return MS_ERR_OUT_OF_RANGE;
    st = smooth_move_rewind(&pl->smooth->move, steps, time16); /* its own checks */
    if (st == MS_OK)
        pl->pos = smooth_move_position(&pl->smooth->move);
    return st;
}

static uint32_t smooth_rewindable(const step_planner_t *pl)
{
    return pl->active ? smooth_move_rewindable(&pl->smooth->move) : 0U;
}

static const struct step_planner_ops SMOOTH_OPS RAMP_TABLE_MEM = {
    smooth_set_params, smooth_left, smooth_from_rest, smooth_move_op, smooth_stop, smooth_next, smooth_reset,
    smooth_rewind, smooth_rewindable
};

motion_status_t step_planner_rewind(step_planner_t *pl, uint32_t steps, int64_t time16, uint16_t last_count)
{
    if (pl == 0)
        return MS_ERR_NULL;
    if (!RAMP_TABLE_FN(pl->ops, rewind))
        return MS_ERR_NOT_SUPPORTED; /* the stepwise ramps cannot (yet) go back to a boundary */
    return RAMP_TABLE_FN(pl->ops, rewind)(pl, steps, time16, last_count);
}

uint32_t step_planner_rewindable(const step_planner_t *pl)
{
    return RAMP_TABLE_FN(pl->ops, rewindable) ? RAMP_TABLE_FN(pl->ops, rewindable)(pl) : 0U;
}

uint8_t step_planner_mirror_ok(const step_planner_t *pl, uint32_t steps_back)
{
    return pl != 0 && pl->algo == RAMP_ALGO_EXACT && pl->active && !pl->params_new && steps_back < pl->exact.n &&
           step_exact_mirror_ok(&pl->exact, pl->exact.n - steps_back);
}

motion_status_t step_planner_stop_mirrored(step_planner_t *pl, uint32_t steps_back, uint32_t steps, int64_t time16)
{
    motion_status_t st;
    if (!step_planner_mirror_ok(pl, steps_back))
        return MS_ERR_OUT_OF_RANGE;
    st = step_exact_stop_mirrored(&pl->exact, pl->exact.n - steps_back, steps, time16);
    if (st != MS_OK)
        return st;
    pl->pos = pl->exact.pos;
    pl->target = ramp_position_after(pl->exact.pos, pl->exact.dir, pl->exact.d - pl->exact.n);
    pl->has_then = 0;
    pl->active = 1;
    return MS_OK;
}
