/* Filtered orientation predicates for the surface checks (internal).
 *
 * orient3d and orient2d evaluate the usual determinants in floating point
 * and compare them with Shewchuk's a-priori error bounds (stage A of his
 * adaptive predicates: the bound covers the rounding of the differences,
 * products and sums). A determinant whose magnitude is within the bound
 * has an uncertain sign and is reported as 0: the points are taken as
 * coplanar (collinear) within rounding. The callers treat 0 as "touching",
 * so an uncertain case can only turn into a reported contact, never hide a
 * certain crossing.
 *
 * The bounds are relative, hence scale-free, as long as the products of
 * three coordinate differences neither overflow nor underflow: the caller
 * scales the coordinates by a power of two (exact) so that the model's
 * bounding-box diagonal is of order 1. */
#ifndef VC_SURFACE_PREDICATES_H
#define VC_SURFACE_PREDICATES_H

#include <math.h>

/* (3 + 16 eps) eps and (7 + 56 eps) eps, eps = 2^-53 (Shewchuk 1997). */
#define VC_CCW_ERRBOUND_A 3.3306690738754716e-16
#define VC_O3D_ERRBOUND_A 7.7715611723761027e-16

/* Sign of det[a - d; b - d; c - d]: +1, -1, or 0 when within rounding. */
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
    return det > bound ? 1 : det < -bound ? -1 : 0;
}

/* Sign of the orientation of (a, b, c) projected on the coordinate axes
 * i and j: +1 counter-clockwise, -1 clockwise, 0 collinear within rounding. */
static inline int vc_orient2d(const double *a, const double *b, const double *c, int i, int j)
{
    double detleft = (a[i] - c[i]) * (b[j] - c[j]);
    double detright = (a[j] - c[j]) * (b[i] - c[i]);
    double det = detleft - detright;
    double bound = VC_CCW_ERRBOUND_A * (fabs(detleft) + fabs(detright));
    return det > bound ? 1 : det < -bound ? -1 : 0;
}

#endif
