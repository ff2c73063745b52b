/* Memory, geometry and summary figures of the polyhedral mesh. */
#include "vorocrust/polymesh.h"
#include "face_geometry.h"
#include "polymesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vc_polymesh_free(vc_polymesh *m)
{
    if (!m)
        return;
    free(m->points);
    free(m->face_offsets);
    free(m->face_vertices);
    free(m->face_owner);
    free(m->face_neighbour);
    free(m->face_other_seed);
    free(m->face_group);
    free(m->group_name);
    free(m->face_area);
    free(m->face_centroid);
    free(m->face_normal);
    free(m->cell_offsets);
    free(m->cell_faces);
    free(m->cell_seed);
    free(m->cell_region);
    free(m->cell_volume);
    free(m->cell_fatness);
    free(m->cell_centroid);
    free(m->seed_xyz);
    memset(m, 0, sizeof *m);
}

void vc_polymesh_update_face_geometry(vc_polymesh *m, int64_t f)
{
    vc_face_geometry_set(m, f, m->face_vertices + m->face_offsets[f], vc_polymesh_face_size(m, f));
}

void vc_polymesh_update_cell_geometry(vc_polymesh *m, int64_t c)
{
    /* Pyramids from a reference point inside the cell (the average of the
     * face centroids) to every face, with outward area vectors. */
    int64_t f0 = m->cell_offsets[c], f1 = m->cell_offsets[c + 1];
    double ref[3] = {0, 0, 0};
    for (int64_t i = f0; i < f1; i++)
        for (int d = 0; d < 3; d++)
            ref[d] += m->face_centroid[3 * m->cell_faces[i] + d];
    for (int d = 0; d < 3; d++)
        ref[d] /= (double)(f1 > f0 ? f1 - f0 : 1);
    double vol = 0, cen[3] = {0, 0, 0};
    for (int64_t i = f0; i < f1; i++) {
        int64_t f = m->cell_faces[i];
        double sgn = m->face_owner[f] == c ? 1.0 : -1.0;
        const double *fc = m->face_centroid + 3 * f, *n = m->face_normal + 3 * f;
        double h = (fc[0] - ref[0]) * n[0] + (fc[1] - ref[1]) * n[1] + (fc[2] - ref[2]) * n[2];
        /* Three times the pyramid's volume: divided once, below. */
        double pv = sgn * h * m->face_area[f];
        vol += pv;
        for (int d = 0; d < 3; d++)
            cen[d] += pv * (ref[d] + 0.75 * (fc[d] - ref[d]));
    }
    m->cell_volume[c] = vol / 3.0;
    for (int d = 0; d < 3; d++)
        m->cell_centroid[3 * c + d] = vol != 0 ? cen[d] / vol : ref[d];
}

void vc_polymesh_compute_geometry(vc_polymesh *m)
{
#pragma omp parallel for schedule(static)
    for (int64_t f = 0; f < m->n_faces; f++)
        vc_polymesh_update_face_geometry(m, f);
#pragma omp parallel for schedule(static)
    for (int64_t c = 0; c < m->n_cells; c++)
        vc_polymesh_update_cell_geometry(m, c);
}

double vc_polymesh_face_seed_distance(const vc_polymesh *m, int64_t f)
{
    if (m->face_neighbour[f] < 0 || !m->seed_xyz)
        return 0;
    const double *a = m->seed_xyz + 3 * m->cell_seed[m->face_owner[f]];
    const double *b = m->seed_xyz + 3 * m->cell_seed[m->face_neighbour[f]];
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

void vc_polymesh_stats_compute(const vc_polymesh *m, vc_polymesh_stats *st)
{
    memset(st, 0, sizeof *st);
    st->volume_min = INFINITY;
    st->volume_max = -INFINITY;
    for (int64_t c = 0; c < m->n_cells; c++) {
        double v = m->cell_volume[c];
        st->volume_total += v;
        if (v < st->volume_min)
            st->volume_min = v;
        if (v > st->volume_max)
            st->volume_max = v;
        double nf = (double)(m->cell_offsets[c + 1] - m->cell_offsets[c]);
        if (nf > st->max_faces_per_cell)
            st->max_faces_per_cell = nf;
        st->mean_faces_per_cell += nf;
    }
    if (m->n_cells > 0)
        st->mean_faces_per_cell /= (double)m->n_cells;
    else
        st->volume_min = st->volume_max = 0;
    st->n_boundary_faces = m->n_faces - m->n_interior_faces;
}
