/* Writing a CSV file of many numeric rows fast: rows are formatted on
 * threads, chunk by chunk, into a buffer, then written in order, through a
 * temporary file renamed at the end (vorocrust/io/csv_rows.c). */
#ifndef VORO_CRUST_IO_CSV_ROWS_H
#define VORO_CRUST_IO_CSV_ROWS_H

#include <stddef.h>
#include <stdint.h>

#include "vorocrust/error.h"

/* Formats row i into out (room bytes, at least row_max); returns the
 * number of bytes written (snprintf's result). */
typedef int (*vc_csv_row_fn)(const void *ctx, int64_t i, char *out, size_t room);

/* Writes header, then rows 0 .. n_rows-1, to path. rows_per_chunk rows
 * are formatted per task. The output does not depend on the thread count.
 * Fails with VC_ENOMEM or VC_EIO (naming path); path is then untouched. */
int vc_csv_write_rows(const char *path, const char *header, int64_t n_rows, size_t row_max,
                      int rows_per_chunk, vc_csv_row_fn row, const void *ctx, vc_error *err);

#endif
