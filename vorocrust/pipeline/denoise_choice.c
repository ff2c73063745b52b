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
 * kept (docs/sampling-convergence.md, session 35). */
#include "denoise_choice.h"

#include <math.h>
#include <string.h>

#include "balls/ball_estimate.h"
#include "sizing/sizing.h"
#include "vorocrust/features.h"

/* The predicted balls of sampling s at the absolute error bound (0 and an
 * error code when out of memory). */
static int predict(const vc_surface *s, double sharp_angle, const unsigned char *extra,
                   double bound, double max_size, int threads, double *n, vc_error *err)
{
    *n = 0;
    vc_features f;
    int rc = vc_features_detect_scaled(s, sharp_angle, extra, bound, &f, err);
    if (rc)
        return rc;
    const double diag = vc_surface_diagonal(s);
    vc_sizing z;
    if (vc_sizing_init(&z, s, &f, sharp_angle, diag > 0 ? bound / diag : 0)) {
        vc_features_free(&f);
        return vc_error_set(err, VC_ENOMEM, "out of memory predicting the balls");
    }
    vc_ball_estimate est;
    rc = vc_ball_estimate_compute(&z, max_size > 0 ? max_size : z.diag, threads, &est);
    vc_sizing_free(&z);
    vc_features_free(&f);
    if (rc)
        return vc_error_set(err, VC_ENOMEM, "out of memory predicting the balls");
    *n = est.n_balls;
    return 0;
}

int vc_choose_denoised(const vc_surface *s, double sharp_angle, const unsigned char *extra,
                       double bound, double max_size, int force, int threads,
                       vc_surface *denoised, vc_denoise_choice *ch, vc_error *err)
{
    memset(denoised, 0, sizeof *denoised);
    memset(ch, 0, sizeof *ch);
    if (force < 0 || !(bound > 0))
        return 0;
    int rc = vc_surface_denoise(s, VC_DENOISE_SHARE * bound, VC_DENOISE_ITERATIONS, threads,
                                denoised, &ch->moved, err);
    if (rc)
        return rc;
    ch->bound = bound - ch->moved.max_move;
    if (force == 0 &&
        ((rc = predict(s, sharp_angle, extra, bound, max_size, threads, &ch->n_input, err)) ||
         (rc = predict(denoised, sharp_angle, extra, ch->bound, max_size, threads, &ch->n_denoised,
                       err)))) {
        vc_surface_free(denoised);
        return rc;
    }
    ch->used = force > 0 || ch->n_input >= VC_DENOISE_GAIN * ch->n_denoised;
    return 0;
}
