/* The Voronoi engine's one geometric decision, made exactly: on which side
 * of the bisector of the seeds s and x a vertex of the cell of s lies.
 * Internal to the engine.
 *
 * A vertex of the cell of s is named by s and its three planes: bisectors
 * of s and another seed (a seed index >= 0) or walls of the clipping box
 * (VC_WALL_XMIN - k, k = 0..5 for xmin, xmax, ymin, ymax, zmin, zmax).
 * The decision is the sign of a determinant of the input coordinates,
 * evaluated in floating-point expansions (util/expansion.h): the caller
 * runs it only where its floating-point filter cannot decide.
 *
 * Exact ties (x on the sphere through s and the vertex's seeds, a bisector
 * through a box corner) are broken by a symbolic perturbation that is the
 * same for every cell: seed i carries the infinitesimal weight eps^(i+1)
 * (a power diagram; a lower index weighs more). The perturbed diagram is
 * simple (every vertex has exactly three planes per cell) and every cell
 * that holds a vertex decides every plane the same way, so the cells fit
 * together by construction (Edelsbrunner and Muecke's simulation of
 * simplicity, applied to the weights). */
#ifndef VC_VORONOI_POWER_SIDE_H
#define VC_VORONOI_POWER_SIDE_H

#include <stdint.h>

typedef struct vc_power_ctx {
    const double *xyz;   /* every seed, 3 per index */
    double box_lo[3], box_hi[3];
} vc_power_ctx;

/* +1 when the vertex (s; plane[0..2]) of the perturbed diagram is strictly
 * nearer s than x (kept by the bisector of s and x), -1 when it is nearer
 * x (cut off); never 0. VC_PREDICATE_NOMEM (util/exact_predicates.h) when
 * out of memory. The three planes must meet in one point. */
int vc_power_side(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t x);

/* The same test in steps, for vertices tested against many planes: the
 * vertex's part of the determinant prepared once per vertex, the plane's
 * once per plane (double-double arithmetic), then each test costs some
 * forty floating-point operations; ties whose arithmetic rounds, and
 * values too near zero for double-double, go on to vc_power_side. */
#define VC_POWER_CACHE 32
void vc_power_vertex_prepare(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3],
                             double cache[VC_POWER_CACHE]);
#define VC_POWER_ROW 9
void vc_power_plane_prepare(const vc_power_ctx *ctx, int64_t s, int64_t x,
                            double row[VC_POWER_ROW]);
/* vc_power_vertex_prepare from the rows vc_power_plane_prepare made for
 * the vertex's three planes (a cell keeps them per plane): the same cache,
 * without recomputing the rows. */
void vc_power_vertex_prepare_rows(const int64_t plane[3], const double *const row[3],
                                  double cache[VC_POWER_CACHE]);
int vc_power_side_cached(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t x,
                         const double cache[VC_POWER_CACHE], const double row[VC_POWER_ROW]);

/* 1 when the vertex (s; plane[0..2]), unperturbed, lies exactly on the
 * plane q (the bisector of s and seed q, or wall q), 0 when not,
 * VC_PREDICATE_NOMEM when out of memory. Two vertices of a cell that share
 * two planes coincide exactly when either lies on the other's third. */
int vc_power_on_plane(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t q);

/* The vertex (s; plane[0..2]) relative to s, from the input seeds and
 * walls: Cramer's rule in integers (util/bigint.h), each coordinate a
 * quotient of exact integers rounded at most three times (within 4 ulp of
 * the exact vertex, barring underflow). Returns 0, or -1 when the
 * integers cannot hold the values (exponents too far apart) or the planes
 * do not meet in a point. */
int vc_power_vertex_exact(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], double y[3]);

/* How many tests needed exact arithmetic, and how many of those the
 * expansions (statistics; all threads). Exact tests run in fixed-width
 * integers: two to five limbs when every difference to s is a double and
 * their exponents lie within 8 of one another (the common tie), else
 * util/bigint.h when the coordinates' exponents are close enough for it,
 * else in expansions. */
long long vc_power_exact_count(void);
long long vc_power_expansion_count(void);

/* The exact test alone, for the tests: method 0 in integers (-2 when they
 * cannot hold the values), 1 in expansions, 2 in the narrow integers (-2
 * when the differences are not doubles or too far apart). */
int vc_power_side_by(const vc_power_ctx *ctx, int64_t s, const int64_t plane[3], int64_t x,
                     int method);

#endif
