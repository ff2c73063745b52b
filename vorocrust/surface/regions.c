/* The regions of a closed surface's arrangement (see
 * include/vorocrust/regions.h). */
#include "surface/solid_angle.h"
#include "vorocrust/regions.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/bucket_sort.h"
#include "util/small_sort.h"
#include "util/union_find.h"

#define PI 3.14159265358979323846

typedef struct edge_rec {
    int64_t lo, hi, tri;
} edge_rec;

/* (lo, hi, tri) and (v, tri): distinct records, the same order for any sort */
#define EDGE_REC_LESS(x, y)                                                                      \
    ((x)->lo < (y)->lo ||                                                                        \
     ((x)->lo == (y)->lo && ((x)->hi < (y)->hi || ((x)->hi == (y)->hi && (x)->tri < (y)->tri))))
VC_SMALL_SORT(sort_edge_recs, edge_rec, EDGE_REC_LESS)
#define EDGE_REC_KEY(x) ((x)->lo)
VC_BUCKET_SORT(bucket_sort_edge_recs, edge_rec, EDGE_REC_KEY, EDGE_REC_LESS, sort_edge_recs)

typedef struct tri_key {
    int64_t v[3]; /* sorted */
    int64_t tri;
} tri_key;

static int tri_key_less(const tri_key *x, const tri_key *y)
{
    for (int k = 0; k < 3; k++)
        if (x->v[k] != y->v[k])
            return x->v[k] < y->v[k];
    return x->tri < y->tri;
}
VC_SMALL_SORT(sort_tri_keys, tri_key, tri_key_less)
#define TRI_KEY_FIRST(x) ((x)->v[0])
VC_BUCKET_SORT(bucket_sort_tri_keys, tri_key, TRI_KEY_FIRST, tri_key_less, sort_tri_keys)

static void sub3(const double *a, const double *b, double *o)
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* min and max inline (libm's fmin and fmax are calls) */
static inline double min2(double a, double b) { return b < a ? b : a; }
static inline double max2(double a, double b) { return b > a ? b : a; }

/* Does triangle t walk its edge from a to b (rather than from b to a)? */
static int walks(const vc_surface *s, int64_t t, int64_t a, int64_t b)
{
    const int64_t *v = s->tri + 3 * t;
    for (int k = 0; k < 3; k++)
        if (v[k] == a && v[(k + 1) % 3] == b)
            return 1;
    return 0;
}

static int64_t third_vertex(const vc_surface *s, int64_t t, int64_t a, int64_t b)
{
    const int64_t *v = s->tri + 3 * t;
    for (int k = 0; k < 3; k++)
        if (v[k] != a && v[k] != b)
            return v[k];
    return v[0];
}

typedef struct around {
    double angle;
    int64_t tri;
    int front_faces_up; /* the triangle's front side faces increasing angle */
} around;

static int cmp_around(const void *a, const void *b)
{
    const around *x = a, *y = b;
    if (x->angle != y->angle)
        return x->angle < y->angle ? -1 : 1;
    return (x->tri > y->tri) - (x->tri < y->tri);
}

int vc_surface_regions(const vc_surface *s, vc_regions *out, vc_error *err)
{
    memset(out, 0, sizeof *out);
    const int64_t nt = s->n_triangles;
    out->n_triangles = nt;
    int rc = 0;
    /* alias[t]: the triangle t repeats (reversed: alias_flip), or t */
    int64_t *alias = malloc(sizeof(int64_t) * (size_t)(nt + 1));
    unsigned char *alias_flip = calloc((size_t)nt + 1, 1);
    tri_key *keys = malloc(sizeof(tri_key) * (size_t)(nt + 1));
    edge_rec *er = malloc(sizeof(edge_rec) * (size_t)(3 * nt + 1));
    int64_t *side = malloc(sizeof(int64_t) * (size_t)(2 * nt + 1)); /* union-find over sides */
    int64_t *comp = malloc(sizeof(int64_t) * (size_t)(nt + 1));      /* over triangles */
    around *ring = NULL;
    int64_t ring_cap = 0;
    int64_t *shell_of = NULL, *shell_first = NULL, *shell_comp = NULL, *shell_region = NULL;
    double *shell_vol = NULL, *shell_box = NULL;
    int64_t *comp_outer = NULL, *shell_parent = NULL;
    if (!alias || !alias_flip || !keys || !er || !side || !comp) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
        goto done;
    }

    /* triangles given twice count once */
    int any_alias = 0;
    for (int64_t t = 0; t < nt; t++) {
        int64_t *v = keys[t].v;
        for (int k = 0; k < 3; k++)
            v[k] = s->tri[3 * t + k];
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2 - i; j++)
                if (v[j] > v[j + 1]) {
                    int64_t x = v[j];
                    v[j] = v[j + 1];
                    v[j + 1] = x;
                }
        keys[t].tri = t;
        alias[t] = t;
    }
    if (bucket_sort_tri_keys(keys, nt, s->n_vertices))
        sort_tri_keys(keys, nt); /* no room for the copy: in place */
    for (int64_t i = 1; i < nt; i++) {
        const tri_key *a = &keys[i - 1], *b = &keys[i];
        if (a->v[0] == b->v[0] && a->v[1] == b->v[1] && a->v[2] == b->v[2]) {
            const int64_t first = alias[a->tri];
            alias[b->tri] = first;
            const int64_t *f = s->tri + 3 * first;
            alias_flip[b->tri] = !walks(s, b->tri, f[0], f[1]);
            out->n_twice += alias_flip[b->tri];
            any_alias = 1;
        }
    }

    /* the edges of the distinct triangles, grouped */
    int64_t ne = 0;
    for (int64_t t = 0; t < nt; t++) {
        if (alias[t] != t)
            continue;
        for (int k = 0; k < 3; k++) {
            int64_t a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
            er[ne].lo = a < b ? a : b;
            er[ne].hi = a < b ? b : a;
            er[ne].tri = t;
            ne++;
        }
    }
    if (bucket_sort_edge_recs(er, ne, s->n_vertices))
        sort_edge_recs(er, ne); /* no room for the copy: in place */
    vc_uf_init(side, 2 * nt);
    vc_uf_init(comp, nt);
    out->closed_shells = !any_alias;
    for (int64_t i = 0; i < ne;) {
        int64_t j = i;
        while (j < ne && er[j].lo == er[i].lo && er[j].hi == er[i].hi)
            j++;
        const int64_t k = j - i;
        if (k != 2)
            out->closed_shells = 0;
        if (k < 2) {
            /* one distinct triangle (an open edge, or the edge of a wall
             * given twice): around the edge, one side leads to the other */
            vc_uf_unite(side, 2 * er[i].tri, 2 * er[i].tri + 1);
            i = j;
            continue;
        }
        if (k == 2) {
            /* Two triangles: the two wedges between them join the up side
             * of each to the down side of the other, in either order
             * around the edge, so no angles are needed (the roots of the
             * unions do not depend on their order either). */
            const int64_t t0 = er[i].tri, t1 = er[i + 1].tri;
            const int up0 = walks(s, t0, er[i].lo, er[i].hi), up1 = walks(s, t1, er[i].lo, er[i].hi);
            vc_uf_unite(comp, t1, t0);
            vc_uf_unite(side, 2 * t0 + (up0 ? 0 : 1), 2 * t1 + (up1 ? 1 : 0));
            vc_uf_unite(side, 2 * t1 + (up1 ? 0 : 1), 2 * t0 + (up0 ? 1 : 0));
            i = j;
            continue;
        }
        if (k > ring_cap) {
            around *q = realloc(ring, sizeof(around) * (size_t)k);
            if (!q) {
                rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
                goto done;
            }
            ring = q;
            ring_cap = k;
        }
        /* a frame about the edge: d along it, b1 and b2 across */
        const double *xa = s->xyz + 3 * er[i].lo, *xb = s->xyz + 3 * er[i].hi;
        double d[3], b1[3] = {0, 0, 0}, b2[3];
        sub3(xb, xa, d);
        const double ld = sqrt(dot3(d, d));
        for (int c = 0; c < 3; c++)
            d[c] /= ld;
        {
            double u[3];
            sub3(s->xyz + 3 * third_vertex(s, er[i].tri, er[i].lo, er[i].hi), xa, u);
            const double ud = dot3(u, d);
            for (int c = 0; c < 3; c++)
                b1[c] = u[c] - ud * d[c];
            const double l1 = sqrt(dot3(b1, b1));
            for (int c = 0; c < 3; c++)
                b1[c] /= l1;
            cross3(d, b1, b2);
        }
        for (int64_t m = 0; m < k; m++) {
            const int64_t t = er[i + m].tri;
            double u[3];
            sub3(s->xyz + 3 * third_vertex(s, t, er[i].lo, er[i].hi), xa, u);
            ring[m].angle = atan2(dot3(u, b2), dot3(u, b1));
            ring[m].tri = t;
            /* the direction of increasing angle at the triangle is d x u;
             * the normal (hi - lo) x (w - lo) of a triangle walking lo -> hi
             * is |hi - lo| (d x u) */
            ring[m].front_faces_up = walks(s, t, er[i].lo, er[i].hi);
            if (m > 0)
                vc_uf_unite(comp, t, ring[0].tri);
        }
        qsort(ring, (size_t)k, sizeof *ring, cmp_around);
        /* the wedge from ring[m] to ring[m + 1]: the side of ring[m] facing
         * up and the side of ring[m + 1] facing down bound it */
        for (int64_t m = 0; m < k; m++) {
            const around *p = &ring[m], *q = &ring[(m + 1) % k];
            const int64_t sp = 2 * p->tri + (p->front_faces_up ? 0 : 1);
            const int64_t sq = 2 * q->tri + (q->front_faces_up ? 1 : 0);
            vc_uf_unite(side, sp, sq);
        }
        i = j;
    }

    /* shells: the classes of sides, numbered by their smallest side */
    shell_of = malloc(sizeof(int64_t) * (size_t)(2 * nt + 1));
    int64_t n_shells = 0;
    if (!shell_of) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
        goto done;
    }
    for (int64_t x = 0; x < 2 * nt; x++) {
        shell_of[x] = -1;
        if (alias[x / 2] != x / 2)
            continue;
        const int64_t r = vc_uf_find(side, x);
        shell_of[x] = r == x ? n_shells++ : shell_of[r];
    }
    shell_first = malloc(sizeof(int64_t) * (size_t)(n_shells + 1));
    shell_comp = malloc(sizeof(int64_t) * (size_t)(n_shells + 1));
    shell_region = malloc(sizeof(int64_t) * (size_t)(n_shells + 1));
    shell_parent = malloc(sizeof(int64_t) * (size_t)(n_shells + 1));
    shell_vol = calloc((size_t)n_shells + 1, sizeof(double));
    shell_box = malloc(sizeof(double) * 6 * (size_t)(n_shells + 1));
    comp_outer = malloc(sizeof(int64_t) * (size_t)(nt + 1));
    if (!shell_first || !shell_comp || !shell_region || !shell_parent || !shell_vol || !shell_box || !comp_outer) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
        goto done;
    }
    for (int64_t h = 0; h < n_shells; h++) {
        shell_first[h] = -1;
        for (int c = 0; c < 3; c++) {
            shell_box[6 * h + c] = INFINITY;
            shell_box[6 * h + 3 + c] = -INFINITY;
        }
    }
    /* signed volumes about the centre of the bounding box (fewer
     * cancellations than about the origin); a shell bounds the space its
     * sides face, so a front side counts its triangle reversed */
    double centre[3] = {0, 0, 0};
    {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int64_t v = 0; v < s->n_vertices; v++)
            for (int c = 0; c < 3; c++) {
                lo[c] = min2(lo[c], s->xyz[3 * v + c]);
                hi[c] = max2(hi[c], s->xyz[3 * v + c]);
            }
        for (int c = 0; c < 3; c++)
            centre[c] = 0.5 * (lo[c] + hi[c]);
    }
    for (int64_t t = 0; t < nt; t++) {
        if (alias[t] != t)
            continue;
        double a[3], b[3], c[3], bc[3];
        sub3(s->xyz + 3 * s->tri[3 * t], centre, a);
        sub3(s->xyz + 3 * s->tri[3 * t + 1], centre, b);
        sub3(s->xyz + 3 * s->tri[3 * t + 2], centre, c);
        cross3(b, c, bc);
        const double v = dot3(a, bc) / 6;
        for (int f = 0; f < 2; f++) {
            const int64_t h = shell_of[2 * t + f];
            shell_vol[h] += f == 0 ? -v : v;
            if (shell_first[h] < 0)
                shell_first[h] = t;
            for (int k = 0; k < 3; k++)
                for (int q = 0; q < 3; q++) {
                    const double x = s->xyz[3 * s->tri[3 * t + k] + q];
                    shell_box[6 * h + q] = min2(shell_box[6 * h + q], x);
                    shell_box[6 * h + 3 + q] = max2(shell_box[6 * h + 3 + q], x);
                }
        }
    }
    /* components and their one outer (negative) shell */
    out->n_components = 0;
    for (int64_t t = 0; t < nt; t++)
        comp_outer[t] = -1;
    for (int64_t h = 0; h < n_shells; h++) {
        const int64_t cr = vc_uf_find(comp, shell_first[h]);
        shell_comp[h] = cr;
        shell_parent[h] = -1;
        shell_region[h] = -1;
        if (shell_vol[h] < 0 && (comp_outer[cr] < 0 || shell_vol[h] < shell_vol[comp_outer[cr]]))
            comp_outer[cr] = h;
    }
    for (int64_t t = 0; t < nt; t++)
        if (alias[t] == t && vc_uf_find(comp, t) == t)
            out->n_components++;

    /* regions: the shells that are not the outer shell of their component,
     * numbered by their first triangle (shells are numbered by their
     * smallest side, so first triangles increase with the shell number
     * only roughly: sort) */
    int64_t n_regions = 0;
    for (int64_t h = 0; h < n_shells; h++)
        if (comp_outer[shell_comp[h]] != h)
            n_regions++;
    out->region = calloc((size_t)n_regions + 1, sizeof(vc_region));
    out->side_region = malloc(sizeof(int64_t) * (size_t)(2 * nt + 1));
    if (!out->region || !out->side_region) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
        goto done;
    }
    {
        int64_t *order = malloc(sizeof(int64_t) * (size_t)(n_regions + 1));
        if (!order) {
            rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
            goto done;
        }
        int64_t m = 0;
        for (int64_t h = 0; h < n_shells; h++)
            if (comp_outer[shell_comp[h]] != h)
                order[m++] = h;
        /* insertion by first triangle: shells are few next to triangles */
        for (int64_t a = 1; a < m; a++) {
            const int64_t x = order[a];
            int64_t b = a - 1;
            while (b >= 0 && shell_first[order[b]] > shell_first[x]) {
                order[b + 1] = order[b];
                b--;
            }
            order[b + 1] = x;
        }
        for (int64_t r = 0; r < m; r++) {
            shell_region[order[r]] = r;
            out->region[r].volume = shell_vol[order[r]];
            out->region[r].first_triangle = shell_first[order[r]];
            out->region[r].parent = -1;
        }
        free(order);
    }
    out->n_regions = n_regions;

    /* nesting: the outer shell of each component lies in the smallest
     * region of another component whose shell winds around one of its
     * triangles' centroids (components do not cross: the input has no
     * self-intersection) */
    for (int64_t h = 0; h < n_shells; h++) {
        if (comp_outer[shell_comp[h]] != h)
            continue;
        const int64_t t0 = shell_first[h];
        double p[3];
        for (int c = 0; c < 3; c++)
            p[c] = (s->xyz[3 * s->tri[3 * t0] + c] + s->xyz[3 * s->tri[3 * t0 + 1] + c] +
                    s->xyz[3 * s->tri[3 * t0 + 2] + c]) / 3;
        int64_t best = -1;
        for (int64_t g = 0; g < n_shells; g++) {
            if (comp_outer[shell_comp[g]] == g || shell_comp[g] == shell_comp[h])
                continue;
            if (best >= 0 && shell_vol[g] >= shell_vol[best])
                continue;
            const double *blo = shell_box + 6 * g, *bhi = blo + 3;
            if (p[0] < blo[0] || p[1] < blo[1] || p[2] < blo[2] || p[0] > bhi[0] || p[1] > bhi[1] ||
                p[2] > bhi[2])
                continue;
            /* the winding number of shell g about p, its sides taken
             * facing away from the space they bound */
            double w = 0;
            for (int64_t t = 0; t < nt; t++) {
                if (alias[t] != t)
                    continue;
                for (int f = 0; f < 2; f++) {
                    if (shell_of[2 * t + f] != g)
                        continue;
                    const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                                 *c = s->xyz + 3 * s->tri[3 * t + 2];
                    const double om = vc_solid_angle(p, a, b, c);
                    w += f == 0 ? -om : om;
                }
            }
            if (w / (4 * PI) > 0.5)
                best = g;
        }
        shell_parent[h] = best;
        if (best >= 0)
            shell_region[h] = shell_region[best];
    }
    /* parents of regions: where their component's outer shell lies */
    for (int64_t h = 0; h < n_shells; h++) {
        const int64_t r = shell_region[h];
        const int64_t outer = comp_outer[shell_comp[h]];
        if (r < 0 || outer == h)
            continue;
        out->region[r].parent = outer >= 0 && shell_parent[outer] >= 0 ? shell_region[shell_parent[outer]] : -1;
    }
    for (int64_t h = 0; h < n_shells; h++) {
        const int64_t r = shell_region[h];
        if (r >= 0 && comp_outer[shell_comp[h]] == h) {
            out->region[r].volume += shell_vol[h];
            out->region[r].n_holes++;
        }
    }

    /* components, numbered by first triangle; their nesting depth and
     * orientation */
    out->component_of = malloc(sizeof(int64_t) * (size_t)(nt + 1));
    out->component_depth = calloc((size_t)out->n_components + 1, sizeof(int64_t));
    out->component_outward = calloc((size_t)out->n_components + 1, 1);
    if (!out->component_of || !out->component_depth || !out->component_outward) {
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
        goto done;
    }
    {
        int64_t *number = malloc(sizeof(int64_t) * (size_t)(nt + 1)); /* by root triangle */
        if (!number) {
            rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
            goto done;
        }
        int64_t nc = 0;
        for (int64_t t = 0; t < nt; t++)
            number[t] = -1;
        for (int64_t t = 0; t < nt; t++) {
            const int64_t root = vc_uf_find(comp, alias[t]);
            if (number[root] < 0)
                number[root] = nc++;
            out->component_of[t] = number[root];
        }
        /* depth: the components whose regions enclose its outer shell,
         * following the regions' parents */
        for (int64_t h = 0; h < n_shells; h++) {
            const int64_t c = number[shell_comp[h]];
            if (comp_outer[shell_comp[h]] == h) {
                int64_t depth = 0;
                for (int64_t g = shell_parent[h]; g >= 0;) {
                    depth++;
                    const int64_t outer = comp_outer[shell_comp[g]];
                    g = outer >= 0 ? shell_parent[outer] : -1;
                }
                out->component_depth[c] = depth;
            }
        }
        /* outward: the back side of its first triangle faces a space it
         * encloses (a positive shell) */
        for (int64_t t = nt - 1; t >= 0; t--)
            if (alias[t] == t)
                out->component_outward[number[vc_uf_find(comp, t)]] = shell_vol[shell_of[2 * t + 1]] > 0;
        free(number);
    }

    /* sides, kinds */
    unsigned char *seen_front = calloc((size_t)n_regions + 2, 1), *seen_back = calloc((size_t)n_regions + 2, 1);
    if (!seen_front || !seen_back) {
        free(seen_front);
        free(seen_back);
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
        goto done;
    }
    /* a triangle given twice, reversed, is a shared interface: each copy
     * belongs to the surface of the region behind it, so only back sides
     * say what a region is there */
    unsigned char *twin = calloc((size_t)nt + 1, 1);
    if (!twin) {
        free(seen_front);
        free(seen_back);
        rc = vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
        goto done;
    }
    for (int64_t t = 0; t < nt; t++)
        if (alias_flip[t])
            twin[t] = twin[alias[t]] = 1;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t a = alias[t];
        for (int f = 0; f < 2; f++) {
            const int fa = alias_flip[t] ? 1 - f : f; /* the same side of the first copy */
            const int64_t r = shell_region[shell_of[2 * a + fa]];
            out->side_region[2 * t + f] = r;
            if (a == t && r >= 0)
                out->region[r].n_sides++;
            if ((a != t && !twin[t]) || (twin[t] && f == 0))
                continue;
            unsigned char *seen = f == 0 ? seen_front : seen_back;
            seen[r + 1] = 1; /* index 0: the unbounded region */
        }
        if (a == t && out->side_region[2 * t] >= 0 && out->side_region[2 * t + 1] >= 0)
            out->n_interface++;
        if (a == t && out->side_region[2 * t] == out->side_region[2 * t + 1]) {
            if (out->n_walls++ == 0)
                out->first_wall = t;
        }
    }
    for (int64_t r = 0; r < n_regions; r++)
        out->region[r].kind = seen_front[r + 1] && seen_back[r + 1] ? VC_REGION_MIXED
                              : seen_front[r + 1]                    ? VC_REGION_VOID
                                                                     : VC_REGION_SOLID;
    out->unbounded_sides = (seen_front[0] ? 1 : 0) | (seen_back[0] ? 2 : 0);
    free(twin);
    free(seen_front);
    free(seen_back);
    out->first_copy = alias; /* handed over */
    alias = NULL;

done:
    if (rc)
        vc_regions_free(out);
    free(alias);
    free(alias_flip);
    free(keys);
    free(er);
    free(side);
    free(comp);
    free(ring);
    free(shell_of);
    free(shell_first);
    free(shell_comp);
    free(shell_region);
    free(shell_parent);
    free(shell_vol);
    free(shell_box);
    free(comp_outer);
    return rc;
}

int vc_regions_single_solid(const vc_regions *r)
{
    for (int64_t i = 0; i < r->n_regions; i++)
        if (r->region[i].kind == VC_REGION_MIXED)
            return 0;
    /* as oriented, the unbounded region faces front sides only and the
     * solids back sides; reversed, the other way round */
    const int orientation = r->unbounded_sides == 1 ? 1 : r->unbounded_sides == 2 ? -1 : 0;
    if (!orientation)
        return 0;
    const vc_region_kind solid = orientation > 0 ? VC_REGION_SOLID : VC_REGION_VOID;
    for (int64_t t = 0; t < r->n_triangles; t++) {
        const int64_t f = r->side_region[2 * t], b = r->side_region[2 * t + 1];
        const int solid_f = f >= 0 && r->region[f].kind == solid;
        const int solid_b = b >= 0 && r->region[b].kind == solid;
        if (solid_f == solid_b)
            return 0;
    }
    return orientation;
}

int64_t vc_regions_even_odd_flips(const vc_regions *r, unsigned char *flip)
{
    if (!r->closed_shells)
        return -1;
    int64_t n_flipped = 0;
    for (int64_t c = 0; c < r->n_components; c++)
        n_flipped += (r->component_depth[c] % 2 == 0) != (r->component_outward[c] != 0);
    for (int64_t t = 0; t < r->n_triangles; t++) {
        const int64_t c = r->component_of[t];
        flip[t] = (r->component_depth[c] % 2 == 0) != (r->component_outward[c] != 0);
    }
    return n_flipped;
}

/* An outermost component whose normals point in (nothing around it). */
static int inside_out(const vc_regions *r, int64_t c)
{
    return r->component_depth[c] == 0 && !r->component_outward[c];
}

int64_t vc_regions_inside_out_flips(const vc_regions *r, unsigned char *flip)
{
    if (!r->closed_shells)
        return 0;
    int64_t n_inside_out = 0, n_outermost = 0;
    for (int64_t c = 0; c < r->n_components; c++) {
        n_outermost += r->component_depth[c] == 0;
        n_inside_out += inside_out(r, c);
    }
    if (n_inside_out == n_outermost)
        return 0; /* one solid oriented inward: nothing to reverse */
    for (int64_t t = 0; flip && n_inside_out > 0 && t < r->n_triangles; t++)
        flip[t] = (unsigned char)inside_out(r, r->component_of[t]);
    return n_inside_out;
}

void vc_regions_free(vc_regions *r)
{
    if (!r)
        return;
    free(r->region);
    free(r->side_region);
    free(r->component_of);
    free(r->component_depth);
    free(r->component_outward);
    free(r->first_copy);
    memset(r, 0, sizeof *r);
}
