/* Tests of vc_polymesh_remove_straight_vertices on meshes built by hand:
 *   - two unit cubes side by side with an extra point in the middle of an
 *     edge of their common face (in the three faces along that edge): the
 *     point goes, the faces become quads again, points are renumbered, the
 *     mesh stays valid, volumes stay 1;
 *   - the same without the extra point: nothing changes;
 *   - a zero-area triangle whose vertex is straight: the vertex is kept
 *     (the face would drop below three vertices).
 * And on the engine: VoroCrust seeds of the torus that used to leave a
 * straight vertex give a valid mesh without one. */
#include "vorocrust/polymesh.h"
#include "polymesh/repair.h"
#include "vorocrust/voronoi.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"
#include "test_cube_block.h"


typedef struct builder {
    int64_t fv[64];
    int64_t off[16];
    int64_t owner[16], nbr[16];
    int nf, nfv;
} builder;

/* Adds a face; when mid >= 0, mid is inserted into the edge between
 * corners a0 and a1 (either direction) if the face has it. */
static void add_face(builder *b, const int64_t *v, int n, int64_t owner, int64_t nbr, int64_t mid,
                     int64_t a0, int64_t a1)
{
    b->off[b->nf] = b->nfv;
    for (int i = 0; i < n; i++) {
        int64_t x = v[i], y = v[(i + 1) % n];
        b->fv[b->nfv++] = x;
        if (mid >= 0 && ((x == a0 && y == a1) || (x == a1 && y == a0)))
            b->fv[b->nfv++] = mid;
    }
    b->owner[b->nf] = owner;
    b->nbr[b->nf] = nbr;
    b->nf++;
    b->off[b->nf] = b->nfv;
}

/* The two-cube mesh; with_mid adds point 12 at (1, 0.5, 0), inside the edge
 * (1,0,0)-(1,1,0). */
static void two_cubes(vc_polymesh *m, int with_mid)
{
    memset(m, 0, sizeof *m);
    builder b;
    memset(&b, 0, sizeof b);
    const int64_t mid = with_mid ? 12 : -1, a0 = block_corner(1, 0, 0), a1 = block_corner(1, 1, 0);
    for (int c = 0; c < 2; c++) {
        int64_t f[6][4];
        block_cube_faces(c, f);
        const int64_t *xlo = f[0], *xhi = f[1], *ylo = f[2], *yhi = f[3], *zlo = f[4], *zhi = f[5];
        if (c == 0) {
            add_face(&b, xhi, 4, 0, 1, mid, a0, a1); /* the common face, first */
            add_face(&b, xlo, 4, 0, -1, mid, a0, a1);
        } else {
            add_face(&b, xhi, 4, 1, -1, mid, a0, a1);
        }
        add_face(&b, ylo, 4, c, -1, mid, a0, a1);
        add_face(&b, yhi, 4, c, -1, mid, a0, a1);
        add_face(&b, zlo, 4, c, -1, mid, a0, a1);
        add_face(&b, zhi, 4, c, -1, mid, a0, a1);
    }
    m->n_points = with_mid ? 13 : 12;
    m->points = malloc(sizeof(double) * 3 * (size_t)m->n_points);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++)
            for (int k = 0; k < 2; k++) {
                double *p = m->points + 3 * block_corner(i, j, k);
                p[0] = i;
                p[1] = j;
                p[2] = k;
            }
    if (with_mid) {
        m->points[36] = 1;
        m->points[37] = 0.5;
        m->points[38] = 0;
    }
    m->n_faces = b.nf;
    m->n_interior_faces = 1;
    m->face_offsets = malloc(sizeof(int64_t) * (size_t)(b.nf + 1));
    memcpy(m->face_offsets, b.off, sizeof(int64_t) * (size_t)(b.nf + 1));
    m->face_vertices = malloc(sizeof(int64_t) * (size_t)b.nfv);
    memcpy(m->face_vertices, b.fv, sizeof(int64_t) * (size_t)b.nfv);
    m->face_owner = malloc(sizeof(int64_t) * (size_t)b.nf);
    m->face_neighbour = malloc(sizeof(int64_t) * (size_t)b.nf);
    m->face_other_seed = malloc(sizeof(int64_t) * (size_t)b.nf);
    for (int f = 0; f < b.nf; f++) {
        m->face_owner[f] = b.owner[f];
        m->face_neighbour[f] = b.nbr[f];
        m->face_other_seed[f] = b.nbr[f] >= 0 ? b.nbr[f] : 2;
    }
    m->face_area = malloc(sizeof(double) * (size_t)b.nf);
    m->face_centroid = malloc(sizeof(double) * 3 * (size_t)b.nf);
    m->face_normal = malloc(sizeof(double) * 3 * (size_t)b.nf);
    m->n_cells = 2;
    m->cell_offsets = malloc(sizeof(int64_t) * 3);
    m->cell_faces = malloc(sizeof(int64_t) * 12);
    /* cell 0: faces 0..5; cell 1: the common face 0, then 6..10 */
    int64_t cf[12] = {0, 1, 2, 3, 4, 5, 0, 6, 7, 8, 9, 10};
    memcpy(m->cell_faces, cf, sizeof cf);
    m->cell_offsets[0] = 0;
    m->cell_offsets[1] = 6;
    m->cell_offsets[2] = 12;
    m->cell_seed = malloc(sizeof(int64_t) * 2);
    m->cell_seed[0] = 0;
    m->cell_seed[1] = 1;
    m->cell_region = malloc(sizeof(int32_t) * 2);
    m->cell_region[0] = m->cell_region[1] = 1;
    m->cell_volume = malloc(sizeof(double) * 2);
    m->cell_centroid = malloc(sizeof(double) * 6);
    vc_polymesh_compute_geometry(m);
}

static void test_two_cubes(void)
{
    vc_polymesh m;
    char report[1024];
    two_cubes(&m, 1);
    CHECK(vc_polymesh_validate(&m, 0, report, sizeof report) == 0);
    CHECK(vc_polymesh_face_size(&m, 0) == 5);
    CHECK(vc_polymesh_remove_straight_vertices(&m, 2) == 1);
    CHECK(m.n_points == 12);
    for (int64_t f = 0; f < m.n_faces; f++)
        CHECK(vc_polymesh_face_size(&m, f) == 4);
    for (int64_t i = 0; i < m.face_offsets[m.n_faces]; i++)
        CHECK(m.face_vertices[i] >= 0 && m.face_vertices[i] < 12);
    int64_t bad = vc_polymesh_validate(&m, 0, report, sizeof report);
    CHECK(bad == 0);
    if (bad)
        fprintf(stderr, "%s", report);
    CHECK(fabs(m.cell_volume[0] - 1) < 1e-14 && fabs(m.cell_volume[1] - 1) < 1e-14);
    CHECK(fabs(m.face_area[0] - 1) < 1e-14);
    CHECK(fabs(m.face_centroid[1] - 0.5) < 1e-14 && fabs(m.face_centroid[2] - 0.5) < 1e-14);
    /* the corners keep their coordinates */
    CHECK(m.points[3 * block_corner(2, 1, 1)] == 2 && m.points[3 * block_corner(2, 1, 1) + 2] == 1);
    /* a second pass finds nothing */
    CHECK(vc_polymesh_remove_straight_vertices(&m, 2) == 0);
    vc_polymesh_free(&m);

    two_cubes(&m, 0);
    double before[3 * 12];
    memcpy(before, m.points, sizeof before);
    CHECK(vc_polymesh_remove_straight_vertices(&m, 2) == 0);
    CHECK(m.n_points == 12 && memcmp(before, m.points, sizeof before) == 0);
    vc_polymesh_free(&m);
}

/* A zero-area triangle (0,0,0) (0.5,0,0) (1,0,0) inside a larger fake
 * "mesh": the middle point has two neighbours but removing it would leave
 * two vertices, so it stays. Only the topology matters here. */
static void test_degenerate_face_kept(void)
{
    vc_polymesh m;
    memset(&m, 0, sizeof m);
    m.n_points = 3;
    m.points = calloc(9, sizeof(double));
    m.points[3] = 0.5;
    m.points[6] = 1;
    m.n_faces = 1;
    m.face_offsets = malloc(sizeof(int64_t) * 2);
    m.face_offsets[0] = 0;
    m.face_offsets[1] = 3;
    m.face_vertices = malloc(sizeof(int64_t) * 3);
    for (int i = 0; i < 3; i++)
        m.face_vertices[i] = i;
    m.face_owner = calloc(1, sizeof(int64_t));
    m.face_neighbour = malloc(sizeof(int64_t));
    m.face_neighbour[0] = -1;
    m.face_area = calloc(1, sizeof(double));
    m.face_centroid = calloc(3, sizeof(double));
    m.face_normal = calloc(3, sizeof(double));
    m.n_cells = 1;
    m.cell_offsets = calloc(2, sizeof(int64_t));
    m.cell_offsets[1] = 1;
    m.cell_faces = calloc(1, sizeof(int64_t));
    m.cell_volume = calloc(1, sizeof(double));
    m.cell_centroid = calloc(3, sizeof(double));
    CHECK(vc_polymesh_remove_straight_vertices(&m, 2) == 0);
    CHECK(m.n_points == 3 && vc_polymesh_face_size(&m, 0) == 3);
    vc_polymesh_free(&m);
}

/* The number of points with exactly two distinct neighbours. */
static int64_t count_straight(const vc_polymesh *m)
{
    int64_t *nb = malloc(sizeof(int64_t) * 2 * (size_t)m->n_points);
    unsigned char *many = calloc((size_t)m->n_points, 1);
    for (int64_t i = 0; i < 2 * m->n_points; i++)
        nb[i] = -1;
    for (int64_t f = 0; f < m->n_faces; f++) {
        int64_t b = m->face_offsets[f], n = vc_polymesh_face_size(m, f);
        for (int64_t i = 0; i < n; i++) {
            int64_t v = m->face_vertices[b + i];
            int64_t ab[2] = {m->face_vertices[b + (i + n - 1) % n], m->face_vertices[b + (i + 1) % n]};
            for (int j = 0; j < 2; j++) {
                if (nb[2 * v] < 0 || nb[2 * v] == ab[j])
                    nb[2 * v] = ab[j];
                else if (nb[2 * v + 1] < 0 || nb[2 * v + 1] == ab[j])
                    nb[2 * v + 1] = ab[j];
                else
                    many[v] = 1;
            }
        }
    }
    int64_t straight = 0;
    for (int64_t v = 0; v < m->n_points; v++)
        straight += !many[v];
    free(nb);
    free(many);
    return straight;
}

/* 2000 VoroCrust surface seeds of torus.obj (default parameters, the
 * neighbourhood of a point where four seeds on one circle, rounded, have
 * their circumcentre on the circle's axis: a true vertex of the rounded
 * seeds, inside a Voronoi edge, which the engine used to output as a
 * straight vertex). The engine's mesh: valid, no straight vertex, the same
 * with 1 and 2 threads. */
static void test_engine_vorocrust_seeds(void)
{
    const char *path = VC_TEST_DATA "/torus-straight-2000.csv";
    vc_seeds s;
    vc_error err = {0, ""};
    if (vc_seeds_read_csv(path, &s, &err) != 0) {
        fprintf(stderr, "%s: %s\n", path, err.msg);
        CHECK(0);
        return;
    }
    CHECK(s.n == 2000);
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    vc_polymesh m[2];
    for (int t = 0; t < 2; t++) {
        opt.threads = t + 1;
        CHECK(vc_voronoi_build(&s, &opt, &m[t], &err) == 0);
    }
    char report[1024];
    int64_t bad = vc_polymesh_validate(&m[0], 0, report, sizeof report);
    CHECK(bad == 0);
    if (bad)
        fprintf(stderr, "%s", report);
    CHECK(count_straight(&m[0]) == 0);
    CHECK(m[0].n_points == m[1].n_points && m[0].n_faces == m[1].n_faces &&
          memcmp(m[0].points, m[1].points, sizeof(double) * 3 * (size_t)m[0].n_points) == 0 &&
          memcmp(m[0].face_vertices, m[1].face_vertices,
                 sizeof(int64_t) * (size_t)m[0].face_offsets[m[0].n_faces]) == 0);
    vc_polymesh_free(&m[0]);
    vc_polymesh_free(&m[1]);
    vc_seeds_free(&s);
}

int main(void)
{
    test_two_cubes();
    test_degenerate_face_kept();
    test_engine_vorocrust_seeds();
    if (failures) {
        fprintf(stderr, "%d check(s) failed\n", failures);
        return 1;
    }
    printf("test_straight_vertices: all checks passed\n");
    return 0;
}
