/* Patch smoothing by adaptive, feature-aware Loop subdivision (thesis
 * 6.2.2, "Patch Smoothing": "we run 6 iterations of loop subdivision,
 * applying subdivision adaptively such that facets with all associated
 * dihedral angles larger than 175 degrees are not subdivided").
 *
 * The sharp features found by vc_features_detect are kept:
 *  - sharp corners never move (their coordinates are copied bit for bit);
 *  - the sharp edges of a crease are split at their midpoints and the
 *    crease's vertices follow the 1D cubic B-spline rule
 *    v' = 3/4 v + 1/8 (a + b) over their two crease neighbours a, b, with
 *    the corners as fixed (interpolated) ends: every crease converges to
 *    the cubic B-spline of its input polyline (a straight crease stays on
 *    its segment), and its tangent becomes continuous, so the patches on
 *    both sides can become smooth up to it;
 *  - every other vertex and edge follows Loop's rules (edge point
 *    3/8 (a + b) + 1/8 (c + d), vertex point (1 - n beta) v + beta sum,
 *    beta = (5/8 - (3/8 + 1/4 cos(2 pi / n))^2) / n).
 *
 * Adaptivity and conformity (red-green refinement): in each round, a
 * triangle is refined ("red", split into 4) when one of its edges inside a
 * patch (not sharp) has a dihedral angle of at most flat_angle_deg; a
 * triangle with two or three edges split by red neighbours becomes red
 * too (repeated until stable), and a triangle with exactly one split edge
 * is bisected ("green", 2 triangles from the split edge's midpoint to the
 * opposite vertex). The result never has a T-junction. A piece of a green
 * cut that gets a split edge in a later round is refined red, not cut
 * again (repeated bisection would halve its angles each round); green
 * cuts are not merged back first, so the smallest triangle angle can
 * still drop (see the guard below for the other source). Only vertices of
 * red triangles move; the others keep their positions, so a surface with
 * nothing to refine is returned unchanged.
 *
 * Feature guard: after each round, vc_features_detect at f->sharp_angle
 * must find exactly the input corners (same vertex indices) and sharp
 * edges exactly along the refined creases. Smoothing can break that where
 * the features pin the surface (a corner that is one only because its fan
 * of triangles spans more than theta_sharp, a crease fading below theta,
 * a bend that ends at a fixed corner); there the triangles around the
 * vertices involved are frozen (kept as they are in this and all later
 * rounds; a refined neighbour with two split edges is then cut into 3) and
 * the round is redone, a ring wider each time (after 8 tries the round is
 * dropped and smoothing stops). A bend next to a frozen triangle does not
 * ask for refinement. So the smallest dihedral angle inside patches can
 * stay where it was next to such features (on fertility.off at 60
 * degrees: 120.5 before and after, while the length of patch edges bent
 * by more than 10 degrees drops from 16290 to 1224).
 *
 * Output layout: the first in->n_vertices vertices of out are the input's
 * vertices in their order (moved by the rules, corners unmoved); new
 * vertices follow. Every output triangle keeps the vertex order
 * (orientation) of the input triangle it comes from, so a closed,
 * manifold, consistently oriented input gives one too, with the same Euler
 * characteristic, and a feature detection at the same theta_sharp finds
 * the same corners (same indices) and creases (refined), see the guard.
 * The result is deterministic (no threads, no randomness). Rounds stop
 * early when nothing is refined. */
#ifndef VORO_CRUST_SMOOTHING_H
#define VORO_CRUST_SMOOTHING_H

#include "vorocrust/error.h"
#include "vorocrust/features.h"
#include "vorocrust/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The thesis' defaults. */
#define VC_SMOOTH_DEFAULT_ITERATIONS 6
#define VC_SMOOTH_DEFAULT_FLAT_ANGLE 175.0
/* Largest accepted iterations (each round can multiply the triangle count
 * by up to 4). */
#define VC_SMOOTH_MAX_ITERATIONS 12

/* Smooths the patches of in (features f = vc_features_detect(in, ...),
 * computed on in itself) by `iterations` rounds of adaptive Loop
 * subdivision; triangles whose non-sharp edges all have dihedral angles
 * larger than flat_angle_deg (degrees; the angle between the two
 * triangles, 180 for a flat pair) are not subdivided; 180 subdivides every
 * triangle that has an edge inside a patch (uniform Loop on the patches). out is allocated
 * (free with vc_surface_free); iterations 0 returns a copy of in.
 * in need not be closed: boundary and non-manifold edges are sharp edges
 * of f and are treated as crease edges.
 * Fails (out is then zeroed) with VC_EPARAM for iterations outside
 * 0..VC_SMOOTH_MAX_ITERATIONS, flat_angle_deg outside (0, 180], f NULL or
 * computed on another surface (vertex or triangle count); VC_EINPUT for a
 * triangle index out of range or repeating a vertex; VC_ENOMEM. */
int vc_surface_smooth(const vc_surface *in, const vc_features *f, int iterations,
                      double flat_angle_deg, vc_surface *out, vc_error *err);

/* Denoising within a bound (vorocrust/surface/denoise.c): `iterations`
 * pairs of Taubin's lambda|mu steps of the umbrella Laplacian (lambda 0.5,
 * mu -0.53: frequencies above about a ninth of the mesh's own decay, the
 * shape below stays, without shrinking), every vertex's move then cut to
 * max_move from its input position. Every vertex moves,
 * corners and creases too: the bound is what protects them. The
 * triangles, their order and groups are the input's, so a closed,
 * oriented input stays one with the same topology. A part thinner than
 * the moves keeps its thickness: a vertex moves at most a quarter of its
 * distance to the nearest triangle behind it that faces away (the other
 * side of a plate or rod). Where triangles would still cross, the moves
 * of their vertices are halved, then withdrawn: the result intersects
 * itself only where the input does.
 * The result does not depend on the thread count. out is allocated (free
 * with vc_surface_free); rep (may be NULL) gets the moves. Fails (out
 * zeroed) with VC_EPARAM (max_move negative or not finite, iterations
 * outside 0..VC_DENOISE_MAX_ITERATIONS), VC_EINPUT (a vertex index out
 * of range), VC_ENOMEM. */
#define VC_DENOISE_MAX_ITERATIONS 1000
typedef struct vc_denoise_report {
    double max_move;  /* largest distance of a vertex from its input position */
    double mean_move;
    int64_t n_held;   /* vertices that ended max_move away (held by the bound) */
    int64_t n_crossing; /* pairs of triangles that cut each other (0 unless in does) */
} vc_denoise_report;

int vc_surface_denoise(const vc_surface *in, double max_move, int iterations, int threads,
                       vc_surface *out, vc_denoise_report *rep, vc_error *err);

#ifdef __cplusplus
}
#endif
#endif
