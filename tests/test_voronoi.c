/* The Voronoi engine on random, lattice, co-spherical, single and
 * duplicate seeds, and on real VoroCrust seeds: validator, volume sums,
 * cube shapes, thread independence. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

#include "test_check.h"
#include "test_polymesh_compare.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double total_volume(const vc_polymesh *m)
{
    double v = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        v += m->cell_volume[c];
    return v;
}

/* Builds with the given neighbour source and validates; returns the
 * build's code. */
static int build_with(const vc_seeds *s, const double *box, int neighbours, int threads,
                      vc_polymesh *m, const char *name)
{
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    if (box) {
        opt.has_box = 1;
        memcpy(opt.box, box, sizeof opt.box);
    }
    opt.threads = threads;
    opt.neighbours = neighbours;
    vc_error err = {0, ""};
    memset(m, 0, sizeof *m);
    int rc = vc_voronoi_build(s, &opt, m, &err);
    CHECKF(rc == 0, "%s: build failed: %s", name, err.msg);
    if (rc)
        return rc;
    char report[4096];
    int64_t problems = vc_polymesh_validate(m, 0, report, sizeof report);
    CHECKF(problems == 0, "%s: %lld validation problems:\n%s", name, (long long)problems, report);
    return 0;
}

/* Builds, validates, and checks the volume sum against expected (if > 0). */
static int build_checked(const char *name, const vc_seeds *s, const double *box, int threads,
                         double expected_volume, vc_polymesh *m)
{
    int rc = build_with(s, box, VC_NEIGHBOURS_AUTO, threads, m, name);
    if (rc)
        return rc;
    if (expected_volume > 0) {
        double v = total_volume(m);
        CHECKF(fabs(v - expected_volume) <= 1e-9 * expected_volume,
              "%s: volume %.17g, expected %.17g (rel err %.3g)", name, v, expected_volume,
              fabs(v - expected_volume) / expected_volume);
    }
    printf("%s: %lld cells, %lld faces (%lld interior), %lld points, volume %.15g\n", name,
           (long long)m->n_cells, (long long)m->n_faces, (long long)m->n_interior_faces,
           (long long)m->n_points, total_volume(m));
    return 0;
}

static void test_random(int64_t n, uint64_t seed)
{
    vc_seeds s;
    vc_seeds_alloc(&s, n, NULL);
    vc_rng rng;
    vc_rng_init(&rng, seed, 0);
    for (int64_t i = 0; i < 3 * n; i++)
        s.xyz[i] = vc_rng_uniform(&rng) * 2.0 - 0.5; /* box [-0.5, 1.5]^3 */
    double box[6] = {-0.5, -0.5, -0.5, 1.5, 1.5, 1.5};
    vc_polymesh m1, m2;
    char name[64];
    snprintf(name, sizeof name, "random %lld", (long long)n);
    if (build_checked(name, &s, box, 1, 8.0, &m1) == 0) {
        CHECKF(m1.n_cells == n, "random: %lld cells for %lld seeds", (long long)m1.n_cells,
              (long long)n);
        if (build_checked(name, &s, box, 2, 8.0, &m2) == 0) {
            CHECKF(same_mesh(&m1, &m2), "random: 1-thread and 2-thread meshes differ");
            vc_polymesh_free(&m2);
        }
        vc_polymesh_free(&m1);
    }
    vc_seeds_free(&s);
}

static void test_lattice(int k)
{
    vc_seeds s;
    int64_t n = (int64_t)k * k * k;
    vc_seeds_alloc(&s, n, NULL);
    for (int64_t i = 0; i < n; i++) {
        s.xyz[3 * i + 0] = (double)(i % k) + 0.5;
        s.xyz[3 * i + 1] = (double)((i / k) % k) + 0.5;
        s.xyz[3 * i + 2] = (double)(i / ((int64_t)k * k)) + 0.5;
    }
    double box[6] = {0, 0, 0, k, k, k};
    vc_polymesh m;
    if (build_checked("lattice", &s, box, 2, (double)n, &m) == 0) {
        for (int64_t c = 0; c < m.n_cells; c++) {
            int64_t nf = m.cell_offsets[c + 1] - m.cell_offsets[c];
            CHECKF(nf == 6, "lattice: cell %lld has %lld faces", (long long)c, (long long)nf);
            for (int64_t i = m.cell_offsets[c]; i < m.cell_offsets[c + 1]; i++)
                CHECKF(vc_polymesh_face_size(&m, m.cell_faces[i]) == 4,
                      "lattice: cell %lld has a face with %lld vertices", (long long)c,
                      (long long)vc_polymesh_face_size(&m, m.cell_faces[i]));
            CHECKF(fabs(m.cell_volume[c] - 1.0) < 1e-12, "lattice: cell %lld volume %.17g",
                  (long long)c, m.cell_volume[c]);
        }
        int64_t kp1 = k + 1;
        CHECKF(m.n_points == kp1 * kp1 * kp1, "lattice: %lld points, expected %lld",
              (long long)m.n_points, (long long)(kp1 * kp1 * kp1));
        vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);
}

/* VoroCrust-like seeds: overlapping balls on a sphere surface; every pair of
 * intersection points of three sphere boundaries gives one seed inside
 * (label 1) and one outside (label 0). Here: each ball centre c_i on the
 * unit sphere has radius r; seeds are c_i +- r u for directions built so
 * that seeds come in mirrored pairs across the surface and many are
 * co-spherical about the ball centres. */
static void test_cospherical(void)
{
    int nb = 200;
    double r = 0.3;
    int per = 6;
    vc_seeds s;
    vc_seeds_alloc(&s, (int64_t)nb * per * 2 + 1, NULL);
    vc_rng rng;
    vc_rng_init(&rng, 7, 1);
    int64_t k = 0;
    for (int b = 0; b < nb; b++) {
        /* Fibonacci sphere point. */
        double z = 1.0 - 2.0 * (b + 0.5) / nb, rho = sqrt(1 - z * z), phi = b * 2.399963229728653;
        double c[3] = {rho * cos(phi), rho * sin(phi), z};
        for (int j = 0; j < per; j++) {
            /* a direction at angle 50 degrees from the normal, so the pair
             * (inside, outside) sits on this ball's sphere symmetrically */
            double a = 2 * M_PI * j / per + 0.1 * b;
            double t[3] = {-sin(phi), cos(phi), 0};
            double u[3] = {c[1] * t[2] - c[2] * t[1], c[2] * t[0] - c[0] * t[2],
                           c[0] * t[1] - c[1] * t[0]};
            double tang[3], sn = sin(50 * M_PI / 180), cs = cos(50 * M_PI / 180);
            for (int d = 0; d < 3; d++)
                tang[d] = cos(a) * t[d] + sin(a) * u[d];
            for (int side = -1; side <= 1; side += 2) {
                for (int d = 0; d < 3; d++)
                    s.xyz[3 * k + d] = c[d] + r * (sn * tang[d] + side * cs * c[d]);
                s.label[k] = side < 0 ? 1 : 0;
                k++;
            }
        }
    }
    /* Plus the centre, so the inside is not empty of interior seeds. */
    s.xyz[3 * k] = s.xyz[3 * k + 1] = s.xyz[3 * k + 2] = 0;
    s.label[k] = 1;
    k++;
    s.n = k;
    vc_polymesh m1, m2;
    if (build_checked("co-spherical pairs", &s, NULL, 1, 0, &m1) == 0) {
        if (build_checked("co-spherical pairs (2 threads)", &s, NULL, 2, 0, &m2) == 0) {
            CHECKF(same_mesh(&m1, &m2), "co-spherical: 1-thread and 2-thread meshes differ");
            vc_polymesh_free(&m2);
        }
        vc_polymesh_free(&m1);
    }
    /* The same seeds inside a box, all kept: volumes must sum to the box. */
    for (int64_t i = 0; i < s.n; i++)
        s.label[i] = 1 + (int32_t)(i % 3);
    double box[6] = {-2, -2, -2, 2, 2, 2};
    if (build_checked("co-spherical pairs in a box", &s, box, 2, 64.0, &m1) == 0)
        vc_polymesh_free(&m1);
    vc_seeds_free(&s);
}

/* Nearly degenerate: a 10^3 lattice in the unit box, each seed moved at
 * random by up to eps times the spacing; with planes_shifted, the layers of
 * constant x are also shifted by up to a fifth of the spacing, so that
 * every four seeds of two neighbouring layers with the same y or z are
 * co-circular (to eps) with their Voronoi edge of degree 4 split in two.
 * Cells decide such near-ties each on its own; corners of four nearly
 * co-circular seeds lie on that edge at places so ill-conditioned that
 * cells compute them up to micrometres apart, and faces come out a
 * billionth of the spacing wide: the mesh must still be closed, convex,
 * fill the box and be the same on 1 and 2 threads. */
static void test_near_degenerate(int planes_shifted, double eps, uint64_t seed)
{
    const int n = 10;
    vc_seeds s;
    vc_seeds_alloc(&s, n * n * n, NULL);
    vc_rng rng;
    vc_rng_init(&rng, seed, 0);
    double layer[10];
    for (int i = 0; i < n; i++)
        layer[i] = (i + 0.5 + (planes_shifted ? 0.4 * vc_rng_uniform(&rng) - 0.2 : 0.0)) / n;
    int64_t k = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int l = 0; l < n; l++, k++) {
                const double x[3] = {layer[i], (j + 0.5) / n, (l + 0.5) / n};
                for (int d = 0; d < 3; d++)
                    s.xyz[3 * k + d] = x[d] + eps * (2.0 * vc_rng_uniform(&rng) - 1.0) / n;
            }
    double box[6] = {0, 0, 0, 1, 1, 1};
    vc_polymesh m1, m2;
    char name[96];
    snprintf(name, sizeof name, "near-degenerate %s, eps %g, seed %llu",
             planes_shifted ? "shifted layers" : "lattice", eps, (unsigned long long)seed);
    if (build_checked(name, &s, box, 1, 1.0, &m1) == 0) {
        if (build_checked(name, &s, box, 2, 1.0, &m2) == 0) {
            CHECKF(same_mesh(&m1, &m2), "%s: 1-thread and 2-thread meshes differ", name);
            vc_polymesh_free(&m2);
        }
        vc_polymesh_free(&m1);
    }
    vc_seeds_free(&s);
}

/* Exactly co-spherical: 8 seeds at the corners of a cube around each
 * point of a coarse lattice (every Voronoi vertex has degree > 4). */
static void test_cube_corners(void)
{
    vc_seeds s;
    vc_seeds_alloc(&s, 4 * 4 * 4 * 8, NULL);
    int64_t k = 0;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            for (int l = 0; l < 4; l++)
                for (int c = 0; c < 8; c++) {
                    s.xyz[3 * k + 0] = i + 0.5 + ((c & 1) ? 0.25 : -0.25);
                    s.xyz[3 * k + 1] = j + 0.5 + ((c & 2) ? 0.25 : -0.25);
                    s.xyz[3 * k + 2] = l + 0.5 + ((c & 4) ? 0.25 : -0.25);
                    k++;
                }
    double box[6] = {0, 0, 0, 4, 4, 4};
    vc_polymesh m;
    if (build_checked("cube corners", &s, box, 2, 64.0, &m) == 0)
        vc_polymesh_free(&m);
    vc_seeds_free(&s);
}

/* Kept cells that touch only along an edge or at a corner, with non-kept
 * cells around it: a 3x3x3 lattice with a checkerboard of kept seeds (every
 * kept pair of neighbours shares at most an edge). Each cube corner must
 * be one mesh point: the kept cubes' corners are exactly the lattice
 * points they touch. */
static void test_checkerboard(void)
{
    const int k = 3;
    vc_seeds s;
    vc_seeds_alloc(&s, k * k * k, NULL);
    int64_t n_kept = 0;
    char used[4][4][4];
    memset(used, 0, sizeof used);
    for (int z = 0, i = 0; z < k; z++)
        for (int y = 0; y < k; y++)
            for (int x = 0; x < k; x++, i++) {
                s.xyz[3 * i] = x + 0.5;
                s.xyz[3 * i + 1] = y + 0.5;
                s.xyz[3 * i + 2] = z + 0.5;
                s.label[i] = (x + y + z) % 2 == 0;
                if (s.label[i]) {
                    n_kept++;
                    for (int c = 0; c < 8; c++)
                        used[z + (c >> 2)][y + ((c >> 1) & 1)][x + (c & 1)] = 1;
                }
            }
    int64_t corners = 0;
    for (int z = 0; z <= k; z++)
        for (int y = 0; y <= k; y++)
            for (int x = 0; x <= k; x++)
                corners += used[z][y][x];
    double box[6] = {0, 0, 0, k, k, k};
    vc_polymesh m;
    if (build_checked("checkerboard", &s, box, 2, (double)n_kept, &m) == 0) {
        CHECKF(m.n_cells == n_kept && m.n_interior_faces == 0,
              "checkerboard: %lld cells, %lld interior faces", (long long)m.n_cells,
              (long long)m.n_interior_faces);
        CHECKF(m.n_points == corners, "checkerboard: %lld points, expected %lld shared corners",
              (long long)m.n_points, (long long)corners);
        vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);
}

static void test_single_and_duplicates(void)
{
    vc_seeds s;
    vc_seeds_alloc(&s, 1, NULL);
    s.xyz[0] = 0.2;
    s.xyz[1] = 0.3;
    s.xyz[2] = 0.4;
    double box[6] = {0, 0, 0, 1, 2, 3};
    vc_polymesh m;
    if (build_checked("single seed", &s, box, 1, 6.0, &m) == 0) {
        CHECKF(m.n_cells == 1 && m.n_faces == 6 && m.n_points == 8,
              "single: %lld cells %lld faces %lld points", (long long)m.n_cells,
              (long long)m.n_faces, (long long)m.n_points);
        CHECKF(m.n_interior_faces == 0, "single: interior faces");
        vc_polymesh_free(&m);
    }
    vc_seeds_free(&s);

    vc_seeds_alloc(&s, 3, NULL);
    double pts[9] = {0.1, 0.1, 0.1, 0.5, 0.5, 0.5, 0.1, 0.1, 0.1};
    memcpy(s.xyz, pts, sizeof pts);
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    opt.has_box = 1;
    double b1[6] = {0, 0, 0, 1, 1, 1};
    memcpy(opt.box, b1, sizeof b1);
    vc_error err = {0, ""};
    int rc = vc_voronoi_build(&s, &opt, &m, &err);
    CHECKF(rc == VC_EINPUT && strstr(err.msg, "seeds 0 and 2 coincide"),
          "duplicates: rc %d, message '%s'", rc, err.msg);
    if (rc == 0)
        vc_polymesh_free(&m);
    /* A seed outside the box. */
    s.xyz[6] = 3.0;
    rc = vc_voronoi_build(&s, &opt, &m, &err);
    CHECKF(rc == VC_EINPUT && strstr(err.msg, "outside the box"), "outside: rc %d '%s'", rc,
          err.msg);
    /* NaN. */
    s.xyz[6] = NAN;
    rc = vc_voronoi_build(&s, &opt, &m, &err);
    CHECKF(rc == VC_EINPUT && strstr(err.msg, "non-finite"), "nan: rc %d '%s'", rc, err.msg);
    /* No kept seed. */
    s.xyz[6] = 0.9;
    s.label[0] = s.label[1] = s.label[2] = 0;
    rc = vc_voronoi_build(&s, &opt, &m, &err);
    CHECKF(rc == VC_EINPUT && strstr(err.msg, "no kept seed"), "no kept: rc %d '%s'", rc, err.msg);
    vc_seeds_free(&s);
}

/* Without a box: the seeds' bounding box grown by its diagonal, so the hull
 * cells reach far out and the search for their neighbours is pruned by the
 * vertices' clearance balls. Two dense clusters far apart plus sparse
 * seeds: a missed cut would make cells overlap, so the volumes must still
 * sum to the box's; the same box given explicitly gives the same mesh. */
static void test_no_box(void)
{
    const int64_t n = 3000;
    vc_seeds s;
    vc_seeds_alloc(&s, n, NULL);
    vc_rng rng;
    vc_rng_init(&rng, 11, 2);
    for (int64_t i = 0; i < n; i++) {
        double c = i < n / 2 ? 0.0 : (i < n - 40 ? 5.0 : -1.0);
        double w = i < n - 40 ? 0.3 : 8.0;
        for (int d = 0; d < 3; d++)
            s.xyz[3 * i + d] = c + w * vc_rng_uniform(&rng);
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s.xyz[3 * i + d]);
            hi[d] = fmax(hi[d], s.xyz[3 * i + d]);
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double box[6], vol = 1;
    for (int d = 0; d < 3; d++) {
        box[d] = lo[d] - diag;
        box[d + 3] = hi[d] + diag;
        vol *= box[d + 3] - box[d];
    }
    vc_polymesh m1, m2, m3;
    if (build_checked("no box", &s, NULL, 1, vol, &m1) == 0) {
        if (build_checked("no box, 2 threads", &s, NULL, 2, vol, &m2) == 0) {
            CHECKF(same_mesh(&m1, &m2), "no box: 1-thread and 2-thread meshes differ");
            vc_polymesh_free(&m2);
        }
        if (build_checked("no box, explicit box", &s, box, 1, vol, &m3) == 0) {
            CHECKF(same_mesh(&m1, &m3), "no box: differs from the same box given explicitly");
            vc_polymesh_free(&m3);
        }
        vc_polymesh_free(&m1);
    }
    vc_seeds_free(&s);
}

/* 281 VoroCrust surface seeds of the torus (vorocrust mesh --seed 3, a
 * neighbourhood of the seed that once gave an open cell): co-spherical only
 * to about 1e-9, so two cells sharing a face resolve its short Voronoi
 * edges differently (a vertex of one copy on an edge of the other: a
 * T-junction). With their labels, then every seed kept in a box: validator,
 * volume sum, 1 vs 2 threads identical. */
static void test_vorocrust_seeds(void)
{
    const char *path = VC_TEST_DATA "/torus-seed3-tjunction-281.csv";
    vc_seeds s;
    vc_error err = {0, ""};
    if (vc_seeds_read_csv(path, &s, &err) != 0) {
        CHECKF(0, "%s: %s", path, err.msg);
        return;
    }
    CHECKF(s.n == 281, "%s: %lld seeds, expected 281", path, (long long)s.n);
    vc_polymesh m1, m2;
    if (build_checked("torus seeds (T-junction)", &s, NULL, 1, 0, &m1) == 0) {
        if (build_checked("torus seeds (T-junction, 2 threads)", &s, NULL, 2, 0, &m2) == 0) {
            CHECKF(same_mesh(&m1, &m2), "torus seeds: 1-thread and 2-thread meshes differ");
            vc_polymesh_free(&m2);
        }
        vc_polymesh_free(&m1);
    }
    double box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < s.n; i++) {
        s.label[i] = 1;
        for (int d = 0; d < 3; d++) {
            box[d] = fmin(box[d], s.xyz[3 * i + d] - 0.25);
            box[d + 3] = fmax(box[d + 3], s.xyz[3 * i + d] + 0.25);
        }
    }
    double vol = (box[3] - box[0]) * (box[4] - box[1]) * (box[5] - box[2]);
    if (build_checked("torus seeds (all kept, in a box)", &s, box, 1, vol, &m1) == 0) {
        if (build_checked("torus seeds (all kept, in a box, 2 threads)", &s, box, 2, vol, &m2) ==
            0) {
            CHECKF(same_mesh(&m1, &m2), "torus seeds in a box: 1-thread and 2-thread meshes differ");
            vc_polymesh_free(&m2);
        }
        vc_polymesh_free(&m1);
    }
    vc_seeds_free(&s);
}

/* The cells' neighbours from the grid's bins and from the k-d tree give
 * the same mesh (the cut order differs, and the order the cells are built
 * and stitched in, bin by bin or leaf by leaf: the cells do not, nor does
 * the stitching), with 1 and 2 threads: on random seeds, on seeds crowded
 * in pairs along a sphere with sparse seeds inside (VoroCrust's layout,
 * where the tree is chosen), on the torus surface seeds and on a cluster
 * of cow.off's. */
static void compare_sources(const char *name, const vc_seeds *s, const double *box)
{
    vc_polymesh grid, tree1, tree2;
    build_with(s, box, VC_NEIGHBOURS_GRID, 1, &grid, name);
    build_with(s, box, VC_NEIGHBOURS_TREE, 1, &tree1, name);
    build_with(s, box, VC_NEIGHBOURS_TREE, 2, &tree2, name);
    /* the same faces between the same cells, each the same cycle of points
     * (numbered independently: the points are compared, bit for bit, the
     * cycles up to where they start; every point is computed from its
     * planes, and a class of points takes the point of its member with the
     * smallest planes, whatever the order) */
    int same = grid.n_cells == tree1.n_cells && grid.n_faces == tree1.n_faces &&
               grid.n_points == tree1.n_points &&
               !memcmp(grid.face_offsets, tree1.face_offsets,
                       sizeof(int64_t) * (size_t)(grid.n_faces + 1)) &&
               !memcmp(grid.face_owner, tree1.face_owner, sizeof(int64_t) * (size_t)grid.n_faces) &&
               !memcmp(grid.face_neighbour, tree1.face_neighbour,
                       sizeof(int64_t) * (size_t)grid.n_faces);
    int64_t bad_faces = 0;
    for (int64_t f = 0; same && f < grid.n_faces; f++) {
        const int64_t a = grid.face_offsets[f], len = grid.face_offsets[f + 1] - a;
        const double *g0 = grid.points + 3 * grid.face_vertices[a];
        int64_t shift = -1;
        for (int64_t k = 0; k < len && shift < 0; k++) {
            const double *t = tree1.points + 3 * tree1.face_vertices[a + k];
            if (t[0] == g0[0] && t[1] == g0[1] && t[2] == g0[2])
                shift = k;
        }
        int ok = shift >= 0;
        for (int64_t k = 0; ok && k < len; k++) {
            const double *g = grid.points + 3 * grid.face_vertices[a + k];
            const double *t = tree1.points + 3 * tree1.face_vertices[a + (k + shift) % len];
            ok = t[0] == g[0] && t[1] == g[1] && t[2] == g[2];
        }
        bad_faces += !ok;
    }
    CHECKF(same && bad_faces == 0, "%s: the grid's and the tree's meshes differ (%lld/%lld cells, "
           "%lld/%lld faces, %lld/%lld points, %lld faces with other points)", name,
           (long long)grid.n_cells, (long long)tree1.n_cells, (long long)grid.n_faces,
           (long long)tree1.n_faces, (long long)grid.n_points, (long long)tree1.n_points,
           (long long)bad_faces);
    CHECKF(same_mesh(&tree1, &tree2), "%s: the tree's meshes differ with 1 and 2 threads", name);
    vc_polymesh_free(&grid);
    vc_polymesh_free(&tree1);
    vc_polymesh_free(&tree2);
}

static void test_neighbour_sources(void)
{
    vc_rng rng;
    vc_rng_init(&rng, 11, 0);
    const int64_t n = 6000;
    vc_seeds s;
    vc_seeds_alloc(&s, n, NULL);
    for (int64_t i = 0; i < 3 * n; i++)
        s.xyz[i] = vc_rng_uniform(&rng);
    const double box[6] = {0, 0, 0, 1, 1, 1};
    compare_sources("random seeds", &s, box);
    for (int64_t i = 0; i < n; i += 2) {
        double p[3], r2 = 0;
        for (int d = 0; d < 3; d++) {
            p[d] = vc_rng_uniform(&rng) * 2 - 1;
            r2 += p[d] * p[d];
        }
        const double r = sqrt(r2);
        const int inner = i >= 5 * n / 6;
        for (int d = 0; d < 3; d++) {
            const double u = r > 0 ? p[d] / r : 0;
            /* a pair a sliver apart across the sphere, or sparse inside */
            s.xyz[3 * i + d] = 1 + (inner ? 0.6 * vc_rng_uniform(&rng) * u : 0.8 * u);
            s.xyz[3 * (i + 1) + d] = 1 + (inner ? 0.6 * vc_rng_uniform(&rng) * u : 0.8015 * u);
        }
        s.label[i] = 1;
        s.label[i + 1] = !inner ? 0 : 1;
    }
    compare_sources("seeds crowded along a sphere", &s, NULL);
    vc_seeds_free(&s);
    vc_error err = {0, ""};
    if (vc_seeds_read_csv(VC_TEST_DATA "/torus-seed3-tjunction-281.csv", &s, &err) == 0) {
        compare_sources("torus seeds", &s, NULL);
        vc_seeds_free(&s);
    }
    /* 899 of cow.off's seeds (vorocrust mesh, defaults, session 38) within
     * 0.0025 of a cluster of Voronoi vertices nearer each other than the
     * merge distance: a class of points. The grid builds the cells bin by
     * bin, the tree leaf by leaf: the class took the point of its first
     * vertex in that order, and two faces of 1e-21 and 2e-15 lay on one
     * segment in one order and not in the other. */
    if (vc_seeds_read_csv(VC_TEST_DATA "/cow-cluster-899.csv", &s, &err) == 0) {
        compare_sources("cow.off's seeds at a cluster", &s, NULL);
        vc_seeds_free(&s);
    } else
        CHECKF(0, "cow-cluster-899.csv: %s", err.msg);
}

/* Parts (one ctest test each, so that they run side by side): "cells"
 * (every test but the near-degenerate sets) and "near_degenerate"; no
 * argument runs both. */
int main(int argc, char **argv)
{
    const char *part = argc > 1 ? argv[1] : "";
    const int all = part[0] == 0;
    if (!all && strcmp(part, "cells") != 0 && strcmp(part, "near_degenerate") != 0) {
        fprintf(stderr, "usage: test_voronoi [cells|near_degenerate]\n");
        return 2;
    }
    if (all || strcmp(part, "cells") == 0) {
        test_single_and_duplicates();
        test_lattice(6);
        test_checkerboard();
        test_cube_corners();
        test_random(2000, 42);
        test_random(20000, 43);
        test_cospherical();
        test_vorocrust_seeds();
        test_no_box();
        test_neighbour_sources();
    }
    if (all || strcmp(part, "near_degenerate") == 0)
        for (int shifted = 0; shifted < 2; shifted++)
            for (int e = 0; e < 7; e++)
                for (uint64_t seed = 1; seed <= 2; seed++)
                    test_near_degenerate(shifted, 1e-9 * pow(10.0, 0.5 * e), seed);
    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("all voronoi checks passed\n");
    return failures ? 1 : 0;
}
