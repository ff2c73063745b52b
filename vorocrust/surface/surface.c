/* Reading a surface file: format dispatch, validation of the polygon soup,
 * triangulation, merging of equal vertices, memory.
 *
 * The C readers of this folder read OBJ, OFF, STL and PLY, the only
 * formats accepted; OpenMesh (openmesh_reader.cpp, which explains the
 * choice) reads the same files again on request, to cross-check them. */
#include "vorocrust/surface.h"
#include "surface/surface_internal.h"
#include "io/text_escape.h"
#include "util/radix_sort.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void vc_surface_free(vc_surface *s)
{
    if (!s)
        return;
    free(s->xyz);
    free(s->tri);
    free(s->tri_group);
    free(s->group_name);
    memset(s, 0, sizeof *s);
}

void vc_surface_report_warn(vc_surface_report *rep, const char *fmt, ...)
{
    if (!rep || rep->n_warnings >= VC_SURFACE_MAX_WARNINGS)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(rep->warnings[rep->n_warnings++], VC_ERROR_LEN, fmt, ap);
    va_end(ap);
}

/* Reads the whole file, with a NUL byte after the last one. */
static int slurp(const char *path, const char *name, char **buf, size_t *len, vc_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return vc_error_set(err, VC_EIO, "%s: cannot open (%s)", name, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f);
        return vc_error_set(err, VC_EIO, "%s: is a directory", name);
    }
    char *b = NULL;
    size_t n = 0, cap = 0;
    for (;;) {
        if (cap - n < 65536) {
            if (cap > SIZE_MAX / 4) {
                free(b);
                fclose(f);
                return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            }
            size_t c = cap ? 2 * cap : 1 << 20;
            char *q = realloc(b, c + 1);
            if (!q) {
                free(b);
                fclose(f);
                return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            }
            b = q;
            cap = c;
        }
        size_t r = fread(b + n, 1, cap - n, f);
        n += r;
        if (r == 0)
            break;
    }
    int bad = ferror(f) ? (errno ? errno : EIO) : 0;
    fclose(f);
    if (bad) {
        free(b);
        return vc_error_set(err, VC_EIO, "%s: read error (%s)", name, strerror(bad));
    }
    b[n] = '\0';
    *buf = b;
    *len = n;
    return 0;
}

/* Lower-case extension of path without the dot ("" when none). */
static void extension(const char *path, char *ext, size_t cap)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    size_t i = 0;
    if (dot && dot != base)
        for (dot++; *dot && i + 1 < cap; dot++)
            ext[i++] = (char)tolower((unsigned char)*dot);
    ext[i] = '\0';
}

static double dist2(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* Validates the soup and turns it into triangles: quads are split along
 * their shorter diagonal, larger polygons fanned from their first vertex. */
static int soup_to_surface(const char *name, const vc_soup *sp, vc_surface *out,
                           vc_surface_report *rep, vc_error *err)
{
    for (int64_t i = 0; i < 3 * sp->nv; i++)
        if (!isfinite(sp->xyz[i]))
            return vc_error_set(err, VC_EINPUT, "%s: vertex %lld has a non-finite coordinate (%g)",
                                name, (long long)(i / 3 + 1), sp->xyz[i]);
    int64_t nt = 0, npoly = 0;
    for (int64_t f = 0; f < sp->nf; f++) {
        int64_t n = sp->off[f + 1] - sp->off[f];
        if (n < 3)
            return vc_error_set(err, VC_EFORMAT, "%s: face %lld has %lld vertices (at least 3 needed)",
                                name, (long long)(f + 1), (long long)n);
        nt += n - 2;
        npoly += n > 3;
        for (int64_t k = sp->off[f]; k < sp->off[f + 1]; k++)
            if (sp->idx[k] < 0 || sp->idx[k] >= sp->nv)
                /* The index as the file writes it (0- or 1-based; a
                                 * 1-based reader stored it minus 1: no overflow). */
                return vc_error_set(err, VC_EINPUT,
                                    "%s: face %lld refers to vertex %lld, but the file has %lld vertices "
                                    "(numbered from %d)",
                                    name, (long long)(f + 1), (long long)sp->idx[k] + sp->index_base,
                                    (long long)sp->nv, sp->index_base);
    }
    if (nt == 0)
        return vc_error_set(err, VC_EINPUT, "%s: no triangles (%lld vertices, 0 faces)", name, (long long)sp->nv);
    out->xyz = malloc((size_t)(sp->nv ? sp->nv : 1) * 3 * sizeof(double));
    out->tri = malloc((size_t)nt * 3 * sizeof(int64_t));
    /* one group is no grouping: the patch stays "surface" */
    const int grouped = sp->n_groups > 1;
    if (grouped) {
        out->tri_group = malloc((size_t)nt * sizeof(int32_t));
        out->group_name = malloc(sizeof *out->group_name * (size_t)sp->n_groups);
        if (out->tri_group && out->group_name) {
            memcpy(out->group_name, sp->group_name, sizeof *out->group_name * (size_t)sp->n_groups);
            out->n_groups = sp->n_groups;
        }
    }
    if (!out->xyz || !out->tri || (grouped && (!out->tri_group || !out->group_name))) {
        vc_surface_free(out);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    memcpy(out->xyz, sp->xyz, (size_t)sp->nv * 3 * sizeof(double));
    out->n_vertices = sp->nv;
    int64_t *t = out->tri;
    for (int64_t f = 0; f < sp->nf; f++) {
        const int64_t *v = sp->idx + sp->off[f];
        int64_t n = sp->off[f + 1] - sp->off[f];
        if (out->tri_group) {
            const int32_t g = sp->face_group[f];
            for (int64_t k = 0; k < n - 2; k++)
                out->tri_group[(t - out->tri) / 3 + k] = g;
        }
        if (n == 4 && dist2(sp->xyz + 3 * v[1], sp->xyz + 3 * v[3]) <
                          dist2(sp->xyz + 3 * v[0], sp->xyz + 3 * v[2])) {
            int64_t q[6] = {v[0], v[1], v[3], v[1], v[2], v[3]};
            memcpy(t, q, sizeof q);
            t += 6;
            continue;
        }
        for (int64_t k = 1; k + 1 < n; k++) {
            *t++ = v[0];
            *t++ = v[k];
            *t++ = v[k + 1];
        }
    }
    out->n_triangles = nt;
    if (rep) {
        rep->n_file_vertices = sp->nv;
        rep->n_file_faces = sp->nf;
        rep->n_polygons_triangulated = npoly;
        if (npoly)
            vc_surface_report_warn(rep, "%s: %lld non-triangle faces triangulated", name, (long long)npoly);
    }
    return 0;
}

int vc_surface_read(const char *path, vc_surface *out, vc_surface_report *rep, vc_error *err)
{
    return vc_surface_read_with(path, VC_READER_AUTO, out, rep, err);
}

int vc_surface_read_with(const char *path, vc_surface_reader which, vc_surface *out,
                         vc_surface_report *rep, vc_error *err)
{
    vc_surface_report local;
    if (!rep)
        rep = &local;
    memset(rep, 0, sizeof *rep);
    memset(out, 0, sizeof *out);
    vc_escape_name(path, rep->name, sizeof rep->name);
    const char *name = rep->name;

    char ext[16];
    extension(path, ext, sizeof ext);
    int (*reader)(const char *, const char *, size_t, vc_soup *, vc_error *) =
        !strcmp(ext, "obj") ? vc_read_obj : !strcmp(ext, "off") ? vc_read_off
        : !strcmp(ext, "stl") ? vc_read_stl : !strcmp(ext, "ply") ? vc_read_ply : NULL;
    /* Only formats our own readers validate: another format would go to
     * OpenMesh unchecked (its .om reader trusts the header's counts and
     * aborts on a malformed chunk). */
    if (!reader)
        return vc_error_set(err, VC_EFORMAT,
                            "%s: unsupported file extension '%s%s' (expected .obj, .off, .stl or .ply)",
                            name, ext[0] ? "." : "", ext);
    char *buf = NULL;
    size_t len = 0;
    int rc = slurp(path, name, &buf, &len, err);
    if (rc)
        return rc;
    size_t i = 0;
    while (i < len && isspace((unsigned char)buf[i]))
        i++;
    if (i == len) {
        free(buf);
        return vc_error_set(err, VC_EFORMAT, "%s: empty file", name);
    }
    vc_soup sp;
    memset(&sp, 0, sizeof sp);
    sp.expected_faces = -1;
    rep->reader = "vorocrust";
    rc = reader ? reader(name, buf, len, &sp, err) : VC_SURFACE_DEFER_TO_OPENMESH;
    free(buf);
    /* OpenMesh's readers trust the header counts (gigabytes reserved, or
     * loops past the end, for a file of 100 bytes): a file in a format of
     * our own readers goes to OpenMesh only once our reader has accepted
     * it, counts checked against the file's size. */
    if (rc == 0 && which == VC_READER_OPENMESH)
        rc = VC_SURFACE_DEFER_TO_OPENMESH;
    if (rc == VC_SURFACE_DEFER_TO_OPENMESH) {
        int64_t expected = sp.expected_faces;
        vc_soup_free(&sp);
        rep->reader = "OpenMesh";
        rc = vc_openmesh_read(path, name, &sp, err);
        sp.expected_faces = expected;
    }
    if (!rc && sp.expected_faces > sp.nf) {
        rep->n_faces_dropped = sp.expected_faces - sp.nf;
        vc_surface_report_warn(rep, "%s: %lld faces could not be read (the file announces %lld)",
                               name, (long long)rep->n_faces_dropped, (long long)sp.expected_faces);
    }
    if (!rc)
        rc = soup_to_surface(name, &sp, out, rep, err);
    vc_soup_free(&sp);
    if (rc)
        return rc;

    rc = vc_surface_merge_vertices(out, &rep->n_duplicate_vertices, &rep->n_unused_vertices,
                                   &rep->n_collapsed, err);
    if (!rc && rep->n_unused_vertices)
        vc_surface_report_warn(rep, "%s: %lld vertices used by no face (removed)", name,
                               (long long)rep->n_unused_vertices);
    if (!rc && rep->n_collapsed)
        vc_surface_report_warn(rep, "%s: %lld triangles repeat a vertex (removed as degenerate)", name,
                               (long long)rep->n_collapsed);
    if (!rc && out->n_triangles == 0)
        rc = vc_error_set(err, VC_EINPUT, "%s: every triangle repeats a vertex (all %lld degenerate)",
                          name, (long long)rep->n_collapsed);
    if (!rc)
        rc = vc_surface_check(out, rep, err);
    if (rc)
        vc_surface_free(out);
    return rc;
}

/* ---- Merging equal vertices. ---- */

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* A hash of the position's values: equal positions (-0 and 0 alike) hash
 * alike. */
static uint64_t position_hash(const double x[3])
{
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (int k = 0; k < 3; k++) {
        const double v = x[k] + 0.0; /* -0 -> +0 */
        uint64_t b;
        memcpy(&b, &v, sizeof b);
        h = mix64(h ^ b) + (uint64_t)k;
    }
    return h;
}

static int same_position(const double *a, const double *b)
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* map[i] = the lowest index of a vertex at i's position; returns how many
 * vertices map elsewhere, or -1 when out of memory. The positions' hashes
 * are sorted with their indices by a stable radix sort, so each run of one
 * hash lists its vertices by increasing index; within a run (almost
 * always one position) each vertex maps to the first earlier one at its
 * position. A comparison sort of the positions took a second on a
 * 1.8-million-triangle STL soup (5.3 million corners); this, a tenth. */
static int64_t first_at_position(const double *xyz, int64_t nv, int64_t *map)
{
    uint64_t *h = malloc((size_t)(nv ? nv : 1) * sizeof *h);
    int64_t *v = malloc((size_t)(nv ? nv : 1) * sizeof *v);
    if (!h || !v) {
        free(h);
        free(v);
        return -1;
    }
    for (int64_t i = 0; i < nv; i++) {
        h[i] = position_hash(xyz + 3 * i);
        v[i] = i;
    }
    if (vc_radix_sort_u64(h, v, nv)) {
        free(h);
        free(v);
        return -1;
    }
    int64_t merged = 0;
    for (int64_t k = 0; k < nv;) {
        int64_t e = k + 1;
        while (e < nv && h[e] == h[k])
            e++;
        for (int64_t j = k; j < e; j++) {
            const int64_t i = v[j];
            map[i] = i;
            for (int64_t q = k; q < j; q++)
                if (map[v[q]] == v[q] && same_position(xyz + 3 * v[q], xyz + 3 * i)) {
                    map[i] = v[q];
                    merged++;
                    break;
                }
        }
        k = e;
    }
    free(h);
    free(v);
    return merged;
}

int vc_surface_merge_vertices(vc_surface *s, int64_t *n_merged, int64_t *n_unused,
                              int64_t *n_collapsed, vc_error *err)
{
    int64_t nv = s->n_vertices;
    int64_t *order = malloc((size_t)(nv ? nv : 1) * sizeof *order);
    int64_t *map = malloc((size_t)(nv ? nv : 1) * sizeof *map);
    const int64_t merged = order && map ? first_at_position(s->xyz, nv, map) : -1;
    if (merged < 0) {
        free(order);
        free(map);
        return vc_error_set(err, VC_ENOMEM, "out of memory merging vertices");
    }
    /* Remap triangles, drop those repeating a vertex, mark used vertices
     * (order[] is reused as the new index, -1 for unused). */
    int64_t nt = 0, collapsed = 0;
    for (int64_t i = 0; i < nv; i++)
        order[i] = -1;
    for (int64_t t = 0; t < s->n_triangles; t++) {
        int64_t a = map[s->tri[3 * t]], b = map[s->tri[3 * t + 1]], c = map[s->tri[3 * t + 2]];
        if (a == b || b == c || c == a) {
            collapsed++;
            continue;
        }
        s->tri[3 * nt] = a;
        s->tri[3 * nt + 1] = b;
        s->tri[3 * nt + 2] = c;
        if (s->tri_group)
            s->tri_group[nt] = s->tri_group[t];
        order[a] = order[b] = order[c] = 0;
        nt++;
    }
    int64_t used = 0;
    for (int64_t i = 0; i < nv; i++) {
        if (order[i] < 0)
            continue;
        order[i] = used;
        memmove(s->xyz + 3 * used, s->xyz + 3 * i, 3 * sizeof(double));
        used++;
    }
    for (int64_t k = 0; k < 3 * nt; k++)
        s->tri[k] = order[s->tri[k]];
    /* Vertices merged into another one are not "unused". */
    int64_t unused = nv - merged - used;
    s->n_vertices = used;
    s->n_triangles = nt;
    free(order);
    free(map);
    if (n_merged)
        *n_merged = merged;
    if (n_unused)
        *n_unused = unused;
    if (n_collapsed)
        *n_collapsed = collapsed;
    return 0;
}

int vc_surface_require_closed(const vc_surface_report *rep, vc_error *err)
{
    if (rep->n_boundary_edges > 0)
        return vc_error_set(err, VC_EINPUT, "%s: %lld open boundary edges (surface is not closed)",
                            rep->name, (long long)rep->n_boundary_edges);
    return 0;
}

/* The index of group name in out (added when new), -1 out of memory. */
static int32_t concat_group(vc_surface *out, const char *name, int32_t *cap)
{
    for (int32_t g = 0; g < out->n_groups; g++)
        if (!strncmp(out->group_name[g], name, 63))
            return g;
    if (out->n_groups == *cap) {
        const int32_t c = *cap ? 2 * *cap : 8;
        char(*p)[64] = realloc(out->group_name, sizeof *p * (size_t)c);
        if (!p)
            return -1;
        out->group_name = p;
        *cap = c;
    }
    snprintf(out->group_name[out->n_groups], 64, "%s", name);
    return out->n_groups++;
}

int vc_surface_concat(const vc_surface *parts, int n_parts, const char *const *part_names,
                      vc_surface *out, vc_error *err)
{
    memset(out, 0, sizeof *out);
    int64_t nv = 0, nt = 0;
    for (int i = 0; i < n_parts; i++) {
        nv += parts[i].n_vertices;
        nt += parts[i].n_triangles;
    }
    out->xyz = malloc(sizeof(double) * 3 * (size_t)(nv + 1));
    out->tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt + 1));
    out->tri_group = malloc(sizeof(int32_t) * (size_t)(nt + 1));
    if (!out->xyz || !out->tri || !out->tri_group) {
        vc_surface_free(out);
        return vc_error_set(err, VC_ENOMEM, "out of memory joining the input surfaces");
    }
    int32_t cap = 0;
    for (int i = 0; i < n_parts; i++) {
        const vc_surface *p = &parts[i];
        memcpy(out->xyz + 3 * out->n_vertices, p->xyz, sizeof(double) * 3 * (size_t)p->n_vertices);
        for (int64_t k = 0; k < 3 * p->n_triangles; k++)
            out->tri[3 * out->n_triangles + k] = p->tri[k] + out->n_vertices;
        /* a part's own groups, or the part as one group */
        char own[64];
        snprintf(own, sizeof own, "%s", part_names && part_names[i] ? part_names[i] : "part");
        if (!part_names || !part_names[i])
            snprintf(own, sizeof own, "part%d", i + 1);
        int32_t single = p->tri_group ? -1 : concat_group(out, own, &cap);
        int32_t map[1024];
        for (int32_t g = 0; p->tri_group && g < p->n_groups && g < 1024; g++)
            if ((map[g] = concat_group(out, p->group_name[g], &cap)) < 0)
                single = -2;
        if (p->tri_group && p->n_groups > 1024) {
            vc_surface_free(out);
            return vc_error_set(err, VC_EINPUT, "%s: %d groups of triangles (at most 1024 per "
                                "input file)", own, (int)p->n_groups);
        }
        if (single == -2 || (!p->tri_group && single < 0)) {
            vc_surface_free(out);
            return vc_error_set(err, VC_ENOMEM, "out of memory joining the input surfaces");
        }
        for (int64_t t = 0; t < p->n_triangles; t++)
            out->tri_group[out->n_triangles + t] = p->tri_group ? map[p->tri_group[t]] : single;
        out->n_vertices += p->n_vertices;
        out->n_triangles += p->n_triangles;
    }
    /* the parts share the vertices of their common interfaces */
    int rc = vc_surface_merge_vertices(out, NULL, NULL, NULL, err);
    if (rc)
        vc_surface_free(out);
    return rc;
}

/* The bounding box of s's vertices (at least one). */
static void bounding_box(const vc_surface *s, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (int64_t v = 0; v < s->n_vertices; v++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * v + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * v + d]);
        }
}

double vc_surface_diagonal(const vc_surface *s)
{
    if (s->n_vertices <= 0)
        return 0;
    double lo[3], hi[3];
    bounding_box(s, lo, hi);
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

double vc_surface_signed_volume(const vc_surface *s)
{
    if (s->n_vertices <= 0 || s->n_triangles <= 0)
        return 0;
    double lo[3], hi[3];
    bounding_box(s, lo, hi);
    const double c[3] = {0.5 * lo[0] + 0.5 * hi[0], 0.5 * lo[1] + 0.5 * hi[1], 0.5 * lo[2] + 0.5 * hi[2]};
    /* differences scaled by 2^-e, the box's largest extent about 2^e */
    double emax = 0;
    for (int d = 0; d < 3; d++)
        emax = fmax(emax, hi[d] - lo[d]);
    int e = 0;
    if (emax > 0 && isfinite(emax))
        frexp(emax, &e);
    const double sc = ldexp(1.0, -e);
    double vol6 = 0;
    for (int64_t t = 0; t < s->n_triangles; t++) {
        double r[3][3];
        for (int j = 0; j < 3; j++)
            for (int d = 0; d < 3; d++)
                r[j][d] = (s->xyz[3 * s->tri[3 * t + j] + d] - c[d]) * sc;
        vol6 += r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    }
    return ldexp(vol6 / 6.0, 3 * e);
}
