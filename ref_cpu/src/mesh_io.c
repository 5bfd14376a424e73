/* pgt: mesh file reading and writing, the part shared by every format: whole-file reads, format
 * from the extension, atomic writes (temporary file + rename), number parsing, the triangle
 * builder that fan-triangulates polygons, and located error messages.
 * The formats themselves are in mesh_io_obj.c, mesh_io_off.c and mesh_io_ply.c. */
#include "mesh_io_internal.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- growable arrays and the triangle builder ---- */

void *pgt_io_grow(void *data, size_t *cap, size_t need, size_t elem) {
    size_t c = *cap ? *cap : 16;
    while (c < need) {
        if (c > SIZE_MAX / 2) return NULL;
        c *= 2;
    }
    if (c > SIZE_MAX / elem) return NULL;
    void *p = realloc(data, c * elem);
    if (!p) return NULL;
    *cap = c;
    return p;
}

pgt_result pgt_io_tris_add(pgt_io_tris *t, const uint32_t *v, const uint32_t *aux, const float *uv,
                           int32_t label, uint64_t where, size_t n) {
    size_t add = n - 2;
    if (t->triangle_count + add > PGT_MESH_MAX_ELEMENTS) return PGT_ERROR_LIMIT;
    size_t tc = t->triangle_count + add;
    if (pgt_io_u32_reserve(&t->indices, 3 * tc) != 0) return PGT_ERROR_OUT_OF_MEMORY;
    if (t->use_aux && pgt_io_u32_reserve(&t->aux, 3 * tc) != 0) return PGT_ERROR_OUT_OF_MEMORY;
    if (t->use_uvs && pgt_io_f32_reserve(&t->uvs, 6 * tc) != 0) return PGT_ERROR_OUT_OF_MEMORY;
    if (t->use_labels && pgt_io_i32_reserve(&t->labels, tc) != 0) return PGT_ERROR_OUT_OF_MEMORY;
    if (t->use_where && pgt_io_u64_reserve(&t->where, tc) != 0) return PGT_ERROR_OUT_OF_MEMORY;
    for (size_t i = 1; i + 1 < n; ++i) {
        const size_t c[3] = {0, i, i + 1};
        for (int k = 0; k < 3; ++k) {
            t->indices.data[t->indices.len++] = v[c[k]];
            if (t->use_aux) t->aux.data[t->aux.len++] = aux[c[k]];
            if (t->use_uvs) {
                t->uvs.data[t->uvs.len++] = uv[2 * c[k]];
                t->uvs.data[t->uvs.len++] = uv[2 * c[k] + 1];
            }
        }
        if (t->use_labels) t->labels.data[t->labels.len++] = label;
        if (t->use_where) t->where.data[t->where.len++] = where;
    }
    t->triangle_count = tc;
    if (n > 3) t->polygon_count++;
    return PGT_OK;
}

const char *pgt_io_tris_problem(pgt_result r) {
    return r == PGT_ERROR_LIMIT ? "more triangles than the pgt limit of 1073741823"
                                : "out of memory for the triangles";
}

void pgt_io_tris_free(pgt_io_tris *t) {
    free(t->indices.data);
    free(t->aux.data);
    free(t->uvs.data);
    free(t->labels.data);
    free(t->where.data);
    free(t->vertex_where.data);
    memset(t, 0, sizeof(*t));
}

pgt_result pgt_io_finish(pgt_mesh *out, const float *positions, size_t vertex_count, pgt_io_tris *t,
                         int with_uvs, pgt_mesh_origin *origin, int offsets, const char *name,
                         pgt_error *err) {
    /* Readers check both counts against the limit before they get here. */
    pgt_result r = pgt_mesh_create(out, (uint32_t)vertex_count, (uint32_t)t->triangle_count,
                                   with_uvs, t->use_labels, err);
    if (r != PGT_OK) return r == PGT_ERROR_OUT_OF_MEMORY
                                ? pgt_error_set(err, r, "%s: out of memory for the mesh", name)
                                : r;
    memcpy(out->positions, positions, vertex_count * 3 * sizeof(float));
    memcpy(out->indices, t->indices.data, t->triangle_count * 3 * sizeof(uint32_t));
    if (with_uvs && t->use_uvs)
        memcpy(out->uvs, t->uvs.data, t->triangle_count * 6 * sizeof(float));
    if (t->use_labels) memcpy(out->labels, t->labels.data, t->triangle_count * sizeof(int32_t));
    if (origin) { /* the places move over: no copy, no second peak */
        assert(t->use_where && t->where.len == t->triangle_count &&
               t->vertex_where.len == vertex_count);
        origin->face = t->where.data;
        origin->face_count = (uint32_t)t->triangle_count;
        origin->vertex = t->vertex_where.data;
        origin->vertex_count = (uint32_t)vertex_count;
        origin->offsets = offsets;
        memset(&t->where, 0, sizeof t->where);
        memset(&t->vertex_where, 0, sizeof t->vertex_where);
    }
    return PGT_OK;
}

void pgt_mesh_origin_keep_vertices(pgt_mesh_origin *origin) {
    if (!origin) return;
    free(origin->face);
    free(origin->uv);
    free(origin->uv_index);
    origin->face = NULL, origin->face_count = 0;
    origin->uv = NULL, origin->uv_index = NULL, origin->uv_count = 0, origin->uv_of_vertex = 0;
}

void pgt_mesh_origin_destroy(pgt_mesh_origin *origin) {
    if (!origin) return;
    pgt_mesh_origin_keep_vertices(origin);
    free(origin->vertex);
    memset(origin, 0, sizeof(*origin));
}

/* "NAME:LINE", "NAME: byte offset N", or NAME when the record is not known. */
static const char *record_where(const uint64_t *place, uint32_t count, int offsets,
                                const char *name, uint32_t k, char *buf, size_t size) {
    if (!place || k >= count)
        snprintf(buf, size, "%s", name);
    else if (offsets)
        snprintf(buf, size, "%s: byte offset %llu", name, (unsigned long long)place[k]);
    else
        snprintf(buf, size, "%s:%llu", name, (unsigned long long)place[k]);
    return buf;
}

const char *pgt_mesh_origin_where(const pgt_mesh_origin *origin, const char *name, uint32_t face,
                                  char *buf, size_t size) {
    return origin ? record_where(origin->face, origin->face_count, origin->offsets, name, face, buf,
                                 size)
                  : record_where(NULL, 0, 0, name, 0, buf, size);
}

const char *pgt_mesh_origin_vertex_where(const pgt_mesh_origin *origin, const char *name,
                                         uint32_t vertex, char *buf, size_t size) {
    return origin ? record_where(origin->vertex, origin->vertex_count, origin->offsets, name,
                                 vertex, buf, size)
                  : record_where(NULL, 0, 0, name, 0, buf, size);
}

const char *pgt_mesh_origin_uv_where(const pgt_mesh_origin *origin, const pgt_mesh *mesh,
                                     const char *name, uint32_t corner, char *buf, size_t size) {
    const uint32_t face = corner / 3u;
    if (!origin || face >= origin->face_count) return record_where(NULL, 0, 0, name, 0, buf, size);
    if (origin->uv && origin->uv_index)
        return record_where(origin->uv, origin->uv_count, origin->offsets, name,
                            origin->uv_index[corner], buf, size);
    if (origin->uv_of_vertex && mesh && face < mesh->face_count)
        return pgt_mesh_origin_vertex_where(origin, name, mesh->indices[corner], buf, size);
    return pgt_mesh_origin_where(origin, name, face, buf, size);
}

void pgt_io_note_fan(const char *name, size_t polygons, int quiet) {
    if (!quiet && polygons > 0)
        fprintf(stderr, "note: %s: fan-triangulated %zu polygons\n", name, polygons);
}

/* ---- numbers ---- */

/* Fast path for plain decimals ("-12.345678", no exponent), most of what OBJ files hold:
 * Clinger's method (W. D. Clinger, "How to Read Floating Point Numbers Accurately", PLDI 1990,
 * section 4): with a mantissa below 2^53 and at most 22 fraction digits, both operands of
 * m / 10^k are exact doubles, so the quotient is the correctly rounded double. Rounding that
 * double to float can differ from rounding the decimal straight to float only when the double
 * lands exactly on a midpoint between two floats; then we defer to strtof. Returns 0 when the
 * token is not a plain decimal or the fast path cannot decide. */
static int parse_float_fast(const char *s, size_t n, float *out) {
#if FLT_EVAL_METHOD != 0
    (void)s, (void)n, (void)out;
    return 0; /* extended-precision evaluation (x87) would round twice */
#else
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    size_t i = 0, digits = 0, frac = 0;
    int neg = 0, dot = 0;
    uint64_t m = 0;
    if (s[0] == '-' || s[0] == '+') neg = s[i++] == '-';
    for (; i < n; ++i) {
        char c = s[i];
        if (c >= '0' && c <= '9') {
            if (++digits > 18) return 0; /* m stays below 10^18 < 2^63 */
            m = m * 10 + (uint64_t)(c - '0');
            frac += (size_t)dot;
        } else if (c == '.' && !dot) {
            dot = 1;
        } else {
            return 0;
        }
    }
    if (digits == 0 || m > (UINT64_C(1) << 53) || frac > 22) return 0;
    double q = (double)m / pow10[frac];
    float f = (float)q;
    if ((double)f != q) {
        float g = nextafterf(f, (double)f < q ? INFINITY : -INFINITY);
        if (((double)f + (double)g) * 0.5 == q) return 0; /* exact midpoint: ask strtof */
    }
    *out = neg ? -f : f;
    return 1;
#endif
}

/* s[0, n) read whole by strtof into *out (finite), or by strtod when out is NULL (any number,
 * nan and inf included). The C string strto* needs is a copy: on the stack (PGT_IO_MAX_NUMBER
 * bytes) when it fits, else on the heap (a decimal of thousands of digits is still a number:
 * "0.000...1", 1e-40 written out; the readers have no line limit, so a token is as long as the
 * file allows). */
static pgt_result scan_number(const char *s, size_t n, float *out) {
    if (n == 0) return PGT_ERROR_PARSE;
    char stack[PGT_IO_MAX_NUMBER + 1], *buf = n <= PGT_IO_MAX_NUMBER ? stack : malloc(n + 1);
    if (!buf) return PGT_ERROR_OUT_OF_MEMORY;
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *e = NULL;
    float f = 0.0f;
    if (out)
        f = strtof(buf, &e);
    else
        (void)strtod(buf, &e);
    const int whole = e == buf + n;
    if (buf != stack) free(buf);
    if (!whole) return PGT_ERROR_PARSE;
    if (!out) return PGT_OK;
    if (!isfinite(f)) return PGT_ERROR_NOT_FINITE;
    *out = f;
    return PGT_OK;
}

pgt_result pgt_io_parse_float(const char *s, size_t n, float *out) {
    if (n > 0 && parse_float_fast(s, n, out)) return PGT_OK;
    return scan_number(s, n, out);
}

const char *pgt_io_float_problem(pgt_result r) {
    return r == PGT_ERROR_NOT_FINITE      ? "not a finite float"
           : r == PGT_ERROR_OUT_OF_MEMORY ? "too long to copy (out of memory)"
                                          : "not a number";
}

pgt_result pgt_io_check_number(const char *s, size_t n) { return scan_number(s, n, NULL); }

int pgt_io_parse_i64(const char *s, size_t n, int64_t *out) {
    size_t i = 0;
    int neg = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) neg = s[i++] == '-';
    if (i == n) return 1;
    uint64_t v = 0;
    int over = 0;
    for (; i < n; ++i) {
        if (s[i] < '0' || s[i] > '9') return 1;
        unsigned d = (unsigned)(s[i] - '0');
        if (v > ((uint64_t)INT64_MAX - d) / 10) over = 1;
        else v = v * 10 + d;
    }
    if (over) v = (uint64_t)INT64_MAX;
    *out = neg ? -(int64_t)v : (int64_t)v;
    return over ? 2 : 0;
}

const char *pgt_io_quote(const char *s, size_t n, char *buf, size_t bufsize) {
    size_t max = bufsize > 4 ? bufsize - 4 : 0, k = 0;
    if (max > 24) max = 24;
    for (; k < n && k < max; ++k) {
        unsigned char c = (unsigned char)s[k];
        buf[k] = (c >= 0x20 && c < 0x7F) ? (char)c : '?';
    }
    if (k < n && bufsize >= 4) {
        memcpy(buf + k, "...", 3);
        k += 3;
    }
    if (bufsize > 0) buf[k < bufsize ? k : bufsize - 1] = '\0';
    return buf;
}

/* ---- errors ---- */

pgt_result pgt_io_fail_line(pgt_error *err, pgt_result code, const char *name, size_t line,
                            const char *fmt, ...) {
    char msg[PGT_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    return pgt_error_set(err, code, "%s:%zu: %s", name, line ? line : 1, msg);
}

pgt_result pgt_io_fail_offset(pgt_error *err, pgt_result code, const char *name, size_t offset,
                              const char *fmt, ...) {
    char msg[PGT_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    return pgt_error_set(err, code, "%s: byte offset %zu: %s", name, offset, msg);
}

/* ---- public API ---- */

pgt_mesh_format pgt_mesh_format_from_path(const char *path) {
    if (!path) return PGT_FORMAT_AUTO;
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || strlen(dot + 1) != 3) return PGT_FORMAT_AUTO;
    char ext[4];
    for (int i = 0; i < 3; ++i) ext[i] = (char)tolower((unsigned char)dot[1 + i]);
    ext[3] = '\0';
    if (strcmp(ext, "obj") == 0) return PGT_FORMAT_OBJ;
    if (strcmp(ext, "off") == 0) return PGT_FORMAT_OFF;
    if (strcmp(ext, "ply") == 0) return PGT_FORMAT_PLY;
    return PGT_FORMAT_AUTO;
}

static pgt_result resolve_format(pgt_mesh_format asked, const char *name, pgt_mesh_format *out,
                                 pgt_error *err) {
    if (asked < PGT_FORMAT_AUTO || asked > PGT_FORMAT_PLY)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: unknown mesh format %d", name,
                             (int)asked);
    *out = asked != PGT_FORMAT_AUTO ? asked : pgt_mesh_format_from_path(name);
    if (*out == PGT_FORMAT_AUTO)
        return pgt_error_set(err, PGT_ERROR_UNSUPPORTED,
                             "%s: unknown mesh file extension (expected .obj, .off or .ply)", name);
    return PGT_OK;
}

pgt_result pgt_mesh_read_memory(pgt_mesh *out, const void *data, size_t size, const char *name,
                                const pgt_mesh_read_options *opts, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (!name) name = "<memory>";
    if (!data && size > 0)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: NULL data of %zu bytes", name,
                             size);
    if (!data) data = "";
    pgt_mesh_origin *origin = opts ? opts->origin : NULL;
    if (origin) memset(origin, 0, sizeof(*origin));
    pgt_mesh_format format = PGT_FORMAT_AUTO;
    pgt_result r = resolve_format(opts ? opts->format : PGT_FORMAT_AUTO, name, &format, err);
    if (r != PGT_OK) return r;
    int quiet = opts ? opts->quiet : 0;
    switch (format) {
    case PGT_FORMAT_OBJ: r = pgt_io_read_obj(out, data, size, name, quiet, origin, err); break;
    case PGT_FORMAT_OFF: r = pgt_io_read_off(out, data, size, name, quiet, origin, err); break;
    default: r = pgt_io_read_ply(out, data, size, name, quiet, origin, err); break;
    }
    if (r != PGT_OK) pgt_mesh_destroy(out), pgt_mesh_origin_destroy(origin);
    return r;
}

/* Reads the whole file; *out_data is malloc'd (at least one byte). */
static pgt_result read_file(const char *path, char **out_data, size_t *out_size, pgt_error *err) {
    *out_data = NULL;
    *out_size = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    size_t cap = 1 << 16, len = 0;
    struct stat st;
    if (fstat(fileno(f), &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            fclose(f);
            return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot read: is a directory", path);
        }
        /* Regular files: one read into a buffer of the file's size (+1 to see EOF at once). */
        if (S_ISREG(st.st_mode) && st.st_size >= 0 && (uint64_t)st.st_size < SIZE_MAX - 1)
            cap = (size_t)st.st_size + 1;
    }
    char *data = malloc(cap);
    if (!data) {
        fclose(f);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu bytes", path,
                             cap);
    }
    for (;;) {
        size_t got = fread(data + len, 1, cap - len, f);
        len += got;
        if (len < cap) break;
        if (cap >= PGT_MESH_MAX_STREAM_BYTES) { /* a pipe or device that does not end */
            free(data);
            fclose(f);
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "%s: more than %llu bytes from a pipe or device (a regular "
                                 "file is read whatever its size)",
                                 path, (unsigned long long)PGT_MESH_MAX_STREAM_BYTES);
        }
        void *p = pgt_io_grow(data, &cap, cap + 1, 1);
        if (!p) {
            free(data);
            fclose(f);
            return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory reading it",
                                 path);
        }
        data = p;
    }
    int failed = ferror(f);
    int e = errno;
    fclose(f);
    if (failed) {
        free(data);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", path, strerror(e));
    }
    *out_data = data;
    *out_size = len;
    return PGT_OK;
}

pgt_result pgt_mesh_read(pgt_mesh *out, const char *path, const pgt_mesh_read_options *opts,
                         pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (opts && opts->origin) memset(opts->origin, 0, sizeof(*opts->origin));
    if (!path) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "mesh read: NULL path");
    pgt_mesh_format format = PGT_FORMAT_AUTO;
    pgt_result r = resolve_format(opts ? opts->format : PGT_FORMAT_AUTO, path, &format, err);
    if (r != PGT_OK) return r;
    char *data;
    size_t size;
    r = read_file(path, &data, &size, err);
    if (r != PGT_OK) return r;
    pgt_mesh_read_options o = {format, opts ? opts->quiet : 0, opts ? opts->origin : NULL};
    r = pgt_mesh_read_memory(out, data, size, path, &o, err);
    free(data);
    return r;
}

/* What write_atomic writes: a pgt_mesh in a format, or a vertex-attributed soup as PLY. */
typedef struct write_job {
    const pgt_mesh *mesh;
    const pgt_vertex_mesh *soup;
    pgt_mesh_format format;
    int precise;
} write_job;

/* Writes the job to PATH.tmp.PID in the same folder and renames it over PATH (rename() replaces
 * the target atomically); on failure removes the temporary file. */
static pgt_result write_atomic(const char *path, const write_job *job, pgt_error *err) {
    size_t tmp_size = strlen(path) + 32;
    char *tmp = malloc(tmp_size);
    if (!tmp) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    pgt_tmp_name(tmp, tmp_size, path);
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        int e = errno;
        free(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot create a temporary file beside it: %s",
                             path, strerror(e));
    }
    if (job->soup) {
        pgt_io_write_ply_soup(f, job->soup);
    } else {
        switch (job->format) {
        case PGT_FORMAT_OBJ: pgt_io_write_obj(f, job->mesh, job->precise); break;
        case PGT_FORMAT_OFF: pgt_io_write_off(f, job->mesh, job->precise); break;
        default: pgt_io_write_ply(f, job->mesh); break;
        }
    }
    int failed = ferror(f) || fflush(f) != 0;
    int e = errno;
    if (fclose(f) != 0 && !failed) {
        failed = 1;
        e = errno;
    }
    if (failed) {
        remove(tmp);
        free(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: write error: %s", path, strerror(e));
    }
    if (pgt_replace_file(tmp, path) != 0) {
        e = errno;
        remove(tmp);
        free(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot move the written file into place: %s",
                             path, strerror(e));
    }
    free(tmp);
    return PGT_OK;
}

pgt_result pgt_mesh_write(const pgt_mesh *mesh, const char *path,
                          const pgt_mesh_write_options *opts, pgt_error *err) {
    if (!mesh || !path)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "mesh write: NULL %s",
                             mesh ? "path" : "mesh");
    pgt_mesh_format format = PGT_FORMAT_AUTO;
    pgt_result r = resolve_format(opts ? opts->format : PGT_FORMAT_AUTO, path, &format, err);
    if (r != PGT_OK) return r;
    if ((mesh->vertex_count && !mesh->positions) || (mesh->face_count && !mesh->indices))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: mesh has NULL arrays", path);
    for (size_t i = 0; i < (size_t)mesh->face_count * 3; ++i)
        if (mesh->indices[i] >= mesh->vertex_count)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: triangle %zu has vertex index %u but the mesh has %u "
                                 "vertices",
                                 path, i / 3, mesh->indices[i], mesh->vertex_count);

    write_job job = {mesh, NULL, format, opts ? opts->precise : 0};
    return write_atomic(path, &job, err);
}

pgt_result pgt_mesh_write_ply_soup(const pgt_vertex_mesh *soup, const char *path, pgt_error *err) {
    if (!soup || !path)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "ply write: NULL %s",
                             soup ? "path" : "mesh");
    if ((soup->vertex_count && !soup->positions) || (soup->triangle_count && !soup->triangles))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: mesh has NULL arrays", path);
    for (size_t i = 0; i < (size_t)soup->triangle_count * 3; ++i)
        if (soup->triangles[i] >= soup->vertex_count)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: triangle %zu has vertex index %u but the mesh has %u "
                                 "vertices",
                                 path, i / 3, soup->triangles[i], soup->vertex_count);
    write_job job = {NULL, soup, PGT_FORMAT_PLY, 0};
    return write_atomic(path, &job, err);
}
