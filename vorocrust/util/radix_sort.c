#include "util/radix_sort.h"

#include <stdlib.h>
#include <string.h>

enum { DIGIT_BITS = 16, DIGITS = 1 << DIGIT_BITS };

int vc_radix_sort_u64(uint64_t *key, int64_t *idx, int64_t n)
{
    uint64_t *k2 = malloc((size_t)(n ? n : 1) * sizeof *k2);
    int64_t *i2 = malloc((size_t)(n ? n : 1) * sizeof *i2);
    int64_t *count = malloc((size_t)DIGITS * sizeof *count);
    if (!k2 || !i2 || !count) {
        free(k2);
        free(i2);
        free(count);
        return -1;
    }
    uint64_t *ka = key, *kb = k2;
    int64_t *ia = idx, *ib = i2;
    for (int shift = 0; shift < 64; shift += DIGIT_BITS) {
        memset(count, 0, (size_t)DIGITS * sizeof *count);
        for (int64_t q = 0; q < n; q++)
            count[(ka[q] >> shift) & (DIGITS - 1)]++;
        if (n > 0 && count[(ka[0] >> shift) & (DIGITS - 1)] == n)
            continue; /* one digit for all: the order stands */
        int64_t sum = 0;
        for (int d = 0; d < DIGITS; d++) {
            const int64_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (int64_t q = 0; q < n; q++) {
            const int64_t to = count[(ka[q] >> shift) & (DIGITS - 1)]++;
            kb[to] = ka[q];
            ib[to] = ia[q];
        }
        uint64_t *kt = ka;
        ka = kb;
        kb = kt;
        int64_t *it = ia;
        ia = ib;
        ib = it;
    }
    if (ka != key) {
        memcpy(key, ka, (size_t)n * sizeof *key);
        memcpy(idx, ia, (size_t)n * sizeof *idx);
    }
    free(k2);
    free(i2);
    free(count);
    return 0;
}
