/* The Voronoi engine's k-d tree (voronoi/seed_kdtree.h) against a brute
 * force: for random points, a lattice (many equal distances: the (d2,
 * seed) order breaks the ties) and clusters of coincident points, every
 * query's k nearest other than the skipped seed, in order, for k from 1 to
 * more than there are points; and the range query after a k-nearest
 * answer (vc_seed_kdtree_within): exactly the brute force's hits after the
 * k-th within the radius, in order, and -1 past its capacity; and the
 * k nearest through the hint of the previous queries
 * (vc_seed_kdtree_knn_hinted), the same answers. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "voronoi/seed_kdtree.h"
#include "vorocrust/random.h"

#include "test_check.h"

static const double *pts;

static int cmp_hit(const void *x, const void *y)
{
    const vc_kd_hit *a = x, *b = y;
    if (a->d2 != b->d2)
        return a->d2 < b->d2 ? -1 : 1;
    return (a->seed > b->seed) - (a->seed < b->seed);
}

/* Every point but skip, by (d2, seed), into all; returns the count. */
static int brute(const double *q, int64_t n, int64_t skip, vc_kd_hit *all)
{
    int m = 0;
    for (int64_t i = 0; i < n; i++) {
        if (i == skip)
            continue;
        const double *p = pts + 3 * i;
        const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        all[m++] = (vc_kd_hit){dx * dx + dy * dy + dz * dz, i};
    }
    qsort(all, (size_t)m, sizeof *all, cmp_hit);
    return m;
}

/* A node filter for the half-space x >= 0.5: a box wholly below it is
 * rejected. */
static int right_half(void *ctx, const double lo[3], const double hi[3])
{
    (void)ctx;
    (void)lo;
    return hi[0] >= 0.5;
}

static void check_set(const char *name, const double *xyz, int64_t n, vc_rng *rng)
{
    pts = xyz;
    vc_seed_kdtree t;
    CHECK(vc_seed_kdtree_build(&t, xyz, n) == 0);
    vc_kd_hit *all = malloc(sizeof *all * (size_t)(n + 1));
    vc_kd_hit *hit = malloc(sizeof *hit * (size_t)(n + 8));
    const int ks[] = {1, 2, 7, 16, 48, 96, (int)n - 1, (int)n + 5};
    int bad = 0;
    /* one hint per k: each query meets the one the previous query of its
     * k left (at a random place: near or far) */
    vc_kd_hint hint[8];
    memset(hint, 0, sizeof hint);
    for (int q = 0; q < 200 && !bad; q++) {
        /* a point of the set (skipped) or a free query point (nothing skipped) */
        const int own = q % 2 == 0;
        const int64_t skip = own ? (int64_t)(vc_rng_next(rng) % (uint64_t)n) : -1;
        double x[3];
        for (int d = 0; d < 3; d++)
            x[d] = own ? xyz[3 * skip + d] : -0.2 + 1.4 * vc_rng_uniform(rng);
        const int m = brute(x, n, skip, all);
        for (size_t j = 0; j < sizeof ks / sizeof ks[0]; j++) {
            const int k = ks[j];
            if (k <= 0)
                continue;
            const int got = vc_seed_kdtree_knn(&t, x, k, skip, hit);
            const int want = k < m ? k : m;
            int same = got == want;
            /* the same through the hint the previous queries left (near
             * or far from here, of this k or another: the bound only
             * prunes, the answer is the unbounded one) */
            {
                vc_kd_hit *h2 = malloc(sizeof *h2 * (size_t)(n + 8));
                const int got2 = vc_seed_kdtree_knn_hinted(&t, &hint[j], x, k, skip, h2);
                int same2 = got2 == want;
                for (int i = 0; same2 && i < got2; i++)
                    same2 = h2[i].seed == all[i].seed && h2[i].d2 == all[i].d2;
                CHECKF(same2, "%s: query %d, k %d, hinted: %d hits, want %d", name, q, k, got2, want);
                free(h2);
            }
            for (int i = 0; same && i < got; i++)
                same = hit[i].seed == all[i].seed && hit[i].d2 == all[i].d2;
            if (!same) {
                CHECKF(same, "%s: query %d, k %d: %d hits, want %d (first difference)", name, q, k,
                       got, want);
                bad = 1;
                break;
            }
            /* the range after the k-th hit, to the distance of a later one
             * (ties at the radius included) */
            if (got < 1 || got >= m)
                continue;
            const int far = got + (m - got) / 3;
            const double r2 = all[far].d2;
            int expect = 0;
            while (got + expect < m && all[got + expect].d2 <= r2)
                expect++;
            int truncated = -1;
            const int in = vc_seed_kdtree_within(&t, x, r2, hit[got - 1], skip, NULL, NULL, hit, (int)n + 8,
                                                 &truncated);
            same = in == expect && truncated == 0;
            for (int i = 0; same && i < in; i++)
                same = hit[i].seed == all[got + i].seed && hit[i].d2 == all[got + i].d2;
            if (!same) {
                CHECKF(same, "%s: query %d, range after %d: %d hits, want %d", name, q, k, in,
                       expect);
                bad = 1;
                break;
            }
            if (expect > 1) {
                /* a cap below the count: the first cap in order, truncated,
                 * then the rest after the last of them */
                const int part = vc_seed_kdtree_within(&t, x, r2, all[got - 1], skip, NULL, NULL, hit,
                                                       expect - 1, &truncated);
                int prefix = part == expect - 1 && truncated == 1;
                for (int i = 0; prefix && i < part; i++)
                    prefix = hit[i].seed == all[got + i].seed && hit[i].d2 == all[got + i].d2;
                CHECKF(prefix, "%s: query %d, capped range after %d: %d hits, truncated %d", name, q, k,
                       part, truncated);
                const int rest = vc_seed_kdtree_within(&t, x, r2, all[got + expect - 2], skip, NULL, NULL,
                                                       hit, (int)n + 8, &truncated);
                CHECK(rest == 1 && truncated == 0 && hit[0].seed == all[got + expect - 1].seed);
            }
            /* with a node filter: every hit in the half-space it keeps is
             * still found, in order, and nothing outside the plain answer */
            const int inh = vc_seed_kdtree_within(&t, x, r2, all[got - 1], skip, right_half, NULL, hit,
                                                  (int)n + 8, &truncated);
            int j = 0, ok = inh >= 0 && truncated == 0;
            /* the filter applies to points too: nothing from the other half */
            for (int i = 0; ok && i < inh; i++)
                ok = pts[3 * hit[i].seed] >= 0.5;
            for (int i = 0; ok && i < expect; i++) {
                const vc_kd_hit *w = &all[got + i];
                if (j < inh && hit[j].seed == w->seed && hit[j].d2 == w->d2)
                    j++;
                else if (pts[3 * w->seed] >= 0.5)
                    ok = 0; /* a hit in the kept half-space went missing */
            }
            if (!(ok && j == inh)) {
                CHECKF(0, "%s: query %d, filtered range after %d: %d hits", name, q, k, inh);
                bad = 1;
                break;
            }
        }
    }
    free(all);
    free(hit);
    vc_seed_kdtree_free(&t);
}

int main(void)
{
    vc_rng rng;
    vc_rng_init(&rng, 5, 0);
    enum { N = 3000 };
    double *xyz = malloc(sizeof(double) * 3 * N);
    /* uniform random */
    for (int i = 0; i < 3 * N; i++)
        xyz[i] = vc_rng_uniform(&rng);
    check_set("random", xyz, N, &rng);
    /* a 14^3 lattice: ties everywhere */
    int64_t n = 0;
    for (int a = 0; a < 14; a++)
        for (int b = 0; b < 14; b++)
            for (int c = 0; c < 14; c++, n++) {
                xyz[3 * n] = a / 13.0;
                xyz[3 * n + 1] = b / 13.0;
                xyz[3 * n + 2] = c / 13.0;
            }
    check_set("lattice", xyz, n, &rng);
    /* clusters of coincident points (and pairs a sliver apart) */
    for (int i = 0; i < N; i++) {
        const int c = i / 10;
        for (int d = 0; d < 3; d++)
            xyz[3 * i + d] = (double)((c * 7919 + d * 104729) % 1000) / 1000.0 +
                             (i % 10 == 9 ? 1e-12 : 0.0);
    }
    check_set("clusters", xyz, N, &rng);
    /* a few points: fewer than k */
    check_set("tiny", xyz, 5, &rng);
    free(xyz);
    return failures != 0;
}
