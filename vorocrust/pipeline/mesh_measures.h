/* The figures vc_mesh reports about its outputs (internal to
 * vorocrust/pipeline). */
#ifndef VC_PIPELINE_MESH_MEASURES_H
#define VC_PIPELINE_MESH_MEASURES_H

#include "vorocrust/vorocrust.h"

/* Triangle quality and angles of the polygons of p, fanned from their
 * centroid (triangles as they are). */
void vc_surface_quality_compute(const vc_polysurface *p, vc_surface_quality *q);

/* Volume enclosed by p, its polygons fanned from their first vertex. */
double vc_polysurface_volume(const vc_polysurface *p);

/* Cell quality of m; fatness (n_cells values, NaN where a cell cannot be
 * measured) may be NULL. threads <= 0: OpenMP's default. The same figures
 * for any thread count. Returns 0 or VC_ENOMEM. */
int vc_cell_quality_compute(const vc_polymesh *m, vc_cell_quality *q, double *fatness,
                            int threads);

#endif
