/* vc-tetgen: the tetrahedral baseline of `vorocrust compare`. Reads a closed
 * triangle surface with the library's reader, tetrahedralizes the volume it
 * encloses with TetGen (quality switches, a volume bound chosen for a
 * target cell count) and writes a .vtu of VTK_TETRA cells. A separate
 * program because TetGen is AGPL: the vorocrust library never links it. */
#include <inttypes.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_util.h"
#include "tetgen_adapter.h"
#include "tetra_vtu_writer.h"
#include "vorocrust/error.h"
#include "vorocrust/regions.h"
#include "vorocrust/surface.h"

/* TetGen's tetrahedra under a volume bound V and radius-edge bound 1.414
 * have a mean volume of about V / 3 in the interior (sphere, icosphere and
 * bracket at 50,000 tetrahedra: V / 2.7 to V / 3.2): the first bound tried
 * for N cells in a volume W is 3 W / N. The count is not a smooth function
 * of V (once V is below the tetrahedra along the surface, TetGen splits the
 * surface triangles: icosphere.obj jumps from 3,012 to 9,731 tetrahedra
 * between two bounds 20% apart), so the bound is then searched. */
#define MEAN_VOLUME_RATIO 3.0
#define SEARCH_RUNS 10      /* TetGen runs at most */
#define SEARCH_TOLERANCE 0.05 /* stop within 5% of the target */

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vc-tetgen INPUT -o OUT.vtu [--target-cells N | --max-volume V]\n"
        "                 [--radius-edge R] [--quiet]\n"
        "       vc-tetgen INPUT --target-cells N --bound-only\n"
        "Tetrahedralizes the volume a closed triangle surface (.obj, .off, .stl, .ply)\n"
        "encloses with TetGen (switches -pq<R>a<V>) and writes VTK_TETRA cells to OUT.vtu.\n"
        "  -o, --output OUT.vtu  the tetrahedral mesh (required, except with --bound-only)\n"
        "  --target-cells N      aim at N tetrahedra: the volume bound giving the count\n"
        "                        closest to N (within 5%%), searched over at most %d TetGen\n"
        "                        runs from %.0f x (enclosed volume) / N\n"
        "  --bound-only          with --target-cells: print the volume bound found\n"
        "                        ('max volume: V', V as --max-volume takes it) on stdout\n"
        "                        and write nothing\n"
        "  --max-volume V        the volume bound itself (TetGen's -a)\n"
        "  --radius-edge R       radius-edge ratio bound, at least 1.1 (default 1.414;\n"
        "                        TetGen's -q)\n"
        "  --quiet               no summary on stderr\n"
        "Without --target-cells or --max-volume, only the quality bound applies.\n"
        "Exit: 0 success, 1 bad input or a TetGen failure, 2 usage error.\n",
        SEARCH_RUNS, MEAN_VOLUME_RATIO);
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

/* TetGen's switches for the bounds (volume bound 0: none). */
static void make_switches(char *buf, size_t size, double radius_edge, double max_volume)
{
    if (max_volume > 0)
        snprintf(buf, size, "pq%.6ga%.6gQ", radius_edge, max_volume);
    else
        snprintf(buf, size, "pq%.6gQ", radius_edge);
}

/* v rounded to the 6 significant digits the switches carry, so that the
 * bound printed by --bound-only gives the same mesh again. */
static double six_digits(double v)
{
    char text[32];
    snprintf(text, sizeof text, "%.6g", v);
    return strtod(text, NULL);
}

/* Runs TetGen under the volume bound giving the cell count closest to
 * target: from the first guess, doubling or halving until the target is
 * bracketed, then bisecting (geometrically); at most SEARCH_RUNS runs,
 * stopping within SEARCH_TOLERANCE. mesh gets the best run's mesh, bound
 * its volume bound, runs the number of runs. Returns 0 or non-zero with msg. */
static int search_bound(const vc_surface *s, const double *holes, int64_t n_holes,
                        double radius_edge, double first, double target, vc_tetgen_mesh *mesh,
                        double *bound, int *runs, char *msg, size_t msg_len)
{
    double lo = 0, hi = 0; /* bounds known to give too many / too few cells (0: none yet) */
    double v = six_digits(first);
    *bound = 0;
    for (*runs = 1; *runs <= SEARCH_RUNS; ++*runs) {
        char switches[128];
        vc_tetgen_mesh m;
        make_switches(switches, sizeof switches, radius_edge, v);
        if (vc_tetgen_tetrahedralize(s, switches, holes, n_holes, &m, msg, msg_len) != 0)
            return 1;
        double n = (double)m.n_tets;
        if (*bound == 0 || fabs(n - target) < fabs((double)mesh->n_tets - target)) {
            vc_tetgen_mesh_free(mesh);
            *mesh = m;
            *bound = v;
        } else {
            vc_tetgen_mesh_free(&m);
        }
        if (fabs(n - target) <= SEARCH_TOLERANCE * target)
            break;
        if (n > target)
            lo = v;
        else
            hi = v;
        double next = lo > 0 && hi > 0 ? sqrt(lo * hi) : hi > 0 ? v / 2 : v * 2;
        next = six_digits(next);
        if (next == v)
            break;
        v = next;
    }
    if (*runs > SEARCH_RUNS)
        *runs = SEARCH_RUNS;
    return 0;
}

/* A point inside each cavity of s (a bounded region its triangles' normals
 * point into), for TetGen to carve out: TetGen only removes what lies
 * outside the outer shell, and meshed a hollow sphere's cavity as solid.
 * The point lies a little in front of one of the cavity's triangles (its
 * centroid moved along its normal by a share of its size, smaller until
 * the region locator puts it in that cavity). *holes (3 per cavity) is
 * allocated; returns the count, or -1 with err set. */
static int64_t cavity_points(const vc_surface *s, double **holes, vc_error *err)
{
    *holes = NULL;
    vc_regions r;
    memset(&r, 0, sizeof r);
    if (vc_surface_regions(s, &r, err) != 0)
        return -1;
    int64_t n_void = 0, n = 0;
    for (int64_t k = 0; k < r.n_regions; k++)
        n_void += r.region[k].kind == VC_REGION_VOID;
    vc_region_locator *L = NULL;
    double *h = malloc(sizeof(double) * 3 * (size_t)(n_void ? n_void : 1));
    if (!h) {
        vc_regions_free(&r);
        return vc_error_set(err, VC_ENOMEM, "out of memory locating cavities"), -1;
    }
    if (n_void > 0 && vc_region_locator_build(s, r.side_region, &L, err) != 0) {
        free(h);
        vc_regions_free(&r);
        return -1;
    }
    for (int64_t k = 0; k < r.n_regions; k++) {
        if (r.region[k].kind != VC_REGION_VOID)
            continue;
        int found = 0;
        /* from the lowest triangle on its boundary: one of the first few
         * faces it */
        for (int64_t t = r.region[k].first_triangle; t < s->n_triangles && !found; t++) {
            if (r.side_region[2 * t] != k)
                continue; /* its front side (the normal's) is not this cavity */
            const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                         *c = s->xyz + 3 * s->tri[3 * t + 2];
            double u[3], v[3], nrm[3], ctr[3];
            for (int d = 0; d < 3; d++) {
                u[d] = b[d] - a[d];
                v[d] = c[d] - a[d];
                ctr[d] = (a[d] + b[d] + c[d]) / 3;
            }
            nrm[0] = u[1] * v[2] - u[2] * v[1];
            nrm[1] = u[2] * v[0] - u[0] * v[2];
            nrm[2] = u[0] * v[1] - u[1] * v[0];
            const double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
            if (!(len > 0))
                continue;
            /* a tenth of the triangle's size, then smaller */
            for (double step = 0.1 * sqrt(0.5 * len); step > 1e-6 * sqrt(0.5 * len) && !found;
                 step *= 0.25) {
                double p[3];
                for (int d = 0; d < 3; d++)
                    p[d] = ctr[d] + step * nrm[d] / len;
                if (vc_region_locate(L, p) == k) {
                    memcpy(h + 3 * n++, p, sizeof p);
                    found = 1;
                }
            }
        }
    }
    vc_region_locator_free(L);
    vc_regions_free(&r);
    *holes = h;
    return n;
}

static int parse_positive(const char *s, double *out)
{
    double v;
    if (vc_cli_parse_double(s, &v) || v <= 0)
        return -1;
    *out = v;
    return 0;
}

int main(int argc, char **argv)
{
    const char *input = NULL, *output = NULL;
    double target = 0, max_volume = 0, radius_edge = 1.414;
    int quiet = 0, bound_only = 0;
    vc_cli_seen seen = {{NULL}, 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (vc_cli_repeated(&seen, "vc-tetgen", "vc-tetgen", a))
            return 2;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(a, "--bound-only")) {
            bound_only = 1;
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
        } else if (vc_cli_positional("vc-tetgen", "vc-tetgen", a, &input)) {
            return 2;
        }
    }
    if (!input)
        return vc_cli_missing("vc-tetgen", "vc-tetgen", "the INPUT surface");
    if (bound_only && !(target > 0)) {
        fprintf(stderr, "vc-tetgen: --bound-only needs --target-cells\n");
        return 2;
    }
    if (!output && !bound_only)
        return vc_cli_missing("vc-tetgen", "vc-tetgen", "-o OUT.vtu");
    if (target > 0 && max_volume > 0) {
        fprintf(stderr, "vc-tetgen: --target-cells and --max-volume exclude each other\n");
        return 2;
    }
    if (output && vc_cli_check_output_file_as("vc-tetgen", output))
        return 1;
    vc_cli_outputs_begin(); /* a signal while writing leaves no temporary file */

    double t0 = vc_cli_now();
    vc_error err = {0, ""};
    vc_surface s = {0, NULL, 0, NULL, NULL, 0, NULL};
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
    double t_read = vc_cli_now();
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
    double *holes = NULL;
    const int64_t n_holes = cavity_points(&s, &holes, &err);
    if (n_holes < 0) {
        fprintf(stderr, "vc-tetgen: %s: %s\n", input, err.msg);
        goto out;
    }
    double t_check = vc_cli_now();
    snprintf(crash_line, sizeof crash_line, "vc-tetgen: %s: TetGen crashed while stopping on "
             "this surface (TetGen 1.5.0 does so on features below its tolerance or facets "
             "too close together)\n", input);
    signal(SIGSEGV, on_tetgen_crash);
    signal(SIGBUS, on_tetgen_crash);
    signal(SIGABRT, on_tetgen_crash);
    int runs = 1, tetgen_rc;
    if (target > 0)
        tetgen_rc = search_bound(&s, holes, n_holes, radius_edge,
                                 MEAN_VOLUME_RATIO * rep.volume / target, target, &mesh,
                                 &max_volume, &runs, msg, sizeof msg);
    else {
        char switches[128];
        make_switches(switches, sizeof switches, radius_edge, max_volume);
        tetgen_rc = vc_tetgen_tetrahedralize(&s, switches, holes, n_holes, &mesh, msg, sizeof msg);
    }
    free(holes);
    signal(SIGSEGV, SIG_DFL);
    signal(SIGBUS, SIG_DFL);
    signal(SIGABRT, SIG_DFL);
    if (tetgen_rc != 0) {
        fprintf(stderr, "vc-tetgen: %s: %s\n", input, msg);
        goto out;
    }
    double t_mesh = vc_cli_now();
    if (bound_only) {
        printf("max volume: %.6g (%" PRId64 " tetrahedra for the target %.0f, %d TetGen runs)\n",
               max_volume, mesh.n_tets, target, runs);
        rc = 0;
        goto out;
    }
    if (vc_write_tetra_vtu(&mesh, output, &err) != 0) {
        fprintf(stderr, "vc-tetgen: %s\n", err.msg);
        goto out;
    }
    vc_cli_outputs_keep();
    double t_write = vc_cli_now();
    if (!quiet) {
        double volume = 0;
        for (int64_t t = 0; t < mesh.n_tets; t++)
            volume += vc_tetra_signed_volume(&mesh, t);
        char switches[128];
        make_switches(switches, sizeof switches, radius_edge, max_volume);
        fprintf(stderr, "vc-tetgen: %s (%" PRId64 " triangles), switches -%s\n", input,
                s.n_triangles, switches);
        fprintf(stderr, "  %" PRId64 " points, %" PRId64 " tetrahedra", mesh.n_points, mesh.n_tets);
        if (target > 0)
            fprintf(stderr, " (target %.0f, %d TetGen runs)", target, runs);
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
