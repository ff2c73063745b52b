/* The Voronoi cell of one kept seed as computed on its own, before the
 * cells are stitched into one conforming mesh. Internal to the engine. */
#ifndef VC_CELL_RESULT_H
#define VC_CELL_RESULT_H

#include <stdint.h>

#include "vorocrust/error.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/seeds.h"

typedef struct vc_cell_result {
    int nv, nf, nfv;
    double *v;          /* 3 * nv, absolute positions */
    int64_t *plane;     /* nf: neighbour seed index, or a wall code (< 0) */
    int *face_start;    /* nf + 1 */
    int *fv;            /* nfv local vertex indices */
    double scale;       /* local cell size: distance to the nearest face's seed */
} vc_cell_result;

/* Stitches the independently computed cells of the kept seeds into out:
 * copies of one Voronoi vertex in different cells are identified (within
 * merge_tol times the local cell size), zero-length edges and zero-area
 * faces are dropped, and every face between two kept cells is stored once.
 * cells[k] is the cell of the k-th kept seed, kept_seed[k] its seed index;
 * order lists the cells in a spatially coherent order (NULL: 0..n_kept-1):
 * vertex copies are numbered in that order, so that neighbouring cells'
 * copies are close in memory. Runs on threads (OpenMP); the result does
 * not depend on their number. */
int vc_assemble_conforming(const vc_seeds *seeds, const vc_cell_result *cells,
                           const int64_t *kept_seed, int64_t n_kept, const int64_t *order,
                           double merge_tol, vc_polymesh *out, vc_error *err);

#endif
