/* Exact geometric predicates on double coordinates (issue 19's engine
 * builds on them): the sign of the orientation and insphere determinants,
 * as if evaluated in exact arithmetic, whatever the inputs.
 *
 * A floating-point evaluation with an a-priori error bound decides the
 * common case (the cost of the plain determinant); only when its sign is
 * uncertain is the determinant evaluated exactly, in floating-point
 * expansions (Shewchuk, "Adaptive precision floating-point arithmetic and
 * fast robust geometric predicates", 1997: a number as a sum of
 * non-overlapping doubles, sums and products formed without rounding).
 * Inputs must be finite and their products must not overflow or
 * underflow (coordinates within about 1e-60 to 1e60 of each other's scale
 * keep every product normal); a determinant that is exactly zero returns
 * 0, there is no symbolic perturbation here. The exact path allocates its
 * expansions: out of memory, a predicate returns VC_PREDICATE_NOMEM, which
 * the caller must treat as an error (the library never aborts). */

#define VC_PREDICATE_NOMEM 2
#ifndef VC_UTIL_EXACT_PREDICATES_H
#define VC_UTIL_EXACT_PREDICATES_H

/* Sign of det[a - d; b - d; c - d]: +1, -1 or 0 (coplanar). Positive when
 * d lies below the plane through a, b, c, those seen counter-clockwise from
 * above (the right-hand normal of a, b, c points away from d). */
int vc_orient3d_exact(const double a[3], const double b[3], const double c[3], const double d[3]);

/* Sign of the insphere determinant: for a, b, c, d with
 * vc_orient3d_exact(a, b, c, d) > 0, +1 when e lies inside the sphere
 * through them, -1 outside, 0 on it (its sign flips with the orientation
 * of a, b, c, d). */
int vc_insphere_exact(const double a[3], const double b[3], const double c[3], const double d[3],
                      const double e[3]);

/* How many calls have needed the exact evaluation (for benchmarks and
 * tests; a relaxed counter over all threads). */
long long vc_exact_predicate_fallbacks(void);

#endif
