/* A row of unit cubes for hand-built mesh tests: the block [0, n] x [0, 1]
 * x [0, 1] with corner (i, j, k) numbered i * 4 + j * 2 + k. */
#ifndef VC_TEST_CUBE_BLOCK_H
#define VC_TEST_CUBE_BLOCK_H

#include <stdint.h>

/* Corner (i, j, k) of the block. */
static inline int64_t block_corner(int i, int j, int k) { return i * 4 + j * 2 + k; }

/* The faces of the cube [x0, x0 + 1] x [0, 1] x [0, 1], outward:
 * f[0] x = x0, f[1] x = x0 + 1, f[2] y = 0, f[3] y = 1, f[4] z = 0,
 * f[5] z = 1. */
static inline void block_cube_faces(int x0, int64_t f[6][4])
{
    const int x1 = x0 + 1;
    const int64_t faces[6][4] = {
        {block_corner(x0, 0, 0), block_corner(x0, 0, 1), block_corner(x0, 1, 1), block_corner(x0, 1, 0)},
        {block_corner(x1, 0, 0), block_corner(x1, 1, 0), block_corner(x1, 1, 1), block_corner(x1, 0, 1)},
        {block_corner(x0, 0, 0), block_corner(x1, 0, 0), block_corner(x1, 0, 1), block_corner(x0, 0, 1)},
        {block_corner(x0, 1, 0), block_corner(x0, 1, 1), block_corner(x1, 1, 1), block_corner(x1, 1, 0)},
        {block_corner(x0, 0, 0), block_corner(x0, 1, 0), block_corner(x1, 1, 0), block_corner(x1, 0, 0)},
        {block_corner(x0, 0, 1), block_corner(x1, 0, 1), block_corner(x1, 1, 1), block_corner(x0, 1, 1)}};
    for (int a = 0; a < 6; a++)
        for (int b = 0; b < 4; b++)
            f[a][b] = faces[a][b];
}

#endif
