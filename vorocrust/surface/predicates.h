/* Orientation predicates for the surface checks (internal), exact.
 *
 * orient3d and orient2d evaluate the usual determinants in floating point
 * and compare them with Shewchuk's a-priori error bounds (stage A of his
 * adaptive predicates); only when the sign is uncertain is the
 * determinant evaluated exactly (vc_orient3d_exact, in expansions). 0
 * means exactly coplanar (collinear): the callers treat it as touching.
 * Until session 36 an uncertain sign was reported as 0, which made two
 * disjoint, nearly coplanar triangles "touch": a rotated plate with
 * parallel faces 0.3% of its size apart, a rotated and decimated bracket,
 * a stretched and rotated cup, all free of intersections in exact
 * arithmetic, were refused as self-intersecting (5 of 43 random surfaces).
 * Out of memory in the exact path, a sign is reported as 0 (touching), as
 * before: an unknown case is reported, a crossing never hidden.
 *
 * The bounds are relative, hence scale-free, as long as the products of
 * three coordinate differences neither overflow nor underflow: the caller
 * scales the coordinates by a power of two (exact) so that the model's
 * bounding-box diagonal is of order 1. */
#ifndef VC_SURFACE_PREDICATES_H
#define VC_SURFACE_PREDICATES_H

#include <math.h>

#include "util/exact_predicates.h"

/* (3 + 16 eps) eps and (7 + 56 eps) eps, eps = 2^-53 (Shewchuk 1997). */
#define VC_CCW_ERRBOUND_A 3.3306690738754716e-16
#define VC_O3D_ERRBOUND_A 7.7715611723761027e-16

/* Sign of det[a - d; b - d; c - d]: +1, -1, or 0 (coplanar). */
static inline int vc_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    double cdxady = cdx * ady, adxcdy = adx * cdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    double perm = (fabs(bdxcdy) + fabs(cdxbdy)) * fabs(adz) + (fabs(cdxady) + fabs(adxcdy)) * fabs(bdz) +
                  (fabs(adxbdy) + fabs(bdxady)) * fabs(cdz);
    double bound = VC_O3D_ERRBOUND_A * perm;
    if (det > bound)
        return 1;
    if (det < -bound)
        return -1;
    if (perm == 0)
        return 0; /* every product is zero: so is the determinant */
    const int s = vc_orient3d_exact(a, b, c, d);
    return s == VC_PREDICATE_NOMEM ? 0 : s;
}

/* Sign of the orientation of (a, b, c) projected on the coordinate axes
 * i and j: +1 counter-clockwise, -1 clockwise, 0 collinear. */
static inline int vc_orient2d(const double *a, const double *b, const double *c, int i, int j)
{
    double detleft = (a[i] - c[i]) * (b[j] - c[j]);
    double detright = (a[j] - c[j]) * (b[i] - c[i]);
    double det = detleft - detright;
    double bound = VC_CCW_ERRBOUND_A * (fabs(detleft) + fabs(detright));
    if (det > bound)
        return 1;
    if (det < -bound)
        return -1;
    if (detleft == 0 && detright == 0)
        return 0;
    /* exactly: lifted to 3D, det[A - D; B - D; C - D] with A = (a_i, a_j, 0),
     * B, C alike and D = (c_i, c_j, 1) is minus the 2D determinant */
    const double A[3] = {a[i], a[j], 0}, B[3] = {b[i], b[j], 0}, C[3] = {c[i], c[j], 0},
                 D[3] = {c[i], c[j], 1};
    const int s = vc_orient3d_exact(A, B, C, D);
    return s == VC_PREDICATE_NOMEM ? 0 : -s;
}

#endif
