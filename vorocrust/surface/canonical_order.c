/* The surface in an order that depends on its geometry alone.
 *
 * The sampler draws its darts over the triangles in their order and walks
 * creases from the vertices in theirs, so one solid written as OBJ, OFF,
 * STL or PLY (each exporter numbers it its own way) gave different meshes.
 * Vertices are put in Morton order of their position in the bounding box
 * (neighbours stay near in memory, which the coverage tests' runs of
 * neighbouring subfaces rely on), exact coordinates breaking ties; each
 * triangle starts at its smallest vertex (its orientation kept), and the
 * triangles are sorted by their vertices. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/surface.h"
#include "util/bucket_sort.h"
#include "util/morton.h"
#include "util/small_sort.h"

typedef struct vertex_key {
    uint64_t morton;
    const double *p;
    int64_t index;
} vertex_key;

typedef struct triangle_key {
    int64_t v[3];
    int32_t group;
    int64_t index;
} triangle_key;

/* (Morton code, exact position, input index): a total order */
static inline int vertex_less(const vertex_key *u, const vertex_key *v)
{
    if (u->morton != v->morton)
        return u->morton < v->morton;
    for (int d = 0; d < 3; d++)
        if (u->p[d] != v->p[d])
            return u->p[d] < v->p[d];
    /* equal positions (not merged by the caller): the input decides */
    return u->index < v->index;
}
VC_SMALL_SORT(sort_vertex_keys, vertex_key, vertex_less)

/* (vertices from the smallest, group, input index): a total order */
static inline int triangle_less(const triangle_key *u, const triangle_key *v)
{
    for (int k = 0; k < 3; k++)
        if (u->v[k] != v->v[k])
            return u->v[k] < v->v[k];
    if (u->group != v->group)
        return u->group < v->group;
    return u->index < v->index;
}
VC_SMALL_SORT(sort_triangle_keys, triangle_key, triangle_less)
/* the first vertex is the smallest: the triangles at a vertex are a bucket */
#define TRIANGLE_FIRST(t) ((t)->v[0])
VC_BUCKET_SORT(bucket_sort_triangle_keys, triangle_key, TRIANGLE_FIRST, triangle_less, sort_triangle_keys)

int vc_surface_canonical_order(const vc_surface *s, vc_surface *out, int64_t *input_triangle,
                               int64_t *input_vertex, vc_error *err)
{
    memset(out, 0, sizeof *out);
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < nv; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = s->xyz[3 * i + d] < lo[d] ? s->xyz[3 * i + d] : lo[d];
            hi[d] = s->xyz[3 * i + d] > hi[d] ? s->xyz[3 * i + d] : hi[d];
        }
    vertex_key *vk = malloc(sizeof *vk * (size_t)(nv + 1));
    int64_t *new_of = malloc(sizeof *new_of * (size_t)(nv + 1));
    triangle_key *tk = malloc(sizeof *tk * (size_t)(nt + 1));
    out->xyz = malloc(sizeof(double) * 3 * (size_t)(nv + 1));
    out->tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt + 1));
    if (s->tri_group) {
        out->tri_group = malloc(sizeof(int32_t) * (size_t)(nt + 1));
        out->group_name = malloc(sizeof *out->group_name * (size_t)(s->n_groups + 1));
    }
    if (!vk || !new_of || !tk || !out->xyz || !out->tri ||
        (s->tri_group && (!out->tri_group || !out->group_name))) {
        free(vk);
        free(new_of);
        free(tk);
        vc_surface_free(out);
        return vc_error_set(err, VC_ENOMEM, "out of memory ordering the surface");
    }
    /* 2^21 cells per axis over the box (a flat axis: one cell) */
    for (int64_t i = 0; i < nv; i++) {
        uint64_t m = 0;
        for (int d = 0; d < 3; d++) {
            const double w = hi[d] - lo[d];
            double t = w > 0 ? (s->xyz[3 * i + d] - lo[d]) / w * 2097151.0 : 0;
            t = t < 0 ? 0 : (t > 2097151.0 ? 2097151.0 : t);
            m |= vc_morton_spread3((uint64_t)t) << d;
        }
        vk[i].morton = m;
        vk[i].p = s->xyz + 3 * i;
        vk[i].index = i;
    }
    sort_vertex_keys(vk, nv);
    for (int64_t i = 0; i < nv; i++) {
        new_of[vk[i].index] = i;
        if (input_vertex)
            input_vertex[i] = vk[i].index;
        memcpy(out->xyz + 3 * i, vk[i].p, sizeof(double) * 3);
    }
    for (int64_t t = 0; t < nt; t++) {
        int64_t w[3];
        for (int k = 0; k < 3; k++)
            w[k] = new_of[s->tri[3 * t + k]];
        /* start at the smallest vertex, the cyclic order (orientation) kept */
        const int f = w[0] < w[1] ? (w[0] < w[2] ? 0 : 2) : (w[1] < w[2] ? 1 : 2);
        for (int k = 0; k < 3; k++)
            tk[t].v[k] = w[(f + k) % 3];
        tk[t].group = s->tri_group ? s->tri_group[t] : 0;
        tk[t].index = t;
    }
    if (bucket_sort_triangle_keys(tk, nt, nv))
        sort_triangle_keys(tk, nt); /* no room for the copy: in place */
    for (int64_t t = 0; t < nt; t++) {
        memcpy(out->tri + 3 * t, tk[t].v, sizeof(int64_t) * 3);
        if (out->tri_group)
            out->tri_group[t] = tk[t].group;
        if (input_triangle)
            input_triangle[t] = tk[t].index;
    }
    out->n_vertices = nv;
    out->n_triangles = nt;
    if (s->tri_group) {
        out->n_groups = s->n_groups;
        memcpy(out->group_name, s->group_name, sizeof *out->group_name * (size_t)s->n_groups);
    }
    free(vk);
    free(new_of);
    free(tk);
    return 0;
}
