/* pgt harness: what a run stopped by a signal leaves behind.
 *
 * Outputs are written to temporary names (PATH.tmp.PID beside PATH, or a staging folder
 * .pgt-stage.PID beside the outputs) and renamed when complete, so an interrupted run never
 * leaves a partial output under an output's name. Without more, a run stopped by Ctrl-C, kill
 * or timeout (SIGINT, SIGTERM, SIGHUP) would leave those temporary files: hundreds of MB for a
 * large subdivision. pgt_cli_signals_start (main) installs a handler for these signals that
 * passes them to a thread of its own; that thread removes every temporary name registered so
 * far and ends the process by the signal's default action (the exit status a shell shows for
 * it, 128 + the signal). The outputs' own paths are never removed: an output
 * renamed into place before the signal stays, one not yet renamed keeps what was there.
 *
 * The other threads go on while the thread removes the files: a writer that creates its
 * PATH.tmp.PID in the microseconds between the sweep and the end leaves it, and one whose file
 * was removed under it may print a write error before the process ends (still by the signal,
 * unless that error's exit comes first).
 *
 * The registrations (pgt_cli_check_outputs, pgt_cli_tmp_open and pgt_cli_stage_add make them)
 * are copies kept for the process's life; at most PGT_CLI_CLEANUP_MAX (further ones are not
 * kept: their temporary files would stay, as without this). */
#ifndef PGT_SIGNAL_CLEANUP_H
#define PGT_SIGNAL_CLEANUP_H

#define PGT_CLI_CLEANUP_MAX 256u

typedef enum pgt_cli_cleanup_kind {
    PGT_CLI_CLEANUP_TMP_OF = 0, /* remove PATH.tmp.PID (PATH is an output: kept) */
    PGT_CLI_CLEANUP_FILE = 1,   /* remove PATH and PATH.tmp.PID (PATH is a staging name) */
    PGT_CLI_CLEANUP_DIR = 2     /* rmdir PATH once the files are gone (a staging folder) */
} pgt_cli_cleanup_kind;

/* Registers `path` (copied; the same path and kind once). */
void pgt_cli_cleanup_add(const char *path, pgt_cli_cleanup_kind kind);

/* Starts the signal thread and installs the handlers (main calls it first). Returns 0, or -1
 * when the thread cannot start: the signals are then left as they were (no clean-up). */
int pgt_cli_signals_start(void);

/* A forked child (without the thread) back to the default actions of the signals the handler
 * took, so that they stop it as they would have. */
void pgt_cli_signals_default(void);

#endif
