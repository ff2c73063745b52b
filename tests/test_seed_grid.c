/* The seed grid's bin order (an internal module of the Voronoi engine):
 * every bin exactly once whatever the grid's shape, and neighbours across
 * every axis close in the order (the stitching's cache behaviour rests on
 * it), where the row-major order puts the neighbours across z a whole
 * layer away. */
#include "../vorocrust/voronoi/seed_grid.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_check.h"

/* The order of the grid of n[0] x n[1] x n[2] bins; NULL on failure. */
static int64_t *order_of(const int n[3], int64_t *n_bins)
{
    vc_seed_grid g = {0};
    for (int d = 0; d < 3; d++)
        g.n[d] = n[d];
    *n_bins = (int64_t)n[0] * n[1] * n[2];
    int64_t *bins = malloc((size_t)*n_bins * sizeof *bins);
    if (bins)
        vc_seed_grid_bin_order(&g, bins);
    return bins;
}

static void test_permutation(void)
{
    const int shapes[][3] = {{1, 1, 1},  {2, 1, 1},   {1, 1, 37}, {7, 3, 1},
                             {5, 5, 5},  {16, 16, 16}, {100, 2, 3}, {9, 31, 4}};
    for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
        int64_t n_bins;
        int64_t *bins = order_of(shapes[s], &n_bins);
        unsigned char *seen = calloc((size_t)n_bins, 1);
        CHECK(bins && seen);
        if (!bins || !seen) {
            free(bins);
            free(seen);
            continue;
        }
        int64_t bad = 0;
        for (int64_t q = 0; q < n_bins; q++) {
            if (bins[q] < 0 || bins[q] >= n_bins || seen[bins[q]])
                bad++;
            else
                seen[bins[q]] = 1;
        }
        CHECKF(bad == 0, "grid %dx%dx%d: %lld entries out of range or repeated", shapes[s][0],
               shapes[s][1], shapes[s][2], (long long)bad);
        free(bins);
        free(seen);
    }
}

/* Fraction of the bins whose neighbour across axis d is within reach
 * places of it in the order. */
static double near_fraction(const int n[3], const int64_t *pos, int d, int64_t reach)
{
    int64_t near = 0, count = 0;
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i + (d == 0) < n[0]; i++) {
                if (j + (d == 1) >= n[1] || k + (d == 2) >= n[2])
                    continue;
                int64_t a = ((int64_t)k * n[1] + j) * n[0] + i;
                int64_t b = ((int64_t)(k + (d == 2)) * n[1] + j + (d == 1)) * n[0] + i + (d == 0);
                near += llabs(pos[a] - pos[b]) <= reach;
                count++;
            }
    return count ? (double)near / (double)count : 0;
}

static void test_locality(void)
{
    const int n[3] = {32, 32, 32};
    int64_t n_bins;
    int64_t *bins = order_of(n, &n_bins);
    int64_t *pos = malloc((size_t)n_bins * sizeof *pos);
    CHECK(bins && pos);
    if (bins && pos) {
        for (int64_t q = 0; q < n_bins; q++)
            pos[bins[q]] = q;
        /* Row-major puts the neighbours across z 1024 bins apart (none
         * within 256); a Z-order keeps most neighbours across every axis
         * within a quarter of a layer (the jumps at the halvings are
         * few). */
        for (int d = 0; d < 3; d++) {
            const double f = near_fraction(n, pos, d, 256);
            printf("32^3 grid, axis %d: %.1f%% of neighbours within 256 places\n", d, 100 * f);
            CHECKF(f >= 0.75, "axis %d: %.1f%% within 256 places", d, 100 * f);
        }
    }
    free(bins);
    free(pos);
}

int main(void)
{
    test_permutation();
    test_locality();
    if (failures) {
        fprintf(stderr, "%d check(s) failed\n", failures);
        return 1;
    }
    printf("test_seed_grid: all checks passed\n");
    return 0;
}
