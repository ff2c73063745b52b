/* _GNU_SOURCE: syscall(SYS_getdents64), the async-signal-safe directory
 * listing of the signal handlers' tree removal. */
#define _GNU_SOURCE
#include "cli_util.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <sys/stat.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/syscall.h>
#endif

#include "io/tmpfile.h"

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
    if (!*path) {
        fprintf(stderr, "%s: an output file name is empty\n", prog);
        return 1;
    }
    /* What the path names, a symbolic link followed (-o link-to-/dev/null
     * means the device), and the link itself. */
    if (stat(path, &st) == 0 || lstat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            fprintf(stderr, "%s: %s: cannot write: Is a directory\n", prog, path);
            return 1;
        }
        if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) {
            fprintf(stderr, "%s: %s: is a %s, not a regular file: refusing to replace it\n",
                    prog, path, vc_tmpfile_kind((unsigned int)st.st_mode));
            return 1;
        }
    }
    if (!vc_cli_directory_writable(path)) {
        fprintf(stderr, "%s: %s: cannot write: directory missing or not writable\n", prog, path);
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
            fprintf(stderr, "vorocrust: %s: cannot write the OpenFOAM case: Not a directory "
                    "(a %s)\n", path,
                    S_ISREG(st.st_mode) ? "regular file" : vc_tmpfile_kind((unsigned int)st.st_mode));
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

/* ---- repeated options ------------------------------------------------------ */

/* "-o" and "--output" are one option (the only short alias of the commands
 * apart from -h, which never gets here twice). */
static const char *canonical_option(const char *a)
{
    return !strcmp(a, "-o") ? "--output" : a;
}

int vc_cli_repeated(vc_cli_seen *seen, const char *prog, const char *command, const char *arg)
{
    if (arg[0] != '-' || !arg[1])
        return 0; /* a positional argument */
    const char *c = canonical_option(arg);
    for (int i = 0; i < seen->n; i++)
        if (!strcmp(seen->names[i], c)) {
            fprintf(stderr, "%s: %s given twice (see '%s --help')\n", prog, arg, command);
            return 2;
        }
    if (seen->n < VC_CLI_SEEN_MAX)
        seen->names[seen->n++] = c;
    return 0;
}

/* ---- outputs and signals ---------------------------------------------------
 * The registry the library's tmpfile tracker fills: fixed slots with the
 * paths copied in, so that a signal handler reads them without allocating.
 * A slot's state is written last (atomically) when it is filled. */

#define OUT_SLOTS 64
#define OUT_PATH 4200 /* paths are checked shorter than PATH_MAX + ".tmp.XXXXXX" */

enum { SLOT_FREE, SLOT_TEMP, SLOT_RENAMING, SLOT_COMMITTED };

typedef struct out_slot {
    atomic_int state;
    int is_dir;
    char tmp[OUT_PATH];
    char final[OUT_PATH];
} out_slot;

static out_slot out_slots[OUT_SLOTS];
static atomic_int out_dying;

static const int caught_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGXFSZ};
#define N_CAUGHT ((int)(sizeof caught_signals / sizeof caught_signals[0]))

/* Removes path and, for a directory, what it holds (no symbolic link is
 * followed): only system calls, no allocation (async-signal-safe). 0 when
 * removed, -1 with errno otherwise. */
static int remove_tree_at(int dirfd, const char *name, int depth)
{
    if (unlinkat(dirfd, name, 0) == 0)
        return 0;
    if (errno != EISDIR && errno != EPERM)
        return -1;
    if (unlinkat(dirfd, name, AT_REMOVEDIR) == 0)
        return 0;
    if (errno != ENOTEMPTY && errno != EEXIST)
        return -1;
#ifdef __linux__
    if (depth > 16)
        return -1;
    int fd = openat(dirfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0)
        return -1;
    /* Entries removed while listing may shift the rest: list again until a
     * pass removes nothing. */
    for (int pass = 0; pass < 8; pass++) {
        int removed = 0;
        (void)lseek(fd, 0, SEEK_SET);
        for (;;) {
            long buf[256]; /* 2 KiB, aligned for the records */
            long n = syscall(SYS_getdents64, fd, buf, sizeof buf);
            if (n <= 0)
                break;
            for (long off = 0; off < n;) {
                const char *rec = (const char *)buf + off;
                unsigned short reclen;
                memcpy(&reclen, rec + 16, sizeof reclen); /* d_ino, d_off, d_reclen */
                const char *ename = rec + 19;             /* after d_type */
                if (strcmp(ename, ".") && strcmp(ename, "..") &&
                    remove_tree_at(fd, ename, depth + 1) == 0)
                    removed = 1;
                if (!reclen)
                    break;
                off += reclen;
            }
        }
        if (!removed)
            break;
    }
    close(fd);
    return unlinkat(dirfd, name, AT_REMOVEDIR);
#else
    (void)depth;
    return -1;
#endif
}

static int remove_path(const char *path)
{
    return remove_tree_at(AT_FDCWD, path, 0);
}

/* Removes what slot s holds for this run: the temporary path, and the
 * committed output (when renaming: when the temporary one is gone, the
 * rename happened). Async-signal-safe. */
static void remove_slot(out_slot *s)
{
    int st = atomic_load(&s->state);
    if (st == SLOT_TEMP) {
        remove_path(s->tmp);
    } else if (st == SLOT_RENAMING) {
        int saved = errno;
        if (remove_path(s->tmp) != 0 && errno == ENOENT)
            remove_path(s->final);
        errno = saved;
    } else if (st == SLOT_COMMITTED) {
        remove_path(s->final);
    }
}

static void remove_all(void)
{
    int saved = errno;
    for (int i = OUT_SLOTS - 1; i >= 0; i--)
        remove_slot(&out_slots[i]);
    errno = saved;
}

static void on_signal(int sig)
{
    atomic_store(&out_dying, 1);
    remove_all();
    /* Die by the same signal: default action, unblocked, raised again. */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = SIG_DFL;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, NULL);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, sig);
    sigprocmask(SIG_UNBLOCK, &set, NULL);
    raise(sig);
    _exit(128 + sig); /* not reached */
}

static int track_event(void *user, vc_tmpfile_event ev, int slot, const char *tmp_path,
                       const char *final_path, int is_dir)
{
    (void)user;
    if (ev == VC_TMPFILE_ADD) {
        if (atomic_load(&out_dying))
            return -1;
        size_t nt = strlen(tmp_path), nf = strlen(final_path);
        if (nt >= OUT_PATH || nf >= OUT_PATH)
            return -1;
        for (int i = 0; i < OUT_SLOTS; i++) {
            out_slot *s = &out_slots[i];
            if (atomic_load(&s->state) != SLOT_FREE)
                continue;
            memcpy(s->tmp, tmp_path, nt + 1);
            memcpy(s->final, final_path, nf + 1);
            s->is_dir = is_dir;
            atomic_store(&s->state, SLOT_TEMP);
            return i;
        }
        return -1;
    }
    if (slot < 0 || slot >= OUT_SLOTS)
        return 0;
    out_slot *s = &out_slots[slot];
    switch (ev) {
    case VC_TMPFILE_DROP: atomic_store(&s->state, SLOT_FREE); break;
    case VC_TMPFILE_RENAMING: atomic_store(&s->state, SLOT_RENAMING); break;
    case VC_TMPFILE_UNRENAMED: atomic_store(&s->state, SLOT_TEMP); break;
    case VC_TMPFILE_COMMITTED: atomic_store(&s->state, SLOT_COMMITTED); break;
    default: break;
    }
    return 0;
}

void vc_cli_outputs_begin(void)
{
    static const vc_tmpfile_tracker tracker = {track_event, NULL};
    vc_tmpfile_track(&tracker);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < N_CAUGHT; i++)
        sigaddset(&sa.sa_mask, caught_signals[i]); /* one cleanup at a time per thread */
    for (int i = 0; i < N_CAUGHT; i++) {
        struct sigaction old;
        /* A signal the shell made ignored (nohup, a background job) stays
         * ignored. */
        if (sigaction(caught_signals[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
            continue;
        sigaction(caught_signals[i], &sa, NULL);
    }
}

int vc_cli_track_temp_dir(const char *dir)
{
    return track_event(NULL, VC_TMPFILE_ADD, -1, dir, dir, 1);
}

void vc_cli_untrack(int slot)
{
    if (slot >= 0)
        track_event(NULL, VC_TMPFILE_DROP, slot, "", "", 0);
}

void vc_cli_outputs_remove(void)
{
    remove_all();
    for (int i = 0; i < OUT_SLOTS; i++)
        atomic_store(&out_slots[i].state, SLOT_FREE);
}

void vc_cli_outputs_keep(void)
{
    for (int i = 0; i < OUT_SLOTS; i++)
        if (atomic_load(&out_slots[i].state) == SLOT_COMMITTED)
            atomic_store(&out_slots[i].state, SLOT_FREE);
}
