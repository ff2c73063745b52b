/* Zero-area triangles removed by flipping their longest edge (see
 * surface.h). A zero-area triangle of a closed surface is a cap: its third
 * vertex lies on its longest edge (a CAD exporter's sliver closing a
 * T-junction). The triangle across that edge then holds the cap's vertex
 * on its side, and splitting it there replaces both: the same area, no
 * zero-area triangle, every edge still shared by the same two sides. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "surface/surface_internal.h"
#include "vorocrust/surface.h"

typedef struct dir_edge {
    int64_t from, to, t;
} dir_edge;

static int compare_dir(const void *p, const void *q)
{
    const dir_edge *u = p, *v = q;
    if (u->from != v->from)
        return u->from < v->from ? -1 : 1;
    if (u->to != v->to)
        return u->to < v->to ? -1 : 1;
    return (u->t > v->t) - (u->t < v->t);
}

int vc_triangle_zero_area(const double *xyz, int64_t a, int64_t b, int64_t c)
{
    const double *p = xyz + 3 * a, *q = xyz + 3 * b, *r = xyz + 3 * c;
    const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    const double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    const double w[3] = {r[0] - q[0], r[1] - q[1], r[2] - q[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double lu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    const double lv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    const double lw = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    const double lmax = fmax(lu, fmax(lv, lw));
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) <= VC_SOLID_ZERO_AREA * lmax;
}

/* The first of the edges sorted in e that walks from -> to, and how many
 * do (*count). */
static int64_t find_walk(const dir_edge *e, int64_t n, int64_t from, int64_t to, int *count)
{
    int64_t lo = 0, hi = n;
    while (lo < hi) {
        const int64_t mid = (lo + hi) / 2;
        if (e[mid].from < from || (e[mid].from == from && e[mid].to < to))
            lo = mid + 1;
        else
            hi = mid;
    }
    *count = 0;
    for (int64_t i = lo; i < n && e[i].from == from && e[i].to == to && *count < 2; i++)
        ++*count;
    return lo;
}

/* The triangle that walks b -> a when the edge ab has exactly two sides,
 * t walking a -> b and that one; else -1 (an edge of one triangle, or of
 * more than two: left alone). */
static int64_t across(const dir_edge *e, int64_t n, int64_t a, int64_t b)
{
    int forward, backward;
    find_walk(e, n, a, b, &forward);
    const int64_t i = find_walk(e, n, b, a, &backward);
    return forward == 1 && backward == 1 ? e[i].t : -1;
}

#define ZERO_AREA_MAX_PASSES 16

int vc_surface_flip_zero_area(vc_surface *s, int64_t *n_flipped, int64_t *n_left, vc_error *err)
{
    *n_flipped = 0;
    *n_left = 0;
    if (s->n_triangles <= 0)
        return 0;
    const int64_t nt = s->n_triangles;
    const size_t n_bytes = (size_t)nt;
    dir_edge *e = malloc(sizeof *e * (size_t)(3 * nt + 1));
    unsigned char *touched = malloc(n_bytes);
    if (!e || !touched) {
        free(e);
        free(touched);
        return vc_error_set(err, VC_ENOMEM, "out of memory flipping zero-area triangles");
    }
    for (int pass = 0; pass < ZERO_AREA_MAX_PASSES; pass++) {
        for (int64_t t = 0; t < nt; t++)
            for (int k = 0; k < 3; k++)
                e[3 * t + k] = (dir_edge){s->tri[3 * t + k], s->tri[3 * t + (k + 1) % 3], t};
        qsort(e, (size_t)(3 * nt), sizeof *e, compare_dir);
        memset(touched, 0, n_bytes);
        int64_t flips = 0;
        for (int64_t t = 0; t < nt; t++) {
            int64_t *v = s->tri + 3 * t;
            if (touched[t] || !vc_triangle_zero_area(s->xyz, v[0], v[1], v[2]))
                continue;
            /* the longest edge a -> b, c opposite */
            int k = 0;
            double best = -1;
            for (int j = 0; j < 3; j++) {
                const double *p = s->xyz + 3 * v[j], *q = s->xyz + 3 * v[(j + 1) % 3];
                const double l = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                                 (q[2] - p[2]) * (q[2] - p[2]);
                if (l > best) {
                    best = l;
                    k = j;
                }
            }
            const int64_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
            const int64_t o = across(e, 3 * nt, a, b);
            if (o < 0 || touched[o])
                continue;
            int64_t *w = s->tri + 3 * o, d = -1;
            for (int j = 0; j < 3; j++)
                if (w[j] != a && w[j] != b)
                    d = w[j];
            /* the triangle across split at c: (b, c, d) and (c, a, d) keep
             * its orientation and the cap's edges' */
            if (d < 0 || d == c || vc_triangle_zero_area(s->xyz, b, c, d) ||
                vc_triangle_zero_area(s->xyz, c, a, d))
                continue;
            v[0] = b, v[1] = c, v[2] = d;
            w[0] = c, w[1] = a, w[2] = d;
            if (s->tri_group)
                s->tri_group[t] = s->tri_group[o]; /* the area is the other's */
            touched[t] = touched[o] = 1;
            flips++;
        }
        *n_flipped += flips;
        if (flips == 0)
            break;
    }
    for (int64_t t = 0; t < nt; t++)
        *n_left += vc_triangle_zero_area(s->xyz, s->tri[3 * t], s->tri[3 * t + 1], s->tri[3 * t + 2]);
    free(e);
    free(touched);
    return 0;
}
