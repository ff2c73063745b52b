/* Plane-by-plane cutting of a convex polyhedron held in dual form (see
 * convex_cell.h).
 *
 * A cut marks the triangles whose vertex lies outside the plane (beyond a
 * tolerance), finds the boundary of that region (its edges whose reverse
 * is not marked), checks that the boundary is one simple cycle, computes
 * where each boundary edge of the polyhedron crosses the plane (by
 * interpolation between its kept and its removed end, so the point lies on
 * the edge), and replaces the marked triangles by a fan of the cycle to
 * the new plane. */
#include "convex_cell.h"

#include "util/exact_predicates.h"

#include <math.h>
#include <stdlib.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <string.h>

/* Makes room for need elements of elem bytes; returns the data pointer,
 * or NULL when out of memory (the buffer then keeps its old contents). */
static void *reserve(vc_cell_buf *b, int need, size_t elem)
{
    if (need > b->cap) {
        int n = b->cap ? b->cap : 64;
        while (n < need)
            n *= 2;
        void *q = realloc(b->data, (size_t)n * elem);
        if (!q)
            return NULL;
        b->data = q;
        b->cap = n;
    }
    return b->data;
}

void vc_convex_cell_init(vc_convex_cell *c) { memset(c, 0, sizeof *c); }

void vc_convex_cell_free(vc_convex_cell *c)
{
    vc_cell_buf *bufs[] = {&c->b_pc, &c->b_r2, &c->b_ev, &c->b_eb, &c->b_out,         &c->b_plane,    &c->b_plane_id, &c->b_tri,      &c->b_px,  &c->b_py, &c->b_pz,
                           &c->b_dist,       &c->b_conflict, &c->b_next,     &c->b_edge_tri,
                           &c->b_edge_out,   &c->b_face_plane, &c->b_face_plane_index, &c->b_face_start, &c->b_fv,
                           &c->b_entry,      &c->b_count,    &c->b_edge_mark, &c->b_edge_owner, &c->b_new_pt,
                           &c->b_new_tri,    &c->b_prow,     &c->b_prow_ok};
    for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++)
        free(bufs[i]->data);
    memset(c, 0, sizeof *c);
}

/* A plane is (n, d, |n|): the normal's length kept for the error bounds
 * of the vertices it makes. */
#define PLANE_STRIDE 5

static inline double norm2(const double *x)
{
    return x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
}

/* rmax2 from the per-vertex squared distances and error bounds: the
 * exact vertex is within ev of the point, so a seed can cut only within
 * twice |x| + ev of the seed, and the point's clearance ball must grow by
 * 2 ev to hold the exact one's. */
static void update_rmax2(vc_convex_cell *c)
{
    double r2 = 0, e = 0;
    for (int i = 0; i < c->nt; i++) {
        r2 = c->r2[i] > r2 ? c->r2[i] : r2;
        e = c->ev[i] > e ? c->ev[i] : e;
    }
    const double r = sqrt(r2) + 2 * e;
    c->rmax2 = r * r;
}

/* Unit roundoff. */
#define U 1.1102230246251565e-16

/* Records triangle t (planes tr[0..2]) as the holder of its three edges. */
static inline void set_edge_owner(uint16_t *owner, const int *tr, int t)
{
    owner[tr[0] * VC_EDGE_OWNER_PLANES + tr[1]] = (uint16_t)t;
    owner[tr[1] * VC_EDGE_OWNER_PLANES + tr[2]] = (uint16_t)t;
    owner[tr[2] * VC_EDGE_OWNER_PLANES + tr[0]] = (uint16_t)t;
}

/* Does triangle tr hold the directed edge a -> b? */
static inline int holds_edge(const int *tr, int a, int b)
{
    /* Without branches: the answer is nearly always yes. */
    return ((tr[0] == a) & (tr[1] == b)) | ((tr[1] == a) & (tr[2] == b)) |
           ((tr[2] == a) & (tr[0] == b));
}

int vc_convex_cell_reset_box(vc_convex_cell *c, const double lo[3],
                             const double hi[3], const int64_t wall_id[6])
{
    c->plane = reserve(&c->b_plane, 6, PLANE_STRIDE * sizeof(double));
    c->plane_id = reserve(&c->b_plane_id, 6, sizeof(int64_t));
    c->tri = reserve(&c->b_tri, 8, 3 * sizeof(int));
    c->px = reserve(&c->b_px, 8, sizeof(double));
    c->py = reserve(&c->b_py, 8, sizeof(double));
    c->pz = reserve(&c->b_pz, 8, sizeof(double));
    c->r2 = reserve(&c->b_r2, 8, sizeof(double));
    c->ev = reserve(&c->b_ev, 8, sizeof(double));
    c->eb = reserve(&c->b_eb, 8, sizeof(double));
    c->pc = reserve(&c->b_pc, 8, VC_POWER_CACHE * sizeof(double));
    c->edge_owner = reserve(&c->b_edge_owner, VC_EDGE_OWNER_PLANES * VC_EDGE_OWNER_PLANES,
                            sizeof(uint16_t));
    c->prow = reserve(&c->b_prow, 6, VC_POWER_ROW * sizeof(double));
    c->prow_ok = reserve(&c->b_prow_ok, 6, 1);
    if (!c->plane || !c->plane_id || !c->tri || !c->px || !c->py || !c->pz || !c->r2 ||
        !c->ev || !c->eb || !c->pc || !c->edge_owner || !c->prow || !c->prow_ok)
        return VC_CELL_NOMEM;
    memset(c->prow_ok, 0, 6);
    /* Plane 2 * axis is the lower wall (normal -e_axis), 2 * axis + 1 the
     * upper one. */
    for (int a = 0; a < 3; a++) {
        for (int side = 0; side < 2; side++) {
            double *q = c->plane + PLANE_STRIDE * (2 * a + side);
            q[0] = q[1] = q[2] = 0;
            q[a] = side ? 1.0 : -1.0;
            q[3] = side ? hi[a] : -lo[a];
            q[4] = 1.0;
            c->plane_id[2 * a + side] = wall_id[2 * a + side];
        }
    }
    c->np = 6;
    /* Corner k: upper x wall if bit 0, upper y if bit 1, upper z if bit 2.
     * The normals' determinant is the product of their signs; swap two
     * planes where it is negative. */
    for (int k = 0; k < 8; k++) {
        int bx = k & 1, by = (k >> 1) & 1, bz = (k >> 2) & 1;
        int *t = c->tri + 3 * k;
        t[0] = bx;
        t[1] = 2 + by;
        t[2] = 4 + bz;
        if ((bx + by + bz) % 2 == 0) { /* one or three negative signs */
            t[1] = 4 + bz;
            t[2] = 2 + by;
        }
        double x[3] = {bx ? hi[0] : lo[0], by ? hi[1] : lo[1], bz ? hi[2] : lo[2]};
        c->px[k] = x[0];
        c->py[k] = x[1];
        c->pz[k] = x[2];
        c->r2[k] = norm2(x);
        /* each coordinate is a wall less the seed, rounded once */
        c->ev[k] = 2 * U * sqrt(c->r2[k]);
        c->eb[k] = c->ev[k] + 8 * U * sqrt(c->r2[k]);
        c->pc[VC_POWER_CACHE * k + 13] = 0;
    }
    c->nt = 8;
    c->n_exact = 0;
    update_rmax2(c);
    for (int t = 0; t < 8; t++)
        set_edge_owner(c->edge_owner, c->tri + 3 * t, t);
    c->edge_owner_ok = 1;
    return 0;
}

/* Does one of the conflict triangles hold the directed edge a -> b? */
static int has_edge(const int *tri, const int *list, int n, int a, int b)
{
    for (int i = 0; i < n; i++) {
        const int *t = tri + 3 * list[i];
        if ((t[0] == a && t[1] == b) || (t[1] == a && t[2] == b) || (t[2] == a && t[0] == b))
            return 1;
    }
    return 0;
}

/* vc_solve_planes with the normals' lengths given (len[i] = |n_i|) and
 * |y| returned in *vy: the cut's new vertices take them from the planes,
 * where they are kept (three square roots a vertex fewer). */
static inline double solve_planes_len(const double *const q[3], const double len[3], const int wall[3],
                                      double y[3], double *det, double *vy_out)
{
    double C[3][3];
    for (int i = 0; i < 3; i++) {
        const double *u = q[(i + 1) % 3], *v = q[(i + 2) % 3];
        C[i][0] = u[1] * v[2] - u[2] * v[1];
        C[i][1] = u[2] * v[0] - u[0] * v[2];
        C[i][2] = u[0] * v[1] - u[1] * v[0];
    }
    const double D = q[0][0] * C[0][0] + q[0][1] * C[0][1] + q[0][2] * C[0][2];
    if (det)
        *det = D;
    for (int k = 0; k < 3; k++)
        y[k] = (q[0][3] * C[0][k] + q[1][3] * C[1][k] + q[2][3] * C[2][k]) / D;
    const double vy = sqrt(norm2(y));
    *vy_out = vy;
    if (!(D != 0))
        return INFINITY;
    double sum = 6 * vy * len[0] * len[1] * len[2];
    for (int i = 0; i < 3; i++) {
        const double d = fabs(q[i][3]);
        const double dd = wall[i] ? d : 4 * len[i] * len[i], dn = wall[i] ? 0 : len[i];
        sum += len[(i + 1) % 3] * len[(i + 2) % 3] * (dd + dn * vy + 7 * d);
    }
    const double e = 4 * U * sum / fabs(D) + 2 * U * vy;
    return isfinite(e) ? e : INFINITY;
}

double vc_solve_planes(const double *const q[3], const int wall[3], double y[3], double *det, double *norm_y)
{
    double len[3], vy;
    for (int i = 0; i < 3; i++)
        len[i] = sqrt(q[i][0] * q[i][0] + q[i][1] * q[i][1] + q[i][2] * q[i][2]);
    const double e = solve_planes_len(q, len, wall, y, det, &vy);
    if (norm_y)
        *norm_y = vy;
    return e;
}

/* The vertex of planes a, b and P (in that order: det(n_a, n_b, n_P) > 0
 * in exact arithmetic) into y, with the bound of vc_solve_planes (+inf
 * where the rounded determinant has the wrong sign). */
static double solve_vertex(const vc_convex_cell *c, int ia, int ib, int ic, double y[3], double *vy)
{
    const double *q[3] = {c->plane + PLANE_STRIDE * ia, c->plane + PLANE_STRIDE * ib,
                          c->plane + PLANE_STRIDE * ic};
    const double len[3] = {q[0][4], q[1][4], q[2][4]};
    const int wall[3] = {c->plane_id[ia] < 0, c->plane_id[ib] < 0, c->plane_id[ic] < 0};
    double D;
    const double e = solve_planes_len(q, len, wall, y, &D, vy);
    return D > 0 ? e : INFINITY;
}

int vc_convex_cell_cut(vc_convex_cell *c, const double p[3], int64_t plane_id)
{
    const double p2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const double half = 0.5 * p2;
    const double plen = sqrt(p2), pterm = 12 * U * plen;
    const int nt = c->nt, np = c->np;

    double *dist = reserve(&c->b_dist, nt, sizeof(double));
    int *conflict = reserve(&c->b_conflict, nt, sizeof(int));
    unsigned char *out = reserve(&c->b_out, nt, 1);
    if (!dist || !conflict || !out)
        return VC_CELL_NOMEM;
    int n_out = 0;
    /* Distances first and whether any may be beyond the plane (branch-free,
     * vectorizable loops); the sides only when the plane may cut. */
    {
        const double *px = c->px, *py = c->py, *pz = c->pz;
        const double p0 = p[0], p1 = p[1], p2c = p[2];
        double smax = -INFINITY; /* of dist + its bound; NaN ignored */
        const double *eb = c->eb;
        int t = 0;
#ifdef __SSE2__
        /* Two vertices at a time, with the same operations in the same
         * order as the scalar expression below. */
        const __m128d P0 = _mm_set1_pd(p0), P1 = _mm_set1_pd(p1), P2 = _mm_set1_pd(p2c),
                      H = _mm_set1_pd(half), PL = _mm_set1_pd(plen), PT = _mm_set1_pd(pterm);
        __m128d m = _mm_set1_pd(-INFINITY);
        for (; t + 1 < nt; t += 2) {
            __m128d s2 = _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(px + t), P0),
                                    _mm_mul_pd(_mm_loadu_pd(py + t), P1));
            s2 = _mm_sub_pd(_mm_add_pd(s2, _mm_mul_pd(_mm_loadu_pd(pz + t), P2)), H);
            _mm_storeu_pd(dist + t, s2);
            __m128d b = _mm_mul_pd(PL, _mm_add_pd(_mm_loadu_pd(eb + t), PT));
            m = _mm_max_pd(_mm_add_pd(s2, b), m); /* per lane */
        }
        double mm[2];
        _mm_storeu_pd(mm, m);
        smax = mm[0] > mm[1] ? mm[0] : mm[1];
#endif
        for (; t < nt; t++) {
            double s = px[t] * p0 + py[t] * p1 + pz[t] * p2c - half;
            dist[t] = s;
            const double hi = s + plen * (eb[t] + pterm);
            smax = hi > smax ? hi : smax;
        }
        if (!(smax > 0))
            return 0; /* every vertex is kept */
    }
    /* The side of each vertex: the filter, else the exact test. */
    double prow[VC_POWER_ROW];
    int prow_ready = 0;
    for (int t = 0; t < nt; t++) {
        const double b = plen * (c->eb[t] + pterm);
        int o;
        if (dist[t] > b)
            o = 1;
        else if (dist[t] < -b)
            o = 0;
        else {
            const int *tr = c->tri + 3 * t;
            const int64_t pl[3] = {c->plane_id[tr[0]], c->plane_id[tr[1]], c->plane_id[tr[2]]};
            double *cache = c->pc + VC_POWER_CACHE * t;
            if (cache[13] != 1) {
                const double *rows[3];
                for (int i = 0; i < 3; i++) {
                    double *row = c->prow + VC_POWER_ROW * tr[i];
                    if (!c->prow_ok[tr[i]]) {
                        vc_power_plane_prepare(c->ctx, c->seed, pl[i], row);
                        c->prow_ok[tr[i]] = 1;
                    }
                    rows[i] = row;
                }
                vc_power_vertex_prepare_rows(pl, rows, cache);
            }
            if (!prow_ready) {
                vc_power_plane_prepare(c->ctx, c->seed, plane_id, prow);
                prow_ready = 1;
            }
            const int r = vc_power_side_cached(c->ctx, c->seed, pl, plane_id, cache, prow);
            c->n_exact++;
            if (r == VC_PREDICATE_NOMEM)
                return VC_CELL_NOMEM;
            o = r < 0;
        }
        out[t] = (unsigned char)o;
        conflict[n_out] = t;
        n_out += o;
    }
    if (n_out == 0)
        return 0;
    if (n_out == nt)
        return -2;

    /* Boundary of the removed region: per plane, its outgoing boundary
     * edge, the removed triangle holding it and the kept one across it. */
    int *next = reserve(&c->b_next, np, sizeof(int));
    int *edge_tri = reserve(&c->b_edge_tri, np, sizeof(int));
    int *edge_out = reserve(&c->b_edge_out, np, sizeof(int));
    if (!next || !edge_tri || !edge_out)
        return VC_CELL_NOMEM;
    for (int i = 0; i < np; i++)
        next[i] = -1;
    int n_boundary = 0, first = -1, simple = 1;
    /* With the edge owners, the triangle across each edge of a removed
     * triangle is looked up: the edge is on the boundary when that one is
     * kept. Directed edges are unique (the triangles are a closed
     * triangulation of the sphere), so this finds what the search below
     * finds; an entry that does not hold the edge (which would mean they
     * are not) sends the cut to the search. */
    int use_owner = c->edge_owner_ok;
    if (use_owner) {
        const uint16_t *owner = c->edge_owner;
        for (int i = 0; i < n_out && use_owner; i++) {
            const int t = conflict[i];
            const int *tr = c->tri + 3 * t;
            for (int e = 0; e < 3; e++) {
                const int a = tr[e], b = tr[e == 2 ? 0 : e + 1];
                const int across = owner[b * VC_EDGE_OWNER_PLANES + a];
                if (across >= nt || !holds_edge(c->tri + 3 * across, b, a)) {
                    use_owner = 0;
                    break;
                }
                if (out[across])
                    continue; /* removed too: not on the boundary */
                if (next[a] != -1)
                    simple = 0; /* the region touches itself: not a disk */
                next[a] = b;
                edge_tri[a] = t;
                edge_out[a] = across;
                n_boundary++;
                if (first < 0)
                    first = a;
            }
        }
        if (!use_owner) {
            c->edge_owner_ok = 0;
            for (int i = 0; i < np; i++)
                next[i] = -1;
            n_boundary = 0;
            first = -1;
            simple = 1;
        }
    }
    /* Otherwise an edge of a removed triangle is on the boundary unless its
     * reverse belongs to a removed triangle too: marked in a plane-pair
     * matrix (cleared again below) or, for huge cells, searched. */
    unsigned char *mark = NULL;
    if (!use_owner && np <= 256) {
        if (c->b_edge_mark.cap < np * np) {
            free(c->b_edge_mark.data);
            c->b_edge_mark.cap = 256 * 256;
            c->b_edge_mark.data = calloc((size_t)c->b_edge_mark.cap, 1);
            if (!c->b_edge_mark.data) {
                c->b_edge_mark.cap = 0;
                return VC_CELL_NOMEM;
            }
        }
        mark = c->b_edge_mark.data;
        for (int i = 0; i < n_out; i++) {
            const int *tr = c->tri + 3 * conflict[i];
            mark[tr[0] * np + tr[1]] = 1;
            mark[tr[1] * np + tr[2]] = 1;
            mark[tr[2] * np + tr[0]] = 1;
        }
    }
    for (int i = 0; i < n_out && !use_owner; i++) {
        const int t = conflict[i];
        const int *tr = c->tri + 3 * t;
        for (int e = 0; e < 3; e++) {
            int a = tr[e], b = tr[e == 2 ? 0 : e + 1];
            if (mark ? mark[b * np + a] != 0 : has_edge(c->tri, conflict, n_out, b, a))
                continue;
            if (next[a] != -1)
                simple = 0; /* the region touches itself: not a disk */
            next[a] = b;
            edge_tri[a] = t;
            edge_out[a] = -1;
            n_boundary++;
            if (first < 0)
                first = a;
        }
    }
    if (mark) {
        for (int i = 0; i < n_out; i++) {
            const int *tr = c->tri + 3 * conflict[i];
            mark[tr[0] * np + tr[1]] = 0;
            mark[tr[1] * np + tr[2]] = 0;
            mark[tr[2] * np + tr[0]] = 0;
        }
    }
    if (!simple)
        return -1;
    int steps = 0, a = first;
    do {
        a = next[a];
        steps++;
    } while (a >= 0 && a != first && steps <= n_boundary);
    if (a != first || steps != n_boundary || n_boundary < 3)
        return -1;
    /* The kept triangle across each boundary edge a -> b holds b -> a
     * (already found with the edge owners). */
    int found = use_owner ? n_boundary : 0;
    for (int t = 0, ci = 0; t < nt && !use_owner; t++) {
        if (ci < n_out && conflict[ci] == t) {
            ci++;
            continue;
        }
        const int *tr = c->tri + 3 * t;
        for (int e = 0; e < 3; e++) {
            int u = tr[e], v = tr[e == 2 ? 0 : e + 1];
            if (next[v] == u && edge_out[v] < 0) {
                edge_out[v] = t;
                found++;
            }
        }
        if (found == n_boundary)
            break; /* directed edges are unique: nothing more to find */
    }
    if (found != n_boundary)
        return -1;

    /* The new plane, and one new vertex per boundary edge, in cycle order,
     * solved from its three planes (or, where that solve is too
     * ill-conditioned to bound, where the edge crosses the plane,
     * interpolated between its ends, within their distance of the exact
     * vertex). */
    const int P = np;
    c->plane = reserve(&c->b_plane, np + 1, PLANE_STRIDE * sizeof(double));
    c->plane_id = reserve(&c->b_plane_id, np + 1, sizeof(int64_t));
    c->prow = reserve(&c->b_prow, np + 1, VC_POWER_ROW * sizeof(double));
    c->prow_ok = reserve(&c->b_prow_ok, np + 1, 1);
    double *new_pt = reserve(&c->b_new_pt, n_boundary, 5 * sizeof(double)); /* x, ev, eb */
    int *new_tri = reserve(&c->b_new_tri, n_boundary, 3 * sizeof(int));
    if (!c->plane || !c->plane_id || !new_pt || !new_tri || !c->prow || !c->prow_ok)
        return VC_CELL_NOMEM;
    c->prow_ok[P] = (unsigned char)prow_ready;
    if (prow_ready)
        memcpy(c->prow + VC_POWER_ROW * P, prow, sizeof prow);
    double *q = c->plane + PLANE_STRIDE * P;
    q[0] = p[0];
    q[1] = p[1];
    q[2] = p[2];
    q[3] = half;
    q[4] = plen;
    c->plane_id[P] = plane_id;
    c->np = np + 1;

    a = first;
    for (int k = 0; k < n_boundary; k++) {
        const int b = next[a], tin = edge_out[a], tout = edge_tri[a];
        double *y = new_pt + 5 * k;
        double vy;
        double e = solve_vertex(c, a, b, P, y, &vy);
        if (!(isfinite(vy) && e <= 1e-6 * vy)) {
            /* ill-conditioned: the vertex in double-double, from the
             * exact seeds (the side test's prepared part: v = -W / C_3) */
            double pc[VC_POWER_CACHE];
            const int64_t pl[3] = {c->plane_id[a], c->plane_id[b], plane_id};
            vc_power_vertex_prepare(c->ctx, c->seed, pl, pc);
            const double C3 = pc[6] + pc[7], eC3 = 3.2e-30 * pc[11];
            double z[3], ez2 = 0, vz = 0;
            for (int j = 0; j < 3; j++) {
                z[j] = -(pc[2 * j] + pc[2 * j + 1]) / C3;
                vz += z[j] * z[j];
            }
            vz = sqrt(vz);
            for (int j = 0; j < 3; j++) {
                const double ej = (3.2e-30 * pc[8 + j] + fabs(z[j]) * eC3) / (fabs(C3) - eC3);
                ez2 += ej * ej;
            }
            double ez = fabs(C3) > eC3 ? sqrt(ez2) + 4 * U * vz : INFINITY;
            if (!(ez < e)) {
                /* last resort: where the edge crosses the plane, within
                 * its ends' distance of the exact vertex */
                const double s_in = dist[tin], s_out = dist[tout];
                double u = -s_in / (s_out - s_in);
                u = u > 0 ? (u < 1 ? u : 1) : 0;
                const double xi[3] = {c->px[tin], c->py[tin], c->pz[tin]};
                const double xo[3] = {c->px[tout], c->py[tout], c->pz[tout]};
                double d2 = 0;
                for (int j = 0; j < 3; j++) {
                    z[j] = xi[j] + u * (xo[j] - xi[j]);
                    d2 += (xo[j] - xi[j]) * (xo[j] - xi[j]);
                }
                ez = sqrt(d2) + c->ev[tin] + c->ev[tout];
            }
            if (ez < e || !(e == e)) {
                y[0] = z[0];
                y[1] = z[1];
                y[2] = z[2];
                e = ez;
            }
        }
        y[3] = e;
        y[4] = e + 8 * U * sqrt(norm2(y));
        new_tri[3 * k] = a;
        new_tri[3 * k + 1] = b;
        new_tri[3 * k + 2] = P;
        a = b;
    }

    /* The fan takes the removed triangles' slots, in the order they were
     * listed, and the end of the array: only what changes is written (the
     * removed region is a few triangles of the cell). When the fan is the
     * smaller, which needs a whole face to vanish, the holes it leaves are
     * closed by compacting the triangles after them. The edge owners of
     * the removed triangles are then stale (no triangle holds those
     * edges), and are kept while the plane indices fit. */
    const int new_nt = nt - n_out + n_boundary;
    c->tri = reserve(&c->b_tri, new_nt > nt ? new_nt : nt, 3 * sizeof(int));
    c->px = reserve(&c->b_px, new_nt > nt ? new_nt : nt, sizeof(double));
    c->py = reserve(&c->b_py, new_nt > nt ? new_nt : nt, sizeof(double));
    c->pz = reserve(&c->b_pz, new_nt > nt ? new_nt : nt, sizeof(double));
    c->r2 = reserve(&c->b_r2, new_nt > nt ? new_nt : nt, sizeof(double));
    c->ev = reserve(&c->b_ev, new_nt > nt ? new_nt : nt, sizeof(double));
    c->eb = reserve(&c->b_eb, new_nt > nt ? new_nt : nt, sizeof(double));
    c->pc = reserve(&c->b_pc, new_nt > nt ? new_nt : nt, VC_POWER_CACHE * sizeof(double));
    if (!c->tri || !c->px || !c->py || !c->pz || !c->r2 || !c->ev || !c->eb || !c->pc)
        return VC_CELL_NOMEM;
    const int keep_owner = c->edge_owner_ok && np + 1 <= VC_EDGE_OWNER_PLANES;
    c->edge_owner_ok = keep_owner;
    uint16_t *owner = c->edge_owner;
    for (int k = 0; k < n_boundary; k++) {
        const int t = k < n_out ? conflict[k] : nt + (k - n_out);
        memcpy(c->tri + 3 * t, new_tri + 3 * k, 3 * sizeof(int));
        if (keep_owner)
            set_edge_owner(owner, new_tri + 3 * k, t);
        c->px[t] = new_pt[5 * k];
        c->py[t] = new_pt[5 * k + 1];
        c->pz[t] = new_pt[5 * k + 2];
        c->r2[t] = norm2(new_pt + 5 * k);
        c->ev[t] = new_pt[5 * k + 3];
        c->eb[t] = new_pt[5 * k + 4];
        c->pc[VC_POWER_CACHE * t + 13] = 0;
    }
    if (n_boundary < n_out) {
        /* The fan is in slots before the first hole left (the removed
         * triangles are listed in increasing order). Every triangle after
         * that hole is copied to w (w <= t), and w only moves past the kept
         * ones. A hole's edge owners are not written: the fan holds its
         * boundary edges now. */
        int w = conflict[n_boundary];
        for (int t = w + 1; t < nt; t++) {
            const int kept = !out[t];
            memcpy(c->tri + 3 * w, c->tri + 3 * t, 3 * sizeof(int));
            if (keep_owner && kept)
                set_edge_owner(owner, c->tri + 3 * w, w);
            c->px[w] = c->px[t];
            c->py[w] = c->py[t];
            c->pz[w] = c->pz[t];
            c->r2[w] = c->r2[t];
            c->ev[w] = c->ev[t];
            c->eb[w] = c->eb[t];
            if (c->pc[VC_POWER_CACHE * t + 13] == 1)
                memcpy(c->pc + VC_POWER_CACHE * w, c->pc + VC_POWER_CACHE * t,
                       VC_POWER_CACHE * sizeof(double));
            else
                c->pc[VC_POWER_CACHE * w + 13] = 0;
            w += kept;
        }
    }
    c->nt = new_nt;
    update_rmax2(c);
    return 1;
}

int vc_convex_cell_faces(vc_convex_cell *c)
{
    const int np = c->np, nt = c->nt;
    /* Per plane, its entries: for triangle t = (a, b, c) rotated to start
     * at the plane a, the step b -> c around face a. */
    int *count = reserve(&c->b_count, np + 1, sizeof(int));
    int *entry = reserve(&c->b_entry, 3 * 3 * nt, sizeof(int)); /* (from, to, t) */
    int *fill = reserve(&c->b_next, np, sizeof(int));
    if (!count || !entry || !fill)
        return VC_CELL_NOMEM;
    memset(count, 0, (size_t)(np + 1) * sizeof(int));
    for (int i = 0; i < 3 * nt; i++)
        count[c->tri[i] + 1]++;
    for (int i = 0; i < np; i++)
        count[i + 1] += count[i];
    memcpy(fill, count, (size_t)np * sizeof(int));
    for (int t = 0; t < nt; t++) {
        const int *tr = c->tri + 3 * t;
        for (int e = 0; e < 3; e++) {
            int k = fill[tr[e]]++;
            entry[3 * k] = tr[e == 2 ? 0 : e + 1];
            entry[3 * k + 1] = tr[e == 0 ? 2 : e - 1];
            entry[3 * k + 2] = t;
        }
    }
    int nf = 0;
    for (int i = 0; i < np; i++)
        nf += count[i + 1] > count[i];
    c->face_plane = reserve(&c->b_face_plane, nf, sizeof(int64_t));
    c->face_plane_index = reserve(&c->b_face_plane_index, nf, sizeof(int));
    c->face_start = reserve(&c->b_face_start, nf + 1, sizeof(int));
    c->fv = reserve(&c->b_fv, 3 * nt, sizeof(int));
    if (!c->face_plane || !c->face_plane_index || !c->face_start || !c->fv)
        return VC_CELL_NOMEM;
    int f = 0, n = 0;
    for (int i = 0; i < np; i++) {
        const int s0 = count[i], s1 = count[i + 1], len = s1 - s0;
        if (len == 0)
            continue;
        c->face_plane[f] = c->plane_id[i];
        c->face_plane_index[f] = i;
        c->face_start[f] = n;
        /* Chain the steps: from entry k, the next holds from == k's to
         * (the first such entry: at[] is filled backwards). */
        int *at = fill; /* per plane, reused: only entries in [s0, s1) count */
        for (int m = s1 - 1; m >= s0; m--)
            at[entry[3 * m]] = m;
        int k = s0;
        for (int j = 0; j < len; j++) {
            c->fv[n++] = entry[3 * k + 2];
            const int to = entry[3 * k + 1];
            const int nk = at[to];
            if (nk < s0 || nk >= s1 || entry[3 * nk] != to)
                return -1;
            k = nk;
        }
        if (k != s0)
            return -1;
        f++;
    }
    c->face_start[f] = n;
    c->nf = f;
    c->nfv = n;
    c->nv = nt;
    return 0;
}
