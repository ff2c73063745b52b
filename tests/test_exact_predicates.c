/* The exact predicates (util/exact_predicates.h) against an independent
 * exact reference: points with integer coordinates (|x| <= 2^20, so every
 * determinant fits a 128-bit integer) evaluated in __int128, on the
 * configurations where floating point fails: exactly coplanar and exactly
 * co-spherical points (the answer is 0), the same moved by one unit
 * (the smallest change, the sign decided by a difference of 1 in a
 * determinant of 2^90), and random points. Every case is also scaled by
 * 2^-40 and 2^+30 (exact: the signs must not change) and translated by
 * 2^21 (exact for these integers). The filters must decide the plain random
 * cases without the exact path. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "util/exact_predicates.h"

#include "test_check.h"

typedef __int128 i128;

static uint64_t rng_state = 0x9e3779b97f4a7c15ULL;

static int64_t rnd(int64_t lo, int64_t hi)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return lo + (int64_t)(rng_state % (uint64_t)(hi - lo + 1));
}

static int sgn(i128 x) { return (x > 0) - (x < 0); }

static i128 orient_ref(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d)
{
    i128 ad[3], bd[3], cd[3];
    for (int k = 0; k < 3; k++) {
        ad[k] = a[k] - d[k];
        bd[k] = b[k] - d[k];
        cd[k] = c[k] - d[k];
    }
    return ad[2] * (bd[0] * cd[1] - cd[0] * bd[1]) + bd[2] * (cd[0] * ad[1] - ad[0] * cd[1]) +
           cd[2] * (ad[0] * bd[1] - bd[0] * ad[1]);
}

/* The insphere determinant as the predicate defines it (the lifted 4x4
 * determinant of a - e, b - e, c - e, d - e), by cofactors of the lift
 * column: sum over the points of (-1)^i lift_i times the orientation of
 * the other three (in the order the predicate uses). */
static i128 insphere_ref(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d,
                         const int64_t *e)
{
    const int64_t *p[4] = {a, b, c, d};
    i128 v[4][3], lift[4];
    for (int i = 0; i < 4; i++) {
        lift[i] = 0;
        for (int k = 0; k < 3; k++) {
            v[i][k] = p[i][k] - e[k];
            lift[i] += v[i][k] * v[i][k];
        }
    }
#define DET3(x, y, z)                                                                              \
    (x[0] * (y[1] * z[2] - y[2] * z[1]) - x[1] * (y[0] * z[2] - y[2] * z[0]) +                     \
     x[2] * (y[0] * z[1] - y[1] * z[0]))
    /* det [v_i | lift_i] expanded along the lift column */
    const i128 m0 = DET3(v[1], v[2], v[3]), m1 = DET3(v[0], v[2], v[3]);
    const i128 m2 = DET3(v[0], v[1], v[3]), m3 = DET3(v[0], v[1], v[2]);
#undef DET3
    return -lift[0] * m0 + lift[1] * m1 - lift[2] * m2 + lift[3] * m3;
}

static void to_double(const int64_t *p, double s, double t, double *out)
{
    for (int k = 0; k < 3; k++)
        out[k] = ((double)p[k] + t) * s;
}

static const double SCALES[3] = {1.0, 0x1p-40, 0x1p30};

static void check_orient(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d)
{
    const int want = sgn(orient_ref(a, b, c, d));
    for (int si = 0; si < 3; si++)
        for (int ti = 0; ti < 2; ti++) {
            double A[3], B[3], C[3], D[3];
            const double t = ti ? 0x1p21 : 0;
            to_double(a, SCALES[si], t, A);
            to_double(b, SCALES[si], t, B);
            to_double(c, SCALES[si], t, C);
            to_double(d, SCALES[si], t, D);
            const int got = vc_orient3d_exact(A, B, C, D);
            if (got != want) {
                fprintf(stderr, "orient3d: got %d, want %d (scale %g, shift %g)\n", got, want,
                        SCALES[si], t);
                failures++;
            }
        }
}

static int check_insphere(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d,
                          const int64_t *e)
{
    const int want = sgn(insphere_ref(a, b, c, d, e));
    for (int si = 0; si < 3; si++)
        for (int ti = 0; ti < 2; ti++) {
            double A[3], B[3], C[3], D[3], E[3];
            const double t = ti ? 0x1p21 : 0;
            to_double(a, SCALES[si], t, A);
            to_double(b, SCALES[si], t, B);
            to_double(c, SCALES[si], t, C);
            to_double(d, SCALES[si], t, D);
            to_double(e, SCALES[si], t, E);
            const int got = vc_insphere_exact(A, B, C, D, E);
            if (got != want) {
                fprintf(stderr, "insphere: got %d, want %d (scale %g, shift %g)\n", got, want,
                        SCALES[si], t);
                failures++;
            }
        }
    return want;
}

/* A point of the sphere x^2 + y^2 + z^2 = r2 about the centre, found by
 * search among integer points; 0 when none was found. */
static int sphere_point(int64_t r2, const int64_t *centre, int64_t *p)
{
    const int64_t r = (int64_t)__builtin_sqrt((double)r2);
    for (int tries = 0; tries < 20000; tries++) {
        const int64_t x = rnd(-r, r), y = rnd(-r, r);
        const int64_t rest = r2 - x * x - y * y;
        if (rest < 0)
            continue;
        int64_t z = (int64_t)__builtin_sqrt((double)rest);
        while (z * z > rest)
            z--;
        while ((z + 1) * (z + 1) <= rest)
            z++;
        if (z * z != rest)
            continue;
        if (rnd(0, 1))
            z = -z;
        p[0] = centre[0] + x;
        p[1] = centre[1] + y;
        p[2] = centre[2] + z;
        return 1;
    }
    return 0;
}

int main(void)
{
    const int64_t M = 1 << 20;
    /* coplanar: d = a + s (b - a) + t (c - a), then nudged by one unit */
    int zeros = 0, nudged = 0;
    for (int it = 0; it < 400; it++) {
        int64_t a[3], b[3], c[3], d[3];
        const int64_t R = 1 << 9;
        for (int k = 0; k < 3; k++) {
            a[k] = rnd(-R, R);
            b[k] = a[k] + rnd(-R, R);
            c[k] = a[k] + rnd(-R, R);
        }
        const int64_t s = rnd(-300, 300), t = rnd(-300, 300);
        for (int k = 0; k < 3; k++)
            d[k] = a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]);
        int far = 0;
        for (int k = 0; k < 3; k++)
            far |= d[k] > M || d[k] < -M;
        if (far)
            continue;
        zeros += orient_ref(a, b, c, d) == 0;
        check_orient(a, b, c, d);
        for (int k = 0; k < 3; k++)
            for (int e = -1; e <= 1; e += 2) {
                d[k] += e;
                check_orient(a, b, c, d);
                nudged += orient_ref(a, b, c, d) != 0;
                d[k] -= e;
            }
    }
    CHECK(zeros > 100);
    CHECK(nudged > 300);
    /* the coplanar and nudged cases went through the exact path */
    CHECK(vc_exact_predicate_fallbacks() > 1000);

    /* co-spherical integer points, then the fifth nudged by one unit */
    int on_sphere = 0, insphere_nonzero = 0;
    for (int it = 0; it < 200; it++) {
        const int64_t centre[3] = {rnd(-1000, 1000), rnd(-1000, 1000), rnd(-1000, 1000)};
        const int64_t r2 = rnd(50000, 400000);
        int64_t p[5][3];
        int ok = 1;
        for (int i = 0; i < 5 && ok; i++)
            ok = sphere_point(r2, centre, p[i]);
        if (!ok)
            continue;
        if (check_insphere(p[0], p[1], p[2], p[3], p[4]) == 0)
            on_sphere++;
        for (int k = 0; k < 3; k++)
            for (int e = -1; e <= 1; e += 2) {
                p[4][k] += e;
                insphere_nonzero += check_insphere(p[0], p[1], p[2], p[3], p[4]) != 0;
                p[4][k] -= e;
            }
    }
    CHECK(on_sphere > 50);
    CHECK(insphere_nonzero > 200);

    /* random points: the filter decides them all */
    const long long before = vc_exact_predicate_fallbacks();
    for (int it = 0; it < 2000; it++) {
        int64_t p[5][3];
        for (int i = 0; i < 5; i++)
            for (int k = 0; k < 3; k++)
                p[i][k] = rnd(-M, M);
        double A[3], B[3], C[3], D[3], E[3];
        to_double(p[0], 1, 0, A);
        to_double(p[1], 1, 0, B);
        to_double(p[2], 1, 0, C);
        to_double(p[3], 1, 0, D);
        to_double(p[4], 1, 0, E);
        CHECK(vc_orient3d_exact(A, B, C, D) == sgn(orient_ref(p[0], p[1], p[2], p[3])));
        CHECK(vc_insphere_exact(A, B, C, D, E) == sgn(insphere_ref(p[0], p[1], p[2], p[3], p[4])));
    }
    CHECK(vc_exact_predicate_fallbacks() - before < 20);

    if (failures)
        fprintf(stderr, "test_exact_predicates: %d failures\n", failures);
    else
        printf("test_exact_predicates: %d coplanar, %d nudged, %d co-spherical, %d nudged: all "
               "exact\n",
               zeros, nudged, on_sphere, insphere_nonzero);
    return failures != 0;
}
