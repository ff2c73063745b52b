/* The radius bound's tree walk (sizing/sizing.h): it skips whole subtrees
 * (by box distance, and the subtrees of one smooth patch by their normal
 * cone and the slab about the point's tangent plane), so it must return,
 * to the bit, what the same rules give element by element over the whole
 * surface (vc_sizing_radius_bound_all): at triangle centroids, sharp edge
 * midpoints and corners, with the error bound and without it, on fine and
 * coarse smooth surfaces and on surfaces with creases and corners.
 * And the tangent slab of a ball on a knife edge (session 49): narrowed by
 * sin^2 of the crease's opening below a right angle, eps above it. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sizing/sizing.h"
#include "vorocrust/features.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

/* A torus (radii 1 and 0.35) whose tube radius waves with the angle
 * around: curvature that varies, nu x nv, outward. */
static void make_wavy_torus(builder *b, int nu, int nv)
{
    int64_t first = b->s.n_vertices;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            double r = 0.35 * (1 + 0.3 * sin(5 * u));
            add_v(b, (1 + r * cos(v)) * cos(u), (1 + r * cos(v)) * sin(u), r * sin(v));
        }
#define V(i, j) (first + (int64_t)((i) % nu) * nv + ((j) % nv))
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++)
            add_q(b, V(i, j), V(i + 1, j), V(i + 1, j + 1), V(i, j + 1));
#undef V
}

/* A lens prism: the section two circular arcs meeting at tips (+-a, 0)
 * under the angle 2 alpha, n points each, extruded along z by len,
 * capped, outward. Returns the arcs' radius. */
static double make_lens_prism(builder *b, double a, double alpha, int n, double len)
{
    const double rho = a / sin(alpha), h = rho - sqrt(rho * rho - a * a);
    const double b0 = atan2(rho - h, a); /* the tip (a, 0) seen from the top arc's centre */
    const int m = 2 * n;
    double *xy = malloc(sizeof(double) * 2 * (size_t)m);
    if (!xy)
        abort();
    for (int i = 0; i < m; i++) {
        /* the top arc from (a, 0) to (-a, 0), then the bottom one back */
        const int k = i < n ? i : m - i;
        const double th = b0 + (M_PI - 2 * b0) * k / n;
        xy[2 * i] = rho * cos(th);
        xy[2 * i + 1] = (h - rho + rho * sin(th)) * (i < n ? 1 : -1);
    }
    extrude_section(b, xy, m, len);
    free(xy);
    return rho;
}

/* The radius bound of an edge ball halfway along the lens' tip crease at
 * (a, 0): where the arc leaves the tangent slab of half-width w, about
 * sqrt(2 rho w), w = eps sin^2(2 alpha) below a right angle, eps above. */
static void check_knife(double alpha_deg)
{
    const double a = 0.5, len = 4, alpha = alpha_deg * M_PI / 180;
    builder b = {0};
    const double rho = make_lens_prism(&b, a, alpha, 400, len);
    vc_features f;
    vc_sizing z;
    vc_error err;
    CHECK(vc_features_detect(&b.s, 60, &f, &err) == 0);
    CHECK(vc_sizing_init(&z, &b.s, &f, 60, 0.004) == 0);
    int64_t tip = -1;
    for (int64_t e = 0; e < f.n_edges; e++) {
        const double *p = b.s.xyz + 3 * f.edge_vertex[2 * e], *q = b.s.xyz + 3 * f.edge_vertex[2 * e + 1];
        if (f.edge_sharp[e] && p[0] > 0.99 * a && q[0] > 0.99 * a && fabs(p[2] - q[2]) > 0.5 * len)
            tip = e;
    }
    CHECKF(tip >= 0, "lens of %g degrees: no sharp edge along the tip", 2 * alpha_deg);
    if (tip >= 0) {
        const double x[3] = {b.s.xyz[3 * f.edge_vertex[2 * tip]], 0, 0.5 * len};
        vc_surface_point sp = {VC_ELEM_EDGE, tip};
        const double got = vc_sizing_radius_bound(&z, &sp, x, z.diag);
        const double s = sin(2 * alpha), w = 2 * alpha < M_PI / 2 ? z.eps * s * s : z.eps;
        const double want = sqrt(2 * rho * w);
        CHECKF(fabs(got / want - 1) < 0.05, "lens of %g degrees: edge ball bound %.5g, expected %.5g",
               2 * alpha_deg, got, want);
        printf("lens of %g degrees: edge ball bound %.5g (slab %.3g of eps: %.5g)\n", 2 * alpha_deg, got,
               w / z.eps, want);
    }
    vc_sizing_free(&z);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

typedef struct tally {
    long points, below; /* bounds compared, of them below the cap */
} tally;

static void compare_at(const vc_sizing *z, const vc_surface_point *sp, const double x[3],
                       double cap, const char *what, tally *t)
{
    const double tree = vc_sizing_radius_bound(z, sp, x, cap);
    const double all = vc_sizing_radius_bound_all(z, sp, x, cap);
    CHECKF(memcmp(&tree, &all, sizeof tree) == 0,
           "%s: element %lld (kind %d): tree %.17g, every element %.17g", what, (long long)sp->id,
           sp->kind, tree, all);
    t->points++;
    t->below += tree < cap;
}

static void compare_surface(const vc_surface *s, double max_error, const char *what)
{
    vc_features f;
    vc_sizing z;
    vc_error err;
    CHECK(vc_features_detect(s, 60, &f, &err) == 0);
    CHECK(vc_sizing_init(&z, s, &f, 60, max_error) == 0);
    tally t = {0, 0};
    for (int c = 0; c < 2; c++) {
        const double cap = c == 0 ? z.diag : 0.1 * z.diag;
        for (int64_t tr = 0; tr < s->n_triangles; tr++) {
            double x[3] = {0, 0, 0};
            for (int k = 0; k < 3; k++)
                for (int d = 0; d < 3; d++)
                    x[d] += s->xyz[3 * s->tri[3 * tr + k] + d] / 3;
            vc_surface_point sp = {VC_ELEM_TRIANGLE, tr};
            compare_at(&z, &sp, x, cap, what, &t);
        }
        for (int64_t e = 0; e < f.n_edges; e++) {
            if (!f.edge_sharp[e])
                continue;
            const double *a = s->xyz + 3 * f.edge_vertex[2 * e], *b = s->xyz + 3 * f.edge_vertex[2 * e + 1];
            const double x[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
            vc_surface_point sp = {VC_ELEM_EDGE, e};
            compare_at(&z, &sp, x, cap, what, &t);
        }
        for (int64_t v = 0; v < s->n_vertices; v++) {
            if (!f.vertex_corner[v])
                continue;
            vc_surface_point sp = {VC_ELEM_CORNER, v};
            compare_at(&z, &sp, s->xyz + 3 * v, cap, what, &t);
        }
    }
    /* not vacuous: many bounds come from the surface, not the cap */
    CHECKF(t.below * 4 > t.points, "%s: only %ld of %ld bounds below the cap", what, t.below, t.points);
    printf("%s (max error %g): %ld bounds equal, %ld below the cap; %lld sharp edges, %lld corners\n",
           what, max_error, t.points, t.below, (long long)f.n_sharp_edges, (long long)f.n_corners);
    vc_sizing_free(&z);
    vc_features_free(&f);
}

int main(void)
{
    const double errors[2] = {0.004, 0};
    for (int k = 0; k < 2; k++) {
        builder b = {0};
        make_sphere(&b, 48, 24); /* fine and smooth: the subtrees skipped by cone and slab */
        compare_surface(&b.s, errors[k], "UV sphere 48 x 24");
        vc_surface_free(&b.s);

        builder w = {0};
        make_wavy_torus(&w, 60, 24);
        compare_surface(&w.s, errors[k], "wavy torus 60 x 24");
        vc_surface_free(&w.s);

        builder c = {0};
        make_prism(&c, 40, 1.5); /* two creased rims, flat caps: several patches */
        compare_surface(&c.s, errors[k], "40-gon prism");
        vc_surface_free(&c.s);

        builder q = {0};
        make_cube(&q); /* corners and creases only */
        compare_surface(&q.s, errors[k], "cube");
        vc_surface_free(&q.s);
    }
    check_knife(8);  /* a 16-degree knife edge: sin^2 = 0.076 */
    check_knife(30); /* 60 degrees: 0.75 */
    check_knife(50); /* 100 degrees: eps */
    return failures ? 1 : 0;
}
