/* Running another program as a child process and measuring what it cost
 * (vorocrust compare runs both meshers this way). */
#ifndef VC_CLI_CHILD_PROCESS_H
#define VC_CLI_CHILD_PROCESS_H

#include <stddef.h>

typedef struct vc_child_result {
    int started;          /* 0: fork or exec failed (see message) */
    int exit_code;        /* the child's exit status, or -1 if a signal ended it */
    int signal;           /* the signal that ended it, 0 if none */
    double wall_seconds;  /* from fork to the end of the child */
    double cpu_seconds;   /* user + system time of the child */
    double peak_mib;      /* its peak resident memory (ru_maxrss) */
    char message[512];    /* the last non-empty line the child wrote, or why it did not run */
} vc_child_result;

/* Runs argv[0] (a path) with the arguments argv (NULL-terminated), its
 * stdout and stderr both appended to log_path (created or truncated), and
 * waits for it (wait4). Returns 0 when the child ran and exited with 0;
 * otherwise non-zero, with the reason in res->message. */
int vc_child_run(char *const argv[], const char *log_path, vc_child_result *res);

/* The absolute path of the running executable (/proc/self/exe) in buf;
 * returns 0, or -1 when it cannot be found or does not fit. */
int vc_self_executable(char *buf, size_t size);

#endif
