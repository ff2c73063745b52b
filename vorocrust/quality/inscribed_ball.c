/* Maximum inscribed ball of a convex cell by linear programming.
 *
 * Primal: maximise r over (x, r) subject to n_f . x + r <= d_f for every
 * face f (n_f unit outward normal, d_f = n_f . point of f).
 * We solve its dual, which is in standard form with only 4 rows:
 *   minimise sum_f d_f y_f  subject to  sum_f y_f n_f = 0,  sum_f y_f = 1,
 *   y >= 0,
 * with a dense two-phase tableau simplex and Bland's rule (smallest index
 * enters, ties in the ratio test to the smallest basic index): the pivots
 * are deterministic and the method terminates on the heavily degenerate
 * problems Voronoi cells give (right-hand side mostly zero). The primal
 * optimum is the vector of simplex multipliers, read off the reduced costs
 * of the artificial columns. The problem is solved in coordinates centred
 * on the vertex average and scaled to unit size, so tolerances are
 * relative. */
#include "vorocrust/quality.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "quality/quality_internal.h"
#include "quality/vec3.h"

#define LP_ROWS 4
#define LP_EPS 1e-11

typedef struct lp_tableau {
    int m;          /* face columns; artificial columns are m .. m+3 */
    int ncol;       /* m + 4 */
    double *a;      /* LP_ROWS x (ncol + 1): the last column is the rhs */
    double *z;      /* ncol + 1 reduced costs; z[ncol] = -objective */
    int basis[LP_ROWS];
} lp_tableau;

static inline double *lp_row(lp_tableau *t, int i)
{
    return t->a + (size_t)i * (size_t)(t->ncol + 1);
}

static void lp_pivot(lp_tableau *t, int r, int c)
{
    double *pr = lp_row(t, r);
    double inv = 1.0 / pr[c];
    for (int j = 0; j <= t->ncol; j++)
        pr[j] *= inv;
    pr[c] = 1.0;
    for (int i = 0; i < LP_ROWS; i++) {
        if (i == r)
            continue;
        double *pi = lp_row(t, i);
        double f = pi[c];
        if (f != 0) {
            for (int j = 0; j <= t->ncol; j++)
                pi[j] -= f * pr[j];
            pi[c] = 0.0;
        }
    }
    double f = t->z[c];
    if (f != 0) {
        for (int j = 0; j <= t->ncol; j++)
            t->z[j] -= f * pr[j];
        t->z[c] = 0.0;
    }
    t->basis[r] = c;
}

/* Runs the simplex on the current reduced costs; columns >= allowed never
 * enter. Returns 0 at the optimum, 1 if unbounded, 2 if out of pivots. */
static int lp_run(lp_tableau *t, int allowed)
{
    int max_pivots = 50 * (t->ncol + 10);
    for (int it = 0; it < max_pivots; it++) {
        int enter = -1;
        for (int j = 0; j < allowed; j++)
            if (t->z[j] < -LP_EPS) {
                enter = j;
                break;
            }
        if (enter < 0)
            return 0;
        int leave = -1;
        double best = INFINITY;
        for (int i = 0; i < LP_ROWS; i++) {
            double *pi = lp_row(t, i);
            if (pi[enter] > LP_EPS) {
                double ratio = fmax(pi[t->ncol], 0.0) / pi[enter]; /* rounding can leave -1e-17 */
                if (ratio < best - 1e-15 ||
                    (ratio <= best + 1e-15 && leave >= 0 && t->basis[i] < t->basis[leave])) {
                    if (ratio < best)
                        best = ratio;
                    leave = i;
                }
            }
        }
        if (leave < 0)
            return 1;
        lp_pivot(t, leave, enter);
    }
    return 2;
}

/* The primal by enumeration, when the simplex fails: the optimum is a
 * vertex of the region n_f . x + r <= d_f in (x, r), where four of the
 * constraints are tight; every four are solved (Gaussian elimination with
 * partial pivoting) and the feasible solution of largest r kept. O(m^4 m)
 * work, so only for cells of few faces, and only as the fallback: the
 * tableau's pivots on nearly degenerate cells (faces 1e-3 of the cell's
 * area beside large ones) can lose the feasibility the closed cell has
 * (a gyroid lattice's cell: phase 1 stopped at 4e-6 above zero). */
#define ENUM_MAX_FACES 48
static int inscribed_by_enumeration(const double *plane, int m, double *best_x, double *best_r)
{
    *best_r = -INFINITY;
    for (int a = 0; a < m; a++)
        for (int b = a + 1; b < m; b++)
            for (int c = b + 1; c < m; c++)
                for (int e = c + 1; e < m; e++) {
                    const int row[4] = {a, b, c, e};
                    double M[4][5];
                    for (int i = 0; i < 4; i++) {
                        for (int d = 0; d < 3; d++)
                            M[i][d] = plane[4 * row[i] + d];
                        M[i][3] = 1.0;
                        M[i][4] = plane[4 * row[i] + 3];
                    }
                    int singular = 0;
                    for (int k = 0; k < 4 && !singular; k++) {
                        int piv = k;
                        for (int i = k + 1; i < 4; i++)
                            if (fabs(M[i][k]) > fabs(M[piv][k]))
                                piv = i;
                        if (!(fabs(M[piv][k]) > 1e-12)) {
                            singular = 1;
                            break;
                        }
                        if (piv != k)
                            for (int j = 0; j < 5; j++) {
                                const double tmp = M[k][j];
                                M[k][j] = M[piv][j];
                                M[piv][j] = tmp;
                            }
                        for (int i = k + 1; i < 4; i++) {
                            const double f = M[i][k] / M[k][k];
                            for (int j = k; j < 5; j++)
                                M[i][j] -= f * M[k][j];
                        }
                    }
                    if (singular)
                        continue;
                    double y[4];
                    for (int k = 3; k >= 0; k--) {
                        double v = M[k][4];
                        for (int j = k + 1; j < 4; j++)
                            v -= M[k][j] * y[j];
                        y[k] = v / M[k][k];
                    }
                    if (!(y[3] > *best_r))
                        continue;
                    int feasible = 1;
                    for (int j = 0; j < m && feasible; j++)
                        feasible = plane[4 * j] * y[0] + plane[4 * j + 1] * y[1] +
                                       plane[4 * j + 2] * y[2] + y[3] <=
                                   plane[4 * j + 3] + 1e-12;
                    if (feasible) {
                        memcpy(best_x, y, 3 * sizeof(double));
                        *best_r = y[3];
                    }
                }
    return *best_r > -INFINITY ? 0 : -1;
}

int vc_max_inscribed_ball(const vc_cell *cell, vc_ball *ball)
{
    return vc_max_inscribed_ball_oriented(cell, vc_cell_volume(cell, NULL) < 0 ? -1.0 : 1.0, ball);
}

int vc_max_inscribed_ball_oriented(const vc_cell *cell, double orient, vc_ball *ball)
{
    const double *P = cell->points;
    int64_t nf = cell->n_faces;
    ball->center[0] = ball->center[1] = ball->center[2] = 0;
    ball->radius = 0;
    if (nf < 4)
        return VC_EINPUT;

    /* Origin and scale: the average of the face vertices, and the largest
     * distance from it. */
    double o[3] = {0, 0, 0};
    int64_t cnt = 0;
    for (int64_t k = cell->face_offsets[0]; k < cell->face_offsets[nf]; k++, cnt++)
        for (int d = 0; d < 3; d++)
            o[d] += P[3 * cell->face_vertices[k] + d];
    if (cnt == 0)
        return VC_EINPUT;
    for (int d = 0; d < 3; d++)
        o[d] /= (double)cnt;
    double s = 0;
    for (int64_t k = cell->face_offsets[0]; k < cell->face_offsets[nf]; k++)
        s = dmax(s, v3_dist2(P + 3 * cell->face_vertices[k], o));
    s = sqrt(s);
    if (!(s > 0) || !isfinite(s))
        return VC_EINPUT;

    /* Face planes in the scaled frame (Newell normals: exact for planar
     * faces, a best fit for slightly warped ones). */
    double *plane = malloc(sizeof *plane * 4 * (size_t)nf);
    if (!plane)
        return VC_ENOMEM;
    int m = 0;
    double area_sum[3] = {0, 0, 0}, area_total = 0; /* of the faces' area vectors */
    for (int64_t f = 0; f < nf; f++) {
        int64_t b = cell->face_offsets[f], e = cell->face_offsets[f + 1];
        double nrm[3] = {0, 0, 0}, c[3] = {0, 0, 0};
        for (int64_t k = b; k < e; k++) {
            const double *p = P + 3 * cell->face_vertices[k];
            const double *q = P + 3 * cell->face_vertices[k + 1 < e ? k + 1 : b];
            double ps[3] = {(p[0] - o[0]) / s, (p[1] - o[1]) / s, (p[2] - o[2]) / s};
            double qs[3] = {(q[0] - o[0]) / s, (q[1] - o[1]) / s, (q[2] - o[2]) / s};
            nrm[0] += (ps[1] - qs[1]) * (ps[2] + qs[2]);
            nrm[1] += (ps[2] - qs[2]) * (ps[0] + qs[0]);
            nrm[2] += (ps[0] - qs[0]) * (ps[1] + qs[1]);
            for (int d = 0; d < 3; d++)
                c[d] += ps[d];
        }
        double len = v3_norm(nrm);
        for (int d = 0; d < 3; d++)
            area_sum[d] += nrm[d];
        area_total += len;
        if (!(len > 1e-14) || e - b < 3)
            continue; /* zero-area face: no constraint */
        for (int d = 0; d < 3; d++)
            plane[4 * m + d] = orient * nrm[d] / len;
        plane[4 * m + 3] = v3_dot(plane + 4 * m, c) / (double)(e - b);
        m++;
    }
    if (m < 4) {
        free(plane);
        return VC_EINPUT;
    }

    lp_tableau t;
    t.m = m;
    t.ncol = m + LP_ROWS;
    t.a = calloc((size_t)LP_ROWS * (size_t)(t.ncol + 1), sizeof *t.a);
    t.z = calloc((size_t)(t.ncol + 1), sizeof *t.z);
    if (!t.a || !t.z) {
        free(t.a);
        free(t.z);
        free(plane);
        return VC_ENOMEM;
    }
    for (int j = 0; j < m; j++) {
        for (int d = 0; d < 3; d++)
            lp_row(&t, d)[j] = plane[4 * j + d];
        lp_row(&t, 3)[j] = 1.0;
    }
    for (int i = 0; i < LP_ROWS; i++) {
        lp_row(&t, i)[m + i] = 1.0;
        t.basis[i] = m + i;
    }
    lp_row(&t, 3)[t.ncol] = 1.0;

    /* Phase 1: minimise the sum of the artificials. */
    for (int j = 0; j <= t.ncol; j++) {
        double sum = 0;
        for (int i = 0; i < LP_ROWS; i++)
            sum += lp_row(&t, i)[j];
        t.z[j] = (j >= m && j < t.ncol) ? 0.0 : -sum;
    }
    int rc = VC_OK;
    if (lp_run(&t, m) != 0 || -t.z[t.ncol] > 1e-9) {
        rc = VC_EINPUT; /* 0 is not a positive mix of the normals: the cell is open */
        goto fallback;
    }
    /* Pivot the artificials still basic (at zero) out where possible. */
    for (int i = 0; i < LP_ROWS; i++) {
        if (t.basis[i] < m)
            continue;
        double *pi = lp_row(&t, i);
        int best = -1;
        for (int j = 0; j < m; j++)
            if (fabs(pi[j]) > 1e-9 && (best < 0 || fabs(pi[j]) > fabs(pi[best])))
                best = j;
        if (best >= 0)
            lp_pivot(&t, i, best);
    }

    /* Phase 2: the real costs d_f; artificials stay out. */
    for (int j = 0; j <= t.ncol; j++)
        t.z[j] = j < m ? plane[4 * j + 3] : 0.0;
    for (int i = 0; i < LP_ROWS; i++) {
        int bcol = t.basis[i];
        double cb = t.z[bcol];
        if (cb != 0) {
            double *pi = lp_row(&t, i);
            for (int j = 0; j <= t.ncol; j++)
                t.z[j] -= cb * pi[j];
        }
    }
    if (lp_run(&t, m) != 0) {
        rc = VC_EINTERNAL;
        goto fallback;
    }
    /* Multipliers: the reduced cost of artificial column m+i is -pi_i. */
    double pi[LP_ROWS];
    for (int i = 0; i < LP_ROWS; i++)
        pi[i] = -t.z[m + i];
    for (int d = 0; d < 3; d++)
        ball->center[d] = o[d] + s * pi[d];
    ball->radius = fmax(0.0, s * pi[3]);
    goto out;
fallback:
    /* a closed cell (its faces' area vectors sum to zero) has a bounded
     * optimum, which the enumeration finds; an open one is left an error */
    if (m <= ENUM_MAX_FACES && v3_norm(area_sum) <= 1e-9 * area_total) {
        double x[3], r;
        if (inscribed_by_enumeration(plane, m, x, &r) == 0 && r > 0) {
            for (int d = 0; d < 3; d++)
                ball->center[d] = o[d] + s * x[d];
            ball->radius = s * r;
            rc = VC_OK;
        }
    }
out:
    free(t.a);
    free(t.z);
    free(plane);
    return rc;
}
