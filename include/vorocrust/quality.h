/* Mesh quality measures: triangle quality and angles, the geometry of convex
 * polyhedral cells (volume, centroid, exact minimum enclosing ball, exact
 * maximum inscribed ball, fatness, shortest edge), tetrahedron dihedral
 * angles, the two-sided Hausdorff distance between triangle surfaces, and
 * summary statistics. Every result is deterministic: no libc rand, no
 * dependence on the number of OpenMP threads. */
#ifndef VORO_CRUST_QUALITY_H
#define VORO_CRUST_QUALITY_H

#include <stdint.h>
#include "vorocrust/error.h"
#include "vorocrust/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- triangles ------------------------------------------------------- */

/* Q = 6 S / (sqrt(3) h P), S the area, h the longest edge, P the half
 * perimeter (thesis 6.4.1, footnote 2): 1 for an equilateral triangle, 0
 * for a degenerate one (also returned when h = 0). */
double vc_triangle_quality(const double a[3], const double b[3], const double c[3]);

/* The three interior angles in degrees, at a, b and c (they sum to 180);
 * all three are 0 when two corners coincide. */
void vc_triangle_angles(const double a[3], const double b[3], const double c[3],
                        double deg[3]);

/* ---- convex cells ---------------------------------------------------- */

/* A convex polyhedral cell seen through point ids into a coordinate array
 * (which may be a whole mesh's). Face f is the id cycle
 * face_vertices[face_offsets[f] .. face_offsets[f + 1] - 1]; faces are
 * oriented consistently (all outward or all inward: inward cells are
 * detected by their negative signed volume). vertices lists the cell's
 * distinct point ids (for the enclosing ball; may be NULL, the ids of the
 * faces are then used, repeats included, which gives the same ball). */
typedef struct vc_cell {
    const double *points;        /* 3 per point */
    int64_t n_vertices;
    const int64_t *vertices;
    int64_t n_faces;
    const int64_t *face_offsets; /* n_faces + 1 entries */
    const int64_t *face_vertices;
} vc_cell;

typedef struct vc_ball {
    double center[3];
    double radius;
} vc_ball;

/* Signed volume (positive when the faces are outward) by the divergence
 * theorem over a fan of every face; centroid may be NULL. */
double vc_cell_volume(const vc_cell *cell, double centroid[3]);

/* The smallest ball enclosing n points (xyz: 3 per point; ids: the points
 * to use, or NULL for points 0..n-1): Welzl's algorithm in its
 * move-to-front form on a fixed pseudo-random order (vorocrust/random.h),
 * so the answer never varies between runs. Points within a relative 1e-12
 * of the sphere count as inside. Returns 0, VC_EPARAM for n < 1, VC_ENOMEM. */
int vc_min_enclosing_ball(int64_t n, const double *xyz, const int64_t *ids,
                          vc_ball *ball);

/* The largest ball inside the cell: the linear program
 *   maximise r subject to n_f . x + r <= d_f for every face f
 * (n_f the unit outward normal of face f, d_f its offset), solved exactly by
 * the simplex method on the dual (Bland's rule: deterministic, never
 * cycles). Faces of zero area are skipped. Returns 0, VC_EINPUT when
 * there are fewer than 4 faces of non-zero area or the planes leave room
 * for balls of any size (an open cell), VC_ENOMEM. The radius is
 * 0 for a flat cell. */
int vc_max_inscribed_ball(const vc_cell *cell, vc_ball *ball);

/* Every measure of one cell. */
typedef struct vc_cell_measures {
    double volume;          /* |signed volume| */
    double signed_volume;   /* negative when the faces are listed inward */
    double centroid[3];
    vc_ball enclosing;      /* minimum enclosing ball of the vertices */
    vc_ball inscribed;      /* maximum inscribed ball */
    double fatness;         /* enclosing.radius / inscribed.radius (INFINITY if flat) */
    double shortest_edge;   /* over the edges of the faces */
    double shortest_edge_rel; /* shortest_edge / enclosing.radius */
} vc_cell_measures;

/* Fills out for cell. Returns 0 or the error of vc_min_enclosing_ball /
 * vc_max_inscribed_ball. */
int vc_cell_measure(const vc_cell *cell, vc_cell_measures *out);

/* ---- tetrahedra ------------------------------------------------------ */

/* Makes cell describe the tetrahedron p[0..3] with its four faces outward
 * (either vertex order of the input is fine), using the caller's storage:
 * points gets the 12 coordinates, ids the 4 vertex ids, face_offsets and
 * face_vertices the faces. */
void vc_tetra_cell(const double p[4][3], double points[12], int64_t ids[4],
                   int64_t face_offsets[5], int64_t face_vertices[12], vc_cell *cell);

/* The six interior dihedral angles of a tetrahedron, in degrees, at the
 * edges 01, 02, 03, 12, 13, 23; min and max may be NULL. A degenerate
 * tetrahedron gives angles of 0 or 180. */
void vc_tetra_dihedral_angles(const double p[4][3], double deg[6], double *min,
                              double *max);

/* ---- Hausdorff distance ---------------------------------------------- */

typedef struct vc_hausdorff_result {
    double distance;      /* max(a_to_b, b_to_a), absolute */
    double a_to_b;        /* max over samples of A of the distance to B */
    double b_to_a;
    double normalised;    /* distance / (bounding-box diagonal of A) */
    double diagonal;      /* bounding-box diagonal of A */
    double spacing;       /* sample spacing used */
    double error_bound;   /* the true distance lies in [distance, distance + error_bound];
                           * at most spacing / sqrt(3) */
    int64_t n_samples_a, n_samples_b;
} vc_hausdorff_result;

/* Two-sided Hausdorff distance between the triangle surfaces a and b.
 * Each surface is sampled at its vertices and on a barycentric grid of
 * every triangle (n subdivisions per edge, n = ceil(longest edge /
 * spacing): edge points and interior points), and every sample's exact
 * distance to the other surface is found through a uniform grid of its
 * triangles. Since the distance to a surface is 1-Lipschitz, and every
 * point of a triangle is within (its longest edge / n) / sqrt(3) <=
 * spacing / sqrt(3) of a sample, the sampled distance is at most
 * error_bound = spacing / sqrt(3) below the true one (and never above it).
 * spacing <= 0 chooses one: 1e-3 of A's bounding-box diagonal, enlarged
 * so that neither surface gets more than about 1e6 samples (or 3 per
 * triangle when it has more than 3.3e5 triangles). Vertices that are not a
 * corner of any triangle are ignored. Runs with
 * OpenMP; the result does not depend on the thread count. Returns 0,
 * VC_EINPUT for an empty surface, VC_ENOMEM. */
int vc_hausdorff(const vc_surface *a, const vc_surface *b, double spacing,
                 vc_hausdorff_result *out, vc_error *err);
/* The same on `threads` threads (<= 0: OpenMP's default). */
int vc_hausdorff_threads(const vc_surface *a, const vc_surface *b, double spacing, int threads,
                         vc_hausdorff_result *out, vc_error *err);

/* Exact distance from p to the triangle (a, b, c) (degenerate triangles
 * included). */
double vc_point_triangle_distance(const double p[3], const double a[3],
                                  const double b[3], const double c[3]);

/* ---- statistics ------------------------------------------------------ */

typedef struct vc_stats {
    int64_t n;            /* values counted (NaN values are skipped) */
    double min, max, mean;
    double p1, p5, p50, p95, p99;
} vc_stats;

/* Summary of values[0..n-1]: percentiles by linear interpolation between
 * the closest ranks of the sorted values (numpy's default), the mean
 * summed in sorted order. With no value every field is NaN and n = 0.
 * Returns 0 or VC_ENOMEM. */
int vc_stats_compute(const double *values, int64_t n, vc_stats *out);

/* The q-th percentile (0..100) of sorted[0..n-1], as vc_stats_compute. */
double vc_percentile_sorted(const double *sorted, int64_t n, double q);

#ifdef __cplusplus
}
#endif
#endif
