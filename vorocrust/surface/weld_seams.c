/* Open seams closed by welding vertices that coincide to rounding (see
 * surface.h). A parametric surface written with its seam vertices
 * computed twice (sin(2 pi) is not 0: VTK's parametric ellipsoid leaves
 * them 1e-14 apart) is open only by rounding; merging exactly equal
 * positions, as the readers do, cannot close it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/surface.h"

typedef struct edge_key {
    int64_t a, b; /* a < b */
} edge_key;

static int compare_edges(const void *p, const void *q)
{
    const edge_key *u = p, *v = q;
    if (u->a != v->a)
        return u->a < v->a ? -1 : 1;
    return (u->b > v->b) - (u->b < v->b);
}

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

static int64_t find_root(int64_t *parent, int64_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

/* Joins the classes of u and v under the smaller index: the result does
 * not depend on the order of the unions. */
static void join(int64_t *parent, int64_t u, int64_t v)
{
    u = find_root(parent, u);
    v = find_root(parent, v);
    if (u < v)
        parent[v] = u;
    else if (v < u)
        parent[u] = v;
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

int vc_surface_weld_open_seams(const vc_surface *s, double tol, vc_surface *out, int64_t *n_welded,
                               vc_error *err)
{
    *n_welded = 0;
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    edge_key *e = malloc(sizeof *e * (size_t)(3 * nt + 1));
    unsigned char *open = calloc((size_t)(nv + 1), 1);
    int64_t *parent = malloc(sizeof(int64_t) * (size_t)(nv + 1));
    by_x *bx = malloc(sizeof *bx * (size_t)(nv + 1));
    if (!e || !open || !parent || !bx || copy_surface(s, out)) {
        free(e);
        free(open);
        free(parent);
        free(bx);
        memset(out, 0, sizeof *out);
        return vc_error_set(err, VC_ENOMEM, "out of memory welding the surface's seams");
    }
    /* the vertices of edges that only one triangle has */
    for (int64_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            const int64_t a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
            e[3 * t + k].a = a < b ? a : b;
            e[3 * t + k].b = a < b ? b : a;
        }
    qsort(e, (size_t)(3 * nt), sizeof *e, compare_edges);
    for (int64_t i = 0; i < 3 * nt;) {
        int64_t j = i + 1;
        while (j < 3 * nt && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        if (j - i == 1)
            open[e[i].a] = open[e[i].b] = 1;
        i = j;
    }
    free(e);
    /* those within tol of each other, by a sweep along x */
    int64_t n_open = 0;
    for (int64_t v = 0; v < nv; v++) {
        parent[v] = v;
        if (open[v]) {
            bx[n_open].x = s->xyz[3 * v];
            bx[n_open++].v = v;
        }
    }
    free(open);
    qsort(bx, (size_t)n_open, sizeof *bx, compare_x);
    for (int64_t i = 0; i < n_open; i++)
        for (int64_t j = i + 1; j < n_open && bx[j].x - bx[i].x <= tol; j++) {
            const double *p = s->xyz + 3 * bx[i].v, *q = s->xyz + 3 * bx[j].v;
            const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
            if (dx * dx + dy * dy + dz * dz <= tol * tol)
                join(parent, bx[i].v, bx[j].v);
        }
    free(bx);
    /* each class becomes its lowest vertex, at that vertex's place */
    for (int64_t v = 0; v < nv; v++) {
        const int64_t r = find_root(parent, v);
        *n_welded += r != v;
    }
    for (int64_t k = 0; k < 3 * nt; k++)
        out->tri[k] = find_root(parent, s->tri[k]);
    free(parent);
    /* triangles that collapsed (a sliver across the seam) and vertices no
     * longer used are dropped */
    const int rc = vc_surface_merge_vertices(out, NULL, NULL, NULL, err);
    if (rc)
        vc_surface_free(out);
    return rc;
}
