/* Functions shared between the quality sources, not public. */
#ifndef VC_QUALITY_INTERNAL_H
#define VC_QUALITY_INTERNAL_H

/* Squared distance from p to the triangle (a, b, c). */
double vc_point_triangle_dist2(const double p[3], const double a[3], const double b[3],
                               const double c[3]);

#endif
