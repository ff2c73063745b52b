/* Object File Format reader: "[ST][C][N][4]OFF" header, counts
 * "nv nf ne", nv vertex lines (extra values such as colours and normals
 * ignored), nf face lines "n i0 .. in-1 [colour]". '#' starts a comment.
 * Binary OFF and 4D vertices are left to OpenMesh. */
#include "surface/surface_internal.h"

#include <stdlib.h>
#include <string.h>

int vc_read_off(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err)
{
    vc_scan sc = {buf, buf + len, 1};
    char w[64];
    vc_scan_space(&sc, 1);
    size_t wl = vc_scan_word(&sc, w, sizeof w);
    if (wl < 3 || wl >= sizeof w || strcmp(w + wl - 3, "OFF") != 0)
        return vc_error_set(err, VC_EFORMAT, "%s: line %lld: missing OFF header", name, (long long)sc.line);
    if (strchr(w, '4') || strchr(w, 'n'))
        return VC_SURFACE_DEFER_TO_OPENMESH; /* 4OFF, nOFF */
    {
        vc_scan look = sc;
        vc_scan_blanks(&look);
        if (!strncmp(look.p, "BINARY", 6))
            return VC_SURFACE_DEFER_TO_OPENMESH;
    }
    int64_t nv, nf, ne;
    vc_scan_space(&sc, 1);
    if (!vc_scan_int(&sc, &nv) || !vc_scan_int(&sc, &nf) || nv < 0 || nf < 0)
        return vc_error_set(err, VC_EFORMAT, "%s: line %lld: malformed counts (expected 'nvertices nfaces nedges')",
                            name, (long long)sc.line);
    (void)vc_scan_int(&sc, &ne);
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
                rc = vc_error_set(err, VC_EFORMAT, "%s: line %lld: face has fewer than the %lld indices it announces",
                                  name, (long long)sc.line, (long long)n);
                break;
            }
        }
        if (!rc && vc_soup_add_face(s, face, n))
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    free(face);
    return rc;
}
