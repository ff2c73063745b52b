/* util/csr_group.h against a direct count: random items with m keys each
 * (repeats within an item included, as a degenerate triangle has), some
 * left out by keep; every key's entries are the items holding it, in
 * increasing order, once per occurrence; empty inputs and keys no item
 * holds. */
#include <stdint.h>
#include <stdlib.h>

#include "util/csr_group.h"
#include "vorocrust/random.h"

#include "test_check.h"

static void check_case(int64_t n, int m, int64_t n_keys, int with_keep, vc_rng *rng)
{
    int64_t *key = malloc(sizeof *key * (size_t)(m * n + 1));
    unsigned char *keep = malloc((size_t)n + 1);
    for (int64_t i = 0; i < m * n; i++)
        key[i] = (int64_t)(vc_rng_uniform(rng) * (double)n_keys) % n_keys;
    for (int64_t i = 0; i < n; i++)
        keep[i] = vc_rng_uniform(rng) < 0.7;
    int64_t *start, *list;
    CHECK(vc_csr_group(key, n, m, n_keys, with_keep ? keep : NULL, &start, &list) == 0);
    CHECK(start[0] == 0);
    for (int64_t k = 0; k < n_keys; k++) {
        /* the expected entries: every kept item, once per time it holds k */
        int64_t at = start[k];
        for (int64_t i = 0; i < n; i++) {
            if (with_keep && !keep[i])
                continue;
            for (int j = 0; j < m; j++)
                if (key[m * i + j] == k) {
                    CHECKF(at < start[k + 1] && list[at] == i, "key %lld, item %lld", (long long)k,
                           (long long)i);
                    at++;
                }
        }
        CHECKF(at == start[k + 1], "key %lld: %lld entries, %lld expected", (long long)k,
               (long long)(start[k + 1] - start[k]), (long long)(at - start[k]));
    }
    free(start);
    free(list);
    free(key);
    free(keep);
}

int main(void)
{
    vc_rng rng;
    vc_rng_init(&rng, 7, 0);
    check_case(0, 3, 5, 0, &rng);
    check_case(1, 3, 1, 0, &rng);
    check_case(50, 3, 40, 0, &rng);  /* triangles at vertices */
    check_case(50, 3, 40, 1, &rng);  /* some triangles left out */
    check_case(200, 2, 500, 1, &rng); /* edges at vertices, most keys empty */
    check_case(300, 1, 7, 0, &rng);   /* one key per item */
    return failures != 0;
}
