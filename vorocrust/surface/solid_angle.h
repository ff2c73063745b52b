/* The signed solid angle of a triangle (internal to the surface module):
 * the generalized winding number of a closed surface about p is the sum
 * over its triangles divided by 4 pi. */
#ifndef VC_SURFACE_SOLID_ANGLE_H
#define VC_SURFACE_SOLID_ANGLE_H

#include <math.h>

/* The solid angle of triangle (a, b, c) seen from p (Van Oosterom and
 * Strackee), signed by the triangle's orientation. */
static inline double vc_solid_angle(const double *p, const double *a, const double *b, const double *c)
{
    const double x[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]};
    const double y[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
    const double z[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]};
    const double lx = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double ly = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    const double lz = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    const double num = x[0] * (y[1] * z[2] - y[2] * z[1]) - x[1] * (y[0] * z[2] - y[2] * z[0]) +
                       x[2] * (y[0] * z[1] - y[1] * z[0]);
    const double den = lx * ly * lz + (x[0] * y[0] + x[1] * y[1] + x[2] * y[2]) * lz +
                       (x[0] * z[0] + x[1] * z[1] + x[2] * z[2]) * ly + (y[0] * z[0] + y[1] * z[1] + y[2] * z[2]) * lx;
    return 2 * atan2(num, den);
}

#endif
