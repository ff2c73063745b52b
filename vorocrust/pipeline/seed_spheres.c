/* The balls' spheres each seed lies on, for the Voronoi engine
 * (vc_seed_spheres): see seed_spheres.h. */
#include "seed_spheres.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balls/ball_set.h"
#include "util/small_sort.h"
#include "util/threads.h"

/* A seed lies on a sphere when its distance from the centre is the radius
 * to this share of it: the triplets' points are placed on their spheres
 * to rounding (about 1e-13 of the radius, limited by the coordinates'
 * size), the sphere seeds too; vc_ball_strictly_contains counts a point
 * inside only beyond 1e-9, so nothing this near a sphere is covered. */
#define ON_SPHERE 1e-9
/* spheres kept per seed (a point of k co-spherical balls lies on k) */
#define MAX_PER_SEED 8

typedef struct on_ctx {
    const vc_balls *b;
    const double *x;
    int64_t ids[MAX_PER_SEED];
    int n;
} on_ctx;

static int collect_on(void *ctx, int64_t i)
{
    on_ctx *c = ctx;
    const double *p = c->b->center + 3 * i;
    const double d = sqrt((c->x[0] - p[0]) * (c->x[0] - p[0]) + (c->x[1] - p[1]) * (c->x[1] - p[1]) +
                          (c->x[2] - p[2]) * (c->x[2] - p[2]));
    const double r = c->b->radius[i];
    if (fabs(d - r) <= ON_SPHERE * r && c->n < MAX_PER_SEED)
        c->ids[c->n++] = i;
    return 0;
}

#define ID_LESS(p, q) (*(p) < *(q))
VC_SMALL_SORT(sort_sphere_ids, int64_t, ID_LESS)

int vc_seed_spheres_find(const vc_balls *balls, const vc_seeds *seeds, int64_t n_near,
                         int threads, vc_seed_spheres_owned *out)
{
    memset(out, 0, sizeof *out);
    const int64_t n = seeds->n;
    if (balls->n == 0 || n == 0)
        return 0;
    if (n_near > n)
        n_near = n;
    vc_ball_set bs;
    if (vc_ball_set_build(&bs, balls, NULL))
        return -1;
    /* scratch for the seeds looked up only (the others are on none) */
    int64_t *ids = malloc(sizeof(int64_t) * MAX_PER_SEED * (size_t)(n_near > 0 ? n_near : 1));
    unsigned char *count = calloc((size_t)n, 1);
    out->start = malloc(sizeof(int64_t) * (size_t)(n + 1));
    out->sphere = malloc(sizeof(double) * 4 * (size_t)balls->n);
    int rc = 0;
    if (!ids || !count || !out->start || !out->sphere) {
        rc = -1;
        goto done;
    }
#pragma omp parallel for schedule(dynamic, 1024) num_threads(vc_threads_or_default(threads))
    for (int64_t s = 0; s < n_near; s++) {
        on_ctx c = {&bs.b, seeds->xyz + 3 * s, {0}, 0};
        vc_ball_set_query(&bs, c.x, 0, 1 + ON_SPHERE, 0.0, collect_on, &c);
        sort_sphere_ids(c.ids, c.n);
        memcpy(ids + MAX_PER_SEED * s, c.ids, sizeof(int64_t) * (size_t)c.n);
        count[s] = (unsigned char)c.n;
    }
    out->start[0] = 0;
    for (int64_t s = 0; s < n; s++)
        out->start[s + 1] = out->start[s] + count[s];
    out->id = malloc(sizeof(int64_t) * (size_t)(out->start[n] > 0 ? out->start[n] : 1));
    if (!out->id) {
        rc = -1;
        goto done;
    }
    for (int64_t s = 0; s < n_near; s++)
        memcpy(out->id + out->start[s], ids + MAX_PER_SEED * s, sizeof(int64_t) * count[s]);
    for (int64_t i = 0; i < balls->n; i++) {
        memcpy(out->sphere + 4 * i, balls->center + 3 * i, 3 * sizeof(double));
        out->sphere[4 * i + 3] = balls->radius[i];
    }
    out->view.n_spheres = balls->n;
    out->view.sphere = out->sphere;
    out->view.start = out->start;
    out->view.id = out->id;
done:
    free(ids);
    free(count);
    vc_ball_set_free(&bs);
    if (rc)
        vc_seed_spheres_free(out);
    return rc;
}

void vc_seed_spheres_free(vc_seed_spheres_owned *s)
{
    free(s->sphere);
    free(s->start);
    free(s->id);
    memset(s, 0, sizeof *s);
}
