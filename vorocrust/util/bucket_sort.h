/* Sorting records whose first key is a small integer (a vertex id), the
 * rest breaking ties: the edges of a triangle list, grouped. A counting
 * sort by that key (stable: two passes over the records and a scatter)
 * and an insertion sort of each bucket by the whole order, which holds a
 * handful of records (the edges at a vertex). On 5.3 million half-edges
 * of a 1.8M-triangle scan the quicksort of util/small_sort.h took 0.6 s,
 * one of five such passes over a large input before sampling.
 *
 * VC_BUCKET_SORT(name, type, key, less, big_sort) defines
 * `static int name(type *a, int64_t n, int64_t n_keys)`: sorts a[0 .. n)
 * by less(x, y) (x, y: const type *), which must order first by key(x), an
 * integer in [0, n_keys); the result is the same as any sort's when no two
 * records are equal under less. A bucket of more than 32 records (the apex
 * of a fan of a thousand triangles) goes to big_sort(type *, int64_t), an
 * O(m log m) sort by the same order. Returns 0, or -1 when out of memory
 * for the copy (a untouched; also when a key is out of range). */
#ifndef VC_UTIL_BUCKET_SORT_H
#define VC_UTIL_BUCKET_SORT_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define VC_BUCKET_SORT(name, type, key, less, big_sort)                                           \
    static int name(type *a, int64_t n, int64_t n_keys)                                           \
    {                                                                                             \
        int64_t *start = calloc((size_t)n_keys + 1, sizeof(int64_t));                             \
        type *tmp = malloc(sizeof(type) * (size_t)(n > 0 ? n : 1));                               \
        if (!start || !tmp) {                                                                     \
            free(start);                                                                          \
            free(tmp);                                                                            \
            return -1;                                                                            \
        }                                                                                         \
        for (int64_t i = 0; i < n; i++) {                                                         \
            const int64_t k_ = key(&a[i]);                                                        \
            if (k_ < 0 || k_ >= n_keys) { /* not the caller's promise: no bucket */               \
                free(start);                                                                      \
                free(tmp);                                                                        \
                return -1;                                                                        \
            }                                                                                     \
            start[k_ + 1]++;                                                                      \
        }                                                                                         \
        for (int64_t k = 0; k < n_keys; k++)                                                      \
            start[k + 1] += start[k];                                                             \
        for (int64_t i = 0; i < n; i++)                                                           \
            tmp[start[key(&a[i])]++] = a[i];                                                      \
        /* start[k] is now the end of bucket k: each bucket by insertion */                       \
        int64_t from = 0;                                                                         \
        for (int64_t k = 0; k < n_keys; k++) {                                                    \
            const int64_t to = start[k];                                                          \
            if (to - from > 32)                                                                   \
                big_sort(tmp + from, to - from);                                                  \
            for (int64_t i = from + 1; to - from <= 32 && i < to; i++) {                          \
                type x = tmp[i];                                                                  \
                int64_t j = i;                                                                    \
                while (j > from && less(&x, &tmp[j - 1])) {                                       \
                    tmp[j] = tmp[j - 1];                                                          \
                    j--;                                                                          \
                }                                                                                 \
                tmp[j] = x;                                                                       \
            }                                                                                     \
            from = to;                                                                            \
        }                                                                                         \
        memcpy(a, tmp, sizeof(type) * (size_t)n);                                                 \
        free(start);                                                                              \
        free(tmp);                                                                                \
        return 0;                                                                                 \
    }

#endif
