/* Interior seeds on a cubic lattice (see include/vorocrust/interior.h).
 * The nearest surface seed of a lattice point is found through the Voronoi
 * engine's k-d tree of seeds (nearest_seed.h), the balls holding it through
 * the octree's k-d tree over the balls (ball_tree.h). */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ball_tree.h"
#include "nearest_seed.h"

double vc_interior_default_spacing(const vc_balls *balls, double max_size)
{
    double r = 0;
    for (int64_t i = 0; i < balls->n; i++)
        r = fmax(r, balls->radius[i]);
    if (max_size > 0 && max_size < r)
        r = max_size;
    return r;
}

int vc_interior_lattice(const vc_balls *balls, const vc_seeds *ss, double spacing, vc_seeds *out,
                        int64_t *n_interior, vc_error *err)
{
    memset(out, 0, sizeof *out);
    *n_interior = 0;
    if (!(spacing > 0) || !isfinite(spacing))
        return vc_error_set(err, VC_EPARAM, "interior spacing must be positive, got %g", spacing);
    if (ss->n == 0)
        return vc_error_set(err, VC_EINPUT, "no surface seeds to place interior seeds against");
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < balls->n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], balls->center[3 * i + d]);
            hi[d] = fmax(hi[d], balls->center[3 * i + d]);
        }
    int64_t n[3];
    double count = 1;
    for (int d = 0; d < 3; d++) {
        n[d] = (int64_t)floor((hi[d] - lo[d]) / spacing) + 1;
        count *= (double)n[d];
    }
    if (count > 1e9)
        return vc_error_set(err, VC_EPARAM, "interior spacing %g makes %.3g lattice points", spacing,
                            count);
    vc_ball_tree tree;
    vc_seed_kdtree g;
    memset(&tree, 0, sizeof tree);
    memset(&g, 0, sizeof g);
    if (vc_ball_tree_build(&tree, balls) || vc_nearest_seed_index_build(&g, ss)) {
        vc_ball_tree_free(&tree);
        vc_seed_kdtree_free(&g);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the interior seeds");
    }
    int rc = 0;
    double *pts = NULL;
    int32_t *lab = NULL; /* the nearest surface seed's label: the region */
    int64_t np = 0, cap = 0;
    /* centre the lattice in the box */
    double off[3];
    for (int d = 0; d < 3; d++)
        off[d] = lo[d] + 0.5 * ((hi[d] - lo[d]) - (double)(n[d] - 1) * spacing);
    for (int64_t k = 0; k < n[2] && !rc; k++)
        for (int64_t j = 0; j < n[1] && !rc; j++)
            for (int64_t i = 0; i < n[0] && !rc; i++) {
                double x[3] = {off[0] + (double)i * spacing, off[1] + (double)j * spacing,
                               off[2] + (double)k * spacing};
                if (vc_ball_tree_covers_scaled(&tree, x, 1 + VC_INTERIOR_CLEARANCE))
                    continue;
                double dn;
                int64_t q = vc_nearest_seed(&g, x, &dn);
                if (q < 0 || ss->label[q] == 0 || dn < 0.5 * spacing)
                    continue;
                if (np == cap) {
                    cap = cap ? 2 * cap : 4096;
                    double *t = realloc(pts, sizeof(double) * 3 * (size_t)cap);
                    if (t)
                        pts = t;
                    int32_t *l = realloc(lab, sizeof(int32_t) * (size_t)cap);
                    if (l)
                        lab = l;
                    if (!t || !l) {
                        rc = -1;
                        break;
                    }
                }
                memcpy(pts + 3 * np, x, sizeof x);
                lab[np] = ss->label[q];
                np++;
            }
    vc_ball_tree_free(&tree);
    vc_seed_kdtree_free(&g);
    const vc_seeds interior = {np, pts, lab};
    if (!rc && vc_seeds_concat(ss, &interior, out, err) == 0) {
        *n_interior = np;
        free(pts);
        free(lab);
        return 0;
    }
    free(pts);
    free(lab);
    return rc ? vc_error_set(err, VC_ENOMEM, "out of memory for the interior seeds")
              : (err ? err->code : VC_ENOMEM);
}
