/* Large memory regions mapped by the Voronoi engine itself (the cells'
 * storage: freeing them returns the memory to the system at once), and
 * whether large arrays ask for huge pages. Internal to the engine. */
#ifndef VC_PAGE_BANK_H
#define VC_PAGE_BANK_H

#include <stddef.h>
#include <stdint.h>

/* Whether the large arrays ask for transparent huge pages
 * (madvise(MADV_HUGEPAGE)): only when the caller asked with
 * vc_voronoi_set_huge_pages(1) (the CLI does on VC_HUGE_PAGES=1). Otherwise the system's own policy applies (huge pages
 * anyway where it is "always"). On the virtual machines this engine is
 * developed on (free page reporting, nested paging), a first touch of a
 * huge page taken from memory the host reclaimed costs about 2.2 s per
 * GB against 0.45 s per GB for small pages, which outweighs the fewer TLB
 * misses: 1M seeds built 1.5 to 2 s faster without asking. */
int vc_huge_pages_wanted(void);

/* Asks for huge pages on [p, p + bytes) when vc_huge_pages_wanted(). */
void vc_pages_advise(void *p, size_t bytes);

/* Maps bytes (a multiple of VC_HUGE_PAGE, see cell_result.h) of fresh
 * memory aligned to a huge page; NULL when out of memory. */
void *vc_pages_map(size_t bytes);
void vc_pages_unmap(void *p, size_t bytes);

#endif
