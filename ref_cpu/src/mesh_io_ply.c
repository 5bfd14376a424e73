/* pgt: PLY (Polygon File Format) reading and writing.
 *
 * Based on Greg Turk, "The PLY Polygon File Format" (1994): a text header ("ply", "format",
 * "element NAME COUNT", "property TYPE NAME", "property list COUNT_TYPE VALUE_TYPE NAME",
 * "comment", "obj_info", "end_header") followed by the element instances in header order, as
 * text (one instance per line, as every common writer emits it) or binary.
 * pgt reads ascii 1.0 and binary_little_endian 1.0 and writes binary_little_endian 1.0.
 * Binary values are decoded byte by byte, so the reader and writer do not depend on the host's
 * byte order. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io_internal.h"

/* Header limits: far above real files (3D Gaussian splat files have ~62 vertex properties). */
#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPERTIES 256

/* Shortest ascii token plus its separator ("0 "): the size check for ascii data. */
#define PLY_MIN_ASCII_VALUE_BYTES 2u

/* The largest double that rounds to a finite float (FLT_MAX plus half an ulp rounds to inf). */
#define PLY_FLOAT_OVERFLOW 0x1.ffffffp+127

typedef enum ply_type {
    PLY_INT8 = 1,
    PLY_UINT8,
    PLY_INT16,
    PLY_UINT16,
    PLY_INT32,
    PLY_UINT32,
    PLY_FLOAT32,
    PLY_FLOAT64
} ply_type;

static const struct {
    const char *name;
    ply_type type;
} ply_type_names[] = {
    {"char", PLY_INT8},      {"int8", PLY_INT8},       {"uchar", PLY_UINT8},
    {"uint8", PLY_UINT8},    {"short", PLY_INT16},     {"int16", PLY_INT16},
    {"ushort", PLY_UINT16},  {"uint16", PLY_UINT16},   {"int", PLY_INT32},
    {"int32", PLY_INT32},    {"uint", PLY_UINT32},     {"uint32", PLY_UINT32},
    {"float", PLY_FLOAT32},  {"float32", PLY_FLOAT32}, {"double", PLY_FLOAT64},
    {"float64", PLY_FLOAT64},
};

static size_t ply_size(ply_type t) {
    switch (t) {
    case PLY_INT8:
    case PLY_UINT8: return 1;
    case PLY_INT16:
    case PLY_UINT16: return 2;
    case PLY_FLOAT64: return 8;
    default: return 4;
    }
}

static int ply_is_int(ply_type t) { return t != PLY_FLOAT32 && t != PLY_FLOAT64; }

static const char *ply_type_name(ply_type t) {
    for (size_t i = 0; i < sizeof(ply_type_names) / sizeof(ply_type_names[0]); i += 2)
        if (ply_type_names[i].type == t) return ply_type_names[i].name;
    return "?";
}

static int ply_parse_type(const char *tok, size_t n, ply_type *out) {
    for (size_t i = 0; i < sizeof(ply_type_names) / sizeof(ply_type_names[0]); ++i)
        if (pgt_io_token_is(tok, n, ply_type_names[i].name)) {
            *out = ply_type_names[i].type;
            return 1;
        }
    return 0;
}

typedef enum ply_role {
    ROLE_SKIP,
    ROLE_X,
    ROLE_Y,
    ROLE_Z,
    ROLE_INDICES,
    ROLE_GROUP,
    ROLE_TEXCOORD,
    ROLE_VERTEX_U, /* per-vertex texture coordinates (u v, s t or texture_u texture_v) */
    ROLE_VERTEX_V
} ply_role;
typedef enum ply_kind { KIND_OTHER, KIND_VERTEX, KIND_FACE } ply_kind;

typedef struct ply_prop {
    const char *name;
    size_t name_len;
    int is_list;
    ply_type count_type, type;
    ply_role role;
    size_t line;
} ply_prop;

typedef struct ply_elem {
    const char *name;
    size_t name_len;
    uint64_t count;
    ply_kind kind;
    size_t line;
    size_t nprops;
    ply_prop props[PLY_MAX_PROPERTIES];
} ply_elem;

typedef struct ply_header {
    int binary;
    size_t nelems;
    ply_elem elems[PLY_MAX_ELEMENTS];
    ply_elem *vertex, *face;
    int vertex_uv;     /* the vertex element has a pair of texture coordinates */
    size_t end_line;   /* line of end_header */
    size_t data_start; /* offset of the first data byte */
} ply_header;

/* Where values come from: binary bytes or the tokens of the current ascii line. */
typedef struct ply_in {
    const char *name;
    pgt_error *err;
    int binary;
    const unsigned char *data;
    size_t size, pos;
    pgt_io_text text;
    const char *p, *end;
    /* the value being read, for messages */
    const ply_elem *elem;
    uint64_t instance;
    const ply_prop *prop;
} ply_in;

static pgt_result ply_fail(ply_in *in, size_t offset, pgt_result code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

static pgt_result ply_fail(ply_in *in, size_t offset, pgt_result code, const char *fmt, ...) {
    char msg[PGT_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    static const char where[] = "%.*s %llu, property '%.*s': %s";
    const int elen = (int)in->elem->name_len, plen = (int)in->prop->name_len;
    const unsigned long long i = (unsigned long long)in->instance;
    if (in->binary)
        return pgt_io_fail_offset(in->err, code, in->name, offset, where, elen, in->elem->name, i,
                                  plen, in->prop->name, msg);
    return pgt_io_fail_line(in->err, code, in->name, in->text.line, where, elen, in->elem->name, i,
                            plen, in->prop->name, msg);
}

static uint64_t load_le(const unsigned char *p, size_t size) {
    uint64_t v = 0;
    for (size_t i = size; i-- > 0;) v = (v << 8) | p[i];
    return v;
}

/* Binary: checks that `bytes` more bytes exist. */
static pgt_result ply_need(ply_in *in, uint64_t bytes, const char *what) {
    if (bytes > in->size - in->pos)
        return ply_fail(in, in->pos, PGT_ERROR_TRUNCATED,
                        "file ends inside the %s (%llu bytes needed, %zu left)", what,
                        (unsigned long long)bytes, in->size - in->pos);
    return PGT_OK;
}

/* Ascii: the next token of the line, or a parse error naming what was expected. */
static pgt_result ply_token(ply_in *in, const char **tok, size_t *n, const char *what) {
    *n = pgt_io_token(&in->p, in->end, tok);
    if (*n == 0) return ply_fail(in, 0, PGT_ERROR_PARSE, "line ends before the %s", what);
    return PGT_OK;
}

static pgt_result ply_read_int(ply_in *in, ply_type type, const char *what, int64_t *out) {
    if (in->binary) {
        size_t at = in->pos, size = ply_size(type);
        pgt_result r = ply_need(in, size, what);
        if (r != PGT_OK) return r;
        uint64_t u = load_le(in->data + at, size);
        in->pos += size;
        switch (type) {
        case PLY_INT8: *out = (int64_t)(int8_t)(uint8_t)u; break;
        case PLY_INT16: *out = (int64_t)(int16_t)(uint16_t)u; break;
        case PLY_INT32: *out = (int64_t)(int32_t)(uint32_t)u; break;
        default: *out = (int64_t)u; break;
        }
        return PGT_OK;
    }
    const char *tok;
    size_t n;
    char q[32];
    pgt_result r = ply_token(in, &tok, &n, what);
    if (r != PGT_OK) return r;
    int64_t v = 0;
    if (pgt_io_parse_i64(tok, n, &v) == 1)
        return ply_fail(in, 0, PGT_ERROR_PARSE, "%s '%s' is not an integer", what,
                        pgt_io_quote(tok, n, q, sizeof(q)));
    int64_t lo = 0, hi = 0;
    switch (type) {
    case PLY_INT8: lo = INT8_MIN, hi = INT8_MAX; break;
    case PLY_UINT8: lo = 0, hi = UINT8_MAX; break;
    case PLY_INT16: lo = INT16_MIN, hi = INT16_MAX; break;
    case PLY_UINT16: lo = 0, hi = UINT16_MAX; break;
    case PLY_INT32: lo = INT32_MIN, hi = INT32_MAX; break;
    default: lo = 0, hi = UINT32_MAX; break;
    }
    if (v < lo || v > hi)
        return ply_fail(in, 0, PGT_ERROR_PARSE, "%s '%s' is outside the range of %s", what,
                        pgt_io_quote(tok, n, q, sizeof(q)), ply_type_name(type));
    *out = v;
    return PGT_OK;
}

static pgt_result ply_read_real(ply_in *in, ply_type type, const char *what, float *out) {
    if (in->binary) {
        size_t at = in->pos, size = ply_size(type);
        pgt_result r = ply_need(in, size, what);
        if (r != PGT_OK) return r;
        uint64_t u = load_le(in->data + at, size);
        in->pos += size;
        if (type == PLY_FLOAT32) {
            uint32_t u32 = (uint32_t)u;
            memcpy(out, &u32, sizeof(*out));
            if (!isfinite(*out))
                return ply_fail(in, at, PGT_ERROR_NOT_FINITE, "%s is not finite", what);
        } else {
            double d;
            memcpy(&d, &u, sizeof(d));
            if (!isfinite(d) || fabs(d) >= PLY_FLOAT_OVERFLOW)
                return ply_fail(in, at, PGT_ERROR_NOT_FINITE, "%s %g is not a finite float", what,
                                d);
            *out = (float)d;
        }
        return PGT_OK;
    }
    const char *tok;
    size_t n;
    char q[32];
    pgt_result r = ply_token(in, &tok, &n, what);
    if (r != PGT_OK) return r;
    r = pgt_io_parse_float(tok, n, out);
    if (r != PGT_OK)
        return ply_fail(in, 0, r, "%s '%s' is %s", what, pgt_io_quote(tok, n, q, sizeof(q)),
                        pgt_io_float_problem(r));
    return PGT_OK;
}

static pgt_result ply_skip_values(ply_in *in, ply_type type, uint64_t count, const char *what) {
    if (in->binary) {
        pgt_result r = ply_need(in, count * ply_size(type), what);
        if (r == PGT_OK) in->pos += (size_t)count * ply_size(type);
        return r;
    }
    for (uint64_t i = 0; i < count; ++i) {
        const char *tok;
        size_t n;
        char q[32];
        pgt_result r = ply_token(in, &tok, &n, what);
        if (r != PGT_OK) return r;
        const pgt_result cr = pgt_io_check_number(tok, n);
        if (cr != PGT_OK)
            return ply_fail(in, 0, cr, "%s '%s' is %s", what, pgt_io_quote(tok, n, q, sizeof(q)),
                            pgt_io_float_problem(cr));
    }
    return PGT_OK;
}

/* A list's length: an integer that is not negative and, in binary, whose values fit the file. */
static pgt_result ply_list_count(ply_in *in, const ply_prop *prop, uint64_t *out) {
    size_t at = in->pos;
    int64_t c = 0;
    pgt_result r = ply_read_int(in, prop->count_type, "list length", &c);
    if (r != PGT_OK) return r;
    if (c < 0) return ply_fail(in, at, PGT_ERROR_PARSE, "negative list length %lld", (long long)c);
    *out = (uint64_t)c;
    if (in->binary) return ply_need(in, *out * ply_size(prop->type), "list");
    return PGT_OK;
}

/* ---- header ---- */

static pgt_result header_fail(pgt_error *err, pgt_result code, const char *name, size_t line,
                              const char *what, const char *tok, size_t n) {
    char q[32];
    return pgt_io_fail_line(err, code, name, line, "%s '%s'", what,
                            pgt_io_quote(tok, n, q, sizeof(q)));
}

static pgt_result parse_header(ply_header *h, const char *data, size_t size, const char *name,
                               pgt_error *err) {
    pgt_io_text t;
    const char *p, *tok;
    size_t n;
    int have_format = 0;
    pgt_io_text_init(&t, data, size);
    if (size == 0) return pgt_io_fail_line(err, PGT_ERROR_EMPTY, name, 1, "file is empty");
    pgt_io_text_next(&t);
    p = t.begin;
    n = pgt_io_token(&p, t.end, &tok);
    if (!pgt_io_token_is(tok, n, "ply") || pgt_io_token(&p, t.end, &tok) != 0)
        return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, 1,
                                pgt_io_starts_with_bom(data, size)
                                    ? "not a PLY file (the first line is not 'ply': it starts "
                                      "with a UTF-8 byte order mark; save it without one)"
                                    : "not a PLY file (the first line is not 'ply')");
    for (;;) {
        if (!pgt_io_text_next(&t) || !t.newline)
            return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                    "file ends inside the header (no end_header line)");
        p = t.begin;
        n = pgt_io_token(&p, t.end, &tok);
        if (n == 0 || pgt_io_token_is(tok, n, "comment") || pgt_io_token_is(tok, n, "obj_info"))
            continue;
        const char *a[5];
        size_t an[5], args = 0;
        while (args < 5 && (an[args] = pgt_io_token(&p, t.end, &a[args])) > 0) args++;
        if (pgt_io_token_is(tok, n, "end_header")) {
            if (args != 0)
                return header_fail(err, PGT_ERROR_PARSE, name, t.line, "unexpected text after",
                                   tok, n);
            break;
        } else if (pgt_io_token_is(tok, n, "format")) {
            if (have_format)
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line, "second format line");
            if (args != 2)
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                        "format line must be 'format TYPE 1.0'");
            if (pgt_io_token_is(a[0], an[0], "ascii")) h->binary = 0;
            else if (pgt_io_token_is(a[0], an[0], "binary_little_endian")) h->binary = 1;
            else if (pgt_io_token_is(a[0], an[0], "binary_big_endian"))
                return pgt_io_fail_line(err, PGT_ERROR_UNSUPPORTED, name, t.line,
                                        "binary_big_endian PLY is not supported (pgt reads ascii "
                                        "and binary_little_endian)");
            else
                return header_fail(err, PGT_ERROR_PARSE, name, t.line, "unknown PLY format", a[0],
                                   an[0]);
            if (!pgt_io_token_is(a[1], an[1], "1.0"))
                return header_fail(err, PGT_ERROR_UNSUPPORTED, name, t.line,
                                   "unsupported PLY version", a[1], an[1]);
            have_format = 1;
        } else if (pgt_io_token_is(tok, n, "element")) {
            if (!have_format)
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                        "element before the format line");
            if (args != 2)
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                        "element line must be 'element NAME COUNT'");
            int64_t count = 0;
            if (pgt_io_parse_i64(a[1], an[1], &count) == 1 || count < 0)
                return header_fail(err, PGT_ERROR_PARSE, name, t.line,
                                   "element count is not a non-negative integer:", a[1], an[1]);
            if (count > PGT_MESH_MAX_ELEMENTS) /* the count as written (one past int64 saturates) */
                return pgt_io_fail_line(err, PGT_ERROR_LIMIT, name, t.line,
                                        "element '%.*s' count %.*s is above the pgt limit of %u",
                                        (int)an[0], a[0], (int)(an[1] < 40 ? an[1] : 40), a[1],
                                        PGT_MESH_MAX_ELEMENTS);
            if (h->nelems == PLY_MAX_ELEMENTS)
                return pgt_io_fail_line(err, PGT_ERROR_LIMIT, name, t.line,
                                        "more than %d elements", PLY_MAX_ELEMENTS);
            ply_elem *e = &h->elems[h->nelems++];
            e->name = a[0];
            e->name_len = an[0];
            e->count = (uint64_t)count;
            e->line = t.line;
            e->kind = pgt_io_token_is(a[0], an[0], "vertex") ? KIND_VERTEX
                      : pgt_io_token_is(a[0], an[0], "face") ? KIND_FACE
                                                             : KIND_OTHER;
            if ((e->kind == KIND_VERTEX && h->vertex) || (e->kind == KIND_FACE && h->face))
                return header_fail(err, PGT_ERROR_PARSE, name, t.line, "second element", a[0],
                                   an[0]);
            if (e->kind == KIND_VERTEX) h->vertex = e;
            if (e->kind == KIND_FACE) h->face = e;
        } else if (pgt_io_token_is(tok, n, "property")) {
            if (h->nelems == 0)
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                        "property before any element");
            ply_elem *e = &h->elems[h->nelems - 1];
            if (e->nprops == PLY_MAX_PROPERTIES)
                return pgt_io_fail_line(err, PGT_ERROR_LIMIT, name, t.line,
                                        "more than %d properties in one element",
                                        PLY_MAX_PROPERTIES);
            ply_prop *pr = &e->props[e->nprops];
            memset(pr, 0, sizeof(*pr));
            pr->line = t.line;
            size_t ni;
            if (args >= 1 && pgt_io_token_is(a[0], an[0], "list")) {
                if (args != 4)
                    return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                            "list property must be 'property list COUNT_TYPE "
                                            "VALUE_TYPE NAME'");
                pr->is_list = 1;
                if (!ply_parse_type(a[1], an[1], &pr->count_type))
                    return header_fail(err, PGT_ERROR_PARSE, name, t.line, "unknown type", a[1],
                                       an[1]);
                if (!ply_is_int(pr->count_type))
                    return header_fail(err, PGT_ERROR_PARSE, name, t.line,
                                       "list length type must be an integer type, not", a[1],
                                       an[1]);
                if (!ply_parse_type(a[2], an[2], &pr->type))
                    return header_fail(err, PGT_ERROR_PARSE, name, t.line, "unknown type", a[2],
                                       an[2]);
                ni = 3;
            } else {
                if (args != 2)
                    return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                            "property must be 'property TYPE NAME'");
                if (!ply_parse_type(a[0], an[0], &pr->type))
                    return header_fail(err, PGT_ERROR_PARSE, name, t.line, "unknown type", a[0],
                                       an[0]);
                ni = 1;
            }
            pr->name = a[ni];
            pr->name_len = an[ni];
            for (size_t i = 0; i < e->nprops; ++i)
                if (e->props[i].name_len == pr->name_len &&
                    memcmp(e->props[i].name, pr->name, pr->name_len) == 0)
                    return header_fail(err, PGT_ERROR_PARSE, name, t.line, "second property",
                                       pr->name, pr->name_len);
            e->nprops++;
        } else {
            return header_fail(err, PGT_ERROR_PARSE, name, t.line, "unknown PLY header keyword",
                               tok, n);
        }
    }
    h->end_line = t.line;
    h->data_start = t.next;
    if (!have_format)
        return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line, "header has no format line");

    /* Roles: what we read, and whether the types allow it. */
    if (!h->vertex)
        return pgt_io_fail_line(err, h->face ? PGT_ERROR_PARSE : PGT_ERROR_EMPTY, name, t.line,
                                "header has no 'vertex' element%s", h->face ? "" : " and no faces");
    static const char *const xyz[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
        ply_prop *found = NULL;
        for (size_t i = 0; i < h->vertex->nprops; ++i)
            if (pgt_io_token_is(h->vertex->props[i].name, h->vertex->props[i].name_len, xyz[k]))
                found = &h->vertex->props[i];
        if (!found)
            return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, h->vertex->line,
                                    "vertex element has no property '%s'", xyz[k]);
        if (found->is_list)
            return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, found->line,
                                    "vertex property '%s' is a list", xyz[k]);
        if (ply_is_int(found->type))
            return pgt_io_fail_line(err, PGT_ERROR_UNSUPPORTED, name, found->line,
                                    "vertex property '%s' is %s (pgt reads float or double)",
                                    xyz[k], ply_type_name(found->type));
        found->role = (ply_role)(ROLE_X + k);
    }
    /* Per-vertex texture coordinates, the first pair present (pgt's own soups write u and v):
     * used when the faces carry no texcoord list, which can hold seams where these cannot. */
    static const char *const uv_names[3][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}};
    for (int p = 0; p < 3 && !h->vertex_uv; ++p) {
        ply_prop *found[2] = {NULL, NULL};
        for (size_t i = 0; i < h->vertex->nprops; ++i)
            for (int k = 0; k < 2; ++k)
                if (pgt_io_token_is(h->vertex->props[i].name, h->vertex->props[i].name_len,
                                    uv_names[p][k]))
                    found[k] = &h->vertex->props[i];
        if (!found[0] || !found[1]) continue;
        for (int k = 0; k < 2; ++k) {
            if (found[k]->is_list || ply_is_int(found[k]->type))
                return pgt_io_fail_line(err, PGT_ERROR_UNSUPPORTED, name, found[k]->line,
                                        "vertex property '%s' is a %s%s (texture coordinates are "
                                        "float or double)",
                                        uv_names[p][k], found[k]->is_list ? "list of " : "",
                                        ply_type_name(found[k]->type));
            found[k]->role = (ply_role)(ROLE_VERTEX_U + k);
        }
        h->vertex_uv = 1;
    }
    if (!h->face)
        return pgt_io_fail_line(err, PGT_ERROR_EMPTY, name, t.line,
                                "header has no 'face' element (no faces)");
    for (size_t i = 0; i < h->face->nprops; ++i) {
        ply_prop *pr = &h->face->props[i];
        if (pgt_io_token_is(pr->name, pr->name_len, "vertex_indices") ||
            pgt_io_token_is(pr->name, pr->name_len, "vertex_index")) {
            for (size_t j = 0; j < i; ++j)
                if (h->face->props[j].role == ROLE_INDICES)
                    return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, pr->line,
                                            "face element has both vertex_indices and "
                                            "vertex_index");
            if (!pr->is_list || !ply_is_int(pr->type))
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, pr->line,
                                        "face property '%.*s' must be a list of integers",
                                        (int)pr->name_len, pr->name);
            pr->role = ROLE_INDICES;
        } else if (pgt_io_token_is(pr->name, pr->name_len, "group")) {
            if (pr->is_list || !ply_is_int(pr->type))
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, pr->line,
                                        "face property 'group' must be an integer scalar");
            pr->role = ROLE_GROUP;
        } else if (pgt_io_token_is(pr->name, pr->name_len, "texcoord")) {
            if (!pr->is_list || ply_is_int(pr->type))
                return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, pr->line,
                                        "face property 'texcoord' must be a list of float or "
                                        "double");
            pr->role = ROLE_TEXCOORD;
        }
    }
    int has_indices = 0;
    for (size_t i = 0; i < h->face->nprops; ++i)
        has_indices |= h->face->props[i].role == ROLE_INDICES;
    if (!has_indices)
        return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, h->face->line,
                                "face element has no 'vertex_indices' (or 'vertex_index') list");
    if (h->face->count == 0)
        return pgt_io_fail_line(err, PGT_ERROR_EMPTY, name, h->face->line,
                                "header declares no faces");

    /* Every instance takes at least this many bytes (lists counted as empty, so that a short
     * face is still reported as such): counts the file cannot hold are rejected before anything
     * is allocated. */
    uint64_t need = 0;
    for (size_t i = 0; i < h->nelems; ++i) {
        const ply_elem *e = &h->elems[i];
        uint64_t per = 0;
        for (size_t j = 0; j < e->nprops; ++j) {
            const ply_prop *pr = &e->props[j];
            per += !h->binary      ? PLY_MIN_ASCII_VALUE_BYTES
                   : pr->is_list ? ply_size(pr->count_type)
                                 : ply_size(pr->type);
        }
        need += per * e->count;
    }
    if (need > size - h->data_start)
        return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                "header declares elements that need at least %llu bytes, but only "
                                "%zu follow",
                                (unsigned long long)need, size - h->data_start);
    return PGT_OK;
}

/* Ascii: moves to the next non-blank line. */
static int ascii_next_line(pgt_io_text *t) {
    while (pgt_io_text_next(t)) {
        const char *s = t->begin;
        while (s < t->end && pgt_io_space(*s)) s++;
        if (s < t->end) return 1;
    }
    return 0;
}

pgt_result pgt_io_read_ply(pgt_mesh *out, const char *data, size_t size, const char *name,
                           int quiet, pgt_mesh_origin *origin, pgt_error *err) {
    ply_header *h = calloc(1, sizeof(*h));
    if (!h) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    pgt_result r = parse_header(h, data, size, name, err);
    if (r != PGT_OK) {
        free(h);
        return r;
    }
    ply_in in;
    memset(&in, 0, sizeof(in));
    in.name = name;
    in.err = err;
    in.binary = h->binary;
    in.data = (const unsigned char *)data;
    in.size = size;
    in.pos = h->data_start;
    pgt_io_text_init(&in.text, data, size);
    in.text.next = h->data_start;
    in.text.line = h->end_line;

    if (!h->binary) {
        /* One instance per line: fewer lines than declared is TRUNCATED, more COUNT_MISMATCH. */
        uint64_t records = 0, found = 0;
        size_t extra_line = 0;
        for (size_t i = 0; i < h->nelems; ++i)
            if (h->elems[i].nprops > 0) records += h->elems[i].count;
        pgt_io_text s = in.text;
        while (ascii_next_line(&s))
            if (++found == records + 1) extra_line = s.line;
        if (found < records) {
            free(h);
            return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, s.line,
                                    "file ends after %llu of the %llu element lines the header "
                                    "declares",
                                    (unsigned long long)found, (unsigned long long)records);
        }
        if (found > records) {
            free(h);
            return pgt_io_fail_line(err, PGT_ERROR_COUNT_MISMATCH, name, extra_line,
                                    "data after the %llu element lines the header declares "
                                    "(%llu extra lines)",
                                    (unsigned long long)records,
                                    (unsigned long long)(found - records));
        }
    }

    const uint64_t V = h->vertex->count;
    float *positions = malloc(((size_t)V * 3 + 1) * sizeof(float));
    float *vertex_uv = h->vertex_uv ? malloc(((size_t)V * 2 + 1) * sizeof(float)) : NULL;
    pgt_io_tris tris;
    memset(&tris, 0, sizeof(tris));
    tris.use_where = origin != NULL;
    pgt_io_u32vec poly = {0};
    pgt_io_f32vec uv = {0};
    for (size_t j = 0; j < h->face->nprops; ++j) {
        tris.use_uvs |= h->face->props[j].role == ROLE_TEXCOORD;
        tris.use_labels |= h->face->props[j].role == ROLE_GROUP;
    }
    if (!positions || (h->vertex_uv && !vertex_uv) ||
        (tris.use_where && pgt_io_u64_reserve(&tris.vertex_where, (size_t)V + 1) != 0)) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu vertices",
                          name, (unsigned long long)V);
        goto done;
    }
    for (size_t ei = 0; ei < h->nelems; ++ei) {
        const ply_elem *e = &h->elems[ei];
        in.elem = e;
        if (e->nprops == 0) continue;
        for (uint64_t i = 0; i < e->count; ++i) {
            in.instance = i;
            in.prop = &e->props[0];
            if (!h->binary) {
                ascii_next_line(&in.text); /* present: counted above */
                if (!in.text.newline) {
                    r = ply_fail(&in, 0, PGT_ERROR_TRUNCATED,
                                 "file ends inside a line (no final newline)");
                    goto done;
                }
                in.p = in.text.begin;
                in.end = in.text.end;
            }
            size_t record_start = in.pos;
            int32_t group = 0;
            poly.len = uv.len = 0;
            for (size_t j = 0; j < e->nprops; ++j) {
                const ply_prop *pr = &e->props[j];
                in.prop = pr;
                size_t at = in.pos;
                uint64_t count = 0;
                int64_t value = 0;
                switch (pr->role) {
                case ROLE_X:
                case ROLE_Y:
                case ROLE_Z:
                    r = ply_read_real(&in, pr->type, "coordinate",
                                      &positions[3 * i + (uint64_t)(pr->role - ROLE_X)]);
                    break;
                case ROLE_VERTEX_U:
                case ROLE_VERTEX_V:
                    r = ply_read_real(&in, pr->type, "texture coordinate",
                                      &vertex_uv[2 * i + (uint64_t)(pr->role - ROLE_VERTEX_U)]);
                    break;
                case ROLE_INDICES:
                    r = ply_list_count(&in, pr, &count);
                    if (r == PGT_OK && count < 3)
                        r = ply_fail(&in, at, PGT_ERROR_PARSE,
                                     "face with %llu vertices (a face needs at least 3)",
                                     (unsigned long long)count);
                    for (uint64_t c = 0; r == PGT_OK && c < count; ++c) {
                        at = in.pos;
                        r = ply_read_int(&in, pr->type, "vertex index", &value);
                        if (r == PGT_OK && V == 0)
                            r = ply_fail(&in, at, PGT_ERROR_INDEX_RANGE,
                                         "vertex index %lld, but the file has no vertices",
                                         (long long)value);
                        else if (r == PGT_OK && (value < 0 || (uint64_t)value >= V))
                            r = ply_fail(&in, at, PGT_ERROR_INDEX_RANGE,
                                         "vertex index %lld is outside 0..%lld", (long long)value,
                                         (long long)V - 1);
                        if (r == PGT_OK && pgt_io_u32_reserve(&poly, poly.len + 1) != 0)
                            r = ply_fail(&in, at, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
                        if (r == PGT_OK) poly.data[poly.len++] = (uint32_t)value;
                    }
                    break;
                case ROLE_TEXCOORD:
                    r = ply_list_count(&in, pr, &count);
                    for (uint64_t c = 0; r == PGT_OK && c < count; ++c) {
                        if (pgt_io_f32_reserve(&uv, uv.len + 1) != 0)
                            r = ply_fail(&in, in.pos, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
                        else
                            r = ply_read_real(&in, pr->type, "texture coordinate",
                                              &uv.data[uv.len++]);
                    }
                    break;
                case ROLE_GROUP:
                    r = ply_read_int(&in, pr->type, "group", &value);
                    if (r == PGT_OK && (value < INT32_MIN || value > INT32_MAX))
                        r = ply_fail(&in, at, PGT_ERROR_PARSE, "group %lld does not fit int32",
                                     (long long)value);
                    group = (int32_t)value;
                    break;
                default:
                    if (pr->is_list) {
                        r = ply_list_count(&in, pr, &count);
                        if (r == PGT_OK) r = ply_skip_values(&in, pr->type, count, "list");
                    } else {
                        r = ply_skip_values(&in, pr->type, 1, "value");
                    }
                    break;
                }
                if (r != PGT_OK) goto done;
            }
            if (!h->binary) {
                const char *tok;
                char q[32];
                size_t n = pgt_io_token(&in.p, in.end, &tok);
                if (n > 0) {
                    r = ply_fail(&in, 0, PGT_ERROR_PARSE, "unexpected '%s' after the last property",
                                 pgt_io_quote(tok, n, q, sizeof(q)));
                    goto done;
                }
            }
            if (e->kind == KIND_VERTEX && tris.use_where)
                tris.vertex_where.data[tris.vertex_where.len++] =
                    h->binary ? record_start : in.text.line;
            if (e->kind != KIND_FACE) continue;
            if (tris.use_uvs && uv.len != 2 * poly.len) {
                r = ply_fail(&in, record_start, PGT_ERROR_COUNT_MISMATCH,
                             "face has %zu vertices but %zu texcoord values (expected %zu)",
                             poly.len, uv.len, 2 * poly.len);
                goto done;
            }
            r = pgt_io_tris_add(&tris, poly.data, NULL, uv.data, group,
                                h->binary ? record_start : in.text.line, poly.len);
            if (r != PGT_OK) {
                r = ply_fail(&in, record_start, r, "%s", pgt_io_tris_problem(r));
                goto done;
            }
        }
    }
    if (h->binary && in.pos != size) {
        r = pgt_io_fail_offset(err, PGT_ERROR_COUNT_MISMATCH, name, in.pos,
                               "%zu bytes after the elements the header declares",
                               size - in.pos);
        goto done;
    }
    const int vertex_uvs = !tris.use_uvs && h->vertex_uv;
    if (vertex_uvs) { /* each corner takes its vertex's coordinates */
        tris.use_uvs = 1;
        if (pgt_io_f32_reserve(&tris.uvs, 6 * tris.triangle_count + 1) != 0) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
            goto done;
        }
        for (size_t c = 0; c < 3 * tris.triangle_count; ++c)
            for (int k = 0; k < 2; ++k)
                tris.uvs.data[2 * c + (size_t)k] =
                    vertex_uv[2 * (size_t)tris.indices.data[c] + (size_t)k];
        tris.uvs.len = 6 * tris.triangle_count;
    }
    pgt_io_note_fan(name, tris.polygon_count, quiet);
    r = pgt_io_finish(out, positions, (size_t)V, &tris, tris.use_uvs, origin, h->binary, name, err);
    if (r == PGT_OK && origin) origin->uv_of_vertex = vertex_uvs;
done:
    free(positions);
    free(vertex_uv);
    free(poly.data);
    free(uv.data);
    pgt_io_tris_free(&tris);
    free(h);
    return r;
}

/* ---- writer ---- */

static unsigned char *store_u32(unsigned char *p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = (unsigned char)(v >> (8 * i));
    return p + 4;
}

static unsigned char *store_f32(unsigned char *p, float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof(u));
    return store_u32(p, u);
}

void pgt_io_write_ply(FILE *f, const pgt_mesh *mesh) {
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\ncomment written by pgt\n"
            "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n"
            "element face %u\nproperty list uchar uint vertex_indices\n",
            mesh->vertex_count, mesh->face_count);
    if (mesh->labels) fputs("property int group\n", f);
    if (mesh->uvs) fputs("property list uchar float texcoord\n", f);
    fputs("end_header\n", f);
    unsigned char rec[1 + 12 + 4 + 1 + 24];
    for (size_t i = 0; i < mesh->vertex_count; ++i) {
        unsigned char *p = rec;
        for (int k = 0; k < 3; ++k) p = store_f32(p, mesh->positions[3 * i + (size_t)k]);
        fwrite(rec, 1, (size_t)(p - rec), f);
    }
    for (size_t t = 0; t < mesh->face_count; ++t) {
        unsigned char *p = rec;
        *p++ = 3;
        for (int k = 0; k < 3; ++k) p = store_u32(p, mesh->indices[3 * t + (size_t)k]);
        if (mesh->labels) {
            uint32_t u;
            memcpy(&u, &mesh->labels[t], sizeof(u));
            p = store_u32(p, u);
        }
        if (mesh->uvs) {
            *p++ = 6;
            for (int k = 0; k < 6; ++k) p = store_f32(p, mesh->uvs[6 * t + (size_t)k]);
        }
        fwrite(rec, 1, (size_t)(p - rec), f);
    }
}

/* Vertex records are assembled in a buffer of this many bytes and written in one call: one
 * fwrite per record (tens of millions for an ivy scene) costs more than the data. */
#define PLY_WRITE_CHUNK (1u << 20)

void pgt_io_write_ply_soup(FILE *f, const pgt_vertex_mesh *soup) {
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\ncomment written by pgt\n"
            "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n",
            soup->vertex_count);
    if (soup->normals) fputs("property float nx\nproperty float ny\nproperty float nz\n", f);
    if (soup->uvs) fputs("property float u\nproperty float v\n", f);
    fprintf(f, "element face %u\nproperty list uchar uint vertex_indices\nend_header\n",
            soup->triangle_count);
    unsigned char *buf = malloc(PLY_WRITE_CHUNK);
    unsigned char small[64];
    size_t cap = buf ? PLY_WRITE_CHUNK : sizeof(small);
    if (!buf) buf = small; /* out of memory: slower, same bytes */
    size_t n = 0;
    for (size_t i = 0; i < soup->vertex_count; ++i) {
        if (cap - n < 32) {
            fwrite(buf, 1, n, f);
            n = 0;
        }
        unsigned char *p = buf + n;
        for (int k = 0; k < 3; ++k) p = store_f32(p, soup->positions[3 * i + (size_t)k]);
        if (soup->normals)
            for (int k = 0; k < 3; ++k) p = store_f32(p, soup->normals[3 * i + (size_t)k]);
        if (soup->uvs)
            for (int k = 0; k < 2; ++k) p = store_f32(p, soup->uvs[2 * i + (size_t)k]);
        n = (size_t)(p - buf);
    }
    for (size_t t = 0; t < soup->triangle_count; ++t) {
        if (cap - n < 13) {
            fwrite(buf, 1, n, f);
            n = 0;
        }
        unsigned char *p = buf + n;
        *p++ = 3;
        for (int k = 0; k < 3; ++k) p = store_u32(p, soup->triangles[3 * t + (size_t)k]);
        n = (size_t)(p - buf);
    }
    fwrite(buf, 1, n, f);
    if (buf != small) free(buf);
}
