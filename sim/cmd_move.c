/* sim/cmd_move.c - `motionsim move`: a coordinated move of the X, Y and Z axes planned by
 * lib/src/step_coord.h (what MultiAxisStepper's `move x.. y.. z..` runs), every axis's commands run
 * through the step interrupt's executor (step_queue.h), the edges of all axes merged in time order.
 *
 * Row quantities (also in --help and docs/motionsim.md):
 *   t_s             whole tick of the edge / F; the move starts at t = 0 (the executor's timeline
 *                   starts half a tick in, so the edge tick is round(F t) of the planned time)
 *   axis            x, y or z
 *   step            the axis's step number, 1..D_axis
 *   position        the axis's position after the step
 *   path_err_steps  distance of the tool (x, y, z positions, after every edge of this tick) from
 *                   the straight line from start to end, in steps (Euclidean in step space)
 * --summary prints one line on stderr: steps per axis, the move's time, the spread of the axes' last
 * edges in ticks and the largest path error.
 * --path writes one row per tick with an edge instead, all numeric (for plots of the path and speeds):
 *   t_s, x_pos, y_pos, z_pos (positions after that tick's edges), x_speed_sps, y_speed_sps, z_speed_sps (F over the
 *   axis's last interval: its mean speed over it, held until its next edge; 0 before its first step),
 *   path_err_steps.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "csv.h"
#include "step_coord.h"
#include "step_queue.h"

#define MOVE_CMD "move"
#define AXES 3
/* --max-rows's default, as motionsim ramp's: the move scenario has 5500 rows */
#define MOVE_MAX_ROWS_DEFAULT 1000000UL

static const char *const axis_names[AXES] = {"x", "y", "z"};

typedef struct {
    step_exec_t x;
    uint64_t abs16; /* absolute time of the last edge, 2^-16 ticks */
    uint64_t tick;  /* whole tick of the pending edge */
    uint32_t step;
    int32_t pos;
    int pending;    /* an edge is pending at `tick` */
    int8_t dir;
} axis_run_t;

/* the axis's next edge (pending = 0 when its part of the move is complete) */
static void advance(step_coord_t *c, uint8_t i, axis_run_t *a)
{
    step_cmd_t cmd;
    if (a->x.left == 0) {
        if (!step_coord_next(c, i, &cmd)) {
            a->pending = 0;
            return;
        }
        step_exec_load(&a->x, &cmd);
        a->dir = (cmd.flags & STEP_CMD_REVERSE) ? -1 : 1;
    }
    a->abs16 += (a->x.flags & STEP_CMD_WIDE) ? (uint64_t)a->x.rate << 16 : a->x.rate;
    (void)step_exec_next(&a->x);
    a->tick = a->abs16 >> 16;
    a->pending = 1;
}

/* The rows --path would write (ticks with an edge of any axis), counted on a copy of the plan;
 * counting stops at limit + 1. */
static uint64_t count_path_rows(const step_coord_t *plan, uint64_t limit)
{
    static step_coord_t c;
    axis_run_t run[AXES];
    uint64_t rows = 0;
    int i;
    c = *plan;
    for (i = 0; i < AXES; i++) {
        memset(&run[i], 0, sizeof run[i]);
        step_exec_init(&run[i].x, 0x8000U);
        run[i].abs16 = 0x8000U;
        advance(&c, (uint8_t)i, &run[i]);
    }
    while (rows <= limit) {
        uint64_t t = UINT64_MAX;
        for (i = 0; i < AXES; i++)
            if (run[i].pending && run[i].tick < t)
                t = run[i].tick;
        if (t == UINT64_MAX)
            break;
        rows++;
        for (i = 0; i < AXES; i++)
            if (run[i].pending && run[i].tick == t)
                advance(&c, (uint8_t)i, &run[i]);
    }
    return rows;
}

/* distance of point p (relative to the start) from the line through 0 and d */
static double line_distance(const double p[AXES], const double d[AXES])
{
    double dd = 0, pd = 0, rr = 0, lambda;
    int i;
    for (i = 0; i < AXES; i++) {
        dd += d[i] * d[i];
        pd += p[i] * d[i];
    }
    lambda = dd > 0 ? pd / dd : 0.0;
    for (i = 0; i < AXES; i++) {
        double r = p[i] - lambda * d[i]; /* the residual, component by component (no cancellation) */
        rr += r * r;
    }
    return sqrt(rr);
}

static const char move_description[] =
    "A coordinated move of X, Y and Z (lib/src/step_coord.h: the step engine's plan of\n"
    "MultiAxisStepper's `move x<target> y<target> z<target>`): one normalised profile s(t), the exact\n"
    "constant-acceleration motion of the axis moving furthest, with its v0, vmax and accel the\n"
    "minima of every axis's own limits scaled by D_max/D_axis; each axis follows its own exact ramp\n"
    "of D_axis s(t), all starting at t = 0 and ending on the same tick. Each axis's commands run\n"
    "through the step interrupt's executor; the edges of all axes are merged in time order.\n"
    "Columns: t_s (whole tick of the edge / F), axis, step (1..D of that axis), position (after the\n"
    "step), path_err_steps (distance of the tool from the straight line start -> end, in steps,\n"
    "after every edge of that tick). Limits per axis: --v0 --vmax --accel for all axes, --x-vmax\n"
    "etc. for one (defaults as MultiAxisStepper: v0 0, vmax 20000, accel 50000, F 16 MHz).\n"
    "--summary: one line on stderr (steps per axis, time, last-edge spread in ticks, largest path\n"
    "error). --path: one row per tick with an edge instead: t_s, the x, y, z positions, each axis's\n"
    "speed (F over its last interval, held) and path_err_steps. An axis without a target (or with its start as target) does not move; at least one\n"
    "must move. --max-rows N (default 1000000): a table of more rows (one per step of every axis;\n"
    "--path: one per tick with an edge) is refused before anything is written (exit 2).";

int cmd_move(int argc, char **argv)
{
    int32_t to[AXES] = {0, 0, 0}, from[AXES] = {0, 0, 0};
    int seen_to[AXES] = {0, 0, 0}, summary = 0, path = 0;
    double v0 = 0.0, vmax = 20000.0, accel = 50000.0;
    double ax_v0[AXES] = {0, 0, 0}, ax_vmax[AXES] = {0, 0, 0}, ax_accel[AXES] = {0, 0, 0};
    int seen_v0[AXES] = {0, 0, 0}, seen_vmax[AXES] = {0, 0, 0}, seen_accel[AXES] = {0, 0, 0};
    uint32_t tick_hz = 16000000UL, max_rows = MOVE_MAX_ROWS_DEFAULT;
    const char *out_path = NULL;
    const cli_opt_t opts[] = {
        {"--x", CLI_INT32, &to[0], "STEPS", "X target position (default: X does not move)", NULL, &seen_to[0]},
        {"--y", CLI_INT32, &to[1], "STEPS", "Y target position", NULL, &seen_to[1]},
        {"--z", CLI_INT32, &to[2], "STEPS", "Z target position", NULL, &seen_to[2]},
        {"--from-x", CLI_INT32, &from[0], "STEPS", "X start position (default 0)", NULL, NULL},
        {"--from-y", CLI_INT32, &from[1], "STEPS", "Y start position (default 0)", NULL, NULL},
        {"--from-z", CLI_INT32, &from[2], "STEPS", "Z start position (default 0)", NULL, NULL},
        {"--v0", CLI_DOUBLE, &v0, "SPS", "every axis: start/stop speed, steps/s (default 0)", NULL, NULL},
        {"--vmax", CLI_DOUBLE, &vmax, "SPS", "every axis: maximum speed, steps/s (default 20000)", NULL, NULL},
        {"--accel", CLI_DOUBLE, &accel, "SPS2", "every axis: acceleration, steps/s^2 (default 50000)", NULL, NULL},
        {"--x-v0", CLI_DOUBLE, &ax_v0[0], "SPS", "X only: v0", NULL, &seen_v0[0]},
        {"--x-vmax", CLI_DOUBLE, &ax_vmax[0], "SPS", "X only: vmax", NULL, &seen_vmax[0]},
        {"--x-accel", CLI_DOUBLE, &ax_accel[0], "SPS2", "X only: accel", NULL, &seen_accel[0]},
        {"--y-v0", CLI_DOUBLE, &ax_v0[1], "SPS", "Y only: v0", NULL, &seen_v0[1]},
        {"--y-vmax", CLI_DOUBLE, &ax_vmax[1], "SPS", "Y only: vmax", NULL, &seen_vmax[1]},
        {"--y-accel", CLI_DOUBLE, &ax_accel[1], "SPS2", "Y only: accel", NULL, &seen_accel[1]},
        {"--z-v0", CLI_DOUBLE, &ax_v0[2], "SPS", "Z only: v0", NULL, &seen_v0[2]},
        {"--z-vmax", CLI_DOUBLE, &ax_vmax[2], "SPS", "Z only: vmax", NULL, &seen_vmax[2]},
        {"--z-accel", CLI_DOUBLE, &ax_accel[2], "SPS2", "Z only: accel", NULL, &seen_accel[2]},
        {"--tick-hz", CLI_UINT32, &tick_hz, "HZ", "F, timer ticks per second, one timeline for all axes "
                                                  "(default 16000000, as the sketch)", NULL, NULL},
        {"--summary", CLI_FLAG, &summary, NULL, "one summary line on stderr", NULL, NULL},
        {"--path", CLI_FLAG, &path, NULL, "one row per tick: t_s,x_pos,y_pos,z_pos,x_speed_sps,y_speed_sps,z_speed_sps,"
                                          "path_err_steps", NULL, NULL},
        {"-o", CLI_STRING, &out_path, "FILE", "write the CSV to FILE instead of stdout", NULL, NULL},
        {"--max-rows", CLI_UINT32, &max_rows, "N", "refuse a table of more than N rows, 1..4294967295 (default 1000000)",
         NULL, NULL},
    };
    const cli_spec_t spec = {MOVE_CMD, "--x N [--y N] [--z N] [--from-x N ...] [--vmax V --accel A --v0 V] "
                                       "[--x-vmax V ...] [--tick-hz F] [--summary] [-o FILE]",
                             move_description, opts, sizeof opts / sizeof opts[0], 0};
    ramp_params_t p[AXES];
    static step_coord_t c;
    axis_run_t run[AXES];
    double d[AXES], max_err = 0.0;
    uint64_t last_tick[AXES] = {0, 0, 0};
    double speed[AXES] = {0, 0, 0};
    motion_status_t st;
    uint64_t rows = 0, longest = 0;
    FILE *f;
    int rc, i, any = 0;

    rc = cli_parse(&spec, argc, argv, NULL, NULL);
    if (rc >= 0)
        return rc;
    for (i = 0; i < AXES; i++) {
        if (!seen_to[i])
            to[i] = from[i];
        if (to[i] != from[i])
            any = 1;
        p[i].v0_sps = seen_v0[i] ? ax_v0[i] : v0;
        p[i].vmax_sps = seen_vmax[i] ? ax_vmax[i] : vmax;
        p[i].accel_sps2 = seen_accel[i] ? ax_accel[i] : accel;
        p[i].tick_hz = tick_hz;
        if (cli_float_range(p[i].v0_sps) != 0 || cli_float_range(p[i].vmax_sps) != 0 ||
            cli_float_range(p[i].accel_sps2) != 0)
            return cli_error(MOVE_CMD, "%s axis: a limit does not fit a float (the planner computes in float, as "
                                       "on the Mega)", axis_names[i]);
    }
    if (max_rows == 0)
        return cli_error(MOVE_CMD, "--max-rows: 0 is not a bound: a table has at least 1 row (give 1..4294967295)");
    if (!any)
        return cli_error(MOVE_CMD, "no axis moves: give at least one of --x --y --z with a target other than its "
                                   "start");
    for (i = 0; i < AXES; i++) {
        /* each axis's own limits, as the sketch checks them (`set`) */
        st = ramp_params_check(&p[i]);
        if (st != MS_OK)
            return cli_error(MOVE_CMD, "%s axis: %s", axis_names[i], motion_status_text(st));
    }
    st = step_coord_plan(&c, AXES, p, from, to);
    if (st != MS_OK)
        return cli_error(MOVE_CMD, "%s", motion_status_text(st));
    /* the rows, before anything is written: one per step of every axis; --path one per tick with an
     * edge, at least the longest axis's steps and at most all of them (counted when in between) */
    for (i = 0; i < AXES; i++) {
        uint64_t n = (uint64_t)((int64_t)to[i] > (int64_t)from[i] ? (int64_t)to[i] - from[i] : (int64_t)from[i] - to[i]);
        rows += n;
        if (n > longest)
            longest = n;
    }
    if (path && longest > max_rows)
        rows = longest;
    else if (path && rows > max_rows)
        rows = count_path_rows(&c, max_rows);
    if (rows > max_rows && path && rows != longest) /* counted up to the bound only */
        return cli_error(MOVE_CMD, "the table would have more than --max-rows %lu rows (--path: one per tick with a "
                                   "step): shorten the move (--x/--y/--z, --from-x ...), or raise --max-rows",
                         (unsigned long)max_rows);
    if (rows > max_rows)
        return cli_error(MOVE_CMD, "the table would have %llu rows, more than --max-rows %lu: shorten the move "
                                   "(--x/--y/--z, --from-x ...), or raise --max-rows (%s)",
                         (unsigned long long)rows, (unsigned long)max_rows,
                         path ? "--path: one row per tick with a step" : "one row per step of every axis");
    f = cli_open_output(MOVE_CMD, out_path);
    if (f == NULL)
        return CLI_EXIT_RUNTIME;
    if (path)
        fprintf(f, "t_s,x_pos,y_pos,z_pos,x_speed_sps,y_speed_sps,z_speed_sps,path_err_steps\n");
    else
        fprintf(f, "t_s,axis,step,position,path_err_steps\n");
    for (i = 0; i < AXES; i++) {
        memset(&run[i], 0, sizeof run[i]);
        step_exec_init(&run[i].x, 0x8000U);
        run[i].abs16 = 0x8000U;
        run[i].pos = from[i];
        d[i] = (double)to[i] - (double)from[i];
        advance(&c, (uint8_t)i, &run[i]);
    }
    for (;;) {
        uint64_t t = UINT64_MAX;
        int fired[AXES] = {0, 0, 0}, n_fired = 0;
        double pt[AXES], err;
        for (i = 0; i < AXES; i++)
            if (run[i].pending && run[i].tick < t)
                t = run[i].tick;
        if (t == UINT64_MAX)
            break;
        for (i = 0; i < AXES; i++) {
            if (run[i].pending && run[i].tick == t) {
                /* the mean speed over the interval that ends here (from t = 0 for the first step) */
                speed[i] = (double)tick_hz / (double)(t - (run[i].step > 0 ? last_tick[i] : 0) + (t == 0));
                run[i].step++;
                run[i].pos += run[i].dir;
                last_tick[i] = t;
                fired[i] = 1;
                n_fired++;
            }
        }
        for (i = 0; i < AXES; i++)
            pt[i] = (double)run[i].pos - (double)from[i];
        err = line_distance(pt, d);
        if (err > max_err)
            max_err = err;
        if (path) {
            csv_num(f, (double)t / (double)tick_hz);
            for (i = 0; i < AXES; i++)
                fprintf(f, ",%ld", (long)run[i].pos);
            for (i = 0; i < AXES; i++) {
                fputc(',', f);
                csv_num(f, speed[i]);
            }
            fputc(',', f);
            csv_num(f, err);
            fputc('\n', f);
        }
        for (i = 0; i < AXES; i++) {
            if (!fired[i])
                continue;
            if (path) {
                advance(&c, (uint8_t)i, &run[i]);
                continue;
            }
            csv_num(f, (double)t / (double)tick_hz);
            fprintf(f, ",%s,%lu,%ld,", axis_names[i], (unsigned long)run[i].step, (long)run[i].pos);
            csv_num(f, err);
            fputc('\n', f);
            advance(&c, (uint8_t)i, &run[i]);
        }
        if (ferror(f))
            break;
        (void)n_fired;
    }
    if (summary) {
        uint64_t lo = UINT64_MAX, hi = 0;
        fprintf(stderr, "summary:");
        for (i = 0; i < AXES; i++) {
            fprintf(stderr, " steps_%s=%lu", axis_names[i], (unsigned long)run[i].step);
            if (run[i].step > 0) {
                if (last_tick[i] < lo)
                    lo = last_tick[i];
                if (last_tick[i] > hi)
                    hi = last_tick[i];
            }
        }
        fprintf(stderr, " time_s=");
        csv_num(stderr, (double)hi / (double)tick_hz);
        fprintf(stderr, " last_edge_spread_ticks=%llu max_path_err_steps=", (unsigned long long)(hi - lo));
        csv_num(stderr, max_err);
        fprintf(stderr, " profile_vmax_sps=");
        csv_num(stderr, c.profile.vmax_sps);
        fprintf(stderr, " profile_accel_sps2=");
        csv_num(stderr, c.profile.accel_sps2);
        fprintf(stderr, "\n");
    }
    return cli_close_output(MOVE_CMD, f, out_path);
}
