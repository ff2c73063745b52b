/* Union-find (see union_find.h). */
#include "util/union_find.h"

void vc_uf_init(int64_t *parent, int64_t n)
{
    for (int64_t x = 0; x < n; x++)
        parent[x] = x;
}

int64_t vc_uf_count_roots(const int64_t *parent, int64_t n)
{
    int64_t roots = 0;
    for (int64_t x = 0; x < n; x++)
        roots += parent[x] == x;
    return roots;
}
