/* k-d tree over ball centres (see ball_tree.h). */
#include "ball_tree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { LEAF_SIZE = 8, MAX_DEPTH = 64 };

/* A ball's coordinate along the split axis; ties go by index, so the tree
 * (and so the order of every query's arithmetic) is fully determined. */
typedef struct keyed_ball {
    double key;
    int64_t index;
} keyed_ball;

static int cmp_keyed_ball(const void *a, const void *b)
{
    const keyed_ball *u = a, *v = b;
    if (u->key != v->key)
        return u->key < v->key ? -1 : 1;
    return (u->index > v->index) - (u->index < v->index);
}

static void fill_node(vc_ball_tree *t, vc_ball_tree_node *nd)
{
    const vc_balls *b = t->balls;
    for (int d = 0; d < 3; d++) {
        nd->lo[d] = INFINITY;
        nd->hi[d] = -INFINITY;
    }
    nd->rmin = INFINITY;
    nd->rmax = 0;
    for (int64_t k = nd->first; k < nd->first + nd->count; k++) {
        int64_t i = t->order[k];
        for (int d = 0; d < 3; d++) {
            nd->lo[d] = fmin(nd->lo[d], b->center[3 * i + d]);
            nd->hi[d] = fmax(nd->hi[d], b->center[3 * i + d]);
        }
        nd->rmin = fmin(nd->rmin, b->radius[i]);
        nd->rmax = fmax(nd->rmax, b->radius[i]);
    }
    nd->child = -1;
}

int vc_ball_tree_build(vc_ball_tree *t, const vc_balls *balls)
{
    memset(t, 0, sizeof *t);
    t->balls = balls;
    int64_t n = balls->n;
    /* a binary tree with leaves of at least LEAF_SIZE / 2 balls has fewer
     * than 2n / (LEAF_SIZE / 2) + 1 nodes */
    int64_t cap = 2 * (n / (LEAF_SIZE / 2)) + 3;
    t->order = malloc(sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
    t->nodes = malloc(sizeof(vc_ball_tree_node) * (size_t)cap);
    keyed_ball *keyed = malloc(sizeof(keyed_ball) * (size_t)(n > 0 ? n : 1));
    if (!t->order || !t->nodes || !keyed) {
        free(keyed);
        vc_ball_tree_free(t);
        return -1;
    }
    for (int64_t i = 0; i < n; i++)
        t->order[i] = i;
    t->n_nodes = 1;
    t->nodes[0].first = 0;
    t->nodes[0].count = n;
    fill_node(t, &t->nodes[0]);
    /* nodes are split in creation order: a node's children follow it */
    for (int64_t k = 0; k < t->n_nodes; k++) {
        vc_ball_tree_node *nd = &t->nodes[k];
        if (nd->count <= LEAF_SIZE || t->n_nodes + 2 > cap)
            continue;
        int axis = 0;
        for (int d = 1; d < 3; d++)
            if (nd->hi[d] - nd->lo[d] > nd->hi[axis] - nd->lo[axis])
                axis = d;
        for (int64_t j = 0; j < nd->count; j++) {
            int64_t i = t->order[nd->first + j];
            keyed[j].key = balls->center[3 * i + axis];
            keyed[j].index = i;
        }
        qsort(keyed, (size_t)nd->count, sizeof *keyed, cmp_keyed_ball);
        for (int64_t j = 0; j < nd->count; j++)
            t->order[nd->first + j] = keyed[j].index;
        int64_t half = nd->count / 2;
        vc_ball_tree_node *a = &t->nodes[t->n_nodes], *b = a + 1;
        a->first = nd->first;
        a->count = half;
        b->first = nd->first + half;
        b->count = nd->count - half;
        fill_node(t, a);
        fill_node(t, b);
        nd->child = t->n_nodes;
        t->n_nodes += 2;
    }
    free(keyed);
    return 0;
}

void vc_ball_tree_free(vc_ball_tree *t)
{
    free(t->order);
    free(t->nodes);
    memset(t, 0, sizeof *t);
}

static double box_dist(const vc_ball_tree_node *nd, const double x[3])
{
    double s = 0;
    for (int d = 0; d < 3; d++) {
        double e = x[d] < nd->lo[d] ? nd->lo[d] - x[d] : (x[d] > nd->hi[d] ? x[d] - nd->hi[d] : 0);
        s += e * e;
    }
    return sqrt(s);
}

/* r + g_r(d): the sizing a ball of radius r gives at distance d. */
static double graded(const vc_ball_grading *g, double r, double d)
{
    const double near = g->far_from * r;
    return r + (d <= near ? g->lipschitz * d : g->lipschitz * near + g->far_lipschitz * (d - near));
}

/* A lower bound of graded(r_p, |x - p|) over a node's balls, D the box's
 * distance: graded grows with d, and for fixed d it is piecewise linear in
 * r with its one kink at r = d / far_from, so its least value over
 * [rmin, rmax] is at an end or at the kink. Far from the balls this prunes
 * by the far rate, not by L. */
static double node_lower(const vc_ball_grading *g, const vc_ball_tree_node *nd, double D)
{
    double v = fmin(graded(g, nd->rmin, D), graded(g, nd->rmax, D));
    if (g->far_from > 0) {
        const double kink = D / g->far_from;
        if (kink > nd->rmin && kink < nd->rmax)
            v = fmin(v, graded(g, kink, D));
    }
    return v;
}

int vc_ball_tree_exceeds(const vc_ball_tree *t, const double x[3], const vc_ball_grading *g,
                         double cap, double length, double factor)
{
    /* length > factor min(cap, v_p) holds when it holds for cap or for one
     * ball (a product by factor > 0 rounds monotonically), so the search
     * stops at the first such ball, and a subtree goes unread when length
     * is not above factor times its least value */
    if (length > factor * cap)
        return 1;
    if (t->balls->n == 0)
        return 0;
    int64_t stack[2 * MAX_DEPTH + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vc_ball_tree_node *nd = &t->nodes[stack[--top]];
        if (!(length > factor * node_lower(g, nd, box_dist(nd, x))))
            continue;
        if (nd->child < 0) {
            const vc_balls *b = t->balls;
            for (int64_t k = nd->first; k < nd->first + nd->count; k++) {
                int64_t i = t->order[k];
                const double *p = b->center + 3 * i;
                double d = sqrt((x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) +
                                (x[2] - p[2]) * (x[2] - p[2]));
                if (length > factor * graded(g, b->radius[i], d))
                    return 1;
            }
            continue;
        }
        const vc_ball_tree_node *c0 = &t->nodes[nd->child], *c1 = c0 + 1;
        int near_first = box_dist(c0, x) <= box_dist(c1, x);
        stack[top++] = nd->child + near_first;
        stack[top++] = nd->child + !near_first;
    }
    return 0;
}

int vc_ball_tree_covers(const vc_ball_tree *t, const double x[3])
{
    return vc_ball_tree_covers_scaled(t, x, 1.0);
}

int vc_ball_tree_covers_scaled(const vc_ball_tree *t, const double x[3], double factor)
{
    return vc_ball_tree_covers_scaled_except(t, x, factor, -1);
}

/* 1 when |x - p| <= factor r_p + h for some ball other than skip. */
static int some_ball_within(const vc_ball_tree *t, const double x[3], double factor, double h, int64_t skip)
{
    if (t->balls->n == 0)
        return 0;
    int64_t stack[2 * MAX_DEPTH + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vc_ball_tree_node *nd = &t->nodes[stack[--top]];
        if (box_dist(nd, x) > factor * nd->rmax + h)
            continue;
        if (nd->child < 0) {
            const vc_balls *b = t->balls;
            for (int64_t k = nd->first; k < nd->first + nd->count; k++) {
                int64_t i = t->order[k];
                if (i == skip)
                    continue;
                const double *p = b->center + 3 * i;
                double d2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) +
                            (x[2] - p[2]) * (x[2] - p[2]);
                const double r = factor * b->radius[i] + h;
                if (d2 <= r * r)
                    return 1;
            }
            continue;
        }
        stack[top++] = nd->child;
        stack[top++] = nd->child + 1;
    }
    return 0;
}

int vc_ball_tree_covers_scaled_except(const vc_ball_tree *t, const double x[3], double factor,
                                      int64_t skip)
{
    return some_ball_within(t, x, factor, 0.0, skip);
}

int vc_ball_tree_reaches(const vc_ball_tree *t, const double x[3], double h)
{
    return some_ball_within(t, x, 1.0, h, -1);
}
