/* _GNU_SOURCE: syscall(SYS_getdents64), the async-signal-safe directory
 * listing of the signal handlers' tree removal. */
#define _GNU_SOURCE
#include "cli_util.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
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

double vc_cli_peak_mib(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    if (f) {
        char line[256];
        long kib = -1;
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "VmHWM: %ld kB", &kib) == 1)
                break;
        fclose(f);
        if (kib >= 0)
            return (double)kib / 1024.0;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0; /* KiB on Linux */
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

enum { SLOT_FREE, SLOT_TEMP, SLOT_RENAMING, SLOT_COMMITTED, SLOT_MADE_DIR, SLOT_BACKUP };

typedef struct out_slot {
    atomic_int state;
    int is_dir;
    char tmp[OUT_PATH];
    char final[OUT_PATH];
} out_slot;

static out_slot out_slots[OUT_SLOTS];
static atomic_int out_dying;
static atomic_int out_owner; /* getpid() of the program once begun, else 0 */
static pthread_t out_thread; /* the thread the handlers run in */
static atomic_int out_child; /* the running child's pid, 0 when none */

/* VC_TEST_SIGNAL_AT (cli_util.h): -1 when unset. */
static int hook_event = -1, hook_signal;
static char hook_suffix[256];

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

/* Pass 1 of the removal: what slot s holds for this run, the temporary
 * path and the committed output (when renaming: when the temporary one is
 * gone, the rename happened). Async-signal-safe. */
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

/* Pass 2: a replaced directory goes back once the new one is removed; when
 * the swap had not begun, tmp is the empty directory made for it (rename
 * fails on the old one, non-empty) and only it goes (rmdir: never data). */
static void restore_slot(out_slot *s)
{
    if (atomic_load(&s->state) == SLOT_BACKUP && rename(s->tmp, s->final) != 0)
        rmdir(s->tmp);
}

/* Pass 3: the directories this run made, once emptied by the passes before
 * (rmdir: only when empty). */
static void unmake_slot(out_slot *s)
{
    if (atomic_load(&s->state) == SLOT_MADE_DIR)
        rmdir(s->final);
}

static void remove_all(void)
{
    int saved = errno;
    for (int i = OUT_SLOTS - 1; i >= 0; i--)
        remove_slot(&out_slots[i]);
    for (int i = OUT_SLOTS - 1; i >= 0; i--)
        restore_slot(&out_slots[i]);
    for (int pass = 0; pass < 2; pass++) /* nested ones: the inner first */
        for (int i = OUT_SLOTS - 1; i >= 0; i--)
            unmake_slot(&out_slots[i]);
    errno = saved;
}

static void caught_set(sigset_t *set)
{
    sigemptyset(set);
    for (int i = 0; i < N_CAUGHT; i++)
        sigaddset(set, caught_signals[i]);
}

void vc_cli_block_signals(sigset_t *saved)
{
    sigset_t set;
    caught_set(&set);
    pthread_sigmask(SIG_BLOCK, &set, saved);
}

void vc_cli_restore_signals(const sigset_t *saved)
{
    pthread_sigmask(SIG_SETMASK, saved, NULL);
}

/* Dies by sig: default action, unblocked, raised again. */
static void die_by(int sig)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = SIG_DFL;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, NULL);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, sig);
    pthread_sigmask(SIG_UNBLOCK, &set, NULL);
    raise(sig);
    _exit(128 + sig); /* not reached */
}

/* The running child gets sig too and is waited for: it removes its own
 * temporary files and stops writing into what the removal is about to
 * remove. Async-signal-safe. */
static void stop_child(int sig)
{
    pid_t pid = (pid_t)atomic_exchange(&out_child, 0);
    if (pid <= 0)
        return;
    kill(pid, sig);
    for (int i = 0; i < 500; i++) { /* 5 s */
        pid_t r = waitpid(pid, NULL, WNOHANG);
        if (r == pid || (r < 0 && errno != EINTR))
            return;
        struct timespec ts = {0, 10 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    kill(pid, SIGKILL);
    while (waitpid(pid, NULL, 0) < 0 && errno == EINTR) {
    }
}

static void on_signal(int sig)
{
    if (atomic_load(&out_owner) != (int)getpid())
        die_by(sig); /* a child between fork and exec: nothing here is its */
    if (!pthread_equal(pthread_self(), out_thread)) {
        /* Another thread (an OpenMP worker) got a signal meant for the
         * process: the cleanup runs in the writing thread, which blocks the
         * signals while a swap of directories is halfway. */
        int saved = errno;
        pthread_kill(out_thread, sig);
        errno = saved;
        return;
    }
    atomic_store(&out_dying, 1);
    stop_child(sig);
    remove_all();
    die_by(sig);
}

static void test_hook(int ev, const char *final_path)
{
    if (ev != hook_event)
        return;
    size_t n = strlen(final_path), k = strlen(hook_suffix);
    if (n >= k && !strcmp(final_path + n - k, hook_suffix))
        raise(hook_signal);
}

static int track_event(void *user, vc_tmpfile_event ev, int slot, const char *tmp_path,
                       const char *final_path, int is_dir)
{
    (void)user;
    if (ev == VC_TMPFILE_ADD || ev == VC_TMPFILE_MKDIR) {
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
            atomic_store(&s->state, ev == VC_TMPFILE_MKDIR ? SLOT_MADE_DIR : SLOT_TEMP);
            test_hook((int)ev, final_path);
            return i;
        }
        return -1;
    }
    if (slot < 0 || slot >= OUT_SLOTS)
        return 0;
    out_slot *s = &out_slots[slot];
    int keep = 0;
    switch (ev) {
    case VC_TMPFILE_DROP: atomic_store(&s->state, SLOT_FREE); break;
    case VC_TMPFILE_RENAMING: atomic_store(&s->state, SLOT_RENAMING); break;
    case VC_TMPFILE_UNRENAMED: atomic_store(&s->state, SLOT_TEMP); break;
    case VC_TMPFILE_COMMITTED: atomic_store(&s->state, SLOT_COMMITTED); break;
    case VC_TMPFILE_BACKUP:
        atomic_store(&s->state, SLOT_BACKUP);
        keep = 1; /* until vc_cli_outputs_keep: a signal puts it back */
        break;
    default: break;
    }
    test_hook((int)ev, final_path);
    return keep;
}

static void read_test_hook(void)
{
    static const char *const names[] = {"add", "drop", "renaming", "unrenamed", "committed",
                                         "mkdir", "backup"};
    static const vc_tmpfile_event events[] = {VC_TMPFILE_ADD, VC_TMPFILE_DROP,
                                              VC_TMPFILE_RENAMING, VC_TMPFILE_UNRENAMED,
                                              VC_TMPFILE_COMMITTED, VC_TMPFILE_MKDIR,
                                              VC_TMPFILE_BACKUP};
    const char *spec = getenv("VC_TEST_SIGNAL_AT");
    const char *c1 = spec ? strchr(spec, ':') : NULL;
    const char *c2 = spec ? strrchr(spec, ':') : NULL;
    long sig;
    if (!c1 || c2 == c1 || (size_t)(c2 - c1 - 1) >= sizeof hook_suffix ||
        vc_cli_parse_int(c2 + 1, 1, 64, &sig))
        return;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strlen(names[i]) == (size_t)(c1 - spec) &&
            !strncmp(spec, names[i], (size_t)(c1 - spec))) {
            memcpy(hook_suffix, c1 + 1, (size_t)(c2 - c1 - 1));
            hook_suffix[c2 - c1 - 1] = 0;
            hook_signal = (int)sig;
            hook_event = (int)events[i];
        }
}

void vc_cli_outputs_begin(void)
{
    static const vc_tmpfile_tracker tracker = {track_event, NULL};
    read_test_hook();
    out_thread = pthread_self();
    atomic_store(&out_owner, (int)getpid());
    vc_tmpfile_track(&tracker);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    caught_set(&sa.sa_mask); /* one cleanup at a time per thread */
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

/* Both run with the signals blocked: a handler must not find a slot
 * halfway between two states. */
void vc_cli_outputs_remove(void)
{
    sigset_t saved;
    vc_cli_block_signals(&saved);
    remove_all();
    for (int i = 0; i < OUT_SLOTS; i++)
        atomic_store(&out_slots[i].state, SLOT_FREE);
    vc_cli_restore_signals(&saved);
}

void vc_cli_outputs_keep(void)
{
    sigset_t saved;
    vc_cli_block_signals(&saved);
    for (int i = 0; i < OUT_SLOTS; i++) {
        out_slot *s = &out_slots[i];
        int st = atomic_load(&s->state);
        if (st == SLOT_BACKUP)
            remove_path(s->tmp); /* the replaced directory, no longer needed */
        if (st == SLOT_COMMITTED || st == SLOT_MADE_DIR || st == SLOT_BACKUP)
            atomic_store(&s->state, SLOT_FREE);
    }
    vc_cli_restore_signals(&saved);
}

void vc_cli_child_started(pid_t pid)
{
    atomic_store(&out_child, (int)pid);
}

void vc_cli_child_ended(void)
{
    atomic_store(&out_child, 0);
}

void vc_cli_child_exec_prepare(const sigset_t *saved)
{
    /* The program's handlers are not the child's: the defaults (an
     * ignored signal stays ignored), then the mask from before the fork. */
    for (int i = 0; i < N_CAUGHT; i++) {
        struct sigaction old;
        if (sigaction(caught_signals[i], NULL, &old) == 0 && old.sa_handler == on_signal) {
            struct sigaction sa;
            memset(&sa, 0, sizeof sa);
            sa.sa_handler = SIG_DFL;
            sigemptyset(&sa.sa_mask);
            sigaction(caught_signals[i], &sa, NULL);
        }
    }
    vc_cli_restore_signals(saved);
}
