/* The centre lift: see centre_lift.h. */
#include "balls/centre_lift.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balls/ball_set.h"
#include "balls/triplets.h"
#include "util/closest_point.h"
#include "util/reserve.h"
#include "util/clock.h"
#include "util/threads.h"

/* checks of one attempt before it is given up */
#define MAX_ROUNDS 8
/* attempts of a pass, each with half the steps of the one before */
#define DAMPED_ATTEMPTS 3
/* checks in all: the lift's cost stays a few triplet scans */
#define MAX_CHECKS 48
/* ball sets from this size on get progress lines through the lift */
#define LARGE_LIFT 50000
/* Passes of the lift: each measures the sags of the facets as the last
 * pass left them and moves the balls by what remains. One pass removes the
 * bias to first order; where the sag is a large share of the radius of
 * curvature (thin tubes: the knot of models/make_hard_surfaces.py, -2.0%
 * of volume unlifted, -1.2% after one pass) the next ones measure the
 * facets the first could not reach and the second-order remainder (-0.26%
 * after two). */
#define MAX_PASSES 4
/* A further pass runs only while the facets' measured bias (the sum of
 * area times sag) is above this share of the volume they enclose: below it
 * the remainder is within what the sag measurement resolves, and one pass,
 * the common case, costs what it did. */
#define VOLUME_BIAS_TOL 1e-3
/* in further passes a ball moves only by more than this share of its
 * radius (fewer balls to check again) */
#define MIN_BALL_MOVE 2e-3
/* rounds in which a failing ball's lift is halved before it is removed,
 * with its neighbours' */
#define HALVING_ROUNDS 3
/* no lift beyond this fraction of the radius: the sag of a facet is a few
 * percent of it; more means the nearest input point is not the facet's */
#define MAX_LIFT 0.1
/* The input is looked for this far (of the facet's smallest radius) from
 * its edge midpoints: MAX_LIFT in the first pass, FAR_REACH in the next.
 * The sag at an edge midpoint is up to r^2 / (2 rho), a fifth of r on a
 * tube 2.5 r thick: the first pass leaves such facets (28% of a coarse
 * 12-sided tube's) out of its balls' means, the next ones measure them and
 * the bias that decides whether to go on. The first pass keeps the short
 * reach so that a surface one pass serves gets the centres it got before
 * passes existed (the OpenFOAM skew-face collapse is fragile to any
 * change of the mesh: issue 20). The other sheet of a thin part is kept
 * out by SAME_SIDE, not by the reach. */
#define SAG_REACH MAX_LIFT
#define FAR_REACH 0.3
/* only input triangles facing the facet's way (cosine) count: the other
 * sheet of a thin part is never the facet's own */
#define SAME_SIDE 0.5
/* A lifted seed may come nearer a fourth sphere (clearance d^2 / r^2 - 1)
 * than CLEAR_ENOUGH only down to NEAR_SPHERE times where it was: a seed
 * nearly on a fourth sphere makes a short Voronoi edge and a sliver facet,
 * and halving a failing lift would otherwise end right at such a
 * configuration. */
#define CLEAR_ENOUGH 2e-3
#define NEAR_SPHERE 0.5

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The nearest point of the input to p among the triangles within reach
 * whose normal faces n. */
typedef struct nearest_ctx {
    const vc_sizing *z;
    const double *p, *n;
    double best_d2;
    double q[3];
    int found;
} nearest_ctx;

static void consider(void *ctx, int kind, int64_t id)
{
    nearest_ctx *c = ctx;
    if (kind != VC_ELEM_TRIANGLE)
        return;
    const vc_sizing *z = c->z;
    if (dot3(z->tri_out_normal + 3 * id, c->n) < SAME_SIDE)
        return;
    const int64_t *t = z->s->tri + 3 * id;
    double q[3];
    double d2 = vc_closest_on_triangle(c->p, z->s->xyz + 3 * t[0], z->s->xyz + 3 * t[1],
                                       z->s->xyz + 3 * t[2], q);
    if (d2 < c->best_d2) {
        c->best_d2 = d2;
        memcpy(c->q, q, sizeof q);
        c->found = 1;
    }
}

/* The facet's unit normal (outward, by its balls' normals) and area, and
 * its mean signed distance to the input (positive: the input is outside
 * the facet), from its three edge midpoints. Returns 0 when some midpoint
 * has no input triangle near enough. */
static int facet_sag(const vc_balls *b, const vc_sizing *z, const int64_t v[3], double reach,
                     double n[3], double *area, double *sag)
{
    const double *c[3] = {b->center + 3 * v[0], b->center + 3 * v[1], b->center + 3 * v[2]};
    double u[3], w[3];
    for (int d = 0; d < 3; d++) {
        u[d] = c[1][d] - c[0][d];
        w[d] = c[2][d] - c[0][d];
    }
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    double len = sqrt(dot3(n, n));
    if (!(len > 0))
        return 0;
    double out[3] = {0, 0, 0};
    for (int m = 0; m < 3; m++)
        for (int d = 0; d < 3; d++)
            out[d] += b->normal[3 * v[m] + d];
    double s = dot3(out, n) < 0 ? -1 / len : 1 / len;
    for (int d = 0; d < 3; d++)
        n[d] *= s;
    *area = len / 2;
    double rmin = fmin(b->radius[v[0]], fmin(b->radius[v[1]], b->radius[v[2]]));
    double sum = 0;
    for (int m = 0; m < 3; m++) {
        const double *a = c[m], *e = c[(m + 1) % 3];
        double p[3] = {(a[0] + e[0]) / 2, (a[1] + e[1]) / 2, (a[2] + e[2]) / 2};
        nearest_ctx q = {z, p, n, INFINITY, {0, 0, 0}, 0};
        /* boxes farther than the nearest so far cannot hold a nearer one */
        vc_sizing_elements_near_within(z, p, reach * rmin, consider, &q, &q.best_d2);
        if (!q.found || q.best_d2 > reach * reach * rmin * rmin)
            return 0;
        double dq[3] = {q.q[0] - p[0], q.q[1] - p[1], q.q[2] - p[2]};
        sum += dot3(dq, n);
    }
    *sag = sum / 3;
    return 1;
}

/* ---------------------------------------------------------------------
 * The check: every triplet of the lifted balls. */

/* A facet: its balls (i < j < k) and the smaller clearance of its two
 * seeds from a fourth sphere (vc_triplet). */
typedef struct facet_clear {
    int64_t v[3];
    double clear;
} facet_clear;

/* Union-find over the balls: the balls of one failing configuration (a
 * half-covered pair's four balls, a facet that appeared or vanished, and
 * the facets it shares balls with) end in one group. */
static int64_t group_root(int64_t *parent, int64_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void group_join(int64_t *parent, int64_t a, int64_t b)
{
    a = group_root(parent, a);
    b = group_root(parent, b);
    if (a != b) /* the smaller index is the root: the same groups for any order */
        parent[a > b ? a : b] = a < b ? a : b;
}

typedef struct check_ctx {
    facet_clear *f;
    int64_t n, cap;
    unsigned char *bad; /* per ball */
    int64_t *group;     /* per ball: union-find parent */
    int oom;
} check_ctx;

static void on_triplet(void *ctx, const vc_triplet *t)
{
    check_ctx *c = ctx;
    int cu = t->cover_up >= 0, cd = t->cover_down >= 0;
    if (cu != cd) {
        const int64_t cover = cu ? t->cover_up : t->cover_down;
        c->bad[t->i] = c->bad[t->j] = c->bad[t->k] = c->bad[cover] = 1;
        group_join(c->group, t->i, t->j);
        group_join(c->group, t->i, t->k);
        group_join(c->group, t->i, cover);
        return;
    }
    if (cu || c->oom)
        return;
    if (vc_reserve(&c->f, &c->cap, c->n + 1, sizeof(facet_clear))) {
        c->oom = 1;
        return;
    }
    facet_clear *r = &c->f[c->n++];
    r->v[0] = t->i;
    r->v[1] = t->j;
    r->v[2] = t->k;
    r->clear = fmin(t->clear_up, t->clear_down);
}

static int cmp_facet(const void *p, const void *q)
{
    const facet_clear *a = p, *b = q;
    for (int m = 0; m < 3; m++)
        if (a->v[m] != b->v[m])
            return a->v[m] < b->v[m] ? -1 : 1;
    return 0;
}

/* Marks in bad the balls of the facets in one list only (both sorted), and
 * of the facets whose seeds came nearer a fourth sphere than NEAR_SPHERE
 * times their clearance before (or CLEAR_ENOUGH). */
static void mark_difference(const facet_clear *a, int64_t na, const facet_clear *b, int64_t nb,
                            unsigned char *bad, int64_t *group)
{
    int64_t i = 0, j = 0;
    while (i < na || j < nb) {
        int c = i == na ? 1 : j == nb ? -1 : cmp_facet(a + i, b + j);
        const facet_clear *f;
        if (c == 0) {
            f = b + j;
            int near = b[j].clear < NEAR_SPHERE * fmin(a[i].clear, CLEAR_ENOUGH);
            i++;
            j++;
            if (!near)
                continue;
        } else {
            f = c < 0 ? a + i++ : b + j++;
        }
        bad[f->v[0]] = bad[f->v[1]] = bad[f->v[2]] = 1;
        group_join(group, f->v[0], f->v[1]);
        group_join(group, f->v[0], f->v[2]);
    }
}

/* The facets of the set bs as it is now, sorted, into *got (replacing
 * what it held), and in bad the balls of half-covered pairs and, when ref
 * is not NULL, of the facets that differ from ref's (mark_difference).
 * full: every triplet; otherwise only those around the balls moved since
 * the last scan, the facets of the other balls kept from *got (scanned:
 * n bytes of scratch). A half-covered pair is always around a moved ball:
 * the balls of the last check's pairs all move, and with all four balls
 * of a pair where they were sampled it is not half covered.
 * Returns the number of balls marked, or -1 when out of memory. */
static int64_t check(vc_ball_set *bs, int full, const facet_clear *ref, int64_t n_ref,
                     int threads, unsigned char *bad, int64_t *group, unsigned char *scanned,
                     facet_clear **got, int64_t *n_got)
{
    const int64_t n = bs->b.n;
    memset(bad, 0, (size_t)n);
    for (int64_t i = 0; i < n; i++)
        group[i] = i;
    check_ctx c = {NULL, 0, 0, bad, group, 0};
    int rc = full ? vc_triplets_scan_all(bs, threads, on_triplet, &c)
                  : vc_triplets_scan_changed(bs, threads, on_triplet, &c, scanned);
    if (!rc && !c.oom && !full) {
        /* a facet is found from its smallest ball */
        int64_t keep = 0;
        for (int64_t q = 0; q < *n_got; q++)
            keep += !scanned[(*got)[q].v[0]];
        facet_clear *f = realloc(c.f, sizeof(facet_clear) * (size_t)(c.n + keep + 1));
        if (!f)
            c.oom = 1;
        else {
            c.f = f;
            for (int64_t q = 0; q < *n_got; q++)
                if (!scanned[(*got)[q].v[0]])
                    c.f[c.n++] = (*got)[q];
        }
    }
    if (rc || c.oom) {
        free(c.f);
        return -1;
    }
    if (c.n > 0)
        qsort(c.f, (size_t)c.n, sizeof(facet_clear), cmp_facet);
    if (ref)
        mark_difference(ref, n_ref, c.f, c.n, bad, group);
    free(*got);
    *got = c.f;
    *n_got = c.n;
    int64_t n_bad = 0;
    for (int64_t i = 0; i < n; i++)
        n_bad += bad[i];
    return n_bad;
}

/* The facets' volume bias, the sum of area times sag (fn, fok: per facet
 * normal, area, sag), over the volume they enclose (positive: the facets
 * enclose too little). */
static double volume_bias(const vc_balls *b, const int64_t *facet_v, int64_t n_facets,
                          const double *fn, const unsigned char *fok)
{
    const double *o = b->center; /* the origin of the volume's cones */
    double bias = 0, vol = 0;
    for (int64_t t = 0; t < n_facets; t++) {
        if (!fok[t])
            continue;
        const double *g = fn + 5 * t, *c = b->center + 3 * facet_v[3 * t];
        const double rel[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
        vol += g[3] * dot3(g, rel) / 3;
        bias += g[3] * g[4];
    }
    return vol > 0 ? bias / vol : 0;
}

/* Each surface ball's next move, into lift: the area-weighted mean of its
 * facets' sags (fn, fok) along their area-weighted normal, the ball's whole
 * move from orig capped at MAX_LIFT of its radius; moves below min_move of
 * the radius are left out. Returns the number of balls that move. acc: 5 n
 * doubles of scratch. */
static int64_t ball_lifts(const vc_balls *b, const double *orig, const int64_t *facet_v,
                          int64_t n_facets, const double *fn, const unsigned char *fok,
                          double min_move, double *acc, double *lift)
{
    int64_t moved = 0;
    const int64_t n = b->n;
    memset(acc, 0, sizeof(double) * 5 * (size_t)n);
    memset(lift, 0, sizeof(double) * 3 * (size_t)n);
    for (int64_t t = 0; t < n_facets; t++) {
        if (!fok[t])
            continue;
        const double *g = fn + 5 * t;
        for (int m = 0; m < 3; m++) {
            double *a = acc + 5 * facet_v[3 * t + m];
            for (int d = 0; d < 3; d++)
                a[d] += g[3] * g[d];
            a[3] += g[3];
            a[4] += g[3] * g[4];
        }
    }
    for (int64_t i = 0; i < n; i++) {
        const double *a = acc + 5 * i;
        double len = sqrt(dot3(a, a));
        if (b->kind[i] != VC_BALL_SURFACE || !(a[3] > 0) || !(len > 0))
            continue;
        const double h = a[4] / a[3], rmax = MAX_LIFT * b->radius[i];
        double so_far[3], to[3], to2 = 0;
        for (int d = 0; d < 3; d++) {
            so_far[d] = b->center[3 * i + d] - orig[3 * i + d];
            lift[3 * i + d] = h * a[d] / len;
            to[d] = so_far[d] + lift[3 * i + d];
            to2 += to[d] * to[d];
        }
        if (to2 > rmax * rmax) {
            const double scale = rmax / sqrt(to2);
            for (int d = 0; d < 3; d++)
                lift[3 * i + d] = scale * to[d] - so_far[d];
        }
        const double l2 = dot3(lift + 3 * i, lift + 3 * i);
        if (l2 > 0 && sqrt(l2) >= min_move * b->radius[i])
            moved++;
        else
            memset(lift + 3 * i, 0, sizeof(double) * 3);
    }
    return moved;
}

/* After a failed check, first the balls of each failing group (check)
 * whose balls all fail for the first time and may all move (surface balls)
 * move together, by the mean of their lifts: a translation keeps the
 * configuration among them as sampled, and the configurations that fail
 * are near-quartets of balls, whose seed nearly lies on a fourth sphere:
 * a relative move of a thousandth of the radius turns them over, while the
 * lifts are a smooth field, nearly the same for four neighbours. Halving
 * such lifts instead removed most of them on tubes a few balls thick
 * (a capped cylinder of radius 10 error bounds: -2.5% of volume after the
 * lift, -3.1% before). Otherwise, or when a moved group fails again, the
 * lift of every ball marked bad is halved; after HALVING_ROUNDS halvings it
 * is removed with that of its facet neighbours; a ball without lift that
 * fails halves its neighbours' lifts. acc: 4 n doubles of scratch. */
static void reduce_lifts(const vc_balls *b, int64_t n, const int64_t *facet_v, int64_t n_facets,
                         const unsigned char *bad, int64_t *group, unsigned char *strikes,
                         double *lift, double *acc)
{
    unsigned char *drop = strikes; /* bit 7: this round's neighbourhood drop */
    /* per group root: the sum of the lifts, and the ball count, or -1 when
     * a ball of the group has failed before or may not move */
    memset(acc, 0, sizeof(double) * 4 * (size_t)n);
    for (int64_t i = 0; i < n; i++) {
        if (!bad[i])
            continue;
        double *a = acc + 4 * group_root(group, i);
        if (strikes[i] != 0 || b->kind[i] != VC_BALL_SURFACE)
            a[3] = -1;
        if (a[3] < 0)
            continue;
        for (int d = 0; d < 3; d++)
            a[d] += lift[3 * i + d];
        a[3] += 1;
    }
    for (int64_t i = 0; i < n; i++) {
        if (!bad[i])
            continue;
        strikes[i] = (unsigned char)((strikes[i] & 0x7f) + 1);
        const double *a = acc + 4 * group_root(group, i);
        if (a[3] > 1) {
            for (int d = 0; d < 3; d++)
                lift[3 * i + d] = a[d] / a[3];
        } else if ((strikes[i] & 0x7f) > HALVING_ROUNDS + 1)
            drop[i] |= 0x80;
        else
            for (int d = 0; d < 3; d++)
                lift[3 * i + d] /= 2;
    }
    for (int64_t t = 0; t < n_facets; t++) {
        const int64_t *v = facet_v + 3 * t;
        if ((drop[v[0]] | drop[v[1]] | drop[v[2]]) & 0x80)
            for (int m = 0; m < 3; m++)
                memset(lift + 3 * v[m], 0, sizeof(double) * 3);
    }
    for (int64_t i = 0; i < n; i++)
        drop[i] &= 0x7f;
    for (int64_t t = 0; t < n_facets; t++) {
        const int64_t *v = facet_v + 3 * t;
        for (int m = 0; m < 3; m++) {
            const double *l = lift + 3 * v[m];
            if (bad[v[m]] && l[0] == 0 && l[1] == 0 && l[2] == 0)
                for (int k = 1; k < 3; k++)
                    for (int d = 0; d < 3; d++)
                        lift[3 * v[(m + k) % 3] + d] /= 2;
        }
    }
}

int vc_lift_centres(vc_balls *b, const int64_t *facet_v, const double *facet_clearance,
                    int64_t n_facets, const vc_sizing *z, int threads, const vc_logger *log,
                    vc_lift_result *res)
{
    const double t0 = vc_clock_seconds();
    /* a line before each stage that can take seconds on a large ball set
     * (a 169,000-ball cup was silent for 4 s here), then at most every 2 s */
    double t_line = t0;
    memset(res, 0, sizeof *res);
    const int64_t n = b->n;
    if (n == 0 || n_facets == 0)
        return 0;
    const int large = n >= LARGE_LIFT;
    if (large)
        vc_log(log, VC_LOG_INFO, "mesh: centre lift of %lld balls: the seeds as sampled",
               (long long)n);
    threads = vc_threads_or_default(threads);
    double *fn = malloc(sizeof(double) * 5 * (size_t)n_facets); /* normal, area, sag */
    unsigned char *fok = malloc((size_t)n_facets);
    double *acc = calloc((size_t)n, sizeof(double) * 5); /* area * normal, area, area * sag */
    double *lift = calloc((size_t)n, sizeof(double) * 3);
    double *step = calloc((size_t)n, sizeof(double) * 3);
    double *xyz = malloc(sizeof(double) * 3 * (size_t)n);
    unsigned char *bad = malloc((size_t)n);
    int64_t *group = malloc(sizeof(int64_t) * (size_t)n);
    unsigned char *strikes = calloc((size_t)n, 1);
    unsigned char *scanned = malloc((size_t)n);
    unsigned char *reduced = calloc((size_t)n, 1);
    double *orig = malloc(sizeof(double) * 3 * (size_t)n);
    vc_ball_set bs;
    int have_set = 0;
    facet_clear *ref = NULL, *got = NULL;
    int64_t n_ref = 0, n_got = 0;
    int rc = 0;
    if (!fn || !fok || !acc || !lift || !step || !xyz || !bad || !group || !strikes || !scanned || !reduced ||
        !orig) {
        rc = -1;
        goto done;
    }

    memcpy(orig, b->center, sizeof(double) * 3 * (size_t)n);

    /* the facets as sampled, with their seeds' clearances: every pass is
     * checked against these, so passes cannot compound their tolerances */
    if (vc_ball_set_build(&bs, b, NULL)) {
        rc = -1;
        goto done;
    }
    have_set = 1;
    if (facet_clearance) {
        ref = malloc(sizeof(facet_clear) * (size_t)n_facets);
        if (!ref) {
            rc = -1;
            goto done;
        }
        for (int64_t t = 0; t < n_facets; t++) {
            memcpy(ref[t].v, facet_v + 3 * t, sizeof ref[t].v);
            ref[t].clear = facet_clearance[t];
        }
        n_ref = n_facets;
        qsort(ref, (size_t)n_ref, sizeof(facet_clear), cmp_facet);
    } else if (check(&bs, 1, NULL, 0, threads, bad, group, scanned, &ref, &n_ref) < 0) {
        rc = -1;
        goto done;
    }
    int full_scan = 1;
    for (int pass = 1; pass <= MAX_PASSES; pass++) {
        /* every facet's sag, as the centres are now, independently (so any
         * thread count gives the same) */
        if (large && vc_clock_seconds() - t_line >= 1.0) {
            t_line = vc_clock_seconds();
            vc_log(log, VC_LOG_INFO, "mesh: centre lift, pass %d: the sags of %lld facets, %.0f s",
                   pass, (long long)n_facets, t_line - t0);
        }
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256)
        for (int64_t t = 0; t < n_facets; t++)
            fok[t] = (unsigned char)facet_sag(b, z, facet_v + 3 * t, pass > 1 ? FAR_REACH : SAG_REACH,
                                              fn + 5 * t, fn + 5 * t + 3, fn + 5 * t + 4);
        if (pass > 1 && fabs(volume_bias(b, facet_v, n_facets, fn, fok)) < VOLUME_BIAS_TOL)
            break;
        if (ball_lifts(b, orig, facet_v, n_facets, fn, fok, pass > 1 ? MIN_BALL_MOVE : 0, acc,
                       step) == 0)
            break;
        /* a pass that does not hold is tried again with its steps damped */
        int held = 0;
        double damping = 1;
        for (int attempt = 0; attempt < DAMPED_ATTEMPTS && !held; attempt++, damping /= 2) {
            for (int64_t i = 0; i < 3 * n; i++)
                lift[i] = damping * step[i];
            memset(strikes, 0, (size_t)n);
            for (int round = 1; round <= MAX_ROUNDS && res->rounds < MAX_CHECKS; round++) {
                for (int64_t i = 0; i < 3 * n; i++)
                    xyz[i] = b->center[i] + lift[i];
                /* every ball moves for the first check; later only those
                 * whose lift changed, and the check looks only around them */
                for (int64_t i = 0; i < n; i++)
                    if (memcmp(xyz + 3 * i, bs.b.center + 3 * i, sizeof(double) * 3) != 0)
                        vc_ball_set_move(&bs, i, xyz + 3 * i);
                int64_t n_bad =
                    check(&bs, full_scan, ref, n_ref, threads, bad, group, scanned, &got, &n_got);
                full_scan = 0;
                if (n_bad < 0) {
                    rc = -1;
                    goto done;
                }
                res->rounds++;
                if (vc_clock_seconds() - t_line >= 2.0 || (large && vc_clock_seconds() - t_line >= 1.0)) {
                    t_line = vc_clock_seconds();
                    vc_log(log, VC_LOG_INFO,
                           "mesh: centre lift, pass %d, check %d: %lld balls to reduce, %.0f s",
                           pass, res->rounds, (long long)n_bad, vc_clock_seconds() - t0);
                }
                if (n_bad == 0) {
                    held = 1;
                    break;
                }
                reduce_lifts(b, n, facet_v, n_facets, bad, group, strikes, lift, acc);
                for (int64_t i = 0; i < n; i++)
                    reduced[i] |= strikes[i] != 0;
            }
        }
        if (!held) {
            /* this pass never held: the centres as the last pass left them */
            if (pass == 1)
                res->dropped = 1;
            break;
        }
        memcpy(b->center, xyz, sizeof(double) * 3 * (size_t)n);
        res->passes = pass;
    }
    double sum = 0, mx = 0;
    for (int64_t i = 0; i < n; i++) {
        double dv[3] = {b->center[3 * i] - orig[3 * i], b->center[3 * i + 1] - orig[3 * i + 1],
                        b->center[3 * i + 2] - orig[3 * i + 2]};
        double l = sqrt(dot3(dv, dv)) / b->radius[i];
        if (l > 0) {
            res->n_lifted++;
            sum += l;
            mx = fmax(mx, l);
        }
        res->n_reduced += reduced[i];
    }
    res->mean_rel = res->n_lifted ? sum / (double)res->n_lifted : 0;
    res->max_rel = mx;
done:
    free(fn);
    free(fok);
    free(acc);
    free(lift);
    free(step);
    free(xyz);
    free(bad);
    free(group);
    free(strikes);
    free(scanned);
    free(reduced);
    free(orig);
    if (have_set)
        vc_ball_set_free(&bs);
    free(ref);
    free(got);
    return rc;
}
