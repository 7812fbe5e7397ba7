/* sim/cli.h - command-line parsing shared by every motionsim subcommand.
 *
 * A subcommand describes its options in a table of cli_opt_t and calls cli_parse(). Numbers are
 * parsed strictly (the whole argument must be a finite decimal number in range; "1e3" is accepted
 * for doubles, "12abc", "", "0x5", "nan" and "inf" are not, nor a double that overflows or
 * underflows, e.g. 1e400 or 1e-320). Each option may be given once ("--kp given twice").
 * The parsing is getopt_long(3)'s, in order, with these choices: whole option names only (a unique
 * prefix such as "--acc" is refused, naming --accel), a value may start with '-' ("--v0 -5"),
 * "--" ends the options, and "-o=FILE" means "-o FILE".
 * Errors print one line
 *   motionsim <cmd>: <what is wrong> (try 'motionsim <cmd> --help')
 * on stderr. Exit codes used by all of motionsim:
 *   0 success, 1 runtime failure (e.g. a file cannot be written), 2 bad input (usage or parameters).
 */
#ifndef MOTIONSIM_CLI_H
#define MOTIONSIM_CLI_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define CLI_EXIT_OK 0
#define CLI_EXIT_RUNTIME 1
#define CLI_EXIT_USAGE 2

/* Results of the number parsers besides 0 (success). */
#define CLI_NUM_MALFORMED (-1) /* not a whole decimal number of the right kind, nan, inf */
#define CLI_NUM_OVERFLOW (-2)  /* magnitude too large for the type */
#define CLI_NUM_UNDERFLOW (-3) /* nonzero but too close to 0 for the type (normal range) */

/* Options one subcommand may have (cli_parse refuses a table with more). */
#define CLI_MAX_OPTS 64

typedef enum {
    CLI_FLAG,    /* no value; dest is int*, set to 1 */
    CLI_DOUBLE,  /* dest is double* */
    CLI_INT32,   /* dest is int32_t*, full signed 32-bit range */
    CLI_UINT32,  /* dest is uint32_t* */
    CLI_STRING,  /* dest is const char** (points into argv) */
    CLI_CHOICE   /* dest is int*: index of the value in the '|'-separated list in `choices` */
} cli_kind_t;

typedef struct {
    const char *name;    /* long option including dashes, e.g. "--v0", or a short one with a value, e.g. "-o" */
    cli_kind_t kind;
    void *dest;
    const char *metavar; /* shown in --help, e.g. "STEPS" */
    const char *help;    /* one line, with units and default */
    const char *choices; /* CLI_CHOICE only: "simplistic|leib|exact|sigmoid" */
    int *seen;           /* optional: set to 1 when the option was given */
} cli_opt_t;

typedef struct {
    const char *cmd;        /* subcommand name, for messages */
    const char *synopsis;   /* one line after "usage: motionsim <cmd> " */
    const char *description;/* a short paragraph for --help */
    const cli_opt_t *opts;
    size_t n_opts;
    size_t max_positional;  /* how many bare arguments are accepted */
} cli_spec_t;

/* Parses argv (argv[0] is the subcommand name). Positional arguments are stored in
 * positional[0..*n_positional). Returns -1 on success, or an exit code the caller should return
 * at once: CLI_EXIT_OK after printing --help, CLI_EXIT_USAGE after printing a one-line error. */
int cli_parse(const cli_spec_t *spec, int argc, char **argv, const char **positional, size_t *n_positional);

/* Prints "motionsim <cmd>: <message>" (printf-style) on stderr and returns CLI_EXIT_USAGE. */
int cli_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Strict number parsing used by cli_parse (exposed for values inside other arguments,
 * e.g. "step:5"). Return 0 on success, else non-zero: cli_parse_double gives CLI_NUM_MALFORMED,
 * CLI_NUM_OVERFLOW or CLI_NUM_UNDERFLOW; the integer parsers -1 if malformed or out of range
 * (decimal only: "0x5" is malformed). *out is written only on success. */
int cli_parse_double(const char *s, double *out);
int cli_parse_int32(const char *s, int32_t *out);
int cli_parse_uint32(const char *s, uint32_t *out);

/* Whether a double survives conversion to float (values computed in float, as on the Mega):
 * 0 if it does (0 included), CLI_NUM_OVERFLOW above FLT_MAX (3.4e38), CLI_NUM_UNDERFLOW for a
 * nonzero magnitude below FLT_MIN (1.2e-38). */
int cli_float_range(double x);

/* Opens the output stream: stdout when path is NULL or "-", else the file (error printed,
 * NULL returned, on failure). cli_close_output() returns CLI_EXIT_RUNTIME if writing failed, after
 * one line on stderr. A loop writing many rows should stop at the first error: test ferror(f)
 * as it goes (a write error is only seen when stdio flushes its buffer) and break out, then
 * call cli_close_output(), which reports it. */
FILE *cli_open_output(const char *cmd, const char *path);
int cli_close_output(const char *cmd, FILE *f, const char *path);

#endif
