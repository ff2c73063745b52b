/* A convex polyhedron cut down plane by plane: the Voronoi cell of one seed
 * while it is being built. Internal to the Voronoi engine.
 *
 * The cell is held in dual form: a list of planes, and one triangle of
 * three plane indices per polyhedron vertex (the three faces meeting
 * there). The triangles form a closed, consistently oriented triangulation
 * of the sphere, so a cut only removes the triangles whose vertex lies
 * outside the new plane and fans the boundary of the removed disk to the
 * new plane: the work is proportional to what changes, not to the cell.
 * A vertex where more than three faces meet (co-spherical seeds) is held
 * as several triangles at one point; the stitching step merges them.
 *
 * Coordinates are relative to the seed (for precision). */
#ifndef VC_CONVEX_CELL_H
#define VC_CONVEX_CELL_H

#include <stdint.h>

#include "power_side.h"

/* A growable array: data, capacity in elements. */
typedef struct vc_cell_buf {
    void *data;
    int cap;
} vc_cell_buf;

/* Planes a cell may hold while edge_owner is kept (below). */
#define VC_EDGE_OWNER_PLANES 64

typedef struct vc_convex_cell {
    /* Planes {x : n.x <= d} as (n, d), and the id each carries (a
     * neighbour seed index, or a wall code of the clipping box). */
    int np;
    double *plane;       /* 4 * np */
    int64_t *plane_id;   /* np */
    /* Triangles: plane indices (counter-clockwise seen from outside, that
     * is det(n_a, n_b, n_c) > 0) and the vertex point. */
    int nt;
    int *tri;            /* 3 * nt */
    double *px, *py, *pz; /* nt each: the vertex points, by coordinate */
    double *r2;          /* nt: squared distance of each vertex */
    /* nt: a bound on the distance from each vertex point to the exact
     * vertex (the meeting point of its three exact planes: bisectors of
     * the input seeds, walls of the box), from the rounding of the planes
     * and of the solve; and that bound plus 8 ulp of |x|, which the side
     * test's filter uses. */
    double *ev, *eb;
    /* nt * VC_POWER_CACHE: each vertex's part of the side test, prepared
     * the first time the filter cannot decide it (entry 13: prepared). */
    double *pc;
    /* np * VC_POWER_ROW: each plane's row of the side test as a tested
     * plane (vc_power_plane_prepare), kept from the cut that added it or
     * made the first time a vertex on it is prepared; prow_ok[i] says
     * whether row i is there. A vertex's rows then cost no arithmetic. */
    double *prow;
    unsigned char *prow_ok;
    double rmax2;        /* largest (|x| + 2 ev)^2 over the vertices: no
                            seed farther than 2 sqrt(rmax2) can cut */
    /* The seed of the cell and the seeds and box behind its planes: where
     * the filter cannot decide a side, the exact test (power_side.h). */
    const vc_power_ctx *ctx;
    int64_t seed;
    int64_t n_exact;     /* exact side tests made (statistics) */
    /* While every plane index is below VC_EDGE_OWNER_PLANES: per directed
     * plane pair (a, b), the triangle holding the edge a -> b, at
     * edge_owner[a * VC_EDGE_OWNER_PLANES + b] (entries of edges no
     * triangle holds are stale). A cut then finds the triangles across
     * the removed region's boundary without a pass over all triangles. */
    uint16_t *edge_owner;
    int edge_owner_ok;

    /* Face form, filled by vc_convex_cell_faces: vertex i is triangle i (its point is
     * px[i], py[i], pz[i]);
     * face k is fv[face_start[k] .. face_start[k+1]-1], counter-clockwise
     * seen from outside, made by plane face_plane[k], which is
     * plane[face_plane_index[k]]. */
    int nv, nf, nfv;
    int64_t *face_plane;
    int *face_plane_index;
    int *face_start;
    int *fv;

    /* Storage and scratch reused by every cut. */
    vc_cell_buf b_plane, b_plane_id, b_tri, b_px, b_py, b_pz, b_r2, b_ev, b_eb, b_out, b_pc;
    vc_cell_buf b_prow, b_prow_ok;
    vc_cell_buf b_dist, b_conflict, b_next, b_edge_tri, b_edge_out, b_new_pt, b_new_tri;
    vc_cell_buf b_edge_mark; /* np * np bytes, all zero between cuts */
    vc_cell_buf b_edge_owner;
    vc_cell_buf b_face_plane, b_face_plane_index, b_face_start, b_fv, b_entry, b_count;
} vc_convex_cell;

/* What the functions below return when a scratch buffer cannot grow. */
#define VC_CELL_NOMEM (-3)

void vc_convex_cell_init(vc_convex_cell *c);
void vc_convex_cell_free(vc_convex_cell *c);

/* Resets c to the box [lo, hi] (relative coordinates, lo < 0 < hi: the
 * walls of ctx's box less the seed's position, rounded), with the six faces
 * carrying wall_id[k] for the walls xmin, xmax, ymin, ymax, zmin, zmax
 * (VC_WALL_XMIN - k). c->ctx and c->seed must be set. Returns 0, or
 * VC_CELL_NOMEM. */
int vc_convex_cell_reset_box(vc_convex_cell *c, const double lo[3],
                             const double hi[3], const int64_t wall_id[6]);

/* Cuts c with the bisector of the seed and seed plane_id, at p relative to
 * the seed (its coordinates less the seed's, rounded): keeps the vertices
 * nearer the seed. Which vertices go is decided exactly, with ties broken
 * by the engine's symbolic perturbation (power_side.h): a floating-point
 * filter with a rigorous error bound decides the clear cases, the exact
 * test the others, and new vertices are computed from their three planes.
 * Returns 1 if the cell changed, 0 if the plane misses it, -1 if the
 * removed part is not a disk (a defect), -2 if nothing of the cell would
 * remain, VC_CELL_NOMEM out of memory (also from the exact test). */
int vc_convex_cell_cut(vc_convex_cell *c, const double p[3], int64_t plane_id);

/* The point where three planes (n, d) meet, {x : n.x = d}, by Cramer's
 * rule, into y; returns a bound on its distance to where the exact planes
 * meet, those of which q are rounded copies: a bisector of the origin and
 * a seed at n (wall[i] = 0; n rounded within U |n| per component, d
 * within 4 U |n|^2) or a wall (wall[i] = 1: n exact, d within U |d|). The
 * bound is first order in U, taken four times; +inf when the rounded
 * determinant is 0. The determinant of the normals goes to *det, and |y|
 * to *norm_y, when they are not NULL. */
double vc_solve_planes(const double *const q[3], const int wall[3], double y[3], double *det, double *norm_y);

/* Fills the face form (nv, nf, nfv, face_plane, face_start, fv) from
 * the current cell. Returns 0, -1 if a face cycle is inconsistent, or
 * VC_CELL_NOMEM. */
int vc_convex_cell_faces(vc_convex_cell *c);

#endif
