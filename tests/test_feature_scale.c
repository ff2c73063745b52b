/* The flat-ground test that judges folds at the error bound
 * (vorocrust/surface/feature_scale.c): on height fields over a grid, noise
 * on a plane and on a curved patch is flat at a scale well above it, a
 * 60-degree crease is not, with or without noise; a coarser grid is
 * looked at farther, and a coarse fold (too few triangles for a quadric
 * even then) is judged by the plane alone. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "surface/feature_scale.h"
#include "vorocrust/features.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

typedef double (*height_fn)(double x, double y);

static double flat(double x, double y)
{
    (void)x;
    (void)y;
    return 0;
}

/* curvature 8: 0.02 above the tangent plane 0.07 away */
static double paraboloid(double x, double y)
{
    return 4.0 * (x * x + y * y);
}

/* curvature 4 */
static double gentle_paraboloid(double x, double y)
{
    return 2.0 * (x * x + y * y);
}

/* two planes whose normals differ by 60 degrees, the crease along x = 0 */
static double roof(double x, double y)
{
    (void)y;
    return -tan(M_PI / 6) * fabs(x);
}

/* An n x n grid over [-1, 1]^2 (n even: x = 0 is a grid line), z = fn +
 * seeded noise of +-amp. */
static void make_field(builder *b, int n, height_fn fn, double amp)
{
    uint64_t state = 777;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
            state = state * 6364136223846793005ULL + 1442695040888963407ULL;
            const double noise = amp * (2.0 * (double)(state >> 11) / 9007199254740992.0 - 1.0);
            add_v(b, x, y, fn(x, y) + noise);
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            const int64_t a = (int64_t)j * (n + 1) + i;
            add_q(b, a, a + 1, a + n + 2, a + n + 1);
        }
}

/* The flat-ground test at the grid edge from vertex (n/2, n/2) to (n/2,
 * n/2 + 1), on the crease line x = 0 (as vc_features_unmark_noise_folds
 * calls it); *reached receives the walk's triangles. */
static int flat_at_centre(const builder *b, int n, double scale, int64_t *reached)
{
    vc_features f;
    vc_error err;
    if (vc_features_detect(&b->s, 60, &f, &err))
        return -1;
    vc_flat_probe p;
    if (vc_flat_probe_init(&p, b->s.n_triangles)) {
        vc_features_free(&f);
        return -1;
    }
    const int64_t u = (int64_t)(n / 2) * (n + 1) + n / 2, v = u + n + 1;
    const int64_t e = vc_features_find_edge(&f, u, v);
    int r = -1;
    if (e >= 0 && f.edge_tri_start[e + 1] - f.edge_tri_start[e] == 2) {
        const int64_t seeds[2] = {f.edge_tri[f.edge_tri_start[e]], f.edge_tri[f.edge_tri_start[e] + 1]};
        const double *pa = b->s.xyz + 3 * u, *pb = b->s.xyz + 3 * v;
        const double x[3] = {0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])};
        r = vc_flat_near(&b->s, &f, &p, seeds, 2, x, VC_FLAT_REACH * scale, VC_FLAT_SLAB * scale, 0, NULL);
        *reached = p.n_reached;
    }
    vc_flat_probe_free(&p);
    vc_features_free(&f);
    return r;
}

static void expect_flat(const char *name, int n, height_fn fn, double amp, double scale, int want,
                        int64_t min_reached, int64_t max_reached)
{
    builder b = {0};
    make_field(&b, n, fn, amp);
    int64_t reached = 0;
    const int r = flat_at_centre(&b, n, scale, &reached);
    CHECKF(r == want && reached >= min_reached && reached <= max_reached,
           "%s: flat %d (want %d), %lld triangles looked at (want %lld to %lld)", name, r, want,
           (long long)reached, (long long)min_reached, (long long)max_reached);
    vc_surface_free(&b.s);
}

/* A grid of needles: nx x ny cells over [-ex, ex] x [-ey, ey], each cell
 * two triangles, z = fn + seeded noise of +-amp (the pole of a fine UV
 * sphere: cells far narrower than long). The fold tested is the grid edge
 * from the centre vertex one step along y. */
static void expect_flat_needles(const char *name, int nx, int ny, double ex, double ey, height_fn fn,
                                double amp, double scale, int want)
{
    builder b = {0};
    uint64_t state = 4242;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            const double x = -ex + 2.0 * ex * i / nx, y = -ey + 2.0 * ey * j / ny;
            state = state * 6364136223846793005ULL + 1442695040888963407ULL;
            const double noise = amp * (2.0 * (double)(state >> 11) / 9007199254740992.0 - 1.0);
            add_v(&b, x, y, fn(x, y) + noise);
        }
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            const int64_t a = (int64_t)j * (nx + 1) + i;
            add_q(&b, a, a + 1, a + nx + 2, a + nx + 1);
        }
    vc_features f;
    vc_error err;
    int r = -1;
    double coherence = 0;
    if (vc_features_detect(&b.s, 60, &f, &err) == 0) {
        vc_flat_probe p;
        if (vc_flat_probe_init(&p, b.s.n_triangles) == 0) {
            const int64_t u = (int64_t)(ny / 2) * (nx + 1) + nx / 2, v = u + nx + 1;
            const int64_t e = vc_features_find_edge(&f, u, v);
            if (e >= 0 && f.edge_tri_start[e + 1] - f.edge_tri_start[e] == 2) {
                const int64_t seeds[2] = {f.edge_tri[f.edge_tri_start[e]], f.edge_tri[f.edge_tri_start[e] + 1]};
                const double *pa = b.s.xyz + 3 * u, *pb = b.s.xyz + 3 * v;
                const double x[3] = {0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])};
                r = vc_flat_near(&b.s, &f, &p, seeds, 2, x, VC_FLAT_REACH * scale, VC_FLAT_SLAB * scale, 0,
                                 NULL);
                /* how much the walk's normals agree (the mean's length) */
                double m[3] = {0, 0, 0}, area = 0;
                for (int64_t i = 0; i < p.n_reached; i++) {
                    const int64_t t = p.queue[i];
                    const double *q0 = b.s.xyz + 3 * b.s.tri[3 * t], *q1 = b.s.xyz + 3 * b.s.tri[3 * t + 1],
                                 *q2 = b.s.xyz + 3 * b.s.tri[3 * t + 2];
                    const double d1[3] = {q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]};
                    const double d2[3] = {q2[0] - q0[0], q2[1] - q0[1], q2[2] - q0[2]};
                    const double c[3] = {d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
                                         d1[0] * d2[1] - d1[1] * d2[0]};
                    for (int k = 0; k < 3; k++)
                        m[k] += c[k];
                    area += sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
                }
                coherence = area > 0 ? sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]) / area : 0;
            }
            vc_flat_probe_free(&p);
        }
        vc_features_free(&f);
    }
    CHECKF(r == want, "%s: flat %d (want %d); the walk's normals agree to %.2f", name, r, want, coherence);
    vc_surface_free(&b.s);
}

int main(void)
{
    /* grid spacing 0.01 (n = 200); scale 0.02: reach 0.08, slab 0.01 from
     * a plane, 0.005 from a quadric */
    const int n = 200;
    expect_flat("plane", n, flat, 0, 0.02, 1, 100, 1000);
    expect_flat("plane, noise 0.004", n, flat, 0.004, 0.02, 1, 100, 1000);
    expect_flat("plane, noise 0.012", n, flat, 0.012, 0.02, 0, 100, 1000);
    /* 0.026 from the tangent plane at reach 0.08: curved, not creased */
    expect_flat("paraboloid", n, paraboloid, 0, 0.02, 1, 100, 1000);
    expect_flat("paraboloid, noise 0.002", n, paraboloid, 0.002, 0.02, 1, 100, 1000);
    expect_flat("paraboloid, noise 0.006", n, paraboloid, 0.006, 0.02, 0, 100, 1000);
    /* a 60-degree crease spreads 0.29 R from the plane, 0.11 R from the
     * quadric: sharp at this scale, and at half of it */
    expect_flat("roof", n, roof, 0, 0.02, 0, 100, 1000);
    expect_flat("roof, scale 0.01", n, roof, 0, 0.01, 0, 24, 400);
    expect_flat("roof, noise 0.002", n, roof, 0.002, 0.02, 0, 100, 1000);
    /* coarser: a 40 x 40 grid (spacing 0.05) has too few triangles within
     * 4 scales for a quadric, and looks twice as far: a paraboloid of
     * curvature 4 (0.05 off its tangent plane there), whose facets sag
     * 0.0025 from it, is flat; the roof is not */
    expect_flat("medium paraboloid", 40, gentle_paraboloid, 0, 0.02, 1, 24, 200);
    expect_flat("medium roof", 40, roof, 0, 0.02, 0, 24, 200);
    /* coarse: a 10 x 10 grid (spacing 0.2) takes 8 triangles even 16
     * scales out, fewer than a quadric needs: the plane decides, and the
     * paraboloid is not flat (its facets sag 0.04 from it anyway) */
    expect_flat("coarse paraboloid", 10, paraboloid, 0, 0.02, 0, 2, 23);
    expect_flat("coarse plane", 10, flat, 0, 0.02, 1, 2, 6);

    /* needles 0.0005 wide, 0.01 long (a fine UV sphere's pole): noise of
     * +-0.004 (within the slab) tips their normals 80 degrees every way,
     * their mean a small share of their area; but every one still faces up
     * from the least-squares plane: flat. The same needles on the roof are
     * not. */
    expect_flat_needles("needles, noise 0.004", 400, 20, 0.1, 0.1, flat, 0.004, 0.02, 1);
    expect_flat_needles("needles on the roof", 400, 20, 0.1, 0.1, roof, 0.004, 0.02, 0);

    if (failures) {
        fprintf(stderr, "test_feature_scale: %d failures\n", failures);
        return 1;
    }
    printf("test_feature_scale: all passed\n");
    return 0;
}
