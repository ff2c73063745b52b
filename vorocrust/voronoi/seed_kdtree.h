/* A k-d tree over the seeds for k-nearest-neighbour queries: the cell of a
 * seed is cut by its neighbours nearest first, however unevenly the seeds
 * are spread (VoroCrust puts pairs of seeds a sliver apart on the surface
 * and graded seeds inside: a uniform grid's bins near the surface held
 * seventy seeds each, and every cell there read two thousand candidates).
 * Internal to the Voronoi engine. */
#ifndef VC_SEED_KDTREE_H
#define VC_SEED_KDTREE_H

#include <stdint.h>

typedef struct vc_kd_node {
    double lo[3], hi[3];   /* bounding box of its points */
    int64_t begin, end;    /* its points: xyz[3 * begin .. 3 * end) */
    int64_t left, right;   /* children, -1 for a leaf */
} vc_kd_node;

typedef struct vc_seed_kdtree {
    int64_t n;
    double *xyz;    /* the points, in tree order */
    int64_t *index; /* their seed indices */
    vc_kd_node *node;
    int64_t n_nodes;
} vc_seed_kdtree;

/* Builds the tree over n points (3 * n coordinates). Deterministic.
 * Returns 0, or -1 when out of memory. */
int vc_seed_kdtree_build(vc_seed_kdtree *t, const double *xyz, int64_t n);
void vc_seed_kdtree_free(vc_seed_kdtree *t);

/* Moves the points to xyz (3 per seed index, the same seeds), keeping the
 * tree's shape: O(n), the boxes recomputed. Queries stay exact; they slow
 * down only when points move far. */
void vc_seed_kdtree_refit(vc_seed_kdtree *t, const double *xyz);

/* A neighbour found: squared distance, seed index. */
typedef struct vc_kd_hit {
    double d2;
    int64_t seed;
} vc_kd_hit;

/* The k seeds nearest x other than seed `skip`, in increasing (d2, seed)
 * order, into hit (room for k); returns how many (fewer when the tree has
 * fewer). The order is total, so the first k of a query for 2k are the
 * answer for k. */
int vc_seed_kdtree_knn(const vc_seed_kdtree *t, const double x[3], int k, int64_t skip,
                       vc_kd_hit *hit);

/* The same among the seeds within squared distance bound2 of x: the same
 * answer when at least k seeds other than skip lie that near (a bound
 * known from a query nearby: its k-th distance plus the distance between
 * the two places), found faster, since nodes beyond it are never read;
 * fewer than k otherwise. */
int vc_seed_kdtree_knn_within(const vc_seed_kdtree *t, const double x[3], int k, int64_t skip,
                              double bound2, vc_kd_hit *hit);

/* A caller's last k-nearest query (one per thread): its place and its k-th
 * distance. Queries made one after the other at nearby places (cells built
 * in a spatial order) bound each other: the last one's k seeds lie within
 * its k-th distance plus the step between the places. */
typedef struct vc_kd_hint {
    int valid, k;
    double x[3], kth;
} vc_kd_hint;

/* vc_seed_kdtree_knn, bounded by the hint when it has one of the same k
 * (and asked again without the bound when that found fewer than k: the
 * answer is always the unbounded one); the hint then becomes this query. */
int vc_seed_kdtree_knn_hinted(const vc_seed_kdtree *t, vc_kd_hint *hint, const double x[3], int k,
                              int64_t skip, vc_kd_hit *hit);

/* The seeds other than `skip` within squared distance r2 of x that come
 * after `after` in (d2, seed) order (what a k-nearest query returned
 * last): the first cap of them in that order, into hit, sorted; returns
 * how many, with *truncated = 1 when there were more (ask again after the
 * last). One range query instead of asking for ever more neighbours: a
 * cell whose reach is known after its nearest neighbours reads each
 * further candidate once. When reach is not NULL, a node whose box it
 * rejects (reach(ctx, lo, hi) == 0: no point of the box can matter) is
 * skipped, and so is a point it rejects (lo = hi = the point). */
int vc_seed_kdtree_within(const vc_seed_kdtree *t, const double x[3], double r2, vc_kd_hit after,
                          int64_t skip, int (*reach)(void *ctx, const double lo[3], const double hi[3]),
                          void *ctx, vc_kd_hit *hit, int cap, int *truncated);

#endif
