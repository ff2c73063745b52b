/* Triangle measures: quality Q, angles, and the exact point-to-triangle
 * distance used by the Hausdorff distance. */
#include "vorocrust/quality.h"

#include <math.h>

#include "quality/vec3.h"
#include "quality/quality_internal.h"

double vc_triangle_quality(const double a[3], const double b[3], const double c[3])
{
    double ab[3], bc[3], ca[3], n[3];
    v3_sub(b, a, ab);
    v3_sub(c, b, bc);
    v3_sub(a, c, ca);
    double la = v3_norm(ab), lb = v3_norm(bc), lc = v3_norm(ca);
    double h = fmax(la, fmax(lb, lc));
    if (!(h > 0))
        return 0.0;
    v3_cross(ab, ca, n);
    double area = 0.5 * v3_norm(n);
    double half_perimeter = 0.5 * (la + lb + lc);
    return 6.0 * area / (sqrt(3.0) * h * half_perimeter);
}

void vc_triangle_angles(const double a[3], const double b[3], const double c[3],
                        double deg[3])
{
    const double *p[3] = {a, b, c};
    double e[3][3]; /* e[i] = p[i+1] - p[i] */
    for (int i = 0; i < 3; i++)
        v3_sub(p[(i + 1) % 3], p[i], e[i]);
    if (!(v3_dot(e[0], e[0]) > 0 && v3_dot(e[1], e[1]) > 0 && v3_dot(e[2], e[2]) > 0)) {
        deg[0] = deg[1] = deg[2] = 0.0;
        return;
    }
    for (int i = 0; i < 3; i++) {
        /* at p[i]: between p[i+1] - p[i] and p[i-1] - p[i] = -e[i-1] */
        double back[3] = {-e[(i + 2) % 3][0], -e[(i + 2) % 3][1], -e[(i + 2) % 3][2]};
        deg[i] = v3_angle(e[i], back) * VC_DEG;
    }
}

/* Squared distance from p to the segment [a, b] (a point when a = b). */
static double segment_dist2(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3];
    v3_sub(b, a, ab);
    v3_sub(p, a, ap);
    double len2 = v3_dot(ab, ab);
    double t = len2 > 0 ? v3_dot(ap, ab) / len2 : 0.0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double q[3] = {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
    return v3_dist2(p, q);
}

double vc_point_triangle_dist2(const double p[3], const double a[3], const double b[3],
                               const double c[3])
{
    double ab[3], ac[3], n[3];
    v3_sub(b, a, ab);
    v3_sub(c, a, ac);
    v3_cross(ab, ac, n);
    double n2 = v3_dot(n, n);
    if (n2 > 0) {
        /* The projection of p lies inside when p is on the inner side of
         * the three edge planes (the normal component cancels out). */
        const double *v[3] = {a, b, c};
        int inside = 1;
        for (int i = 0; i < 3 && inside; i++) {
            double e[3], vp[3], x[3];
            v3_sub(v[(i + 1) % 3], v[i], e);
            v3_sub(p, v[i], vp);
            v3_cross(e, vp, x);
            inside = v3_dot(x, n) >= 0;
        }
        if (inside) {
            double ap[3];
            v3_sub(p, a, ap);
            double h = v3_dot(ap, n);
            return h * h / n2;
        }
    }
    double d2 = segment_dist2(p, a, b);
    double e2 = segment_dist2(p, b, c);
    double f2 = segment_dist2(p, c, a);
    d2 = e2 < d2 ? e2 : d2;
    return f2 < d2 ? f2 : d2;
}

double vc_point_triangle_distance(const double p[3], const double a[3],
                                  const double b[3], const double c[3])
{
    return sqrt(vc_point_triangle_dist2(p, a, b, c));
}
