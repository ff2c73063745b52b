/* Open cells closed by collapsing the clusters of points at their open
 * edges (see vc_polymesh_collapse_open_clusters in polymesh.h). */
#include "polymesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct dir_edge {
    int64_t lo, hi; /* the points, lo < hi */
    int forward;    /* the cell goes lo -> hi */
} dir_edge;

static int cmp_dir_edge(const void *pa, const void *pb)
{
    const dir_edge *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->forward - b->forward;
}

/* The directed edges of cell c (outward) into *buf, sorted by their
 * points; returns their number, or -1 when out of memory. */
static int64_t cell_edges(const vc_polymesh *m, int64_t c, dir_edge **buf, int64_t *cap)
{
    int64_t ne = 0;
    for (int64_t i = m->cell_offsets[c]; i < m->cell_offsets[c + 1]; i++)
        ne += vc_polymesh_face_size(m, m->cell_faces[i]);
    if (ne > *cap) {
        dir_edge *q = realloc(*buf, (size_t)ne * sizeof *q);
        if (!q)
            return -1;
        *buf = q;
        *cap = ne;
    }
    int64_t k = 0;
    for (int64_t i = m->cell_offsets[c]; i < m->cell_offsets[c + 1]; i++) {
        const int64_t f = m->cell_faces[i], n = vc_polymesh_face_size(m, f);
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        const int rev = m->face_owner[f] != c;
        for (int64_t j = 0; j < n; j++) {
            int64_t a = fv[j], b = fv[j + 1 < n ? j + 1 : 0];
            if (rev) {
                const int64_t t = a;
                a = b;
                b = t;
            }
            (*buf)[k++] = a < b ? (dir_edge){a, b, 1} : (dir_edge){b, a, 0};
        }
    }
    qsort(*buf, (size_t)k, sizeof **buf, cmp_dir_edge);
    return k;
}

/* Is the edge run e[i..j) (one pair of points) used once each way? */
static int balanced(const dir_edge *e, int64_t i, int64_t j)
{
    return j - i == 2 && e[i].forward == 0 && e[i + 1].forward == 1;
}

/* A table of directed edges for the closure test, reused from cell to
 * cell: an entry holds an edge of the cell stamped in it. */
typedef struct edge_table {
    int64_t *a, *b, *stamp;
    int64_t size, mask; /* a power of 2 */
} edge_table;

static void edge_table_free(edge_table *t)
{
    free(t->a);
    free(t->b);
    free(t->stamp);
    memset(t, 0, sizeof *t);
}

/* Room for n edges at a load under one half; 0, or -1 when out of memory. */
static int edge_table_reserve(edge_table *t, int64_t n)
{
    if (2 * n <= t->size)
        return 0;
    int64_t size = 64;
    while (size < 2 * n)
        size *= 2;
    edge_table_free(t);
    t->a = malloc((size_t)size * sizeof *t->a);
    t->b = malloc((size_t)size * sizeof *t->b);
    t->stamp = malloc((size_t)size * sizeof *t->stamp);
    if (!t->a || !t->b || !t->stamp) {
        edge_table_free(t);
        return -1;
    }
    for (int64_t i = 0; i < size; i++)
        t->stamp[i] = -1;
    t->size = size;
    t->mask = size - 1;
    return 0;
}

static inline int64_t edge_slot(const edge_table *t, int64_t a, int64_t b)
{
    const uint64_t h = (uint64_t)a * 0x9E3779B97F4A7C15u ^ (uint64_t)b * 0xC2B2AE3D27D4EB4Fu;
    return (int64_t)((h ^ (h >> 29)) & (uint64_t)t->mask);
}

/* Adds a -> b for the cell stamped s; 0 when it was there already. */
static int edge_add(edge_table *t, int64_t s, int64_t a, int64_t b)
{
    for (int64_t i = edge_slot(t, a, b);; i = (i + 1) & t->mask) {
        if (t->stamp[i] != s) {
            t->stamp[i] = s;
            t->a[i] = a;
            t->b[i] = b;
            return 1;
        }
        if (t->a[i] == a && t->b[i] == b)
            return 0;
    }
}

static int edge_has(const edge_table *t, int64_t s, int64_t a, int64_t b)
{
    for (int64_t i = edge_slot(t, a, b); t->stamp[i] == s; i = (i + 1) & t->mask)
        if (t->a[i] == a && t->b[i] == b)
            return 1;
    return 0;
}

/* Does cell c use each of its edges exactly once each way? -1 when out of
 * memory. */
static int cell_closed(const vc_polymesh *m, int64_t c, edge_table *t)
{
    int64_t ne = 0;
    for (int64_t i = m->cell_offsets[c]; i < m->cell_offsets[c + 1]; i++)
        ne += vc_polymesh_face_size(m, m->cell_faces[i]);
    if (edge_table_reserve(t, ne) != 0)
        return -1;
    for (int pass = 0; pass < 2; pass++) {
        for (int64_t i = m->cell_offsets[c]; i < m->cell_offsets[c + 1]; i++) {
            const int64_t f = m->cell_faces[i], n = vc_polymesh_face_size(m, f);
            const int64_t *fv = m->face_vertices + m->face_offsets[f];
            const int rev = m->face_owner[f] != c;
            for (int64_t j = 0; j < n; j++) {
                const int64_t x = fv[j], y = fv[j + 1 < n ? j + 1 : 0];
                const int64_t a = rev ? y : x, b = rev ? x : y;
                if (pass == 0 ? !edge_add(t, c, a, b) || a == b : !edge_has(t, c, b, a))
                    return 0;
            }
        }
    }
    return 1;
}

static double dist(const double *p, const double *q)
{
    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static void unite(int64_t *parent, int64_t a, int64_t b)
{
    a = vc_point_root(parent, a);
    b = vc_point_root(parent, b);
    if (a != b) {
        /* The smaller index is the root: the result does not depend on
         * the order of the unions. */
        if (a < b)
            parent[b] = a;
        else
            parent[a] = b;
    }
}

/* Unites the points of a cell (e: its sorted edges, k of them) within
 * radius of an end of one of its unbalanced edges. */
static void collapse_at_open_edges(const vc_polymesh *m, const dir_edge *e, int64_t k,
                                   double radius, int64_t *parent, unsigned char *moved)
{
    for (int64_t i = 0, j; i < k; i = j) {
        for (j = i + 1; j < k && e[j].lo == e[i].lo && e[j].hi == e[i].hi; j++)
            ;
        if (balanced(e, i, j))
            continue;
        const int64_t ends[2] = {e[i].lo, e[i].hi};
        for (int s = 0; s < 2; s++) {
            const double *p = m->points + 3 * ends[s];
            for (int64_t q = 0; q < k; q++) {
                const int64_t pts[2] = {e[q].lo, e[q].hi};
                for (int t = 0; t < 2; t++) {
                    if (pts[t] == ends[s] || dist(p, m->points + 3 * pts[t]) > radius)
                        continue;
                    unite(parent, ends[s], pts[t]);
                    moved[ends[s]] = moved[pts[t]] = 1;
                }
            }
        }
    }
}

int64_t vc_polymesh_collapse_open_clusters(vc_polymesh *m, double rel_radius)
{
    dir_edge *e = NULL;
    int64_t cap = 0;
    int64_t *parent = NULL;
    unsigned char *moved = NULL;
    /* Which cells are open: a pass on threads (each cell on its own). */
    unsigned char *open = calloc((size_t)(m->n_cells > 0 ? m->n_cells : 1), 1);
    if (!open)
        return -1;
    int failed = 0;
#pragma omp parallel
    {
        edge_table t = {NULL, NULL, NULL, 0, 0};
#pragma omp for schedule(dynamic, 256)
        for (int64_t c = 0; c < m->n_cells; c++) {
            const int r = cell_closed(m, c, &t);
            if (r < 0) {
#pragma omp atomic write
                failed = 1;
            }
            open[c] = r == 0;
        }
        edge_table_free(&t);
    }
    if (failed)
        goto nomem;
    for (int64_t c = 0; c < m->n_cells; c++) {
        if (!open[c])
            continue;
        const int64_t k = cell_edges(m, c, &e, &cap);
        if (k < 0)
            goto nomem;
        if (!parent) {
            parent = malloc((size_t)m->n_points * sizeof *parent);
            moved = calloc((size_t)m->n_points, 1);
            if (!parent || !moved)
                goto nomem;
            for (int64_t v = 0; v < m->n_points; v++)
                parent[v] = v;
        }
        /* The cell's size as the validator measures it: the largest
         * distance from its centroid to a vertex. */
        double size = 0;
        for (int64_t i = 0; i < k; i++) {
            const double dl = dist(m->cell_centroid + 3 * c, m->points + 3 * e[i].lo);
            const double dh = dist(m->cell_centroid + 3 * c, m->points + 3 * e[i].hi);
            size = dl > size ? dl : size;
            size = dh > size ? dh : size;
        }
        collapse_at_open_edges(m, e, k, rel_radius * size, parent, moved);
    }
    free(e);
    e = NULL;
    int64_t n_merged = 0;
    if (parent) {
        for (int64_t v = 0; v < m->n_points; v++)
            n_merged += vc_point_root(parent, v) != v;
    }
    if (n_merged > 0) {
        vc_point_merge_buffers b;
        if (vc_point_merge_buffers_init(&b, m) != 0)
            goto nomem;
        vc_polymesh_merge_points(m, parent, moved, NULL, &b);
        vc_point_merge_buffers_free(&b);
        if (vc_polymesh_drop_unused_points(m) != 0)
            goto nomem;
    }
    free(parent);
    free(moved);
    free(open);
    return n_merged;
nomem:
    free(e);
    free(parent);
    free(moved);
    free(open);
    return -1;
}
