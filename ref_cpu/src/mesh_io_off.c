/* pgt: OFF (Object File Format) reading and writing.
 *
 * Based on the OFF description in the Geomview manual, section "OFF Files": an "OFF" keyword,
 * a line "NVertices NFaces NEdges", one "x y z" line per vertex, then one
 * "n i0 ... i(n-1) [colour]" line per face with 0-based indices; '#' starts a comment.
 * pgt reads plain OFF only (not COFF, NOFF, STOFF, 4OFF, nOFF or binary OFF) and reads it line
 * by line: one vertex or face per line, the way every common writer emits it. Each record line
 * must end with '\n' (a last line cut short cannot be told from a complete one otherwise). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io_internal.h"

/* Every vertex or face takes a line of at least one character and its '\n': a header whose
 * counts need more bytes than the file holds is rejected before anything is allocated (and
 * before the lines are counted, which then tells a short file from one with extra data). */
#define OFF_MIN_RECORD_BYTES 2u

/* Most colour values a face line may carry after its indices (r g b a, or a colour-map index). */
#define OFF_MAX_FACE_COLOUR 4u

/* Moves to the next line holding data (not blank, not only a comment); sets *p and *end to its
 * content. 0 at the end of the file. */
static int next_data_line(pgt_io_text *t, const char **p, const char **end) {
    while (pgt_io_text_next(t)) {
        const char *e = pgt_io_strip_comment(t->begin, t->end), *s = t->begin;
        while (s < e && pgt_io_space(*s)) s++;
        if (s < e) {
            *p = s;
            *end = e;
            return 1;
        }
    }
    return 0;
}

static int is_off_variant(const char *tok, size_t n) {
    if (n <= 3 || memcmp(tok + n - 3, "OFF", 3) != 0) return 0;
    for (size_t i = 0; i + 3 < n; ++i)
        if (!strchr("STCN4n", tok[i])) return 0;
    return 1;
}

pgt_result pgt_io_read_off(pgt_mesh *out, const char *data, size_t size, const char *name,
                           int quiet, pgt_mesh_origin *origin, pgt_error *err) {
    pgt_io_text t;
    const char *p, *end, *tok;
    size_t n;
    char q[32];
    pgt_io_text_init(&t, data, size);
    pgt_io_text_skip_bom(&t);
    if (size == 0) return pgt_io_fail_line(err, PGT_ERROR_EMPTY, name, 1, "file is empty");
    if (!next_data_line(&t, &p, &end))
        return pgt_io_fail_line(err, PGT_ERROR_EMPTY, name, t.line,
                                "file holds only comments and blank lines");

    /* Header: "OFF", with the counts on the same line or the next data line. */
    n = pgt_io_token(&p, end, &tok);
    if (!pgt_io_token_is(tok, n, "OFF")) {
        const int variant = is_off_variant(tok, n);
        return pgt_io_fail_line(err, variant ? PGT_ERROR_UNSUPPORTED : PGT_ERROR_PARSE, name,
                                t.line, "expected the header 'OFF', found '%s'%s",
                                pgt_io_quote(tok, n, q, sizeof(q)),
                                variant ? " (pgt reads plain OFF only)" : "");
    }
    if (!t.newline)
        return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                "file ends after the OFF header");
    n = pgt_io_token(&p, end, &tok);
    if (pgt_io_token_is(tok, n, "BINARY"))
        return pgt_io_fail_line(err, PGT_ERROR_UNSUPPORTED, name, t.line,
                                "binary OFF is not supported");
    if (n == 0) {
        if (!next_data_line(&t, &p, &end))
            return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                    "file ends before the counts line");
        if (!t.newline)
            return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                    "file ends inside the counts line");
        n = pgt_io_token(&p, end, &tok);
    }
    int64_t counts[3] = {0, 0, 0};
    size_t k = 0;
    for (; n > 0; n = pgt_io_token(&p, end, &tok), ++k) {
        if (k == 3)
            return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                    "counts line has more than 3 values (V F E)");
        if (pgt_io_parse_i64(tok, n, &counts[k]) == 1 || counts[k] < 0)
            return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                    "count '%s' is not a non-negative integer",
                                    pgt_io_quote(tok, n, q, sizeof(q)));
    }
    if (k < 2)
        return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                "counts line needs the vertex and face counts (V F E)");
    const int64_t V = counts[0], F = counts[1];
    if (V > PGT_MESH_MAX_ELEMENTS || F > PGT_MESH_MAX_ELEMENTS)
        return pgt_io_fail_line(err, PGT_ERROR_LIMIT, name, t.line,
                                "%lld vertices and %lld faces: more than the pgt limit of %u",
                                (long long)V, (long long)F, PGT_MESH_MAX_ELEMENTS);
    if (F == 0)
        return pgt_io_fail_line(err, PGT_ERROR_EMPTY, name, t.line, "header declares no faces");
    const uint64_t need = OFF_MIN_RECORD_BYTES * ((uint64_t)V + (uint64_t)F);
    if (need > size - t.next)
        return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                "header declares %lld vertices and %lld faces, which need at least "
                                "%llu bytes, but only %zu follow",
                                (long long)V, (long long)F, (unsigned long long)need,
                                size - t.next);

    /* Count the record lines first: fewer than declared is TRUNCATED, more is COUNT_MISMATCH,
     * whichever section the difference is in. */
    {
        pgt_io_text s = t;
        const uint64_t records = (uint64_t)V + (uint64_t)F;
        uint64_t found = 0;
        size_t extra_line = 0;
        while (next_data_line(&s, &p, &end))
            if (++found == records + 1) extra_line = s.line;
        if (found < records)
            return pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, s.line,
                                    "file ends after %llu of the %llu vertex and face lines the "
                                    "header declares (%lld + %lld)",
                                    (unsigned long long)found, (unsigned long long)records,
                                    (long long)V, (long long)F);
        if (found > records)
            return pgt_io_fail_line(err, PGT_ERROR_COUNT_MISMATCH, name, extra_line,
                                    "data after the %lld vertices and %lld faces the header "
                                    "declares (%llu extra lines)",
                                    (long long)V, (long long)F,
                                    (unsigned long long)(found - records));
    }

    pgt_result r = PGT_OK;
    float *positions = malloc(((size_t)V * 3 + 1) * sizeof(float));
    pgt_io_tris tris;
    memset(&tris, 0, sizeof(tris));
    tris.use_where = origin != NULL;
    pgt_io_u32vec poly = {0};
    if (!positions ||
        (tris.use_where && pgt_io_u64_reserve(&tris.vertex_where, (size_t)V + 1) != 0)) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %lld vertices",
                          name, (long long)V);
        goto done;
    }
    for (int64_t v = 0; v < V; ++v) {
        next_data_line(&t, &p, &end); /* present: counted above */
        if (!t.newline) {
            r = pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                 "file ends inside a line (no final newline)");
            goto done;
        }
        size_t c = 0;
        while ((n = pgt_io_token(&p, end, &tok)) > 0) {
            float x = 0.0f;
            pgt_result pr = c < 3 ? pgt_io_parse_float(tok, n, &x) : PGT_OK;
            if (pr != PGT_OK) {
                r = pgt_io_fail_line(err, pr, name, t.line, "vertex %lld: '%s' is %s", (long long)v,
                                     pgt_io_quote(tok, n, q, sizeof(q)), pgt_io_float_problem(pr));
                goto done;
            }
            if (c < 3) positions[3 * v + (int64_t)c] = x;
            c++;
        }
        if (c != 3) {
            r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                 "vertex %lld: line has %zu values, expected x y z", (long long)v,
                                 c);
            goto done;
        }
        if (tris.use_where) tris.vertex_where.data[tris.vertex_where.len++] = t.line;
    }
    for (int64_t f = 0; f < F; ++f) {
        next_data_line(&t, &p, &end);
        if (!t.newline) {
            r = pgt_io_fail_line(err, PGT_ERROR_TRUNCATED, name, t.line,
                                 "file ends inside a line (no final newline)");
            goto done;
        }
        int64_t corners = 0;
        n = pgt_io_token(&p, end, &tok);
        if (pgt_io_parse_i64(tok, n, &corners) == 1) {
            r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                 "face %lld: vertex count '%s' is not an integer", (long long)f,
                                 pgt_io_quote(tok, n, q, sizeof(q)));
            goto done;
        }
        if (corners < 3) {
            r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                 "face %lld has %lld vertices (a face needs at least 3)",
                                 (long long)f, (long long)corners);
            goto done;
        }
        poly.len = 0;
        for (int64_t c = 0; c < corners; ++c) {
            int64_t idx = 0;
            n = pgt_io_token(&p, end, &tok);
            if (n == 0) {
                r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                     "face %lld declares %lld vertices but the line has %lld "
                                     "indices",
                                     (long long)f, (long long)corners, (long long)c);
                goto done;
            }
            if (pgt_io_parse_i64(tok, n, &idx) == 1) {
                r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                     "face %lld: index '%s' is not an integer", (long long)f,
                                     pgt_io_quote(tok, n, q, sizeof(q)));
                goto done;
            }
            if (idx < 0 || idx >= V) {
                if (V == 0)
                    r = pgt_io_fail_line(err, PGT_ERROR_INDEX_RANGE, name, t.line,
                                         "face %lld: vertex index %s, but the file has no "
                                         "vertices",
                                         (long long)f, pgt_io_quote(tok, n, q, sizeof(q)));
                else
                    r = pgt_io_fail_line(err, PGT_ERROR_INDEX_RANGE, name, t.line,
                                         "face %lld: vertex index %s is outside 0..%lld",
                                         (long long)f, pgt_io_quote(tok, n, q, sizeof(q)),
                                         (long long)V - 1);
                goto done;
            }
            if (pgt_io_u32_reserve(&poly, poly.len + 1) != 0) {
                r = pgt_io_fail_line(err, PGT_ERROR_OUT_OF_MEMORY, name, t.line, "out of memory");
                goto done;
            }
            poly.data[poly.len++] = (uint32_t)idx;
        }
        /* Optional colour after the indices: ignored, but it must be numbers. */
        for (size_t c = 0; (n = pgt_io_token(&p, end, &tok)) > 0; ++c) {
            const pgt_result cr =
                c == OFF_MAX_FACE_COLOUR ? PGT_ERROR_PARSE : pgt_io_check_number(tok, n);
            if (cr == PGT_ERROR_OUT_OF_MEMORY) {
                r = pgt_io_fail_line(err, cr, name, t.line, "face %lld: colour value '%s' is %s",
                                     (long long)f, pgt_io_quote(tok, n, q, sizeof(q)),
                                     pgt_io_float_problem(cr));
                goto done;
            }
            if (cr != PGT_OK) {
                r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                     "face %lld: unexpected '%s' after its %lld indices (at most "
                                     "%u colour values may follow)",
                                     (long long)f, pgt_io_quote(tok, n, q, sizeof(q)),
                                     (long long)corners, OFF_MAX_FACE_COLOUR);
                goto done;
            }
        }
        r = pgt_io_tris_add(&tris, poly.data, NULL, NULL, 0, t.line, poly.len);
        if (r != PGT_OK) {
            r = pgt_io_fail_line(err, r, name, t.line, "%s", pgt_io_tris_problem(r));
            goto done;
        }
    }
    pgt_io_note_fan(name, tris.polygon_count, quiet);
    r = pgt_io_finish(out, positions, (size_t)V, &tris, 0, origin, 0, name, err);
done:
    free(positions);
    free(poly.data);
    pgt_io_tris_free(&tris);
    return r;
}

void pgt_io_write_off(FILE *f, const pgt_mesh *mesh, int precise) {
    const int d = precise ? 17 : 9; /* 9 significant digits read back as the same float */
    fprintf(f, "OFF\n%u %u 0\n", mesh->vertex_count, mesh->face_count);
    for (size_t i = 0; i < mesh->vertex_count; ++i)
        fprintf(f, "%.*g %.*g %.*g\n", d, (double)mesh->positions[3 * i], d,
                (double)mesh->positions[3 * i + 1], d, (double)mesh->positions[3 * i + 2]);
    for (size_t t = 0; t < mesh->face_count; ++t)
        fprintf(f, "3 %u %u %u\n", mesh->indices[3 * t], mesh->indices[3 * t + 1],
                mesh->indices[3 * t + 2]);
}
