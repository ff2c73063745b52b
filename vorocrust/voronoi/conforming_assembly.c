/* Stitching independently computed Voronoi cells into one conforming mesh
 * (see cell_result.h).
 *
 * The cells are handled in the spatial order given by the caller (their
 * position in it is called m below; neighbouring cells are close in it),
 * through a compact header per cell, so that a cell's neighbours are
 * usually in cache. Every cell holds its own copy of each of its vertices;
 * copy i of the cell at position m is numbered vbase[m] + i.
 *
 * Copies of one Voronoi vertex are identified with a union-find:
 *  - inside a cell, the ends of edges shorter than the tolerance;
 *  - across two kept cells, the vertices of their common face: the two
 *    copies of the face are normally the same cycle in opposite directions,
 *    checked in one pass; otherwise (degenerate faces) every vertex is
 *    matched to the nearest copy on the other side, both ways;
 *  - copies on faces against a non-kept cell or the box, by position (a
 *    hash grid), for kept cells that meet only along an edge or at a vertex;
 *  - then, for the faces whose two copies were matched vertex by vertex and
 *    still differ: copies of one vertex the tolerance kept apart are united,
 *    and a vertex of one copy lying on an edge of the other is inserted
 *    into that edge in every face that has it (see T-junctions below).
 * The component's smallest copy index is its representative, so the result
 * does not depend on the order of the unions: they run on threads, linking
 * roots with compare-and-swap (a root is only ever linked to a smaller
 * index).
 *
 * Every later step is a pass over the cells, on threads, writing to places
 * fixed by prefix sums over the cells, so the output is the same byte for
 * byte whatever the thread count:
 *  - a face between two kept cells is written once, by its owner (the
 *    lower cell index, i.e. the lower seed index), from the owner's copy,
 *    or from the neighbour's copy reversed when the owner's degenerated;
 *    interior faces come out sorted by (owner, neighbour), boundary faces
 *    by (owner, face);
 *  - points are the representatives used by some face, numbered in copy
 *    order (spatially coherent);
 *  - a cell lists its faces in increasing face index;
 *  - the geometry is vc_polymesh_compute_geometry's (the same routines,
 *    polymesh/face_geometry.h), in a pass over the faces once the
 *    stitching's own arrays are released (the peak memory is then the
 *    mesh's, not the mesh's plus the stitching's).
 *
 * The phase times go to the logger at VC_LOG_DEBUG. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE 1 /* madvise */
#endif
#include "cell_result.h"
#include "polymesh/face_geometry.h"
#include "util/union_find.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __linux__
#include <sys/mman.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

/* ---------------------------------------------------------------------
 * Memory. The large arrays are touched once, in parallel passes; on Linux
 * they are backed by transparent huge pages when the system allows it,
 * which makes first touches several times cheaper. They are freed with
 * free(), like any other allocation (the mesh's arrays are among them). */

#define BIG_ARRAY(n, type) ((type *)vc_big_alloc((size_t)(n) * sizeof(type)))
/* The same on pages the cells' storage has released (page_bank.h). */
#define BANK_ARRAY(n, type) ((type *)vc_page_bank_alloc(&bank, (size_t)(n) * sizeof(type)))

/* The stitching's own large arrays are mapped by the engine, so that
 * their pages can go to the bank when they are released: *bytes receives
 * the size mapped. */
static void *mapped_array(size_t n, size_t elem, size_t *bytes)
{
    const size_t want = n * elem > 0 ? n * elem : 1;
    *bytes = (want + VC_HUGE_PAGE - 1) & ~(VC_HUGE_PAGE - 1);
    return vc_pages_map(*bytes);
}

/* Releases a mapped_array (or NULL) to bank (NULL: to the system). */
static void mapped_release(void *p, size_t bytes, vc_page_bank *bank)
{
    if (!p)
        return;
    if (bank)
        (void)vc_page_bank_add(bank, p, bytes);
    else
        vc_pages_unmap(p, bytes);
}

static double wall_time(void)
{
#ifdef _OPENMP
    return omp_get_wtime();
#else
    return 0;
#endif
}

/* CPU time of the process (for the timing lines: steadier than wall time
 * on a shared machine). */
static double cpu_time(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return 0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Resident memory in MiB (for the timing lines; 0 where unknown). */
static double rss_mib(void)
{
    double mib = 0;
#ifdef __linux__
    FILE *f = fopen("/proc/self/statm", "r");
    if (f) {
        long size = 0, resident = 0;
        if (fscanf(f, "%ld %ld", &size, &resident) == 2)
            mib = (double)resident * 4096.0 / (1024.0 * 1024.0);
        fclose(f);
    }
#endif
    return mib;
}

/* ---------------------------------------------------------------------
 * Union-find over the vertex copies: util/union_find.h's concurrent
 * flavour (vc_uf_find_atomic, vc_uf_unite_atomic), whose roots are the
 * components' smallest copy indices. */

/* An entry of the union-find: a copy index (its parent) or, once the used
 * roots are numbered, -(point id + 1). 32 bits (the copies are counted
 * below 2^31, checked) halve the largest array of the stitching. */
typedef int32_t copy_id;

static inline double dist2(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* A cell, at its position m in the spatial order. */
typedef struct cell_hdr {
    const double *v;
    const int32_t *plane;
    const uint16_t *face_start;
    const uint16_t *fv;
    int64_t vbase;  /* copy index of its vertex 0 */
    int64_t fbase;  /* index of its face 0 among all cells' faces */
    int64_t k;      /* cell index */
    int64_t seed;   /* seed index (increasing with k) */
    double tol;     /* merge tolerance */
    int nv, nf;
} cell_hdr;

/* Per cell, at its position: counts, then (after the prefix sums) the
 * places of its faces in the output. */
typedef struct cell_acc {
    int64_t n_int, n_bnd;   /* faces it owns; then their first index */
    int64_t fv_int, fv_bnd; /* their vertex count; then their first offset */
    int64_t n_nb;           /* faces it lists but does not own (atomic) */
    int64_t nb_fill;        /* of those, listed so far (atomic) */
    int64_t cell_off;       /* its first entry in cell_faces */
    int64_t first_point;
    int32_t own_int, own_bnd; /* after the prefix sums: faces it owns */
} cell_acc;

typedef struct assembly {
    const cell_hdr *h; /* n cells, in spatial order */
    int64_t n;
    int32_t *nbr;      /* per face: position of the kept cell beyond, or -1 */
    int16_t *twin;     /* per face: the same face in that cell, or -1 (a cell has
                          fewer than 2^15 faces: at most 65535 face vertices) */
    copy_id *parent;   /* union-find over the copies; later, point ids */
    unsigned char *slow; /* per face: its twin was matched vertex by vertex, not as one cycle */
    /* per face, once the splits are known (the same bytes as slow): for a
     * face its cell writes from its own copy, that copy's output length and
     * whether it is simple (LEN_*); 0 when the writing works it out */
    unsigned char *len_code;
    cell_acc *acc;
    const struct split_table *sp; /* points inserted into edges (T-junctions) */
    int threads;       /* for every parallel region (>= 1) */
} assembly;

/* Face of cell c made by seed s, or -1. */
static int face_with_plane(const cell_hdr *c, int64_t s)
{
    for (int f = 0; f < c->nf; f++)
        if (c->plane[f] == s)
            return f;
    return -1;
}

/* Unites every vertex of face fa of cell a with the nearest vertex of face
 * fb of cell b (all of b's vertices when fb < 0 or none is close), when
 * within tol. */
static void match_nearest(copy_id *parent, const cell_hdr *ca, int fa, const cell_hdr *cb,
                          int fb, double tol2)
{
    for (int i = ca->face_start[fa]; i < ca->face_start[fa + 1]; i++) {
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
            vc_uf_unite_atomic(parent, ca->vbase + va, cb->vbase + vb);
    }
}

/* The identity of vertex v of cell c: its seed and the planes (seeds or
 * walls) of the three faces that meet there, sorted. Returns 0 when v is
 * not on exactly three faces. */
static int vertex_key(const cell_hdr *c, int v, int64_t key[4])
{
    int n = 0;
    key[n++] = c->seed;
    for (int f = 0; f < c->nf; f++)
        for (int i = c->face_start[f]; i < c->face_start[f + 1]; i++)
            if (c->fv[i] == v) {
                if (n == 4)
                    return 0;
                key[n++] = c->plane[f];
                break;
            }
    if (n != 4)
        return 0;
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && key[j - 1] > key[j]; j--) {
            const int64_t t = key[j];
            key[j] = key[j - 1];
            key[j - 1] = t;
        }
    return 1;
}

/* Unites the vertices of face fa of cell a and face fb of cell b that are
 * the same corner of the same four cells (or walls): the same point,
 * however far apart rounding put the two copies. Where four seeds are
 * nearly co-circular, the corner they share lies on their (nearly
 * degree-4) edge at a place so ill-conditioned that two cells compute it
 * up to 1e-4 of the cell size apart, along that edge (which lies in the
 * corner's three face planes: uniting the copies keeps the faces flat).
 * Where the four are co-circular to rounding, the "corner" is an artifact
 * of the rounding, anywhere on the edge, and copies in different cells are
 * not one point: measured, those are more than the cell size apart, and
 * true corners within 1e-4 of it (bracket, fertility); copies farther
 * apart than KEY_MATCH_REACH merge tolerances are left alone. */
#define KEY_MATCH_REACH 1e5
/* Longest face whose corners are matched by key (as CYCLE_BUF below). */
#define KEY_FACE_MAX 512

static void match_keys(copy_id *parent, const cell_hdr *ca, int fa, const cell_hdr *cb, int fb)
{
    const double reach = KEY_MATCH_REACH * (ca->tol > cb->tol ? ca->tol : cb->tol);
    const int b0 = cb->face_start[fb], nb = cb->face_start[fb + 1] - b0;
    if (nb > KEY_FACE_MAX)
        return;
    int64_t kb[KEY_FACE_MAX][4];
    int has_kb[KEY_FACE_MAX];
    for (int j = 0; j < nb; j++)
        has_kb[j] = vertex_key(cb, cb->fv[b0 + j], kb[j]);
    for (int i = ca->face_start[fa]; i < ca->face_start[fa + 1]; i++) {
        int64_t ka[4];
        if (!vertex_key(ca, ca->fv[i], ka))
            continue;
        for (int jj = 0; jj < nb; jj++) {
            const int j = b0 + jj;
            if (has_kb[jj] && ka[0] == kb[jj][0] && ka[1] == kb[jj][1] && ka[2] == kb[jj][2] &&
                ka[3] == kb[jj][3] &&
                dist2(ca->v + 3 * ca->fv[i], cb->v + 3 * cb->fv[j]) <= reach * reach) {
                vc_uf_unite_atomic(parent, ca->vbase + ca->fv[i], cb->vbase + cb->fv[j]);
                break;
            }
        }
    }
}

/* A face of cell c that its neighbour does not have, all within
 * TINY_FACE merge tolerances (the larger of the two cells'): the
 * neighbour judged its plane to touch the cell at one point. Its vertices
 * are united, so that the face is gone on this side too. Nearly
 * co-spherical seeds (within a few 1e-9 of the cell size) make such faces
 * where two cells resolve a cluster of vertices differently. */
#define TINY_FACE 100.0

static void collapse_if_tiny(copy_id *parent, const cell_hdr *c, int f, double tol)
{
    const int s0 = c->face_start[f], s1 = c->face_start[f + 1];
    const double *x0 = c->v + 3 * c->fv[s0];
    const double reach2 = (0.5 * TINY_FACE * tol) * (0.5 * TINY_FACE * tol);
    for (int i = s0 + 1; i < s1; i++)
        if (dist2(x0, c->v + 3 * c->fv[i]) > reach2)
            return;
    for (int i = s0 + 1; i < s1; i++)
        vc_uf_unite_atomic(parent, c->vbase + c->fv[s0], c->vbase + c->fv[i]);
}

/* Identifies the copies on face fa of cell a and face fb (>= 0) of cell b,
 * the same face seen from both sides. In general position both are the
 * same cycle in opposite directions: one pass checks it and unites the
 * pairs (returns 1). Otherwise, the same corners (match_keys), then
 * nearest matches both ways (returns 0): the
 * two copies may then still differ after merging (see T-junctions below). */
static int match_face(copy_id *parent, const cell_hdr *ca, int fa, const cell_hdr *cb, int fb,
                       double tol2)
{
    const uint16_t *pa = ca->fv + ca->face_start[fa], *pb = cb->fv + cb->face_start[fb];
    const int n = ca->face_start[fa + 1] - ca->face_start[fa];
    if (n == cb->face_start[fb + 1] - cb->face_start[fb] && n >= 3) {
        const double *x0 = ca->v + 3 * pa[0];
        int j0 = -1;
        double best = tol2;
        for (int j = 0; j < n; j++) {
            double d = dist2(x0, cb->v + 3 * pb[j]);
            if (d <= best) {
                best = d;
                j0 = j;
            }
        }
        int ok = j0 >= 0;
        for (int i = 1, j = j0; i < n && ok; i++) {
            j = j == 0 ? n - 1 : j - 1;
            ok = dist2(ca->v + 3 * pa[i], cb->v + 3 * pb[j]) <= tol2;
        }
        if (ok) {
            for (int i = 0, j = j0; i < n; i++, j = j == 0 ? n - 1 : j - 1)
                vc_uf_unite_atomic(parent, ca->vbase + pa[i], cb->vbase + pb[j]);
            return 1;
        }
    }
    match_keys(parent, ca, fa, cb, fb);
    match_nearest(parent, ca, fa, cb, fb, tol2);
    match_nearest(parent, cb, fb, ca, fa, tol2);
    return 0;
}

/* The matching reads the data of each cell's neighbours later in the
 * spatial order, often for the first time (from memory): they are
 * prefetched a few cells ahead, the headers first. */
#define PREFETCH_AHEAD 4
/* The same for the faces' geometry. */
#define GEOMETRY_AHEAD 4

static void prefetch_headers(const assembly *as, int64_t m)
{
    const cell_hdr *c = &as->h[m];
    for (int f = 0; f < c->nf; f++) {
        int32_t om = as->nbr[c->fbase + f];
        if (om > m) {
            __builtin_prefetch(&as->h[om]);
            __builtin_prefetch((const char *)&as->h[om] + sizeof(cell_hdr) - 1);
        }
    }
}

static void prefetch_lines(const void *p, size_t bytes)
{
    const char *a = (const char *)((uintptr_t)p & ~(uintptr_t)63), *e = (const char *)p + bytes;
    for (; a < e; a += 64)
        __builtin_prefetch(a);
}

static void prefetch_cells(const assembly *as, int64_t m)
{
    const cell_hdr *c = &as->h[m];
    for (int f = 0; f < c->nf; f++) {
        int32_t om = as->nbr[c->fbase + f];
        if (om > m) {
            const cell_hdr *d = &as->h[om];
            prefetch_lines(d->plane, (size_t)d->nf * sizeof(int32_t));
            prefetch_lines(d->face_start, (size_t)(d->nf + 1) * sizeof(int));
            prefetch_lines(d->v, (size_t)d->nv * 3 * sizeof(double));
            prefetch_lines(as->parent + d->vbase, (size_t)d->nv * sizeof(copy_id));
        }
    }
}

/* ---------------------------------------------------------------------
 * Kept cells that meet only along an edge or at a vertex (every cell
 * around it in between is not kept) share no face, so their copies of the
 * common vertices are matched by position: the copies on faces against a
 * non-kept cell or the box go into a hash grid of cubes of side 4 h (h: the
 * largest merge tolerance); each copy looks at the 2 x 2 x 2 cubes nearest
 * to it, which hold every point within 2 h of it. */

typedef struct loose_copy {
    int64_t copy; /* -1: unused entry */
    const double *x;
    double tol;
    int64_t key[3];
} loose_copy;

static inline uint64_t key_hash(const int64_t k[3])
{
    uint64_t h = (uint64_t)k[0] * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)k[1] * 0xC2B2AE3D27D4EB4Full + (h >> 29);
    h ^= (uint64_t)k[2] * 0x165667B19E3779F9ull + (h >> 31);
    return h ^ (h >> 32);
}

/* n_outer[m]: number of copies (with repeats) of cell m on its outer
 * faces. Returns -1 when out of memory. */
static int match_loose_copies(const assembly *as, const int64_t *n_outer, int max_nv)
{
    const int64_t n_cells = as->n;
    int64_t *start = BIG_ARRAY(n_cells + 1, int64_t);
    if (!start)
        return -1;
    start[0] = 0;
    double h = 0;
    for (int64_t m = 0; m < n_cells; m++) {
        start[m + 1] = start[m] + n_outer[m];
        if (n_outer[m] > 0 && as->h[m].tol > h)
            h = as->h[m].tol;
    }
    const int64_t n = start[n_cells];
    if (n == 0 || !(h > 0)) {
        free(start);
        return 0;
    }
    const double side = 4 * h;
    int64_t n_slots = 1;
    while (n_slots < 2 * n)
        n_slots *= 2;
    loose_copy *e = BIG_ARRAY(n, loose_copy);
    int64_t *head = BIG_ARRAY(n_slots, int64_t);
    int64_t *next = BIG_ARRAY(n, int64_t);
    int failed = 0;
    if (!e || !head || !next) {
        free(start);
        free(e);
        free(head);
        free(next);
        return -1;
    }
#pragma omp parallel num_threads(as->threads)
    {
        unsigned char *seen = calloc((size_t)max_nv + 1, 1);
        if (!seen) {
#pragma omp atomic write
            failed = 1;
        }
#pragma omp for schedule(static)
        for (int64_t i = 0; i < n_slots; i++)
            head[i] = -1;
        /* Entries in copy order, inserted into the grid's chains. The
         * chains' order varies with the threads, the unions found do not. */
#pragma omp for schedule(dynamic, 256)
        for (int64_t m = 0; m < n_cells; m++) {
            const cell_hdr *c = &as->h[m];
            if (!seen || n_outer[m] == 0)
                continue;
            int64_t w = start[m];
            for (int f = 0; f < c->nf; f++) {
                if (as->nbr[c->fbase + f] >= 0)
                    continue;
                for (int i = c->face_start[f]; i < c->face_start[f + 1]; i++) {
                    int v = c->fv[i];
                    if (seen[v])
                        continue;
                    seen[v] = 1;
                    loose_copy *q = &e[w];
                    q->copy = c->vbase + v;
                    q->x = c->v + 3 * v;
                    q->tol = c->tol;
                    for (int d = 0; d < 3; d++)
                        q->key[d] = (int64_t)floor(q->x[d] / side);
                    int64_t slot = (int64_t)(key_hash(q->key) & (uint64_t)(n_slots - 1));
                    int64_t old = __atomic_load_n(&head[slot], __ATOMIC_RELAXED);
                    do
                        next[w] = old;
                    while (!__atomic_compare_exchange_n(&head[slot], &old, w, 1, __ATOMIC_RELAXED,
                                                        __ATOMIC_RELAXED));
                    w++;
                }
            }
            for (int f = 0; f < c->nf; f++)
                for (int i = c->face_start[f]; i < c->face_start[f + 1]; i++)
                    seen[c->fv[i]] = 0;
            for (; w < start[m + 1]; w++) /* repeated copies */
                e[w] = (loose_copy){-1, NULL, 0, {0, 0, 0}};
        }
        free(seen);
        if (!failed) {
            /* head[] and next[] are complete after the loop's barrier. */
#pragma omp for schedule(dynamic, 1024)
            for (int64_t i = 0; i < n; i++) {
                const loose_copy *q = &e[i];
                if (q->copy < 0)
                    continue;
                int64_t step[3];
                for (int d = 0; d < 3; d++)
                    step[d] = q->x[d] / side - (double)q->key[d] < 0.5 ? -1 : 1;
                for (int b = 0; b < 8; b++) {
                    int64_t key[3] = {q->key[0] + ((b & 1) ? step[0] : 0),
                                      q->key[1] + ((b & 2) ? step[1] : 0),
                                      q->key[2] + ((b & 4) ? step[2] : 0)};
                    int64_t slot = (int64_t)(key_hash(key) & (uint64_t)(n_slots - 1));
                    for (int64_t j = head[slot]; j >= 0; j = next[j]) {
                        const loose_copy *r = &e[j];
                        if (r->copy <= q->copy || r->key[0] != key[0] || r->key[1] != key[1] ||
                            r->key[2] != key[2])
                            continue;
                        double tol = q->tol > r->tol ? q->tol : r->tol;
                        if (dist2(q->x, r->x) <= tol * tol)
                            vc_uf_unite_atomic(as->parent, q->copy, r->copy);
                    }
                }
            }
        }
    }
    free(start);
    free(e);
    free(head);
    free(next);
    return failed ? -1 : 0;
}

/* ---------------------------------------------------------------------
 * Faces after merging. The cycle of a face is the sequence of its copies'
 * representatives with repeated consecutive ones (and a last one equal to
 * the first) removed; fewer than 3 left: the face is gone. */

/* The root of a copy, from parent[] holding roots, before or after the used
 * roots are numbered (a numbered root holds a negative value). */
static inline int64_t root_of(const copy_id *parent, int64_t copy)
{
    int64_t p = parent[copy];
    return p < 0 ? copy : p;
}

/* Cycle length of face f of cell c (parent[] holds roots, possibly
 * numbered: the comparisons are between roots, so the length is the same
 * before and after the numbering). *spike is set when a root may come
 * back two steps later (x, a, x: the face folds back on itself, which
 * merging makes of a face a few merge tolerances wide), wrap-around
 * included; it may also be set for other repeats. */
static int cycle_len(const copy_id *parent, const cell_hdr *c, int f, int *spike)
{
    const int64_t base = c->vbase;
    const int s0 = c->face_start[f], s1 = c->face_start[f + 1];
    int64_t first = root_of(parent, base + c->fv[s0]), last = first, before = -1, before2 = -1,
            second = -1;
    int n = 1, folds = 0;
    for (int i = s0 + 1; i < s1; i++) {
        int64_t r = root_of(parent, base + c->fv[i]);
        if (r != last) {
            folds |= r == before;
            if (n == 1)
                second = r;
            n++;
            before2 = before;
            before = last;
            last = r;
        }
    }
    /* Around the end: the cycle is r0 .. r(n-1), or r0 .. r(n-2) when the
     * last root is the first again; its last two roots against its first
     * two. (Testing second == before on a cycle that does not close with
     * its first root flagged every triangle, where before is second.) */
    if (n >= 3)
        folds |= last == first ? second == before || first == before2
                               : second == last || first == before;
    *spike = folds;
    if (n > 1 && last == first)
        n--;
    return n >= 3 ? n : 0;
}

/* Takes the spikes out of a cycle of roots in place (x, a, x becomes x,
 * around the end too), and consecutive repeats. A spike's two edges, a -> x
 * and x -> a, are each other's reverse in the same face: without them the
 * face's cell is still closed. Returns the new length. */
static int remove_spikes(int64_t *r, int n)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        const int64_t x = r[i];
        if (m > 0 && r[m - 1] == x)
            continue;
        if (m > 1 && r[m - 2] == x) {
            m--;
            continue;
        }
        r[m++] = x;
    }
    for (;;) {
        if (m > 1 && r[m - 1] == r[0])
            m--;
        else if (m > 2 && r[m - 2] == r[0])
            m--;
        else if (m > 2 && r[m - 1] == r[1]) {
            memmove(r, r + 1, (size_t)(m - 1) * sizeof *r);
            m--;
        } else
            break;
    }
    return m;
}

/* Marks the roots of the cycle of face f of cell c as used. */
static void mark_used(const copy_id *parent, const cell_hdr *c, int f, unsigned char *used)
{
    const copy_id *par = parent + c->vbase;
    for (int i = c->face_start[f]; i < c->face_start[f + 1]; i++)
        __atomic_store_n(&used[par[c->fv[i]]], 1, __ATOMIC_RELAXED);
}

/* Point id of a copy once the used roots are numbered: a used root r holds
 * -(id + 1) in parent[r], any other copy its root. */
static inline int64_t point_of(const copy_id *parent, int64_t copy)
{
    int64_t p = parent[copy];
    return p < 0 ? -p - 1 : -parent[p] - 1;
}

/* Writes the point ids of the cycle of face f of cell c (len entries,
 * known), reversed when rev. */
static void write_cycle(const copy_id *parent, const cell_hdr *c, int f, int len, int rev,
                        int64_t *dst)
{
    const int s0 = c->face_start[f], s1 = c->face_start[f + 1];
    int n = 0;
    int64_t last = -1;
    for (int i = s0; i < s1 && n < len; i++) {
        int64_t p = point_of(parent, c->vbase + c->fv[i]);
        if (n == 0 || p != last) {
            dst[rev ? len - 1 - n : n] = p;
            n++;
            last = p;
        }
    }
}

/* ---------------------------------------------------------------------
 * T-junctions. Near-degenerate seeds (co-spherical only to about 1e-9, as
 * VoroCrust's are: each seed is the meeting point of three spheres,
 * computed in floating point) have true Voronoi edges a little longer than
 * the merge tolerance, which two cells sharing a face do not always both
 * resolve. Cutting a cell is exact up to the clipping tolerance on the
 * distance of a vertex to a plane, but a vertex made where a plane crosses
 * an edge it is nearly parallel to can land anywhere along that edge: one
 * cell's copy of the shared face then has a vertex u that the other copy
 * lacks, either near one of its vertices (farther than the merge
 * tolerance of one of the two cells: the tolerances are relative to each
 * cell's own size) or anywhere along one of its edges v-w. No merge
 * tolerance absorbs the second kind, and either kind leaves a cell open
 * (the shared face is written from one copy only).
 *
 * So, for each face whose two copies were matched vertex by vertex (not as
 * one cycle) and still differ after merging:
 *  - u within 100 merge tolerances of a vertex of the other copy is united
 *    with the nearest one, and the faces are compared again (rounds, until
 *    no union is made);
 *  - then u within that distance of an edge v-w of the other copy, strictly
 *    between its ends, is inserted into the edge v-w of every face of every
 *    cell that has that edge (the edge is split). Each cell's own faces
 *    form a closed surface, and both faces of a cell along an edge get the
 *    same points in the same order, so it stays closed, and the two copies
 *    of the shared face become the same cycle. No tolerance decides which
 *    faces are changed (only which points lie on which edge): the result
 *    is exact. General-position input has no such faces. */

typedef struct edge_split {
    int64_t lo, hi; /* the edge's end roots, lo < hi */
    double t;       /* where the point lies, from lo (0 < t < 1) */
    int64_t u;      /* the point's root */
} edge_split;

typedef struct split_table {
    edge_split *s; /* sorted by (lo, hi, t) */
    int64_t n, cap;
} split_table;

/* Recursion depth of the insertion (a point inserted into an edge that was
 * itself made by a split). */
#define SPLIT_DEPTH 4

static int cmp_split(const void *a, const void *b)
{
    const edge_split *x = a, *y = b;
    if (x->lo != y->lo)
        return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi)
        return x->hi < y->hi ? -1 : 1;
    if (x->t != y->t)
        return x->t < y->t ? -1 : 1;
    return (x->u > y->u) - (x->u < y->u);
}

/* What a walk over a face's output cycle does with each point: counts it,
 * marks its root used (used != NULL) and writes its point id (dst !=
 * NULL). */
typedef struct emitter {
    const copy_id *parent;
    unsigned char *used;
    int64_t *dst;
    int n;
    int64_t *roots; /* when not NULL: the roots, up to CYCLE_BUF of them */
} emitter;

/* Longest output cycle whose spikes are taken out (longer ones are
 * written as they are). */
#define CYCLE_BUF 512

static inline void emit(emitter *e, int64_t r)
{
    if (e->used)
        __atomic_store_n(&e->used[r], 1, __ATOMIC_RELAXED);
    if (e->dst)
        e->dst[e->n] = -e->parent[r] - 1;
    if (e->roots && e->n < CYCLE_BUF)
        e->roots[e->n] = r;
    e->n++;
}

/* Emits the points inserted into the edge a -> b (not a and b), a part of
 * the face's edge ta -> tb: a point inserted into a part is never one of
 * the ends of the whole edge (two copies of one vertex, each found on an
 * edge ending at the other). The result depends on the edge alone, not on
 * the face: both faces of a cell along an edge get the same points. */
static void expand_edge(const split_table *sp, emitter *e, int64_t a, int64_t b, int64_t ta,
                        int64_t tb, int depth)
{
    const int64_t lo = a < b ? a : b, hi = a < b ? b : a;
    int64_t i0 = 0, i1 = sp->n;
    while (i0 < i1) { /* first entry >= (lo, hi) */
        int64_t mid = i0 + (i1 - i0) / 2;
        const edge_split *q = &sp->s[mid];
        if (q->lo < lo || (q->lo == lo && q->hi < hi))
            i0 = mid + 1;
        else
            i1 = mid;
    }
    i1 = i0;
    while (i1 < sp->n && sp->s[i1].lo == lo && sp->s[i1].hi == hi)
        i1++;
    if (i0 == i1)
        return;
    int64_t prev = a;
    for (int64_t k = 0; k < i1 - i0; k++) {
        const int64_t u = sp->s[a == lo ? i0 + k : i1 - 1 - k].u;
        if (u == ta || u == tb)
            continue;
        if (depth + 1 < SPLIT_DEPTH)
            expand_edge(sp, e, prev, u, ta, tb, depth + 1);
        emit(e, u);
        prev = u;
    }
    if (depth + 1 < SPLIT_DEPTH)
        expand_edge(sp, e, prev, b, ta, tb, depth + 1);
}

/* Walks the output cycle of face f of cell c (whose cycle_len is >= 3): its
 * roots, without repeats, with the split points inserted. Returns its
 * length. */
static int walk_face(const split_table *sp, emitter *e, const cell_hdr *c, int f)
{
    const int64_t base = c->vbase;
    const int s0 = c->face_start[f];
    int s1 = c->face_start[f + 1];
    const int64_t first = root_of(e->parent, base + c->fv[s0]);
    while (s1 - 1 > s0 && root_of(e->parent, base + c->fv[s1 - 1]) == first)
        s1--;
    int64_t last = first;
    emit(e, first);
    for (int i = s0 + 1; i < s1; i++) {
        const int64_t r = root_of(e->parent, base + c->fv[i]);
        if (r != last) {
            expand_edge(sp, e, last, r, last, r, 0);
            emit(e, r);
            last = r;
        }
    }
    expand_edge(sp, e, last, first, last, first, 0);
    return e->n;
}

/* The output cycle of face f of cell c as roots in buf (CYCLE_BUF
 * entries), with its spikes taken out. Returns its length (0: the face is
 * gone), or -1 when it does not fit. */
static int face_cycle(const split_table *sp, const copy_id *parent, const cell_hdr *c, int f,
                      int64_t *buf)
{
    emitter e = {parent, NULL, NULL, 0, buf};
    walk_face(sp, &e, c, f);
    if (e.n > CYCLE_BUF)
        return -1;
    const int n = remove_spikes(buf, e.n);
    return n >= 3 ? n : 0;
}

/* Output cycle length of face f of cell c (0: gone). *simple (if not
 * NULL) is set when that cycle is the copies' roots as they come (no split
 * point, no spike): the marking and the writing then take it as it is. */
static int face_len(const split_table *sp, const copy_id *parent, const cell_hdr *c, int f,
                    int *simple)
{
    int spike;
    int len = cycle_len(parent, c, f, &spike);
    if (simple)
        *simple = !spike && sp->n == 0;
    if (len > 0 && (spike || sp->n > 0)) {
        int64_t buf[CYCLE_BUF];
        int n = face_cycle(sp, parent, c, f, buf);
        if (n >= 0)
            return n;
        emitter e = {parent, NULL, NULL, 0, NULL};
        len = walk_face(sp, &e, c, f);
    }
    return len;
}

/* Output cycle length of face f of cell c (0: gone), whose roots are
 * marked used when it is not gone. *simple (if not NULL): as face_len's. */
static int face_len_mark(const split_table *sp, const copy_id *parent, const cell_hdr *c, int f,
                         unsigned char *used, int *simple_out)
{
    int simple;
    const int len = face_len(sp, parent, c, f, &simple);
    if (simple_out)
        *simple_out = simple;
    if (len == 0)
        return 0;
    if (simple) {
        mark_used(parent, c, f, used);
        return len;
    }
    int64_t buf[CYCLE_BUF];
    int n = face_cycle(sp, parent, c, f, buf);
    if (n >= 0) {
        for (int i = 0; i < n; i++)
            __atomic_store_n(&used[buf[i]], 1, __ATOMIC_RELAXED);
        return len;
    }
    emitter e = {parent, used, NULL, 0, NULL};
    walk_face(sp, &e, c, f);
    return len;
}

/* Writes the point ids of the output cycle of face f of cell c (len
 * entries, known), reversed when rev. simple: face_len's flag, or -1 when
 * not known. */
static void face_write(const split_table *sp, const copy_id *parent, const cell_hdr *c, int f,
                       int len, int rev, int simple, int64_t *dst)
{
    if (simple < 0) {
        int spike;
        cycle_len(parent, c, f, &spike);
        simple = !spike && sp->n == 0;
    }
    if (simple) {
        write_cycle(parent, c, f, len, rev, dst);
        return;
    }
    int64_t buf[CYCLE_BUF];
    int n = face_cycle(sp, parent, c, f, buf);
    if (n >= 0) {
        for (int i = 0; i < n && i < len; i++)
            dst[rev ? len - 1 - i : i] = -parent[buf[i]] - 1;
        return;
    }
    emitter e = {parent, NULL, dst, 0, NULL};
    walk_face(sp, &e, c, f);
    if (rev)
        for (int i = 0, j = len - 1; i < j; i++, j--) {
            int64_t x = dst[i];
            dst[i] = dst[j];
            dst[j] = x;
        }
}

/* The cell whose copies include copy x. */
static const cell_hdr *cell_of_copy(const assembly *as, int64_t x)
{
    int64_t lo = 0, hi = as->n - 1;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo + 1) / 2;
        if (as->h[mid].vbase <= x)
            lo = mid;
        else
            hi = mid - 1;
    }
    return &as->h[lo];
}

static const double *copy_point(const assembly *as, int64_t x)
{
    const cell_hdr *c = cell_of_copy(as, x);
    return c->v + 3 * (x - c->vbase);
}

/* The distinct roots of face f of cell c into *buf (grown as needed);
 * returns their number in cycle order (consecutive repeats dropped), or -1
 * when out of memory. */
static int face_roots(const copy_id *parent, const cell_hdr *c, int f, int64_t **buf, int *cap)
{
    const int s0 = c->face_start[f], s1 = c->face_start[f + 1];
    if (*cap < s1 - s0) {
        int64_t *b = realloc(*buf, (size_t)(s1 - s0) * sizeof(int64_t));
        if (!b)
            return -1;
        *buf = b;
        *cap = s1 - s0;
    }
    int n = 0;
    for (int i = s0; i < s1; i++) {
        int64_t r = root_of(parent, c->vbase + c->fv[i]);
        if (n == 0 || r != (*buf)[n - 1])
            (*buf)[n++] = r;
    }
    while (n > 1 && (*buf)[n - 1] == (*buf)[0])
        n--;
    return n;
}

static int add_split(split_table *sp, edge_split q)
{
    if (sp->n == sp->cap) {
        int64_t cap = sp->cap ? 2 * sp->cap : 64;
        edge_split *s = realloc(sp->s, (size_t)cap * sizeof *s);
        if (!s)
            return -1;
        sp->s = s;
        sp->cap = cap;
    }
    sp->s[sp->n++] = q;
    return 0;
}

/* The roots of x[0..nx) missing from y[0..ny): one within max_dist of a
 * vertex of y is a copy of it that the merge tolerance of one of the cells
 * kept apart (the pair goes into snap, to be united); one within max_dist
 * of an edge of y, strictly between its ends, lies on it (into sp). */
/* Sorts the splits by (lo, hi, t) and drops repeats: the same point on the
 * same edge, found from several faces. */
static void sort_splits(split_table *sp)
{
    if (sp->n < 2)
        return;
    qsort(sp->s, (size_t)sp->n, sizeof *sp->s, cmp_split);
    int64_t w = 1;
    for (int64_t k = 1; k < sp->n; k++) {
        const edge_split *q = &sp->s[k];
        int dup = 0;
        for (int64_t j = w - 1; j >= 0 && sp->s[j].lo == q->lo && sp->s[j].hi == q->hi; j--)
            dup |= sp->s[j].u == q->u;
        if (!dup)
            sp->s[w++] = *q;
    }
    sp->n = w;
}

static int split_missing(const assembly *as, const int64_t *x, int nx, const int64_t *y, int ny,
                         double max_dist, split_table *sp, split_table *snap, int64_t *n_unplaced)
{
    const double max2 = max_dist * max_dist;
    for (int i = 0; i < nx; i++) {
        int found = 0;
        for (int j = 0; j < ny && !found; j++)
            found = x[i] == y[j];
        if (found)
            continue;
        const double *p = copy_point(as, x[i]);
        double best = max2;
        int64_t near = -1;
        for (int j = 0; j < ny; j++) {
            double d2 = dist2(p, copy_point(as, y[j]));
            if (d2 <= best) {
                best = d2;
                near = y[j];
            }
        }
        if (near >= 0) {
            if (add_split(snap, (edge_split){x[i], near, 0, -1}) != 0)
                return -1;
            continue;
        }
        best = max2;
        edge_split q = {-1, -1, 0, x[i]};
        for (int j = 0; j < ny && ny >= 2; j++) {
            const int64_t v = y[j], w = y[j + 1 < ny ? j + 1 : 0];
            const int64_t lo = v < w ? v : w, hi = v < w ? w : v;
            const double *a = copy_point(as, lo), *b = copy_point(as, hi);
            double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
            double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
            if (!(l2 > 0))
                continue;
            double t = (ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2]) / l2;
            if (!(t > 0 && t < 1))
                continue;
            double e[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
            double d2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            if (d2 <= best) {
                best = d2;
                q.lo = lo;
                q.hi = hi;
                q.t = t;
            }
        }
        if (q.lo < 0)
            (*n_unplaced)++;
        else if (add_split(sp, q) != 0)
            return -1;
    }
    return 0;
}

/* Finds the split points: the faces between two kept cells whose copies
 * were matched vertex by vertex and still differ after merging. Serial (such
 * faces are rare) and in cell order, then sorted: the table does not depend
 * on the threads. Returns -1 when out of memory. */
static int find_splits(const assembly *as, split_table *sp, split_table *snap,
                       int64_t *n_unplaced)
{
    int64_t *ra = NULL, *rb = NULL;
    int cap_a = 0, cap_b = 0, rc = 0;
    for (int64_t m = 0; m < as->n && rc == 0; m++) {
        const cell_hdr *c = &as->h[m];
        for (int f = 0; f < c->nf && rc == 0; f++) {
            const int64_t i = c->fbase + f;
            if (!as->slow[i] || as->nbr[i] <= m)
                continue;
            const cell_hdr *d = &as->h[as->nbr[i]];
            const int g = as->twin[i];
            int na = face_roots(as->parent, c, f, &ra, &cap_a);
            int nb = face_roots(as->parent, d, g, &rb, &cap_b);
            if (na < 0 || nb < 0) {
                rc = -1;
                break;
            }
            if (na < 3 && nb < 3)
                continue; /* gone on both sides */
            /* A vertex within this distance of an edge lies on it: far
             * above the rounding of the positions, far below any edge that
             * is not a T-junction. */
            double tol = c->tol > d->tol ? c->tol : d->tol;
            if (split_missing(as, ra, na, rb, nb, tol * 1e2, sp, snap, n_unplaced) != 0 ||
                split_missing(as, rb, nb, ra, na, tol * 1e2, sp, snap, n_unplaced) != 0)
                rc = -1;
        }
    }
    free(ra);
    free(rb);
    if (rc == 0)
        sort_splits(sp);
    return rc;
}

/* The points on an edge split the sub-edges between them too: a cell
 * whose own copy of the edge ends at one of those points (an artefact
 * corner of four co-circular seeds, placed by each cell somewhere else
 * along their edge) has an edge from the end to that point, which must get
 * the points lying between them. For each split edge lo - u_1 - ... - u_k -
 * hi, every sub-edge between two points of that chain that are not
 * neighbours in it gets the chain's points between them. */
static int add_subedge_splits(split_table *sp)
{
    const int64_t n0 = sp->n;
    for (int64_t i0 = 0; i0 < n0;) {
        int64_t i1 = i0;
        while (i1 < n0 && sp->s[i1].lo == sp->s[i0].lo && sp->s[i1].hi == sp->s[i0].hi)
            i1++;
        const int64_t k = i1 - i0; /* chain: lo, the k points by t, hi */
        for (int64_t a = 0; a <= k + 1; a++)
            for (int64_t b = a + 2; b <= k + 1; b++) {
                if (a == 0 && b == k + 1)
                    continue; /* the edge itself */
                const int64_t pa = a == 0 ? sp->s[i0].lo : sp->s[i0 + a - 1].u;
                const int64_t pb = b == k + 1 ? sp->s[i0].hi : sp->s[i0 + b - 1].u;
                const double ta = a == 0 ? 0.0 : sp->s[i0 + a - 1].t;
                const double tb = b == k + 1 ? 1.0 : sp->s[i0 + b - 1].t;
                for (int64_t m = a + 1; m < b; m++) {
                    const edge_split *q = &sp->s[i0 + m - 1];
                    const double t = (q->t - ta) / (tb - ta);
                    edge_split r = pa < pb ? (edge_split){pa, pb, t, q->u}
                                           : (edge_split){pb, pa, 1.0 - t, q->u};
                    if (add_split(sp, r) != 0)
                        return -1;
                }
            }
        i0 = i1;
    }
    sort_splits(sp);
    return 0;
}

/* A face between two kept cells known only to the higher one (the owner
 * has no face with the neighbour's seed: rounding). */
typedef struct orphan {
    int64_t owner_seed, neighbour_seed;
    int32_t owner, neighbour; /* positions */
    int src_face;             /* in the neighbour */
    int len;
} orphan;

static int cmp_orphan(const void *a, const void *b)
{
    const orphan *x = a, *y = b;
    if (x->owner_seed != y->owner_seed)
        return x->owner_seed < y->owner_seed ? -1 : 1;
    return (x->neighbour_seed > y->neighbour_seed) - (x->neighbour_seed < y->neighbour_seed);
}

/* The orphans owned by the cell at position m: a range of the sorted list. */
static const orphan *orphans_of(const orphan *o, int64_t n, int64_t seed, int64_t *count)
{
    int64_t lo = 0, hi = n;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (o[mid].owner_seed < seed)
            lo = mid + 1;
        else
            hi = mid;
    }
    int64_t e = lo;
    while (e < n && o[e].owner_seed == seed)
        e++;
    *count = e - lo;
    return o + lo;
}

/* The survival pass keeps each face's output length for the writing, in
 * a byte: the length (below LEN_UNKNOWN) and LEN_SIMPLE for face_len's
 * flag; 0 when not kept (the face is gone, written from the twin, or too
 * long), in which case the writing works it out again. */
#define LEN_SIMPLE 0x80
#define LEN_UNKNOWN 0x7f

static inline unsigned char len_code(int len, int simple)
{
    return len > 0 && len < LEN_UNKNOWN ? (unsigned char)(len | (simple ? LEN_SIMPLE : 0)) : 0;
}

/* face_len of face f of the cell at position m, from the byte the survival
 * pass kept when there is one. */
static int kept_face_len(const assembly *as, int64_t m, int f, int *simple)
{
    const cell_hdr *c = &as->h[m];
    const unsigned char code = as->len_code[c->fbase + f];
    if (!code)
        return face_len(as->sp, as->parent, c, f, simple);
    *simple = (code & LEN_SIMPLE) != 0;
    return code & LEN_UNKNOWN;
}

/* A face of the output, as enumerated by its owner. */
typedef struct out_face {
    int64_t other_seed;
    int32_t neighbour; /* position, or -1 */
    int32_t src;       /* position of the cell whose copy is written */
    int src_face;
    int len;
    int reversed;      /* the source copy is seen from the neighbour */
    int simple;        /* face_len's flag for the source copy, or -1 */
} out_face;

/* The faces owned by the cell at position m into buf: the interior ones
 * sorted by neighbour (o: the orphans it owns), then the boundary ones.
 * Returns the number of interior ones; *n_bnd gets the others. */
static int owned_faces(const assembly *as, int64_t m, const orphan *o, int64_t n_o,
                       out_face *buf, int *n_bnd)
{
    const cell_hdr *c = &as->h[m];
    const int64_t fb = c->fbase;
    int n = 0;
    for (int f = 0; f < c->nf; f++) {
        const int32_t om = as->nbr[fb + f];
        const int64_t t = c->plane[f];
        if (om < 0 || t < c->seed)
            continue;
        out_face r = {t, om, (int32_t)m, f, 0, 0, 0};
        r.len = kept_face_len(as, m, f, &r.simple);
        if (r.len <= 0) {
            int g = as->twin[fb + f];
            r.len = g >= 0 ? face_len(as->sp, as->parent, &as->h[om], g, &r.simple) : 0;
            if (r.len == 0)
                continue;
            r.src = om;
            r.src_face = g;
            r.reversed = 1;
        }
        buf[n++] = r;
    }
    for (int64_t i = 0; i < n_o; i++)
        buf[n++] = (out_face){o[i].neighbour_seed, o[i].neighbour, o[i].neighbour,
                              o[i].src_face, o[i].len, 1, -1};
    for (int i = 1; i < n; i++) { /* insertion sort by neighbour */
        out_face r = buf[i];
        int j = i;
        for (; j > 0 && buf[j - 1].other_seed > r.other_seed; j--)
            buf[j] = buf[j - 1];
        buf[j] = r;
    }
    int nb = 0;
    for (int f = 0; f < c->nf; f++)
        if (as->nbr[fb + f] < 0) {
            int simple;
            const int len = kept_face_len(as, m, f, &simple);
            if (len > 0)
                buf[n + nb++] = (out_face){c->plane[f], -1, (int32_t)m, f, len, 0, simple};
        }
    *n_bnd = nb;
    return n;
}

int vc_assemble_conforming(const vc_seeds *seeds, vc_cell_result **cells_owned,
                           const int64_t *kept_seed, int64_t n_kept, const int64_t *order,
                           vc_cell_store *store, double merge_tol, int threads,
                           const vc_logger *log, vc_polymesh *out, int64_t *n_degenerate,
                           vc_error *err)
{
    const vc_cell_result *cells = *cells_owned;
    split_table splits = {NULL, 0, 0};
    vc_page_bank bank = {NULL, NULL, 0, 0}; /* the cells' released pages */
    size_t h_bytes = 0, parent_bytes = 0, nbr_bytes = 0, twin_bytes = 0;
    int64_t n_unplaced = 0, n_gone = 0;
    *n_degenerate = 0;
    assembly as = {.n = n_kept, .sp = &splits, .threads = threads > 0 ? threads : 1};
    cell_hdr *h = NULL;
    int32_t *mpos = NULL;
    int64_t *n_outer = NULL;
    unsigned char *used = NULL;
    orphan *orphans = NULL;
    int64_t n_orphans = 0, cap_orphans = 0;
    int rc = 0, failed = 0, max_nv = 0, max_nf = 0;
    const int timing = vc_log_enabled(log, VC_LOG_DEBUG);
    double t0 = wall_time(), t_prev = t0, cpu_prev = cpu_time();
#define PHASE(name)                                                                          \
    do {                                                                                     \
        if (timing) {                                                                        \
            double t_now = wall_time(), cpu_now = cpu_time();                                \
            vc_log(log, VC_LOG_DEBUG, "  assembly: %-8s %.3f s  cpu %.3f s  rss %.0f MiB", name, \
                    t_now - t_prev, cpu_now - cpu_prev, rss_mib());                          \
            t_prev = t_now;                                                                  \
            cpu_prev = cpu_now;                                                              \
        }                                                                                    \
    } while (0)

    memset(out, 0, sizeof *out);
    if (n_kept > INT32_MAX - 1)
        return vc_error_set(err, VC_EPARAM, "%lld cells: at most %d can be assembled",
                            (long long)n_kept, INT32_MAX - 1);
    h = mapped_array((size_t)n_kept + 1, sizeof(cell_hdr), &h_bytes);
    mpos = BIG_ARRAY(seeds->n, int32_t);
    as.acc = BIG_ARRAY(n_kept + 1, cell_acc);
    n_outer = BIG_ARRAY(n_kept + 1, int64_t);
    if (!h || !mpos || !as.acc || !n_outer)
        goto nomem;
    as.h = h;

    /* Headers in spatial order, copy and face numbering. */
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t i = 0; i < seeds->n; i++)
        mpos[i] = -1;
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        const int64_t k = order ? order[m] : m;
        const vc_cell_result *c = &cells[m];
        h[m] = (cell_hdr){c->v, c->plane, c->face_start, c->fv, 0, 0, k, kept_seed[k],
                          merge_tol * c->scale, c->nv, c->nf};
        mpos[kept_seed[k]] = (int32_t)m;
        as.acc[m] = (cell_acc){0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    }
    int64_t n_copies = 0, n_faces_all = 0;
    for (int64_t m = 0; m < n_kept; m++) {
        h[m].vbase = n_copies;
        h[m].fbase = n_faces_all;
        n_copies += h[m].nv;
        n_faces_all += h[m].nf;
        if (h[m].nv > max_nv)
            max_nv = h[m].nv;
        if (h[m].nf > max_nf)
            max_nf = h[m].nf;
    }
    if (n_copies > INT32_MAX) {
        rc = vc_error_set(err, VC_EPARAM,
                          "%lld vertex copies in %lld cells: at most %d can be assembled",
                          (long long)n_copies, (long long)n_kept, INT32_MAX);
        goto done;
    }
    as.parent = mapped_array((size_t)n_copies, sizeof(copy_id), &parent_bytes);
    as.nbr = mapped_array((size_t)n_faces_all, sizeof(int32_t), &nbr_bytes);
    as.twin = mapped_array((size_t)n_faces_all, sizeof(int16_t), &twin_bytes);
    as.slow = BIG_ARRAY(n_faces_all, unsigned char);
    if (!as.parent || !as.nbr || !as.twin || !as.slow)
        goto nomem;
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        cell_hdr *c = &h[m];
        for (int v = 0; v < c->nv; v++)
            as.parent[c->vbase + v] = (copy_id)(c->vbase + v);
        for (int f = 0; f < c->nf; f++) {
            int64_t t = c->plane[f];
            as.nbr[c->fbase + f] = t >= 0 ? mpos[t] : -1;
            as.twin[c->fbase + f] = -1;
            as.slow[c->fbase + f] = 0;
        }
    }
    free(*cells_owned); /* everything needed is in the headers now */
    *cells_owned = NULL;
    cells = NULL;
    PHASE("setup");

    /* Identify copies: short edges inside a cell, then the faces shared
     * with cells later in the spatial order (whose twin faces are found
     * here, for both sides). */
#pragma omp parallel for schedule(dynamic, 64) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        const cell_hdr *c = &h[m];
        const int64_t fb = c->fbase;
        if (m + 2 * PREFETCH_AHEAD < n_kept)
            prefetch_headers(&as, m + 2 * PREFETCH_AHEAD);
        if (m + PREFETCH_AHEAD < n_kept)
            prefetch_cells(&as, m + PREFETCH_AHEAD);
        const double tol2 = c->tol * c->tol;
#ifndef EXP_NOSHORT
        for (int f = 0; f < c->nf; f++) {
            int s0 = c->face_start[f], s1 = c->face_start[f + 1];
            for (int i = s0, a = c->fv[s1 - 1]; i < s1; i++) {
                int b = c->fv[i];
                if (a < b && dist2(c->v + 3 * a, c->v + 3 * b) <= tol2)
                    vc_uf_unite_atomic(as.parent, c->vbase + a, c->vbase + b);
                a = b;
            }
        }
#endif
        int64_t outer = 0;
        for (int f = 0; f < c->nf; f++) {
            const int32_t om = as.nbr[fb + f];
            if (om < 0)
                outer += c->face_start[f + 1] - c->face_start[f];
            if (om <= m)
                continue;
            const cell_hdr *d = &h[om];
            int g = face_with_plane(d, c->seed);
            double tol = c->tol > d->tol ? c->tol : d->tol;
#ifdef EXP_NOMATCH
            if (g >= 0) { as.twin[fb + f] = (int16_t)g; as.twin[d->fbase + g] = (int16_t)f; } continue;
#endif
            if (g >= 0) {
                as.twin[fb + f] = (int16_t)g;
                as.twin[d->fbase + g] = (int16_t)f;
                as.slow[fb + f] = (unsigned char)!match_face(as.parent, c, f, d, g, tol * tol);
            } else {
                match_nearest(as.parent, c, f, d, -1, tol * tol);
            }
        }
        n_outer[m] = outer;
    }
    PHASE("faces");
    /* Faces the neighbour lacks (their twins are all known now). */
#pragma omp parallel for schedule(dynamic, 256) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        const cell_hdr *c = &h[m];
        for (int f = 0; f < c->nf; f++) {
            const int32_t om = as.nbr[c->fbase + f];
            if (om >= 0 && as.twin[c->fbase + f] < 0)
                collapse_if_tiny(as.parent, c, f, c->tol > h[om].tol ? c->tol : h[om].tol);
        }
    }
    if (match_loose_copies(&as, n_outer, max_nv) != 0)
        goto nomem;
    free(n_outer);
    n_outer = NULL;
    PHASE("loose");
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t i = 0; i < n_copies; i++)
        as.parent[i] = (copy_id)vc_uf_find_atomic(as.parent, i);
    PHASE("roots");
    /* Copies of a shared face that still differ: unite the copies of one
     * vertex that the tolerance kept apart, until none is left (each round
     * unites at least two roots), then split the edges. */
    for (int round = 0;; round++) {
        split_table snap = {NULL, 0, 0};
        splits.n = 0;
        n_unplaced = 0;
        if (find_splits(&as, &splits, &snap, &n_unplaced) != 0) {
            free(snap.s);
            goto nomem;
        }
        if (snap.n == 0 || round == 16) {
            free(snap.s);
            break;
        }
        for (int64_t i = 0; i < snap.n; i++)
            vc_uf_unite_atomic(as.parent, snap.s[i].lo, snap.s[i].hi);
        free(snap.s);
#pragma omp parallel for schedule(static) num_threads(as.threads)
        for (int64_t i = 0; i < n_copies; i++)
            as.parent[i] = (copy_id)vc_uf_find_atomic(as.parent, i);
    }
    if (add_subedge_splits(&splits) != 0)
        goto nomem;
    if (timing)
        vc_log(log, VC_LOG_DEBUG, "  assembly: %lld edge splits, %lld vertices on no edge",
                (long long)splits.n, (long long)n_unplaced);
    PHASE("splits");

    /* Which faces survive, who writes them, and the used roots. A face
     * between two kept cells is decided by its owner, except an orphan. */
    used = calloc((size_t)(n_copies > 0 ? n_copies : 1), 1);
    if (!used)
        goto nomem;
    as.len_code = as.slow; /* no longer needed as slow */
    as.slow = NULL;
#pragma omp parallel for schedule(dynamic, 64) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        const cell_hdr *c = &h[m];
        const int64_t fb = c->fbase;
        cell_acc *a = &as.acc[m];
        int64_t n_int = 0, n_bnd = 0, fv_int = 0, fv_bnd = 0;
        for (int f = 0; f < c->nf; f++) {
            const int32_t om = as.nbr[fb + f];
            const int64_t t = c->plane[f];
            int len, simple;
            unsigned char code = 0; /* kept for the writing */
            if (om < 0) {
                len = face_len_mark(&splits, as.parent, c, f, used, &simple);
                code = len_code(len, simple);
                if (len > 0) {
                    n_bnd++;
                    fv_bnd += len;
                } else {
                    __atomic_fetch_add(&n_gone, 1, __ATOMIC_RELAXED);
                }
            } else if (t > c->seed) {
                len = face_len_mark(&splits, as.parent, c, f, used, &simple);
                code = len_code(len, simple);
                int sl = len;
                if (len == 0 && as.twin[fb + f] >= 0)
                    sl = face_len_mark(&splits, as.parent, &h[om], as.twin[fb + f], used, NULL);
                if (sl > 0) {
                    n_int++;
                    fv_int += sl;
                    __atomic_fetch_add(&as.acc[om].n_nb, 1, __ATOMIC_RELAXED);
                } else {
                    __atomic_fetch_add(&n_gone, 1, __ATOMIC_RELAXED);
                }
            } else if (as.twin[fb + f] < 0) {
                len = face_len_mark(&splits, as.parent, c, f, used, NULL);
                if (len > 0) {
                    __atomic_fetch_add(&a->n_nb, 1, __ATOMIC_RELAXED);
#pragma omp critical(vc_assembly_orphans)
                    {
                        if (n_orphans == cap_orphans) {
                            int64_t cap = cap_orphans ? 2 * cap_orphans : 64;
                            orphan *o = realloc(orphans, (size_t)cap * sizeof *o);
                            if (o) {
                                orphans = o;
                                cap_orphans = cap;
                            } else {
                                failed = 1;
                            }
                        }
                        if (n_orphans < cap_orphans)
                            orphans[n_orphans++] =
                                (orphan){h[om].seed, c->seed, om, (int32_t)m, f, len};
                    }
                } else {
                    __atomic_fetch_add(&n_gone, 1, __ATOMIC_RELAXED);
                }
            }
            as.len_code[fb + f] = code;
        }
        a->n_int = n_int;
        a->n_bnd = n_bnd;
        a->fv_int = fv_int;
        a->fv_bnd = fv_bnd;
    }
    if (failed)
        goto nomem;
    if (n_orphans > 1)
        qsort(orphans, (size_t)n_orphans, sizeof *orphans, cmp_orphan);
    for (int64_t i = 0; i < n_orphans; i++) {
        as.acc[orphans[i].owner].n_int++;
        as.acc[orphans[i].owner].fv_int += orphans[i].len;
    }
    PHASE("survive");

    /* Places in the output: prefix sums in cell order. */
    int64_t n_int = 0, n_bnd = 0, n_fv_int = 0, n_fv_bnd = 0, n_cf = 0;
    out->n_cells = n_kept;
    out->cell_offsets = BIG_ARRAY(n_kept + 1, int64_t);
    if (!out->cell_offsets)
        goto nomem;
    for (int64_t k = 0; k < n_kept; k++) {
        cell_acc *a = &as.acc[mpos[kept_seed[k]]];
        int64_t ni = a->n_int, nb = a->n_bnd, fi = a->fv_int, fb = a->fv_bnd;
        a->own_int = (int32_t)ni;
        a->own_bnd = (int32_t)nb;
        a->n_int = n_int;
        a->n_bnd = n_bnd;
        a->fv_int = n_fv_int;
        a->fv_bnd = n_fv_bnd;
        a->cell_off = n_cf;
        out->cell_offsets[k] = n_cf;
        n_int += ni;
        n_bnd += nb;
        n_fv_int += fi;
        n_fv_bnd += fb;
        n_cf += a->n_nb + ni + nb;
    }
    out->cell_offsets[n_kept] = n_cf;
    const int64_t n_faces = n_int + n_bnd;
    free(mpos);
    mpos = NULL;

    /* Points: the used roots in copy order. */
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        const unsigned char *u = used + h[m].vbase;
        int64_t np = 0;
        for (int v = 0; v < h[m].nv; v++)
            np += u[v] != 0;
        as.acc[m].first_point = np;
    }
    int64_t n_points = 0;
    for (int64_t m = 0; m < n_kept; m++) {
        int64_t np = as.acc[m].first_point;
        as.acc[m].first_point = n_points;
        n_points += np;
    }
    out->n_points = n_points;
    out->points = BIG_ARRAY(3 * n_points, double);
    if (!out->points)
        goto nomem;
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        const cell_hdr *c = &h[m];
        int64_t p = as.acc[m].first_point;
        for (int v = 0; v < c->nv; v++)
            if (used[c->vbase + v]) {
                as.parent[c->vbase + v] = (copy_id)(-(p + 1));
                memcpy(out->points + 3 * p, c->v + 3 * v, 3 * sizeof(double));
                p++;
            }
    }
    free(used);
    used = NULL;
    /* The faces' geometry is computed from the points: the cells' own
     * coordinates are no longer needed, and their pages (already touched)
     * become the face arrays' (page_bank.h). */
    if (store) {
        vc_region_pool_release(&store->coord, &bank);
        for (int64_t m = 0; m < n_kept; m++)
            h[m].v = NULL;
    }
    PHASE("points");

    /* Faces: records, vertex lists, cell lists and geometry. */
    out->n_faces = n_faces;
    out->n_interior_faces = n_int;
    out->face_offsets = BANK_ARRAY(n_faces + 1, int64_t);
    out->face_vertices = BANK_ARRAY(n_fv_int + n_fv_bnd, int64_t);
    out->face_owner = BANK_ARRAY(n_faces, int64_t);
    out->face_neighbour = BANK_ARRAY(n_faces, int64_t);
    out->face_other_seed = BANK_ARRAY(n_faces, int64_t);
    out->cell_faces = BANK_ARRAY(n_cf, int64_t);
    if (!out->face_offsets || !out->face_vertices || !out->face_owner || !out->face_neighbour ||
        !out->face_other_seed ||
        !out->cell_faces)
        goto nomem;
    out->face_offsets[0] = 0;
#pragma omp parallel num_threads(as.threads)
    {
        out_face *buf = malloc((size_t)(max_nf + n_orphans + 1) * sizeof *buf);
        if (!buf) {
#pragma omp atomic write
            failed = 1;
        }
#pragma omp for schedule(dynamic, 64)
        for (int64_t m = 0; m < n_kept; m++) {
            if (!buf)
                continue;
            const cell_hdr *c = &h[m];
            const cell_acc *a = &as.acc[m];
            int64_t n_o = 0;
            const orphan *o = n_orphans ? orphans_of(orphans, n_orphans, c->seed, &n_o) : NULL;
            int nb;
            const int ni = owned_faces(&as, m, o, n_o, buf, &nb);
            int64_t pos_i = a->fv_int, pos_b = n_fv_int + a->fv_bnd;
            int64_t *cf = out->cell_faces + a->cell_off + a->n_nb;
            for (int j = 0; j < ni + nb; j++) {
                const out_face *r = &buf[j];
                int64_t i, *pos;
                if (j < ni) {
                    i = a->n_int + j;
                    pos = &pos_i;
                    cell_acc *an = &as.acc[r->neighbour];
                    int64_t s = __atomic_fetch_add(&an->nb_fill, 1, __ATOMIC_RELAXED);
                    out->cell_faces[an->cell_off + s] = i;
                    out->face_neighbour[i] = h[r->neighbour].k;
                } else {
                    i = n_int + a->n_bnd + (j - ni);
                    pos = &pos_b;
                    out->face_neighbour[i] = -1;
                }
                out->face_owner[i] = c->k;
                out->face_other_seed[i] = r->other_seed;
                int64_t *fv = out->face_vertices + *pos;
                face_write(&splits, as.parent, &h[r->src], r->src_face, r->len, r->reversed,
                           r->simple, fv);
                *pos += r->len;
                out->face_offsets[i + 1] = *pos;
                cf[j] = i;
            }
        }
        free(buf);
    }
    if (failed)
        goto nomem;
    /* Only the cells' places are needed from here on: the rest is released
     * to the bank before the geometry and cell arrays are allocated,
     * which then take its pages (first touches of new memory are a large
     * part of the time). */
    mapped_release(h, h_bytes, &bank);
    h = NULL;
    as.h = NULL;
    mapped_release(as.parent, parent_bytes, &bank);
    as.parent = NULL;
    mapped_release(as.nbr, nbr_bytes, &bank);
    as.nbr = NULL;
    mapped_release(as.twin, twin_bytes, &bank);
    as.twin = NULL;
    free(as.len_code);
    as.len_code = NULL;
    if (store)
        vc_region_pool_release(&store->topo, &bank);
    PHASE("faces");

    /* The faces' geometry, in a pass of its own: its arrays are only
     * allocated now, on the pages just released (about a third of the
     * mesh at 1M seeds: keeping them out of the pass above lowers the peak
     * memory by as much). By owner in the spatial order, so that the
     * points read are in cache. */
    out->face_area = BANK_ARRAY(n_faces, double);
    out->face_centroid = BANK_ARRAY(3 * n_faces, double);
    out->face_normal = BANK_ARRAY(3 * n_faces, double);
    if (!out->face_area || !out->face_centroid || !out->face_normal)
        goto nomem;
#pragma omp parallel for schedule(dynamic, 256) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        /* A cell's faces are scattered (numbered by cell index, visited in
         * the spatial order): their records are fetched a few cells
         * ahead, the vertex lists once their offsets are in. */
        if (m + 2 * GEOMETRY_AHEAD < n_kept) {
            const cell_acc *b = &as.acc[m + 2 * GEOMETRY_AHEAD];
            __builtin_prefetch(out->face_offsets + b->n_int);
            __builtin_prefetch(out->face_offsets + n_int + b->n_bnd);
        }
        if (m + GEOMETRY_AHEAD < n_kept) {
            const cell_acc *b = &as.acc[m + GEOMETRY_AHEAD];
            if (b->own_int > 0) {
                prefetch_lines(out->face_vertices + out->face_offsets[b->n_int],
                               (size_t)(out->face_offsets[b->n_int + b->own_int] -
                                        out->face_offsets[b->n_int]) * sizeof(int64_t));
                __builtin_prefetch(out->face_area + b->n_int, 1);
                __builtin_prefetch(out->face_centroid + 3 * b->n_int, 1);
                __builtin_prefetch(out->face_normal + 3 * b->n_int, 1);
            }
        }
        const cell_acc *a = &as.acc[m];
        const int64_t ranges[2][2] = {{a->n_int, a->n_int + a->own_int},
                                      {n_int + a->n_bnd, n_int + a->n_bnd + a->own_bnd}};
        for (int r = 0; r < 2; r++)
            for (int64_t i = ranges[r][0]; i < ranges[r][1]; i++)
                vc_face_geometry_set(out, i, out->face_vertices + out->face_offsets[i],
                                     out->face_offsets[i + 1] - out->face_offsets[i]);
    }
    PHASE("geometry");

    /* Each cell's faces from the neighbour's side, in face order, then the
     * cells' geometry and data. */
    out->cell_seed = BANK_ARRAY(n_kept, int64_t);
    out->cell_region = BANK_ARRAY(n_kept, int32_t);
    out->n_seeds = seeds->n;
    out->seed_xyz = BANK_ARRAY(3 * seeds->n, double);
    out->cell_volume = BANK_ARRAY(n_kept, double);
    out->cell_centroid = BANK_ARRAY(3 * n_kept, double);
    if (!out->cell_seed || !out->cell_region || !out->seed_xyz || !out->cell_volume ||
        !out->cell_centroid)
        goto nomem;
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t m = 0; m < n_kept; m++) {
        int64_t *l = out->cell_faces + as.acc[m].cell_off;
        for (int64_t i = 1; i < as.acc[m].n_nb; i++) {
            int64_t x = l[i], j = i;
            for (; j > 0 && l[j - 1] > x; j--)
                l[j] = l[j - 1];
            l[j] = x;
        }
    }
#pragma omp parallel for schedule(static) num_threads(as.threads)
    for (int64_t k = 0; k < n_kept; k++) {
        out->cell_seed[k] = kept_seed[k];
        out->cell_region[k] = seeds->label[kept_seed[k]];
        vc_polymesh_update_cell_geometry(out, k);
    }
    memcpy(out->seed_xyz, seeds->xyz, (size_t)seeds->n * 3 * sizeof(double));
    PHASE("cells");
    if (timing)
        vc_log(log, VC_LOG_DEBUG, "  assembly: total    %.3f s", wall_time() - t0);
    *n_degenerate = n_gone + splits.n;
    goto done;

nomem:
    rc = vc_error_set(err, VC_ENOMEM, "out of memory while assembling %lld cells",
                      (long long)n_kept);
    vc_polymesh_free(out);
done:
    vc_page_bank_free(&bank);
    mapped_release(h, h_bytes, NULL);
    h = NULL;
    free(mpos);
    free(n_outer);
    free(as.acc);
    mapped_release(as.parent, parent_bytes, NULL);
    as.parent = NULL;
    mapped_release(as.nbr, nbr_bytes, NULL);
    as.nbr = NULL;
    mapped_release(as.twin, twin_bytes, NULL);
    as.twin = NULL;
    free(as.slow);
    free(as.len_code);
    free(splits.s);
    free(used);
    free(orphans);
    return rc;
#undef PHASE
}
