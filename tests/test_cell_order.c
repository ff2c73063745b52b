/* The cell order (polymesh.h: vc_polymesh_rcm_order, _renumber_cells): on
 * the Voronoi mesh of random seeds in a box and of seeds crowded near a
 * sphere (as VoroCrust's), reverse Cuthill-McKee must cut the matrix
 * bandwidth several times, and renumbering (by it, and by a random
 * permutation, which turns many faces) must keep a valid mesh: the
 * validator passes, owner < neighbour and normals from owner to neighbour
 * seed, the same cells (seed, volume), the same cell pairs across faces,
 * the same boundary, the same total volume, the same points. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/polymesh.h"
#include "vorocrust/random.h"
#include "vorocrust/seeds.h"
#include "vorocrust/voronoi.h"

#include "test_check.h"

static int cmp_pair(const void *p, const void *q)
{
    const int64_t *a = p, *b = q;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* The interior faces as sorted seed pairs (n_interior_faces pairs). */
static int64_t *seed_pairs(const vc_polymesh *m)
{
    int64_t *p = malloc(sizeof(int64_t) * 2 * (size_t)(m->n_interior_faces + 1));
    for (int64_t f = 0; f < m->n_interior_faces; f++) {
        int64_t a = m->cell_seed[m->face_owner[f]], b = m->cell_seed[m->face_neighbour[f]];
        p[2 * f] = a < b ? a : b;
        p[2 * f + 1] = a < b ? b : a;
    }
    qsort(p, (size_t)m->n_interior_faces, sizeof(int64_t) * 2, cmp_pair);
    return p;
}

static double total_volume(const vc_polymesh *m)
{
    double v = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        v += m->cell_volume[c];
    return v;
}

/* m renumbered by new_of_old must be the same mesh as ref, in another order. */
static void check_renumbered(const char *name, const vc_polymesh *ref, vc_polymesh *m,
                             const int64_t *new_of_old)
{
    CHECK(vc_polymesh_renumber_cells(m, new_of_old) == 0);
    char report[2048];
    const int64_t problems = vc_polymesh_validate(m, 0, report, sizeof report);
    if (problems)
        fprintf(stderr, "%s: %lld problems:\n%s", name, (long long)problems, report);
    CHECK(problems == 0);
    CHECK(m->n_cells == ref->n_cells && m->n_faces == ref->n_faces &&
          m->n_interior_faces == ref->n_interior_faces && m->n_points == ref->n_points);
    for (int64_t c = 0; c < ref->n_cells; c++) {
        const int64_t k = new_of_old[c];
        CHECK(m->cell_seed[k] == ref->cell_seed[c]);
        CHECK(m->cell_volume[k] == ref->cell_volume[c]);
    }
    int bad_order = 0, bad_normal = 0;
    for (int64_t f = 0; f < m->n_interior_faces; f++) {
        const int64_t o = m->face_owner[f], b = m->face_neighbour[f];
        bad_order += !(o < b) || (f > 0 && (m->face_owner[f - 1] > o ||
                                             (m->face_owner[f - 1] == o && m->face_neighbour[f - 1] >= b)));
        const double *so = m->seed_xyz + 3 * m->cell_seed[o], *sb = m->seed_xyz + 3 * m->cell_seed[b];
        const double *n = m->face_normal + 3 * f;
        bad_normal += (sb[0] - so[0]) * n[0] + (sb[1] - so[1]) * n[1] + (sb[2] - so[2]) * n[2] <= 0;
    }
    CHECK(bad_order == 0);
    CHECK(bad_normal == 0);
    int64_t *pa = seed_pairs(ref), *pb = seed_pairs(m);
    CHECK(memcmp(pa, pb, sizeof(int64_t) * 2 * (size_t)ref->n_interior_faces) == 0);
    free(pa);
    free(pb);
    CHECK(fabs(total_volume(m) - total_volume(ref)) <= 1e-12 * total_volume(ref));
}

static void run_case(const char *name, const vc_seeds *s, const double box[6], int64_t min_gain)
{
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    opt.has_box = 1;
    memcpy(opt.box, box, sizeof opt.box);
    vc_polymesh ref, m;
    vc_error err = {0, ""};
    if (vc_voronoi_build(s, &opt, &ref, &err) != 0 || vc_voronoi_build(s, &opt, &m, &err) != 0) {
        fprintf(stderr, "%s: %s\n", name, err.msg);
        failures++;
        return;
    }
    const int64_t n = ref.n_cells;
    int64_t *order = malloc(sizeof(int64_t) * (size_t)n);
    CHECK(vc_polymesh_rcm_order(&ref, order) == 0);
    /* a permutation */
    unsigned char *seen = calloc((size_t)n, 1);
    int perm_ok = 1;
    for (int64_t c = 0; c < n; c++) {
        perm_ok &= order[c] >= 0 && order[c] < n && !seen[order[c]];
        if (order[c] >= 0 && order[c] < n)
            seen[order[c]] = 1;
    }
    CHECK(perm_ok);
    free(seen);
    const int64_t before = vc_polymesh_bandwidth(&ref);
    check_renumbered(name, &ref, &m, order);
    const int64_t after = vc_polymesh_bandwidth(&m);
    printf("%s: %lld cells, bandwidth %lld in seed order, %lld after reverse Cuthill-McKee\n", name,
           (long long)n, (long long)before, (long long)after);
    CHECK(after * min_gain <= before);
    /* any permutation (turns about half the faces) */
    vc_polymesh m2;
    if (vc_voronoi_build(s, &opt, &m2, &err) == 0) {
        vc_rng rng;
        vc_rng_init(&rng, 7, 0);
        for (int64_t c = 0; c < n; c++)
            order[c] = c;
        for (int64_t c = n - 1; c > 0; c--) {
            const int64_t j = (int64_t)(vc_rng_uniform(&rng) * (double)(c + 1)) % (c + 1);
            const int64_t t = order[c];
            order[c] = order[j];
            order[j] = t;
        }
        check_renumbered(name, &ref, &m2, order);
        vc_polymesh_free(&m2);
    }
    free(order);
    vc_polymesh_free(&ref);
    vc_polymesh_free(&m);
}

int main(void)
{
    vc_rng rng;
    vc_rng_init(&rng, 3, 0);
    const int64_t n = 8000;
    vc_seeds s;
    vc_seeds_alloc(&s, n, NULL);
    for (int64_t i = 0; i < 3 * n; i++)
        s.xyz[i] = vc_rng_uniform(&rng);
    /* random seeds in random order: the engine's order by seed has no
     * locality at all, as VoroCrust's surface-then-interior one */
    const double box[6] = {0, 0, 0, 1, 1, 1};
    run_case("random", &s, box, 5);
    /* crowded near a sphere: pairs on both sides, sparse inside */
    for (int64_t i = 0; i < n; i++) {
        double p[3], r2 = 0;
        for (int d = 0; d < 3; d++) {
            p[d] = vc_rng_uniform(&rng) * 2 - 1;
            r2 += p[d] * p[d];
        }
        const double r = sqrt(r2), shell = i < n / 2 ? (i % 2 ? 0.81 : 0.79) : 0.7 * vc_rng_uniform(&rng);
        for (int d = 0; d < 3; d++)
            s.xyz[3 * i + d] = r > 0 ? 1 + shell * p[d] / r : 1;
    }
    const double box2[6] = {0, 0, 0, 2, 2, 2};
    run_case("shell", &s, box2, 4);
    vc_seeds_free(&s);
    if (failures)
        fprintf(stderr, "test_cell_order: %d failures\n", failures);
    return failures != 0;
}
