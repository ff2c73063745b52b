/* How many balls the sampling will make, predicted from the sizing before
 * any is placed (Sheehy's output-size bound: the number of points of a
 * well-spaced sample is the integral of 1/h^2 over the surface, h the
 * sizing). Internal to vorocrust/balls. */
#ifndef VC_BALLS_BALL_ESTIMATE_H
#define VC_BALLS_BALL_ESTIMATE_H

#include <stdint.h>

#include "sizing/sizing.h"

typedef struct vc_ball_estimate {
    double n_balls;      /* predicted balls: corners + creases + patches */
    double r_min;        /* the smallest radius bound met */
    double r_min_at[3];  /* where */
} vc_ball_estimate;

/* Predicts the ball count of a sampling with the sizing z and largest
 * radius sz. The radius bound is evaluated at the corners, at the
 * midpoint of every sharp edge and at the centroid of every triangle, or
 * of every k-th of them (in file order, weighted by area and length) on
 * surfaces with more than 4,096 (threads threads; the result does not
 * depend on their number; r_min is that of the evaluated points). A
 * triangle larger than twice its centroid's bound is integrated over its
 * quarters, recursively, the heaviest pieces first within one budget of
 * bound evaluations for all (a coarse facet's bound falls towards its
 * folds, a large face's towards a small feature along it).
 * A patch takes 0.93 / r^2 balls per unit area outside the corner and
 * crease balls, a crease 0.86 / r per unit length outside the corner
 * balls (maximal Poisson-disk densities in 2D and 1D at the spacing
 * (1 - alpha) r of deep coverage, alpha = 1 - sqrt(3) / 2), times 1.8 for
 * what the Lipschitz condition and sliver elimination add. Measured: 0.63
 * to 1.7 times the balls made on 18 shared and generated surfaces (a
 * sphere decimated to 144 triangles 1.3e3 * 1.8 for 2,960; fandisk.off
 * 1.6e3 * 1.8 for 3,399); meant to refuse absurd work and size the
 * progress lines, not to plan memory. Returns 0, or -1 when out of
 * memory. */
int vc_ball_estimate_compute(const vc_sizing *z, double sz, int threads, vc_ball_estimate *out);

#endif
