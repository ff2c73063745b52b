/* Lifting the ball centres off the input by the sag of the reconstructed
 * facets (docs/sampling-convergence.md, "The centre lift").
 *
 * The reconstructed surface is the triangulation of the ball centres by
 * the facets (triplets whose two seeds stay): chords, which lie inside the
 * input on its convex parts and outside on its concave parts, by about
 * 3/8 R^2 / rho on average (R the facet's circumradius, rho the radius of
 * curvature). That bias, not the error bound, makes the enclosed volume
 * too small by about 1% on smooth curved shapes. Each facet's mean signed
 * distance to the input is measured at its edge midpoints (the rule exact
 * for a quadratic surface over a triangle), and every surface ball's centre
 * is moved along the reconstructed surface's normal by the area-weighted
 * mean of its facets' distances: the reconstruction then has no bias to
 * first order. Corner and crease balls stay on their features.
 *
 * The move is a few percent of the radius and smooth from ball to ball,
 * but sliver elimination ends with margins that can be that small, so the
 * lifted balls are checked as the sampler checks its result: every triplet
 * scanned again, and accepted when no seed pair is half covered and the
 * facets are the same triplets (the same triangulation, moved), none with
 * a seed much nearer a fourth sphere than before (a short edge). Where the
 * check fails, the balls of each failing configuration (a near-quartet)
 * first move together, by the mean of their lifts (a translation keeps
 * what sliver elimination left among them); where that fails too, the
 * lift of the balls involved is halved, then removed with that of their
 * neighbours, and after MAX_ROUNDS all lifts are dropped:
 * the result is never worse than the unlifted sampling. Further passes
 * measure the lifted facets again and move by what remains (a thin tube's
 * second-order remainder), each checked against the sampled facets the
 * same way; a pass that does not hold leaves the last one's centres. */
#ifndef VC_BALLS_CENTRE_LIFT_H
#define VC_BALLS_CENTRE_LIFT_H

#include <stdint.h>
#include "sizing/sizing.h"
#include "vorocrust/log.h"
#include "vorocrust/sampling.h"

typedef struct vc_lift_result {
    int64_t n_lifted;      /* balls moved */
    int rounds;            /* checks run, over all passes (1 when the first lift held) */
    int passes;            /* passes accepted (0 when dropped) */
    int64_t n_reduced;     /* balls whose lift was reduced by a failed check */
    int dropped;           /* 1 when every lift was dropped */
    double mean_rel;       /* mean |lift| / radius over the moved balls */
    double max_rel;        /* largest |lift| / radius */
} vc_lift_result;

/* Moves the centres of b's surface balls as described above. facet_v holds
 * the facets, 3 ball indices each, as sliver elimination left them (no
 * half-covered pair); facet_clearance, when not NULL, each facet's
 * clearance (the smaller of its triplet's two, vc_triplet) from a scan of
 * every triplet of b as it is (the reference the checks compare with;
 * NULL: the lift scans for it); z is the sizing of the input (its
 * elements and normals). Same result for any thread count. A progress
 * line per check on log (VC_LOG_INFO) once the lift has run 2 s. Returns
 * 0, or -1 when out of memory (b unchanged). */
int vc_lift_centres(vc_balls *b, const int64_t *facet_v, const double *facet_clearance,
                    int64_t n_facets, const vc_sizing *z, int threads, const vc_logger *log,
                    vc_lift_result *res);

#endif
