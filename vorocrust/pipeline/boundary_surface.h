/* The boundary faces of a volume mesh as a surface (internal to
 * vorocrust/pipeline). */
#ifndef VC_PIPELINE_BOUNDARY_SURFACE_H
#define VC_PIPELINE_BOUNDARY_SURFACE_H

#include "vorocrust/polymesh.h"
#include "vorocrust/sampling.h"

/* The boundary faces of m (those with no neighbour), oriented out of their
 * cells as m stores them, over the points they use (renumbered in order of
 * first use). Returns 0, or -1 when out of memory (out is then empty). */
int vc_polymesh_boundary_surface(const vc_polymesh *m, vc_polysurface *out);

#endif
