/* Turned-over needles (vc_surface_flip_turned_needles).
 *
 * A needle is a triangle (w, u, v) whose apex w lies close to its longest
 * edge u v. When w has crossed that edge, the needle faces the other way
 * from the triangle (v, u, o) across it: the surface folds back on itself
 * by nearly 180 degrees over a width of the apex's height h, a pleat that
 * decimation and scan meshing leave (cow.off has two, with h a seventh and a
 * quarter of the error bound). No ball sampling follows such a pleat: the
 * sizing sees two sheets h apart and sliver elimination runs away there.
 *
 * Flipping the edge u v (the triangles become (w, u, o) and (w, o, v))
 * removes the pleat, and moves the surface by at most h: every point of the
 * old pair lies within h of the new pair and back, since the path u w v
 * stays within h of the segment u v and both pairs are the cones from o
 * over these (plus the needle itself, within h of the path). So a flip is
 * made only where h is at most the caller's max_move (a part of the error
 * bound), the new triangles do not fold by 90 degrees or more against each
 * other, the largest fold of the five edges involved goes down, the new
 * edge w o is not already an edge, and both triangles carry one group.
 * Rounds over the triangles in index order until one flips nothing (at most
 * MAX_ROUNDS): the result does not depend on anything but the input. */
#include "vorocrust/surface.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ROUNDS 8
/* A needle standing up like a fin, folding against the triangle across its
 * long edge by 60 to 90 degrees (a T-junction closed by a sliver whose apex
 * is off the edge: a sphere with twenty such, apexes 1e-6 off, was
 * predicted 2.8e9 balls), is flipped too when its height is at most
 * FIN_SHARE of max_move (a tenth of the error bound for vc_mesh's half):
 * far below what the mesh shows; a turned-over one (past 90 degrees) up
 * to max_move. */
#define FIN_FOLD_COS 0.5
#define FIN_SHARE 0.2

/* Open-addressing table from an edge (a < b) to its one or two triangles;
 * t[1] == -2 marks an edge of more than two triangles (never flipped). A
 * removed edge keeps its slot as a tombstone (a = -1). */
typedef struct edge_slot {
    int64_t a, b;
    int64_t t[2];
} edge_slot;

typedef struct edge_table {
    edge_slot *slot;
    size_t mask;
} edge_table;

static size_t edge_hash(int64_t a, int64_t b)
{
    uint64_t h = (uint64_t)a * 0x9E3779B97F4A7C15ull ^ ((uint64_t)b + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full;
    return (size_t)(h ^ (h >> 29));
}

static edge_slot *edge_find(const edge_table *e, int64_t a, int64_t b)
{
    if (a > b) {
        int64_t x = a;
        a = b;
        b = x;
    }
    for (size_t i = edge_hash(a, b) & e->mask;; i = (i + 1) & e->mask) {
        edge_slot *s = &e->slot[i];
        if (s->a == a && s->b == b)
            return s;
        if (s->a == -2) /* never used: the end of the probe */
            return NULL;
    }
}

/* The slot of edge (a, b), made if absent (the table never fills: it has
 * at least two slots per edge, and a flip adds one edge for the one it
 * removes). */
static edge_slot *edge_insert(edge_table *e, int64_t a, int64_t b)
{
    if (a > b) {
        int64_t x = a;
        a = b;
        b = x;
    }
    edge_slot *free_slot = NULL;
    for (size_t i = edge_hash(a, b) & e->mask;; i = (i + 1) & e->mask) {
        edge_slot *s = &e->slot[i];
        if (s->a == a && s->b == b)
            return s;
        if (s->a == -1 && !free_slot)
            free_slot = s;
        if (s->a == -2) {
            if (!free_slot)
                free_slot = s;
            free_slot->a = a;
            free_slot->b = b;
            free_slot->t[0] = free_slot->t[1] = -1;
            return free_slot;
        }
    }
}

static void add_triangle(edge_table *e, int64_t a, int64_t b, int64_t t)
{
    edge_slot *s = edge_insert(e, a, b);
    if (s->t[0] < 0)
        s->t[0] = t;
    else if (s->t[1] == -1)
        s->t[1] = t;
    else
        s->t[1] = -2;
}

static void replace_triangle(edge_table *e, int64_t a, int64_t b, int64_t from, int64_t to)
{
    edge_slot *s = edge_find(e, a, b);
    if (!s)
        return;
    for (int k = 0; k < 2; k++)
        if (s->t[k] == from) {
            s->t[k] = to;
            return;
        }
}

static void sub3(const double *a, const double *b, double *r)
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

/* Twice the area vector of (a, b, c); its norm in *len. */
static void area_vector(const double *a, const double *b, const double *c, double n[3], double *len)
{
    double u[3], v[3];
    sub3(b, a, u);
    sub3(c, a, v);
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    *len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Cosine of the fold between triangles given by their vertex ids; 1 when
 * one of them has no area (no fold to speak of). */
static double fold_cos(const vc_surface *s, const int64_t *p, const int64_t *q)
{
    double n[3], m[3], ln, lm;
    area_vector(s->xyz + 3 * p[0], s->xyz + 3 * p[1], s->xyz + 3 * p[2], n, &ln);
    area_vector(s->xyz + 3 * q[0], s->xyz + 3 * q[1], s->xyz + 3 * q[2], m, &lm);
    if (!(ln > 0) || !(lm > 0))
        return 1;
    return (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]) / (ln * lm);
}

/* The triangle across edge (a, b) from triangle t, or -1. */
static int64_t across(const edge_table *e, int64_t a, int64_t b, int64_t t)
{
    const edge_slot *s = edge_find(e, a, b);
    if (!s || s->t[1] < 0)
        return -1;
    return s->t[0] == t ? s->t[1] : s->t[1] == t ? s->t[0] : -1;
}

/* The smallest fold cosine between the triangle (x, y, z) and the
 * triangles across its edges other than the pair's own (skip_a, skip_b)
 * and other than the triangles in skip[2]. */
static double outer_folds(const vc_surface *s, const edge_table *e, const int64_t *tri, int64_t self,
                          const int64_t skip[2])
{
    double worst = 1;
    for (int k = 0; k < 3; k++) {
        const int64_t a = tri[k], b = tri[(k + 1) % 3];
        const int64_t g = across(e, a, b, self);
        if (g < 0 || g == skip[0] || g == skip[1])
            continue;
        const double c = fold_cos(s, tri, s->tri + 3 * g);
        if (c < worst)
            worst = c;
    }
    return worst;
}

/* The height of triangle t's apex over its longest edge (infinite for a
 * triangle without area or length), the apex's corner (0..2) in *kw and
 * the longest edge's squared length in *long2. */
static double apex_height(const vc_surface *s, int64_t t, int *kw, double *long2)
{
    const int64_t *T = s->tri + 3 * t;
    int k_apex = 0;
    double best = -1;
    for (int k = 0; k < 3; k++) {
        double d[3];
        sub3(s->xyz + 3 * T[(k + 2) % 3], s->xyz + 3 * T[(k + 1) % 3], d);
        const double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (l2 > best) {
            best = l2;
            k_apex = k;
        }
    }
    *kw = k_apex;
    *long2 = best;
    double n[3], area2;
    area_vector(s->xyz + 3 * T[0], s->xyz + 3 * T[1], s->xyz + 3 * T[2], n, &area2);
    const double long_len = sqrt(best);
    if (!(area2 > 0) || !(long_len > 0))
        return INFINITY;
    return area2 / long_len;
}

/* Triangle t as a needle against the triangle across its longest edge:
 * the apex w, the edge (u, v), the triangle g across and its far corner o,
 * the apex's height h, the longest edge's squared length and the pair's
 * fold cosine. */
typedef struct needle_pair {
    int64_t w, u, v, g, o;
    double h, long2, fold;
} needle_pair;

/* Is t a needle low enough, turned over or standing as a low fin against
 * the triangle across its longest edge, of the same group? What only t and
 * that triangle decide (the rest of try_flip reads their neighbours). */
static int as_needle(const vc_surface *s, const edge_table *e, int64_t t, double max_move,
                     needle_pair *np)
{
    const int64_t *T = s->tri + 3 * t;
    /* the longest edge (u, v), the apex w: T = (w, u, v) in its order */
    int kw;
    np->h = apex_height(s, t, &kw, &np->long2); /* the apex's height over u v */
    if (!(np->h <= max_move))
        return 0;
    np->w = T[kw];
    np->u = T[(kw + 1) % 3];
    np->v = T[(kw + 2) % 3];
    np->g = across(e, np->u, np->v, t);
    if (np->g < 0)
        return 0;
    const int64_t *G = s->tri + 3 * np->g;
    if (s->tri_group && s->tri_group[t] != s->tri_group[np->g])
        return 0;
    /* G holds (v, u) in its order (the orientation is consistent) */
    int kv = -1;
    for (int k = 0; k < 3; k++)
        if (G[k] == np->v && G[(k + 1) % 3] == np->u)
            kv = k;
    if (kv < 0)
        return 0;
    np->o = G[(kv + 2) % 3];
    if (np->o == np->w)
        return 0;
    np->fold = fold_cos(s, T, G);
    /* turned over, or a low fin */
    return np->fold < 0 || (np->fold < FIN_FOLD_COS && np->h <= FIN_SHARE * max_move);
}

/* Tries the flip of triangle t's longest edge; 1 when made (with the
 * triangle across in *pair). */
static int try_flip(vc_surface *s, edge_table *e, int64_t t, double max_move, double *moved,
                    int64_t *fins, int64_t *pair)
{
    needle_pair np;
    if (!as_needle(s, e, t, max_move, &np) || edge_find(e, np.w, np.o))
        return 0;
    int64_t *T = s->tri + 3 * t;
    const int64_t w = np.w, u = np.u, v = np.v, g = np.g, o = np.o;
    int64_t *G = s->tri + 3 * g;
    const double h = np.h, best = np.long2, before_pair = np.fold;
    const int64_t skip[2] = {t, g};
    double before = before_pair;
    const double ft = outer_folds(s, e, T, t, skip), fg = outer_folds(s, e, G, g, skip);
    before = fmin(before, fmin(ft, fg));

    const int64_t nt[3] = {w, u, o}, ng[3] = {w, o, v};
    double m[3], la, lb;
    area_vector(s->xyz + 3 * nt[0], s->xyz + 3 * nt[1], s->xyz + 3 * nt[2], m, &la);
    area_vector(s->xyz + 3 * ng[0], s->xyz + 3 * ng[1], s->xyz + 3 * ng[2], m, &lb);
    const double tiny = 1e-12 * best;
    if (!(la > tiny) || !(lb > tiny))
        return 0;
    const double after_pair = fold_cos(s, nt, ng);
    if (!(after_pair > 0))
        return 0;
    /* the outer folds after: each outer edge keeps its triangle across */
    double after = after_pair;
    for (int side = 0; side < 2; side++) {
        const int64_t *q = side == 0 ? nt : ng;
        for (int j = 0; j < 3; j++) {
            const int64_t a = q[j], b = q[(j + 1) % 3];
            if ((a == w && b == o) || (a == o && b == w))
                continue;
            int64_t x = across(e, a, b, t);
            if (x < 0)
                x = across(e, a, b, g);
            if (x < 0 || x == t || x == g)
                continue;
            const double c = fold_cos(s, q, s->tri + 3 * x);
            if (c < after)
                after = c;
        }
    }
    if (!(after > before))
        return 0;
    /* flip: the edge table first (it reads the old triangles) */
    edge_slot *old = edge_find(e, u, v);
    old->a = -1;
    old->b = -1;
    replace_triangle(e, u, o, g, t);
    replace_triangle(e, v, w, t, g);
    edge_slot *ne = edge_insert(e, w, o);
    ne->t[0] = t;
    ne->t[1] = g;
    memcpy(T, nt, sizeof nt);
    memcpy(G, ng, sizeof ng);
    if (h > *moved)
        *moved = h;
    *fins += !(before_pair < 0);
    *pair = g;
    return 1;
}

/* Marks triangle t and the triangles across its edges. */
static void mark_around(const vc_surface *s, const edge_table *e, int64_t t, unsigned char *mark)
{
    mark[t] = 1;
    const int64_t *T = s->tri + 3 * t;
    for (int k = 0; k < 3; k++) {
        const int64_t x = across(e, T[k], T[(k + 1) % 3], t);
        if (x >= 0)
            mark[x] = 1;
    }
}

int64_t vc_surface_count_low_needles(const vc_surface *s, double max_move)
{
    int64_t low = 0;
#pragma omp parallel for reduction(+ : low) schedule(static)
    for (int64_t t = 0; t < s->n_triangles; t++) {
        int kw;
        double long2;
        low += apex_height(s, t, &kw, &long2) <= max_move;
    }
    return low;
}

int vc_surface_flip_turned_needles(vc_surface *s, double max_move, vc_needle_flip_report *rep, vc_error *err)
{
    vc_needle_flip_report r = {0, 0, 0};
    if (rep)
        *rep = r;
    if (!(max_move > 0) || s->n_triangles < 2)
        return 0;
    /* Most inputs have no needle that low, and a flip needs one: no table
     * then (on a 1M-triangle input it cost 0.45 s and 256 MB). */
    if (vc_surface_count_low_needles(s, max_move) == 0)
        return 0;
    edge_table e;
    size_t cap = 16;
    while (cap < 2 * 3 * (size_t)s->n_triangles / 2 + 16)
        cap *= 2;
    e.slot = malloc(sizeof(edge_slot) * cap);
    if (!e.slot)
        return vc_error_set(err, VC_ENOMEM, "out of memory for the needle flips");
    e.mask = cap - 1;
    for (size_t i = 0; i < cap; i++)
        e.slot[i].a = e.slot[i].b = -2;
    for (int64_t t = 0; t < s->n_triangles; t++) {
        const int64_t *T = s->tri + 3 * t;
        for (int k = 0; k < 3; k++)
            add_triangle(&e, T[k], T[(k + 1) % 3], t);
    }
    /* What t and the triangle across its longest edge decide is judged
     * for all at once, in parallel: a triangle that fails it is tried only
     * once a flip has touched it or a neighbour (the pair's quad, and the
     * triangles across its edges, are marked), which gives the rounds in
     * index order what trying every triangle gave (a 1.8M-triangle scan:
     * 0.6 s of serial tries). */
    unsigned char *judged = malloc((size_t)s->n_triangles), *touched = calloc((size_t)s->n_triangles, 1);
    if (!judged || !touched) {
        free(judged);
        free(touched);
        free(e.slot);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the needle flips");
    }
#pragma omp parallel for schedule(static)
    for (int64_t t = 0; t < s->n_triangles; t++) {
        needle_pair np;
        judged[t] = (unsigned char)as_needle(s, &e, t, max_move, &np);
    }
    for (int round = 0; round < MAX_ROUNDS; round++) {
        int64_t flips = 0;
        for (int64_t t = 0; t < s->n_triangles; t++) {
            int64_t g;
            if ((judged[t] || touched[t]) &&
                try_flip(s, &e, t, max_move, &r.max_move, &r.n_fins, &g)) {
                flips++;
                mark_around(s, &e, t, touched);
                mark_around(s, &e, g, touched);
            }
        }
        r.n_flipped += flips;
        if (flips == 0)
            break;
    }
    free(judged);
    free(touched);
    free(e.slot);
    if (rep)
        *rep = r;
    return 0;
}
