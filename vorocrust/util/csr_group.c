/* Items grouped by key (see csr_group.h). */
#include "util/csr_group.h"

#include <stdlib.h>

int vc_csr_group(const int64_t *key, int64_t n, int m, int64_t n_keys, const unsigned char *keep,
                 int64_t **start, int64_t **list)
{
    int64_t *st = calloc((size_t)n_keys + 1, sizeof *st);
    int64_t *fill = malloc(((size_t)n_keys + 1) * sizeof *fill);
    int64_t total = 0;
    if (st && fill) {
        for (int64_t i = 0; i < n; i++)
            if (!keep || keep[i])
                for (int j = 0; j < m; j++)
                    st[key[m * i + j] + 1]++;
        for (int64_t k = 0; k < n_keys; k++)
            st[k + 1] += st[k];
        total = st[n_keys];
    }
    int64_t *ls = malloc((size_t)(total > 0 ? total : 1) * sizeof *ls);
    if (!st || !fill || !ls) {
        free(st);
        free(fill);
        free(ls);
        *start = *list = NULL;
        return -1;
    }
    for (int64_t k = 0; k <= n_keys; k++)
        fill[k] = st[k];
    for (int64_t i = 0; i < n; i++)
        if (!keep || keep[i])
            for (int j = 0; j < m; j++)
                ls[fill[key[m * i + j]]++] = i;
    free(fill);
    *start = st;
    *list = ls;
    return 0;
}
