/* pgt: how far a long computation has come, for a caller's progress line.
 *
 * A pgt_progress is shared by a computation and an observer. The computation names each stage
 * as it starts it (with the work it holds, when known) and adds the work it finished, from any
 * of its threads; the observer (pgt's command-line program prints a line every few seconds from
 * a thread of its own) reads a snapshot whenever it likes. Nothing here changes what the
 * computation computes: a NULL pgt_progress makes every call a no-op, and the stages' work is
 * counted in the computation's own units (seeds, segments), never timed.
 *
 * Threads: pgt_progress_add and pgt_progress_read may run on any thread at any time;
 * pgt_progress_stage replaces the stage under a lock (a reader sees the old stage or the new
 * one, never a mix). */
#ifndef PGT_PROGRESS_H
#define PGT_PROGRESS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Longest stage name kept (longer ones are cut). */
#define PGT_PROGRESS_STAGE_MAX 120u

typedef struct pgt_progress pgt_progress;

/* A snapshot: the stage's name and unit ("" before the first stage), the work done and the
 * stage's total (0: not known), and how many stages have started (it changes when the stage
 * does). */
typedef struct pgt_progress_state {
    char stage[PGT_PROGRESS_STAGE_MAX + 1];
    char unit[32];
    uint64_t done, total;
    uint32_t stages;
} pgt_progress_state;

/* A new tracker (NULL when out of memory: the callers' no-op). */
pgt_progress *pgt_progress_create(void);

/* Frees p (NULL: no-op). No thread may use it any more. */
void pgt_progress_destroy(pgt_progress *p);

/* Starts a stage: its name, its work in `unit`s (0: not known) and done = 0. */
void pgt_progress_stage(pgt_progress *p, const char *stage, uint64_t total, const char *unit);

/* Adds n units of finished work to the current stage. */
void pgt_progress_add(pgt_progress *p, uint64_t n);

/* Raises the current stage's work done to `done` (never lowers it: callers on several threads
 * may report fractions out of order). */
void pgt_progress_raise(pgt_progress *p, uint64_t done);

/* Reads a snapshot (zeroed with a NULL p). done is the count as added, never capped at total,
 * so that a test sees work counted twice; a display caps it itself (harness/progress_line.c):
 * work a thread adds to a stage just as the next one starts can land in the next. */
void pgt_progress_read(pgt_progress *p, pgt_progress_state *s);

#ifdef __cplusplus
}
#endif

#endif
