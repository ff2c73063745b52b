/* util/bigint.h against __int128 (values below 2^126) and against
 * identities at full width: (a + b) - b = a, a * b = b * a, (a * b) with a
 * carry through every limb, and overflow reported at the capacity. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "util/bigint.h"
#include "vorocrust/random.h"

#include "test_check.h"

typedef __int128 i128;

static vc_rng rng;

static uint64_t next(void) { return vc_rng_next(&rng); }

/* The value of a bigint that fits in 126 bits. */
static i128 value(const vc_bigint *a)
{
    i128 v = 0;
    for (int i = a->n - 1; i >= 0; i--)
        v = (v << 64) | (i128)a->d[i];
    return a->neg ? -v : v;
}

static int equal(const vc_bigint *a, const vc_bigint *b)
{
    return a->n == b->n && a->neg == b->neg && !memcmp(a->d, b->d, (size_t)a->n * sizeof a->d[0]);
}

int main(void)
{
    vc_rng_init(&rng, 9, 0);
    /* small values: every operation against __int128 */
    for (int t = 0; t < 20000; t++) {
        const int64_t ma = (int64_t)(next() >> (11 + next() % 40)) * ((next() & 1) ? -1 : 1);
        const int64_t mb = (int64_t)(next() >> (11 + next() % 40)) * ((next() & 1) ? -1 : 1);
        const int sa = (int)(next() % 60), sb = (int)(next() % 60);
        vc_bigint a, b, r;
        CHECK(vc_bigint_set(&a, ma, sa) == 0 && vc_bigint_set(&b, mb, sb) == 0);
        const i128 va = (i128)ma * ((i128)1 << sa), vb = (i128)mb * ((i128)1 << sb);
        CHECK(value(&a) == va && value(&b) == vb);
        CHECK(vc_bigint_add(&r, &a, &b) == 0 && value(&r) == va + vb);
        CHECK(vc_bigint_sub(&r, &a, &b) == 0 && value(&r) == va - vb);
        CHECK(vc_bigint_sign(&r) == ((va - vb > 0) - (va - vb < 0)));
        /* products below 2^110 */
        const int64_t pa = ma >> 12, pb = mb >> 12;
        CHECK(vc_bigint_set(&a, pa, sa / 4) == 0 && vc_bigint_set(&b, pb, sb / 4) == 0);
        const i128 xa = (i128)pa * ((i128)1 << (sa / 4)), xb = (i128)pb * ((i128)1 << (sb / 4));
        CHECK(vc_bigint_mul(&r, &a, &b) == 0 && value(&r) == xa * xb);
        /* in place */
        CHECK(vc_bigint_add(&a, &a, &a) == 0 && value(&a) == 2 * xa);
    }
    /* wide values: identities */
    for (int t = 0; t < 2000; t++) {
        vc_bigint a, b, c, r, q;
        CHECK(vc_bigint_set(&a, (int64_t)(next() >> 1) - (int64_t)(next() >> 1), (int)(next() % 300)) == 0);
        CHECK(vc_bigint_set(&b, (int64_t)(next() >> 1) - (int64_t)(next() >> 1), (int)(next() % 300)) == 0);
        CHECK(vc_bigint_set(&c, (int64_t)(next() >> 2), (int)(next() % 200)) == 0);
        CHECK(vc_bigint_mul(&a, &a, &c) == 0 && vc_bigint_mul(&b, &b, &c) == 0);
        CHECK(vc_bigint_add(&r, &a, &b) == 0 && vc_bigint_sub(&q, &r, &b) == 0 && equal(&q, &a));
        CHECK(vc_bigint_mul(&r, &a, &b) == 0 && vc_bigint_mul(&q, &b, &a) == 0 && equal(&r, &q));
        CHECK(vc_bigint_sub(&r, &a, &a) == 0 && vc_bigint_sign(&r) == 0);
    }
    /* (2^(64k) - 1)^2: a carry through every limb */
    {
        vc_bigint a, one, r, s;
        CHECK(vc_bigint_set(&a, 1, 64 * 8) == 0 && vc_bigint_set(&one, 1, 0) == 0);
        CHECK(vc_bigint_sub(&a, &a, &one) == 0 && a.n == 8);
        CHECK(vc_bigint_mul(&r, &a, &a) == 0 && r.n == 16);
        /* (2^512 - 1)^2 + 2 (2^512 - 1) + 1 = 2^1024 */
        CHECK(vc_bigint_add(&s, &r, &a) == 0 && vc_bigint_add(&s, &s, &a) == 0 &&
              vc_bigint_add(&s, &s, &one) == 0);
        CHECK(s.n == 17 && s.d[16] == 1);
        for (int i = 0; i < 16; i++)
            CHECK(s.d[i] == 0);
    }
    /* overflow at the capacity is reported and leaves the result 0, so a
     * chain of operations tested once at its end reads no garbage (an unset
     * result crashed the exact power side in Release) */
    {
        vc_bigint a, r, s;
        memset(&r, 0x5a, sizeof r);
        CHECK(vc_bigint_set(&a, 3, 64 * (VC_BIGINT_LIMBS / 2)) == 0);
        CHECK(vc_bigint_mul(&r, &a, &a) == -1);
        CHECK(r.n == 0 && r.neg == 0);
        memset(&r, 0x5a, sizeof r);
        CHECK(vc_bigint_set(&r, 1, 64 * VC_BIGINT_LIMBS) == -1);
        CHECK(r.n == 0 && r.neg == 0);
        CHECK(vc_bigint_set(&r, 1, -1) == -1 && r.n == 0);
        CHECK(vc_bigint_set(&a, 1, 0) == 0);
        for (int i = 0; i < VC_BIGINT_LIMBS; i++)
            a.d[i] = ~(uint64_t)0;
        a.n = VC_BIGINT_LIMBS;
        memset(&s, 0x5a, sizeof s);
        CHECK(vc_bigint_add(&s, &a, &a) == -1);
        CHECK(s.n == 0 && s.neg == 0);
    }
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("all bigint checks passed\n");
    return failures ? 1 : 0;
}
