/* Functions shared between the quality sources, not public. */
#ifndef VC_QUALITY_INTERNAL_H
#define VC_QUALITY_INTERNAL_H

#include "vorocrust/quality.h"

/* Squared distance from p to the triangle (a, b, c). */
double vc_point_triangle_dist2(const double p[3], const double a[3], const double b[3],
                               const double c[3]);

/* vc_max_inscribed_ball for a cell whose faces are outward (orient = 1)
 * or inward (orient = -1), already known from its signed volume. */
int vc_max_inscribed_ball_oriented(const vc_cell *cell, double orient, vc_ball *ball);

#endif
