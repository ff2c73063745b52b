/* The sub-commands of the vorocrust executable. Each takes the arguments
 * after the sub-command name (argv[0] is the sub-command) and returns the
 * process exit code. */
#ifndef VC_CLI_COMMANDS_H
#define VC_CLI_COMMANDS_H

int vc_cmd_info(int argc, char **argv);
int vc_cmd_voronoi(int argc, char **argv);
int vc_cmd_mesh(int argc, char **argv);
int vc_cmd_quality(int argc, char **argv);
int vc_cmd_compare(int argc, char **argv);

#endif
