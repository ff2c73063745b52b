/* The input group of every boundary face of the volume mesh: the boundary
 * patches (issue 21). */
#ifndef VC_PIPELINE_BOUNDARY_GROUPS_H
#define VC_PIPELINE_BOUNDARY_GROUPS_H

#include <stdint.h>

#include "vorocrust/polymesh.h"
#include "vorocrust/surface.h"

/* Sets m->face_group (and copies the n_groups names): each boundary face
 * takes the group of the input triangle nearest the point where the
 * segment between its two seeds crosses it (on the surface within the
 * sampling's error bound), tri_group[t] for triangle t of s. Returns 0 or
 * VC_ENOMEM. */
int vc_mesh_boundary_groups(vc_polymesh *m, const vc_surface *s, const int32_t *tri_group,
                            int32_t n_groups, const char (*names)[64], int threads,
                            vc_error *err);

#endif
