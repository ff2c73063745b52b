/* Collapsing edges far shorter than anything the mesher resolves (see
 * vc_surface_collapse_short_edges and vc_surface_collapse_hairpins in
 * include/vorocrust/surface.h). */
#include "vorocrust/surface.h"
#include "vorocrust/features.h"

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

static double unit_normal(const vc_surface *o, int64_t t, double n[3])
{
    tri_normal(o->xyz + 3 * o->tri[3 * t], o->xyz + 3 * o->tri[3 * t + 1], o->xyz + 3 * o->tri[3 * t + 2], n);
    const double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 0)
        for (int k = 0; k < 3; k++)
            n[k] /= l;
    return l;
}

static double dist2(const double *p, const double *q)
{
    return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
}

/* The one live triangle other than t on edge (p, q), found among q's
 * triangles; -1 when none or several. */
static int64_t across(const vc_surface *o, const int64_t *start, const int64_t *inc,
                      const unsigned char *dead, int64_t t, int64_t p, int64_t q)
{
    int64_t found = -1;
    for (int64_t i = start[q]; i < start[q + 1]; i++) {
        const int64_t u = inc[i];
        const int64_t *f = o->tri + 3 * u;
        if (u == t || dead[u] || !(f[0] == p || f[1] == p || f[2] == p))
            continue;
        if (found >= 0)
            return -1;
        found = u;
    }
    return found;
}

/* Is edge k of triangle t (a, b; apex c) the base of a hairpin: its
 * shortest edge, the triangles across its other two edges folding from it
 * by more than the sharp angle (cos_sharp) each and agreeing with each
 * other within it? */
static int hairpin_base(const vc_surface *o, const int64_t *start, const int64_t *inc,
                        const unsigned char *dead, int64_t t, int k, double cos_sharp,
                        const vc_features *f)
{
    const int64_t a = o->tri[3 * t + k], b = o->tri[3 * t + (k + 1) % 3], c = o->tri[3 * t + (k + 2) % 3];
    const double *A = o->xyz + 3 * a, *B = o->xyz + 3 * b, *C = o->xyz + 3 * c;
    const double ab = dist2(A, B);
    if (!(ab <= dist2(A, C) && ab <= dist2(B, C)))
        return 0;
    const int64_t u1 = across(o, start, inc, dead, t, a, c), u2 = across(o, start, inc, dead, t, b, c);
    if (u1 < 0 || u2 < 0 || u1 == u2)
        return 0;
    double nt[3], n1[3], n2[3];
    if (!(unit_normal(o, t, nt) > 0 && unit_normal(o, u1, n1) > 0 && unit_normal(o, u2, n2) > 0))
        return 0;
    const double c1 = nt[0] * n1[0] + nt[1] * n1[1] + nt[2] * n1[2];
    const double c2 = nt[0] * n2[0] + nt[1] * n2[1] + nt[2] * n2[2];
    const double c12 = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
    if (!(c1 < cos_sharp && c2 < cos_sharp && c12 >= cos_sharp))
        return 0;
    if (!f)
        return 1;
    const int64_t e1 = vc_features_find_edge(f, a, c), e2 = vc_features_find_edge(f, b, c);
    return e1 >= 0 && e2 >= 0 && f->edge_sharp[e1] && f->edge_sharp[e2];
}

/* The live triangles of each vertex v: inc[start[v] .. start[v + 1] - 1]
 * (start: n_vertices + 1, inc: 3 n_triangles). Returns -1 when out of
 * memory. */
static int incidence(const vc_surface *o, const unsigned char *dead, int64_t *start, int64_t *inc)
{
    const int64_t nv = o->n_vertices, nt = o->n_triangles;
    int64_t *fill = malloc((size_t)(nv + 1) * sizeof *fill);
    if (!fill)
        return -1;
    memset(start, 0, (size_t)(nv + 1) * sizeof *start);
    for (int64_t t = 0; t < nt; t++)
        if (!dead[t])
            for (int k = 0; k < 3; k++)
                start[o->tri[3 * t + k] + 1]++;
    for (int64_t v = 0; v < nv; v++)
        start[v + 1] += start[v];
    memcpy(fill, start, (size_t)nv * sizeof *fill);
    for (int64_t t = 0; t < nt; t++)
        if (!dead[t])
            for (int k = 0; k < 3; k++)
                inc[fill[o->tri[3 * t + k]]++] = t;
    free(fill);
    return 0;
}

/* Collapses u into v (at distance sqrt(d2)) when the link condition holds
 * and no triangle around u turns over or goes flat; returns 1 when done. */
static int try_collapse(vc_surface *o, const int64_t *start, const int64_t *inc, unsigned char *dead,
                        unsigned char *mark, double *drift, int64_t u, int64_t v, double d2,
                        double *max_move)
{
    const double *W = o->xyz + 3 * v;
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
        return 0;
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
        return 0;
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
    return 1;
}

/* Collapses edges shorter than eps (hairpin bases only when hairpin is
 * set), in passes; see vc_surface_collapse_short_edges. */
static int64_t collapse_edges(vc_surface *o, int64_t first_movable, double eps, int hairpin,
                              double cos_sharp, const vc_features *f, double *max_move)
{
    const int64_t nv = o->n_vertices, nt = o->n_triangles;
    int64_t *start = malloc((size_t)(nv + 1) * sizeof *start), *inc = malloc((size_t)(3 * nt + 1) * sizeof *inc);
    unsigned char *dead = calloc((size_t)nt + 1, 1), *mark = malloc((size_t)nv + 1);
    double *drift = calloc((size_t)nv + 1, sizeof *drift); /* how far merged points moved */
    int64_t total = 0;
    if (max_move)
        *max_move = 0;
    if (!start || !inc || !dead || !mark || !drift) {
        total = -1;
        goto done;
    }
    for (int pass = 0; pass < 16; pass++) {
        if (incidence(o, dead, start, inc)) {
            total = -1;
            goto done;
        }
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
                const double d2 = dist2(o->xyz + 3 * u, o->xyz + 3 * v);
                if (!(d2 < eps * eps))
                    continue;
                /* a hairpin's collapses do not chain beyond its bound */
                if (hairpin && (mark[o->tri[3 * t + (k + 2) % 3]] ||
                                fmax(drift[u], drift[v]) + sqrt(d2) > eps ||
                                !hairpin_base(o, start, inc, dead, t, k, cos_sharp, f)))
                    continue;
                /* a hairpin's base either way (the turn-over test may
                 * refuse one) */
                if (try_collapse(o, start, inc, dead, mark, drift, u, v, d2, max_move) ||
                    (hairpin && try_collapse(o, start, inc, dead, mark, drift, v, u, d2, max_move)))
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
    return total;
}

int64_t vc_surface_collapse_short_edges(vc_surface *o, int64_t first_movable, double eps, double *max_move)
{
    return collapse_edges(o, first_movable, eps, 0, 0.0, NULL, max_move);
}

int64_t vc_surface_collapse_hairpins(vc_surface *o, double max_base, double cos_sharp,
                                     const vc_features *f, double *max_move)
{
    return collapse_edges(o, 0, max_base, 1, cos_sharp, f, max_move);
}

int64_t vc_surface_count_hairpins(const vc_surface *o, double max_base, double cos_sharp)
{
    const int64_t nv = o->n_vertices, nt = o->n_triangles;
    int64_t *start = malloc((size_t)(nv + 1) * sizeof *start), *inc = malloc((size_t)(3 * nt + 1) * sizeof *inc);
    unsigned char *dead = calloc((size_t)nt + 1, 1);
    int64_t n = 0;
    if (!start || !inc || !dead || incidence(o, dead, start, inc))
        n = -1;
    for (int64_t t = 0; t < nt && n >= 0; t++)
        for (int k = 0; k < 3; k++)
            n += dist2(o->xyz + 3 * o->tri[3 * t + k], o->xyz + 3 * o->tri[3 * t + (k + 1) % 3]) <
                     max_base * max_base &&
                 hairpin_base(o, start, inc, dead, t, k, cos_sharp, NULL);
    free(start);
    free(inc);
    free(dead);
    return n;
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
