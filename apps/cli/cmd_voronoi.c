/* vorocrust voronoi: the conforming Voronoi mesh of a seed file. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli_log.h"
#include "cli_util.h"
#include "commands.h"
#include "vorocrust/io.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/seeds.h"
#include "vorocrust/voronoi.h"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vorocrust voronoi SEEDS.csv -o OUT.vtu [options]\n"
        "  SEEDS.csv               header line, then rows x,y,z[,label]; label 0 = cell not kept\n"
        "  -o, --output OUT.vtu    the mesh (VTK_POLYHEDRON cells)\n"
        "  --box X0 Y0 Z0 X1 Y1 Z1 clip every cell to this box (all seeds must lie in it)\n"
        "  --connections OUT.csv   interior faces: cells, seeds, area, seed distance, centroid, normal\n"
        "  --foam CASE_DIR         OpenFOAM case: CASE_DIR/constant/polyMesh (and system/controlDict)\n"
        "  --encoding zlib|raw     binary encoding of the .vtu (default zlib)\n"
        "  --threads N             threads (default: all cores); the mesh does not depend on it\n"
        "  --no-validate           skip the mesh validator\n"
        "  --quiet                 no progress or summary\n"
        "  --verbose               also the phase timings of the engine\n");
}

/* Options that are followed by a value (reached here only when it is missing). */
static int takes_value(const char *a)
{
    static const char *const with_value[] = {"-o", "--output", "--connections", "--threads",
                                             "--encoding", "--foam"};
    for (size_t i = 0; i < sizeof with_value / sizeof with_value[0]; i++)
        if (!strcmp(a, with_value[i]))
            return 1;
    return 0;
}

int vc_cmd_voronoi(int argc, char **argv)
{
    const char *seeds_path = NULL, *out_path = NULL, *conn_path = NULL, *foam_path = NULL;
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    vc_vtu_encoding enc = VC_VTU_ZLIB;
    int validate = 1, quiet = 0, verbose = 0;
    vc_cli_seen seen = {{NULL}, 0};

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (vc_cli_repeated(&seen, "vorocrust", "vorocrust voronoi", a))
            return 2;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if ((!strcmp(a, "-o") || !strcmp(a, "--output")) && i + 1 < argc) {
            out_path = argv[++i];
        } else if (!strcmp(a, "--connections") && i + 1 < argc) {
            conn_path = argv[++i];
        } else if (!strcmp(a, "--foam") && i + 1 < argc) {
            foam_path = argv[++i];
        } else if (!strcmp(a, "--box")) {
            if (i + 6 >= argc) {
                fprintf(stderr, "vorocrust: --box needs 6 numbers\n");
                return 2;
            }
            for (int d = 0; d < 6; d++)
                if (vc_cli_parse_double(argv[i + 1 + d], &opt.box[d]) != 0) {
                    fprintf(stderr, "vorocrust: --box: '%s' is not a finite number\n",
                            argv[i + 1 + d]);
                    return 2;
                }
            for (int d = 0; d < 3; d++)
                if (!(opt.box[d] < opt.box[d + 3])) {
                    fprintf(stderr, "vorocrust: --box: min %g >= max %g on axis %c\n",
                            opt.box[d], opt.box[d + 3], 'x' + d);
                    return 2;
                }
            opt.has_box = 1;
            i += 6;
        } else if (!strcmp(a, "--threads") && i + 1 < argc) {
            long t;
            if (vc_cli_parse_int(argv[++i], 1, 4096, &t) != 0) {
                fprintf(stderr, "vorocrust: --threads: '%s' is not a count from 1 to 4096\n",
                        argv[i]);
                return 2;
            }
            opt.threads = (int)t;
#ifdef _OPENMP
            omp_set_num_threads((int)t); /* also for writing the outputs */
#endif
        } else if (!strcmp(a, "--encoding") && i + 1 < argc) {
            const char *e = argv[++i];
            if (!strcmp(e, "zlib"))
                enc = VC_VTU_ZLIB;
            else if (!strcmp(e, "raw"))
                enc = VC_VTU_RAW;
            else {
                fprintf(stderr, "vorocrust: --encoding: '%s' is not zlib or raw\n", e);
                return 2;
            }
        } else if (!strcmp(a, "--no-validate")) {
            validate = 0;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(a, "--verbose")) {
            verbose = 1;
        } else if (takes_value(a)) {
            fprintf(stderr, "vorocrust: %s needs a value (see 'vorocrust voronoi --help')\n", a);
            return 2;
        } else if (vc_cli_positional("vorocrust", "vorocrust voronoi", a, &seeds_path)) {
            return 2;
        }
    }
    if (!seeds_path || !out_path)
        return vc_cli_missing("vorocrust", "vorocrust voronoi",
                              !seeds_path ? "the seeds file SEEDS.csv" : "-o OUT.vtu");
    /* Refuse unwritable outputs before the work, not after. */
    const char *outputs[2] = {out_path, conn_path};
    for (int i = 0; i < 2; i++)
        if (outputs[i] && vc_cli_check_output_file(outputs[i]))
            return 1;
    if (foam_path) {
        int frc = vc_cli_check_case_dir(foam_path);
        if (frc)
            return frc;
        if (!strcmp(foam_path, out_path) || (conn_path && !strcmp(foam_path, conn_path))) {
            fprintf(stderr, "vorocrust: %s: named by --foam and by another output\n", foam_path);
            return 2;
        }
    }
    if (conn_path && !strcmp(conn_path, out_path)) {
        fprintf(stderr, "vorocrust: %s: named by both -o and --connections\n", out_path);
        return 2;
    }
    vc_cli_outputs_begin();
    vc_logger log, relay;
    vc_cli_logger_init(&log, quiet ? VC_LOG_WARNING : verbose ? VC_LOG_DEBUG : VC_LOG_INFO);
    /* a line at least every VC_CLI_KEEPALIVE seconds (cli_log.h) */
    vc_log_keepalive *keepalive = vc_log_keepalive_start(&log, VC_CLI_KEEPALIVE, &relay);
    opt.log = &relay;

    vc_error err = {0, ""};
    vc_seeds seeds = {0, NULL, NULL};
    vc_polymesh mesh;
    memset(&mesh, 0, sizeof mesh);
    int rc = 1;
    double t0 = vc_cli_now();
    if (vc_seeds_read_csv(seeds_path, &seeds, &err) != 0) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        goto out;
    }
    double t1 = vc_cli_now();
    if (vc_voronoi_build(&seeds, &opt, &mesh, &err) != 0) {
        fprintf(stderr, "vorocrust: %s: %s\n", seeds_path, err.msg);
        goto out;
    }
    double t2 = vc_cli_now();
    int64_t problems = 0;
    char report[2048];
    if (validate) {
        if (mesh.n_cells >= VC_CLI_PROGRESS_CELLS)
            vc_log(&relay, VC_LOG_INFO, "voronoi: checking %lld cells", (long long)mesh.n_cells);
        problems = vc_polymesh_validate(&mesh, 0, report, sizeof report);
        if (problems) {
            fprintf(stderr, "vorocrust: %s: the mesh fails validation (%lld problems):\n%s",
                    seeds_path, (long long)problems, report);
            goto out;
        }
    }
    double t3 = vc_cli_now();
    if (mesh.n_cells >= VC_CLI_PROGRESS_CELLS)
        vc_log(&relay, VC_LOG_INFO, "voronoi: writing %s", out_path);
    /* All outputs or none: a failed write or a signal removes the ones
     * already committed (vc_cli_outputs_begin, at the start). */
    if (vc_write_vtu(&mesh, out_path, enc, &err) != 0 ||
        (conn_path && vc_write_connections_csv(&mesh, conn_path, &err) != 0) ||
        (foam_path && vc_write_openfoam(&mesh, foam_path, &err) != 0)) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        vc_cli_outputs_remove();
        goto out;
    }
    vc_cli_outputs_keep();
    double t4 = vc_cli_now();
    vc_log_keepalive_stop(keepalive);
    keepalive = NULL;
    if (!quiet) {
        vc_polymesh_stats st;
        vc_polymesh_stats_compute(&mesh, &st);
        fprintf(stderr,
                "vorocrust voronoi: %lld seeds, %lld cells, %lld faces (%lld interior, %lld boundary), "
                "%lld vertices\n"
                "  volume %.17g (cell min %.6g, max %.6g), faces per cell mean %.2f max %.0f\n"
                "  validation %s\n"
                "  time: read %.3f s, cells %.3f s (%.0f cells/s), validate %.3f s, write %.3f s\n",
                (long long)seeds.n, (long long)mesh.n_cells, (long long)mesh.n_faces,
                (long long)mesh.n_interior_faces, (long long)st.n_boundary_faces,
                (long long)mesh.n_points, st.volume_total, st.volume_min, st.volume_max,
                st.mean_faces_per_cell, st.max_faces_per_cell, validate ? "passed" : "skipped",
                t1 - t0, t2 - t1, (double)mesh.n_cells / (t2 - t1 > 0 ? t2 - t1 : 1e-9), t3 - t2,
                t4 - t3);
    }
    rc = 0;
out:
    vc_log_keepalive_stop(keepalive);
    vc_polymesh_free(&mesh);
    vc_seeds_free(&seeds);
    return rc;
}
