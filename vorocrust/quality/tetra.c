/* Tetrahedra: as cells, and their dihedral angles. */
#include "vorocrust/quality.h"

#include <math.h>
#include <string.h>

#include "quality/vec3.h"

void vc_tetra_cell(const double p[4][3], double points[12], int64_t ids[4],
                   int64_t face_offsets[5], int64_t face_vertices[12], vc_cell *cell)
{
    /* Outward for a positively oriented tetrahedron ((p1-p0) x (p2-p0) .
     * (p3-p0) > 0): each face is the opposite vertex's, seen from outside. */
    static const int outward[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    double u[3], v[3], w[3], x[3];
    v3_sub(p[1], p[0], u);
    v3_sub(p[2], p[0], v);
    v3_sub(p[3], p[0], w);
    v3_cross(u, v, x);
    int flip = v3_dot(x, w) < 0;
    for (int i = 0; i < 4; i++) {
        memcpy(points + 3 * i, p[i], 3 * sizeof(double));
        ids[i] = i;
        face_offsets[i] = 3 * i;
        for (int k = 0; k < 3; k++)
            face_vertices[3 * i + k] = outward[i][flip ? 2 - k : k];
    }
    face_offsets[4] = 12;
    cell->points = points;
    cell->n_vertices = 4;
    cell->vertices = ids;
    cell->n_faces = 4;
    cell->face_offsets = face_offsets;
    cell->face_vertices = face_vertices;
}

void vc_tetra_dihedral_angles(const double p[4][3], double deg[6], double *min, double *max)
{
    static const int edge[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                   {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 6; k++) {
        const int *ed = edge[k];
        /* e x (p_k - p_i) and e x (p_l - p_i) are the parts of the two other
         * vertices perpendicular to the edge e, turned by 90 degrees: the
         * angle between them is the dihedral angle at e. */
        double e[3], a[3], b[3], u[3], v[3];
        v3_sub(p[ed[1]], p[ed[0]], e);
        v3_sub(p[ed[2]], p[ed[0]], a);
        v3_sub(p[ed[3]], p[ed[0]], b);
        v3_cross(e, a, u);
        v3_cross(e, b, v);
        double ang = v3_angle(u, v) * VC_DEG;
        deg[k] = ang;
        lo = fmin(lo, ang);
        hi = fmax(hi, ang);
    }
    if (min)
        *min = lo;
    if (max)
        *max = hi;
}
