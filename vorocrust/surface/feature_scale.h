/* Sharp features at the scale of the approximation error (internal to the
 * surface module; see feature_scale.c and docs/sampling-convergence.md,
 * "Noise below the error bound"). */
#ifndef VC_SURFACE_FEATURE_SCALE_H
#define VC_SURFACE_FEATURE_SCALE_H

#include <stdint.h>
#include "vorocrust/features.h"
#include "vorocrust/surface.h"

/* How far from a fold the surface is looked at, and how far from one
 * plane it may then stray, in units of the error bound. */
#define VC_FLAT_REACH 4.0
#define VC_FLAT_SLAB 0.5
/* ... and how much its normals must agree: the length of their
 * area-weighted mean over the area */
#define VC_FLAT_COHERENCE 0.5
/* ... and, when they do not agree that well, the walk must be a graph over
 * its least-squares plane: the area facing away from it, weighted by how
 * far, at most VC_FLAT_TURNED of the whole (a sheet turned over: 0.5) */
#define VC_FLAT_TURNED 0.02
/* Curved ground: when the points stray farther from the plane, they may
 * lie within VC_FLAT_QUADRIC_SLAB of the slab from their least-squares
 * quadric instead, if the walk took at least VC_FLAT_QUADRIC_MIN
 * triangles (a quadric fits the few points of a coarse fold exactly). A
 * quadric absorbs about half of a crease's kink: a 60-degree crease at
 * reach R strays 0.11 R from it, 0.43 error bounds at 4 of them, so the
 * quadric's slab is half the plane's. */
#define VC_FLAT_QUADRIC_SLAB 0.5
#define VC_FLAT_QUADRIC_MIN 24
/* A coarse tessellation's walk takes fewer: it is made again twice as far,
 * up to this many times (the quadric is then held to its facets'
 * midpoints and centroids too, which a coarse curved facet chords away
 * from). */
#define VC_FLAT_GROW 2

/* A network of sharp edges whose vertices' bounding box has a diagonal
 * below this many error bounds is noise on coherent ground, however curved
 * (vc_features_unmark_noise_folds). */
#define VC_SPECK_EXTENT 1.0

/* Scratch memory of the neighbourhood walks (one per thread). */
typedef struct vc_flat_probe {
    int64_t *stamp;  /* n_triangles: the walk that last reached a triangle */
    int64_t *queue;  /* n_triangles */
    signed char *sign; /* n_triangles: orientation relative to the seeds */
    int64_t walk;
    int64_t n_reached; /* the last walk's triangles: queue[0 .. n_reached) */
} vc_flat_probe;

/* +1 when triangle t walks edge e from edge_vertex[2e] to edge_vertex[2e+1]
 * in its input order, -1 otherwise. */
int vc_features_walks_forward(const vc_features *f, const vc_surface *s, int64_t t, int64_t e);
/* Triangle t's centroid, its normal scaled by twice its area (the cross
 * product of its edges from its first vertex), and twice its area. */
void vc_triangle_centroid(const vc_surface *s, int64_t t, double c[3]);
void vc_triangle_cross(const vc_surface *s, int64_t t, double n[3]);
double vc_triangle_twice_area(const vc_surface *s, int64_t t);

int vc_flat_probe_init(vc_flat_probe *p, int64_t n_triangles);
void vc_flat_probe_free(vc_flat_probe *p);

/* Whether the surface near x lies within distance slab of one plane (or
 * within VC_FLAT_QUADRIC_SLAB * slab of a quadric, looking farther on a
 * coarse tessellation, see above): the
 * triangles reached from seeds[0..n_seeds-1] (always taken) across
 * manifold edges (only non-sharp ones when within_patch), each taken when
 * its centroid lies within reach of x. The plane is the one through their
 * area-weighted centroid normal to their area-weighted mean normal
 * (normals turned consistently across each edge crossed, from f->tri_normal
 * as it is at the call); false also when that mean is shorter than
 * VC_FLAT_COHERENCE of their area. If mean is not NULL it receives that mean normal
 * (unit, in the orientation of seeds[0]; zero when it vanishes). */
int vc_flat_near(const vc_surface *s, const vc_features *f, vc_flat_probe *p, const int64_t *seeds,
                 int n_seeds, const double x[3], double reach, double slab, int within_patch,
                 double mean[3]);

/* Step 2b of vc_features_detect_scaled: the folds above theta_sharp (edges
 * marked VC_SHARP_ANGLE) where the surface within VC_FLAT_REACH * scale
 * lies within VC_FLAT_SLAB * scale of one plane are not sharp: noise (a
 * scan's, a marching-cubes sliver's), not a feature, at the error bound;
 * only whole networks of sharp edges (joined at vertices) are unmarked,
 * and so are networks smaller than VC_SPECK_EXTENT * scale on coherent
 * ground.
 * Sets f->n_sharp_noise; marks in near (n_triangles bytes, zeroed by the
 * caller) the triangles there that lean more than theta_sharp / 2 from
 * the mean normal (the noise's). Returns 0 or -1 when out of memory. */
int vc_features_unmark_noise_folds(const vc_surface *s, vc_features *f, double scale,
                                   unsigned char *near);

/* Whether the surface around vertex v (its triangles vtri[0..n_vtri-1],
 * then out to VC_FLAT_REACH * scale) is flat to VC_FLAT_SLAB * scale: a
 * sector corner there is noise. If so, marks the leaning triangles there
 * in near (as vc_features_unmark_noise_folds). */
int vc_features_vertex_flat(const vc_surface *s, const vc_features *f, vc_flat_probe *p, int64_t v,
                            const int64_t *vtri, int64_t n_vtri, double scale, unsigned char *near);

/* Step 2c (round_creases.c): the folds below theta_sharp in the middle of
 * rounds narrower than the error bound scale become creases
 * (VC_SHARP_ROUND; f->n_sharp_round, and n_sharp_edges raised). *round_normal
 * receives NULL when none did, else 3 * n_triangles: for the triangles of
 * their bands, the flank normal each took (unit, in the triangle's input
 * orientation), zero elsewhere; the caller frees it. cos_theta: of
 * theta_sharp; near (or NULL): triangles beside noise, left alone. Returns
 * the edges made creases, or -1 when out of memory. */
int64_t vc_features_mark_rounds(const vc_surface *s, vc_features *f, double scale, double cos_theta,
                                const unsigned char *near, double **round_normal);

/* Step 6: f->tri_smooth_normal, the area-weighted mean of the patch-oriented
 * normals within VC_FLAT_REACH * scale of each marked triangle (near[t]), in
 * its patch; the triangle's own normal elsewhere (within theta_sharp / 2
 * of that mean, where noise was judged). Returns 0 or -1 when out
 * of memory. */
int vc_features_smooth_normals(const vc_surface *s, vc_features *f, double scale,
                               const unsigned char *near);

#endif
