/* Short-edge protection of the interior seeds (see
 * include/vorocrust/interior.h and docs/solver-grade-cells.md).
 *
 * A Voronoi edge is short when five seeds lie nearly on one empty sphere.
 * The surface seeds are fixed by the balls; the octree's seeds are exact
 * lattice points whose ties the engine resolves into one vertex; the
 * near-ties are where the two meet. There each interior seed whose cell
 * has a short edge at one of its vertices is moved within a small ball
 * around its original place (a picking region, as in Li and Teng's and
 * Ghosh's protection): the places that make a given five seeds nearly
 * co-spherical are a thin shell, so a few random points find one clear of
 * all of them, unless the near-tie does not involve the seed at all (two
 * near-coincident surface seeds), which no move mends. */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "ball_tree.h"
#include "nearest_seed.h"
#include "util/threads.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/random.h"
#include "voronoi/convex_cell.h"
#include "voronoi/seed_kdtree.h"
#include "util/clock.h"

/* Neighbours read first, and at most (a cell not closed by K_MAX of them
 * is measured as it is); neighbours of a seed's original place read once
 * for all its candidate places. */
enum { K_FIRST = 64, K_MAX = 512, K_AROUND = 64 };
/* A seed whose nearest this many are lattice seeds (octree leaf centres,
 * unmoved) is taken as protected without a measure: a lattice point's
 * cell is bounded by its 26 lattice neighbours, and every tie among them
 * is exact. */
enum { LATTICE_NEIGHBOURS = 32 };
/* Random points tried per seed and round; rounds of moves. */
enum { N_CANDIDATES = 8, MAX_ROUNDS = 12 };
/* Edges no longer than this share of their vertices' distance to their
 * seeds join vertices that are one for the engine (co-spherical seeds,
 * exactly or to rounding: lattice corners, ball centres), and seeds whose
 * power gap at a vertex is below it are co-spherical there. */
#define TIE 1e-9
/* The picking region's radius, a share of the distance from the seed's
 * original place to its nearest neighbour. */
#define PICK_RADIUS 0.25

typedef struct workspace {
    vc_convex_cell cell;
    vc_power_ctx ctx;
    double local[3 * (K_MAX + 1)]; /* the point, then its neighbours (absolute) */
    vc_kd_hit hit[K_MAX];
    vc_kd_hit around[K_AROUND];    /* the neighbours of the original place */
    int n_around;
    int64_t nb[K_MAX];             /* seeds whose planes bound the cell */
    int64_t best_nb[K_MAX];        /* those of the best candidate so far */
    int n_nb;
    unsigned char used[K_MAX + 1];
    /* the thread's last k-nearest query: the next one, nearby in seed
     * order, searches within its k-th distance plus the step first (the
     * same answers, a quarter of the protection's time was the tree) */
    vc_kd_hint hint;
    /* the reach balls of the cell's vertices (measure_reaches): 5 doubles
     * each, room for ball_cap */
    double *ball;
    int ball_cap;
} workspace;

/* Which seeds a measure can still need (measure_at's range queries): a
 * seed y cuts the cell only inside the clearance ball of one of its
 * vertices w (|y - w| < |w|, relative to the point), and edge_measure
 * reads it only where |y - w| < |w| + 2 len, len at most cap times the
 * cell's radius. |y - p|^2 - (|p| + d)^2 is concave in p, so a seed
 * outside every ball B(w, |w| + d) of the cell's vertices is outside
 * B(p, |p| + d) for every point p of the cell, the vertices of any smaller
 * cell the further cuts leave included: the balls of the cell as it is
 * when the query is made hold every seed the measure needs. */
typedef struct measure_reach {
    const double *ball; /* x, y, z, radius, |w|; by decreasing |w| */
    int n;
    const double *x;    /* the point (absolute) */
    double lo[3], hi[3]; /* the balls' bounding box, relative */
} measure_reach;

static int measure_reaches(void *ctx, const double lo[3], const double hi[3])
{
    const measure_reach *c = ctx;
    double l[3], h[3], d2 = 0;
    for (int d = 0; d < 3; d++) {
        l[d] = lo[d] - c->x[d];
        h[d] = hi[d] - c->x[d];
        if (l[d] > c->hi[d] || h[d] < c->lo[d])
            return 0;
        const double e = l[d] > 0 ? l[d] : (h[d] < 0 ? -h[d] : 0);
        d2 += e * e;
    }
    for (int v = 0; v < c->n; v++) {
        const double *b = c->ball + 5 * v;
        /* a ball about a vertex at |w| of radius |w| + d reaches 2 |w| + d
         * from the point; the rest reach less */
        if ((b[4] + b[3]) * (b[4] + b[3]) < d2)
            break;
        double e2 = 0;
        for (int d = 0; d < 3; d++) {
            const double e = b[d] < l[d] ? l[d] - b[d] : (b[d] > h[d] ? b[d] - h[d] : 0);
            e2 += e * e;
        }
        if (e2 <= b[3] * b[3])
            return 1;
    }
    return 0;
}

/* The reach balls of the cell's vertices into ws->ball (grown by cap times
 * the cell's radius, twice, and by the vertices' error and a relative
 * 1e-9), by decreasing distance from the point; -1 when out of memory. */
static int reach_balls(workspace *ws, double cap, measure_reach *mr, const double *x)
{
    const vc_convex_cell *cell = &ws->cell;
    if (cell->nt > ws->ball_cap) {
        double *q = realloc(ws->ball, sizeof(double) * 5 * (size_t)(cell->nt + 64));
        if (!q)
            return -1;
        ws->ball = q;
        ws->ball_cap = cell->nt + 64;
    }
    double ev = 0;
    for (int t = 0; t < cell->nt; t++)
        ev = fmax(ev, cell->ev[t]);
    const double grow = 2 * cap * sqrt(cell->rmax2) + 2 * ev;
    for (int d = 0; d < 3; d++) {
        mr->lo[d] = INFINITY;
        mr->hi[d] = -INFINITY;
    }
    int n = 0;
    for (int t = 0; t < cell->nt; t++) {
        const double w[3] = {cell->px[t], cell->py[t], cell->pz[t]};
        const double wr = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        const double rad = (wr + grow) * (1 + 1e-9);
        int j = n++; /* insertion by decreasing |w| */
        while (j > 0 && ws->ball[5 * (j - 1) + 4] < wr) {
            memcpy(ws->ball + 5 * j, ws->ball + 5 * (j - 1), 5 * sizeof(double));
            j--;
        }
        double *b = ws->ball + 5 * j;
        b[0] = w[0];
        b[1] = w[1];
        b[2] = w[2];
        b[3] = rad;
        b[4] = wr;
        for (int d = 0; d < 3; d++) {
            mr->lo[d] = fmin(mr->lo[d], w[d] - rad);
            mr->hi[d] = fmax(mr->hi[d], w[d] + rad);
        }
    }
    mr->ball = ws->ball;
    mr->n = n;
    mr->x = x;
    return 0;
}

/* The calling thread's workspace. */
static inline workspace *own_workspace(workspace *ws)
{
#ifdef _OPENMP
    return &ws[omp_get_thread_num()];
#else
    return &ws[0];
#endif
}

/* Cuts the cell by the neighbours ws->hit[from, m) (their points in
 * ws->local already); returns as cut_cell. */
static int cut_more(workspace *ws, const double x[3], int from, int m, int all_seeds)
{
    vc_convex_cell *cell = &ws->cell;
    for (int i = from; i < m; i++) {
        if (!(ws->hit[i].d2 <= 4.0 * cell->rmax2 * (1.0 + 1e-9)))
            break; /* sorted: no farther seed can cut */
        if (ws->hit[i].d2 == 0)
            return 2;
        const double *y = ws->local + 3 * (i + 1);
        const double p[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
        const int r = vc_convex_cell_cut(cell, p, i + 1);
        if (r == VC_CELL_NOMEM)
            return -1;
        if (r < 0)
            return 2;
    }
    return all_seeds || ws->hit[m - 1].d2 > 4.0 * cell->rmax2 * (1.0 + 1e-9);
}

/* Cuts the cell of x by the m neighbours in ws->hit (sorted by distance
 * from x). Returns 1 when no seed beyond them can cut it (all_seeds: they
 * are all there are), 0 when one might, 2 when x makes no proper cell (on
 * a seed, or a defect), -1 when out of memory. */
static int cut_cell(workspace *ws, const double *xyz, const double x[3], int m, int all_seeds)
{
    vc_convex_cell *cell = &ws->cell;
    const double reach = sqrt(ws->hit[m - 1].d2);
    /* walls far enough that a cell bounded by its neighbours never
     * meets them */
    const double wall = 4 * reach + 1e-300;
    for (int d = 0; d < 3; d++) {
        ws->local[d] = x[d];
        ws->ctx.box_lo[d] = x[d] - wall;
        ws->ctx.box_hi[d] = x[d] + wall;
    }
    for (int i = 0; i < m; i++)
        memcpy(ws->local + 3 * (i + 1), xyz + 3 * ws->hit[i].seed, 3 * sizeof(double));
    ws->ctx.xyz = ws->local;
    cell->ctx = &ws->ctx;
    cell->seed = 0;
    const double lo[3] = {-wall, -wall, -wall}, hi[3] = {wall, wall, wall};
    const int64_t walls[6] = {VC_WALL_XMIN - 0, VC_WALL_XMIN - 1, VC_WALL_XMIN - 2,
                              VC_WALL_XMIN - 3, VC_WALL_XMIN - 4, VC_WALL_XMIN - 5};
    if (vc_convex_cell_reset_box(cell, lo, hi, walls) != 0)
        return -1;
    return cut_more(ws, x, 0, m, all_seeds);
}

/* Whether the cell just cut has a vertex on a wall of its box. */
static int on_walls(const vc_convex_cell *cell)
{
    for (int t = 0; t < cell->nt; t++) {
        const int *pl = cell->tri + 3 * t;
        if (cell->plane_id[pl[0]] < 0 || cell->plane_id[pl[1]] < 0 || cell->plane_id[pl[2]] < 0)
            return 1;
    }
    return 0;
}

/* The shortest Voronoi edge at the vertices of the cell just cut (m
 * neighbours), over the cell's radius: the cell's own edges, and at each
 * vertex the edge that leaves the cell (equidistant to the vertex's
 * three other seeds a, b, c), which ends where a fifth seed y comes as
 * near: along it y's power less a's changes at the rate 2 u.(a - y).
 * Together they are every edge whose length depends on where the seed
 * is; at most cap (longer edges do not matter). Fills ws->nb. Stops at
 * the first edge below beat (its value is then an upper bound). */
static double edge_measure(workspace *ws, int m, double beat, double cap)
{
    vc_convex_cell *cell = &ws->cell;
    ws->n_nb = 0;
    memset(ws->used, 0, sizeof ws->used);
    double rcell2 = 0;
    for (int t = 0; t < cell->nt; t++) {
        const int *pl = cell->tri + 3 * t;
        const int64_t a = cell->plane_id[pl[0]], b = cell->plane_id[pl[1]],
                      c = cell->plane_id[pl[2]];
        if (a > 0)
            ws->used[a] = 1;
        if (b > 0)
            ws->used[b] = 1;
        if (c > 0)
            ws->used[c] = 1;
        if (a > 0 && b > 0 && c > 0 && cell->r2[t] > rcell2)
            rcell2 = cell->r2[t];
    }
    for (int i = 1; i <= m; i++)
        if (ws->used[i])
            ws->nb[ws->n_nb++] = ws->hit[i - 1].seed;
    if (!(rcell2 > 0))
        return INFINITY;
    const double rcell = sqrt(rcell2);
    double shortest = cap * rcell;
    /* the cell's own edges: consecutive vertices of its faces */
    if (vc_convex_cell_faces(cell) != 0)
        return 0;
    for (int f = 0; f < cell->nf; f++) {
        const int f0 = cell->face_start[f], f1 = cell->face_start[f + 1];
        if (cell->face_plane[f] < 0)
            continue;
        for (int k = f0; k < f1; k++) {
            const int u = cell->fv[k], v = cell->fv[k + 1 < f1 ? k + 1 : f0];
            const int *pu = cell->tri + 3 * u, *pv = cell->tri + 3 * v;
            if (cell->plane_id[pu[0]] < 0 || cell->plane_id[pu[1]] < 0 ||
                cell->plane_id[pu[2]] < 0 || cell->plane_id[pv[0]] < 0 ||
                cell->plane_id[pv[1]] < 0 || cell->plane_id[pv[2]] < 0)
                continue;
            const double dx = cell->px[u] - cell->px[v], dy = cell->py[u] - cell->py[v],
                         dz = cell->pz[u] - cell->pz[v];
            const double len = sqrt(dx * dx + dy * dy + dz * dz);
            if (len > TIE * sqrt(cell->r2[u]) && len < shortest) {
                shortest = len;
                if (shortest < beat * rcell)
                    return shortest / rcell;
            }
        }
    }
    /* the edges leaving the cell (coordinates relative to the point) */
    const double *x = ws->local;
    for (int t = 0; t < cell->nt; t++) {
        const int *pl = cell->tri + 3 * t;
        const int64_t a = cell->plane_id[pl[0]], b = cell->plane_id[pl[1]],
                      c = cell->plane_id[pl[2]];
        if (a < 0 || b < 0 || c < 0)
            continue;
        double ya[3], yb[3], yc[3];
        for (int d = 0; d < 3; d++) {
            ya[d] = ws->local[3 * a + d] - x[d];
            yb[d] = ws->local[3 * b + d] - x[d];
            yc[d] = ws->local[3 * c + d] - x[d];
        }
        const double e1[3] = {yb[0] - ya[0], yb[1] - ya[1], yb[2] - ya[2]};
        const double e2[3] = {yc[0] - ya[0], yc[1] - ya[1], yc[2] - ya[2]};
        double u[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        const double lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (!(lu > 0))
            continue;
        /* away from the point: the point's power grows faster than a's */
        const double sgn = u[0] * ya[0] + u[1] * ya[1] + u[2] * ya[2] > 0 ? 1 / lu : -1 / lu;
        for (int d = 0; d < 3; d++)
            u[d] *= sgn;
        const double w[3] = {cell->px[t], cell->py[t], cell->pz[t]};
        const double r2 = cell->r2[t], r = sqrt(r2);
        const double ua = u[0] * ya[0] + u[1] * ya[1] + u[2] * ya[2];
        double len = shortest;
        for (int i = 1; i <= m; i++) {
            /* y ends the edge before len only if |y - w| < r + 2 len (its
             * power gap is below 2 len times its rate, at most |y - w| + r),
             * so |y| < 2 r + 2 len: the neighbours are sorted by |y| */
            const double reach = 2 * r + 2 * len;
            if (ws->hit[i - 1].d2 >= reach * reach)
                break;
            if (i == a || i == b || i == c)
                continue;
            const double *yy = ws->local + 3 * i;
            const double y[3] = {yy[0] - x[0], yy[1] - x[1], yy[2] - x[2]};
            const double rate = u[0] * y[0] + u[1] * y[1] + u[2] * y[2] - ua;
            if (!(rate > 0))
                continue; /* y falls behind along the edge */
            const double e0 = y[0] - w[0], e1y = y[1] - w[1], e2y = y[2] - w[2];
            const double fy = e0 * e0 + e1y * e1y + e2y * e2y - r2;
            if (fy <= TIE * r2)
                continue; /* co-spherical: the same vertex */
            const double ty = fy / (2 * rate);
            if (ty < len)
                len = ty;
        }
        if (len < shortest) {
            shortest = len;
            if (shortest < beat * rcell)
                return shortest / rcell;
        }
    }
    /* cap itself when nothing is shorter (cap r / r need not be cap) */
    return shortest < cap * rcell ? shortest / rcell : cap;
}

/* The measure of a point x for seed `self` (edge_measure), its cell's
 * neighbours into ws->nb: from ws->around when they are enough (use_around),
 * else from the tree. Returns 0, or -1 when out of memory. */
static int measure_at(workspace *ws, const vc_seed_kdtree *tree, const double *xyz,
                      const double x[3], int64_t self, int use_around, int have_first,
                      double beat, double cap, double *out)
{
    *out = INFINITY;
    ws->n_nb = 0;
    if (use_around && ws->n_around > 0) {
        const int m = ws->n_around;
        for (int i = 0; i < m; i++) {
            const double *y = xyz + 3 * ws->around[i].seed;
            const double dx = y[0] - x[0], dy = y[1] - x[1], dz = y[2] - x[2];
            vc_kd_hit h = {dx * dx + dy * dy + dz * dz, ws->around[i].seed};
            int j = i; /* insertion sort by (d2, seed) */
            while (j > 0 && (ws->hit[j - 1].d2 > h.d2 ||
                             (ws->hit[j - 1].d2 == h.d2 && ws->hit[j - 1].seed > h.seed))) {
                ws->hit[j] = ws->hit[j - 1];
                j--;
            }
            ws->hit[j] = h;
        }
        const int r = cut_cell(ws, xyz, x, m, 0);
        if (r < 0)
            return -1;
        if (r == 2) {
            *out = 0;
            return 0;
        }
        if (r == 1) {
            *out = edge_measure(ws, m, beat, cap);
            return 0;
        }
    }
    /* have_first: ws->hit holds the first K_FIRST already */
    int m = have_first ? have_first : vc_seed_kdtree_knn_hinted(tree, &ws->hint, x, K_FIRST, self, ws->hit);
    if (m == 0)
        return 0;
    int r = cut_cell(ws, xyz, x, m, m < K_FIRST);
    for (int k = K_FIRST;; k *= 2) {
        if (r < 0)
            return -1;
        if (r == 2) {
            *out = 0;
            return 0;
        }
        if (r == 1 || 2 * k > K_MAX) {
            *out = edge_measure(ws, m, beat, cap);
            return 0;
        }
        /* twice the neighbours. The first k of the 2 k nearest are these
         * (the order is total): only the next k are asked for and cut,
         * unless the box the cell was cut in, sized for the first k, still
         * bounds it (a cell on the domain's edge: cut again in a larger
         * one). Asking for all 2 k and cutting them from the box each time
         * cost a third of the protection's time (bunny.off: 120,582 of its
         * 282,986 cuts from a box needed 128 to 512 neighbours; 6.06 s,
         * now 4.02 s). */
        if (!on_walls(&ws->cell)) {
            /* no seed beyond 2 rmax cuts the cell, and edge_measure reads
             * none beyond 2 rmax + 2 cap rmax: the next k within that (all
             * of them when fewer, and then the cell is done) */
            const double reach = 2 * sqrt(ws->cell.rmax2) * (1 + cap) * (1 + 1e-9);
            int truncated;
            measure_reach mr;
            if (reach_balls(ws, cap, &mr, x) != 0)
                return -1;
            const int add = vc_seed_kdtree_within(tree, x, isfinite(reach) ? reach * reach : INFINITY,
                                                  ws->hit[m - 1], self, measure_reaches, &mr,
                                                  ws->hit + m, k, &truncated);
            for (int i = m; i < m + add; i++)
                memcpy(ws->local + 3 * (i + 1), xyz + 3 * ws->hit[i].seed, 3 * sizeof(double));
            const int from = m;
            m += add;
            r = add == 0 ? 1 : cut_more(ws, x, from, m, add < k);
        } else {
            m = vc_seed_kdtree_knn(tree, x, 2 * k, self, ws->hit);
            r = cut_cell(ws, xyz, x, m, m < 2 * k);
        }
    }
}

/* A seed's move in one round: where to, and every seed whose cell it
 * touched at either place (sorted). */
typedef struct proposal {
    double to[3];
    double gap_before, gap_after;
    int n_old, n;  /* touch[0 .. n_old): the cell's neighbours where it is */
    int64_t *touch;
} proposal;

double vc_protect_ball_gap(double min_edge)
{
    return 4 * min_edge;
}

void vc_protect_options_default(vc_protect_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->min_edge = 0.01;
    opt->random_seed = 1;
    opt->lattice_begin = -1;
}

int vc_interior_protect(const vc_balls *balls, vc_seeds *seeds, int64_t n_surface,
                        const vc_protect_options *opt, vc_protect_stats *stats, vc_error *err)
{
    const double t0 = vc_clock_seconds();
    vc_protect_stats st;
    memset(&st, 0, sizeof st);
    st.min_edge_before = st.min_edge_after = INFINITY;
    if (stats)
        *stats = st;
    if (n_surface < 0 || n_surface > seeds->n || !(opt->min_edge >= 0 && opt->min_edge < 0.25) ||
        opt->n_poles < 0 || opt->n_poles > seeds->n - n_surface || (opt->n_poles && !opt->pole_ball))
        return vc_error_set(err, VC_EPARAM, "seed protection: bad shortest edge %g, surface seed "
                            "count %lld or pole seeds", opt->min_edge, (long long)n_surface);
    const int64_t n = seeds->n, n_int = n - n_surface;
    if (n_int == 0 || opt->min_edge == 0)
        return 0;
    const double gap = opt->min_edge; /* the target of the measure */
    const int threads = vc_threads_or_default(opt->threads);

    vc_ball_tree balls_tree;
    vc_seed_kdtree surface_tree, tree;
    memset(&surface_tree, 0, sizeof surface_tree);
    memset(&tree, 0, sizeof tree);
    int have_balls = 0, rc = 0;
    double *origin = malloc(sizeof(double) * 3 * (size_t)n_int);
    double *pick = malloc(sizeof(double) * (size_t)n_int);
    proposal *prop = calloc((size_t)n_int, sizeof *prop);
    unsigned char *active = malloc((size_t)n_int), *next = malloc((size_t)n_int);
    unsigned char *dirty = calloc((size_t)n_int, 1);
    unsigned char *touched = malloc((size_t)n);
    int *moved_round = malloc(sizeof(int) * (size_t)n);
    double *gap_now = malloc(sizeof(double) * (size_t)n_int);
    int64_t *list = malloc(sizeof(int64_t) * (size_t)n_int);
    workspace *ws = calloc((size_t)threads, sizeof *ws);
    const vc_seeds surface = {n_surface, seeds->xyz, seeds->label};
    if (!origin || !pick || !prop || !active || !next || !dirty || !touched || !moved_round || !gap_now ||
        !list || !ws || vc_ball_tree_build(&balls_tree, balls) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory protecting the interior seeds");
        goto done;
    }
    have_balls = 1;
    if (n_surface > 0 && vc_nearest_seed_index_build(&surface_tree, &surface) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory protecting the interior seeds");
        goto done;
    }
    for (int t = 0; t < threads; t++)
        vc_convex_cell_init(&ws[t].cell);
    memcpy(origin, seeds->xyz + 3 * n_surface, sizeof(double) * 3 * (size_t)n_int);
    memset(active, 1, (size_t)n_int);
    for (int64_t i = 0; i < n; i++)
        moved_round[i] = -1;
    const double margin = sqrt(1 + vc_protect_ball_gap(gap));

    for (int round = 0; round <= MAX_ROUNDS && !rc; round++) {
        if (round == 0) {
            if (vc_seed_kdtree_build(&tree, seeds->xyz, n) != 0) {
                rc = vc_error_set(err, VC_ENOMEM, "out of memory protecting the interior seeds");
                break;
            }
        } else {
            vc_seed_kdtree_refit(&tree, seeds->xyz); /* moves are small */
        }
        int64_t n_list = 0;
        for (int64_t i = 0; i < n_int; i++)
            if (active[i])
                list[n_list++] = i;
        if (n_list == 0)
            break;
        const int propose = round < MAX_ROUNDS;
        int failed = 0;
        int64_t measures = 0;
        /* 1. Measure every listed seed where it is; keep the neighbours of
         * those below the target. */
#pragma omp parallel for num_threads(threads) schedule(dynamic, 16) reduction(| : failed) \
    reduction(+ : measures)
        for (int64_t l = 0; l < n_list; l++) {
            workspace *w = own_workspace(ws);
            const int64_t i = list[l], s = n_surface + i;
            proposal *pr = &prop[i];
            free(pr->touch);
            pr->touch = NULL;
            pr->n = pr->n_old = 0;
            int have_first = 0;
            if (round == 0) {
                /* the picking region: a share of the distance to the
                 * nearest seed from the original place */
                if ((have_first = vc_seed_kdtree_knn_hinted(&tree, &w->hint, origin + 3 * i, K_FIRST, s,
                                                            w->hit)) < 1) {
                    pick[i] = 0;
                    gap_now[i] = INFINITY;
                    continue;
                }
                pick[i] = PICK_RADIUS * sqrt(w->hit[0].d2);
                /* among lattice seeds only, every tie is exact and every
                 * edge long: nothing to measure */
                int lattice = opt->lattice_begin >= 0 && s >= opt->lattice_begin;
                for (int k = 0; k < LATTICE_NEIGHBOURS && k < have_first && lattice; k++)
                    lattice = w->hit[k].seed >= opt->lattice_begin;
                if (lattice) {
                    gap_now[i] = INFINITY;
                    continue;
                }
            }
            double g;
            measures++;
            if (measure_at(w, &tree, seeds->xyz, seeds->xyz + 3 * s, s, 0, have_first, -INFINITY, gap, &g) != 0) {
                failed = 1;
                continue;
            }
            gap_now[i] = g;
            if (g >= gap || !propose || pick[i] <= 0)
                continue;
            pr->touch = malloc(sizeof(int64_t) * (size_t)(w->n_nb > 0 ? w->n_nb : 1));
            if (!pr->touch) {
                failed = 1;
                continue;
            }
            memcpy(pr->touch, w->nb, sizeof(int64_t) * (size_t)w->n_nb);
            pr->n_old = w->n_nb;
            pr->gap_before = g;
        }
        st.n_measures += measures;
        measures = 0;
        if (failed) {
            rc = vc_error_set(err, VC_ENOMEM, "out of memory protecting the interior seeds");
            break;
        }
        int64_t below = 0;
        for (int64_t l = 0; l < n_list; l++) {
            const int64_t i = list[l];
            below += gap_now[i] < gap;
            if (round == 0) {
                st.n_checked++;
                if (gap_now[i] < st.min_edge_before)
                    st.min_edge_before = gap_now[i];
            }
        }
        if (round == 0)
            st.n_short_before = below;
        st.rounds = round;
        if (!propose)
            break;
        /* 2. Pick, in seed order, the seeds below the target none of whose
         * neighbours is picked: their moves hardly interfere. */
        memset(touched, 0, (size_t)n);
        memset(next, 0, (size_t)n_int);
        int64_t n_pick = 0;
        for (int64_t l = 0; l < n_list; l++) {
            const int64_t i = list[l], s = n_surface + i;
            proposal *pr = &prop[i];
            if (!pr->touch)
                continue;
            if (touched[s]) {
                next[i] = 1; /* a neighbour goes first */
                free(pr->touch);
                pr->touch = NULL;
                continue;
            }
            touched[s] = 1;
            for (int k = 0; k < pr->n_old; k++)
                touched[pr->touch[k]] = 1;
            list[n_pick++] = i;
        }
        /* 3. Search their picking regions. */
#pragma omp parallel for num_threads(threads) schedule(dynamic, 4) reduction(| : failed) \
    reduction(+ : measures)
        for (int64_t l = 0; l < n_pick; l++) {
            workspace *w = own_workspace(ws);
            const int64_t i = list[l], s = n_surface + i;
            proposal *pr = &prop[i];
            w->n_around = vc_seed_kdtree_knn(&tree, origin + 3 * i, K_AROUND, s, w->around);
            vc_rng rng;
            vc_rng_init(&rng, opt->random_seed ^ 0x5EED5AFEull,
                        (uint64_t)(s * (MAX_ROUNDS + 1) + round));
            double best = pr->gap_before, best_x[3] = {0, 0, 0};
            int n_best = -1;
            for (int c = 0; c < N_CANDIDATES && best < gap; c++) {
                double u[3], q = 2;
                while (q > 1) { /* uniform in the unit ball */
                    for (int d = 0; d < 3; d++)
                        u[d] = 2 * vc_rng_uniform(&rng) - 1;
                    q = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
                }
                double x[3];
                for (int d = 0; d < 3; d++)
                    x[d] = origin[3 * i + d] + pick[i] * u[d];
                int64_t own_ball = -1;
                if (i < opt->n_poles) {
                    /* a pole: onto its sphere */
                    own_ball = opt->pole_ball[i];
                    const double *bc = balls->center + 3 * own_ball;
                    const double br = balls->radius[own_ball];
                    const double e[3] = {x[0] - bc[0], x[1] - bc[1], x[2] - bc[2]};
                    const double le = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                    if (!(le > 0))
                        continue;
                    for (int d = 0; d < 3; d++)
                        x[d] = bc[d] + br * e[d] / le;
                }
                /* away from every ball by the gap (the ball centres are
                 * vertices of the surface seeds' diagram, their balls the
                 * empty spheres), and inside the same region: the nearest
                 * surface seed carries the seed's label */
                if (vc_ball_tree_covers_scaled_except(&balls_tree, x, margin, own_ball))
                    continue;
                double dn;
                const int64_t ns = n_surface > 0 ? vc_nearest_seed(&surface_tree, x, &dn) : -1;
                if (ns < 0 || seeds->label[ns] != seeds->label[s])
                    continue;
                double gc;
                measures++;
                if (measure_at(w, &tree, seeds->xyz, x, s, 1, 0, best, gap, &gc) != 0) {
                    failed = 1;
                    break;
                }
                if (gc > best && w->n_nb <= K_MAX) {
                    best = gc;
                    memcpy(best_x, x, sizeof x);
                    n_best = w->n_nb;
                    memcpy(w->best_nb, w->nb, sizeof(int64_t) * (size_t)n_best);
                }
            }
            int64_t *grown = n_best < 0 ? NULL
                                        : realloc(pr->touch, sizeof(int64_t) *
                                                                 (size_t)(pr->n_old + n_best + 1));
            if (!grown) {
                failed |= n_best >= 0; /* out of memory */
                free(pr->touch);
                pr->touch = NULL;
                continue;
            }
            pr->touch = grown;
            memcpy(pr->touch + pr->n_old, w->best_nb, sizeof(int64_t) * (size_t)n_best);
            pr->n = pr->n_old + n_best;
            memcpy(pr->to, best_x, sizeof best_x);
            pr->gap_after = best;
        }
        st.n_measures += measures;
        if (failed) {
            rc = vc_error_set(err, VC_ENOMEM, "out of memory protecting the interior seeds");
            break;
        }
        /* 4. Take the moves in seed order, each only if no seed it
         * touches has moved in this round and no earlier move touched it
         * (a picked seed may still move next to another); the others wait
         * for the next round. */
        memset(touched, 0, (size_t)n);
        int64_t accepted = 0;
        for (int64_t l = 0; l < n_pick; l++) {
            const int64_t i = list[l], s = n_surface + i;
            proposal *pr = &prop[i];
            if (!pr->touch)
                continue;
            int clash = touched[s];
            for (int k = 0; k < pr->n && !clash; k++)
                clash = moved_round[pr->touch[k]] == round;
            if (clash) {
                next[i] = 1;
                continue;
            }
            memcpy(seeds->xyz + 3 * s, pr->to, sizeof pr->to);
            moved_round[s] = round;
            accepted++;
            for (int k = 0; k < pr->n; k++)
                touched[pr->touch[k]] = 1;
            /* its former neighbours may meet where it was: measured again
             * in the next round (the new ones share its vertices) */
            for (int k = 0; k < pr->n_old; k++)
                if (pr->touch[k] >= n_surface)
                    dirty[pr->touch[k] - n_surface] = 1;
        }
        /* Next: the seeds that waited, those that moved but are still
         * below the target, and the former neighbours of a move (a move
         * is measured with every edge at a vertex of its own cell, where
         * its near-ties are; where it was, its neighbours' cells meet
         * anew). Measured in the next round, not once nothing else is
         * left: then the last round's measure found near-ties the moves
         * had left behind and no round was left to mend them (torus.obj,
         * --protect 0.01, seeds 1 to 4: shortest edge 6.6e-6, 2.8e-4,
         * 5.7e-6, 3.1e-5 of the cell's radius and 301, 300, 279, 247 seeds
         * left short; now 4.0e-4, 2.8e-4, 5.7e-6, 3.1e-5 and 235, 231, 219,
         * 203, for a tenth more time). */
        int64_t n_next = 0;
        for (int64_t i = 0; i < n_int; i++) {
            const int64_t s = n_surface + i;
            if (moved_round[s] == round)
                gap_now[i] = prop[i].gap_after;
            if ((moved_round[s] == round && gap_now[i] < gap) || dirty[i])
                next[i] = 1;
            n_next += next[i];
        }
        memset(dirty, 0, (size_t)n_int);
        st.n_moves += accepted;
        memcpy(active, next, (size_t)n_int);
        if (n_next == 0)
            break;
    }
    if (!rc) {
        /* the final figures: every seed's last measured gap */
        st.n_short_after = 0;
        for (int64_t i = 0; i < n_int; i++) {
            st.n_short_after += gap_now[i] < gap;
            if (gap_now[i] < st.min_edge_after)
                st.min_edge_after = gap_now[i];
            st.n_moved += moved_round[n_surface + i] >= 0;
        }
    }

done:
    if (ws) {
        for (int t = 0; t < threads; t++) {
            vc_convex_cell_free(&ws[t].cell);
            free(ws[t].ball);
        }
        free(ws);
    }
    if (prop)
        for (int64_t i = 0; i < n_int; i++)
            free(prop[i].touch);
    free(prop);
    free(origin);
    free(pick);
    free(active);
    free(next);
    free(dirty);
    free(touched);
    free(moved_round);
    free(gap_now);
    free(list);
    vc_seed_kdtree_free(&tree);
    vc_seed_kdtree_free(&surface_tree);
    if (have_balls)
        vc_ball_tree_free(&balls_tree);
    st.seconds = vc_clock_seconds() - t0;
    if (stats)
        *stats = st;
    return rc;
}
