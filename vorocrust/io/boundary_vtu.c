/* The boundary faces of a mesh as a .vtu of VTK_POLYGON cells, with their
 * patch and region (see include/vorocrust/io.h, vc_write_boundary_vtu). */
#include "vorocrust/io.h"
#include "io/io_patches.h"

#include "io/tmpfile.h"
#include "io/vtu_byte_order.h"

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
                             "byte_order=\"" VTU_BYTE_ORDER "\" header_type=\"UInt64\">\n"
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
    fprintf(fp, "</Array>\n</FieldData>\n");
    /* The arrays as raw appended data (each a UInt64 byte count, then the
     * bytes): printing 17 digits per coordinate in ASCII took a third of
     * a second for bunny.off's 40,000 faces. */
    const int64_t nfv = m->face_offsets[m->n_faces] - m->face_offsets[ni];
    const uint64_t bytes[7] = {24 * (uint64_t)np, 8 * (uint64_t)nfv, 8 * (uint64_t)nb, (uint64_t)nb,
                               4 * (uint64_t)nb, 4 * (uint64_t)nb, 8 * (uint64_t)nb};
    uint64_t off[7], at = 0;
    for (int a = 0; a < 7; a++) {
        off[a] = at;
        at += 8 + bytes[a];
    }
    fprintf(fp,
            "<Piece NumberOfPoints=\"%" PRId64 "\" NumberOfCells=\"%" PRId64 "\">\n"
            "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" "
            "offset=\"%" PRIu64 "\"/>\n</Points>\n<Cells>\n"
            "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"%" PRIu64
            "\"/>\n"
            "<DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "</Cells>\n<CellData>\n"
            "<DataArray type=\"Int32\" Name=\"patch\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "<DataArray type=\"Int32\" Name=\"region\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "<DataArray type=\"Float64\" Name=\"area\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "</CellData>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_",
            np, nb, off[0], off[1], off[2], off[3], off[4], off[5], off[6]);
#define PUT_COUNT(a) (bad_io = bad_io || fwrite(&bytes[a], 8, 1, fp) != 1)
#define PUT(x) (bad_io = bad_io || fwrite(&(x), sizeof(x), 1, fp) != 1)
    PUT_COUNT(0);
    for (int64_t i = 0; i < np && !bad_io; i++)
        bad_io = fwrite(m->points + 3 * used[i], sizeof(double), 3, fp) != 3;
    PUT_COUNT(1);
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++)
        /* outward: as the face is stored, out of its owner */
        for (int64_t j = m->face_offsets[f]; j < m->face_offsets[f + 1]; j++) {
            const int64_t v = map[m->face_vertices[j]];
            PUT(v);
        }
    PUT_COUNT(2);
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++) {
        const int64_t end = m->face_offsets[f + 1] - m->face_offsets[ni];
        PUT(end);
    }
    PUT_COUNT(3);
    for (int64_t f = 0; f < nb && !bad_io; f++) {
        const uint8_t polygon = 7;
        PUT(polygon);
    }
    PUT_COUNT(4);
    for (int64_t f = 0; f < nb && !bad_io; f++) {
        const int32_t patch = bp.face_patch[f];
        PUT(patch);
    }
    PUT_COUNT(5);
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++) {
        const int32_t region = m->cell_region ? m->cell_region[m->face_owner[f]] : 1;
        PUT(region);
    }
    PUT_COUNT(6);
    for (int64_t f = ni; f < m->n_faces && !bad_io; f++)
        PUT(m->face_area[f]);
#undef PUT
#undef PUT_COUNT
    if (fprintf(fp, "\n</AppendedData>\n</VTKFile>\n") < 0)
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
