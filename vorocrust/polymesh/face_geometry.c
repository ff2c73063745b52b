/* Polygon face geometry (see face_geometry.h). */
#include "face_geometry.h"

void vc_polygon_geometry(const double *points, const int64_t *cycle, int64_t n,
                         const double *const *targets, double av[3], double cen[3])
{
    vc_face_area_centroid(points, cycle, n, targets, 1, av, cen);
}
