/* Small 3-vector helpers shared by the quality sources. */
#ifndef VC_QUALITY_VEC3_H
#define VC_QUALITY_VEC3_H

#include <math.h>

#define VC_PI 3.14159265358979323846
#define VC_DEG (180.0 / VC_PI)

/* Plain max / min (fmax and fmin are library calls without -ffast-math;
 * NaN handling is not needed where these are used). */
static inline double dmax(double a, double b)
{
    return a > b ? a : b;
}

static inline double dmin(double a, double b)
{
    return a < b ? a : b;
}

static inline void v3_sub(const double a[3], const double b[3], double out[3])
{
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

static inline double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void v3_cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double v3_norm(const double a[3])
{
    return sqrt(v3_dot(a, a));
}

static inline double v3_dist2(const double a[3], const double b[3])
{
    double d[3];
    v3_sub(a, b, d);
    return v3_dot(d, d);
}

/* The angle between u and v in radians, accurate near 0 and pi. */
static inline double v3_angle(const double u[3], const double v[3])
{
    double c[3];
    v3_cross(u, v, c);
    return atan2(v3_norm(c), v3_dot(u, v));
}

#endif
