/* mesh_surface: mesh a closed surface with the vorocrust library.
 *
 *     mesh_surface INPUT OUT.vtu
 *
 * Reads INPUT (.obj, .off, .stl, .ply), meshes it with the default options
 * (those of `vorocrust mesh INPUT -o OUT.vtu`, whose .vtu is the same byte
 * for byte), writes the polyhedral mesh to OUT.vtu (zlib-compressed VTK
 * XML) and prints a short summary. Progress goes to stderr.
 *
 * With the default octree interior the program owns MPI: it initialises it
 * before vc_mesh and finalises it at the end. */
#include <inttypes.h>
#include <stdio.h>

#include <mpi.h>

#include "vorocrust/vorocrust.h"

/* The library writes nothing itself: every message comes here. */
static void log_to_stderr(void *user, vc_log_level level, const char *message)
{
    static const char *const names[] = {"error", "warning", "info", "debug"};
    (void)user;
    fprintf(stderr, "%s: %s\n", level <= VC_LOG_DEBUG ? names[level] : "log", message);
}

static int mesh_file(const char *in_path, const char *out_path)
{
    vc_error err = {0};
    vc_surface s = {0};
    vc_mesh_result r = {0};
    int status = 1;

    if (vc_surface_read(in_path, &s, NULL, &err) != 0) {
        fprintf(stderr, "mesh_surface: %s\n", err.msg);
        return 1;
    }

    vc_logger log = {log_to_stderr, NULL, VC_LOG_INFO};
    vc_mesh_options opt;
    vc_mesh_options_default(&opt);
    opt.name = in_path;
    opt.log = &log;

    if (vc_mesh(&s, &opt, &r, &err) != 0) {
        fprintf(stderr, "mesh_surface: %s\n", err.msg);
    } else if (vc_write_vtu(&r.mesh, out_path, VC_VTU_ZLIB, &err) != 0) {
        fprintf(stderr, "mesh_surface: %s\n", err.msg);
    } else {
        printf("vorocrust %s: %s -> %s\n", vc_version(), in_path, out_path);
        printf("balls:         %" PRId64 "\n", r.balls.n);
        printf("surface seeds: %" PRId64 " (%" PRId64 " inside)\n", r.n_surface_seeds,
               r.n_inside_seeds);
        printf("cells:         %" PRId64 "\n", r.mesh.n_cells);
        printf("volume:        %.6g (input %.6g, %+.3f%%)\n", r.mesh_volume, r.input.volume,
               100.0 * (r.mesh_volume - r.input.volume) / r.input.volume);
        printf("fatness max:   %.3f\n", r.cell_quality.fatness_max);
        printf("time:          %.2f s\n", r.time.total);
        status = 0;
    }

    vc_mesh_result_free(&r);
    vc_surface_free(&s);
    return status;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s INPUT OUT.vtu\n", argv[0]);
        return 2;
    }
    MPI_Init(&argc, &argv);
    int status = mesh_file(argv[1], argv[2]);
    MPI_Finalize();
    return status;
}
