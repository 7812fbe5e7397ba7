/* sim/cmd_pid_replay.c - `motionsim pid-replay [--float] VECTOR.csv`: replays a PID_v1 reference
 * vector (test/data/pid_v1/: NAME.csv with its set-up in NAME.json) through our pidv1_ctrl
 * module and writes CSV `t_ms,computed,output`, one row per vector row. In double (default) the
 * output must equal the vector's `output` column bit for bit; with --float the module runs in
 * 32-bit float, as on the Mega, and must equal the float32/ vectors. Numbers are written in the
 * shortest form that reads back to the same value of the precision used (as the vectors are).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli.h"
#include "commands.h"
#include "csv.h"
#include "csv_float.h"
#include "pid_vector.h"

typedef struct {
    FILE *f;
    const pv_vector_t *v;
} replay_out_t;

static void print_double(FILE *f, double x)
{
    if (x == 0.0 && signbit(x))
        fputs("-0", f);
    else
        csv_num(f, x);
}

static void row_double(void *user, size_t row, int computed, double output, const pid_ctrl_t *c)
{
    replay_out_t *o = user;
    (void)c;
    fprintf(o->f, "%lu,%d,", (unsigned long)o->v->rows[row].t_ms, computed);
    print_double(o->f, output);
    fputc('\n', o->f);
}

static void row_float(void *user, size_t row, int computed, float output, const pidf_ctrl_t *c)
{
    replay_out_t *o = user;
    (void)c;
    fprintf(o->f, "%lu,%d,", (unsigned long)o->v->rows[row].t_ms, computed);
    csv_num_f32(o->f, output);
    fputc('\n', o->f);
}

int cmd_pid_replay(int argc, char **argv)
{
    int use_float = 0;
    const char *out_path = NULL;
    const char *pos[1];
    size_t n_pos = 0;
    static pv_vector_t v;
    char err[512];
    replay_out_t o;
    FILE *f;
    int rc;
    motion_status_t st;
    const cli_opt_t opts[] = {
        {"--float", CLI_FLAG, &use_float, NULL, "run the controller in 32-bit float, as on the Mega (compare with float32/ vectors)", NULL, NULL},
        {"-o", CLI_STRING, &out_path, "FILE", "write the CSV to FILE instead of stdout", NULL, NULL},
    };
    const cli_spec_t spec = {
        "pid-replay", "[--float] [-o FILE] VECTOR.csv",
        "Replays a PID_v1 1.2.1 reference vector through our controller: the set-up comes from\n"
        "NAME.json beside NAME.csv (or one folder up for float32/NAME.csv); each row sets Input and\n"
        "Setpoint, runs its commands and calls Compute() at t_ms. Output: CSV t_ms,computed,output.",
        opts, sizeof opts / sizeof opts[0], 1};
    rc = cli_parse(&spec, argc, argv, pos, &n_pos);
    if (rc >= 0)
        return rc;
    if (n_pos != 1)
        return cli_error(argv[0], "one VECTOR.csv is needed (try 'motionsim pid-replay --help')");
    if (pv_load(&v, pos[0], err, sizeof err) != 0)
        return cli_error(argv[0], "%s", err);
    f = cli_open_output(argv[0], out_path);
    if (f == NULL) {
        pv_free(&v);
        return CLI_EXIT_RUNTIME;
    }
    o.f = f;
    o.v = &v;
    fputs("t_ms,computed,output\n", f);
    st = use_float ? pv_replay_float(&v, row_float, &o) : pv_replay_double(&v, row_double, &o);
    pv_free(&v);
    rc = cli_close_output(argv[0], f, out_path);
    if (st != MS_OK) /* not expected: pv_load refuses what the constructor would reject */
        return cli_error(argv[0], "the controller refused the set-up: %s", motion_status_text(st));
    return rc;
}
