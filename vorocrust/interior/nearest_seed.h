/* Nearest surface seed of a point, through a k-d tree of the seeds (the
 * Voronoi engine's). Internal to the interior-seed placement: the label of
 * the nearest surface seed decides whether a point is inside. */
#ifndef VC_INTERIOR_NEAREST_SEED_H
#define VC_INTERIOR_NEAREST_SEED_H

#include <stdint.h>

#include "vorocrust/seeds.h"
#include "voronoi/seed_kdtree.h"

/* Indexes the seeds; returns 0, or -1 when out of memory. Free with
 * vc_seed_kdtree_free. */
int vc_nearest_seed_index_build(vc_seed_kdtree *t, const vc_seeds *s);

/* The nearest seed to x (ties: the lowest index) and its distance; -1 for
 * no seeds. */
int64_t vc_nearest_seed(const vc_seed_kdtree *t, const double x[3], double *dist);

#endif
