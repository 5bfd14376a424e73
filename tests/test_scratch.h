/* pgt tests: a scratch folder for files a case writes, made per case and removed with its
 * contents at the end (one copy for every test program that writes files). */
#ifndef PGT_TEST_SCRATCH_H
#define PGT_TEST_SCRATCH_H

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char scratch[256];

/* Makes /tmp/pgt_test_<tag>_XXXXXX (scratch is empty when that fails). */
static inline void scratch_make_for(const char *tag) {
    snprintf(scratch, sizeof(scratch), "/tmp/pgt_test_%s_XXXXXX", tag);
    if (!mkdtemp(scratch)) scratch[0] = '\0';
}

/* scratch/name, in a static buffer (valid until the next call). */
static inline const char *scratch_path(const char *name) {
    static char path[512];
    snprintf(path, sizeof(path), "%s/%s", scratch, name);
    return path;
}

/* Entries in the folder (-1 when it cannot be read). */
static inline int scratch_count(void) {
    DIR *d = opendir(scratch);
    int n = 0;
    if (!d) return -1;
    for (struct dirent *e; (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
    closedir(d);
    return n;
}

/* Removes the folder and what a case left in it (files and empty folders). */
static inline void scratch_remove(void) {
    DIR *d = opendir(scratch);
    if (!d) return;
    char path[512];
    for (struct dirent *e; (e = readdir(d));) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(path, sizeof(path), "%s/%s", scratch, e->d_name);
        if (remove(path) != 0) rmdir(path);
    }
    closedir(d);
    rmdir(scratch);
}

#endif
