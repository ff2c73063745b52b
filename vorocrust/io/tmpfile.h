/* The temporary-file-and-rename pattern of every writer (internal to the
 * library and its programs): vc_tmpfile_open creates "<path>.tmp.XXXXXX"
 * and opens it for binary writing; vc_tmpfile_commit closes and renames it
 * over path (removing it on failure); vc_tmpfile_discard closes and
 * removes it. A failed run never leaves a half-written output. The
 * OpenFOAM writer stages its case directory the same way (vc_tmpdir).
 *
 * Neither replaces an existing path that is not a regular file (or a
 * symbolic link, which rename replaces, not what it points to): a
 * character or block device, a FIFO, a socket or a directory is refused
 * with "PATH: is a character device, not a regular file" (a directory:
 * "PATH: cannot write: Is a directory"). */
#ifndef VC_IO_TMPFILE_H
#define VC_IO_TMPFILE_H

#include "vorocrust/error.h"

/* ---- tracking (opt-in) ----------------------------------------------------
 * A program that must leave nothing behind when a signal kills it (the CLI)
 * registers a tracker; the library then reports every temporary file and
 * directory it creates, renames and removes, so that a signal handler can
 * remove them (and the outputs already committed) from paths recorded
 * beforehand. The library keeps no other state and installs no handler;
 * without a tracker (the default) nothing is reported.
 *
 * The events of one temporary path, in order (slot: what ADD returned):
 *   VC_TMPFILE_ADD       tmp_path is about to be created (final_path its
 *                        target, is_dir for a directory): record both and
 *                        return a slot >= 0, or -1 to refuse (the open then
 *                        fails with "cannot track the temporary file"). A
 *                        handler running now may find tmp_path missing.
 *   VC_TMPFILE_DROP      tmp_path is gone (not created after all, or
 *                        removed); the slot is free again.
 *   VC_TMPFILE_RENAMING  tmp_path is about to be renamed over final_path:
 *                        from now on, if tmp_path is missing, final_path is
 *                        this run's output.
 *   VC_TMPFILE_UNRENAMED the rename failed: tmp_path is still there (a DROP
 *                        follows once it is removed).
 *   VC_TMPFILE_COMMITTED final_path is now this run's output; the slot
 *                        stays the tracker's (the library reports nothing
 *                        more about it).
 * Two more kinds of slot:
 *   VC_TMPFILE_MKDIR     (instead of ADD) final_path (tmp_path the same) is
 *                        about to be made as a new directory of this run's
 *                        (vc_outdir_make): return a slot >= 0 or -1 to
 *                        refuse. A DROP follows when it was not made or
 *                        the library removed it; otherwise the slot stays
 *                        the tracker's: remove the directory with the
 *                        outputs, after them and only if empty (rmdir).
 *   VC_TMPFILE_BACKUP    (on a slot of a temporary directory) tmp_path is
 *                        about to receive what final_path holds (the old
 *                        directory of vc_tmpdir_replace), before the new
 *                        one is renamed over final_path. From now on the
 *                        old content is in tmp_path, or still in
 *                        final_path while tmp_path is an empty directory:
 *                        to undo the run, rename tmp_path back over
 *                        final_path once the outputs are removed (and
 *                        rmdir tmp_path when that fails: it is then the
 *                        empty one). Return 1 to keep tmp_path until the
 *                        outputs are kept (then remove it with its
 *                        contents): the slot is the tracker's. Return 0
 *                        and the library removes it after the swap (DROP).
 * The callback runs in the writing thread; with writers in several threads
 * it must be thread-safe. tmp_path and final_path are valid only during
 * the call (copy them). */
typedef enum vc_tmpfile_event {
    VC_TMPFILE_ADD,
    VC_TMPFILE_DROP,
    VC_TMPFILE_RENAMING,
    VC_TMPFILE_UNRENAMED,
    VC_TMPFILE_COMMITTED,
    VC_TMPFILE_MKDIR,
    VC_TMPFILE_BACKUP
} vc_tmpfile_event;

typedef struct vc_tmpfile_tracker {
    int (*event)(void *user, vc_tmpfile_event ev, int slot, const char *tmp_path,
                 const char *final_path, int is_dir);
    void *user;
} vc_tmpfile_tracker;

/* Registers tracker (copied) for the whole process; NULL stops tracking.
 * Set it before any writer runs, not while one does. */
void vc_tmpfile_track(const vc_tmpfile_tracker *tracker);

/* ---- temporary files ------------------------------------------------------ */

typedef struct vc_tmpfile {
    void *fp; /* FILE * */
    char *tmp_path;
    char *final_path;
    int slot; /* the tracker's slot, -1 when untracked */
} vc_tmpfile;

int vc_tmpfile_open(vc_tmpfile *t, const char *path, vc_error *err);
int vc_tmpfile_commit(vc_tmpfile *t, vc_error *err);
void vc_tmpfile_discard(vc_tmpfile *t);

/* ---- temporary directories ------------------------------------------------
 * vc_tmpdir_create makes "<path>.<kind>.XXXXXX" (kind "tmp", or "old" for a
 * directory set aside), mode 0777 less the umask, tracked with is_dir (a
 * handler removes it with its contents). vc_tmpdir_commit renames it over
 * path (an absent path or an empty directory); on failure the directory is
 * left to the caller, still tracked. vc_tmpdir_drop tells the tracker the
 * caller removed it (or that it is no longer temporary) and frees d. */
typedef struct vc_tmpdir {
    char *tmp_path;
    char *final_path;
    int slot;
} vc_tmpdir;

int vc_tmpdir_create(vc_tmpdir *d, const char *path, const char *kind, vc_error *err);
int vc_tmpdir_commit(vc_tmpdir *d, vc_error *err);
void vc_tmpdir_drop(vc_tmpdir *d);

/* The directory d->final_path exists: it is renamed aside to
 * "<path>.old.XXXXXX" and d renamed over it, then the old one is removed
 * (or left to the tracker: VC_TMPFILE_BACKUP). SIGINT, SIGTERM, SIGHUP and
 * SIGXFSZ are blocked in the calling thread across the two renames and
 * the restore, so that a handler never sees a state halfway. When d cannot
 * be renamed in, the old directory is put back (err says so; d is left to
 * the caller, still tracked, as by vc_tmpdir_commit). */
int vc_tmpdir_replace(vc_tmpdir *d, vc_error *err);

/* A new directory of this run's: made (mkdir 0777, less the umask) and
 * tracked (VC_TMPFILE_MKDIR) so that a handler can remove it with the
 * outputs when it is empty; *slot is the tracker's slot (-1 untracked).
 * report names it in messages. vc_outdir_unmake removes it (rmdir: only
 * when empty) and tells the tracker. */
int vc_outdir_make(const char *path, const char *report, int *slot, vc_error *err);
void vc_outdir_unmake(const char *path, int slot);

/* Removes path and, for a directory, everything under it (no symbolic
 * link followed); errors are ignored (this is cleanup). */
void vc_remove_tree(const char *path);

/* "a/b", malloc'ed (NULL when out of memory). */
char *vc_path_join(const char *a, const char *b);

/* 0 when path is absent, a regular file or a symbolic link; otherwise
 * sets err ("PATH: is a FIFO, not a regular file") and returns VC_EIO.
 * vc_tmpfile_kind names the kind of a st_mode ("character device", ...). */
int vc_tmpfile_check_target(const char *path, vc_error *err);
const char *vc_tmpfile_kind(unsigned int st_mode);

#endif
