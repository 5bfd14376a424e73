/* pgt harness: progress lines (see progress_line.h). */
#include "progress_line.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"

/* The running lines (one verb a process, started and stopped on its main thread). */
static pgt_cli_progress *active_progress;

/* One line of where the work stands. */
static void print_line(const pgt_cli_progress *p) {
    pgt_progress_state s;
    pgt_progress_read(p->progress, &s);
    const double secs = (pgt_cli_now_ms() - p->start_ms) * 1e-3;
    const char *stage = s.stage[0] ? s.stage : "starting";
    if (s.total && s.done > s.total) s.done = s.total; /* see pgt_progress_read */
    if (s.total)
        fprintf(stderr, "pgt %s: %s: %llu of %llu %s (%.0f %%), %.0f s\n", p->verb, stage,
                (unsigned long long)s.done, (unsigned long long)s.total, s.unit,
                floor(100.0 * (double)s.done / (double)s.total), secs);
    else if (s.done)
        fprintf(stderr, "pgt %s: %s: %llu %s, %.0f s\n", p->verb, stage,
                (unsigned long long)s.done, s.unit, secs);
    else
        fprintf(stderr, "pgt %s: %s, %.0f s\n", p->verb, stage, secs);
}

/* The absolute CLOCK_MONOTONIC time ms milliseconds after the start. */
static struct timespec deadline(const pgt_cli_progress *p, double ms) {
    const double at = (p->start_ms + ms) * 1e-3;
    struct timespec ts;
    ts.tv_sec = (time_t)floor(at);
    ts.tv_nsec = (long)((at - floor(at)) * 1e9);
    if (ts.tv_nsec >= 1000000000L) ts.tv_sec++, ts.tv_nsec -= 1000000000L;
    return ts;
}

static void *run(void *vp) {
    pgt_cli_progress *p = vp;
    double next = p->period_ms;
    pthread_mutex_lock(&p->lock);
    while (!p->stop) {
        const struct timespec ts = deadline(p, next);
        const int rc = pthread_cond_timedwait(&p->wake, &p->lock, &ts);
        if (p->stop) break;
        if (rc == ETIMEDOUT) {
            print_line(p);
            /* the next period after now: a stalled machine does not get a burst of lines */
            const double now = pgt_cli_now_ms() - p->start_ms;
            while (next <= now) next += p->period_ms;
        }
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

int pgt_cli_progress_start(pgt_cli_progress *p, const char *verb) {
    memset(p, 0, sizeof *p);
    p->verb = verb;
    double secs = PGT_CLI_PROGRESS_DEFAULT_SECONDS;
    const char *env = getenv("PGT_PROGRESS_SECONDS");
    if (env && *env) {
        char *end = NULL;
        errno = 0;
        secs = strtod(env, &end);
        if (errno || *end ||
            !(secs == 0.0 ||
              (secs >= PGT_CLI_PROGRESS_MIN_SECONDS && secs <= PGT_CLI_PROGRESS_MAX_SECONDS)))
            return pgt_cli_fail(verb,
                                "the environment variable PGT_PROGRESS_SECONDS is '%s': give "
                                "seconds between progress lines, %g to %.0f (0: none)",
                                env, PGT_CLI_PROGRESS_MIN_SECONDS, PGT_CLI_PROGRESS_MAX_SECONDS);
    }
    if (secs == 0.0) return 0;
    p->period_ms = secs * 1e3;
    p->start_ms = pgt_cli_now_ms();
    if (!(p->progress = pgt_progress_create())) return 0;
    pthread_condattr_t attr;
    int ok = pthread_condattr_init(&attr) == 0;
    if (ok) {
        ok = pthread_condattr_setclock(&attr, CLOCK_MONOTONIC) == 0 &&
             pthread_cond_init(&p->wake, &attr) == 0;
        pthread_condattr_destroy(&attr);
    }
    if (ok && pthread_mutex_init(&p->lock, NULL) != 0) {
        pthread_cond_destroy(&p->wake);
        ok = 0;
    }
    if (ok && pthread_create(&p->thread, NULL, run, p) != 0) {
        pthread_mutex_destroy(&p->lock);
        pthread_cond_destroy(&p->wake);
        ok = 0;
    }
    if (!ok) { /* no lines: the work runs as without them */
        pgt_progress_destroy(p->progress);
        p->progress = NULL;
        return 0;
    }
    p->running = 1;
    active_progress = p;
    return 0;
}

void pgt_cli_progress_stagef(pgt_progress *p, const char *format, ...) {
    if (!p) return;
    char stage[PGT_PROGRESS_STAGE_MAX + 1];
    va_list ap;
    va_start(ap, format);
    vsnprintf(stage, sizeof stage, format, ap);
    va_end(ap);
    pgt_progress_stage(p, stage, 0, "");
}

/* Tells the thread to stop; once this returns it prints nothing more (it prints holding the
 * lock, and looks at stop before printing). */
static void request_stop(pgt_cli_progress *p) {
    pthread_mutex_lock(&p->lock);
    p->stop = 1;
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
}

void pgt_cli_progress_silence(void) {
    if (active_progress && active_progress->running) request_stop(active_progress);
}

void pgt_cli_progress_stop(pgt_cli_progress *p) {
    if (active_progress == p) active_progress = NULL;
    if (p->running) {
        request_stop(p);
        pthread_join(p->thread, NULL);
        pthread_mutex_destroy(&p->lock);
        pthread_cond_destroy(&p->wake);
        p->running = 0;
    }
    pgt_progress_destroy(p->progress);
    p->progress = NULL;
}
