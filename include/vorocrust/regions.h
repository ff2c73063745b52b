/* The regions of space a closed triangle surface bounds: the cells of its
 * arrangement (thesis 6.2.2, non-manifold domains).
 *
 * Around every edge the triangles are ordered by angle; the two triangle
 * sides that face each other across a wedge between consecutive triangles
 * bound the same piece of space. Joined over all edges, the triangle sides
 * fall into shells: closed oriented surfaces, each bounding one connected
 * piece of a region. A shell whose enclosed signed volume is positive
 * bounds its piece from outside; the one negative shell of each connected
 * surface component faces away from it, and lies inside a positive shell
 * of another component (the smallest that contains it: the component is
 * nested there, as a cavity or an inclusion) or in the unbounded region.
 * A region is a positive shell with the negative shells directly inside
 * it. Triangles given twice with opposite orientation (two closed
 * surfaces that share an interface) count once.
 *
 * Regions are numbered in input order: by the first triangle (lowest
 * index) on their boundary. */
#ifndef VORO_CRUST_REGIONS_H
#define VORO_CRUST_REGIONS_H

#include <stdint.h>

#include "vorocrust/error.h"
#include "vorocrust/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the triangles' orientation says a region is. */
typedef enum vc_region_kind {
    VC_REGION_SOLID = 1, /* every boundary triangle's normal points out of it */
    VC_REGION_VOID = 2,  /* every boundary triangle's normal points into it (a cavity) */
    VC_REGION_MIXED = 3  /* both: the orientation does not say (an interface, or nested
                            shells of the same orientation) */
} vc_region_kind;

typedef struct vc_region {
    double volume;          /* enclosed: the outer shell's minus its holes' */
    int64_t first_triangle; /* the lowest triangle index on its boundary (0-based) */
    int64_t n_sides;        /* triangle sides on its boundary */
    int64_t n_holes;        /* shells of nested components bounding it from inside */
    int64_t parent;         /* the region its outer shell lies in, -1: the unbounded one */
    vc_region_kind kind;
} vc_region;

typedef struct vc_regions {
    int64_t n_regions;      /* bounded regions */
    vc_region *region;
    /* per triangle: the region on its front side (where its normal
     * points; 2t) and on its back side (2t + 1); -1: the unbounded region */
    int64_t *side_region;
    int64_t n_triangles;
    int64_t n_components;   /* surface components connected through edges */
    int64_t *component_of;  /* per triangle: its component, numbered by first triangle */
    int64_t *component_depth; /* per component: how many components enclose it */
    unsigned char *component_outward; /* per component: its triangles' normals point away
                                         from the space it encloses */
    int64_t n_twice;        /* triangles given a second time, reversed (counted once) */
    int64_t *first_copy;    /* per triangle: the lower-numbered triangle it repeats
                               (the same three vertices), or itself */
    int unbounded_sides;    /* which sides the unbounded region touches: 1 front, 2 back, 3 both */
    int64_t n_interface;    /* triangles with a bounded region on both sides */
    int64_t n_walls;        /* triangles with the same region on both sides: walls of
                               zero thickness (a fin inside a region, a flat sheet) */
    int64_t first_wall;     /* the lowest such triangle */
    int closed_shells;      /* every edge has exactly two distinct triangles: the
                               components are closed 2-manifold shells */
} vc_regions;

/* The regions of the closed surface s (call it after vc_surface_check has
 * found no boundary edge; an edge of one distinct triangle, such as the
 * rim of a wall given twice, joins that triangle's two sides). Returns 0
 * or VC_ENOMEM. */
int vc_surface_regions(const vc_surface *s, vc_regions *out, vc_error *err);

/* Whether the regions are those of one solid as the orientation defines
 * it: every region VC_REGION_SOLID or VC_REGION_VOID, the unbounded region
 * outside, and every triangle between a solid and a void: returns 1; or
 * so with every triangle reversed (a surface oriented inward): returns -1;
 * else 0 (an interface between regions, nested shells of the same
 * orientation, components oriented differently). */
int vc_regions_single_solid(const vc_regions *r);

/* The orientation the even-odd rule gives a surface of nested closed
 * shells: the outermost components bound solid, the ones inside them
 * cavities, the ones inside those solid again, and so on. Writes to flip
 * (n_triangles bytes) 1 for every triangle whose component must be
 * reversed for that, and returns how many components; -1 when some
 * component is not a closed 2-manifold shell of its own (closed_shells 0:
 * an interface between regions, where the rule does not apply). */
int64_t vc_regions_even_odd_flips(const vc_regions *r, unsigned char *flip);

/* Parts exported inside out: the outermost closed shells whose normals
 * point in (nothing around them) when another outermost shell points out
 * (a model all inside out is one solid oriented inward, left as it is).
 * Returns how many components (0 when none, or when the components are
 * not closed shells of their own); when that is not 0 and flip is not
 * NULL, writes to flip (n_triangles bytes) 1 for their triangles. What
 * vorocrust mesh reverses and vorocrust info reports. */
int64_t vc_regions_inside_out_flips(const vc_regions *r, unsigned char *flip);

/* Locating points in the regions of a surface: vc_region_locate returns
 * the region (0-based) that holds p, -1 for the unbounded region, -2 when
 * p lies on the surface or every segment tried from it grazes an edge.
 * side_region holds the regions of the two sides of every triangle of s,
 * as vc_regions.side_region does. The locator keeps pointers to s and
 * side_region (they must outlive it); s must hold each triangle once (a
 * triangle given twice, reversed, is one interface: drop the second copy,
 * its sides are the first's). Queries are read-only and may run in
 * parallel. */
typedef struct vc_region_locator vc_region_locator;
int vc_region_locator_build(const vc_surface *s, const int64_t *side_region,
                            vc_region_locator **out, vc_error *err);
int64_t vc_region_locate(const vc_region_locator *L, const double p[3]);
/* The triangle nearest p (the lowest index among equals), -1 for an empty
 * surface. A locator built with side_region NULL answers only this
 * (vc_region_locate then returns -2). */
int64_t vc_region_locator_nearest(const vc_region_locator *L, const double p[3]);
void vc_region_locator_free(vc_region_locator *L);

/* Frees the arrays of r and zeroes it. Safe on a zeroed vc_regions. */
void vc_regions_free(vc_regions *r);

#ifdef __cplusplus
}
#endif

#endif
