/* Sharp features of a triangle surface: edge index, sharp edges, sharp
 * corners, creases and surface patches (thesis 6.2.2). See
 * include/vorocrust/features.h for the definitions.
 *
 * Order of the work, each step linear in the surface size:
 *  1. edge index: half-edges bucketed by their smaller vertex (counting
 *     sort), each bucket sorted by the other vertex;
 *  2. triangle normals and sharp edges (the angle test compares normals
 *     made consistent across the edge, so an inconsistently oriented input
 *     gives the same answer);
 *  3. sectors: union-find (with relative orientation) over triangle
 *     corners joined through non-sharp edges; then the corner tests per
 *     vertex;
 *  4. creases: walks along sharp edges from each corner, then around the
 *     remaining cycles;
 *  5. patches: breadth-first flood across non-sharp edges, orienting each
 *     new triangle against the one it was reached from. */
#include "vorocrust/features.h"
#include "feature_scale.h"
#include "util/csr_group.h"
#include "util/small_sort.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void vc_features_free(vc_features *f)
{
    if (!f)
        return;
    free(f->edge_vertex);
    free(f->edge_tri_start);
    free(f->edge_tri);
    free(f->tri_edge);
    free(f->vertex_edge_start);
    free(f->edge_sharp);
    free(f->edge_crease);
    free(f->edge_crease_dir);
    free(f->vertex_corner);
    free(f->vertex_sharp_degree);
    free(f->tri_patch);
    free(f->tri_orient);
    free(f->tri_normal);
    free(f->tri_smooth_normal);
    free(f->tri_round);
    free(f->crease_start);
    free(f->crease_edge);
    free(f->crease_vertex);
    free(f->crease_closed);
    free(f->patch_start);
    free(f->patch_tri);
    free(f->patch_orientable);
    memset(f, 0, sizeof *f);
}

/* malloc of n elements of size sz, never of 0 bytes. */
static void *xalloc(int64_t n, size_t sz)
{
    return malloc((size_t)(n > 0 ? n : 1) * sz);
}

static void *xcalloc(int64_t n, size_t sz)
{
    return calloc((size_t)(n > 0 ? n : 1), sz);
}

/* ---- 1. Edge index ---- */

/* A half-edge in the bucket of its smaller vertex: the other vertex and
 * the triangle side h = 3t + j. */
typedef struct half {
    int64_t b, h;
} half;

static int half_less(const half *x, const half *y)
{
    return x->b < y->b || (x->b == y->b && x->h < y->h);
}

/* distinct records (h is unique): the same order for any sort */
VC_SMALL_SORT(sort_halves, half, half_less)

static int build_edges(const vc_surface *s, vc_features *f, vc_error *err)
{
    int64_t nv = s->n_vertices, nt = s->n_triangles, nh = 3 * nt;
    int64_t *start = xcalloc(nv + 1, sizeof *start);
    half *hs = xalloc(nh, sizeof *hs);
    f->tri_edge = xalloc(nh, sizeof *f->tri_edge);
    f->vertex_edge_start = xalloc(nv + 1, sizeof *f->vertex_edge_start);
    if (!start || !hs || !f->tri_edge || !f->vertex_edge_start) {
        free(start);
        free(hs);
        return vc_error_set(err, VC_ENOMEM, "out of memory indexing %lld triangles", (long long)nt);
    }
    for (int64_t h = 0; h < nh; h++) {
        int64_t a = s->tri[h], b = s->tri[h - h % 3 + (h % 3 + 1) % 3];
        start[(a < b ? a : b) + 1]++;
    }
    for (int64_t v = 0; v < nv; v++)
        start[v + 1] += start[v];
    /* Fill (start[v] runs ahead as the fill position; restored below). */
    for (int64_t h = 0; h < nh; h++) {
        int64_t a = s->tri[h], b = s->tri[h - h % 3 + (h % 3 + 1) % 3];
        int64_t lo = a < b ? a : b, hi = a < b ? b : a;
        hs[start[lo]++] = (half){hi, h};
    }
    for (int64_t v = nv; v > 0; v--)
        start[v] = start[v - 1];
    start[0] = 0;

    /* Count the edges, then fill. */
    int64_t ne = 0;
    for (int64_t v = 0; v < nv; v++) {
        sort_halves(hs + start[v], start[v + 1] - start[v]);
        for (int64_t k = start[v]; k < start[v + 1]; k++)
            ne += k == start[v] || hs[k].b != hs[k - 1].b;
    }
    f->n_edges = ne;
    f->edge_vertex = xalloc(2 * ne, sizeof *f->edge_vertex);
    f->edge_tri_start = xalloc(ne + 1, sizeof *f->edge_tri_start);
    f->edge_tri = xalloc(nh, sizeof *f->edge_tri);
    if (!f->edge_vertex || !f->edge_tri_start || !f->edge_tri) {
        free(start);
        free(hs);
        return vc_error_set(err, VC_ENOMEM, "out of memory indexing %lld edges", (long long)ne);
    }
    int64_t e = -1;
    for (int64_t v = 0; v < nv; v++) {
        f->vertex_edge_start[v] = e + 1;
        for (int64_t k = start[v]; k < start[v + 1]; k++) {
            if (k == start[v] || hs[k].b != hs[k - 1].b) {
                e++;
                f->edge_vertex[2 * e] = v;
                f->edge_vertex[2 * e + 1] = hs[k].b;
                f->edge_tri_start[e] = k;
            }
            f->edge_tri[k] = hs[k].h / 3;
            f->tri_edge[hs[k].h] = e;
        }
    }
    f->vertex_edge_start[nv] = ne;
    f->edge_tri_start[ne] = nh;
    free(start);
    free(hs);
    return 0;
}

double vc_features_fold_cos(const vc_features *f, int64_t e)
{
    if (f->edge_sharp[e] || f->edge_tri_start[e + 1] - f->edge_tri_start[e] != 2)
        return 1;
    const double *n1 = f->tri_normal + 3 * f->edge_tri[f->edge_tri_start[e]];
    const double *n2 = f->tri_normal + 3 * f->edge_tri[f->edge_tri_start[e] + 1];
    return n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
}

int64_t vc_features_find_edge(const vc_features *f, int64_t a, int64_t b)
{
    if (a > b) {
        int64_t t = a;
        a = b;
        b = t;
    }
    if (a < 0 || b >= f->n_vertices || a == b)
        return -1;
    int64_t lo = f->vertex_edge_start[a], hi = f->vertex_edge_start[a + 1];
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        int64_t m = f->edge_vertex[2 * mid + 1];
        if (m == b)
            return mid;
        if (m < b)
            lo = mid + 1;
        else
            hi = mid;
    }
    return -1;
}

/* ---- 2. Normals and sharp edges ---- */

/* Side of triangle t that is edge e (0..2). */
static int side_of(const vc_features *f, int64_t t, int64_t e)
{
    return f->tri_edge[3 * t] == e ? 0 : f->tri_edge[3 * t + 1] == e ? 1 : 2;
}

/* +1 when triangle t walks edge e from edge_vertex[2e] to
 * edge_vertex[2e+1] in its input order, -1 otherwise. */
static int walk_dir(const vc_features *f, const vc_surface *s, int64_t t, int64_t e)
{
    int j = side_of(f, t, e);
    return s->tri[3 * t + j] == f->edge_vertex[2 * e] ? 1 : -1;
}

static void compute_normals(const vc_surface *s, vc_features *f)
{
    int64_t degenerate = 0;
    for (int64_t t = 0; t < s->n_triangles; t++) {
        const double *p0 = s->xyz + 3 * s->tri[3 * t];
        const double *p1 = s->xyz + 3 * s->tri[3 * t + 1];
        const double *p2 = s->xyz + 3 * s->tri[3 * t + 2];
        double u[3], v[3], w[3];
        for (int k = 0; k < 3; k++) {
            u[k] = p1[k] - p0[k];
            v[k] = p2[k] - p0[k];
            w[k] = p2[k] - p1[k];
        }
        double lu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        double lv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        double lw = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        double lmax = lu > lv ? lu : lv;
        lmax = lmax > lw ? lmax : lw;
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double *out = f->tri_normal + 3 * t;
        if (len <= 1e-12 * lmax || len == 0) {
            out[0] = out[1] = out[2] = 0;
            degenerate++;
        } else {
            for (int k = 0; k < 3; k++)
                out[k] = n[k] / len;
        }
    }
    f->n_degenerate = degenerate;
}

static int has_normal(const vc_features *f, int64_t t)
{
    const double *n = f->tri_normal + 3 * t;
    return n[0] != 0 || n[1] != 0 || n[2] != 0;
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* see vc_features_detect_scaled's cos_theta */
#define FOLD_TIE 1e-6

/* The cosine of the fold at edge e between its triangles t1 and t2, both
 * with normals, before the patches are oriented: the input's triangles of
 * a consistently oriented pair walk the edge in opposite directions, and
 * the normals are made to agree across it. */
static double input_fold_cos(const vc_surface *s, const vc_features *f, int64_t e, int64_t t1,
                             int64_t t2)
{
    const double d = dot3(f->tri_normal + 3 * t1, f->tri_normal + 3 * t2);
    return walk_dir(f, s, t1, e) == walk_dir(f, s, t2, e) ? -d : d;
}

static void find_sharp_edges(const vc_surface *s, vc_features *f, double cos_theta,
                             const unsigned char *extra)
{
    int64_t n_sharp = 0, n_angle = 0, n_boundary = 0, n_nm = 0;
    for (int64_t e = 0; e < f->n_edges; e++) {
        int64_t m = f->edge_tri_start[e + 1] - f->edge_tri_start[e];
        unsigned char why = 0;
        if (m == 1) {
            why = VC_SHARP_BOUNDARY;
            n_boundary++;
        } else if (m > 2) {
            why = VC_SHARP_NONMANIFOLD;
            n_nm++;
        } else {
            int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
            if (has_normal(f, t1) && has_normal(f, t2)) {
                if (input_fold_cos(s, f, e, t1, t2) < cos_theta) {
                    why = VC_SHARP_ANGLE;
                    n_angle++;
                }
            }
        }
        if (!why && extra && extra[e])
            why = VC_SHARP_FOLD;
        f->edge_sharp[e] = why;
        n_sharp += why != 0;
    }
    f->n_sharp_edges = n_sharp;
    f->n_sharp_by_angle = n_angle;
    f->n_boundary_edges = n_boundary;
    f->n_nonmanifold_edges = n_nm;
}

/* Folds below theta_sharp that the error bound sees become creases (see
 * vc_features_detect_scaled); not on ground judged noisy (near). */
static void promote_visible_folds(const vc_surface *s, vc_features *f, double scale,
                                  const unsigned char *near)
{
    int64_t n = 0;
    for (int64_t e = 0; e < f->n_edges; e++) {
        if (f->edge_sharp[e] || f->edge_tri_start[e + 1] - f->edge_tri_start[e] != 2)
            continue;
        const int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
        if (!has_normal(f, t1) || !has_normal(f, t2) || (near && (near[t1] || near[t2])))
            continue;
        const double d = input_fold_cos(s, f, e, t1, t2);
        const double sin_fold = sqrt(fmax(0.0, 1 - d * d));
        /* each triangle's height over the edge: its apex's distance from
         * the edge's line */
        const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
        double dir[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double len = sqrt(dot3(dir, dir));
        if (!(len > 0))
            continue;
        for (int k = 0; k < 3; k++)
            dir[k] /= len;
        double height = INFINITY;
        for (int k = 0; k < 2; k++) {
            const int64_t t = k ? t2 : t1;
            const double *p = s->xyz + 3 * s->tri[3 * t + (side_of(f, t, e) + 2) % 3];
            const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]}, along = dot3(ap, dir);
            height = fmin(height, sqrt(fmax(0.0, dot3(ap, ap) - along * along)));
        }
        if (sin_fold * height > VC_VISIBLE_FOLD * scale) {
            f->edge_sharp[e] = VC_SHARP_FOLD;
            n++;
        }
    }
    f->n_sharp_visible = n;
    f->n_sharp_edges += n;
}

/* ---- 5. Surface patches ---- */

static int build_patches(const vc_surface *s, vc_features *f, vc_error *err)
{
    int64_t nt = s->n_triangles;
    int64_t *queue = f->patch_tri; /* patches are laid out in flood order, sorted after */
    unsigned char *orientable = xalloc(nt, 1);
    int64_t *start = xalloc(nt + 1, sizeof *start);
    if (!orientable || !start) {
        free(orientable);
        free(start);
        return vc_error_set(err, VC_ENOMEM, "out of memory flooding patches");
    }
    for (int64_t t = 0; t < nt; t++) {
        f->tri_patch[t] = -1;
        f->tri_orient[t] = 0;
    }
    int64_t np = 0, tail = 0, n_nonorientable = 0;
    for (int64_t seed = 0; seed < nt; seed++) {
        if (f->tri_patch[seed] >= 0)
            continue;
        int64_t head = tail, first = tail;
        start[np] = first;
        orientable[np] = 1;
        f->tri_patch[seed] = np;
        f->tri_orient[seed] = 1;
        queue[tail++] = seed;
        while (head < tail) {
            int64_t t = queue[head++];
            for (int j = 0; j < 3; j++) {
                int64_t e = f->tri_edge[3 * t + j];
                if (f->edge_sharp[e])
                    continue; /* exactly two triangles otherwise */
                int64_t k = f->edge_tri_start[e];
                int64_t u = f->edge_tri[k] == t ? f->edge_tri[k + 1] : f->edge_tri[k];
                /* Opposite walks keep the orientation, equal walks flip it. */
                int same = walk_dir(f, s, t, e) == walk_dir(f, s, u, e);
                signed char o = (signed char)(same ? -f->tri_orient[t] : f->tri_orient[t]);
                if (f->tri_patch[u] < 0) {
                    f->tri_patch[u] = np;
                    f->tri_orient[u] = o;
                    queue[tail++] = u;
                } else if (f->tri_orient[u] != o) {
                    orientable[np] = 0;
                }
            }
        }
        /* Keep the input orientation of the majority. */
        int64_t flipped = 0;
        for (int64_t k = first; k < tail; k++)
            flipped += f->tri_orient[queue[k]] < 0;
        if (2 * flipped > tail - first)
            for (int64_t k = first; k < tail; k++)
                f->tri_orient[queue[k]] = (signed char)-f->tri_orient[queue[k]];
        n_nonorientable += !orientable[np];
        np++;
    }
    start[np] = tail;
    /* Triangles of each patch in ascending order: a counting pass over
     * the triangles (already grouped by patch through tri_patch). */
    for (int64_t p = 0; p <= np; p++)
        start[p] = 0;
    for (int64_t t = 0; t < nt; t++)
        start[f->tri_patch[t] + 1]++;
    for (int64_t p = 0; p < np; p++)
        start[p + 1] += start[p];
    int64_t *pos = xalloc(np, sizeof *pos);
    if (!pos) {
        free(orientable);
        free(start);
        return vc_error_set(err, VC_ENOMEM, "out of memory flooding patches");
    }
    memcpy(pos, start, (size_t)np * sizeof *pos);
    for (int64_t t = 0; t < nt; t++)
        f->patch_tri[pos[f->tri_patch[t]]++] = t;
    free(pos);

    f->n_patches = np;
    f->n_nonorientable_patches = n_nonorientable;
    /* Kept at their allocated size (at most one entry per triangle): a
     * shrinking realloc saves little and GCC 12 flags the fallback path. */
    f->patch_start = start;
    f->patch_orientable = orientable;
    return 0;
}

/* ---- 3. Sectors and corners ---- */

/* Union-find with parity: par[i] is the orientation of i relative to
 * parent[i] (+1 same, -1 opposite). After uf_find(i), parent[i] is the
 * root and par[i] the orientation of i relative to it. */
static int64_t uf_find(int64_t *parent, signed char *par, int64_t i)
{
    int64_t r = i;
    int p = 1;
    while (parent[r] != r) {
        p *= par[r];
        r = parent[r];
    }
    /* Compress: every node on the path points to r with its parity. */
    while (parent[i] != r && parent[i] != i) {
        int64_t next = parent[i];
        int pn = p * par[i]; /* parity of next relative to r */
        parent[i] = r;
        par[i] = (signed char)p;
        i = next;
        p = pn;
    }
    return r;
}

/* Records that o(b) = o(a) * rel. */
static void uf_union(int64_t *parent, signed char *par, int64_t a, int64_t b, int rel)
{
    int64_t ra = uf_find(parent, par, a), rb = uf_find(parent, par, b);
    if (ra == rb)
        return; /* a fan around a vertex is a disk: no conflict to record */
    int p = par[a] * rel * par[b]; /* o(rb) = o(ra) * p */
    if (ra < rb) {
        parent[rb] = ra;
        par[rb] = (signed char)p;
    } else {
        parent[ra] = rb;
        par[ra] = (signed char)p;
    }
}

/* The corner slot of vertex v in triangle t: 3t + j with tri[3t+j] == v. */
static int64_t slot_of(const vc_surface *s, int64_t t, int64_t v)
{
    return 3 * t + (s->tri[3 * t] == v ? 0 : s->tri[3 * t + 1] == v ? 1 : 2);
}

/* A corner slot with its sector (union-find root) for sorting. */
typedef struct slot_rec {
    int64_t root, slot;
} slot_rec;

/* (root, slot): distinct records (slots are unique), the same order for any sort */
#define SLOT_LESS(p, q) ((p)->root < (q)->root || ((p)->root == (q)->root && (p)->slot < (q)->slot))
VC_SMALL_SORT(sort_slots, slot_rec, SLOT_LESS)

/* The normal sector_spread counts for corner slot h: NULL for a
 * zero-area triangle, and for one whose tilt a fold beside it was judged
 * noise at the error bound (tilted[t], may be NULL): a marching-cubes
 * sliver's normal swings by 70 degrees over the sliver's width of 1e-8,
 * and counting it made its corners sector corners 3e-7 apart, which
 * sliver elimination could not resolve. */
static const double *counted_normal(const vc_features *f, int64_t h, const unsigned char *tilted)
{
    const double *q = f->tri_normal + 3 * (h / 3);
    if ((q[0] == 0 && q[1] == 0 && q[2] == 0) || (tilted && tilted[h / 3]))
        return NULL;
    return q;
}

/* Whether two of the normals of the triangles of the corner slots
 * r[0..n-1] (those counted_normal skips left out), each turned by the
 * slot's sign par (the orientation of the sector), differ by at least
 * theta, i.e. have dot <= cos_theta. When every normal is within theta / 2
 * of the mean direction no pair can; otherwise pairs are compared until
 * one is found. */
static int sector_spread(const vc_features *f, const slot_rec *r, int64_t n, const signed char *par,
                         double cos_theta, double cos_half, const unsigned char *tilted)
{
    double m[3] = {0, 0, 0};
    int64_t used = 0;
    for (int64_t i = 0; i < n; i++) {
        const double *q = counted_normal(f, r[i].slot, tilted);
        if (!q)
            continue;
        double sg = par[r[i].slot];
        m[0] += sg * q[0];
        m[1] += sg * q[1];
        m[2] += sg * q[2];
        used++;
    }
    if (used < 2)
        return 0;
    double len = sqrt(dot3(m, m));
    if (len > 0) {
        int inside = 1;
        for (int64_t i = 0; i < n && inside; i++) {
            const double *q = counted_normal(f, r[i].slot, tilted);
            if (q)
                inside = par[r[i].slot] * dot3(q, m) > cos_half * len;
        }
        if (inside)
            return 0;
    }
    for (int64_t i = 0; i < n; i++) {
        const double *p = counted_normal(f, r[i].slot, tilted);
        if (!p)
            continue;
        for (int64_t j = i + 1; j < n; j++) {
            const double *q = counted_normal(f, r[j].slot, tilted);
            if (q && par[r[i].slot] * par[r[j].slot] * dot3(p, q) <= cos_theta)
                return 1;
        }
    }
    return 0;
}

/* Vertex -> sharp edges adjacency (CSR), also fills vertex_sharp_degree. */
static int sharp_adjacency(vc_features *f, int64_t **adj_start, int64_t **adj, vc_error *err)
{
    int64_t nv = f->n_vertices;
    int64_t *st = xcalloc(nv + 1, sizeof *st);
    int64_t *a = xalloc(2 * f->n_sharp_edges, sizeof *a);
    if (!st || !a) {
        free(st);
        free(a);
        return vc_error_set(err, VC_ENOMEM, "out of memory indexing sharp edges");
    }
    for (int64_t e = 0; e < f->n_edges; e++)
        if (f->edge_sharp[e]) {
            st[f->edge_vertex[2 * e] + 1]++;
            st[f->edge_vertex[2 * e + 1] + 1]++;
        }
    for (int64_t v = 0; v < nv; v++) {
        f->vertex_sharp_degree[v] = (int32_t)st[v + 1];
        st[v + 1] += st[v];
    }
    for (int64_t e = 0; e < f->n_edges; e++)
        if (f->edge_sharp[e]) {
            a[st[f->edge_vertex[2 * e]]++] = e;
            a[st[f->edge_vertex[2 * e + 1]]++] = e;
        }
    for (int64_t v = nv; v > 0; v--)
        st[v] = st[v - 1];
    st[0] = 0;
    *adj_start = st;
    *adj = a;
    return 0;
}

static int find_corners(const vc_surface *s, vc_features *f, const int64_t *adj_start,
                        const int64_t *adj, double cos_theta, double scale, unsigned char *near,
                        vc_error *err)
{
    int64_t nv = s->n_vertices, nt = s->n_triangles, nh = 3 * nt;
    double cos_half = cos(0.5 * acos(cos_theta));
    int64_t *parent = xalloc(nh, sizeof *parent);
    signed char *par = xalloc(nh, 1);
    /* the slots (triangle corners, 3 t + k) at each vertex */
    int64_t *vstart = NULL, *vslot = NULL;
    slot_rec *recs = NULL;
    if (!parent || !par || vc_csr_group(s->tri, nh, 1, nv, NULL, &vstart, &vslot)) {
        free(parent);
        free(par);
        return vc_error_set(err, VC_ENOMEM, "out of memory finding corners");
    }
    /* Sectors: corners of triangles joined through non-sharp edges, with
     * their orientation relative to the sector's root (the input
     * orientation need not be consistent, and a patch need not be
     * orientable, but a sector is). */
    for (int64_t h = 0; h < nh; h++) {
        parent[h] = h;
        par[h] = 1;
    }
    for (int64_t e = 0; e < f->n_edges; e++) {
        if (f->edge_sharp[e])
            continue;
        int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
        int rel = walk_dir(f, s, t1, e) == walk_dir(f, s, t2, e) ? -1 : 1;
        for (int k = 0; k < 2; k++) {
            int64_t v = f->edge_vertex[2 * e + k];
            uf_union(parent, par, slot_of(s, t1, v), slot_of(s, t2, v), rel);
        }
    }
    /* Every slot straight under its root, parity relative to the root. */
    for (int64_t h = 0; h < nh; h++)
        uf_find(parent, par, h);
    /* the largest group of slots sizes the sort buffer */
    int64_t kmax = 0;
    for (int64_t v = 0; v < nv; v++)
        kmax = vstart[v + 1] - vstart[v] > kmax ? vstart[v + 1] - vstart[v] : kmax;
    recs = xalloc(kmax, sizeof *recs);
    /* the sector corners to judge at the error bound (after the loop) */
    int64_t *judge = scale > 0 ? xalloc(nv, sizeof *judge) : NULL;
    int64_t n_judge = 0;
    if (!recs || (scale > 0 && !judge)) {
        free(recs);
        free(judge);
        free(parent);
        free(par);
        free(vstart);
        free(vslot);
        return vc_error_set(err, VC_ENOMEM, "out of memory finding corners");
    }

    int64_t n_corners = 0;
    for (int64_t v = 0; v < nv; v++) {
        unsigned char why = 0;
        int64_t deg = adj_start[v + 1] - adj_start[v];
        if (deg > 2)
            why |= VC_CORNER_DEGREE;
        else if (deg == 1)
            why |= VC_CORNER_END;
        else if (deg == 2) {
            int64_t e0 = adj[adj_start[v]], e1 = adj[adj_start[v] + 1];
            int64_t a = f->edge_vertex[2 * e0] == v ? f->edge_vertex[2 * e0 + 1] : f->edge_vertex[2 * e0];
            int64_t b = f->edge_vertex[2 * e1] == v ? f->edge_vertex[2 * e1 + 1] : f->edge_vertex[2 * e1];
            const double *pv = s->xyz + 3 * v, *pa = s->xyz + 3 * a, *pb = s->xyz + 3 * b;
            double u[3] = {pa[0] - pv[0], pa[1] - pv[1], pa[2] - pv[2]};
            double w[3] = {pb[0] - pv[0], pb[1] - pv[1], pb[2] - pv[2]};
            /* angle(u, w) < pi - theta  <=>  cos(angle) > -cos(theta) */
            if (dot3(u, w) > -cos_theta * sqrt(dot3(u, u) * dot3(w, w)))
                why |= VC_CORNER_TURN;
        }
        slot_rec *r = recs;
        int64_t k = vstart[v + 1] - vstart[v];
        for (int64_t i = 0; i < k; i++) {
            int64_t h = vslot[vstart[v] + i];
            r[i] = (slot_rec){parent[h], h};
        }
        sort_slots(r, k);
        int64_t n_sectors = 0;
        for (int64_t i = 0; i < k;) {
            int64_t j = i + 1;
            while (j < k && r[j].root == r[i].root)
                j++;
            n_sectors++;
            if (!(why & VC_CORNER_SECTOR) && sector_spread(f, r + i, j - i, par, cos_theta, cos_half, near))
                why |= VC_CORNER_SECTOR;
            i = j;
        }
        if (why == VC_CORNER_SECTOR && scale > 0)
            judge[n_judge++] = v;
        if (deg == 0 && n_sectors > 1)
            why |= VC_CORNER_PINCH;
        f->vertex_corner[v] = why;
        n_corners += why != 0;
    }
    /* A sector corner on flat ground at the error bound is noise, not a
     * corner: judged in parallel (a walk each, from the vertex's first
     * triangle in sector order; the verdicts do not depend on the order:
     * a UV sphere's noisy poles have thousands) */
    unsigned char *noise = n_judge > 0 ? calloc((size_t)n_judge, 1) : NULL;
    int fail = n_judge > 0 && !noise;
    if (!fail && n_judge > 0) {
#pragma omp parallel reduction(| : fail)
        {
            vc_flat_probe probe;
            slot_rec *rr = xalloc(kmax, sizeof *rr);
            int64_t *vtri = xalloc(kmax, sizeof *vtri);
            if (!rr || !vtri || vc_flat_probe_init(&probe, nt))
                fail = 1;
            else {
#pragma omp for schedule(dynamic, 16)
                for (int64_t j = 0; j < n_judge; j++) {
                    const int64_t v = judge[j], k = vstart[v + 1] - vstart[v];
                    for (int64_t i = 0; i < k; i++) {
                        const int64_t h = vslot[vstart[v] + i];
                        rr[i] = (slot_rec){parent[h], h};
                    }
                    sort_slots(rr, k);
                    for (int64_t i = 0; i < k; i++)
                        vtri[i] = rr[i].slot / 3;
                    noise[j] = (unsigned char)vc_features_vertex_flat(s, f, &probe, v, vtri, k, scale, near);
                }
                vc_flat_probe_free(&probe);
            }
            free(rr);
            free(vtri);
        }
    }
    for (int64_t j = 0; j < n_judge && !fail; j++)
        if (noise[j]) {
            f->vertex_corner[judge[j]] = 0;
            f->n_corner_noise++;
            n_corners--;
        }
    f->n_corners = n_corners;
    free(noise);
    free(judge);
    free(parent);
    free(par);
    free(vstart);
    free(vslot);
    free(recs);
    if (fail)
        return vc_error_set(err, VC_ENOMEM, "out of memory judging corners");
    return 0;
}

static int64_t close_cosmooth_corners(const vc_surface *s, vc_features *f, double theta_sharp_deg);
static int take_round_normals(vc_features *f, const double *round_normal);

/* ---- 4. Creases ---- */

static int build_creases(vc_features *f, const int64_t *adj_start, const int64_t *adj,
                         vc_error *err)
{
    int64_t ns = f->n_sharp_edges;
    f->crease_start = xalloc(ns + 1, sizeof *f->crease_start);
    f->crease_edge = xalloc(ns, sizeof *f->crease_edge);
    f->crease_vertex = xalloc(2 * ns, sizeof *f->crease_vertex);
    f->crease_closed = xalloc(ns, 1);
    if (!f->crease_start || !f->crease_edge || !f->crease_vertex || !f->crease_closed)
        return vc_error_set(err, VC_ENOMEM, "out of memory building creases");
    for (int64_t e = 0; e < f->n_edges; e++) {
        f->edge_crease[e] = -1;
        f->edge_crease_dir[e] = 0;
    }
    int64_t nc = 0, n_open = 0, ne_used = 0, nvx = 0;
    /* Open creases: from every corner along each of its unused sharp edges
     * to the next corner. */
    for (int pass = 0; pass < 2; pass++) {
        for (int64_t v0 = 0; v0 < f->n_vertices; v0++) {
            if (pass == 0 && !f->vertex_corner[v0])
                continue;
            if (pass == 1 && (f->vertex_corner[v0] || f->vertex_sharp_degree[v0] == 0))
                continue;
            for (int64_t i = adj_start[v0]; i < adj_start[v0 + 1]; i++) {
                int64_t e = adj[i];
                if (f->edge_crease[e] >= 0)
                    continue;
                /* Pass 1: a remaining edge at a non-corner vertex lies on a
                 * cycle without corners. */
                f->crease_start[nc] = ne_used;
                f->crease_vertex[nvx++] = v0;
                int64_t v = v0;
                for (;;) {
                    int64_t a = f->edge_vertex[2 * e], b = f->edge_vertex[2 * e + 1];
                    int64_t w = a == v ? b : a;
                    f->edge_crease[e] = nc;
                    f->edge_crease_dir[e] = (signed char)(a == v ? 1 : -1);
                    f->crease_edge[ne_used++] = e;
                    f->crease_vertex[nvx++] = w;
                    v = w;
                    if (f->vertex_corner[v] || v == v0)
                        break;
                    /* A non-corner vertex has exactly two sharp edges. */
                    int64_t e0 = adj[adj_start[v]], e1 = adj[adj_start[v] + 1];
                    int64_t next = e0 == e ? e1 : e0;
                    if (adj_start[v + 1] - adj_start[v] != 2 || f->edge_crease[next] >= 0)
                        return vc_error_set(err, VC_EINTERNAL,
                                            "crease walk: vertex %lld has %lld sharp edges, not a corner",
                                            (long long)v, (long long)(adj_start[v + 1] - adj_start[v]));
                    e = next;
                }
                f->crease_closed[nc] = (unsigned char)(pass == 1);
                if (pass == 1 && v != v0)
                    return vc_error_set(err, VC_EINTERNAL, "crease walk from vertex %lld did not close",
                                        (long long)v0);
                nc++;
            }
        }
        if (pass == 0)
            n_open = nc;
    }
    f->n_closed_creases = nc - n_open;
    f->crease_start[nc] = ne_used;
    f->n_creases = nc;
    if (ne_used != ns || nvx != ns + nc)
        return vc_error_set(err, VC_EINTERNAL, "creases cover %lld of %lld sharp edges",
                            (long long)ne_used, (long long)ns);
    return 0;
}

/* ---- Driver ---- */

int vc_features_detect(const vc_surface *s, double theta_sharp_deg, vc_features *out,
                       vc_error *err)
{
    return vc_features_detect_with(s, theta_sharp_deg, NULL, out, err);
}

int vc_features_detect_with(const vc_surface *s, double theta_sharp_deg,
                            const unsigned char *extra_sharp, vc_features *out, vc_error *err)
{
    return vc_features_detect_scaled(s, theta_sharp_deg, extra_sharp, 0, out, err);
}

int vc_features_detect_scaled(const vc_surface *s, double theta_sharp_deg,
                              const unsigned char *extra_sharp, double scale, vc_features *out,
                              vc_error *err)
{
    memset(out, 0, sizeof *out);
    if (!(theta_sharp_deg > 0 && theta_sharp_deg < 180))
        return vc_error_set(err, VC_EPARAM, "sharp angle %g degrees: must be in (0, 180)",
                            theta_sharp_deg);
    int64_t nv = s->n_vertices, nt = s->n_triangles;
    if (nv < 0 || nt < 0)
        return vc_error_set(err, VC_EINPUT, "surface with negative counts");
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *v = s->tri + 3 * t;
        for (int j = 0; j < 3; j++)
            if (v[j] < 0 || v[j] >= nv)
                return vc_error_set(err, VC_EINPUT, "triangle %lld refers to vertex %lld of %lld",
                                    (long long)(t + 1), (long long)v[j] + 1, (long long)nv);
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
            return vc_error_set(err, VC_EINPUT, "triangle %lld repeats vertex %lld", (long long)(t + 1),
                                (long long)(v[0] == v[1] || v[0] == v[2] ? v[0] : v[1]) + 1);
    }
    vc_features *f = out;
    f->sharp_angle = theta_sharp_deg;
    f->n_vertices = nv;
    f->n_triangles = nt;
    f->noise_scale = scale > 0 && isfinite(scale) ? scale : 0;
    unsigned char *near = NULL;
    double *round_normal = NULL;
    /* Folds within FOLD_TIE radians of theta_sharp count as sharp: an input
     * that folds by exactly theta_sharp (a hexagonal prism at 60 degrees)
     * has its folds computed a few ulps either side of it, a few 1e-7
     * either side from float32 STL coordinates; classified apart, the ones
     * just below were sampled as smooth, where sliver elimination stalled
     * until they became creases after all. */
    double cos_theta = cos(theta_sharp_deg * M_PI / 180.0 - FOLD_TIE);

    int rc = build_edges(s, f, err);
    int64_t *adj_start = NULL, *adj = NULL;
    if (!rc) {
        int64_t ne = f->n_edges;
        f->edge_sharp = xalloc(ne, 1);
        f->vertex_corner = xalloc(nv, 1);
        f->vertex_sharp_degree = xalloc(nv, sizeof *f->vertex_sharp_degree);
        f->tri_normal = xalloc(3 * nt, sizeof *f->tri_normal);
        if (!f->edge_sharp || !f->vertex_corner || !f->vertex_sharp_degree || !f->tri_normal)
            rc = vc_error_set(err, VC_ENOMEM, "out of memory detecting features of %lld triangles",
                              (long long)nt);
    }
    if (!rc) {
        compute_normals(s, f);
        find_sharp_edges(s, f, cos_theta, extra_sharp);
        if (f->noise_scale > 0 && (!(near = xcalloc(nt, 1)) ||
                                   vc_features_unmark_noise_folds(s, f, f->noise_scale, near)))
            rc = vc_error_set(err, VC_ENOMEM, "out of memory detecting features");
        else if (f->noise_scale > 0) {
            promote_visible_folds(s, f, f->noise_scale, near);
            if (vc_features_mark_rounds(s, f, f->noise_scale, cos_theta, near, &round_normal) < 0)
                rc = vc_error_set(err, VC_ENOMEM, "out of memory detecting features");
        }
    }
    if (!rc)
        rc = sharp_adjacency(f, &adj_start, &adj, err);
    if (!rc)
        rc = find_corners(s, f, adj_start, adj, cos_theta, f->noise_scale, near, err);
    /* The arrays of the later steps are allocated after the corner step's
     * scratch memory is freed, to lower the peak. */
    if (!rc) {
        f->edge_crease = xalloc(f->n_edges, sizeof *f->edge_crease);
        f->edge_crease_dir = xalloc(f->n_edges, 1);
        if (!f->edge_crease || !f->edge_crease_dir)
            rc = vc_error_set(err, VC_ENOMEM, "out of memory building creases");
    }
    if (!rc)
        rc = build_creases(f, adj_start, adj, err);
    free(adj_start);
    free(adj);
    adj_start = adj = NULL;
    if (!rc) {
        f->tri_patch = xalloc(nt, sizeof *f->tri_patch);
        f->tri_orient = xalloc(nt, 1);
        f->patch_tri = xalloc(nt, sizeof *f->patch_tri);
        if (!f->tri_patch || !f->tri_orient || !f->patch_tri)
            rc = vc_error_set(err, VC_ENOMEM, "out of memory flooding patches");
    }
    if (!rc)
        rc = build_patches(s, f, err);
    if (!rc) {
        /* Normals in the patch orientation. */
        for (int64_t t = 0; t < nt; t++)
            if (f->tri_orient[t] < 0)
                for (int k = 0; k < 3; k++)
                    f->tri_normal[3 * t + k] = -f->tri_normal[3 * t + k];
    }
    if (!rc && f->n_sharp_noise + f->n_corner_noise > 0 &&
        vc_features_smooth_normals(s, f, f->noise_scale, near))
        rc = vc_error_set(err, VC_ENOMEM, "out of memory smoothing normals");
    if (!rc && round_normal && take_round_normals(f, round_normal))
        rc = vc_error_set(err, VC_ENOMEM, "out of memory smoothing normals");
    if (!rc && close_cosmooth_corners(s, f, theta_sharp_deg) < 0)
        rc = vc_error_set(err, VC_ENOMEM, "out of memory checking the corners");
    free(near);
    free(round_normal);
    free(adj_start);
    free(adj);
    if (rc)
        vc_features_free(f);
    return rc;
}

/* Step 2c's band triangles (round_normal non-zero, in their input
 * orientation) take that flank as their smoothed normal, in the patch
 * orientation, and are flagged in tri_round. Returns 0, or -1 when out of
 * memory. */
static int take_round_normals(vc_features *f, const double *round_normal)
{
    const int64_t nt = f->n_triangles;
    if (!f->tri_smooth_normal) {
        f->tri_smooth_normal = malloc(sizeof(double) * 3 * (size_t)(nt > 0 ? nt : 1));
        if (!f->tri_smooth_normal)
            return -1;
        memcpy(f->tri_smooth_normal, f->tri_normal, sizeof(double) * 3 * (size_t)nt);
    }
    f->tri_round = xcalloc(nt, 1);
    if (!f->tri_round)
        return -1;
    for (int64_t t = 0; t < nt; t++) {
        const double *r = round_normal + 3 * t;
        if (r[0] == 0 && r[1] == 0 && r[2] == 0)
            continue;
        for (int k = 0; k < 3; k++)
            f->tri_smooth_normal[3 * t + k] = f->tri_orient[t] * r[k];
        f->tri_round[t] = 1;
    }
    return 0;
}

/* ---- 7. Corners where co-smoothness breaks ----
 *
 * The sizing takes two triangles of a patch as co-smooth when their
 * normals agree within theta_sharp, or their normals smoothed at the error
 * bound do (sizing.c, normals_agree). Around a vertex that is no corner,
 * the triangles of one sector (joined around it through non-sharp edges)
 * must all be co-smooth so: two that are not lie at distance zero from
 * each other's points at the vertex, the sizing falls to zero there, and
 * the sampling chases the vertex with ever smaller balls (a marching-cubes
 * Perlin blob: a vertex whose six triangles spread by 66 degrees, every
 * fold at it below 60, balls down to 7e-9 of the error bound near it). The
 * corner step counts such a spread (VC_CORNER_SECTOR) but without the
 * triangles that a noise fold nearby tilted, whose smoothed normals the
 * sizing then reads: the two views can disagree, and this step closes the
 * gap with the sizing's own test. Such a vertex is a corner, which a corner
 * ball protects. Returns the vertices made corners, or -1 when out of
 * memory. */
static int64_t close_cosmooth_corners(const vc_surface *s, vc_features *f, double theta_sharp_deg)
{
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    const double cos_smooth = cos(theta_sharp_deg * M_PI / 180.0);
    const double *m = f->tri_smooth_normal;
    int64_t *vstart = NULL, *vslot = NULL;
    if (vc_csr_group(s->tri, 3 * nt, 1, nv, NULL, &vstart, &vslot))
        return -1;
    int64_t added = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : added)
    for (int64_t v = 0; v < nv; v++) {
        /* Only a vertex without sharp edges: its triangles are one sector (a
         * pinch is a corner already); one on a crease is the crease's, whose
         * balls cover it, and a corner there would cut the crease. */
        if (f->vertex_corner[v] || f->vertex_sharp_degree[v] != 0)
            continue;
        const int64_t *slot = vslot + vstart[v], k = vstart[v + 1] - vstart[v];
        int conflict = 0;
        for (int64_t i = 0; i < k && !conflict; i++) {
            const int64_t t = slot[i] / 3;
            const double *a = f->tri_normal + 3 * t;
            /* zero area: no normal; a Moebius strip: no orientation */
            if ((a[0] == 0 && a[1] == 0 && a[2] == 0) || !f->patch_orientable[f->tri_patch[t]])
                continue;
            for (int64_t j = i + 1; j < k && !conflict; j++) {
                const int64_t u = slot[j] / 3;
                const double *b = f->tri_normal + 3 * u;
                if (b[0] == 0 && b[1] == 0 && b[2] == 0)
                    continue;
                conflict = dot3(a, b) < cos_smooth && !(m && dot3(m + 3 * t, m + 3 * u) >= cos_smooth);
            }
        }
        if (conflict) {
            f->vertex_corner[v] = VC_CORNER_SECTOR;
            added++;
        }
    }
    free(vstart);
    free(vslot);
    f->n_corners += added;
    f->n_corner_cosmooth = added;
    return added;
}

void vc_features_oriented_triangle(const vc_features *f, const vc_surface *s, int64_t t,
                                   int64_t v[3])
{
    v[0] = s->tri[3 * t];
    if (f->tri_orient[t] < 0) {
        v[1] = s->tri[3 * t + 2];
        v[2] = s->tri[3 * t + 1];
    } else {
        v[1] = s->tri[3 * t + 1];
        v[2] = s->tri[3 * t + 2];
    }
}
