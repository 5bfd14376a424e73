/* pgt: fork-join parallel loop on pthreads (see parallel.h for the chunking contract). */
#include "pgt/parallel.h"

#include <pthread.h>
#include <stdatomic.h>

/* Shared by the threads of one call: each takes the next block of `block` elements. */
typedef struct pgt_parallel_job {
    pgt_range_fn fn;
    void *ctx;
    uint32_t count, block;
    atomic_uint_fast64_t next;
} pgt_parallel_job;

typedef struct pgt_parallel_worker {
    pgt_parallel_job *job;
    uint32_t worker;
} pgt_parallel_worker;

static void *pgt_parallel_run(void *arg) {
    pgt_parallel_worker *w = arg;
    pgt_parallel_job *job = w->job;
    for (;;) {
        const uint64_t b = atomic_fetch_add(&job->next, job->block);
        if (b >= job->count) break;
        const uint64_t e = b + job->block < job->count ? b + job->block : job->count;
        job->fn(job->ctx, (uint32_t)b, (uint32_t)e, w->worker);
    }
    return NULL;
}

void pgt_parallel_for(uint32_t count, uint32_t threads, pgt_range_fn fn, void *ctx) {
    threads = pgt_parallel_workers(threads);
    /* Below this many elements a thread costs more than it saves (pthread_create is ~20 us). */
    const uint32_t min_per_thread = 4096;
    if (count / min_per_thread < threads)
        threads = count / min_per_thread > 0 ? count / min_per_thread : 1;
    if (threads <= 1) {
        if (count) fn(ctx, 0, count, 0);
        return;
    }
    /* Blocks taken on demand, about PGT_PARALLEL_BLOCKS_PER_THREAD per thread: passes whose
     * elements cost unequal work (old vertices walking fans next to face points that do not)
     * and a shared, noisy machine both balance without a scheduler. */
    const uint32_t per = threads * PGT_PARALLEL_BLOCKS_PER_THREAD;
    uint32_t block = count / per + (count % per != 0);
    if (block < min_per_thread / 4) block = min_per_thread / 4;
    pgt_parallel_job job = {fn, ctx, count, block, 0};
    atomic_init(&job.next, 0);
    pgt_parallel_worker workers[PGT_MAX_THREADS];
    pthread_t tids[PGT_MAX_THREADS];
    int started[PGT_MAX_THREADS];
    for (uint32_t t = 0; t < threads; ++t) {
        workers[t] = (pgt_parallel_worker){&job, t};
        started[t] = t > 0 && pthread_create(&tids[t], NULL, pgt_parallel_run, &workers[t]) == 0;
    }
    pgt_parallel_run(&workers[0]); /* also does the share of any thread that could not start */
    for (uint32_t t = 1; t < threads; ++t)
        if (started[t]) pthread_join(tids[t], NULL);
}

typedef struct pgt_items_job {
    pgt_range_fn fn;
    void *ctx;
    uint32_t weight;
} pgt_items_job;

static void pgt_items_trampoline(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const pgt_items_job *j = vctx;
    /* the items whose first element lies in [begin, end) (in 64 bits: end + weight - 1 may
     * pass 2^32 when count * weight is near it) */
    const uint32_t i0 = (uint32_t)(((uint64_t)begin + j->weight - 1u) / j->weight),
                   i1 = (uint32_t)(((uint64_t)end + j->weight - 1u) / j->weight);
    if (i0 < i1) j->fn(j->ctx, i0, i1, worker);
}

void pgt_parallel_for_items(uint32_t count, uint32_t weight, uint32_t threads, pgt_range_fn fn,
                            void *ctx) {
    if (!count) return;
    if (weight == 0 || (uint64_t)count * weight > UINT32_MAX) {
        fn(ctx, 0, count, 0);
        return;
    }
    pgt_items_job j = {fn, ctx, weight};
    pgt_parallel_for(count * weight, threads, pgt_items_trampoline, &j);
}
