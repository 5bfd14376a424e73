/* pgt: private helpers shared by the OBJ, OFF and PLY readers and writers (mesh_io*.c).
 *
 * Readers parse a whole file held in memory, (data, size), with every access bounds-checked:
 * nothing here assumes the buffer is NUL-terminated, so pgt_mesh_read_memory needs no copy. */
#ifndef PGT_MESH_IO_INTERNAL_H
#define PGT_MESH_IO_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "pgt/mesh_io.h"

/* Longest number token copied to the stack for strtof (which needs a NUL-terminated copy); far
 * above the 17 digits plus sign and exponent any writer needs. Longer tokens are copied to the
 * heap: a decimal written out to thousands of digits is still a number. */
#define PGT_IO_MAX_NUMBER 255

/* ---- growable arrays ---- */

/* Returns data grown to hold at least `need` elements of `elem` bytes (doubling), updating
 * *cap; NULL on overflow or out of memory, leaving data valid. */
void *pgt_io_grow(void *data, size_t *cap, size_t need, size_t elem);

typedef struct pgt_io_u32vec {
    uint32_t *data;
    size_t len, cap;
} pgt_io_u32vec;

typedef struct pgt_io_f32vec {
    float *data;
    size_t len, cap;
} pgt_io_f32vec;

typedef struct pgt_io_i32vec {
    int32_t *data;
    size_t len, cap;
} pgt_io_i32vec;

typedef struct pgt_io_u64vec {
    uint64_t *data;
    size_t len, cap;
} pgt_io_u64vec;

#define PGT_IO_DEFINE_RESERVE(fn, type)                                                        \
    static inline int fn(type *v, size_t need) {                                               \
        if (need <= v->cap) return 0;                                                          \
        void *p = pgt_io_grow(v->data, &v->cap, need, sizeof(*v->data));                       \
        if (!p) return -1;                                                                     \
        v->data = p;                                                                           \
        return 0;                                                                              \
    }
PGT_IO_DEFINE_RESERVE(pgt_io_u32_reserve, pgt_io_u32vec)
PGT_IO_DEFINE_RESERVE(pgt_io_f32_reserve, pgt_io_f32vec)
PGT_IO_DEFINE_RESERVE(pgt_io_i32_reserve, pgt_io_i32vec)
PGT_IO_DEFINE_RESERVE(pgt_io_u64_reserve, pgt_io_u64vec)
#undef PGT_IO_DEFINE_RESERVE

/* ---- triangles collected while reading: polygons are fan-triangulated here ---- */

typedef struct pgt_io_tris {
    pgt_io_u32vec indices; /* 3 per triangle */
    pgt_io_u32vec aux;     /* 3 per triangle when use_aux (OBJ: each corner's vt or PGT_NONE) */
    pgt_io_f32vec uvs;     /* 6 per triangle when use_uvs */
    pgt_io_i32vec labels;  /* 1 per triangle when use_labels */
    pgt_io_u64vec where;   /* 1 per triangle when use_where: its face record's line or offset */
    pgt_io_u64vec vertex_where; /* when use_where: 1 per vertex, its record's line or offset
                                   (the reader reserves and fills it) */
    int use_aux, use_uvs, use_labels, use_where;
    size_t triangle_count;
    size_t polygon_count; /* faces with more than 3 corners */
} pgt_io_tris;

/* Adds the polygon v[0..n) (n >= 3) as the fan (v0, vi, vi+1), i = 1..n-2; aux/uv (2 floats per
 * corner) follow the corners, and label and where (the record's line, or its byte offset in
 * binary PLY) go to every triangle. Returns PGT_OK,
 * PGT_ERROR_OUT_OF_MEMORY or PGT_ERROR_LIMIT (more than PGT_MESH_MAX_ELEMENTS triangles); the
 * caller writes the message (see pgt_io_tris_problem). */
pgt_result pgt_io_tris_add(pgt_io_tris *t, const uint32_t *v, const uint32_t *aux, const float *uv,
                           int32_t label, uint64_t where, size_t n);
const char *pgt_io_tris_problem(pgt_result r);
void pgt_io_tris_free(pgt_io_tris *t);

/* Builds *out from positions (3 * vertex_count floats) and the triangles; uvs/labels are copied
 * when the builder uses them (OBJ fills uvs itself afterwards), and the triangles' and vertices'
 * record places move from t into *origin when it is not NULL (offsets: binary PLY). */
pgt_result pgt_io_finish(pgt_mesh *out, const float *positions, size_t vertex_count, pgt_io_tris *t,
                         int with_uvs, pgt_mesh_origin *origin, int offsets, const char *name,
                         pgt_error *err);

/* ---- text: lines and tokens ---- */

typedef struct pgt_io_text {
    const char *data;
    size_t size;
    size_t next;             /* offset of the next line */
    size_t line;             /* 1-based number of the current line, 0 before the first */
    const char *begin, *end; /* the current line, without its '\n' */
    int newline;             /* the current line ends with '\n' (not at end of file) */
} pgt_io_text;

static inline void pgt_io_text_init(pgt_io_text *t, const char *data, size_t size) {
    memset(t, 0, sizeof(*t));
    t->data = data;
    t->size = size;
}

/* A UTF-8 byte order mark: Windows editors (Notepad before 2019, some exporters) start a text
 * file with it. */
#define PGT_IO_UTF8_BOM "\xEF\xBB\xBF"

static inline int pgt_io_starts_with_bom(const char *data, size_t size) {
    return size >= 3 && memcmp(data, PGT_IO_UTF8_BOM, 3) == 0;
}

/* The text formats without a magic number (OBJ, OFF) read past a leading byte order mark; the
 * line numbers and byte offsets stay the file's. PLY's first bytes must be "ply" (Turk's
 * format): its reader names a mark there instead. */
static inline void pgt_io_text_skip_bom(pgt_io_text *t) {
    if (t->next == 0 && pgt_io_starts_with_bom(t->data, t->size)) t->next = 3;
}

/* Moves to the next line; 0 at the end of the data. */
static inline int pgt_io_text_next(pgt_io_text *t) {
    if (t->next >= t->size) return 0;
    const char *b = t->data + t->next;
    const char *nl = memchr(b, '\n', t->size - t->next);
    t->line++;
    t->begin = b;
    if (nl) {
        t->end = nl;
        t->newline = 1;
        t->next = (size_t)(nl - t->data) + 1;
    } else {
        t->end = t->data + t->size;
        t->newline = 0;
        t->next = t->size;
    }
    return 1;
}

static inline int pgt_io_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* The next whitespace-separated token of [*p, end): sets *tok and returns its length (0 when
 * none is left), advancing *p past it. */
static inline size_t pgt_io_token(const char **p, const char *end, const char **tok) {
    const char *s = *p;
    while (s < end && pgt_io_space(*s)) s++;
    const char *e = s;
    while (e < end && !pgt_io_space(*e)) e++;
    *tok = s;
    *p = e;
    return (size_t)(e - s);
}

/* End of the line's content before a '#' comment. */
static inline const char *pgt_io_strip_comment(const char *begin, const char *end) {
    const char *h = memchr(begin, '#', (size_t)(end - begin));
    return h ? h : end;
}

static inline int pgt_io_token_is(const char *tok, size_t n, const char *word) {
    size_t w = strlen(word);
    return n == w && memcmp(tok, word, n) == 0;
}

/* A float token (C locale strtof; rounding straight to float, so %.9g output round-trips).
 * PGT_OK, PGT_ERROR_PARSE (not entirely a number), PGT_ERROR_NOT_FINITE (nan, inf, or beyond
 * the float range such as 1e39 or 1e999) or PGT_ERROR_OUT_OF_MEMORY (a token too long to copy). */
pgt_result pgt_io_parse_float(const char *s, size_t n, float *out);

/* What a failed pgt_io_parse_float says of its token: "not a number", "not a finite float" or
 * "too long to copy (out of memory)". */
const char *pgt_io_float_problem(pgt_result r);

/* Any number strtod accepts, including nan and inf (values we skip): PGT_OK, PGT_ERROR_PARSE or
 * PGT_ERROR_OUT_OF_MEMORY (a token too long to copy; pgt_io_float_problem says which). */
pgt_result pgt_io_check_number(const char *s, size_t n);

/* A decimal integer with optional sign. 0: ok; 1: not an integer; 2: beyond +-INT64_MAX (then
 * *out is saturated to +-INT64_MAX, so range checks still reject it). */
int pgt_io_parse_i64(const char *s, size_t n, int64_t *out);

/* Copies a token for a message: at most ~24 characters, non-printable bytes as '?'. */
const char *pgt_io_quote(const char *s, size_t n, char *buf, size_t bufsize);

/* ---- errors with a location ---- */

/* "NAME:LINE: message" */
pgt_result pgt_io_fail_line(pgt_error *err, pgt_result code, const char *name, size_t line,
                            const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* "NAME: byte offset N: message" (binary PLY data) */
pgt_result pgt_io_fail_offset(pgt_error *err, pgt_result code, const char *name, size_t offset,
                              const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* ---- the formats ---- */

/* Prints "note: NAME: fan-triangulated N polygons" unless quiet or N == 0. */
void pgt_io_note_fan(const char *name, size_t polygons, int quiet);

/* The readers: origin (may be NULL) as in pgt_mesh_read_options. */
pgt_result pgt_io_read_obj(pgt_mesh *out, const char *data, size_t size, const char *name,
                           int quiet, pgt_mesh_origin *origin, pgt_error *err);
pgt_result pgt_io_read_off(pgt_mesh *out, const char *data, size_t size, const char *name,
                           int quiet, pgt_mesh_origin *origin, pgt_error *err);
pgt_result pgt_io_read_ply(pgt_mesh *out, const char *data, size_t size, const char *name,
                           int quiet, pgt_mesh_origin *origin, pgt_error *err);

/* Writers only write; the caller checks ferror/fclose and renames. */
void pgt_io_write_obj(FILE *f, const pgt_mesh *mesh, int precise);
void pgt_io_write_off(FILE *f, const pgt_mesh *mesh, int precise);
void pgt_io_write_ply(FILE *f, const pgt_mesh *mesh);
void pgt_io_write_ply_soup(FILE *f, const pgt_vertex_mesh *soup);

#endif
