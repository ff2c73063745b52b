/* The quality report of a whole mesh read from a .vtu file (polyhedra and
 * tetrahedra): every cell measured with the quality library, the boundary
 * (faces of exactly one cell) as a triangle surface, and optionally its
 * Hausdorff distance to the input surface. `vorocrust quality` prints it;
 * `vorocrust compare` computes it for two meshers' meshes of one input, so
 * both are measured the same way. */
#ifndef VORO_CRUST_MESH_REPORT_H
#define VORO_CRUST_MESH_REPORT_H

#include <stdint.h>
#include "vorocrust/error.h"
#include "vorocrust/quality.h"
#include "vorocrust/surface.h"
#include "vorocrust/vtu_reader.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vc_mesh_report {
    /* Counts. */
    int64_t n_cells;              /* cells measured (polyhedra and tetrahedra) */
    int64_t n_tetrahedra;
    int64_t n_points;             /* points in the file */
    int64_t n_faces;              /* distinct faces: same vertex set = same face */
    int64_t n_boundary_faces;     /* faces of exactly one cell */
    int64_t n_faces_shared_more;  /* faces of more than two cells (non-manifold) */
    /* Cells that could not be trusted; first_* is the cell's index in the
     * file, -1 when there is none. */
    int64_t n_open_cells;         /* an edge not walked once each way by its faces */
    int64_t first_open_cell;
    int64_t n_inverted_cells;     /* every face listed inward */
    int64_t n_unmeasured_cells;   /* no inscribed ball: left out of the statistics */
    int64_t first_unmeasured_cell;

    /* Cell measures (statistics over the measured cells). */
    double total_volume;
    vc_stats volume, fatness, shortest_edge_rel;
    double short_edge_share;      /* share of the measured cells whose shortest edge is
                                     below 1e-2 of their enclosing radius */
    vc_stats small_face_rel;      /* per cell: smallest face area / enclosing radius^2 */
    vc_stats dihedral_min, dihedral_max; /* tetrahedra only (n = 0 without any) */
    /* OpenFOAM checkMesh's measures of the faces between two cells, from
     * the cells' centroids (NaN without such faces): non-orthogonality in
     * degrees (max, and the mean as checkMesh prints it: the angle of the
     * mean cosine), skewness (max, and the faces above checkMesh's 4). */
    double non_orthogonality_max, non_orthogonality_mean, skewness_max;
    int64_t n_skew_faces;
    /* Per face between two cells, when the file carries each cell's seed
     * (vorocrust's "seed_point"; n = 0 without): the two-point-flux
     * connection, the seeds' distance over the mean of the two cells'
     * enclosing radii. */
    vc_stats connection_rel;

    /* The boundary faces as triangles (polygons fanned from their vertex
     * average). */
    int64_t n_boundary_triangles;
    vc_stats triangle_quality;
    double angles_below_30;       /* percent of the triangles' angles; NaN without triangles */
    double angles_above_90;

    /* Against the input surface (when one was given). */
    int has_hausdorff;
    vc_hausdorff_result hausdorff;

    /* Seconds spent on the cells, the boundary and the Hausdorff distance. */
    double time_cells, time_boundary, time_hausdorff;

    /* Per-item values, owned by the report (for histograms): the fatness of
     * every cell (NaN when unmeasured) and the quality of every boundary
     * triangle. */
    double *cell_fatness;         /* n_cells */
    double *triangle_qualities;   /* n_boundary_triangles */
} vc_mesh_report;

/* Measures the mesh m; with input non-NULL, also the two-sided Hausdorff
 * distance between m's boundary and input (normalised by input's
 * bounding-box diagonal). mesh_name and input_name are used in messages
 * only. Runs with OpenMP; the report does not depend on the thread count.
 * Returns 0; VC_EINPUT (one line naming both files) when an input is given
 * but the mesh has no boundary face; VC_ENOMEM. out is zeroed on failure. */
int vc_mesh_report_compute(const vc_vtu_mesh *m, const char *mesh_name,
                           const vc_surface *input, const char *input_name,
                           vc_mesh_report *out, vc_error *err);

/* Frees the arrays of r and zeroes it; safe on a zeroed report. */
void vc_mesh_report_free(vc_mesh_report *r);

#ifdef __cplusplus
}
#endif
#endif
