/* The union of a closed surface that intersects itself
 * (vc_surface_self_union): a cow whose tail runs through its rump, two
 * overlapping boxes given as one file. The region such a surface bounds is
 * the set of points it winds around at least once; its boundary is made of
 * the parts of the input that have winding number 0 on their outer side.
 *
 * 1. The intersecting pairs of triangles (the self-intersection test's
 *    hierarchy) each give a segment of an intersection curve. In general
 *    position its two ends are points where an edge of one triangle pierces
 *    the other (or the vertex two triangles share). Such a point is named by
 *    its edge (two vertex ids) and the pierced triangle, and computed from
 *    them in one fixed order, so the triangles around an edge agree on it
 *    by construction, not by a distance.
 *    Where two segments cross inside a triangle, three sheets pass through
 *    one point (generic where three parts overlap: a pack of spheres): the
 *    point the three triangles' planes share, named by the three triangles
 *    and computed from them in one order, splits the three pairs' segments,
 *    alike in the three triangles (split_at_triple_points).
 * 2. Each cut triangle is split along its segments: the planar graph of
 *    its border (corners and the points on its edges) and the segments,
 *    its faces traced by angle, each face triangulated by ear clipping.
 * 3. The pieces, joined across every edge that is not on a curve, form
 *    patches; one point of each patch gets the winding number of the rest
 *    of the surface (solid angles): w + 1/2 where w is the number on the
 *    patch's outer side. Patches with w == 0 bound the union; the others lie
 *    inside another part (w >= 1) or outside everything (w < 0) and go.
 *
 * Degenerate contacts (a vertex or edge in another triangle's plane within
 * rounding, coplanar overlaps, a triple point on an edge or within rounding
 * of a curve's end, a curve closed inside one triangle) are refused with the
 * triangles named: their union needs exact constructions this file does not
 * make. The decisions use
 * the filtered predicates of predicates.h on coordinates centred and scaled
 * by a power of two, as in the self-intersection test. */
#include "vorocrust/surface.h"
#include "surface/predicates.h"
#include "surface/self_intersection.h"
#include "surface/solid_angle.h"
#include "util/csr_group.h"
#include "util/reserve.h"
#include "util/union_find.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Edges shorter than this share of the bounding-box diagonal that end at a
 * cut point are collapsed (collapse_short_edges): far below any error bound
 * a user sets (0.5 % is the acceptance's), far above the rounding. */
#define COLLAPSE_EDGE 1e-4

/* A point of an intersection curve: edge (a < b) piercing triangle t. */
typedef struct cut_point {
    int64_t a, b, t;
} cut_point;

/* A segment of a curve: triangles x and y, end ids (vertex ids: < nv the
 * input's, else nv + a cut point). */
typedef struct segment {
    int64_t x, y, e[2];
} segment;

typedef struct builder {
    const vc_surface *s;
    const double *xyz; /* scaled */
    int64_t nv;
    cut_point *pts;
    double *pxyz; /* scaled coordinates of the cut points */
    int64_t n_pts, cap_pts;
    int64_t *slot; /* open addressing: index into pts, -1 empty */
    int64_t n_slots;
} builder;

static const double *vertex_of(const builder *u, int64_t id)
{
    return id < u->nv ? u->xyz + 3 * id : u->pxyz + 3 * (id - u->nv);
}

/* det[a - d; b - d; c - d], the value whose sign vc_orient3d filters. */
static double det3(const double *a, const double *b, const double *c, const double *d)
{
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    return adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
}

static uint64_t hash_point(int64_t a, int64_t b, int64_t t)
{
    uint64_t h = (uint64_t)a * 0x9e3779b97f4a7c15ULL;
    h ^= (uint64_t)b * 0xc2b2ae3d27d4eb4fULL + (h << 6) + (h >> 2);
    h ^= (uint64_t)t * 0x165667b19e3779f9ULL + (h << 6) + (h >> 2);
    h ^= h >> 29;
    return h;
}

/* The index of point (a, b, t) among the cut points, made on first use
 * (*fresh = 1: its coordinates are the caller's to set); -1 when out of
 * memory. */
static int64_t point_slot(builder *u, int64_t a, int64_t b, int64_t t, int *fresh)
{
    *fresh = 0;
    uint64_t mask = (uint64_t)u->n_slots - 1;
    for (uint64_t h = hash_point(a, b, t) & mask;; h = (h + 1) & mask) {
        int64_t k = u->slot[h];
        if (k < 0) {
            if (u->n_pts == u->cap_pts) {
                int64_t c = 2 * u->cap_pts;
                cut_point *p = realloc(u->pts, (size_t)c * sizeof *p);
                if (p)
                    u->pts = p;
                double *x = realloc(u->pxyz, (size_t)c * 3 * sizeof *x);
                if (x)
                    u->pxyz = x;
                if (!p || !x)
                    return -1;
                u->cap_pts = c;
            }
            k = u->n_pts++;
            u->pts[k] = (cut_point){a, b, t};
            u->slot[h] = k;
            *fresh = 1;
            return k;
        }
        if (u->pts[k].a == a && u->pts[k].b == b && u->pts[k].t == t)
            return k;
    }
}

/* The id of the point where edge (a, b) (a < b) pierces triangle t, made
 * on first use; -1 when out of memory. */
static int64_t point_id(builder *u, int64_t a, int64_t b, int64_t t)
{
    int fresh;
    const int64_t k = point_slot(u, a, b, t, &fresh);
    if (k < 0)
        return -1;
    if (fresh) {
        const int64_t *vt = u->s->tri + 3 * t;
        const double *A = u->xyz + 3 * a, *B = u->xyz + 3 * b;
        const double *T0 = u->xyz + 3 * vt[0], *T1 = u->xyz + 3 * vt[1], *T2 = u->xyz + 3 * vt[2];
        double da = det3(T0, T1, T2, A), db = det3(T0, T1, T2, B), f = da / (da - db);
        for (int c = 0; c < 3; c++)
            u->pxyz[3 * k + c] = A[c] + f * (B[c] - A[c]);
    }
    return u->nv + k;
}

/* The (unnormalised) normal of triangle t. */
static void triangle_normal(const builder *u, int64_t t, double n[3])
{
    const int64_t *v = u->s->tri + 3 * t;
    const double *A = u->xyz + 3 * v[0], *B = u->xyz + 3 * v[1], *C = u->xyz + 3 * v[2];
    const double e1[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
    const double e2[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

/* The determinant of the rows r[0], r[1], r[2]. */
static double det_rows(const double r[3][3])
{
    return r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
           r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
}

/* The id of the point where triangles x < y < z meet (three sheets through
 * one point, where two curves cross inside each of the three), named by
 * them (stored as a = -1 - x, b = y, t = z) and computed from their planes
 * in that order, so the three agree on it (NaN coordinates when the planes
 * meet in no one point); -1 when out of memory. */
static int64_t triple_id(builder *u, int64_t x, int64_t y, int64_t z)
{
    int fresh;
    const int64_t k = point_slot(u, -1 - x, y, z, &fresh);
    if (k < 0 || !fresh)
        return k < 0 ? -1 : u->nv + k;
    const int64_t t3[3] = {x, y, z};
    double n[3][3], d[3];
    for (int i = 0; i < 3; i++) {
        triangle_normal(u, t3[i], n[i]);
        const double *A = u->xyz + 3 * u->s->tri[3 * t3[i]];
        d[i] = n[i][0] * A[0] + n[i][1] * A[1] + n[i][2] * A[2];
    }
    /* Cramer's rule; NaN when the planes meet in no one point */
    const double det = det_rows((const double(*)[3])n);
    for (int c = 0; c < 3; c++) {
        double m[3][3];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                m[i][j] = j == c ? d[i] : n[i][j];
        u->pxyz[3 * k + c] = det != 0 && isfinite(det) ? det_rows((const double(*)[3])m) / det : NAN;
    }
    return u->nv + k;
}

/* Whether edge (a, b) of one triangle, whose ends lie strictly on both
 * sides of triangle t's plane, passes through t: 1 yes, 0 no, -1 through
 * an edge or vertex of t within rounding. The same decision from every
 * triangle around the edge: a < b and t's corners in their order. */
static int pierces(const builder *u, int64_t a, int64_t b, int64_t t)
{
    if (a > b) {
        int64_t c = a;
        a = b;
        b = c;
    }
    const int64_t *vt = u->s->tri + 3 * t;
    const double *A = u->xyz + 3 * a, *B = u->xyz + 3 * b;
    int o[3], pos = 0, neg = 0, zero = 0;
    for (int k = 0; k < 3; k++) {
        o[k] = vc_orient3d(A, B, u->xyz + 3 * vt[k], u->xyz + 3 * vt[(k + 1) % 3]);
        pos += o[k] > 0;
        neg += o[k] < 0;
        zero += o[k] == 0;
    }
    if (pos && neg)
        return 0;
    return zero ? -1 : 1;
}

/* The segment of pair (x, y): 1 with its ends, 0 when they only touch at
 * a shared vertex, -1 when degenerate. */
static int pair_segment(builder *u, int64_t x, int64_t y, int64_t ends[2], int *oom)
{
    const int64_t *vx = u->s->tri + 3 * x, *vy = u->s->tri + 3 * y;
    int64_t shared = -1;
    int n_shared = 0, sx[3], sy[3];
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++)
            if (vx[k] == vy[l]) {
                shared = vx[k];
                n_shared++;
            }
    if (n_shared >= 2)
        return -1; /* folded onto each other across their edge */
    const double *X[3], *Y[3];
    for (int k = 0; k < 3; k++) {
        X[k] = u->xyz + 3 * vx[k];
        Y[k] = u->xyz + 3 * vy[k];
    }
    int xpos = 0, xneg = 0, ypos = 0, yneg = 0;
    for (int k = 0; k < 3; k++) {
        sx[k] = vx[k] == shared ? 0 : vc_orient3d(Y[0], Y[1], Y[2], X[k]);
        sy[k] = vy[k] == shared ? 0 : vc_orient3d(X[0], X[1], X[2], Y[k]);
        if ((vx[k] != shared && sx[k] == 0) || (vy[k] != shared && sy[k] == 0))
            return -1; /* a vertex in the other's plane */
        xpos += sx[k] > 0;
        xneg += sx[k] < 0;
        ypos += sy[k] > 0;
        yneg += sy[k] < 0;
    }
    if (!(xpos && xneg) || !(ypos && yneg))
        return 0;
    int n = 0;
    if (n_shared)
        ends[n++] = shared;
    for (int side = 0; side < 2; side++) {
        const int64_t *v = side ? vy : vx, other = side ? x : y;
        const int *sg = side ? sy : sx;
        for (int k = 0; k < 3; k++) {
            int l = (k + 1) % 3;
            if (sg[k] * sg[l] >= 0)
                continue;
            int r = pierces(u, v[k], v[l], other);
            if (r < 0)
                return -1;
            if (!r)
                continue;
            if (n == 2)
                return -1;
            int64_t id = point_id(u, v[k] < v[l] ? v[k] : v[l], v[k] < v[l] ? v[l] : v[k], other);
            if (id < 0) {
                *oom = 1;
                return 0;
            }
            ends[n++] = id;
        }
    }
    if (n_shared && n == 1)
        return 0;
    return n == 2 ? 1 : -1;
}

/* ---- Splitting one triangle along its segments ---- */

typedef struct growing {
    int64_t *v;
    int64_t n, cap;
} growing;

static int grow_push(growing *g, int64_t a, int64_t b, int64_t c, int64_t d)
{
    if (g->n + 4 > g->cap) {
        int64_t c2 = g->cap ? 2 * g->cap : 256;
        while (c2 < g->n + 4)
            c2 *= 2;
        int64_t *p = realloc(g->v, (size_t)c2 * sizeof *p);
        if (!p)
            return -1;
        g->v = p;
        g->cap = c2;
    }
    g->v[g->n++] = a;
    g->v[g->n++] = b;
    g->v[g->n++] = c;
    g->v[g->n++] = d;
    return 0;
}

typedef struct local_vertex {
    int64_t id;
    int side;     /* edge of the triangle it lies on (0..2), 3 inside, -1 - k corner k */
    double param; /* along that edge */
} local_vertex;

/* Whether the vertex lies on edge k (corners k and k + 1 included). */
static int on_edge(const local_vertex *v, int k)
{
    return v->side == k || v->side == -1 - k || v->side == -1 - (k + 1) % 3;
}

/* Whether three vertices lie on one edge of the triangle: collinear by
 * construction, whatever the rounded coordinates say. */
static int on_one_edge(const local_vertex *a, const local_vertex *b, const local_vertex *c)
{
    for (int k = 0; k < 3; k++)
        if (on_edge(a, k) && on_edge(b, k) && on_edge(c, k))
            return 1;
    return 0;
}

/* Orientation of (a, b, c) on axes i, j, with the cut points' rounding
 * taken as collinear: |det| within a tolerance of the three points' own
 * extent L (1e-13 L^2, and 1e-15 L for the absolute rounding of a cut
 * point, about an ulp of the scaled coordinates) is 0. Chains of cut points
 * from coplanar triangles (a box face given as two) are straight, and the
 * ulp their construction rounds off would otherwise decide. */
static int orient_tol(const double *a, const double *b, const double *c, int i, int j)
{
    double ax = a[i] - c[i], ay = a[j] - c[j], bx = b[i] - c[i], by = b[j] - c[j];
    double det = ax * by - ay * bx;
    double l2 = fmax(ax * ax + ay * ay, bx * bx + by * by);
    double tol = 1e-13 * l2 + 1e-15 * sqrt(l2);
    return det > tol ? 1 : det < -tol ? -1 : 0;
}

typedef struct halfedge_ref {
    int64_t h;
    double angle;
} halfedge_ref;

static int cmp_angle(const void *pa, const void *pb)
{
    const halfedge_ref *a = pa, *b = pb;
    return a->angle < b->angle ? -1 : a->angle > b->angle;
}

/* Twice the area over the sum of the squared edges: 0 flat, largest for
 * an equilateral triangle. */
static double fatness(const double *P, const double *Q, const double *R, int ai, int aj)
{
    double ux = Q[ai] - P[ai], uy = Q[aj] - P[aj], vx = R[ai] - P[ai], vy = R[aj] - P[aj];
    double wx = R[ai] - Q[ai], wy = R[aj] - Q[aj];
    return (ux * vy - uy * vx) / (ux * ux + uy * uy + vx * vx + vy * vy + wx * wx + wy * wy);
}

/* Whether the closed segments ab and cd meet (tolerant orientations). */
static int segments_meet(const double *a, const double *b, const double *c, const double *d, int ai, int aj)
{
    int o1 = orient_tol(a, b, c, ai, aj), o2 = orient_tol(a, b, d, ai, aj);
    int o3 = orient_tol(c, d, a, ai, aj), o4 = orient_tol(c, d, b, ai, aj);
    if (o1 * o2 < 0 && o3 * o4 < 0)
        return 1;
    /* a point on the other segment (collinear and within its box) */
    const double *pt[4] = {c, d, a, b}, *s0[4] = {a, a, c, c}, *s1[4] = {b, b, d, d};
    int o[4] = {o1, o2, o3, o4};
    for (int k = 0; k < 4; k++)
        if (o[k] == 0) {
            double lo_i = s0[k][ai] < s1[k][ai] ? s0[k][ai] : s1[k][ai];
            double hi_i = s0[k][ai] < s1[k][ai] ? s1[k][ai] : s0[k][ai];
            double lo_j = s0[k][aj] < s1[k][aj] ? s0[k][aj] : s1[k][aj];
            double hi_j = s0[k][aj] < s1[k][aj] ? s1[k][aj] : s0[k][aj];
            if (pt[k][ai] >= lo_i && pt[k][ai] <= hi_i && pt[k][aj] >= lo_j && pt[k][aj] <= hi_j)
                return 1;
        }
    return 0;
}

/* Whether the chord between polygon vertices i and j (not neighbours) of
 * the counter-clockwise polygon face[0..nf) runs inside it and meets no
 * edge away from its ends. O(nf). */
static int diagonal_ok(const builder *u, const local_vertex *lv, const int64_t *face, int64_t nf, int64_t i,
                       int64_t j, int ai, int aj)
{
#define FP(i) vertex_of(u, lv[face[i]].id)
    int good = 1;
    for (int side = 0; side < 2 && good; side++) {
        int64_t a = side ? j : i, b = side ? i : j;
        const double *A = FP(a), *B = FP(b), *A0 = FP((a + nf - 1) % nf), *A1 = FP((a + 1) % nf);
        if (orient_tol(A0, A, A1, ai, aj) > 0)
            good = orient_tol(A, B, A0, ai, aj) > 0 && orient_tol(B, A, A1, ai, aj) > 0;
        else
            good = !(orient_tol(A, B, A1, ai, aj) >= 0 && orient_tol(B, A, A0, ai, aj) >= 0);
    }
    for (int64_t k = 0; k < nf && good; k++) {
        int64_t l = (k + 1) % nf;
        if (k == i || k == j || l == i || l == j)
            continue;
        good = !segments_meet(FP(i), FP(j), FP(k), FP(l), ai, aj);
    }
    return good;
#undef FP
}

/* Triangulates the counter-clockwise simple polygon face[0..nf) (local
 * vertex indices) so that its thinnest triangle is as fat as possible
 * (dynamic programming over the valid diagonals, O(nf^3)): a greedy ear
 * clipping can leave three nearly collinear curve points for the last
 * triangle, a sliver whose normal the sizing then trusts. Appends the
 * triangles to out; 0, -1 when no triangulation without a flat triangle
 * exists, -2 out of memory. */
static int triangulate_face(const builder *u, const local_vertex *lv, const int64_t *face, int64_t nf, int ai,
                            int aj, int64_t x, growing *out)
{
#define FP(i) vertex_of(u, lv[face[i]].id)
    unsigned char *ok = malloc((size_t)(nf * nf));
    double *best = malloc((size_t)(nf * nf) * sizeof *best);
    int64_t *pick = malloc((size_t)(nf * nf) * sizeof *pick);
    int64_t *stack = malloc((size_t)(4 * nf + 4) * sizeof *stack);
    int rc = 0;
    if (!ok || !best || !pick || !stack) {
        rc = -2;
        goto done;
    }
    /* valid chords: polygon edges, and diagonals inside the polygon that
     * meet no edge away from their ends */
    for (int64_t i = 0; i < nf; i++)
        for (int64_t j = 0; j < nf; j++) {
            int64_t d = (j - i + nf) % nf;
            ok[i * nf + j] = d == 1 || d == nf - 1;
        }
    for (int64_t i = 0; i < nf; i++)
        for (int64_t j = i + 2; j < nf; j++) {
            if (i == 0 && j == nf - 1)
                continue;
            int good = diagonal_ok(u, lv, face, nf, i, j, ai, aj);
            ok[i * nf + j] = ok[j * nf + i] = (unsigned char)good;
        }
    /* best[i][j]: the fattest thinnest triangle of the part i, i+1, ..., j */
    for (int64_t len = 1; len < nf; len++)
        for (int64_t i = 0; i + len < nf; i++) {
            int64_t j = i + len;
            best[i * nf + j] = len == 1 ? INFINITY : -INFINITY;
            pick[i * nf + j] = -1;
            if (len == 1 || !ok[i * nf + j])
                continue;
            for (int64_t k = i + 1; k < j; k++) {
                double b1 = best[i * nf + k], b2 = best[k * nf + j];
                if (b1 == -INFINITY || b2 == -INFINITY || on_one_edge(&lv[face[i]], &lv[face[k]], &lv[face[j]]) ||
                    orient_tol(FP(i), FP(k), FP(j), ai, aj) <= 0)
                    continue;
                double f = fatness(FP(i), FP(k), FP(j), ai, aj);
                f = f < b1 ? f : b1;
                f = f < b2 ? f : b2;
                if (f > best[i * nf + j]) {
                    best[i * nf + j] = f;
                    pick[i * nf + j] = k;
                }
            }
        }
    if (pick[nf - 1] < 0) {
        rc = -1;
        goto done;
    }
    int64_t sp = 0;
    stack[sp++] = 0;
    stack[sp++] = nf - 1;
    while (sp > 0 && !rc) {
        int64_t j = stack[--sp], i = stack[--sp];
        if (j - i < 2)
            continue;
        int64_t k = pick[i * nf + j];
        if (grow_push(out, lv[face[i]].id, lv[face[k]].id, lv[face[j]].id, x))
            rc = -2;
        stack[sp++] = i;
        stack[sp++] = k;
        stack[sp++] = k;
        stack[sp++] = j;
    }
done:
    free(ok);
    free(best);
    free(pick);
    free(stack);
    return rc;
#undef FP
}

/* Faces up to this many vertices are triangulated by the O(n^3) dynamic
 * programme; larger ones (a coarse triangle crossed by a fine part's
 * curve: thousands of points) are first halved by short diagonals. */
#define DP_MAX_VERTICES 48

/* Triangulates a face of any size: halves it by the shortest valid
 * diagonal between opposite vertices (O(nf^2) candidates tested in O(nf)
 * each, any valid diagonal when none of those is) until the parts are
 * small enough for triangulate_face. */
static int triangulate_large_face(const builder *u, const local_vertex *lv, const int64_t *face, int64_t nf,
                                  int ai, int aj, int64_t x, growing *out)
{
    if (nf <= DP_MAX_VERTICES)
        return triangulate_face(u, lv, face, nf, ai, aj, x, out);
    int64_t bi = -1, bj = -1;
    double best = INFINITY;
    for (int pass = 0; pass < 2 && bi < 0; pass++)
        for (int64_t i = 0; i < nf; i++)
            for (int64_t d = pass ? 2 : nf / 2; pass ? d <= nf - 2 : d == nf / 2; d++) {
                int64_t j = (i + d) % nf;
                if (!diagonal_ok(u, lv, face, nf, i, j, ai, aj))
                    continue;
                const double *A = vertex_of(u, lv[face[i]].id), *B = vertex_of(u, lv[face[j]].id);
                double l2 = (A[ai] - B[ai]) * (A[ai] - B[ai]) + (A[aj] - B[aj]) * (A[aj] - B[aj]);
                if (l2 < best) {
                    best = l2;
                    bi = i;
                    bj = j;
                }
                if (pass)
                    break; /* any valid one will do */
            }
    if (bi < 0)
        return -1;
    if (bi > bj) {
        int64_t t = bi;
        bi = bj;
        bj = t;
    }
    int64_t n1 = bj - bi + 1, n2 = nf - (bj - bi) + 1;
    int64_t *part = malloc((size_t)(n1 > n2 ? n1 : n2) * sizeof *part);
    if (!part)
        return -2;
    for (int64_t k = 0; k < n1; k++)
        part[k] = face[bi + k];
    int rc = triangulate_large_face(u, lv, part, n1, ai, aj, x, out);
    if (!rc) {
        for (int64_t k = 0; k < n2; k++)
            part[k] = face[(bj + k) % nf];
        rc = triangulate_large_face(u, lv, part, n2, ai, aj, x, out);
    }
    free(part);
    return rc;
}

/* The two axes of the projection that keeps triangle t counter-clockwise
 * (its normal's largest coordinate dropped). */
static void plane_axes(const builder *u, int64_t t, int *ai, int *aj)
{
    double n[3];
    triangle_normal(u, t, n);
    int kz = fabs(n[0]) > fabs(n[1]) ? (fabs(n[0]) > fabs(n[2]) ? 0 : 2) : (fabs(n[1]) > fabs(n[2]) ? 1 : 2);
    *ai = (kz + 1) % 3;
    *aj = (kz + 2) % 3;
    if (n[kz] < 0) {
        int k = *ai;
        *ai = *aj;
        *aj = k;
    }
}

/* Splits triangle x along segments seg[list[0..n)]: appends (a, b, c, x)
 * for each piece to out (the input's orientation). Returns 0, -1 when the
 * split is degenerate, -2 when out of memory. */
static int split_triangle(const builder *u, int64_t x, const segment *seg, const int64_t *list, int64_t n,
                          growing *out)
{
    const int64_t *c = u->s->tri + 3 * x;
    const double *C[3] = {u->xyz + 3 * c[0], u->xyz + 3 * c[1], u->xyz + 3 * c[2]};
    int ai, aj;
    plane_axes(u, x, &ai, &aj);

    int64_t m_cap = 3 + 2 * n, e_cap = 3 + 2 * n + n;
    local_vertex *lv = malloc((size_t)m_cap * sizeof *lv);
    int64_t *order = malloc((size_t)m_cap * sizeof *order);
    int64_t *edge = malloc((size_t)e_cap * 2 * sizeof *edge);
    int64_t *face = malloc((size_t)(2 * e_cap + 1) * sizeof *face);
    halfedge_ref *ref = malloc((size_t)2 * e_cap * sizeof *ref);
    int64_t *first = malloc((size_t)(m_cap + 1) * sizeof *first);
    int64_t *pos_of = malloc((size_t)2 * e_cap * sizeof *pos_of);
    unsigned char *seen = calloc((size_t)2 * e_cap, 1);
    int rc = 0;
    if (!lv || !order || !edge || !face || !ref || !first || !pos_of || !seen) {
        rc = -2;
        goto done;
    }
    /* the vertices: corners, then every segment end once */
    int64_t m = 0;
    for (int k = 0; k < 3; k++)
        lv[m++] = (local_vertex){c[k], -1 - k, 0};
    for (int64_t q = 0; q < n; q++)
        for (int j = 0; j < 2; j++) {
            int64_t id = seg[list[q]].e[j];
            int dup = 0;
            for (int64_t r = 0; r < m && !dup; r++)
                dup = lv[r].id == id;
            if (dup)
                continue;
            if (id < u->nv) {
                rc = -1; /* a vertex id that is not a corner */
                goto done;
            }
            const cut_point *p = &u->pts[id - u->nv];
            const double *P = u->pxyz + 3 * (id - u->nv);
            local_vertex v = {id, 3, 0};
            /* a triple point lies inside each of its three triangles */
            if (p->a >= 0 && p->t != x) {
                v.side = -9;
                for (int k = 0; k < 3; k++) {
                    int64_t a = c[k], b = c[(k + 1) % 3];
                    if ((p->a == a && p->b == b) || (p->a == b && p->b == a)) {
                        v.side = k;
                        double d2 = 0, dp = 0;
                        for (int l = 0; l < 3; l++) {
                            double dl = C[(k + 1) % 3][l] - C[k][l];
                            d2 += dl * dl;
                            dp += (P[l] - C[k][l]) * dl;
                        }
                        v.param = dp / d2;
                    }
                }
                if (v.side < 0) {
                    rc = -1;
                    goto done;
                }
            }
            lv[m++] = v;
        }
    /* the border cycle: corner k, then the points on edge k by parameter */
    int64_t nb = 0;
    for (int k = 0; k < 3; k++) {
        order[nb++] = k;
        int64_t from = nb;
        for (int64_t r = 3; r < m; r++)
            if (lv[r].side == k)
                order[nb++] = r;
        /* sort the indices order[from..nb) by parameter (few: insertion) */
        for (int64_t i = from + 1; i < nb; i++)
            for (int64_t j = i; j > from && lv[order[j]].param < lv[order[j - 1]].param; j--) {
                int64_t t = order[j];
                order[j] = order[j - 1];
                order[j - 1] = t;
            }
        for (int64_t i = from + 1; i < nb; i++)
            if (!(lv[order[i]].param > lv[order[i - 1]].param)) {
                rc = -1;
                goto done;
            }
    }
    int64_t ne = 0;
    for (int64_t i = 0; i < nb; i++) {
        edge[2 * ne] = order[i];
        edge[2 * ne + 1] = order[(i + 1) % nb];
        ne++;
    }
    for (int64_t q = 0; q < n; q++) {
        int64_t a = -1, b = -1;
        for (int64_t r = 0; r < m; r++) {
            if (lv[r].id == seg[list[q]].e[0])
                a = r;
            if (lv[r].id == seg[list[q]].e[1])
                b = r;
        }
        int dup = a == b;
        for (int64_t i = 0; i < ne && !dup; i++)
            dup = (edge[2 * i] == a && edge[2 * i + 1] == b) || (edge[2 * i] == b && edge[2 * i + 1] == a);
        if (dup) {
            rc = -1; /* a segment along the border, or twice: not general position */
            goto done;
        }
        edge[2 * ne] = a;
        edge[2 * ne + 1] = b;
        ne++;
    }
#define LP(r) vertex_of(u, lv[r].id)
    /* no two edges may cross or touch away from a shared end (three sheets
     * through one point) */
    for (int64_t i = nb; i < ne; i++)
        for (int64_t j = 0; j < i; j++) {
            int64_t a = edge[2 * i], b = edge[2 * i + 1], p = edge[2 * j], q = edge[2 * j + 1];
            if (a == p || a == q || b == p || b == q)
                continue;
            if (segments_meet(LP(a), LP(b), LP(p), LP(q), ai, aj)) {
                rc = -1;
                goto done;
            }
        }
    /* outgoing half-edges of each vertex by angle (h = 2e: a -> b, 2e + 1:
     * b -> a) */
    for (int64_t r = 0; r <= m; r++)
        first[r] = 0;
    for (int64_t e = 0; e < ne; e++) {
        first[edge[2 * e] + 1]++;
        first[edge[2 * e + 1] + 1]++;
    }
    for (int64_t r = 0; r < m; r++) {
        if (first[r + 1] < 2) {
            rc = -1; /* a curve that ends inside the triangle */
            goto done;
        }
        first[r + 1] += first[r];
    }
    {
        int64_t *fill = order; /* reused: nb <= m */
        for (int64_t r = 0; r < m; r++)
            fill[r] = first[r];
        for (int64_t h = 0; h < 2 * ne; h++) {
            int64_t from = edge[2 * (h >> 1) + (h & 1)], to = edge[2 * (h >> 1) + !(h & 1)];
            const double *A = LP(from), *B = LP(to);
            ref[fill[from]++] = (halfedge_ref){h, atan2(B[aj] - A[aj], B[ai] - A[ai])};
        }
    }
    for (int64_t r = 0; r < m; r++) {
        qsort(ref + first[r], (size_t)(first[r + 1] - first[r]), sizeof *ref, cmp_angle);
        for (int64_t k = first[r]; k < first[r + 1]; k++)
            pos_of[ref[k].h] = k;
    }
    /* the faces: next(a -> b) is the half-edge before b -> a around b */
    int n_outer = 0;
    for (int64_t h0 = 0; h0 < 2 * ne && !rc; h0++) {
        if (seen[h0])
            continue;
        int64_t nf = 0, h = h0;
        double area2 = 0;
        do {
            seen[h] = 1;
            int64_t from = edge[2 * (h >> 1) + (h & 1)], to = edge[2 * (h >> 1) + !(h & 1)];
            if (nf > 2 * ne) {
                rc = -1;
                break;
            }
            face[nf++] = from;
            const double *A = LP(from), *B = LP(to);
            area2 += A[ai] * B[aj] - A[aj] * B[ai];
            int64_t twin = h ^ 1, k = pos_of[twin];
            int64_t prev = k == first[to] ? first[to + 1] - 1 : k - 1;
            h = ref[prev].h;
        } while (h != h0);
        if (rc)
            break;
        if (area2 <= 0) {
            n_outer++;
            continue;
        }
        for (int64_t i = 0; i < nf; i++)
            for (int64_t j = 0; j < i; j++)
                if (face[i] == face[j])
                    rc = -1; /* a vertex twice on one face: a bridge */
        rc = triangulate_large_face(u, lv, face, nf, ai, aj, x, out);
    }
#undef LP
    if (!rc && n_outer != 1)
        rc = -1; /* a curve closed inside the triangle (a second component) */
done:
    free(lv);
    free(order);
    free(edge);
    free(face);
    free(ref);
    free(first);
    free(pos_of);
    free(seen);
    return rc;
}

/* ---- Triple points ---- */

/* The segments of each triangle, in segment order: those of triangle t are
 * (*list)[(*start)[t] .. (*start)[t + 1]). Returns 0, or -1 when out of
 * memory. */
static int segments_by_triangle(const segment *seg, int64_t n_seg, int64_t nt, int64_t **start,
                                int64_t **list)
{
    int64_t *key = malloc((size_t)(2 * n_seg + 1) * sizeof *key);
    if (!key)
        return -1;
    for (int64_t q = 0; q < n_seg; q++) {
        key[2 * q] = seg[q].x;
        key[2 * q + 1] = seg[q].y;
    }
    const int rc = vc_csr_group(key, n_seg, 2, nt, NULL, start, list);
    free(key);
    return rc;
}

/* Segment q's other triangle than t. */
static inline int64_t other_of(const segment *q, int64_t t)
{
    return q->x == t ? q->y : q->x;
}

typedef struct split_rec {
    int64_t seg, point;
    double param;
} split_rec;

static int cmp_split_rec(const void *pa, const void *pb)
{
    const split_rec *a = pa, *b = pb;
    if (a->seg != b->seg)
        return a->seg < b->seg ? -1 : 1;
    if (a->param != b->param)
        return a->param < b->param ? -1 : 1;
    return (a->point > b->point) - (a->point < b->point);
}

/* Where two segments of one triangle cross properly (three sheets through
 * one point: the triangle, and the two others of the segments), the point
 * the three triangles' planes share (triple_id) splits the three segments
 * of the three pairs, in every one of the three triangles alike: the curves
 * then meet at a vertex instead of crossing. A crossing that is not proper
 * within rounding (an end on the other segment) is left, and split_triangle
 * refuses it as before. *segp (n_seg of them) is replaced by the split
 * segments. Returns 0, or -1 when out of memory. */
static int split_at_triple_points(builder *u, segment **segp, int64_t *n_segp)
{
    segment *seg = *segp;
    const int64_t n_seg = *n_segp;
    int64_t *start = NULL, *list = NULL;
    split_rec *sp = NULL;
    int64_t n_sp = 0, cap_sp = 0;
    int rc = segments_by_triangle(seg, n_seg, u->s->n_triangles, &start, &list);
    for (int64_t t = 0; t < u->s->n_triangles && !rc; t++) {
        const int64_t k0 = start[t], k1 = start[t + 1];
        if (k1 - k0 < 2)
            continue;
        int ai, aj;
        plane_axes(u, t, &ai, &aj);
        for (int64_t i = k0; i < k1 && !rc; i++)
            for (int64_t j = i + 1; j < k1 && !rc; j++) {
                const segment *p = &seg[list[i]], *q = &seg[list[j]];
                if (p->e[0] == q->e[0] || p->e[0] == q->e[1] || p->e[1] == q->e[0] || p->e[1] == q->e[1])
                    continue;
                const double *A = vertex_of(u, p->e[0]), *B = vertex_of(u, p->e[1]);
                const double *C = vertex_of(u, q->e[0]), *D = vertex_of(u, q->e[1]);
                if (!(orient_tol(A, B, C, ai, aj) * orient_tol(A, B, D, ai, aj) < 0 &&
                      orient_tol(C, D, A, ai, aj) * orient_tol(C, D, B, ai, aj) < 0))
                    continue;
                const int64_t y = other_of(p, t), z = other_of(q, t);
                /* the third pair's segment, among y's */
                int64_t third = -1;
                for (int64_t l = start[y]; l < start[y + 1] && third < 0; l++)
                    if (other_of(&seg[list[l]], y) == z)
                        third = list[l];
                if (y == z || third < 0)
                    continue;
                const int64_t lo = t < y ? (t < z ? t : z) : (y < z ? y : z);
                const int64_t hi = t > y ? (t > z ? t : z) : (y > z ? y : z);
                const int64_t pid = triple_id(u, lo, t ^ y ^ z ^ lo ^ hi, hi);
                if (pid < 0 || vc_reserve(&sp, &cap_sp, n_sp + 3, sizeof *sp)) {
                    rc = -1;
                    break;
                }
                const double *P = vertex_of(u, pid);
                if (isnan(P[0]))
                    continue;
                const int64_t sq[3] = {list[i], list[j], third};
                for (int m = 0; m < 3; m++) {
                    const segment *r = &seg[sq[m]];
                    const double *E0 = vertex_of(u, r->e[0]), *E1 = vertex_of(u, r->e[1]);
                    double num = 0, den = 0;
                    for (int c = 0; c < 3; c++) {
                        num += (P[c] - E0[c]) * (E1[c] - E0[c]);
                        den += (E1[c] - E0[c]) * (E1[c] - E0[c]);
                    }
                    sp[n_sp++] = (split_rec){sq[m], pid, num / den};
                }
            }
    }
    if (!rc && n_sp > 0) {
        /* the split segments: each segment's points by parameter, once */
        qsort(sp, (size_t)n_sp, sizeof *sp, cmp_split_rec);
        segment *out = malloc((size_t)(n_seg + n_sp + 1) * sizeof *out);
        if (!out)
            rc = -1;
        int64_t n_out = 0, k = 0;
        for (int64_t q = 0; q < n_seg && out; q++) {
            int64_t from = seg[q].e[0];
            for (; k < n_sp && sp[k].seg == q; k++) {
                if (sp[k].point == from || (k > 0 && sp[k - 1].seg == q && sp[k - 1].point == sp[k].point))
                    continue;
                out[n_out++] = (segment){seg[q].x, seg[q].y, {from, sp[k].point}};
                from = sp[k].point;
            }
            out[n_out++] = (segment){seg[q].x, seg[q].y, {from, seg[q].e[1]}};
        }
        if (out) {
            free(seg);
            *segp = out;
            *n_segp = n_out;
        }
    }
    free(start);
    free(list);
    free(sp);
    return rc;
}

/* ---- Patches and their winding numbers ---- */

typedef struct edge_entry {
    int64_t lo, hi, piece;
} edge_entry;

static int cmp_edge_entry(const void *pa, const void *pb)
{
    const edge_entry *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->piece < b->piece ? -1 : a->piece > b->piece;
}

/* ---- Short curve edges collapsed ---- */

int vc_surface_self_union(const vc_surface *s, const char *name, vc_surface *out, vc_self_union_report *rep,
                          vc_error *err)
{
    memset(out, 0, sizeof *out);
    vc_self_union_report r_local, *r = rep ? rep : &r_local;
    memset(r, 0, sizeof *r);
    name = name && name[0] ? name : "surface";
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    if (nv <= 0 || nt <= 0)
        return vc_error_set(err, VC_EINPUT, "%s: no triangles", name);

    /* coordinates scaled by a power of two: the diagonal in [0.5, 1) */
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++)
        lo[k] = hi[k] = s->xyz[k];
    for (int64_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            double v = s->xyz[3 * i + k];
            lo[k] = v < lo[k] ? v : lo[k];
            hi[k] = v > hi[k] ? v : hi[k];
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(diag > 0) || !isfinite(diag))
        return vc_error_set(err, VC_EINPUT, "%s: the surface has no extent", name);
    int ed;
    frexp(diag, &ed);
    builder u;
    memset(&u, 0, sizeof u);
    u.s = s;
    u.nv = nv;
    double *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    int64_t *pairs = NULL, n_pairs = 0;
    segment *seg = NULL;
    growing pieces = {0};
    int64_t *parent = NULL, *list = NULL, *start = NULL, *rep_piece = NULL;
    edge_entry *ent = NULL;
    double *winding = NULL;
    int rc = 0;
    if (!xyz)
        goto oom;
    /* about the box's centre: the cut points' rounding is then an ulp of
     * the model's size, not of its distance from the origin */
    double centre[3];
    for (int k = 0; k < 3; k++)
        centre[k] = 0.5 * lo[k] + 0.5 * hi[k];
    for (int64_t i = 0; i < 3 * nv; i++)
        xyz[i] = ldexp(s->xyz[i] - centre[i % 3], -ed);
    u.xyz = xyz;
    if (vc_self_intersection_pairs(xyz, s->tri, nt, &pairs, &n_pairs))
        goto oom;
    r->n_pairs = n_pairs;

    /* 1. the segments */
    u.cap_pts = 64;
    for (u.n_slots = 64; u.n_slots < 8 * n_pairs + 64; u.n_slots *= 2)
        ;
    u.pts = malloc((size_t)u.cap_pts * sizeof *u.pts);
    u.pxyz = malloc((size_t)u.cap_pts * 3 * sizeof *u.pxyz);
    u.slot = malloc((size_t)u.n_slots * sizeof *u.slot);
    seg = malloc((size_t)(n_pairs + 1) * sizeof *seg);
    if (!u.pts || !u.pxyz || !u.slot || !seg)
        goto oom;
    for (int64_t i = 0; i < u.n_slots; i++)
        u.slot[i] = -1;
    int64_t n_seg = 0;
    for (int64_t k = 0; k < n_pairs; k++) {
        int64_t x = pairs[2 * k], y = pairs[2 * k + 1], ends[2];
        int oom_flag = 0;
        int res = pair_segment(&u, x, y, ends, &oom_flag);
        if (oom_flag)
            goto oom;
        if (res < 0) {
            rc = vc_error_set(err, VC_EINPUT,
                              "%s: the surface intersects itself (%lld pairs of triangles) and triangles "
                              "%lld and %lld touch in a degenerate way (a vertex or an edge in the other's "
                              "plane, or coplanar): the union of its parts cannot be formed; repair it "
                              "(a boolean union, or remesh)",
                              name, (long long)n_pairs, (long long)x + 1, (long long)y + 1);
            goto done;
        }
        if (res == 1)
            seg[n_seg++] = (segment){x, y, {ends[0], ends[1]}};
    }
    /* 1b. curves crossing inside a triangle: split at their triple points */
    if (split_at_triple_points(&u, &seg, &n_seg) < 0)
        goto oom;
    r->n_segments = n_seg;

    /* 2. the segments of each triangle (segments_by_triangle), each cut triangle
     * split */
    if (segments_by_triangle(seg, n_seg, nt, &start, &list))
        goto oom;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *v = s->tri + 3 * t;
        if (start[t + 1] == start[t]) {
            if (grow_push(&pieces, v[0], v[1], v[2], t))
                goto oom;
            continue;
        }
        r->n_split++;
        int res = split_triangle(&u, t, seg, list + start[t], start[t + 1] - start[t], &pieces);
        if (res == -2)
            goto oom;
        if (res < 0) {
            rc = vc_error_set(err, VC_EINPUT,
                              "%s: the surface intersects itself (%lld pairs of triangles) and the curves "
                              "cross triangle %lld in a degenerate way (three sheets through one point on "
                              "an edge, or a curve closed inside it): the union of its parts cannot be formed; repair "
                              "it (a boolean union, or remesh)",
                              name, (long long)n_pairs, (long long)t + 1);
            goto done;
        }
    }
    const int64_t np = pieces.n / 4;

    /* 3. patches: pieces joined across the edges that are not on a curve */
    ent = malloc((size_t)(3 * np + 2 * n_seg + 1) * sizeof *ent);
    parent = malloc((size_t)(np + 1) * sizeof *parent);
    if (!ent || !parent)
        goto oom;
    int64_t n_ent = 0;
    for (int64_t q = 0; q < n_seg; q++) {
        int64_t a = seg[q].e[0], b = seg[q].e[1];
        ent[n_ent++] = (edge_entry){a < b ? a : b, a < b ? b : a, -1}; /* a curve edge */
    }
    for (int64_t p = 0; p < np; p++) {
        parent[p] = p;
        for (int k = 0; k < 3; k++) {
            int64_t a = pieces.v[4 * p + k], b = pieces.v[4 * p + (k + 1) % 3];
            ent[n_ent++] = (edge_entry){a < b ? a : b, a < b ? b : a, p};
        }
    }
    qsort(ent, (size_t)n_ent, sizeof *ent, cmp_edge_entry);
    for (int64_t i = 0; i < n_ent;) {
        int64_t j = i + 1;
        while (j < n_ent && ent[j].lo == ent[i].lo && ent[j].hi == ent[i].hi)
            j++;
        /* curve edges sort first (piece -1) and join nothing; neither
         * does an edge of more than two pieces (sheets that touch there) */
        if (ent[i].piece >= 0 && j == i + 2)
            vc_uf_unite(parent, ent[i + 1].piece, ent[i].piece);
        i = j;
    }
    /* one representative per patch: its largest piece (deterministic) */
    rep_piece = malloc((size_t)(np + 1) * sizeof *rep_piece);
    winding = malloc((size_t)(np + 1) * sizeof *winding);
    if (!rep_piece || !winding)
        goto oom;
    double *area = winding; /* reused before the winding numbers */
    int64_t n_patches = 0;
    for (int64_t p = 0; p < np; p++)
        rep_piece[p] = -1;
    for (int64_t p = 0; p < np; p++) {
        const double *A = vertex_of(&u, pieces.v[4 * p]), *B = vertex_of(&u, pieces.v[4 * p + 1]),
                     *C = vertex_of(&u, pieces.v[4 * p + 2]);
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = B[k] - A[k];
            e2[k] = C[k] - A[k];
        }
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
        area[p] = cx * cx + cy * cy + cz * cz;
        int64_t root = vc_uf_find(parent, p);
        if (rep_piece[root] < 0)
            n_patches++;
        if (rep_piece[root] < 0 || area[p] > area[rep_piece[root]])
            rep_piece[root] = p;
    }
    /* the roots' representatives, in order */
    int64_t *roots = malloc((size_t)(n_patches + 1) * sizeof *roots);
    double *w_patch = malloc((size_t)(n_patches + 1) * sizeof *w_patch);
    if (!roots || !w_patch) {
        free(roots);
        free(w_patch);
        goto oom;
    }
    int64_t nr = 0;
    for (int64_t p = 0; p < np; p++)
        if (vc_uf_find(parent, p) == p)
            roots[nr++] = p;
    r->n_patches = n_patches;
    int bad = 0;
#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t i = 0; i < nr; i++) {
        int64_t p = rep_piece[roots[i]], src = pieces.v[4 * p + 3];
        double P[3];
        for (int k = 0; k < 3; k++)
            P[k] = (vertex_of(&u, pieces.v[4 * p])[k] + vertex_of(&u, pieces.v[4 * p + 1])[k] +
                    vertex_of(&u, pieces.v[4 * p + 2])[k]) / 3;
        double sum = 0;
        for (int64_t t = 0; t < nt; t++)
            if (t != src)
                sum += vc_solid_angle(P, xyz + 3 * s->tri[3 * t], xyz + 3 * s->tri[3 * t + 1],
                                      xyz + 3 * s->tri[3 * t + 2]);
        w_patch[i] = sum / (4 * 3.14159265358979323846) - 0.5; /* the winding number on the outer side */
    }
    for (int64_t i = 0; i < nr; i++) {
        double w = w_patch[i], wr = floor(w + 0.5);
        if (fabs(w - wr) > 0.25)
            bad = 1;
        winding[roots[i]] = wr;
    }
    free(roots);
    free(w_patch);
    if (bad) {
        rc = vc_error_set(err, VC_EINPUT,
                          "%s: the surface intersects itself (%lld pairs of triangles) and the winding "
                          "numbers of its parts are not whole numbers: it is not closed and oriented "
                          "around each part; repair it (a boolean union, or remesh)",
                          name, (long long)n_pairs);
        goto done;
    }

    /* 4. the kept pieces (outer winding number 0), vertices renumbered in
     * id order */
    int64_t n_ids = nv + u.n_pts, n_keep = 0;
    int64_t *new_id = malloc((size_t)n_ids * sizeof *new_id);
    if (!new_id)
        goto oom;
    for (int64_t i = 0; i < n_ids; i++)
        new_id[i] = -1;
    for (int64_t p = 0; p < np; p++) {
        if (winding[vc_uf_find(parent, p)] != 0)
            continue;
        n_keep++;
        for (int k = 0; k < 3; k++)
            new_id[pieces.v[4 * p + k]] = 0;
    }
    int64_t n_out_v = 0;
    for (int64_t i = 0; i < n_ids; i++)
        if (new_id[i] == 0)
            new_id[i] = n_out_v++;
    out->xyz = malloc((size_t)(n_out_v + 1) * 3 * sizeof *out->xyz);
    out->tri = malloc((size_t)(n_keep + 1) * 3 * sizeof *out->tri);
    if (s->tri_group && s->n_groups > 0) {
        out->tri_group = malloc((size_t)(n_keep + 1) * sizeof *out->tri_group);
        out->group_name = malloc((size_t)s->n_groups * sizeof *out->group_name);
    }
    if (!out->xyz || !out->tri || (s->tri_group && s->n_groups > 0 && (!out->tri_group || !out->group_name))) {
        free(new_id);
        goto oom;
    }
    for (int64_t i = 0; i < n_ids; i++)
        if (new_id[i] >= 0) {
            if (i < nv)
                memcpy(out->xyz + 3 * new_id[i], s->xyz + 3 * i, 3 * sizeof *out->xyz);
            else
                for (int k = 0; k < 3; k++)
                    out->xyz[3 * new_id[i] + k] = centre[k] + ldexp(u.pxyz[3 * (i - nv) + k], ed);
        }
    int64_t q = 0;
    for (int64_t p = 0; p < np; p++) {
        if (winding[vc_uf_find(parent, p)] != 0)
            continue;
        for (int k = 0; k < 3; k++)
            out->tri[3 * q + k] = new_id[pieces.v[4 * p + k]];
        if (out->tri_group)
            out->tri_group[q] = s->tri_group[pieces.v[4 * p + 3]];
        q++;
    }
    int64_t first_cut = 0; /* the input's vertices come first */
    for (int64_t i = 0; i < nv; i++)
        first_cut += new_id[i] >= 0;
    free(new_id);
    out->n_vertices = n_out_v;
    out->n_triangles = n_keep;
    if (out->tri_group) {
        out->n_groups = s->n_groups;
        memcpy(out->group_name, s->group_name, (size_t)s->n_groups * sizeof *out->group_name);
    }
    for (int64_t p = 0; p < np; p++) {
        int64_t root = vc_uf_find(parent, p);
        if (p == root && winding[p] != 0)
            r->n_patches_dropped++;
    }
    r->n_pieces_dropped = np - n_keep;
    {
        int64_t nc = vc_surface_collapse_short_edges(out, first_cut, COLLAPSE_EDGE * diag, NULL);
        if (nc < 0)
            goto oom;
        r->n_collapsed = nc;
        double vol6 = 0;
        for (int64_t t = 0; t < out->n_triangles; t++) {
            const double *A = out->xyz + 3 * out->tri[3 * t], *B = out->xyz + 3 * out->tri[3 * t + 1],
                         *C = out->xyz + 3 * out->tri[3 * t + 2];
            vol6 += A[0] * (B[1] * C[2] - B[2] * C[1]) - A[1] * (B[0] * C[2] - B[2] * C[0]) +
                    A[2] * (B[0] * C[1] - B[1] * C[0]);
        }
        r->volume = vol6 / 6;
    }
    if (n_keep == 0) {
        rc = vc_error_set(err, VC_EINPUT, "%s: the surface intersects itself and no part of it bounds "
                          "the region it winds around", name);
        goto done;
    }
    goto done;
oom:
    rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory forming the union of the self-intersecting surface",
                      name);
done:
    if (rc)
        vc_surface_free(out);
    free(xyz);
    free(pairs);
    free(seg);
    free(u.pts);
    free(u.pxyz);
    free(u.slot);
    free(pieces.v);
    free(parent);
    free(list);
    free(start);
    free(rep_piece);
    free(ent);
    free(winding);
    return rc;
}
