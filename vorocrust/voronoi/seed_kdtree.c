#include "seed_kdtree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


/* Points per leaf: a few, so that a query reads few beyond the k it keeps
 * (bunny.off's 153,626 seeds, 48 neighbours: 8.5 us per query with 8 per
 * leaf, 7.2 with 16, 7.1 with 32). */
#define LEAF_SIZE 16

static int before(const vc_seed_kdtree *t, int64_t a, int64_t b, int d)
{
    const double x = t->xyz[3 * a + d], y = t->xyz[3 * b + d];
    return x < y || (x == y && t->index[a] < t->index[b]);
}

static void swap_points(vc_seed_kdtree *t, int64_t a, int64_t b)
{
    for (int d = 0; d < 3; d++) {
        const double v = t->xyz[3 * a + d];
        t->xyz[3 * a + d] = t->xyz[3 * b + d];
        t->xyz[3 * b + d] = v;
    }
    const int64_t i = t->index[a];
    t->index[a] = t->index[b];
    t->index[b] = i;
}

/* Puts the point of rank m (by coordinate d, then seed index) of
 * [lo, hi) at m, smaller ones before it (quickselect, middle pivot). */
static void select_rank(vc_seed_kdtree *t, int64_t lo, int64_t hi, int64_t m, int d)
{
    while (hi - lo > 1) {
        swap_points(t, lo + (hi - lo) / 2, hi - 1); /* pivot to the end */
        int64_t store = lo;
        for (int64_t i = lo; i < hi - 1; i++)
            if (before(t, i, hi - 1, d))
                swap_points(t, i, store++);
        swap_points(t, store, hi - 1);
        if (store == m)
            return;
        if (m < store)
            hi = store;
        else
            lo = store + 1;
    }
}

static int64_t build_node(vc_seed_kdtree *t, int64_t begin, int64_t end)
{
    const int64_t id = t->n_nodes++;
    vc_kd_node *nd = &t->node[id];
    for (int d = 0; d < 3; d++) {
        nd->lo[d] = t->xyz[3 * begin + d];
        nd->hi[d] = t->xyz[3 * begin + d];
    }
    for (int64_t i = begin + 1; i < end; i++)
        for (int d = 0; d < 3; d++) {
            const double x = t->xyz[3 * i + d];
            nd->lo[d] = x < nd->lo[d] ? x : nd->lo[d];
            nd->hi[d] = x > nd->hi[d] ? x : nd->hi[d];
        }
    nd->begin = begin;
    nd->end = end;
    nd->left = nd->right = -1;
    if (end - begin <= LEAF_SIZE)
        return id;
    int dim = 0;
    for (int d = 1; d < 3; d++)
        if (nd->hi[d] - nd->lo[d] > nd->hi[dim] - nd->lo[dim])
            dim = d;
    const int64_t mid = begin + (end - begin) / 2;
    select_rank(t, begin, end, mid, dim);
    const int64_t l = build_node(t, begin, mid);
    const int64_t r = build_node(t, mid, end);
    t->node[id].left = l; /* nd may have moved? no: node is preallocated */
    t->node[id].right = r;
    return id;
}

int vc_seed_kdtree_build(vc_seed_kdtree *t, const double *xyz, int64_t n)
{
    memset(t, 0, sizeof *t);
    t->n = n;
    /* at most 2 n / (LEAF_SIZE / 2) + 1 nodes: every leaf holds more than
     * LEAF_SIZE / 2 points unless the tree is one leaf */
    const int64_t max_nodes = n > 0 ? 4 * (n / (LEAF_SIZE / 2) + 1) : 1;
    t->xyz = malloc(sizeof(double) * 3 * (size_t)(n > 0 ? n : 1));
    t->index = malloc(sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
    t->node = malloc(sizeof(vc_kd_node) * (size_t)max_nodes);
    if (!t->xyz || !t->index || !t->node) {
        vc_seed_kdtree_free(t);
        return -1;
    }
    memcpy(t->xyz, xyz, sizeof(double) * 3 * (size_t)n);
    for (int64_t i = 0; i < n; i++)
        t->index[i] = i;
    if (n > 0)
        build_node(t, 0, n);
    return 0;
}

void vc_seed_kdtree_refit(vc_seed_kdtree *t, const double *xyz)
{
    for (int64_t i = 0; i < t->n; i++)
        memcpy(t->xyz + 3 * i, xyz + 3 * t->index[i], 3 * sizeof(double));
    /* children come after their parent: from the last node back */
    for (int64_t id = t->n_nodes - 1; id >= 0; id--) {
        vc_kd_node *nd = &t->node[id];
        if (nd->left < 0) {
            for (int d = 0; d < 3; d++)
                nd->lo[d] = nd->hi[d] = t->xyz[3 * nd->begin + d];
            for (int64_t i = nd->begin + 1; i < nd->end; i++)
                for (int d = 0; d < 3; d++) {
                    const double x = t->xyz[3 * i + d];
                    nd->lo[d] = x < nd->lo[d] ? x : nd->lo[d];
                    nd->hi[d] = x > nd->hi[d] ? x : nd->hi[d];
                }
            continue;
        }
        const vc_kd_node *l = &t->node[nd->left], *r = &t->node[nd->right];
        for (int d = 0; d < 3; d++) {
            nd->lo[d] = l->lo[d] < r->lo[d] ? l->lo[d] : r->lo[d];
            nd->hi[d] = l->hi[d] > r->hi[d] ? l->hi[d] : r->hi[d];
        }
    }
}

void vc_seed_kdtree_free(vc_seed_kdtree *t)
{
    free(t->xyz);
    free(t->index);
    free(t->node);
    memset(t, 0, sizeof *t);
}

/* (d2, seed) order */
static inline int worse(const vc_kd_hit *a, const vc_kd_hit *b)
{
    return a->d2 > b->d2 || (a->d2 == b->d2 && a->seed > b->seed);
}

/* Inserts h into the sorted hits (n of them, room for cap): the worst
 * drops out when they are full, and h is left out when it sorts after all
 * of them then. Insertion by moving the worse ones up one place: a query's
 * hits arrive nearly nearest first (nearer boxes first), so few move; a
 * max-heap cost bunny.off's 48-nearest queries 6.6 us each, this 4.9. */
static inline int insert_sorted(vc_kd_hit *hit, int n, int cap, vc_kd_hit h)
{
    int j;
    if (n < cap)
        j = n++;
    else if (worse(&hit[cap - 1], &h))
        j = cap - 1;
    else
        return n;
    while (j > 0 && worse(&hit[j - 1], &h)) {
        hit[j] = hit[j - 1];
        j--;
    }
    hit[j] = h;
    return n;
}

static double box_dist2(const vc_kd_node *nd, const double x[3])
{
    double s = 0;
    for (int d = 0; d < 3; d++) {
        const double e = x[d] < nd->lo[d] ? nd->lo[d] - x[d] : (x[d] > nd->hi[d] ? x[d] - nd->hi[d] : 0);
        s += e * e;
    }
    return s;
}

/* The squared distance from x to the farthest point of the node's box. */
static double box_dist2_far(const vc_kd_node *nd, const double x[3])
{
    double s = 0;
    for (int d = 0; d < 3; d++) {
        const double a = x[d] - nd->lo[d], b = nd->hi[d] - x[d];
        const double e = a > b ? a : b;
        s += e * e;
    }
    return s;
}

int vc_seed_kdtree_knn(const vc_seed_kdtree *t, const double x[3], int k, int64_t skip,
                       vc_kd_hit *hit)
{
    return vc_seed_kdtree_knn_within(t, x, k, skip, INFINITY, hit);
}

int vc_seed_kdtree_knn_within(const vc_seed_kdtree *t, const double x[3], int k, int64_t skip,
                              double bound2, vc_kd_hit *hit)
{
    if (t->n == 0 || k <= 0)
        return 0;
    int n = 0;
    /* depth-first, nearer child first; a node is skipped when its box is
     * farther than the k-th hit so far (ties kept: a farther box cannot
     * hold a point that sorts before it) */
    int64_t stack[128];
    double stack_d2[128];
    int top = 0;
    stack[top] = 0;
    stack_d2[top++] = box_dist2(&t->node[0], x);
    double limit = bound2; /* the k-th hit's once there are k */
    while (top > 0) {
        --top;
        const int64_t id = stack[top];
        if (stack_d2[top] > limit)
            continue;
        const vc_kd_node *nd = &t->node[id];
        if (nd->left < 0) {
            for (int64_t i = nd->begin; i < nd->end; i++) {
                const double *p = t->xyz + 3 * i;
                const double dx = p[0] - x[0], dy = p[1] - x[1], dz = p[2] - x[2];
                const double d2 = dx * dx + dy * dy + dz * dz;
                const int64_t s = t->index[i];
                if (d2 > limit || s == skip)
                    continue;
                n = insert_sorted(hit, n, k, (vc_kd_hit){d2, s});
                if (n == k)
                    limit = hit[k - 1].d2;
            }
            continue;
        }
        const double dl = box_dist2(&t->node[nd->left], x);
        const double dr = box_dist2(&t->node[nd->right], x);
        /* push the farther first, so the nearer is visited next */
        const int64_t a = dl <= dr ? nd->left : nd->right, b = dl <= dr ? nd->right : nd->left;
        const double da = dl <= dr ? dl : dr, db = dl <= dr ? dr : dl;
        if (!(db > limit)) {
            stack[top] = b;
            stack_d2[top++] = db;
        }
        stack[top] = a;
        stack_d2[top++] = da;
    }
    return n;
}

int vc_seed_kdtree_knn_hinted(const vc_seed_kdtree *t, vc_kd_hint *hint, const double x[3], int k,
                              int64_t skip, vc_kd_hit *hit)
{
    int got = -1;
    if (hint->valid && hint->k == k) {
        const double dx = x[0] - hint->x[0], dy = x[1] - hint->x[1], dz = x[2] - hint->x[2];
        /* grown far above the rounding of the distances */
        const double b = (hint->kth + sqrt(dx * dx + dy * dy + dz * dz)) * (1 + 1e-9);
        got = vc_seed_kdtree_knn_within(t, x, k, skip, b * b, hit);
        if (got < k)
            got = -1; /* fewer within the bound: ask without it */
    }
    if (got < 0)
        got = vc_seed_kdtree_knn(t, x, k, skip, hit);
    hint->valid = got == k && k > 0;
    if (hint->valid) {
        hint->k = k;
        memcpy(hint->x, x, sizeof hint->x);
        hint->kth = sqrt(hit[got - 1].d2);
    }
    return got;
}

int vc_seed_kdtree_within(const vc_seed_kdtree *t, const double x[3], double r2, vc_kd_hit after,
                          int64_t skip, int (*reach)(void *ctx, const double lo[3], const double hi[3]),
                          void *ctx, vc_kd_hit *hit, int cap, int *truncated)
{
    *truncated = 0;
    if (t->n == 0 || cap <= 0)
        return 0;
    int n = 0;
    int64_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vc_kd_node *nd = &t->node[stack[--top]];
        const double near2 = box_dist2(nd, x);
        if (near2 > r2 || box_dist2_far(nd, x) < after.d2 || (reach && !reach(ctx, nd->lo, nd->hi)))
            continue;
        if (n == cap && near2 > hit[cap - 1].d2) {
            *truncated = 1; /* what it holds comes after the cap */
            continue;
        }
        if (nd->left >= 0) {
            stack[top++] = nd->left;
            stack[top++] = nd->right;
            continue;
        }
        for (int64_t i = nd->begin; i < nd->end; i++) {
            const int64_t s = t->index[i];
            const double *p = t->xyz + 3 * i;
            const double dx = p[0] - x[0], dy = p[1] - x[1], dz = p[2] - x[2];
            const vc_kd_hit h = {dx * dx + dy * dy + dz * dz, s};
            if (h.d2 > r2 || s == skip || !worse(&h, &after) || (reach && !reach(ctx, p, p)))
                continue;
            if (n == cap)
                *truncated = 1;
            n = insert_sorted(hit, n, cap, h);
        }
    }
    return n;
}
