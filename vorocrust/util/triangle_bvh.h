/* A bounding-volume hierarchy over a triangle surface's triangles, for
 * nearest-triangle distances: split at the median centroid along the
 * longest axis of the centroids (a balanced tree, no tuning; the same
 * tree for any thread count), float boxes rounded outward. The Hausdorff
 * check and the denoiser's thickness query use it. */
#ifndef VC_UTIL_TRIANGLE_BVH_H
#define VC_UTIL_TRIANGLE_BVH_H

#include <stdint.h>

typedef struct vc_tri_bvh_node {
    float lo[3], hi[3];   /* slightly padded box (float is enough for pruning) */
    int32_t left, right;  /* children, or -1; leaves hold order[first .. first + count) */
    int32_t first, count;
} vc_tri_bvh_node;

typedef struct vc_tri_bvh {
    const double *xyz;    /* the surface's vertices and triangles (borrowed) */
    const int64_t *tri;
    int64_t *order;       /* triangle ids, grouped by leaf */
    vc_tri_bvh_node *node;
    int32_t n_nodes;
} vc_tri_bvh;

/* Builds the tree over nt triangles (below 2^30); xyz and tri must outlive
 * it. Returns 0, or -1 when out of memory (nothing to free then). */
int vc_tri_bvh_build(vc_tri_bvh *h, const double *xyz, const int64_t *tri, int64_t nt, int threads);
void vc_tri_bvh_free(vc_tri_bvh *h);

/* The distance from p to the nearest triangle when it exceeds threshold;
 * otherwise some value <= threshold (the search stops at the first
 * triangle that close; threshold < 0: the exact distance). *hint is a
 * triangle to try first (or -1), updated to the nearest triangle found. */
double vc_tri_bvh_distance_above(const vc_tri_bvh *h, const double p[3], double threshold,
                                 int64_t *hint);

/* The distance from p to the nearest triangle t with keep(ctx, t, d2)
 * non-zero (d2: t's squared distance from p) among those within `within`
 * of it; INFINITY when there is none. */
double vc_tri_bvh_nearest_where(const vc_tri_bvh *h, const double p[3], double within,
                                int (*keep)(void *ctx, int64_t t, double d2), void *ctx);

#endif
