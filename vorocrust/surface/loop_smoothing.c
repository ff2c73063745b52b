/* Adaptive, feature-aware Loop subdivision for patch smoothing (thesis
 * 6.2.2; semantics in include/vorocrust/smoothing.h).
 *
 * Written in C on flat arrays rather than on OpenMesh's halfedge mesh.
 * OpenMesh's subdividers (Uniform/LoopT, Adaptive/Composite) know neither
 * our sharp corners and creases nor red-green closure, so the rules would
 * have to be written here either way; what OpenMesh would add is the
 * halfedge structure, and a round of red-green refinement needs only an
 * edge index (rebuilt per round in linear time below), a per-side crease
 * bit and a per-vertex kind. Flat arrays also keep the output vertex order
 * under our control (input vertices first, same indices, so corners keep
 * their numbers), accept the non-manifold edges vc_surface allows (an
 * OpenMesh PolyConnectivity refuses complex edges), and avoid copying the
 * surface into and out of a C++ mesh each call.
 *
 * One round:
 *  1. edge index of the current surface (sides bucketed by their lower
 *     vertex, sorted by (upper vertex, side) inside a bucket: O(n) for
 *     bounded valence, deterministic);
 *  2. an edge is "bent" when it is not a crease edge, has two triangles and
 *     their normals (the second flipped when both walk the edge the same
 *     way) differ by at least 180 - flat_angle degrees (the dihedral
 *     angle is at most flat_angle) and no frozen triangle is on it; a
 *     triangle with a bent edge is red;
 *  3. closure: the edges of red triangles are split; a triangle with two or
 *     three split edges becomes red, and so does a piece of an earlier
 *     green cut with one; repeated with a work list;
 *  4. positions, all from the old surface: odd (edge) points by Loop's edge
 *     rule, or the midpoint on crease edges; even points of vertices on a
 *     split edge by Loop's vertex rule, the B-spline crease rule on crease
 *     vertices, unchanged at corners; other vertices do not move;
 *  5. red triangles into 4, green (one split edge) into 2, the rest copied,
 *     every piece in the orientation of its parent; halves of crease sides
 *     stay crease sides, new inner sides are not;
 *  6. guard: vc_features_detect on the result at the input's theta_sharp
 *     must find exactly the tracked features (the input corners, and sharp
 *     edges exactly on the crease sides). Where it does not (a sector
 *     corner whose fan got flatter, a fading crease whose angle dropped
 *     below theta, a new bend sharper than theta next to a fixed corner),
 *     the triangles around the old vertices involved are frozen (never
 *     split, their vertices never moved, in this round and all later ones)
 *     and the round is redone, one ring wider around a vertex each time it
 *     is involved again; after GUARD_ATTEMPTS tries the round is dropped
 *     and smoothing stops. A frozen triangle next to a red one with two
 *     split edges makes the red one a 3-split (a "blue" triangle: the
 *     corner triangle and the remaining quad cut along its shorter
 *     diagonal), which keeps the mesh conforming. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/smoothing.h"
#include "util/csr_group.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { KIND_SMOOTH = 0, KIND_CREASE = 1, KIND_CORNER = 2 };

/* Tries per round before the round is given up (see guard). */
#define GUARD_ATTEMPTS 8

/* The surface being refined. */
typedef struct lmesh {
    int64_t nv, nt;
    double *xyz;            /* 3 nv */
    int64_t *tri;           /* 3 nt */
    unsigned char *crease;  /* nt: bit j set when side j is a crease side */
    unsigned char *kind;    /* nv: KIND_* */
    unsigned char *frozen;  /* nt: kept as is by every later round */
    unsigned char *green;   /* nt: a piece of a green (or 3-split) cut */
} lmesh;

static void lmesh_free(lmesh *m)
{
    free(m->xyz);
    free(m->tri);
    free(m->crease);
    free(m->kind);
    free(m->frozen);
    free(m->green);
    memset(m, 0, sizeof *m);
}

/* Edge index: edge e has the sides side[start[e] .. start[e+1]-1]
 * (side s = 3t + j, ascending), endpoints lo[e] < hi[e]; side_edge[s] is
 * the edge of side s. */
typedef struct eindex {
    int64_t ne;
    int64_t *lo, *hi, *start, *side, *side_edge;
} eindex;

static void eindex_free(eindex *x)
{
    free(x->lo);
    free(x->hi);
    free(x->start);
    free(x->side);
    free(x->side_edge);
    memset(x, 0, sizeof *x);
}

typedef struct skey {
    int64_t hi, s;
} skey;

static int skey_cmp(const void *a, const void *b)
{
    const skey *x = a, *y = b;
    if (x->hi != y->hi)
        return x->hi < y->hi ? -1 : 1;
    return (x->s > y->s) - (x->s < y->s);
}

static void *xmalloc(int64_t n, size_t size)
{
    if (n < 0 || (uint64_t)n > SIZE_MAX / size / 2)
        return NULL;
    return malloc(n ? (size_t)n * size : 1);
}

static void *xcalloc(int64_t n, size_t size)
{
    if (n < 0 || (uint64_t)n > SIZE_MAX / size / 2)
        return NULL;
    return calloc(n ? (size_t)n : 1, size);
}

static int build_eindex(const lmesh *m, eindex *x)
{
    int64_t ns = 3 * m->nt;
    memset(x, 0, sizeof *x);
    int64_t *bstart = xcalloc(m->nv + 1, sizeof *bstart);
    skey *keys = xmalloc(ns, sizeof *keys);
    x->side = xmalloc(ns, sizeof *x->side);
    x->side_edge = xmalloc(ns, sizeof *x->side_edge);
    x->lo = xmalloc(ns, sizeof *x->lo);
    x->hi = xmalloc(ns, sizeof *x->hi);
    x->start = xmalloc(ns + 1, sizeof *x->start);
    if (!bstart || !keys || !x->side || !x->side_edge || !x->lo || !x->hi || !x->start) {
        free(bstart);
        free(keys);
        eindex_free(x);
        return VC_ENOMEM;
    }
    for (int64_t s = 0; s < ns; s++) {
        int64_t a = m->tri[s], b = m->tri[s - s % 3 + (s % 3 + 1) % 3];
        bstart[(a < b ? a : b) + 1]++;
    }
    for (int64_t v = 0; v < m->nv; v++)
        bstart[v + 1] += bstart[v];
    for (int64_t s = 0; s < ns; s++) {
        int64_t a = m->tri[s], b = m->tri[s - s % 3 + (s % 3 + 1) % 3];
        int64_t lo = a < b ? a : b, hi = a < b ? b : a;
        keys[bstart[lo]++] = (skey){hi, s};
    }
    /* bstart[v] is now the end of bucket v, i.e. the start of bucket v+1. */
    int64_t ne = 0, b0 = 0;
    for (int64_t v = 0; v < m->nv; v++) {
        int64_t b1 = bstart[v];
        int64_t len = b1 - b0;
        if (len > 24) {
            qsort(keys + b0, (size_t)len, sizeof *keys, skey_cmp);
        } else {
            for (int64_t i = b0 + 1; i < b1; i++) {
                skey k = keys[i];
                int64_t j = i;
                while (j > b0 && skey_cmp(&keys[j - 1], &k) > 0) {
                    keys[j] = keys[j - 1];
                    j--;
                }
                keys[j] = k;
            }
        }
        for (int64_t i = b0; i < b1; i++) {
            if (i == b0 || keys[i].hi != keys[i - 1].hi) {
                x->lo[ne] = v;
                x->hi[ne] = keys[i].hi;
                x->start[ne] = i;
                ne++;
            }
            x->side[i] = keys[i].s;
            x->side_edge[keys[i].s] = ne - 1;
        }
        b0 = b1;
    }
    x->start[ne] = ns;
    x->ne = ne;
    free(bstart);
    free(keys);
    return VC_OK;
}

static void tri_normal(const lmesh *m, int64_t t, double n[3])
{
    const double *a = m->xyz + 3 * m->tri[3 * t], *b = m->xyz + 3 * m->tri[3 * t + 1],
                 *c = m->xyz + 3 * m->tri[3 * t + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double e = 0;
    for (int k = 0; k < 3; k++) {
        double d2 = u[k] * u[k] + w[k] * w[k];
        e += d2;
    }
    /* Zero area (relative): no normal. */
    if (!(l > 1e-12 * e)) {
        n[0] = n[1] = n[2] = 0;
        return;
    }
    n[0] /= l;
    n[1] /= l;
    n[2] /= l;
}

/* The vertex at the start of side s, and the one opposite it. */
static inline int64_t side_from(const lmesh *m, int64_t s) { return m->tri[s]; }
static inline int64_t side_opp(const lmesh *m, int64_t s) { return m->tri[s - s % 3 + (s % 3 + 2) % 3]; }

/* One round on m with the triangles frozen[t] != 0 kept as they are (none
 * of their edges split, none of their vertices moved). Sets *refined to
 * the number of red triangles (0: nothing to do, *o untouched). On success
 * with *refined > 0, *o is the refined surface (its frozen triangles are
 * the copies of m's frozen ones) and (*origin)[2 (w - m->nv) + 0..1] are
 * the endpoints of the edge new vertex w splits. */
static int loop_round(const lmesh *m, const unsigned char *frozen, double cos_limit, lmesh *o,
                      int64_t **origin, int64_t *refined)
{
    eindex x;
    *refined = 0;
    *origin = NULL;
    memset(o, 0, sizeof *o);
    int rc = build_eindex(m, &x);
    if (rc)
        return rc;
    int64_t nv = m->nv, nt = m->nt, ne = x.ne;
    unsigned char *ecrease = xcalloc(ne, 1);
    unsigned char *efrozen = xcalloc(ne, 1);
    unsigned char *split = xcalloc(ne, 1);
    unsigned char *red = xcalloc(nt, 1);
    unsigned char *pinned = xcalloc(nv, 1);
    double *nrm = xmalloc(3 * nt, sizeof *nrm);
    int64_t *stack = xmalloc(nt, sizeof *stack);
    int64_t *mid = NULL, *org = NULL;
    double *sum = NULL;
    int64_t *cnt = NULL;
    unsigned char *moved = NULL;
    if (!ecrease || !efrozen || !split || !red || !pinned || !nrm || !stack) {
        rc = VC_ENOMEM;
        goto done;
    }

    /* Crease edges: any crease side, and every edge without exactly two
     * triangles (those are sharp whatever the features said). Frozen
     * edges and pinned vertices: those of frozen triangles. */
    for (int64_t e = 0; e < ne; e++) {
        int64_t k = x.start[e + 1] - x.start[e];
        unsigned char c = k != 2;
        for (int64_t i = x.start[e]; i < x.start[e + 1]; i++) {
            int64_t s = x.side[i];
            if (m->crease[s / 3] >> (s % 3) & 1)
                c = 1;
            if (frozen[s / 3])
                efrozen[e] = 1;
        }
        ecrease[e] = c;
    }
    for (int64_t t = 0; t < nt; t++) {
        tri_normal(m, t, nrm + 3 * t);
        if (frozen[t])
            pinned[m->tri[3 * t]] = pinned[m->tri[3 * t + 1]] = pinned[m->tri[3 * t + 2]] = 1;
    }

    /* Red triangles: a bent edge inside a patch (not a frozen one: the
     * bend there stays whatever the other side does). */
    int64_t nred = 0;
    for (int64_t e = 0; e < ne; e++) {
        if (ecrease[e] || efrozen[e])
            continue;
        int64_t s1 = x.side[x.start[e]], s2 = x.side[x.start[e] + 1];
        int64_t t1 = s1 / 3, t2 = s2 / 3;
        const double *n1 = nrm + 3 * t1, *n2 = nrm + 3 * t2;
        double sign = side_from(m, s1) == side_from(m, s2) ? -1.0 : 1.0;
        double l1 = n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2];
        double l2 = n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2];
        if (l1 == 0 || l2 == 0)
            continue;
        double c = sign * (n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2]);
        if (c <= cos_limit) {
            if (!red[t1] && !frozen[t1]) {
                red[t1] = 1;
                nred++;
            }
            if (!red[t2] && !frozen[t2]) {
                red[t2] = 1;
                nred++;
            }
        }
    }
    if (nred == 0)
        goto done; /* nothing changes */

    /* Closure (red-green): split the splittable edges of red triangles; a
     * triangle with two or more split edges turns red, and so does a piece
     * of an earlier green cut with one (green pieces are never cut again:
     * that would halve their angles round after round). A red triangle
     * with a frozen edge ends with fewer than three split edges. */
    int64_t top = 0;
    for (int64_t t = 0; t < nt; t++)
        if (red[t])
            stack[top++] = t;
    while (top > 0) {
        int64_t t = stack[--top];
        for (int j = 0; j < 3; j++) {
            int64_t e = x.side_edge[3 * t + j];
            if (split[e] || efrozen[e])
                continue;
            split[e] = 1;
            for (int64_t i = x.start[e]; i < x.start[e + 1]; i++) {
                int64_t u = x.side[i] / 3;
                if (red[u])
                    continue;
                int ns = split[x.side_edge[3 * u]] + split[x.side_edge[3 * u + 1]] +
                         split[x.side_edge[3 * u + 2]];
                if (ns >= 2 || m->green[u]) {
                    red[u] = 1;
                    nred++;
                    stack[top++] = u;
                }
            }
        }
    }
    *refined = nred;

    /* New vertices: one per split edge, after the old ones. */
    mid = xmalloc(ne, sizeof *mid);
    if (!mid) {
        rc = VC_ENOMEM;
        goto done;
    }
    int64_t nsplit = 0;
    for (int64_t e = 0; e < ne; e++)
        mid[e] = split[e] ? nv + nsplit++ : -1;
    int64_t nt_new = 0;
    for (int64_t t = 0; t < nt; t++)
        nt_new += 1 + split[x.side_edge[3 * t]] + split[x.side_edge[3 * t + 1]] + split[x.side_edge[3 * t + 2]];
    o->nv = nv + nsplit;
    o->nt = nt_new;
    o->xyz = xmalloc(3 * o->nv, sizeof *o->xyz);
    o->tri = xmalloc(3 * o->nt, sizeof *o->tri);
    o->crease = xcalloc(o->nt, 1);
    o->frozen = xcalloc(o->nt, 1);
    o->green = xcalloc(o->nt, 1);
    o->kind = xmalloc(o->nv, 1);
    org = xmalloc(2 * nsplit, sizeof *org);
    sum = xcalloc(6 * nv, sizeof *sum); /* all neighbours, crease neighbours */
    cnt = xcalloc(2 * nv, sizeof *cnt);
    moved = xcalloc(nv, 1);
    if (!o->xyz || !o->tri || !o->crease || !o->frozen || !o->green || !o->kind || !org || !sum || !cnt || !moved) {
        rc = VC_ENOMEM;
        goto done;
    }

    /* Even points. */
    for (int64_t e = 0; e < ne; e++) {
        int64_t a = x.lo[e], b = x.hi[e];
        const double *pa = m->xyz + 3 * a, *pb = m->xyz + 3 * b;
        for (int k = 0; k < 3; k++) {
            sum[6 * a + k] += pb[k];
            sum[6 * b + k] += pa[k];
        }
        cnt[2 * a]++;
        cnt[2 * b]++;
        if (ecrease[e]) {
            for (int k = 0; k < 3; k++) {
                sum[6 * a + 3 + k] += pb[k];
                sum[6 * b + 3 + k] += pa[k];
            }
            cnt[2 * a + 1]++;
            cnt[2 * b + 1]++;
        }
        if (split[e])
            moved[a] = moved[b] = 1;
    }
    for (int64_t v = 0; v < nv; v++) {
        const double *p = m->xyz + 3 * v;
        double *q = o->xyz + 3 * v;
        memcpy(q, p, 3 * sizeof *q);
        o->kind[v] = m->kind[v];
        if (!moved[v] || pinned[v] || m->kind[v] == KIND_CORNER)
            continue;
        if (m->kind[v] == KIND_CREASE) {
            if (cnt[2 * v + 1] == 2)
                for (int k = 0; k < 3; k++)
                    q[k] = 0.75 * p[k] + 0.125 * sum[6 * v + 3 + k];
        } else if (cnt[2 * v + 1] == 0 && cnt[2 * v] >= 3) {
            double n = (double)cnt[2 * v];
            double c = 0.375 + 0.25 * cos(2.0 * M_PI / n);
            double beta = (0.625 - c * c) / n;
            for (int k = 0; k < 3; k++)
                q[k] = (1.0 - n * beta) * p[k] + beta * sum[6 * v + k];
        }
    }

    /* Odd points. */
    for (int64_t e = 0; e < ne; e++) {
        if (!split[e])
            continue;
        int64_t w = mid[e];
        org[2 * (w - nv)] = x.lo[e];
        org[2 * (w - nv) + 1] = x.hi[e];
        const double *pa = m->xyz + 3 * x.lo[e], *pb = m->xyz + 3 * x.hi[e];
        double *q = o->xyz + 3 * w;
        if (ecrease[e]) {
            for (int k = 0; k < 3; k++)
                q[k] = 0.5 * (pa[k] + pb[k]);
            o->kind[w] = KIND_CREASE;
        } else {
            const double *pc = m->xyz + 3 * side_opp(m, x.side[x.start[e]]);
            const double *pd = m->xyz + 3 * side_opp(m, x.side[x.start[e] + 1]);
            for (int k = 0; k < 3; k++)
                q[k] = 0.375 * (pa[k] + pb[k]) + 0.125 * (pc[k] + pd[k]);
            o->kind[w] = KIND_SMOOTH;
        }
    }

    /* Triangles: 4 (three split sides), 3 (two: the quad cut along its
     * shorter diagonal), 2 (one: green), 1 (none), each in its parent's
     * orientation; halves of crease sides are crease sides. */
    int64_t nt2 = 0;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *v = m->tri + 3 * t;
        unsigned cr = m->crease[t];
        int64_t mm[3];
        int nsp = 0;
        for (int j = 0; j < 3; j++) {
            mm[j] = mid[x.side_edge[3 * t + j]];
            nsp += mm[j] >= 0;
        }
        int64_t *d = o->tri + 3 * nt2;
        unsigned char *dc = o->crease + nt2;
        if (nsp == 3) {
            unsigned c0 = cr & 1, c1 = cr >> 1 & 1, c2 = cr >> 2 & 1;
            d[0] = v[0], d[1] = mm[0], d[2] = mm[2];
            dc[0] = (unsigned char)(c0 | c2 << 2);
            d[3] = mm[0], d[4] = v[1], d[5] = mm[1];
            dc[1] = (unsigned char)(c0 | c1 << 1);
            d[6] = mm[2], d[7] = mm[1], d[8] = v[2];
            dc[2] = (unsigned char)(c1 << 1 | c2 << 2);
            d[9] = mm[0], d[10] = mm[1], d[11] = mm[2];
            dc[3] = 0;
        } else if (nsp == 2) {
            int j = mm[0] < 0 ? 0 : mm[1] < 0 ? 1 : 2; /* the unsplit side */
            int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            int64_t a = v[j], b = v[j1], c = v[j2], m1 = mm[j1], m2 = mm[j2];
            unsigned ca = cr >> j & 1, cb = cr >> j1 & 1, cc = cr >> j2 & 1;
            d[0] = m2, d[1] = m1, d[2] = c;
            dc[0] = (unsigned char)(cb << 1 | cc << 2);
            const double *pa = o->xyz + 3 * a, *pb = o->xyz + 3 * b, *p1 = o->xyz + 3 * m1, *p2 = o->xyz + 3 * m2;
            double la = 0, lb = 0;
            for (int k = 0; k < 3; k++) {
                la += (pa[k] - p1[k]) * (pa[k] - p1[k]);
                lb += (pb[k] - p2[k]) * (pb[k] - p2[k]);
            }
            if (la <= lb) {
                d[3] = a, d[4] = b, d[5] = m1;
                dc[1] = (unsigned char)(ca | cb << 1);
                d[6] = a, d[7] = m1, d[8] = m2;
                dc[2] = (unsigned char)(cc << 2);
            } else {
                d[3] = a, d[4] = b, d[5] = m2;
                dc[1] = (unsigned char)(ca | cc << 2);
                d[6] = b, d[7] = m1, d[8] = m2;
                dc[2] = (unsigned char)cb;
            }
        } else if (nsp == 1) {
            int j = mm[0] >= 0 ? 0 : mm[1] >= 0 ? 1 : 2;
            int64_t a = v[j], b = v[(j + 1) % 3], c = v[(j + 2) % 3], w = mm[j];
            unsigned ca = cr >> j & 1, cb = cr >> ((j + 1) % 3) & 1, cc = cr >> ((j + 2) % 3) & 1;
            d[0] = a, d[1] = w, d[2] = c;
            dc[0] = (unsigned char)(ca | cc << 2);
            d[3] = w, d[4] = b, d[5] = c;
            dc[1] = (unsigned char)(ca | cb << 1);
        } else {
            d[0] = v[0], d[1] = v[1], d[2] = v[2];
            dc[0] = (unsigned char)cr;
            o->frozen[nt2] = frozen[t];
            o->green[nt2] = m->green[t];
        }
        if (nsp == 1 || nsp == 2)
            memset(o->green + nt2, 1, (size_t)(nsp + 1));
        nt2 += nsp + 1;
    }
    if (nt2 != o->nt) {
        rc = VC_EINTERNAL;
        goto done;
    }
    *origin = org;
    org = NULL;

done:
    if (rc)
        lmesh_free(o);
    eindex_free(&x);
    free(ecrease);
    free(efrozen);
    free(split);
    free(red);
    free(pinned);
    free(nrm);
    free(stack);
    free(mid);
    free(org);
    free(sum);
    free(cnt);
    free(moved);
    return rc;
}

/* Compares the features of o at theta with the tracked ones (corners are
 * the KIND_CORNER vertices, sharp edges the crease sides) and marks, in
 * bad (over m's nv vertices), the vertices of m whose neighbourhood
 * produced a difference: a vertex of o is itself when old, else the two
 * ends of the edge it splits. Returns the number of differences found,
 * or -1 when out of memory. */
static int64_t guard(const lmesh *o, const int64_t *origin, int64_t nv, double theta, unsigned char *bad)
{
    vc_surface s = {o->nv, o->xyz, o->nt, o->tri, NULL, 0, NULL};
    vc_features g;
    vc_error err;
    int rc = vc_features_detect(&s, theta, &g, &err);
    if (rc)
        return rc == VC_ENOMEM ? -1 : 1; /* cannot judge: reject */
    int64_t n = 0;
#define MARK(w)                                                                \
    do {                                                                       \
        int64_t w_ = (w);                                                      \
        if (w_ < nv)                                                           \
            bad[w_] = 1;                                                       \
        else                                                                   \
            bad[origin[2 * (w_ - nv)]] = bad[origin[2 * (w_ - nv) + 1]] = 1;   \
        n++;                                                                   \
    } while (0)
    for (int64_t v = 0; v < o->nv; v++)
        if ((g.vertex_corner[v] != 0) != (o->kind[v] == KIND_CORNER))
            MARK(v);
    for (int64_t e = 0; e < g.n_edges; e++) {
        int expect = g.edge_tri_start[e + 1] - g.edge_tri_start[e] != 2;
        for (int64_t i = g.edge_tri_start[e]; i < g.edge_tri_start[e + 1]; i++) {
            int64_t t = g.edge_tri[i];
            for (int j = 0; j < 3; j++)
                if (g.tri_edge[3 * t + j] == e && (o->crease[t] >> j & 1))
                    expect = 1;
        }
        if ((g.edge_sharp[e] != 0) != expect) {
            MARK(g.edge_vertex[2 * e]);
            MARK(g.edge_vertex[2 * e + 1]);
        }
    }
#undef MARK
    vc_features_free(&g);
    return n;
}

/* Freezes, in frozen (m's triangles), the triangles within radius[v]
 * rings of every vertex v with radius[v] > 0 (1: the triangles at v). */
static int freeze_rings(const lmesh *m, const int *radius, unsigned char *frozen)
{
    int64_t nv = m->nv, nt = m->nt;
    int64_t *vstart, *vtri;
    int *dist = xmalloc(nv, sizeof *dist);
    if (!dist || vc_csr_group(m->tri, nt, 3, nv, NULL, &vstart, &vtri)) {
        free(dist);
        return VC_ENOMEM;
    }
    /* dist[v]: rings still to freeze around v; levels in decreasing
     * order, each vertex handled once with its largest budget. */
    int maxr = 0;
    for (int64_t v = 0; v < nv; v++) {
        dist[v] = radius[v];
        if (radius[v] > maxr)
            maxr = radius[v];
    }
    for (int r = maxr; r >= 1; r--)
        for (int64_t v = 0; v < nv; v++) {
            if (dist[v] != r)
                continue;
            for (int64_t i = vstart[v]; i < vstart[v + 1]; i++) {
                int64_t t = vtri[i];
                frozen[t] = 1;
                for (int j = 0; j < 3; j++) {
                    int64_t u = m->tri[3 * t + j];
                    if (dist[u] < r - 1)
                        dist[u] = r - 1;
                }
            }
        }
    free(vstart);
    free(vtri);
    free(dist);
    return VC_OK;
}

int vc_surface_smooth(const vc_surface *in, const vc_features *f, int iterations,
                      double flat_angle_deg, vc_surface *out, vc_error *err)
{
    memset(out, 0, sizeof *out);
    if (iterations < 0 || iterations > VC_SMOOTH_MAX_ITERATIONS)
        return vc_error_set(err, VC_EPARAM, "smoothing: iterations %d outside 0..%d", iterations,
                            VC_SMOOTH_MAX_ITERATIONS);
    if (!(flat_angle_deg > 0 && flat_angle_deg <= 180))
        return vc_error_set(err, VC_EPARAM, "smoothing: flat angle %g outside (0, 180] degrees",
                            flat_angle_deg);
    if (!f)
        return vc_error_set(err, VC_EPARAM, "smoothing: no features given");
    if (f->n_vertices != in->n_vertices || f->n_triangles != in->n_triangles)
        return vc_error_set(err, VC_EPARAM,
                            "smoothing: the features are of another surface (%lld vertices, %lld triangles; "
                            "the surface has %lld, %lld)",
                            (long long)f->n_vertices, (long long)f->n_triangles, (long long)in->n_vertices,
                            (long long)in->n_triangles);
    for (int64_t t = 0; t < in->n_triangles; t++) {
        const int64_t *v = in->tri + 3 * t;
        for (int j = 0; j < 3; j++)
            if (v[j] < 0 || v[j] >= in->n_vertices)
                return vc_error_set(err, VC_EINPUT, "smoothing: triangle %lld has vertex index %lld out of range",
                                    (long long)t, (long long)v[j]);
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
            return vc_error_set(err, VC_EINPUT, "smoothing: triangle %lld repeats a vertex", (long long)t);
    }

    lmesh m = {0};
    m.nv = in->n_vertices;
    m.nt = in->n_triangles;
    m.xyz = xmalloc(3 * m.nv, sizeof *m.xyz);
    m.tri = xmalloc(3 * m.nt, sizeof *m.tri);
    m.crease = xcalloc(m.nt, 1);
    m.kind = xcalloc(m.nv, 1);
    m.frozen = xcalloc(m.nt, 1);
    m.green = xcalloc(m.nt, 1);
    if (!m.xyz || !m.tri || !m.crease || !m.kind || !m.frozen || !m.green) {
        lmesh_free(&m);
        return vc_error_set(err, VC_ENOMEM, "smoothing: out of memory");
    }
    if (m.nv)
        memcpy(m.xyz, in->xyz, (size_t)(3 * m.nv) * sizeof *m.xyz);
    if (m.nt)
        memcpy(m.tri, in->tri, (size_t)(3 * m.nt) * sizeof *m.tri);
    for (int64_t t = 0; t < m.nt; t++)
        for (int j = 0; j < 3; j++)
            if (f->edge_sharp[f->tri_edge[3 * t + j]])
                m.crease[t] |= (unsigned char)(1u << j);
    for (int64_t v = 0; v < m.nv; v++)
        m.kind[v] = f->vertex_corner[v] ? KIND_CORNER : f->vertex_sharp_degree[v] > 0 ? KIND_CREASE : KIND_SMOOTH;

    /* Bent: the normals differ by at least 180 - flat_angle degrees. */
    double cos_limit = flat_angle_deg == 180.0 ? 1.0 : cos((180.0 - flat_angle_deg) * M_PI / 180.0);
    for (int it = 0; it < iterations; it++) {
        int rc = VC_OK, accepted = 0;
        int *radius = xcalloc(m.nv, sizeof *radius);
        unsigned char *bad = xmalloc(m.nv, 1);
        unsigned char *mask = xmalloc(m.nt, 1);
        if (!radius || !bad || !mask)
            rc = VC_ENOMEM;
        for (int attempt = 0; rc == VC_OK && attempt < GUARD_ATTEMPTS; attempt++) {
            memcpy(mask, m.frozen, (size_t)m.nt);
            if (attempt > 0 && (rc = freeze_rings(&m, radius, mask)) != VC_OK)
                break;
            lmesh o;
            int64_t *origin = NULL, refined = 0;
            rc = loop_round(&m, mask, cos_limit, &o, &origin, &refined);
            if (rc != VC_OK || refined == 0)
                break;
            memset(bad, 0, (size_t)m.nv);
            int64_t n = guard(&o, origin, m.nv, f->sharp_angle, bad);
            free(origin);
            if (n < 0) {
                rc = VC_ENOMEM;
                lmesh_free(&o);
                break;
            }
            if (n == 0) {
                lmesh_free(&m);
                m = o;
                accepted = 1;
                break;
            }
            /* Changed features: keep the neighbourhood of the vertices
             * involved as it is, one ring more each time they are involved
             * again, and redo the round. */
            for (int64_t v = 0; v < m.nv; v++)
                radius[v] += bad[v];
            lmesh_free(&o);
        }
        free(radius);
        free(bad);
        free(mask);
        if (rc) {
            lmesh_free(&m);
            return vc_error_set(err, rc, rc == VC_ENOMEM ? "smoothing: out of memory (round %d)"
                                                         : "smoothing: internal error in round %d",
                                it + 1);
        }
        if (!accepted)
            break; /* nothing left to refine, or no refinement keeps the features */
    }
    out->n_vertices = m.nv;
    out->xyz = m.xyz;
    out->n_triangles = m.nt;
    out->tri = m.tri;
    free(m.crease);
    free(m.kind);
    free(m.frozen);
    free(m.green);
    return VC_OK;
}
