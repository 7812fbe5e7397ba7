/* sim/cmd_smooth.c - `motionsim ramp --algo smooth`: the filter-shaped (jerk-limited) move of
 * lib/src/smooth_move.h (the moving-average-filter note's velocity command through its two moving
 * averages), as a step table, through the step engine (--queue), or compared with the trapezoid
 * (exact ramp from rest) and the sigmoid table (--compare). cmd_ramp() hands `--algo smooth` here.
 *
 * Table rows (also in --help):
 *   t_s            step n's exact time t_n (the root of the piecewise-cubic position law)
 *   interval_ticks (t_n - t_(n-1)) F
 *   speed_sps, accel_sps2, jerk_sps3   the law's velocity, acceleration and jerk at t_n
 * --queue: the same columns from the executor's edges (whole ticks), speed and acceleration as
 * `ramp --queue` measures them, jerk_sps3 the change of accel_sps2 between consecutive rows over
 * the mean of their two intervals.
 * --compare: one row per algorithm for the same move, every figure measured from the step times
 * alone in the same way: speed 1/dt at each interval's mid-time, acceleration the change of
 * speed between mid-times, jerk the change of acceleration between its instants.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "csv.h"
#include "ramp.h"
#include "smooth_move.h"
#include "step_queue.h"

#define SMOOTH_CMD "ramp"
#define SMOOTH_MAX_ROWS_DEFAULT 1000000UL
#define SMOOTH_MAX_EVENTS 64

int cmd_ramp_wants_smooth(int argc, char **argv)
{
    int i;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--") == 0)
            return 0;
        if (strcmp(argv[i], "--algo=smooth") == 0)
            return 1;
        if (strcmp(argv[i], "--algo") == 0 && i + 1 < argc && strcmp(argv[i + 1], "smooth") == 0)
            return 1;
    }
    return 0;
}

/* ---- finite differences of step times (--compare, --queue) ---- */
typedef struct {
    double t_prev, dt_prev;   /* time of the previous step, its interval (0: none yet) */
    double v_prev, tv_prev;   /* previous speed and its mid-time */
    double a_prev, ta_prev;   /* previous acceleration and its instant */
    int nv, na;
    double v, a, j;           /* the latest values */
    double vmax, amax, jmax;  /* peaks (magnitudes) */
} diff_t;

static void diff_init(diff_t *d)
{
    memset(d, 0, sizeof *d);
}

/* the next step at time t (s); the move starts at rest at t = 0 */
static void diff_step(diff_t *d, double t)
{
    double dt = t - d->t_prev, tv = d->t_prev + dt / 2;
    d->v = dt > 0 ? 1.0 / dt : 0.0;
    if (d->nv == 0) {
        d->a = dt > 0 ? d->v / tv : 0.0; /* from rest at t = 0 */
        d->j = 0.0;
    } else {
        double ta = (d->tv_prev + tv) / 2;
        d->a = (d->v - d->v_prev) / (tv - d->tv_prev);
        d->j = d->na > 0 ? (d->a - d->a_prev) / (ta - d->ta_prev) : 0.0;
        d->ta_prev = ta;
        d->na++;
    }
    if (d->nv == 0)
        d->ta_prev = tv / 2;
    d->nv++;
    d->a_prev = d->a;
    d->v_prev = d->v;
    d->tv_prev = tv;
    d->t_prev = t;
    if (fabs(d->v) > d->vmax)
        d->vmax = fabs(d->v);
    if (fabs(d->a) > d->amax)
        d->amax = fabs(d->a);
    if (fabs(d->j) > d->jmax)
        d->jmax = fabs(d->j);
}

typedef struct {
    const char *name;
    uint64_t steps;
    double time_s;
    diff_t d;
} cmp_row_t;

static void compare_print(FILE *f, const cmp_row_t *r)
{
    double v[5];
    fprintf(f, "%s,", r->name);
    v[0] = (double)r->steps;
    v[1] = r->time_s;
    v[2] = r->d.vmax;
    v[3] = r->d.amax;
    v[4] = r->d.jmax;
    csv_row(f, v, 5);
}

static const char smooth_description[] =
    "--algo smooth: the filter-shaped move (lib/src/smooth_move.h): the velocity command, a\n"
    "rectangle of height vmax and area |to - from| (lower and tau1 + tau2 long for moves between\n"
    "vmax (tau1 - tau2) and vmax (tau1 + tau2) steps), through the moving-average-filter note's two\n"
    "moving averages tau1 = vmax/accel and tau2 = accel/jerk: acceleration at most accel, jerk at\n"
    "most jerk, velocity and acceleration continuous, the distance exact. Rows:\n"
    "step,position,t_s,interval_ticks,speed_sps,accel_sps2,jerk_sps3: t_s the exact step time,\n"
    "speed/accel/jerk the law's values at t_s. --queue: the same columns rebuilt from the step\n"
    "engine's commands (whole-tick edges; speed and acceleration from the intervals as in\n"
    "`ramp --queue`, jerk the change of acceleration over the mean interval); --stop-at N and\n"
    "--retarget-at N:TARGET[,...] as there. --compare: one row per algorithm for the same move,\n"
    "algo,steps,move_time_s,peak_speed_sps,peak_accel_sps2,peak_jerk_sps3, all measured from the\n"
    "step times (speed 1/dt at mid-interval, acceleration and jerk by differences): trapezoid\n"
    "(the exact ramp from rest, v0 0), smooth, sigmoid (the S-curve table with fmax = vmax,\n"
    "timer-hz = tick-hz, fmin = max(vmax/10, tick-hz/65535 + 1) and its defaults len 1000, flex 8, hold 4, or --fmin/--flex/\n"
    "--len/--hold; left out with its reason on stderr when it refuses them).";

typedef struct {
    uint32_t at;
    int stop;
    int32_t target;
} sm_event_t;

static int parse_events(const char *arg, sm_event_t *ev, size_t *n)
{
    const char *p = arg;
    for (;;) {
        char piece[64], *colon;
        const char *comma = strchr(p, ',');
        size_t len = comma != NULL ? (size_t)(comma - p) : strlen(p);
        sm_event_t e;
        if (len == 0 || len >= sizeof piece || memchr(p, ':', len) == NULL)
            return cli_error(SMOOTH_CMD, "--retarget-at: '%.*s' is not N:TARGET (step number, colon, target)",
                             (int)(len < 40 ? len : 40), p);
        memcpy(piece, p, len);
        piece[len] = '\0';
        colon = strchr(piece, ':');
        *colon = '\0';
        if (cli_parse_uint32(piece, &e.at) != 0 || e.at == 0)
            return cli_error(SMOOTH_CMD, "--retarget-at: the step number '%s' is not a whole number in 1..4294967295",
                             piece);
        if (cli_parse_int32(colon + 1, &e.target) != 0)
            return cli_error(SMOOTH_CMD, "--retarget-at: the target '%s' is not a whole number in "
                                         "-2147483648..2147483647", colon + 1);
        e.stop = 0;
        if (*n > 0 && e.at <= ev[*n - 1].at)
            return cli_error(SMOOTH_CMD, "--retarget-at: the step numbers must increase");
        if (*n >= SMOOTH_MAX_EVENTS)
            return cli_error(SMOOTH_CMD, "--retarget-at: more than %d N:TARGET pairs", SMOOTH_MAX_EVENTS);
        ev[(*n)++] = e;
        if (comma == NULL)
            return -1;
        p = comma + 1;
    }
}

/* --queue: commands through the executor; table may be NULL (dry run: counts steps only) */
static int queue_run(smooth_move_t *s, const sm_event_t *ev, size_t n_ev, FILE *table, double tick_hz,
                     uint64_t max_steps, uint64_t *steps_out, size_t *events_done, motion_status_t *st)
{
    step_exec_t x;
    step_cmd_t c;
    uint64_t abs16 = 0x8000U, prev_edge = 0, steps = 0;
    int64_t pos = smooth_move_position(s);
    double prev_dt = 0, prev_speed = 0, prev_accel = 0;
    size_t done = 0;
    *st = MS_OK;
    step_exec_init(&x, 0x8000U);
    while (smooth_move_next(s, &c)) {
        if (table != NULL && ferror(table))
            break;
        if (table == NULL) {
            steps += c.count;
        } else {
            step_exec_load(&x, &c);
            while (x.left > 0U) {
                uint32_t before = x.acc, wide_ticks = step_exec_wide_ticks(&x);
                int wide = (x.flags & STEP_CMD_WIDE) != 0;
                uint64_t edge;
                double dt, speed, accel, jerk;
                (void)step_exec_next(&x);
                abs16 += wide ? (uint64_t)wide_ticks << 16 : (uint64_t)(uint32_t)(x.acc - before);
                edge = abs16 >> 16;
                pos += (x.flags & STEP_CMD_REVERSE) ? -1 : 1;
                steps++;
                dt = (double)(edge - prev_edge) / tick_hz;
                speed = dt > 0 ? 1.0 / dt : 0.0;
                accel = prev_dt == 0.0 ? (dt > 0 ? speed / (dt / 2) : 0.0) : (speed - prev_speed) / ((dt + prev_dt) / 2);
                jerk = prev_dt == 0.0 ? 0.0 : (accel - prev_accel) / ((dt + prev_dt) / 2);
                fprintf(table, "%llu,%lld,", (unsigned long long)steps, (long long)pos);
                csv_num(table, (double)edge / tick_hz);
                fprintf(table, ",%llu,", (unsigned long long)(edge - prev_edge));
                csv_num(table, speed);
                fputc(',', table);
                csv_num(table, accel);
                fputc(',', table);
                csv_num(table, jerk);
                fputc('\n', table);
                prev_edge = edge;
                prev_dt = dt;
                prev_speed = speed;
                prev_accel = accel;
            }
        }
        if (steps > max_steps) {
            *steps_out = steps;
            return 1;
        }
        while (done < n_ev && steps >= ev[done].at) {
            const sm_event_t *e = &ev[done++];
            if (e->stop) {
                smooth_move_stop(s);
            } else {
                *st = smooth_move_to(s, e->target);
                if (*st != MS_OK) {
                    *steps_out = steps;
                    *events_done = done;
                    return 0;
                }
            }
        }
    }
    *steps_out = steps;
    *events_done = done;
    return 0;
}

/* the trapezoid, smooth and sigmoid rows for the same move */
static int run_compare(FILE *f, const smooth_params_t *sp, int32_t from, int32_t to, const ramp_sigmoid_params_t *sig,
                       uint64_t max_steps)
{
    cmp_row_t rows[3];
    int have[3] = {0, 0, 0}, i;
    uint64_t d = (uint64_t)((int64_t)to > (int64_t)from ? (int64_t)to - from : (int64_t)from - to);
    ramp_params_t tp;
    ramp_t r;
    motion_status_t st;
    if (d > max_steps)
        return cli_error(SMOOTH_CMD, "--compare: the move has %llu steps, more than --max-rows %llu (each step "
                                     "is measured): shorten it or raise --max-rows",
                         (unsigned long long)d, (unsigned long long)max_steps);
    memset(rows, 0, sizeof rows);
    /* trapezoid: the exact ramp from rest */
    tp.v0_sps = 0;
    tp.vmax_sps = sp->vmax_sps;
    tp.accel_sps2 = sp->accel_sps2;
    tp.tick_hz = sp->tick_hz;
    st = ramp_plan(&r, RAMP_ALGO_EXACT, &tp, from, to);
    rows[0].name = "trapezoid";
    if (st != MS_OK) {
        fprintf(stderr, "motionsim ramp: --compare: trapezoid left out: %s\n", motion_status_text(st));
    } else {
        ramp_step_t s;
        have[0] = 1;
        diff_init(&rows[0].d);
        while (ramp_next(&r, &s)) {
            double t = ramp_exact_time_s(&r.u.exact, s.step);
            diff_step(&rows[0].d, t);
            rows[0].steps++;
            rows[0].time_s = t;
        }
    }
    /* smooth */
    {
        smooth_law_t law;
        uint64_t n;
        rows[1].name = "smooth";
        st = smooth_law_set_params(&law, sp);
        if (st == MS_OK) {
            smooth_law_reset(&law, from);
            st = smooth_law_start(&law, to);
        }
        if (st != MS_OK)
            return cli_error(SMOOTH_CMD, "%s", motion_status_text(st));
        have[1] = 1;
        diff_init(&rows[1].d);
        for (n = 1; n <= d; n++) {
            smx_t t = smooth_law_time_of(&law, (uint32_t)n, NULL);
            double ts = smx_to_double(t) / sp->tick_hz;
            diff_step(&rows[1].d, ts);
            rows[1].steps++;
            rows[1].time_s = ts;
            smooth_law_knots_to(&law, t);
        }
    }
    /* sigmoid */
    {
        uint16_t *table = malloc(sizeof *table * sig->len);
        rows[2].name = "sigmoid";
        if (table == NULL) {
            fprintf(stderr, "motionsim ramp: out of memory\n");
            return CLI_EXIT_RUNTIME;
        }
        st = ramp_sigmoid_check(sig);
        if (st == MS_OK)
            st = ramp_sigmoid_fill(sig, table, sig->len);
        if (st == MS_OK)
            st = ramp_plan_sigmoid(&r, sig, table, sig->len, from, to);
        if (st != MS_OK) {
            fprintf(stderr, "motionsim ramp: --compare: sigmoid left out (fmax = vmax %g, timer-hz = tick-hz %lu): "
                            "%s\n", (double)sig->fmax_hz, (unsigned long)sig->timer_hz, motion_status_text(st));
        } else {
            ramp_step_t s;
            uint64_t ticks = 0;
            have[2] = 1;
            diff_init(&rows[2].d);
            while (ramp_next(&r, &s)) {
                double t;
                ticks += s.whole_ticks;
                t = (double)ticks / sig->timer_hz;
                diff_step(&rows[2].d, t);
                rows[2].steps++;
                rows[2].time_s = t;
            }
        }
        free(table);
    }
    fputs("algo,steps,move_time_s,peak_speed_sps,peak_accel_sps2,peak_jerk_sps3\n", f);
    for (i = 0; i < 3; i++)
        if (have[i])
            compare_print(f, &rows[i]);
    return CLI_EXIT_OK;
}

int cmd_ramp_smooth(int argc, char **argv)
{
    int algo = 0, compare = 0, queue = 0, stop_seen = 0, jerk_seen = 0;
    int seen_sig[4] = {0, 0, 0, 0};
    int32_t from = 0, to = 50;
    double vmax = 20.0, accel = 10.0, jerk = 0.0, fmin = 500.0, flex = 8.0;
    uint32_t tick_hz = 1000, max_rows = SMOOTH_MAX_ROWS_DEFAULT, stop_at = 0, len = 1000, hold = 4;
    const char *out_path = NULL, *retarget_arg = NULL;
    static sm_event_t ev[SMOOTH_MAX_EVENTS + 1];
    size_t n_ev = 0;
    const cli_opt_t opts[] = {
        {"--algo", CLI_CHOICE, &algo, NULL, "smooth: the filter-shaped move", "smooth", NULL},
        {"--from", CLI_INT32, &from, "STEPS", "start position (default 0)", NULL, NULL},
        {"--to", CLI_INT32, &to, "STEPS", "target position (default 50); any int32", NULL, NULL},
        {"--vmax", CLI_DOUBLE, &vmax, "SPS", "the command's height, steps/s (default 20)", NULL, NULL},
        {"--accel", CLI_DOUBLE, &accel, "SPS2", "peak acceleration, steps/s^2 (default 10)", NULL, NULL},
        {"--jerk", CLI_DOUBLE, &jerk, "SPS3", "peak jerk, steps/s^3, at least accel^2/vmax (required)", NULL, &jerk_seen},
        {"--tick-hz", CLI_UINT32, &tick_hz, "HZ", "F, timer ticks per second (default 1000)", NULL, NULL},
        {"--compare", CLI_FLAG, &compare, NULL, "trapezoid, smooth and sigmoid for the same move (peaks)", NULL, NULL},
        {"--fmin", CLI_DOUBLE, &fmin, "HZ", "--compare's sigmoid: start/stop step rate (default vmax/10)", NULL, &seen_sig[0]},
        {"--flex", CLI_DOUBLE, &flex, "X", "--compare's sigmoid: flexibility (default 8)", NULL, &seen_sig[1]},
        {"--len", CLI_UINT32, &len, "N", "--compare's sigmoid: table entries (default 1000)", NULL, &seen_sig[2]},
        {"--hold", CLI_UINT32, &hold, "N", "--compare's sigmoid: steps per entry (default 4)", NULL, &seen_sig[3]},
        {"--queue", CLI_FLAG, &queue, NULL, "rebuild the table from the step engine's commands", NULL, NULL},
        {"--stop-at", CLI_UINT32, &stop_at, "N", "--queue: stop after the command containing step N", NULL, &stop_seen},
        {"--retarget-at", CLI_STRING, &retarget_arg, "N:TARGET[,N:TARGET...]",
         "--queue: new target TARGET after the command containing step N", NULL, NULL},
        {"--max-rows", CLI_UINT32, &max_rows, "N", "refuse a table of more than N rows (default 1000000)", NULL, NULL},
        {"-o", CLI_STRING, &out_path, "FILE", "write the CSV to FILE instead of stdout", NULL, NULL},
    };
    const cli_spec_t spec = {SMOOTH_CMD,
                             "--algo smooth --jerk SPS3 [--from N --to N] [--vmax SPS --accel SPS2 --tick-hz HZ] "
                             "[--compare | --queue [--stop-at N] [--retarget-at N:TARGET,...]] [-o FILE]",
                             smooth_description, opts, sizeof opts / sizeof opts[0], 0};
    smooth_params_t sp;
    motion_status_t st;
    uint64_t d;
    FILE *f;
    int rc, i;
    rc = cli_parse(&spec, argc, argv, NULL, NULL);
    if (rc >= 0)
        return rc;
    if (!jerk_seen)
        return cli_error(SMOOTH_CMD, "--algo smooth needs --jerk SPS3 (the peak jerk, steps/s^3)");
    if (compare && queue)
        return cli_error(SMOOTH_CMD, "--queue and --compare cannot be combined");
    if (max_rows == 0)
        return cli_error(SMOOTH_CMD, "--max-rows: 0 is not a bound: a table has at least 1 row (give 1..4294967295)");
    if (!queue && (stop_seen || retarget_arg != NULL))
        return cli_error(SMOOTH_CMD, "%s needs --queue (it works on the step engine's commands)",
                         stop_seen ? "--stop-at" : "--retarget-at");
    for (i = 0; i < 4; i++)
        if (seen_sig[i] && !compare)
            return cli_error(SMOOTH_CMD, "%s applies to --compare's sigmoid only",
                             i == 0 ? "--fmin" : i == 1 ? "--flex" : i == 2 ? "--len" : "--hold");
    if (len > 65535U || hold > 65535U)
        return cli_error(SMOOTH_CMD, "%s: more than 65535", len > 65535U ? "--len" : "--hold");
    for (i = 0; i < 3; i++) {
        double x = i == 0 ? vmax : i == 1 ? accel : jerk;
        if (cli_float_range(x) != 0)
            return cli_error(SMOOTH_CMD, "%s: %g does not fit a float (the sketches compute in float)",
                             i == 0 ? "--vmax" : i == 1 ? "--accel" : "--jerk", x);
    }
    sp.vmax_sps = vmax;
    sp.accel_sps2 = accel;
    sp.jerk_sps3 = jerk;
    sp.tick_hz = tick_hz;
    {
        smooth_law_t probe;
        st = smooth_law_set_params(&probe, &sp);
        if (st != MS_OK) {
            if (st == MS_ERR_JERK_TOO_LOW)
                return cli_error(SMOOTH_CMD, "%s (accel^2/vmax = %g steps/s^3)", motion_status_text(st),
                                 (double)(float)accel * (double)(float)accel / (double)(float)vmax);
            return cli_error(SMOOTH_CMD, "%s", motion_status_text(st));
        }
    }
    d = (uint64_t)((int64_t)to > (int64_t)from ? (int64_t)to - from : (int64_t)from - to);
    if (compare) {
        ramp_sigmoid_params_t sig;
        sig.len = (uint16_t)len;
        sig.hold = (uint16_t)hold;
        /* default fmin: vmax/10, at least the lowest rate whose period fits 16 bits */
        sig.fmin_hz = (float)(seen_sig[0] ? fmin : fmax(vmax / 10, ceil(tick_hz / 65535.0) + 1));
        sig.fmax_hz = (float)vmax;
        sig.flex = (float)flex;
        sig.timer_hz = tick_hz;
        f = cli_open_output(SMOOTH_CMD, out_path);
        if (f == NULL)
            return CLI_EXIT_RUNTIME;
        rc = run_compare(f, &sp, from, to, &sig, max_rows);
        if (rc != CLI_EXIT_OK) {
            (void)cli_close_output(SMOOTH_CMD, f, out_path);
            return rc;
        }
        return cli_close_output(SMOOTH_CMD, f, out_path);
    }
    if (queue) {
        smooth_move_t s, dry;
        uint64_t steps = 0;
        size_t done = 0;
        if (retarget_arg != NULL && (rc = parse_events(retarget_arg, ev, &n_ev)) >= 0)
            return rc;
        if (stop_seen) {
            size_t k = 0, j;
            if (stop_at == 0)
                return cli_error(SMOOTH_CMD, "--stop-at: 0 is not a step number (the steps of a move count from 1)");
            while (k < n_ev && ev[k].at < stop_at)
                k++;
            if (k < n_ev && ev[k].at == stop_at)
                return cli_error(SMOOTH_CMD, "--stop-at %lu and --retarget-at fall on the same step",
                                 (unsigned long)stop_at);
            for (j = n_ev; j > k; j--)
                ev[j] = ev[j - 1];
            ev[k].at = stop_at;
            ev[k].stop = 1;
            ev[k].target = 0;
            n_ev++;
        }
        st = smooth_move_init(&s, &sp, from);
        if (st == MS_OK)
            st = smooth_move_to(&s, to);
        if (st != MS_OK)
            return cli_error(SMOOTH_CMD, "%s", motion_status_text(st));
        dry = s;
        if (queue_run(&dry, ev, n_ev, NULL, tick_hz, max_rows, &steps, &done, &st))
            return cli_error(SMOOTH_CMD, "the table would have more than --max-rows %lu rows", (unsigned long)max_rows);
        if (st != MS_OK)
            return cli_error(SMOOTH_CMD, "--retarget-at %lu:%ld: %s", (unsigned long)ev[done - 1].at,
                             (long)ev[done - 1].target, motion_status_text(st));
        if (done < n_ev)
            return cli_error(SMOOTH_CMD, "%s %lu: the move has only %llu steps by then",
                             ev[done].stop ? "--stop-at" : "--retarget-at", (unsigned long)ev[done].at,
                             (unsigned long long)steps);
        f = cli_open_output(SMOOTH_CMD, out_path);
        if (f == NULL)
            return CLI_EXIT_RUNTIME;
        fputs("step,position,t_s,interval_ticks,speed_sps,accel_sps2,jerk_sps3\n", f);
        (void)queue_run(&s, ev, n_ev, f, tick_hz, max_rows, &steps, &done, &st);
        return cli_close_output(SMOOTH_CMD, f, out_path);
    }
    if (d > max_rows)
        return cli_error(SMOOTH_CMD, "the table would have %llu rows, more than --max-rows %lu: shorten the move "
                                     "(--from/--to), or raise --max-rows",
                         (unsigned long long)d, (unsigned long)max_rows);
    f = cli_open_output(SMOOTH_CMD, out_path);
    if (f == NULL)
        return CLI_EXIT_RUNTIME;
    fputs("step,position,t_s,interval_ticks,speed_sps,accel_sps2,jerk_sps3\n", f);
    {
        smooth_law_t law;
        uint64_t n;
        double t_prev = 0;
        int dir = to >= from ? 1 : -1;
        (void)smooth_law_set_params(&law, &sp);
        smooth_law_reset(&law, from);
        (void)smooth_law_start(&law, to);
        for (n = 1; n <= d && !ferror(f); n++) {
            smx_t t = smooth_law_time_of(&law, (uint32_t)n, NULL);
            double ts = smx_to_double(t) / tick_hz, v, a, j;
            smooth_law_knots_to(&law, t);
            smooth_law_eval(&law, t, NULL, &v, &a, &j);
            fprintf(f, "%llu,%lld,", (unsigned long long)n, (long long)from + dir * (long long)n);
            csv_num(f, ts);
            fputc(',', f);
            csv_num(f, (ts - t_prev) * tick_hz);
            fputc(',', f);
            csv_num(f, v);
            fputc(',', f);
            csv_num(f, a);
            fputc(',', f);
            csv_num(f, j);
            fputc('\n', f);
            t_prev = ts;
        }
    }
    return cli_close_output(SMOOTH_CMD, f, out_path);
}
