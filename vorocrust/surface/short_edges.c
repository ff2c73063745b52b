/* Collapsing edges far shorter than anything the mesher resolves (see
 * vc_surface_collapse_short_edges in include/vorocrust/surface.h). */
#include "vorocrust/surface.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void tri_normal(const double *a, const double *b, const double *c, double n[3])
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

int64_t vc_surface_collapse_short_edges(vc_surface *o, int64_t first_movable, double eps, double *max_move)
{
    const int64_t nv = o->n_vertices, nt = o->n_triangles;
    int64_t *start = malloc((size_t)(nv + 1) * sizeof *start), *inc = malloc((size_t)(3 * nt + 1) * sizeof *inc);
    unsigned char *dead = calloc((size_t)nt + 1, 1), *mark = malloc((size_t)nv + 1);
    double *drift = calloc((size_t)nv + 1, sizeof *drift); /* how far merged points moved */
    int64_t *nb = NULL, total = 0;
    if (max_move)
        *max_move = 0;
    if (!start || !inc || !dead || !mark || !drift) {
        total = -1;
        goto done;
    }
    for (int pass = 0; pass < 16; pass++) {
        memset(start, 0, (size_t)(nv + 1) * sizeof *start);
        for (int64_t t = 0; t < nt; t++)
            if (!dead[t])
                for (int k = 0; k < 3; k++)
                    start[o->tri[3 * t + k] + 1]++;
        for (int64_t v = 0; v < nv; v++)
            start[v + 1] += start[v];
        int64_t *fill = nb = malloc((size_t)(nv + 1) * sizeof *fill);
        if (!fill) {
            total = -1;
            goto done;
        }
        memcpy(fill, start, (size_t)nv * sizeof *fill);
        for (int64_t t = 0; t < nt; t++)
            if (!dead[t])
                for (int k = 0; k < 3; k++)
                    inc[fill[o->tri[3 * t + k]]++] = t;
        free(nb);
        nb = NULL;
        memset(mark, 0, (size_t)nv);
        int64_t done_here = 0;
        for (int64_t t = 0; t < nt; t++) {
            if (dead[t])
                continue;
            for (int k = 0; k < 3 && !dead[t]; k++) {
                int64_t a = o->tri[3 * t + k], b = o->tri[3 * t + (k + 1) % 3];
                int64_t u = -1, v = -1; /* u goes into v */
                if (b >= first_movable && (a < first_movable || a < b)) {
                    u = b;
                    v = a;
                } else if (a >= first_movable) {
                    u = a;
                    v = b;
                } else {
                    continue;
                }
                if (mark[u] || mark[v])
                    continue;
                const double *U = o->xyz + 3 * u, *W = o->xyz + 3 * v;
                double d2 = (U[0] - W[0]) * (U[0] - W[0]) + (U[1] - W[1]) * (U[1] - W[1]) + (U[2] - W[2]) * (U[2] - W[2]);
                if (!(d2 < eps * eps))
                    continue;
                /* link condition: the vertices next to both u and v are the
                 * apexes of the triangles on edge uv, and there are two */
                int n_shared_tri = 0, bad = 0;
                for (int64_t i = start[u]; i < start[u + 1] && !bad; i++) {
                    int64_t tu = inc[i];
                    const int64_t *f = o->tri + 3 * tu;
                    int has_v = f[0] == v || f[1] == v || f[2] == v;
                    n_shared_tri += has_v;
                    for (int j = 0; j < 3 && !bad; j++) {
                        int64_t w = f[j];
                        if (w == u || w == v)
                            continue;
                        /* w next to u: is it next to v, and through a triangle on uv? */
                        int next_v = 0;
                        for (int64_t i2 = start[v]; i2 < start[v + 1] && !next_v; i2++) {
                            const int64_t *g = o->tri + 3 * inc[i2];
                            next_v = g[0] == w || g[1] == w || g[2] == w;
                        }
                        if (next_v && !has_v) {
                            int on_uv = 0;
                            for (int64_t i3 = start[u]; i3 < start[u + 1] && !on_uv; i3++) {
                                const int64_t *h = o->tri + 3 * inc[i3];
                                on_uv = (h[0] == v || h[1] == v || h[2] == v) && (h[0] == w || h[1] == w || h[2] == w);
                            }
                            bad = !on_uv;
                        }
                    }
                }
                if (bad || n_shared_tri != 2)
                    continue;
                /* no triangle around u turns over or goes flat */
                for (int64_t i = start[u]; i < start[u + 1] && !bad; i++) {
                    const int64_t *f = o->tri + 3 * inc[i];
                    if (f[0] == v || f[1] == v || f[2] == v)
                        continue;
                    const double *P[3], *Q[3];
                    for (int j = 0; j < 3; j++) {
                        P[j] = o->xyz + 3 * f[j];
                        Q[j] = f[j] == u ? W : P[j];
                    }
                    double n0[3], n1[3];
                    tri_normal(P[0], P[1], P[2], n0);
                    tri_normal(Q[0], Q[1], Q[2], n1);
                    double l0 = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
                    double l1 = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
                    bad = !(n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] > 0.5 * l0 * l1);
                }
                if (bad)
                    continue;
                for (int64_t i = start[u]; i < start[u + 1]; i++) {
                    int64_t tu = inc[i];
                    int64_t *f = o->tri + 3 * tu;
                    if (f[0] == v || f[1] == v || f[2] == v) {
                        dead[tu] = 1;
                        continue;
                    }
                    for (int j = 0; j < 3; j++) {
                        if (f[j] == u)
                            f[j] = v;
                        mark[f[j]] = 1;
                    }
                }
                for (int64_t i = start[v]; i < start[v + 1]; i++)
                    for (int j = 0; j < 3; j++)
                        mark[o->tri[3 * inc[i] + j]] = 1;
                mark[u] = mark[v] = 1;
                const double moved = drift[u] + sqrt(d2);
                drift[v] = moved > drift[v] ? moved : drift[v];
                if (max_move && drift[v] > *max_move)
                    *max_move = drift[v];
                done_here++;
            }
        }
        total += done_here;
        if (!done_here)
            break;
    }
    /* compact: live triangles, used vertices */
    int64_t q = 0;
    for (int64_t t = 0; t < nt; t++)
        if (!dead[t]) {
            memmove(o->tri + 3 * q, o->tri + 3 * t, 3 * sizeof *o->tri);
            if (o->tri_group)
                o->tri_group[q] = o->tri_group[t];
            q++;
        }
    o->n_triangles = q;
    for (int64_t v = 0; v < nv; v++)
        start[v] = -1;
    for (int64_t k = 0; k < 3 * q; k++)
        start[o->tri[k]] = 0;
    int64_t m = 0;
    for (int64_t v = 0; v < nv; v++)
        if (start[v] == 0) {
            memmove(o->xyz + 3 * m, o->xyz + 3 * v, 3 * sizeof *o->xyz);
            start[v] = m++;
        }
    for (int64_t k = 0; k < 3 * q; k++)
        o->tri[k] = start[o->tri[k]];
    o->n_vertices = m;
done:
    free(start);
    free(inc);
    free(dead);
    free(mark);
    free(drift);
    free(nb);
    return total;
}


int vc_surface_has_edge_shorter(const vc_surface *s, double eps)
{
    const double e2 = eps * eps;
    for (int64_t t = 0; t < s->n_triangles; t++)
        for (int k = 0; k < 3; k++) {
            const double *a = s->xyz + 3 * s->tri[3 * t + k], *b = s->xyz + 3 * s->tri[3 * t + (k + 1) % 3];
            const double d2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                              (a[2] - b[2]) * (a[2] - b[2]);
            if (d2 < e2)
                return 1;
        }
    return 0;
}
