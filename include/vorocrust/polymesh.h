/* The polyhedral mesh: the output of the Voronoi engine and the input of
 * every writer and quality measure.
 *
 * Faces are stored once. A face is oriented so that its normal (right-hand
 * rule on its vertex cycle) points out of its owner cell and into its
 * neighbour cell. Interior faces (neighbour >= 0) come first, sorted by
 * (owner, neighbour), then the boundary faces sorted by owner: the order
 * OpenFOAM's polyMesh expects. A cell lists its faces; the cell is the
 * owner of a face when face_owner[f] equals the cell index, otherwise the
 * face is seen reversed from that cell. */
#ifndef VORO_CRUST_POLYMESH_H
#define VORO_CRUST_POLYMESH_H

#include <stddef.h>
#include <stdint.h>
#include "vorocrust/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* face_other_seed of a boundary face on a wall of the clipping box:
 * VC_WALL_XMIN - k for the wall k in order xmin, xmax, ymin, ymax, zmin, zmax. */
#define VC_WALL_XMIN (-1)

typedef struct vc_polymesh {
    /* Vertices. */
    int64_t n_points;
    double *points; /* 3 * n_points */

    /* Faces: the vertex cycle of face f is
     * face_vertices[face_offsets[f] .. face_offsets[f + 1] - 1]. */
    int64_t n_faces;
    int64_t n_interior_faces; /* faces 0 .. n_interior_faces-1 are interior */
    int64_t *face_offsets;    /* n_faces + 1 */
    int64_t *face_vertices;
    int64_t *face_owner;      /* cell index */
    int64_t *face_neighbour;  /* cell index, or -1 for a boundary face */
    /* For every face, the seed on the other side of the owner's seed: the
     * neighbour's seed, a non-kept seed (boundary face), or a wall code
     * (VC_WALL_XMIN - k) for a face on the clipping box. */
    int64_t *face_other_seed;
    /* Optional (NULL): per face, the input group of a boundary face (an
     * index into group_name, n_groups of them), -1 for other faces; set
     * by vorocrust mesh from the input's triangle groups, it names the
     * boundary patches (vc_polymesh_boundary_patches). */
    int32_t *face_group;
    int32_t n_groups;
    char (*group_name)[64];
    double *face_area;        /* n_faces */
    double *face_centroid;    /* 3 * n_faces */
    double *face_normal;      /* 3 * n_faces, unit, owner -> neighbour */

    /* Cells: the faces of cell c are
     * cell_faces[cell_offsets[c] .. cell_offsets[c + 1] - 1]. */
    int64_t n_cells;
    int64_t *cell_offsets;    /* n_cells + 1 */
    int64_t *cell_faces;
    int64_t *cell_seed;       /* index of the cell's seed in the input seeds */
    int32_t *cell_region;     /* the seed's label */
    double *cell_volume;      /* n_cells */
    double *cell_fatness;     /* n_cells or NULL: enclosing / inscribed ball radius,
                                 set by callers that measure it (vorocrust mesh);
                                 written to the .vtu when present */
    double *cell_centroid;    /* 3 * n_cells */

    /* Copy of the seed positions (3 * n_seeds), for connection distances. */
    int64_t n_seeds;
    double *seed_xyz;
} vc_polymesh;

void vc_polymesh_free(vc_polymesh *m);

/* Number of vertices of face f. */
static inline int64_t vc_polymesh_face_size(const vc_polymesh *m, int64_t f)
{
    return m->face_offsets[f + 1] - m->face_offsets[f];
}

/* Recomputes face areas, centroids, normals, cell volumes and centroids
 * from the vertex positions and topology. */
void vc_polymesh_compute_geometry(vc_polymesh *m);

/* The same for one face (area, centroid, normal), and for one cell (volume
 * and centroid, from its faces' current geometry). */
void vc_polymesh_update_face_geometry(vc_polymesh *m, int64_t f);
void vc_polymesh_update_cell_geometry(vc_polymesh *m, int64_t c);

/* Skewness of interior face f exactly as OpenFOAM's checkMesh computes it
 * from the stored geometry (face centroid and normal, cell centroids: the
 * same formulas as OpenFOAM's): the distance from the face centroid to the
 * point where the line between the two cell centroids crosses the face
 * plane, divided by the larger of a fifth of the centroid distance and the
 * face's extent in that direction. 0 for a boundary face. checkMesh fails a
 * mesh with a face above 4. */
double vc_polymesh_face_skewness(const vc_polymesh *m, int64_t f);
/* The same for face f between two cells whose centroids are co and cn
 * (either side; f may be a boundary face whose other cell lies in another
 * mesh). */
double vc_polymesh_face_skewness_between(const vc_polymesh *m, int64_t f, const double co[3],
                                         const double cn[3]);

typedef struct vc_skew_collapse_stats {
    double max_skew_before, max_skew_after;
    int64_t n_collapsed;  /* faces collapsed */
    int64_t n_made_room;  /* of which not skew, but in the way of a skew one */
    int64_t n_skew_left;  /* faces still above the limit */
    int n_rounds;
    double max_move;      /* largest distance a point was moved */
} vc_skew_collapse_stats;

/* Mesh improvement for finite-volume solvers that use cell centroids
 * (OpenFOAM): collapses every interior face whose skewness exceeds
 * max_skew, in up to max_rounds rounds, most skew first: two of its edges
 * survive as one segment (the points between them merge into its ends), or
 * as a last resort the whole face merges into one point, whichever safe way
 * moves points least. A merged run of points goes to its one boundary point
 * (a point of a boundary face, or of a face between cells of two regions;
 * a run with two or more cannot move: the boundary and the interfaces
 * never move), else to
 * its average. A face in the way of a collapse (it would turn over or lose
 * its pyramid) and smaller than the skew face is collapsed first, next
 * round. A collapse is refused when a face around it would
 * pinch or turn by 90 degrees or more, when a cell around it would lose
 * volume or a face pyramid (judged from its new centroid), or when a face
 * would get a non-orthogonality above 65 degrees. Faces left with
 * fewer than three points are removed; the cells stay closed, the boundary
 * and the total volume unchanged, but the faces around a collapse are no
 * longer exactly planar and the cells no longer exact Voronoi cells: use it
 * on a copy meant for such a solver. Deterministic. Unused points are
 * dropped. Returns 0, or -1 when out of memory (the mesh is then left
 * consistent but possibly partly improved). */
int vc_polymesh_collapse_skew_faces(vc_polymesh *m, double max_skew, int max_rounds,
                                    vc_skew_collapse_stats *st);

/* A cell order for solvers: reverse Cuthill-McKee over the graph of cells
 * joined by interior faces (each connected part from a pseudo-peripheral
 * cell, neighbours by increasing degree, then index), into new_of_old
 * (n_cells). Deterministic. Returns 0, or -1 when out of memory. */
int vc_polymesh_rcm_order(const vc_polymesh *m, int64_t *new_of_old);

/* Renumbers the cells of m (cell c becomes new_of_old[c], a permutation),
 * keeping every invariant: interior faces sorted by (owner, neighbour) with
 * the owner the lower cell (a face whose cells swap roles is reversed, its
 * normal too), boundary faces by owner, each cell's faces in increasing
 * order, points numbered by first use in the faces. The geometry is
 * carried over unchanged. One array is rebuilt at a time (the peak is the
 * mesh and its largest array). Returns 0, or -1 when out of memory (m is
 * then inconsistent: free it). */
int vc_polymesh_renumber_cells(vc_polymesh *m, const int64_t *new_of_old);

/* Largest |owner - neighbour| over the interior faces: the bandwidth of a
 * solver's matrix in this cell order. */
int64_t vc_polymesh_bandwidth(const vc_polymesh *m);

/* Distance between the seeds of the two cells of interior face f (the
 * two-point-flux connection length). */
double vc_polymesh_face_seed_distance(const vc_polymesh *m, int64_t f);

/* Checks every invariant of the mesh:
 *  - indices in range, every face has >= 3 distinct vertices;
 *  - every interior face is listed by exactly its owner and its neighbour,
 *    every boundary face by its owner only;
 *  - every cell is closed (each of its edges is used once in each
 *    direction by its outward-oriented faces), convex (every vertex of the
 *    cell lies on the inner side of every face plane, within rel_tol times
 *    the cell size, times 1 + the cell size over the face's width for the
 *    error of a thin face's plane), and has positive volume.
 * rel_tol <= 0 selects the default (1e-7: ten times the Voronoi engine's
 * merge tolerance, since merging copies of a vertex moves it that far).
 * Returns the number of problems found (0 = valid). When report is not
 * NULL, up to report_len bytes of the first problems, one per line, are
 * written there. */
int64_t vc_polymesh_validate(const vc_polymesh *m, double rel_tol,
                             char *report, size_t report_len);

/* The boundary patches of a mesh, as every writer names them: a boundary
 * face against a non-kept seed belongs to its input group's patch (named
 * as the group, face_group) or, without one, to "surface"; one on a wall
 * of the clipping box to "xmin" ... "zmax"; with cells of several labels
 * (regions) every patch is split by its cells' label ("region2_surface",
 * "region2_inlet"). Patches are numbered in that order (by label, then
 * surface, xmin, ..., zmax, then the groups), only those that have
 * faces. */
typedef struct vc_boundary_patches {
    int n_patches;
    char (*name)[64];
    int64_t *size;         /* faces per patch */
    int *group;            /* per patch: its input group, or -1 (surface, walls) */
    int *face_patch;       /* per boundary face f: face_patch[f - n_interior_faces] */
    int n_labels;          /* the distinct cell labels (1 without cell_region) */
    int32_t *label_value;  /* ascending; NULL without cell_region */
} vc_boundary_patches;

/* The point where the segment between the seed of face f's owner and the
 * seed across f (the neighbour's, or the non-kept one of a boundary face)
 * crosses f: their midpoint, on the bisector that holds the face; the
 * face's centroid for a face on a wall of the clipping box. The two-point
 * flux's face point: the distance from either seed is half theirs. */
void vc_polymesh_face_seed_point(const vc_polymesh *m, int64_t f, double x[3]);

/* Fills out. Returns 0, -1 when out of memory, -2 for a boundary face with
 * an unknown wall code (its index in *bad_face when not NULL). */
int vc_polymesh_boundary_patches(const vc_polymesh *m, vc_boundary_patches *out,
                                 int64_t *bad_face);
/* The rank of a label among p's labels (0 with one label). */
int vc_boundary_patches_label_rank(const vc_boundary_patches *p, int32_t label);
void vc_boundary_patches_free(vc_boundary_patches *p);

/* Summary statistics used by the CLI. */
typedef struct vc_polymesh_stats {
    double volume_total, volume_min, volume_max;
    int64_t n_boundary_faces;
    double max_faces_per_cell, mean_faces_per_cell;
} vc_polymesh_stats;

void vc_polymesh_stats_compute(const vc_polymesh *m, vc_polymesh_stats *st);

#ifdef __cplusplus
}
#endif
#endif
