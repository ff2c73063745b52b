/* The conforming polyhedral Voronoi engine.
 *
 * Builds the Voronoi cells of the kept seeds (label != 0) of a seed set,
 * with the non-kept seeds shaping the cells but contributing none, and
 * assembles them into one conforming mesh: global vertices, every face
 * between two kept cells stored once. Coincident Voronoi vertices (seeds
 * that are co-spherical, as VoroCrust's are by construction) are merged
 * and zero-length edges and zero-area faces dropped, with a tolerance
 * relative to the local cell size (the distance from the seed to its
 * nearest neighbour). */
#ifndef VORO_CRUST_VORONOI_H
#define VORO_CRUST_VORONOI_H

#include "vorocrust/error.h"
#include "vorocrust/log.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/seeds.h"

#ifdef __cplusplus
extern "C" {
#endif

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
    /* 1: the exact engine (experimental; issue 19): every side decision by
     * an exact predicate with a symbolic perturbation, cells stitched by
     * their vertices' seeds, no repair passes (voronoi/cell_stitch.h).
     * It meshes random, lattice, co-spherical and VoroCrust seed sets, but
     * can leave a face of zero area where a degenerate face has a vertex
     * inside its segment (not yet handled), and is slower on VoroCrust
     * seeds. 0 (the default): the tolerance engine. */
    int exact;
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

#ifdef __cplusplus
}
#endif
#endif
