/* The quality report of a mesh read from a .vtu file: every cell measured
 * (checked closed first: the volume and the face planes rely on it), the
 * boundary's triangle quality and angles, and the Hausdorff distance to the
 * input surface. */
#include "vorocrust/mesh_report.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "quality_internal.h"
#include "util/clock.h"

#define DEG_PER_RAD 57.295779513082320876798

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

/* ---- the report -------------------------------------------------------------- */

void vc_mesh_report_free(vc_mesh_report *r)
{
    if (!r)
        return;
    free(r->cell_fatness);
    free(r->triangle_qualities);
    memset(r, 0, sizeof *r);
}

/* Measures every cell: fills fat (r->cell_fatness), rel, vol, dmin, dmax
 * (NaN when not a tetrahedron) and the cell counts of r. Returns 0 or -1
 * (out of memory). */
/* Area of face f of m (half the norm of its Newell normal). */
static double face_area(const vc_vtu_mesh *m, int64_t f)
{
    double n[3] = {0, 0, 0};
    const int64_t b = m->face_offsets[f], e = m->face_offsets[f + 1];
    for (int64_t k = b; k < e; k++) {
        const double *p = m->points + 3 * m->face_vertices[k];
        const double *q = m->points + 3 * m->face_vertices[k + 1 < e ? k + 1 : b];
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Cell c of m as the quality library sees it. */
static vc_cell cell_of_mesh(const vc_vtu_mesh *m, int64_t c)
{
    vc_cell cell;
    cell.points = m->points;
    cell.n_vertices = 0;
    cell.vertices = NULL;
    cell.n_faces = m->cell_faces[c + 1] - m->cell_faces[c];
    cell.face_offsets = m->face_offsets + m->cell_faces[c];
    cell.face_vertices = m->face_vertices;
    return cell;
}

static int measure_cells(const vc_vtu_mesh *m, vc_mesh_report *r, double *vol, double *rel,
                         double *small, double *rad, double *dmin, double *dmax)
{
    const int64_t nc = m->n_cells;
    double *fat = r->cell_fatness;
    unsigned char *open_flag = calloc(nc ? (size_t)nc : 1, 1);
    if (!open_flag)
        return -1;
    int64_t n_failed = 0, n_inverted = 0, n_open = 0, n_tet = 0;
    int64_t max_corners = 0; /* face-vertex entries of the largest cell */
    for (int64_t c = 0; c < nc; c++) {
        int64_t k = m->face_offsets[m->cell_faces[c + 1]] - m->face_offsets[m->cell_faces[c]];
        max_corners = k > max_corners ? k : max_corners;
        n_tet += m->cell_type[c] == VC_VTK_TETRA;
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
        if (!cell_is_closed(m, c, edges)) {
            n_open++;
            open_flag[c] = 1;
        }
        vc_cell cell = cell_of_mesh(m, c);
        vc_cell_measures cm;
        double signed_volume;
        if (vc_cell_measure(&cell, &cm) == 0) {
            signed_volume = cm.signed_volume;
            fat[c] = cm.fatness;
            rel[c] = cm.shortest_edge_rel;
            double a = INFINITY;
            for (int64_t f = m->cell_faces[c]; f < m->cell_faces[c + 1]; f++)
                a = fmin(a, face_area(m, f));
            const double rr = cm.enclosing.radius;
            small[c] = rr > 0 ? a / (rr * rr) : NAN;
            rad[c] = rr;
        } else {
            signed_volume = vc_cell_volume(&cell, NULL);
            fat[c] = rel[c] = small[c] = rad[c] = NAN; /* left out of the statistics, counted */
            n_failed++;
        }
        n_inverted += signed_volume < 0;
        vol[c] = fabs(signed_volume);
        dmin[c] = dmax[c] = NAN;
        if (m->cell_type[c] == VC_VTK_TETRA) {
            /* the reader's first face is (1, 2, 3), the second starts with 0 */
            const int64_t *id = m->face_vertices + m->face_offsets[m->cell_faces[c]];
            int64_t ids[4] = {m->face_vertices[m->face_offsets[m->cell_faces[c] + 1]], id[0],
                              id[1], id[2]};
            double p[4][3], deg[6];
            for (int k = 0; k < 4; k++)
                memcpy(p[k], m->points + 3 * ids[k], sizeof p[k]);
            vc_tetra_dihedral_angles(p, deg, &dmin[c], &dmax[c]);
        }
    }
    free(edges);
    }
    r->n_cells = nc;
    r->n_tetrahedra = n_tet;
    r->n_open_cells = n_open;
    r->n_inverted_cells = n_inverted;
    r->n_unmeasured_cells = n_failed;
    r->first_open_cell = r->first_unmeasured_cell = -1;
    for (int64_t c = 0; c < nc && n_open; c++)
        if (open_flag[c]) {
            r->first_open_cell = m->cell_file_index[c];
            break;
        }
    for (int64_t c = 0; c < nc && n_failed; c++)
        if (isnan(fat[c])) {
            r->first_unmeasured_cell = m->cell_file_index[c];
            break;
        }
    r->total_volume = 0;
    for (int64_t c = 0; c < nc; c++)
        r->total_volume += vol[c];
    free(open_flag);
    return oom ? -1 : 0;
}

/* The boundary triangles' quality (r->triangle_qualities, allocated here)
 * and angle percentages. Returns 0 or -1 (out of memory). */
static int measure_boundary(const vc_surface *boundary, vc_mesh_report *r)
{
    const int64_t nt = boundary->n_triangles;
    double *q = malloc(sizeof *q * (size_t)(nt ? nt : 1));
    if (!q)
        return -1;
    r->triangle_qualities = q;
    r->n_boundary_triangles = nt;
    int64_t below30 = 0, above90 = 0;
#pragma omp parallel for schedule(static) reduction(+ : below30, above90)
    for (int64_t t = 0; t < nt; t++) {
        const double *a = boundary->xyz + 3 * boundary->tri[3 * t];
        const double *b = boundary->xyz + 3 * boundary->tri[3 * t + 1];
        const double *c = boundary->xyz + 3 * boundary->tri[3 * t + 2];
        double deg[3];
        q[t] = vc_triangle_quality(a, b, c);
        vc_triangle_angles(a, b, c, deg);
        for (int k = 0; k < 3; k++) {
            below30 += deg[k] < 30;
            above90 += deg[k] > 90;
        }
    }
    r->angles_below_30 = nt ? 100.0 * (double)below30 / (3.0 * (double)nt) : NAN;
    r->angles_above_90 = nt ? 100.0 * (double)above90 / (3.0 * (double)nt) : NAN;
    return vc_stats_compute(q, nt, &r->triangle_quality) ? -1 : 0;
}

/* Face f's area centroid and area vector (fanned from its vertex average). */
static void face_geometry(const vc_vtu_mesh *m, int64_t f, double c[3], double s[3])
{
    const int64_t b = m->face_offsets[f], n = m->face_offsets[f + 1] - b;
    double o[3] = {0, 0, 0};
    for (int64_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            o[k] += m->points[3 * m->face_vertices[b + i] + k] / (double)n;
    double a_sum = 0;
    c[0] = c[1] = c[2] = s[0] = s[1] = s[2] = 0;
    for (int64_t i = 0; i < n; i++) {
        const double *p = m->points + 3 * m->face_vertices[b + i];
        const double *q = m->points + 3 * m->face_vertices[b + (i + 1) % n];
        const double u[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
        const double v[3] = {q[0] - o[0], q[1] - o[1], q[2] - o[2]};
        const double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                             u[0] * v[1] - u[1] * v[0]};
        const double a = 0.5 * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        for (int k = 0; k < 3; k++) {
            s[k] += 0.5 * x[k];
            c[k] += a * (o[k] + p[k] + q[k]) / 3;
        }
        a_sum += a;
    }
    for (int k = 0; k < 3; k++)
        c[k] = a_sum > 0 ? c[k] / a_sum : o[k];
}

/* checkMesh's measures of the faces between two cells: non-orthogonality
 * (the angle between the face's area vector and the line between the
 * cells' centroids; the mean as checkMesh prints it, the angle of the mean
 * cosine) and skewness (the distance from the face centroid to where that
 * line crosses the face's plane, over the larger of a fifth of the
 * centroids' distance and the face's extent that way). */
static int solver_measures(const vc_vtu_mesh *m, const int64_t *twin, const double *rad,
                           vc_mesh_report *r)
{
    const int64_t nc = m->n_cells, nf = m->n_faces;
    double *centre = malloc(sizeof(double) * 3 * (size_t)(nc + 1));
    int64_t *cell_of = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    /* per face: the connection's length over the cells' size (NaN but on
     * one copy of each face between two cells, and without the seeds) */
    double *conn = m->cell_seed_point ? malloc(sizeof(double) * (size_t)(nf + 1)) : NULL;
    if (!centre || !cell_of || (m->cell_seed_point && !conn)) {
        free(centre);
        free(cell_of);
        free(conn);
        return -1;
    }
#pragma omp parallel for schedule(dynamic, 256)
    for (int64_t c = 0; c < nc; c++) {
        vc_cell cell = cell_of_mesh(m, c);
        vc_cell_volume(&cell, centre + 3 * c);
        for (int64_t f = m->cell_faces[c]; f < m->cell_faces[c + 1]; f++)
            cell_of[f] = c;
    }
    double max_angle = 0, sum_cos = 0, max_skew = 0;
    int64_t n = 0, n_skew = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(max : max_angle, max_skew) \
    reduction(+ : sum_cos, n, n_skew)
    for (int64_t f = 0; f < nf; f++) {
        const int64_t g = twin[f];
        if (conn)
            conn[f] = NAN;
        if (g < 0 || g < f)
            continue; /* boundary, or the pair seen from its other copy */
        if (conn) {
            const double *sa = m->cell_seed_point + 3 * cell_of[f],
                         *sb = m->cell_seed_point + 3 * cell_of[g];
            const double mean_r = 0.5 * (rad[cell_of[f]] + rad[cell_of[g]]);
            const double ds[3] = {sb[0] - sa[0], sb[1] - sa[1], sb[2] - sa[2]};
            conn[f] = mean_r > 0 ? sqrt(ds[0] * ds[0] + ds[1] * ds[1] + ds[2] * ds[2]) / mean_r
                                 : NAN;
        }
        const double *co = centre + 3 * cell_of[f], *cn = centre + 3 * cell_of[g];
        double fc[3], sv[3];
        face_geometry(m, f, fc, sv); /* outward of cell_of[f]: towards cn */
        const double d[3] = {cn[0] - co[0], cn[1] - co[1], cn[2] - co[2]};
        const double sl = sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]);
        const double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(sl > 0 && dl > 0))
            continue;
        double cs = (sv[0] * d[0] + sv[1] * d[1] + sv[2] * d[2]) / (sl * dl);
        cs = cs > 1 ? 1 : cs < -1 ? -1 : cs;
        max_angle = fmax(max_angle, acos(cs) * DEG_PER_RAD);
        sum_cos += cs;
        n++;
        /* skewness */
        const double nn[3] = {sv[0] / sl, sv[1] / sl, sv[2] / sl};
        const double cpf[3] = {fc[0] - co[0], fc[1] - co[1], fc[2] - co[2]};
        const double dn = nn[0] * d[0] + nn[1] * d[1] + nn[2] * d[2];
        double skew = INFINITY;
        if (dn != 0) {
            const double t = (nn[0] * cpf[0] + nn[1] * cpf[1] + nn[2] * cpf[2]) / dn;
            const double w[3] = {cpf[0] - t * d[0], cpf[1] - t * d[1], cpf[2] - t * d[2]};
            const double s = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            double extent = 0.2 * dl;
            for (int64_t i = m->face_offsets[f]; s > 0 && i < m->face_offsets[f + 1]; i++) {
                const double *p = m->points + 3 * m->face_vertices[i];
                const double q[3] = {p[0] - fc[0], p[1] - fc[1], p[2] - fc[2]};
                extent = fmax(extent, fabs(w[0] * q[0] + w[1] * q[1] + w[2] * q[2]) / s);
            }
            skew = s > 0 ? s / extent : 0;
        }
        max_skew = fmax(max_skew, skew);
        n_skew += skew > 4;
    }
    r->non_orthogonality_max = n ? max_angle : NAN;
    r->non_orthogonality_mean = n ? acos(fmin(1, sum_cos / (double)n)) * DEG_PER_RAD : NAN;
    r->skewness_max = n ? max_skew : NAN;
    r->n_skew_faces = n_skew;
    int rc = conn ? vc_stats_compute(conn, nf, &r->connection_rel) : 0;
    free(centre);
    free(cell_of);
    free(conn);
    return rc ? -1 : 0;
}

int vc_mesh_report_compute(const vc_vtu_mesh *m, const char *mesh_name,
                           const vc_surface *input, const char *input_name,
                           vc_mesh_report *out, vc_error *err)
{
    memset(out, 0, sizeof *out);
    const int64_t nc = m->n_cells;
    const size_t cn = nc ? (size_t)nc : 1;
    vc_surface boundary = {0, NULL, 0, NULL, NULL, 0, NULL};
    double *vol = malloc(sizeof *vol * cn), *rel = malloc(sizeof *rel * cn);
    double *dmin = malloc(sizeof *dmin * cn), *dmax = malloc(sizeof *dmax * cn);
    double *small = malloc(sizeof *small * cn), *rad = malloc(sizeof *rad * cn);
    int64_t *uses = malloc(sizeof *uses * (size_t)(m->n_faces ? m->n_faces : 1));
    int64_t *twin = malloc(sizeof *twin * (size_t)(m->n_faces ? m->n_faces : 1));
    out->cell_fatness = malloc(sizeof *out->cell_fatness * cn);
    int rc = VC_ENOMEM,
        oom = !vol || !rel || !dmin || !dmax || !small || !rad || !uses || !twin || !out->cell_fatness;
    double t0 = vc_clock_seconds();
    oom = oom || measure_cells(m, out, vol, rel, small, rad, dmin, dmax) != 0;
    oom = oom || vc_stats_compute(vol, nc, &out->volume) || vc_stats_compute(out->cell_fatness,
          nc, &out->fatness) || vc_stats_compute(rel, nc, &out->shortest_edge_rel) ||
          vc_stats_compute(small, nc, &out->small_face_rel) ||
          vc_stats_compute(dmin, nc, &out->dihedral_min) ||
          vc_stats_compute(dmax, nc, &out->dihedral_max);
    double t1 = vc_clock_seconds();
    if (!oom) {
        int64_t n_short = 0;
        for (int64_t c = 0; c < nc; c++)
            n_short += rel[c] < 1e-2; /* NaN (unmeasured) counts as not short */
        out->short_edge_share =
            out->shortest_edge_rel.n ? (double)n_short / (double)out->shortest_edge_rel.n : NAN;
        out->n_points = m->n_points;
        out->n_faces = vc_mesh_face_uses(m, uses, twin);
        oom = out->n_faces < 0 || vc_mesh_boundary_surface(m, uses, &boundary) != 0 ||
              solver_measures(m, twin, rad, out) != 0;
    }
    if (!oom) {
        for (int64_t f = 0; f < m->n_faces; f++) {
            out->n_boundary_faces += uses[f] == 1;
            out->n_faces_shared_more += uses[f] > 2;
        }
        oom = measure_boundary(&boundary, out) != 0;
    }
    double t2 = vc_clock_seconds();
    if (oom) {
        vc_error_set(err, VC_ENOMEM, "%s: out of memory", mesh_name);
    } else if (input && boundary.n_triangles == 0) {
        rc = vc_error_set(err, VC_EINPUT, "%s: the mesh has no boundary face to compare with %s",
                          mesh_name, input_name);
    } else if (input) {
        vc_error herr = {0, ""};
        rc = vc_hausdorff(input, &boundary, 0, &out->hausdorff, &herr);
        if (rc)
            vc_error_set(err, rc, "%s: %s", mesh_name, herr.msg);
        out->has_hausdorff = rc == 0;
    } else {
        rc = VC_OK;
    }
    double t3 = vc_clock_seconds();
    out->time_cells = t1 - t0;
    out->time_boundary = t2 - t1;
    out->time_hausdorff = t3 - t2;
    free(vol);
    free(rel);
    free(dmin);
    free(dmax);
    free(small);
    free(rad);
    free(uses);
    free(twin);
    vc_surface_free(&boundary);
    if (rc)
        vc_mesh_report_free(out);
    return rc;
}
