/* The temporary-file-and-rename pattern of every writer (internal to the
 * library and its programs): vc_tmpfile_open creates "<path>.tmp.XXXXXX"
 * and opens it for binary writing; vc_tmpfile_commit closes and renames it
 * over path (removing it on failure); vc_tmpfile_discard closes and
 * removes it. A failed run never leaves a half-written output. */
#ifndef VC_IO_TMPFILE_H
#define VC_IO_TMPFILE_H

#include "vorocrust/error.h"

typedef struct vc_tmpfile {
    void *fp; /* FILE * */
    char *tmp_path;
    char *final_path;
} vc_tmpfile;

int vc_tmpfile_open(vc_tmpfile *t, const char *path, vc_error *err);
int vc_tmpfile_commit(vc_tmpfile *t, vc_error *err);
void vc_tmpfile_discard(vc_tmpfile *t);

#endif
