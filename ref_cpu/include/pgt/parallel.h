/* pgt: a minimal fork-join parallel loop on pthreads for the reference.
 *
 * The range [0, count) is cut into contiguous blocks that the threads take on demand. fn must
 * compute each element independently of which thread and which block it lands in, so results are
 * the same bytes for any thread count; `worker` (< threads) is only for per-thread scratch. */
#ifndef PGT_PARALLEL_H
#define PGT_PARALLEL_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Most worker threads a call may use. */
#define PGT_MAX_THREADS 256u

/* Blocks per thread a loop is cut into (dynamic balance vs. per-block overhead). */
#define PGT_PARALLEL_BLOCKS_PER_THREAD 16u

/* The workers a call asked for `threads` may use: 0 means 1, at most PGT_MAX_THREADS (what
 * per-worker scratch is sized for; worker < this). */
static inline uint32_t pgt_parallel_workers(uint32_t threads) {
    return threads == 0 ? 1u : threads < PGT_MAX_THREADS ? threads : PGT_MAX_THREADS;
}

typedef void (*pgt_range_fn)(void *ctx, uint32_t begin, uint32_t end, uint32_t worker);

/* Calls fn(ctx, begin, end, worker) on disjoint chunks covering [0, count), on up to `threads`
 * threads (the caller's among them). Falls back to running inline when a thread cannot start. */
void pgt_parallel_for(uint32_t count, uint32_t threads, pgt_range_fn fn, void *ctx);

/* The same over `count` items that each cost about `weight` elements (rows of an image, charts,
 * subtrees): pgt_parallel_for keeps thousands of elements per thread, too many items when they
 * are big. fn receives item ranges; an item is done by the range that holds its first element.
 * Falls back to one inline call when count * weight does not fit 32 bits. */
void pgt_parallel_for_items(uint32_t count, uint32_t weight, uint32_t threads, pgt_range_fn fn,
                            void *ctx);

#ifdef __cplusplus
}
#endif

#endif
