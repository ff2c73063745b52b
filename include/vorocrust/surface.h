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
    /* Optional: the named groups of the triangles (OBJ g / o / usemtl, the
     * solids of an ASCII STL, several input files), which become the mesh's
     * boundary patches. NULL and 0 when the input names none. */
    int32_t *tri_group;  /* n_triangles: an index into group_name */
    int32_t n_groups;
    char (*group_name)[64];
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
 * extension (.obj, .off, .stl, .ply, any case; any other extension is
 * refused: the project reads only formats its own readers validate).
 * rep may be NULL.
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
 * (vc_surface_read's choice), or OpenMesh, after the project's reader has
 * accepted the file (for cross-checking the readers; the same four
 * formats). */
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

/* *out = s in an order that depends on its geometry alone: vertices in
 * Morton order of their position in the bounding box (exact coordinates
 * breaking ties), each triangle starting at its smallest vertex (its
 * orientation kept), triangles sorted by their vertices, then group; the
 * groups and their names copied. The same solid read from any format or
 * numbering then meshes the same (vc_mesh samples one solid so).
 * input_triangle and input_vertex (optional, n_triangles and n_vertices
 * entries) receive each triangle's and vertex's index in s. out is freed
 * with vc_surface_free. Returns 0 or VC_ENOMEM. */
int vc_surface_canonical_order(const vc_surface *s, vc_surface *out, int64_t *input_triangle,
                               int64_t *input_vertex, vc_error *err);

/* *out = s with the vertices of its open edges (edges of one triangle)
 * that lie within tol of each other welded: each group becomes its
 * lowest-numbered vertex, at that vertex's place; triangles that then
 * repeat a vertex and vertices no longer used are dropped (and exactly
 * coincident vertices merged, as vc_surface_merge_vertices does). For
 * seams open only by rounding (a parametric surface whose seam vertices
 * were computed twice). *n_welded receives the vertices welded into
 * another. out is freed with vc_surface_free. Returns 0 or VC_ENOMEM.
 * vc_mesh and `vorocrust info` weld an open surface so, then split its
 * T-junctions (vc_surface_split_t_junctions), at vc_surface_seam_tolerance,
 * and take the result when it is closed with no new edge of more than two
 * triangles. */
#define VC_SURFACE_SEAM_WELD 1e-7

/* The distance below which the vertices of open edges are one, or lie on
 * an edge: VC_SURFACE_SEAM_WELD times the bounding-box diagonal plus four
 * single-precision ulps of the largest |coordinate|. The copies of a seam
 * vertex computed twice differ by a few double ulps (4e-15 of VTK's
 * parametric ellipsoid's diagonal); coordinates written in single
 * precision (binary STL, "%.9g") are off by half a float ulp each, which
 * far from the origin is far more than 1e-7 of the model (a part 237 wide
 * at x = 10,000: 5e-4); any error bound is far above both. */
double vc_surface_seam_tolerance(const vc_surface *s);

/* Splits, in place, every triangle with an open edge (an edge of one
 * triangle) on which vertices of other open edges lie, within tol of the
 * segment and farther than tol from its ends: the triangle becomes a fan
 * from its third corner through those vertices, its orientation and
 * group kept (a T-junction: two faces of a CAD model tessellated apart, one
 * side's vertex on the other side's edge). Repeated while it splits, at
 * most 8 passes. *n_split receives the triangles split. Returns 0 or
 * VC_ENOMEM. */
int vc_surface_split_t_junctions(vc_surface *s, double tol, int64_t *n_split, vc_error *err);
int vc_surface_weld_open_seams(const vc_surface *s, double tol, vc_surface *out, int64_t *n_welded,
                               vc_error *err);

/* *out = s with the two ends of the shortest edge of every zero-area
 * triangle (vc_surface_check's degenerate test) welded when that edge is
 * at most tol long (a needle: two vertices that coincide to rounding, not
 * merged because not exactly equal), each group becoming its lowest
 * vertex; the triangles that then repeat a vertex (the needles) and the
 * unused vertices are dropped. *n_welded receives the welds (0: out is
 * left empty). vc_mesh and `vorocrust info` do it, at
 * vc_surface_seam_tolerance, for the zero-area triangles that are not caps
 * (vc_surface_flip_zero_area), and take the result when it has fewer
 * zero-area triangles, no open edge and no new edge of more than two
 * triangles. Returns 0 or VC_ENOMEM. */
int vc_surface_weld_needles(const vc_surface *s, double tol, vc_surface *out, int64_t *n_welded,
                            vc_error *err);

/* The rounding repairs vc_mesh and `vorocrust info` make, each taken only
 * when it helps (rep: vc_surface_check's report of s):
 *  - open: vc_surface_weld_open_seams then vc_surface_split_t_junctions at
 *    vc_surface_seam_tolerance, taken when the result is closed with no
 *    more edges of three or more triangles than s;
 *  - needles: vc_surface_weld_needles at that tolerance, taken when the
 *    result has fewer zero-area triangles, no open edge and no more edges
 *    of three or more triangles.
 * Returns 0 with *out the repaired surface and *out_rep its report (name
 * and reading fields copied from rep) and the counts set when it is taken;
 * 0 with *out empty when not; VC_ENOMEM. */
int vc_surface_close_by_rounding(const vc_surface *s, const vc_surface_report *rep, vc_surface *out,
                                 vc_surface_report *out_rep, int64_t *n_welded, int64_t *n_split,
                                 vc_error *err);
int vc_surface_drop_needles(const vc_surface *s, const vc_surface_report *rep, vc_surface *out,
                            vc_surface_report *out_rep, vc_error *err);

/* Removes, in place, the zero-area triangles of s (vc_surface_check's
 * degenerate ones: |cross| <= VC_SOLID_ZERO_AREA * (longest edge)^2) that
 * are caps: the triangle across the longest edge a -> b (the edge of
 * exactly these two) is split at the cap's third vertex c, and the two
 * become (b, c, d) and (c, a, d), d that triangle's third vertex: the
 * same area and orientation, every edge shared as before. A flip that would
 * make another zero-area triangle waits for a later pass (at most 16).
 * *n_flipped receives the caps removed, *n_left the zero-area triangles
 * left. Returns 0 or VC_ENOMEM. */
int vc_surface_flip_zero_area(vc_surface *s, int64_t *n_flipped, int64_t *n_left, vc_error *err);

/* One surface of n_parts surfaces: their vertices and triangles in order
 * (part 0's triangles first), vertices with exactly equal positions merged
 * (so that parts meeting along an interface share its vertices, edges and
 * triangles: a triangle given by two parts, reversed, is then one
 * interface). The triangles' groups: a part's own (tri_group), or the part
 * as one group named part_names[i] (NULL: "part1", "part2", ...); groups
 * of the same name are one. At most 1024 groups per part. Returns 0 or
 * VC_ENOMEM. */
int vc_surface_concat(const vc_surface *parts, int n_parts, const char *const *part_names,
                      vc_surface *out, vc_error *err);

/* The diagonal of the bounding box of s's vertices (0 without vertices):
 * the length the relative parameters (--max-error, the Hausdorff budget)
 * are fractions of. */
double vc_surface_diagonal(const vc_surface *s);

/* The signed volume a closed surface encloses: the sum over its triangles
 * of det(a, b, c) / 6, positive when they are oriented outwards; summed
 * relative to the bounding box's centre and scaled by a power of two, so
 * that coordinates far from the origin lose no digits and models from
 * 1e-300 to 1e300 neither overflow nor underflow. 0 without triangles. */
double vc_surface_signed_volume(const vc_surface *s);

/* Returns 0 when the checked surface has no open boundary edge, else
 * VC_EINPUT with "FILE: N open boundary edges (surface is not closed)". */
int vc_surface_require_closed(const vc_surface_report *rep, vc_error *err);

/* The flips that orient s consistently: flip[t] (n_triangles bytes) is 1
 * for the triangles to reverse so that every edge of exactly two triangles
 * is walked once each way; in each component (triangles joined through
 * such edges) the orientation most of its triangles have is kept (the
 * lowest-numbered triangle's on a tie), so an inward cavity shell stays
 * inward. *n_flipped receives their number. VC_EINPUT when a component is
 * one-sided (no orientation exists), VC_ENOMEM. */
int vc_surface_consistent_flips(const vc_surface *s, unsigned char *flip, int64_t *n_flipped,
                                vc_error *err);

/* Reverses the triangles t of s with flip[t] != 0 (in place). */
void vc_surface_reverse_triangles(vc_surface *s, const unsigned char *flip);

/* vc_surface_check_solid's limits: the largest |coordinate| over the
 * bounding-box diagonal, the zero-area ratio |cross| / longest edge^2, the
 * smallest share of the bounding box's volume the surface must enclose. */
#define VC_SOLID_MAX_COORDINATE_RATIO 1e9
#define VC_SOLID_ZERO_AREA 1e-12
#define VC_SOLID_MIN_VOLUME_RATIO 1e-9

/* What vc_surface_check_solid found. Triangle indices are 0-based (the
 * messages print them 1-based), -1 when there is none. */
typedef struct vc_solid_report {
    double coordinate_ratio;       /* largest |coordinate| / bounding-box diagonal */
    int64_t n_zero_area;           /* triangles with |cross| <= 1e-12 (longest edge)^2 */
    int64_t first_zero_area;
    int64_t n_repeated_same;       /* triangles repeating the vertices of an earlier one in the same orientation */
    int64_t first_repeated_same[2];
    int64_t n_repeated_opposite;   /* triangles repeating an earlier one reversed (not refused:
                                      an interface given once per side, or a wall of zero
                                      thickness, which vc_surface_regions tells apart) */
    int64_t first_repeated_opposite[2];
    int64_t n_self_intersections;  /* pairs of triangles that cut or touch each other improperly */
    int64_t first_self_intersection[2];
    double volume_ratio;           /* the sum over components (connected through vertices) of
                                      |the volume each encloses| / bounding-box volume (a part
                                      inside out counts); NaN when not checked */
    int solid;                     /* 1 when every check passed */
} vc_solid_report;

/* Whether the checked surface s (rep from vc_surface_check; may be NULL,
 * then the surface is taken as closed and named "surface") can bound a
 * volume. Returns 0 when it can, VC_EINPUT with one line "NAME: ..." naming
 * the first problem, the triangles (1-based) and a remedy, or VC_ENOMEM.
 * out (may be NULL) receives every count, also on failure. The checks, in
 * the order they are reported:
 *   1. precision: the largest |coordinate| must stay within 1e9 times the
 *      bounding-box diagonal; beyond, rounding merges vertices and flattens
 *      triangles (a unit cube offset by 1e300 is refused here);
 *   2. zero-area triangles, |cross(b - a, c - a)| <= 1e-12 (longest edge)^2
 *      as in vc_surface_check: refused, not repaired;
 *   3. triangles repeated with the same orientation (the same three
 *      vertices); repeated with the opposite orientation they are counted,
 *      not refused: two closed surfaces sharing an interface give it once
 *      each (vc_surface_regions counts it once, and tells a wall of zero
 *      thickness, with one region on both sides, apart);
 *   4. self-intersections: two triangles sharing no vertex that meet, one
 *      vertex and meet elsewhere, or an edge and fold onto each other
 *      coplanar; contact within rounding counts (filtered orientation
 *      predicates, a bounding-volume hierarchy, OpenMP);
 *   5. an enclosed volume of at most 1e-9 of the bounding-box volume
 *      (flat surfaces); skipped when rep counts open or inconsistently
 *      oriented edges, which vc_surface_check already reports.
 * Every test runs on coordinates scaled by a power of two to a diagonal of
 * order 1, so verdicts do not change when the model is scaled (1e-300 to
 * 1e300); the result does not depend on the thread count. Edges shared by
 * more than two triangles are accepted when no triangle is repeated.
 * O(n log n) in the number of triangles plus the candidate pairs of
 * overlapping boxes; docs/input-checks.md has the details. */
int vc_surface_check_solid(const vc_surface *s, const vc_surface_report *rep, vc_solid_report *out,
                           vc_error *err);

/* What vc_surface_self_union did. */
typedef struct vc_self_union_report {
    int64_t n_pairs;           /* pairs of triangles that intersect */
    int64_t n_segments;        /* segments of the intersection curves */
    int64_t n_split;           /* input triangles cut along them */
    int64_t n_patches;         /* pieces of surface between the curves */
    int64_t n_patches_dropped; /* those inside another part (or outside all) */
    int64_t n_pieces_dropped;  /* triangles (after the cuts) dropped with them */
    int64_t n_collapsed;       /* edges at cut points shorter than 1e-4 of the diagonal, collapsed */
    double volume;             /* the volume the union encloses */
} vc_self_union_report;

/* The union of a closed, consistently oriented surface that intersects
 * itself (vc_surface_check_solid's self-intersections): out receives the
 * boundary of the region s winds around at least once, as triangles. The
 * triangles of s are cut along the intersection curves (new vertices where
 * an edge pierces a triangle), and the pieces whose outer side has winding
 * number 0 are kept with their orientation and group; the curves become
 * edges of the result (creases where the parts meet at an angle); edges
 * shorter than 1e-4 of the diagonal at a cut point are collapsed. A surface
 * without self-intersections comes back as it is, except that a shell
 * inside another of the same orientation is dropped. Fails with
 * VC_EINPUT, one line "NAME: ..." naming the triangles, when the contact is
 * degenerate (a vertex or edge in another triangle's plane within rounding,
 * coplanar overlaps, three sheets through one point, a curve closed inside
 * one triangle) or the winding numbers are not whole; VC_ENOMEM. O(n log n)
 * for the pairs, plus the surface's size for each patch's winding number.
 * rep may be NULL. */
int vc_surface_self_union(const vc_surface *s, const char *name, vc_surface *out, vc_self_union_report *rep,
                          vc_error *err);

/* Collapses the edges shorter than eps whose end u >= first_movable (the
 * larger id of the two when both are) into the other end, in passes until
 * none is left: edges far below the error bound (marching cubes' clusters
 * of vertices around a grid point where the field is nearly zero, cut
 * points of a union passing within a hair of each other) would otherwise
 * set the sizing, and every ball around them. A collapse is made only when
 * it keeps the surface manifold (the link condition: two triangles on the
 * edge, no other common neighbour) and turns no triangle around u over;
 * the two triangles on the edge go, the triangles and groups are
 * compacted, unused vertices dropped. *max_move (may be NULL): the largest
 * distance a vertex moved (chains of collapses add up). Returns the number
 * of collapses, -1 when out of memory (the surface then unchanged only
 * if none was made). */
int64_t vc_surface_collapse_short_edges(vc_surface *s, int64_t first_movable, double eps,
                                        double *max_move);

/* Collapses the bases of hairpins, like vc_surface_collapse_short_edges
 * (the same link and turn-over tests, either end into the other; no chain
 * of collapses moves a point by more than max_base): a triangle whose
 * shortest edge is below max_base and whose two other edges fold by more
 * than the sharp angle (cos_sharp: its cosine) against two triangles that
 * agree with each other within it, a sliver of one face reaching into
 * another (a decimated marching-cubes part has them along its rims). Its
 * two sharp edges would be two creases max_base apart, meeting at a
 * corner, and the balls along them would shrink to that width for their
 * whole length; collapsed, the two sides of the slit are one smooth edge.
 * f (may be NULL): features of s as given (vc_features_detect_scaled at
 * the error bound); then only hairpins whose two folds are sharp in f, not
 * noise, are collapsed. The surface moves by at most *max_move (may be
 * NULL). Returns the number of collapses, -1 when out of memory. */
struct vc_features;
int64_t vc_surface_collapse_hairpins(vc_surface *s, double max_base, double cos_sharp,
                                     const struct vc_features *f, double *max_move);

/* The hairpins of s by the geometric test of vc_surface_collapse_hairpins
 * alone (the candidates; none: nothing to do), -1 when out of memory. */
int64_t vc_surface_count_hairpins(const vc_surface *s, double max_base, double cos_sharp);

/* 1 when some edge of s is shorter than eps. */
int vc_surface_has_edge_shorter(const vc_surface *s, double eps);

/* What vc_surface_flip_turned_needles did. */
typedef struct vc_needle_flip_report {
    int64_t n_flipped; /* edges flipped */
    int64_t n_fins;    /* ... of which needles standing up (60 to 90 degrees), not turned over */
    double max_move;   /* the largest apex height of a flipped needle: the surface moved by at
                          most this (two-sided Hausdorff distance) */
} vc_needle_flip_report;

/* Removes the turned-over needles of a closed, consistently oriented
 * surface, in place (s->tri is rewritten; vertices, triangle count and
 * groups stay): a triangle whose apex lies within max_move of its longest
 * edge and which folds by more than 90 degrees against the triangle across
 * that edge (the apex crossed the edge: a pleat that no ball sampling
 * follows), or by 60 to 90 degrees with its apex within a fifth of max_move
 * (a fin: a T-junction closed by a sliver whose apex is off the edge),
 * gets that edge flipped, when the flip lowers the largest fold
 * of the edges involved, the two new triangles fold by less than 90
 * degrees, the new edge is not already an edge and both triangles have one
 * group. The surface moves by at most the apex's height (rep->max_move).
 * Serial and deterministic, linear in the surface's size. max_move <= 0:
 * nothing is done. Fails only with VC_ENOMEM. rep may be NULL. */
int vc_surface_flip_turned_needles(vc_surface *s, double max_move, vc_needle_flip_report *rep,
                                   vc_error *err);

/* The triangles whose apex lies within max_move of their longest edge:
 * the candidates of vc_surface_flip_turned_needles (none: it has nothing
 * to do, and a caller need not copy the surface for it). */
int64_t vc_surface_count_low_needles(const vc_surface *s, double max_move);

/* What vc_surface_open_pinches did. */
typedef struct vc_pinch_report {
    int64_t n_pinches; /* vertices whose triangles formed several fans */
    int64_t n_copies;  /* vertices added (a fan beyond the first each) */
    double max_move;   /* the largest move of a copy: the surface moved by at most this */
} vc_pinch_report;

/* Opens the pinch vertices of a surface, in place: a vertex whose
 * triangles form several fans (cones touching only at their apex; joined
 * across the edges at the vertex, an edge of more than two triangles
 * joining all of its) gets a copy per fan beyond the first, appended to
 * the vertices, and each copy, the vertex itself for the first fan, moves
 * towards the centroid of its fan's ring by max_move, at most a quarter of
 * the distance to the nearest ring vertex. With min_cos > -1 only the
 * pinches whose fans meet at a small angle are opened: an edge of one fan
 * within the angle of min_cos of an edge of another (sheets that part
 * slowly from the apex, which sampling cannot follow; cones meeting at a
 * wide angle, two cubes' corners, are kept). The Euler characteristic
 * grows by the copies. Serial, deterministic. max_move <= 0: nothing is
 * done. Fails only with VC_ENOMEM. rep may be NULL. */
int vc_surface_open_pinches(vc_surface *s, double max_move, double min_cos, vc_pinch_report *rep,
                            vc_error *err);

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
