/* Self-intersections of a triangle surface (internal to the surface
 * module; vc_surface_check_solid reports them). */
#ifndef VC_SURFACE_SELF_INTERSECTION_H
#define VC_SURFACE_SELF_INTERSECTION_H

#include <stdint.h>

/* Counts the pairs of triangles that intersect where a surface must not
 * cut itself:
 *   - no shared vertex: the closed triangles meet (cross or touch);
 *   - one shared vertex: they meet anywhere else than at that vertex;
 *   - a shared edge: they are coplanar and lie on the same side of the
 *     edge (folded onto each other).
 * Pairs with the same three vertices (repeated triangles) are not counted
 * here. Triangles with skip[t] != 0 (zero-area ones; skip may be NULL) are
 * left out. xyz should be scaled so that the bounding-box diagonal is of
 * order 1 (see predicates.h).
 *
 * A bounding-volume hierarchy over the triangles' boxes (Morton order,
 * balanced) gives the candidate pairs; each candidate is decided with the
 * exact orientation predicates of predicates.h. O(n log n + k) for k
 * candidate pairs; parallel over triangles with OpenMP, the result does not
 * depend on the thread count.
 *
 * *count receives the number of pairs, first[0] < first[1] the first pair
 * (smallest first[0], then first[1]; 0-based) or -1, -1. Returns 0, or -1
 * when out of memory. */
int vc_self_intersections(const double *xyz, const int64_t *tri, int64_t nt, const unsigned char *skip,
                          int64_t *count, int64_t first[2]);

/* The same pairs, listed: *pairs receives 2 * *count triangle indices
 * (lo < hi; sorted by lo, then hi; NULL when there are none; free() it).
 * Returns 0, or -1 when out of memory. */
int vc_self_intersection_pairs(const double *xyz, const int64_t *tri, int64_t nt, int64_t **pairs,
                               int64_t *count);

#endif
