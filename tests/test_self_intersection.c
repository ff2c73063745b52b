/* The triangle-pair test of the input checks (surface/self_intersection.c)
 * on pairs that rounding used to decide: its orientations are exact, so
 * two disjoint needle triangles lying nearly on one line, far from the
 * origin, do not touch; the same pair moved onto each other does. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "surface/self_intersection.h"
#include "test_check.h"

static int64_t pairs_of(const double *xyz, const int64_t *tri, int64_t nt)
{
    int64_t count = -1, first[2];
    if (vc_self_intersections(xyz, tri, nt, NULL, &count, first) != 0)
        return -1;
    return count;
}

int main(void)
{
    /* Triangles 1687 and 4014 (1-based) of a random holed plate (stretched,
     * rotated, scaled and moved; session 36's sweep), needles along one line
     * with a gap between them: the filtered predicates called them touching
     * and the input was refused as self-intersecting (330 such pairs);
     * exact rational arithmetic finds them apart. */
    double xyz[18] = {-4.9084413349622968, 552.82494276676562, -33.779849050439779,
                      -4.9020410672992032, 552.84789456190094, -33.801152262011172,
                      -4.6008763026250223, 553.31699875447407, -33.905630462252141,
                      -4.6095707872004166, 553.30174431740306, -33.900098334119988,
                      -4.310700313737633, 553.77854574342132, -34.020347578959957,
                      -4.6182653460749075, 553.28648975571286, -33.894566167147595};
    const int64_t tri[6] = {0, 1, 2, 3, 4, 5};
    int64_t n = pairs_of(xyz, tri, 2);
    CHECKF(n == 0, "disjoint needles far from the origin: %lld intersecting pairs", (long long)n);

    /* The same with the second triangle's first corner moved onto the
     * first triangle's third: they touch at a point (not shared by index). */
    memcpy(xyz + 9, xyz + 6, 3 * sizeof(double));
    n = pairs_of(xyz, tri, 2);
    CHECKF(n == 1, "needles touching at a corner: %lld pairs, expected 1", (long long)n);

    /* Two triangles in one plane, overlapping: a pair. */
    const double flat[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 0, 1.2, 0.2, 0, 0.2, 1.2, 0};
    n = pairs_of(flat, tri, 2);
    CHECKF(n == 1, "overlapping coplanar triangles: %lld pairs, expected 1", (long long)n);

    if (failures)
        fprintf(stderr, "%d check(s) failed\n", failures);
    else
        printf("all self-intersection checks passed\n");
    return failures ? 1 : 0;
}
