/* Chunked, parallel formatting of CSV rows (see csv_rows.h). */
#include "io/csv_rows.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/io.h"
#include "io/tmpfile.h"

#define CSV_CHUNKS 64 /* chunks formatted per batch, then written in order */

int vc_csv_write_rows(const char *path, const char *header, int64_t n_rows, size_t row_max,
                      int rows_per_chunk, vc_csv_row_fn row, const void *ctx, vc_error *err)
{
    const size_t chunk_bytes = (size_t)rows_per_chunk * row_max;
    char *buf = malloc(CSV_CHUNKS * chunk_bytes);
    size_t *used = malloc(sizeof *used * CSV_CHUNKS);
    if (!buf || !used) {
        free(buf);
        free(used);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    vc_tmpfile t;
    int rc = vc_tmpfile_open(&t, path, err);
    if (rc) {
        free(buf);
        free(used);
        return rc;
    }
    int write_errno = 0;
    if (fputs(header, t.fp) == EOF)
        write_errno = errno ? errno : EIO;
    const int64_t batch = (int64_t)CSV_CHUNKS * rows_per_chunk;
    for (int64_t b0 = 0; b0 < n_rows && !write_errno; b0 += batch) {
        int64_t b1 = b0 + batch < n_rows ? b0 + batch : n_rows;
        int nchunks = (int)((b1 - b0 + rows_per_chunk - 1) / rows_per_chunk);
#pragma omp parallel for schedule(dynamic) if (nchunks > 1)
        for (int k = 0; k < nchunks; ++k) {
            char *out = buf + (size_t)k * chunk_bytes;
            size_t len = 0;
            int64_t r0 = b0 + (int64_t)k * rows_per_chunk;
            int64_t r1 = r0 + rows_per_chunk < b1 ? r0 + rows_per_chunk : b1;
            for (int64_t i = r0; i < r1; ++i) {
                int w = row(ctx, i, out + len, row_max);
                len += (w > 0 && (size_t)w < row_max) ? (size_t)w : 0;
            }
            used[k] = len;
        }
        for (int k = 0; k < nchunks && !write_errno; ++k)
            if (fwrite(buf + (size_t)k * chunk_bytes, 1, used[k], t.fp) != used[k])
                write_errno = errno ? errno : EIO;
    }
    free(buf);
    free(used);
    if (write_errno) {
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(write_errno));
    }
    return vc_tmpfile_commit(&t, err);
}
