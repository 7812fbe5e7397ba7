/* sim/motionsim.c - the host simulator: runs the same lib/ code as the Mega sketches and writes
 * CSV. This file only dispatches to the subcommands (sim/cmd_*.c). Time is virtual everywhere:
 * nothing sleeps, a 2000-step move or a 60 s servo run takes milliseconds. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "commands.h"

#define MOTIONSIM_VERSION "0.1.0"

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command_t;

static const command_t commands[] = {
    {"ramp", cmd_ramp, "stepper ramp step table (simplistic, Leib, exact, sigmoid S-curve); --compare"},
    {"filter", cmd_filter, "acceleration/deceleration filter response (moving average, two-stage, exponential)"},
    {"servo", cmd_servo, "closed-loop position control (P or PID) of the DC motor + encoder plant"},
    {"pid-replay", cmd_pid_replay, "replay a PID_v1 reference vector through our controller"},
    {"move", cmd_move, "coordinated move of the X, Y and Z stepper axes: every axis's steps and the path error"},
};
#define N_COMMANDS (sizeof commands / sizeof commands[0])

static void usage(FILE *f)
{
    size_t i;
    fprintf(f, "usage: motionsim <command> [options]\n\n"
               "Host simulator for the Mega 2560 motion-control firmware: the same lib/ code,\n"
               "virtual time, CSV on stdout (or -o FILE).\n\ncommands:\n");
    for (i = 0; i < N_COMMANDS; i++)
        fprintf(f, "  %-12s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n'motionsim <command> --help' lists a command's options.\n");
}

int main(int argc, char **argv)
{
    size_t i;
    if (argc < 2) {
        /* one line, as every other usage error */
        fprintf(stderr, "motionsim: the command is missing: usage: motionsim <command> [options] (commands: ramp, filter, "
                        "servo, pid-replay, move; try 'motionsim --help')\n");
        return CLI_EXIT_USAGE;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        usage(stdout);
        return CLI_EXIT_OK;
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("motionsim %s\n", MOTIONSIM_VERSION);
        return CLI_EXIT_OK;
    }
    for (i = 0; i < N_COMMANDS; i++)
        if (strcmp(argv[1], commands[i].name) == 0)
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "motionsim: unknown command '%s' (commands: ramp, filter, servo, pid-replay, move; try 'motionsim --help')\n", argv[1]);
    return CLI_EXIT_USAGE;
}
