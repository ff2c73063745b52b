/* Child processes for vorocrust compare: fork, exec, wait4 for the rusage
 * (CPU time and peak memory belong to the child alone), the child's
 * output kept in a log file whose last line explains a failure. The
 * running child is recorded in the output registry (cli_util.h), so that a
 * signal that stops compare stops the child first. */
#define _DEFAULT_SOURCE /* wait4 and struct rusage */
#include "child_process.h"
#include "cli_util.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The last non-empty line of the file (its last 8 KiB are enough) into
 * buf; buf is empty when there is none. */
static void last_line(const char *path, char *buf, size_t size)
{
    char tail[8192];
    buf[0] = 0;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return;
    size_t n = 0;
    if (fseek(fp, 0, SEEK_END) == 0) {
        long end = ftell(fp);
        long from = end > (long)sizeof tail - 1 ? end - (long)sizeof tail + 1 : 0;
        if (end >= 0 && fseek(fp, from, SEEK_SET) == 0)
            n = fread(tail, 1, sizeof tail - 1, fp);
    }
    fclose(fp);
    tail[n] = 0;
    while (n > 0 && (tail[n - 1] == '\n' || tail[n - 1] == '\r' || tail[n - 1] == ' '))
        tail[--n] = 0;
    char *start = strrchr(tail, '\n');
    snprintf(buf, size, "%s", start ? start + 1 : tail);
}

int vc_child_run(char *const argv[], const char *log_path, vc_child_result *res)
{
    memset(res, 0, sizeof *res);
    res->exit_code = -1;
    int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0) {
        snprintf(res->message, sizeof res->message, "%s: cannot write: %s", log_path,
                 strerror(errno));
        return -1;
    }
    fflush(NULL); /* nothing buffered may be written twice */
    double t0 = now();
    /* Blocked from the fork until the child is recorded: a signal in
     * between would leave it running, unknown to the handler. */
    sigset_t saved;
    vc_cli_block_signals(&saved);
    pid_t pid = fork();
    if (pid < 0) {
        int e = errno;
        vc_cli_restore_signals(&saved);
        snprintf(res->message, sizeof res->message, "cannot start %s: %s", argv[0],
                 strerror(e));
        close(fd);
        return -1;
    }
    if (pid == 0) {
        vc_cli_child_exec_prepare(&saved);
        if (dup2(fd, STDOUT_FILENO) < 0 || dup2(fd, STDERR_FILENO) < 0)
            _exit(127);
        close(fd);
        execv(argv[0], argv);
        dprintf(STDERR_FILENO, "cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    vc_cli_child_started(pid);
    vc_cli_restore_signals(&saved);
    close(fd);
    /* Waited for without reaping it first (WNOWAIT): its pid stays its own
     * until it is reaped with the signals blocked and forgotten at once, so
     * that a handler never signals a pid reused by another process. */
    siginfo_t info;
    int w;
    do {
        w = waitid(P_PID, (id_t)pid, &info, WEXITED | WNOWAIT);
    } while (w < 0 && errno == EINTR);
    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    vc_cli_block_signals(&saved);
    pid_t got;
    do {
        got = wait4(pid, &status, 0, &ru);
    } while (got < 0 && errno == EINTR);
    int wait_errno = errno;
    vc_cli_child_ended();
    vc_cli_restore_signals(&saved);
    res->wall_seconds = now() - t0;
    if (got < 0) {
        snprintf(res->message, sizeof res->message, "waiting for %s: %s", argv[0],
                 strerror(wait_errno));
        return -1;
    }
    res->started = 1;
    res->cpu_seconds = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
                       (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
    res->peak_mib = (double)ru.ru_maxrss / 1024.0; /* KiB on Linux */
    if (WIFEXITED(status)) {
        res->exit_code = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
        res->signal = WTERMSIG(status);
    }
    if (res->exit_code == 0)
        return 0;
    char line[400];
    last_line(log_path, line, sizeof line);
    if (res->signal)
        snprintf(res->message, sizeof res->message, "killed by signal %d (%s)%s%s", res->signal,
                 strsignal(res->signal), line[0] ? "; last output: " : "", line);
    else
        snprintf(res->message, sizeof res->message, "exit %d: %s", res->exit_code,
                 line[0] ? line : "(no message)");
    return -1;
}

int vc_self_executable(char *buf, size_t size)
{
    ssize_t n = readlink("/proc/self/exe", buf, size);
    if (n <= 0 || (size_t)n >= size)
        return -1;
    buf[n] = 0;
    return 0;
}
