/* Open cells closed by collapsing the clusters of points at their open
 * edges (see vc_polymesh_collapse_open_clusters in polymesh/repair.h). */
#include "polymesh_internal.h"
#include "repair.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A table of a cell's directed edges with their counts, reused from cell
 * to cell: an entry belongs to the cell stamped in it. */
typedef struct edge_table {
    int64_t *a, *b, *stamp, *count;
    int64_t size, mask; /* a power of 2 */
} edge_table;

static void edge_table_free(edge_table *t)
{
    free(t->a);
    free(t->b);
    free(t->stamp);
    free(t->count);
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
    t->count = malloc((size_t)size * sizeof *t->count);
    if (!t->a || !t->b || !t->stamp || !t->count) {
        edge_table_free(t);
        return -1;
    }
    for (int64_t i = 0; i < size; i++)
        t->stamp[i] = -1;
    t->size = size;
    t->mask = size - 1;
    return 0;
}

/* The entry of a -> b for the cell stamped s: its own, or the empty one
 * where it would go. */
static int64_t edge_slot(const edge_table *t, int64_t s, int64_t a, int64_t b)
{
    const uint64_t h = (uint64_t)a * 0x9E3779B97F4A7C15u ^ (uint64_t)b * 0xC2B2AE3D27D4EB4Fu;
    int64_t i = (int64_t)((h ^ (h >> 29)) & (uint64_t)t->mask);
    while (t->stamp[i] == s && (t->a[i] != a || t->b[i] != b))
        i = (i + 1) & t->mask;
    return i;
}

static int64_t edge_count(const edge_table *t, int64_t s, int64_t a, int64_t b)
{
    const int64_t i = edge_slot(t, s, a, b);
    return t->stamp[i] == s ? t->count[i] : 0;
}

/* The directed edge a -> b of face f as cell c goes round it (outward):
 * the j-th of its n points and the next. */
static inline void cell_edge(const vc_polymesh *m, int64_t c, int64_t f, int64_t n, int64_t j,
                             int64_t *a, int64_t *b)
{
    const int64_t *fv = m->face_vertices + m->face_offsets[f];
    const int64_t x = fv[j], y = fv[j + 1 < n ? j + 1 : 0];
    const int rev = m->face_owner[f] != c;
    *a = rev ? y : x;
    *b = rev ? x : y;
}

/* Is a -> b of cell c (counted in t) used once, its reverse once, and not
 * a loop? */
static int edge_balanced(const edge_table *t, int64_t c, int64_t a, int64_t b)
{
    return a != b && edge_count(t, c, a, b) == 1 && edge_count(t, c, b, a) == 1;
}

/* Counts the directed edges of cell c into t, then tells whether each is
 * balanced. Returns 1 (closed), 0 (open) or -1 when out of memory. */
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
            for (int64_t j = 0; j < n; j++) {
                int64_t a, b;
                cell_edge(m, c, f, n, j, &a, &b);
                if (pass == 1) {
                    if (!edge_balanced(t, c, a, b))
                        return 0;
                    continue;
                }
                const int64_t k = edge_slot(t, c, a, b);
                if (t->stamp[k] != c) {
                    t->stamp[k] = c;
                    t->a[k] = a;
                    t->b[k] = b;
                    t->count[k] = 0;
                }
                t->count[k]++;
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

/* Unites the points of open cell c (its edges counted in t) within
 * rel_radius times its size of an end of one of its unbalanced edges. */
static void collapse_at_open_edges(const vc_polymesh *m, int64_t c, const edge_table *t,
                                   double rel_radius, int64_t *parent, unsigned char *moved)
{
    const int64_t f0 = m->cell_offsets[c], f1 = m->cell_offsets[c + 1];
    /* The cell's size as the validator measures it: the largest distance
     * from its centroid to a vertex. */
    double size = 0;
    for (int64_t i = f0; i < f1; i++) {
        const int64_t f = m->cell_faces[i], n = vc_polymesh_face_size(m, f);
        for (int64_t j = 0; j < n; j++) {
            const double d = dist(m->cell_centroid + 3 * c,
                                  m->points + 3 * m->face_vertices[m->face_offsets[f] + j]);
            size = d > size ? d : size;
        }
    }
    const double radius = rel_radius * size;
    for (int64_t i = f0; i < f1; i++) {
        const int64_t f = m->cell_faces[i], n = vc_polymesh_face_size(m, f);
        for (int64_t j = 0; j < n; j++) {
            int64_t ends[2];
            cell_edge(m, c, f, n, j, &ends[0], &ends[1]);
            if (edge_balanced(t, c, ends[0], ends[1]))
                continue;
            for (int s = 0; s < 2; s++) {
                const double *p = m->points + 3 * ends[s];
                for (int64_t i2 = f0; i2 < f1; i2++) {
                    const int64_t g = m->cell_faces[i2];
                    const int64_t *gv = m->face_vertices + m->face_offsets[g];
                    for (int64_t k = 0; k < vc_polymesh_face_size(m, g); k++) {
                        if (gv[k] == ends[s] || dist(p, m->points + 3 * gv[k]) > radius)
                            continue;
                        vc_uf_unite(parent, ends[s], gv[k]);
                        moved[ends[s]] = moved[gv[k]] = 1;
                    }
                }
            }
        }
    }
}

int64_t vc_polymesh_collapse_open_clusters(vc_polymesh *m, double rel_radius, int threads)
{
    int64_t *parent = NULL;
    unsigned char *moved = NULL;
    edge_table t = {NULL, NULL, NULL, NULL, 0, 0};
    /* Which cells are open: a pass on threads (each cell on its own). */
    unsigned char *open = calloc((size_t)(m->n_cells > 0 ? m->n_cells : 1), 1);
    if (!open)
        return -1;
    int failed = 0;
#pragma omp parallel num_threads(threads > 0 ? threads : 1)
    {
        edge_table tt = {NULL, NULL, NULL, NULL, 0, 0};
#pragma omp for schedule(dynamic, 256)
        for (int64_t c = 0; c < m->n_cells; c++) {
            const int r = cell_closed(m, c, &tt);
            if (r < 0) {
#pragma omp atomic write
                failed = 1;
            }
            open[c] = r == 0;
        }
        edge_table_free(&tt);
    }
    if (failed)
        goto nomem;
    for (int64_t c = 0; c < m->n_cells; c++) {
        if (!open[c])
            continue;
        if (!parent) {
            parent = malloc((size_t)m->n_points * sizeof *parent);
            moved = calloc((size_t)m->n_points, 1);
            if (!parent || !moved)
                goto nomem;
            vc_uf_init(parent, m->n_points);
        }
        if (cell_closed(m, c, &t) < 0) /* counts its edges into t */
            goto nomem;
        collapse_at_open_edges(m, c, &t, rel_radius, parent, moved);
    }
    edge_table_free(&t);
    int64_t n_merged = 0;
    if (parent) {
        for (int64_t v = 0; v < m->n_points; v++)
            n_merged += vc_uf_find(parent, v) != v;
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
    edge_table_free(&t);
    free(parent);
    free(moved);
    free(open);
    return -1;
}
