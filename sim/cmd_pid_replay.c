/* sim/cmd_pid_replay.c - placeholder until this subcommand lands. */
#include "cli.h"
#include "commands.h"

int cmd_pid_replay(int argc, char **argv)
{
    (void)argc;
    return cli_error(argv[0], "not implemented yet");
}
