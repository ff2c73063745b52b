/* Two-sided Hausdorff distance between triangle surfaces.
 *
 * Samples: the barycentric grid of every triangle with n = ceil(longest
 * edge / spacing) subdivisions per edge (its corners are the vertices, its
 * border points the edge points). Every point of the triangle is then
 * within the circumradius-like bound (longest edge / n) / sqrt(3) of a
 * grid point (the farthest point from the corners of a triangle with
 * longest edge l is at most l / sqrt(3) away from them).
 *
 * Distances to the other surface: a bounding-volume hierarchy over its
 * triangles, split at the median centroid along the longest axis (a
 * balanced tree, no tuning), queried nearest-child first with pruning on
 * box distance. A sample closer to the
 * other surface than the running maximum cannot change the result, so its
 * search stops at the first triangle that close (usually the previous
 * sample's nearest triangle), and whole triangles are skipped when a
 * Lipschitz bound from their corners shows they cannot hold the maximum. */
#include "vorocrust/quality.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "quality/vec3.h"
#include "quality/quality_internal.h"
#include "util/median_tree.h"
#include "util/threads.h"

#define BVH_LEAF 4
#define SAMPLE_BUDGET 1000000.0

typedef struct bvh_node {
    float lo[3], hi[3];   /* slightly padded box (float is enough for pruning) */
    int32_t left, right;  /* children, or -1; leaves hold tri[first .. first+count) */
    int32_t first, count;
} bvh_node;

typedef struct bvh {
    const vc_surface *s;
    int64_t *tri;         /* triangle ids in Morton order */
    bvh_node *node;
    int32_t n_nodes;
} bvh;

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
static int32_t bvh_build_range(bvh *h, int32_t id, int32_t first, int32_t count, const double *cen)
{
    bvh_node *nd = &h->node[id];
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count > BVH_LEAF) {
        double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int32_t k = first; k < first + count; k++)
            for (int d = 0; d < 3; d++) {
                clo[d] = dmin(clo[d], cen[3 * h->tri[k] + d]);
                chi[d] = dmax(chi[d], cen[3 * h->tri[k] + d]);
            }
        int axis = 0;
        for (int d = 1; d < 3; d++)
            if (chi[d] - clo[d] > chi[axis] - clo[axis])
                axis = d;
        int32_t half = count / 2;
        select_kth(h->tri + first, count, half, cen, axis);
        const int32_t l = id + 1;
        int32_t r, next;
        if (count > VC_MEDIAN_TREE_TASK) {
            r = l + (int32_t)vc_median_tree_nodes(half, BVH_LEAF);
#pragma omp task default(shared)
            bvh_build_range(h, l, first, half, cen);
            next = bvh_build_range(h, r, first + half, count - half, cen);
#pragma omp taskwait
        } else {
            r = bvh_build_range(h, l, first, half, cen);
            next = bvh_build_range(h, r, first + half, count - half, cen);
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
            const double *p = h->s->xyz + 3 * h->s->tri[3 * h->tri[k] + c];
            for (int d = 0; d < 3; d++) {
                lo[d] = dmin(lo[d], p[d]);
                hi[d] = dmax(hi[d], p[d]);
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

static int bvh_build(bvh *h, const vc_surface *s, int nth)
{
    memset(h, 0, sizeof *h);
    h->s = s;
    int64_t n = s->n_triangles;
    if (n > INT32_MAX / 2)
        return VC_ENOMEM;
    double *cen = malloc(sizeof *cen * 3 * (size_t)n);
    h->tri = malloc(sizeof *h->tri * (size_t)n);
    h->node = malloc(sizeof *h->node * (size_t)(2 * n + 1));
    if (!cen || !h->tri || !h->node) {
        free(cen);
        return VC_ENOMEM;
    }
#pragma omp parallel for schedule(static) num_threads(nth)
    for (int64_t t = 0; t < n; t++) {
        h->tri[t] = t;
        for (int d = 0; d < 3; d++) {
            double c = 0;
            for (int k = 0; k < 3; k++)
                c += s->xyz[3 * s->tri[3 * t + k] + d];
            cen[3 * t + d] = c / 3.0;
        }
    }
    int32_t n_nodes = 0;
#pragma omp parallel num_threads(nth) if (n > VC_MEDIAN_TREE_TASK)
#pragma omp single
    n_nodes = bvh_build_range(h, 0, 0, (int32_t)n, cen);
    h->n_nodes = n_nodes;
    free(cen);
    return VC_OK;
}

static void bvh_free(bvh *h)
{
    free(h->tri);
    free(h->node);
}

static double box_dist2(const bvh_node *nd, const double p[3])
{
    double s = 0;
    for (int d = 0; d < 3; d++) {
        double v = p[d] < nd->lo[d] ? nd->lo[d] - p[d] : p[d] > nd->hi[d] ? p[d] - nd->hi[d] : 0;
        s += v * v;
    }
    return s;
}

static double tri_dist2(const vc_surface *s, int64_t t, const double p[3])
{
    const int64_t *v = s->tri + 3 * t;
    return vc_point_triangle_dist2(p, s->xyz + 3 * v[0], s->xyz + 3 * v[1], s->xyz + 3 * v[2]);
}

/* The distance from p to the hierarchy's surface when it exceeds
 * `threshold`; otherwise some value <= threshold (the search stops as soon
 * as a triangle that close is found: such a sample cannot raise the
 * maximum). *hint is a triangle to try first (or -1); it is updated to the
 * nearest triangle found. Squared distances throughout; the stack keeps
 * each node's box distance, computed once when its parent is opened. */
static double bvh_distance_above(const bvh *h, const double p[3], double threshold,
                                 int64_t *hint)
{
    int32_t stack[128];
    double stack_d2[128];
    int top = 0;
    /* (OpenMP starts a max reduction at -DBL_MAX: a negative threshold
     * must not square into a large limit) */
    double best2 = INFINITY, limit2 = threshold >= 0 ? threshold * threshold : -1.0;
    if (*hint >= 0) {
        best2 = tri_dist2(h->s, *hint, p);
        if (best2 <= limit2)
            return sqrt(best2);
    }
    stack[top] = 0;
    stack_d2[top++] = box_dist2(&h->node[0], p);
    while (top > 0) {
        --top;
        if (stack_d2[top] >= best2)
            continue;
        const bvh_node *nd = &h->node[stack[top]];
        if (nd->left < 0) {
            for (int32_t k = nd->first; k < nd->first + nd->count; k++) {
                double d2 = tri_dist2(h->s, h->tri[k], p);
                if (d2 < best2) {
                    best2 = d2;
                    *hint = h->tri[k];
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

static double tri_longest_edge(const vc_surface *s, int64_t t)
{
    const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                 *c = s->xyz + 3 * s->tri[3 * t + 2];
    return sqrt(fmax(v3_dist2(a, b), fmax(v3_dist2(b, c), v3_dist2(c, a))));
}

static int64_t subdivisions(double longest, double spacing)
{
    double n = ceil(longest / spacing);
    return n < 1 ? 1 : n > 1e6 ? 1000000 : (int64_t)n;
}

static double count_samples(const vc_surface *s, double spacing)
{
    double total = 0;
    for (int64_t t = 0; t < s->n_triangles; t++) {
        double n = (double)subdivisions(tri_longest_edge(s, t), spacing);
        total += (n + 1) * (n + 2) / 2;
    }
    return total;
}

/* max over the samples of `from` of the distance to the hierarchy `to`;
 * -1 when out of memory.
 *
 * First the exact distance of every vertex (they are samples). Since the
 * distance is 1-Lipschitz and every point of a triangle with longest edge
 * l is within l / sqrt(3) of a corner, no sample of a triangle can exceed
 * max(corner distances) + l / sqrt(3); a triangle whose bound is below the
 * running maximum is skipped whole. Skipped samples and early-stopped
 * searches can never hold the maximum, so the result is exactly the
 * maximum over all samples, whatever the thread count or order. */
static double one_sided(const vc_surface *from, const bvh *to, double spacing, int nth,
                        int64_t *n_samples, double *sub_edge)
{
    const int64_t nv = from->n_vertices, nt = from->n_triangles;
    double *dv = malloc(sizeof *dv * (size_t)(nv ? nv : 1));
    int64_t *near_tri = malloc(sizeof *near_tri * (size_t)(nv ? nv : 1));
    if (!dv || !near_tri) {
        free(dv);
        free(near_tri);
        return -1;
    }
    for (int64_t v = 0; v < nv; v++)
        near_tri[v] = -2; /* not a corner of any triangle: not a sample */
    for (int64_t k = 0; k < 3 * nt; k++)
        near_tri[from->tri[k]] = -1;
    double vmax = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(max : vmax) num_threads(nth)
    for (int64_t v = 0; v < nv; v++) {
        dv[v] = 0;
        if (near_tri[v] == -2)
            continue;
        dv[v] = bvh_distance_above(to, from->xyz + 3 * v, -1.0, &near_tri[v]);
        if (dv[v] > vmax)
            vmax = dv[v];
    }
    double worst = 0, longest_sub = 0;
    int64_t count = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : worst, longest_sub) reduction(+ : count) num_threads(nth)
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *id = from->tri + 3 * t;
        const double *a = from->xyz + 3 * id[0], *b = from->xyz + 3 * id[1], *c = from->xyz + 3 * id[2];
        double longest = tri_longest_edge(from, t);
        int64_t n = subdivisions(longest, spacing);
        if (longest / (double)n > longest_sub)
            longest_sub = longest / (double)n; /* <= spacing unless n hit its cap */
        count += (n + 1) * (n + 2) / 2;
        double floor_ = worst > vmax ? worst : vmax;
        double corner = fmax(dv[id[0]], fmax(dv[id[1]], dv[id[2]]));
        if (corner + longest / sqrt(3.0) <= floor_)
            continue;
        int64_t hint = near_tri[id[0]]; /* neighbouring samples share their nearest triangle */
        for (int64_t i = 0; i <= n; i++)
            for (int64_t j = 0; i + j <= n; j++) {
                double u = (double)i / (double)n, v = (double)j / (double)n, w = 1.0 - u - v;
                double p[3];
                for (int d = 0; d < 3; d++)
                    p[d] = w * a[d] + u * b[d] + v * c[d];
                /* only a sample beyond this thread's maximum matters, so
                 * the search may stop at the first triangle that close */
                double dist = bvh_distance_above(to, p, floor_, &hint);
                if (dist > floor_)
                    floor_ = dist;
            }
        if (floor_ > worst)
            worst = floor_;
    }
    free(dv);
    free(near_tri);
    *n_samples = count;
    *sub_edge = longest_sub;
    return worst > vmax ? worst : vmax;
}

static double bbox_diagonal(const vc_surface *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t t = 0; t < 3 * s->n_triangles; t++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * s->tri[t] + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * s->tri[t] + d]);
        }
    double e[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    return v3_norm(e);
}

int vc_hausdorff(const vc_surface *a, const vc_surface *b, double spacing,
                 vc_hausdorff_result *out, vc_error *err)
{
    return vc_hausdorff_threads(a, b, spacing, 0, out, err);
}

int vc_hausdorff_threads(const vc_surface *a, const vc_surface *b, double spacing, int threads,
                         vc_hausdorff_result *out, vc_error *err)
{
    const int nth = vc_threads_or_default(threads);
    memset(out, 0, sizeof *out);
    if (!a || !b || a->n_triangles < 1 || b->n_triangles < 1)
        return vc_error_set(err, VC_EINPUT, "Hausdorff distance: a surface has no triangle");
    double diag = bbox_diagonal(a);
    if (!(spacing > 0)) {
        spacing = diag > 0 ? 1e-3 * diag : 1.0;
        /* Coarsen until neither side exceeds the budget (samples scale as
         * 1 / spacing^2, plus at least 3 per triangle). */
        for (int it = 0; it < 40; it++) {
            double na = count_samples(a, spacing), nb = count_samples(b, spacing);
            double worst = fmax(na, nb);
            double floor_samples = 3.0 * (double)(a->n_triangles > b->n_triangles ? a->n_triangles
                                                                                   : b->n_triangles);
            if (worst <= SAMPLE_BUDGET || worst <= 1.05 * floor_samples)
                break;
            spacing *= fmax(1.1, sqrt(worst / SAMPLE_BUDGET));
        }
    }
    bvh ha, hb;
    int rc = bvh_build(&ha, a, nth);
    if (!rc)
        rc = bvh_build(&hb, b, nth);
    else
        memset(&hb, 0, sizeof hb);
    if (rc) {
        bvh_free(&ha);
        bvh_free(&hb);
        return vc_error_set(err, VC_ENOMEM, "Hausdorff distance: out of memory");
    }
    double sub_a = 0, sub_b = 0;
    out->a_to_b = one_sided(a, &hb, spacing, nth, &out->n_samples_a, &sub_a);
    out->b_to_a = one_sided(b, &ha, spacing, nth, &out->n_samples_b, &sub_b);
    bvh_free(&ha);
    bvh_free(&hb);
    if (out->a_to_b < 0 || out->b_to_a < 0)
        return vc_error_set(err, VC_ENOMEM, "Hausdorff distance: out of memory");
    out->distance = fmax(out->a_to_b, out->b_to_a);
    out->diagonal = diag;
    out->normalised = diag > 0 ? out->distance / diag : 0;
    out->spacing = spacing;
    /* the longest edge of any sampling sub-triangle, over sqrt(3) */
    out->error_bound = dmax(sub_a, sub_b) / sqrt(3.0);
    return VC_OK;
}
