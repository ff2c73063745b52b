/* vc-tetgen: the tetrahedral baseline of `vorocrust compare`. Reads a closed
 * triangle surface with the library's reader, tetrahedralizes the volume it
 * encloses with TetGen (quality switches, a volume bound chosen for a
 * target cell count) and writes a .vtu of VTK_TETRA cells. A separate
 * program because TetGen is AGPL: the vorocrust library never links it. */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "tetgen_adapter.h"
#include "tetra_vtu_writer.h"
#include "vorocrust/error.h"
#include "vorocrust/surface.h"

/* TetGen's tetrahedra under a volume bound V and radius-edge bound 1.414
 * have a mean volume of about V / 3 (measured on sphere, icosphere and
 * bracket at 50,000 tetrahedra: V / 2.7 to V / 3.2), so a target of N
 * cells in a volume W asks for the bound 3 W / N. A coarse target gives
 * more cells than asked: TetGen keeps every input triangle as a boundary
 * face (torus.obj, 9,216 triangles, never gets below about 45,000
 * tetrahedra). */
#define MEAN_VOLUME_RATIO 3.0

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vc-tetgen INPUT -o OUT.vtu [--target-cells N | --max-volume V]\n"
        "                 [--radius-edge R] [--quiet]\n"
        "Tetrahedralizes the volume a closed triangle surface (.obj, .off, .stl, .ply)\n"
        "encloses with TetGen (switches -pq<R>a<V>) and writes VTK_TETRA cells to OUT.vtu.\n"
        "  -o, --output OUT.vtu  the tetrahedral mesh (required)\n"
        "  --target-cells N      aim at about N tetrahedra: the volume bound is\n"
        "                        %.1f x (enclosed volume) / N\n"
        "  --max-volume V        the volume bound itself (TetGen's -a)\n"
        "  --radius-edge R       radius-edge ratio bound, at least 1.1 (default 1.414;\n"
        "                        TetGen's -q)\n"
        "  --quiet               no summary on stderr\n"
        "Without --target-cells or --max-volume, only the quality bound applies.\n"
        "Exit: 0 success, 1 bad input or a TetGen failure, 2 usage error.\n",
        MEAN_VOLUME_RATIO);
}

/* TetGen 1.5.0 frees its memory twice when it stops on an error it did not
 * foresee (a feature too small for its tolerance, facets too close): it
 * crashes instead of throwing its error code. While it runs, a crash prints
 * this line and exits 1 instead. */
static char crash_line[600];

static void on_tetgen_crash(int sig)
{
    (void)sig;
    ssize_t unused = write(STDERR_FILENO, crash_line, strlen(crash_line));
    (void)unused;
    _exit(1);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Whether the directory that would hold path exists and is writable. */
static int directory_writable(const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    if (!slash)
        return access(".", W_OK) == 0;
    size_t n = slash == path ? 1 : (size_t)(slash - path);
    if (n >= sizeof dir)
        return 0;
    memcpy(dir, path, n);
    dir[n] = 0;
    return access(dir, W_OK) == 0;
}

static int parse_positive(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || !isfinite(v) || v <= 0)
        return -1;
    *out = v;
    return 0;
}

int main(int argc, char **argv)
{
    const char *input = NULL, *output = NULL;
    double target = 0, max_volume = 0, radius_edge = 1.414;
    int quiet = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output") || !strcmp(a, "--target-cells") ||
                   !strcmp(a, "--max-volume") || !strcmp(a, "--radius-edge")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "vc-tetgen: %s needs a value (see 'vc-tetgen --help')\n", a);
                return 2;
            }
            const char *v = argv[++i];
            if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
                output = v;
            } else if (!strcmp(a, "--target-cells")) {
                if (parse_positive(v, &target) || target != floor(target) || target > 1e9) {
                    fprintf(stderr, "vc-tetgen: --target-cells: '%s' is not a count from 1 to 1e9\n", v);
                    return 2;
                }
            } else if (!strcmp(a, "--max-volume")) {
                if (parse_positive(v, &max_volume)) {
                    fprintf(stderr, "vc-tetgen: --max-volume: '%s' is not a positive number\n", v);
                    return 2;
                }
            } else if (parse_positive(v, &radius_edge) || radius_edge < 1.1 || radius_edge > 1e6) {
                fprintf(stderr, "vc-tetgen: --radius-edge: '%s' is not a number from 1.1 to 1e6 "
                        "(TetGen may not terminate below 1.1)\n", v);
                return 2;
            }
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "vc-tetgen: unknown option '%s' (see 'vc-tetgen --help')\n", a);
            return 2;
        } else if (!input) {
            input = a;
        } else {
            fprintf(stderr, "vc-tetgen: unexpected argument '%s'\n", a);
            return 2;
        }
    }
    if (!input) {
        fprintf(stderr, "vc-tetgen: missing the INPUT surface (see 'vc-tetgen --help')\n");
        return 2;
    }
    if (!output) {
        fprintf(stderr, "vc-tetgen: missing -o OUT.vtu (see 'vc-tetgen --help')\n");
        return 2;
    }
    if (target > 0 && max_volume > 0) {
        fprintf(stderr, "vc-tetgen: --target-cells and --max-volume exclude each other\n");
        return 2;
    }
    struct stat st;
    if (!directory_writable(output)) {
        fprintf(stderr, "vc-tetgen: %s: cannot write: directory missing or not writable\n", output);
        return 1;
    }
    if (stat(output, &st) == 0 && S_ISDIR(st.st_mode)) {
        fprintf(stderr, "vc-tetgen: %s: cannot write: Is a directory\n", output);
        return 1;
    }

    double t0 = now();
    vc_error err = {0, ""};
    vc_surface s = {0, NULL, 0, NULL};
    vc_surface_report rep;
    vc_tetgen_mesh mesh = {0, NULL, 0, NULL};
    int rc = 1;
    if (vc_surface_read(input, &s, &rep, &err) != 0 || vc_surface_require_closed(&rep, &err) != 0) {
        fprintf(stderr, "vc-tetgen: %s\n", err.msg);
        goto out;
    }
    if (rep.n_nonmanifold_edges) {
        fprintf(stderr, "vc-tetgen: %s: %" PRId64 " non-manifold edges (the surface must bound "
                "one volume)\n", input, rep.n_nonmanifold_edges);
        goto out;
    }
    if (!(rep.volume > 0)) {
        fprintf(stderr, "vc-tetgen: %s: the surface encloses no volume\n", input);
        goto out;
    }
    if (target > 0)
        max_volume = MEAN_VOLUME_RATIO * rep.volume / target;

    char switches[128];
    if (max_volume > 0)
        snprintf(switches, sizeof switches, "pq%.6ga%.6gQ", radius_edge, max_volume);
    else
        snprintf(switches, sizeof switches, "pq%.6gQ", radius_edge);
    double t_read = now();
    char msg[512];
    int64_t n_crossing = 0;
    if (vc_tetgen_self_intersections(&s, &n_crossing, msg, sizeof msg) != 0) {
        fprintf(stderr, "vc-tetgen: %s: %s\n", input, msg);
        goto out;
    }
    if (n_crossing) {
        fprintf(stderr, "vc-tetgen: %s: the surface intersects itself (%" PRId64 " triangles "
                "cross others; TetGen needs a surface without self-intersections)\n", input,
                n_crossing);
        goto out;
    }
    double t_check = now();
    snprintf(crash_line, sizeof crash_line, "vc-tetgen: %s: TetGen crashed while stopping on "
             "this surface (TetGen 1.5.0 does so on features below its tolerance or facets "
             "too close together)\n", input);
    signal(SIGSEGV, on_tetgen_crash);
    signal(SIGBUS, on_tetgen_crash);
    signal(SIGABRT, on_tetgen_crash);
    int tetgen_rc = vc_tetgen_tetrahedralize(&s, switches, &mesh, msg, sizeof msg);
    signal(SIGSEGV, SIG_DFL);
    signal(SIGBUS, SIG_DFL);
    signal(SIGABRT, SIG_DFL);
    if (tetgen_rc != 0) {
        fprintf(stderr, "vc-tetgen: %s: %s\n", input, msg);
        goto out;
    }
    double t_mesh = now();
    if (vc_write_tetra_vtu(&mesh, output, &err) != 0) {
        fprintf(stderr, "vc-tetgen: %s\n", err.msg);
        goto out;
    }
    double t_write = now();
    if (!quiet) {
        double volume = 0;
        for (int64_t t = 0; t < mesh.n_tets; t++)
            volume += vc_tetra_signed_volume(&mesh, t);
        fprintf(stderr, "vc-tetgen: %s (%" PRId64 " triangles), switches -%s\n", input,
                s.n_triangles, switches);
        fprintf(stderr, "  %" PRId64 " points, %" PRId64 " tetrahedra", mesh.n_points, mesh.n_tets);
        if (target > 0)
            fprintf(stderr, " (target %.0f)", target);
        fprintf(stderr, ", volume %.12g (input %.12g)\n", volume, rep.volume);
        fprintf(stderr, "  time (s): read %.3f, self-intersection check %.3f, tetgen %.3f, "
                "write %.3f\n", t_read - t0, t_check - t_read, t_mesh - t_check, t_write - t_mesh);
    }
    rc = 0;
out:
    vc_tetgen_mesh_free(&mesh);
    vc_surface_free(&s);
    return rc;
}
