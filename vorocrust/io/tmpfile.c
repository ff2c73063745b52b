/* Temporary file next to the target, renamed over it on success: a failed or
 * interrupted run never leaves a half-written output file behind. */
#include "vorocrust/io.h"
#include "io/tmpfile.h"
#include "file_mode.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
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

static void vc_tmpfile_clear(vc_tmpfile *t)
{
    free(t->tmp_path);
    free(t->final_path);
    t->tmp_path = NULL;
    t->final_path = NULL;
    t->fp = NULL;
}

int vc_tmpfile_open(vc_tmpfile *t, const char *path, vc_error *err)
{
    t->fp = NULL;
    t->tmp_path = NULL;
    t->final_path = NULL;
    if (!path || !*path)
        return vc_error_set(err, VC_EPARAM, "output path is empty");

    size_t n = strlen(path);
    t->final_path = vc_strdup(path);
    t->tmp_path = malloc(n + sizeof ".tmp.XXXXXX");
    if (!t->final_path || !t->tmp_path) {
        vc_tmpfile_clear(t);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    memcpy(t->tmp_path, path, n);
    memcpy(t->tmp_path + n, ".tmp.XXXXXX", sizeof ".tmp.XXXXXX");

    int fd = mkstemp(t->tmp_path);
    if (fd < 0) {
        int e = errno;
        vc_tmpfile_clear(t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e));
    }
    /* mkstemp gives 0600; the output gets what fopen would give it */
    (void)fchmod(fd, (mode_t)(0666 & ~vc_io_umask()));
    FILE *fp = fdopen(fd, "wb");
    if (!fp) {
        int e = errno;
        close(fd);
        remove(t->tmp_path);
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
    if (!e && rename(t->tmp_path, t->final_path) != 0)
        e = errno ? errno : EIO;
    if (e) {
        remove(t->tmp_path);
        int rc = vc_error_set(err, VC_EIO, "%s: cannot write: %s", t->final_path,
                              strerror(e));
        vc_tmpfile_clear(t);
        return rc;
    }
    vc_tmpfile_clear(t);
    return VC_OK;
}

void vc_tmpfile_discard(vc_tmpfile *t)
{
    if (!t)
        return;
    if (t->fp)
        fclose((FILE *)t->fp);
    if (t->tmp_path)
        remove(t->tmp_path);
    vc_tmpfile_clear(t);
}
