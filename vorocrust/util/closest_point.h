/* Closest points on segments and triangles (exact up to rounding). */
#ifndef VC_UTIL_CLOSEST_POINT_H
#define VC_UTIL_CLOSEST_POINT_H

/* Squared distance from p to the segment [a, b]; the closest point in q
 * when q is not NULL. */
double vc_closest_on_segment(const double p[3], const double a[3], const double b[3], double q[3]);

/* Squared distance from p to the triangle (a, b, c); the closest point in
 * q when q is not NULL. Works for degenerate triangles too. */
double vc_closest_on_triangle(const double p[3], const double a[3], const double b[3],
                              const double c[3], double q[3]);

#endif
