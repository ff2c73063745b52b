/* Plane-by-plane cutting of a convex polyhedron (see convex_cell.h).
 *
 * A cut classifies every vertex as inside, on or outside the plane with a
 * tolerance, rewrites every face as the part of its cycle that is not
 * outside (adding the points where edges cross the plane, each computed
 * once per edge so the two faces of an edge share it), and closes the hole
 * with a new face chained from the on-plane edges of the surviving faces,
 * each taken reversed. */
#include "convex_cell.h"

#include <stdlib.h>
#include <string.h>

enum { SIDE_IN = -1, SIDE_ON = 0, SIDE_OUT = 1 };

/* Makes room for need elements of elem bytes; returns the data pointer. */
static void *reserve(vc_cell_buf *b, int need, size_t elem)
{
    if (need > b->cap) {
        int n = b->cap ? b->cap : 32;
        while (n < need)
            n *= 2;
        void *q = realloc(b->data, (size_t)n * elem);
        if (!q)
            abort(); /* out of memory inside one cell: nothing sane to do */
        b->data = q;
        b->cap = n;
    }
    return b->data;
}

void vc_convex_cell_init(vc_convex_cell *c) { memset(c, 0, sizeof *c); }

void vc_convex_cell_free(vc_convex_cell *c)
{
    vc_cell_buf *bufs[] = {&c->b_v, &c->b_face_plane, &c->b_face_start, &c->b_fv,
                           &c->b_dist, &c->b_side, &c->b_remap, &c->b_on,
                           &c->b_cap_next, &c->b_new_v, &c->b_new_face_plane,
                           &c->b_new_face_start, &c->b_new_fv, &c->b_cut};
    for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++)
        free(bufs[i]->data);
    memset(c, 0, sizeof *c);
}

void vc_convex_cell_reset_box(vc_convex_cell *c, const double lo[3],
                              const double hi[3], const int64_t wall_id[6])
{
    /* Vertex k has x = hi if bit 0, y = hi if bit 1, z = hi if bit 2;
     * cycles are counter-clockwise seen from outside. */
    static const int box_faces[6][4] = {
        {0, 4, 6, 2}, /* xmin */
        {1, 3, 7, 5}, /* xmax */
        {0, 1, 5, 4}, /* ymin */
        {2, 6, 7, 3}, /* ymax */
        {0, 2, 3, 1}, /* zmin */
        {4, 5, 7, 6}, /* zmax */
    };
    c->v = reserve(&c->b_v, 8, 3 * sizeof(double));
    c->face_plane = reserve(&c->b_face_plane, 6, sizeof(int64_t));
    c->face_start = reserve(&c->b_face_start, 7, sizeof(int));
    c->fv = reserve(&c->b_fv, 24, sizeof(int));
    c->nv = 8;
    for (int k = 0; k < 8; k++) {
        c->v[3 * k + 0] = (k & 1) ? hi[0] : lo[0];
        c->v[3 * k + 1] = (k & 2) ? hi[1] : lo[1];
        c->v[3 * k + 2] = (k & 4) ? hi[2] : lo[2];
    }
    c->nf = 6;
    c->nfv = 24;
    for (int f = 0; f < 6; f++) {
        c->face_plane[f] = wall_id[f];
        c->face_start[f] = 4 * f;
        for (int i = 0; i < 4; i++)
            c->fv[4 * f + i] = box_faces[f][i];
    }
    c->face_start[6] = 24;
}

double vc_convex_cell_max_radius2(const vc_convex_cell *c)
{
    double r2 = 0;
    for (int i = 0; i < c->nv; i++) {
        const double *x = c->v + 3 * i;
        double d = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        if (d > r2)
            r2 = d;
    }
    return r2;
}

/* Per-cut state. */
typedef struct cut_state {
    double *new_v;
    int n_new_v;
    int *cut; /* triples (lo, hi, index) of the edges crossed so far */
    int n_cut;
} cut_state;

/* Index of the crossing point on edge (a, b), created on first request. */
static int crossing(vc_convex_cell *c, cut_state *st, const double *dist, int a, int b)
{
    int lo = a < b ? a : b, hi = a < b ? b : a;
    for (int k = 0; k < st->n_cut; k++)
        if (st->cut[3 * k] == lo && st->cut[3 * k + 1] == hi)
            return st->cut[3 * k + 2];
    st->cut = reserve(&c->b_cut, 3 * (st->n_cut + 1), sizeof(int));
    st->new_v = reserve(&c->b_new_v, st->n_new_v + 1, 3 * sizeof(double));
    int idx = st->n_new_v++;
    /* Interpolate from the inside vertex: the point does not depend on
     * which of the edge's two faces asked first. */
    int in = dist[a] < 0 ? a : b, out = in == a ? b : a;
    double t = dist[in] / (dist[in] - dist[out]);
    const double *xi = c->v + 3 * in, *xo = c->v + 3 * out;
    double *y = st->new_v + 3 * idx;
    for (int d = 0; d < 3; d++)
        y[d] = xi[d] + t * (xo[d] - xi[d]);
    st->cut[3 * st->n_cut] = lo;
    st->cut[3 * st->n_cut + 1] = hi;
    st->cut[3 * st->n_cut + 2] = idx;
    st->n_cut++;
    return idx;
}

int vc_convex_cell_cut(vc_convex_cell *c, const double p[3], int64_t plane_id,
                       double tol)
{
    const double p2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const double half = 0.5 * p2;
    const double thr = tol * p2; /* (tol |p|) in distance, times |p| */
    const int nv = c->nv;

    double *dist = reserve(&c->b_dist, nv, sizeof(double));
    signed char *side = reserve(&c->b_side, nv, 1);
    int n_out = 0, n_in = 0;
    for (int i = 0; i < nv; i++) {
        const double *x = c->v + 3 * i;
        double s = x[0] * p[0] + x[1] * p[1] + x[2] * p[2] - half;
        dist[i] = s;
        if (s > thr) {
            side[i] = SIDE_OUT;
            n_out++;
        } else if (s < -thr) {
            side[i] = SIDE_IN;
            n_in++;
        } else {
            side[i] = SIDE_ON;
        }
    }
    if (n_out == 0)
        return 0;
    if (n_in == 0)
        return -2;

    /* Surviving vertices keep their order; crossing points follow them. */
    int *remap = reserve(&c->b_remap, nv, sizeof(int));
    cut_state st = {reserve(&c->b_new_v, nv + 8, 3 * sizeof(double)), 0, c->b_cut.data, 0};
    for (int i = 0; i < nv; i++) {
        if (side[i] != SIDE_OUT) {
            memcpy(st.new_v + 3 * st.n_new_v, c->v + 3 * i, 3 * sizeof(double));
            remap[i] = st.n_new_v++;
        } else {
            remap[i] = -1;
        }
    }
    const int n_kept = st.n_new_v;

    const int nf = c->nf;
    int *new_face_start = reserve(&c->b_new_face_start, nf + 2, sizeof(int));
    int64_t *new_face_plane = reserve(&c->b_new_face_plane, nf + 1, sizeof(int64_t));
    int *new_fv = reserve(&c->b_new_fv, c->nfv + 2 * nf + 8, sizeof(int));
    int n_new_f = 0, n_new_fv = 0;

    for (int f = 0; f < nf; f++) {
        const int s0 = c->face_start[f], len = c->face_start[f + 1] - s0;
        const int *cyc = c->fv + s0;
        const int start = n_new_fv;
        new_fv = reserve(&c->b_new_fv, n_new_fv + 2 * len + 2, sizeof(int));
        for (int k = 0; k < len; k++) {
            int a = cyc[k], b = cyc[k + 1 < len ? k + 1 : 0];
            int sa = side[a], sb = side[b];
            if (sa != SIDE_OUT)
                new_fv[n_new_fv++] = remap[a];
            if ((sa == SIDE_IN && sb == SIDE_OUT) || (sa == SIDE_OUT && sb == SIDE_IN))
                new_fv[n_new_fv++] = crossing(c, &st, dist, a, b);
        }
        if (n_new_fv - start < 3) {
            n_new_fv = start; /* cut away, or down to a segment */
            continue;
        }
        new_face_plane[n_new_f] = c->face_plane[f];
        new_face_start[n_new_f] = start;
        n_new_f++;
    }
    new_face_start[n_new_f] = n_new_fv;

    /* on[i]: new vertex i lies on the plane (kept on-vertex or crossing). */
    char *on = reserve(&c->b_on, st.n_new_v, 1);
    for (int i = 0; i < nv; i++)
        if (remap[i] >= 0)
            on[remap[i]] = side[i] == SIDE_ON;
    for (int i = n_kept; i < st.n_new_v; i++)
        on[i] = 1;

    /* Each on-plane edge of a surviving face borders the cap; the cap uses
     * it reversed. A face lying in the plane is replaced by the cap. */
    int *cap_next = reserve(&c->b_cap_next, st.n_new_v, sizeof(int));
    for (int i = 0; i < st.n_new_v; i++)
        cap_next[i] = -1;
    int cap_start = -1, n_cap_edges = 0, kept_f = 0, kept_fv = 0;
    for (int f = 0; f < n_new_f; f++) {
        int s0 = new_face_start[f], len = new_face_start[f + 1] - s0, n_on = 0;
        for (int k = 0; k < len; k++)
            n_on += on[new_fv[s0 + k]];
        if (n_on == len)
            continue;
        if (n_on >= 2) {
            for (int k = 0; k < len; k++) {
                int a = new_fv[s0 + k], b = new_fv[s0 + (k + 1 < len ? k + 1 : 0)];
                if (on[a] && on[b]) {
                    if (cap_next[b] != -1)
                        return -1;
                    cap_next[b] = a;
                    cap_start = b;
                    n_cap_edges++;
                }
            }
        }
        /* Compact in place (kept_fv <= s0 always). */
        memmove(new_fv + kept_fv, new_fv + s0, (size_t)len * sizeof(int));
        new_face_plane[kept_f] = new_face_plane[f];
        new_face_start[kept_f] = kept_fv;
        kept_f++;
        kept_fv += len;
    }
    n_new_f = kept_f;
    n_new_fv = kept_fv;

    if (n_cap_edges >= 3) {
        new_fv = reserve(&c->b_new_fv, n_new_fv + n_cap_edges, sizeof(int));
        int cap_face_start = n_new_fv, x = cap_start, cap_len = 0;
        do {
            new_fv[n_new_fv++] = x;
            cap_len++;
            x = cap_next[x];
        } while (x >= 0 && x != cap_start && cap_len <= n_cap_edges);
        if (x != cap_start || cap_len != n_cap_edges)
            return -1;
        new_face_start = reserve(&c->b_new_face_start, n_new_f + 2, sizeof(int));
        new_face_plane = reserve(&c->b_new_face_plane, n_new_f + 1, sizeof(int64_t));
        new_face_plane[n_new_f] = plane_id;
        new_face_start[n_new_f] = cap_face_start;
        n_new_f++;
    }
    new_face_start[n_new_f] = n_new_fv;

    /* The new polyhedron becomes current: swap buffers. */
    vc_cell_buf t;
    t = c->b_v, c->b_v = c->b_new_v, c->b_new_v = t;
    t = c->b_face_plane, c->b_face_plane = c->b_new_face_plane, c->b_new_face_plane = t;
    t = c->b_face_start, c->b_face_start = c->b_new_face_start, c->b_new_face_start = t;
    t = c->b_fv, c->b_fv = c->b_new_fv, c->b_new_fv = t;
    c->v = c->b_v.data;
    c->face_plane = c->b_face_plane.data;
    c->face_start = c->b_face_start.data;
    c->fv = c->b_fv.data;
    c->nv = st.n_new_v;
    c->nf = n_new_f;
    c->nfv = n_new_fv;
    return 1;
}
