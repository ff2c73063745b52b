/* Skewness of interior faces as OpenFOAM's checkMesh measures it, and the
 * collapse of the faces above a limit (see polymesh.h).
 *
 * Why: VoroCrust puts every surface vertex at a ball centre that is
 * equidistant from all the seeds on that ball's sphere. The inside seeds of
 * one sphere lie nearly on a circle, so their cells meet near the sphere's
 * inward axis in small or needle-like faces. Those faces are exact Voronoi
 * faces, but the line between the two cell centroids (which lie deep in the
 * cells) passes far from them, and checkMesh calls them skew. Collapsing
 * such a face to a segment or a point removes it; the thesis (7.4) suggests
 * this kind of mesh improvement as a post-process. The boundary (the reconstructed
 * surface) is never moved. */
#include "vorocrust/polymesh.h"
#include "polymesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A collapse is refused when a face around it would turn by more than
 * acos(SKEW_MAX_TURN_COS), lose a pyramid, or get a non-orthogonality
 * above SKEW_MAX_NONORTH_DEG (checkMesh's limit is 70 degrees). */
#define SKEW_MAX_TURN_COS 0.0
#define SKEW_MAX_NONORTH_DEG 65.0
/* A collapse touching more cells than this is refused (never seen). */
#define SKEW_MAX_NEAR_CELLS 256

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double norm3(const double *a)
{
    return sqrt(dot3(a, a));
}

/* OpenFOAM's faceSkewness for interior face f: the distance from the face
 * centre to where the line between the cell centres crosses the face plane,
 * over the face's extent in that direction (at least a fifth of the centre
 * distance). */
double vc_polymesh_face_skewness(const vc_polymesh *m, int64_t f)
{
    if (m->face_neighbour[f] < 0)
        return 0;
    return vc_polymesh_face_skewness_between(m, f, m->cell_centroid + 3 * m->face_owner[f],
                                             m->cell_centroid + 3 * m->face_neighbour[f]);
}

double vc_polymesh_face_skewness_between(const vc_polymesh *m, int64_t f, const double co[3],
                                         const double cn[3])
{
    const double *fc = m->face_centroid + 3 * f, *n = m->face_normal + 3 * f;
    double d[3] = {cn[0] - co[0], cn[1] - co[1], cn[2] - co[2]};
    double cpf[3] = {fc[0] - co[0], fc[1] - co[1], fc[2] - co[2]};
    double dn = dot3(n, d);
    if (dn == 0)
        return INFINITY;
    double t = dot3(n, cpf) / dn, sv[3];
    for (int k = 0; k < 3; k++)
        sv[k] = cpf[k] - t * d[k];
    double s = norm3(sv);
    if (s == 0)
        return 0;
    double extent = 0.2 * norm3(d);
    const int64_t *fv = m->face_vertices + m->face_offsets[f];
    for (int64_t i = 0, nv = vc_polymesh_face_size(m, f); i < nv; i++) {
        const double *p = m->points + 3 * fv[i];
        double r[3] = {p[0] - fc[0], p[1] - fc[1], p[2] - fc[2]};
        extent = fmax(extent, fabs(dot3(sv, r)) / s);
    }
    return s / extent;
}

typedef struct collapse_state {
    vc_polymesh *m;
    int64_t *parent;          /* union-find over points: merged groups */
    unsigned char *fixed;     /* point on the boundary */
    unsigned char *touched;   /* point near a collapse of this round */
    unsigned char *cell_hit;  /* cell near a collapse of this round */
    int64_t *vf_offsets;      /* point -> faces, CSR */
    int64_t *vf_faces;
    vc_point_merge_buffers merge; /* for vc_polymesh_merge_points */
    unsigned char *point_moved;   /* merged or moved in this round */
    int64_t *scratch;         /* a face's cycle after a plan (-1 - target: merged) */
    int64_t blocker;          /* the face that made collapse_is_safe refuse */
    int64_t near_cells[SKEW_MAX_NEAR_CELLS];      /* cells around a plan */
    double near_centroids[SKEW_MAX_NEAR_CELLS][3]; /* and their new centroids */
    unsigned char *forced;    /* face to collapse although not skew: it blocked one */
    int64_t *blockers;        /* this round's blocking faces (old numbering) */
    int64_t max_face_size;
} collapse_state;

/* A way of collapsing a face: its points (all of them, in cycle order) go
 * to one or two targets; with two, each takes a contiguous run of the
 * cycle and the face becomes a segment. */
typedef struct collapse_plan {
    int n;               /* points of the face */
    const int64_t *pts;  /* the face's cycle */
    unsigned char *to;   /* target of each point: 0 or 1 */
    double pos[2][3];
    double max_move;
} collapse_plan;

static int plan_target(const collapse_plan *pl, int64_t v)
{
    for (int i = 0; i < pl->n; i++)
        if (pl->pts[i] == v)
            return pl->to[i];
    return -1;
}

/* Face g's cycle after the plan (merged points as -1 - target) in
 * s->scratch; its length, 0 when it degenerates (removed), -1 when it
 * pinches (a point twice). */
static int64_t cycle_after(collapse_state *s, const collapse_plan *pl, int64_t g)
{
    const vc_polymesh *m = s->m;
    const int64_t *fv = m->face_vertices + m->face_offsets[g];
    const int64_t n = vc_polymesh_face_size(m, g);
    int64_t w = 0;
    for (int64_t i = 0; i < n; i++) {
        int t = plan_target(pl, fv[i]);
        int64_t x = t >= 0 ? -1 - t : fv[i];
        if (w == 0 || s->scratch[w - 1] != x)
            s->scratch[w++] = x;
    }
    while (w > 1 && s->scratch[0] == s->scratch[w - 1])
        w--;
    if (w < 3)
        return 0;
    for (int64_t i = 0; i < w; i++)
        for (int64_t j = i + 1; j < w; j++)
            if (s->scratch[i] == s->scratch[j])
                return -1;
    return w;
}

/* Area vector and centroid of the cycle cycle_after left in s->scratch. */
static void cycle_geometry(const collapse_state *s, const collapse_plan *pl, int64_t w,
                           double av[3], double cen[3])
{
    const double *const targets[2] = {pl->pos[0], pl->pos[1]};
    vc_polygon_geometry(s->m->points, s->scratch, w, targets, av, cen);
}

/* Checks cell c after the plan: no face pinches or turns over, the volume
 * is positive and every face pyramid from the new centroid too (OpenFOAM's
 * "face pyramids" check). Sets the new centroid. */
static int cell_stays_valid(collapse_state *s, const collapse_plan *pl, int64_t c, double cen[3])
{
    const vc_polymesh *m = s->m;
    const int64_t b = m->cell_offsets[c], e = m->cell_offsets[c + 1];
    double ref[3] = {0, 0, 0};
    int64_t n_kept = 0;
    for (int pass = 0; pass < 3; pass++) {
        double vol = 0, acc[3] = {0, 0, 0};
        for (int64_t k = b; k < e; k++) {
            const int64_t g = m->cell_faces[k];
            const int64_t w = cycle_after(s, pl, g);
            if (w < 0)
                return 0;
            if (w == 0)
                continue;
            double av[3], fc[3];
            cycle_geometry(s, pl, w, av, fc);
            const double sgn = m->face_owner[g] == c ? 1.0 : -1.0;
            if (pass == 0) {
                double a = norm3(av);
                if (!(a > 0) || dot3(av, m->face_normal + 3 * g) < SKEW_MAX_TURN_COS * a) {
                    s->blocker = g;
                    return 0;
                }
                for (int d = 0; d < 3; d++)
                    ref[d] += fc[d];
                n_kept++;
            } else if (pass == 1) {
                double pv = sgn * (av[0] * (fc[0] - ref[0]) + av[1] * (fc[1] - ref[1]) +
                                   av[2] * (fc[2] - ref[2])) / 3.0;
                vol += pv;
                for (int d = 0; d < 3; d++)
                    acc[d] += pv * (0.75 * fc[d] + 0.25 * ref[d]);
            } else {
                double r[3] = {fc[0] - cen[0], fc[1] - cen[1], fc[2] - cen[2]};
                if (sgn * dot3(av, r) <= 0) {
                    s->blocker = g;
                    return 0;
                }
            }
        }
        if (pass == 0) {
            if (n_kept < 4)
                return 0;
            for (int d = 0; d < 3; d++)
                ref[d] /= (double)n_kept;
        } else if (pass == 1) {
            if (!(vol > 0))
                return 0;
            for (int d = 0; d < 3; d++)
                cen[d] = acc[d] / vol;
        }
    }
    return 1;
}

/* Whether the plan keeps every cell around the face's points valid (see
 * cell_stays_valid) and the faces around them orthogonal enough, judged
 * with the cells' new centroids. */
static int collapse_is_safe(collapse_state *s, int64_t f, const collapse_plan *pl)
{
    const vc_polymesh *m = s->m;
    const double cos_nonorth = cos(SKEW_MAX_NONORTH_DEG * 3.14159265358979323846 / 180.0);
    int n_cells = 0;
    for (int gi = 0; gi < pl->n; gi++) {
        const int64_t v = pl->pts[gi];
        for (int64_t k = s->vf_offsets[v]; k < s->vf_offsets[v + 1]; k++) {
            const int64_t g = s->vf_faces[k];
            const int64_t cells[2] = {m->face_owner[g], m->face_neighbour[g]};
            for (int j = 0; j < 2; j++) {
                int known = cells[j] < 0;
                for (int i = 0; i < n_cells && !known; i++)
                    known = s->near_cells[i] == cells[j];
                if (known)
                    continue;
                if (n_cells == SKEW_MAX_NEAR_CELLS)
                    return 0;
                s->near_cells[n_cells] = cells[j];
                if (!cell_stays_valid(s, pl, cells[j], s->near_centroids[n_cells]))
                    return 0;
                n_cells++;
            }
        }
    }
    for (int gi = 0; gi < pl->n; gi++) {
        const int64_t v = pl->pts[gi];
        for (int64_t k = s->vf_offsets[v]; k < s->vf_offsets[v + 1]; k++) {
            const int64_t g = s->vf_faces[k];
            if (g == f || m->face_neighbour[g] < 0)
                continue;
            const int64_t w = cycle_after(s, pl, g);
            if (w <= 0)
                continue;
            double av[3], fc[3];
            cycle_geometry(s, pl, w, av, fc);
            const double *co = NULL, *cn = NULL;
            for (int i = 0; i < n_cells; i++) {
                if (s->near_cells[i] == m->face_owner[g])
                    co = s->near_centroids[i];
                if (s->near_cells[i] == m->face_neighbour[g])
                    cn = s->near_centroids[i];
            }
            double d[3] = {cn[0] - co[0], cn[1] - co[1], cn[2] - co[2]};
            if (dot3(d, av) < cos_nonorth * norm3(d) * norm3(av))
                return 0;
        }
    }
    return 1;
}

/* Marks the points and cells around the face's points as touched: a later
 * collapse in the same round would be checked against moving positions. */
static void mark_touched(collapse_state *s, const collapse_plan *pl)
{
    const vc_polymesh *m = s->m;
    for (int gi = 0; gi < pl->n; gi++) {
        const int64_t v = pl->pts[gi];
        for (int64_t k = s->vf_offsets[v]; k < s->vf_offsets[v + 1]; k++) {
            const int64_t g = s->vf_faces[k];
            for (int64_t i = m->face_offsets[g]; i < m->face_offsets[g + 1]; i++)
                s->touched[m->face_vertices[i]] = 1;
            s->cell_hit[m->face_owner[g]] = 1;
            if (m->face_neighbour[g] >= 0)
                s->cell_hit[m->face_neighbour[g]] = 1;
        }
    }
}

static int face_is_free(const collapse_state *s, int64_t f)
{
    const vc_polymesh *m = s->m;
    for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; i++) {
        const int64_t v = m->face_vertices[i];
        if (s->touched[v])
            return 0;
        for (int64_t k = s->vf_offsets[v]; k < s->vf_offsets[v + 1]; k++) {
            const int64_t g = s->vf_faces[k];
            if (s->cell_hit[m->face_owner[g]] ||
                (m->face_neighbour[g] >= 0 && s->cell_hit[m->face_neighbour[g]]))
                return 0;
        }
    }
    return 1;
}

/* Sets target t of the plan for the points whose pl->to is t: the one
 * boundary point among them (a run with two cannot move: returns -1), else
 * their average; and raises pl->max_move. */
static int plan_place(const collapse_state *s, collapse_plan *pl, int t)
{
    const double *points = s->m->points;
    int n_fixed = 0, count = 0;
    double *pos = pl->pos[t];
    pos[0] = pos[1] = pos[2] = 0;
    for (int i = 0; i < pl->n; i++) {
        if (pl->to[i] != t)
            continue;
        count++;
        if (s->fixed[pl->pts[i]]) {
            if (n_fixed++)
                return -1;
            memcpy(pos, points + 3 * pl->pts[i], sizeof(double) * 3);
        }
    }
    if (!n_fixed)
        for (int i = 0; i < pl->n; i++)
            if (pl->to[i] == t)
                for (int k = 0; k < 3; k++)
                    pos[k] += points[3 * pl->pts[i] + k] / count;
    for (int i = 0; i < pl->n; i++)
        if (pl->to[i] == t) {
            const double *p = points + 3 * pl->pts[i];
            double d[3] = {p[0] - pos[0], p[1] - pos[1], p[2] - pos[2]};
            pl->max_move = fmax(pl->max_move, norm3(d));
        }
    return 0;
}

/* Finds the safe collapse of face f that moves points least. Two edges of
 * the face survive as one segment (the points between them merge into its
 * two ends), tried for every pair of edges; the last resort merges the
 * whole face into one point. Returns 1 with the plan in *best, else 0 and
 * in *blocker the face that turned over in the least-moving plan (-1 if
 * none did). */
static int try_collapse(collapse_state *s, int64_t f, collapse_plan *best, unsigned char *to_best,
                        unsigned char *to_try, int64_t *blocker)
{
    const vc_polymesh *m = s->m;
    const int n = (int)vc_polymesh_face_size(m, f);
    const int64_t *fv = m->face_vertices + m->face_offsets[f];
    int found = 0;
    double blocked_move = INFINITY;
    *blocker = -1;
    best->max_move = INFINITY;
    collapse_plan pl = {n, fv, to_try, {{0}}, 0};
    /* edge i runs from point i to point i+1; surviving edges i < j split the
     * cycle into points i+1..j (target 0) and the rest (target 1) */
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j <= n; j++) {
            const int whole = j == n; /* the last resort, tried once */
            if (whole && i > 0)
                break;
            for (int k = 0; k < n; k++)
                to_try[k] = whole ? 0 : (unsigned char)!(k > i && k <= j);
            pl.max_move = 0;
            if (plan_place(s, &pl, 0) || (!whole && plan_place(s, &pl, 1)))
                continue;
            if (pl.max_move >= best->max_move)
                continue;
            s->blocker = -1;
            if (!collapse_is_safe(s, f, &pl)) {
                if (!found && s->blocker >= 0 && pl.max_move < blocked_move) {
                    blocked_move = pl.max_move;
                    *blocker = s->blocker;
                }
                continue;
            }
            *best = pl;
            best->to = to_best;
            memcpy(to_best, to_try, (size_t)n);
            found = 1;
        }
    return found;
}

static int build_point_faces(collapse_state *s)
{
    const vc_polymesh *m = s->m;
    free(s->vf_offsets);
    free(s->vf_faces);
    s->vf_offsets = calloc((size_t)m->n_points + 1, sizeof(int64_t));
    s->vf_faces = malloc(sizeof(int64_t) * (size_t)(m->face_offsets[m->n_faces] + 1));
    if (!s->vf_offsets || !s->vf_faces)
        return -1;
    for (int64_t i = 0; i < m->face_offsets[m->n_faces]; i++)
        s->vf_offsets[m->face_vertices[i] + 1]++;
    for (int64_t v = 0; v < m->n_points; v++)
        s->vf_offsets[v + 1] += s->vf_offsets[v];
    for (int64_t f = 0; f < m->n_faces; f++)
        for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; i++) {
            const int64_t v = m->face_vertices[i];
            s->vf_faces[s->vf_offsets[v]++] = f;
        }
    for (int64_t v = m->n_points; v > 0; v--)
        s->vf_offsets[v] = s->vf_offsets[v - 1];
    s->vf_offsets[0] = 0;
    return 0;
}

typedef struct skew_face {
    double skew;
    int64_t face;
} skew_face;

static int cmp_skew_desc(const void *pa, const void *pb)
{
    const skew_face *a = pa, *b = pb;
    if (a->skew != b->skew)
        return a->skew > b->skew ? -1 : 1;
    return (a->face > b->face) - (a->face < b->face);
}

static void collapse_state_free(collapse_state *s)
{
    free(s->parent);
    free(s->fixed);
    free(s->touched);
    free(s->cell_hit);
    free(s->vf_offsets);
    free(s->vf_faces);
    vc_point_merge_buffers_free(&s->merge);
    free(s->point_moved);
    free(s->forced);
    free(s->blockers);
    free(s->scratch);
}

int vc_polymesh_collapse_skew_faces(vc_polymesh *m, double max_skew, int max_rounds,
                                    vc_skew_collapse_stats *st)
{
    memset(st, 0, sizeof *st);
    collapse_state s;
    memset(&s, 0, sizeof s);
    s.m = m;
    const size_t np = (size_t)(m->n_points > 0 ? m->n_points : 1);
    const size_t nc = (size_t)(m->n_cells > 0 ? m->n_cells : 1);
    s.parent = malloc(sizeof(int64_t) * np);
    s.fixed = calloc(np, 1);
    s.touched = calloc(np, 1);
    s.cell_hit = calloc(nc, 1);
    int merge_ok = vc_point_merge_buffers_init(&s.merge, m) == 0;
    s.point_moved = calloc(np, 1);
    s.forced = calloc((size_t)(m->n_faces > 0 ? m->n_faces : 1), 1);
    s.blockers = malloc(sizeof(int64_t) * (size_t)(m->n_interior_faces + 1));
    for (int64_t f = 0; f < m->n_faces; f++)
        s.max_face_size = fmax(s.max_face_size, vc_polymesh_face_size(m, f));
    s.scratch = malloc(sizeof(int64_t) * (size_t)(s.max_face_size + 1));
    unsigned char *to_best = malloc((size_t)(s.max_face_size + 1));
    unsigned char *to_try = malloc((size_t)(s.max_face_size + 1));
    skew_face *bad = malloc(sizeof(skew_face) * (size_t)(m->n_interior_faces + 1));
    int rc = -1;
    if (!s.parent || !s.fixed || !s.touched || !s.cell_hit || !merge_ok ||
        !s.point_moved || !s.forced || !s.blockers ||
        !s.scratch || !to_best || !to_try || !bad)
        goto out;
    /* the boundary, and the interfaces between regions, stay where they are */
    for (int64_t f = 0; f < m->n_faces; f++) {
        if (f < m->n_interior_faces &&
            (!m->cell_region ||
             m->cell_region[m->face_owner[f]] == m->cell_region[m->face_neighbour[f]]))
            continue;
        for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; i++)
            s.fixed[m->face_vertices[i]] = 1;
    }

    for (int round = 0;; round++) {
        int64_t n_bad = 0, n_skew = 0;
        double worst = 0;
        for (int64_t f = 0; f < m->n_interior_faces; f++) {
            double k = vc_polymesh_face_skewness(m, f);
            worst = fmax(worst, k);
            n_skew += k > max_skew;
            if (k > max_skew || s.forced[f])
                bad[n_bad++] = (skew_face){k, f};
        }
        if (round == 0)
            st->max_skew_before = worst;
        st->max_skew_after = worst;
        st->n_skew_left = n_skew;
        if (n_skew == 0 || round == max_rounds)
            break;
        qsort(bad, (size_t)n_bad, sizeof *bad, cmp_skew_desc);
        if (build_point_faces(&s))
            goto out;
        vc_uf_init(s.parent, m->n_points);
        memset(s.touched, 0, np);
        memset(s.point_moved, 0, np);
        memset(s.cell_hit, 0, nc);
        int64_t n_done = 0, n_blockers = 0;
        for (int64_t i = 0; i < n_bad; i++) {
            const int64_t f = bad[i].face;
            if (!face_is_free(&s, f))
                continue; /* next round, with fresh geometry */
            collapse_plan pl;
            int64_t blocker;
            if (!try_collapse(&s, f, &pl, to_best, to_try, &blocker)) {
                /* A smaller face in the way goes first, next round. */
                if (blocker >= 0 && blocker < m->n_interior_faces && !s.forced[blocker] &&
                    m->face_area[blocker] < m->face_area[f])
                    s.blockers[n_blockers++] = blocker;
                continue;
            }
            st->n_made_room += s.forced[f] && !(bad[i].skew > max_skew);
            st->max_move = fmax(st->max_move, pl.max_move);
            for (int t = 0; t < 2; t++) {
                int64_t root = -1;
                for (int g = 0; g < pl.n; g++)
                    if (pl.to[g] == t && (root < 0 || s.fixed[pl.pts[g]]))
                        root = pl.pts[g];
                if (root < 0)
                    continue;
                for (int g = 0; g < pl.n; g++)
                    if (pl.to[g] == t) {
                        s.parent[pl.pts[g]] = root;
                        s.point_moved[pl.pts[g]] = 1;
                    }
                memcpy(m->points + 3 * root, pl.pos[t], sizeof pl.pos[t]);
            }
            mark_touched(&s, &pl);
            n_done++;
        }
        if (n_done == 0 && n_blockers == 0)
            break;
        st->n_collapsed += n_done;
        st->n_rounds = round + 1;
        vc_polymesh_merge_points(m, s.parent, s.point_moved, NULL, &s.merge);
        memset(s.forced, 0, (size_t)(m->n_faces > 0 ? m->n_faces : 1));
        for (int64_t i = 0; i < n_blockers; i++)
            if (s.merge.new_face[s.blockers[i]] >= 0)
                s.forced[s.merge.new_face[s.blockers[i]]] = 1;
    }
    if (vc_polymesh_drop_unused_points(m))
        goto out;
    rc = 0;
out:
    collapse_state_free(&s);
    free(to_best);
    free(to_try);
    free(bad);
    return rc;
}
