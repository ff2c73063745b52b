/* Pole seeds (see include/vorocrust/interior.h and
 * docs/solver-grade-cells.md).
 *
 * The surface seeds of one side of a ball lie on its sphere and, where the
 * surface is smooth, nearly on one plane parallel to it: nearly on one
 * circle. Below the ball centre their cells then meet along a nearly
 * degenerate fan around the circle's axis, every sphere through three of
 * them passing near the others, and wherever an interior seed cuts that
 * fan it makes short edges and sliver faces (three quarters of the short
 * edges of the torus' mesh). A seed at the pole of the sphere, on the
 * axis, takes the whole axis below the centre (along it the pole is nearer
 * than any point of the circle), so the fan ends at the centre, where all
 * these seeds are co-spherical by construction: one vertex for the engine,
 * no edge. */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ball_tree.h"
#include "nearest_seed.h"
#include "voronoi/seed_kdtree.h"

/* Another pole nearer than this share of the ball's radius makes the
 * later one (by ball index) redundant: near-coincident seeds. */
#define MIN_POLE_SEPARATION 0.25
/* Poles compared for that, the nearest first. */
enum { SEPARATION_NEIGHBOURS = 8 };

int vc_interior_pole_seeds(const vc_balls *balls, const vc_seeds *surface_seeds, double gap,
                           vc_seeds *out, int64_t **ball_of, vc_error *err)
{
    memset(out, 0, sizeof *out);
    *ball_of = NULL;
    if (balls->n == 0 || surface_seeds->n == 0)
        return 0;
    if (!(gap >= 0 && gap < 1))
        return vc_error_set(err, VC_EPARAM, "pole seeds: bad gap %g", gap);
    vc_ball_tree tree;
    vc_seed_kdtree nearest, poles;
    memset(&nearest, 0, sizeof nearest);
    memset(&poles, 0, sizeof poles);
    const int64_t nc = 2 * balls->n;
    double *cand = malloc(sizeof(double) * 3 * (size_t)nc);
    int32_t *label = malloc(sizeof(int32_t) * (size_t)nc);
    vc_kd_hit hit[SEPARATION_NEIGHBOURS];
    int rc = 0, have_tree = 0;
    if (!cand || !label || vc_ball_tree_build(&tree, balls) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the pole seeds");
        goto done;
    }
    have_tree = 1;
    if (vc_nearest_seed_index_build(&nearest, surface_seeds) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the pole seeds");
        goto done;
    }
    /* Both poles of every ball on its normal; a pole is kept when it lies
     * outside every other ball by the gap (its own sphere holds it: a
     * tie at the centre) and its nearest surface seed is an inside seed,
     * whose label it takes: one pole per side for a ball on an interface
     * between two regions. */
    const double margin = sqrt(1 + gap);
    int64_t n = 0;
#pragma omp parallel for schedule(static) reduction(+ : n) if (balls->n > 4096)
    for (int64_t b = 0; b < balls->n; b++) {
        const double *c = balls->center + 3 * b, *nrm = balls->normal + 3 * b;
        const double r = balls->radius[b];
        for (int side = 0; side < 2; side++) {
            const int64_t k = 2 * b + side;
            const double s = side ? r : -r;
            double *q = cand + 3 * k;
            for (int d = 0; d < 3; d++)
                q[d] = c[d] + s * nrm[d];
            label[k] = 0;
            if (vc_ball_tree_covers_scaled_except(&tree, q, margin, b))
                continue;
            double dist;
            const int64_t ns = vc_nearest_seed(&nearest, q, &dist);
            if (ns < 0 || surface_seeds->label[ns] == 0)
                continue;
            label[k] = surface_seeds->label[ns];
            n++;
        }
    }
    /* Near-coincident poles (balls nearly concentric): the first by index
     * stays. */
    if (vc_seed_kdtree_build(&poles, cand, nc) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the pole seeds");
        goto done;
    }
    for (int64_t k = 0; k < nc; k++) {
        if (!label[k])
            continue;
        const double sep = MIN_POLE_SEPARATION * balls->radius[k / 2];
        const int m = vc_seed_kdtree_knn(&poles, cand + 3 * k, SEPARATION_NEIGHBOURS, k, hit);
        for (int j = 0; j < m && hit[j].d2 < sep * sep; j++)
            if (hit[j].seed < k && label[hit[j].seed]) {
                label[k] = 0;
                n--;
                break;
            }
    }
    if (n > 0) {
        if ((rc = vc_seeds_alloc(out, n, err)) != 0)
            goto done;
        *ball_of = malloc(sizeof(int64_t) * (size_t)n);
        if (!*ball_of) {
            vc_seeds_free(out);
            rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the pole seeds");
            goto done;
        }
        int64_t i = 0;
        for (int64_t k = 0; k < nc; k++)
            if (label[k]) {
                memcpy(out->xyz + 3 * i, cand + 3 * k, 3 * sizeof(double));
                (*ball_of)[i] = k / 2;
                out->label[i++] = label[k];
            }
    }

done:
    vc_seed_kdtree_free(&nearest);
    vc_seed_kdtree_free(&poles);
    if (have_tree)
        vc_ball_tree_free(&tree);
    free(cand);
    free(label);
    return rc;
}
