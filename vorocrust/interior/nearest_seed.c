/* Nearest seed from the k-d tree (see nearest_seed.h). The surface seeds
 * crowd a thin shell: a uniform grid's shells of bins searched far through
 * empty bins from the middle of a large part. */
#include "nearest_seed.h"

#include <math.h>

int vc_nearest_seed_index_build(vc_seed_kdtree *t, const vc_seeds *s)
{
    return vc_seed_kdtree_build(t, s->xyz, s->n);
}

int64_t vc_nearest_seed(const vc_seed_kdtree *t, const double x[3], double *dist)
{
    vc_kd_hit h;
    if (vc_seed_kdtree_knn(t, x, 1, -1, &h) != 1) {
        *dist = INFINITY;
        return -1;
    }
    *dist = sqrt(h.d2);
    return h.seed;
}
