/* Wall-clock seconds for the phase timings the library reports. Internal. */
#ifndef VC_UTIL_CLOCK_H
#define VC_UTIL_CLOCK_H

#include <time.h>

/* Seconds on the monotonic clock (from an arbitrary origin). */
static inline double vc_clock_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#endif
