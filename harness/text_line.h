/* pgt harness: one line of a text input (scene files, quad OBJs, ivy seed and stroke files).
 *
 * Header-only: pgt_datasets compiles facade_scene.c and facade_quads.c without the harness
 * library. fgets cannot tell a NUL byte from the end of the line (the line's C string ends at
 * the NUL and what follows is dropped or taken for an over-long line), so lines are read a byte
 * at a time and a NUL is its own error. */
#ifndef PGT_TEXT_LINE_H
#define PGT_TEXT_LINE_H

#include <stddef.h>
#include <stdio.h>
#include <string.h>

typedef enum pgt_text_line {
    PGT_TEXT_LINE_OK = 0, /* a line (the last one may lack its '\n') */
    PGT_TEXT_LINE_END,    /* no more lines (or a read error: check ferror) */
    PGT_TEXT_LINE_LONG,   /* more than size - 1 characters before the '\n' */
    PGT_TEXT_LINE_NUL     /* a NUL byte at column *out_len + 1 */
} pgt_text_line;

/* getc without a lock per byte where POSIX has it (a 90 MB OBJ read 1.35x slower with getc;
 * the readers keep a stream to one thread) */
#if defined(_POSIX_C_SOURCE) && _POSIX_C_SOURCE >= 200112L
#define PGT_TEXT_LINE_GETC getc_unlocked
#else
#define PGT_TEXT_LINE_GETC getc
#endif

/* Reads the next line of f into buf (size >= 4 bytes) as a C string without its '\n'; *out_len
 * gets its length (on PGT_TEXT_LINE_NUL, the characters before the NUL). A read error, at the
 * start of a line or inside one, is PGT_TEXT_LINE_END with ferror(f) set. With first_line (the
 * file's first line), a leading UTF-8 byte order mark (Windows editors such as Notepad before
 * 2019 begin a text file with one) is dropped before anything is counted: columns and the
 * length limit count from the text, as editors show them. */
static inline pgt_text_line pgt_text_line_read(FILE *f, char *buf, size_t size, size_t *out_len,
                                               int first_line) {
    size_t n = 0;
    int c = PGT_TEXT_LINE_GETC(f);
    if (c == EOF) {
        buf[0] = '\0', *out_len = 0;
        return PGT_TEXT_LINE_END;
    }
    for (; c != EOF && c != '\n'; c = PGT_TEXT_LINE_GETC(f)) {
        if (c == 0 || n + 1 >= size) {
            buf[n] = '\0', *out_len = n;
            return c == 0 ? PGT_TEXT_LINE_NUL : PGT_TEXT_LINE_LONG;
        }
        buf[n++] = (char)c;
        if (first_line && n == 3u && (unsigned char)buf[0] == 0xEFu &&
            (unsigned char)buf[1] == 0xBBu && (unsigned char)buf[2] == 0xBFu)
            n = 0, first_line = 0;
    }
    buf[n] = '\0', *out_len = n;
    return c == EOF && ferror(f) ? PGT_TEXT_LINE_END : PGT_TEXT_LINE_OK;
}

/* Room for pgt_text_line_message: a path as long as Linux allows (PATH_MAX, 4096) and the
 * rest. A reader that hands the message on through a pgt_error cuts it to that error's size. */
#define PGT_TEXT_LINE_MESSAGE (4096 + 128)

/* The message for a line pgt_text_line_read could not read as text (got: LONG or NUL), naming
 * the file, the line (1-based) and, for a NUL, its column: "PATH:LINE: line longer than MAX
 * characters" or "PATH:LINE:COL: a NUL byte (expected text)". */
static inline void pgt_text_line_message(pgt_text_line got, const char *path, unsigned line,
                                         size_t len, size_t max, char *msg, size_t size) {
    if (got == PGT_TEXT_LINE_NUL)
        snprintf(msg, size, "%s:%u:%zu: a NUL byte (expected text)", path, line, len + 1u);
    else
        snprintf(msg, size, "%s:%u: line longer than %zu characters", path, line, max);
}

#endif
