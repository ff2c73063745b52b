/* Skew faces mended at the seeds (vc_interior_unskew), on seed sets built
 * here: random interior seeds inside a shell of fixed seeds on the unit
 * sphere (not kept: they bound the cells, as outside seeds do), one small
 * ball in the middle.
 * - the faces above the target skewness (checkMesh's formula) are fewer
 *   after the moves, counted on the cells built again (the moves also
 *   mend faces of small interpolation weight or volume ratio and concave
 *   cells: checkMesh -allGeometry's limits);
 * - the fixed seeds and the seeds of no skew face stay; every moved seed
 *   within a quarter of its nearest-seed distance, none into the ball
 *   grown by the clearance;
 * - the same moves on 1 and 2 threads;
 * - a cubic lattice, where nothing fails: nothing moves;
 * - bad options are refused (VC_EPARAM). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"
#include "test_seed_shell.h"
#include "vorocrust/interior.h"
#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

/* Faces of m above limit (checkMesh's skewness). */
static int64_t skew_faces(const vc_polymesh *m, double limit)
{
    int64_t n = 0;
    for (int64_t f = 0; f < m->n_interior_faces; f++)
        n += vc_polymesh_face_skewness(m, f) > limit;
    return n;
}

int main(void)
{
    const int64_t n_surface = 600, n_int = 2500;
    /* random seeds have few faces above checkMesh's 4: a lower target gives
     * the test dozens to mend */
    const double target = 2.5;
    vc_seeds before, one, two;
    shell_seeds(&before, n_surface, n_int, 11, 0);
    shell_seeds(&one, n_surface, n_int, 11, 0);
    shell_seeds(&two, n_surface, n_int, 11, 0);
    double centre[3] = {0.05, -0.02, 0.03}, radius = 0.03, normal[3] = {0, 0, 1};
    signed char kind = 0;
    int64_t element = 0;
    vc_balls balls = {1, centre, &radius, &kind, &element, normal};

    vc_polymesh m0;
    if (shell_build(&before, &m0))
        return 1;
    const int64_t n0 = skew_faces(&m0, target);
    CHECKF(n0 >= 5, "random seeds with only %lld faces above %g: nothing to mend", (long long)n0,
           target);

    vc_unskew_options uo;
    vc_unskew_options_default(&uo);
    CHECK(uo.max_skew == 3.9 && uo.candidates == 16 && uo.clearance == VC_INTERIOR_CLEARANCE);
    uo.max_skew = target;
    uo.movable_begin = n_surface; /* the shell stays (n_surface 0 below: no
                                     label to keep, the shell's is 0) */
    vc_unskew_stats st1, st2;
    vc_error err;
    uo.threads = 1;
    CHECK(vc_interior_unskew(&balls, &one, 0, &m0, &uo, &st1, &err) == 0);
    uo.threads = 2;
    CHECK(vc_interior_unskew(&balls, &two, 0, &m0, &uo, &st2, &err) == 0);
    CHECK(memcmp(one.xyz, two.xyz, sizeof(double) * 3 * (size_t)one.n) == 0);
    CHECK(st1.n_moved == st2.n_moved && st1.n_skew_faces == n0);
    CHECK(memcmp(before.xyz, one.xyz, sizeof(double) * 3 * (size_t)n_surface) == 0);
    CHECKF(st1.n_moved > 0 && st1.n_moved <= st1.n_tried, "%lld moved of %lld tried",
           (long long)st1.n_moved, (long long)st1.n_tried);

    /* stuck: every seed tried is moved or flagged; a second call on the
     * same mesh tries none of the flagged ones, and moves none of them */
    {
        vc_seeds three;
        CHECK(vc_seeds_alloc(&three, before.n, &err) == 0);
        memcpy(three.xyz, before.xyz, sizeof(double) * 3 * (size_t)before.n);
        memcpy(three.label, before.label, sizeof(int32_t) * (size_t)before.n);
        unsigned char *stuck = calloc((size_t)before.n, 1);
        uo.stuck = stuck;
        vc_unskew_stats sa, sb;
        CHECK(vc_interior_unskew(&balls, &three, 0, &m0, &uo, &sa, &err) == 0);
        CHECK(memcmp(three.xyz, one.xyz, sizeof(double) * 3 * (size_t)one.n) == 0);
        int64_t flagged = 0;
        for (int64_t i = 0; i < before.n; i++)
            flagged += stuck[i];
        CHECKF(flagged == sa.n_tried - sa.n_moved && flagged > 0, "stuck: %lld flagged, %lld tried, "
               "%lld moved", (long long)flagged, (long long)sa.n_tried, (long long)sa.n_moved);
        memcpy(three.xyz, before.xyz, sizeof(double) * 3 * (size_t)before.n);
        CHECK(vc_interior_unskew(&balls, &three, 0, &m0, &uo, &sb, &err) == 0);
        CHECKF(sb.n_tried == sa.n_tried - flagged, "stuck: %lld tried again of %lld, %lld flagged",
               (long long)sb.n_tried, (long long)sa.n_tried, (long long)flagged);
        int64_t moved_flagged = 0;
        for (int64_t i = 0; i < before.n; i++)
            moved_flagged += stuck[i] && memcmp(three.xyz + 3 * i, before.xyz + 3 * i,
                                                3 * sizeof(double)) != 0;
        CHECK(moved_flagged == 0);
        uo.stuck = NULL;
        free(stuck);
        vc_seeds_free(&three);
    }

    vc_polymesh m1;
    if (shell_build(&one, &m1) == 0) {
        const int64_t n1 = skew_faces(&m1, target);
        CHECKF(n1 < n0, "faces above %g: %lld before, %lld after %lld moves", target,
               (long long)n0, (long long)n1, (long long)st1.n_moved);
        fprintf(stderr, "test_unskew_seeds: faces above %g: %lld -> %lld (%lld seeds moved of "
                "%lld tried, %lld cells built)\n", target, (long long)n0, (long long)n1,
                (long long)st1.n_moved, (long long)st1.n_tried, (long long)st1.n_cells_built);
        vc_polymesh_free(&m1);
    }

    /* moves within a quarter of the nearest-seed distance (as it was when
     * the seed moved: at most the distance before any move plus the moves
     * of the others, bounded here by the set before and after), none into
     * the ball grown by the clearance */
    int64_t far = 0, in_ball = 0;
    for (int64_t i = n_surface; i < before.n; i++) {
        double mv2 = 0, b2 = 0;
        for (int d = 0; d < 3; d++) {
            mv2 += (before.xyz[3 * i + d] - one.xyz[3 * i + d]) *
                   (before.xyz[3 * i + d] - one.xyz[3 * i + d]);
            b2 += (one.xyz[3 * i + d] - centre[d]) * (one.xyz[3 * i + d] - centre[d]);
        }
        if (mv2 == 0)
            continue;
        double nn2 = INFINITY;
        for (int64_t j = 0; j < before.n; j++) {
            if (j == i)
                continue;
            double d2 = 0, e2 = 0;
            for (int d = 0; d < 3; d++) {
                d2 += (before.xyz[3 * i + d] - before.xyz[3 * j + d]) *
                      (before.xyz[3 * i + d] - before.xyz[3 * j + d]);
                e2 += (before.xyz[3 * i + d] - one.xyz[3 * j + d]) *
                      (before.xyz[3 * i + d] - one.xyz[3 * j + d]);
            }
            d2 = d2 > e2 ? d2 : e2;
            nn2 = d2 < nn2 ? d2 : nn2;
        }
        far += mv2 > 0.0625 * nn2 * (1 + 1e-12);
        const double grown = radius * (1 + VC_INTERIOR_CLEARANCE);
        in_ball += b2 <= grown * grown;
    }
    CHECKF(far == 0, "%lld seeds moved beyond their picking region", (long long)far);
    CHECKF(in_ball == 0, "%lld seeds moved into the ball", (long long)in_ball);

    /* a cubic lattice (cubes: no skewness, no concave cell, weights 0.5,
     * equal volumes): nothing fails, nothing moves */
    vc_seeds lattice;
    CHECK(vc_seeds_alloc(&lattice, 216, &err) == 0);
    for (int64_t i = 0; i < 216; i++) {
        lattice.xyz[3 * i] = (double)(i % 6) + 0.5;
        lattice.xyz[3 * i + 1] = (double)(i / 6 % 6) + 0.5;
        lattice.xyz[3 * i + 2] = (double)(i / 36) + 0.5;
        lattice.label[i] = 1;
    }
    vc_polymesh ml;
    vc_unskew_stats st3;
    vc_unskew_options_default(&uo);
    double far_centre[3] = {-10, -10, -10};
    vc_balls far_ball = {1, far_centre, &radius, &kind, &element, normal};
    if (shell_build(&lattice, &ml) == 0) {
        vc_seeds same;
        CHECK(vc_seeds_alloc(&same, 216, &err) == 0);
        memcpy(same.xyz, lattice.xyz, sizeof(double) * 3 * 216);
        memcpy(same.label, lattice.label, sizeof(int32_t) * 216);
        CHECK(vc_interior_unskew(&far_ball, &same, 0, &ml, &uo, &st3, &err) == 0);
        CHECKF(st3.n_skew_faces == 0 && st3.n_weak_faces == 0 && st3.n_concave_cells == 0 &&
                   st3.n_moved == 0 && st3.max_skew < 1e-9,
               "lattice: %lld skew, %lld weak faces, %lld concave cells, %lld moved, max %g",
               (long long)st3.n_skew_faces, (long long)st3.n_weak_faces,
               (long long)st3.n_concave_cells, (long long)st3.n_moved, st3.max_skew);
        CHECK(memcmp(lattice.xyz, same.xyz, sizeof(double) * 3 * 216) == 0);
        vc_seeds_free(&same);
        vc_polymesh_free(&ml);
    }
    vc_seeds_free(&lattice);
    vc_seeds same;
    shell_seeds(&same, n_surface, n_int, 11, 0);

    /* bad options */
    uo.max_skew = 0;
    CHECK(vc_interior_unskew(&balls, &same, n_surface, &m0, &uo, &st3, &err) == VC_EPARAM);
    vc_unskew_options_default(&uo);
    uo.candidates = 0;
    CHECK(vc_interior_unskew(&balls, &same, n_surface, &m0, &uo, &st3, &err) == VC_EPARAM);
    vc_unskew_options_default(&uo);
    uo.n_sphere_seeds = 3; /* without their balls */
    CHECK(vc_interior_unskew(&balls, &same, n_surface, &m0, &uo, &st3, &err) == VC_EPARAM);

    vc_polymesh_free(&m0);
    vc_seeds_free(&before);
    vc_seeds_free(&one);
    vc_seeds_free(&two);
    vc_seeds_free(&same);
    return failures != 0;
}
