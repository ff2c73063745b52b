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
        goto out;
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
        goto out;
    }
    /* Multipliers: the reduced cost of artificial column m+i is -pi_i. */
    double pi[LP_ROWS];
    for (int i = 0; i < LP_ROWS; i++)
        pi[i] = -t.z[m + i];
    for (int d = 0; d < 3; d++)
        ball->center[d] = o[d] + s * pi[d];
    ball->radius = fmax(0.0, s * pi[3]);
out:
    free(t.a);
    free(t.z);
    free(plane);
    return rc;
}
