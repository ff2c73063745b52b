/* Short-edge protection of interior seeds (vc_interior_protect) and pole
 * seeds (vc_interior_sphere_seeds: poles and caps), on seed sets built here:
 * - random interior seeds inside a shell of fixed "surface" seeds: the
 *   Voronoi mesh before and after, its cells' shortest edges over their
 *   radius (the share below 1e-2 falls from about 40% to almost none), the
 *   fixed seeds untouched, every moved seed within its picking region, the
 *   same seeds on 1 and 2 threads, no move into a ball;
 * - a pole seed in a cluster made to be near-co-spherical moves, and stays
 *   on its ball's sphere;
 * - the pole seeds of a row of balls on a plane: one below each ball, on
 *   its sphere, outside the others, labelled as the inside seeds;
 * - the caps of a corner ball ringed by small balls (caps_of_a_corner). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"
#include "test_seed_shell.h"
#include "vorocrust/interior.h"
#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

/* Per cell of m, the shortest edge over the largest distance from the
 * cell's seed to a vertex; returns how many cells have it below limit
 * (cells of seeds with index >= first only), the smallest into *min. */
static int64_t short_cells(const vc_polymesh *m, int64_t first, double limit, double *min)
{
    int64_t n = 0;
    *min = INFINITY;
    for (int64_t c = 0; c < m->n_cells; c++) {
        if (m->cell_seed[c] < first)
            continue;
        const double *s = m->seed_xyz + 3 * m->cell_seed[c];
        double r2 = 0, e2 = INFINITY;
        for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; k++) {
            const int64_t f = m->cell_faces[k], f0 = m->face_offsets[f], f1 = m->face_offsets[f + 1];
            for (int64_t j = f0; j < f1; j++) {
                const double *p = m->points + 3 * m->face_vertices[j];
                const double *q = m->points + 3 * m->face_vertices[j + 1 < f1 ? j + 1 : f0];
                double d2 = 0, l2 = 0;
                for (int d = 0; d < 3; d++) {
                    d2 += (p[d] - s[d]) * (p[d] - s[d]);
                    l2 += (p[d] - q[d]) * (p[d] - q[d]);
                }
                r2 = d2 > r2 ? d2 : r2;
                e2 = l2 < e2 ? l2 : e2;
            }
        }
        const double rel = sqrt(e2 / r2);
        n += rel < limit;
        *min = rel < *min ? rel : *min;
    }
    return n;
}

static void random_interior(void)
{
    const int64_t n_surface = 800, n_int = 3000;
    vc_seeds before, one, two;
    shell_seeds(&before, n_surface, n_int, 7, 1);
    shell_seeds(&one, n_surface, n_int, 7, 1);
    shell_seeds(&two, n_surface, n_int, 7, 1);
    /* one small ball near the middle: no seed may move into it */
    double centre[3] = {0.05, -0.02, 0.03}, radius = 0.02, normal[3] = {0, 0, 1};
    signed char kind = 0;
    int64_t element = 0;
    vc_balls balls = {1, centre, &radius, &kind, &element, normal};

    vc_protect_options po;
    vc_protect_options_default(&po);
    CHECK(po.min_edge == 0.01);
    vc_protect_stats st1, st2;
    vc_error err;
    po.threads = 1;
    CHECK(vc_interior_protect(&balls, &one, n_surface, &po, &st1, &err) == 0);
    po.threads = 2;
    CHECK(vc_interior_protect(&balls, &two, n_surface, &po, &st2, &err) == 0);
    CHECK(memcmp(one.xyz, two.xyz, sizeof(double) * 3 * (size_t)one.n) == 0);
    CHECK(memcmp(before.xyz, one.xyz, sizeof(double) * 3 * (size_t)n_surface) == 0);
    CHECKF(st1.n_short_before > n_int / 5 && st1.n_short_after < st1.n_short_before / 10,
           "%lld seeds below before, %lld after", (long long)st1.n_short_before,
           (long long)st1.n_short_after);
    CHECK(st1.n_moved > 0 && st1.n_moves >= st1.n_moved && st1.n_checked == n_int);

    /* moves within a quarter of the distance to the nearest seed */
    int64_t far = 0, in_ball = 0;
    for (int64_t i = n_surface; i < before.n; i++) {
        double nn2 = INFINITY, mv2 = 0, b2 = 0;
        for (int64_t j = 0; j < before.n; j++) {
            if (j == i)
                continue;
            double d2 = 0;
            for (int d = 0; d < 3; d++)
                d2 += (before.xyz[3 * i + d] - before.xyz[3 * j + d]) *
                      (before.xyz[3 * i + d] - before.xyz[3 * j + d]);
            nn2 = d2 < nn2 ? d2 : nn2;
        }
        for (int d = 0; d < 3; d++) {
            mv2 += (before.xyz[3 * i + d] - one.xyz[3 * i + d]) *
                   (before.xyz[3 * i + d] - one.xyz[3 * i + d]);
            b2 += (one.xyz[3 * i + d] - centre[d]) * (one.xyz[3 * i + d] - centre[d]);
        }
        far += mv2 > 0.0625 * nn2 * (1 + 1e-12);
        in_ball += mv2 > 0 && b2 <= radius * radius * (1 + 4 * po.min_edge);
    }
    CHECKF(far == 0, "%lld seeds moved beyond their picking region", (long long)far);
    CHECKF(in_ball == 0, "%lld seeds moved into the ball", (long long)in_ball);

    /* the meshes: interior cells with an edge below 1e-2 of their radius */
    vc_polymesh ma, mb;
    if (shell_build(&before, &ma) == 0 && shell_build(&one, &mb) == 0) {
        double min_a, min_b;
        const int64_t na = short_cells(&ma, n_surface, 1e-2, &min_a);
        const int64_t nb = short_cells(&mb, n_surface, 1e-2, &min_b);
        printf("random interior: %lld seeds below the target, %lld after; cells with an edge below 1e-2 of the radius %lld -> %lld of %lld, "
               "shortest %.3g -> %.3g; %lld moves of %lld seeds, %lld cells measured\n",
               (long long)st1.n_short_before, (long long)st1.n_short_after,
               (long long)na, (long long)nb, (long long)n_int, min_a, min_b,
               (long long)st1.n_moves, (long long)st1.n_moved, (long long)st1.n_measures);
        CHECKF(na > n_int / 5, "random seeds: only %lld short cells before", (long long)na);
        CHECKF(nb <= n_int / 50, "%lld of %lld cells still have an edge below 1e-2", (long long)nb,
               (long long)n_int);
        CHECKF(min_b > 10 * min_a && min_b > 1e-4, "shortest %.3g before, %.3g after", min_a, min_b);
        /* the same volume: the seeds moved inside the box the cells fill */
        double va = 0, vb = 0;
        for (int64_t c = 0; c < ma.n_cells; c++)
            va += ma.cell_volume[c];
        for (int64_t c = 0; c < mb.n_cells; c++)
            vb += mb.cell_volume[c];
        CHECKF(fabs(va - vb) <= 1e-9 * va, "volumes %.17g and %.17g", va, vb);
        vc_polymesh_free(&mb);
    }
    vc_polymesh_free(&ma);
    vc_seeds_free(&before);
    vc_seeds_free(&one);
    vc_seeds_free(&two);
}

/* A pole seed in a near-tie moves, on its sphere. */
static void pole_on_sphere(void)
{
    /* ball 0 at the origin, radius 1, its pole at (0, 0, -1); four fixed
     * seeds on the circle z = -0.6, r = 0.8 of its sphere (a tie with the
     * pole at the centre: one vertex), and four on the sphere of radius
     * 0.8 about (0, 0, -1.8), which passes through the pole, at different
     * heights (no four on one circle), the last one 1e-4 off it: five
     * seeds nearly on one empty sphere, a short edge */
    vc_error err;
    vc_seeds s;
    CHECK(vc_seeds_alloc(&s, 9, &err) == 0);
    /* the last four: polar angles 120, 80, 110, 130 degrees from +z about
     * (0, 0, -1.8), azimuths 0, 90, 180, 270 */
    const double d = 3.14159265358979323846 / 180, c0 = -1.8;
    const double fixed[8][3] = {
        {0.8, 0, -0.6}, {0, 0.8, -0.6}, {-0.8, 0, -0.6}, {0, -0.8, -0.6},
        {0.8 * sin(120 * d), 0, c0 + 0.8 * cos(120 * d)},
        {0, 0.8 * sin(80 * d), c0 + 0.8 * cos(80 * d)},
        {-0.8 * sin(110 * d), 0, c0 + 0.8 * cos(110 * d)},
        {0, -0.8 * (1 + 1e-4) * sin(130 * d), c0 + 0.8 * (1 + 1e-4) * cos(130 * d)}};
    for (int i = 0; i < 8; i++)
        memcpy(s.xyz + 3 * i, fixed[i], sizeof fixed[i]);
    s.xyz[24] = 0;
    s.xyz[25] = 0;
    s.xyz[26] = -1;
    for (int i = 0; i < 9; i++)
        s.label[i] = 1;
    double centre[3] = {0, 0, 0}, radius = 1, normal[3] = {0, 0, 1};
    signed char kind = 0;
    int64_t element = 0;
    vc_balls balls = {1, centre, &radius, &kind, &element, normal};
    const int64_t pole_ball = 0;
    vc_protect_options po;
    vc_protect_options_default(&po);
    po.n_poles = 1;
    po.pole_ball = &pole_ball;
    vc_protect_stats st;
    CHECK(vc_interior_protect(&balls, &s, 8, &po, &st, &err) == 0);
    const double *q = s.xyz + 24;
    const double r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    printf("pole: measure (target %g) %.3g -> %.3g, %lld moves, at (%.4f %.4f %.4f)\n", po.min_edge, st.min_edge_before,
           st.min_edge_after, (long long)st.n_moves, q[0], q[1], q[2]);
    CHECK(st.n_checked == 1 && st.n_short_before == 1 && st.min_edge_before < 1e-3);
    CHECK(st.n_moves >= 1 && st.n_short_after == 0 && st.min_edge_after >= po.min_edge);
    CHECKF(fabs(r - 1) < 1e-12, "the pole left its sphere: radius %.17g", r);
    CHECK(memcmp(s.xyz, fixed, sizeof fixed) == 0);
    /* options refused */
    po.min_edge = 0.3;
    CHECK(vc_interior_protect(&balls, &s, 8, &po, &st, &err) == VC_EPARAM);
    po.min_edge = 0.01;
    po.n_poles = 2;
    CHECK(vc_interior_protect(&balls, &s, 8, &po, &st, &err) == VC_EPARAM);
    vc_seeds_free(&s);
}

/* Pole seeds of a row of five balls on the plane z = 0 (outward normal
 * +z): the inside surface seeds below the plane, the outside ones above. */
static void poles_of_a_row(void)
{
    double centre[15], radius[5], normal[15];
    signed char kind[5] = {0};
    int64_t element[5] = {0};
    for (int i = 0; i < 5; i++) {
        kind[i] = VC_BALL_SURFACE;
        centre[3 * i] = i;
        centre[3 * i + 1] = centre[3 * i + 2] = 0;
        radius[i] = 0.7;
        normal[3 * i] = normal[3 * i + 1] = 0;
        normal[3 * i + 2] = 1;
    }
    vc_balls balls = {5, centre, radius, kind, element, normal};
    /* surface seeds: where neighbouring spheres meet, above and below */
    vc_error err;
    vc_seeds surf;
    CHECK(vc_seeds_alloc(&surf, 8, &err) == 0);
    const double h = sqrt(0.49 - 0.25);
    for (int i = 0; i < 4; i++)
        for (int side = 0; side < 2; side++) {
            double *x = surf.xyz + 3 * (2 * i + side);
            x[0] = i + 0.5;
            x[1] = 0;
            x[2] = side ? h : -h;
            surf.label[2 * i + side] = side ? 0 : 3;
        }
    vc_seeds poles;
    int64_t *ball_of = NULL;
    vc_sphere_seed_options so;
    vc_sphere_seed_options_default(&so);
    CHECK(so.caps == 1 && so.poles == 0);
    so.poles = 1;
    so.pole_gap = 0.04;
    so.caps = 1; /* surface balls: no caps */
    CHECK(vc_interior_sphere_seeds(&balls, &surf, &so, &poles, &ball_of, &err) == 0);
    CHECKF(poles.n == 5, "%lld poles", (long long)poles.n);
    for (int64_t k = 0; k < poles.n && ball_of; k++) {
        const double *q = poles.xyz + 3 * k, *c = centre + 3 * ball_of[k];
        CHECK(ball_of[k] == k);
        CHECK(poles.label[k] == 3);
        CHECK(fabs(q[0] - c[0]) < 1e-15 && fabs(q[1]) < 1e-15 && fabs(q[2] + 0.7) < 1e-15);
        for (int j = 0; j < 5; j++) {
            if (j == ball_of[k])
                continue;
            const double d2 = (q[0] - centre[3 * j]) * (q[0] - centre[3 * j]) + q[2] * q[2];
            CHECK(d2 > (1 + 0.04) * radius[j] * radius[j]);
        }
    }
    free(ball_of);
    vc_seeds_free(&poles);
    /* a bad gap */
    so.pole_gap = 1.5;
    CHECK(vc_interior_sphere_seeds(&balls, &surf, &so, &poles, &ball_of, &err) == VC_EPARAM);
    vc_seeds_free(&surf);
}

/* Caps: a corner ball of radius 1 at the origin (normal +z) with a ring of
 * 16 small surface balls (radius 0.15) around its equator; the surface
 * seeds on the corner's sphere where the ring crosses it, inside ones
 * (label 1) below the equator, outside ones above. The caps lie on the
 * corner's sphere, inside (below), outside every ring ball by the interior
 * clearance, at least half a radius from every surface seed and a quarter
 * radius from each other; none without caps or for a surface ball. */
static void caps_of_a_corner(void)
{
    enum { RING = 16 };
    double centre[3 * (RING + 1)], radius[RING + 1], normal[3 * (RING + 1)];
    signed char kind[RING + 1];
    int64_t element[RING + 1] = {0};
    const double pi = acos(-1.0);
    centre[0] = centre[1] = centre[2] = 0;
    radius[0] = 1;
    kind[0] = VC_BALL_CORNER;
    for (int i = 0; i <= RING; i++) {
        normal[3 * i] = normal[3 * i + 1] = 0;
        normal[3 * i + 2] = 1;
        if (i == 0)
            continue;
        const double a = 2 * pi * (i - 1) / RING;
        centre[3 * i] = cos(a);
        centre[3 * i + 1] = sin(a);
        centre[3 * i + 2] = 0;
        radius[i] = 0.15;
        kind[i] = VC_BALL_SURFACE;
    }
    vc_balls balls = {RING + 1, centre, radius, kind, element, normal};
    vc_error err;
    vc_seeds surf;
    CHECK(vc_seeds_alloc(&surf, 2 * RING, &err) == 0);
    for (int i = 0; i < RING; i++)
        for (int side = 0; side < 2; side++) {
            /* on the corner's sphere, between two ring balls, 0.1 off the
             * equator */
            const double a = 2 * pi * (i + 0.5) / RING, z = side ? 0.1 : -0.1, rr = sqrt(1 - z * z);
            double *x = surf.xyz + 3 * (2 * i + side);
            x[0] = rr * cos(a);
            x[1] = rr * sin(a);
            x[2] = z;
            surf.label[2 * i + side] = side ? 0 : 1;
        }
    vc_sphere_seed_options so;
    vc_sphere_seed_options_default(&so);
    vc_seeds caps;
    int64_t *ball_of = NULL;
    CHECK(vc_interior_sphere_seeds(&balls, &surf, &so, &caps, &ball_of, &err) == 0);
    CHECKF(caps.n >= 8, "%lld caps", (long long)caps.n);
    for (int64_t k = 0; k < caps.n && ball_of; k++) {
        const double *q = caps.xyz + 3 * k;
        CHECK(ball_of[k] == 0 && caps.label[k] == 1 && q[2] < 0);
        CHECK(fabs(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) - 1) < 1e-12);
        for (int j = 1; j <= RING; j++) {
            const double *c = centre + 3 * j;
            const double d = sqrt((q[0] - c[0]) * (q[0] - c[0]) + (q[1] - c[1]) * (q[1] - c[1]) +
                                  (q[2] - c[2]) * (q[2] - c[2]));
            CHECKF(d > (1 + VC_INTERIOR_CLEARANCE) * radius[j], "cap %lld at %g of ring ball %d",
                   (long long)k, d / radius[j], j);
        }
        for (int64_t i = 0; i < surf.n; i++) {
            const double *x = surf.xyz + 3 * i;
            CHECK((q[0] - x[0]) * (q[0] - x[0]) + (q[1] - x[1]) * (q[1] - x[1]) +
                      (q[2] - x[2]) * (q[2] - x[2]) >= 0.25);
        }
        for (int64_t m = 0; m < k; m++) {
            const double *p = caps.xyz + 3 * m;
            CHECK((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                      (q[2] - p[2]) * (q[2] - p[2]) >= 0.25 * 0.25);
        }
    }
    printf("caps of a corner ball: %lld\n", (long long)caps.n);
    free(ball_of);
    vc_seeds_free(&caps);
    /* none without caps, none on a surface ball */
    so.caps = 0;
    CHECK(vc_interior_sphere_seeds(&balls, &surf, &so, &caps, &ball_of, &err) == 0 && caps.n == 0 &&
          !ball_of);
    so.caps = 1;
    kind[0] = VC_BALL_SURFACE;
    CHECK(vc_interior_sphere_seeds(&balls, &surf, &so, &caps, &ball_of, &err) == 0 && caps.n == 0 &&
          !ball_of);
    vc_seeds_free(&surf);
}

int main(void)
{
    random_interior();
    pole_on_sphere();
    poles_of_a_row();
    caps_of_a_corner();
    if (failures)
        fprintf(stderr, "test_protect_seeds: %d failure(s)\n", failures);
    return failures != 0;
}
