/* sim/cmd_ramp.c - `motionsim ramp`: the step table of a stepper move planned by lib/src/ramp.h
 * (the same code the Mega sketches run), or with --compare the deviation of the simplistic and
 * Leib ramps from the exact constant-acceleration ramp.
 *
 * Row quantities (also in --help and README.md):
 *   t_s            time of the step's pulse; the move starts at t = 0, so step 1 is at its interval
 *                  (exact ramp: t_n from the closed form; others: sum of the intervals / F)
 *   interval_ticks time since the previous step (or the start), timer ticks
 *   speed_sps      F / interval_ticks: the mean speed over that interval, which for a linear ramp is
 *                  the true speed at the interval's mid-time
 *   accel_sps2     (speed_n - speed_(n-1)) / ((dt_n + dt_(n-1))/2): the change of mean speed between
 *                  consecutive mid-times; row 1 uses the start speed v0 at t = 0 and dt_1/2. The exact
 *                  ramp gives exactly +a, 0, -a in its phases.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "csv.h"
#include "csv_float.h"
#include "ramp.h"
#include "step_planner.h"
#include "step_queue.h"

#define RAMP_CMD "ramp"
/* --max-rows's default: the lab's table has 50 rows, the largest scenario (tools/scenarios) 10000;
 * a million rows of about 60 bytes is 60 MB written in about a second. */
#define RAMP_MAX_ROWS_DEFAULT 1000000UL

/* Per-row kinematics shared by the table and --compare (definitions in the file comment). */
typedef struct {
    double tick_hz;
    double v_start;   /* speed at t = 0 */
    double prev_dt_s; /* 0 before the first row */
    double prev_speed;
    double t_sum_ticks; /* running sum of real intervals */
    uint64_t t_sum_whole;
} kin_t;

typedef struct {
    double t_s, dt_s, speed_sps, accel_sps2;
} kin_row_t;

static void kin_init(kin_t *k, double tick_hz, double v_start)
{
    memset(k, 0, sizeof *k);
    k->tick_hz = tick_hz;
    k->v_start = v_start;
}

static kin_row_t kin_row(kin_t *k, double interval_ticks, uint32_t whole_ticks, int whole, double exact_t_s)
{
    kin_row_t row;
    double ticks = whole ? (double)whole_ticks : interval_ticks;
    row.dt_s = ticks / k->tick_hz;
    if (whole) {
        k->t_sum_whole += whole_ticks;
        row.t_s = (double)k->t_sum_whole / k->tick_hz;
    } else {
        k->t_sum_ticks += interval_ticks;
        row.t_s = exact_t_s >= 0.0 ? exact_t_s : k->t_sum_ticks / k->tick_hz;
    }
    row.speed_sps = ticks > 0.0 ? k->tick_hz / ticks : 0.0;
    if (k->prev_dt_s == 0.0)
        row.accel_sps2 = row.dt_s > 0.0 ? (row.speed_sps - k->v_start) / (row.dt_s / 2.0) : 0.0;
    else
        row.accel_sps2 = (row.speed_sps - k->prev_speed) / ((row.dt_s + k->prev_dt_s) / 2.0);
    k->prev_dt_s = row.dt_s;
    k->prev_speed = row.speed_sps;
    return row;
}

/* Accounts for n more rows equal to the last one (a cruise): only the running time moves on. */
static void kin_skip(kin_t *k, uint32_t n, double interval_ticks, uint32_t whole_ticks, int whole)
{
    if (whole)
        k->t_sum_whole += (uint64_t)n * whole_ticks;
    else
        k->t_sum_ticks += (double)n * interval_ticks;
}

/* Time of step n after kin_skip: the running sum, or the exact ramp's closed form. */
static double kin_time_s(const kin_t *k, int whole, const ramp_exact_t *exact, uint32_t n)
{
    if (exact != NULL)
        return ramp_exact_time_s(exact, n);
    return whole ? (double)k->t_sum_whole / k->tick_hz : k->t_sum_ticks / k->tick_hz;
}

/* ---- --compare ---- */
typedef struct {
    const char *name;
    uint32_t steps;
    double move_time_s, exact_time_s;
    double t_max_dev_s;
    double i_max_dev_ticks, i_max_dev_pct, i_sum_sq_ticks, i_sum_sq_pct;
    uint32_t i_max_step;
    double a_max_dev, a_sum_sq;
    uint32_t a_max_step;
} cmp_t;

/* Deviation of the planned ramp r from the planned exact ramp ex, step by step. Cruise steps are
 * accounted for in one go: once both ramps are in a cruise whose next step repeats the step just
 * taken (same interval in each), the rows in between would all equal that row (same intervals and
 * deviations, acceleration 0 in both), and the step-time deviation changes linearly there, so its
 * extremes are at the two ends, which are stepped normally. The sums get n times the row's
 * squares: the result equals stepping through (test_ramp.py checks it), at a cost that no longer
 * grows with the cruise (a 2^32-step move takes milliseconds). */
static int compare_one(cmp_t *c, ramp_t *r, ramp_t *ex, const ramp_params_t *p, int whole, uint64_t *budget)
{
    ramp_step_t s, e;
    kin_t kr, ke;
    memset(c, 0, sizeof *c);
    c->name = ramp_algo_name(r->algo);
    c->steps = r->steps_total;
    kin_init(&kr, (double)p->tick_hz, p->v0_sps);
    kin_init(&ke, (double)p->tick_hz, p->v0_sps);
    while (ramp_next(r, &s) && ramp_next(ex, &e)) {
        double own_t = (r->algo == RAMP_ALGO_EXACT && !whole) ? ramp_exact_time_s(&r->u.exact, s.step) : -1.0;
        kin_row_t a = kin_row(&kr, s.interval_ticks, s.whole_ticks, whole, own_t);
        kin_row_t b = kin_row(&ke, e.interval_ticks, e.whole_ticks, 0, ramp_exact_time_s(&ex->u.exact, e.step));
        double di = (a.dt_s - b.dt_s) * (double)p->tick_hz;
        double dpct = 100.0 * (a.dt_s - b.dt_s) / b.dt_s;
        double da = a.accel_sps2 - b.accel_sps2;
        double dt = fabs(a.t_s - b.t_s);
        uint32_t skip;
        if (*budget == 0)
            return 0; /* more steps outside a cruise than --max-rows */
        (*budget)--;
        if (dt > c->t_max_dev_s)
            c->t_max_dev_s = dt;
        if (fabs(dpct) > fabs(c->i_max_dev_pct) || s.step == 1) {
            c->i_max_dev_pct = dpct;
            c->i_max_dev_ticks = di;
            c->i_max_step = s.step;
        }
        c->i_sum_sq_ticks += di * di;
        c->i_sum_sq_pct += dpct * dpct;
        if (fabs(da) > fabs(c->a_max_dev) || s.step == 1) {
            c->a_max_dev = da;
            c->a_max_step = s.step;
        }
        c->a_sum_sq += da * da;
        c->move_time_s = a.t_s;
        c->exact_time_s = b.t_s;
        skip = ramp_cruise_skippable(r);
        if (skip > 0) {
            uint32_t skip_ex = ramp_cruise_skippable(ex);
            if (skip_ex < skip)
                skip = skip_ex;
        }
        if (skip > 0) {
            /* the skipped steps repeat the next step of each ramp: skip only if that is this one */
            ramp_t rn = *r, en = *ex;
            ramp_step_t s2, e2;
            if (ramp_next(&rn, &s2) && ramp_next(&en, &e2) && s2.interval_ticks == s.interval_ticks &&
                s2.whole_ticks == s.whole_ticks && e2.interval_ticks == e.interval_ticks) {
                (void)ramp_skip_cruise_at_most(r, skip);
                (void)ramp_skip_cruise_at_most(ex, skip);
                kin_skip(&kr, skip, s.interval_ticks, s.whole_ticks, whole);
                kin_skip(&ke, skip, e.interval_ticks, e.whole_ticks, 0);
                /* the step-time deviation at the last skipped step (the other end was this one) */
                dt = fabs(kin_time_s(&kr, whole, r->algo == RAMP_ALGO_EXACT && !whole ? &r->u.exact : NULL,
                                     r->steps_done) -
                          ramp_exact_time_s(&ex->u.exact, ex->steps_done));
                if (dt > c->t_max_dev_s)
                    c->t_max_dev_s = dt;
                /* each skipped row: the same di and dpct, and speed unchanged in both ramps */
                c->i_sum_sq_ticks += (double)skip * di * di;
                c->i_sum_sq_pct += (double)skip * dpct * dpct;
            }
        }
    }
    return 1;
}

static void compare_row(FILE *f, const cmp_t *c, double accel)
{
    double n = c->steps > 0 ? (double)c->steps : 1.0;
    double v[12];
    fprintf(f, "%s,", c->name);
    v[0] = c->steps;
    v[1] = c->move_time_s;
    v[2] = c->exact_time_s > 0.0 ? 100.0 * (c->move_time_s - c->exact_time_s) / c->exact_time_s : 0.0;
    v[3] = c->t_max_dev_s;
    v[4] = c->i_max_dev_ticks;
    v[5] = c->i_max_dev_pct;
    v[6] = c->i_max_step;
    v[7] = sqrt(c->i_sum_sq_pct / n);
    v[8] = c->a_max_dev;
    v[9] = 100.0 * fabs(c->a_max_dev) / accel;
    v[10] = c->a_max_step;
    v[11] = sqrt(c->a_sum_sq / n);
    csv_row(f, v, 12);
}

typedef struct {
    ramp_algo_t algo;
    ramp_t plan;
    const char *left_out; /* why this algorithm has no row, or NULL */
    char why[200];        /* room for left_out's text */
} cmp_plan_t;

/* Every algorithm's row, computed before anything is written; 0 when an algorithm's comparison would
 * step through more than max_steps steps one at a time (outside the cruises, which are summed in
 * one go): a move whose table fits max_steps rows always compares. */
static int compute_compare(cmp_t *out, cmp_plan_t *plans, size_t n, const ramp_t *exact, const ramp_params_t *p,
                           int whole, uint64_t max_steps)
{
    size_t i;
    for (i = 0; i < n; i++) {
        ramp_t ex = *exact;
        uint64_t budget = max_steps;
        if (plans[i].left_out != NULL)
            continue;
        if (!compare_one(&out[i], &plans[i].plan, &ex, p, whole, &budget))
            return 0;
    }
    return 1;
}

static void run_compare(FILE *f, const cmp_t *rows, const cmp_plan_t *plans, size_t n, const ramp_params_t *p)
{
    size_t i;
    fputs("algo,steps,move_time_s,move_time_dev_pct,step_time_max_dev_s,interval_max_dev_ticks,"
          "interval_max_dev_pct,interval_max_dev_step,interval_rms_dev_pct,accel_max_dev_sps2,"
          "accel_max_dev_pct,accel_max_dev_step,accel_rms_dev_sps2\n",
          f);
    for (i = 0; i < n && !ferror(f); i++)
        if (plans[i].left_out == NULL)
            compare_row(f, &rows[i], p->accel_sps2);
}

/* ---- the step table ---- */
static void table_header(FILE *f)
{
    fputs("step,position,t_s,interval_ticks,speed_sps,accel_sps2\n", f);
}

static void table_rows(FILE *f, ramp_t *r, double tick_hz, double v_start, int whole)
{
    ramp_step_t s;
    kin_t k;
    kin_init(&k, tick_hz, v_start);
    while (!ferror(f) && ramp_next(r, &s)) { /* stop at the first write error (a full disk) */
        double exact_t = (r->algo == RAMP_ALGO_EXACT && !whole) ? ramp_exact_time_s(&r->u.exact, s.step) : -1.0;
        kin_row_t row = kin_row(&k, s.interval_ticks, s.whole_ticks, whole, exact_t);
        fprintf(f, "%lu,%ld,", (unsigned long)s.step, (long)s.position);
        csv_num(f, row.t_s);
        fputc(',', f);
        if (whole)
            fprintf(f, "%lu", (unsigned long)s.whole_ticks);
        else if (r->algo == RAMP_ALGO_SIMPLISTIC || r->algo == RAMP_ALGO_LEIB)
            csv_num_f32(f, (float)s.interval_ticks); /* the float the Mega computes */
        else
            csv_num(f, s.interval_ticks);
        fputc(',', f);
        csv_num(f, row.speed_sps);
        fputc(',', f);
        csv_num(f, row.accel_sps2);
        fputc('\n', f);
    }
}

/* Why a double does not survive conversion to float, or NULL. */
static const char *float_problem(double x)
{
    switch (cli_float_range(x)) {
    case CLI_NUM_OVERFLOW: return "is out of range for a float (magnitude above 3.4e38)";
    case CLI_NUM_UNDERFLOW: return "underflows a float (nonzero magnitude below 1.2e-38)";
    default: return NULL;
    }
}

/* Why parameters computed in float by `who` do not fit one (a sentence naming the option), or NULL. */
static const char *float_params_problem_of(const char *who, const ramp_params_t *p, char *msg, size_t n)
{
    const char *names[3] = {"--v0", "--vmax", "--accel"};
    double values[3];
    int i;
    values[0] = p->v0_sps;
    values[1] = p->vmax_sps;
    values[2] = p->accel_sps2;
    for (i = 0; i < 3; i++) {
        const char *why = float_problem(values[i]);
        if (why != NULL) {
            snprintf(msg, n, "%s: %g %s; %s computes in float, as on the Mega", names[i], values[i], why, who);
            return msg;
        }
    }
    return NULL;
}

/* Simplistic and Leib compute in float: why their parameters do not fit one, or NULL. The exact
 * ramp computes in double: always NULL. */
static const char *float_params_problem(ramp_algo_t algo, const ramp_params_t *p, char *msg, size_t n)
{
    if (algo != RAMP_ALGO_SIMPLISTIC && algo != RAMP_ALGO_LEIB)
        return NULL;
    return float_params_problem_of(ramp_algo_name(algo), p, msg, n);
}

/* The one line refusing a table of `rows` rows (exit 2). */
static int too_many_rows(uint64_t rows, uint32_t max_rows)
{
    return cli_error(RAMP_CMD, "the table would have %llu rows, more than --max-rows %lu: shorten the move "
                               "(--from/--to), or raise --max-rows (each row is one step, about 60 bytes)",
                     (unsigned long long)rows, (unsigned long)max_rows);
}

/* ---- --queue: the move through the step engine (step_planner.h -> step_queue.h's executor) ---- */

/* A stop or a new target, applied after the command that contains step `at` has been handed out. */
typedef struct {
    uint32_t at;
    int stop;       /* 1: step_planner_stop; 0: step_planner_move(target) */
    int32_t target;
} queue_event_t;

#define QUEUE_MAX_EVENTS 64

typedef struct {
    uint64_t steps;      /* steps made (every command's count) */
    uint64_t commands;
    size_t events_done;  /* events applied, in order */
    motion_status_t st;  /* MS_OK, or what a new target returned (events[events_done - 1]) */
    int internal_error;  /* the executor's 16-bit edge disagreed with the absolute timeline */
    int over_limit;      /* stopped: more than max_steps steps */
} queue_result_t;

static void queue_cmd_row(FILE *f, uint64_t index, uint64_t first_step, const step_cmd_t *c)
{
    int wide = (c->flags & STEP_CMD_WIDE) != 0, rev = (c->flags & STEP_CMD_REVERSE) != 0;
    /* 6 decimals recover the 16.16 value exactly: round(ticks * 65536), the error is below 0.04 */
    double rate = wide ? (double)c->rate : (double)c->rate / 65536.0;
    fprintf(f, "%llu,%llu,%u,%.6f,%.6f,%s\n", (unsigned long long)index, (unsigned long long)first_step,
            (unsigned)c->count, rate, (double)c->add / 65536.0,
            wide && rev ? "wide reverse" : wide ? "wide" : rev ? "reverse" : "");
}

/* Hands every command out of the planner, applying the events, and (with `table`) executes each
 * step by step_exec_load/step_exec_next as the step interrupt does: one table row per step, its
 * time the whole tick of its edge. table and cmds may be NULL (the dry run that checks every event
 * falls inside the move before anything is written). Stops at the first write error, and with
 * over_limit set as soon as more than max_steps steps have been handed out (the dry run's bound: a
 * move of 2^32 steps is not counted out to the end). */
static queue_result_t queue_run(step_planner_t *pl, int32_t from, const queue_event_t *ev, size_t n_ev, FILE *table,
                                FILE *cmds, double tick_hz, double v_start, uint64_t max_steps)
{
    queue_result_t res;
    step_exec_t x;
    step_cmd_t c;
    kin_t k;
    uint64_t abs16 = 0x8000U, prev_edge = 0;
    int64_t pos = from;
    memset(&res, 0, sizeof res);
    res.st = MS_OK;
    step_exec_init(&x, 0x8000U);
    kin_init(&k, tick_hz, v_start);
    while (step_planner_next(pl, &c)) {
        if ((table != NULL && ferror(table)) || (cmds != NULL && ferror(cmds)))
            break;
        res.commands++;
        if (cmds != NULL)
            queue_cmd_row(cmds, res.commands, res.steps + 1U, &c);
        if (table == NULL) {
            res.steps += c.count;
        } else {
            step_exec_load(&x, &c);
            while (x.left > 0U && !ferror(table)) {
                uint32_t before = x.acc, wide_ticks = step_exec_wide_ticks(&x);
                int wide = (x.flags & STEP_CMD_WIDE) != 0;
                uint16_t edge16 = step_exec_next(&x);
                uint64_t edge;
                uint32_t interval;
                kin_row_t row;
                /* the absolute time: the executor's own advance of acc; a WIDE step's whole interval is
                 * counted out as the interrupt counts the timer's wraps */
                abs16 += wide ? (uint64_t)wide_ticks << 16 : (uint64_t)(uint32_t)(x.acc - before);
                edge = abs16 >> 16;
                if (edge16 != (uint16_t)edge || (uint32_t)abs16 != x.acc) {
                    res.internal_error = 1;
                    return res;
                }
                pos += (x.flags & STEP_CMD_REVERSE) ? -1 : 1;
                res.steps++;
                interval = (uint32_t)(edge - prev_edge); /* at most 2^32 - 1: one WIDE interval */
                prev_edge = edge;
                row = kin_row(&k, 0.0, interval, 1, -1.0);
                fprintf(table, "%llu,%lld,", (unsigned long long)res.steps, (long long)pos);
                csv_num(table, row.t_s);
                fprintf(table, ",%lu,", (unsigned long)interval);
                csv_num(table, row.speed_sps);
                fputc(',', table);
                csv_num(table, row.accel_sps2);
                fputc('\n', table);
            }
        }
        if (res.steps > max_steps) {
            res.over_limit = 1;
            return res;
        }
        while (res.events_done < n_ev && res.steps >= ev[res.events_done].at) {
            const queue_event_t *e = &ev[res.events_done++];
            if (e->stop) {
                step_planner_stop(pl);
            } else {
                res.st = step_planner_move(pl, e->target);
                if (res.st != MS_OK)
                    return res;
            }
        }
    }
    return res;
}

/* --retarget-at N:TARGET[,N:TARGET...] into ev[*n..]: -1, or the exit code after one line. */
static int parse_retargets(const char *arg, queue_event_t *ev, size_t *n)
{
    const char *p = arg;
    for (;;) {
        char piece[64], *colon;
        const char *comma = strchr(p, ',');
        size_t len = comma != NULL ? (size_t)(comma - p) : strlen(p);
        queue_event_t e;
        if (len == 0 || len >= sizeof piece || (colon = memchr(p, ':', len)) == NULL)
            return cli_error(RAMP_CMD, "--retarget-at: '%.*s' is not N:TARGET (step number, colon, target position; "
                                       "e.g. 6000:1000, several separated by commas)",
                             (int)(len < 40 ? len : 40), p);
        memcpy(piece, p, len);
        piece[len] = '\0';
        colon = piece + (colon - p);
        *colon = '\0';
        if (cli_parse_uint32(piece, &e.at) != 0 || e.at == 0)
            return cli_error(RAMP_CMD, "--retarget-at: the step number '%s' in '%s:%s' is not a whole number in "
                                       "1..4294967295", piece, piece, colon + 1);
        if (cli_parse_int32(colon + 1, &e.target) != 0)
            return cli_error(RAMP_CMD, "--retarget-at: the target '%s' in '%s:%s' is not a whole number in "
                                       "-2147483648..2147483647", colon + 1, piece, colon + 1);
        e.stop = 0;
        if (*n > 0 && e.at <= ev[*n - 1].at)
            return cli_error(RAMP_CMD, "--retarget-at: the step numbers must increase: %lu:%ld comes after %lu:%ld",
                             (unsigned long)e.at, (long)e.target, (unsigned long)ev[*n - 1].at,
                             (long)ev[*n - 1].target);
        if (*n >= QUEUE_MAX_EVENTS)
            return cli_error(RAMP_CMD, "--retarget-at: more than %d N:TARGET pairs", QUEUE_MAX_EVENTS);
        ev[(*n)++] = e;
        if (comma == NULL)
            return -1;
        p = comma + 1;
    }
}

/* --stop-at joins the new targets in step order (a stop and a new target on one step: refused). */
static int add_stop(queue_event_t *ev, size_t *n, uint32_t at)
{
    size_t i = 0, j;
    if (at == 0)
        return cli_error(RAMP_CMD, "--stop-at: 0 is not a step number (the steps of a move count from 1)");
    while (i < *n && ev[i].at < at)
        i++;
    if (i < *n && ev[i].at == at)
        return cli_error(RAMP_CMD, "--stop-at %lu and --retarget-at %lu:%ld fall on the same step: give them "
                                   "different steps", (unsigned long)at, (unsigned long)ev[i].at, (long)ev[i].target);
    if (*n >= QUEUE_MAX_EVENTS + 1)
        return cli_error(RAMP_CMD, "--stop-at: too many events");
    for (j = *n; j > i; j--)
        ev[j] = ev[j - 1];
    ev[i].at = at;
    ev[i].stop = 1;
    ev[i].target = 0;
    (*n)++;
    return -1;
}

typedef struct {
    const char *out_path;  /* the step table: -o (NULL: stdout) */
    const char *cmds_path; /* --commands, or NULL */
    queue_event_t ev[QUEUE_MAX_EVENTS + 1];
    size_t n_ev;
    uint32_t max_rows;     /* --max-rows */
} queue_opts_t;

/* The planner at `from` for the algorithm (sigmoid: over `table`): MS_OK or its status. */
static motion_status_t queue_planner(step_planner_t *pl, int algo, const ramp_params_t *params,
                                     const ramp_sigmoid_params_t *sp, const uint16_t *table, int32_t from, int32_t to)
{
    motion_status_t st;
    if (algo == RAMP_ALGO_SIGMOID)
        st = step_planner_init_sigmoid(pl, sp, table, sp->len, from);
    else
        st = step_planner_init_trapezoid(pl, (ramp_algo_t)algo, params, from);
    if (st != MS_OK)
        return st;
    return step_planner_move(pl, to);
}

static int queue_main(const queue_opts_t *q, int algo, const ramp_params_t *params, const ramp_sigmoid_params_t *sp,
                      const uint16_t *table, int32_t from, int32_t to, double tick_hz, double v_start)
{
    step_planner_t pl;
    queue_result_t res;
    motion_status_t st = queue_planner(&pl, algo, params, sp, table, from, to);
    FILE *tf, *cf = NULL;
    int rc, rc2;
    if (st != MS_OK) {
        if (algo == RAMP_ALGO_EXACT && ramp_params_check(params) == MS_OK) {
            /* the ramp's own checks passed: one of step_exact.h's limits; say which */
            double reach_s = params->vmax_sps / params->accel_sps2, limit_s = 17179869184.0 / params->tick_hz;
            if (params->tick_hz > (1UL << 25))
                return cli_error(RAMP_CMD, "%s: --tick-hz %lu is above 33554432 (2^25), the limit of --queue "
                                           "--algo exact (step_exact.h)",
                                 motion_status_text(st), (unsigned long)params->tick_hz);
            if (st == MS_ERR_ACCEL_PHASE_TOO_LONG)
                return cli_error(RAMP_CMD, "%s (vmax/accel = %g s, above %g s at %lu Hz)", motion_status_text(st), reach_s,
                                 limit_s, (unsigned long)params->tick_hz);
        }
        return cli_error(RAMP_CMD, "%s", motion_status_text(st));
    }
    if (q->n_ev == 0) {
        /* the move's rows are known: one per step from `from` to `to` */
        uint64_t rows = (uint64_t)((int64_t)to > (int64_t)from ? (int64_t)to - from : (int64_t)from - to);
        if (rows > q->max_rows)
            return too_many_rows(rows, q->max_rows);
    } else {
        /* a dry run (commands only, nothing written): every event inside the move, every new target
         * accepted, the rows within --max-rows, before any output exists */
        step_planner_t dry = pl;
        res = queue_run(&dry, from, q->ev, q->n_ev, NULL, NULL, tick_hz, v_start, q->max_rows);
        if (res.over_limit)
            return cli_error(RAMP_CMD, "the table would have more than --max-rows %lu rows: the move with its "
                                       "--retarget-at/--stop-at makes at least %llu steps; stop or retarget it "
                                       "earlier, or raise --max-rows",
                             (unsigned long)q->max_rows, (unsigned long long)res.steps);
        if (res.st != MS_OK) {
            const queue_event_t *e = &q->ev[res.events_done - 1];
            return cli_error(RAMP_CMD, "--retarget-at %lu:%ld: %s", (unsigned long)e->at, (long)e->target,
                             motion_status_text(res.st));
        }
        if (res.events_done < q->n_ev) {
            const queue_event_t *e = &q->ev[res.events_done];
            if (e->stop)
                return cli_error(RAMP_CMD, "--stop-at %lu: the move has only %llu steps", (unsigned long)e->at,
                                 (unsigned long long)res.steps);
            return cli_error(RAMP_CMD, "--retarget-at %lu:%ld: the move has only %llu steps by then",
                             (unsigned long)e->at, (long)e->target, (unsigned long long)res.steps);
        }
    }
    tf = cli_open_output(RAMP_CMD, q->out_path);
    if (tf == NULL)
        return CLI_EXIT_RUNTIME;
    if (q->cmds_path != NULL) {
        cf = cli_open_output(RAMP_CMD, q->cmds_path);
        if (cf == NULL) {
            (void)cli_close_output(RAMP_CMD, tf, q->out_path);
            return CLI_EXIT_RUNTIME;
        }
        fputs("cmd,first_step,count,rate_ticks,add_ticks,flags\n", cf);
    }
    table_header(tf);
    res = queue_run(&pl, from, q->ev, q->n_ev, tf, cf, tick_hz, v_start, q->max_rows);
    if (res.internal_error)
        fprintf(stderr, "motionsim ramp: internal error: the executor's edge disagrees with its timeline at step "
                        "%llu\n", (unsigned long long)res.steps + 1U);
    rc = cli_close_output(RAMP_CMD, tf, q->out_path);
    rc2 = cf != NULL ? cli_close_output(RAMP_CMD, cf, q->cmds_path) : CLI_EXIT_OK;
    if (res.internal_error)
        return CLI_EXIT_RUNTIME;
    return rc != CLI_EXIT_OK ? rc : rc2;
}

static const char ramp_description[] =
    "Plans a stepper move with the same lib/ code as the Mega sketches and writes one CSV row per\n"
    "step (virtual time, nothing sleeps): step,position,t_s,interval_ticks,speed_sps,accel_sps2.\n"
    "  t_s            time of the step's pulse; the move starts at t = 0, step 1 comes one interval\n"
    "                 later (exact ramp: t_n = (sqrt(v0^2 + 2 a n) - v0)/a in its acceleration)\n"
    "  interval_ticks time since the previous step (or the start), in timer ticks (F per second);\n"
    "                 the algorithm's own value (float for simplistic/leib, as on the Mega), or with\n"
    "                 --integer-ticks the whole ticks the firmware's timer counts (nearest tick)\n"
    "  speed_sps      F / interval_ticks: mean speed over the interval (= the speed at its mid-time\n"
    "                 for a linear ramp)\n"
    "  accel_sps2     change of speed_sps between consecutive mid-times; row 1 from v0 at t = 0\n"
    "                 (the exact ramp gives +a, 0, -a)\n"
    "Algorithms: simplistic (lab eqs. 1-2), leib (lab §4.3.3 steps 1-6), exact (true constant\n"
    "acceleration), sigmoid (the S-curve article S-curve table; options --len --fmin --fmax --flex --timer-hz\n"
    "--hold instead of --v0 --vmax --accel --tick-hz); smooth (the filter-shaped, jerk-limited move:\n"
    "--algo smooth --jerk SPS3; its own table, --queue and --compare: motionsim ramp --algo smooth --help).\n"
    "--compare (no --algo) prints, for exact, simplistic and leib, how far each deviates from the\n"
    "exact ramp: move time, largest step-time error, largest and RMS interval error, largest and\n"
    "RMS acceleration error (with the step where the largest occurs); cruise steps are summed in\n"
    "one go, so any move takes milliseconds. An algorithm that refuses the parameters is left out\n"
    "with its reason on stderr; if the exact ramp refuses them, nothing is printed (exit 2).\n"
    "The firmware's intervals: LeibRampStepper = --algo leib --tick-hz 2000000 --integer-ticks.\n"
    "--queue plans the move with the step engine (lib/src/step_planner.h, as the sketches' step\n"
    "interrupt is fed: exact by step_exact.h, the others' whole ticks packed into commands) and\n"
    "rebuilds the table by running every command through the interrupt's executor (step_exec_load,\n"
    "step_exec_next; acc starts at half a tick): the same columns, t_s = whole tick of the edge / F,\n"
    "interval_ticks in whole ticks, position signed (reversals show). --commands FILE also writes\n"
    "the commands, one row each: cmd,first_step,count,rate_ticks,add_ticks,flags (rate and add in\n"
    "ticks with 6 decimals: the 16.16 value is round(x * 65536); WIDE: rate in whole ticks; flags\n"
    "'wide', 'reverse', 'wide reverse' or empty). --commands - puts them on stdout (then give the\n"
    "table -o FILE). --stop-at N calls step_planner_stop, --retarget-at N:TARGET step_planner_move\n"
    "(TARGET), right after the command that contains step N is handed out; N counts every step\n"
    "made so far, and must be reached (exit 2 otherwise).\n"
    "--max-rows N (default 1000000) bounds the table: a move of more steps is refused before\n"
    "anything is written (exit 2; with --retarget-at/--stop-at the dry run stops counting there);\n"
    "--compare takes at most N steps one by one per algorithm (cruise steps do not count).";

/* Refuses a value that does not survive conversion to float (what the module computes in, as on
 * the Mega): one line naming the option. Returns -1 when it fits. */
static int check_float_option(const char *name, double x, const char *who)
{
    const char *why = float_problem(x);
    if (why == NULL)
        return -1;
    return cli_error(RAMP_CMD, "%s: %g %s; %s computes in float, as on the Mega", name, x, why, who);
}

int cmd_ramp(int argc, char **argv)
{
    int algo = RAMP_ALGO_LEIB, compare = 0, whole = 0, algo_given = 0, queue = 0, stop_seen = 0;
    uint32_t stop_at = 0, max_rows = RAMP_MAX_ROWS_DEFAULT;
    const char *retarget_arg = NULL;
    static queue_opts_t q;
    int32_t from = 0, to = 50;
    double v0 = 1.0, vmax = 20.0, accel = 10.0;
    uint32_t tick_hz = 1000;
    uint32_t len = 1000, hold = 4, timer_hz = 10000000;
    double fmin = 500.0, fmax = 64000.0, flex = 8.0;
    const char *out_path = NULL;
    int seen_trap[4] = {0, 0, 0, 0};
    int seen_sig[6] = {0, 0, 0, 0, 0, 0};
    static const char *trap_names[4] = {"--v0", "--vmax", "--accel", "--tick-hz"};
    static const char *sig_names[6] = {"--len", "--fmin", "--fmax", "--flex", "--timer-hz", "--hold"};
    const cli_opt_t opts[] = {
        {"--algo", CLI_CHOICE, &algo, NULL, "ramp algorithm (default leib)", "simplistic|leib|exact|sigmoid",
         &algo_given},
        {"--from", CLI_INT32, &from, "STEPS", "start position (default 0)", NULL, NULL},
        {"--to", CLI_INT32, &to, "STEPS", "target position (default 50); any int32", NULL, NULL},
        {"--v0", CLI_DOUBLE, &v0, "SPS", "minimum (start/stop) speed, steps/s (default 1)", NULL, &seen_trap[0]},
        {"--vmax", CLI_DOUBLE, &vmax, "SPS", "maximum permissible speed, steps/s (default 20)", NULL, &seen_trap[1]},
        {"--accel", CLI_DOUBLE, &accel, "SPS2", "acceleration, steps/s^2 (default 10)", NULL, &seen_trap[2]},
        {"--tick-hz", CLI_UINT32, &tick_hz, "HZ", "F, timer ticks per second (default 1000: the lab's ms)", NULL,
         &seen_trap[3]},
        {"--len", CLI_UINT32, &len, "N", "sigmoid: table entries, 2..65535 (default 1000)", NULL, &seen_sig[0]},
        {"--fmin", CLI_DOUBLE, &fmin, "HZ", "sigmoid: start/stop step rate (default 500)", NULL, &seen_sig[1]},
        {"--fmax", CLI_DOUBLE, &fmax, "HZ", "sigmoid: top step rate (default 64000)", NULL, &seen_sig[2]},
        {"--flex", CLI_DOUBLE, &flex, "X", "sigmoid: flexibility, > 0 (default 8)", NULL, &seen_sig[3]},
        {"--timer-hz", CLI_UINT32, &timer_hz, "HZ", "sigmoid: timer ticks per second (default 10000000)", NULL,
         &seen_sig[4]},
        {"--hold", CLI_UINT32, &hold, "N", "sigmoid: steps per table entry, 1..65535 (default 4)", NULL, &seen_sig[5]},
        {"--integer-ticks", CLI_FLAG, &whole, NULL, "intervals in whole ticks, as the firmware's timer counts them",
         NULL, NULL},
        {"--compare", CLI_FLAG, &compare, NULL,
         "per algorithm, its deviation from the exact ramp (a table; not with --algo)", NULL, NULL},
        {"-o", CLI_STRING, &out_path, "FILE", "write the CSV to FILE instead of stdout", NULL, NULL},
        {"--queue", CLI_FLAG, &queue, NULL,
         "plan with the step engine (step_planner) and rebuild the table from its commands", NULL, NULL},
        {"--commands", CLI_STRING, &q.cmds_path, "FILE", "--queue: also write the step commands to FILE ('-': stdout)",
         NULL, NULL},
        {"--stop-at", CLI_UINT32, &stop_at, "N", "--queue: stop after the command containing step N is handed out",
         NULL, &stop_seen},
        {"--retarget-at", CLI_STRING, &retarget_arg, "N:TARGET[,N:TARGET...]",
         "--queue: new target TARGET after the command containing step N", NULL, NULL},
        {"--max-rows", CLI_UINT32, &max_rows, "N",
         "refuse a table of more than N rows, 1..4294967295 (default 1000000; --compare: steps compared one by one)",
         NULL, NULL},
    };
    const cli_spec_t spec = {RAMP_CMD,
                             "[--algo A | --compare] [--from N --to N] [options] [-o FILE]\n"
                             "       motionsim ramp --queue [--algo A] [--from N --to N] [options] [-o FILE] "
                             "[--commands FILE] [--stop-at N] [--retarget-at N:TARGET,...]",
                             ramp_description, opts, sizeof opts / sizeof opts[0], 0};
    ramp_t r, exact;
    cmp_plan_t plans[3];
    cmp_t cmp_rows[3];
    size_t n_plans = 0;
    ramp_params_t params;
    ramp_sigmoid_params_t sp;
    uint16_t *table = NULL;
    double v_start, rate;
    motion_status_t st;
    FILE *f;
    int rc, i;

    if (cmd_ramp_wants_smooth(argc, argv)) /* --algo smooth: sim/cmd_smooth.c */
        return cmd_ramp_smooth(argc, argv);
    rc = cli_parse(&spec, argc, argv, NULL, NULL);
    if (rc >= 0)
        return rc;
    if (compare && algo_given)
        return cli_error(RAMP_CMD, "--algo and --compare cannot be combined: --compare runs every algorithm");
    if (compare && queue)
        return cli_error(RAMP_CMD, "--queue and --compare cannot be combined: --queue runs one algorithm through "
                                   "the step engine");
    if (max_rows == 0)
        return cli_error(RAMP_CMD, "--max-rows: 0 is not a bound: a table has at least 1 row (give 1..4294967295)");
    if (!queue && (stop_seen || retarget_arg != NULL || q.cmds_path != NULL))
        return cli_error(RAMP_CMD, "%s needs --queue (it works on the step engine's commands)",
                         stop_seen ? "--stop-at" : retarget_arg != NULL ? "--retarget-at" : "--commands");
    if (queue) {
        q.out_path = out_path;
        q.n_ev = 0;
        q.max_rows = max_rows;
        if (retarget_arg != NULL && (rc = parse_retargets(retarget_arg, q.ev, &q.n_ev)) >= 0)
            return rc;
        if (stop_seen && (rc = add_stop(q.ev, &q.n_ev, stop_at)) >= 0)
            return rc;
        if (q.cmds_path != NULL && strcmp(q.cmds_path, "-") == 0 && (out_path == NULL || strcmp(out_path, "-") == 0))
            return cli_error(RAMP_CMD, "--commands -: the step table goes to stdout already: give it -o FILE");
        if (q.cmds_path != NULL && out_path != NULL && strcmp(q.cmds_path, out_path) == 0)
            return cli_error(RAMP_CMD, "--commands and -o name the same file '%s'", out_path);
    }
    for (i = 0; i < 6; i++)
        if (seen_sig[i] && algo != RAMP_ALGO_SIGMOID)
            return cli_error(RAMP_CMD, "%s applies to --algo sigmoid only", sig_names[i]);
    for (i = 0; i < 4; i++)
        if (seen_trap[i] && algo == RAMP_ALGO_SIGMOID)
            return cli_error(RAMP_CMD, "%s does not apply to --algo sigmoid (it uses --len --fmin --fmax --flex "
                                       "--timer-hz --hold)",
                             trap_names[i]);
    if (len > 65535U)
        return cli_error(RAMP_CMD, "--len: %lu is more than 65535 entries", (unsigned long)len);
    if (hold > 65535U)
        return cli_error(RAMP_CMD, "--hold: %lu is more than 65535 steps", (unsigned long)hold);

    params.v0_sps = v0;
    params.vmax_sps = vmax;
    params.accel_sps2 = accel;
    params.tick_hz = tick_hz;
    v_start = v0;
    rate = tick_hz;
    if (algo == RAMP_ALGO_SIGMOID) {
        if ((rc = check_float_option("--fmin", fmin, "the S-curve table")) >= 0 ||
            (rc = check_float_option("--fmax", fmax, "the S-curve table")) >= 0 ||
            (rc = check_float_option("--flex", flex, "the S-curve table")) >= 0)
            return rc;
        sp.len = (uint16_t)len;
        sp.hold = (uint16_t)hold;
        sp.fmin_hz = (float)fmin;
        sp.fmax_hz = (float)fmax;
        sp.flex = (float)flex;
        sp.timer_hz = timer_hz;
        st = ramp_sigmoid_check(&sp);
        if (st != MS_OK)
            return cli_error(RAMP_CMD, "%s", motion_status_text(st));
        table = malloc(sizeof *table * len);
        if (table == NULL) {
            fprintf(stderr, "motionsim ramp: out of memory for a %lu-entry table\n", (unsigned long)len);
            return CLI_EXIT_RUNTIME;
        }
        st = ramp_sigmoid_fill(&sp, table, (uint16_t)len);
        if (st == MS_OK)
            st = ramp_plan_sigmoid(&r, &sp, table, (uint16_t)len, from, to);
        v_start = sp.fmin_hz;
        rate = (double)timer_hz;
    } else if (compare) {
        /* every row is measured against the exact ramp: without it there is nothing to print */
        static const ramp_algo_t algos[] = {RAMP_ALGO_EXACT, RAMP_ALGO_SIMPLISTIC, RAMP_ALGO_LEIB};
        size_t k;
        st = ramp_plan(&exact, RAMP_ALGO_EXACT, &params, from, to);
        if (st != MS_OK)
            return cli_error(RAMP_CMD, "%s (the exact ramp, which --compare measures against)",
                             motion_status_text(st));
        for (k = 0; k < sizeof algos / sizeof algos[0]; k++) {
            cmp_plan_t *c = &plans[n_plans++];
            c->algo = algos[k];
            c->left_out = float_params_problem(algos[k], &params, c->why, sizeof c->why);
            if (c->left_out == NULL) {
                st = ramp_plan(&c->plan, algos[k], &params, from, to);
                if (st != MS_OK)
                    c->left_out = motion_status_text(st); /* e.g. simplistic with v0 = 0 */
            }
        }
        st = MS_OK;
    } else {
        char msg[200];
        /* the step engine's exact planner takes its parameters as floats too (step_exact.h) */
        const char *why = queue && algo == RAMP_ALGO_EXACT
                              ? float_params_problem_of("the step engine's exact planner", &params, msg, sizeof msg)
                              : float_params_problem((ramp_algo_t)algo, &params, msg, sizeof msg);
        if (why != NULL)
            return cli_error(RAMP_CMD, "%s", why);
        /* --queue: the planner checks the parameters itself (step_exact's limits for exact) */
        st = queue ? MS_OK : ramp_plan(&r, (ramp_algo_t)algo, &params, from, to);
    }
    if (st != MS_OK) {
        free(table);
        return cli_error(RAMP_CMD, "%s", motion_status_text(st));
    }
    if (!queue && !compare && r.steps_total > max_rows) {
        free(table);
        return too_many_rows(r.steps_total, max_rows);
    }
    if (compare && !compute_compare(cmp_rows, plans, n_plans, &exact, &params, whole, max_rows))
        return cli_error(RAMP_CMD, "--compare would compare more than --max-rows %lu steps one by one (only cruise "
                                   "steps are summed in one go, and these ramps accelerate and decelerate longer "
                                   "than that): shorten the move, lower --vmax or raise --accel, or raise --max-rows",
                         (unsigned long)max_rows);
    if (queue) {
        rc = queue_main(&q, algo, &params, &sp, table, from, to, rate, v_start);
        free(table);
        return rc;
    }
    f = cli_open_output(RAMP_CMD, out_path);
    if (f == NULL) {
        free(table);
        return CLI_EXIT_RUNTIME;
    }
    if (compare) {
        size_t k;
        for (k = 0; k < n_plans; k++)
            if (plans[k].left_out != NULL)
                fprintf(stderr, "motionsim ramp: %s left out of the comparison: %s\n", ramp_algo_name(plans[k].algo),
                        plans[k].left_out);
        run_compare(f, cmp_rows, plans, n_plans, &params);
    } else {
        table_header(f);
        table_rows(f, &r, rate, v_start, whole);
    }
    free(table);
    return cli_close_output(RAMP_CMD, f, out_path);
}
