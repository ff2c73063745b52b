/* A stable sort of 64-bit keys carrying an index each (least significant
 * digit first, 16 bits a pass, a pass skipped when every key shares its
 * digit): linear time for the millions of keys of a large input (Morton
 * codes of triangles, hashes of vertex positions). */
#ifndef VC_UTIL_RADIX_SORT_H
#define VC_UTIL_RADIX_SORT_H

#include <stdint.h>

/* Sorts key[0 .. n) ascending, idx moving with them; equal keys keep
 * their order. Returns 0, or -1 when out of memory (both untouched). */
int vc_radix_sort_u64(uint64_t *key, int64_t *idx, int64_t n);

#endif
