/* The boundary faces of a mesh as a .vtu of VTK_POLYGON cells, with their
 * patch and region (see include/vorocrust/io.h, vc_write_boundary_vtu). */
#include "vorocrust/io.h"
#include "io/io_patches.h"

#include "io/tmpfile.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int vc_write_boundary_vtu(const vc_polymesh *m, const char *path, vc_error *err)
{
    if (!m || !path || !*path)
        return vc_error_set(err, VC_EPARAM, "vc_write_boundary_vtu: no mesh or no path");
    vc_boundary_patches bp;
    const int prc = vc_io_boundary_patches(m, path, &bp, err);
    if (prc)
        return prc;
    const int64_t ni = m->n_interior_faces, nb = m->n_faces - ni;
    /* the boundary faces' points, numbered by first use */
    int64_t *map = malloc(sizeof(int64_t) * (size_t)(m->n_points + 1));
    int64_t *used = malloc(sizeof(int64_t) * (size_t)(m->face_offsets[m->n_faces] + 1));
    if (!map || !used) {
        free(map);
        free(used);
        vc_boundary_patches_free(&bp);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    for (int64_t p = 0; p < m->n_points; p++)
        map[p] = -1;
    int64_t np = 0;
    for (int64_t f = ni; f < m->n_faces; f++)
        for (int64_t j = m->face_offsets[f]; j < m->face_offsets[f + 1]; j++)
            if (map[m->face_vertices[j]] < 0) {
                map[m->face_vertices[j]] = np;
                used[np++] = m->face_vertices[j];
            }
    vc_tmpfile t;
    if (vc_tmpfile_open(&t, path, err) != 0) {
        free(map);
        free(used);
        vc_boundary_patches_free(&bp);
        return err ? err->code : VC_EIO;
    }
    FILE *fp = (FILE *)t.fp;
    int bad_io = fprintf(fp, "<?xml version=\"1.0\"?>\n"
                             "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                             "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
                             "<UnstructuredGrid>\n<FieldData>\n"
                             "<Array type=\"String\" Name=\"patch_names\" NumberOfTuples=\"%d\" "
                             "format=\"ascii\">\n",
                         bp.n_patches) < 0;
    /* the patch names: each string's character codes and a 0 */
    for (int k = 0; k < bp.n_patches && !bad_io; k++) {
        for (const char *c = bp.name[k]; *c; c++)
            fprintf(fp, "%d ", (unsigned char)*c);
        bad_io = fprintf(fp, "0\n") < 0;
    }
    fprintf(fp, "</Array>\n</FieldData>\n"
                "<Piece NumberOfPoints=\"%" PRId64 "\" NumberOfCells=\"%" PRId64 "\">\n"
                "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
            np, nb);
    for (int64_t i = 0; i < np && !bad_io; i++) {
        const double *x = m->points + 3 * used[i];
        bad_io = fprintf(fp, "%.17g %.17g %.17g\n", x[0], x[1], x[2]) < 0;
    }
    fprintf(fp, "</DataArray>\n</Points>\n<Cells>\n"
                "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++) {
        /* outward: as the face is stored, out of its owner */
        for (int64_t j = m->face_offsets[f]; j < m->face_offsets[f + 1]; j++)
            fprintf(fp, "%" PRId64 " ", map[m->face_vertices[j]]);
        bad_io = fputc('\n', fp) == EOF;
    }
    fprintf(fp, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++)
        bad_io = fprintf(fp, "%" PRId64 "\n",
                         m->face_offsets[f + 1] - m->face_offsets[ni]) < 0;
    fprintf(fp, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (int64_t f = 0; f < nb && !bad_io; f++)
        bad_io = fputs("7\n", fp) < 0;
    fprintf(fp, "</DataArray>\n</Cells>\n<CellData>\n"
                "<DataArray type=\"Int32\" Name=\"patch\" format=\"ascii\">\n");
    for (int64_t f = 0; f < nb && !bad_io; f++)
        bad_io = fprintf(fp, "%d\n", bp.face_patch[f]) < 0;
    fprintf(fp, "</DataArray>\n<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n");
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++)
        bad_io = fprintf(fp, "%d\n", m->cell_region ? (int)m->cell_region[m->face_owner[f]] : 1) < 0;
    fprintf(fp, "</DataArray>\n<DataArray type=\"Float64\" Name=\"area\" format=\"ascii\">\n");
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++)
        bad_io = fprintf(fp, "%.17g\n", m->face_area[f]) < 0;
    if (fprintf(fp, "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n") < 0)
        bad_io = 1;
    free(map);
    free(used);
    vc_boundary_patches_free(&bp);
    if (bad_io || ferror(fp)) {
        const int e = errno;
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e ? e : EIO));
    }
    return vc_tmpfile_commit(&t, err) == 0 ? VC_OK : (err ? err->code : VC_EIO);
}
