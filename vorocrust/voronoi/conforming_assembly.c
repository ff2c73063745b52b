/* Stitching independently computed Voronoi cells into one conforming mesh
 * (see cell_result.h).
 *
 * Every cell holds its own copy of each of its vertices. Copies of one
 * Voronoi vertex are identified with a union-find: inside a cell, the ends
 * of edges shorter than the tolerance; across two kept cells, the vertices
 * of their common face, matched to the nearest copy on the other side.
 * The component's smallest copy index is its representative, so the result
 * does not depend on the order of the unions: they run on threads, linking
 * roots with compare-and-swap (a root is only ever linked to a smaller
 * index). A face between two kept cells is then written once, from its
 * owner (the lower cell index). */
#include "cell_result.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct assembly {
    const vc_cell_result *cells;
    const int64_t *kept_seed;
    int64_t n_kept;
    int64_t *cell_of_seed; /* seed -> kept cell index, or -1 */
    int64_t *vbase;        /* cell -> index of its first vertex copy */
    int64_t *parent;       /* union-find over vertex copies */
} assembly;

/* Thread-safe find with path halving: a parent pointer only ever moves to
 * an ancestor, which stays an ancestor whatever other threads link. */
static int64_t find_root(int64_t *parent, int64_t x)
{
    for (;;) {
        int64_t p = __atomic_load_n(&parent[x], __ATOMIC_RELAXED);
        if (p == x)
            return x;
        int64_t g = __atomic_load_n(&parent[p], __ATOMIC_RELAXED);
        if (g != p)
            __atomic_store_n(&parent[x], g, __ATOMIC_RELAXED);
        x = g;
    }
}

/* Links the larger root under the smaller one, if it is still a root. */
static void unite(int64_t *parent, int64_t a, int64_t b)
{
    for (;;) {
        a = find_root(parent, a);
        b = find_root(parent, b);
        if (a == b)
            return;
        int64_t hi = a > b ? a : b, lo = a > b ? b : a, expected = hi;
        if (__atomic_compare_exchange_n(&parent[hi], &expected, lo, 0, __ATOMIC_RELAXED,
                                        __ATOMIC_RELAXED))
            return;
    }
}

static double dist2(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* Face of cell c made by seed s, or -1. */
static int face_with_plane(const vc_cell_result *c, int64_t s)
{
    for (int f = 0; f < c->nf; f++)
        if (c->plane[f] == s)
            return f;
    return -1;
}

/* Unites every vertex of face fa of cell a with the nearest vertex of face
 * fb of cell b (all of b's vertices when fb < 0), when within tol. */
static void match_face(assembly *as, int64_t a, int fa, int64_t b, int fb, double tol2)
{
    const vc_cell_result *ca = &as->cells[a], *cb = &as->cells[b];
    int s0 = ca->face_start[fa], s1 = ca->face_start[fa + 1];
    for (int i = s0; i < s1; i++) {
        int va = ca->fv[i];
        const double *x = ca->v + 3 * va;
        double best = tol2;
        int vb = -1;
        if (fb >= 0) {
            for (int j = cb->face_start[fb]; j < cb->face_start[fb + 1]; j++) {
                double d = dist2(x, cb->v + 3 * cb->fv[j]);
                if (d <= best) {
                    best = d;
                    vb = cb->fv[j];
                }
            }
        }
        if (vb < 0) {
            for (int j = 0; j < cb->nv; j++) {
                double d = dist2(x, cb->v + 3 * j);
                if (d <= best) {
                    best = d;
                    vb = j;
                }
            }
        }
        if (vb >= 0)
            unite(as->parent, as->vbase[a] + va, as->vbase[b] + vb);
    }
}

/* Writes the representative cycle of face f of cell k into buf (removing
 * repeated consecutive vertices); returns its length (< 3: degenerate). */
static int face_cycle(const assembly *as, int64_t k, int f, int64_t *buf)
{
    const vc_cell_result *c = &as->cells[k];
    int n = 0;
    for (int i = c->face_start[f]; i < c->face_start[f + 1]; i++) {
        int64_t r = as->parent[as->vbase[k] + c->fv[i]];
        if (n == 0 || buf[n - 1] != r)
            buf[n++] = r;
    }
    while (n > 1 && buf[n - 1] == buf[0])
        n--;
    return n >= 3 ? n : 0;
}

typedef struct face_rec {
    int64_t owner, neighbour; /* neighbour -1: boundary */
    int64_t other_seed;
    int64_t src_cell;         /* the cell whose copy of the face is used */
    int src_face;
    int reversed;             /* 1: the source cycle is seen from the neighbour */
} face_rec;

/* A vertex copy on a face against a non-kept cell or a wall, binned by
 * position for matching copies of cells that share no face. */
typedef struct loose_copy {
    int64_t key[3];
    int64_t copy;
    const double *x;
    double tol;
} loose_copy;

static int cmp_loose(const void *a, const void *b)
{
    const loose_copy *x = a, *y = b;
    for (int d = 0; d < 3; d++)
        if (x->key[d] != y->key[d])
            return x->key[d] < y->key[d] ? -1 : 1;
    return x->copy < y->copy ? -1 : (x->copy > y->copy);
}

/* First entry with key >= k. */
static int64_t lower_bound(const loose_copy *e, int64_t n, const int64_t k[3])
{
    int64_t lo = 0, hi = n;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        int less = 0;
        for (int d = 0; d < 3; d++)
            if (e[mid].key[d] != k[d]) {
                less = e[mid].key[d] < k[d];
                break;
            }
        if (less)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Kept cells that meet only along an edge or at a vertex (every cell
 * around it in between is not kept) share no face, so their copies of the
 * common vertices are matched here, by position: the copies on outer faces
 * are binned on a grid of the largest merge tolerance and compared with
 * the copies in the 27 surrounding bins. Returns -1 when out of memory. */
static int match_loose_copies(assembly *as, double merge_tol)
{
    int64_t n = 0;
    for (int64_t k = 0; k < as->n_kept; k++) {
        const vc_cell_result *c = &as->cells[k];
        for (int f = 0; f < c->nf; f++)
            if (c->plane[f] < 0 || as->cell_of_seed[c->plane[f]] < 0)
                n += c->face_start[f + 1] - c->face_start[f];
    }
    if (n == 0)
        return 0;
    loose_copy *e = malloc((size_t)n * sizeof *e);
    if (!e)
        return -1;
    double h = 0;
    int64_t m = 0;
    for (int64_t k = 0; k < as->n_kept; k++) {
        const vc_cell_result *c = &as->cells[k];
        double tol = merge_tol * c->scale;
        if (tol > h)
            h = tol;
        for (int f = 0; f < c->nf; f++) {
            if (!(c->plane[f] < 0 || as->cell_of_seed[c->plane[f]] < 0))
                continue;
            for (int i = c->face_start[f]; i < c->face_start[f + 1]; i++) {
                e[m].copy = as->vbase[k] + c->fv[i];
                e[m].x = c->v + 3 * c->fv[i];
                e[m].tol = tol;
                m++;
            }
        }
    }
    if (!(h > 0)) {
        free(e);
        return 0;
    }
    for (int64_t i = 0; i < n; i++)
        for (int d = 0; d < 3; d++)
            e[i].key[d] = (int64_t)floor(e[i].x[d] / h);
    qsort(e, (size_t)n, sizeof *e, cmp_loose);
    for (int64_t i = 0; i < n; i++) {
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int64_t k[3] = {e[i].key[0] + dx, e[i].key[1] + dy, e[i].key[2] + dz};
                    for (int64_t j = lower_bound(e, n, k); j < n; j++) {
                        if (e[j].key[0] != k[0] || e[j].key[1] != k[1] || e[j].key[2] != k[2])
                            break;
                        if (e[j].copy <= e[i].copy)
                            continue;
                        double tol = e[i].tol > e[j].tol ? e[i].tol : e[j].tol;
                        if (dist2(e[i].x, e[j].x) <= tol * tol)
                            unite(as->parent, e[i].copy, e[j].copy);
                    }
                }
    }
    free(e);
    return 0;
}

static int cmp_interior(const void *a, const void *b)
{
    const face_rec *x = a, *y = b;
    if (x->owner != y->owner)
        return x->owner < y->owner ? -1 : 1;
    if (x->neighbour != y->neighbour)
        return x->neighbour < y->neighbour ? -1 : 1;
    return 0;
}

int vc_assemble_conforming(const vc_seeds *seeds, const vc_cell_result *cells,
                           const int64_t *kept_seed, int64_t n_kept, const int64_t *order,
                           double merge_tol, vc_polymesh *out, vc_error *err)
{
    assembly as = {cells, kept_seed, n_kept, NULL, NULL, NULL};
    face_rec *interior = NULL, *boundary = NULL;
    int64_t *pid = NULL, *buf = NULL, *fbase = NULL;
    char *face_ok = NULL;
    int *twin = NULL;
    int max_len = 0;
    int rc = 0;

    as.cell_of_seed = malloc((size_t)seeds->n * sizeof(int64_t));
    as.vbase = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
    if (!as.cell_of_seed || !as.vbase)
        goto nomem;
    for (int64_t i = 0; i < seeds->n; i++)
        as.cell_of_seed[i] = -1;
    int64_t n_faces_all = 0, n_copies = 0;
    for (int64_t m = 0; m < n_kept; m++) {
        const int64_t k = order ? order[m] : m;
        as.vbase[k] = n_copies;
        n_copies += cells[k].nv;
    }
    for (int64_t k = 0; k < n_kept; k++) {
        as.cell_of_seed[kept_seed[k]] = k;
        n_faces_all += cells[k].nf;
        for (int f = 0; f < cells[k].nf; f++) {
            int len = cells[k].face_start[f + 1] - cells[k].face_start[f];
            if (len > max_len)
                max_len = len;
        }
    }
    as.parent = malloc((size_t)(n_copies > 0 ? n_copies : 1) * sizeof(int64_t));
    buf = malloc((size_t)(max_len + 1) * sizeof(int64_t));
    if (!as.parent || !buf)
        goto nomem;
    for (int64_t i = 0; i < n_copies; i++)
        as.parent[i] = i;

    /* Identify copies: short edges inside a cell, then common faces. Cells
     * are visited in the spatial order, so neighbours are in cache. */
#pragma omp parallel for schedule(dynamic, 64)
    for (int64_t m = 0; m < n_kept; m++) {
        const int64_t k = order ? order[m] : m;
        const vc_cell_result *c = &cells[k];
        double tol2 = merge_tol * c->scale * merge_tol * c->scale;
        for (int f = 0; f < c->nf; f++) {
            int s0 = c->face_start[f], s1 = c->face_start[f + 1];
            for (int i = s0; i < s1; i++) {
                int a = c->fv[i], b = c->fv[i + 1 < s1 ? i + 1 : s0];
                if (dist2(c->v + 3 * a, c->v + 3 * b) <= tol2)
                    unite(as.parent, as.vbase[k] + a, as.vbase[k] + b);
            }
        }
        for (int f = 0; f < c->nf; f++) {
            int64_t t = c->plane[f];
            if (t < 0 || as.cell_of_seed[t] <= k)
                continue;
            int64_t d = as.cell_of_seed[t];
            double sc = c->scale > cells[d].scale ? c->scale : cells[d].scale;
            double tol2f = merge_tol * sc * merge_tol * sc;
            int g = face_with_plane(&cells[d], kept_seed[k]);
            match_face(&as, k, f, d, g, tol2f);
            if (g >= 0)
                match_face(&as, d, g, k, f, tol2f);
        }
    }
    if (match_loose_copies(&as, merge_tol) != 0)
        goto nomem;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n_copies; i++)
        as.parent[i] = find_root(as.parent, i);

    /* Faces: each interior one once, from its owner's point of view. */
    interior = malloc((size_t)(n_faces_all > 0 ? n_faces_all : 1) * sizeof(face_rec));
    boundary = malloc((size_t)(n_faces_all > 0 ? n_faces_all : 1) * sizeof(face_rec));
    if (!interior || !boundary)
        goto nomem;
    /* Per face of every cell (in parallel): whether it survives the
     * merging, and the index of the same face in the neighbour cell. */
    fbase = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
    if (!fbase)
        goto nomem;
    fbase[0] = 0;
    for (int64_t k = 0; k < n_kept; k++)
        fbase[k + 1] = fbase[k] + cells[k].nf;
    face_ok = malloc((size_t)(n_faces_all > 0 ? n_faces_all : 1));
    twin = malloc((size_t)(n_faces_all > 0 ? n_faces_all : 1) * sizeof(int));
    if (!face_ok || !twin)
        goto nomem;
    int alloc_failed = 0;
#pragma omp parallel
    {
        int64_t *tbuf = malloc((size_t)(max_len + 1) * sizeof(int64_t));
        if (!tbuf) {
#pragma omp atomic write
            alloc_failed = 1;
        }
#pragma omp for schedule(dynamic, 64)
        for (int64_t m = 0; m < n_kept; m++) {
            const int64_t k = order ? order[m] : m;
            const vc_cell_result *c = &cells[k];
            for (int f = 0; f < c->nf && tbuf; f++) {
                int64_t t = c->plane[f];
                int64_t d = t >= 0 ? as.cell_of_seed[t] : -1;
                face_ok[fbase[k] + f] = face_cycle(&as, k, f, tbuf) > 0;
                twin[fbase[k] + f] = d >= 0 ? face_with_plane(&cells[d], kept_seed[k]) : -1;
            }
        }
        free(tbuf);
    }
    if (alloc_failed)
        goto nomem;
    int64_t n_int = 0, n_bnd = 0;
    for (int64_t k = 0; k < n_kept; k++) {
        const vc_cell_result *c = &cells[k];
        for (int f = 0; f < c->nf; f++) {
            int64_t t = c->plane[f];
            int64_t d = t >= 0 ? as.cell_of_seed[t] : -1;
            int ok = face_ok[fbase[k] + f];
            if (d < 0) {
                if (ok)
                    boundary[n_bnd++] = (face_rec){k, -1, t, k, f, 0};
                continue;
            }
            int g = twin[fbase[k] + f];
            int ok_other = g >= 0 && face_ok[fbase[d] + g];
            if (d > k) {
                if (ok)
                    interior[n_int++] = (face_rec){k, d, t, k, f, 0};
                else if (ok_other)
                    interior[n_int++] = (face_rec){k, d, t, d, g, 1};
            } else if (!ok_other && ok) {
                /* The owner lost this face to rounding: use ours. */
                interior[n_int++] = (face_rec){d, k, kept_seed[k], k, f, 1};
            }
        }
    }
    qsort(interior, (size_t)n_int, sizeof *interior, cmp_interior);

    /* Mesh arrays. */
    int64_t n_faces = n_int + n_bnd;
    out->n_faces = n_faces;
    out->n_interior_faces = n_int;
    out->face_offsets = malloc((size_t)(n_faces + 1) * sizeof(int64_t));
    out->face_owner = malloc((size_t)(n_faces > 0 ? n_faces : 1) * sizeof(int64_t));
    out->face_neighbour = malloc((size_t)(n_faces > 0 ? n_faces : 1) * sizeof(int64_t));
    out->face_other_seed = malloc((size_t)(n_faces > 0 ? n_faces : 1) * sizeof(int64_t));
    if (!out->face_offsets || !out->face_owner || !out->face_neighbour || !out->face_other_seed)
        goto nomem;
    /* Face lengths and the used representatives (in parallel), points
     * numbered in copy order (spatially coherent: copies follow the bin
     * order), then the vertex lists (in parallel). */
    pid = malloc((size_t)(n_copies > 0 ? n_copies : 1) * sizeof(int64_t));
    if (!pid)
        goto nomem;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n_copies; i++)
        pid[i] = -1;
    alloc_failed = 0;
#pragma omp parallel
    {
        int64_t *tbuf = malloc((size_t)(max_len + 1) * sizeof(int64_t));
        if (!tbuf) {
#pragma omp atomic write
            alloc_failed = 1;
        }
#pragma omp for schedule(dynamic, 1024)
        for (int64_t i = 0; i < n_faces; i++) {
            if (!tbuf)
                continue;
            const face_rec *r = i < n_int ? &interior[i] : &boundary[i - n_int];
            int len = face_cycle(&as, r->src_cell, r->src_face, tbuf);
            out->face_offsets[i + 1] = len;
            out->face_owner[i] = r->owner;
            out->face_neighbour[i] = r->neighbour;
            out->face_other_seed[i] = r->other_seed;
            for (int j = 0; j < len; j++)
                __atomic_store_n(&pid[tbuf[j]], 0, __ATOMIC_RELAXED); /* used */
        }
        free(tbuf);
    }
    if (alloc_failed)
        goto nomem;
    out->face_offsets[0] = 0;
    for (int64_t i = 0; i < n_faces; i++)
        out->face_offsets[i + 1] += out->face_offsets[i];
    const int64_t total_fv = out->face_offsets[n_faces];
    int64_t n_points = 0;
    for (int64_t i = 0; i < n_copies; i++)
        if (pid[i] == 0)
            pid[i] = n_points++;
        else
            pid[i] = -1;
    out->face_vertices = malloc((size_t)(total_fv > 0 ? total_fv : 1) * sizeof(int64_t));
    if (!out->face_vertices)
        goto nomem;
#pragma omp parallel
    {
        int64_t *tbuf = malloc((size_t)(max_len + 1) * sizeof(int64_t));
        if (!tbuf) {
#pragma omp atomic write
            alloc_failed = 1;
        }
#pragma omp for schedule(dynamic, 1024)
        for (int64_t i = 0; i < n_faces; i++) {
            if (!tbuf)
                continue;
            const face_rec *r = i < n_int ? &interior[i] : &boundary[i - n_int];
            int len = face_cycle(&as, r->src_cell, r->src_face, tbuf);
            int64_t *dst = out->face_vertices + out->face_offsets[i];
            for (int j = 0; j < len; j++)
                dst[j] = pid[tbuf[r->reversed ? len - 1 - j : j]];
        }
        free(tbuf);
    }
    if (alloc_failed)
        goto nomem;
    out->n_points = n_points;
    out->points = malloc((size_t)(n_points > 0 ? n_points : 1) * 3 * sizeof(double));
    if (!out->points)
        goto nomem;
    for (int64_t k = 0; k < n_kept; k++)
        for (int v = 0; v < cells[k].nv; v++) {
            int64_t copy = as.vbase[k] + v;
            if (as.parent[copy] == copy && pid[copy] >= 0)
                memcpy(out->points + 3 * pid[copy], cells[k].v + 3 * v, 3 * sizeof(double));
        }

    /* Cells and their face lists. */
    out->n_cells = n_kept;
    out->cell_offsets = calloc((size_t)n_kept + 1, sizeof(int64_t));
    out->cell_seed = malloc((size_t)n_kept * sizeof(int64_t));
    out->cell_region = malloc((size_t)n_kept * sizeof(int32_t));
    out->cell_faces = malloc((size_t)(n_int * 2 + n_bnd + 1) * sizeof(int64_t));
    if (!out->cell_offsets || !out->cell_seed || !out->cell_region || !out->cell_faces)
        goto nomem;
    for (int64_t i = 0; i < n_faces; i++) {
        out->cell_offsets[out->face_owner[i] + 1]++;
        if (out->face_neighbour[i] >= 0)
            out->cell_offsets[out->face_neighbour[i] + 1]++;
    }
    for (int64_t k = 0; k < n_kept; k++)
        out->cell_offsets[k + 1] += out->cell_offsets[k];
    {
        int64_t *fill = pid; /* reuse: pid is no longer needed */
        memcpy(fill, out->cell_offsets, (size_t)n_kept * sizeof(int64_t));
        for (int64_t i = 0; i < n_faces; i++) {
            out->cell_faces[fill[out->face_owner[i]]++] = i;
            if (out->face_neighbour[i] >= 0)
                out->cell_faces[fill[out->face_neighbour[i]]++] = i;
        }
    }
    for (int64_t k = 0; k < n_kept; k++) {
        out->cell_seed[k] = kept_seed[k];
        out->cell_region[k] = seeds->label[kept_seed[k]];
    }
    out->n_seeds = seeds->n;
    out->seed_xyz = malloc((size_t)seeds->n * 3 * sizeof(double));
    out->face_area = malloc((size_t)(n_faces > 0 ? n_faces : 1) * sizeof(double));
    out->face_centroid = malloc((size_t)(n_faces > 0 ? n_faces : 1) * 3 * sizeof(double));
    out->face_normal = malloc((size_t)(n_faces > 0 ? n_faces : 1) * 3 * sizeof(double));
    out->cell_volume = malloc((size_t)n_kept * sizeof(double));
    out->cell_centroid = malloc((size_t)n_kept * 3 * sizeof(double));
    if (!out->seed_xyz || !out->face_area || !out->face_centroid || !out->face_normal ||
        !out->cell_volume || !out->cell_centroid)
        goto nomem;
    memcpy(out->seed_xyz, seeds->xyz, (size_t)seeds->n * 3 * sizeof(double));
    vc_polymesh_compute_geometry(out);
    goto done;

nomem:
    rc = vc_error_set(err, VC_ENOMEM, "out of memory while assembling %lld cells",
                      (long long)n_kept);
    vc_polymesh_free(out);
done:
    free(as.cell_of_seed);
    free(as.vbase);
    free(as.parent);
    free(interior);
    free(boundary);
    free(pid);
    free(buf);
    free(fbase);
    free(face_ok);
    free(twin);
    return rc;
}
