/* Interior seeds on a cubic lattice (see include/vorocrust/interior.h).
 * The nearest surface seed of a lattice point is found through a uniform
 * grid of the surface seeds, searched in growing shells. */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balls/ball_set.h"

typedef struct seed_grid3 {
    double lo[3], h;
    int64_t n[3];
    int64_t *start; /* n0 n1 n2 + 1 */
    int64_t *idx;
} seed_grid3;

static int64_t clampi(int64_t v, int64_t lo, int64_t hi) { return v < lo ? lo : (v > hi ? hi : v); }

static int grid_build(seed_grid3 *g, const vc_seeds *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < s->n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * i + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * i + d]);
        }
    double vol = 1;
    for (int d = 0; d < 3; d++)
        vol *= fmax(hi[d] - lo[d], 1e-300);
    g->h = cbrt(vol / (double)(s->n > 0 ? s->n : 1)) * 1.5; /* ~3 seeds per bin */
    if (!(g->h > 0))
        g->h = 1;
    int64_t total = 1;
    for (int d = 0; d < 3; d++) {
        g->lo[d] = lo[d];
        g->n[d] = (int64_t)floor((hi[d] - lo[d]) / g->h) + 1;
        if (g->n[d] > 2048)
            g->n[d] = 2048;
        total *= g->n[d];
    }
    g->start = calloc((size_t)total + 1, sizeof(int64_t));
    g->idx = malloc(sizeof(int64_t) * (size_t)(s->n ? s->n : 1));
    if (!g->start || !g->idx)
        return -1;
    int64_t *bin = malloc(sizeof(int64_t) * (size_t)(s->n ? s->n : 1));
    if (!bin)
        return -1;
    for (int64_t i = 0; i < s->n; i++) {
        int64_t c[3];
        for (int d = 0; d < 3; d++)
            c[d] = clampi((int64_t)floor((s->xyz[3 * i + d] - g->lo[d]) / g->h), 0, g->n[d] - 1);
        bin[i] = (c[2] * g->n[1] + c[1]) * g->n[0] + c[0];
        g->start[bin[i] + 1]++;
    }
    for (int64_t b = 0; b < total; b++)
        g->start[b + 1] += g->start[b];
    int64_t *fill = malloc(sizeof(int64_t) * (size_t)total);
    if (!fill) {
        free(bin);
        return -1;
    }
    memcpy(fill, g->start, sizeof(int64_t) * (size_t)total);
    for (int64_t i = 0; i < s->n; i++)
        g->idx[fill[bin[i]]++] = i;
    free(fill);
    free(bin);
    return 0;
}

/* The nearest seed to x (ties: lowest index) and its distance. */
static int64_t grid_nearest(const seed_grid3 *g, const vc_seeds *s, const double x[3], double *dist)
{
    int64_t c[3];
    for (int d = 0; d < 3; d++)
        c[d] = clampi((int64_t)floor((x[d] - g->lo[d]) / g->h), 0, g->n[d] - 1);
    double best2 = INFINITY;
    int64_t best = -1;
    int64_t maxn = g->n[0] > g->n[1] ? g->n[0] : g->n[1];
    maxn = maxn > g->n[2] ? maxn : g->n[2];
    for (int64_t ring = 0; ring <= maxn; ring++) {
        /* a seed in ring r is at least (r - 1) h away (x may lie outside the grid: then
         * the bound is only used once something is found) */
        if (best >= 0) {
            double lim = (double)(ring - 1) * g->h;
            if (lim > 0 && lim * lim > best2)
                break;
        }
        for (int64_t k = c[2] - ring; k <= c[2] + ring; k++) {
            if (k < 0 || k >= g->n[2])
                continue;
            for (int64_t j = c[1] - ring; j <= c[1] + ring; j++) {
                if (j < 0 || j >= g->n[1])
                    continue;
                int shell = llabs(k - c[2]) == ring || llabs(j - c[1]) == ring;
                for (int64_t i = c[0] - ring; i <= c[0] + ring; i += (shell || ring == 0) ? 1 : 2 * ring) {
                    if (i < 0 || i >= g->n[0])
                        continue;
                    int64_t b = (k * g->n[1] + j) * g->n[0] + i;
                    for (int64_t m = g->start[b]; m < g->start[b + 1]; m++) {
                        int64_t q = g->idx[m];
                        const double *y = s->xyz + 3 * q;
                        double d2 = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                                    (x[2] - y[2]) * (x[2] - y[2]);
                        if (d2 < best2 || (d2 == best2 && q < best)) {
                            best2 = d2;
                            best = q;
                        }
                    }
                }
            }
        }
    }
    *dist = sqrt(best2);
    return best;
}

typedef struct inside_ctx {
    const vc_balls *b;
    const double *x;
} inside_ctx;

static int ball_holds(void *ctx, int64_t i)
{
    inside_ctx *c = ctx;
    const double *p = c->b->center + 3 * i;
    double d2 = (p[0] - c->x[0]) * (p[0] - c->x[0]) + (p[1] - c->x[1]) * (p[1] - c->x[1]) +
                (p[2] - c->x[2]) * (p[2] - c->x[2]);
    return d2 <= c->b->radius[i] * c->b->radius[i];
}

double vc_interior_default_spacing(const vc_balls *balls, double max_size)
{
    double r = 0;
    for (int64_t i = 0; i < balls->n; i++)
        r = fmax(r, balls->radius[i]);
    if (max_size > 0 && max_size < r)
        r = max_size;
    return r;
}

int vc_interior_lattice(const vc_balls *balls, const vc_seeds *ss, double spacing, vc_seeds *out,
                        int64_t *n_interior, vc_error *err)
{
    memset(out, 0, sizeof *out);
    *n_interior = 0;
    if (!(spacing > 0) || !isfinite(spacing))
        return vc_error_set(err, VC_EPARAM, "interior spacing must be positive, got %g", spacing);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < balls->n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], balls->center[3 * i + d]);
            hi[d] = fmax(hi[d], balls->center[3 * i + d]);
        }
    int64_t n[3];
    double count = 1;
    for (int d = 0; d < 3; d++) {
        n[d] = (int64_t)floor((hi[d] - lo[d]) / spacing) + 1;
        count *= (double)n[d];
    }
    if (count > 1e9)
        return vc_error_set(err, VC_EPARAM, "interior spacing %g makes %.3g lattice points", spacing,
                            count);
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    vc_ball_set bs;
    seed_grid3 g;
    memset(&g, 0, sizeof g);
    if (vc_ball_set_init(&bs, lo, diag) || grid_build(&g, ss)) {
        vc_ball_set_free(&bs);
        free(g.start);
        free(g.idx);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the interior seeds");
    }
    int rc = 0;
    for (int64_t i = 0; i < balls->n && !rc; i++)
        if (vc_ball_set_add(&bs, balls->center + 3 * i, balls->radius[i], balls->kind[i],
                            balls->element[i], balls->normal + 3 * i) < 0)
            rc = -1;
    double *pts = NULL;
    int64_t np = 0, cap = 0;
    /* centre the lattice in the box */
    double off[3];
    for (int d = 0; d < 3; d++)
        off[d] = lo[d] + 0.5 * ((hi[d] - lo[d]) - (double)(n[d] - 1) * spacing);
    for (int64_t k = 0; k < n[2] && !rc; k++)
        for (int64_t j = 0; j < n[1] && !rc; j++)
            for (int64_t i = 0; i < n[0] && !rc; i++) {
                double x[3] = {off[0] + (double)i * spacing, off[1] + (double)j * spacing,
                               off[2] + (double)k * spacing};
                inside_ctx ic = {&bs.b, x};
                if (vc_ball_set_query(&bs, x, 0, 1.0, 0.0, ball_holds, &ic))
                    continue;
                double dn;
                int64_t q = grid_nearest(&g, ss, x, &dn);
                if (q < 0 || ss->label[q] == 0 || dn < 0.5 * spacing)
                    continue;
                if (np == cap) {
                    cap = cap ? 2 * cap : 4096;
                    double *t = realloc(pts, sizeof(double) * 3 * (size_t)cap);
                    if (!t) {
                        rc = -1;
                        break;
                    }
                    pts = t;
                }
                memcpy(pts + 3 * np, x, sizeof x);
                np++;
            }
    vc_ball_set_free(&bs);
    free(g.start);
    free(g.idx);
    if (!rc && vc_seeds_alloc(out, ss->n + np, err) == 0) {
        memcpy(out->xyz, ss->xyz, sizeof(double) * 3 * (size_t)ss->n);
        memcpy(out->label, ss->label, sizeof(int32_t) * (size_t)ss->n);
        memcpy(out->xyz + 3 * ss->n, pts, sizeof(double) * 3 * (size_t)np);
        for (int64_t i = 0; i < np; i++)
            out->label[ss->n + i] = 1;
        *n_interior = np;
        free(pts);
        return 0;
    }
    free(pts);
    return rc ? vc_error_set(err, VC_ENOMEM, "out of memory for the interior seeds")
              : (err ? err->code : VC_ENOMEM);
}
