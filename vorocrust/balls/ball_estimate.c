/* Ball count predicted from the sizing (see ball_estimate.h). */
#include "ball_estimate.h"
#include "ball_set.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/threads.h"

/* balls per unit area of radius bound r is PATCH_DENSITY / r^2, per unit
 * length of crease CREASE_DENSITY / r: random maximal packings (2D
 * packing fraction 0.547, 1D 0.748) at spacing (1 - alpha) r = 0.866 r */
#define PATCH_DENSITY 0.93
#define CREASE_DENSITY 0.86
/* At most about this many triangles (and sharp edges) are evaluated: on a
 * fine surface every k-th of them in file order, weighted by the area
 * (length) of all over that of the ones evaluated. A radius bound costs a
 * tree walk over the elements it may reach, which for the large balls of
 * a fine, smooth surface is thousands: evaluating all 301,052 triangles of
 * fertility.off smoothed took 10 s on 2 threads, longer than sampling, and
 * 16,384 of the 197,996 of a marching-cubes blob 1 s. 4,096 predict within
 * 5% of 16,384 (blobby, genus3, bumpy-cube, fandisk), well inside what the
 * prediction is for: refusing absurd work and sizing the progress lines. */
#define MAX_EVALUATED 4096
/* A triangle longer than twice the bound at its centroid is integrated
 * over its four quarters (cut at its edges' midpoints), and so on, level
 * by level, while the budget of ADAPTIVE_BUDGET bound evaluations lasts
 * (the heaviest pieces first), at most MAX_DEPTH levels.
 * One sample per coarse facet saw only its middle, where the bound is
 * largest: a sphere decimated to 144 triangles was predicted 399 balls for
 * 2,960. Only the pieces that need it are split, so the budget goes where
 * the bound falls: along a small feature in a large face (the bound
 * proportional to the distance to it) every level splits the pieces that
 * touch it, about twice as many as the level before. An equal share per
 * triangle and 5 levels at most stopped at pieces 1/32 of the face, far
 * above such a feature's scale. */
#define ADAPTIVE_BUDGET 65536
#define MAX_DEPTH 24
/* The sampling makes more balls than the packing densities of the bounds:
 * the Lipschitz condition lowers radii between small and large balls, and
 * sliver elimination adds about a fifth. Measured (session 28) on 18
 * surfaces, the bare integral was 0.35 to 0.93 of the balls made, median
 * 0.55; with this factor, on 40 surfaces (the shared models and the
 * generated ones), 0.40 to 1.77; the same (session 39) with the pieces
 * refined under one budget, and a unit cube with a 0.2% chamfer at 0.34
 * (0.16 before). Grading the pieces' bounds by the Lipschitz condition
 * (min over pieces j of r_j + L |x - x_j|, as the sampling grades its
 * balls) was tried: the chamfer 0.52, but the bound's narrow minima at a
 * scan's noise folds, where no ball sits, spread over the whole surface
 * (scan_sphere 4.7 times the balls made, and its input then judged worth
 * a denoised copy). */
#define SAMPLING_EXCESS 1.8

typedef struct estimate_ctx {
    const vc_sizing *z;
    double sz;
    const double *corner_r;  /* per vertex: the corner ball's bound, or 0 */
    const double *edge_r;    /* per edge: the crease ball's bound near it, or 0 */
    /* the corners and sharp edges, each as a ball holding the points
     * within its bound (an edge's: about its midpoint, its half length
     * more), the element's kind and id with it */
    vc_ball_set lower;
} estimate_ctx;

/* A piece of a patch the estimate integrates over: its centroid, area and
 * radius bound there, or area 0 when the corner and crease balls cover it
 * (the patch makes no ball there). */
typedef struct piece {
    double x[3];
    double area, r;
} piece;

/* The pieces of one triangle, in the order of the recursion. */
typedef struct piece_list {
    piece *p;
    int64_t n, cap;
} piece_list;

typedef struct covered_ctx {
    const estimate_ctx *e;
    const double *x;
} covered_ctx;

static int within_lower(void *ctx, int64_t i)
{
    const covered_ctx *c = ctx;
    const vc_balls *b = &c->e->lower.b;
    const int kind = b->kind[i];
    const int64_t id = b->element[i];
    const double r = kind == VC_ELEM_CORNER ? c->e->corner_r[id] : c->e->edge_r[id];
    return vc_sizing_element_dist2(c->e->z, kind, id, c->x) < r * r;
}

/* Is x within the balls of a corner or a crease (their bounds standing
 * for their radii)? The patches' balls only fill what those leave: near a
 * crease the patch's bound falls to 0.49 times the distance to the other
 * side, and counting it there predicted fandisk.off 39,100 balls for
 * 3,399. */
static int under_lower_strata(const estimate_ctx *e, const double x[3])
{
    if (e->lower.b.n == 0)
        return 0;
    covered_ctx c = {e, x};
    return vc_ball_set_query(&e->lower, x, 0, 1.0, 0.0, within_lower, &c);
}

/* The index of the corner and crease balls (see estimate_ctx); 0, or -1
 * when out of memory. */
static int index_lower(estimate_ctx *e)
{
    const vc_surface *s = e->z->s;
    const vc_features *f = e->z->f;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t v = 0; v < s->n_vertices; v++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * v + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * v + d]);
        }
    const double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                             (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (vc_ball_set_init(&e->lower, lo, diag))
        return -1;
    const double none[3] = {0, 0, 0};
    for (int64_t v = 0; v < s->n_vertices; v++)
        if (e->corner_r[v] > 0 && isfinite(e->corner_r[v]) &&
            vc_ball_set_add(&e->lower, s->xyz + 3 * v, e->corner_r[v], VC_ELEM_CORNER, v, none) < 0)
            return -1;
    for (int64_t k = 0; k < f->n_edges; k++) {
        if (!(e->edge_r[k] > 0) || !isfinite(e->edge_r[k]))
            continue;
        const double *a = s->xyz + 3 * f->edge_vertex[2 * k], *b = s->xyz + 3 * f->edge_vertex[2 * k + 1];
        const double m[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
        const double half = 0.5 * sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                       (b[2] - a[2]) * (b[2] - a[2]));
        if (vc_ball_set_add(&e->lower, m, e->edge_r[k] + half, VC_ELEM_EDGE, k, none) < 0)
            return -1;
    }
    return 0;
}

static void lengths(const double *a, const double *b, const double *c, double *area, double *longest)
{
    double u[3], w[3], v[3];
    for (int d = 0; d < 3; d++) {
        u[d] = b[d] - a[d];
        w[d] = c[d] - a[d];
        v[d] = c[d] - b[d];
    }
    const double cx = u[1] * w[2] - u[2] * w[1], cy = u[2] * w[0] - u[0] * w[2], cz = u[0] * w[1] - u[1] * w[0];
    *area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
    *longest = sqrt(fmax(u[0] * u[0] + u[1] * u[1] + u[2] * u[2],
                         fmax(w[0] * w[0] + w[1] * w[1] + w[2] * w[2], v[0] * v[0] + v[1] * v[1] + v[2] * v[2])));
}

/* A piece awaiting its verdict: split, or integrated as it is. */
typedef struct open_piece {
    double v[9]; /* corners */
    double x[3], r, area, longest;
} open_piece;

static void open_piece_set(const estimate_ctx *e, int64_t t, const double *a, const double *b, const double *c,
                           open_piece *o)
{
    memcpy(o->v, a, sizeof(double) * 3);
    memcpy(o->v + 3, b, sizeof(double) * 3);
    memcpy(o->v + 6, c, sizeof(double) * 3);
    for (int d = 0; d < 3; d++)
        o->x[d] = (a[d] + b[d] + c[d]) / 3;
    lengths(a, b, c, &o->area, &o->longest);
    vc_surface_point sp = {VC_ELEM_TRIANGLE, t};
    o->r = o->area > 0 ? vc_sizing_radius_bound(e->z, &sp, o->x, e->sz) : INFINITY;
}

static int push_piece(piece_list *L, const estimate_ctx *e, const open_piece *o)
{
    if (L->n == L->cap) {
        const int64_t cap = L->cap ? 2 * L->cap : 4;
        piece *q = realloc(L->p, sizeof *q * (size_t)cap);
        if (!q)
            return -1;
        L->p = q;
        L->cap = cap;
    }
    piece *q = &L->p[L->n++];
    memcpy(q->x, o->x, sizeof q->x);
    q->area = under_lower_strata(e, o->x) ? 0 : o->area;
    q->r = o->r;
    return 0;
}

typedef struct split_key {
    double weight; /* the piece's balls as it stands: area / r^2 */
    int64_t k;
} split_key;

static int heavier_first(const void *a, const void *b)
{
    const split_key *u = a, *v = b;
    if (u->weight != v->weight)
        return u->weight > v->weight ? -1 : 1;
    return (u->k > v->k) - (u->k < v->k);
}

/* The pieces of the evaluated triangles (every tri_stride-th), into
 * pieces[t], refined level by level over all of them at once: a piece
 * longer than twice its bound is split into its four quarters while the
 * budget lasts, the heaviest first (area / r^2) when it cannot split all
 * of a level's. tri_r[t] and tri_at[t] get the smallest bound met on t
 * and where. The same pieces for any thread count. Returns 0, or -1 when
 * out of memory. */
static int patch_pieces(const estimate_ctx *e, int64_t tri_stride, int nth, piece_list *pieces,
                        double *tri_r, double *tri_at)
{
    const vc_surface *s = e->z->s;
    const int64_t nt = s->n_triangles;
    int64_t n = 0;
    for (int64_t t = 0; t < nt; t += tri_stride)
        n++;
    open_piece *level = malloc(sizeof *level * (size_t)(n + 1));
    int64_t *level_t = malloc(sizeof(int64_t) * (size_t)(n + 1));
    if (!level || !level_t) {
        free(level);
        free(level_t);
        return -1;
    }
#pragma omp parallel for schedule(dynamic, 64) num_threads(nth)
    for (int64_t k = 0; k < n; k++) {
        const int64_t t = k * tri_stride;
        level_t[k] = t;
        open_piece_set(e, t, s->xyz + 3 * s->tri[3 * t], s->xyz + 3 * s->tri[3 * t + 1],
                       s->xyz + 3 * s->tri[3 * t + 2], &level[k]);
    }
    int64_t budget = ADAPTIVE_BUDGET;
    int rc = 0;
    for (int depth = 0; n > 0 && !rc; depth++) {
        split_key *want = malloc(sizeof *want * (size_t)(n + 1));
        if (!want) {
            rc = -1;
            break;
        }
        int64_t n_want = 0;
        for (int64_t k = 0; k < n; k++) {
            const open_piece *o = &level[k];
            if (!(o->area > 0))
                continue;
            const int64_t t = level_t[k];
            if (o->r < tri_r[t]) {
                tri_r[t] = o->r;
                memcpy(tri_at + 3 * t, o->x, sizeof o->x);
            }
            if (depth < MAX_DEPTH && o->longest > 2 * o->r) {
                want[n_want].weight = o->r > 0 ? o->area / (o->r * o->r) : INFINITY;
                want[n_want++].k = k;
            }
        }
        if (4 * n_want > budget) {
            qsort(want, (size_t)n_want, sizeof *want, heavier_first);
            n_want = budget / 4;
        }
        /* split marks the pieces split, in level order */
        unsigned char *split = calloc((size_t)(n + 1), 1);
        int64_t *rank = malloc(sizeof(int64_t) * (size_t)(n + 1));
        open_piece *next = malloc(sizeof *next * (size_t)(4 * n_want + 1));
        int64_t *next_t = malloc(sizeof(int64_t) * (size_t)(4 * n_want + 1));
        if (!split || !rank || !next || !next_t) {
            free(want);
            free(split);
            free(rank);
            free(next);
            free(next_t);
            rc = -1;
            break;
        }
        for (int64_t m = 0; m < n_want; m++)
            split[want[m].k] = 1;
        free(want);
        int64_t n_split = 0;
        for (int64_t k = 0; k < n && !rc; k++) {
            rank[k] = n_split;
            if (split[k])
                n_split++;
            else if (level[k].area > 0 && push_piece(&pieces[level_t[k]], e, &level[k]))
                rc = -1;
        }
#pragma omp parallel for schedule(dynamic, 64) num_threads(nth)
        for (int64_t k = 0; k < n; k++) {
            if (!split[k])
                continue;
            const open_piece *o = &level[k];
            const int64_t t = level_t[k];
            open_piece *ch = next + 4 * rank[k];
            double m[3][3];
            for (int d = 0; d < 3; d++) {
                m[0][d] = 0.5 * (o->v[d] + o->v[3 + d]);
                m[1][d] = 0.5 * (o->v[3 + d] + o->v[6 + d]);
                m[2][d] = 0.5 * (o->v[6 + d] + o->v[d]);
            }
            open_piece_set(e, t, o->v, m[0], m[2], &ch[0]);
            open_piece_set(e, t, m[0], o->v + 3, m[1], &ch[1]);
            open_piece_set(e, t, m[2], m[1], o->v + 6, &ch[2]);
            open_piece_set(e, t, m[0], m[1], m[2], &ch[3]);
            for (int q = 0; q < 4; q++)
                next_t[4 * rank[k] + q] = t;
        }
        free(split);
        free(rank);
        free(level);
        free(level_t);
        level = next;
        level_t = next_t;
        n = 4 * n_split;
        budget -= 4 * n_split;
    }
    free(level);
    free(level_t);
    return rc;
}

/* tri_n[t] = the balls of triangle t's pieces: 0.93 / r^2 per unit area,
 * summed in the pieces' order (the same for any thread count). */
static void integrate_pieces(const piece_list *pieces, int64_t nt, int nth, double *tri_n)
{
#pragma omp parallel for schedule(dynamic, 64) num_threads(nth)
    for (int64_t t = 0; t < nt; t++) {
        double sum = 0;
        for (int64_t m = 0; m < pieces[t].n; m++) {
            const piece *q = &pieces[t].p[m];
            if (q->area > 0)
                sum += q->r > 0 ? PATCH_DENSITY * q->area / (q->r * q->r) : INFINITY;
        }
        tri_n[t] = sum;
    }
}

int vc_ball_estimate_compute(const vc_sizing *z, double sz, int threads, vc_ball_estimate *out)
{
    const vc_surface *s = z->s;
    const vc_features *f = z->f;
    memset(out, 0, sizeof *out);
    const int64_t nt = s->n_triangles, ne = f->n_edges, nv = s->n_vertices;
    double *tri_n = malloc(sizeof(double) * (size_t)(nt > 0 ? nt : 1));
    double *tri_r = malloc(sizeof(double) * (size_t)(nt > 0 ? nt : 1));
    double *tri_at = malloc(sizeof(double) * 3 * (size_t)(nt > 0 ? nt : 1));
    double *edge_n = malloc(sizeof(double) * (size_t)(ne > 0 ? ne : 1));
    double *edge_r = malloc(sizeof(double) * (size_t)(ne > 0 ? ne : 1));
    double *edge_ball = calloc((size_t)(ne > 0 ? ne : 1), sizeof(double));
    double *corner_r = calloc((size_t)(nv > 0 ? nv : 1), sizeof(double));
    int64_t *edge_rank = malloc(sizeof(int64_t) * (size_t)(ne > 0 ? ne : 1)); /* among sharp edges */
    if (!tri_n || !tri_r || !tri_at || !edge_n || !edge_r || !edge_ball || !corner_r || !edge_rank) {
        free(tri_n);
        free(tri_r);
        free(tri_at);
        free(edge_n);
        free(edge_r);
        free(edge_ball);
        free(corner_r);
        free(edge_rank);
        return -1;
    }
    int64_t n_sharp = 0;
    for (int64_t e = 0; e < ne; e++)
        edge_rank[e] = f->edge_sharp[e] ? n_sharp++ : -1;
    const int64_t tri_stride = nt > MAX_EVALUATED ? (nt + MAX_EVALUATED - 1) / MAX_EVALUATED : 1;
    const int64_t edge_stride = n_sharp > MAX_EVALUATED ? (n_sharp + MAX_EVALUATED - 1) / MAX_EVALUATED : 1;
    const int nth = vc_threads_or_default(threads); /* 0: all cores, as everywhere */

    /* the corner balls */
#pragma omp parallel for schedule(dynamic, 256) num_threads(nth)
    for (int64_t v = 0; v < nv; v++) {
        if (!f->vertex_corner[v])
            continue;
        vc_surface_point sp = {VC_ELEM_CORNER, v};
        corner_r[v] = vc_sizing_radius_bound(z, &sp, s->xyz + 3 * v, sz);
    }
    /* the creases: a sample at every evaluated edge's midpoint */
#pragma omp parallel for schedule(dynamic, 256) num_threads(nth)
    for (int64_t e = 0; e < ne; e++) {
        edge_n[e] = 0;
        edge_r[e] = INFINITY;
        if (!f->edge_sharp[e] || (edge_stride > 1 && edge_rank[e] % edge_stride != 0))
            continue;
        const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
        const double x[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
        const double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                (b[2] - a[2]) * (b[2] - a[2]));
        vc_surface_point sp = {VC_ELEM_EDGE, e};
        const double r = vc_sizing_radius_bound(z, &sp, x, sz);
        edge_r[e] = r;
        /* within a corner's ball, the corner covers the crease */
        int in_corner = 0;
        for (int k = 0; k < 2; k++) {
            const int64_t v = f->edge_vertex[2 * e + k];
            const double *p = s->xyz + 3 * v;
            const double d2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) +
                              (x[2] - p[2]) * (x[2] - p[2]);
            in_corner |= corner_r[v] > 0 && d2 < corner_r[v] * corner_r[v];
        }
        edge_n[e] = in_corner ? 0 : r > 0 ? CREASE_DENSITY * len / r : INFINITY;
    }
    /* every sharp edge's crease balls: those of the last one evaluated
     * before it (all of them, below MAX_EVALUATED) */
    double last = 0;
    for (int64_t e = 0; e < ne; e++) {
        if (!f->edge_sharp[e])
            continue;
        if (isfinite(edge_r[e]))
            last = edge_r[e];
        edge_ball[e] = last;
    }
    estimate_ctx ec = {.z = z, .sz = sz, .corner_r = corner_r, .edge_r = edge_ball};
    int fail = index_lower(&ec);

    /* the patches */
    piece_list *pieces = calloc((size_t)(nt > 0 ? nt : 1), sizeof *pieces);
    for (int64_t t = 0; t < nt; t++) {
        tri_n[t] = 0;
        tri_r[t] = INFINITY;
    }
    if (!pieces || (!fail && patch_pieces(&ec, tri_stride, nth, pieces, tri_r, tri_at)))
        fail = 1;
    if (!fail)
        integrate_pieces(pieces, nt, nth, tri_n);
    for (int64_t t = 0; pieces && t < nt; t++)
        free(pieces[t].p);
    free(pieces);
    /* the evaluated ones stand for all: weights by area and length */
    double area_all = 0, area_eval = 0, len_all = 0, len_eval = 0;
    for (int64_t t = 0; t < nt; t++) {
        double area, longest;
        lengths(s->xyz + 3 * s->tri[3 * t], s->xyz + 3 * s->tri[3 * t + 1], s->xyz + 3 * s->tri[3 * t + 2], &area,
                &longest);
        area_all += area;
        if (t % tri_stride == 0)
            area_eval += area;
    }
    for (int64_t e = 0; e < ne; e++) {
        if (!f->edge_sharp[e])
            continue;
        const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
        const double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                (b[2] - a[2]) * (b[2] - a[2]));
        len_all += len;
        if (edge_stride == 1 || edge_rank[e] % edge_stride == 0)
            len_eval += len;
    }
    const double tri_weight = tri_stride > 1 && area_eval > 0 ? area_all / area_eval : 1;
    const double edge_weight = edge_stride > 1 && len_eval > 0 ? len_all / len_eval : 1;
    /* summed in index order: the same figure for any thread count */
    double n = 0, r_min = INFINITY;
    double n_tri = 0, n_edge = 0;
    for (int64_t t = 0; t < nt; t++) {
        n_tri += tri_n[t];
        if (tri_r[t] < r_min) {
            r_min = tri_r[t];
            memcpy(out->r_min_at, tri_at + 3 * t, sizeof out->r_min_at);
        }
    }
    for (int64_t e = 0; e < ne; e++) {
        n_edge += edge_n[e];
        if (edge_r[e] < r_min) {
            r_min = edge_r[e];
            const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
            for (int d = 0; d < 3; d++)
                out->r_min_at[d] = 0.5 * (a[d] + b[d]);
        }
    }
    n += SAMPLING_EXCESS * (tri_weight * n_tri + edge_weight * n_edge);
    for (int64_t v = 0; v < nv; v++)
        n += f->vertex_corner[v] != 0;
    out->n_balls = n;
    out->r_min = r_min;
    free(tri_n);
    free(tri_r);
    free(tri_at);
    free(edge_n);
    free(edge_r);
    free(edge_ball);
    free(corner_r);
    free(edge_rank);
    vc_ball_set_free(&ec.lower);
    return fail ? -1 : 0;
}
