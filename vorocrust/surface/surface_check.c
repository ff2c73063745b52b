/* Topology and geometry checks of a triangle surface: edges (boundary,
 * non-manifold, orientation), components, Euler characteristic, genus,
 * degenerate triangles, bounding box and enclosed volume. */
#include "vorocrust/surface.h"
#include "util/bucket_sort.h"
#include "util/small_sort.h"
#include "util/union_find.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct edge_use {
    int64_t a, b; /* a < b */
    int64_t hd;   /* 2 h + dir: the triangle side h = 3 t + j, dir 1 when it walks a -> b */
} edge_use;

/* (a, b, hd): distinct records, so the order is the same for any sort */
#define EDGE_USE_LESS(p, q)                                                                      \
    ((p)->a < (q)->a || ((p)->a == (q)->a && ((p)->b < (q)->b || ((p)->b == (q)->b && (p)->hd < (q)->hd))))
VC_SMALL_SORT(sort_edge_uses, edge_use, EDGE_USE_LESS)
#define EDGE_USE_KEY(p) ((p)->a)
VC_BUCKET_SORT(bucket_sort_edge_uses, edge_use, EDGE_USE_KEY, EDGE_USE_LESS, sort_edge_uses)

int vc_surface_check(const vc_surface *s, vc_surface_report *rep, vc_error *err)
{
    const char *name = rep->name[0] ? rep->name : "surface";
    int64_t nv = s->n_vertices, nt = s->n_triangles;
    rep->n_vertices = nv;
    rep->n_triangles = nt;
    if (nt <= 0)
        return vc_error_set(err, VC_EINPUT, "%s: no triangles", name);
    for (int64_t i = 0; i < 3 * nv; i++)
        if (!isfinite(s->xyz[i]))
            return vc_error_set(err, VC_EINPUT, "%s: vertex %lld has a non-finite coordinate (%g)",
                                name, (long long)(i / 3 + 1), s->xyz[i]);
    for (int64_t k = 0; k < 3 * nt; k++)
        if (s->tri[k] < 0 || s->tri[k] >= nv)
            return vc_error_set(err, VC_EINPUT, "%s: triangle %lld refers to vertex %lld of %lld",
                                name, (long long)(k / 3 + 1), (long long)s->tri[k] + 1, (long long)nv);

    /* Bounding box. */
    double *bb = rep->bbox;
    for (int k = 0; k < 3; k++) {
        bb[k] = nv ? s->xyz[k] : 0;
        bb[k + 3] = bb[k];
    }
    for (int64_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            double x = s->xyz[3 * i + k];
            if (x < bb[k])
                bb[k] = x;
            if (x > bb[k + 3])
                bb[k + 3] = x;
        }
    /* Differences are scaled by sc = 2^-escale, the box's largest extent
     * being about 2^escale: exact, and the products below then neither overflow nor
     * underflow for models from 1e-300 to 1e300 (the verdicts are
     * scale-free). */
    double emax = 0;
    for (int k = 0; k < 3; k++)
        emax = fmax(emax, bb[k + 3] - bb[k]);
    int escale = 0;
    if (emax > 0 && isfinite(emax))
        frexp(emax, &escale);
    const double sc = ldexp(1.0, -escale);

    /* Degenerate triangles. */
    int64_t degenerate = 0;
    for (int64_t t = 0; t < nt; t++) {
        const double *p[3];
        for (int j = 0; j < 3; j++)
            p[j] = s->xyz + 3 * s->tri[3 * t + j];
        double u[3], v[3], w[3], lmax = 0;
        for (int k = 0; k < 3; k++) {
            u[k] = (p[1][k] - p[0][k]) * sc;
            v[k] = (p[2][k] - p[0][k]) * sc;
            w[k] = (p[2][k] - p[1][k]) * sc;
        }
        double lu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        double lv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        double lw = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        lmax = lu > lv ? lu : lv;
        lmax = lmax > lw ? lmax : lw;
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        double area2 = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (area2 <= 1e-12 * lmax)
            degenerate++;
    }
    rep->n_degenerate = degenerate;
    rep->signed_volume = vc_surface_signed_volume(s);
    rep->volume = fabs(rep->signed_volume);
    if (degenerate == nt)
        return vc_error_set(err, VC_EINPUT, "%s: all %lld triangles are degenerate (zero area)",
                            name, (long long)nt);

    /* Edges. */
    edge_use *e = malloc((size_t)nt * 3 * sizeof *e);
    int64_t *parent = malloc((size_t)(nv ? nv : 1) * sizeof *parent);
    if (!e || !parent) {
        free(e);
        free(parent);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory checking the surface", name);
    }
    for (int64_t t = 0; t < nt; t++)
        for (int j = 0; j < 3; j++) {
            int64_t a = s->tri[3 * t + j], b = s->tri[3 * t + (j + 1) % 3];
            edge_use *u = &e[3 * t + j];
            u->a = a < b ? a : b;
            u->b = a < b ? b : a;
            u->hd = 2 * (3 * t + j) + (a < b);
        }
    if (bucket_sort_edge_uses(e, 3 * nt, nv))
        sort_edge_uses(e, 3 * nt); /* no room for the copy: in place */
    int64_t n_edges = 0, boundary = 0, nonmanifold = 0, inconsistent = 0;
    for (int64_t k = 0; k < 3 * nt;) {
        int64_t j = k + 1;
        while (j < 3 * nt && e[j].a == e[k].a && e[j].b == e[k].b)
            j++;
        int64_t m = j - k;
        n_edges++;
        if (m == 1)
            boundary++;
        else if (m == 2)
            inconsistent += (e[k].hd & 1) == (e[k + 1].hd & 1);
        else
            nonmanifold++;
        k = j;
    }
    free(e);

    /* Components: vertices joined by triangles. */
    vc_uf_init(parent, nv);
    for (int64_t t = 0; t < nt; t++)
        for (int j = 1; j < 3; j++)
            vc_uf_unite(parent, s->tri[3 * t], s->tri[3 * t + j]);
    /* Vertices no triangle uses count as components of their own; after
     * vc_surface_merge_vertices there are none. */
    int64_t comps = vc_uf_count_roots(parent, nv);
    free(parent);

    rep->n_edges = n_edges;
    rep->n_boundary_edges = boundary;
    rep->n_nonmanifold_edges = nonmanifold;
    rep->n_inconsistent_edges = inconsistent;
    rep->n_components = comps;
    rep->euler = nv - n_edges + nt;
    rep->closed_manifold = boundary == 0 && nonmanifold == 0;
    rep->genus = -1;
    if (rep->closed_manifold && (2 * comps - rep->euler) % 2 == 0 && 2 * comps >= rep->euler)
        rep->genus = (2 * comps - rep->euler) / 2;

    if (degenerate)
        vc_surface_report_warn(rep, "%s: %lld degenerate (zero-area) triangles", name, (long long)degenerate);
    if (boundary)
        vc_surface_report_warn(rep, "%s: %lld open boundary edges (surface is not closed)", name,
                               (long long)boundary);
    if (nonmanifold)
        vc_surface_report_warn(rep, "%s: %lld non-manifold edges (shared by 3 or more triangles; kept)", name,
                               (long long)nonmanifold);
    if (inconsistent)
        vc_surface_report_warn(rep,
                               "%s: %lld inconsistently oriented edges (both triangles walk them the same way)",
                               name, (long long)inconsistent);
    if (!boundary && !inconsistent && rep->signed_volume < 0)
        vc_surface_report_warn(rep, "%s: enclosed volume is negative (%.6g): triangles are oriented inward",
                               name, rep->signed_volume);
    return 0;
}
