/* Signed integers of a fixed capacity (VC_BIGINT_LIMBS 64-bit limbs,
 * sign and magnitude), for exact determinants whose entries are doubles
 * brought to one binary exponent (the Voronoi engine's exact ties,
 * voronoi/power_side.c). Small and on the stack: faster than floating-point
 * expansions for the same determinant. Every operation reports an
 * overflow of the capacity (the caller then takes another path) and then
 * leaves its result 0. */
#ifndef VC_UTIL_BIGINT_H
#define VC_UTIL_BIGINT_H

#include <stdint.h>

#define VC_BIGINT_LIMBS 24

typedef struct vc_bigint {
    int n;   /* limbs in use (0: the value is 0) */
    int neg; /* 1 when negative (never for 0) */
    uint64_t d[VC_BIGINT_LIMBS]; /* magnitude, least significant first */
} vc_bigint;

/* r = m * 2^shift (shift >= 0). Returns 0, or -1 when it does not fit. */
int vc_bigint_set(vc_bigint *r, int64_t m, int shift);
/* r = a + b and r = a - b (r may be a or b). Return 0, or -1 on overflow. */
int vc_bigint_add(vc_bigint *r, const vc_bigint *a, const vc_bigint *b);
int vc_bigint_sub(vc_bigint *r, const vc_bigint *a, const vc_bigint *b);
/* r = a * b (r may be a or b). Returns 0, or -1 on overflow. */
int vc_bigint_mul(vc_bigint *r, const vc_bigint *a, const vc_bigint *b);
/* -1, 0 or +1. */
static inline int vc_bigint_sign(const vc_bigint *a)
{
    return a->n == 0 ? 0 : (a->neg ? -1 : 1);
}

#endif
