/* Building small surfaces in memory for the C unit tests: a vc_surface
 * grown vertex by vertex and triangle by triangle, and a few shapes built
 * that way. Start from `builder b = {0};`; the surface is b.s (free it
 * with vc_surface_free). */
#ifndef VC_TEST_SURFACE_UTIL_H
#define VC_TEST_SURFACE_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "vorocrust/surface.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct builder {
    vc_surface s;
    int64_t cap_v, cap_t;
} builder;

static inline int64_t add_v(builder *b, double x, double y, double z)
{
    if (b->s.n_vertices == b->cap_v) {
        b->cap_v = b->cap_v ? 2 * b->cap_v : 16;
        b->s.xyz = realloc(b->s.xyz, (size_t)b->cap_v * 3 * sizeof(double));
    }
    double *p = b->s.xyz + 3 * b->s.n_vertices;
    p[0] = x;
    p[1] = y;
    p[2] = z;
    return b->s.n_vertices++;
}

static inline void add_t(builder *b, int64_t i, int64_t j, int64_t k)
{
    if (b->s.n_triangles == b->cap_t) {
        b->cap_t = b->cap_t ? 2 * b->cap_t : 16;
        b->s.tri = realloc(b->s.tri, (size_t)b->cap_t * 3 * sizeof(int64_t));
    }
    int64_t *t = b->s.tri + 3 * b->s.n_triangles++;
    t[0] = i;
    t[1] = j;
    t[2] = k;
}

/* A quad a b c d (counter-clockwise) as two triangles. */
static inline void add_q(builder *b, int64_t a, int64_t c1, int64_t c2, int64_t d)
{
    add_t(b, a, c1, c2);
    add_t(b, a, c2, d);
}

/* The closed polygon xy (m points, counter-clockwise) extruded along z
 * from 0 to len, caps fanned from a centre vertex at the origin's (0, 0),
 * outward oriented; its vertices follow those already in b. */
static inline void extrude_section(builder *b, const double *xy, int m, double len)
{
    int64_t base = b->s.n_vertices;
    for (int i = 0; i < m; i++) {
        add_v(b, xy[2 * i], xy[2 * i + 1], 0);
        add_v(b, xy[2 * i], xy[2 * i + 1], len);
    }
    int64_t c0 = add_v(b, 0, 0, 0), c1 = add_v(b, 0, 0, len);
    for (int i = 0; i < m; i++) {
        int j = (i + 1) % m;
        int64_t lo_i = base + 2 * i, hi_i = lo_i + 1, lo_j = base + 2 * j, hi_j = lo_j + 1;
        add_q(b, lo_i, lo_j, hi_j, hi_i);
        add_t(b, c0, lo_j, lo_i);
        add_t(b, c1, hi_i, hi_j);
    }
}

/* An n-gon prism of radius 1 and height h, caps fanned from a centre
 * vertex, outward oriented; its vertices follow those already in b. */
static inline void make_prism(builder *b, int n, double h)
{
    double *xy = malloc(sizeof(double) * 2 * (size_t)n);
    if (!xy)
        abort();
    for (int i = 0; i < n; i++) {
        xy[2 * i] = cos(2 * M_PI * i / n);
        xy[2 * i + 1] = sin(2 * M_PI * i / n);
    }
    extrude_section(b, xy, n, h);
    free(xy);
}

/* A UV sphere of radius 1, nu x nv, outward. */
static inline void make_sphere(builder *b, int nu, int nv)
{
    int64_t top = add_v(b, 0, 0, 1), bottom = add_v(b, 0, 0, -1);
    int64_t first = b->s.n_vertices;
    for (int j = 1; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
            add_v(b, sin(th) * cos(ph), sin(th) * sin(ph), cos(th));
        }
#define V(i, j) (first + (int64_t)((j) - 1) * nu + ((i) % nu))
    for (int i = 0; i < nu; i++) {
        add_t(b, top, V(i, 1), V(i + 1, 1));
        add_t(b, bottom, V(i + 1, nv - 1), V(i, nv - 1));
        for (int j = 1; j + 1 < nv; j++)
            add_q(b, V(i, j), V(i, j + 1), V(i + 1, j + 1), V(i + 1, j));
    }
#undef V
}

/* A cube [0, 1]^3, outward. */
static inline void make_cube(builder *b)
{
    int64_t v[8];
    for (int k = 0; k < 8; k++)
        v[k] = add_v(b, k & 1, (k >> 1) & 1, (k >> 2) & 1);
    add_q(b, v[0], v[2], v[3], v[1]); /* z = 0 */
    add_q(b, v[4], v[5], v[7], v[6]); /* z = 1 */
    add_q(b, v[0], v[1], v[5], v[4]); /* y = 0 */
    add_q(b, v[2], v[6], v[7], v[3]); /* y = 1 */
    add_q(b, v[0], v[4], v[6], v[2]); /* x = 0 */
    add_q(b, v[1], v[3], v[7], v[5]); /* x = 1 */
}

/* The volume the triangles enclose (divergence theorem). */
static inline double surface_enclosed_volume(const vc_surface *s)
{
    double v = 0;
    for (int64_t t = 0; t < s->n_triangles; t++) {
        const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                     *c = s->xyz + 3 * s->tri[3 * t + 2];
        v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
              a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
    return v;
}

/* A row of n unit boxes along x, [k, k+1] x [0,1] x [0,1], as one surface:
 * each box's faces once (the face between box k and k+1 belongs to box k,
 * facing +x), with a grid of g x g squares per unit face so that edges and
 * vertices abound. */
static inline void box_row(builder *b, int n, int g)
{
    /* vertices on the lattice (i/g, j/g, k/g), i in 0..n g */
    const int nx = n * g + 1, ny = g + 1, nz = g + 1;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++)
                add_v(b, (double)i / g, (double)j / g, (double)k / g);
#define V(i, j, k) ((int64_t)(k) * ny * nx + (int64_t)(j) * nx + (i))
    /* a square (a, b, c, d counter-clockwise seen from where it faces) */
#define SQUARE(a, bb, c, d) do { add_t(b, a, bb, c); add_t(b, a, c, d); } while (0)
    for (int i = 0; i < nx - 1; i++)
        for (int j = 0; j < ny - 1; j++) {
            SQUARE(V(i, j, 0), V(i, j + 1, 0), V(i + 1, j + 1, 0), V(i + 1, j, 0));         /* -z */
            SQUARE(V(i, j, nz - 1), V(i + 1, j, nz - 1), V(i + 1, j + 1, nz - 1), V(i, j + 1, nz - 1));
        }
    for (int i = 0; i < nx - 1; i++)
        for (int k = 0; k < nz - 1; k++) {
            SQUARE(V(i, 0, k), V(i + 1, 0, k), V(i + 1, 0, k + 1), V(i, 0, k + 1));         /* -y */
            SQUARE(V(i, ny - 1, k), V(i, ny - 1, k + 1), V(i + 1, ny - 1, k + 1), V(i + 1, ny - 1, k));
        }
    /* x = const walls: the outer two, and one between every two boxes */
    for (int w = 0; w <= n; w++) {
        const int i = w * g;
        for (int j = 0; j < ny - 1; j++)
            for (int k = 0; k < nz - 1; k++) {
                if (w == 0) /* -x */
                    SQUARE(V(i, j, k), V(i, j, k + 1), V(i, j + 1, k + 1), V(i, j + 1, k));
                else        /* +x */
                    SQUARE(V(i, j, k), V(i, j + 1, k), V(i, j + 1, k + 1), V(i, j, k + 1));
            }
    }
#undef SQUARE
#undef V
}

#endif
