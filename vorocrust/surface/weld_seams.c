/* Open seams closed by welding vertices that coincide to rounding (see
 * surface.h). A parametric surface written with its seam vertices
 * computed twice (sin(2 pi) is not 0: VTK's parametric ellipsoid leaves
 * them 1e-14 apart) is open only by rounding; merging exactly equal
 * positions, as the readers do, cannot close it. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "surface/surface_internal.h"
#include "util/union_find.h"
#include "vorocrust/surface.h"

/* A vertex with a key: its x (the sweeps), or where it lies along an edge
 * (0 to 1, the T-junctions). */
typedef struct by_x {
    double x;
    int64_t v;
} by_x;

static int compare_x(const void *p, const void *q)
{
    const by_x *u = p, *w = q;
    if (u->x != w->x)
        return u->x < w->x ? -1 : 1;
    return (u->v > w->v) - (u->v < w->v);
}

typedef struct open_edge {
    int64_t a, b; /* a < b */
    int64_t t;    /* its triangle */
    int k;        /* the edge runs from corner k to corner k + 1 of t */
} open_edge;

static int compare_open_edges(const void *p, const void *q)
{
    const open_edge *u = p, *v = q;
    if (u->a != v->a)
        return u->a < v->a ? -1 : 1;
    if (u->b != v->b)
        return u->b < v->b ? -1 : 1;
    return (u->t > v->t) - (u->t < v->t);
}

/* The open edges of s (of one triangle each: *edges, with that triangle)
 * and their vertices sorted by x (*verts, *n_verts of them); the caller
 * frees both. Returns the number of open edges, or -1 when out of
 * memory. */
static int64_t find_open(const vc_surface *s, open_edge **edges, by_x **verts, int64_t *n_verts)
{
    const int64_t nt = s->n_triangles;
    open_edge *e = malloc(sizeof *e * (size_t)(3 * nt + 1));
    unsigned char *open = calloc((size_t)(s->n_vertices + 1), 1);
    by_x *bx = malloc(sizeof *bx * (size_t)(s->n_vertices + 1));
    if (!e || !open || !bx) {
        free(e);
        free(open);
        free(bx);
        return -1;
    }
    for (int64_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            const int64_t a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
            e[3 * t + k] = (open_edge){a < b ? a : b, a < b ? b : a, t, k};
        }
    qsort(e, (size_t)(3 * nt), sizeof *e, compare_open_edges);
    int64_t n = 0;
    for (int64_t i = 0; i < 3 * nt;) {
        int64_t j = i + 1;
        while (j < 3 * nt && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        if (j - i == 1) {
            open[e[i].a] = open[e[i].b] = 1;
            e[n++] = e[i];
        }
        i = j;
    }
    int64_t m = 0;
    for (int64_t v = 0; v < s->n_vertices; v++)
        if (open[v])
            bx[m++] = (by_x){s->xyz[3 * v], v};
    free(open);
    qsort(bx, (size_t)m, sizeof *bx, compare_x);
    *edges = e;
    *verts = bx;
    *n_verts = m;
    return n;
}

static int copy_surface(const vc_surface *s, vc_surface *out)
{
    memset(out, 0, sizeof *out);
    out->xyz = malloc(sizeof(double) * 3 * (size_t)(s->n_vertices + 1));
    out->tri = malloc(sizeof(int64_t) * 3 * (size_t)(s->n_triangles + 1));
    if (s->tri_group) {
        out->tri_group = malloc(sizeof(int32_t) * (size_t)(s->n_triangles + 1));
        out->group_name = malloc(sizeof *out->group_name * (size_t)(s->n_groups + 1));
    }
    if (!out->xyz || !out->tri || (s->tri_group && (!out->tri_group || !out->group_name))) {
        vc_surface_free(out);
        return -1;
    }
    memcpy(out->xyz, s->xyz, sizeof(double) * 3 * (size_t)s->n_vertices);
    memcpy(out->tri, s->tri, sizeof(int64_t) * 3 * (size_t)s->n_triangles);
    if (s->tri_group) {
        memcpy(out->tri_group, s->tri_group, sizeof(int32_t) * (size_t)s->n_triangles);
        memcpy(out->group_name, s->group_name, sizeof *out->group_name * (size_t)s->n_groups);
    }
    out->n_vertices = s->n_vertices;
    out->n_triangles = s->n_triangles;
    out->n_groups = s->n_groups;
    return 0;
}

/* *out = s with every vertex replaced by its class's root in parent (the
 * lowest index, at its own place); the triangles that then repeat a vertex
 * and the vertices no longer used dropped. Frees parent. Returns 0, or
 * VC_ENOMEM with *out empty. */
static int weld_classes(const vc_surface *s, int64_t *parent, vc_surface *out, vc_error *err)
{
    if (copy_surface(s, out)) {
        free(parent);
        return vc_error_set(err, VC_ENOMEM, "out of memory welding the surface");
    }
    for (int64_t k = 0; k < 3 * s->n_triangles; k++)
        out->tri[k] = vc_uf_find(parent, s->tri[k]);
    free(parent);
    const int rc = vc_surface_merge_vertices(out, NULL, NULL, NULL, err);
    if (rc)
        vc_surface_free(out);
    return rc;
}

double vc_surface_seam_tolerance(const vc_surface *s)
{
    double m = 0;
    for (int64_t i = 0; i < 3 * s->n_vertices; i++)
        m = fmax(m, fabs(s->xyz[i]));
    return VC_SURFACE_SEAM_WELD * vc_surface_diagonal(s) + 4 * FLT_EPSILON * m;
}

int vc_surface_weld_open_seams(const vc_surface *s, double tol, vc_surface *out, int64_t *n_welded,
                               vc_error *err)
{
    *n_welded = 0;
    const int64_t nv = s->n_vertices;
    int64_t *parent = malloc(sizeof(int64_t) * (size_t)(nv + 1));
    open_edge *e = NULL;
    by_x *bx = NULL;
    int64_t n_open = 0;
    memset(out, 0, sizeof *out);
    if (!parent || find_open(s, &e, &bx, &n_open) < 0) {
        free(parent);
        free(e);
        free(bx);
        memset(out, 0, sizeof *out);
        return vc_error_set(err, VC_ENOMEM, "out of memory welding the surface's seams");
    }
    free(e);
    /* the vertices of open edges within tol of each other, by a sweep
     * along x */
    vc_uf_init(parent, nv);
    for (int64_t i = 0; i < n_open; i++)
        for (int64_t j = i + 1; j < n_open && bx[j].x - bx[i].x <= tol; j++) {
            const double *p = s->xyz + 3 * bx[i].v, *q = s->xyz + 3 * bx[j].v;
            const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
            if (dx * dx + dy * dy + dz * dz <= tol * tol)
                vc_uf_unite(parent, bx[i].v, bx[j].v);
        }
    free(bx);
    /* each class becomes its lowest vertex, at that vertex's place */
    for (int64_t v = 0; v < nv; v++)
        *n_welded += vc_uf_find(parent, v) != v;
    /* triangles that collapsed (a sliver across the seam) are dropped */
    return weld_classes(s, parent, out, err);
}

/* Is triangle t of zero area (vc_triangle_zero_area)? Then the ends of
 * its shortest edge into *a, *b and its length into *shortest. */
static int needle(const vc_surface *s, int64_t t, int64_t *a, int64_t *b, double *shortest)
{
    const int64_t *v = s->tri + 3 * t;
    if (!vc_triangle_zero_area(s->xyz, v[0], v[1], v[2]))
        return 0;
    double l2[3];
    for (int k = 0; k < 3; k++) {
        const double *p = s->xyz + 3 * v[k], *q = s->xyz + 3 * v[(k + 1) % 3];
        l2[k] = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]);
    }
    int k = 0;
    for (int j = 1; j < 3; j++)
        if (l2[j] < l2[k])
            k = j;
    *a = v[k];
    *b = v[(k + 1) % 3];
    *shortest = sqrt(l2[k]);
    return 1;
}

int vc_surface_weld_needles(const vc_surface *s, double tol, vc_surface *out, int64_t *n_welded,
                            vc_error *err)
{
    *n_welded = 0;
    memset(out, 0, sizeof *out);
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    int64_t *parent = malloc(sizeof(int64_t) * (size_t)(nv + 1));
    if (!parent)
        return vc_error_set(err, VC_ENOMEM, "out of memory welding needle triangles");
    vc_uf_init(parent, nv);
    for (int64_t t = 0; t < nt; t++) {
        int64_t a, b;
        double l;
        if (needle(s, t, &a, &b, &l) && l <= tol && vc_uf_find(parent, a) != vc_uf_find(parent, b)) {
            vc_uf_unite(parent, a, b);
            ++*n_welded;
        }
    }
    if (*n_welded == 0) {
        free(parent);
        return 0;
    }
    return weld_classes(s, parent, out, err);
}

/* ---------------------------------------------------------------------
 * T-junctions: a vertex of one side's tessellation lying on an edge of
 * the other side's (two faces of a CAD model tessellated apart). */

/* Work at most this many vertex-edge tests (a pathological input's open
 * edges all along x would make it quadratic). */
#define T_JUNCTION_MAX_TESTS 100000000LL
#define T_JUNCTION_MAX_PASSES 8

int vc_surface_split_t_junctions(vc_surface *s, double tol, int64_t *n_split, vc_error *err)
{
    *n_split = 0;
    long long tests = 0;
    for (int pass = 0; pass < T_JUNCTION_MAX_PASSES; pass++) {
        open_edge *e;
        by_x *bx;
        int64_t n_bx;
        const int64_t n_e = find_open(s, &e, &bx, &n_bx);
        if (n_e < 0)
            return vc_error_set(err, VC_ENOMEM, "out of memory splitting T-junctions");
        /* per triangle, at most one edge split per pass: the vertices on it */
        const int64_t nt = s->n_triangles;
        int64_t *split_edge = malloc(sizeof(int64_t) * (size_t)(nt + 1)); /* index into e, or -1 */
        by_x *on = malloc(sizeof *on * (size_t)(n_bx + 1));
        int64_t *on_start = malloc(sizeof(int64_t) * (size_t)(n_e + 2));
        by_x *all = NULL;
        int64_t n_all = 0, cap_all = 0, n_new = 0;
        int fail = !split_edge || !on || !on_start;
        for (int64_t t = 0; !fail && t < nt; t++)
            split_edge[t] = -1;
        for (int64_t i = 0; !fail && i < n_e; i++) {
            on_start[i] = n_all;
            const open_edge *oe = &e[i];
            if (split_edge[oe->t] >= 0)
                continue;
            const double *a = s->xyz + 3 * oe->a, *b = s->xyz + 3 * oe->b;
            const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            const double len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
            if (!(len2 > 4 * tol * tol))
                continue;
            const double xlo = fmin(a[0], b[0]) - tol, xhi = fmax(a[0], b[0]) + tol;
            int64_t lo = 0, hi = n_bx;
            while (lo < hi) { /* the first vertex at xlo or beyond */
                const int64_t mid = (lo + hi) / 2;
                if (bx[mid].x < xlo)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            int64_t n_on = 0;
            for (int64_t j = lo; j < n_bx && bx[j].x <= xhi && tests < T_JUNCTION_MAX_TESTS; j++, tests++) {
                const int64_t v = bx[j].v;
                if (v == oe->a || v == oe->b)
                    continue;
                const double *p = s->xyz + 3 * v;
                const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
                const double u = (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2;
                const double len = sqrt(len2);
                if (u * len <= tol || (1 - u) * len <= tol)
                    continue;
                const double d[3] = {ap[0] - u * ab[0], ap[1] - u * ab[1], ap[2] - u * ab[2]};
                if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= tol * tol)
                    on[n_on++] = (by_x){u, v};
            }
            if (n_on == 0)
                continue;
            qsort(on, (size_t)n_on, sizeof *on, compare_x);
            if (n_all + n_on > cap_all) {
                cap_all = 2 * (n_all + n_on);
                by_x *q = realloc(all, sizeof *q * (size_t)cap_all);
                if (!q) {
                    fail = 1;
                    break;
                }
                all = q;
            }
            memcpy(all + n_all, on, sizeof *on * (size_t)n_on);
            n_all += n_on;
            n_new += n_on;
            split_edge[oe->t] = i;
        }
        on_start[n_e] = n_all;
        free(on);
        free(bx);
        if (!fail && n_new > 0) {
            /* each split triangle becomes a fan from its third corner */
            int64_t *tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt + n_new + 1));
            int32_t *grp = s->tri_group ? malloc(sizeof(int32_t) * (size_t)(nt + n_new + 1)) : NULL;
            if (!tri || (s->tri_group && !grp)) {
                free(tri);
                free(grp);
                fail = 1;
            } else {
                int64_t m = 0;
                for (int64_t t = 0; t < nt; t++) {
                    const int64_t i = split_edge[t];
                    if (i < 0) {
                        memcpy(tri + 3 * m, s->tri + 3 * t, sizeof(int64_t) * 3);
                        if (grp)
                            grp[m] = s->tri_group[t];
                        m++;
                        continue;
                    }
                    const int k = e[i].k;
                    const int64_t a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3],
                                  c = s->tri[3 * t + (k + 2) % 3];
                    /* the vertices on it from a to b (sorted from e[i].a) */
                    const int64_t n_on = on_start[i + 1] - on_start[i];
                    int64_t prev = a;
                    for (int64_t q = 0; q <= n_on; q++) {
                        const int64_t next = q == n_on ? b
                                           : a == e[i].a ? all[on_start[i] + q].v
                                                         : all[on_start[i] + n_on - 1 - q].v;
                        tri[3 * m] = prev;
                        tri[3 * m + 1] = next;
                        tri[3 * m + 2] = c;
                        if (grp)
                            grp[m] = s->tri_group[t];
                        m++;
                        prev = next;
                    }
                    *n_split += 1;
                }
                free(s->tri);
                s->tri = tri;
                if (grp) {
                    free(s->tri_group);
                    s->tri_group = grp;
                }
                s->n_triangles = m;
            }
        }
        free(e);
        free(split_edge);
        free(on_start);
        free(all);
        if (fail)
            return vc_error_set(err, VC_ENOMEM, "out of memory splitting T-junctions");
        if (n_new == 0)
            break;
    }
    return 0;
}

/* Takes *cand (own arrays) into *out when its report passes `accept`;
 * frees it otherwise. */
static int checked(const vc_surface_report *rep, vc_surface *cand, vc_surface_report *out_rep,
                   int (*accept)(const vc_surface_report *before, const vc_surface_report *after))
{
    vc_surface_report r = *rep;
    r.n_warnings = 0;
    vc_error e = {0, ""};
    if (cand->n_triangles > 0 && vc_surface_check(cand, &r, &e) == 0 && accept(rep, &r)) {
        *out_rep = r;
        return 1;
    }
    vc_surface_free(cand);
    return 0;
}

static int closed_no_new_nonmanifold(const vc_surface_report *before, const vc_surface_report *after)
{
    return after->n_boundary_edges == 0 && after->n_nonmanifold_edges <= before->n_nonmanifold_edges;
}

static int fewer_zero_area(const vc_surface_report *before, const vc_surface_report *after)
{
    return closed_no_new_nonmanifold(before, after) && after->n_degenerate < before->n_degenerate;
}

int vc_surface_close_by_rounding(const vc_surface *s, const vc_surface_report *rep, vc_surface *out,
                                 vc_surface_report *out_rep, int64_t *n_welded, int64_t *n_split,
                                 vc_error *err)
{
    memset(out, 0, sizeof *out);
    *n_welded = *n_split = 0;
    if (rep->n_boundary_edges == 0)
        return 0;
    const double tol = vc_surface_seam_tolerance(s);
    int rc = vc_surface_weld_open_seams(s, tol, out, n_welded, err);
    if (!rc)
        rc = vc_surface_split_t_junctions(out, tol, n_split, err);
    if (rc) {
        vc_surface_free(out);
        return rc;
    }
    if (*n_welded + *n_split == 0)
        vc_surface_free(out);
    else if (!checked(rep, out, out_rep, closed_no_new_nonmanifold))
        *n_welded = *n_split = 0;
    return 0;
}

int vc_surface_drop_needles(const vc_surface *s, const vc_surface_report *rep, vc_surface *out,
                            vc_surface_report *out_rep, vc_error *err)
{
    memset(out, 0, sizeof *out);
    if (rep->n_degenerate == 0)
        return 0;
    int64_t n = 0;
    const int rc = vc_surface_weld_needles(s, vc_surface_seam_tolerance(s), out, &n, err);
    if (rc)
        return rc;
    if (n > 0)
        checked(rep, out, out_rep, fewer_zero_area);
    return 0;
}
