/* The conforming polyhedral Voronoi engine.
 *
 * Builds the Voronoi cells of the kept seeds (label != 0) of a seed set,
 * with the non-kept seeds shaping the cells but contributing none, and
 * assembles them into one conforming mesh: global vertices, every face
 * between two kept cells stored once.
 *
 * Every decision about a cell's shape (is this vertex beyond the bisector
 * of the seed and that neighbour?) is exact: a floating-point filter with
 * a rigorous error bound, then double-double and expansion arithmetic,
 * with exact ties (co-spherical seeds, as VoroCrust's are by construction)
 * broken by one symbolic perturbation that every cell applies alike. A
 * Voronoi vertex is named by its seeds; cells that share it agree by
 * construction and are stitched by that name. Vertices of degree above 4
 * come out as one point, zero-length edges and zero-area faces disappear;
 * Voronoi vertices that differ only by rounding (nearer each other than
 * 1e-8 of their distance to their seeds) are also one point. */
#ifndef VORO_CRUST_VORONOI_H
#define VORO_CRUST_VORONOI_H

#include "vorocrust/error.h"
#include "vorocrust/log.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/seeds.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Spheres that pass through seeds by construction (VoroCrust's balls: a
 * surface seed is a point where three of their spheres meet, so every
 * seed on a ball's sphere is equidistant from its centre). Seed s lies on
 * the spheres id[start[s]] .. id[start[s + 1] - 1], ascending (start has
 * one entry per seed and one more, non-decreasing from 0; every id below
 * n_spheres: vc_voronoi_build checks both); sphere a is sphere[4a ..
 * 4a + 3]: centre, radius. */
typedef struct vc_seed_spheres {
    int64_t n_spheres;
    const double *sphere;
    const int64_t *start;
    const int64_t *id;
} vc_seed_spheres;

typedef struct vc_voronoi_options {
    /* Clip every cell to the box [box[0],box[3]] x [box[1],box[4]] x
     * [box[2],box[5]] when has_box; otherwise cells are bounded by a box
     * enclosing the seeds with a margin of the seeds' bounding-box diagonal
     * (VoroCrust's outside seeds bound every kept cell well inside it). */
    int has_box;
    double box[6];
    /* Threads for the cell computation; <= 0 means OpenMP's default. The
     * output does not depend on it. */
    int threads;
    /* Progress (VC_LOG_INFO: every tenth of the cells) and phase timings
     * (VC_LOG_DEBUG) go here; NULL: nowhere. */
    const vc_logger *log;
    /* Where each cell's neighbours come from: VC_NEIGHBOURS_AUTO (0, the
     * default: the grid's bins, or a k-d tree's nearest neighbours when the
     * seeds crowd the bins), VC_NEIGHBOURS_GRID or VC_NEIGHBOURS_TREE. The
     * cells are the same either way; only the time differs. */
    int neighbours;
    /* NULL, or the spheres the seeds lie on: a Voronoi vertex whose four
     * seeds lie on one of them (and that lies within 1e-4 of its radius
     * of its centre) is its centre. More than four seeds on one sphere
     * are co-spherical only to rounding in doubles, which splits their
     * common vertex into a cluster of vertices; where two of the seeds
     * are nearly coincident the cluster spans more than the engine's
     * merge distance (1e-8 of the radius) and leaves edges and faces of
     * that size. The lists make it one vertex, at the centre. */
    const vc_seed_spheres *spheres;
} vc_voronoi_options;

enum { VC_NEIGHBOURS_AUTO = 0, VC_NEIGHBOURS_GRID = 1, VC_NEIGHBOURS_TREE = 2 };

void vc_voronoi_options_default(vc_voronoi_options *opt);

/* Whether the engine's large arrays ask the kernel for transparent huge
 * pages (madvise), for the whole process; default 0, where the system's
 * own policy applies. Huge pages make first touches cheaper on most
 * machines but several times dearer on virtual machines whose host
 * reclaims freed memory (see docs/voronoi-engine.md). The output does not
 * depend on it. */
void vc_voronoi_set_huge_pages(int wanted);

/* Builds the mesh. Fails with VC_EINPUT on coincident seeds (naming both),
 * non-finite coordinates, seeds outside the box, or no kept seed. */
int vc_voronoi_build(const vc_seeds *seeds, const vc_voronoi_options *opt,
                     vc_polymesh *out, vc_error *err);

/* The cells of a build, kept so that the mesh of the same seeds with a
 * few of them moved is made without building every cell again. */
typedef struct vc_voronoi_cells vc_voronoi_cells;

/* vc_voronoi_build, keeping its cells in *cells (freed with
 * vc_voronoi_cells_free; about 100 to 200 bytes per cell). */
int vc_voronoi_build_keep(const vc_seeds *seeds, const vc_voronoi_options *opt,
                          vc_polymesh *out, vc_voronoi_cells **cells, vc_error *err);

/* The mesh of seeds (the same count and kept labels as when the cells were
 * built, the seeds moved[0 .. n_moved) at new places, every other seed
 * where it was) into out, and the kept cells updated: only the cells of
 * the moved seeds and of the seeds next to them, before or after the
 * move, are built again (Voronoi neighbourhood is symmetric, and decided
 * exactly), then all are stitched. The mesh is the one vc_voronoi_build
 * gives for these seeds, byte for byte; when a moved seed leaves the
 * bounding box the first seeds had, every cell is built again. opt: the
 * same box and neighbour source as the build (its threads, log and
 * spheres may differ). After a failed rebuild the cells are refused
 * (VC_EPARAM): build them again. */
int vc_voronoi_rebuild(vc_voronoi_cells *cells, const vc_seeds *seeds, const int64_t *moved,
                       int64_t n_moved, const vc_voronoi_options *opt, vc_polymesh *out,
                       vc_error *err);

/* How many cells the last build or rebuild of cells computed. */
int64_t vc_voronoi_cells_rebuilt(const vc_voronoi_cells *cells);

void vc_voronoi_cells_free(vc_voronoi_cells *cells);

#ifdef __cplusplus
}
#endif
#endif
