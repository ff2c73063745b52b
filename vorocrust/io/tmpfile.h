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
 * The callback runs in the writing thread; with writers in several threads
 * it must be thread-safe. tmp_path and final_path are valid only during
 * the call (copy them). */
typedef enum vc_tmpfile_event {
    VC_TMPFILE_ADD,
    VC_TMPFILE_DROP,
    VC_TMPFILE_RENAMING,
    VC_TMPFILE_UNRENAMED,
    VC_TMPFILE_COMMITTED
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

/* 0 when path is absent, a regular file or a symbolic link; otherwise
 * sets err ("PATH: is a FIFO, not a regular file") and returns VC_EIO.
 * vc_tmpfile_kind names the kind of a st_mode ("character device", ...). */
int vc_tmpfile_check_target(const char *path, vc_error *err);
const char *vc_tmpfile_kind(unsigned int st_mode);

#endif
