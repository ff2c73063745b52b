/* Polygon geometry and point merging shared by the mesh passes
 * (polymesh.c, skew_faces.c). Not part of the public API. */
#ifndef VORO_CRUST_POLYMESH_INTERNAL_H
#define VORO_CRUST_POLYMESH_INTERNAL_H

#include "vorocrust/polymesh.h"

/* Area vector and centroid of a polygon given as point indices, where an
 * entry -1 - t stands for targets[t] (may be NULL without such entries);
 * the formula of vc_polymesh_update_face_geometry and OpenFOAM. */
void vc_polygon_geometry(const double *points, const int64_t *cycle, int64_t n,
                         const double *const *targets, double av[3], double cen[3]);

/* Scratch for vc_polymesh_merge_points, sized for the mesh it is
 * initialised with (a merge only ever shrinks the mesh). */
typedef struct vc_point_merge_buffers {
    int64_t *new_face;           /* face -> its index after the merge, -1: removed */
    unsigned char *face_changed; /* by new index */
    unsigned char *cell_changed;
} vc_point_merge_buffers;

int vc_point_merge_buffers_init(vc_point_merge_buffers *b, const vc_polymesh *m);
void vc_point_merge_buffers_free(vc_point_merge_buffers *b);

/* Root of point v in the union-find parent[] (path halving). */
int64_t vc_point_root(int64_t *parent, int64_t v);

/* Rewrites every face through the union-find parent[] (each point becomes
 * its root, whose position the caller has set; NULL: every point is its
 * own), removes the repeated points this makes, drops the faces left with
 * fewer than three points and the faces f with drop[f] set (drop may be
 * NULL) from the face arrays, in order, and from their cells' lists, and
 * recomputes the geometry of the faces with a point in moved[] (NULL:
 * none) and of their cells and of the cells of dropped faces.
 * b->new_face then maps old face indices to new ones. */
void vc_polymesh_merge_points(vc_polymesh *m, int64_t *parent, const unsigned char *moved,
                              const unsigned char *drop, vc_point_merge_buffers *b);

/* Drops the points no face uses, renumbering the rest in order. Returns 0,
 * or -1 when out of memory (the mesh is then unchanged). */
int vc_polymesh_drop_unused_points(vc_polymesh *m);

#endif
