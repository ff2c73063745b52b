/* The exact side test of the Voronoi engine (see power_side.h).
 *
 * Coordinates relative to s. A bisector of s and seed a is the constraint
 * p_a . v = (|p_a|^2 - w_a + w_s) / 2 (p_a = a - s, w the weights), a wall
 * of axis k at X is e_k . v = X - s_k. With the three planes of the vertex
 * as rows [n_i, -d_i] of a 4 x 4 matrix M and the tested plane as the last
 * row ([-p_x, (|p_x|^2 - w_x + w_s) / 2] for the bisector of s and x),
 * det M = det A * f(v), A the 3 x 3 block of normals and f(v) half the
 * power of v with respect to x minus that with respect to s (a Schur
 * complement). So the side is sign(det M) * sign(det A).
 *
 * det M is affine in the weights (they appear only in the last column):
 * det M = det M0 + sum_j w_j coef_j, coef_j = sum_i D_ij C_i with C_i the
 * cofactors of the last column and D_ij the derivative of row i's last
 * entry by w_j (+-1/2; the common factor 1/2 is dropped). With w_j =
 * eps^(j+1), the sign is that of det M0 or else of the first non-zero
 * coef_j in increasing seed index. coef_x = -det A is never zero, so the
 * test always decides. f is the same function of the weights in every
 * cell holding the vertex (the vertex is where the powers of its seeds are
 * equal), so every cell reads the same sign. */
#include "power_side.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/small_sort.h"

#include "util/exact_predicates.h"
#include "util/bigint.h"
#include "util/expansion.h"

/* The double-double stage rounds every product with fma. Built for plain
 * x86-64 (no FMA in the baseline), each fma() is a call into libm; the
 * functions that multiply are cloned for CPUs with FMA instead, chosen
 * once at load time (GNU ifunc): the instruction inline, 15 to 20% of the
 * cells' time on VoroCrust seeds (bunny.off). fma is exact either way, so
 * every clone gives the same bits. */
#if defined(__x86_64__) && !defined(__FMA__) && defined(__GNUC__) && defined(__linux__) && \
    !defined(__clang__)
#define VC_FMA_CLONES __attribute__((target_clones("fma", "default")))
#else
#define VC_FMA_CLONES
#endif

/* Which seed weights move a row's last entry: d(last)/dw = +1 for plus,
 * -1 for minus (-1: none). */
typedef struct row_weight {
    int64_t plus, minus;
} row_weight;

/* One row of M: three normal components and the last entry. */
typedef struct row {
    vc_expn n[3], last;
    row_weight w;
} row;

static void row_free(row *r)
{
    for (int k = 0; k < 3; k++)
        vc_expn_release(r->n[k].v);
    vc_expn_release(r->last.v);
}

/* |p|^2 / 2 for the expansion vector p (p kept). */
static vc_expn half_norm2(const vc_expn p[3])
{
    vc_expn q = vc_expn_add_free(vc_expn_add_free(vc_expn_mul(p[0], p[0]), vc_expn_mul(p[1], p[1])),
                                 vc_expn_mul(p[2], p[2]));
    return vc_expn_mul_free(q, vc_expn_from_double(0.5));
}

/* The row of plane id (bisector or wall) for the cell of s. A vertex
 * plane: [n, -d]. tested: the tested bisector's row [-p, |p|^2 / 2]
 * (the wall's row is the same either way). */
static row make_row(const vc_power_ctx *ctx, int64_t s, int64_t id, int tested)
{
    row r;
    const double *xs = ctx->xyz + 3 * s;
    r.w.plus = r.w.minus = -1;
    if (id >= 0) {
        const double *xa = ctx->xyz + 3 * id;
        for (int k = 0; k < 3; k++)
            r.n[k] = vc_expn_diff(xa[k], xs[k]);
        r.last = half_norm2(r.n);
        if (tested) {
            for (int k = 0; k < 3; k++)
                r.n[k] = vc_expn_neg(r.n[k]);
            r.w.plus = s;   /* (|p|^2 - w_x + w_s) / 2 */
            r.w.minus = id;
        } else {
            r.last = vc_expn_neg(r.last); /* -(|p|^2 - w_a + w_s) / 2 */
            r.w.plus = id;
            r.w.minus = s;
        }
    } else {
        const int k = (int)(-1 - id), axis = k / 2; /* VC_WALL_XMIN = -1 */
        const double X = (k % 2) ? ctx->box_hi[axis] : ctx->box_lo[axis];
        for (int j = 0; j < 3; j++)
            r.n[j] = vc_expn_from_double(j == axis ? 1.0 : 0.0);
        r.last = vc_expn_neg(vc_expn_diff(X, xs[axis]));
    }
    return r;
}

/* det [a; b; c] of expansion rows (operands kept). */
static vc_expn det3(const vc_expn *a, const vc_expn *b, const vc_expn *c)
{
    vc_expn m0 = vc_expn_add_free(vc_expn_mul(b[1], c[2]), vc_expn_neg(vc_expn_mul(b[2], c[1])));
    vc_expn m1 = vc_expn_add_free(vc_expn_mul(b[0], c[2]), vc_expn_neg(vc_expn_mul(b[2], c[0])));
    vc_expn m2 = vc_expn_add_free(vc_expn_mul(b[0], c[1]), vc_expn_neg(vc_expn_mul(b[1], c[0])));
    vc_expn t = vc_expn_add_free(vc_expn_mul_free(vc_expn_copy(a[0]), m0),
                                 vc_expn_neg(vc_expn_mul_free(vc_expn_copy(a[1]), m1)));
    return vc_expn_add_free(t, vc_expn_mul_free(vc_expn_copy(a[2]), m2));
}

/* The cofactors C_i of the last column of M (rows r[0..3]). */
static void cofactors(const row *r, vc_expn C[4])
{
    for (int i = 0; i < 4; i++) {
        const vc_expn *q[3];
        for (int j = 0, m = 0; j < 4; j++)
            if (j != i)
                q[m++] = r[j].n;
        C[i] = det3(q[0], q[1], q[2]);
        if ((i + 3) % 2)
            C[i] = vc_expn_neg(C[i]);
    }
}

#define SEED_LESS(x, y) (*(x) < *(y))
VC_SMALL_SORT(sort_seeds, int64_t, SEED_LESS)

/* Sorts seed[0..n) and drops repeats; returns the count (a few seeds:
 * glibc's qsort allocates and calls a comparator). */
static int sorted_unique(int64_t *seed, int n)
{
    sort_seeds(seed, n);
    int w = 0;
    for (int i = 0; i < n; i++)
        if (w == 0 || seed[i] != seed[w - 1])
            seed[w++] = seed[i];
    return w;
}

/* The seeds whose weights move the four rows, ascending, once each;
 * returns their count. */
static int weighted_seeds(const row_weight w[4], int64_t seed[8])
{
    int ns = 0;
    for (int i = 0; i < 4; i++) {
        if (w[i].plus >= 0)
            seed[ns++] = w[i].plus;
        if (w[i].minus >= 0)
            seed[ns++] = w[i].minus;
    }
    return sorted_unique(seed, ns);
}

/* sign(det M0), or with perturb the sign of det M(eps); C: the cofactors. */
static int det_sign(const row *r, const vc_expn C[4], int perturb)
{
    vc_expn d = vc_expn_from_double(0);
    for (int i = 0; i < 4; i++)
        d = vc_expn_add_free(d, vc_expn_mul(r[i].last, C[i]));
    const int s0 = vc_expn_sign_free(d);
    if (s0 != 0 || !perturb)
        return s0;
    int64_t seed[8];
    const row_weight w[4] = {r[0].w, r[1].w, r[2].w, r[3].w};
    const int ns = weighted_seeds(w, seed);
    for (int m = 0; m < ns; m++) {
        vc_expn coef = vc_expn_from_double(0);
        for (int i = 0; i < 4; i++) {
            if (r[i].w.plus == seed[m])
                coef = vc_expn_add_free(coef, vc_expn_copy(C[i]));
            if (r[i].w.minus == seed[m])
                coef = vc_expn_add_free(coef, vc_expn_neg(vc_expn_copy(C[i])));
        }
        const int sc = vc_expn_sign_free(coef);
        if (sc != 0)
            return sc;
    }
    return 0; /* not reached for a tested bisector: coef_x = -det A */
}

/* ---- the double-double stage ----------------------------------------
 * det M0 in double-double arithmetic (a value as an unevaluated sum hi +
 * lo, about 106 bits): the differences to s are exact, every later
 * operation errs by at most a few units of 2^-104 of its magnitude. With
 * a bound on that error from the permanent (the same sums of absolute
 * values), this decides every vertex that rounding alone puts near the
 * plane (seeds co-spherical to rounding, rounded lattices) at the cost of
 * some hundred floating-point operations; only exact ties, and values
 * below about 1e-29 of the permanent, go on to the expansions. */
typedef struct dd {
    double hi, lo;
} dd;

static inline dd dd_two_sum(double a, double b)
{
    const double s = a + b, bv = s - a, av = s - bv;
    return (dd){s, (a - av) + (b - bv)};
}

/* The operations below also clear *ex when they round: a value computed
 * with *ex still set is exact (the inputs' differences are exact, and
 * lattice-like seeds, whose coordinates have few significant bits, keep
 * every product and sum exact: their ties are then settled here). */
static inline dd dd_add(dd a, dd b, int *ex)
{
    dd s = dd_two_sum(a.hi, b.hi);
    const dd t1 = dd_two_sum(s.lo, a.lo), t2 = dd_two_sum(t1.hi, b.lo);
    *ex &= (t1.lo == 0) & (t2.lo == 0);
    return dd_two_sum(s.hi, t2.hi);
}

static inline dd dd_neg(dd a) { return (dd){-a.hi, -a.lo}; }

static inline dd dd_mul(dd a, dd b, int *ex)
{
    const double p = a.hi * b.hi, pe = fma(a.hi, b.hi, -p);
    /* Two plain doubles (the rows' differences of seed coordinates,
     * nearly always exact): the product is exactly p + pe, and the general
     * path below would give (p, pe) with *ex untouched. */
    if (a.lo == 0 && b.lo == 0)
        return (dd){p, pe};
    const double c1 = a.hi * b.lo, c2 = a.lo * b.hi;
    const dd e1 = dd_two_sum(pe, c1), e2 = dd_two_sum(e1.hi, c2);
    *ex &= (fma(a.hi, b.lo, -c1) == 0) & (fma(a.lo, b.hi, -c2) == 0) & (a.lo * b.lo == 0) &
           (e1.lo == 0) & (e2.lo == 0);
    return dd_two_sum(p, e2.hi);
}

static inline double dd_abs(dd a) { return fabs(a.hi) + fabs(a.lo); }

static inline int dd_sign(dd a)
{
    const double v = a.hi != 0 ? a.hi : a.lo;
    return (v > 0) - (v < 0);
}

/* A row in double-double: normals and last entry. */
typedef struct dd_row {
    dd n[3], last;
    row_weight w;
} dd_row;

VC_FMA_CLONES
static dd_row make_dd_row(const vc_power_ctx *ctx, int64_t s, int64_t id, int tested, int *ex)
{
    dd_row r;
    const double *xs = ctx->xyz + 3 * s;
    r.w.plus = r.w.minus = -1;
    if (id >= 0) {
        const double *xa = ctx->xyz + 3 * id;
        for (int k = 0; k < 3; k++)
            r.n[k] = dd_two_sum(xa[k], -xs[k]); /* exact */
        dd q = dd_add(dd_add(dd_mul(r.n[0], r.n[0], ex), dd_mul(r.n[1], r.n[1], ex), ex),
                      dd_mul(r.n[2], r.n[2], ex), ex);
        q.hi *= 0.5; /* exact unless it underflows */
        q.lo *= 0.5;
        if (tested) {
            for (int k = 0; k < 3; k++)
                r.n[k] = dd_neg(r.n[k]);
            r.last = q;
            r.w.plus = s;
            r.w.minus = id;
        } else {
            r.last = dd_neg(q);
            r.w.plus = id;
            r.w.minus = s;
        }
    } else {
        const int k = (int)(-1 - id), axis = k / 2;
        const double X = (k % 2) ? ctx->box_hi[axis] : ctx->box_lo[axis];
        for (int j = 0; j < 3; j++)
            r.n[j] = (dd){j == axis ? 1.0 : 0.0, 0.0};
        r.last = dd_neg(dd_two_sum(X, -xs[axis]));
    }
    return r;
}

/* The double-double stage: the sign of det M0 (0 for an exact tie), or
 * with side the perturbed side as vc_power_side returns it, when this
 * stage can tell; 2 when it cannot. */
VC_FMA_CLONES
static int dd_stage(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t q,
                    int side)
{
    int ex = 1;
    dd_row r[4];
    for (int i = 0; i < 3; i++)
        r[i] = make_dd_row(ctx, s, plane[i], 0, &ex);
    r[3] = make_dd_row(ctx, s, q, 1, &ex);
    dd det = {0, 0}, C[4];
    double perm = 0, permA = 0;
    for (int i = 0; i < 4; i++) {
        const dd_row *a[3];
        for (int j = 0, m = 0; j < 4; j++)
            if (j != i)
                a[m++] = &r[j];
        /* det3 of the normals of a[0..2] */
        dd m0 = dd_add(dd_mul(a[1]->n[1], a[2]->n[2], &ex), dd_neg(dd_mul(a[1]->n[2], a[2]->n[1], &ex)), &ex);
        dd m1 = dd_add(dd_mul(a[1]->n[0], a[2]->n[2], &ex), dd_neg(dd_mul(a[1]->n[2], a[2]->n[0], &ex)), &ex);
        dd m2 = dd_add(dd_mul(a[1]->n[0], a[2]->n[1], &ex), dd_neg(dd_mul(a[1]->n[1], a[2]->n[0], &ex)), &ex);
        dd c = dd_add(dd_add(dd_mul(a[0]->n[0], m0, &ex), dd_neg(dd_mul(a[0]->n[1], m1, &ex)), &ex),
                      dd_mul(a[0]->n[2], m2, &ex), &ex);
        const double p0 = dd_abs(a[1]->n[1]) * dd_abs(a[2]->n[2]) + dd_abs(a[1]->n[2]) * dd_abs(a[2]->n[1]);
        const double p1 = dd_abs(a[1]->n[0]) * dd_abs(a[2]->n[2]) + dd_abs(a[1]->n[2]) * dd_abs(a[2]->n[0]);
        const double p2 = dd_abs(a[1]->n[0]) * dd_abs(a[2]->n[1]) + dd_abs(a[1]->n[1]) * dd_abs(a[2]->n[0]);
        const double pc = dd_abs(a[0]->n[0]) * p0 + dd_abs(a[0]->n[1]) * p1 + dd_abs(a[0]->n[2]) * p2;
        if ((i + 3) % 2)
            c = dd_neg(c);
        C[i] = c;
        if (i == 3)
            permA = pc;
        det = dd_add(det, dd_mul(r[i].last, c, &ex), &ex);
        perm += dd_abs(r[i].last) * pc;
    }
    /* det A = C[3], never zero for a vertex */
    const double boundA = 64.0 * 4.930380657631324e-32 * permA;
    int sa = dd_sign(C[3]);
    if (!ex && fabs(C[3].hi + C[3].lo) <= boundA)
        return 2;
    int sm;
    if (ex)
        sm = dd_sign(det);
    else {
        /* about 12 operations deep, each within 4 * 2^-104 of its
         * magnitude: 64 * 2^-104 * perm with room */
        const double bound = 64.0 * 4.930380657631324e-32 * perm, v = det.hi + det.lo;
        sm = v > bound ? 1 : (v < -bound ? -1 : 2);
        if (sm == 2)
            return 2;
    }
    if (!side)
        return sm;
    if (sm == 0) {
        /* an exact tie: the first weight, by seed index, whose
         * coefficient (a sum of cofactors, exact here) is not zero */
        int64_t seed[8];
        const row_weight w[4] = {r[0].w, r[1].w, r[2].w, r[3].w};
        const int ns = weighted_seeds(w, seed);
        for (int m = 0; m < ns && sm == 0; m++) {
            dd coef = {0, 0};
            for (int i = 0; i < 4; i++) {
                if (r[i].w.plus == seed[m])
                    coef = dd_add(coef, C[i], &ex);
                if (r[i].w.minus == seed[m])
                    coef = dd_add(coef, dd_neg(C[i]), &ex);
            }
            if (!ex)
                return 2;
            sm = dd_sign(coef);
        }
    }
    return sm * sa > 0 ? 1 : -1;
}

/* ---- the integer stage: exact ties in fixed-width integers ------------
 * Every double involved (s, the rows' seeds, the walls) is M 2^e with M a
 * 53-bit integer; brought to the smallest exponent E of them, each is an
 * integer, and so are the differences to s. Row by row, a seed row [p,
 * -|p|^2 / 2] (p = I 2^E) times 2^(1-E) is [2 I, -|I|^2 2^E], a wall row
 * [e_k, -(X - s_k)] times 2 is [2 e_k, -2 J 2^E]; the last column then
 * shares the factor 2^E, dropped. Every factor is positive, so det M, det
 * A and every coefficient of the weights (which the seed rows scale alike)
 * keep their signs. What does not fit the integers' capacity (exponents
 * too far apart) goes to the expansions. */
typedef struct int_row {
    vc_bigint n[3], last;
    row_weight w;
} int_row;

static void min_exponent(double v, int *E)
{
    if (v != 0) {
        int e;
        (void)frexp(v, &e);
        if (e - 53 < *E)
            *E = e - 53;
    }
}

/* v as an integer in units of 2^E (E at most v's exponent less 53). */
static int to_integer(double v, int E, vc_bigint *r)
{
    if (v == 0)
        return vc_bigint_set(r, 0, 0);
    int e;
    const double f = frexp(v, &e);
    return vc_bigint_set(r, (int64_t)ldexp(f, 53), e - 53 - E);
}

static int make_int_row(const vc_power_ctx *ctx, const vc_bigint S[3], int E, int64_t s,
                        int64_t id, int tested, int_row *r)
{
    int rc = 0;
    r->w.plus = r->w.minus = -1;
    if (id >= 0) {
        const double *xa = ctx->xyz + 3 * id;
        vc_bigint I[3], q;
        for (int k = 0; k < 3 && !rc; k++) {
            vc_bigint a;
            rc |= to_integer(xa[k], E, &a);
            rc |= vc_bigint_sub(&I[k], &a, &S[k]);
        }
        if (rc)
            return -1;
        rc |= vc_bigint_mul(&r->last, &I[0], &I[0]);
        rc |= vc_bigint_mul(&q, &I[1], &I[1]);
        rc |= vc_bigint_add(&r->last, &r->last, &q);
        rc |= vc_bigint_mul(&q, &I[2], &I[2]);
        rc |= vc_bigint_add(&r->last, &r->last, &q);
        for (int k = 0; k < 3; k++)
            rc |= vc_bigint_add(&r->n[k], &I[k], &I[k]);
        if (tested) {
            for (int k = 0; k < 3; k++)
                r->n[k].neg = r->n[k].n ? !r->n[k].neg : 0;
            r->w.plus = s;
            r->w.minus = id;
        } else {
            r->last.neg = r->last.n ? !r->last.neg : 0;
            r->w.plus = id;
            r->w.minus = s;
        }
    } else {
        const int k = (int)(-1 - id), axis = k / 2;
        const double X = (k % 2) ? ctx->box_hi[axis] : ctx->box_lo[axis];
        vc_bigint x;
        for (int j = 0; j < 3; j++)
            rc |= vc_bigint_set(&r->n[j], j == axis ? 2 : 0, 0);
        rc |= to_integer(X, E, &x);
        rc |= vc_bigint_sub(&r->last, &S[axis], &x); /* -(X - s_k) */
        rc |= vc_bigint_add(&r->last, &r->last, &r->last);
    }
    return rc ? -1 : 0;
}

/* The integer rows of the planes ids[0..n) of the cell of s (the last one
 * the tested bisector when tested_last), the doubles brought to the
 * smallest exponent *E among s's coordinates, the seeds' and the walls'.
 * Returns 0, or -1 when they do not fit. */
static int integer_rows(const vc_power_ctx *ctx, int64_t s, const int64_t *ids, int n,
                        int tested_last, int_row *r, int *E)
{
    const double *xs = ctx->xyz + 3 * s;
    *E = 1 << 20;
    for (int d = 0; d < 3; d++)
        min_exponent(xs[d], E);
    for (int i = 0; i < n; i++) {
        if (ids[i] >= 0) {
            for (int d = 0; d < 3; d++)
                min_exponent(ctx->xyz[3 * ids[i] + d], E);
        } else {
            const int k = (int)(-1 - ids[i]), axis = k / 2;
            min_exponent((k % 2) ? ctx->box_hi[axis] : ctx->box_lo[axis], E);
        }
    }
    vc_bigint S[3];
    for (int d = 0; d < 3; d++)
        if (to_integer(xs[d], *E, &S[d]) != 0)
            return -1;
    for (int i = 0; i < n; i++)
        if (make_int_row(ctx, S, *E, s, ids[i], tested_last && i == n - 1, &r[i]) != 0)
            return -1;
    return 0;
}

/* det [a; b; c] of integer rows into r. */
static int int_det3(const vc_bigint *a, const vc_bigint *b, const vc_bigint *c, vc_bigint *r)
{
    vc_bigint m, t;
    int rc = 0;
    r->n = 0;
    r->neg = 0;
    static const int idx[3][2] = {{1, 2}, {2, 0}, {0, 1}}; /* a_k (b x c)_k */
    for (int k = 0; k < 3; k++) {
        const int i = idx[k][0], j = idx[k][1];
        rc |= vc_bigint_mul(&m, &b[i], &c[j]);
        rc |= vc_bigint_mul(&t, &b[j], &c[i]);
        rc |= vc_bigint_sub(&m, &m, &t);
        rc |= vc_bigint_mul(&m, &m, &a[k]);
        rc |= vc_bigint_add(r, r, &m);
    }
    return rc ? -1 : 0;
}

/* The test in integers: as evaluate (below); returns 0 with *result set,
 * or -1 when the values do not fit. */
static int evaluate_integer(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t q,
                            int side, int *result)
{
    const int64_t ids[4] = {plane[0], plane[1], plane[2], q};
    int_row r[4];
    int E;
    if (integer_rows(ctx, s, ids, 4, 1, r, &E) != 0)
        return -1;
    vc_bigint C[4], det = {0, 0, {0}}, t;
    for (int i = 0; i < 4; i++) {
        const vc_bigint *m[3];
        for (int j = 0, k = 0; j < 4; j++)
            if (j != i)
                m[k++] = r[j].n;
        if (int_det3(m[0], m[1], m[2], &C[i]) != 0)
            return -1;
        if ((i + 3) % 2)
            C[i].neg = C[i].n ? !C[i].neg : 0;
        if (vc_bigint_mul(&t, &r[i].last, &C[i]) != 0 || vc_bigint_add(&det, &det, &t) != 0)
            return -1;
    }
    int sm = vc_bigint_sign(&det);
    const int sa = vc_bigint_sign(&C[3]);
    if (sm == 0 && side) {
        int64_t seed[8];
        const row_weight w[4] = {r[0].w, r[1].w, r[2].w, r[3].w};
        const int ns = weighted_seeds(w, seed);
        for (int m = 0; m < ns && sm == 0; m++) {
            vc_bigint coef = {0, 0, {0}};
            for (int i = 0; i < 4; i++) {
                if (r[i].w.plus == seed[m] && vc_bigint_add(&coef, &coef, &C[i]) != 0)
                    return -1;
                if (r[i].w.minus == seed[m] && vc_bigint_sub(&coef, &coef, &C[i]) != 0)
                    return -1;
            }
            sm = vc_bigint_sign(&coef);
        }
    }
    *result = side ? (sm * sa > 0 ? 1 : -1) : sm == 0;
    return 0;
}

/* ---- the narrow integer stage: the common exact tie, in fixed width ----
 * Most ties (a lattice whose spacing is not a power of two, VoroCrust's
 * co-spherical seeds) have every difference to s (a_k - s_k, X - s_k)
 * exact in a double, and those differences within 61 bits of one another
 * in units of the smallest one's last bit. Then each difference is an
 * int64 I (the integer stage's rows, with the differences' exponent in
 * place of the coordinates'), |I|^2 fits 124 bits, the 2 x 2 minors of
 * the normals 125, the cofactors 189 and det M 315: two's-complement
 * integers of 2, 3 and 5 limbs, no loop over a variable width and no copy
 * of 200-byte values. The integer stage took 2 us per test, most of the
 * cells' time on a lattice of spacing 1/46. */
typedef struct i192 {
    uint64_t w[3];
} i192;
typedef struct i320 {
    uint64_t w[5];
} i320;

static void negate_limbs(uint64_t *w, int n)
{
    unsigned carry = 1;
    for (int i = 0; i < n; i++) {
        const uint64_t v = ~w[i] + carry;
        carry = carry && v == 0;
        w[i] = v;
    }
}

static void add_limbs(uint64_t *r, const uint64_t *a, const uint64_t *b, int n)
{
    unsigned carry = 0;
    for (int i = 0; i < n; i++) {
        const uint64_t s = a[i] + b[i], t = s + carry;
        carry = (s < a[i]) | (t < s);
        r[i] = t;
    }
}

static int sign_limbs(const uint64_t *w, int n)
{
    if (w[n - 1] >> 63)
        return -1;
    for (int i = 0; i < n; i++)
        if (w[i])
            return 1;
    return 0;
}

/* a * b, |a| < 2^63, |b| < 2^127 */
static i192 mul_64_128(int64_t a, __int128 b)
{
    const int neg = (a < 0) != (b < 0);
    const uint64_t ua = a < 0 ? -(uint64_t)a : (uint64_t)a;
    const unsigned __int128 ub = b < 0 ? -(unsigned __int128)b : (unsigned __int128)b;
    const unsigned __int128 lo = (unsigned __int128)ua * (uint64_t)ub;
    const unsigned __int128 hi = (unsigned __int128)ua * (uint64_t)(ub >> 64);
    const unsigned __int128 mid = (lo >> 64) + (uint64_t)hi;
    i192 r = {{(uint64_t)lo, (uint64_t)mid, (uint64_t)(hi >> 64) + (uint64_t)(mid >> 64)}};
    if (neg)
        negate_limbs(r.w, 3);
    return r;
}

/* a * b, |a| < 2^191, |b| < 2^127 */
static i320 mul_192_128(i192 a, __int128 b)
{
    const int na = (int)(a.w[2] >> 63), neg = na != (b < 0);
    if (na)
        negate_limbs(a.w, 3);
    const unsigned __int128 ub = b < 0 ? -(unsigned __int128)b : (unsigned __int128)b;
    const uint64_t bl[2] = {(uint64_t)ub, (uint64_t)(ub >> 64)};
    i320 r = {{0, 0, 0, 0, 0}};
    for (int i = 0; i < 3; i++) {
        uint64_t carry = 0;
        for (int j = 0; j < 2; j++) {
            const unsigned __int128 t = (unsigned __int128)a.w[i] * bl[j] + r.w[i + j] + carry;
            r.w[i + j] = (uint64_t)t;
            carry = (uint64_t)(t >> 64);
        }
        r.w[i + 2] += carry;
    }
    if (neg)
        negate_limbs(r.w, 5);
    return r;
}

/* The rows of the narrow stage: normals and last entry as the integer
 * stage makes them (seed rows [2 I, -+|I|^2], wall rows [2 e_k, -2 J]). */
typedef struct narrow_row {
    int64_t n[3];
    __int128 last;
    row_weight w;
} narrow_row;

/* The differences of the row of plane id (a seed's three, a wall's one)
 * into d; returns how many, or -1 when one is not a double. */
static int row_differences(const vc_power_ctx *ctx, int64_t s, int64_t id, double d[3])
{
    const double *xs = ctx->xyz + 3 * s;
    if (id >= 0) {
        const double *xa = ctx->xyz + 3 * id;
        for (int k = 0; k < 3; k++) {
            const dd t = dd_two_sum(xa[k], -xs[k]);
            if (t.lo != 0)
                return -1;
            d[k] = t.hi;
        }
        return 3;
    }
    const int k = (int)(-1 - id), axis = k / 2;
    const dd t = dd_two_sum((k % 2) ? ctx->box_hi[axis] : ctx->box_lo[axis], -xs[axis]);
    if (t.lo != 0)
        return -1;
    d[0] = t.hi;
    return 1;
}

/* The side test (or with side 0 whether the vertex is on the plane) in
 * the narrow stage: 0 with *result set, -1 when it does not apply. */
static int evaluate_narrow(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t q,
                           int side, int *result)
{
    const int64_t ids[4] = {plane[0], plane[1], plane[2], q};
    double d[4][3];
    /* each difference as its 53-bit significand m and the exponent e of
     * its last bit (|d| = m 2^e), read from its bits (frexp and ldexp
     * were a tenth of this stage) */
    int64_t m[4][3];
    int e[4][3], nd[4], emin = INT32_MAX, emax = INT32_MIN;
    for (int i = 0; i < 4; i++) {
        nd[i] = row_differences(ctx, s, ids[i], d[i]);
        if (nd[i] < 0)
            return -1;
        for (int k = 0; k < nd[i]; k++) {
            uint64_t bits;
            memcpy(&bits, &d[i][k], sizeof bits);
            const int eb = (int)(bits >> 52 & 0x7ff);
            const uint64_t frac = bits & ((UINT64_C(1) << 52) - 1);
            m[i][k] = (int64_t)(eb ? frac | UINT64_C(1) << 52 : frac);
            if (bits >> 63)
                m[i][k] = -m[i][k];
            e[i][k] = eb ? eb : 1;
            if (m[i][k] != 0) {
                emin = e[i][k] < emin ? e[i][k] : emin;
                emax = e[i][k] > emax ? e[i][k] : emax;
            }
        }
    }
    /* in units of the smallest last bit, |m| 2^(e - emin) < 2^61 */
    if (emin == INT32_MAX || emax - emin > 8)
        return -1;
    narrow_row r[4];
    for (int i = 0; i < 4; i++) {
        int64_t I[3];
        for (int k = 0; k < nd[i]; k++)
            I[k] = m[i][k] == 0 ? 0 : m[i][k] * ((int64_t)1 << (e[i][k] - emin));
        r[i].w.plus = r[i].w.minus = -1;
        if (nd[i] == 1) {
            const int axis = (int)(-1 - ids[i]) / 2;
            for (int k = 0; k < 3; k++)
                r[i].n[k] = k == axis ? 2 : 0;
            r[i].last = -2 * (__int128)I[0];
            continue;
        }
        __int128 q2 = 0;
        for (int k = 0; k < 3; k++) {
            q2 += (__int128)I[k] * I[k];
            r[i].n[k] = 2 * I[k];
        }
        if (i == 3) {
            for (int k = 0; k < 3; k++)
                r[i].n[k] = -r[i].n[k];
            r[i].last = q2;
            r[i].w.plus = s;
            r[i].w.minus = ids[i];
        } else {
            r[i].last = -q2;
            r[i].w.plus = ids[i];
            r[i].w.minus = s;
        }
    }
    i192 C[4];
    i320 det = {{0, 0, 0, 0, 0}};
    for (int i = 0; i < 4; i++) {
        const int64_t *m[3];
        for (int j = 0, k = 0; j < 4; j++)
            if (j != i)
                m[k++] = r[j].n;
        /* det [a; b; c] = sum_k a_k (b x c)_k */
        static const int idx[3][2] = {{1, 2}, {2, 0}, {0, 1}};
        i192 c = {{0, 0, 0}};
        for (int k = 0; k < 3; k++) {
            const int a = idx[k][0], b = idx[k][1];
            const __int128 minor = (__int128)m[1][a] * m[2][b] - (__int128)m[1][b] * m[2][a];
            const i192 t = mul_64_128(m[0][k], minor);
            add_limbs(c.w, c.w, t.w, 3);
        }
        if ((i + 3) % 2)
            negate_limbs(c.w, 3);
        C[i] = c;
        const i320 t = mul_192_128(c, r[i].last);
        add_limbs(det.w, det.w, t.w, 5);
    }
    int sm = sign_limbs(det.w, 5);
    const int sa = sign_limbs(C[3].w, 3);
    if (sm == 0 && side) {
        int64_t seed[8];
        const row_weight w[4] = {r[0].w, r[1].w, r[2].w, r[3].w};
        const int ns = weighted_seeds(w, seed);
        for (int m = 0; m < ns && sm == 0; m++) {
            i192 coef = {{0, 0, 0}};
            for (int i = 0; i < 4; i++) {
                if (r[i].w.plus == seed[m])
                    add_limbs(coef.w, coef.w, C[i].w, 3);
                if (r[i].w.minus == seed[m]) {
                    i192 t = C[i];
                    negate_limbs(t.w, 3);
                    add_limbs(coef.w, coef.w, t.w, 3);
                }
            }
            sm = sign_limbs(coef.w, 3);
        }
    }
    *result = side ? (sm * sa > 0 ? 1 : -1) : sm == 0;
    return 0;
}

/* An integer as m 2^e, m a double (the top 128 bits, rounded). */
static double bigint_to_double(const vc_bigint *a, int *e)
{
    *e = 0;
    if (a->n == 0)
        return 0;
    double m = (double)a->d[a->n - 1];
    if (a->n >= 2) {
        m = m * 0x1p64 + (double)a->d[a->n - 2];
        *e = 64 * (a->n - 2);
    }
    return a->neg ? -m : m;
}

int vc_power_vertex_exact(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], double y[3])
{
    int_row r[3];
    int E;
    if (integer_rows(ctx, s, plane, 3, 0, r, &E) != 0)
        return -1;
    /* rows [n'_i, last'_i] with n'_i . u = -last'_i and the vertex 2^E u:
     * u = sum_i (-last'_i) X_i / D, X_i the cross product of the other two
     * normals in cyclic order, D = n'_0 . X_0 */
    vc_bigint X[3][3], W[3], D = {0, 0, {0}}, t, q;
    int rc = 0;
    for (int i = 0; i < 3; i++) {
        const vc_bigint *a = r[(i + 1) % 3].n, *b = r[(i + 2) % 3].n;
        for (int k = 0; k < 3; k++) {
            const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            rc |= vc_bigint_mul(&t, &a[k1], &b[k2]);
            rc |= vc_bigint_mul(&q, &a[k2], &b[k1]);
            rc |= vc_bigint_sub(&X[i][k], &t, &q);
        }
    }
    for (int k = 0; k < 3 && !rc; k++) {
        rc |= vc_bigint_mul(&t, &r[0].n[k], &X[0][k]);
        rc |= vc_bigint_add(&D, &D, &t);
        W[k] = (vc_bigint){0, 0, {0}};
        for (int i = 0; i < 3; i++) {
            rc |= vc_bigint_mul(&t, &r[i].last, &X[i][k]);
            rc |= vc_bigint_sub(&W[k], &W[k], &t);
        }
    }
    if (rc || D.n == 0)
        return -1;
    int eD;
    const double mD = bigint_to_double(&D, &eD);
    for (int k = 0; k < 3; k++) {
        int eW;
        const double mW = bigint_to_double(&W[k], &eW);
        y[k] = ldexp(mW / mD, eW - eD + E);
    }
    return 0;
}

static long long n_expansion;

long long vc_power_expansion_count(void)
{
    return __atomic_load_n(&n_expansion, __ATOMIC_RELAXED);
}

static int evaluate_expansions(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3],
                               int64_t q, int side);

static long long n_exact_eval;

long long vc_power_exact_count(void)
{
    return __atomic_load_n(&n_exact_eval, __ATOMIC_RELAXED);
}

/* The exact test: in integers when they can hold it, else in expansions.
 * side: the perturbed side (vc_power_side's value); otherwise whether
 * the unperturbed vertex lies on the plane. */
static int evaluate(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t q,
                    int side)
{
    __atomic_add_fetch(&n_exact_eval, 1, __ATOMIC_RELAXED);
    int by_integers;
    if (evaluate_integer(ctx, s, plane, q, side, &by_integers) == 0)
        return by_integers;
    return evaluate_expansions(ctx, s, plane, q, side);
}

int vc_power_side_by(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t x,
                     int method)
{
    int r;
    if (method == 0)
        return evaluate_integer(ctx, s, plane, x, 1, &r) == 0 ? r : -2;
    if (method == 2)
        return evaluate_narrow(ctx, s, plane, x, 1, &r) == 0 ? r : -2;
    return evaluate_expansions(ctx, s, plane, x, 1);
}

static int evaluate_expansions(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3],
                               int64_t q, int side)
{
    __atomic_add_fetch(&n_expansion, 1, __ATOMIC_RELAXED);
    vc_expn_arena_begin();
    row r[4];
    for (int i = 0; i < 3; i++)
        r[i] = make_row(ctx, s, plane[i], 0);
    r[3] = make_row(ctx, s, q, 1);
    vc_expn C[4];
    cofactors(r, C);
    int result;
    const int sm = det_sign(r, C, side);
    /* det A = det of the three vertex rows = C_3 (cofactor sign +). */
    const int sa = vc_expn_sign_free(vc_expn_copy(C[3]));
    if (sm == VC_PREDICATE_NOMEM || sa == VC_PREDICATE_NOMEM)
        result = VC_PREDICATE_NOMEM;
    else if (side)
        result = sm * sa > 0 ? 1 : -1;
    else
        result = sm == 0;
    for (int i = 0; i < 4; i++) {
        row_free(&r[i]);
        vc_expn_release(C[i].v);
    }
    vc_expn_arena_end();
    return result;
}

/* The vertex's part of det M0, cached (see power_side.h): with X_i the
 * cross products of the other two vertex rows' normals, the cofactors are
 * C_i = -n_3 . X_i (i < 3) and C_3 = det A, so det M0 = -n_3 . W + L_3 C_3
 * with W = sum_i L_i X_i (the Cramer numerator of the vertex). Layout:
 * W (3 double-doubles), C_3, the permanents of W's components and of C_3,
 * whether all of it is exact, 1 (prepared), then X_0, X_1, X_2 (for
 * ties). */
VC_FMA_CLONES
static void prepare_from_rows(const dd_row r[3], int ex, double cache[VC_POWER_CACHE]);

void vc_power_vertex_prepare(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3],
                             double cache[VC_POWER_CACHE])
{
    int ex = 1;
    dd_row r[3];
    for (int i = 0; i < 3; i++)
        r[i] = make_dd_row(ctx, s, plane[i], 0, &ex);
    prepare_from_rows(r, ex, cache);
}

void vc_power_vertex_prepare_rows(const int64_t plane[3], const double *const row[3],
                                  double cache[VC_POWER_CACHE])
{
    /* A tested plane's row is the negation of the same seed's vertex row
     * (exactly: only signs change); a wall's is the same. */
    int ex = 1;
    dd_row r[3];
    for (int i = 0; i < 3; i++) {
        const double sg = plane[i] >= 0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; k++)
            r[i].n[k] = (dd){sg * row[i][2 * k], sg * row[i][2 * k + 1]};
        r[i].last = (dd){sg * row[i][6], sg * row[i][7]};
        ex &= row[i][8] != 0;
    }
    prepare_from_rows(r, ex, cache);
}

/* The cache from the vertex's three rows (ex: whether they are exact). */
VC_FMA_CLONES
static void prepare_from_rows(const dd_row r[3], int ex, double cache[VC_POWER_CACHE])
{
    dd W[3] = {{0, 0}, {0, 0}, {0, 0}};
    double pW[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++) {
        const dd *a = r[(i + 1) % 3].n, *b = r[(i + 2) % 3].n;
        const dd X[3] = {
            dd_add(dd_mul(a[1], b[2], &ex), dd_neg(dd_mul(a[2], b[1], &ex)), &ex),
            dd_add(dd_mul(a[2], b[0], &ex), dd_neg(dd_mul(a[0], b[2], &ex)), &ex),
            dd_add(dd_mul(a[0], b[1], &ex), dd_neg(dd_mul(a[1], b[0], &ex)), &ex)};
        const double pX[3] = {dd_abs(a[1]) * dd_abs(b[2]) + dd_abs(a[2]) * dd_abs(b[1]),
                              dd_abs(a[2]) * dd_abs(b[0]) + dd_abs(a[0]) * dd_abs(b[2]),
                              dd_abs(a[0]) * dd_abs(b[1]) + dd_abs(a[1]) * dd_abs(b[0])};
        for (int k = 0; k < 3; k++) {
            cache[14 + 6 * i + 2 * k] = X[k].hi;
            cache[15 + 6 * i + 2 * k] = X[k].lo;
            W[k] = dd_add(W[k], dd_mul(r[i].last, X[k], &ex), &ex);
            pW[k] += dd_abs(r[i].last) * pX[k];
        }
        if (i == 0) {
            const dd C3 = dd_add(dd_add(dd_mul(r[0].n[0], X[0], &ex), dd_mul(r[0].n[1], X[1], &ex), &ex),
                                 dd_mul(r[0].n[2], X[2], &ex), &ex);
            cache[6] = C3.hi;
            cache[7] = C3.lo;
            cache[11] = dd_abs(r[0].n[0]) * pX[0] + dd_abs(r[0].n[1]) * pX[1] + dd_abs(r[0].n[2]) * pX[2];
        }
    }
    for (int k = 0; k < 3; k++) {
        cache[2 * k] = W[k].hi;
        cache[2 * k + 1] = W[k].lo;
        cache[8 + k] = pW[k];
    }
    cache[12] = ex;
    cache[13] = 1;
}

/* An exact tie, every cached value exact: the perturbed side from the
 * cofactors C_i = -n_3 . X_i and C_3 (see det_sign). 2 when a coefficient
 * rounds. */
VC_FMA_CLONES
static int cached_tie(int64_t s, const int64_t plane[3], int64_t x, const dd_row *t,
                      const double *cache, int sa)
{
    int ex = 1;
    dd C[4];
    for (int i = 0; i < 3; i++) {
        const double *X = cache + 14 + 6 * i;
        C[i] = dd_neg(dd_add(dd_add(dd_mul(t->n[0], (dd){X[0], X[1]}, &ex),
                                    dd_mul(t->n[1], (dd){X[2], X[3]}, &ex), &ex),
                             dd_mul(t->n[2], (dd){X[4], X[5]}, &ex), &ex));
    }
    C[3] = (dd){cache[6], cache[7]};
    if (!ex)
        return 2;
    /* rows: i < 3 the vertex planes (+ for its seed, - for s), 3 the
     * tested plane (+ for s, - for x) */
    int64_t seed[5];
    int ns = 0;
    seed[ns++] = s;
    seed[ns++] = x;
    for (int i = 0; i < 3; i++)
        if (plane[i] >= 0)
            seed[ns++] = plane[i];
    ns = sorted_unique(seed, ns);
    for (int m = 0; m < ns; m++) {
        dd coef = {0, 0};
        if (seed[m] == s) {
            for (int i = 0; i < 3; i++)
                if (plane[i] >= 0)
                    coef = dd_add(coef, dd_neg(C[i]), &ex);
            coef = dd_add(coef, C[3], &ex);
        } else if (seed[m] == x)
            coef = dd_neg(C[3]);
        else
            for (int i = 0; i < 3; i++)
                if (plane[i] == seed[m])
                    coef = C[i];
        if (!ex)
            return 2;
        const int sc = dd_sign(coef);
        if (sc != 0)
            return sc * sa > 0 ? 1 : -1;
    }
    return 2;
}

VC_FMA_CLONES
void vc_power_plane_prepare(const vc_power_ctx *ctx, int64_t s, int64_t x,
                            double row[VC_POWER_ROW])
{
    int ex = 1;
    const dd_row t = make_dd_row(ctx, s, x, 1, &ex);
    for (int k = 0; k < 3; k++) {
        row[2 * k] = t.n[k].hi;
        row[2 * k + 1] = t.n[k].lo;
    }
    row[6] = t.last.hi;
    row[7] = t.last.lo;
    row[8] = ex;
}

VC_FMA_CLONES
int vc_power_side_cached(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t x,
                         const double cache[VC_POWER_CACHE], const double row[VC_POWER_ROW])
{
    int ex = cache[12] != 0 && row[8] != 0;
    dd_row t;
    for (int k = 0; k < 3; k++)
        t.n[k] = (dd){row[2 * k], row[2 * k + 1]};
    t.last = (dd){row[6], row[7]};
    const dd W[3] = {{cache[0], cache[1]}, {cache[2], cache[3]}, {cache[4], cache[5]}};
    const dd C3 = {cache[6], cache[7]};
    const dd nw = dd_add(dd_add(dd_mul(t.n[0], W[0], &ex), dd_mul(t.n[1], W[1], &ex), &ex),
                         dd_mul(t.n[2], W[2], &ex), &ex);
    const dd det = dd_add(dd_neg(nw), dd_mul(t.last, C3, &ex), &ex);
    const double perm = dd_abs(t.n[0]) * cache[8] + dd_abs(t.n[1]) * cache[9] +
                        dd_abs(t.n[2]) * cache[10] + dd_abs(t.last) * cache[11];
    const double bound = 64.0 * 4.930380657631324e-32 * perm;
    const double boundA = 64.0 * 4.930380657631324e-32 * cache[11];
    const double v = det.hi + det.lo, a = C3.hi + C3.lo;
    if ((ex || fabs(a) > boundA) && a != 0) {
        const int sa = a > 0 ? 1 : -1;
        if (ex ? v != 0 : fabs(v) > bound)
            return (v > 0 ? 1 : -1) * sa > 0 ? 1 : -1;
        if (ex) {
            const int r = cached_tie(s, plane, x, &t, cache, sa);
            if (r != 2)
                return r;
        }
    }
    return vc_power_side(ctx, s, plane, x); /* a tie, or too near one */
}

/* Past the filter: the narrow integers when they apply (exact, and
 * cheaper than the double-double stage that cannot settle a tie unless
 * every product is exact), else double-double, else the exact stages. */
static int decide(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t q, int side)
{
    int r;
    if (evaluate_narrow(ctx, s, plane, q, side, &r) == 0) {
        __atomic_add_fetch(&n_exact_eval, 1, __ATOMIC_RELAXED);
        return r;
    }
    r = dd_stage(ctx, s, plane, q, side);
    if (r != 2)
        return side ? r : r == 0;
    return evaluate(ctx, s, plane, q, side);
}

int vc_power_side(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t x)
{
    return decide(ctx, s, plane, x, 1);
}

int vc_power_on_plane(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t q)
{
    return decide(ctx, s, plane, q, 0);
}
