/* A smooth surface S' near the input, for the ball centres (issue 16,
 * docs/sampling-convergence.md).
 *
 * Sliver elimination terminates only when the centres lie on a surface
 * that is smooth at the scale of the balls, to about 1% of their radius:
 * a fold between flat triangles is a kink at every scale. S' is the
 * moving-least-squares surface of algebraic spheres (APSS) fitted to
 * area-weighted samples of the input triangles with their normals, with
 * a compactly supported C2 kernel of radius `width`. Where the input is
 * flat over the kernel's reach S' is the input itself; elsewhere it rounds
 * the folds, within a fraction of the width. Only samples of the same
 * patch whose normals are within theta_sharp of the query triangle's
 * normal count: S' never smooths across a sharp edge, nor reaches the
 * other sheet of a thin part. */
#ifndef VC_SIZING_SMOOTH_SURFACE_H
#define VC_SIZING_SMOOTH_SURFACE_H

#include <stdint.h>
#include "sizing/sizing.h"

typedef struct vc_smooth_surface {
    const vc_sizing *z;
    double width;
    double cos_sharp;
    /* samples, sorted by grid cell */
    int64_t n;
    double *pos;      /* 3 per sample */
    double *nrm;      /* 3 per sample: the outward normal of its triangle */
    double *weight;   /* its share of the triangle's area */
    int64_t *patch;
    /* uniform grid: cells of size `cell` (at least width) */
    double lo[3], cell;
    int64_t dim[3];
    int64_t *cell_start; /* dim[0] dim[1] dim[2] + 1 */
} vc_smooth_surface;

/* width: the kernel radius (absolute). Returns -1 when out of memory. */
int vc_smooth_surface_init(vc_smooth_surface *m, const vc_sizing *z, double width);
void vc_smooth_surface_free(vc_smooth_surface *m);

/* The point of S' for the point x of triangle tri: the fixed point of the
 * fit and projection steps from start (x, or a guess close to S', which
 * takes fewer steps), blended back into x within one kernel width of a
 * sharp feature (or of another sheet) by a smoothstep of the distance
 * to it. Also its outward unit normal n and the radius of curvature of
 * the fitted sphere (INFINITY where S' is flat). Returns 0, 1 when the
 * point is in that blend, or -1 when no sample is within reach (y = x, n
 * the triangle's normal). */
int vc_smooth_surface_project(const vc_smooth_surface *m, int64_t tri, const double x[3],
                              const double start[3], double y[3], double n[3], double *radius);

/* The point of S' nearest to z, a point close to S' (within the sag of an
 * interpolated subface) that stands for the point x of triangle tri: S'
 * along its normal from z, so that z's neighbourhood and its image agree
 * (the orthogonal projection of x lands aside, by as much as the
 * interpolation drifted along S'); nz: S's normal near z. Within one kernel width of a sharp
 * feature, where S' blends into the input, vc_smooth_surface_project. */
int vc_smooth_surface_settle(const vc_smooth_surface *m, int64_t tri, const double x[3],
                             const double z[3], const double nz[3], double y[3], double n[3],
                             double *radius);

/* The largest absolute principal curvature of S' at its point y (normal n)
 * near triangle tri: the shape operator from the change of the fitted
 * normal over a tenth of the width along two tangent directions. The
 * fitted sphere's own curvature is a mean curvature: it misses saddles and
 * cylinders, where four co-circular centres are not co-planar. 0 where S'
 * is flat. */
double vc_smooth_surface_max_curvature(const vc_smooth_surface *m, int64_t tri, const double y[3],
                                       const double n[3]);

#endif
