/* vc_surface_consistent_flips: the flips that orient a surface
 * consistently, each component keeping the orientation most of its
 * triangles have; a one-sided strip refused. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

static void reverse(vc_surface *s, int64_t t)
{
    const int64_t x = s->tri[3 * t + 1];
    s->tri[3 * t + 1] = s->tri[3 * t + 2];
    s->tri[3 * t + 2] = x;
}

/* Applies the flips and checks that the surface is then consistent. */
static int64_t apply_and_count_inconsistent(vc_surface *s, const unsigned char *flip)
{
    vc_surface_reverse_triangles(s, flip);
    vc_surface_report rep;
    memset(&rep, 0, sizeof rep);
    vc_error err;
    return vc_surface_check(s, &rep, &err) == 0 ? rep.n_inconsistent_edges : -1;
}

int main(void)
{
    vc_error err;
    /* a sphere and, apart, a cube: triangles 3, 17 and 40 of the sphere
     * and 2 of the cube's 12 reversed; the flips are exactly those */
    builder b = {0};
    make_sphere(&b, 12, 8);
    const int64_t n_sphere = b.s.n_triangles;
    builder c = {0};
    make_cube(&c);
    for (int64_t v = 0; v < c.s.n_vertices; v++)
        add_v(&b, c.s.xyz[3 * v] + 5, c.s.xyz[3 * v + 1], c.s.xyz[3 * v + 2]);
    for (int64_t t = 0; t < c.s.n_triangles; t++)
        add_t(&b, c.s.tri[3 * t] + (b.s.n_vertices - c.s.n_vertices),
              c.s.tri[3 * t + 1] + (b.s.n_vertices - c.s.n_vertices),
              c.s.tri[3 * t + 2] + (b.s.n_vertices - c.s.n_vertices));
    const double volume = surface_enclosed_volume(&b.s);
    const int64_t bad[] = {3, 17, 40, n_sphere + 2};
    for (int k = 0; k < 4; k++)
        reverse(&b.s, bad[k]);
    unsigned char *flip = calloc((size_t)b.s.n_triangles, 1);
    int64_t n_flipped = -1;
    CHECK(vc_surface_consistent_flips(&b.s, flip, &n_flipped, &err) == 0);
    int wrong = 0;
    for (int64_t t = 0; t < b.s.n_triangles; t++)
        wrong += flip[t] != (t == 3 || t == 17 || t == 40 || t == n_sphere + 2);
    CHECKF(n_flipped == 4 && wrong == 0, "sphere and cube: %lld flipped, %d wrong", (long long)n_flipped, wrong);
    CHECK(apply_and_count_inconsistent(&b.s, flip) == 0);
    CHECKF(fabs(surface_enclosed_volume(&b.s) - volume) < 1e-12, "sphere and cube: volume %.17g, before %.17g",
           surface_enclosed_volume(&b.s), volume);

    /* the majority decides: 7 of the cube's 12 reversed make it an
     * inward cube whose other 5 are reversed */
    builder d = {0};
    make_cube(&d);
    for (int64_t t = 0; t < 7; t++)
        reverse(&d.s, t);
    unsigned char f12[12];
    CHECK(vc_surface_consistent_flips(&d.s, f12, &n_flipped, &err) == 0);
    wrong = 0;
    for (int64_t t = 0; t < 12; t++)
        wrong += f12[t] != (t >= 7);
    CHECKF(n_flipped == 5 && wrong == 0, "cube, 7 of 12 reversed: %lld flipped, %d wrong", (long long)n_flipped, wrong);
    CHECK(apply_and_count_inconsistent(&d.s, f12) == 0);
    CHECKF(fabs(surface_enclosed_volume(&d.s) + 1) < 1e-12, "cube: volume %g, not -1 (inward)",
           surface_enclosed_volume(&d.s));

    /* a Moebius strip has no orientation */
    builder m = {0};
    const int n = 20;
    for (int i = 0; i < n; i++) {
        const double u = 2 * M_PI * i / n;
        for (int s = -1; s <= 1; s += 2) {
            const double r = 3 + 0.5 * s * cos(u / 2);
            add_v(&m, r * cos(u), r * sin(u), 0.5 * s * sin(u / 2));
        }
    }
    for (int i = 0; i < n; i++) {
        const int64_t a0 = 2 * i, a1 = 2 * i + 1;
        const int64_t b0 = i + 1 < n ? 2 * (i + 1) : 1, b1 = i + 1 < n ? b0 + 1 : 0;
        add_q(&m, a0, b0, b1, a1);
    }
    unsigned char *fm = calloc((size_t)m.s.n_triangles, 1);
    CHECKF(vc_surface_consistent_flips(&m.s, fm, &n_flipped, &err) == VC_EINPUT && strstr(err.msg, "one-sided"),
           "moebius: %s", err.msg);
    free(fm);
    free(flip);
    vc_surface_free(&b.s);
    vc_surface_free(&c.s);
    vc_surface_free(&d.s);
    vc_surface_free(&m.s);
    if (failures) {
        fprintf(stderr, "test_orientation: %d failures\n", failures);
        return 1;
    }
    printf("test_orientation: all passed\n");
    return 0;
}
