/* Sorting in the hot loops (a cell's edges, a seed's nearest neighbours, a
 * ball's overlapping balls, the reconstructed surface's edges): glibc's
 * qsort allocates a buffer and calls the comparator through a pointer for
 * every pair, which made it 3.6% of a whole bunny.off mesh.
 * VC_SMALL_SORT(name, type, less) defines `static void name(type *a,
 * int64_t n)`, sorting a[0 .. n) by the expression less(x, y) (x, y: const
 * type *): insertion sort below 24 elements, else quicksort, its pivot the
 * median of three elements (of three such medians above 512: Tukey's
 * ninther), looping on the larger part and recursing into the smaller;
 * past 2 log2 n levels of partitions a part is heap-sorted, so the time is
 * O(n log n) whatever the order. A triangle list whose last triangles hold
 * the smallest vertex ids (a UV sphere's south pole) gave three-element
 * pivots from one end of the range at every level: 3M half-edges took
 * 1.8 s against qsort's 0.45 (test_small_sort counts the comparisons).
 * For keys without ties (many equal keys make the partitions uneven); not
 * stable, so with distinct keys the result is the same as qsort's. */
#ifndef VC_UTIL_SMALL_SORT_H
#define VC_UTIL_SMALL_SORT_H

#include <stdint.h>

#define VC_SMALL_SORT(name, type, less)                                                           \
    /* the index of the median of a[i], a[j], a[k] */                                             \
    static inline int64_t name##_median3(const type *a, int64_t i, int64_t j, int64_t k)          \
    {                                                                                             \
        if (less(&a[i], &a[j]))                                                                   \
            return less(&a[j], &a[k]) ? j : (less(&a[i], &a[k]) ? k : i);                         \
        return less(&a[i], &a[k]) ? i : (less(&a[j], &a[k]) ? k : j);                             \
    }                                                                                             \
    static void name##_sift(type *a, int64_t n, int64_t i)                                        \
    {                                                                                             \
        type x = a[i];                                                                            \
        for (;;) {                                                                                \
            int64_t c = 2 * i + 1;                                                                \
            if (c >= n)                                                                           \
                break;                                                                            \
            if (c + 1 < n && less(&a[c], &a[c + 1]))                                              \
                c++;                                                                              \
            if (!less(&x, &a[c]))                                                                 \
                break;                                                                            \
            a[i] = a[c];                                                                          \
            i = c;                                                                                \
        }                                                                                         \
        a[i] = x;                                                                                 \
    }                                                                                             \
    static void name##_heap(type *a, int64_t n)                                                   \
    {                                                                                             \
        for (int64_t i = n / 2 - 1; i >= 0; i--)                                                  \
            name##_sift(a, n, i);                                                                 \
        for (int64_t m = n - 1; m > 0; m--) {                                                     \
            type t = a[0];                                                                        \
            a[0] = a[m];                                                                          \
            a[m] = t;                                                                             \
            name##_sift(a, m, 0);                                                                 \
        }                                                                                         \
    }                                                                                             \
    static void name##_intro(type *a, int64_t n, int depth)                                       \
    {                                                                                             \
        while (n > 24) {                                                                          \
            if (depth-- == 0) {                                                                   \
                name##_heap(a, n);                                                                \
                return;                                                                           \
            }                                                                                     \
            type t;                                                                               \
            const int64_t m = n / 2, z = n - 1;                                                   \
            int64_t p;                                                                            \
            if (n > 512) {                                                                        \
                const int64_t e = n / 8;                                                          \
                p = name##_median3(a, name##_median3(a, 0, e, 2 * e),                             \
                                   name##_median3(a, m - e, m, m + e),                            \
                                   name##_median3(a, z - 2 * e, z - e, z));                       \
            } else {                                                                              \
                p = name##_median3(a, 0, m, z);                                                   \
            }                                                                                     \
            t = a[p], a[p] = a[z], a[z] = t; /* the pivot to a[z] */                              \
            int64_t s = 0;                                                                        \
            for (int64_t i = 0; i < z; i++)                                                       \
                if (less(&a[i], &a[z])) {                                                         \
                    t = a[i], a[i] = a[s], a[s] = t;                                              \
                    s++;                                                                          \
                }                                                                                 \
            t = a[s], a[s] = a[z], a[z] = t;                                                      \
            /* a[0 .. s) < a[s] <= a[s + 1 .. n) */                                               \
            if (s < n - 1 - s) {                                                                  \
                name##_intro(a, s, depth);                                                        \
                a += s + 1;                                                                       \
                n -= s + 1;                                                                       \
            } else {                                                                              \
                name##_intro(a + s + 1, n - 1 - s, depth);                                        \
                n = s;                                                                            \
            }                                                                                     \
        }                                                                                         \
        for (int64_t i = 1; i < n; i++) {                                                         \
            type x = a[i];                                                                        \
            int64_t j = i;                                                                        \
            while (j > 0 && less(&x, &a[j - 1])) {                                                \
                a[j] = a[j - 1];                                                                  \
                j--;                                                                              \
            }                                                                                     \
            a[j] = x;                                                                             \
        }                                                                                         \
    }                                                                                             \
    static void name(type *a, int64_t n)                                                          \
    {                                                                                             \
        int depth = 0;                                                                            \
        for (int64_t k = n; k > 1; k >>= 1)                                                       \
            depth += 2;                                                                           \
        name##_intro(a, n, depth);                                                                \
    }

#endif
