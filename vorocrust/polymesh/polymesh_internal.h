/* Polygon geometry and point merging shared by the mesh passes
 * (polymesh.c, skew_faces.c). Not part of the public API. */
#ifndef VORO_CRUST_POLYMESH_INTERNAL_H
#define VORO_CRUST_POLYMESH_INTERNAL_H

#include "face_geometry.h"
#include "util/union_find.h"
#include "vorocrust/polymesh.h"

/* Scratch for vc_polymesh_merge_points, sized for the mesh it is
 * initialised with (a merge only ever shrinks the mesh). */
typedef struct vc_point_merge_buffers {
    int64_t *new_face;           /* face -> its index after the merge, -1: removed */
    unsigned char *face_changed; /* by new index */
    unsigned char *cell_changed;
} vc_point_merge_buffers;

int vc_point_merge_buffers_init(vc_point_merge_buffers *b, const vc_polymesh *m);
void vc_point_merge_buffers_free(vc_point_merge_buffers *b);

/* Rewrites every face through the union-find parent[] (util/union_find.h:
 * each point becomes its root, whose position the caller has set; NULL:
 * every point is its own), removes the repeated points this makes, drops
 * the faces left with fewer than three points and the faces f with
 * drop[f] set (drop may be NULL) from the face arrays, in order, and from
 * their cells' lists, and recomputes the geometry of the faces with a
 * point in moved[] (NULL: none) and of their cells and of the cells of
 * dropped faces. b->new_face then maps old face indices to new ones. */
void vc_polymesh_merge_points(vc_polymesh *m, int64_t *parent, const unsigned char *moved,
                              const unsigned char *drop, vc_point_merge_buffers *b);

/* Drops the points no face uses, renumbering the rest in order. Returns 0,
 * or -1 when out of memory (the mesh is then unchanged). */
int vc_polymesh_drop_unused_points(vc_polymesh *m);

#endif
