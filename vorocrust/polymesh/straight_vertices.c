/* Removal of straight vertices (points inside an edge), see polymesh.h. */
#include "vorocrust/polymesh.h"
#include "repair.h"

#include <stdlib.h>
#include <string.h>

/* Records x as a neighbour of v: nb[2v], nb[2v+1] hold the first two
 * distinct ones, many[v] is set at a third. */
static inline void note_neighbour(int64_t *nb, unsigned char *many, int64_t v, int64_t x)
{
    int64_t *n = nb + 2 * v;
    if (n[0] < 0 || n[0] == x)
        n[0] = x;
    else if (n[1] < 0 || n[1] == x)
        n[1] = x;
    else
        many[v] = 1;
}

int64_t vc_polymesh_remove_straight_vertices(vc_polymesh *m, int threads)
{
    const int64_t np = m->n_points, nf = m->n_faces;
    if (np == 0 || nf == 0)
        return 0;
    int64_t *nb = malloc(sizeof(int64_t) * 2 * (size_t)np);
    unsigned char *straight = calloc((size_t)np, 1);
    if (!nb || !straight) {
        free(nb);
        free(straight);
        return -1;
    }
    memset(nb, 0xff, sizeof(int64_t) * 2 * (size_t)np); /* all -1 */
    for (int64_t f = 0; f < nf; f++) {
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        const int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
        for (int64_t i = 0; i < n; i++) {
            const int64_t v = fv[i];
            note_neighbour(nb, straight, v, fv[i == 0 ? n - 1 : i - 1]);
            note_neighbour(nb, straight, v, fv[i == n - 1 ? 0 : i + 1]);
        }
    }
    /* straight[] held "more than two neighbours"; turn it into the mark. */
    int64_t n_straight = 0;
    for (int64_t v = 0; v < np; v++) {
        straight[v] = !straight[v] && nb[2 * v + 1] >= 0;
        n_straight += straight[v];
    }
    free(nb);
    if (n_straight == 0) {
        free(straight);
        return 0;
    }
    /* Keep the straight vertices of a face that would drop below three
     * (a zero-area face); keeping more only helps other faces. */
    int64_t new_nfv = 0;
    for (int64_t f = 0; f < nf; f++) {
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        const int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
        int64_t keep = 0;
        for (int64_t i = 0; i < n; i++)
            keep += !straight[fv[i]];
        if (keep < 3)
            for (int64_t i = 0; i < n; i++)
                straight[fv[i]] = 0;
    }
    int64_t *new_index = malloc(sizeof(int64_t) * (size_t)np);
    if (!new_index) {
        free(straight);
        return -1;
    }
    int64_t n_points = 0;
    for (int64_t v = 0; v < np; v++)
        new_index[v] = straight[v] ? -1 : n_points++;
    n_straight = np - n_points;
    if (n_straight == 0) {
        free(straight);
        free(new_index);
        return 0;
    }
    for (int64_t f = 0; f < nf; f++)
        for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; i++)
            new_nfv += !straight[m->face_vertices[i]];
    int64_t *fv_new = malloc(sizeof(int64_t) * (size_t)new_nfv);
    unsigned char *cell_changed = calloc((size_t)(m->n_cells > 0 ? m->n_cells : 1), 1);
    unsigned char *face_changed = calloc((size_t)nf, 1);
    if (!fv_new || !cell_changed || !face_changed) {
        free(fv_new);
        free(cell_changed);
        free(face_changed);
        free(straight);
        free(new_index);
        return -1;
    }

    /* The faces without their straight vertices; the changed ones and
     * their cells get their geometry again. */
    int64_t w = 0;
    for (int64_t f = 0; f < nf; f++) {
        const int64_t b = m->face_offsets[f], e = m->face_offsets[f + 1];
        int changed = 0;
        m->face_offsets[f] = w;
        for (int64_t i = b; i < e; i++) {
            const int64_t v = m->face_vertices[i];
            if (straight[v])
                changed = 1;
            else
                fv_new[w++] = new_index[v];
        }
        if (changed) {
            face_changed[f] = 1;
            cell_changed[m->face_owner[f]] = 1;
            if (m->face_neighbour[f] >= 0)
                cell_changed[m->face_neighbour[f]] = 1;
        }
    }
    m->face_offsets[nf] = w;
    free(m->face_vertices);
    m->face_vertices = fv_new;
    for (int64_t v = 0; v < np; v++)
        if (new_index[v] >= 0)
            memmove(m->points + 3 * new_index[v], m->points + 3 * v, sizeof(double) * 3);
    m->n_points = n_points;
    double *shrunk = realloc(m->points, sizeof(double) * 3 * (size_t)(n_points > 0 ? n_points : 1));
    if (shrunk)
        m->points = shrunk;

#pragma omp parallel for schedule(static) num_threads(threads > 0 ? threads : 1)
    for (int64_t f = 0; f < nf; f++)
        if (face_changed[f])
            vc_polymesh_update_face_geometry(m, f);
#pragma omp parallel for schedule(static) num_threads(threads > 0 ? threads : 1)
    for (int64_t c = 0; c < m->n_cells; c++)
        if (cell_changed[c])
            vc_polymesh_update_cell_geometry(m, c);
    free(face_changed);
    free(cell_changed);
    free(straight);
    free(new_index);
    return n_straight;
}
