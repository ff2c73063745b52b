/* Small helpers the sub-commands share. libc, and the tracker of the
 * library's temporary files (io/tmpfile.h) only: vc-tetgen (apps/tetgen)
 * compiles cli_util.c too, so it must need nothing else of the CLI. */
#ifndef VC_CLI_UTIL_H
#define VC_CLI_UTIL_H

#include <signal.h>
#include <sys/types.h>

/* Monotonic clock in seconds. */
double vc_cli_now(void);

/* This process's peak resident memory in MiB: VmHWM of /proc/self/status,
 * which counts from the exec (getrusage's ru_maxrss keeps the high-water
 * mark of the process before its exec: run from a Python script holding
 * VTK, a 18 MiB mesh reported 125), else ru_maxrss. */
double vc_cli_peak_mib(void);

/* A finite number filling the whole string; 0 on success. */
int vc_cli_parse_double(const char *s, double *out);

/* A base-10 integer in [lo, hi] filling the whole string; 0 on success. */
int vc_cli_parse_int(const char *s, long lo, long hi, long *out);

/* Whether the directory that would hold path exists and is writable. */
int vc_cli_directory_writable(const char *path);

/* Refuses (one line on stderr, returns the exit code 1) an output file
 * that exists and is not a regular file (a character or block device, a
 * FIFO, a socket, a directory; a symbolic link is followed: "PATH: is a
 * character device, not a regular file: refusing to replace it"), or whose
 * directory is missing or not writable; returns 0 when it can be written. */
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

/* Repeated options: each command's loop calls vc_cli_repeated on every
 * argument it reads as an option or a positional (not on option values);
 * an option given a second time ("-o" and "--output" are the same) is
 * refused: "prog: OPT given twice (see 'COMMAND --help')", exit code 2
 * returned; otherwise 0. */
#define VC_CLI_SEEN_MAX 64
typedef struct vc_cli_seen {
    const char *names[VC_CLI_SEEN_MAX];
    int n;
} vc_cli_seen;

int vc_cli_repeated(vc_cli_seen *seen, const char *prog, const char *command, const char *arg);

/* Outputs: all or none. vc_cli_outputs_begin (once, before the first
 * output is written) registers a tracker of the library's temporary files
 * (vc_tmpfile_track) and installs handlers of SIGINT, SIGTERM, SIGHUP and
 * SIGXFSZ (a signal ignored at start stays ignored). On such a signal the
 * handler removes (unlink, rmdir, from paths recorded beforehand: no
 * allocation) every temporary file and directory and every output this run
 * has committed, then dies by the same signal (default action, raised
 * again). vc_cli_outputs_remove does the same removal without dying (a
 * write failed: call it before returning the error); vc_cli_outputs_keep,
 * after the last output is committed, makes the committed outputs
 * permanent (a later signal leaves them). */
void vc_cli_outputs_begin(void);
void vc_cli_outputs_remove(void);
void vc_cli_outputs_keep(void);
/* Two more kinds of output the registry handles: a directory this run made
 * (removed after the outputs, only when empty), and an existing directory
 * the run replaced (an OpenFOAM case's polyMesh): put back on a signal or
 * vc_cli_outputs_remove, removed by vc_cli_outputs_keep. The handlers run
 * in the thread that called vc_cli_outputs_begin (a signal another thread
 * receives is sent on to it), so that the library can block the signals
 * across a swap of directories (vc_tmpdir_replace).
 *
 * Test hook: with VC_TEST_SIGNAL_AT="EVENT:SUFFIX:SIGNAL" in the
 * environment (EVENT one of add, mkdir, renaming, backup, committed), the
 * program raises SIGNAL (a number) in itself when the library reports that
 * event for an output path ending in SUFFIX: a signal at a given moment of
 * the writing, for the tests. */

/* Child processes (vorocrust compare): a signal handled by the registry is
 * first sent on to the running child, which is waited for (up to 5 s, then
 * SIGKILL), so that it stops writing before its directory is removed.
 * vc_cli_block_signals blocks the handled signals in this thread (saved
 * receives the mask to restore with vc_cli_restore_signals): around the
 * fork and the recording of the child (vc_cli_child_started), and around
 * its reaping (vc_cli_child_ended), so that no handler sees a child that
 * is not recorded, or a recorded pid already reaped (and reusable). In the
 * child, vc_cli_child_exec_prepare restores the defaults before exec. */
void vc_cli_block_signals(sigset_t *saved);
void vc_cli_restore_signals(const sigset_t *saved);
void vc_cli_child_started(pid_t pid);
void vc_cli_child_ended(void);
void vc_cli_child_exec_prepare(const sigset_t *saved);

/* A temporary directory of the program's own (not the library's), removed
 * with its contents by a signal or vc_cli_outputs_remove: the slot, or -1
 * when it cannot be recorded. vc_cli_untrack(slot) forgets it (the program
 * removed it itself). */
int vc_cli_track_temp_dir(const char *dir);
void vc_cli_untrack(int slot);

#endif
