/* Small helpers the sub-commands share. libc only: vc-tetgen (apps/tetgen)
 * compiles cli_util.c too, so it must not need the vorocrust library or
 * anything else. */
#ifndef VC_CLI_UTIL_H
#define VC_CLI_UTIL_H

/* Monotonic clock in seconds. */
double vc_cli_now(void);

/* A finite number filling the whole string; 0 on success. */
int vc_cli_parse_double(const char *s, double *out);

/* A base-10 integer in [lo, hi] filling the whole string; 0 on success. */
int vc_cli_parse_int(const char *s, long lo, long hi, long *out);

/* Whether the directory that would hold path exists and is writable. */
int vc_cli_directory_writable(const char *path);

/* Refuses (one line on stderr, returns the exit code 1) an output file
 * whose directory is missing or not writable, or that is a directory;
 * returns 0 when it can be written. */
int vc_cli_check_output_file(const char *path);

/* The same, with the message starting "prog: " (vc_cli_check_output_file
 * is this with "vorocrust"). */
int vc_cli_check_output_file_as(const char *prog, const char *path);

/* An argument of the command `command` (such as "vorocrust compare") that
 * no option took: an unknown option (a "-" and more), or a positional one
 * when *positional is already set, is refused (one line on stderr starting
 * "prog: "; returns the exit code 2); otherwise it becomes *positional and
 * 0 is returned. */
int vc_cli_positional(const char *prog, const char *command, const char *arg,
                      const char **positional);

/* Refuses a command line that lacks what (such as "the INPUT surface"):
 * "prog: missing WHAT (see 'COMMAND --help')" on stderr; returns the exit
 * code 2. */
int vc_cli_missing(const char *prog, const char *command, const char *what);

/* The same for an OpenFOAM case directory: an existing writable directory
 * (its polyMesh is replaced) or a new one in a writable directory, never a
 * file. Returns 0, or the exit code (2 for an empty name, 1 otherwise). */
int vc_cli_check_case_dir(const char *path);

#endif
