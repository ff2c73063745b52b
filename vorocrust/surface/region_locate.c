/* Which region of a surface's arrangement holds a point (see
 * include/vorocrust/regions.h, vc_region_locate).
 *
 * The first triangle a segment from the point crosses bounds the point's
 * region on the side the segment comes from: nothing lies between them.
 * So the answer needs one first hit that is not degenerate (through a
 * triangle's interior, at an angle, not tied with another triangle).
 * Segments aim at interior points of the triangle nearest the point, then
 * of the triangles around it; a bounding-volume hierarchy over the
 * triangles answers both the nearest-triangle and the first-hit queries. */
#include "vorocrust/regions.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sizing/closest_point.h"

#define LEAF_SIZE 4
/* a hit this close (in barycentric terms) to a triangle's edge, or a
 * segment this close to a triangle's plane, may have gone through a
 * neighbour instead: aim elsewhere */
#define EDGE_MARGIN 1e-7
#define GRAZE_COS 1e-6
/* two hits this close along the segment (relative) are a tie */
#define TIE_REL 1e-9

typedef struct bvh_node {
    double lo[3], hi[3];
    int64_t first, count; /* leaf: triangles order[first..first+count-1]; inner: count 0 */
    int64_t left, right;
} bvh_node;

struct vc_region_locator {
    const vc_surface *s;
    const int64_t *side_region; /* 2 per triangle */
    int64_t *order;
    bvh_node *node;
    int64_t n_nodes;
    double *centroid;
};

static const double *vtx(const vc_region_locator *L, int64_t t, int k)
{
    return L->s->xyz + 3 * L->s->tri[3 * t + k];
}

typedef struct sort_ctx {
    const double *centroid;
    int axis;
} sort_ctx;

static sort_ctx g_sort; /* build is single-threaded */

static int cmp_centroid(const void *a, const void *b)
{
    const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    const double u = g_sort.centroid[3 * x + g_sort.axis], v = g_sort.centroid[3 * y + g_sort.axis];
    if (u != v)
        return u < v ? -1 : 1;
    return (x > y) - (x < y);
}

static int64_t build(vc_region_locator *L, int64_t first, int64_t count)
{
    const int64_t id = L->n_nodes++;
    bvh_node *nd = &L->node[id];
    for (int d = 0; d < 3; d++) {
        nd->lo[d] = INFINITY;
        nd->hi[d] = -INFINITY;
    }
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = first; i < first + count; i++) {
        const int64_t t = L->order[i];
        for (int k = 0; k < 3; k++) {
            const double *p = vtx(L, t, k);
            for (int d = 0; d < 3; d++) {
                nd->lo[d] = fmin(nd->lo[d], p[d]);
                nd->hi[d] = fmax(nd->hi[d], p[d]);
            }
        }
        for (int d = 0; d < 3; d++) {
            clo[d] = fmin(clo[d], L->centroid[3 * t + d]);
            chi[d] = fmax(chi[d], L->centroid[3 * t + d]);
        }
    }
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count <= LEAF_SIZE)
        return id;
    int axis = 0;
    for (int d = 1; d < 3; d++)
        if (chi[d] - clo[d] > chi[axis] - clo[axis])
            axis = d;
    g_sort.centroid = L->centroid;
    g_sort.axis = axis;
    qsort(L->order + first, (size_t)count, sizeof(int64_t), cmp_centroid);
    const int64_t half = count / 2;
    const int64_t left = build(L, first, half);
    const int64_t right = build(L, first + half, count - half);
    nd = &L->node[id];
    nd->count = 0;
    nd->left = left;
    nd->right = right;
    return id;
}

int vc_region_locator_build(const vc_surface *s, const int64_t *side_region,
                            vc_region_locator **out, vc_error *err)
{
    *out = NULL;
    vc_region_locator *L = calloc(1, sizeof *L);
    const int64_t n = s->n_triangles;
    if (L) {
        L->s = s;
        L->side_region = side_region;
        L->order = malloc(sizeof(int64_t) * (size_t)(n + 1));
        L->node = malloc(sizeof(bvh_node) * (size_t)(2 * n + 1));
        L->centroid = malloc(sizeof(double) * 3 * (size_t)(n + 1));
    }
    if (!L || !L->order || !L->node || !L->centroid) {
        vc_region_locator_free(L);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the region locator");
    }
    for (int64_t t = 0; t < n; t++) {
        L->order[t] = t;
        for (int d = 0; d < 3; d++)
            L->centroid[3 * t + d] = (vtx(L, t, 0)[d] + vtx(L, t, 1)[d] + vtx(L, t, 2)[d]) / 3.0;
    }
    if (n > 0)
        build(L, 0, n);
    *out = L;
    return 0;
}

void vc_region_locator_free(vc_region_locator *L)
{
    if (!L)
        return;
    free(L->order);
    free(L->node);
    free(L->centroid);
    free(L);
}

static double box_dist2(const bvh_node *nd, const double p[3])
{
    double d2 = 0;
    for (int d = 0; d < 3; d++) {
        const double e = p[d] < nd->lo[d] ? nd->lo[d] - p[d] : p[d] > nd->hi[d] ? p[d] - nd->hi[d] : 0;
        d2 += e * e;
    }
    return d2;
}

/* The triangles within sqrt(r2) of p, up to cap of them, nearest first is
 * not needed: the caller sorts. Returns how many were written. */
static int64_t near_triangles(const vc_region_locator *L, const double p[3], double r2,
                              int64_t *tri, double *dist2, int64_t cap)
{
    int64_t stack[128];
    int top = 0, n = 0;
    if (L->n_nodes == 0)
        return 0;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &L->node[stack[--top]];
        if (box_dist2(nd, p) > r2)
            continue;
        if (nd->count == 0) {
            if (top + 2 <= 128) {
                stack[top++] = nd->left;
                stack[top++] = nd->right;
            }
            continue;
        }
        for (int64_t i = nd->first; i < nd->first + nd->count; i++) {
            const int64_t t = L->order[i];
            const double d2 = vc_closest_on_triangle(p, vtx(L, t, 0), vtx(L, t, 1), vtx(L, t, 2), NULL);
            if (d2 <= r2 && n < cap) {
                tri[n] = t;
                dist2[n] = d2;
                n++;
            }
        }
    }
    return n;
}

/* The triangle nearest p (lowest index among ties). */
static int64_t nearest_triangle(const vc_region_locator *L, const double p[3], double *best2)
{
    int64_t stack[128];
    int top = 0;
    int64_t best = -1;
    *best2 = INFINITY;
    if (L->n_nodes == 0)
        return -1;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &L->node[stack[--top]];
        if (box_dist2(nd, p) > *best2)
            continue;
        if (nd->count == 0) {
            /* the nearer child last, so it is searched first */
            const double dl = box_dist2(&L->node[nd->left], p), dr = box_dist2(&L->node[nd->right], p);
            if (top + 2 <= 128) {
                stack[top++] = dl < dr ? nd->right : nd->left;
                stack[top++] = dl < dr ? nd->left : nd->right;
            }
            continue;
        }
        for (int64_t i = nd->first; i < nd->first + nd->count; i++) {
            const int64_t t = L->order[i];
            const double d2 = vc_closest_on_triangle(p, vtx(L, t, 0), vtx(L, t, 1), vtx(L, t, 2), NULL);
            if (d2 < *best2 || (d2 == *best2 && t < best)) {
                *best2 = d2;
                best = t;
            }
        }
    }
    return best;
}

/* Does the segment p + s d, s in [0, 1], meet the box? */
static int segment_meets_box(const bvh_node *nd, const double p[3], const double d[3], double smax)
{
    double s0 = 0, s1 = smax;
    for (int k = 0; k < 3; k++) {
        if (fabs(d[k]) < 1e-300) {
            if (p[k] < nd->lo[k] || p[k] > nd->hi[k])
                return 0;
            continue;
        }
        double a = (nd->lo[k] - p[k]) / d[k], b = (nd->hi[k] - p[k]) / d[k];
        if (a > b) {
            const double x = a;
            a = b;
            b = x;
        }
        s0 = fmax(s0, a);
        s1 = fmin(s1, b);
        if (s0 > s1 * (1 + 1e-12) + 1e-300)
            return 0;
    }
    return 1;
}

/* The region on p's side of the first triangle the segment p + s d
 * (0 < s <= 1) crosses; -2 when that first crossing is degenerate or
 * there is none. */
static int64_t first_hit_region(const vc_region_locator *L, const double p[3], const double d[3])
{
    int64_t stack[128];
    int top = 0;
    double best_s = 1.0 + 1e-9, second_s = INFINITY;
    int64_t best_t = -1;
    int best_side = 0, best_clean = 0;
    const double dn = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &L->node[stack[--top]];
        if (!segment_meets_box(nd, p, d, best_s * (1 + TIE_REL) + 1e-12))
            continue;
        if (nd->count == 0) {
            if (top + 2 <= 128) {
                stack[top++] = nd->left;
                stack[top++] = nd->right;
            }
            continue;
        }
        for (int64_t i = nd->first; i < nd->first + nd->count; i++) {
            const int64_t t = L->order[i];
            const double *a = vtx(L, t, 0), *b = vtx(L, t, 1), *c = vtx(L, t, 2);
            /* Moller-Trumbore */
            const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            const double h[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                                 d[0] * e2[1] - d[1] * e2[0]};
            const double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
            const double nx = e1[1] * e2[2] - e1[2] * e2[1], ny = e1[2] * e2[0] - e1[0] * e2[2],
                         nz = e1[0] * e2[1] - e1[1] * e2[0];
            const double nn = sqrt(nx * nx + ny * ny + nz * nz);
            const double sv[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
            if (det == 0 || nn == 0) {
                /* parallel to the plane: a crossing only if p lies in it */
                continue;
            }
            const double inv = 1.0 / det;
            const double u = (sv[0] * h[0] + sv[1] * h[1] + sv[2] * h[2]) * inv;
            const double q[3] = {sv[1] * e1[2] - sv[2] * e1[1], sv[2] * e1[0] - sv[0] * e1[2],
                                 sv[0] * e1[1] - sv[1] * e1[0]};
            const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
            const double s = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
            const double m = EDGE_MARGIN;
            if (u < -m || v < -m || u + v > 1 + m || s <= 0 || s > 1 + 1e-9)
                continue;
            const int clean = u > m && v > m && u + v < 1 - m &&
                              fabs(det) > GRAZE_COS * nn * dn;
            if (s < best_s) {
                second_s = best_s;
                best_s = s;
                best_t = t;
                best_clean = clean;
                /* d against the normal: the segment enters through the front */
                best_side = (nx * d[0] + ny * d[1] + nz * d[2]) < 0 ? 0 : 1;
            } else if (s < second_s) {
                second_s = s;
            }
        }
    }
    if (best_t < 0 || !best_clean || second_s - best_s <= TIE_REL * (best_s + 1e-300))
        return -2;
    return L->side_region[2 * best_t + best_side];
}

/* Interior points of a triangle to aim at, in barycentric coordinates. */
static const double aim[][3] = {
    {1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.6, 0.2, 0.2}, {0.2, 0.6, 0.2}, {0.2, 0.2, 0.6},
    {0.45, 0.45, 0.1}, {0.1, 0.45, 0.45}, {0.45, 0.1, 0.45}, {0.7, 0.13, 0.17},
};
#define N_AIM ((int)(sizeof aim / sizeof aim[0]))
#define N_NEAR 16

static int64_t aim_at(const vc_region_locator *L, const double p[3], int64_t t)
{
    const double *a = vtx(L, t, 0), *b = vtx(L, t, 1), *c = vtx(L, t, 2);
    for (int k = 0; k < N_AIM; k++) {
        double d[3];
        for (int j = 0; j < 3; j++)
            d[j] = (aim[k][0] * a[j] + aim[k][1] * b[j] + aim[k][2] * c[j] - p[j]) * (1 + 1e-6);
        const int64_t r = first_hit_region(L, p, d);
        if (r != -2)
            return r;
    }
    return -2;
}

int64_t vc_region_locate(const vc_region_locator *L, const double p[3])
{
    double d2;
    const int64_t t = nearest_triangle(L, p, &d2);
    if (t < 0)
        return -1;
    if (d2 == 0)
        return -2;
    int64_t r = aim_at(L, p, t);
    if (r != -2)
        return r;
    /* every aim at the nearest triangle grazed something: the triangles a
     * little farther */
    int64_t tri[N_NEAR];
    double dist2[N_NEAR];
    const int64_t n = near_triangles(L, p, 4 * d2 + 1e-300, tri, dist2, N_NEAR);
    for (int64_t i = 0; i < n; i++)
        if (tri[i] != t && (r = aim_at(L, p, tri[i])) != -2)
            return r;
    return -2;
}
