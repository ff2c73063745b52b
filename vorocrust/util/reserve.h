/* Growing arrays: room for more elements, doubling the capacity. */
#ifndef VC_UTIL_RESERVE_H
#define VC_UTIL_RESERVE_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

/* Makes room for `need` elements of `elem` bytes in the array *(T **)pp of
 * capacity *cap (in elements): the capacity doubles from at least 64
 * until it holds need. Returns 0, or -1 when out of memory or the size
 * overflows (the array and *cap are then unchanged). */
static inline int vc_reserve(void *pp, int64_t *cap, int64_t need, size_t elem)
{
    if (need <= *cap)
        return 0;
    int64_t c = *cap > 64 ? *cap : 64;
    while (c < need) {
        if (c > INT64_MAX / 2)
            return -1;
        c *= 2;
    }
    if ((uint64_t)c > SIZE_MAX / elem)
        return -1;
    void *q = realloc(*(void **)pp, (size_t)c * elem);
    if (!q)
        return -1;
    *(void **)pp = q;
    *cap = c;
    return 0;
}

#endif
