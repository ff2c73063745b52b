#include "balls/triplets.h"
#include "util/reserve.h"
#include "util/small_sort.h"
#include "util/threads.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A point placed on a sphere is inside another ball only when it is inside
 * by more than this fraction of the radius: the shrinking in sliver
 * elimination leaves points 1% of their distance outside, well clear of it. */
#define INSIDE_MARGIN 1e-9

/* Newton steps on the three sphere equations |p - c|^2 = r^2: the frame
 * above rounds in several places, and a point of a triplet must lie on
 * its three spheres as nearly as doubles allow (every seed of a ball's
 * sphere is then co-spherical about its centre to rounding, and the
 * Voronoi vertex there is one point for the engine's merge rule). */
static void refine_on_spheres(const double *ca, double ra, const double *cb, double rb,
                              const double *cc, double rc, double p[3])
{
    const double *c[3] = {ca, cb, cc};
    const double r[3] = {ra, rb, rc};
    for (int it = 0; it < 2; it++) {
        double J[3][3], F[3];
        for (int i = 0; i < 3; i++) {
            double d[3] = {p[0] - c[i][0], p[1] - c[i][1], p[2] - c[i][2]};
            F[i] = fma(d[0], d[0], fma(d[1], d[1], fma(d[2], d[2], -r[i] * r[i])));
            for (int k = 0; k < 3; k++)
                J[i][k] = 2 * d[k];
        }
        const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                           J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                           J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
        if (!(fabs(det) > 0))
            return;
        double x[3];
        for (int k = 0; k < 3; k++) {
            double M[3][3];
            memcpy(M, J, sizeof M);
            for (int i = 0; i < 3; i++)
                M[i][k] = -F[i];
            x[k] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                    M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                    M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
        }
        /* a step far larger than rounding means the solve is not to be
         * trusted (nearly tangent spheres): keep the point */
        if (!(fabs(x[0]) + fabs(x[1]) + fabs(x[2]) < 1e-6 * ra))
            return;
        for (int k = 0; k < 3; k++)
            p[k] += x[k];
    }
}

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
    refine_on_spheres(ca, ra, cb, rb, cc, rc, up);
    refine_on_spheres(ca, ra, cb, rb, cc, rc, down);
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

/* Do balls p and q overlap? The same answer for (q, p). */
static int overlap(const vc_balls *b, int64_t p, int64_t q)
{
    const double *a = b->center + 3 * p, *c = b->center + 3 * q;
    double d[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
    double s = b->radius[p] + b->radius[q];
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < s * s;
}

static int collect_overlapping(void *ctx, int64_t q)
{
    nb_list *L = ctx;
    if (q == L->self || !overlap(L->b, L->self, q))
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

#define ID_LESS(p, q) (*(p) < *(q))
VC_SMALL_SORT(sort_ids, int64_t, ID_LESS)

/* The covering ball of p among the neighbours (other than i, j, k) that is
 * closest to its sphere (the least shrinking uncovers p), or -1; when there
 * is none, *clear is p's clearance from the nearest fourth sphere (see
 * vc_triplet). */
static int64_t best_cover(const vc_balls *b, const nb_list *L, int64_t j, int64_t k,
                          const double p[3], double *clear, int64_t *clear_ball)
{
    int64_t best = -1;
    double best_gap = INFINITY;
    *clear = INFINITY;
    *clear_ball = -1;
    for (int64_t m = 0; m < L->n; m++) {
        int64_t f = L->ids[m];
        if (f == j || f == k)
            continue;
        if (!vc_ball_strictly_contains(b, f, p)) {
            const double *c = b->center + 3 * f;
            double d2 = (p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                        (p[2] - c[2]) * (p[2] - c[2]);
            double q = d2 / (b->radius[f] * b->radius[f]) - 1;
            if (q < *clear) {
                *clear = q;
                *clear_ball = f;
            }
            continue;
        }
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

/* The triplets whose smallest ball is i, appended to *out in increasing
 * (j, k) order. */
typedef struct triplet_buf {
    vc_triplet *t;
    int64_t n, cap;
    int oom;
} triplet_buf;

/* The overlap graph of every ball (CSR, each list ascending). */
typedef struct overlap_graph {
    int64_t *start, *adj;
} overlap_graph;

/* A query's pairs (its ball, a ball it overlaps), per thread. */
typedef struct pair_buf {
    const vc_balls *b;
    int64_t self;
    int64_t *pair; /* 2 per pair */
    int64_t n, cap;
    int oom;
} pair_buf;

/* Lists q when it overlaps self and comes after it in (radius, index)
 * order: every overlapping pair once, from its smaller ball. */
static int collect_later(void *ctx, int64_t q)
{
    pair_buf *P = ctx;
    const vc_balls *b = P->b;
    const double rs = b->radius[P->self], rq = b->radius[q];
    if (!(rq > rs || (rq == rs && q > P->self)) || !overlap(b, P->self, q))
        return 0;
    if (vc_reserve(&P->pair, &P->cap, 2 * P->n + 2, sizeof(int64_t))) {
        P->oom = 1;
        return 1;
    }
    P->pair[2 * P->n] = P->self;
    P->pair[2 * P->n + 1] = q;
    P->n++;
    return 0;
}

/* The overlap graph of every ball of bs: each ball's query reads only the
 * levels of radii at least its own (a ball's level holds radii up to
 * twice its bound), so a pair is found by the query of its smaller ball
 * and entered in both lists. A query down to the smallest balls' levels
 * probes many tiny cells: a full scan's neighbour queries took 0.175 s of
 * CPU on cow.off's 39,000 balls, these 0.07 s. The lists are those
 * collect_overlapping makes. Returns 0, or -1 when out of memory. */
static int build_overlap_graph(const vc_ball_set *bs, int threads, overlap_graph *g)
{
    const vc_balls *b = &bs->b;
    const int64_t n = b->n;
    g->start = NULL;
    g->adj = NULL;
    pair_buf *buf = calloc((size_t)threads, sizeof *buf);
    if (!buf)
        return -1;
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
    for (int64_t i = 0; i < n; i++) {
        int t = 0;
#ifdef _OPENMP
        t = omp_get_thread_num();
#endif
        pair_buf *P = &buf[t];
        P->b = b;
        P->self = i;
        vc_ball_set_query(bs, b->center + 3 * i, b->radius[i], 1.0, b->radius[i], collect_later, P);
    }
    int rc = 0;
    for (int t = 0; t < threads; t++)
        rc |= buf[t].oom;
    int64_t *start = rc ? NULL : calloc((size_t)n + 2, sizeof(int64_t));
    int64_t total = 0;
    for (int t = 0; t < threads; t++)
        total += buf[t].n;
    int64_t *adj = start ? malloc(sizeof(int64_t) * (size_t)(2 * total + 1)) : NULL;
    if (adj) {
        for (int t = 0; t < threads; t++)
            for (int64_t m = 0; m < buf[t].n; m++) {
                start[buf[t].pair[2 * m] + 2]++;
                start[buf[t].pair[2 * m + 1] + 2]++;
            }
        for (int64_t i = 0; i < n; i++)
            start[i + 2] += start[i + 1];
        /* start[i + 1]: where ball i's list is filled next */
        for (int t = 0; t < threads; t++)
            for (int64_t m = 0; m < buf[t].n; m++) {
                const int64_t x = buf[t].pair[2 * m], y = buf[t].pair[2 * m + 1];
                adj[start[x + 1]++] = y;
                adj[start[y + 1]++] = x;
            }
#pragma omp parallel for schedule(dynamic, 1024) num_threads(threads)
        for (int64_t i = 0; i < n; i++)
            sort_ids(adj + start[i], start[i + 1] - start[i]);
    } else
        rc = -1;
    for (int t = 0; t < threads; t++)
        free(buf[t].pair);
    free(buf);
    if (rc) {
        free(start);
        free(adj);
        return -1;
    }
    g->start = start;
    g->adj = adj;
    return 0;
}

/* The balls overlapping ball i into L, ascending: from the graph when
 * there is one, else by a query. */
static int neighbours_of(const vc_ball_set *bs, const overlap_graph *g, int64_t i, nb_list *L)
{
    const vc_balls *b = &bs->b;
    L->self = i;
    L->n = 0;
    if (g && g->start) {
        const int64_t k = g->start[i + 1] - g->start[i];
        if (vc_reserve(&L->ids, &L->cap, k + 1, sizeof(int64_t)))
            return -1;
        memcpy(L->ids, g->adj + g->start[i], sizeof(int64_t) * (size_t)k);
        L->n = k;
        return 0;
    }
    vc_ball_set_query(bs, b->center + 3 * i, b->radius[i], 1.0, 0.0, collect_overlapping, L);
    if (L->oom)
        return -1;
    sort_ids(L->ids, L->n);
    return 0;
}

static void triplets_of(const vc_ball_set *bs, const overlap_graph *g, int64_t i, nb_list *L,
                        triplet_buf *out)
{
    const vc_balls *b = &bs->b;
    if (neighbours_of(bs, g, i, L)) {
        out->oom = 1;
        return;
    }
    for (int64_t a = 0; a < L->n; a++) {
        int64_t j = L->ids[a];
        if (j < i)
            continue;
        for (int64_t c = a + 1; c < L->n; c++) {
            int64_t k = L->ids[c];
            if (!overlap(b, j, k))
                continue;
            vc_triplet t;
            t.i = i;
            t.j = j;
            t.k = k;
            if (!vc_sphere_triple_points(b->center + 3 * i, b->radius[i], b->center + 3 * j,
                                         b->radius[j], b->center + 3 * k, b->radius[k], t.up,
                                         t.down))
                continue;
            t.cover_up = best_cover(b, L, j, k, t.up, &t.clear_up, &t.clear_ball_up);
            t.cover_down = best_cover(b, L, j, k, t.down, &t.clear_down, &t.clear_ball_down);
            if (vc_reserve(&out->t, &out->cap, out->n + 1, sizeof(vc_triplet))) {
                out->oom = 1;
                return;
            }
            out->t[out->n++] = t;
        }
    }
}

/* A ball's triplets change only when it, or a ball that reaches it (whose
 * triplets it shares, or which covers points of its sphere), was added or
 * resized: mark[i] = 1 for those, from the set's changed_reach. */
typedef struct reach_ctx {
    const vc_balls *b;
    const double *c;
    double reach;
    unsigned char *mark;
} reach_ctx;

static int mark_reached(void *ctx, int64_t i)
{
    reach_ctx *r = ctx;
    const double *p = r->b->center + 3 * i;
    double d[3] = {p[0] - r->c[0], p[1] - r->c[1], p[2] - r->c[2]};
    double s = r->reach + r->b->radius[i];
    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < s * s)
        r->mark[i] = 1;
    return 0;
}

/* Balls per block: the triplets of a block are computed in parallel, then
 * handed to fn in (i, j, k) order, so fn sees the same sequence for any
 * thread count. */
#define SCAN_BLOCK 4096

static int scan(const vc_ball_set *bs, const unsigned char *only, int threads,
                void (*fn)(void *ctx, const vc_triplet *t), void *ctx)
{
    const vc_balls *b = &bs->b;
    const int64_t n = b->n;
    threads = vc_threads_or_default(threads);
    int64_t *first = malloc(sizeof(int64_t) * SCAN_BLOCK), *count = malloc(sizeof(int64_t) * SCAN_BLOCK);
    int *owner = malloc(sizeof(int) * SCAN_BLOCK);
    triplet_buf *buf = calloc((size_t)threads, sizeof *buf);
    nb_list *lists = calloc((size_t)threads, sizeof *lists);
    int rc = (!first || !count || !owner || !buf || !lists) ? -1 : 0;
    /* every ball: its neighbours from the overlap graph (a scan of a few
     * balls queries for them) */
    overlap_graph graph = {NULL, NULL};
    if (!rc && !only && build_overlap_graph(bs, threads, &graph))
        rc = -1;
    for (int64_t start = 0; start < n && !rc; start += SCAN_BLOCK) {
        const int64_t end = start + SCAN_BLOCK < n ? start + SCAN_BLOCK : n;
        for (int t = 0; t < threads; t++)
            buf[t].n = 0;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
        for (int64_t i = start; i < end; i++) {
            int t = 0;
#ifdef _OPENMP
            t = omp_get_thread_num();
#endif
            owner[i - start] = t;
            first[i - start] = buf[t].n;
            if (!only || only[i]) {
                lists[t].b = b;
                triplets_of(bs, &graph, i, &lists[t], &buf[t]);
            }
            count[i - start] = buf[t].n - first[i - start];
        }
        for (int t = 0; t < threads; t++)
            if (buf[t].oom || lists[t].oom)
                rc = -1;
        if (rc)
            break;
        for (int64_t i = start; i < end; i++) {
            const triplet_buf *tb = &buf[owner[i - start]];
            for (int64_t q = first[i - start]; q < first[i - start] + count[i - start]; q++)
                fn(ctx, &tb->t[q]);
        }
    }
    free(graph.start);
    free(graph.adj);
    for (int t = 0; buf && t < threads; t++)
        free(buf[t].t);
    for (int t = 0; lists && t < threads; t++)
        free(lists[t].ids);
    free(buf);
    free(lists);
    free(first);
    free(count);
    free(owner);
    return rc;
}

int vc_triplets_scan_changed(vc_ball_set *bs, int threads,
                             void (*fn)(void *ctx, const vc_triplet *t), void *ctx,
                             unsigned char *scanned)
{
    const vc_balls *b = &bs->b;
    unsigned char *mark = NULL;
    if (bs->n_changed < b->n / 2) {
        mark = calloc((size_t)b->n + 1, 1);
        if (!mark)
            return -1;
        for (int64_t q = 0; q < b->n; q++) {
            if (!(bs->changed_reach[q] > 0))
                continue;
            mark[q] = 1;
            reach_ctx r = {b, b->center + 3 * q, bs->changed_reach[q], mark};
            vc_ball_set_query(bs, r.c, r.reach, 1.0, 0.0, mark_reached, &r);
        }
    }
    vc_ball_set_forget_changes(bs);
    if (scanned) {
        if (mark)
            memcpy(scanned, mark, (size_t)b->n);
        else
            memset(scanned, 1, (size_t)b->n);
    }
    int rc = scan(bs, mark, threads, fn, ctx);
    free(mark);
    return rc;
}

int vc_triplets_scan_all(vc_ball_set *bs, int threads,
                         void (*fn)(void *ctx, const vc_triplet *t), void *ctx)
{
    vc_ball_set_forget_changes(bs);
    return scan(bs, NULL, threads, fn, ctx);
}
