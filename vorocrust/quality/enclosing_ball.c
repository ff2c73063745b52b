/* Minimum enclosing ball of a point set: Welzl's algorithm in Gärtner's
 * move-to-front form. The points are visited in a fixed pseudo-random
 * order (the project's own generator with a constant seed), which gives
 * the expected linear running time and the same ball on every run. */
#include "vorocrust/quality.h"

#include <math.h>
#include <stdlib.h>

#include "quality/vec3.h"
#include "vorocrust/random.h"

typedef struct mtf_ctx {
    const double *xyz;
    int64_t *order;      /* point ids in visiting order */
    const double *support[4];
    vc_ball ball;
    double tol;          /* absolute: points this far out still count as inside */
} mtf_ctx;

/* Solves the k x k system g x = r (k <= 3) by Gaussian elimination with
 * partial pivoting; returns 0 when a pivot falls below eps. */
static int solve_small(int k, double g[3][3], double r[3], double x[3], double eps)
{
    for (int c = 0; c < k; c++) {
        int piv = c;
        for (int i = c + 1; i < k; i++)
            if (fabs(g[i][c]) > fabs(g[piv][c]))
                piv = i;
        if (!(fabs(g[piv][c]) > eps))
            return 0;
        if (piv != c) {
            for (int j = 0; j < k; j++) {
                double t = g[c][j];
                g[c][j] = g[piv][j];
                g[piv][j] = t;
            }
            double t = r[c];
            r[c] = r[piv];
            r[piv] = t;
        }
        for (int i = c + 1; i < k; i++) {
            double f = g[i][c] / g[c][c];
            for (int j = c; j < k; j++)
                g[i][j] -= f * g[c][j];
            r[i] -= f * r[c];
        }
    }
    for (int i = k - 1; i >= 0; i--) {
        double s = r[i];
        for (int j = i + 1; j < k; j++)
            s -= g[i][j] * x[j];
        x[i] = s / g[i][i];
    }
    return 1;
}

/* The smallest sphere through the k points q (1 <= k <= 4): its centre
 * lies in their affine hull, q0 + sum l_j (q_j - q0), with
 * 2 (v_i . v_j) l_j = |v_i|^2. Returns 0 when the points are affinely
 * dependent (the system is singular). */
static int circumball(const double *const *q, int k, vc_ball *b)
{
    double v[3][3], g[3][3], r[3], l[3] = {0, 0, 0};
    double scale2 = 0;
    for (int i = 1; i < k; i++) {
        v3_sub(q[i], q[0], v[i - 1]);
        scale2 = dmax(scale2, v3_dot(v[i - 1], v[i - 1]));
    }
    for (int i = 0; i < k - 1; i++) {
        for (int j = 0; j < k - 1; j++)
            g[i][j] = 2.0 * v3_dot(v[i], v[j]);
        r[i] = v3_dot(v[i], v[i]);
    }
    if (k > 1 && !solve_small(k - 1, g, r, l, 1e-13 * scale2))
        return 0;
    for (int d = 0; d < 3; d++) {
        double c = q[0][d];
        for (int j = 0; j < k - 1; j++)
            c += l[j] * v[j][d];
        b->center[d] = c;
    }
    b->radius = 0;
    for (int i = 0; i < k; i++)
        b->radius = dmax(b->radius, sqrt(v3_dist2(b->center, q[i])));
    return 1;
}

static int contains(const vc_ball *b, const double p[3], double tol)
{
    return b->radius >= 0 && sqrt(v3_dist2(b->center, p)) <= b->radius + tol;
}

/* The smallest ball with the k support points on or inside it. Normally
 * their circumball; when they are (numerically) affinely dependent, the
 * smallest ball of a subset that contains them all. */
static void support_ball(const double *const *q, int k, double tol, vc_ball *b)
{
    if (k == 0) {
        b->center[0] = b->center[1] = b->center[2] = 0;
        b->radius = -1; /* contains nothing */
        return;
    }
    if (circumball(q, k, b))
        return;
    vc_ball best = {{0, 0, 0}, INFINITY};
    for (int skip = 0; skip < k; skip++) {
        const double *sub[4] = {NULL, NULL, NULL, NULL};
        int m = 0;
        for (int i = 0; i < k; i++)
            if (i != skip)
                sub[m++] = q[i];
        vc_ball cand;
        support_ball(sub, m, tol, &cand);
        int ok = contains(&cand, q[skip], tol);
        if (ok && cand.radius < best.radius)
            best = cand;
    }
    if (!isfinite(best.radius)) /* cannot happen with k <= 4; keep a valid ball */
        circumball(q, 1, &best);
    *b = best;
}

/* Ball of the first `end` points of ctx->order with the nb support points
 * on its boundary; points found outside move to the front of the order. */
static void mtf(mtf_ctx *ctx, int64_t end, int nb)
{
    support_ball(ctx->support, nb, ctx->tol, &ctx->ball);
    if (nb == 4)
        return;
    for (int64_t i = 0; i < end; i++) {
        int64_t id = ctx->order[i];
        const double *p = ctx->xyz + 3 * id;
        if (contains(&ctx->ball, p, ctx->tol))
            continue;
        ctx->support[nb] = p;
        mtf(ctx, i, nb + 1);
        for (int64_t j = i; j > 0; j--)
            ctx->order[j] = ctx->order[j - 1];
        ctx->order[0] = id;
    }
}

int vc_min_enclosing_ball(int64_t n, const double *xyz, const int64_t *ids, vc_ball *ball)
{
    if (n < 1 || !xyz)
        return VC_EPARAM;
    mtf_ctx ctx;
    ctx.xyz = xyz;
    ctx.order = malloc(sizeof *ctx.order * (size_t)n);
    if (!ctx.order)
        return VC_ENOMEM;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < n; i++) {
        int64_t id = ids ? ids[i] : i;
        ctx.order[i] = id;
        for (int d = 0; d < 3; d++) {
            lo[d] = dmin(lo[d], xyz[3 * id + d]);
            hi[d] = dmax(hi[d], xyz[3 * id + d]);
        }
    }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    ctx.tol = 1e-12 * diag;
    /* Fisher-Yates with a fixed seed: the same order on every run. */
    vc_rng rng;
    vc_rng_init(&rng, 0x5eed0fba11ULL, (uint64_t)n);
    for (int64_t i = n - 1; i > 0; i--) {
        int64_t j = (int64_t)(vc_rng_next(&rng) % (uint64_t)(i + 1));
        int64_t t = ctx.order[i];
        ctx.order[i] = ctx.order[j];
        ctx.order[j] = t;
    }
    mtf(&ctx, n, 0);
    *ball = ctx.ball;
    free(ctx.order);
    return VC_OK;
}
