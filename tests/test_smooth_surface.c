/* The smooth centre surface (sizing/smooth_surface.h): it is the input
 * itself on flat faces, it follows a faceted sphere closer than the
 * facets' centroids are, with the sphere's normal and radius of curvature, and the
 * sampler on it gives a closed, sliver-free set of balls. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sizing/sizing.h"
#include "sizing/smooth_surface.h"
#include "vorocrust/features.h"
#include "vorocrust/sampling.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

/* A UV sphere of radius 1, nu x nv, outward. */
static void make_sphere(builder *b, int nu, int nv)
{
    int64_t top = add_v(b, 0, 0, 1), bottom = add_v(b, 0, 0, -1);
    int64_t first = b->s.n_vertices;
    for (int j = 1; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
            add_v(b, sin(th) * cos(ph), sin(th) * sin(ph), cos(th));
        }
#define V(i, j) (first + (int64_t)((j) - 1) * nu + ((i) % nu))
    for (int i = 0; i < nu; i++) {
        add_t(b, top, V(i, 1), V(i + 1, 1));
        add_t(b, bottom, V(i + 1, nv - 1), V(i, nv - 1));
        for (int j = 1; j + 1 < nv; j++)
            add_q(b, V(i, j), V(i, j + 1), V(i + 1, j + 1), V(i + 1, j));
    }
#undef V
}

/* A cube [0, 1]^3, outward. */
static void make_cube(builder *b)
{
    int64_t v[8];
    for (int k = 0; k < 8; k++)
        v[k] = add_v(b, k & 1, (k >> 1) & 1, (k >> 2) & 1);
    add_q(b, v[0], v[2], v[3], v[1]); /* z = 0 */
    add_q(b, v[4], v[5], v[7], v[6]); /* z = 1 */
    add_q(b, v[0], v[1], v[5], v[4]); /* y = 0 */
    add_q(b, v[2], v[6], v[7], v[3]); /* y = 1 */
    add_q(b, v[0], v[4], v[6], v[2]); /* x = 0 */
    add_q(b, v[1], v[3], v[7], v[5]); /* x = 1 */
}

static void check_cube(void)
{
    builder b = {0};
    make_cube(&b);
    vc_features f;
    vc_error err;
    CHECK(vc_features_detect(&b.s, 60, &f, &err) == 0);
    vc_sizing z;
    CHECK(vc_sizing_init(&z, &b.s, &f, 60, 0.004) == 0);
    vc_smooth_surface m;
    CHECK(vc_smooth_surface_init(&m, &z, 0.1) == 0);
    /* the middle of face z = 0 (triangle 0) and a point near its edge: the
     * input itself, bit for bit */
    const double pts[2][3] = {{0.5, 0.4, 0}, {0.03, 0.5, 0}};
    for (int k = 0; k < 2; k++) {
        double y[3], n[3], R;
        CHECK(vc_smooth_surface_project(&m, 0, pts[k], pts[k], y, n, &R) == 0);
        CHECK(y[0] == pts[k][0] && y[1] == pts[k][1] && y[2] == pts[k][2]);
        CHECK(fabs(n[2] + 1) < 1e-12);
    }
    vc_smooth_surface_free(&m);
    vc_sizing_free(&z);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

static void check_sphere(void)
{
    builder b = {0};
    make_sphere(&b, 24, 12); /* folds of 15 degrees */
    vc_features f;
    vc_error err;
    CHECK(vc_features_detect(&b.s, 60, &f, &err) == 0);
    vc_sizing z;
    CHECK(vc_sizing_init(&z, &b.s, &f, 60, 0.004) == 0);
    vc_smooth_surface m;
    CHECK(vc_smooth_surface_init(&m, &z, 0.4) == 0);
    double worst_facet = 0, worst = 0, worst_n = 0, worst_r = 0;
    for (int64_t t = 0; t < b.s.n_triangles; t += 7) {
        const int64_t *v = b.s.tri + 3 * t;
        double x[3];
        for (int d = 0; d < 3; d++)
            x[d] = (b.s.xyz[3 * v[0] + d] + b.s.xyz[3 * v[1] + d] + b.s.xyz[3 * v[2] + d]) / 3;
        double y[3], n[3], R;
        CHECK(vc_smooth_surface_project(&m, t, x, x, y, n, &R) == 0);
        const double lx = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        const double ly = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        worst_facet = fmax(worst_facet, 1 - lx);
        worst = fmax(worst, fabs(1 - ly));
        worst_n = fmax(worst_n, 1 - (n[0] * y[0] + n[1] * y[1] + n[2] * y[2]) / ly);
        worst_r = fmax(worst_r, fabs(R - 1));
        /* the same point from another start */
        double y2[3], n2[3], R2, s[3] = {1.01 * x[0], 1.01 * x[1], 1.01 * x[2]};
        CHECK(vc_smooth_surface_project(&m, t, x, s, y2, n2, &R2) == 0);
        const double l2 = sqrt(y2[0] * y2[0] + y2[1] * y2[1] + y2[2] * y2[2]);
        CHECK(fabs(l2 - ly) < 1e-3);
    }
    printf("sphere: facet centroids %.4f inside, S' within %.4f of the sphere, normals within "
           "%.2e, radius of curvature within %.3f\n", worst_facet, worst, worst_n, worst_r);
    CHECK(worst < worst_facet); /* S' is near the facets, not the sphere they approximate */
    CHECK(worst_n < 1e-3);
    CHECK(worst_r < 0.1);
    vc_smooth_surface_free(&m);
    vc_sizing_free(&z);

    /* the sampler on S' of the same sphere: no half-covered pair left, and
     * every surface ball centred on S' (near the unit sphere) */
    vc_sampling_options opt;
    vc_sampling_options_default(&opt);
    opt.max_error = 0.02;
    opt.smooth_width = 4;
    opt.threads = 2;
    vc_balls balls;
    vc_sampling_stats st;
    CHECK_MSG(vc_sample_surface(&b.s, &f, &opt, &balls, &st, &err) == 0, err.msg);
    CHECK(st.n_half_covered == 0 && !st.diverged);
    double off = 0;
    for (int64_t i = 0; i < balls.n; i++) {
        const double *c = balls.center + 3 * i;
        off = fmax(off, fabs(1 - sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])));
    }
    printf("sphere: %lld balls on S', centres within %.4f of the sphere\n", (long long)balls.n, off);
    CHECK(balls.n > 100 && off < worst_facet);
    vc_balls_free(&balls);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

int main(void)
{
    check_cube();
    check_sphere();
    if (failures)
        fprintf(stderr, "%d checks failed\n", failures);
    return failures ? 1 : 0;
}
