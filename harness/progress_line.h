/* pgt harness: a progress line on stderr while a verb's long work runs.
 *
 * pgt_cli_progress_start creates a pgt_progress (pgt/progress.h) for the verb's computation and
 * a thread that, every PGT_PROGRESS_SECONDS seconds (default PGT_CLI_PROGRESS_DEFAULT_SECONDS)
 * after the start, prints one line of where the work stands:
 *   pgt ivy: terminals: 1890000 of 4608000 segments (41 %), 12 s
 *   pgt ivy: writing iv.ply (14.1 GiB), 31 s
 * One line each, not a line rewritten in place: a log keeps them readable. Work that ends
 * before the first period prints nothing, so short runs (and their one-line errors) look as
 * they did; PGT_PROGRESS_SECONDS=0 turns the lines off. The lines only observe: the output
 * bytes are the same with or without them. */
#ifndef PGT_PROGRESS_LINE_H
#define PGT_PROGRESS_LINE_H

#include <pthread.h>

#include "pgt/progress.h"

/* Seconds between progress lines (and before the first). */
#define PGT_CLI_PROGRESS_DEFAULT_SECONDS 5.0
/* Most seconds PGT_PROGRESS_SECONDS may ask for (a day), and fewest but 0 (a millisecond: a
 * shorter period would keep the thread busy catching up, not printing). */
#define PGT_CLI_PROGRESS_MAX_SECONDS 86400.0
#define PGT_CLI_PROGRESS_MIN_SECONDS 0.001

typedef struct pgt_cli_progress {
    pgt_progress *progress; /* hand to the computation; NULL when the lines are off */
    const char *verb;
    double start_ms, period_ms;
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake;
    int running, stop;
} pgt_cli_progress;

/* Starts the lines for `verb` (a string that outlives them). Without a thread (lines off, or
 * the thread could not start) p->progress is NULL and the work runs as it would without. A
 * PGT_PROGRESS_SECONDS that is neither 0 nor a number in [PGT_CLI_PROGRESS_MIN_SECONDS,
 * PGT_CLI_PROGRESS_MAX_SECONDS] is an error
 * (one line naming it, returns PGT_EXIT_USAGE; 0 otherwise). */
int pgt_cli_progress_start(pgt_cli_progress *p, const char *verb);

/* Starts a stage of unknown size named by printf's format (cut to PGT_PROGRESS_STAGE_MAX):
 * "reading %s", "writing %s (%u vertices)". Nothing is formatted when p is NULL (lines off). */
void pgt_cli_progress_stagef(pgt_progress *p, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Stops the thread (at once, without a last line) and frees the tracker; a p that never
 * started (zeroed) is a no-op. */
void pgt_cli_progress_stop(pgt_cli_progress *p);

/* No more lines from the running progress (if any) once this returns: pgt_cli_fail calls it
 * before its message, so that an error stays stderr's last line. */
void pgt_cli_progress_silence(void);

#endif
