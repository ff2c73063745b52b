/* Faces a cell lists twice (see vc_polymesh_drop_duplicate_faces in
 * polymesh.h). */
#include "polymesh_internal.h"
#include "repair.h"

#include <stdlib.h>
#include <string.h>

/* Point i of face f's cycle as seen from cell c (outward from c). */
static inline int64_t cycle_point(const vc_polymesh *m, int64_t f, int64_t c, int64_t i)
{
    const int64_t *fv = m->face_vertices + m->face_offsets[f];
    const int64_t n = vc_polymesh_face_size(m, f);
    return m->face_owner[f] == c ? fv[i] : fv[n - 1 - i];
}

/* Are faces f and g of cell c the same cycle in the same direction, both
 * seen from c? */
static int same_cycle(const vc_polymesh *m, int64_t c, int64_t f, int64_t g)
{
    const int64_t n = vc_polymesh_face_size(m, f);
    if (vc_polymesh_face_size(m, g) != n)
        return 0;
    const int64_t x0 = cycle_point(m, f, c, 0);
    int64_t j0 = -1;
    for (int64_t j = 0; j < n && j0 < 0; j++)
        if (cycle_point(m, g, c, j) == x0)
            j0 = j;
    if (j0 < 0)
        return 0;
    for (int64_t i = 1; i < n; i++)
        if (cycle_point(m, f, c, i) != cycle_point(m, g, c, (j0 + i) % n))
            return 0;
    return 1;
}

/* Does another face of cell d hold the reverse of an edge of face f, all
 * seen from d? When none does, f hangs on d by its points alone: d is
 * closed without it. */
static int attached(const vc_polymesh *m, int64_t d, int64_t f)
{
    const int64_t n = vc_polymesh_face_size(m, f);
    for (int64_t k = m->cell_offsets[d]; k < m->cell_offsets[d + 1]; k++) {
        const int64_t g = m->cell_faces[k];
        if (g == f)
            continue;
        const int64_t ng = vc_polymesh_face_size(m, g);
        for (int64_t i = 0; i < ng; i++) {
            const int64_t a = cycle_point(m, g, d, i), b = cycle_point(m, g, d, (i + 1) % ng);
            for (int64_t j = 0; j < n; j++)
                if (cycle_point(m, f, d, j) == b && cycle_point(m, f, d, (j + 1) % n) == a)
                    return 1;
        }
    }
    return 0;
}

/* A face of a cell, keyed for finding repeats: its smallest point and its
 * size. */
typedef struct face_key {
    int64_t min_point, size, face;
} face_key;

static int key_less(const face_key *a, const face_key *b)
{
    return a->min_point < b->min_point || (a->min_point == b->min_point && a->size < b->size);
}

/* Marks in drop[] the copy that goes of each face cell c lists twice
 * (keys: room for the cell's faces). */
static void mark_duplicates(const vc_polymesh *m, int64_t c, face_key *keys, unsigned char *drop)
{
    const int64_t k0 = m->cell_offsets[c], nk = m->cell_offsets[c + 1] - k0;
    /* The cell's faces by key (insertion sort: a few tens of faces). */
    for (int64_t i = 0; i < nk; i++) {
        const int64_t f = m->cell_faces[k0 + i];
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        face_key key = {fv[0], vc_polymesh_face_size(m, f), f};
        for (int64_t j = 1; j < key.size; j++)
            key.min_point = fv[j] < key.min_point ? fv[j] : key.min_point;
        int64_t w = i;
        for (; w > 0 && key_less(&key, &keys[w - 1]); w--)
            keys[w] = keys[w - 1];
        keys[w] = key;
    }
    for (int64_t i = 0; i + 1 < nk; i++) {
        if (keys[i].min_point != keys[i + 1].min_point || keys[i].size != keys[i + 1].size)
            continue;
        const int64_t f = keys[i].face, g = keys[i + 1].face;
        if (!same_cycle(m, c, f, g))
            continue;
        /* The cell would use each edge of the cycle twice in one
         * direction. The copy that hangs on its other cell by its points
         * goes (from both cells); when neither or both do, the mesh is
         * left as it is (the validator reports it). */
        const int64_t df = m->face_owner[f] == c ? m->face_neighbour[f] : m->face_owner[f];
        const int64_t dg = m->face_owner[g] == c ? m->face_neighbour[g] : m->face_owner[g];
        const int hang_f = df >= 0 && !attached(m, df, f);
        const int hang_g = dg >= 0 && !attached(m, dg, g);
        if (hang_f != hang_g)
            __atomic_store_n(&drop[hang_f ? f : g], 1, __ATOMIC_RELAXED);
    }
}

int64_t vc_polymesh_drop_duplicate_faces(vc_polymesh *m, int threads)
{
    unsigned char *drop = calloc((size_t)(m->n_faces > 0 ? m->n_faces : 1), 1);
    if (!drop)
        return -1;
    int failed = 0;
    /* On threads, each cell on its own: the marks do not depend on the
     * order. */
#pragma omp parallel num_threads(threads > 0 ? threads : 1)
    {
        face_key *keys = NULL;
        int64_t cap = 0;
#pragma omp for schedule(dynamic, 256)
        for (int64_t c = 0; c < m->n_cells; c++) {
            const int64_t nk = m->cell_offsets[c + 1] - m->cell_offsets[c];
            if (nk > cap) {
                free(keys);
                cap = nk > 2 * cap ? nk : 2 * cap;
                keys = malloc((size_t)cap * sizeof *keys);
                if (!keys) {
                    cap = 0;
#pragma omp atomic write
                    failed = 1;
                    continue;
                }
            }
            mark_duplicates(m, c, keys, drop);
        }
        free(keys);
    }
    int64_t n_drop = 0;
    for (int64_t f = 0; f < m->n_faces && !failed; f++)
        n_drop += drop[f];
    if (!failed && n_drop > 0) {
        vc_point_merge_buffers b;
        failed = vc_point_merge_buffers_init(&b, m) != 0;
        if (!failed) {
            vc_polymesh_merge_points(m, NULL, NULL, drop, &b);
            vc_point_merge_buffers_free(&b);
            failed = vc_polymesh_drop_unused_points(m) != 0;
        }
    }
    free(drop);
    return failed ? -1 : n_drop;
}
