/* Reading VTK XML UnstructuredGrid (.vtu) files of polyhedra and
 * tetrahedra, written by vorocrust or by VTK itself.
 *
 * Accepted: VTK_POLYHEDRON (42) and VTK_TETRA (10) cells, mixed; DataArrays
 * in ascii, inline binary (base64) or appended (raw or base64) format,
 * uncompressed or vtkZLibDataCompressor-compressed, with UInt32 or UInt64
 * headers; any integer type for ids, Float32 or Float64 (or integer)
 * points; polyhedron faces in the VTK 9.0-9.3 layout (faces, faceoffsets)
 * or the VTK 9.4 layout (face_connectivity, face_offsets,
 * polyhedron_to_faces, polyhedron_offsets). Cells of other types are
 * skipped and counted. Of the cell data, only the seeds ("seed_point", 3
 * components) are read. One Piece; LittleEndian files only. */
#ifndef VORO_CRUST_VTU_READER_H
#define VORO_CRUST_VTU_READER_H

#include <stdint.h>
#include "vorocrust/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VC_VTK_TETRA 10
#define VC_VTK_POLYHEDRON 42

/* The cells kept from a .vtu file, every one described by its faces:
 * face f of the mesh is the point-id cycle
 * face_vertices[face_offsets[f] .. face_offsets[f + 1] - 1], and cell c
 * has the faces cell_faces[c] .. cell_faces[c + 1] - 1. A tetrahedron
 * (p0, p1, p2, p3) gets the faces (1,2,3), (0,3,2), (0,1,3), (0,2,1):
 * outward when (p1-p0) x (p2-p0) . (p3-p0) > 0. Polyhedron faces are as in
 * the file (VTK asks for outward faces; the quality measures accept
 * consistently inward cells too). */
typedef struct vc_vtu_mesh {
    int64_t n_points;
    double *points;          /* 3 * n_points */
    int64_t n_cells;         /* cells kept */
    uint8_t *cell_type;      /* VC_VTK_POLYHEDRON or VC_VTK_TETRA */
    int64_t *cell_file_index;/* each kept cell's index in the file */
    int64_t *cell_faces;     /* n_cells + 1 */
    int64_t n_faces;
    int64_t *face_offsets;   /* n_faces + 1 */
    int64_t *face_vertices;
    int64_t n_file_cells;    /* cells in the file */
    int64_t n_skipped;       /* cells of other types (not kept) */
    int first_skipped_type;  /* VTK type of the first skipped cell, or -1 */
    /* 3 * n_cells: each kept cell's seed, from the optional CellData array
     * "seed_point" (written by vorocrust), or NULL when the file has none. */
    double *cell_seed_point;
} vc_vtu_mesh;

/* Reads path into out (zeroed on failure). Errors, one line starting with
 * "PATH: ": VC_EIO missing or unreadable file; VC_EFORMAT not a VTK XML
 * UnstructuredGrid, a missing or malformed array, an unsupported encoding
 * or compressor, corrupt compressed data, a truncated file, point ids out
 * of range, inconsistent offsets; VC_EINPUT no polyhedron or tetrahedron
 * in the file; VC_ENOMEM. */
int vc_vtu_read(const char *path, vc_vtu_mesh *out, vc_error *err);

/* Frees the arrays of m and zeroes it; safe on a zeroed mesh. */
void vc_vtu_mesh_free(vc_vtu_mesh *m);

#ifdef __cplusplus
}
#endif
#endif
