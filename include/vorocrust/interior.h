/* Interior seeds (thesis 5.5.2, 6.2.10): seeds inside the volume, outside
 * the union of surface balls, so that the Voronoi cells of the inside
 * surface seeds and the interior seeds fill the volume the reconstructed
 * surface encloses.
 *
 * vc_interior_lattice places them on a cubic lattice (a hex-dominant
 * interior, thesis 6.2.10). A lattice point becomes a seed when it lies
 * outside every ball by the clearance (VC_INTERIOR_CLEARANCE, below),
 * inside the domain and at least half a spacing away
 * from every surface seed; inside means that its nearest surface seed is
 * an inside seed (the labels of the surface seeds decide, no second test).
 *
 * vc_interior_octree grades them instead (thesis 5.5.2): an octree (p4est)
 * over the bounding box, refined while a leaf's diagonal exceeds twice the
 * sizing at its centre (see vc_octree_options), 2:1 balanced, one seed at the centre of each leaf
 * that passes the same three tests (outside every ball by the clearance, inside, at least
 * half the leaf's side away from every surface seed). Cells then grow away
 * from the surface at the rate the Lipschitz constant allows.
 *
 * vc_interior_lloyd relaxes the interior seeds towards the centroids of
 * their Voronoi cells, the surface seeds fixed.
 *
 * vc_interior_protect moves the interior seeds that make short Voronoi
 * edges, a little, so that no five seeds lie nearly on one empty sphere. */
#ifndef VORO_CRUST_INTERIOR_H
#define VORO_CRUST_INTERIOR_H

#include "vorocrust/error.h"
#include "vorocrust/sampling.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/seeds.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How far outside every ball an interior seed lies: at least
 * (1 + VC_INTERIOR_CLEARANCE) r from the centre of a ball of radius r.
 * The surface seeds of a ball lie on its sphere, so their cells meet at
 * its centre in a fan of cones, thin near the centre (a corner or edge
 * ball has tens of seeds on its sphere). A seed at distance (1 + g) r
 * from the centre, at an angle a from the nearest of those seeds, cuts
 * the fan down to about g r / a from the centre: just outside a ball (g
 * of 1e-3, as the leaf centres of an octree fall) it leaves tiny faces
 * between cones whose bodies lie far away, the skew faces OpenFOAM's
 * checkMesh counts (bunny.off: 781 above 4, at most 35, 631 of them at
 * corner balls). 0.1: 223 above 4, at most 13.7, with no cell fatter
 * than before; docs/solver-grade-cells.md has the measurements. */
#define VC_INTERIOR_CLEARANCE 0.1

/* The default lattice spacing: the largest surface-ball radius (so that
 * interior cells are about the size of the largest surface cells), capped
 * by max_size when positive. */
double vc_interior_default_spacing(const vc_balls *balls, double max_size);

/* Appends the interior seeds (each labelled as its nearest surface seed:
 * its region) on a lattice of the given spacing to
 * a copy of the surface seeds: out = surface seeds, then interior seeds
 * in lattice order. *n_interior receives their number. Fails with
 * VC_EPARAM for a spacing that is not positive or would make more than
 * 1e9 lattice points, VC_ENOMEM. */
int vc_interior_lattice(const vc_balls *balls, const vc_seeds *surface_seeds, double spacing,
                        vc_seeds *out, int64_t *n_interior, vc_error *err);

/* Octree interior. The sizing at x is r(x) = min over the surface balls
 * of (r_p + g(|x - p|)), capped by max_size: g(d) = L d within far_from
 * radii of the ball's centre (the L-Lipschitz extension of the ball radii
 * into the volume, where the surface seeds' cells meet the first interior
 * cells), and beyond that it grows by far_lipschitz per unit of distance
 * (1: each leaf about as large as its distance to the surface, the
 * grading the octree's 2:1 balance allows). */
typedef struct vc_octree_options {
    double lipschitz; /* L, 0 < L < 1; default 0.25, the sampling's default */
    double far_from;  /* radii from a ball's centre where the far grading begins,
                         >= 0; default 3 */
    double far_lipschitz; /* L <= far_lipschitz; default 1 (far_lipschitz = L,
                             or far_from = INFINITY: L everywhere, as before
                             session 28) */
    double max_size;  /* cap of the sizing; <= 0: none (the box bounds the leaves) */
    double diagonal_factor; /* a leaf is refined while its diagonal exceeds this times
                               the sizing at its centre; default 2, thesis 5.5.2 (a leaf's
                               half-diagonal at most delta lfs(c), a ball radius being
                               delta lfs); 1 gives leaves half as large, 8 times as many */
    double clearance; /* a leaf centre within (1 + clearance) r of the centre of a
                         ball of radius r is no seed; default VC_INTERIOR_CLEARANCE,
                         >= 0 */
    int threads;      /* for the seed tests; <= 0: OpenMP's default; the output
                         does not depend on it */
} vc_octree_options;

void vc_octree_options_default(vc_octree_options *opt);

typedef struct vc_octree_stats {
    int64_t n_trees;         /* cubes of the brick the forest starts from */
    int64_t n_leaves;        /* after refinement and 2:1 balance */
    int64_t n_refined_leaves;/* before the balance */
    int64_t n_seeds;         /* interior seeds placed */
    int64_t n_covered;       /* leaves whose centre lies in a surface ball grown by the clearance */
    int64_t n_outside;       /* leaves whose centre's nearest surface seed is outside */
    int64_t n_near_seed;     /* leaves with a surface seed closer than half their side */
    int min_level, max_level;
    double seconds;          /* forest, balance and seed tests */
} vc_octree_stats;

/* The leaves of the forest, for inspection and tests: leaf k is the cube
 * of side side[k] centred at center[3k..3k+2], level[k] times halved from
 * its tree; seed_leaf[i] is the leaf of interior seed i. */
typedef struct vc_octree_leaves {
    int64_t n;
    double *center;
    double *side;
    int *level;
    int64_t n_seeds;
    int64_t *seed_leaf;
    double box[6];           /* the forest's box: lo x, y, z, hi x, y, z */
} vc_octree_leaves;

void vc_octree_leaves_free(vc_octree_leaves *l);

/* Appends the interior seeds (labelled as their nearest surface seeds) of the octree to a copy of the
 * surface seeds: out = surface seeds, then interior seeds in leaf (Morton)
 * order; *n_interior receives their number. stats and leaves may be NULL.
 * The program must have initialised MPI (MPI_Init or MPI_Init_thread;
 * the forest lives on MPI_COMM_SELF). Fails with VC_EPARAM on a bad option
 * or when MPI is not initialised, VC_EINPUT when there are no balls or
 * surface seeds, VC_ENOMEM. */
int vc_interior_octree(const vc_balls *balls, const vc_seeds *surface_seeds,
                       const vc_octree_options *opt, vc_seeds *out, int64_t *n_interior,
                       vc_octree_stats *stats, vc_octree_leaves *leaves, vc_error *err);

/* Lloyd relaxation: each of the iterations builds the Voronoi mesh of seeds
 * and moves every interior seed (index >= n_surface) to its cell's
 * centroid, all at once; the surface seeds stay fixed. A move is refused
 * (the seed stays put) when the centroid lies in a surface ball or its
 * nearest surface seed is an outside seed, so the interior seeds stay
 * inside and the reconstructed surface stays the same; interior seeds
 * whose cells touch a surface seed's cell stay put too. The mesh of the
 * relaxed seeds is built and validated once more at the end: when it
 * fails the validator, the relaxation stops at the last seeds whose mesh
 * passed (stats->reverted). Deterministic, whatever the thread count. */
typedef struct vc_lloyd_stats {
    int iterations;               /* done and kept */
    int reverted;                 /* 1 when the last iteration was undone */
    int64_t n_moved, n_refused;  /* in the last iteration */
    double mean_shift, max_shift; /* of the moved seeds in the last iteration, relative to
                                     the cube root of their cell's volume */
    double seconds;
} vc_lloyd_stats;

int vc_interior_lloyd(const vc_balls *balls, vc_seeds *seeds, int64_t n_surface, int iterations,
                      int threads, vc_lloyd_stats *stats, vc_error *err);

/* Seeds on the balls' spheres (docs/solver-grade-cells.md), inside the
 * domain: each a point of a ball's sphere that lies outside every other
 * ball by a margin and whose nearest surface seed is an inside seed, whose
 * label it takes (one per side on an interface between regions), less
 * those within a quarter of the ball's radius of an earlier one. On its
 * own sphere a seed is co-spherical with the ball's surface seeds (one
 * vertex at the centre for the engine), and outside the other balls it
 * leaves the reconstructed surface as it is.
 *  - poles (--protect): both points on every ball's normal (centre +-
 *    radius normal), outside the other balls scaled by sqrt(1 + pole_gap).
 *    The surface seeds of a side of a ball lie nearly on one circle of its
 *    sphere; the pole ends the nearly degenerate fan their cells make
 *    below the ball centre at the centre itself, instead of wherever an
 *    interior seed cuts it (short edges).
 *  - caps (default): 48 points spread over the sphere of every corner and
 *    edge ball, outside the other balls by the interior clearance
 *    (VC_INTERIOR_CLEARANCE) and at least half the ball's radius from
 *    every surface seed. Such a ball's seeds lie on the rings where the
 *    small balls around it cross its sphere; without caps their cells
 *    reach across the ball and the interior seeds cut them unevenly,
 *    leaving skew faces near its centre (bunny.off: 223 faces above
 *    checkMesh's skewness 4 without caps, 5 with them).
 * out gets the poles in ball order, then the caps in ball order (nothing
 * when there are none), *ball_of (malloc'ed, NULL when none) the ball of
 * each. Fails with VC_EPARAM (pole_gap outside [0, 1) with poles),
 * VC_ENOMEM. */
typedef struct vc_sphere_seed_options {
    int poles;       /* both poles of every ball; default 0 */
    double pole_gap; /* 0 <= pole_gap < 1; default 0 */
    int caps;        /* caps on every corner and edge ball; default 1 */
} vc_sphere_seed_options;

void vc_sphere_seed_options_default(vc_sphere_seed_options *opt);

int vc_interior_sphere_seeds(const vc_balls *balls, const vc_seeds *surface_seeds,
                             const vc_sphere_seed_options *opt, vc_seeds *out,
                             int64_t **ball_of, vc_error *err);

/* Short-edge protection of the interior seeds (issue 20;
 * docs/solver-grade-cells.md). A Voronoi edge is short when five seeds lie
 * nearly on one empty sphere; every such configuration a seed is part of
 * shows at a vertex of its own cell: as one of the cell's edges, or as the
 * edge that leaves the cell there (equidistant to the vertex's three other
 * seeds), which ends where a fifth seed comes as near. The measure of a
 * seed is the shortest of these edges over its cell's radius (the largest
 * distance from the seed to a vertex), edges shorter than 1e-9 of their
 * vertices' radius being ties (co-spherical seeds, exactly or to rounding:
 * one vertex for the engine). Every interior seed (index >= n_surface)
 * whose measure is below opt->min_edge is moved to the first of up to 8
 * random points (a fixed sequence per seed and round, from
 * opt->random_seed) within a quarter of the distance from its original
 * place to its nearest seed whose measure reaches the target, or to the
 * best of them when it beats the current place (Ghosh's and Li and Teng's
 * picking regions). A point is eligible only outside every surface ball
 * scaled by sqrt(1 + vc_protect_ball_gap(min_edge)) and with a nearest
 * surface seed of the seed's own label, so the reconstructed surface and
 * the regions do not change. In each round the seeds below the target none of whose cell's
 * neighbours is picked before them (seed order) search at once, and their
 * moves are taken in seed order, each only when no seed whose cell it
 * changes has moved in the round; the seeds a move took neighbours from
 * are measured again in the next round; up to 12 rounds. A seed
 * on a ball's sphere (vc_interior_sphere_seeds: a pole or a cap; opt->n_poles
 * of them, seeds n_surface .. n_surface + n_poles - 1)
 * moves on its ball's sphere (the point of the sphere nearest each random
 * point), so the ball centre stays a vertex of its cell. The surface seeds
 * never move: their own near-ties (two triplets of a near-quartet of
 * balls) stay. Deterministic, whatever the thread count. */
typedef struct vc_protect_options {
    double min_edge;      /* 0 <= min_edge < 0.25 (0: nothing moves); default 0.01 */
    uint64_t random_seed; /* default 1 */
    int64_t n_poles;
    const int64_t *pole_ball; /* n_poles: the ball of each sphere seed */
    /* Seeds from this index on are unmoved lattice points (the octree's
     * leaf centres, or the cubic lattice): one whose 32 nearest seeds all
     * are is not measured (its cell's ties are exact, its edges long).
     * < 0 (default): none. */
    int64_t lattice_begin;
    int threads;          /* <= 0: OpenMP's default; the result does not depend on it */
} vc_protect_options;

void vc_protect_options_default(vc_protect_options *opt);

/* The power gap, d^2 / r^2 - 1, by which a seed protected to min_edge
 * keeps outside every surface ball (whose centre is a vertex): 4 min_edge,
 * a gap of g at a vertex keeping its edges longer than about g R / 4. */
double vc_protect_ball_gap(double min_edge);

typedef struct vc_protect_stats {
    int64_t n_checked;            /* interior seeds measured or skipped as lattice seeds */
    int64_t n_short_before;       /* with a measure below the target, before */
    int64_t n_short_after;        /* and after */
    int64_t n_moved;              /* seeds moved (once or more) */
    int64_t n_moves;              /* moves in all rounds */
    int64_t n_measures;           /* cells built and measured */
    int rounds;
    double min_edge_before, min_edge_after; /* the smallest measure */
    double seconds;
} vc_protect_stats;

/* Fails with VC_EPARAM on a bad option or surface seed count, VC_ENOMEM. */
int vc_interior_protect(const vc_balls *balls, vc_seeds *seeds, int64_t n_surface,
                        const vc_protect_options *opt, vc_protect_stats *stats, vc_error *err);

/* Skew faces (issue 20): OpenFOAM's skewness of a face (checkMesh's, from
 * the two cells' centroids; vc_polymesh_face_skewness) above max_skew, and
 * checkMesh -allGeometry's other limits (interpolation weight 0.05, volume
 * ratio 0.01, concave cells), are mended at the seeds, not in the mesh: of
 * the seeds of each such face or cell, those that may move (index >=
 * movable_begin; for a surface seed's cell, the movable seeds next to it)
 * try `candidates` random places within a quarter of their
 * distance to the nearest seed, each judged by building the Voronoi cells
 * around it exactly (the seeds within a radius that holds every seed able
 * to cut the cells whose faces are judged) and summing by how much the
 * seed's cell and its neighbours' cells and faces miss those limits,
 * before and after; the best place that lowers it is taken. Places inside a ball
 * grown by `clearance` (its radius times 1 + clearance) or nearer a
 * surface seed of another label are not tried. The seeds are visited in
 * index order, each judged with the moves before it (the cells a move
 * changed, as it left them): the same moves for any thread count. The mesh is that of the seeds as they are (its
 * cell_seed indices into seeds); the caller builds the cells again. */
typedef struct vc_unskew_options {
    double max_skew;       /* default 3.9 (checkMesh fails a face above 4) */
    int64_t movable_begin; /* default -1: every seed from n_surface on */
    /* Seeds n_surface .. n_surface + n_sphere_seeds - 1 lie on the sphere
     * of ball sphere_ball[i] (vc_interior_sphere_seeds): their places are
     * taken on it. Default 0, NULL. */
    int64_t n_sphere_seeds;
    const int64_t *sphere_ball;
    double clearance;      /* default VC_INTERIOR_CLEARANCE */
    int candidates;        /* default 16 */
    uint64_t random_seed;  /* default 1 */
    int threads;           /* <= 0: OpenMP's default */
    /* NULL (default), or one flag per seed, read and written: a flagged
     * seed is not tried; a seed whose places were all judged and none
     * helped is flagged. Rounds of calls keep it, clearing the flags of
     * the seeds next to a seed that moved (vorocrust mesh --unskew). */
    unsigned char *stuck;
} vc_unskew_options;

void vc_unskew_options_default(vc_unskew_options *opt);

typedef struct vc_unskew_stats {
    int64_t n_skew_faces;  /* faces above max_skew in the mesh given */
    double max_skew;       /* the largest skewness there */
    int64_t n_weak_faces;  /* faces below checkMesh's interpolation weight
                              0.05 or volume ratio 0.01 */
    int64_t n_concave_cells; /* cells concave by checkMesh's test (a face
                              centre within 1e-6 of another face's plane) */
    int64_t n_tried;       /* movable seeds of those faces */
    int64_t n_moved;       /* seeds moved */
    int64_t n_cells_built; /* cells built to judge the places */
    double seconds;
} vc_unskew_stats;

/* Fails with VC_EPARAM on a bad option, VC_ENOMEM. */
int vc_interior_unskew(const vc_balls *balls, vc_seeds *seeds, int64_t n_surface,
                       const vc_polymesh *mesh, const vc_unskew_options *opt,
                       vc_unskew_stats *stats, vc_error *err);

#ifdef __cplusplus
}
#endif
#endif
