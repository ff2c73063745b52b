/* The geometry of a polygon face: area vector, area, area-weighted
 * centroid and unit normal, from a fan around the vertex average (exact
 * for planar polygons; OpenFOAM's formula). One formula for every face of
 * the library: the mesh passes (polymesh.c, skew_faces.c) and the Voronoi
 * stitching (voronoi/conforming_assembly.c). Not part of the public API.
 *
 * The arithmetic and its order are those of the two copies this replaces
 * (the stitching's and vc_polymesh_update_face_geometry's), so the values
 * are the same to the bit. Inline, so that the stitching's pass over every
 * face is as fast as its own copy was; vc_polygon_geometry
 * (face_geometry.c) is the out-of-line entry with substitute points. */
#ifndef VC_POLYMESH_FACE_GEOMETRY_H
#define VC_POLYMESH_FACE_GEOMETRY_H

#include "vorocrust/polymesh.h"

#include <math.h>
#include <stdint.h>

/* The sums of the fan over the polygon cycle[0..n-1] of points (xyz
 * triples): its vertex average c0, its area vector a (normal times area),
 * and the area-weighted sum c of its triangles' centroids with the total
 * weight wsum (the centroid is c / wsum when wsum > 0, else c0). With
 * subst set, an entry -1 - t stands for the point targets[t]; without,
 * every entry is a point index (a constant 0 removes the test from the
 * inlined code). */
static inline void vc_face_fan_sums(const double *points, const int64_t *cycle, int64_t n,
                                    const double *const *targets, int subst, double c0[3],
                                    double a[3], double c[3], double *wsum)
{
#define VC_FACE_POINT(i)                                                                          \
    (subst && cycle[i] < 0 ? targets[-1 - cycle[i]] : points + 3 * cycle[i])
    for (int d = 0; d < 3; d++)
        c0[d] = 0;
    /* points[3 * k + d] rather than VC_FACE_POINT: the stitching's code
     * shape (one address computation fewer per vertex). */
    for (int64_t i = 0; i < n; i++)
        for (int d = 0; d < 3; d++)
            c0[d] += subst && cycle[i] < 0 ? targets[-1 - cycle[i]][d] : points[3 * cycle[i] + d];
    for (int d = 0; d < 3; d++)
        c0[d] /= (double)n;
    double w_sum = 0;
    for (int d = 0; d < 3; d++)
        a[d] = c[d] = 0;
    for (int64_t i = 0; i < n; i++) {
        const double *p = VC_FACE_POINT(i), *q = VC_FACE_POINT(i + 1 < n ? i + 1 : 0);
        double u[3] = {p[0] - c0[0], p[1] - c0[1], p[2] - c0[2]};
        double v[3] = {q[0] - c0[0], q[1] - c0[1], q[2] - c0[2]};
        double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        /* Twice the triangles' areas and three times their centroids:
         * the factors are applied once, after the sums. */
        for (int d = 0; d < 3; d++)
            a[d] += x[d];
        double w = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        for (int d = 0; d < 3; d++)
            c[d] += w * (c0[d] + p[d] + q[d]);
        w_sum += w;
    }
#undef VC_FACE_POINT
    for (int d = 0; d < 3; d++)
        a[d] *= 0.5;
    *wsum = w_sum * 3.0;
}

/* Area vector (normal times area) and centroid of the polygon
 * cycle[0..n-1] (subst, targets: as vc_face_fan_sums). */
static inline void vc_face_area_centroid(const double *points, const int64_t *cycle, int64_t n,
                                         const double *const *targets, int subst, double av[3],
                                         double cen[3])
{
    double c0[3], c[3], wsum;
    vc_face_fan_sums(points, cycle, n, targets, subst, c0, av, c, &wsum);
    for (int d = 0; d < 3; d++)
        cen[d] = wsum > 0 ? c[d] / wsum : c0[d];
}

/* Sets face_area[f], face_centroid[f] and face_normal[f] of m for face f,
 * whose n point indices are fv. */
static inline void vc_face_geometry_set(vc_polymesh *m, int64_t f, const int64_t *fv, int64_t n)
{
    double c0[3], a[3], c[3], wsum;
    vc_face_fan_sums(m->points, fv, n, NULL, 0, c0, a, c, &wsum);
    double area = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    m->face_area[f] = area;
    for (int d = 0; d < 3; d++) {
        m->face_centroid[3 * f + d] = wsum > 0 ? c[d] / wsum : c0[d];
        m->face_normal[3 * f + d] = area > 0 ? a[d] / area : 0;
    }
}

/* vc_face_area_centroid with substitute points: an entry -1 - t of cycle
 * stands for targets[t] (targets may be NULL without such entries). */
void vc_polygon_geometry(const double *points, const int64_t *cycle, int64_t n,
                         const double *const *targets, double av[3], double cen[3]);

#endif
