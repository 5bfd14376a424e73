/* pgt: allocation of large buffers. Private to ref_cpu. */
#ifndef PGT_ALLOC_INTERNAL_H
#define PGT_ALLOC_INTERNAL_H

#include <stddef.h>

/* malloc for a large buffer that a producer fills once (freed with free). On Linux a buffer of
 * 8 MiB or more is aligned to 2 MiB and advised (madvise MADV_HUGEPAGE) to be backed by
 * transparent huge pages where the system grants them ("madvise" mode, as on this VM,
 * or "always"): a first write then faults once per 2 MiB instead of once per 4 KiB. Measured on the
 * atlas image (44 MiB at 1024^2, pgt_image_create_unset): pizza's raster 20-21 -> 15-16 ms,
 * human_neutral's 15.6-16.5 -> 12.6-12.8 ms (2 threads, alternating runs). Not every buffer
 * gains: advising the builder's 4 MiB chart array too made its raster 2-3 ms slower again
 * (cube_sphere_64 14 -> 17 ms), likely from cache-set conflicts (within a huge page, physical
 * addresses follow virtual ones, so arrays aligned to 2 MiB share their L2 sets texel for
 * texel), so callers opt in where it was measured. */
void *pgt_alloc_large(size_t bytes);

/* pgt_alloc_large from one huge page (2 MiB) up: for arrays read at random, where a miss of the
 * TLB adds to one of the cache. The marcher's atlas view (pgt_march_atlas_create: 30 MiB of
 * codes, texels, jump records and ring masks at 1024^2, read wherever a jump lands; 28 MiB
 * without the masks when this was measured) is the caller: pgt
 * bench march on pizza (a jump every 4.4 steps; one thread, 8192 walkers x 500 steps, ten
 * alternating runs on the AMD VM) went from medians of 7.78 to 9.01 M steps/s without positions
 * and 5.90 to 6.90 with them. */
void *pgt_alloc_huge(size_t bytes);

#endif
