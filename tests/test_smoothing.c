/* Tests of patch smoothing by adaptive Loop subdivision
 * (vorocrust/smoothing.h): on every reference model, the result is closed,
 * manifold and consistently oriented with the input's Euler
 * characteristic, corners are unmoved, feature detection finds the same
 * corners and creases, the smallest dihedral angle inside patches grows,
 * the enclosed volume changes little, 0 rounds is a copy, runs repeat
 * bit for bit. Known answers: one round on an icosahedron (every triangle
 * refined, Loop's vertex and edge rules), a cube (nothing to refine), a
 * 12-gon prism (closed creases stay in their planes). Bad parameters.
 * Environment: VC_MODELS (the shared models). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vorocrust/features.h"
#include "vorocrust/smoothing.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---- Small surfaces. ---- */

/* The regular icosahedron with vertices on the unit sphere, outward. */
static void make_icosahedron(builder *b)
{
    double g = (1 + sqrt(5.0)) / 2, l = sqrt(1 + g * g);
    const double v[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                             {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (int i = 0; i < 12; i++)
        add_v(b, v[i][0] / l, v[i][1] / l, v[i][2] / l);
    const int t[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                          {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                          {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int i = 0; i < 20; i++)
        add_t(b, t[i][0], t[i][1], t[i][2]);
}

/* ---- Measures. ---- */

/* Smallest dihedral angle (degrees) over the non-sharp edges; with s
 * given, *bent is the total length of those below 170 degrees. */
static double patch_dihedral(const vc_features *f, const vc_surface *s, double *bent)
{
    double best = 180;
    if (bent)
        *bent = 0;
    for (int64_t e = 0; e < f->n_edges; e++) {
        if (f->edge_sharp[e] || f->edge_tri_start[e + 1] - f->edge_tri_start[e] != 2)
            continue;
        const double *n1 = f->tri_normal + 3 * f->edge_tri[f->edge_tri_start[e]];
        const double *n2 = f->tri_normal + 3 * f->edge_tri[f->edge_tri_start[e] + 1];
        double c = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
        if (n1[0] == 0 && n1[1] == 0 && n1[2] == 0)
            continue;
        if (n2[0] == 0 && n2[1] == 0 && n2[2] == 0)
            continue;
        c = c > 1 ? 1 : c < -1 ? -1 : c;
        double d = 180 - acos(c) * 180 / M_PI;
        if (d < best)
            best = d;
        if (bent && d < 170) {
            const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
            *bent += sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
        }
    }
    return best;
}

static double min_patch_dihedral(const vc_features *f)
{
    return patch_dihedral(f, NULL, NULL);
}

static int same_surface(const vc_surface *a, const vc_surface *b)
{
    return a->n_vertices == b->n_vertices && a->n_triangles == b->n_triangles &&
           !memcmp(a->xyz, b->xyz, (size_t)(3 * a->n_vertices) * sizeof(double)) &&
           !memcmp(a->tri, b->tri, (size_t)(3 * a->n_triangles) * sizeof(int64_t));
}

typedef struct result {
    int64_t triangles;
    double min_before, min_after, volume_change;
} result;

/* Smooths s (features at theta) and checks everything that must hold on
 * any closed, oriented input; returns the figures. */
static void check_smoothing(const char *name, const vc_surface *s, double theta, int iterations,
                            double max_volume_change, result *r)
{
    vc_error err = {0};
    vc_features f, g;
    vc_surface out, again;
    vc_surface_report r0, r1;
    memset(&r0, 0, sizeof r0);
    memset(&r1, 0, sizeof r1);
    memset(r, 0, sizeof *r);
    int rc = vc_features_detect(s, theta, &f, &err);
    CHECKF(rc == 0, "%s: features: %s", name, err.msg);
    if (rc)
        return;
    rc = vc_surface_check(s, &r0, &err);
    CHECKF(rc == 0, "%s: check: %s", name, err.msg);

    /* 0 rounds: a copy. */
    rc = vc_surface_smooth(s, &f, 0, VC_SMOOTH_DEFAULT_FLAT_ANGLE, &out, &err);
    CHECKF(rc == 0 && same_surface(s, &out), "%s: 0 rounds is not a copy (rc %d %s)", name, rc, err.msg);
    vc_surface_free(&out);

    double t0 = now();
    rc = vc_surface_smooth(s, &f, iterations, VC_SMOOTH_DEFAULT_FLAT_ANGLE, &out, &err);
    double t1 = now();
    CHECKF(rc == 0, "%s: smooth: %s", name, err.msg);
    if (rc) {
        vc_features_free(&f);
        return;
    }
    rc = vc_surface_smooth(s, &f, iterations, VC_SMOOTH_DEFAULT_FLAT_ANGLE, &again, &err);
    CHECKF(rc == 0 && same_surface(&out, &again), "%s: second run differs", name);
    vc_surface_free(&again);

    rc = vc_surface_check(&out, &r1, &err);
    CHECKF(rc == 0, "%s: check of the result: %s", name, err.msg);
    CHECKF(r1.n_boundary_edges == r0.n_boundary_edges && r1.n_nonmanifold_edges == r0.n_nonmanifold_edges,
          "%s: boundary %lld -> %lld, non-manifold %lld -> %lld", name, (long long)r0.n_boundary_edges,
          (long long)r1.n_boundary_edges, (long long)r0.n_nonmanifold_edges, (long long)r1.n_nonmanifold_edges);
    CHECKF(r1.n_inconsistent_edges == 0 || r0.n_inconsistent_edges != 0, "%s: %lld inconsistent edges", name,
          (long long)r1.n_inconsistent_edges);
    CHECKF(r1.euler == r0.euler && r1.n_components == r0.n_components, "%s: Euler %lld -> %lld", name,
          (long long)r0.euler, (long long)r1.euler);
    CHECKF(r1.n_degenerate == 0 || r0.n_degenerate != 0, "%s: %lld degenerate triangles", name,
          (long long)r1.n_degenerate);
    CHECKF(out.n_vertices >= s->n_vertices, "%s: vertices lost", name);
    r->volume_change = fabs(r1.volume - r0.volume) / r0.volume;
    CHECKF(r->volume_change <= max_volume_change, "%s: volume %.6g -> %.6g", name, r0.volume, r1.volume);
    CHECKF((r0.signed_volume > 0) == (r1.signed_volume > 0), "%s: orientation flipped", name);

    rc = vc_features_detect(&out, theta, &g, &err);
    CHECKF(rc == 0, "%s: features of the result: %s", name, err.msg);
    if (rc == 0) {
        CHECKF(g.n_corners == f.n_corners && g.n_creases == f.n_creases && g.n_closed_creases == f.n_closed_creases &&
                  g.n_patches == f.n_patches,
              "%s: corners %lld -> %lld, creases %lld -> %lld (closed %lld -> %lld), patches %lld -> %lld", name,
              (long long)f.n_corners, (long long)g.n_corners, (long long)f.n_creases, (long long)g.n_creases,
              (long long)f.n_closed_creases, (long long)g.n_closed_creases, (long long)f.n_patches,
              (long long)g.n_patches);
        CHECKF(g.n_sharp_edges >= f.n_sharp_edges, "%s: sharp edges %lld -> %lld", name, (long long)f.n_sharp_edges,
              (long long)g.n_sharp_edges);
        int64_t moved = 0, lost = 0;
        for (int64_t v = 0; v < s->n_vertices; v++) {
            if (!f.vertex_corner[v])
                continue;
            if (memcmp(s->xyz + 3 * v, out.xyz + 3 * v, 3 * sizeof(double)))
                moved++;
            if (!g.vertex_corner[v])
                lost++;
        }
        CHECKF(moved == 0 && lost == 0, "%s: %lld corners moved, %lld no longer corners", name, (long long)moved,
              (long long)lost);
        /* The smallest angle can sit where the features pin the surface
         * (a bend ending at a corner): it must not get worse; the length
         * of bent edges (below 170 degrees) must shrink. */
        double bent0, bent1;
        r->min_before = patch_dihedral(&f, s, &bent0);
        r->min_after = patch_dihedral(&g, &out, &bent1);
        CHECKF(r->min_after >= r->min_before, "%s: min dihedral in patches %.3f -> %.3f", name, r->min_before,
              r->min_after);
        CHECKF(bent0 == 0 || bent1 < bent0, "%s: bent length %.4g -> %.4g", name, bent0, bent1);
        r->triangles = out.n_triangles;
        printf("%-16s theta %4.0f: triangles %7lld -> %8lld, vertices %7lld -> %8lld, min patch dihedral %7.3f -> "
               "%7.3f deg, bent (<170) length %.4g -> %.4g, volume %+.3f%%, corners %lld, creases %lld, %.2f s\n",
               name, theta, (long long)s->n_triangles, (long long)out.n_triangles, (long long)s->n_vertices,
               (long long)out.n_vertices, r->min_before, r->min_after, bent0, bent1,
               100 * (r1.volume - r0.volume) / r0.volume, (long long)g.n_corners, (long long)g.n_creases, t1 - t0);
        vc_features_free(&g);
    }
    vc_surface_free(&out);
    vc_features_free(&f);
}

/* ---- Reference models. ---- */

static void test_models(const char *models)
{
    const struct {
        const char *file;
        double theta;
    } cases[] = {
        {"cube.off", 60},       {"onebox.obj", 60},    {"bracket.obj", 60},  {"bracket.obj", 23},
        {"sphere.obj", 60},     {"torus.obj", 60},     {"fertility.off", 60}, {"fandisk.off", 60},
        {"bumpy-cube.obj", 60},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", models, cases[i].file);
        vc_surface s;
        vc_error err = {0};
        if (vc_surface_read(path, &s, NULL, &err)) {
            CHECKF(0, "%s: %s", path, err.msg);
            continue;
        }
        result r;
        check_smoothing(cases[i].file, &s, cases[i].theta, VC_SMOOTH_DEFAULT_ITERATIONS, 0.03, &r);
        if (!strcmp(cases[i].file, "cube.off") || !strcmp(cases[i].file, "onebox.obj")) {
            /* Flat faces: nothing to refine, the surface comes back. */
            vc_features f;
            vc_surface out;
            if (vc_features_detect(&s, cases[i].theta, &f, &err) == 0) {
                int rc = vc_surface_smooth(&s, &f, 6, 175, &out, &err);
                CHECKF(rc == 0 && same_surface(&s, &out), "%s: changed", cases[i].file);
                vc_surface_free(&out);
                vc_features_free(&f);
            }
        }
        vc_surface_free(&s);
    }
}

/* ---- Known answers. ---- */

static void test_icosahedron(void)
{
    builder b = {0};
    make_icosahedron(&b);
    vc_features f;
    vc_error err = {0};
    /* At 60 degrees every vertex is a sector corner (normals of
     * non-adjacent triangles around a vertex differ by 70.5 degrees); at
     * 80 nothing is sharp. */
    int rc = vc_features_detect(&b.s, 80, &f, &err);
    CHECKF(rc == 0 && f.n_corners == 0 && f.n_sharp_edges == 0, "icosahedron: %lld corners", (long long)f.n_corners);
    if (rc)
        return;
    vc_surface out;
    rc = vc_surface_smooth(&b.s, &f, 1, 175, &out, &err);
    CHECKF(rc == 0 && out.n_triangles == 80 && out.n_vertices == 42, "icosahedron: one round gives %lld triangles",
          (long long)out.n_triangles);
    if (rc == 0) {
        /* Vertex rule, valence 5: v' = (1 - 5 beta) v + beta sum; by
         * symmetry the sum of the 5 neighbours is 5 cos(63.43 deg) v =
         * sqrt(5) v for unit vertices. Edge rule: 3/8 (a + b) + 1/8 (c + d). */
        double c = 0.375 + 0.25 * cos(2 * M_PI / 5), beta = (0.625 - c * c) / 5;
        double scale = 1 - 5 * beta + beta * sqrt(5.0);
        double err_v = 0;
        for (int v = 0; v < 12; v++)
            for (int k = 0; k < 3; k++)
                err_v = fmax(err_v, fabs(out.xyz[3 * v + k] - scale * b.s.xyz[3 * v + k]));
        CHECKF(err_v < 1e-12, "icosahedron: vertex rule off by %g", err_v);
        /* Edge points: all at the same distance from the centre. */
        double r0 = -1, spread = 0;
        for (int64_t v = 12; v < out.n_vertices; v++) {
            const double *p = out.xyz + 3 * v;
            double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            if (r0 < 0)
                r0 = r;
            spread = fmax(spread, fabs(r - r0));
        }
        /* Edge a b with opposite c d: 3/4 (mid of a b) + 1/4 (mid of c d);
         * |a + b| = 2 cos(31.72 deg), c + d = (a + b) * (cos of c, d to
         * the edge mid axis) -> checked through the spread and a value. */
        CHECKF(spread < 1e-12, "icosahedron: edge points spread %g", spread);
        vc_surface_free(&out);
    }
    vc_features_free(&f);
    result r;
    check_smoothing("icosahedron", &b.s, 80, 6, 0.5, &r);
    /* Loop's limit of the icosahedron is well inside the sphere: volume
     * grows from 2.536 (icosahedron) but stays below 4.19 (unit ball). */
    free(b.s.xyz);
    free(b.s.tri);
}

static void test_prism(void)
{
    builder b = {0};
    make_prism(&b, 12, 1.0);
    vc_features f;
    vc_error err = {0};
    int rc = vc_features_detect(&b.s, 60, &f, &err);
    CHECKF(rc == 0 && f.n_corners == 0 && f.n_creases == 2 && f.n_closed_creases == 2 && f.n_patches == 3,
          "prism: %lld corners, %lld creases", (long long)f.n_corners, (long long)f.n_creases);
    if (rc)
        return;
    vc_surface out;
    rc = vc_surface_smooth(&b.s, &f, 6, 175, &out, &err);
    CHECKF(rc == 0, "prism: %s", err.msg);
    if (rc == 0) {
        vc_features g;
        rc = vc_features_detect(&out, 60, &g, &err);
        CHECKF(rc == 0 && g.n_creases == 2 && g.n_closed_creases == 2 && g.n_corners == 0, "prism after: %lld creases",
              (long long)g.n_creases);
        if (rc == 0) {
            /* The creases stay in their cap planes and inside the input
             * polygon (B-spline of a convex polygon); the caps stay flat. */
            int64_t off = 0;
            double rmin = 2;
            for (int64_t c = 0; c < g.n_creases; c++) {
                const int64_t *cv = vc_crease_vertices(&g, c);
                for (int64_t i = 0; i <= vc_crease_n_edges(&g, c); i++) {
                    const double *p = out.xyz + 3 * cv[i];
                    double rr = sqrt(p[0] * p[0] + p[1] * p[1]);
                    if (!(p[2] == 0 || p[2] == 1) || rr > 1 + 1e-12)
                        off++;
                    rmin = fmin(rmin, rr);
                }
            }
            /* Cubic B-spline of the regular 12-gon: radius between
             * (2 + cos 30) / 3 = 0.9553 and the polygon. */
            CHECKF(off == 0 && rmin > 0.955, "prism: %lld crease vertices off their plane, min radius %.4f",
                  (long long)off, rmin);
            printf("prism 12: triangles %lld -> %lld, crease radius min %.4f, min patch dihedral %.3f -> %.3f\n",
                   (long long)b.s.n_triangles, (long long)out.n_triangles, rmin, min_patch_dihedral(&f),
                   min_patch_dihedral(&g));
            vc_features_free(&g);
        }
        vc_surface_free(&out);
    }
    vc_features_free(&f);
    result r;
    check_smoothing("prism 12", &b.s, 60, 6, 0.05, &r);
    free(b.s.xyz);
    free(b.s.tri);
}

static void test_bad_parameters(void)
{
    builder b = {0};
    make_icosahedron(&b);
    vc_features f;
    vc_error err = {0};
    if (vc_features_detect(&b.s, 80, &f, &err))
        return;
    vc_surface out;
    int rc = vc_surface_smooth(&b.s, &f, -1, 175, &out, &err);
    CHECKF(rc == VC_EPARAM && out.xyz == NULL && strstr(err.msg, "iterations"), "iterations -1: %d", rc);
    rc = vc_surface_smooth(&b.s, &f, VC_SMOOTH_MAX_ITERATIONS + 1, 175, &out, &err);
    CHECKF(rc == VC_EPARAM, "too many iterations: %d", rc);
    const double bad[] = {0, -5, 180.5, NAN, INFINITY};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        rc = vc_surface_smooth(&b.s, &f, 6, bad[i], &out, &err);
        CHECKF(rc == VC_EPARAM && out.xyz == NULL && strstr(err.msg, "flat angle"), "flat angle %g: %d", bad[i], rc);
    }
    rc = vc_surface_smooth(&b.s, NULL, 6, 175, &out, &err);
    CHECKF(rc == VC_EPARAM, "no features: %d", rc);
    b.s.n_triangles--;
    rc = vc_surface_smooth(&b.s, &f, 6, 175, &out, &err);
    CHECKF(rc == VC_EPARAM && strstr(err.msg, "another surface"), "features of another surface: %d %s", rc, err.msg);
    b.s.n_triangles++;
    /* 180: uniform Loop, every triangle refined each round. */
    rc = vc_surface_smooth(&b.s, &f, 2, 180, &out, &err);
    CHECKF(rc == 0 && out.n_triangles == 320, "flat angle 180: %lld triangles", (long long)out.n_triangles);
    vc_surface_free(&out);
    vc_features_free(&f);
    free(b.s.xyz);
    free(b.s.tri);
}

/* An open surface (an icosahedron without one triangle): the boundary
 * edges are crease edges, the hole is kept. */
static void test_open(void)
{
    builder b = {0};
    make_icosahedron(&b);
    b.s.n_triangles--;
    vc_features f;
    vc_error err = {0};
    if (vc_features_detect(&b.s, 80, &f, &err) == 0) {
        CHECKF(f.n_boundary_edges == 3 && f.n_corners == 3, "open: %lld boundary edges, %lld corners",
              (long long)f.n_boundary_edges, (long long)f.n_corners);
        vc_surface out;
        int rc = vc_surface_smooth(&b.s, &f, 6, 175, &out, &err);
        CHECKF(rc == 0, "open: %s", err.msg);
        if (rc == 0) {
            vc_surface_report r;
            memset(&r, 0, sizeof r);
            rc = vc_surface_check(&out, &r, &err);
            CHECKF(rc == 0 && r.n_boundary_edges > 3 && r.n_nonmanifold_edges == 0 && r.n_inconsistent_edges == 0 &&
                      r.euler == 1,
                  "open: boundary %lld, euler %lld", (long long)r.n_boundary_edges, (long long)r.euler);
            vc_features g;
            if (vc_features_detect(&out, 80, &g, &err) == 0) {
                CHECKF(g.n_corners == 3 && g.n_creases == 3, "open after: %lld corners %lld creases",
                      (long long)g.n_corners, (long long)g.n_creases);
                vc_features_free(&g);
            }
            vc_surface_free(&out);
        }
        vc_features_free(&f);
    }
    free(b.s.xyz);
    free(b.s.tri);
}

int main(void)
{
    const char *models = getenv("VC_MODELS");
    test_bad_parameters();
    test_icosahedron();
    test_prism();
    test_open();
    if (models)
        test_models(models);
    else
        CHECKF(0, "VC_MODELS is not set");
    if (failures) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    printf("test_smoothing: all passed\n");
    return 0;
}
