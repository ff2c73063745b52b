/* Point merging: union-find groups of points become one point (see
 * polymesh_internal.h). */
#include "polymesh_internal.h"

#include <stdlib.h>
#include <string.h>

int vc_point_merge_buffers_init(vc_point_merge_buffers *b, const vc_polymesh *m)
{
    const size_t nf = (size_t)(m->n_faces > 0 ? m->n_faces : 1);
    b->new_face = malloc(sizeof(int64_t) * nf);
    b->face_changed = calloc(nf, 1);
    b->cell_changed = calloc((size_t)(m->n_cells > 0 ? m->n_cells : 1), 1);
    if (!b->new_face || !b->face_changed || !b->cell_changed) {
        vc_point_merge_buffers_free(b);
        return -1;
    }
    return 0;
}

void vc_point_merge_buffers_free(vc_point_merge_buffers *b)
{
    free(b->new_face);
    free(b->face_changed);
    free(b->cell_changed);
    memset(b, 0, sizeof *b);
}

void vc_polymesh_merge_points(vc_polymesh *m, int64_t *parent, const unsigned char *moved,
                              const unsigned char *drop, vc_point_merge_buffers *b)
{
    const int64_t nf = m->n_faces;
    memset(b->cell_changed, 0, (size_t)(m->n_cells > 0 ? m->n_cells : 1));
    /* In place: face f is written at wf <= f, its points at wv <= its old
     * start, so nothing is overwritten before it is read. */
    int64_t wf = 0, wv = 0, n_interior = 0;
    for (int64_t f = 0; f < nf; f++) {
        const int64_t first = m->face_offsets[f], end = m->face_offsets[f + 1];
        const int64_t start = wv;
        const int dropped = drop && drop[f];
        int changed = dropped;
        for (int64_t i = first; i < end && !dropped; i++) {
            const int64_t v = m->face_vertices[i], r = parent ? vc_uf_find(parent, v) : v;
            changed |= moved ? moved[v] : 0;
            if (wv == start || m->face_vertices[wv - 1] != r)
                m->face_vertices[wv++] = r;
        }
        while (wv - start > 1 && m->face_vertices[start] == m->face_vertices[wv - 1])
            wv--;
        if (changed) {
            b->cell_changed[m->face_owner[f]] = 1;
            if (m->face_neighbour[f] >= 0)
                b->cell_changed[m->face_neighbour[f]] = 1;
        }
        if (wv - start < 3) {
            b->new_face[f] = -1;
            wv = start;
            continue;
        }
        b->new_face[f] = wf;
        n_interior += f < m->n_interior_faces;
        m->face_offsets[wf] = start;
        m->face_owner[wf] = m->face_owner[f];
        m->face_neighbour[wf] = m->face_neighbour[f];
        m->face_other_seed[wf] = m->face_other_seed[f];
        if (m->face_group)
            m->face_group[wf] = m->face_group[f];
        memmove(m->face_centroid + 3 * wf, m->face_centroid + 3 * f, sizeof(double) * 3);
        memmove(m->face_normal + 3 * wf, m->face_normal + 3 * f, sizeof(double) * 3);
        m->face_area[wf] = m->face_area[f];
        b->face_changed[wf] = (unsigned char)changed;
        wf++;
    }
    m->face_offsets[wf] = wv;
    m->n_faces = wf;
    m->n_interior_faces = n_interior;
    for (int64_t f = 0; f < wf; f++)
        if (b->face_changed[f])
            vc_polymesh_update_face_geometry(m, f);
    int64_t wc = 0;
    for (int64_t c = 0; c < m->n_cells; c++) {
        const int64_t first = m->cell_offsets[c], end = m->cell_offsets[c + 1];
        m->cell_offsets[c] = wc;
        for (int64_t i = first; i < end; i++)
            if (b->new_face[m->cell_faces[i]] >= 0)
                m->cell_faces[wc++] = b->new_face[m->cell_faces[i]];
    }
    m->cell_offsets[m->n_cells] = wc;
    for (int64_t c = 0; c < m->n_cells; c++)
        if (b->cell_changed[c])
            vc_polymesh_update_cell_geometry(m, c);
}

int vc_polymesh_drop_unused_points(vc_polymesh *m)
{
    int64_t *index = malloc(sizeof(int64_t) * (size_t)(m->n_points > 0 ? m->n_points : 1));
    if (!index)
        return -1;
    for (int64_t v = 0; v < m->n_points; v++)
        index[v] = -1;
    for (int64_t i = 0; i < m->face_offsets[m->n_faces]; i++)
        index[m->face_vertices[i]] = 0;
    int64_t np = 0;
    for (int64_t v = 0; v < m->n_points; v++)
        if (index[v] == 0) {
            index[v] = np;
            memmove(m->points + 3 * np, m->points + 3 * v, sizeof(double) * 3);
            np++;
        }
    for (int64_t i = 0; i < m->face_offsets[m->n_faces]; i++)
        m->face_vertices[i] = index[m->face_vertices[i]];
    m->n_points = np;
    free(index);
    return 0;
}
