/* The tetrahedral .vtu writer of vc-tetgen. Every array's size is known in
 * advance, so the offsets in the XML header are computed before any data is
 * written: raw appended data, one UInt64 byte count before each array. */
#include "tetra_vtu_writer.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/io.h"
#include "io/tmpfile.h"

#define VTK_TETRA_TYPE 10

#if defined(__BYTE_ORDER__) && defined(__ORDER_BIG_ENDIAN__) && \
    __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define VTU_BYTE_ORDER "BigEndian"
#else
#define VTU_BYTE_ORDER "LittleEndian"
#endif

enum { A_VOLUME, A_POINTS, A_CONN, A_OFFSETS, A_TYPES, A_COUNT };

double vc_tetra_signed_volume(const vc_tetgen_mesh *m, int64_t t)
{
    const int64_t *id = m->tets + 4 * t;
    const double *p0 = m->points + 3 * id[0];
    double a[3], b[3], c[3];
    for (int d = 0; d < 3; d++) {
        a[d] = m->points[3 * id[1] + d] - p0[d];
        b[d] = m->points[3 * id[2] + d] - p0[d];
        c[d] = m->points[3 * id[3] + d] - p0[d];
    }
    return ((a[1] * b[2] - a[2] * b[1]) * c[0] + (a[2] * b[0] - a[0] * b[2]) * c[1] +
            (a[0] * b[1] - a[1] * b[0]) * c[2]) / 6.0;
}

/* One array's byte count then its bytes; 0 or -1 on a write error. */
static int write_array(FILE *fp, const void *data, uint64_t nbytes)
{
    if (fwrite(&nbytes, sizeof nbytes, 1, fp) != 1)
        return -1;
    return nbytes == 0 || fwrite(data, 1, (size_t)nbytes, fp) == nbytes ? 0 : -1;
}

int vc_write_tetra_vtu(const vc_tetgen_mesh *m, const char *path, vc_error *err)
{
    const int64_t np = m->n_points, nt = m->n_tets;
    const size_t cn = nt ? (size_t)nt : 1;
    double *volume = malloc(sizeof *volume * cn);
    int64_t *offsets = malloc(sizeof *offsets * cn);
    unsigned char *types = malloc(cn);
    if (!volume || !offsets || !types) {
        free(volume);
        free(offsets);
        free(types);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    for (int64_t t = 0; t < nt; t++) {
        volume[t] = vc_tetra_signed_volume(m, t);
        offsets[t] = 4 * (t + 1);
        types[t] = VTK_TETRA_TYPE;
    }
    const uint64_t bytes[A_COUNT] = {8 * (uint64_t)nt, 24 * (uint64_t)np, 32 * (uint64_t)nt,
                                     8 * (uint64_t)nt, (uint64_t)nt};
    uint64_t offset[A_COUNT], at = 0;
    for (int a = 0; a < A_COUNT; a++) {
        offset[a] = at;
        at += 8 + bytes[a];
    }

    vc_tmpfile t;
    int rc = vc_tmpfile_open(&t, path, err);
    if (rc) {
        free(volume);
        free(offsets);
        free(types);
        return rc;
    }
    FILE *fp = t.fp;
    fprintf(fp,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" VTU_BYTE_ORDER "\""
            " header_type=\"UInt64\">\n"
            "  <UnstructuredGrid>\n"
            "    <Piece NumberOfPoints=\"%" PRId64 "\" NumberOfCells=\"%" PRId64 "\">\n"
            "      <CellData Scalars=\"volume\">\n"
            "        <DataArray type=\"Float64\" Name=\"volume\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "      </CellData>\n"
            "      <Points>\n"
            "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "      </Points>\n"
            "      <Cells>\n"
            "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "        <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"%" PRIu64 "\"/>\n"
            "      </Cells>\n"
            "    </Piece>\n"
            "  </UnstructuredGrid>\n"
            "  <AppendedData encoding=\"raw\">\n   _",
            np, nt, offset[A_VOLUME], offset[A_POINTS], offset[A_CONN], offset[A_OFFSETS],
            offset[A_TYPES]);
    int bad = write_array(fp, volume, bytes[A_VOLUME]) || write_array(fp, m->points, bytes[A_POINTS]) ||
              write_array(fp, m->tets, bytes[A_CONN]) || write_array(fp, offsets, bytes[A_OFFSETS]) ||
              write_array(fp, types, bytes[A_TYPES]) ||
              fputs("\n  </AppendedData>\n</VTKFile>\n", fp) == EOF || ferror(fp);
    int e = errno;
    free(volume);
    free(offsets);
    free(types);
    if (bad) {
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e ? e : EIO));
    }
    return vc_tmpfile_commit(&t, err);
}
