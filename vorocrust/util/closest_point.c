/* Closest point on a triangle by its Voronoi regions: the closest point is
 * a vertex, a point of an edge, or the projection into the interior,
 * decided from the barycentric signs of the projection. */
#include "util/closest_point.h"

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double dist2(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return dot3(d, d);
}

double vc_closest_on_segment(const double p[3], const double a[3], const double b[3], double q[3])
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double l2 = dot3(ab, ab);
    double t = l2 > 0 ? dot3(ap, ab) / l2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    double c[3] = {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
    if (q) {
        q[0] = c[0];
        q[1] = c[1];
        q[2] = c[2];
    }
    return dist2(p, c);
}

double vc_closest_on_triangle(const double p[3], const double a[3], const double b[3],
                              const double c[3], double q[3])
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    double r[3];
    if (d1 <= 0 && d2 <= 0) { /* vertex a */
        r[0] = a[0], r[1] = a[1], r[2] = a[2];
        goto done;
    }
    double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) { /* vertex b */
        r[0] = b[0], r[1] = b[1], r[2] = b[2];
        goto done;
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { /* edge ab */
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++)
            r[k] = a[k] + v * ab[k];
        goto done;
    }
    double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) { /* vertex c */
        r[0] = c[0], r[1] = c[1], r[2] = c[2];
        goto done;
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { /* edge ac */
        double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++)
            r[k] = a[k] + w * ac[k];
        goto done;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) { /* edge bc */
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++)
            r[k] = b[k] + w * (c[k] - b[k]);
        goto done;
    }
    {
        double den = va + vb + vc;
        if (!(den > 0)) { /* degenerate triangle: nearest of its edges */
            double qa[3], qb[3], qc[3];
            double da = vc_closest_on_segment(p, a, b, qa);
            double db = vc_closest_on_segment(p, b, c, qb);
            double dc = vc_closest_on_segment(p, a, c, qc);
            const double *best = qa;
            double bd = da;
            if (db < bd)
                best = qb, bd = db;
            if (dc < bd)
                best = qc, bd = dc;
            r[0] = best[0], r[1] = best[1], r[2] = best[2];
            goto done;
        }
        double v = vb / den, w = vc / den;
        for (int k = 0; k < 3; k++)
            r[k] = a[k] + ab[k] * v + ac[k] * w;
    }
done:
    if (q) {
        q[0] = r[0];
        q[1] = r[1];
        q[2] = r[2];
    }
    return dist2(p, r);
}
