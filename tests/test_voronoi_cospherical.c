/* The Voronoi engine on exactly co-spherical and nearly co-spherical seed
 * sets (issue 19): every Voronoi vertex where more than four cells meet
 * must come out as one mesh point, every cell closed (the validator's
 * combinatorial checks have no tolerance: each cell uses each of its
 * edges once each way, each interior face is listed by its two cells),
 * the volumes must sum to the box's within 1e-12, and 1 and 2 threads
 * must give the same mesh.
 *
 * Sets: integer points on one sphere (all cells meet at its centre) and on
 * two concentric spheres, cubic and body-centred cubic lattices, the
 * centres of a graded octree's leaves (the corners of equal leaves are
 * co-spherical), a lattice of spacing 0.1 (not representable: co-spherical
 * only up to rounding), and a lattice whose seeds are moved by eps of the
 * spacing, eps from 1e-12 to 1e-6. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

#include "test_check.h"
#include "test_polymesh_compare.h"

static double total_volume(const vc_polymesh *m)
{
    double v = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        v += m->cell_volume[c];
    return v;
}

/* Builds on 1 and 2 threads in the box, validates both, checks the volume
 * and that both are the same; m gets the 1-thread mesh (freed by the
 * caller when 0 is returned). */
static int build(const char *name, const vc_seeds *s, const double box[6], vc_polymesh *m)
{
    const double box_volume = (box[3] - box[0]) * (box[4] - box[1]) * (box[5] - box[2]);
    vc_polymesh mt[2];
    int ok = 1;
    for (int t = 0; t < 2; t++) {
        vc_voronoi_options opt;
        vc_voronoi_options_default(&opt);
        opt.has_box = 1;
        memcpy(opt.box, box, sizeof opt.box);
        opt.threads = t + 1;
        vc_error err = {0, ""};
        if (vc_voronoi_build(s, &opt, &mt[t], &err) != 0) {
            CHECKF(0, "%s: build on %d thread(s) failed: %s", name, t + 1, err.msg);
            if (t == 1)
                vc_polymesh_free(&mt[0]);
            return -1;
        }
        char report[2048];
        const int64_t problems = vc_polymesh_validate(&mt[t], 0, report, sizeof report);
        CHECKF(problems == 0, "%s: %lld validation problems:\n%s", name, (long long)problems,
               report);
        ok &= problems == 0;
    }
    const double v = total_volume(&mt[0]);
    CHECKF(fabs(v - box_volume) <= 1e-12 * box_volume, "%s: volume %.17g, box %.17g (rel %.3g)",
           name, v, box_volume, fabs(v - box_volume) / box_volume);
    CHECKF(mt[0].n_cells == s->n, "%s: %lld cells for %lld seeds", name,
           (long long)mt[0].n_cells, (long long)s->n);
    CHECKF(same_mesh(&mt[0], &mt[1]), "%s: the meshes of 1 and 2 threads differ", name);
    printf("%s: %lld seeds, %lld cells, %lld faces, %lld points, volume %.15g\n", name,
           (long long)s->n, (long long)mt[0].n_cells, (long long)mt[0].n_faces,
           (long long)mt[0].n_points, v);
    vc_polymesh_free(&mt[1]);
    *m = mt[0];
    return ok ? 0 : -1;
}

/* How many mesh points lie exactly at x. */
static int64_t points_at(const vc_polymesh *m, const double x[3])
{
    int64_t k = 0;
    for (int64_t i = 0; i < m->n_points; i++)
        k += m->points[3 * i] == x[0] && m->points[3 * i + 1] == x[1] && m->points[3 * i + 2] == x[2];
    return k;
}

/* How many cells have a vertex exactly at x. */
static int64_t cells_at(const vc_polymesh *m, const double x[3])
{
    int64_t n = 0;
    for (int64_t c = 0; c < m->n_cells; c++) {
        int hit = 0;
        for (int64_t i = m->cell_offsets[c]; i < m->cell_offsets[c + 1] && !hit; i++) {
            const int64_t f = m->cell_faces[i];
            for (int64_t j = m->face_offsets[f]; j < m->face_offsets[f + 1] && !hit; j++) {
                const double *p = m->points + 3 * m->face_vertices[j];
                hit = p[0] == x[0] && p[1] == x[1] && p[2] == x[2];
            }
        }
        n += hit;
    }
    return n;
}

/* Appends the integer points with x^2 + y^2 + z^2 = r2, scaled by scale. */
static int64_t add_sphere_points(vc_seeds *s, int64_t k, int r2, double scale)
{
    const int r = (int)ceil(sqrt((double)r2));
    for (int x = -r; x <= r; x++)
        for (int y = -r; y <= r; y++)
            for (int z = -r; z <= r; z++)
                if (x * x + y * y + z * z == r2) {
                    s->xyz[3 * k] = scale * x;
                    s->xyz[3 * k + 1] = scale * y;
                    s->xyz[3 * k + 2] = scale * z;
                    s->label[k++] = 1;
                }
    return k;
}

static int64_t count_sphere_points(int r2)
{
    vc_seeds s;
    vc_seeds_alloc(&s, 8 * (int64_t)(r2 + 1) * (r2 + 1), NULL);
    const int64_t n = add_sphere_points(&s, 0, r2, 1.0);
    vc_seeds_free(&s);
    return n;
}

/* Points on one sphere: every cell is a cone from the centre, which is one
 * point shared by all of them; and two concentric spheres. */
static void test_spheres(void)
{
    const int r2a = 1001, r2b = 3 * 1001;
    const int64_t na = count_sphere_points(r2a), nb = count_sphere_points(r2b);
    vc_seeds s;
    vc_seeds_alloc(&s, na + nb, NULL);
    int64_t k = add_sphere_points(&s, 0, r2a, 0.25);
    s.n = k;
    const double box[6] = {-20, -20, -20, 20, 20, 20};
    const double centre[3] = {0, 0, 0};
    vc_polymesh m;
    if (build("one sphere", &s, box, &m) == 0) {
        CHECKF(points_at(&m, centre) == 1 && cells_at(&m, centre) == k,
               "one sphere: %lld points at the centre, %lld of %lld cells touch it",
               (long long)points_at(&m, centre), (long long)cells_at(&m, centre), (long long)k);
        vc_polymesh_free(&m);
    }
    k = add_sphere_points(&s, k, r2b, 0.25);
    s.n = k;
    if (build("two concentric spheres", &s, box, &m) == 0) {
        CHECKF(points_at(&m, centre) == 1 && cells_at(&m, centre) == na,
               "concentric spheres: %lld points at the centre, %lld cells touch it (inner %lld)",
               (long long)points_at(&m, centre), (long long)cells_at(&m, centre), (long long)na);
        vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);
}

/* Cubic lattice of spacing h from lo + h / 2 (n^3 seeds): every interior
 * lattice corner is one point of 8 cells. With bcc, the cube centres too
 * (truncated octahedra). */
static void lattice(vc_seeds *s, int n, double h, int bcc)
{
    vc_seeds_alloc(s, (int64_t)n * n * n * (bcc ? 2 : 1), NULL);
    int64_t k = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int l = 0; l < n; l++) {
                s->xyz[3 * k] = (i + 0.5) * h;
                s->xyz[3 * k + 1] = (j + 0.5) * h;
                s->xyz[3 * k + 2] = (l + 0.5) * h;
                s->label[k++] = 1;
                if (bcc && i + 1 < n && j + 1 < n && l + 1 < n) {
                    s->xyz[3 * k] = (i + 1) * h;
                    s->xyz[3 * k + 1] = (j + 1) * h;
                    s->xyz[3 * k + 2] = (l + 1) * h;
                    s->label[k++] = 1;
                }
            }
    s->n = k;
}

static void test_lattices(void)
{
    const int n = 8;
    vc_seeds s;
    vc_polymesh m;
    /* spacing 1: every interior corner exactly shared */
    lattice(&s, n, 1.0, 0);
    const double box[6] = {0, 0, 0, n, n, n};
    if (build("cubic lattice", &s, box, &m) == 0) {
        CHECKF(m.n_points == (int64_t)(n + 1) * (n + 1) * (n + 1),
               "cubic lattice: %lld points, expected %d", (long long)m.n_points,
               (n + 1) * (n + 1) * (n + 1));
        vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);
    lattice(&s, n, 1.0, 1);
    if (build("bcc lattice", &s, box, &m) == 0) {
        int64_t n14 = 0;
        for (int64_t c = 0; c < m.n_cells; c++)
            n14 += m.cell_offsets[c + 1] - m.cell_offsets[c] == 14;
        /* the cells of the inner body centres are truncated octahedra */
        CHECKF(n14 >= (int64_t)(n - 3) * (n - 3) * (n - 3),
               "bcc lattice: %lld cells with 14 faces", (long long)n14);
        vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);
    /* spacing 0.1, not representable: co-spherical up to rounding only */
    lattice(&s, n, 0.1, 0);
    const double box01[6] = {0, 0, 0, n * 0.1, n * 0.1, n * 0.1};
    if (build("cubic lattice, spacing 0.1", &s, box01, &m) == 0) {
        CHECKF(m.n_points == (int64_t)(n + 1) * (n + 1) * (n + 1) && m.n_faces ==
                   (int64_t)3 * n * n * (n + 1),
               "lattice 0.1: %lld points, %lld faces: the rounding left vertices or faces apart",
               (long long)m.n_points, (long long)m.n_faces);
        vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);
}

/* The centres of the leaves of an octree of the unit cube, refined while a
 * leaf's side exceeds 0.02 + 0.25 times its centre's distance to the
 * corner (0, 0, 0) (a Lipschitz size: neighbouring leaves differ by one
 * level at most), then balanced to 2:1 across faces, edges and corners. */
typedef struct leaf {
    int level, i, j, k; /* side 2^-level, low corner (i, j, k) 2^-level */
} leaf;

static int leaf_needs_split(const leaf *q)
{
    const double side = ldexp(1.0, -q->level);
    const double c[3] = {(q->i + 0.5) * side, (q->j + 0.5) * side, (q->k + 0.5) * side};
    return side > 0.02 + 0.25 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/* Does leaf a touch leaf b (faces, edges or corners)? */
static int leaves_touch(const leaf *a, const leaf *b)
{
    const int L = a->level > b->level ? a->level : b->level;
    const int64_t sa = (int64_t)1 << (L - a->level), sb = (int64_t)1 << (L - b->level);
    const int64_t la[3] = {a->i * sa, a->j * sa, a->k * sa}, lb[3] = {b->i * sb, b->j * sb, b->k * sb};
    for (int d = 0; d < 3; d++)
        if (la[d] > lb[d] + sb || lb[d] > la[d] + sa)
            return 0;
    return 1;
}

static void test_octree(void)
{
    int cap = 1 << 16, n = 1;
    leaf *q = malloc((size_t)cap * sizeof *q);
    q[0] = (leaf){0, 0, 0, 0};
    for (int changed = 1; changed;) {
        changed = 0;
        for (int a = 0; a < n; a++) {
            int split = leaf_needs_split(&q[a]);
            for (int b = 0; b < n && !split; b++)
                split = q[b].level > q[a].level + 1 && leaves_touch(&q[a], &q[b]);
            if (!split || n + 7 > cap)
                continue;
            const leaf p = q[a];
            for (int c = 0; c < 8; c++) {
                const leaf ch = {p.level + 1, 2 * p.i + (c & 1), 2 * p.j + ((c >> 1) & 1),
                                 2 * p.k + ((c >> 2) & 1)};
                if (c == 0)
                    q[a] = ch;
                else
                    q[n++] = ch;
            }
            changed = 1;
        }
    }
    vc_seeds s;
    vc_seeds_alloc(&s, n, NULL);
    int max_level = 0;
    for (int a = 0; a < n; a++) {
        const double side = ldexp(1.0, -q[a].level);
        s.xyz[3 * a] = (q[a].i + 0.5) * side;
        s.xyz[3 * a + 1] = (q[a].j + 0.5) * side;
        s.xyz[3 * a + 2] = (q[a].k + 0.5) * side;
        s.label[a] = 1;
        max_level = q[a].level > max_level ? q[a].level : max_level;
    }
    free(q);
    CHECKF(max_level >= 4, "octree: only %d levels", max_level);
    const double box[6] = {0, 0, 0, 1, 1, 1};
    vc_polymesh m;
    if (build("octree leaf centres", &s, box, &m) == 0)
        vc_polymesh_free(&m);
    vc_seeds_free(&s);
}

/* A lattice whose seeds are moved at random by up to eps of the spacing:
 * every corner a cluster of vertices eps wide. */
static void test_near(double eps)
{
    vc_seeds s;
    lattice(&s, 8, 0.125, 0);
    vc_rng rng;
    vc_rng_init(&rng, 11, 0);
    for (int64_t i = 0; i < 3 * s.n; i++)
        s.xyz[i] += eps * 0.125 * (2 * vc_rng_uniform(&rng) - 1);
    const double box[6] = {0, 0, 0, 1, 1, 1};
    char name[64];
    snprintf(name, sizeof name, "lattice moved by %g", eps);
    vc_polymesh m;
    if (build(name, &s, box, &m) == 0)
        vc_polymesh_free(&m);
    vc_seeds_free(&s);
}

int main(void)
{
    test_spheres();
    test_lattices();
    test_octree();
    for (int e = -12; e <= -6; e++)
        test_near(pow(10.0, e));
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("all co-spherical voronoi checks passed\n");
    return failures ? 1 : 0;
}
