/* sim/commands.h - the motionsim subcommands, one source file each (sim/cmd_<name>.c).
 * Each takes argv with argv[0] = the subcommand name and returns an exit code (see cli.h). */
#ifndef MOTIONSIM_COMMANDS_H
#define MOTIONSIM_COMMANDS_H

int cmd_ramp(int argc, char **argv);       /* stepper ramps: step tables and --compare */
int cmd_ramp_smooth(int argc, char **argv); /* ramp --algo smooth (sim/cmd_smooth.c) */
int cmd_ramp_wants_smooth(int argc, char **argv); /* argv selects --algo smooth */
int cmd_filter(int argc, char **argv);     /* acc/dec filters: moving average, two-stage, exponential */
int cmd_servo(int argc, char **argv);      /* P / PID position loop against the DC-motor plant */
int cmd_pid_replay(int argc, char **argv); /* replay a PID_v1 reference vector */
int cmd_move(int argc, char **argv);       /* coordinated move of the X, Y and Z axes */

#endif
