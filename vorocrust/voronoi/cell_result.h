/* The Voronoi cell of one kept seed as computed on its own, before the
 * cells are stitched into one conforming mesh. Internal to the engine. */
#ifndef VC_CELL_RESULT_H
#define VC_CELL_RESULT_H

#include <stdint.h>
#include <stdlib.h>
#ifdef __linux__
#include <sys/mman.h>
#endif

#include "vorocrust/error.h"
#include "vorocrust/log.h"
#include "vorocrust/polymesh.h"
#include "vorocrust/seeds.h"

#include "page_bank.h"

/* Only the combinatorics: the stitching computes every vertex's point from
 * the seeds of its planes (cell_stitch.c), so the cells' own points are
 * not kept. */
typedef struct vc_cell_result {
    int nv, nf, nfv;    /* nfv <= 65535 */
    int32_t *plane;     /* nf: neighbour seed index, or a wall code (< 0) */
    uint16_t *face_start; /* nf + 1 */
    uint16_t *fv;       /* nfv local vertex indices */
    uint16_t *vf;       /* 3 * nv: the faces of each vertex's three planes */
} vc_cell_result;

/* Large arrays that are touched once, in passes: aligned to huge pages,
 * and backed by them when asked (see vc_huge_pages_wanted in page_bank.h).
 * Freed with free(). */
#define VC_BIG_ALLOC_MIN ((size_t)4 << 20)
#define VC_HUGE_PAGE ((size_t)2 << 20)

static inline void *vc_big_alloc(size_t bytes)
{
    if (bytes == 0)
        bytes = 1;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= VC_BIG_ALLOC_MIN) {
        size_t rounded = (bytes + VC_HUGE_PAGE - 1) & ~(VC_HUGE_PAGE - 1);
        void *p = NULL;
        if (posix_memalign(&p, VC_HUGE_PAGE, rounded) != 0)
            return NULL;
        vc_pages_advise(p, rounded);
        return p;
    }
#endif
    return malloc(bytes);
}

/* Where the cells' data live: the blocks of consecutive cells, carved out
 * of large regions mapped by the engine itself, so that freeing the pool
 * returns its memory to the system at once. */
typedef struct vc_region_pool {
    char **region;
    size_t *region_size;
    int64_t n, cap;
    size_t used; /* bytes taken from the last region */
} vc_region_pool;

typedef struct vc_cell_store {
    vc_region_pool topo;
} vc_cell_store;

#define VC_REGION_BYTES ((size_t)64 << 20)

/* bytes (a multiple of 8) from the pool; NULL when out of memory. Not
 * thread-safe. */
static inline void *vc_region_take(vc_region_pool *p, size_t bytes)
{
    if (p->n == 0 || p->region_size[p->n - 1] - p->used < bytes) {
        if (p->n == p->cap) {
            int64_t cap = p->cap ? 2 * p->cap : 16;
            char **r = (char **)realloc(p->region, (size_t)cap * sizeof *r);
            if (!r)
                return NULL;
            p->region = r;
            size_t *s = (size_t *)realloc(p->region_size, (size_t)cap * sizeof *s);
            if (!s)
                return NULL;
            p->region_size = s;
            p->cap = cap;
        }
        size_t size = bytes > VC_REGION_BYTES ? bytes : VC_REGION_BYTES;
        size = (size + VC_HUGE_PAGE - 1) & ~(VC_HUGE_PAGE - 1);
        char *q = (char *)vc_pages_map(size);
        if (!q)
            return NULL;
        p->region[p->n] = q;
        p->region_size[p->n] = size;
        p->n++;
        p->used = 0;
    }
    void *out = p->region[p->n - 1] + p->used;
    p->used += bytes;
    return out;
}

/* Empties the pool: its regions go back to the system. */
static inline void vc_region_pool_free(vc_region_pool *p)
{
    for (int64_t i = 0; i < p->n; i++)
        vc_pages_unmap(p->region[i], p->region_size[i]);
    free(p->region);
    free(p->region_size);
    p->region = NULL;
    p->region_size = NULL;
    p->n = p->cap = 0;
    p->used = 0;
}

#endif
