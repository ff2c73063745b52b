/* When the pipeline says more about its progress. Internal. */
#ifndef VC_UTIL_PROGRESS_H
#define VC_UTIL_PROGRESS_H

/* Inputs of this many triangles or more take seconds in their checks and
 * their sizing: vc_mesh announces the checks and the sampler the sizing,
 * so that no 2 s pass without a line (a million triangles: 0.9 s at most). */
#define VC_LARGE_INPUT_TRIANGLES 100000

#endif
