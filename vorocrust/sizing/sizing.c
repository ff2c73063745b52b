#include "sizing/sizing.h"
#include "util/csr_group.h"
#include "util/closest_point.h"
#include "util/median_tree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LEAF_SIZE 4

static const double *vtx(const vc_sizing *z, int64_t v) { return z->s->xyz + 3 * v; }

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void elem_bounds(const vc_sizing *z, int kind, int64_t id, double lo[3], double hi[3])
{
    int64_t v[3];
    int nv;
    if (kind == VC_ELEM_CORNER) {
        v[0] = id;
        nv = 1;
    } else if (kind == VC_ELEM_EDGE) {
        v[0] = z->f->edge_vertex[2 * id];
        v[1] = z->f->edge_vertex[2 * id + 1];
        nv = 2;
    } else {
        for (int k = 0; k < 3; k++)
            v[k] = z->s->tri[3 * id + k];
        nv = 3;
    }
    for (int d = 0; d < 3; d++)
        lo[d] = hi[d] = vtx(z, v[0])[d];
    for (int k = 1; k < nv; k++)
        for (int d = 0; d < 3; d++) {
            double x = vtx(z, v[k])[d];
            lo[d] = x < lo[d] ? x : lo[d];
            hi[d] = x > hi[d] ? x : hi[d];
        }
}

double vc_sizing_element_dist2(const vc_sizing *z, int kind, int64_t id, const double p[3])
{
    if (kind == VC_ELEM_CORNER) {
        const double *a = vtx(z, id);
        double d[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    }
    if (kind == VC_ELEM_EDGE)
        return vc_closest_on_segment(p, vtx(z, z->f->edge_vertex[2 * id]),
                                     vtx(z, z->f->edge_vertex[2 * id + 1]), NULL);
    const int64_t *t = z->s->tri + 3 * id;
    return vc_closest_on_triangle(p, vtx(z, t[0]), vtx(z, t[1]), vtx(z, t[2]), NULL);
}

/* Top-down build: split the elements at the median of the longest axis of
 * their centres. Elements are (kind, id, centre) records sorted in place. */
typedef struct build_elem {
    double c[3];
    double lo[3], hi[3];
    signed char kind;
    int64_t id;
} build_elem;

/* The elements ordered along one axis (then by kind and id): one
 * comparator per axis, since qsort passes no context and a static axis
 * would race between two sizings built on two threads. */
static int cmp_along(const build_elem *a, const build_elem *b, int axis)
{
    double x = a->c[axis], y = b->c[axis];
    if (x < y)
        return -1;
    if (x > y)
        return 1;
    if (a->kind != b->kind)
        return a->kind < b->kind ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}
static int cmp_x(const void *a, const void *b) { return cmp_along(a, b, 0); }
static int cmp_y(const void *a, const void *b) { return cmp_along(a, b, 1); }
static int cmp_z(const void *a, const void *b) { return cmp_along(a, b, 2); }

static void swap_elem(build_elem *a, build_elem *b)
{
    build_elem t = *a;
    *a = *b;
    *b = t;
}

/* Reorders e[0 .. n) so that its k smallest (cmp_along on axis, a strict
 * total order) come first: what sorting does to the two halves' sets, in
 * linear expected time (sorting every node's range was most of the tree's
 * build: 190k triangles, 0.5 s). Quickselect with a median-of-three pivot;
 * after 64 rounds (adversarial input) it sorts what is left. */
static void select_first(build_elem *e, int64_t n, int64_t k, int axis)
{
    int64_t lo = 0, hi = n - 1;
    for (int round = 0; hi > lo; round++) {
        if (round == 64) {
            qsort(e + lo, (size_t)(hi - lo + 1), sizeof *e, axis == 0 ? cmp_x : axis == 1 ? cmp_y : cmp_z);
            return;
        }
        const int64_t mid = lo + (hi - lo) / 2;
        if (cmp_along(&e[mid], &e[lo], axis) < 0)
            swap_elem(&e[mid], &e[lo]);
        if (cmp_along(&e[hi], &e[lo], axis) < 0)
            swap_elem(&e[hi], &e[lo]);
        if (cmp_along(&e[hi], &e[mid], axis) < 0)
            swap_elem(&e[hi], &e[mid]);
        /* the median of the three to hi; partition e[lo .. hi) about it */
        swap_elem(&e[mid], &e[hi]);
        int64_t store = lo;
        for (int64_t i = lo; i < hi; i++)
            if (cmp_along(&e[i], &e[hi], axis) < 0)
                swap_elem(&e[i], &e[store++]);
        swap_elem(&e[store], &e[hi]);
        if (store == k)
            return;
        if (store < k)
            lo = store + 1;
        else
            hi = store - 1;
    }
}

static inline double min2(double a, double b) { return b < a ? b : a; }
static inline double max2(double a, double b) { return b > a ? b : a; }

/* Node me over e[start .. start + count) and its subtree, numbered in
 * preorder from me; returns the next free node index. The axis is the
 * widest spread of the elements' centres; a node's box is its leaf's
 * elements' or its children's union (no element is read twice for it).
 * Inline min and max: libm's fmin and fmax calls were a third of the
 * build (1.8 million triangles: 2.4 s). */
static int64_t build_node(vc_sizing *z, build_elem *e, int64_t me, int64_t start, int64_t count)
{
    vc_bvh_node *nd = &z->nodes[me];
    if (count <= LEAF_SIZE) {
        for (int d = 0; d < 3; d++) {
            nd->lo[d] = INFINITY;
            nd->hi[d] = -INFINITY;
        }
        for (int64_t i = start; i < start + count; i++)
            for (int d = 0; d < 3; d++) {
                nd->lo[d] = min2(nd->lo[d], e[i].lo[d]);
                nd->hi[d] = max2(nd->hi[d], e[i].hi[d]);
            }
        nd->start = start;
        nd->count = count;
        nd->left = nd->right = -1;
        return me + 1;
    }
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = start; i < start + count; i++)
        for (int d = 0; d < 3; d++) {
            clo[d] = min2(clo[d], e[i].c[d]);
            chi[d] = max2(chi[d], e[i].c[d]);
        }
    int axis = 0;
    for (int d = 1; d < 3; d++)
        if (chi[d] - clo[d] > chi[axis] - clo[axis])
            axis = d;
    int64_t half = count / 2;
    /* A child with more than LEAF_SIZE elements orders its own range
     * again, so only the two sets matter there; a leaf keeps this order. */
    if (half <= LEAF_SIZE || count - half <= LEAF_SIZE)
        qsort(e + start, (size_t)count, sizeof(build_elem),
              axis == 0 ? cmp_x : axis == 1 ? cmp_y : cmp_z);
    else
        select_first(e + start, count, half, axis);
    const int64_t l = me + 1;
    int64_t r, next;
    if (count > VC_MEDIAN_TREE_TASK) {
        /* the halves at once (util/median_tree.h): the same tree */
        r = l + vc_median_tree_nodes(half, LEAF_SIZE);
#pragma omp task default(shared)
        build_node(z, e, l, start, half);
        next = build_node(z, e, r, start + half, count - half);
#pragma omp taskwait
    } else {
        r = build_node(z, e, l, start, half);
        next = build_node(z, e, r, start + half, count - half);
    }
    nd = &z->nodes[me];
    nd->start = start;
    nd->count = 0;
    nd->left = l;
    nd->right = r;
    for (int d = 0; d < 3; d++) {
        nd->lo[d] = min2(z->nodes[l].lo[d], z->nodes[r].lo[d]);
        nd->hi[d] = max2(z->nodes[l].hi[d], z->nodes[r].hi[d]);
    }
    return next;
}

/* The patch and normal cone of every node (see vc_bvh_node), children
 * before parents: a node's index is below its children's (preorder). The
 * cone is widened by a margin well above rounding, so that a subtree it
 * lets vc_sizing_radius_bound skip holds only triangles the per-element
 * test would skip too. */
#define CONE_MARGIN 1e-9

static int node_cones(vc_sizing *z)
{
    const double theta_smooth = acos(fmax(-1.0, fmin(1.0, z->cos_smooth)));
    double *half = malloc(sizeof(double) * (size_t)(z->n_nodes ? z->n_nodes : 1));
    if (!half)
        return -1;
    for (int64_t k = z->n_nodes - 1; k >= 0; k--) {
        vc_bvh_node *nd = &z->nodes[k];
        nd->patch = -1;
        nd->cos_need = 2;
        half[k] = INFINITY;
        double a[3] = {0, 0, 0};
        if (nd->count > 0) {
            int64_t patch = -2;
            for (int64_t i = nd->start; i < nd->start + nd->count && patch != -1; i++) {
                if (z->elem_kind[i] != VC_ELEM_TRIANGLE) {
                    patch = -1;
                    break;
                }
                const int64_t pt = z->f->tri_patch[z->elem_id[i]];
                patch = patch == -2 || patch == pt ? pt : -1;
                for (int d = 0; d < 3; d++)
                    a[d] += z->tri_out_normal[3 * z->elem_id[i] + d];
            }
            if (patch < 0)
                continue;
            const double l = sqrt(dot3(a, a));
            if (!(l > 0))
                continue;
            double h = 0;
            for (int d = 0; d < 3; d++)
                a[d] /= l;
            for (int64_t i = nd->start; i < nd->start + nd->count; i++)
                h = fmax(h, acos(fmax(-1.0, fmin(1.0, dot3(a, z->tri_out_normal + 3 * z->elem_id[i])))));
            nd->patch = patch;
            half[k] = h;
        } else {
            const vc_bvh_node *l = &z->nodes[nd->left], *r = &z->nodes[nd->right];
            if (l->patch < 0 || l->patch != r->patch)
                continue;
            for (int d = 0; d < 3; d++)
                a[d] = l->axis[d] + r->axis[d];
            const double n = sqrt(dot3(a, a));
            if (!(n > 0))
                continue;
            for (int d = 0; d < 3; d++)
                a[d] /= n;
            const double hl = acos(fmax(-1.0, fmin(1.0, dot3(a, l->axis)))) + half[nd->left];
            const double hr = acos(fmax(-1.0, fmin(1.0, dot3(a, r->axis)))) + half[nd->right];
            nd->patch = l->patch;
            half[k] = fmax(hl, hr);
        }
        for (int d = 0; d < 3; d++)
            nd->axis[d] = a[d];
        const double room = theta_smooth - half[k] - CONE_MARGIN;
        if (room > 0)
            nd->cos_need = cos(room) + CONE_MARGIN;
    }
    free(half);
    return 0;
}

static void csr_free(int64_t **a, int64_t **b)
{
    free(*a);
    free(*b);
    *a = *b = NULL;
}

/* The normal that stands for triangle t's plane: for a triangle of a
 * round's band (vc_features.tri_round), the flank it took. */
static const double *plane_normal(const vc_features *f, int64_t t)
{
    return f->tri_round && f->tri_round[t] ? f->tri_smooth_normal + 3 * t : f->tri_normal + 3 * t;
}

/* Is sharp edge e on a round's crease, or beside a round's band? (A
 * round's crease has its band on both sides.) */
static int edge_on_round(const vc_features *f, int64_t e)
{
    for (int64_t k = f->edge_tri_start[e]; k < f->edge_tri_start[e + 1]; k++)
        if (f->tri_round[f->edge_tri[k]])
            return 1;
    return 0;
}

/* A crease along a round narrower than the error bound (a wing's tip cap
 * around its rounded trailing edge) turns with it, by the round's whole
 * turn within a fraction of the bound: its points there are not co-smooth
 * by tangent, and the edge balls would shrink to the round's size, as the
 * surface balls did before the round became a crease. Its edges there take
 * the direction of the flanks' planes instead, the intersection of the
 * planes of their two triangles (flank normals on the round's side): as
 * the crease runs where the round is sharp. Along each run of such edges
 * the sign is the run's: the direction its chords advance along. */
static void round_crease_tangents(vc_sizing *z)
{
    const vc_features *f = z->f;
    for (int64_t c = 0; c < f->n_creases; c++) {
        const int64_t k0 = f->crease_start[c], k1 = f->crease_start[c + 1];
        for (int64_t k = k0; k < k1;) {
            /* a run of edges beside a round's band, whose planes meet */
            int64_t j = k;
            double net = 0, prev[3] = {0, 0, 0};
            for (; j < k1; j++) {
                const int64_t e = f->crease_edge[j];
                if (f->edge_tri_start[e + 1] - f->edge_tri_start[e] != 2)
                    break;
                if (!edge_on_round(f, e))
                    break;
                const int64_t u = f->edge_tri[f->edge_tri_start[e]], v = f->edge_tri[f->edge_tri_start[e] + 1];
                const double *nu = plane_normal(f, u), *nv = plane_normal(f, v);
                double t[3] = {nu[1] * nv[2] - nu[2] * nv[1], nu[2] * nv[0] - nu[0] * nv[2],
                               nu[0] * nv[1] - nu[1] * nv[0]};
                const double l = sqrt(dot3(t, t));
                if (!(l > 0.1))
                    break; /* (nearly) parallel planes: no line of theirs */
                for (int d = 0; d < 3; d++)
                    t[d] /= l;
                /* each edge's sign follows the one before it: a run can
                 * turn through a whole circle (a can's rounded rim) */
                if (j > k && dot3(t, prev) < 0)
                    for (int d = 0; d < 3; d++)
                        t[d] = -t[d];
                memcpy(prev, t, sizeof prev);
                memcpy(z->edge_tangent + 3 * e, t, sizeof t);
                /* the chord, in the crease's direction */
                const double *a = vtx(z, f->crease_vertex[j + c]), *b = vtx(z, f->crease_vertex[j + c + 1]);
                const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                net += dot3(ab, t);
            }
            if (j == k) {
                k++;
                continue;
            }
            /* the run advances against its tangents: turn them */
            if (net < 0)
                for (int64_t i = k; i < j; i++)
                    for (int d = 0; d < 3; d++)
                        z->edge_tangent[3 * f->crease_edge[i] + d] = -z->edge_tangent[3 * f->crease_edge[i] + d];
            k = j;
        }
    }
}

/* The narrowest tangent slab of an edge or corner ball, as a share of eps:
 * a quarter of the radius, where the curvature sets it. */
#define PINNED_SLAB_MIN (1.0 / 16)

/* The half-width of the tangent slabs of a ball centred on sharp edge e.
 * Its centre stays on the crease, so the sag of its facets, chords of the
 * patches beside it, biases the volume inward where the centre lift
 * removes that bias for surface balls. Per unit of crease, a ball of
 * radius R whose slab of half-width w bounds the sag takes about R w off
 * the section, against the R^2 sin(phi) / 2 that the wedge of opening phi
 * holds within R, with R growing as sqrt(w): at w = eps sin^2(phi) the
 * share is that of a right-angled crease. So a knife edge (a blade's
 * trailing edge, 16 degrees: edge balls of 21 error bounds took 0.5% off
 * the blade's volume) takes balls its section can afford; an edge opening
 * by a right angle or more, or concave, or of more than two triangles,
 * keeps eps. */
static double crease_slab(const vc_sizing *z, int64_t e)
{
    const vc_features *f = z->f;
    const int64_t k0 = f->edge_tri_start[e];
    if (!isfinite(z->eps) || f->edge_tri_start[e + 1] - k0 != 2)
        return z->eps;
    const int64_t t1 = f->edge_tri[k0], t2 = f->edge_tri[k0 + 1];
    const double *n1 = z->tri_out_normal + 3 * t1, *n2 = z->tri_out_normal + 3 * t2;
    const double c = dot3(n1, n2);
    if (!(c < 0))
        return z->eps; /* the normals turn by 90 degrees at most: opens by 90 or more */
    /* convex when t2's vertex off the edge lies below t1's plane */
    const int64_t a = f->edge_vertex[2 * e], b = f->edge_vertex[2 * e + 1];
    int64_t off = -1;
    for (int k = 0; k < 3; k++) {
        const int64_t v = z->s->tri[3 * t2 + k];
        if (v != a && v != b)
            off = v;
    }
    if (off < 0)
        return z->eps;
    const double *pa = vtx(z, a), *po = vtx(z, off);
    const double h = n1[0] * (po[0] - pa[0]) + n1[1] * (po[1] - pa[1]) + n1[2] * (po[2] - pa[2]);
    if (!(h < 0))
        return z->eps;
    /* opening phi = pi - fold: sin^2(phi) = sin^2(fold) = 1 - c^2 */
    return z->eps * fmax(PINNED_SLAB_MIN, 1 - c * c);
}

/* The slab half-width of a ball at sp: an edge's, the narrowest of a
 * corner's sharp edges, eps for a surface point. */
static double pinned_slab(const vc_sizing *z, const vc_surface_point *sp)
{
    if (sp->kind == VC_ELEM_EDGE)
        return z->edge_slab[sp->id];
    if (sp->kind != VC_ELEM_CORNER)
        return z->eps;
    double w = z->eps;
    for (int64_t k = z->vedge_start[sp->id]; k < z->vedge_start[sp->id + 1]; k++)
        w = fmin(w, z->edge_slab[z->vedge[k]]);
    return w;
}

int vc_sizing_init(vc_sizing *z, const vc_surface *s, const vc_features *f,
                   double sharp_angle_deg, double max_error)
{
    memset(z, 0, sizeof *z);
    z->s = s;
    z->f = f;
    z->cos_sharp = cos(sharp_angle_deg * 3.14159265358979323846 / 180.0);
    z->cos_smooth = z->cos_sharp;
    int64_t nv = s->n_vertices, nt = s->n_triangles, ne = f->n_edges;

    /* Orientation: the signed volume of the patch-oriented triangles. */
    double vol = 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t v = 0; v < nv; v++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * v + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * v + d]);
        }
    z->diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
    z->eps = max_error > 0 ? max_error * z->diag : INFINITY;
    for (int64_t t = 0; t < nt; t++) {
        int64_t w[3];
        vc_features_oriented_triangle(f, s, t, w);
        const double *a = vtx(z, w[0]), *b = vtx(z, w[1]), *c = vtx(z, w[2]);
        double ax = a[0] - lo[0], ay = a[1] - lo[1], az = a[2] - lo[2];
        double bx = b[0] - lo[0], by = b[1] - lo[1], bz = b[2] - lo[2];
        double cx = c[0] - lo[0], cy = c[1] - lo[1], cz = c[2] - lo[2];
        vol += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    }
    z->orientation = vol < 0 ? -1.0 : 1.0;

    z->tri_out_normal = malloc(sizeof(double) * 3 * (size_t)(nt ? nt : 1));
    z->edge_tangent = calloc(3 * (size_t)(ne ? ne : 1), sizeof(double));
    /* vertex -> triangles, vertex -> sharp edges */
    if (!z->tri_out_normal || !z->edge_tangent ||
        vc_csr_group(s->tri, nt, 3, nv, NULL, &z->vtri_start, &z->vtri) ||
        vc_csr_group(f->edge_vertex, ne, 2, nv, f->edge_sharp, &z->vedge_start, &z->vedge)) {
        vc_sizing_free(z);
        return -1;
    }
    for (int64_t t = 0; t < nt; t++)
        for (int d = 0; d < 3; d++)
            z->tri_out_normal[3 * t + d] = z->orientation * f->tri_normal[3 * t + d];
    for (int64_t e = 0; e < ne; e++) {
        if (!f->edge_sharp[e])
            continue;
        const double *a = vtx(z, f->edge_vertex[2 * e]), *b = vtx(z, f->edge_vertex[2 * e + 1]);
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double sg = f->edge_crease_dir[e] < 0 ? -1.0 : 1.0;
        if (l > 0)
            for (int k = 0; k < 3; k++)
                z->edge_tangent[3 * e + k] = sg * d[k] / l;
    }
    if (f->tri_round)
        round_crease_tangents(z);
    z->edge_slab = malloc(sizeof(double) * (size_t)(ne ? ne : 1));
    if (!z->edge_slab) {
        vc_sizing_free(z);
        return -1;
    }
    for (int64_t e = 0; e < ne; e++)
        z->edge_slab[e] = f->edge_sharp[e] ? crease_slab(z, e) : z->eps;
    /* The elements and their tree. */
    int64_t n = nt + f->n_sharp_edges + f->n_corners;
    build_elem *be = malloc(sizeof(build_elem) * (size_t)(n ? n : 1));
    z->elem_kind = malloc((size_t)(n ? n : 1));
    z->elem_id = malloc(sizeof(int64_t) * (size_t)(n ? n : 1));
    z->nodes = malloc(sizeof(vc_bvh_node) * (size_t)(2 * n + 1));
    if (!be || !z->elem_kind || !z->elem_id || !z->nodes) {
        free(be);
        vc_sizing_free(z);
        return -1;
    }
    int64_t m = 0;
    for (int64_t v = 0; v < nv; v++)
        if (f->vertex_corner[v])
            be[m].kind = VC_ELEM_CORNER, be[m++].id = v;
    for (int64_t e = 0; e < ne; e++)
        if (f->edge_sharp[e])
            be[m].kind = VC_ELEM_EDGE, be[m++].id = e;
    for (int64_t t = 0; t < nt; t++)
        be[m].kind = VC_ELEM_TRIANGLE, be[m++].id = t;
    for (int64_t i = 0; i < m; i++) {
        elem_bounds(z, be[i].kind, be[i].id, be[i].lo, be[i].hi);
        for (int d = 0; d < 3; d++)
            be[i].c[d] = 0.5 * (be[i].lo[d] + be[i].hi[d]);
    }
    z->n_elems = m;
    if (m > 0) {
        int64_t n_nodes = 0;
#pragma omp parallel if (m > VC_MEDIAN_TREE_TASK)
#pragma omp single
        n_nodes = build_node(z, be, 0, 0, m);
        z->n_nodes = n_nodes;
    }
    for (int64_t i = 0; i < m; i++) {
        z->elem_kind[i] = be[i].kind;
        z->elem_id[i] = be[i].id;
    }
    free(be);
    if (node_cones(z)) {
        vc_sizing_free(z);
        return -1;
    }
    return 0;
}

void vc_sizing_free(vc_sizing *z)
{
    free(z->tri_out_normal);
    free(z->edge_tangent);
    free(z->edge_slab);
    csr_free(&z->vtri_start, &z->vtri);
    csr_free(&z->vedge_start, &z->vedge);
    free(z->elem_kind);
    free(z->elem_id);
    free(z->nodes);
    memset(z, 0, sizeof *z);
}

/* Is triangle t co-smooth with an edge or corner point whose adjacent
 * triangles are given? */
/* Triangles u and t of one patch are co-smooth when their normals agree
 * within theta_sharp, or their normals smoothed at the error bound do
 * (noise judged by the features: vc_features.tri_smooth_normal). */
static int normals_agree(const vc_sizing *z, int64_t u, int64_t t)
{
    if (dot3(z->tri_out_normal + 3 * u, z->tri_out_normal + 3 * t) >= z->cos_smooth)
        return 1;
    const double *m = z->f->tri_smooth_normal;
    return m && dot3(m + 3 * u, m + 3 * t) >= z->cos_smooth;
}

static int tri_cosmooth_with_list(const vc_sizing *z, const int64_t *tris, int64_t n, int64_t t)
{
    int64_t pt = z->f->tri_patch[t];
    for (int64_t i = 0; i < n; i++) {
        int64_t u = tris[i];
        if (z->f->tri_patch[u] == pt && normals_agree(z, u, t))
            return 1;
    }
    return 0;
}

/* For an edge or corner point: the normal of its own triangle (around the
 * edge or corner) in triangle t's patch that is nearest t's, the tangent
 * plane of that patch there (for a triangle of a round's band, the flank
 * it took: vc_features.tri_round), in buf; NULL when none is in t's patch. */
static const double *patch_normal_at(const vc_sizing *z, const vc_surface_point *sp, int64_t t,
                                     double buf[3])
{
    const int64_t *tris;
    int64_t n;
    if (sp->kind == VC_ELEM_EDGE) {
        tris = z->f->edge_tri + z->f->edge_tri_start[sp->id];
        n = z->f->edge_tri_start[sp->id + 1] - z->f->edge_tri_start[sp->id];
    } else if (sp->kind == VC_ELEM_CORNER) {
        tris = z->vtri + z->vtri_start[sp->id];
        n = z->vtri_start[sp->id + 1] - z->vtri_start[sp->id];
    } else {
        return NULL;
    }
    const double *nt = z->tri_out_normal + 3 * t, *best = NULL;
    double best_dot = -2;
    for (int64_t i = 0; i < n; i++) {
        int64_t u = tris[i];
        double d = dot3(z->tri_out_normal + 3 * u, nt);
        if (z->f->tri_patch[u] == z->f->tri_patch[t] && d > best_dot) {
            best_dot = d;
            best = z->tri_out_normal + 3 * u;
            if (z->f->tri_round && z->f->tri_round[u]) {
                for (int k = 0; k < 3; k++)
                    buf[k] = z->orientation * z->f->tri_smooth_normal[3 * u + k];
                best = buf;
            }
        }
    }
    return best;
}

int vc_sizing_cosmooth(const vc_sizing *z, const vc_surface_point *sp, int kind, int64_t id)
{
    const vc_features *f = z->f;
    if (kind == VC_ELEM_CORNER)
        return sp->kind == VC_ELEM_CORNER && sp->id == id;
    if (kind == VC_ELEM_EDGE) {
        if (sp->kind == VC_ELEM_TRIANGLE)
            return 0;
        const double *te = z->edge_tangent + 3 * id;
        if (sp->kind == VC_ELEM_EDGE)
            return f->edge_crease[sp->id] == f->edge_crease[id] &&
                   dot3(z->edge_tangent + 3 * sp->id, te) >= z->cos_sharp;
        for (int64_t k = z->vedge_start[sp->id]; k < z->vedge_start[sp->id + 1]; k++) {
            int64_t e = z->vedge[k];
            if (f->edge_crease[e] == f->edge_crease[id] &&
                dot3(z->edge_tangent + 3 * e, te) >= z->cos_sharp)
                return 1;
        }
        return 0;
    }
    /* a triangle */
    if (sp->kind == VC_ELEM_TRIANGLE)
        return f->tri_patch[sp->id] == f->tri_patch[id] && normals_agree(z, sp->id, id);
    if (sp->kind == VC_ELEM_EDGE)
        return tri_cosmooth_with_list(z, f->edge_tri + f->edge_tri_start[sp->id],
                                      f->edge_tri_start[sp->id + 1] - f->edge_tri_start[sp->id],
                                      id);
    return tri_cosmooth_with_list(z, z->vtri + z->vtri_start[sp->id],
                                  z->vtri_start[sp->id + 1] - z->vtri_start[sp->id], id);
}

/* Is the box of nd within distance h of the plane through p with unit
 * normal n? */
static int box_in_slab(const vc_bvh_node *nd, const double p[3], const double n[3], double h)
{
    double c = 0, e = 0;
    for (int d = 0; d < 3; d++) {
        c += n[d] * (0.5 * (nd->lo[d] + nd->hi[d]) - p[d]);
        e += fabs(n[d]) * 0.5 * (nd->hi[d] - nd->lo[d]);
    }
    return fabs(c) + e <= h;
}

static double box_dist2(const vc_bvh_node *nd, const double p[3])
{
    double d2 = 0;
    for (int d = 0; d < 3; d++) {
        double e = p[d] < nd->lo[d] ? nd->lo[d] - p[d] : (p[d] > nd->hi[d] ? p[d] - nd->hi[d] : 0);
        d2 += e * e;
    }
    return d2;
}

double vc_sizing_conflict_distance(const vc_sizing *z, const vc_surface_point *sp,
                                   const double p[3], double bound)
{
    if (z->n_elems == 0)
        return bound;
    double best2 = bound * bound;
    int64_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vc_bvh_node *nd = &z->nodes[stack[--top]];
        if (box_dist2(nd, p) >= best2)
            continue;
        if (nd->count > 0) {
            for (int64_t i = nd->start; i < nd->start + nd->count; i++) {
                int kind = z->elem_kind[i];
                int64_t id = z->elem_id[i];
                double d2 = vc_sizing_element_dist2(z, kind, id, p);
                if (d2 < best2 && !vc_sizing_cosmooth(z, sp, kind, id))
                    best2 = d2;
            }
            continue;
        }
        /* nearer child last, so it is popped first */
        double dl = box_dist2(&z->nodes[nd->left], p), dr = box_dist2(&z->nodes[nd->right], p);
        if (top + 2 > 128)
            continue; /* cannot happen: the tree depth is about log2(n) */
        if (dl < dr) {
            stack[top++] = nd->right;
            stack[top++] = nd->left;
        } else {
            stack[top++] = nd->left;
            stack[top++] = nd->right;
        }
    }
    return sqrt(best2);
}

void vc_sizing_elements_near(const vc_sizing *z, const double p[3], double r,
                             void (*fn)(void *ctx, int kind, int64_t id), void *ctx)
{
    vc_sizing_elements_near_within(z, p, r, fn, ctx, NULL);
}

void vc_sizing_elements_near_within(const vc_sizing *z, const double p[3], double r,
                                    void (*fn)(void *ctx, int kind, int64_t id), void *ctx,
                                    const double *within2)
{
    if (z->n_elems == 0)
        return;
    double r2 = r * r;
    int64_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vc_bvh_node *nd = &z->nodes[stack[--top]];
        const double b2 = box_dist2(nd, p);
        if (b2 > r2 || (within2 && b2 > *within2))
            continue;
        if (nd->count > 0) {
            for (int64_t i = nd->start; i < nd->start + nd->count; i++)
                fn(ctx, z->elem_kind[i], z->elem_id[i]);
            continue;
        }
        if (top + 2 <= 128) {
            stack[top++] = nd->left;
            stack[top++] = nd->right;
        }
    }
}

int vc_sizing_triangle_within(const vc_sizing *z, const double p[3], double r)
{
    int64_t hint = -1;
    return vc_sizing_triangle_within_hint(z, p, r, &hint);
}

int vc_sizing_triangle_within_hint(const vc_sizing *z, const double p[3], double r, int64_t *hint)
{
    if (z->n_elems == 0)
        return 0;
    const double r2 = r * r;
    if (*hint >= 0 && *hint < z->s->n_triangles &&
        vc_sizing_element_dist2(z, VC_ELEM_TRIANGLE, *hint, p) < r2)
        return 1;
    int64_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vc_bvh_node *nd = &z->nodes[stack[--top]];
        if (box_dist2(nd, p) >= r2)
            continue;
        if (nd->count > 0) {
            for (int64_t i = nd->start; i < nd->start + nd->count; i++)
                if (z->elem_kind[i] == VC_ELEM_TRIANGLE &&
                    vc_sizing_element_dist2(z, VC_ELEM_TRIANGLE, z->elem_id[i], p) < r2) {
                    *hint = z->elem_id[i];
                    return 1;
                }
            continue;
        }
        if (top + 2 > 128)
            continue;
        /* nearer child last, so it is popped first */
        if (box_dist2(&z->nodes[nd->left], p) < box_dist2(&z->nodes[nd->right], p)) {
            stack[top++] = nd->right;
            stack[top++] = nd->left;
        } else {
            stack[top++] = nd->left;
            stack[top++] = nd->right;
        }
    }
    return 0;
}

void vc_sizing_point_normal(const vc_sizing *z, const vc_surface_point *sp, double n[3])
{
    const int64_t *tris;
    int64_t cnt;
    if (sp->kind == VC_ELEM_TRIANGLE) {
        tris = &sp->id;
        cnt = 1;
    } else if (sp->kind == VC_ELEM_EDGE) {
        tris = z->f->edge_tri + z->f->edge_tri_start[sp->id];
        cnt = z->f->edge_tri_start[sp->id + 1] - z->f->edge_tri_start[sp->id];
    } else {
        tris = z->vtri + z->vtri_start[sp->id];
        cnt = z->vtri_start[sp->id + 1] - z->vtri_start[sp->id];
    }
    n[0] = n[1] = n[2] = 0;
    for (int64_t i = 0; i < cnt; i++)
        for (int d = 0; d < 3; d++)
            n[d] += z->tri_out_normal[3 * tris[i] + d];
    double l = sqrt(dot3(n, n));
    if (l > 0)
        for (int d = 0; d < 3; d++)
            n[d] /= l;
}

/* ---------------------------------------------------------------------
 * Radius bound with the approximation-error criterion. */

/* Distance from p to the part of triangle t where side * (n . (x - p)) > eps
 * (INFINITY when that part is empty). */
static double dist_outside_slab(const vc_sizing *z, int64_t t, const double p[3], const double n[3],
                                double side, double eps)
{
    double v[3][3], sv[3];
    int any = 0;
    for (int k = 0; k < 3; k++) {
        const double *x = vtx(z, z->s->tri[3 * t + k]);
        for (int d = 0; d < 3; d++)
            v[k][d] = x[d];
        sv[k] = side * (n[0] * (x[0] - p[0]) + n[1] * (x[1] - p[1]) + n[2] * (x[2] - p[2])) - eps;
        any |= sv[k] > 0;
    }
    if (!any)
        return INFINITY;
    /* clip the triangle to sv >= 0: at most 4 vertices */
    double poly[4][3];
    int m = 0;
    for (int k = 0; k < 3; k++) {
        int k2 = (k + 1) % 3;
        if (sv[k] >= 0) {
            for (int d = 0; d < 3; d++)
                poly[m][d] = v[k][d];
            m++;
        }
        if ((sv[k] >= 0) != (sv[k2] >= 0)) {
            double a = sv[k] / (sv[k] - sv[k2]);
            for (int d = 0; d < 3; d++)
                poly[m][d] = v[k][d] + a * (v[k2][d] - v[k][d]);
            m++;
        }
    }
    double best = INFINITY;
    if (m == 1)
        return sqrt((poly[0][0] - p[0]) * (poly[0][0] - p[0]) + (poly[0][1] - p[1]) * (poly[0][1] - p[1]) +
                    (poly[0][2] - p[2]) * (poly[0][2] - p[2]));
    if (m == 2)
        return sqrt(vc_closest_on_segment(p, poly[0], poly[1], NULL));
    for (int k = 1; k + 1 < m; k++)
        best = fmin(best, vc_closest_on_triangle(p, poly[0], poly[k], poly[k + 1], NULL));
    return sqrt(best);
}

/* Is triangle t within eps of the plane through p with normal n, on both
 * sides (exactly the test that makes dist_outside_slab return INFINITY)? */
static int tri_in_slab(const vc_sizing *z, int64_t t, const double p[3], const double n[3])
{
    for (int k = 0; k < 3; k++) {
        const double *x = vtx(z, z->s->tri[3 * t + k]);
        double h = n[0] * (x[0] - p[0]) + n[1] * (x[1] - p[1]) + n[2] * (x[2] - p[2]);
        if (h - z->eps > 0 || -h - z->eps > 0)
            return 0;
    }
    return 1;
}

/* Distance from p to the part of sharp edge e farther than eps from the
 * line through p with direction tp (INFINITY when empty). */
static double dist_outside_cylinder(const vc_sizing *z, int64_t e, const double p[3],
                                    const double tp[3])
{
    const double *a = vtx(z, z->f->edge_vertex[2 * e]), *b = vtx(z, z->f->edge_vertex[2 * e + 1]);
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]};
    double wt = dot3(w, tp), ut = dot3(u, tp);
    double w2[3], u2[3];
    for (int d = 0; d < 3; d++) {
        w2[d] = w[d] - wt * tp[d];
        u2[d] = u[d] - ut * tp[d];
    }
    double A = dot3(u2, u2), B = 2 * dot3(w2, u2), C = dot3(w2, w2) - z->eps * z->eps;
    double ivl[2][2];
    int ni = 0;
    if (A <= 1e-30 * (dot3(u, u) + 1e-300)) {
        if (C <= 0)
            return INFINITY;
        ivl[ni][0] = 0, ivl[ni][1] = 1, ni++;
    } else {
        double disc = B * B - 4 * A * C;
        if (disc < 0) {
            ivl[ni][0] = 0, ivl[ni][1] = 1, ni++;
        } else {
            double sq = sqrt(disc);
            double t1 = (-B - sq) / (2 * A), t2 = (-B + sq) / (2 * A);
            if (t1 > 0)
                ivl[ni][0] = 0, ivl[ni][1] = fmin(t1, 1), ni++;
            if (t2 < 1)
                ivl[ni][0] = fmax(t2, 0), ivl[ni][1] = 1, ni++;
        }
    }
    double uu = dot3(u, u), best = INFINITY;
    double tstar = uu > 0 ? -dot3(w, u) / uu : 0;
    for (int k = 0; k < ni; k++) {
        if (ivl[k][0] > ivl[k][1])
            continue;
        double t = fmin(fmax(tstar, ivl[k][0]), ivl[k][1]);
        double x[3] = {w[0] + t * u[0], w[1] + t * u[1], w[2] + t * u[2]};
        best = fmin(best, sqrt(dot3(x, x)));
    }
    return best;
}

/* Lowers *best by element i of the tree order (see vc_sizing_radius_bound);
 * np / tp: p's outward normal when it lies on a triangle, its crease's
 * tangent when on a sharp edge, else NULL. */
static void bound_by_element(const vc_sizing *z, const vc_surface_point *sp, const double p[3],
                             const double *np, const double *tp, int64_t i, double *best)
{
    int kind = z->elem_kind[i];
    int64_t id = z->elem_id[i];
    /* a triangle co-smooth with p and within eps of its tangent plane
     * cannot lower the bound: the common case on a fine, smooth surface,
     * where a large ball reaches thousands; skip its distance */
    if (np && kind == VC_ELEM_TRIANGLE && isfinite(z->eps) && tri_in_slab(z, id, p, np) &&
        vc_sizing_cosmooth(z, sp, kind, id))
        return;
    double d = sqrt(vc_sizing_element_dist2(z, kind, id, p));
    if (0.49 * d >= *best)
        return;
    if (!vc_sizing_cosmooth(z, sp, kind, id)) {
        *best = 0.49 * d;
        return;
    }
    if (d >= *best || !isfinite(z->eps))
        return;
    if (np && kind == VC_ELEM_TRIANGLE)
        *best = fmin(*best, fmin(dist_outside_slab(z, id, p, np, 1.0, z->eps),
                                 dist_outside_slab(z, id, p, np, -1.0, z->eps)));
    else if (tp && kind == VC_ELEM_EDGE)
        *best = fmin(*best, dist_outside_cylinder(z, id, p, tp));
    else if (kind == VC_ELEM_TRIANGLE) {
        /* an edge or corner ball: each patch it meets against that
         * patch's tangent plane there (without this, a corner ball on a
         * curved patch reached 0.6% of the diagonal away from it:
         * fandisk.off) */
        double buf[3];
        const double *nq = patch_normal_at(z, sp, id, buf);
        if (nq) {
            const double w = pinned_slab(z, sp);
            *best = fmin(*best, fmin(dist_outside_slab(z, id, p, nq, 1.0, w),
                                     dist_outside_slab(z, id, p, nq, -1.0, w)));
        }
    }
}

/* Edge and corner balls on a round's crease reach at most this many error
 * bounds: the flanks' width judged flat (2 W) times two. */
#define ROUND_CAP 2.0

/* The radius cap of an edge or corner ball on a round's crease (or on a
 * crease beside its band), INFINITY for any other point. The crease runs
 * through the round's middle and the reconstruction is sharp there: a
 * ball of radius R along it cuts about the round's radius times R off
 * the section, and chords the flanks beyond what was judged flat (a wing's
 * rounded trailing edge under balls of 0.35: -1.4% of its volume; a lens
 * 0.02 thick, its rim rounded: -0.32% at 4 bounds, -0.12% at 2, -0.06%
 * at 1, with 8% more balls at 2 than at 4 and 17% at 1; a filleted block
 * 11,741, 18,760 and 34,111 balls). */
static double round_cap(const vc_sizing *z, const vc_surface_point *sp)
{
    const vc_features *f = z->f;
    if (!f->tri_round || !isfinite(z->eps))
        return INFINITY;
    if (sp->kind == VC_ELEM_EDGE)
        return edge_on_round(f, sp->id) ? ROUND_CAP * z->eps : INFINITY;
    if (sp->kind == VC_ELEM_CORNER)
        for (int64_t k = z->vedge_start[sp->id]; k < z->vedge_start[sp->id + 1]; k++)
            if (edge_on_round(f, z->vedge[k]))
                return ROUND_CAP * z->eps;
    return INFINITY;
}

double vc_sizing_radius_bound(const vc_sizing *z, const vc_surface_point *sp, const double p[3],
                              double bound)
{
    if (z->n_elems == 0)
        return bound;
    double best = fmin(bound, round_cap(z, sp));
    const double *np = sp->kind == VC_ELEM_TRIANGLE ? z->tri_out_normal + 3 * sp->id : NULL;
    const double *tp = sp->kind == VC_ELEM_EDGE ? z->edge_tangent + 3 * sp->id : NULL;
    const int64_t patch = np ? z->f->tri_patch[sp->id] : -1;
    int64_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vc_bvh_node *nd = &z->nodes[stack[--top]];
        double bd = sqrt(box_dist2(nd, p));
        if (0.49 * bd >= best)
            continue;
        /* A subtree of triangles of p's patch, co-smooth with p by their
         * normal cone: each of them can only lower the bound to its
         * distance outside the slab of half-width eps about p's tangent
         * plane, which is at least the box's distance (not 0.49 of it), and
         * not at all when the box lies inside the slab. So the subtree is
         * skipped when every one of its triangles would be (with margins
         * over rounding, so that the bound is the same to the bit). On a
         * fine, smooth surface this is most of what a large ball reaches:
         * three quarters of it lie between best and best / 0.49. */
        if (np && nd->patch == patch && dot3(np, nd->axis) >= nd->cos_need &&
            (!isfinite(z->eps) || bd * (1 - CONE_MARGIN) >= best ||
             box_in_slab(nd, p, np, z->eps * (1 - CONE_MARGIN))))
            continue;
        if (nd->count > 0) {
            for (int64_t i = nd->start; i < nd->start + nd->count; i++)
                bound_by_element(z, sp, p, np, tp, i, &best);
            continue;
        }
        double dl = box_dist2(&z->nodes[nd->left], p), dr = box_dist2(&z->nodes[nd->right], p);
        if (top + 2 > 128)
            continue;
        if (dl < dr) {
            stack[top++] = nd->right;
            stack[top++] = nd->left;
        } else {
            stack[top++] = nd->left;
            stack[top++] = nd->right;
        }
    }
    return best;
}

double vc_sizing_radius_bound_all(const vc_sizing *z, const vc_surface_point *sp,
                                  const double p[3], double bound)
{
    double best = fmin(bound, round_cap(z, sp));
    const double *np = sp->kind == VC_ELEM_TRIANGLE ? z->tri_out_normal + 3 * sp->id : NULL;
    const double *tp = sp->kind == VC_ELEM_EDGE ? z->edge_tangent + 3 * sp->id : NULL;
    for (int64_t i = 0; i < z->n_elems; i++)
        bound_by_element(z, sp, p, np, tp, i, &best);
    return best;
}
