/* sim/cli.c - strict option parsing for motionsim subcommands (see cli.h). */
#include "cli.h"

#include <errno.h>
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

int cli_parse_double(const char *s, double *out)
{
    char *end = NULL;
    double v;
    if (s == NULL || *s == '\0' || strchr(" \t\n", s[0]) != NULL || strpbrk(s, "xX") != NULL)
        return -1; /* no leading space, no hexadecimal (strtod would take 0x5) */
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

static int parse_integer(const char *s, long long lo, long long hi, long long *out)
{
    char *end = NULL;
    long long v;
    if (s == NULL || *s == '\0' || strchr(" \t\n", s[0]) != NULL)
        return -1;
    errno = 0;
    v = strtoll(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

int cli_parse_int32(const char *s, int32_t *out)
{
    long long v;
    if (parse_integer(s, INT32_MIN, INT32_MAX, &v) != 0)
        return -1;
    *out = (int32_t)v;
    return 0;
}

int cli_parse_uint32(const char *s, uint32_t *out)
{
    long long v;
    if (s != NULL && s[0] == '-')
        return -1;
    if (parse_integer(s, 0, UINT32_MAX, &v) != 0)
        return -1;
    *out = (uint32_t)v;
    return 0;
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

static void print_help(const cli_spec_t *spec)
{
    size_t i;
    printf("usage: motionsim %s %s\n", spec->cmd, spec->synopsis);
    if (spec->description != NULL)
        printf("\n%s\n", spec->description);
    printf("\noptions:\n");
    for (i = 0; i < spec->n_opts; i++) {
        const cli_opt_t *o = &spec->opts[i];
        char left[96];
        if (o->kind == CLI_FLAG)
            snprintf(left, sizeof left, "%s", o->name);
        else
            snprintf(left, sizeof left, "%s %s", o->name, kind_metavar(o));
        printf("  %-30s %s\n", left, o->help != NULL ? o->help : "");
    }
    printf("  %-30s %s\n", "-h, --help", "show this help and exit");
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
            if (cli_parse_double(value, (double *)o->dest) != 0)
                return cli_error(spec->cmd, "%s: '%s' is not a finite number", o->name, value);
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
    int bad = ferror(f);
    if (f == stdout)
        bad |= fflush(f) != 0;
    else
        bad |= fclose(f) != 0;
    if (bad) {
        fprintf(stderr, "motionsim %s: writing '%s' failed\n", cmd, path != NULL ? path : "stdout");
        return CLI_EXIT_RUNTIME;
    }
    return CLI_EXIT_OK;
}
