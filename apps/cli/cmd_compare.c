/* vorocrust compare: runs `vorocrust mesh` and the TetGen baseline
 * (vc-tetgen) on the same input, each in its own process, measures both
 * meshes the same way (the quality library) and prints them side by side;
 * optionally an HTML report. vc-tetgen is a separate program because TetGen
 * is AGPL: nothing here links it. */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cli_util.h"
#include "commands.h"
#include "compare.h"
#include "vorocrust/mesh_report.h"
#include "vorocrust/vorocrust.h"
#include "vorocrust/surface.h"
#include "vorocrust/vtu_reader.h"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vorocrust compare INPUT [-o REPORT.html] [options]\n"
        "Meshes the closed surface INPUT with `vorocrust mesh` and with TetGen (vc-tetgen,\n"
        "found next to this program), each in its own process, and prints both meshes'\n"
        "figures side by side: time, CPU time, peak memory, vertices, cells, faces,\n"
        "volume, fatness, shortest relative edge, boundary triangle quality and angles,\n"
        "Hausdorff distance to INPUT over its bounding-box diagonal.\n"
        "  -o, --output REPORT.html  also an HTML report: the table and histograms of cell\n"
        "                    fatness and boundary triangle quality (inline SVG)\n"
        "  --threads N       threads for vorocrust mesh and the measures (default: all cores)\n"
        "  --seed N          random seed of vorocrust mesh (default 1)\n"
        "  --target-cells N  TetGen's target cell count (default: vorocrust's cell count;\n"
        "                    when vorocrust fails, TetGen runs with its quality bound only)\n"
        "  --mesh-dir DIR    keep the meshes and logs in DIR (an existing directory):\n"
        "                    vorocrust.vtu, tetgen.vtu, vorocrust.log, tetgen.log\n"
        "                    (default: a temporary directory, removed)\n"
        "  --quiet           no progress lines on stderr\n"
        "Exit: 0 when both meshers succeeded; 1 for bad input, or when a mesher failed\n"
        "(the table and the report are still printed and written, the failed column\n"
        "marked 'failed', and one line on stderr says why); 2 for a usage error.\n");
}

/* The command line as text, for the table and the report. */
static void join_command(char *const argv[], char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; argv[i] && n + 1 < size; i++) {
        int quote = strchr(argv[i], ' ') != NULL;
        int k = snprintf(buf + n, size - n, "%s%s%s%s", i ? " " : "", quote ? "'" : "", argv[i],
                         quote ? "'" : "");
        if (k < 0)
            break;
        n += (size_t)k;
    }
}

/* The segments where the plane (axis = value) crosses the faces of m's
 * cells, in the plane's two other coordinates. Returns 0 or -1 (memory). */
static int cut_mesh(const vc_vtu_mesh *m, int axis, double value, double **out, int64_t *n_out)
{
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    int64_t n = 0, cap = 1024;
    double *seg = malloc(sizeof(double) * 4 * (size_t)cap);
    if (!seg)
        return -1;
    for (int64_t f = 0; f < m->n_faces; f++) {
        const int64_t b = m->face_offsets[f], k = m->face_offsets[f + 1] - b;
        double pts[2][2];
        int np = 0;
        for (int64_t i = 0; i < k && np < 2; i++) {
            const double *p = m->points + 3 * m->face_vertices[b + i];
            const double *q = m->points + 3 * m->face_vertices[b + (i + 1) % k];
            const double dp = p[axis] - value, dq = q[axis] - value;
            if ((dp < 0) == (dq < 0))
                continue;
            const double t = dp / (dp - dq);
            pts[np][0] = p[u] + t * (q[u] - p[u]);
            pts[np][1] = p[v] + t * (q[v] - p[v]);
            np++;
        }
        if (np < 2)
            continue;
        if (n == cap) {
            cap *= 2;
            double *s2 = realloc(seg, sizeof(double) * 4 * (size_t)cap);
            if (!s2) {
                free(seg);
                return -1;
            }
            seg = s2;
        }
        memcpy(seg + 4 * n, pts, sizeof pts);
        n++;
    }
    *out = seg;
    *n_out = n;
    return 0;
}

/* Reads and measures a mesher's output into side, and cuts it; 0, or -1
 * with side->failure set. */
static int measure(vc_compare_side *side, const char *mesh_path, const vc_surface *input,
                   const char *input_path, int cut_axis, double cut_value)
{
    vc_error err = {0, ""};
    vc_vtu_mesh m;
    if (vc_vtu_read(mesh_path, &m, &err) != 0 ||
        vc_mesh_report_compute(&m, mesh_path, input, input_path, &side->report, &err) != 0) {
        snprintf(side->failure, sizeof side->failure, "%s", err.msg);
        vc_vtu_mesh_free(&m);
        return -1;
    }
    if (cut_mesh(&m, cut_axis, cut_value, &side->cut, &side->n_cut) != 0) {
        snprintf(side->failure, sizeof side->failure, "%s: out of memory cutting the mesh",
                 mesh_path);
        vc_vtu_mesh_free(&m);
        return -1;
    }
    vc_vtu_mesh_free(&m);
    side->ok = 1;
    return 0;
}

/* Runs one mesher and measures its mesh. */
static void read_summary(vc_compare_side *side, const char *log_path);

static void run_side(vc_compare_side *side, char *const argv[], const char *mesh_path,
                     const char *log_path, const vc_surface *input, const char *input_path,
                     int quiet, int cut_axis, double cut_value)
{
    join_command(argv, side->command, sizeof side->command);
    if (!quiet)
        fprintf(stderr, "vorocrust compare: running %s\n", side->command);
    if (vc_child_run(argv, log_path, &side->run) != 0) {
        snprintf(side->failure, sizeof side->failure, "%s", side->run.message);
        return;
    }
    if (!quiet)
        fprintf(stderr, "vorocrust compare: %s done in %.2f s, measuring %s\n", side->name,
                side->run.wall_seconds, mesh_path);
    read_summary(side, log_path);
    measure(side, mesh_path, input, input_path, cut_axis, cut_value);
}

/* What vorocrust's summary (in its log) says of the run: its phase times
 * and whether it sampled twice. */
static void read_summary(vc_compare_side *side, const char *log_path)
{
    FILE *fp = fopen(log_path, "r");
    char line[4096];
    while (fp && fgets(line, sizeof line, fp)) {
        line[strcspn(line, "\n")] = 0;
        const char *p = strstr(line, "  time (s): ");
        if (p == line)
            snprintf(side->phases, sizeof side->phases, "%.1000s", line + 12);
        p = strstr(line, ", after sampling at ");
        if (p && strstr(line, "vorocrust mesh: ") == line) {
            side->resampled = 1;
            snprintf(side->resample_note, sizeof side->resample_note, "%.*s", (int)strcspn(p + 2, ")"),
                     p + 2);
        }
        if (strstr(line, "sampling again with") && !side->resample_note[0]) {
            side->resampled = 1;
            snprintf(side->resample_note, sizeof side->resample_note, "%.250s", line);
        }
    }
    if (fp)
        fclose(fp);
}

static void print_table(const vc_compare *c)
{
    printf("compare: %s (%" PRId64 " triangles, enclosed volume %.10g, bounding-box diagonal %.6g)\n",
           c->input, c->input_triangles, c->input_volume, c->input_diagonal);
    printf("%-28s  %16s  %16s\n", "metric", c->side[0].name, c->side[1].name);
    for (int r = 0; r < vc_compare_row_count(); r++) {
        char a[64], b[64];
        vc_compare_row_value(c, 0, r, a, sizeof a);
        vc_compare_row_value(c, 1, r, b, sizeof b);
        printf("%-28s  %16s  %16s\n", vc_compare_row_name(r), a, b);
    }
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        if (c->side[s].command[0])
            printf("command %s: %s\n", c->side[s].name, c->side[s].command);
    if (c->tetgen_target)
        printf("tetgen target cells: %" PRId64 " (volume bound from: %s)\n", c->tetgen_target,
               c->tetgen_bound_command);
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        if (!c->side[s].ok)
            printf("failed %s: %s\n", c->side[s].name, c->side[s].failure);
}

/* The bound from the log of `vc-tetgen --bound-only` ("max volume: V ...")
 * into buf, as printed; 0, or -1 when there is none. */
static int read_bound(const char *log_path, char *buf, size_t size)
{
    FILE *fp = fopen(log_path, "r");
    char line[512];
    int rc = -1;
    while (fp && rc && fgets(line, sizeof line, fp)) {
        char value[64];
        double v;
        if (sscanf(line, "max volume: %63s", value) == 1 && !vc_cli_parse_double(value, &v) &&
            v > 0) {
            snprintf(buf, size, "%s", value);
            rc = 0;
        }
    }
    if (fp)
        fclose(fp);
    return rc;
}

/* Removes the files compare made in its temporary directory, then it. */
static void remove_work_dir(const char *dir, char paths[][4096], int n)
{
    for (int i = 0; i < n; i++)
        unlink(paths[i]);
    rmdir(dir);
}

int vc_cmd_compare(int argc, char **argv)
{
    const char *input_path = NULL, *report_path = NULL, *mesh_dir = NULL;
    const char *threads = NULL, *seed = "1";
    long target = 0;
    int quiet = 0;
    vc_cli_seen seen = {{NULL}, 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (vc_cli_repeated(&seen, "vorocrust", "vorocrust compare", a))
            return 2;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output") || !strcmp(a, "--threads") ||
                   !strcmp(a, "--seed") || !strcmp(a, "--target-cells") ||
                   !strcmp(a, "--mesh-dir")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "vorocrust: %s needs a value (see 'vorocrust compare --help')\n", a);
                return 2;
            }
            const char *v = argv[++i];
            long x;
            if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
                report_path = v;
            } else if (!strcmp(a, "--mesh-dir")) {
                mesh_dir = v;
            } else if (!strcmp(a, "--threads")) {
                if (vc_cli_parse_int(v, 1, 4096, &x)) {
                    fprintf(stderr, "vorocrust: --threads: '%s' is not a count from 1 to 4096\n", v);
                    return 2;
                }
                threads = v;
#ifdef _OPENMP
                omp_set_num_threads((int)x);
#endif
            } else if (!strcmp(a, "--seed")) {
                if (vc_cli_parse_int(v, 0, 2147483647L, &x)) {
                    fprintf(stderr, "vorocrust: --seed: '%s' is not an integer from 0 to 2147483647\n", v);
                    return 2;
                }
                seed = v;
            } else if (vc_cli_parse_int(v, 1, 1000000000L, &target)) {
                fprintf(stderr, "vorocrust: --target-cells: '%s' is not a count from 1 to 1e9\n", v);
                return 2;
            }
        } else if (vc_cli_positional("vorocrust", "vorocrust compare", a, &input_path)) {
            return 2;
        }
    }
    if (!input_path)
        return vc_cli_missing("vorocrust", "vorocrust compare", "the INPUT surface");
    if (report_path && vc_cli_check_output_file(report_path))
        return 1;
    struct stat st;
    if (mesh_dir && (stat(mesh_dir, &st) != 0 || !S_ISDIR(st.st_mode) || access(mesh_dir, W_OK))) {
        fprintf(stderr, "vorocrust: --mesh-dir %s: not a writable directory\n", mesh_dir);
        return 1;
    }

    /* The input is checked here, so that a bad one is one line, not two
     * failed meshers. */
    vc_error err = {0, ""};
    vc_surface input = {0, NULL, 0, NULL, NULL, 0, NULL};
    vc_surface_report rep;
    if (vc_surface_read(input_path, &input, &rep, &err) != 0 ||
        vc_surface_require_closed(&rep, &err) != 0) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        vc_surface_free(&input);
        return 1;
    }

    char self[4096], tetgen[4096 + 16];
    if (vc_self_executable(self, sizeof self) != 0) {
        fprintf(stderr, "vorocrust: compare: cannot find the running executable (/proc/self/exe)\n");
        vc_surface_free(&input);
        return 1;
    }
    snprintf(tetgen, sizeof tetgen, "%.*s/vc-tetgen", (int)(strrchr(self, '/') - self), self);
    if (access(tetgen, X_OK) != 0) {
        fprintf(stderr, "vorocrust: compare: %s: not found or not executable (vc-tetgen is built "
                "next to vorocrust when TetGen, libtet1.5-dev, is installed)\n", tetgen);
        vc_surface_free(&input);
        return 1;
    }

    char work[3968]; /* room left in paths for "/vorocrust.log" */
    int work_slot = -1;
    vc_cli_outputs_begin(); /* a signal removes the work directory and the report */
    if (mesh_dir) {
        snprintf(work, sizeof work, "%s", mesh_dir);
    } else {
        const char *tmp = getenv("TMPDIR");
        snprintf(work, sizeof work, "%s/vc-compare.XXXXXX", tmp && *tmp ? tmp : "/tmp");
        if (!mkdtemp(work)) {
            fprintf(stderr, "vorocrust: compare: cannot create a temporary directory %s: %s\n",
                    work, strerror(errno));
            vc_surface_free(&input);
            return 1;
        }
        work_slot = vc_cli_track_temp_dir(work);
    }
    enum { VORO_MESH, VORO_LOG, TET_MESH, TET_LOG, TET_BOUND_LOG, VORO_BOUNDARY, N_PATHS };
    static const char *const names[N_PATHS] = {"vorocrust.vtu", "vorocrust.log", "tetgen.vtu",
                                               "tetgen.log", "tetgen-bound.log",
                                               "vorocrust_boundary.vtu"};
    char paths[N_PATHS][4096];
    for (int i = 0; i < N_PATHS; i++) {
        snprintf(paths[i], sizeof paths[i], "%s/%s", work, names[i]);
        if (mesh_dir)
            unlink(paths[i]); /* a stale mesh must not pass for a new one */
    }

    vc_compare c;
    memset(&c, 0, sizeof c);
    c.input = input_path;
    c.input_triangles = input.n_triangles;
    c.input_volume = rep.volume;
    c.input_diagonal = sqrt((rep.bbox[3] - rep.bbox[0]) * (rep.bbox[3] - rep.bbox[0]) +
                            (rep.bbox[4] - rep.bbox[1]) * (rep.bbox[4] - rep.bbox[1]) +
                            (rep.bbox[5] - rep.bbox[2]) * (rep.bbox[5] - rep.bbox[2]));
    c.side[VC_COMPARE_VOROCRUST].name = "vorocrust";
    c.side[VC_COMPARE_TETGEN].name = "tetgen";
    /* the run: version, date, threads; the cut through the middle of the
     * box, across its smallest extent */
    memcpy(c.bbox, rep.bbox, sizeof c.bbox);
    c.cut_axis = 0;
    for (int k = 1; k < 3; k++)
        if (rep.bbox[k + 3] - rep.bbox[k] < rep.bbox[c.cut_axis + 3] - rep.bbox[c.cut_axis])
            c.cut_axis = k;
    c.cut_value = 0.5 * (rep.bbox[c.cut_axis] + rep.bbox[c.cut_axis + 3]);
    snprintf(c.version, sizeof c.version, "%s", vc_version());
    {
        time_t now = time(NULL);
        struct tm tmv;
        if (gmtime_r(&now, &tmv))
            strftime(c.date, sizeof c.date, "%Y-%m-%d %H:%M UTC", &tmv);
    }
    long nthreads = 0;
    if (threads)
        vc_cli_parse_int(threads, 1, 4096, &nthreads);
#ifdef _OPENMP
    c.threads = threads ? (int)nthreads : omp_get_max_threads();
#else
    c.threads = 1;
#endif
    c.work_dir = mesh_dir ? NULL : work;

    /* vorocrust first: its cell count is TetGen's target. */
    {
        char *args[16];
        int n = 0;
        args[n++] = self;
        args[n++] = "mesh";
        args[n++] = (char *)input_path;
        args[n++] = "-o";
        args[n++] = paths[VORO_MESH];
        args[n++] = "--seed";
        args[n++] = (char *)seed;
        if (threads) {
            args[n++] = "--threads";
            args[n++] = (char *)threads;
        }
        args[n] = NULL;
        run_side(&c.side[VC_COMPARE_VOROCRUST], args, paths[VORO_MESH], paths[VORO_LOG], &input,
                 input_path, quiet, c.cut_axis, c.cut_value);
    }
    c.tetgen_target = target ? target
                    : c.side[VC_COMPARE_VOROCRUST].ok ? c.side[VC_COMPARE_VOROCRUST].report.n_cells
                    : 0;
    /* TetGen: the volume bound for the target is searched in a first run
     * (several TetGen runs), so that the measured run is a single one. */
    vc_compare_side *tet = &c.side[VC_COMPARE_TETGEN];
    char bound_text[64] = "";
    if (c.tetgen_target) {
        char target_text[32];
        snprintf(target_text, sizeof target_text, "%" PRId64, c.tetgen_target);
        char *args[] = {tetgen, (char *)input_path, "--target-cells", target_text, "--bound-only",
                        NULL};
        join_command(args, c.tetgen_bound_command, sizeof c.tetgen_bound_command);
        if (!quiet)
            fprintf(stderr, "vorocrust compare: running %s\n", c.tetgen_bound_command);
        vc_child_result bound_run;
        if (vc_child_run(args, paths[TET_BOUND_LOG], &bound_run) != 0 ||
            read_bound(paths[TET_BOUND_LOG], bound_text, sizeof bound_text) != 0) {
            snprintf(tet->failure, sizeof tet->failure, "finding the volume bound: %s",
                     bound_run.message[0] ? bound_run.message : "no 'max volume:' line");
            join_command(args, tet->command, sizeof tet->command);
        }
    }
    if (!tet->failure[0]) {
        char *args[] = {tetgen, (char *)input_path, "-o", paths[TET_MESH], "--max-volume",
                        bound_text, NULL};
        if (!bound_text[0])
            args[4] = NULL; /* no target: TetGen's quality bound alone */
        run_side(tet, args, paths[TET_MESH], paths[TET_LOG], &input, input_path, quiet,
                 c.cut_axis, c.cut_value);
    }
    print_table(&c);
    fflush(stdout);
    int rc = 0;
    for (int s = 0; s < VC_COMPARE_SIDES; s++)
        if (!c.side[s].ok) {
            fprintf(stderr, "vorocrust: compare: %s: %s failed: %s\n", input_path, c.side[s].name,
                    c.side[s].failure);
            rc = 1;
        }
    if (report_path && vc_compare_write_html(&c, report_path, &err) != 0) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        rc = 1;
    }
    vc_cli_outputs_keep();
    if (!mesh_dir) {
        remove_work_dir(work, paths, N_PATHS);
        vc_cli_untrack(work_slot);
    }
    for (int s = 0; s < VC_COMPARE_SIDES; s++) {
        vc_mesh_report_free(&c.side[s].report);
        free(c.side[s].cut);
    }
    vc_surface_free(&input);
    return rc;
}
