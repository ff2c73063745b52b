/* Ball count predicted from the sizing (see ball_estimate.h). */
#include "ball_estimate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* balls per unit area of radius bound r is PATCH_DENSITY / r^2, per unit
 * length of crease CREASE_DENSITY / r: random maximal packings (2D
 * packing fraction 0.547, 1D 0.748) at spacing (1 - alpha) r = 0.866 r */
#define PATCH_DENSITY 0.93
#define CREASE_DENSITY 0.86
/* At most about this many triangles (and sharp edges) are evaluated: on a
 * fine surface every k-th of them in file order, weighted by the area
 * (length) of all over that of the ones evaluated. A radius bound costs a
 * tree walk over the elements it may reach, which for the large balls of
 * a fine, smooth surface is thousands: evaluating all 301,052 triangles of
 * fertility.off smoothed took 10 s on 2 threads, longer than sampling, and
 * 16,384 of the 197,996 of a marching-cubes blob 1 s. 4,096 predict within
 * 5% of 16,384 (blobby, genus3, bumpy-cube, fandisk), well inside what the
 * prediction is for: refusing absurd work and sizing the progress lines. */
#define MAX_EVALUATED 4096

int vc_ball_estimate_compute(const vc_sizing *z, double sz, int threads, vc_ball_estimate *out)
{
    const vc_surface *s = z->s;
    const vc_features *f = z->f;
    memset(out, 0, sizeof *out);
    const int64_t nt = s->n_triangles, ne = f->n_edges;
    double *tri_n = malloc(sizeof(double) * (size_t)(nt > 0 ? nt : 1));
    double *tri_r = malloc(sizeof(double) * (size_t)(nt > 0 ? nt : 1));
    double *edge_n = malloc(sizeof(double) * (size_t)(ne > 0 ? ne : 1));
    double *edge_r = malloc(sizeof(double) * (size_t)(ne > 0 ? ne : 1));
    int64_t *edge_rank = malloc(sizeof(int64_t) * (size_t)(ne > 0 ? ne : 1)); /* among sharp edges */
    if (!tri_n || !tri_r || !edge_n || !edge_r || !edge_rank) {
        free(tri_n);
        free(tri_r);
        free(edge_n);
        free(edge_r);
        free(edge_rank);
        return -1;
    }
    int64_t n_sharp = 0;
    for (int64_t e = 0; e < ne; e++)
        edge_rank[e] = f->edge_sharp[e] ? n_sharp++ : -1;
    const int64_t tri_stride = nt > MAX_EVALUATED ? (nt + MAX_EVALUATED - 1) / MAX_EVALUATED : 1;
    const int64_t edge_stride = n_sharp > MAX_EVALUATED ? (n_sharp + MAX_EVALUATED - 1) / MAX_EVALUATED : 1;
    for (int64_t t = 0; t < nt; t++) {
        tri_n[t] = 0;
        tri_r[t] = INFINITY;
    }
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads > 0 ? threads : 1)
    for (int64_t t = 0; t < nt; t++) {
        if (t % tri_stride != 0)
            continue;
        const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                     *c = s->xyz + 3 * s->tri[3 * t + 2];
        double x[3], u[3], w[3];
        for (int d = 0; d < 3; d++) {
            x[d] = (a[d] + b[d] + c[d]) / 3;
            u[d] = b[d] - a[d];
            w[d] = c[d] - a[d];
        }
        const double cx = u[1] * w[2] - u[2] * w[1], cy = u[2] * w[0] - u[0] * w[2],
                     cz = u[0] * w[1] - u[1] * w[0];
        const double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        vc_surface_point sp = {VC_ELEM_TRIANGLE, t};
        const double r = vc_sizing_radius_bound(z, &sp, x, sz);
        tri_r[t] = r;
        tri_n[t] = area > 0 ? (r > 0 ? PATCH_DENSITY * area / (r * r) : INFINITY) : 0;
    }
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads > 0 ? threads : 1)
    for (int64_t e = 0; e < ne; e++) {
        edge_n[e] = 0;
        edge_r[e] = INFINITY;
        if (!f->edge_sharp[e] || (edge_stride > 1 && edge_rank[e] % edge_stride != 0))
            continue;
        const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
        const double x[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
        const double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                (b[2] - a[2]) * (b[2] - a[2]));
        vc_surface_point sp = {VC_ELEM_EDGE, e};
        const double r = vc_sizing_radius_bound(z, &sp, x, sz);
        edge_r[e] = r;
        edge_n[e] = r > 0 ? CREASE_DENSITY * len / r : INFINITY;
    }
    /* the evaluated ones stand for all: weights by area and length */
    double area_all = 0, area_eval = 0, len_all = 0, len_eval = 0;
    for (int64_t t = 0; t < nt; t++) {
        const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                     *c = s->xyz + 3 * s->tri[3 * t + 2];
        double u[3], w[3];
        for (int d = 0; d < 3; d++) {
            u[d] = b[d] - a[d];
            w[d] = c[d] - a[d];
        }
        const double cx = u[1] * w[2] - u[2] * w[1], cy = u[2] * w[0] - u[0] * w[2],
                     cz = u[0] * w[1] - u[1] * w[0];
        const double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        area_all += area;
        if (t % tri_stride == 0)
            area_eval += area;
    }
    for (int64_t e = 0; e < ne; e++) {
        if (!f->edge_sharp[e])
            continue;
        const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
        const double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                (b[2] - a[2]) * (b[2] - a[2]));
        len_all += len;
        if (edge_stride == 1 || edge_rank[e] % edge_stride == 0)
            len_eval += len;
    }
    const double tri_weight = tri_stride > 1 && area_eval > 0 ? area_all / area_eval : 1;
    const double edge_weight = edge_stride > 1 && len_eval > 0 ? len_all / len_eval : 1;
    /* summed in index order: the same figure for any thread count */
    double n = 0, r_min = INFINITY;
    int64_t at_tri = -1, at_edge = -1;
    double n_tri = 0, n_edge = 0;
    for (int64_t t = 0; t < nt; t++) {
        n_tri += tri_n[t];
        if (tri_r[t] < r_min) {
            r_min = tri_r[t];
            at_tri = t;
        }
    }
    for (int64_t e = 0; e < ne; e++) {
        n_edge += edge_n[e];
        if (edge_r[e] < r_min) {
            r_min = edge_r[e];
            at_edge = e;
            at_tri = -1;
        }
    }
    n += tri_weight * n_tri + edge_weight * n_edge;
    for (int64_t v = 0; v < s->n_vertices; v++)
        n += f->vertex_corner[v] != 0;
    out->n_balls = n;
    out->r_min = r_min;
    const int64_t *vi = at_edge >= 0 ? f->edge_vertex + 2 * at_edge : at_tri >= 0 ? s->tri + 3 * at_tri : NULL;
    const int nv = at_edge >= 0 ? 2 : 3;
    for (int k = 0; vi && k < nv; k++)
        for (int d = 0; d < 3; d++)
            out->r_min_at[d] += s->xyz[3 * vi[k] + d] / nv;
    free(tri_n);
    free(tri_r);
    free(edge_n);
    free(edge_r);
    free(edge_rank);
    return 0;
}
