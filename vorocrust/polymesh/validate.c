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

/* Whether the sorted edges e[0..n) hold (a, b): a binary search. */
static int has_edge(const edge *e, int64_t n, int64_t a, int64_t b)
{
    int64_t lo = 0, hi = n;
    while (lo < hi) {
        const int64_t mid = lo + (hi - lo) / 2;
        if (e[mid].a < a || (e[mid].a == a && e[mid].b < b))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && e[lo].a == a && e[lo].b == b;
}

/* Scratch of cell_ok: open-addressing sets of a cell's directed edges and
 * of its vertices (2^bits slots each; key -1: free), and the vertices'
 * points. */
typedef struct cell_scratch {
    edge *slot;
    int64_t *vslot;
    double *pts;
    int bits;
} cell_scratch;

static inline uint64_t hash_pair(int64_t a, int64_t b)
{
    return ((uint64_t)a * 0x9E3779B97F4A7C15ull) ^ ((uint64_t)b * 0xC2B2AE3D27D4EB4Full);
}

/* Whether the cell passes every test of check_cell, decided as check_cell
 * decides (the same conditions and arithmetic), with hash sets instead of
 * sorting its edges (two sorts were half of the validation): the parallel
 * pass's answer, check_cell then names what is wrong. -1 out of memory. */
static int cell_ok(const vc_polymesh *m, const double *face_width, int64_t c, double rel_tol,
                   cell_scratch *w)
{
    const int64_t f0 = m->cell_offsets[c], f1 = m->cell_offsets[c + 1];
    if (f1 - f0 < 4)
        return 0;
    int64_t ne = 0;
    for (int64_t i = f0; i < f1; i++)
        ne += vc_polymesh_face_size(m, m->cell_faces[i]);
    int bits = 6;
    while (((int64_t)1 << bits) < 2 * ne)
        bits++;
    if (bits > w->bits) {
        const size_t ns = (size_t)1 << bits;
        edge *q = realloc(w->slot, ns * sizeof *q);
        if (q)
            w->slot = q;
        int64_t *vq = realloc(w->vslot, ns * sizeof *vq);
        if (vq)
            w->vslot = vq;
        double *pq = realloc(w->pts, 3 * ns * sizeof *pq);
        if (pq)
            w->pts = pq;
        if (!q || !vq || !pq)
            return -1;
        w->bits = bits;
    }
    const uint64_t mask = ((uint64_t)1 << bits) - 1;
    for (uint64_t i = 0; i <= mask; i++) {
        w->slot[i].a = -1;
        w->vslot[i] = -1;
    }
    /* the directed edges: none twice; the distinct vertices, gathered */
    int64_t nd = 0;
    for (int64_t i = f0; i < f1; i++) {
        const int64_t f = m->cell_faces[i];
        if (m->face_owner[f] != c && m->face_neighbour[f] != c)
            return 0;
        const int rev = m->face_owner[f] != c;
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        const int64_t n = vc_polymesh_face_size(m, f);
        for (int64_t j = 0; j < n; j++) {
            const int64_t u = fv[j], v = fv[j + 1 < n ? j + 1 : 0];
            const int64_t a = rev ? v : u, b = rev ? u : v;
            uint64_t h = hash_pair(a, b) >> (64 - bits);
            while (w->slot[h].a >= 0) {
                if (w->slot[h].a == a && w->slot[h].b == b)
                    return 0; /* the same direction twice */
                h = (h + 1) & mask;
            }
            w->slot[h] = (edge){a, b};
            uint64_t g = ((uint64_t)a * 0x9E3779B97F4A7C15ull) >> (64 - bits);
            while (w->vslot[g] >= 0 && w->vslot[g] != a)
                g = (g + 1) & mask;
            if (w->vslot[g] < 0) {
                w->vslot[g] = a;
                memcpy(w->pts + 3 * nd++, m->points + 3 * a, 3 * sizeof(double));
            }
        }
    }
    /* every edge has its opposite */
    for (uint64_t i = 0; i <= mask; i++) {
        if (w->slot[i].a < 0)
            continue;
        const int64_t a = w->slot[i].b, b = w->slot[i].a;
        uint64_t h = hash_pair(a, b) >> (64 - bits);
        while (w->slot[h].a >= 0 && !(w->slot[h].a == a && w->slot[h].b == b))
            h = (h + 1) & mask;
        if (w->slot[h].a < 0)
            return 0;
    }
    if (!(m->cell_volume[c] > 0))
        return 0;
    /* convexity, as check_cell tests it */
    const double *cc = m->cell_centroid + 3 * c;
    double size = 0;
    for (int64_t j = 0; j < nd; j++) {
        const double *p = w->pts + 3 * j;
        double d = sqrt((p[0] - cc[0]) * (p[0] - cc[0]) + (p[1] - cc[1]) * (p[1] - cc[1]) +
                        (p[2] - cc[2]) * (p[2] - cc[2]));
        if (d > size)
            size = d;
    }
    for (int64_t i = f0; i < f1; i++) {
        const int64_t f = m->cell_faces[i];
        const double sgn = m->face_owner[f] == c ? 1.0 : -1.0;
        const double *n = m->face_normal + 3 * f, *fc = m->face_centroid + 3 * f;
        const double allowed = rel_tol * size * (1.0 + size / face_width[f]);
        for (int64_t j = 0; j < nd; j++) {
            const double *p = w->pts + 3 * j;
            const double h =
                sgn * ((p[0] - fc[0]) * n[0] + (p[1] - fc[1]) * n[1] + (p[2] - fc[2]) * n[2]);
            if (h > allowed)
                return 0;
        }
    }
    return 1;
}

/* Checks one cell; returns the number of problems (reported into r). */
static void check_cell(const vc_polymesh *m, const double *face_width, int64_t c, double rel_tol,
                       report *r, edge **ebuf, int64_t *ecap)
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
    if (2 * ne > *ecap) {
        edge *q = realloc(*ebuf, (size_t)(2 * ne) * sizeof(edge));
        if (!q) {
            problem(r, "out of memory checking cell %lld", (long long)c);
            return;
        }
        *ebuf = q;
        *ecap = 2 * ne;
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
    /* Closed and consistently oriented: the edges reversed and sorted are
     * the edges, and none repeats; only a cell failing that is searched
     * for the edge to name. */
    edge *rev_e = e + k;
    for (int64_t j = 0; j < k; j++)
        rev_e[j] = (edge){e[j].b, e[j].a};
    sort_edges(rev_e, k);
    int closed = 1;
    for (int64_t j = 0; j < k && closed; j++)
        closed = rev_e[j].a == e[j].a && rev_e[j].b == e[j].b &&
                 !(j + 1 < k && e[j].a == e[j + 1].a && e[j].b == e[j + 1].b);
    for (int64_t j = 0; j < k && !closed; j++) {
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
        const double width = face_width[f];
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

/* A face's width: its area over its diameter (twice the largest distance
 * from its centroid to a vertex), what the convexity test's tolerance
 * grows with (check_cell). */
static double face_width_of(const vc_polymesh *m, int64_t f)
{
    const int64_t *fv = m->face_vertices + m->face_offsets[f];
    const int64_t n = vc_polymesh_face_size(m, f);
    const double *fc = m->face_centroid + 3 * f;
    double radius = 0;
    for (int64_t j = 0; j < n; j++) {
        const double *p = m->points + 3 * fv[j];
        double d = sqrt((p[0] - fc[0]) * (p[0] - fc[0]) + (p[1] - fc[1]) * (p[1] - fc[1]) +
                        (p[2] - fc[2]) * (p[2] - fc[2]));
        radius = d > radius ? d : radius;
    }
    return m->face_area[f] / (2.0 * radius);
}

/* The checks of face f on its own (its vertices, owner, neighbour, area). */
static void check_face(const vc_polymesh *m, int64_t f, report *r)
{
    int64_t n = vc_polymesh_face_size(m, f);
    const int64_t *fv = m->face_vertices + m->face_offsets[f];
    if (n < 3) {
        problem(r, "face %lld has %lld vertices", (long long)f, (long long)n);
        return;
    }
    for (int64_t i = 0; i < n; i++) {
        if (fv[i] < 0 || fv[i] >= m->n_points) {
            problem(r, "face %lld has vertex index %lld out of range", (long long)f,
                    (long long)fv[i]);
            break;
        }
        for (int64_t j = 0; j < i; j++)
            if (fv[j] == fv[i]) {
                problem(r, "face %lld repeats vertex %lld", (long long)f, (long long)fv[i]);
                break;
            }
    }
    int64_t o = m->face_owner[f], nb = m->face_neighbour[f];
    if (o < 0 || o >= m->n_cells)
        problem(r, "face %lld has owner %lld out of range", (long long)f, (long long)o);
    if ((f < m->n_interior_faces) != (nb >= 0))
        problem(r, "face %lld: interior faces must come first (neighbour %lld)", (long long)f,
                (long long)nb);
    if (nb >= m->n_cells || nb == o)
        problem(r, "face %lld has neighbour %lld (owner %lld)", (long long)f, (long long)nb,
                (long long)o);
    if (!(m->face_area[f] > 0))
        problem(r, "face %lld has area %g", (long long)f, m->face_area[f]);
}

int64_t vc_polymesh_validate(const vc_polymesh *m, double rel_tol, char *buf, size_t len)
{
    report r = {buf, len, 0, 0};
    if (buf && len)
        buf[0] = '\0';
    if (rel_tol <= 0)
        rel_tol = 1e-7;

    /* The faces in parallel, counting only; when one is wrong, all of
     * them again in order, into the report (the same for any thread
     * count). */
    int64_t n_bad_faces = 0;
    double *face_width = malloc(sizeof(double) * (size_t)(m->n_faces > 0 ? m->n_faces : 1));
    if (!face_width) {
        problem(&r, "out of memory");
        return r.count;
    }
#pragma omp parallel for schedule(static) reduction(+ : n_bad_faces)
    for (int64_t f = 0; f < m->n_faces; f++) {
        report quiet = {NULL, 0, 0, 0};
        check_face(m, f, &quiet);
        n_bad_faces += quiet.count;
        /* read by both its cells below: once here, in the faces' order */
        face_width[f] = quiet.count ? 0 : face_width_of(m, f);
    }
    for (int64_t f = 0; f < m->n_faces && n_bad_faces > 0; f++)
        check_face(m, f, &r);
    if (r.count) {
        free(face_width);
        return r.count;
    }

    /* Each face listed by its owner and its neighbour exactly once. */
    int64_t *refs = calloc((size_t)(m->n_faces > 0 ? m->n_faces : 1), sizeof(int64_t));
    if (!refs) {
        problem(&r, "out of memory");
        goto out;
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
        goto out;

    /* The cells on their own, in parallel, counting only; then the cells
     * found wrong once more in order, into the report: the same report for
     * any thread count. */
    unsigned char *bad = calloc((size_t)(m->n_cells > 0 ? m->n_cells : 1), 1);
    if (!bad) {
        problem(&r, "out of memory");
        goto out;
    }
#pragma omp parallel
    {
        cell_scratch w = {NULL, NULL, NULL, 0};
#pragma omp for schedule(dynamic, 512)
        for (int64_t c = 0; c < m->n_cells; c++)
            bad[c] = cell_ok(m, face_width, c, rel_tol, &w) != 1; /* out of memory: checked again */
        free(w.slot);
        free(w.vslot);
        free(w.pts);
    }
    edge *ebuf = NULL;
    int64_t ecap = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        if (bad[c])
            check_cell(m, face_width, c, rel_tol, &r, &ebuf, &ecap);
    free(ebuf);
    free(bad);
out:
    free(face_width);
    return r.count;
}
