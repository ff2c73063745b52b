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

/* Index of the group of that name, added when new; -1 when out of memory. */
static int32_t group_index(vc_soup *s, const char *name, size_t len)
{
    char w[64];
    if (len > 63)
        len = 63;
    memcpy(w, name, len);
    w[len] = 0;
    if (!w[0])
        strcpy(w, "surface");
    for (int32_t g = 0; g < s->n_groups; g++)
        if (!strcmp(s->group_name[g], w))
            return g;
    if (s->n_groups == s->cap_names) {
        const int32_t cap = s->cap_names ? 2 * s->cap_names : 8;
        char(*p)[64] = realloc(s->group_name, sizeof *p * (size_t)cap);
        if (!p)
            return -1;
        s->group_name = p;
        s->cap_names = cap;
    }
    memcpy(s->group_name[s->n_groups], w, 64);
    return s->n_groups++;
}

int vc_soup_set_group_rest(vc_soup *s, vc_scan *sc)
{
    const char *a = sc->p;
    while (a < sc->end && vc_scan_is_blank(*a))
        a++;
    const char *b = a;
    while (b < sc->end && *b != '\n')
        b++;
    while (b > a && (vc_scan_is_blank(b[-1]) || b[-1] == '\r'))
        b--;
    return vc_soup_set_group(s, a, (size_t)(b - a));
}

int vc_soup_set_group(vc_soup *s, const char *name, size_t len)
{
    if (s->n_groups == 0 && s->nf > 0) {
        /* the faces so far had no group: the group "surface" */
        if (vc_reserve(&s->face_group, &s->cap_g, s->nf + 1, sizeof(int32_t)))
            return VC_ENOMEM;
        const int32_t d = group_index(s, "surface", 7);
        if (d < 0)
            return VC_ENOMEM;
        for (int64_t f = 0; f < s->nf; f++)
            s->face_group[f] = d;
    }
    const int32_t g = group_index(s, name, len);
    if (g < 0)
        return VC_ENOMEM;
    s->cur_group = g;
    return 0;
}

int vc_soup_add_face(vc_soup *s, const int64_t *v, int64_t n)
{
    if (n < 0 || n > INT64_MAX - s->ni)
        return VC_ENOMEM;
    if (s->n_groups > 0) {
        if (vc_reserve(&s->face_group, &s->cap_g, s->nf + 1, sizeof(int32_t)))
            return VC_ENOMEM;
        s->face_group[s->nf] = s->cur_group;
    }
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
    free(s->face_group);
    free(s->group_name);
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
