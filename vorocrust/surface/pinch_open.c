/* Pinch vertices (vc_surface_open_pinches).
 *
 * A vertex whose triangles form several fans (cones that touch only at
 * their apex) is a pinch: the union of a self-intersecting input leaves one
 * where two of its intersection curves meet (cow.off: where its tail lies
 * on its rump). No ball sampling resolves a pinch: the balls near it must
 * stay below the gap between the two sheets, which goes to zero at the
 * apex, and where the sheets meet at a small angle that costs thousands of
 * balls (cow.off: 10,000 of its 53,761) and a reconstruction that keeps
 * the pinch. Opening it gives each fan its own copy of the vertex, moved
 * towards the centroid of its fan's ring by max_move (at most a quarter of
 * the distance to the nearest ring vertex): the cones part by about twice
 * that, and the surface moves by at most that much. Fans are the classes
 * of the vertex's triangles joined across the edges at the vertex; an edge
 * of more than two triangles joins them all (an interface or touching
 * parts, not a pinch). Serial and deterministic; the copies are appended
 * to the vertices in the order of the pinches and of their fans' first
 * triangles. */
#include "vorocrust/surface.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/csr_group.h"
#include "util/union_find.h"

/* Vertex i: an input vertex, or a copy made so far (its triangles already
 * name it). */
static const double *vertex_at(const vc_surface *s, const double *moved, int64_t nv, int64_t i)
{
    return i < nv ? s->xyz + 3 * i : moved + 3 * (i - nv);
}

/* Do two of the vertex's fans meet at less than the angle of min_cos: an
 * edge of one within that angle of an edge of another (sheets that part
 * slowly from the apex)? */
static int fans_meet_within(const vc_surface *s, const double *moved, int64_t nv, const double *x,
                            const int64_t *link, int64_t *parent, int64_t deg, double min_cos)
{
    for (int64_t i = 0; i < deg; i++)
        for (int64_t j = 0; j < deg; j++) {
            if (vc_uf_find(parent, i) >= vc_uf_find(parent, j))
                continue;
            for (int a = 0; a < 2; a++)
                for (int b = 0; b < 2; b++) {
                    const double *p = vertex_at(s, moved, nv, link[2 * i + a]);
                    const double *q = vertex_at(s, moved, nv, link[2 * j + b]);
                    double u[3], w[3], uu = 0, ww = 0, uw = 0;
                    for (int k = 0; k < 3; k++) {
                        u[k] = p[k] - x[k];
                        w[k] = q[k] - x[k];
                        uu += u[k] * u[k];
                        ww += w[k] * w[k];
                        uw += u[k] * w[k];
                    }
                    if (uu > 0 && ww > 0 && uw > min_cos * sqrt(uu * ww))
                        return 1;
                }
        }
    return 0;
}

int vc_surface_open_pinches(vc_surface *s, double max_move, double min_cos, vc_pinch_report *rep,
                            vc_error *err)
{
    vc_pinch_report r = {0, 0, 0};
    if (rep)
        *rep = r;
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    if (!(max_move > 0) || nt == 0)
        return 0;
    /* vertex -> triangles (CSR) */
    int64_t *start, *inc;
    if (vc_csr_group(s->tri, nt, 3, nv, NULL, &start, &inc))
        return vc_error_set(err, VC_ENOMEM, "out of memory for the pinch vertices");
    int64_t max_deg = 0;
    for (int64_t v = 0; v < nv; v++)
        if (start[v + 1] - start[v] > max_deg)
            max_deg = start[v + 1] - start[v];
    /* per vertex scratch: the fan class of each incident triangle, and the
     * link vertices (two per triangle) */
    int64_t *parent = malloc(sizeof(int64_t) * (size_t)(max_deg + 1));
    int64_t *link = malloc(sizeof(int64_t) * (size_t)(2 * max_deg + 1));
    double *moved = NULL; /* the copies' positions, 3 each */
    int64_t n_new = 0, cap_new = 0;
    int rc = 0;
    if (!parent || !link) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the pinch vertices");
        goto done;
    }
    for (int64_t v = 0; v < nv && !rc; v++) {
        const int64_t b = start[v], deg = start[v + 1] - b;
        if (deg < 2)
            continue;
        vc_uf_init(parent, deg);
        for (int64_t i = 0; i < deg; i++) {
            const int64_t *T = s->tri + 3 * inc[b + i];
            const int k = T[0] == v ? 0 : T[1] == v ? 1 : 2;
            link[2 * i] = T[(k + 1) % 3];
            link[2 * i + 1] = T[(k + 2) % 3];
        }
        /* triangles sharing an edge at v (a link vertex) are one fan */
        for (int64_t i = 0; i < deg; i++)
            for (int64_t j = i + 1; j < deg; j++)
                if (link[2 * i] == link[2 * j] || link[2 * i] == link[2 * j + 1] ||
                    link[2 * i + 1] == link[2 * j] || link[2 * i + 1] == link[2 * j + 1])
                    vc_uf_unite(parent, i, j);
        int64_t n_fans = 0;
        for (int64_t i = 0; i < deg; i++)
            n_fans += vc_uf_find(parent, i) == i;
        if (n_fans < 2)
            continue;
        const double *x = s->xyz + 3 * v;
        if (min_cos > -1 && !fans_meet_within(s, moved, nv, x, link, parent, deg, min_cos))
            continue;
        r.n_pinches++;
        double new_v[3] = {x[0], x[1], x[2]};
        int first = 1;
        /* each fan, in the order of its first triangle */
        for (int64_t i = 0; i < deg; i++) {
            if (vc_uf_find(parent, i) != i)
                continue;
            double c[3] = {0, 0, 0}, near = INFINITY;
            int64_t n_ring = 0;
            for (int64_t j = 0; j < deg; j++) {
                if (vc_uf_find(parent, j) != i)
                    continue;
                for (int e = 0; e < 2; e++) {
                    const double *p = vertex_at(s, moved, nv, link[2 * j + e]);
                    const double d = sqrt((p[0] - x[0]) * (p[0] - x[0]) + (p[1] - x[1]) * (p[1] - x[1]) +
                                          (p[2] - x[2]) * (p[2] - x[2]));
                    near = fmin(near, d);
                    for (int a = 0; a < 3; a++)
                        c[a] += p[a];
                    n_ring++;
                }
            }
            double dir[3], len = 0;
            for (int a = 0; a < 3; a++) {
                dir[a] = c[a] / (double)n_ring - x[a];
                len += dir[a] * dir[a];
            }
            len = sqrt(len);
            const double step = fmin(max_move, 0.25 * near);
            double p[3] = {x[0], x[1], x[2]};
            if (len > 0 && step > 0)
                for (int a = 0; a < 3; a++)
                    p[a] += step * dir[a] / len;
            r.max_move = fmax(r.max_move, step);
            if (first) { /* the vertex itself serves the first fan */
                memcpy(new_v, p, sizeof p);
                first = 0;
                continue;
            }
            if (n_new == cap_new) {
                cap_new = cap_new ? 2 * cap_new : 16;
                double *m2 = realloc(moved, sizeof(double) * 3 * (size_t)cap_new);
                if (!m2) {
                    rc = vc_error_set(err, VC_ENOMEM, "out of memory for the pinch vertices");
                    break;
                }
                moved = m2;
            }
            memcpy(moved + 3 * n_new, p, sizeof p);
            /* the fan's triangles take the copy */
            for (int64_t j = 0; j < deg; j++) {
                if (vc_uf_find(parent, j) != i)
                    continue;
                int64_t *T = s->tri + 3 * inc[b + j];
                for (int k = 0; k < 3; k++)
                    if (T[k] == v)
                        T[k] = nv + n_new;
            }
            n_new++;
        }
        /* the vertex itself moves after its fans have been measured from it */
        memcpy(s->xyz + 3 * v, new_v, sizeof new_v);
    }
    if (!rc && n_new > 0) {
        double *xyz = realloc(s->xyz, sizeof(double) * 3 * (size_t)(nv + n_new));
        if (!xyz) {
            rc = vc_error_set(err, VC_ENOMEM, "out of memory for the pinch vertices");
        } else {
            s->xyz = xyz;
            memcpy(s->xyz + 3 * nv, moved, sizeof(double) * 3 * (size_t)n_new);
            s->n_vertices = nv + n_new;
            r.n_copies = n_new;
        }
    }
done:
    free(start);
    free(inc);
    free(parent);
    free(link);
    free(moved);
    if (!rc && rep)
        *rep = r;
    return rc;
}
