/* The thread count a library call runs on: the caller's, or OpenMP's
 * default when it is 0 or less (1 without OpenMP). Not part of the public
 * API: threads are passed per call, the library changes no OpenMP setting. */
#ifndef VC_UTIL_THREADS_H
#define VC_UTIL_THREADS_H

#ifdef _OPENMP
#include <omp.h>
#endif

static inline int vc_threads_or_default(int threads)
{
#ifdef _OPENMP
    if (threads <= 0)
        threads = omp_get_max_threads();
    return threads > 0 ? threads : 1;
#else
    (void)threads;
    return 1;
#endif
}

#endif
