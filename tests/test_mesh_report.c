/* Tests of the whole-mesh report (vc_mesh_report_compute) on a mesh with
 * known answers: two regular tetrahedra sharing a face (the second the
 * mirror image of the first), laid out as the .vtu reader lays them out.
 * Fatness 3, equilateral boundary triangles, dihedral angles acos(1/3),
 * 7 distinct faces of which 6 on the boundary, volume 2 x 8/3; the Hausdorff
 * distance to its own boundary is 0; a cell listed inward is counted and
 * measured the same; a cell missing a face is counted open. */
#include "vorocrust/mesh_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"

/* The regular tetrahedron (1,1,1), (1,-1,-1), (-1,1,-1), (-1,-1,1) and the
 * mirror image of its first corner across the opposite face. */
static double points[5][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1},
                              {-5.0 / 3, -5.0 / 3, -5.0 / 3}};

/* Storage for a mesh of up to 2 tetrahedra. */
typedef struct two_tets {
    uint8_t type[2];
    int64_t file_index[2], cell_faces[3], face_offsets[9], face_vertices[24];
    vc_vtu_mesh m;
} two_tets;

static double orientation(const int64_t t[4])
{
    double a[3], b[3], c[3];
    for (int d = 0; d < 3; d++) {
        a[d] = points[t[1]][d] - points[t[0]][d];
        b[d] = points[t[2]][d] - points[t[0]][d];
        c[d] = points[t[3]][d] - points[t[0]][d];
    }
    return (a[1] * b[2] - a[2] * b[1]) * c[0] + (a[2] * b[0] - a[0] * b[2]) * c[1] +
           (a[0] * b[1] - a[1] * b[0]) * c[2];
}

/* Tetrahedra a = (0,1,2,3) and b = (4,1,2,3) reordered to be positive,
 * with the reader's faces (1,2,3), (0,3,2), (0,1,3), (0,2,1); inward_b
 * reverses every face of b, drop_b_face leaves b's last face out. */
static void build(two_tets *s, int inward_b, int drop_b_face)
{
    int64_t tets[2][4] = {{0, 1, 2, 3}, {4, 1, 2, 3}};
    static const int corner[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    int64_t nf = 0, nv = 0;
    memset(s, 0, sizeof *s);
    for (int c = 0; c < 2; c++) {
        if (orientation(tets[c]) < 0) {
            int64_t t = tets[c][2];
            tets[c][2] = tets[c][3];
            tets[c][3] = t;
        }
        s->type[c] = VC_VTK_TETRA;
        s->file_index[c] = c;
        s->cell_faces[c] = nf;
        int n_faces = c == 1 && drop_b_face ? 3 : 4;
        for (int f = 0; f < n_faces; f++) {
            s->face_offsets[nf++] = nv;
            for (int k = 0; k < 3; k++)
                s->face_vertices[nv++] = tets[c][corner[f][c == 1 && inward_b ? 2 - k : k]];
        }
    }
    s->cell_faces[2] = nf;
    s->face_offsets[nf] = nv;
    s->m.n_points = 5;
    s->m.points = &points[0][0];
    s->m.n_cells = 2;
    s->m.cell_type = s->type;
    s->m.cell_file_index = s->file_index;
    s->m.cell_faces = s->cell_faces;
    s->m.n_faces = nf;
    s->m.face_offsets = s->face_offsets;
    s->m.face_vertices = s->face_vertices;
    s->m.n_file_cells = 2;
    s->m.first_skipped_type = -1;
}

static void test_two_regular_tetrahedra(void)
{
    two_tets s;
    build(&s, 0, 0);
    vc_mesh_report r;
    vc_error err = {0, ""};
    CHECK(vc_mesh_report_compute(&s.m, "two.vtu", NULL, NULL, &r, &err) == 0);
    CHECK(r.n_cells == 2 && r.n_tetrahedra == 2 && r.n_points == 5);
    CHECK(r.n_faces == 7 && r.n_boundary_faces == 6 && r.n_faces_shared_more == 0);
    CHECK(r.n_open_cells == 0 && r.first_open_cell == -1 && r.n_inverted_cells == 0);
    CHECK(r.n_unmeasured_cells == 0 && r.first_unmeasured_cell == -1);
    CHECK_NEAR(r.total_volume, 16.0 / 3, 1e-12);
    CHECK(r.volume.n == 2);
    CHECK_NEAR(r.volume.min, 8.0 / 3, 1e-12);
    CHECK_NEAR(r.fatness.min, 3, 1e-9);
    CHECK_NEAR(r.fatness.max, 3, 1e-9);
    CHECK_NEAR(r.cell_fatness[0], 3, 1e-9);
    CHECK_NEAR(r.cell_fatness[1], 3, 1e-9);
    /* shortest edge 2 sqrt 2 over the circumradius sqrt 3 */
    CHECK_NEAR(r.shortest_edge_rel.max, 2 * sqrt(2.0) / sqrt(3.0), 1e-9);
    double dihedral = acos(1.0 / 3) * 180 / acos(-1.0);
    CHECK_NEAR(r.dihedral_min.min, dihedral, 1e-9);
    CHECK_NEAR(r.dihedral_max.max, dihedral, 1e-9);
    CHECK(r.n_boundary_triangles == 6 && r.triangle_quality.n == 6);
    CHECK_NEAR(r.triangle_quality.min, 1, 1e-12);
    CHECK_NEAR(r.triangle_qualities[5], 1, 1e-12);
    CHECK(r.angles_below_30 == 0 && r.angles_above_90 == 0);
    CHECK(!r.has_hausdorff);
    vc_mesh_report_free(&r);
    CHECK(r.cell_fatness == NULL && r.triangle_qualities == NULL);
}

/* The Hausdorff distance from the mesh's boundary to the same triangles. */
static void test_hausdorff_to_own_boundary(void)
{
    two_tets s;
    build(&s, 0, 0);
    int64_t tri[18];
    int n = 0;
    for (int f = 0; f < 8; f++) {
        if (f == 0 || f == 4)
            continue; /* the shared face: (1,2,3) listed first by both cells */
        for (int k = 0; k < 3; k++)
            tri[3 * n + k] = s.face_vertices[s.face_offsets[f] + k];
        n++;
    }
    vc_surface input = {5, &points[0][0], 6, tri, NULL, 0, NULL};
    vc_mesh_report r;
    vc_error err = {0, ""};
    CHECK(n == 6);
    CHECK(vc_mesh_report_compute(&s.m, "two.vtu", &input, "two.obj", &r, &err) == 0);
    CHECK(r.has_hausdorff);
    CHECK(r.hausdorff.distance <= 1e-12);
    CHECK(r.hausdorff.n_samples_a > 0 && r.hausdorff.n_samples_b > 0);
    vc_mesh_report_free(&r);
}

static void test_inward_and_open_cells(void)
{
    two_tets s;
    vc_mesh_report r;
    vc_error err = {0, ""};
    build(&s, 1, 0);
    CHECK(vc_mesh_report_compute(&s.m, "inward.vtu", NULL, NULL, &r, &err) == 0);
    CHECK(r.n_inverted_cells == 1 && r.n_open_cells == 0);
    CHECK_NEAR(r.total_volume, 16.0 / 3, 1e-12);
    CHECK_NEAR(r.fatness.max, 3, 1e-9);
    vc_mesh_report_free(&r);

    build(&s, 0, 1);
    CHECK(vc_mesh_report_compute(&s.m, "open.vtu", NULL, NULL, &r, &err) == 0);
    CHECK(r.n_open_cells == 1 && r.first_open_cell == 1);
    CHECK(r.n_faces == 6 && r.n_boundary_faces == 5);
    vc_mesh_report_free(&r);
}

int main(void)
{
    test_two_regular_tetrahedra();
    test_hausdorff_to_own_boundary();
    test_inward_and_open_cells();
    if (failures) {
        fprintf(stderr, "test_mesh_report: %d failures\n", failures);
        return 1;
    }
    printf("test_mesh_report: all checks passed\n");
    return 0;
}
