/* The Voronoi engine's sphere lists (vc_voronoi_options.spheres): seeds on
 * one sphere, co-spherical only to rounding in doubles and with a pair of
 * them nearly coincident (which without the lists leaves a cluster of mesh
 * points near the centre), must meet in exactly one mesh point, at the
 * sphere's centre, with every cell valid, the volumes summing to the
 * box's, and 1 and 2 threads giving the same mesh. Lists that claim a
 * sphere the seeds are not on change nothing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

#include "test_check.h"
#include "test_polymesh_compare.h"

static const double CENTRE[3] = {0.123456789, 0.234567891, 0.345678912};
static const double RADIUS = 0.3;
#define N_ON 40
#define N_OUT 200

static void unit(vc_rng *r, double u[3])
{
    double l;
    do {
        for (int d = 0; d < 3; d++)
            u[d] = 2 * vc_rng_uniform(r) - 1;
        l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    } while (!(l > 0.1 && l <= 1));
    for (int d = 0; d < 3; d++)
        u[d] /= l;
}

/* N_ON seeds on the sphere (the last two 1e-9 of the radius apart), then
 * N_OUT seeds outside it, between 1.5 and 3 radii from its centre. */
static int make_seeds(vc_seeds *s)
{
    vc_error err = {0, ""};
    if (vc_seeds_alloc(s, N_ON + N_OUT, &err))
        return -1;
    vc_rng r;
    vc_rng_init(&r, 7, 0);
    double u[3];
    for (int i = 0; i < N_ON - 1; i++) {
        unit(&r, u);
        for (int d = 0; d < 3; d++)
            s->xyz[3 * i + d] = CENTRE[d] + RADIUS * u[d];
    }
    /* the last: near the one before, moved along the sphere */
    const double *p = s->xyz + 3 * (N_ON - 2);
    double q[3], t[3] = {1, 2, 3}, n[3];
    for (int d = 0; d < 3; d++)
        n[d] = (p[d] - CENTRE[d]) / RADIUS;
    const double dn = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
    double lt = 0;
    for (int d = 0; d < 3; d++) {
        t[d] -= dn * n[d];
        lt += t[d] * t[d];
    }
    lt = sqrt(lt);
    double lq = 0;
    for (int d = 0; d < 3; d++) {
        q[d] = n[d] + 1e-9 * t[d] / lt;
        lq += q[d] * q[d];
    }
    lq = sqrt(lq);
    for (int d = 0; d < 3; d++)
        s->xyz[3 * (N_ON - 1) + d] = CENTRE[d] + RADIUS * q[d] / lq;
    for (int i = N_ON; i < N_ON + N_OUT; i++) {
        unit(&r, u);
        const double rr = RADIUS * (1.5 + 1.5 * vc_rng_uniform(&r));
        for (int d = 0; d < 3; d++)
            s->xyz[3 * i + d] = CENTRE[d] + rr * u[d];
    }
    return 0;
}

static int build(const char *name, const vc_seeds *s, const vc_seed_spheres *sp, int threads,
                 vc_polymesh *m)
{
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    opt.has_box = 1;
    for (int d = 0; d < 3; d++) {
        opt.box[d] = CENTRE[d] - 4 * RADIUS;
        opt.box[d + 3] = CENTRE[d] + 4 * RADIUS;
    }
    opt.threads = threads;
    opt.spheres = sp;
    vc_error err = {0, ""};
    if (vc_voronoi_build(s, &opt, m, &err) != 0) {
        CHECKF(0, "%s: build on %d thread(s) failed: %s", name, threads, err.msg);
        return -1;
    }
    char report[2048];
    const int64_t problems = vc_polymesh_validate(m, 0, report, sizeof report);
    CHECKF(problems == 0, "%s: %lld validation problems:\n%s", name, (long long)problems, report);
    double v = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        v += m->cell_volume[c];
    const double box = pow(8 * RADIUS, 3);
    CHECKF(fabs(v - box) <= 1e-12 * box, "%s: volume %.17g, box %.17g", name, v, box);
    CHECKF(m->n_cells == s->n, "%s: %lld cells for %lld seeds", name, (long long)m->n_cells,
           (long long)s->n);
    return 0;
}

/* Mesh points within reach of the centre; *exact: one of them is it. */
static int points_near_centre(const vc_polymesh *m, double reach, int *exact)
{
    int n = 0;
    *exact = 0;
    for (int64_t p = 0; p < m->n_points; p++) {
        const double *x = m->points + 3 * p;
        const double d = sqrt((x[0] - CENTRE[0]) * (x[0] - CENTRE[0]) +
                              (x[1] - CENTRE[1]) * (x[1] - CENTRE[1]) +
                              (x[2] - CENTRE[2]) * (x[2] - CENTRE[2]));
        if (d <= reach) {
            n++;
            *exact |= d == 0;
        }
    }
    return n;
}

int main(void)
{
    vc_seeds s;
    if (make_seeds(&s)) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    /* the lists: the first N_ON seeds on sphere 0 */
    double sphere[4] = {CENTRE[0], CENTRE[1], CENTRE[2], RADIUS};
    int64_t start[N_ON + N_OUT + 1], id[N_ON];
    for (int i = 0; i <= N_ON + N_OUT; i++)
        start[i] = i < N_ON ? i : N_ON;
    for (int i = 0; i < N_ON; i++)
        id[i] = 0;
    const vc_seed_spheres sp = {1, sphere, start, id};

    vc_polymesh plain, with[2];
    if (build("no lists", &s, NULL, 1, &plain) == 0) {
        int exact;
        const int n = points_near_centre(&plain, 1e-3 * RADIUS, &exact);
        printf("without the lists: %d mesh points within 1e-3 of the radius of the centre\n", n);
        CHECKF(n > 1, "without the lists, %d point near the centre: the case tests nothing", n);
        if (build("lists, 1 thread", &s, &sp, 1, &with[0]) == 0) {
            const int m = points_near_centre(&with[0], 1e-3 * RADIUS, &exact);
            printf("with the lists: %d mesh point(s) there, the centre itself: %s\n", m,
                   exact ? "yes" : "no");
            CHECKF(m == 1 && exact, "with the lists, %d points near the centre (exact: %d)", m,
                   exact);
            /* every cell of a seed on the sphere has the centre */
            int64_t missing = 0;
            for (int64_t c = 0; c < N_ON; c++) {
                int has = 0;
                for (int64_t k = with[0].cell_offsets[c]; k < with[0].cell_offsets[c + 1] && !has;
                     k++) {
                    const int64_t f = with[0].cell_faces[k];
                    for (int64_t j = with[0].face_offsets[f]; j < with[0].face_offsets[f + 1]; j++) {
                        const double *x = with[0].points + 3 * with[0].face_vertices[j];
                        has |= x[0] == CENTRE[0] && x[1] == CENTRE[1] && x[2] == CENTRE[2];
                    }
                }
                missing += !has;
            }
            printf("cells of the sphere's seeds without the centre: %lld of %d\n",
                   (long long)missing, N_ON);
            if (build("lists, 2 threads", &s, &sp, 2, &with[1]) == 0) {
                CHECKF(same_mesh(&with[0], &with[1]), "the meshes of 1 and 2 threads differ");
                vc_polymesh_free(&with[1]);
            }
            vc_polymesh_free(&with[0]);
        }
        /* lists that claim the outer seeds lie on the sphere change nothing */
        int64_t start_wrong[N_ON + N_OUT + 1], id_wrong[N_OUT];
        for (int i = 0; i <= N_ON + N_OUT; i++)
            start_wrong[i] = i <= N_ON ? 0 : i - N_ON;
        for (int i = 0; i < N_OUT; i++)
            id_wrong[i] = 0;
        const vc_seed_spheres wrong = {1, sphere, start_wrong, id_wrong};
        vc_polymesh w;
        if (build("wrong lists", &s, &wrong, 2, &w) == 0) {
            CHECKF(same_mesh(&plain, &w), "lists naming seeds off the sphere changed the mesh");
            vc_polymesh_free(&w);
        }
        vc_polymesh_free(&plain);
    }
    /* lists naming a sphere that is not there are refused */
    {
        int64_t start_bad[N_ON + N_OUT + 1], id_bad[1] = {1};
        for (int i = 0; i <= N_ON + N_OUT; i++)
            start_bad[i] = i == 0 ? 0 : 1;
        const vc_seed_spheres bad = {1, sphere, start_bad, id_bad};
        vc_voronoi_options opt;
        vc_voronoi_options_default(&opt);
        opt.spheres = &bad;
        vc_polymesh m;
        vc_error err = {0, ""};
        const int rc = vc_voronoi_build(&s, &opt, &m, &err);
        CHECKF(rc == VC_EPARAM, "lists naming sphere 1 of 1: code %d (%s)", rc, err.msg);
        if (rc == 0)
            vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("all sphere-list checks passed\n");
    return failures ? 1 : 0;
}
