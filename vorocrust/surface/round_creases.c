/* Rounds narrower than the error bound are creases (step 2c of
 * vc_features_detect_scaled; docs/sampling-convergence.md, "Session 48").
 *
 * An edge rounded far below the error bound (a wing's trailing edge of
 * radius a quarter of the bound, a coin's rim, a small fillet a CAD export
 * tessellated into folds below theta_sharp) turns the surface by more than
 * theta_sharp across a band the bound does not resolve. Kept smooth, the
 * band has no crease: the sizing finds the far side of the round, not
 * co-smooth, a radius of curvature away, and the balls shrink to that and
 * grade out over both flanks (a NACA 0012 wing whose trailing edge is
 * rounded to 0.24 error bounds: 60,556 balls and 18.6 s, against 6,751 and
 * 2.1 s for the same wing with a sharp trailing edge). At the bound's scale
 * the band is a crease, and a crease through it moves the reconstruction
 * by less than the round's radius.
 *
 * 1. A fold e (below theta_sharp, at least ROUND_MIN_FOLD of it, and
 *    steeper than a curvature radius of W = ROUND_WIDTH error bounds would
 *    make it over its triangles' widths) is in a round when its flanks are
 *    flat (each spreads by at most ROUND_FLANK_SPREAD of the turn between
 *    them) and turn by at least theta_sharp. A flank: the triangles beside
 *    the fold (their centroids' projections on its line within W of it)
 *    whose centroids lie W or more from that line, entered within 2 W of
 *    it by a Dijkstra walk from the fold's two triangles within the patch
 *    (each side the one its walk started from), whose steps count the
 *    distance across each edge crossed, not along it (a CAD export's band
 *    of triangles long along the round). Curved ground fails the test at
 *    any radius: on a cylinder the flanks spread by a third of the turn
 *    between them. A fold beside a crease along it (within W) is left: the
 *    round is that crease's.
 * 2. Each triangle beside such a fold takes the nearer of the two flank
 *    normals of one of its folds (the lowest-numbered; a triangle about
 *    halfway, within ROUND_TIE, takes the flank first in an order of the
 *    pair that turns slowly along a band, so that the middle row of a
 *    symmetric round goes one way along all of it).
 * 3. The edges between triangles that took flanks more than theta_sharp
 *    apart are the crease (VC_SHARP_ROUND): the boundary of a set of
 *    triangles, so it has no gaps. Networks of them spanning less than
 *    ROUND_EXTENT error bounds are dropped, and those with an end on smooth
 *    ground (not within W of another network or crease).
 * 4. The triangles of the band keep the flank they took as their smoothed
 *    normal (vc_features.tri_smooth_normal, marked in tri_round): the
 *    sizing then sees each side of the crease as its flank, as on a sharp
 *    edge. */
#include "feature_scale.h"
#include "util/reserve.h"
#include "util/union_find.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* the flanks start this many error bounds from the fold, and end twice as far */
#define ROUND_WIDTH 0.5
/* each flank's spread at most this share of the turn between them */
#define ROUND_FLANK_SPREAD 0.25
/* a fold below this share of theta_sharp is no round's */
#define ROUND_MIN_FOLD 0.125
/* a flank's area at least this many W^2 (a flat half annulus has 4.7) */
#define ROUND_FLANK_AREA 1.0
/* a crease network (edges joined at vertices) spans at least this many
 * error bounds, the reach the flatness of folds is judged over
 * (VC_FLAT_REACH): a shorter one is a speck of noise folds that happened
 * to line up */
#define ROUND_EXTENT VC_FLAT_REACH
/* a triangle whose normal is within this sine of the plane bisecting its
 * two flanks is halfway between them (the flanks of one fold are measured
 * over regions offset by a triangle: a lens's rim strip, vertical, came
 * out 0.6 degrees nearer one or the other at random) */
#define ROUND_TIE 0.05

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* -1 when triangles t and u, which share edge e, walk it the same way (one
 * of them turned over relative to the other), +1 otherwise. */
static int relative_sign(const vc_surface *s, const vc_features *f, int64_t t, int64_t u, int64_t e)
{
    return -vc_features_walks_forward(f, s, t, e) * vc_features_walks_forward(f, s, u, e);
}

static double area(const vc_surface *s, int64_t t)
{
    return 0.5 * vc_triangle_twice_area(s, t);
}

/* Distance from c to the line through edge e; *beyond (if not NULL): how
 * far c's projection on that line lies outside the edge. */
static double line_distance(const vc_surface *s, const vc_features *f, int64_t e, const double c[3],
                            double *beyond)
{
    const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
    const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double l2 = dot3(ab, ab), t = l2 > 0 ? dot3(ac, ab) / l2 : 0;
    const double d[3] = {ac[0] - t * ab[0], ac[1] - t * ab[1], ac[2] - t * ab[2]};
    if (beyond)
        *beyond = fmax(0.0, fmax(-t, t - 1)) * sqrt(l2);
    return sqrt(dot3(d, d));
}

/* Has triangle t taken a flank (step 2; zero: none)? */
static int labelled(const double *label, int64_t t)
{
    const double *l = label + 3 * t;
    return l[0] != 0 || l[1] != 0 || l[2] != 0;
}

static int has_normal(const vc_features *f, int64_t t)
{
    const double *n = f->tri_normal + 3 * t;
    return n[0] != 0 || n[1] != 0 || n[2] != 0;
}

/* A walk's scratch (one per thread): per triangle the walk that last
 * reached it, its distance (at its centroid, and where it was entered), side (1 or 2) and sign relative to the fold's
 * first triangle; and a binary heap of (distance, triangle). */
typedef struct round_walk {
    int64_t *stamp, walk;
    double *dist, *entry;
    signed char *side, *sign;
    struct heap_item {
        double d;
        int64_t t;
    } *heap;
    int64_t n_heap, cap_heap;
} round_walk;

static int walk_init(round_walk *w, int64_t nt)
{
    const size_t n = (size_t)(nt > 0 ? nt : 1);
    memset(w, 0, sizeof *w);
    w->stamp = calloc(n, sizeof *w->stamp);
    w->dist = malloc(n * sizeof *w->dist);
    w->entry = malloc(n * sizeof *w->entry);
    w->side = malloc(n);
    w->sign = malloc(n);
    return w->stamp && w->dist && w->entry && w->side && w->sign ? 0 : -1;
}

static void walk_free(round_walk *w)
{
    free(w->stamp);
    free(w->dist);
    free(w->entry);
    free(w->side);
    free(w->sign);
    free(w->heap);
    memset(w, 0, sizeof *w);
}

/* Ordered by distance, then triangle: the same walk on any thread. */
static int item_less(const struct heap_item *a, const struct heap_item *b)
{
    return a->d < b->d || (a->d == b->d && a->t < b->t);
}

static int heap_push(round_walk *w, double d, int64_t t)
{
    if (vc_reserve(&w->heap, &w->cap_heap, w->n_heap + 1, sizeof *w->heap))
        return -1;
    int64_t i = w->n_heap++;
    const struct heap_item it = {d, t};
    while (i > 0 && item_less(&it, &w->heap[(i - 1) / 2])) {
        w->heap[i] = w->heap[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    w->heap[i] = it;
    return 0;
}

static struct heap_item heap_pop(round_walk *w)
{
    const struct heap_item top = w->heap[0], last = w->heap[--w->n_heap];
    int64_t i = 0;
    for (;;) {
        int64_t c = 2 * i + 1;
        if (c >= w->n_heap)
            break;
        if (c + 1 < w->n_heap && item_less(&w->heap[c + 1], &w->heap[c]))
            c++;
        if (!item_less(&w->heap[c], &last))
            break;
        w->heap[i] = w->heap[c];
        i = c;
    }
    if (w->n_heap > 0)
        w->heap[i] = last;
    return top;
}

/* Do edges g and e make an angle below 45 degrees? */
static int along(const vc_surface *s, const vc_features *f, int64_t g, int64_t e)
{
    double u[3], v[3];
    for (int d = 0; d < 3; d++) {
        u[d] = s->xyz[3 * f->edge_vertex[2 * g + 1] + d] - s->xyz[3 * f->edge_vertex[2 * g] + d];
        v[d] = s->xyz[3 * f->edge_vertex[2 * e + 1] + d] - s->xyz[3 * f->edge_vertex[2 * e] + d];
    }
    const double uv = dot3(u, v);
    return uv * uv > 0.5 * dot3(u, u) * dot3(v, v);
}

/* Step 1 for fold e (triangles t1, t2): whether it lies in a round, with
 * the unit flank normals n1 (t1's side), n2 in t1's orientation. Returns 1
 * (a round), 0 (not) or -1 (out of memory). */
static int fold_in_round(const vc_surface *s, const vc_features *f, round_walk *w, int64_t e,
                         int64_t t1, int64_t t2, double W, double cos_theta, double n1[3],
                         double n2[3])
{
    double sum[2][3] = {{0, 0, 0}, {0, 0, 0}}, mass[2] = {0, 0}, capped[2] = {0, 0};
    w->walk++;
    w->n_heap = 0;
    for (int k = 0; k < 2; k++) {
        const int64_t t = k ? t2 : t1;
        double c[3];
        vc_triangle_centroid(s, t, c);
        w->stamp[t] = w->walk;
        w->dist[t] = line_distance(s, f, e, c, NULL);
        w->entry[t] = 0;
        w->side[t] = (signed char)(k + 1);
        w->sign[t] = (signed char)(k ? relative_sign(s, f, t1, t2, e) : 1);
        if (heap_push(w, w->dist[t], t))
            return -1;
    }
    while (w->n_heap > 0) {
        const struct heap_item it = heap_pop(w);
        const int64_t t = it.t;
        if (it.d > w->dist[t])
            continue; /* a stale entry */
        const int k = w->side[t] - 1;
        double ct[3], beyond;
        vc_triangle_centroid(s, t, ct);
        /* beside the fold only: the band's next stretch, along it, is no
         * flank of this fold */
        const double across = line_distance(s, f, e, ct, &beyond);
        if (beyond > W)
            continue;
        /* a flank triangle: its centroid W or more from the fold's line,
         * entered within 2 W of it (a wide triangle next to a narrow band
         * is a flank) */
        if (across >= W && w->entry[t] < 2 * W && has_normal(f, t)) {
            const double ar = area(s, t), *n = f->tri_normal + 3 * t;
            for (int d = 0; d < 3; d++)
                sum[k][d] += ar * w->sign[t] * n[d];
            mass[k] += ar;
            capped[k] += fmin(ar, 2 * W * W);
        }
        if (it.d >= 2 * W)
            continue;
        for (int j = 0; j < 3; j++) {
            const int64_t g = f->tri_edge[3 * t + j];
            /* a crease along the band, within it: the round is the
             * crease's (a rim whose middle folds by theta_sharp on one side
             * and just below it on the other); a second crease beside it
             * would be one more feature the width of the band away */
            if (g != e && f->edge_sharp[g] && it.d < W && along(s, f, g, e))
                return 0;
            if (g == e || f->edge_sharp[g] || f->edge_tri_start[g + 1] - f->edge_tri_start[g] != 2)
                continue;
            const int64_t u = f->edge_tri[f->edge_tri_start[g]] == t ? f->edge_tri[f->edge_tri_start[g] + 1]
                                                                    : f->edge_tri[f->edge_tri_start[g]];
            /* across each edge crossed, not along it: a long triangle of a
             * band (a CAD export's) is as far from the fold as it is wide */
            double cu[3];
            vc_triangle_centroid(s, u, cu);
            const double in = it.d + line_distance(s, f, g, ct, NULL),
                         du = in + line_distance(s, f, g, cu, NULL);
            if (w->stamp[u] == w->walk && !(du < w->dist[u]))
                continue;
            w->stamp[u] = w->walk;
            w->dist[u] = du;
            w->entry[u] = in;
            w->side[u] = w->side[t];
            w->sign[u] = (signed char)(w->sign[t] * relative_sign(s, f, t, u, g));
            if (heap_push(w, du, u))
                return -1;
        }
    }
    if (!(capped[0] >= ROUND_FLANK_AREA * W * W && capped[1] >= ROUND_FLANK_AREA * W * W))
        return 0;
    const double l1 = sqrt(dot3(sum[0], sum[0])), l2 = sqrt(dot3(sum[1], sum[1]));
    if (!(l1 > 0 && l2 > 0))
        return 0;
    for (int d = 0; d < 3; d++) {
        n1[d] = sum[0][d] / l1;
        n2[d] = sum[1][d] / l2;
    }
    const double c12 = dot3(n1, n2);
    if (!(c12 <= cos_theta))
        return 0;
    /* a flank's spread: an arc of angle a has mean length sin(a/2)/(a/2),
     * so a is about 2 sqrt(3) acos(mean length) */
    const double turn = acos(fmax(-1.0, c12));
    const double spread = 2 * sqrt(3.0) * acos(fmin(1.0, fmin(l1 / mass[0], l2 / mass[1])));
    return spread <= ROUND_FLANK_SPREAD * turn;
}

/* Which of two flanks p, q a triangle halfway between them takes, the
 * same along a band: the pair is first turned so that the largest
 * component of its bisector is positive (either orientation of a
 * triangle then gives the same flank), then p is taken when the largest
 * component of p - q is positive. Along a band the bisector and the
 * difference turn slowly; a wing's trailing edge sends its middle row up
 * all along, a lens's rim to its top face. */
static int take_first(const double *p, const double *q)
{
    double b[3], d[3];
    int ib = 0, id = 0;
    for (int k = 0; k < 3; k++) {
        b[k] = p[k] + q[k];
        d[k] = p[k] - q[k];
        ib = fabs(b[k]) > fabs(b[ib]) ? k : ib;
        id = fabs(d[k]) > fabs(d[id]) ? k : id;
    }
    return (b[ib] < 0) != (d[id] > 0);
}

/* A vertex by its x coordinate, for the range searches of step 3. */
typedef struct by_x {
    double x;
    int64_t v;
} by_x;

static int by_x_less(const void *a, const void *b)
{
    const by_x *p = a, *q = b;
    return p->x < q->x ? -1 : p->x > q->x ? 1 : (p->v > q->v) - (p->v < q->v);
}

int64_t vc_features_mark_rounds(const vc_surface *s, vc_features *f, double scale, double cos_theta,
                                const unsigned char *near, double **round_normal)
{
    *round_normal = NULL;
    const int64_t ne = f->n_edges, nt = s->n_triangles, nv = s->n_vertices;
    if (!(scale > 0) || ne == 0)
        return 0;
    const double W = ROUND_WIDTH * scale;
    const double theta = acos(fmax(-1.0, fmin(1.0, cos_theta)));
    const double cos_min_fold = cos(ROUND_MIN_FOLD * theta);

    /* the folds to try */
    int64_t *cand = malloc(sizeof *cand * (size_t)(ne > 0 ? ne : 1));
    if (!cand)
        return -1;
    int64_t nc = 0;
    for (int64_t e = 0; e < ne; e++) {
        if (f->edge_sharp[e] || f->edge_tri_start[e + 1] - f->edge_tri_start[e] != 2)
            continue;
        const int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
        if (!has_normal(f, t1) || !has_normal(f, t2) || (near && (near[t1] || near[t2])))
            continue;
        const double c = relative_sign(s, f, t1, t2, e) *
                         dot3(f->tri_normal + 3 * t1, f->tri_normal + 3 * t2);
        if (!(c < cos_min_fold))
            continue;
        /* a fold no steeper than a radius of W over its triangles' widths
         * (the smaller height over the edge) would make is curved ground */
        const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
        const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double len = sqrt(dot3(ab, ab));
        if (!(len > 0))
            continue;
        const double h = 2 * fmin(area(s, t1), area(s, t2)) / len;
        if (!(acos(fmax(-1.0, c)) > h / W))
            continue;
        cand[nc++] = e;
    }
    if (nc == 0) {
        free(cand);
        return 0;
    }
    double *label = NULL;
    unsigned char *keep = NULL;
    int64_t *parent = NULL;
    double *box = NULL;
    unsigned char *degree = NULL;
    by_x *near_v = NULL;
    int64_t n_crease = 0, n_round = 0;
    double *flank = malloc(sizeof *flank * 6 * (size_t)nc);
    signed char *in_round = malloc((size_t)nc);
    int64_t *slot = malloc(sizeof *slot * (size_t)ne);
    int oom = !flank || !in_round || !slot;
    if (oom)
        goto done;
#pragma omp parallel reduction(| : oom)
    {
        round_walk w;
        if (walk_init(&w, nt))
            oom = 1;
        else {
#pragma omp for schedule(dynamic, 64)
            for (int64_t i = 0; i < nc; i++) {
                const int64_t e = cand[i];
                const int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
                const int r = fold_in_round(s, f, &w, e, t1, t2, W, cos_theta, flank + 6 * i,
                                            flank + 6 * i + 3);
                in_round[i] = (signed char)(r > 0);
                if (r < 0)
                    oom = 1;
            }
        }
        walk_free(&w);
    }
    for (int64_t e = 0; e < ne; e++)
        slot[e] = -1;
    for (int64_t i = 0; i < nc; i++)
        if (in_round[i]) {
            slot[cand[i]] = i;
            n_round++;
        }
    if (oom || n_round == 0)
        goto done;

    /* 2. each triangle beside a fold in a round takes a flank, in its own
     * orientation (zero: none) */
    label = calloc((size_t)(3 * nt), sizeof *label);
    if (!label) {
        oom = 1;
        goto done;
    }
#pragma omp parallel for schedule(dynamic, 1024)
    for (int64_t t = 0; t < nt; t++) {
        int64_t e = -1;
        for (int j = 0; j < 3; j++) {
            const int64_t g = f->tri_edge[3 * t + j];
            if (slot[g] >= 0 && (e < 0 || g < e))
                e = g;
        }
        if (e < 0)
            continue;
        const int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
        const double sg = t == t1 ? 1.0 : relative_sign(s, f, t1, t2, e);
        double p[3], q[3];
        for (int d = 0; d < 3; d++) {
            p[d] = sg * flank[6 * slot[e] + d];
            q[d] = sg * flank[6 * slot[e] + 3 + d];
        }
        const double *n = f->tri_normal + 3 * t;
        const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]}, nd = dot3(n, d);
        const double *pick = fabs(nd) < ROUND_TIE * sqrt(dot3(d, d)) ? (take_first(p, q) ? p : q)
                                                                     : (nd > 0 ? p : q);
        memcpy(label + 3 * t, pick, sizeof(double) * 3);
    }

    /* 3. the crease: edges between triangles whose flanks differ by theta */
    keep = calloc((size_t)(ne > 0 ? ne : 1), 1);
    parent = malloc(sizeof *parent * (size_t)(nv > 0 ? nv : 1));
    if (!keep || !parent) {
        oom = 1;
        goto done;
    }
    vc_uf_init(parent, nv);
    for (int64_t e = 0; e < ne; e++) {
        if (f->edge_sharp[e] || f->edge_tri_start[e + 1] - f->edge_tri_start[e] != 2)
            continue;
        const int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
        if (!labelled(label, t1) || !labelled(label, t2) ||
            !(relative_sign(s, f, t1, t2, e) * dot3(label + 3 * t1, label + 3 * t2) <= cos_theta))
            continue;
        keep[e] = 1;
        vc_uf_unite(parent, f->edge_vertex[2 * e], f->edge_vertex[2 * e + 1]);
    }
    /* networks shorter than ROUND_EXTENT error bounds are dropped, and so
     * are those that end in smooth ground (an end at no other sharp edge): a
     * round crease runs round a closed rim or into other features; a
     * stretch of one is the few folds of a round fading below the test's
     * threshold, or noise folds that passed it, whose ends would be
     * corners */
    box = malloc(sizeof *box * 6 * (size_t)(nv > 0 ? nv : 1));
    degree = calloc((size_t)(nv > 0 ? nv : 1), sizeof *degree);
    near_v = malloc(sizeof *near_v * (size_t)(nv > 0 ? nv : 1));
    if (!box || !degree || !near_v) {
        oom = 1;
        goto done;
    }
    for (int64_t e = 0; e < ne; e++)
        if (keep[e] || f->edge_sharp[e])
            for (int k = 0; k < 2; k++) {
                unsigned char *dv = degree + f->edge_vertex[2 * e + k];
                if (f->edge_sharp[e])
                    *dv |= 0x80; /* on a crease already */
                else if ((*dv & 0x7f) < 3)
                    (*dv)++;
            }
    for (int64_t v = 0; v < nv; v++)
        for (int d = 0; d < 3; d++) {
            box[6 * v + d] = INFINITY;
            box[6 * v + 3 + d] = -INFINITY;
        }
    for (int64_t e = 0; e < ne; e++)
        if (keep[e])
            for (int k = 0; k < 2; k++) {
                const int64_t v = f->edge_vertex[2 * e + k], r = vc_uf_find(parent, v);
                for (int d = 0; d < 3; d++) {
                    box[6 * r + d] = fmin(box[6 * r + d], s->xyz[3 * v + d]);
                    box[6 * r + 3 + d] = fmax(box[6 * r + 3 + d], s->xyz[3 * v + d]);
                }
            }
    /* a free end: the network is dropped (its box emptied), unless the end
     * lies within W of a vertex of another network or of a crease (three
     * round creases stop short of a box's rounded corner, where none of
     * the corner's triangles lies between two flat flanks) */
    int64_t n_near = 0;
    for (int64_t v = 0; v < nv; v++)
        if (degree[v])
            near_v[n_near++] = (by_x){s->xyz[3 * v], v};
    qsort(near_v, (size_t)n_near, sizeof *near_v, by_x_less);
    for (int64_t v = 0; v < nv; v++) {
        if (!((degree[v] & 0x7f) == 1 && !(degree[v] & 0x80)))
            continue;
        const int64_t r = vc_uf_find(parent, v);
        const double *p = s->xyz + 3 * v;
        /* the candidates within W in x, from a binary search */
        int64_t lo = 0, hi = n_near;
        while (lo < hi) {
            const int64_t mid = lo + (hi - lo) / 2;
            if (near_v[mid].x < p[0] - W)
                lo = mid + 1;
            else
                hi = mid;
        }
        int attached = 0;
        for (int64_t i = lo; i < n_near && near_v[i].x <= p[0] + W && !attached; i++) {
            const int64_t u = near_v[i].v;
            if ((degree[u] & 0x7f) && vc_uf_find(parent, u) == r)
                continue;
            const double *q = s->xyz + 3 * u;
            const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            attached = dot3(d, d) <= W * W;
        }
        if (!attached)
            box[6 * r] = NAN;
    }
    for (int64_t e = 0; e < ne; e++) {
        if (!keep[e])
            continue;
        const double *bx = box + 6 * vc_uf_find(parent, f->edge_vertex[2 * e]);
        double diag2 = 0;
        for (int d = 0; d < 3; d++)
            diag2 += (bx[3 + d] - bx[d]) * (bx[3 + d] - bx[d]);
        if (!(diag2 >= ROUND_EXTENT * ROUND_EXTENT * scale * scale)) { /* NaN: dropped */
            keep[e] = 0;
            continue;
        }
        f->edge_sharp[e] = VC_SHARP_ROUND;
        n_crease++;
    }
    /* 4. the band: the labelled triangles joined (across non-sharp edges,
     * through labelled triangles) to a triangle of the crease keep their
     * flank; the others go back to their own normal */
    if (n_crease > 0) {
        unsigned char *reach = calloc((size_t)(nt > 0 ? nt : 1), 1);
        int64_t *queue = malloc(sizeof *queue * (size_t)(nt > 0 ? nt : 1));
        if (!reach || !queue) {
            free(reach);
            free(queue);
            oom = 1;
            goto done;
        }
        int64_t tail = 0;
        for (int64_t e = 0; e < ne; e++)
            if (keep[e])
                for (int64_t k = f->edge_tri_start[e]; k < f->edge_tri_start[e + 1]; k++)
                    if (!reach[f->edge_tri[k]]) {
                        reach[f->edge_tri[k]] = 1;
                        queue[tail++] = f->edge_tri[k];
                    }
        for (int64_t head = 0; head < tail; head++) {
            const int64_t t = queue[head];
            for (int j = 0; j < 3; j++) {
                const int64_t g = f->tri_edge[3 * t + j];
                if (f->edge_sharp[g] || f->edge_tri_start[g + 1] - f->edge_tri_start[g] != 2)
                    continue;
                const int64_t u = f->edge_tri[f->edge_tri_start[g]] == t ? f->edge_tri[f->edge_tri_start[g] + 1]
                                                                        : f->edge_tri[f->edge_tri_start[g]];
                if (reach[u] || !labelled(label, u))
                    continue;
                reach[u] = 1;
                queue[tail++] = u;
            }
        }
        for (int64_t t = 0; t < nt; t++)
            if (!reach[t])
                label[3 * t] = label[3 * t + 1] = label[3 * t + 2] = 0;
        free(reach);
        free(queue);
        *round_normal = label;
        label = NULL;
    }
done:
    free(cand);
    free(flank);
    free(in_round);
    free(slot);
    free(label);
    free(keep);
    free(parent);
    free(box);
    free(degree);
    free(near_v);
    if (oom) {
        free(*round_normal);
        *round_normal = NULL;
        return -1;
    }
    f->n_sharp_round = n_crease;
    f->n_sharp_edges += n_crease;
    return n_crease;
}
