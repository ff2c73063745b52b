/* Surface seeds from the union of balls (thesis 6.2.7): the two points
 * where the spheres of each triplet of overlapping balls meet, kept when
 * no fourth ball holds them. The two points of a triplet are mirror images
 * across the plane of its centres; the one on the side the ball normals
 * point to is outside (label 0), the other inside (label 1). */
#include "vorocrust/sampling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balls/ball_set.h"
#include "balls/triplets.h"

typedef struct seed_acc {
    const vc_balls *b;
    double *xyz;
    int32_t *label;
    double *tol; /* merge tolerance per seed */
    int64_t n, cap;
    int64_t n_half;
    int oom;
} seed_acc;

static int push(seed_acc *a, const double p[3], int label, double tol)
{
    if (a->n == a->cap) {
        int64_t c = a->cap ? 2 * a->cap : 4096;
        double *x = realloc(a->xyz, sizeof(double) * 3 * (size_t)c);
        if (x)
            a->xyz = x;
        int32_t *l = realloc(a->label, sizeof(int32_t) * (size_t)c);
        if (l)
            a->label = l;
        double *t = realloc(a->tol, sizeof(double) * (size_t)c);
        if (t)
            a->tol = t;
        if (!x || !l || !t)
            return -1;
        a->cap = c;
    }
    memcpy(a->xyz + 3 * a->n, p, sizeof(double) * 3);
    a->label[a->n] = label;
    a->tol[a->n] = tol;
    a->n++;
    return 0;
}

static void on_triplet(void *ctx, const vc_triplet *t)
{
    seed_acc *a = ctx;
    if (a->oom)
        return;
    int cu = t->cover_up >= 0, cd = t->cover_down >= 0;
    if (cu != cd)
        a->n_half++;
    if (cu && cd)
        return;
    const vc_balls *b = a->b;
    const double *ci = b->center + 3 * t->i, *cj = b->center + 3 * t->j, *ck = b->center + 3 * t->k;
    double u[3] = {cj[0] - ci[0], cj[1] - ci[1], cj[2] - ci[2]};
    double w[3] = {ck[0] - ci[0], ck[1] - ci[1], ck[2] - ci[2]};
    double m[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    double nrm[3] = {0, 0, 0};
    for (int d = 0; d < 3; d++)
        nrm[d] = b->normal[3 * t->i + d] + b->normal[3 * t->j + d] + b->normal[3 * t->k + d];
    /* up lies on the +m side: outside when m agrees with the normals */
    int up_outside = (m[0] * nrm[0] + m[1] * nrm[1] + m[2] * nrm[2]) > 0;
    double rmin = fmin(b->radius[t->i], fmin(b->radius[t->j], b->radius[t->k]));
    double tol = 1e-9 * rmin;
    if (!cu && push(a, t->up, up_outside ? 0 : 1, tol))
        a->oom = 1;
    if (!cd && push(a, t->down, up_outside ? 1 : 0, tol))
        a->oom = 1;
}

typedef struct order_rec {
    double x;
    int64_t i;
} order_rec;

static int cmp_order(const void *p, const void *q)
{
    const order_rec *a = p, *b = q;
    if (a->x < b->x)
        return -1;
    if (a->x > b->x)
        return 1;
    return (a->i > b->i) - (a->i < b->i);
}

int vc_balls_seeds(const vc_balls *b, int threads, vc_seeds *out, int64_t *n_half_covered,
                   vc_error *err)
{
    memset(out, 0, sizeof *out);
    if (b->n == 0)
        return vc_error_set(err, VC_EINPUT, "no balls");
    vc_ball_set bs;
    if (vc_ball_set_build(&bs, b, NULL))
        return vc_error_set(err, VC_ENOMEM, "out of memory for the seeds");
    seed_acc a = {&bs.b, NULL, NULL, NULL, 0, 0, 0, 0};
    int rc = vc_triplets_scan_all(&bs, threads, on_triplet, &a);
    if (rc || a.oom) {
        vc_ball_set_free(&bs);
        free(a.xyz);
        free(a.label);
        free(a.tol);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the seeds");
    }
    vc_ball_set_free(&bs);
    if (n_half_covered)
        *n_half_covered = a.n_half;

    /* Merge coincident points (a point shared by four or more spheres comes
     * from several triplets): sort by x, compare within the tolerance. */
    order_rec *ord = malloc(sizeof(order_rec) * (size_t)(a.n ? a.n : 1));
    unsigned char *dup = calloc((size_t)(a.n ? a.n : 1), 1);
    if (!ord || !dup) {
        free(ord);
        free(dup);
        free(a.xyz);
        free(a.label);
        free(a.tol);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the seeds");
    }
    double maxtol = 0;
    for (int64_t i = 0; i < a.n; i++) {
        ord[i].x = a.xyz[3 * i];
        ord[i].i = i;
        maxtol = fmax(maxtol, a.tol[i]);
    }
    qsort(ord, (size_t)a.n, sizeof(order_rec), cmp_order);
    for (int64_t p = 0; p < a.n; p++) {
        int64_t i = ord[p].i;
        if (dup[i])
            continue;
        for (int64_t q = p + 1; q < a.n && ord[q].x - ord[p].x <= maxtol; q++) {
            int64_t j = ord[q].i;
            if (dup[j])
                continue;
            double t = fmax(a.tol[i], a.tol[j]);
            const double *x = a.xyz + 3 * i, *y = a.xyz + 3 * j;
            if (fabs(x[0] - y[0]) <= t && fabs(x[1] - y[1]) <= t && fabs(x[2] - y[2]) <= t)
                dup[j] = 1;
        }
    }
    int64_t n = 0;
    for (int64_t i = 0; i < a.n; i++)
        n += !dup[i];
    if (vc_seeds_alloc(out, n, err)) {
        free(ord);
        free(dup);
        free(a.xyz);
        free(a.label);
        free(a.tol);
        return err ? err->code : VC_ENOMEM;
    }
    int64_t m = 0;
    for (int64_t i = 0; i < a.n; i++) {
        if (dup[i])
            continue;
        memcpy(out->xyz + 3 * m, a.xyz + 3 * i, sizeof(double) * 3);
        out->label[m] = a.label[i];
        m++;
    }
    free(ord);
    free(dup);
    free(a.xyz);
    free(a.label);
    free(a.tol);
    return 0;
}
