/* Functions shared between the quality sources, not public. */
#ifndef VC_QUALITY_INTERNAL_H
#define VC_QUALITY_INTERNAL_H

#include <stdint.h>
#include "vorocrust/quality.h"
#include "vorocrust/vtu_reader.h"

/* Squared distance from p to the triangle (a, b, c). */
double vc_point_triangle_dist2(const double p[3], const double a[3], const double b[3],
                               const double c[3]);

/* vc_max_inscribed_ball for a cell whose faces are outward (orient = 1)
 * or inward (orient = -1), already known from its signed volume. */
int vc_max_inscribed_ball_oriented(const vc_cell *cell, double orient, vc_ball *ball);

/* mesh_faces.c: sets uses[f] (n_faces entries) to the number of faces of
 * m, f included, with the same vertex set, and when twin is not NULL,
 * twin[f] to the other copy of a face of exactly two cells (else -1);
 * returns the number of distinct faces, or -1 when out of memory. */
int64_t vc_mesh_face_uses(const vc_vtu_mesh *m, int64_t *uses, int64_t *twin);

/* mesh_faces.c: the faces f with uses[f] == 1 (the boundary) as a triangle
 * surface on m's points, polygons fanned from their vertex average (added
 * as points). Returns 0, or -1 when out of memory (s may then hold arrays:
 * free it with vc_surface_free). */
int vc_mesh_boundary_surface(const vc_vtu_mesh *m, const int64_t *uses, vc_surface *s);

#endif
