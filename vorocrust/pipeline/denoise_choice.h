/* Whether the sampling takes a denoised copy of the input (see
 * denoise_choice.c). Internal to the pipeline. */
#ifndef VC_PIPELINE_DENOISE_CHOICE_H
#define VC_PIPELINE_DENOISE_CHOICE_H

#include "vorocrust/vorocrust.h"

/* Smoothing moves no vertex farther than this share of the error bound;
 * the denoised surface is then sampled within the rest of it. */
#define VC_DENOISE_SHARE 0.5
/* Taubin lambda|mu pairs of steps */
#define VC_DENOISE_ITERATIONS 80
/* The denoised copy is taken when the input's predicted balls are at
 * least this many times the copy's. */
#define VC_DENOISE_GAIN 1.5
/* ... and only when its enclosed volume is within this share of the
 * input's: a copy that removes noise changes it by 1e-4 or less (noisy
 * spheres and blobs, 2e4 to 8e4 triangles), one that moves real geometry
 * (the corners and creases of a CAD part, its walls and gaps) by 2e-3 to
 * 4e-2, most of or more than the 0.5% a mesh may be off
 * (docs/sampling-convergence.md, session 38). */
#define VC_DENOISE_MAX_VOLUME_CHANGE 1e-3
/* After the input's sampling diverged, the copy is the remedy when its
 * volume is within this share of the input's: half the 0.5% a mesh may be
 * off. The other remedy, folds made creases where sliver elimination is
 * stuck, samples everything again per round and leaves slivers on
 * marching-cubes staircases (a gyroid clipped by a box, 74k triangles:
 * three rounds, 144 s, surface Q min 0.001, fattest cell 1,870; the copy,
 * +0.11% of the volume: 15 s, Q min 0.078, fattest cell 22); copies of
 * CAD parts change the volume by 0.5% and more, ridged and touching
 * shapes by 0.27 to 0.30% (docs/sampling-convergence.md, sessions 38 and
 * 41). */
#define VC_DENOISE_REMEDY_VOLUME_CHANGE 2.5e-3

/* Predicts the balls of a sampling of s at theta_sharp sharp_angle (extra:
 * the edges that are creases whatever their angle, or NULL), the absolute
 * error bound `bound` (> 0) and largest radius max_size (<= 0: the
 * diagonal), then, when the input's balls where its radius bound is below
 * the error bound could make the difference, of a denoised copy
 * (vc_make_denoised) sampled within the rest of the bound. A copy made
 * is left in *denoised (the caller frees it; kept for a sampling of the
 * input that diverges; none: zeroed), and ch->used set when it takes
 * VC_DENOISE_GAIN times fewer balls (force > 0: always, nothing
 * predicted; force < 0: never, nothing done) and changes the enclosed
 * volume by at most VC_DENOISE_MAX_VOLUME_CHANGE. When both were predicted,
 * *f_chosen gets the features (vc_features_detect_scaled at the bound it
 * is sampled at) of the surface chosen, for the caller to sample with and
 * free; otherwise it is zeroed (n_triangles 0). A rough input is said on
 * log (a line naming the input, name) before the predictions, which take
 * seconds on a fine one. Returns 0, or an error
 * code (VC_ENOMEM) with *denoised and *f_chosen zeroed. */
/* The copy alone: vc_surface_denoise of s by VC_DENOISE_SHARE of the
 * absolute bound into *denoised, ch->moved, ch->bound and ch->volume_change
 * set. */
int vc_make_denoised(const vc_surface *s, double bound, int threads, vc_surface *denoised,
                     vc_denoise_choice *ch, vc_error *err);

int vc_choose_denoised(const vc_surface *s, double sharp_angle, const unsigned char *extra,
                       double bound, double max_size, int force, int threads,
                       vc_surface *denoised, vc_denoise_choice *ch, vc_features *f_chosen,
                       const vc_logger *log, const char *name, vc_error *err);

#endif
