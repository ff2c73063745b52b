/* STL reader. Binary when the size is 84 + 50 * (the uint32 count at byte
 * 80), whatever the header says (binary headers often start with
 * "solid"); otherwise ASCII when the file is text (no control bytes) ("solid ... facet normal ... outer loop vertex x y z
 * ... endloop endfacet ... endsolid"). Every facet gets its own three
 * vertices: the caller merges equal positions. */
#include "surface/surface_internal.h"
#include "io/text_escape.h"

#include <string.h>
#include <strings.h>


static int read_binary(const char *name, const unsigned char *b, uint32_t n, vc_soup *s, vc_error *err)
{
    s->expected_faces = n;
    for (uint32_t t = 0; t < n; t++) {
        const unsigned char *r = b + 84 + 50 * (size_t)t + 12; /* skip the normal */
        int64_t v[3];
        for (int k = 0; k < 3; k++) {
            v[k] = s->nv;
            if (vc_soup_add_vertex(s, vc_le_float(r + 12 * k), vc_le_float(r + 12 * k + 4), vc_le_float(r + 12 * k + 8)))
                return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
        }
        if (vc_soup_add_face(s, v, 3))
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    return 0;
}

/* Keywords in any case: some writers use upper case ("SOLID", "FACET
 * NORMAL"), and readers such as VTK's accept them. */
static int keyword(const char *w, const char *k)
{
    return !strcasecmp(w, k);
}

static int read_ascii(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err)
{
    vc_scan sc = {buf, buf + len, 1};
    char w[32];
    int64_t face[3], n = -1; /* n = -1 outside a facet */
    int64_t facet_line = 0;
    s->expected_faces = -1;
    for (;;) {
        vc_scan_space(&sc, 0);
        if (sc.p >= sc.end)
            break;
        size_t wl = vc_scan_word(&sc, w, sizeof w);
        if (keyword(w, "facet")) {
            if (n >= 0)
                return vc_error_set(err, VC_EFORMAT, "%s: line %lld: 'facet' inside the facet of line %lld",
                                    name, (long long)sc.line, (long long)facet_line);
            n = 0;
            facet_line = sc.line;
            vc_scan_next_line(&sc); /* the normal */
        } else if (keyword(w, "vertex")) {
            double x, y, z;
            if (n < 0 || n >= 3)
                return vc_error_set(err, VC_EFORMAT, "%s: line %lld: 'vertex' %s", name, (long long)sc.line,
                                    n < 0 ? "outside a facet" : "beyond the third of a facet");
            if (!vc_scan_double(&sc, &x) || !vc_scan_double(&sc, &y) || !vc_scan_double(&sc, &z))
                return vc_error_set(err, VC_EFORMAT, "%s: line %lld: malformed vertex (expected 'vertex x y z')",
                                    name, (long long)sc.line);
            face[n++] = s->nv;
            if (vc_soup_add_vertex(s, x, y, z))
                return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
        } else if (keyword(w, "endfacet")) {
            if (n != 3)
                return vc_error_set(err, VC_EFORMAT, "%s: line %lld: facet with %lld vertices (3 needed)",
                                    name, (long long)facet_line, (long long)(n < 0 ? 0 : n));
            if (vc_soup_add_face(s, face, 3))
                return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            n = -1;
        } else if (keyword(w, "solid")) {
            /* each solid NAME block is a group of triangles (a patch) */
            if (vc_soup_set_group_rest(s, &sc))
                return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            vc_scan_next_line(&sc);
        } else if (keyword(w, "endsolid")) {
            vc_scan_next_line(&sc); /* the solid's name */
        } else if (keyword(w, "outer") || keyword(w, "loop") || keyword(w, "endloop")) {
            /* structure only */
        } else {
            char shown[64];
            return vc_error_set(err, VC_EFORMAT, "%s: line %lld: unexpected word '%s' in ASCII STL",
                                name, (long long)sc.line, vc_escape_span(w, wl < sizeof w ? wl : sizeof w - 1,
                                                                         shown, sizeof shown));
        }
    }
    if (n >= 0)
        return vc_error_set(err, VC_EFORMAT, "%s: facet of line %lld is not closed by 'endfacet'",
                            name, (long long)facet_line);
    return 0;
}

int vc_read_stl(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err)
{
    const unsigned char *b = (const unsigned char *)buf;
    if (len >= 84) {
        uint32_t n = vc_le32(b + 80);
        if ((uint64_t)len == 84 + 50 * (uint64_t)n)
            return read_binary(name, b, n, s, err);
    }
    size_t i = 0;
    while (i < len && (vc_scan_is_blank(buf[i]) || buf[i] == '\n'))
        i++;
    /* ASCII STL is text: a file that starts with "solid" but holds control
     * bytes (binary writers often start their 80-byte header with "solid")
     * is a binary STL whose size does not match its triangle count. */
    int text = 1;
    for (size_t k = 0; k < len && text; k++) {
        unsigned char c = (unsigned char)buf[k];
        if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') || c == 0x7f)
            text = 0;
    }
    if (text && len - i >= 5 && !strncasecmp(buf + i, "solid", 5))
        return read_ascii(name, buf, len, s, err);
    if (len >= 84)
        return vc_error_set(err, VC_EFORMAT,
                            "%s: malformed binary STL: the header announces %lu triangles (%llu bytes) but the file has %llu bytes",
                            name, (unsigned long)vc_le32(b + 80), 84 + 50 * (unsigned long long)vc_le32(b + 80),
                            (unsigned long long)len);
    return vc_error_set(err, VC_EFORMAT, "%s: malformed STL: neither ASCII text starting with 'solid' nor a binary "
                        "STL (84 bytes at least)", name);
}
