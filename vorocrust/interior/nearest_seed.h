/* Nearest surface seed of a point, through the Voronoi engine's grid of
 * seed bins. Internal to the interior-seed placement: the label of the
 * nearest surface seed decides whether a point is inside. */
#ifndef VC_INTERIOR_NEAREST_SEED_H
#define VC_INTERIOR_NEAREST_SEED_H

#include <stdint.h>

#include "vorocrust/seeds.h"
#include "voronoi/seed_grid.h"

/* Bins the seeds; returns 0, or -1 when out of memory. */
int vc_nearest_seed_grid_build(vc_seed_grid *g, const vc_seeds *s);

/* The nearest seed to x (ties: the lowest index) and its distance, searching
 * the grid's bins in growing shells; -1 for an empty grid. */
int64_t vc_nearest_seed(const vc_seed_grid *g, const double x[3], double *dist);

#endif
