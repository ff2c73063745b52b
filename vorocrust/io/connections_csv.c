/* Connections CSV: one row per interior face, the data a two-point-flux
 * finite-volume solver needs (cells, seeds, area, seed distance, face
 * centroid and unit normal from cell_i to cell_j, the two cells' regions),
 * then one row per boundary face with its patch.
 *
 * Rows are formatted in parallel, in chunks, and written in order. */
#include "vorocrust/io.h"
#include "io/io_patches.h"

#include "io/csv_rows.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CONN_ROWS_PER_CHUNK 256
#define CONN_ROW_MAX 416 /* 4 * 20 + 2 * 11 digits + 8 * 24 chars + a 63-byte patch name
                            + separators < 416 */

/* Distance between the seeds of the two cells of interior face f. Computed
 * here (not via vc_polymesh_face_seed_distance) so the writer does not
 * depend on the Voronoi module. */
static double conn_seed_distance(const vc_polymesh *m, int64_t f)
{
    const double *a = m->seed_xyz + 3 * m->cell_seed[m->face_owner[f]];
    const double *b = m->seed_xyz + 3 * m->cell_seed[m->face_neighbour[f]];
    double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

typedef struct conn_ctx {
    const vc_polymesh *m;
    const vc_boundary_patches *bp;
} conn_ctx;

/* A boundary face's row: cell_j -1, seed_j the seed across it (-1 on a
 * wall of the box), distance from the seed to the face's plane (half the
 * seed distance), the outward normal, region_j 0, its patch. */
static int conn_format_boundary(const conn_ctx *x, int64_t f, char *out, size_t room)
{
    const vc_polymesh *m = x->m;
    const int64_t ci = m->face_owner[f];
    const int64_t o = m->face_other_seed ? m->face_other_seed[f] : -1;
    const double *c = m->face_centroid + 3 * f, *nf = m->face_normal + 3 * f;
    const double *xi = m->seed_xyz + 3 * m->cell_seed[ci];
    double n[3] = {nf[0], nf[1], nf[2]}, dist;
    if (o >= 0 && o < m->n_seeds) {
        const double *xo = m->seed_xyz + 3 * o;
        const double d[3] = {xo[0] - xi[0], xo[1] - xi[1], xo[2] - xi[2]};
        const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        dist = 0.5 * len;
        if (len > 0)
            for (int k = 0; k < 3; k++)
                n[k] = d[k] / len;
    } else {
        dist = fabs((c[0] - xi[0]) * n[0] + (c[1] - xi[1]) * n[1] + (c[2] - xi[2]) * n[2]);
    }
    return snprintf(out, room,
                    "%" PRId64 ",-1,%" PRId64 ",%" PRId64
                    ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%" PRId32 ",0,%s\n",
                    ci, m->cell_seed[ci], o >= 0 ? o : (int64_t)-1, m->face_area[f], dist, c[0],
                    c[1], c[2], n[0], n[1], n[2], m->cell_region ? m->cell_region[ci] : 1,
                    x->bp->name[x->bp->face_patch[f - m->n_interior_faces]]);
}

static int conn_format_row(const vc_polymesh *m, int64_t f, char *out, size_t room)
{
    int64_t ci = m->face_owner[f], cj = m->face_neighbour[f];
    const double *c = m->face_centroid + 3 * f;
    /* A Voronoi face is orthogonal to its seed pair: the unit seed
     * direction is its exact normal, free of the vertex-merge rounding in
     * the face's own geometry. */
    const double *xi = m->seed_xyz + 3 * m->cell_seed[ci], *xj = m->seed_xyz + 3 * m->cell_seed[cj];
    double n[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0)
        for (int k = 0; k < 3; k++)
            n[k] /= len;
    return snprintf(out, room,
                    "%" PRId64 ",%" PRId64 ",%" PRId64 ",%" PRId64
                    ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%" PRId32 ",%" PRId32 ",\n",
                    ci, cj, m->cell_seed[ci], m->cell_seed[cj], m->face_area[f],
                    conn_seed_distance(m, f), c[0], c[1], c[2], n[0], n[1], n[2],
                    m->cell_region ? m->cell_region[ci] : 1, m->cell_region ? m->cell_region[cj] : 1);
}

static int conn_check(const vc_polymesh *m, const char *path, vc_error *err)
{
    if (m->n_interior_faces < 0 || m->n_interior_faces > m->n_faces)
        return vc_error_set(err, VC_EINPUT, "%s: bad interior face count %" PRId64, path,
                            m->n_interior_faces);
    if (m->n_faces == 0)
        return VC_OK;
    if (!m->face_owner || (!m->face_neighbour && m->n_interior_faces > 0) || !m->face_area ||
        !m->face_centroid || !m->face_normal || !m->cell_seed)
        return vc_error_set(err, VC_EINPUT, "%s: mesh lacks face geometry or cell seeds",
                            path);
    if (!m->seed_xyz)
        return vc_error_set(err, VC_EINPUT,
                            "%s: mesh has no seed positions (needed for distances)", path);
    for (int64_t f = m->n_interior_faces; f < m->n_faces; ++f)
        if (m->face_owner[f] < 0 || m->face_owner[f] >= m->n_cells)
            return vc_error_set(err, VC_EINPUT, "%s: boundary face %" PRId64 " has cell %" PRId64
                                " (of %" PRId64 ")", path, f, m->face_owner[f], m->n_cells);
    for (int64_t f = 0; f < m->n_interior_faces; ++f) {
        int64_t ci = m->face_owner[f], cj = m->face_neighbour[f];
        if (ci < 0 || ci >= m->n_cells || cj < 0 || cj >= m->n_cells)
            return vc_error_set(err, VC_EINPUT,
                                "%s: interior face %" PRId64 " has cells %" PRId64
                                ", %" PRId64 " (of %" PRId64 ")",
                                path, f, ci, cj, m->n_cells);
        int64_t si = m->cell_seed[ci], sj = m->cell_seed[cj];
        if (si < 0 || si >= m->n_seeds || sj < 0 || sj >= m->n_seeds)
            return vc_error_set(err, VC_EINPUT,
                                "%s: interior face %" PRId64 " has seeds %" PRId64
                                ", %" PRId64 " (of %" PRId64 ")",
                                path, f, si, sj, m->n_seeds);
    }
    return VC_OK;
}

static int conn_row(const void *ctx, int64_t f, char *out, size_t room)
{
    const conn_ctx *x = ctx;
    return f < x->m->n_interior_faces ? conn_format_row(x->m, f, out, room)
                                      : conn_format_boundary(x, f, out, room);
}

int vc_write_connections_csv(const vc_polymesh *m, const char *path, vc_error *err)
{
    if (!m || !path)
        return vc_error_set(err, VC_EPARAM, "vc_write_connections_csv: NULL argument");
    int rc = conn_check(m, path, err);
    if (rc)
        return rc;
    vc_boundary_patches bp;
    const int prc = vc_io_boundary_patches(m, path, &bp, err);
    if (prc)
        return prc;
    const conn_ctx ctx = {m, &bp};
    rc = vc_csv_write_rows(path, "cell_i,cell_j,seed_i,seed_j,area,distance,cx,cy,cz,nx,ny,nz,"
                           "region_i,region_j,patch\n",
                           m->n_faces, CONN_ROW_MAX, CONN_ROWS_PER_CHUNK, conn_row, &ctx, err);
    vc_boundary_patches_free(&bp);
    return rc;
}
