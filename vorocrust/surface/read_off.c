/* Object File Format reader: "[ST][C][N]OFF" header, counts
 * "nv nf ne", nv vertex lines (extra values such as colours and normals
 * ignored), nf face lines "n i0 .. in-1 [colour]". '#' starts a comment.
 * Anything but blanks and comments after the last face (more faces than
 * the header announces) is refused.
 *
 * Binary OFF ("[ST][C][N]OFF BINARY") is read here too, in the layout
 * OpenMesh writes and reads: after the header line, little-endian uint32
 * nv, nf, ne; per vertex float32 x, y, z, then float32 normal (N), uint32
 * r, g, b (C) and float32 s, t (ST); per face uint32 n then n uint32
 * indices. Every count is checked against the bytes the file has before
 * anything is allocated (OpenMesh's own reader reserves what the header
 * asks, gigabytes for a 100-byte file, and loops on faces past the end).
 * 4OFF and nOFF (vertex dimension other than 3) are refused. */
#include "surface/surface_internal.h"
#include "io/text_escape.h"

#include <stdlib.h>
#include <string.h>

/* Parses the header keyword [ST][C][N][4][n]OFF; returns 0 when w is not
 * one. *extra: float32 or uint32 words per binary vertex beyond x, y, z. */
static int off_keyword(const char *w, int *extra, int *dim_not_3)
{
    *extra = 0;
    *dim_not_3 = 0;
    if (w[0] == 'S' && w[1] == 'T') {
        *extra += 2;
        w += 2;
    }
    if (*w == 'C') {
        *extra += 3;
        w++;
    }
    if (*w == 'N') {
        *extra += 3;
        w++;
    }
    if (*w == '4') {
        *dim_not_3 = 1;
        w++;
    }
    if (*w == 'n') {
        *dim_not_3 = 1;
        w++;
    }
    return !strcmp(w, "OFF");
}


/* Binary OFF from b (just after the header line) to end. */
static int read_binary(const char *name, const unsigned char *b, const unsigned char *end, int extra,
                       vc_soup *s, vc_error *err)
{
    size_t left = (size_t)(end - b);
    if (left < 12)
        return vc_error_set(err, VC_EFORMAT, "%s: binary OFF: file ends inside the counts", name);
    uint64_t nv = vc_le32(b), nf = vc_le32(b + 4);
    b += 12;
    left -= 12;
    /* A vertex takes 4 * (3 + extra) bytes, a face at least 16 (n and three
     * indices): both counts must fit in what is left (64-bit arithmetic of
     * 32-bit counts: no overflow). */
    uint64_t vbytes = 4 * (uint64_t)(3 + extra);
    if (nv * vbytes > left || nf * 16 > left - nv * vbytes)
        return vc_error_set(err, VC_EFORMAT,
                            "%s: binary OFF: the header announces %llu vertices and %llu faces "
                            "(at least %llu bytes) but %llu bytes follow it",
                            name, (unsigned long long)nv, (unsigned long long)nf,
                            (unsigned long long)(nv * vbytes + nf * 16), (unsigned long long)left);
    s->expected_faces = (int64_t)nf;
    for (uint64_t i = 0; i < nv; i++) {
        if (vc_soup_add_vertex(s, vc_le_float(b), vc_le_float(b + 4), vc_le_float(b + 8)))
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
        b += vbytes;
    }
    int64_t *face = NULL, cap = 0;
    int rc = 0;
    for (uint64_t f = 0; f < nf && !rc; f++) {
        left = (size_t)(end - b);
        if (left < 4) {
            rc = vc_error_set(err, VC_EFORMAT, "%s: binary OFF: file ends after %llu of %llu faces",
                              name, (unsigned long long)f, (unsigned long long)nf);
            break;
        }
        uint64_t n = vc_le32(b);
        b += 4;
        left -= 4;
        if (n < 3 || n * 4 > left) {
            rc = vc_error_set(err, VC_EFORMAT,
                              n < 3 ? "%s: binary OFF: face %llu has %llu vertices (at least 3 needed)"
                                    : "%s: binary OFF: face %llu announces %llu vertices past the end of the file",
                              name, (unsigned long long)f, (unsigned long long)n);
            break;
        }
        if ((int64_t)n > cap) {
            int64_t *q = realloc(face, (size_t)n * sizeof *q);
            if (!q) {
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                break;
            }
            face = q;
            cap = (int64_t)n;
        }
        for (uint64_t j = 0; j < n; j++)
            face[j] = vc_le32(b + 4 * j);
        b += 4 * n;
        if (vc_soup_add_face(s, face, (int64_t)n))
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    free(face);
    if (!rc && b != end)
        rc = vc_error_set(err, VC_EFORMAT, "%s: binary OFF: %llu bytes after the %llu faces the header announces",
                          name, (unsigned long long)(end - b), (unsigned long long)nf);
    return rc;
}

int vc_read_off(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err)
{
    vc_scan sc = {buf, buf + len, 1};
    char w[64];
    vc_scan_space(&sc, 1);
    size_t wl = vc_scan_word(&sc, w, sizeof w);
    int extra, dim_not_3;
    s->index_base = 0;
    if (wl >= sizeof w || !off_keyword(w, &extra, &dim_not_3)) {
        char shown[64];
        return vc_error_set(err, VC_EFORMAT, "%s: line %lld: missing OFF header (found '%s')", name,
                            (long long)sc.line, vc_escape_str(w, shown, sizeof shown));
    }
    if (dim_not_3)
        return vc_error_set(err, VC_EFORMAT, "%s: line %lld: %s (vertex dimension other than 3) is not supported",
                            name, (long long)sc.line, w);
    {
        vc_scan look = sc;
        vc_scan_blanks(&look);
        if (look.end - look.p >= 6 && !strncmp(look.p, "BINARY", 6)) {
            vc_scan_next_line(&look);
            return read_binary(name, (const unsigned char *)look.p, (const unsigned char *)look.end,
                               extra, s, err);
        }
    }
    int64_t nv, nf, ne;
    vc_scan_space(&sc, 1);
    if (!vc_scan_int(&sc, &nv) || !vc_scan_int(&sc, &nf) || nv < 0 || nf < 0)
        return vc_error_set(err, VC_EFORMAT, "%s: line %lld: malformed counts (expected 'nvertices nfaces nedges')",
                            name, (long long)sc.line);
    (void)vc_scan_int(&sc, &ne);
    /* Nothing is reserved from the counts: the arrays grow as lines are
     * read, and a count beyond the file ends at its end. */
    s->expected_faces = nf;
    for (int64_t i = 0; i < nv; i++) {
        vc_scan_next_line(&sc);
        vc_scan_space(&sc, 1);
        double x, y, z;
        if (sc.p >= sc.end)
            return vc_error_set(err, VC_EFORMAT, "%s: file ends after %lld of %lld vertices",
                                name, (long long)i, (long long)nv);
        if (!vc_scan_double(&sc, &x) || !vc_scan_double(&sc, &y) || !vc_scan_double(&sc, &z))
            return vc_error_set(err, VC_EFORMAT, "%s: line %lld: malformed vertex (expected 'x y z')",
                                name, (long long)sc.line);
        if (vc_soup_add_vertex(s, x, y, z))
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    int64_t *face = NULL, cap = 0;
    int rc = 0;
    for (int64_t f = 0; f < nf && !rc; f++) {
        vc_scan_next_line(&sc);
        vc_scan_space(&sc, 1);
        int64_t n;
        if (sc.p >= sc.end) {
            rc = vc_error_set(err, VC_EFORMAT, "%s: file ends after %lld of %lld faces",
                              name, (long long)f, (long long)nf);
            break;
        }
        if (!vc_scan_int(&sc, &n) || n < 3 || n > 1000000) {
            rc = vc_error_set(err, VC_EFORMAT, "%s: line %lld: malformed face (expected 'n i0 .. in-1', n >= 3)",
                              name, (long long)sc.line);
            break;
        }
        if (n > cap) {
            int64_t *q = realloc(face, (size_t)n * sizeof *q);
            if (!q) {
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                break;
            }
            face = q;
            cap = n;
        }
        for (int64_t j = 0; j < n; j++) {
            if (!vc_scan_int(&sc, &face[j])) {
                rc = vc_error_set(err, VC_EFORMAT,
                                  "%s: line %lld: face has fewer than the %lld integer indices it announces",
                                  name, (long long)sc.line, (long long)n);
                break;
            }
        }
        if (!rc && vc_soup_add_face(s, face, n))
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    free(face);
    if (!rc) {
        /* Only blanks and comments may follow the last face. */
        vc_scan_next_line(&sc);
        vc_scan_space(&sc, 1);
        if (sc.p < sc.end)
            rc = vc_error_set(err, VC_EFORMAT,
                              "%s: line %lld: data after the %lld faces the header announces "
                              "(more faces than the header counts?)",
                              name, (long long)sc.line, (long long)nf);
    }
    return rc;
}
