/* Ball counts predicted from the sizing (see predict_balls.h). */
#include "predict_balls.h"

#include "balls/ball_estimate.h"
#include "sizing/sizing.h"
#include "vorocrust/features.h"

int vc_predict_balls(const vc_surface *s, double sharp_angle, const unsigned char *extra,
                     double bound, double max_size, int threads, double *n, vc_features *f,
                     vc_error *err)
{
    *n = 0;
    int rc = vc_features_detect_scaled(s, sharp_angle, extra, bound, f, err);
    if (rc)
        return rc;
    const double diag = vc_surface_diagonal(s);
    vc_sizing z;
    if (vc_sizing_init(&z, s, f, sharp_angle, diag > 0 ? bound / diag : 0)) {
        vc_features_free(f);
        return vc_error_set(err, VC_ENOMEM, "out of memory predicting the balls");
    }
    vc_ball_estimate est;
    rc = vc_ball_estimate_compute(&z, max_size > 0 ? max_size : z.diag, threads, &est);
    vc_sizing_free(&z);
    if (rc) {
        vc_features_free(f);
        return vc_error_set(err, VC_ENOMEM, "out of memory predicting the balls");
    }
    *n = est.n_balls;
    return 0;
}
