/* vc_surface_flip_turned_needles: a UV sphere with one pleat (a needle
 * whose apex crossed its long edge onto the neighbouring triangle) gets
 * that edge flipped when the apex's height is within max_move, and only
 * then; the result is a closed, consistently oriented surface without a
 * fold of 90 degrees, moved by the apex's height at most. A needle that did
 * not cross its edge is left alone. vc_surface_collapse_hairpins: a box
 * whose front face reaches into its top face as a needle (a hairpin of two
 * creases) loses it when its base is below max_base (and its folds are
 * sharp in the features given), and only then, closed and oriented. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"
#include "test_surface_util.h"
#include "vorocrust/features.h"
#include "vorocrust/surface.h"

static void sub(const double *a, const double *b, double *r)
{
    for (int k = 0; k < 3; k++)
        r[k] = a[k] - b[k];
}

static void cross(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm(const double *a)
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

static void unit_normal(const vc_surface *s, int64_t t, double n[3])
{
    const int64_t *T = s->tri + 3 * t;
    double u[3], v[3];
    sub(s->xyz + 3 * T[1], s->xyz + 3 * T[0], u);
    sub(s->xyz + 3 * T[2], s->xyz + 3 * T[0], v);
    cross(u, v, n);
    const double l = norm(n);
    for (int k = 0; k < 3; k++)
        n[k] /= l;
}

/* The triangle holding the directed edge (a, b), or -1. */
static int64_t holder(const vc_surface *s, int64_t a, int64_t b)
{
    for (int64_t t = 0; t < s->n_triangles; t++)
        for (int k = 0; k < 3; k++)
            if (s->tri[3 * t + k] == a && s->tri[3 * t + (k + 1) % 3] == b)
                return t;
    return -1;
}

/* Every directed edge once, its reverse once; and the smallest cosine of
 * the fold between neighbours. */
static int closed_oriented(const vc_surface *s, double *min_fold_cos)
{
    *min_fold_cos = 1;
    for (int64_t t = 0; t < s->n_triangles; t++)
        for (int k = 0; k < 3; k++) {
            const int64_t a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
            int n_same = 0;
            for (int64_t q = 0; q < s->n_triangles; q++)
                for (int j = 0; j < 3; j++)
                    n_same += s->tri[3 * q + j] == a && s->tri[3 * q + (j + 1) % 3] == b;
            const int64_t g = holder(s, b, a);
            if (n_same != 1 || g < 0)
                return 0;
            double n[3], m[3];
            unit_normal(s, t, n);
            unit_normal(s, g, m);
            const double c = n[0] * m[0] + n[1] * m[1] + n[2] * m[2];
            if (c < *min_fold_cos)
                *min_fold_cos = c;
        }
    return 1;
}

/* Splits triangle t = (u, v, o) at a new point w near the middle of u v:
 * moved by `across` times height along the plane of the triangle (v, u, a)
 * beyond u v (a turned-over needle), or, with across < 0, into t itself
 * (a needle that did not cross). Returns w's height over the line u v. */
static double add_needle(builder *b, int64_t t, double height, int across)
{
    vc_surface *s = &b->s;
    const int64_t u = s->tri[3 * t], v = s->tri[3 * t + 1], o = s->tri[3 * t + 2];
    const int64_t g = holder(s, v, u);
    int64_t a = -1;
    for (int k = 0; k < 3; k++)
        if (s->tri[3 * g + k] != u && s->tri[3 * g + k] != v)
            a = s->tri[3 * g + k];
    double m[3], d[3], e[3], f[3], n2[3], w[3];
    for (int k = 0; k < 3; k++)
        m[k] = 0.5 * (s->xyz[3 * u + k] + s->xyz[3 * v + k]);
    sub(s->xyz + 3 * (across ? a : o), m, d);
    sub(s->xyz + 3 * u, s->xyz + 3 * v, e);
    sub(s->xyz + 3 * a, s->xyz + 3 * v, f);
    cross(e, f, n2);
    /* d made perpendicular to u v, so that the height is known */
    const double el = norm(e), dl0 = (d[0] * e[0] + d[1] * e[1] + d[2] * e[2]) / (el * el);
    for (int k = 0; k < 3; k++)
        d[k] -= dl0 * e[k];
    const double dl = norm(d), nl = norm(n2);
    for (int k = 0; k < 3; k++)
        w[k] = m[k] + height * d[k] / dl + (across ? height / 3 * n2[k] / nl : 0);
    const int64_t iw = add_v(b, w[0], w[1], w[2]);
    s = &b->s;
    s->tri[3 * t + 2] = iw; /* (u, v, w) */
    add_t(b, v, o, iw);
    add_t(b, o, u, iw);
    /* the height of w over the line u v */
    double wu[3], c[3];
    sub(w, b->s.xyz + 3 * u, wu);
    cross(wu, e, c);
    return norm(c) / el;
}

/* Splits triangle t = (u, v, o) at w, `height` above the middle of u v
 * along t's normal: the needle (u, v, w) stands up against the triangle
 * across u v by about 90 degrees (a fin: a T-junction closed by a sliver
 * whose apex is off the edge). */
static void add_fin(builder *b, int64_t t, double height)
{
    vc_surface *s = &b->s;
    const int64_t u = s->tri[3 * t], v = s->tri[3 * t + 1], o = s->tri[3 * t + 2];
    double e[3], f[3], n[3], w[3];
    sub(s->xyz + 3 * v, s->xyz + 3 * u, e);
    sub(s->xyz + 3 * o, s->xyz + 3 * u, f);
    cross(e, f, n);
    const double nl = norm(n);
    for (int k = 0; k < 3; k++)
        w[k] = 0.5 * (s->xyz[3 * u + k] + s->xyz[3 * v + k]) + height * n[k] / nl;
    const int64_t iw = add_v(b, w[0], w[1], w[2]);
    s = &b->s;
    s->tri[3 * t + 2] = iw; /* (u, v, w) */
    add_t(b, v, o, iw);
    add_t(b, o, u, iw);
}

static vc_surface copy_surface(const vc_surface *s)
{
    vc_surface c = *s;
    c.xyz = malloc(sizeof(double) * 3 * (size_t)s->n_vertices);
    c.tri = malloc(sizeof(int64_t) * 3 * (size_t)s->n_triangles);
    memcpy(c.xyz, s->xyz, sizeof(double) * 3 * (size_t)s->n_vertices);
    memcpy(c.tri, s->tri, sizeof(int64_t) * 3 * (size_t)s->n_triangles);
    return c;
}

/* The unit cube whose front face (y = 0) reaches into its top face (z = 1)
 * as a needle: from the rim's middle a = (0.5, 0, 1) and b = (0.5, 0,
 * 1 - h) just below it to the apex c = (0.5, 0.6, 1) inside the top face,
 * standing up 90 degrees between the top face's triangles on either side.
 * Returns c. */
static int64_t make_hairpin_box(builder *b, double h)
{
    int64_t v[8];
    for (int k = 0; k < 8; k++)
        v[k] = add_v(b, k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const int64_t a = add_v(b, 0.5, 0, 1), bb = add_v(b, 0.5, 0, 1 - h), c = add_v(b, 0.5, 0.6, 1);
    add_q(b, v[0], v[2], v[3], v[1]); /* z = 0 */
    add_q(b, v[2], v[6], v[7], v[3]); /* y = 1 */
    add_q(b, v[0], v[4], v[6], v[2]); /* x = 0 */
    add_q(b, v[1], v[3], v[7], v[5]); /* x = 1 */
    add_t(b, v[4], a, c);             /* z = 1, around c */
    add_t(b, bb, v[5], c);
    add_t(b, v[5], v[7], c);
    add_t(b, v[7], v[6], c);
    add_t(b, v[6], v[4], c);
    add_t(b, a, bb, c); /* the needle */
    add_t(b, v[0], v[1], bb); /* y = 0 */
    add_t(b, v[1], v[5], bb);
    add_t(b, v[0], bb, a);
    add_t(b, v[0], a, v[4]);
    return c;
}

/* The sharp edges at vertex v at theta_sharp theta (degrees). */
static int sharp_at(const vc_surface *s, int64_t v, double theta)
{
    vc_features f;
    vc_error err;
    if (vc_features_detect(s, theta, &f, &err))
        return -1;
    int n = 0;
    for (int64_t e = 0; e < f.n_edges; e++)
        n += f.edge_sharp[e] && (f.edge_vertex[2 * e] == v || f.edge_vertex[2 * e + 1] == v);
    vc_features_free(&f);
    return n;
}

static void check_hairpins(void)
{
    const double h = 0.002, cos60 = 0.5;
    builder b = {0};
    const int64_t c = make_hairpin_box(&b, h);
    double c0;
    CHECK(closed_oriented(&b.s, &c0));
    CHECKF(sharp_at(&b.s, c, 60) == 2, "%d sharp edges at the apex", sharp_at(&b.s, c, 60));
    const double vol0 = surface_enclosed_volume(&b.s);
    CHECK(vc_surface_count_hairpins(&b.s, 2 * h, cos60) == 1);
    CHECK(vc_surface_count_hairpins(&b.s, 0.5 * h, cos60) == 0);

    /* its base longer than max_base: nothing */
    vc_surface s1 = copy_surface(&b.s);
    double move = -1;
    CHECK(vc_surface_collapse_hairpins(&s1, 0.5 * h, cos60, NULL, &move) == 0 && move == 0);
    CHECK(s1.n_triangles == b.s.n_triangles);
    vc_surface_free(&s1);

    /* features at the bound 0.1 (the rim within reach: not flat ground)
     * take its folds as creases: collapsed, closed and oriented, no crease
     * left at the apex, moved by the base's length */
    vc_features f;
    vc_error err;
    CHECK(vc_features_detect_scaled(&b.s, 60, NULL, 0.1, &f, &err) == 0);
    vc_surface s2 = copy_surface(&b.s);
    CHECKF(vc_surface_collapse_hairpins(&s2, 2 * h, cos60, &f, &move) == 1, "%lld triangles left",
           (long long)s2.n_triangles);
    CHECK(s2.n_triangles == b.s.n_triangles - 2 && s2.n_vertices == b.s.n_vertices - 1);
    CHECKF(fabs(move - h) <= 1e-12, "moved by %.17g", move);
    double c2;
    CHECK(closed_oriented(&s2, &c2));
    int64_t apex = -1; /* c's index after compaction: the point (0.5, 0.6, 1) */
    for (int64_t v = 0; v < s2.n_vertices; v++)
        if (s2.xyz[3 * v] == 0.5 && s2.xyz[3 * v + 1] == 0.6 && s2.xyz[3 * v + 2] == 1)
            apex = v;
    CHECK(apex >= 0 && sharp_at(&s2, apex, 60) == 0);
    CHECKF(fabs(surface_enclosed_volume(&s2) - vol0) < h, "volume %.9g to %.9g", vol0,
           surface_enclosed_volume(&s2));
    vc_surface_free(&s2);
    vc_features_free(&f);

    /* features that do not take its folds as creases (theta_sharp 100):
     * left alone */
    CHECK(vc_features_detect(&b.s, 100, &f, &err) == 0);
    vc_surface s3 = copy_surface(&b.s);
    CHECK(vc_surface_collapse_hairpins(&s3, 2 * h, cos60, &f, &move) == 0);
    vc_surface_free(&s3);
    vc_features_free(&f);
    vc_surface_free(&b.s);
}

int main(void)
{
    builder b = {0};
    make_sphere(&b, 24, 12);
    const int64_t t = 7 * 22 + 2 + 2 * 5; /* column 7 (22 triangles each): a quad at mid-latitude */
    const double h = add_needle(&b, t, 0.01, 1);
    const double vol0 = surface_enclosed_volume(&b.s);
    vc_error err;
    double c0;
    CHECK(closed_oriented(&b.s, &c0));
    CHECKF(c0 < -0.9, "the pleat folds by %.1f degrees", acos(c0) * 180 / M_PI);

    /* the pleat's needle is the one candidate above its height, none below */
    CHECKF(vc_surface_count_low_needles(&b.s, 1.1 * h) >= 1 && vc_surface_count_low_needles(&b.s, 0.9 * h) == 0,
           "low needles: %lld above the apex's height, %lld below",
           (long long)vc_surface_count_low_needles(&b.s, 1.1 * h),
           (long long)vc_surface_count_low_needles(&b.s, 0.9 * h));

    /* max_move below the apex's height: nothing */
    vc_surface s1 = copy_surface(&b.s);
    vc_needle_flip_report rep;
    CHECK(vc_surface_flip_turned_needles(&s1, 0.9 * h, &rep, &err) == 0);
    CHECK(rep.n_flipped == 0 && rep.max_move == 0);
    CHECK(memcmp(s1.tri, b.s.tri, sizeof(int64_t) * 3 * (size_t)b.s.n_triangles) == 0);
    vc_surface_free(&s1);

    /* above it: one flip, the surface moved by h at most */
    vc_surface s2 = copy_surface(&b.s);
    CHECK(vc_surface_flip_turned_needles(&s2, 1.1 * h, &rep, &err) == 0);
    CHECKF(rep.n_flipped == 1, "%lld flips", (long long)rep.n_flipped);
    CHECKF(fabs(rep.max_move - h) <= 1e-12, "max_move %.17g, apex height %.17g", rep.max_move, h);
    double c2;
    CHECK(closed_oriented(&s2, &c2));
    CHECKF(c2 > 0.5, "a fold of %.1f degrees left", acos(c2) * 180 / M_PI);
    CHECK(s2.n_triangles == b.s.n_triangles && s2.n_vertices == b.s.n_vertices);
    /* the swept volume is a thin tetrahedron: at most the pleat's area
     * times h */
    const double vol2 = surface_enclosed_volume(&s2);
    CHECKF(fabs(vol2 - vol0) < 0.3 * 0.3 * h, "volume %.9g to %.9g", vol0, vol2);
    vc_surface_free(&s2);

    /* max_move 0: nothing, and no failure */
    vc_surface s3 = copy_surface(&b.s);
    CHECK(vc_surface_flip_turned_needles(&s3, 0, &rep, &err) == 0 && rep.n_flipped == 0);
    vc_surface_free(&s3);
    vc_surface_free(&b.s);

    /* a fin 1e-6 high: flipped when its height is within a fifth of
     * max_move, counted as a fin; left alone below that */
    builder bf = {0};
    make_sphere(&bf, 24, 12);
    add_fin(&bf, t, 1e-6);
    double cf;
    CHECK(closed_oriented(&bf.s, &cf));
    CHECKF(cf < 0.2 && cf > -0.2, "the fin folds by %.1f degrees", acos(cf) * 180 / M_PI);
    vc_surface f4 = copy_surface(&bf.s);
    CHECK(vc_surface_flip_turned_needles(&f4, 2e-6, &rep, &err) == 0 && rep.n_flipped == 0);
    vc_surface_free(&f4);
    vc_surface f5 = copy_surface(&bf.s);
    CHECK(vc_surface_flip_turned_needles(&f5, 1e-5, &rep, &err) == 0);
    CHECKF(rep.n_flipped == 1 && rep.n_fins == 1, "%lld flips, %lld fins", (long long)rep.n_flipped,
           (long long)rep.n_fins);
    double c5;
    CHECK(closed_oriented(&f5, &c5));
    CHECKF(c5 > 0.5, "a fold of %.1f degrees left", acos(c5) * 180 / M_PI);
    vc_surface_free(&f5);
    vc_surface_free(&bf.s);

    /* a needle that did not cross its edge stays */
    builder c = {0};
    make_sphere(&c, 24, 12);
    add_needle(&c, t, 0.01, 0);
    double c4;
    CHECK(closed_oriented(&c.s, &c4) && c4 > 0);
    vc_surface s4 = copy_surface(&c.s);
    CHECK(vc_surface_flip_turned_needles(&s4, 1.0, &rep, &err) == 0 && rep.n_flipped == 0);
    CHECK(memcmp(s4.tri, c.s.tri, sizeof(int64_t) * 3 * (size_t)c.s.n_triangles) == 0);
    vc_surface_free(&s4);
    vc_surface_free(&c.s);

    check_hairpins();
    return failures ? 1 : 0;
}
