/* vorocrust mesh: VoroCrust surface sampling of a closed triangle surface,
 * its seeds, the reconstructed surface and (without --surface-only) the
 * Voronoi mesh of the inside seeds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli_util.h"
#include "commands.h"
#include "vorocrust/features.h"
#include "vorocrust/interior.h"
#include "vorocrust/io.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/quality.h"
#include "vorocrust/sampling.h"
#include "vorocrust/smoothing.h"
#include "vorocrust/surface.h"
#include "vorocrust/voronoi.h"

/* The OpenFOAM case gets its skew faces collapsed down to this skewness by
 * default: checkMesh fails above 4, and a margin keeps versions of OpenFOAM
 * that round differently on the right side. */
#define FOAM_DEFAULT_MAX_SKEW 3.5
#define FOAM_COLLAPSE_ROUNDS 20

static void usage(FILE *f)
{
    vc_sampling_options d;
    vc_sampling_options_default(&d);
    fprintf(f,
        "usage: vorocrust mesh INPUT (--surface-only --surface OUT.obj | -o OUT.vtu) [options]\n"
        "  INPUT               closed triangle surface: .obj, .off, .stl, .ply\n"
        "  --surface-only      stop after the surface: sampling, seeds, reconstructed surface\n"
        "  --surface OUT       the reconstructed surface: OBJ polygons, or VTK_POLYGON cells\n"
        "                      when OUT ends in .vtu\n"
        "  -o, --output OUT.vtu  the volume mesh: the Voronoi cells of the inside surface seeds\n"
        "                      and the interior seeds\n"
        "  --foam CASE_DIR     also write the volume mesh as OpenFOAM CASE_DIR/constant/polyMesh\n"
        "  --connections OUT.csv  with -o: the interior faces of the volume mesh (cells, seeds,\n"
        "                      area, seed distance, centroid, normal), as 'vorocrust voronoi'\n"
        "  --foam-max-skew S   before writing the OpenFOAM case, collapse the faces whose\n"
        "                      checkMesh skewness exceeds S (default %g; 0: write the exact\n"
        "                      Voronoi cells; checkMesh fails a mesh above 4)\n"
        "  --interior octree|lattice|none  interior seeds: graded by a p4est octree (default),\n"
        "                      on a cubic lattice, or none\n"
        "  --interior-spacing H  lattice spacing (default: the largest ball radius)\n"
        "  --lloyd N           N iterations of Lloyd relaxation of the interior seeds, 0 to\n"
        "                      1000 (default 0); the surface seeds stay fixed\n"
        "  --seeds OUT.csv     the seeds (x,y,z,label: 1 inside, 0 outside)\n"
        "  --balls OUT.csv     the balls (x,y,z,radius,kind,element,nx,ny,nz)\n"
        "  --sharp-angle DEG   theta_sharp, 0 < DEG < 180 (default %g)\n"
        "  --smooth-iterations N  rounds of adaptive, feature-preserving Loop subdivision\n"
        "                      of the patches before sampling, 0 to %d (default 0; the\n"
        "                      thesis uses %d, but Loop moves the surface off the input)\n"
        "  --max-error E       approximation error bound, a fraction of the bounding-box\n"
        "                      diagonal, 0 <= E < 1 (default %g; 0: none, as in the thesis)\n"
        "  --lipschitz L       0 < L < 1 (default %g)\n"
        "  --max-size H        largest ball radius and cap of the octree sizing (default:\n"
        "                      the bounding-box diagonal)\n"
        "  --seed N            random seed (default %llu)\n"
        "  --threads N         threads, 1 to 4096 (default: all cores)\n"
        "  --quiet             no progress and no summary on stderr\n",
        FOAM_DEFAULT_MAX_SKEW, d.sharp_angle, VC_SMOOTH_MAX_ITERATIONS, VC_SMOOTH_DEFAULT_ITERATIONS, d.max_error,
        d.lipschitz, (unsigned long long)d.seed);
}

static int takes_value(const char *a)
{
    static const char *const with_value[] = {"-o", "--output", "--surface", "--seeds", "--balls",
                                             "--sharp-angle", "--max-error", "--lipschitz",
                                             "--max-size", "--seed", "--threads", "--interior", "--smooth-iterations",
                                             "--interior-spacing", "--foam", "--lloyd",
                                             "--foam-max-skew", "--connections"};
    for (size_t i = 0; i < sizeof with_value / sizeof *with_value; i++)
        if (!strcmp(a, with_value[i]))
            return 1;
    return 0;
}

/* Cell quality of the volume mesh: volume and fatness extremes, fatness
 * over the interior cells (no face on the boundary), shortest edge
 * relative to the enclosing radius. */
typedef struct mesh_quality {
    double vol_min, vol_max;
    double fat_max, fat_sum, fat_int_max, fat_int_sum, edge_rel_min;
    int64_t n, n_int, n_unmeasured;
} mesh_quality;

static void measure_mesh(const vc_polymesh *m, mesh_quality *q, double *fatness)
{
    memset(q, 0, sizeof *q);
    q->vol_min = q->edge_rel_min = INFINITY;
    int64_t cap_f = 64, cap_v = 512;
    int64_t *foff = malloc(sizeof(int64_t) * (size_t)(cap_f + 1));
    int64_t *fv = malloc(sizeof(int64_t) * (size_t)cap_v);
    int64_t *vs = malloc(sizeof(int64_t) * (size_t)cap_v);
    if (!foff || !fv || !vs)
        goto done;
    for (int64_t c = 0; c < m->n_cells; c++) {
        int64_t f0 = m->cell_offsets[c], f1 = m->cell_offsets[c + 1], nfv = 0, nf = f1 - f0;
        int boundary = 0;
        for (int64_t k = f0; k < f1; k++) {
            int64_t f = m->cell_faces[k];
            nfv += m->face_offsets[f + 1] - m->face_offsets[f];
            boundary |= m->face_neighbour[f] < 0;
        }
        if (nf > cap_f || nfv > cap_v) {
            cap_f = nf > cap_f ? 2 * nf : cap_f;
            cap_v = nfv > cap_v ? 2 * nfv : cap_v;
            int64_t *a = realloc(foff, sizeof(int64_t) * (size_t)(cap_f + 1));
            int64_t *b = realloc(fv, sizeof(int64_t) * (size_t)cap_v);
            int64_t *d = realloc(vs, sizeof(int64_t) * (size_t)cap_v);
            if (a)
                foff = a;
            if (b)
                fv = b;
            if (d)
                vs = d;
            if (!a || !b || !d)
                goto done;
        }
        int64_t n = 0;
        foff[0] = 0;
        for (int64_t k = f0; k < f1; k++) {
            int64_t f = m->cell_faces[k], a = m->face_offsets[f], len = m->face_offsets[f + 1] - a;
            int rev = m->face_owner[f] != c;
            for (int64_t j = 0; j < len; j++)
                fv[n + j] = m->face_vertices[a + (rev ? len - 1 - j : j)];
            n += len;
            foff[k - f0 + 1] = n;
        }
        /* distinct vertices */
        int64_t nv = 0;
        for (int64_t j = 0; j < n; j++) {
            int seen = 0;
            for (int64_t i = 0; i < nv && !seen; i++)
                seen = vs[i] == fv[j];
            if (!seen)
                vs[nv++] = fv[j];
        }
        vc_cell cell = {m->points, nv, vs, nf, foff, fv};
        vc_cell_measures cm;
        if (vc_cell_measure(&cell, &cm) != 0 || !isfinite(cm.fatness)) {
            q->n_unmeasured++;
            if (fatness)
                fatness[c] = NAN;
            continue;
        }
        if (fatness)
            fatness[c] = cm.fatness;
        q->n++;
        q->vol_min = fmin(q->vol_min, cm.volume);
        q->vol_max = fmax(q->vol_max, cm.volume);
        q->fat_max = fmax(q->fat_max, cm.fatness);
        q->fat_sum += cm.fatness;
        q->edge_rel_min = fmin(q->edge_rel_min, cm.shortest_edge_rel);
        if (!boundary) {
            q->n_int++;
            q->fat_int_max = fmax(q->fat_int_max, cm.fatness);
            q->fat_int_sum += cm.fatness;
        }
    }
done:
    free(foff);
    free(fv);
    free(vs);
}

int vc_cmd_mesh(int argc, char **argv)
{
    const char *in_path = NULL, *surf_path = NULL, *out_path = NULL, *seeds_path = NULL,
               *balls_path = NULL, *foam_path = NULL, *conn_path = NULL;
    enum { INTERIOR_NONE, INTERIOR_LATTICE, INTERIOR_OCTREE } interior = INTERIOR_OCTREE;
    int surface_only = 0, quiet = 0, lloyd_iterations = 0, sharp_angle_given = 0,
        smooth_iterations_given = 0;
    /* 0 by default, not the thesis' 6: Loop subdivision approximates, it
     * pulls the surface off the input (sphere.obj: 0.78% of the diagonal,
     * 3.3% of the volume after 6 rounds), beyond the 0.5% error budget. */
    int smooth_iterations = 0;
    double interior_spacing = 0, foam_max_skew = FOAM_DEFAULT_MAX_SKEW;
    vc_skew_collapse_stats foam_skew;
    memset(&foam_skew, 0, sizeof foam_skew);
    vc_sampling_options opt;
    vc_sampling_options_default(&opt);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--surface-only")) {
            surface_only = 1;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (takes_value(a) && !v) {
            fprintf(stderr, "vorocrust: %s needs a value (see 'vorocrust mesh --help')\n", a);
            return 2;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            out_path = argv[++i];
        } else if (!strcmp(a, "--foam")) {
            foam_path = argv[++i];
        } else if (!strcmp(a, "--connections")) {
            conn_path = argv[++i];
        } else if (!strcmp(a, "--foam-max-skew")) {
            if (vc_cli_parse_double(v, &foam_max_skew) ||
                !(foam_max_skew == 0 || (foam_max_skew >= 1 && foam_max_skew <= 1000))) {
                fprintf(stderr, "vorocrust: --foam-max-skew needs 0 or a number from 1 to 1000, "
                        "got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--surface")) {
            surf_path = argv[++i];
        } else if (!strcmp(a, "--smooth-iterations")) {
            long it;
            if (vc_cli_parse_int(v, 0, VC_SMOOTH_MAX_ITERATIONS, &it)) {
                fprintf(stderr, "vorocrust: --smooth-iterations needs an integer from 0 to %d, "
                        "got '%s'\n", VC_SMOOTH_MAX_ITERATIONS, v);
                return 2;
            }
            smooth_iterations = (int)it;
            smooth_iterations_given = 1;
            i++;
        } else if (!strcmp(a, "--interior")) {
            if (!strcmp(v, "octree"))
                interior = INTERIOR_OCTREE;
            else if (!strcmp(v, "lattice"))
                interior = INTERIOR_LATTICE;
            else if (!strcmp(v, "none"))
                interior = INTERIOR_NONE;
            else {
                fprintf(stderr, "vorocrust: --interior: '%s' is not octree, lattice or none\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--lloyd")) {
            long it;
            if (vc_cli_parse_int(v, 0, 1000, &it)) {
                fprintf(stderr, "vorocrust: --lloyd needs an integer from 0 to 1000, got '%s'\n", v);
                return 2;
            }
            lloyd_iterations = (int)it;
            i++;
        } else if (!strcmp(a, "--interior-spacing")) {
            if (vc_cli_parse_double(v, &interior_spacing) || !(interior_spacing > 0)) {
                fprintf(stderr, "vorocrust: --interior-spacing needs a positive number, got '%s'\n",
                        v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--seeds")) {
            seeds_path = argv[++i];
        } else if (!strcmp(a, "--balls")) {
            balls_path = argv[++i];
        } else if (!strcmp(a, "--sharp-angle")) {
            sharp_angle_given = 1;
            if (vc_cli_parse_double(v, &opt.sharp_angle) ||
                !(opt.sharp_angle > 0 && opt.sharp_angle < 180)) {
                fprintf(stderr, "vorocrust: --sharp-angle needs a number of degrees in (0, 180), "
                        "got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--max-error")) {
            if (vc_cli_parse_double(v, &opt.max_error) ||
                !(opt.max_error >= 0 && opt.max_error < 1)) {
                fprintf(stderr, "vorocrust: --max-error needs a number in [0, 1), got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--lipschitz")) {
            if (vc_cli_parse_double(v, &opt.lipschitz) || !(opt.lipschitz > 0 && opt.lipschitz < 1)) {
                fprintf(stderr, "vorocrust: --lipschitz needs a number in (0, 1), got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--max-size")) {
            if (vc_cli_parse_double(v, &opt.max_size) || !(opt.max_size > 0)) {
                fprintf(stderr, "vorocrust: --max-size needs a positive number, got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--seed")) {
            long s;
            if (vc_cli_parse_int(v, 0, 2147483647L, &s)) {
                fprintf(stderr, "vorocrust: --seed needs an integer from 0 to 2147483647, got '%s'\n",
                        v);
                return 2;
            }
            opt.seed = (uint64_t)s;
            i++;
        } else if (!strcmp(a, "--threads")) {
            long t;
            if (vc_cli_parse_int(v, 1, 4096, &t)) {
                fprintf(stderr, "vorocrust: --threads: '%s' is not a count from 1 to 4096\n", v);
                return 2;
            }
            opt.threads = (int)t;
#ifdef _OPENMP
            omp_set_num_threads((int)t);
#endif
            i++;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "vorocrust: unknown option '%s' (see 'vorocrust mesh --help')\n", a);
            return 2;
        } else if (!in_path) {
            in_path = a;
        } else {
            fprintf(stderr, "vorocrust: unexpected argument '%s'\n", a);
            return 2;
        }
    }
    if (!in_path) {
        fprintf(stderr, "vorocrust: missing the input surface (see 'vorocrust mesh --help')\n");
        return 2;
    }
    if (surface_only && !surf_path && !seeds_path && !balls_path) {
        fprintf(stderr, "vorocrust: --surface-only needs --surface, --seeds or --balls\n");
        return 2;
    }
    if (surface_only && out_path) {
        fprintf(stderr, "vorocrust: -o and --surface-only exclude each other\n");
        return 2;
    }
    if (!surface_only && !out_path) {
        fprintf(stderr, "vorocrust: missing -o OUT.vtu (or --surface-only)\n");
        return 2;
    }
    if (foam_path && surface_only) {
        fprintf(stderr, "vorocrust: --foam and --surface-only exclude each other\n");
        return 2;
    }
    if (conn_path && surface_only) {
        fprintf(stderr, "vorocrust: --connections and --surface-only exclude each other\n");
        return 2;
    }
    if (foam_path) {
        int frc = vc_cli_check_case_dir(foam_path);
        if (frc)
            return frc;
    }
    const char *outputs[6] = {out_path, surf_path, seeds_path, balls_path, conn_path, foam_path};
    for (int i = 0; i < 6; i++) {
        if (!outputs[i])
            continue;
        for (int j = 0; j < i; j++)
            if (outputs[j] && !strcmp(outputs[i], outputs[j])) {
                fprintf(stderr, "vorocrust: %s: named by two outputs\n", outputs[i]);
                return 2;
            }
        if (i < 5 && vc_cli_check_output_file(outputs[i])) /* foam_path: checked above */
            return 1;
    }
    opt.progress = !quiet;

    vc_error err = {0, ""};
    vc_surface s, smoothed;
    vc_surface_report rep;
    vc_features f;
    vc_balls balls;
    vc_seeds seeds = {0, NULL, NULL};
    vc_polysurface ps;
    vc_sampling_stats st;
    memset(&s, 0, sizeof s);
    memset(&smoothed, 0, sizeof smoothed);
    memset(&f, 0, sizeof f);
    memset(&balls, 0, sizeof balls);
    memset(&ps, 0, sizeof ps);
    int rc = 1;
    const char *written[5] = {NULL, NULL, NULL, NULL, NULL};
    int n_written = 0;

    double t0 = vc_cli_now();
    if (vc_surface_read(in_path, &s, &rep, &err)) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        return 1;
    }
    if (rep.n_boundary_edges > 0) {
        fprintf(stderr, "vorocrust: %s: the surface is open: %lld boundary edges (VoroCrust needs a "
                "closed surface)\n", in_path, (long long)rep.n_boundary_edges);
        goto out;
    }
    if (rep.n_inconsistent_edges > 0) {
        fprintf(stderr, "vorocrust: %s: %lld inconsistently oriented edges: the inside of the "
                "surface is undefined\n", in_path, (long long)rep.n_inconsistent_edges);
        goto out;
    }
    /* When sliver elimination diverges and the user chose neither
     * theta_sharp nor smoothing, sample once more. The thesis (6.2.1)
     * assumes that inside a patch every dihedral fold is small (at most
     * theta_flat, 10 to 15 degrees after its smoothing). A sharper fold of
     * flat triangles is a kink at every scale: however small the balls, the
     * ones on its two sides meet at the same angle, so shrinking the ball
     * that covers a seed (sliver elimination) opens holes whose new balls
     * make the same slivers at a smaller scale, and the half-covered pairs
     * never decay (fandisk.off, seeds 2 to 8 at 60 degrees: nearly all of
     * them within two radii of its 22-29 degree fillet folds and its
     * 20-57 degree folds; the safe mode with alpha / 2 diverges there too).
     * The remedy is decided on the input, by its folds between fold_angle
     * and theta_sharp (edges that are sharp at fold_angle, not at
     * theta_sharp):
     *  - few (under 2% of the edges): isolated kinks, such as the facets of
     *    a narrow fillet (fandisk.off: 177 edges, 0.8%, 12 more corners).
     *    They become creases: theta_sharp fold_angle, at which the patches
     *    meet the thesis' smoothness assumption and the creases are
     *    protected by edge balls;
     *  - many: the surface is not smooth at the scale of the balls, a
     *    coarse tessellation of a curved shape (fertility.off: 8.2%, and
     *    1,815 corners at 20 degrees; most edges bend by 10 to 60 degrees;
     *    its 60-degree "features" are 64 spurious corners). The thesis'
     *    remedy: Loop smoothing of the patches (6 rounds), with theta_sharp
     *    120 so that only edges folded back beyond 120 degrees stay
     *    creases. */
    const double fold_angle = 20, smooth_angle = 120;
    const double first_angle = opt.sharp_angle;
    double t_failed = 0, t1 = 0, t2 = 0;
    const double t_read = vc_cli_now() - t0; /* before any sampling attempt */
    int64_t n_input_triangles = s.n_triangles;
    const vc_surface *sampled = &s;
    for (int attempt = 0;; attempt++) {
        t1 = vc_cli_now();
        if (vc_features_detect(&s, opt.sharp_angle, &f, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
            goto out;
        }
        if (smooth_iterations > 0) {
            vc_surface_free(&smoothed);
            if (vc_surface_smooth(&s, &f, smooth_iterations, VC_SMOOTH_DEFAULT_FLAT_ANGLE, &smoothed,
                                  &err)) {
                fprintf(stderr, "vorocrust: %s: smoothing: %s\n", in_path, err.msg);
                goto out;
            }
            vc_features_free(&f);
            sampled = &smoothed;
            if (vc_features_detect(sampled, opt.sharp_angle, &f, &err)) {
                fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
                goto out;
            }
        }
        t2 = vc_cli_now();
        if (vc_sample_surface(sampled, &f, &opt, &balls, &st, &err) == 0)
            break;
        int64_t n_folds = 0, n_edges = 0;
        if (attempt == 0 && st.diverged && !sharp_angle_given && opt.sharp_angle > fold_angle) {
            /* f holds the input's features at theta_sharp unless the input
             * was smoothed first. */
            vc_features at_fold, at_sharp;
            memset(&at_fold, 0, sizeof at_fold);
            memset(&at_sharp, 0, sizeof at_sharp);
            const vc_features *sharp = sampled == &s ? &f : &at_sharp;
            if (vc_features_detect(&s, fold_angle, &at_fold, &err) ||
                (sharp == &at_sharp &&
                 vc_features_detect(&s, opt.sharp_angle, &at_sharp, &err))) {
                vc_features_free(&at_fold);
                fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
                goto out;
            }
            n_folds = at_fold.n_sharp_edges - sharp->n_sharp_edges;
            n_edges = at_fold.n_edges;
            vc_features_free(&at_fold);
            vc_features_free(&at_sharp);
        }
        int local = n_folds > 0 && 50 * n_folds <= n_edges;
        int retry = attempt == 0 && st.diverged && !sharp_angle_given &&
                    (local || !smooth_iterations_given);
        if (!retry) {
            fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
            goto out;
        }
        if (!quiet && local)
            fprintf(stderr, "mesh: %s\nmesh: sampling again with --sharp-angle %g (%lld folds of %g "
                    "to %g degrees inside the patches, %.1f%% of the edges, become creases)\n",
                    err.msg, fold_angle, (long long)n_folds, fold_angle, opt.sharp_angle,
                    100.0 * (double)n_folds / (double)n_edges);
        else if (!quiet)
            fprintf(stderr, "mesh: %s\nmesh: sampling again with --smooth-iterations %d "
                    "--sharp-angle %g (the surface bends too much everywhere: the thesis' "
                    "smoothing of the patches)\n", err.msg, VC_SMOOTH_DEFAULT_ITERATIONS,
                    smooth_angle);
        vc_features_free(&f);
        if (local) {
            opt.sharp_angle = fold_angle;
        } else {
            opt.sharp_angle = smooth_angle;
            smooth_iterations = VC_SMOOTH_DEFAULT_ITERATIONS;
        }
        t_failed = vc_cli_now() - t1;
    }
    st.t_features = t2 - t1;
    double t3 = vc_cli_now();
    int64_t n_half = 0;
    if (vc_balls_seeds(&balls, &seeds, &n_half, &err)) {
        fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
        goto out;
    }
    int64_t n_inside = 0, n_surface_seeds = seeds.n;
    for (int64_t i = 0; i < seeds.n; i++)
        n_inside += seeds.label[i] != 0;
    double t4 = vc_cli_now();
    int64_t n_repaired = 0;
    if (vc_reconstruct_surface(&seeds, opt.threads, &ps, &n_repaired, &err)) {
        fprintf(stderr, "vorocrust: %s: reconstructing the surface: %s\n", in_path, err.msg);
        goto out;
    }
    double t5 = vc_cli_now();
    vc_polysurface_topology topo;
    if (vc_polysurface_topology_compute(&ps, &topo, &err)) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        goto out;
    }
    /* said even with --quiet: the guarantee the sampling exists for */
    if (topo.n_boundary_edges || topo.n_nonmanifold_edges || topo.n_misoriented_edges ||
        topo.n_nonmanifold_vertices || topo.euler != rep.euler)
        fprintf(stderr, "vorocrust: warning: %s: the reconstructed surface is not a closed "
                "consistently oriented 2-manifold with the input's Euler characteristic (%lld "
                "boundary, %lld non-manifold and %lld misoriented edges, %lld non-manifold "
                "vertices; Euler characteristic %lld, input %lld)\n",
                in_path, (long long)topo.n_boundary_edges, (long long)topo.n_nonmanifold_edges,
                (long long)topo.n_misoriented_edges, (long long)topo.n_nonmanifold_vertices,
                (long long)topo.euler, (long long)rep.euler);
    if (surf_path) {
        if (vc_polysurface_write(&ps, surf_path, &err))
            goto write_failed;
        written[n_written++] = surf_path;
    }
    if (balls_path) {
        if (vc_balls_write_csv(&balls, balls_path, &err))
            goto write_failed;
        written[n_written++] = balls_path;
    }
    double t6 = vc_cli_now(), t7 = t6;
    int64_t n_cells = 0, n_interior = 0, n_faces = 0, n_interior_faces = 0, n_vertices = 0;
    double mesh_volume = 0;
    mesh_quality mq;
    memset(&mq, 0, sizeof mq);
    vc_seeds all = {0, NULL, NULL};
    vc_octree_stats ost;
    vc_lloyd_stats lst;
    memset(&ost, 0, sizeof ost);
    memset(&lst, 0, sizeof lst);
    if (out_path && interior == INTERIOR_OCTREE) {
        vc_octree_options oo;
        vc_octree_options_default(&oo);
        oo.lipschitz = opt.lipschitz; /* the sizing extends the balls' own grading */
        oo.max_size = opt.max_size;
        oo.threads = opt.threads;
        if (!quiet)
            fprintf(stderr, "mesh: interior octree\n");
        if (vc_interior_octree(&balls, &seeds, &oo, &all, &n_interior, &ost, NULL, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
            goto cleanup_outputs;
        }
        vc_seeds_free(&seeds);
        seeds = all;
    } else if (out_path && interior == INTERIOR_LATTICE) {
        double h = interior_spacing > 0 ? interior_spacing
                                        : vc_interior_default_spacing(&balls, opt.max_size);
        if (vc_interior_lattice(&balls, &seeds, h, &all, &n_interior, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
            goto cleanup_outputs;
        }
        vc_seeds_free(&seeds);
        seeds = all;
    }
    double t_interior = vc_cli_now() - t6;
    if (out_path && lloyd_iterations > 0 && n_interior > 0) {
        if (!quiet)
            fprintf(stderr, "mesh: Lloyd relaxation, %d iterations of %lld seeds\n",
                    lloyd_iterations, (long long)seeds.n);
        if (vc_interior_lloyd(&balls, &seeds, n_surface_seeds, lloyd_iterations, opt.threads, &lst,
                              &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
            goto cleanup_outputs;
        }
    }
    double t_lloyd = vc_cli_now() - t6 - t_interior;
    if (seeds_path) {
        if (vc_seeds_write_csv(seeds_path, &seeds, &err))
            goto write_failed;
        written[n_written++] = seeds_path;
    }
    if (out_path) {
        vc_voronoi_options vo;
        vc_voronoi_options_default(&vo);
        vo.threads = opt.threads;
        vo.progress = 0;
        vc_polymesh m;
        if (!quiet)
            fprintf(stderr, "mesh: Voronoi cells of %lld seeds\n", (long long)seeds.n);
        if (vc_voronoi_build(&seeds, &vo, &m, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", in_path, err.msg);
            goto cleanup_outputs;
        }
        n_cells = m.n_cells;
        n_faces = m.n_faces;
        n_interior_faces = m.n_interior_faces;
        n_vertices = m.n_points;
        for (int64_t c = 0; c < m.n_cells; c++)
            mesh_volume += m.cell_volume[c];
        char report[1024];
        int64_t problems = vc_polymesh_validate(&m, 0, report, sizeof report);
        if (problems)
            fprintf(stderr, "vorocrust: warning: %s: the volume mesh fails validation (%lld "
                    "problems), first: %.*s\n",
                    in_path, (long long)problems, (int)strcspn(report, "\n"), report);
        /* per-cell fatness goes into the .vtu as well */
        m.cell_fatness = malloc(sizeof(double) * (size_t)(m.n_cells ? m.n_cells : 1));
        measure_mesh(&m, &mq, m.cell_fatness);
        int wrc = vc_write_vtu(&m, out_path, VC_VTU_ZLIB, &err);
        if (!wrc)
            written[n_written++] = out_path;
        if (!wrc && conn_path) {
            wrc = vc_write_connections_csv(&m, conn_path, &err);
            if (!wrc)
                written[n_written++] = conn_path;
        }
        if (!wrc && foam_path && foam_max_skew > 0 &&
            vc_polymesh_collapse_skew_faces(&m, foam_max_skew, FOAM_COLLAPSE_ROUNDS, &foam_skew)) {
            vc_error_set(&err, VC_ENOMEM, "out of memory collapsing the skew faces");
            wrc = -1;
        }
        if (!wrc && foam_path)
            wrc = vc_write_openfoam(&m, foam_path, &err);
        vc_polymesh_free(&m);
        if (wrc)
            goto write_failed;
        t7 = vc_cli_now();
    }
    if (!quiet) {
        /* surface quality: polygons fanned from their centroid */
        double qmin = INFINITY, qsum = 0;
        int64_t ntri = 0, nang = 0, below30 = 0, above90 = 0;
        for (int64_t k = 0; k < ps.n_polys; k++) {
            int64_t a = ps.poly_offsets[k], n = ps.poly_offsets[k + 1] - a;
            double c[3] = {0, 0, 0};
            for (int64_t j = 0; j < n; j++)
                for (int d = 0; d < 3; d++)
                    c[d] += ps.points[3 * ps.poly_vertices[a + j] + d] / (double)n;
            int64_t fan = n == 3 ? 1 : n;
            for (int64_t j = 0; j < fan; j++) {
                const double *p0, *p1, *p2;
                if (n == 3) {
                    p0 = ps.points + 3 * ps.poly_vertices[a];
                    p1 = ps.points + 3 * ps.poly_vertices[a + 1];
                    p2 = ps.points + 3 * ps.poly_vertices[a + 2];
                } else {
                    p0 = c;
                    p1 = ps.points + 3 * ps.poly_vertices[a + j];
                    p2 = ps.points + 3 * ps.poly_vertices[a + (j + 1) % n];
                }
                double ang[3];
                double q = vc_triangle_quality(p0, p1, p2);
                vc_triangle_angles(p0, p1, p2, ang);
                qmin = fmin(qmin, q);
                qsum += q;
                ntri++;
                for (int m = 0; m < 3; m++) {
                    nang++;
                    below30 += ang[m] < 30;
                    above90 += ang[m] > 90;
                }
            }
        }
        char retry_note[64] = "", failed_time[64] = "";
        if (opt.sharp_angle != first_angle) {
            snprintf(retry_note, sizeof retry_note, ", after sampling at %g diverged", first_angle);
            snprintf(failed_time, sizeof failed_time, ", failed sampling at %g %.3f", first_angle,
                     t_failed);
        }
        fprintf(stderr,
                "vorocrust mesh: %s (%lld triangles, %lld after %d smoothing rounds; sharp angle %g%s)\n"
                "  balls: %lld (corner %lld, edge %lld, surface %lld); shrunk for Lipschitz %lld, "
                "for slivers %lld in %d iterations%s, for flat facets %lld; half-covered seed pairs %lld\n"
                "  surface seeds: %lld (%lld inside, %lld outside)\n"
                "  surface: %lld vertices, %lld polygons, %lld edges, euler %lld (input %lld), "
                "%s, %lld components, %lld T-junction vertices repaired\n"
                "  surface quality: Q min %.3f mean %.3f; angles < 30 deg %.1f%%, > 90 deg %.1f%% "
                "(%lld triangles, polygons fanned from their centroid)\n"
                "  time (s): read %.3f, features and smoothing %.3f, sizing %.3f, corner protection %.3f, edge "
                "protection %.3f, surface coverage %.3f, Lipschitz fixes %.3f, sliver elimination "
                "%.3f, seeds %.3f, surface %.3f, write %.3f%s\n",
                in_path, (long long)n_input_triangles, (long long)sampled->n_triangles, smooth_iterations,
                opt.sharp_angle, retry_note,
                (long long)balls.n, (long long)st.n_corner, (long long)st.n_edge,
                (long long)st.n_surface, (long long)st.n_shrunk_lipschitz,
                (long long)st.n_shrunk_sliver, st.sliver_iterations,
                st.safe_mode ? " (safe mode)" : "", (long long)st.n_shrunk_flat, (long long)n_half, (long long)n_surface_seeds,
                (long long)n_inside, (long long)(n_surface_seeds - n_inside), (long long)topo.n_vertices,
                (long long)topo.n_faces, (long long)topo.n_edges, (long long)topo.euler,
                (long long)rep.euler,
                topo.n_boundary_edges == 0 && topo.n_nonmanifold_edges == 0 &&
                        topo.n_misoriented_edges == 0 && topo.n_nonmanifold_vertices == 0
                    ? "closed 2-manifold, consistently oriented"
                    : "NOT a closed consistently oriented 2-manifold",
                (long long)topo.n_components, (long long)n_repaired, qmin, ntri ? qsum / (double)ntri : 0,
                nang ? 100.0 * (double)below30 / (double)nang : 0,
                nang ? 100.0 * (double)above90 / (double)nang : 0, (long long)ntri, t_read,
                st.t_features, st.t_sizing, st.t_corners, st.t_edges, st.t_surface,
                st.t_lipschitz, st.t_slivers, t4 - t3, t5 - t4, t6 - t5, failed_time);
        if (out_path) {
            /* volume enclosed by the reconstructed surface, polygons fanned */
            double sv = 0;
            for (int64_t k = 0; k < ps.n_polys; k++) {
                int64_t a = ps.poly_offsets[k], n = ps.poly_offsets[k + 1] - a;
                const double *p0 = ps.points + 3 * ps.poly_vertices[a];
                for (int64_t j = 1; j + 1 < n; j++) {
                    const double *p1 = ps.points + 3 * ps.poly_vertices[a + j];
                    const double *p2 = ps.points + 3 * ps.poly_vertices[a + j + 1];
                    sv += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) -
                           p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
                           p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) / 6;
                }
            }
            if (interior == INTERIOR_OCTREE)
                fprintf(stderr,
                        "  interior: octree of %lld leaves (%lld before the 2:1 balance; %lld "
                        "trees, levels %d to %d), %lld interior seeds (leaves left out: %lld in a "
                        "ball, %lld outside, %lld next to a surface seed), %.3f s\n",
                        (long long)ost.n_leaves, (long long)ost.n_refined_leaves,
                        (long long)ost.n_trees, ost.min_level, ost.max_level,
                        (long long)ost.n_seeds, (long long)ost.n_covered,
                        (long long)ost.n_outside, (long long)ost.n_near_seed, t_interior);
            else
                fprintf(stderr, "  interior: %s, %lld interior seeds, %.3f s\n",
                        interior == INTERIOR_LATTICE ? "lattice" : "none", (long long)n_interior,
                        t_interior);
            if (lloyd_iterations > 0)
                fprintf(stderr,
                        "  Lloyd: %d iterations%s, last one moved %lld seeds (%lld stayed: "
                        "next to the surface, or centroid in a ball or outside), shift / cell "
                        "size mean %.3g max %.3g, %.3f s\n",
                        lst.iterations,
                        lst.reverted ? " (the next one was undone: its mesh failed the validator)"
                                     : "",
                        (long long)lst.n_moved, (long long)lst.n_refused, lst.mean_shift,
                        lst.max_shift, t_lloyd);
            fprintf(stderr,
                    "  volume mesh: %lld cells (%lld interior seeds), volume %.12g (reconstructed "
                    "surface %.12g, input %.12g), %.3f s; %lld faces (%lld interior, %lld "
                    "boundary), %lld vertices\n",
                    (long long)n_cells, (long long)n_interior, mesh_volume, sv, rep.volume,
                    t7 - t6 - t_interior - t_lloyd, (long long)n_faces,
                    (long long)n_interior_faces, (long long)(n_faces - n_interior_faces),
                    (long long)n_vertices);
            fprintf(stderr,
                    "  cell quality: volume min %.6g max %.6g; fatness max %.3f mean %.3f "
                    "(interior cells: max %.3f mean %.3f); shortest edge / enclosing radius "
                    "min %.3g%s\n",
                    mq.vol_min, mq.vol_max, mq.fat_max, mq.n ? mq.fat_sum / (double)mq.n : 0,
                    mq.fat_int_max, mq.n_int ? mq.fat_int_sum / (double)mq.n_int : 0,
                    mq.edge_rel_min, mq.n_unmeasured ? " (some cells could not be measured)" : "");
            if (foam_path && foam_max_skew > 0)
                fprintf(stderr,
                        "  OpenFOAM case: %lld faces collapsed in %d rounds (skewness above %g, "
                        "%lld of them to make room), largest point move %.3g; max skewness "
                        "%.3f before, %.3f after (%lld faces above %g left)\n",
                        (long long)foam_skew.n_collapsed, foam_skew.n_rounds, foam_max_skew,
                        (long long)foam_skew.n_made_room, foam_skew.max_move,
                        foam_skew.max_skew_before, foam_skew.max_skew_after,
                        (long long)foam_skew.n_skew_left, foam_max_skew);
            struct rusage ru;
            getrusage(RUSAGE_SELF, &ru);
            fprintf(stderr, "  total: %.3f s, peak memory %.1f MiB\n", vc_cli_now() - t0,
                    (double)ru.ru_maxrss / 1024.0);
        }
    }
    rc = 0;
    goto out;
write_failed:
    fprintf(stderr, "vorocrust: %s\n", err.msg);
cleanup_outputs:
    for (int i = 0; i < n_written; i++)
        remove(written[i]); /* all outputs or none */
out:
    vc_polysurface_free(&ps);
    vc_seeds_free(&seeds);
    vc_balls_free(&balls);
    vc_features_free(&f);
    vc_surface_free(&smoothed);
    vc_surface_free(&s);
    return rc;
}
