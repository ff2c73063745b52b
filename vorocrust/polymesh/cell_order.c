/* Cell order for solvers: reverse Cuthill-McKee over the cells' face
 * graph, and the mesh renumbered to it (see polymesh.h). */
#include "vorocrust/polymesh.h"

#include <stdlib.h>
#include <string.h>

/* Cells next to each cell (CSR), through interior faces. */
static int cell_graph(const vc_polymesh *m, int64_t **start, int64_t **adj)
{
    const int64_t n = m->n_cells, nf = m->n_interior_faces;
    int64_t *s = calloc((size_t)n + 1, sizeof(int64_t));
    int64_t *a = malloc(sizeof(int64_t) * (size_t)(2 * nf + 1));
    if (!s || !a) {
        free(s);
        free(a);
        return -1;
    }
    for (int64_t f = 0; f < nf; f++) {
        s[m->face_owner[f] + 1]++;
        s[m->face_neighbour[f] + 1]++;
    }
    for (int64_t c = 0; c < n; c++)
        s[c + 1] += s[c];
    int64_t *fill = malloc(sizeof(int64_t) * (size_t)(n + 1));
    if (!fill) {
        free(s);
        free(a);
        return -1;
    }
    memcpy(fill, s, sizeof(int64_t) * (size_t)n);
    for (int64_t f = 0; f < nf; f++) {
        a[fill[m->face_owner[f]]++] = m->face_neighbour[f];
        a[fill[m->face_neighbour[f]]++] = m->face_owner[f];
    }
    free(fill);
    *start = s;
    *adj = a;
    return 0;
}

/* Breadth-first order from `root` over the cells not yet placed (place[c]
 * < 0), neighbours by increasing degree, then index; appends to order from
 * *n and returns the last cell placed. */
static int64_t bfs(const int64_t *s, const int64_t *a, int64_t root, int64_t *place, int64_t *order,
                   int64_t *n, int64_t *scratch)
{
    int64_t head = *n;
    place[root] = (*n)++;
    order[place[root]] = root;
    int64_t last = root;
    while (head < *n) {
        const int64_t c = order[head++];
        last = c;
        int64_t k = 0;
        for (int64_t j = s[c]; j < s[c + 1]; j++)
            if (place[a[j]] < 0) {
                /* insertion by (degree, index): few neighbours */
                const int64_t x = a[j], dx = s[x + 1] - s[x];
                int64_t i = k++;
                while (i > 0) {
                    const int64_t y = scratch[i - 1], dy = s[y + 1] - s[y];
                    if (dy < dx || (dy == dx && y < x))
                        break;
                    scratch[i] = y;
                    i--;
                }
                scratch[i] = x;
                place[x] = -2; /* queued */
            }
        for (int64_t i = 0; i < k; i++) {
            place[scratch[i]] = *n;
            order[(*n)++] = scratch[i];
        }
    }
    return last;
}

int vc_polymesh_rcm_order(const vc_polymesh *m, int64_t *new_of_old)
{
    const int64_t n = m->n_cells;
    int64_t *s = NULL, *a = NULL;
    if (cell_graph(m, &s, &a))
        return -1;
    int64_t maxdeg = 0;
    for (int64_t c = 0; c < n; c++)
        maxdeg = s[c + 1] - s[c] > maxdeg ? s[c + 1] - s[c] : maxdeg;
    int64_t *place = malloc(sizeof(int64_t) * (size_t)(n + 1));
    int64_t *order = malloc(sizeof(int64_t) * (size_t)(n + 1));
    int64_t *scratch = malloc(sizeof(int64_t) * (size_t)(maxdeg + 1));
    if (!place || !order || !scratch) {
        free(s);
        free(a);
        free(place);
        free(order);
        free(scratch);
        return -1;
    }
    for (int64_t c = 0; c < n; c++)
        place[c] = -1;
    int64_t placed = 0;
    for (int64_t c0 = 0; c0 < n; c0++) {
        if (place[c0] >= 0)
            continue;
        /* each component from a far cell: the last cell of a first sweep
         * (a pseudo-peripheral start, as George and Liu's heuristic) */
        const int64_t from = placed;
        const int64_t far = bfs(s, a, c0, place, order, &placed, scratch);
        for (int64_t i = from; i < placed; i++)
            place[order[i]] = -1;
        placed = from;
        bfs(s, a, far, place, order, &placed, scratch);
    }
    /* reversed */
    for (int64_t i = 0; i < n; i++)
        new_of_old[order[i]] = n - 1 - i;
    free(s);
    free(a);
    free(place);
    free(order);
    free(scratch);
    return 0;
}

/* ---- renumbering -------------------------------------------------------- */

typedef struct face_sort {
    int64_t owner, neighbour, old; /* neighbour -1: boundary, sorted last */
} face_sort;

static int cmp_face(const void *p, const void *q)
{
    const face_sort *x = p, *y = q;
    const int bx = x->neighbour < 0, by = y->neighbour < 0;
    if (bx != by)
        return bx - by;
    if (x->owner != y->owner)
        return x->owner < y->owner ? -1 : 1;
    if (x->neighbour != y->neighbour)
        return x->neighbour < y->neighbour ? -1 : 1;
    return x->old < y->old ? -1 : x->old > y->old;
}

static int cmp_i64(const void *p, const void *q)
{
    const int64_t x = *(const int64_t *)p, y = *(const int64_t *)q;
    return (x > y) - (x < y);
}

int vc_polymesh_renumber_cells(vc_polymesh *m, const int64_t *new_of_old)
{
    const int64_t nc = m->n_cells, nf = m->n_faces, np = m->n_points;
    const int64_t nfv = m->face_offsets[nf], ncf = m->cell_offsets[nc];
    face_sort *fs = malloc(sizeof(face_sort) * (size_t)(nf + 1));
    int64_t *new_face = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    int64_t *new_point = malloc(sizeof(int64_t) * (size_t)(np + 1));
    int64_t *old_of_new = malloc(sizeof(int64_t) * (size_t)(nc + 1));
    vc_polymesh r;
    memset(&r, 0, sizeof r);
    r.face_offsets = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    r.face_vertices = malloc(sizeof(int64_t) * (size_t)(nfv + 1));
    r.face_owner = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    r.face_neighbour = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    r.face_other_seed = m->face_other_seed ? malloc(sizeof(int64_t) * (size_t)(nf + 1)) : NULL;
    r.face_area = malloc(sizeof(double) * (size_t)(nf + 1));
    r.face_centroid = malloc(sizeof(double) * 3 * (size_t)(nf + 1));
    r.face_normal = malloc(sizeof(double) * 3 * (size_t)(nf + 1));
    r.points = malloc(sizeof(double) * 3 * (size_t)(np + 1));
    r.cell_offsets = malloc(sizeof(int64_t) * (size_t)(nc + 1));
    r.cell_faces = malloc(sizeof(int64_t) * (size_t)(ncf + 1));
    r.cell_seed = malloc(sizeof(int64_t) * (size_t)(nc + 1));
    r.cell_region = malloc(sizeof(int32_t) * (size_t)(nc + 1));
    r.cell_volume = malloc(sizeof(double) * (size_t)(nc + 1));
    r.cell_centroid = malloc(sizeof(double) * 3 * (size_t)(nc + 1));
    r.cell_fatness = m->cell_fatness ? malloc(sizeof(double) * (size_t)(nc + 1)) : NULL;
    if (!fs || !new_face || !new_point || !old_of_new || !r.face_offsets || !r.face_vertices ||
        !r.face_owner || !r.face_neighbour || (m->face_other_seed && !r.face_other_seed) ||
        !r.face_area || !r.face_centroid || !r.face_normal || !r.points || !r.cell_offsets ||
        !r.cell_faces || !r.cell_seed || !r.cell_region || !r.cell_volume || !r.cell_centroid ||
        (m->cell_fatness && !r.cell_fatness)) {
        free(fs);
        free(new_face);
        free(new_point);
        free(old_of_new);
        r.seed_xyz = NULL;
        vc_polymesh_free(&r);
        return -1;
    }
    for (int64_t c = 0; c < nc; c++)
        old_of_new[new_of_old[c]] = c;
    /* faces: interior by (owner, neighbour) with owner the lower cell,
     * then the boundary by owner */
    for (int64_t f = 0; f < nf; f++) {
        int64_t o = new_of_old[m->face_owner[f]];
        int64_t b = m->face_neighbour[f] >= 0 ? new_of_old[m->face_neighbour[f]] : -1;
        if (b >= 0 && b < o) {
            const int64_t t = o;
            o = b;
            b = t;
        }
        fs[f] = (face_sort){o, b, f};
    }
    qsort(fs, (size_t)nf, sizeof *fs, cmp_face);
    for (int64_t p = 0; p < np; p++)
        new_point[p] = -1;
    int64_t k = 0, npn = 0;
    r.face_offsets[0] = 0;
    for (int64_t g = 0; g < nf; g++) {
        const int64_t f = fs[g].old;
        new_face[f] = g;
        /* turned when the lower cell was the neighbour */
        const int flip = fs[g].neighbour >= 0 && fs[g].owner != new_of_old[m->face_owner[f]];
        const int64_t a = m->face_offsets[f], len = m->face_offsets[f + 1] - a;
        for (int64_t j = 0; j < len; j++) {
            /* reversed, keeping the first vertex first */
            const int64_t v = m->face_vertices[a + (flip ? (len - j) % len : j)];
            if (new_point[v] < 0) {
                new_point[v] = npn;
                memcpy(r.points + 3 * npn, m->points + 3 * v, sizeof(double) * 3);
                npn++;
            }
            r.face_vertices[k++] = new_point[v];
        }
        r.face_offsets[g + 1] = k;
        r.face_owner[g] = fs[g].owner;
        r.face_neighbour[g] = fs[g].neighbour;
        if (r.face_other_seed)
            r.face_other_seed[g] = flip ? m->cell_seed[m->face_owner[f]] : m->face_other_seed[f];
        r.face_area[g] = m->face_area[f];
        for (int d = 0; d < 3; d++) {
            r.face_centroid[3 * g + d] = m->face_centroid[3 * f + d];
            r.face_normal[3 * g + d] = flip ? -m->face_normal[3 * f + d] : m->face_normal[3 * f + d];
        }
    }
    /* cells: their faces in increasing new index */
    int64_t q = 0;
    r.cell_offsets[0] = 0;
    for (int64_t c = 0; c < nc; c++) {
        const int64_t old = old_of_new[c];
        const int64_t from = q;
        for (int64_t j = m->cell_offsets[old]; j < m->cell_offsets[old + 1]; j++)
            r.cell_faces[q++] = new_face[m->cell_faces[j]];
        qsort(r.cell_faces + from, (size_t)(q - from), sizeof(int64_t), cmp_i64);
        r.cell_offsets[c + 1] = q;
        r.cell_seed[c] = m->cell_seed[old];
        r.cell_region[c] = m->cell_region[old];
        r.cell_volume[c] = m->cell_volume[old];
        memcpy(r.cell_centroid + 3 * c, m->cell_centroid + 3 * old, sizeof(double) * 3);
        if (r.cell_fatness)
            r.cell_fatness[c] = m->cell_fatness[old];
    }
    r.n_points = npn;
    r.n_faces = nf;
    r.n_interior_faces = m->n_interior_faces;
    r.n_cells = nc;
    r.n_seeds = m->n_seeds;
    r.seed_xyz = m->seed_xyz;
    m->seed_xyz = NULL;
    vc_polymesh_free(m);
    *m = r;
    free(fs);
    free(new_face);
    free(new_point);
    free(old_of_new);
    return 0;
}

int64_t vc_polymesh_bandwidth(const vc_polymesh *m)
{
    int64_t w = 0;
    for (int64_t f = 0; f < m->n_interior_faces; f++) {
        const int64_t d = m->face_neighbour[f] - m->face_owner[f];
        w = (d < 0 ? -d : d) > w ? (d < 0 ? -d : d) : w;
    }
    return w;
}
