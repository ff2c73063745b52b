/* The balls' spheres each seed lies on (internal to the pipeline): the
 * surface seeds are points where three spheres meet, the sphere seeds lie
 * on their ball's; given to the Voronoi engine (vc_seed_spheres), the
 * vertex at a ball's centre, where all the seeds on its sphere meet, is
 * one vertex placed at the centre rather than a cluster that rounding
 * spreads. */
#ifndef VC_PIPELINE_SEED_SPHERES_H
#define VC_PIPELINE_SEED_SPHERES_H

#include "vorocrust/sampling.h"
#include "vorocrust/seeds.h"
#include "vorocrust/voronoi.h"

typedef struct vc_seed_spheres_owned {
    vc_seed_spheres view; /* what the engine reads (pointers into the arrays below) */
    double *sphere;
    int64_t *start, *id;
} vc_seed_spheres_owned;

/* Finds, for each of the first n_near seeds, the balls whose sphere it
 * lies on (to 1e-9 of the radius; up to 8 per seed, ascending); the
 * others lie on none (the interior seeds keep a clearance from every
 * ball). Returns 0, or -1 when out of memory (out is then empty). The
 * result does not depend on threads. */
int vc_seed_spheres_find(const vc_balls *balls, const vc_seeds *seeds, int64_t n_near,
                         int threads, vc_seed_spheres_owned *out);
void vc_seed_spheres_free(vc_seed_spheres_owned *s);

#endif
