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
 * radius sz. The radius bound is evaluated at the centroid of every
 * triangle and the midpoint of every sharp edge, or of every k-th of them
 * (in file order, weighted by area and length) on surfaces with more than
 * 16,384 (threads threads; the result does not depend on their number;
 * r_min is that of the evaluated ones); a patch takes 0.93 / r^2
 * balls per unit area and a crease 0.86 / r per unit length (maximal
 * Poisson-disk densities in 2D and 1D at the spacing (1 - alpha) r of
 * deep coverage, alpha = 1 - sqrt(3) / 2). The Lipschitz condition and
 * sliver elimination add balls, and one sample per triangle misjudges
 * large triangles next to features: an estimate within a factor of three
 * (icosphere 456 for 783 balls, torus.obj 2,580 for 6,390, bracket.obj
 * 15,600 for 6,596), meant to refuse absurd work, not to plan memory. Returns 0, or -1 when out of memory. */
int vc_ball_estimate_compute(const vc_sizing *z, double sz, int threads, vc_ball_estimate *out);

#endif
