/* The flat-ground test that judges folds at the error bound
 * (vorocrust/surface/feature_scale.c): on height fields over a grid, noise
 * on a plane and on a curved patch is flat at a scale well above it, a
 * 60-degree crease is not, with or without noise; a coarser grid is
 * looked at farther, and a coarse fold (too few triangles for a quadric
 * even then) is judged by the plane alone; a needle's folds smaller than
 * the bound are noise on any coherent ground. And the converse: folds
 * below theta_sharp whose triangles leave each other's plane by more than
 * VC_VISIBLE_FOLD bounds are creases, the others not. */
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

/* waves of 0.012 and wavelength 0.16: within four bounds of a point (the
 * bounds below) the ground strays from a plane and a quadric by more than
 * their slabs */
static double wavy(double x, double y)
{
    return 0.012 * sin(40 * x) * cos(40 * y);
}

/* The wavy field, 200 x 200 cells over [-1, 1]^2, with a needle planted
 * in the cell (i0, j0): its triangle (a, b, c) (a b its edge along x,
 * 0.01 long) split at m, 2e-7 off the middle of a b towards c and lifted
 * so that the needle (a, b, m) leans 70 degrees from its neighbours (a
 * marching-cubes sliver). Features judged at scale: the needle's three
 * folds must be noise (want_noise) or sharp, and a, b, m corners or not
 * accordingly. */
static void expect_needle(const char *name, double scale, int want_noise)
{
    const int n = 200, i0 = n / 2 + 3, j0 = n / 2 + 3;
    builder b = {0};
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
            add_v(&b, x, y, wavy(x, y));
        }
    int64_t na = -1, nb = -1, nm = -1;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            const int64_t a = (int64_t)j * (n + 1) + i, c = a + n + 2;
            if (i != i0 || j != j0) {
                add_q(&b, a, a + 1, c, a + n + 1);
                continue;
            }
            const double *pa = b.s.xyz + 3 * a, *pb = b.s.xyz + 3 * (a + 1), *pc = b.s.xyz + 3 * c;
            const double ab[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
            const double ac[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
            double nn[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                            ab[0] * ac[1] - ab[1] * ac[0]};
            const double ln = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            for (int k = 0; k < 3; k++)
                nn[k] /= ln;
            double tw[3] = {nn[1] * ab[2] - nn[2] * ab[1], nn[2] * ab[0] - nn[0] * ab[2],
                            nn[0] * ab[1] - nn[1] * ab[0]};
            const double lt = sqrt(tw[0] * tw[0] + tw[1] * tw[1] + tw[2] * tw[2]);
            const double w = 2e-7, up = w * tan(70 * M_PI / 180);
            double m[3];
            for (int k = 0; k < 3; k++)
                m[k] = 0.5 * (pa[k] + pb[k]) + w * tw[k] / lt + up * nn[k];
            nm = add_v(&b, m[0], m[1], m[2]);
            na = a;
            nb = a + 1;
            add_t(&b, a, a + 1, nm);
            add_t(&b, a + 1, c, nm);
            add_t(&b, c, a, nm);
            add_t(&b, a, c, a + n + 1);
        }
    vc_features f;
    vc_error err;
    if (vc_features_detect_scaled(&b.s, 60, NULL, scale, &f, &err)) {
        CHECKF(0, "%s: %s", name, err.msg);
        vc_surface_free(&b.s);
        return;
    }
    const int64_t e[3] = {vc_features_find_edge(&f, na, nb), vc_features_find_edge(&f, na, nm),
                          vc_features_find_edge(&f, nb, nm)};
    int sharp = 0;
    for (int k = 0; k < 3; k++)
        sharp += e[k] >= 0 && f.edge_sharp[e[k]] != 0;
    const int corners = (f.vertex_corner[na] != 0) + (f.vertex_corner[nb] != 0) + (f.vertex_corner[nm] != 0);
    /* the ground is not flat there by the plane or the quadric: the rule
     * for networks smaller than the bound decides */
    vc_flat_probe p;
    int flat = -1;
    if (e[0] >= 0 && vc_flat_probe_init(&p, b.s.n_triangles) == 0) {
        const int64_t seeds[2] = {f.edge_tri[f.edge_tri_start[e[0]]], f.edge_tri[f.edge_tri_start[e[0]] + 1]};
        const double *pa = b.s.xyz + 3 * na, *pb = b.s.xyz + 3 * nb;
        const double x[3] = {0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])};
        flat = vc_flat_near(&b.s, &f, &p, seeds, 2, x, VC_FLAT_REACH * scale, VC_FLAT_SLAB * scale, 0, NULL);
        vc_flat_probe_free(&p);
    }
    CHECKF(flat == 0, "%s: the ground at the needle is flat (%d): the test would not test the rule", name, flat);
    if (want_noise)
        CHECKF(sharp == 0 && corners == 0 && f.n_sharp_noise >= 3,
               "%s: %d of the needle's folds sharp, %d corners, %lld folds judged noise (want 0, 0, >= 3)",
               name, sharp, corners, (long long)f.n_sharp_noise);
    else
        CHECKF(sharp == 3 && corners > 0, "%s: %d of the needle's folds sharp, %d corners (want 3, > 0)", name,
               sharp, corners);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

/* The folds the error bound sees (features.h, VC_VISIBLE_FOLD): a 12-gon
 * prism of radius 1 and height 3 folds by 30 degrees along its 12 side
 * edges, and the triangles beside each are a chord 2 sin(15 deg) = 0.518
 * wide: the far side of each leaves the other's plane by sin(30 deg) times
 * that, 0.259, which is 8 bounds at a bound of 0.0324. Below that bound
 * the 12 side edges are creases, above it they are not; the quads'
 * diagonals (no fold) never are, nor the rims (sharp by angle anyway). */
static void expect_visible_folds(double theta, double scale, int64_t want)
{
    builder b = {0};
    make_prism(&b, 12, 3.0);
    vc_features f;
    vc_error err = {0};
    CHECK(vc_features_detect_scaled(&b.s, theta, NULL, scale, &f, &err) == 0);
    int64_t folds = 0, angle = 0;
    for (int64_t e = 0; e < f.n_edges; e++) {
        folds += f.edge_sharp[e] == VC_SHARP_FOLD;
        angle += f.edge_sharp[e] == VC_SHARP_ANGLE;
    }
    CHECKF(f.n_sharp_visible == want && folds == want,
           "12-gon prism at %g degrees, bound %g: %lld folds seen (%lld marked), want %lld",
           theta, scale, (long long)f.n_sharp_visible, (long long)folds, (long long)want);
    /* the rims, and at 20 degrees the side edges, by angle */
    CHECKF(angle == (theta < 30 ? 36 : 24), "12-gon prism at %g degrees: %lld sharp by angle", theta,
           (long long)angle);
    CHECKF(f.n_sharp_edges == angle + want, "12-gon prism: %lld sharp edges", (long long)f.n_sharp_edges);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

int main(void)
{
    expect_visible_folds(60, 0.030, 12);
    expect_visible_folds(60, 0.034, 0);
    expect_visible_folds(60, 0, 0);
    expect_visible_folds(20, 0.030, 0);

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

    /* A marching-cubes needle (folds of 70 degrees, a network 0.01 wide)
     * on wavy ground: below the bound 0.02 it is noise, however curved the
     * ground; at a bound of 0.009 it is wider than the bound, a feature */
    expect_needle("needle on waves, bound 0.02", 0.02, 1);
    expect_needle("needle on waves, bound 0.009", 0.009, 0);

    if (failures) {
        fprintf(stderr, "test_feature_scale: %d failures\n", failures);
        return 1;
    }
    printf("test_feature_scale: all passed\n");
    return 0;
}
