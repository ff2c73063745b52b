/* Seed sets for the tests of the interior seeds' moves (test_protect_seeds,
 * test_unskew_seeds): random interior seeds inside a shell of seeds on the
 * unit sphere, and their Voronoi mesh. Include after test_check.h. */
#ifndef VC_TEST_SEED_SHELL_H
#define VC_TEST_SEED_SHELL_H

#include <math.h>

#include "vorocrust/random.h"
#include "vorocrust/seeds.h"
#include "vorocrust/voronoi.h"

/* The mesh of s on 2 threads; a failed build is a failed check. */
static int shell_build(const vc_seeds *s, vc_polymesh *m)
{
    vc_voronoi_options vo;
    vc_voronoi_options_default(&vo);
    vo.threads = 2;
    vc_error err;
    const int rc = vc_voronoi_build(s, &vo, m, &err);
    CHECK_MSG(rc == 0, err.msg);
    return rc;
}

/* n_surface points on the unit sphere (label shell_label: 0 when they only
 * bound the others' cells, as VoroCrust's outside seeds do) and then n_int
 * random points in the ball of radius 0.8 (label 1), from the random
 * stream rng_seed. */
static void shell_seeds(vc_seeds *s, int64_t n_surface, int64_t n_int, uint64_t rng_seed,
                        int32_t shell_label)
{
    vc_error err;
    CHECK(vc_seeds_alloc(s, n_surface + n_int, &err) == 0);
    vc_rng rng;
    vc_rng_init(&rng, rng_seed, 0);
    for (int64_t i = 0; i < s->n; i++) {
        double u[3], q = 2;
        while (q > 1 || q < 1e-6) {
            for (int d = 0; d < 3; d++)
                u[d] = 2 * vc_rng_uniform(&rng) - 1;
            q = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        }
        const double scale = i < n_surface ? 1 / sqrt(q) : 0.8;
        for (int d = 0; d < 3; d++)
            s->xyz[3 * i + d] = scale * u[d];
        s->label[i] = i < n_surface ? shell_label : 1;
    }
}

#endif
