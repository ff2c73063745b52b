/* The mesh validator: every invariant the Voronoi engine promises. */
#include "vorocrust/polymesh.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/small_sort.h"

typedef struct report {
    char *buf;
    size_t len, used;
    int64_t count;
} report;

static void problem(report *r, const char *fmt, ...)
{
    r->count++;
    if (!r->buf || r->used + 1 >= r->len)
        return;
    va_list ap;
    va_start(ap, fmt);
    int w = vsnprintf(r->buf + r->used, r->len - r->used, fmt, ap);
    va_end(ap);
    if (w < 0)
        return;
    r->used += (size_t)w;
    if (r->used + 1 < r->len) {
        r->buf[r->used++] = '\n';
        r->buf[r->used] = '\0';
    } else {
        r->used = r->len - 1;
    }
}

typedef struct edge {
    int64_t a, b;
} edge;

#define EDGE_LESS(p, q) ((p)->a < (q)->a || ((p)->a == (q)->a && (p)->b < (q)->b))
VC_SMALL_SORT(sort_edges, edge, EDGE_LESS)

static int cmp_edge(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    return 0;
}

static int has_edge(const edge *e, int64_t n, int64_t a, int64_t b)
{
    edge key = {a, b};
    return bsearch(&key, e, (size_t)n, sizeof *e, cmp_edge) != NULL;
}

/* Checks one cell; returns the number of problems (reported into r). */
static void check_cell(const vc_polymesh *m, int64_t c, double rel_tol, report *r,
                       edge **ebuf, int64_t *ecap)
{
    int64_t f0 = m->cell_offsets[c], f1 = m->cell_offsets[c + 1];
    if (f1 - f0 < 4) {
        problem(r, "cell %lld has %lld faces (a closed polyhedron needs 4)", (long long)c,
                (long long)(f1 - f0));
        return;
    }
    int64_t ne = 0;
    for (int64_t i = f0; i < f1; i++)
        ne += vc_polymesh_face_size(m, m->cell_faces[i]);
    if (ne > *ecap) {
        edge *q = realloc(*ebuf, (size_t)ne * sizeof(edge));
        if (!q) {
            problem(r, "out of memory checking cell %lld", (long long)c);
            return;
        }
        *ebuf = q;
        *ecap = ne;
    }
    edge *e = *ebuf;
    int64_t k = 0;
    for (int64_t i = f0; i < f1; i++) {
        int64_t f = m->cell_faces[i];
        if (m->face_owner[f] != c && m->face_neighbour[f] != c) {
            problem(r, "cell %lld lists face %lld, which is not one of its faces", (long long)c,
                    (long long)f);
            return;
        }
        int rev = m->face_owner[f] != c;
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        int64_t n = vc_polymesh_face_size(m, f);
        for (int64_t j = 0; j < n; j++) {
            int64_t a = fv[j], b = fv[(j + 1) % n];
            e[k++] = rev ? (edge){b, a} : (edge){a, b};
        }
    }
    sort_edges(e, k);
    for (int64_t j = 0; j < k; j++) {
        if (j + 1 < k && e[j].a == e[j + 1].a && e[j].b == e[j + 1].b) {
            problem(r, "cell %lld uses edge %lld->%lld twice in the same direction (faces not "
                       "outward-oriented consistently)",
                    (long long)c, (long long)e[j].a, (long long)e[j].b);
            return;
        }
        if (!has_edge(e, k, e[j].b, e[j].a)) {
            problem(r, "cell %lld is not closed: edge %lld->%lld has no opposite", (long long)c,
                    (long long)e[j].a, (long long)e[j].b);
            return;
        }
    }
    if (!(m->cell_volume[c] > 0)) {
        problem(r, "cell %lld has volume %g", (long long)c, m->cell_volume[c]);
        return;
    }
    /* Convexity: every vertex on the inner side of every face plane. The
     * cell's distinct vertices (in the edges' sorted order) are gathered
     * once when they fit a local array: every face's test then reads them
     * side by side instead of every edge's point from the mesh. */
    const double *cc = m->cell_centroid + 3 * c;
    enum { LOCAL_VERTICES = 256 };
    double local[3 * LOCAL_VERTICES];
    int64_t nd = 0;
    for (int64_t j = 0; j < k && nd <= LOCAL_VERTICES; j++) {
        if (j > 0 && e[j].a == e[j - 1].a)
            continue;
        if (nd < LOCAL_VERTICES)
            memcpy(local + 3 * nd, m->points + 3 * e[j].a, 3 * sizeof(double));
        nd++;
    }
    const int gathered = nd <= LOCAL_VERTICES;
    double size = 0;
    for (int64_t j = 0; j < k; j++) {
        if (gathered && j >= nd)
            break;
        const double *p = gathered ? local + 3 * j : m->points + 3 * e[j].a;
        double d = sqrt((p[0] - cc[0]) * (p[0] - cc[0]) + (p[1] - cc[1]) * (p[1] - cc[1]) +
                        (p[2] - cc[2]) * (p[2] - cc[2]));
        if (d > size)
            size = d;
    }
    for (int64_t i = f0; i < f1; i++) {
        int64_t f = m->cell_faces[i];
        double sgn = m->face_owner[f] == c ? 1.0 : -1.0;
        const double *n = m->face_normal + 3 * f, *fc = m->face_centroid + 3 * f;
        /* A face's plane comes from its vertices, each placed within about
         * rel_tol * size: its normal is off by up to that over the face's
         * width (area / diameter), which tilts the plane by size times as
         * much at the far side of the cell. Nearly co-circular seeds give
         * real faces a billionth of the cell wide. */
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        const int64_t nfv = vc_polymesh_face_size(m, f);
        double radius = 0;
        for (int64_t j = 0; j < nfv; j++) {
            const double *p = m->points + 3 * fv[j];
            double d = sqrt((p[0] - fc[0]) * (p[0] - fc[0]) + (p[1] - fc[1]) * (p[1] - fc[1]) +
                            (p[2] - fc[2]) * (p[2] - fc[2]));
            radius = d > radius ? d : radius;
        }
        const double width = m->face_area[f] / (2.0 * radius);
        const double allowed = rel_tol * size * (1.0 + size / width);
        if (gathered) {
            int64_t worst = -1;
            for (int64_t j = 0; j < nd; j++) {
                const double *p = local + 3 * j;
                const double h =
                    sgn * ((p[0] - fc[0]) * n[0] + (p[1] - fc[1]) * n[1] + (p[2] - fc[2]) * n[2]);
                if (h > allowed) {
                    worst = j;
                    break;
                }
            }
            if (worst < 0)
                continue;
            /* the report names the vertex: found again among the edges */
        }
        for (int64_t j = 0; j < k; j++) {
            if (j > 0 && e[j].a == e[j - 1].a)
                continue;
            const double *p = m->points + 3 * e[j].a;
            double h = sgn * ((p[0] - fc[0]) * n[0] + (p[1] - fc[1]) * n[1] + (p[2] - fc[2]) * n[2]);
            if (h > allowed) {
                problem(r, "cell %lld is not convex: vertex %lld lies %g (relative %g) outside "
                           "the plane of face %lld",
                        (long long)c, (long long)e[j].a, h, h / size, (long long)f);
                return;
            }
        }
    }
}

int64_t vc_polymesh_validate(const vc_polymesh *m, double rel_tol, char *buf, size_t len)
{
    report r = {buf, len, 0, 0};
    if (buf && len)
        buf[0] = '\0';
    if (rel_tol <= 0)
        rel_tol = 1e-7;

    for (int64_t f = 0; f < m->n_faces; f++) {
        int64_t n = vc_polymesh_face_size(m, f);
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        if (n < 3) {
            problem(&r, "face %lld has %lld vertices", (long long)f, (long long)n);
            continue;
        }
        for (int64_t i = 0; i < n; i++) {
            if (fv[i] < 0 || fv[i] >= m->n_points) {
                problem(&r, "face %lld has vertex index %lld out of range", (long long)f,
                        (long long)fv[i]);
                break;
            }
            for (int64_t j = 0; j < i; j++)
                if (fv[j] == fv[i]) {
                    problem(&r, "face %lld repeats vertex %lld", (long long)f, (long long)fv[i]);
                    break;
                }
        }
        int64_t o = m->face_owner[f], nb = m->face_neighbour[f];
        if (o < 0 || o >= m->n_cells)
            problem(&r, "face %lld has owner %lld out of range", (long long)f, (long long)o);
        if ((f < m->n_interior_faces) != (nb >= 0))
            problem(&r, "face %lld: interior faces must come first (neighbour %lld)",
                    (long long)f, (long long)nb);
        if (nb >= m->n_cells || nb == o)
            problem(&r, "face %lld has neighbour %lld (owner %lld)", (long long)f, (long long)nb,
                    (long long)o);
        if (!(m->face_area[f] > 0))
            problem(&r, "face %lld has area %g", (long long)f, m->face_area[f]);
    }
    if (r.count)
        return r.count;

    /* Each face listed by its owner and its neighbour exactly once. */
    int64_t *refs = calloc((size_t)(m->n_faces > 0 ? m->n_faces : 1), sizeof(int64_t));
    if (!refs) {
        problem(&r, "out of memory");
        return r.count;
    }
    for (int64_t c = 0; c < m->n_cells; c++)
        for (int64_t i = m->cell_offsets[c]; i < m->cell_offsets[c + 1]; i++) {
            int64_t f = m->cell_faces[i];
            if (f < 0 || f >= m->n_faces) {
                problem(&r, "cell %lld lists face %lld out of range", (long long)c, (long long)f);
                continue;
            }
            refs[f]++;
        }
    for (int64_t f = 0; f < m->n_faces; f++) {
        int64_t want = m->face_neighbour[f] >= 0 ? 2 : 1;
        if (refs[f] != want)
            problem(&r, "face %lld is listed by %lld cells, expected %lld", (long long)f,
                    (long long)refs[f], (long long)want);
    }
    free(refs);
    if (r.count)
        return r.count;

    /* The cells on their own, in parallel, counting only; then the cells
     * found wrong once more in order, into the report: the same report for
     * any thread count. */
    unsigned char *bad = calloc((size_t)(m->n_cells > 0 ? m->n_cells : 1), 1);
    if (!bad) {
        problem(&r, "out of memory");
        return r.count;
    }
#pragma omp parallel
    {
        edge *eb = NULL;
        int64_t ec = 0;
#pragma omp for schedule(dynamic, 512)
        for (int64_t c = 0; c < m->n_cells; c++) {
            report quiet = {NULL, 0, 0, 0};
            check_cell(m, c, rel_tol, &quiet, &eb, &ec);
            bad[c] = quiet.count > 0;
        }
        free(eb);
    }
    edge *ebuf = NULL;
    int64_t ecap = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        if (bad[c])
            check_cell(m, c, rel_tol, &r, &ebuf, &ecap);
    free(ebuf);
    free(bad);
    return r.count;
}
