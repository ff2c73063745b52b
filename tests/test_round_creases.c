/* Rounds narrower than the error bound become creases
 * (vorocrust/surface/round_creases.c): a wedge whose tip is rounded to a
 * fifth of the bound, extruded, gets one crease along the middle of the
 * round, on one row of edges all along (with the round split into an even
 * number of facets, the apex row; an odd number, one of the two middle
 * rows, the same one everywhere), its band's triangles take their flank's
 * normal; at a bound no larger than the round nothing changes, nor on a
 * cylinder as wide as the bound; a concave round (an L's inner corner)
 * is found as a convex one is. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "vorocrust/features.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

/* The closed profile of a wedge (flanks at +-beta from the -x axis, length
 * flank back from the round) whose tip is an arc of radius rho about the
 * origin in k facets, closed by a straight back; counter-clockwise. */
static int profile(double rho, double beta, int k, double flank, double *xy, int *tip_first)
{
    int n = 0;
    const double sb = sin(beta), cb = cos(beta);
    /* the lower flank's back end, then along it to the round */
    for (int i = 0; i < 8; i++) {
        const double s = flank * (1 - i / 8.0);
        xy[2 * n] = rho * sb - s * cb;
        xy[2 * n + 1] = -rho * cb - s * sb;
        n++;
    }
    *tip_first = n;
    const double a0 = -(M_PI / 2 - beta), a1 = M_PI / 2 - beta;
    for (int j = 0; j <= k; j++) {
        const double a = a0 + (a1 - a0) * j / k;
        xy[2 * n] = rho * cos(a);
        xy[2 * n + 1] = rho * sin(a);
        n++;
    }
    for (int i = 1; i <= 8; i++) {
        const double s = flank * i / 8.0;
        xy[2 * n] = rho * sb - s * cb;
        xy[2 * n + 1] = rho * cb + s * sb;
        n++;
    }
    return n;
}

/* The profile extruded along z over nz steps of dz, capped by fans from
 * (cx, cy) (a point the profile is star-shaped about). */
static void extrude(builder *b, const double *xy, int n, int nz, double dz, double cx, double cy)
{
    for (int l = 0; l <= nz; l++)
        for (int i = 0; i < n; i++)
            add_v(b, xy[2 * i], xy[2 * i + 1], l * dz);
    const int64_t c0 = add_v(b, cx, cy, 0), c1 = add_v(b, cx, cy, nz * dz);
    for (int l = 0; l < nz; l++)
        for (int i = 0; i < n; i++) {
            const int j = (i + 1) % n;
            add_q(b, (int64_t)l * n + i, (int64_t)l * n + j, (int64_t)(l + 1) * n + j,
                  (int64_t)(l + 1) * n + i);
        }
    for (int i = 0; i < n; i++) {
        const int j = (i + 1) % n;
        add_t(b, c0, j, i);
        add_t(b, c1, (int64_t)nz * n + i, (int64_t)nz * n + j);
    }
}

/* The rounded wedge at bound scale: want_row -3: the crease is the row of
 * z edges at the round's middle vertex (k even); -2: one of the two rows
 * beside its middle facet (k odd), all of it on that one; -1: none. */
static void expect_round(const char *name, double rho, int k, double scale, int want_row)
{
    double xy[2 * 64];
    int tip;
    const double beta = 10 * M_PI / 180;
    const int n = profile(rho, beta, k, 0.1, xy, &tip);
    const int nz = 10;
    double cx = 0, cy = 0;
    for (int i = 0; i < n; i++) {
        cx += xy[2 * i] / n;
        cy += xy[2 * i + 1] / n;
    }
    builder b = {0};
    extrude(&b, xy, n, nz, 0.02, cx, cy);
    vc_features f;
    vc_error err = {0};
    if (vc_features_detect_scaled(&b.s, 60, NULL, scale, &f, &err)) {
        CHECKF(0, "%s: %s", name, err.msg);
        vc_surface_free(&b.s);
        return;
    }
    int64_t n_round = 0, n_row[64] = {0}, other = 0;
    for (int64_t e = 0; e < f.n_edges; e++) {
        if (f.edge_sharp[e] != VC_SHARP_ROUND)
            continue;
        n_round++;
        const int64_t a = f.edge_vertex[2 * e], c = f.edge_vertex[2 * e + 1];
        if (a < (int64_t)(nz + 1) * n && c == a + n)
            n_row[a % n]++;
        else
            other++;
    }
    CHECKF(f.n_sharp_round == n_round, "%s: n_sharp_round %lld, %lld edges marked", name,
           (long long)f.n_sharp_round, (long long)n_round);
    if (want_row == -1) {
        CHECKF(n_round == 0 && !f.tri_round, "%s: %lld round creases (want none)", name, (long long)n_round);
    } else {
        int row = tip + k / 2;
        if (want_row == -2)
            row = n_row[tip + k / 2] > 0 ? tip + k / 2 : tip + k / 2 + 1;
        CHECKF(n_round == nz && n_row[row] == nz && other == 0,
               "%s: %lld round creases, %lld on row %d, %lld off the rows (want %d, all on it)", name,
               (long long)n_round, (long long)n_row[row], row, (long long)other, nz);
        /* the band's triangles face their flanks: every tip triangle
         * beside a fold inside the round (all but the outer halves of the
         * two outer facets, which meet the flanks at no fold) is flagged,
         * and the smoothed normal of each flagged one is a flank normal
         * (+-(sin beta, cos beta, 0) turned outward) within 2 degrees */
        int64_t flagged = 0, facing = 0;
        for (int l = 0; l < nz && f.tri_round; l++)
            for (int i = tip; i < tip + k; i++)
                for (int h = 0; h < 2; h++) {
                    const int64_t t = 2 * ((int64_t)l * n + i) + h;
                    flagged += f.tri_round[t];
                    const double *m = f.tri_smooth_normal + 3 * t;
                    const double up = m[0] * sin(beta) + m[1] * cos(beta);
                    const double down = m[0] * sin(beta) - m[1] * cos(beta);
                    facing += f.tri_round[t] && fabs(m[2]) < 1e-9 &&
                              fmax(fabs(up), fabs(down)) > cos(2 * M_PI / 180);
                }
        CHECKF(flagged >= 2 * (k - 1) * nz && facing == flagged,
               "%s: %lld of %d tip triangles in the band (want at least %d), %lld facing a flank", name,
               (long long)flagged, 2 * k * nz, 2 * (k - 1) * nz, (long long)facing);
    }
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

/* The points of m straight runs (x0, y0, x1, y1), 4 segments each, the
 * runs' ends left to the next run, after the n points of xy; returns the
 * new count. */
static int add_runs(double *xy, int n, const double (*run)[4], int m)
{
    for (int q = 0; q < m; q++)
        for (int i = 0; i < 4; i++) {
            xy[2 * n] = run[q][0] + (run[q][2] - run[q][0]) * i / 4;
            xy[2 * n + 1] = run[q][1] + (run[q][3] - run[q][1]) * i / 4;
            n++;
        }
    return n;
}

/* An L-shaped block (arms 1 long, 0.3 wide) whose inner corner is a
 * concave round of radius r in k facets (k even), extruded over nz steps of
 * 0.05, caps fanned from (0.15, 0.15) (the L is star-shaped about it): at
 * a bound of 0.006 a radius of 0.001 is a crease along the round's middle
 * row, 0.02 is not. */
static void expect_concave(double r, int k, int64_t want)
{
    double xy[2 * 64];
    int n = 0, mid = -1;
    /* the outline: straight runs of 4 segments, then the round */
    const double run[][4] = {{0, 0, 1, 0}, {1, 0, 1, 0.3}, {1, 0.3, 0.3 + r, 0.3}};
    n = add_runs(xy, n, run, 3);
    for (int j = 0; j < k; j++) {
        const double a = -M_PI / 2 - (M_PI / 2) * j / k;
        if (j == k / 2)
            mid = n;
        xy[2 * n] = 0.3 + r + r * cos(a);
        xy[2 * n + 1] = 0.3 + r + r * sin(a);
        n++;
    }
    const double run2[][4] = {{0.3, 0.3 + r, 0.3, 1}, {0.3, 1, 0, 1}, {0, 1, 0, 0}};
    n = add_runs(xy, n, run2, 3);
    const int nz = 8;
    builder b = {0};
    extrude(&b, xy, n, nz, 0.05, 0.15, 0.15);
    vc_features f;
    vc_error err = {0};
    CHECK(vc_features_detect_scaled(&b.s, 60, NULL, 0.006, &f, &err) == 0);
    int64_t on_mid = 0;
    for (int64_t e = 0; e < f.n_edges; e++)
        if (f.edge_sharp[e] == VC_SHARP_ROUND)
            on_mid += f.edge_vertex[2 * e] % n == mid && f.edge_vertex[2 * e + 1] == f.edge_vertex[2 * e] + n;
    CHECKF(f.n_sharp_round == want && on_mid == want,
           "L block, concave round of radius %g: %lld round creases, %lld on its middle row (want %lld)", r,
           (long long)f.n_sharp_round, (long long)on_mid, (long long)want);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

/* A capped n-gon cylinder of radius 1 at bound scale: no rounds, its sides
 * curved ground (the rims are sharp already). */
static void expect_cylinder(int sides, double scale)
{
    builder b = {0};
    make_prism(&b, sides, 3.0);
    vc_features f;
    vc_error err = {0};
    CHECK(vc_features_detect_scaled(&b.s, 60, NULL, scale, &f, &err) == 0);
    CHECKF(f.n_sharp_round == 0, "%d-gon cylinder, bound %g: %lld round creases (want none)", sides, scale,
           (long long)f.n_sharp_round);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

int main(void)
{
    /* radius 0.002 at bounds 0.01 (W = 0.005): flanks 0.005 to 0.01 from
     * the fold are flat, and turn by 160 degrees */
    expect_round("round of 8 facets", 0.002, 8, 0.01, -3);
    expect_round("round of 7 facets", 0.002, 7, 0.01, -2);
    expect_round("round of 16 facets", 0.002, 16, 0.01, -3);
    /* the bound at the round's radius: the flanks lie on the round */
    expect_round("round of 8 facets, bound 0.002", 0.002, 8, 0.002, -1);
    /* no bound: nothing judged at a scale */
    expect_round("round of 8 facets, no bound", 0.002, 8, 0, -1);
    /* concave: the inner corner of an L */
    expect_concave(0.001, 6, 8);
    expect_concave(0.02, 6, 0);
    /* curved ground: a cylinder of radius 1 under a bound of 2.5 (its flanks
     * 1.25 to 2.5 round it spread by half the turn between them) and 4
     * (flanks beyond the far side), fine and coarse; folds on a cylinder
     * narrower than the bound take part only when W exceeds the radius */
    expect_cylinder(64, 2.5);
    expect_cylinder(64, 4.0);
    expect_cylinder(24, 2.5);
    expect_cylinder(24, 4.0);
    if (failures) {
        fprintf(stderr, "%d failures\n", failures);
        return 1;
    }
    printf("test_round_creases: ok\n");
    return 0;
}
