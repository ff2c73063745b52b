/* vc_surface_open_pinches: two tetrahedra sharing one vertex (a pinch: two
 * fans touching at their apex) get a copy of it, and the two apexes part
 * by the move each makes into its own fan; every edge still has two
 * triangles walked both ways, no vertex has two fans any more, the Euler
 * characteristic grows by one and the volumes stay within the moves'
 * reach. Asked for fans meeting at less than 60 degrees, it keeps the
 * tetrahedra (90) and opens two flat pyramids apex to apex. A sphere, and two boxes sharing an edge (four triangles at it:
 * touching parts, not a pinch), are left alone. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"
#include "test_surface_util.h"
#include "vorocrust/sampling.h"
#include "vorocrust/surface.h"

/* The number of fans at vertex v (classes of its triangles joined across
 * the edges at v). */
static int fans_at(const vc_surface *s, int64_t v)
{
    int64_t tri[64], n = 0;
    for (int64_t t = 0; t < s->n_triangles && n < 64; t++)
        for (int k = 0; k < 3; k++)
            if (s->tri[3 * t + k] == v)
                tri[n++] = t;
    int64_t cls[64];
    for (int64_t i = 0; i < n; i++)
        cls[i] = i;
    for (int changed = 1; changed;) {
        changed = 0;
        for (int64_t i = 0; i < n; i++)
            for (int64_t j = 0; j < n; j++) {
                int shared = 0;
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++) {
                        const int64_t x = s->tri[3 * tri[i] + a], y = s->tri[3 * tri[j] + b];
                        shared += x == y && x != v;
                    }
                if (shared && cls[j] > cls[i]) {
                    cls[j] = cls[i];
                    changed = 1;
                }
            }
    }
    int fans = 0;
    for (int64_t i = 0; i < n; i++)
        fans += cls[i] == i;
    return fans;
}

static int64_t euler(const vc_surface *s)
{
    /* edges: each directed edge once per triangle; closed surfaces: E = 3F/2 */
    return s->n_vertices - 3 * s->n_triangles / 2 + s->n_triangles;
}

static int closed_oriented(const vc_surface *s)
{
    for (int64_t t = 0; t < s->n_triangles; t++)
        for (int k = 0; k < 3; k++) {
            const int64_t a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
            int fwd = 0, back = 0;
            for (int64_t q = 0; q < s->n_triangles; q++)
                for (int j = 0; j < 3; j++) {
                    const int64_t x = s->tri[3 * q + j], y = s->tri[3 * q + (j + 1) % 3];
                    fwd += x == a && y == b;
                    back += x == b && y == a;
                }
            if (fwd != back || fwd == 0)
                return 0;
        }
    return 1;
}

static void add_tet(builder *b, int64_t apex, double sx, double sy, double sz)
{
    /* a tetrahedron with one corner at `apex`, the others at apex + (s, 0,
     * 0), (0, s, 0), (0, 0, s) scaled by the signs, outward */
    const double *x = b->s.xyz + 3 * apex;
    const double o[3] = {x[0], x[1], x[2]};
    const int64_t p = add_v(b, o[0] + sx, o[1], o[2]);
    const int64_t q = add_v(b, o[0], o[1] + sy, o[2]);
    const int64_t r = add_v(b, o[0], o[1], o[2] + sz);
    const int flip = (sx * sy * sz) < 0;
    if (!flip) {
        add_t(b, apex, q, p);
        add_t(b, apex, p, r);
        add_t(b, apex, r, q);
        add_t(b, p, q, r);
    } else {
        add_t(b, apex, p, q);
        add_t(b, apex, r, p);
        add_t(b, apex, q, r);
        add_t(b, p, r, q);
    }
}

/* vc_polysurface_topology_compute on the triangles of s: the check the
 * reconstructed surface goes through (a pinch's closed fans have as many
 * polygons as edges: only its link tells). */
static vc_polysurface_topology topology_of(const vc_surface *s)
{
    vc_polysurface p = {s->n_vertices, s->xyz, s->n_triangles, NULL, s->tri};
    p.poly_offsets = malloc(sizeof(int64_t) * (size_t)(s->n_triangles + 1));
    for (int64_t t = 0; t <= s->n_triangles; t++)
        p.poly_offsets[t] = 3 * t;
    vc_polysurface_topology topo;
    vc_error err;
    memset(&topo, 0, sizeof topo);
    CHECK(vc_polysurface_topology_compute(&p, &topo, &err) == 0);
    free(p.poly_offsets);
    return topo;
}

int main(void)
{
    vc_error err;
    vc_pinch_report rep;

    builder b = {0};
    const int64_t v = add_v(&b, 0, 0, 0);
    add_tet(&b, v, 1, 1, 1);
    add_tet(&b, v, -1, -1, -1);
    const double vol0 = surface_enclosed_volume(&b.s);
    CHECKF(fabs(vol0 - 1.0 / 3) < 1e-12, "volume %.17g", vol0);
    CHECK(closed_oriented(&b.s) && fans_at(&b.s, v) == 2);
    const int64_t e0 = euler(&b.s), nv0 = b.s.n_vertices;
    vc_polysurface_topology t0 = topology_of(&b.s);
    CHECKF(t0.n_nonmanifold_vertices == 1 && t0.n_nonmanifold_edges == 0 && t0.n_boundary_edges == 0 &&
           t0.euler == 3, "pinch: %lld non-manifold vertices, Euler %lld",
           (long long)t0.n_nonmanifold_vertices, (long long)t0.euler);

    CHECK(vc_surface_open_pinches(&b.s, 0, -2, &rep, &err) == 0 && rep.n_pinches == 0 &&
          b.s.n_vertices == nv0);

    const double move = 0.01;
    CHECK(vc_surface_open_pinches(&b.s, move, -2, &rep, &err) == 0);
    CHECKF(rep.n_pinches == 1 && rep.n_copies == 1 && fabs(rep.max_move - move) < 1e-15,
           "%lld pinches, %lld copies, move %g", (long long)rep.n_pinches, (long long)rep.n_copies,
           rep.max_move);
    CHECK(b.s.n_vertices == nv0 + 1 && euler(&b.s) == e0 + 1 && closed_oriented(&b.s));
    vc_polysurface_topology t1 = topology_of(&b.s);
    CHECK(t1.n_nonmanifold_vertices == 0 && t1.euler == 4 && t1.n_components == 2);
    for (int64_t i = 0; i < b.s.n_vertices; i++)
        CHECKF(fans_at(&b.s, i) == 1, "vertex %lld: %d fans", (long long)i, fans_at(&b.s, i));
    /* the two apexes moved into their own tetrahedra, along the diagonals */
    const double *a0 = b.s.xyz + 3 * v, *a1 = b.s.xyz + 3 * nv0;
    const double d = sqrt((a0[0] - a1[0]) * (a0[0] - a1[0]) + (a0[1] - a1[1]) * (a0[1] - a1[1]) +
                          (a0[2] - a1[2]) * (a0[2] - a1[2]));
    CHECKF(fabs(d - 2 * move) < 1e-12, "the apexes %.17g apart", d);
    CHECK(a0[0] > 0 && a0[1] > 0 && a0[2] > 0 && a1[0] < 0 && a1[1] < 0 && a1[2] < 0);
    const double vol1 = surface_enclosed_volume(&b.s);
    CHECKF(fabs(vol1 - vol0) < 2 * move * 3 * 0.5, "volume %.17g to %.17g", vol0, vol1);
    vc_surface_free(&b.s);

    /* with an angle: the two tetrahedra's fans meet at 90 degrees (their
     * edges along opposite axes), kept at 60; two flat hexagonal pyramids
     * apex to apex (their sheets 5.7 degrees apart) are opened */
    builder g = {0};
    const int64_t gv = add_v(&g, 0, 0, 0);
    add_tet(&g, gv, 1, 1, 1);
    add_tet(&g, gv, -1, -1, -1);
    const double cos60 = 0.5;
    CHECK(vc_surface_open_pinches(&g.s, 0.01, cos60, &rep, &err) == 0 && rep.n_pinches == 0 &&
          g.s.n_vertices == 7);
    vc_surface_free(&g.s);
    builder h = {0};
    const int64_t hv = add_v(&h, 0, 0, 0);
    for (int side = -1; side <= 1; side += 2) {
        int64_t ring[6];
        for (int k = 0; k < 6; k++)
            ring[k] = add_v(&h, cos(k * M_PI / 3), sin(k * M_PI / 3), 0.1 * side);
        const int64_t cap = add_v(&h, 0, 0, 0.2 * side);
        for (int k = 0; k < 6; k++) {
            const int64_t a = ring[k], c = ring[(k + 1) % 6];
            if (side > 0) { /* outward: the apex below, the cap above */
                add_t(&h, hv, c, a);
                add_t(&h, cap, a, c);
            } else {
                add_t(&h, hv, a, c);
                add_t(&h, cap, c, a);
            }
        }
    }
    CHECK(closed_oriented(&h.s) && fans_at(&h.s, hv) == 2);
    CHECK(vc_surface_open_pinches(&h.s, 0.01, cos60, &rep, &err) == 0 && rep.n_pinches == 1 &&
          rep.n_copies == 1 && closed_oriented(&h.s) && fans_at(&h.s, hv) == 1);
    vc_surface_free(&h.s);

    /* no pinch: a sphere, and two boxes on a common edge */
    builder c = {0};
    make_sphere(&c, 16, 8);
    vc_surface s = c.s;
    const int64_t nvs = s.n_vertices;
    CHECK(topology_of(&s).n_nonmanifold_vertices == 0);
    CHECK(vc_surface_open_pinches(&s, 0.1, -2, &rep, &err) == 0 && rep.n_pinches == 0 && s.n_vertices == nvs);
    vc_surface_free(&s);

    builder e = {0};
    make_cube(&e);
    {
        /* a second unit box on the edge x = 1, y = 1 of the first (its
         * vertices 3 and 7: (1, 1, 0) and (1, 1, 1)) */
        int64_t w[8];
        for (int k = 0; k < 8; k++) {
            const double x = 1 + (k & 1), y = 1 + ((k >> 1) & 1), z = (k >> 2) & 1;
            w[k] = k == 0 ? 3 : k == 4 ? 7 : add_v(&e, x, y, z);
        }
        add_q(&e, w[0], w[2], w[3], w[1]);
        add_q(&e, w[4], w[5], w[7], w[6]);
        add_q(&e, w[0], w[1], w[5], w[4]);
        add_q(&e, w[2], w[6], w[7], w[3]);
        add_q(&e, w[0], w[4], w[6], w[2]);
        add_q(&e, w[1], w[3], w[7], w[5]);
    }
    const int64_t nve = e.s.n_vertices;
    CHECK(vc_surface_open_pinches(&e.s, 0.1, -2, &rep, &err) == 0 && rep.n_pinches == 0 &&
          e.s.n_vertices == nve);
    vc_surface_free(&e.s);
    return failures ? 1 : 0;
}
