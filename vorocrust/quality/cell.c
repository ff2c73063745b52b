/* Volume, centroid and the combined measures of a convex cell. */
#include "vorocrust/quality.h"

#include <math.h>
#include <stdlib.h>

#include "quality/quality_internal.h"
#include "quality/vec3.h"

double vc_cell_volume(const vc_cell *cell, double centroid[3])
{
    const double *P = cell->points;
    int64_t nf = cell->n_faces;
    /* Reference point: the first vertex, so the tetrahedra are small and
     * far-from-origin cells lose no digits. */
    const double *r = nf > 0 && cell->face_offsets[nf] > cell->face_offsets[0]
                          ? P + 3 * cell->face_vertices[cell->face_offsets[0]]
                          : NULL;
    double vol6 = 0, acc[3] = {0, 0, 0};
    for (int64_t f = 0; r && f < nf; f++) {
        int64_t b = cell->face_offsets[f], e = cell->face_offsets[f + 1];
        if (e - b < 3)
            continue;
        /* Fan from the face's vertex average: exact for planar faces,
         * watertight for warped ones. */
        double c[3] = {0, 0, 0};
        for (int64_t k = b; k < e; k++)
            for (int d = 0; d < 3; d++)
                c[d] += P[3 * cell->face_vertices[k] + d];
        for (int d = 0; d < 3; d++)
            c[d] = c[d] / (double)(e - b) - r[d];
        for (int64_t k = b; k < e; k++) {
            const double *p = P + 3 * cell->face_vertices[k];
            const double *q = P + 3 * cell->face_vertices[k + 1 < e ? k + 1 : b];
            double u[3], v[3], x[3];
            v3_sub(p, r, u);
            v3_sub(q, r, v);
            v3_cross(u, v, x);
            double t6 = v3_dot(c, x); /* 6 x the signed volume of (r, c, p, q) */
            vol6 += t6;
            for (int d = 0; d < 3; d++)
                acc[d] += t6 * (c[d] + u[d] + v[d]); /* tetra centroid = r + sum / 4 */
        }
    }
    if (centroid) {
        for (int d = 0; d < 3; d++)
            centroid[d] = vol6 != 0 ? r[d] + acc[d] / (4.0 * vol6) : (r ? r[d] : NAN);
    }
    return vol6 / 6.0;
}

int vc_cell_measure(const vc_cell *cell, vc_cell_measures *out)
{
    double vol = vc_cell_volume(cell, out->centroid);
    out->signed_volume = vol;
    out->volume = fabs(vol);
    int rc;
    if (cell->vertices)
        rc = vc_min_enclosing_ball(cell->n_vertices, cell->points, cell->vertices,
                                   &out->enclosing);
    else
        rc = vc_min_enclosing_ball(cell->face_offsets[cell->n_faces] - cell->face_offsets[0],
                                   cell->points, cell->face_vertices + cell->face_offsets[0],
                                   &out->enclosing);
    if (rc)
        return rc;
    rc = vc_max_inscribed_ball_oriented(cell, vol < 0 ? -1.0 : 1.0, &out->inscribed);
    if (rc)
        return rc;
    out->fatness = out->inscribed.radius > 0 ? out->enclosing.radius / out->inscribed.radius
                                             : INFINITY;
    double shortest2 = INFINITY;
    for (int64_t f = 0; f < cell->n_faces; f++) {
        int64_t b = cell->face_offsets[f], e = cell->face_offsets[f + 1];
        for (int64_t k = b; k < e; k++) {
            const double *p = cell->points + 3 * cell->face_vertices[k];
            const double *q = cell->points + 3 * cell->face_vertices[k + 1 < e ? k + 1 : b];
            shortest2 = dmin(shortest2, v3_dist2(p, q));
        }
    }
    out->shortest_edge = sqrt(shortest2);
    out->shortest_edge_rel = out->enclosing.radius > 0 ? out->shortest_edge / out->enclosing.radius
                                                       : 0.0;
    return VC_OK;
}
