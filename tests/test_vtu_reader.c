/* Tests of the .vtu reader (vorocrust/io/vtu_reader.c):
 *   - files written by our own writer (raw and zlib) read back to exactly
 *     the mesh written: points, every cell's faces outward in order, and
 *     each cell's seed (seed_point);
 *   - a hand-written ascii file in the VTK 9.4 polyhedron layout, with a
 *     tetrahedron and a skipped hexahedron, with and without seed_point
 *     (its values mapped to the kept cells; wrong components, counts and
 *     non-finite values refused);
 *   - malformed files: one error line naming the file;
 *   - mutation fuzzing (flipped bytes, truncation) of small raw, zlib and
 *     base64 files: every outcome is a clean success or a clean error (the
 *     sanitizer build catches any out-of-bounds access), and the cell
 *     measures of every damaged file that still reads run cleanly too. */
#include "vorocrust/io.h"
#include "vorocrust/quality.h"
#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"
#include "vorocrust/vtu_reader.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"
#include "test_file_util.h"

static const char *tmpdir = ".";

static char *tmp_path(const char *name)
{
    size_t n = strlen(tmpdir) + strlen(name) + 2;
    char *p = malloc(n);
    snprintf(p, n, "%s/%s", tmpdir, name);
    return p;
}

static void write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f)
        return;
    CHECK(fwrite(data, 1, n, f) == n);
    fclose(f);
}

/* The error must be one line starting with "PATH: ". */
static void check_error_line(const vc_error *err, const char *path)
{
    size_t n = strlen(path);
    CHECK(strncmp(err->msg, path, n) == 0 && err->msg[n] == ':' && err->msg[n + 1] == ' ');
    CHECK(strchr(err->msg, '\n') == NULL);
}

static void test_own_writer(void)
{
    vc_seeds seeds;
    vc_error err;
    int n = 40;
    CHECK(vc_seeds_alloc(&seeds, n, &err) == 0);
    vc_rng rng;
    vc_rng_init(&rng, 99, 0);
    for (int i = 0; i < 3 * n; i++)
        seeds.xyz[i] = vc_rng_uniform(&rng);
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    vc_polymesh mesh;
    memset(&mesh, 0, sizeof mesh);
    CHECK(vc_voronoi_build(&seeds, &opt, &mesh, &err) == 0);
    const vc_vtu_encoding encs[2] = {VC_VTU_RAW, VC_VTU_ZLIB};
    for (int e = 0; e < 2; e++) {
        char *p = tmp_path(e ? "vtu_reader_own_zlib.vtu" : "vtu_reader_own_raw.vtu");
        CHECK(vc_write_vtu(&mesh, p, encs[e], &err) == 0);
        vc_vtu_mesh m;
        int rc = vc_vtu_read(p, &m, &err);
        CHECK(rc == 0);
        if (rc) {
            fprintf(stderr, "%s\n", err.msg);
            free(p);
            continue;
        }
        CHECK(m.n_points == mesh.n_points);
        CHECK(memcmp(m.points, mesh.points, sizeof(double) * 3 * (size_t)mesh.n_points) == 0);
        CHECK(m.n_cells == mesh.n_cells && m.n_file_cells == mesh.n_cells && m.n_skipped == 0);
        int same = 1;
        for (int64_t c = 0; c < mesh.n_cells && same; c++) {
            same = m.cell_type[c] == VC_VTK_POLYHEDRON && m.cell_file_index[c] == c &&
                   m.cell_faces[c + 1] - m.cell_faces[c] == mesh.cell_offsets[c + 1] - mesh.cell_offsets[c];
            for (int64_t k = 0; same && k < mesh.cell_offsets[c + 1] - mesh.cell_offsets[c]; k++) {
                int64_t f = mesh.cell_faces[mesh.cell_offsets[c] + k], g = m.cell_faces[c] + k;
                int64_t b = mesh.face_offsets[f], len = mesh.face_offsets[f + 1] - b;
                same = m.face_offsets[g + 1] - m.face_offsets[g] == len;
                for (int64_t i = 0; same && i < len; i++) {
                    int64_t want = mesh.face_owner[f] == c ? mesh.face_vertices[b + i]
                                                           : mesh.face_vertices[b + len - 1 - i];
                    same = m.face_vertices[m.face_offsets[g] + i] == want;
                }
            }
        }
        CHECK(same);
        /* each cell's seed, exactly */
        CHECK(m.cell_seed_point != NULL);
        for (int64_t c = 0; m.cell_seed_point && c < mesh.n_cells; c++)
            CHECK(memcmp(m.cell_seed_point + 3 * c, seeds.xyz + 3 * mesh.cell_seed[c],
                         sizeof(double) * 3) == 0);
        vc_vtu_mesh_free(&m);
        free(p);
    }
    vc_polymesh_free(&mesh);
    vc_seeds_free(&seeds);
}

/* A unit cube (polyhedron, VTK 9.4 layout), a tetrahedron and a hexahedron. */
static const char vtk94[] =
    "<?xml version=\"1.0\"?>\n"
    "<!-- written by hand -->\n"
    "<VTKFile type=\"UnstructuredGrid\" version=\"2.3\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
    "<UnstructuredGrid><Piece NumberOfPoints=\"9\" NumberOfCells=\"3\">\n"
    "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n"
    "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1 2 0 0</DataArray></Points>\n"
    "<Cells>\n"
    "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 4 5 6 7 1 8 2 5 0 1 2 3 4 5 6 7</DataArray>\n"
    "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">8 12 20</DataArray>\n"
    "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">42 10 12</DataArray>\n"
    "<DataArray type=\"Int32\" Name=\"face_connectivity\" format=\"ascii\">"
    "0 3 2 1 4 5 6 7 0 1 5 4 2 3 7 6 1 2 6 5 0 4 7 3</DataArray>\n"
    "<DataArray type=\"Int32\" Name=\"face_offsets\" format=\"ascii\">0 4 8 12 16 20 24</DataArray>\n"
    "<DataArray type=\"Int32\" Name=\"polyhedron_to_faces\" format=\"ascii\">0 1 2 3 4 5</DataArray>\n"
    "<DataArray type=\"Int32\" Name=\"polyhedron_offsets\" format=\"ascii\">0 6 6 6</DataArray>\n"
    "</Cells></Piece></UnstructuredGrid></VTKFile>\n";

static void test_vtk94_layout(void)
{
    char *p = tmp_path("vtu_reader_vtk94.vtu");
    write_file(p, vtk94, sizeof vtk94 - 1);
    vc_vtu_mesh m;
    vc_error err;
    int rc = vc_vtu_read(p, &m, &err);
    CHECK(rc == 0);
    if (rc == 0) {
        CHECK(m.n_points == 9 && m.n_cells == 2 && m.n_file_cells == 3);
        CHECK(m.n_skipped == 1 && m.first_skipped_type == 12);
        CHECK(m.cell_type[0] == VC_VTK_POLYHEDRON && m.cell_type[1] == VC_VTK_TETRA);
        CHECK(m.cell_file_index[0] == 0 && m.cell_file_index[1] == 1);
        CHECK(m.cell_faces[0] == 0 && m.cell_faces[1] == 6 && m.cell_faces[2] == 10);
        CHECK(m.n_faces == 10 && m.face_offsets[10] == 24 + 12);
        /* the tetrahedron (1, 8, 2, 5): faces (8,2,5), (1,5,2), (1,8,5), (1,2,8) */
        const int64_t tet[12] = {8, 2, 5, 1, 5, 2, 1, 8, 5, 1, 2, 8};
        CHECK(memcmp(m.face_vertices + 24, tet, sizeof tet) == 0);
        CHECK(m.points[3 * 8] == 2.0 && m.points[3 * 6 + 2] == 1.0);
        vc_vtu_mesh_free(&m);
    } else {
        fprintf(stderr, "%s\n", err.msg);
    }
    free(p);
}

/* vtk94 with a CellData block holding seed_point's DataArray (its
 * components and values as given), and a scalar array before it, which the
 * reader skips. */
static char *with_seed_points(const char *ncomp, const char *values)
{
    char block[512];
    snprintf(block, sizeof block,
             "<CellData><DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">1 1 1"
             "</DataArray><DataArray type=\"Float64\" Name=\"seed_point\" NumberOfComponents="
             "\"%s\" format=\"ascii\">%s</DataArray></CellData><Points>", ncomp, values);
    const char *at = strstr(vtk94, "<Points>");
    size_t n = sizeof vtk94 + strlen(block);
    char *s = malloc(n);
    snprintf(s, n, "%.*s%s%s", (int)(at - vtk94), vtk94, block, at + strlen("<Points>"));
    return s;
}

static void test_seed_points(void)
{
    char *text = with_seed_points("3", "0.5 0.5 0.5 1 0 0 9 9 9");
    char *p = tmp_path("vtu_reader_seed_points.vtu");
    write_file(p, text, strlen(text));
    vc_vtu_mesh m;
    vc_error err;
    int rc = vc_vtu_read(p, &m, &err);
    CHECK(rc == 0);
    if (rc == 0) {
        /* the kept cells: the cube (file cell 0) and the tetrahedron (1) */
        const double want[6] = {0.5, 0.5, 0.5, 1, 0, 0};
        CHECK(m.cell_seed_point && memcmp(m.cell_seed_point, want, sizeof want) == 0);
        vc_vtu_mesh_free(&m);
    }
    free(text);
    free(p);
    /* the file without: NULL */
    p = tmp_path("vtu_reader_no_seed_points.vtu");
    write_file(p, vtk94, sizeof vtk94 - 1);
    if (vc_vtu_read(p, &m, &err) == 0) {
        CHECK(m.cell_seed_point == NULL);
        vc_vtu_mesh_free(&m);
    }
    free(p);
}

static void expect_error(const char *name, const char *text, int code, const char *needle)
{
    char *p = tmp_path(name);
    write_file(p, text, strlen(text));
    vc_vtu_mesh m;
    vc_error err;
    int rc = vc_vtu_read(p, &m, &err);
    if (rc != code) {
        fprintf(stderr, "%s: code %d, expected %d (%s)\n", name, rc, code, rc ? err.msg : "");
        failures++;
    }
    if (rc) {
        check_error_line(&err, p);
        if (!strstr(err.msg, needle)) {
            fprintf(stderr, "%s: message '%s' lacks '%s'\n", name, err.msg, needle);
            failures++;
        }
    } else {
        vc_vtu_mesh_free(&m);
    }
    CHECK(m.n_cells == 0 && m.points == NULL); /* zeroed on failure */
    free(p);
}

/* vtk94 with one substring replaced. */
static char *variant(const char *from, const char *to)
{
    const char *at = strstr(vtk94, from);
    size_t n = sizeof vtk94 + strlen(to);
    char *s = malloc(n);
    if (!at) {
        snprintf(s, n, "%s", vtk94);
        return s;
    }
    snprintf(s, n, "%.*s%s%s", (int)(at - vtk94), vtk94, to, at + strlen(from));
    return s;
}

static void test_errors(void)
{
    static const struct { const char *from, *to, *needle; int code; } cases[] = {
        {"type=\"UnstructuredGrid\"", "type=\"PolyData\"", "not an UnstructuredGrid", VC_EFORMAT},
        {"header_type=\"UInt64\"", "header_type=\"UInt16\"", "header_type 'UInt16'", VC_EFORMAT},
        {"NumberOfCells=\"3\"", "NumberOfCells=\"x\"", "NumberOfCells", VC_EFORMAT},
        {"NumberOfCells=\"3\"", "NumberOfCells=\"4\"", "4 cells but 3 offsets", VC_EFORMAT},
        {"NumberOfPoints=\"9\"", "NumberOfPoints=\"8\"", "expected 3 x 8", VC_EFORMAT},
        {"0 1 5 4 2 3", "0 1 5 4 2 9", "point 9 out of range", VC_EFORMAT},
        {"8 12 20", "8 7 20", "out of order", VC_EFORMAT},
        {"42 10 12", "12 12 12", "no polyhedron or tetrahedron", VC_EINPUT},
        {"1 0 1 1 1 1", "1 0 1 1 nan 1", "non-finite", VC_EFORMAT},
        {"0 4 8 12", "0 4 8 99", "face_offsets", VC_EFORMAT},
        {"0 6 6 6", "0 6 6", "polyhedron_offsets", VC_EFORMAT},
        {"format=\"ascii\">0 1 2 3 4", "format=\"fancy\">0 1 2 3 4", "unknown format 'fancy'", VC_EFORMAT},
        {"format=\"ascii\">8 12 20</DataArray>", "format=\"appended\" offset=\"0\"/>",
         "no AppendedData", VC_EFORMAT},
        {"type=\"Int32\" Name=\"offsets\"", "type=\"Float32\" Name=\"offsets\"", "where integers", VC_EFORMAT},
        {"type=\"Int32\" Name=\"offsets\"", "type=\"Int31\" Name=\"offsets\"", "unsupported type 'Int31'", VC_EFORMAT},
        {"<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\"",
         "<Points><DataArray type=\"Float64\" NumberOfComponents=\"2\"", "2 components", VC_EFORMAT},
        {"</Piece>", "</Piece><Piece NumberOfPoints=\"0\" NumberOfCells=\"0\"></Piece>",
         "more than one Piece", VC_EFORMAT},
        {"<Cells>", "<Cells x=>", "malformed XML tag", VC_EFORMAT},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *text = variant(cases[i].from, cases[i].to);
        char name[64];
        snprintf(name, sizeof name, "vtu_reader_bad_%zu.vtu", i);
        expect_error(name, text, cases[i].code, cases[i].needle);
        free(text);
    }
    char *sp = with_seed_points("2", "0 0 1 1 2 2");
    expect_error("vtu_reader_seed_2.vtu", sp, VC_EFORMAT, "'seed_point' has 2 components");
    free(sp);
    sp = with_seed_points("3", "0 0 0 1 1 1");
    expect_error("vtu_reader_seed_short.vtu", sp, VC_EFORMAT, "expected 3 x 3");
    free(sp);
    sp = with_seed_points("3", "0 0 0 1 nan 1 2 2 2");
    expect_error("vtu_reader_seed_nan.vtu", sp, VC_EFORMAT, "non-finite 'seed_point'");
    free(sp);
    expect_error("vtu_reader_empty.vtu", "", VC_EFORMAT, "empty file");
    expect_error("vtu_reader_text.vtu", "just text", VC_EFORMAT, "not a VTK XML file");
    expect_error("vtu_reader_other.vtu", "<foo/>", VC_EFORMAT, "not a VTK XML file");
    vc_vtu_mesh m;
    vc_error err;
    char *missing = tmp_path("vtu_reader_does_not_exist.vtu");
    CHECK(vc_vtu_read(missing, &m, &err) == VC_EIO);
    check_error_line(&err, missing);
    free(missing);
    CHECK(vc_vtu_read(tmpdir, &m, &err) != 0); /* a directory */
}

/* Flips bytes and truncates; every read must end cleanly. */
static void fuzz(const char *src_name, int flips)
{
    char *src = tmp_path(src_name);
    size_t n;
    char *orig = read_file_bytes(src, &n);
    CHECK(orig != NULL);
    if (!orig) {
        free(src);
        return;
    }
    char *p = tmp_path("vtu_reader_fuzz.vtu");
    char *buf = malloc(n);
    vc_rng rng;
    vc_rng_init(&rng, 4242, n);
    int ok = 0, bad = 0;
    for (int k = 0; k < flips; k++) {
        memcpy(buf, orig, n);
        int nflip = 1 + (int)(vc_rng_next(&rng) % 3);
        for (int j = 0; j < nflip; j++)
            buf[vc_rng_next(&rng) % n] ^= (char)(1u << (vc_rng_next(&rng) % 8));
        write_file(p, buf, n);
        vc_vtu_mesh m;
        vc_error err;
        if (vc_vtu_read(p, &m, &err) == 0) {
            ok++;
            /* damaged but readable cells (warped, repeated vertices, ...)
             * must not upset the measures either */
            for (int64_t c = 0; c < m.n_cells; c++) {
                vc_cell cell = {m.points, 0, NULL, m.cell_faces[c + 1] - m.cell_faces[c],
                                m.face_offsets + m.cell_faces[c], m.face_vertices};
                vc_cell_measures cm;
                (void)vc_cell_measure(&cell, &cm);
            }
            vc_vtu_mesh_free(&m);
        } else {
            bad++;
            check_error_line(&err, p);
        }
    }
    for (size_t len = 0; len < n; len += 1 + n / 300) {
        write_file(p, orig, len);
        vc_vtu_mesh m;
        vc_error err;
        if (vc_vtu_read(p, &m, &err) == 0)
            vc_vtu_mesh_free(&m);
        else
            check_error_line(&err, p);
    }
    CHECK(bad > 0);
    printf("fuzz %s: %d mutations read, %d refused\n", src_name, ok, bad);
    free(buf);
    free(orig);
    free(src);
    free(p);
}

/* A small mesh (8 seeds) written by our writer, for fuzzing. */
static void write_small(void)
{
    vc_seeds seeds;
    vc_error err;
    CHECK(vc_seeds_alloc(&seeds, 8, &err) == 0);
    for (int i = 0; i < 8; i++)
        for (int d = 0; d < 3; d++)
            seeds.xyz[3 * i + d] = ((i >> d) & 1) + 0.1 * d * i;
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    vc_polymesh mesh;
    memset(&mesh, 0, sizeof mesh);
    CHECK(vc_voronoi_build(&seeds, &opt, &mesh, &err) == 0);
    char *p = tmp_path("vtu_reader_small_raw.vtu");
    CHECK(vc_write_vtu(&mesh, p, VC_VTU_RAW, &err) == 0);
    free(p);
    p = tmp_path("vtu_reader_small_zlib.vtu");
    CHECK(vc_write_vtu(&mesh, p, VC_VTU_ZLIB, &err) == 0);
    free(p);
    vc_polymesh_free(&mesh);
    vc_seeds_free(&seeds);
}

/* VTK's inline base64 encoding of a compressed array: the header and the
 * data encoded separately (padding in the middle). Points of 1 tetrahedron
 * as Float32, header UInt32, made with Python's zlib and base64. */
static const char base64_tet[] =
    "<?xml version=\"1.0\"?>\n"
    "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" "
    "header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\">\n"
    "<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points>\n"
    "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\">\n"
    "  AQAAAACAAAAwAAAAEAAAAA==eJxjYEAGDfYMBPgAJ70CPg==\n"
    "</DataArray></Points><Cells>\n"
    "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\n"
    "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n"
    "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray>\n"
    "</Cells></Piece></UnstructuredGrid></VTKFile>\n";

static void test_base64(void)
{
    char *p = tmp_path("vtu_reader_b64.vtu");
    write_file(p, base64_tet, sizeof base64_tet - 1);
    vc_vtu_mesh m;
    vc_error err;
    int rc = vc_vtu_read(p, &m, &err);
    CHECK(rc == 0);
    if (rc == 0) {
        const double want[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
        CHECK(m.n_points == 4 && memcmp(m.points, want, sizeof want) == 0);
        CHECK(m.n_cells == 1 && m.cell_type[0] == VC_VTK_TETRA);
        vc_vtu_mesh_free(&m);
    } else {
        fprintf(stderr, "%s\n", err.msg);
    }
    free(p);
}

int main(void)
{
    const char *t = getenv("VC_TMP");
    if (t && *t)
        tmpdir = t;
    test_own_writer();
    test_vtk94_layout();
    test_seed_points();
    test_base64();
    test_errors();
    write_small();
    fuzz("vtu_reader_small_raw.vtu", 600);
    fuzz("vtu_reader_small_zlib.vtu", 600);
    fuzz("vtu_reader_b64.vtu", 300);
    fuzz("vtu_reader_vtk94.vtu", 300);
    if (failures) {
        fprintf(stderr, "test_vtu_reader: %d failures\n", failures);
        return 1;
    }
    printf("test_vtu_reader: all checks passed\n");
    return 0;
}
