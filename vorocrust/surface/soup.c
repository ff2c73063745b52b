/* The polygon soup the readers fill, and the text scanner they share. */
#include "surface/surface_internal.h"
#include "util/number_span.h"
#include "util/reserve.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

int vc_soup_add_vertex(vc_soup *s, double x, double y, double z)
{
    if (vc_reserve(&s->xyz, &s->cap_v, s->nv + 1, 3 * sizeof(double)))
        return VC_ENOMEM;
    double *v = s->xyz + 3 * s->nv++;
    v[0] = x;
    v[1] = y;
    v[2] = z;
    return 0;
}

int vc_soup_add_face(vc_soup *s, const int64_t *v, int64_t n)
{
    if (n < 0 || n > INT64_MAX - s->ni)
        return VC_ENOMEM;
    if (vc_reserve(&s->off, &s->cap_f, s->nf + 2, sizeof(int64_t)) ||
        vc_reserve(&s->idx, &s->cap_i, s->ni + n, sizeof(int64_t)))
        return VC_ENOMEM;
    if (s->nf == 0)
        s->off[0] = 0;
    memcpy(s->idx + s->ni, v, (size_t)n * sizeof(int64_t));
    s->ni += n;
    s->off[++s->nf] = s->ni;
    return 0;
}

void vc_soup_free(vc_soup *s)
{
    free(s->xyz);
    free(s->off);
    free(s->idx);
    memset(s, 0, sizeof *s);
}

void vc_scan_space(vc_scan *sc, int comments)
{
    while (sc->p < sc->end) {
        char c = *sc->p;
        if (vc_scan_is_blank(c)) {
            sc->p++;
        } else if (c == '\n') {
            sc->p++;
            sc->line++;
        } else if (comments && c == '#') {
            while (sc->p < sc->end && *sc->p != '\n')
                sc->p++;
        } else {
            break;
        }
    }
}

int vc_scan_double(vc_scan *sc, double *v)
{
    vc_scan_blanks(sc);
    if (sc->p >= sc->end || *sc->p == '\n')
        return 0;
    double d;
    int erange;
    const char *e = sc->p + vc_strtod_span(sc->p, sc->end, &d, &erange);
    /* ERANGE on underflow still gives a usable value; overflow gives inf,
     * which the caller's finiteness check reports. */
    if (e == sc->p || e > sc->end || !vc_scan_is_end(sc, e))
        return 0;
    sc->p = e;
    *v = d;
    return 1;
}

int vc_scan_int(vc_scan *sc, int64_t *v)
{
    vc_scan_blanks(sc);
    if (sc->p >= sc->end || *sc->p == '\n')
        return 0;
    long long k;
    int erange;
    const char *e = sc->p + vc_strtoll_span(sc->p, sc->end, &k, &erange);
    if (e == sc->p || erange || !vc_scan_is_end(sc, e))
        return 0;
    sc->p = e;
    *v = (int64_t)k;
    return 1;
}

size_t vc_scan_word(vc_scan *sc, char *w, size_t cap)
{
    vc_scan_blanks(sc);
    size_t n = 0;
    while (sc->p < sc->end && !vc_scan_is_blank(*sc->p) && *sc->p != '\n') {
        if (n + 1 < cap)
            w[n] = *sc->p;
        n++;
        sc->p++;
    }
    if (cap)
        w[n < cap ? n : cap - 1] = '\0';
    return n;
}
