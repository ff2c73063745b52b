/* PLY reader (ASCII, binary little and big endian). The header is parsed
 * into elements and properties so that any element and property can be
 * skipped; the vertex element gives x, y, z and the face element its
 * "vertex_indices" (or "vertex_index") list, and the face's group from an
 * integer property patch, group, region, material, label or tag (the
 * group "patch3" for patch 3). */
#include "surface/surface_internal.h"
#include "io/text_escape.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 };

typedef struct ply_prop {
    int type;       /* value type */
    int count_type; /* list length type, T_NONE for a scalar */
    int role;       /* 0 other, 1..3 x/y/z, 4 face indices, 5 the face's group */
    char name[16];  /* of a group property */
} ply_prop;

#define PLY_MAX_PROPS 64
#define PLY_MAX_ELEMS 16

typedef struct ply_elem {
    char name[32];
    int64_t count;
    int kind; /* 0 other, 1 vertex, 2 face */
    int n_props;
    ply_prop props[PLY_MAX_PROPS];
} ply_elem;

static int type_of(const char *w)
{
    static const struct { const char *n; int t; } tab[] = {
        {"char", T_I8}, {"int8", T_I8}, {"uchar", T_U8}, {"uint8", T_U8},
        {"short", T_I16}, {"int16", T_I16}, {"ushort", T_U16}, {"uint16", T_U16},
        {"int", T_I32}, {"int32", T_I32}, {"uint", T_U32}, {"uint32", T_U32},
        {"float", T_F32}, {"float32", T_F32}, {"double", T_F64}, {"float64", T_F64}};
    for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
        if (!strcmp(w, tab[i].n))
            return tab[i].t;
    return T_NONE;
}

static size_t type_size(int t)
{
    static const size_t sz[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sz[t];
}

/* Decodes one binary value; big selects big-endian byte order. */
static double decode(const unsigned char *p, int t, int big)
{
    unsigned char b[8];
    size_t n = type_size(t);
    for (size_t i = 0; i < n; i++)
        b[i] = big ? p[n - 1 - i] : p[i];
    union { int8_t i8; uint8_t u8; int16_t i16; uint16_t u16; int32_t i32; uint32_t u32; float f; double d; } u;
    /* Assemble a little-endian value into host order. */
    uint64_t v = 0;
    for (size_t i = 0; i < n; i++)
        v |= (uint64_t)b[i] << (8 * i);
    switch (t) {
    case T_I8: u.u8 = (uint8_t)v; return u.i8;
    case T_U8: return (double)(uint8_t)v;
    case T_I16: u.u16 = (uint16_t)v; return u.i16;
    case T_U16: return (double)(uint16_t)v;
    case T_I32: u.u32 = (uint32_t)v; return u.i32;
    case T_U32: return (double)(uint32_t)v;
    case T_F32: { uint32_t w = (uint32_t)v; memcpy(&u.f, &w, 4); return u.f; }
    default: memcpy(&u.d, &v, 8); return u.d;
    }
}

static int is_int_type(int t) { return t != T_F32 && t != T_F64; }

int vc_read_ply(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err)
{
    vc_scan sc = {buf, buf + len, 1};
    char w[64], w2[64], w3[64];
    int format = -1; /* 0 ascii, 1 little, 2 big endian */
    ply_elem *el = calloc(PLY_MAX_ELEMS, sizeof *el);
    int ne = 0, rc = 0;
    int64_t *face = NULL, cap = 0;
    if (!el)
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
#define FAIL(code, ...) do { rc = vc_error_set(err, code, __VA_ARGS__); goto done; } while (0)
    vc_scan_word(&sc, w, sizeof w);
    if (strcmp(w, "ply"))
        FAIL(VC_EFORMAT, "%s: line 1: missing 'ply' header", name);
    s->index_base = 0;
    for (;;) {
        vc_scan_next_line(&sc);
        if (sc.p >= sc.end)
            FAIL(VC_EFORMAT, "%s: header not closed by 'end_header'", name);
        vc_scan_word(&sc, w, sizeof w);
        if (!strcmp(w, "end_header")) {
            vc_scan_next_line(&sc);
            break;
        } else if (!strcmp(w, "format")) {
            vc_scan_word(&sc, w2, sizeof w2);
            format = !strcmp(w2, "ascii") ? 0 : !strcmp(w2, "binary_little_endian") ? 1
                   : !strcmp(w2, "binary_big_endian") ? 2 : -2;
            if (format == -2) {
                char shown[96];
                FAIL(VC_EFORMAT, "%s: line %lld: unknown PLY format '%s'", name, (long long)sc.line,
                     vc_escape_str(w2, shown, sizeof shown));
            }
        } else if (!strcmp(w, "element")) {
            int64_t n;
            if (ne == PLY_MAX_ELEMS)
                FAIL(VC_EFORMAT, "%s: line %lld: more than %d elements", name, (long long)sc.line, PLY_MAX_ELEMS);
            {
                char raw[32];
                vc_scan_word(&sc, raw, sizeof raw);
                vc_escape_str(raw, el[ne].name, sizeof el[ne].name);
            }
            if (!vc_scan_int(&sc, &n) || n < 0)
                FAIL(VC_EFORMAT, "%s: line %lld: malformed element count", name, (long long)sc.line);
            el[ne].count = n;
            el[ne].kind = !strcmp(el[ne].name, "vertex") ? 1 : !strcmp(el[ne].name, "face") ? 2 : 0;
            ne++;
        } else if (!strcmp(w, "property")) {
            if (ne == 0)
                FAIL(VC_EFORMAT, "%s: line %lld: property before any element", name, (long long)sc.line);
            ply_elem *e = &el[ne - 1];
            if (e->n_props == PLY_MAX_PROPS)
                FAIL(VC_EFORMAT, "%s: line %lld: too many properties", name, (long long)sc.line);
            ply_prop *pr = &e->props[e->n_props++];
            memset(pr, 0, sizeof *pr);
            vc_scan_word(&sc, w2, sizeof w2);
            if (!strcmp(w2, "list")) {
                vc_scan_word(&sc, w2, sizeof w2);
                vc_scan_word(&sc, w3, sizeof w3);
                pr->count_type = type_of(w2);
                pr->type = type_of(w3);
                if (pr->count_type == T_NONE || pr->type == T_NONE || !is_int_type(pr->count_type))
                    FAIL(VC_EFORMAT, "%s: line %lld: unknown list property types", name, (long long)sc.line);
            } else {
                pr->type = type_of(w2);
                if (pr->type == T_NONE) {
                    char shown[96];
                    FAIL(VC_EFORMAT, "%s: line %lld: unknown property type '%s'", name, (long long)sc.line,
                         vc_escape_str(w2, shown, sizeof shown));
                }
            }
            vc_scan_word(&sc, w3, sizeof w3);
            if (e->kind == 1 && !pr->count_type && w3[0] >= 'x' && w3[0] <= 'z' && !w3[1])
                pr->role = 1 + (w3[0] - 'x');
            if (e->kind == 2 && pr->count_type && (!strcmp(w3, "vertex_indices") || !strcmp(w3, "vertex_index")))
                pr->role = 4;
            /* an integer face property that names the face's group (the
             * first of them): its values are the boundary patches */
            static const char *const group_props[] = {"patch", "group", "region", "material",
                                                      "label", "tag"};
            if (e->kind == 2 && !pr->count_type && is_int_type(pr->type)) {
                int taken = 0;
                for (int k = 0; k + 1 < e->n_props; k++)
                    taken |= e->props[k].role == 5;
                for (size_t k = 0; !taken && k < sizeof group_props / sizeof *group_props; k++)
                    if (!strcmp(w3, group_props[k])) {
                        pr->role = 5;
                        snprintf(pr->name, sizeof pr->name, "%s", group_props[k]);
                    }
            }
        }
        /* comment, obj_info and unknown keywords are ignored */
    }
    if (format < 0)
        FAIL(VC_EFORMAT, "%s: PLY header without a 'format' line", name);
    for (int i = 0; i < ne; i++) {
        int roles = 0;
        for (int k = 0; k < el[i].n_props; k++)
            roles |= 1 << el[i].props[k].role;
        if (el[i].kind == 1 && (roles & 14) != 14)
            FAIL(VC_EFORMAT, "%s: PLY vertex element without x, y and z properties", name);
        if (el[i].kind == 2) {
            if (!(roles & 16))
                FAIL(VC_EFORMAT, "%s: PLY face element without a vertex_indices list", name);
            s->expected_faces = (s->expected_faces < 0 ? 0 : s->expected_faces) + el[i].count;
        }
    }

    const unsigned char *p = (const unsigned char *)sc.p, *end = (const unsigned char *)sc.end;
    /* Nothing is reserved from the counts (rows past the end of the file
     * are reported where they run out), but an element without properties
     * would take no bytes per row: 1e18 such rows would loop for ever.
     * Every row takes at least a byte per value in binary (a list: its
     * length), two in ascii ("0 "). */
    {
        uint64_t left = (uint64_t)(end - p) + (format == 0); /* the last value needs no blank */
        for (int i = 0; i < ne; i++) {
            uint64_t row = 0;
            for (int k = 0; k < el[i].n_props; k++)
                row += format == 0 ? 2 : type_size(el[i].props[k].count_type ? el[i].props[k].count_type
                                                                            : el[i].props[k].type);
            if (el[i].count > 0 && row == 0)
                FAIL(VC_EFORMAT, "%s: PLY element '%s' has %lld rows but no properties", name, el[i].name,
                     (long long)el[i].count);
            if (row && (uint64_t)el[i].count > left / row)
                break; /* the rows run past the end: reported where they do */
            left -= (uint64_t)el[i].count * row;
        }
    }
    for (int i = 0; i < ne; i++) {
        ply_elem *e = &el[i];
        for (int64_t r = 0; r < e->count; r++) {
            double xyz[3] = {0, 0, 0};
            int64_t nface = 0;
            if (format == 0) {
                vc_scan_space(&sc, 0);
                if (sc.p >= sc.end)
                    FAIL(VC_EFORMAT, "%s: file ends inside element '%s' (%lld of %lld read)",
                         name, e->name, (long long)r, (long long)e->count);
            }
            for (int k = 0; k < e->n_props; k++) {
                ply_prop *pr = &e->props[k];
                int64_t nval = 1;
                if (pr->count_type) {
                    double c;
                    if (format == 0) {
                        if (!vc_scan_double(&sc, &c))
                            FAIL(VC_EFORMAT, "%s: line %lld: malformed list length", name, (long long)sc.line);
                    } else {
                        if ((size_t)(end - p) < type_size(pr->count_type))
                            FAIL(VC_EFORMAT, "%s: file ends inside element '%s'", name, e->name);
                        c = decode(p, pr->count_type, format == 2);
                        p += type_size(pr->count_type);
                    }
                    /* (NaN fails every comparison: tested this way round) */
                    if (!(c >= 0 && c <= 1e6) || c != (double)(int64_t)c)
                        FAIL(VC_EFORMAT, "%s: element '%s' %lld: list length %g is not an integer from 0 to 1e6",
                             name, e->name, (long long)r, c);
                    nval = (int64_t)c;
                    if (pr->role == 4) {
                        if (nval < 3)
                            FAIL(VC_EFORMAT, "%s: face %lld has %lld vertices (at least 3 needed)",
                                 name, (long long)r, (long long)nval);
                        if (nval > cap) {
                            int64_t *q = realloc(face, (size_t)nval * sizeof *q);
                            if (!q)
                                FAIL(VC_ENOMEM, "%s: out of memory", name);
                            face = q;
                            cap = nval;
                        }
                        nface = nval;
                    }
                }
                for (int64_t j = 0; j < nval; j++) {
                    double v;
                    if (format == 0) {
                        if (!vc_scan_double(&sc, &v))
                            FAIL(VC_EFORMAT, "%s: line %lld: malformed value in element '%s'",
                                 name, (long long)sc.line, e->name);
                    } else {
                        if ((size_t)(end - p) < type_size(pr->type))
                            FAIL(VC_EFORMAT, "%s: file ends inside element '%s' (%lld of %lld read)",
                                 name, e->name, (long long)r, (long long)e->count);
                        v = decode(p, pr->type, format == 2);
                        p += type_size(pr->type);
                    }
                    if (pr->role >= 1 && pr->role <= 3)
                        xyz[pr->role - 1] = v;
                    else if (pr->role == 5) {
                        char g[48];
                        const int n = snprintf(g, sizeof g, "%s%lld", pr->name,
                                               (long long)(v > -9e18 && v < 9e18 ? v : 0));
                        if (vc_soup_set_group(s, g, (size_t)n))
                            FAIL(VC_ENOMEM, "%s: out of memory", name);
                    }
                    else if (pr->role == 4) {
                        if (!(v > -9e18 && v < 9e18) || v != (double)(int64_t)v)
                            FAIL(VC_EFORMAT, "%s: face %lld: vertex index %g is not an integer",
                                 name, (long long)r, v);
                        face[j] = (int64_t)v;
                    }
                }
            }
            if (e->kind == 1 && vc_soup_add_vertex(s, xyz[0], xyz[1], xyz[2]))
                FAIL(VC_ENOMEM, "%s: out of memory", name);
            if (e->kind == 2 && vc_soup_add_face(s, face, nface))
                FAIL(VC_ENOMEM, "%s: out of memory", name);
        }
    }
    if (format == 0) {
        vc_scan_space(&sc, 0);
        if (sc.p < sc.end)
            FAIL(VC_EFORMAT, "%s: line %lld: data after the last element (more rows than the header "
                 "announces?)", name, (long long)sc.line);
    } else if (p != end) {
        FAIL(VC_EFORMAT, "%s: %llu bytes after the last element (more rows than the header announces?)",
             name, (unsigned long long)(end - p));
    }
#undef FAIL
done:
    free(face);
    free(el);
    return rc;
}
