/* vc-bench-voronoi: figures for the Voronoi engine against Voro++.
 *
 * For every N, N uniform random seeds in the unit cube (the project's RNG,
 * all labels 1) are meshed by vc_voronoi_build for each thread count, and
 * by Voro++ once (it is single-threaded). Every run happens in its own
 * forked child, so the peak memory (the child's ru_maxrss from wait4) is
 * that run's alone; the child generates the seeds, times only the engine
 * call (CLOCK_MONOTONIC wall time, plus the process CPU time) and sends its
 * figures back through a pipe. A "seeds only" child gives the baseline
 * memory of the process plus the input.
 *
 * Results go to stdout as a table; progress goes to stderr. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE 1
#endif

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "vorocrust/error.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/random.h"
#include "vorocrust/seeds.h"
#include "vorocrust/voronoi.h"
#include "voropp_adapter.h"

#define MAX_LIST 32
#define MSG_LEN (VC_ERROR_LEN + 64)

enum engine { ENGINE_SEEDS, ENGINE_VOROCRUST, ENGINE_VOROPP };

static const char *engine_name(int e)
{
    return e == ENGINE_SEEDS ? "seeds only" : e == ENGINE_VOROCRUST ? "vorocrust" : "Voro++";
}

/* What a child sends back to the parent (fixed size, one write). */
typedef struct child_report {
    int ok;
    double seconds;     /* wall time of the engine call */
    double cpu_seconds; /* process CPU time of the engine call */
    double volume;      /* sum of the cell volumes */
    int64_t cells, points, faces, interior_faces, boundary_faces;
    int64_t cell_faces; /* sum over cells of their face count */
    int64_t invalid;    /* vc_polymesh_validate problems; -1 if not run */
    uint64_t digest;    /* of the mesh's points, faces and cells (vorocrust) */
    int grid[3];        /* Voro++ block grid */
    /* --rebuild K: the mesh again after K kept seeds moved, from the kept
     * cells (vc_voronoi_rebuild) and from scratch (vc_voronoi_build) */
    double rebuild_seconds, fresh_seconds;
    int64_t rebuilt_cells;
    int rebuild_same;   /* the two meshes byte-identical */
    char msg[MSG_LEN];
} child_report;

/* One measured configuration (best of --repeat runs). */
typedef struct run {
    int engine, threads, done, ok;
    int64_t n;
    child_report rep;
    double maxrss_mib; /* largest over the repeats */
    char failure[MSG_LEN];
} run;

typedef struct config {
    int64_t n_list[MAX_LIST];
    int n_count;
    int threads[MAX_LIST];
    int threads_count;
    uint64_t seed;
    int skip_voropp, skip_vorocrust, validate, repeat;
    const char *seeds_path; /* a seeds CSV instead of random seeds */
    int keep_labels;        /* cells only for its seeds of a non-zero label */
    int64_t rebuild;        /* seeds moved for the rebuild figures (0: none) */
} config;

static double clock_seconds(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int write_all(int fd, const void *buf, size_t len)
{
    const char *p = buf;
    while (len > 0) {
        ssize_t w = write(fd, p, len);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        len -= (size_t)w;
    }
    return 0;
}

static size_t read_all(int fd, void *buf, size_t len)
{
    char *p = buf;
    size_t got = 0;
    while (got < len) {
        ssize_t r = read(fd, p + got, len - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        got += (size_t)r;
    }
    return got;
}

/* The seeds of a run, and the box: N random seeds in the unit cube, or
 * the seeds of cfg->seeds_path (every one kept, or, with --keep-labels, those
 * of a non-zero label), in their bounding box grown by 1% of its diagonal on
 * every side. */
/* FNV-1a over bytes, continued from h. */
static uint64_t fnv1a(uint64_t h, const void *data, size_t len)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* A digest of the mesh's bytes: equal digests for the runs of one N on
 * different thread counts stand for byte-identical meshes. */
static uint64_t mesh_digest(const vc_polymesh *m)
{
    uint64_t h = 14695981039346656037ull;
    h = fnv1a(h, m->points, (size_t)m->n_points * 3 * sizeof(double));
    h = fnv1a(h, m->face_offsets, (size_t)(m->n_faces + 1) * sizeof(int64_t));
    h = fnv1a(h, m->face_vertices, (size_t)m->face_offsets[m->n_faces] * sizeof(int64_t));
    h = fnv1a(h, m->face_owner, (size_t)m->n_faces * sizeof(int64_t));
    h = fnv1a(h, m->face_neighbour, (size_t)m->n_faces * sizeof(int64_t));
    h = fnv1a(h, m->cell_faces, (size_t)m->cell_offsets[m->n_cells] * sizeof(int64_t));
    return h;
}

static int make_seeds(vc_seeds *s, int64_t n, const config *cfg, double box[6], vc_error *err)
{
    if (cfg->seeds_path) {
        int rc = vc_seeds_read_csv(cfg->seeds_path, s, err);
        if (rc)
            return rc;
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int64_t i = 0; i < s->n; i++) {
            if (!cfg->keep_labels)
                s->label[i] = 1;
            for (int d = 0; d < 3; d++) {
                lo[d] = fmin(lo[d], s->xyz[3 * i + d]);
                hi[d] = fmax(hi[d], s->xyz[3 * i + d]);
            }
        }
        const double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                 (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                 (hi[2] - lo[2]) * (hi[2] - lo[2]));
        for (int d = 0; d < 3; d++) {
            box[d] = lo[d] - 0.01 * diag;
            box[d + 3] = hi[d] + 0.01 * diag;
        }
        return VC_OK;
    }
    for (int d = 0; d < 3; d++) {
        box[d] = 0;
        box[d + 3] = 1;
    }
    const uint64_t seed = cfg->seed;
    int rc = vc_seeds_alloc(s, n, err);
    if (rc)
        return rc;
    vc_rng rng;
    vc_rng_init(&rng, seed, 0);
    for (int64_t i = 0; i < 3 * n; i++)
        s->xyz[i] = vc_rng_uniform(&rng);
    return VC_OK; /* labels are already 1 */
}

/* Moves k kept seeds (distinct, at random, none on the seeds' bounding
 * box, so that it stays) by up to a tenth of the mean spacing per axis,
 * kept strictly inside the bounds; their indices into moved. Returns how
 * many moved. */
static int64_t move_kept(vc_seeds *s, int64_t k, uint64_t seed, int64_t *moved)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < s->n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * i + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * i + d]);
        }
    const double step = 0.1 * cbrt((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]) /
                                   (double)s->n);
    unsigned char *taken = calloc((size_t)s->n, 1);
    if (!taken)
        return 0;
    vc_rng rng;
    vc_rng_init(&rng, seed, 7);
    int64_t m = 0;
    for (int64_t tries = 0; m < k && tries < 100 * k; tries++) {
        int64_t i = (int64_t)(vc_rng_uniform(&rng) * (double)s->n);
        i = i < s->n ? i : s->n - 1;
        int edge = taken[i] || s->label[i] == 0;
        for (int d = 0; d < 3; d++)
            edge |= s->xyz[3 * i + d] == lo[d] || s->xyz[3 * i + d] == hi[d];
        if (edge)
            continue;
        taken[i] = 1;
        for (int d = 0; d < 3; d++) {
            const double x = s->xyz[3 * i + d] + step * (2 * vc_rng_uniform(&rng) - 1);
            const double a = lo[d] + 1e-9 * (hi[d] - lo[d]), b = hi[d] - 1e-9 * (hi[d] - lo[d]);
            s->xyz[3 * i + d] = x < a ? a : x > b ? b : x;
        }
        moved[m++] = i;
    }
    free(taken);
    return m;
}

/* The body of a measuring child: never returns. */
static void child_main(int fd, int engine, int64_t n, int threads, const config *cfg)
{
    child_report rep;
    memset(&rep, 0, sizeof rep);
    rep.invalid = -1;
    vc_error err;
    memset(&err, 0, sizeof err);
    vc_seeds seeds;
    double box[6];

    if (make_seeds(&seeds, n, cfg, box, &err)) {
        snprintf(rep.msg, sizeof rep.msg, "%s", err.msg);
    } else if (engine == ENGINE_SEEDS) {
        rep.ok = 1;
    } else if (engine == ENGINE_VOROCRUST) {
        vc_voronoi_options opt;
        vc_voronoi_options_default(&opt);
        opt.threads = threads;
        opt.has_box = 1;
        memcpy(opt.box, box, sizeof box);
        vc_polymesh mesh;
        vc_voronoi_cells *kept = NULL;
        double c0 = clock_seconds(CLOCK_PROCESS_CPUTIME_ID);
        double t0 = clock_seconds(CLOCK_MONOTONIC);
        int rc = cfg->rebuild > 0 ? vc_voronoi_build_keep(&seeds, &opt, &mesh, &kept, &err)
                                  : vc_voronoi_build(&seeds, &opt, &mesh, &err);
        rep.seconds = clock_seconds(CLOCK_MONOTONIC) - t0;
        rep.cpu_seconds = clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - c0;
        if (rc) {
            snprintf(rep.msg, sizeof rep.msg, "vc_voronoi_build: %s", err.msg);
        } else {
            rep.ok = 1;
            rep.cells = mesh.n_cells;
            rep.points = mesh.n_points;
            rep.faces = mesh.n_faces;
            rep.interior_faces = mesh.n_interior_faces;
            rep.boundary_faces = mesh.n_faces - mesh.n_interior_faces;
            rep.cell_faces = mesh.cell_offsets[mesh.n_cells];
            double v = 0.0;
            for (int64_t c = 0; c < mesh.n_cells; c++)
                v += mesh.cell_volume[c];
            rep.volume = v / ((box[3] - box[0]) * (box[4] - box[1]) * (box[5] - box[2]));
            rep.digest = mesh_digest(&mesh);
            if (cfg->validate) {
                char report[200];
                report[0] = '\0';
                rep.invalid = vc_polymesh_validate(&mesh, 0.0, report, sizeof report);
                if (rep.invalid)
                    snprintf(rep.msg, sizeof rep.msg, "%s", report);
            }
            vc_polymesh_free(&mesh);
        }
        if (rep.ok && kept) {
            int64_t *moved = malloc(sizeof(int64_t) * (size_t)cfg->rebuild);
            const int64_t k = moved ? move_kept(&seeds, cfg->rebuild, cfg->seed, moved) : 0;
            vc_polymesh a, b;
            double t1 = clock_seconds(CLOCK_MONOTONIC);
            int ra = vc_voronoi_rebuild(kept, &seeds, moved, k, &opt, &a, &err);
            rep.rebuild_seconds = clock_seconds(CLOCK_MONOTONIC) - t1;
            rep.rebuilt_cells = vc_voronoi_cells_rebuilt(kept);
            t1 = clock_seconds(CLOCK_MONOTONIC);
            int rb = ra ? -1 : vc_voronoi_build(&seeds, &opt, &b, &err);
            rep.fresh_seconds = clock_seconds(CLOCK_MONOTONIC) - t1;
            if (ra || rb || k < cfg->rebuild) {
                rep.ok = 0;
                snprintf(rep.msg, sizeof rep.msg, "rebuild: %s",
                         k < cfg->rebuild ? "could not pick the seeds to move" : err.msg);
            } else {
                rep.rebuild_same = mesh_digest(&a) == mesh_digest(&b);
            }
            if (!ra)
                vc_polymesh_free(&a);
            if (!ra && !rb)
                vc_polymesh_free(&b);
            free(moved);
        }
        vc_voronoi_cells_free(kept);
    } else {
        vc_bench_voropp_result vr;
        double c0 = clock_seconds(CLOCK_PROCESS_CPUTIME_ID);
        double t0 = clock_seconds(CLOCK_MONOTONIC);
        int rc = vc_bench_voropp(seeds.xyz, n, box, &vr, rep.msg, sizeof rep.msg);
        rep.seconds = clock_seconds(CLOCK_MONOTONIC) - t0;
        rep.cpu_seconds = clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - c0;
        if (rc == 0) {
            rep.ok = 1;
            rep.cells = vr.cells;
            rep.cell_faces = vr.cell_faces;
            rep.boundary_faces = vr.boundary_faces;
            rep.interior_faces = (vr.cell_faces - vr.boundary_faces) / 2;
            rep.volume = vr.volume / ((box[3] - box[0]) * (box[4] - box[1]) * (box[5] - box[2]));
            memcpy(rep.grid, vr.grid, sizeof rep.grid);
        }
    }
    int wrc = write_all(fd, &rep, sizeof rep);
    close(fd);
    _exit(wrc == 0 ? 0 : 3);
}

/* Runs one measurement in a forked child. Returns 1 on success. */
static int measure_once(int engine, int64_t n, int threads, const config *cfg,
                        child_report *rep, double *maxrss_mib, char *failure)
{
    int fds[2];
    if (pipe(fds) != 0) {
        snprintf(failure, MSG_LEN, "pipe: %s", strerror(errno));
        return 0;
    }
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(failure, MSG_LEN, "fork: %s", strerror(errno));
        close(fds[0]);
        close(fds[1]);
        return 0;
    }
    if (pid == 0) {
        close(fds[0]);
        child_main(fds[1], engine, n, threads, cfg);
    }
    close(fds[1]);
    size_t got = read_all(fds[0], rep, sizeof *rep);
    close(fds[0]);

    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    while (wait4(pid, &status, 0, &ru) < 0) {
        if (errno != EINTR) {
            snprintf(failure, MSG_LEN, "wait4: %s", strerror(errno));
            return 0;
        }
    }
    *maxrss_mib = (double)ru.ru_maxrss / 1024.0; /* ru_maxrss is in KiB on Linux */
    if (WIFSIGNALED(status)) {
        snprintf(failure, MSG_LEN, "child killed by signal %d%s", WTERMSIG(status),
                 WTERMSIG(status) == SIGKILL ? " (out of memory?)" : "");
        return 0;
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || got != sizeof *rep) {
        snprintf(failure, MSG_LEN, "child failed (exit status %d, %zu of %zu report bytes)",
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1, got, sizeof *rep);
        return 0;
    }
    rep->msg[MSG_LEN - 1] = '\0';
    if (!rep->ok) {
        snprintf(failure, MSG_LEN, "%s", rep->msg);
        return 0;
    }
    return 1;
}

static void measure(run *r, const config *cfg)
{
    r->done = 1;
    r->ok = 0;
    r->maxrss_mib = 0.0;
    for (int k = 0; k < cfg->repeat; k++) {
        child_report rep;
        double rss = 0.0;
        char failure[MSG_LEN] = "";
        int ok = measure_once(r->engine, r->n, r->threads, cfg, &rep, &rss, failure);
        if (rss > r->maxrss_mib)
            r->maxrss_mib = rss;
        if (!ok) {
            r->ok = 0;
            snprintf(r->failure, sizeof r->failure, "%s", failure);
            fprintf(stderr, "[vc-bench-voronoi] N=%" PRId64 " %s threads=%d: FAILED: %s\n", r->n,
                    engine_name(r->engine), r->threads, failure);
            return;
        }
        if (!r->ok || rep.seconds < r->rep.seconds)
            r->rep = rep;
        r->ok = 1;
        if (r->engine != ENGINE_SEEDS)
            fprintf(stderr,
                    "[vc-bench-voronoi] N=%" PRId64 " %s threads=%d run %d/%d: %.3f s, "
                    "peak %.1f MiB\n",
                    r->n, engine_name(r->engine), r->threads, k + 1, cfg->repeat, rep.seconds, rss);
    }
}

/* ---- command line ---- */

static void usage(FILE *f)
{
    fprintf(f,
            "usage: vc-bench-voronoi [options]\n"
            "  --n N[,N...]           seed counts (repeatable; default 100000,1000000)\n"
            "  --threads-list T[,T...] vorocrust thread counts (default 1,2)\n"
            "  --seed S               random seed (default 1)\n"
            "  --seeds FILE.csv       these seeds (x,y,z[,label]; all kept) in their bounding box\n"
            "                         grown by 1%% of its diagonal, instead of random ones\n"
            "  --keep-labels          with --seeds: cells only for the seeds of a non-zero label\n"
            "                         (the others only cut them: a mesh's outside seeds)\n"
            "  --repeat R             runs per configuration, the fastest is reported (default 1)\n"
            "  --skip-voropp          do not run Voro++\n"
            "  --skip-vorocrust       do not run vorocrust\n"
            "  --validate             check every vorocrust mesh with vc_polymesh_validate\n"
            "                         (after the timing)\n"
            "  --rebuild K            also move K kept seeds (by a tenth of the mean spacing) and\n"
            "                         time the mesh again from the kept cells (vc_voronoi_rebuild)\n"
            "                         against a fresh build of the moved seeds\n"
            "  --help\n");
}

/* Parses a positive integer, allowing forms like 1e6. */
static int parse_count(const char *s, int64_t max, int64_t *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !(v >= 1.0) || v > (double)max ||
        v != floor(v))
        return 0;
    *out = (int64_t)v;
    return 1;
}

static int parse_list(const char *opt, const char *arg, int64_t max, int64_t *list, int *count)
{
    char buf[512];
    if (strlen(arg) >= sizeof buf) {
        fprintf(stderr, "vc-bench-voronoi: %s: argument too long\n", opt);
        return 0;
    }
    strcpy(buf, arg);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        int64_t v;
        if (!parse_count(tok, max, &v)) {
            fprintf(stderr, "vc-bench-voronoi: %s: '%s' is not a positive integer <= %" PRId64 "\n",
                    opt, tok, max);
            return 0;
        }
        if (*count >= MAX_LIST) {
            fprintf(stderr, "vc-bench-voronoi: %s: more than %d values\n", opt, MAX_LIST);
            return 0;
        }
        list[(*count)++] = v;
    }
    return 1;
}

static int parse_args(int argc, char **argv, config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->seed = 1;
    cfg->repeat = 1;
    for (int i = 1; i < argc; i++) {
        char name[64];
        const char *a = argv[i], *val = NULL;
        const char *eq = strchr(a, '=');
        if (strncmp(a, "--", 2) == 0 && eq && (size_t)(eq - a) < sizeof name) {
            memcpy(name, a, (size_t)(eq - a));
            name[eq - a] = '\0';
            val = eq + 1;
        } else {
            snprintf(name, sizeof name, "%s", a);
        }
        int takes_value = !strcmp(name, "--n") || !strcmp(name, "--threads-list") ||
                          !strcmp(name, "--seed") || !strcmp(name, "--repeat") ||
                          !strcmp(name, "--seeds") || !strcmp(name, "--rebuild");
        if (takes_value && !val) {
            if (i + 1 >= argc) {
                fprintf(stderr, "vc-bench-voronoi: %s needs a value\n", name);
                return 0;
            }
            val = argv[++i];
        } else if (!takes_value && val) {
            fprintf(stderr, "vc-bench-voronoi: %s takes no value\n", name);
            return 0;
        }
        if (!strcmp(name, "--n")) {
            if (!parse_list(name, val, INT32_MAX, cfg->n_list, &cfg->n_count))
                return 0;
        } else if (!strcmp(name, "--threads-list")) {
            int64_t tmp[MAX_LIST];
            int cnt = 0;
            if (!parse_list(name, val, 4096, tmp, &cnt))
                return 0;
            for (int k = 0; k < cnt; k++) {
                if (cfg->threads_count >= MAX_LIST) {
                    fprintf(stderr, "vc-bench-voronoi: too many thread counts\n");
                    return 0;
                }
                cfg->threads[cfg->threads_count++] = (int)tmp[k];
            }
        } else if (!strcmp(name, "--seed")) {
            char *end = NULL;
            errno = 0;
            unsigned long long s = strtoull(val, &end, 0);
            if (end == val || *end != '\0' || errno != 0 || val[0] == '-') {
                fprintf(stderr, "vc-bench-voronoi: --seed: '%s' is not an unsigned integer\n", val);
                return 0;
            }
            cfg->seed = (uint64_t)s;
        } else if (!strcmp(name, "--repeat")) {
            int64_t r;
            if (!parse_count(val, 1000, &r)) {
                fprintf(stderr, "vc-bench-voronoi: --repeat: '%s' is not in 1..1000\n", val);
                return 0;
            }
            cfg->repeat = (int)r;
        } else if (!strcmp(name, "--seeds")) {
            cfg->seeds_path = val;
        } else if (!strcmp(name, "--keep-labels")) {
            cfg->keep_labels = 1;
        } else if (!strcmp(name, "--rebuild")) {
            if (!parse_count(val, INT32_MAX, &cfg->rebuild)) {
                fprintf(stderr, "vc-bench-voronoi: --rebuild: '%s' is not a positive integer\n", val);
                return 0;
            }
        } else if (!strcmp(name, "--skip-voropp")) {
            cfg->skip_voropp = 1;
        } else if (!strcmp(name, "--skip-vorocrust")) {
            cfg->skip_vorocrust = 1;
        } else if (!strcmp(name, "--validate")) {
            cfg->validate = 1;
        } else if (!strcmp(name, "--help") || !strcmp(name, "-h")) {
            usage(stdout);
            exit(0);
        } else {
            fprintf(stderr, "vc-bench-voronoi: unknown option '%s'\n", a);
            usage(stderr);
            return 0;
        }
    }
    if (cfg->seeds_path) {
        if (cfg->n_count) {
            fprintf(stderr, "vc-bench-voronoi: --seeds and --n exclude each other\n");
            return 0;
        }
        vc_seeds s;
        vc_error err;
        if (vc_seeds_read_csv(cfg->seeds_path, &s, &err)) {
            fprintf(stderr, "vc-bench-voronoi: %s\n", err.msg);
            return 0;
        }
        cfg->n_list[0] = s.n;
        cfg->n_count = 1;
        vc_seeds_free(&s);
    }
    if (cfg->n_count == 0) {
        cfg->n_list[0] = 100000;
        cfg->n_list[1] = 1000000;
        cfg->n_count = 2;
    }
    if (cfg->threads_count == 0) {
        cfg->threads[0] = 1;
        cfg->threads[1] = 2;
        cfg->threads_count = 2;
    }
    return 1;
}

/* ---- output ---- */

static double rate(const run *r)
{
    return r->ok && r->rep.seconds > 0 ? (double)r->n / r->rep.seconds : 0.0;
}

static void print_row(const run *r)
{
    char threads[16];
    if (r->engine == ENGINE_SEEDS)
        snprintf(threads, sizeof threads, "-");
    else
        snprintf(threads, sizeof threads, "%d", r->threads);
    if (!r->ok) {
        printf("| %-10s | %7s | %9" PRId64 " | FAILED: %s |\n", engine_name(r->engine), threads,
               r->n, r->failure);
        return;
    }
    if (r->engine == ENGINE_SEEDS) {
        printf("| %-10s | %7s | %9" PRId64 " | %9s | %12s | %8s | %9.1f | %9s |\n",
               engine_name(r->engine), threads, r->n, "-", "-", "-", r->maxrss_mib, "-");
        return;
    }
    printf("| %-10s | %7s | %9" PRId64 " | %9.3f | %12.0f | %8.3f | %9.1f | %9.1e |\n",
           engine_name(r->engine), threads, r->n, r->rep.seconds, rate(r), r->rep.cpu_seconds,
           r->maxrss_mib, fabs(r->rep.volume - 1.0));
}

static void print_header(void)
{
    printf("| %-10s | %7s | %9s | %9s | %12s | %8s | %9s | %9s |\n", "engine", "threads", "N",
           "seconds", "cells/s", "CPU s", "peak MiB", "|vol-1|");
    printf("|------------|--------:|----------:|----------:|-------------:|---------:|----------:|"
           "----------:|\n");
}

static void print_ratio(double num, double den, const char *what)
{
    if (num > 0 && den > 0)
        printf("  %-44s %6.2f\n", what, num / den);
    else
        printf("  %-44s    n/a\n", what);
}

int main(int argc, char **argv)
{
    config cfg;
    if (!parse_args(argc, argv, &cfg))
        return 2;

    int per_n = 1 + (cfg.skip_vorocrust ? 0 : cfg.threads_count) + (cfg.skip_voropp ? 0 : 1);
    int n_runs = per_n * cfg.n_count;
    run *runs = calloc((size_t)n_runs, sizeof *runs);
    if (!runs) {
        fprintf(stderr, "vc-bench-voronoi: out of memory\n");
        return 1;
    }
    int k = 0;
    for (int i = 0; i < cfg.n_count; i++) {
        runs[k++] = (run){.engine = ENGINE_SEEDS, .threads = 1, .n = cfg.n_list[i]};
        if (!cfg.skip_vorocrust)
            for (int t = 0; t < cfg.threads_count; t++)
                runs[k++] = (run){.engine = ENGINE_VOROCRUST, .threads = cfg.threads[t],
                                  .n = cfg.n_list[i]};
        if (!cfg.skip_voropp)
            runs[k++] = (run){.engine = ENGINE_VOROPP, .threads = 1, .n = cfg.n_list[i]};
    }

    double load[3] = {0, 0, 0};
    FILE *lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3)
            load[0] = load[1] = load[2] = 0;
        fclose(lf);
    }
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);

    for (k = 0; k < n_runs; k++)
        measure(&runs[k], &cfg);

    if (cfg.seeds_path)
        printf("# vc-bench-voronoi: the %" PRId64 " seeds of %s, %s, cells clipped to their "
               "bounding box grown by 1%% of its diagonal\n",
               cfg.n_list[0], cfg.seeds_path,
               cfg.keep_labels ? "cells for those of a non-zero label" : "all kept");
    else
        printf("# vc-bench-voronoi: N uniform random seeds in the unit cube (seed %" PRIu64
               "), cells clipped to [0,1]^3\n",
               cfg.seed);
    printf("# %ld CPUs online, load average %.2f at start; best of %d run(s); each run in its own "
           "process\n",
           ncpu, load[0], cfg.repeat);
    printf("# seconds: wall time of the engine call; CPU s: its process CPU time; peak MiB: the "
           "run's max RSS\n\n");
    print_header();
    for (k = 0; k < n_runs; k++)
        print_row(&runs[k]);

    printf("\nMesh sizes (cell faces: sum over cells of their face count, an interior face "
           "counted twice):\n");
    for (k = 0; k < n_runs; k++) {
        const run *r = &runs[k];
        if (!r->ok || r->engine == ENGINE_SEEDS)
            continue;
        const child_report *p = &r->rep;
        if (r->engine == ENGINE_VOROCRUST) {
            /* The mesh does not depend on the thread count: print it once,
             * with whether every thread count gave the same bytes. */
            int seen = 0, same = 1, counts = 0;
            for (int j = 0; j < n_runs; j++)
                if (runs[j].ok && runs[j].engine == ENGINE_VOROCRUST && runs[j].n == r->n) {
                    seen |= j < k;
                    same &= runs[j].rep.digest == p->digest;
                    counts++;
                }
            if (seen)
                continue;
            printf("  vorocrust N=%" PRId64 ": %" PRId64 " points, %" PRId64 " faces (%" PRId64
                   " interior, %" PRId64 " boundary), %" PRId64 " cells, %" PRId64
                   " cell faces (%.2f per cell)",
                   r->n, p->points, p->faces, p->interior_faces, p->boundary_faces, p->cells,
                   p->cell_faces, p->cells ? (double)p->cell_faces / (double)p->cells : 0.0);
            if (p->invalid >= 0)
                printf(", validate: %" PRId64 " problem(s)%s%s", p->invalid,
                       p->invalid ? ": " : "", p->invalid ? p->msg : "");
            if (counts > 1)
                printf(", %s for the %d thread counts", same ? "byte-identical" : "DIFFERENT",
                       counts);
            printf("\n");
        } else {
            printf("  Voro++    N=%" PRId64 ": %" PRId64 " cells, %" PRId64 " cell faces (%.2f "
                   "per cell), so %" PRId64 " interior + %" PRId64 " wall faces; block grid "
                   "%dx%dx%d\n",
                   r->n, p->cells, p->cell_faces,
                   p->cells ? (double)p->cell_faces / (double)p->cells : 0.0, p->interior_faces,
                   p->boundary_faces, p->grid[0], p->grid[1], p->grid[2]);
        }
    }

    if (cfg.rebuild > 0) {
        printf("\nRebuild after %" PRId64 " kept seeds moved (the cells next to them built again, "
               "all stitched) against a fresh build of the moved seeds:\n", cfg.rebuild);
        for (k = 0; k < n_runs; k++) {
            const run *r = &runs[k];
            if (!r->ok || r->engine != ENGINE_VOROCRUST)
                continue;
            const child_report *p = &r->rep;
            printf("  N=%" PRId64 ", %d thread(s): %" PRId64 " of %" PRId64 " cells built again, "
                   "%.3f s against %.3f s (%.2fx), %s\n", r->n, r->threads, p->rebuilt_cells,
                   p->cells, p->rebuild_seconds, p->fresh_seconds,
                   p->rebuild_seconds > 0 ? p->fresh_seconds / p->rebuild_seconds : 0.0,
                   p->rebuild_same ? "byte-identical" : "DIFFERENT");
        }
    }

    printf("\nRatios (cells/s):\n");
    for (int i = 0; i < cfg.n_count; i++) {
        const run *one = NULL, *vp = NULL;
        for (k = 0; k < n_runs; k++) {
            const run *r = &runs[k];
            if (r->n != cfg.n_list[i] || !r->ok)
                continue;
            if (r->engine == ENGINE_VOROCRUST && r->threads == 1 && !one)
                one = r;
            if (r->engine == ENGINE_VOROPP && !vp)
                vp = r;
        }
        printf(" N=%" PRId64 ":\n", cfg.n_list[i]);
        if (cfg.skip_vorocrust) {
            printf("  n/a (vorocrust skipped)\n");
            continue;
        }
        if (!cfg.skip_voropp)
            print_ratio(one ? rate(one) : 0, vp ? rate(vp) : 0,
                        "vorocrust 1 thread / Voro++");
        for (k = 0; k < n_runs; k++) {
            const run *r = &runs[k];
            if (r->n != cfg.n_list[i] || r->engine != ENGINE_VOROCRUST || r->threads == 1)
                continue;
            char what[64];
            snprintf(what, sizeof what, "vorocrust speed-up %d threads vs 1", r->threads);
            print_ratio(rate(r), one ? rate(one) : 0, what);
        }
    }

    int failed = 0;
    for (k = 0; k < n_runs; k++)
        failed |= !runs[k].ok;
    free(runs);
    return failed ? 1 : 0;
}
