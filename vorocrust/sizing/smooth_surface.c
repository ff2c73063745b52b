/* APSS surface of the input's samples (smooth_surface.h).
 *
 * The fit at a point y (Guennebaud and Gross, "Algebraic point set
 * surfaces", 2007): with normalised weights w_i of the samples p_i (taken
 * relative to y) and their normals n_i, the algebraic sphere
 * s(q) = u0 + u.q + u4 |q|^2 whose gradient best matches the normals and
 * whose mean over the samples is zero:
 *   u4 = (1/2) (sum w p.n - (sum w p).(sum w n)) / (sum w |p|^2 - |sum w p|^2)
 *   u  = sum w n - 2 u4 sum w p
 *   u0 = -u.(sum w p) - u4 sum w |p|^2.
 * y moves to the nearest point of that sphere (or plane), and the fit is
 * made again there until y stops moving: S' is the set of such fixed
 * points. The kernel (1 - d^2 / width^2)^3 is C2 at its edge, so the fit,
 * and S', change smoothly with y. */
#include "sizing/smooth_surface.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* samples per width along a triangle's longest edge */
#define SAMPLES_PER_WIDTH 3.0
/* the most samples kept: beyond, the spacing grows */
#define MAX_SAMPLES 20000000.0
#define MAX_STEPS 24
/* steps of the fast orthogonal projection before the robust one takes over */
#define FAST_STEPS 10
/* normals within acos(-0.3) of the query triangle's count, fully within acos(0.3) */
#define NORMAL_RAMP 0.3

static int64_t cell_index(const vc_smooth_surface *m, const double x[3], int64_t c[3])
{
    for (int d = 0; d < 3; d++) {
        double t = floor((x[d] - m->lo[d]) / m->cell);
        c[d] = t < 0 ? 0 : t >= (double)m->dim[d] ? m->dim[d] - 1 : (int64_t)t;
    }
    return (c[2] * m->dim[1] + c[1]) * m->dim[0] + c[0];
}

/* the number of subdivisions of triangle t for the spacing h */
static int64_t tri_divisions(const vc_surface *s, int64_t t, double h)
{
    const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                 *c = s->xyz + 3 * s->tri[3 * t + 2];
    double l = 0;
    for (int e = 0; e < 3; e++) {
        const double *p = e == 0 ? a : e == 1 ? b : c, *q = e == 0 ? b : e == 1 ? c : a;
        double d2 = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                    (q[2] - p[2]) * (q[2] - p[2]);
        l = fmax(l, sqrt(d2));
    }
    double k = ceil(l / h);
    return k < 1 ? 1 : (int64_t)k;
}

int vc_smooth_surface_init(vc_smooth_surface *m, const vc_sizing *z, double width)
{
    memset(m, 0, sizeof *m);
    m->z = z;
    m->width = width;
    m->cos_sharp = z->cos_sharp;
    const vc_surface *s = z->s;
    const int64_t nt = s->n_triangles;
    /* spacing: width / 5, coarser when that would make too many samples */
    double h = width / SAMPLES_PER_WIDTH;
    for (;;) {
        double total = 0;
        for (int64_t t = 0; t < nt; t++) {
            double k = (double)tri_divisions(s, t, h);
            total += k * k;
        }
        if (total <= MAX_SAMPLES)
            break;
        h *= 1.5;
    }
    int64_t *first = malloc(sizeof(int64_t) * (size_t)(nt + 1));
    if (!first)
        return -1;
    first[0] = 0;
    for (int64_t t = 0; t < nt; t++) {
        int64_t k = tri_divisions(s, t, h);
        first[t + 1] = first[t] + k * k;
    }
    const int64_t n = first[nt];
    double *pos = malloc(sizeof(double) * 3 * (size_t)(n ? n : 1));
    int64_t *owner = malloc(sizeof(int64_t) * (size_t)(n ? n : 1));
    if (!pos || !owner) {
        free(first);
        free(pos);
        free(owner);
        return -1;
    }
    /* the centroids of the k x k sub-triangles of every triangle */
    for (int64_t t = 0; t < nt; t++) {
        const int64_t k = tri_divisions(s, t, h);
        const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                     *c = s->xyz + 3 * s->tri[3 * t + 2];
        int64_t q = first[t];
        for (int64_t i = 0; i < k; i++)
            for (int64_t j = 0; i + j < k; j++)
                for (int up = 0; up < 2; up++) {
                    if (up && i + j + 1 >= k)
                        continue;
                    const double bu = ((double)i + (up ? 2.0 : 1.0) / 3) / (double)k;
                    const double bv = ((double)j + (up ? 2.0 : 1.0) / 3) / (double)k;
                    for (int d = 0; d < 3; d++)
                        pos[3 * q + d] = a[d] + bu * (b[d] - a[d]) + bv * (c[d] - a[d]);
                    owner[q++] = t;
                }
    }
    /* grid, then the samples in cell order */
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int d = 0; d < 3; d++)
        m->lo[d] = INFINITY;
    for (int64_t v = 0; v < s->n_vertices; v++)
        for (int d = 0; d < 3; d++) {
            m->lo[d] = fmin(m->lo[d], s->xyz[3 * v + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * v + d]);
        }
    /* cells of the kernel's width, coarser when that would make a grid far
     * larger than the samples (a query then visits more samples per cell) */
    for (int d = 0; d < 3; d++)
        m->lo[d] -= width;
    m->cell = 0.5 * width;
    for (;;) {
        double cells = 1;
        for (int d = 0; d < 3; d++) {
            double k = floor((hi[d] + width - m->lo[d]) / m->cell) + 1;
            m->dim[d] = (int64_t)k;
            cells *= k;
        }
        if (cells <= 4.0 * (double)n + 1e6)
            break;
        m->cell *= 1.5;
    }
    const int64_t nc = m->dim[0] * m->dim[1] * m->dim[2];
    m->cell_start = calloc((size_t)nc + 1, sizeof(int64_t));
    int64_t *cell_of = malloc(sizeof(int64_t) * (size_t)(n ? n : 1));
    int64_t *fill = malloc(sizeof(int64_t) * (size_t)(nc ? nc : 1));
    m->pos = malloc(sizeof(double) * 3 * (size_t)(n ? n : 1));
    m->nrm = malloc(sizeof(double) * 3 * (size_t)(n ? n : 1));
    m->weight = malloc(sizeof(double) * (size_t)(n ? n : 1));
    m->patch = malloc(sizeof(int64_t) * (size_t)(n ? n : 1));
    if (!m->cell_start || !cell_of || !fill || !m->pos || !m->nrm || !m->weight || !m->patch) {
        free(first);
        free(pos);
        free(owner);
        free(cell_of);
        free(fill);
        vc_smooth_surface_free(m);
        return -1;
    }
    m->n = n;
    for (int64_t q = 0; q < n; q++) {
        int64_t c[3];
        cell_of[q] = cell_index(m, pos + 3 * q, c);
        m->cell_start[cell_of[q] + 1]++;
    }
    for (int64_t c = 0; c < nc; c++)
        m->cell_start[c + 1] += m->cell_start[c];
    memcpy(fill, m->cell_start, sizeof(int64_t) * (size_t)nc);
    for (int64_t q = 0; q < n; q++) {
        const int64_t t = owner[q];
        const int64_t at = fill[cell_of[q]]++;
        const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                     *c = s->xyz + 3 * s->tri[3 * t + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2],
               w = u[0] * v[1] - u[1] * v[0];
        const double k = (double)(first[t + 1] - first[t]);
        memcpy(m->pos + 3 * at, pos + 3 * q, sizeof(double) * 3);
        memcpy(m->nrm + 3 * at, z->tri_out_normal + 3 * t, sizeof(double) * 3);
        m->weight[at] = 0.5 * sqrt(x * x + y * y + w * w) / k;
        m->patch[at] = z->f->tri_patch[t];
    }
    free(fill);
    free(first);
    free(pos);
    free(owner);
    free(cell_of);
    return 0;
}

void vc_smooth_surface_free(vc_smooth_surface *m)
{
    free(m->pos);
    free(m->nrm);
    free(m->weight);
    free(m->patch);
    free(m->cell_start);
    memset(m, 0, sizeof *m);
}

typedef struct fit {
    double u0, u[3], u4;
    int flat; /* every sample in the plane of the query triangle */
} fit;

/* The algebraic sphere at y (coordinates relative to y); returns -1 when no
 * sample counts. */
/* nref: the normal the samples' normals are weighed against (S's own at
 * the current estimate); ntri: the query triangle's, for the flatness test. */
static int fit_at(const vc_smooth_surface *m, const double y[3], const double nref[3],
                  const double ntri[3], int64_t patch, fit *F)
{
    const double W = m->width, W2 = W * W;
    double sw = 0, sp[3] = {0, 0, 0}, sn[3] = {0, 0, 0}, spn = 0, spp = 0;
    double off_plane = 0, off_normal = 0;
    int64_t lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
        double a = floor((y[d] - W - m->lo[d]) / m->cell), b = floor((y[d] + W - m->lo[d]) / m->cell);
        lo[d] = a < 0 ? 0 : (int64_t)a;
        hi[d] = b >= (double)m->dim[d] ? m->dim[d] - 1 : (int64_t)b;
    }
    for (int64_t cz = lo[2]; cz <= hi[2]; cz++)
        for (int64_t cy = lo[1]; cy <= hi[1]; cy++) {
            const int64_t row = (cz * m->dim[1] + cy) * m->dim[0];
            const int64_t from = m->cell_start[row + lo[0]], to = m->cell_start[row + hi[0] + 1];
            for (int64_t i = from; i < to; i++) {
                if (m->patch[i] != patch)
                    continue;
                const double *n = m->nrm + 3 * i;
                const double cn = n[0] * nref[0] + n[1] * nref[1] + n[2] * nref[2];
                if (cn <= -NORMAL_RAMP)
                    continue;
                const double q[3] = {m->pos[3 * i] - y[0], m->pos[3 * i + 1] - y[1],
                                     m->pos[3 * i + 2] - y[2]};
                const double d2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
                if (d2 >= W2)
                    continue;
                const double t = 1 - d2 / W2;
                /* samples facing away fade out smoothly (the other sheet of a
                 * thin part): the fit changes little from one triangle to
                 * the next */
                const double a = cn >= NORMAL_RAMP ? 1 : (cn + NORMAL_RAMP) / (2 * NORMAL_RAMP);
                const double w = m->weight[i] * t * t * t * a * a * (3 - 2 * a);
                const double qn = q[0] * n[0] + q[1] * n[1] + q[2] * n[2];
                sw += w;
                for (int d = 0; d < 3; d++) {
                    sp[d] += w * q[d];
                    sn[d] += w * n[d];
                }
                spn += w * qn;
                spp += w * d2;
                off_plane = fmax(off_plane, fabs(q[0] * ntri[0] + q[1] * ntri[1] + q[2] * ntri[2]));
                off_normal = fmax(off_normal,
                                  1 - (n[0] * ntri[0] + n[1] * ntri[1] + n[2] * ntri[2]));
            }
        }
    if (!(sw > 0))
        return -1;
    F->flat = off_plane <= 1e-12 * W && off_normal <= 1e-14;
    for (int d = 0; d < 3; d++) {
        sp[d] /= sw;
        sn[d] /= sw;
    }
    spn /= sw;
    spp /= sw;
    const double pp = sp[0] * sp[0] + sp[1] * sp[1] + sp[2] * sp[2];
    const double den = spp - pp;
    F->u4 = den > 1e-300 ? 0.5 * (spn - (sp[0] * sn[0] + sp[1] * sn[1] + sp[2] * sn[2])) / den : 0;
    for (int d = 0; d < 3; d++)
        F->u[d] = sn[d] - 2 * F->u4 * sp[d];
    F->u0 = -(F->u[0] * sp[0] + F->u[1] * sp[1] + F->u[2] * sp[2]) - F->u4 * spp;
    return 0;
}

/* The nearest point of the fitted sphere (or plane) to q (coordinates
 * relative to y, where the fit was made); its outward normal; the
 * sphere's radius. */
static int fit_project(const fit *F, const double W, const double q[3], double step[3],
                       double n[3], double *radius)
{
    const double lu = sqrt(F->u[0] * F->u[0] + F->u[1] * F->u[1] + F->u[2] * F->u[2]);
    if (!(lu > 0))
        return -1;
    if (2e6 * fabs(F->u4) * W <= lu) { /* a plane: radius beyond 1e6 widths */
        const double t = (F->u[0] * q[0] + F->u[1] * q[1] + F->u[2] * q[2] + F->u0) / lu;
        for (int d = 0; d < 3; d++) {
            n[d] = F->u[d] / lu;
            step[d] = q[d] - t * n[d];
        }
        *radius = INFINITY;
        return 0;
    }
    double c[3];
    for (int d = 0; d < 3; d++)
        c[d] = -F->u[d] / (2 * F->u4);
    const double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    const double r2 = cc - F->u0 / F->u4;
    const double qc[3] = {q[0] - c[0], q[1] - c[1], q[2] - c[2]};
    const double lqc = sqrt(qc[0] * qc[0] + qc[1] * qc[1] + qc[2] * qc[2]);
    if (!(r2 > 0) || !(lqc > 0))
        return -1;
    const double R = sqrt(r2);
    for (int d = 0; d < 3; d++)
        step[d] = c[d] + R * qc[d] / lqc;
    double g[3];
    for (int d = 0; d < 3; d++)
        g[d] = F->u[d] + 2 * F->u4 * step[d];
    const double lg = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    if (!(lg > 0))
        return -1;
    for (int d = 0; d < 3; d++)
        n[d] = g[d] / lg;
    *radius = R;
    return 0;
}

/* Onto S' from y: fit at y, move to the sphere's nearest point, until
 * still. Robust (each step lands on a fitted sphere through nearby
 * samples), but where it ends depends on where it starts. nw: the normal
 * the samples are weighed against, updated. Returns -1 when no sample is
 * within reach of the first fit. */
static int onto_surface(const vc_smooth_surface *m, int64_t tri, double y[3], double n[3],
                        double nw[3], double *radius)
{
    const double *nref = m->z->tri_out_normal + 3 * tri;
    const int64_t patch = m->z->f->tri_patch[tri];
    for (int it = 0; it < MAX_STEPS; it++) {
        fit F;
        if (fit_at(m, y, nw, nref, patch, &F))
            return it == 0 ? -1 : 0;
        double step[3], nn[3], R;
        const double zero[3] = {0, 0, 0};
        if (F.flat) { /* one plane around y: S' is the triangle's plane */
            const double *a = m->z->s->xyz + 3 * m->z->s->tri[3 * tri];
            const double h = (y[0] - a[0]) * nref[0] + (y[1] - a[1]) * nref[1] + (y[2] - a[2]) * nref[2];
            for (int d = 0; d < 3; d++) {
                y[d] -= h * nref[d];
                n[d] = nref[d];
            }
            *radius = INFINITY;
            return 0;
        }
        if (fit_project(&F, m->width, zero, step, nn, &R))
            return it == 0 ? -1 : 0;
        for (int d = 0; d < 3; d++)
            y[d] += step[d];
        memcpy(n, nn, sizeof nn);
        memcpy(nw, nn, sizeof nn);
        *radius = R;
        if (sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2]) <= 1e-7 * m->width)
            break;
    }
    return 0;
}

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* The orthogonal projection of x onto S', so that x has one image whichever
 * triangle it is seen from and wherever the search starts: the pools of
 * neighbouring triangles then cover S' without gaps between their images,
 * and the corners of a subface stay where they were when projected again.
 * First the fixed point y of "fit at y, then the nearest point to x of the
 * fitted sphere" from start (a guess near it), which takes 3 to 4 fits;
 * where that does not settle (x far from S' next to a tight bend), Gauss-
 * Newton steps along S' that shorten |x - y| every time. */
static int fixed_point(const vc_smooth_surface *m, int64_t tri, const double x[3],
                       const double start[3], double y[3], double n[3], double *radius)
{
    const double *nref = m->z->tri_out_normal + 3 * tri;
    const int64_t patch = m->z->f->tri_patch[tri];
    const double tol = 1e-7 * m->width;
    memcpy(y, start, sizeof(double) * 3);
    memcpy(n, nref, sizeof(double) * 3);
    *radius = INFINITY;
    /* The samples are weighed against S's normal at the current estimate,
     * not the triangle's: the fixed point is then a property of the point
     * alone, and S' does not jump from one triangle to the next where
     * samples turn away by about 90 degrees. */
    double nw[3] = {nref[0], nref[1], nref[2]};
    for (int it = 0; it < FAST_STEPS; it++) {
        fit F;
        if (fit_at(m, y, nw, nref, patch, &F))
            return it == 0 ? -1 : 0;
        if (F.flat) { /* the input is one plane around y: S' is the input */
            memcpy(y, x, sizeof(double) * 3);
            memcpy(n, nref, sizeof(double) * 3);
            *radius = INFINITY;
            return 0;
        }
        double target[3], nn[3], R;
        const double q[3] = {x[0] - y[0], x[1] - y[1], x[2] - y[2]};
        if (fit_project(&F, m->width, q, target, nn, &R))
            break;
        for (int d = 0; d < 3; d++)
            y[d] += target[d];
        memcpy(n, nn, sizeof nn);
        memcpy(nw, nn, sizeof nn);
        *radius = R;
        if (sqrt(target[0] * target[0] + target[1] * target[1] + target[2] * target[2]) <= tol)
            return 0;
    }
    /* not settled: onto S', then slide along it towards x */
    if (onto_surface(m, tri, y, n, nw, radius))
        return -1;
    double best = dist3(x, y);
    for (int it = 0; it < MAX_STEPS; it++) {
        double t[3];
        const double dn = (x[0] - y[0]) * n[0] + (x[1] - y[1]) * n[1] + (x[2] - y[2]) * n[2];
        for (int d = 0; d < 3; d++)
            t[d] = x[d] - y[d] - dn * n[d];
        if (sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) <= tol)
            break;
        int moved = 0;
        for (double lambda = 1; lambda >= 1.0 / 16 && !moved; lambda *= 0.5) {
            double y2[3], n2[3], nw2[3], R2;
            for (int d = 0; d < 3; d++) {
                y2[d] = y[d] + lambda * t[d];
                nw2[d] = n[d];
            }
            if (onto_surface(m, tri, y2, n2, nw2, &R2))
                continue;
            const double d2 = dist3(x, y2);
            if (d2 < best) {
                best = d2;
                memcpy(y, y2, sizeof y2);
                memcpy(n, n2, sizeof n2);
                *radius = R2;
                moved = 1;
            }
        }
        if (!moved)
            break;
    }
    return 0;
}

int vc_smooth_surface_project(const vc_smooth_surface *m, int64_t tri, const double x[3],
                              const double start[3], double y[3], double n[3], double *radius)
{
    double ys[3], ns[3];
    if (fixed_point(m, tri, x, start, ys, ns, radius)) {
        memcpy(y, x, sizeof(double) * 3);
        memcpy(n, m->z->tri_out_normal + 3 * tri, sizeof(double) * 3);
        *radius = INFINITY;
        return -1;
    }
    /* Next to a sharp feature (or another sheet) S' blends back into the
     * input, which the edge and corner balls cover: over one kernel width,
     * with a smoothstep of the distance to it. */
    const vc_surface_point sp = {VC_ELEM_TRIANGLE, tri};
    const double d = vc_sizing_conflict_distance(m->z, &sp, x, m->width);
    if (d >= m->width) {
        memcpy(y, ys, sizeof ys);
        memcpy(n, ns, sizeof ns);
        return 0;
    }
    const double t = d / m->width, phi = t * t * (3 - 2 * t);
    const double *nt = m->z->tri_out_normal + 3 * tri;
    double l = 0;
    for (int k = 0; k < 3; k++) {
        y[k] = x[k] + phi * (ys[k] - x[k]);
        n[k] = phi * ns[k] + (1 - phi) * nt[k];
        l += n[k] * n[k];
    }
    l = sqrt(l);
    for (int k = 0; k < 3; k++)
        n[k] /= l;
    return 1;
}

/* the normal of the fit at q (the gradient of its sphere there) */
static void fitted_normal(const vc_smooth_surface *m, const double q[3], const double *nref,
                          int64_t patch, double n[3])
{
    fit F;
    double l = 0;
    if (!fit_at(m, q, nref, nref, patch, &F) && !F.flat)
        l = sqrt(F.u[0] * F.u[0] + F.u[1] * F.u[1] + F.u[2] * F.u[2]);
    for (int d = 0; d < 3; d++)
        n[d] = l > 0 ? F.u[d] / l : nref[d];
}

int vc_smooth_surface_settle(const vc_smooth_surface *m, int64_t tri, const double x[3],
                             const double z[3], const double nz[3], double y[3], double n[3],
                             double *radius)
{
    const vc_surface_point sp = {VC_ELEM_TRIANGLE, tri};
    if (vc_sizing_conflict_distance(m->z, &sp, x, m->width) < m->width)
        return vc_smooth_surface_project(m, tri, x, z, y, n, radius);
    const double *nref = m->z->tri_out_normal + 3 * tri;
    /* the first fit weighs the samples against S's normal near z, as every
     * later one does: against the triangle's, it would lean the first step
     * aside where samples turn by about 90 degrees (a thin ear), and the
     * steps would settle elsewhere on S' */
    double nw[3] = {nz[0], nz[1], nz[2]};
    memcpy(y, z, sizeof(double) * 3);
    memcpy(n, nref, sizeof(double) * 3);
    *radius = INFINITY;
    if (onto_surface(m, tri, y, n, nw, radius))
        return vc_smooth_surface_project(m, tri, x, z, y, n, radius);
    return 0;
}

double vc_smooth_surface_max_curvature(const vc_smooth_surface *m, int64_t tri, const double y[3],
                                       const double n[3])
{
    const int64_t patch = m->z->f->tri_patch[tri];
    /* a tangent basis t[0], t[1] */
    double t[2][3];
    const int k = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2)
                                          : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
    double e[3] = {0, 0, 0};
    e[k] = 1;
    t[0][0] = n[1] * e[2] - n[2] * e[1];
    t[0][1] = n[2] * e[0] - n[0] * e[2];
    t[0][2] = n[0] * e[1] - n[1] * e[0];
    const double l = sqrt(t[0][0] * t[0][0] + t[0][1] * t[0][1] + t[0][2] * t[0][2]);
    for (int d = 0; d < 3; d++)
        t[0][d] /= l;
    t[1][0] = n[1] * t[0][2] - n[2] * t[0][1];
    t[1][1] = n[2] * t[0][0] - n[0] * t[0][2];
    t[1][2] = n[0] * t[0][1] - n[1] * t[0][0];
    const double h = 0.1 * m->width;
    double S[2][2];
    for (int j = 0; j < 2; j++) {
        double qp[3], qm[3], np[3], nm[3];
        for (int d = 0; d < 3; d++) {
            qp[d] = y[d] + h * t[j][d];
            qm[d] = y[d] - h * t[j][d];
        }
        fitted_normal(m, qp, n, patch, np);
        fitted_normal(m, qm, n, patch, nm);
        for (int i = 0; i < 2; i++)
            S[i][j] = ((np[0] - nm[0]) * t[i][0] + (np[1] - nm[1]) * t[i][1] +
                       (np[2] - nm[2]) * t[i][2]) / (2 * h);
    }
    const double mean = 0.5 * (S[0][0] + S[1][1]), b = 0.5 * (S[0][1] + S[1][0]);
    const double half = 0.5 * (S[0][0] - S[1][1]);
    return fabs(mean) + sqrt(half * half + b * b);
}
