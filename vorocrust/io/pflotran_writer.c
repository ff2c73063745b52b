/* PFLOTRAN explicit unstructured grid (GRID TYPE UNSTRUCTURED_EXPLICIT):
 * the .uge file and one .ex boundary-connection file per patch (REGION ...
 * FILE name.ex), see include/vorocrust/io.h.
 *
 * The cell point is the seed, and a connection's point is where the
 * segment between the two seeds crosses the face (their midpoint, on the
 * bisector that holds the face): PFLOTRAN splits the two-point distance
 * there, and for a Voronoi mesh that split is exact (one half each way).
 * For a boundary face the other seed is the non-kept one across it, so
 * the point is again on the face's plane, at the cell's half-distance. */
#include "vorocrust/io.h"
#include "io/io_patches.h"

#include "io/tmpfile.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int write_uge(const vc_polymesh *m, const char *path, vc_error *err)
{
    vc_tmpfile t;
    if (vc_tmpfile_open(&t, path, err) != 0)
        return err ? err->code : VC_EIO;
    FILE *fp = (FILE *)t.fp;
    int bad = fprintf(fp, "CELLS %" PRId64 "\n", m->n_cells) < 0;
    for (int64_t c = 0; c < m->n_cells && !bad; c++) {
        const double *s = m->seed_xyz + 3 * m->cell_seed[c];
        bad = fprintf(fp, "%" PRId64 " %.17g %.17g %.17g %.17g\n", c + 1, s[0], s[1], s[2],
                      m->cell_volume[c]) < 0;
    }
    bad = bad || fprintf(fp, "CONNECTIONS %" PRId64 "\n", m->n_interior_faces) < 0;
    for (int64_t f = 0; f < m->n_interior_faces && !bad; f++) {
        double x[3];
        vc_polymesh_face_seed_point(m, f, x);
        bad = fprintf(fp, "%" PRId64 " %" PRId64 " %.17g %.17g %.17g %.17g\n",
                      m->face_owner[f] + 1, m->face_neighbour[f] + 1, x[0], x[1], x[2],
                      m->face_area[f]) < 0;
    }
    if (bad || ferror(fp)) {
        const int e = errno;
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e ? e : EIO));
    }
    return vc_tmpfile_commit(&t, err) == 0 ? VC_OK : (err ? err->code : VC_EIO);
}

static int write_ex(const vc_polymesh *m, const vc_boundary_patches *bp, int patch,
                    const char *path, vc_error *err)
{
    vc_tmpfile t;
    if (vc_tmpfile_open(&t, path, err) != 0)
        return err ? err->code : VC_EIO;
    FILE *fp = (FILE *)t.fp;
    int bad = fprintf(fp, "CONNECTIONS %" PRId64 "\n", bp->size[patch]) < 0;
    for (int64_t f = m->n_interior_faces; f < m->n_faces && !bad; f++) {
        if (bp->face_patch[f - m->n_interior_faces] != patch)
            continue;
        double x[3];
        vc_polymesh_face_seed_point(m, f, x);
        bad = fprintf(fp, "%" PRId64 " %.17g %.17g %.17g %.17g\n", m->face_owner[f] + 1, x[0],
                      x[1], x[2], m->face_area[f]) < 0;
    }
    if (bad || ferror(fp)) {
        const int e = errno;
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e ? e : EIO));
    }
    return vc_tmpfile_commit(&t, err) == 0 ? VC_OK : (err ? err->code : VC_EIO);
}

/* PATH without its extension (".uge"), then "_NAME.ex". */
static char *ex_path(const char *uge, const char *name)
{
    size_t n = strlen(uge);
    const char *slash = strrchr(uge, '/');
    const char *dot = strrchr(uge, '.');
    if (dot && (!slash || dot > slash))
        n = (size_t)(dot - uge);
    char *p = malloc(n + strlen(name) + 5);
    if (p)
        sprintf(p, "%.*s_%s.ex", (int)n, uge, name);
    return p;
}

int vc_write_pflotran(const vc_polymesh *m, const char *path, vc_error *err)
{
    if (!m || !path || !*path)
        return vc_error_set(err, VC_EPARAM, "vc_write_pflotran: no mesh or no path");
    if (m->n_cells > 0 && (!m->seed_xyz || !m->cell_seed || !m->cell_volume || !m->face_area))
        return vc_error_set(err, VC_EINPUT, "%s: the mesh lacks seeds, volumes or face areas",
                            path);
    vc_boundary_patches bp;
    const int prc = vc_io_boundary_patches(m, path, &bp, err);
    if (prc)
        return prc;
    int rc = write_uge(m, path, err);
    for (int k = 0; k < bp.n_patches && rc == VC_OK; k++) {
        char *ex = ex_path(path, bp.name[k]);
        if (!ex) {
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
            break;
        }
        rc = write_ex(m, &bp, k, ex, err);
        free(ex);
    }
    vc_boundary_patches_free(&bp);
    return rc;
}
