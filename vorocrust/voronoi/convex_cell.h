/* A convex polyhedron cut down plane by plane: the Voronoi cell of one seed
 * while it is being built. Internal to the Voronoi engine.
 *
 * Coordinates are relative to the seed (for precision). Faces are vertex
 * cycles oriented outward (counter-clockwise seen from outside); each face
 * carries the id of the plane that made it (a neighbour seed index, or a
 * wall code of the clipping box). */
#ifndef VC_CONVEX_CELL_H
#define VC_CONVEX_CELL_H

#include <stdint.h>

/* A growable array: data, count in use is kept by the owner, capacity here. */
typedef struct vc_cell_buf {
    void *data;
    int cap;
} vc_cell_buf;

typedef struct vc_convex_cell {
    int nv, nf, nfv;
    double *v;           /* 3 * nv */
    int64_t *face_plane; /* nf */
    int *face_start;     /* nf + 1: face k is fv[face_start[k] .. face_start[k+1]-1] */
    int *fv;
    /* Storage behind the arrays above, and scratch reused by every cut. */
    vc_cell_buf b_v, b_face_plane, b_face_start, b_fv;
    vc_cell_buf b_dist, b_side, b_remap, b_on, b_cap_next;
    vc_cell_buf b_new_v, b_new_face_plane, b_new_face_start, b_new_fv;
    vc_cell_buf b_cut;
} vc_convex_cell;

void vc_convex_cell_init(vc_convex_cell *c);
void vc_convex_cell_free(vc_convex_cell *c);

/* Resets c to the box [lo, hi] (relative coordinates, lo < 0 < hi), with the
 * six faces carrying wall_id[k] for the walls xmin, xmax, ymin, ymax, zmin,
 * zmax. */
void vc_convex_cell_reset_box(vc_convex_cell *c, const double lo[3],
                              const double hi[3], const int64_t wall_id[6]);

/* Cuts c with the bisector of the seed (origin) and the point p: keeps
 * {x : x.p <= |p|^2 / 2}. Vertices within tol * |p| of the plane count as
 * on it, so a plane through existing vertices creates no sliver face.
 * Returns 1 if the cell changed, 0 if the plane misses it, -1 on a
 * numerical failure (the cut face could not be closed), -2 if nothing of
 * the cell would remain. */
int vc_convex_cell_cut(vc_convex_cell *c, const double p[3], int64_t plane_id,
                       double tol);

/* Largest squared distance of a vertex from the seed. */
double vc_convex_cell_max_radius2(const vc_convex_cell *c);

#endif
