/* Nearest seed in growing shells of grid bins (see nearest_seed.h). */
#include "nearest_seed.h"

#include <math.h>
#include <stdlib.h>

int vc_nearest_seed_grid_build(vc_seed_grid *g, const vc_seeds *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < s->n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * i + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * i + d]);
        }
    if (s->n == 0)
        for (int d = 0; d < 3; d++)
            lo[d] = hi[d] = 0;
    return vc_seed_grid_build(g, s->xyz, s->n, lo, hi, 3.0);
}

int64_t vc_nearest_seed(const vc_seed_grid *g, const double x[3], double *dist)
{
    int c[3];
    vc_seed_grid_locate(g, x, c);
    double best2 = INFINITY;
    int64_t best = -1;
    int maxn = g->n[0] > g->n[1] ? g->n[0] : g->n[1];
    maxn = maxn > g->n[2] ? maxn : g->n[2];
    for (int ring = 0; ring <= maxn; ring++) {
        /* a seed in ring r is at least (r - 1) h away (also from a point
         * outside the grid, clamped to a border bin) */
        if (best >= 0) {
            double lim = (double)(ring - 1) * g->h;
            if (lim > 0 && lim * lim > best2)
                break;
        }
        for (int k = c[2] - ring; k <= c[2] + ring; k++) {
            if (k < 0 || k >= g->n[2])
                continue;
            for (int j = c[1] - ring; j <= c[1] + ring; j++) {
                if (j < 0 || j >= g->n[1])
                    continue;
                int shell = abs(k - c[2]) == ring || abs(j - c[1]) == ring;
                for (int i = c[0] - ring; i <= c[0] + ring; i += (shell || ring == 0) ? 1 : 2 * ring) {
                    if (i < 0 || i >= g->n[0])
                        continue;
                    int64_t b = vc_seed_grid_bin(g, i, j, k);
                    for (int64_t m = g->bin_start[b]; m < g->bin_start[b + 1]; m++) {
                        int64_t q = g->seed_index[m];
                        const double *y = g->xyz + 3 * m;
                        double d2 = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                                    (x[2] - y[2]) * (x[2] - y[2]);
                        if (d2 < best2 || (d2 == best2 && q < best)) {
                            best2 = d2;
                            best = q;
                        }
                    }
                }
            }
        }
    }
    *dist = sqrt(best2);
    return best;
}
