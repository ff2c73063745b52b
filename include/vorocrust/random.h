/* The project's own seeded random generator (xoshiro256** seeded by
 * splitmix64), so that results never depend on the C library or on the
 * number of threads: every parallel task derives its own stream. */
#ifndef VORO_CRUST_RANDOM_H
#define VORO_CRUST_RANDOM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vc_rng {
    uint64_t s[4];
} vc_rng;

/* Seeds the generator; stream selects an independent sequence for the same
 * seed (e.g. a cell or task index). */
void vc_rng_init(vc_rng *rng, uint64_t seed, uint64_t stream);
uint64_t vc_rng_next(vc_rng *rng);
/* Uniform double in [0, 1). */
double vc_rng_uniform(vc_rng *rng);

#ifdef __cplusplus
}
#endif
#endif
