/* Exact orientation and insphere signs (see exact_predicates.h).
 *
 * Expansions: arrays of doubles, non-overlapping, in increasing magnitude,
 * zeros removed, whose exact sum is the value; the sign of the value is the
 * sign of the last (largest) component. The operations below keep those
 * properties (Shewchuk 1997, section 2): two_sum and two_product return a
 * rounded result and its exact error, grow adds a double to an expansion,
 * sum adds two, scale multiplies by a double, mul multiplies two. The exact
 * path is simple rather than fast (sums by repeated growth): it runs only
 * when the filter cannot decide. */
#include "util/exact_predicates.h"
#include "util/expansion.h"

#include <math.h>
#include <stdlib.h>

/* Expansions live in a per-thread arena while an evaluation holds one
 * (vc_expn_arena_begin): one block instead of a heap allocation per
 * operation; beyond it, or outside an evaluation, the heap. */
#define ARENA_BYTES ((size_t)60 << 10)
typedef struct expn_arena {
    char *base;
    size_t used;
    int depth;
} expn_arena;
static _Thread_local expn_arena tl_arena;

void vc_expn_arena_begin(void)
{
    if (tl_arena.depth++ == 0) {
        tl_arena.base = malloc(ARENA_BYTES);
        tl_arena.used = 0;
    }
}

void vc_expn_arena_end(void)
{
    if (--tl_arena.depth == 0) {
        free(tl_arena.base);
        tl_arena.base = NULL;
    }
}

static void *xalloc(size_t n)
{
    n = (n + 15) & ~(size_t)15;
    if (tl_arena.base && tl_arena.used + n <= ARENA_BYTES) {
        void *p = tl_arena.base + tl_arena.used;
        tl_arena.used += n;
        return p;
    }
    return malloc(n);
}

void vc_expn_release(void *p)
{
    const char *c = p;
    if (tl_arena.base && c >= tl_arena.base && c < tl_arena.base + ARENA_BYTES)
        return; /* freed with the arena */
    free(p);
}

/* The filters' relative error bounds: (3 + 16 eps) eps for orient3d's
 * permanent and (16 + 224 eps) eps for insphere's, eps = 2^-53 (Shewchuk
 * 1997, errboundA of each predicate). */
#define O3D_BOUND 7.7715611723761027e-16
#define ISP_BOUND (2 * 1.7763568394002532e-15) /* twice the bound: a margin costs only fallbacks */

static long long n_fallbacks;

long long vc_exact_predicate_fallbacks(void)
{
    return __atomic_load_n(&n_fallbacks, __ATOMIC_RELAXED);
}

/* x + y = a + b exactly, x the rounded sum. */
static inline void two_sum(double a, double b, double *x, double *y)
{
    const double s = a + b, bv = s - a, av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* x + y = a * b exactly, x the rounded product (fma is exact for the
 * error: it rounds a * b - x once, and that is representable). */
static inline void two_product(double a, double b, double *x, double *y)
{
    *x = a * b;
    *y = fma(a, b, -*x);
}

/* h = e + f, for nonoverlapping e and f as this file makes them (from
 * exact differences, two_product, scale and this sum, with round-to-even:
 * Shewchuk's strongly nonoverlapping expansions): the components of both
 * merged by magnitude, then accumulated in one pass, keeping the non-zero
 * rounding errors (his linear-time expansion sum, Theorem 13). h may not
 * alias e or f; it holds ne + nf components. Returns its length. */
static int sum(const double *e, int ne, const double *f, int nf, double *h)
{
    int i = 0, j = 0, n = 0;
    double q;
    if (ne + nf < 2) { /* not made here: every expansion has a component */
        h[0] = ne ? e[0] : f[0];
        return 1;
    }
    /* the two smallest components, in increasing magnitude */
    double g[2];
    for (int k = 0; k < 2; k++) {
        if (j >= nf || (i < ne && fabs(e[i]) <= fabs(f[j])))
            g[k] = e[i++];
        else
            g[k] = f[j++];
    }
    {
        /* fast two-sum: |g[1]| >= |g[0]| */
        q = g[1] + g[0];
        const double err = g[0] - (q - g[1]);
        if (err != 0)
            h[n++] = err;
    }
    while (i < ne || j < nf) {
        double x;
        if (j >= nf || (i < ne && fabs(e[i]) <= fabs(f[j])))
            x = e[i++];
        else
            x = f[j++];
        double s, err;
        two_sum(q, x, &s, &err);
        q = s;
        if (err != 0)
            h[n++] = err;
    }
    if (q != 0 || n == 0)
        h[n++] = q;
    return n;
}

/* h = e * b; returns its length (at most 2 ne). */
static int scale(const double *e, int ne, double b, double *h)
{
    int n = 0;
    double q, err;
    two_product(e[0], b, &q, &err);
    if (err != 0)
        h[n++] = err;
    for (int i = 1; i < ne; i++) {
        double p, perr, s, serr;
        two_product(e[i], b, &p, &perr);
        two_sum(q, perr, &s, &serr);
        if (serr != 0)
            h[n++] = serr;
        two_sum(p, s, &q, &err);
        if (err != 0)
            h[n++] = err;
    }
    if (q != 0 || n == 0)
        h[n++] = q;
    return n;
}

vc_expn vc_expn_from_double(double x)
{
    vc_expn r = {xalloc(sizeof(double)), 1};
    if (r.v)
        r.v[0] = x;
    return r;
}

/* a - b exactly, as an expansion of at most two components. */
vc_expn vc_expn_diff(double a, double b)
{
    vc_expn r = {xalloc(2 * sizeof(double)), 0};
    if (!r.v)
        return r;
    const double s = a - b, bv = a - s, av = s + bv;
    const double err = (a - av) + (bv - b);
    if (err != 0)
        r.v[r.n++] = err;
    r.v[r.n++] = s;
    return r;
}

vc_expn vc_expn_add(vc_expn a, vc_expn b)
{
    vc_expn r = {xalloc(sizeof(double) * (size_t)(a.n + b.n + 1)), 0};
    if (r.v && a.v && b.v)
        r.n = sum(a.v, a.n, b.v, b.n, r.v);
    else {
        vc_expn_release(r.v);
        r.v = NULL;
    }
    return r;
}

vc_expn vc_expn_neg(vc_expn a)
{
    for (int i = 0; a.v && i < a.n; i++)
        a.v[i] = -a.v[i];
    return a;
}

vc_expn vc_expn_mul(vc_expn a, vc_expn b)
{
    vc_expn acc = vc_expn_from_double(0);
    double *part = xalloc(sizeof(double) * (size_t)(2 * a.n + 1));
    if (!part || !a.v || !b.v || !acc.v) {
        vc_expn_release(part);
        vc_expn_release(acc.v);
        return (vc_expn){NULL, 0};
    }
    for (int j = 0; j < b.n; j++) {
        vc_expn p = {part, scale(a.v, a.n, b.v[j], part)};
        vc_expn s = vc_expn_add(acc, p);
        vc_expn_release(acc.v);
        acc = s;
        if (!acc.v)
            break;
    }
    vc_expn_release(part);
    return acc;
}

/* Frees x and y, returns x op y. */
vc_expn vc_expn_add_free(vc_expn x, vc_expn y)
{
    vc_expn r = vc_expn_add(x, y);
    vc_expn_release(x.v);
    vc_expn_release(y.v);
    return r;
}

vc_expn vc_expn_mul_free(vc_expn x, vc_expn y)
{
    vc_expn r = vc_expn_mul(x, y);
    vc_expn_release(x.v);
    vc_expn_release(y.v);
    return r;
}

vc_expn vc_expn_copy(vc_expn a)
{
    vc_expn r = {xalloc(sizeof(double) * (size_t)(a.n > 0 ? a.n : 1)), a.n};
    for (int i = 0; r.v && a.v && i < a.n; i++)
        r.v[i] = a.v[i];
    if (!a.v) {
        vc_expn_release(r.v);
        r.v = NULL;
    }
    return r;
}

/* The sign, or VC_PREDICATE_NOMEM when out of memory. */
int vc_expn_sign_free(vc_expn x)
{
    if (!x.v)
        return VC_PREDICATE_NOMEM;
    const double top = x.v[x.n - 1];
    vc_expn_release(x.v);
    return (top > 0) - (top < 0);
}

/* x0 * y1 - x1 * y0 (frees nothing) */
static vc_expn cross2(vc_expn x0, vc_expn y0, vc_expn x1, vc_expn y1)
{
    return vc_expn_add_free(vc_expn_mul(x0, y1), vc_expn_neg(vc_expn_mul(x1, y0)));
}

/* ---- orient3d ----------------------------------------------------------- */

static int orient3d_expansion(const double *a, const double *b, const double *c, const double *d)
{
    vc_expn ad[3], bd[3], cd[3];
    for (int k = 0; k < 3; k++) {
        ad[k] = vc_expn_diff(a[k], d[k]);
        bd[k] = vc_expn_diff(b[k], d[k]);
        cd[k] = vc_expn_diff(c[k], d[k]);
    }
    /* adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady) */
    vc_expn t1 = vc_expn_mul_free(vc_expn_copy(ad[2]), cross2(bd[0], bd[1], cd[0], cd[1]));
    vc_expn t2 = vc_expn_mul_free(vc_expn_copy(bd[2]), cross2(cd[0], cd[1], ad[0], ad[1]));
    vc_expn t3 = vc_expn_mul_free(vc_expn_copy(cd[2]), cross2(ad[0], ad[1], bd[0], bd[1]));
    const int s = vc_expn_sign_free(vc_expn_add_free(vc_expn_add_free(t1, t2), t3));
    for (int k = 0; k < 3; k++) {
        vc_expn_release(ad[k].v);
        vc_expn_release(bd[k].v);
        vc_expn_release(cd[k].v);
    }
    return s; /* VC_PREDICATE_NOMEM (2) when out of memory */
}

int vc_orient3d_exact(const double a[3], const double b[3], const double c[3], const double d[3])
{
    const double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    const double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    const double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const double cdxady = cdx * ady, adxcdy = adx * cdy;
    const double adxbdy = adx * bdy, bdxady = bdx * ady;
    const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    const double perm = (fabs(bdxcdy) + fabs(cdxbdy)) * fabs(adz) +
                        (fabs(cdxady) + fabs(adxcdy)) * fabs(bdz) +
                        (fabs(adxbdy) + fabs(bdxady)) * fabs(cdz);
    const double bound = O3D_BOUND * perm;
    if (det > bound)
        return 1;
    if (det < -bound)
        return -1;
    __atomic_add_fetch(&n_fallbacks, 1, __ATOMIC_RELAXED);
    return orient3d_expansion(a, b, c, d);
}

/* ---- insphere ----------------------------------------------------------- */

/* The determinant below, with every difference to e exact. */
static int insphere_expansion(const double *a, const double *b, const double *c, const double *d,
                              const double *e)
{
    const double *p[4] = {a, b, c, d};
    vc_expn x[4], y[4], z[4], lift[4];
    for (int i = 0; i < 4; i++) {
        x[i] = vc_expn_diff(p[i][0], e[0]);
        y[i] = vc_expn_diff(p[i][1], e[1]);
        z[i] = vc_expn_diff(p[i][2], e[2]);
        lift[i] = vc_expn_add_free(vc_expn_add_free(vc_expn_mul(x[i], x[i]), vc_expn_mul(y[i], y[i])), vc_expn_mul(z[i], z[i]));
    }
    /* the 2x2 minors of the x, y columns */
    vc_expn ab = cross2(x[0], y[0], x[1], y[1]), bc = cross2(x[1], y[1], x[2], y[2]);
    vc_expn cd = cross2(x[2], y[2], x[3], y[3]), da = cross2(x[3], y[3], x[0], y[0]);
    vc_expn ac = cross2(x[0], y[0], x[2], y[2]), bd = cross2(x[1], y[1], x[3], y[3]);
    /* the 3x3 minors */
    vc_expn abc = vc_expn_add_free(vc_expn_add_free(vc_expn_mul(z[0], bc), vc_expn_neg(vc_expn_mul(z[1], ac))), vc_expn_mul(z[2], ab));
    vc_expn bcd = vc_expn_add_free(vc_expn_add_free(vc_expn_mul(z[1], cd), vc_expn_neg(vc_expn_mul(z[2], bd))), vc_expn_mul(z[3], bc));
    vc_expn cda = vc_expn_add_free(vc_expn_add_free(vc_expn_mul(z[2], da), vc_expn_mul(z[3], ac)), vc_expn_mul(z[0], cd));
    vc_expn dab = vc_expn_add_free(vc_expn_add_free(vc_expn_mul(z[3], ab), vc_expn_mul(z[0], bd)), vc_expn_mul(z[1], da));
    /* (dlift abc - clift dab) + (blift cda - alift bcd) */
    vc_expn det = vc_expn_add_free(vc_expn_add_free(vc_expn_mul(lift[3], abc), vc_expn_neg(vc_expn_mul(lift[2], dab))),
                        vc_expn_add_free(vc_expn_mul(lift[1], cda), vc_expn_neg(vc_expn_mul(lift[0], bcd))));
    const int s = vc_expn_sign_free(det);
    for (int i = 0; i < 4; i++) {
        vc_expn_release(x[i].v);
        vc_expn_release(y[i].v);
        vc_expn_release(z[i].v);
        vc_expn_release(lift[i].v);
    }
    vc_expn_release(ab.v);
    vc_expn_release(bc.v);
    vc_expn_release(cd.v);
    vc_expn_release(da.v);
    vc_expn_release(ac.v);
    vc_expn_release(bd.v);
    vc_expn_release(abc.v);
    vc_expn_release(bcd.v);
    vc_expn_release(cda.v);
    vc_expn_release(dab.v);
    return s;
}

int vc_insphere_exact(const double a[3], const double b[3], const double c[3], const double d[3],
                      const double e[3])
{
    const double aex = a[0] - e[0], aey = a[1] - e[1], aez = a[2] - e[2];
    const double bex = b[0] - e[0], bey = b[1] - e[1], bez = b[2] - e[2];
    const double cex = c[0] - e[0], cey = c[1] - e[1], cez = c[2] - e[2];
    const double dex = d[0] - e[0], dey = d[1] - e[1], dez = d[2] - e[2];
    const double aexbey = aex * bey, bexaey = bex * aey, ab = aexbey - bexaey;
    const double bexcey = bex * cey, cexbey = cex * bey, bc = bexcey - cexbey;
    const double cexdey = cex * dey, dexcey = dex * cey, cd = cexdey - dexcey;
    const double dexaey = dex * aey, aexdey = aex * dey, da = dexaey - aexdey;
    const double aexcey = aex * cey, cexaey = cex * aey, ac = aexcey - cexaey;
    const double bexdey = bex * dey, dexbey = dex * bey, bd = bexdey - dexbey;
    const double abc = aez * bc - bez * ac + cez * ab;
    const double bcd = bez * cd - cez * bd + dez * bc;
    const double cda = cez * da + dez * ac + aez * cd;
    const double dab = dez * ab + aez * bd + bez * da;
    const double alift = aex * aex + aey * aey + aez * aez;
    const double blift = bex * bex + bey * bey + bez * bez;
    const double clift = cex * cex + cey * cey + cez * cez;
    const double dlift = dex * dex + dey * dey + dez * dez;
    const double det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
    const double aez_ = fabs(aez), bez_ = fabs(bez), cez_ = fabs(cez), dez_ = fabs(dez);
    const double aexbey_ = fabs(aexbey) + fabs(bexaey), bexcey_ = fabs(bexcey) + fabs(cexbey);
    const double cexdey_ = fabs(cexdey) + fabs(dexcey), dexaey_ = fabs(dexaey) + fabs(aexdey);
    const double aexcey_ = fabs(aexcey) + fabs(cexaey), bexdey_ = fabs(bexdey) + fabs(dexbey);
    const double perm =
        ((cexdey_ * bez_ + bexdey_ * cez_ + bexcey_ * dez_) * alift +
         (dexaey_ * cez_ + aexcey_ * dez_ + cexdey_ * aez_) * blift) +
        ((aexbey_ * dez_ + bexdey_ * aez_ + dexaey_ * bez_) * clift +
         (bexcey_ * aez_ + aexcey_ * bez_ + aexbey_ * cez_) * dlift);
    const double bound = ISP_BOUND * perm;
    if (det > bound)
        return 1;
    if (det < -bound)
        return -1;
    __atomic_add_fetch(&n_fallbacks, 1, __ATOMIC_RELAXED);
    return insphere_expansion(a, b, c, d, e);
}
