/* strtod / strtoll on a span of a larger in-memory buffer.
 *
 * The readers parse whole files in place. Calling strtod directly on a
 * pointer into such a buffer is correct, but sanitizers with strict string
 * checks (ASAN_OPTIONS=strict_string_checks=1, as in CI) measure the whole
 * rest of the buffer at every call, which makes a million-row file
 * quadratic. These helpers copy just the number-like run of characters first,
 * so the cost is the token's length. */
#ifndef VC_UTIL_NUMBER_SPAN_H
#define VC_UTIL_NUMBER_SPAN_H

#include <stddef.h>

/* Parses a floating-point number at the start of [b, e). Returns the number
 * of characters consumed (0 when no number starts at b) and sets *v; sets
 * *erange to 1 when strtod reported ERANGE (overflow or underflow). */
size_t vc_strtod_span(const char *b, const char *e, double *v, int *erange);

/* Parses a base-10 integer at the start of [b, e); as vc_strtod_span. */
size_t vc_strtoll_span(const char *b, const char *e, long long *v, int *erange);

#endif
