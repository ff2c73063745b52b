/* Is a segment or a triangle inside a union of balls?
 *
 * Maximal Poisson-disk sampling drops a piece of the surface once the
 * balls cover it. Tested ball by ball, a piece is dropped only when one
 * ball holds all of it, so the pieces along every seam between two balls
 * are split until they fit in the lens where the balls overlap: about as
 * many tests per round as the round before, for as many rounds as it
 * takes the pieces to shrink from a triangle to the lens's width. The
 * union is tested directly instead, through the power diagram of the
 * balls: a point x is in the union exactly when the ball of least power
 * at x (|x - c_i|^2 - r_i^2) holds it, so the piece is covered exactly
 * when, for every ball i, the part of the piece in i's power cell lies in
 * ball i. Each part is convex (the piece clipped by half-spaces), and a
 * convex polygon lies in a ball when its corners do. */
#ifndef VC_BALLS_UNION_COVER_H
#define VC_BALLS_UNION_COVER_H

/* The most balls one test takes (more: the caller splits the piece). */
#define VC_UNION_COVER_MAX 32

/* v: nv corners (2: a segment, 3: a triangle); the k balls' centres c
 * (3 k) and radii r. Returns 1 when every point of the piece lies in some
 * ball, 0 otherwise. The radii are taken 1e-9 smaller (relative) than
 * given, so that rounding in the clipping never calls a gap of that size
 * covered; k must be at most VC_UNION_COVER_MAX. */
int vc_union_covers(const double *v, int nv, const double *c, const double *r, int k);

#endif
