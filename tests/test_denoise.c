/* vc_surface_denoise (vorocrust/smoothing.h): every vertex stays within
 * the bound of its input position, noise goes (a UV sphere with seeded
 * radial noise ends nearer the sphere), the shape stays (no shrinking of
 * a clean sphere beyond its facets' scale), the triangles and groups are
 * the input's, 1 and 2 threads give the same bits, and bad parameters are
 * refused. A part thinner than the moves keeps its thickness: a
 * hexagonal rod of radius 0.002 denoised within 0.005 keeps half its
 * radius (each side moves at most a quarter of its distance to the other),
 * and the copy does not cut itself. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/smoothing.h"
#include "vorocrust/surface.h"
#include "surface/self_intersection.h"

#include "test_check.h"
#include "test_surface_util.h"

/* RMS of |x| - 1 over the vertices: distance from the unit sphere. */
static double radial_rms(const vc_surface *s)
{
    double sum = 0;
    for (int64_t v = 0; v < s->n_vertices; v++) {
        const double *p = s->xyz + 3 * v;
        const double e = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1;
        sum += e * e;
    }
    return sqrt(sum / (double)s->n_vertices);
}

static double max_move(const vc_surface *a, const vc_surface *b)
{
    double m = 0;
    for (int64_t v = 0; v < a->n_vertices; v++) {
        const double *p = a->xyz + 3 * v, *q = b->xyz + 3 * v;
        m = fmax(m, sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                         (p[2] - q[2]) * (p[2] - q[2])));
    }
    return m;
}

int main(void)
{
    vc_error err;
    /* a UV sphere of 96 x 48, every vertex moved radially by seeded
     * uniform noise of +-0.01 (about a third of its edges) */
    builder b = {0};
    make_sphere(&b, 96, 48);
    vc_surface clean = b.s;
    builder nb = {0};
    make_sphere(&nb, 96, 48);
    vc_surface noisy = nb.s;
    uint64_t state = 12345;
    for (int64_t v = 0; v < noisy.n_vertices; v++) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        const double u = (double)(state >> 11) / 9007199254740992.0; /* [0, 1) */
        const double f = 1 + 0.01 * (2 * u - 1);
        for (int d = 0; d < 3; d++)
            noisy.xyz[3 * v + d] *= f;
    }
    const double bound = 0.01;
    vc_surface out1, out2;
    vc_denoise_report rep;
    CHECK(vc_surface_denoise(&noisy, bound, 40, 1, &out1, &rep, &err) == 0);
    CHECK(vc_surface_denoise(&noisy, bound, 40, 2, &out2, NULL, &err) == 0);
    /* the same surface, bit for bit, for any thread count */
    CHECK(out1.n_vertices == noisy.n_vertices && out2.n_vertices == noisy.n_vertices);
    CHECK(memcmp(out1.xyz, out2.xyz, sizeof(double) * 3 * (size_t)noisy.n_vertices) == 0);
    /* the triangles are the input's */
    CHECK(out1.n_triangles == noisy.n_triangles &&
          memcmp(out1.tri, noisy.tri, sizeof(int64_t) * 3 * (size_t)noisy.n_triangles) == 0);
    /* held within the bound (and the report says how far) */
    const double moved = max_move(&noisy, &out1);
    CHECKF(moved <= bound * (1 + 1e-12), "largest move %g above the bound %g", moved, bound);
    CHECKF(fabs(rep.max_move - moved) <= 1e-15, "report: largest move %g, measured %g", rep.max_move,
           moved);
    CHECK(rep.mean_move > 0 && rep.mean_move <= rep.max_move);
    /* the shape stays: the clean sphere moves off itself by little more
     * than its facets' sag (0.002 at 96 x 48) */
    vc_surface clean_out;
    CHECK(vc_surface_denoise(&clean, bound, 40, 2, &clean_out, NULL, &err) == 0);
    const double clean_err = radial_rms(&clean_out);
    /* the noise goes: the noisy sphere's vertices end 3 times nearer the
     * clean sphere's (both denoised alike) than they were */
    double before = 0, after = 0;
    for (int64_t v = 0; v < noisy.n_vertices; v++) {
        const double *p = noisy.xyz + 3 * v, *q = clean.xyz + 3 * v;
        const double *po = out1.xyz + 3 * v, *qo = clean_out.xyz + 3 * v;
        const double e0 = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) -
                          sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        const double e1 = sqrt(po[0] * po[0] + po[1] * po[1] + po[2] * po[2]) -
                          sqrt(qo[0] * qo[0] + qo[1] * qo[1] + qo[2] * qo[2]);
        before += e0 * e0;
        after += e1 * e1;
    }
    before = sqrt(before / (double)noisy.n_vertices);
    after = sqrt(after / (double)noisy.n_vertices);
    CHECKF(after < before / 3, "noise (radial RMS) %g before, %g after", before, after);
    printf("test_denoise: noise %.3g -> %.3g, clean sphere off itself by %.3g (RMS)\n", before,
           after, clean_err);
    CHECKF(clean_err < 0.003, "clean sphere: radial RMS %g after denoising", clean_err);
    const double v0 = surface_enclosed_volume(&clean), v1 = surface_enclosed_volume(&clean_out);
    CHECKF(fabs(v1 - v0) <= 0.01 * v0, "clean sphere: volume %g before, %g after", v0, v1);
    /* no iterations: the input itself */
    vc_surface same;
    CHECK(vc_surface_denoise(&noisy, bound, 0, 2, &same, NULL, &err) == 0);
    CHECK(memcmp(same.xyz, noisy.xyz, sizeof(double) * 3 * (size_t)noisy.n_vertices) == 0);
    /* a zero bound moves nothing */
    vc_surface held;
    CHECK(vc_surface_denoise(&noisy, 0, 40, 2, &held, &rep, &err) == 0);
    CHECK(memcmp(held.xyz, noisy.xyz, sizeof(double) * 3 * (size_t)noisy.n_vertices) == 0);
    CHECK(rep.max_move == 0 && rep.n_held == 0);
    /* refused: a negative or infinite bound, too many iterations, a bad index */
    vc_surface bad;
    CHECK(vc_surface_denoise(&noisy, -1, 10, 1, &bad, NULL, &err) == VC_EPARAM && !bad.xyz);
    CHECK(vc_surface_denoise(&noisy, INFINITY, 10, 1, &bad, NULL, &err) == VC_EPARAM);
    CHECK(vc_surface_denoise(&noisy, bound, VC_DENOISE_MAX_ITERATIONS + 1, 1, &bad, NULL, &err) ==
          VC_EPARAM);
    noisy.tri[4] = noisy.n_vertices;
    CHECK(vc_surface_denoise(&noisy, bound, 10, 1, &bad, NULL, &err) == VC_EINPUT && !bad.xyz);
    vc_surface_free(&clean);
    vc_surface_free(&noisy);
    vc_surface_free(&out1);
    vc_surface_free(&out2);
    vc_surface_free(&clean_out);
    vc_surface_free(&same);
    vc_surface_free(&held);
    /* a rod thinner than the moves: hexagonal, radius 0.002, 400 rings
     * along [0, 1], capped by fans, denoised within 0.005 */
    builder rb = {0};
    const int sides = 6, rings = 400;
    const double radius = 0.002;
    const int64_t c0 = add_v(&rb, 0, 0, 0), c1 = add_v(&rb, 1, 0, 0), first = rb.s.n_vertices;
    for (int j = 0; j <= rings; j++)
        for (int i = 0; i < sides; i++)
            add_v(&rb, (double)j / rings, radius * cos(2 * M_PI * i / sides),
                  radius * sin(2 * M_PI * i / sides));
#define RING(i, j) (first + (int64_t)(j) * sides + ((i) % sides))
    for (int i = 0; i < sides; i++) {
        add_t(&rb, c0, RING(i + 1, 0), RING(i, 0));
        add_t(&rb, c1, RING(i, rings), RING(i + 1, rings));
        for (int j = 0; j < rings; j++)
            add_q(&rb, RING(i, j), RING(i + 1, j), RING(i + 1, j + 1), RING(i, j + 1));
    }
#undef RING
    vc_surface rod = rb.s, rod_out;
    CHECK(vc_surface_denoise(&rod, 0.005, 80, 2, &rod_out, NULL, &err) == 0);
    double kept = INFINITY;
    for (int64_t v = first; v < rod.n_vertices; v++) {
        const double *p = rod_out.xyz + 3 * v;
        kept = fmin(kept, sqrt(p[1] * p[1] + p[2] * p[2]) / radius);
    }
    const double vol_kept = vc_surface_signed_volume(&rod_out) / vc_surface_signed_volume(&rod);
    int64_t *pairs = NULL, n_cross = -1;
    CHECK(vc_self_intersection_pairs(rod_out.xyz, rod_out.tri, rod_out.n_triangles, &pairs, &n_cross) == 0);
    free(pairs);
    /* plain Taubin steps left 0.28 of the radius, 14% of the volume */
    CHECKF(kept >= 0.5 && vol_kept >= 0.25 && n_cross == 0,
           "rod of radius 0.002 denoised within 0.005: %.3g of the radius kept, %.3g of the volume, "
           "%lld pairs of triangles crossing", kept, vol_kept, (long long)n_cross);
    printf("test_denoise: rod of radius 0.002 denoised within 0.005: %.3g of its radius kept, %.3g of "
           "its volume, %lld crossing pairs\n", kept, vol_kept, (long long)n_cross);
    vc_surface_free(&rod);
    vc_surface_free(&rod_out);
    if (failures == 0)
        printf("test_denoise: all checks passed\n");
    return failures ? 1 : 0;
}
