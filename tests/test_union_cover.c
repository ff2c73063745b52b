/* balls/union_cover.h against dense point sampling: a piece called covered
 * has every sample point in some ball; a piece whose sample points are all
 * inside some ball by more than the samples' spacing (so that every point
 * of the piece is covered) is called covered. Plus hand-made cases: two
 * balls that cover a segment only together, three balls around a triangle
 * that leave its middle open, a fourth that closes it. */
#include <math.h>
#include <stdio.h>

#include "balls/union_cover.h"
#include "vorocrust/random.h"

#include "test_check.h"

static vc_rng rng;

static double uniform(double a, double b) { return a + (b - a) * vc_rng_uniform(&rng); }

/* The largest depth (r - distance) of x in any ball. */
static double depth(const double x[3], const double *c, const double *r, int k)
{
    double best = -INFINITY;
    for (int i = 0; i < k; i++) {
        const double d = sqrt((x[0] - c[3 * i]) * (x[0] - c[3 * i]) +
                              (x[1] - c[3 * i + 1]) * (x[1] - c[3 * i + 1]) +
                              (x[2] - c[3 * i + 2]) * (x[2] - c[3 * i + 2]));
        best = fmax(best, r[i] - d);
    }
    return best;
}

/* The least depth over a grid of N steps per edge on the piece, and the
 * grid's spacing bound (every point of the piece is within it of a grid
 * point). */
static double least_depth(const double *v, int nv, const double *c, const double *r, int k, int N,
                          double *spacing)
{
    double lmax = 0;
    for (int a = 0; a < nv; a++)
        for (int b = a + 1; b < nv; b++) {
            double l = 0;
            for (int e = 0; e < 3; e++)
                l += (v[3 * a + e] - v[3 * b + e]) * (v[3 * a + e] - v[3 * b + e]);
            lmax = fmax(lmax, sqrt(l));
        }
    *spacing = lmax / N;
    double least = INFINITY;
    for (int i = 0; i <= N; i++)
        for (int j = 0; j <= (nv == 3 ? N - i : 0); j++) {
            const double u = (double)i / N, w = (double)j / N;
            double x[3];
            for (int e = 0; e < 3; e++)
                x[e] = nv == 3 ? v[e] + u * (v[3 + e] - v[e]) + w * (v[6 + e] - v[e])
                               : v[e] + u * (v[3 + e] - v[e]);
            least = fmin(least, depth(x, c, r, k));
        }
    return least;
}

static void hand_made(void)
{
    /* a segment of length 2 on the x axis: two unit balls at its ends'
     * quarter points cover it together, neither alone */
    const double seg[6] = {-1, 0, 0, 1, 0, 0};
    const double c2[6] = {-0.5, 0, 0, 0.5, 0, 0};
    const double r2[2] = {0.6, 0.6};
    CHECK(vc_union_covers(seg, 2, c2, r2, 1) == 0);
    CHECK(vc_union_covers(seg, 2, c2, r2, 2) == 1);
    const double r2s[2] = {0.6, 0.45}; /* the right end left out */
    CHECK(vc_union_covers(seg, 2, c2, r2s, 2) == 0);
    const double r2g[2] = {0.49, 0.49}; /* a gap at the middle */
    CHECK(vc_union_covers(seg, 2, c2, r2g, 2) == 0);

    /* an equilateral triangle with balls at its corners through its
     * edges' midpoints and a little beyond: the centroid is left open */
    const double h = sqrt(3.0) / 2;
    const double tri[9] = {0, 0, 0, 1, 0, 0, 0.5, h, 0};
    double c4[12], r4[4];
    for (int i = 0; i < 9; i++)
        c4[i] = tri[i];
    for (int i = 0; i < 3; i++)
        r4[i] = 0.52;
    CHECK(vc_union_covers(tri, 3, c4, r4, 3) == 0);
    /* a fourth ball at the centroid closes it */
    c4[9] = 0.5;
    c4[10] = h / 3;
    c4[11] = 0;
    r4[3] = 0.2;
    CHECK(vc_union_covers(tri, 3, c4, r4, 4) == 1);
    /* but not a ball too small to reach the hole's corners */
    r4[3] = 0.05;
    CHECK(vc_union_covers(tri, 3, c4, r4, 4) == 0);
    /* one ball holding the whole triangle, far out of its plane */
    const double c1[3] = {0.5, 0.3, 0.5};
    const double r1[1] = {0.95};
    CHECK(vc_union_covers(tri, 3, c1, r1, 1) == 1);
    /* no balls, too many balls */
    CHECK(vc_union_covers(tri, 3, c1, r1, 0) == 0);
    /* a position far from the origin: the test works relative to centres */
    double far_tri[9], far_c[12];
    for (int i = 0; i < 9; i++)
        far_tri[i] = tri[i] + 1e6;
    for (int i = 0; i < 12; i++)
        far_c[i] = c4[i] + 1e6;
    r4[3] = 0.2;
    CHECK(vc_union_covers(far_tri, 3, far_c, r4, 4) == 1);
}

int main(void)
{
    vc_rng_init(&rng, 17, 0);
    hand_made();
    int n_covered = 0, n_open = 0, n_sure = 0;
    for (int t = 0; t < 20000; t++) {
        const int nv = 2 + (t & 1);
        double v[9] = {0};
        for (int m = 0; m < nv; m++)
            for (int e = 0; e < 3; e++)
                v[3 * m + e] = uniform(-1, 1);
        if (t % 4 < 2) /* flat in z: balls cut it in disks of varied size */
            for (int m = 0; m < nv; m++)
                v[3 * m + 2] = 0;
        const int k = 1 + (int)(vc_rng_next(&rng) % 12);
        double c[3 * VC_UNION_COVER_MAX], r[VC_UNION_COVER_MAX];
        for (int i = 0; i < k; i++) {
            /* centres near the piece, radii that make covering a coin toss */
            for (int e = 0; e < 3; e++)
                c[3 * i + e] = uniform(-1.2, 1.2);
            r[i] = uniform(0.3, 1.6);
        }
        const int covered = vc_union_covers(v, nv, c, r, k);
        double spacing;
        const double least = least_depth(v, nv, c, r, k, 60, &spacing);
        if (covered) {
            n_covered++;
            CHECKF(least >= -1e-12, "case %d: called covered, a sample point is %g outside", t,
                   -least);
        } else
            n_open++;
        if (least > spacing + 1e-8) {
            n_sure++;
            CHECKF(covered, "case %d: every point is covered (depth %g > spacing %g)", t, least,
                   spacing);
        }
    }
    printf("%d covered, %d not, %d surely covered by sampling\n", n_covered, n_open, n_sure);
    /* the random cases must exercise both answers */
    CHECK(n_covered > 2000 && n_open > 2000 && n_sure > 500);
    return failures != 0;
}
