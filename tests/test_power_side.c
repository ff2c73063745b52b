/* The Voronoi engine's exact side test (voronoi/power_side.h): its two
 * exact evaluations, in integers (narrow and wide) and in floating-point
 * expansions, must agree on every configuration, and the full test (filter,
 * double-double, then the exact path) with them:
 *  - random seeds at several scales and offsets (2^-40, 1, 2^30; shifted
 *    by 2^21), with and without box walls among the vertex's planes;
 *  - exact ties: seeds mirrored across a plane x = c (what flat CAD faces
 *    make: two mirrored pairs are co-circular, so every fifth seed is on
 *    their sphere), and integer points of one sphere; the symbolic
 *    perturbation then decides;
 *  - cubic lattices whose spacing (0.1, 1/46) is not a power of two:
 *    corners of eight co-spherical seeds, ties the double-double stage
 *    cannot settle; the narrow integers (two to five limbs) take every one
 *    of them without walls;
 *  - exponents too far apart for the integers (coordinates 1e-300 next to
 *    1): the integer path declines (-2) and the expansions decide.
 * Every stage that takes a configuration must agree with the expansions. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "util/exact_predicates.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/random.h"
#include "voronoi/power_side.h"

#include "test_check.h"

static vc_rng rng;

static double uniform(void) { return vc_rng_uniform(&rng); }

static int n_compared, n_ties, n_declined, n_narrow;

/* Compares the evaluations on seed s, planes pl and tested seed x; skips
 * a vertex of four coplanar seeds (its planes do not meet in a point). */
static void compare(const vc_power_ctx *ctx, int64_t s, const int64_t pl[3], int64_t x,
                    const char *what)
{
    if (pl[0] >= 0 && pl[1] >= 0 && pl[2] >= 0 &&
        vc_orient3d_exact(ctx->xyz + 3 * s, ctx->xyz + 3 * pl[0], ctx->xyz + 3 * pl[1],
                          ctx->xyz + 3 * pl[2]) == 0)
        return;
    const int by_int = vc_power_side_by(ctx, s, pl, x, 0);
    const int by_exp = vc_power_side_by(ctx, s, pl, x, 1);
    const int by_narrow = vc_power_side_by(ctx, s, pl, x, 2);
    const int full = vc_power_side(ctx, s, pl, x);
    CHECKF(by_narrow == -2 || by_narrow == by_exp, "%s: narrow integers %d, expansions %d (s %lld, "
           "planes %lld %lld %lld, x %lld)", what, by_narrow, by_exp, (long long)s,
           (long long)pl[0], (long long)pl[1], (long long)pl[2], (long long)x);
    n_narrow += by_narrow != -2;
    CHECKF(by_exp == 1 || by_exp == -1, "%s: expansions gave %d", what, by_exp);
    CHECKF(by_int == -2 || by_int == by_exp, "%s: integers %d, expansions %d (s %lld, planes %lld "
           "%lld %lld, x %lld)", what, by_int, by_exp, (long long)s, (long long)pl[0],
           (long long)pl[1], (long long)pl[2], (long long)x);
    CHECKF(full == by_exp, "%s: the full test %d, expansions %d", what, full, by_exp);
    n_compared++;
    n_declined += by_int == -2;
    if (vc_power_on_plane(ctx, s, pl, x) == 1)
        n_ties++;
}

static void set_box(vc_power_ctx *ctx, double lo, double hi)
{
    for (int d = 0; d < 3; d++) {
        ctx->box_lo[d] = lo;
        ctx->box_hi[d] = hi;
    }
}

/* Random seeds (scale, offset), vertices of three seeds or two seeds and
 * a wall. */
static void test_random(double scale, double offset)
{
    enum { N = 40 };
    double xyz[3 * N];
    for (int i = 0; i < 3 * N; i++)
        xyz[i] = offset + scale * uniform();
    vc_power_ctx ctx = {xyz, {0}, {0}};
    set_box(&ctx, offset - 0.5 * scale, offset + 1.5 * scale);
    char what[96];
    snprintf(what, sizeof what, "random, scale %g, offset %g", scale, offset);
    for (int t = 0; t < 400; t++) {
        const int64_t s = t % N, a = (t + 1 + t / N) % N, b = (t + 7) % N, c = (t + 13) % N,
                      x = (t + 29) % N;
        if (a == s || b == s || c == s || x == s || a == b || b == c || a == c || x == a ||
            x == b || x == c)
            continue;
        const int64_t pl[3] = {a, b, c};
        compare(&ctx, s, pl, x, what);
        const int64_t pw[3] = {a, b, VC_WALL_XMIN - (t % 6)};
        compare(&ctx, s, pw, x, what);
    }
}

/* Seed pairs mirrored across x = c: rows of (c - d, y, z), (c + d, y, z). */
static void test_mirrored(double c)
{
    enum { P = 12 };
    double xyz[6 * P];
    for (int i = 0; i < P; i++) {
        const double d = 0.1 + uniform(), y = uniform() * 4, z = uniform() * 4;
        xyz[6 * i] = c - d;
        xyz[6 * i + 3] = c + d;
        xyz[6 * i + 1] = xyz[6 * i + 4] = y;
        xyz[6 * i + 2] = xyz[6 * i + 5] = z;
    }
    vc_power_ctx ctx = {xyz, {0}, {0}};
    set_box(&ctx, c - 10, c + 10);
    char what[64];
    snprintf(what, sizeof what, "mirrored across x = %g", c);
    int ties_before = n_ties;
    /* s and a mirrored, b and x mirrored: co-circular, so x is on the
     * sphere through s, a, b and any c */
    for (int i = 0; i < P; i++)
        for (int j = 0; j < P; j++) {
            if (i == j)
                continue;
            const int64_t s = 2 * i, a = 2 * i + 1, b = 2 * j, x = 2 * j + 1;
            for (int k = 0; k < 2 * P; k++) {
                if (k / 2 == i || k / 2 == j)
                    continue;
                const int64_t pl[3] = {a, b, k};
                compare(&ctx, s, pl, x, what);
            }
        }
    CHECKF(n_ties - ties_before > 100, "%s: only %d exact ties", what, n_ties - ties_before);
}

/* Integer points of the sphere x^2 + y^2 + z^2 = 1001 about (cx, cy, cz),
 * times h. */
static void test_sphere(double h, double cx)
{
    double xyz[3 * 600];
    int n = 0;
    for (int x = -32; x <= 32; x++)
        for (int y = -32; y <= 32; y++)
            for (int z = -32; z <= 32 && n < 600; z++)
                if (x * x + y * y + z * z == 1001) {
                    xyz[3 * n] = h * (cx + x);
                    xyz[3 * n + 1] = h * y;
                    xyz[3 * n + 2] = h * z;
                    n++;
                }
    vc_power_ctx ctx = {xyz, {0}, {0}};
    set_box(&ctx, -100 * h + h * cx, 100 * h + h * cx);
    char what[64];
    snprintf(what, sizeof what, "sphere points, h %g, centre x %g", h, cx);
    const int ties_before = n_ties;
    for (int t = 0; t < 300; t++) {
        const int64_t s = (7 * t) % n, a = (7 * t + 11) % n, b = (7 * t + 47) % n,
                      c = (7 * t + 101) % n, x = (7 * t + 163) % n;
        const int64_t pl[3] = {a, b, c};
        compare(&ctx, s, pl, x, what);
    }
    /* scaled by a power of two the points stay exactly on the sphere */
    if (h == ldexp(1.0, ilogb(h)))
        CHECKF(n_ties - ties_before > 100, "%s: only %d exact ties", what, n_ties - ties_before);
}

/* A cubic lattice of spacing h about (o, o, o) (h = 0.1 or 1/46: not
 * doubles' multiples of a power of two, so the differences' products
 * round and the double-double stage cannot settle the ties): every
 * vertex of a lattice cell is a corner shared by eight co-spherical
 * seeds, so most tests are exact ties, which the narrow integers must
 * take (and agree with both other stages on). With walls too. */
static void test_lattice(double h, double o)
{
    enum { L = 5 };
    double xyz[3 * L * L * L];
    for (int i = 0; i < L; i++)
        for (int j = 0; j < L; j++)
            for (int k = 0; k < L; k++) {
                double *p = xyz + 3 * ((i * L + j) * L + k);
                p[0] = o + h * i;
                p[1] = o + h * j;
                p[2] = o + h * k;
            }
    vc_power_ctx ctx = {xyz, {0}, {0}};
    set_box(&ctx, o - 0.5 * h, o + (L - 0.5) * h);
    char what[80];
    snprintf(what, sizeof what, "lattice, spacing %g, origin %g", h, o);
    const int ties_before = n_ties;
    int n_seed_tests = 0, n_seed_narrow = 0;
    /* s at the centre; planes and the tested seed among its 26 neighbours
     * (the unit cube's corners about s's corner vertex among them) */
    const int64_t s = (2 * L + 2) * L + 2;
    int64_t nb[26], n = 0;
    for (int di = -1; di <= 1; di++)
        for (int dj = -1; dj <= 1; dj++)
            for (int dk = -1; dk <= 1; dk++)
                if (di || dj || dk)
                    nb[n++] = ((2 + di) * L + 2 + dj) * L + 2 + dk;
    for (int a = 0; a < 26; a++)
        for (int b = a + 1; b < 26; b += 2)
            for (int c = b + 1; c < 26; c += 3) {
                const int64_t pl[3] = {nb[a], nb[b], nb[c]};
                for (int x = 0; x < 26; x += 5)
                    if (x != a && x != b && x != c) {
                        compare(&ctx, s, pl, nb[x], what);
                        /* neighbours' differences are doubles (Sterbenz) */
                        n_seed_tests++;
                        n_seed_narrow += vc_power_side_by(&ctx, s, pl, nb[x], 2) != -2 ||
                                         vc_orient3d_exact(xyz + 3 * s, xyz + 3 * pl[0],
                                                           xyz + 3 * pl[1], xyz + 3 * pl[2]) == 0;
                    }
                const int64_t pw[3] = {nb[a], nb[b], VC_WALL_XMIN - (c % 6)};
                compare(&ctx, s, pw, nb[c], what);
            }
    CHECKF(n_ties - ties_before > 50, "%s: only %d exact ties", what, n_ties - ties_before);
    CHECKF(n_seed_narrow == n_seed_tests && n_seed_tests > 1000,
           "%s: the narrow integers took %d of %d tests without walls", what, n_seed_narrow,
           n_seed_tests);
}

/* Exponents far apart: the integers decline, the expansions decide. */
static void test_far_exponents(void)
{
    double xyz[15] = {1e-300, 0.3, 0.2, 1.0, 0.1, 0.7, 0.2, 1.1, 0.4, 0.9, 0.8, 0.05, 0.5, 0.5, 0.5};
    vc_power_ctx ctx = {xyz, {0}, {0}};
    set_box(&ctx, -2, 2);
    const int64_t pl[3] = {1, 2, 3};
    const int declined_before = n_declined;
    compare(&ctx, 0, pl, 4, "far exponents");
    CHECKF(n_declined > declined_before, "far exponents: the integers did not decline");
}

/* vc_power_vertex_exact: the vertex of s and three seeds (or two seeds
 * and a wall) is equidistant from s and its seeds (and on the wall), to
 * rounding, at every scale; random seeds near one another and far from
 * the origin make the double solve lose digits the integers keep. */
static void test_vertex_exact(double scale, double offset)
{
    enum { N = 24 };
    double xyz[3 * N];
    for (int i = 0; i < 3 * N; i++)
        xyz[i] = offset + scale * uniform();
    vc_power_ctx ctx = {xyz, {0}, {0}};
    set_box(&ctx, offset - 0.5 * scale, offset + 1.5 * scale);
    for (int t = 0; t < 200; t++) {
        const int64_t s = t % N, a = (t + 3) % N, b = (t + 8) % N, c = (t + 15) % N;
        const int64_t pl[3] = {a, b, t % 2 ? c : VC_WALL_XMIN - (t % 6)};
        if (pl[2] >= 0 && vc_orient3d_exact(xyz + 3 * s, xyz + 3 * a, xyz + 3 * b, xyz + 3 * c) == 0)
            continue;
        double y[3];
        if (vc_power_vertex_exact(&ctx, s, pl, y) != 0) {
            CHECKF(0, "vertex_exact declined: scale %g, offset %g", scale, offset);
            continue;
        }
        /* |y - (p - s)|^2 - |y|^2 = 0 for every seed p of the planes, in
         * long double against the terms' size */
        const long double r2 = (long double)y[0] * y[0] + (long double)y[1] * y[1] +
                               (long double)y[2] * y[2];
        for (int i = 0; i < 3; i++) {
            if (pl[i] < 0) {
                const int k = (int)(-1 - pl[i]), axis = k / 2;
                const double X = (k % 2) ? ctx.box_hi[axis] : ctx.box_lo[axis];
                const long double off = (long double)xyz[3 * s + axis] + y[axis] - X;
                CHECKF(fabsl(off) <= 1e-14L * (fabsl((long double)X) + sqrtl(r2)),
                       "vertex_exact off its wall by %Lg (scale %g)", off, scale);
                continue;
            }
            long double q2 = 0, pp = 0;
            for (int d = 0; d < 3; d++) {
                const long double p = (long double)xyz[3 * pl[i] + d] - xyz[3 * s + d];
                q2 += ((long double)y[d] - p) * ((long double)y[d] - p);
                pp += p * p;
            }
            CHECKF(fabsl(q2 - r2) <= 1e-13L * (r2 + pp), "vertex_exact: unequal distances %Lg "
                   "against %Lg (scale %g, offset %g)", q2, r2, scale, offset);
        }
    }
}

int main(void)
{
    vc_rng_init(&rng, 5, 0);
    test_vertex_exact(1.0, 0);
    test_vertex_exact(1e-6, 1000);
    test_vertex_exact(0x1.0p30, 0x1.0p40);
    const double scales[3] = {0x1.0p-40, 1.0, 0x1.0p30};
    for (int i = 0; i < 3; i++) {
        test_random(scales[i], 0);
        test_random(scales[i], 0x1.0p21 * scales[i]);
    }
    test_mirrored(-32.5);
    test_mirrored(0.0);
    test_mirrored(1e6);
    test_sphere(1.0, 0);
    test_sphere(0.1, 3);
    test_sphere(0x1.0p-30, 1000);
    test_lattice(0.1, 0.0);
    test_lattice(1.0 / 46, 0.5 / 46);
    test_lattice(0.1, 1e3);
    test_far_exponents();
    printf("%d configurations compared, %d exact ties, %d declined by the integers, %d taken by "
           "the narrow integers\n", n_compared, n_ties, n_declined, n_narrow);
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("all power side checks passed\n");
    return failures ? 1 : 0;
}
