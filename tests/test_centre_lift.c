/* The centre lift (balls/centre_lift.h): on a faceted sphere the
 * reconstructed surface of the lifted balls encloses the input's volume
 * (without the lift it is short by the chords' sag), every ball moves
 * outward by a few percent of its radius at most, the seeds stay free of
 * half-covered pairs, the surface stays a closed sphere, and the result is
 * the same on 1 and 2 threads; on a cube (flat faces) nothing moves; on a
 * thin torus further passes remove what one pass leaves. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/features.h"
#include "vorocrust/sampling.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

/* Enclosed volume of a closed polygonal surface (polygons fanned). */
static double poly_volume(const vc_polysurface *p)
{
    double v = 0;
    for (int64_t k = 0; k < p->n_polys; k++) {
        const int64_t *w = p->poly_vertices + p->poly_offsets[k];
        int64_t m = p->poly_offsets[k + 1] - p->poly_offsets[k];
        const double *a = p->points + 3 * w[0];
        for (int64_t j = 1; j + 1 < m; j++) {
            const double *b = p->points + 3 * w[j], *c = p->points + 3 * w[j + 1];
            v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
        }
    }
    return v;
}

typedef struct sampled {
    vc_balls balls;
    vc_sampling_stats st;
    double volume;          /* of the reconstructed surface */
    int64_t n_half, euler;
    int closed;
} sampled;

static void sample(const vc_surface *s, const vc_features *f, double max_error, int lift,
                   int threads, sampled *out)
{
    memset(out, 0, sizeof *out);
    vc_sampling_options opt;
    vc_sampling_options_default(&opt);
    opt.max_error = max_error;
    opt.lift_centres = lift;
    opt.threads = threads;
    vc_error err;
    CHECK_MSG(vc_sample_surface(s, f, &opt, &out->balls, &out->st, &err) == 0, err.msg);
    vc_seeds seeds;
    CHECK_MSG(vc_balls_seeds(&out->balls, 1, &seeds, &out->n_half, &err) == 0, err.msg);
    vc_polysurface ps;
    CHECK_MSG(vc_reconstruct_surface(&seeds, 0, NULL, threads, NULL, &ps, &err) == 0, err.msg);
    vc_polysurface_topology top;
    CHECK_MSG(vc_polysurface_topology_compute(&ps, &top, &err) == 0, err.msg);
    out->euler = top.euler;
    out->closed = top.n_boundary_edges == 0 && top.n_nonmanifold_edges == 0 &&
                  top.n_misoriented_edges == 0 && top.n_nonmanifold_vertices == 0;
    out->volume = poly_volume(&ps);
    vc_polysurface_free(&ps);
    vc_seeds_free(&seeds);
}

static void check_sphere(void)
{
    builder b = {0};
    make_sphere(&b, 48, 24);
    vc_features f;
    vc_error err;
    CHECK_MSG(vc_features_detect(&b.s, VC_FEATURES_DEFAULT_SHARP_ANGLE, &f, &err) == 0, err.msg);
    double v_in = surface_enclosed_volume(&b.s);
    sampled flat, lifted, lifted1;
    sample(&b.s, &f, 0.01, 0, 2, &flat);
    sample(&b.s, &f, 0.01, 1, 2, &lifted);
    sample(&b.s, &f, 0.01, 1, 1, &lifted1);
    double e_flat = flat.volume / v_in - 1, e_lift = lifted.volume / v_in - 1;
    printf("sphere: %lld balls, volume error %+.3f%% on the facets, %+.3f%% lifted "
           "(%lld moved by %.4f r on average, largest %.4f r, %lld reduced, %d checks)\n",
           (long long)lifted.balls.n, 100 * e_flat, 100 * e_lift, (long long)lifted.st.n_lifted,
           lifted.st.lift_mean_rel, lifted.st.lift_max_rel, (long long)lifted.st.n_lift_reduced,
           lifted.st.lift_rounds);
    /* the chords' bias is what the lift removes */
    CHECK(e_flat < -0.002);
    CHECK(fabs(e_lift) < fabs(e_flat) / 4);
    CHECK(!lifted.st.lift_dropped && lifted.st.n_lifted > lifted.balls.n / 2);
    CHECK(lifted.st.lift_max_rel <= 0.1 && lifted.st.lift_mean_rel > 0.005);
    /* a valid sampling still: no half-covered pair, a closed sphere */
    CHECK(lifted.n_half == 0 && lifted.closed && lifted.euler == 2);
    /* the same balls as without the lift, each moved outward (a convex
     * input) by at most a tenth of its radius */
    CHECK(flat.balls.n == lifted.balls.n);
    int64_t inward = 0;
    double worst = 0;
    for (int64_t i = 0; i < flat.balls.n && flat.balls.n == lifted.balls.n; i++) {
        const double *p = flat.balls.center + 3 * i, *q = lifted.balls.center + 3 * i;
        double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        worst = fmax(worst, len / flat.balls.radius[i]);
        inward += d[0] * p[0] + d[1] * p[1] + d[2] * p[2] < 0;
    }
    CHECK(inward == 0 && worst <= 0.1 + 1e-12);
    /* any thread count, the same centres */
    CHECK(lifted1.balls.n == lifted.balls.n &&
          memcmp(lifted1.balls.center, lifted.balls.center,
                 sizeof(double) * 3 * (size_t)lifted.balls.n) == 0);
    vc_balls_free(&flat.balls);
    vc_balls_free(&lifted.balls);
    vc_balls_free(&lifted1.balls);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

static void check_cube(void)
{
    builder b = {0};
    make_cube(&b);
    vc_features f;
    vc_error err;
    CHECK_MSG(vc_features_detect(&b.s, VC_FEATURES_DEFAULT_SHARP_ANGLE, &f, &err) == 0, err.msg);
    sampled flat, lifted;
    sample(&b.s, &f, 0.004, 0, 2, &flat);
    sample(&b.s, &f, 0.004, 1, 2, &lifted);
    CHECK(flat.balls.n == lifted.balls.n && flat.balls.n > 50);
    double worst = 0;
    for (int64_t i = 0; i < 3 * flat.balls.n && flat.balls.n == lifted.balls.n; i++)
        worst = fmax(worst, fabs(flat.balls.center[i] - lifted.balls.center[i]));
    printf("cube: %lld balls, largest move %.2e, volume %.12f\n", (long long)lifted.balls.n, worst,
           lifted.volume);
    CHECK(worst < 1e-12);
    CHECK(lifted.n_half == 0 && lifted.closed && lifted.euler == 2);
    CHECK(fabs(lifted.volume - 1) < 1e-9);
    vc_balls_free(&flat.balls);
    vc_balls_free(&lifted.balls);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

/* A torus of ring radius 1 and tube radius r, nu x nv quads, outward. */
static void make_torus(builder *b, int nu, int nv, double r)
{
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            add_v(b, (1 + r * cos(v)) * cos(u), (1 + r * cos(v)) * sin(u), r * sin(v));
        }
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            int i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            add_q(b, i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1);
        }
}

/* A thin tube: the balls' sag is a large share of its radius, one pass
 * of the lift leaves a second-order remainder, and further passes
 * (measured on the lifted facets, checked against the sampled ones) take
 * the volume error well inside the 0.5% of issue 16. */
static void check_thin_torus(void)
{
    builder b = {0};
    make_torus(&b, 192, 32, 0.15);
    vc_features f;
    vc_error err;
    CHECK_MSG(vc_features_detect(&b.s, VC_FEATURES_DEFAULT_SHARP_ANGLE, &f, &err) == 0, err.msg);
    double v_in = surface_enclosed_volume(&b.s);
    sampled flat, lifted, lifted1;
    sample(&b.s, &f, 0.004, 0, 2, &flat);
    sample(&b.s, &f, 0.004, 1, 2, &lifted);
    sample(&b.s, &f, 0.004, 1, 1, &lifted1);
    double e_flat = flat.volume / v_in - 1, e_lift = lifted.volume / v_in - 1;
    printf("thin torus: %lld balls, volume error %+.3f%% on the facets, %+.3f%% lifted "
           "(%d passes, %d checks, %lld moved by %.4f r on average, largest %.4f r)\n",
           (long long)lifted.balls.n, 100 * e_flat, 100 * e_lift, lifted.st.lift_passes,
           lifted.st.lift_rounds, (long long)lifted.st.n_lifted, lifted.st.lift_mean_rel,
           lifted.st.lift_max_rel);
    CHECK(e_flat < -0.01);
    CHECK(lifted.st.lift_passes >= 2);
    CHECK(fabs(e_lift) < 0.003);
    CHECK(lifted.st.lift_max_rel <= 0.1 + 1e-12);
    CHECK(lifted.n_half == 0 && lifted.closed && lifted.euler == 0);
    CHECK(lifted1.balls.n == lifted.balls.n &&
          memcmp(lifted1.balls.center, lifted.balls.center,
                 sizeof(double) * 3 * (size_t)lifted.balls.n) == 0);
    vc_balls_free(&flat.balls);
    vc_balls_free(&lifted.balls);
    vc_balls_free(&lifted1.balls);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

/* Thinner tubes, 3 to 4 balls across: the lifts that turn a near-quartet
 * of balls over are not halved away but taken by the quartet's balls
 * together (reduce_lifts), and the volume error stays well inside 0.5%
 * (before: -0.52% on the tube of radius 0.1, -0.30% on the one of radius
 * 0.05; -2.5% on a capped cylinder, see docs/sampling-convergence.md). */
static void check_thinner_tube(double r, int nu, int nv)
{
    builder b = {0};
    make_torus(&b, nu, nv, r);
    vc_features f;
    vc_error err;
    CHECK_MSG(vc_features_detect(&b.s, VC_FEATURES_DEFAULT_SHARP_ANGLE, &f, &err) == 0, err.msg);
    double v_in = surface_enclosed_volume(&b.s);
    sampled lifted;
    sample(&b.s, &f, 0.004, 1, 2, &lifted);
    double e_lift = lifted.volume / v_in - 1;
    printf("torus, tube radius %g (%d x %d): %lld balls, volume error %+.3f%% lifted "
           "(%d passes, %d checks, %lld moved by %.4f r on average, %lld reduced)\n",
           r, nu, nv, (long long)lifted.balls.n, 100 * e_lift, lifted.st.lift_passes,
           lifted.st.lift_rounds, (long long)lifted.st.n_lifted, lifted.st.lift_mean_rel,
           (long long)lifted.st.n_lift_reduced);
    CHECK(fabs(e_lift) < 0.0025);
    CHECK(lifted.st.lift_max_rel <= 0.1 + 1e-12);
    CHECK(lifted.n_half == 0 && lifted.closed && lifted.euler == 0);
    vc_balls_free(&lifted.balls);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

int main(void)
{
    check_sphere();
    check_cube();
    check_thin_torus();
    check_thinner_tube(0.1, 192, 32);
    check_thinner_tube(0.05, 384, 24);
    if (failures)
        fprintf(stderr, "%d checks failed\n", failures);
    return failures ? 1 : 0;
}
