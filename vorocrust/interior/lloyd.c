/* Lloyd relaxation of the interior seeds (see include/vorocrust/interior.h):
 * the Voronoi engine gives every cell's centroid, the interior seeds move
 * there together, the surface seeds never move. */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "ball_tree.h"
#include "nearest_seed.h"
#include "vorocrust/voronoi.h"
#include "util/threads.h"
#include "util/clock.h"

int vc_interior_lloyd(const vc_balls *balls, vc_seeds *seeds, int64_t n_surface, int iterations,
                      int threads, vc_lloyd_stats *stats, vc_error *err)
{
    double t0 = vc_clock_seconds();
    vc_lloyd_stats st, kept;
    memset(&st, 0, sizeof st);
    kept = st;
    if (stats)
        *stats = st;
    if (iterations < 0 || n_surface < 0 || n_surface > seeds->n)
        return vc_error_set(err, VC_EPARAM, "Lloyd relaxation: bad iteration count %d or "
                            "surface seed count %lld", iterations, (long long)n_surface);
    if (iterations == 0 || n_surface == seeds->n)
        return 0;
    vc_ball_tree tree;
    vc_seed_kdtree grid;
    memset(&grid, 0, sizeof grid);
    vc_seeds surface = {n_surface, seeds->xyz, seeds->label};
    if (vc_ball_tree_build(&tree, balls))
        return vc_error_set(err, VC_ENOMEM, "out of memory for the Lloyd relaxation");
    if (vc_nearest_seed_index_build(&grid, &surface)) {
        vc_ball_tree_free(&tree);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the Lloyd relaxation");
    }
    int64_t n = seeds->n;
    /* target[3i..]: where interior seed n_surface + i goes; moved[i]: 1 moved,
     * 0 refused, -1 no cell */
    double *target = malloc(sizeof(double) * 3 * (size_t)(n - n_surface));
    double *previous = malloc(sizeof(double) * 3 * (size_t)(n - n_surface));
    double *shift = malloc(sizeof(double) * (size_t)(n - n_surface));
    signed char *moved = malloc((size_t)(n - n_surface));
    char *pinned = malloc((size_t)(n - n_surface));
    int64_t *cell_of = malloc(sizeof(int64_t) * (size_t)n);
    int rc = 0;
    if (!target || !previous || !shift || !moved || !pinned || !cell_of) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the Lloyd relaxation");
        goto done;
    }
    threads = vc_threads_or_default(threads);
    /* One more build than iterations: the mesh of the relaxed seeds is
     * checked too. A relaxed seed set whose mesh fails the validator (the
     * engine can leave a cell open on nearly degenerate seeds: a slightly
     * perturbed lattice is the worst case) is dropped for the previous one. */
    for (int it = 0; it <= iterations && !rc; it++) {
        vc_voronoi_options vo;
        vc_voronoi_options_default(&vo);
        vo.threads = threads;
        vo.log = NULL;
        vc_polymesh m;
        rc = vc_voronoi_build(seeds, &vo, &m, err);
        if (rc)
            break;
        if (it > 0 && vc_polymesh_validate(&m, 0, NULL, 0) != 0) {
            vc_polymesh_free(&m);
            memcpy(seeds->xyz + 3 * n_surface, previous,
                   sizeof(double) * 3 * (size_t)(n - n_surface));
            st = kept; /* the figures of the last iteration kept */
            st.reverted = 1;
            break;
        }
        if (it == iterations) {
            vc_polymesh_free(&m);
            break;
        }
        kept = st;
        memcpy(previous, seeds->xyz + 3 * n_surface, sizeof(double) * 3 * (size_t)(n - n_surface));
        for (int64_t i = 0; i < n; i++)
            cell_of[i] = -1;
        memset(pinned, 0, (size_t)(n - n_surface));
        for (int64_t c = 0; c < m.n_cells; c++)
            cell_of[m.cell_seed[c]] = c;
        /* Interior seeds whose cells touch a surface seed's cell stay put:
         * moved next to the surface seeds (which are co-spherical by
         * construction), they made nearly degenerate vertices the engine
         * did not always close (sphere.obj, icosphere, 2 iterations). */
        for (int64_t f = 0; f < m.n_faces; f++) {
            int64_t a = m.cell_seed[m.face_owner[f]], b = m.face_other_seed[f];
            if (a >= n_surface && b >= 0 && b < n_surface)
                pinned[a - n_surface] = 1;
            if (b >= n_surface && a < n_surface)
                pinned[b - n_surface] = 1;
        }
        /* each seed decided alone, so the result is independent of threads */
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
#endif
        for (int64_t i = 0; i < n - n_surface; i++) {
            int64_t c = cell_of[n_surface + i];
            const double *x = seeds->xyz + 3 * (n_surface + i);
            double *y = target + 3 * i;
            memcpy(y, x, sizeof(double) * 3);
            moved[i] = -1;
            shift[i] = 0;
            if (c < 0 || !(m.cell_volume[c] > 0))
                continue;
            moved[i] = 0;
            if (pinned[i])
                continue;
            const double *g = m.cell_centroid + 3 * c;
            double dn;
            int64_t q = vc_nearest_seed(&grid, g, &dn);
            /* nor may it leave its region */
            if (q < 0 || seeds->label[q] != seeds->label[n_surface + i] ||
                vc_ball_tree_covers_scaled(&tree, g, 1 + VC_INTERIOR_CLEARANCE))
                continue;
            moved[i] = 1;
            memcpy(y, g, sizeof(double) * 3);
            shift[i] = sqrt((g[0] - x[0]) * (g[0] - x[0]) + (g[1] - x[1]) * (g[1] - x[1]) +
                            (g[2] - x[2]) * (g[2] - x[2])) / cbrt(m.cell_volume[c]);
        }
        vc_polymesh_free(&m);
        st.iterations = it + 1;
        st.n_moved = st.n_refused = 0;
        st.mean_shift = st.max_shift = 0;
        for (int64_t i = 0; i < n - n_surface; i++) {
            st.n_moved += moved[i] == 1;
            st.n_refused += moved[i] == 0;
            st.mean_shift += shift[i];
            st.max_shift = fmax(st.max_shift, shift[i]);
        }
        if (st.n_moved)
            st.mean_shift /= (double)st.n_moved;
        memcpy(seeds->xyz + 3 * n_surface, target, sizeof(double) * 3 * (size_t)(n - n_surface));
    }
done:
    free(target);
    free(previous);
    free(shift);
    free(moved);
    free(pinned);
    free(cell_of);
    vc_ball_tree_free(&tree);
    vc_seed_kdtree_free(&grid);
    st.seconds = vc_clock_seconds() - t0;
    if (stats)
        *stats = st;
    return rc;
}
