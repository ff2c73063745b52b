/* Stitching the independently built Voronoi cells into one conforming mesh,
 * by the identity of their vertices. Internal to the engine.
 *
 * Every cell is built with the same exact, symbolically perturbed side
 * test (power_side.h), so the cells form one cell complex by construction:
 * a vertex is the same four planes (the cell's seed and three seeds or
 * walls) in every cell that has it, and a face between two kept cells is
 * the same cycle of vertices in both, reversed. Stitching is a lookup:
 *  - a vertex is numbered by its owner, the kept cell of the lowest seed
 *    index among its four; the other cells find it in the owner's face
 *    against them, by its four planes;
 *  - the perturbed diagram is simple, so a vertex where more than four
 *    seeds are co-spherical is a cluster of vertices joined by edges of
 *    length zero. An edge is collapsed when its ends coincide exactly
 *    (decided by vc_power_on_plane) or lie nearer each other than
 *    merge_tol times their distance to their seeds (seeds co-spherical to
 *    rounding, as VoroCrust's are); the decision is a function of the
 *    edge's two vertices alone, so every cell collapses it alike;
 *  - a vertex whose four seeds lie on one of the spheres given (spheres
 *    may be NULL; see vc_seed_spheres) is that sphere's centre: its point
 *    becomes the centre and every such vertex of the centre joins one
 *    class, decided by the seeds' lists, not by distances;
 *  - faces whose cycle collapses below three points disappear from both
 *    cells, a cycle that folds back on itself (x, a, x) loses the fold,
 *    a face whose points all lie on one segment (zero area) leaves both
 *    cells, its points inserted into the edges of the faces around it,
 *    and a point left inside a straight edge (two neighbours in the faces
 *    as written) leaves every face.
 * Output: interior faces sorted by (owner, neighbour), the owner being the
 * lower cell, then boundary faces by owner, in the cell's face order;
 * points in the owners' order (cells in the spatial order given); a cell
 * lists its faces in increasing order. The same bytes for any thread
 * count. A vertex that its owner lacks is a defect of the engine:
 * VC_EINTERNAL. */
#ifndef VC_VORONOI_CELL_STITCH_H
#define VC_VORONOI_CELL_STITCH_H

#include "cell_result.h"
#include "power_side.h"
#include "vorocrust/voronoi.h"

/* cells[m] is the cell of kept seed kept_seed[order[m]] (kept_seed
 * ascending, n_kept of them). store (may be NULL): where the cells' data
 * live; its pools are emptied as soon as they are no longer read (the
 * coordinates once the points are known, the rest before the mesh's
 * geometry is allocated), which lowers the peak memory; cells must not be
 * read after the call then. */
int vc_stitch_cells(const vc_seeds *seeds, const vc_power_ctx *ctx, const vc_cell_result *cells,
                    const int64_t *kept_seed, int64_t n_kept, const int64_t *order,
                    vc_cell_store *store, double merge_tol, const vc_seed_spheres *spheres,
                    int threads, const vc_logger *log, vc_polymesh *out, vc_error *err);

#endif
