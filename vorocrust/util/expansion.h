/* Exact real numbers as floating-point expansions (Shewchuk 1997): a sum of
 * non-overlapping doubles in increasing magnitude, whose sign is the sign
 * of the largest component. For the exact paths of the predicates
 * (exact_predicates.c, the Voronoi engine's power_side.c): sums merge
 * their operands in linear time, products scale one operand by each
 * component of the other; every value has its own buffer (from the arena
 * below when one is open). An operation that runs
 * out of memory returns an expansion whose v is NULL; every later
 * operation propagates it and vc_expn_sign_free reports it. */
#ifndef VC_UTIL_EXPANSION_H
#define VC_UTIL_EXPANSION_H

typedef struct vc_expn {
    double *v;
    int n;
} vc_expn;

vc_expn vc_expn_from_double(double x);
/* a - b exactly (at most two components). */
vc_expn vc_expn_diff(double a, double b);
/* New expansions; the operands are kept. */
vc_expn vc_expn_add(vc_expn a, vc_expn b);
vc_expn vc_expn_mul(vc_expn a, vc_expn b);
vc_expn vc_expn_copy(vc_expn a);
/* Negates a in place and returns it. */
vc_expn vc_expn_neg(vc_expn a);
/* x + y and x * y; both operands are freed. */
vc_expn vc_expn_add_free(vc_expn x, vc_expn y);
vc_expn vc_expn_mul_free(vc_expn x, vc_expn y);
/* The sign of x (+1, -1, 0), or VC_PREDICATE_NOMEM (exact_predicates.h)
 * when x is an out-of-memory result; frees x. */
int vc_expn_sign_free(vc_expn x);
/* Frees an expansion's storage (v). */
void vc_expn_release(void *v);
/* Between begin and end (nested pairs allowed, per thread) expansions are
 * taken from one block freed at the end: an evaluation's expansions must
 * not outlive it. */
void vc_expn_arena_begin(void);
void vc_expn_arena_end(void);

#endif
