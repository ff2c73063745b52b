/* Noise at the error bound: sample the input, or a copy smoothed within
 * half the bound?
 *
 * The sizing reads the surface at its facets: the tangent plane of the
 * facet a ball sits on, and the distance to the nearest facet that folds
 * away from it by more than theta_sharp. Noise of a fraction of the error
 * bound between facets smaller than the bound (a scan, a marching-cubes
 * isosurface of noisy data, a subdivided surface jittered) makes those
 * folds everywhere: the radii fall to a tenth of the bound and below, the
 * balls multiply (a noisy 50,480-triangle blob: 306,000 balls predicted
 * for what its smoothed copy does with 12,200), and sliver elimination
 * fights the folds without end. Yet a surface within the bound of such an
 * input need not have them: Taubin smoothing held within half the bound
 * (vc_surface_denoise) takes them out, and sampling the copy within the
 * other half keeps the reconstruction within the whole bound of the
 * input. The copy is taken when the sizing itself says the noise costs:
 * the prediction of balls (Sheehy's bound, vc_ball_estimate) for the
 * input at least VC_DENOISE_GAIN times that for the copy. On a clean
 * surface the copy moves little where the surface is smooth, and at
 * creases and coarse facets its halved bound costs balls: the input is
 * kept (docs/sampling-convergence.md, session 35). Nor is the copy taken
 * when its enclosed volume differs from the input's by more than noise
 * makes it (VC_DENOISE_MAX_VOLUME_CHANGE): the smoothing moves every
 * vertex, corners and creases too, and on a CAD part with a narrow gap or
 * slot it widened the gap (fewer balls predicted) and took 1.6 to 2.4% of
 * the volume with it (session 38). */
#include "denoise_choice.h"
#include "predict_balls.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balls/ball_estimate.h"
#include "sizing/sizing.h"
#include "util/csr_group.h"
#include "vorocrust/features.h"

/* A vertex is rough when the normals of its triangles spread by more than
 * this many degrees from their mean; the choice is made only when more
 * than VC_ROUGH_SHARE of the vertices are (it costs a second or more on a
 * million triangles, while a clean fine tessellation has none). */
#define VC_ROUGH_ANGLE 20.0
#define VC_ROUGH_SHARE 0.01

/* The share of rough vertices (0 when out of memory: no choice made). */
static double rough_share(const vc_surface *s, int threads)
{
    const int64_t nv = s->n_vertices, nt = s->n_triangles;
    int64_t *vstart = NULL, *vtri = NULL;
    double *nrm = malloc(sizeof(double) * 3 * (size_t)(nt ? nt : 1));
    if (!nrm || vc_csr_group(s->tri, nt, 3, nv, NULL, &vstart, &vtri)) {
        free(nrm);
        return 0;
    }
    /* each triangle's normal, length twice its area */
#pragma omp parallel for schedule(static) num_threads(threads) if (nt > 65536)
    for (int64_t t = 0; t < nt; t++) {
        const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                     *c = s->xyz + 3 * s->tri[3 * t + 2];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        nrm[3 * t] = u[1] * v[2] - u[2] * v[1];
        nrm[3 * t + 1] = u[2] * v[0] - u[0] * v[2];
        nrm[3 * t + 2] = u[0] * v[1] - u[1] * v[0];
    }
    const double cos_rough = cos(VC_ROUGH_ANGLE * 3.14159265358979323846 / 180.0);
    int64_t rough = 0;
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : rough) if (nv > 65536)
    for (int64_t w = 0; w < nv; w++) {
        double m[3] = {0, 0, 0};
        for (int64_t j = vstart[w]; j < vstart[w + 1]; j++)
            for (int d = 0; d < 3; d++)
                m[d] += nrm[3 * vtri[j] + d];
        const double lm = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        int spread = 0;
        for (int64_t j = vstart[w]; j < vstart[w + 1] && lm > 0 && !spread; j++) {
            const double *n = nrm + 3 * vtri[j];
            const double ln = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            spread = ln > 0 && (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]) < cos_rough * ln * lm;
        }
        rough += spread;
    }
    free(nrm);
    free(vstart);
    free(vtri);
    return nv > 0 ? (double)rough / (double)nv : 0;
}

int vc_make_denoised(const vc_surface *s, double bound, int threads, vc_surface *denoised,
                     vc_denoise_choice *ch, vc_error *err)
{
    int rc = vc_surface_denoise(s, VC_DENOISE_SHARE * bound, VC_DENOISE_ITERATIONS, threads,
                                denoised, &ch->moved, err);
    if (rc)
        return rc;
    ch->bound = bound - ch->moved.max_move;
    const double v_in = vc_surface_signed_volume(s);
    ch->volume_change = v_in != 0 ? vc_surface_signed_volume(denoised) / v_in - 1 : 0;
    /* A copy that cut itself would make the sizing vanish along the
     * crossing (a propeller's copy: balls of 6e-8, 1e-5 of the bound).
     * vc_surface_denoise withdraws the moves that make its triangles
     * cross, and the input has none here (the pipeline's union made
     * sure): the pairs it reports left are a guard, 0 unless that fails. */
    ch->self_intersections = ch->moved.n_crossing;
    return 0;
}

int vc_choose_denoised(const vc_surface *s, double sharp_angle, const unsigned char *extra,
                       double bound, double max_size, int force, int threads,
                       vc_surface *denoised, vc_denoise_choice *ch, vc_features *f_chosen,
                       const vc_logger *log, const char *name, vc_error *err)
{
    memset(denoised, 0, sizeof *denoised);
    memset(ch, 0, sizeof *ch);
    memset(f_chosen, 0, sizeof *f_chosen);
    if (force < 0 || !(bound > 0))
        return 0;
    int rc;
    if (force > 0) {
        if ((rc = vc_make_denoised(s, bound, threads, denoised, ch, err)) != 0)
            return rc;
        ch->used = ch->self_intersections == 0;
        return 0;
    }
    /* a clean surface, nothing to weigh (a million-triangle sphere: the
     * choice cost 4.5 s of a 9.4 s run) */
    ch->rough_share = rough_share(s, threads);
    if (!(ch->rough_share > VC_ROUGH_SHARE))
        return 0;
    /* the predictions take seconds on a fine rough input (a noisy
     * 374,000-triangle blob: 4.7 s), which the progress lines otherwise
     * spent repeating the last input check */
    vc_log(log, VC_LOG_INFO, "mesh: %s: %.1f%% of the vertices have a triangle %g degrees "
           "off their mean normal (creases or noise): weighing the balls of the input against a "
           "copy smoothed within half the error bound", name, 100 * ch->rough_share, VC_ROUGH_ANGLE);
    vc_features f_input, f_copy;
    if ((rc = vc_predict_balls(s, sharp_angle, extra, bound, max_size, threads, &ch->n_input, &f_input, err)))
        return rc;
    if ((rc = vc_make_denoised(s, bound, threads, denoised, ch, err)) != 0 ||
        (rc = vc_predict_balls(denoised, sharp_angle, extra, ch->bound, max_size, threads, &ch->n_denoised,
                      &f_copy, err)) != 0) {
        vc_features_free(&f_input);
        vc_surface_free(denoised);
        return rc;
    }
    ch->used = ch->n_input >= VC_DENOISE_GAIN * ch->n_denoised &&
               fabs(ch->volume_change) <= VC_DENOISE_MAX_VOLUME_CHANGE &&
               ch->self_intersections == 0;
    /* the sampling's first attempt takes the features of the surface it
     * samples from here (they take seconds on a fine noisy input) */
    *f_chosen = ch->used ? f_copy : f_input;
    vc_features_free(ch->used ? &f_input : &f_copy);
    return 0;
}
