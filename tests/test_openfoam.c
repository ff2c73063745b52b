/* Tests of the OpenFOAM writer (vorocrust/io/openfoam_writer.c) on a mesh of
 * two unit cubes side by side, built by hand:
 *   - the written files, parsed back: headers, note, counts, the interior
 *     face first and oriented +x, boundary faces grouped by patch (a
 *     "surface" face first, then the walls in order);
 *   - a mesh whose interior face is stored from the higher cell (owner 1,
 *     neighbour 0): written flipped, owner 0 -> neighbour 1;
 *   - an unused point: dropped and the faces renumbered;
 *   - errors: CASE_DIR a file, a vertex out of range (nothing created);
 *   - writing into an existing case keeps the user's system/controlDict;
 *   - the number formatter: 17 significant digits that read back exactly,
 *     the same text as printf's "%.17g". */
#include "vorocrust/io.h"

#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test_check.h"
#include "test_file_util.h"

size_t vc_foam_format_double(char *out, double x); /* in openfoam_writer.c */

static char tmpdir[1024];

/* ---- the two-cube mesh ------------------------------------------------- */

typedef struct two_cubes {
    vc_polymesh m;
    double points[3 * 13];
    int64_t offsets[12], verts[44], owner[11], neighbour[11], other[11];
} two_cubes;

/* Point (i, j, k), i in 0..2, j, k in 0..1, at index shift + i + 3j + 6k. */
static int64_t pid(int shift, int i, int j, int k)
{
    return shift + i + 3 * j + 6 * k;
}

/* flip: store the interior face from cell 1 (reversed); shift: an unused
 * point at index 0; surface: cell 1's xmax face is against a non-kept seed. */
static void build(two_cubes *t, int flip, int shift)
{
    memset(t, 0, sizeof *t);
    int np = 12 + shift;
    if (shift)
        t->points[0] = t->points[1] = t->points[2] = -7.0;
    for (int k = 0; k < 2; k++)
        for (int j = 0; j < 2; j++)
            for (int i = 0; i < 3; i++) {
                double *p = t->points + 3 * pid(shift, i, j, k);
                p[0] = i, p[1] = j, p[2] = k;
            }
    int nf = 0, nv = 0;
#define FACE(a, b, c, d, own, nei, oth)                                           \
    do {                                                                          \
        t->offsets[nf] = nv;                                                      \
        t->verts[nv++] = (a), t->verts[nv++] = (b), t->verts[nv++] = (c),          \
        t->verts[nv++] = (d);                                                     \
        t->owner[nf] = (own), t->neighbour[nf] = (nei), t->other[nf] = (oth);     \
        nf++;                                                                     \
    } while (0)
    int s = shift;
    /* Interior face x = 1, +x from cell 0 (or -x from cell 1). */
    if (!flip)
        FACE(pid(s, 1, 0, 0), pid(s, 1, 1, 0), pid(s, 1, 1, 1), pid(s, 1, 0, 1), 0, 1, 101);
    else
        FACE(pid(s, 1, 0, 0), pid(s, 1, 0, 1), pid(s, 1, 1, 1), pid(s, 1, 1, 0), 1, 0, 100);
    for (int c = 0; c < 2; c++) {
        int x0 = c, x1 = c + 1;
        /* xmin of cell 0 (-x), or xmax of cell 1 (+x, against seed 7). */
        if (c == 0)
            FACE(pid(s, 0, 0, 0), pid(s, 0, 0, 1), pid(s, 0, 1, 1), pid(s, 0, 1, 0), 0, -1,
                 VC_WALL_XMIN);
        else
            FACE(pid(s, 2, 0, 0), pid(s, 2, 1, 0), pid(s, 2, 1, 1), pid(s, 2, 0, 1), 1, -1, 7);
        /* ymin (-y), ymax (+y), zmin (-z), zmax (+z). */
        FACE(pid(s, x0, 0, 0), pid(s, x1, 0, 0), pid(s, x1, 0, 1), pid(s, x0, 0, 1), c, -1,
             VC_WALL_XMIN - 2);
        FACE(pid(s, x0, 1, 0), pid(s, x0, 1, 1), pid(s, x1, 1, 1), pid(s, x1, 1, 0), c, -1,
             VC_WALL_XMIN - 3);
        FACE(pid(s, x0, 0, 0), pid(s, x0, 1, 0), pid(s, x1, 1, 0), pid(s, x1, 0, 0), c, -1,
             VC_WALL_XMIN - 4);
        FACE(pid(s, x0, 0, 1), pid(s, x1, 0, 1), pid(s, x1, 1, 1), pid(s, x0, 1, 1), c, -1,
             VC_WALL_XMIN - 5);
    }
#undef FACE
    t->offsets[nf] = nv;
    vc_polymesh *m = &t->m;
    m->n_points = np;
    m->points = t->points;
    m->n_faces = nf;
    m->n_interior_faces = 1;
    m->face_offsets = t->offsets;
    m->face_vertices = t->verts;
    m->face_owner = t->owner;
    m->face_neighbour = t->neighbour;
    m->face_other_seed = t->other;
    m->n_cells = 2;
}

/* ---- reading back ------------------------------------------------------- */

static char *case_file(const char *c, const char *rel)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s/%s", c, rel);
    return buf;
}

/* The list of a file: the integers after the header's "}" (list size,
 * then entries; for faces, the size prefix and the vertices). */
static int read_ints(const char *text, int64_t *out, int max)
{
    const char *p = strchr(text, '}');
    int n = 0;
    if (!p)
        return -1;
    for (p++; *p && n < max;) {
        if (*p >= '0' && *p <= '9') {
            char *e;
            out[n++] = strtoll(p, &e, 10);
            p = e;
        } else {
            p++;
        }
    }
    return n;
}

static void check_two_cubes(const char *c, int shift_written)
{
    (void)shift_written;
    char *owner = read_file_text(case_file(c, "constant/polyMesh/owner"));
    char *neigh = read_file_text(case_file(c, "constant/polyMesh/neighbour"));
    char *faces = read_file_text(case_file(c, "constant/polyMesh/faces"));
    char *points = read_file_text(case_file(c, "constant/polyMesh/points"));
    char *bnd = read_file_text(case_file(c, "constant/polyMesh/boundary"));
    char *ctl = read_file_text(case_file(c, "system/controlDict"));
    CHECK(owner && neigh && faces && points && bnd && ctl);
    if (!(owner && neigh && faces && points && bnd && ctl))
        goto out;
    CHECK(strstr(owner, "class       labelList;"));
    CHECK(strstr(owner, "object      owner;"));
    CHECK(strstr(owner, "note        \"nPoints:12  nCells:2  nFaces:11  nInternalFaces:1\";"));
    CHECK(strstr(neigh, "object      neighbour;"));
    CHECK(strstr(faces, "class       faceList;"));
    CHECK(strstr(points, "class       vectorField;"));
    CHECK(strstr(bnd, "class       polyBoundaryMesh;"));
    CHECK(strstr(ctl, "object      controlDict;"));

    int64_t v[64];
    /* owner: 11 entries; interior face owned by 0; the surface face (cell
     * 1's xmax) first among the boundary faces, then xmin (cell 0), then
     * ymin, ymax, zmin, zmax of cells 0 and 1. */
    static const int64_t want_owner[12] = {11, 0, 1, 0, 0, 1, 0, 1, 0, 1, 0, 1};
    CHECK(read_ints(owner, v, 64) == 12 && !memcmp(v, want_owner, sizeof want_owner));
    CHECK(read_ints(neigh, v, 64) == 2 && v[0] == 1 && v[1] == 1);
    /* faces: the interior face +x, starting at point (1,0,0). */
    int n = read_ints(faces, v, 64);
    CHECK(n == 1 + 11 * 5);
    CHECK(v[0] == 11 && v[1] == 4);
    CHECK(v[2] == pid(0, 1, 0, 0) && v[3] == pid(0, 1, 1, 0) && v[4] == pid(0, 1, 1, 1) &&
          v[5] == pid(0, 1, 0, 1));
    /* the surface face: cell 1's xmax. */
    CHECK(v[7] == pid(0, 2, 0, 0) && v[8] == pid(0, 2, 1, 0));
    /* points: 12, the first (0 0 0), the last (2 1 1). */
    CHECK(strstr(points, "\n12\n(\n(0 0 0)\n(1 0 0)\n(2 0 0)\n(0 1 0)\n"));
    CHECK(strstr(points, "(2 1 1)\n)\n"));
    CHECK(strstr(bnd, "\n6\n(\n    surface\n"));
    /* a surface without input groups is a wall, the box's walls patches */
    static const char *const patches[6][4] = {
        {"surface", "1", "1", "wall"}, {"xmin", "1", "2", "patch"}, {"ymin", "2", "3", "patch"},
        {"ymax", "2", "5", "patch"},   {"zmin", "2", "7", "patch"}, {"zmax", "2", "9", "patch"}};
    for (int i = 0; i < 6; i++) {
        char want[256];
        snprintf(want, sizeof want,
                 "    %s\n    {\n        type            %s;\n        nFaces          %s;\n"
                 "        startFace       %s;\n    }\n",
                 patches[i][0], patches[i][3], patches[i][1], patches[i][2]);
        CHECK(strstr(bnd, want));
    }
    CHECK(!strstr(bnd, "xmax"));
out:
    free(owner);
    free(neigh);
    free(faces);
    free(points);
    free(bnd);
    free(ctl);
}

static void remove_case(const char *c)
{
    static const char *const files[] = {
        "constant/polyMesh/points", "constant/polyMesh/faces", "constant/polyMesh/owner",
        "constant/polyMesh/neighbour", "constant/polyMesh/boundary", "system/controlDict",
        "system/fvSchemes", "system/fvSolution", "constant/polyMesh", "constant", "system", ""};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++)
        remove(case_file(c, files[i]));
    rmdir(c);
}

static void test_cases(void)
{
    char c[4096], sub[2048];
    snprintf(sub, sizeof sub, "%s/openfoam_test", tmpdir);
    remove_case(sub); /* leftovers of an earlier run */
    mkdir(sub, 0777);
    int before = count_dir_entries(sub, NULL);
    vc_error err = {0, ""};
    two_cubes t;
    int variants[3][2] = {{0, 0}, {1, 0}, {0, 1}}; /* plain, flipped, unused point */
    for (int i = 0; i < 3; i++) {
        build(&t, variants[i][0], variants[i][1]);
        snprintf(c, sizeof c, "%s/case%d", sub, i);
        remove_case(c);
        int rc = vc_write_openfoam(&t.m, c, &err);
        CHECK(rc == VC_OK);
        if (rc != VC_OK)
            fprintf(stderr, "  %s\n", err.msg);
        check_two_cubes(c, variants[i][1]);
        remove_case(c);
    }

    /* An existing case: the user's controlDict stays, polyMesh is new. */
    build(&t, 0, 0);
    snprintf(c, sizeof c, "%s/existing", sub);
    remove_case(c);
    mkdir(c, 0777);
    mkdir(case_file(c, "system"), 0777);
    FILE *fp = fopen(case_file(c, "system/controlDict"), "w");
    if (fp) {
        fputs("user\n", fp);
        fclose(fp);
    }
    CHECK(vc_write_openfoam(&t.m, c, &err) == VC_OK);
    char *ctl = read_file_text(case_file(c, "system/controlDict"));
    CHECK(ctl && !strcmp(ctl, "user\n"));
    free(ctl);
    CHECK(count_dir_entries(case_file(c, "constant/polyMesh"), NULL) == 5);
    CHECK(count_dir_entries(case_file(c, "system"), NULL) == 3);
    CHECK(count_dir_entries(case_file(c, "constant"), NULL) == 1);
    remove_case(c);

    /* Errors: CASE_DIR a file; a vertex out of range. Nothing is left. */
    snprintf(c, sizeof c, "%s/a_file", sub);
    fp = fopen(c, "w");
    if (fp)
        fclose(fp);
    CHECK(vc_write_openfoam(&t.m, c, &err) == VC_EIO);
    CHECK(strstr(err.msg, "a_file") && strstr(err.msg, "Not a directory"));
    remove(c);
    build(&t, 0, 0);
    t.verts[5] = 12;
    snprintf(c, sizeof c, "%s/bad", sub);
    CHECK(vc_write_openfoam(&t.m, c, &err) == VC_EINPUT);
    CHECK(strstr(err.msg, "vertex 12"));
    CHECK(count_dir_entries(sub, NULL) == before);
    rmdir(sub);
}

/* ---- the number formatter --------------------------------------------- */

static uint64_t rng_state = 0x9E3779B97F4A7C15ULL;
static uint64_t rng_next(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

static void test_format(void)
{
    static const double fixed[] = {0.0,     1.0,   -1.0,    0.5,    -2.25,  0.1,
                                   1e-5,    1e-4,  123.456, 1e16,   1e17,   9.999999999999999e16,
                                   1e-300,  1e300, 5e-324,  DBL_MAX, DBL_MIN, 0.30000000000000004,
                                   2.0 / 3, 1e-38, 1e38,    -0.0};
    char a[64], b[64];
    int mismatch = 0, total = 0;
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) {
        vc_foam_format_double(a, fixed[i]);
        CHECK(strtod(a, NULL) == fixed[i]);
        snprintf(b, sizeof b, "%.17g", fixed[i]);
        if (fixed[i] != 0 && strcmp(a, b)) {
            fprintf(stderr, "format %s, printf %s\n", a, b);
            ++failures;
        }
    }
    /* Random doubles of every magnitude a mesh can have, and raw bit
     * patterns. */
    for (int i = 0; i < 400000; i++) {
        double x;
        if (i & 1) {
            uint64_t bits = rng_next();
            memcpy(&x, &bits, sizeof x);
            if (!isfinite(x))
                continue;
        } else {
            x = ((double)(rng_next() >> 11) / 9007199254740992.0 - 0.5) *
                pow(10.0, (double)((int)(rng_next() % 41) - 20));
        }
        size_t n = vc_foam_format_double(a, x);
        char *end;
        double y = strtod(a, &end);
        if (y != x || *end || n >= 32) {
            fprintf(stderr, "format %.17g -> '%s' reads back as %.17g\n", x, a, y);
            ++failures;
            break;
        }
        snprintf(b, sizeof b, "%.17g", x);
        total++;
        mismatch += x != 0 && strcmp(a, b) != 0;
    }
    CHECK(mismatch == 0);
    printf("formatter: %d random doubles read back exactly; %d differ from %%.17g in the last "
           "digit\n", total, mismatch);
}

int main(void)
{
    const char *t = getenv("VC_TMP");
    snprintf(tmpdir, sizeof tmpdir, "%s", t && *t ? t : "/tmp");
    test_format();
    test_cases();
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("test_openfoam: all checks passed\n");
    return 0;
}
