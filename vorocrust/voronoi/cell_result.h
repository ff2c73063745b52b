/* The Voronoi cell of one kept seed as computed on its own, before the
 * cells are stitched into one conforming mesh. Internal to the engine. */
#ifndef VC_CELL_RESULT_H
#define VC_CELL_RESULT_H

#include <stdint.h>
#include <stdlib.h>

#include "vorocrust/error.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/seeds.h"

typedef struct vc_cell_result {
    int nv, nf, nfv;    /* nfv <= 65535 */
    double *v;          /* 3 * nv, absolute positions */
    int64_t *plane;     /* nf: neighbour seed index, or a wall code (< 0) */
    uint16_t *face_start; /* nf + 1 */
    uint16_t *fv;       /* nfv local vertex indices */
    double scale;       /* local cell size: distance to the nearest face's seed */
} vc_cell_result;

/* Where the cells' data live: per chunk of the build order, one block of
 * coordinates (the cells' v) and one of the rest. The stitching frees the
 * coordinate blocks (and clears their pointers) once it no longer needs
 * them. */
typedef struct vc_cell_store {
    int64_t n_blocks;
    void **coord;
    void **topo;
} vc_cell_store;

static inline void vc_cell_store_free(vc_cell_store *st)
{
    for (int64_t b = 0; b < st->n_blocks; b++) {
        if (st->coord)
            free(st->coord[b]);
        if (st->topo)
            free(st->topo[b]);
    }
    free(st->coord);
    free(st->topo);
    st->coord = st->topo = NULL;
    st->n_blocks = 0;
}

/* Stitches the independently computed cells of the kept seeds into out:
 * copies of one Voronoi vertex in different cells are identified (within
 * merge_tol times the local cell size), zero-length edges and zero-area
 * faces are dropped, and every face between two kept cells is stored once.
 * cells[k] is the cell of the k-th kept seed, kept_seed[k] its seed index;
 * order lists the cells in a spatially coherent order (NULL: 0..n_kept-1):
 * vertex copies are numbered in that order, so that neighbouring cells'
 * copies are close in memory. store: where the cells' data live (its
 * coordinate blocks are freed once the points are written; NULL: never).
 * Runs on threads (OpenMP); the result does not depend on their number. */
int vc_assemble_conforming(const vc_seeds *seeds, const vc_cell_result *cells,
                           const int64_t *kept_seed, int64_t n_kept, const int64_t *order,
                           vc_cell_store *store, double merge_tol, vc_polymesh *out,
                           vc_error *err);

#endif
