/* Recursive maximal Poisson-disk sampling of the surface (thesis 6.2.4 to
 * 6.2.9): corner balls, then edge balls on every crease, then surface balls
 * on every patch; the local Lipschitz condition on the radii; sliver
 * elimination; and, after every shrinking, sampling again around the
 * shrunk balls until the surface is covered and no seed pair is half
 * covered. Then, a few times, the balls that make the flattest facets
 * of the reconstructed surface are shrunk a little and the same loop
 * runs again (unflatten_facets).
 *
 * Coverage rules (6.2.4, 6.2.5): a point of a stratum of dimension k is
 * covered when a ball of a lower dimension holds it, or a ball of the same
 * dimension holds it alpha-deeply (within (1 - alpha) r). Balls of higher
 * dimension never hold it: their radius keeps them 0.49 times their
 * distance away from every lower stratum. The first coverage and its
 * Lipschitz fixes ask for alpha-deep coverage; once sliver elimination (or
 * a pass after it) has shrunk balls, the sampling around them asks for
 * alpha / 2 (6.2.7: a ball set whose points are alpha'-deeply covered,
 * alpha' < alpha, is accepted after shrinking): a shrunk ball still holds
 * most of its old ground that deeply, and only what it gave up below that
 * is sampled again, where alpha-deep coverage sampled the whole ring it
 * lost again (cow.off: 45,252 balls before, 39,263 now).
 *
 * Radius of a new sample p (6.2.3, 6.2.6): min(sz, 0.49 |p - q*|,
 * min_q (r_q + L |p - q|)), q* the nearest element not co-smooth with p,
 * and capped by the approximation-error criterion (sizing/sizing.h); if an existing centre q lies alpha-deeply inside, p is
 * dropped with probability 0.1 and otherwise r_p is cut to
 * |p - q| / (1 - alpha) (density regulation and the spacing part of C4). */
#include "vorocrust/sampling.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "balls/ball_estimate.h"
#include "balls/ball_set.h"
#include "balls/centre_lift.h"
#include "balls/triplets.h"
#include "balls/union_cover.h"
#include "util/closest_point.h"
#include "util/csr_group.h"
#include "util/progress.h"
#include "util/reserve.h"
#include "util/small_sort.h"
#include "sizing/sizing.h"
#include "sizing/smooth_surface.h"
#include "vorocrust/random.h"
#include "vorocrust/quality.h"
#include "util/threads.h"
#include "util/clock.h"

#define MAX_MISSES 100
/* Darts are drawn in batches of DART_BATCH: drawn in order, their first
 * coverage test in parallel (against the balls there before the batch),
 * then taken in order, each also tested against the balls the batch has
 * added so far. The batch is fixed, not the thread count's: the darts and
 * the balls are the same for any thread count. A batch is cut short when
 * MAX_MISSES darts in a row miss (the rest are not used). */
#define DART_BATCH 256
#define KEEP_WHOLE 100.0 /* see mps */
#define PARENT_BATCH 16384 /* subfaces split at a time before their children are tested */
/* A shrunk ball leaves the point it uncovers this far outside (relative to
 * its distance). Cut only to the point (1e-7 before session 14), the four
 * spheres of the quartet still nearly meet there: the seeds of its
 * triplets nearly coincide, the Voronoi vertices between them make edges
 * of 1e-9 of the radius and facets of quality 0 (fandisk.off), and the
 * next pass finds the same quartet half covered again (fandisk.off at 60
 * degrees: 54 passes at 1e-7, 13 at 1e-3, 8 at 1e-2). */
#define SHRINK_MARGIN 1e-2
/* Flat facets (see unflatten_facets): the quality below which a facet is
 * worked on (the top of the thesis' 0.37 to 0.40 on smooth models), the
 * largest cut of a radius for it, how far inside the covering ball the
 * removed facet's seeds must end up (relative to its radius, away from
 * four co-spherical balls and their near-zero facets), and how many
 * passes. */
#define FLAT_Q 0.40
#define FLAT_MAX_SHRINK 0.2
#define FLAT_SEED_DEPTH 0.01
#define FLAT_PASSES 3
/* ball sets from this size on say when they scan every triplet again */
#define LARGE_SCAN 50000
/* A ball shrunk below this share of the error bound follows the surface at
 * a scale far finer than the accuracy asked: only a point where the sizing
 * has no lower bound, or a fold judged noise that sliver elimination cannot
 * follow, drives balls there, shrinking them further at every pass, each pass
 * dearer than the last (a marching-cubes blob with Perlin noise of
 * frequency 11: balls of 7e-9 of the bound after ten passes, the last ones
 * 10 to 20 s each, before the pair counts said it diverged). The sampling
 * stops there as not converging. The smallest ball of the converging
 * samplings of 60 surfaces (the shared models, make_hard_surfaces.py) is
 * 3e-3 of the bound (cow.off), the rest above 7e-3. */
#define TINY_BALL 1e-5
/* A sampling that makes this many times the balls the sizing predicted
 * (and at least RUNAWAY_MIN) does not converge either: on 60 surfaces the
 * balls made were 0.34 to 3.3 times the prediction, while a decimated
 * shaft's first coverage went on adding balls where the area was covered,
 * 638,000 for 12,400 predicted after 300 s, slower and slower, far from
 * the ball limit. Stopped there, it is said as a divergence (where its
 * smallest ball is), and the mesh command's remedies follow. */
#define RUNAWAY 20.0
#define RUNAWAY_MIN 100000
/* subfaces whose midpoints lie this close to S' (times the kernel width)
 * are subdivided without projecting them */
#define SAG_TOLERANCE 1e-2
/* ... and darts on them are centres without projection below this */
#define ACCURATE_SAG 1e-6
/* a subface below SEAM_SIZE kernel widths whose image on S' is SEAM_STRETCH
 * times larger straddles a seam of the projection */
#define SEAM_SIZE 1e-2
#define SEAM_STRETCH 10.0
/* subfaces below MIN_SUBFACE kernel widths are left (on_seam) */
#define MIN_SUBFACE 1e-4

typedef struct subface {
    double v[9];   /* a segment (v[0..5]) or a triangle, on the input */
    int64_t elem;  /* the sharp edge or triangle */
} subface;

/* A triangle subface on the smooth surface S' (sampled with
 * opt.smooth_width): its corners there, which the coverage tests use. */
typedef struct subface_on_smooth {
    double p[9];   /* the corners on S' */
    double pn[9];  /* S's unit normals there */
    double sag;    /* how far the midpoints of p's edges may lie from S' (the last
                      projections' corrections; interpolated corners keep it) */
    unsigned char todo; /* bit m: corner m is a first guess, not yet projected */
    unsigned char interpolated; /* some corner is a midpoint never projected */
    unsigned char blended; /* some corner is where S' blends into the input: never
                              interpolated (the darts are projections of points of
                              the input, and so must the corners be) */
} subface_on_smooth;

/* Subfaces; g (the same indices) only for triangles on S'. */
typedef struct pool {
    subface *f;
    subface_on_smooth *g;
    int64_t n, cap;
    int smooth;
} pool;

typedef struct sampler {
    const vc_surface *s;
    const vc_features *f;
    vc_sampling_options opt;
    double alpha;      /* the deep-coverage constant of new balls' spacing (alpha / 2 in the
                          safe mode) */
    double cover_alpha; /* ... and of the coverage tests: alpha until sliver elimination
                           shrinks balls, alpha / 2 from then on (top of the file) */
    double sz;
    vc_sizing z;
    vc_ball_set bs;
    vc_rng rng;
    vc_sampling_stats *st;
    int oom;
    /* balls added or shrunk by sliver elimination since the last Lipschitz
     * pass: only they can constrain other radii */
    unsigned char *dirty;
    int64_t dirty_cap;
    int threads;        /* for the parallel parts (OpenMP's default when opt.threads <= 0) */
    int too_many;       /* the ball count reached opt.max_balls */
    int64_t runaway_at; /* RUNAWAY times the balls predicted (0: no check) */
    int runaway;        /* ... reached: the sampling does not converge */
    const char *phase;  /* for the progress lines */
    vc_smooth_surface ss; /* S', when opt.smooth_width > 0 */
    int smooth;         /* centres of surface balls on S' */
    double *tri_on_smooth; /* 19 per triangle: its corners on S', S's normals there, and
                              1 when some corner is in the blend into the input */
    double t_start, t_logged;
    /* While sampling again after balls shrank: those balls at their old
     * radii. Everything outside them was covered before and still is
     * (balls only grow in number and shrink), so a subface that misses
     * all of them needs no test and no darts. NULL in the first coverage. */
    const vc_ball_set *lost;
} sampler;

static int mark_dirty(sampler *S, int64_t i)
{
    if (i >= S->dirty_cap) {
        int64_t c = S->dirty_cap ? 2 * S->dirty_cap : 4096;
        while (c <= i)
            c *= 2;
        unsigned char *q = realloc(S->dirty, (size_t)c);
        if (!q)
            return -1;
        memset(q + S->dirty_cap, 0, (size_t)(c - S->dirty_cap));
        S->dirty = q;
        S->dirty_cap = c;
    }
    S->dirty[i] = 1;
    return 0;
}

static double dist(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static int pool_push(pool *P, const subface *sf, const subface_on_smooth *sg)
{
    if (P->n == P->cap) {
        int64_t c = P->cap ? 2 * P->cap : 1024;
        subface *q = realloc(P->f, sizeof(subface) * (size_t)c);
        if (!q)
            return -1;
        P->f = q;
        if (P->smooth) {
            subface_on_smooth *r = realloc(P->g, sizeof(subface_on_smooth) * (size_t)c);
            if (!r)
                return -1;
            P->g = r;
        }
        P->cap = c;
    }
    if (P->smooth)
        P->g[P->n] = *sg;
    P->f[P->n++] = *sf;
    return 0;
}

/* ---------------------------------------------------------------------
 * Coverage */

typedef struct cover_ctx {
    const vc_balls *b;
    const double *x;
    int kind;          /* the stratum's dimension */
    double deep;       /* 1 - alpha */
} cover_ctx;

static int covers_point(void *ctx, int64_t i)
{
    cover_ctx *c = ctx;
    int k = c->b->kind[i];
    if (k > c->kind)
        return 0;
    double d = dist(c->b->center + 3 * i, c->x);
    double r = c->b->radius[i];
    return k < c->kind ? d < r : d <= c->deep * r;
}

static int point_covered(const sampler *S, const double x[3], int kind)
{
    cover_ctx c = {&S->bs.b, x, kind, 1 - S->cover_alpha};
    return vc_ball_set_query(&S->bs, x, 0, 1.0, 0.0, covers_point, &c);
}

typedef struct subface_cover_ctx {
    const vc_balls *b;
    const double *v;
    int nv;
    int kind;
    double deep;
    double margin; /* how far the corners may be from S' (0 on the input) */
    const double *centre; /* the corners' centroid */
    double reach;         /* ... and the largest distance from it to a corner */
    int64_t found;        /* the covering ball */
    /* the balls that meet the subface, for the union test (their centres
     * and radii as the coverage rules count them) */
    int n_cand, overflow;
    double cand_c[3 * VC_UNION_COVER_MAX], cand_r[VC_UNION_COVER_MAX];
    int64_t cand_id[VC_UNION_COVER_MAX];
} subface_cover_ctx;

/* The radius ball i covers a point of the stratum with: its own for a
 * lower stratum, alpha-deeply for the same one, none (negative) for a
 * higher one. */
static inline double cover_radius(const vc_balls *b, int64_t i, int kind, double deep)
{
    const int k = b->kind[i];
    return k > kind ? -1.0 : b->radius[i] * (k < kind ? 1.0 : deep);
}

static inline double dist2(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

/* Does ball i hold every corner? */
static int holds_corners(const subface_cover_ctx *c, int64_t i, double r)
{
    for (int m = 0; m < c->nv; m++)
        if (dist(c->b->center + 3 * i, c->v + 3 * m) > r)
            return 0;
    return 1;
}

/* Stops at a ball that holds the whole subface; lists the others that
 * meet it. */
static int covers_subface(void *ctx, int64_t i)
{
    subface_cover_ctx *c = ctx;
    const double r0 = cover_radius(c->b, i, c->kind, c->deep);
    if (r0 < 0)
        return 0;
    const double r = r0 + c->margin;
    const double far = r + c->reach;
    if (dist2(c->b->center + 3 * i, c->centre) >= far * far)
        return 0; /* misses the subface's bounding ball */
    if (holds_corners(c, i, r)) {
        c->found = i;
        return 1;
    }
    /* A ball that misses the piece itself takes no part in covering it
     * (its power cell holds no covered point of it), however near the
     * bounding ball: a long, thin piece (the needle triangles of a coarse
     * cylinder, split along their length) has a bounding ball far wider
     * than itself, and the balls it caught filled the union test's places
     * or made it cost up to 32 x 31 clippings, to no avail: a 92-triangle
     * rod (20 long, radius 0.1) spent 60% of its 9.4 s of surface coverage
     * there, 6.7 s with this test. */
    const double *ci = c->b->center + 3 * i;
    const double d2 = c->nv == 3 ? vc_closest_on_triangle(ci, c->v, c->v + 3, c->v + 6, NULL)
                                 : vc_closest_on_segment(ci, c->v, c->v + 3, NULL);
    if (!(d2 < r * r))
        return 0;
    if (c->n_cand == VC_UNION_COVER_MAX) {
        c->overflow = 1;
        return 0;
    }
    memcpy(c->cand_c + 3 * c->n_cand, c->b->center + 3 * i, 3 * sizeof(double));
    c->cand_id[c->n_cand] = i;
    c->cand_r[c->n_cand++] = r;
    return 0;
}

/* The corners the coverage tests use (on S' when sampled there), their
 * centroid c and the largest distance from c to a corner; returns the
 * corners. */
static const double *subface_bound(const subface *sf, const subface_on_smooth *sg, int nv,
                                   double c[3], double *reach)
{
    const double *v = sg ? sg->p : sf->v;
    c[0] = c[1] = c[2] = 0;
    for (int m = 0; m < nv; m++)
        for (int d = 0; d < 3; d++)
            c[d] += v[3 * m + d] / nv;
    *reach = 0;
    for (int m = 0; m < nv; m++)
        *reach = fmax(*reach, dist(c, v + 3 * m));
    return v;
}

/* The coverage test of a subface set up: its corners (on S' when sampled
 * there), their bounding ball and margin; no ball found yet. */
static void subface_test_init(const sampler *S, const subface *sf, const subface_on_smooth *sg,
                              int nv, int kind, subface_cover_ctx *cc, double c[3])
{
    double reach;
    cc->v = subface_bound(sf, sg, nv, c, &reach);
    cc->b = &S->bs.b;
    cc->nv = nv;
    cc->kind = kind;
    cc->deep = 1 - S->cover_alpha;
    /* corners placed between projected ones lie off S' by about the sag:
     * they count as covered that much further out, or the darts (on S')
     * and the subfaces would disagree at the edges of the coverage */
    cc->margin = sg && sg->interpolated ? sg->sag : 0;
    cc->centre = c;
    cc->reach = reach;
    cc->found = -1;
    cc->n_cand = cc->overflow = 0;
}

/* Subfaces come in runs of neighbours (a face's children, triangles in
 * mesh order): the ball that covered the last one often covers this one
 * too, and trying it first skips most queries. The answer (is the subface
 * covered?) does not depend on which ball is found. */
static int last_cover_holds(const subface_cover_ctx *cc, int64_t last)
{
    if (last < 0 || last >= cc->b->n)
        return 0;
    const double r = cover_radius(cc->b, last, cc->kind, cc->deep);
    return r >= 0 && holds_corners(cc, last, r + cc->margin);
}

/* After the balls meeting the subface were listed (none holds it whole):
 * is it inside their union? The balls go to the test in the order of
 * their indices, so that its rounding does not depend on the order they
 * were found in (a query's cells, or a group's list). */
static int union_covered(subface_cover_ctx *cc)
{
    if (cc->overflow || cc->n_cand < 2)
        return 0;
    for (int a = 1; a < cc->n_cand; a++) {
        const int64_t id = cc->cand_id[a];
        const double r = cc->cand_r[a], x = cc->cand_c[3 * a], y = cc->cand_c[3 * a + 1],
                     z = cc->cand_c[3 * a + 2];
        int b = a;
        for (; b > 0 && cc->cand_id[b - 1] > id; b--) {
            cc->cand_id[b] = cc->cand_id[b - 1];
            cc->cand_r[b] = cc->cand_r[b - 1];
            memcpy(cc->cand_c + 3 * b, cc->cand_c + 3 * (b - 1), 3 * sizeof(double));
        }
        cc->cand_id[b] = id;
        cc->cand_r[b] = r;
        cc->cand_c[3 * b] = x;
        cc->cand_c[3 * b + 1] = y;
        cc->cand_c[3 * b + 2] = z;
    }
    return vc_union_covers(cc->v, cc->nv, cc->cand_c, cc->cand_r, cc->n_cand);
}

/* Is the whole subface covered: by one ball (balls are convex), or else by
 * the union of the balls that meet it (union_cover.h)? */
static int subface_covered(const sampler *S, const subface *sf, const subface_on_smooth *sg,
                           int nv, int kind, int64_t *last_cover)
{
    double c[3];
    subface_cover_ctx cc;
    subface_test_init(S, sf, sg, nv, kind, &cc, c);
    if (last_cover_holds(&cc, *last_cover))
        return 1;
    /* A ball meeting the subface has its centre within its radius (plus
     * the margin) of the subface's bounding ball. One that holds it has a
     * radius of at least reach / 2; the union test takes no smaller ones
     * either (fewer balls can only find less covered: such a subface is
     * split, and its children see them), which keeps the query to a few
     * cells per level. */
    if (vc_ball_set_query(&S->bs, c, cc.reach + cc.margin, 1.0, 0.5 * cc.reach, covers_subface,
                          &cc)) {
        *last_cover = cc.found;
        return 1;
    }
    return union_covered(&cc);
}

/* Neighbouring subfaces of similar size are tested as a group: one query
 * lists the balls that can meet any of them, and each subface reads that
 * list, taking the balls its own query would take (a level whose radii
 * reach half its bounding radius: vc_ball_set_query's rule) through the
 * same callback, so each answer is its own query's. A query was a
 * microsecond, most of it memory latency over the index's levels and
 * cells (cow.off: 1.5 million of them); a list of a few dozen balls,
 * read by each subface of the group, stays in cache. The list holds
 * every ball any subface's query would call back: the group's bounding
 * ball holds each subface's (grown by its margin), and it reads every
 * level the subface with the smallest radius needs. */
#define GROUP_MAX 32
/* a group's bounding radius at most this many times its smallest
 * subface's (the list then holds few balls that subface cannot use) */
#define GROUP_SPREAD 6.0

typedef struct id_list {
    int64_t *id;
    int64_t n, cap;
    int oom;
} id_list;

static int collect_id(void *ctx, int64_t i)
{
    id_list *l = ctx;
    if (vc_reserve(&l->id, &l->cap, l->n + 1, sizeof(int64_t))) {
        l->oom = 1;
        return 1; /* stop: the caller sees oom */
    }
    l->id[l->n++] = i;
    return 0;
}

/* A group of subfaces being formed: their tests (set up by
 * subface_test_init; one slot more for the subface that may join), their
 * places in the pool, and the box of their bounding balls (grown by their
 * margins) and their smallest bounding radius. */
typedef struct subface_group {
    int n;
    subface_cover_ctx t[GROUP_MAX + 1];
    double centre[GROUP_MAX + 1][3];
    int64_t member[GROUP_MAX];
    double lo[3], hi[3], min_reach;
} subface_group;

/* Does the subface in slot g->n fit the group (at most GROUP_MAX, and its
 * bounding radius at most GROUP_SPREAD times the smallest)? */
static int group_fits(const subface_group *g)
{
    const subface_cover_ctx *t = &g->t[g->n];
    const double e = t->reach + t->margin, mn = fmin(g->min_reach, t->reach);
    double r2 = 0;
    for (int d = 0; d < 3; d++) {
        const double lo = fmin(g->lo[d], t->centre[d] - e), hi = fmax(g->hi[d], t->centre[d] + e);
        r2 += 0.25 * (hi - lo) * (hi - lo);
    }
    return g->n < GROUP_MAX && r2 <= GROUP_SPREAD * GROUP_SPREAD * mn * mn;
}

/* Takes the subface in slot g->n (pool index i) into the group. */
static void group_add(subface_group *g, int64_t i)
{
    const subface_cover_ctx *t = &g->t[g->n];
    const double e = t->reach + t->margin;
    for (int d = 0; d < 3; d++) {
        g->lo[d] = fmin(g->n ? g->lo[d] : INFINITY, t->centre[d] - e);
        g->hi[d] = fmax(g->n ? g->hi[d] : -INFINITY, t->centre[d] + e);
    }
    g->min_reach = g->n ? fmin(g->min_reach, t->reach) : t->reach;
    g->member[g->n++] = i;
}

/* The group's subfaces tested with one listing query (their tests take
 * their balls): covered[q] for each; the last covering ball kept in *last
 * as subface_covered does.
 * Returns 0, or -1 when out of memory. */
static int group_covered(const sampler *S, subface_group *g, unsigned char *covered,
                         int64_t *last, id_list *list)
{
    double C[3], R2 = 0;
    for (int d = 0; d < 3; d++) {
        C[d] = 0.5 * (g->lo[d] + g->hi[d]);
        R2 += 0.25 * (g->hi[d] - g->lo[d]) * (g->hi[d] - g->lo[d]);
    }
    /* grown far above the rounding: the list must hold every ball any of
     * the subfaces' own queries would call back */
    const double R = sqrt(R2) * (1 + 1e-6), min_r = 0.5 * g->min_reach;
    list->n = 0;
    vc_ball_set_query(&S->bs, C, R, 1.0, min_r, collect_id, list);
    if (list->oom)
        return -1;
    const vc_ball_set *bs = &S->bs;
    for (int q = 0; q < g->n; q++) {
        subface_cover_ctx *cc = &g->t[q];
        if (last_cover_holds(cc, *last)) {
            covered[q] = 1;
            continue;
        }
        const double need = 0.5 * cc->reach;
        int found = 0;
        for (int64_t m = 0; m < list->n && !found; m++) {
            const int64_t i = list->id[m];
            /* the levels the subface's own query reads */
            if (bs->scale[bs->level[i] + 1] < need)
                continue;
            found = covers_subface(cc, i);
        }
        if (found) {
            *last = cc->found;
            covered[q] = 1;
        } else
            covered[q] = (unsigned char)union_covered(cc);
    }
    return 0;
}

/* The midpoint of the cubic through a and b whose tangents there are the
 * chord's projections on the tangent planes (normals na, nb): on a circle
 * of radius rho it lies the sag L^2 / (8 rho) above the chord, so a guess
 * for S' between two of its points good to third order. Also the
 * normalised mean normal. */
static void curved_midpoint(const double a[3], const double na[3], const double b[3],
                            const double nb[3], double m[3], double nm[3])
{
    const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double sa = ab[0] * na[0] + ab[1] * na[1] + ab[2] * na[2];
    const double sb = ab[0] * nb[0] + ab[1] * nb[1] + ab[2] * nb[2];
    double l = 0;
    for (int d = 0; d < 3; d++) {
        m[d] = 0.5 * (a[d] + b[d]) + 0.125 * (sb * nb[d] - sa * na[d]);
        nm[d] = na[d] + nb[d];
        l += nm[d] * nm[d];
    }
    l = sqrt(l);
    for (int d = 0; d < 3; d++)
        nm[d] = l > 0 ? nm[d] / l : na[d];
}

/* Projects the corners of a triangle subface not yet on S'. */
static void project_corners(const sampler *S, const subface *sf, subface_on_smooth *sg)
{
    if (!sg->todo)
        return;
    double sag = 0;
    for (int m = 0; m < 3; m++) {
        if (!(sg->todo >> m & 1))
            continue;
        double start[3] = {sg->p[3 * m], sg->p[3 * m + 1], sg->p[3 * m + 2]}, rho;
        if (vc_smooth_surface_project(&S->ss, sf->elem, sf->v + 3 * m, start, sg->p + 3 * m,
                                      sg->pn + 3 * m, &rho) == 1)
            sg->blended = 1;
        sag = fmax(sag, dist(start, sg->p + 3 * m));
    }
    sg->sag = sag;
    sg->todo = 0;
}

/* Is this tiny subface's image on S' far larger than the subface itself?
 * The projection onto S' is continuous wherever the input lies within
 * S's reach; at a spike of the input (a vertex farther from S' than S' is
 * curved) the nearest points jump, and the images of the two sides of
 * that seam do not meet. Splitting such a subface never makes its image
 * smaller, so it is dropped (the balls of both sides cover the seam). */
static int on_seam(const sampler *S, const subface *sf, const subface_on_smooth *sg)
{
    double in = 0, out = 0;
    for (int e = 0; e < 3; e++) {
        in = fmax(in, dist(sf->v + 3 * e, sf->v + 3 * ((e + 1) % 3)));
        out = fmax(out, dist(sg->p + 3 * e, sg->p + 3 * ((e + 1) % 3)));
    }
    /* Below MIN_SUBFACE widths, a subface still uncovered is one whose darts
     * land on covered ground once on S' (the image of a tiny interpolated
     * subface sits up to its sag aside): it is left, a gap far below any
     * ball's deep-coverage margin. */
    return in < MIN_SUBFACE * S->ss.width ||
           (in < SEAM_SIZE * S->ss.width && out > SEAM_STRETCH * in);
}

typedef struct lost_ctx {
    const vc_balls *b;
    const double *c;
    double reach;
    int64_t found;
} lost_ctx;

static int meets_lost(void *ctx, int64_t i)
{
    lost_ctx *l = ctx;
    if (!(dist(l->b->center + 3 * i, l->c) < l->b->radius[i] + l->reach))
        return 0;
    l->found = i;
    return 1;
}

/* Can the subface hold a point only a lost ball covered? A conservative
 * test: the ball around the corners' centroid through the farthest corner
 * (plus the margin of interpolated corners) meets a lost ball. The lost
 * ball the last subface met (*last, -1 for none) is tried first: the
 * subfaces of a chunk are neighbours, and the answer does not depend on
 * which lost ball is found. */
static int in_lost_region(const sampler *S, const subface *sf, const subface_on_smooth *sg, int nv,
                          int64_t *last)
{
    if (!S->lost)
        return 1;
    double c[3], reach;
    subface_bound(sf, sg, nv, c, &reach);
    if (sg && sg->interpolated)
        reach += sg->sag;
    lost_ctx l = {&S->lost->b, c, reach, -1};
    if (*last >= 0 && *last < S->lost->b.n && meets_lost(&l, *last))
        return 1;
    if (!vc_ball_set_query(S->lost, c, reach, 1.0, 0.0, meets_lost, &l))
        return 0;
    *last = l.found;
    return 1;
}

/* Keeps the subfaces of P from index `from` on that no single ball
 * covers, in their order. The tests only read the balls, so they run in
 * parallel in chunks of neighbouring subfaces (each chunk with its own
 * last covering ball); the answer does not depend on the thread count. */
static int drop_covered(const sampler *S, pool *P, int64_t from, int nv, int kind)
{
    const int64_t n = P->n - from;
    if (n <= 0)
        return 0;
    subface *f = P->f + from;
    subface_on_smooth *g = P->smooth ? P->g + from : NULL;
    unsigned char *keep = malloc((size_t)n);
    if (!keep)
        return -1;
    const int64_t chunk = 256;
    const int64_t n_chunks = (n + chunk - 1) / chunk;
    int oom = 0;
#pragma omp parallel num_threads(S->threads) if (n > 2 * chunk) reduction(| : oom)
    {
        id_list list = {NULL, 0, 0, 0};
        subface_group grp;
        unsigned char covered[GROUP_MAX];
#pragma omp for schedule(dynamic, 1)
        for (int64_t c = 0; c < n_chunks; c++) {
            int64_t last = -1, last_lost = -1;
            const int64_t end = (c + 1) * chunk < n ? (c + 1) * chunk : n;
            grp.n = 0;
            for (int64_t i = c * chunk; i <= end; i++) {
                int take = 0;
                if (i < end) {
                    if (g)
                        project_corners(S, &f[i], &g[i]);
                    keep[i] = 0;
                    take = !(g && on_seam(S, &f[i], &g[i])) &&
                           in_lost_region(S, &f[i], g ? &g[i] : NULL, nv, &last_lost);
                    if (take)
                        subface_test_init(S, &f[i], g ? &g[i] : NULL, nv, kind, &grp.t[grp.n],
                                          grp.centre[grp.n]);
                }
                /* the group so far is tested at the chunk's end, or when
                 * this subface does not fit it (and starts the next) */
                if (grp.n > 0 && (i == end || (take && !group_fits(&grp)))) {
                    if (grp.n == 1) {
                        const int64_t m0 = grp.member[0];
                        keep[m0] = !subface_covered(S, &f[m0], g ? &g[m0] : NULL, nv, kind, &last);
                    } else {
                        if (group_covered(S, &grp, covered, &last, &list))
                            oom = 1;
                        for (int q = 0; q < grp.n; q++)
                            keep[grp.member[q]] = !covered[q];
                    }
                    if (take) {
                        grp.t[0] = grp.t[grp.n];
                        memcpy(grp.centre[0], grp.centre[grp.n], sizeof grp.centre[0]);
                        grp.t[0].centre = grp.centre[0];
                    }
                    grp.n = 0;
                }
                if (take)
                    group_add(&grp, i);
            }
        }
        free(list.id);
    }
    if (oom) {
        free(keep);
        return -1;
    }
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++)
        if (keep[i]) {
            if (g)
                g[m] = g[i];
            f[m++] = f[i];
        }
    P->n = from + m;
    free(keep);
    return 0;
}

/* ---------------------------------------------------------------------
 * Radius of a new sample */

typedef struct radius_ctx {
    const vc_balls *b;
    const double *x;
    int kind;          /* C3 binds balls of the same kind only */
    double r;          /* the running estimate */
    double L;
    double deep;
    double nearest_deep; /* the nearest centre alpha-deeply inside the estimate */
} radius_ctx;

static int lipschitz_bound(void *ctx, int64_t i)
{
    radius_ctx *c = ctx;
    if (c->b->kind[i] != c->kind)
        return 0;
    double d = dist(c->b->center + 3 * i, c->x);
    double lim = c->b->radius[i] + c->L * d;
    if (lim < c->r)
        c->r = lim;
    return 0;
}

typedef struct spacing_ctx {
    const vc_balls *b;
    const double *x;
    double nearest;
} spacing_ctx;

static int nearest_centre(void *ctx, int64_t i)
{
    spacing_ctx *c = ctx;
    double d = dist(c->b->center + 3 * i, c->x);
    if (d < c->nearest)
        c->nearest = d;
    return 0;
}

/* The radius for a new ball on element sp, or a negative value when
 * density regulation drops the sample. bound: the sizing's radius bound
 * at the dart on the input (vc_sizing_radius_bound, capped at S->sz); c:
 * the centre (the dart, or its projection on S' with radius of curvature
 * rho there). */
static int ball_kind_of(const vc_surface_point *sp)
{
    return sp->kind == VC_ELEM_CORNER ? VC_BALL_CORNER
         : sp->kind == VC_ELEM_EDGE   ? VC_BALL_EDGE
                                      : VC_BALL_SURFACE;
}

/* The two conditions among the balls at a new centre c, over the balls
 * there now: *r lowered from r0 by the Lipschitz condition, *nearest the
 * nearest centre within (1 - alpha) *r (INFINITY: none). Both are minima
 * over balls, so the balls added later can be taken in afterwards
 * (radius_after). */
static void radius_conditions(const sampler *S, int kind, const double c[3], double r0, double *r,
                              double *nearest)
{
    radius_ctx rc = {&S->bs.b, c, kind, r0, S->opt.lipschitz, 1 - S->alpha, INFINITY};
    /* ball i binds only when r_i + L d < r, so d < (r - r_i) / L; a level's
     * radii are at least half its largest (level 0: at least 0, hence the
     * unit added), so only centres within (r + unit - rl / 2) / L count */
    const double L = S->opt.lipschitz;
    vc_ball_set_query(&S->bs, c, (r0 + S->bs.unit) / L, -0.5 / L, 0.0, lipschitz_bound, &rc);
    *r = rc.r;
    /* only a centre nearer than deep r changes anything */
    spacing_ctx sc = {&S->bs.b, c, INFINITY};
    vc_ball_set_query(&S->bs, c, (1 - S->alpha) * *r, 0.0, 0.0, nearest_centre, &sc);
    *nearest = sc.nearest;
}

/* The radius from the conditions over the balls before ball `from` (r,
 * nearest: radius_conditions then) and the balls from `from` on, or a
 * negative value when density regulation drops the sample. A ball that
 * cannot bind leaves a minimum as it is, so this is the radius the
 * conditions over all balls give, whichever balls the first part read. */
static double radius_after(sampler *S, int kind, const double c[3], double r, double nearest,
                           int64_t from)
{
    const vc_balls *b = &S->bs.b;
    const double L = S->opt.lipschitz;
    for (int64_t i = from; i < b->n; i++) {
        const double d = dist(b->center + 3 * i, c);
        if (b->kind[i] == kind && b->radius[i] + L * d < r)
            r = b->radius[i] + L * d;
        if (d < nearest)
            nearest = d;
    }
    const double deep = 1 - S->alpha;
    if (nearest < deep * r) {
        if (vc_rng_uniform(&S->rng) < 0.1)
            return -1;
        r = nearest / deep;
    }
    return r;
}

static double new_radius(sampler *S, const vc_surface_point *sp, double bound, const double c[3],
                         double rho)
{
    double r = bound;
    if (S->smooth && sp->kind == VC_ELEM_TRIANGLE)
        r = fmin(r, S->opt.curvature_factor * rho);
    const int kind = ball_kind_of(sp);
    /* the conditions among balls hold at the centre */
    double nearest;
    radius_conditions(S, kind, c, r, &r, &nearest);
    return radius_after(S, kind, c, r, nearest, S->bs.b.n);
}

/* The smallest ball of b (among those with among[i] set; among NULL: all),
 * -1 when none. */
static int64_t smallest_ball(const vc_balls *b, const unsigned char *among)
{
    int64_t smallest = -1;
    for (int64_t i = 0; i < b->n; i++)
        if ((!among || among[i]) && (smallest < 0 || b->radius[i] < b->radius[smallest]))
            smallest = i;
    return smallest;
}

/* normal: the outward normal at x, or NULL for the input's */
static int add_ball(sampler *S, const double x[3], double r, const vc_surface_point *sp,
                    const double *normal)
{
    if (S->opt.max_balls > 0 && S->bs.b.n >= S->opt.max_balls) {
        S->too_many = 1;
        return -1;
    }
    if (S->runaway_at > 0 && S->bs.b.n >= S->runaway_at) {
        S->runaway = 1;
        return -1;
    }
    double n[3];
    if (normal)
        memcpy(n, normal, sizeof n);
    else
        vc_sizing_point_normal(&S->z, sp, n);
    int kind = sp->kind == VC_ELEM_CORNER ? VC_BALL_CORNER
             : sp->kind == VC_ELEM_EDGE   ? VC_BALL_EDGE
                                          : VC_BALL_SURFACE;
    int64_t i = vc_ball_set_add(&S->bs, x, r, kind, sp->id, n);
    if (i < 0 || mark_dirty(S, i)) {
        S->oom = 1;
        return -1;
    }
    return 0;
}

/* Is x covered by one of the balls added since ball n_before (in the
 * current batch of darts, which its parallel test did not see)? */
static int covered_by_new(const sampler *S, const double x[3], int kind, int64_t n_before)
{
    cover_ctx c = {&S->bs.b, x, kind, 1 - S->cover_alpha};
    for (int64_t i = n_before; i < S->bs.b.n; i++)
        if (covers_point(&c, i))
            return 1;
    return 0;
}

/* ---------------------------------------------------------------------
 * Maximal Poisson-disk sampling of one pool (segments: nv = 2, triangles:
 * nv = 3), until every subface is covered. */

static double measure(const subface *sf, int nv)
{
    const double *a = sf->v, *b = sf->v + 3;
    if (nv == 2)
        return dist(a, b);
    const double *c = sf->v + 6;
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2],
           z = u[0] * w[1] - u[1] * w[0];
    return 0.5 * sqrt(x * x + y * y + z * z);
}

/* x on the subface; on a triangle, also z at the same place of its corners
 * on S' (z may be NULL) */
static void random_point(vc_rng *rng, const subface *sf, const subface_on_smooth *sg, int nv,
                         double x[3], double *z)
{
    if (nv == 2) {
        double t = vc_rng_uniform(rng);
        for (int d = 0; d < 3; d++)
            x[d] = sf->v[d] + t * (sf->v[3 + d] - sf->v[d]);
        return;
    }
    double u = vc_rng_uniform(rng), v = vc_rng_uniform(rng);
    if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
    }
    for (int d = 0; d < 3; d++)
        x[d] = sf->v[d] + u * (sf->v[3 + d] - sf->v[d]) + v * (sf->v[6 + d] - sf->v[d]);
    if (sg)
        for (int d = 0; d < 3; d++)
            z[d] = sg->p[d] + u * (sg->p[3 + d] - sg->p[d]) + v * (sg->p[6 + d] - sg->p[d]);
}

/* The four children of a triangle subface on S' (in the order of mps's
 * split): the parent's corners, and guesses for the midpoints (the cubic
 * through the corners with their normals), to be projected by drop_covered
 * until the corrections that makes are negligible; then S' is flat enough
 * across a subface (the chord sag falls fourfold per subdivision) that the
 * guesses stand. */
static void split_on_smooth(const sampler *S, const subface_on_smooth *sg,
                            subface_on_smooth ch[4])
{
    double pm[3][3], nm[3][3];
    for (int e = 0; e < 3; e++)
        curved_midpoint(sg->p + 3 * e, sg->pn + 3 * e, sg->p + 3 * ((e + 1) % 3),
                        sg->pn + 3 * ((e + 1) % 3), pm[e], nm[e]);
    const double *pa = sg->p, *pb = sg->p + 3, *pc = sg->p + 6;
    const double *ptri[4][3] = {{pa, pm[0], pm[2]}, {pm[0], pb, pm[1]}, {pm[2], pm[1], pc},
                                {pm[0], pm[1], pm[2]}};
    const double *na = sg->pn, *nb = sg->pn + 3, *nc = sg->pn + 6;
    const double *ntri[4][3] = {{na, nm[0], nm[2]}, {nm[0], nb, nm[1]}, {nm[2], nm[1], nc},
                                {nm[0], nm[1], nm[2]}};
    const int exact = !(sg->sag <= SAG_TOLERANCE * S->ss.width) || sg->blended;
    static const unsigned char midpoints[4] = {6, 5, 3, 7}; /* the corners that are midpoints */
    for (int q = 0; q < 4; q++) {
        for (int e = 0; e < 3; e++) {
            memcpy(ch[q].p + 3 * e, ptri[q][e], sizeof(double) * 3);
            memcpy(ch[q].pn + 3 * e, ntri[q][e], sizeof(double) * 3);
        }
        ch[q].todo = exact ? midpoints[q] : 0;
        /* an interpolated corner keeps the error it was placed with:
         * the sag does not shrink with the subfaces (the new midpoints'
         * own errors, third order in the size, add up to a fraction of
         * the last correction) */
        ch[q].sag = sg->sag;
        ch[q].interpolated = sg->interpolated || !exact;
        ch[q].blended = sg->blended;
    }
}

/* The vertex (0..2) of triangle abc opposite its longest edge. */
static int longest_edge_apex(const double *a, const double *b, const double *c)
{
    double la = dist(b, c), lb = dist(a, c), lc = dist(a, b);
    return la >= lb && la >= lc ? 0 : lb >= lc ? 1 : 2;
}

/* A thin triangle subface (its longest edge more than THIN_ASPECT times
 * its height over that edge) is halved across its longest edge instead of
 * split in four similar children: one ball holds a subface only when its
 * radius reaches half the longest edge, so similar children of a sliver
 * (the long facets of a coarse tessellation next to a rim or a fillet,
 * marching cubes' slivers) would be split until their length, not their
 * width, is below the balls' size, their number growing with the square of
 * the aspect (a thin disc's faces: 300 subface tests per ball). Halving
 * across the longest edge brings every triangle to a bounded aspect. Returns
 * the corner opposite the longest edge, or -1 when the subface is not
 * thin. */
#define THIN_ASPECT 3.0
/* ... and a needle when its apex stands within this share of the longest
 * edge's length from one of its ends (see mps) */
#define NEEDLE_END 0.25
static int thin_apex(const subface *sf)
{
    const int o = longest_edge_apex(sf->v, sf->v + 3, sf->v + 6);
    const double *p0 = sf->v + 3 * ((o + 1) % 3), *p1 = sf->v + 3 * ((o + 2) % 3);
    const double l2 = dist2(p0, p1);
    const double twice_area = 2 * measure(sf, 3); /* longest edge times height */
    return l2 > THIN_ASPECT * twice_area ? o : -1;
}

/* ch[0 .. n) from the corner pointers of tri (the parent's element is set
 * by the caller). */
static void fill_children(subface *ch, const double *const (*tri)[3], int n)
{
    for (int q = 0; q < n; q++)
        for (int e = 0; e < 3; e++)
            memcpy(ch[q].v + 3 * e, tri[q][e], sizeof(double) * 3);
}

/* The children of subface sf (nv corners; smooth: on S', whose split
 * keeps the corners there) into ch; returns their number. Their element
 * is the parent's. */
static int split_subface(const subface *sf, int nv, int smooth, subface ch[4])
{
    int nch;
    /* a thin triangle is halved across its longest edge (see
     * thin_apex; not on S', whose split keeps its children's
     * corners there) */
    const int o = nv == 3 && !smooth ? thin_apex(sf) : -1;
    if (nv == 2) {
        double m[3];
        for (int d = 0; d < 3; d++)
            m[d] = 0.5 * (sf->v[d] + sf->v[3 + d]);
        memcpy(ch[0].v, sf->v, sizeof(double) * 3);
        memcpy(ch[0].v + 3, m, sizeof m);
        memcpy(ch[1].v, m, sizeof m);
        memcpy(ch[1].v + 3, sf->v + 3, sizeof(double) * 3);
        nch = 2;
    } else if (o >= 0) {
        const double *apex = sf->v + 3 * o, *p0 = sf->v + 3 * ((o + 1) % 3),
                     *p1 = sf->v + 3 * ((o + 2) % 3);
        /* where the apex stands over the longest edge */
        double e01[3], e0a[3];
        for (int d = 0; d < 3; d++) {
            e01[d] = p1[d] - p0[d];
            e0a[d] = apex[d] - p0[d];
        }
        const double t = (e01[0] * e0a[0] + e01[1] * e0a[1] + e01[2] * e0a[2]) /
                         (e01[0] * e01[0] + e01[1] * e01[1] + e01[2] * e01[2]);
        if (t >= NEEDLE_END && t <= 1 - NEEDLE_END) {
            double m[3];
            for (int d = 0; d < 3; d++)
                m[d] = 0.5 * (p0[d] + p1[d]);
            const double *const tri[2][3] = {{apex, p0, m}, {apex, m, p1}};
            fill_children(ch, tri, 2);
            nch = 2;
        } else {
            /* A needle: the apex stands near an end of the longest
             * edge, so the shortest edge (apex and that end) is its
             * width. Halving across the longest edge would leave a
             * child as long and half as wide (a right-angled needle
             * keeps its aspect for ever: four children per halving
             * of the length, all needles). Cut across the length
             * instead, through the midpoints of the two long edges:
             * the far tip (similar, half as long) and the near half
             * as two triangles as wide as the needle. */
            const double *near = t < 0.5 ? p0 : p1, *far = t < 0.5 ? p1 : p0;
            double u[3], w[3];
            for (int d = 0; d < 3; d++) {
                u[d] = 0.5 * (apex[d] + far[d]);
                w[d] = 0.5 * (near[d] + far[d]);
            }
            const double *const tri[3][3] = {{u, w, far}, {apex, near, w}, {apex, w, u}};
            fill_children(ch, tri, 3);
            nch = 3;
        }
    } else {
        double m[3][3];
        for (int e = 0; e < 3; e++)
            for (int d = 0; d < 3; d++)
                m[e][d] = 0.5 * (sf->v[3 * e + d] + sf->v[3 * ((e + 1) % 3) + d]);
        const double *a = sf->v, *b = sf->v + 3, *c = sf->v + 6;
        const double *const tri[4][3] = {{a, m[0], m[2]}, {m[0], b, m[1]}, {m[2], m[1], c},
                                   {m[0], m[1], m[2]}};
        fill_children(ch, tri, 4);
        nch = 4;
    }
    for (int q = 0; q < nch; q++)
        ch[q].elem = sf->elem;
    return nch;
}

static int mps(sampler *S, pool *P, int nv)
{
    int kind = nv == 2 ? VC_ELEM_EDGE : VC_ELEM_TRIANGLE;
    double *cum = NULL;
    int64_t cum_cap = 0;
    pool next = {NULL, NULL, 0, 0, P->smooth};
    int rc = 0;
    /* drop what is already covered */
    if (drop_covered(S, P, 0, nv, kind))
        return -1;
    double area0 = 0;
    for (int64_t i = 0; i < P->n; i++)
        area0 += measure(&P->f[i], nv);
    /* darts since the last progress line, and how many of them fell on
     * covered ground: the share of the pool's area covered, estimated */
    int64_t darts = 0, darts_covered = 0;
    struct {
        int64_t sub;  /* the subface */
        double x[3];  /* the dart on the input */
        double c[3];  /* ... and where its coverage is tested (on S', or x) */
        double bound; /* the sizing's radius bound at x (uncovered darts) */
        /* on the input (no S'): the radius conditions over the balls before
         * the batch (radius_conditions), for uncovered darts */
        double r, nearest;
    } batch[DART_BATCH];
    unsigned char batch_covered[DART_BATCH];
    for (int round = 0; P->n > 0 && round < 60; round++) {
        if (P->n > cum_cap) {
            double *q = realloc(cum, sizeof(double) * (size_t)P->n);
            if (!q) {
                rc = -1;
                break;
            }
            cum = q;
            cum_cap = P->n;
        }
        double total = 0;
        for (int64_t i = 0; i < P->n; i++) {
            total += measure(&P->f[i], nv);
            cum[i] = total;
        }
        int misses = 0;
        int64_t thrown = 0; /* darts used this round */
        const int64_t balls_at_round = S->bs.b.n;
        while (misses < MAX_MISSES && total > 0 && !rc) {
            /* a batch of darts, drawn in order (a dart's subface by area,
             * then its place on it) */
            for (int b = 0; b < DART_BATCH; b++) {
                const double t = vc_rng_uniform(&S->rng) * total;
                int64_t lo = 0, hi = P->n - 1;
                while (lo < hi) {
                    int64_t mid = (lo + hi) / 2;
                    if (cum[mid] <= t)
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                batch[b].sub = lo;
                random_point(&S->rng, &P->f[lo], P->smooth ? &P->g[lo] : NULL, nv, batch[b].x,
                             batch[b].c);
                if (!P->smooth)
                    memcpy(batch[b].c, batch[b].x, sizeof batch[b].c);
            }
            /* their first coverage test against the balls there before the
             * batch, in parallel (most darts land on covered ground) */
            const int64_t n_before = S->bs.b.n;
#pragma omp parallel for schedule(static) num_threads(S->threads) if (S->threads > 1)
            for (int b = 0; b < DART_BATCH; b++) {
                batch_covered[b] = (unsigned char)point_covered(S, batch[b].c, kind);
                /* the sizing bound of a dart that may make a ball: a tree
                 * walk that depends on the dart alone, so done here in
                 * parallel rather than in the serial loop below */
                if (!batch_covered[b]) {
                    const vc_surface_point sp = {kind, P->f[batch[b].sub].elem};
                    batch[b].bound = vc_sizing_radius_bound(&S->z, &sp, batch[b].x, S->sz);
                    /* and, on the input, where the centre is the dart, the
                     * ball-index queries of its radius (the serial loop
                     * below then reads only the batch's new balls) */
                    if (!P->smooth)
                        radius_conditions(S, ball_kind_of(&sp), batch[b].c, batch[b].bound,
                                          &batch[b].r, &batch[b].nearest);
                }
            }
            for (int b = 0; b < DART_BATCH && misses < MAX_MISSES; b++) {
                /* a line every 2 s: phase, the share of the area (length)
                 * covered (that of the pool left at the start of this
                 * round, covered since, as the recent darts saw it), balls
                 * against the prediction (the area can read 100% covered
                 * while the last specks take most of the balls: noise
                 * above a tight bound, where the prediction is low) */
                if ((++darts & 1023) == 0 && vc_clock_seconds() - S->t_logged >= 2.0) {
                    S->t_logged = vc_clock_seconds();
                    const double left = area0 > 0 ? total / area0 : 0;
                    const double seen = (double)darts_covered / (double)darts;
                    vc_log(S->opt.log, VC_LOG_INFO,
                           "mesh: %s, %s: %.1f%% of the %s covered, %lld balls (%.3g predicted), %.0f s",
                           S->phase, nv == 2 ? "creases" : "patches", 100.0 * (1 - left * (1 - seen)),
                           nv == 2 ? "length" : "area", (long long)S->bs.b.n, S->st->n_balls_predicted,
                           vc_clock_seconds() - S->t_start);
                    darts = darts_covered = 0;
                }
                thrown++;
                const subface *sf = &P->f[batch[b].sub];
                const subface_on_smooth *sg = P->smooth ? &P->g[batch[b].sub] : NULL;
                double *x = batch[b].x, *c = batch[b].c, cn[3], rho = INFINITY;
                const int on_smooth = sg != NULL;
                /* on S': the dart between the subface's corners there is
                 * tested first, then its projection */
                if (batch_covered[b] || covered_by_new(S, c, kind, n_before)) {
                    darts_covered++;
                    misses++;
                    continue;
                }
                if (on_smooth) {
                    double z[3] = {c[0], c[1], c[2]};
                    /* between interpolated corners, the dart stands for the
                     * point of S' under it; between projected ones, for the
                     * projection of x, as the corners do */
                    if (sg->interpolated) {
                        double nz[3] = {0, 0, 0}, l = 0;
                        for (int k = 0; k < 9; k++)
                            nz[k % 3] += sg->pn[k];
                        for (int d = 0; d < 3; d++)
                            l += nz[d] * nz[d];
                        l = sqrt(l);
                        for (int d = 0; d < 3; d++)
                            nz[d] = l > 0 ? nz[d] / l : S->z.tri_out_normal[3 * sf->elem + d];
                        vc_smooth_surface_settle(&S->ss, sf->elem, x, z, nz, c, cn, &rho);
                    } else
                        vc_smooth_surface_project(&S->ss, sf->elem, x, z, c, cn, &rho);
                    /* on a subface whose corners pin S' down to far below
                     * the noise sliver elimination tolerates, the dart
                     * itself is the centre: a projection lands a little
                     * aside, and a gap on the subface would never get its
                     * ball */
                    if (sg->interpolated && sg->sag <= ACCURATE_SAG * S->ss.width)
                        memcpy(c, z, sizeof z);
                    if (point_covered(S, c, kind)) {
                        darts_covered++;
                        misses++;
                        continue;
                    }
                    /* the radius bound: the largest principal curvature
                     * (four fits, so only for darts that make a ball) */
                    const double k = vc_smooth_surface_max_curvature(&S->ss, sf->elem, c, cn);
                    if (k > 0)
                        rho = fmin(rho, 1 / k);
                }
                vc_surface_point sp = {kind, sf->elem};
                double r = on_smooth ? new_radius(S, &sp, batch[b].bound, c, rho)
                                     : radius_after(S, ball_kind_of(&sp), c, batch[b].r,
                                                    batch[b].nearest, n_before);
                if (r <= 0) {
                    misses++;
                    continue;
                }
                if (add_ball(S, c, r, &sp, on_smooth ? cn : NULL)) {
                    rc = -1;
                    break;
                }
                misses = 0;
            }
        }
        if (rc)
            break;
        /* The balls this round added may cover whole subfaces: testing
         * each once before splitting costs one test where its children
         * would cost four. */
        const int64_t n_pool = P->n; /* the round's pool, for KEEP_WHOLE */
        if (S->bs.b.n > balls_at_round && drop_covered(S, P, 0, nv, kind)) {
            rc = -1;
            break;
        }
        /* subdivide and keep the uncovered children, tested in batches
         * (children of PARENT_BATCH parents at a time, not all at once:
         * the pool can be large) */
        next.n = 0;
        int64_t batch_from = 0;
        for (int64_t i = 0; i < P->n && !rc; i++) {
            const subface *sf = &P->f[i];
            subface ch[4];
            /* A subface far smaller than the pool's mean (KEEP_WHOLE
             * times) that expected less than one of this round's darts
             * stays whole: splitting what no dart has tried only multiplies
             * it. Darts go by area, and a round's darts end after
             * MAX_MISSES misses in a row, a number that does not grow with
             * the pool: a speck of radius 0.01 beside a box of side 10 (its
             * share of the area 1e-6) was split every round, 10 million
             * subfaces, 1.1 GB, 14 s, before the box's coverage left it
             * darts. As the rest is covered the mean comes down to it, and
             * it is split like any other. (Weighing the darts instead, no
             * subface below a quarter of the mean, fixed the speck but
             * biased the darts towards small triangles: fertility.off's
             * surface Q min fell from 0.15-0.20 to 0.09-0.16 over four
             * random seeds.) */
            const double a = measure(sf, nv);
            if (KEEP_WHOLE * a * (double)n_pool < total && (double)thrown * a < total) {
                if (pool_push(&next, sf, P->smooth ? &P->g[i] : NULL))
                    rc = -1;
                continue;
            }
            const int nch = split_subface(sf, nv, P->smooth, ch);
            if (P->smooth) {
                subface_on_smooth chg[4];
                split_on_smooth(S, &P->g[i], chg);
                for (int q = 0; q < nch; q++)
                    if (pool_push(&next, &ch[q], &chg[q]))
                        rc = -1;
            } else {
                for (int q = 0; q < nch; q++)
                    if (pool_push(&next, &ch[q], NULL))
                        rc = -1;
            }
            if (!rc && (i + 1) % PARENT_BATCH == 0) {
                if (drop_covered(S, &next, batch_from, nv, kind))
                    rc = -1;
                batch_from = next.n;
            }
        }
        if (!rc && drop_covered(S, &next, batch_from, nv, kind))
            rc = -1;
        pool tmp = *P;
        *P = next;
        next = tmp;

    }
    free(cum);
    free(next.f);
    free(next.g);
    if (S->oom)
        rc = -1;
    return rc;
}

/* ---------------------------------------------------------------------
 * Pools */

static void edge_subface(const sampler *S, int64_t e, subface *sf)
{
    const double *a = S->s->xyz + 3 * S->f->edge_vertex[2 * e];
    const double *b = S->s->xyz + 3 * S->f->edge_vertex[2 * e + 1];
    memcpy(sf->v, a, sizeof(double) * 3);
    memcpy(sf->v + 3, b, sizeof(double) * 3);
    sf->elem = e;
}

/* Triangle t; on S' too when sampled there (sg). */
static void tri_subface(const sampler *S, int64_t t, subface *sf, subface_on_smooth *sg)
{
    for (int k = 0; k < 3; k++)
        memcpy(sf->v + 3 * k, S->s->xyz + 3 * S->s->tri[3 * t + k], sizeof(double) * 3);
    sf->elem = t;
    if (S->smooth) {
        memcpy(sg->p, S->tri_on_smooth + 19 * t, sizeof sg->p);
        memcpy(sg->pn, S->tri_on_smooth + 19 * t + 9, sizeof sg->pn);
        sg->blended = S->tri_on_smooth[19 * t + 18] != 0;
        sg->todo = 0;
        sg->interpolated = 0;
        sg->sag = INFINITY; /* unknown: the midpoints are projected */
    }
}

typedef struct near_ctx {
    unsigned char *mark_edge, *mark_tri;
} near_ctx;

static void mark_near(void *ctx, int kind, int64_t id)
{
    near_ctx *c = ctx;
    if (kind == VC_ELEM_EDGE)
        c->mark_edge[id] = 1;
    else if (kind == VC_ELEM_TRIANGLE)
        c->mark_tri[id] = 1;
}

/* Samples the creases, then the patches, restricted to the elements marked
 * (all when marks are NULL). */
static int sample_strata(sampler *S, const unsigned char *mark_edge, const unsigned char *mark_tri)
{

    pool E = {NULL, NULL, 0, 0, 0};
    int rc = 0;
    double t0 = vc_clock_seconds();
    for (int64_t e = 0; e < S->f->n_edges && !rc; e++) {
        if (!S->f->edge_sharp[e] || (mark_edge && !mark_edge[e]))
            continue;
        subface sf;
        edge_subface(S, e, &sf);
        rc = pool_push(&E, &sf, NULL);
    }
    if (!rc)
        rc = mps(S, &E, 2);
    free(E.f);
    double t1 = vc_clock_seconds();
    S->st->t_edges += t1 - t0;
    pool T = {NULL, NULL, 0, 0, S->smooth};
    for (int64_t t = 0; t < S->s->n_triangles && !rc; t++) {
        if (mark_tri && !mark_tri[t])
            continue;
        subface sf;
        subface_on_smooth sg;
        tri_subface(S, t, &sf, &sg);
        rc = pool_push(&T, &sf, &sg);
    }
    if (!rc)
        rc = mps(S, &T, 3);
    S->st->t_surface += vc_clock_seconds() - t1;
    free(T.f);
    free(T.g);
    return rc;
}

/* Samples again around the balls whose radius went down from old_r. */
static int resample_around(sampler *S, const double *old_r, const unsigned char *shrunk)
{
    unsigned char *me = calloc((size_t)S->f->n_edges + 1, 1);
    unsigned char *mt = calloc((size_t)S->s->n_triangles + 1, 1);
    if (!me || !mt) {
        free(me);
        free(mt);
        return -1;
    }
    near_ctx nc = {me, mt};
    /* the shrunk balls at their old radii (see sampler.lost), over their
     * bounding box */
    const vc_balls *b = &S->bs.b;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int64_t n_lost = 0;
    for (int64_t i = 0; i < b->n; i++)
        if (shrunk[i]) {
            vc_sizing_elements_near(&S->z, b->center + 3 * i, old_r[i], mark_near, &nc);
            for (int d = 0; d < 3; d++) {
                lo[d] = fmin(lo[d], b->center[3 * i + d] - old_r[i]);
                hi[d] = fmax(hi[d], b->center[3 * i + d] + old_r[i]);
            }
            n_lost++;
        }
    int rc = n_lost == 0 ? 0 : -1;
    vc_ball_set lost;
    if (n_lost > 0 && vc_ball_set_init(&lost, lo, dist(lo, hi)) == 0) {
        int ok = 1;
        for (int64_t i = 0; i < b->n && ok; i++)
            if (shrunk[i])
                ok = vc_ball_set_add(&lost, b->center + 3 * i, old_r[i], b->kind[i], b->element[i],
                                     b->normal + 3 * i) >= 0;
        if (ok) {
            S->lost = &lost;
            rc = sample_strata(S, me, mt);
            S->lost = NULL;
        }
        vc_ball_set_free(&lost);
    }
    free(me);
    free(mt);
    return rc;
}

/* ---------------------------------------------------------------------
 * Local Lipschitz condition C3 among balls of the same kind:
 * r_p <= r_q + L |p - q| (across kinds it would make the small edge balls
 * shrink the surface balls next to them and back, without end).
 *
 * The condition held among the balls after the previous pass, so only the
 * balls added or shrunk since (dirty) can bind: each dirty ball q lowers
 * r_p to r_q + L |p - q| wherever that is smaller. One pass is exact: the
 * minimum over q of r_q + L |p - q| is itself L-Lipschitz, so the balls
 * lowered here need no second pass. A ball p with radius at most h (its
 * level's bound) can be bound by q only within (h - r_q) / L. */

typedef struct lipschitz_ctx {
    const vc_balls *b;
    int64_t q;
    double L;
    uint64_t *newr; /* the bits of positive doubles: ordered as the values */
} lipschitz_ctx;

/* newr[p] = min(newr[p], v) for a positive v, from any thread: positive
 * doubles order as their bit patterns do, and the minimum does not depend
 * on the order of the updates. */
static void lower_to(uint64_t *slot, double v)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    uint64_t cur = __atomic_load_n(slot, __ATOMIC_RELAXED);
    while (bits < cur &&
           !__atomic_compare_exchange_n(slot, &cur, bits, 1, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
        ;
}

static int lower_neighbour(void *ctx, int64_t p)
{
    lipschitz_ctx *c = ctx;
    if (p == c->q || c->b->kind[p] != c->b->kind[c->q])
        return 0;
    double lim = c->b->radius[c->q] + c->L * dist(c->b->center + 3 * p, c->b->center + 3 * c->q);
    if (lim < c->b->radius[p])
        lower_to(&c->newr[p], lim);
    return 0;
}

static int64_t enforce_lipschitz(sampler *S, double *old_r, unsigned char *shrunk)
{
    vc_balls *b = &S->bs.b;
    int64_t n = b->n, changed = 0;
    if (n == 0)
        return 0;
    memcpy(old_r, b->radius, sizeof(double) * (size_t)n);
    uint64_t *newr = malloc(sizeof(uint64_t) * (size_t)n);
    if (!newr)
        return -1;
    memcpy(newr, b->radius, sizeof(double) * (size_t)n);
    const double L = S->opt.lipschitz;
    const int64_t nq = n < S->dirty_cap ? n : S->dirty_cap;
    /* the dirty balls in parallel (a gyroid's 65,828 first balls took 1.6 s
     * on one thread); each lowers its neighbours' bounds atomically */
#pragma omp parallel for schedule(dynamic, 64) num_threads(S->threads) if (nq > 256)
    for (int64_t q = 0; q < nq; q++) {
        if (!S->dirty[q])
            continue;
        S->dirty[q] = 0;
        lipschitz_ctx c = {b, q, L, newr};
        vc_ball_set_query(&S->bs, b->center + 3 * q, -b->radius[q] / L, 1.0 / L, b->radius[q],
                          lower_neighbour, &c);
    }
    for (int64_t i = 0; i < n; i++) {
        double r;
        memcpy(&r, &newr[i], sizeof r);
        if (r < old_r[i] * (1 - 1e-12)) {
            shrunk[i] = 1;
            changed++;
            if (vc_ball_set_resize(&S->bs, i, r))
                changed = -1;
        }
    }
    free(newr);
    return changed;
}

/* After a pass shrank balls (sliver elimination, flat facets, pinches,
 * facets off the input; marked in shrunk, their radii before in old_r),
 * the Lipschitz condition those balls now impose, applied before the
 * ground they uncovered is sampled again: the balls it shrinks join the
 * same resampling, which a separate Lipschitz round after it would redo
 * (every pass of sliver elimination took one more round of sampling for
 * them). old_r keeps the radius before either shrinking. Returns the
 * balls shrunk, or -1 when out of memory. */
static int64_t enforce_lipschitz_after(sampler *S, double *old_r, unsigned char *shrunk)
{
    const int64_t n = S->bs.b.n;
    double *before = malloc(sizeof(double) * (size_t)(n ? n : 1));
    unsigned char *now = malloc((size_t)(n ? n : 1));
    if (!before || !now) {
        free(before);
        free(now);
        return -1;
    }
    memcpy(before, old_r, sizeof(double) * (size_t)n);
    memset(now, 0, (size_t)n);
    const int64_t nl = enforce_lipschitz(S, old_r, now);
    for (int64_t i = 0; nl > 0 && i < n; i++) {
        if (shrunk[i])
            old_r[i] = before[i];
        shrunk[i] |= now[i];
    }
    if (nl <= 0)
        memcpy(old_r, before, sizeof(double) * (size_t)n);
    free(before);
    free(now);
    return nl;
}

/* ---------------------------------------------------------------------
 * Sliver elimination (6.2.7): for every triplet with exactly one of its two
 * points covered by a fourth ball, the covering ball that needs the least
 * shrinking is cut to leave the point just outside. */

/* The facets of the reconstructed surface, as triplets of balls, and how
 * near their seeds come to a fourth sphere (min of the triplet's two
 * clearances: the centre lift's reference). */
typedef struct facet_rec {
    int64_t v[3];
    double clear;
} facet_rec;

typedef struct facet_list {
    facet_rec *f;
    int64_t n, cap;
    int oom;
} facet_list;

/* The facets' balls, 3 per facet, in a new array (NULL when out of
 * memory). */
static int64_t *facet_balls(const facet_list *l)
{
    int64_t *v = malloc(sizeof(int64_t) * 3 * (size_t)(l->n + 1));
    for (int64_t f = 0; v && f < l->n; f++)
        memcpy(v + 3 * f, l->f[f].v, sizeof l->f[f].v);
    return v;
}

static void push_facet(facet_list *l, facet_rec r)
{
    if (l->oom || vc_reserve(&l->f, &l->cap, l->n + 1, sizeof(facet_rec))) {
        l->oom = 1;
        return;
    }
    l->f[l->n++] = r;
}

/* a triplet whose two seeds both stay is a facet of the surface */
static void collect_facet(facet_list *l, const vc_triplet *t)
{
    push_facet(l, (facet_rec){{t->i, t->j, t->k}, fmin(t->clear_up, t->clear_down)});
}

/* A half-covered pair: its triplet, the covering ball and the radius that
 * uncovers the point. */
typedef struct half_rec {
    int64_t v[3], cover;
    double r;
    double s; /* the cut, relative to the cover's radius */
} half_rec;

typedef struct sliver_ctx {
    const vc_balls *b;
    double margin;     /* SHRINK_MARGIN */
    double quartet_gap; /* opt.quartet_gap */
    half_rec *half;    /* n_half of them */
    int64_t n_half, cap;
    int oom;
    double where[3]; /* the first half-covered point found */
    facet_list *facets; /* the triplets with both seeds uncovered */
} sliver_ctx;

/* Records that ball f must shrink to radius r (less the margin) for the
 * point g of triplet t. */
static void push_cut(sliver_ctx *c, const vc_triplet *t, int64_t f, const double g[3], double r)
{
    if (c->n_half == 0)
        memcpy(c->where, g, sizeof c->where);
    if (vc_reserve(&c->half, &c->cap, c->n_half + 1, sizeof(half_rec))) {
        c->oom = 1;
        return;
    }
    half_rec *h = &c->half[c->n_half++];
    h->v[0] = t->i;
    h->v[1] = t->j;
    h->v[2] = t->k;
    h->cover = f;
    h->r = r * (1 - c->margin);
}

static void on_triplet(void *ctx, const vc_triplet *t)
{
    sliver_ctx *c = ctx;
    if (t->cover_up < 0 && t->cover_down < 0)
        collect_facet(c->facets, t);
    if (t->cover_up < 0 && t->cover_down < 0 && c->quartet_gap > 0 && !c->oom) {
        /* a near-quartet: a seed nearly on a fourth sphere; that ball
         * shrinks until the seed's gap is quartet_gap */
        const int up = t->clear_up <= t->clear_down;
        const double clear = up ? t->clear_up : t->clear_down;
        const int64_t f = up ? t->clear_ball_up : t->clear_ball_down;
        if (clear < c->quartet_gap && f >= 0) {
            const double *g = up ? t->up : t->down;
            push_cut(c, t, f, g, dist(c->b->center + 3 * f, g) / sqrt(1 + c->quartet_gap));
        }
        return;
    }
    if ((t->cover_up < 0) == (t->cover_down < 0) || c->oom)
        return;
    int64_t f = t->cover_up >= 0 ? t->cover_up : t->cover_down;
    const double *g = t->cover_up >= 0 ? t->up : t->down;
    push_cut(c, t, f, g, dist(c->b->center + 3 * f, g));
}

/* The radius each ball is cut to (thesis 6.2.7: per quartet, the ball
 * that needs the least shrinking). A sliver of four balls, each covering a
 * seed of the other three's triplet, keeps its shape when all four shrink
 * a little, which cutting every cover did (fandisk.off at 20 degrees: the
 * same four balls, each cut by 0.1% to 0.8%, for ten passes; at 60
 * degrees it diverged). So the cuts are taken smallest first (relative to
 * the radius; by ball and triplet on a tie), and a cut whose triplet has a
 * ball already cut this pass waits: that triplet changes with it, and is
 * looked at again next pass. The smallest cut is always taken, so every
 * pass cuts something. */
static int cmp_half(const void *p, const void *q)
{
    const half_rec *a = p, *b = q;
    if (a->s != b->s)
        return a->s < b->s ? -1 : 1;
    if (a->cover != b->cover)
        return a->cover < b->cover ? -1 : 1;
    for (int m = 0; m < 3; m++)
        if (a->v[m] != b->v[m])
            return a->v[m] < b->v[m] ? -1 : 1;
    return 0;
}

static void cut_radii(const vc_balls *b, sliver_ctx *c, unsigned char *cut, double *target)
{
    if (c->n_half == 0)
        return;
    for (int64_t k = 0; k < c->n_half; k++)
        c->half[k].s = 1 - c->half[k].r / b->radius[c->half[k].cover];
    qsort(c->half, (size_t)c->n_half, sizeof(half_rec), cmp_half);
    for (int64_t k = 0; k < c->n_half; k++) {
        const half_rec *h = &c->half[k];
        if (cut[h->v[0]] || cut[h->v[1]] || cut[h->v[2]])
            continue;
        cut[h->cover] = 1;
        if (h->r < target[h->cover])
            target[h->cover] = h->r;
    }
}

#define FACET_REC_LESS(a, b)                                                                      \
    ((a)->v[0] != (b)->v[0]   ? (a)->v[0] < (b)->v[0]                                              \
     : (a)->v[1] != (b)->v[1] ? (a)->v[1] < (b)->v[1]                                              \
                              : (a)->v[2] < (b)->v[2])
VC_SMALL_SORT(sort_facet_recs, facet_rec, FACET_REC_LESS)

/* Also leaves the facets of the balls as they were before shrinking in
 * *facets, in (i, j, k) order, as a scan of every triplet lists them. With
 * all = 0 only the triplets around the balls changed since the last scan
 * are computed again; the facets of the other balls are kept from the
 * last call (a facet is found from its smallest ball, and every change to
 * the set marks the balls it can affect: vc_triplets_scan_changed). */
static int64_t eliminate_slivers(sampler *S, double *old_r, unsigned char *shrunk,
                                 int64_t *n_half, double where[3], facet_list *facets, int all)
{
    vc_balls *b = &S->bs.b;
    int64_t n = b->n;
    *n_half = 0;
    if (n == 0) {
        facets->n = 0;
        return 0;
    }
    memcpy(old_r, b->radius, sizeof(double) * (size_t)n);
    facet_list fresh = {NULL, 0, 0, 0};
    sliver_ctx c = {b, SHRINK_MARGIN, S->opt.quartet_gap, NULL, 0, 0, 0,
                    {0, 0, 0}, &fresh};
    double *target = malloc(sizeof(double) * (size_t)n);
    unsigned char *cut = calloc((size_t)n, 1);
    unsigned char *scanned = malloc((size_t)n);
    if (!target || !cut || !scanned) {
        free(target);
        free(cut);
        free(scanned);
        return -1;
    }
    memcpy(target, b->radius, sizeof(double) * (size_t)n);
    if ((all ? vc_triplets_scan_all(&S->bs, S->opt.threads, on_triplet, &c)
             : vc_triplets_scan_changed(&S->bs, S->opt.threads, on_triplet, &c, scanned)) ||
        fresh.oom || c.oom) {
        free(target);
        free(cut);
        free(scanned);
        free(c.half);
        free(fresh.f);
        return -1;
    }
    if (!all) {
        /* the facets of the balls not scanned, as they were */
        for (int64_t q = 0; q < facets->n && !fresh.oom; q++)
            if (!scanned[facets->f[q].v[0]])
                push_facet(&fresh, facets->f[q]);
        if (fresh.oom) {
            free(target);
            free(cut);
            free(scanned);
            free(c.half);
            free(fresh.f);
            return -1;
        }
        if (fresh.n > 1)
            sort_facet_recs(fresh.f, fresh.n);
    }
    free(scanned);
    free(facets->f);
    *facets = fresh;
    cut_radii(b, &c, cut, target);
    int64_t changed = 0;
    for (int64_t i = 0; i < n; i++)
        if (target[i] < b->radius[i]) {
            shrunk[i] = 1;
            changed++;
            if (vc_ball_set_resize(&S->bs, i, target[i]) || mark_dirty(S, i))
                changed = -1;
        }
    *n_half = c.n_half;
    memcpy(where, c.where, sizeof c.where);
    free(target);
    free(cut);
    free(c.half);
    return changed;
}

/* ---------------------------------------------------------------------
 * Flat facets.
 *
 * The worst facets of the reconstructed surface are all of one kind: a ball
 * p wedged in a small gap between the deep-coverage boundaries of larger
 * balls q1 and q2 (within a few percent of (1 - alpha) r_q from both), so
 * the facet p q1 q2 has an angle of 130 degrees or more at p. No position
 * of p in that gap is better, and C4 holds its radius down. The facet on
 * the other side of q1 q2 has a third ball s; when s holds both seeds of
 * (p, q1, q2), that facet and the edge q1 q2 go away, and the two facets
 * become p s q1 and p s q2, far from flat. Growing s would do it but is
 * nearly always barred by C3 or C4 (s sits at its limits after the
 * Lipschitz fixes); shrinking q1 or q2 by a few percent does it too and,
 * like sliver elimination, keeps every ball condition, with the Lipschitz
 * fixes, sampling again around the shrunk ball and sliver elimination
 * following as after any shrinking. */

typedef struct edge_rec {
    int64_t a, b, facet; /* a < b */
} edge_rec;

static int cmp_edge_rec(const void *p, const void *q)
{
    const edge_rec *x = p, *y = q;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return (x->facet > y->facet) - (x->facet < y->facet);
}
/* Records equal in every field are the same: any sort gives qsort's array. */
#define EDGE_REC_LESS(x, y)                                                                       \
    ((x)->a != (y)->a ? (x)->a < (y)->a : (x)->b != (y)->b ? (x)->b < (y)->b : (x)->facet < (y)->facet)
VC_SMALL_SORT(sort_edge_recs, edge_rec, EDGE_REC_LESS)

/* Are both points where the spheres of p, q (with radius rq) and o meet
 * inside ball s, FLAT_SEED_DEPTH deep? */
static int seeds_held(const vc_balls *B, int64_t p, int64_t q, double rq, int64_t o, int64_t s)
{
    double up[3], down[3];
    const double *c = B->center;
    if (!vc_sphere_triple_points(c + 3 * p, B->radius[p], c + 3 * q, rq, c + 3 * o, B->radius[o],
                                 up, down))
        return 0;
    double r = B->radius[s] * (1 - FLAT_SEED_DEPTH);
    return dist(c + 3 * s, up) < r && dist(c + 3 * s, down) < r;
}

/* The largest radius, at most FLAT_MAX_SHRINK below r_q, with which ball q
 * of the facet (p, q, o) lets s hold the facet's seeds; 0 when none. */
static double flip_radius(const vc_balls *B, int64_t p, int64_t q, int64_t o, int64_t s)
{
    /* the seeds vanish when q no longer meets p and o, so the condition
     * is not monotone over the whole range: step down by 1% to the first
     * radius that works, then bisect above it */
    double r0 = B->radius[q], lo = r0, hi = r0;
    int found = 0, steps = (int)(100 * FLAT_MAX_SHRINK + 0.5);
    for (int t = 1; t <= steps && !found; t++) {
        hi = lo;
        lo = r0 * (1 - 0.01 * t);
        found = seeds_held(B, p, q, lo, o, s);
    }
    if (!found)
        return 0;
    for (int it = 0; it < 30; it++) {
        double mid = 0.5 * (lo + hi);
        if (seeds_held(B, p, q, mid, o, s))
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The edges of the facets (three per facet, a < b), sorted; NULL when out
 * of memory. */
static edge_rec *sorted_edges(const facet_list *fl)
{
    edge_rec *e = malloc(sizeof(edge_rec) * (size_t)(3 * fl->n + 1));
    if (!e)
        return NULL;
    for (int64_t f = 0; f < fl->n; f++)
        for (int k = 0; k < 3; k++) {
            int64_t a = fl->f[f].v[k], b = fl->f[f].v[(k + 1) % 3];
            e[3 * f + k] = (edge_rec){a < b ? a : b, a < b ? b : a, f};
        }
    sort_edge_recs(e, 3 * fl->n);
    return e;
}

/* Shrinks, for every facet (of fl, the current balls' facets) below
 * FLAT_Q among balls of one kind (not corners), whichever of q1 and q2
 * needs the smaller cut, recording the old radii and marking the shrunk
 * balls like the other passes. Returns the number of balls shrunk, or -1. */
static int64_t unflatten_facets(sampler *S, const facet_list *facets, double *old_r,
                                unsigned char *shrunk)
{
    const facet_list fl = *facets;
    edge_rec *e = sorted_edges(&fl);
    if (!e)
        return -1;
    vc_balls *B = &S->bs.b;
    memcpy(old_r, B->radius, sizeof(double) * (size_t)B->n);
    int64_t changed = 0;
    for (int64_t f = 0; f < fl.n; f++) {
        const int64_t *v = fl.f[f].v;
        const double *c0 = B->center + 3 * v[0], *c1 = B->center + 3 * v[1],
                     *c2 = B->center + 3 * v[2];
        if (!(vc_triangle_quality(c0, c1, c2) < FLAT_Q))
            continue;
        int apex = longest_edge_apex(c0, c1, c2);
        int64_t p = v[apex], q1 = v[(apex + 1) % 3], q2 = v[(apex + 2) % 3];
        /* the other facet on edge q1 q2 (a manifold edge has two) */
        edge_rec key = {q1 < q2 ? q1 : q2, q1 < q2 ? q2 : q1, -1};
        int64_t lo = 0, hi = 3 * fl.n;
        while (lo < hi) {
            int64_t mid = (lo + hi) / 2;
            if (cmp_edge_rec(&e[mid], &key) < 0)
                lo = mid + 1;
            else
                hi = mid;
        }
        int64_t other = -1, count = 0;
        for (int64_t m = lo; m < 3 * fl.n && e[m].a == key.a && e[m].b == key.b; m++) {
            count++;
            if (e[m].facet != f)
                other = e[m].facet;
        }
        if (count != 2 || other < 0)
            continue;
        int64_t s = -1;
        for (int k = 0; k < 3; k++)
            if (fl.f[other].v[k] != q1 && fl.f[other].v[k] != q2)
                s = fl.f[other].v[k];
        int kind = B->kind[p];
        if (s < 0 || kind == VC_BALL_CORNER || B->kind[q1] != kind || B->kind[q2] != kind ||
            B->kind[s] != kind)
            continue;
        double r1 = flip_radius(B, p, q1, q2, s), r2 = flip_radius(B, p, q2, q1, s);
        if (r1 <= 0 && r2 <= 0)
            continue;
        int64_t q = r1 / B->radius[q1] >= r2 / B->radius[q2] ? q1 : q2;
        double r = q == q1 ? r1 : r2;
        if (vc_ball_set_resize(&S->bs, q, r) || mark_dirty(S, q)) {
            changed = -1;
            break;
        }
        if (!shrunk[q])
            changed++;
        shrunk[q] = 1;
    }
    free(e);
    return changed;
}

/* Cuts ball q to factor times its radius unless it was cut already in
 * this pass or is a corner ball; returns changed plus one when cut,
 * changed when not, -1 when out of memory. */
static int64_t cut_once(sampler *S, int64_t q, double factor, unsigned char *shrunk,
                        int64_t changed)
{
    if (shrunk[q] || S->bs.b.kind[q] == VC_BALL_CORNER)
        return changed;
    if (vc_ball_set_resize(&S->bs, q, factor * S->bs.b.radius[q]) || mark_dirty(S, q))
        return -1;
    shrunk[q] = 1;
    return changed + 1;
}

/* ---------------------------------------------------------------------
 * Facets that stray from the input.
 *
 * The sizing bounds each ball's reach from its own tangent plane, not the
 * facet between three balls: where the input folds by less than
 * theta_sharp between two balls, the facet cuts the fold by about the
 * distance of the nearer centre from it times sin(fold / 2), which can
 * exceed the error bound (a fin's ridge: 1.3 times). After sliver
 * elimination converges, every facet is probed against the input
 * (facet_strays); the balls of a facet farther than DEVIATION_BOUND times
 * the error bound are cut to DEVIATION_SHRINK of their radius, and the
 * sampling runs again around them (new centres come between, nearer the
 * fold), up to DEVIATION_PASSES times. */
#define DEVIATION_BOUND 1.0
#define DEVIATION_SHRINK 0.7
#define DEVIATION_PASSES 4

/* Is the facet of centres v farther than bound from the input at one of
 * its probes: EDGE_PROBES points along each edge and the centroid with
 * the points halfway from it to the corners? A chord that cuts a fold is
 * farthest from the input where it passes the fold, anywhere along it
 * (a fin's ridge: 0.6 of the way, 1.2 times as far as at the midpoint). */
#define EDGE_PROBES 7
static int facet_strays(const sampler *S, const int64_t v[3], double bound, int64_t *hint)
{
    const double *c[3] = {S->bs.b.center + 3 * v[0], S->bs.b.center + 3 * v[1],
                          S->bs.b.center + 3 * v[2]};
    double w[3 * EDGE_PROBES + 4][3];
    int n = 0;
    for (int e = 0; e < 3; e++)
        for (int k = 1; k <= EDGE_PROBES; k++, n++) {
            const double t = (double)k / (EDGE_PROBES + 1);
            w[n][e] = 1 - t;
            w[n][(e + 1) % 3] = t;
            w[n][(e + 2) % 3] = 0;
        }
    for (int m = 0; m < 3; m++, n++)
        for (int d = 0; d < 3; d++)
            w[n][d] = d == m ? 2.0 / 3 : 1.0 / 6;
    w[n][0] = w[n][1] = w[n][2] = 1.0 / 3;
    n++;
    for (int m = 0; m < n; m++) {
        double p[3];
        for (int d = 0; d < 3; d++)
            p[d] = w[m][0] * c[0][d] + w[m][1] * c[1][d] + w[m][2] * c[2][d];
        if (!vc_sizing_triangle_within_hint(&S->z, p, bound, hint))
            return 1;
    }
    return 0;
}

/* Cuts the balls of the straying facets (not corner balls, each once);
 * returns the number cut, or -1 when out of memory. */
static int64_t shrink_straying(sampler *S, const facet_list *facets, double *old_r,
                               unsigned char *shrunk)
{
    const double bound = DEVIATION_BOUND * S->z.eps;
    if (!isfinite(bound) || facets->n == 0)
        return 0;
    unsigned char *strays = malloc((size_t)facets->n);
    if (!strays)
        return -1;
#pragma omp parallel num_threads(S->threads)
    {
        /* the triangle near the last probe is tried first: the next
         * probes, and the next facet's (facets in ball order are
         * neighbours), are mostly near it too; the answers are the same
         * (cow.off's pass 0.21 -> 0.03 s, bunny.off's 0.10 -> 0.02 s) */
        int64_t hint = -1;
#pragma omp for schedule(dynamic, 256)
        for (int64_t f = 0; f < facets->n; f++)
            strays[f] = (unsigned char)facet_strays(S, facets->f[f].v, bound, &hint);
    }
    memcpy(old_r, S->bs.b.radius, sizeof(double) * (size_t)S->bs.b.n);
    int64_t changed = 0;
    for (int64_t f = 0; f < facets->n && changed >= 0; f++)
        for (int k = 0; k < 3 && strays[f] && changed >= 0; k++)
            changed = cut_once(S, facets->f[f].v[k], DEVIATION_SHRINK, shrunk, changed);
    free(strays);
    return changed;
}

/* The other direction: an input vertex farther than the bound from every
 * facet of the balls that hold it. Where a crease or fold turns at a
 * vertex the facets cut the corner off, on the input's own plane (a cap's
 * rim of a coarse prism: 1.2 times the error bound), which no probe of a
 * facet sees. The balls holding such a vertex are cut like those of a
 * straying facet. Facets per ball: CSR from the facet list. */
typedef struct holding_ctx {
    const vc_balls *b;
    const double *x;
    int64_t *ids;
    int n, cap;
} holding_ctx;

static int collect_holding(void *ctx, int64_t i)
{
    holding_ctx *h = ctx;
    if (dist(h->b->center + 3 * i, h->x) <= h->b->radius[i] && h->n < h->cap)
        h->ids[h->n++] = i;
    return 0;
}

#define HOLDING_MAX 64

static int64_t shrink_far_vertices(sampler *S, const facet_list *facets, double *old_r,
                                   unsigned char *shrunk)
{
    const double bound = DEVIATION_BOUND * S->z.eps;
    const vc_surface *s = S->s;
    const int64_t nb = S->bs.b.n, nv = s->n_vertices;
    if (!isfinite(bound) || facets->n == 0 || nv == 0)
        return 0;
    /* the facets at each ball */
    int64_t *start, *of;
    unsigned char *far = calloc((size_t)nv, 1);
    int64_t *fv = facet_balls(facets);
    if (!far || !fv || vc_csr_group(fv, facets->n, 3, nb, NULL, &start, &of)) {
        free(far);
        free(fv);
        return -1;
    }
    free(fv);
    const vc_balls *b = &S->bs.b;
#pragma omp parallel for schedule(dynamic, 256) num_threads(S->threads)
    for (int64_t v = 0; v < nv; v++) {
        const double *x = s->xyz + 3 * v;
        int64_t ids[HOLDING_MAX];
        holding_ctx h = {b, x, ids, 0, HOLDING_MAX};
        vc_ball_set_query(&S->bs, x, 0, 1.0, 0.0, collect_holding, &h);
        double best2 = INFINITY;
        for (int m = 0; m < h.n && best2 > bound * bound; m++)
            for (int64_t q = start[ids[m]]; q < start[ids[m] + 1] && best2 > bound * bound; q++) {
                const int64_t *t = facets->f[of[q]].v;
                best2 = fmin(best2, vc_closest_on_triangle(x, b->center + 3 * t[0], b->center + 3 * t[1],
                                                           b->center + 3 * t[2], NULL));
            }
        far[v] = h.n > 0 && best2 > bound * bound;
    }
    free(start);
    free(of);
    memcpy(old_r, S->bs.b.radius, sizeof(double) * (size_t)nb);
    int64_t changed = 0;
    for (int64_t v = 0; v < nv && changed >= 0; v++) {
        if (!far[v])
            continue;
        int64_t ids[HOLDING_MAX];
        holding_ctx h = {b, s->xyz + 3 * v, ids, 0, HOLDING_MAX};
        vc_ball_set_query(&S->bs, s->xyz + 3 * v, 0, 1.0, 0.0, collect_holding, &h);
        /* the query's order is the index's: cut in ball order */
        for (int m = 1; m < h.n; m++)
            for (int j = m; j > 0 && ids[j - 1] > ids[j]; j--) {
                const int64_t t = ids[j];
                ids[j] = ids[j - 1];
                ids[j - 1] = t;
            }
        for (int m = 0; m < h.n && changed >= 0; m++)
            changed = cut_once(S, ids[m], DEVIATION_SHRINK, shrunk, changed);
    }
    free(far);
    return changed;
}

/* ---------------------------------------------------------------------
 * Pinches.
 *
 * With no half-covered pair left, the facets still meet four to an edge at
 * a few places of a faceted input: where it folds by nearly theta_sharp
 * (bunny.off: three spots with folds of 47 to 58 degrees; fertility.off:
 * one). There two sheets of facets touch, and the reconstructed surface is
 * not a 2-manifold. Smaller balls follow the fold: both balls of every
 * edge that is not in exactly two facets are cut to PINCH_SHRINK of their
 * radius, and the sampling runs again around them, up to PINCH_PASSES
 * times; what is left the mesh command reports as an error. */
#define PINCH_SHRINK 0.7
#define PINCH_PASSES 8


/* Do the n link edges {b, facet} of one ball (undirected: the facets are
 * not oriented) form a single cycle? Reorders them along the walk. */
static int one_cycle(edge_rec *l, int64_t n)
{
    if (n < 3)
        return 0;
    const int64_t start = l[0].b;
    int64_t at = l[0].facet;
    for (int64_t i = 1; i < n; i++) {
        int64_t k = i;
        while (k < n && l[k].b != at && l[k].facet != at)
            k++;
        if (k == n)
            return 0;
        edge_rec t = l[i];
        l[i] = l[k];
        l[k] = t;
        at = l[i].b == at ? l[i].facet : l[i].b;
    }
    return at == start;
}

/* Balls on a non-manifold edge of the input, or at a corner of one: their
 * facets meet as the input's sheets do (three or more to an edge between
 * two such balls, a link of several cycles), which is no pinch. Fills nm
 * (one byte per ball); returns whether any is set. */
static int mark_nonmanifold_balls(const sampler *S, unsigned char *nm_vertex, unsigned char *nm)
{
    const vc_features *f = S->f;
    const vc_balls *B = &S->bs.b;
    int any = 0;
    memset(nm_vertex, 0, (size_t)f->n_vertices + 1);
    for (int64_t e = 0; e < f->n_edges; e++)
        if (f->edge_sharp[e] & VC_SHARP_NONMANIFOLD) {
            nm_vertex[f->edge_vertex[2 * e]] = nm_vertex[f->edge_vertex[2 * e + 1]] = 1;
            any = 1;
        }
    for (int64_t q = 0; q < B->n; q++)
        nm[q] = any && ((B->kind[q] == VC_BALL_EDGE &&
                         (f->edge_sharp[B->element[q]] & VC_SHARP_NONMANIFOLD)) ||
                        (B->kind[q] == VC_BALL_CORNER && nm_vertex[B->element[q]]));
    return any;
}

static int64_t shrink_pinches(sampler *S, const facet_list *facets, double *old_r,
                              unsigned char *shrunk)
{
    const facet_list fl = *facets;
    edge_rec *e = sorted_edges(&fl);
    unsigned char *nm = malloc((size_t)S->bs.b.n + 1);
    unsigned char *nm_vertex = malloc((size_t)S->f->n_vertices + 1);
    if (!e || !nm || !nm_vertex) {
        free(e);
        free(nm);
        free(nm_vertex);
        return -1;
    }
    mark_nonmanifold_balls(S, nm_vertex, nm);
    free(nm_vertex);
    vc_balls *B = &S->bs.b;
    memcpy(old_r, B->radius, sizeof(double) * (size_t)B->n);
    int64_t changed = 0;
    for (int64_t m = 0; m < 3 * fl.n && changed >= 0;) {
        int64_t m2 = m;
        while (m2 < 3 * fl.n && e[m2].a == e[m].a && e[m2].b == e[m].b)
            m2++;
        if (m2 - m != 2 && !(nm[e[m].a] && nm[e[m].b])) {
            const int64_t ends[2] = {e[m].a, e[m].b};
            for (int k = 0; k < 2 && changed >= 0; k++)
                changed = cut_once(S, ends[k], PINCH_SHRINK, shrunk, changed);
        }
        m = m2;
    }
    /* vertices whose facets make more than one fan: the link of every ball
     * (the edge opposite it in each of its facets) must be one cycle */
    for (int64_t f = 0; f < fl.n; f++)
        for (int k = 0; k < 3; k++)
            e[3 * f + k] = (edge_rec){fl.f[f].v[k], fl.f[f].v[(k + 1) % 3], fl.f[f].v[(k + 2) % 3]};
    sort_edge_recs(e, 3 * fl.n);
    for (int64_t m = 0; m < 3 * fl.n && changed >= 0;) {
        int64_t m2 = m;
        while (m2 < 3 * fl.n && e[m2].a == e[m].a)
            m2++;
        if (!nm[e[m].a] && !one_cycle(e + m, m2 - m)) {
            /* the ball and the balls of its link */
            for (int64_t k = m; k <= m2 && changed >= 0; k++)
                changed = cut_once(S, k == m2 ? e[m].a : e[k].b, PINCH_SHRINK, shrunk, changed);
        }
        m = m2;
    }
    free(e);
    free(nm);
    return changed;
}

/* ---------------------------------------------------------------------
 * The driver */

void vc_sampling_options_default(vc_sampling_options *opt)
{
    opt->sharp_angle = VC_FEATURES_DEFAULT_SHARP_ANGLE;
    opt->max_error = 0.004;
    opt->lipschitz = 0.25;
    opt->max_size = 0;
    opt->alpha = 1 - sqrt(3.0) / 2;
    opt->seed = 1;
    opt->threads = 0;
    opt->log = NULL;
    opt->max_sliver_iterations = 100;
    opt->max_balls = 0;
    opt->stuck_tri = NULL;
    opt->fold_stop_angle = 0;
    opt->smooth_width = 0;
    opt->curvature_factor = 0.2;
    opt->lift_centres = 1;
    opt->quartet_gap = 0;
}

void vc_balls_free(vc_balls *b)
{
    free(b->center);
    free(b->radius);
    free(b->kind);
    free(b->element);
    free(b->normal);
    memset(b, 0, sizeof *b);
}

/* The triangles the balls shrunk by the last sliver pass reached before
 * (where sliver elimination is stuck), into stuck (n_triangles bytes). */
static void mark_stuck(const sampler *S, const unsigned char *shrunk, const double *old_r,
                       unsigned char *stuck)
{
    memset(stuck, 0, (size_t)S->s->n_triangles);
    unsigned char *me = calloc((size_t)S->f->n_edges + 1, 1);
    if (!me)
        return;
    near_ctx nc = {me, stuck};
    for (int64_t i = 0; i < S->bs.b.n; i++)
        if (shrunk[i])
            vc_sizing_elements_near(&S->z, S->bs.b.center + 3 * i, old_r[i], mark_near, &nc);
    free(me);
}

/* Whether a stuck triangle has an edge that is not sharp and folds by more
 * than the angle whose cosine is cos_fold. */
static int stuck_at_fold(const sampler *S, const unsigned char *stuck, double cos_fold)
{
    const vc_features *f = S->f;
    for (int64_t t = 0; t < S->s->n_triangles; t++) {
        if (!stuck[t])
            continue;
        const int64_t *v = S->s->tri + 3 * t;
        for (int k = 0; k < 3; k++) {
            int64_t e = vc_features_find_edge(f, v[k], v[(k + 1) % 3]);
            if (e >= 0 && vc_features_fold_cos(f, e) < cos_fold)
                return 1;
        }
    }
    return 0;
}

static int grow_scratch(double **old_r, unsigned char **shrunk, int64_t n)
{
    double *a = realloc(*old_r, sizeof(double) * (size_t)(n ? n : 1));
    if (!a)
        return -1;
    *old_r = a;
    unsigned char *s = realloc(*shrunk, (size_t)(n ? n : 1));
    if (!s)
        return -1;
    *shrunk = s;
    memset(s, 0, (size_t)n);
    return 0;
}

/* enforce_lipschitz_after, then the resampling of what the shrunk balls
 * uncovered; 0, or -1 when out of memory. */
static int lipschitz_then_resample(sampler *S, double *old_r, unsigned char *shrunk)
{
    S->cover_alpha = S->alpha / 2; /* from the first shrinking pass on (top of the file) */
    const double ta = vc_clock_seconds();
    const int64_t nl = enforce_lipschitz_after(S, old_r, shrunk);
    S->st->t_lipschitz += vc_clock_seconds() - ta;
    if (nl < 0)
        return -1;
    S->st->n_shrunk_lipschitz += nl;
    const double tr = vc_clock_seconds();
    const int rc = resample_around(S, old_r, shrunk);
    vc_log(S->opt.log, VC_LOG_DEBUG, "  sampling: %lld more balls shrunk for Lipschitz, resampled "
           "to %lld balls (%.3f s)", (long long)nl, (long long)S->bs.b.n, vc_clock_seconds() - tr);
    return rc;
}

/* The thesis' safe mode (6.2.8): deep coverage at alpha / 2, under which
 * sliver elimination terminates; the sampling after shrinking already asks
 * for no more than that, so the safe mode halves it again (and the spacing
 * of new balls with it). Returns the pass it began at. */
static int enter_safe_mode(sampler *S, int iter)
{
    S->st->safe_mode = 1;
    S->alpha = S->opt.alpha / 2;
    S->cover_alpha = S->alpha / 2;
    return iter;
}

int vc_sample_surface(const vc_surface *s, const vc_features *f,
                      const vc_sampling_options *opt, vc_balls *out,
                      vc_sampling_stats *stats, vc_error *err)
{
    memset(out, 0, sizeof *out);
    vc_sampling_stats local;
    vc_sampling_stats *st = stats ? stats : &local;
    memset(st, 0, sizeof *st);
    if (!(opt->lipschitz > 0 && opt->lipschitz < 1))
        return vc_error_set(err, VC_EPARAM, "--lipschitz must be in (0, 1), got %g", opt->lipschitz);
    if (!(opt->sharp_angle > 0 && opt->sharp_angle < 180))
        return vc_error_set(err, VC_EPARAM, "--sharp-angle must be in (0, 180), got %g",
                            opt->sharp_angle);
    if (!(opt->max_error < 1) || !isfinite(opt->max_error))
        return vc_error_set(err, VC_EPARAM, "--max-error must be below 1, got %g", opt->max_error);
    if (!(opt->alpha > 0 && opt->alpha < 1))
        return vc_error_set(err, VC_EPARAM, "alpha must be in (0, 1), got %g", opt->alpha);
    if (!(opt->max_size >= 0) || !isfinite(opt->max_size))
        return vc_error_set(err, VC_EPARAM, "--max-size must be a positive number, got %g",
                            opt->max_size);
    if (f->n_boundary_edges > 0)
        return vc_error_set(err, VC_EINPUT,
                            "the surface is open: %lld boundary edges (VoroCrust needs a "
                            "closed surface)", (long long)f->n_boundary_edges);

    sampler S;
    memset(&S, 0, sizeof S);
    S.threads = vc_threads_or_default(opt->threads);
    S.s = s;
    S.f = f;
    S.opt = *opt;
    S.alpha = opt->alpha;
    S.cover_alpha = opt->alpha;
    S.st = st;
    vc_rng_init(&S.rng, opt->seed, 0);
    double t0 = vc_clock_seconds();
    /* a large input's sizing takes seconds (a million triangles: the tree
     * 0.4 s, the prediction's radius bounds 1.5 s on 2 threads): said
     * first, so that no more than 2 s pass without a line */
    const int large = s->n_triangles >= VC_LARGE_INPUT_TRIANGLES;
    if (large)
        vc_log(opt->log, VC_LOG_INFO, "mesh: sizing %lld triangles: their tree", (long long)s->n_triangles);
    if (vc_sizing_init(&S.z, s, f, opt->sharp_angle, opt->max_error))
        return vc_error_set(err, VC_ENOMEM, "out of memory for the sizing structures");
    S.sz = opt->max_size > 0 ? opt->max_size : S.z.diag;
    double lo[3] = {INFINITY, INFINITY, INFINITY};
    for (int64_t v = 0; v < s->n_vertices; v++)
        for (int d = 0; d < 3; d++)
            lo[d] = fmin(lo[d], s->xyz[3 * v + d]);
    if (vc_ball_set_init(&S.bs, lo, S.z.diag)) {
        vc_sizing_free(&S.z);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the balls");
    }
    S.t_start = S.t_logged = t0;
    if (opt->smooth_width > 0 && isfinite(S.z.eps)) {
        if (vc_smooth_surface_init(&S.ss, &S.z, opt->smooth_width * S.z.eps)) {
            vc_ball_set_free(&S.bs);
            vc_sizing_free(&S.z);
            return vc_error_set(err, VC_ENOMEM, "out of memory for the smooth surface");
        }
        S.smooth = 1;
        S.tri_on_smooth = malloc(sizeof(double) * 19 * (size_t)(s->n_triangles ? s->n_triangles : 1));
        if (!S.tri_on_smooth) {
            vc_smooth_surface_free(&S.ss);
            vc_ball_set_free(&S.bs);
            vc_sizing_free(&S.z);
            return vc_error_set(err, VC_ENOMEM, "out of memory for the smooth surface");
        }
#pragma omp parallel for schedule(dynamic, 256) num_threads(S.threads)
        for (int64_t t = 0; t < s->n_triangles; t++) {
            int blended = 0;
            for (int k = 0; k < 3; k++) {
                const double *x = s->xyz + 3 * s->tri[3 * t + k];
                double rho;
                blended |= vc_smooth_surface_project(&S.ss, t, x, x, S.tri_on_smooth + 19 * t + 3 * k,
                                                     S.tri_on_smooth + 19 * t + 9 + 3 * k, &rho) == 1;
            }
            S.tri_on_smooth[19 * t + 18] = blended;
        }
    }

    /* The work predicted from the sizing, said before any is done, and
     * refused when it exceeds the limit. */
    if (large)
        vc_log(opt->log, VC_LOG_INFO, "mesh: sizing %lld triangles: the radius bound at a sample of them",
               (long long)s->n_triangles);
    vc_ball_estimate est;
    if (vc_ball_estimate_compute(&S.z, S.sz, opt->threads, &est)) {
        vc_ball_set_free(&S.bs);
        vc_smooth_surface_free(&S.ss);
        free(S.tri_on_smooth);
        vc_sizing_free(&S.z);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the ball estimate");
    }
    st->n_balls_predicted = est.n_balls;
    S.runaway_at = (int64_t)fmax(RUNAWAY * est.n_balls, RUNAWAY_MIN);
    st->t_sizing = vc_clock_seconds() - t0; /* the sizing structures and the prediction */
    vc_log(opt->log, VC_LOG_INFO,
           "mesh: sampling %lld triangles: about %.3g balls predicted from the sizing "
           "(radius bound %.3g to %.3g)", (long long)s->n_triangles, est.n_balls, est.r_min,
           S.sz);
    if (opt->max_balls > 0 && !(est.n_balls <= (double)opt->max_balls)) {
        const double diag = S.z.diag;
        /* a surface folded at most of its edges (a coarse twisted
         * extrusion, a crumpled mesh) is creases everywhere: where that
         * brings the radii a hundred times below the bound, say so, it is
         * the likeliest cause */
        char folded[320] = "";
        if (f->n_edges > 0 && 2 * f->n_sharp_edges > f->n_edges && est.r_min < 0.01 * S.z.eps)
            snprintf(folded, sizeof folded,
                     "; %lld of its %lld edges fold by more than the sharp angle: a surface "
                     "creased at most of its edges needs balls below its facets' size (a finer "
                     "or smoother tessellation of it would not)",
                     (long long)f->n_sharp_edges, (long long)f->n_edges);
        vc_ball_set_free(&S.bs);
        vc_smooth_surface_free(&S.ss);
        free(S.tri_on_smooth);
        vc_sizing_free(&S.z);
        return vc_error_set(err, VC_EPARAM,
                            "about %.3g balls predicted from the sizing, above the limit of "
                            "%lld: radius bounds down to %.3g (near %.6g %.6g %.6g) for a "
                            "surface of diagonal %.3g; raise the limit (--max-balls), or the "
                            "largest radius (--max-size) or the error bound (--max-error)%s",
                            est.n_balls, (long long)opt->max_balls, est.r_min, est.r_min_at[0],
                            est.r_min_at[1], est.r_min_at[2], diag, folded);
    }

    int rc = 0;
    double *old_r = NULL;
    unsigned char *shrunk = NULL;

    /* Phase 1: one ball per sharp corner, then C3 among them. */
    t0 = vc_clock_seconds();
    for (int64_t v = 0; v < s->n_vertices && !rc; v++) {
        if (!f->vertex_corner[v])
            continue;
        vc_surface_point sp = {VC_ELEM_CORNER, v};
        const double *x = s->xyz + 3 * v;
        double r = vc_sizing_radius_bound(&S.z, &sp, x, S.sz);
        rc = add_ball(&S, x, r, &sp, NULL);
    }
    if (!rc && (rc = grow_scratch(&old_r, &shrunk, S.bs.b.n)) == 0)
        rc = enforce_lipschitz(&S, old_r, shrunk) < 0 ? -1 : 0;
    st->t_corners = vc_clock_seconds() - t0;

    /* Phases 2 and 3: creases, then patches. */
    S.phase = "first coverage";
    if (!rc)
        rc = sample_strata(&S, NULL, NULL);
    S.phase = "sampling around shrunk balls";
    if (!rc)
        vc_log(opt->log, VC_LOG_INFO, "mesh: %lld balls after the first coverage",
               (long long)S.bs.b.n);
    const int64_t n_first = S.bs.b.n;
    int diverged = 0, rising = 0;
    double tiny_ball = 0, tiny_rel = 0; /* a ball's radius below TINY_BALL, and over the bound */
    int safe_from = opt->max_sliver_iterations; /* the pass the safe mode began at */
    /* the pairs one and two passes ago (valid from pass 2 and 3), the
     * balls after the last pass and the balls it added */
    int64_t half_1 = 0, half_2 = 0, balls_1 = n_first, added_1 = 0;
    double where[3] = {0, 0, 0};

    /* Lipschitz fixes and sliver elimination, sampling again after every
     * shrinking, until nothing changes; then the flat-facet pass and the
     * same again, up to FLAT_PASSES times. */
    int iter = 0, flat_passes = 0, pinch_passes = 0, deviation_passes = 0;
    facet_list facets = {NULL, 0, 0, 0};
    int facets_of_all = 0; /* facets holds a scan of every triplet of the balls as they are */
    while (!rc) {
        double ta = vc_clock_seconds();
        if (grow_scratch(&old_r, &shrunk, S.bs.b.n)) {
            rc = -1;
            break;
        }
        int64_t nl = enforce_lipschitz(&S, old_r, shrunk);
        st->t_lipschitz += vc_clock_seconds() - ta;
        if (nl < 0) {
            rc = -1;
            break;
        }
        st->n_shrunk_lipschitz += nl;
        if (nl > 0) {
            const double tr = vc_clock_seconds();
            rc = resample_around(&S, old_r, shrunk);
            vc_log(opt->log, VC_LOG_DEBUG, "  sampling: %lld balls shrunk for Lipschitz (%.3f s), "
                   "resampled to %lld balls (%.3f s)", (long long)nl, tr - ta,
                   (long long)S.bs.b.n, vc_clock_seconds() - tr);
            continue;
        }
        double tb = vc_clock_seconds();
        int64_t n_half = 0;
        /* only the triplets near balls added or resized since the last
         * scan can have changed (the facets of the others are kept); once
         * no pass has anything left to do, every triplet once more: that
         * proves it for all of them */
        int64_t ns = eliminate_slivers(&S, old_r, shrunk, &n_half, where, &facets, 0);
        st->t_slivers += vc_clock_seconds() - tb;
        vc_log(opt->log, VC_LOG_DEBUG, "  sampling: triplet scan %.3f s", vc_clock_seconds() - tb);
        if (ns < 0) {
            rc = -1;
            break;
        }
        st->n_half_covered = n_half;
        if (ns == 0 && flat_passes < FLAT_PASSES) {
            /* converged: work on the flat facets, then go round again */
            flat_passes++;
            double tf = vc_clock_seconds();
            int64_t nf = unflatten_facets(&S, &facets, old_r, shrunk);
            st->t_slivers += vc_clock_seconds() - tf;
            if (nf < 0) {
                rc = -1;
                break;
            }
            if (nf > 0) {
                st->n_shrunk_flat += nf;
                vc_log(opt->log, VC_LOG_INFO, "mesh: flat facets %d: %lld balls shrunk",
                       flat_passes, (long long)nf);
                rc = lipschitz_then_resample(&S, old_r, shrunk);
                continue;
            }
        }
        if (ns == 0 && deviation_passes < DEVIATION_PASSES) {
            deviation_passes++;
            int64_t nd = shrink_straying(&S, &facets, old_r, shrunk);
            if (nd == 0)
                nd = shrink_far_vertices(&S, &facets, old_r, shrunk);
            if (nd < 0) {
                rc = -1;
                break;
            }
            if (nd == 0) {
                deviation_passes = DEVIATION_PASSES; /* smaller balls only come nearer */
            } else {
                st->n_shrunk_deviation += nd;
                vc_log(opt->log, VC_LOG_INFO,
                       "mesh: facets and input farther apart than the error bound %d: %lld balls "
                       "shrunk", deviation_passes, (long long)nd);
                rc = lipschitz_then_resample(&S, old_r, shrunk);
                continue;
            }
        }
        if (ns == 0 && pinch_passes < PINCH_PASSES) {
            pinch_passes++;
            int64_t np = shrink_pinches(&S, &facets, old_r, shrunk);
            if (np < 0) {
                rc = -1;
                break;
            }
            if (np > 0) {
                st->n_shrunk_pinch += np;
                vc_log(opt->log, VC_LOG_INFO, "mesh: pinches %d: %lld balls shrunk", pinch_passes,
                       (long long)np);
                rc = lipschitz_then_resample(&S, old_r, shrunk);
                continue;
            }
        }
        if (ns == 0) {
            tb = vc_clock_seconds();
            /* seconds on a large ball set (a cup's 169,000 balls) */
            if (S.bs.b.n >= LARGE_SCAN)
                vc_log(opt->log, VC_LOG_INFO, "mesh: sliver elimination: every triplet of %lld "
                       "balls once more", (long long)S.bs.b.n);
            ns = eliminate_slivers(&S, old_r, shrunk, &n_half, where, &facets, 1);
            st->t_slivers += vc_clock_seconds() - tb;
            if (ns < 0) {
                rc = -1;
                break;
            }
            st->n_half_covered = n_half;
            if (ns == 0) {
                facets_of_all = 1;
                break;
            }
        }
        st->n_shrunk_sliver += ns;
        iter++;
        st->sliver_iterations = iter;
        vc_log(opt->log, VC_LOG_INFO, "mesh: sliver elimination %d: %lld half-covered pairs, "
               "%lld balls shrunk, %lld balls", iter, (long long)n_half, (long long)ns,
               (long long)S.bs.b.n);
        if (S.z.eps > 0) {
            const int64_t smallest = smallest_ball(&S.bs.b, shrunk);
            if (smallest >= 0 && S.bs.b.radius[smallest] < TINY_BALL * S.z.eps) {
                tiny_ball = S.bs.b.radius[smallest];
                tiny_rel = tiny_ball / S.z.eps;
                memcpy(where, S.bs.b.center + 3 * smallest, sizeof where);
                diverged = 1;
                break;
            }
        }
        /* Sliver elimination normally removes most half-covered pairs at
         * every pass and adds a fraction of the balls; four passes in a row
         * with more half-covered pairs, or an eightfold ball count, mean it
         * does not converge (folds sharper than the smoothness the sampling
         * needs, but below theta_sharp): stop with an explanation rather
         * than run on. */
        rising = iter >= 2 && n_half > half_1 ? rising + 1 : 0;
        /* Two rising passes with a fifth of the balls in half-covered
         * pairs: the whole surface bends too much at the scale of the
         * balls (a coarse tessellation of a curved shape), no need to wait
         * for four. */
        /* No decay, and no slowing down: a fold sliver elimination cannot
         * follow keeps the half-covered pairs level and adds as many balls
         * at every pass, or more (the 200-triangle torus at 60 degrees:
         * 2,448, 2,528, 2,522 pairs, 4,775, 7,262, 13,146, 19,008 balls, and
         * on for four more passes of growing cost). A converging elimination
         * removes a third of the pairs per two passes or adds fewer balls
         * at every pass (a Loop-smoothed 60-triangle torus: 246, 184, 180
         * pairs while the balls grow by 159, 95, 75; it converges at pass
         * 22). Only once the balls more than doubled, and while a pass
         * adds a tenth of them (the small counts of the last passes of a
         * converging elimination go up and down). */
        const int64_t added = S.bs.b.n - balls_1;
        int stalled = S.bs.b.n > 2 * n_first + 1000 && added >= added_1 && 10 * added >= S.bs.b.n &&
                      ((iter == 2 && n_half > half_1) || (iter >= 3 && 10 * n_half > 7 * half_2));
        const int runaway = S.bs.b.n > 8 * n_first + 1000;
        if (stalled || rising >= 4 || (rising >= 2 && 5 * n_half > S.bs.b.n) || runaway) {
            /* A local struggle (under 2% of the balls in half-covered
             * pairs, the balls not running away) is what the safe mode is
             * for: with alpha halved sliver elimination terminates (thesis
             * 6.2.8). Enter it now rather than stop: the pairs left at a
             * noisy pole went 16, 42, 38, 42, 48, 60, 104 over seven passes
             * of a sphere with 3% noise, which the safe mode ended in five
             * passes with another random seed. Only a struggle in the safe
             * mode, or a global one, stops. */
            if (!st->safe_mode && !runaway && 50 * n_half < S.bs.b.n) {
                safe_from = enter_safe_mode(&S, iter);
                rising = 0;
                vc_log(opt->log, VC_LOG_INFO, "mesh: sliver elimination %d: %lld half-covered "
                       "pairs left rising: safe mode (alpha / 2)", iter, (long long)n_half);
            } else {
                diverged = 1;
                break;
            }
        }
        /* With fold_stop_angle: stop as soon as the half-covered pairs stop
         * halving per pass once the balls have doubled, if they are stuck
         * at a fold the caller can make a crease. */
        if (opt->fold_stop_angle > 0 && opt->stuck_tri && iter >= 2 && n_half > 0 &&
            2 * n_half > half_1 && S.bs.b.n > 2 * n_first) {
            mark_stuck(&S, shrunk, old_r, opt->stuck_tri);
            if (stuck_at_fold(&S, opt->stuck_tri, cos(opt->fold_stop_angle * 3.14159265358979323846 / 180.0))) {
                diverged = 1;
                break;
            }
        }
        half_2 = half_1;
        half_1 = n_half;
        added_1 = added;
        balls_1 = S.bs.b.n;
        if (iter == opt->max_sliver_iterations && !st->safe_mode) {
            safe_from = enter_safe_mode(&S, iter);
        } else if (iter >= safe_from + opt->max_sliver_iterations) {
            /* the safe mode did not end it either: not converging */
            diverged = 1;
            break;
        }
        rc = lipschitz_then_resample(&S, old_r, shrunk);
    }
    if (diverged && opt->stuck_tri)
        mark_stuck(&S, shrunk, old_r, opt->stuck_tri);
    if (!rc && !diverged && opt->lift_centres && st->n_half_covered == 0 && facets.n > 0) {
        double tl = vc_clock_seconds();
        vc_lift_result lr;
        memset(&lr, 0, sizeof lr);
        /* when the last scan was of every triplet of these balls, its
         * facets and clearances are the lift's reference (the lift does
         * not scan for it again) */
        int64_t *fv = facet_balls(&facets);
        double *fclear = facets_of_all ? malloc(sizeof(double) * (size_t)(facets.n + 1)) : NULL;
        if (!fv || (facets_of_all && !fclear))
            rc = -1;
        for (int64_t f = 0; !rc && fclear && f < facets.n; f++)
            fclear[f] = facets.f[f].clear;
        if (!rc)
            rc = vc_lift_centres(&S.bs.b, fv, fclear, facets.n, &S.z, S.opt.threads, opt->log,
                                 &lr);
        free(fv);
        free(fclear);
        st->t_lift = vc_clock_seconds() - tl;
        st->n_lifted = lr.n_lifted;
        st->n_lift_reduced = lr.n_reduced;
        st->lift_rounds = lr.rounds;
        st->lift_passes = lr.passes;
        st->lift_dropped = lr.dropped;
        st->lift_mean_rel = lr.mean_rel;
        st->lift_max_rel = lr.max_rel;
        if (!rc)
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: centre lift: %lld balls moved by %.3g of their radius on average "
                   "(largest %.3g), %lld reduced, %d passes, %d checks%s, %.2f s",
                   (long long)lr.n_lifted, lr.mean_rel, lr.max_rel, (long long)lr.n_reduced,
                   lr.passes, lr.rounds, lr.dropped ? ", every lift dropped" : "", st->t_lift);
    }
    free(old_r);
    free(shrunk);
    free(facets.f);
    free(S.dirty);
    vc_smooth_surface_free(&S.ss);
    free(S.tri_on_smooth);
    vc_sizing_free(&S.z);
    if (rc && S.runaway && !S.oom) {
        /* where the balls are smallest (there are RUNAWAY_MIN of them) */
        const int64_t smallest = smallest_ball(&S.bs.b, NULL), nb = S.bs.b.n;
        const double *at = S.bs.b.center + 3 * smallest, r_small = S.bs.b.radius[smallest];
        st->diverged = 1;
        st->n_balls_diverged = nb;
        const int e = vc_error_set(err, VC_EINPUT,
                            "the sampling does not converge (%lld balls in the %s, %.0f times the %.3g "
                            "predicted from the sizing; the smallest, of radius %.3g, near (%.6g, %.6g, "
                            "%.6g)): the surface bends there more sharply than the sampling can follow "
                            "without a crease; try a smaller --sharp-angle (e.g. 20)",
                            (long long)nb, S.phase, RUNAWAY, est.n_balls, r_small, at[0], at[1], at[2]);
        vc_ball_set_free(&S.bs);
        return e;
    }
    if (rc) {
        vc_ball_set_free(&S.bs);
        if (S.too_many)
            return vc_error_set(err, VC_EPARAM,
                                "the sampling reached the limit of %lld balls (%.3g were "
                                "predicted from the sizing) and stopped; raise the limit "
                                "(--max-balls), or the largest radius (--max-size) or the error "
                                "bound (--max-error)",
                                (long long)opt->max_balls, est.n_balls);
        return vc_error_set(err, VC_ENOMEM, "out of memory while sampling the surface");
    }
    if (diverged) {
        int64_t nb = S.bs.b.n;
        st->diverged = 1;
        st->n_balls_diverged = nb;
        vc_ball_set_free(&S.bs);
        char what[96] = "half-covered seed pairs";
        if (tiny_ball > 0)
            snprintf(what, sizeof what, "a ball shrunk to %.3g, %.2g of the error bound,", tiny_ball,
                     tiny_rel);
        return vc_error_set(err, VC_EINPUT,
                            "sliver elimination does not converge (%lld balls after %d iterations, "
                            "from %lld; %s near (%.6g, %.6g, %.6g)): the surface bends there more "
                            "sharply than the sampling can follow without a crease; try a smaller "
                            "--sharp-angle (e.g. 20)",
                            (long long)nb, iter, (long long)n_first, what, where[0], where[1],
                            where[2]);
    }
    /* hand the balls over, trimmed */
    *out = S.bs.b;
    memset(&S.bs.b, 0, sizeof S.bs.b);
    vc_ball_set_free(&S.bs);
    for (int64_t i = 0; i < out->n; i++) {
        if (out->kind[i] == VC_BALL_CORNER)
            st->n_corner++;
        else if (out->kind[i] == VC_BALL_EDGE)
            st->n_edge++;
        else
            st->n_surface++;
    }
    return 0;
}
