/* A k-d tree over the surface balls for the two questions the interior
 * seeds ask at a point x: the sizing r(x) = min over balls of
 * (r_p + L |x - p|) (the L-Lipschitz extension of the radii into the
 * volume, growing faster far from the balls: vc_ball_tree_exceeds), and
 * whether x lies inside some ball. Each node keeps the
 * bounding box of its centres and the smallest and largest radius below
 * it, so both queries prune whole subtrees by a lower bound:
 * r_p + L |x - p| >= rmin + L dist(x, box) and |x - p| >= dist(x, box).
 * Internal to vorocrust/interior. */
#ifndef VC_INTERIOR_BALL_TREE_H
#define VC_INTERIOR_BALL_TREE_H

#include <stdint.h>

#include "vorocrust/sampling.h"

typedef struct vc_ball_tree_node {
    double lo[3], hi[3];     /* bounding box of the centres */
    double rmin, rmax;
    int64_t first, count;    /* the node's balls: order[first .. first + count - 1] */
    int64_t child;           /* first of the two children, -1 for a leaf */
} vc_ball_tree_node;

typedef struct vc_ball_tree {
    const vc_balls *balls;
    int64_t *order;          /* ball indices, grouped by node */
    vc_ball_tree_node *nodes;
    int64_t n_nodes;
} vc_ball_tree;

/* Builds the tree (the balls must outlive it); 0, or -1 when out of memory. */
int vc_ball_tree_build(vc_ball_tree *t, const vc_balls *balls);
void vc_ball_tree_free(vc_ball_tree *t);

/* How the sizing grows away from the balls: at rate lipschitz within
 * far_from radii of a ball's centre, at rate far_lipschitz (>= lipschitz)
 * beyond. */
typedef struct vc_ball_grading {
    double lipschitz, far_from, far_lipschitz;
} vc_ball_grading;

/* The sizing at x is min(cap, min over balls of r_p + g_p(|x - p|)), g_p(d)
 * = L d up to d = far_from r_p and L far_from r_p + far_lipschitz (d -
 * far_from r_p) beyond; cap may be INFINITY. Returns 1 when length >
 * factor times the sizing (factor > 0), stopping at the first ball that
 * shows it; a subtree is pruned by the least value its radius range can
 * give at its box's distance. The octree's refinement test. */
int vc_ball_tree_exceeds(const vc_ball_tree *t, const double x[3], const vc_ball_grading *g,
                         double cap, double length, double factor);

/* 1 when |x - p| <= r_p for some ball (on a sphere counts as inside). */
int vc_ball_tree_covers(const vc_ball_tree *t, const double x[3]);

/* 1 when |x - p| <= factor r_p for some ball (factor > 0); the second
 * leaves ball `skip` out. */
int vc_ball_tree_covers_scaled(const vc_ball_tree *t, const double x[3], double factor);
int vc_ball_tree_covers_scaled_except(const vc_ball_tree *t, const double x[3], double factor,
                                      int64_t skip);

/* 1 when some ball reaches within h of x: |x - p| <= r_p + h. */
int vc_ball_tree_reaches(const vc_ball_tree *t, const double x[3], double h);

#endif
