/* Tests of vc_surface_self_union: two boxes overlapping in general position
 * (the union's volume is known in closed form), a box through a sphere, a
 * box nested in another (no crossing: the inner one goes), a surface that
 * does not intersect itself (kept as it is), a degenerate overlap (edges
 * through edges: refused), the same result on 1 and 2 threads, and
 * cow.off (VC_MODELS). Each union must be closed, edge-manifold and
 * consistently oriented. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

/* The box [x0, x1] x [y0, y1] x [z0, z1], outward. */
static void add_box(builder *b, double x0, double y0, double z0, double x1, double y1, double z1)
{
    int64_t v[8];
    for (int k = 0; k < 8; k++)
        v[k] = add_v(b, k & 1 ? x1 : x0, (k >> 1) & 1 ? y1 : y0, (k >> 2) & 1 ? z1 : z0);
    add_q(b, v[0], v[2], v[3], v[1]);
    add_q(b, v[4], v[5], v[7], v[6]);
    add_q(b, v[0], v[1], v[5], v[4]);
    add_q(b, v[2], v[6], v[7], v[3]);
    add_q(b, v[0], v[4], v[6], v[2]);
    add_q(b, v[1], v[3], v[7], v[5]);
}

/* The union of s, checked closed, manifold and oriented with Euler
 * characteristic euler; returns its volume (NaN on failure). */
static double union_of(const vc_surface *s, const char *name, int64_t euler, vc_self_union_report *r,
                       vc_surface *u)
{
    vc_error err = {0, ""};
    int rc = vc_surface_self_union(s, name, u, r, &err);
    CHECKF(rc == 0, "%s: rc %d %s", name, rc, err.msg);
    if (rc)
        return NAN;
    vc_surface_report rep;
    memset(&rep, 0, sizeof rep);
    rc = vc_surface_check(u, &rep, &err);
    CHECKF(rc == 0, "%s: check %s", name, err.msg);
    CHECKF(rep.n_boundary_edges == 0 && rep.n_nonmanifold_edges == 0 && rep.n_inconsistent_edges == 0,
           "%s: union has %lld boundary, %lld non-manifold, %lld inconsistent edges", name,
           (long long)rep.n_boundary_edges, (long long)rep.n_nonmanifold_edges,
           (long long)rep.n_inconsistent_edges);
    CHECKF(rep.euler == euler, "%s: Euler characteristic %lld, expected %lld", name, (long long)rep.euler,
           (long long)euler);
    double v = surface_enclosed_volume(u);
    CHECKF(fabs(v - r->volume) <= 1e-12 * fabs(v), "%s: reported volume %.17g, enclosed %.17g", name,
           r->volume, v);
    return v;
}

static void test_two_boxes(void)
{
    builder b = {0};
    const double ox = 0.5123, oy = 0.3217, oz = 0.2731;
    add_box(&b, 0, 0, 0, 1, 1, 1);
    add_box(&b, ox, oy, oz, 1 + ox, 1 + oy, 1 + oz);
    vc_self_union_report r;
    vc_surface u;
    double v = union_of(&b.s, "two boxes", 2, &r, &u);
    double expected = 2 - (1 - ox) * (1 - oy) * (1 - oz);
    CHECKF(fabs(v - expected) <= 1e-12, "two boxes: union volume %.17g, expected %.17g", v, expected);
    CHECKF(r.n_pairs > 0 && r.n_patches == 4 && r.n_patches_dropped == 2,
           "two boxes: %lld pairs, %lld patches, %lld dropped", (long long)r.n_pairs, (long long)r.n_patches,
           (long long)r.n_patches_dropped);
    /* the same triangles on one thread as on two */
    omp_set_num_threads(1);
    vc_surface u1;
    vc_error err = {0, ""};
    int rc = vc_surface_self_union(&b.s, "two boxes", &u1, NULL, &err);
    omp_set_num_threads(2);
    CHECKF(rc == 0 && u1.n_triangles == u.n_triangles && u1.n_vertices == u.n_vertices &&
               !memcmp(u1.tri, u.tri, (size_t)u.n_triangles * 3 * sizeof *u.tri) &&
               !memcmp(u1.xyz, u.xyz, (size_t)u.n_vertices * 3 * sizeof *u.xyz),
           "two boxes: the union differs on 1 thread (rc %d)", rc);
    vc_surface_free(&u1);
    vc_surface_free(&u);
    vc_surface_free(&b.s);
}

/* The volume of the intersection of boxes a and b ({x0, y0, z0, x1, y1, z1}),
 * into c. */
static double box_meet(const double *a, const double *b, double *c)
{
    double v = 1;
    for (int k = 0; k < 3; k++) {
        c[k] = fmax(a[k], b[k]);
        c[k + 3] = fmin(a[k + 3], b[k + 3]);
        v *= fmax(0, c[k + 3] - c[k]);
    }
    return v;
}

/* Three boxes, each pair overlapping, all three sharing a block, their
 * coordinates all distinct: faces of the three meet at isolated points
 * inside a triangle of each, where two curves cross inside every one of
 * the three (triple points; refused until session 47). The union's volume
 * by inclusion and exclusion. */
static void test_three_boxes(void)
{
    const double bx[3][6] = {{0, 0, 0, 2, 2, 2},
                             {1.1, 0.37, 0.29, 3.05, 1.63, 1.71},
                             {0.53, 1.09, 0.61, 2.47, 3.01, 2.57}};
    builder b = {0};
    double expected = 0, ab[6], ac[6], bc[6], abc[6];
    for (int i = 0; i < 3; i++) {
        add_box(&b, bx[i][0], bx[i][1], bx[i][2], bx[i][3], bx[i][4], bx[i][5]);
        expected += (bx[i][3] - bx[i][0]) * (bx[i][4] - bx[i][1]) * (bx[i][5] - bx[i][2]);
    }
    expected -= box_meet(bx[0], bx[1], ab) + box_meet(bx[0], bx[2], ac) + box_meet(bx[1], bx[2], bc);
    expected += box_meet(ab, bx[2], abc);
    vc_self_union_report r;
    vc_surface u;
    double v = union_of(&b.s, "three boxes", 2, &r, &u);
    CHECKF(fabs(v - expected) <= 1e-12 * expected, "three boxes: union volume %.17g, expected %.17g", v,
           expected);
    if (!isnan(v)) {
        /* no triangle of the union crosses another: a solid */
        vc_error err = {0, ""};
        vc_solid_report sr;
        memset(&sr, 0, sizeof sr);
        CHECKF(vc_surface_check_solid(&u, NULL, &sr, &err) == 0 && sr.n_self_intersections == 0,
               "three boxes: the union is not a solid (%lld self-intersections): %s",
               (long long)sr.n_self_intersections, err.msg);
        vc_surface_free(&u);
    }
    vc_surface_free(&b.s);
}

static void test_box_through_sphere(void)
{
    builder b = {0};
    make_sphere(&b, 24, 12);
    double vs = surface_enclosed_volume(&b.s);
    add_box(&b, 0.31, -0.27, -0.23, 2.13, 0.29, 0.21);
    double vb = 1.82 * 0.56 * 0.44;
    vc_self_union_report r;
    vc_surface u;
    double v = union_of(&b.s, "box through sphere", 2, &r, &u);
    /* the part of the box outside the unit sphere: at least the slab
     * beyond x = 1, at most the box beyond x = 0.31 */
    CHECKF(v > vs + (2.13 - 1) * 0.56 * 0.44 && v < vs + vb, "box through sphere: volume %.9g (sphere %.9g, box %.9g)",
           v, vs, vb);
    CHECKF(r.n_patches_dropped == 2, "box through sphere: %lld patches dropped", (long long)r.n_patches_dropped);
    vc_surface_free(&u);
    vc_surface_free(&b.s);
}

static void test_nested_and_plain(void)
{
    builder b = {0};
    add_box(&b, 0, 0, 0, 1, 1, 1);
    add_box(&b, 0.2, 0.3, 0.4, 0.6, 0.7, 0.8);
    vc_self_union_report r;
    vc_surface u;
    double v = union_of(&b.s, "nested boxes", 2, &r, &u);
    CHECKF(fabs(v - 1) < 1e-14 && u.n_triangles == 12 && r.n_pairs == 0,
           "nested boxes: volume %.17g, %lld triangles, %lld pairs", v, (long long)u.n_triangles,
           (long long)r.n_pairs);
    vc_surface_free(&u);
    vc_surface_free(&b.s);

    builder c = {0};
    make_sphere(&c, 16, 8);
    v = union_of(&c.s, "sphere", 2, &r, &u);
    CHECKF(u.n_triangles == c.s.n_triangles && u.n_vertices == c.s.n_vertices &&
               !memcmp(u.tri, c.s.tri, (size_t)u.n_triangles * 3 * sizeof *u.tri),
           "sphere: not kept as it is (%lld triangles)", (long long)u.n_triangles);
    vc_surface_free(&u);
    vc_surface_free(&c.s);
}

static void test_degenerate(void)
{
    /* the cubes of ../shared/repro/hangs/cubes_overlap.obj: an edge of one
     * runs through a face diagonal of the other */
    builder b = {0};
    add_box(&b, 0, 0, 0, 1, 1, 1);
    add_box(&b, 0.5, 0.5, 0.5, 1.5, 1.5, 1.5);
    vc_surface u;
    vc_error err = {0, ""};
    int rc = vc_surface_self_union(&b.s, "overlap", &u, NULL, &err);
    CHECKF(rc == VC_EINPUT && strstr(err.msg, "overlap: ") == err.msg && strstr(err.msg, "degenerate"),
           "degenerate overlap: rc %d %s", rc, err.msg);
    CHECKF(u.n_triangles == 0 && !u.tri, "degenerate overlap: output left behind");
    vc_surface_free(&b.s);
}

static void test_cow(void)
{
    const char *dir = getenv("VC_MODELS");
    if (!dir || !dir[0]) {
        printf("VC_MODELS not set: cow.off skipped\n");
        return;
    }
    char path[1024];
    snprintf(path, sizeof path, "%s/cow.off", dir);
    vc_surface s;
    vc_surface_report rep;
    vc_error err = {0, ""};
    memset(&rep, 0, sizeof rep);
    if (vc_surface_read(path, &s, &rep, &err)) {
        CHECKF(0, "%s", err.msg);
        return;
    }
    double signed_volume = surface_enclosed_volume(&s);
    vc_self_union_report r;
    vc_surface u;
    /* the tail crosses the rump and touches it at one vertex: a handle and
     * a pinch, Euler characteristic 2 - 2 - 1 */
    double v = union_of(&s, "cow.off", -1, &r, &u);
    CHECKF(r.n_pairs == 83 && r.n_segments == 83, "cow.off: %lld pairs, %lld segments", (long long)r.n_pairs,
           (long long)r.n_segments);
    CHECKF(v < signed_volume && v > 0.999 * signed_volume, "cow.off: union volume %.9g, signed sum %.9g", v,
           signed_volume);
    vc_surface_free(&u);
    vc_surface_free(&s);
}

int main(void)
{
    omp_set_num_threads(2);
    test_two_boxes();
    test_three_boxes();
    test_box_through_sphere();
    test_nested_and_plain();
    test_degenerate();
    test_cow();
    if (failures) {
        fprintf(stderr, "test_self_union: %d failures\n", failures);
        return 1;
    }
    printf("test_self_union: all passed\n");
    return 0;
}
