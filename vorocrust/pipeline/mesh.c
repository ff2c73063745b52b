/* vc_mesh: the VoroCrust pipeline, from a closed surface to the volume
 * mesh (see vorocrust/vorocrust.h). Each stage is a public function of its
 * own header; this file decides their order, the resampling policy and
 * the figures of the result. */
#include "vorocrust/vorocrust.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "boundary_surface.h"
#include "mesh_measures.h"
#include "interior/octree_runtime.h"
#include "util/progress.h"
#include "vorocrust/features.h"
#include "vorocrust/regions.h"
#include "boundary_groups.h"
#include "denoise_choice.h"
#include "predict_balls.h"
#include "seed_spheres.h"
#include "materials.h"
#include "vorocrust/features.h"
#include "vorocrust/smoothing.h"
#include "vorocrust/voronoi.h"

/* The resampling policy (see resample_plan). */
#define FOLD_ANGLE 20.0   /* folds sharper than this inside a patch are kinks */
#define SMOOTH_ANGLE 120.0/* theta_sharp after Loop smoothing: only edges folded
                             back beyond 120 degrees stay creases */

/* Meshes from this many cells get a progress line for each step after
 * the cells (ordering, checks, measures: about a second per 200,000). */
#define PROGRESS_CELLS 50000

/* The model sizes vc_mesh accepts (see vc_voronoi_build's seed extent). */
#define VC_MESH_MIN_SIZE 1e-60
#define VC_MESH_MAX_SIZE 1e60

const char *vc_version(void) { return VC_VERSION_STRING; }

int vc_version_number(void) { return VC_VERSION_NUMBER; }

static double now(void)
{
#ifdef _OPENMP
    return omp_get_wtime();
#else
    return 0;
#endif
}

/* The input checks of a large surface take seconds (1M triangles: 2.3 s
 * here, 5 s on a slower machine) before the first sampling line: one line
 * names each step that starts half a second or more after the last line
 * (every step takes under a second here). */
static void check_progress(const vc_mesh_options *opt, double *t_last, const char *name, const char *step)
{
    const double t = now();
    if (t - *t_last < 0.5)
        return;
    *t_last = t;
    vc_log(opt->log, VC_LOG_INFO, "mesh: %s: %s", name, step);
}

int64_t vc_mesh_default_max_balls(void)
{
    /* measured: 10 KiB per ball for the whole run (torus, bracket:
     * 62 to 66 MiB peak for 6,400 to 6,600 balls) */
    const double bytes_per_ball = 16384;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0)
        return (int64_t)1 << 26;
    return (int64_t)((double)pages * (double)page / bytes_per_ball);
}

void vc_mesh_options_default(vc_mesh_options *opt)
{
    memset(opt, 0, sizeof *opt);
    vc_sampling_options so;
    vc_sampling_options_default(&so);
    opt->sharp_angle = so.sharp_angle;
    opt->max_error = so.max_error;
    opt->self_union = 1;
    opt->smooth_width = so.smooth_width;
    opt->curvature_factor = so.curvature_factor;
    opt->lipschitz = so.lipschitz;
    opt->max_size = so.max_size;
    opt->seed = so.seed;
    /* 0, not the thesis' 6: Loop subdivision approximates, it pulls the
     * surface off the input (sphere.obj: 0.78% of the diagonal, 3.3% of the
     * volume after 6 rounds), beyond the 0.5% error budget. */
    opt->smooth_iterations = 0;
    /* folds that defeat sliver elimination become creases where it is
     * stuck (the surface is not moved; session 31: marching cubes of a
     * union of shapes, whose junction creases are staircases of folds
     * partly below theta_sharp, diverged) */
    opt->resample = VC_RESAMPLE_FOLDS;
    opt->interior = VC_INTERIOR_OCTREE;
}

void vc_mesh_result_free(vc_mesh_result *r)
{
    if (!r)
        return;
    vc_balls_free(&r->balls);
    vc_seeds_free(&r->seeds);
    vc_polysurface_free(&r->surface);
    vc_polymesh_free(&r->mesh);
    free(r->region_mesh);
    free(r->sphere_ball);
    memset(r, 0, sizeof *r);
}

static int check_options(const vc_mesh_options *o, vc_error *err)
{
    if (o->patches < VC_PATCHES_GROUPS || o->patches > VC_PATCHES_NONE)
        return vc_error_set(err, VC_EPARAM, "patches: %d is not a vc_patch_source", (int)o->patches);
    if (!(o->sharp_angle > 0 && o->sharp_angle < 180))
        return vc_error_set(err, VC_EPARAM, "sharp angle %g: needs degrees in (0, 180)",
                            o->sharp_angle);
    if (!(o->smooth_width >= 0 && o->smooth_width <= 100))
        return vc_error_set(err, VC_EPARAM, "smooth width %g: needs a number in [0, 100]",
                            o->smooth_width);
    if (!(o->curvature_factor > 0 && o->curvature_factor <= 10))
        return vc_error_set(err, VC_EPARAM, "curvature factor %g: needs a number in (0, 10]",
                            o->curvature_factor);
    if (!(o->max_error >= 0 && o->max_error < 1))
        return vc_error_set(err, VC_EPARAM, "max error %g: needs a number in [0, 1)", o->max_error);
    if (!(o->lipschitz > 0 && o->lipschitz < 1))
        return vc_error_set(err, VC_EPARAM, "Lipschitz constant %g: needs a number in (0, 1)",
                            o->lipschitz);
    if (!(o->max_size >= 0) || !isfinite(o->max_size))
        return vc_error_set(err, VC_EPARAM, "max size %g: needs a positive number (0: none)",
                            o->max_size);
    if (o->smooth_iterations < 0 || o->smooth_iterations > VC_SMOOTH_MAX_ITERATIONS)
        return vc_error_set(err, VC_EPARAM, "%d smoothing rounds: 0 to %d are allowed",
                            o->smooth_iterations, VC_SMOOTH_MAX_ITERATIONS);
    if (o->denoise < -1 || o->denoise > 1)
        return vc_error_set(err, VC_EPARAM, "denoise %d: needs -1 (off), 0 (auto) or 1 (on)",
                            o->denoise);
    /* a copy asked for that cannot be made is an error, not ignored */
    if (o->denoise > 0 && (o->smooth_iterations > 0 || o->smooth_width > 0 || !(o->max_error > 0)))
        return vc_error_set(err, VC_EPARAM, "denoise on: not with %s (the copy is smoothed within "
                            "half the error bound)",
                            o->smooth_iterations > 0 ? "smoothing rounds"
                            : o->smooth_width > 0    ? "a smooth width"
                                                     : "max error 0");
    if (o->max_sliver_iterations < 0 || o->max_sliver_iterations > 100000)
        return vc_error_set(err, VC_EPARAM, "%d sliver passes: 0 (the default) to 100000 are "
                            "allowed", o->max_sliver_iterations);
    if (!(o->unskew == 0 || (o->unskew >= 1 && o->unskew <= 1000)))
        return vc_error_set(err, VC_EPARAM, "the skewness to mend down to must be 0 (off) or in "
                            "[1, 1000], got %g", o->unskew);
    if (!(o->protect_edge >= 0 && o->protect_edge < 0.25))
        return vc_error_set(err, VC_EPARAM, "protect edge %g: needs a number in [0, 0.25)",
                            o->protect_edge);
    if (o->lloyd_iterations < 0 || o->lloyd_iterations > 1000)
        return vc_error_set(err, VC_EPARAM, "%d Lloyd iterations: 0 to 1000 are allowed",
                            o->lloyd_iterations);
    if (o->interior != VC_INTERIOR_OCTREE && o->interior != VC_INTERIOR_LATTICE &&
        o->interior != VC_INTERIOR_NONE)
        return vc_error_set(err, VC_EPARAM, "unknown interior kind %d", (int)o->interior);
    if (!(o->interior_spacing >= 0) || !isfinite(o->interior_spacing))
        return vc_error_set(err, VC_EPARAM, "interior spacing %g: needs a positive number",
                            o->interior_spacing);
    return 0;
}

/* Prefixes err's message with the input's name (and what was being done). */
static int named(vc_error *err, const char *name, const char *doing)
{
    if (!err)
        return VC_EINTERNAL;
    char full[2 * VC_ERROR_LEN + 64];
    snprintf(full, sizeof full, "%s: %s%s%s", name, doing ? doing : "", doing ? ": " : "",
             err->msg);
    size_t n = strlen(full);
    if (n >= sizeof err->msg)
        n = sizeof err->msg - 1; /* cut, as any message */
    memcpy(err->msg, full, n);
    err->msg[n] = 0;
    return err->code ? err->code : VC_EINTERNAL;
}

/* When sliver elimination diverges on the first attempt, how to sample
 * once more: returns 1 with the new sharp angle and smoothing rounds, or 0.
 *
 * The thesis (6.2.1) assumes that inside a patch every dihedral fold is
 * small (at most theta_flat, 10 to 15 degrees after its smoothing). A
 * sharper fold of flat triangles is a kink at every scale: however small
 * the balls, the ones on its two sides meet at the same angle, so
 * shrinking the ball that covers a seed (sliver elimination) opens holes
 * whose new balls make the same slivers at a smaller scale, and the
 * half-covered pairs never decay (fandisk.off, seeds 2 to 8 at 60 degrees:
 * nearly all of them within two radii of its 22-29 degree fillet folds and
 * its 20-57 degree folds; the safe mode with alpha / 2 diverges there too).
 * The remedies, in order, after a divergence at theta_sharp:
 *  1. the folds between FOLD_ANGLE and theta_sharp inside the patches
 *     (edges that are sharp at FOLD_ANGLE, not at theta_sharp) become
 *     creases: theta_sharp FOLD_ANGLE, at which the patches nearly meet
 *     the thesis' smoothness assumption and the creases are protected by
 *     edge balls. The surface is not moved. Isolated kinks (fandisk.off:
 *     177 edges, 0.8%) cost little; a scan whose edges fold everywhere
 *     (bunny.off: 18% of them) costs many small balls (118k), but meshes
 *     on its own surface;
 *  2. when that diverges too (folds below FOLD_ANGLE that still defeat
 *     sliver elimination), the thesis' remedy: Loop smoothing of the
 *     patches (VC_SMOOTH_DEFAULT_ITERATIONS rounds) at theta_sharp
 *     SMOOTH_ANGLE, which moves the surface.
 * `attempt` is the number of samplings that diverged so far. */
static int resample_plan(const vc_surface *s, const vc_features *f_input, double sharp_angle,
                         int allowed, int attempt, double *new_angle, int *new_smooth,
                         int64_t *n_folds, int64_t *n_edges, vc_error *err)
{
    *n_folds = *n_edges = 0;
    if (attempt == 1 && (allowed & VC_RESAMPLE_CREASES) && sharp_angle > FOLD_ANGLE) {
        vc_features at_fold, at_sharp;
        memset(&at_fold, 0, sizeof at_fold);
        memset(&at_sharp, 0, sizeof at_sharp);
        const vc_features *sharp = f_input ? f_input : &at_sharp;
        if (vc_features_detect(s, FOLD_ANGLE, &at_fold, err) ||
            (!f_input && vc_features_detect(s, sharp_angle, &at_sharp, err))) {
            vc_features_free(&at_fold);
            return -1;
        }
        *n_folds = at_fold.n_sharp_edges - sharp->n_sharp_edges;
        *n_edges = at_fold.n_edges;
        vc_features_free(&at_fold);
        vc_features_free(&at_sharp);
        if (*n_folds > 0) {
            *new_angle = FOLD_ANGLE;
            return 1;
        }
    }
    if (attempt <= 2 && (allowed & VC_RESAMPLE_SMOOTH) && *new_smooth == 0) {
        *new_angle = SMOOTH_ANGLE;
        *new_smooth = VC_SMOOTH_DEFAULT_ITERATIONS;
        return 2;
    }
    return 0;
}

/* Folds that defeat sliver elimination become creases (VC_RESAMPLE_FOLDS):
 * after a divergence, every edge of a triangle where it is stuck whose
 * fold exceeds FOLD_FLAT joins the creases (extra[e] = 1); after
 * FOLD_LOCAL_ROUNDS such rounds, every fold above FOLD_FLAT of the whole
 * surface. Returns the number of edges added. The surface is not moved:
 * the patches keep their triangles, only cut along more creases, and the
 * folds left inside them are at most FOLD_FLAT, the smoothness the
 * thesis' sampling assumes (6.2.1: theta_flat, 10 to 15 degrees). */
#define FOLD_FLAT 10.0
#define FOLD_LOCAL_ROUNDS 4
static int64_t promote_folds(const vc_features *f, const unsigned char *stuck_tri,
                             int everywhere, unsigned char *extra)
{
    const double cos_flat = cos(FOLD_FLAT * 3.14159265358979323846 / 180.0);
    int64_t added = 0;
    for (int64_t e = 0; e < f->n_edges; e++) {
        if (extra[e] || !(vc_features_fold_cos(f, e) < cos_flat))
            continue;
        const int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
        if (everywhere || stuck_tri[t1] || stuck_tri[t2]) {
            extra[e] = 1;
            added++;
        }
    }
    return added;
}

/* The balls' spheres the surface and sphere seeds of seeds lie on (the
 * engine makes each ball's centre one vertex from them). Returns 0, or
 * VC_ENOMEM with err set. */
static int find_seed_spheres(const vc_mesh_options *opt, const vc_mesh_result *out,
                             const vc_seeds *seeds, vc_seed_spheres_owned *on, vc_error *err)
{
    const double t = now();
    if (vc_seed_spheres_find(&out->balls, seeds, out->n_surface_seeds + out->n_sphere_seeds,
                             opt->threads, on))
        return vc_error_set(err, VC_ENOMEM, "out of memory for the seeds' spheres");
    vc_log(opt->log, VC_LOG_DEBUG, "  mesh: the spheres of %lld seeds, %.3f s",
           (long long)seeds->n, now() - t);
    return 0;
}

static int volume_mesh(const vc_mesh_options *opt, const char *name, const vc_materials *mm,
                       vc_mesh_result *out, vc_error *err);
static int surface_only(const vc_mesh_options *opt, const char *name, vc_mesh_result *out,
                        vc_error *err);

/* The regions of a multi-material mesh against the input's: each region's
 * cells bounded by a closed oriented 2-manifold of the input region's
 * Euler characteristic (else VC_EINPUT with *unresolved set, as for one
 * solid), and of the input region's volume within REGION_VOLUME_TOL. */
#define REGION_VOLUME_TOL 0.01
static int check_regions(const vc_mesh_options *opt, const char *name, const vc_materials *mm,
                         vc_mesh_result *out, int *unresolved, double t, vc_error *err)
{
    free(out->region_mesh);
    out->region_mesh = calloc((size_t)mm->n_regions + 1, sizeof(vc_region_mesh));
    if (!out->region_mesh)
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    int rc = vc_materials_measure(mm, &out->mesh, out->region_mesh, &out->surface, err);
    if (rc)
        return named(err, name, NULL);
    if ((rc = vc_polysurface_topology_compute(&out->surface, &out->surface_topology, err)) != 0)
        return rc;
    out->time.reconstruct = now() - t;
    out->surface_closed = 1;
    for (int64_t k = 0; k < mm->n_regions; k++) {
        const vc_region_mesh *r = &out->region_mesh[k];
        if (r->label == 0 || r->closed)
            continue;
        out->surface_closed = 0;
        *unresolved = 1;
        const vc_polysurface_topology *tp = &r->topology;
        return vc_error_set(err, VC_EINPUT,
                            "the cells of region %lld are not bounded by a closed consistently "
                            "oriented 2-manifold with the input region's Euler characteristic "
                            "(%lld boundary, %lld non-manifold and %lld misoriented edges, %lld "
                            "non-manifold vertices; Euler characteristic %lld, input %lld): the "
                            "sampling did not resolve the surface; try another --seed or a "
                            "smaller --max-error",
                            (long long)k + 1, (long long)tp->n_boundary_edges,
                            (long long)tp->n_nonmanifold_edges, (long long)tp->n_misoriented_edges,
                            (long long)tp->n_nonmanifold_vertices, (long long)tp->euler,
                            (long long)r->euler_input);
    }
    for (int64_t k = 0; k < mm->n_regions; k++) {
        const vc_region_mesh *r = &out->region_mesh[k];
        if (r->label == 0)
            continue;
        const double rel = (r->mesh_volume - r->input_volume) / r->input_volume;
        if (!(fabs(rel) <= REGION_VOLUME_TOL))
            return vc_error_set(err, VC_EINPUT,
                                "%s: the cells of region %lld hold %g, the input region %g "
                                "(%+.2f%%, more than %g%% off): the mesh is wrong there",
                                name, (long long)k + 1, r->mesh_volume, r->input_volume,
                                100 * rel, 100 * REGION_VOLUME_TOL);
    }
    if (opt->surface_only) {
        vc_polymesh_free(&out->mesh);
        out->has_mesh = 0;
    }
    return 0;
}

/* The surface seeds of the balls, the volume mesh unless opt->surface_only,
 * and the reconstructed surface: the volume mesh's boundary, or with
 * surface_only the Voronoi facets between inside and outside surface
 * seeds. VC_EINPUT (with *unresolved set) when that surface is not a
 * closed, consistently oriented 2-manifold with the input's Euler
 * characteristic. */
static int count_nonmanifold_vertices(const vc_surface *s, int64_t *n, vc_error *err);

static int reconstruct(const vc_surface *s, const vc_mesh_options *opt, const char *name,
                       const vc_materials *mm, vc_mesh_result *out, int *unresolved, vc_error *err)
{
    *unresolved = 0;
    vc_seeds_free(&out->seeds);
    vc_polysurface_free(&out->surface);
    vc_polymesh_free(&out->mesh);
    out->has_mesh = 0;
    out->n_inside_seeds = 0;
    double t = now();
    if (out->balls.n >= PROGRESS_CELLS / 2)
        vc_log(opt->log, VC_LOG_INFO, "mesh: seeds of %lld balls", (long long)out->balls.n);
    if (vc_balls_seeds(&out->balls, opt->threads, &out->seeds, &out->n_half_covered, err) != 0)
        return named(err, name, NULL);
    out->n_surface_seeds = out->seeds.n;
    if (mm) {
        /* every seed takes the label of the region it lies in: across an
         * interface both seeds of a pair are kept, in their own regions;
         * at a non-manifold edge each seed falls in one wedge */
        const int64_t lost = vc_materials_label_seeds(mm, &out->seeds, out->seeds.n, opt->threads);
        if (lost > 0)
            vc_log(opt->log, VC_LOG_WARNING,
                   "%s: %lld surface seeds lie on the input surface: no region, not kept", name,
                   (long long)lost);
    }
    for (int64_t i = 0; i < out->seeds.n; i++)
        out->n_inside_seeds += out->seeds.label[i] != 0;
    out->time.seeds = now() - t;

    int rc;
    if (mm) {
        /* the regions are read off the volume mesh's cells (surface_only
         * too, of the surface seeds alone: the facets between regions
         * are not those of one inside and one outside seed) */
        vc_mesh_options vo = *opt;
        if (opt->surface_only)
            vo.interior = VC_INTERIOR_NONE;
        if ((rc = volume_mesh(&vo, name, mm, out, err)) != 0)
            return rc;
        t = now();
        return check_regions(opt, name, mm, out, unresolved, t, err);
    }
    if (opt->surface_only) {
        t = now();
        if ((rc = surface_only(opt, name, out, err)) != 0)
            return rc;
    } else {
        /* The volume mesh holds the surface as its boundary faces: one
         * Voronoi computation instead of two, and the surface checked is
         * the one the cells bound (interior seeds included). */
        if ((rc = volume_mesh(opt, name, NULL, out, err)) != 0)
            return rc;
        t = now();
        if (vc_polymesh_boundary_surface(&out->mesh, &out->surface))
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    rc = vc_polysurface_topology_compute(&out->surface, &out->surface_topology, err);
    if (rc)
        return rc;
    out->time.reconstruct = now() - t;
    const vc_polysurface_topology *topo = &out->surface_topology;
    /* Where the input's parts touch along an edge (four triangles at it),
     * the reconstruction touches there too: non-manifold edges are then
     * right, provided each is walked as often each way (closed parts). */
    const int touching = out->input.n_nonmanifold_edges > 0 &&
                         topo->n_balanced_nonmanifold_edges == topo->n_nonmanifold_edges;
    /* Where parts of the input s touch at a vertex only (a pinch it keeps:
     * two cubes sharing a corner), the reconstruction may too; counted only
     * when the reconstruction has such vertices. */
    int64_t input_nonmanifold = 0;
    if (topo->n_nonmanifold_vertices > 0 &&
        (rc = count_nonmanifold_vertices(s, &input_nonmanifold, err)) != 0)
        return rc;
    const int pinched = input_nonmanifold > 0;
    out->surface_closed = !topo->n_boundary_edges && !topo->n_misoriented_edges &&
                          (touching || (!topo->n_nonmanifold_edges &&
                                        (pinched || !topo->n_nonmanifold_vertices))) &&
                          topo->euler == out->input.euler;
    /* a surface known to be wrong is an error, not a mesh with a warning */
    if (!out->surface_closed) {
        *unresolved = 1;
        return vc_error_set(err, VC_EINPUT,
                            "the reconstructed surface is not a closed consistently oriented "
                            "2-manifold with the input's Euler characteristic (%lld boundary, %lld "
                            "non-manifold and %lld misoriented edges, %lld non-manifold vertices; "
                            "Euler characteristic %lld, input %lld): the sampling did not resolve "
                            "the surface; try another --seed or a smaller --max-error",
                            (long long)topo->n_boundary_edges,
                            (long long)topo->n_nonmanifold_edges,
                            (long long)topo->n_misoriented_edges,
                            (long long)topo->n_nonmanifold_vertices, (long long)topo->euler,
                            (long long)out->input.euler);
    }
    return 0;
}

/* The absolute error bound of the sampling: max_error times the
 * bounding-box diagonal of s (0 when max_error is 0). The sharp features
 * are judged at it (vc_features_detect_scaled). */
static double error_bound_of(const vc_surface *s, double max_error)
{
    return max_error > 0 ? max_error * vc_surface_diagonal(s) : 0;
}

/* The sampling, with more attempts when it diverges (resample_plan,
 * promote_folds). Fills out's sampling fields and balls. */
/* *extra (allocated, per edge of vc_features_detect's numbering, which is
 * the surface's own): 1 for an edge between triangles of two groups. */
static int group_borders(const vc_surface *s, double sharp_angle, unsigned char **extra,
                         vc_error *err)
{
    vc_features f;
    memset(&f, 0, sizeof f);
    int rc = vc_features_detect(s, sharp_angle, &f, err);
    if (rc)
        return rc;
    *extra = calloc((size_t)f.n_edges + 1, 1);
    if (!*extra) {
        vc_features_free(&f);
        return vc_error_set(err, VC_ENOMEM, "out of memory");
    }
    for (int64_t e = 0; e < f.n_edges; e++)
        for (int64_t k = f.edge_tri_start[e] + 1; k < f.edge_tri_start[e + 1]; k++)
            if (s->tri_group[f.edge_tri[k]] != s->tri_group[f.edge_tri[f.edge_tri_start[e]]])
                (*extra)[e] = 1;
    vc_features_free(&f);
    return 0;
}

/* Group borders as creases cost what the sizing says: along a border that
 * is a clean line next to nothing, an edge's balls; along one that zigzags
 * over the facets of a smooth patch (a file split into solids by
 * triangle order, or along an axis), a crease that turns at every vertex,
 * next to itself: a 404-triangle STL in two solids was predicted 5.6e5
 * balls and ran past 150 s, 2,239 balls without the borders. When the
 * borders multiply the predicted balls by more than GROUP_BORDER_GAIN,
 * they are not made creases (*extra freed); the boundary facets still take
 * the group of the input triangle they lie on, so the patches' border
 * follows the facets near the input's. */
#define GROUP_BORDER_GAIN 2.0
static int weigh_group_borders(const vc_surface *s, const vc_mesh_options *opt, const char *name,
                               unsigned char **extra, vc_error *err)
{
    const double bound = error_bound_of(s, opt->max_error);
    double with = 0, without = 0;
    vc_features f;
    int rc = vc_predict_balls(s, opt->sharp_angle, *extra, bound, opt->max_size, opt->threads,
                              &with, &f, err);
    if (rc)
        return named(err, name, NULL);
    vc_features_free(&f);
    if ((rc = vc_predict_balls(s, opt->sharp_angle, NULL, bound, opt->max_size, opt->threads,
                               &without, &f, err)) != 0)
        return named(err, name, NULL);
    vc_features_free(&f);
    if (with > GROUP_BORDER_GAIN * without) {
        vc_log(opt->log, VC_LOG_INFO,
               "mesh: the borders between the input's %d groups as creases would take about %.3g "
               "balls, %.3g without: not creases (their facets zigzag); the patches follow the "
               "input's triangles",
               (int)s->n_groups, with, without);
        free(*extra);
        *extra = NULL;
    }
    return 0;
}

static int sample(const vc_surface *s, const vc_mesh_options *opt, const char *name,
                  const vc_materials *mm, vc_mesh_result *out, vc_error *err)
{
    vc_sampling_options so;
    vc_sampling_options_default(&so);
    so.sharp_angle = opt->sharp_angle;
    so.max_error = opt->max_error;
    so.smooth_width = opt->smooth_width;
    so.curvature_factor = opt->curvature_factor;
    so.lift_centres = !opt->no_lift;
    so.quartet_gap = opt->quartet_gap;
    if (opt->max_sliver_iterations > 0)
        so.max_sliver_iterations = opt->max_sliver_iterations;
    so.lipschitz = opt->lipschitz;
    so.max_size = opt->max_size;
    so.seed = opt->seed;
    so.threads = opt->threads;
    so.log = opt->log;
    so.max_balls = opt->max_balls == 0 ? vc_mesh_default_max_balls() : opt->max_balls;
    int smooth = opt->smooth_iterations;
    vc_features f;
    vc_surface smoothed;
    memset(&f, 0, sizeof f);
    memset(&smoothed, 0, sizeof smoothed);
    int rc = 0;
    out->first_sharp_angle = so.sharp_angle;
    const int folds = (opt->resample & VC_RESAMPLE_FOLDS) && smooth == 0;
    unsigned char *stuck = NULL, *extra = NULL;
    /* the borders between the input's groups are creases: the patches'
     * edges are then sampled, and every boundary facet lies on one side */
    if (opt->patches == VC_PATCHES_GROUPS && s->tri_group && s->n_groups > 1 &&
        (rc = group_borders(s, opt->sharp_angle, &extra, err)) != 0)
        return named(err, name, NULL);
    if (extra && (rc = weigh_group_borders(s, opt, name, &extra, err)) != 0) {
        free(extra);
        return rc;
    }
    /* noise at the error bound: sample a copy smoothed within half of it
     * when the sizing says the noise costs (denoise_choice.c); not with
     * the smoothing options, which have their own surface, nor on several
     * regions (the seeds are located in the input's regions: a copy would
     * move the interfaces off them) */
    vc_surface denoised;
    memset(&denoised, 0, sizeof denoised);
    vc_denoise_choice *dc = &out->denoise;
    memset(dc, 0, sizeof *dc);
    if (opt->denoise > 0 && mm) {
        free(extra);
        return vc_error_set(err, VC_EPARAM,
                            "%s: --denoise on: the input bounds %lld regions, whose seeds are "
                            "located in the input's own; a denoised copy would move their "
                            "interfaces", name, (long long)mm->n_regions);
    }
    /* the features of the first attempt, when the choice made them */
    vc_features f_first;
    memset(&f_first, 0, sizeof f_first);
    const int copy_allowed =
        smooth == 0 && !(opt->smooth_width > 0) && opt->denoise >= 0 && opt->max_error > 0 && !mm;
    if (copy_allowed) {
        const double t_choice = now();
        if ((rc = vc_choose_denoised(s, so.sharp_angle, extra, error_bound_of(s, opt->max_error),
                                     opt->max_size, opt->denoise, opt->threads, &denoised, dc,
                                     &f_first, opt->log, name, err)) != 0) {
            free(extra);
            return named(err, name, NULL);
        }
        out->time.denoise = now() - t_choice;
        vc_log(opt->log, VC_LOG_DEBUG,
               "  mesh: balls predicted for the input %.4g, for a copy smoothed within %.4g "
               "(mean move %.3g, volume %+.3f%%) %.4g; %.3f s", dc->n_input, dc->moved.max_move,
               dc->moved.mean_move, 100 * dc->volume_change, dc->n_denoised, out->time.denoise);
        if (!dc->used && dc->self_intersections > 0 &&
            (opt->denoise > 0 || dc->n_input >= VC_DENOISE_GAIN * dc->n_denoised))
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: a copy smoothed within half the error bound would intersect itself (%lld "
                   "pairs of triangles: a part thinner than the smoothing's reach): sampling the "
                   "input", (long long)dc->self_intersections);
        else if (!dc->used && dc->n_input >= VC_DENOISE_GAIN * dc->n_denoised && dc->n_denoised > 0)
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: a copy smoothed within half the error bound would take about %.3g balls "
                   "(the input %.3g) but change the volume by %+.2f%%: sampling the input",
                   dc->n_denoised, dc->n_input, 100 * dc->volume_change);
        if (dc->used) {
            so.max_error = dc->bound / vc_surface_diagonal(&denoised);
            if (opt->denoise > 0)
                vc_log(opt->log, VC_LOG_INFO,
                       "mesh: sampling a copy smoothed within %.3g (--denoise on: %.2f of the "
                       "error bound, vertices moved %.3g on average)",
                       dc->moved.max_move, dc->moved.max_move / error_bound_of(s, opt->max_error),
                       dc->moved.mean_move);
            else
                vc_log(opt->log, VC_LOG_INFO,
                       "mesh: noise at the error bound: the input would take about %.3g balls, a "
                       "copy smoothed within %.3g (%.2f of the bound; vertices moved %.3g on "
                       "average) %.3g within the rest of the bound: sampling the copy",
                       dc->n_input, dc->moved.max_move,
                       dc->moved.max_move / error_bound_of(s, opt->max_error),
                       dc->moved.mean_move, dc->n_denoised);
        }
    }
    const vc_surface *base = dc->used ? &denoised : s; /* changes if the input diverges */
    int fold_round = 0;
    if (folds) {
        stuck = calloc((size_t)s->n_triangles + 1, 1);
        if (!stuck) {
            free(extra);
            vc_surface_free(&denoised);
            vc_features_free(&f_first);
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
        }
        so.stuck_tri = stuck;
        so.fold_stop_angle = FOLD_FLAT;
    }
    for (int attempt = 0;; attempt++) {
        const double t1 = now();
        const vc_surface *sampled = base;
        /* said first: on a fine noisy surface the folds judged at the
         * error bound take seconds (a 198,400-triangle UV sphere: 7 s) */
        const double bound = dc->used ? dc->bound : error_bound_of(s, opt->max_error);
        if (attempt == 0)
            vc_log(opt->log, VC_LOG_INFO, "mesh: sharp features of %lld triangles at %g degrees, "
                   "judged at the error bound %g", (long long)s->n_triangles, so.sharp_angle, bound);
        if (attempt == 0 && f_first.n_triangles > 0) {
            f = f_first; /* made by the choice, for this surface and bound */
            memset(&f_first, 0, sizeof f_first);
        } else if (vc_features_detect_scaled(base, so.sharp_angle, extra, bound, &f, err)) {
            rc = named(err, name, NULL);
            break;
        }
        if (attempt == 0 && f.n_sharp_noise + f.n_corner_noise > 0)
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: %lld folds over %g degrees and %lld corners are noise at the error bound "
                   "(%g: on ground flat at it, or smaller than it), not features; left inside the "
                   "patches",
                   (long long)f.n_sharp_noise, so.sharp_angle, (long long)f.n_corner_noise,
                   f.noise_scale);
        if (attempt == 0 && f.n_corner_cosmooth > 0)
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: %lld vertices are corners: two of their triangles agree within %g "
                   "degrees neither in their normals nor in their normals smoothed at the error "
                   "bound (no sampling converges at such a vertex without a corner ball)",
                   (long long)f.n_corner_cosmooth, so.sharp_angle);
        if (attempt == 0 && f.n_sharp_visible > 0)
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: %lld folds below %g degrees are creases: their triangles leave each "
                   "other's plane by more than %g times the error bound",
                   (long long)f.n_sharp_visible, so.sharp_angle, VC_VISIBLE_FOLD);
        if (attempt == 0 && f.n_sharp_round > 0)
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: %lld edges are creases in the middle of rounds narrower than the error "
                   "bound (the surface turns by more than %g degrees between flat flanks %g "
                   "apart)",
                   (long long)f.n_sharp_round, so.sharp_angle, bound);
        if (smooth > 0) {
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: %d rounds of Loop smoothing of the patches (%lld triangles, about %lld "
                   "after)", smooth, (long long)s->n_triangles,
                   (long long)s->n_triangles << (2 * smooth));
            vc_surface_free(&smoothed);
            if (vc_surface_smooth(base, &f, smooth, VC_SMOOTH_DEFAULT_FLAT_ANGLE, &smoothed, err)) {
                rc = named(err, name, "smoothing");
                break;
            }
            vc_features_free(&f);
            sampled = &smoothed;
            if (vc_features_detect(sampled, so.sharp_angle, &f, err)) {
                rc = named(err, name, NULL);
                break;
            }
        }
        const double t2 = now();
        vc_balls_free(&out->balls);
        int unresolved = 0;
        if (vc_sample_surface(sampled, &f, &so, &out->balls, &out->sampling, err) == 0) {
            out->sampling.t_features = t2 - t1;
            out->sharp_angle = so.sharp_angle;
            out->smooth_iterations = smooth;
            out->n_sampled_triangles = sampled->n_triangles;
            rc = reconstruct(s, opt, name, mm, out, &unresolved, err);
            if (rc == 0 || !unresolved)
                break;
            rc = 0;
        }
        double new_angle = so.sharp_angle;
        int new_smooth = smooth;
        int64_t n_folds = 0, n_edges = 0;
        vc_error why = *err;
        /* Sliver elimination fought the input's folds without end: the
         * copy smoothed within half the bound is sampled next (once; the
         * fold rounds below then act on it). A clean marching-cubes part
         * whose sharp rims are staircases of folds needs it: the copy's
         * prediction is close to the input's, but its rims are smooth at
         * the bound's scale. */
        const int copy_next = out->sampling.diverged && !dc->used && copy_allowed && smooth == 0 &&
                              fold_round == 0 && !dc->copy_refused;
        if (copy_next && !denoised.xyz &&
            vc_make_denoised(s, error_bound_of(s, opt->max_error), opt->threads, &denoised, dc, err)) {
            rc = named(err, name, NULL);
            break;
        }
        /* a copy that moves real geometry is no remedy: the fold rounds
         * below act on the input instead */
        if (copy_next && !(fabs(dc->volume_change) <= VC_DENOISE_REMEDY_VOLUME_CHANGE)) {
            dc->copy_refused = 1;
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: %s; a copy smoothed within half the error bound would change the "
                   "volume by %+.2f%%: not sampled", why.msg, 100 * dc->volume_change);
        } else if (copy_next && dc->self_intersections > 0) {
            dc->copy_refused = 1;
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: %s; a copy smoothed within half the error bound would intersect itself "
                   "(%lld pairs of triangles: a part thinner than the smoothing's reach): not "
                   "sampled", why.msg, (long long)dc->self_intersections);
        } else if (copy_next) {
            dc->used = 1;
            base = &denoised;
            so.max_error = dc->bound / vc_surface_diagonal(&denoised);
            vc_log(opt->log, VC_LOG_INFO, "mesh: %s", why.msg);
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: sampling again a copy smoothed within %.3g (%.2f of the error bound; "
                   "vertices moved %.3g on average; volume %+.3f%%), within the rest of the bound",
                   dc->moved.max_move, dc->moved.max_move / error_bound_of(s, opt->max_error),
                   dc->moved.mean_move, 100 * dc->volume_change);
            vc_features_free(&f);
            if (stuck)
                memset(stuck, 0, (size_t)s->n_triangles + 1);
            out->resampled = 1;
            out->time.failed_sampling += now() - t1;
            continue;
        }
        if (folds && out->sampling.diverged && fold_round <= FOLD_LOCAL_ROUNDS) {
            if (!extra && !(extra = calloc((size_t)f.n_edges + 1, 1))) {
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                break;
            }
            int everywhere = fold_round == FOLD_LOCAL_ROUNDS;
            int64_t added = promote_folds(&f, stuck, everywhere, extra);
            if (added == 0 && !everywhere) {
                everywhere = 1;
                fold_round = FOLD_LOCAL_ROUNDS;
                added = promote_folds(&f, stuck, 1, extra);
            }
            fold_round++;
            if (added > 0) {
                vc_log(opt->log, VC_LOG_INFO, "mesh: %s", why.msg);
                vc_log(opt->log, VC_LOG_INFO,
                       "mesh: sampling again with %lld more folds of over %g degrees as creases "
                       "(%s; round %d)", (long long)added, FOLD_FLAT,
                       everywhere ? "all of them" : "where sliver elimination is stuck",
                       fold_round);
                vc_features_free(&f);
                out->resampled = 1;
                out->time.failed_sampling += now() - t1;
                continue;
            }
        }
        /* f holds the input's features at theta_sharp unless the input was
         * smoothed first */
        /* the creases at FOLD_ANGLE can predict more balls than allowed:
         * then the smoothing is the remedy left */
        const int refused_creases = attempt == 1 && smooth == 0 &&
                                    so.sharp_angle == FOLD_ANGLE &&
                                    !(out->sampling.n_balls_predicted <= (double)so.max_balls);
        /* a sampling that converged but whose surface is not the input's
         * topology (a few pinches sliver elimination and the pinch passes
         * left) is sampled again as a diverged one is */
        int plan = (out->sampling.diverged || refused_creases || unresolved) &&
                           (!folds || attempt == 0)
                       ? resample_plan(base, sampled == base ? &f : NULL, so.sharp_angle,
                                       /* smoothing would move the interfaces off the
                                          regions the seeds are located in */
                                       mm ? opt->resample & ~VC_RESAMPLE_SMOOTH : opt->resample,
                                       attempt + 1, &new_angle, &new_smooth,
                                       &n_folds, &n_edges, err)
                       : 0;
        if (plan < 0) {
            rc = named(err, name, NULL);
            break;
        }
        if (plan == 0) {
            *err = why;
            if (out->sampling.diverged && !(opt->resample & (VC_RESAMPLE_CREASES | VC_RESAMPLE_SMOOTH)) &&
                !mm) {
                /* the ladder is the user's choice, never the default */
                size_t len = strlen(err->msg);
                snprintf(err->msg + len, sizeof err->msg - len,
                         ", or --fallback (sample again at theta_sharp %g, then after %d rounds of "
                         "smoothing, which moves the surface)", FOLD_ANGLE,
                         VC_SMOOTH_DEFAULT_ITERATIONS);
            }
            rc = named(err, name, NULL);
            break;
        }
        vc_log(opt->log, VC_LOG_INFO, "mesh: %s", why.msg);
        if (plan == 1)
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: sampling again with --sharp-angle %g (%lld folds of %g to %g degrees "
                   "inside the patches, %.1f%% of the edges, become creases)",
                   new_angle, (long long)n_folds, FOLD_ANGLE, so.sharp_angle,
                   100.0 * (double)n_folds / (double)n_edges);
        else
            vc_log(opt->log, VC_LOG_INFO,
                   "mesh: sampling again with --smooth-iterations %d --sharp-angle %g (the "
                   "surface bends too much everywhere: the thesis' smoothing of the patches)",
                   new_smooth, new_angle);
        vc_features_free(&f);
        so.sharp_angle = new_angle;
        smooth = new_smooth;
        out->resampled = 1;
        out->time.failed_sampling += now() - t1;
    }
    vc_features_free(&f);
    vc_surface_free(&smoothed);
    vc_surface_free(&denoised);
    vc_features_free(&f_first);
    free(stuck);
    free(extra);
    return rc;
}

/* The surface seeds followed by the interior seeds of opt->interior
 * (octree or lattice) into *all, their count into *n_interior; nothing
 * for VC_INTERIOR_NONE. The seeds on the balls' spheres
 * (vc_interior_sphere_seeds: caps on corner and edge balls, and poles
 * with --protect) come first among the interior seeds, and the octree or
 * lattice keeps away from them as from the surface seeds. */
static int interior_seeds(const vc_mesh_options *opt, const char *name, vc_mesh_result *out,
                          vc_seeds *all, int64_t *n_interior, vc_octree_stats *octree,
                          vc_error *err)
{
    *n_interior = 0;
    out->n_sphere_seeds = 0;
    free(out->sphere_ball);
    out->sphere_ball = NULL;
    if (opt->interior == VC_INTERIOR_NONE)
        return 0;
    /* the surface seeds and the sphere seeds: what the interior keeps away
     * from */
    vc_seeds base = out->seeds, sphere = {0, NULL, NULL}, joined = {0, NULL, NULL};
    vc_sphere_seed_options so;
    vc_sphere_seed_options_default(&so);
    so.poles = opt->protect_edge > 0;
    /* the poles keep clear of the other balls as the moved seeds do */
    so.pole_gap = so.poles ? vc_protect_ball_gap(opt->protect_edge) : 0;
    if (vc_interior_sphere_seeds(&out->balls, &out->seeds, &so, &sphere, &out->sphere_ball, err))
        return named(err, name, NULL);
    if (sphere.n > 0) {
        if (vc_seeds_concat(&out->seeds, &sphere, &joined, err)) {
            vc_seeds_free(&sphere);
            return named(err, name, NULL);
        }
        base = joined;
    }
    out->n_sphere_seeds = sphere.n;
    vc_seeds_free(&sphere);
    int rc = 0;
    if (opt->interior == VC_INTERIOR_OCTREE) {
        vc_octree_options oo;
        vc_octree_options_default(&oo);
        oo.lipschitz = opt->lipschitz; /* the sizing extends the balls' own grading */
        oo.max_size = opt->max_size;
        oo.threads = opt->threads;
        vc_log(opt->log, VC_LOG_INFO, "mesh: interior octree");
        if (vc_interior_octree(&out->balls, &base, &oo, all, n_interior, octree, NULL, err))
            rc = named(err, name, NULL);
    } else if (opt->interior == VC_INTERIOR_LATTICE) {
        double h = opt->interior_spacing > 0
                       ? opt->interior_spacing
                       : vc_interior_default_spacing(&out->balls, opt->max_size);
        if (vc_interior_lattice(&out->balls, &base, h, all, n_interior, err))
            rc = named(err, name, NULL);
    }
    vc_seeds_free(&joined);
    if (!rc)
        *n_interior += out->n_sphere_seeds;
    return rc;
}

/* The surface alone (--surface-only): the facets between the inside and
 * outside surface seeds. The inside cells are bounded by the interior
 * seeds the volume mesh would have (not built themselves): without them
 * each inside cell is a column reaching across the solid to the medial
 * axis (the noisy sphere's 141,110 inside cells took 14 s on 2 threads).
 * The interior seeds lie away from the balls, so the facets are the
 * volume mesh's boundary faces. */
static int surface_only(const vc_mesh_options *opt, const char *name, vc_mesh_result *out,
                        vc_error *err)
{
    vc_seeds all = {0, NULL, NULL};
    int64_t n_interior = 0;
    vc_octree_stats octree;
    /* a library caller that has not started MPI gets the same surface
     * without the octree's bounds, more slowly */
    if ((opt->interior != VC_INTERIOR_OCTREE || vc_octree_runtime_available()) &&
        interior_seeds(opt, name, out, &all, &n_interior, &octree, err))
        return err->code;
    const vc_seeds *seeds = n_interior > 0 ? &all : &out->seeds;
    for (int64_t i = out->n_surface_seeds; i < seeds->n; i++)
        seeds->label[i] = 0; /* bounding seeds: not kept */
    if (seeds->n >= PROGRESS_CELLS)
        vc_log(opt->log, VC_LOG_INFO, "mesh: the surface: Voronoi cells of %lld seeds",
               (long long)seeds->n);
    vc_seed_spheres_owned on_spheres;
    if (find_seed_spheres(opt, out, seeds, &on_spheres, err)) {
        vc_seeds_free(&all);
        return named(err, name, NULL);
    }
    const int rc = vc_reconstruct_surface(seeds, out->n_surface_seeds, &on_spheres.view,
                                          opt->threads, opt->log, &out->surface, err);
    vc_seed_spheres_free(&on_spheres);
    vc_seeds_free(&all);
    return rc ? named(err, name, "reconstructing the surface") : 0;
}

/* Rounds of mending checkMesh's failures at the seeds (vc_interior_unskew),
 * each followed by the cells again, while a round moves seeds and the count
 * of failing faces and cells falls. */
#define UNSKEW_ROUNDS 3

static int unskew_rounds(const vc_mesh_options *opt, const char *name, vc_mesh_result *out,
                         vc_voronoi_options *vo, vc_voronoi_cells *cells, vc_error *err)
{
    const double t = now();
    int64_t moved = 0, built = 0;
    int64_t last = -1;
    const int64_t n = out->seeds.n;
    double *before = malloc(sizeof(double) * 3 * (size_t)n);
    int64_t *which = malloc(sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
    /* seeds tried in vain, not tried again until a neighbour moves
     * (cow.off's three rounds tried 989, 831 and 793 seeds and moved 296,
     * 202 and 160; now they try 989, 291 and 229) */
    unsigned char *stuck = calloc((size_t)n + 1, 1), *moved_now = calloc((size_t)n + 1, 1);
    if (!before || !which || !stuck || !moved_now) {
        free(before);
        free(which);
        free(stuck);
        free(moved_now);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory mending skew faces", name);
    }
    int rc = 0;
    for (int round = 0; round < UNSKEW_ROUNDS && !rc; round++) {
        vc_unskew_options uo;
        vc_unskew_options_default(&uo);
        uo.max_skew = opt->unskew;
        uo.random_seed = opt->seed + 0x9E3779B9ull * (uint64_t)round;
        uo.threads = opt->threads;
        uo.n_sphere_seeds = out->n_sphere_seeds;
        uo.sphere_ball = out->sphere_ball;
        uo.stuck = stuck;
        vc_unskew_stats us;
        vc_log(opt->log, VC_LOG_INFO, "mesh: mending skew faces, round %d", round + 1);
        memcpy(before, out->seeds.xyz, sizeof(double) * 3 * (size_t)n);
        if (vc_interior_unskew(&out->balls, &out->seeds, out->n_surface_seeds, &out->mesh, &uo,
                               &us, err)) {
            rc = named(err, name, NULL);
            break;
        }
        if (round == 0)
            out->unskew = us;
        moved += us.n_moved;
        built += us.n_cells_built;
        vc_log(opt->log, VC_LOG_DEBUG, "  mesh: skew faces above %g: %lld (max %.3g), faces of "
               "small weight or volume ratio %lld, concave cells %lld; %lld seeds tried, %lld "
               "moved, %lld cells built, %.3f s", opt->unskew, (long long)us.n_skew_faces,
               us.max_skew, (long long)us.n_weak_faces, (long long)us.n_concave_cells,
               (long long)us.n_tried, (long long)us.n_moved, (long long)us.n_cells_built,
               us.seconds);
        /* on while the faces and cells that fail fall (the moves of a round
         * lower the failures around each seed, but at the same count a
         * further round gained little: gear, skewness 4.19 to 4.16 in 3
         * rounds) */
        const int64_t failing = us.n_skew_faces + us.n_weak_faces + us.n_concave_cells;
        if (us.n_moved == 0 || (last >= 0 && failing >= last))
            break;
        last = failing;
        /* the mesh again: only the cells next to a moved seed are built
         * again (vc_voronoi_rebuild), then all stitched */
        int64_t n_which = 0;
        for (int64_t i = 0; i < n; i++)
            if (memcmp(before + 3 * i, out->seeds.xyz + 3 * i, 3 * sizeof(double)) != 0)
                which[n_which++] = i;
        vc_seed_spheres_owned on_spheres;
        if (find_seed_spheres(opt, out, &out->seeds, &on_spheres, err)) {
            rc = named(err, name, NULL);
            break;
        }
        vo->spheres = &on_spheres.view;
        vc_polymesh_free(&out->mesh);
        out->has_mesh = 0;
        rc = vc_voronoi_rebuild(cells, &out->seeds, which, n_which, vo, &out->mesh, err);
        vc_seed_spheres_free(&on_spheres);
        vo->spheres = NULL;
        if (rc) {
            rc = named(err, name, NULL);
            break;
        }
        out->has_mesh = 1;
        out->unskew_rounds = round + 1;
        /* the seeds next to a moved one may be helped now */
        for (int64_t q = 0; q < n_which; q++)
            moved_now[which[q]] = 1;
        const vc_polymesh *m = &out->mesh;
        for (int64_t f = 0; f < m->n_interior_faces; f++) {
            const int64_t a = m->cell_seed[m->face_owner[f]], b = m->cell_seed[m->face_neighbour[f]];
            if (moved_now[a] || moved_now[b])
                stuck[a] = stuck[b] = 0;
        }
        for (int64_t q = 0; q < n_which; q++)
            moved_now[which[q]] = 0;
    }
    free(before);
    free(which);
    free(stuck);
    free(moved_now);
    if (rc)
        return rc;
    out->unskew.n_moved = moved;
    out->unskew.n_cells_built = built;
    out->time.unskew = now() - t;
    return 0;
}

/* Interior seeds, Lloyd relaxation, the Voronoi mesh and its measures. */
static int volume_mesh(const vc_mesh_options *opt, const char *name, const vc_materials *mm,
                       vc_mesh_result *out, vc_error *err)
{
    double t = now();
    vc_seeds all = {0, NULL, NULL};
    if (interior_seeds(opt, name, out, &all, &out->n_interior_seeds, &out->octree, err))
        return err->code;
    if (opt->interior != VC_INTERIOR_NONE) {
        vc_seeds_free(&out->seeds);
        out->seeds = all;
    }
    if (mm && out->n_interior_seeds > 0) {
        /* the interior seeds took their nearest surface seed's region,
         * which is right unless a seed of another region lies nearer (not
         * seen on the tests' cases); the locator decides it exactly */
        vc_seeds rest = {out->n_interior_seeds, out->seeds.xyz + 3 * out->n_surface_seeds,
                         out->seeds.label + out->n_surface_seeds};
        int32_t *before = malloc(sizeof(int32_t) * (size_t)rest.n);
        if (!before)
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
        memcpy(before, rest.label, sizeof(int32_t) * (size_t)rest.n);
        vc_materials_label_seeds(mm, &rest, rest.n, opt->threads);
        int64_t changed = 0;
        for (int64_t i = 0; i < rest.n; i++)
            changed += before[i] != rest.label[i];
        free(before);
        vc_log(opt->log, VC_LOG_DEBUG, "mesh: %lld of %lld interior seeds change region by the "
               "locator", (long long)changed, (long long)rest.n);
    }
    out->time.interior = now() - t;

    t = now();
    if (opt->lloyd_iterations > 0 && out->n_interior_seeds > 0) {
        vc_log(opt->log, VC_LOG_INFO, "mesh: Lloyd relaxation, %d iterations of %lld seeds",
               opt->lloyd_iterations, (long long)out->seeds.n);
        if (vc_interior_lloyd(&out->balls, &out->seeds, out->n_surface_seeds,
                              opt->lloyd_iterations, opt->threads, &out->lloyd, err))
            return named(err, name, NULL);
    }
    out->time.lloyd = now() - t;

    t = now();
    if (opt->protect_edge > 0 && out->n_interior_seeds > 0) {
        vc_protect_options po;
        vc_protect_options_default(&po);
        po.min_edge = opt->protect_edge;
        po.random_seed = opt->seed;
        po.threads = opt->threads;
        vc_log(opt->log, VC_LOG_INFO, "mesh: protecting %lld interior seeds from short edges",
               (long long)out->n_interior_seeds);
        po.n_poles = out->n_sphere_seeds;
        po.pole_ball = out->sphere_ball;
        /* the octree's or lattice's seeds, unless Lloyd moved them */
        if (opt->lloyd_iterations == 0)
            po.lattice_begin = out->n_surface_seeds + out->n_sphere_seeds;
        if (vc_interior_protect(&out->balls, &out->seeds, out->n_surface_seeds, &po,
                                &out->protect, err))
            return named(err, name, NULL);
    }
    out->time.protect = now() - t;

    t = now();
    vc_voronoi_options vo;
    vc_voronoi_options_default(&vo);
    vo.threads = opt->threads;
    vo.log = opt->log;
    vc_log(opt->log, VC_LOG_INFO, "mesh: Voronoi cells of %lld seeds", (long long)out->seeds.n);
    /* the vertex at a ball's centre is one point (vc_seed_spheres) */
    vc_seed_spheres_owned on_spheres;
    if (find_seed_spheres(opt, out, &out->seeds, &on_spheres, err))
        return named(err, name, NULL);
    vo.spheres = &on_spheres.view;
    /* --unskew moves seeds and makes the mesh again: the cells are kept
     * for that */
    const int unskew = opt->unskew > 0 && out->n_interior_seeds > 0;
    vc_voronoi_cells *cells = NULL;
    int built = unskew ? vc_voronoi_build_keep(&out->seeds, &vo, &out->mesh, &cells, err)
                       : vc_voronoi_build(&out->seeds, &vo, &out->mesh, err);
    vc_seed_spheres_free(&on_spheres);
    if (built)
        return named(err, name, NULL);
    out->has_mesh = 1;
    if (unskew) {
        built = unskew_rounds(opt, name, out, &vo, cells, err);
        vc_voronoi_cells_free(cells);
        if (built)
            return built;
    }
    /* what follows takes a second or more on a few hundred thousand
     * cells: a progress line */
    if (out->mesh.n_cells >= PROGRESS_CELLS)
        vc_log(opt->log, VC_LOG_INFO, "mesh: ordering and checking %lld cells",
               (long long)out->mesh.n_cells);
    const double t_order = now();
    /* the cells in a solver's order (reverse Cuthill-McKee), for every
     * output alike: the engine numbers them by seed, and the surface seeds
     * come before the interior ones */
    {
        out->cell_bandwidth_engine = vc_polymesh_bandwidth(&out->mesh);
        int64_t *order = malloc(sizeof(int64_t) * (size_t)(out->mesh.n_cells + 1));
        if (!order || vc_polymesh_rcm_order(&out->mesh, order) ||
            vc_polymesh_renumber_cells(&out->mesh, order)) {
            free(order);
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory ordering the cells", name);
        }
        free(order);
        out->cell_bandwidth = vc_polymesh_bandwidth(&out->mesh);
    }
    out->time.voronoi = now() - t - out->time.unskew;
    vc_log(opt->log, VC_LOG_DEBUG, "  mesh: cell order %.3f s", now() - t_order);

    t = now();
    vc_polymesh *m = &out->mesh;
    out->mesh_volume = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        out->mesh_volume += m->cell_volume[c];
    char report[1024];
    out->mesh_problems = vc_polymesh_validate(m, 0, report, sizeof report);
    if (out->mesh_problems) {
        /* a mesh known to be broken is an error, not a result */
        snprintf(out->mesh_problem, sizeof out->mesh_problem, "%.*s",
                 (int)strcspn(report, "\n"), report);
        return vc_error_set(err, VC_EINTERNAL,
                            "%s: the volume mesh fails validation (%lld problems, first: %s): "
                            "the Voronoi engine's tolerances did not resolve nearly degenerate "
                            "seeds there; try another --seed", name,
                            (long long)out->mesh_problems, out->mesh_problem);
    }
    const double t_validated = now();
    if (m->n_cells >= PROGRESS_CELLS)
        vc_log(opt->log, VC_LOG_INFO, "mesh: %lld cells valid; measuring them",
               (long long)m->n_cells);
    /* per-cell fatness goes into the .vtu as well */
    m->cell_fatness = malloc(sizeof(double) * (size_t)(m->n_cells ? m->n_cells : 1));
    if (!m->cell_fatness || vc_cell_quality_compute(m, &out->cell_quality, m->cell_fatness, opt->threads))
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory measuring the cells", name);
    out->time.quality = now() - t;
    vc_log(opt->log, VC_LOG_DEBUG, "  mesh: validation %.3f s, cell quality %.3f s",
           t_validated - t, now() - t_validated);
    return 0;
}

/* The volume the outer boundary of a multi-material mesh encloses: its
 * faces between a kept cell and the outside (with surface_only, where the
 * mesh is gone, the whole surface's, interfaces included). */
static double outer_volume(const vc_polymesh *m, const vc_polysurface *surface)
{
    if (!m->n_cells)
        return vc_polysurface_volume(surface);
    double v = 0;
    for (int64_t f = m->n_interior_faces; f < m->n_faces; f++) {
        const double *c = m->face_centroid + 3 * f, *n = m->face_normal + 3 * f;
        v += m->face_area[f] * (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]) / 3;
    }
    for (int64_t f = 0; f < m->n_interior_faces; f++) {
        const int32_t a = m->cell_region[m->face_owner[f]], b = m->cell_region[m->face_neighbour[f]];
        if ((a == 0) == (b == 0))
            continue;
        const double *c = m->face_centroid + 3 * f, *n = m->face_normal + 3 * f;
        v += (a ? 1 : -1) * m->face_area[f] * (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]) / 3;
    }
    return v;
}

/* A model this many times its size from the origin is meshed about its
 * centre (below it, the offset costs less than 4 bits). */
#define FAR_FROM_ORIGIN 16.0

static double far_size(const double *bbox)
{
    const double dx = bbox[3] - bbox[0], dy = bbox[4] - bbox[1], dz = bbox[5] - bbox[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* When the box's centre is more than FAR_FROM_ORIGIN sizes from the
 * origin: *out = s moved by -centre (its own vertices; triangles and
 * groups borrowed from s: free it with free_centred), the centre in shift.
 * Otherwise *out stays empty. Returns 0 or VC_ENOMEM. */
static int centre_far_model(const vc_surface *s, const double *bbox, vc_surface *out,
                            double shift[3], vc_error *err)
{
    double c[3], far = 0;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5 * (bbox[k] + bbox[k + 3]);
        far = fmax(far, fabs(c[k]));
    }
    if (!(far > FAR_FROM_ORIGIN * far_size(bbox)))
        return 0;
    out->xyz = malloc(sizeof(double) * 3 * (size_t)(s->n_vertices + 1));
    if (!out->xyz)
        return vc_error_set(err, VC_ENOMEM, "out of memory moving the model");
    for (int64_t v = 0; v < s->n_vertices; v++)
        for (int k = 0; k < 3; k++)
            out->xyz[3 * v + k] = s->xyz[3 * v + k] - c[k];
    out->n_vertices = s->n_vertices;
    out->n_triangles = s->n_triangles;
    out->tri = s->tri;
    out->tri_group = s->tri_group;
    out->n_groups = s->n_groups;
    out->group_name = s->group_name;
    memcpy(shift, c, sizeof c);
    return 0;
}

static void free_centred(vc_surface *c)
{
    free(c->xyz);
    memset(c, 0, sizeof *c); /* the rest is borrowed */
}

static void move_points(double *xyz, int64_t n, const double shift[3])
{
    for (int64_t i = 0; xyz && i < n; i++)
        for (int k = 0; k < 3; k++)
            xyz[3 * i + k] += shift[k];
}

/* Every position of the results back by +shift (volumes, areas and
 * normals do not move). */
static void move_results(vc_mesh_result *out, const double shift[3])
{
    move_points(out->balls.center, out->balls.n, shift);
    move_points(out->seeds.xyz, out->seeds.n, shift);
    move_points(out->surface.points, out->surface.n_points, shift);
    vc_polymesh *m = &out->mesh;
    move_points(m->points, m->n_points, shift);
    move_points(m->face_centroid, m->n_faces, shift);
    move_points(m->cell_centroid, m->n_cells, shift);
    move_points(m->seed_xyz, m->n_seeds, shift);
}

/* *out = s with its own copy of the triangles, the vertices and groups
 * borrowed from s (free out->tri only). */
static int copy_triangles(const vc_surface *s, vc_surface *out, vc_error *err)
{
    *out = *s;
    out->tri = malloc(sizeof(int64_t) * 3 * (size_t)(s->n_triangles + 1));
    if (!out->tri) {
        memset(out, 0, sizeof *out);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the repaired surface");
    }
    memcpy(out->tri, s->tri, sizeof(int64_t) * 3 * (size_t)s->n_triangles);
    return 0;
}

/* *out = s with its own copies of the vertices and triangles, the groups
 * borrowed (free out->xyz and out->tri only). */
static int copy_vertices_and_triangles(const vc_surface *s, vc_surface *out, vc_error *err)
{
    int rc = copy_triangles(s, out, err);
    if (rc)
        return rc;
    out->xyz = malloc(sizeof(double) * 3 * (size_t)(s->n_vertices + 1));
    if (!out->xyz) {
        free(out->tri);
        memset(out, 0, sizeof *out);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the repaired surface");
    }
    memcpy(out->xyz, s->xyz, sizeof(double) * 3 * (size_t)s->n_vertices);
    return 0;
}

/* *out = s with its own vertices, triangles and triangle groups, the group
 * names borrowed (free out->xyz, out->tri and out->tri_group only). */
static int copy_surface_own(const vc_surface *s, vc_surface *out, vc_error *err)
{
    int rc = copy_vertices_and_triangles(s, out, err);
    if (rc || !s->tri_group)
        return rc;
    out->tri_group = malloc(sizeof(int32_t) * (size_t)(s->n_triangles + 1));
    if (!out->tri_group) {
        free(out->xyz);
        free(out->tri);
        memset(out, 0, sizeof *out);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the repaired surface");
    }
    memcpy(out->tri_group, s->tri_group, sizeof(int32_t) * (size_t)s->n_triangles);
    return 0;
}

/* A repair was made: the surface meshed and its groups' source become
 * `repaired`, and the input's report describes it. */
static int adopt_repair(const vc_surface **s, const vc_surface **s_input, const vc_surface *repaired,
                        vc_surface_report *input, vc_error *err)
{
    *s = repaired;
    *s_input = repaired;
    return vc_surface_check(repaired, input, err);
}

/* Pinch vertices (sheets touching at a point: where two intersection
 * curves of a union meet, cow.off's tail on its rump; parts of an input
 * that touch at a vertex) opened by an eighth of the error bound
 * (vc_surface_open_pinches; with min_cos > -1 only those whose fans meet
 * at a small angle). *opened receives src with its pinches opened (own
 * vertices and triangles, the groups borrowed from src), or stays empty
 * when src has none, or when opening them would make triangles cross that
 * did not. */
static int open_pinches(const vc_surface *src, const char *name, const vc_mesh_options *opt,
                        double min_cos, vc_surface *opened, vc_pinch_report *rep, vc_error *err)
{
    memset(rep, 0, sizeof *rep);
    memset(opened, 0, sizeof *opened);
    if (!(opt->max_error > 0))
        return 0;
    const double bound = error_bound_of(src, opt->max_error);
    int rc = copy_vertices_and_triangles(src, opened, err);
    if (!rc)
        rc = vc_surface_open_pinches(opened, 0.125 * bound, min_cos, rep, err);
    int keep = !rc && rep->n_pinches > 0;
    if (keep) {
        /* src's own crossings (a union's cut points rounded off their
         * planes) against the opened surface's */
        vc_surface_report r0, r1;
        vc_solid_report s0, s1;
        memset(&r0, 0, sizeof r0);
        memset(&r1, 0, sizeof r1);
        vc_error e0 = {0, ""}, e1 = {0, ""};
        keep = !vc_surface_check(src, &r0, &e0) && !vc_surface_check(opened, &r1, &e1);
        if (keep) {
            const int c0 = vc_surface_check_solid(src, &r0, &s0, &e0);
            const int c1 = vc_surface_check_solid(opened, &r1, &s1, &e1);
            if (c0 == VC_ENOMEM || c1 == VC_ENOMEM)
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            keep = !rc && s1.n_self_intersections <= s0.n_self_intersections;
        }
        if (!rc && !keep)
            vc_log(opt->log, VC_LOG_INFO, "mesh: %s: opening its %lld pinch vertices would make "
                   "triangles cross: kept", name, (long long)rep->n_pinches);
    }
    if (!keep) {
        free(opened->xyz);
        free(opened->tri);
        memset(opened, 0, sizeof *opened);
        memset(rep, 0, sizeof *rep);
    }
    return rc;
}

/* The non-manifold vertices of the triangle surface s, counted as the
 * reconstructed surface's are (vc_polysurface_topology_compute). */
static int count_nonmanifold_vertices(const vc_surface *s, int64_t *n, vc_error *err)
{
    vc_polysurface view;
    view.n_points = s->n_vertices;
    view.points = s->xyz;
    view.n_polys = s->n_triangles;
    view.poly_vertices = s->tri;
    view.poly_offsets = malloc(sizeof(int64_t) * (size_t)(s->n_triangles + 1));
    if (!view.poly_offsets)
        return vc_error_set(err, VC_ENOMEM, "out of memory");
    for (int64_t t = 0; t <= s->n_triangles; t++)
        view.poly_offsets[t] = 3 * t;
    vc_polysurface_topology topo;
    const int rc = vc_polysurface_topology_compute(&view, &topo, err);
    free(view.poly_offsets);
    *n = rc ? 0 : topo.n_nonmanifold_vertices;
    return rc;
}

/* The same with the triangles flip[t] != 0 reversed. */
static int reversed_copy(const vc_surface *s, const unsigned char *flip, vc_surface *out, vc_error *err)
{
    int rc = copy_triangles(s, out, err);
    if (!rc)
        vc_surface_reverse_triangles(out, flip);
    return rc;
}

/* The groups that name the boundary patches (opt->patches): the input's
 * triangle groups, or its sharp-feature patches. */
static int boundary_patches(const vc_surface *s, const vc_mesh_options *opt, const char *name,
                            vc_mesh_result *out, vc_error *err)
{
    if (opt->patches == VC_PATCHES_GROUPS) {
        if (!s->tri_group || s->n_groups < 1)
            return 0;
        return vc_mesh_boundary_groups(&out->mesh, s, s->tri_group, s->n_groups,
                                       (const char(*)[64])s->group_name, opt->threads, err);
    }
    vc_features f;
    memset(&f, 0, sizeof f);
    int rc = vc_features_detect_scaled(s, opt->sharp_angle, NULL, error_bound_of(s, opt->max_error), &f,
                                       err);
    if (rc)
        return named(err, name, NULL);
    int32_t *group = malloc(sizeof(int32_t) * (size_t)(s->n_triangles + 1));
    char(*names)[64] = malloc(sizeof *names * (size_t)(f.n_patches + 1));
    if (!group || !names) {
        free(group);
        free(names);
        vc_features_free(&f);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
    }
    for (int64_t t = 0; t < s->n_triangles; t++)
        group[t] = (int32_t)f.tri_patch[t];
    for (int64_t k = 0; k < f.n_patches; k++)
        snprintf(names[k], 64, "patch%lld", (long long)k + 1);
    rc = vc_mesh_boundary_groups(&out->mesh, s, group, (int32_t)f.n_patches,
                                 (const char(*)[64])names, opt->threads, err);
    free(group);
    free(names);
    vc_features_free(&f);
    return rc;
}

/* How far the reconstructed surface may lie from the input, in error
 * bounds, before the result is an error. */
#define SURFACE_DISTANCE_BOUNDS 2

/* The two-sided Hausdorff distance between the surface meshed and the
 * reconstructed one, its polygons fanned from their first corner (Voronoi
 * facets: planar and convex). 0, or an error code. */
static int surface_distance(const vc_surface *s, const vc_polysurface *p, int threads,
                            vc_hausdorff_result *out, vc_error *err)
{
    memset(out, 0, sizeof *out);
    int64_t nt = 0;
    for (int64_t f = 0; f < p->n_polys; f++)
        nt += p->poly_offsets[f + 1] - p->poly_offsets[f] - 2;
    vc_surface t;
    memset(&t, 0, sizeof t);
    t.n_vertices = p->n_points;
    t.xyz = p->points;
    t.n_triangles = nt;
    t.tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt > 0 ? nt : 1));
    if (!t.tri)
        return vc_error_set(err, VC_ENOMEM, "out of memory measuring the surface's distance");
    int64_t k = 0;
    for (int64_t f = 0; f < p->n_polys; f++) {
        const int64_t *v = p->poly_vertices + p->poly_offsets[f];
        const int64_t n = p->poly_offsets[f + 1] - p->poly_offsets[f];
        for (int64_t j = 1; j + 1 < n; j++) {
            t.tri[k++] = v[0];
            t.tri[k++] = v[j];
            t.tri[k++] = v[j + 1];
        }
    }
    const int rc = nt > 0 ? vc_hausdorff_threads(s, &t, 0, threads, out, err) : 0;
    free(t.tri);
    return rc;
}

int vc_mesh(const vc_surface *s, const vc_mesh_options *opt_in, vc_mesh_result *out,
            vc_error *err)
{
    int done = 0;        /* the result is complete: the cleanup keeps it */
    const vc_surface *s_input = s; /* with its triangle groups */
    vc_surface oriented; /* the input reoriented by --cavities (own triangles, the rest borrowed) */
    memset(&oriented, 0, sizeof oriented);
    vc_surface consistent; /* the input with its flipped triangles reversed */
    memset(&consistent, 0, sizeof consistent);
    vc_materials mm;     /* with several regions */
    memset(&mm, 0, sizeof mm);
    vc_surface centred;  /* a model far from the origin, moved to it */
    memset(&centred, 0, sizeof centred);
    vc_surface unioned;  /* a self-intersecting input's union */
    memset(&unioned, 0, sizeof unioned);
    vc_surface repaired; /* turned-over needles flipped (own triangles, the rest borrowed) */
    memset(&repaired, 0, sizeof repaired);
    vc_surface opened;   /* pinch vertices opened (own vertices and triangles, groups borrowed) */
    memset(&opened, 0, sizeof opened);
    vc_surface union_opened; /* the same of the union */
    memset(&union_opened, 0, sizeof union_opened);
    vc_surface welded; /* open seams welded (vc_surface_weld_open_seams; its own arrays) */
    memset(&welded, 0, sizeof welded);
    vc_surface turned_out; /* parts inside out reversed (own triangles, the rest borrowed) */
    memset(&turned_out, 0, sizeof turned_out);
    vc_surface needled; /* zero-area needles welded (vc_surface_weld_needles; its own arrays) */
    memset(&needled, 0, sizeof needled);
    vc_surface capped; /* zero-area caps flipped (own triangles and groups, vertices borrowed) */
    memset(&capped, 0, sizeof capped);
    int32_t *capped_group = NULL;
    vc_surface collapsed; /* edges far below the error bound collapsed (own arrays, group
                             names borrowed) */
    memset(&collapsed, 0, sizeof collapsed);
    vc_surface hairpinned; /* hairpin bases collapsed (the same ownership) */
    memset(&hairpinned, 0, sizeof hairpinned);
    vc_surface canonical; /* in the order of its geometry (vc_surface_canonical_order) */
    memset(&canonical, 0, sizeof canonical);
    int64_t *input_triangle = NULL, *input_vertex = NULL; /* canonical's in s before it */
    vc_mesh_options opt;
    if (opt_in)
        opt = *opt_in;
    else
        vc_mesh_options_default(&opt);
    memset(out, 0, sizeof *out);
    const char *name = opt.name && opt.name[0] ? opt.name : "surface";
    int rc = check_options(&opt, err);
    if (rc)
        return rc;
    const double t0 = now();
    double t_line = t0;
    /* a large input's checks take seconds: said at once (a small one's
     * refusal stays one line) */
    if (s->n_triangles >= VC_LARGE_INPUT_TRIANGLES)
        vc_log(opt.log, VC_LOG_INFO, "mesh: %s: %lld triangles; checking that they bound a volume", name,
               (long long)s->n_triangles);

    /* The input: closed and consistently oriented, or its inside is not
     * defined. */
    snprintf(out->input.name, sizeof out->input.name, "%s", name);
    if ((rc = vc_surface_check(s, &out->input, err)) != 0)
        goto fail;
    /* Open only by rounding (seam vertices computed twice, 1e-14 apart; a
     * vertex of one face's tessellation on the edge of another's): welded
     * and split, and said so; open beyond that: refused. */
    if (out->input.n_boundary_edges > 0) {
        const int64_t n_open = out->input.n_boundary_edges;
        const double tol = vc_surface_seam_tolerance(s);
        int64_t n_welded = 0, n_split = 0;
        vc_surface_report r_welded;
        if ((rc = vc_surface_close_by_rounding(s, &out->input, &welded, &r_welded, &n_welded, &n_split,
                                               err)) != 0)
            goto fail;
        if (!welded.xyz) {
            rc = vc_error_set(err, VC_EINPUT, "%s: the surface is open: %lld boundary edges "
                              "(VoroCrust needs a closed surface; welding the vertices within %.3g "
                              "of each other and splitting the edges they lie on does not close it)",
                              name, (long long)n_open, tol);
            goto fail;
        }
        out->input = r_welded;
        s = &welded;
        s_input = &welded;
        vc_log(opt.log, VC_LOG_WARNING,
               "mesh: %s: open at %lld edges by rounding: %lld vertices within %.3g (%.2g of the "
               "diagonal) of another welded, %lld triangles split at vertices on their edges "
               "(T-junctions), the surface closed", name, (long long)n_open, (long long)n_welded,
               tol, tol / vc_surface_diagonal(s), (long long)n_split);
    }
    /* Triangles that disagree on the orientation (an exporter's flipped
     * facets) are reversed, each component keeping the orientation most of
     * its triangles have: the inside is then what the input meant, unless
     * it is one-sided. */
    if (out->input.n_inconsistent_edges > 0) {
        const int64_t n_bad = out->input.n_inconsistent_edges;
        unsigned char *flip = malloc((size_t)s->n_triangles + 1);
        if (!flip) {
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            goto fail;
        }
        char why[VC_ERROR_LEN];
        rc = vc_surface_consistent_flips(s, flip, &out->n_flipped, err);
        snprintf(why, sizeof why, "%s", err->msg);
        if (rc == 0)
            rc = reversed_copy(s, flip, &consistent, err);
        free(flip);
        if (rc == VC_EINPUT)
            rc = vc_error_set(err, VC_EINPUT, "%s: %lld inconsistently oriented edges, and %s: the "
                              "inside of the surface is undefined", name, (long long)n_bad, why);
        if (rc)
            goto fail;
        if ((rc = adopt_repair(&s, &s_input, &consistent, &out->input, err)) != 0)
            goto fail;
        if (out->input.n_inconsistent_edges > 0) { /* only edges of more than two triangles left */
            rc = vc_error_set(err, VC_EINPUT, "%s: %lld inconsistently oriented edges: the inside "
                              "of the surface is undefined", name,
                              (long long)out->input.n_inconsistent_edges);
            goto fail;
        }
        vc_log(opt.log, VC_LOG_WARNING,
               "mesh: %s: %lld inconsistently oriented edges: %lld triangles reversed (each "
               "component keeps the orientation most of its triangles have)",
               name, (long long)n_bad, (long long)out->n_flipped);
    }
    /* Zero-area caps (a vertex on the opposite edge: a CAD exporter's
     * sliver closing a T-junction) cannot bound anything: the triangle
     * across that edge is split at the vertex instead, which changes no
     * area. Those that are not caps are refused by the solid check. */
    if (out->input.n_degenerate > 0) {
        if ((rc = copy_triangles(s, &capped, err)) != 0)
            goto fail;
        if (s->tri_group) {
            capped_group = malloc(sizeof(int32_t) * (size_t)(s->n_triangles + 1));
            if (!capped_group) {
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                goto fail;
            }
            memcpy(capped_group, s->tri_group, sizeof(int32_t) * (size_t)s->n_triangles);
            capped.tri_group = capped_group;
        }
        int64_t n_caps = 0, n_left = 0;
        if ((rc = vc_surface_flip_zero_area(&capped, &n_caps, &n_left, err)) != 0)
            goto fail;
        if (n_caps > 0) {
            const int64_t n_zero = out->input.n_degenerate;
            if ((rc = adopt_repair(&s, &s_input, &capped, &out->input, err)) != 0)
                goto fail;
            vc_log(opt.log, VC_LOG_WARNING,
                   "mesh: %s: %lld of its %lld zero-area triangles were caps (a vertex on the "
                   "opposite edge): the triangles across split there instead (the surface unchanged)",
                   name, (long long)n_caps, (long long)n_zero);
        }
    }
    /* Zero-area needles (two of their vertices coincide to rounding): those
     * two welded, the needles dropped. What is left is refused by the
     * solid check. */
    if (out->input.n_degenerate > 0) {
        vc_surface_report r_needled;
        if ((rc = vc_surface_drop_needles(s, &out->input, &needled, &r_needled, err)) != 0)
            goto fail;
        if (needled.xyz) {
            vc_log(opt.log, VC_LOG_WARNING,
                   "mesh: %s: %lld zero-area needles (two vertices %.3g apart or closer) removed by "
                   "welding those vertices; %lld zero-area triangles left", name,
                   (long long)(out->input.n_degenerate - r_needled.n_degenerate),
                   vc_surface_seam_tolerance(s), (long long)r_needled.n_degenerate);
            out->input = r_needled;
            s = &needled;
            s_input = &needled;
        }
    }
    /* Pleats of the tessellation below the error bound (a needle whose
     * apex crossed its long edge: cow.off has two) are flipped away before
     * anything else looks at the surface: no sampling follows them, and
     * they often cross their neighbours. Half the error bound at most, the
     * other half left to the sampling. */
    if (opt.max_error > 0 &&
        vc_surface_count_low_needles(s, 0.5 * error_bound_of(s, opt.max_error)) > 0) {
        check_progress(&opt, &t_line, name, "turned-over needles");
        if ((rc = copy_triangles(s, &repaired, err)) != 0)
            goto fail;
        if ((rc = vc_surface_flip_turned_needles(&repaired, 0.5 * error_bound_of(s, opt.max_error),
                                                 &out->needles, err)) != 0)
            goto fail;
        if (out->needles.n_flipped > 0) {
            if ((rc = adopt_repair(&s, &s_input, &repaired, &out->input, err)) != 0)
                goto fail;
            if (out->needles.n_fins > 0)
                vc_log(opt.log, VC_LOG_INFO,
                       "mesh: %s: %lld needle triangles standing up as fins (60 to 90 degrees, the apex "
                       "within a tenth of the error bound of the long edge) flipped",
                       name, (long long)out->needles.n_fins);
            if (out->needles.n_flipped > out->needles.n_fins)
                vc_log(opt.log, VC_LOG_INFO,
                       "mesh: %s: %lld turned-over needle triangles (an apex across its long edge) "
                       "flipped; the surface moved by at most %.3g (%.2g of the error bound)",
                       name, (long long)(out->needles.n_flipped - out->needles.n_fins),
                       out->needles.max_move, out->needles.max_move / error_bound_of(s, opt.max_error));
            else
                vc_log(opt.log, VC_LOG_INFO, "mesh: %s: the surface moved by at most %.3g (%.2g of the "
                       "error bound)", name, out->needles.max_move,
                       out->needles.max_move / error_bound_of(s, opt.max_error));
        }
    }
    /* Hairpins: a sliver of one face reaching into another, its two long
     * edges folding beyond theta_sharp, its base far below the error bound
     * (decimated marching-cubes parts have them along their rims): two
     * creases that close, for their whole length, would hold every ball
     * near them to the slit's width (a decimated bracket: 119,777 balls,
     * 44,500 without its six hairpins). Collapsed at the base, the slit's
     * sides are one edge of the face. */
    if (opt.max_error > 0) {
        const double bound = error_bound_of(s, opt.max_error);
        const double cos_sharp = cos(opt.sharp_angle * 3.14159265358979323846 / 180);
        check_progress(&opt, &t_line, name, "hairpins");
        const int64_t candidates = vc_surface_count_hairpins(s, VC_MESH_HAIRPIN_BASE * bound, cos_sharp);
        if (candidates < 0) {
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            goto fail;
        }
        if (candidates > 0) {
            /* only the hairpins whose folds are features at the error
             * bound: on noisy ground (a scan's pole) they are noise, which
             * the sizing already smooths, and collapses there fold it more */
            vc_features fh;
            if ((rc = vc_features_detect_scaled(s, opt.sharp_angle, NULL, bound, &fh, err)) != 0)
                goto fail;
            rc = copy_surface_own(s, &hairpinned, err);
            const int64_t nh = rc ? 0
                                  : vc_surface_collapse_hairpins(&hairpinned, VC_MESH_HAIRPIN_BASE * bound,
                                                                 cos_sharp, &fh, &out->hairpin_move);
            vc_features_free(&fh);
            if (rc)
                goto fail;
            if (nh < 0) {
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                goto fail;
            }
            if (nh > 0) {
                out->n_hairpins = nh;
                if ((rc = adopt_repair(&s, &s_input, &hairpinned, &out->input, err)) != 0)
                    goto fail;
                vc_log(opt.log, VC_LOG_INFO,
                       "mesh: %s: %lld hairpins (slivers of one face reaching into another, their "
                       "bases below %g of the error bound) collapsed; the surface moved by at most %.3g",
                       name, (long long)nh, VC_MESH_HAIRPIN_BASE, out->hairpin_move);
            }
        }
    }
    /* Parts that touch at a vertex only, their sheets parting at less than
     * theta_sharp (two spheres sharing a pole diverged: the balls must stay
     * below a gap that grows slowly from zero), are parted there like the
     * union's pinches; cones meeting at a wide angle (two cubes' corners)
     * are kept, as is any vertex on an edge of more than two triangles
     * (the interfaces of materials, parts touching along an edge). */
    if (out->input.n_nonmanifold_edges == 0) {
        check_progress(&opt, &t_line, name, "pinch vertices");
        if ((rc = open_pinches(s, name, &opt, cos(opt.sharp_angle * 3.14159265358979323846 / 180), &opened,
                               &out->input_pinches, err)) != 0)
            goto fail;
        if (opened.xyz) {
            if ((rc = adopt_repair(&s, &s_input, &opened, &out->input, err)) != 0)
                goto fail;
            vc_log(opt.log, VC_LOG_INFO,
                   "mesh: %s: %lld pinch vertices (parts touching at a point at a small angle) opened: "
                   "the surface moved by at most %.3g (%.2g of the error bound)", name,
                   (long long)out->input_pinches.n_pinches, out->input_pinches.max_move,
                   out->input_pinches.max_move / error_bound_of(s, opt.max_error));
        }
    }
    /* Edges a thousand times shorter than the error bound (marching cubes
     * leave clusters of vertices 1e-6 apart around grid points where the
     * field is nearly zero, their triangles folded every way) are below
     * anything the mesh can show, but the sizing would see their folds
     * and grade balls down to their size all around: a sheet gyroid's 18
     * such clusters made 264,000 balls for 52,000 predicted. Collapsed,
     * keeping the surface manifold; said so. */
    if (opt.max_error > 0 && !opt.keep_short_edges) {
        const double eps = VC_MESH_SHORT_EDGE * error_bound_of(s, opt.max_error);
        if (vc_surface_has_edge_shorter(s, eps)) {
            if ((rc = copy_surface_own(s, &collapsed, err)) != 0)
                goto fail;
            const int64_t nc =
                vc_surface_collapse_short_edges(&collapsed, 0, eps, &out->short_collapse_move);
            if (nc < 0) {
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                goto fail;
            }
            if (nc > 0) {
                out->n_short_collapsed = nc;
                if ((rc = adopt_repair(&s, &s_input, &collapsed, &out->input, err)) != 0)
                    goto fail;
                vc_log(opt.log, VC_LOG_INFO,
                       "mesh: %s: %lld edges shorter than %.3g (%g of the error bound) collapsed; "
                       "the surface moved by at most %.3g", name, (long long)nc, eps,
                       VC_MESH_SHORT_EDGE, out->short_collapse_move);
            }
        }
    }
    /* And it can bound a volume: no repeated or zero-area triangle, no
     * self-intersection, a volume (before sampling, which would not end). */
    {
        vc_solid_report solid;
        check_progress(&opt, &t_line, name, "repeated triangles, self-intersections, volume");
        rc = vc_surface_check_solid(s, &out->input, &solid, err);
        /* A surface whose only fault is that it runs through itself (a box
         * through a box) bounds the region it winds around at least once:
         * with opt.self_union (the default since session 30, when cow.off's
         * union meshed once its turned-over needles were flipped), that
         * union is meshed. */
        if (rc == VC_EINPUT && opt.self_union && solid.n_self_intersections > 0 && solid.n_zero_area == 0 &&
            solid.n_repeated_same == 0 && !(solid.coordinate_ratio > VC_SOLID_MAX_COORDINATE_RATIO)) {
            const double volume_before = out->input.volume;
            /* cut and triangulated in the order of its geometry, so that
             * the union does not depend on the input's numbering */
            vc_surface ordered;
            if ((rc = vc_surface_canonical_order(s, &ordered, NULL, NULL, err)) != 0) {
                rc = named(err, name, NULL);
                goto fail;
            }
            rc = vc_surface_self_union(&ordered, name, &unioned, &out->self_union, err);
            vc_surface_free(&ordered);
            if (rc)
                goto fail;
            if ((rc = open_pinches(&unioned, name, &opt, -2, &union_opened, &out->pinches, err)) != 0)
                goto fail;
            s = union_opened.xyz ? &union_opened : &unioned;
            s_input = s;
            out->unioned = 1;
            if ((rc = vc_surface_check(s, &out->input, err)) != 0)
                goto fail;
            /* Its cut points are rounded off their triangles' planes by an
             * ulp: pieces of one triangle, or along a curve, may then touch
             * within rounding, which the strict test reports; the other
             * checks must pass. */
            vc_solid_report after;
            rc = vc_surface_check_solid(s, &out->input, &after, err);
            if (rc == VC_EINPUT && after.n_self_intersections > 0 && after.n_zero_area == 0 &&
                after.n_repeated_same == 0 && after.volume_ratio > VC_SOLID_MIN_VOLUME_RATIO)
                rc = 0;
            if (rc == VC_EINPUT) {
                char why[VC_ERROR_LEN];
                snprintf(why, sizeof why, "%s", err->msg);
                rc = vc_error_set(err, VC_EINPUT, "%s: the union of the self-intersecting surface is not a "
                                  "valid solid (%s); repair the input (a boolean union, or remesh)",
                                  name, why);
            }
            if (rc)
                goto fail;
            vc_log(opt.log, VC_LOG_WARNING,
                   "mesh: %s intersects itself (%lld pairs of triangles): meshing the union of its "
                   "parts (%lld triangles cut, %lld of %lld patches inside another part dropped, %lld "
                   "short edges collapsed; volume %.6g, the signed sum was %.6g)",
                   name, (long long)out->self_union.n_pairs, (long long)out->self_union.n_split,
                   (long long)out->self_union.n_patches_dropped, (long long)out->self_union.n_patches,
                   (long long)out->self_union.n_collapsed,
                   out->self_union.volume, volume_before);
            if (out->pinches.n_pinches > 0)
                vc_log(opt.log, VC_LOG_INFO,
                       "mesh: %s: the union's %lld pinch vertices (sheets touching at a point) opened: "
                       "the surface moved by at most %.3g (%.2g of the error bound)", name,
                       (long long)out->pinches.n_pinches, out->pinches.max_move,
                       out->pinches.max_move / error_bound_of(s, opt.max_error));
        }
        if (rc)
            goto fail;
    }
    /* A size the sampling and the engine handle in double precision: their
     * squared distances and volumes (a size cubed) must stay normal
     * numbers, as vc_voronoi_build requires of the seeds' extent. */
    {
        const double *b = out->input.bbox;
        const double dx = b[3] - b[0], dy = b[4] - b[1], dz = b[5] - b[2];
        const double size = fmax(dx, fmax(dy, dz));
        if (!(size >= VC_MESH_MIN_SIZE && size <= VC_MESH_MAX_SIZE)) {
            rc = vc_error_set(err, VC_EINPUT,
                              "%s: the model's size (%g) is outside what the mesher handles in "
                              "double precision (%g to %g): scale it (the mesh scales with it)",
                              name, size, VC_MESH_MIN_SIZE, VC_MESH_MAX_SIZE);
            goto fail;
        }
    }

    /* Far from the origin (a model in UTM coordinates: 4e6 away, 4e3 wide),
     * every stage would compute with coordinates that carry the offset's
     * magnitude and lose its digits at the mesh's scale (the Voronoi engine
     * then fails on a layered basin). The pipeline runs on the model moved
     * to its box's centre, and the results are moved back at the end. */
    double shift[3] = {0, 0, 0};
    if ((rc = centre_far_model(s, out->input.bbox, &centred, shift, err)) != 0)
        goto fail;
    if (centred.xyz) {
        s = &centred;
        s_input = &centred;
        vc_log(opt.log, VC_LOG_INFO, "mesh: the model lies %.3g of its size from the origin: "
               "meshed about its centre (%.17g, %.17g, %.17g)",
               sqrt(shift[0] * shift[0] + shift[1] * shift[1] + shift[2] * shift[2]) /
                   far_size(out->input.bbox), shift[0], shift[1], shift[2]);
    }

    /* The regions of its arrangement: one solid as its orientation defines
     * it (each region inside or outside, every triangle between the two)
     * takes the single-material path, where the ball normals tell inside
     * from outside; several materials (an interface with a region on both
     * sides, nested shells of the same orientation, triangles given twice)
     * label every seed with its region (pipeline/materials.c). With
     * opt.cavities, nested shells are reoriented by the even-odd rule. */
    {
        vc_regions regions;
        check_progress(&opt, &t_line, name, "regions");
        if ((rc = vc_surface_regions(s, &regions, err)) != 0) {
            rc = named(err, name, NULL);
            goto fail;
        }
        if (opt.cavities) {
            unsigned char *flip = malloc((size_t)s->n_triangles + 1);
            const int64_t n_flipped = flip ? vc_regions_even_odd_flips(&regions, flip) : 0;
            if (!flip)
                rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            else if (n_flipped < 0)
                rc = vc_error_set(err, VC_EINPUT,
                                  "%s: --cavities needs closed shells, each a 2-manifold of its "
                                  "own; this surface has edges of more than two triangles (an "
                                  "interface between materials)", name);
            else if (n_flipped > 0 && (rc = reversed_copy(s, flip, &oriented, err)) == 0) {
                /* sampled without the groups, as before (the boundary
                 * patches still come from s_input's) */
                oriented.tri_group = NULL;
                oriented.n_groups = 0;
                oriented.group_name = NULL;
            }
            free(flip);
            if (rc) {
                vc_regions_free(&regions);
                goto fail;
            }
            if (n_flipped > 0) {
                vc_log(opt.log, VC_LOG_INFO,
                       "mesh: %lld of %lld surface components reversed: nested shells "
                       "alternate solid and cavity (--cavities)",
                       (long long)n_flipped, (long long)regions.n_components);
                s = &oriented;
                vc_regions_free(&regions);
                if ((rc = vc_surface_regions(s, &regions, err)) != 0) {
                    rc = named(err, name, NULL);
                    goto fail;
                }
            }
        }
        /* A shell whose normals point in with nothing around it, next to
         * one that points out, is no cavity of anything: a part of an
         * assembly exported inside out. Reversed (with --cavities the
         * even-odd rule above did so already). A model all inside out is
         * one solid oriented inward, meshed as it is. */
        if (!opt.cavities) {
            const int64_t n_inside_out = vc_regions_inside_out_flips(&regions, NULL);
            if (n_inside_out > 0) {
                unsigned char *flip = malloc((size_t)s->n_triangles + 1);
                if (!flip) {
                    rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
                    vc_regions_free(&regions);
                    goto fail;
                }
                vc_regions_inside_out_flips(&regions, flip);
                const int64_t n_components = regions.n_components;
                rc = reversed_copy(s, flip, &turned_out, err);
                free(flip);
                vc_regions_free(&regions);
                if (rc)
                    goto fail;
                vc_log(opt.log, VC_LOG_WARNING,
                       "mesh: %s: %lld of its %lld surface components were inside out (normals "
                       "pointing in, nothing around them): reversed", name, (long long)n_inside_out,
                       (long long)n_components);
                s = &turned_out;
                s_input = &turned_out;
                if ((rc = vc_surface_check(s, &out->input, err)) != 0 ||
                    (rc = vc_surface_regions(s, &regions, err)) != 0) {
                    rc = named(err, name, NULL);
                    goto fail;
                }
            }
        }
        const int one = vc_regions_single_solid(&regions);
        out->n_regions = regions.n_regions;
        if (regions.n_walls > 0) {
            const int64_t t = regions.first_wall, r = regions.side_region[2 * t];
            rc = vc_error_set(err, VC_EINPUT,
                              "%s: %lld triangles have %s on both sides (first: triangle %lld): "
                              "a wall of zero thickness bounds no volume; remove it or give it "
                              "a thickness", name, (long long)regions.n_walls,
                              r < 0 ? "the outside" : "the same region", (long long)t + 1);
            vc_regions_free(&regions);
            goto fail;
        }
        /* a triangle given twice (reversed) is sampled once: the regions
         * label the seeds */
        if (!one || regions.n_twice > 0) {
            /* several materials, interfaces, inclusions: every seed is
             * labelled with its region */
            if (opt.smooth_iterations > 0) {
                rc = vc_error_set(err, VC_EPARAM,
                                  "%s: --smooth-iterations would move the interfaces between "
                                  "this surface's %lld regions: not with several materials",
                                  name, (long long)regions.n_regions);
                vc_regions_free(&regions);
                goto fail;
            }
            if ((rc = vc_materials_init(s, &regions, &mm, err)) != 0) {
                rc = named(err, name, NULL);
                vc_regions_free(&regions);
                goto fail;
            }
            out->multi_material = 1;
            vc_log(opt.log, VC_LOG_INFO,
                   "mesh: %lld regions (%lld triangles between two of them): every seed "
                   "labelled with its region", (long long)regions.n_regions,
                   (long long)regions.n_interface);
        }
        vc_regions_free(&regions);
    }
    /* One solid is sampled in an order that depends on its geometry
     * alone: the sampling follows the triangles' and vertices' order, and
     * one solid exported by two programs must mesh the same. (Several
     * materials keep the input's order, which numbers their regions as
     * `vorocrust info` does; reoriented cavities too, sampled without the
     * groups s_input keeps in the input's order.) */
    const int canonical_order = !out->multi_material && s == s_input;
    if (canonical_order) {
        input_triangle = malloc(sizeof(int64_t) * (size_t)(s->n_triangles + 1));
        input_vertex = malloc(sizeof(int64_t) * (size_t)(s->n_vertices + 1));
        if (!input_triangle || !input_vertex) {
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", name);
            goto fail;
        }
        if ((rc = vc_surface_canonical_order(s, &canonical, input_triangle, input_vertex, err)) != 0) {
            rc = named(err, name, NULL);
            goto fail;
        }
        s = &canonical;
        s_input = &canonical;
    }
    if ((rc = sample(out->multi_material ? &mm.surface : s, &opt, name,
                     out->multi_material ? &mm : NULL, out, err)) != 0)
        goto fail;
    /* the balls' corner vertices and triangles in the numbering the
     * surface had (a smoothed surface has its own) */
    if (canonical_order && out->smooth_iterations == 0)
        for (int64_t i = 0; i < out->balls.n; i++) {
            int64_t *e = &out->balls.element[i];
            if (out->balls.kind[i] == VC_BALL_CORNER)
                *e = input_vertex[*e];
            else if (out->balls.kind[i] == VC_BALL_SURFACE)
                *e = input_triangle[*e];
        }
    /* the boundary patches: each boundary face takes its input group */
    if (out->has_mesh && opt.patches != VC_PATCHES_NONE &&
        (rc = boundary_patches(s_input, &opt, name, out, err)) != 0)
        goto fail;
    out->time.features = out->sampling.t_features;
    out->time.sizing = out->sampling.t_sizing;
    out->time.corners = out->sampling.t_corners;
    out->time.edges = out->sampling.t_edges;
    out->time.surface = out->sampling.t_surface;
    out->time.lipschitz = out->sampling.t_lipschitz;
    out->time.slivers = out->sampling.t_slivers;

    vc_surface_quality_compute(&out->surface, &out->surface_quality);
    out->surface_volume = out->multi_material ? outer_volume(&out->mesh, &out->surface)
                                              : vc_polysurface_volume(&out->surface);
    /* the reconstructed surface's distance to the surface meshed: more
     * than twice the error bound is a wrong result (the sampling holds it
     * within the bound; the tests within 5/4 of it) */
    if ((rc = surface_distance(s, &out->surface, opt.threads, &out->surface_distance, err)) != 0) {
        rc = named(err, name, NULL);
        goto fail;
    }
    const double bound = error_bound_of(s, opt.max_error);
    if (out->smooth_iterations == 0 && bound > 0 &&
        !(out->surface_distance.distance <= SURFACE_DISTANCE_BOUNDS * bound)) {
        rc = vc_error_set(err, VC_EINPUT,
                          "%s: the reconstructed surface lies %g from the input (%.3g%% of its "
                          "diagonal), more than %g times the error bound %g: the mesh is wrong; "
                          "try a smaller --max-error",
                          name, out->surface_distance.distance,
                          100 * out->surface_distance.normalised, (double)SURFACE_DISTANCE_BOUNDS,
                          bound);
        goto fail;
    }
    /* one solid: its volume against the input's, as every region's is
     * (check_regions); not after Loop smoothing, asked for (or by
     * --fallback), which moves the surface off the input by design */
    const double meshed_volume = fabs(vc_surface_signed_volume(s)); /* reoriented, unioned */
    if (!out->multi_material && out->smooth_iterations == 0 && meshed_volume > 0) {
        const double rel = out->surface_volume / meshed_volume - 1;
        if (!(fabs(rel) <= REGION_VOLUME_TOL)) {
            rc = vc_error_set(err, VC_EINPUT,
                              "%s: the reconstructed surface encloses %g, the input %g (%+.2f%%, "
                              "more than %g%% off): the mesh is wrong; try a smaller --max-error",
                              name, out->surface_volume, meshed_volume, 100 * rel,
                              100 * REGION_VOLUME_TOL);
            goto fail;
        }
    }
    if (centred.xyz)
        move_results(out, shift);
    out->time.total = now() - t0;
    done = 1;
fail:
    free(oriented.tri);
    vc_materials_free(&mm);
    free_centred(&centred);
    free(consistent.tri); /* the rest is borrowed */
    free(repaired.tri);
    free(opened.xyz);
    free(opened.tri);
    free(union_opened.xyz);
    free(union_opened.tri);
    vc_surface_free(&unioned);
    vc_surface_free(&canonical);
    free(collapsed.xyz);
    free(collapsed.tri);
    free(collapsed.tri_group);
    free(hairpinned.xyz);
    free(hairpinned.tri);
    free(hairpinned.tri_group);
    vc_surface_free(&welded);
    vc_surface_free(&needled);
    free(capped.tri);
    free(capped_group);
    free(turned_out.tri);
    free(input_triangle);
    free(input_vertex);
    if (done)
        return 0;
    vc_mesh_result_free(out);
    return rc ? rc : VC_EINTERNAL;
}
