/* Unit tests: cutting the queued commands and replanning from the cut (step_exact_rewind,
 * step_planner_rewind, step_exact_cmd_time16; issue 23 item 4, the planner's part).
 * References: the executor itself (step_exec_next) for a command's time; a planner that never
 * emitted the dropped commands (the same calls without them) for the commands after a rewind, bit
 * for bit; the closed form of constant acceleration (closed_form.h, long double, independent of
 * lib/) for the step times of a stop planned after a rewind and the speed at the cut. */
#include "cmocka_all.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "step_exact.h"
#include "step_planner.h"
#include "step_queue.h"

#define TEST_RNG_SEED 0x5EEC2026D1CEULL
#define SPAN_MAX 128U /* the longest command of a ramp (step_exact.c: 2^SEG_B steps) */
#include "closed_form.h"

/* ---- a command's time in the executor -------------------------------------------------------- */

/* runs c through the executor; returns the time its steps took, 2^-16 ticks, counted in 64 bits
 * from the executor's own increments (WIDE: whole ticks) */
static int64_t exec_time16(const step_cmd_t *c)
{
    step_exec_t x;
    uint64_t sum = 0;
    uint32_t before;
    step_exec_init(&x, 0x8000U);
    step_exec_load(&x, c);
    while (x.left > 0U) {
        uint32_t rate = x.rate;
        before = x.acc;
        (void)step_exec_next(&x);
        if (c->flags & STEP_CMD_WIDE)
            sum += (uint64_t)rate << 16;
        else
            sum += rate; /* the increment the executor made */
        assert_int_equal((uint32_t)(x.acc - before), (uint32_t)((c->flags & STEP_CMD_WIDE) ? rate << 16 : rate));
    }
    return (int64_t)sum;
}

static void cmd_time_is_the_executors(void **state)
{
    uint32_t i;
    step_cmd_t c;
    (void)state;
    /* 2.5, 3.75, 5.0 ticks: 11.25 ticks */
    c.rate = 0x28000U;
    c.add = 0x14000;
    c.count = 3;
    c.flags = 0;
    assert_true(step_exact_cmd_time16(&c) == 11 * 65536 + 16384);
    for (i = 0; i < 20000U; i++) {
        uint32_t count = (i % 5U) == 0 ? 1U + (uint32_t)urand(0, 65535) : 1U + (uint32_t)lrand(1, 300);
        c.count = (uint16_t)count;
        c.flags = (uint8_t)((i & 1U) ? STEP_CMD_REVERSE : 0U);
        if ((i % 7U) == 0) {
            c.flags |= STEP_CMD_WIDE;
            c.rate = 65536U + (uint32_t)lrand(1, 4.0e9);
            c.add = 0;
            c.count = (uint16_t)(1U + (uint32_t)urand(0, 4));
        } else {
            /* intervals from rate to rate + add (count - 1), all within 1..65535 ticks */
            double r0 = lrand(1, 65535), r1 = (i % 3U) == 0 ? r0 : lrand(1, 65535);
            int64_t add = count > 1U ? (int64_t)((r1 - r0) * 65536.0 / (double)(count - 1U)) : 0;
            if (add != (int32_t)add)
                add = 0; /* beyond what a command's add holds */
            c.rate = (uint32_t)(r0 * 65536.0);
            c.add = (int32_t)add;
            if ((int64_t)c.rate + add * (int64_t)(count - 1U) < 65536)
                c.add = 0;
        }
        if (step_exact_cmd_time16(&c) != exec_time16(&c))
            fail_msg("rate %u add %d count %u flags %u: %lld, the executor %lld", c.rate, c.add, c.count, c.flags,
                     (long long)step_exact_cmd_time16(&c), (long long)exec_time16(&c));
    }
}

/* ---- planners A and B ------------------------------------------------------------------------ */

static int cmd_eq(const step_cmd_t *a, const step_cmd_t *b)
{
    return a->rate == b->rate && a->add == b->add && a->count == b->count && a->flags == b->flags;
}

/* The state that decides what comes next, field by field (where B must equal A exactly) */
static void expect_same_state(const step_exact_t *a, const step_exact_t *b, const char *what)
{
    if (a->pos != b->pos || a->n != b->n || a->moving != b->moving || a->acc16 != b->acc16 || a->y != b->y ||
        a->q != b->q || a->err != b->err || a->d != b->d || a->dir != b->dir ||
        (a->y != 0U && a->slope_i != b->slope_i) || (a->y == 0U && a->cfrac != b->cfrac))
        fail_msg("%s: rewound state differs: n %u/%u pos %d/%d acc16 %lld/%lld y %llu/%llu q %llu/%llu err %d/%d "
                 "slope %u/%u cfrac %u/%u moving %u/%u",
                 what, a->n, b->n, a->pos, b->pos, (long long)a->acc16, (long long)b->acc16, (unsigned long long)a->y,
                 (unsigned long long)b->y, (unsigned long long)a->q, (unsigned long long)b->q, a->err, b->err,
                 a->slope_i, b->slope_i, a->cfrac, b->cfrac, a->moving, b->moving);
}

/* The span state where the rewind rebuilds it exactly: region A decelerating and region D (the
 * span the rule allows, or 0 after a span whose intervals did not fit; both 0: the same) */
static void expect_same_span(const step_exact_t *a, const step_exact_t *b, uint16_t last_count, const char *what)
{
    uint32_t p = a->n - last_count;
    /* (at the end of the region the span is never read again) */
    uint8_t in_d = p >= a->n1 && p >= a->n2 && a->n < a->d, in_a_down = a->a_down && a->n < a->n1;
    if ((in_d || in_a_down) && (a->span_b != 0U || b->span_b != 0U) &&
        (a->span_b != b->span_b || a->thr != b->thr))
        fail_msg("%s: span %u/%u thr %u/%u after the rewind", what, a->span_b, b->span_b, a->thr, b->thr);
}

/* A and B hand out commands until both are done (or max commands): the same, bit for bit */
static uint32_t expect_same_commands(step_planner_t *a, step_planner_t *b, uint32_t max, const char *what)
{
    step_cmd_t ca, cb;
    uint32_t k = 0;
    for (;;) {
        uint8_t ra, rb;
        if (k >= max)
            break;
        ra = step_planner_next(a, &ca);
        rb = step_planner_next(b, &cb);
        if (ra != rb)
            fail_msg("%s: command %u: A %s, B %s", what, k, ra ? "one more" : "done", rb ? "one more" : "done");
        if (!ra)
            break;
        if (!cmd_eq(&ca, &cb))
            fail_msg("%s: command %u differs: A rate %u add %d count %u flags %u, B rate %u add %d count %u flags %u",
                     what, k, ca.rate, ca.add, ca.count, ca.flags, cb.rate, cb.add, cb.count, cb.flags);
        k++;
    }
    assert_int_equal(step_planner_position(a), step_planner_position(b));
    assert_int_equal(step_planner_target(a), step_planner_target(b));
    return k;
}

typedef enum { ACT_NONE, ACT_STOP, ACT_AHEAD, ACT_NEAR, ACT_BEHIND, ACT_SET_MOVE, ACT__N } act_t;

static int32_t clamp_target(int64_t t)
{
    if (t > INT32_MAX)
        return INT32_MAX;
    if (t < INT32_MIN)
        return INT32_MIN;
    return (int32_t)t;
}

/* the same stop / new target on A and B */
static void act(step_planner_t *a, step_planner_t *b, act_t what, const ramp_params_t *p2, uint32_t span)
{
    int32_t pos = step_planner_position(a);
    int8_t dir = a->exact.dir != 0 ? a->exact.dir : 1;
    int32_t to = pos;
    motion_status_t sa, sb;
    switch (what) {
    case ACT_NONE:
        return;
    case ACT_STOP:
        step_planner_stop(a);
        step_planner_stop(b);
        return;
    case ACT_AHEAD:
        to = clamp_target((int64_t)pos + dir * (int64_t)(span + 1U));
        break;
    case ACT_NEAR:
        to = clamp_target((int64_t)pos + dir * (int64_t)(1U + span / 64U));
        break;
    case ACT_BEHIND:
        to = clamp_target((int64_t)pos - dir * (int64_t)(1U + span / 8U));
        break;
    case ACT_SET_MOVE:
        assert_int_equal(step_planner_set_params(a, p2), MS_OK);
        assert_int_equal(step_planner_set_params(b, p2), MS_OK);
        to = clamp_target((int64_t)pos + dir * (int64_t)(span / 2U + 1U));
        break;
    default:
        break;
    }
    sa = step_planner_move(a, to);
    sb = step_planner_move(b, to);
    assert_int_equal(sa, sb);
}

static uint32_t stat_cases, stat_refused, stat_cmds;

/* One cut: pl has handed out some commands; A = pl. B hands out `more` further commands, takes
 * them back (step_planner_rewind with their steps and executor time, the last kept command's
 * count), then A and B get the same stop or new target and must hand out the same commands. */
static void cut_case(const step_planner_t *pl, const step_cmd_t *last_kept, uint32_t more, act_t what,
                     const ramp_params_t *p2, uint32_t span, uint32_t max_after, const char *label)
{
    step_planner_t a = *pl, b = *pl, saved;
    step_cmd_t c;
    uint32_t steps = 0, i;
    int64_t t16 = 0;
    motion_status_t st;
    char what_s[160];
    for (i = 0; i < more && step_planner_next(&b, &c); i++) {
        steps += c.count;
        t16 += step_exact_cmd_time16(&c);
    }
    saved = b;
    st = step_planner_rewind(&b, steps, t16, last_kept->count);
    stat_cases++;
    if (st != MS_OK) {
        /* only when the dropped commands reach into another profile (a stop's move from rest) or
         * the profile ended by a replan: then the planner is untouched */
        assert_int_equal(st, MS_ERR_OUT_OF_RANGE);
        assert_memory_equal(&saved, &b, sizeof b);
        assert_true(steps >= saved.exact.n || a.exact.n == 0U || saved.exact.us != a.exact.us ||
                    saved.exact.d != a.exact.d);
        stat_refused++;
        return;
    }
    snprintf(what_s, sizeof what_s, "%s: cut after %u steps of the profile, %u commands dropped, action %d", label,
             a.exact.n, i, (int)what);
    expect_same_state(&a.exact, &b.exact, what_s);
    expect_same_span(&a.exact, &b.exact, last_kept->count, what_s);
    assert_int_equal(step_planner_position(&a), step_planner_position(&b));
    act(&a, &b, what, p2, span);
    stat_cmds += expect_same_commands(&a, &b, max_after, what_s);
}

static void random_params(ramp_params_t *p, uint32_t i)
{
    uint32_t f = (i % 3U) == 0 ? 2000000U : 16000000U;
    double a = lrand(50, 3e6);
    double vmax = lrand(20, 160000);
    double v0 = (i % 4U) == 0 ? 0.0 : vmax * urand(0, 0.6);
    p->v0_sps = (float)v0;
    p->vmax_sps = (float)vmax;
    p->accel_sps2 = (float)a;
    p->tick_hz = f;
}

/* hands out commands until the cut: k commands of the current profile (the last one in *last) */
static uint8_t run_to_cut(step_planner_t *pl, uint32_t k, step_cmd_t *last)
{
    uint32_t i;
    for (i = 0; i < k; i++)
        if (!step_planner_next(pl, last))
            return 0;
    return 1;
}

static void random_cuts_bit_for_bit(void **state)
{
    uint32_t i, done = 0;
    (void)state;
    stat_cases = stat_refused = stat_cmds = 0;
    for (i = 0; i < 2500U; i++) {
        ramp_params_t p, p2;
        step_planner_t pl;
        step_cmd_t last;
        uint32_t d = (uint32_t)lrand(1, 60000), k, more;
        int32_t from = (int32_t)urand(-100000, 100000);
        int8_t dir = (i & 1U) ? 1 : -1;
        act_t what = (act_t)(i % ACT__N);
        char label[200];
        random_params(&p, i);
        random_params(&p2, i + 1U);
        if (step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, from) != MS_OK ||
            step_planner_set_params(&pl, &p2) != MS_OK)
            continue;
        assert_int_equal(step_planner_set_params(&pl, &p), MS_OK);
        assert_int_equal(step_planner_move(&pl, from + dir * (int32_t)d), MS_OK);
        snprintf(label, sizeof label, "case %u: v0 %g vmax %g a %g F %u D %u dir %d", i, p.v0_sps, p.vmax_sps,
                 p.accel_sps2, p.tick_hz, d, dir);
        if ((i % 5U) == 1U) {
            /* continued: a replan (new target, maybe new parameters) after some commands */
            uint32_t j = 1U + (uint32_t)lrand(1, 200);
            (void)run_to_cut(&pl, j, &last);
            if ((i % 10U) == 1U)
                assert_int_equal(step_planner_set_params(&pl, &p2), MS_OK);
            if (step_planner_move(&pl, from + dir * (int32_t)(d + (uint32_t)lrand(1, 30000))) != MS_OK)
                continue;
        } else if ((i % 5U) == 3U) {
            /* reversed: a stop, then the move back from rest (the cut in either) */
            uint32_t j = 1U + (uint32_t)lrand(1, 200);
            (void)run_to_cut(&pl, j, &last);
            if (step_planner_move(&pl, from - dir * (int32_t)(uint32_t)lrand(1, 30000)) != MS_OK)
                continue;
        }
        /* the cut: somewhere in the profile (k commands of it), often early, sometimes late */
        k = 1U + (uint32_t)((i % 3U) == 0 ? urand(0, 8) : lrand(1, 3000));
        if (!run_to_cut(&pl, k, &last))
            continue;
        more = (i % 9U) == 0 ? 0U : (uint32_t)lrand(1, 60);
        cut_case(&pl, &last, more, what, &p2, d, 5000000U, label);
        done++;
    }
    printf("# %u cuts (%u refused as they should be), %u commands compared after them\n", stat_cases, stat_refused,
           stat_cmds);
    assert_true(done > 1500U);
    assert_true(stat_refused < stat_cases / 10U);
}

/* every boundary of some moves in turn (the spans' growth and shrinking, the cruise's entry, region
 * D's first step, slow steps that do not fit a span): cut at each, B drops 1..9 commands */
static void every_boundary(void **state)
{
    static const struct {
        float v0, vmax, a;
        uint32_t f, d;
    } mv[] = {
        {0.0f, 20000.0f, 50000.0f, 16000000U, 20000U},   /* the sketch's defaults */
        {0.0f, 160000.0f, 3.0e6f, 16000000U, 30000U},    /* fast */
        {0.0f, 300.0f, 60.0f, 2000000U, 3000U},          /* slow: long intervals, spans that fail */
        {5.0f, 400.0f, 9.0f, 16000000U, 4000U},          /* slow from v0, WIDE steps */
        {1000.0f, 5000.0f, 2.0e5f, 16000000U, 1000U},    /* short ramps, a long cruise */
        {0.0f, 50000.0f, 1.0e5f, 16000000U, 7000U},      /* triangular */
        {0.0f, 20000.0f, 50000.0f, 16000000U, 3U},       /* three steps */
    };
    uint32_t m;
    (void)state;
    for (m = 0; m < sizeof mv / sizeof mv[0]; m++) {
        ramp_params_t p = {mv[m].v0, mv[m].vmax, mv[m].a, mv[m].f};
        step_planner_t pl;
        step_cmd_t last;
        uint32_t k;
        char label[160];
        assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0), MS_OK);
        assert_int_equal(step_planner_move(&pl, (int32_t)mv[m].d), MS_OK);
        for (k = 0; step_planner_next(&pl, &last); k++) {
            snprintf(label, sizeof label, "move %u command %u", m, k);
            cut_case(&pl, &last, 1U + k % 9U, (act_t)(k % ACT__N), &p, mv[m].d, 100000U, label);
        }
    }
}

/* a move with a decelerating region A (entered above vmax after vmax is lowered while moving) */
static void every_boundary_from_above_vmax(void **state)
{
    ramp_params_t p = {0.0f, 40000.0f, 80000.0f, 16000000U}, p2 = {0.0f, 6000.0f, 50000.0f, 16000000U};
    step_planner_t pl;
    step_cmd_t last;
    uint32_t k, above = 0;
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 100000), MS_OK);
    while (step_planner_next(&pl, &last) && pl.exact.n < 9000U) {
    }
    assert_int_equal(step_planner_set_params(&pl, &p2), MS_OK);
    assert_int_equal(step_planner_move(&pl, 100000), MS_OK);
    assert_true(pl.exact.a_down);
    for (k = 0; step_planner_next(&pl, &last); k++) {
        char label[80];
        if (pl.exact.n <= pl.exact.n1)
            above++;
        snprintf(label, sizeof label, "from above vmax, command %u", k);
        cut_case(&pl, &last, 1U + k % 7U, (act_t)(k % ACT__N), &p, 50000U, 100000U, label);
    }
    assert_true(above > 20U);
}

/* the same slow: region A's intervals too long for a span (single steps from there on) */
static void every_boundary_from_above_vmax_slow(void **state)
{
    ramp_params_t p = {0.0f, 400.0f, 9.0f, 16000000U}, p2 = {0.0f, 150.0f, 9.0f, 16000000U};
    step_planner_t pl;
    step_cmd_t last;
    uint32_t k, singles = 0;
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 100000), MS_OK);
    while (step_planner_next(&pl, &last) && pl.exact.n < 8800U) {
    }
    assert_int_equal(step_planner_set_params(&pl, &p2), MS_OK);
    assert_int_equal(step_planner_move(&pl, 100000), MS_OK);
    assert_true(pl.exact.a_down);
    for (k = 0; step_planner_next(&pl, &last) && k < 20000U; k++) {
        char label[80];
        if (pl.exact.n <= pl.exact.n1 && last.count == 1U)
            singles++;
        snprintf(label, sizeof label, "slow from above vmax, command %u", k);
        cut_case(&pl, &last, 1U + k % 5U, (act_t)(k % ACT__N), &p, 50000U, 3000U, label);
    }
    assert_true(singles > 20U);
}

/* 2^31 - 1 steps: cuts early in region A, in the cruise and in region D */
static void longest_move(void **state)
{
    ramp_params_t p = {0.0f, 100000.0f, 1000000.0f, 16000000U};
    step_planner_t pl;
    step_cmd_t last;
    const uint32_t d = 2147483647U;
    uint32_t cuts = 0;
    (void)state;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, INT32_MIN), MS_OK);
    assert_int_equal(step_planner_move(&pl, -1), MS_OK);
    while (step_planner_next(&pl, &last)) {
        uint32_t n = pl.exact.n;
        if (n < 6000U || (n > 1000000000U && n < 1000050000U) || n > d - 6000U) {
            if ((cuts % 7U) == 0U || n > d - 6000U)
                cut_case(&pl, &last, 1U + cuts % 11U, (act_t)(cuts % ACT__N), &p, 100000U, 200U, "2^31 - 1 steps");
            cuts++;
        }
    }
    assert_int_equal(step_planner_position(&pl), -1);
    assert_true(cuts > 100U);
}

/* ---- the exact level: n and acc16 from A's state, or from the kept commands ---------------- */

static void exact_level_from_kept_commands(void **state)
{
    uint32_t i, ok = 0;
    (void)state;
    for (i = 0; i < 600U; i++) {
        ramp_params_t p;
        step_exact_t a, b;
        step_cmd_t c, last = {0, 0, 0, 0};
        uint32_t d = (uint32_t)lrand(1, 40000), k = 1U + (uint32_t)lrand(1, 500), j, more = (uint32_t)lrand(1, 40);
        int64_t kept16 = 0;
        random_params(&p, i);
        memset(&a, 0, sizeof a);
        if (step_exact_set_params(&a, &p) != MS_OK)
            continue;
        step_exact_reset(&a, 0);
        assert_int_equal(step_exact_plan(&a, (int32_t)d), MS_OK);
        for (j = 0; j < k && step_exact_next(&a, &c); j++) {
            kept16 += step_exact_cmd_time16(&c);
            last = c;
        }
        assert_true(kept16 == a.acc16); /* the planner's timeline is the executor's */
        b = a;
        for (j = 0; j < more && step_exact_next(&b, &c); j++) {
        }
        assert_int_equal(step_exact_rewind(&b, a.n, kept16, last.count), MS_OK);
        expect_same_state(&a, &b, "exact level");
        expect_same_span(&a, &b, last.count, "exact level");
        if ((i % 3U) == 1U) {
            step_exact_stop(&a);
            step_exact_stop(&b);
        } else if ((i % 3U) == 2U) {
            /* a new target ahead (or, nearer than the stopping distance, MS_ERR_BUSY on both) */
            int32_t to = a.pos + (int32_t)(uint32_t)lrand(1, 80000);
            assert_int_equal(step_exact_plan(&a, to), step_exact_plan(&b, to));
        }
        for (;;) {
            step_cmd_t ca, cb;
            uint8_t ra = step_exact_next(&a, &ca), rb = step_exact_next(&b, &cb);
            assert_int_equal(ra, rb);
            if (!ra)
                break;
            assert_true(cmd_eq(&ca, &cb));
        }
        ok++;
    }
    assert_true(ok > 300U);
}

/* ---- refusals change nothing ---------------------------------------------------------------- */

static void expect_refused(step_exact_t *e, uint32_t n, int64_t acc16, uint16_t count, const char *why)
{
    step_exact_t before;
    motion_status_t st;
    memcpy(&before, e, sizeof before);
    st = step_exact_rewind(e, n, acc16, count);
    if (st != MS_ERR_OUT_OF_RANGE)
        fail_msg("%s: status %d, not refused", why, (int)st);
    assert_memory_equal(&before, e, sizeof before);
}

static void refusals_change_nothing(void **state)
{
    ramp_params_t p = {0.0f, 20000.0f, 50000.0f, 16000000U}, p2 = {0.0f, 20000.0f, 60000.0f, 16000000U};
    step_exact_t e, f;
    step_planner_t pl, before;
    step_cmd_t c, last = {0, 0, 0, 0};
    int64_t acc_at_n1 = 0;
    uint32_t n_at_n1 = 0, count_at_n1 = 0;
    (void)state;
    assert_int_equal(step_exact_rewind(0, 1, 0, 1), MS_ERR_NULL);
    memset(&e, 0, sizeof e);
    assert_int_equal(step_exact_set_params(&e, &p), MS_OK);
    step_exact_reset(&e, 0);
    expect_refused(&e, 1, 0, 1, "no profile");
    assert_int_equal(step_exact_plan(&e, 20000), MS_OK);
    expect_refused(&e, 0, 0, 1, "no command emitted yet");
    while (step_exact_next(&e, &c) && e.n < 12000U) {
        if (e.n == e.n1) {
            acc_at_n1 = e.acc16;
            n_at_n1 = e.n;
            count_at_n1 = c.count;
        }
        last = c;
    }
    assert_true(n_at_n1 > 0U && e.n > e.n1);
    /* the last command's own boundary is fine (and a no-op) */
    f = e;
    assert_int_equal(step_exact_rewind(&f, e.n, e.acc16, last.count), MS_OK);
    expect_same_state(&e, &f, "rewind to the state itself");
    f = e;
    assert_int_equal(step_exact_rewind(&f, n_at_n1, acc_at_n1, (uint16_t)count_at_n1), MS_OK);
    expect_refused(&e, 0, 0, 1, "n = 0");
    expect_refused(&e, e.n + 1U, e.acc16, 1, "n beyond the steps emitted");
    expect_refused(&e, e.n, e.acc16, 0, "count 0");
    expect_refused(&e, n_at_n1, acc_at_n1, (uint16_t)(n_at_n1 + 1U), "count beyond n");
    expect_refused(&e, n_at_n1 + 1U, acc_at_n1, 2, "a command across the end of region A");
    expect_refused(&e, n_at_n1, acc_at_n1, (uint16_t)(SPAN_MAX + 1U), "region A: a count beyond the largest span");
    {
        /* a count of no span (3): the first 3 steps of a longer command, the rest cut (the engine's
         * split): the same step, speed and position as that boundary's (the span from those steps) */
        step_exact_t g = e;
        assert_int_equal(step_exact_rewind(&g, n_at_n1, acc_at_n1, 3), MS_OK);
        assert_int_equal(g.n, f.n);
        assert_true(g.y == f.y && g.q == f.q && g.pos == f.pos && g.acc16 == f.acc16);
        assert_int_equal(g.span_b, 1);
    }
    expect_refused(&e, n_at_n1, acc_at_n1 + (1LL << 21), (uint16_t)count_at_n1, "acc16 32 ticks off");
    expect_refused(&e, n_at_n1, acc_at_n1 - (1LL << 21), (uint16_t)count_at_n1, "acc16 32 ticks early");
    /* region D: its first command is one step, and spans as the rule allows */
    while (step_exact_next(&e, &c) && e.n < e.n2 + 1U) {
    }
    assert_true(e.n == e.n2 + 1U);
    expect_refused(&e, e.n, e.acc16, 2, "region D's first command is one step");
    while (step_exact_next(&e, &c) && c.count < 64U) {
    }
    assert_true(c.count >= 64U);
    expect_refused(&e, e.n, e.acc16, (uint16_t)(SPAN_MAX + 1U), "region D: a count beyond the largest span");
    {
        /* half of that command (a power of two below its span): its first half, the rest cut */
        step_exact_t g = e;
        assert_int_equal(step_exact_rewind(&g, e.n, e.acc16, (uint16_t)(c.count / 2U)), MS_OK);
        assert_true(g.n == e.n && g.y == e.y && g.q == e.q && g.pos == e.pos);
    }
    assert_int_equal(step_exact_rewind(&e, e.n, e.acc16, c.count), MS_OK);
    /* the constants changed: by change_params (the profile ends) or set_params (at rest) */
    f = e;
    assert_int_equal(step_exact_change_params(&f, &p2), MS_OK);
    expect_refused(&f, e.n, e.acc16, c.count, "after change_params");
    while (step_exact_next(&e, &c)) {
        last = c;
    }
    assert_int_equal(e.moving, 0);
    f = e;
    assert_int_equal(step_exact_rewind(&f, e.n, e.acc16, last.count), MS_OK); /* the end itself */
    /* after a set the constants may not be the profile's any more: step_exact_profile_intact */
    assert_int_equal(step_exact_profile_intact(&e), 1);
    f = e;
    assert_int_equal(step_exact_set_params(&f, &p2), MS_OK);
    assert_int_equal(step_exact_profile_intact(&f), 0); /* a new accel */
    p2.accel_sps2 = 50000.0f;
    p2.vmax_sps = 20001.0f; /* the cruise's interval */
    f = e;
    assert_int_equal(step_exact_set_params(&f, &p2), MS_OK);
    assert_int_equal(step_exact_profile_intact(&f), 0);
    p2.vmax_sps = 20000.0f;
    p2.v0_sps = 1.0f;
    f = e;
    assert_int_equal(step_exact_set_params(&f, &p2), MS_OK);
    assert_int_equal(step_exact_profile_intact(&f), 0);
    expect_refused(&f, e.n, e.acc16, last.count, "after set_params with a new v0 (the radicand shows it)");
    /* an accel one float step (ulp) away: C differs in its last bits only */
    p2 = p;
    p2.accel_sps2 = nextafterf(p.accel_sps2, 1e9f);
    f = e;
    assert_int_equal(step_exact_set_params(&f, &p2), MS_OK);
    assert_true(f.k.cu != e.k.cu);
    assert_int_equal(step_exact_profile_intact(&f), 0);
    /* C a few units different, its float the same (and so every float of the profile): short moves,
     * where nothing but the radicand shows it */
    {
        float a1 = 50000.0f, a2 = 0.0f;
        uint32_t dd, tried = 0;
        step_exact_t g;
        for (;;) {
            ramp_params_t q1 = {0.0f, 20000.0f, a1, 16000000U};
            a2 = nextafterf(a1, 1e9f);
            q1.accel_sps2 = a2;
            memset(&g, 0, sizeof g);
            assert_int_equal(step_exact_set_params(&g, &q1), MS_OK);
            q1.accel_sps2 = a1;
            memset(&f, 0, sizeof f);
            assert_int_equal(step_exact_set_params(&f, &q1), MS_OK);
            if (f.k.cu != g.k.cu && f.k.cu_f == g.k.cu_f)
                break;
            a1 = a2;
        }
        for (dd = 2; dd < 40U; dd++) {
            ramp_params_t q1 = {0.0f, 20000.0f, a1, 16000000U}, q2 = {0.0f, 20000.0f, a2, 16000000U};
            memset(&f, 0, sizeof f);
            assert_int_equal(step_exact_set_params(&f, &q1), MS_OK);
            step_exact_reset(&f, 0);
            assert_int_equal(step_exact_plan(&f, (int32_t)dd), MS_OK);
            assert_int_equal(step_exact_next(&f, &c), 1);
            g = f;
            assert_int_equal(step_exact_set_params(&g, &q2), MS_OK);
            expect_refused(&g, f.n, f.acc16, c.count, "after set_params with C a few units off");
            tried++;
        }
        assert_true(tried > 30U);
    }
    f = e;
    assert_int_equal(step_exact_set_params(&f, &p), MS_OK); /* the same values: fine */
    assert_int_equal(step_exact_profile_intact(&f), 1);
    assert_int_equal(step_exact_rewind(&f, e.n, e.acc16, last.count), MS_OK);
    /* the planner: a move handed out to its end, then a set: refused (with the same values: fine) */
    p2 = p;
    p2.accel_sps2 = 40000.0f;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 3000), MS_OK);
    while (step_planner_next(&pl, &c)) {
        last = c;
    }
    assert_int_equal(pl.active, 0);
    assert_int_equal(step_planner_set_params(&pl, &p2), MS_OK);
    before = pl;
    assert_int_equal(step_planner_rewind(&pl, last.count, step_exact_cmd_time16(&last), 1), MS_ERR_OUT_OF_RANGE);
    assert_memory_equal(&before, &pl, sizeof pl);
    assert_int_equal(step_planner_set_params(&pl, &p), MS_OK);
    assert_int_equal(step_planner_rewind(&pl, 0, 0, last.count), MS_OK);
    assert_int_equal(pl.active, 1);
    assert_int_equal(step_planner_next(&pl, &c), 0); /* the end: nothing more */
    /* the planner: other ramps not (yet); dropping the whole profile refused */
    assert_int_equal(step_planner_rewind(0, 0, 0, 1), MS_ERR_NULL);
    p.v0_sps = 100.0f;
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_LEIB, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 1000), MS_OK);
    assert_int_equal(step_planner_next(&pl, &c), 1);
    before = pl;
    assert_int_equal(step_planner_rewind(&pl, 0, 0, c.count), MS_ERR_NOT_SUPPORTED);
    assert_memory_equal(&before, &pl, sizeof pl);
    assert_int_equal(step_planner_init_trapezoid(&pl, RAMP_ALGO_EXACT, &p, 0), MS_OK);
    assert_int_equal(step_planner_move(&pl, 1000), MS_OK);
    assert_int_equal(step_planner_next(&pl, &c), 1);
    before = pl;
    assert_int_equal(step_planner_rewind(&pl, c.count, step_exact_cmd_time16(&c), c.count), MS_ERR_OUT_OF_RANGE);
    assert_memory_equal(&before, &pl, sizeof pl);
}

/* ---- the stop after a cut follows the law; the speed at the cut is continuous --------------- */

/* a profile from speed vs over D steps to v0 (peak min(vmax, what D allows)), seconds at step j */
typedef struct {
    long double vs, v0, a, vp, xa, xd, ta, tc, tt, d;
} prof_t;

static prof_t prof_plan(long double vs, long double v0, long double vmax, long double a, uint32_t d)
{
    prof_t r;
    long double vp2 = (2.0L * a * d + vs * vs + v0 * v0) / 2.0L;
    r.vs = vs;
    r.v0 = v0;
    r.a = a;
    r.d = d;
    r.vp = sqrtl(vp2);
    if (r.vp > vmax)
        r.vp = vmax;
    if (r.vp < vs)
        r.vp = vs;
    r.xa = (r.vp * r.vp - vs * vs) / (2.0L * a);
    r.xd = (r.vp * r.vp - v0 * v0) / (2.0L * a);
    r.ta = (r.vp - vs) / a;
    r.tc = (d - r.xa - r.xd) / r.vp;
    if (r.tc < 0.0L)
        r.tc = 0.0L;
    r.tt = r.ta + r.tc + (r.vp - v0) / a;
    return r;
}

static long double prof_time(const prof_t *r, long double j)
{
    if (j <= r->xa)
        return (sqrtl(r->vs * r->vs + 2.0L * r->a * j) - r->vs) / r->a;
    if (j <= r->d - r->xd)
        return r->ta + (j - r->xa) / r->vp;
    return r->tt - (sqrtl(r->v0 * r->v0 + 2.0L * r->a * (r->d - j)) - r->v0) / r->a;
}

/* case i's random parameters, a move of d steps from 0 planned with them and its closed form; 0 when
 * the planner refuses them (the case is skipped) */
static int random_move(step_planner_t *pl, ramp_params_t *p, closed_t *cf, uint32_t i, uint32_t d)
{
    random_params(p, i);
    if (step_planner_init_trapezoid(pl, RAMP_ALGO_EXACT, p, 0) != MS_OK)
        return 0;
    assert_int_equal(step_planner_move(pl, (int32_t)d), MS_OK);
    *cf = closed_plan(p->v0_sps, p->vmax_sps, p->accel_sps2, d);
    return 1;
}

/* the closed-form speed of the move cf after x steps */
static long double closed_speed(const closed_t *cf, long double x)
{
    if (x <= cf->xa)
        return sqrtl(cf->v0 * cf->v0 + 2.0L * cf->a * x);
    if (x <= cf->d - cf->xa)
        return cf->vp;
    return sqrtl(cf->v0 * cf->v0 + 2.0L * cf->a * (cf->d - x));
}

/* inside: the cut lands inside a cruise command (a command of constant intervals, 2 steps or more),
 * as the MotionStepper library's engine cuts one (MultiStepEngine::cut_find's split): only its first
 * m steps are kept, the rewind is told m as the last command's count and the executor's time of the
 * rest (count - m intervals of its rate) as dropped */
static void stop_after_cut(int inside)
{
    uint32_t i, checked = 0, kept_profile = 0, split_ramp = 0;
    long double worst = 0.0L, worst_jump = 0.0L;
    uint64_t *edges = calloc(60001U, sizeof *edges);
    uint8_t *wide = calloc(60001U, 1U);
    assert_non_null(edges);
    assert_non_null(wide);
    for (i = 0; i < 1500U; i++) {
        ramp_params_t p;
        step_planner_t pl, b;
        step_cmd_t c, last;
        closed_t cf;
        uint32_t d = (uint32_t)lrand(3, 60000), k = 1U + (uint32_t)lrand(1, 2000), j, n = 0, more, steps = 0, ds;
        uint32_t kept_count = 0, ncmd;
        int ramp_cut = 0;
        int64_t t16 = 0;
        uint64_t abs16 = 0x8000U, cut16;
        long double f, v_cut, x_stop, t_prev = 0.0L, t_prev2 = 0.0L, law_before, law_after, act_before, act_after;
        uint64_t e_prev = 0, e_prev2 = 0;
        uint32_t s;
        int near_whole;
        prof_t sp;
        if (!random_move(&pl, &p, &cf, i, d))
            continue;
        f = p.tick_hz;
        /* the kept commands, through the executor's arithmetic (inside: up to the first cruise command
         * from the k-th on, of which m steps) */
        if (inside == 1)
            k = 1U + (uint32_t)lrand(1, 300);
        else if (inside == 2)
            k = 1U + (uint32_t)((i & 1U) ? lrand(0, 40) : lrand(1, 3000)); /* the acceleration, or anywhere */
        for (j = 0; (inside || j < k) && pl.exact.n < d - 1U && step_planner_next(&pl, &last); j++) {
            uint32_t rate = last.rate, s, use = last.count;
            int split = inside && j + 1U >= k && (last.add == 0 || inside == 2) && !(last.flags & STEP_CMD_WIDE) &&
                        last.count >= (last.add != 0 ? 3U : 2U);
            if (split)
                use = (uint32_t)lrand(1, (long)last.count - 1L);
            if (split && last.add != 0 && use < 2U)
                use = 2U; /* the engine keeps two steps of a ramp's command at least (split_at) */
            if (split && inside == 2) {
                /* a command with an add (a ramp's), split as the engine splits it: the executor's time
                 * of the steps dropped, the full command's less its first `use` */
                step_cmd_t kept_part = last;
                kept_part.count = (uint16_t)use;
                t16 = step_exact_cmd_time16(&last) - step_exact_cmd_time16(&kept_part);
                ramp_cut = last.add != 0;
            }
            for (s = 0; s < use; s++) {
                abs16 += (last.flags & STEP_CMD_WIDE) ? (uint64_t)rate << 16 : rate;
                rate += (uint32_t)last.add;
                n++;
                e_prev2 = e_prev;
                e_prev = abs16 >> 16;
            }
            kept_count = use;
            if (split) {
                steps = last.count - use; /* dropped with the commands after it */
                if (inside != 2)
                    t16 = (int64_t)steps * last.rate;
                break;
            }
        }
        if (n < 2U || n >= d || (inside && steps == 0U))
            continue;
        cut16 = abs16;
        /* B: further commands, then taken back */
        b = pl;
        more = (uint32_t)lrand(1, 40);
        for (j = 0; j < more && step_planner_next(&b, &c); j++) {
            steps += c.count;
            t16 += step_exact_cmd_time16(&c);
        }
        assert_int_equal(step_planner_rewind(&b, steps, t16, (uint16_t)kept_count), MS_OK);
        step_planner_stop(&b);
        /* the stop's step times (the executor's arithmetic, from the cut) */
        j = 0;
        ncmd = 0;
        while (step_planner_next(&b, &c)) {
            uint32_t rate = c.rate, s;
            ncmd++;
            for (s = 0; s < c.count; s++) {
                abs16 += (c.flags & STEP_CMD_WIDE) ? (uint64_t)rate << 16 : rate;
                rate += (uint32_t)c.add;
                assert_true(j < d);
                edges[j] = abs16 >> 16;
                wide[j] = (c.flags & STEP_CMD_WIDE) != 0U;
                j++;
            }
        }
        /* in commands of the span rule, not one step each where the intervals are short (below 8,000
         * ticks at the cut: a rewound state that took a cut command for one whose span did not fit went
         * on in single steps, 1,941 commands for 1,941 steps, which the AVR could not plan in time) */
        if (j >= 400U && ncmd > j / 2U && closed_speed(&cf, n) * 8000.0L > f)
            fail_msg("case %u (v0 %g vmax %g a %g F %u D %u, cut at %u): the stop's %u steps came in %u commands", i,
                     p.v0_sps, p.vmax_sps, p.accel_sps2, p.tick_hz, d, n, j, ncmd);
        /* the law at the cut: the move's speed after n steps; a stop of ceil(x_stop) steps (or, x_stop
         * a whole number to a few ulps, one more or less), or the move's own end if that comes as soon */
        t_prev = closed_time(&cf, n);
        t_prev2 = closed_time(&cf, n - 1U);
        v_cut = closed_speed(&cf, n);
        x_stop = (v_cut * v_cut - cf.v0 * cf.v0) / (2.0L * cf.a);
        ds = (uint32_t)ceill(x_stop);
        near_whole = fabsl(x_stop - roundl(x_stop)) < 1e-6L * (x_stop + 1.0L);
        if (j == d - n && (ds >= d - n || (near_whole && ds + 1U >= d - n)))
            kept_profile++;
        else if (!(j == ds || (near_whole && fabsl((long double)j - x_stop) <= 1.0L + 1e-6L * (x_stop + 1.0L))))
            fail_msg("case %u (v0 %g vmax %g a %g F %u D %u, cut at %u): the stop took %u steps, the law %.6Lf", i,
                     p.v0_sps, p.vmax_sps, p.accel_sps2, p.tick_hz, d, n, j, x_stop);
        sp = prof_plan(v_cut, cf.v0, p.vmax_sps, cf.a, j);
        for (s = 1; s <= j; s++) {
            long double want = floorl((long double)cut16 / 65536.0L + prof_time(&sp, s) * f), err;
            if (wide[s - 1U])
                continue; /* whole ticks by design */
            err = (long double)edges[s - 1U] - want;
            if (fabsl(err) > worst)
                worst = fabsl(err);
            if (fabsl(err) > 1.0L)
                fail_msg("case %u (v0 %g vmax %g a %g F %u D %u, cut at %u): stop step %u of %u at %llu, the law %.1Lf",
                         i, p.v0_sps, p.vmax_sps, p.accel_sps2, p.tick_hz, d, n, s, j,
                         (unsigned long long)edges[s - 1U], want);
        }
        act_after = (long double)edges[0] - (long double)e_prev;
        /* the speed at the cut: the interval before and after it, each as the law has it */
        act_before = (long double)e_prev - (long double)e_prev2;
        law_before = (t_prev - t_prev2) * f;
        law_after = prof_time(&sp, 1) * f;
        if (fabsl(act_before - law_before) > 2.0L || fabsl(act_after - law_after) > 2.0L ||
            fabsl(act_after - act_before) > fabsl(law_after - law_before) + 2.0L)
            fail_msg("case %u: interval before the cut %.0Lf (law %.1Lf), after %.0Lf (law %.1Lf)", i, act_before,
                     law_before, act_after, law_after);
        if (fabsl(act_after - act_before) - fabsl(law_after - law_before) > worst_jump)
            worst_jump = fabsl(act_after - act_before) - fabsl(law_after - law_before);
        checked++;
        split_ramp += ramp_cut ? 1U : 0U;
    }
    printf("# %u stops after a cut%s (%u kept the move's own deceleration; %u inside a command with an add): worst "
           "edge %.0Lf tick from the law, interval change at the cut at most %.0Lf tick more than the law's\n",
           checked, inside == 1 ? " inside a cruise command" : inside == 2 ? " inside any command" : "", kept_profile,
           split_ramp, worst, worst_jump);
    free(edges);
    free(wide);
    assert_true(checked > (inside ? 150U : 800U));
    if (inside == 2)
        assert_true(split_ramp > 300U);
}

static void stop_after_cut_follows_the_law(void **state)
{
    (void)state;
    stop_after_cut(0);
}

static void stop_after_cut_inside_a_cruise_command_follows_the_law(void **state)
{
    (void)state;
    stop_after_cut(1);
}

/* make fuzz seed 31 (MultiAxisStepper, 2026-12-06): y decelerating from 85026 towards 68788 (vmax 19123,
 * accel 10000) got its own target again; the cut landed inside a deceleration's command, and the
 * rewind, told a count of 1, took it for a command whose span did not fit: the rest of the
 * deceleration came in single steps (1,941 commands), more than the AVR could plan (107 underruns).
 * A count of 2 or more is a prefix of that command and keeps the span rule; a count of 1 still means
 * single steps (what a span that did not fit leaves), so MultiStepEngine's split_at keeps two steps of a
 * ramp's command at least. */
static void a_split_deceleration_keeps_its_spans(void **state)
{
    ramp_params_t p = {0.0f, 19123.0f, 10000.0f, 16000000U};
    step_planner_t a, b;
    step_cmd_t c, more[3];
    uint32_t use, nm = 0;
    (void)state;
    assert_int_equal(step_planner_init_exact(&a, &p, 85026), MS_OK);
    assert_int_equal(step_planner_move(&a, 68788), MS_OK);
    while (step_planner_next(&a, &c) && !(a.exact.n > a.exact.n2 + 20U && a.exact.d - a.exact.n < 1950U)) {
    }
    while (nm < 3U && step_planner_next(&a, &more[nm]))
        nm++;
    assert_true(nm == 3U && more[0].count >= 8U && more[0].add != 0);
    for (use = 1; use < more[0].count; use++) {
        step_cmd_t kept = more[0];
        uint32_t steps = more[0].count - use, i, ncmd = 0, tot = 0;
        int64_t t16;
        kept.count = (uint16_t)use;
        t16 = step_exact_cmd_time16(&more[0]) - step_exact_cmd_time16(&kept);
        for (i = 1; i < nm; i++) {
            steps += more[i].count;
            t16 += step_exact_cmd_time16(&more[i]);
        }
        b = a;
        assert_int_equal(step_planner_rewind(&b, steps, t16, (uint16_t)use), MS_OK);
        assert_int_equal(step_planner_move(&b, 68788), MS_OK); /* its target again: it keeps the deceleration */
        while (step_planner_next(&b, &c)) {
            ncmd++;
            tot += c.count;
        }
        assert_true(tot > 1500U);
        if (use == 1U)
            assert_int_equal(ncmd, tot); /* single steps: why split_at keeps two */
        else if (ncmd > tot / 4U)
            fail_msg("a cut keeping %u steps of a %u-step deceleration command: %u steps in %u commands", use,
                     more[0].count, tot, ncmd);
    }
}

/* A stop while accelerating begun with the acceleration's last commands reversed (the MotionStepper
 * library's cut lays them out at once, step_planner_stop_mirrored plans the rest), in a move from rest
 * and (every other case) after a farther target while accelerating (the profile then starts from that
 * speed): every edge of the stop on the closed-form law of the deceleration from the speed at the cut,
 * t(j) = (v - sqrt(v^2 - 2 a j)) / a (within 2 ticks: the reversed steps carry the acceleration's own
 * rounding), the stop n steps long (the exact stopping distance from step n of a move from rest; after
 * the new target one step less where the speed it started from was rounded below that of its step),
 * the position where it ends. */
static void mirrored_stop_follows_the_law(void **state)
{
    uint32_t i, checked = 0, checked_retarget = 0, max_mirrored = 0;
    long double worst = 0.0L;
    uint64_t *edges = calloc(60001U, sizeof *edges);
    step_cmd_t *hist = calloc(4096U, sizeof *hist);
    (void)state;
    assert_non_null(edges);
    assert_non_null(hist);
    for (i = 0; i < 4000U; i++) {
        ramp_params_t p;
        step_planner_t pl;
        step_cmd_t c, rev[8];
        closed_t cf;
        uint32_t d = (uint32_t)lrand(20, 60000), k = 1U + (uint32_t)lrand(1, 80), nh = 0, nh0 = 0, use, back, n = 0,
                 n0 = 0, ms = 0, nr = 0;
        uint32_t j, s, want_cmds = 1U + (i % 5U);
        uint8_t retarget = (uint8_t)(i & 1U), short_stop = 0;
        uint64_t abs16 = 0x8000U, cut16;
        int64_t t16 = 0;
        long double f, v_cut;
        if (!random_move(&pl, &p, &cf, i, d))
            continue;
        f = p.tick_hz;
        while (nh < k && nh < 4096U && step_planner_next(&pl, &hist[nh]))
            nh++;
        if (nh == 0U)
            continue;
        if (retarget) {
            /* a farther target: the move goes on from the speed after these commands, accelerating */
            for (j = 0; j < nh; j++)
                n0 += hist[j].count;
            if (!pl.exact.moving || pl.exact.n >= pl.exact.n1)
                continue; /* (no longer accelerating) */
            if (step_planner_move(&pl, (int32_t)(d + (uint32_t)lrand(1, 200000))) != MS_OK)
                continue;
            /* the speed it goes on from, rounded to the planner's unit: a hair below that of step n0 (its
             * square below u0^2 + n0 C), the stop's radicands end one step before rest's */
            short_stop = (long double)pl.exact.us * (long double)pl.exact.us <
                         (long double)pl.exact.k.u0 * (long double)pl.exact.k.u0 + (long double)n0 * (long double)pl.exact.k.cu;
            nh0 = nh;
            k = nh + 1U + (uint32_t)lrand(1, 80);
            while (nh < k && nh < 4096U && step_planner_next(&pl, &hist[nh]))
                nh++;
            if (nh == nh0)
                continue;
        }
        /* the cut inside the last command handed out: its first `use` steps kept */
        use = hist[nh - 1U].count >= 2U ? (uint32_t)lrand(1, (double)hist[nh - 1U].count + 0.999) : 1U;
        if (use > hist[nh - 1U].count)
            use = hist[nh - 1U].count;
        back = hist[nh - 1U].count - use;
        if (!step_planner_mirror_ok(&pl, back))
            continue;
        for (j = 0; j < nh; j++) {
            uint32_t rate = hist[j].rate, cnt = j + 1U == nh ? use : hist[j].count;
            for (s = 0; s < cnt; s++) {
                abs16 += (hist[j].flags & STEP_CMD_WIDE) ? (uint64_t)rate << 16 : rate;
                rate += (uint32_t)hist[j].add;
                n++;
            }
        }
        cut16 = abs16;
        /* the kept commands of the profile reversed, the last first, up to want_cmds of them and its
         * steps less 2 */
        for (j = nh; j-- > nh0 && nr < want_cmds && nr < 8U;) {
            const step_cmd_t *o = &hist[j];
            uint32_t cnt = j + 1U == nh ? use : o->count;
            if (ms + cnt + 2U > n - n0)
                break;
            rev[nr].count = (uint16_t)cnt;
            rev[nr].flags = (uint8_t)((o->flags & (STEP_CMD_REVERSE | STEP_CMD_WIDE)) | (RAMP_DECEL << STEP_CMD_PHASE_SHIFT));
            rev[nr].rate = (o->flags & STEP_CMD_WIDE) ? o->rate : o->rate + (uint32_t)o->add * (cnt - 1U);
            rev[nr].add = (o->flags & STEP_CMD_WIDE) ? 0 : -o->add;
            t16 += step_exact_cmd_time16(&rev[nr]);
            ms += cnt;
            nr++;
        }
        if (ms == 0U)
            continue;
        assert_int_equal(step_planner_stop_mirrored(&pl, back, ms, t16), MS_OK);
        /* the stop's edges: the reversed commands, then the planner's */
        j = 0;
        for (s = 0; s < nr; s++) {
            uint32_t rate = rev[s].rate, q;
            for (q = 0; q < rev[s].count; q++) {
                abs16 += (rev[s].flags & STEP_CMD_WIDE) ? (uint64_t)rate << 16 : rate;
                rate += (uint32_t)rev[s].add;
                edges[j++] = abs16 >> 16;
            }
        }
        while (step_planner_next(&pl, &c)) {
            uint32_t rate = c.rate, q;
            for (q = 0; q < c.count; q++) {
                abs16 += (c.flags & STEP_CMD_WIDE) ? (uint64_t)rate << 16 : rate;
                rate += (uint32_t)c.add;
                assert_true(j < 60000U);
                edges[j++] = abs16 >> 16;
            }
        }
        if (j != n - (short_stop ? 1U : 0U))
            fail_msg("case %u (v0 %g vmax %g a %g F %u D %u, new target after %u, cut at %u, %u mirrored): the stop "
                     "took %u steps, not %u", i, p.v0_sps, p.vmax_sps, p.accel_sps2, p.tick_hz, d, n0, n, ms, j,
                     n - (short_stop ? 1U : 0U));
        assert_int_equal(step_planner_position(&pl), (int32_t)(n + j));
        v_cut = sqrtl(cf.v0 * cf.v0 + 2.0L * cf.a * n);
        for (s = 1; s <= j; s++) {
            long double v2 = v_cut * v_cut - 2.0L * cf.a * s, err;
            long double want = floorl((long double)cut16 / 65536.0L + (v_cut - sqrtl(v2 > 0.0L ? v2 : 0.0L)) / cf.a * f);
            err = (long double)edges[s - 1U] - want;
            if (fabsl(err) > worst)
                worst = fabsl(err);
            if (fabsl(err) > 2.0L)
                fail_msg("case %u (v0 %g vmax %g a %g F %u D %u, new target after %u, cut at %u, %u mirrored): stop "
                         "step %u of %u at %llu, the law %.1Lf", i, p.v0_sps, p.vmax_sps, p.accel_sps2, p.tick_hz, d,
                         n0, n, ms, s, j, (unsigned long long)edges[s - 1U], want);
        }
        if (ms > max_mirrored)
            max_mirrored = ms;
        checked++;
        checked_retarget += retarget;
    }
    printf("# %u stops while accelerating (%u after a new target) begun with up to %u steps reversed: worst edge "
           "%.0Lf tick from the law\n", checked, checked_retarget, max_mirrored, worst);
    assert_true(checked_retarget > 300U && checked - checked_retarget > 300U);
    free(edges);
    free(hist);
}

/* the cut inside an acceleration's or a deceleration's command (a quadratic: rate and add), as the
 * MotionStepper library's engine splits one since 2026-12-06 (a stop while accelerating acted at the
 * next command's start, up to 128 steps later) */
static void stop_after_cut_inside_a_ramp_command_follows_the_law(void **state)
{
    (void)state;
    stop_after_cut(2);
}

/* ---- the commands of a deceleration, estimated (step_exact_decel_cmds) -------------------------
 * Reference: the stop itself, planned (step_exact_stop) and handed out command by command. Over random
 * parameter sets and random moments of random moves (accelerating, cruising, decelerating), the
 * estimate from the speed there must cover the commands handed out (a planner that plans a stop's
 * work ahead from it must not be short) and stay within a quarter and 8 commands above them. */
static void decel_cmds_estimate_covers_the_stop(void **state)
{
    uint32_t i, done = 0, worst_i = 0;
    double worst = 0.0;
    (void)state;
    for (i = 0; i < 6000U; i++) {
        ramp_params_t p;
        step_exact_t e;
        step_cmd_t c;
        uint32_t d = (uint32_t)lrand(2, 200000), k = (uint32_t)lrand(1, 5000), j, est, got = 0;
        float v;
        random_params(&p, i);
        if (step_exact_set_params(&e, &p) != MS_OK)
            continue;
        step_exact_reset(&e, 0);
        if (step_exact_plan(&e, (int32_t)d) != MS_OK)
            continue;
        for (j = 0; j < k && step_exact_next(&e, &c); j++) {
        }
        if (!e.moving)
            continue;
        v = step_exact_speed_sps(&e);
        est = step_exact_decel_cmds(&e, v);
        step_exact_stop(&e);
        while (step_exact_next(&e, &c) && got < 10000000U)
            got++;
        if (got < 8U)
            continue; /* a stop of a few steps: nothing to plan ahead */
        if (est < got || est > got + got / 4U + 8U)
            fail_msg("case %u: v0 %g vmax %g a %g F %u, at %g steps/s: estimate %u commands, the stop took %u", i,
                     p.v0_sps, p.vmax_sps, p.accel_sps2, p.tick_hz, v, est, got);
        if ((double)est / got > worst) {
            worst = (double)est / got;
            worst_i = i;
        }
        done++;
    }
    printf("# %u stops, the estimate at most %.3f times the commands (case %u)\n", done, worst, worst_i);
    assert_true(done > 800U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cmd_time_is_the_executors),
        cmocka_unit_test(refusals_change_nothing),
        cmocka_unit_test(exact_level_from_kept_commands),
        cmocka_unit_test(every_boundary),
        cmocka_unit_test(every_boundary_from_above_vmax),
        cmocka_unit_test(every_boundary_from_above_vmax_slow),
        cmocka_unit_test(random_cuts_bit_for_bit),
        cmocka_unit_test(stop_after_cut_follows_the_law),
        cmocka_unit_test(stop_after_cut_inside_a_cruise_command_follows_the_law),
        cmocka_unit_test(stop_after_cut_inside_a_ramp_command_follows_the_law),
        cmocka_unit_test(mirrored_stop_follows_the_law),
        cmocka_unit_test(a_split_deceleration_keeps_its_spans),
        cmocka_unit_test(longest_move),
        cmocka_unit_test(decel_cmds_estimate_covers_the_stop),
    };
    return cmocka_run_group_tests(tests, 0, 0);
}
