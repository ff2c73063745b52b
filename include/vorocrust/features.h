/* Sharp features of a triangle surface (thesis 6.2.2, "Feature Detection").
 *
 * Given a surface and the angle threshold theta_sharp, vc_features_detect
 * indexes the edges and computes the strata VoroCrust samples separately:
 *
 *  - sharp edges: edges whose two triangles' normals differ by more than
 *    theta_sharp (dihedral angle below pi - theta_sharp), and every edge
 *    with one triangle (open boundary) or more than two (non-manifold);
 *  - sharp corners: vertices with more than two sharp edges, with exactly
 *    two whose directions from the vertex make an angle below
 *    pi - theta_sharp, or with two triangles in one sector (the triangles
 *    around the vertex joined through its non-sharp edges) whose normals
 *    differ by at least theta_sharp. Two choices beyond the thesis text:
 *    a vertex with exactly one sharp edge (a crease fading into a smooth
 *    surface) is a corner, so that every crease is a cycle or joins two
 *    corners (the sector rule already makes it one whenever the edge is
 *    sharp by angle); and a vertex with no sharp edge whose triangles form
 *    more than one sector (a pinch point where surfaces touch at a single
 *    vertex) is a corner;
 *  - creases: maximal chains of sharp edges through vertices that are not
 *    corners; each either joins two corners (possibly the same one) or is
 *    a closed cycle without corners; each has an index and an orientation
 *    (its vertex order) applied to all its edges;
 *  - surface patches: the triangles connected across non-sharp edges; each
 *    has an index, and its triangles are oriented consistently (each
 *    interior edge walked in opposite directions by its two triangles),
 *    keeping the input orientation of the majority of the patch.
 *
 * Cost: O(n) in the size of the surface, except the sector test at a vertex
 * of valence k, which is O(k) when the sector's normals lie within
 * theta_sharp / 2 of their mean and O(k^2) in the worst case otherwise.
 *
 * Triangles of zero area (|cross| <= 1e-12 * longest edge^2, as in
 * vc_surface_check) have no normal: an edge between two triangles of which
 * one has zero area is not sharp by angle, and zero-area triangles are
 * skipped by the sector test. They still belong to a patch. */
#ifndef VORO_CRUST_FEATURES_H
#define VORO_CRUST_FEATURES_H

#include <stdint.h>
#include "vorocrust/error.h"
#include "vorocrust/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The default theta_sharp in degrees: the thesis' value for smooth models
 * (6.4.1, "We set theta_sharp to 60 degrees for smooth models, and choose
 * an appropriate value for models with sharp features"). The public
 * implementation's test inputs set their angle (VC_ANGLE) to 60 for
 * OneBox and Torus and to 23 for Bracket. */
#define VC_FEATURES_DEFAULT_SHARP_ANGLE 60.0

/* Why an edge is sharp (bits of edge_sharp; 0 = not sharp). */
enum {
    VC_SHARP_ANGLE = 1,       /* two triangles, normals differ by more than theta_sharp */
    VC_SHARP_BOUNDARY = 2,    /* one triangle */
    VC_SHARP_NONMANIFOLD = 4, /* three or more triangles */
    VC_SHARP_FOLD = 8,        /* a fold below theta_sharp the caller made a crease */
    VC_SHARP_ROUND = 16       /* the middle of a round narrower than the error bound */
};

/* Why a vertex is a sharp corner (bits of vertex_corner; 0 = no corner). */
enum {
    VC_CORNER_DEGREE = 1,  /* more than two sharp edges */
    VC_CORNER_TURN = 2,    /* two sharp edges at an angle below pi - theta_sharp */
    VC_CORNER_SECTOR = 4,  /* two triangles of a sector differ by >= theta_sharp */
    VC_CORNER_END = 8,     /* exactly one sharp edge (end of a crease) */
    VC_CORNER_PINCH = 16   /* no sharp edge, several sectors */
};

typedef struct vc_features {
    double sharp_angle;        /* theta_sharp, degrees */
    int64_t n_vertices, n_triangles; /* of the surface */

    /* ---- Edge index ----
     * Edge e joins edge_vertex[2e] < edge_vertex[2e+1]; edges are sorted
     * by (edge_vertex[2e], edge_vertex[2e+1]). Its triangles are
     * edge_tri[edge_tri_start[e] .. edge_tri_start[e+1] - 1], ascending
     * (one for a boundary edge, three or more for a non-manifold edge).
     * Side j of triangle t, from tri[3t+j] to tri[3t+(j+1)%3], is edge
     * tri_edge[3t+j]. The edges whose smaller vertex is v are
     * vertex_edge_start[v] .. vertex_edge_start[v+1] - 1. */
    int64_t n_edges;
    int64_t *edge_vertex;       /* 2 * n_edges */
    int64_t *edge_tri_start;    /* n_edges + 1 */
    int64_t *edge_tri;          /* 3 * n_triangles */
    int64_t *tri_edge;          /* 3 * n_triangles */
    int64_t *vertex_edge_start; /* n_vertices + 1 */

    /* ---- Per edge ---- */
    unsigned char *edge_sharp;  /* VC_SHARP_* bits, 0 when not sharp */
    int64_t *edge_crease;       /* crease of a sharp edge, -1 otherwise */
    signed char *edge_crease_dir; /* +1: the crease walks edge_vertex[2e] ->
                                     edge_vertex[2e+1]; -1: the other way;
                                     0: not sharp */

    /* ---- Per vertex ---- */
    unsigned char *vertex_corner; /* VC_CORNER_* bits, 0 when not a corner */
    int32_t *vertex_sharp_degree; /* number of sharp edges at the vertex */

    /* ---- Per triangle ---- */
    int64_t *tri_patch;         /* the patch of each triangle */
    signed char *tri_orient;    /* +1: the patch orientation is the input
                                   vertex order; -1: reversed */
    double *tri_normal;         /* 3 * n_triangles: unit normal in the patch
                                   orientation; (0,0,0) for zero area */
    /* NULL unless vc_features_detect_scaled judged folds or corners to be
     * noise, or made rounds creases: then 3 * n_triangles, the normals
     * smoothed at the error bound next to noise (the area-weighted mean of
     * the patch's normals within a few error bounds), the flank normal on
     * a round's band (tri_round), tri_normal elsewhere. The sizing takes
     * two triangles of a patch as co-smooth when either their normals or
     * these agree. */
    double *tri_smooth_normal;
    /* NULL unless a round narrower than the error bound became a crease
     * (VC_SHARP_ROUND): then n_triangles flags, 1 for the triangles of
     * its band, whose tri_smooth_normal is the flank of the round they lie
     * on; the sizing takes that as their tangent plane too. */
    unsigned char *tri_round;

    /* ---- Counts ---- */
    int64_t n_sharp_edges;
    int64_t n_sharp_by_angle;   /* sharp edges with VC_SHARP_ANGLE */
    int64_t n_boundary_edges;
    int64_t n_nonmanifold_edges;
    int64_t n_corners;
    int64_t n_degenerate;       /* zero-area triangles */
    double noise_scale;         /* the error bound features were judged at (0: none) */
    int64_t n_sharp_noise;      /* folds above theta_sharp left inside a patch: flat
                                   ground at noise_scale */
    int64_t n_corner_noise;     /* sector corners dropped for the same reason */
    int64_t n_corner_cosmooth;  /* vertices made corners (VC_CORNER_SECTOR, in n_corners)
                                   after the noise judgement: two triangles of one sector
                                   there agree neither in normals nor in smoothed ones,
                                   so the sizing would vanish at the vertex */
    int64_t n_sharp_visible;    /* folds below theta_sharp made creases: visible at
                                   noise_scale (VC_SHARP_FOLD) */
    int64_t n_sharp_round;      /* edges made creases in the middle of rounds narrower
                                   than noise_scale (VC_SHARP_ROUND) */

    /* ---- Creases ----
     * Crease c has k = crease_start[c+1] - crease_start[c] edges,
     * crease_edge[crease_start[c] .. crease_start[c+1] - 1], in order, and
     * the k + 1 vertices crease_vertex[crease_start[c] + c ..
     * crease_start[c+1] + c]: edge i of the crease goes from vertex i to
     * vertex i + 1. An open crease starts and ends at corners (the start
     * is the lower-numbered one); a closed crease has no corner and its
     * last vertex repeats its first. Open creases come first, ordered by
     * their start corner; closed ones are numbered after them. */
    int64_t n_creases;
    int64_t n_closed_creases;
    int64_t *crease_start;      /* n_creases + 1 */
    int64_t *crease_edge;       /* n_sharp_edges */
    int64_t *crease_vertex;     /* n_sharp_edges + n_creases */
    unsigned char *crease_closed; /* n_creases */

    /* ---- Surface patches ----
     * Patch p has the triangles patch_tri[patch_start[p] ..
     * patch_start[p+1] - 1], ascending. Patches are numbered by their
     * lowest triangle. A patch is non-orientable (patch_orientable 0) when
     * the flood met a triangle from both sides (a Moebius strip); its
     * tri_orient is then the one the flood gave first. */
    int64_t n_patches;
    int64_t n_nonorientable_patches;
    int64_t *patch_start;       /* n_patches + 1 */
    int64_t *patch_tri;         /* n_triangles */
    unsigned char *patch_orientable; /* n_patches */
} vc_features;

/* Detects the sharp features of s with the threshold theta_sharp_deg
 * (degrees, 0 < theta < 180; the thesis asks theta < 90, larger values
 * are allowed for experiments). s need not be closed or manifold.
 * Fails (out is then zeroed) with VC_EPARAM for a bad angle, VC_EINPUT
 * for a triangle index out of range or a triangle repeating a vertex,
 * VC_ENOMEM. */
int vc_features_detect(const vc_surface *s, double theta_sharp_deg, vc_features *out,
                       vc_error *err);

/* The same, with the edges e for which extra_sharp[e] != 0 sharp too
 * (VC_SHARP_FOLD) when no other rule makes them so; extra_sharp (or NULL)
 * is indexed like the edges of vc_features_detect on the same surface
 * (they are numbered by their sorted vertex pairs, so the numbering does
 * not depend on the angle). */
int vc_features_detect_with(const vc_surface *s, double theta_sharp_deg,
                            const unsigned char *extra_sharp, vc_features *out, vc_error *err);

/* The same, with the sharp features judged at the scale of the
 * approximation error: scale (an absolute length; 0 or not finite:
 * none, as vc_features_detect_with) is the error bound the mesh is asked
 * to keep. A fold above theta_sharp, or a sector corner, where the surface
 * within 4 * scale lies within scale / 2 of one plane is not a feature
 * there but noise (a scan's, marching cubes' slivers), and stays inside
 * its patch (n_sharp_noise, n_corner_noise, tri_smooth_normal). Folds of
 * coarse tessellations and true creases stay sharp: their own triangles,
 * or their two sides, spread wider than that.
 *
 * Conversely, a fold below theta_sharp that the error bound sees is a
 * crease (VC_SHARP_FOLD, n_sharp_visible): one whose flat triangles
 * leave the plane of each other by more than VC_VISIBLE_FOLD times scale
 * (the sine of the fold times the smaller of the two triangles' heights
 * over the edge). Kept smooth, such a fold bounds the balls on it by
 * scale / sin(fold), VC_VISIBLE_FOLD times smaller than its triangles: a
 * kink at the scale it is sampled at, where sliver elimination does not
 * converge (a 9,216-triangle torus at a bound of 1e-4 of its diagonal:
 * 650,000 balls and no end), while as a crease its sides are flat and take
 * balls of their own size. */
#define VC_VISIBLE_FOLD 8.0
/*
 * And a round narrower than the error bound is a crease (VC_SHARP_ROUND,
 * n_sharp_round): where folds below theta_sharp turn the surface by more
 * than theta_sharp between two flat flanks half an error bound apart, the
 * edges in the middle of the round (between the triangles nearer one
 * flank and those nearer the other) are sharp, and the band's triangles
 * take their flank's normal as their smoothed normal (tri_round). Kept
 * smooth, such a round bounds the balls by its radius over both flanks (a
 * wing whose trailing edge is rounded to a quarter of the bound: nine
 * times the balls of the same wing with a sharp edge). */
int vc_features_detect_scaled(const vc_surface *s, double theta_sharp_deg,
                              const unsigned char *extra_sharp, double scale, vc_features *out,
                              vc_error *err);

/* The cosine of the fold at edge e: of the angle between the normals of
 * its two triangles; 1 for an edge that is sharp or does not have exactly
 * two triangles (no fold inside a patch). */
double vc_features_fold_cos(const vc_features *f, int64_t e);

/* Frees the arrays of f and zeroes it. Safe on a zeroed vc_features. */
void vc_features_free(vc_features *f);

/* The edge joining vertices a and b (either order), or -1 when none. */
int64_t vc_features_find_edge(const vc_features *f, int64_t a, int64_t b);

/* Number of edges of crease c, and its vertices (n_edges + 1 of them). */
static inline int64_t vc_crease_n_edges(const vc_features *f, int64_t c)
{
    return f->crease_start[c + 1] - f->crease_start[c];
}
static inline const int64_t *vc_crease_vertices(const vc_features *f, int64_t c)
{
    return f->crease_vertex + f->crease_start[c] + c;
}

/* The vertices of triangle t in its patch orientation. */
void vc_features_oriented_triangle(const vc_features *f, const vc_surface *s, int64_t t,
                                   int64_t v[3]);

#ifdef __cplusplus
}
#endif
#endif
