/* The Voronoi engine's driver: checks the seeds, computes every kept cell on
 * its own (in parallel: a cell depends only on the seeds), then stitches
 * them into one conforming mesh. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE 1 /* madvise, in cell_result.h */
#endif
#include "vorocrust/voronoi.h"
#include "vorocrust/seeds.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cell_result.h"
#include "convex_cell.h"
#include "seed_grid.h"
#include "seed_kdtree.h"
#include "cell_stitch.h"
#include "util/threads.h"

static double wall_seconds(void)
{
#ifdef _OPENMP
    return omp_get_wtime();
#else
    return 0;
#endif
}

/* The stitching (cell_stitch.h) merges Voronoi vertices nearer each other
 * than MERGE_TOL times their distance to their seeds: seeds co-spherical
 * to rounding give one vertex. */
#define MERGE_TOL 1e-8

void vc_voronoi_options_default(vc_voronoi_options *opt)
{
    memset(opt, 0, sizeof *opt);
}

enum {
    CELL_OK = 0,
    CELL_DUPLICATE = 1,
    CELL_NUMERIC = 2,
    CELL_EMPTY = 3,
    CELL_NOMEM = 4,
    CELL_TOO_BIG = 5
};

typedef struct cell_job {
    const vc_seed_grid *grid;
    const vc_seed_kdtree *tree;
    double box_lo[3], box_hi[3];
    double dup_dist2;
    double slack; /* rounding allowance on bin boxes (absolute) */
    const double *seed_xyz; /* the seeds' coordinates, by seed index */
    vc_power_ctx ctx;       /* the same, and the box, for the exact side test */
} cell_job;

/* Beyond the first shell of bins, a seed t (at p relative to the seed) can
 * only cut the cell if some vertex x is closer to t than to the seed:
 * |x - p| < |x|, i.e. t lies in the clearance ball of x (centre x, radius
 * |x|). Bins are tested against the balls of the vertices that can reach
 * them (4 |x|^2 >= the bin's squared distance), and the rings of bins stop
 * where no ball reaches. Only seeds that would leave the cell unchanged
 * are skipped, so the cuts made, and their order, are the same as when
 * every seed passing the radius test is tried. */
typedef struct prune {
    vc_cell_buf ball;  /* 4 per vertex: x, y, z (relative), |x|^2 (grown), by
                          decreasing |x| */
    int n;             /* vertices with 4 |x|^2 >= h^2 (the others cannot reach) */
    int dirty;         /* the cell changed since the balls were listed */
    int range_ok;      /* range[] is up to date */
    int range[3][2];   /* bins any ball reaches (clamped to the grid) */
    int no_balls;      /* out of memory for the balls: nothing is pruned */
} prune;

/* Relative slack for the ball tests: far above rounding, far below the
 * cutting tolerance's effect (a vertex must be tol |p| beyond the plane). */
#define BALL_GROW (1.0 + 1e-9)
/* Cells whose squared radius exceeds BIG_CELL bin sizes squared use the
 * ball test in the first rings of bins too. */
#define BIG_CELL 2.25

/* The squared radius of vertex t's clearance ball (centre: the vertex
 * relative to the seed, x): the exact vertex is within ev of x, its ball
 * within 2 ev of x's, grown for rounding. */
static inline double clearance_r2(const vc_convex_cell *cell, int t, const double x[3])
{
    const double rr = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) + 2 * cell->ev[t];
    return rr * rr * BALL_GROW;
}

/* Inserts the ball (x, r2) into the n balls of b (4 doubles each), kept in
 * decreasing radius. */
static void insert_by_radius(double *b, int n, const double x[3], double r2)
{
    int w = n;
    for (; w > 0 && b[4 * (w - 1) + 3] < r2; w--)
        memcpy(b + 4 * w, b + 4 * (w - 1), 4 * sizeof(double));
    b[4 * w] = x[0];
    b[4 * w + 1] = x[1];
    b[4 * w + 2] = x[2];
    b[4 * w + 3] = r2;
}

static void prune_refresh(const cell_job *job, const vc_convex_cell *cell, prune *pr)
{
    if (!pr->dirty)
        return;
    const double h2 = job->grid->h * job->grid->h;
    if (pr->ball.cap < cell->nt) {
        free(pr->ball.data);
        pr->ball.cap = cell->nt + 64;
        pr->ball.data = malloc((size_t)pr->ball.cap * 4 * sizeof(double));
        if (!pr->ball.data) {
            /* The balls only prune: without them every bin is visited,
             * which gives the same cell, more slowly. */
            pr->ball.cap = 0;
            pr->no_balls = 1;
            pr->dirty = 0;
            pr->range_ok = 0;
            return;
        }
    }
    pr->no_balls = 0;
    double *b = pr->ball.data;
    int n = 0;
    for (int t = 0; t < cell->nt; t++) {
        const double x[3] = {cell->px[t], cell->py[t], cell->pz[t]};
        const double r2 = clearance_r2(cell, t, x);
        if (4.0 * r2 < 0.9 * h2)
            continue;
        /* by decreasing radius: a bin test stops at the first ball too
         * small to reach the bin */
        insert_by_radius(b, n++, x, r2);
    }
    pr->n = n;
    pr->dirty = 0;
    pr->range_ok = 0;
}

/* May a seed of bin (i, j, k) cut the cell of the seed at xs? d2: the
 * squared distance from xs to the bin (a lower bound of |p|^2). */
static int bin_reachable(const cell_job *job, const vc_convex_cell *cell, prune *pr,
                         const double *xs, int i, int j, int k, double d2)
{
    prune_refresh(job, cell, pr);
    if (pr->no_balls)
        return 1;
    const vc_seed_grid *g = job->grid;
    const int b[3] = {i, j, k};
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
        lo[d] = (g->lo[d] + b[d] * g->h) - xs[d] - job->slack;
        hi[d] = lo[d] + g->h + 2 * job->slack;
    }
    const double *x = pr->ball.data;
    for (int v = 0; v < pr->n; v++, x += 4) {
        if (4.0 * x[3] < d2)
            break; /* this ball and the smaller ones cannot reach the bin */
        double e2 = 0;
        for (int d = 0; d < 3; d++) {
            double e = x[d] < lo[d] ? lo[d] - x[d] : (x[d] > hi[d] ? x[d] - hi[d] : 0);
            e2 += e * e;
        }
        if (e2 <= x[3])
            return 1;
    }
    return 0;
}

/* The bins any clearance ball reaches, per axis (clamped to the grid). */
static void prune_range(const cell_job *job, const vc_convex_cell *cell, prune *pr,
                        const double *xs)
{
    prune_refresh(job, cell, pr);
    if (pr->range_ok)
        return;
    const vc_seed_grid *g = job->grid;
    if (pr->no_balls) { /* the whole grid */
        for (int d = 0; d < 3; d++) {
            pr->range[d][0] = 0;
            pr->range[d][1] = g->n[d] - 1;
        }
        return;
    }
    for (int d = 0; d < 3; d++) {
        pr->range[d][0] = g->n[d];
        pr->range[d][1] = -1;
    }
    /* A ball meets the grid's box G only where, along axis d, it is within
     * sqrt(r^2 - (its squared distance to G across the other axes)) of
     * its centre. */
    const double *x = pr->ball.data;
    for (int v = 0; v < pr->n; v++, x += 4) {
        double r = sqrt(x[3]) * BALL_GROW + job->slack;
        double c[3], e2[3], sum = 0;
        for (int d = 0; d < 3; d++) {
            c[d] = xs[d] + x[d] - g->lo[d];
            double top = g->n[d] * g->h;
            double e = c[d] < 0 ? -c[d] : (c[d] > top ? c[d] - top : 0);
            e2[d] = e * e;
            sum += e2[d];
        }
        if (sum > r * r)
            continue; /* misses the grid */
        for (int d = 0; d < 3; d++) {
            double w = sqrt(r * r - (sum - e2[d])) * BALL_GROW + job->slack;
            double a = floor((c[d] - w) / g->h) - 1, z = floor((c[d] + w) / g->h) + 1;
            int ia = a < 0 ? 0 : (a >= g->n[d] ? g->n[d] - 1 : (int)a);
            int iz = z < 0 ? 0 : (z >= g->n[d] ? g->n[d] - 1 : (int)z);
            if (ia < pr->range[d][0])
                pr->range[d][0] = ia;
            if (iz > pr->range[d][1])
                pr->range[d][1] = iz;
        }
    }
    pr->range_ok = 1;
}

/* Cuts the cell with the bisector of seed t (at relative position p,
 * squared distance d2); returns CELL_*. */
static int cut_with_seed(const cell_job *job, vc_convex_cell *cell, prune *pr, int64_t t,
                         const double p[3], double d2, int64_t *other)
{
    if (d2 <= job->dup_dist2) {
        *other = t;
        return CELL_DUPLICATE;
    }
    int r = vc_convex_cell_cut(cell, p, t);
    if (r == VC_CELL_NOMEM)
        return CELL_NOMEM;
    if (r == -1)
        return CELL_NUMERIC;
    if (r == -2)
        return CELL_EMPTY;
    if (r == 1)
        pr->dirty = 1;
    return CELL_OK;
}

/* A plane at distance |p| / 2 can only cut the cell if |p| < 2 rmax. */
static inline int may_cut(const vc_convex_cell *cell, double d2)
{
    return d2 <= 4.0 * cell->rmax2 * (1.0 + 1e-9);
}

/* Visits the seeds of one bin; returns CELL_*. */
static int cut_with_bin(const cell_job *job, vc_convex_cell *cell, prune *pr, int64_t s,
                        const double *xs, int64_t bin, int64_t *other)
{
    const vc_seed_grid *g = job->grid;
    for (int64_t k = g->bin_start[bin]; k < g->bin_start[bin + 1]; k++) {
        int64_t t = g->seed_index[k];
        if (t == s)
            continue;
        const double *xt = g->xyz + 3 * k;
        double p[3] = {xt[0] - xs[0], xt[1] - xs[1], xt[2] - xs[2]};
        double d2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        if (!may_cut(cell, d2))
            continue;
        int r = cut_with_seed(job, cell, pr, t, p, d2, other);
        if (r != CELL_OK)
            return r;
    }
    return CELL_OK;
}

/* A neighbour candidate of the first shell of bins. */
typedef struct candidate {
    double d2;
    int32_t k;    /* position in the grid's seed order (< 2^31, checked) */
    int32_t step; /* distance step, for the sort below */
} candidate;

static candidate *reserve_candidates(vc_cell_buf *b, int need)
{
    if (need > b->cap) {
        int n = b->cap ? 2 * b->cap : 128;
        while (n < need)
            n *= 2;
        void *q = realloc(b->data, (size_t)n * sizeof(candidate));
        if (!q)
            return NULL;
        b->data = q;
        b->cap = n;
    }
    return b->data;
}

/* Distance from x to bin i along axis d (0 when x is level with it). */
static inline double axis_gap(const vc_seed_grid *g, const double *x, int d, int i)
{
    double lo = g->lo[d] + i * g->h, hi = lo + g->h;
    return x[d] < lo ? lo - x[d] : (x[d] > hi ? x[d] - hi : 0);
}

/* Squared distance from x to the box of bin (i, j, k). */
static double bin_dist2(const vc_seed_grid *g, const double *x, int i, int j, int k)
{
    const int b[3] = {i, j, k};
    double d2 = 0;
    for (int d = 0; d < 3; d++) {
        double e = axis_gap(g, x, d, b[d]);
        d2 += e * e;
    }
    return d2;
}

/* Per axis d, the squared gap from x to the bins at offsets -R .. R
 * (R = VC_GRID_MAX_RING) from bin b, infinite for bins outside the grid:
 * the squared distance to the bin at offset (i, j, k) is then
 * gap2[0][i + R] + gap2[1][j + R] + gap2[2][k + R], bin_dist2's sum. */
static void offset_gaps(const vc_seed_grid *g, const double *x, const int b[3],
                        double gap2[3][2 * VC_GRID_MAX_RING + 1])
{
    for (int d = 0; d < 3; d++)
        for (int o = -VC_GRID_MAX_RING; o <= VC_GRID_MAX_RING; o++) {
            const int i = b[d] + o;
            const double e = i >= 0 && i < g->n[d] ? axis_gap(g, x, d, i) : INFINITY;
            gap2[d][o + VC_GRID_MAX_RING] = e * e;
        }
}

/* Resets the cell of the seed at xs to the clipping box, in coordinates
 * relative to the seed. */
static int reset_to_box(const cell_job *job, vc_convex_cell *cell, int64_t s, const double *xs)
{
    cell->ctx = &job->ctx;
    cell->seed = s;
    double lo[3], hi[3];
    const int64_t walls[6] = {VC_WALL_XMIN - 0, VC_WALL_XMIN - 1, VC_WALL_XMIN - 2,
                              VC_WALL_XMIN - 3, VC_WALL_XMIN - 4, VC_WALL_XMIN - 5};
    for (int d = 0; d < 3; d++) {
        lo[d] = job->box_lo[d] - xs[d];
        hi[d] = job->box_hi[d] - xs[d];
    }
    return vc_convex_cell_reset_box(cell, lo, hi, walls);
}

/* Builds the cell of seed s (at xs) into cell; returns CELL_*. The seeds of the
 * 27 nearest bins are cut nearest first, so that the cell shrinks fast and
 * the farther seeds are mostly rejected by the radius test alone. */
static int compute_cell(const cell_job *job, vc_convex_cell *cell, vc_cell_buf *cand_buf,
                        prune *pr, int64_t s, const double *xs, int64_t *other)
{
    const vc_seed_grid *g = job->grid;

    if (reset_to_box(job, cell, s, xs) != 0)
        return CELL_NOMEM;
    int b[3];
    vc_seed_grid_locate(g, xs, b);
    const double h2 = g->h * g->h;
    enum { R = VC_GRID_MAX_RING };
    double gap2[3][2 * R + 1];
    offset_gaps(g, xs, b, gap2);

    /* The first shell: offsets with a zero distance bound come first. They
     * are tried near first, by a counting sort on the distance in steps
     * of h / 4 squared: cheaper than a full sort and as effective (the
     * order within a step hardly changes how fast the cell shrinks). */
    enum { N_STEPS = 32 };
    int step_start[N_STEPS + 1] = {0};
    const double inv_step = 16.0 / h2;
    int n_cand = 0, o = 0;
    for (; o < g->n_offsets && g->offsets[o].dmin2 == 0; o++) {
        const vc_grid_offset *off = &g->offsets[o];
        if (isinf(gap2[0][off->dx + R] + gap2[1][off->dy + R] + gap2[2][off->dz + R]))
            continue; /* outside the grid */
        int i = b[0] + off->dx, j = b[1] + off->dy, k = b[2] + off->dz;
        int64_t bin = vc_seed_grid_bin(g, i, j, k);
        int64_t k0 = g->bin_start[bin], k1 = g->bin_start[bin + 1];
        if (k1 == k0)
            continue;
        candidate *cand = reserve_candidates(cand_buf, n_cand + (int)(k1 - k0));
        if (!cand)
            return CELL_NOMEM;
        for (int64_t kk = k0; kk < k1; kk++) {
            if (g->seed_index[kk] == s)
                continue;
            const double *xt = g->xyz + 3 * kk;
            double dx = xt[0] - xs[0], dy = xt[1] - xs[1], dz = xt[2] - xs[2];
            const double d2 = dx * dx + dy * dy + dz * dz, q = d2 * inv_step;
            const int st = q < N_STEPS - 1 ? (int)q : N_STEPS - 1;
            cand[n_cand] = (candidate){d2, (int32_t)kk, st};
            step_start[st + 1]++;
            n_cand++;
        }
    }
    candidate *cand = reserve_candidates(cand_buf, 2 * n_cand);
    if (!cand)
        return CELL_NOMEM;
    candidate *sorted = cand + n_cand;
    for (int st = 0; st < N_STEPS; st++)
        step_start[st + 1] += step_start[st];
    for (int m = 0; m < n_cand; m++)
        sorted[step_start[cand[m].step]++] = cand[m];
    for (int m = 0; m < n_cand; m++) {
        if (!may_cut(cell, sorted[m].d2))
            continue;
        const double *xt = g->xyz + 3 * sorted[m].k;
        double p[3] = {xt[0] - xs[0], xt[1] - xs[1], xt[2] - xs[2]};
        int r = cut_with_seed(job, cell, pr, g->seed_index[sorted[m].k], p, sorted[m].d2, other);
        if (r != CELL_OK)
            return r;
    }

    pr->dirty = 1;
    for (; o < g->n_offsets; o++) {
        const vc_grid_offset *off = &g->offsets[o];
        /* The offsets are a cube of Chebyshev radius R sorted by distance:
         * past the first one out of reach, none of them is in reach, but
         * the rings beyond the cube start at (R h)^2 and may be. */
        if (!may_cut(cell, off->dmin2 * h2)) {
            if (!may_cut(cell, (double)R * R * h2))
                return CELL_OK;
            break;
        }
        /* Infinite outside the grid, which may_cut rejects. */
        const double bd2 = gap2[0][off->dx + R] + gap2[1][off->dy + R] + gap2[2][off->dz + R];
        if (!may_cut(cell, bd2))
            continue;
        int i = b[0] + off->dx, j = b[1] + off->dy, k = b[2] + off->dz;
        /* The ball test costs more than it saves on ordinary cells. */
        if (cell->rmax2 > BIG_CELL * h2 && !bin_reachable(job, cell, pr, xs, i, j, k, bd2))
            continue;
        int r = cut_with_bin(job, cell, pr, s, xs, vc_seed_grid_bin(g, i, j, k), other);
        if (r != CELL_OK)
            return r;
    }
    /* Beyond the precomputed offsets: whole rings of bins, outward, within
     * the bins the clearance balls reach. */
    int max_n = g->n[0];
    if (g->n[1] > max_n)
        max_n = g->n[1];
    if (g->n[2] > max_n)
        max_n = g->n[2];
    for (int ring = R + 1; ring <= max_n; ring++) {
        double dmin = (ring - 1) * g->h;
        if (!may_cut(cell, dmin * dmin))
            break;
        prune_range(job, cell, pr, xs);
        /* The range is only recomputed per ring: a stale one is larger. */
        const int(*rg)[2] = pr->range;
        if (b[0] - rg[0][0] < ring && rg[0][1] - b[0] < ring && b[1] - rg[1][0] < ring &&
            rg[1][1] - b[1] < ring && b[2] - rg[2][0] < ring && rg[2][1] - b[2] < ring)
            break; /* no ball reaches this ring or beyond */
        int k0 = b[2] - ring > rg[2][0] ? b[2] - ring : rg[2][0];
        int k1 = b[2] + ring < rg[2][1] ? b[2] + ring : rg[2][1];
        int j0 = b[1] - ring > rg[1][0] ? b[1] - ring : rg[1][0];
        int j1 = b[1] + ring < rg[1][1] ? b[1] + ring : rg[1][1];
        for (int k = k0; k <= k1; k++) {
            for (int j = j0; j <= j1; j++) {
                int on_shell_jk = abs(k - b[2]) == ring || abs(j - b[1]) == ring;
                int step = on_shell_jk ? 1 : 2 * ring;
                int i0 = b[0] - ring, i1 = b[0] + ring;
                if (on_shell_jk) {
                    i0 = i0 > rg[0][0] ? i0 : rg[0][0];
                    i1 = i1 < rg[0][1] ? i1 : rg[0][1];
                }
                for (int i = i0; i <= i1; i += step) {
                    if (i < rg[0][0] || i > rg[0][1])
                        continue;
                    double bd2 = bin_dist2(g, xs, i, j, k);
                    if (!may_cut(cell, bd2) || !bin_reachable(job, cell, pr, xs, i, j, k, bd2))
                        continue;
                    int r = cut_with_bin(job, cell, pr, s, xs, vc_seed_grid_bin(g, i, j, k),
                                         other);
                    if (r != CELL_OK)
                        return r;
                }
            }
        }
    }
    return CELL_OK;
}

/* Neighbours asked of the tree at first; when the cell still reaches
 * beyond the last of them, every seed within twice its radius and within a
 * clearance ball of one of its vertices comes from range queries, RANGE_MAX
 * at a time, nearest first (about 15 neighbours cut an ordinary cell, but a
 * VoroCrust surface cell reaches 60 to 200 seeds, and a cell open to the
 * clipping box thousands). After each batch the cell's reach and balls are
 * taken again: they shrink as the cell is cut, so a small batch prunes what
 * a large one would have listed. Since session 46 a cell still open to the
 * box goes the same way (it asked the tree for twice as many neighbours,
 * up to 3,072, then searched the grid's rings): every seed's cell of
 * fertility.off's seeds (65,543, one thread) 7.4 -> 3.2 s, bunny.off's
 * (112,657) 10.5 -> 5.5 s, the same cells. Batches of 4,096 cost 7.4 s
 * there, of 1,024 6.4 s, of 256 5.7 s, of 64 (open cells on the grid's
 * rings) 5.5 s. */
#define KNN_FIRST 48
#define RANGE_MAX 64

static int reserve_hits(vc_cell_buf *b, int k)
{
    if (b->cap >= k)
        return 0;
    void *q = realloc(b->data, sizeof(vc_kd_hit) * (size_t)k);
    if (!q)
        return -1;
    b->data = q;
    b->cap = k;
    return 0;
}

/* Cuts the cell by hit[0..n) in order while they can reach it; returns
 * CELL_*, and *more = 1 when the last one could still cut. */
static int cut_with_hits(const cell_job *job, vc_convex_cell *cell, prune *pr, const double *xs,
                         const vc_kd_hit *hit, int n, int *more, int64_t *other)
{
    *more = 0;
    for (int m = 0; m < n; m++) {
        if (!may_cut(cell, hit[m].d2))
            return CELL_OK; /* the rest are farther still */
        const double *xt = job->seed_xyz + 3 * hit[m].seed;
        double p[3] = {xt[0] - xs[0], xt[1] - xs[1], xt[2] - xs[2]};
        int r = cut_with_seed(job, cell, pr, hit[m].seed, p, hit[m].d2, other);
        if (r != CELL_OK)
            return r;
    }
    *more = n > 0 && may_cut(cell, hit[n - 1].d2);
    return CELL_OK;
}

/* The clearance balls of a cell's vertices (relative to its seed, grown by
 * the vertices' error), for the range query: a seed outside all of them
 * leaves the cell as it is, and so does it any smaller cell (a half-space
 * that meets a convex cell holds one of its vertices), so the balls of the
 * cell at the query stay valid while the candidates cut it. */
typedef struct clearance {
    const double *ball; /* 4 per vertex: x, y, z, squared radius; by
                           decreasing radius */
    int n;
    const double *xs;
    double slack;
    double lo[3], hi[3]; /* the balls' bounding box */
} clearance;

static int clearance_reaches(void *ctx, const double lo[3], const double hi[3])
{
    const clearance *c = ctx;
    double l[3], h[3], d2 = 0;
    for (int d = 0; d < 3; d++) {
        l[d] = lo[d] - c->xs[d] - c->slack;
        h[d] = hi[d] - c->xs[d] + c->slack;
        if (l[d] > c->hi[d] || h[d] < c->lo[d])
            return 0; /* outside every ball's bounding box */
        const double e = l[d] > 0 ? l[d] : (h[d] < 0 ? -h[d] : 0);
        d2 += e * e;
    }
    const double *x = c->ball;
    for (int v = 0; v < c->n; v++, x += 4) {
        /* a ball through the seed reaches at most its diameter from it;
         * the rest are smaller still */
        if (4.0 * x[3] < d2)
            break;
        double e2 = 0;
        for (int d = 0; d < 3; d++) {
            const double e = x[d] < l[d] ? l[d] - x[d] : (x[d] > h[d] ? x[d] - h[d] : 0);
            e2 += e * e;
        }
        if (e2 <= x[3])
            return 1;
    }
    return 0;
}

/* The clearance balls of every vertex of the cell into b (4 doubles each),
 * by decreasing radius, and their bounding box into cl. */
static int clearance_balls(const vc_convex_cell *cell, vc_cell_buf *b, clearance *cl)
{
    if (b->cap < cell->nt) {
        void *q = realloc(b->data, sizeof(double) * 4 * (size_t)(cell->nt + 64));
        if (!q)
            return -1;
        b->data = q;
        b->cap = cell->nt + 64;
    }
    double *bd = b->data;
    for (int d = 0; d < 3; d++) {
        cl->lo[d] = INFINITY;
        cl->hi[d] = -INFINITY;
    }
    for (int t = 0; t < cell->nt; t++) {
        const double x[3] = {cell->px[t], cell->py[t], cell->pz[t]};
        const double r2 = clearance_r2(cell, t, x), r = sqrt(r2);
        for (int d = 0; d < 3; d++) {
            cl->lo[d] = fmin(cl->lo[d], x[d] - r);
            cl->hi[d] = fmax(cl->hi[d], x[d] + r);
        }
        insert_by_radius(bd, t, x, r2);
    }
    cl->ball = bd;
    cl->n = cell->nt;
    return 0;
}

/* Builds the cell of seed s (at xs) into cell; returns CELL_*. Its
 * neighbours are cut nearest first (from the k-d tree), until the next
 * one is farther than twice the cell's radius: no seed beyond can cut. */
static int compute_cell_knn(const cell_job *job, vc_convex_cell *cell, vc_cell_buf *hit_buf,
                            prune *pr, vc_kd_hint *hint, int64_t s, const double *xs,
                            int64_t *other)
{
    if (reset_to_box(job, cell, s, xs) != 0 || reserve_hits(hit_buf, KNN_FIRST) != 0)
        return CELL_NOMEM;
    const vc_seed_kdtree *t = job->tree;
    vc_kd_hit *hit = hit_buf->data;
    /* bounded by the thread's previous cell's (its neighbour in the build
     * order): the k-d tree's share of cow.off's cells 14.6% -> 12.8% */
    const int got = vc_seed_kdtree_knn_hinted(t, hint, xs, KNN_FIRST, s, hit);
    int more, r = cut_with_hits(job, cell, pr, xs, hit, got, &more, other);
    if (r != CELL_OK || got < KNN_FIRST || !more)
        return r;
    /* every further seed that can still cut: within twice the radius the
     * cell has now (it only shrinks) and in a clearance ball of one of its
     * vertices, RANGE_MAX at a time in (d2, seed) order, the cell's reach
     * and balls taken again after each batch */
    vc_kd_hit last = hit[got - 1];
    if (reserve_hits(hit_buf, RANGE_MAX) != 0)
        return CELL_NOMEM;
    hit = hit_buf->data;
    for (;;) {
        clearance cl = {NULL, 0, xs, job->slack, {0, 0, 0}, {0, 0, 0}};
        if (clearance_balls(cell, &pr->ball, &cl) != 0)
            return CELL_NOMEM;
        pr->dirty = 1; /* the grid's pruning lists its balls again */
        int truncated;
        const int n = vc_seed_kdtree_within(t, xs, 4.0 * cell->rmax2 * (1.0 + 1e-9), last, s,
                                            clearance_reaches, &cl, hit, RANGE_MAX, &truncated);
        r = cut_with_hits(job, cell, pr, xs, hit, n, &more, other);
        if (r != CELL_OK || !truncated || !more)
            return r;
        last = hit[n - 1];
    }
}

/* The finished cells of one chunk of the build order are appended to a
 * per-thread scratch buffer (planes and face lists), then copied into one
 * exact-size block: few allocations, in the spatial order the stitching
 * reads them in. */
typedef struct byte_buf {
    char *data;
    size_t len, cap;
} byte_buf;

static char *byte_buf_grow(byte_buf *b, size_t add)
{
    if (b->len + add > b->cap) {
        size_t n = b->cap ? 2 * b->cap : (size_t)1 << 16;
        while (n < b->len + add)
            n *= 2;
        char *q = realloc(b->data, n);
        if (!q)
            return NULL;
        b->data = q;
        b->cap = n;
    }
    char *p = b->data + b->len;
    b->len += add;
    return p;
}

static size_t topo_bytes(int nf, int nfv, int nv)
{
    size_t b = (size_t)nf * sizeof(int32_t) + (size_t)(nf + 1 + nfv + 3 * nv) * sizeof(uint16_t);
    return (b + 7) & ~(size_t)7;
}

/* Appends the finished cell's combinatorics to the scratch buffer (res
 * gets the counts; its pointers are set when the chunk is stored).
 * Returns 0, or -1 when out of memory. */
static int store_cell(vc_convex_cell *cell, byte_buf *topo, vc_cell_result *res)
{
    char *t = byte_buf_grow(topo, topo_bytes(cell->nf, cell->nfv, cell->nv));
    if (!t)
        return -1;
    res->nv = cell->nv;
    res->nf = cell->nf;
    res->nfv = cell->nfv;
    int32_t *plane = (int32_t *)t;
    uint16_t *fs = (uint16_t *)(plane + cell->nf), *fv = fs + cell->nf + 1;
    uint16_t *vf = fv + cell->nfv;
    for (int f = 0; f < cell->nf; f++)
        plane[f] = (int32_t)cell->face_plane[f]; /* seed indices < 2^31 (checked) */
    for (int f = 0; f <= cell->nf; f++)
        fs[f] = (uint16_t)cell->face_start[f];
    for (int i = 0; i < cell->nfv; i++)
        fv[i] = (uint16_t)cell->fv[i];
    /* Each vertex's three planes as the local faces they make (every plane
     * of a vertex has a face), in the triangle's order. The faces' scratch
     * (b_count) is free again: it maps plane indices to faces. */
    int *face_of = cell->b_count.data;
    for (int f = 0; f < cell->nf; f++)
        face_of[cell->face_plane_index[f]] = f;
    for (int i = 0; i < 3 * cell->nv; i++)
        vf[i] = (uint16_t)face_of[cell->tri[i]];
    return 0;
}

/* Cells per chunk of the build order (one thread builds a chunk). */
#define CHUNK 256

/* About 3 seeds per bin: measured fastest on uniform random seeds (1 and 5
 * are 5 to 15% slower). */
#define SEEDS_PER_BIN 3.0
/* Bins this many times SEEDS_PER_BIN full where the seeds are: the tree.
 * Measured with the range query after the 48 nearest, pruned by the
 * clearance balls (1 thread, cells and stitching, grid / tree; the figure
 * is the mean count of a seed's bin; the mesh pipeline's seed sets, whose
 * outside seeds are not built, and the same with every seed kept): torus.obj
 * 6.8: 1.16 / 1.36 s, all kept 2.53 / 2.66; bracket 36.5: 3.36 / 3.34,
 * all kept 5.42 / 5.97; fertility 105.9: 6.02 / 5.14, all kept 9.76 /
 * 10.39; bunny 1299: 14.1 / 10.8. Uniform random seeds (4.0) are far
 * faster on the grid. */
#define CROWDED_BINS 20.0

/* The seeds' (or the box's) span: cell volumes go as its cube, the
 * duplicate distance as its square; outside these bounds either leaves the
 * normal doubles. */
#define VC_SPAN_MAX 1e60
#define VC_SPAN_MIN 1e-60

/* The diagonal of the box lo..hi without overflow or underflow: the
 * extents scaled by a power of two (exact), so that it is bit for bit
 * sqrt(dx^2 + dy^2 + dz^2) whenever that does not overflow; +inf when an
 * extent does. */
static double span_diagonal(const double lo[3], const double hi[3])
{
    double m = 0;
    for (int d = 0; d < 3; d++)
        if (hi[d] - lo[d] > m)
            m = hi[d] - lo[d];
    if (!(m > 0) || !isfinite(m))
        return m > 0 ? INFINITY : 0;
    int e;
    (void)frexp(m, &e);
    double sum = 0;
    for (int d = 0; d < 3; d++) {
        double u = ldexp(hi[d] - lo[d], -e);
        sum += u * u;
    }
    return ldexp(sqrt(sum), e);
}

/* What a build keeps for rebuilding (vc_voronoi_build_keep): the cells by
 * their place in the build order, the seeds' bounds and the clipping box
 * of the first build. */
struct vc_voronoi_cells {
    int64_t n, n_kept;
    double slo[3], shi[3];  /* the seeds' bounds at the first build */
    cell_job job;           /* its box, duplicate distance and slack */
    int64_t *kept_seed;     /* k -> seed */
    int64_t *build_order;   /* m -> k */
    vc_cell_result *cells;  /* by m */
    vc_cell_store store;
    int64_t last_rebuilt;   /* cells the last rebuild computed again */
    int broken;             /* a rebuild failed half-way: the cells are of no seeds */
};

/* Checks the sphere lists of opt (NULL: none). */
static int check_spheres(const vc_seed_spheres *sp, int64_t n, vc_error *err)
{
    if (!sp)
        return 0;
    int bad = sp->n_spheres < 0 || !sp->start || (sp->n_spheres > 0 && !sp->sphere) ||
              (sp->start && sp->start[0] != 0);
    for (int64_t s = 0; s < n && !bad; s++) {
        bad = sp->start[s + 1] < sp->start[s] || (sp->start[s + 1] > sp->start[s] && !sp->id);
        for (int64_t q = sp->start[s]; q < sp->start[s + 1] && !bad; q++)
            bad = sp->id[q] < 0 || sp->id[q] >= sp->n_spheres ||
                  (q > sp->start[s] && sp->id[q] <= sp->id[q - 1]);
    }
    return bad ? vc_error_set(err, VC_EPARAM, "the seeds' sphere lists are not valid (start "
                              "non-decreasing from 0, ids ascending and below n_spheres)")
               : 0;
}

/* The seeds' neighbour sources: the grid's bins, and the k-d tree where
 * the seeds crowd them (use_tree: -1 decides, else as given). */
static int index_seeds(const vc_seeds *seeds, const double slo[3], const double shi[3],
                       int neighbours, int *use_tree, vc_seed_grid *grid, vc_seed_kdtree *tree,
                       double *crowd_out, vc_error *err)
{
    const int64_t n = seeds->n;
    memset(tree, 0, sizeof *tree);
    if (vc_seed_grid_build(grid, seeds->xyz, n, slo, shi, SEEDS_PER_BIN) != 0)
        return vc_error_set(err, VC_ENOMEM, "out of memory binning %lld seeds", (long long)n);
    /* How crowded the bins are where the seeds are: the mean count of the
     * bin of a seed (sum of squared counts over the seeds). Near
     * SEEDS_PER_BIN + 1 for evenly spread seeds; VoroCrust's seeds crowd
     * the bins along the surface (bunny.off: 70), where every cell would
     * read the seeds of 27 such bins: then the k-d tree. */
    double crowd = 0;
    const int64_t nb = (int64_t)grid->n[0] * grid->n[1] * grid->n[2];
    for (int64_t b = 0; b < nb; b++) {
        const double c = (double)(grid->bin_start[b + 1] - grid->bin_start[b]);
        crowd += c * c;
    }
    crowd /= (double)n;
    *crowd_out = crowd;
    if (*use_tree < 0)
        *use_tree = neighbours == VC_NEIGHBOURS_TREE ||
                    (neighbours != VC_NEIGHBOURS_GRID && crowd > CROWDED_BINS * SEEDS_PER_BIN);
    if (*use_tree && vc_seed_kdtree_build(tree, seeds->xyz, n) != 0) {
        vc_seed_grid_free(grid);
        return vc_error_set(err, VC_ENOMEM, "out of memory indexing %lld seeds", (long long)n);
    }
    return 0;
}

/* A list of cells to build: cell q is seed index[pos[q]] (index NULL: pos[q]
 * itself) at xyz + 3 pos[q]; its result goes to res[q], its status to
 * status[q], a coincident seed's index to other[q]. */
typedef struct cell_batch {
    int64_t n;
    const int64_t *pos, *index;
    const double *xyz;
    vc_cell_result *res;
    int *status;
    int64_t *other;
} cell_batch;

/* Builds the cells of the batch in parallel, chunk by chunk, into the
 * store; progress on the log when asked. Returns the side tests that
 * passed the filter. */
static int64_t build_batch(const cell_job *job, const cell_batch *b, vc_cell_store *store,
                           int threads, const vc_logger *log, int progress)
{
    int64_t done = 0;
    /* progress: looked at every hundredth of the cells, said once a second
     * after the first (a tenth of the cells took up to 3 s on a loaded
     * machine: a 337,562-cell cup) */
    const int64_t report_step = b->n / 100 > 0 ? b->n / 100 : 1;
    double last_report = 0;
    const double t_start = wall_seconds();
    const int64_t n_chunks = (b->n + CHUNK - 1) / CHUNK;
    int64_t n_exact = 0;
#pragma omp parallel num_threads(threads) reduction(+ : n_exact)
    {
        int64_t n_exact_thread = 0;
        vc_convex_cell cell;
        vc_convex_cell_init(&cell);
        vc_cell_buf cand_buf = {NULL, 0}, hit_buf = {NULL, 0};
        prune pr;
        memset(&pr, 0, sizeof pr);
        byte_buf topo = {NULL, 0, 0};
        vc_kd_hint hint = {0, 0, {0, 0, 0}, 0};
#pragma omp for schedule(dynamic, 1)
        for (int64_t ch = 0; ch < n_chunks; ch++) {
            const int64_t q0 = ch * CHUNK, q1 = q0 + CHUNK < b->n ? q0 + CHUNK : b->n;
            topo.len = 0;
            int chunk_ok = 1;
            for (int64_t q = q0; q < q1; q++) {
                const int64_t p = b->pos[q];
                const int64_t s = b->index ? b->index[p] : p;
                const double *xs = b->xyz + 3 * p; /* seed s, or a copy of it */
                int r = job->tree ? compute_cell_knn(job, &cell, &hit_buf, &pr, &hint, s, xs,
                                                     &b->other[q])
                                  : compute_cell(job, &cell, &cand_buf, &pr, s, xs, &b->other[q]);
                if (r == CELL_OK) {
                    const int fr = vc_convex_cell_faces(&cell);
                    r = fr == 0 ? CELL_OK : fr == VC_CELL_NOMEM ? CELL_NOMEM : CELL_NUMERIC;
                }
                n_exact_thread += cell.n_exact;
                /* Local vertex indices are 16-bit in the stored cell. */
                if (r == CELL_OK && cell.nfv > 65535)
                    r = CELL_TOO_BIG;
                if (r == CELL_OK && store_cell(&cell, &topo, &b->res[q]) != 0)
                    r = CELL_NOMEM;
                if (r != CELL_OK)
                    chunk_ok = 0;
                b->status[q] = r;
                if (progress) {
                    int64_t d;
#pragma omp atomic capture
                    d = ++done;
                    if (d % report_step == 0) {
                        const double now = wall_seconds();
                        int say = 0;
#pragma omp critical(vc_voronoi_progress)
                        if (now - t_start > 1.0 && now - last_report >= 1.0) {
                            last_report = now;
                            say = 1;
                        }
                        if (say)
                            vc_log(log, VC_LOG_INFO, "voronoi: %lld / %lld cells", (long long)d,
                                   (long long)b->n);
                    }
                }
            }
            if (!chunk_ok)
                continue; /* the build fails: the cells are not needed */
            char *tb;
#pragma omp critical(vc_cell_store)
            tb = vc_region_take(&store->topo, topo.len);
            if (!tb) {
                for (int64_t q = q0; q < q1; q++)
                    b->status[q] = CELL_NOMEM;
                continue;
            }
            memcpy(tb, topo.data, topo.len);
            for (int64_t q = q0; q < q1; q++) {
                vc_cell_result *c = &b->res[q];
                c->plane = (int32_t *)tb;
                c->face_start = (uint16_t *)(c->plane + c->nf);
                c->fv = c->face_start + c->nf + 1;
                c->vf = c->fv + c->nfv;
                tb += topo_bytes(c->nf, c->nfv, c->nv);
            }
        }
        vc_convex_cell_free(&cell);
        n_exact += n_exact_thread;
        free(cand_buf.data);
        free(hit_buf.data);
        free(pr.ball.data);
        free(topo.data);
    }
    return n_exact;
}

/* The failure of the batch's lowest seed as an error (0 when every cell
 * is built). */
static int batch_error(const cell_batch *b, const vc_seeds *seeds, int64_t n_kept, vc_error *err)
{
    int64_t worst = -1, s = -1;
    for (int64_t q = 0; q < b->n; q++) {
        if (b->status[q] == CELL_OK)
            continue;
        const int64_t p = b->pos[q], sq = b->index ? b->index[p] : p;
        if (worst < 0 || sq < s) {
            worst = q;
            s = sq;
        }
    }
    if (worst >= 0) {
        const int64_t q = worst;
        const double *x = seeds->xyz + 3 * s;
        switch (b->status[q]) {
        case CELL_DUPLICATE:
            return vc_error_set(err, VC_EINPUT, "seeds %lld and %lld coincide at (%g %g %g)",
                                (long long)s, (long long)b->other[q], x[0], x[1], x[2]);
        case CELL_NUMERIC:
            return vc_error_set(err, VC_EINTERNAL,
                                "the cell of seed %lld (%g %g %g): a cut did not remove a disk "
                                "(a defect of the engine)",
                                (long long)s, x[0], x[1], x[2]);
        case CELL_NOMEM:
            return vc_error_set(err, VC_ENOMEM, "out of memory storing %lld cells",
                                (long long)n_kept);
        case CELL_TOO_BIG:
            return vc_error_set(err, VC_EINTERNAL,
                                "the cell of seed %lld (%g %g %g) has too many vertices",
                                (long long)s, x[0], x[1], x[2]);
        default:
            return vc_error_set(err, VC_EINTERNAL, "the cell of seed %lld (%g %g %g) is empty",
                                (long long)s, x[0], x[1], x[2]);
        }
    }
    return 0;
}

void vc_voronoi_cells_free(vc_voronoi_cells *vc)
{
    if (!vc)
        return;
    vc_region_pool_free(&vc->store.topo);
    free(vc->kept_seed);
    free(vc->build_order);
    free(vc->cells);
    free(vc);
}

int64_t vc_voronoi_cells_rebuilt(const vc_voronoi_cells *vc)
{
    return vc ? vc->last_rebuilt : 0;
}

/* The build order (build_order[m]: the kept index of the m-th cell built)
 * and where each seed is in the neighbour source's own order
 * (build_pos[m]): the k-d tree's leaves when there is one (the crowded
 * bins that call for it hold thousands of seeds each, in input order, and
 * the tree's order is spatial at every scale), else the grid's bins in a
 * spatially coherent order, so that consecutive cells read the same seeds
 * from cache and the stitching reads each cell with its neighbours. (The
 * tree's order measured no faster on cow.off's seeds; kept so that
 * test_voronoi's comparison of the two neighbour sources builds in two
 * orders.) Returns 0, or -1 when out of memory. */
static int make_build_order(const vc_seeds *seeds, const vc_seed_grid *grid,
                            const vc_seed_kdtree *tree, int64_t *build_order, int64_t *build_pos)
{
    const int64_t n = seeds->n;
    const int64_t n_bins = (int64_t)grid->n[0] * grid->n[1] * grid->n[2];
    int64_t *kept_index = malloc((size_t)n * sizeof(int64_t));
    int64_t *bin_order = tree->n > 0 ? NULL : malloc((size_t)n_bins * sizeof(int64_t));
    if (!kept_index || (tree->n == 0 && !bin_order)) {
        free(kept_index);
        free(bin_order);
        return -1;
    }
    for (int64_t i = 0, k = 0; i < n; i++)
        kept_index[i] = seeds->label[i] != 0 ? k++ : -1;
    if (tree->n > 0) {
        for (int64_t j = 0, m = 0; j < n; j++) {
            const int64_t k = kept_index[tree->index[j]];
            if (k >= 0) {
                build_order[m] = k;
                build_pos[m++] = j;
            }
        }
    } else {
        vc_seed_grid_bin_order(grid, bin_order);
        for (int64_t q = 0, m = 0; q < n_bins; q++) {
            const int64_t b = bin_order[q];
            for (int64_t j = grid->bin_start[b]; j < grid->bin_start[b + 1]; j++) {
                const int64_t k = kept_index[grid->seed_index[j]];
                if (k >= 0) {
                    build_order[m] = k;
                    build_pos[m++] = j;
                }
            }
        }
    }
    free(kept_index);
    free(bin_order);
    return 0;
}

/* The seeds' bounding box and kept count; fails on a non-finite
 * coordinate. */
static int seed_bounds(const vc_seeds *seeds, double slo[3], double shi[3], int64_t *n_kept,
                       vc_error *err)
{
    for (int d = 0; d < 3; d++) {
        slo[d] = INFINITY;
        shi[d] = -INFINITY;
    }
    *n_kept = 0;
    for (int64_t i = 0; i < seeds->n; i++) {
        for (int d = 0; d < 3; d++) {
            double x = seeds->xyz[3 * i + d];
            if (!isfinite(x))
                return vc_error_set(err, VC_EINPUT, "seed %lld has a non-finite coordinate",
                                    (long long)i);
            if (x < slo[d])
                slo[d] = x;
            if (x > shi[d])
                shi[d] = x;
        }
        *n_kept += seeds->label[i] != 0;
    }
    return 0;
}

/* The caller's options, or the defaults. */
static vc_voronoi_options options_or_default(const vc_voronoi_options *opt)
{
    vc_voronoi_options o;
    if (opt)
        o = *opt;
    else
        vc_voronoi_options_default(&o);
    return o;
}

/* vc_voronoi_build, and when keep is given, what a rebuild needs. */
static int build_mesh(const vc_seeds *seeds, const vc_voronoi_options *opt_in, vc_polymesh *out,
                      vc_voronoi_cells **keep, vc_error *err)
{
    const vc_voronoi_options opt = options_or_default(opt_in);
    memset(out, 0, sizeof *out);
    if (keep)
        *keep = NULL;
    const int64_t n = seeds->n;
    if (n <= 0)
        return vc_error_set(err, VC_EINPUT, "no seeds");
    if (check_spheres(opt.spheres, n, err))
        return err->code;
    if (n > INT32_MAX)
        return vc_error_set(err, VC_EPARAM, "%lld seeds: at most %d are supported", (long long)n,
                            INT32_MAX);

    double slo[3], shi[3];
    int64_t n_kept;
    if (seed_bounds(seeds, slo, shi, &n_kept, err))
        return err->code;
    if (n_kept == 0)
        return vc_error_set(err, VC_EINPUT, "no kept seed (every label is 0)");

    cell_job job;
    memset(&job, 0, sizeof job);
    double diag = span_diagonal(slo, shi);
    if (opt.has_box) {
        for (int d = 0; d < 3; d++) {
            if (!(opt.box[d] < opt.box[d + 3]) || !isfinite(opt.box[d]) || !isfinite(opt.box[d + 3]))
                return vc_error_set(err, VC_EPARAM, "empty or invalid box on axis %c", 'x' + d);
            job.box_lo[d] = opt.box[d];
            job.box_hi[d] = opt.box[d + 3];
        }
        for (int64_t i = 0; i < n; i++)
            for (int d = 0; d < 3; d++) {
                double x = seeds->xyz[3 * i + d];
                if (x < job.box_lo[d] || x > job.box_hi[d])
                    return vc_error_set(err, VC_EINPUT,
                                        "seed %lld (%g %g %g) lies outside the box", (long long)i,
                                        seeds->xyz[3 * i], seeds->xyz[3 * i + 1],
                                        seeds->xyz[3 * i + 2]);
            }
        double bd = span_diagonal(job.box_lo, job.box_hi);
        if (bd > diag)
            diag = bd;
    }
    /* Squared distances and cell volumes must stay normal doubles: spans
     * beyond VC_SPAN_MAX overflow them (seeds at 0 and 1e300 would all
     * look coincident), spans below VC_SPAN_MIN underflow them. */
    if (!(diag <= VC_SPAN_MAX) || (diag > 0 && diag < VC_SPAN_MIN))
        return vc_error_set(err, VC_EINPUT,
                            "the seeds%s span %g: beyond what double precision can mesh "
                            "(squared distances and cell volumes need a span from %g to %g)",
                            opt.has_box ? " and the box" : "", diag, VC_SPAN_MIN, VC_SPAN_MAX);
    if (!opt.has_box) {
        double margin = diag > 0 ? diag : 1.0;
        for (int d = 0; d < 3; d++) {
            job.box_lo[d] = slo[d] - margin;
            job.box_hi[d] = shi[d] + margin;
        }
        if (diag == 0)
            diag = 1.0;
    }
    job.dup_dist2 = (1e-12 * diag) * (1e-12 * diag);
    {
        double amax = 0;
        for (int d = 0; d < 3; d++) {
            if (fabs(slo[d]) > amax)
                amax = fabs(slo[d]);
            if (fabs(shi[d]) > amax)
                amax = fabs(shi[d]);
        }
        job.slack = 1e-13 * amax + 1e-12 * diag;
    }

    vc_seed_grid grid;
    vc_seed_kdtree tree;
    double crowd;
    int use_tree = -1;
    if (index_seeds(seeds, slo, shi, opt.neighbours, &use_tree, &grid, &tree, &crowd, err))
        return err->code;
    job.grid = &grid;
    job.seed_xyz = seeds->xyz;
    job.ctx.xyz = seeds->xyz;
    for (int d = 0; d < 3; d++) {
        job.ctx.box_lo[d] = job.box_lo[d];
        job.ctx.box_hi[d] = job.box_hi[d];
    }
    job.tree = tree.n > 0 ? &tree : NULL;

    int64_t *kept_seed = malloc((size_t)n_kept * sizeof(int64_t));
    /* Every entry is written before it is read (status for every cell,
     * the result of a cell built, other of a duplicate). */
    vc_cell_result *cells = vc_big_alloc((size_t)n_kept * sizeof(vc_cell_result));
    int *status = vc_big_alloc((size_t)n_kept * sizeof(int));
    int64_t *other = vc_big_alloc((size_t)n_kept * sizeof(int64_t));
    int64_t *build_order = malloc((size_t)n_kept * sizeof(int64_t));
    int64_t *build_pos = malloc((size_t)n_kept * sizeof(int64_t));
    vc_voronoi_cells *vc = keep ? calloc(1, sizeof *vc) : NULL;
    if (!kept_seed || !cells || !status || !other || !build_order || !build_pos ||
        (keep && !vc) || make_build_order(seeds, &grid, &tree, build_order, build_pos) != 0) {
        free(kept_seed);
        free(cells);
        free(status);
        free(other);
        free(build_order);
        free(build_pos);
        free(vc);
        vc_seed_grid_free(&grid);
        vc_seed_kdtree_free(&tree);
        return vc_error_set(err, VC_ENOMEM, "out of memory for %lld cells", (long long)n_kept);
    }
    for (int64_t i = 0, k = 0; i < n; i++)
        if (seeds->label[i] != 0)
            kept_seed[k++] = i;
    const int64_t *order_index = job.tree ? tree.index : grid.seed_index;
    const double *order_xyz = job.tree ? tree.xyz : grid.xyz;

    const int threads = vc_threads_or_default(opt.threads);
    const int progress = vc_log_enabled(opt.log, VC_LOG_INFO);
    const double t_start = wall_seconds();
    vc_cell_store store;
    memset(&store, 0, sizeof store);
    const cell_batch batch = {n_kept, build_pos, order_index, order_xyz, cells, status, other};
    const int64_t n_exact = build_batch(&job, &batch, &store, threads, opt.log, progress);
    int rc = batch_error(&batch, seeds, n_kept, err);
    vc_seed_grid_free(&grid); /* not needed by the stitching */
    vc_seed_kdtree_free(&tree);
    free(build_pos);
    free(status);
    free(other);
    if (rc == 0) {
        vc_log(opt.log, VC_LOG_DEBUG, "  cells: %s (%.1f seeds in the bin of a seed)",
               job.tree ? "neighbours from the k-d tree" : "neighbours from the grid's bins",
               crowd);
        if (progress && wall_seconds() - t_start > 1.0)
            vc_log(opt.log, VC_LOG_INFO, "voronoi: %lld cells built in %.3f s; stitching",
                   (long long)n_kept, wall_seconds() - t_start);
        vc_log(opt.log, VC_LOG_DEBUG,
               "  cells: %lld side tests past the filter; so far %lld exact (%lld in expansions)",
               (long long)n_exact, vc_power_exact_count(), vc_power_expansion_count());
        /* kept for a rebuild: the stitching must not free the cells */
        rc = vc_stitch_cells(seeds, &job.ctx, cells, kept_seed, n_kept, build_order,
                             vc ? NULL : &store, MERGE_TOL, opt.spheres, threads, opt.log, out,
                             err);
    }
    if (rc == 0 && vc) {
        vc->n = n;
        vc->n_kept = n_kept;
        memcpy(vc->slo, slo, sizeof slo);
        memcpy(vc->shi, shi, sizeof shi);
        vc->job = job;
        vc->job.grid = NULL;
        vc->job.tree = NULL;
        vc->kept_seed = kept_seed;
        vc->build_order = build_order;
        vc->cells = cells;
        vc->store = store;
        vc->last_rebuilt = n_kept;
        *keep = vc;
        return 0;
    }
    free(vc);
    vc_region_pool_free(&store.topo);
    free(cells);
    free(kept_seed);
    free(build_order);
    return rc;
}

int vc_voronoi_build(const vc_seeds *seeds, const vc_voronoi_options *opt, vc_polymesh *out,
                     vc_error *err)
{
    return build_mesh(seeds, opt, out, NULL, err);
}

int vc_voronoi_build_keep(const vc_seeds *seeds, const vc_voronoi_options *opt,
                          vc_polymesh *out, vc_voronoi_cells **cells, vc_error *err)
{
    if (!cells)
        return vc_error_set(err, VC_EPARAM, "vc_voronoi_build_keep: no place for the cells");
    return build_mesh(seeds, opt, out, cells, err);
}

/* The kept index of seed s, or -1 when it is not kept. */
static int64_t kept_of(const vc_voronoi_cells *vc, int64_t s)
{
    int64_t lo = 0, hi = vc->n_kept;
    while (lo < hi) {
        const int64_t mid = lo + (hi - lo) / 2;
        if (vc->kept_seed[mid] < s)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < vc->n_kept && vc->kept_seed[lo] == s ? lo : -1;
}

/* Marks (by kept index) the cells whose planes name a seed flagged in
 * moved (by seed index). */
static void mark_neighbours_of(const vc_voronoi_cells *vc, const unsigned char *moved,
                               unsigned char *mark, int threads)
{
#pragma omp parallel for num_threads(threads) schedule(static, 4096)
    for (int64_t m = 0; m < vc->n_kept; m++) {
        const vc_cell_result *c = &vc->cells[m];
        for (int f = 0; f < c->nf; f++)
            if (c->plane[f] >= 0 && moved[c->plane[f]]) {
                mark[vc->build_order[m]] = 1;
                break;
            }
    }
}

int vc_voronoi_rebuild(vc_voronoi_cells *vc, const vc_seeds *seeds, const int64_t *moved,
                       int64_t n_moved, const vc_voronoi_options *opt_in, vc_polymesh *out,
                       vc_error *err)
{
    const vc_voronoi_options opt = options_or_default(opt_in);
    memset(out, 0, sizeof *out);
    if (vc && vc->broken)
        return vc_error_set(err, VC_EPARAM, "vc_voronoi_rebuild: an earlier rebuild of these "
                            "cells failed");
    if (!vc || seeds->n != vc->n || n_moved < 0 || (n_moved > 0 && !moved))
        return vc_error_set(err, VC_EPARAM, "vc_voronoi_rebuild: not the seeds of the kept cells "
                            "(%lld seeds, %lld moved)", (long long)seeds->n, (long long)n_moved);
    const int64_t n = vc->n, n_kept = vc->n_kept;
    for (int64_t q = 0; q < n_moved; q++)
        if (moved[q] < 0 || moved[q] >= n)
            return vc_error_set(err, VC_EPARAM, "vc_voronoi_rebuild: moved seed %lld of %lld "
                                "seeds", (long long)moved[q], (long long)n);
    if (check_spheres(opt.spheres, n, err))
        return err->code;
    double slo[3], shi[3];
    int64_t kept;
    if (seed_bounds(seeds, slo, shi, &kept, err))
        return err->code;
    {
        int same = kept == n_kept;
        for (int64_t k = 0; k < n_kept && same; k++)
            same = seeds->label[vc->kept_seed[k]] != 0;
        if (!same)
            return vc_error_set(err, VC_EPARAM, "vc_voronoi_rebuild: the seeds kept (label not "
                                "0) changed since the cells were built");
    }
    /* From here the kept cells are of the places before these moves: a
     * failure leaves them of no use (the next call would not name these
     * moves), until the cells are updated below. */
    vc->broken = 1;
    /* Other bounds (a seed at the edge of the set moved) give another
     * clipping box, other bins and another build order: every cell again. */
    if (memcmp(slo, vc->slo, sizeof slo) != 0 || memcmp(shi, vc->shi, sizeof shi) != 0) {
        vc_voronoi_cells *fresh;
        const int rc = build_mesh(seeds, &opt, out, &fresh, err);
        if (rc)
            return rc;
        /* the new cells in the old handle */
        vc_voronoi_cells old = *vc;
        *vc = *fresh;
        *fresh = old;
        vc_voronoi_cells_free(fresh);
        return 0;
    }
    const int threads = vc_threads_or_default(opt.threads);
    const double t0 = wall_seconds();

    vc_seed_grid grid;
    vc_seed_kdtree tree;
    double crowd;
    int use_tree = -1; /* decided as a fresh build would */
    if (index_seeds(seeds, slo, shi, opt.neighbours, &use_tree, &grid, &tree, &crowd, err))
        return err->code;
    cell_job job = vc->job;
    job.grid = &grid;
    job.tree = tree.n > 0 ? &tree : NULL;
    job.seed_xyz = seeds->xyz;
    job.ctx.xyz = seeds->xyz;

    int rc = 0;
    unsigned char *is_moved = calloc((size_t)n, 1);
    unsigned char *mark = calloc((size_t)n_kept, 1);
    /* room for the moved seeds' cells (step 1) or every kept one (step 2) */
    const size_t room = (size_t)(n_kept > n_moved ? n_kept : n_moved) + 1;
    int64_t *pos = malloc(sizeof(int64_t) * room);
    int *status = malloc(sizeof(int) * room);
    int64_t *other = malloc(sizeof(int64_t) * room);
    vc_cell_result *res = malloc(sizeof(vc_cell_result) * room);
    vc_cell_result *moved_cell = malloc(sizeof(vc_cell_result) * ((size_t)n_moved + 1));
    int64_t *moved_at = malloc(sizeof(int64_t) * ((size_t)n_kept + 1));
    int64_t *order = malloc(sizeof(int64_t) * ((size_t)n_kept + 1));
    int64_t *order_pos = malloc(sizeof(int64_t) * ((size_t)n_kept + 1));
    int64_t *was_at = malloc(sizeof(int64_t) * ((size_t)n_kept + 1));
    vc_cell_result *cells = vc_big_alloc(sizeof(vc_cell_result) * (size_t)n_kept);
    if (!is_moved || !mark || !pos || !status || !other || !res || !moved_cell || !moved_at ||
        !order || !order_pos || !was_at || !cells || make_build_order(seeds, &grid, &tree, order, order_pos) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory rebuilding %lld cells", (long long)n_kept);
        goto done;
    }
    for (int64_t q = 0; q < n_moved; q++)
        is_moved[moved[q]] = 1;
    /* The cells that change: the moved seeds' own, those they bounded
     * where they were, and those they bound where they are (Voronoi
     * neighbourhood is symmetric, and the engine decides it exactly and
     * alike in both cells). */
    mark_neighbours_of(vc, is_moved, mark, threads);
    int64_t n_first = 0;
    for (int64_t i = 0; i < n; i++)
        if (is_moved[i])
            pos[n_first++] = i; /* ascending seed index */
    /* 1. the moved seeds' cells where they are now (kept or not: a seed
     * that is not kept bounds cells too), for their neighbours; a kept
     * one's is its new cell (mark 2), a cell that is not kept stays in the
     * store unused */
    const cell_batch first = {n_first, pos, NULL, seeds->xyz, moved_cell, status, other};
    build_batch(&job, &first, &vc->store, threads, opt.log, 0);
    if ((rc = batch_error(&first, seeds, n_kept, err)) != 0)
        goto done;
    for (int64_t q = 0; q < n_first; q++) {
        const int64_t k = kept_of(vc, pos[q]);
        if (k >= 0)
            moved_at[k] = q;
        const vc_cell_result *c = &moved_cell[q];
        for (int f = 0; f < c->nf; f++) {
            const int64_t kn = c->plane[f] >= 0 ? kept_of(vc, c->plane[f]) : -1;
            if (kn >= 0 && !mark[kn])
                mark[kn] = 1;
        }
        if (k >= 0)
            mark[k] = 2;
    }
    /* 2. the cells in the order a fresh build takes (the stitching numbers
     * the vertices in it): the unchanged ones moved there, the moved seeds'
     * from step 1, their neighbours built again into the kept store (the
     * old blocks stay there unused until the cells are freed) */
    for (int64_t m = 0; m < n_kept; m++)
        was_at[vc->build_order[m]] = m;
    int64_t n_again = 0, n_moved_kept = 0;
    for (int64_t m = 0; m < n_kept; m++) {
        const int64_t k = order[m];
        n_moved_kept += mark[k] == 2;
        if (mark[k] == 1)
            pos[n_again++] = m;
        else
            cells[m] = mark[k] == 2 ? moved_cell[moved_at[k]] : vc->cells[was_at[k]];
    }
    const int64_t *order_index = job.tree ? tree.index : grid.seed_index;
    const double *order_xyz = job.tree ? tree.xyz : grid.xyz;
    for (int64_t q = 0; q < n_again; q++)
        was_at[q] = order_pos[pos[q]]; /* the seed's place in the neighbour source */
    const cell_batch second = {n_again, was_at, order_index, order_xyz, res, status, other};
    build_batch(&job, &second, &vc->store, threads, opt.log, 0);
    if ((rc = batch_error(&second, seeds, n_kept, err)) != 0)
        goto done;
    for (int64_t q = 0; q < n_again; q++)
        cells[pos[q]] = res[q];
    free(vc->cells);
    vc->cells = cells;
    cells = NULL;
    free(vc->build_order);
    vc->build_order = order;
    order = NULL;
    vc->last_rebuilt = n_moved_kept + n_again;
    vc->broken = 0;
    vc_log(opt.log, VC_LOG_DEBUG, "  voronoi: %lld of %lld cells built again for %lld moved "
           "seeds, %.3f s; stitching", (long long)vc->last_rebuilt, (long long)n_kept, (long long)n_moved,
           wall_seconds() - t0);
    vc_seed_grid_free(&grid); /* zeroed: freed again below, harmlessly */
    vc_seed_kdtree_free(&tree);
    rc = vc_stitch_cells(seeds, &job.ctx, vc->cells, vc->kept_seed, n_kept, vc->build_order, NULL,
                         MERGE_TOL, opt.spheres, threads, opt.log, out, err);
done:
    free(is_moved);
    free(mark);
    free(pos);
    free(status);
    free(other);
    free(res);
    free(order);
    free(order_pos);
    free(was_at);
    free(cells);
    free(moved_cell);
    free(moved_at);
    vc_seed_grid_free(&grid);
    vc_seed_kdtree_free(&tree);
    return rc;
}
