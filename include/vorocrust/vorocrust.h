/* vorocrust: the whole VoroCrust pipeline as one call.
 *
 *     vc_surface s;            // vc_surface_read(path, &s, NULL, &err)
 *     vc_mesh_options opt;
 *     vc_mesh_options_default(&opt);
 *     vc_mesh_result r;
 *     if (vc_mesh(&s, &opt, &r, &err) == 0) {
 *         vc_write_vtu(&r.mesh, "out.vtu", VC_VTU_ZLIB, &err);
 *         vc_mesh_result_free(&r);
 *     }
 *
 * vc_mesh runs, in order: the input checks, sharp-feature detection
 * (optionally Loop smoothing), the surface sampling (protection of corners
 * and creases, coverage, Lipschitz fixes, sliver elimination), the surface
 * seeds, the reconstructed surface, the interior seeds (a p4est octree or a
 * lattice), optional Lloyd relaxation, the conforming Voronoi mesh, its
 * validation and its cell quality. When sliver elimination diverges it
 * samples once more, as described at vc_mesh_options.resample.
 *
 * The caller owns the process: the library starts no MPI, sets no
 * environment variable, changes no OpenMP setting (threads go to each
 * parallel region as a num_threads clause), never exits or aborts and
 * writes to no stream; every message goes to the logger of the options.
 * With the octree interior (the default) MPI must be initialised by the
 * caller before vc_mesh (MPI_Init or MPI_Init_thread; the octree lives on
 * MPI_COMM_SELF); vc_mesh fails with VC_EPARAM otherwise.
 *
 * Same surface, options and seed give the same result, byte for byte,
 * whatever the number of threads.
 *
 * The stage headers included below (sampling, interior, voronoi, ...) are
 * the advanced interface: each stage can be called on its own. */
#ifndef VORO_CRUST_VOROCRUST_H
#define VORO_CRUST_VOROCRUST_H

#include <stdint.h>

#include "vorocrust/error.h"
#include "vorocrust/interior.h"
#include "vorocrust/io.h"
#include "vorocrust/log.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/quality.h"
#include "vorocrust/regions.h"
#include "vorocrust/sampling.h"
#include "vorocrust/seeds.h"
#include "vorocrust/smoothing.h"
#include "vorocrust/surface.h"
#include "vorocrust/version.h"

#ifdef __cplusplus
extern "C" {
#endif

/* vc_mesh collapses the input's edges shorter than this share of the error
 * bound (far below what the mesh can show: vc_surface_collapse_short_edges). */
#define VC_MESH_SHORT_EDGE 1e-3
/* A sliver of one face reaching into another (a hairpin of two creases)
 * whose base is below this share of the error bound is collapsed before
 * sampling (vc_surface_collapse_hairpins): the slit is that narrow at its
 * widest. */
#define VC_MESH_HAIRPIN_BASE 0.125

/* The version of the library the program runs with, "MAJOR.MINOR.PATCH"
 * (VC_VERSION_STRING is the one it was compiled against). */
const char *vc_version(void);
/* VC_VERSION_NUMBER of the library the program runs with. */
int vc_version_number(void);

typedef enum vc_interior_kind {
    VC_INTERIOR_OCTREE = 0,  /* graded by a p4est octree (thesis 5.5.2); needs MPI */
    VC_INTERIOR_LATTICE = 1, /* a cubic lattice (thesis 6.2.10) */
    VC_INTERIOR_NONE = 2     /* only the inside surface seeds */
} vc_interior_kind;

/* What vc_mesh may do when sliver elimination diverges on the first
 * sampling (flags of vc_mesh_options.resample). VC_RESAMPLE_FOLDS by
 * default; with none, the divergence is an error naming where it is
 * stuck. */
enum {
    /* Folds between 20 degrees and theta_sharp inside the patches: sample
     * again at theta_sharp 20, where they are creases (the surface is not
     * moved). */
    VC_RESAMPLE_CREASES = 1,
    /* When that diverges too (or is not allowed): sample again after
     * VC_SMOOTH_DEFAULT_ITERATIONS rounds of Loop smoothing of the patches
     * at theta_sharp 120 (this moves the surface off the input). */
    VC_RESAMPLE_SMOOTH = 2,
    /* Make the folds over 10 degrees where sliver elimination is stuck
     * creases and sample again, up to 4 times, then every fold over 10
     * degrees (the surface is not moved; the default). */
    VC_RESAMPLE_FOLDS = 4
};

/* Where the boundary patches come from (vc_mesh_options.patches). */
typedef enum vc_patch_source {
    VC_PATCHES_GROUPS = 0,   /* the input's triangle groups (vc_surface.tri_group), if any */
    VC_PATCHES_FEATURES = 1, /* the input's sharp-feature patches at theta_sharp (thesis
                                6.2.2): "patch1", "patch2", ... */
    VC_PATCHES_NONE = 2      /* one patch, "surface" */
} vc_patch_source;

typedef struct vc_mesh_options {
    /* The sampling (see vc_sampling_options for the meaning of each). */
    double sharp_angle;     /* theta_sharp, degrees, default 60 */
    double max_error;       /* fraction of the bounding-box diagonal, default 0.004 */
    double smooth_width;    /* > 0: surface ball centres on a smooth surface near the
                               input (an APSS fit whose kernel radius is this many times
                               the error bound), radii at most curvature_factor times its
                               radius of curvature; 0 (default): on the input's facets */
    double curvature_factor; /* default 0.2 */
    int max_sliver_iterations; /* sliver passes before the safe mode, and half the passes
                               after which a sampling counts as diverged (then resampled
                               as resample says); 0: the default, 100 */
    int keep_short_edges;   /* 1: the input's edges shorter than VC_MESH_SHORT_EDGE times the
                               error bound are kept; 0 (default): collapsed, said so */
    int no_lift;            /* 1: surface ball centres stay on the input; 0 (default): they
                               move off it by the mean sag of their reconstructed facets,
                               so that the reconstruction has no volume bias
                               (vc_sampling_options.lift_centres) */
    double lipschitz;       /* L, default 0.25 */
    double max_size;        /* largest ball radius; <= 0: the bounding-box diagonal */
    uint64_t seed;          /* random seed, default 1 */
    int smooth_iterations;  /* rounds of Loop smoothing before sampling, default 0 */
    int resample;           /* VC_RESAMPLE_* flags, default VC_RESAMPLE_FOLDS; the
                               CLI's --fallback: CREASES | SMOOTH, --no-fold-creases: 0 */
    /* Stop after the reconstructed surface (no volume mesh). The interior
     * seeds are still placed: they bound the inside surface seeds' cells,
     * which are built alone; the surface is the one the volume mesh would
     * have. Without MPI started, the octree is skipped: the same surface,
     * slower. */
    int surface_only;
    /* Nested closed shells alternate solid and cavity by the even-odd rule
     * (outermost solid), whatever their orientation: each component is
     * reoriented before sampling. Without it the orientation decides, and
     * nested shells of the same orientation (an inclusion) are refused. */
    int cavities;
    /* 1 (default): a surface that intersects itself is meshed as the
     * region it winds around at least once (vc_surface_self_union), with a
     * warning (degenerate contacts are still refused); 0: it is refused. */
    int self_union;
    vc_patch_source patches; /* default VC_PATCHES_GROUPS */
    vc_interior_kind interior;
    double interior_spacing; /* lattice spacing; <= 0: vc_interior_default_spacing */
    int lloyd_iterations;    /* 0 to 1000, default 0 */
    /* Short-edge protection (docs/solver-grade-cells.md), 0 <= E < 0.25:
     * with E > 0, pole seeds (vc_interior_sphere_seeds) join the interior
     * seeds, and the interior seeds at short Voronoi edges are moved a
     * little (vc_interior_protect) until every edge at their cells'
     * vertices is at least E times the cell's radius. 0.01 is the
     * recommended value; default 0: off (it costs about as much again as
     * the Voronoi cells). */
    double protect_edge;
    /* checkMesh's failures mended at the seeds (vc_interior_unskew): with
     * S > 0, the interior seeds of faces whose checkMesh skewness exceeds S
     * or that miss -allGeometry's interpolation weight or volume ratio, and
     * of the cells it calls concave, move a little and the cells are built
     * again, up to 3 rounds while that lowers the count; default 0: off.
     * 3.9 keeps a margin below checkMesh's limit of 4. */
    double unskew;
    double quartet_gap;      /* vc_sampling_options.quartet_gap; default 0 */
    /* Noise at the error bound (docs/sampling-convergence.md, session 35):
     * 0 (default): the input is sampled, or a copy of it smoothed within
     * half the error bound (vc_surface_denoise) and sampled within the
     * other half when the input is rough (over 1% of its vertices with a
     * triangle normal 20 degrees off their mean) and the sizing predicts
     * that it would take at least 1.5 times the copy's balls; 1: the copy
     * always; -1: the input always. A sampling of the input that diverges is followed by the
     * copy's (unless -1). Not with smooth_iterations or smooth_width, nor
     * on multi-material inputs (the seeds are located in the input's
     * regions). */
    int denoise;
    int threads;             /* <= 0: OpenMP's default */
    /* A sampling predicted (from the sizing) to need more balls than this
     * is refused before it starts, and one that reaches it stops, both with
     * VC_EPARAM. 0 (default): vc_mesh_default_max_balls(); < 0: no limit. */
    int64_t max_balls;
    /* Where messages go (NULL: nowhere), and the name they give the input
     * (a file name; NULL: "surface"). */
    const vc_logger *log;
    const char *name;
} vc_mesh_options;

void vc_mesh_options_default(vc_mesh_options *opt);

/* The ball limit that max_balls = 0 stands for: what this machine's memory
 * holds with a margin (about 16 KiB per ball for the balls, seeds, surface
 * and volume mesh). */
int64_t vc_mesh_default_max_balls(void);

/* Whether a denoised copy of the input was sampled (vc_mesh_options.denoise). */
typedef struct vc_denoise_choice {
    int used;                   /* the copy was sampled */
    double rough_share;         /* vertices whose triangles' normals spread by over 20
                                   degrees; 1% or less: nothing predicted, no copy made */
    double n_input, n_denoised; /* balls predicted for each (0 when not predicted) */
    double bound;               /* the copy's absolute error bound: the input's less max_move */
    vc_denoise_report moved;    /* how far the copy's vertices are from the input's */
    double volume_change;       /* the copy's enclosed volume over the input's, less 1
                                   (0 when no copy was made) */
    int64_t self_intersections; /* pairs of the copy's triangles that cut each other
                                   (moved.n_crossing: 0, since vc_surface_denoise
                                   withdraws such moves; a guard); such a copy is never
                                   sampled */
    int copy_refused;           /* a copy made was not sampled for its volume change or
                                   its self-intersections */
} vc_denoise_choice;

/* Quality of the reconstructed surface: polygons fanned from their
 * centroid (triangles as they are), Q = the triangle quality of
 * vc_triangle_quality. */
typedef struct vc_surface_quality {
    int64_t n_triangles;
    double q_min, q_mean;
    double pct_below_30, pct_above_90; /* % of the angles */
} vc_surface_quality;

/* Cell quality of the volume mesh; interior cells are those without a
 * boundary face. Fatness is the enclosing over the inscribed ball radius. */
typedef struct vc_cell_quality {
    int64_t n_measured, n_unmeasured, n_interior;
    double volume_min, volume_max;
    double fatness_max, fatness_mean;
    double interior_fatness_max, interior_fatness_mean;
    double shortest_edge_rel_min; /* shortest edge / enclosing radius */
    /* What finite-volume solvers trip over (issue 20), over the measured
     * cells and the interior faces: */
    double shortest_edge_rel_p1;  /* 1st percentile of shortest edge / enclosing radius */
    double short_edge_share;      /* share of cells whose shortest edge is below 1e-2 of it */
    double small_face_rel_min;    /* smallest face area / enclosing radius^2 */
    double small_face_rel_p1;
    double connection_rel_min;    /* seed distance / mean enclosing radius of the two cells */
    double connection_rel_p1;
    double non_orthogonality_max; /* degrees between a face's normal and the line between
                                     its cells' centroids (checkMesh's) */
    double non_orthogonality_mean;/* checkMesh's average: the angle of the mean cosine */
    double skewness_max;          /* checkMesh's (vc_polymesh_face_skewness) */
    int64_t n_skew_faces;         /* interior faces above 4, checkMesh's limit */
} vc_cell_quality;

/* One region of a multi-material domain in the volume mesh. */
typedef struct vc_region_mesh {
    int32_t label;          /* its cells' region value (region index + 1); 0: a void
                               (a cavity by orientation), which gets no cells */
    vc_region_kind kind;
    double input_volume;    /* enclosed by its boundary in the input */
    double mesh_volume;     /* sum of its cells' volumes */
    int64_t n_cells;
    int64_t n_boundary_faces;  /* faces between its cells and the outside */
    int64_t n_interface_faces; /* faces between its cells and another region's */
    int64_t euler_input;    /* Euler characteristic of its boundary in the input */
    vc_polysurface_topology topology; /* of the faces around its cells */
    int closed;             /* those faces make a closed, consistently oriented
                               2-manifold with the input's Euler characteristic */
} vc_region_mesh;

/* Seconds per phase. */
typedef struct vc_mesh_times {
    double features;        /* detection and smoothing of the kept attempt */
    double sizing, corners, edges, surface, lipschitz, slivers; /* the sampling */
    double failed_sampling; /* the attempt that diverged, when resampled */
    double denoise;         /* the denoised copy and the two predictions */
    double seeds, reconstruct, interior, lloyd, protect, voronoi, quality, unskew;
    double total;
} vc_mesh_times;

typedef struct vc_mesh_result {
    /* The input as vc_mesh checked it (topology, Euler characteristic,
     * enclosed volume). */
    vc_surface_report input;
    /* 1 when the input intersected itself and its union was meshed; input
     * then describes the union. */
    int unioned;
    vc_self_union_report self_union;
    /* Triangles reversed because the input's orientation was inconsistent
     * (each component keeps the orientation most of its triangles have;
     * input then describes the reoriented surface). */
    int64_t n_flipped;
    /* Turned-over needles whose long edge was flipped
     * (vc_surface_flip_turned_needles, within half the error bound); input
     * then describes the repaired surface. */
    vc_needle_flip_report needles;
    /* Edges shorter than VC_MESH_SHORT_EDGE times the error bound collapsed
     * (vc_surface_collapse_short_edges): how many, and the largest distance
     * a vertex moved; input then describes the collapsed surface. */
    int64_t n_short_collapsed;
    double short_collapse_move;
    /* Hairpin bases collapsed (vc_surface_collapse_hairpins, bases below
     * VC_MESH_HAIRPIN_BASE times the error bound): how many, and the largest
     * distance a vertex moved; input then describes the collapsed surface. */
    int64_t n_hairpins;
    double hairpin_move;
    /* Pinch vertices opened (vc_surface_open_pinches, by an eighth of the
     * error bound): the input's whose fans meet at less than theta_sharp
     * (input then describes the opened surface) and, when unioned, every
     * one of the union's. */
    vc_pinch_report input_pinches, pinches;
    int64_t n_regions;          /* bounded regions of its arrangement (vorocrust/regions.h) */
    /* 1 when they are not one solid (vc_regions_single_solid): several
     * materials, interfaces, inclusions; then every seed and cell carries
     * its region's label and region_mesh[k] describes region k. */
    int multi_material;
    vc_region_mesh *region_mesh; /* n_regions entries when multi_material */

    /* The sampling that was kept. */
    double first_sharp_angle;   /* the angle of the first attempt */
    double sharp_angle;         /* the angle of the kept one */
    int resampled;              /* 1 when the first attempt diverged */
    int smooth_iterations;      /* rounds applied before the kept sampling */
    vc_denoise_choice denoise;  /* the denoised copy, when sampled instead of the input */
    int64_t n_sampled_triangles;/* triangles of the sampled (maybe smoothed) surface */
    /* The balls; a corner ball's element is a vertex and a surface ball's
     * a triangle of the input as checked (after the repairs the log names:
     * welded seams, split T-junctions and caps, a union; several materials:
     * their surface with each interface once), unless smoothed;
     * an edge ball's indexes the sampled surface's sharp edges. */
    vc_balls balls;
    vc_sampling_stats sampling;
    int64_t n_half_covered;     /* seed pairs left half covered (0 on success) */

    /* Seeds: the n_surface_seeds surface seeds first (n_inside_seeds of
     * them inside, label 1; the others outside, label 0), then the
     * n_interior_seeds interior seeds (after Lloyd relaxation, if any). */
    vc_seeds seeds;
    int64_t n_surface_seeds, n_inside_seeds, n_interior_seeds;

    /* The reconstructed surface. */
    vc_polysurface surface;
    vc_polysurface_topology surface_topology;
    /* The volume mesh's cells are in reverse Cuthill-McKee order: the
     * largest |owner - neighbour| of an interior face, in it and in the
     * engine's order by seed. */
    int64_t cell_bandwidth, cell_bandwidth_engine;
    int surface_closed;         /* closed, consistently oriented 2-manifold with the
                                   input's Euler characteristic (always 1 on success:
                                   vc_mesh fails otherwise) */
    double surface_volume;      /* enclosed by it (polygons fanned) */
    vc_surface_quality surface_quality;
    /* its two-sided Hausdorff distance to the surface meshed (the input,
     * or its union, its shells reoriented), sampled (vc_hausdorff);
     * normalised by that surface's bounding-box diagonal */
    vc_hausdorff_result surface_distance;

    /* The volume mesh (not with surface_only): the Voronoi cells of the
     * inside surface seeds and the interior seeds, cell_fatness set. */
    int has_mesh;
    vc_polymesh mesh;
    double mesh_volume;         /* sum of the cell volumes */
    int64_t mesh_problems;      /* found by vc_polymesh_validate (always 0 on success:
                                   vc_mesh fails with VC_EINTERNAL otherwise) */
    char mesh_problem[VC_ERROR_LEN]; /* the first one, when any */
    vc_cell_quality cell_quality;
    vc_octree_stats octree;     /* with the octree interior */
    vc_lloyd_stats lloyd;       /* with lloyd_iterations > 0 */
    vc_protect_stats protect;   /* with protect_edge > 0 and interior seeds */
    vc_unskew_stats unskew;     /* with unskew > 0: the first round's, with the
                                   moves and cells built of all rounds */
    int unskew_rounds;          /* rounds that moved seeds (each builds the cells again) */
    int64_t n_sphere_seeds;     /* the first of the interior seeds: on the balls'
                                   spheres (vc_interior_sphere_seeds) */
    int64_t *sphere_ball;       /* n_sphere_seeds: the ball of each */

    vc_mesh_times time;
} vc_mesh_result;

/* Runs the pipeline on the surface s (as read by vc_surface_read, or built
 * by the caller). On success fills *out (free it with vc_mesh_result_free).
 * On failure *out is left empty and err says why: VC_EINPUT for an input
 * that cannot bound one solid (open, inconsistently oriented, repeated or
 * zero-area triangles, self-intersections, no volume, several regions
 * that are not one solid: see vc_regions_single_solid), a sampling that
 * diverged even after the resampling allowed, or a reconstructed surface
 * that is not a closed oriented 2-manifold of the input's Euler
 * characteristic (for several materials: a region's cells not bounded so,
 * or off the input region's volume by more than 1%); VC_EPARAM for a bad
 * option or, with the octree interior, MPI not initialised; VC_ENOMEM;
 * VC_EINTERNAL, also for a volume mesh that fails vc_polymesh_validate. */
int vc_mesh(const vc_surface *s, const vc_mesh_options *opt, vc_mesh_result *out,
            vc_error *err);

/* Frees every array of r and zeroes it; safe on a zeroed result. */
void vc_mesh_result_free(vc_mesh_result *r);

#ifdef __cplusplus
}
#endif
#endif
