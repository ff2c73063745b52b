/* Wavefront OBJ reader: "v x y z [w]" and "f a b c ..." lines, where an
 * index may be written a, a/t, a//n or a/t/n and may be negative (counted
 * back from the last vertex read). Every other line type is ignored. */
#include "surface/surface_internal.h"

#include <stdlib.h>

int vc_read_obj(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err)
{
    vc_scan sc = {buf, buf + len, 1};
    int64_t *face = NULL, cap = 0;
    int rc = 0;
    s->expected_faces = -1;
    while (sc.p < sc.end) {
        vc_scan_blanks(&sc);
        const char *p = sc.p;
        if (p + 1 < sc.end && p[0] == 'v' && vc_scan_is_blank(p[1])) {
            sc.p += 1;
            double x, y, z;
            if (!vc_scan_double(&sc, &x) || !vc_scan_double(&sc, &y) || !vc_scan_double(&sc, &z)) {
                rc = vc_error_set(err, VC_EFORMAT, "%s: line %lld: malformed vertex (expected 'v x y z')",
                                  name, (long long)sc.line);
                break;
            }
            if ((rc = vc_soup_add_vertex(s, x, y, z)))
                break;
        } else if (p + 1 < sc.end && p[0] == 'f' && vc_scan_is_blank(p[1])) {
            sc.p += 1;
            int64_t n = 0, k;
            while (!vc_scan_at_eol(&sc)) {
                if (!vc_scan_int(&sc, &k) || k == 0) {
                    rc = vc_error_set(err, VC_EFORMAT, "%s: line %lld: malformed face index",
                                      name, (long long)sc.line);
                    goto done;
                }
                /* Skip "/t/n". */
                while (sc.p < sc.end && !vc_scan_is_blank(*sc.p) && *sc.p != '\n')
                    sc.p++;
                if (n == cap) {
                    cap = cap ? 2 * cap : 16;
                    int64_t *q = realloc(face, (size_t)cap * sizeof *q);
                    if (!q) {
                        rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                        goto done;
                    }
                    face = q;
                }
                face[n++] = k > 0 ? k - 1 : s->nv + k;
            }
            if (n < 3) {
                rc = vc_error_set(err, VC_EFORMAT, "%s: line %lld: face with %lld vertices (at least 3 needed)",
                                  name, (long long)sc.line, (long long)n);
                break;
            }
            if ((rc = vc_soup_add_face(s, face, n)))
                break;
        }
        vc_scan_next_line(&sc);
    }
done:
    free(face);
    if (rc == VC_ENOMEM)
        vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    return rc;
}
