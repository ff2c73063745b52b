/* Mesh writers. Every writer writes to a temporary file next to the target
 * and renames it, so a failed run never leaves a half-written file. */
#ifndef VORO_CRUST_IO_H
#define VORO_CRUST_IO_H

#include "vorocrust/error.h"
#include "vorocrust/polymesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vc_vtu_encoding {
    VC_VTU_RAW = 0,  /* binary appended data, uncompressed */
    VC_VTU_ZLIB = 1  /* binary appended data, zlib-compressed blocks */
} vc_vtu_encoding;

/* Writes an unstructured grid of VTK_POLYHEDRON (42) cells in the VTK XML
 * format, file version 1.0 (faces/faceoffsets arrays), Int64 ids, binary
 * appended data. Cell data: "region" (Int32), "seed" (Int64), "volume"
 * (Float64). Every face is written outward for the cell that lists it
 * (reversed when the cell is not the face's owner). ZLIB compresses the
 * arrays in 32 KiB blocks (in parallel with OpenMP). Errors: VC_EIO naming
 * the path ("out.vtu: cannot write: ..."), VC_EINPUT for an index out of
 * range, VC_ENOMEM. */
int vc_write_vtu(const vc_polymesh *m, const char *path, vc_vtu_encoding enc,
                 vc_error *err);

/* Writes the connections as CSV with the header
 * cell_i,cell_j,seed_i,seed_j,area,distance,cx,cy,cz,nx,ny,nz,region_i,region_j,patch
 * First one row per interior face: cell_i is the face's owner, the normal
 * points from cell_i to cell_j, distance is between the two cells' seeds
 * (needs m->seed_xyz), region_i, region_j the cells' labels (1 without
 * cell_region), patch empty. Then one row per boundary face: cell_j -1,
 * seed_j the seed across the face (-1 on a wall of the box), distance from
 * seed_i to the face's plane, the outward normal, region_j 0, and the
 * face's patch (vc_polymesh_boundary_patches). (cx, cy, cz) is the face's
 * area centroid; values with %.17g. */
int vc_write_connections_csv(const vc_polymesh *m, const char *path,
                             vc_error *err);

/* Writes the boundary faces of m (faces of one cell) as an ASCII .vtu of
 * VTK_POLYGON cells, each oriented out of its cell, with cell data
 * "patch" (Int32, the index of its patch, vc_polymesh_boundary_patches),
 * "region" (Int32, its cell's label) and "area" (Float64), and the patch
 * names in the field data "patch_names" (a string array). Errors: VC_EIO
 * naming the path, VC_EINPUT, VC_ENOMEM. */
int vc_write_boundary_vtu(const vc_polymesh *m, const char *path, vc_error *err);

/* Writes a PFLOTRAN explicit unstructured grid (GRID TYPE
 * UNSTRUCTURED_EXPLICIT) to path: "CELLS n", then one line "id x y z
 * volume" per cell (ids from 1, in mesh order; the point is the cell's
 * seed); "CONNECTIONS m", then one line "id_up id_dn x y z area" per
 * interior face (the point is where the segment between the two seeds
 * crosses the face: their midpoint). For each boundary patch
 * (vc_polymesh_boundary_patches), path without its extension plus
 * "_PATCH.ex": "CONNECTIONS k", then "id x y z area" per boundary face
 * of the patch (the point is the midpoint of the cell's seed and the
 * seed across the face; a face on the clipping box: its centroid), for a
 * REGION ... FILE card. Numbers with 17 significant digits; each file
 * through a temporary file. Errors: VC_EIO naming the path, VC_EINPUT,
 * VC_ENOMEM. */
int vc_write_pflotran(const vc_polymesh *m, const char *path, vc_error *err);

/* Writes a TOUGH2 / TOUGH3 MESH file to path, in the fixed 80-column format
 * of the TOUGH2 user's guide. "ELEME" records (columns 1-5 name, 16-20
 * material, 21-30 volume, 51-80 x y z): one element per cell, named
 * A0000, A0001, ... (a letter, two base-36 characters, two digits), of
 * material "R0001" for label 1 (region N: "R%04d"), centred on its seed;
 * then one boundary element per boundary face, patch after patch
 * (vc_polymesh_boundary_patches), of volume 1e50 (its state never changes)
 * and its cell's material, centred on the face at the seeds' midpoint.
 * "CONNE" records (1-10 the two names, 26-30 ISOT, 31-40 D1, 41-50 D2,
 * 51-60 area, 61-70 BETAX): every interior face, D1 = D2 = half the seed
 * distance; every boundary face to its boundary element, D2 = 0. ISOT is
 * the axis the connection runs closest to; BETAX the cosine of the angle
 * between gravity (-z) and the line from element 1 to element 2. Each
 * number is written in its ten columns with as many digits as fit (fixed
 * or exponent notation). Fails with VC_EINPUT beyond 3,369,600 elements
 * or for a number outside 1e-99 to 1e99; VC_EIO naming the path;
 * VC_ENOMEM. Through a temporary file. */
int vc_write_tough(const vc_polymesh *m, const char *path, vc_error *err);

/* Writes the mesh as an OpenFOAM case: CASE_DIR/constant/polyMesh/{points,
 * faces, owner, neighbour, boundary} in OpenFOAM's ASCII format (classes
 * vectorField, faceList, labelList with the nPoints/nCells/nFaces/
 * nInternalFaces note, polyBoundaryMesh), and CASE_DIR/system/controlDict
 * (minimal, enough for checkMesh) when the case has none. Interior faces
 * come first in upper-triangular order (owner < neighbour, sorted by owner
 * then neighbour), oriented owner -> neighbour; boundary faces follow,
 * grouped by patch: "surface" (faces against non-kept seeds), then one
 * patch per used wall of the clipping box ("xmin", "xmax", "ymin", "ymax",
 * "zmin", "zmax"), all of type patch. Cells of several labels (regions)
 * split every patch by the region of its cells ("region2_surface", ...)
 * and add constant/polyMesh/cellZones (one zone "regionN" per label N)
 * and faceZones (one zone "regionA_to_regionB" per pair of labels A < B
 * that share faces, oriented from A to B), as splitMeshRegions -cellZones
 * reads them. Coordinates have 17 significant
 * digits (they read back as the same doubles); unused points are dropped.
 * CASE_DIR may be missing (the case is assembled in CASE_DIR.tmp.XXXXXX
 * and renamed) or an existing directory (its constant/polyMesh is replaced
 * as a whole, other files are kept). A failure leaves nothing behind.
 * Errors: VC_EIO naming the path, VC_EINPUT for an inconsistent mesh,
 * VC_ENOMEM. */
int vc_write_openfoam(const vc_polymesh *m, const char *case_dir, vc_error *err);

/* The same with patch types: the patch named name (or every patch of the
 * input group name, "region2_inlet" being of group "inlet") gets type
 * (patch, wall, symmetryPlane, symmetry or empty; the last entry that
 * names it wins). Without an entry, the one patch of a surface without
 * named groups ("surface") is a wall, every other a patch. With several
 * regions each patch lists its input group in inGroups, so that a
 * solver's boundary conditions can name "inlet" once for every region.
 * VC_EPARAM for an unknown type. */
typedef struct vc_foam_patch_type {
    const char *name;
    const char *type;
} vc_foam_patch_type;
int vc_write_openfoam_typed(const vc_polymesh *m, const char *case_dir,
                            const vc_foam_patch_type *types, int n_types, vc_error *err);

#ifdef __cplusplus
}
#endif
#endif
