/* The balls a sampling would take, predicted before it (Sheehy's bound:
 * vc_ball_estimate). Internal to the pipeline: the denoised copy's choice
 * and the group borders' weigh their options with it. */
#ifndef VC_PIPELINE_PREDICT_BALLS_H
#define VC_PIPELINE_PREDICT_BALLS_H

#include "vorocrust/vorocrust.h"

/* The predicted balls of sampling s at theta_sharp sharp_angle, the
 * absolute error bound `bound` (> 0) and largest radius max_size (<= 0:
 * the diagonal), extra (or NULL) marking the edges that are creases
 * whatever their angle, into *n, and the features that took into *f (the
 * caller frees them). Returns 0, or an error code (*n 0, *f empty). */
int vc_predict_balls(const vc_surface *s, double sharp_angle, const unsigned char *extra,
                     double bound, double max_size, int threads, double *n, vc_features *f,
                     vc_error *err);

#endif
