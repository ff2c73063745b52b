/* Surface and cell quality of vc_mesh's outputs (see mesh_measures.h). */
#include "mesh_measures.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/quality.h"

void vc_surface_quality_compute(const vc_polysurface *ps, vc_surface_quality *out)
{
    double qmin = INFINITY, qsum = 0;
    int64_t ntri = 0, nang = 0, below30 = 0, above90 = 0;
    for (int64_t k = 0; k < ps->n_polys; k++) {
        int64_t a = ps->poly_offsets[k], n = ps->poly_offsets[k + 1] - a;
        double c[3] = {0, 0, 0};
        for (int64_t j = 0; j < n; j++)
            for (int d = 0; d < 3; d++)
                c[d] += ps->points[3 * ps->poly_vertices[a + j] + d] / (double)n;
        int64_t fan = n == 3 ? 1 : n;
        for (int64_t j = 0; j < fan; j++) {
            const double *p0, *p1, *p2;
            if (n == 3) {
                p0 = ps->points + 3 * ps->poly_vertices[a];
                p1 = ps->points + 3 * ps->poly_vertices[a + 1];
                p2 = ps->points + 3 * ps->poly_vertices[a + 2];
            } else {
                p0 = c;
                p1 = ps->points + 3 * ps->poly_vertices[a + j];
                p2 = ps->points + 3 * ps->poly_vertices[a + (j + 1) % n];
            }
            double ang[3];
            double q = vc_triangle_quality(p0, p1, p2);
            vc_triangle_angles(p0, p1, p2, ang);
            qmin = fmin(qmin, q);
            qsum += q;
            ntri++;
            for (int m = 0; m < 3; m++) {
                nang++;
                below30 += ang[m] < 30;
                above90 += ang[m] > 90;
            }
        }
    }
    out->n_triangles = ntri;
    out->q_min = qmin;
    out->q_mean = ntri ? qsum / (double)ntri : 0;
    out->pct_below_30 = nang ? 100.0 * (double)below30 / (double)nang : 0;
    out->pct_above_90 = nang ? 100.0 * (double)above90 / (double)nang : 0;
}

double vc_polysurface_volume(const vc_polysurface *ps)
{
    double sv = 0;
    for (int64_t k = 0; k < ps->n_polys; k++) {
        int64_t a = ps->poly_offsets[k], n = ps->poly_offsets[k + 1] - a;
        const double *p0 = ps->points + 3 * ps->poly_vertices[a];
        for (int64_t j = 1; j + 1 < n; j++) {
            const double *p1 = ps->points + 3 * ps->poly_vertices[a + j];
            const double *p2 = ps->points + 3 * ps->poly_vertices[a + j + 1];
            sv += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) -
                   p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
                   p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) / 6;
        }
    }
    return sv;
}

/* Makes room for n elements of elem bytes in *p (capacity *cap). */
static int grow(void *pp, int64_t *cap, int64_t n, size_t elem)
{
    if (n <= *cap)
        return 0;
    int64_t c = 2 * n;
    void *q = realloc(*(void **)pp, elem * (size_t)c);
    if (!q)
        return -1;
    *(void **)pp = q;
    *cap = c;
    return 0;
}

/* The measures of cell c (an outward face list and the distinct vertices
 * gathered into the scratch arrays); 0, 1 when it cannot be measured, -1
 * when out of memory. */
static int measure_cell(const vc_polymesh *m, int64_t c, int64_t **foff, int64_t *cap_f,
                        int64_t **fv, int64_t *cap_v, int64_t **vs, int64_t *cap_s,
                        vc_cell_measures *cm, int *boundary)
{
    int64_t f0 = m->cell_offsets[c], f1 = m->cell_offsets[c + 1], nfv = 0, nf = f1 - f0;
    *boundary = 0;
    for (int64_t k = f0; k < f1; k++) {
        int64_t f = m->cell_faces[k];
        nfv += m->face_offsets[f + 1] - m->face_offsets[f];
        *boundary |= m->face_neighbour[f] < 0;
    }
    if (grow(foff, cap_f, nf + 1, sizeof **foff) || grow(fv, cap_v, nfv, sizeof **fv) ||
        grow(vs, cap_s, nfv, sizeof **vs))
        return -1;
    /* the cell's faces, oriented outward */
    int64_t n = 0;
    (*foff)[0] = 0;
    for (int64_t k = f0; k < f1; k++) {
        int64_t f = m->cell_faces[k], a = m->face_offsets[f], len = m->face_offsets[f + 1] - a;
        int rev = m->face_owner[f] != c;
        for (int64_t j = 0; j < len; j++)
            (*fv)[n + j] = m->face_vertices[a + (rev ? len - 1 - j : j)];
        n += len;
        (*foff)[k - f0 + 1] = n;
    }
    /* its distinct vertices */
    int64_t nv = 0;
    for (int64_t j = 0; j < n; j++) {
        int seen = 0;
        for (int64_t i = 0; i < nv && !seen; i++)
            seen = (*vs)[i] == (*fv)[j];
        if (!seen)
            (*vs)[nv++] = (*fv)[j];
    }
    vc_cell cell = {m->points, nv, *vs, nf, *foff, *fv};
    return vc_cell_measure(&cell, cm) != 0 || !isfinite(cm->fatness);
}

int vc_cell_quality_compute(const vc_polymesh *m, vc_cell_quality *q, double *fatness,
                            int threads)
{
    memset(q, 0, sizeof *q);
    q->volume_min = q->shortest_edge_rel_min = INFINITY;
    const int64_t n = m->n_cells;
    /* per cell: volume, fatness (NaN: not measured), shortest edge; boundary */
    double *per = malloc(sizeof(double) * 3 * (size_t)(n + 1));
    unsigned char *on_boundary = malloc((size_t)n + 1);
    int oom = !per || !on_boundary;
    /* each cell is measured on its own, in parallel; the sums below run in
     * cell order, so the figures do not depend on the thread count */
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads()) if (!oom)
    {
        int64_t cap_f = 0, cap_v = 0, cap_s = 0;
        int64_t *foff = NULL, *fv = NULL, *vs = NULL;
#pragma omp for schedule(dynamic, 256)
        for (int64_t c = 0; c < n; c++) {
            vc_cell_measures cm;
            memset(&cm, 0, sizeof cm);
            int boundary = 0;
            int r = measure_cell(m, c, &foff, &cap_f, &fv, &cap_v, &vs, &cap_s, &cm, &boundary);
            if (r < 0) {
#pragma omp atomic write
                oom = 1;
            }
            per[3 * c] = cm.volume;
            per[3 * c + 1] = r == 0 ? cm.fatness : NAN;
            per[3 * c + 2] = cm.shortest_edge_rel;
            on_boundary[c] = (unsigned char)boundary;
        }
        free(foff);
        free(fv);
        free(vs);
    }
    if (oom) {
        free(per);
        free(on_boundary);
        return VC_ENOMEM;
    }
    double fat_sum = 0, fat_int_sum = 0;
    for (int64_t c = 0; c < n; c++) {
        const double fat = per[3 * c + 1];
        if (fatness)
            fatness[c] = fat;
        if (isnan(fat)) {
            q->n_unmeasured++;
            continue;
        }
        q->n_measured++;
        q->volume_min = fmin(q->volume_min, per[3 * c]);
        q->volume_max = fmax(q->volume_max, per[3 * c]);
        q->fatness_max = fmax(q->fatness_max, fat);
        fat_sum += fat;
        q->shortest_edge_rel_min = fmin(q->shortest_edge_rel_min, per[3 * c + 2]);
        if (!on_boundary[c]) {
            q->n_interior++;
            q->interior_fatness_max = fmax(q->interior_fatness_max, fat);
            fat_int_sum += fat;
        }
    }
    q->fatness_mean = q->n_measured ? fat_sum / (double)q->n_measured : 0;
    q->interior_fatness_mean = q->n_interior ? fat_int_sum / (double)q->n_interior : 0;
    free(per);
    free(on_boundary);
    return 0;
}
