/* Tests of the passes that repair what nearly co-spherical seeds leave in a
 * stitched mesh, on meshes built by hand:
 *   - vc_polymesh_collapse_open_clusters: two unit cubes side by side where
 *     the second cube's bottom and front faces use their own copy of a
 *     corner of the common face, 1e-9 away from it (the cell is open
 *     there): the copy is merged into the corner, the mesh validates and
 *     the volumes are 1; the same copy 1e-3 away is beyond the radius and
 *     nothing changes; a closed mesh is left alone;
 *   - vc_polymesh_drop_duplicate_faces: two tetrahedra A and C sharing a
 *     triangle T, and a third one B elsewhere, with A listing T a second
 *     time as a face towards B (the pattern three cells collapsed onto one
 *     triangle leave): that copy goes, the mesh validates, each volume is
 *     1/6; a valid mesh is left alone. */
#include "vorocrust/polymesh.h"
#include "polymesh/repair.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"
#include "test_cube_block.h"

/* A mesh under construction: faces (owner, neighbour, points) and which
 * cells list them. */
typedef struct builder {
    int64_t fv[128];
    int64_t off[32];
    int64_t owner[32], nbr[32];
    int nf, nfv;
    int64_t cell_list[8][16];
    int cell_n[8];
} builder;

static void add_face(builder *b, const int64_t *v, int n, int64_t owner, int64_t nbr)
{
    b->off[b->nf] = b->nfv;
    for (int i = 0; i < n; i++)
        b->fv[b->nfv++] = v[i];
    b->owner[b->nf] = owner;
    b->nbr[b->nf] = nbr;
    b->cell_list[owner][b->cell_n[owner]++] = b->nf;
    if (nbr >= 0)
        b->cell_list[nbr][b->cell_n[nbr]++] = b->nf;
    b->nf++;
    b->off[b->nf] = b->nfv;
}

/* The mesh of b with the given points and cells (interior faces must come
 * first, n_interior of them); geometry computed. */
static void build(vc_polymesh *m, const builder *b, const double *pts, int64_t n_points,
                  int64_t n_cells, int64_t n_interior)
{
    memset(m, 0, sizeof *m);
    m->n_points = n_points;
    m->points = malloc(sizeof(double) * 3 * (size_t)n_points);
    memcpy(m->points, pts, sizeof(double) * 3 * (size_t)n_points);
    m->n_faces = b->nf;
    m->n_interior_faces = n_interior;
    m->face_offsets = malloc(sizeof(int64_t) * (size_t)(b->nf + 1));
    memcpy(m->face_offsets, b->off, sizeof(int64_t) * (size_t)(b->nf + 1));
    m->face_vertices = malloc(sizeof(int64_t) * (size_t)b->nfv);
    memcpy(m->face_vertices, b->fv, sizeof(int64_t) * (size_t)b->nfv);
    m->face_owner = malloc(sizeof(int64_t) * (size_t)b->nf);
    m->face_neighbour = malloc(sizeof(int64_t) * (size_t)b->nf);
    m->face_other_seed = malloc(sizeof(int64_t) * (size_t)b->nf);
    for (int f = 0; f < b->nf; f++) {
        m->face_owner[f] = b->owner[f];
        m->face_neighbour[f] = b->nbr[f];
        m->face_other_seed[f] = b->nbr[f] >= 0 ? b->nbr[f] : n_cells;
    }
    m->face_area = malloc(sizeof(double) * (size_t)b->nf);
    m->face_centroid = malloc(sizeof(double) * 3 * (size_t)b->nf);
    m->face_normal = malloc(sizeof(double) * 3 * (size_t)b->nf);
    m->n_cells = n_cells;
    m->cell_offsets = malloc(sizeof(int64_t) * (size_t)(n_cells + 1));
    int64_t total = 0;
    for (int64_t c = 0; c < n_cells; c++)
        total += b->cell_n[c];
    m->cell_faces = malloc(sizeof(int64_t) * (size_t)total);
    m->cell_offsets[0] = 0;
    for (int64_t c = 0; c < n_cells; c++) {
        /* in increasing face index, as the engine lists them */
        int64_t *l = m->cell_faces + m->cell_offsets[c];
        for (int i = 0; i < b->cell_n[c]; i++) {
            int64_t x = b->cell_list[c][i];
            int j = i;
            for (; j > 0 && l[j - 1] > x; j--)
                l[j] = l[j - 1];
            l[j] = x;
        }
        m->cell_offsets[c + 1] = m->cell_offsets[c] + b->cell_n[c];
    }
    m->cell_seed = malloc(sizeof(int64_t) * (size_t)n_cells);
    m->cell_region = malloc(sizeof(int32_t) * (size_t)n_cells);
    for (int64_t c = 0; c < n_cells; c++) {
        m->cell_seed[c] = c;
        m->cell_region[c] = 1;
    }
    m->cell_volume = malloc(sizeof(double) * (size_t)n_cells);
    m->cell_centroid = malloc(sizeof(double) * 3 * (size_t)n_cells);
    vc_polymesh_compute_geometry(m);
}

static int64_t validate(const vc_polymesh *m, int print)
{
    char report[2048];
    int64_t bad = vc_polymesh_validate(m, 0, report, sizeof report);
    if (bad && print)
        fprintf(stderr, "%s", report);
    return bad;
}


/* Two unit cubes side by side; the second cube's y = 0 and z = 0 faces use
 * point 12, at corner (1,0,0) + (0, gap, 0), instead of that corner (gap
 * 0: the plain mesh, without point 12). */
static void two_cubes(vc_polymesh *m, double gap)
{
    builder b;
    memset(&b, 0, sizeof b);
    const int64_t moved = block_corner(1, 0, 0), copy = gap > 0 ? 12 : moved;
    for (int c = 0; c < 2; c++) {
        int64_t f[6][4];
        block_cube_faces(c, f);
        int64_t *xlo = f[0], *xhi = f[1], *ylo = f[2], *yhi = f[3], *zlo = f[4], *zhi = f[5];
        if (c == 1)
            for (int i = 0; i < 4; i++) {
                ylo[i] = ylo[i] == moved ? copy : ylo[i];
                zlo[i] = zlo[i] == moved ? copy : zlo[i];
            }
        if (c == 0) {
            add_face(&b, xhi, 4, 0, 1); /* the common face: interior, first */
            add_face(&b, xlo, 4, 0, -1);
        } else {
            add_face(&b, xhi, 4, 1, -1);
        }
        add_face(&b, ylo, 4, c, -1);
        add_face(&b, yhi, 4, c, -1);
        add_face(&b, zlo, 4, c, -1);
        add_face(&b, zhi, 4, c, -1);
    }
    double pts[3 * 13];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++)
            for (int k = 0; k < 2; k++) {
                double *p = pts + 3 * block_corner(i, j, k);
                p[0] = i;
                p[1] = j;
                p[2] = k;
            }
    pts[36] = 1;
    pts[37] = gap;
    pts[38] = 0;
    build(m, &b, pts, gap > 0 ? 13 : 12, 2, 1);
}

static void test_open_cluster(void)
{
    vc_polymesh m;
    two_cubes(&m, 1e-9);
    CHECK(validate(&m, 0) > 0); /* the second cube is open at point 12 */
    CHECK(vc_polymesh_collapse_open_clusters(&m, 1e-7, 2) == 1);
    CHECK(m.n_points == 12);
    CHECK(validate(&m, 1) == 0);
    CHECK(fabs(m.cell_volume[0] - 1) < 1e-14 && fabs(m.cell_volume[1] - 1) < 1e-14);
    for (int64_t i = 0; i < m.face_offsets[m.n_faces]; i++)
        CHECK(m.face_vertices[i] >= 0 && m.face_vertices[i] < 12);
    /* the corner kept its position (the lower index is kept) */
    CHECK(m.points[3 * block_corner(1, 0, 0) + 1] == 0);
    CHECK(vc_polymesh_collapse_open_clusters(&m, 1e-7, 2) == 0);
    vc_polymesh_free(&m);

    /* A copy 1e-3 away is not a cluster at 1e-7 of the cell size. */
    two_cubes(&m, 1e-3);
    CHECK(vc_polymesh_collapse_open_clusters(&m, 1e-7, 2) == 0);
    CHECK(m.n_points == 13 && validate(&m, 0) > 0);
    vc_polymesh_free(&m);

    /* A closed mesh is left alone. */
    two_cubes(&m, 0);
    double before[3 * 12];
    memcpy(before, m.points, sizeof before);
    CHECK(vc_polymesh_collapse_open_clusters(&m, 1e-7, 2) == 0);
    CHECK(m.n_points == 12 && memcmp(before, m.points, sizeof before) == 0);
    vc_polymesh_free(&m);
}

/* Tetrahedra A (cell 0, apex above T), C (cell 2, apex below T) sharing
 * the triangle T in z = 0, and B (cell 1) 10 away along x. With
 * duplicate, A also lists T as a face towards B. */
static void three_tets(vc_polymesh *m, int duplicate)
{
    const double pts[3 * 9] = {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,  0, 0, -1,
                               10, 0, 0, 11, 0, 0, 10, 1, 0, 10, 0, 1};
    builder b;
    memset(&b, 0, sizeof b);
    const int64_t t[3] = {0, 2, 1}; /* outward from A: -z */
    if (duplicate)
        add_face(&b, t, 3, 0, 1);
    add_face(&b, t, 3, 0, 2);
    const int64_t a0[3] = {0, 1, 3}, a1[3] = {1, 2, 3}, a2[3] = {2, 0, 3};
    add_face(&b, a0, 3, 0, -1);
    add_face(&b, a1, 3, 0, -1);
    add_face(&b, a2, 3, 0, -1);
    const int64_t b0[3] = {5, 7, 6}, b1[3] = {5, 6, 8}, b2[3] = {6, 7, 8}, b3[3] = {7, 5, 8};
    add_face(&b, b0, 3, 1, -1);
    add_face(&b, b1, 3, 1, -1);
    add_face(&b, b2, 3, 1, -1);
    add_face(&b, b3, 3, 1, -1);
    const int64_t c0[3] = {0, 4, 1}, c1[3] = {1, 4, 2}, c2[3] = {2, 4, 0};
    add_face(&b, c0, 3, 2, -1);
    add_face(&b, c1, 3, 2, -1);
    add_face(&b, c2, 3, 2, -1);
    build(m, &b, pts, 9, 3, duplicate ? 2 : 1);
}

static void test_duplicate_face(void)
{
    vc_polymesh m;
    three_tets(&m, 1);
    CHECK(validate(&m, 0) > 0); /* A uses T's edges twice one way */
    const int64_t nf = m.n_faces;
    CHECK(vc_polymesh_drop_duplicate_faces(&m, 2) == 1);
    CHECK(m.n_faces == nf - 1 && m.n_interior_faces == 1);
    CHECK(validate(&m, 1) == 0);
    for (int c = 0; c < 3; c++)
        CHECK(fabs(m.cell_volume[c] - 1.0 / 6.0) < 1e-14);
    /* T is left between A and C; B has its four faces. */
    CHECK(m.face_owner[0] == 0 && m.face_neighbour[0] == 2);
    CHECK(m.cell_offsets[2] - m.cell_offsets[1] == 4);
    CHECK(m.n_points == 9);
    CHECK(vc_polymesh_drop_duplicate_faces(&m, 2) == 0);
    vc_polymesh_free(&m);

    three_tets(&m, 0);
    CHECK(validate(&m, 1) == 0);
    CHECK(vc_polymesh_drop_duplicate_faces(&m, 2) == 0);
    CHECK(m.n_faces == 11);
    vc_polymesh_free(&m);
}

int main(void)
{
    test_open_cluster();
    test_duplicate_face();
    if (failures) {
        fprintf(stderr, "%d check(s) failed\n", failures);
        return 1;
    }
    printf("test_degenerate_repair: all checks passed\n");
    return 0;
}
