/* pgt harness: quad meshes with UVs and normals as OBJ (facade_quads.h). */
#include "facade_quads.h"
#include "text_line.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct fbuf {
    float *v;
    uint32_t n, cap; /* floats */
} fbuf;

static int fpush(fbuf *b, const float *x, uint32_t k) {
    if (b->n + k > b->cap) {
        uint32_t cap = b->cap ? b->cap * 2u : 1024u;
        float *p = realloc(b->v, (size_t)cap * sizeof *p);
        if (!p) return 0;
        b->v = p, b->cap = cap;
    }
    memcpy(b->v + b->n, x, k * sizeof *x);
    b->n += k;
    return 1;
}

/* Parses "A/T/N" (1-based or negative) into 0-based indices given the counts so far. */
static int corner(const char *s, const uint32_t count[3], uint32_t out[3]) {
    for (int k = 0; k < 3; ++k) {
        char *end;
        errno = 0;
        const long long x = strtoll(s, &end, 10);
        if (end == s || errno) return 0;
        const long long i = x > 0 ? x - 1 : (long long)count[k] + x;
        if (x == 0 || i < 0 || i >= (long long)count[k]) return 0;
        out[k] = (uint32_t)i;
        s = end;
        if (k < 2) {
            if (*s != '/') return 0;
            ++s;
        }
    }
    return *s == '\0';
}

pgt_result pgt_facade_quads_read_obj(pgt_facade_quads *out, const char *path, pgt_error *err) {
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "rb");
    if (!f) return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    fbuf pos = {0}, uv = {0}, nrm = {0};
    uint32_t *tri = NULL, ncorner = 0, cap = 0; /* (v, vt, vn) per corner */
    char line[4096];
    unsigned lineno = 0;
    pgt_result r = PGT_OK;
    pgt_text_line got;
    size_t len;
    while (r == PGT_OK && (got = pgt_text_line_read(f, line, sizeof line, &len, lineno == 0)) !=
                              PGT_TEXT_LINE_END) {
        ++lineno;
        if (got != PGT_TEXT_LINE_OK) { /* too long, or a NUL */
            char msg[PGT_TEXT_LINE_MESSAGE];
            pgt_text_line_message(got, path, lineno, len, sizeof line - 1u, msg, sizeof msg);
            r = pgt_error_set(err, got == PGT_TEXT_LINE_LONG ? PGT_ERROR_LIMIT : PGT_ERROR_PARSE,
                              "%s", msg);
            break;
        }
        char *hash = strchr(line, '#'); /* a comment runs to the end of the line */
        if (hash) *hash = '\0';
        char *save = NULL, *tok = strtok_r(line, " \t\r\n", &save);
        if (!tok) continue;
        const int is_v = !strcmp(tok, "v"), is_vt = !strcmp(tok, "vt"), is_vn = !strcmp(tok, "vn");
        if (is_v || is_vt || is_vn) {
            const uint32_t need = is_vt ? 2u : 3u;
            float x[3];
            for (uint32_t k = 0; k < need && r == PGT_OK; ++k) {
                char *t = strtok_r(NULL, " \t\r\n", &save), *end = NULL;
                if (t) x[k] = strtof(t, &end);
                if (!t || *end != '\0')
                    r = pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: %s needs %u numbers", path,
                                      lineno, tok, need);
                else if (!isfinite(x[k]))
                    r = pgt_error_set(err, PGT_ERROR_NOT_FINITE,
                                      "%s:%u: %s value '%s' is not a finite float", path, lineno,
                                      tok, t);
                else if (!is_vn && !(fabsf(x[k]) <= PGT_FACADE_MAX_COORD))
                    r = pgt_error_set(err, PGT_ERROR_LIMIT,
                                      "%s:%u: %s value %s beyond +-%g metres (a facade's float "
                                      "arithmetic loses its windows beyond)",
                                      path, lineno, tok, t, (double)PGT_FACADE_MAX_COORD);
            }
            /* what may follow, read as the mesh reader reads it and unused: up to 4 more
             * numbers after v's 3 (a weight, or a colour r g b and its weight), 1 after vt's 2 */
            const uint32_t more = is_v ? 4u : (is_vt ? 1u : 0u);
            for (uint32_t extra = 0; r == PGT_OK;) {
                char *t = strtok_r(NULL, " \t\r\n", &save), *end = NULL;
                if (!t) break;
                if (extra++ == more || (strtof(t, &end), *end != '\0'))
                    r = more ? pgt_error_set(err, PGT_ERROR_PARSE,
                                             "%s:%u: %s takes %u to %u numbers, got '%s' after "
                                             "them",
                                             path, lineno, tok, need, need + more, t)
                             : pgt_error_set(err, PGT_ERROR_PARSE,
                                             "%s:%u: %s takes %u numbers, got '%s' after them",
                                             path, lineno, tok, need, t);
            }
            fbuf *b = is_v ? &pos : (is_vt ? &uv : &nrm);
            if (r == PGT_OK && b->n / need >= PGT_FACADE_QUADS_MAX)
                r = pgt_error_set(err, PGT_ERROR_LIMIT, "%s:%u: more than %u %s", path, lineno,
                                  PGT_FACADE_QUADS_MAX, tok);
            if (r == PGT_OK && !fpush(b, x, need))
                r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        } else if (!strcmp(tok, "f")) {
            const uint32_t count[3] = {pos.n / 3u, uv.n / 2u, nrm.n / 3u};
            uint32_t c[4][3], n = 0;
            char *t;
            while (r == PGT_OK && (t = strtok_r(NULL, " \t\r\n", &save))) {
                if (n == 4 || !corner(t, count, c[n]))
                    r = pgt_error_set(err, PGT_ERROR_PARSE,
                                      "%s:%u: a face is 4 corners V/T/N with indices of earlier "
                                      "v, vt and vn lines (quads with UVs and normals), got '%s'",
                                      path, lineno, t);
                ++n;
            }
            if (r == PGT_OK && n != 4)
                r = pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: a face of %u corners (quads only)",
                                  path, lineno, n);
            if (r == PGT_OK && ncorner / 4u >= PGT_FACADE_QUADS_MAX)
                r = pgt_error_set(err, PGT_ERROR_LIMIT, "%s:%u: more than %u quads", path, lineno,
                                  PGT_FACADE_QUADS_MAX);
            if (r == PGT_OK && ncorner + 4u > cap) {
                const uint32_t nc = cap ? cap * 2u : 1024u;
                uint32_t *p = realloc(tri, (size_t)nc * 3u * sizeof *p);
                if (!p)
                    r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
                else
                    tri = p, cap = nc;
            }
            if (r == PGT_OK)
                for (uint32_t k = 0; k < 4; ++k) memcpy(tri + 3u * ncorner++, c[k], sizeof c[k]);
        }
    }
    if (r == PGT_OK && ferror(f)) /* errno: the failed read's (a folder: EISDIR) */
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", path, strerror(errno));
    fclose(f);
    if (r == PGT_OK && ncorner == 0) r = pgt_error_set(err, PGT_ERROR_EMPTY, "%s: no faces", path);
    /* one vertex per distinct (v, vt, vn): open addressing over the corners */
    uint32_t hcap = 1;
    while (r == PGT_OK && hcap < 2u * ncorner) hcap *= 2u;
    uint32_t *hash = r == PGT_OK ? malloc((size_t)hcap * sizeof *hash) : NULL;
    if (r == PGT_OK) {
        out->indices = malloc((size_t)ncorner * sizeof *out->indices);
        out->positions = malloc((size_t)ncorner * 3u * sizeof(float));
        out->normals = malloc((size_t)ncorner * 3u * sizeof(float));
        out->uvs = malloc((size_t)ncorner * 2u * sizeof(float));
        if (!hash || !out->indices || !out->positions || !out->normals || !out->uvs)
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    uint32_t *first_corner = NULL; /* corner that made vertex k */
    if (r == PGT_OK) {
        first_corner = malloc((size_t)ncorner * sizeof *first_corner);
        if (!first_corner)
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    if (r == PGT_OK) {
        memset(hash, 0xFF, (size_t)hcap * sizeof *hash);
        uint32_t V = 0;
        for (uint32_t i = 0; i < ncorner; ++i) {
            const uint32_t *c = tri + 3u * i;
            uint32_t h =
                (c[0] * 0x9E3779B1u ^ c[1] * 0x85EBCA77u ^ c[2] * 0xC2B2AE3Du) & (hcap - 1u);
            while (hash[h] != PGT_NONE &&
                   memcmp(tri + 3u * first_corner[hash[h]], c, 3u * sizeof *c) != 0)
                h = (h + 1u) & (hcap - 1u);
            if (hash[h] == PGT_NONE) {
                hash[h] = V, first_corner[V] = i;
                memcpy(out->positions + 3u * V, pos.v + 3u * c[0], 3u * sizeof(float));
                memcpy(out->uvs + 2u * V, uv.v + 2u * c[1], 2u * sizeof(float));
                memcpy(out->normals + 3u * V, nrm.v + 3u * c[2], 3u * sizeof(float));
                ++V;
            }
            out->indices[i] = hash[h];
        }
        out->vertex_count = V, out->quad_count = ncorner / 4u;
    }
    free(first_corner);
    free(hash);
    free(tri);
    free(pos.v), free(uv.v), free(nrm.v);
    if (r != PGT_OK) pgt_facade_quads_destroy(out);
    return r;
}

pgt_result pgt_facade_quads_write_obj(const pgt_facade_quads *m, const char *path,
                                      const char *comment, pgt_error *err) {
    /* a temporary file beside it, renamed when complete: a failed write keeps the old file */
    char tmp[4200];
    pgt_tmp_name(tmp, sizeof tmp, path);
    FILE *f = fopen(tmp, "wb");
    if (!f)
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot create a temporary file beside it: %s",
                             path, strerror(errno));
    if (comment) fprintf(f, "# %s\n", comment);
    fprintf(f, "# %u vertices, %u quads; vt = (u, v) in facade space, metres\n", m->vertex_count,
            m->quad_count);
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        const float *p = m->positions + 3u * v, *n = m->normals + 3u * v, *t = m->uvs + 2u * v;
        fprintf(f, "v %.9g %.9g %.9g\nvt %.9g %.9g\nvn %.9g %.9g %.9g\n", (double)p[0],
                (double)p[1], (double)p[2], (double)t[0], (double)t[1], (double)n[0], (double)n[1],
                (double)n[2]);
    }
    for (uint32_t q = 0; q < m->quad_count; ++q) {
        fputc('f', f);
        for (uint32_t c = 0; c < 4; ++c) {
            const uint32_t i = m->indices[4u * q + c] + 1u;
            fprintf(f, " %u/%u/%u", i, i, i);
        }
        fputc('\n', f);
    }
    const int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        remove(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: write error", path);
    }
    if (pgt_replace_file(tmp, path) != 0) {
        const int e = errno;
        remove(tmp);
        return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot rename %s: %s", path, tmp, strerror(e));
    }
    return PGT_OK;
}
