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

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* The other triangle of edge (p, q) of triangle t, or -1. */
static int64_t neighbour_across(const vc_surface *s, int64_t t, int64_t p, int64_t q)
{
    for (int64_t u = 0; u < s->n_triangles; u++) {
        if (u == t)
            continue;
        int has = 0;
        for (int k = 0; k < 3; k++)
            has += s->tri[3 * u + k] == p || s->tri[3 * u + k] == q;
        if (has == 2)
            return u;
    }
    return -1;
}

/* A closed cylinder of radius 1 and height 8 around the z axis, nu
 * facets around, nz rows, outward. */
static void make_cylinder(builder *b, int nu, int nz)
{
    int64_t first = b->s.n_vertices;
    for (int j = 0; j <= nz; j++)
        for (int i = 0; i < nu; i++)
            add_v(b, cos(2 * M_PI * i / nu), sin(2 * M_PI * i / nu), 8.0 * j / nz - 4);
    int64_t bottom = add_v(b, 0, 0, -4), top = add_v(b, 0, 0, 4);
#define V(i, j) (first + (int64_t)(j) * nu + ((i) % nu))
    for (int i = 0; i < nu; i++) {
        for (int j = 0; j < nz; j++)
            add_q(b, V(i, j), V(i + 1, j), V(i + 1, j + 1), V(i, j + 1));
        add_t(b, bottom, V(i + 1, 0), V(i, 0));
        add_t(b, top, V(i, nz), V(i + 1, nz));
    }
#undef V
}

/* The features (at 60 degrees), sizing and S' of kernel width `width` of b's surface. */
static void smooth_setup(builder *b, double width, vc_features *f, vc_sizing *z,
                         vc_smooth_surface *m)
{
    vc_error err;
    CHECK(vc_features_detect(&b->s, 60, f, &err) == 0);
    CHECK(vc_sizing_init(z, &b->s, f, 60, 0.004) == 0);
    CHECK(vc_smooth_surface_init(m, z, width) == 0);
}

/* On a cylinder the fitted sphere's radius is a mean curvature's (about
 * 2); the largest principal curvature is 1. Balls bounded by the former
 * reach twice as far around the cylinder as sliver elimination allows. */
static void check_cylinder(void)
{
    builder b = {0};
    make_cylinder(&b, 48, 24);
    vc_features f;
    vc_sizing z;
    vc_smooth_surface m;
    smooth_setup(&b, 0.4, &f, &z, &m);
    double worst_k = 0, mean_R = 0;
    int n = 0;
    for (int64_t t = 0; t < b.s.n_triangles; t++) {
        const int64_t *v = b.s.tri + 3 * t;
        double x[3];
        for (int d = 0; d < 3; d++)
            x[d] = (b.s.xyz[3 * v[0] + d] + b.s.xyz[3 * v[1] + d] + b.s.xyz[3 * v[2] + d]) / 3;
        if (fabs(x[2]) > 2) /* away from the caps and their blend */
            continue;
        double y[3], nn[3], R;
        CHECK(vc_smooth_surface_project(&m, t, x, x, y, nn, &R) == 0);
        worst_k = fmax(worst_k, fabs(vc_smooth_surface_max_curvature(&m, t, y, nn) - 1));
        mean_R += R;
        n++;
    }
    mean_R /= n;
    printf("cylinder: %d points, max curvature within %.3f of 1, fitted sphere radius %.2f\n", n,
           worst_k, mean_R);
    CHECK(n > 100);
    CHECK(worst_k < 0.1);
    CHECK(mean_R > 1.5);
    vc_smooth_surface_free(&m);
    vc_sizing_free(&z);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

static void check_cube(void)
{
    builder b = {0};
    make_cube(&b);
    vc_features f;
    vc_sizing z;
    vc_smooth_surface m;
    smooth_setup(&b, 0.1, &f, &z, &m);
    /* the middle of face z = 0 (triangle 0) and a point near its edge: the
     * input itself, bit for bit */
    const double pts[2][3] = {{0.5, 0.4, 0}, {0.03, 0.5, 0}};
    for (int k = 0; k < 2; k++) {
        double y[3], n[3], R;
        /* 0 in the middle; 1 within a kernel width of the edge, in the
         * blend into the input */
        CHECK(vc_smooth_surface_project(&m, 0, pts[k], pts[k], y, n, &R) == k);
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
    vc_sizing z;
    vc_smooth_surface m;
    smooth_setup(&b, 0.4, &f, &z, &m);
    double worst_facet = 0, worst = 0, worst_n = 0, worst_r = 0;
    double worst_start = 0, worst_seam = 0, worst_settle = 0, worst_k = 0;
    int n_seam = 0;
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
        /* the same point from another start: the orthogonal projection
         * does not depend on where the search starts */
        double y2[3], n2[3], R2, s[3] = {1.01 * x[0], 1.01 * x[1], 1.01 * x[2]};
        CHECK(vc_smooth_surface_project(&m, t, x, s, y2, n2, &R2) == 0);
        worst_start = fmax(worst_start, dist3(y, y2));
        /* a point of one of its edges, seen from the triangle across that
         * edge: the same point of S' (no seam between the triangles'
         * images) */
        const int64_t across = neighbour_across(&b.s, t, v[0], v[1]);
        if (across >= 0) {
            double e[3], ya[3], yb[3], na[3], nb[3], Ra, Rb;
            for (int d = 0; d < 3; d++)
                e[d] = 0.7 * b.s.xyz[3 * v[0] + d] + 0.3 * b.s.xyz[3 * v[1] + d];
            CHECK(vc_smooth_surface_project(&m, t, e, e, ya, na, &Ra) == 0);
            CHECK(vc_smooth_surface_project(&m, across, e, e, yb, nb, &Rb) == 0);
            worst_seam = fmax(worst_seam, dist3(ya, yb));
            n_seam++;
        }
        /* settling a point just off S' along its normal lands back on it */
        double z[3], ys[3], ns[3], Rs;
        for (int d = 0; d < 3; d++)
            z[d] = y[d] + 1e-3 * n[d];
        CHECK(vc_smooth_surface_settle(&m, t, x, z, n, ys, ns, &Rs) == 0);
        worst_settle = fmax(worst_settle, dist3(ys, y));
        /* the largest principal curvature of a sphere is 1 / radius */
        worst_k = fmax(worst_k, fabs(vc_smooth_surface_max_curvature(&m, t, y, n) - 1));
    }
    printf("sphere: other start %.1e, across %d edges %.1e, settled %.1e, max curvature within "
           "%.3f of 1\n", worst_start, n_seam, worst_seam, worst_settle, worst_k);
    CHECK(worst_start < 1e-6);
    CHECK(n_seam > 20 && worst_seam < 1e-6);
    CHECK(worst_settle < 1e-5);
    CHECK(worst_k < 0.1);
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
    vc_error err;
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
    check_cylinder();
    check_sphere();
    if (failures)
        fprintf(stderr, "%d checks failed\n", failures);
    return failures ? 1 : 0;
}
