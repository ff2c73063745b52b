/* Which region of a surface's arrangement holds a point (see
 * include/vorocrust/regions.h, vc_region_locate).
 *
 * The first triangle a segment from the point crosses bounds the point's
 * region on the side the segment comes from: nothing lies between them.
 * So the answer needs one first hit that is not degenerate (through a
 * triangle's interior, at an angle, not tied with another triangle).
 * Segments aim at the nearest point of the nearest triangle (pulled a
 * little inside it), then at interior points of that triangle and of the
 * triangles around it; a bounding-volume hierarchy over the
 * triangles answers both the nearest-triangle and the first-hit queries. */
#include "vorocrust/regions.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/closest_point.h"
#include "util/exact_predicates.h"

#define LEAF_SIZE 4
/* how far the first aim moves from the nearest point towards the
 * triangle's centroid (a share of the way) */
#define PULL 1e-4
/* two hits this close along the segment (relative) are a tie */
#define TIE_REL 1e-9

typedef struct keyed {
    double key;
    int64_t t;
} keyed;

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
    keyed *scratch; /* while building */
};

static const double *vtx(const vc_region_locator *L, int64_t t, int k)
{
    return L->s->xyz + 3 * L->s->tri[3 * t + k];
}

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return (x->t > y->t) - (x->t < y->t);
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
    /* median split along the widest spread of the centroids */
    keyed *k = L->scratch + first;
    for (int64_t i = 0; i < count; i++)
        k[i] = (keyed){L->centroid[3 * L->order[first + i] + axis], L->order[first + i]};
    qsort(k, (size_t)count, sizeof(keyed), cmp_keyed);
    for (int64_t i = 0; i < count; i++)
        L->order[first + i] = k[i].t;
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
    L->scratch = malloc(sizeof(keyed) * (size_t)(n + 1));
    if (!L->scratch) {
        vc_region_locator_free(L);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the region locator");
    }
    if (n > 0)
        build(L, 0, n);
    free(L->scratch);
    L->scratch = NULL;
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
    free(L->scratch);
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

/* Does the segment from p to e cross triangle abc through its interior?
 * 1 yes, 0 no, -1 degenerate (an end on its plane, or the line through an
 * edge or a vertex). Exact (orientation predicates), so a segment that
 * passes 1e-12 beside an edge is a clean miss or a clean hit. *front:
 * the segment enters through the front (the side the normal of a, b, c
 * points to). -2 when out of memory. */
static int crosses(const double p[3], const double e[3], const double *a, const double *b,
                   const double *c, int *front)
{
    const int sp = vc_orient3d_exact(a, b, c, p), se = vc_orient3d_exact(a, b, c, e);
    if (sp == VC_PREDICATE_NOMEM || se == VC_PREDICATE_NOMEM)
        return -2;
    if (sp == se)
        return sp == 0 ? -1 : 0;
    if (sp == 0 || se == 0)
        return -1;
    const int s1 = vc_orient3d_exact(p, e, a, b), s2 = vc_orient3d_exact(p, e, b, c),
              s3 = vc_orient3d_exact(p, e, c, a);
    if (s1 == VC_PREDICATE_NOMEM || s2 == VC_PREDICATE_NOMEM || s3 == VC_PREDICATE_NOMEM)
        return -2;
    if ((s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0)) {
        /* orient3d(a, b, c, p) < 0: p above the plane, on the front */
        *front = sp < 0;
        return 1;
    }
    if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0))
        return -1; /* through an edge or a vertex */
    return 0;
}

/* The region on p's side of the first triangle the segment p + s d
 * (0 < s <= 1) crosses; -2 when that first crossing is degenerate (through
 * an edge, or tied with another), or there is none. */
static int64_t first_hit_region(const vc_region_locator *L, const double p[3], const double d[3])
{
    int64_t stack[128];
    int top = 0;
    const double e[3] = {p[0] + d[0], p[1] + d[1], p[2] + d[2]};
    double best_s = INFINITY, second_s = INFINITY;
    int64_t best_t = -1;
    int best_front = 0, best_clean = 0;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &L->node[stack[--top]];
        if (!segment_meets_box(nd, p, d, fmin(1.0, best_s * (1 + TIE_REL)) + 1e-12))
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
            int front = 0;
            const int x = crosses(p, e, a, b, c, &front);
            if (x == 0)
                continue;
            if (x == -2)
                return -2;
            /* where along the segment: by the plane's distances (only the
             * order of the hits needs it; near-ties are refused below) */
            const double n[3] = {(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                                 (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                                 (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])};
            const double dp = n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]) + n[2] * (p[2] - a[2]);
            const double dd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
            const double s = dd != 0 ? -dp / dd : 0;
            if (s < best_s) {
                second_s = best_s;
                best_s = s;
                best_t = t;
                best_front = front;
                best_clean = x == 1;
            } else if (s < second_s) {
                second_s = s;
            }
        }
    }
    if (best_t < 0 || !best_clean || second_s - best_s <= TIE_REL * fabs(best_s))
        return -2;
    return L->side_region[2 * best_t + (best_front ? 0 : 1)];
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

/* Aims at the point of triangle t nearest p, pulled a little into the
 * triangle (so that a nearest point on an edge is not shared with the
 * neighbour): from a point very close to the surface, the one direction
 * that crosses it at an angle. */
static int64_t aim_nearest(const vc_region_locator *L, const double p[3], int64_t t)
{
    const double *a = vtx(L, t, 0), *b = vtx(L, t, 1), *c = vtx(L, t, 2);
    double q[3];
    vc_closest_on_triangle(p, a, b, c, q);
    double d[3];
    for (int j = 0; j < 3; j++) {
        const double centre = (a[j] + b[j] + c[j]) / 3.0;
        d[j] = (q[j] + PULL * (centre - q[j]) - p[j]) * (1 + 1e-6);
    }
    return first_hit_region(L, p, d);
}

int64_t vc_region_locator_nearest(const vc_region_locator *L, const double p[3])
{
    double d2;
    return nearest_triangle(L, p, &d2);
}

int64_t vc_region_locate(const vc_region_locator *L, const double p[3])
{
    if (!L->side_region)
        return -2;
    double d2;
    const int64_t t = nearest_triangle(L, p, &d2);
    if (t < 0)
        return -1;
    if (d2 == 0)
        return -2;
    int64_t r = aim_nearest(L, p, t);
    if (r != -2)
        return r;
    r = aim_at(L, p, t);
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
