/* util/small_sort.h against qsort: random arrays of every length from 0 to
 * 300 and a few long ones (distinct keys, as the library's callers have),
 * already sorted, reversed, organ-pipe and sawtooth orders (the inputs that
 * defeat a naive pivot), and pairs with few ties: the same array as
 * qsort's, element for element; and the comparisons counted on a UV
 * sphere's half-edges (an order that made the pivots poor). Also
 * util/bucket_sort.h against the small sort on the same half-edges (the
 * poles' buckets hold 800 records) and random half-edges, and its refusal
 * of a key out of range. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "util/bucket_sort.h"
#include "util/small_sort.h"
#include "vorocrust/random.h"

#include "test_check.h"

typedef struct pair {
    int64_t a, b;
} pair;

#define I64_LESS(p, q) (*(p) < *(q))
VC_SMALL_SORT(sort_i64, int64_t, I64_LESS)
/* half-edges by (smaller vertex, larger vertex, side), counting the
 * comparisons */
typedef struct half_edge {
    int64_t a, b, side;
} half_edge;
static int64_t n_less;
#define HALF_EDGE_LESS(p, q)                                                                     \
    ((p)->a < (q)->a || ((p)->a == (q)->a && ((p)->b < (q)->b || ((p)->b == (q)->b && (p)->side < (q)->side))))
#define HALF_EDGE_COUNTED_LESS(p, q) (n_less++, HALF_EDGE_LESS(p, q))
VC_SMALL_SORT(sort_half_edges_counted, half_edge, HALF_EDGE_COUNTED_LESS)
VC_SMALL_SORT(sort_half_edges, half_edge, HALF_EDGE_LESS)
#define HALF_EDGE_KEY(p) ((p)->a)
VC_BUCKET_SORT(bucket_sort_half_edges, half_edge, HALF_EDGE_KEY, HALF_EDGE_LESS, sort_half_edges)

/* The bucket sort of e[0 .. n) (keys below n_keys) against the small sort;
 * 1 when they give the same array. */
static int bucket_agrees(const half_edge *e, int64_t n, int64_t n_keys)
{
    half_edge *x = malloc(sizeof *x * (size_t)(n + 1)), *y = malloc(sizeof *y * (size_t)(n + 1));
    memcpy(x, e, sizeof *x * (size_t)n);
    memcpy(y, e, sizeof *y * (size_t)n);
    const int rc = bucket_sort_half_edges(x, n, n_keys);
    sort_half_edges(y, n);
    const int same = rc == 0 && memcmp(x, y, sizeof *x * (size_t)n) == 0;
    free(x);
    free(y);
    return same;
}
#define PAIR_LESS(p, q) ((p)->a < (q)->a || ((p)->a == (q)->a && (p)->b < (q)->b))
VC_SMALL_SORT(sort_pairs, pair, PAIR_LESS)

static int cmp_i64(const void *x, const void *y)
{
    const int64_t a = *(const int64_t *)x, b = *(const int64_t *)y;
    return (a > b) - (a < b);
}

static int cmp_pair(const void *x, const void *y)
{
    const pair *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return (p->b > q->b) - (p->b < q->b);
}

/* Sorts a copy of v[0 .. n) both ways; 1 when they agree. */
static int agrees_i64(const int64_t *v, int64_t n)
{
    int64_t *x = malloc(sizeof *x * (size_t)(n + 1)), *y = malloc(sizeof *y * (size_t)(n + 1));
    memcpy(x, v, sizeof *x * (size_t)n);
    memcpy(y, v, sizeof *y * (size_t)n);
    sort_i64(x, n);
    qsort(y, (size_t)n, sizeof *y, cmp_i64);
    const int same = memcmp(x, y, sizeof *x * (size_t)n) == 0;
    free(x);
    free(y);
    return same;
}

int main(void)
{
    vc_rng rng;
    vc_rng_init(&rng, 7, 0);
    enum { LONGEST = 20000 };
    int64_t *v = malloc(sizeof *v * LONGEST);
    /* random distinct keys: a shuffled range, shifted */
    const int64_t lengths[] = {1000, 4096, LONGEST};
    for (int64_t n = 0; n <= 300 + 3; n++) {
        const int64_t len = n <= 300 ? n : lengths[n - 301];
        for (int64_t i = 0; i < len; i++)
            v[i] = 3 * i - 1000;
        for (int64_t i = len - 1; i > 0; i--) {
            const int64_t j = (int64_t)(vc_rng_uniform(&rng) * (double)(i + 1));
            const int64_t t = v[i];
            v[i] = v[j < i ? j : i];
            v[j < i ? j : i] = t;
        }
        CHECKF(agrees_i64(v, len), "random keys, n = %lld", (long long)len);
    }
    /* orders that defeat a pivot taken from one end */
    const int64_t n = LONGEST;
    for (int64_t i = 0; i < n; i++)
        v[i] = i;
    CHECK(agrees_i64(v, n));
    for (int64_t i = 0; i < n; i++)
        v[i] = n - i;
    CHECK(agrees_i64(v, n));
    for (int64_t i = 0; i < n; i++)
        v[i] = i < n / 2 ? 2 * i : 2 * (n - i) + 1; /* organ pipe, distinct */
    CHECK(agrees_i64(v, n));
    for (int64_t i = 0; i < n; i++)
        v[i] = (i % 100) * n + i; /* sawtooth, distinct */
    CHECK(agrees_i64(v, n));
    /* O(n log n) comparisons on the half-edges of a UV sphere in the order
     * a sphere source writes its triangles (the north cap, the south cap,
     * then the bands column by column), keyed by (smaller vertex, larger
     * vertex, side): with three-element pivots from the ends of each range
     * the sort made 18 n log2 n comparisons here (30 at a million
     * triangles, 4 times qsort's time); at most 4 n log2 n */
    {
        const int th = 400, ph = 200;
        int64_t nt = 0;
        int64_t *tri = malloc(sizeof *tri * 3 * 2 * (size_t)(th * ph));
        half_edge *e = malloc(sizeof *e * 3 * 2 * (size_t)(th * ph));
#define TRI(x, y, z) (tri[3 * nt] = (x), tri[3 * nt + 1] = (y), tri[3 * nt + 2] = (z), nt++)
        for (int i = 0; i < th; i++)
            TRI(2 + i * (ph - 2), 2 + ((i + 1) % th) * (ph - 2), 0);
        for (int i = 0; i < th; i++)
            TRI(2 + i * (ph - 2) + ph - 3, 1, 2 + ((i + 1) % th) * (ph - 2) + ph - 3);
        for (int i = 0; i < th; i++)
            for (int j = 0; j < ph - 3; j++) {
                const int64_t a = 2 + i * (ph - 2) + j, b = a + 1, c = 2 + ((i + 1) % th) * (ph - 2) + j;
                TRI(a, b, c + 1);
                TRI(a, c + 1, c);
            }
#undef TRI
        for (int64_t t = 0; t < nt; t++)
            for (int j = 0; j < 3; j++) {
                const int64_t a = tri[3 * t + j], b = tri[3 * t + (j + 1) % 3];
                e[3 * t + j] = (half_edge){a < b ? a : b, a < b ? b : a, 3 * t + j};
            }
        const int64_t n_e = 3 * nt;
        CHECK(bucket_agrees(e, n_e, 2 + th * (ph - 2)));
        int lg = 0;
        for (int64_t k = n_e; k > 1; k >>= 1)
            lg++;
        n_less = 0;
        sort_half_edges_counted(e, n_e);
        int sorted = 1;
        for (int64_t i = 1; i < n_e; i++)
            sorted &= HALF_EDGE_LESS(&e[i - 1], &e[i]);
        CHECK(sorted);
        CHECKF(n_less <= 4 * n_e * lg, "%lld comparisons for %lld half-edges (%.1f n log2 n)",
               (long long)n_less, (long long)n_e, (double)n_less / (double)n_e / lg);
        free(tri);
        free(e);
    }
    /* random half-edges over 1,000 vertices, some buckets empty */
    {
        enum { N_E = 30000 };
        half_edge *e = malloc(sizeof *e * N_E);
        for (int64_t i = 0; i < N_E; i++) {
            const int64_t a = (int64_t)(vc_rng_uniform(&rng) * 1000), b = (int64_t)(vc_rng_uniform(&rng) * 1000);
            e[i] = (half_edge){a < b ? a : b, a < b ? b : a, N_E - i};
        }
        CHECK(bucket_agrees(e, N_E, 1000));
        CHECK(bucket_agrees(e, 0, 1000));
        /* a key out of range: refused, the array as it was */
        e[17].a = 1000;
        half_edge *copy = malloc(sizeof *copy * N_E);
        memcpy(copy, e, sizeof *e * N_E);
        CHECK(bucket_sort_half_edges(e, N_E, 1000) == -1);
        CHECK(memcmp(copy, e, sizeof *e * N_E) == 0);
        free(copy);
        free(e);
    }
    /* pairs: keys tied in a, told apart by b, and a few equal pairs */
    pair *p = malloc(sizeof *p * 3000), *q = malloc(sizeof *q * 3000);
    for (int64_t i = 0; i < 3000; i++) {
        p[i].a = (int64_t)(vc_rng_uniform(&rng) * 50);
        p[i].b = i % 7 == 0 ? 0 : (int64_t)(vc_rng_uniform(&rng) * 1e9);
    }
    memcpy(q, p, sizeof *p * 3000);
    sort_pairs(p, 3000);
    qsort(q, 3000, sizeof *q, cmp_pair);
    CHECK(memcmp(p, q, sizeof *p * 3000) == 0);
    free(p);
    free(q);
    free(v);
    return failures != 0;
}
