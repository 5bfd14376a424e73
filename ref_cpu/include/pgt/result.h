/* pgt: result codes and error messages shared by every reference module.
 *
 * Every function that can fail on user input returns a pgt_result and, when given a pgt_error,
 * fills it with a one-line message that names the file and line (or byte offset, flag, element).
 * Broken contracts between our own functions are asserts instead (see ../shared/STYLE.md). */
#ifndef PGT_RESULT_H
#define PGT_RESULT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Sentinel for "no element" in every uint32 index array (a border half-edge's opposite, a
 * root's parent, ...), here so that every header using it gets it through result.h. */
#define PGT_NONE 0xFFFFFFFFu

typedef enum pgt_result {
    PGT_OK = 0,
    PGT_ERROR_INVALID_ARGUMENT = 1, /* a caller or flag passed a value outside the contract */
    PGT_ERROR_OUT_OF_MEMORY = 2,
    PGT_ERROR_IO = 3,             /* a file could not be opened, read, written or renamed */
    PGT_ERROR_PARSE = 4,          /* a token is not what the format allows at that place */
    PGT_ERROR_TRUNCATED = 5,      /* the input ends before what its header promised */
    PGT_ERROR_COUNT_MISMATCH = 6, /* a declared count disagrees with the data */
    PGT_ERROR_INDEX_RANGE = 7,    /* an index is zero (OBJ), negative past the start, or too big */
    PGT_ERROR_NOT_FINITE = 8,     /* a coordinate is NaN or infinite */
    PGT_ERROR_LIMIT = 9,          /* a declared or produced size exceeds what pgt supports */
    PGT_ERROR_UNSUPPORTED = 10,   /* valid input that uses a feature pgt does not read */
    PGT_ERROR_EMPTY = 11,         /* the input holds no faces */
    PGT_ERROR_NON_MANIFOLD = 12,  /* an operation that needs a 2-manifold met a bad edge/vertex */
    PGT_ERROR_DEGENERATE = 13,    /* a face repeats a vertex */
    PGT_ERROR_BACKEND = 14        /* a GPU API call failed */
} pgt_result;

#define PGT_ERROR_MESSAGE_SIZE 512

typedef struct pgt_error {
    pgt_result code;
    char message[PGT_ERROR_MESSAGE_SIZE];
} pgt_error;

/* Stable lower-case name of a code ("ok", "parse", ...), for messages and JSON. */
const char *pgt_result_name(pgt_result code);

/* Records the first error only: a later call on an error that already holds one keeps the first
 * (embree's rtcGetDeviceError model). err may be NULL. The message is one line: control bytes
 * in it (from names in a file, a library's text) are replaced by '?'. Returns code, so callers can
 * write `return pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: ...", path, line);`. */
pgt_result pgt_error_set(pgt_error *err, pgt_result code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Clears err to PGT_OK and an empty message. err may be NULL. */
void pgt_error_clear(pgt_error *err);

/* Longest file name (one path component) an output may have: Linux's NAME_MAX. */
#define PGT_NAME_MAX 255

/* The temporary name every pgt writer puts an output under in its folder before
 * pgt_replace_file renames it over path: PATH.tmp.PID. When path's file name is too long for
 * that suffix (over PGT_NAME_MAX with it, which the output itself is not), the file name is cut
 * (at a UTF-8 character's start) and 16 hex digits of a hash of the whole name added, so that a
 * name of up to PGT_NAME_MAX bytes can be written: NAME-CUT~HASH.tmp.PID. Never longer than
 * strlen(path) + 32 bytes with its NUL. Returns 0, or -1 when it does not fit tmp_size. */
int pgt_tmp_name(char *tmp, size_t tmp_size, const char *path);

/* Finishes an output written under a temporary name in its folder (PATH.tmp.PID): renames tmp
 * over path, which replaces path atomically. Returns 0, or -1 with errno set and tmp left for the
 * caller to remove; errno is EPERM (EISDIR for a folder) when path exists and is not a regular
 * file: a rename would replace a device such as /dev/null, or a fifo, by a regular file (run as
 * root, the device would be gone), so every pgt writer refuses such a path. */
int pgt_replace_file(const char *tmp, const char *path);

/* The file-name part of path: what follows its last '/', or path itself. */
const char *pgt_path_name(const char *path);

/* The folder part of path into buf: "." without a '/', "/" for a file at the root. Returns 0, or
 * -1 (buf holding ".") when it does not fit size. */
int pgt_path_folder(const char *path, char *buf, size_t size);

/* Before a long run: 0 when path can be written as far as can be told now (an existing regular
 * file, or a new name of at most PGT_NAME_MAX bytes in an existing folder this process may write
 * to); else nonzero with the reason in why ("it is a folder, not a regular file", or strerror's
 * words, those the final write would use). The final write still checks: the file system may
 * change meanwhile. */
int pgt_output_check(const char *path, char *why, size_t why_size);

#ifdef __cplusplus
}
#endif

#endif
