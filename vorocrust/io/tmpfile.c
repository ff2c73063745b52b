/* Temporary file next to the target, renamed over it on success: a failed
 * run never leaves a half-written output file behind, and an interrupted one
 * neither when the program tracks the temporary files (vc_tmpfile_track:
 * the CLI removes them from its signal handlers).
 *
 * The temporary names are made here rather than by mkstemp, so that the
 * tracker records a name before the file exists (O_CREAT | O_EXCL, retried
 * on a clash): a signal can never find a temporary file it does not know. */
#include "vorocrust/io.h"
#include "io/tmpfile.h"
#include "file_mode.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

mode_t vc_io_umask(void)
{
    FILE *fp = fopen("/proc/self/status", "r");
    if (fp) {
        char line[256];
        unsigned int mask;
        while (fgets(line, sizeof line, fp)) {
            if (sscanf(line, "Umask: %o", &mask) == 1) {
                fclose(fp);
                return (mode_t)(mask & 0777);
            }
        }
        fclose(fp);
    }
    mode_t mask = umask(022);
    umask(mask);
    return mask;
}

static char *vc_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

/* ---- tracking --------------------------------------------------------------- */

static vc_tmpfile_tracker vc_tracker; /* set by vc_tmpfile_track only */

void vc_tmpfile_track(const vc_tmpfile_tracker *tracker)
{
    if (tracker)
        vc_tracker = *tracker;
    else
        memset(&vc_tracker, 0, sizeof vc_tracker);
}

static int vc_track(vc_tmpfile_event ev, int slot, const char *tmp, const char *final, int is_dir)
{
    const int adds = ev == VC_TMPFILE_ADD || ev == VC_TMPFILE_MKDIR;
    if (!vc_tracker.event)
        return adds ? -1 : 0;
    if (!adds && slot < 0)
        return 0;
    return vc_tracker.event(vc_tracker.user, ev, slot, tmp, final, is_dir);
}

/* ---- names -------------------------------------------------------------------- */

const char *vc_tmpfile_kind(unsigned int st_mode)
{
    mode_t m = (mode_t)st_mode;
    if (S_ISCHR(m))
        return "character device";
    if (S_ISBLK(m))
        return "block device";
    if (S_ISFIFO(m))
        return "FIFO";
    if (S_ISSOCK(m))
        return "socket";
    if (S_ISDIR(m))
        return "directory";
    return "special file";
}

int vc_tmpfile_check_target(const char *path, vc_error *err)
{
    struct stat st;
    if (lstat(path, &st) != 0 || S_ISREG(st.st_mode) || S_ISLNK(st.st_mode))
        return VC_OK;
    if (S_ISDIR(st.st_mode))
        return vc_error_set(err, VC_EIO, "%s: cannot write: Is a directory", path);
    return vc_error_set(err, VC_EIO, "%s: is a %s, not a regular file: refusing to replace it",
                        path, vc_tmpfile_kind((unsigned int)st.st_mode));
}

/* Fills the last 6 characters of name (the XXXXXX) from state. */
static void vc_fill_name(char *name, uint64_t *state)
{
    static const char letters[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    size_t n = strlen(name);
    uint64_t x = *state;
    for (size_t i = n - 6; i < n; i++) {
        /* splitmix64 step */
        x += 0x9E3779B97F4A7C15ull;
        uint64_t z = x;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        name[i] = letters[z % 62];
    }
    *state = x;
}

static uint64_t vc_name_seed(const void *where)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (uint64_t)ts.tv_nsec ^ ((uint64_t)ts.tv_sec << 30) ^ ((uint64_t)getpid() << 20) ^
           (uint64_t)(uintptr_t)where;
}

/* "<path>.<kind>.XXXXXX" (malloc'ed) or NULL. */
static char *vc_tmp_template(const char *path, const char *kind)
{
    size_t n = strlen(path), k = strlen(kind);
    char *s = malloc(n + k + 9);
    if (!s)
        return NULL;
    memcpy(s, path, n);
    s[n] = '.';
    memcpy(s + n + 1, kind, k);
    memcpy(s + n + 1 + k, ".XXXXXX", 8);
    return s;
}

#define VC_TMP_ATTEMPTS 100

/* Creates tmp (a template; its XXXXXX replaced) as a file (returns the
 * descriptor) or a directory (returns 0), tracked in *slot; -1 with errno
 * (ENOLCK: the tracker refused). */
static int vc_tmp_create(char *tmp, const char *final, int is_dir, int *slot)
{
    uint64_t state = vc_name_seed(tmp);
    const int tracked = vc_tracker.event != NULL;
    for (int attempt = 0; attempt < VC_TMP_ATTEMPTS; attempt++) {
        vc_fill_name(tmp, &state);
        *slot = -1;
        if (tracked) {
            *slot = vc_track(VC_TMPFILE_ADD, -1, tmp, final, is_dir);
            if (*slot < 0) {
                errno = ENOLCK;
                return -1;
            }
        }
        int fd = is_dir ? mkdir(tmp, 0777)
                        : open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0)
            return fd;
        int e = errno;
        vc_track(VC_TMPFILE_DROP, *slot, tmp, final, is_dir);
        *slot = -1;
        errno = e;
        if (e != EEXIST)
            return -1;
    }
    errno = EEXIST;
    return -1;
}

static int vc_create_error(vc_error *err, const char *path, int e)
{
    if (e == ENOLCK)
        return vc_error_set(err, VC_EIO, "%s: cannot track the temporary file (too many "
                            "outputs, or a path too long)", path);
    return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e));
}

/* ---- files ---------------------------------------------------------------------- */

static void vc_tmpfile_clear(vc_tmpfile *t)
{
    free(t->tmp_path);
    free(t->final_path);
    t->tmp_path = NULL;
    t->final_path = NULL;
    t->fp = NULL;
    t->slot = -1;
}

int vc_tmpfile_open(vc_tmpfile *t, const char *path, vc_error *err)
{
    t->fp = NULL;
    t->tmp_path = NULL;
    t->final_path = NULL;
    t->slot = -1;
    if (!path || !*path)
        return vc_error_set(err, VC_EPARAM, "output path is empty");
    int rc = vc_tmpfile_check_target(path, err);
    if (rc)
        return rc;

    t->final_path = vc_strdup(path);
    t->tmp_path = vc_tmp_template(path, "tmp");
    if (!t->final_path || !t->tmp_path) {
        vc_tmpfile_clear(t);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    /* open(..., 0666) gives the output what fopen would give it (the umask
     * applies) */
    int fd = vc_tmp_create(t->tmp_path, path, 0, &t->slot);
    if (fd < 0) {
        int e = errno;
        vc_tmpfile_clear(t);
        return vc_create_error(err, path, e);
    }
    FILE *fp = fdopen(fd, "wb");
    if (!fp) {
        int e = errno;
        close(fd);
        remove(t->tmp_path);
        vc_track(VC_TMPFILE_DROP, t->slot, t->tmp_path, path, 0);
        vc_tmpfile_clear(t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e));
    }
    t->fp = fp;
    return VC_OK;
}

int vc_tmpfile_commit(vc_tmpfile *t, vc_error *err)
{
    FILE *fp = (FILE *)t->fp;
    if (!fp || !t->tmp_path || !t->final_path) {
        vc_tmpfile_discard(t);
        return vc_error_set(err, VC_EINTERNAL, "vc_tmpfile_commit: file is not open");
    }
    int e = 0;
    errno = 0;
    if (fflush(fp) != 0 || ferror(fp))
        e = errno ? errno : EIO;
    if (fclose(fp) != 0 && !e)
        e = errno ? errno : EIO;
    t->fp = NULL;
    int rc = VC_OK;
    if (!e) {
        /* Checked again at the last moment: a device or a FIFO made there
         * since the open is not replaced either. */
        rc = vc_tmpfile_check_target(t->final_path, err);
        if (rc == VC_OK) {
            vc_track(VC_TMPFILE_RENAMING, t->slot, t->tmp_path, t->final_path, 0);
            if (rename(t->tmp_path, t->final_path) != 0) {
                e = errno ? errno : EIO;
                vc_track(VC_TMPFILE_UNRENAMED, t->slot, t->tmp_path, t->final_path, 0);
            }
        }
    }
    if (e || rc) {
        remove(t->tmp_path);
        vc_track(VC_TMPFILE_DROP, t->slot, t->tmp_path, t->final_path, 0);
        if (e)
            rc = vc_error_set(err, VC_EIO, "%s: cannot write: %s", t->final_path, strerror(e));
        vc_tmpfile_clear(t);
        return rc;
    }
    vc_track(VC_TMPFILE_COMMITTED, t->slot, t->tmp_path, t->final_path, 0);
    vc_tmpfile_clear(t);
    return VC_OK;
}

void vc_tmpfile_discard(vc_tmpfile *t)
{
    if (!t)
        return;
    if (t->fp)
        fclose((FILE *)t->fp);
    if (t->tmp_path) {
        remove(t->tmp_path);
        vc_track(VC_TMPFILE_DROP, t->slot, t->tmp_path, t->final_path, 0);
    }
    vc_tmpfile_clear(t);
}

/* ---- directories ------------------------------------------------------------------ */

static void vc_tmpdir_clear(vc_tmpdir *d)
{
    free(d->tmp_path);
    free(d->final_path);
    d->tmp_path = NULL;
    d->final_path = NULL;
    d->slot = -1;
}

int vc_tmpdir_create(vc_tmpdir *d, const char *path, const char *kind, vc_error *err)
{
    d->slot = -1;
    d->final_path = vc_strdup(path);
    d->tmp_path = vc_tmp_template(path, kind);
    if (!d->final_path || !d->tmp_path) {
        vc_tmpdir_clear(d);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    if (vc_tmp_create(d->tmp_path, path, 1, &d->slot) < 0) {
        int e = errno;
        vc_tmpdir_clear(d);
        return vc_create_error(err, path, e);
    }
    return VC_OK;
}

int vc_tmpdir_commit(vc_tmpdir *d, vc_error *err)
{
    vc_track(VC_TMPFILE_RENAMING, d->slot, d->tmp_path, d->final_path, 1);
    if (rename(d->tmp_path, d->final_path) != 0) {
        int e = errno;
        vc_track(VC_TMPFILE_UNRENAMED, d->slot, d->tmp_path, d->final_path, 1);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", d->final_path, strerror(e));
    }
    vc_track(VC_TMPFILE_COMMITTED, d->slot, d->tmp_path, d->final_path, 1);
    d->slot = -1; /* the tracker's now */
    vc_tmpdir_clear(d);
    return VC_OK;
}

void vc_tmpdir_drop(vc_tmpdir *d)
{
    if (!d)
        return;
    if (d->tmp_path)
        vc_track(VC_TMPFILE_DROP, d->slot, d->tmp_path, d->final_path, 1);
    vc_tmpdir_clear(d);
}

/* The swap of an existing directory. The signals a program's cleanup
 * handler catches are blocked in this thread from before the old directory
 * is set aside until the new one is in (or the old one back): a handler
 * then sees the tracker's slots and the directories agree. */
static void vc_block_cleanup_signals(sigset_t *saved)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    sigaddset(&set, SIGXFSZ);
    pthread_sigmask(SIG_BLOCK, &set, saved);
}

int vc_tmpdir_replace(vc_tmpdir *d, vc_error *err)
{
    vc_tmpdir od;
    int rc = vc_tmpdir_create(&od, d->final_path, "old", err);
    if (rc != VC_OK)
        return rc;
    sigset_t saved;
    vc_block_cleanup_signals(&saved);
    /* Announced before the rename: a handler that finds od still empty
     * fails to rename it over the old directory and only removes it. */
    const int tracker_keeps =
        vc_track(VC_TMPFILE_BACKUP, od.slot, od.tmp_path, od.final_path, 1) == 1;
    if (rename(d->final_path, od.tmp_path) != 0) {
        int e = errno;
        rmdir(od.tmp_path);
        vc_tmpdir_drop(&od);
        pthread_sigmask(SIG_SETMASK, &saved, NULL);
        return vc_error_set(err, VC_EIO, "%s: cannot replace: %s", d->final_path, strerror(e));
    }
    rc = vc_tmpdir_commit(d, err);
    if (rc != VC_OK) {
        if (rename(od.tmp_path, od.final_path) != 0) {
            /* Never removed: the message says where the old one is. */
            int e = errno;
            char first[VC_ERROR_LEN];
            snprintf(first, sizeof first, "%s", err ? err->msg : "");
            rc = vc_error_set(err, VC_EIO, "%s; the old directory could not be put back (%s): "
                              "it is %s", first, strerror(e), od.tmp_path);
        }
        vc_tmpdir_drop(&od);
    } else if (!tracker_keeps) {
        vc_remove_tree(od.tmp_path);
        vc_tmpdir_drop(&od);
    } else {
        od.slot = -1; /* the tracker's: removed when the outputs are kept */
        vc_tmpdir_clear(&od);
    }
    pthread_sigmask(SIG_SETMASK, &saved, NULL);
    return rc;
}

/* ---- new directories of the run ---------------------------------------------------- */

int vc_outdir_make(const char *path, const char *report, int *slot, vc_error *err)
{
    *slot = -1;
    if (vc_tracker.event) {
        *slot = vc_track(VC_TMPFILE_MKDIR, -1, path, path, 1);
        if (*slot < 0)
            return vc_create_error(err, report, ENOLCK);
    }
    if (mkdir(path, 0777) != 0) {
        int e = errno;
        vc_track(VC_TMPFILE_DROP, *slot, path, path, 1);
        *slot = -1;
        return vc_error_set(err, VC_EIO, "%s: cannot create: %s", report, strerror(e));
    }
    return VC_OK;
}

void vc_outdir_unmake(const char *path, int slot)
{
    rmdir(path);
    vc_track(VC_TMPFILE_DROP, slot, path, path, 1);
}

/* ---- removal ------------------------------------------------------------------------ */

char *vc_path_join(const char *a, const char *b)
{
    size_t na = strlen(a), nb = strlen(b);
    char *s = malloc(na + nb + 2);
    if (!s)
        return NULL;
    memcpy(s, a, na);
    s[na] = '/';
    memcpy(s + na + 1, b, nb + 1);
    return s;
}

static void vc_remove_tree_at(const char *path, int depth)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return;
    if (S_ISDIR(st.st_mode) && depth < 32) {
        DIR *d = opendir(path);
        if (d) {
            struct dirent *e;
            while ((e = readdir(d)) != NULL) {
                if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
                    continue;
                char *sub = vc_path_join(path, e->d_name);
                if (sub) {
                    vc_remove_tree_at(sub, depth + 1);
                    free(sub);
                }
            }
            closedir(d);
        }
        rmdir(path);
    } else {
        unlink(path);
    }
}

void vc_remove_tree(const char *path)
{
    vc_remove_tree_at(path, 0);
}
