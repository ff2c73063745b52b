/* The input triangle surface: reading, cleaning and validation.
 *
 * vc_surface_read reads OBJ, OFF, STL (ASCII and binary) and PLY (ASCII,
 * binary little and big endian) files, triangulates polygons, merges
 * vertices with exactly equal positions (STL stores every triangle corner
 * separately), drops unreferenced vertices and triangles that repeat a
 * vertex, and checks the result (vc_surface_check).
 *
 * Edges shared by more than two triangles are kept: they are the
 * interfaces of multi-material inputs. Open boundaries, non-manifold
 * edges, inconsistent orientation and zero-area triangles are not fatal:
 * they are counted in a vc_surface_report, which also holds one warning
 * line per problem for the caller to print. Stages that need a closed
 * surface call vc_surface_require_closed. */
#ifndef VORO_CRUST_SURFACE_H
#define VORO_CRUST_SURFACE_H

#include <stdint.h>
#include "vorocrust/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An indexed triangle surface. Triangle t has the vertices
 * tri[3t], tri[3t+1], tri[3t+2] (0-based), counter-clockwise seen from
 * outside for an outward-oriented closed surface. */
typedef struct vc_surface {
    int64_t n_vertices;
    double *xyz;         /* 3 * n_vertices */
    int64_t n_triangles;
    int64_t *tri;        /* 3 * n_triangles */
} vc_surface;

#define VC_SURFACE_MAX_WARNINGS 12

/* What vc_surface_read / vc_surface_check found. */
typedef struct vc_surface_report {
    char name[256];             /* the file name used in every message */
    const char *reader;         /* "vorocrust" or "OpenMesh" */

    /* Reading and cleaning (set by vc_surface_read). */
    int64_t n_file_vertices;    /* vertices in the file */
    int64_t n_file_faces;       /* faces (polygons) in the file */
    int64_t n_faces_dropped;    /* faces announced but not delivered by the reader */
    int64_t n_polygons_triangulated; /* faces with more than 3 vertices */
    int64_t n_duplicate_vertices;    /* vertices merged into an equal position */
    int64_t n_unused_vertices;  /* vertices no triangle refers to (removed) */
    int64_t n_collapsed;        /* triangles repeating a vertex (removed) */

    /* Topology and geometry of the final surface (set by vc_surface_check). */
    int64_t n_vertices, n_triangles, n_edges;
    int64_t n_degenerate;       /* zero-area triangles (kept) */
    int64_t n_boundary_edges;   /* edges of one triangle: the surface is open */
    int64_t n_nonmanifold_edges;/* edges of three or more triangles */
    int64_t n_inconsistent_edges; /* two-triangle edges walked the same way by both */
    int64_t n_components;       /* connected through shared vertices */
    int64_t euler;              /* V - E + F */
    int closed_manifold;        /* no boundary and no non-manifold edge */
    int64_t genus;              /* sum of component genera; -1 unless closed_manifold */
    double bbox[6];             /* xmin, ymin, zmin, xmax, ymax, zmax */
    double signed_volume;       /* sum over triangles of det(a, b, c) / 6 */
    double volume;              /* |signed_volume| */

    /* One line per non-fatal problem, without trailing newline. */
    int n_warnings;
    char warnings[VC_SURFACE_MAX_WARNINGS][VC_ERROR_LEN];
} vc_surface_report;

/* Reads, cleans and checks the surface in path; the format follows the
 * extension (.obj, .off, .stl, .ply, any case; other extensions OpenMesh
 * reads, such as .om, go through OpenMesh). rep may be NULL.
 * Fails (out is then empty) with
 *   VC_EIO      missing or unreadable file;
 *   VC_EFORMAT  unsupported extension, malformed file (message names the
 *               line), empty file;
 *   VC_EINPUT   no triangles, non-finite coordinates, face index out of
 *               range, every triangle of zero area.
 * Every message is one line starting with "FILE: ". */
int vc_surface_read(const char *path, vc_surface *out, vc_surface_report *rep,
                    vc_error *err);

/* Which reader vc_surface_read_with uses: the one for the extension
 * (vc_surface_read's choice), or OpenMesh for every format (for
 * cross-checking the readers). */
typedef enum vc_surface_reader { VC_READER_AUTO = 0, VC_READER_OPENMESH = 1 } vc_surface_reader;

int vc_surface_read_with(const char *path, vc_surface_reader which, vc_surface *out,
                         vc_surface_report *rep, vc_error *err);

/* Frees the arrays of s and zeroes it. Safe on a zeroed surface. */
void vc_surface_free(vc_surface *s);

/* Computes the topology and geometry fields of rep for s (the reading
 * fields and name are left as they are: set rep->name first, or zero rep)
 * and adds a warning line for each problem found. Degenerate means
 * |cross(b - a, c - a)| <= 1e-12 * (longest edge)^2.
 * Fails with VC_EINPUT when s has no triangle, a non-finite coordinate, an
 * index out of range, or only zero-area triangles. */
int vc_surface_check(const vc_surface *s, vc_surface_report *rep, vc_error *err);

/* Merges vertices with exactly equal positions, removes vertices no
 * triangle uses and triangles that repeat a vertex, keeping the first
 * occurrence order. Counts are returned through the optional pointers.
 * Returns 0 or VC_ENOMEM. */
int vc_surface_merge_vertices(vc_surface *s, int64_t *n_merged,
                              int64_t *n_unused, int64_t *n_collapsed,
                              vc_error *err);

/* Returns 0 when the checked surface has no open boundary edge, else
 * VC_EINPUT with "FILE: N open boundary edges (surface is not closed)". */
int vc_surface_require_closed(const vc_surface_report *rep, vc_error *err);

/* Adds a warning line to rep (printf-style); extra lines beyond
 * VC_SURFACE_MAX_WARNINGS are dropped. */
void vc_surface_report_warn(vc_surface_report *rep, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#ifdef __cplusplus
}
#endif
#endif
