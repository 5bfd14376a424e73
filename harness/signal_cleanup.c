/* pgt harness: removing temporary outputs when a signal stops the run (signal_cleanup.h). */
#include "signal_cleanup.h"

#include "pgt/result.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static pthread_mutex_t cleanup_lock = PTHREAD_MUTEX_INITIALIZER;
static char *cleanup_path[PGT_CLI_CLEANUP_MAX];
static uint8_t cleanup_kind[PGT_CLI_CLEANUP_MAX];
static uint32_t cleanup_count;

void pgt_cli_cleanup_add(const char *path, pgt_cli_cleanup_kind kind) {
    if (!path || !*path) return;
    pthread_mutex_lock(&cleanup_lock);
    uint32_t k = 0;
    while (k < cleanup_count && !(cleanup_kind[k] == kind && !strcmp(cleanup_path[k], path))) ++k;
    if (k == cleanup_count && k < PGT_CLI_CLEANUP_MAX) {
        const size_t n = strlen(path) + 1u;
        char *copy = malloc(n);
        if (copy) {
            memcpy(copy, path, n);
            cleanup_path[k] = copy, cleanup_kind[k] = (uint8_t)kind;
            cleanup_count++;
        }
    }
    pthread_mutex_unlock(&cleanup_lock);
}

/* Removes every registered temporary name: files first, then the (empty) folders. Runs on the
 * signal thread, an ordinary thread, so ordinary calls are allowed; the lock keeps a
 * registration from being half made while it reads. */
static void remove_registered(void) {
    pthread_mutex_lock(&cleanup_lock);
    char tmp[4400];
    for (uint32_t k = 0; k < cleanup_count; ++k) {
        if (cleanup_kind[k] == PGT_CLI_CLEANUP_DIR) continue;
        pgt_tmp_name(tmp, sizeof tmp, cleanup_path[k]);
        unlink(tmp);
        if (cleanup_kind[k] == PGT_CLI_CLEANUP_FILE) unlink(cleanup_path[k]);
    }
    for (uint32_t k = 0; k < cleanup_count; ++k)
        if (cleanup_kind[k] == PGT_CLI_CLEANUP_DIR) rmdir(cleanup_path[k]);
    /* the lock stays held: nothing registers anything more before the process ends */
}

/* The write end of the pipe the handler writes the signal to; the thread reads the other. */
static int signal_pipe[2] = {-1, -1};

/* Async-signal-safe: one byte down the pipe, nothing else. */
static void on_signal(int sig) {
    const unsigned char b = (unsigned char)sig;
    const int saved = errno;
    ssize_t w = write(signal_pipe[1], &b, 1);
    (void)w;
    errno = saved;
}

static const int handled[3] = {SIGINT, SIGTERM, SIGHUP};
static int handler_set[3];

/* One of the three (not handler_set, which is written after the handler is in place). */
static int is_handled(int sig) {
    for (int k = 0; k < 3; ++k)
        if (handled[k] == sig) return 1;
    return 0;
}

static void *wait_for_signal(void *arg) {
    (void)arg;
    unsigned char b = 0;
    for (;;) {
        const ssize_t n = read(signal_pipe[0], &b, 1);
        if (n == 1 && is_handled(b)) break;
        if (n < 0 && errno == EINTR) continue;
        if (n != 1) return NULL; /* the pipe is gone: nothing more will come */
    }
    const int sig = b;
    remove_registered();
    /* the signal's default action ends the process, as it would have without the handler */
    signal(sig, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    pthread_sigmask(SIG_UNBLOCK, &one, NULL);
    raise(sig);
    _exit(128 + sig); /* not reached */
}

/* A handler, not a mask and sigwait: a blocked mask would pass to the programs pgt starts (git,
 * the oracles, through popen), which Ctrl-C could then not stop; a handler is reset by exec.
 * SA_RESTART: the other threads' reads and writes go on. SIGINT, SIGTERM and SIGHUP, but not
 * one the process was started ignoring (a shell starts a background job with SIGINT ignored,
 * nohup with SIGHUP): that one stays ignored. */

/* fd moved to a descriptor >= 3 with close-on-exec: a process started with stdin, stdout or
 * stderr closed would otherwise get the pipe as one of them (what pgt printed would be read as
 * signals), and the programs pgt starts would inherit it. -1 on failure (fd closed). */
static int high_cloexec(int fd) {
    const int moved = fcntl(fd, F_DUPFD_CLOEXEC, 3);
    close(fd);
    return moved;
}

void pgt_cli_signals_default(void) {
    for (int k = 0; k < 3; ++k)
        if (handler_set[k]) signal(handled[k], SIG_DFL);
}

int pgt_cli_signals_start(void) {
    int fds[2];
    if (pipe(fds) != 0) return -1;
    signal_pipe[0] = high_cloexec(fds[0]), signal_pipe[1] = high_cloexec(fds[1]);
    if (signal_pipe[0] < 0 || signal_pipe[1] < 0) {
        if (signal_pipe[0] >= 0) close(signal_pipe[0]);
        if (signal_pipe[1] >= 0) close(signal_pipe[1]);
        signal_pipe[0] = signal_pipe[1] = -1;
        return -1;
    }
    pthread_t thread;
    pthread_attr_t attr;
    int ok = pthread_attr_init(&attr) == 0;
    if (ok) {
        ok = pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED) == 0 &&
             pthread_create(&thread, &attr, wait_for_signal, NULL) == 0;
        pthread_attr_destroy(&attr);
    }
    if (!ok) {
        close(signal_pipe[0]), close(signal_pipe[1]);
        signal_pipe[0] = signal_pipe[1] = -1;
        return -1;
    }
    for (int k = 0; k < 3; ++k) {
        struct sigaction sa;
        if (sigaction(handled[k], NULL, &sa) != 0 || sa.sa_handler == SIG_IGN) continue;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sa.sa_flags = SA_RESTART;
        sigemptyset(&sa.sa_mask);
        handler_set[k] = sigaction(handled[k], &sa, NULL) == 0;
    }
    return 0;
}
