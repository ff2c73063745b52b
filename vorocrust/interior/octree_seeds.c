/* Graded interior seeds from a p4est octree (see include/vorocrust/interior.h).
 *
 * The forest starts from a brick of equal cubes covering the balls'
 * bounding box, so every leaf is a cube. A leaf is refined while its
 * diagonal exceeds twice the sizing at its centre: the sizing is
 * L-Lipschitz, so across a leaf it changes by at most L times the
 * diagonal, leaves next to the surface come out about the size of the
 * balls there and grow away from it. */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <p8est_extended.h>

#include "ball_tree.h"
#include "nearest_seed.h"
#include "octree_runtime.h"
#include "util/threads.h"
#include "util/clock.h"

/* Bricks longer than this many trees on their long side are not worth it:
 * refinement reaches every scale anyway. */
enum { MAX_TREES_PER_AXIS = 16 };

/* What the refinement callback needs (p4est passes it as user_pointer). */
typedef struct forest_geometry {
    double lo[3];    /* the brick's low corner */
    double tree_side;
    vc_ball_grading grading;
    double cap, diagonal_factor;
    const vc_ball_tree *balls;
    const vc_seed_kdtree *seeds; /* the surface seeds, and their labels */
    const int32_t *label;
} forest_geometry;

void vc_octree_options_default(vc_octree_options *opt)
{
    opt->lipschitz = 0.25;
    opt->far_from = 3;
    opt->far_lipschitz = 1;
    opt->max_size = 0;
    opt->diagonal_factor = 2;
    opt->clearance = VC_INTERIOR_CLEARANCE;
    opt->threads = 0;
}

void vc_octree_leaves_free(vc_octree_leaves *l)
{
    free(l->center);
    free(l->side);
    free(l->level);
    free(l->seed_leaf);
    memset(l, 0, sizeof *l);
}

/* The centre and side of a quadrant in space. */
static void quadrant_cube(const p8est_t *forest, const forest_geometry *g, p4est_topidx_t tree,
                          const p8est_quadrant_t *q, double center[3], double *side)
{
    p4est_qcoord_t half = P8EST_QUADRANT_LEN(q->level) / 2;
    double v[3];
    p8est_qcoord_to_vertex(forest->connectivity, tree, q->x + half, q->y + half, q->z + half, v);
    for (int d = 0; d < 3; d++)
        center[d] = g->lo[d] + g->tree_side * v[d];
    *side = g->tree_side * ldexp(1.0, -(int)q->level);
}

static int leaf_too_large(const p8est_t *forest, p4est_topidx_t tree, const p8est_quadrant_t *q)
{
    const forest_geometry *g = forest->user_pointer;
    double c[3], side;
    quadrant_cube(forest, g, tree, q, c, &side);
    double diagonal = sqrt(3.0) * side;
    if (!vc_ball_tree_exceeds(g->balls, c, &g->grading, g->cap, diagonal, g->diagonal_factor))
        return 0;
    /* A leaf no ball reaches lies on one side of the reconstructed surface
     * (the balls hold it); outside (its centre's nearest surface seed an
     * outside one) it never holds a seed, and its children would not
     * either: left whole. The 2:1 balance refines it where an inside
     * neighbour needs. The inside leaves, and so the seeds, are what they
     * were; bunny.off's 131,000 outside leaves of 325,000 were refined to
     * the balls' size for nothing. */
    if (!vc_ball_tree_reaches(g->balls, c, 0.5 * diagonal)) {
        double dn;
        const int64_t q = vc_nearest_seed(g->seeds, c, &dn);
        if (q >= 0 && g->label[q] == 0)
            return 0;
    }
    return 1;
}

/* Each leaf carries its verdict (1: split it, 0: keep it, -1: not yet
 * decided, for the children a round made). */
static void leaf_undecided(p8est_t *forest, p4est_topidx_t tree, p8est_quadrant_t *q)
{
    (void)forest;
    (void)tree;
    *(int *)q->p.user_data = -1;
}

static int leaf_marked(p8est_t *forest, p4est_topidx_t tree, p8est_quadrant_t *q)
{
    (void)forest;
    (void)tree;
    return *(int *)q->p.user_data == 1;
}

/* Refines the forest until no leaf is too large, one level per round: the
 * sizing queries of a round's new leaves run in parallel (p4est's
 * recursive refinement calls them one by one), then p4est splits the
 * marked ones. Each verdict depends on its leaf alone, so the forest is
 * the recursive refinement's, for any thread count. Returns 0, or -1 when
 * out of memory. */
static int refine_by_sizing(p8est_t *forest, int threads)
{
    for (;;) {
        int64_t n = 0;
        for (p4est_topidx_t t = forest->first_local_tree; t <= forest->last_local_tree; t++)
            n += (int64_t)p8est_tree_array_index(forest->trees, t)->quadrants.elem_count;
        p8est_quadrant_t **leaf = malloc(sizeof *leaf * (size_t)(n > 0 ? n : 1));
        p4est_topidx_t *leaf_tree = malloc(sizeof *leaf_tree * (size_t)(n > 0 ? n : 1));
        if (!leaf || !leaf_tree) {
            free(leaf);
            free(leaf_tree);
            return -1;
        }
        int64_t m = 0;
        for (p4est_topidx_t t = forest->first_local_tree; t <= forest->last_local_tree; t++) {
            p8est_tree_t *tr = p8est_tree_array_index(forest->trees, t);
            for (size_t i = 0; i < tr->quadrants.elem_count; i++) {
                p8est_quadrant_t *q = p8est_quadrant_array_index(&tr->quadrants, i);
                if (*(int *)q->p.user_data < 0) {
                    leaf[m] = q;
                    leaf_tree[m++] = t;
                }
            }
        }
        int64_t n_split = 0;
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) reduction(+ : n_split)
        for (int64_t k = 0; k < m; k++) {
            const int split = leaf[k]->level < P8EST_QMAXLEVEL &&
                              leaf_too_large(forest, leaf_tree[k], leaf[k]);
            *(int *)leaf[k]->p.user_data = split;
            n_split += split;
        }
        free(leaf);
        free(leaf_tree);
        if (n_split == 0)
            return 0;
        p8est_refine_ext(forest, 0, P8EST_QMAXLEVEL, leaf_marked, leaf_undecided, NULL);
    }
}

/* Significant bits kept of the trees' side (see snap_to_lattice). */
enum { SIDE_BITS = 12 };

/* Puts the leaf centres on an exact binary lattice: the side rounded up to
 * SIDE_BITS significant bits, the low corner to a multiple of the side's
 * last bit over 2^20 (p4est's coordinates are multiples of 2^-19 of a
 * tree). Every centre lo + side * v is then exact in double, and the
 * differences of neighbouring centres have few significant bits. Why: the
 * centres of the leaves around a shared corner are co-spherical (the
 * corners of any box are), and the exact Voronoi engine certifies such
 * ties in double-double arithmetic only when their products are short;
 * otherwise each costs an evaluation in expansions. The side grows by at
 * most 2^-12 of itself (the brick stays centred); a brick too far from
 * the origin for the lattice to be exact is left as it is. */
static void snap_to_lattice(double lo[3], double *side, const int n[3])
{
    int e;
    (void)frexp(*side, &e); /* side = f 2^e, f in [0.5, 1) */
    const double unit = ldexp(1.0, e - SIDE_BITS);
    const double snapped = unit * ceil(*side / unit);
    const double quantum = ldexp(unit, -20);
    double out[3];
    for (int d = 0; d < 3; d++) {
        const double centred = lo[d] - 0.5 * (double)n[d] * (snapped - *side);
        out[d] = quantum * nearbyint(centred / quantum);
        /* exact while every centre stays below 2^53 quanta */
        if (!(fabs(out[d]) + (double)(n[d] + 1) * snapped < ldexp(quantum, 52)))
            return;
    }
    memcpy(lo, out, sizeof out);
    *side = snapped;
}

/* The bounding box of the ball centres, grown by 1% of its diagonal so that
 * no centre sits on the forest's boundary, then covered by a brick of
 * n[0] x n[1] x n[2] cubes of side *tree_side, centred on it. */
static void brick_layout(const vc_balls *b, double lo[3], double *tree_side, int n[3])
{
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    lo[0] = lo[1] = lo[2] = INFINITY;
    for (int64_t i = 0; i < b->n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], b->center[3 * i + d]);
            hi[d] = fmax(hi[d], b->center[3 * i + d]);
        }
    double ext[3], diag2 = 0, max_ext = 0;
    for (int d = 0; d < 3; d++) {
        ext[d] = hi[d] - lo[d];
        diag2 += ext[d] * ext[d];
    }
    double grow = 0.01 * sqrt(diag2);
    if (!(grow > 0))
        grow = b->radius[0] > 0 ? b->radius[0] : 1.0; /* a single ball */
    for (int d = 0; d < 3; d++) {
        lo[d] -= grow;
        ext[d] += 2 * grow;
        max_ext = fmax(max_ext, ext[d]);
    }
    double min_ext = fmin(ext[0], fmin(ext[1], ext[2]));
    /* cubes as large as the thinnest side allows, at most 16 along the
     * longest */
    double side = fmax(min_ext, max_ext / MAX_TREES_PER_AXIS);
    for (int d = 0; d < 3; d++) {
        n[d] = (int)ceil(ext[d] / side - 1e-9);
        if (n[d] < 1)
            n[d] = 1;
        lo[d] -= 0.5 * ((double)n[d] * side - ext[d]);
    }
    *tree_side = side;
    snap_to_lattice(lo, tree_side, n);
}

int vc_interior_octree(const vc_balls *balls, const vc_seeds *ss, const vc_octree_options *opt,
                       vc_seeds *out, int64_t *n_interior, vc_octree_stats *stats,
                       vc_octree_leaves *leaves, vc_error *err)
{
    double t0 = vc_clock_seconds();
    memset(out, 0, sizeof *out);
    *n_interior = 0;
    vc_octree_stats st;
    memset(&st, 0, sizeof st);
    if (stats)
        *stats = st;
    if (leaves)
        memset(leaves, 0, sizeof *leaves);
    if (!(opt->lipschitz > 0 && opt->lipschitz < 1))
        return vc_error_set(err, VC_EPARAM, "the octree's Lipschitz constant must be in (0, 1), "
                            "got %g", opt->lipschitz);
    if (!(opt->far_from >= 0) || !(opt->far_lipschitz >= opt->lipschitz) || !isfinite(opt->far_lipschitz))
        return vc_error_set(err, VC_EPARAM, "the octree's far grading must start at a distance >= 0 "
                            "and grow at least as fast as near the balls, got %g radii and %g",
                            opt->far_from, opt->far_lipschitz);
    if (!(opt->diagonal_factor > 0) || !isfinite(opt->diagonal_factor))
        return vc_error_set(err, VC_EPARAM, "the octree's diagonal factor must be positive, got %g",
                            opt->diagonal_factor);
    if (!(opt->clearance >= 0) || !isfinite(opt->clearance))
        return vc_error_set(err, VC_EPARAM, "the octree's clearance from the balls must be a "
                            "number >= 0, got %g", opt->clearance);
    if (balls->n == 0)
        return vc_error_set(err, VC_EINPUT, "no surface balls to grade the octree by");
    if (ss->n == 0)
        return vc_error_set(err, VC_EINPUT, "no surface seeds to place interior seeds against");
    int rc = vc_octree_runtime_start(err);
    if (rc)
        return rc;

    forest_geometry g;
    int n[3];
    brick_layout(balls, g.lo, &g.tree_side, n);
    g.grading.lipschitz = opt->lipschitz;
    g.grading.far_from = opt->far_from;
    g.grading.far_lipschitz = opt->far_lipschitz;
    g.diagonal_factor = opt->diagonal_factor;
    g.cap = opt->max_size > 0 ? opt->max_size : INFINITY;
    vc_ball_tree tree;
    vc_seed_kdtree grid;
    memset(&grid, 0, sizeof grid);
    if (vc_ball_tree_build(&tree, balls))
        return vc_error_set(err, VC_ENOMEM, "out of memory for the octree interior");
    if (vc_nearest_seed_index_build(&grid, ss)) {
        vc_ball_tree_free(&tree);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the octree interior");
    }
    g.balls = &tree;
    g.seeds = &grid;
    g.label = ss->label;

    p8est_connectivity_t *conn = p8est_connectivity_new_brick(n[0], n[1], n[2], 0, 0, 0);
    p8est_t *forest = p8est_new_ext(MPI_COMM_SELF, conn, 0, 0, 1, sizeof(int), leaf_undecided, &g);
    if (refine_by_sizing(forest, vc_threads_or_default(opt->threads))) {
        p8est_destroy(forest);
        p8est_connectivity_destroy(conn);
        vc_seed_kdtree_free(&grid);
        vc_ball_tree_free(&tree);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the octree interior");
    }
    st.n_refined_leaves = (int64_t)forest->local_num_quadrants;
    /* Full (face, edge and corner) balance: every pair of leaves that touch,
     * even at a corner, differs by one level at most. Leaf centres become
     * seeds whose Voronoi cells neighbour across edges and corners too, so
     * face balance alone would let a cell meet cells 4 times smaller. */
    p8est_balance(forest, P8EST_CONNECT_FULL, NULL);
    st.n_trees = (int64_t)n[0] * n[1] * n[2];
    st.n_leaves = (int64_t)forest->local_num_quadrants;

    int64_t nl = st.n_leaves;
    double *center = malloc(sizeof(double) * 3 * (size_t)(nl > 0 ? nl : 1));
    double *side = malloc(sizeof(double) * (size_t)(nl > 0 ? nl : 1));
    int *level = malloc(sizeof(int) * (size_t)(nl > 0 ? nl : 1));
    signed char *verdict = malloc((size_t)(nl > 0 ? nl : 1));
    /* the label of a seed's nearest surface seed: its region */
    int32_t *leaf_label = malloc(sizeof(int32_t) * (size_t)(nl > 0 ? nl : 1));
    if (center && side && level && verdict && leaf_label) {
        st.min_level = P8EST_QMAXLEVEL;
        int64_t k = 0;
        for (p4est_topidx_t t = forest->first_local_tree; t <= forest->last_local_tree; t++) {
            p8est_tree_t *tr = p8est_tree_array_index(forest->trees, t);
            for (size_t i = 0; i < tr->quadrants.elem_count; i++, k++) {
                p8est_quadrant_t *q = p8est_quadrant_array_index(&tr->quadrants, i);
                quadrant_cube(forest, &g, t, q, center + 3 * k, side + k);
                level[k] = q->level;
                st.min_level = level[k] < st.min_level ? level[k] : st.min_level;
                st.max_level = level[k] > st.max_level ? level[k] : st.max_level;
            }
        }
    }
    p8est_destroy(forest);
    p8est_connectivity_destroy(conn);
    if (!center || !side || !level || !verdict || !leaf_label) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for %lld octree leaves", (long long)nl);
        goto done;
    }

    /* The seed tests, leaf by leaf (independent, so any thread count gives
     * the same verdicts): 0 seed, 1 in a ball (grown by the clearance), 2 outside, 3 too near a
     * surface seed. A surface seed closer than half the side lies inside
     * the leaf's inscribed ball: it already gives that region its cell,
     * and a seed at the centre would split it into two thin cells. Half the
     * side is also the lattice's rule (half a spacing). */
    const int threads = vc_threads_or_default(opt->threads);
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
    for (int64_t k = 0; k < nl; k++) {
        const double *c = center + 3 * k;
        if (vc_ball_tree_covers_scaled(&tree, c, 1 + opt->clearance)) {
            verdict[k] = 1;
            continue;
        }
        double dn;
        int64_t q = vc_nearest_seed(&grid, c, &dn);
        leaf_label[k] = q < 0 ? 0 : ss->label[q];
        if (q < 0 || ss->label[q] == 0)
            verdict[k] = 2;
        else if (dn < 0.5 * side[k])
            verdict[k] = 3;
        else
            verdict[k] = 0;
    }
    int64_t ns = 0;
    for (int64_t k = 0; k < nl; k++) {
        ns += verdict[k] == 0;
        st.n_covered += verdict[k] == 1;
        st.n_outside += verdict[k] == 2;
        st.n_near_seed += verdict[k] == 3;
    }
    if (vc_seeds_alloc(out, ss->n + ns, err)) {
        rc = VC_ENOMEM;
        goto done;
    }
    memcpy(out->xyz, ss->xyz, sizeof(double) * 3 * (size_t)ss->n);
    memcpy(out->label, ss->label, sizeof(int32_t) * (size_t)ss->n);
    int64_t *seed_leaf = leaves ? malloc(sizeof(int64_t) * (size_t)(ns > 0 ? ns : 1)) : NULL;
    if (leaves && !seed_leaf) {
        vc_seeds_free(out);
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the octree leaves");
        goto done;
    }
    int64_t m = ss->n;
    for (int64_t k = 0; k < nl; k++) {
        if (verdict[k] != 0)
            continue;
        if (seed_leaf)
            seed_leaf[m - ss->n] = k;
        memcpy(out->xyz + 3 * m, center + 3 * k, sizeof(double) * 3);
        out->label[m++] = leaf_label[k];
    }
    *n_interior = ns;
    st.n_seeds = ns;
    if (leaves) {
        leaves->n = nl;
        leaves->center = center;
        leaves->side = side;
        leaves->level = level;
        leaves->n_seeds = ns;
        leaves->seed_leaf = seed_leaf;
        for (int d = 0; d < 3; d++) {
            leaves->box[d] = g.lo[d];
            leaves->box[3 + d] = g.lo[d] + n[d] * g.tree_side;
        }
        center = side = NULL;
        level = NULL;
    }
done:
    free(center);
    free(side);
    free(level);
    free(verdict);
    free(leaf_label);
    vc_ball_tree_free(&tree);
    vc_seed_kdtree_free(&grid);
    st.seconds = vc_clock_seconds() - t0;
    if (stats)
        *stats = st;
    return rc;
}
