/* pgt: fork-join parallel loop on pthreads (see parallel.h for the chunking contract). */
#include "pgt/parallel.h"

#include <pthread.h>

typedef struct pgt_parallel_job {
    pgt_range_fn fn;
    void *ctx;
    uint32_t begin, end, worker;
} pgt_parallel_job;

static void *pgt_parallel_run(void *arg) {
    pgt_parallel_job *job = arg;
    job->fn(job->ctx, job->begin, job->end, job->worker);
    return NULL;
}

void pgt_parallel_for(uint32_t count, uint32_t threads, pgt_range_fn fn, void *ctx) {
    if (threads == 0) threads = 1;
    if (threads > PGT_MAX_THREADS) threads = PGT_MAX_THREADS;
    /* Below this many elements a thread costs more than it saves (pthread_create is ~20 us). */
    const uint32_t min_per_thread = 4096;
    if (count / min_per_thread < threads)
        threads = count / min_per_thread > 0 ? count / min_per_thread : 1;
    if (threads <= 1) {
        if (count) fn(ctx, 0, count, 0);
        return;
    }
    pgt_parallel_job jobs[PGT_MAX_THREADS];
    pthread_t tids[PGT_MAX_THREADS];
    int started[PGT_MAX_THREADS];
    uint32_t chunk = count / threads + (count % threads != 0);
    for (uint32_t t = 0; t < threads; ++t) {
        uint32_t b = t * chunk, e = b + chunk;
        if (b > count) b = count;
        if (e > count) e = count;
        jobs[t] = (pgt_parallel_job){fn, ctx, b, e, t};
        started[t] = 0;
    }
    for (uint32_t t = 1; t < threads; ++t)
        started[t] = pthread_create(&tids[t], NULL, pgt_parallel_run, &jobs[t]) == 0;
    pgt_parallel_run(&jobs[0]);
    for (uint32_t t = 1; t < threads; ++t) {
        if (started[t])
            pthread_join(tids[t], NULL);
        else
            pgt_parallel_run(&jobs[t]); /* could not start a thread: do its share here */
    }
}
