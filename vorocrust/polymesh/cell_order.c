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


static void insertion_sort_i64(int64_t *a, int64_t n)
{
    for (int64_t i = 1; i < n; i++) {
        const int64_t x = a[i];
        int64_t j = i;
        for (; j > 0 && a[j - 1] > x; j--)
            a[j] = a[j - 1];
        a[j] = x;
    }
}

/* Sorts the faces in cmp_face's order in linear time: a stable counting
 * sort by bucket (interior faces by owner, then boundary faces by owner),
 * the faces listed by increasing old index, then each interior bucket (a
 * cell's few faces toward higher cells) by neighbour. *fs is replaced;
 * returns 0, or -1 when out of memory. */
static int sort_faces(face_sort **fs, int64_t nf, int64_t nc)
{
    int64_t *start = calloc((size_t)(2 * nc + 1), sizeof(int64_t));
    face_sort *out = malloc(sizeof(face_sort) * (size_t)(nf + 1));
    if (!start || !out) {
        free(start);
        free(out);
        return -1;
    }
    const face_sort *in = *fs;
    for (int64_t f = 0; f < nf; f++)
        start[(in[f].neighbour < 0 ? nc : 0) + in[f].owner + 1]++;
    for (int64_t b = 0; b < 2 * nc; b++)
        start[b + 1] += start[b];
    for (int64_t f = 0; f < nf; f++)
        out[start[(in[f].neighbour < 0 ? nc : 0) + in[f].owner]++] = in[f];
    /* start[b] is now the end of bucket b */
    for (int64_t b = 0, from = 0; b < nc; from = start[b], b++)
        for (int64_t i = from + 1; i < start[b]; i++) {
            const face_sort x = out[i];
            int64_t j = i;
            for (; j > from && cmp_face(&out[j - 1], &x) > 0; j--)
                out[j] = out[j - 1];
            out[j] = x;
        }
    free(start);
    free(*fs);
    *fs = out;
    return 0;
}

/* Replaces *arr (n records of size bytes) by its records taken in the
 * order src[0 .. n): one array at a time, so the peak memory is the mesh
 * and one array. */
static int gather(void *arr, size_t size, int64_t n, const int64_t *src)
{
    char **p = arr;
    if (!*p)
        return 0;
    char *q = malloc(size * (size_t)(n > 0 ? n : 1));
    if (!q)
        return -1;
    for (int64_t i = 0; i < n; i++)
        memcpy(q + size * (size_t)i, *p + size * (size_t)src[i], size);
    free(*p);
    *p = q;
    return 0;
}

int vc_polymesh_renumber_cells(vc_polymesh *m, const int64_t *new_of_old)
{
    const int64_t nc = m->n_cells, nf = m->n_faces, np = m->n_points;
    const int64_t nfv = m->face_offsets[nf], ncf = m->cell_offsets[nc];
    face_sort *fs = malloc(sizeof(face_sort) * (size_t)(nf + 1));
    int64_t *old_face = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    int64_t *new_point = malloc(sizeof(int64_t) * (size_t)(np + 1));
    int64_t *old_point = malloc(sizeof(int64_t) * (size_t)(np + 1));
    int64_t *old_of_new = malloc(sizeof(int64_t) * (size_t)(nc + 1));
    unsigned char *flip = malloc((size_t)nf + 1);
    int rc = -1;
    if (!fs || !old_face || !new_point || !old_point || !old_of_new || !flip)
        goto done;
    for (int64_t c = 0; c < nc; c++)
        old_of_new[new_of_old[c]] = c;
    /* faces: interior by (owner, neighbour) with the owner the lower cell,
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
    if (sort_faces(&fs, nf, nc))
        goto done;
    for (int64_t g = 0; g < nf; g++) {
        old_face[g] = fs[g].old;
        /* turned when the lower cell was the neighbour */
        flip[g] = fs[g].neighbour >= 0 && fs[g].owner != new_of_old[m->face_owner[fs[g].old]];
    }
    /* the face vertex lists in the new order (reversed where turned,
     * keeping the first vertex first), points numbered by first use */
    int64_t *fo = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    int64_t *fv = malloc(sizeof(int64_t) * (size_t)(nfv + 1));
    if (!fo || !fv) {
        free(fo);
        free(fv);
        goto done;
    }
    for (int64_t p = 0; p < np; p++)
        new_point[p] = -1;
    int64_t k = 0, npn = 0;
    fo[0] = 0;
    for (int64_t g = 0; g < nf; g++) {
        const int64_t f = old_face[g], a = m->face_offsets[f], len = m->face_offsets[f + 1] - a;
        for (int64_t j = 0; j < len; j++) {
            const int64_t v = m->face_vertices[a + (flip[g] ? (len - j) % len : j)];
            if (new_point[v] < 0) {
                old_point[npn] = v;
                new_point[v] = npn++;
            }
            fv[k++] = new_point[v];
        }
        fo[g + 1] = k;
    }
    free(m->face_offsets);
    free(m->face_vertices);
    m->face_offsets = fo;
    m->face_vertices = fv;
    /* the other face arrays */
    if (gather(&m->face_other_seed, sizeof(int64_t), nf, old_face) ||
        (m->face_group && gather(&m->face_group, sizeof(int32_t), nf, old_face)) ||
        gather(&m->face_area, sizeof(double), nf, old_face) ||
        gather(&m->face_centroid, 3 * sizeof(double), nf, old_face) ||
        gather(&m->face_normal, 3 * sizeof(double), nf, old_face))
        goto done;
    for (int64_t g = 0; g < nf; g++) {
        m->face_owner[g] = fs[g].owner;
        m->face_neighbour[g] = fs[g].neighbour;
        if (flip[g])
            for (int d = 0; d < 3; d++)
                m->face_normal[3 * g + d] = -m->face_normal[3 * g + d];
    }
    /* an interior face's other seed is its neighbour's (cell_seed is still
     * in the old order here), which a turned face swaps */
    if (m->face_other_seed)
        for (int64_t g = 0; g < nf; g++)
            if (fs[g].neighbour >= 0)
                m->face_other_seed[g] = m->cell_seed[old_of_new[fs[g].neighbour]];
    /* points */
    if (gather(&m->points, 3 * sizeof(double), npn, old_point))
        goto done;
    m->n_points = npn;
    /* cells: their faces by new index, in increasing order */
    int64_t *nfi = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    int64_t *co = malloc(sizeof(int64_t) * (size_t)(nc + 1));
    int64_t *cf = malloc(sizeof(int64_t) * (size_t)(ncf + 1));
    if (!nfi || !co || !cf) {
        free(nfi);
        free(co);
        free(cf);
        goto done;
    }
    for (int64_t g = 0; g < nf; g++)
        nfi[old_face[g]] = g;
    int64_t q = 0;
    co[0] = 0;
    for (int64_t c = 0; c < nc; c++) {
        const int64_t old = old_of_new[c], from = q;
        for (int64_t j = m->cell_offsets[old]; j < m->cell_offsets[old + 1]; j++)
            cf[q++] = nfi[m->cell_faces[j]];
        insertion_sort_i64(cf + from, q - from); /* a cell's dozen faces */
        co[c + 1] = q;
    }
    free(nfi);
    free(m->cell_offsets);
    free(m->cell_faces);
    m->cell_offsets = co;
    m->cell_faces = cf;
    if (gather(&m->cell_seed, sizeof(int64_t), nc, old_of_new) ||
        gather(&m->cell_region, sizeof(int32_t), nc, old_of_new) ||
        gather(&m->cell_volume, sizeof(double), nc, old_of_new) ||
        gather(&m->cell_centroid, 3 * sizeof(double), nc, old_of_new) ||
        gather(&m->cell_fatness, sizeof(double), nc, old_of_new))
        goto done;
    rc = 0;
done:
    free(fs);
    free(old_face);
    free(new_point);
    free(old_point);
    free(old_of_new);
    free(flip);
    return rc;
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
