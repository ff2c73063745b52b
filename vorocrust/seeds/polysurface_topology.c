/* Edge and vertex topology of a polygonal surface. Edges are found by
 * sorting (min, max, polygon, direction) records. */
#include "vorocrust/sampling.h"
#include "util/union_find.h"

#include <stdlib.h>
#include <string.h>

typedef struct edge_rec {
    int64_t a, b;   /* a < b */
    int64_t poly;
    int dir;        /* +1 when the polygon walks a -> b */
} edge_rec;

static int cmp_edge(const void *p, const void *q)
{
    const edge_rec *x = p, *y = q;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return (x->poly > y->poly) - (x->poly < y->poly);
}

/* A polygon corner: its vertex and the link edge (prev, next) it adds to
 * the vertex's link. */
typedef struct corner_rec {
    int64_t v, prev, next;
} corner_rec;

static int cmp_corner(const void *p, const void *q)
{
    const corner_rec *x = p, *y = q;
    if (x->v != y->v)
        return x->v < y->v ? -1 : 1;
    if (x->prev != y->prev)
        return x->prev < y->prev ? -1 : 1;
    return (x->next > y->next) - (x->next < y->next);
}

/* Vertices whose polygons form several fans (pinches: cones touching at
 * their apex), found by the components of each vertex's link graph; a
 * degree count (polygons against edges) does not see them when every fan
 * is closed. Sets multi[v] for them; returns 0, or -1 when out of
 * memory. */
static int mark_multi_fan_vertices(const vc_polysurface *p, unsigned char *multi)
{
    const int64_t nc = p->poly_offsets[p->n_polys];
    corner_rec *c = malloc(sizeof(corner_rec) * (size_t)(nc ? nc : 1));
    if (!c)
        return -1;
    for (int64_t f = 0, m = 0; f < p->n_polys; f++) {
        const int64_t s = p->poly_offsets[f], n = p->poly_offsets[f + 1] - s;
        for (int64_t i = 0; i < n; i++, m++) {
            c[m].v = p->poly_vertices[s + i];
            c[m].prev = p->poly_vertices[s + (i + n - 1) % n];
            c[m].next = p->poly_vertices[s + (i + 1) % n];
        }
    }
    qsort(c, (size_t)nc, sizeof *c, cmp_corner);
    int64_t cap = 0;
    int64_t *ids = NULL, *parent = NULL;
    for (int64_t i = 0; i < nc;) {
        int64_t j = i;
        while (j < nc && c[j].v == c[i].v)
            j++;
        const int64_t d = j - i;
        if (2 * d > cap) {
            cap = 4 * d;
            int64_t *a = realloc(ids, sizeof(int64_t) * (size_t)cap);
            if (a)
                ids = a;
            int64_t *b = realloc(parent, sizeof(int64_t) * (size_t)cap);
            if (b)
                parent = b;
            if (!a || !b) {
                free(ids);
                free(parent);
                free(c);
                return -1;
            }
        }
        /* the link's vertices, numbered locally (a linear search: a
         * vertex has a few dozen polygons) */
        int64_t nl = 0;
        for (int64_t k = i; k < j; k++) {
            const int64_t end[2] = {c[k].prev, c[k].next};
            int64_t loc[2];
            for (int e = 0; e < 2; e++) {
                int64_t q = 0;
                while (q < nl && ids[q] != end[e])
                    q++;
                if (q == nl) {
                    ids[nl] = end[e];
                    parent[nl] = nl;
                    nl++;
                }
                loc[e] = q;
            }
            vc_uf_unite(parent, loc[0], loc[1]);
        }
        int64_t roots = 0;
        for (int64_t q = 0; q < nl; q++)
            roots += vc_uf_find(parent, q) == q;
        if (roots > 1)
            multi[c[i].v] = 1;
        i = j;
    }
    free(ids);
    free(parent);
    free(c);
    return 0;
}

int vc_polysurface_topology_compute(const vc_polysurface *p, vc_polysurface_topology *t,
                                    vc_error *err)
{
    memset(t, 0, sizeof *t);
    int64_t ne = p->poly_offsets[p->n_polys];
    edge_rec *e = malloc(sizeof(edge_rec) * (size_t)(ne ? ne : 1));
    int64_t *parent = malloc(sizeof(int64_t) * (size_t)(p->n_points ? p->n_points : 1));
    /* vertex fans: per vertex, count its polygons and the unions of the
     * polygons around it through shared edges */
    int64_t *vdeg = calloc((size_t)(p->n_points ? p->n_points : 1), sizeof(int64_t));
    int64_t *vedge = calloc((size_t)(p->n_points ? p->n_points : 1), sizeof(int64_t));
    if (!e || !parent || !vdeg || !vedge) {
        free(e);
        free(parent);
        free(vdeg);
        free(vedge);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the surface topology");
    }
    int64_t m = 0;
    for (int64_t f = 0; f < p->n_polys; f++) {
        int64_t s = p->poly_offsets[f], n = p->poly_offsets[f + 1] - s;
        for (int64_t i = 0; i < n; i++) {
            int64_t a = p->poly_vertices[s + i], b = p->poly_vertices[s + (i + 1) % n];
            vdeg[a]++;
            e[m].a = a < b ? a : b;
            e[m].b = a < b ? b : a;
            e[m].poly = f;
            e[m].dir = a < b ? 1 : -1;
            m++;
        }
    }
    qsort(e, (size_t)m, sizeof(edge_rec), cmp_edge);
    vc_uf_init(parent, p->n_points);
    for (int64_t i = 0; i < m;) {
        int64_t j = i;
        while (j < m && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        int64_t cnt = j - i;
        t->n_edges++;
        vedge[e[i].a]++;
        vedge[e[i].b]++;
        if (cnt == 1)
            t->n_boundary_edges++;
        else if (cnt > 2) {
            t->n_nonmanifold_edges++;
            int64_t balance = 0;
            for (int64_t k = i; k < j; k++)
                balance += e[k].dir;
            t->n_balanced_nonmanifold_edges += balance == 0;
        }
        else if (e[i].dir == e[i + 1].dir)
            t->n_misoriented_edges++;
        vc_uf_unite(parent, e[i].a, e[i].b);
        i = j;
    }
    /* A manifold vertex of a closed surface has as many edges as polygons
     * (one fan); more polygons than edges would mean several fans. Closed
     * fans that touch only at the vertex are found by its link. */
    unsigned char *multi = calloc((size_t)(p->n_points ? p->n_points : 1), 1);
    if (!multi || mark_multi_fan_vertices(p, multi)) {
        free(multi);
        free(e);
        free(parent);
        free(vdeg);
        free(vedge);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the surface topology");
    }
    for (int64_t v = 0; v < p->n_points; v++)
        t->n_nonmanifold_vertices += vdeg[v] != vedge[v] || multi[v];
    free(multi);
    t->n_components = vc_uf_count_roots(parent, p->n_points);
    t->n_vertices = p->n_points;
    t->n_faces = p->n_polys;
    t->euler = t->n_vertices - t->n_edges + t->n_faces;
    free(e);
    free(parent);
    free(vdeg);
    free(vedge);
    return 0;
}
