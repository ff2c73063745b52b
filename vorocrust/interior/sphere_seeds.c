/* Seeds on the balls' spheres (see include/vorocrust/interior.h and
 * docs/solver-grade-cells.md).
 *
 * Every seed on a ball's sphere is at the same distance from its centre,
 * so their cells meet there in a fan of cones, thin near the centre.
 *
 * Poles (--protect): the surface seeds of one side of a ball lie, where the
 * surface is smooth, nearly on one circle of its sphere, and below the
 * ball centre their cells meet along a nearly degenerate fan around the
 * circle's axis; wherever an interior seed cuts that fan it makes short
 * edges and sliver faces (three quarters of the short edges of the torus'
 * mesh). A seed at the pole of the sphere, on the axis, takes the whole
 * axis below the centre (along it the pole is nearer than any point of the
 * circle), so the fan ends at the centre, where all these seeds are
 * co-spherical by construction: one vertex for the engine, no edge.
 *
 * Caps (default): a corner or edge ball carries tens of seeds on its
 * sphere, on the rings where the small balls around it cross it, and the
 * rest of its inner sphere is empty: the cones of the ring seeds reach
 * across the ball, and the interior seeds beyond its sphere cut them at
 * uneven depths, leaving faces near the centre between cones whose bodies
 * lie far apart (the skew faces OpenFOAM counts: bunny.off 223 above 4,
 * cow.off 1,012, nearly all at corner and edge balls). Seeds spread over
 * the empty part of the sphere give every cone an end at the sphere. */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ball_tree.h"
#include "nearest_seed.h"
#include "voronoi/seed_kdtree.h"

/* Another sphere seed nearer than this share of the ball's radius makes
 * the later one (by candidate order) redundant: near-coincident seeds. */
#define MIN_POLE_SEPARATION 0.25
/* Sphere seeds compared for that, the nearest first. */
enum { SEPARATION_NEIGHBOURS = 8 };
/* Candidate directions on the sphere of a corner or edge ball (a
 * Fibonacci lattice: about 0.5 radian apart), and how far a cap keeps from
 * every surface seed (a share of its ball's radius): nearer, it thins the
 * cell of that seed (bracket.obj's fattest cell 8.9 to 9.6 at 0; 0.25 and
 * 0.5 leave it, with as few skew faces). */
enum { CAP_DIRECTIONS = 48 };
#define CAP_SURFACE_SEPARATION 0.5

/* Direction i of n spread evenly over the unit sphere. */
static void fibonacci_direction(int i, int n, double u[3])
{
    const double golden = acos(-1.0) * (3 - sqrt(5.0));
    const double z = 1 - (2 * i + 1) / (double)n;
    const double rr = sqrt(1 - z * z), phi = golden * i;
    u[0] = rr * cos(phi);
    u[1] = rr * sin(phi);
    u[2] = z;
}

void vc_sphere_seed_options_default(vc_sphere_seed_options *opt)
{
    opt->poles = 0;
    opt->pole_gap = 0;
    opt->caps = 1;
}

int vc_interior_sphere_seeds(const vc_balls *balls, const vc_seeds *surface_seeds,
                             const vc_sphere_seed_options *opt, vc_seeds *out,
                             int64_t **ball_of, vc_error *err)
{
    memset(out, 0, sizeof *out);
    *ball_of = NULL;
    if (opt->poles && !(opt->pole_gap >= 0 && opt->pole_gap < 1))
        return vc_error_set(err, VC_EPARAM, "pole seeds: bad gap %g", opt->pole_gap);
    if (balls->n == 0 || surface_seeds->n == 0 || (!opt->poles && !opt->caps))
        return 0;
    /* the candidates: both poles of every ball (when asked), then the cap
     * directions of every corner and edge ball (when asked), each with its
     * ball */
    int64_t nc = opt->poles ? 2 * balls->n : 0;
    if (opt->caps)
        for (int64_t b = 0; b < balls->n; b++)
            nc += balls->kind[b] != VC_BALL_SURFACE ? CAP_DIRECTIONS : 0;
    if (nc == 0)
        return 0;
    vc_ball_tree tree;
    vc_seed_kdtree nearest, poles;
    memset(&nearest, 0, sizeof nearest);
    memset(&poles, 0, sizeof poles);
    double *cand = malloc(sizeof(double) * 3 * (size_t)nc);
    int32_t *label = malloc(sizeof(int32_t) * (size_t)nc);
    int64_t *cand_ball = malloc(sizeof(int64_t) * (size_t)nc);
    vc_kd_hit hit[SEPARATION_NEIGHBOURS];
    int rc = 0, have_tree = 0;
    if (cand_ball) {
        int64_t k = 0;
        if (opt->poles)
            for (int64_t b = 0; b < balls->n; b++) {
                cand_ball[k++] = b;
                cand_ball[k++] = b;
            }
        if (opt->caps)
            for (int64_t b = 0; b < balls->n; b++)
                for (int j = 0; balls->kind[b] != VC_BALL_SURFACE && j < CAP_DIRECTIONS; j++)
                    cand_ball[k++] = b;
    }
    const int64_t n_pole_cand = opt->poles ? 2 * balls->n : 0;
    if (!cand || !label || !cand_ball || vc_ball_tree_build(&tree, balls) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the sphere seeds");
        goto done;
    }
    have_tree = 1;
    if (vc_nearest_seed_index_build(&nearest, surface_seeds) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the sphere seeds");
        goto done;
    }
    /* A candidate is kept when it lies outside every other ball by the
     * margin (its own sphere holds it: a tie at the centre) and its nearest
     * surface seed is an inside seed, whose label it takes: one pole per
     * side for a ball on an interface between two regions; a cap also
     * keeps clear of the surface seeds. Poles keep the protection's gap,
     * caps the interior seeds' clearance (VC_INTERIOR_CLEARANCE). */
    const double pole_margin = sqrt(1 + opt->pole_gap), cap_margin = 1 + VC_INTERIOR_CLEARANCE;
    int64_t n = 0;
#pragma omp parallel for schedule(static) reduction(+ : n) if (nc > 8192)
    for (int64_t k = 0; k < nc; k++) {
        const int64_t b = cand_ball[k];
        const double *c = balls->center + 3 * b, *nrm = balls->normal + 3 * b;
        const double r = balls->radius[b];
        const int cap = k >= n_pole_cand;
        double u[3];
        if (cap)
            fibonacci_direction((int)((k - n_pole_cand) % CAP_DIRECTIONS), CAP_DIRECTIONS, u);
        else
            for (int d = 0; d < 3; d++)
                u[d] = (k & 1) ? nrm[d] : -nrm[d];
        double *q = cand + 3 * k;
        for (int d = 0; d < 3; d++)
            q[d] = c[d] + r * u[d];
        label[k] = 0;
        if (vc_ball_tree_covers_scaled_except(&tree, q, cap ? cap_margin : pole_margin, b))
            continue;
        double dist;
        const int64_t ns = vc_nearest_seed(&nearest, q, &dist);
        if (ns < 0 || surface_seeds->label[ns] == 0 ||
            (cap && dist < CAP_SURFACE_SEPARATION * r))
            continue;
        label[k] = surface_seeds->label[ns];
        n++;
    }
    /* Near-coincident sphere seeds (balls nearly concentric, a cap next to
     * a pole): the first candidate stays. */
    if (vc_seed_kdtree_build(&poles, cand, nc) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the sphere seeds");
        goto done;
    }
    for (int64_t k = 0; k < nc; k++) {
        if (!label[k])
            continue;
        const double sep = MIN_POLE_SEPARATION * balls->radius[cand_ball[k]];
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
            rc = vc_error_set(err, VC_ENOMEM, "out of memory placing the sphere seeds");
            goto done;
        }
        int64_t i = 0;
        for (int64_t k = 0; k < nc; k++)
            if (label[k]) {
                memcpy(out->xyz + 3 * i, cand + 3 * k, 3 * sizeof(double));
                (*ball_of)[i] = cand_ball[k];
                out->label[i++] = label[k];
            }
    }

done:
    vc_seed_kdtree_free(&nearest);
    vc_seed_kdtree_free(&poles);
    if (have_tree)
        vc_ball_tree_free(&tree);
    free(cand);
    free(cand_ball);
    free(label);
    return rc;
}
