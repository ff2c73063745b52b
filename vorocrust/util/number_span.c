#include "util/number_span.h"

#include <errno.h>
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

size_t vc_strtod_span(const char *b, const char *e, double *v, int *erange)
{
    return parse_span(b, e, 0, v, NULL, erange);
}

size_t vc_strtoll_span(const char *b, const char *e, long long *v, int *erange)
{
    return parse_span(b, e, 1, NULL, v, erange);
}
