/* vc-tetgen's C view of TetGen (tetgen_adapter.cpp). TetGen is AGPL: only
 * the vc-tetgen executable links it, never the vorocrust library. */
#ifndef VC_TETGEN_ADAPTER_H
#define VC_TETGEN_ADAPTER_H

#include <stddef.h>
#include <stdint.h>

#include "vorocrust/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A tetrahedral mesh: tetrahedron t has the corners tets[4t .. 4t+3]
 * (0-based point ids), ordered so that (p1-p0) x (p2-p0) . (p3-p0) > 0,
 * VTK's positive orientation. */
typedef struct vc_tetgen_mesh {
    int64_t n_points;
    double *points; /* 3 * n_points */
    int64_t n_tets;
    int64_t *tets;  /* 4 * n_tets */
} vc_tetgen_mesh;

/* Tetrahedralizes the volume the closed surface s encloses with TetGen
 * (the surface is its piecewise linear complex, one facet per triangle)
 * under the command-line switches given (e.g. "pq1.414a0.01Q"), with
 * n_holes points (3 each; may be NULL when 0) inside cavities: TetGen
 * removes the tetrahedra of the region around each, as it removes those
 * outside. Returns 0, or non-zero with one line in msg (TetGen's failure: a
 * self-intersecting surface, an out-of-memory, ...). out is zeroed on
 * failure. */
int vc_tetgen_tetrahedralize(const vc_surface *s, const char *switches, const double *holes,
                             int64_t n_holes, vc_tetgen_mesh *out, char *msg, size_t msg_len);

/* The number of triangles of s that intersect another one (TetGen's -d
 * check) into n_triangles. TetGen 1.5.0 crashes when it stops on a
 * self-intersecting surface while meshing (it frees its memory twice on
 * the way out), so vc-tetgen asks this first. Returns 0, or non-zero with
 * one line in msg. */
int vc_tetgen_self_intersections(const vc_surface *s, int64_t *n_triangles, char *msg,
                                 size_t msg_len);

/* Frees the arrays of m and zeroes it; safe on a zeroed mesh. */
void vc_tetgen_mesh_free(vc_tetgen_mesh *m);

#ifdef __cplusplus
}
#endif
#endif
