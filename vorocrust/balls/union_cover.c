/* The union-of-balls test of a segment or triangle (see union_cover.h). */
#include "balls/union_cover.h"

/* Relative shrink of the radii (see union_cover.h). */
#define SHRINK 1e-9

/* Keeps the part of the polygon (or, when closed is 0, the segment) p[0 ..
 * n) where 2 y.d <= rhs, into q; returns its corner count (0: nothing
 * left). */
static int clip(const double (*p)[3], int n, int closed, const double d[3], double rhs,
                double (*q)[3])
{
    double s[VC_UNION_COVER_MAX + 3];
    int n_out = 0;
    for (int m = 0; m < n; m++) {
        s[m] = 2 * (p[m][0] * d[0] + p[m][1] * d[1] + p[m][2] * d[2]) - rhs;
        n_out += s[m] > 0;
    }
    if (n_out == 0) {
        for (int m = 0; m < n; m++)
            for (int e = 0; e < 3; e++)
                q[m][e] = p[m][e];
        return n;
    }
    if (n_out == n)
        return 0;
    int w = 0;
    const int n_edges = closed ? n : n - 1;
    for (int m = 0; m < n; m++) {
        if (s[m] <= 0) {
            for (int e = 0; e < 3; e++)
                q[w][e] = p[m][e];
            w++;
        }
        if (m >= n_edges)
            continue;
        const int o = m + 1 < n ? m + 1 : 0;
        if ((s[m] > 0) != (s[o] > 0)) {
            /* where the edge crosses the plane, from its inner end */
            const int a = s[m] <= 0 ? m : o, b = a == m ? o : m;
            const double t = s[a] / (s[a] - s[b]);
            for (int e = 0; e < 3; e++)
                q[w][e] = p[a][e] + t * (p[b][e] - p[a][e]);
            w++;
        }
    }
    return w;
}

int vc_union_covers(const double *v, int nv, const double *c, const double *r, int k)
{
    if (k <= 0 || k > VC_UNION_COVER_MAX || nv < 2 || nv > 3)
        return 0;
    /* A corner in no ball: not covered, without the k (k - 1) clippings
     * (most pieces that fail, fail at a corner: a dart's gap reaches the
     * piece's edge). The same answer as the clipping below, which would
     * find that corner outside the ball of its power cell. */
    for (int m = 0; m < nv; m++) {
        int held = 0;
        for (int i = 0; i < k && !held; i++) {
            const double ri = r[i] * (1 - SHRINK);
            const double dx = v[3 * m] - c[3 * i], dy = v[3 * m + 1] - c[3 * i + 1],
                         dz = v[3 * m + 2] - c[3 * i + 2];
            held = dx * dx + dy * dy + dz * dz <= ri * ri;
        }
        if (!held)
            return 0;
    }
    /* A triangle clipped by k - 1 planes has at most 3 + k - 1 corners. */
    double buf[2][VC_UNION_COVER_MAX + 3][3];
    for (int i = 0; i < k; i++) {
        const double *ci = c + 3 * i;
        int n = nv, cur = 0;
        /* in coordinates relative to the centre: values of the radius'
         * size, not of the model's position */
        for (int m = 0; m < nv; m++)
            for (int e = 0; e < 3; e++)
                buf[0][m][e] = v[3 * m + e] - ci[e];
        for (int j = 0; j < k && n > 0; j++) {
            if (j == i)
                continue;
            /* the power cell of i against j: |y|^2 - ri^2 <= |y - d|^2 -
             * rj^2, that is 2 y.d <= |d|^2 + ri^2 - rj^2 */
            const double d[3] = {c[3 * j] - ci[0], c[3 * j + 1] - ci[1], c[3 * j + 2] - ci[2]};
            const double rhs = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + r[i] * r[i] - r[j] * r[j];
            n = clip((const double(*)[3])buf[cur], n, nv == 3, d, rhs, buf[1 - cur]);
            cur = 1 - cur;
        }
        const double ri = r[i] * (1 - SHRINK), r2 = ri * ri;
        for (int m = 0; m < n; m++) {
            const double *y = buf[cur][m];
            if (!(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] <= r2))
                return 0; /* a point of the piece nearest (in power) to i, outside i */
        }
    }
    return 1;
}
