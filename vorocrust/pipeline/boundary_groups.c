/* The input group of every boundary face (see boundary_groups.h). */
#include "boundary_groups.h"

#include <stdlib.h>
#include <string.h>

#include "vorocrust/regions.h"
#include "util/threads.h"

int vc_mesh_boundary_groups(vc_polymesh *m, const vc_surface *s, const int32_t *tri_group,
                            int32_t n_groups, const char (*names)[64], int threads,
                            vc_error *err)
{
    vc_region_locator *L = NULL;
    int rc = vc_region_locator_build(s, NULL, &L, err);
    if (rc)
        return rc;
    free(m->face_group);
    free(m->group_name);
    m->face_group = malloc(sizeof(int32_t) * (size_t)(m->n_faces + 1));
    m->group_name = malloc(sizeof *m->group_name * (size_t)(n_groups + 1));
    if (!m->face_group || !m->group_name) {
        vc_region_locator_free(L);
        free(m->face_group);
        free(m->group_name);
        m->face_group = NULL;
        m->group_name = NULL;
        return vc_error_set(err, VC_ENOMEM, "out of memory for the boundary groups");
    }
    memcpy(m->group_name, names, sizeof *m->group_name * (size_t)n_groups);
    m->n_groups = n_groups;
    const int64_t ni = m->n_interior_faces;
    for (int64_t f = 0; f < ni; f++)
        m->face_group[f] = -1;
    const int nth = vc_threads_or_default(threads);
    (void)nth;
#pragma omp parallel for schedule(dynamic, 256) num_threads(nth)
    for (int64_t f = ni; f < m->n_faces; f++) {
        const int64_t o = m->face_other_seed ? m->face_other_seed[f] : -1;
        int32_t g = -1;
        if (o >= 0 && o < m->n_seeds) {
            double x[3];
            vc_polymesh_face_seed_point(m, f, x);
            const int64_t t = vc_region_locator_nearest(L, x);
            g = t >= 0 ? tri_group[t] : -1;
        }
        m->face_group[f] = g;
    }
    vc_region_locator_free(L);
    return 0;
}
