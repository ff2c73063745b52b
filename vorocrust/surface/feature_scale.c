/* Sharp features at the scale of the approximation error.
 *
 * A fold between two triangles is a kink at every scale, and the sampler
 * treats a fold above theta_sharp as a crease (its own balls, its corners).
 * On a scan or a marching-cubes isosurface with a little noise, the
 * slivers' normals swing by more than theta_sharp wherever a vertex moves
 * by a fraction of a sliver's width: thousands of creases a few triangles
 * long, corners at their ends, and radius bounds that collapse to the
 * slivers' size (a marching-cubes sphere with noise 1/7 of the error bound:
 * 3e5 balls predicted, against 1.5e3 for the same sphere without
 * features). Yet nothing there is a feature at the scale the mesh is asked
 * to resolve: the surface within a few error bounds of such a fold lies
 * within half an error bound of one plane, and a reconstruction through it
 * stays within the bound.
 *
 * So a fold is sharp only if the surface around it is not flat at the
 * error bound: the triangles reached from the fold's two triangles within
 * VC_FLAT_REACH error bounds (always the two themselves) must stray from
 * their mean plane by more than VC_FLAT_SLAB error bounds. A true crease
 * of angle theta spreads its two sides about R sin(theta / 2) / 2 from
 * that plane at reach R (about one error bound at 60 degrees), and a coarse
 * tessellation's fold spreads its own triangles by their size: both stay
 * sharp. The same test drops sector corners (a vertex whose triangles
 * differ by theta_sharp) on flat ground.
 *
 * The sizing compares normals to decide which parts of a patch may share a
 * ball; for the triangles next to a fold judged noise it also compares
 * their smoothed normals: the mean over the same reach, within the patch
 * (vc_features.tri_smooth_normal). */
#include "feature_scale.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int vc_flat_probe_init(vc_flat_probe *p, int64_t n_triangles)
{
    size_t n = (size_t)(n_triangles > 0 ? n_triangles : 1);
    p->stamp = calloc(n, sizeof *p->stamp);
    p->queue = malloc(n * sizeof *p->queue);
    p->sign = malloc(n);
    p->walk = 0;
    if (!p->stamp || !p->queue || !p->sign) {
        vc_flat_probe_free(p);
        return -1;
    }
    return 0;
}

void vc_flat_probe_free(vc_flat_probe *p)
{
    free(p->stamp);
    free(p->queue);
    free(p->sign);
    memset(p, 0, sizeof *p);
}

int vc_features_walks_forward(const vc_features *f, const vc_surface *s, int64_t t, int64_t e)
{
    const int j = f->tri_edge[3 * t] == e ? 0 : f->tri_edge[3 * t + 1] == e ? 1 : 2;
    return s->tri[3 * t + j] == f->edge_vertex[2 * e] ? 1 : -1;
}

void vc_triangle_centroid(const vc_surface *s, int64_t t, double c[3])
{
    const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                 *d = s->xyz + 3 * s->tri[3 * t + 2];
    for (int k = 0; k < 3; k++)
        c[k] = (a[k] + b[k] + d[k]) / 3.0;
}

void vc_triangle_cross(const vc_surface *s, int64_t t, double n[3])
{
    const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                 *d = s->xyz + 3 * s->tri[3 * t + 2];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

double vc_triangle_twice_area(const vc_surface *s, int64_t t)
{
    double n[3];
    vc_triangle_cross(s, t, n);
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Solves the n x n system a x = b (row-major a, n <= 6) by elimination
 * with partial pivoting; 0 when a pivot falls below 1e-12 of the largest
 * entry (a degenerate spread of points). */
static int solve_small(double *a, double *b, int n, double *x)
{
    double big = 0;
    for (int i = 0; i < n * n; i++)
        big = fmax(big, fabs(a[i]));
    if (!(big > 0))
        return 0;
    for (int k = 0; k < n; k++) {
        int piv = k;
        for (int i = k + 1; i < n; i++)
            if (fabs(a[i * n + k]) > fabs(a[piv * n + k]))
                piv = i;
        if (!(fabs(a[piv * n + k]) > 1e-12 * big))
            return 0;
        if (piv != k) {
            for (int j = 0; j < n; j++) {
                const double t = a[k * n + j];
                a[k * n + j] = a[piv * n + j];
                a[piv * n + j] = t;
            }
            const double t = b[k];
            b[k] = b[piv];
            b[piv] = t;
        }
        for (int i = k + 1; i < n; i++) {
            const double f = a[i * n + k] / a[k * n + k];
            for (int j = k; j < n; j++)
                a[i * n + j] -= f * a[k * n + j];
            b[i] -= f * b[k];
        }
    }
    for (int k = n - 1; k >= 0; k--) {
        double t = b[k];
        for (int j = k + 1; j < n; j++)
            t -= a[k * n + j] * x[j];
        x[k] = t / a[k * n + k];
    }
    return 1;
}

/* The quadric's row (x^2, xy, y^2, x, y, 1) and height z of point q in
 * the frame (u, v, m) about c, in units of reach. */
static void local_row(const double q[3], const double c[3], const double u[3], const double v[3],
                      const double m[3], double reach, double row[6], double *z)
{
    const double r[3] = {(q[0] - c[0]) / reach, (q[1] - c[1]) / reach, (q[2] - c[2]) / reach};
    const double x = r[0] * u[0] + r[1] * u[1] + r[2] * u[2];
    const double y = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
    *z = r[0] * m[0] + r[1] * m[1] + r[2] * m[2];
    row[0] = x * x;
    row[1] = x * y;
    row[2] = y * y;
    row[3] = x;
    row[4] = y;
    row[5] = 1;
}

/* Whether the walk's triangles queue[0..n) lie within slab of the
 * least-squares quadric height function of their vertices over the plane
 * through c normal to m (unit): curved ground, not only flat ground, is
 * smooth at the scale. The residual is taken at the corners, the edge
 * midpoints and the centroid of every triangle: a coarse facet chords
 * across a curved quadric whose vertices it shares. */
static int quadric_fits(const vc_surface *s, const vc_flat_probe *p, int64_t n, const double m[3],
                        const double c[3], double reach, double slab)
{
    double u[3] = {0, 0, 0};
    u[fabs(m[0]) < fabs(m[1]) ? (fabs(m[0]) < fabs(m[2]) ? 0 : 2) : (fabs(m[1]) < fabs(m[2]) ? 1 : 2)] = 1;
    const double d = u[0] * m[0] + u[1] * m[1] + u[2] * m[2];
    for (int k = 0; k < 3; k++)
        u[k] -= d * m[k];
    const double lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; k++)
        u[k] /= lu;
    const double v[3] = {m[1] * u[2] - m[2] * u[1], m[2] * u[0] - m[0] * u[2], m[0] * u[1] - m[1] * u[0]};
    double ata[36] = {0}, atz[6] = {0}, coef[6], row[6], z;
    for (int64_t i = 0; i < n; i++)
        for (int j = 0; j < 3; j++) {
            local_row(s->xyz + 3 * s->tri[3 * p->queue[i] + j], c, u, v, m, reach, row, &z);
            for (int a = 0; a < 6; a++) {
                atz[a] += row[a] * z;
                for (int b = 0; b < 6; b++)
                    ata[6 * a + b] += row[a] * row[b];
            }
        }
    if (!solve_small(ata, atz, 6, coef))
        return 0;
    for (int64_t i = 0; i < n; i++) {
        const int64_t *w = s->tri + 3 * p->queue[i];
        for (int k = 0; k < 7; k++) {
            double q[3];
            for (int e = 0; e < 3; e++) {
                const double a = s->xyz[3 * w[k % 3] + e], b = s->xyz[3 * w[(k + 1) % 3] + e],
                             g = s->xyz[3 * w[(k + 2) % 3] + e];
                q[e] = k < 3 ? a : k < 6 ? 0.5 * (a + b) : (a + b + g) / 3.0;
            }
            local_row(q, c, u, v, m, reach, row, &z);
            double h = z;
            for (int a = 0; a < 6; a++)
                h -= coef[a] * row[a];
            if (!(fabs(h) * reach <= slab))
                return 0;
        }
    }
    return 1;
}

static int flat_walk(const vc_surface *s, const vc_features *f, vc_flat_probe *p, const int64_t *seeds,
                     int n_seeds, const double x[3], double reach, double slab, int within_patch,
                     double mean[3], int grow);

int vc_flat_near(const vc_surface *s, const vc_features *f, vc_flat_probe *p, const int64_t *seeds,
                 int n_seeds, const double x[3], double reach, double slab, int within_patch,
                 double mean[3])
{
    return flat_walk(s, f, p, seeds, n_seeds, x, reach, slab, within_patch, mean, VC_FLAT_GROW);
}

/* The unit normal of the least-squares plane through c of the corners of
 * the walk's n triangles (the eigenvector of their scatter matrix with the
 * least eigenvalue, by Jacobi rotations); 0 when it is not defined. */
static int least_squares_normal(const vc_surface *s, const vc_flat_probe *p, int64_t n, const double c[3],
                                double q[3])
{
    double a[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int64_t i = 0; i < n; i++) {
        const int64_t *v = s->tri + 3 * p->queue[i];
        for (int j = 0; j < 3; j++) {
            const double *x = s->xyz + 3 * v[j];
            const double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
            for (int r = 0; r < 3; r++)
                for (int k = 0; k < 3; k++)
                    a[r][k] += d[r] * d[k];
        }
    }
    double vec[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 32; sweep++) {
        const double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        if (!(off > 1e-300) || off <= 1e-15 * (fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2])))
            break;
        for (int r = 0; r < 2; r++)
            for (int k = r + 1; k < 3; k++) {
                if (a[r][k] == 0)
                    continue;
                const double theta = 0.5 * (a[k][k] - a[r][r]) / a[r][k];
                const double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
                const double cs = 1 / sqrt(t * t + 1), sn = t * cs;
                for (int j = 0; j < 3; j++) { /* A <- A J (columns r, k) */
                    const double x = a[j][r], y = a[j][k];
                    a[j][r] = cs * x - sn * y;
                    a[j][k] = sn * x + cs * y;
                }
                for (int j = 0; j < 3; j++) { /* A <- J^T A (rows r, k) */
                    const double x = a[r][j], y = a[k][j];
                    a[r][j] = cs * x - sn * y;
                    a[k][j] = sn * x + cs * y;
                }
                for (int j = 0; j < 3; j++) {
                    const double x = vec[j][r], y = vec[j][k];
                    vec[j][r] = cs * x - sn * y;
                    vec[j][k] = sn * x + cs * y;
                }
            }
    }
    int least = 0;
    for (int k = 1; k < 3; k++)
        if (a[k][k] < a[least][least])
            least = k;
    const double l = sqrt(vec[0][least] * vec[0][least] + vec[1][least] * vec[1][least] +
                          vec[2][least] * vec[2][least]);
    if (!(l > 0) || !isfinite(l))
        return 0;
    for (int k = 0; k < 3; k++)
        q[k] = vec[k][least] / l;
    return 1;
}

/* vc_flat_near; when the points leave the plane's slab and the walk took
 * too few triangles for a quadric, the walk is made again, up to grow
 * times, each time twice as far. */
static int flat_walk(const vc_surface *s, const vc_features *f, vc_flat_probe *p, const int64_t *seeds,
                     int n_seeds, const double x[3], double reach, double slab, int within_patch,
                     double mean[3], int grow)
{
    const int64_t walk = ++p->walk;
    int64_t head = 0, tail = 0;
    for (int i = 0; i < n_seeds; i++) {
        const int64_t t = seeds[i];
        if (p->stamp[t] == walk)
            continue;
        p->stamp[t] = walk;
        /* the seeds of a fold: its two triangles, turned consistently */
        p->sign[t] = 1;
        if (i > 0 && !within_patch) {
            for (int j = 0; j < 3; j++) {
                const int64_t e = f->tri_edge[3 * t + j];
                for (int64_t k = f->edge_tri_start[e]; k < f->edge_tri_start[e + 1]; k++)
                    if (f->edge_tri[k] == seeds[0] && f->edge_tri_start[e + 1] - f->edge_tri_start[e] == 2)
                        p->sign[t] = (signed char)(vc_features_walks_forward(f, s, t, e) == vc_features_walks_forward(f, s, seeds[0], e)
                                                       ? -1
                                                       : 1);
            }
        }
        p->queue[tail++] = t;
    }
    double m[3] = {0, 0, 0}, c[3] = {0, 0, 0}, area = 0;
    while (head < tail) {
        const int64_t t = p->queue[head++];
        const double w = vc_triangle_twice_area(s, t);
        double ct[3];
        vc_triangle_centroid(s, t, ct);
        for (int k = 0; k < 3; k++) {
            m[k] += p->sign[t] * w * f->tri_normal[3 * t + k];
            c[k] += w * ct[k];
        }
        area += w;
        for (int j = 0; j < 3; j++) {
            const int64_t e = f->tri_edge[3 * t + j];
            if (f->edge_tri_start[e + 1] - f->edge_tri_start[e] != 2 || (within_patch && f->edge_sharp[e]))
                continue;
            const int64_t u = f->edge_tri[f->edge_tri_start[e]] == t ? f->edge_tri[f->edge_tri_start[e] + 1]
                                                                      : f->edge_tri[f->edge_tri_start[e]];
            if (p->stamp[u] == walk)
                continue;
            double cu[3];
            vc_triangle_centroid(s, u, cu);
            if ((cu[0] - x[0]) * (cu[0] - x[0]) + (cu[1] - x[1]) * (cu[1] - x[1]) + (cu[2] - x[2]) * (cu[2] - x[2]) >
                reach * reach)
                continue;
            p->stamp[u] = walk;
            p->sign[u] = within_patch ? 1
                                      : (signed char)(vc_features_walks_forward(f, s, t, e) == vc_features_walks_forward(f, s, u, e)
                                                          ? -p->sign[t]
                                                          : p->sign[t]);
            p->queue[tail++] = u;
        }
    }
    p->n_reached = tail;
    const double len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    if (mean)
        for (int k = 0; k < 3; k++)
            mean[k] = len > 0 ? m[k] / len : 0;
    if (!(slab < INFINITY)) /* only the mean was asked for */
        return len > 0 && len >= VC_FLAT_COHERENCE * area;
    /* the normals must mostly agree: a surface, not a speck folded up
     * within the reach (whose mean normal nearly vanishes) */
    if (!(area > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        c[k] /= area;
    if (len >= VC_FLAT_COHERENCE * area) {
        for (int k = 0; k < 3; k++)
            m[k] /= len;
    } else {
        /* The normals disagree: a speck folded up, a sheet turned over (the
         * rim of a plate thinner than the slab), or slivers the noise tilted
         * far but not over (the needles at a UV sphere's pole: +-0.002 of
         * noise across 0.0005 of width, normals 80 degrees off on every
         * side, their mean a tenth of their area). The least-squares plane
         * of the walk's corners decides: flat only if every triangle faces
         * its side of it (the walk is a graph over the plane, nothing turned
         * over) and the corners lie in its slab (below). */
        double q[3];
        if (!least_squares_normal(s, p, tail, c, q))
            return 0;
        if (q[0] * m[0] + q[1] * m[1] + q[2] * m[2] < 0)
            for (int k = 0; k < 3; k++)
                q[k] = -q[k];
        /* facing away: a turned-over sheet has half its area there; noise
         * tips a few needles just past upright (their normals within 1e-3 of
         * the plane) */
        double away = 0;
        for (int64_t i = 0; i < tail; i++) {
            const int64_t t = p->queue[i];
            const double *n = f->tri_normal + 3 * t;
            const double d = p->sign[t] * (n[0] * q[0] + n[1] * q[1] + n[2] * q[2]);
            if (d < 0)
                away += vc_triangle_twice_area(s, t) * -d;
        }
        if (!(away <= VC_FLAT_TURNED * area))
            /* a few triangles of a fan (a UV sphere's pole) make no plane
             * to judge by: farther */
            return grow > 0 && flat_walk(s, f, p, seeds, n_seeds, x, 2 * reach, slab, within_patch, mean,
                                         grow - 1);
        memcpy(m, q, sizeof q);
    }
    int in_slab = 1;
    for (int64_t i = 0; i < tail && in_slab; i++) {
        const int64_t *v = s->tri + 3 * p->queue[i];
        for (int j = 0; j < 3; j++) {
            const double *q = s->xyz + 3 * v[j];
            const double h = m[0] * (q[0] - c[0]) + m[1] * (q[1] - c[1]) + m[2] * (q[2] - c[2]);
            if (!(fabs(h) <= slab))
                in_slab = 0;
        }
    }
    if (in_slab)
        return 1;
    if (tail >= VC_FLAT_QUADRIC_MIN)
        return quadric_fits(s, p, tail, m, c, reach, VC_FLAT_QUADRIC_SLAB * slab);
    return grow > 0 && flat_walk(s, f, p, seeds, n_seeds, x, 2 * reach, slab, within_patch, mean, grow - 1);
}

/* Marks in near the triangles of the last walk whose normal leans more
 * than theta_sharp / 2 from the walk's mean m: those the noise tilted.
 * The others lie within theta_sharp / 2 of the smoothed normal already,
 * so their own normal stands for it (half the triangles a walk takes need
 * no smoothing walk of their own). */
static void mark_tilted(const vc_features *f, const vc_flat_probe *p, const double m[3],
                        unsigned char *near)
{
    const double cos_tilt = cos(0.5 * f->sharp_angle * 3.14159265358979323846 / 180.0);
    for (int64_t i = 0; i < p->n_reached; i++) {
        const int64_t u = p->queue[i];
        const double *n = f->tri_normal + 3 * u;
        if (p->sign[u] * (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]) < cos_tilt) {
#pragma omp atomic write
            near[u] = 1;
        }
    }
}

static int64_t root_of(int64_t *parent, int64_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

/* The flat-ground walk of fold e (a manifold edge): from its two
 * triangles, around its midpoint. */
static int fold_flat(const vc_surface *s, const vc_features *f, vc_flat_probe *p, int64_t e, double reach,
                     double slab, double mean[3])
{
    const int64_t seeds[2] = {f->edge_tri[f->edge_tri_start[e]], f->edge_tri[f->edge_tri_start[e] + 1]};
    const double *a = s->xyz + 3 * f->edge_vertex[2 * e], *b = s->xyz + 3 * f->edge_vertex[2 * e + 1];
    const double x[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
    return vc_flat_near(s, f, p, seeds, 2, x, reach, slab, 0, mean);
}

/* The walks of the folds, in parallel, each with its own probe: without
 * near, the folds above theta_sharp judged (flat[e]); with it, the
 * triangles tilted around each fold with flat[e] marked in near. Neither
 * depends on the order, so neither on the thread count. 0, or -1 when out
 * of memory. */
static int walk_folds(const vc_surface *s, const vc_features *f, unsigned char *flat, double scale,
                      unsigned char *near)
{
    int fail = 0;
#pragma omp parallel reduction(| : fail)
    {
        vc_flat_probe q;
        if (vc_flat_probe_init(&q, s->n_triangles))
            fail = 1;
        else {
#pragma omp for schedule(dynamic, 16)
            for (int64_t e = 0; e < f->n_edges; e++) {
                if (!near && f->edge_sharp[e] == VC_SHARP_ANGLE) {
                    flat[e] = (unsigned char)fold_flat(s, f, &q, e, VC_FLAT_REACH * scale,
                                                       VC_FLAT_SLAB * scale, NULL);
                } else if (near && flat[e]) {
                    double m[3];
                    fold_flat(s, f, &q, e, VC_FLAT_REACH * scale, INFINITY, m);
                    mark_tilted(f, &q, m, near);
                }
            }
            vc_flat_probe_free(&q);
        }
    }
    return fail ? -1 : 0;
}

/* Networks of sharp edges smaller than the error bound (the diagonal of
 * their vertices' bounding box below VC_SPECK_EXTENT * scale) on coherent
 * ground are noise too, however curved that ground: the folds of
 * marching-cubes slivers on a bumpy surface (the plane and the quadric
 * tests above fail there: a noise blob contoured at 480^3 kept 5 folds of
 * 70 degrees around triangles of area 1e-10 and 1e-15, two of their
 * corners 3e-7 apart, and the sampling's radius bound fell to 8.5e-9: a
 * first coverage still running after 5 minutes). A feature below the error
 * bound is below the resolution asked for; the reconstruction passes
 * within the bound of it either way. The ground is coherent when the
 * triangles within VC_FLAT_REACH * scale of the network's centre, turned
 * consistently, have a mean normal of at least VC_FLAT_COHERENCE of their
 * area: a surface, not a speck folded up (a tiny closed part, whose mean
 * normal vanishes, keeps its features). Only networks of folds
 * (VC_SHARP_ANGLE) qualify: a boundary, a non-manifold edge or a crease
 * asked for keeps its network. Those networks' edges get flat[e] set and
 * their root's kept cleared. Returns 0, or -1 when out of memory. */
static int unkeep_specks(const vc_surface *s, const vc_features *f, int64_t *parent,
                         unsigned char *kept, unsigned char *flat, double scale)
{
    const int64_t nv = s->n_vertices;
    int64_t n_kept = 0;
    for (int64_t v = 0; v < nv; v++)
        n_kept += kept[v];
    if (n_kept == 0)
        return 0;
    /* the kept networks' bounding boxes and one triangle each (a walk's
     * seed), indexed by root */
    double *box = malloc(sizeof(double) * 6 * (size_t)nv);
    int64_t *seed = malloc(sizeof(int64_t) * (size_t)nv);
    vc_flat_probe q;
    if (!box || !seed || vc_flat_probe_init(&q, s->n_triangles)) {
        free(box);
        free(seed);
        return -1;
    }
    for (int64_t v = 0; v < nv; v++)
        if (kept[v]) {
            seed[v] = -1;
            for (int k = 0; k < 3; k++) {
                box[6 * v + k] = INFINITY;
                box[6 * v + 3 + k] = -INFINITY;
            }
        }
    for (int64_t e = 0; e < f->n_edges; e++) {
        if (!f->edge_sharp[e])
            continue;
        const int64_t r = root_of(parent, f->edge_vertex[2 * e]);
        if (!kept[r])
            continue;
        /* only folds are judged: a network with a boundary, non-manifold
         * or requested edge stays (seed -2) */
        if (f->edge_sharp[e] != VC_SHARP_ANGLE)
            seed[r] = -2;
        if (seed[r] == -2)
            continue;
        if (seed[r] < 0 && f->edge_tri_start[e + 1] > f->edge_tri_start[e])
            seed[r] = f->edge_tri[f->edge_tri_start[e]];
        for (int j = 0; j < 2; j++) {
            const double *x = s->xyz + 3 * f->edge_vertex[2 * e + j];
            for (int k = 0; k < 3; k++) {
                box[6 * r + k] = fmin(box[6 * r + k], x[k]);
                box[6 * r + 3 + k] = fmax(box[6 * r + 3 + k], x[k]);
            }
        }
    }
    /* in vertex order: the same answer for any thread count */
    for (int64_t v = 0; v < nv; v++) {
        if (!kept[v] || seed[v] < 0)
            continue; /* not a root, or a network that is not all folds */
        const double *b = box + 6 * v;
        const double d[3] = {b[3] - b[0], b[4] - b[1], b[5] - b[2]};
        if (!(sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) < VC_SPECK_EXTENT * scale))
            continue;
        const double x[3] = {0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5])};
        if (vc_flat_near(s, f, &q, &seed[v], 1, x, VC_FLAT_REACH * scale, INFINITY, 0, NULL))
            kept[v] = 2; /* noise: its edges are marked below */
    }
    for (int64_t e = 0; e < f->n_edges; e++)
        if (f->edge_sharp[e] && kept[root_of(parent, f->edge_vertex[2 * e])] == 2)
            flat[e] = 1;
    for (int64_t v = 0; v < nv; v++)
        if (kept[v] == 2)
            kept[v] = 0;
    vc_flat_probe_free(&q);
    free(box);
    free(seed);
    return 0;
}

int vc_features_unmark_noise_folds(const vc_surface *s, vc_features *f, double scale,
                                   unsigned char *near)
{
    f->n_sharp_noise = 0;
    if (!(scale > 0) || !isfinite(scale) || f->n_sharp_by_angle == 0)
        return 0;
    const int64_t nv = s->n_vertices;
    int64_t *parent = malloc(sizeof(int64_t) * (size_t)(nv > 0 ? nv : 1));
    unsigned char *kept = calloc((size_t)(nv > 0 ? nv : 1), 1);
    unsigned char *flat = calloc((size_t)(f->n_edges > 0 ? f->n_edges : 1), 1);
    if (!parent || !kept || !flat) {
        free(parent);
        free(kept);
        free(flat);
        return -1;
    }
    /* The sharp edges joined at their vertices form networks; a network is
     * noise only when every edge of it lies on flat ground (a short
     * chamfer of a true crease network is flat at the error bound, but
     * unmarking it alone would leave the crease's 90-degree turns inside a
     * patch). */
    for (int64_t v = 0; v < nv; v++)
        parent[v] = v;
    for (int64_t e = 0; e < f->n_edges; e++)
        if (f->edge_sharp[e]) {
            const int64_t a = root_of(parent, f->edge_vertex[2 * e]), b = root_of(parent, f->edge_vertex[2 * e + 1]);
            if (a != b)
                parent[a < b ? b : a] = a < b ? a : b;
        }
    /* Every fold judged by its own walk, in parallel (a UV sphere's noisy
     * poles have thousands of folds whose walks take 2,000 needles each) */
    int fail = walk_folds(s, f, flat, scale, NULL) != 0;
    for (int64_t e = 0; e < f->n_edges && !fail; e++)
        if (f->edge_sharp[e] && !flat[e])
            kept[root_of(parent, f->edge_vertex[2 * e])] = 1;
    if (!fail && unkeep_specks(s, f, parent, kept, flat, scale))
        fail = 1;
    for (int64_t e = 0; e < f->n_edges && !fail; e++) {
        if (!flat[e])
            continue;
        if (kept[root_of(parent, f->edge_vertex[2 * e])]) {
            flat[e] = 0;
            continue;
        }
        f->edge_sharp[e] = 0;
        f->n_sharp_edges--;
        f->n_sharp_by_angle--;
        f->n_sharp_noise++;
    }
    /* the ground looked at, again, for the smoothed normals */
    if (!fail)
        fail = walk_folds(s, f, flat, scale, near) != 0;
    free(parent);
    free(kept);
    free(flat);
    return fail ? -1 : 0;
}

int vc_features_vertex_flat(const vc_surface *s, const vc_features *f, vc_flat_probe *p, int64_t v,
                            const int64_t *vtri, int64_t n_vtri, double scale, unsigned char *near)
{
    if (n_vtri <= 0)
        return 0;
    /* a walk from one triangle of v: every other one must be reached (a
     * triangle beyond the reach, or a fan joined only at v, is not flat
     * ground) */
    const double *x = s->xyz + 3 * v;
    double m[3];
    if (!vc_flat_near(s, f, p, vtri, 1, x, VC_FLAT_REACH * scale, VC_FLAT_SLAB * scale, 0, m))
        return 0;
    for (int64_t i = 0; i < n_vtri; i++)
        if (p->stamp[vtri[i]] != p->walk)
            return 0;
    mark_tilted(f, p, m, near);
    return 1;
}

int vc_features_smooth_normals(const vc_surface *s, vc_features *f, double scale,
                               const unsigned char *near)
{
    const int64_t nt = s->n_triangles;
    f->tri_smooth_normal = malloc(sizeof(double) * 3 * (size_t)(nt > 0 ? nt : 1));
    if (!f->tri_smooth_normal)
        return -1;
    memcpy(f->tri_smooth_normal, f->tri_normal, sizeof(double) * 3 * (size_t)nt);
    int fail = 0;
#pragma omp parallel reduction(| : fail)
    {
        vc_flat_probe p;
        if (vc_flat_probe_init(&p, nt))
            fail = 1;
        else {
#pragma omp for schedule(dynamic, 256)
            for (int64_t t = 0; t < nt; t++) {
                if (!near[t])
                    continue;
                double c[3], m[3];
                vc_triangle_centroid(s, t, c);
                vc_flat_near(s, f, &p, &t, 1, c, VC_FLAT_REACH * scale, INFINITY, 1, m);
                if (m[0] != 0 || m[1] != 0 || m[2] != 0)
                    memcpy(f->tri_smooth_normal + 3 * t, m, sizeof m);
            }
            vc_flat_probe_free(&p);
        }
    }
    if (fail) {
        free(f->tri_smooth_normal);
        f->tri_smooth_normal = NULL;
        return -1;
    }
    return 0;
}
