/* The reconstructed surface: the Voronoi facets between an inside and an
 * outside seed, taken from the conforming Voronoi mesh of the inside
 * seeds (the outside seeds are its non-kept seeds), so the facets share
 * the mesh's global vertices.
 *
 * T-junction repair: all the seeds of the triplets sharing a pair of balls
 * lie on one circle, so the surface edge between the two ball centres is a
 * degenerate Voronoi edge of four or more cells, and rounding can leave a
 * vertex on it in the facets of one side only (a facet walks a -> b while
 * the other side walks b -> c -> a with c on the segment ab). Such vertices
 * are inserted into the facet that misses them. The engine's own handling
 * of that degeneracy is the real fix (see the README's limitations). */
#include "vorocrust/sampling.h"
#include "vorocrust/voronoi.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct dedge {
    int64_t a, b;
} dedge;

static int cmp_dedge(const void *p, const void *q)
{
    const dedge *x = p, *y = q;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    return (x->b > y->b) - (x->b < y->b);
}

static int has_edge(const dedge *e, int64_t n, int64_t a, int64_t b)
{
    dedge k = {a, b};
    return bsearch(&k, e, (size_t)n, sizeof(dedge), cmp_dedge) != NULL;
}

/* Position of t along a -> b (0..1) when p lies on the open segment within
 * a relative tolerance, else -1. */
static double on_segment(const double *pa, const double *pb, const double *pc)
{
    double ab[3], ac[3], l2 = 0, t = 0;
    for (int d = 0; d < 3; d++) {
        ab[d] = pb[d] - pa[d];
        ac[d] = pc[d] - pa[d];
        l2 += ab[d] * ab[d];
        t += ab[d] * ac[d];
    }
    if (!(l2 > 0))
        return -1;
    t /= l2;
    if (!(t > 1e-9 && t < 1 - 1e-9))
        return -1;
    double perp2 = 0;
    for (int d = 0; d < 3; d++) {
        double x = ac[d] - t * ab[d];
        perp2 += x * x;
    }
    return perp2 <= 1e-18 * l2 ? t : -1;
}

/* Inserts, into every facet edge a -> b without a twin b -> a, the chain
 * b -> c1 -> ... -> a of unmatched edges through vertices on the segment.
 * Returns the number of vertices inserted, or -1 when out of memory. */
static int64_t repair_t_junctions(vc_polysurface *p)
{
    int64_t ne = p->poly_offsets[p->n_polys];
    dedge *e = malloc(sizeof(dedge) * (size_t)(ne ? ne : 1));
    if (!e)
        return -1;
    for (int64_t f = 0, m = 0; f < p->n_polys; f++) {
        int64_t s0 = p->poly_offsets[f], n = p->poly_offsets[f + 1] - s0;
        for (int64_t i = 0; i < n; i++, m++) {
            e[m].a = p->poly_vertices[s0 + i];
            e[m].b = p->poly_vertices[s0 + (i + 1) % n];
        }
    }
    qsort(e, (size_t)ne, sizeof(dedge), cmp_dedge);
    /* the unmatched edges, sorted */
    dedge *u = malloc(sizeof(dedge) * (size_t)(ne ? ne : 1));
    if (!u) {
        free(e);
        return -1;
    }
    int64_t nu = 0;
    for (int64_t i = 0; i < ne; i++)
        if (!has_edge(e, ne, e[i].b, e[i].a))
            u[nu++] = e[i];
    free(e);
    if (nu == 0) {
        free(u);
        return 0;
    }
    int64_t cap = ne + nu + 1, k = 0, inserted = 0;
    int64_t *nv = malloc(sizeof(int64_t) * (size_t)cap);
    int64_t *noff = malloc(sizeof(int64_t) * (size_t)(p->n_polys + 1));
    if (!nv || !noff) {
        free(u);
        free(nv);
        free(noff);
        return -1;
    }
    enum { MAX_CHAIN = 8 };
    noff[0] = 0;
    for (int64_t f = 0; f < p->n_polys; f++) {
        int64_t s0 = p->poly_offsets[f], n = p->poly_offsets[f + 1] - s0;
        for (int64_t i = 0; i < n; i++) {
            int64_t a = p->poly_vertices[s0 + i], b = p->poly_vertices[s0 + (i + 1) % n];
            nv[k++] = a;
            if (!has_edge(u, nu, a, b))
                continue;
            /* follow unmatched edges from b back to a along the segment */
            int64_t chain[MAX_CHAIN];
            int len = 0, closed = 0;
            int64_t cur = b;
            while (len < MAX_CHAIN && !closed) {
                dedge key = {cur, INT64_MIN};
                int64_t lo = 0, hi = nu;
                while (lo < hi) { /* first unmatched edge leaving cur */
                    int64_t mid = (lo + hi) / 2;
                    if (cmp_dedge(&u[mid], &key) < 0)
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                int64_t next = -1;
                for (int64_t j = lo; j < nu && u[j].a == cur; j++) {
                    if (u[j].b == a) {
                        closed = 1;
                        break;
                    }
                    if (next < 0 && on_segment(p->points + 3 * a, p->points + 3 * b,
                                               p->points + 3 * u[j].b) >= 0)
                        next = u[j].b;
                }
                if (closed || next < 0)
                    break;
                chain[len++] = next;
                cur = next;
            }
            if (!closed || len == 0)
                continue;
            if (k + len + (n - i) > cap)
                continue; /* cannot happen: each unmatched edge serves one facet */
            for (int c = len - 1; c >= 0; c--)
                nv[k++] = chain[c];
            inserted += len;
        }
        noff[f + 1] = k;
    }
    free(u);
    if (inserted == 0) {
        free(nv);
        free(noff);
        return 0;
    }
    free(p->poly_vertices);
    free(p->poly_offsets);
    p->poly_vertices = nv;
    p->poly_offsets = noff;
    return inserted;
}

void vc_polysurface_free(vc_polysurface *p)
{
    free(p->points);
    free(p->poly_offsets);
    free(p->poly_vertices);
    memset(p, 0, sizeof *p);
}

int vc_reconstruct_surface(const vc_seeds *seeds, int threads, vc_polysurface *out,
                           int64_t *n_repaired, vc_error *err)
{
    if (n_repaired)
        *n_repaired = 0;
    memset(out, 0, sizeof *out);
    vc_voronoi_options vo;
    vc_voronoi_options_default(&vo);
    vo.threads = threads;
    vc_polymesh m;
    int rc = vc_voronoi_build(seeds, &vo, &m, err);
    if (rc)
        return rc;
    int64_t nf = 0, nfv = 0;
    for (int64_t f = m.n_interior_faces; f < m.n_faces; f++)
        if (m.face_other_seed[f] >= 0) {
            nf++;
            nfv += m.face_offsets[f + 1] - m.face_offsets[f];
        }
    int64_t *newid = malloc(sizeof(int64_t) * (size_t)(m.n_points ? m.n_points : 1));
    out->poly_offsets = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    out->poly_vertices = malloc(sizeof(int64_t) * (size_t)(nfv ? nfv : 1));
    if (!newid || !out->poly_offsets || !out->poly_vertices) {
        free(newid);
        vc_polysurface_free(out);
        vc_polymesh_free(&m);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the reconstructed surface");
    }
    for (int64_t i = 0; i < m.n_points; i++)
        newid[i] = -1;
    int64_t np = 0, k = 0, q = 0;
    out->poly_offsets[0] = 0;
    for (int64_t f = m.n_interior_faces; f < m.n_faces; f++) {
        if (m.face_other_seed[f] < 0)
            continue;
        for (int64_t j = m.face_offsets[f]; j < m.face_offsets[f + 1]; j++) {
            int64_t v = m.face_vertices[j];
            if (newid[v] < 0)
                newid[v] = np++;
            out->poly_vertices[k++] = newid[v];
        }
        out->poly_offsets[++q] = k;
    }
    out->n_polys = nf;
    out->n_points = np;
    out->points = malloc(sizeof(double) * 3 * (size_t)(np ? np : 1));
    if (!out->points) {
        free(newid);
        vc_polysurface_free(out);
        vc_polymesh_free(&m);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the reconstructed surface");
    }
    for (int64_t i = 0; i < m.n_points; i++)
        if (newid[i] >= 0)
            memcpy(out->points + 3 * newid[i], m.points + 3 * i, sizeof(double) * 3);
    free(newid);
    vc_polymesh_free(&m);
    int64_t rep = repair_t_junctions(out);
    if (rep < 0) {
        vc_polysurface_free(out);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the reconstructed surface");
    }
    if (n_repaired)
        *n_repaired = rep;
    return 0;
}
