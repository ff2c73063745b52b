/* Union-find over the indices 0..n-1 of a caller-owned parent[] array
 * (parent[x] == x: x is a root). Not part of the public API.
 *
 * One rule everywhere: a set's root is its smallest index (a root is only
 * ever linked under a smaller one), so the roots, and whatever is numbered
 * from them, do not depend on the order of the unions. Finds use path
 * halving (every visited entry is pointed at its grandparent).
 *
 * Two flavours of the same idea:
 *  - sequential, on int64_t entries (vc_uf_init, vc_uf_find, vc_uf_unite);
 *  - concurrent, on int32_t entries (vc_uf_find_atomic, vc_uf_unite_atomic),
 *    for unions made from several threads at once: relaxed atomic loads and
 *    stores, roots linked with compare-and-swap. A parent pointer only ever
 *    moves to an ancestor, which stays an ancestor whatever other threads
 *    link, so the final sets and roots are those of the sequential flavour.
 *    The callers keep their indices below 2^31.
 *
 * The finds and unions are inline: the Voronoi stitching calls them in its
 * innermost loops. */
#ifndef VC_UTIL_UNION_FIND_H
#define VC_UTIL_UNION_FIND_H

#include <stdint.h>

/* Every index its own set: parent[x] = x for x < n. */
void vc_uf_init(int64_t *parent, int64_t n);

/* Number of sets among the indices 0..n-1 (the roots). */
int64_t vc_uf_count_roots(const int64_t *parent, int64_t n);

/* The root of x, halving the path. */
static inline int64_t vc_uf_find(int64_t *parent, int64_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/* Unites the sets of a and b (the larger root goes under the smaller);
 * returns the root of the union. */
static inline int64_t vc_uf_unite(int64_t *parent, int64_t a, int64_t b)
{
    a = vc_uf_find(parent, a);
    b = vc_uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
    return a < b ? a : b;
}

/* vc_uf_find, safe while other threads unite. */
static inline int64_t vc_uf_find_atomic(int32_t *parent, int64_t x)
{
    for (;;) {
        int64_t p = __atomic_load_n(&parent[x], __ATOMIC_RELAXED);
        if (p == x)
            return x;
        int64_t g = __atomic_load_n(&parent[p], __ATOMIC_RELAXED);
        if (g != p)
            __atomic_store_n(&parent[x], (int32_t)g, __ATOMIC_RELAXED);
        x = g;
    }
}

/* vc_uf_unite, safe while other threads unite and find: the larger root
 * is linked under the smaller one if it is still a root, else both roots
 * are looked up again. */
static inline void vc_uf_unite_atomic(int32_t *parent, int64_t a, int64_t b)
{
    for (;;) {
        a = vc_uf_find_atomic(parent, a);
        b = vc_uf_find_atomic(parent, b);
        if (a == b)
            return;
        int64_t hi = a > b ? a : b, lo = a > b ? b : a;
        int32_t expected = (int32_t)hi;
        if (__atomic_compare_exchange_n(&parent[hi], &expected, (int32_t)lo, 0, __ATOMIC_RELAXED,
                                        __ATOMIC_RELAXED))
            return;
    }
}

#endif
