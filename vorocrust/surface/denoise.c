/* Denoising within a bound (see vorocrust/smoothing.h, vc_surface_denoise).
 *
 * Taubin's lambda|mu smoothing S: a step of the umbrella Laplacian with
 * lambda > 0 (shrinks every frequency), then one with mu < -lambda
 * (grows them back), so frequencies below the pass band k_pb = 1 / lambda
 * + 1 / mu keep their amplitude and those above it decay: the noise goes,
 * the shape stays, with no overall shrinking. But its gain
 * f(k) = (1 - lambda k)(1 - mu k) slightly exceeds 1 below the pass band
 * (1.00085 per pair at k = 0.057, 3.4% after 40 pairs): a coarse sphere
 * grew by that much, its volume by 1.7%. Twicing (Tukey) removes it: the
 * result is 2 S(x) - S(S(x)), of gain 1 - (1 - f)^2, never above 1, still
 * 0 where f is. Each vertex's move is then scaled down to max_move, which
 * bounds what the smoothing may do to anything that is not noise (a
 * crease, a thin wall, a coarse facet).
 *
 * A part thinner than the moves (a marching-cubes blade 0.07 of the error
 * bound thick) must keep its thickness: Taubin's steps pull its two sides
 * together near a rim, and a propeller's copy came out with sides 1e-7
 * apart there (balls of 6e-8, cells the validator refused). So a vertex
 * moves at most a quarter of its distance to the other side (the nearest
 * triangle behind it, facing away from it): the two sides keep half their
 * gap. Where the surface would still cut itself (a blade's ragged rim, the
 * needles of a noisy pole), the moves of the triangles that cross are
 * halved, then withdrawn: the copy never intersects itself where the input
 * does not (a propeller's copy that did needed 1.5 million balls).
 *
 * Updates are Jacobi steps (new positions from the previous ones), in
 * parallel over the vertices; each vertex's sum runs over its triangles in
 * a fixed order, so the result does not depend on the thread count. */
#include "vorocrust/smoothing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/closest_point.h"
#include "util/csr_group.h"
#include "util/triangle_bvh.h"
#include "feature_scale.h"
#include "self_intersection.h"

/* pass band 1 / lambda + 1 / mu = 0.11 (Taubin's 0.6307|-0.6732 in half
 * the pairs gave the same choices, but a collapsed surface triangle on
 * the jittered plate: the sampler's near-quartets come and go with the
 * copy's last digits, docs/sampling-convergence.md, session 35) */
#define TAUBIN_LAMBDA 0.5
#define TAUBIN_MU -0.53

/* The neighbours of every vertex (the other corners of its triangles,
 * each once, ascending) in compressed rows; -1 when out of memory. */
static int neighbours(const vc_surface *s, int64_t **start, int64_t **list)
{
    const int64_t nv = s->n_vertices;
    int64_t *vstart = NULL, *vtri = NULL;
    *start = *list = NULL;
    if (vc_csr_group(s->tri, s->n_triangles, 3, nv, NULL, &vstart, &vtri))
        return -1;
    /* at most two per triangle at the vertex */
    int64_t *st = malloc(sizeof(int64_t) * (size_t)(nv + 1));
    int64_t *ls = malloc(sizeof(int64_t) * (size_t)(2 * vstart[nv] + 1));
    if (!st || !ls) {
        free(st);
        free(ls);
        free(vstart);
        free(vtri);
        return -1;
    }
    int64_t n = 0;
    for (int64_t v = 0; v < nv; v++) {
        st[v] = n;
        for (int64_t j = vstart[v]; j < vstart[v + 1]; j++)
            for (int c = 0; c < 3; c++) {
                const int64_t u = s->tri[3 * vtri[j] + c];
                if (u == v)
                    continue;
                /* insertion into the vertex's sorted run, once */
                int64_t k = n;
                while (k > st[v] && ls[k - 1] > u)
                    k--;
                if (k > st[v] && ls[k - 1] == u)
                    continue;
                memmove(ls + k + 1, ls + k, sizeof(int64_t) * (size_t)(n - k));
                ls[k] = u;
                n++;
            }
    }
    st[nv] = n;
    free(vstart);
    free(vtri);
    *start = st;
    *list = ls;
    return 0;
}

/* A vertex moves at most this share of its distance to the other side of
 * a thin part. */
#define THIN_SHARE 0.25
/* The other side: triangles whose normal is more than 120 degrees from the
 * vertex's (cosine below this), their nearest point behind it. */
#define FACING_AWAY -0.5

typedef struct other_side {
    const vc_surface *s;
    const double *p, *n;   /* the vertex and its (unit) normal */
    int64_t v;
    double best2;          /* the nearest such triangle's squared distance from p */
} other_side;

/* Records triangle t when it is of the other side; never stops the search
 * (every triangle of the query's ball is looked at). */
static int record_other_side(void *ctx, int64_t t, double d2)
{
    (void)d2;
    other_side *o = ctx;
    const int64_t *tv = o->s->tri + 3 * t;
    if (tv[0] == o->v || tv[1] == o->v || tv[2] == o->v)
        return 0;
    double m[3];
    vc_triangle_cross(o->s, t, m);
    const double l = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    if (!(l > 0) || m[0] * o->n[0] + m[1] * o->n[1] + m[2] * o->n[2] >= FACING_AWAY * l)
        return 0;
    double q[3];
    const double e2 = vc_closest_on_triangle(o->p, o->s->xyz + 3 * tv[0], o->s->xyz + 3 * tv[1],
                                             o->s->xyz + 3 * tv[2], q);
    const double h = (q[0] - o->p[0]) * o->n[0] + (q[1] - o->p[1]) * o->n[1] + (q[2] - o->p[2]) * o->n[2];
    if (h < 0 && e2 < o->best2)
        o->best2 = e2;
    return 0;
}

/* Each vertex's largest move: max_move, or THIN_SHARE of its distance to
 * the other side when that is nearer than max_move / THIN_SHARE. The
 * other side is looked for in the ball of that reach's half behind the
 * vertex (its own side near it stays out of the query: few triangles on a
 * fine surface). 0, or -1 when out of memory. */
static int move_caps(const vc_surface *s, double max_move, int threads, double *cap)
{
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    for (int64_t v = 0; v < nv; v++)
        cap[v] = max_move;
    if (!(max_move > 0) || nt == 0)
        return 0;
    double *vn = calloc(3 * (size_t)nv, sizeof(double));
    vc_tri_bvh h;
    if (!vn || vc_tri_bvh_build(&h, s->xyz, s->tri, nt, threads)) {
        free(vn);
        return -1;
    }
    for (int64_t t = 0; t < nt; t++) {
        double m[3];
        vc_triangle_cross(s, t, m);
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++)
                vn[3 * s->tri[3 * t + k] + d] += m[d];
    }
    const double reach = max_move / THIN_SHARE;
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (nv > 4096)
    for (int64_t v = 0; v < nv; v++) {
        double *n = vn + 3 * v;
        const double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(l > 0))
            continue;
        for (int d = 0; d < 3; d++)
            n[d] /= l;
        const double *p = s->xyz + 3 * v;
        const double c[3] = {p[0] - 0.5 * reach * n[0], p[1] - 0.5 * reach * n[1],
                             p[2] - 0.5 * reach * n[2]};
        other_side o = {s, p, n, v, reach * reach};
        vc_tri_bvh_nearest_where(&h, c, 0.5 * reach, record_other_side, &o);
        if (o.best2 < reach * reach)
            cap[v] = THIN_SHARE * sqrt(o.best2);
    }
    vc_tri_bvh_free(&h);
    free(vn);
    return 0;
}

/* Rounds of uncrossing in which the crossing triangles' moves are halved,
 * before they are withdrawn. */
#define UNCROSS_HALVINGS 3

/* Withdraws the moves (out against in) that make out cut itself: the
 * vertices of every intersecting pair of triangles move half as far,
 * UNCROSS_HALVINGS rounds, then back to their input positions with their
 * neighbours (start, list: each vertex's), until no pair is left. Each
 * withdrawal round puts at least one more vertex back (a pair whose six
 * vertices are all back is a pair of the input's triangles, and in has
 * none), so the rounds end; withdrawing the neighbours too ends them in a
 * few (a withdrawn vertex tilts its neighbours' triangles, which then
 * cross others: a decimated bracket's copy took 118, 48, 35, 20, 16, 6, 3,
 * 3 pairs over eight rounds withdrawing the pairs' vertices alone). The
 * test runs on coordinates scaled by a power of two to a diagonal of order
 * one. Returns the pairs left (0 unless in intersects itself), -1 when out
 * of memory. */
static int64_t uncross(const vc_surface *in, vc_surface *out, const int64_t *start, const int64_t *list)
{
    const int64_t nv = out->n_vertices, nt = out->n_triangles;
    if (nv == 0 || nt == 0)
        return 0;
    const double diag = vc_surface_diagonal(in);
    int e = 0;
    if (diag > 0)
        frexp(diag, &e);
    double *scaled = malloc(sizeof(double) * 3 * (size_t)nv);
    unsigned char *mark = malloc((size_t)nv);
    if (!scaled || !mark) {
        free(scaled);
        free(mark);
        return -1;
    }
    int64_t left = 0;
    for (int64_t round = 0; round <= UNCROSS_HALVINGS + nv; round++) {
        for (int64_t i = 0; i < 3 * nv; i++)
            scaled[i] = ldexp(out->xyz[i], -e);
        int64_t *pairs = NULL;
        if (vc_self_intersection_pairs(scaled, out->tri, nt, &pairs, &left)) {
            left = -1;
            break;
        }
        if (left == 0) {
            free(pairs);
            break;
        }
        memset(mark, 0, (size_t)nv);
        for (int64_t i = 0; i < 2 * left; i++)
            for (int k = 0; k < 3; k++)
                mark[out->tri[3 * pairs[i] + k]] = 1;
        free(pairs);
        if (round < UNCROSS_HALVINGS) {
            for (int64_t v = 0; v < nv; v++)
                if (mark[v])
                    for (int k = 0; k < 3; k++)
                        out->xyz[3 * v + k] = in->xyz[3 * v + k] + 0.5 * (out->xyz[3 * v + k] - in->xyz[3 * v + k]);
            continue;
        }
        /* withdrawn: the marked vertices and their neighbours */
        for (int64_t v = 0; v < nv; v++)
            if (mark[v] == 1)
                for (int64_t j = start[v]; j < start[v + 1]; j++)
                    if (!mark[list[j]])
                        mark[list[j]] = 2;
        for (int64_t v = 0; v < nv; v++)
            if (mark[v])
                memcpy(out->xyz + 3 * v, in->xyz + 3 * v, 3 * sizeof(double));
    }
    free(scaled);
    free(mark);
    return left;
}

/* One umbrella step of weight w from x into y. */
static void umbrella_step(int64_t n, const int64_t *start, const int64_t *list, const double *x,
                          double *y, double w, int threads)
{
#pragma omp parallel for schedule(static) num_threads(threads) if (n > 4096)
    for (int64_t v = 0; v < n; v++) {
        double sum[3] = {0, 0, 0};
        for (int64_t j = start[v]; j < start[v + 1]; j++) {
            const double *q = x + 3 * list[j];
            sum[0] += q[0];
            sum[1] += q[1];
            sum[2] += q[2];
        }
        const int64_t k = start[v + 1] - start[v];
        for (int d = 0; d < 3; d++)
            y[3 * v + d] = k > 0 ? x[3 * v + d] + w * (sum[d] / (double)k - x[3 * v + d])
                                 : x[3 * v + d];
    }
}

int vc_surface_denoise(const vc_surface *in, double max_move, int iterations, int threads,
                       vc_surface *out, vc_denoise_report *rep, vc_error *err)
{
    memset(out, 0, sizeof *out);
    if (rep)
        memset(rep, 0, sizeof *rep);
    if (!(max_move >= 0) || !isfinite(max_move))
        return vc_error_set(err, VC_EPARAM, "denoising: largest move %g: needs a finite number >= 0",
                            max_move);
    if (iterations < 0 || iterations > VC_DENOISE_MAX_ITERATIONS)
        return vc_error_set(err, VC_EPARAM, "denoising: %d iterations: needs 0 to %d", iterations,
                            VC_DENOISE_MAX_ITERATIONS);
    const int64_t nv = in->n_vertices, nt = in->n_triangles;
    for (int64_t i = 0; i < 3 * nt; i++)
        if (in->tri[i] < 0 || in->tri[i] >= nv)
            return vc_error_set(err, VC_EINPUT, "denoising: triangle %lld refers to vertex %lld of %lld",
                                (long long)(i / 3), (long long)in->tri[i], (long long)nv);
    int64_t *vstart = NULL, *vnb = NULL;
    out->xyz = malloc(sizeof(double) * 3 * (size_t)(nv ? nv : 1));
    out->tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt ? nt : 1));
    double *tmp = malloc(sizeof(double) * 3 * (size_t)(nv ? nv : 1));
    double *twice = malloc(sizeof(double) * 3 * (size_t)(nv ? nv : 1));
    if (in->tri_group) {
        out->tri_group = malloc(sizeof(int32_t) * (size_t)(nt ? nt : 1));
        out->group_name = malloc(sizeof *out->group_name * (size_t)(in->n_groups ? in->n_groups : 1));
    }
    if (!out->xyz || !out->tri || !tmp || !twice || (in->tri_group && (!out->tri_group || !out->group_name)) ||
        neighbours(in, &vstart, &vnb)) {
        free(tmp);
        free(twice);
        vc_surface_free(out);
        return vc_error_set(err, VC_ENOMEM, "denoising: out of memory");
    }
    out->n_vertices = nv;
    out->n_triangles = nt;
    memcpy(out->tri, in->tri, sizeof(int64_t) * 3 * (size_t)nt);
    if (in->tri_group) {
        memcpy(out->tri_group, in->tri_group, sizeof(int32_t) * (size_t)nt);
        memcpy(out->group_name, in->group_name, sizeof *out->group_name * (size_t)in->n_groups);
        out->n_groups = in->n_groups;
    }
    /* y = S(x) into out, then S(y) into twice, and out = 2 y - S(y) */
    memcpy(out->xyz, in->xyz, sizeof(double) * 3 * (size_t)nv);
    for (int i = 0; i < iterations; i++) {
        /* x -> tmp (lambda), tmp -> x (mu) */
        umbrella_step(nv, vstart, vnb, out->xyz, tmp, TAUBIN_LAMBDA, threads);
        umbrella_step(nv, vstart, vnb, tmp, out->xyz, TAUBIN_MU, threads);
    }
    memcpy(twice, out->xyz, sizeof(double) * 3 * (size_t)nv);
    for (int i = 0; i < iterations; i++) {
        umbrella_step(nv, vstart, vnb, twice, tmp, TAUBIN_LAMBDA, threads);
        umbrella_step(nv, vstart, vnb, tmp, twice, TAUBIN_MU, threads);
    }
    for (int64_t i = 0; i < 3 * nv; i++)
        out->xyz[i] = 2 * out->xyz[i] - twice[i];
    /* each vertex's move scaled down to max_move at most, and to a
     * quarter of its distance to the other side of a thin part (tmp holds
     * the caps: its smoothing work is done) */
    if (move_caps(in, max_move, threads, tmp)) {
        free(tmp);
        free(twice);
        free(vstart);
        free(vnb);
        vc_surface_free(out);
        return vc_error_set(err, VC_ENOMEM, "denoising: out of memory");
    }
    for (int64_t v = 0; v < nv; v++) {
        double *p = out->xyz + 3 * v;
        const double *q = in->xyz + 3 * v;
        const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        const double m = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (m > tmp[v])
            for (int k = 0; k < 3; k++)
                p[k] = q[k] + d[k] * (tmp[v] / m);
    }
    free(tmp);
    free(twice);
    const int64_t crossing = uncross(in, out, vstart, vnb);
    free(vstart);
    free(vnb);
    if (crossing < 0) {
        vc_surface_free(out);
        return vc_error_set(err, VC_ENOMEM, "denoising: out of memory");
    }
    if (rep) {
        double sum = 0;
        for (int64_t v = 0; v < nv; v++) {
            const double *a = in->xyz + 3 * v, *b = out->xyz + 3 * v;
            const double m = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                  (a[2] - b[2]) * (a[2] - b[2]));
            rep->max_move = fmax(rep->max_move, m);
            sum += m;
            rep->n_held += m >= max_move * (1 - 1e-12) && max_move > 0 && m > 0;
        }
        rep->mean_move = nv ? sum / (double)nv : 0;
        rep->n_crossing = crossing;
    }
    return 0;
}
