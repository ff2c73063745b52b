/* Sorting short arrays in the hot loops (a cell's edges, a seed's nearest
 * neighbours, a ball's overlapping balls): glibc's qsort allocates a
 * buffer and calls the comparator through a pointer for every pair, which
 * made it 3.6% of a whole bunny.off mesh. VC_SMALL_SORT(name, type, less)
 * defines `static void name(type *a, int64_t n)`, sorting a[0 .. n) by the
 * expression less(x, y) (x, y: const type *): insertion sort below 24
 * elements, else a median-of-three quicksort on the larger part's loop and
 * recursion into the smaller (depth at most log2 n). For keys without
 * ties (many equal keys make it quadratic); not stable, so with distinct
 * keys the result is the same as qsort's. */
#ifndef VC_UTIL_SMALL_SORT_H
#define VC_UTIL_SMALL_SORT_H

#include <stdint.h>

#define VC_SMALL_SORT(name, type, less)                                                           \
    static void name(type *a, int64_t n)                                                          \
    {                                                                                             \
        while (n > 24) {                                                                          \
            type t;                                                                               \
            const int64_t m = n / 2, z = n - 1;                                                   \
            /* the median of a[0], a[m], a[z] to a[z], the least to a[0] */                      \
            if (less(&a[m], &a[0])) {                                                             \
                t = a[m], a[m] = a[0], a[0] = t;                                                  \
            }                                                                                     \
            if (less(&a[z], &a[0])) {                                                             \
                t = a[z], a[z] = a[0], a[0] = t;                                                  \
            }                                                                                     \
            if (less(&a[m], &a[z])) {                                                             \
                t = a[m], a[m] = a[z], a[z] = t;                                                  \
            }                                                                                     \
            int64_t s = 0;                                                                        \
            for (int64_t i = 0; i < z; i++)                                                       \
                if (less(&a[i], &a[z])) {                                                         \
                    t = a[i], a[i] = a[s], a[s] = t;                                              \
                    s++;                                                                          \
                }                                                                                 \
            t = a[s], a[s] = a[z], a[z] = t;                                                      \
            /* a[0 .. s) < a[s] <= a[s + 1 .. n) */                                               \
            if (s < n - 1 - s) {                                                                  \
                name(a, s);                                                                       \
                a += s + 1;                                                                       \
                n -= s + 1;                                                                       \
            } else {                                                                              \
                name(a + s + 1, n - 1 - s);                                                       \
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
    }

#endif
