/* pgt: progress of long computations (see progress.h). */
#include "pgt/progress.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct pgt_progress {
    pthread_mutex_t lock; /* guards stage, unit, total and stages */
    char stage[PGT_PROGRESS_STAGE_MAX + 1];
    char unit[32];
    uint64_t total;
    uint32_t stages;
    atomic_uint_least64_t done; /* added from the computation's threads */
};

pgt_progress *pgt_progress_create(void) {
    pgt_progress *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    if (pthread_mutex_init(&p->lock, NULL) != 0) {
        free(p);
        return NULL;
    }
    atomic_init(&p->done, 0);
    return p;
}

void pgt_progress_destroy(pgt_progress *p) {
    if (!p) return;
    pthread_mutex_destroy(&p->lock);
    free(p);
}

void pgt_progress_stage(pgt_progress *p, const char *stage, uint64_t total, const char *unit) {
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    snprintf(p->stage, sizeof p->stage, "%s", stage ? stage : ""); /* cut to fit */
    snprintf(p->unit, sizeof p->unit, "%s", unit ? unit : "");
    p->total = total;
    p->stages++;
    atomic_store_explicit(&p->done, 0, memory_order_relaxed);
    pthread_mutex_unlock(&p->lock);
}

void pgt_progress_add(pgt_progress *p, uint64_t n) {
    if (p) atomic_fetch_add_explicit(&p->done, n, memory_order_relaxed);
}

void pgt_progress_raise(pgt_progress *p, uint64_t done) {
    if (!p) return;
    uint_least64_t cur = atomic_load_explicit(&p->done, memory_order_relaxed);
    while (cur < done && !atomic_compare_exchange_weak_explicit(&p->done, &cur, done,
                                                               memory_order_relaxed,
                                                               memory_order_relaxed)) {
    }
}

void pgt_progress_read(pgt_progress *p, pgt_progress_state *s) {
    memset(s, 0, sizeof *s);
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    memcpy(s->stage, p->stage, sizeof s->stage);
    memcpy(s->unit, p->unit, sizeof s->unit);
    s->total = p->total;
    s->stages = p->stages;
    s->done = atomic_load_explicit(&p->done, memory_order_relaxed);
    pthread_mutex_unlock(&p->lock);
}
