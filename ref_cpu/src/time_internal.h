/* pgt: the monotonic clock the reference's stage timings share. Private to ref_cpu. */
#ifndef PGT_TIME_INTERNAL_H
#define PGT_TIME_INTERNAL_H

#include <time.h>

/* Milliseconds of CLOCK_MONOTONIC (only differences mean anything). */
static inline double pgt_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

#endif
