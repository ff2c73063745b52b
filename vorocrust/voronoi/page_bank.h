/* Pages the process has already touched, handed on to new large arrays
 * instead of being returned to the system. Internal to the Voronoi engine.
 *
 * On this kind of machine the first touch of fresh memory (the kernel
 * clearing it) costs about 2 s per GB, a large part of a 1M-cell build;
 * the stitching frees the cells' storage and then allocates the mesh's
 * arrays of about the same size. A bank holds regions mapped by the
 * engine itself; on Linux their pages are moved (mremap, no copy, no
 * clearing) into the large arrays allocated from it, which stay ordinary
 * heap blocks freed with free(). Elsewhere it only allocates. */
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

typedef struct vc_page_bank {
    char **region;
    size_t *size; /* bytes left at region[i] (multiples of VC_HUGE_PAGE) */
    int64_t n, cap;
} vc_page_bank;

/* Adds a region from vc_pages_map to the bank, which then owns it. Returns
 * 0, or -1 when out of memory (the region is unmapped then). */
int vc_page_bank_add(vc_page_bank *b, void *p, size_t bytes);

/* bytes of memory, like vc_big_alloc (freed with free()), with as much of
 * it as the bank holds made of the bank's pages (contents undefined). */
void *vc_page_bank_alloc(vc_page_bank *b, size_t bytes);

/* Unmaps what is left in the bank. */
void vc_page_bank_free(vc_page_bank *b);

#endif
