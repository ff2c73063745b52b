/* Morton (Z-order) codes: points sorted by them stay near their spatial
 * neighbours. Not part of the public API. */
#ifndef VC_UTIL_MORTON_H
#define VC_UTIL_MORTON_H

#include <stdint.h>

/* The low 21 bits of x spread to every third bit: a coordinate's bits
 * interleaved with two others' by (spread(x) | spread(y) << 1 |
 * spread(z) << 2). */
static inline uint64_t vc_morton_spread3(uint64_t x)
{
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

#endif
