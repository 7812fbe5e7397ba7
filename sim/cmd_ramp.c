/* sim/cmd_ramp.c - placeholder until this subcommand lands. */
#include "cli.h"
#include "commands.h"

int cmd_ramp(int argc, char **argv)
{
    (void)argc;
    return cli_error(argv[0], "not implemented yet");
}
