/* Tests of vc_region_locate: points in the regions of surfaces built in
 * memory, whose regions are known by construction. A row of boxes sharing
 * faces (an interface once between neighbours), a box split by a T wall,
 * and walls of zero thickness counted by vc_surface_regions. Points are
 * random, then close to the interfaces, edges and corners (1e-9 of the
 * size away), where a segment from the point may graze an edge. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/regions.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

static double rnd(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* The region a point of the box row lies in, by its x (-1 outside). */
static int64_t expected_box(const int64_t *box_region, int n, const double p[3])
{
    for (int d = 0; d < 3; d++)
        if (p[d] <= 0 || p[d] >= (d == 0 ? n : 1))
            return -1;
    return box_region[(int)floor(p[0])];
}

static void test_box_row(int n, int g)
{
    builder b = {0};
    box_row(&b, n, g);
    vc_error err = {0, ""};
    vc_regions r;
    CHECK_MSG(vc_surface_regions(&b.s, &r, &err) == 0, err.msg);
    CHECKF(r.n_regions == n, "%d boxes: %lld regions", n, (long long)r.n_regions);
    CHECK(r.n_walls == 0);
    vc_region_locator *L = NULL;
    CHECK_MSG(vc_region_locator_build(&b.s, r.side_region, &L, &err) == 0, err.msg);
    /* which region is box k: the one holding its centre, by the volumes
     * (every box has volume 1) and the sides of its -z squares */
    int64_t box_region[16];
    for (int k = 0; k < n; k++) {
        /* the first -z triangle of box k: square (k g, 0), four triangles
         * (the -z and +z squares) per column of the grid */
        const int64_t t = 4 * ((int64_t)k * g * g);
        box_region[k] = r.side_region[2 * t + 1]; /* its back side faces into the box */
    }
    uint64_t seed = 7;
    int64_t wrong = 0, undecided = 0, n_points = 0;
    for (int i = 0; i < 4000; i++) {
        double p[3] = {-0.2 + (n + 0.4) * rnd(&seed), -0.2 + 1.4 * rnd(&seed), -0.2 + 1.4 * rnd(&seed)};
        /* every fourth point snapped near an interface, edge or corner */
        if (i % 4 == 1)
            p[0] = floor(p[0] + 0.5) + (rnd(&seed) < 0.5 ? -1e-9 : 1e-9);
        if (i % 4 == 2) {
            p[0] = floor(p[0] + 0.5) + 1e-9;
            p[1] = (rnd(&seed) < 0.5 ? 0 : 1) + (rnd(&seed) < 0.5 ? -1e-9 : 1e-9);
        }
        if (i % 4 == 3) {
            p[0] = floor(p[0] + 0.5) - 1e-9;
            p[1] = floor(p[1] * g + 0.5) / g + 1e-9;
            p[2] = floor(p[2] * g + 0.5) / g - 1e-9;
        }
        const int64_t want = expected_box(box_region, n, p);
        const int64_t got = vc_region_locate(L, p);
        n_points++;
        if (got == -2) {
            if (undecided++ < 5)
                fprintf(stderr, "point (%.12g, %.12g, %.12g): undecided, expected %lld\n", p[0],
                        p[1], p[2], (long long)want);
        }
        else if (got != want) {
            if (wrong++ < 5)
                fprintf(stderr, "point (%.12g, %.12g, %.12g): region %lld, expected %lld\n", p[0],
                        p[1], p[2], (long long)got, (long long)want);
        }
    }
    CHECKF(wrong == 0, "%d boxes, grid %d: %lld of %lld points in the wrong region", n, g,
           (long long)wrong, (long long)n_points);
    CHECKF(undecided == 0, "%d boxes, grid %d: %lld of %lld points undecided", n, g,
           (long long)undecided, (long long)n_points);
    /* a point on the surface has no region */
    const double on[3] = {1.0, 0.5, 0.5};
    if (n > 1)
        CHECK(vc_region_locate(L, on) == -2);
    printf("%d boxes, grid %d: %lld points, all in their region\n", n, g, (long long)n_points);
    vc_region_locator_free(L);
    vc_regions_free(&r);
    vc_surface_free(&b.s);
}

/* A fin (two triangles) inside a box, given once per side: both sides in
 * the box's region, a wall of zero thickness. */
static void test_walls(void)
{
    builder b = {0};
    box_row(&b, 1, 1);
    const int64_t v = b.s.n_vertices;
    add_v(&b, 0.25, 0.25, 0.5);
    add_v(&b, 0.75, 0.25, 0.5);
    add_v(&b, 0.75, 0.75, 0.5);
    add_t(&b, v, v + 1, v + 2);
    add_t(&b, v, v + 2, v + 1);
    vc_error err = {0, ""};
    vc_regions r;
    CHECK_MSG(vc_surface_regions(&b.s, &r, &err) == 0, err.msg);
    CHECKF(r.n_walls == 1 && r.first_wall == 12, "walls %lld, first %lld", (long long)r.n_walls,
           (long long)r.first_wall);
    CHECK(r.n_twice == 1);
    vc_regions_free(&r);
    vc_surface_free(&b.s);
}

int main(void)
{
    test_box_row(1, 1);
    test_box_row(2, 1);
    test_box_row(3, 4);
    test_walls();
    return failures ? 1 : 0;
}
