/* Tests of the output module (vorocrust/io): temporary files, the VTU
 * writer, the connections CSV, and the seeds CSV reader/writer.
 *
 * Also leaves these files in $VC_TMP for tests/e2e_vtu_readback.py, which
 * reads them back with VTK:
 *   io_two_cubes_raw.vtu, io_two_cubes_zlib.vtu  two unit cubes side by side
 *   io_grid_raw.vtu, io_grid_zlib.vtu            a 24x20x18 box grid with
 *                                                uneven spacing (several zlib
 *                                                blocks per array) */
#include "vorocrust/io.h"
#include "io/tmpfile.h"
#include "vorocrust/seeds.h"

#include <dirent.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test_check.h"
#include "test_file_util.h"

static const char *tmpdir;

static char *path_in(const char *dir, const char *name)
{
    size_t n = strlen(dir) + strlen(name) + 2;
    char *p = malloc(n);
    snprintf(p, n, "%s/%s", dir, name);
    return p;
}

static int file_exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

static long file_size(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0 ? (long)st.st_size : -1;
}

/* Removes the files (not subdirectories) of dir. */
static void clear_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char *p = path_in(dir, e->d_name);
        remove(p);
        free(p);
    }
    closedir(d);
}

static void write_text(const char *p, const char *text)
{
    FILE *fp = fopen(p, "wb");
    if (!fp) {
        fprintf(stderr, "cannot create %s\n", p);
        exit(2);
    }
    fputs(text, fp);
    fclose(fp);
}

/* ---- a hand-built mesh: an nx x ny x nz grid of boxes ----------------- */

/* Box (i,j,k) spans [xs[i],xs[i+1]] x [ys[j],ys[j+1]] x [zs[k],zs[k+1]].
 * Faces follow the polymesh conventions: interior faces first, sorted by
 * (owner, neighbour), each oriented out of its owner; then boundary faces
 * sorted by owner. Cell c has seed c + SEED_SHIFT at its centre. */
#define SEED_SHIFT 5

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    return p;
}

typedef struct grid {
    int n[3];
    const double *co[3];
} grid;

static int64_t grid_point(const grid *g, const int ijk[3])
{
    return ijk[0] + (int64_t)(g->n[0] + 1) * (ijk[1] + (int64_t)(g->n[1] + 1) * ijk[2]);
}

static int64_t grid_cell(const grid *g, const int ijk[3])
{
    return ijk[0] + (int64_t)g->n[0] * (ijk[1] + (int64_t)g->n[1] * ijk[2]);
}

/* Adds the face of cell ijk on side (d, s) (s = 0: low, 1: high), oriented
 * along +e_d when s = 1 and -e_d when s = 0. */
static void grid_add_face(const grid *g, vc_polymesh *m, const int ijk[3], int d, int s,
                          int64_t owner, int64_t neighbour, int64_t other_seed)
{
    int u = (d + 1) % 3, w = (d + 2) % 3;
    static const int cyc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    int64_t f = m->n_faces++;
    int64_t base = m->face_offsets[f];
    double cen[3] = {0, 0, 0};
    for (int q = 0; q < 4; ++q) {
        int qq = s ? q : 3 - q;
        int p[3];
        p[d] = ijk[d] + s;
        p[u] = ijk[u] + cyc[qq][0];
        p[w] = ijk[w] + cyc[qq][1];
        m->face_vertices[base + q] = grid_point(g, p);
        for (int a = 0; a < 3; ++a)
            cen[a] += 0.25 * g->co[a][p[a]];
    }
    m->face_offsets[f + 1] = base + 4;
    m->face_owner[f] = owner;
    m->face_neighbour[f] = neighbour;
    m->face_other_seed[f] = other_seed;
    m->face_area[f] = (g->co[u][ijk[u] + 1] - g->co[u][ijk[u]]) *
                      (g->co[w][ijk[w] + 1] - g->co[w][ijk[w]]);
    for (int a = 0; a < 3; ++a) {
        m->face_centroid[3 * f + a] = cen[a];
        m->face_normal[3 * f + a] = (a == d) ? (s ? 1.0 : -1.0) : 0.0;
    }
}

static void build_grid(vc_polymesh *m, int nx, int ny, int nz, const double *xs,
                       const double *ys, const double *zs)
{
    grid g = {{nx, ny, nz}, {xs, ys, zs}};
    memset(m, 0, sizeof *m);
    int64_t nc = (int64_t)nx * ny * nz;
    int64_t np = (int64_t)(nx + 1) * (ny + 1) * (nz + 1);
    int64_t nf_max = 6 * nc;
    m->n_points = np;
    m->points = xmalloc(sizeof(double) * 3 * np);
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) {
                int p[3] = {i, j, k};
                int64_t id = grid_point(&g, p);
                m->points[3 * id + 0] = xs[i];
                m->points[3 * id + 1] = ys[j];
                m->points[3 * id + 2] = zs[k];
            }
    m->face_offsets = xmalloc(sizeof(int64_t) * (nf_max + 1));
    m->face_offsets[0] = 0;
    m->face_vertices = xmalloc(sizeof(int64_t) * 4 * nf_max);
    m->face_owner = xmalloc(sizeof(int64_t) * nf_max);
    m->face_neighbour = xmalloc(sizeof(int64_t) * nf_max);
    m->face_other_seed = xmalloc(sizeof(int64_t) * nf_max);
    m->face_area = xmalloc(sizeof(double) * nf_max);
    m->face_centroid = xmalloc(sizeof(double) * 3 * nf_max);
    m->face_normal = xmalloc(sizeof(double) * 3 * nf_max);

    /* interior faces: for each owner, its +x, +y, +z neighbours (increasing) */
    for (int64_t c = 0; c < nc; ++c) {
        int ijk[3] = {(int)(c % nx), (int)((c / nx) % ny), (int)(c / ((int64_t)nx * ny))};
        for (int d = 0; d < 3; ++d) {
            if (ijk[d] + 1 < g.n[d]) {
                int nb[3] = {ijk[0], ijk[1], ijk[2]};
                nb[d] += 1;
                int64_t cn = grid_cell(&g, nb);
                grid_add_face(&g, m, ijk, d, 1, c, cn, cn + SEED_SHIFT);
            }
        }
    }
    m->n_interior_faces = m->n_faces;
    /* boundary faces, by owner; walls xmin, xmax, ymin, ymax, zmin, zmax */
    for (int64_t c = 0; c < nc; ++c) {
        int ijk[3] = {(int)(c % nx), (int)((c / nx) % ny), (int)(c / ((int64_t)nx * ny))};
        for (int d = 0; d < 3; ++d)
            for (int s = 0; s < 2; ++s)
                if ((s == 0 && ijk[d] == 0) || (s == 1 && ijk[d] == g.n[d] - 1))
                    grid_add_face(&g, m, ijk, d, s, c, -1, VC_WALL_XMIN - (2 * d + s));
    }

    /* cells: list faces by scanning (fine for test sizes) */
    m->n_cells = nc;
    m->cell_offsets = xmalloc(sizeof(int64_t) * (nc + 1));
    m->cell_faces = xmalloc(sizeof(int64_t) * 6 * nc);
    int64_t *count = calloc((size_t)nc, sizeof(int64_t));
    for (int64_t f = 0; f < m->n_faces; ++f) {
        count[m->face_owner[f]]++;
        if (m->face_neighbour[f] >= 0)
            count[m->face_neighbour[f]]++;
    }
    m->cell_offsets[0] = 0;
    for (int64_t c = 0; c < nc; ++c)
        m->cell_offsets[c + 1] = m->cell_offsets[c] + count[c];
    for (int64_t c = 0; c < nc; ++c)
        count[c] = m->cell_offsets[c];
    for (int64_t f = 0; f < m->n_faces; ++f) {
        m->cell_faces[count[m->face_owner[f]]++] = f;
        if (m->face_neighbour[f] >= 0)
            m->cell_faces[count[m->face_neighbour[f]]++] = f;
    }
    free(count);

    m->cell_seed = xmalloc(sizeof(int64_t) * nc);
    m->cell_region = xmalloc(sizeof(int32_t) * nc);
    m->cell_volume = xmalloc(sizeof(double) * nc);
    m->cell_centroid = xmalloc(sizeof(double) * 3 * nc);
    m->n_seeds = nc + SEED_SHIFT;
    m->seed_xyz = xmalloc(sizeof(double) * 3 * m->n_seeds);
    for (int64_t i = 0; i < 3 * SEED_SHIFT; ++i)
        m->seed_xyz[i] = -100.0 - (double)i; /* seeds without a kept cell */
    for (int64_t c = 0; c < nc; ++c) {
        int ijk[3] = {(int)(c % nx), (int)((c / nx) % ny), (int)(c / ((int64_t)nx * ny))};
        double vol = 1.0;
        for (int a = 0; a < 3; ++a) {
            double lo = g.co[a][ijk[a]], hi = g.co[a][ijk[a] + 1];
            vol *= hi - lo;
            m->cell_centroid[3 * c + a] = 0.5 * (lo + hi);
            m->seed_xyz[3 * (c + SEED_SHIFT) + a] = 0.5 * (lo + hi);
        }
        m->cell_volume[c] = vol;
        m->cell_seed[c] = c + SEED_SHIFT;
        m->cell_region[c] = (int32_t)(c % 3) + 1;
    }
}

static void build_two_cubes(vc_polymesh *m)
{
    static const double xs[3] = {0.0, 1.0, 2.0}, ys[2] = {0.0, 1.0}, zs[2] = {0.0, 1.0};
    build_grid(m, 2, 1, 1, xs, ys, zs);
}

/* ---- tests ------------------------------------------------------------ */

static void test_two_cubes_mesh_shape(void)
{
    vc_polymesh m;
    build_two_cubes(&m);
    CHECK(m.n_points == 12);
    CHECK(m.n_faces == 11);
    CHECK(m.n_interior_faces == 1);
    CHECK(m.face_owner[0] == 0 && m.face_neighbour[0] == 1);
    CHECK(m.n_cells == 2);
    CHECK(m.cell_offsets[1] == 6 && m.cell_offsets[2] == 12);
    vc_polymesh_free(&m);
}

/* Checks the beginning of a written VTU file. */
static void check_vtu_header(const char *p, int zlib)
{
    char *s = read_file_text(p);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK(strncmp(s, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" "
                     "version=\"1.0\"", 56) == 0);
    CHECK(strstr(s, "header_type=\"UInt64\"") != NULL);
    CHECK((strstr(s, "compressor=\"vtkZLibDataCompressor\"") != NULL) == (zlib != 0));
    CHECK(strstr(s, "Name=\"faceoffsets\"") != NULL);
    CHECK(strstr(s, "<AppendedData encoding=\"raw\">") != NULL);
    free(s);
}

static void test_vtu_write(void)
{
    vc_error err = {0, ""};
    vc_polymesh m;
    build_two_cubes(&m);

    char *raw = path_in(tmpdir, "io_two_cubes_raw.vtu");
    char *zl = path_in(tmpdir, "io_two_cubes_zlib.vtu");
    remove(raw);
    remove(zl);
    int rc = vc_write_vtu(&m, raw, VC_VTU_RAW, &err);
    CHECK_MSG(rc == 0, err.msg);
    rc = vc_write_vtu(&m, zl, VC_VTU_ZLIB, &err);
    CHECK_MSG(rc == 0, err.msg);
    CHECK(file_exists(raw) && file_size(raw) > 0);
    CHECK(file_exists(zl) && file_size(zl) > 0);
    check_vtu_header(raw, 0);
    check_vtu_header(zl, 1);

    /* raw size is exactly predictable from the arrays */
    {
        char *s = read_file_text(raw);
        const char *u = s ? strstr(s, "<AppendedData encoding=\"raw\">\n   _") : NULL;
        CHECK(u != NULL);
        if (u) {
            long head = (long)(u - s) + (long)strlen("<AppendedData encoding=\"raw\">\n   _");
            /* region 2*4, seed 2*8, volume 2*8, seed_point 2*24 (the mesh
             * carries its seeds), points 12*24, then the indices as Int32
             * (every one fits): conn 16*4, offsets 2*4, types 2, faces
             * 2*(1+6*5)*4, faceoffsets 2*4; 10 headers */
            long data = 8 + 16 + 16 + 48 + 288 + 64 + 8 + 2 + 248 + 8 + 10 * 8;
            long tail = (long)strlen("\n  </AppendedData>\n</VTKFile>\n");
            CHECK(file_size(raw) == head + data + tail);
        }
        free(s);
    }

    /* temp files: a private directory, so other tests' files don't count */
    char *sub = path_in(tmpdir, "io_test_tmpcheck");
    mkdir(sub, 0777);
    char *a = path_in(sub, "a.vtu");
    char *adir = path_in(sub, "adir");
    rmdir(adir);
    clear_dir(sub);
    CHECK(count_dir_entries(sub, NULL) == 0);
    rc = vc_write_vtu(&m, a, VC_VTU_ZLIB, &err);
    CHECK_MSG(rc == 0, err.msg);
    rc = vc_write_vtu(&m, a, VC_VTU_RAW, &err); /* overwrite */
    CHECK_MSG(rc == 0, err.msg);
    CHECK(count_dir_entries(sub, ".tmp.") == 0);
    CHECK(count_dir_entries(sub, NULL) == 1);

    /* rename onto a directory fails at commit: the temp file must go */
    mkdir(adir, 0777);
    err.code = 0;
    err.msg[0] = '\0';
    rc = vc_write_vtu(&m, adir, VC_VTU_RAW, &err);
    CHECK(rc == VC_EIO);
    CHECK(err.code == VC_EIO);
    CHECK_MSG(strstr(err.msg, adir) != NULL, err.msg);
    CHECK(count_dir_entries(sub, ".tmp.") == 0);
    CHECK(count_dir_entries(sub, NULL) == 2);
    rmdir(adir);

    /* a directory that does not exist */
    char *bad = path_in(tmpdir, "io_no_such_dir/out.vtu");
    char *baddir = path_in(tmpdir, "io_no_such_dir");
    rmdir(baddir);
    err.msg[0] = '\0';
    rc = vc_write_vtu(&m, bad, VC_VTU_ZLIB, &err);
    CHECK(rc == VC_EIO);
    CHECK_MSG(strstr(err.msg, bad) != NULL, err.msg);
    CHECK_MSG(strstr(err.msg, "cannot write") != NULL, err.msg);
    CHECK_MSG(strstr(err.msg, strerror(ENOENT)) != NULL, err.msg);
    CHECK(!file_exists(bad) && !file_exists(baddir));
    printf("expected error: %s\n", err.msg);

    /* connections CSV: the single interior face */
    char *csv = path_in(sub, "conn.csv");
    rc = vc_write_connections_csv(&m, csv, &err);
    CHECK_MSG(rc == 0, err.msg);
    char *txt = read_file_text(csv);
    /* the interior face, then the ten boundary faces with their patches
     * (walls of the box, per region), distance from the seed to the face */
    CHECK(txt && strcmp(txt, "cell_i,cell_j,seed_i,seed_j,area,distance,cx,cy,cz,nx,ny,nz,"
                             "region_i,region_j,patch\n"
                             "0,1,5,6,1,1,1,0.5,0.5,1,0,0,1,2,\n"
                             "0,-1,5,-1,1,0.5,0,0.5,0.5,-1,0,0,1,0,region1_xmin\n"
                             "0,-1,5,-1,1,0.5,0.5,0,0.5,0,-1,0,1,0,region1_ymin\n"
                             "0,-1,5,-1,1,0.5,0.5,1,0.5,0,1,0,1,0,region1_ymax\n"
                             "0,-1,5,-1,1,0.5,0.5,0.5,0,0,0,-1,1,0,region1_zmin\n"
                             "0,-1,5,-1,1,0.5,0.5,0.5,1,0,0,1,1,0,region1_zmax\n"
                             "1,-1,6,-1,1,0.5,2,0.5,0.5,1,0,0,2,0,region2_xmax\n"
                             "1,-1,6,-1,1,0.5,1.5,0,0.5,0,-1,0,2,0,region2_ymin\n"
                             "1,-1,6,-1,1,0.5,1.5,1,0.5,0,1,0,2,0,region2_ymax\n"
                             "1,-1,6,-1,1,0.5,1.5,0.5,0,0,0,-1,2,0,region2_zmin\n"
                             "1,-1,6,-1,1,0.5,1.5,0.5,1,0,0,1,2,0,region2_zmax\n") == 0);
    if (txt && failures)
        fprintf(stderr, "connections csv:\n%s", txt);
    free(txt);
    char *badcsv = path_in(tmpdir, "io_no_such_dir/conn.csv");
    rc = vc_write_connections_csv(&m, badcsv, &err);
    CHECK(rc == VC_EIO);
    CHECK_MSG(strstr(err.msg, badcsv) != NULL, err.msg);
    CHECK(count_dir_entries(sub, ".tmp.") == 0);

    /* tmpfile abort leaves nothing */
    vc_tmpfile t;
    char *tp = path_in(sub, "aborted.txt");
    rc = vc_tmpfile_open(&t, tp, &err);
    CHECK_MSG(rc == 0, err.msg);
    if (rc == 0) {
        fputs("partial", (FILE *)t.fp);
        vc_tmpfile_discard(&t);
    }
    CHECK(!file_exists(tp));
    CHECK(count_dir_entries(sub, ".tmp.") == 0);
    clear_dir(sub);
    rmdir(sub);

    free(tp);
    free(badcsv);
    free(csv);
    free(bad);
    free(baddir);
    free(a);
    free(adir);
    free(sub);
    free(raw);
    free(zl);
    vc_polymesh_free(&m);
}

/* A bigger grid with uneven spacing: every array spans several zlib blocks
 * (and the faces array several parallel batches). */
#define GX 24
#define GY 20
#define GZ 18
static void test_vtu_grid(void)
{
    double xs[GX + 1], ys[GY + 1], zs[GZ + 1];
    for (int i = 0; i <= GX; ++i)
        xs[i] = i + 0.03 * i * i;
    for (int j = 0; j <= GY; ++j)
        ys[j] = 0.5 * j + 0.01 * j * j;
    for (int k = 0; k <= GZ; ++k)
        zs[k] = -3.0 + 0.25 * k;
    vc_polymesh m;
    build_grid(&m, GX, GY, GZ, xs, ys, zs);
    vc_error err = {0, ""};
    char *raw = path_in(tmpdir, "io_grid_raw.vtu");
    char *zl = path_in(tmpdir, "io_grid_zlib.vtu");
    int rc = vc_write_vtu(&m, raw, VC_VTU_RAW, &err);
    CHECK_MSG(rc == 0, err.msg);
    rc = vc_write_vtu(&m, zl, VC_VTU_ZLIB, &err);
    CHECK_MSG(rc == 0, err.msg);
    CHECK(file_size(zl) > 0 && file_size(zl) < file_size(raw));
    /* the expected totals, for the python test */
    double vol = (xs[GX] - xs[0]) * (ys[GY] - ys[0]) * (zs[GZ] - zs[0]);
    printf("grid: %d cells, volume %.17g\n", GX * GY * GZ, vol);

    /* connections: one row per interior face */
    char *csv = path_in(tmpdir, "io_grid_connections.csv");
    rc = vc_write_connections_csv(&m, csv, &err);
    CHECK_MSG(rc == 0, err.msg);
    char *txt = read_file_text(csv);
    if (txt) {
        int64_t lines = 0;
        for (const char *q = txt; *q; ++q)
            lines += (*q == '\n');
        CHECK(lines == 1 + m.n_faces); /* interior faces, then boundary faces */
        /* row of interior face 0: cells 0 and 1 along x */
        const char *row = strchr(txt, '\n') + 1;
        int64_t ci, cj, si, sj;
        double area, dist;
        CHECK(sscanf(row, "%" SCNd64 ",%" SCNd64 ",%" SCNd64 ",%" SCNd64 ",%lf,%lf", &ci, &cj,
                     &si, &sj, &area, &dist) == 6);
        CHECK(ci == 0 && cj == 1 && si == 5 && sj == 6);
        CHECK(fabs(area - (ys[1] - ys[0]) * (zs[1] - zs[0])) < 1e-15);
        CHECK(fabs(dist - 0.5 * (xs[2] - xs[0])) < 1e-15);
    } else {
        CHECK(txt != NULL);
    }
    free(txt);
    remove(csv);
    free(csv);

    /* a point index out of range in a late cell (the check runs on the
     * cells in parallel): refused with the first bad face named, no file */
    char *badp = path_in(tmpdir, "io_grid_bad.vtu");
    remove(badp);
    const int64_t last_face = m.cell_faces[m.cell_offsets[m.n_cells] - 1];
    const int64_t keep = m.face_vertices[m.face_offsets[last_face]];
    m.face_vertices[m.face_offsets[last_face]] = m.n_points + 7;
    err.msg[0] = '\0';
    rc = vc_write_vtu(&m, badp, VC_VTU_ZLIB, &err);
    CHECK(rc == VC_EINPUT);
    char want[160];
    snprintf(want, sizeof want, "face %" PRId64 " has vertex %" PRId64 " out of range", last_face,
             m.n_points + 7);
    CHECK_MSG(strstr(err.msg, want) != NULL, err.msg);
    CHECK(!file_exists(badp));
    m.face_vertices[m.face_offsets[last_face]] = keep;
    free(badp);
    free(raw);
    free(zl);
    vc_polymesh_free(&m);
}

/* ---- seeds CSV ---------------------------------------------------------- */

static void test_seeds_roundtrip(void)
{
    vc_error err = {0, ""};
    vc_seeds s;
    const int64_t n = 2000;
    CHECK(vc_seeds_alloc(&s, n, &err) == 0);
    CHECK(s.n == n && s.label[0] == 1 && s.label[n - 1] == 1);
    uint64_t x = 88172645463325252ull;
    for (int64_t i = 0; i < 3 * n; ++i) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        double u = (double)(x >> 11) / 9007199254740992.0;
        s.xyz[i] = (u - 0.5) * pow(10.0, (double)((int)(x % 41) - 20));
    }
    s.xyz[0] = -0.0;
    s.xyz[1] = 1e-308;
    s.xyz[2] = 1.7976931348623157e308;
    s.xyz[3] = 0.1;
    for (int64_t i = 0; i < n; ++i)
        s.label[i] = (int32_t)(i % 7) - 2;
    s.label[1] = INT32_MIN;
    s.label[2] = INT32_MAX;

    char *p = path_in(tmpdir, "io_seeds_roundtrip.csv");
    int rc = vc_seeds_write_csv(p, &s, &err);
    CHECK_MSG(rc == 0, err.msg);
    vc_seeds r;
    rc = vc_seeds_read_csv(p, &r, &err);
    CHECK_MSG(rc == 0, err.msg);
    if (rc == 0) {
        CHECK(r.n == n);
        CHECK(memcmp(r.xyz, s.xyz, sizeof(double) * 3 * (size_t)n) == 0);
        CHECK(memcmp(r.label, s.label, sizeof(int32_t) * (size_t)n) == 0);
        CHECK(signbit(r.xyz[0]));
    }
    vc_seeds_free(&r);
    CHECK(r.n == 0 && r.xyz == NULL && r.label == NULL);
    vc_seeds_free(&s);
    remove(p);

    char *bad = path_in(tmpdir, "io_no_such_dir/seeds.csv");
    vc_seeds e;
    CHECK(vc_seeds_alloc(&e, 0, &err) == 0);
    rc = vc_seeds_write_csv(bad, &e, &err);
    CHECK(rc == VC_EIO);
    CHECK_MSG(strstr(err.msg, bad) != NULL, err.msg);
    vc_seeds_free(&e);
    CHECK(vc_seeds_alloc(&e, -1, &err) == VC_EPARAM);
    free(bad);
    free(p);
}

/* Writes text to a file, reads it as seeds, and checks the outcome. */
static void seeds_case(const char *name, const char *text, int want_rc, const char *want_in_msg,
                       int64_t want_n)
{
    vc_error err = {0, ""};
    char *p = path_in(tmpdir, name);
    if (text)
        write_text(p, text);
    else
        remove(p);
    vc_seeds s = {123, (double *)1, (int32_t *)1};
    int rc = vc_seeds_read_csv(p, &s, &err);
    if (rc != want_rc)
        fprintf(stderr, "seeds case %s: rc %d, want %d (%s)\n", name, rc, want_rc, err.msg);
    CHECK(rc == want_rc);
    if (want_rc) {
        CHECK_MSG(strstr(err.msg, p) != NULL, err.msg);
        if (want_in_msg)
            CHECK_MSG(strstr(err.msg, want_in_msg) != NULL, err.msg);
        CHECK(s.n == 0 && s.xyz == NULL && s.label == NULL);
        printf("expected error: %s\n", err.msg);
    } else {
        CHECK(s.n == want_n);
    }
    vc_seeds_free(&s);
    remove(p);
    free(p);
}

static void test_seeds_read(void)
{
    /* good files */
    seeds_case("io_s_ok3.csv", "x,y,z\n1,2,3\n4.5,-6e-3,7\n", 0, NULL, 2);
    seeds_case("io_s_ok4.csv", "x,y,z,label\r\n1,2,3,4\r\n 5 , 6 ,7, 0 \r\n\r\n", 0, NULL, 2);
    seeds_case("io_s_noeol.csv", "\xEF\xBB\xBFx,y,z\n1,2,3", 0, NULL, 1);
    seeds_case("io_s_header_only.csv", "x,y,z\n", 0, NULL, 0);
    seeds_case("io_s_blank.csv", "\n  \nx,y,z\n\n1,2,3\n\n4,5,6\n", 0, NULL, 2);
    {
        vc_error err = {0, ""};
        char *p = path_in(tmpdir, "io_s_vals.csv");
        write_text(p, "px,py,pz,region\n0.25,-1e300,0x1p-3,-7\n");
        vc_seeds s;
        int rc = vc_seeds_read_csv(p, &s, &err);
        CHECK_MSG(rc == 0, err.msg);
        if (!rc) {
            CHECK(s.n == 1 && s.xyz[0] == 0.25 && s.xyz[1] == -1e300 && s.xyz[2] == 0.125);
            CHECK(s.label[0] == -7);
        }
        vc_seeds_free(&s);
        write_text(p, "x,y,z\n1,2,3\n");
        rc = vc_seeds_read_csv(p, &s, &err);
        CHECK(rc == 0 && s.n == 1 && s.label[0] == 1);
        vc_seeds_free(&s);
        remove(p);
        free(p);
    }

    /* bad files */
    seeds_case("io_s_missing.csv", NULL, VC_EIO, strerror(ENOENT), 0);
    seeds_case("io_s_empty.csv", "", VC_EFORMAT, "empty", 0);
    seeds_case("io_s_blankonly.csv", "\n \n", VC_EFORMAT, "empty", 0);
    seeds_case("io_s_noheader.csv", "1,2,3\n4,5,6\n", VC_EFORMAT, ":1: missing header", 0);
    seeds_case("io_s_fields2.csv", "x,y,z\n1,2,3\n4,5,6\n7,8\n", VC_EFORMAT, ":4:", 0);
    seeds_case("io_s_fields5.csv", "x,y,z\n1,2,3,4,5\n", VC_EFORMAT, ":2: expected 3 or 4", 0);
    seeds_case("io_s_mixed.csv", "x,y,z\n1,2,3\n1,2,3,4\n", VC_EFORMAT, ":3: expected 3", 0);
    seeds_case("io_s_word.csv", "x,y,z\n1,2,3\n1,abc,3\n", VC_EFORMAT, ":3: field 2 \"abc\"", 0);
    seeds_case("io_s_emptyfield.csv", "x,y,z\n1,,3\n", VC_EFORMAT, ":2: field 2", 0);
    seeds_case("io_s_trailing.csv", "x,y,z\n1,2,3\n1,2,3,\n", VC_EFORMAT, ":3: label", 0);
    seeds_case("io_s_nan.csv", "x,y,z\n1,2,3\n\n1,nan,3\n", VC_EINPUT, ":4: field 2", 0);
    seeds_case("io_s_inf.csv", "x,y,z\n-inf,2,3\n", VC_EINPUT, "not finite", 0);
    seeds_case("io_s_huge.csv", "x,y,z\n1e999,2,3\n", VC_EINPUT, ":2: field 1", 0);
    seeds_case("io_s_label.csv", "x,y,z,label\n1,2,3,1.5\n", VC_EFORMAT, ":2: label \"1.5\"", 0);
    seeds_case("io_s_label_big.csv", "x,y,z,label\n1,2,3,3000000000\n", VC_EFORMAT, ":2: label",
               0);
}

/* 1e6 rows: write and read back, timed (informative). */
static void test_seeds_large(void)
{
    vc_error err = {0, ""};
    vc_seeds s;
    const int64_t n = 1000000;
    if (vc_seeds_alloc(&s, n, &err))
        return;
    for (int64_t i = 0; i < n; ++i) {
        s.xyz[3 * i] = sin((double)i);
        s.xyz[3 * i + 1] = cos((double)i) * 1e3;
        s.xyz[3 * i + 2] = (double)i / 7.0;
        s.label[i] = (int32_t)(i % 5);
    }
    char *p = path_in(tmpdir, "io_seeds_large.csv");
    int rc = vc_seeds_write_csv(p, &s, &err);
    CHECK_MSG(rc == 0, err.msg);
    vc_seeds r;
    rc = vc_seeds_read_csv(p, &r, &err);
    CHECK_MSG(rc == 0, err.msg);
    if (!rc) {
        CHECK(r.n == n);
        CHECK(memcmp(r.xyz, s.xyz, sizeof(double) * 3 * (size_t)n) == 0);
        CHECK(memcmp(r.label, s.label, sizeof(int32_t) * (size_t)n) == 0);
    }
    vc_seeds_free(&r);
    vc_seeds_free(&s);
    remove(p);
    free(p);
}

int main(void)
{
    tmpdir = getenv("VC_TMP");
    if (!tmpdir || !*tmpdir)
        tmpdir = ".";
    test_two_cubes_mesh_shape();
    test_vtu_write();
    test_vtu_grid();
    test_seeds_roundtrip();
    test_seeds_read();
    test_seeds_large();
    if (failures) {
        fprintf(stderr, "test_io: %d check(s) failed\n", failures);
        return 1;
    }
    printf("test_io: all checks passed\n");
    return 0;
}
