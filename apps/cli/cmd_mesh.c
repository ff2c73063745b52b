/* vorocrust mesh: VoroCrust surface sampling of a closed triangle surface,
 * its seeds, the reconstructed surface and (without --surface-only) the
 * Voronoi mesh of the inside seeds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli_log.h"
#include "cli_util.h"
#include "commands.h"
#include "mpi_session.h"
#include "vorocrust/smoothing.h"
#include "vorocrust/vorocrust.h"

/* The OpenFOAM case gets its skew faces collapsed down to this skewness by
 * default: checkMesh fails above 4, and a margin keeps versions of OpenFOAM
 * that round differently on the right side. */
#define FOAM_DEFAULT_MAX_SKEW 3.5
#define FOAM_COLLAPSE_ROUNDS 60
/* checkMesh fails a mesh with a face more skew than this */
#define CHECKMESH_MAX_SKEW 4
/* input surfaces of one run (closed surfaces that share interfaces) */
#define MAX_INPUTS 64
#define MAX_PATCH_TYPES 64

static void usage(FILE *f)
{
    vc_sampling_options d;
    vc_sampling_options_default(&d);
    fprintf(f,
        "usage: vorocrust mesh INPUT... (--surface-only --surface OUT.obj | -o OUT.vtu) [options]\n"
        "  INPUT...            closed triangle surface: .obj, .off, .stl, .ply; several files\n"
        "                      are one surface (closed surfaces sharing interfaces: each\n"
        "                      region, in file order, gets its own cells, label N)\n"
        "  --surface-only      stop after the surface: sampling, seeds, reconstructed surface\n"
        "  --surface OUT       the reconstructed surface: OBJ polygons, or VTK_POLYGON cells\n"
        "                      when OUT ends in .vtu\n"
        "  -o, --output OUT.vtu  the volume mesh: the Voronoi cells of the inside surface seeds\n"
        "                      and the interior seeds; and OUT_boundary.vtu, its boundary\n"
        "                      faces with their patch and region\n"
        "  --foam CASE_DIR     also write the volume mesh as OpenFOAM CASE_DIR/constant/polyMesh\n"
        "  --connections OUT.csv  with -o: the interior faces of the volume mesh (cells, seeds,\n"
        "                      area, seed distance, centroid, normal), as 'vorocrust voronoi'\n"
        "  --uge OUT.uge       with -o: a PFLOTRAN explicit unstructured grid, and one\n"
        "                      OUT_PATCH.ex boundary-connection file per patch\n"
        "  --tough MESH        with -o: a TOUGH2/TOUGH3 MESH file (ELEME, CONNE; boundary\n"
        "                      elements of volume 1e50 per patch)\n"
        "  --patches groups|features|none  boundary patches from the input's groups (OBJ g/o/\n"
        "                      usemtl, STL solids, one per input file; default), from its\n"
        "                      sharp-feature patches (patch1, patch2, ...), or one: surface\n"
        "  --patch-type NAME=TYPE  the OpenFOAM type of patch (or group) NAME: patch, wall,\n"
        "                      symmetryPlane, symmetry, empty (repeatable; default: patch, and\n"
        "                      wall for the one patch of a surface without groups)\n"
        "  --foam-max-skew S   before writing the OpenFOAM case, collapse the faces whose\n"
        "                      checkMesh skewness exceeds S (default %g, 4 with --unskew; 0:\n"
        "                      write the exact Voronoi cells; checkMesh fails a mesh above 4)\n"
        "  --interior octree|lattice|none  interior seeds: graded by a p4est octree (default),\n"
        "                      on a cubic lattice, or none\n"
        "  --interior-spacing H  lattice spacing (default: the largest ball radius)\n"
        "  --lloyd N           N iterations of Lloyd relaxation of the interior seeds, 0 to\n"
        "                      1000 (default 0); the surface seeds stay fixed\n"
        "  --protect E         no short edges: pole seeds under the balls, and the interior\n"
        "                      seeds at short Voronoi edges moved a little until every edge\n"
        "                      at their vertices is at least E times the cell's radius,\n"
        "                      0 <= E < 0.25 (0.01 recommended; default 0: off; about\n"
        "                      doubles the run's time)\n"
        "  --unskew S          checkMesh's failures mended at the seeds: the interior seeds\n"
        "                      of faces above skewness S (or below checkMesh's weight or\n"
        "                      volume ratio) and of concave cells move a little and the\n"
        "                      cells are built again (3.9 recommended; default 0: off)\n"
        "  --quartet-gap G     experimental: sliver elimination also shrinks a ball whose\n"
        "                      sphere passes within a power gap G of a seed (a near-quartet\n"
        "                      of balls: two near-coincident seeds), 0 <= G < 1 (default 0)\n"
        "  --seeds OUT.csv     the seeds (x,y,z,label: 1 inside, 0 outside)\n"
        "  --balls OUT.csv     the balls (x,y,z,radius,kind,element,nx,ny,nz)\n"
        "  --sharp-angle DEG   theta_sharp, 0 < DEG < 180 (default %g)\n"
        "  --smooth-iterations N  rounds of adaptive, feature-preserving Loop subdivision\n"
        "                      of the patches before sampling, 0 to %d (default 0; the\n"
        "                      thesis uses %d, but Loop moves the surface off the input)\n"
        "  --max-error E       approximation error bound, a fraction of the bounding-box\n"
        "                      diagonal, 0 <= E < 1 (default %g; 0: none, as in the thesis)\n"
        "  --denoise auto|on|off  noise at the error bound: sample a copy of the input\n"
        "                      smoothed within half the bound (Taubin), within the other\n"
        "                      half; auto (default): on a rough input (over 1%% of its\n"
        "                      vertices with a triangle normal 20 degrees off their mean)\n"
        "                      when the sizing predicts that it would take at least 1.5\n"
        "                      times the copy's balls, or when sliver elimination\n"
        "                      diverges on the input\n"
        "  --smooth-width K    experimental: centre the surface balls on a smooth surface\n"
        "                      near the input (moving least squares, kernel K times the\n"
        "                      error bound; 4 is a good start) instead of on its facets,\n"
        "                      so that folds between facets do not defeat sliver\n"
        "                      elimination; slower (default 0: off)\n"
        "  --curvature-factor C  with --smooth-width: radii at most C times the smooth\n"
        "                      surface's radius of curvature (default 0.2)\n"
        "  --keep-short-edges  keep the input's edges shorter than 1e-3 of the error bound\n"
        "                      (default: collapse them, said so; marching cubes leave\n"
        "                      clusters of such edges whose folds would set the sizing)\n"
        "  --no-lift           keep the surface ball centres on the input (default: move\n"
        "                      them off it by the mean sag of their reconstructed facets,\n"
        "                      which removes the chords' volume bias)\n"
        "  --lipschitz L       0 < L < 1 (default %g)\n"
        "  --max-size H        largest ball radius and cap of the octree sizing (default:\n"
        "                      the bounding-box diagonal)\n"
        "  --seed N            random seed (default %llu)\n"
        "  --max-balls N       refuse a sampling predicted to need more balls, and stop one\n"
        "                      that reaches N (default: what this machine's memory holds)\n"
        "  --threads N         threads, 1 to 4096 (default: all cores)\n"
        "  --quiet             no progress and no summary on stderr\n"
        "  --verbose           also the phase timings on stderr: each sampling pass (its\n"
        "                      shrinks and resampling), the Voronoi engine's phases\n"
        "  --cavities          nested closed shells alternate solid and cavity (the\n"
        "                      outermost solid), whatever their orientation\n"
        "  --no-union          refuse a surface that intersects itself (default: mesh the\n"
        "                      union of its parts, the region it winds around at least\n"
        "                      once, with a warning; --union, the default, is accepted)\n"
        "  --fallback          when sliver elimination diverges, sample again at theta_sharp\n"
        "                      20 (folds become creases), then after %d rounds of Loop\n"
        "                      smoothing at 120 (moves the surface); instead of the default\n"
        "  --no-fold-creases   when sliver elimination diverges (on the denoised copy, or\n"
        "                      on the input with --denoise off), stop with an error (default:\n"
        "                      make the folds over 10 degrees where it is stuck creases and\n"
        "                      sample again, up to 4 times, then all such folds; the surface\n"
        "                      is not moved; --fold-creases, the default, is accepted)\n",
        FOAM_DEFAULT_MAX_SKEW, d.sharp_angle, VC_SMOOTH_MAX_ITERATIONS, VC_SMOOTH_DEFAULT_ITERATIONS, d.max_error,
        d.lipschitz, (unsigned long long)d.seed, VC_SMOOTH_DEFAULT_ITERATIONS);
}

static int takes_value(const char *a)
{
    static const char *const with_value[] = {"-o", "--output", "--surface", "--seeds", "--balls",
                                             "--sharp-angle", "--max-error", "--lipschitz", "--smooth-width", "--curvature-factor",
                                             "--max-size", "--seed", "--threads", "--interior", "--smooth-iterations",
                                             "--interior-spacing", "--foam", "--lloyd", "--protect", "--unskew", "--quartet-gap", "--denoise",
                                             "--foam-max-skew", "--connections", "--max-balls", "--uge", "--tough",
                                             "--patch-type", "--patches"};
    for (size_t i = 0; i < sizeof with_value / sizeof *with_value; i++)
        if (!strcmp(a, with_value[i]))
            return 1;
    return 0;
}

/* The summary on stderr: what the run did, its figures and times. */
static void print_summary(const char *in_path, int64_t n_input_triangles,
                          const vc_mesh_options *opt, const vc_mesh_result *r, int foam_collapsed, double foam_max_skew,
                          const vc_skew_collapse_stats *foam_skew, double t_read,
                          double t_write_surface, double t_write_mesh, double t_total)
{
    const vc_sampling_stats *st = &r->sampling;
    const vc_polysurface_topology *topo = &r->surface_topology;
    const vc_surface_quality *sq = &r->surface_quality;
    const vc_mesh_times *t = &r->time;
    char retry_note[64] = "", failed_time[64] = "";
    if (r->resampled) {
        snprintf(retry_note, sizeof retry_note, ", after sampling at %g diverged",
                 r->first_sharp_angle);
        snprintf(failed_time, sizeof failed_time, ", failed sampling at %g %.3f",
                 r->first_sharp_angle, t->failed_sampling);
    }
    char lift_note[200];
    if (opt->no_lift)
        snprintf(lift_note, sizeof lift_note, "off (--no-lift)");
    else if (st->lift_dropped)
        snprintf(lift_note, sizeof lift_note, "dropped (no lift held after %d checks): centres on "
                 "the input", st->lift_rounds);
    else
        snprintf(lift_note, sizeof lift_note, "%lld balls moved by %.3f of their radius on "
                 "average (largest %.3f), %lld lifts reduced, %d passes, %d checks, %.3f s",
                 (long long)st->n_lifted, st->lift_mean_rel, st->lift_max_rel,
                 (long long)st->n_lift_reduced, st->lift_passes, st->lift_rounds, st->t_lift);
    fprintf(stderr,
            "vorocrust mesh: %s (%lld triangles, %lld after %d smoothing rounds; sharp angle %g%s)\n"
            "  balls: %lld (corner %lld, edge %lld, surface %lld), %.3g predicted; shrunk for Lipschitz %lld, "
            "for slivers %lld in %d iterations%s, for flat facets %lld, for facets off the input %lld, at pinches %lld; "
            "half-covered seed pairs %lld\n"
            "  centre lift: %s\n"
            "  surface seeds: %lld (%lld inside, %lld outside)\n"
            "  surface: %lld vertices, %lld polygons, %lld edges, euler %lld (input %lld), "
            "%s, %lld components\n"
            "  surface quality: Q min %.3f mean %.3f; angles < 30 deg %.1f%%, > 90 deg %.1f%% "
            "(%lld triangles, polygons fanned from their centroid)\n"
            "  time (s): read %.3f, features and smoothing %.3f, sizing %.3f, corner protection %.3f, edge "
            "protection %.3f, surface coverage %.3f, Lipschitz fixes %.3f, sliver elimination "
            "%.3f, seeds %.3f, surface %.3f, write %.3f%s\n",
            in_path, (long long)n_input_triangles, (long long)r->n_sampled_triangles,
            r->smooth_iterations, r->sharp_angle, retry_note, (long long)r->balls.n,
            (long long)st->n_corner, (long long)st->n_edge, (long long)st->n_surface,
            st->n_balls_predicted, (long long)st->n_shrunk_lipschitz, (long long)st->n_shrunk_sliver,
            st->sliver_iterations, st->safe_mode ? " (safe mode)" : "",
            (long long)st->n_shrunk_flat, (long long)st->n_shrunk_deviation, (long long)st->n_shrunk_pinch,
            (long long)r->n_half_covered,
            lift_note,
            (long long)r->n_surface_seeds, (long long)r->n_inside_seeds,
            (long long)(r->n_surface_seeds - r->n_inside_seeds), (long long)topo->n_vertices,
            (long long)topo->n_faces, (long long)topo->n_edges, (long long)topo->euler,
            (long long)r->input.euler,
            r->multi_material
                ? (r->surface_closed ? "the regions' boundaries closed 2-manifolds, consistently "
                                       "oriented (the interfaces are non-manifold)"
                                     : "NOT every region's boundary a closed consistently "
                                       "oriented 2-manifold")
            : topo->n_boundary_edges == 0 && topo->n_nonmanifold_edges == 0 &&
                    topo->n_misoriented_edges == 0 && topo->n_nonmanifold_vertices == 0
                ? "closed 2-manifold, consistently oriented"
            : r->surface_closed ? "closed and consistently oriented, parts touching where the input's "
                                  "do (its non-manifold edges or vertices)"
                                : "NOT a closed consistently oriented 2-manifold",
            (long long)topo->n_components, sq->q_min,
            sq->q_mean, sq->pct_below_30, sq->pct_above_90, (long long)sq->n_triangles, t_read,
            t->features, t->sizing, t->corners, t->edges, t->surface, t->lipschitz, t->slivers,
            t->seeds, t->reconstruct, t_write_surface, failed_time);
    if (r->surface_distance.n_samples_a > 0)
        fprintf(stderr,
                "  surface distance: %.3g to the input, two-sided Hausdorff (%.3f%% of its "
                "diagonal; input to surface %.3g, surface to input %.3g; sampled within %.2g)\n",
                r->surface_distance.distance, 100 * r->surface_distance.normalised,
                r->surface_distance.a_to_b, r->surface_distance.b_to_a,
                r->surface_distance.error_bound);
    if (r->denoise.used) {
        const double bound = r->denoise.bound + r->denoise.moved.max_move;
        fprintf(stderr,
                "  denoised copy sampled: vertices moved at most %.3g (%.2f of the error bound), "
                "%.3g on average; the copy's error bound %.3g; balls predicted for the input %.3g, "
                "for the copy %.3g; %.3f s\n",
                r->denoise.moved.max_move, bound > 0 ? r->denoise.moved.max_move / bound : 0,
                r->denoise.moved.mean_move, r->denoise.bound, r->denoise.n_input,
                r->denoise.n_denoised, t->denoise);
    }
    for (int64_t k = 0; r->multi_material && k < r->n_regions; k++) {
        const vc_region_mesh *g = &r->region_mesh[k];
        if (g->label == 0) {
            fprintf(stderr, "  region %lld: a void (its boundary faces inward), no cells, "
                    "volume %.12g\n", (long long)k + 1, g->input_volume);
            continue;
        }
        fprintf(stderr,
                "  region %lld: %lld cells, volume %.12g (input %.12g, %+.3f%%), %lld boundary "
                "faces, %lld interface faces, euler %lld (input %lld)\n",
                (long long)k + 1, (long long)g->n_cells, g->mesh_volume, g->input_volume,
                100.0 * (g->mesh_volume - g->input_volume) / g->input_volume,
                (long long)g->n_boundary_faces, (long long)g->n_interface_faces,
                (long long)g->topology.euler, (long long)g->euler_input);
    }
    if (opt->surface_only)
        return;
    const vc_octree_stats *ost = &r->octree;
    if (opt->interior == VC_INTERIOR_OCTREE)
        fprintf(stderr,
                "  interior: octree of %lld leaves (%lld before the 2:1 balance; %lld "
                "trees, levels %d to %d), %lld interior seeds (leaves left out: %lld in or "
                "next to a ball, %lld outside, %lld next to a surface or sphere seed), and %lld sphere "
                "seeds, %.3f s\n",
                (long long)ost->n_leaves, (long long)ost->n_refined_leaves,
                (long long)ost->n_trees, ost->min_level, ost->max_level,
                (long long)ost->n_seeds, (long long)ost->n_covered, (long long)ost->n_outside,
                (long long)ost->n_near_seed, (long long)r->n_sphere_seeds, t->interior);
    else
        fprintf(stderr, "  interior: %s, %lld interior seeds (%lld sphere seeds), %.3f s\n",
                opt->interior == VC_INTERIOR_LATTICE ? "lattice" : "none",
                (long long)r->n_interior_seeds, (long long)r->n_sphere_seeds, t->interior);
    const vc_lloyd_stats *lst = &r->lloyd;
    if (opt->lloyd_iterations > 0)
        fprintf(stderr,
                "  Lloyd: %d iterations%s, last one moved %lld seeds (%lld stayed: "
                "next to the surface, or centroid in a ball or outside), shift / cell "
                "size mean %.3g max %.3g, %.3f s\n",
                lst->iterations,
                lst->reverted ? " (the next one was undone: its mesh failed the validator)" : "",
                (long long)lst->n_moved, (long long)lst->n_refused, lst->mean_shift,
                lst->max_shift, t->lloyd);
    const vc_protect_stats *pst = &r->protect;
    if (opt->protect_edge > 0 && r->n_interior_seeds > 0)
        fprintf(stderr,
                "  short-edge protection: %lld of %lld interior seeds with an edge below %g of "
                "their cell's radius, %lld after %lld moves of %lld seeds in %d rounds (%lld "
                "cells measured); shortest %.3g (before %.3g); %.3f s\n",
                (long long)pst->n_short_before, (long long)pst->n_checked, opt->protect_edge,
                (long long)pst->n_short_after, (long long)pst->n_moves, (long long)pst->n_moved,
                pst->rounds, (long long)pst->n_measures, pst->min_edge_after,
                pst->min_edge_before, t->protect);
    const vc_unskew_stats *ust = &r->unskew;
    if (opt->unskew > 0 && r->n_interior_seeds > 0)
        fprintf(stderr,
                "  skew faces: %lld above %g (max %.3g), %lld of small weight or volume ratio, "
                "%lld concave cells; %lld interior seeds moved in %d rounds (%lld cells built to "
                "judge the places); %.3f s\n",
                (long long)ust->n_skew_faces, opt->unskew, ust->max_skew,
                (long long)ust->n_weak_faces, (long long)ust->n_concave_cells,
                (long long)ust->n_moved, r->unskew_rounds, (long long)ust->n_cells_built, t->unskew);
    const vc_polymesh *m = &r->mesh;
    /* several materials: the input's volume is its material regions' */
    double input_volume = r->input.volume;
    if (r->multi_material) {
        input_volume = 0;
        for (int64_t k = 0; k < r->n_regions; k++)
            if (r->region_mesh[k].label)
                input_volume += r->region_mesh[k].input_volume;
    }
    fprintf(stderr,
            "  volume mesh: %lld cells (%lld interior seeds), volume %.12g (reconstructed "
            "surface %.12g, input %.12g), %.3f s (cells %.3f, checks and quality %.3f, "
            "writing %.3f); %lld faces (%lld interior, %lld boundary), %lld vertices\n",
            (long long)m->n_cells, (long long)r->n_interior_seeds, r->mesh_volume,
            r->surface_volume, input_volume, t->voronoi + t->quality + t_write_mesh, t->voronoi,
            t->quality, t_write_mesh,
            (long long)m->n_faces, (long long)m->n_interior_faces,
            (long long)(m->n_faces - m->n_interior_faces), (long long)m->n_points);
    {
        /* the boundary patches, as every writer names them */
        vc_boundary_patches bp;
        if (vc_polymesh_boundary_patches(m, &bp, NULL) == 0) {
            fprintf(stderr, "  boundary patches: %d", bp.n_patches);
            for (int k = 0; k < bp.n_patches; k++) {
                double area = 0;
                for (int64_t f = m->n_interior_faces; f < m->n_faces; f++)
                    if (bp.face_patch[f - m->n_interior_faces] == k)
                        area += m->face_area[f];
                fprintf(stderr, "%s %s (%lld faces, area %.6g)", k ? "," : ":", bp.name[k],
                        (long long)bp.size[k], area);
            }
            fprintf(stderr, "\n");
            vc_boundary_patches_free(&bp);
        }
    }
    const vc_cell_quality *q = &r->cell_quality;
    fprintf(stderr,
            "  cell quality: volume min %.6g max %.6g; fatness max %.3f mean %.3f "
            "(interior cells: max %.3f mean %.3f); shortest edge / enclosing radius "
            "min %.3g%s\n",
            q->volume_min, q->volume_max, q->fatness_max, q->fatness_mean,
            q->interior_fatness_max, q->interior_fatness_mean, q->shortest_edge_rel_min,
            q->n_unmeasured ? " (some cells could not be measured)" : "");
    fprintf(stderr, "  cell order: reverse Cuthill-McKee, matrix bandwidth %lld (%lld in seed "
            "order)\n", (long long)r->cell_bandwidth, (long long)r->cell_bandwidth_engine);
    fprintf(stderr,
            "  solver measures: shortest edge / enclosing radius p1 %.3g, %.1f%% of the cells "
            "below 1e-2; smallest face / radius^2 min %.3g p1 %.3g; seed distance / cell radius "
            "min %.3g p1 %.3g; non-orthogonality max %.1f average %.1f degrees; skewness max %.2f "
            "(%lld faces above 4)\n",
            q->shortest_edge_rel_p1, 100.0 * q->short_edge_share, q->small_face_rel_min,
            q->small_face_rel_p1, q->connection_rel_min, q->connection_rel_p1,
            q->non_orthogonality_max, q->non_orthogonality_mean, q->skewness_max,
            (long long)q->n_skew_faces);
    if (foam_collapsed)
        fprintf(stderr,
                "  OpenFOAM case: %lld faces collapsed in %d rounds (skewness above %g, "
                "%lld of them to make room), largest point move %.3g; max skewness "
                "%.3f before, %.3f after (%lld faces above %g left)\n",
                (long long)foam_skew->n_collapsed, foam_skew->n_rounds, foam_max_skew,
                (long long)foam_skew->n_made_room, foam_skew->max_move,
                foam_skew->max_skew_before, foam_skew->max_skew_after,
                (long long)foam_skew->n_skew_left, foam_max_skew);
    fprintf(stderr, "  total: %.3f s, peak memory %.1f MiB\n", t_total, vc_cli_peak_mib());
}

/* OUT.vtu -> OUT_boundary.vtu (malloc'd). */
static char *boundary_path(const char *out)
{
    size_t n = strlen(out);
    const char *slash = strrchr(out, '/');
    const char *dot = strrchr(out, '.');
    if (dot && (!slash || dot > slash))
        n = (size_t)(dot - out);
    char *p = malloc(n + 16);
    if (p)
        snprintf(p, n + 16, "%.*s_boundary.vtu", (int)n, out);
    return p;
}

/* The input surfaces as one: each read (and named in its errors), then
 * joined with their common vertices merged (vc_surface_concat). */
static int read_inputs(const char *const *paths, int n, vc_surface *out, vc_error *err)
{
    if (n == 1)
        return vc_surface_read(paths[0], out, NULL, err);
    vc_surface parts[MAX_INPUTS];
    memset(parts, 0, sizeof parts);
    /* a file without groups of its own is one group: its name's stem */
    char stem[MAX_INPUTS][64];
    const char *names[MAX_INPUTS];
    for (int i = 0; i < n; i++) {
        const char *b = strrchr(paths[i], '/');
        b = b ? b + 1 : paths[i];
        const char *dot = strrchr(b, '.');
        const int len = dot && dot > b ? (int)(dot - b) : (int)strlen(b);
        snprintf(stem[i], sizeof stem[i], "%.*s", len < 63 ? len : 63, b);
        names[i] = stem[i];
    }
    int rc = 0;
    for (int i = 0; i < n && !rc; i++)
        rc = vc_surface_read(paths[i], &parts[i], NULL, err);
    if (!rc)
        rc = vc_surface_concat(parts, n, names, out, err);
    for (int i = 0; i < n; i++)
        vc_surface_free(&parts[i]);
    return rc;
}

/* the keep-alive of the run (vorocrust/log.h): a static, so that
 * vc_cmd_mesh stops it whichever way run_mesh returns */
static vc_log_keepalive *keepalive;

static int run_mesh(int argc, char **argv)
{
    const char *inputs[MAX_INPUTS];
    int n_inputs = 0;
    vc_foam_patch_type patch_type[MAX_PATCH_TYPES];
    char patch_type_text[MAX_PATCH_TYPES][128];
    int n_patch_types = 0;
    const char *in_path = NULL, *surf_path = NULL, *out_path = NULL, *seeds_path = NULL,
               *balls_path = NULL, *foam_path = NULL, *conn_path = NULL, *uge_path = NULL,
               *tough_path = NULL;
    int surface_only = 0, curvature_given = 0, quiet = 0, verbose = 0, fold_creases = 1, fallback = 0,
        smooth_iterations_given = 0;
    double foam_max_skew = FOAM_DEFAULT_MAX_SKEW;
    int foam_max_skew_given = 0;
    vc_skew_collapse_stats foam_skew;
    memset(&foam_skew, 0, sizeof foam_skew);
    vc_mesh_options opt;
    vc_mesh_options_default(&opt);
    vc_cli_seen seen = {{NULL}, 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--patch-type") && vc_cli_repeated(&seen, "vorocrust", "vorocrust mesh", a))
            return 2;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--surface-only")) {
            surface_only = 1;
        } else if (!strcmp(a, "--keep-short-edges")) {
            opt.keep_short_edges = 1;
        } else if (!strcmp(a, "--no-lift")) {
            opt.no_lift = 1;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(a, "--verbose")) {
            verbose = 1;
        } else if (!strcmp(a, "--fold-creases")) {
            fold_creases = 1;
        } else if (!strcmp(a, "--no-fold-creases")) {
            fold_creases = 0;
        } else if (!strcmp(a, "--fallback")) {
            fallback = 1;
        } else if (!strcmp(a, "--cavities")) {
            opt.cavities = 1;
        } else if (!strcmp(a, "--union")) {
            opt.self_union = 1;
        } else if (!strcmp(a, "--no-union")) {
            opt.self_union = 0;
        } else if (takes_value(a) && !v) {
            fprintf(stderr, "vorocrust: %s needs a value (see 'vorocrust mesh --help')\n", a);
            return 2;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            out_path = argv[++i];
        } else if (!strcmp(a, "--foam")) {
            foam_path = argv[++i];
        } else if (!strcmp(a, "--connections")) {
            conn_path = argv[++i];
        } else if (!strcmp(a, "--uge")) {
            uge_path = argv[++i];
        } else if (!strcmp(a, "--tough")) {
            tough_path = argv[++i];
        } else if (!strcmp(a, "--patches")) {
            if (!strcmp(v, "groups"))
                opt.patches = VC_PATCHES_GROUPS;
            else if (!strcmp(v, "features"))
                opt.patches = VC_PATCHES_FEATURES;
            else if (!strcmp(v, "none"))
                opt.patches = VC_PATCHES_NONE;
            else {
                fprintf(stderr, "vorocrust: --patches: '%s' is not groups, features or none\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--patch-type")) {
            static const char *const ok[] = {"patch", "wall", "symmetryPlane", "symmetry", "empty"};
            const char *eq = strchr(v, '=');
            int known = 0;
            for (size_t j = 0; eq && j < sizeof ok / sizeof *ok; j++)
                known |= !strcmp(eq + 1, ok[j]);
            if (!eq || eq == v || !known || strlen(v) >= sizeof patch_type_text[0]) {
                fprintf(stderr, "vorocrust: --patch-type: '%s' is not NAME=TYPE with TYPE patch, wall, "
                        "symmetryPlane, symmetry or empty\n", v);
                return 2;
            }
            if (n_patch_types == MAX_PATCH_TYPES) {
                fprintf(stderr, "vorocrust: more than %d --patch-type options\n", MAX_PATCH_TYPES);
                return 2;
            }
            snprintf(patch_type_text[n_patch_types], sizeof patch_type_text[0], "%s", v);
            char *t = patch_type_text[n_patch_types];
            t[eq - v] = 0;
            patch_type[n_patch_types].name = t;
            patch_type[n_patch_types].type = t + (eq - v) + 1;
            n_patch_types++;
            i++;
        } else if (!strcmp(a, "--foam-max-skew")) {
            foam_max_skew_given = 1;
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
            opt.smooth_iterations = (int)it;
            smooth_iterations_given = 1;
            i++;
        } else if (!strcmp(a, "--interior")) {
            if (!strcmp(v, "octree"))
                opt.interior = VC_INTERIOR_OCTREE;
            else if (!strcmp(v, "lattice"))
                opt.interior = VC_INTERIOR_LATTICE;
            else if (!strcmp(v, "none"))
                opt.interior = VC_INTERIOR_NONE;
            else {
                fprintf(stderr, "vorocrust: --interior: '%s' is not octree, lattice or none\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--denoise")) {
            if (!strcmp(v, "auto"))
                opt.denoise = 0;
            else if (!strcmp(v, "on"))
                opt.denoise = 1;
            else if (!strcmp(v, "off"))
                opt.denoise = -1;
            else {
                fprintf(stderr, "vorocrust: --denoise: '%s' is not auto, on or off\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--lloyd")) {
            long it;
            if (vc_cli_parse_int(v, 0, 1000, &it)) {
                fprintf(stderr, "vorocrust: --lloyd needs an integer from 0 to 1000, got '%s'\n", v);
                return 2;
            }
            opt.lloyd_iterations = (int)it;
            i++;
        } else if (!strcmp(a, "--quartet-gap")) {
            if (vc_cli_parse_double(v, &opt.quartet_gap) ||
                !(opt.quartet_gap >= 0 && opt.quartet_gap < 1)) {
                fprintf(stderr, "vorocrust: --quartet-gap needs a number in [0, 1), got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--unskew")) {
            if (vc_cli_parse_double(v, &opt.unskew) ||
                !(opt.unskew == 0 || (opt.unskew >= 1 && opt.unskew <= 1000))) {
                fprintf(stderr, "vorocrust: --unskew needs 0 or a number in [1, 1000], got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--protect")) {
            if (vc_cli_parse_double(v, &opt.protect_edge) ||
                !(opt.protect_edge >= 0 && opt.protect_edge < 0.25)) {
                fprintf(stderr, "vorocrust: --protect needs a number in [0, 0.25), got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--interior-spacing")) {
            if (vc_cli_parse_double(v, &opt.interior_spacing) || !(opt.interior_spacing > 0)) {
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
        } else if (!strcmp(a, "--smooth-width")) {
            if (vc_cli_parse_double(v, &opt.smooth_width) ||
                !(opt.smooth_width >= 0 && opt.smooth_width <= 100)) {
                fprintf(stderr, "vorocrust: --smooth-width needs a number in [0, 100], got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--curvature-factor")) {
            curvature_given = 1;
            if (vc_cli_parse_double(v, &opt.curvature_factor) ||
                !(opt.curvature_factor > 0 && opt.curvature_factor <= 10)) {
                fprintf(stderr, "vorocrust: --curvature-factor needs a number in (0, 10], got '%s'\n", v);
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
        } else if (!strcmp(a, "--max-balls")) {
            long nb;
            if (vc_cli_parse_int(v, 1, 2147483647L, &nb)) {
                fprintf(stderr, "vorocrust: --max-balls needs an integer from 1 to 2147483647, "
                        "got '%s'\n", v);
                return 2;
            }
            opt.max_balls = nb;
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
        } else if (n_inputs < MAX_INPUTS) {
            inputs[n_inputs++] = a;
            if (!in_path)
                in_path = a;
        } else {
            fprintf(stderr, "vorocrust: more than %d input surfaces\n", MAX_INPUTS);
            return 2;
        }
    }
    if (!in_path) {
        fprintf(stderr, "vorocrust: missing the input surface (see 'vorocrust mesh --help')\n");
        return 2;
    }
    if (curvature_given && !(opt.smooth_width > 0)) {
        fprintf(stderr, "vorocrust: --curvature-factor needs --smooth-width (it bounds the radii "
                        "on the smooth surface only)\n");
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
    if ((conn_path || uge_path || tough_path) && surface_only) {
        fprintf(stderr, "vorocrust: --%s and --surface-only exclude each other\n",
                conn_path ? "connections" : uge_path ? "uge" : "tough");
        return 2;
    }
    if (foam_path) {
        int frc = vc_cli_check_case_dir(foam_path);
        if (frc)
            return frc;
    }
    /* --unskew mends the skew faces at the seeds: the case's collapse, unless
     * asked for, takes only what it left above checkMesh's limit, so that
     * the case is the .vtu's mesh wherever --unskew mended every face */
    if (opt.unskew > 0 && !foam_max_skew_given)
        foam_max_skew = CHECKMESH_MAX_SKEW;
    /* -o OUT.vtu writes OUT_boundary.vtu too */
    char *boundary_out = out_path ? boundary_path(out_path) : NULL;
    const char *outputs[9] = {out_path, surf_path, seeds_path, balls_path, conn_path, uge_path,
                              tough_path, boundary_out, foam_path};
    for (int i = 0; i < 9; i++) {
        if (!outputs[i])
            continue;
        for (int j = 0; j < i; j++)
            if (outputs[j] && !strcmp(outputs[i], outputs[j])) {
                fprintf(stderr, "vorocrust: %s: named by two outputs%s\n", outputs[i],
                        i == 7 || j == 7 ? " (-o writes its _boundary.vtu too)" : "");
                free(boundary_out);
                return 2;
            }
        if (i < 8 && vc_cli_check_output_file(outputs[i])) { /* foam_path: checked above */
            free(boundary_out);
            return 1;
        }
    }
    free(boundary_out);
    if (fallback)
        /* smoothing first already: only the creases are left to try */
        opt.resample = smooth_iterations_given ? VC_RESAMPLE_CREASES
                                               : VC_RESAMPLE_CREASES | VC_RESAMPLE_SMOOTH;
    else
        opt.resample = fold_creases ? VC_RESAMPLE_FOLDS : 0;
    vc_logger log;
    vc_cli_logger_init(&log, quiet ? VC_LOG_WARNING : verbose ? VC_LOG_DEBUG : VC_LOG_INFO);
    /* several inputs: their names joined, for every message */
    char joined[1024];
    if (n_inputs > 1) {
        size_t k = 0;
        for (int i = 0; i < n_inputs && k < sizeof joined; i++)
            k += (size_t)snprintf(joined + k, sizeof joined - k, "%s%s", i ? " + " : "", inputs[i]);
        in_path = joined;
    }
    opt.name = in_path;
    opt.surface_only = surface_only;
    if (opt.interior == VC_INTERIOR_OCTREE && vc_cli_mpi_start())
        return 1;
    /* a line on stderr at least every VC_CLI_KEEPALIVE seconds, whatever
     * the phase (a million cells' checks, quality and writing are seconds
     * each); stopped before the summary, or by vc_cmd_mesh */
    vc_logger relay;
    keepalive = vc_log_keepalive_start(&log, VC_CLI_KEEPALIVE, &relay);
    opt.log = &relay;

    vc_error err = {0, ""};
    vc_cli_outputs_begin(); /* a signal removes the temporary files and the outputs */
    const double t0 = vc_cli_now();
    vc_surface s;
    /* a large file takes a second or more to read (50 MB: 0.8 s): said
     * before, so that the first line comes within 2 s */
    for (int i = 0; i < n_inputs && !quiet; i++) {
        struct stat st;
        if (stat(inputs[i], &st) == 0 && st.st_size > (16 << 20))
            fprintf(stderr, "mesh: reading %s (%.0f MB)\n", inputs[i], (double)st.st_size / (1 << 20));
    }
    if (read_inputs(inputs, n_inputs, &s, &err)) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        return 1;
    }
    /* every --patch-type names a patch the input has */
    for (int k = 0; k < n_patch_types; k++) {
        int found = !strcmp(patch_type[k].name, "surface") && (!s.tri_group || opt.patches == VC_PATCHES_NONE);
        for (int32_t g = 0; opt.patches == VC_PATCHES_GROUPS && g < s.n_groups; g++)
            found |= !strcmp(patch_type[k].name, s.group_name[g]);
        if (opt.patches == VC_PATCHES_FEATURES && !strncmp(patch_type[k].name, "patch", 5))
            found = 1; /* patchN: known once the features are */
        if (!found) {
            char list[512] = "";
            size_t n = 0;
            for (int32_t g = 0; g < s.n_groups && n + 70 < sizeof list; g++)
                n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", g ? ", " : "", s.group_name[g]);
            fprintf(stderr, "vorocrust: --patch-type %s=%s: the input has no patch '%s' (its patches: %s)\n",
                    patch_type[k].name, patch_type[k].type, patch_type[k].name,
                    s.tri_group && opt.patches == VC_PATCHES_GROUPS ? list : "surface");
            vc_surface_free(&s);
            return 2;
        }
    }
    const double t_read = vc_cli_now() - t0;
    vc_mesh_result r;
    int rc = vc_mesh(&s, &opt, &r, &err);
    const int64_t n_input_triangles = s.n_triangles;
    vc_surface_free(&s);
    if (rc) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        return 1;
    }

    /* All outputs or none: a failed write (vc_cli_outputs_remove) or a
     * signal removes the ones already committed. */
    const double tw = vc_cli_now();
    double t_write_mesh = 0;
    rc = 1;
    if (surf_path) {
        if (vc_polysurface_write(&r.surface, surf_path, &err))
            goto write_failed;
    }
    if (balls_path) {
        if (vc_balls_write_csv(&r.balls, balls_path, &err))
            goto write_failed;
    }
    if (seeds_path) {
        if (vc_seeds_write_csv(seeds_path, &r.seeds, &err))
            goto write_failed;
    }
    const double t_write_surface = vc_cli_now() - tw;
    if (out_path) {
        const double tm = vc_cli_now();
        /* large meshes take seconds to write (and the OpenFOAM case's
         * collapse): a progress line */
        if (r.mesh.n_cells >= VC_CLI_PROGRESS_CELLS)
            vc_log(&relay, VC_LOG_INFO, "mesh: writing %s%s%s%s%s%s%s", out_path,
                   conn_path ? ", " : "", conn_path ? conn_path : "", uge_path ? ", " : "",
                   uge_path ? uge_path : "", tough_path || foam_path ? ", " : "",
                   tough_path && foam_path ? "TOUGH MESH and OpenFOAM case"
                   : tough_path            ? tough_path
                   : foam_path             ? foam_path
                                           : "");
        if (vc_write_vtu(&r.mesh, out_path, VC_VTU_ZLIB, &err))
            goto write_failed;
        /* and its boundary faces with their patches: OUT_boundary.vtu */
        {
            char *bpath = boundary_path(out_path);
            if (!bpath) {
                vc_error_set(&err, VC_ENOMEM, "out of memory");
                goto write_failed;
            }
            const int brc = vc_write_boundary_vtu(&r.mesh, bpath, &err);
            free(bpath);
            if (brc)
                goto write_failed;
        }
        if (conn_path) {
            if (vc_write_connections_csv(&r.mesh, conn_path, &err))
                goto write_failed;
        }
        /* before the OpenFOAM case's collapse changes the mesh */
        if (uge_path) {
            if (vc_write_pflotran(&r.mesh, uge_path, &err))
                goto write_failed;
        }
        if (tough_path) {
            if (vc_write_tough(&r.mesh, tough_path, &err))
                goto write_failed;
        }
        if (foam_path && foam_max_skew > 0 &&
            vc_polymesh_collapse_skew_faces(&r.mesh, foam_max_skew, FOAM_COLLAPSE_ROUNDS,
                                            &foam_skew)) {
            vc_error_set(&err, VC_ENOMEM, "out of memory collapsing the skew faces");
            goto write_failed;
        }
        /* a case meant to pass checkMesh that is known to fail it is an error,
         * not an output */
        if (foam_path && foam_max_skew > 0 && foam_max_skew <= CHECKMESH_MAX_SKEW &&
            foam_skew.max_skew_after > CHECKMESH_MAX_SKEW) {
            /* how many, and where the worst is (a user can look there) */
            int64_t n_over = 0, worst = -1;
            double worst_skew = 0;
            for (int64_t f = 0; f < r.mesh.n_interior_faces; f++) {
                const double sk = vc_polymesh_face_skewness(&r.mesh, f);
                n_over += sk > CHECKMESH_MAX_SKEW;
                if (sk > worst_skew) {
                    worst_skew = sk;
                    worst = f;
                }
            }
            const double *at = worst >= 0 && r.mesh.face_centroid
                                   ? r.mesh.face_centroid + 3 * worst
                                   : (const double[3]){0, 0, 0};
            vc_error_set(&err, VC_EINPUT,
                         "%s: the OpenFOAM case would fail checkMesh: after collapsing %lld skew "
                         "faces, %lld keep a skewness above %g (at most %.3g, at %.6g %.6g %.6g); "
                         "--foam-max-skew 0 writes the exact Voronoi cells, which fail checkMesh's "
                         "skewness check only",
                         in_path, (long long)foam_skew.n_collapsed, (long long)n_over,
                         (double)CHECKMESH_MAX_SKEW, foam_skew.max_skew_after, at[0], at[1], at[2]);
            goto write_failed;
        }
        if (foam_path &&
            vc_write_openfoam_typed(&r.mesh, foam_path, patch_type, n_patch_types, &err))
            goto write_failed;
        t_write_mesh = vc_cli_now() - tm;
    }
    vc_cli_outputs_keep();
    vc_log_keepalive_stop(keepalive);
    keepalive = NULL;
    if (!quiet)
        print_summary(in_path, n_input_triangles, &opt, &r, foam_path && foam_max_skew > 0,
                      foam_max_skew, &foam_skew, t_read, t_write_surface, t_write_mesh,
                      vc_cli_now() - t0);
    rc = 0;
    goto out;
write_failed:
    fprintf(stderr, "vorocrust: %s\n", err.msg);
    vc_cli_outputs_remove();
out:
    vc_mesh_result_free(&r);
    return rc;
}

int vc_cmd_mesh(int argc, char **argv)
{
    int rc = run_mesh(argc, argv);
    vc_log_keepalive_stop(keepalive); /* the error paths */
    keepalive = NULL;
    vc_cli_mpi_stop();
    return rc;
}
