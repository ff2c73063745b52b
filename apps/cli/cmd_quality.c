/* vorocrust quality: the quality report of a polyhedral or tetrahedral
 * .vtu mesh, optionally against the input surface it approximates. */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "commands.h"
#include "vorocrust/quality.h"
#include "vorocrust/surface.h"
#include "vorocrust/vtu_reader.h"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vorocrust quality MESH.vtu [--input SURFACE] [--threads N]\n"
        "  MESH.vtu          VTK XML unstructured grid of polyhedra (42) and/or tetrahedra (10)\n"
        "  --input SURFACE   also the two-sided Hausdorff distance between the mesh boundary\n"
        "                    and this surface (.obj, .off, .stl, .ply), normalised by the\n"
        "                    surface's bounding-box diagonal\n"
        "  --threads N       threads (default: all cores); the report does not depend on it\n"
        "Prints cell counts, total volume and, as min, max, mean and percentiles p1, p5,\n"
        "p50, p95, p99: cell volume, fatness (minimum enclosing ball radius / maximum\n"
        "inscribed ball radius), shortest edge / enclosing radius, and for tetrahedra the\n"
        "smallest and largest dihedral angle per cell. The boundary (faces of one cell,\n"
        "polygons fanned from their centroid) gives the triangle quality\n"
        "Q = 6 S / (sqrt(3) h P) and the percentages of angles below 30 and above 90 degrees.\n");
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void print_stats(const char *name, const double *v, int64_t n)
{
    vc_stats st;
    if (vc_stats_compute(v, n, &st) != 0) {
        printf("%s: (out of memory)\n", name);
        return;
    }
    if (st.n == 0) {
        printf("%s: none\n", name);
        return;
    }
    printf("%s: min %.6g, max %.6g, mean %.6g, p1 %.6g, p5 %.6g, p50 %.6g, p95 %.6g, p99 %.6g\n",
           name, st.min, st.max, st.mean, st.p1, st.p5, st.p50, st.p95, st.p99);
}

/* ---- closed, consistently oriented cells ------------------------------------ */

typedef struct cell_edge {
    int64_t from, to; /* from = -1: empty slot */
} cell_edge;

/* Slots of the edge hash table for cells of up to `corners` face-vertex
 * entries: a power of two at least twice that. */
static int64_t edge_table_size(int64_t corners)
{
    int64_t size = 16;
    while (size < 2 * corners)
        size *= 2;
    return size;
}

static int64_t edge_slot(const cell_edge *table, int64_t mask, int64_t from, int64_t to)
{
    uint64_t h = (uint64_t)from * 0x9e3779b97f4a7c15ULL ^ (uint64_t)to * 0xc2b2ae3d27d4eb4fULL;
    int64_t i = (int64_t)(h >> 17) & mask;
    while (table[i].from >= 0 && (table[i].from != from || table[i].to != to))
        i = (i + 1) & mask;
    return i;
}

/* Whether every edge of cell c is walked exactly twice, once each way (a
 * closed surface with consistently oriented faces, which the volume and
 * the face planes rely on): every directed edge appears once and so does
 * its reverse. table has edge_table_size(corners of c) slots. */
static int cell_is_closed(const vc_vtu_mesh *m, int64_t c, cell_edge *table)
{
    int64_t corners = m->face_offsets[m->cell_faces[c + 1]] - m->face_offsets[m->cell_faces[c]];
    int64_t size = edge_table_size(corners), mask = size - 1;
    for (int64_t i = 0; i < size; i++)
        table[i].from = -1;
    if (corners == 0 || corners % 2)
        return 0;
    for (int64_t f = m->cell_faces[c]; f < m->cell_faces[c + 1]; f++) {
        int64_t b = m->face_offsets[f], e = m->face_offsets[f + 1];
        for (int64_t k = b; k < e; k++) {
            int64_t u = m->face_vertices[k], v = m->face_vertices[k + 1 < e ? k + 1 : b];
            int64_t i = edge_slot(table, mask, u, v);
            if (u == v || table[i].from >= 0)
                return 0; /* a repeated vertex, or the same edge walked twice the same way */
            table[i].from = u;
            table[i].to = v;
        }
    }
    for (int64_t i = 0; i < size; i++)
        if (table[i].from >= 0 && table[edge_slot(table, mask, table[i].to, table[i].from)].from < 0)
            return 0;
    return 1;
}

/* ---- boundary faces: faces listed by exactly one cell ------------------------ */

typedef struct face_key {
    uint64_t hash;
    int64_t face;
} face_key;

/* The face's ids sorted into buf (faces are small: insertion sort). */
static int64_t sorted_ids(const vc_vtu_mesh *m, int64_t f, int64_t *buf)
{
    int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
    for (int64_t i = 0; i < n; i++) {
        int64_t x = m->face_vertices[m->face_offsets[f] + i], j = i;
        while (j > 0 && buf[j - 1] > x) {
            buf[j] = buf[j - 1];
            j--;
        }
        buf[j] = x;
    }
    return n;
}

/* Stable LSD radix sort of the keys by hash, 16 bits per pass: equal
 * hashes keep face order, so the result is deterministic. */
static int radix_sort_keys(face_key *key, int64_t n)
{
    face_key *tmp = malloc(sizeof *tmp * (size_t)(n ? n : 1));
    int64_t *count = malloc(sizeof *count * 65536);
    if (!tmp || !count) {
        free(tmp);
        free(count);
        return -1;
    }
    for (int shift = 0; shift < 64; shift += 16) {
        memset(count, 0, sizeof *count * 65536);
        for (int64_t i = 0; i < n; i++)
            count[(key[i].hash >> shift) & 0xffff]++;
        int64_t sum = 0;
        for (int d = 0; d < 65536; d++) {
            int64_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (int64_t i = 0; i < n; i++)
            tmp[count[(key[i].hash >> shift) & 0xffff]++] = key[i];
        face_key *t = key;
        memcpy(t, tmp, sizeof *tmp * (size_t)n);
    }
    free(tmp);
    free(count);
    return 0;
}

/* Sets uses[f] to the number of faces (itself included) with the same
 * vertex set; returns the number of distinct faces, or -1 (out of memory).
 * Faces are bucketed by a hash of their sorted ids, then compared exactly
 * within each bucket (buckets in parallel: each owns its faces). */
static int64_t count_face_uses(const vc_vtu_mesh *m, int64_t *uses)
{
    int64_t nf = m->n_faces, maxlen = 0;
    for (int64_t f = 0; f < nf; f++)
        if (m->face_offsets[f + 1] - m->face_offsets[f] > maxlen)
            maxlen = m->face_offsets[f + 1] - m->face_offsets[f];
    face_key *key = malloc(sizeof *key * (size_t)(nf ? nf : 1));
    int64_t *run = malloc(sizeof *run * (size_t)(nf + 1));
    if (!key || !run) {
        free(key);
        free(run);
        return -1;
    }
    int oom = 0;
#pragma omp parallel reduction(| : oom)
    {
        int64_t *a = malloc(sizeof *a * (size_t)(maxlen + 1));
        oom |= !a;
#pragma omp for schedule(static)
        for (int64_t f = 0; f < nf; f++) {
            if (!a)
                continue;
            int64_t n = sorted_ids(m, f, a);
            uint64_t h = 1469598103934665603ULL ^ (uint64_t)n;
            for (int64_t i = 0; i < n; i++) {
                h ^= (uint64_t)a[i] + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
                h *= 1099511628211ULL;
            }
            key[f].hash = h;
            key[f].face = f;
        }
        free(a);
    }
    if (oom || radix_sort_keys(key, nf) != 0) {
        free(key);
        free(run);
        return -1;
    }
    int64_t nrun = 0;
    for (int64_t i = 0; i < nf; i++)
        if (i == 0 || key[i].hash != key[i - 1].hash)
            run[nrun++] = i;
    run[nrun] = nf;
    int64_t distinct = 0;
#pragma omp parallel reduction(+ : distinct) reduction(| : oom)
    {
        int64_t *a = malloc(sizeof *a * (size_t)(2 * maxlen + 2));
        oom |= !a;
#pragma omp for schedule(dynamic, 4096)
        for (int64_t r = 0; r < nrun; r++) {
            if (!a)
                continue;
            int64_t *b = a + maxlen + 1;
            int64_t i = run[r], j = run[r + 1];
            /* group exactly equal vertex sets (runs are almost always 1 or
             * 2 long) */
            for (int64_t k = i; k < j; k++)
                uses[key[k].face] = 0;
            for (int64_t k = i; k < j; k++) {
                if (uses[key[k].face])
                    continue;
                int64_t nk = sorted_ids(m, key[k].face, a), count = 1;
                for (int64_t l = k + 1; l < j; l++) {
                    if (uses[key[l].face])
                        continue;
                    int64_t nl = sorted_ids(m, key[l].face, b);
                    if (nl == nk && !memcmp(a, b, sizeof *a * (size_t)nk))
                        count++, uses[key[l].face] = -1;
                }
                uses[key[k].face] = count;
                for (int64_t l = k + 1; l < j; l++)
                    if (uses[key[l].face] == -1)
                        uses[key[l].face] = count;
                distinct++;
            }
        }
        free(a);
    }
    free(key);
    free(run);
    return oom ? -1 : distinct;
}

/* The boundary faces as a triangle surface on the mesh points (polygons
 * fanned from their vertex average, which is appended as a point). */
static int boundary_surface(const vc_vtu_mesh *m, const int64_t *uses, vc_surface *s)
{
    int64_t nt = 0, nextra = 0;
    for (int64_t f = 0; f < m->n_faces; f++) {
        if (uses[f] != 1)
            continue;
        int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
        nt += n == 3 ? 1 : n;
        nextra += n == 3 ? 0 : 1;
    }
    s->n_vertices = m->n_points + nextra;
    s->n_triangles = nt;
    s->xyz = malloc(sizeof(double) * 3 * (size_t)(s->n_vertices ? s->n_vertices : 1));
    s->tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt ? nt : 1));
    if (!s->xyz || !s->tri)
        return -1;
    memcpy(s->xyz, m->points, sizeof(double) * 3 * (size_t)m->n_points);
    int64_t t = 0, v = m->n_points;
    for (int64_t f = 0; f < m->n_faces; f++) {
        if (uses[f] != 1)
            continue;
        const int64_t *id = m->face_vertices + m->face_offsets[f];
        int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
        if (n == 3) {
            memcpy(s->tri + 3 * t++, id, 3 * sizeof *id);
            continue;
        }
        double *c = s->xyz + 3 * v;
        c[0] = c[1] = c[2] = 0;
        for (int64_t i = 0; i < n; i++)
            for (int d = 0; d < 3; d++)
                c[d] += m->points[3 * id[i] + d] / (double)n;
        for (int64_t i = 0; i < n; i++) {
            s->tri[3 * t] = v;
            s->tri[3 * t + 1] = id[i];
            s->tri[3 * t + 2] = id[(i + 1) % n];
            t++;
        }
        v++;
    }
    return 0;
}

int vc_cmd_quality(int argc, char **argv)
{
    const char *mesh_path = NULL, *input_path = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--input") || !strcmp(a, "--threads")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "vorocrust: %s needs a value (see 'vorocrust quality --help')\n", a);
                return 2;
            }
            const char *v = argv[++i];
            if (!strcmp(a, "--input")) {
                input_path = v;
                continue;
            }
            char *end;
            errno = 0;
            long t = strtol(v, &end, 10);
            if (errno || end == v || *end || t < 1 || t > 4096) {
                fprintf(stderr, "vorocrust: --threads: '%s' is not a count from 1 to 4096\n", v);
                return 2;
            }
#ifdef _OPENMP
            omp_set_num_threads((int)t);
#endif
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "vorocrust: unknown option '%s' (see 'vorocrust quality --help')\n", a);
            return 2;
        } else if (!mesh_path) {
            mesh_path = a;
        } else {
            fprintf(stderr, "vorocrust: unexpected argument '%s'\n", a);
            return 2;
        }
    }
    if (!mesh_path) {
        fprintf(stderr, "vorocrust: missing the mesh MESH.vtu (see 'vorocrust quality --help')\n");
        return 2;
    }

    vc_error err = {0, ""};
    vc_vtu_mesh m;
    vc_surface input = {0, NULL, 0, NULL}, boundary = {0, NULL, 0, NULL};
    vc_surface_report rep;
    double *vol = NULL, *fat = NULL, *rel = NULL, *dmin = NULL, *dmax = NULL, *q = NULL;
    int64_t *uses = NULL;
    unsigned char *open_flag = NULL;
    int rc = 1;
    double t0 = now();
    memset(&m, 0, sizeof m);
    /* The input first: it is usually the smaller file, so a bad one fails fast. */
    if (input_path) {
        if (vc_surface_read(input_path, &input, &rep, &err) != 0) {
            fprintf(stderr, "vorocrust: %s\n", err.msg);
            goto out;
        }
        for (int i = 0; i < rep.n_warnings; i++)
            fprintf(stderr, "vorocrust: warning: %s\n", rep.warnings[i]);
    }
    if (vc_vtu_read(mesh_path, &m, &err) != 0) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        goto out;
    }
    if (m.n_skipped)
        fprintf(stderr, "vorocrust: warning: %s: %" PRId64 " cells of other types skipped "
                "(first: VTK cell type %d); only polyhedra (42) and tetrahedra (10) are measured\n",
                mesh_path, m.n_skipped, m.first_skipped_type);

    double t_read = now();
    const int64_t nc = m.n_cells;
    int64_t n_tet = 0;
    for (int64_t c = 0; c < nc; c++)
        n_tet += m.cell_type[c] == VC_VTK_TETRA;
    size_t cn = (size_t)nc;
    vol = malloc(sizeof *vol * cn);
    fat = malloc(sizeof *fat * cn);
    rel = malloc(sizeof *rel * cn);
    dmin = malloc(sizeof *dmin * cn);
    dmax = malloc(sizeof *dmax * cn);
    uses = malloc(sizeof *uses * (size_t)(m.n_faces ? m.n_faces : 1));
    open_flag = calloc(cn ? cn : 1, 1);
    if (!vol || !fat || !rel || !dmin || !dmax || !uses || !open_flag) {
        fprintf(stderr, "vorocrust: %s: out of memory\n", mesh_path);
        goto out;
    }
    int64_t n_failed = 0, n_inverted = 0, first_failed = -1, n_open = 0, first_open = -1;
    int64_t max_corners = 0; /* face-vertex entries of the largest cell */
    for (int64_t c = 0; c < nc; c++) {
        int64_t k = m.face_offsets[m.cell_faces[c + 1]] - m.face_offsets[m.cell_faces[c]];
        max_corners = k > max_corners ? k : max_corners;
    }
    int oom = 0;
#pragma omp parallel reduction(+ : n_failed, n_inverted, n_open) reduction(| : oom)
    {
    cell_edge *edges = malloc(sizeof *edges * (size_t)edge_table_size(max_corners));
    oom |= !edges;
#pragma omp for schedule(dynamic, 64)
    for (int64_t c = 0; c < nc; c++) {
        if (!edges)
            continue;
        if (!cell_is_closed(&m, c, edges)) {
            n_open++;
            open_flag[c] = 1;
        }
        vc_cell cell;
        cell.points = m.points;
        cell.n_vertices = 0;
        cell.vertices = NULL;
        cell.n_faces = m.cell_faces[c + 1] - m.cell_faces[c];
        cell.face_offsets = m.face_offsets + m.cell_faces[c];
        cell.face_vertices = m.face_vertices;
        vc_cell_measures cm;
        double signed_volume;
        if (vc_cell_measure(&cell, &cm) == 0) {
            signed_volume = cm.signed_volume;
            fat[c] = cm.fatness;
            rel[c] = cm.shortest_edge_rel;
        } else {
            signed_volume = vc_cell_volume(&cell, NULL);
            fat[c] = rel[c] = NAN; /* left out of the statistics, counted */
            n_failed++;
        }
        n_inverted += signed_volume < 0;
        vol[c] = fabs(signed_volume);
        dmin[c] = dmax[c] = NAN;
        if (m.cell_type[c] == VC_VTK_TETRA) {
            /* the reader's first face is (1, 2, 3), the second starts with 0 */
            const int64_t *id = m.face_vertices + m.face_offsets[m.cell_faces[c]];
            int64_t ids[4] = {m.face_vertices[m.face_offsets[m.cell_faces[c] + 1]], id[0], id[1],
                              id[2]};
            double p[4][3], deg[6];
            for (int k = 0; k < 4; k++)
                memcpy(p[k], m.points + 3 * ids[k], sizeof p[k]);
            vc_tetra_dihedral_angles(p, deg, &dmin[c], &dmax[c]);
        }
    }
    free(edges);
    }
    if (oom) {
        fprintf(stderr, "vorocrust: %s: out of memory\n", mesh_path);
        goto out;
    }
    for (int64_t c = 0; c < nc && n_open; c++)
        if (open_flag[c]) {
            first_open = m.cell_file_index[c];
            break;
        }
    for (int64_t c = 0; c < nc && n_failed; c++)
        if (isnan(fat[c])) {
            first_failed = m.cell_file_index[c];
            break;
        }
    double total_volume = 0;
    for (int64_t c = 0; c < nc; c++)
        total_volume += vol[c];
    double t_cells = now();

    int64_t distinct = count_face_uses(&m, uses);
    if (distinct < 0 || boundary_surface(&m, uses, &boundary) != 0) {
        fprintf(stderr, "vorocrust: %s: out of memory\n", mesh_path);
        goto out;
    }
    int64_t n_bfaces = 0, n_shared_more = 0;
    for (int64_t f = 0; f < m.n_faces; f++) {
        n_bfaces += uses[f] == 1;
        n_shared_more += uses[f] > 2;
    }
    const int64_t nt = boundary.n_triangles;
    q = malloc(sizeof *q * (size_t)(nt ? nt : 1));
    if (!q) {
        fprintf(stderr, "vorocrust: %s: out of memory\n", mesh_path);
        goto out;
    }
    int64_t below30 = 0, above90 = 0;
#pragma omp parallel for schedule(static) reduction(+ : below30, above90)
    for (int64_t t = 0; t < nt; t++) {
        const double *a = boundary.xyz + 3 * boundary.tri[3 * t];
        const double *b = boundary.xyz + 3 * boundary.tri[3 * t + 1];
        const double *c = boundary.xyz + 3 * boundary.tri[3 * t + 2];
        double deg[3];
        q[t] = vc_triangle_quality(a, b, c);
        vc_triangle_angles(a, b, c, deg);
        for (int k = 0; k < 3; k++) {
            below30 += deg[k] < 30;
            above90 += deg[k] > 90;
        }
    }
    double t_boundary = now();
    vc_hausdorff_result hd;
    if (input_path) {
        if (nt == 0) {
            fprintf(stderr, "vorocrust: %s: the mesh has no boundary face to compare with %s\n",
                    mesh_path, input_path);
            goto out;
        }
        if (vc_hausdorff(&input, &boundary, 0, &hd, &err) != 0) {
            fprintf(stderr, "vorocrust: %s: %s\n", mesh_path, err.msg);
            goto out;
        }
    }
    double t1 = now();

    printf("file: %s\n", mesh_path);
    printf("cells: %" PRId64 " (%" PRId64 " polyhedra, %" PRId64 " tetrahedra)\n", nc, nc - n_tet,
           n_tet);
    if (m.n_skipped)
        printf("skipped cells: %" PRId64 " (other cell types)\n", m.n_skipped);
    printf("vertices: %" PRId64 "\n", m.n_points);
    printf("faces: %" PRId64 " (%" PRId64 " boundary)\n", distinct, n_bfaces);
    if (n_shared_more)
        printf("faces shared by more than two cells: %" PRId64 "\n", n_shared_more);
    if (n_open)
        printf("open cells: %" PRId64 " (an edge not shared by exactly two faces in opposite "
               "directions: volume and fatness unreliable; first: cell %" PRId64 ")\n", n_open,
               first_open);
    if (n_inverted)
        printf("inverted cells: %" PRId64 " (faces listed inward)\n", n_inverted);
    if (n_failed)
        printf("unmeasured cells: %" PRId64 " (no inscribed ball: open or degenerate; first: cell %"
               PRId64 ")\n", n_failed, first_failed);
    printf("total volume: %.17g\n", total_volume);
    print_stats("volume", vol, nc);
    print_stats("fatness", fat, nc);
    print_stats("shortest relative edge", rel, nc);
    if (n_tet) {
        print_stats("dihedral angle min", dmin, nc);
        print_stats("dihedral angle max", dmax, nc);
    }
    printf("boundary triangles: %" PRId64 "\n", nt);
    if (nt) {
        print_stats("triangle quality", q, nt);
        printf("angles below 30 degrees: %.4f%%\n", 100.0 * (double)below30 / (3.0 * (double)nt));
        printf("angles above 90 degrees: %.4f%%\n", 100.0 * (double)above90 / (3.0 * (double)nt));
    }
    if (input_path) {
        printf("input: %s\n", input_path);
        printf("hausdorff distance: %.6g (normalised by the input's bounding-box diagonal %.6g: %.6g)\n",
               hd.distance, hd.diagonal, hd.normalised);
        printf("hausdorff input to mesh: %.6g, mesh to input: %.6g, sampling error at most %.3g "
               "(%" PRId64 " + %" PRId64 " samples)\n", hd.a_to_b, hd.b_to_a, hd.error_bound,
               hd.n_samples_a, hd.n_samples_b);
    }
    printf("time: %.3f s (read %.3f s, cells %.3f s, boundary %.3f s, hausdorff %.3f s)\n", t1 - t0,
           t_read - t0, t_cells - t_read, t_boundary - t_cells, t1 - t_boundary);
    rc = 0;
out:
    vc_vtu_mesh_free(&m);
    vc_surface_free(&input);
    vc_surface_free(&boundary);
    free(vol);
    free(fat);
    free(rel);
    free(dmin);
    free(dmax);
    free(q);
    free(uses);
    free(open_flag);
    return rc;
}
