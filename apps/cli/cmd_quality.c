/* vorocrust quality: the quality report of a polyhedral or tetrahedral
 * .vtu mesh, optionally against the input surface it approximates. */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli_util.h"
#include "commands.h"
#include "vorocrust/mesh_report.h"
#include "vorocrust/surface.h"
#include "vorocrust/vtu_reader.h"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vorocrust quality MESH.vtu [--input SURFACE] [--threads N]\n"
        "  MESH.vtu          VTK XML unstructured grid of polyhedra (42) and/or tetrahedra (10)\n"
        "  --input SURFACE   also the two-sided Hausdorff distance between the mesh boundary\n"
        "                    and this surface (.obj, .off, .stl, .ply), normalised by the\n"
        "                    surface's bounding-box diagonal\n"
        "  --threads N       threads (default: all cores); the report does not depend on it\n"
        "Prints cell counts, total volume and, as min, max, mean and percentiles p1, p5,\n"
        "p50, p95, p99: cell volume, fatness (minimum enclosing ball radius / maximum\n"
        "inscribed ball radius), shortest edge / enclosing radius, smallest face /\n"
        "enclosing radius^2, and for tetrahedra the smallest and largest dihedral angle\n"
        "per cell; checkMesh's non-orthogonality and skewness of the faces between two\n"
        "cells and, when the file holds each cell's seed (vorocrust's 'seed_point'), the\n"
        "seeds' distance over the two cells' mean enclosing radius. The boundary (faces of one cell,\n"
        "polygons fanned from their centroid) gives the triangle quality\n"
        "Q = 6 S / (sqrt(3) h P) and the percentages of angles below 30 and above 90 degrees.\n");
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void print_stats(const char *name, const vc_stats *st)
{
    if (st->n == 0) {
        printf("%s: none\n", name);
        return;
    }
    printf("%s: min %.6g, max %.6g, mean %.6g, p1 %.6g, p5 %.6g, p50 %.6g, p95 %.6g, p99 %.6g\n",
           name, st->min, st->max, st->mean, st->p1, st->p5, st->p50, st->p95, st->p99);
}

int vc_cmd_quality(int argc, char **argv)
{
    const char *mesh_path = NULL, *input_path = NULL;
    vc_cli_seen seen = {{NULL}, 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (vc_cli_repeated(&seen, "vorocrust", "vorocrust quality", a))
            return 2;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--input") || !strcmp(a, "--threads")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "vorocrust: %s needs a value (see 'vorocrust quality --help')\n", a);
                return 2;
            }
            const char *v = argv[++i];
            if (!strcmp(a, "--input")) {
                input_path = v;
                continue;
            }
            char *end;
            errno = 0;
            long t = strtol(v, &end, 10);
            if (errno || end == v || *end || t < 1 || t > 4096) {
                fprintf(stderr, "vorocrust: --threads: '%s' is not a count from 1 to 4096\n", v);
                return 2;
            }
#ifdef _OPENMP
            omp_set_num_threads((int)t);
#endif
        } else if (vc_cli_positional("vorocrust", "vorocrust quality", a, &mesh_path)) {
            return 2;
        }
    }
    if (!mesh_path)
        return vc_cli_missing("vorocrust", "vorocrust quality", "the mesh MESH.vtu");

    vc_error err = {0, ""};
    vc_vtu_mesh m;
    vc_surface input = {0, NULL, 0, NULL, NULL, 0, NULL};
    vc_surface_report rep;
    vc_mesh_report r;
    int rc = 1;
    double t0 = now();
    memset(&m, 0, sizeof m);
    memset(&r, 0, sizeof r);
    /* The input first: it is usually the smaller file, so a bad one fails fast. */
    if (input_path) {
        if (vc_surface_read(input_path, &input, &rep, &err) != 0) {
            fprintf(stderr, "vorocrust: %s\n", err.msg);
            goto out;
        }
        for (int i = 0; i < rep.n_warnings; i++)
            fprintf(stderr, "vorocrust: warning: %s\n", rep.warnings[i]);
    }
    if (vc_vtu_read(mesh_path, &m, &err) != 0) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        goto out;
    }
    if (m.n_skipped)
        fprintf(stderr, "vorocrust: warning: %s: %" PRId64 " cells of other types skipped "
                "(first: VTK cell type %d); only polyhedra (42) and tetrahedra (10) are measured\n",
                mesh_path, m.n_skipped, m.first_skipped_type);
    double t_read = now();
    if (vc_mesh_report_compute(&m, mesh_path, input_path ? &input : NULL, input_path, &r,
                               &err) != 0) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        goto out;
    }
    double t1 = now();

    printf("file: %s\n", mesh_path);
    printf("cells: %" PRId64 " (%" PRId64 " polyhedra, %" PRId64 " tetrahedra)\n", r.n_cells,
           r.n_cells - r.n_tetrahedra, r.n_tetrahedra);
    if (m.n_skipped)
        printf("skipped cells: %" PRId64 " (other cell types)\n", m.n_skipped);
    printf("vertices: %" PRId64 "\n", r.n_points);
    printf("faces: %" PRId64 " (%" PRId64 " boundary)\n", r.n_faces, r.n_boundary_faces);
    if (r.n_faces_shared_more)
        printf("faces shared by more than two cells: %" PRId64 "\n", r.n_faces_shared_more);
    if (r.n_open_cells)
        printf("open cells: %" PRId64 " (an edge not shared by exactly two faces in opposite "
               "directions: volume and fatness unreliable; first: cell %" PRId64 ")\n",
               r.n_open_cells, r.first_open_cell);
    if (r.n_inverted_cells)
        printf("inverted cells: %" PRId64 " (faces listed inward)\n", r.n_inverted_cells);
    if (r.n_unmeasured_cells)
        printf("unmeasured cells: %" PRId64 " (no inscribed ball: open or degenerate; first: cell %"
               PRId64 ")\n", r.n_unmeasured_cells, r.first_unmeasured_cell);
    printf("total volume: %.17g\n", r.total_volume);
    print_stats("volume", &r.volume);
    print_stats("fatness", &r.fatness);
    print_stats("shortest relative edge", &r.shortest_edge_rel);
    printf("cells with a shortest relative edge below 1e-2: %.2f%%\n", 100.0 * r.short_edge_share);
    print_stats("smallest face / enclosing radius^2", &r.small_face_rel);
    if (!isnan(r.non_orthogonality_max))
        printf("checkMesh measures: non-orthogonality max %.6g average %.6g degrees, skewness max "
               "%.6g (%" PRId64 " faces above 4)\n", r.non_orthogonality_max,
               r.non_orthogonality_mean, r.skewness_max, r.n_skew_faces);
    if (r.connection_rel.n)
        print_stats("seed distance / mean enclosing radius", &r.connection_rel);
    if (r.n_tetrahedra) {
        print_stats("dihedral angle min", &r.dihedral_min);
        print_stats("dihedral angle max", &r.dihedral_max);
    }
    printf("boundary triangles: %" PRId64 "\n", r.n_boundary_triangles);
    if (r.n_boundary_triangles) {
        print_stats("triangle quality", &r.triangle_quality);
        printf("angles below 30 degrees: %.4f%%\n", r.angles_below_30);
        printf("angles above 90 degrees: %.4f%%\n", r.angles_above_90);
    }
    if (r.has_hausdorff) {
        const vc_hausdorff_result *hd = &r.hausdorff;
        printf("input: %s\n", input_path);
        printf("hausdorff distance: %.6g (normalised by the input's bounding-box diagonal %.6g: %.6g)\n",
               hd->distance, hd->diagonal, hd->normalised);
        printf("hausdorff input to mesh: %.6g, mesh to input: %.6g, sampling error at most %.3g "
               "(%" PRId64 " + %" PRId64 " samples)\n", hd->a_to_b, hd->b_to_a, hd->error_bound,
               hd->n_samples_a, hd->n_samples_b);
    }
    printf("time: %.3f s (read %.3f s, cells %.3f s, boundary %.3f s, hausdorff %.3f s)\n", t1 - t0,
           t_read - t0, r.time_cells, r.time_boundary, r.time_hausdorff);
    rc = 0;
out:
    vc_mesh_report_free(&r);
    vc_vtu_mesh_free(&m);
    vc_surface_free(&input);
    return rc;
}
