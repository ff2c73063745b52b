/* Surface and cell quality of vc_mesh's outputs (see mesh_measures.h). */
#include "mesh_measures.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "util/reserve.h"
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

/* The measures of cell c (an outward face list and the distinct vertices
 * gathered into the scratch arrays); 0, 1 when it cannot be measured, -1
 * when out of memory. */
static int measure_cell(const vc_polymesh *m, int64_t c, int64_t **foff, int64_t *cap_f,
                        int64_t **fv, int64_t *cap_v, int64_t **vs, int64_t *cap_s,
                        int64_t *seen_by, vc_cell_measures *cm, int *boundary)
{
    int64_t f0 = m->cell_offsets[c], f1 = m->cell_offsets[c + 1], nfv = 0, nf = f1 - f0;
    *boundary = 0;
    for (int64_t k = f0; k < f1; k++) {
        int64_t f = m->cell_faces[k];
        nfv += m->face_offsets[f + 1] - m->face_offsets[f];
        *boundary |= m->face_neighbour[f] < 0;
    }
    if (vc_reserve(foff, cap_f, nf + 1, sizeof **foff) || vc_reserve(fv, cap_v, nfv, sizeof **fv) ||
        vc_reserve(vs, cap_s, nfv, sizeof **vs))
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
    /* its distinct vertices, in order of first use (seen_by: per point,
     * the last cell of this thread that listed it; a pairwise search was
     * a fifth of the measures on VoroCrust cells of sixty face corners) */
    int64_t nv = 0;
    for (int64_t j = 0; j < n; j++) {
        const int64_t v = (*fv)[j];
        if (seen_by[v] != c) {
            seen_by[v] = c;
            (*vs)[nv++] = v;
        }
    }
    vc_cell cell = {m->points, nv, *vs, nf, *foff, *fv};
    return vc_cell_measure(&cell, cm) != 0 || !isfinite(cm->fatness);
}

/* A cell's shortest edge below this fraction of its enclosing radius
 * counts as short (issue 20's share). */
#define SHORT_EDGE 1e-2

/* The percentiles of the measured cells' columns and the interior faces'
 * measures; per holds 5 values per cell (see vc_cell_quality_compute).
 * The faces are measured in parallel into arrays, then reduced in face
 * order: the figures do not depend on the thread count. */
static int solver_measures(const vc_polymesh *m, const double *per, vc_cell_quality *q,
                           int threads)
{
    const int64_t n = m->n_cells, nf = m->n_interior_faces;
    double *col = malloc(sizeof(double) * (size_t)((n > nf ? n : nf) + 1));
    double *cosang = malloc(sizeof(double) * (size_t)(nf + 1));
    double *skew = malloc(sizeof(double) * (size_t)(nf + 1));
    if (!col || !cosang || !skew) {
        free(col);
        free(cosang);
        free(skew);
        return VC_ENOMEM;
    }
    vc_stats st;
    int rc = 0;
    for (int64_t c = 0; c < n; c++)
        col[c] = isnan(per[5 * c + 1]) ? NAN : per[5 * c + 2];
    rc |= vc_stats_compute(col, n, &st);
    q->shortest_edge_rel_p1 = st.p1;
    for (int64_t c = 0; c < n; c++)
        col[c] = per[5 * c + 3];
    rc |= vc_stats_compute(col, n, &st);
    q->small_face_rel_min = st.min;
    q->small_face_rel_p1 = st.p1;
    /* interior faces: the seeds' distance against the cells' size, and
     * checkMesh's angle between the face normal and the centroids' line
     * (cosine NaN where the centroids coincide) */
#pragma omp parallel for schedule(static) num_threads(threads > 0 ? threads : omp_get_max_threads())
    for (int64_t f = 0; f < nf; f++) {
        const int64_t o = m->face_owner[f], b = m->face_neighbour[f];
        const double ro = per[5 * o + 4], rb = per[5 * b + 4];
        col[f] = isnan(ro) || isnan(rb) || m->n_seeds == 0
                     ? NAN
                     : vc_polymesh_face_seed_distance(m, f) / (0.5 * (ro + rb));
        const double *co = m->cell_centroid + 3 * o, *cb = m->cell_centroid + 3 * b;
        const double *fn = m->face_normal + 3 * f;
        const double d[3] = {cb[0] - co[0], cb[1] - co[1], cb[2] - co[2]};
        const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        cosang[f] = len > 0 ? (d[0] * fn[0] + d[1] * fn[1] + d[2] * fn[2]) / len : NAN;
        skew[f] = vc_polymesh_face_skewness(m, f);
    }
    double no_sum = 0, cos_min = INFINITY;
    int64_t no_n = 0;
    q->skewness_max = 0;
    q->n_skew_faces = 0;
    for (int64_t f = 0; f < nf; f++) {
        if (!isnan(cosang[f])) {
            cos_min = fmin(cos_min, cosang[f]);
            no_sum += fmin(1.0, cosang[f]);
            no_n++;
        }
        q->skewness_max = fmax(q->skewness_max, skew[f]);
        q->n_skew_faces += skew[f] > 4;
    }
    /* the largest angle is that of the least cosine (acos decreases) */
    q->non_orthogonality_max =
        no_n ? acos(fmax(-1.0, fmin(1.0, cos_min))) * (180.0 / 3.14159265358979323846) : 0;
    /* checkMesh's "average": the angle of the mean cosine */
    q->non_orthogonality_mean =
        no_n ? acos(fmax(-1.0, fmin(1.0, no_sum / (double)no_n))) * (180.0 / 3.14159265358979323846)
             : 0;
    rc |= vc_stats_compute(col, nf, &st);
    q->connection_rel_min = st.min;
    q->connection_rel_p1 = st.p1;
    free(col);
    free(cosang);
    free(skew);
    return rc ? VC_ENOMEM : 0;
}

int vc_cell_quality_compute(const vc_polymesh *m, vc_cell_quality *q, double *fatness,
                            int threads)
{
    memset(q, 0, sizeof *q);
    q->volume_min = q->shortest_edge_rel_min = INFINITY;
    const int64_t n = m->n_cells;
    /* per cell: volume, fatness (NaN: not measured), shortest edge, smallest
     * face over the enclosing radius squared, enclosing radius; boundary */
    double *per = malloc(sizeof(double) * 5 * (size_t)(n + 1));
    unsigned char *on_boundary = malloc((size_t)n + 1);
    int oom = !per || !on_boundary;
    /* each cell is measured on its own, in parallel; the sums below run in
     * cell order, so the figures do not depend on the thread count */
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads()) if (!oom)
    {
        int64_t cap_f = 0, cap_v = 0, cap_s = 0;
        int64_t *foff = NULL, *fv = NULL, *vs = NULL;
        int64_t *seen_by = malloc(sizeof(int64_t) * (size_t)(m->n_points + 1));
        if (!seen_by) {
#pragma omp atomic write
            oom = 1;
        }
        for (int64_t v = 0; seen_by && v < m->n_points; v++)
            seen_by[v] = -1;
#pragma omp for schedule(dynamic, 256)
        for (int64_t c = 0; c < n; c++) {
            vc_cell_measures cm;
            memset(&cm, 0, sizeof cm);
            int boundary = 0;
            int r = seen_by ? measure_cell(m, c, &foff, &cap_f, &fv, &cap_v, &vs, &cap_s, seen_by,
                                           &cm, &boundary)
                            : -1;
            if (r < 0) {
#pragma omp atomic write
                oom = 1;
            }
            double small = INFINITY;
            for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; k++)
                small = fmin(small, m->face_area[m->cell_faces[k]]);
            const double rr = cm.enclosing.radius;
            per[5 * c] = cm.volume;
            per[5 * c + 1] = r == 0 ? cm.fatness : NAN;
            per[5 * c + 2] = cm.shortest_edge_rel;
            per[5 * c + 3] = r == 0 && rr > 0 ? small / (rr * rr) : NAN;
            per[5 * c + 4] = r == 0 ? rr : NAN;
            on_boundary[c] = (unsigned char)boundary;
        }
        free(foff);
        free(fv);
        free(vs);
        free(seen_by);
    }
    if (oom) {
        free(per);
        free(on_boundary);
        return VC_ENOMEM;
    }
    double fat_sum = 0, fat_int_sum = 0;
    int64_t n_short = 0;
    for (int64_t c = 0; c < n; c++) {
        const double fat = per[5 * c + 1];
        if (fatness)
            fatness[c] = fat;
        if (isnan(fat)) {
            q->n_unmeasured++;
            continue;
        }
        q->n_measured++;
        q->volume_min = fmin(q->volume_min, per[5 * c]);
        q->volume_max = fmax(q->volume_max, per[5 * c]);
        q->fatness_max = fmax(q->fatness_max, fat);
        fat_sum += fat;
        q->shortest_edge_rel_min = fmin(q->shortest_edge_rel_min, per[5 * c + 2]);
        n_short += per[5 * c + 2] < SHORT_EDGE;
        if (!on_boundary[c]) {
            q->n_interior++;
            q->interior_fatness_max = fmax(q->interior_fatness_max, fat);
            fat_int_sum += fat;
        }
    }
    q->fatness_mean = q->n_measured ? fat_sum / (double)q->n_measured : 0;
    q->interior_fatness_mean = q->n_interior ? fat_int_sum / (double)q->n_interior : 0;
    q->short_edge_share = q->n_measured ? (double)n_short / (double)q->n_measured : 0;
    int rc = solver_measures(m, per, q, threads);
    free(per);
    free(on_boundary);
    return rc;
}
