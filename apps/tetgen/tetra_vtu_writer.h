/* Writes a tetrahedral mesh as a VTK XML UnstructuredGrid of VTK_TETRA
 * cells (what VTK 9.1 and ParaView read). */
#ifndef VC_TETRA_VTU_WRITER_H
#define VC_TETRA_VTU_WRITER_H

#include "tetgen_adapter.h"
#include "vorocrust/error.h"

/* The signed volume of tetrahedron t of m (positive: VTK's orientation). */
double vc_tetra_signed_volume(const vc_tetgen_mesh *m, int64_t t);

/* Writes m to path: Float64 points, Int64 connectivity and offsets, UInt8
 * types (10), cell data "volume" (Float64), all raw binary appended data
 * with UInt64 headers. Written to a temporary file next to path and
 * renamed. Returns 0, or VC_EIO / VC_ENOMEM with one line naming path. */
int vc_write_tetra_vtu(const vc_tetgen_mesh *m, const char *path, vc_error *err);

#endif
