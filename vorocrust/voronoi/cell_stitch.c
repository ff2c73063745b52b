/* Stitching Voronoi cells by the identity of their vertices (see
 * cell_stitch.h).
 *
 * Positions: m is a cell's place in the spatial build order, k its kept
 * index (the output cell index, ascending seed). Every pass is over the
 * cells, on threads, writing to places fixed by prefix sums, or a
 * union-find whose classes do not depend on the order of the unions (the
 * smallest member is the root), so the output is the same for any thread
 * count. */
#include "cell_stitch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "convex_cell.h"
#include "util/exact_predicates.h"
#include "util/reserve.h"
#include "util/small_sort.h"
#include "util/union_find.h"

/* A vertex is a sphere's centre (vc_seed_spheres) only within this share
 * of the radius of it. Rounding moves it further the nearer two seeds of
 * the sphere are (any four seeds with two nearly coincident are nearly
 * co-circular, and their vertex slides along the circle's axis): seeds
 * 1e-9 of the radius apart spread the cluster beyond 1e-6 of it
 * (test_voronoi_spheres). The balls' centres lie a sizeable share of a
 * radius apart, so no vertex of another centre comes this near. */
#define VC_SPHERE_CENTRE_REACH 1e-4

static inline int omp_thread(void)
{
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

/* Resident memory in MiB, for the phase lines (0 where unknown). */
static double resident_mib(void)
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

static double wall_time(void)
{
#ifdef _OPENMP
    return omp_get_wtime();
#else
    return 0;
#endif
}

typedef struct stitch {
    const vc_seeds *seeds;
    const vc_power_ctx *ctx;
    const vc_cell_result *cells;
    const int64_t *kept_seed, *order;
    int64_t n_kept;
    int64_t *kidx;    /* per seed: its kept index, or -1 */
    int64_t *kpos;    /* per kept index: its position m */
    int64_t *loc_off; /* per position: the first of its vertices in gid[] */
    int32_t *gid;     /* per cell vertex: its global vertex (below 2^31: checked) */
    int64_t n_gid;
    double *gp;       /* 3 per global vertex: the owner's position */
    double *gev;      /* per global vertex: the owner's error bound */
    double *grad;     /* per global vertex: its distance to its lowest seed */
    int64_t *gkey;    /* 4 per global vertex: its planes, ascending */
    int64_t *root;    /* per global vertex: its class (the smallest member) */
    unsigned char *nontrivial; /* per root: its class has several members */
    unsigned char *candidate;  /* per root: may be a straight point */
    unsigned char *straight;   /* per root: a point inside a straight edge */
    unsigned char *split_point; /* per root: inside an edge of a degenerate face */
    int64_t *face_off;         /* per position: its first face in degenerate[] */
    unsigned char *degenerate; /* per cell face: a segment (zero area) */
    struct split *splits;      /* points of degenerate faces inside edges */
    int64_t n_splits;
} stitch;

/* A point p inside the edge lo - hi (lo < hi) at parameter t from lo. */
typedef struct split {
    int64_t lo, hi, p;
    double t;
} split;

static int cmp_split(const void *x, const void *y)
{
    const split *a = x, *b = y;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    if (a->t != b->t)
        return a->t < b->t ? -1 : 1;
    return (a->p > b->p) - (a->p < b->p);
}

static inline int64_t seed_of(const stitch *st, int64_t m)
{
    return st->kept_seed[st->order[m]];
}

/* The four planes of vertex i of the cell at m, ascending. */
static void vertex_key(const stitch *st, int64_t m, int i, int64_t key[4])
{
    const vc_cell_result *c = &st->cells[m];
    key[0] = seed_of(st, m);
    for (int j = 0; j < 3; j++)
        key[j + 1] = c->plane[c->vf[3 * i + j]];
    for (int a = 1; a < 4; a++) {
        int64_t x = key[a];
        int b = a;
        for (; b > 0 && key[b - 1] > x; b--)
            key[b] = key[b - 1];
        key[b] = x;
    }
}

/* A cell's own vertex: its key and local index, to number them by key. */
typedef struct owned_key {
    int64_t key[4];
    int local;
} owned_key;
/* keys of one cell's vertices are distinct (each names one vertex) */
#define OWNED_KEY_LESS(x, y)                                                                      \
    ((x)->key[0] != (y)->key[0]   ? (x)->key[0] < (y)->key[0]                                      \
     : (x)->key[1] != (y)->key[1] ? (x)->key[1] < (y)->key[1]                                      \
     : (x)->key[2] != (y)->key[2] ? (x)->key[2] < (y)->key[2]                                      \
                                  : (x)->key[3] < (y)->key[3])
VC_SMALL_SORT(sort_owned_keys, owned_key, OWNED_KEY_LESS)

/* The position of the owner of a key: the kept seed of lowest index. */
static int64_t owner_of(const stitch *st, const int64_t key[4])
{
    for (int j = 0; j < 4; j++)
        if (key[j] >= 0 && st->kidx[key[j]] >= 0)
            return st->kpos[st->kidx[key[j]]];
    return -1; /* not reached: the cell's own seed is kept */
}

/* Does the cell at m own its vertex i: is its own seed the lowest kept
 * seed of the vertex's four? (owner_of without the key.) */
static inline int owns_vertex(const stitch *st, int64_t m, int i)
{
    const vc_cell_result *c = &st->cells[m];
    const int64_t s = seed_of(st, m);
    for (int j = 0; j < 3; j++) {
        const int64_t p = c->plane[c->vf[3 * i + j]];
        if (p >= 0 && p < s && st->kidx[p] >= 0)
            return 0;
    }
    return 1;
}

static inline int key_cmp(const int64_t *a, const int64_t *b)
{
    for (int j = 0; j < 4; j++)
        if (a[j] != b[j])
            return a[j] < b[j] ? -1 : 1;
    return 0;
}

/* The global vertex with this key among the owner's (gkey[vbase[o] ..
 * vbase[o + 1]), ascending: the owner numbers its vertices in key order),
 * or -1 when the owner lacks it. */
static int64_t find_in_owner(const stitch *st, const int64_t *vbase, int64_t o,
                             const int64_t key[4])
{
    int64_t lo = vbase[o], hi = vbase[o + 1];
    while (lo < hi) {
        const int64_t mid = lo + (hi - lo) / 2;
        const int c = key_cmp(st->gkey + 4 * mid, key);
        if (c == 0)
            return mid;
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return -1;
}

/* The point of a vertex from its key alone, so that it depends neither on
 * which cells are kept nor on how a cell was built: the planes of the
 * key's other entries relative to its lowest seed, solved in double, or
 * where that is too ill-conditioned, exactly in integers and rounded.
 * Returns a bound on its distance to the exact vertex. */
static double canonical_point(const vc_power_ctx *ctx, const int64_t key[4], double x[3],
                              double *rad)
{
    int b = 0;
    while (b < 4 && key[b] < 0)
        b++;
    const double *xb = ctx->xyz + 3 * key[b];
    double q[3][4];
    int wall[3];
    for (int j = 0, m = 0; j < 4; j++) {
        if (j == b)
            continue;
        if (key[j] >= 0) {
            const double *xa = ctx->xyz + 3 * key[j];
            for (int d = 0; d < 3; d++)
                q[m][d] = xa[d] - xb[d];
            q[m][3] = 0.5 * (q[m][0] * q[m][0] + q[m][1] * q[m][1] + q[m][2] * q[m][2]);
            wall[m] = 0;
        } else {
            const int k = (int)(-1 - key[j]), axis = k / 2;
            const double X = (k % 2) ? ctx->box_hi[axis] : ctx->box_lo[axis];
            for (int d = 0; d < 3; d++)
                q[m][d] = d == axis ? 1.0 : 0.0;
            q[m][3] = X - xb[axis];
            wall[m] = 1;
        }
        m++;
    }
    const double *qp[3] = {q[0], q[1], q[2]};
    double y[3];
    double e = vc_solve_planes(qp, wall, y, NULL, rad);
    if (!(isfinite(*rad) && e <= 1e-6 * *rad)) {
        /* too ill-conditioned in double: the exact vertex, rounded */
        int64_t pl[3];
        for (int j = 0, m = 0; j < 4; j++)
            if (j != b)
                pl[m++] = key[j];
        if (vc_power_vertex_exact(ctx, key[b], pl, y) == 0) {
            *rad = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
            e = 8 * 1.1102230246251565e-16 * *rad;
        } else if (!isfinite(*rad)) {
            /* not reached for inputs the integers can hold (exponents
             * within about 300 bits of each other): the seed itself, with
             * no bound, so that every decision about it is exact */
            y[0] = y[1] = y[2] = 0;
            *rad = 0;
            e = INFINITY;
        }
    }
    for (int d = 0; d < 3; d++)
        x[d] = xb[d] + y[d];
    return e + 2.3e-16 * (fabs(x[0]) + fabs(x[1]) + fabs(x[2]));
}

/* Are the global vertices u and v the same point exactly? u's point on
 * every plane of v's. 1, 0, or VC_PREDICATE_NOMEM. */
static int same_point(const stitch *st, int64_t u, int64_t v)
{
    const int64_t *ku = st->gkey + 4 * u, *kv = st->gkey + 4 * v;
    int b = 0;
    while (b < 4 && ku[b] < 0)
        b++;
    int64_t pl[3];
    for (int j = 0, m = 0; j < 4; j++)
        if (j != b)
            pl[m++] = ku[j];
    for (int j = 0; j < 4; j++) {
        const int64_t q = kv[j];
        if (q == ku[0] || q == ku[1] || q == ku[2] || q == ku[3])
            continue;
        const int r = vc_power_on_plane(st->ctx, ku[b], pl, q);
        if (r != 1)
            return r;
    }
    return 1;
}

/* Are the global vertices u and v one point of the mesh? Nearer each
 * other than merge_tol of their distance to their seeds, or the same point
 * exactly (tested only when within their error bounds). A function of the
 * two vertices alone, so every cell and every pass decides alike. Returns
 * 1, 0, or VC_PREDICATE_NOMEM. */
static int points_coincide(const stitch *st, int64_t u, int64_t v, double merge_tol)
{
    const double *a = st->gp + 3 * u, *b = st->gp + 3 * v;
    const double d = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                          (a[2] - b[2]) * (a[2] - b[2]));
    const double r = st->grad[u] < st->grad[v] ? st->grad[u] : st->grad[v];
    if (d <= merge_tol * r)
        return 1;
    if (d > st->gev[u] + st->gev[v])
        return 0;
    return same_point(st, u, v);
}

/* The cycle of face f of the cell at m as class roots, without repeats
 * and folds (x, a, x becomes x), into buf (room for the face). Returns its
 * length (below 3: the face is gone). */
static int clean_cycle(const stitch *st, int64_t m, int f, int64_t *buf)
{
    const vc_cell_result *c = &st->cells[m];
    int n = 0;
    for (int j = c->face_start[f]; j < c->face_start[f + 1]; j++) {
        const int64_t r = st->root[st->gid[st->loc_off[m] + c->fv[j]]];
        if (n > 0 && buf[n - 1] == r)
            continue;
        buf[n++] = r;
        /* a fold: ... x, a, x */
        while (n >= 3 && buf[n - 1] == buf[n - 3])
            n -= 2;
    }
    /* the same across the cycle's end */
    for (int changed = 1; changed && n >= 2;) {
        changed = 0;
        if (buf[n - 1] == buf[0]) {
            n--;
            changed = 1;
        } else if (n >= 3 && buf[n - 2] == buf[0]) { /* x, ..., x, a | */
            n -= 2;
            changed = 1;
        } else if (n >= 3 && buf[n - 1] == buf[1]) { /* | a, x, ..., x */
            memmove(buf, buf + 2, (size_t)(n - 2) * sizeof *buf);
            n -= 2;
            changed = 1;
        }
    }
    return n >= 3 ? n : 0;
}

/* The splits of the edge a - b: their range in st->splits. */
static int64_t splits_of(const stitch *st, int64_t a, int64_t b, int64_t *count)
{
    const int64_t lo = a < b ? a : b, hi = a < b ? b : a;
    int64_t l = 0, h = st->n_splits;
    while (l < h) {
        const int64_t mid = (l + h) / 2;
        const split *q = &st->splits[mid];
        if (q->lo < lo || (q->lo == lo && q->hi < hi))
            l = mid + 1;
        else
            h = mid;
    }
    int64_t e = l;
    while (e < st->n_splits && st->splits[e].lo == lo && st->splits[e].hi == hi)
        e++;
    *count = e - l;
    return l;
}

/* The cycle of face f of the cell at m as written: clean_cycle, nothing
 * for a degenerate face, the points of degenerate faces inside its edges
 * inserted, and straight points left out. *buf grows as needed.
 * Returns the length, 0 when the face is gone, -1 out of memory. */
static int final_cycle(const stitch *st, int64_t m, int f, int64_t **buf, int64_t *cap,
                       int64_t *tmp)
{
    if (st->degenerate && st->degenerate[st->face_off[m] + f])
        return 0;
    const int len = clean_cycle(st, m, f, tmp);
    if (len == 0)
        return 0;
    int n = 0;
    for (int j = 0; j < len; j++) {
        const int64_t a = tmp[j], b = tmp[j + 1 < len ? j + 1 : 0];
        /* a, then what lies inside a -> b: the edge's split points, and
         * theirs inside the pieces (degenerate faces next to each other),
         * to a fixed depth */
        const int start = n;
        if (vc_reserve(buf, cap, n + 2, sizeof **buf) != 0)
            return -1;
        (*buf)[n++] = a;
        (*buf)[n++] = b; /* removed below */
        for (int depth = 0, changed = 1; changed && depth < 8 && st->n_splits; depth++) {
            changed = 0;
            for (int i = start; i + 1 < n; i++) {
                const int64_t u = (*buf)[i], v = (*buf)[i + 1];
                int64_t k = 0;
                const int64_t at = splits_of(st, u, v, &k);
                if (k == 0)
                    continue;
                if (vc_reserve(buf, cap, n + k, sizeof **buf) != 0)
                    return -1;
                /* only points not yet in this edge's list (rounding can
                 * order nearly coincident points differently in two
                 * degenerate faces) */
                int64_t add[64];
                int na = 0;
                for (int64_t q = 0; q < k && na < 64; q++) {
                    const int64_t p = st->splits[u < v ? at + q : at + k - 1 - q].p;
                    int seen = 0;
                    for (int r = start; r < n && !seen; r++)
                        seen = (*buf)[r] == p;
                    if (!seen)
                        add[na++] = p;
                }
                if (na == 0)
                    continue;
                memmove(*buf + i + 1 + na, *buf + i + 1, (size_t)(n - i - 1) * sizeof **buf);
                for (int q = 0; q < na; q++)
                    (*buf)[i + 1 + q] = add[q];
                n += na;
                i += na;
                changed = 1;
            }
        }
        n--; /* b starts the next edge */
    }
    /* straight points last: the splits are keyed by the edges around them */
    int w = 0;
    for (int j = 0; j < n; j++)
        if (!st->straight[(*buf)[j]])
            (*buf)[w++] = (*buf)[j];
    return w >= 3 ? w : 0;
}

/* Is face f of the cell at m written by that cell (interior faces by the
 * lower seed, boundary faces always)? */
static inline int owns_face(const stitch *st, int64_t m, int f)
{
    const int64_t t = st->cells[m].plane[f];
    return t < 0 || st->kidx[t] < 0 || seed_of(st, m) < t;
}

static inline int is_interior(const stitch *st, int64_t t)
{
    return t >= 0 && st->kidx[t] >= 0;
}

/* Has cell c a face against seed t? */
static inline int has_plane(const vc_cell_result *c, int64_t t)
{
    for (int f = 0; f < c->nf; f++)
        if (c->plane[f] == t)
            return 1;
    return 0;
}

/* The face other than f that vertices a and b of cell c share: the second
 * face along their edge (f itself if there is none: no edge). */
static inline int other_face(const vc_cell_result *c, int a, int b, int f)
{
    const uint16_t *va = c->vf + 3 * a, *vb = c->vf + 3 * b;
    for (int i = 0; i < 3; i++)
        if (va[i] != f && (va[i] == vb[0] || va[i] == vb[1] || va[i] == vb[2]))
            return va[i];
    return f;
}

/* Per cell (by position): counts, then places. */
typedef struct cell_count {
    int64_t n_int, fv_int, n_bnd, fv_bnd;
} cell_count;

static int max_face_len(const vc_cell_result *c)
{
    int mx = 0;
    for (int f = 0; f < c->nf; f++)
        if (c->face_start[f + 1] - c->face_start[f] > mx)
            mx = c->face_start[f + 1] - c->face_start[f];
    return mx;
}

/* The growing per-thread lists below: {v, n, cap}. PUSH appends x to
 * the list at b; 0, or -1 when out of memory. */
#define PUSH(b, x)                                                                                \
    (vc_reserve(&(b)->v, &(b)->cap, (b)->n + 1, sizeof *(b)->v) != 0 ? -1                         \
                                                                       : ((b)->v[(b)->n++] = (x), 0))

typedef struct pair64 {
    int64_t a, b;
} pair64;

typedef struct pair_buf {
    pair64 *v;
    int64_t n, cap;
} pair_buf;

/* A point of a boundary face, by the hash cell of its position. */
typedef struct hashed_point {
    int64_t i[3];
    int64_t g;
} hashed_point;

#define HASHED_LESS(a, b)                                                                         \
    ((a)->i[0] != (b)->i[0]   ? (a)->i[0] < (b)->i[0]                                              \
     : (a)->i[1] != (b)->i[1] ? (a)->i[1] < (b)->i[1]                                              \
     : (a)->i[2] != (b)->i[2] ? (a)->i[2] < (b)->i[2]                                              \
                              : (a)->g < (b)->g)
VC_SMALL_SORT(sort_hashed, hashed_point, HASHED_LESS)

/* The columns of hash cells (i0, i1) that hold points: an open-addressing
 * table from a column to its first point in the sorted order (a column's
 * points are consecutive there). A probe is one or two loads where a
 * binary search over all points was eighteen. */
typedef struct column_table {
    int64_t *key0, *key1, *first; /* first -1: an empty slot */
    int64_t mask;
} column_table;

static uint64_t column_hash(int64_t a, int64_t b)
{
    uint64_t x = (uint64_t)a * 0x9e3779b97f4a7c15ULL ^ (uint64_t)b * 0xc2b2ae3d27d4eb4fULL;
    x ^= x >> 31;
    x *= 0xbf58476d1ce4e5b9ULL;
    return x ^ (x >> 29);
}

/* The first point of column (a, b), or -1. */
static int64_t column_first(const column_table *c, int64_t a, int64_t b)
{
    for (int64_t s = (int64_t)(column_hash(a, b) & (uint64_t)c->mask);; s = (s + 1) & c->mask) {
        if (c->first[s] < 0)
            return -1;
        if (c->key0[s] == a && c->key1[s] == b)
            return c->first[s];
    }
}

/* Builds the table of the sorted points h[0 .. nb); -1 when out of memory. */
static int column_table_build(column_table *c, const hashed_point *h, int64_t nb)
{
    int64_t size = 16;
    while (size < 2 * nb)
        size *= 2;
    c->mask = size - 1;
    c->key0 = malloc((size_t)size * sizeof(int64_t));
    c->key1 = malloc((size_t)size * sizeof(int64_t));
    c->first = malloc((size_t)size * sizeof(int64_t));
    if (!c->key0 || !c->key1 || !c->first)
        return -1;
    for (int64_t s = 0; s < size; s++)
        c->first[s] = -1;
    for (int64_t a = 0; a < nb; a++) {
        if (a > 0 && h[a].i[0] == h[a - 1].i[0] && h[a].i[1] == h[a - 1].i[1])
            continue;
        int64_t s = (int64_t)(column_hash(h[a].i[0], h[a].i[1]) & (uint64_t)c->mask);
        while (c->first[s] >= 0)
            s = (s + 1) & c->mask;
        c->key0[s] = h[a].i[0];
        c->key1[s] = h[a].i[1];
        c->first[s] = a;
    }
    return 0;
}

static void column_table_free(column_table *c)
{
    free(c->key0);
    free(c->key1);
    free(c->first);
}

/* Hash cells (of width q) around a boundary point that it must search:
 * two points coincide within merge_tol of their distance to their seeds
 * (at most q) or, when exactly the same point, within the sum of their
 * error bounds, so the point with the larger bound finds the other within
 * q + 2 gev. Bounds are a few ulp of the point (width 1), up to 1e-6 of
 * its distance to its seed for an ill-conditioned solve: the width is
 * capped there (a pair of such points farther apart is not matched; the
 * validator then reports the open cell). */
#define MAX_SEARCH_WIDTH 16
static int64_t search_width(const stitch *st, int64_t g, double q)
{
    const double w = ceil((q + 2 * st->gev[g]) / q);
    return w < MAX_SEARCH_WIDTH ? (w > 1 ? (int64_t)w : 1) : MAX_SEARCH_WIDTH;
}

/* Kept cells that meet only across non-kept cells or the box (an edge or
 * a corner, as in a checkerboard) share vertices that no edge of a kept
 * cell joins. The points of boundary faces are united with every other
 * such point that is the same exact point, or nearer than merge_tol of
 * their distance to their seeds: a function of the two points alone, so
 * the classes do not depend on the order. Returns the unions made, or -1
 * when out of memory. */
static int64_t match_boundary_points(stitch *st, int threads, double merge_tol)
{
    const int64_t ng = st->n_gid;
    unsigned char *on = calloc((size_t)ng + 1, 1);
    if (!on)
        return -1;
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
    for (int64_t m = 0; m < st->n_kept; m++) {
        const vc_cell_result *c = &st->cells[m];
        for (int f = 0; f < c->nf; f++) {
            if (is_interior(st, c->plane[f]))
                continue;
            for (int j = c->face_start[f]; j < c->face_start[f + 1]; j++)
                on[st->gid[st->loc_off[m] + c->fv[j]]] = 1; /* the same value from any thread */
        }
    }
    int64_t nb = 0;
    double extent = 0;
    for (int64_t g = 0; g < ng; g++) {
        if (!on[g])
            continue;
        nb++;
        for (int d = 0; d < 3; d++)
            extent = fabs(st->gp[3 * g + d]) > extent ? fabs(st->gp[3 * g + d]) : extent;
    }
    hashed_point *h = malloc((size_t)(nb + 1) * sizeof *h);
    if (!h) {
        free(on);
        return -1;
    }
    /* Hash cells as wide as the largest merge distance (merge_tol of the
     * distance to the seeds); a point whose error bound reaches farther
     * (an ill-conditioned vertex) searches as many cells as it needs
     * (search_width). */
    double q = 0;
    for (int64_t g = 0; g < ng; g++)
        if (on[g] && merge_tol * st->grad[g] > q)
            q = merge_tol * st->grad[g];
    if (!(q > 1e-13 * (extent + 1)))
        q = 1e-13 * (extent + 1);
    for (int64_t g = 0, n = 0; g < ng; g++) {
        if (!on[g])
            continue;
        for (int d = 0; d < 3; d++)
            h[n].i[d] = (int64_t)floor(st->gp[3 * g + d] / q);
        h[n++].g = g;
    }
    free(on);
    sort_hashed(h, nb);
    column_table cols = {NULL, NULL, NULL, 0};
    if (column_table_build(&cols, h, nb) != 0) {
        column_table_free(&cols);
        free(h);
        return -1;
    }
    /* The pairs that coincide, found in parallel against the classes as
     * they are (a compressed copy: finds in the shared array would write),
     * then united in one pass. Testing a pair the unions of this pass
     * would have made redundant changes nothing: the classes are the
     * closure of the coinciding pairs either way, and the unions made
     * (the classes merged) are counted alike. */
    const int64_t ng_all = st->n_gid;
    int64_t *snap = malloc((size_t)(ng_all + 1) * sizeof *snap);
    pair_buf *found = calloc((size_t)threads, sizeof *found);
    if (!snap || !found) {
        free(snap);
        free(found);
        free(h);
        column_table_free(&cols);
        return -1;
    }
    for (int64_t g = 0; g < ng_all; g++)
        snap[g] = vc_uf_find(st->root, g);
    volatile int failed = 0;
#pragma omp parallel for schedule(dynamic, 1024) num_threads(threads)
    for (int64_t a = 0; a < nb; a++) {
#ifdef _OPENMP
        pair_buf *pb = &found[omp_get_thread_num()];
#else
        pair_buf *pb = &found[0];
#endif
        const int64_t u = h[a].g;
        const int64_t w = search_width(st, u, q);
        /* the (2 w + 1)^2 columns of neighbouring cells: each column's
         * cells (dz) are consecutive in the sorted order */
        for (int64_t dx = -w; dx <= w; dx++)
            for (int64_t dy = -w; dy <= w; dy++) {
                const hashed_point key = {{h[a].i[0] + dx, h[a].i[1] + dy, h[a].i[2] - w}, -1};
                int64_t lo = column_first(&cols, key.i[0], key.i[1]);
                if (lo < 0)
                    continue;
                while (lo < nb && h[lo].i[0] == key.i[0] && h[lo].i[1] == key.i[1] &&
                       h[lo].i[2] < key.i[2])
                    lo++;
                for (int64_t b = lo; b < nb && h[b].i[0] == key.i[0] && h[b].i[1] == key.i[1] &&
                                     h[b].i[2] <= key.i[2] + 2 * w;
                     b++) {
                    const int64_t v = h[b].g;
                    if (v == u || snap[u] == snap[v])
                        continue; /* already one class */
                    /* each pair once: from the wider search, or the lower
                     * index at equal widths (both searches reach the other) */
                    const int64_t wv = search_width(st, v, q);
                    if (wv > w || (wv == w && v < u))
                        continue;
                    const int join = points_coincide(st, u, v, merge_tol);
                    if (join == VC_PREDICATE_NOMEM || (join == 1 && PUSH(pb, ((pair64){u, v}))))
                        failed = 1;
                }
            }
    }
    int64_t n_unions = -1;
    if (!failed) {
        n_unions = 0;
        for (int t = 0; t < threads; t++)
            for (int64_t k = 0; k < found[t].n; k++) {
                const int64_t ra = vc_uf_find(st->root, found[t].v[k].a);
                const int64_t rb = vc_uf_find(st->root, found[t].v[k].b);
                if (ra != rb) {
                    vc_uf_unite(st->root, ra, rb);
                    n_unions++;
                }
            }
    }
    for (int t = 0; t < threads; t++)
        free(found[t].v);
    free(found);
    free(snap);
    free(h);
    column_table_free(&cols);
    return n_unions;
}

/* Do the points cyc[0..n) lie on one segment, within merge_tol of their
 * distance to their seeds? Then t[j] is point j's parameter along it (from
 * the end of lower index of the farthest pair). A function of the point
 * set alone: both copies of a face decide alike. */
static int on_segment(const stitch *st, const int64_t *cyc, int n, double merge_tol, double *t)
{
    int pa = 0, pb = 1;
    double best = -1;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            const double *x = st->gp + 3 * cyc[i], *y = st->gp + 3 * cyc[j];
            const double d2 = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                              (x[2] - y[2]) * (x[2] - y[2]);
            const int64_t lo = cyc[i] < cyc[j] ? cyc[i] : cyc[j];
            const int64_t blo = cyc[pa] < cyc[pb] ? cyc[pa] : cyc[pb];
            if (d2 > best || (d2 == best && lo < blo)) {
                best = d2;
                pa = i;
                pb = j;
            }
        }
    if (cyc[pb] < cyc[pa]) {
        const int x = pa;
        pa = pb;
        pb = x;
    }
    if (!(best > 0))
        return 0;
    double rmin = INFINITY;
    for (int i = 0; i < n; i++)
        rmin = st->grad[cyc[i]] < rmin ? st->grad[cyc[i]] : rmin;
    const double *P = st->gp + 3 * cyc[pa], *Q = st->gp + 3 * cyc[pb];
    const double u[3] = {Q[0] - P[0], Q[1] - P[1], Q[2] - P[2]};
    const double L = sqrt(best);
    for (int i = 0; i < n; i++) {
        const double *x = st->gp + 3 * cyc[i];
        const double w[3] = {x[0] - P[0], x[1] - P[1], x[2] - P[2]};
        const double c[3] = {w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2],
                             w[0] * u[1] - w[1] * u[0]};
        if (sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / L > merge_tol * rmin)
            return 0;
        t[i] = (w[0] * u[0] + w[1] * u[1] + w[2] * u[2]) / best;
    }
    return 1;
}

typedef struct split_buf {
    split *v;
    int64_t n, cap;
} split_buf;

/* A face's vertex cycle (global ids pid[ob[j]]) into dst, from its
 * smallest id on, in the same direction: the cell's own cycle starts where
 * its cuts happened to leave it, and the mesh must not depend on the
 * order of the cuts (a cell kept by vc_voronoi_rebuild was cut in another
 * order than a fresh build would cut it). */
static void put_cycle(int64_t *dst, const int64_t *pid, const int64_t *ob, int len)
{
    int first = 0;
    for (int j = 1; j < len; j++)
        if (pid[ob[j]] < pid[ob[first]])
            first = j;
    for (int j = 0; j < len; j++) {
        const int at = first + j < len ? first + j : first + j - len;
        dst[j] = pid[ob[at]];
    }
}

/* *buf with room for the longest face of c (grown as needed). */
static int face_buf(const vc_cell_result *c, int64_t **buf, int64_t *cap)
{
    return vc_reserve(buf, cap, max_face_len(c), sizeof **buf);
}

typedef struct u64_buf {
    uint64_t *v;
    int64_t n, cap;
} u64_buf;

#define PAIR_LESS(x, y) ((x)->a != (y)->a ? (x)->a < (y)->a : (x)->b < (y)->b)
VC_SMALL_SORT(sort_pairs, pair64, PAIR_LESS)

/* Frees the stitching's arrays (and clears them). */
static void free_stitch_arrays(stitch *st)
{
    void *arrays[] = {st->kidx, st->kpos, st->loc_off, st->gid, st->gp, st->gev,
                      st->grad, st->root, st->gkey, st->nontrivial, st->candidate, st->straight,
                      st->split_point, st->face_off, st->degenerate, st->splits};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        free(arrays[i]);
    st->kidx = st->kpos = st->loc_off = st->root = st->gkey = st->face_off = NULL;
    st->gid = NULL;
    st->gp = st->gev = st->grad = NULL;
    st->nontrivial = st->candidate = st->straight = st->split_point = st->degenerate = NULL;
    st->splits = NULL;
    st->n_splits = 0;
}

/* The common sphere of a vertex's four seeds (see vc_seed_spheres), or -1:
 * the lowest-numbered sphere every seed of the key lies on whose centre
 * is within VC_SPHERE_CENTRE_REACH of its radius from the vertex. */
static int64_t common_sphere(const vc_seed_spheres *sp, const int64_t key[4], const double p[3])
{
    for (int j = 0; j < 4; j++)
        if (key[j] < 0)
            return -1; /* a wall */
    const int64_t s0 = key[0];
    for (int64_t q = sp->start[s0]; q < sp->start[s0 + 1]; q++) {
        const int64_t a = sp->id[q];
        int all = 1;
        for (int j = 1; j < 4 && all; j++) {
            int found = 0;
            for (int64_t r = sp->start[key[j]]; r < sp->start[key[j] + 1] && !found; r++)
                found = sp->id[r] == a;
            all = found;
        }
        if (!all)
            continue;
        const double *c = sp->sphere + 4 * a;
        const double d = sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                              (p[2] - c[2]) * (p[2] - c[2]));
        if (d <= VC_SPHERE_CENTRE_REACH * c[3])
            return a;
    }
    return -1;
}

/* A vertex whose four seeds lie on one sphere of the list is that sphere's
 * centre: its point becomes the centre, and the vertices of each centre
 * are one class. Returns the unions made, or -1 when out of memory. */
/* A vertex whose point a class took: its own point, put back before the
 * classes are looked at again. */
typedef struct saved_point {
    int64_t g;
    double p[3], ev, rad;
} saved_point;

typedef struct saved_points {
    saved_point *v;
    int64_t n, cap;
} saved_points;

/* Is key a (4 planes, ascending) before key b? */
static int key_before(const int64_t *a, const int64_t *b)
{
    for (int j = 0; j < 4; j++)
        if (a[j] != b[j])
            return a[j] < b[j];
    return 0;
}

/* Every class of vertices (st->root) at the point of its member with the
 * smallest key: its root is its smallest id, and the ids follow the order
 * the cells were built in, which must not show in the mesh (the points
 * of a class differ by up to the merge distance, and which one the class
 * takes decides what lies on one segment). The roots' own points are
 * saved in *sv and put back first, so that a later round chooses from the
 * members' own points again. 0, or -1 when out of memory. */
static int class_points(stitch *st, saved_points *sv)
{
    for (int64_t i = 0; i < sv->n; i++) {
        const saved_point *q = &sv->v[i];
        memcpy(st->gp + 3 * q->g, q->p, sizeof q->p);
        st->gev[q->g] = q->ev;
        st->grad[q->g] = q->rad;
    }
    sv->n = 0;
    const int64_t ng = st->n_gid;
    int64_t *rep = malloc((size_t)(ng + 1) * sizeof(int64_t));
    if (!rep)
        return -1;
    for (int64_t g = 0; g < ng; g++)
        rep[g] = -1;
    for (int64_t g = 0; g < ng; g++) {
        const int64_t r = st->root[g];
        if (r != g && (rep[r] < 0 || key_before(st->gkey + 4 * g, st->gkey + 4 * rep[r])))
            rep[r] = g;
    }
    int failed = 0;
    for (int64_t r = 0; r < ng && !failed; r++) {
        const int64_t m = rep[r];
        if (m < 0 || key_before(st->gkey + 4 * r, st->gkey + 4 * m))
            continue; /* a single vertex, or the root's key is the smallest */
        if (vc_reserve(&sv->v, &sv->cap, sv->n + 1, sizeof(saved_point))) {
            failed = 1;
            break;
        }
        saved_point *q = &sv->v[sv->n++];
        q->g = r;
        memcpy(q->p, st->gp + 3 * r, sizeof q->p);
        q->ev = st->gev[r];
        q->rad = st->grad[r];
        memcpy(st->gp + 3 * r, st->gp + 3 * m, 3 * sizeof(double));
        st->gev[r] = st->gev[m];
        st->grad[r] = st->grad[m];
    }
    free(rep);
    return failed ? -1 : 0;
}

static int64_t unite_at_sphere_centres(stitch *st, const vc_seed_spheres *sp, int threads)
{
    const int64_t ng = st->n_gid;
    int64_t *at = malloc((size_t)(ng + 1) * sizeof(int64_t));
    if (!at)
        return -1;
#pragma omp parallel for schedule(dynamic, 1024) num_threads(threads)
    for (int64_t g = 0; g < ng; g++) {
        at[g] = common_sphere(sp, st->gkey + 4 * g, st->gp + 3 * g);
        if (at[g] >= 0)
            memcpy(st->gp + 3 * g, sp->sphere + 4 * at[g], 3 * sizeof(double));
    }
    /* the first vertex met of each centre (the ids are dense: an array) */
    int64_t *first = malloc((size_t)(sp->n_spheres + 1) * sizeof(int64_t));
    if (!first) {
        free(at);
        return -1;
    }
    for (int64_t a = 0; a < sp->n_spheres; a++)
        first[a] = -1;
    int64_t n_united = 0;
    for (int64_t g = 0; g < ng; g++) {
        if (at[g] < 0)
            continue;
        if (first[at[g]] < 0)
            first[at[g]] = g;
        else if (vc_uf_find(st->root, first[at[g]]) != vc_uf_find(st->root, g)) {
            vc_uf_unite(st->root, first[at[g]], g);
            n_united++;
        }
    }
    free(at);
    free(first);
    return n_united;
}

int vc_stitch_cells(const vc_seeds *seeds, const vc_power_ctx *ctx, const vc_cell_result *cells,
                    const int64_t *kept_seed, int64_t n_kept, const int64_t *order,
                    vc_cell_store *store, double merge_tol, const vc_seed_spheres *spheres,
                    int threads, const vc_logger *log, vc_polymesh *out, vc_error *err)
{
    const int timing = vc_log_enabled(log, VC_LOG_DEBUG);
    const int progress = vc_log_enabled(log, VC_LOG_INFO);
    double t0 = wall_time(), tp = t0, t_info = t0;
    /* a progress line after a pass when the last one is a second old (a
     * million cells stitch in about 14 s on one thread) */
#define PHASE(name)                                                                               \
    do {                                                                                          \
        const double now_ = wall_time();                                                          \
        if (timing)                                                                               \
            vc_log(log, VC_LOG_DEBUG, "  stitch: %-10s %.3f s, resident %.0f MiB", name,         \
                   now_ - tp, resident_mib());                                                    \
        if (progress && now_ - t_info >= 1.0) {                                                   \
            vc_log(log, VC_LOG_INFO, "voronoi: stitching, %s done, %.1f s", name, now_ - t0);     \
            t_info = now_;                                                                        \
        }                                                                                         \
        tp = now_;                                                                                \
    } while (0)
    memset(out, 0, sizeof *out);
    stitch st;
    memset(&st, 0, sizeof st);
    st.seeds = seeds;
    st.ctx = ctx;
    st.cells = cells;
    st.kept_seed = kept_seed;
    st.order = order;
    st.n_kept = n_kept;
    const int64_t n = seeds->n;
    int rc = 0;
    int64_t *owned = NULL, *vbase = NULL;
    cell_count *cnt = NULL;
    pair_buf *pairs = NULL, *near = NULL;
    u64_buf *links = NULL;
    int64_t *fill = NULL;
    unsigned char *used = NULL;
    saved_points class_saved = {NULL, 0, 0};
    int64_t *pid = NULL;
    volatile int failed = 0, inconsistent = 0;
    int64_t bad_m = -1;

    st.kidx = malloc((size_t)n * sizeof(int64_t));
    st.kpos = malloc((size_t)n_kept * sizeof(int64_t));
    st.loc_off = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
    owned = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
    vbase = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
    if (!st.kidx || !st.kpos || !st.loc_off || !owned || !vbase)
        goto nomem;
    for (int64_t i = 0; i < n; i++)
        st.kidx[i] = -1;
    for (int64_t k = 0; k < n_kept; k++)
        st.kidx[kept_seed[k]] = k;
    for (int64_t m = 0; m < n_kept; m++)
        st.kpos[order[m]] = m;
    st.loc_off[0] = 0;
    for (int64_t m = 0; m < n_kept; m++)
        st.loc_off[m + 1] = st.loc_off[m] + cells[m].nv;
    st.gid = malloc((size_t)(st.loc_off[n_kept] > 0 ? st.loc_off[n_kept] : 1) * sizeof(int32_t));
    if (!st.gid)
        goto nomem;

    /* Owned vertices, numbered in the owners' order: within the cell by
     * their keys (not by where the cell's cuts left them, which depends on
     * the order its neighbours came in: the class roots, the smallest
     * members, would follow it), then offset by the cells before. Their
     * keys go to gkey in that order, where the other cells find them. */
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
    for (int64_t m = 0; m < n_kept; m++) {
        int n_own = 0;
        for (int i = 0; i < cells[m].nv; i++)
            n_own += owns_vertex(&st, m, i);
        owned[m] = n_own;
    }
    vbase[0] = 0;
    for (int64_t m = 0; m < n_kept; m++)
        vbase[m + 1] = vbase[m] + owned[m];
    st.n_gid = vbase[n_kept];
    if (st.n_gid >= INT32_MAX) {
        rc = vc_error_set(err, VC_EPARAM, "%lld Voronoi vertices: at most %d are supported",
                          (long long)st.n_gid, INT32_MAX - 1);
        goto done;
    }
    st.gkey = malloc((size_t)(4 * st.n_gid + 1) * sizeof(int64_t));
    if (!st.gkey)
        goto nomem;
    int oom_keys = 0;
#pragma omp parallel num_threads(threads)
    {
        owned_key *ok = NULL;
        int64_t ok_cap = 0;
#pragma omp for schedule(dynamic, 256)
        for (int64_t m = 0; m < n_kept; m++) {
            if (vc_reserve(&ok, &ok_cap, cells[m].nv + 1, sizeof(owned_key))) {
#pragma omp atomic write
                oom_keys = 1;
                continue;
            }
            int n_own = 0;
            for (int i = 0; i < cells[m].nv; i++) {
                if (owns_vertex(&st, m, i)) {
                    vertex_key(&st, m, i, ok[n_own].key);
                    ok[n_own++].local = i;
                } else {
                    st.gid[st.loc_off[m] + i] = -1;
                }
            }
            sort_owned_keys(ok, n_own);
            for (int c = 0; c < n_own; c++) {
                const int64_t g = vbase[m] + c;
                st.gid[st.loc_off[m] + ok[c].local] = (int32_t)g;
                memcpy(st.gkey + 4 * g, ok[c].key, sizeof ok[c].key);
            }
        }
        free(ok);
    }
    if (oom_keys)
        goto nomem;
    /* The others, looked up among their owners' keys: a cell's keys and
     * owners first, the owners' keys prefetched, then the searches (the
     * owners' keys are the lookup's cache misses; a cell's twenty-odd of
     * them overlap). */
    int oom_lookup = 0;
#pragma omp parallel num_threads(threads)
    {
        owned_key *q = NULL; /* key, and in .local the vertex */
        int64_t *qo = NULL, q_cap = 0, qo_cap = 0;
#pragma omp for schedule(dynamic, 256)
        for (int64_t m = 0; m < n_kept; m++) {
            const int nv = cells[m].nv;
            if (vc_reserve(&q, &q_cap, nv + 1, sizeof *q) || vc_reserve(&qo, &qo_cap, nv + 1, sizeof *qo)) {
#pragma omp atomic write
                oom_lookup = 1;
                continue;
            }
            int nq = 0;
            for (int i = 0; i < nv; i++) {
                if (st.gid[st.loc_off[m] + i] >= 0)
                    continue;
                vertex_key(&st, m, i, q[nq].key);
                q[nq].local = i;
                qo[nq] = owner_of(&st, q[nq].key);
                __builtin_prefetch(st.gkey + 4 * vbase[qo[nq]]);
                nq++;
            }
            for (int j = 0; j < nq; j++) {
                const int64_t g = find_in_owner(&st, vbase, qo[j], q[j].key);
                if (g < 0) {
#pragma omp critical(vc_stitch_bad)
                    if (bad_m < 0 || m < bad_m)
                        bad_m = m;
                    inconsistent = 1;
                    continue;
                }
                st.gid[st.loc_off[m] + q[j].local] = (int32_t)g;
            }
        }
        free(q);
        free(qo);
    }
    if (oom_lookup)
        goto nomem;
    if (inconsistent) {
        const int64_t s = seed_of(&st, bad_m);
        rc = vc_error_set(err, VC_EINTERNAL,
                          "the cells of seed %lld (%g %g %g) and a neighbour disagree on a vertex "
                          "(a defect of the engine)",
                          (long long)s, seeds->xyz[3 * s], seeds->xyz[3 * s + 1],
                          seeds->xyz[3 * s + 2]);
        goto done;
    }
    free(owned);
    owned = NULL;
    PHASE("lookup");

    /* The global vertices' points. */
    const int64_t ng = st.n_gid;
    st.gp = malloc((size_t)(3 * ng + 1) * sizeof(double));
    st.gev = malloc((size_t)(ng + 1) * sizeof(double));
    st.grad = malloc((size_t)(ng + 1) * sizeof(double));
    st.root = malloc((size_t)(ng + 1) * sizeof(int64_t));
    if (!st.gp || !st.gev || !st.grad || !st.root)
        goto nomem;
#pragma omp parallel for schedule(dynamic, 4096) num_threads(threads)
    for (int64_t g = 0; g < ng; g++) {
        const int64_t *key = st.gkey + 4 * g;
        double rad;
        st.gev[g] = canonical_point(ctx, key, st.gp + 3 * g, &rad);
        st.grad[g] = rad;
        /* a vertex on a wall lies exactly on it */
        for (int j = 0; j < 4; j++)
            if (key[j] < 0) {
                const int w = (int)(-1 - key[j]), axis = w / 2;
                st.gp[3 * g + axis] = (w % 2) ? ctx->box_hi[axis] : ctx->box_lo[axis];
            }
    }

    /* Collapsed edges, then their classes. */
    pairs = calloc((size_t)threads, sizeof *pairs);
    near = calloc((size_t)threads, sizeof *near);
    links = calloc((size_t)threads, sizeof *links);
    if (!pairs || !near || !links)
        goto nomem;
#pragma omp parallel num_threads(threads)
    {
#ifdef _OPENMP
        pair_buf *pb = &pairs[omp_get_thread_num()];
#else
        pair_buf *pb = &pairs[0];
#endif
#pragma omp for schedule(dynamic, 256)
        for (int64_t m = 0; m < n_kept; m++) {
            const vc_cell_result *c = &cells[m];
            const int64_t s = seed_of(&st, m);
            for (int f = 0; f < c->nf; f++) {
                const int j0 = c->face_start[f], j1 = c->face_start[f + 1];
                const int64_t t = c->plane[f];
                if (is_interior(&st, t) && t < s)
                    continue; /* the edges of this face: tested by t's cell or a lower one */
                for (int j = j0; j < j1; j++) {
                    const int a = c->fv[j], b = c->fv[j + 1 < j1 ? j + 1 : j0];
                    const int64_t ga = st.gid[st.loc_off[m] + a], gb = st.gid[st.loc_off[m] + b];
                    if (ga > gb)
                        continue; /* each edge once per cell: from its lower end */
                    /* and once in the mesh: by the kept cell of the lowest
                     * seed of the three whose cells meet along it */
                    const int64_t t2 = c->plane[other_face(c, a, b, f)];
                    if (t2 != t && is_interior(&st, t2) && t2 < s)
                        continue;
                    const int r = points_coincide(&st, ga, gb, merge_tol);
                    if (r == VC_PREDICATE_NOMEM || (r == 1 && PUSH(pb, ((pair64){ga, gb})) != 0))
                        failed = 1;
                }
            }
        }
    }
    if (failed)
        goto nomem;
    for (int64_t g = 0; g < ng; g++)
        st.root[g] = g;
    int64_t n_collapsed = 0;
    for (int t = 0; t < threads; t++) {
        for (int64_t i = 0; i < pairs[t].n; i++)
            vc_uf_unite(st.root, pairs[t].v[i].a, pairs[t].v[i].b);
        n_collapsed += pairs[t].n;
        free(pairs[t].v);
        pairs[t] = (pair_buf){NULL, 0, 0};
    }
    if (spheres && spheres->n_spheres > 0) {
        const int64_t n_centred = unite_at_sphere_centres(&st, spheres, threads);
        if (n_centred < 0)
            goto nomem;
        n_collapsed += n_centred;
    }
    const int64_t n_matched = match_boundary_points(&st, threads, merge_tol);
    if (n_matched < 0)
        goto nomem;
    n_collapsed += n_matched;
    st.nontrivial = calloc((size_t)ng + 1, 1);
    st.candidate = calloc((size_t)ng + 1, 1);
    st.straight = calloc((size_t)ng + 1, 1);
    if (!st.nontrivial || !st.candidate || !st.straight)
        goto nomem;
    /* The classes, and what follows from them; again when degenerate faces
     * hold points too near each other to order along them (below). */
    int reclass_round = 0;
reclass:
    for (int64_t g = 0; g < ng; g++)
        st.root[g] = vc_uf_find(st.root, g);
    if (class_points(&st, &class_saved) != 0)
        goto nomem;
    memset(st.nontrivial, 0, (size_t)ng + 1);
    memset(st.candidate, 0, (size_t)ng + 1);
    memset(st.straight, 0, (size_t)ng + 1);
    for (int64_t g = 0; g < ng; g++)
        if (st.root[g] != g)
            st.nontrivial[st.root[g]] = 1;
    PHASE("collapse");


    /* Degenerate faces: a face whose points lie on one segment has no area
     * (seeds co-circular, exactly or to rounding). It leaves both cells,
     * and each of its points lying inside an edge of it joins every face
     * that has that edge, so the cells stay closed. Only where edges
     * collapsed: a face of the perturbed diagram that has no area in the
     * exact one has some of its vertices coincide. */
    if (n_collapsed > 0) {
        st.face_off = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
        if (!st.face_off)
            goto nomem;
        st.face_off[0] = 0;
        for (int64_t m = 0; m < n_kept; m++)
            st.face_off[m + 1] = st.face_off[m] + cells[m].nf;
        st.degenerate = calloc((size_t)st.face_off[n_kept] + 1, 1);
        split_buf *sb = calloc((size_t)threads, sizeof *sb);
        if (!st.degenerate || !sb) {
            free(sb);
            goto nomem;
        }
#pragma omp parallel num_threads(threads)
        {
#ifdef _OPENMP
            split_buf *b = &sb[omp_get_thread_num()];
#else
            split_buf *b = &sb[0];
#endif
            int64_t *buf = NULL, cap = 0, tcap = 0;
            double *t = NULL;
#pragma omp for schedule(dynamic, 256)
            for (int64_t m = 0; m < n_kept; m++) {
                const vc_cell_result *c = &cells[m];
                if (face_buf(c, &buf, &cap) != 0 ||
                    vc_reserve(&t, &tcap, max_face_len(c), sizeof *t) != 0) {
                    failed = 1;
                    continue;
                }
                for (int f = 0; f < c->nf; f++) {
                    const int len = clean_cycle(&st, m, f, buf);
                    if (len < 3 || !on_segment(&st, buf, len, merge_tol, t))
                        continue;
                    st.degenerate[st.face_off[m] + f] = 1;
                    /* Points nearer each other than four times the width
                     * allowed cannot be ordered along the segment alike in
                     * every face: they are united (and all redone). */
                    double rmin = INFINITY;
                    for (int j = 0; j < len; j++)
                        rmin = st.grad[buf[j]] < rmin ? st.grad[buf[j]] : rmin;
                    for (int i2 = 0; i2 < len; i2++)
                        for (int j2 = i2 + 1; j2 < len; j2++) {
                            const double *x = st.gp + 3 * buf[i2], *y = st.gp + 3 * buf[j2];
                            const double d = sqrt((x[0] - y[0]) * (x[0] - y[0]) +
                                                  (x[1] - y[1]) * (x[1] - y[1]) +
                                                  (x[2] - y[2]) * (x[2] - y[2]));
                            if (d <= 4 * merge_tol * rmin &&
                                PUSH(&near[omp_thread()], ((pair64){buf[i2], buf[j2]})) != 0)
                                failed = 1;
                        }
                    for (int j = 0; j < len; j++) {
                        const int jn = j + 1 < len ? j + 1 : 0;
                        const int64_t a = buf[j], bb = buf[jn];
                        const double ta = t[j], tb = t[jn];
                        const double lo_t = a < bb ? ta : tb, hi_t = a < bb ? tb : ta;
                        for (int q = 0; q < len; q++) {
                            const double tq = t[q];
                            const int inside = (tq > ta && tq < tb) || (tq < ta && tq > tb);
                            if (!inside || buf[q] == a || buf[q] == bb)
                                continue;
                            const split x = {a < bb ? a : bb, a < bb ? bb : a, buf[q],
                                             (tq - lo_t) / (hi_t - lo_t)};
                            if (PUSH(b, x) != 0)
                                failed = 1;
                        }
                    }
                }
            }
            free(buf);
            free(t);
        }
        int64_t total = 0;
        for (int th = 0; th < threads; th++)
            total += sb[th].n;
        if (total > 0 && !failed) {
            st.splits = malloc((size_t)total * sizeof *st.splits);
            if (!st.splits)
                failed = 1;
            else {
                int64_t at = 0;
                for (int th = 0; th < threads; th++) {
                    if (sb[th].n)
                        memcpy(st.splits + at, sb[th].v, (size_t)sb[th].n * sizeof *st.splits);
                    at += sb[th].n;
                }
                qsort(st.splits, (size_t)total, sizeof *st.splits, cmp_split);
                int64_t w = 0;
                for (int64_t i = 0; i < total; i++)
                    if (w == 0 || st.splits[i].lo != st.splits[w - 1].lo ||
                        st.splits[i].hi != st.splits[w - 1].hi || st.splits[i].p != st.splits[w - 1].p)
                        st.splits[w++] = st.splits[i];
                st.n_splits = w;
                st.split_point = calloc((size_t)ng + 1, 1);
                if (!st.split_point)
                    failed = 1;
                else
                    for (int64_t i = 0; i < w; i++)
                        st.split_point[st.splits[i].p] = 1;
            }
        }
        for (int th = 0; th < threads; th++)
            free(sb[th].v);
        free(sb);
        if (failed)
            goto nomem;
        int64_t n_near = 0;
        for (int th = 0; th < threads; th++) {
            for (int64_t i = 0; i < near[th].n; i++)
                if (vc_uf_find(st.root, near[th].v[i].a) != vc_uf_find(st.root, near[th].v[i].b)) {
                    vc_uf_unite(st.root, near[th].v[i].a, near[th].v[i].b);
                    n_near++;
                }
            free(near[th].v);
            near[th] = (pair_buf){NULL, 0, 0};
        }
        if (n_near > 0 && reclass_round < 3) {
            n_collapsed += n_near;
            reclass_round++;
            free(st.face_off);
            free(st.degenerate);
            free(st.splits);
            free(st.split_point);
            st.split_point = NULL;
            st.face_off = NULL;
            st.degenerate = NULL;
            st.splits = NULL;
            st.n_splits = 0;
            goto reclass;
        }
    }
    PHASE("degenerate");
    /* Straight points: only where a class has several members or a
     * degenerate face left a point inside an edge can one appear (the exact
     * diagram's vertices have three edges or more in every cell).
     * Candidates: such points and their neighbours; their degree over the
     * faces as written (degenerate faces gone, split points in). A split
     * point only non-kept cells need is one: kept cells would show it as a
     * hanging vertex on a straight edge, which floating point cannot keep
     * convex. */
    if (n_collapsed > 0) { /* splits exist only where edges collapsed */
#pragma omp parallel num_threads(threads)
        {
            int64_t *buf = NULL, *ob = NULL, cap = 0, ocap = 0;
#pragma omp for schedule(dynamic, 256)
            for (int64_t m = 0; m < n_kept; m++) {
                const vc_cell_result *c = &cells[m];
                if (face_buf(c, &buf, &cap) != 0) {
                    failed = 1;
                    continue;
                }
                for (int f = 0; f < c->nf; f++) {
                    if (!owns_face(&st, m, f))
                        continue; /* every written face once */
                    const int len = final_cycle(&st, m, f, &ob, &ocap, buf);
                    if (len < 0)
                        failed = 1;
                    for (int j = 0; j < len; j++) {
                        const int64_t v = ob[j], u = ob[j ? j - 1 : len - 1],
                                      w = ob[j + 1 < len ? j + 1 : 0];
                        if (st.nontrivial[v] || st.nontrivial[u] || st.nontrivial[w] ||
                            (st.split_point && st.split_point[v]))
                            st.candidate[v] = 1; /* the same value from every thread */
                    }
                }
            }
#ifdef _OPENMP
            u64_buf *pb = &links[omp_get_thread_num()];
#else
            u64_buf *pb = &links[0];
#endif
#pragma omp barrier
#pragma omp for schedule(dynamic, 256)
            for (int64_t m = 0; m < n_kept; m++) {
                const vc_cell_result *c = &cells[m];
                if (face_buf(c, &buf, &cap) != 0) {
                    failed = 1;
                    continue;
                }
                for (int f = 0; f < c->nf; f++) {
                    if (!owns_face(&st, m, f))
                        continue;
                    const int len = final_cycle(&st, m, f, &ob, &ocap, buf);
                    if (len < 0)
                        failed = 1;
                    for (int j = 0; j < len; j++) {
                        const uint64_t v = (uint64_t)ob[j];
                        if (!st.candidate[v])
                            continue;
                        if (PUSH(pb, v << 32 | (uint64_t)ob[j ? j - 1 : len - 1]) != 0 ||
                            PUSH(pb, v << 32 | (uint64_t)ob[j + 1 < len ? j + 1 : 0]) != 0)
                            failed = 1;
                    }
                }
            }
            free(buf);
            free(ob);
        }
        if (failed)
            goto nomem;
        /* A candidate's distinct neighbours, up to three (three make it
         * no straight point), from the (vertex, neighbour) links packed in
         * 64 bits (global vertices are below 2^31: checked); the count
         * does not depend on the links' order, so neither on the threads.
         * Candidates get dense indices first: three slots per global
         * vertex would cost 12 bytes each at a million seeds. */
        int32_t *cidx = malloc((size_t)(ng + 1) * sizeof *cidx);
        if (!cidx)
            goto nomem;
        int64_t n_cand = 0;
        for (int64_t g = 0; g < ng; g++)
            cidx[g] = st.candidate[g] ? (int32_t)n_cand++ : -1;
        int32_t *nbr = malloc((size_t)(3 * n_cand + 1) * sizeof *nbr);
        unsigned char *n_nbr = calloc((size_t)n_cand + 1, 1);
        if (!nbr || !n_nbr) {
            free(cidx);
            free(nbr);
            free(n_nbr);
            goto nomem;
        }
        for (int t = 0; t < threads; t++) {
            for (int64_t i = 0; i < links[t].n; i++) {
                const uint64_t l = links[t].v[i];
                const int32_t c = cidx[l >> 32], u = (int32_t)(l & 0xffffffffu);
                int32_t *slot = nbr + 3 * (int64_t)c;
                const int k = n_nbr[c];
                if (k == 3 || (k > 0 && slot[0] == u) || (k > 1 && slot[1] == u))
                    continue;
                slot[k] = u;
                n_nbr[c] = (unsigned char)(k + 1);
            }
            free(links[t].v);
            links[t] = (u64_buf){NULL, 0, 0};
        }
        for (int64_t g = 0; g < ng; g++)
            if (cidx[g] >= 0 && n_nbr[cidx[g]] == 2)
                st.straight[g] = 1;
        free(cidx);
        free(nbr);
        free(n_nbr);
    }
    PHASE("straight");
    /* What the faces no longer need, freed before the mesh's arrays are
     * allocated (a lower peak): the vertices' keys, bounds, distances and
     * the classes' marks. */
    free(st.gkey);
    free(st.gev);
    free(st.grad);
    free(st.nontrivial);
    free(st.candidate);
    free(st.split_point);
    st.gkey = NULL;
    st.gev = st.grad = NULL;
    st.nontrivial = st.candidate = st.split_point = NULL;

    /* Counts per cell, and the points used. */
    cnt = calloc((size_t)n_kept + 1, sizeof *cnt);
    used = calloc((size_t)ng + 1, 1);
    if (!cnt || !used)
        goto nomem;
#pragma omp parallel num_threads(threads)
    {
        int64_t *buf = NULL, *ob = NULL, cap = 0, ocap = 0;
#pragma omp for schedule(dynamic, 256)
        for (int64_t m = 0; m < n_kept; m++) {
            const vc_cell_result *c = &cells[m];
            if (face_buf(c, &buf, &cap) != 0) {
                failed = 1;
                continue;
            }
            cell_count *a = &cnt[m];
            for (int f = 0; f < c->nf; f++) {
                if (!owns_face(&st, m, f)) {
                    /* written by the cell across, which must have it */
                    if (!has_plane(&cells[st.kpos[st.kidx[c->plane[f]]]], seed_of(&st, m)))
                        inconsistent = 1;
                    continue;
                }
                const int len = final_cycle(&st, m, f, &ob, &ocap, buf);
                if (len < 0)
                    failed = 1;
                if (len <= 0)
                    continue;
                if (is_interior(&st, c->plane[f])) {
                    a->n_int++;
                    a->fv_int += len;
                } else {
                    a->n_bnd++;
                    a->fv_bnd += len;
                }
                for (int j = 0; j < len; j++)
                    used[ob[j]] = 1;
            }
        }
        free(buf);
        free(ob);
    }
    if (failed)
        goto nomem;
    if (inconsistent) {
        rc = vc_error_set(err, VC_EINTERNAL,
                          "two neighbouring cells disagree on their common face (a defect of "
                          "the engine)");
        goto done;
    }
    /* Points: the used roots in global order. */
    pid = malloc((size_t)(ng + 1) * sizeof(int64_t));
    if (!pid)
        goto nomem;
    int64_t n_points = 0;
    for (int64_t g = 0; g < ng; g++)
        pid[g] = used[g] ? n_points++ : -1;
    free(used);
    used = NULL;
    out->n_points = n_points;
    /* in place: pid[g] <= g */
    for (int64_t g = 0; g < ng; g++)
        if (pid[g] >= 0 && pid[g] != g)
            memcpy(st.gp + 3 * pid[g], st.gp + 3 * g, 3 * sizeof(double));
    {
        double *shrunk = realloc(st.gp, (size_t)(3 * n_points + 1) * sizeof(double));
        out->points = shrunk ? shrunk : st.gp;
        st.gp = NULL;
    }

    /* Places, by kept index. */
    int64_t n_int = 0, n_bnd = 0, fv_int = 0, fv_bnd = 0;
    out->n_cells = n_kept;
    for (int64_t k = 0; k < n_kept; k++) {
        cell_count *a = &cnt[st.kpos[k]];
        const int64_t ni = a->n_int, nb = a->n_bnd, fi = a->fv_int, fb = a->fv_bnd;
        a->n_int = n_int;
        a->n_bnd = n_bnd;
        a->fv_int = fv_int;
        a->fv_bnd = fv_bnd;
        n_int += ni;
        n_bnd += nb;
        fv_int += fi;
        fv_bnd += fb;
    }
    const int64_t n_faces = n_int + n_bnd;
    out->n_faces = n_faces;
    out->n_interior_faces = n_int;
    out->face_offsets = malloc((size_t)(n_faces + 1) * sizeof(int64_t));
    out->face_vertices = malloc((size_t)(fv_int + fv_bnd + 1) * sizeof(int64_t));
    out->face_owner = malloc((size_t)(n_faces + 1) * sizeof(int64_t));
    out->face_neighbour = malloc((size_t)(n_faces + 1) * sizeof(int64_t));
    out->face_other_seed = malloc((size_t)(n_faces + 1) * sizeof(int64_t));
    if (!out->face_offsets || !out->face_vertices || !out->face_owner || !out->face_neighbour ||
        !out->face_other_seed)
        goto nomem;
    out->face_offsets[0] = 0;

    /* The faces, each by its owner: interior ones by neighbour, boundary
     * ones by the seed (or wall) across (not in the cell's own order,
     * which follows the order its cuts came in). */
#pragma omp parallel num_threads(threads)
    {
        int64_t *buf = NULL, *ob = NULL, cap = 0, ocap = 0, nb_cap = 0, bd_cap = 0;
        pair64 *nb = NULL, *bd = NULL;
#pragma omp for schedule(dynamic, 256)
        for (int64_t m = 0; m < n_kept; m++) {
            const vc_cell_result *c = &cells[m];
            const int64_t k = order[m];
            if (face_buf(c, &buf, &cap) != 0 || vc_reserve(&nb, &nb_cap, c->nf, sizeof *nb) != 0 ||
                vc_reserve(&bd, &bd_cap, c->nf, sizeof *bd) != 0) {
                failed = 1;
                continue;
            }
            const cell_count *a = &cnt[m];
            int n_nb = 0, n_bd = 0;
            int64_t ib = n_int + a->n_bnd, pb = fv_int + a->fv_bnd;
            for (int f = 0; f < c->nf; f++) {
                if (!owns_face(&st, m, f))
                    continue;
                const int64_t t = c->plane[f];
                if (is_interior(&st, t))
                    nb[n_nb++] = (pair64){st.kidx[t], f};
                else
                    bd[n_bd++] = (pair64){t, f};
            }
            sort_pairs(bd, n_bd);
            for (int q = 0; q < n_bd; q++) {
                const int f = (int)bd[q].b;
                const int64_t t = bd[q].a;
                const int len = final_cycle(&st, m, f, &ob, &ocap, buf);
                if (len < 0)
                    failed = 1;
                if (len <= 0)
                    continue;
                out->face_owner[ib] = k;
                out->face_neighbour[ib] = -1;
                out->face_other_seed[ib] = t;
                put_cycle(out->face_vertices + pb, pid, ob, len);
                pb += len;
                out->face_offsets[ib + 1] = pb;
                ib++;
            }
            sort_pairs(nb, n_nb);
            int64_t ii = a->n_int, pi = a->fv_int;
            for (int q = 0; q < n_nb; q++) {
                const int f = (int)nb[q].b;
                const int len = final_cycle(&st, m, f, &ob, &ocap, buf);
                if (len < 0)
                    failed = 1;
                if (len <= 0)
                    continue;
                out->face_owner[ii] = k;
                out->face_neighbour[ii] = nb[q].a;
                out->face_other_seed[ii] = c->plane[f];
                put_cycle(out->face_vertices + pi, pid, ob, len);
                pi += len;
                out->face_offsets[ii + 1] = pi;
                ii++;
            }
        }
        free(buf);
        free(ob);
        free(nb);
        free(bd);
    }
    if (failed)
        goto nomem;
    /* Nor the cells, nor the stitching's own arrays: freed before the
     * geometry's arrays are allocated, which lowers the peak (at 1M random
     * seeds the stitching's arrays are about 0.6 KB per cell). */
    if (store)
        vc_region_pool_free(&store->topo);
    free_stitch_arrays(&st);
    free(pid);
    free(cnt);
    pid = NULL;
    cnt = NULL;
    PHASE("faces");

    /* Each cell's faces, in increasing order. */
    out->cell_offsets = calloc((size_t)(n_kept + 1), sizeof(int64_t));
    fill = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
    if (!out->cell_offsets || !fill)
        goto nomem;
    for (int64_t i = 0; i < n_faces; i++) {
        out->cell_offsets[out->face_owner[i] + 1]++;
        if (out->face_neighbour[i] >= 0)
            out->cell_offsets[out->face_neighbour[i] + 1]++;
    }
    for (int64_t k = 0; k < n_kept; k++)
        out->cell_offsets[k + 1] += out->cell_offsets[k];
    out->cell_faces = malloc((size_t)(out->cell_offsets[n_kept] + 1) * sizeof(int64_t));
    if (!out->cell_faces)
        goto nomem;
    memcpy(fill, out->cell_offsets, (size_t)(n_kept + 1) * sizeof(int64_t));
    for (int64_t i = 0; i < n_faces; i++) {
        out->cell_faces[fill[out->face_owner[i]]++] = i;
        if (out->face_neighbour[i] >= 0)
            out->cell_faces[fill[out->face_neighbour[i]]++] = i;
    }

    out->cell_seed = malloc((size_t)(n_kept + 1) * sizeof(int64_t));
    out->cell_region = malloc((size_t)(n_kept + 1) * sizeof(int32_t));
    out->n_seeds = n;
    out->seed_xyz = malloc((size_t)(3 * n + 1) * sizeof(double));
    out->face_area = malloc((size_t)(n_faces + 1) * sizeof(double));
    out->face_centroid = malloc((size_t)(3 * n_faces + 1) * sizeof(double));
    out->face_normal = malloc((size_t)(3 * n_faces + 1) * sizeof(double));
    out->cell_volume = malloc((size_t)(n_kept + 1) * sizeof(double));
    out->cell_centroid = malloc((size_t)(3 * n_kept + 1) * sizeof(double));
    if (!out->cell_seed || !out->cell_region || !out->seed_xyz || !out->face_area ||
        !out->face_centroid || !out->face_normal || !out->cell_volume || !out->cell_centroid)
        goto nomem;
    for (int64_t k = 0; k < n_kept; k++) {
        out->cell_seed[k] = kept_seed[k];
        out->cell_region[k] = seeds->label[kept_seed[k]];
    }
    memcpy(out->seed_xyz, seeds->xyz, (size_t)n * 3 * sizeof(double));
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int64_t i = 0; i < n_faces; i++)
        vc_polymesh_update_face_geometry(out, i);
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int64_t k = 0; k < n_kept; k++)
        vc_polymesh_update_cell_geometry(out, k);
    PHASE("geometry");
    if (timing)
        vc_log(log, VC_LOG_DEBUG, "  stitch: %lld vertices, %lld edges collapsed, total %.3f s",
               (long long)ng, (long long)n_collapsed, wall_time() - t0);
    goto done;

nomem:
    rc = vc_error_set(err, VC_ENOMEM, "out of memory while stitching %lld cells",
                      (long long)n_kept);
done:
    if (rc != 0)
        vc_polymesh_free(out);
    if (pairs)
        for (int t = 0; t < threads; t++)
            free(pairs[t].v);
    free(pairs);
    if (near)
        for (int t = 0; t < threads; t++)
            free(near[t].v);
    free(near);
    if (links)
        for (int t = 0; t < threads; t++)
            free(links[t].v);
    free(links);
    free_stitch_arrays(&st);
    free(owned);
    free(vbase);
    free(cnt);
    free(fill);
    free(used);
    free(pid);
    free(class_saved.v);
    return rc;
#undef PHASE
}
