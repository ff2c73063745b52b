/* Items grouped by key in compressed rows: the triangles at each vertex,
 * the sharp edges at each vertex, the corners at each vertex. Internal. */
#ifndef VC_UTIL_CSR_GROUP_H
#define VC_UTIL_CSR_GROUP_H

#include <stdint.h>

/* Items 0 .. n - 1, each with the m keys key[m i .. m i + m) in
 * [0, n_keys), grouped by key: the entries of key k are
 * (*list)[(*start)[k] .. (*start)[k + 1]), in increasing item order, each
 * entry the item i. Items with keep[i] == 0 are left out (keep NULL: none).
 * *start has n_keys + 1 entries, *list one per key of a kept item; the
 * caller frees both. Returns 0, or -1 when out of memory (then both are
 * NULL). */
int vc_csr_group(const int64_t *key, int64_t n, int m, int64_t n_keys, const unsigned char *keep,
                 int64_t **start, int64_t **list);

#endif
