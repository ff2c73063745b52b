/* Moving touched pages into new large arrays (see page_bank.h). */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE 1 /* mremap */
#endif
#include "page_bank.h"

#include <stdlib.h>

#include "cell_result.h"
#include "vorocrust/voronoi.h"

#if defined(__linux__) && defined(MREMAP_FIXED) && defined(MADV_HUGEPAGE)
#define VC_PAGE_BANK_MOVES 1
#endif

/* The process's memory policy, set by the caller (vorocrust/voronoi.h). */
static int huge_pages_wanted;

void vc_voronoi_set_huge_pages(int wanted)
{
    __atomic_store_n(&huge_pages_wanted, wanted != 0, __ATOMIC_RELAXED);
}

int vc_huge_pages_wanted(void)
{
    return __atomic_load_n(&huge_pages_wanted, __ATOMIC_RELAXED);
}

void vc_pages_advise(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (vc_huge_pages_wanted())
        (void)madvise(p, bytes, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

void *vc_pages_map(size_t bytes)
{
#ifdef VC_PAGE_BANK_MOVES
    /* Over-map by one huge page and trim, for the alignment mremap needs
     * to move whole huge pages. */
    char *q = mmap(NULL, bytes + VC_HUGE_PAGE, PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (q == MAP_FAILED)
        return NULL;
    size_t lead = (VC_HUGE_PAGE - ((uintptr_t)q & (VC_HUGE_PAGE - 1))) & (VC_HUGE_PAGE - 1);
    if (lead)
        munmap(q, lead);
    if (VC_HUGE_PAGE - lead)
        munmap(q + lead + bytes, VC_HUGE_PAGE - lead);
    vc_pages_advise(q + lead, bytes);
    return q + lead;
#else
    return vc_big_alloc(bytes);
#endif
}

void vc_pages_unmap(void *p, size_t bytes)
{
#ifdef VC_PAGE_BANK_MOVES
    if (p)
        munmap(p, bytes);
#else
    (void)bytes;
    free(p);
#endif
}
