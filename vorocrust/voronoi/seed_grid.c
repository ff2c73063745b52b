#include "seed_grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double gap(int d)
{
    int a = abs(d) - 1;
    return a > 0 ? (double)a : 0.0;
}

/* Boxes of at most this many bins are listed row by row. */
#define ORDER_LEAF 8

/* Appends the bins of the box [lo, hi) to bins at *n, halves first. */
static void order_box(const vc_seed_grid *g, const int lo[3], const int hi[3], int64_t *bins,
                      int64_t *n)
{
    int d = 0;
    for (int e = 1; e < 3; e++)
        if (hi[e] - lo[e] > hi[d] - lo[d])
            d = e;
    const int64_t size = (int64_t)(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    if (size <= ORDER_LEAF) {
        for (int k = lo[2]; k < hi[2]; k++)
            for (int j = lo[1]; j < hi[1]; j++)
                for (int i = lo[0]; i < hi[0]; i++)
                    bins[(*n)++] = vc_seed_grid_bin(g, i, j, k);
        return;
    }
    const int mid = lo[d] + (hi[d] - lo[d]) / 2;
    int a_hi[3] = {hi[0], hi[1], hi[2]}, b_lo[3] = {lo[0], lo[1], lo[2]};
    a_hi[d] = mid;
    b_lo[d] = mid;
    order_box(g, lo, a_hi, bins, n);
    order_box(g, b_lo, hi, bins, n);
}

void vc_seed_grid_bin_order(const vc_seed_grid *g, int64_t *bins)
{
    const int lo[3] = {0, 0, 0};
    int64_t n = 0;
    order_box(g, lo, g->n, bins, &n);
}

void vc_seed_grid_locate(const vc_seed_grid *g, const double x[3], int b[3])
{
    for (int d = 0; d < 3; d++) {
        double t = (x[d] - g->lo[d]) / g->h;
        int i = t >= 0 ? (int)t : 0;
        if (i >= g->n[d])
            i = g->n[d] - 1;
        if (i < 0)
            i = 0;
        b[d] = i;
    }
}

int vc_seed_grid_build(vc_seed_grid *g, const double *xyz, int64_t n,
                       const double lo[3], const double hi[3], double seeds_per_bin)
{
    memset(g, 0, sizeof *g);
    double ext[3], vol = 1.0, maxext = 0;
    for (int d = 0; d < 3; d++) {
        ext[d] = hi[d] - lo[d];
        if (ext[d] > maxext)
            maxext = ext[d];
    }
    if (!(maxext > 0))
        maxext = 1.0; /* a single seed, or all seeds at one point */
    for (int d = 0; d < 3; d++) {
        if (ext[d] < 1e-12 * maxext)
            ext[d] = 1e-12 * maxext; /* flat seed sets still get a volume */
        vol *= ext[d];
    }
    double h = cbrt(vol * seeds_per_bin / (double)(n > 0 ? n : 1));
    /* Cap the bin count so that huge, sparse boxes stay cheap. */
    for (;;) {
        double nb = 1;
        for (int d = 0; d < 3; d++)
            nb *= floor(ext[d] / h) + 1;
        if (nb <= 4.0 * (double)n + 64)
            break;
        h *= 1.25;
    }
    g->h = h;
    int64_t nbins = 1;
    for (int d = 0; d < 3; d++) {
        g->lo[d] = lo[d];
        g->n[d] = (int)floor(ext[d] / h) + 1;
        nbins *= g->n[d];
    }
    g->bin_start = calloc((size_t)nbins + 1, sizeof(int64_t));
    g->seed_index = malloc((size_t)(n > 0 ? n : 1) * sizeof(int64_t));
    g->xyz = malloc((size_t)(n > 0 ? n : 1) * 3 * sizeof(double));
    int64_t *bin_of = malloc((size_t)(n > 0 ? n : 1) * sizeof(int64_t));
    if (!g->bin_start || !g->seed_index || !g->xyz || !bin_of) {
        free(bin_of);
        vc_seed_grid_free(g);
        return -1;
    }
    for (int64_t i = 0; i < n; i++) {
        int b[3];
        vc_seed_grid_locate(g, xyz + 3 * i, b);
        bin_of[i] = vc_seed_grid_bin(g, b[0], b[1], b[2]);
        g->bin_start[bin_of[i] + 1]++;
    }
    for (int64_t b = 0; b < nbins; b++)
        g->bin_start[b + 1] += g->bin_start[b];
    /* Stable counting sort: seeds keep their input order inside a bin. */
    int64_t *fill = malloc((size_t)nbins * sizeof(int64_t));
    if (!fill) {
        free(bin_of);
        vc_seed_grid_free(g);
        return -1;
    }
    memcpy(fill, g->bin_start, (size_t)nbins * sizeof(int64_t));
    for (int64_t i = 0; i < n; i++) {
        int64_t k = fill[bin_of[i]]++;
        g->seed_index[k] = i;
        memcpy(g->xyz + 3 * k, xyz + 3 * i, 3 * sizeof(double));
    }
    free(fill);
    free(bin_of);

    const int R = VC_GRID_MAX_RING;
    int side = 2 * R + 1;
    g->offsets = malloc((size_t)side * side * side * sizeof(vc_grid_offset));
    if (!g->offsets) {
        vc_seed_grid_free(g);
        return -1;
    }
    /* Nearest first, ties by (dz, dy, dx): a stable counting sort of the
     * offsets listed in (dz, dy, dx) order by their squared gap, an integer
     * of at most 3 (R - 1)^2 (a sort of the same table for every grid cost
     * the unskew's local builds, thousands of small grids, 2% of their
     * time) */
    enum { MAX_SUM = 3 * (VC_GRID_MAX_RING - 1) * (VC_GRID_MAX_RING - 1) };
    int start[MAX_SUM + 2] = {0};
    for (int dz = -R; dz <= R; dz++)
        for (int dy = -R; dy <= R; dy++)
            for (int dx = -R; dx <= R; dx++)
                start[(int)(gap(dx) * gap(dx) + gap(dy) * gap(dy) + gap(dz) * gap(dz)) + 1]++;
    for (int v = 0; v <= MAX_SUM; v++)
        start[v + 1] += start[v];
    int k = 0;
    for (int dz = -R; dz <= R; dz++)
        for (int dy = -R; dy <= R; dy++)
            for (int dx = -R; dx <= R; dx++) {
                const double d2 = gap(dx) * gap(dx) + gap(dy) * gap(dy) + gap(dz) * gap(dz);
                vc_grid_offset *o = &g->offsets[start[(int)d2]++];
                o->dx = dx;
                o->dy = dy;
                o->dz = dz;
                o->dmin2 = d2;
                k++;
            }
    g->n_offsets = k;
    return 0;
}

void vc_seed_grid_free(vc_seed_grid *g)
{
    free(g->bin_start);
    free(g->seed_index);
    free(g->xyz);
    free(g->offsets);
    memset(g, 0, sizeof *g);
}
