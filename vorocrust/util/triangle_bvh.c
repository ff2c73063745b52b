/* The triangle hierarchy (see triangle_bvh.h). */
#include "util/triangle_bvh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/closest_point.h"
#include "util/median_tree.h"

#define BVH_LEAF 4

/* Key of triangle t along axis: its centroid coordinate, ties by id, so
 * every key is distinct and the partition is deterministic. */
static inline int key_less(const double *cen, int axis, int64_t t, int64_t u)
{
    double a = cen[3 * t + axis], b = cen[3 * u + axis];
    return a < b || (a == b && t < u);
}

/* Reorders tri[0..n) so that tri[k] is the k-th smallest by key and
 * everything before it is smaller (quickselect, median-of-three pivot). */
static void select_kth(int64_t *tri, int64_t n, int64_t k, const double *cen, int axis)
{
    int64_t lo = 0, hi = n - 1;
    while (hi > lo) {
        int64_t mid = lo + (hi - lo) / 2;
        /* median of three to tri[mid] */
        if (key_less(cen, axis, tri[mid], tri[lo])) { int64_t x = tri[mid]; tri[mid] = tri[lo]; tri[lo] = x; }
        if (key_less(cen, axis, tri[hi], tri[lo])) { int64_t x = tri[hi]; tri[hi] = tri[lo]; tri[lo] = x; }
        if (key_less(cen, axis, tri[hi], tri[mid])) { int64_t x = tri[hi]; tri[hi] = tri[mid]; tri[mid] = x; }
        int64_t pivot = tri[mid];
        int64_t i = lo, j = hi;
        while (i <= j) {
            while (key_less(cen, axis, tri[i], pivot))
                i++;
            while (key_less(cen, axis, pivot, tri[j]))
                j--;
            if (i <= j) {
                int64_t x = tri[i];
                tri[i] = tri[j];
                tri[j] = x;
                i++;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

/* Builds the subtree of tri[first .. first+count), node id and its
 * descendants numbered in preorder from id; returns the next free node
 * index. Split at the median centroid along the longest axis of the
 * centroids' box; halves above VC_MEDIAN_TREE_TASK triangles built as two
 * OpenMP tasks (their node numbers follow from their counts: the same tree
 * for any thread count). */
static int32_t build_range(vc_tri_bvh *h, int32_t id, int32_t first, int32_t count, const double *cen)
{
    vc_tri_bvh_node *nd = &h->node[id];
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count > BVH_LEAF) {
        double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int32_t k = first; k < first + count; k++)
            for (int d = 0; d < 3; d++) {
                clo[d] = fmin(clo[d], cen[3 * h->order[k] + d]);
                chi[d] = fmax(chi[d], cen[3 * h->order[k] + d]);
            }
        int axis = 0;
        for (int d = 1; d < 3; d++)
            if (chi[d] - clo[d] > chi[axis] - clo[axis])
                axis = d;
        int32_t half = count / 2;
        select_kth(h->order + first, count, half, cen, axis);
        const int32_t l = id + 1;
        int32_t r, next;
        if (count > VC_MEDIAN_TREE_TASK) {
            r = l + (int32_t)vc_median_tree_nodes(half, BVH_LEAF);
#pragma omp task default(shared)
            build_range(h, l, first, half, cen);
            next = build_range(h, r, first + half, count - half, cen);
#pragma omp taskwait
        } else {
            r = build_range(h, l, first, half, cen);
            next = build_range(h, r, first + half, count - half, cen);
        }
        nd = &h->node[id];
        nd->left = l;
        nd->right = r;
        for (int d = 0; d < 3; d++) {
            /* float boxes: the children's bounds, exact */
            nd->lo[d] = h->node[l].lo[d] < h->node[r].lo[d] ? h->node[l].lo[d] : h->node[r].lo[d];
            nd->hi[d] = h->node[l].hi[d] > h->node[r].hi[d] ? h->node[l].hi[d] : h->node[r].hi[d];
        }
        return next;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int32_t k = first; k < first + count; k++)
        for (int c = 0; c < 3; c++) {
            const double *p = h->xyz + 3 * h->tri[3 * h->order[k] + c];
            for (int d = 0; d < 3; d++) {
                lo[d] = fmin(lo[d], p[d]);
                hi[d] = fmax(hi[d], p[d]);
            }
        }
    for (int d = 0; d < 3; d++) {
        /* round outward so the float box still contains the triangles */
        float fl = (float)lo[d], fh = (float)hi[d];
        nd->lo[d] = (double)fl > lo[d] ? nextafterf(fl, -INFINITY) : fl;
        nd->hi[d] = (double)fh < hi[d] ? nextafterf(fh, INFINITY) : fh;
    }
    return id + 1;
}

int vc_tri_bvh_build(vc_tri_bvh *h, const double *xyz, const int64_t *tri, int64_t n, int nth)
{
    memset(h, 0, sizeof *h);
    h->xyz = xyz;
    h->tri = tri;
    if (n > INT32_MAX / 2)
        return -1;
    double *cen = malloc(sizeof *cen * 3 * (size_t)(n ? n : 1));
    h->order = malloc(sizeof *h->order * (size_t)(n ? n : 1));
    h->node = malloc(sizeof *h->node * (size_t)(2 * n + 1));
    if (!cen || !h->order || !h->node) {
        free(cen);
        vc_tri_bvh_free(h);
        return -1;
    }
#pragma omp parallel for schedule(static) num_threads(nth)
    for (int64_t t = 0; t < n; t++) {
        h->order[t] = t;
        for (int d = 0; d < 3; d++) {
            double c = 0;
            for (int k = 0; k < 3; k++)
                c += xyz[3 * tri[3 * t + k] + d];
            cen[3 * t + d] = c / 3.0;
        }
    }
    int32_t n_nodes = 0;
    if (n > 0) {
#pragma omp parallel num_threads(nth) if (n > VC_MEDIAN_TREE_TASK)
#pragma omp single
        n_nodes = build_range(h, 0, 0, (int32_t)n, cen);
    }
    h->n_nodes = n_nodes;
    free(cen);
    return 0;
}

void vc_tri_bvh_free(vc_tri_bvh *h)
{
    free(h->order);
    free(h->node);
    memset(h, 0, sizeof *h);
}

static double box_dist2(const vc_tri_bvh_node *nd, const double p[3])
{
    double s = 0;
    for (int d = 0; d < 3; d++) {
        double v = p[d] < nd->lo[d] ? nd->lo[d] - p[d] : p[d] > nd->hi[d] ? p[d] - nd->hi[d] : 0;
        s += v * v;
    }
    return s;
}

static double tri_dist2(const vc_tri_bvh *h, int64_t t, const double p[3])
{
    const int64_t *v = h->tri + 3 * t;
    return vc_closest_on_triangle(p, h->xyz + 3 * v[0], h->xyz + 3 * v[1], h->xyz + 3 * v[2], NULL);
}

/* Squared distances throughout; the stack keeps each node's box distance,
 * computed once when its parent is opened. */
double vc_tri_bvh_distance_above(const vc_tri_bvh *h, const double p[3], double threshold,
                                 int64_t *hint)
{
    int32_t stack[128];
    double stack_d2[128];
    int top = 0;
    /* (OpenMP starts a max reduction at -DBL_MAX: a negative threshold
     * must not square into a large limit) */
    double best2 = INFINITY, limit2 = threshold >= 0 ? threshold * threshold : -1.0;
    if (*hint >= 0) {
        best2 = tri_dist2(h, *hint, p);
        if (best2 <= limit2)
            return sqrt(best2);
    }
    stack[top] = 0;
    stack_d2[top++] = box_dist2(&h->node[0], p);
    while (top > 0) {
        --top;
        if (stack_d2[top] >= best2)
            continue;
        const vc_tri_bvh_node *nd = &h->node[stack[top]];
        if (nd->left < 0) {
            for (int32_t k = nd->first; k < nd->first + nd->count; k++) {
                double d2 = tri_dist2(h, h->order[k], p);
                if (d2 < best2) {
                    best2 = d2;
                    *hint = h->order[k];
                    if (best2 <= limit2)
                        return sqrt(best2);
                }
            }
            continue;
        }
        double dl = box_dist2(&h->node[nd->left], p), dr = box_dist2(&h->node[nd->right], p);
        /* push the farther child first so the nearer one is searched first */
        int32_t near = dl <= dr ? nd->left : nd->right, far = dl <= dr ? nd->right : nd->left;
        double dnear = dl <= dr ? dl : dr, dfar = dl <= dr ? dr : dl;
        if (dfar < best2) {
            stack[top] = far;
            stack_d2[top++] = dfar;
        }
        if (dnear < best2) {
            stack[top] = near;
            stack_d2[top++] = dnear;
        }
    }
    return sqrt(best2);
}

double vc_tri_bvh_nearest_where(const vc_tri_bvh *h, const double p[3], double within,
                                int (*keep)(void *ctx, int64_t t, double d2), void *ctx)
{
    if (h->n_nodes == 0)
        return INFINITY;
    int32_t stack[128];
    double stack_d2[128];
    int top = 0;
    double best2 = within * within;
    int found = 0;
    stack[top] = 0;
    stack_d2[top++] = box_dist2(&h->node[0], p);
    while (top > 0) {
        --top;
        if (stack_d2[top] > best2)
            continue;
        const vc_tri_bvh_node *nd = &h->node[stack[top]];
        if (nd->left < 0) {
            for (int32_t k = nd->first; k < nd->first + nd->count; k++) {
                const double d2 = tri_dist2(h, h->order[k], p);
                if (d2 <= best2 && keep(ctx, h->order[k], d2)) {
                    best2 = d2;
                    found = 1;
                }
            }
            continue;
        }
        double dl = box_dist2(&h->node[nd->left], p), dr = box_dist2(&h->node[nd->right], p);
        int32_t near = dl <= dr ? nd->left : nd->right, far = dl <= dr ? nd->right : nd->left;
        double dnear = dl <= dr ? dl : dr, dfar = dl <= dr ? dr : dl;
        if (dfar <= best2 && top < 127) {
            stack[top] = far;
            stack_d2[top++] = dfar;
        }
        if (dnear <= best2 && top < 127) {
            stack[top] = near;
            stack_d2[top++] = dnear;
        }
    }
    return found ? sqrt(best2) : INFINITY;
}
