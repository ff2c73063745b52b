#include "balls/triplets.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A point placed on a sphere is inside another ball only when it is inside
 * by more than this fraction of the radius: the shrinking in sliver
 * elimination leaves points 1e-7 outside, well clear of it. */
#define INSIDE_MARGIN 1e-9

int vc_sphere_triple_points(const double *ca, double ra, const double *cb, double rb,
                            const double *cc, double rc, double up[3], double down[3])
{
    double e1[3], e2[3], e3[3], ac[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = cb[k] - ca[k];
        ac[k] = cc[k] - ca[k];
    }
    double d = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    if (!(d > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        e1[k] /= d;
    double i = e1[0] * ac[0] + e1[1] * ac[1] + e1[2] * ac[2];
    for (int k = 0; k < 3; k++)
        e2[k] = ac[k] - i * e1[k];
    double j = sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
    if (!(j > 1e-12 * d))
        return 0;
    for (int k = 0; k < 3; k++)
        e2[k] /= j;
    e3[0] = e1[1] * e2[2] - e1[2] * e2[1];
    e3[1] = e1[2] * e2[0] - e1[0] * e2[2];
    e3[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double u = (ra * ra - rb * rb + d * d) / (2 * d);
    double v = (ra * ra - rc * rc + i * i + j * j - 2 * i * u) / (2 * j);
    double w2 = ra * ra - u * u - v * v;
    if (!(w2 > 1e-14 * ra * ra))
        return 0;
    double w = sqrt(w2);
    for (int k = 0; k < 3; k++) {
        double base = ca[k] + u * e1[k] + v * e2[k];
        up[k] = base + w * e3[k];
        down[k] = base - w * e3[k];
    }
    return 1;
}

int vc_ball_strictly_contains(const vc_balls *b, int64_t i, const double p[3])
{
    const double *c = b->center + 3 * i;
    double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    double r = b->radius[i] * (1 - INSIDE_MARGIN);
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < r * r;
}

typedef struct nb_list {
    const vc_balls *b;
    int64_t self;
    int64_t *ids;
    int64_t n, cap;
    int oom;
} nb_list;

static int collect_overlapping(void *ctx, int64_t q)
{
    nb_list *L = ctx;
    if (q == L->self)
        return 0;
    const double *a = L->b->center + 3 * L->self, *c = L->b->center + 3 * q;
    double d[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
    double s = L->b->radius[L->self] + L->b->radius[q];
    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= s * s)
        return 0;
    if (L->n == L->cap) {
        int64_t c2 = L->cap ? 2 * L->cap : 64;
        int64_t *q2 = realloc(L->ids, sizeof(int64_t) * (size_t)c2);
        if (!q2) {
            L->oom = 1;
            return 1;
        }
        L->ids = q2;
        L->cap = c2;
    }
    L->ids[L->n++] = q;
    return 0;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static int overlap(const vc_balls *b, int64_t p, int64_t q)
{
    const double *a = b->center + 3 * p, *c = b->center + 3 * q;
    double d[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
    double s = b->radius[p] + b->radius[q];
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < s * s;
}

/* The covering ball of p among the neighbours (other than i, j, k) that is
 * closest to its sphere (the least shrinking uncovers p), or -1. */
static int64_t best_cover(const vc_balls *b, const nb_list *L, int64_t j, int64_t k,
                          const double p[3])
{
    int64_t best = -1;
    double best_gap = INFINITY;
    for (int64_t m = 0; m < L->n; m++) {
        int64_t f = L->ids[m];
        if (f == j || f == k || !vc_ball_strictly_contains(b, f, p))
            continue;
        const double *c = b->center + 3 * f;
        double d = sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                        (p[2] - c[2]) * (p[2] - c[2]));
        double gap = (b->radius[f] - d) / b->radius[f];
        if (gap < best_gap || (gap == best_gap && f < best)) {
            best_gap = gap;
            best = f;
        }
    }
    return best;
}

int vc_triplets_scan(const vc_ball_set *bs, void (*fn)(void *ctx, const vc_triplet *t),
                     void *ctx)
{
    const vc_balls *b = &bs->b;
    nb_list L = {b, 0, NULL, 0, 0, 0};
    for (int64_t i = 0; i < b->n; i++) {
        L.self = i;
        L.n = 0;
        vc_ball_set_query(bs, b->center + 3 * i, b->radius[i], 1.0, 0.0, collect_overlapping, &L);
        if (L.oom) {
            free(L.ids);
            return -1;
        }
        qsort(L.ids, (size_t)L.n, sizeof(int64_t), cmp_i64);
        for (int64_t a = 0; a < L.n; a++) {
            int64_t j = L.ids[a];
            if (j < i)
                continue;
            for (int64_t c = a + 1; c < L.n; c++) {
                int64_t k = L.ids[c];
                if (!overlap(b, j, k))
                    continue;
                vc_triplet t;
                t.i = i;
                t.j = j;
                t.k = k;
                if (!vc_sphere_triple_points(b->center + 3 * i, b->radius[i], b->center + 3 * j,
                                             b->radius[j], b->center + 3 * k, b->radius[k],
                                             t.up, t.down))
                    continue;
                t.cover_up = best_cover(b, &L, j, k, t.up);
                t.cover_down = best_cover(b, &L, j, k, t.down);
                fn(ctx, &t);
            }
        }
    }
    free(L.ids);
    return 0;
}
