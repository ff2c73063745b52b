/* Triplets of pairwise overlapping balls and the two points where their
 * spheres meet (thesis 6.2.7): the candidate seeds, and the half-covered
 * pairs that sliver elimination removes. */
#ifndef VC_BALLS_TRIPLETS_H
#define VC_BALLS_TRIPLETS_H

#include <stdint.h>
#include "balls/ball_set.h"

/* The two points where the spheres of balls a, b, c meet; returns 0 when
 * they do not meet in two distinct points (or the centres are collinear).
 * up is on the side of (cb - ca) x (cc - ca). */
int vc_sphere_triple_points(const double *ca, double ra, const double *cb, double rb,
                            const double *cc, double rc, double up[3], double down[3]);

/* Is p strictly inside ball i (with a relative margin, so that a point
 * placed on a sphere by vc_sphere_triple_points is not inside)? */
int vc_ball_strictly_contains(const vc_balls *b, int64_t i, const double p[3]);

/* One triplet (i < j < k) with its points and which of them a fourth ball
 * covers; cover_up / cover_down is the covering ball that needs the least
 * shrinking (-1 when uncovered). clear_up / clear_down: for an uncovered
 * point, how far it is outside the nearest fourth sphere, as d^2 / r^2 - 1
 * (about twice the distance over the radius; INFINITY when no fourth ball
 * is near): a point nearly on a fourth sphere makes a short Voronoi edge. */
typedef struct vc_triplet {
    int64_t i, j, k;
    double up[3], down[3];
    int64_t cover_up, cover_down;
    double clear_up, clear_down;
    int64_t clear_ball_up, clear_ball_down; /* the nearest fourth sphere's ball, or -1 */
} vc_triplet;

/* Calls fn(ctx, &t) for the triplets of pairwise overlapping balls whose
 * spheres meet in two points, in increasing (i, j, k) order, that may
 * have changed since the last call:
 * those of every ball that was added, resized or moved (changed_reach) or
 * that reaches such a ball, computed on threads threads (<= 0: OpenMP's
 * default) and handed to fn in the same order for any thread count. Marks
 * the set unchanged. With most balls changed, every triplet. A triplet is
 * handed over when its smallest ball i is scanned; scanned (n bytes, or
 * NULL) gets 1 for the balls scanned: every triplet of theirs whose
 * smallest ball they are was handed over, the others are as before. */
int vc_triplets_scan_changed(vc_ball_set *bs, int threads,
                             void (*fn)(void *ctx, const vc_triplet *t), void *ctx,
                             unsigned char *scanned);

/* Every triplet, on threads threads, in increasing (i, j, k) order; marks
 * the set unchanged. Returns 0, or -1 when out of memory. */
int vc_triplets_scan_all(vc_ball_set *bs, int threads,
                         void (*fn)(void *ctx, const vc_triplet *t), void *ctx);

#endif
