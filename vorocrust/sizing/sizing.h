/* Sizing for the ball refinement (thesis 6.2.3, 6.3.1, 6.3.2): the
 * distance from a surface point p to the nearest point of the input that is
 * not co-smooth with p, so that a ball of radius 0.49 times that distance
 * satisfies the smooth-coverage condition C1 when it is created.
 *
 * Instead of the thesis' supersampled point clouds, the query runs on the
 * input's own elements (sharp corners, sharp edges, triangles) through a
 * bounding-volume hierarchy, with exact point-to-element distances: no
 * sampling error and no million-point clouds. The co-smoothness of an
 * element with p is decided from the strata and vectors of both:
 *  - a corner is co-smooth only with the ball at that corner;
 *  - a sharp edge is co-smooth with a point of the same crease whose
 *    tangent is within theta_sharp of its own (for a corner: with one of
 *    the corner's crease edges), never with a surface point;
 *  - a triangle is co-smooth with a point of the same patch whose normal
 *    (for an edge or corner point: one of its adjacent triangles' normals
 *    on that patch) is within theta_sharp of its own.
 * The whole element counts as not co-smooth: a conservative distance.
 *
 * The radius bound adds an approximation-error criterion (beyond the
 * thesis, whose theta_sharp alone lets balls span 60 degrees of a curved
 * patch): a surface ball at p may not reach the part of a co-smooth
 * triangle lying farther than eps from the tangent plane at p, and an edge
 * ball may not reach the part of its crease farther than eps from the
 * tangent line. The reconstructed facets are planar through ball centres,
 * so this bounds how far they stray from the input. An edge or corner
 * ball at a crease that opens by less than a right angle takes a narrower
 * slab (sin^2 of the opening, at least 1/16 of eps): its centre stays on
 * the crease, so its facets' sag is not lifted away, and across a thin
 * wedge it would bias a large share of the section. Unlike a smaller
 * co-smoothness angle, it gives no vanishing radii next to a non-sharp
 * bend of a coarse tessellation. */
#ifndef VC_SIZING_SIZING_H
#define VC_SIZING_SIZING_H

#include <stdint.h>
#include "vorocrust/features.h"
#include "vorocrust/surface.h"

enum { VC_ELEM_CORNER = 0, VC_ELEM_EDGE = 1, VC_ELEM_TRIANGLE = 2 };

typedef struct vc_bvh_node {
    double lo[3], hi[3];
    int64_t start, count; /* leaf: elements [start, start + count); inner: count = 0 */
    int64_t left, right;  /* children (inner nodes) */
    /* When every element below is a triangle of one patch: that patch, and
     * a cone holding their outward normals (axis, unit): every one of them
     * is co-smooth by normal with a unit vector n when n . axis >= cos_need
     * (2: never). Otherwise patch = -1. Lets the radius bound skip whole
     * subtrees of a fine, smooth patch (see vc_sizing_radius_bound). */
    int64_t patch;
    double axis[3], cos_need;
} vc_bvh_node;

typedef struct vc_sizing {
    const vc_surface *s;
    const vc_features *f;
    double cos_sharp, cos_smooth;
    double eps;               /* absolute approximation error for the radius bound */
    double *tri_out_normal;   /* 3 per triangle: outward unit normal */
    double *edge_tangent;     /* 3 per edge: unit, along its crease (sharp edges) */
    /* per edge: the half-width of the tangent slabs of a ball centred on
     * it (sharp edges; eps, narrower at a crease opening below a right
     * angle: see pinned_slab in sizing.c) */
    double *edge_slab;
    /* vertex -> incident triangles and incident sharp edges (CSR) */
    int64_t *vtri_start, *vtri;
    int64_t *vedge_start, *vedge;
    /* the elements, in tree order */
    int64_t n_elems;
    signed char *elem_kind;
    int64_t *elem_id;
    int64_t n_nodes;
    vc_bvh_node *nodes;
    double diag;              /* bounding-box diagonal of the surface */
    double orientation;       /* +1 if the patch orientation is outward, -1 otherwise */
} vc_sizing;

/* A point of the surface, described by the element it lies on. */
typedef struct vc_surface_point {
    int kind;        /* VC_ELEM_* */
    int64_t id;      /* corner vertex, sharp edge or triangle */
} vc_surface_point;

/* max_error: eps as a fraction of the bounding-box diagonal (<= 0: none). */
int vc_sizing_init(vc_sizing *z, const vc_surface *s, const vc_features *f,
                   double sharp_angle_deg, double max_error);
void vc_sizing_free(vc_sizing *z);

/* Is element (kind, id) co-smooth with the point p described by sp? */
int vc_sizing_cosmooth(const vc_sizing *z, const vc_surface_point *sp, int kind, int64_t id);

/* Distance from p to the nearest element not co-smooth with sp, or bound
 * when none is closer than bound. */
double vc_sizing_conflict_distance(const vc_sizing *z, const vc_surface_point *sp,
                                   const double p[3], double bound);

/* The largest radius, up to bound, of a ball at p that respects 0.49 times
 * the distance to non-co-smooth elements and the error criterion. */
double vc_sizing_radius_bound(const vc_sizing *z, const vc_surface_point *sp, const double p[3],
                              double bound);

/* The same bound from every element in turn, without the tree: what the
 * tree walk must return to the bit (tests). */
double vc_sizing_radius_bound_all(const vc_sizing *z, const vc_surface_point *sp, const double p[3],
                                  double bound);

/* Squared distance from p to element (kind, id). */
double vc_sizing_element_dist2(const vc_sizing *z, int kind, int64_t id, const double p[3]);

/* Calls fn(ctx, kind, id) for every element whose bounding box is within
 * distance r of p. */
void vc_sizing_elements_near(const vc_sizing *z, const double p[3], double r,
                             void (*fn)(void *ctx, int kind, int64_t id), void *ctx);

/* As vc_sizing_elements_near, in the same order, but a box farther than
 * *within2 (a squared distance fn may lower as it goes: a nearest-element
 * search) is skipped too. */
void vc_sizing_elements_near_within(const vc_sizing *z, const double p[3], double r,
                                    void (*fn)(void *ctx, int kind, int64_t id), void *ctx,
                                    const double *within2);

/* Is some triangle closer to p than r (vc_sizing_element_dist2 < r^2)?
 * Stops at the first one found, nearest boxes first. */
int vc_sizing_triangle_within(const vc_sizing *z, const double p[3], double r);
/* The same, trying triangle *hint first (-1: none) and leaving in it the
 * triangle found: nearby points (a facet's probes) are mostly near the
 * same triangle. */
int vc_sizing_triangle_within_hint(const vc_sizing *z, const double p[3], double r, int64_t *hint);

/* Outward normal at the point (for an edge or corner: the normalised mean
 * of its triangles' normals). */
void vc_sizing_point_normal(const vc_sizing *z, const vc_surface_point *sp, double n[3]);

#endif
