/* Unit test of the octree interior (vc_interior_octree) on synthetic balls:
 * balls centred on a sphere of radius 1 (radius 0.12, one at the north pole
 * 0.03 to make the grading visible), an inside surface seed 0.05 below each
 * centre and an outside one 0.05 above. Checked against brute force:
 * - the leaves tile the forest's box (volumes add up), and every leaf is
 *   small enough: diagonal <= 2 r(centre), r(x) = min (r_p + L |x - p|);
 * - refinement went no further than the sizing asks: a leaf whose parent
 *   was already small enough can only come from the 2:1 balance;
 * - 2:1 balance: leaves that touch (even at a corner) differ by one level
 *   at most;
 * - every interior seed is a leaf centre outside every ball grown by the
 *   clearance (also with none), its nearest
 *   surface seed is an inside seed, and no surface seed is closer than
 *   half the leaf's side; every other leaf centre fails one of these;
 * - --max-size caps the leaves; 1 and 2 threads give the same seeds; two
 *   calls in one process;
 * - before the program initialises MPI, and after it finalises it, the
 *   octree is refused (VC_EPARAM): the library never starts MPI. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/interior.h"

#include "test_check.h"
#include "test_mpi.h"

static double dist(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* The sizing by brute force: r_p + L d within far_from radii of a ball's
 * centre, growing at far_lipschitz beyond. */
static double sizing(const vc_balls *b, const double x[3], const vc_octree_options *o, double cap)
{
    double r = cap;
    for (int64_t i = 0; i < b->n; i++) {
        const double d = dist(x, b->center + 3 * i), near = o->far_from * b->radius[i];
        r = fmin(r, b->radius[i] + (d <= near ? o->lipschitz * d
                                              : o->lipschitz * near + o->far_lipschitz * (d - near)));
    }
    return r;
}

/* n balls on the unit sphere (a Fibonacci spiral) and their seeds. */
static void make_sphere(int n, vc_balls *b, vc_seeds *s)
{
    memset(b, 0, sizeof *b);
    b->n = n;
    b->center = malloc(sizeof(double) * 3 * (size_t)n);
    b->radius = malloc(sizeof(double) * (size_t)n);
    b->kind = calloc((size_t)n, 1);
    b->element = calloc((size_t)n, sizeof(int64_t));
    b->normal = malloc(sizeof(double) * 3 * (size_t)n);
    vc_seeds_alloc(s, 2 * n, NULL);
    double golden = acos(-1.0) * (3 - sqrt(5.0));
    for (int i = 0; i < n; i++) {
        double z = 1 - 2 * (i + 0.5) / n, rr = sqrt(1 - z * z), t = golden * i;
        double p[3] = {rr * cos(t), rr * sin(t), z};
        if (i == 0) {
            p[0] = p[1] = 0;
            p[2] = 1;
        }
        memcpy(b->center + 3 * i, p, sizeof p);
        memcpy(b->normal + 3 * i, p, sizeof p);
        b->radius[i] = i == 0 ? 0.03 : 0.12;
        for (int d = 0; d < 3; d++) {
            s->xyz[3 * (2 * i) + d] = p[d] * 0.95;
            s->xyz[3 * (2 * i + 1) + d] = p[d] * 1.05;
        }
        s->label[2 * i] = 1;
        s->label[2 * i + 1] = 0;
    }
}

/* Closed cubes a and b intersect (touch included), with a tolerance. */
static int touch(const double *ca, double sa, const double *cb, double sb)
{
    for (int d = 0; d < 3; d++)
        if (fabs(ca[d] - cb[d]) > 0.5 * (sa + sb) * (1 + 1e-12))
            return 0;
    return 1;
}

/* A leaf the sizing does not bind (octree_seeds.c): no ball reaches within
 * its half diagonal of its centre, and the centre's nearest surface seed
 * is an outside one (brute force). */
static int outside_leaf(const vc_balls *b, const vc_seeds *ss, const double *c, double side)
{
    const double h = 0.5 * sqrt(3.0) * side;
    for (int64_t i = 0; i < b->n; i++)
        if (dist(b->center + 3 * i, c) <= b->radius[i] + h)
            return 0;
    int64_t best = -1;
    double bd = INFINITY;
    for (int64_t i = 0; i < ss->n; i++) {
        const double d = dist(ss->xyz + 3 * i, c);
        if (d < bd) {
            bd = d;
            best = i;
        }
    }
    return best >= 0 && ss->label[best] == 0;
}

static void check_forest(const vc_balls *b, const vc_seeds *ss, const vc_octree_options *o,
                         const vc_seeds *out, int64_t n_int, const vc_octree_stats *st,
                         const vc_octree_leaves *lv)
{
    double cap = o->max_size > 0 ? o->max_size : INFINITY;
    CHECKF(lv->n == st->n_leaves && lv->n_seeds == n_int && st->n_seeds == n_int,
          "counts: leaves %lld/%lld seeds %lld/%lld", (long long)lv->n, (long long)st->n_leaves,
          (long long)lv->n_seeds, (long long)n_int);
    CHECKF(out->n == ss->n + n_int, "out has %lld seeds", (long long)out->n);
    CHECKF(memcmp(out->xyz, ss->xyz, sizeof(double) * 3 * (size_t)ss->n) == 0,
          "surface seeds not copied first");
    double box_vol = 1, vol = 0;
    for (int d = 0; d < 3; d++)
        box_vol *= lv->box[3 + d] - lv->box[d];
    int64_t too_big = 0, needless = 0, outside_whole = 0;
    for (int64_t k = 0; k < lv->n; k++) {
        const double *c = lv->center + 3 * k;
        double a = lv->side[k];
        vol += a * a * a;
        if (sqrt(3.0) * a > 2 * sizing(b, c, o, cap) * (1 + 1e-12)) {
            if (outside_leaf(b, ss, c, a))
                outside_whole++;
            else
                too_big++;
        }
        /* the parent: the cube of side 2a on the grid of that size */
        double pc[3];
        for (int d = 0; d < 3; d++)
            pc[d] = lv->box[d] + (floor((c[d] - lv->box[d]) / (2 * a)) + 0.5) * 2 * a;
        if (lv->level[k] > 0 && sqrt(3.0) * 2 * a <= 2 * sizing(b, pc, o, cap))
            needless++;
    }
    CHECKF(fabs(vol - box_vol) <= 1e-9 * box_vol, "leaves cover %.12g of a box of %.12g", vol,
          box_vol);
    CHECKF(too_big == 0, "%lld leaves larger than the sizing allows", (long long)too_big);
    /* outside, the leaves no ball reaches are left larger (the balls lie in
     * a box with room around them) */
    CHECKF(outside_whole > 0, "no outside leaf left larger than the sizing");
    /* balance splits a leaf into 8: at most 8 of every 7 added leaves */
    int64_t added = st->n_leaves - st->n_refined_leaves;
    CHECKF(needless <= 8 * added / 7, "%lld leaves refined beyond the sizing (balance added %lld)",
          (long long)needless, (long long)added);
    int64_t unbalanced = 0;
    for (int64_t i = 0; i < lv->n; i++)
        for (int64_t j = i + 1; j < lv->n; j++)
            if (abs(lv->level[i] - lv->level[j]) > 1 &&
                touch(lv->center + 3 * i, lv->side[i], lv->center + 3 * j, lv->side[j]))
                unbalanced++;
    CHECKF(unbalanced == 0, "%lld touching leaf pairs differ by more than one level",
          (long long)unbalanced);
    /* the seed rules, by brute force over every leaf */
    char *is_seed = calloc((size_t)(lv->n > 0 ? lv->n : 1), 1);
    for (int64_t i = 0; i < n_int; i++) {
        int64_t k = lv->seed_leaf[i];
        CHECKF(k >= 0 && k < lv->n && memcmp(out->xyz + 3 * (ss->n + i), lv->center + 3 * k,
                                            sizeof(double) * 3) == 0 &&
                  out->label[ss->n + i] == 1,
              "seed %lld is not its leaf's centre", (long long)i);
        if (k >= 0 && k < lv->n)
            is_seed[k] = 1;
    }
    int64_t wrong = 0;
    for (int64_t k = 0; k < lv->n; k++) {
        const double *c = lv->center + 3 * k;
        int covered = 0;
        for (int64_t i = 0; i < b->n && !covered; i++)
            covered = dist(c, b->center + 3 * i) <= (1 + o->clearance) * b->radius[i];
        int64_t q = 0;
        for (int64_t i = 1; i < ss->n; i++)
            if (dist(c, ss->xyz + 3 * i) < dist(c, ss->xyz + 3 * q))
                q = i;
        int ok = !covered && ss->label[q] == 1 && dist(c, ss->xyz + 3 * q) >= 0.5 * lv->side[k];
        wrong += ok != is_seed[k];
    }
    free(is_seed);
    CHECKF(wrong == 0, "%lld leaves where the seed rule disagrees with brute force",
          (long long)wrong);
}

int main(void)
{
    vc_balls b;
    vc_seeds ss;
    make_sphere(300, &b, &ss);
    {
        vc_octree_options d;
        vc_octree_options_default(&d);
        vc_seeds early = {0, NULL, NULL};
        int64_t n_early = 0;
        vc_error e0 = {0, ""};
        CHECKF(vc_interior_octree(&b, &ss, &d, &early, &n_early, NULL, NULL, &e0) == VC_EPARAM &&
                   strstr(e0.msg, "initialise MPI"),
               "octree without MPI: %s", e0.msg);
        vc_seeds_free(&early);
    }
    if (test_mpi_start() != 0) {
        fprintf(stderr, "test_interior_octree: MPI_Init failed\n");
        return 1;
    }
    vc_octree_options o;
    vc_octree_options_default(&o);
    CHECKF(o.lipschitz == 0.25 && o.diagonal_factor == 2 && o.far_from == 3 &&
               o.far_lipschitz == 1 && o.clearance == VC_INTERIOR_CLEARANCE,
           "defaults");

    vc_seeds out[2];
    int64_t n_int[2];
    vc_octree_stats st;
    vc_octree_leaves lv;
    vc_error err = {0, ""};
    for (int t = 0; t < 2; t++) {
        o.threads = t + 1;
        int rc = vc_interior_octree(&b, &ss, &o, &out[t], &n_int[t], &st, &lv, &err);
        CHECKF(rc == 0, "octree: %s", err.msg);
        if (rc)
            return 1;
        printf("threads %d: %lld leaves (levels %d-%d), %lld seeds, %.3f s\n", t + 1,
               (long long)st.n_leaves, st.min_level, st.max_level, (long long)n_int[t], st.seconds);
        if (t == 0) {
            check_forest(&b, &ss, &o, &out[0], n_int[0], &st, &lv);
            CHECKF(n_int[0] > 50, "only %lld interior seeds", (long long)n_int[0]);
            /* graded: the leaves at the centre are larger than at the small ball */
            double at_centre = 0, at_pole = INFINITY, origin[3] = {0, 0, 0}, pole[3] = {0, 0, 1};
            for (int64_t k = 0; k < lv.n; k++) {
                if (dist(lv.center + 3 * k, origin) < lv.side[k])
                    at_centre = fmax(at_centre, lv.side[k]);
                if (dist(lv.center + 3 * k, pole) < lv.side[k])
                    at_pole = fmin(at_pole, lv.side[k]);
            }
            CHECKF(at_centre >= 4 * at_pole, "not graded: leaves %g at the centre, %g at the pole",
                  at_centre, at_pole);
        }
        vc_octree_leaves_free(&lv);
    }
    CHECKF(n_int[0] == n_int[1] &&
              memcmp(out[0].xyz, out[1].xyz, sizeof(double) * 3 * (size_t)out[0].n) == 0,
          "1 and 2 threads give different seeds");
    vc_seeds_free(&out[0]);
    vc_seeds_free(&out[1]);

    /* the cap */
    o.threads = 0;
    o.max_size = 0.25;
    int rc = vc_interior_octree(&b, &ss, &o, &out[0], &n_int[0], &st, &lv, &err);
    CHECKF(rc == 0, "capped octree: %s", err.msg);
    if (rc == 0) {
        double largest = 0;
        for (int64_t k = 0; k < lv.n; k++)
            if (!outside_leaf(&b, &ss, lv.center + 3 * k, lv.side[k]))
                largest = fmax(largest, lv.side[k]);
        CHECKF(sqrt(3.0) * largest <= 2 * 0.25, "capped: a leaf of side %g", largest);
        printf("capped: %lld leaves, %lld seeds\n", (long long)st.n_leaves, (long long)n_int[0]);
        check_forest(&b, &ss, &o, &out[0], n_int[0], &st, &lv);
        vc_octree_leaves_free(&lv);
        vc_seeds_free(&out[0]);
    }

    /* one grading everywhere (as before the far grading): the same rules,
     * and more leaves deep inside */
    {
        vc_octree_options u = o;
        u.max_size = 0;
        u.far_from = INFINITY;
        vc_octree_stats su, sf;
        u.threads = 0;
        int ru = vc_interior_octree(&b, &ss, &u, &out[0], &n_int[0], &su, &lv, &err);
        CHECKF(ru == 0, "uniform grading: %s", err.msg);
        if (ru == 0) {
            check_forest(&b, &ss, &u, &out[0], n_int[0], &su, &lv);
            vc_octree_leaves_free(&lv);
            vc_seeds_free(&out[0]);
            u.far_from = 3;
            int rf = vc_interior_octree(&b, &ss, &u, &out[0], &n_int[0], &sf, NULL, &err);
            CHECKF(rf == 0 && sf.n_seeds < su.n_seeds,
                   "far grading: %lld interior seeds, %lld with one grading", (long long)sf.n_seeds,
                   (long long)su.n_seeds);
            printf("one grading: %lld seeds; faster far from the balls: %lld\n", (long long)su.n_seeds,
                   (long long)sf.n_seeds);
            if (rf == 0)
                vc_seeds_free(&out[0]);
        }
    }

    /* The clearance: no seed within (1 + clearance) r of a ball's centre
     * (check_forest's brute force), and without it, more seeds, some of
     * them just outside a ball (leaf centres fall anywhere). */
    {
        vc_octree_options z = o;
        z.max_size = 0;
        z.clearance = 0;
        vc_octree_stats s0, s1;
        int r0 = vc_interior_octree(&b, &ss, &z, &out[0], &n_int[0], &s0, &lv, &err);
        CHECKF(r0 == 0, "no clearance: %s", err.msg);
        if (r0 == 0) {
            check_forest(&b, &ss, &z, &out[0], n_int[0], &s0, &lv);
            int64_t near = 0;
            for (int64_t i = ss.n; i < out[0].n; i++)
                for (int64_t k = 0; k < b.n; k++)
                    near += dist(out[0].xyz + 3 * i, b.center + 3 * k) <
                            (1 + VC_INTERIOR_CLEARANCE) * b.radius[k];
            CHECKF(near > 0, "no seed within the clearance of a ball even without it");
            vc_octree_leaves_free(&lv);
            vc_seeds_free(&out[0]);
            z.clearance = VC_INTERIOR_CLEARANCE;
            int r1 = vc_interior_octree(&b, &ss, &z, &out[0], &n_int[0], &s1, NULL, &err);
            CHECKF(r1 == 0 && s1.n_seeds < s0.n_seeds && s1.n_leaves == s0.n_leaves,
                   "clearance %g: %lld seeds of %lld leaves; none: %lld of %lld", z.clearance,
                   (long long)s1.n_seeds, (long long)s1.n_leaves, (long long)s0.n_seeds,
                   (long long)s0.n_leaves);
            printf("clearance 0: %lld seeds (%lld within %g of a radius of a sphere); %g: %lld\n",
                   (long long)s0.n_seeds, (long long)near, VC_INTERIOR_CLEARANCE, z.clearance,
                   (long long)s1.n_seeds);
            if (r1 == 0)
                vc_seeds_free(&out[0]);
        }
    }

    /* bad options and input */
    o.clearance = -1;
    CHECKF(vc_interior_octree(&b, &ss, &o, &out[0], &n_int[0], NULL, NULL, &err) == VC_EPARAM,
           "negative clearance accepted");
    o.clearance = VC_INTERIOR_CLEARANCE;
    o.max_size = 0;
    o.far_lipschitz = 0.1;
    CHECKF(vc_interior_octree(&b, &ss, &o, &out[0], &n_int[0], NULL, NULL, &err) == VC_EPARAM,
           "far grading slower than near accepted");
    o.far_lipschitz = 1;
    o.lipschitz = 1.5;
    CHECKF(vc_interior_octree(&b, &ss, &o, &out[0], &n_int[0], NULL, NULL, &err) == VC_EPARAM,
          "L = 1.5 accepted");
    o.lipschitz = 0.25;
    vc_seeds none = {0, NULL, NULL};
    CHECKF(vc_interior_octree(&b, &none, &o, &out[0], &n_int[0], NULL, NULL, &err) == VC_EINPUT,
          "no surface seeds accepted");

    test_mpi_stop();
    {
        vc_seeds late = {0, NULL, NULL};
        int64_t n_late = 0;
        vc_error e1 = {0, ""};
        CHECKF(vc_interior_octree(&b, &ss, &o, &late, &n_late, NULL, NULL, &e1) == VC_EPARAM,
               "octree after MPI_Finalize: %s", e1.msg);
        vc_seeds_free(&late);
    }
    vc_seeds_free(&ss);
    vc_balls_free(&b);
    if (failures) {
        fprintf(stderr, "test_interior_octree: %d failure(s)\n", failures);
        return 1;
    }
    printf("test_interior_octree: all checks passed\n");
    return 0;
}
