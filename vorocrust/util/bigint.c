/* Fixed-capacity signed integers (see bigint.h). */
#include "bigint.h"

#include <string.h>

/* Drops the leading zero limbs; a zero is not negative. */
static void trim(vc_bigint *r)
{
    while (r->n > 0 && r->d[r->n - 1] == 0)
        r->n--;
    if (r->n == 0)
        r->neg = 0;
}

/* An overflow leaves r zero, a defined value: callers chain operations and
 * test the or of their results once, so a failed step must not leave
 * garbage for the next one to read (an unset limb count overran the stack). */
static int overflow(vc_bigint *r)
{
    r->n = 0;
    r->neg = 0;
    return -1;
}

int vc_bigint_set(vc_bigint *r, int64_t m, int shift)
{
    r->n = 0;
    r->neg = m < 0;
    if (m == 0) {
        r->neg = 0;
        return 0;
    }
    /* the magnitude (2^63 as well) without overflow */
    const uint64_t mag = m < 0 ? (uint64_t)0 - (uint64_t)m : (uint64_t)m;
    const int limb = shift / 64, bit = shift % 64;
    if (shift < 0 || limb + 2 > VC_BIGINT_LIMBS)
        return overflow(r);
    memset(r->d, 0, (size_t)(limb + 2) * sizeof r->d[0]);
    r->d[limb] = mag << bit;
    r->d[limb + 1] = bit ? mag >> (64 - bit) : 0;
    r->n = limb + 2;
    trim(r);
    return 0;
}

/* *r = *t, reading only the limbs in use (the capacity is several times
 * what a side test needs: copying all 24 limbs cost 4% of a lattice's
 * exact ties). */
static inline void assign(vc_bigint *r, const vc_bigint *t)
{
    if (r == t)
        return;
    r->n = t->n;
    r->neg = t->neg;
    memcpy(r->d, t->d, (size_t)t->n * sizeof t->d[0]);
}

/* |a| compared with |b|: -1, 0, +1. */
static int cmp_mag(const vc_bigint *a, const vc_bigint *b)
{
    if (a->n != b->n)
        return a->n < b->n ? -1 : 1;
    for (int i = a->n - 1; i >= 0; i--)
        if (a->d[i] != b->d[i])
            return a->d[i] < b->d[i] ? -1 : 1;
    return 0;
}

/* r = |a| + |b| with the sign neg. */
static int add_mag(vc_bigint *r, const vc_bigint *a, const vc_bigint *b, int neg)
{
    const int n = a->n > b->n ? a->n : b->n;
    uint64_t carry = 0;
    vc_bigint t;
    for (int i = 0; i < n; i++) {
        const uint64_t x = i < a->n ? a->d[i] : 0, y = i < b->n ? b->d[i] : 0;
        const uint64_t s = x + y, c1 = s < x;
        t.d[i] = s + carry;
        carry = c1 | (t.d[i] < s);
    }
    t.n = n;
    if (carry) {
        if (n >= VC_BIGINT_LIMBS)
            return overflow(r);
        t.d[t.n++] = 1;
    }
    t.neg = neg;
    trim(&t);
    assign(r, &t);
    return 0;
}

/* r = |a| - |b| (|a| >= |b|) with the sign neg. */
static void sub_mag(vc_bigint *r, const vc_bigint *a, const vc_bigint *b, int neg)
{
    uint64_t borrow = 0;
    vc_bigint t;
    for (int i = 0; i < a->n; i++) {
        const uint64_t x = a->d[i], y = i < b->n ? b->d[i] : 0;
        const uint64_t d = x - y, b1 = x < y;
        t.d[i] = d - borrow;
        borrow = b1 | (d < borrow);
    }
    t.n = a->n;
    t.neg = neg;
    trim(&t);
    assign(r, &t);
}

/* r = a + (negate_b ? -b : b). */
static int add_signed(vc_bigint *r, const vc_bigint *a, const vc_bigint *b, int negate_b)
{
    const int bneg = b->n ? b->neg ^ negate_b : 0;
    if (a->neg == bneg || a->n == 0 || b->n == 0) {
        if (a->n == 0) {
            assign(r, b);
            r->neg = bneg;
            return 0;
        }
        if (b->n == 0) {
            assign(r, a);
            return 0;
        }
        return add_mag(r, a, b, a->neg);
    }
    if (cmp_mag(a, b) >= 0)
        sub_mag(r, a, b, a->neg);
    else
        sub_mag(r, b, a, bneg);
    return 0;
}

int vc_bigint_add(vc_bigint *r, const vc_bigint *a, const vc_bigint *b)
{
    return add_signed(r, a, b, 0);
}

int vc_bigint_sub(vc_bigint *r, const vc_bigint *a, const vc_bigint *b)
{
    return add_signed(r, a, b, 1);
}

int vc_bigint_mul(vc_bigint *r, const vc_bigint *a, const vc_bigint *b)
{
    vc_bigint t;
    if (a->n == 0 || b->n == 0) {
        r->n = 0;
        r->neg = 0;
        return 0;
    }
    const int n = a->n + b->n;
    if (n - 1 > VC_BIGINT_LIMBS) /* the product has n or n - 1 limbs */
        return overflow(r);
    const int cap = n < VC_BIGINT_LIMBS ? n : VC_BIGINT_LIMBS;
    memset(t.d, 0, (size_t)cap * sizeof t.d[0]);
    uint64_t top = 0; /* limb n - 1 when it falls beyond the capacity */
    for (int i = 0; i < a->n; i++) {
        unsigned __int128 carry = 0;
        for (int j = 0; j < b->n; j++) {
            const int k = i + j;
            const unsigned __int128 p = (unsigned __int128)a->d[i] * b->d[j] + t.d[k] + carry;
            t.d[k] = (uint64_t)p;
            carry = p >> 64;
        }
        const int k = i + b->n;
        if (k < cap) {
            t.d[k] = (uint64_t)carry; /* first write of this limb in row i */
        } else if (carry) {
            top |= (uint64_t)carry;
        }
    }
    if (top)
        return overflow(r);
    t.n = cap;
    t.neg = a->neg ^ b->neg;
    trim(&t);
    assign(r, &t);
    return 0;
}
