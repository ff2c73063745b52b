/* Self-intersections of a triangle surface: a bounding-volume hierarchy
 * gives the pairs of triangles whose boxes overlap, and a triangle-triangle
 * test built on filtered orientation predicates (predicates.h) decides each
 * pair according to how many vertices the two share (see
 * self_intersection.h for what counts as an intersection).
 *
 * The tests, for triangles A and B:
 *   - no shared vertex: if the vertices of one are strictly on one side of
 *     the other's plane, they are apart. If one lies in the other's plane,
 *     the test is two-dimensional (projection on the coordinate plane the
 *     normal is closest to): an edge of A meets B, or a vertex of B lies in
 *     A. Otherwise two non-coplanar triangles meet iff an edge of one meets
 *     the other (the ends of their common segment lie on edges).
 *   - one shared vertex v, A = (v, a, b), B = (v, c, d): they meet beyond v
 *     iff edge ab meets B or edge cd meets A (the common part is a segment
 *     or region from v, whose far end lies on ab or cd; coplanar wedges
 *     likewise).
 *   - a shared edge ab, A = (a, b, c), B = (a, b, d): they overlap iff they
 *     are coplanar and c, d lie on the same side of ab.
 * The orientations are exact (predicates.h): zero only for points exactly
 * coplanar, which counts as touching. */
#include "surface/self_intersection.h"
#include "util/radix_sort.h"
#include "surface/predicates.h"
#include "util/morton.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Inline minimum and maximum (fmin/fmax are library calls without
 * -ffast-math; no NaN reaches them: the coordinates are finite). */
static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* ---- Triangle tests ---- */

/* The two coordinate axes left when dropping the one the normal of abc is
 * closest to. */
static void plane_axes(const double *a, const double *b, const double *c, int *i, int *j)
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {fabs(u[1] * v[2] - u[2] * v[1]), fabs(u[2] * v[0] - u[0] * v[2]),
                   fabs(u[0] * v[1] - u[1] * v[0])};
    int k = n[0] >= n[1] && n[0] >= n[2] ? 0 : n[1] >= n[2] ? 1 : 2;
    *i = (k + 1) % 3;
    *j = (k + 2) % 3;
}

/* Whether r, collinear with p and q, lies within the box of the segment pq. */
static int within(const double *p, const double *q, const double *r, int i, int j)
{
    return r[i] >= dmin(p[i], q[i]) && r[i] <= dmax(p[i], q[i]) && r[j] >= dmin(p[j], q[j]) &&
           r[j] <= dmax(p[j], q[j]);
}

/* Closed segments pq and rs meet (2D, axes i, j). */
static int seg_seg_2d(const double *p, const double *q, const double *r, const double *s, int i, int j)
{
    int o1 = vc_orient2d(p, q, r, i, j), o2 = vc_orient2d(p, q, s, i, j);
    int o3 = vc_orient2d(r, s, p, i, j), o4 = vc_orient2d(r, s, q, i, j);
    if (o1 * o2 < 0 && o3 * o4 < 0)
        return 1;
    return (o1 == 0 && within(p, q, r, i, j)) || (o2 == 0 && within(p, q, s, i, j)) ||
           (o3 == 0 && within(r, s, p, i, j)) || (o4 == 0 && within(r, s, q, i, j));
}

/* p lies in the closed triangle abc (2D). A triangle collinear in the
 * projection contains nothing (the callers project along its normal). */
static int point_in_tri_2d(const double *p, const double *a, const double *b, const double *c, int i, int j)
{
    int o1 = vc_orient2d(a, b, p, i, j), o2 = vc_orient2d(b, c, p, i, j), o3 = vc_orient2d(c, a, p, i, j);
    int pos = o1 > 0 || o2 > 0 || o3 > 0, neg = o1 < 0 || o2 < 0 || o3 < 0;
    return !(pos && neg) && (pos || neg);
}

static int seg_tri_2d(const double *p, const double *q, const double *a, const double *b, const double *c,
                      int i, int j)
{
    return point_in_tri_2d(p, a, b, c, i, j) || point_in_tri_2d(q, a, b, c, i, j) ||
           seg_seg_2d(p, q, a, b, i, j) || seg_seg_2d(p, q, b, c, i, j) || seg_seg_2d(p, q, c, a, i, j);
}

/* Closed segment pq meets the closed triangle abc; sp, sq are the signs of
 * p and q against abc's plane (vc_orient3d(a, b, c, .)). */
static int seg_tri(const double *p, const double *q, int sp, int sq, const double *a, const double *b,
                   const double *c)
{
    if (sp * sq > 0)
        return 0;
    int i, j;
    if (sp == 0 || sq == 0) {
        /* An end in the plane (exactly): it is where the segment
         * meets the plane (a line test would follow a nearly parallel
         * line to a crossing far away). */
        plane_axes(a, b, c, &i, &j);
        if (sp == 0 && sq == 0)
            return seg_tri_2d(p, q, a, b, c, i, j);
        return point_in_tri_2d(sp == 0 ? p : q, a, b, c, i, j);
    }
    int o1 = vc_orient3d(p, q, a, b), o2 = vc_orient3d(p, q, b, c), o3 = vc_orient3d(p, q, c, a);
    int pos = o1 > 0 || o2 > 0 || o3 > 0, neg = o1 < 0 || o2 < 0 || o3 < 0;
    if (pos && neg)
        return 0;
    if (!pos && !neg) { /* the line lies in the plane */
        plane_axes(a, b, c, &i, &j);
        return seg_tri_2d(p, q, a, b, c, i, j);
    }
    return 1;
}

static int same_strict_side(const int *s) { return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0); }

/* A and B share no vertex. */
static int disjoint_pair(const double *const *A, const double *const *B)
{
    int sa[3], sb[3];
    for (int k = 0; k < 3; k++)
        sa[k] = vc_orient3d(B[0], B[1], B[2], A[k]);
    if (same_strict_side(sa))
        return 0;
    for (int k = 0; k < 3; k++)
        sb[k] = vc_orient3d(A[0], A[1], A[2], B[k]);
    if (same_strict_side(sb))
        return 0;
    if ((!sa[0] && !sa[1] && !sa[2]) || (!sb[0] && !sb[1] && !sb[2])) {
        int i, j;
        plane_axes(A[0], A[1], A[2], &i, &j);
        for (int k = 0; k < 3; k++)
            if (seg_tri_2d(A[k], A[(k + 1) % 3], B[0], B[1], B[2], i, j))
                return 1;
        return point_in_tri_2d(B[0], A[0], A[1], A[2], i, j);
    }
    for (int k = 0; k < 3; k++) {
        int l = (k + 1) % 3;
        if (seg_tri(A[k], A[l], sa[k], sa[l], B[0], B[1], B[2]) ||
            seg_tri(B[k], B[l], sb[k], sb[l], A[0], A[1], A[2]))
            return 1;
    }
    return 0;
}

/* A = (v, a, b), B = (v, c, d). */
static int vertex_pair(const double *v, const double *a, const double *b, const double *c, const double *d)
{
    int sc = vc_orient3d(v, a, b, c), sd = vc_orient3d(v, a, b, d);
    if (sc * sd > 0)
        return 0;
    int sa = vc_orient3d(v, c, d, a), sb = vc_orient3d(v, c, d, b);
    if (sa * sb > 0)
        return 0;
    return seg_tri(c, d, sc, sd, v, a, b) || seg_tri(a, b, sa, sb, v, c, d);
}

/* A = (a, b, c), B = (a, b, d). */
static int edge_pair(const double *a, const double *b, const double *c, const double *d)
{
    if (vc_orient3d(a, b, c, d) != 0)
        return 0;
    int i, j;
    plane_axes(a, b, c, &i, &j);
    return vc_orient2d(a, b, c, i, j) * vc_orient2d(a, b, d, i, j) > 0;
}

/* Whether triangles t and u intersect improperly. */
static int pair_intersects(const double *xyz, const int64_t *tri, int64_t t, int64_t u)
{
    const int64_t *vt = tri + 3 * t, *vu = tri + 3 * u;
    int shared = 0, st[3] = {-1, -1, -1}; /* st[k]: the corner of u equal to corner k of t */
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++)
            if (vt[k] == vu[l]) {
                st[k] = l;
                shared++;
            }
    const double *A[3], *B[3];
    for (int k = 0; k < 3; k++) {
        A[k] = xyz + 3 * vt[k];
        B[k] = xyz + 3 * vu[k];
    }
    if (shared == 0)
        return disjoint_pair(A, B);
    if (shared >= 3)
        return 0; /* the same triangle: reported as repeated */
    if (shared == 1) {
        int k = st[0] >= 0 ? 0 : st[1] >= 0 ? 1 : 2, l = st[k];
        return vertex_pair(A[k], A[(k + 1) % 3], A[(k + 2) % 3], B[(l + 1) % 3], B[(l + 2) % 3]);
    }
    /* Two shared: the corner of t not shared, the one of u not shared. */
    int k = st[0] < 0 ? 0 : st[1] < 0 ? 1 : 2;
    int used[3] = {0, 0, 0};
    for (int m = 0; m < 3; m++)
        if (st[m] >= 0)
            used[st[m]] = 1;
    int l = !used[0] ? 0 : !used[1] ? 1 : 2;
    return edge_pair(A[(k + 1) % 3], A[(k + 2) % 3], A[k], B[l]);
}

/* ---- Bounding-volume hierarchy ---- */

typedef struct box {
    double lo[3], hi[3];
} box;

/* An inner node holds its two children's boxes and item ranges, so that a
 * query reads one node to decide both; a child with c[k] < 0 is a leaf (its
 * items are scanned). */
typedef struct node {
    box cb[2];
    int64_t c[2];
    int64_t lo[2], hi[2]; /* the children's items: sorted positions [lo, hi) */
} node;

enum { LEAF = 4 };

static inline int overlap(const box *a, const box *b)
{
    return a->lo[0] <= b->hi[0] && b->lo[0] <= a->hi[0] && a->lo[1] <= b->hi[1] && b->lo[1] <= a->hi[1] &&
           a->lo[2] <= b->hi[2] && b->lo[2] <= a->hi[2];
}

static void box_union(box *r, const box *a, const box *b)
{
    for (int k = 0; k < 3; k++) {
        r->lo[k] = dmin(a->lo[k], b->lo[k]);
        r->hi[k] = dmax(a->hi[k], b->hi[k]);
    }
}

/* Builds the subtree of the items [lo, hi) (more than LEAF of them); sets
 * *bound to their box; returns the node's index. */
static int64_t build(node *nodes, int64_t *n_nodes, const box *items, int64_t lo, int64_t hi, box *bound)
{
    int64_t id = (*n_nodes)++;
    int64_t mid = lo + (hi - lo) / 2;
    int64_t r[3] = {lo, mid, hi};
    for (int k = 0; k < 2; k++) {
        box bk;
        int64_t ck = -1;
        if (r[k + 1] - r[k] <= LEAF) {
            bk = items[r[k]];
            for (int64_t q = r[k] + 1; q < r[k + 1]; q++)
                box_union(&bk, &bk, &items[q]);
        } else {
            ck = build(nodes, n_nodes, items, r[k], r[k + 1], &bk);
        }
        node *nd = &nodes[id];
        nd->cb[k] = bk;
        nd->c[k] = ck;
        nd->lo[k] = r[k];
        nd->hi[k] = r[k + 1];
    }
    box_union(bound, &nodes[id].cb[0], &nodes[id].cb[1]);
    return id;
}

static int cmp_pair(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    return x[0] != y[0] ? (x[0] < y[0] ? -1 : 1) : x[1] < y[1] ? -1 : x[1] > y[1];
}

/* Appends the pair (lo, hi) to a growing array; -1 when out of memory. */
static int push_pair(int64_t **v, int64_t *n, int64_t *cap, int64_t lo, int64_t hi)
{
    if (*n == *cap) {
        int64_t c = *cap ? 2 * *cap : 64;
        int64_t *g = realloc(*v, (size_t)c * 2 * sizeof *g);
        if (!g)
            return -1;
        *v = g;
        *cap = c;
    }
    (*v)[2 * *n] = lo;
    (*v)[2 * *n + 1] = hi;
    ++*n;
    return 0;
}

/* Counts the intersecting pairs and, with pairs != NULL, lists them. */
static int scan(const double *xyz, const int64_t *tri, int64_t nt, const unsigned char *skip,
                int64_t *count, int64_t first[2], int64_t **pairs)
{
    *count = 0;
    first[0] = first[1] = -1;
    int64_t m = 0;
    for (int64_t t = 0; t < nt; t++)
        m += !(skip && skip[t]);
    if (m < 2)
        return 0;

    int64_t *order = malloc((size_t)m * sizeof *order);
    uint64_t *key = malloc((size_t)m * sizeof *key);
    box *tbox = malloc((size_t)m * sizeof *tbox);
    box *items = malloc((size_t)m * sizeof *items);
    node *nodes = malloc((size_t)m * sizeof *nodes);
    if (!order || !key || !tbox || !items || !nodes) {
        free(order);
        free(key);
        free(tbox);
        free(items);
        free(nodes);
        return -1;
    }

    /* Boxes of the kept triangles (tri_of[q]: the triangle of tbox[q]) and
     * the box of their centres. */
    int64_t *tri_of = malloc((size_t)m * sizeof *tri_of);
    if (!tri_of) {
        free(order);
        free(key);
        free(tbox);
        free(items);
        free(nodes);
        return -1;
    }
    box all = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    m = 0;
    for (int64_t t = 0; t < nt; t++) {
        if (skip && skip[t])
            continue;
        box *b = &tbox[m];
        for (int k = 0; k < 3; k++) {
            double x0 = xyz[3 * tri[3 * t] + k], x1 = xyz[3 * tri[3 * t + 1] + k], x2 = xyz[3 * tri[3 * t + 2] + k];
            b->lo[k] = dmin(x0, dmin(x1, x2));
            b->hi[k] = dmax(x0, dmax(x1, x2));
            double cen = 0.5 * b->lo[k] + 0.5 * b->hi[k];
            all.lo[k] = dmin(all.lo[k], cen);
            all.hi[k] = dmax(all.hi[k], cen);
        }
        tri_of[m++] = t;
    }
    /* Morton order of the box centres. */
    for (int64_t q = 0; q < m; q++) {
        uint64_t code = 0;
        for (int k = 0; k < 3; k++) {
            double ext = all.hi[k] - all.lo[k];
            double cen = 0.5 * tbox[q].lo[k] + 0.5 * tbox[q].hi[k];
            double f = ext > 0 ? (cen - all.lo[k]) / ext : 0;
            uint64_t g = (uint64_t)(dmin(dmax(f, 0), 1) * 2097151.0);
            code |= vc_morton_spread3(g) << k;
        }
        key[q] = code;
        order[q] = q; /* position in tbox for now */
    }
    int64_t *pos_tri = malloc((size_t)m * sizeof *pos_tri);
    if (!pos_tri || vc_radix_sort_u64(key, order, m)) {
        free(pos_tri);
        free(tri_of);
        free(order);
        free(key);
        free(tbox);
        free(items);
        free(nodes);
        return -1;
    }
    /* Sorted position q holds tbox[order[q]]. */
    for (int64_t q = 0; q < m; q++) {
        items[q] = tbox[order[q]];
        pos_tri[q] = tri_of[order[q]];
    }
    free(tri_of);
    free(tbox);
    free(order);
    free(key);

    /* Fewer items than a leaf: one node whose first child holds them all. */
    int64_t n_nodes = 0;
    if (m > LEAF) {
        box root_box;
        build(nodes, &n_nodes, items, 0, m, &root_box);
    } else {
        node *nd = &nodes[n_nodes++];
        nd->cb[0] = nd->cb[1] = items[0];
        nd->c[0] = nd->c[1] = -1;
        nd->lo[0] = 0;
        nd->hi[0] = m;
        nd->lo[1] = nd->hi[1] = m;
    }

    int64_t total = 0, best0 = -1, best1 = -1, *all_pairs = NULL, n_all = 0;
    int oom = 0;
#pragma omp parallel
    {
        int64_t local = 0, b0 = -1, b1 = -1, *mine = NULL, n_mine = 0, cap = 0;
        int my_oom = 0;
        int64_t stack[128];
#pragma omp for schedule(dynamic, 256) nowait
        for (int64_t p = 0; p < m; p++) {
            const box *bp = &items[p];
            int64_t t = pos_tri[p];
            int sp = 0;
            stack[sp++] = 0;
            while (sp > 0) {
                const node *nd = &nodes[stack[--sp]];
                for (int k = 0; k < 2; k++) {
                    if (nd->hi[k] <= p + 1 || !overlap(&nd->cb[k], bp))
                        continue;
                    if (nd->c[k] >= 0) {
                        stack[sp++] = nd->c[k];
                        continue;
                    }
                    for (int64_t q = nd->lo[k] > p + 1 ? nd->lo[k] : p + 1; q < nd->hi[k]; q++) {
                        if (!overlap(&items[q], bp))
                            continue;
                        int64_t u = pos_tri[q];
                        if (!pair_intersects(xyz, tri, t, u))
                            continue;
                        local++;
                        int64_t lo = t < u ? t : u, hi = t < u ? u : t;
                        if (pairs && !my_oom && push_pair(&mine, &n_mine, &cap, lo, hi))
                            my_oom = 1;
                        if (b0 < 0 || lo < b0 || (lo == b0 && hi < b1)) {
                            b0 = lo;
                            b1 = hi;
                        }
                    }
                }
            }
        }
#pragma omp critical(vc_self_intersections)
        {
            total += local;
            if (pairs && !oom) {
                int64_t *g = my_oom ? NULL : realloc(all_pairs, (size_t)(n_all + n_mine + 1) * 2 * sizeof *g);
                if (!g) {
                    oom = 1;
                } else {
                    all_pairs = g;
                    if (n_mine)
                        memcpy(all_pairs + 2 * n_all, mine, (size_t)n_mine * 2 * sizeof *mine);
                    n_all += n_mine;
                }
            }
            if (b0 >= 0 && (best0 < 0 || b0 < best0 || (b0 == best0 && b1 < best1))) {
                best0 = b0;
                best1 = b1;
            }
        }
        free(mine);
    }
    free(pos_tri);
    free(items);
    free(nodes);
    *count = total;
    first[0] = best0;
    first[1] = best1;
    if (pairs) {
        if (oom) {
            free(all_pairs);
            return -1;
        }
        /* the threads' order varies: sorted, the list does not */
        if (n_all > 1)
            qsort(all_pairs, (size_t)n_all, 2 * sizeof *all_pairs, cmp_pair);
        *pairs = all_pairs;
    }
    return 0;
}

int vc_self_intersections(const double *xyz, const int64_t *tri, int64_t nt, const unsigned char *skip,
                          int64_t *count, int64_t first[2])
{
    return scan(xyz, tri, nt, skip, count, first, NULL);
}

int vc_self_intersection_pairs(const double *xyz, const int64_t *tri, int64_t nt, int64_t **pairs,
                               int64_t *count)
{
    int64_t first[2];
    *pairs = NULL;
    return scan(xyz, tri, nt, NULL, count, first, pairs);
}
