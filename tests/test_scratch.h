/* pgt tests: file helpers every test program that reads or writes files shares: a scratch
 * folder made per case and removed with its contents at the end, and whole-file reading. */
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

/* The whole file at path (NULL when it cannot be read); *size gets its length. Free with free(). */
static inline void *load_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, len = 0;
    unsigned char *data = malloc(cap);
    while (data) {
        len += fread(data + len, 1, cap - len, f);
        if (len < cap) break;
        unsigned char *grown = realloc(data, cap *= 2);
        if (!grown) free(data);
        data = grown;
    }
    fclose(f);
    *size = len;
    return data;
}

#endif
