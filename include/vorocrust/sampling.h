/* VoroCrust surface sampling (thesis 6.2.3 to 6.2.9): a union of balls
 * centred on the input surface that protects its sharp corners and creases
 * and covers its patches, and the Voronoi seeds placed where triplets of
 * ball spheres meet, on both sides of the surface.
 *
 * vc_sample_surface runs the recursive maximal Poisson-disk sampling in
 * three phases (corners, creases, patches), enforces the local Lipschitz
 * condition on the radii and removes slivers (triplets of balls whose seed
 * pair is half covered by a fourth ball) until none is left.
 * vc_balls_seeds then places the seeds and vc_reconstruct_surface builds
 * the reconstructed surface: the Voronoi facets between an inside and an
 * outside seed.
 *
 * Same surface, options and random seed give the same balls, seeds and
 * surface, whatever the number of threads. */
#ifndef VORO_CRUST_SAMPLING_H
#define VORO_CRUST_SAMPLING_H

#include <stdint.h>
#include "vorocrust/error.h"
#include "vorocrust/features.h"
#include "vorocrust/log.h"
#include "vorocrust/seeds.h"
#include "vorocrust/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Ball kinds: the dimension of the stratum the centre lies on. */
enum { VC_BALL_CORNER = 0, VC_BALL_EDGE = 1, VC_BALL_SURFACE = 2 };

typedef struct vc_sampling_options {
    double sharp_angle;   /* theta_sharp in degrees (features and co-smoothness), default 60 */
    double max_error;     /* approximation error bound, as a fraction of the bounding-box
                             diagonal: a ball may not reach the input farther than this
                             from its centre's tangent plane (surface balls) or tangent
                             line (edge balls); default 0.004; <= 0: no bound */
    double lipschitz;     /* L, 0 < L < 1, default 0.25 */
    double max_size;      /* sz: largest ball radius; <= 0: the bounding-box diagonal */
    double alpha;         /* deep-coverage constant, default 1 - sqrt(3)/2; the sampling
                             after sliver elimination shrank balls asks for alpha / 2
                             (thesis 6.2.7) */
    uint64_t seed;        /* random seed, default 1 */
    int threads;          /* <= 0: OpenMP's default */
    const vc_logger *log; /* progress lines (VC_LOG_INFO); NULL: none */
    int max_sliver_iterations; /* before the safe mode (alpha halved again), default 100; after
                                  twice as many the sampling counts as diverged */
    int64_t max_balls;    /* refuse a sampling predicted to need more balls, and stop one
                             that reaches this many (VC_EPARAM); <= 0: no limit (default) */
    unsigned char *stuck_tri; /* NULL, or n_triangles bytes: when sliver elimination
                             diverges, set to 1 for the triangles the balls of its last
                             pass reached before they were shrunk (where it is stuck),
                             0 elsewhere */
    double fold_stop_angle; /* > 0, with stuck_tri: also stop (diverged) as soon as the
                             half-covered pairs stop halving per pass, the balls having
                             doubled since the first coverage, when they are stuck at a
                             non-sharp edge folded by more than this many degrees */
    double smooth_width;  /* > 0: surface balls are centred on a smooth surface S' near
                             the input (an APSS fit of kernel radius smooth_width times
                             the error bound; sizing/smooth_surface.h) instead of on its
                             facets, and their radii are bounded by curvature_factor
                             times its radius of curvature; 0: on the facets */
    double curvature_factor; /* see smooth_width */
    double quartet_gap;   /* > 0: sliver elimination also separates near-quartets: a
                             seed whose power gap to a fourth sphere, d^2 / r^2 - 1, is
                             below this has that ball shrunk until it is this (two
                             near-coincident seeds of one side otherwise make short
                             Voronoi edges); 0 (default): only covered seeds */
    int lift_centres;     /* 1 (default): once sampled, surface ball centres move off the
                             input by the mean sag of their reconstructed facets, so that
                             the reconstruction has no volume bias (balls/centre_lift.h);
                             0: centres stay on the input */
} vc_sampling_options;

void vc_sampling_options_default(vc_sampling_options *opt);

/* The union of balls. */
typedef struct vc_balls {
    int64_t n;
    double *center;      /* 3n */
    double *radius;      /* n */
    signed char *kind;   /* VC_BALL_* */
    int64_t *element;    /* the corner vertex, sharp edge or triangle the centre lies on */
    double *normal;      /* 3n: outward unit normal of the surface at the centre (for an
                            edge or corner ball, the mean of the adjacent triangles') */
} vc_balls;

void vc_balls_free(vc_balls *b);

/* What the sampling did. */
typedef struct vc_sampling_stats {
    int64_t n_corner, n_edge, n_surface;   /* balls by kind */
    int64_t n_shrunk_lipschitz;            /* radius reductions for C3 */
    int64_t n_shrunk_sliver;               /* radius reductions for slivers */
    int64_t n_shrunk_flat;                 /* radius reductions for flat facets */
    int64_t n_shrunk_pinch;                /* radius reductions at edges of more than two
                                              facets (pinches) */
    int64_t n_shrunk_deviation;            /* radius reductions for facets farther from the
                                              input than the error bound */
    int sliver_iterations;
    int safe_mode;                         /* 1 when alpha was halved again (the safe
                                              mode: alpha / 4 after shrinking) */
    int64_t n_half_covered;                /* left at the end (0 on success) */
    double n_balls_predicted;              /* from the sizing, before sampling */
    /* Set when sampling failed because sliver elimination diverged
     * (n_half_covered then holds the last pass's count, n_balls_diverged
     * the ball count at that point). */
    int diverged;
    int64_t n_balls_diverged;
    /* Seconds per phase, as in the thesis' Table 6.1. */
    double t_features, t_sizing, t_corners, t_edges, t_surface, t_lipschitz, t_slivers;
    /* The centre lift (lift_centres): balls moved, checks run, passes
     * accepted, balls whose lift a failed check reduced, 1 when every lift
     * was dropped, the mean and largest move over the radius, seconds. */
    int64_t n_lifted, n_lift_reduced;
    int lift_rounds, lift_passes, lift_dropped;
    double lift_mean_rel, lift_max_rel, t_lift;
} vc_sampling_stats;

/* Samples the closed surface s with its features f (detected with
 * opt->sharp_angle). Fails with VC_EINPUT on an open surface (naming the
 * number of boundary edges) or when sliver elimination diverges (stats:
 * diverged), VC_EPARAM on bad options, VC_ENOMEM. */
int vc_sample_surface(const vc_surface *s, const vc_features *f,
                      const vc_sampling_options *opt, vc_balls *out,
                      vc_sampling_stats *stats, vc_error *err);

/* The seeds of a union of balls: for every triplet of pairwise
 * overlapping balls, the two points where their spheres meet, kept when no
 * fourth ball holds them strictly inside; label 1 on the inside of the
 * surface (the side the ball normals point away from), 0 outside. Points
 * closer than 1e-9 of the smallest radius involved are merged. Counts the
 * half-covered pairs (triplets with exactly one point kept) in
 * *n_half_covered when not NULL. The triplets are found on threads
 * threads (<= 0: OpenMP's default); the seeds are the same for any count. */
int vc_balls_seeds(const vc_balls *b, int threads, vc_seeds *out, int64_t *n_half_covered,
                   vc_error *err);

/* A polygonal surface: polygon k has the vertices
 * poly_vertices[poly_offsets[k] .. poly_offsets[k + 1] - 1]. */
typedef struct vc_polysurface {
    int64_t n_points;
    double *points;        /* 3 * n_points */
    int64_t n_polys;
    int64_t *poly_offsets; /* n_polys + 1 */
    int64_t *poly_vertices;
} vc_polysurface;

void vc_polysurface_free(vc_polysurface *p);

/* The reconstructed surface: the Voronoi facets between an inside
 * (label != 0) and an outside (label 0) seed among seeds[0 .. n_surface)
 * (n_surface <= 0: all of them), oriented outward (seen counter-clockwise
 * from the outside seed), with the mesh's global vertices (unused ones
 * dropped). Seeds from n_surface on must have label 0: they only bound
 * the cells (interior seeds, away from the balls, keep the inside cells
 * from reaching across the whole solid), and the facets toward them are
 * not the surface. spheres (may be NULL): the balls' spheres the seeds
 * lie on, so that every ball centre is one vertex (vc_voronoi_options).
 * The Voronoi engine's progress and phase times go to log (may be NULL). */
struct vc_seed_spheres;
int vc_reconstruct_surface(const vc_seeds *seeds, int64_t n_surface,
                           const struct vc_seed_spheres *spheres, int threads,
                           const vc_logger *log, vc_polysurface *out, vc_error *err);

/* Topology of a polygonal surface: edges used by exactly two polygons in
 * opposite directions make a closed, consistently oriented surface. */
typedef struct vc_polysurface_topology {
    int64_t n_vertices, n_edges, n_faces;
    int64_t euler;
    int64_t n_boundary_edges;      /* used by one polygon */
    int64_t n_nonmanifold_edges;   /* used by three or more */
    int64_t n_balanced_nonmanifold_edges; /* of those, walked as often each way (an even
                                             number of polygons: parts touching along
                                             the edge, each closed) */
    int64_t n_misoriented_edges;   /* two polygons walking it the same way */
    int64_t n_nonmanifold_vertices;/* whose polygons do not form one fan */
    int64_t n_components;
} vc_polysurface_topology;

int vc_polysurface_topology_compute(const vc_polysurface *p, vc_polysurface_topology *t,
                                    vc_error *err);

/* Writes the surface as OBJ (polygons), or as a .vtu of VTK_POLYGON cells
 * when the name ends in .vtu; through a temporary file. */
int vc_polysurface_write(const vc_polysurface *p, const char *path, vc_error *err);

/* Writes the balls as CSV: x,y,z,radius,kind,element,nx,ny,nz. */
int vc_balls_write_csv(const vc_balls *b, const char *path, vc_error *err);

#ifdef __cplusplus
}
#endif
#endif
