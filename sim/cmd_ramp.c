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

#define RAMP_CMD "ramp"

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

static motion_status_t compare_one(cmp_t *c, ramp_algo_t algo, const ramp_params_t *p, int32_t from, int32_t to,
                                   int whole)
{
    ramp_t r, ex;
    ramp_step_t s, e;
    kin_t kr, ke;
    motion_status_t st = ramp_plan(&r, algo, p, from, to);
    if (st != MS_OK)
        return st;
    st = ramp_plan(&ex, RAMP_ALGO_EXACT, p, from, to);
    if (st != MS_OK)
        return st;
    memset(c, 0, sizeof *c);
    c->name = ramp_algo_name(algo);
    c->steps = r.steps_total;
    kin_init(&kr, (double)p->tick_hz, p->v0_sps);
    kin_init(&ke, (double)p->tick_hz, p->v0_sps);
    while (ramp_next(&r, &s) && ramp_next(&ex, &e)) {
        double own_t = (algo == RAMP_ALGO_EXACT && !whole) ? ramp_exact_time_s(&r.u.exact, s.step) : -1.0;
        kin_row_t a = kin_row(&kr, s.interval_ticks, s.whole_ticks, whole, own_t);
        kin_row_t b = kin_row(&ke, e.interval_ticks, e.whole_ticks, 0, ramp_exact_time_s(&ex.u.exact, e.step));
        double di = (a.dt_s - b.dt_s) * (double)p->tick_hz;
        double dpct = 100.0 * (a.dt_s - b.dt_s) / b.dt_s;
        double da = a.accel_sps2 - b.accel_sps2;
        double dt = fabs(a.t_s - b.t_s);
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
    }
    return MS_OK;
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

static int run_compare(FILE *f, const ramp_params_t *p, int32_t from, int32_t to, int whole)
{
    static const ramp_algo_t algos[] = {RAMP_ALGO_EXACT, RAMP_ALGO_SIMPLISTIC, RAMP_ALGO_LEIB};
    size_t i;
    fputs("algo,steps,move_time_s,move_time_dev_pct,step_time_max_dev_s,interval_max_dev_ticks,"
          "interval_max_dev_pct,interval_max_dev_step,interval_rms_dev_pct,accel_max_dev_sps2,"
          "accel_max_dev_pct,accel_max_dev_step,accel_rms_dev_sps2\n",
          f);
    for (i = 0; i < sizeof algos / sizeof algos[0]; i++) {
        cmp_t c;
        motion_status_t st = compare_one(&c, algos[i], p, from, to, whole);
        if (st != MS_OK) {
            /* e.g. the simplistic ramp with v0 = 0: the others are still worth comparing */
            fprintf(stderr, "motionsim ramp: %s left out of the comparison: %s\n", ramp_algo_name(algos[i]),
                    motion_status_text(st));
            continue;
        }
        compare_row(f, &c, p->accel_sps2);
    }
    return CLI_EXIT_OK;
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
    while (ramp_next(r, &s)) {
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
    "acceleration), sigmoid (seed 001 S-curve table; options --len --fmin --fmax --flex --timer-hz\n"
    "--hold instead of --v0 --vmax --accel --tick-hz).\n"
    "--compare prints, for exact, simplistic and leib, how far each deviates from the exact ramp:\n"
    "move time, largest step-time error, largest and RMS interval error, largest and RMS\n"
    "acceleration error (with the step where the largest occurs).\n"
    "The firmware's intervals: LeibRampStepper = --algo leib --tick-hz 2000000 --integer-ticks.";

int cmd_ramp(int argc, char **argv)
{
    int algo = RAMP_ALGO_LEIB, compare = 0, whole = 0;
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
        {"--algo", CLI_CHOICE, &algo, NULL, "ramp algorithm (default leib)", "simplistic|leib|exact|sigmoid", NULL},
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
        {"--compare", CLI_FLAG, &compare, NULL, "deviation of simplistic and leib from exact (a table)", NULL, NULL},
        {"-o", CLI_STRING, &out_path, "FILE", "write the CSV to FILE instead of stdout", NULL, NULL},
    };
    const cli_spec_t spec = {RAMP_CMD, "[--algo A] [--from N --to N] [options] [--compare] [-o FILE]",
                             ramp_description, opts, sizeof opts / sizeof opts[0], 0};
    ramp_t r;
    ramp_params_t params;
    ramp_sigmoid_params_t sp;
    uint16_t *table = NULL;
    double v_start, rate;
    motion_status_t st;
    FILE *f;
    int rc, i;

    rc = cli_parse(&spec, argc, argv, NULL, NULL);
    if (rc >= 0)
        return rc;
    for (i = 0; i < 6; i++)
        if (seen_sig[i] && algo != RAMP_ALGO_SIGMOID)
            return cli_error(RAMP_CMD, "%s applies to --algo sigmoid only", sig_names[i]);
    for (i = 0; i < 4; i++)
        if (seen_trap[i] && algo == RAMP_ALGO_SIGMOID)
            return cli_error(RAMP_CMD, "%s does not apply to --algo sigmoid (it uses --len --fmin --fmax --flex "
                                       "--timer-hz --hold)",
                             trap_names[i]);
    if (compare && algo == RAMP_ALGO_SIGMOID)
        return cli_error(RAMP_CMD, "--compare measures simplistic and leib against exact; not for sigmoid");
    if (len > 65535U)
        return cli_error(RAMP_CMD, "--len: %lu is more than 65535 entries", (unsigned long)len);
    if (hold > 65535U)
        return cli_error(RAMP_CMD, "--hold: %lu is more than 65535 steps", (unsigned long)hold);

    params.v0_sps = v0;
    params.vmax_sps = vmax;
    params.accel_sps2 = accel;
    params.tick_hz = tick_hz;
    if (algo == RAMP_ALGO_SIGMOID) {
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
        st = ramp_params_check(&params);
        v_start = v0;
        rate = tick_hz;
    } else {
        st = ramp_plan(&r, (ramp_algo_t)algo, &params, from, to);
        v_start = v0;
        rate = tick_hz;
    }
    if (st != MS_OK) {
        free(table);
        return cli_error(RAMP_CMD, "%s", motion_status_text(st));
    }
    f = cli_open_output(RAMP_CMD, out_path);
    if (f == NULL) {
        free(table);
        return CLI_EXIT_RUNTIME;
    }
    if (compare) {
        run_compare(f, &params, from, to, whole);
    } else {
        table_header(f);
        table_rows(f, &r, rate, v_start, whole);
    }
    free(table);
    return cli_close_output(RAMP_CMD, f, out_path);
}
