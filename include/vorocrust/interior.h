/* Interior seeds (thesis 5.5.2, 6.2.10): seeds inside the volume, outside
 * the union of surface balls, so that the Voronoi cells of the inside
 * surface seeds and the interior seeds fill the volume the reconstructed
 * surface encloses.
 *
 * vc_interior_lattice places them on a cubic lattice (a hex-dominant
 * interior, thesis 6.2.10). A lattice point becomes a seed when it lies
 * outside every ball, inside the domain and at least half a spacing away
 * from every surface seed; inside means that its nearest surface seed is
 * an inside seed (the labels of the surface seeds decide, no second test).
 * The graded octree interior (p4est) is not implemented yet. */
#ifndef VORO_CRUST_INTERIOR_H
#define VORO_CRUST_INTERIOR_H

#include "vorocrust/error.h"
#include "vorocrust/sampling.h"
#include "vorocrust/seeds.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The default lattice spacing: the largest surface-ball radius (so that
 * interior cells are about the size of the largest surface cells), capped
 * by max_size when positive. */
double vc_interior_default_spacing(const vc_balls *balls, double max_size);

/* Appends the interior seeds (label 1) on a lattice of the given spacing to
 * a copy of the surface seeds: out = surface seeds, then interior seeds
 * in lattice order. *n_interior receives their number. Fails with
 * VC_EPARAM for a spacing that is not positive or would make more than
 * 1e9 lattice points, VC_ENOMEM. */
int vc_interior_lattice(const vc_balls *balls, const vc_seeds *surface_seeds, double spacing,
                        vc_seeds *out, int64_t *n_interior, vc_error *err);

#ifdef __cplusplus
}
#endif
#endif
