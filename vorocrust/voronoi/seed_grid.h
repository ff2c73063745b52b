/* A uniform grid of bins over the seeds, for nearest-first neighbour
 * visits during cell construction. Internal to the Voronoi engine. */
#ifndef VC_SEED_GRID_H
#define VC_SEED_GRID_H

#include <stdint.h>

typedef struct vc_grid_offset {
    int dx, dy, dz;
    double dmin2; /* squared lower bound of the distance from any point of a
                     bin to any point of the bin at this offset, in bin units */
} vc_grid_offset;

/* Chebyshev radius of the precomputed bin offsets. */
#define VC_GRID_MAX_RING 3

typedef struct vc_seed_grid {
    int n[3];
    double lo[3];
    double h;            /* bin edge length */
    int64_t *bin_start;  /* n[0]*n[1]*n[2] + 1 */
    int64_t *seed_index; /* seeds ordered by bin */
    double *xyz;         /* their positions, in the same order */
    /* Bin offsets of Chebyshev radius <= VC_GRID_MAX_RING, nearest
     * first. */
    vc_grid_offset *offsets;
    int n_offsets;
} vc_seed_grid;

/* Bins n seeds (3 * n coordinates) inside [lo, hi] with about
 * seeds_per_bin seeds per bin. Returns 0, or -1 when out of memory. */
int vc_seed_grid_build(vc_seed_grid *g, const double *xyz, int64_t n,
                       const double lo[3], const double hi[3], double seeds_per_bin);
void vc_seed_grid_free(vc_seed_grid *g);

/* Every bin index once, in a spatially coherent order (recursive halving
 * of the longest side: a Z-order that also suits elongated grids), into
 * bins (n[0] * n[1] * n[2] entries). Neighbouring bins are mostly close
 * in it along all three axes, where the row-major order puts the
 * neighbours across z a whole layer of bins away. */
void vc_seed_grid_bin_order(const vc_seed_grid *g, int64_t *bins);

/* Bin coordinates of a point (clamped to the grid). */
void vc_seed_grid_locate(const vc_seed_grid *g, const double x[3], int b[3]);

static inline int64_t vc_seed_grid_bin(const vc_seed_grid *g, int i, int j, int k)
{
    return ((int64_t)k * g->n[1] + j) * g->n[0] + i;
}

#endif
