/* sim/cmd_filter.c - `motionsim filter`: the acceleration/deceleration filters of the moving-average-filter note (moving
 * average, two-stage S-curve, exponential) run on a test input in virtual time, through the same
 * lib/ code as the MovingAverageFilter sketch (accdec_filter.h). Writes CSV k,t_s,u,y, or with
 * --stream the sketch's own serial lines t_ms,u,y, byte for byte. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accdec_filter.h"
#include "cli.h"
#include "commands.h"
#include "csv.h"
#include "csv_read.h"
#include "filter_param.h"
#include "filter_stream.h"

#define MAX_SAMPLES 1000000000ull /* rows per run */
#define MAX_ROWS_DEFAULT 1000000UL /* --max-rows's default, as motionsim ramp's and move's */

typedef enum { IN_STEP, IN_SQUARE, IN_CSV } input_kind_t;

typedef struct {
    input_kind_t kind;
    int16_t amp;        /* step/square amplitude in quanta */
    uint64_t k0;        /* step: first sample at the amplitude */
    uint64_t half;      /* square: samples per half period */
    int16_t *samples;   /* csv: one quantised sample per row */
    uint64_t n_samples;
} input_t;

static int16_t input_at(const input_t *in, uint64_t k)
{
    switch (in->kind) {
    case IN_STEP: return k >= in->k0 ? in->amp : 0;
    case IN_SQUARE: return (k % (2 * in->half)) < in->half ? in->amp : 0;
    default: return in->samples[k];
    }
}

static const char *const input_syntax =
    "expected step:AMPLITUDE[:T_START], square:AMPLITUDE:PERIOD or csv:FILE";

/* Whole number of samples in `seconds` (within 1 ppm), or -1. */
static int64_t whole_samples(double seconds, double ts)
{
    double r = seconds / ts, n = floor(r + 0.5);
    if (!isfinite(r) || r < 0 || r > 1e15 || fabs(r - n) > 1e-6 * (n > 1 ? n : 1))
        return -1;
    return (int64_t)n;
}

static int parse_amplitude(const char *cmd, const char *spec, const char *text, double quantum, int16_t *amp)
{
    double v;
    motion_status_t st;
    if (cli_parse_double(text, &v) != 0)
        return cli_error(cmd, "--input '%s': amplitude '%s' is not a number of volts (%s)", spec, text, input_syntax);
    st = filt_quantise_whole(v, quantum, amp);
    if (st != MS_OK)
        return cli_error(cmd, "--input '%s': amplitude '%s': %s (--quantum %g, at most %g V)", spec, text,
                         motion_status_text(st), quantum, FILT_MAX_QUANTA * quantum);
    return -1;
}

/* Splits "a:b:c" into at most `max` fields (in place). Returns the count, or max + 1 if more. */
static int split_colons(char *s, char **fields, int max)
{
    int n = 0;
    for (;;) {
        char *c = strchr(s, ':');
        if (n == max)
            return max + 1;
        fields[n++] = s;
        if (c == NULL)
            return n;
        *c = '\0';
        s = c + 1;
    }
}

/* ---- csv:FILE ---------------------------------------------------------------------------------- */

#define CSV_MAX_COLS 32

static int load_csv(const char *cmd, const char *path, double ts, double quantum, input_t *in)
{
    csv_reader_t r;
    const char *why;
    size_t n_alloc = 0;
    int got, n_cols = 0, col_u = -1, col_t = -1, col_k = -1, rc = -1;
    uint64_t n = 0;
    double t0 = 0, k_first = 0;
    int16_t *samples = NULL;
    if (csv_open(&r, path, 1) != 0)
        return cli_error(cmd, "--input csv:%s: cannot read the file: %s", path, strerror(errno));
    while ((got = csv_next(&r, &why)) > 0) {
        char **fields = r.fields;
        int nf = (int)r.n_fields;
        unsigned long long lineno = r.lineno;
        if (csv_blank(&r))
            continue;
        if (n_cols == 0) { /* the header */
            const char *twice = csv_duplicate_column(&r);
            if (nf > CSV_MAX_COLS) {
                rc = cli_error(cmd, "csv:%s: more than %d columns", path, CSV_MAX_COLS);
                goto out;
            }
            if (twice != NULL) {
                rc = cli_error(cmd, "csv:%s: the header names column '%s' twice", path, twice);
                goto out;
            }
            n_cols = nf;
            col_u = csv_column(&r, "u");
            col_t = csv_column(&r, "t_ms");
            col_k = csv_column(&r, "k");
            if (col_u < 0 && nf == 1)
                col_u = 0;
            if (col_u < 0) {
                rc = cli_error(cmd, "csv:%s: the header has no column named u (and more than one column)", path);
                goto out;
            }
            continue;
        }
        if (nf != n_cols) {
            rc = cli_error(cmd, "csv:%s line %llu: %d fields, the header has %d", path, lineno, nf, n_cols);
            goto out;
        }
        if (n == n_alloc) {
            size_t grow = n_alloc ? 2 * n_alloc : 4096;
            int16_t *p = realloc(samples, grow * sizeof *samples);
            if (p == NULL) {
                rc = cli_error(cmd, "csv:%s: out of memory", path);
                goto out;
            }
            samples = p;
            n_alloc = grow;
        }
        {
            double v, tv;
            motion_status_t st;
            if (cli_parse_double(fields[col_u], &v) != 0) {
                rc = cli_error(cmd, "csv:%s line %llu: u '%s' is not a number", path, lineno, fields[col_u]);
                goto out;
            }
            st = filt_quantise(v, quantum, &samples[n]);
            if (st != MS_OK) {
                rc = cli_error(cmd, "csv:%s line %llu: u = %s: %s", path, lineno, fields[col_u], motion_status_text(st));
                goto out;
            }
            /* Rows must be consecutive samples: a decimated or gappy capture cannot be replayed. */
            if (col_t >= 0) {
                if (cli_parse_double(fields[col_t], &tv) != 0) {
                    rc = cli_error(cmd, "csv:%s line %llu: t_ms '%s' is not a number", path, lineno, fields[col_t]);
                    goto out;
                }
                if (n == 0)
                    t0 = tv;
                else if (fabs(tv - (t0 + (double)n * ts * 1000.0)) > 0.5) {
                    rc = cli_error(cmd, "csv:%s line %llu: t_ms %s is not %.0f: rows must be consecutive samples %g ms apart (stream every 1, no dropped lines)",
                                   path, lineno, fields[col_t], t0 + (double)n * ts * 1000.0, ts * 1000.0);
                    goto out;
                }
            }
            if (col_k >= 0) {
                if (cli_parse_double(fields[col_k], &tv) != 0) {
                    rc = cli_error(cmd, "csv:%s line %llu: k '%s' is not a number", path, lineno, fields[col_k]);
                    goto out;
                }
                if (n == 0)
                    k_first = tv;
                else if (tv != k_first + (double)n) {
                    rc = cli_error(cmd, "csv:%s line %llu: k %s is not %.0f: rows must be consecutive samples", path,
                                   lineno, fields[col_k], k_first + (double)n);
                    goto out;
                }
            }
        }
        n++;
        if (n > MAX_SAMPLES) {
            rc = cli_error(cmd, "csv:%s: more than %llu rows", path, MAX_SAMPLES);
            goto out;
        }
    }
    if (got < 0) {
        /* a read error has no line of its own */
        if (strcmp(why, "read error") == 0)
            rc = cli_error(cmd, "csv:%s: read error", path);
        else
            rc = cli_error(cmd, "csv:%s line %lu: %s", path, r.lineno, why);
        goto out;
    }
    if (n_cols == 0 || n == 0) {
        rc = cli_error(cmd, "csv:%s: no samples (a header line, then one row per sample)", path);
        goto out;
    }
    in->kind = IN_CSV;
    in->samples = samples;
    in->n_samples = n;
    samples = NULL;
out:
    free(samples);
    csv_close(&r);
    return rc;
}

/* ---- input specification ---------------------------------------------------------------------- */

static int parse_input(const char *cmd, const char *spec, double ts, double quantum, input_t *in)
{
    char copy[512], *fields[4];
    int n, rc;
    memset(in, 0, sizeof *in);
    if (strncmp(spec, "csv:", 4) == 0) {
        if (spec[4] == '\0')
            return cli_error(cmd, "--input '%s': no file name (%s)", spec, input_syntax);
        return load_csv(cmd, spec + 4, ts, quantum, in);
    }
    if (strlen(spec) >= sizeof copy)
        return cli_error(cmd, "--input: too long (%s)", input_syntax);
    strcpy(copy, spec);
    n = split_colons(copy, fields, 3);
    if (strcmp(fields[0], "step") == 0 && (n == 2 || n == 3)) {
        in->kind = IN_STEP;
        if ((rc = parse_amplitude(cmd, spec, fields[1], quantum, &in->amp)) >= 0)
            return rc;
        if (n == 3) {
            double t_start;
            if (cli_parse_double(fields[2], &t_start) != 0 || t_start < 0)
                return cli_error(cmd, "--input '%s': T_START '%s' is not a number of seconds >= 0 (%s)", spec, fields[2], input_syntax);
            if (t_start / ts > (double)MAX_SAMPLES)
                return cli_error(cmd, "--input '%s': T_START '%s' is beyond the longest run (%llu samples)", spec, fields[2], MAX_SAMPLES);
            /* the first sample at or after T_START (1 ppm tolerance: 1.23/0.01 = 123.00000000000001) */
            in->k0 = (uint64_t)ceil(t_start / ts - 1e-6 * (t_start / ts > 1 ? t_start / ts : 1));
        }
        return -1;
    }
    if (strcmp(fields[0], "square") == 0 && n == 3) {
        double period;
        int64_t samples;
        in->kind = IN_SQUARE;
        if ((rc = parse_amplitude(cmd, spec, fields[1], quantum, &in->amp)) >= 0)
            return rc;
        if (cli_parse_double(fields[2], &period) != 0 || !(period > 0))
            return cli_error(cmd, "--input '%s': PERIOD '%s' is not a number of seconds > 0 (%s)", spec, fields[2], input_syntax);
        samples = whole_samples(period / 2, ts);
        if (samples < 1)
            return cli_error(cmd, "--input '%s': half the period (%g s) must be a whole number of samples of %g s", spec, period / 2, ts);
        in->half = (uint64_t)samples;
        return -1;
    }
    return cli_error(cmd, "--input '%s': %s", spec, input_syntax);
}

/* ---- the command ------------------------------------------------------------------------------- */

static const char description[] =
    "Runs an acceleration/deceleration filter of the moving-average-filter note on a test input, one row per sample\n"
    "(virtual time), through the same lib/ code as the MovingAverageFilter sketch:\n"
    "  ma   moving average, N = tau/Ts taps: y[k] = y[k-1] + (u[k-1] - u[k-1-N])/N (linear ramp)\n"
    "  ma2  two moving averages in series, tau then tau2 (S-curve), exact at the samples\n"
    "  exp  first order 1/(tau s + 1): y[k] = a y[k-1] + (1 - a) u[k-1], a = exp(-Ts/tau)\n"
    "tau and tau2 must be whole multiples of Ts (within 1 ppm) for every kind.\n"
    "Delay convention: u[k] is held from k*Ts to (k+1)*Ts; y[k] is the exact output at t = k*Ts, so it\n"
    "depends on u[k-1], u[k-2], ... only: a step at sample k0 first moves y at k0+1 and (ma) reaches\n"
    "its final value at exactly k0 + N, tau after the step.\n"
    "Inputs are quantised to --quantum (1 mV, as the sketch) and filtered in exact integers.\n"
    "--input:\n"
    "  step:AMPLITUDE[:T_START]  0 V before T_START seconds (default 0), AMPLITUDE volts from the first\n"
    "                            sample at or after it (the moving-average-filter note: step:5, the constant V_FC = 5 V)\n"
    "  square:AMPLITUDE:PERIOD   AMPLITUDE for the first half of each PERIOD (seconds), then 0 V;\n"
    "                            PERIOD/2 must be a whole number of samples\n"
    "  csv:FILE                  one sample per row after a header line: the column named u (volts),\n"
    "                            or the only column; a t_ms or k column must count consecutive samples.\n"
    "                            The sketch's stream (t_ms,u,y) and this command's output both work.\n"
    "Output: CSV k,t_s,u,y (t_s = k*Ts; u the quantised input and y the output, in volts), rows\n"
    "k = 0 .. floor(duration/Ts). --stream writes the sketch's serial lines instead: t_ms,u,y with\n"
    "t_ms = k*Ts in ms, u with 3 decimals, y rounded to 6 decimals (needs --quantum 0.001).\n"
    "--max-rows N (default 1000000): a run of more rows is refused before anything is written.";

int cmd_filter(int argc, char **argv)
{
    const char *cmd = argv[0];
    int kind = 0, stream = 0, seen_tau2 = 0, seen_duration = 0, rc;
    double tau = 9.0, tau2 = 3.0, ts = 0.01, duration = 20.0, quantum = 0.001;
    uint32_t max_rows = MAX_ROWS_DEFAULT;
    const char *input_spec = "step:5", *out_path = NULL;
    const cli_opt_t opts[] = {
        {"--kind", CLI_CHOICE, &kind, NULL, "filter kind (default ma)", "ma|ma2|exp", NULL},
        {"--tau", CLI_DOUBLE, &tau, "S", "time constant tau in s: ma window, ma2 first stage, exp lag (default 9)", NULL, NULL},
        {"--tau2", CLI_DOUBLE, &tau2, "S", "ma2 only: second stage's window in s (default 3)", NULL, &seen_tau2},
        {"--ts", CLI_DOUBLE, &ts, "S", "sample time Ts in s (default 0.01: 100 Hz)", NULL, NULL},
        {"--input", CLI_STRING, &input_spec, "SPEC", "step:AMPLITUDE[:T_START] | square:AMPLITUDE:PERIOD | csv:FILE (default step:5)", NULL, NULL},
        {"--duration", CLI_DOUBLE, &duration, "S", "simulated time in s (default 20; csv: the whole file)", NULL, &seen_duration},
        {"--quantum", CLI_DOUBLE, &quantum, "V", "input quantum in V (default 0.001, as the sketch)", NULL, NULL},
        {"--stream", CLI_FLAG, &stream, NULL, "write the MovingAverageFilter sketch's serial lines t_ms,u,y", NULL, NULL},
        {"-o", CLI_STRING, &out_path, "FILE", "write the CSV to FILE instead of stdout", NULL, NULL},
        {"--max-rows", CLI_UINT32, &max_rows, "N", "refuse a run of more than N rows, 1..4294967295 (default 1000000)",
         NULL, NULL},
    };
    const cli_spec_t spec = {"filter",
                             "[--kind ma|ma2|exp] [--tau S] [--tau2 S] [--ts S] [--input SPEC] [--duration S] [--quantum V] [--stream] [-o FILE]",
                             description, opts, sizeof opts / sizeof opts[0], 0};
    accdec_config_t cfg;
    accdec_filter_t filt;
    input_t in;
    int16_t *buf = NULL;
    uint16_t taps;
    uint32_t den;
    uint64_t k, last;
    double inv_q, y_scale;
    motion_status_t st;
    FILE *out;

    if ((rc = cli_parse(&spec, argc, argv, NULL, NULL)) >= 0)
        return rc;
    if (max_rows == 0)
        return cli_error(cmd, "--max-rows: 0 is not a bound: a table has at least 1 row (give 1..4294967295)");
    if (!(quantum > 0))
        return cli_error(cmd, "--quantum %g: %s", quantum, motion_status_text(MS_ERR_QUANTUM_NOT_POSITIVE));
    if (seen_tau2 && kind != ACCDEC_MA2)
        return cli_error(cmd, "--tau2 applies to --kind ma2 only");
    st = filt_taps(tau, ts, &taps);
    if (st != MS_OK)
        return cli_error(cmd, "--tau %.12g, --ts %.12g: %s%s", tau, ts, motion_status_text(st),
                         st == MS_ERR_TOO_MANY_TAPS ? " (at most 65535)" : "");
    if (kind == ACCDEC_MA2 && (st = filt_taps(tau2, ts, &taps)) != MS_OK)
        return cli_error(cmd, "--tau2 %.12g, --ts %.12g: %s%s", tau2, ts, motion_status_text(st),
                         st == MS_ERR_TOO_MANY_TAPS ? " (at most 65535)" : "");
    st = accdec_configure(&cfg, (accdec_kind_t)kind, tau, tau2, ts, FILT_MAX_TAPS);
    if (st != MS_OK)
        return cli_error(cmd, "--tau %.12g, --tau2 %.12g, --ts %.12g: %s (at most %u taps in all)", tau, tau2, ts,
                         motion_status_text(st), FILT_MAX_TAPS);
    if (stream && fabs(quantum - 0.001) > 1e-15)
        return cli_error(cmd, "--stream writes the sketch's millivolt stream: it needs --quantum 0.001");
    if (!(duration >= 0))
        return cli_error(cmd, "--duration %.12g: must be 0 s or more", duration);
    if ((rc = parse_input(cmd, input_spec, ts, quantum, &in)) >= 0)
        return rc;

    if (in.kind == IN_CSV && !seen_duration) {
        last = in.n_samples - 1;
    } else {
        double r = duration / ts;
        if (!(r < (double)MAX_SAMPLES)) {
            free(in.samples);
            return cli_error(cmd, "--duration %.12g s is more than %llu samples of %g s", duration, MAX_SAMPLES, ts);
        }
        last = (uint64_t)floor(r + 1e-9 * (r > 1 ? r : 1));
        if (in.kind == IN_CSV && last >= in.n_samples) {
            rc = cli_error(cmd, "--duration %.12g s needs %llu samples; %s holds %llu", duration,
                           (unsigned long long)last + 1, input_spec, (unsigned long long)in.n_samples);
            free(in.samples);
            return rc;
        }
    }
    if (last >= max_rows) { /* rows k = 0 .. last */
        free(in.samples);
        return cli_error(cmd, "the table would have %llu rows, more than --max-rows %lu: shorten --duration, or raise "
                              "--max-rows (one row per sample of %g s)",
                         (unsigned long long)last + 1, (unsigned long)max_rows, ts);
    }
    if (stream && (double)last * ts * 1000.0 > 4294967295.0) {
        free(in.samples);
        return cli_error(cmd, "--stream: t_ms would pass 2^32-1 ms (the sketch's counter); shorten --duration");
    }

    if (accdec_buffer_taps(&cfg) > 0) {
        buf = malloc(accdec_buffer_taps(&cfg) * sizeof *buf);
        if (buf == NULL) {
            free(in.samples);
            fprintf(stderr, "motionsim %s: out of memory\n", cmd);
            return CLI_EXIT_RUNTIME;
        }
    }
    st = accdec_start(&filt, &cfg, buf, accdec_buffer_taps(&cfg));
    if (st != MS_OK) { /* cannot happen after accdec_configure; kept as a guard */
        free(buf);
        free(in.samples);
        return cli_error(cmd, "%s", motion_status_text(st));
    }
    out = cli_open_output(cmd, out_path);
    if (out == NULL) {
        free(buf);
        free(in.samples);
        return CLI_EXIT_RUNTIME;
    }

    /* Volts from counts: divide by 1/q when that is a whole number (1000 for 1 mV), so 1234 counts
     * print as 1.234 and y = num / (den * 1000) is the correctly rounded quotient. */
    den = accdec_den(&cfg);
    inv_q = floor(1.0 / quantum + 0.5);
    if (fabs(1.0 / quantum - inv_q) > 1e-9 * inv_q || inv_q > 1e6)
        inv_q = 0;
    y_scale = inv_q > 0 ? (double)den * inv_q : 0;

    fputs(stream ? FSTREAM_HEADER "\n" : "k,t_s,u,y\n", out);
    for (k = 0; k <= last; k++) {
        int16_t u = input_at(&in, k);
        int64_t num = accdec_step(&filt, u);
        if (stream) {
            char line[FSTREAM_LINE_MAX + 1];
            uint32_t t_ms = (uint32_t)floor((double)k * ts * 1000.0 + 0.5);
            fstream_format(line, t_ms, u, accdec_milli_quanta(num, den));
            fputs(line, out);
            fputc('\n', out);
        } else {
            double row[4];
            row[0] = (double)k;
            row[1] = floor((double)k * ts * 1e9 + 0.5) / 1e9; /* k Ts, to the nanosecond */
            row[2] = inv_q > 0 ? u / inv_q : u * quantum;
            row[3] = inv_q > 0 ? (double)num / y_scale : (double)num * quantum / den;
            csv_row(out, row, 4);
        }
        if (ferror(out))
            break; /* cli_close_output reports it */
    }
    free(buf);
    free(in.samples);
    return cli_close_output(cmd, out, out_path);
}
