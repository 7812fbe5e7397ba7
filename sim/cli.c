/* sim/cli.c - strict option parsing for motionsim subcommands (see cli.h). */
#include "cli.h"

#include "text_parse.h"

#include <errno.h>
#include <float.h>
#include <getopt.h>
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

/* Options that getopt_long(3) returns: a table entry k named "--name" comes back as OPT_LONG + k, one
 * named "-x" as the character x; help as 'h'. */
#define OPT_LONG 256

/* The name as the user typed it in `elem` (up to '=' for a long option), for messages. */
static int typed_len(const char *elem)
{
    const char *eq = strncmp(elem, "--", 2) == 0 ? strchr(elem, '=') : NULL;
    return eq != NULL ? (int)(eq - elem) : (int)strlen(elem);
}

/* Stores the value of option o (a kind with a value) or returns the usage exit code. */
static int store_value(const cli_spec_t *spec, const cli_opt_t *o, const char *value)
{
    switch (o->kind) {
    case CLI_DOUBLE:
        switch (cli_parse_double(value, (double *)o->dest)) {
        case 0:
            return -1;
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
    case CLI_INT32:
        if (cli_parse_int32(value, (int32_t *)o->dest) != 0)
            return cli_error(spec->cmd, "%s: '%s' is not a whole number in -2147483648..2147483647", o->name, value);
        return -1;
    case CLI_UINT32:
        if (cli_parse_uint32(value, (uint32_t *)o->dest) != 0)
            return cli_error(spec->cmd, "%s: '%s' is not a whole number in 0..4294967295", o->name, value);
        return -1;
    case CLI_STRING:
        if (value[0] == '\0')
            return cli_error(spec->cmd, "%s: the value is empty", o->name);
        *(const char **)o->dest = value;
        return -1;
    case CLI_CHOICE: {
        int idx = choice_index(o->choices, value);
        if (idx < 0)
            return cli_error(spec->cmd, "%s: '%s' is not one of %s", o->name, value, o->choices);
        *(int *)o->dest = idx;
        return -1;
    }
    default:
        return -1;
    }
}

/* The table as getopt_long(3) wants it. Options are processed in order (optstring "-:": bare arguments
 * come back as 1 where they stand, a missing value as ':'), "--" ends the options, and only whole
 * option names are accepted: getopt_long's unique-prefix abbreviations ("--acc" for "--accel") are
 * refused, so that a script keeps its meaning when an option is added. Every short option here takes
 * a value or ends the parse (-h), so each call starts at the beginning of an argument. */
int cli_parse(const cli_spec_t *spec, int argc, char **argv, const char **positional, size_t *n_positional)
{
    struct option longopts[CLI_MAX_OPTS + 2];
    char optstring[2 * CLI_MAX_OPTS + 8];
    unsigned char given[CLI_MAX_OPTS];
    size_t npos = 0, k, nl = 0, ns = 0;
    int c;
    if (spec->n_opts > CLI_MAX_OPTS)
        return cli_error(spec->cmd, "internal error: more than %d options", CLI_MAX_OPTS);
    memset(given, 0, sizeof given);
    optstring[ns++] = '-';
    optstring[ns++] = ':';
    optstring[ns++] = 'h';
    for (k = 0; k < spec->n_opts; k++) {
        const cli_opt_t *o = &spec->opts[k];
        int has_arg = o->kind == CLI_FLAG ? no_argument : required_argument;
        if (strncmp(o->name, "--", 2) == 0) {
            longopts[nl].name = o->name + 2;
            longopts[nl].has_arg = has_arg;
            longopts[nl].flag = NULL;
            longopts[nl].val = OPT_LONG + (int)k;
            nl++;
        } else {
            optstring[ns++] = o->name[1];
            if (has_arg == required_argument)
                optstring[ns++] = ':';
        }
    }
    optstring[ns] = '\0';
    longopts[nl].name = "help";
    longopts[nl].has_arg = no_argument;
    longopts[nl].flag = NULL;
    longopts[nl].val = 'h';
    nl++;
    memset(&longopts[nl], 0, sizeof longopts[nl]);
    opterr = 0; /* the messages are ours, one line each */
    optind = 0; /* glibc: start afresh */
    for (;;) {
        int at = optind < 1 ? 1 : optind; /* the argument this call reads */
        const char *elem = at < argc ? argv[at] : "";
        const cli_opt_t *o = NULL;
        int rc, id;
        c = getopt_long(argc, argv, optstring, longopts, NULL);
        if (c == -1)
            break;
        if (c == 1) { /* a bare argument */
            if (npos >= spec->max_positional)
                return cli_error(spec->cmd, "unexpected argument '%s' (try 'motionsim %s --help')", optarg, spec->cmd);
            if (positional != NULL)
                positional[npos] = optarg;
            npos++;
            continue;
        }
        id = (c == '?' || c == ':') ? optopt : c;
        if (c == '?' && id == 0) /* a long option not in the table (or a prefix of several) */
            return cli_error(spec->cmd, "unknown option '%.*s' (try 'motionsim %s --help')", typed_len(elem), elem,
                             spec->cmd);
        if (c == '?' && id < OPT_LONG && id != 'h') /* a short option not in the table */
            return cli_error(spec->cmd, "unknown option '-%c' (try 'motionsim %s --help')", id, spec->cmd);
        if (id >= OPT_LONG)
            o = &spec->opts[id - OPT_LONG];
        else
            for (k = 0; k < spec->n_opts; k++)
                if (spec->opts[k].name[1] == id && spec->opts[k].name[2] == '\0')
                    o = &spec->opts[k];
        /* a long option as typed must be the whole name */
        if (strncmp(elem, "--", 2) == 0) {
            const char *want = o != NULL ? o->name : "--help";
            int n = typed_len(elem);
            if ((size_t)n != strlen(want) || strncmp(elem, want, (size_t)n) != 0)
                return cli_error(spec->cmd, "option '%.*s' is abbreviated: write %s (abbreviations are not accepted)", n,
                                 elem, want);
        }
        if (id == 'h') {
            if (c == '?')
                return cli_error(spec->cmd, "option --help takes no value");
            print_help(spec);
            return CLI_EXIT_OK;
        }
        if (o == NULL) /* cannot happen: getopt_long returns only what the table holds */
            return cli_error(spec->cmd, "unknown option '%s' (try 'motionsim %s --help')", elem, spec->cmd);
        k = (size_t)(o - spec->opts);
        /* a second value would silently replace the first: refuse it, as a typo usually */
        if (given[k])
            return cli_error(spec->cmd, "%s given twice", o->name);
        given[k] = 1;
        if (c == ':')
            return cli_error(spec->cmd, "option %s needs a value (%s)", o->name, kind_metavar(o));
        if (c == '?')
            return cli_error(spec->cmd, "option %s takes no value", o->name);
        if (o->kind == CLI_FLAG) {
            *(int *)o->dest = 1;
        } else {
            const char *value = optarg;
            /* "-o=FILE" as "-o FILE" (the '=' is not part of the value, as for "--name=VALUE") */
            if (o->name[1] != '-' && value == elem + 2 && value[0] == '=')
                value++;
            if ((rc = store_value(spec, o, value)) >= 0)
                return rc;
        }
        if (o->seen != NULL)
            *o->seen = 1;
    }
    /* after "--": the rest are bare arguments */
    for (; optind < argc; optind++) {
        if (npos >= spec->max_positional)
            return cli_error(spec->cmd, "unexpected argument '%s' (try 'motionsim %s --help')", argv[optind], spec->cmd);
        if (positional != NULL)
            positional[npos] = argv[optind];
        npos++;
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
