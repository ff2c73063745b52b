#include "cli_util.h"

#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

double vc_cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int vc_cli_parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

int vc_cli_parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

int vc_cli_directory_writable(const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    if (!slash)
        return access(".", W_OK) == 0;
    size_t n = (size_t)(slash - path);
    if (n == 0)
        n = 1; /* the root directory */
    if (n >= sizeof dir)
        return 0;
    memcpy(dir, path, n);
    dir[n] = 0;
    return access(dir, W_OK) == 0;
}

int vc_cli_check_output_file_as(const char *prog, const char *path)
{
    struct stat st;
    if (!vc_cli_directory_writable(path)) {
        fprintf(stderr, "%s: %s: cannot write: directory missing or not writable\n", prog, path);
        return 1;
    }
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        fprintf(stderr, "%s: %s: cannot write: Is a directory\n", prog, path);
        return 1;
    }
    return 0;
}

int vc_cli_check_output_file(const char *path)
{
    return vc_cli_check_output_file_as("vorocrust", path);
}

int vc_cli_positional(const char *prog, const char *command, const char *arg,
                      const char **positional)
{
    if (arg[0] == '-' && arg[1]) {
        fprintf(stderr, "%s: unknown option '%s' (see '%s --help')\n", prog, arg, command);
        return 2;
    }
    if (*positional) {
        fprintf(stderr, "%s: unexpected argument '%s'\n", prog, arg);
        return 2;
    }
    *positional = arg;
    return 0;
}

int vc_cli_missing(const char *prog, const char *command, const char *what)
{
    fprintf(stderr, "%s: missing %s (see '%s --help')\n", prog, what, command);
    return 2;
}

/* Whether the directory that would hold path (trailing slashes ignored)
 * exists, is a directory and is writable. */
static int parent_directory_writable(const char *path)
{
    char dir[4096];
    size_t n = strlen(path);
    while (n > 1 && path[n - 1] == '/')
        n--;
    while (n > 0 && path[n - 1] != '/')
        n--;
    while (n > 1 && path[n - 1] == '/')
        n--;
    if (n == 0)
        return access(".", W_OK | X_OK) == 0;
    if (n >= sizeof dir)
        return 0;
    memcpy(dir, path, n);
    dir[n] = 0;
    struct stat st;
    return stat(dir, &st) == 0 && S_ISDIR(st.st_mode) && access(dir, W_OK | X_OK) == 0;
}

int vc_cli_check_case_dir(const char *path)
{
    struct stat st;
    if (!*path) {
        fprintf(stderr, "vorocrust: --foam: the case directory is empty\n");
        return 2;
    }
    if (stat(path, &st) == 0) {
        if (!S_ISDIR(st.st_mode)) {
            fprintf(stderr, "vorocrust: %s: cannot write the OpenFOAM case: Not a directory\n",
                    path);
            return 1;
        }
        if (access(path, W_OK | X_OK) != 0) {
            fprintf(stderr, "vorocrust: %s: cannot write the OpenFOAM case: %s\n", path,
                    strerror(errno));
            return 1;
        }
    } else if (!parent_directory_writable(path)) {
        fprintf(stderr,
                "vorocrust: %s: cannot write the OpenFOAM case: directory missing or not "
                "writable\n",
                path);
        return 1;
    }
    return 0;
}
