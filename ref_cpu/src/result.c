/* pgt: result codes and first-error-wins messages. */
#include "pgt/result.h"

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *pgt_result_name(pgt_result code) {
    switch (code) {
    case PGT_OK:
        return "ok";
    case PGT_ERROR_INVALID_ARGUMENT:
        return "invalid_argument";
    case PGT_ERROR_OUT_OF_MEMORY:
        return "out_of_memory";
    case PGT_ERROR_IO:
        return "io";
    case PGT_ERROR_PARSE:
        return "parse";
    case PGT_ERROR_TRUNCATED:
        return "truncated";
    case PGT_ERROR_COUNT_MISMATCH:
        return "count_mismatch";
    case PGT_ERROR_INDEX_RANGE:
        return "index_range";
    case PGT_ERROR_NOT_FINITE:
        return "not_finite";
    case PGT_ERROR_LIMIT:
        return "limit";
    case PGT_ERROR_UNSUPPORTED:
        return "unsupported";
    case PGT_ERROR_EMPTY:
        return "empty";
    case PGT_ERROR_NON_MANIFOLD:
        return "non_manifold";
    case PGT_ERROR_DEGENERATE:
        return "degenerate";
    case PGT_ERROR_BACKEND:
        return "backend";
    }
    return "unknown";
}

pgt_result pgt_error_set(pgt_error *err, pgt_result code, const char *fmt, ...) {
    if (err && err->code == PGT_OK && code != PGT_OK) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof(err->message), fmt, ap);
        va_end(ap);
        /* one line whatever a file put into a name or a library into its text: control bytes
         * (a newline in an EXR channel name) become '?' */
        for (char *c = err->message; *c; ++c)
            if ((unsigned char)*c < 0x20u || *c == 0x7f) *c = '?';
        err->code = code;
    }
    return code;
}

void pgt_error_clear(pgt_error *err) {
    if (!err) return;
    err->code = PGT_OK;
    err->message[0] = '\0';
}

int pgt_tmp_name(char *tmp, size_t tmp_size, const char *path) {
    char suffix[32];
    const int ns = snprintf(suffix, sizeof suffix, ".tmp.%ld", (long)getpid());
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const size_t nb = strlen(base), nd = (size_t)(base - path);
    int n;
    if (nb + (size_t)ns <= PGT_NAME_MAX) {
        n = snprintf(tmp, tmp_size, "%s%s", path, suffix);
    } else {
        uint64_t h = 0xcbf29ce484222325ull; /* FNV-1a over the whole file name */
        for (size_t k = 0; k < nb; ++k) h = (h ^ (unsigned char)base[k]) * 0x100000001b3ull;
        size_t keep = PGT_NAME_MAX - (size_t)ns - 17u; /* '~' and 16 hex digits */
        while (keep > 0 && ((unsigned char)base[keep] & 0xC0u) == 0x80u) --keep;
        n = snprintf(tmp, tmp_size, "%.*s%.*s~%016llx%s", (int)nd, path, (int)keep, base,
                     (unsigned long long)h, suffix);
    }
    return n >= 0 && (size_t)n < tmp_size ? 0 : -1;
}

int pgt_replace_file(const char *tmp, const char *path) {
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        errno = S_ISDIR(st.st_mode) ? EISDIR : EPERM;
        return -1;
    }
    return rename(tmp, path) == 0 ? 0 : -1;
}

const char *pgt_path_name(const char *path) {
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

int pgt_path_folder(const char *path, char *buf, size_t size) {
    const char *slash = strrchr(path, '/');
    if (!slash || slash == path) return snprintf(buf, size, slash ? "/" : "."), 0;
    const size_t len = (size_t)(slash - path);
    if (len >= size) return snprintf(buf, size, "."), -1;
    snprintf(buf, size, "%.*s", (int)len, path);
    return 0;
}

int pgt_output_check(const char *path, char *why, size_t why_size) {
    struct stat st;
    if (!path[0]) { /* no file name at all */
        snprintf(why, why_size, "%s", strerror(ENOENT));
        return 1;
    }
    if (stat(path, &st) == 0) {
        if (S_ISREG(st.st_mode)) return 0;
        snprintf(why, why_size, "it is %s, not a regular file",
                 S_ISDIR(st.st_mode) ? "a folder" : "a device, fifo or socket");
        return 1;
    }
    int e = 0;
    char dir[4096];
    if (errno == ENAMETOOLONG || strlen(pgt_path_name(path)) > PGT_NAME_MAX ||
        pgt_path_folder(path, dir, sizeof dir) != 0)
        e = ENAMETOOLONG; /* also on a file system that answers ENOENT for a name it cannot hold */
    else if (stat(dir, &st) != 0)
        e = errno;
    else if (!S_ISDIR(st.st_mode))
        e = ENOTDIR;
    else if (access(dir, W_OK | X_OK) != 0)
        e = errno;
    if (!e) return 0;
    snprintf(why, why_size, "%s", strerror(e));
    return 1;
}
