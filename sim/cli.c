/* sim/cli.c - strict option parsing for motionsim subcommands (see cli.h). */
#include "cli.h"

#include "text_parse.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

int cli_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "motionsim %s: ", cmd);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    return CLI_EXIT_USAGE;
}

/* The numbers are lib's text_parse (the sketches' parser): one parser for the board and the host. */
int cli_parse_double(const char *s, double *out)
{
    if (s == NULL)
        return CLI_NUM_MALFORMED;
    switch (text_scan_real(s, out)) {
    case MS_OK: return 0;
    case MS_ERR_OUT_OF_RANGE: return CLI_NUM_OVERFLOW;
    case MS_ERR_UNDERFLOW: return CLI_NUM_UNDERFLOW;
    default: return CLI_NUM_MALFORMED;
    }
}

int cli_float_range(double x)
{
    double m = fabs(x);
    if (m > FLT_MAX)
        return CLI_NUM_OVERFLOW;
    if (m != 0.0 && m < FLT_MIN)
        return CLI_NUM_UNDERFLOW;
    return 0;
}

int cli_parse_int32(const char *s, int32_t *out)
{
    return s != NULL && text_parse_int32(s, INT32_MIN, INT32_MAX, out) == MS_OK ? 0 : -1;
}

int cli_parse_uint32(const char *s, uint32_t *out)
{
    return s != NULL && text_parse_uint32(s, 0, UINT32_MAX, out) == MS_OK ? 0 : -1;
}

static const char *kind_metavar(const cli_opt_t *o)
{
    if (o->metavar != NULL)
        return o->metavar;
    switch (o->kind) {
    case CLI_DOUBLE: return "X";
    case CLI_INT32: return "N";
    case CLI_UINT32: return "N";
    case CLI_STRING: return "TEXT";
    case CLI_CHOICE: return o->choices;
    default: return "";
    }
}

/* Column where option descriptions start ("  " + option + at least two blanks). An option whose
 * name and value are wider than HELP_NAME_WIDTH gets its own line and the description goes on the
 * next one, at the same column, so a long choice list never runs into its text. */
#define HELP_NAME_WIDTH 30

static void print_option_help(const char *left, const char *help)
{
    if (strlen(left) > HELP_NAME_WIDTH)
        printf("  %s\n  %-*s  %s\n", left, HELP_NAME_WIDTH, "", help);
    else
        printf("  %-*s  %s\n", HELP_NAME_WIDTH, left, help);
}

static void print_help(const cli_spec_t *spec)
{
    size_t i;
    printf("usage: motionsim %s %s\n", spec->cmd, spec->synopsis);
    if (spec->description != NULL)
        printf("\n%s\n", spec->description);
    printf("\noptions:\n");
    for (i = 0; i < spec->n_opts; i++) {
        const cli_opt_t *o = &spec->opts[i];
        char left[128];
        if (o->kind == CLI_FLAG)
            snprintf(left, sizeof left, "%s", o->name);
        else
            snprintf(left, sizeof left, "%s %s", o->name, kind_metavar(o));
        print_option_help(left, o->help != NULL ? o->help : "");
    }
    print_option_help("-h, --help", "show this help and exit");
}

/* Finds the index of `value` in a '|'-separated list, or -1. */
static int choice_index(const char *choices, const char *value)
{
    int idx = 0;
    const char *p = choices;
    size_t n = strlen(value);
    while (p != NULL && *p != '\0') {
        const char *bar = strchr(p, '|');
        size_t len = bar != NULL ? (size_t)(bar - p) : strlen(p);
        if (len == n && strncmp(p, value, n) == 0)
            return idx;
        idx++;
        p = bar != NULL ? bar + 1 : NULL;
    }
    return -1;
}

int cli_parse(const cli_spec_t *spec, int argc, char **argv, const char **positional, size_t *n_positional)
{
    int i;
    size_t npos = 0;
    unsigned char given[CLI_MAX_OPTS];
    if (spec->n_opts > CLI_MAX_OPTS)
        return cli_error(spec->cmd, "internal error: more than %d options", CLI_MAX_OPTS);
    memset(given, 0, sizeof given);
    for (i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = NULL;
        const cli_opt_t *o = NULL;
        size_t k, name_len;
        const char *eq;
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            print_help(spec);
            return CLI_EXIT_OK;
        }
        if (arg[0] != '-' || strcmp(arg, "-") == 0 || (arg[1] >= '0' && arg[1] <= '9')) {
            if (npos >= spec->max_positional)
                return cli_error(spec->cmd, "unexpected argument '%s' (try 'motionsim %s --help')", arg, spec->cmd);
            if (positional != NULL)
                positional[npos] = arg;
            npos++;
            continue;
        }
        eq = strchr(arg, '=');
        name_len = eq != NULL ? (size_t)(eq - arg) : strlen(arg);
        for (k = 0; k < spec->n_opts; k++) {
            if (strlen(spec->opts[k].name) == name_len && strncmp(spec->opts[k].name, arg, name_len) == 0) {
                o = &spec->opts[k];
                break;
            }
        }
        if (o == NULL)
            return cli_error(spec->cmd, "unknown option '%.*s' (try 'motionsim %s --help')", (int)name_len, arg, spec->cmd);
        /* a second value would silently replace the first: refuse it, as a typo usually */
        if (given[k])
            return cli_error(spec->cmd, "%s given twice", o->name);
        given[k] = 1;
        if (o->kind == CLI_FLAG) {
            if (eq != NULL)
                return cli_error(spec->cmd, "option %s takes no value", o->name);
            *(int *)o->dest = 1;
            if (o->seen != NULL)
                *o->seen = 1;
            continue;
        }
        if (eq != NULL) {
            value = eq + 1;
        } else {
            if (i + 1 >= argc)
                return cli_error(spec->cmd, "option %s needs a value (%s)", o->name, kind_metavar(o));
            value = argv[++i];
        }
        switch (o->kind) {
        case CLI_DOUBLE:
            switch (cli_parse_double(value, (double *)o->dest)) {
            case 0:
                break;
            case CLI_NUM_OVERFLOW:
                return cli_error(spec->cmd, "%s: '%s' is out of range: it overflows a double (magnitude above 1.8e308)",
                                 o->name, value);
            case CLI_NUM_UNDERFLOW:
                return cli_error(spec->cmd,
                                 "%s: '%s' is out of range: it underflows a double (nonzero magnitude below 2.2e-308)",
                                 o->name, value);
            default:
                return cli_error(spec->cmd, "%s: '%s' is not a finite number", o->name, value);
            }
            break;
        case CLI_INT32:
            if (cli_parse_int32(value, (int32_t *)o->dest) != 0)
                return cli_error(spec->cmd, "%s: '%s' is not a whole number in -2147483648..2147483647", o->name, value);
            break;
        case CLI_UINT32:
            if (cli_parse_uint32(value, (uint32_t *)o->dest) != 0)
                return cli_error(spec->cmd, "%s: '%s' is not a whole number in 0..4294967295", o->name, value);
            break;
        case CLI_STRING:
            if (value[0] == '\0')
                return cli_error(spec->cmd, "%s: the value is empty", o->name);
            *(const char **)o->dest = value;
            break;
        case CLI_CHOICE: {
            int idx = choice_index(o->choices, value);
            if (idx < 0)
                return cli_error(spec->cmd, "%s: '%s' is not one of %s", o->name, value, o->choices);
            *(int *)o->dest = idx;
            break;
        }
        default:
            break;
        }
        if (o->seen != NULL)
            *o->seen = 1;
    }
    if (n_positional != NULL)
        *n_positional = npos;
    return -1;
}

FILE *cli_open_output(const char *cmd, const char *path)
{
    FILE *f;
    if (path == NULL || strcmp(path, "-") == 0)
        return stdout;
    f = fopen(path, "w");
    if (f == NULL)
        fprintf(stderr, "motionsim %s: cannot write '%s': %s\n", cmd, path, strerror(errno));
    return f;
}

int cli_close_output(const char *cmd, FILE *f, const char *path)
{
    int bad = ferror(f), closed_bad, err;
    errno = 0;
    if (f == stdout)
        closed_bad = fflush(f) != 0;
    else
        closed_bad = fclose(f) != 0;
    err = errno;
    if (bad || closed_bad) {
        /* the reason is known when flushing the rest failed too (the usual case: a full disk) */
        if (closed_bad && err != 0)
            fprintf(stderr, "motionsim %s: writing '%s' failed: %s\n", cmd, path != NULL ? path : "stdout",
                    strerror(err));
        else
            fprintf(stderr, "motionsim %s: writing '%s' failed\n", cmd, path != NULL ? path : "stdout");
        return CLI_EXIT_RUNTIME;
    }
    return CLI_EXIT_OK;
}
