/* pgt: large-buffer allocation (alloc_internal.h). */
#define _DEFAULT_SOURCE /* madvise's MADV_HUGEPAGE (Linux) */
#include <stdlib.h>

#include "alloc_internal.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

/* The x86-64 and AArch64 (4 KiB granule) huge page size. */
#define PGT_ALLOC_HUGE_PAGE ((size_t)2 << 20)
/* Smaller buffers are left to malloc (rounding up to whole huge pages wastes under a quarter
 * from here on). */
#define PGT_ALLOC_HUGE_MIN ((size_t)8 << 20)

void *pgt_alloc_huge(size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= PGT_ALLOC_HUGE_PAGE) {
        const size_t rounded = (bytes + PGT_ALLOC_HUGE_PAGE - 1u) & ~(PGT_ALLOC_HUGE_PAGE - 1u);
        /* a size within a huge page of SIZE_MAX wraps: malloc refuses it below */
        void *p = rounded >= bytes ? aligned_alloc(PGT_ALLOC_HUGE_PAGE, rounded) : NULL;
        if (p) {
            (void)madvise(p, rounded, MADV_HUGEPAGE);
            return p;
        }
    }
#endif
    return malloc(bytes);
}

void *pgt_alloc_large(size_t bytes) {
    return bytes >= PGT_ALLOC_HUGE_MIN ? pgt_alloc_huge(bytes) : malloc(bytes);
}
