#include "util/number_span.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Characters that can belong to a number strtod accepts (decimal, hex float,
 * inf, nan); the run they form bounds what strtod can consume. */
static int number_char(char c)
{
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
           c == '.' || c == '+' || c == '-';
}

/* Copies the number-like run at b into buf (or a heap block when it is
 * long); returns the copy, its length in *n, or NULL when out of memory. */
static char *copy_run(const char *b, const char *e, char *buf, size_t cap, size_t *n)
{
    const char *t = b;
    while (t < e && number_char(*t))
        ++t;
    *n = (size_t)(t - b);
    char *s = (*n < cap) ? buf : malloc(*n + 1);
    if (!s)
        return NULL;
    memcpy(s, b, *n);
    s[*n] = '\0';
    return s;
}

/* Copies the number-like run at b and parses it as a double (is_int 0)
 * or a base-10 long long; returns the characters consumed. */
static size_t parse_span(const char *b, const char *e, int is_int, double *dv, long long *iv,
                         int *erange)
{
    char buf[128];
    size_t n;
    *erange = 0;
    char *s = copy_run(b, e, buf, sizeof buf, &n);
    size_t used = 0;
    if (s && n > 0) {
        char *end;
        errno = 0;
        if (is_int)
            *iv = strtoll(s, &end, 10);
        else
            *dv = strtod(s, &end);
        *erange = (errno == ERANGE);
        used = (size_t)(end - s);
    }
    if (s && s != buf)
        free(s);
    return used;
}

/* The exact powers of ten a double holds (10^22 is the last). */
static const double exact_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                       1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                       1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* A plain decimal [sign] digits [. digits] [(e|E) [sign] digits] that is
 * the whole number-like run at b, whose significant digits make an integer
 * of at most 2^53 and whose power of ten is at most 22 either way: then
 * that integer and that power are exact doubles, and one multiplication or
 * division rounds them once, correctly, to what strtod returns (Clinger's
 * fast path). Most files' coordinates (a few to fifteen digits) are such;
 * the rest go to strtod. Returns the characters consumed, or 0. */
static size_t fast_double(const char *b, const char *e, double *v)
{
    const char *p = b;
    int neg = 0;
    if (p < e && (*p == '+' || *p == '-'))
        neg = *p++ == '-';
    uint64_t m = 0;
    int digits = 0, significant = 0, scale = 0;
    while (p < e && *p >= '0' && *p <= '9') {
        if (significant || *p != '0') {
            if (++significant > 19)
                return 0;
            m = 10 * m + (uint64_t)(*p - '0');
        }
        digits++;
        p++;
    }
    if (p < e && *p == '.') {
        p++;
        while (p < e && *p >= '0' && *p <= '9') {
            if (significant || *p != '0') {
                if (++significant > 19)
                    return 0;
                m = 10 * m + (uint64_t)(*p - '0');
            }
            scale--;
            digits++;
            p++;
        }
    }
    if (digits == 0)
        return 0;
    if (p < e && (*p == 'e' || *p == 'E')) {
        p++;
        int eneg = 0;
        if (p < e && (*p == '+' || *p == '-'))
            eneg = *p++ == '-';
        int ex = 0, edigits = 0;
        while (p < e && *p >= '0' && *p <= '9') {
            if (ex < 10000)
                ex = 10 * ex + (*p - '0');
            edigits++;
            p++;
        }
        if (edigits == 0)
            return 0;
        scale += eneg ? -ex : ex;
    }
    /* the run must end here (strtod then stops here too) */
    if (p < e && number_char(*p))
        return 0;
    if (m > ((uint64_t)1 << 53) || scale > 22 || scale < -22)
        return 0;
    double x = (double)m;
    x = scale >= 0 ? x * exact_pow10[scale] : x / exact_pow10[-scale];
    *v = neg ? -x : x;
    return (size_t)(p - b);
}

/* [sign] at most 18 digits, the whole number-like run: exact in 64 bits. */
static size_t fast_int(const char *b, const char *e, long long *v)
{
    const char *p = b;
    int neg = 0;
    if (p < e && (*p == '+' || *p == '-'))
        neg = *p++ == '-';
    long long x = 0;
    int digits = 0;
    while (p < e && *p >= '0' && *p <= '9') {
        if (++digits > 18)
            return 0;
        x = 10 * x + (*p - '0');
        p++;
    }
    if (digits == 0 || (p < e && number_char(*p)))
        return 0;
    *v = neg ? -x : x;
    return (size_t)(p - b);
}

size_t vc_strtod_span(const char *b, const char *e, double *v, int *erange)
{
    const size_t n = fast_double(b, e, v);
    if (n) {
        *erange = 0;
        return n;
    }
    return parse_span(b, e, 0, v, NULL, erange);
}

size_t vc_strtoll_span(const char *b, const char *e, long long *v, int *erange)
{
    const size_t n = fast_int(b, e, v);
    if (n) {
        *erange = 0;
        return n;
    }
    return parse_span(b, e, 1, NULL, v, erange);
}
