/* The C unit tests' checks: each failed check prints where and what on
 * stderr and counts in `failures`; a test's main returns non-zero when
 * failures is not 0, so one run reports every failed check, not just the
 * first. */
#ifndef VC_TEST_CHECK_H
#define VC_TEST_CHECK_H

#include <math.h>
#include <stdio.h>

static int failures = 0;

#define CHECK(cond)                                                              \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            ++failures;                                                          \
        }                                                                        \
    } while (0)

/* With a message (a string) that says more, such as an error text. */
#define CHECK_MSG(cond, msg)                                                     \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "%s:%d: check failed: %s (message: %s)\n", __FILE__,  \
                    __LINE__, #cond, (msg));                                     \
            ++failures;                                                          \
        }                                                                        \
    } while (0)

/* With a printf-style explanation. */
#define CHECKF(cond, ...)                                                        \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                        \
            fputc('\n', stderr);                                                 \
            ++failures;                                                          \
        }                                                                        \
    } while (0)

/* |a - b| <= tol, printing both values when not. */
#define CHECK_NEAR(a, b, tol)                                                    \
    do {                                                                         \
        double a_ = (a), b_ = (b);                                               \
        if (!(fabs(a_ - b_) <= (tol))) {                                         \
            fprintf(stderr, "%s:%d: check failed: %s = %.17g, expected %.17g (tol %g)\n", \
                    __FILE__, __LINE__, #a, a_, b_, (double)(tol));              \
            ++failures;                                                          \
        }                                                                        \
    } while (0)

#endif
