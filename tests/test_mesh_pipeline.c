/* Unit test of the library's pipeline call, vc_mesh (vorocrust/vorocrust.h),
 * on the bundled icosphere (models/icosphere.obj) and on surfaces built in
 * memory:
 * - the version API agrees with the header's macros;
 * - the default options; bad options are refused with VC_EPARAM, an open
 *   surface with VC_EINPUT (an inconsistently oriented one is reversed back), each with a
 *   message naming the input (opt.name), and the result left empty;
 * - the octree interior is refused before the program initialises MPI;
 * - surface only: balls, surface seeds (inside ones labelled 1), a closed
 *   reconstructed surface with the input's Euler characteristic enclosing
 *   the input's volume within 1%, no volume mesh;
 * - the volume mesh: cell volumes that sum to the reconstructed surface's
 *   volume (1e-9) and to the mesh_volume figure, every face shared by at
 *   most two cells, the validator's verdict 0, fatness set for every cell
 *   and within the reported range, seeds = surface seeds + interior seeds;
 * - the lattice interior and none;
 * - 1 and 2 threads give the same mesh, array by array;
 * - the logger receives progress (VC_LOG_INFO) and nothing above its
 *   max_level; a NULL logger is silent;
 * - two calls at once on two threads give what one call alone gives (the
 *   library keeps no shared state);
 * - the ball count is predicted before sampling: absurd work (max_size
 *   1e-9, or a limit below the prediction) is refused at once with
 *   VC_EPARAM, and a sampling that reaches max_balls stops with VC_EPARAM. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/vorocrust.h"

#include "test_check.h"
#include "test_surface_util.h"
#include "test_mpi.h"

typedef struct log_count {
    int n[4];
} log_count;

static void count_messages(void *user, vc_log_level level, const char *message)
{
    log_count *c = user;
    if (level >= VC_LOG_ERROR && level <= VC_LOG_DEBUG)
        c->n[level]++;
    CHECKF(message && !strchr(message, '\n'), "a log message spans lines: %s", message);
}

static int same_mesh(const vc_polymesh *a, const vc_polymesh *b)
{
    if (a->n_points != b->n_points || a->n_faces != b->n_faces || a->n_cells != b->n_cells ||
        a->n_interior_faces != b->n_interior_faces)
        return 0;
    return !memcmp(a->points, b->points, sizeof(double) * 3 * (size_t)a->n_points) &&
           !memcmp(a->face_offsets, b->face_offsets, sizeof(int64_t) * (size_t)(a->n_faces + 1)) &&
           !memcmp(a->face_vertices, b->face_vertices,
                   sizeof(int64_t) * (size_t)a->face_offsets[a->n_faces]) &&
           !memcmp(a->face_owner, b->face_owner, sizeof(int64_t) * (size_t)a->n_faces) &&
           !memcmp(a->cell_volume, b->cell_volume, sizeof(double) * (size_t)a->n_cells) &&
           !memcmp(a->cell_fatness, b->cell_fatness, sizeof(double) * (size_t)a->n_cells);
}

/* The volume mesh's own invariants. */
static void check_volume_mesh(const vc_mesh_result *r, const char *what)
{
    const vc_polymesh *m = &r->mesh;
    CHECKF(r->has_mesh && m->n_cells > 0, "%s: no volume mesh", what);
    double sum = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        sum += m->cell_volume[c];
    CHECKF(fabs(sum - r->mesh_volume) <= 1e-12 * fabs(sum), "%s: mesh_volume %.15g, cells %.15g",
           what, r->mesh_volume, sum);
    CHECKF(fabs(sum - r->surface_volume) <= 1e-9 * fabs(r->surface_volume),
           "%s: cells %.15g, reconstructed surface %.15g", what, sum, r->surface_volume);
    CHECKF(r->mesh_problems == 0, "%s: %lld validator problems: %s", what,
           (long long)r->mesh_problems, r->mesh_problem);
    int64_t *uses = calloc((size_t)m->n_faces, sizeof *uses);
    for (int64_t k = 0; uses && k < m->cell_offsets[m->n_cells]; k++)
        uses[m->cell_faces[k]]++;
    int64_t bad = 0;
    for (int64_t f = 0; uses && f < m->n_faces; f++)
        bad += uses[f] != (m->face_neighbour[f] >= 0 ? 2 : 1);
    CHECKF(uses && bad == 0, "%s: %lld faces not listed by their one or two cells", what,
           (long long)bad);
    free(uses);
    int64_t unset = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        unset += !(m->cell_fatness[c] >= 1 && m->cell_fatness[c] <= r->cell_quality.fatness_max);
    CHECKF(m->cell_fatness && unset == 0, "%s: %lld cells with fatness outside [1, max %g]", what,
           (long long)unset, r->cell_quality.fatness_max);
    CHECKF(r->seeds.n == r->n_surface_seeds + r->n_interior_seeds,
           "%s: %lld seeds, %lld surface + %lld interior", what, (long long)r->seeds.n,
           (long long)r->n_surface_seeds, (long long)r->n_interior_seeds);
    CHECKF(m->n_cells == r->n_inside_seeds + r->n_interior_seeds,
           "%s: %lld cells for %lld inside and %lld interior seeds", what, (long long)m->n_cells,
           (long long)r->n_inside_seeds, (long long)r->n_interior_seeds);
}

/* A unit cube (12 triangles, outward), optionally with one triangle
 * dropped (open) or flipped (inconsistent). */
static void cube(vc_surface *s, double *xyz, int64_t *tri, int drop, int flip)
{
    static const int64_t t[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                  1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
    for (int k = 0; k < 8; k++) {
        xyz[3 * k] = (k == 1 || k == 2 || k == 5 || k == 6);
        xyz[3 * k + 1] = (k == 2 || k == 3 || k == 6 || k == 7);
        xyz[3 * k + 2] = k >= 4;
    }
    memcpy(tri, t, sizeof t);
    if (flip) {
        int64_t x = tri[1];
        tri[1] = tri[2];
        tri[2] = x;
    }
    s->n_vertices = 8;
    s->xyz = xyz;
    s->n_triangles = drop ? 11 : 12;
    s->tri = tri;
}

/* A coarse torus (radii 1 and 0.4), nu x nv quads split in two, outward:
 * every edge folds by 360 / nu or 360 / nv degrees. */
static void coarse_torus(vc_surface *s, double *xyz, int64_t *tri, int nu, int nv)
{
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            const double u = 2 * 3.14159265358979323846 * i / nu,
                         v = 2 * 3.14159265358979323846 * j / nv;
            double *p = xyz + 3 * (i * nv + j);
            p[0] = (1 + 0.4 * cos(v)) * cos(u);
            p[1] = (1 + 0.4 * cos(v)) * sin(u);
            p[2] = 0.4 * sin(v);
        }
    int64_t k = 0;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            const int64_t a = i * nv + j, b = ((i + 1) % nu) * nv + j,
                          c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
            const int64_t t[6] = {a, b, c, a, c, d};
            memcpy(tri + 6 * k++, t, sizeof t);
        }
    s->n_vertices = nu * nv;
    s->xyz = xyz;
    s->n_triangles = 2 * nu * nv;
    s->tri = tri;
}

/* The resampling ladder on a 10 x 6 coarse torus (folds of 36 and 60
 * degrees at every edge). Its sampling at 60 degrees converges since
 * session 14 (in 6 passes), within the error bound; no input tried still
 * diverges, so a budget of one sliver pass (and one in the safe mode)
 * stands for the divergence here. Then by default its folds become creases
 * (theta_sharp 20, where it needs no pass) and the surface is its own,
 * volume and all; with creases not allowed, 6 rounds of Loop smoothing at
 * 120 degrees (its sampling then counts as diverged too, and the error
 * says so). */
static void check_ladder(void)
{
    double xyz[3 * 60];
    int64_t tri[3 * 120];
    vc_surface torus;
    coarse_torus(&torus, xyz, tri, 10, 6);
    const double v_in = surface_enclosed_volume(&torus);
    vc_mesh_options o;
    vc_mesh_options_default(&o);
    o.surface_only = 1;
    o.max_error = 0.05;
    o.name = "torus";
    /* the ladder on the input itself: no denoised copy after a divergence
     * (a copy diverges as well within a budget of one pass) */
    o.denoise = -1;
    vc_mesh_result r;
    vc_error err = {0, ""};
    /* with the default budget: at 60 degrees, no resampling, closed, the
     * input's Euler characteristic, the volume within 1% */
    if (vc_mesh(&torus, &o, &r, &err) != 0) {
        CHECKF(0, "coarse torus at 60 degrees: %s", err.msg);
    } else {
        CHECKF(!r.resampled && r.sharp_angle == 60 && r.surface_closed &&
                   fabs(r.surface_volume - v_in) <= 0.01 * v_in,
               "coarse torus at 60 degrees: resampled %d at %g, volume %.9g against %.9g",
               r.resampled, r.sharp_angle, r.surface_volume, v_in);
        vc_mesh_result_free(&r);
    }
    o.max_sliver_iterations = 1;
    /* by default (VC_RESAMPLE_FOLDS) the folds where it is stuck become
     * creases: the torus is its own, resampled, at theta_sharp 60 */
    if (vc_mesh(&torus, &o, &r, &err) != 0) {
        CHECKF(0, "coarse torus, one pass, folds as creases: %s", err.msg);
    } else {
        CHECKF(r.resampled && r.sharp_angle == 60 && r.smooth_iterations == 0 && r.surface_closed &&
                   fabs(r.surface_volume - v_in) <= 0.01 * v_in,
               "coarse torus, one pass, folds as creases: resampled %d at %g, %d smoothing rounds, "
               "volume %.9g against %.9g", r.resampled, r.sharp_angle, r.smooth_iterations,
               r.surface_volume, v_in);
        vc_mesh_result_free(&r);
    }
    /* with no resampling the divergence is the error, and it names the
     * fallback */
    o.resample = 0;
    if (vc_mesh(&torus, &o, &r, &err) == 0) {
        CHECKF(0, "coarse torus, one pass, no fallback: meshed (resampled %d)", r.resampled);
        vc_mesh_result_free(&r);
    } else {
        CHECKF(strstr(err.msg, "does not converge") && strstr(err.msg, "--fallback"),
               "coarse torus, one pass, no fallback: %s", err.msg);
    }
    o.resample = VC_RESAMPLE_CREASES | VC_RESAMPLE_SMOOTH;
    if (vc_mesh(&torus, &o, &r, &err) != 0) {
        CHECKF(0, "coarse torus, creases: %s", err.msg);
    } else {
        CHECKF(r.resampled && r.first_sharp_angle == 60 && r.sharp_angle == 20 &&
                   r.smooth_iterations == 0 && r.surface_closed &&
                   fabs(r.surface_volume - v_in) <= 1e-9 * v_in,
               "coarse torus, creases: resampled %d at %g after %g, %d smoothing rounds, "
               "volume %.12g against %.12g",
               r.resampled, r.sharp_angle, r.first_sharp_angle, r.smooth_iterations,
               r.surface_volume, v_in);
        vc_mesh_result_free(&r);
    }
    o.resample = VC_RESAMPLE_SMOOTH;
    if (vc_mesh(&torus, &o, &r, &err) != 0) {
        /* the smoothed torus needs more than the budget of one pass: the
         * error names the divergence after the smoothing */
        CHECKF(strstr(err.msg, "does not converge") != NULL, "coarse torus, smoothing: %s",
               err.msg);
    } else {
        CHECKF(r.resampled && r.sharp_angle == 120 && r.smooth_iterations == 6 &&
                   r.surface_closed && r.surface_volume < 0.95 * v_in,
               "coarse torus, smoothing: resampled %d at %g, %d smoothing rounds, volume %.6g "
               "against %.6g",
               r.resampled, r.sharp_angle, r.smooth_iterations, r.surface_volume, v_in);
        vc_mesh_result_free(&r);
    }
}

int main(void)
{
    CHECKF(!strcmp(vc_version(), VC_VERSION_STRING) && vc_version_number() == VC_VERSION_NUMBER &&
               VC_VERSION_NUMBER == VC_VERSION_MAJOR * 10000 + VC_VERSION_MINOR * 100 +
                                        VC_VERSION_PATCH,
           "version %s / %d against the header's %s", vc_version(), vc_version_number(),
           VC_VERSION_STRING);

    check_ladder();

    vc_mesh_options d;
    vc_mesh_options_default(&d);
    CHECKF(d.sharp_angle == 60 && d.interior == VC_INTERIOR_OCTREE && d.lloyd_iterations == 0 &&
               d.smooth_iterations == 0 && d.resample == VC_RESAMPLE_FOLDS &&
               d.log == NULL && !d.surface_only,
           "defaults");

    vc_error err = {0, ""};
    vc_mesh_result r;
    double xyz[24];
    int64_t tri[36];
    vc_surface box;
    vc_mesh_options o = d;
    o.name = "cube.obj";

    /* refusals: the message names the input, the result stays empty */
    cube(&box, xyz, tri, 1, 0);
    CHECKF(vc_mesh(&box, &o, &r, &err) == VC_EINPUT && strstr(err.msg, "cube.obj: ") == err.msg &&
               strstr(err.msg, "open") && r.balls.n == 0 && !r.has_mesh,
           "open cube: %s", err.msg);
    /* a flipped triangle is reversed back: the cube's own mesh */
    cube(&box, xyz, tri, 0, 0);
    vc_mesh_options quick = o;
    quick.surface_only = 1;
    int64_t n_plain = -1;
    if (vc_mesh(&box, &quick, &r, &err) == 0) {
        n_plain = r.balls.n;
        vc_mesh_result_free(&r);
    }
    cube(&box, xyz, tri, 0, 1);
    CHECKF(vc_mesh(&box, &quick, &r, &err) == 0 && r.n_flipped == 1 && r.balls.n == n_plain && n_plain > 0 &&
               r.input.n_inconsistent_edges == 0,
           "flipped triangle: %s (%lld flipped, %lld balls, %lld without the flip)", err.msg,
           (long long)r.n_flipped, (long long)r.balls.n, (long long)n_plain);
    vc_mesh_result_free(&r);
    cube(&box, xyz, tri, 0, 0);
    const struct {
        double sharp, lipschitz, max_error;
        int lloyd, smooth;
    } bad[] = {{0, 0.25, 0.004, 0, 0},  {180, 0.25, 0.004, 0, 0}, {60, 1, 0.004, 0, 0},
               {60, 0.25, 1, 0, 0},     {60, 0.25, -1, 0, 0},     {60, 0.25, 0.004, -1, 0},
               {60, 0.25, 0.004, 0, -1}, {60, NAN, 0.004, 0, 0}};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        vc_mesh_options b = o;
        b.sharp_angle = bad[k].sharp;
        b.lipschitz = bad[k].lipschitz;
        b.max_error = bad[k].max_error;
        b.lloyd_iterations = bad[k].lloyd;
        b.smooth_iterations = bad[k].smooth;
        CHECKF(vc_mesh(&box, &b, &r, &err) == VC_EPARAM, "bad option set %zu accepted", k);
    }
    /* a denoised copy that cannot be made is refused, not ignored */
    {
        const struct {
            int denoise, smooth;
            double width, max_error;
        } nd[] = {{2, 0, 0, 0.004}, {-2, 0, 0, 0.004}, {1, 1, 0, 0.004}, {1, 0, 4, 0.004},
                  {1, 0, 0, 0}};
        for (size_t k = 0; k < sizeof nd / sizeof *nd; k++) {
            vc_mesh_options b = o;
            b.denoise = nd[k].denoise;
            b.smooth_iterations = nd[k].smooth;
            b.smooth_width = nd[k].width;
            b.max_error = nd[k].max_error;
            CHECKF(vc_mesh(&box, &b, &r, &err) == VC_EPARAM && strstr(err.msg, "denoise"),
                   "denoise option set %zu: %s", k, err.msg);
        }
    }
    /* the octree interior needs the program's MPI */
    CHECKF(vc_mesh(&box, &o, &r, &err) == VC_EPARAM && strstr(err.msg, "initialise MPI"),
           "octree without MPI: %s", err.msg);

    vc_surface ico;
    const char *path = VC_TEST_DATA "/../../models/icosphere.obj";
    if (vc_surface_read(path, &ico, NULL, &err)) {
        fprintf(stderr, "test_mesh_pipeline: %s\n", err.msg);
        return 1;
    }
    vc_surface_report in;
    memset(&in, 0, sizeof in);
    vc_surface_check(&ico, &in, &err);

    /* surface only, no MPI needed */
    log_count lc;
    memset(&lc, 0, sizeof lc);
    vc_logger log = {count_messages, &lc, VC_LOG_INFO};
    o = d;
    o.surface_only = 1;
    o.log = &log;
    if (vc_mesh(&ico, &o, &r, &err) != 0) {
        CHECKF(0, "icosphere surface only: %s", err.msg);
    } else {
        CHECKF(r.balls.n > 100 && r.n_surface_seeds > r.balls.n && !r.has_mesh &&
                   r.n_half_covered == 0 && r.sampling.n_half_covered == 0 && !r.resampled,
               "surface only: %lld balls, %lld seeds, mesh %d", (long long)r.balls.n,
               (long long)r.n_surface_seeds, r.has_mesh);
        int64_t inside = 0;
        for (int64_t i = 0; i < r.seeds.n; i++)
            inside += r.seeds.label[i] == 1;
        CHECKF(inside == r.n_inside_seeds && inside > 0 && inside < r.seeds.n,
               "inside seeds %lld, reported %lld", (long long)inside, (long long)r.n_inside_seeds);
        CHECKF(r.surface_closed && r.surface_topology.euler == in.euler &&
                   r.input.euler == in.euler,
               "reconstructed surface: closed %d, euler %lld (input %lld)", r.surface_closed,
               (long long)r.surface_topology.euler, (long long)in.euler);
        CHECKF(fabs(r.surface_volume - in.volume) <= 0.01 * in.volume,
               "surface volume %g, input %g", r.surface_volume, in.volume);
        CHECKF(r.surface_quality.q_min > 0.2 && r.surface_quality.q_min <= r.surface_quality.q_mean,
               "surface quality min %g mean %g", r.surface_quality.q_min, r.surface_quality.q_mean);
        CHECKF(r.time.total > 0 && r.time.surface > 0, "times");
        CHECKF(lc.n[VC_LOG_INFO] > 0 && lc.n[VC_LOG_DEBUG] == 0 && lc.n[VC_LOG_WARNING] == 0,
               "logger: %d info, %d debug, %d warnings", lc.n[VC_LOG_INFO], lc.n[VC_LOG_DEBUG],
               lc.n[VC_LOG_WARNING]);
        vc_mesh_result_free(&r);
        CHECKF(r.balls.n == 0 && r.seeds.xyz == NULL, "free zeroes the result");
    }

    /* predicted and bounded work */
    {
        vc_mesh_options b = d;
        b.surface_only = 1;
        b.max_size = 1e-9;
        CHECKF(vc_mesh(&ico, &b, &r, &err) == VC_EPARAM && strstr(err.msg, "predicted") &&
                   r.balls.n == 0,
               "max size 1e-9: %s", err.msg);
        b.max_size = 0;
        b.max_balls = 50;
        CHECKF(vc_mesh(&ico, &b, &r, &err) == VC_EPARAM && strstr(err.msg, "predicted"),
               "a limit below the prediction: %s", err.msg);
        /* a gentler grading makes more balls than the sizing predicts
         * (821): a limit above the prediction is reached while sampling */
        b.max_balls = 900;
        b.lipschitz = 0.05;
        CHECKF(vc_mesh(&ico, &b, &r, &err) == VC_EPARAM && strstr(err.msg, "reached the limit"),
               "a limit reached while sampling: %s", err.msg);
        b.lipschitz = d.lipschitz;
        b.max_balls = -1;
        if (vc_mesh(&ico, &b, &r, &err) == 0) {
            CHECKF(r.sampling.n_balls_predicted > 0.2 * (double)r.balls.n &&
                       r.sampling.n_balls_predicted < 5.0 * (double)r.balls.n,
                   "predicted %g for %lld balls", r.sampling.n_balls_predicted,
                   (long long)r.balls.n);
            vc_mesh_result_free(&r);
        } else {
            CHECKF(0, "no limit: %s", err.msg);
        }
        CHECKF(vc_mesh_default_max_balls() > 10000, "default ball limit %lld",
               (long long)vc_mesh_default_max_balls());
    }

    /* two calls at once, on two threads, against one alone */
    {
        vc_mesh_options c = d;
        c.surface_only = 1;
        c.threads = 1;
        vc_mesh_result alone, both[2];
        vc_error e2[2];
        int rc_alone = vc_mesh(&ico, &c, &alone, &err), rc2[2] = {-1, -1};
#pragma omp parallel for num_threads(2) schedule(static, 1)
        for (int k = 0; k < 2; k++)
            rc2[k] = vc_mesh(&ico, &c, &both[k], &e2[k]);
        for (int k = 0; k < 2; k++) {
            CHECKF(rc_alone == 0 && rc2[k] == 0, "concurrent call %d: %s", k, e2[k].msg);
            if (rc_alone || rc2[k])
                continue;
            CHECKF(alone.balls.n == both[k].balls.n &&
                       !memcmp(alone.balls.center, both[k].balls.center,
                               sizeof(double) * 3 * (size_t)alone.balls.n) &&
                       !memcmp(alone.balls.radius, both[k].balls.radius,
                               sizeof(double) * (size_t)alone.balls.n) &&
                       alone.seeds.n == both[k].seeds.n &&
                       !memcmp(alone.seeds.xyz, both[k].seeds.xyz,
                               sizeof(double) * 3 * (size_t)alone.seeds.n),
                   "concurrent call %d differs from a call alone", k);
            vc_mesh_result_free(&both[k]);
        }
        vc_mesh_result_free(&alone);
    }

    /* the denoised copy (vc_mesh_options.denoise): a clean icosphere keeps
     * its input by default (not rough: nothing predicted), always takes the
     * copy with 1, and does nothing with -1; the copy stays within half
     * the bound */
    {
        const double bound = d.max_error * vc_surface_diagonal(&ico);
        const int modes[3] = {0, 1, -1};
        for (int k = 0; k < 3; k++) {
            o = d;
            o.surface_only = 1;
            o.denoise = modes[k];
            if (vc_mesh(&ico, &o, &r, &err) != 0) {
                CHECKF(0, "icosphere, denoise %d: %s", modes[k], err.msg);
                continue;
            }
            const vc_denoise_choice *c = &r.denoise;
            if (modes[k] == 0) /* clean: no vertex's normals spread by 20 degrees */
                CHECKF(!c->used && c->rough_share <= 0.01 && c->n_input == 0 && c->n_denoised == 0,
                       "denoise auto: used %d, rough vertices %g, predicted %g and %g", c->used,
                       c->rough_share, c->n_input, c->n_denoised);
            else if (modes[k] == 1)
                CHECKF(c->used && c->moved.max_move > 0 && c->moved.max_move <= 0.5 * bound * (1 + 1e-12) &&
                           fabs(c->bound - (bound - c->moved.max_move)) <= 1e-12 * bound &&
                           r.surface_closed && fabs(r.surface_volume - in.volume) <= 0.01 * in.volume,
                       "denoise on: used %d, moved %g (bound %g), copy's bound %g, closed %d, "
                       "volume %g (input %g)", c->used, c->moved.max_move, bound, c->bound,
                       r.surface_closed, r.surface_volume, in.volume);
            else
                CHECKF(!c->used && c->n_input == 0 && c->n_denoised == 0,
                       "denoise off: used %d, predicted %g and %g", c->used, c->n_input,
                       c->n_denoised);
            vc_mesh_result_free(&r);
        }
    }

    /* lattice and no interior: no MPI needed either */
    o = d;
    o.interior = VC_INTERIOR_LATTICE;
    if (vc_mesh(&ico, &o, &r, &err) != 0) {
        CHECKF(0, "lattice: %s", err.msg);
    } else {
        check_volume_mesh(&r, "lattice");
        CHECKF(r.n_interior_seeds > 0, "lattice: no interior seed");
        vc_mesh_result_free(&r);
    }
    o.interior = VC_INTERIOR_NONE;
    if (vc_mesh(&ico, &o, &r, &err) != 0) {
        CHECKF(0, "no interior: %s", err.msg);
    } else {
        check_volume_mesh(&r, "no interior");
        CHECKF(r.n_interior_seeds == 0, "no interior: %lld interior seeds",
               (long long)r.n_interior_seeds);
        vc_mesh_result_free(&r);
    }

    /* the default pipeline, 1 and 2 threads */
    if (test_mpi_start() != 0) {
        fprintf(stderr, "test_mesh_pipeline: MPI_Init failed\n");
        return 1;
    }
    vc_mesh_result r1, r2;
    o = d;
    o.threads = 1;
    int rc1 = vc_mesh(&ico, &o, &r1, &err);
    CHECKF(rc1 == 0, "octree, 1 thread: %s", err.msg);
    o.threads = 2;
    memset(&lc, 0, sizeof lc);
    log.max_level = VC_LOG_DEBUG;
    o.log = &log;
    int rc2 = vc_mesh(&ico, &o, &r2, &err);
    CHECKF(rc2 == 0, "octree, 2 threads: %s", err.msg);
    if (rc1 == 0 && rc2 == 0) {
        check_volume_mesh(&r2, "octree");
        CHECKF(r2.n_interior_seeds > 0 && r2.octree.n_leaves > 0, "octree: %lld interior seeds",
               (long long)r2.n_interior_seeds);
        CHECKF(same_mesh(&r1.mesh, &r2.mesh), "1 and 2 threads give different meshes");
        CHECKF(lc.n[VC_LOG_INFO] > 0, "no progress with 2 threads");
        printf("icosphere: %lld balls, %lld surface seeds, %lld cells, volume %.9g (input %.9g), "
               "fatness max %.3f\n",
               (long long)r2.balls.n, (long long)r2.n_surface_seeds, (long long)r2.mesh.n_cells,
               r2.mesh_volume, in.volume, r2.cell_quality.fatness_max);
    }
    vc_mesh_result_free(&r1);
    vc_mesh_result_free(&r2);
    test_mpi_stop();
    vc_surface_free(&ico);
    if (failures) {
        fprintf(stderr, "test_mesh_pipeline: %d failure(s)\n", failures);
        return 1;
    }
    printf("test_mesh_pipeline: all checks passed\n");
    return 0;
}
