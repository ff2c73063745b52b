/* The boundary of a volume mesh as a polygonal surface: the surface the
 * mesh actually has, after the engine's own reconciliation of its cells,
 * so the surface written and checked is the one the cells bound. */
#include "boundary_surface.h"

#include <stdlib.h>
#include <string.h>

int vc_polymesh_boundary_surface(const vc_polymesh *m, vc_polysurface *out)
{
    memset(out, 0, sizeof *out);
    const int64_t nb = m->n_faces - m->n_interior_faces;
    const int64_t nv = m->face_offsets[m->n_faces] - m->face_offsets[m->n_interior_faces];
    int64_t *map = malloc(sizeof(int64_t) * (size_t)(m->n_points + 1));
    out->poly_offsets = malloc(sizeof(int64_t) * (size_t)(nb + 1));
    out->poly_vertices = malloc(sizeof(int64_t) * (size_t)(nv + 1));
    if (!map || !out->poly_offsets || !out->poly_vertices)
        goto oom;
    for (int64_t p = 0; p < m->n_points; p++)
        map[p] = -1;
    /* the points in the order the boundary faces first use them */
    int64_t np = 0, k = 0;
    out->poly_offsets[0] = 0;
    for (int64_t f = m->n_interior_faces; f < m->n_faces; f++) {
        for (int64_t j = m->face_offsets[f]; j < m->face_offsets[f + 1]; j++) {
            const int64_t p = m->face_vertices[j];
            if (map[p] < 0)
                map[p] = np++;
            out->poly_vertices[k++] = map[p];
        }
        out->poly_offsets[f - m->n_interior_faces + 1] = k;
    }
    out->points = malloc(sizeof(double) * 3 * (size_t)(np + 1));
    if (!out->points)
        goto oom;
    for (int64_t p = 0; p < m->n_points; p++)
        if (map[p] >= 0)
            memcpy(out->points + 3 * map[p], m->points + 3 * p, sizeof(double) * 3);
    out->n_points = np;
    out->n_polys = nb;
    free(map);
    return 0;
oom:
    free(map);
    vc_polysurface_free(out);
    return -1;
}
