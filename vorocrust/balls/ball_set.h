/* The growing set of balls and its spatial index.
 *
 * Radii vary over orders of magnitude (tiny balls at sharp corners, large
 * ones on flat patches), so one uniform grid does not fit: balls are
 * indexed in levels by radius, level k holding radii in
 * [unit 2^k, unit 2^(k+1)) in a grid of cell size unit 2^(k+2), so the
 * centre of a ball touching a point always lies in one of the 8 cells
 * nearest to it at its level. Each ball is also listed in a coarse cell of
 * its level (16 cells wide): a query whose range covers more than 512
 * cells of a level reads the coarse cells instead. A query at a level
 * whose cell range would exceed the number of balls there scans that
 * level's list instead. */
#ifndef VC_BALLS_BALL_SET_H
#define VC_BALLS_BALL_SET_H

#include <stdint.h>
#include "vorocrust/sampling.h"

#define VC_BALL_LEVELS 48

/* A ball as its cell lists it: the centre and radius a query filters by
 * (the cell's balls side by side: walking a cell reads consecutive memory,
 * where a chain through the balls' arrays was a cache miss per ball, most
 * of the sampler's time), and the ball's index. */
typedef struct vc_ball_rec {
    double c[3], r;
    int64_t id;
} vc_ball_rec;

/* A cell of the hash grid (open addressing): its key (UINT64_MAX when the
 * slot is free) and its balls, in the order they were linked; n_dead of
 * the n records are of balls unlinked since (id -1). A cell left empty
 * keeps its slot until the table is rebuilt. */
typedef struct vc_ball_cell {
    uint64_t key;
    int32_t n, cap, n_dead;
    vc_ball_rec *rec;
} vc_ball_cell;

typedef struct vc_ball_set {
    vc_balls b;          /* the balls (center, radius, kind, element, normal) */
    int64_t cap;
    double unit;         /* radius of level 0 */
    double scale[VC_BALL_LEVELS + 2]; /* unit 2^k: the levels' radii and cells, precomputed */
    double origin[3];    /* cell coordinates count from here */
    /* hash grid: cell key -> the cell's balls */
    int64_t table_size;  /* power of two */
    int table_bits;      /* its log2 */
    int64_t n_slots_used; /* slots holding a key (cells, empty or not) */
    vc_ball_cell *cell;
    uint64_t *filter;    /* occupancy bits of the cell keys (ball_set.c) */
    int64_t n_unlinked;  /* balls unlinked since the filter was made */
    uint64_t *key;       /* 2 i: ball i's cell, 2 i + 1: its coarse cell */
    int32_t *pos;        /* its place in each of the two cells' lists */
    int *level;
    /* per-level lists */
    int64_t *level_pos;  /* position of the ball in its level's list */
    int64_t *level_list[VC_BALL_LEVELS];
    int64_t level_n[VC_BALL_LEVELS], level_cap[VC_BALL_LEVELS];
    /* Balls added or resized since the last vc_ball_set_forget_changes:
     * changed_reach[i] > 0 is the largest radius ball i had since (what it
     * could reach: a shrunk ball still matters where it was), 0 for a ball
     * unchanged; a local sliver scan needs only the neighbourhood of these. */
    double *changed_reach;
    int64_t n_changed;
} vc_ball_set;

/* lo: the low corner of the surface's bounding box, diag its diagonal. */
int vc_ball_set_init(vc_ball_set *bs, const double lo[3], double diag);
void vc_ball_set_free(vc_ball_set *bs);

/* Adds a ball; returns its index or -1 when out of memory. */
int64_t vc_ball_set_add(vc_ball_set *bs, const double c[3], double r, int kind, int64_t element,
                        const double normal[3]);

/* A new set holding copies of the balls of b, with their centres at xyz
 * (b's own when NULL), over their bounding box. Returns 0, or -1 when out
 * of memory (nothing to free then). */
int vc_ball_set_build(vc_ball_set *bs, const vc_balls *b, const double *xyz);

/* Sets the radius of ball i (re-indexing it when its level changes). */
int vc_ball_set_resize(vc_ball_set *bs, int64_t i, double r);

/* Moves ball i's centre to c (marked changed, with the reach of where it
 * was). Returns 0. */
int vc_ball_set_move(vc_ball_set *bs, int64_t i, const double c[3]);

/* Marks every ball unchanged (see changed_reach). */
void vc_ball_set_forget_changes(vc_ball_set *bs);

/* Calls fn(ctx, i) for every ball whose centre is within distance
 * reach + its radius * radius_factor of p, and for no ball farther than
 * that by more than a relative 1e-9 (fn tests its exact condition, which
 * must not accept a ball beyond that distance); balls whose radius is
 * below min_radius may be left out. Cell by cell, the most recently linked
 * ball of a cell first: the same order for the same calls. Stops early
 * when fn returns non-zero, and returns that. */
int vc_ball_set_query(const vc_ball_set *bs, const double p[3], double reach,
                      double radius_factor, double min_radius, int (*fn)(void *ctx, int64_t i),
                      void *ctx);

#endif
