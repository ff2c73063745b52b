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
 * Updates are Jacobi steps (new positions from the previous ones), in
 * parallel over the vertices; each vertex's sum runs over its triangles in
 * a fixed order, so the result does not depend on the thread count. */
#include "vorocrust/smoothing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/csr_group.h"

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
    /* each vertex's move scaled down to max_move at most */
    for (int64_t v = 0; v < nv; v++) {
        double *p = out->xyz + 3 * v;
        const double *q = in->xyz + 3 * v;
        const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        const double m = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (m > max_move)
            for (int k = 0; k < 3; k++)
                p[k] = q[k] + d[k] * (max_move / m);
    }
    free(tmp);
    free(twice);
    free(vstart);
    free(vnb);
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
    }
    return 0;
}
