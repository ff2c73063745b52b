/* Byte-for-byte comparison of two meshes, for the tests that check that
 * the thread count does not change the output. */
#ifndef VC_TEST_POLYMESH_COMPARE_H
#define VC_TEST_POLYMESH_COMPARE_H

#include <stdint.h>
#include <string.h>

#include "vorocrust/polymesh.h"

/* The same points, faces (cycles and owners) and cells, bit for bit. */
static int same_mesh(const vc_polymesh *a, const vc_polymesh *b)
{
    if (a->n_points != b->n_points || a->n_faces != b->n_faces || a->n_cells != b->n_cells ||
        a->n_interior_faces != b->n_interior_faces)
        return 0;
    return !memcmp(a->points, b->points, (size_t)a->n_points * 3 * sizeof(double)) &&
           !memcmp(a->face_offsets, b->face_offsets, (size_t)(a->n_faces + 1) * sizeof(int64_t)) &&
           !memcmp(a->face_vertices, b->face_vertices,
                   (size_t)a->face_offsets[a->n_faces] * sizeof(int64_t)) &&
           !memcmp(a->face_owner, b->face_owner, (size_t)a->n_faces * sizeof(int64_t)) &&
           !memcmp(a->cell_offsets, b->cell_offsets, (size_t)(a->n_cells + 1) * sizeof(int64_t)) &&
           !memcmp(a->cell_faces, b->cell_faces,
                   (size_t)a->cell_offsets[a->n_cells] * sizeof(int64_t));
}

#endif
