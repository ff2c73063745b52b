/* Voronoi seeds: positions and region labels. */
#ifndef VORO_CRUST_SEEDS_H
#define VORO_CRUST_SEEDS_H

#include <stddef.h>
#include <stdint.h>
#include "vorocrust/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* n seeds; xyz holds 3*n coordinates; label[i] is the region of seed i.
 * Label 0 marks a seed whose cell is not kept (it only shapes its
 * neighbours, e.g. a VoroCrust seed outside the surface). */
typedef struct vc_seeds {
    int64_t n;
    double *xyz;
    int32_t *label;
} vc_seeds;

/* Allocates room for n seeds (labels set to 1). Returns VC_ENOMEM on failure. */
int vc_seeds_alloc(vc_seeds *s, int64_t n, vc_error *err);
void vc_seeds_free(vc_seeds *s);

/* out = the seeds of a followed by those of b (copies, labels kept).
 * Returns VC_OK or VC_ENOMEM (out then empty). */
int vc_seeds_concat(const vc_seeds *a, const vc_seeds *b, vc_seeds *out, vc_error *err);

/* Reads a CSV file with a header line and rows "x,y,z[,label]".
 * A missing label means 1. Errors name the file and line. Rules: the first
 * non-blank line is the header and must not start with a number; every row
 * has the field count of the first row (3 or 4); coordinates must be finite
 * numbers (strtod syntax), labels 32-bit integers; blank lines, spaces
 * around fields, CRLF line ends and a UTF-8 BOM are accepted; a file with
 * only a header gives 0 seeds. Codes: VC_EIO (cannot open/read),
 * VC_EFORMAT (empty file, no header, field count, not a number/integer),
 * VC_EINPUT (NaN or infinite coordinate), VC_ENOMEM. On failure *out is
 * left empty (n = 0, NULL arrays). */
int vc_seeds_read_csv(const char *path, vc_seeds *out, vc_error *err);

/* Writes "x,y,z,label" rows with a header, via a temporary file + rename. */
int vc_seeds_write_csv(const char *path, const vc_seeds *s, vc_error *err);

#ifdef __cplusplus
}
#endif
#endif
