/* checkMesh's failures mended at the seeds (see include/vorocrust/interior.h
 * and docs/solver-grade-cells.md).
 *
 * checkMesh's skewness of a face is the distance from its centroid to
 * where the line between the two cells' centroids crosses its plane, over
 * the face's extent that way: small faces whose cells' centroids sit askew
 * fail it, and -allGeometry adds the faces' interpolation weights, the
 * cells' volume ratios and its concave-cell test. Every cell stays the
 * Voronoi cell of its seed: an interior seed of such a face or cell (or
 * next to it) moves a little (within a quarter of its distance to its
 * nearest seed), to the place among a few random ones that lowers what
 * fails around it most. A place is judged exactly: the cells of the seed
 * and of its neighbours are built from every seed that can cut them, and
 * measured as they would be in the mesh. */
#include "vorocrust/interior.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ball_tree.h"
#include "nearest_seed.h"
#include "util/clock.h"
#include "util/threads.h"
#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"
#include "voronoi/seed_kdtree.h"

/* Seeds around a seed its local cells are built from, at most (the cells
 * judged must be exact: built from every seed that can cut them). */
enum { LOCAL_MAX = 4096 };
/* Cells built around a seed at most, and builds of them: a seed whose
 * neighbourhood needs more is left as it is (cow.off's seeds along the
 * knife edge where its parts meet need thousands). */
enum { KEEP_MAX = 512, MAX_ATTEMPTS = 6 };
/* Places built and judged together (see the loop). */
enum { PLACE_BATCH = 4 };
/* The picking region's radius, a share of the distance from the seed to
 * its nearest neighbour (as the short-edge protection's). */
#define PICK_RADIUS 0.25

void vc_unskew_options_default(vc_unskew_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->max_skew = 3.9;
    opt->movable_begin = -1;
    opt->clearance = VC_INTERIOR_CLEARANCE;
    opt->candidates = 16;
    opt->random_seed = 1;
}

/* The cells around a seed s with s at some place: the Voronoi cells of
 * the seeds to keep among those near s (the others only cut them), and for
 * each whether it is the cell the whole seed set gives (exact). */
typedef struct local_mesh {
    vc_polymesh m;
    int64_t *seed;         /* per local seed: its index in the whole set */
    int64_t *cell_of;      /* per local seed: its cell, or -1 */
    unsigned char *exact;  /* per local cell */
    int64_t s_cell;        /* the cell of s (local seed 0) */
} local_mesh;

static void local_free(local_mesh *l)
{
    vc_polymesh_free(&l->m);
    free(l->seed);
    free(l->cell_of);
    free(l->exact);
    memset(l, 0, sizeof *l);
}

/* The largest distance from a cell's seed to its vertices. */
static double cell_reach(const vc_polymesh *m, int64_t c, const double *x)
{
    double r2 = 0;
    for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; k++) {
        const int64_t f = m->cell_faces[k];
        for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; i++) {
            const double *p = m->points + 3 * m->face_vertices[i];
            const double d[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
            const double e = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            r2 = e > r2 ? e : r2;
        }
    }
    return sqrt(r2);
}

/* Builds the cells of the seeds marked in keep (and of s) among s and the
 * got seeds of hit (every seed within `reach` of s's place, origin), s put
 * at x. A cell is exact when every seed within twice its reach from its
 * seed is there: |q - origin| + 2 reach <= `reach`. Returns 0, -1 when out
 * of memory, 1 when the seeds make no mesh (nothing to judge). */
static int local_build(const vc_seeds *seeds, int64_t s, const double origin[3], const double x[3],
                       const vc_kd_hit *hit, int got, double reach, const unsigned char *keep,
                       local_mesh *out)
{
    memset(out, 0, sizeof *out);
    const int n = got + 1;
    vc_seeds ls = {n, malloc(sizeof(double) * 3 * (size_t)n), malloc(sizeof(int32_t) * (size_t)n)};
    out->seed = malloc(sizeof(int64_t) * (size_t)n);
    out->cell_of = malloc(sizeof(int64_t) * (size_t)n);
    if (!ls.xyz || !ls.label || !out->seed || !out->cell_of) {
        free(ls.xyz);
        free(ls.label);
        local_free(out);
        return -1;
    }
    memcpy(ls.xyz, x, 3 * sizeof(double));
    out->seed[0] = s;
    ls.label[0] = 1;
    for (int i = 0; i < got; i++) {
        memcpy(ls.xyz + 3 * (i + 1), seeds->xyz + 3 * hit[i].seed, 3 * sizeof(double));
        out->seed[i + 1] = hit[i].seed;
        ls.label[i + 1] = keep[hit[i].seed] ? 1 : 0;
    }
    vc_voronoi_options vo;
    vc_voronoi_options_default(&vo);
    vo.threads = 1;
    vc_error e;
    memset(&e, 0, sizeof e);
    const int rc = vc_voronoi_build(&ls, &vo, &out->m, &e);
    out->exact = rc ? NULL : malloc((size_t)out->m.n_cells + 1);
    if (rc || !out->exact) {
        free(ls.xyz);
        free(ls.label);
        local_free(out);
        return rc && e.code != VC_ENOMEM ? 1 : -1;
    }
    for (int i = 0; i < n; i++)
        out->cell_of[i] = -1;
    out->s_cell = -1;
    for (int64_t c = 0; c < out->m.n_cells; c++) {
        const int64_t q = out->m.cell_seed[c];
        const double *xq = ls.xyz + 3 * q;
        const double d[3] = {xq[0] - origin[0], xq[1] - origin[1], xq[2] - origin[2]};
        const double dq = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        out->exact[c] = (dq + 2 * cell_reach(&out->m, c, xq)) * (1 + 1e-9) <= reach;
        out->cell_of[q] = c;
        if (q == 0)
            out->s_cell = c;
    }
    free(ls.xyz);
    free(ls.label);
    return 0;
}

/* The local seed across face f from cell c (-1: a wall). */
static int64_t across(const vc_polymesh *m, int64_t f, int64_t c)
{
    if (m->face_neighbour[f] >= 0)
        return m->cell_seed[m->face_owner[f] == c ? m->face_neighbour[f] : m->face_owner[f]];
    return m->face_other_seed[f];
}

/* The local index of whole-set seed t in l, or -1. */
static int64_t local_index(const local_mesh *l, int64_t t)
{
    for (int64_t q = 0; q < l->m.n_seeds; q++)
        if (l->seed[q] == t)
            return q;
    return -1;
}

/* Marks in `focus` (by whole-set index; the caller clears it through the
 * list) the seed s and the seeds across its cell's faces in l: the cells
 * a move of s changes. */
static void mark_focus(const local_mesh *l, unsigned char *focus, int64_t *list, int *n_list)
{
    const vc_polymesh *m = &l->m;
    const int64_t c = l->s_cell;
    const int64_t s = l->seed[0];
    if (!focus[s]) {
        focus[s] = 1;
        list[(*n_list)++] = s;
    }
    for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; k++) {
        const int64_t q = across(m, m->cell_faces[k], c);
        if (q < 0 || focus[l->seed[q]])
            continue;
        focus[l->seed[q]] = 1;
        list[(*n_list)++] = l->seed[q];
    }
}

/* What a judgement found missing: seeds whose cells must be built too,
 * or a neighbourhood too small for some cell to be exact. */
typedef struct shortfall {
    int64_t *missing;
    int n_missing, cap;
    int grow;
} shortfall;

/* checkMesh's limits besides the skewness (its -allGeometry checks):
 * the smaller of a face's two distances to its cells' centroids (along its
 * normal) over their sum, and the smaller cell's volume over the larger's;
 * a cell is concave when the centre of one of its faces lies within
 * 1e-6 (a cosine) of another face's plane or beyond it. */
#define MIN_WEIGHT 0.05
#define MIN_VOLUME_RATIO 0.01
#define PLANAR_COS 1e-6

/* Is cell c of m concave by checkMesh's test? */
static int cell_concave(const vc_polymesh *m, int64_t c)
{
    for (int64_t i = m->cell_offsets[c]; i < m->cell_offsets[c + 1]; i++) {
        const int64_t fi = m->cell_faces[i];
        const double *fc = m->face_centroid + 3 * fi, *n = m->face_normal + 3 * fi;
        const double sg = m->face_owner[fi] == c ? 1.0 : -1.0; /* out of c */
        for (int64_t j = m->cell_offsets[c]; j < m->cell_offsets[c + 1]; j++) {
            if (j == i)
                continue;
            const double *pc = m->face_centroid + 3 * m->cell_faces[j];
            const double d[3] = {pc[0] - fc[0], pc[1] - fc[1], pc[2] - fc[2]};
            const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (len > 0 && sg * (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / len > -PLANAR_COS)
                return 1;
        }
    }
    return 0;
}

/* What checkMesh would say of face f of m between centroids co (volume
 * vo) and cn (vn): the skewness above max_skew, and a unit for each of the
 * other limits missed, by how much (a share of the limit). */
static double face_badness(const vc_polymesh *m, int64_t f, const double co[3], double vo,
                           const double cn[3], double vn, double max_skew)
{
    double bad = 0;
    const double sk = vc_polymesh_face_skewness_between(m, f, co, cn);
    if (sk > max_skew)
        bad += sk - max_skew;
    const double *fc = m->face_centroid + 3 * f, *n = m->face_normal + 3 * f;
    const double dox = fabs(n[0] * (fc[0] - co[0]) + n[1] * (fc[1] - co[1]) + n[2] * (fc[2] - co[2]));
    const double dnx = fabs(n[0] * (cn[0] - fc[0]) + n[1] * (cn[1] - fc[1]) + n[2] * (cn[2] - fc[2]));
    const double w = dox + dnx > 0 ? (dox < dnx ? dox : dnx) / (dox + dnx) : 0;
    if (w < MIN_WEIGHT)
        bad += (MIN_WEIGHT - w) / MIN_WEIGHT;
    const double r = vo < vn ? vo / vn : vn / vo;
    if (r < MIN_VOLUME_RATIO)
        bad += (MIN_VOLUME_RATIO - r) / MIN_VOLUME_RATIO;
    return bad;
}

/* How badly the focus seeds' cells in l fail checkMesh: the sum over their
 * faces between two cells the mesh keeps (labels != 0) of face_badness,
 * and 1 for each concave focus cell (a move that mends one face and leaves
 * a worse one nearby as it was still counts; a face between two focus
 * cells counts twice, before and after alike). A cell across from a focus
 * cell that is not a focus cell itself is as the mesh has it, or as the
 * moves before made it (a move of s changes only s's cell and its
 * neighbours'): its centroid and volume are centroid_now's and
 * volume_now's. Records in sf the focus cells it needed and did not have,
 * and whether one was not exact. */
static double focus_badness(const local_mesh *l, const vc_seeds *seeds, const double *centroid_now,
                            const double *volume_now, const unsigned char *focus,
                            const int64_t *focus_list, int n_focus, double max_skew, shortfall *sf)
{
    const vc_polymesh *m = &l->m;
    double bad = 0;
    for (int i = 0; i < n_focus; i++) {
        const int64_t t = focus_list[i];
        if (seeds->label[t] == 0)
            continue; /* not a cell of the mesh */
        const int64_t lt = local_index(l, t);
        const int64_t c = lt >= 0 ? l->cell_of[lt] : -1;
        if (c < 0) {
            if (lt < 0)
                sf->grow = 1;
            else if (sf->n_missing < sf->cap)
                sf->missing[sf->n_missing++] = t;
            continue;
        }
        if (!l->exact[c]) {
            sf->grow = 1;
            continue;
        }
        bad += cell_concave(m, c);
        for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; k++) {
            const int64_t f = m->cell_faces[k];
            const int64_t q = across(m, f, c);
            if (q < 0 || seeds->label[l->seed[q]] == 0)
                continue;
            const int64_t u = l->seed[q];
            const double *cn;
            double vn;
            if (focus[u]) {
                const int64_t o = l->cell_of[q];
                if (o < 0) {
                    if (sf->n_missing < sf->cap)
                        sf->missing[sf->n_missing++] = u;
                    continue;
                }
                if (!l->exact[o]) {
                    sf->grow = 1;
                    continue;
                }
                cn = m->cell_centroid + 3 * o;
                vn = m->cell_volume[o];
            } else {
                cn = centroid_now + 3 * u;
                vn = volume_now[u];
                if (cn[0] != cn[0])
                    continue; /* no cell in the mesh */
            }
            bad += face_badness(m, f, m->cell_centroid + 3 * c, m->cell_volume[c], cn, vn, max_skew);
        }
    }
    return bad;
}

typedef struct candidate {
    double x[3];
    double before, after; /* the skewness in excess around, both judged on
                             the same cells' faces */
    int ok;
} candidate;

/* Marks seed t to keep (once), listing it. */
static void keep_seed(unsigned char *keep, int64_t *list, int64_t *n, int64_t cap, int64_t t)
{
    if (keep[t] || *n >= cap)
        return;
    keep[t] = 1;
    list[(*n)++] = t;
}

int vc_interior_unskew(const vc_balls *balls, vc_seeds *seeds, int64_t n_surface,
                       const vc_polymesh *mesh, const vc_unskew_options *opt,
                       vc_unskew_stats *stats, vc_error *err)
{
    const double t0 = vc_clock_seconds();
    vc_unskew_stats st;
    memset(&st, 0, sizeof st);
    if (stats)
        *stats = st;
    const int64_t n = seeds->n;
    const int64_t movable = opt->movable_begin >= 0 ? opt->movable_begin : n_surface;
    if (!(opt->max_skew > 0) || !(opt->clearance >= 0) || opt->candidates < 1 ||
        opt->candidates > 1024 || n_surface < 0 || n_surface > n || movable < n_surface ||
        opt->n_sphere_seeds < 0 || opt->n_sphere_seeds > n - n_surface ||
        (opt->n_sphere_seeds > 0 && !opt->sphere_ball))
        return vc_error_set(err, VC_EPARAM, "skew faces: bad options (skewness %g, clearance %g, "
                            "%d candidates)", opt->max_skew, opt->clearance, opt->candidates);
    /* the seeds that may move of the faces and cells that fail checkMesh,
     * in index order: a cell's own seed when it may move, else (a surface
     * seed, fixed by the balls) the movable seeds next to it, whose moves
     * change the cell */
    unsigned char *want = calloc((size_t)n + 1, 1);
    if (!want)
        return vc_error_set(err, VC_ENOMEM, "out of memory mending skew faces");
#define WANT_CELL(cell)                                                                            \
    do {                                                                                           \
        const int64_t c_ = (cell), s_ = mesh->cell_seed[c_];                                       \
        if (s_ >= movable && s_ < n) {                                                             \
            want[s_] = 1;                                                                          \
            break;                                                                                 \
        }                                                                                          \
        for (int64_t k_ = mesh->cell_offsets[c_]; k_ < mesh->cell_offsets[c_ + 1]; k_++) {         \
            const int64_t g_ = mesh->cell_faces[k_];                                               \
            if (mesh->face_neighbour[g_] < 0)                                                      \
                continue;                                                                          \
            const int64_t o_ = mesh->face_owner[g_] == c_ ? mesh->face_neighbour[g_]               \
                                                          : mesh->face_owner[g_];                  \
            const int64_t t_ = mesh->cell_seed[o_];                                                \
            if (t_ >= movable && t_ < n)                                                           \
                want[t_] = 1;                                                                      \
        }                                                                                          \
    } while (0)
    for (int64_t f = 0; f < mesh->n_interior_faces; f++) {
        const int64_t ca = mesh->face_owner[f], cb = mesh->face_neighbour[f];
        const double k = vc_polymesh_face_skewness(mesh, f);
        st.max_skew = k > st.max_skew ? k : st.max_skew;
        st.n_skew_faces += k > opt->max_skew;
        const double other = face_badness(mesh, f, mesh->cell_centroid + 3 * ca, mesh->cell_volume[ca],
                                          mesh->cell_centroid + 3 * cb, mesh->cell_volume[cb],
                                          INFINITY);
        st.n_weak_faces += other > 0;
        if (k > opt->max_skew || other > 0) {
            WANT_CELL(ca);
            WANT_CELL(cb);
        }
    }
    for (int64_t c = 0; c < mesh->n_cells; c++)
        if (cell_concave(mesh, c)) {
            st.n_concave_cells++;
            WANT_CELL(c);
        }
#undef WANT_CELL
    /* seeds an earlier call tried in vain, around which nothing moved
     * since: the same places would be judged the same */
    if (opt->stuck)
        for (int64_t i = 0; i < n; i++)
            if (opt->stuck[i])
                want[i] = 0;
    int64_t n_want = 0;
    for (int64_t i = 0; i < n; i++)
        n_want += want[i];
    st.n_tried = n_want;
    if (n_want == 0) {
        free(want);
        st.seconds = vc_clock_seconds() - t0;
        if (stats)
            *stats = st;
        return 0;
    }

    const int threads = vc_threads_or_default(opt->threads);
    const int nc = opt->candidates;
    vc_ball_tree balls_tree;
    vc_seed_kdtree tree, surface_tree;
    memset(&tree, 0, sizeof tree);
    memset(&surface_tree, 0, sizeof surface_tree);
    int have_balls = 0, rc = 0;
    unsigned char *focus = calloc((size_t)n + 1, 1);
    unsigned char *keep = calloc((size_t)n + 1, 1);
    double *centroid_now = malloc(sizeof(double) * 3 * (size_t)(n + 1));
    double *volume_now = malloc(sizeof(double) * (size_t)(n + 1));
    int64_t *focus_list = malloc(sizeof(int64_t) * (size_t)(2 * LOCAL_MAX + 4));
    int64_t *keep_list = malloc(sizeof(int64_t) * (size_t)(KEEP_MAX + 1));
    int64_t *cell_of_seed = malloc(sizeof(int64_t) * (size_t)(n + 1));
    int64_t *missing = malloc(sizeof(int64_t) * (size_t)(KEEP_MAX + 1));
    candidate *cand = malloc(sizeof(candidate) * (size_t)nc);
    unsigned char *valid = malloc((size_t)nc);
    local_mesh *after = calloc((size_t)nc, sizeof *after);
    vc_kd_hit *hits = malloc(sizeof(vc_kd_hit) * LOCAL_MAX);
    const vc_seeds surface = {n_surface, seeds->xyz, seeds->label};
    if (!focus || !keep || !centroid_now || !volume_now || !focus_list || !keep_list || !cell_of_seed || !missing ||
        !cand || !valid || !after || !hits || vc_seed_kdtree_build(&tree, seeds->xyz, n) ||
        (n_surface > 0 && vc_nearest_seed_index_build(&surface_tree, &surface))) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory mending skew faces");
        goto done;
    }
    if (vc_ball_tree_build(&balls_tree, balls) != 0) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory mending skew faces");
        goto done;
    }
    have_balls = 1;
    for (int64_t i = 0; i < n; i++)
        cell_of_seed[i] = -1;
    for (int64_t i = 0; i < 3 * n; i++)
        centroid_now[i] = NAN;
    for (int64_t c = 0; c < mesh->n_cells; c++)
        if (mesh->cell_seed[c] >= 0 && mesh->cell_seed[c] < n) {
            cell_of_seed[mesh->cell_seed[c]] = c;
            memcpy(centroid_now + 3 * mesh->cell_seed[c], mesh->cell_centroid + 3 * c,
                   3 * sizeof(double));
            volume_now[mesh->cell_seed[c]] = mesh->cell_volume[c];
        }

    for (int64_t s = movable; s < n && !rc; s++) {
        if (!want[s])
            continue;
        /* the cells built: s's and its neighbours' (the cells its move
         * changes; more when a place gives it new neighbours), as the mesh
         * had them (a neighbour an earlier move gave it shows as missing) */
        int64_t n_keep = 0;
        keep_seed(keep, keep_list, &n_keep, KEEP_MAX, s);
        {
            const int64_t c = cell_of_seed[s];
            for (int64_t k = c < 0 ? 0 : mesh->cell_offsets[c]; c >= 0 && k < mesh->cell_offsets[c + 1];
                 k++) {
                const int64_t f = mesh->cell_faces[k];
                const int64_t o = mesh->face_neighbour[f] < 0 ? -1
                                  : mesh->face_owner[f] == c ? mesh->face_neighbour[f]
                                                             : mesh->face_owner[f];
                if (o >= 0)
                    keep_seed(keep, keep_list, &n_keep, KEEP_MAX, mesh->cell_seed[o]);
            }
        }
        double origin[3];
        memcpy(origin, seeds->xyz + 3 * s, sizeof origin);
        vc_kd_hit nearest;
        if (vc_seed_kdtree_knn(&tree, origin, 1, s, &nearest) < 1) {
            for (int64_t i = 0; i < n_keep; i++)
                keep[keep_list[i]] = 0;
            continue;
        }
        const double pick = PICK_RADIUS * sqrt(nearest.d2);
        /* the places, from a stream of this seed's own */
        vc_rng rng;
        vc_rng_init(&rng, opt->random_seed ^ 0x5CE3F00Dull, (uint64_t)s);
        for (int c = 0; c < nc; c++) {
            double u[3], q = 2;
            while (q > 1) {
                for (int d = 0; d < 3; d++)
                    u[d] = 2 * vc_rng_uniform(&rng) - 1;
                q = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
            }
            double *x = cand[c].x;
            for (int d = 0; d < 3; d++)
                x[d] = origin[d] + pick * u[d];
            valid[c] = 0;
            int64_t own = -1;
            if (s - n_surface < opt->n_sphere_seeds) {
                /* a seed on a ball's sphere: onto it */
                own = opt->sphere_ball[s - n_surface];
                const double *bc = balls->center + 3 * own;
                const double e[3] = {x[0] - bc[0], x[1] - bc[1], x[2] - bc[2]};
                const double le = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                if (!(le > 0))
                    continue;
                for (int d = 0; d < 3; d++)
                    x[d] = bc[d] + balls->radius[own] * e[d] / le;
            }
            double dn;
            const int64_t ns = n_surface > 0 ? vc_nearest_seed(&surface_tree, x, &dn) : -1;
            valid[c] = !vc_ball_tree_covers_scaled_except(&balls_tree, x, 1 + opt->clearance, own) &&
                       (n_surface == 0 || (ns >= 0 && seeds->label[ns] == seeds->label[s]));
        }
        /* The seeds around: within a radius that holds every seed able to
         * cut the cells of s and its neighbours as the mesh has them (the
         * places move s by at most `pick`). Build, judge; more cells or a
         * larger radius while a judged cell is missing or not exact. */
        double reach = 0;
        for (int64_t i = 0; i < n_keep; i++) {
            const int64_t t = keep_list[i], c = cell_of_seed[t];
            const double *xt = seeds->xyz + 3 * t;
            const double d[3] = {xt[0] - origin[0], xt[1] - origin[1], xt[2] - origin[2]};
            const double dt = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            const double r = dt + 2 * (c >= 0 ? cell_reach(mesh, c, xt) : 0) + 2 * pick;
            reach = r > reach ? r : reach;
        }
        reach *= 1.01;
        int decided = 0, moved_s = 0;
        for (int attempt = 0; attempt < MAX_ATTEMPTS && n_keep < KEEP_MAX && !rc && !decided;
             attempt++) {
            int truncated;
            const vc_kd_hit all = {-1.0, -1};
            const int got = vc_seed_kdtree_within(&tree, origin, reach * reach, all, s, NULL, NULL,
                                                  hits, LOCAL_MAX, &truncated);
            if (truncated)
                break; /* too many: this seed stays */
            for (int c = 0; c < nc; c++)
                cand[c].ok = valid[c];
            local_mesh before;
            const int b = local_build(seeds, s, origin, origin, hits, got, reach, keep, &before);
            if (b < 0) {
                rc = vc_error_set(err, VC_ENOMEM, "out of memory mending skew faces");
                break;
            }
            if (b > 0 || before.s_cell < 0) {
                local_free(&before);
                break;
            }
            st.n_cells_built += before.m.n_cells;
            int failed = 0;
            shortfall sf = {missing, 0, KEEP_MAX, 0};
            /* The places in batches of PLACE_BATCH (a fixed size: the same
             * places judged for any thread count), until one leaves
             * nothing failing around s: most seeds need one batch. */
            for (int c0 = 0; c0 < nc && !failed; c0 += PLACE_BATCH) {
                const int c1 = c0 + PLACE_BATCH < nc ? c0 + PLACE_BATCH : nc;
                int64_t built = 0;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1) reduction(| : failed) \
    reduction(+ : built)
                for (int c = c0; c < c1; c++) {
                    if (!cand[c].ok)
                        continue;
                    const int a = local_build(seeds, s, origin, cand[c].x, hits, got, reach, keep,
                                              &after[c]);
                    if (a < 0)
                        failed = 1;
                    if (a != 0 || after[c].s_cell < 0) {
                        cand[c].ok = 0;
                        continue;
                    }
                    built += after[c].m.n_cells;
                }
                st.n_cells_built += built;
                if (failed)
                    break;
                /* judged one by one (the focus marks are shared): the
                 * faces of the cells of s and its neighbours, before or
                 * after the move */
                int clean = 0;
                for (int c = c0; c < c1; c++) {
                    if (!cand[c].ok)
                        continue;
                    int n_focus = 0;
                    mark_focus(&before, focus, focus_list, &n_focus);
                    mark_focus(&after[c], focus, focus_list, &n_focus);
                    cand[c].before = focus_badness(&before, seeds, centroid_now, volume_now, focus,
                                                   focus_list, n_focus, opt->max_skew, &sf);
                    cand[c].after = focus_badness(&after[c], seeds, centroid_now, volume_now, focus,
                                                  focus_list, n_focus, opt->max_skew, &sf);
                    for (int i = 0; i < n_focus; i++)
                        focus[focus_list[i]] = 0;
                    clean |= cand[c].after == 0;
                }
                if (sf.n_missing > 0 || sf.grow)
                    break; /* more cells or a larger radius first */
                if (clean) {
                    for (int c = c1; c < nc; c++)
                        cand[c].ok = 0; /* not judged */
                    break;
                }
            }
            int best = -1;
            if (!failed && sf.n_missing == 0 && !sf.grow) {
                decided = 1;
                for (int c = 0; c < nc; c++)
                    if (cand[c].ok && cand[c].after < cand[c].before &&
                        (best < 0 || cand[c].after < cand[best].after))
                        best = c;
            }
            if (best >= 0) {
                moved_s = 1;
                memcpy(seeds->xyz + 3 * s, cand[best].x, 3 * sizeof(double));
                vc_seed_kdtree_refit(&tree, seeds->xyz);
                st.n_moved++;
                /* the cells it changed, as they are now (exact: judged) */
                const local_mesh *a = &after[best];
                int n_focus = 0;
                mark_focus(a, focus, focus_list, &n_focus);
                for (int i = 0; i < n_focus; i++) {
                    const int64_t t = focus_list[i], lt = local_index(a, t);
                    const int64_t c = lt >= 0 ? a->cell_of[lt] : -1;
                    if (c >= 0) {
                        memcpy(centroid_now + 3 * t, a->m.cell_centroid + 3 * c, 3 * sizeof(double));
                        volume_now[t] = a->m.cell_volume[c];
                    }
                    focus[t] = 0;
                }
            }
            local_free(&before);
            for (int c = 0; c < nc; c++)
                local_free(&after[c]);
            if (failed) {
                rc = vc_error_set(err, VC_ENOMEM, "out of memory mending skew faces");
                break;
            }
            if (decided)
                break;
            if (sf.n_missing > 0) {
                const int64_t had = n_keep;
                for (int i = 0; i < sf.n_missing; i++)
                    keep_seed(keep, keep_list, &n_keep, KEEP_MAX, sf.missing[i]);
                if (n_keep > had)
                    continue; /* those cells too */
                break;        /* no room: this seed stays */
            }
            reach *= 1.5;     /* a judged cell was not exact */
        }
        /* tried in vain (no place helped, or its cells were too many to
         * judge): the same would happen again while nothing near moves */
        if (!moved_s && !rc && opt->stuck)
            opt->stuck[s] = 1;
        for (int64_t i = 0; i < n_keep; i++)
            keep[keep_list[i]] = 0;
    }

done:
    free(want);
    free(focus);
    free(keep);
    free(centroid_now);
    free(volume_now);
    free(focus_list);
    free(keep_list);
    free(cell_of_seed);
    free(missing);
    free(cand);
    free(valid);
    free(after);
    free(hits);
    vc_seed_kdtree_free(&tree);
    vc_seed_kdtree_free(&surface_tree);
    if (have_balls)
        vc_ball_tree_free(&balls_tree);
    st.seconds = vc_clock_seconds() - t0;
    if (stats)
        *stats = st;
    return rc;
}
