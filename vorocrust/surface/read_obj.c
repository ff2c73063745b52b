/* Wavefront OBJ reader: "v x y z [w]" and "f a b c ..." lines, where an
 * index may be written a, a/t, a//n or a/t/n (a, t and n integers) and may
 * be negative (counted back from the last vertex read; one reaching before
 * the first vertex is refused with its value). "g", "o" or "usemtl" lines
 * name the groups of the faces that follow (see group_keyword). Every
 * other line type is ignored. */
#include "surface/surface_internal.h"

#include "util/number_span.h"

#include <stdlib.h>
#include <string.h>

/* Parses an optional integer at *p (for the t and n of a/t/n); returns 0
 * when the text there is neither empty nor an integer. */
static int obj_sub_index(vc_scan *sc)
{
    if (sc->p >= sc->end || *sc->p == '/' || vc_scan_is_end(sc, sc->p))
        return 1;
    long long k;
    int erange;
    size_t used = vc_strtoll_span(sc->p, sc->end, &k, &erange);
    if (used == 0 || erange)
        return 0;
    sc->p += used;
    return 1;
}

/* Parses one face vertex "a", "a/t", "a//n" or "a/t/n" into *k (a); 0 when
 * malformed (a not an integer, e.g. "2.7", or junk after it). */
static int obj_face_index(vc_scan *sc, int64_t *k)
{
    vc_scan_blanks(sc);
    if (sc->p >= sc->end || *sc->p == '\n')
        return 0;
    long long v;
    int erange;
    size_t used = vc_strtoll_span(sc->p, sc->end, &v, &erange);
    if (used == 0 || erange)
        return 0;
    sc->p += used;
    for (int slash = 0; slash < 2 && sc->p < sc->end && *sc->p == '/'; slash++) {
        sc->p++;
        if (!obj_sub_index(sc))
            return 0;
    }
    if (!vc_scan_is_end(sc, sc->p))
        return 0;
    *k = (int64_t)v;
    return 1;
}

/* Which statement names the groups: "g" if the file has one, else "o",
 * else "usemtl" (0 when none): files that give several (an object made
 * of materials) group by the most specific the exporter meant as parts. */
static const char *group_keyword(const char *buf, size_t len)
{
    static const char *const kw[3] = {"g", "o", "usemtl"};
    for (int k = 0; k < 3; k++) {
        const size_t n = strlen(kw[k]);
        for (const char *p = buf; p && p + n < buf + len;) {
            while (p < buf + len && (*p == ' ' || *p == '\t'))
                p++;
            if (p + n < buf + len && !memcmp(p, kw[k], n) && (p[n] == ' ' || p[n] == '\t'))
                return kw[k];
            p = memchr(p, '\n', (size_t)(buf + len - p));
            if (p)
                p++;
        }
    }
    return NULL;
}

int vc_read_obj(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err)
{
    vc_scan sc = {buf, buf + len, 1};
    const char *group_kw = group_keyword(buf, len);
    const size_t group_kw_len = group_kw ? strlen(group_kw) : 0;
    int64_t *face = NULL, cap = 0;
    int rc = 0;
    s->expected_faces = -1;
    s->index_base = 1;
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
        } else if (group_kw && p + group_kw_len < sc.end && !memcmp(p, group_kw, group_kw_len) &&
                   vc_scan_is_blank(p[group_kw_len])) {
            sc.p += group_kw_len;
            if ((rc = vc_soup_set_group_rest(s, &sc)))
                break;
        } else if (p + 1 < sc.end && p[0] == 'f' && vc_scan_is_blank(p[1])) {
            sc.p += 1;
            int64_t n = 0, k;
            while (!vc_scan_at_eol(&sc)) {
                if (!obj_face_index(&sc, &k)) {
                    rc = vc_error_set(err, VC_EFORMAT,
                                      "%s: line %lld: malformed face index (expected an integer "
                                      "a, a/t, a//n or a/t/n)", name, (long long)sc.line);
                    goto done;
                }
                if (k == 0) {
                    rc = vc_error_set(err, VC_EFORMAT,
                                      "%s: line %lld: face index 0 (OBJ indices start at 1)",
                                      name, (long long)sc.line);
                    goto done;
                }
                if (k < 0 && k < -s->nv) {
                    rc = vc_error_set(err, VC_EINPUT,
                                      "%s: line %lld: relative face index %lld refers before the "
                                      "first vertex (%lld vertices read so far)",
                                      name, (long long)sc.line, (long long)k, (long long)s->nv);
                    goto done;
                }
                if (n == cap) {
                    if (cap > ((int64_t)1 << 40)) {
                        rc = vc_error_set(err, VC_EFORMAT, "%s: line %lld: face with too many vertices",
                                          name, (long long)sc.line);
                        goto done;
                    }
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
