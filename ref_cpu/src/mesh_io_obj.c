/* pgt: Wavefront OBJ reading and writing.
 *
 * Based on the OBJ format description in Wavefront's "Advanced Visualizer" manual, Appendix B1
 * ("Object Files (.obj)"): geometric vertices `v x y z [w]`, texture vertices `vt u [v [w]]`,
 * normals `vn i j k`, and polygon faces `f v/vt/vn ...` whose indices start at 1 and may be
 * negative (relative to the end of the list read so far).
 *
 * Two passes over the buffer: the first counts v/vt/vn lines so that positive indices (which
 * may refer forward) are checked against the totals and positions are allocated once; the
 * second parses. Faces keep each corner's vt index and UVs are resolved at the end, because the
 * OBJ rule is all-or-nothing per mesh here: when only some faces have vt the UVs are dropped
 * with a note. */
#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io_internal.h"

/* Statements of the OBJ specification that pgt does not read (free-form geometry, points,
 * lines, rendering attributes): valid OBJ, so PGT_ERROR_UNSUPPORTED rather than PARSE. */
static const char *const obj_unsupported[] = {
    "vp",   "p",     "l",     "curv",    "curv2",    "surf",     "parm",       "trim",
    "hole", "scrv",  "sp",    "end",     "con",      "cstype",   "deg",        "bmat",
    "step", "mg",    "lod",   "bevel",   "c_interp", "d_interp", "usemap",     "maplib",
    "ctech", "stech", "call", "csh",     "shadow_obj", "trace_obj", "res",     "bsp",
    "bzp",  "cdc",   "cdp",
};

/* Statements read and ignored: names, groups, smoothing and materials. */
static const char *const obj_ignored[] = {"o", "g", "s", "usemtl", "mtllib"};

static int in_list(const char *tok, size_t n, const char *const *list, size_t count) {
    for (size_t i = 0; i < count; ++i)
        if (pgt_io_token_is(tok, n, list[i])) return 1;
    return 0;
}

typedef struct obj_counts {
    size_t v, vt, vn; /* lines read so far (pass 2) or in the file (pass 1) */
} obj_counts;

/* Resolves one OBJ index (1-based, or negative relative to `seen`) to 0-based, checking it
 * against `total`. */
static pgt_result obj_index(const char *tok, size_t n, size_t seen, size_t total, const char *what,
                            const char *name, size_t line, uint32_t *out, pgt_error *err) {
    char q[32];
    int64_t raw;
    int s = pgt_io_parse_i64(tok, n, &raw);
    if (s == 1)
        return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, line, "%s index '%s' is not an integer",
                                what, pgt_io_quote(tok, n, q, sizeof(q)));
    if (raw == 0)
        return pgt_io_fail_line(err, PGT_ERROR_INDEX_RANGE, name, line,
                                "face %s index 0 (OBJ indices start at 1)", what);
    if (raw > 0) {
        if ((uint64_t)raw > total)
            return pgt_io_fail_line(err, PGT_ERROR_INDEX_RANGE, name, line,
                                    "face %s index %s but the file has %zu", what,
                                    pgt_io_quote(tok, n, q, sizeof(q)), total);
        *out = (uint32_t)(raw - 1);
    } else {
        if ((uint64_t)(-raw) > seen)
            return pgt_io_fail_line(err, PGT_ERROR_INDEX_RANGE, name, line,
                                    "relative face %s index %s reaches before the first (%zu "
                                    "read so far)",
                                    what, pgt_io_quote(tok, n, q, sizeof(q)), seen);
        *out = (uint32_t)(seen - (size_t)(-raw));
    }
    return PGT_OK;
}

/* Parses `count_min..count_max` numbers of a v/vt/vn line; the first `stored` must be finite
 * and go to dst. */
static pgt_result obj_numbers(const char *p, const char *end, size_t count_min, size_t count_max,
                              size_t stored, float *dst, const char *what, const char *name,
                              size_t line, pgt_error *err) {
    size_t k = 0;
    const char *tok;
    size_t n;
    char q[32];
    while ((n = pgt_io_token(&p, end, &tok)) > 0) {
        if (k == count_max)
            return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, line,
                                    "'%s' line has more than %zu values", what, count_max);
        float f = 0.0f;
        pgt_result r = pgt_io_parse_float(tok, n, &f);
        /* Values we do not store (w, vertex colours, normals) may be nan or inf. */
        if (r != PGT_OK && (r != PGT_ERROR_NOT_FINITE || k < stored))
            return pgt_io_fail_line(err, r, name, line, "'%s' value '%s' is %s", what,
                                    pgt_io_quote(tok, n, q, sizeof(q)), pgt_io_float_problem(r));
        if (k < stored) dst[k] = f;
        k++;
    }
    if (k < count_min)
        return pgt_io_fail_line(err, PGT_ERROR_PARSE, name, line,
                                "'%s' line has %zu values, needs at least %zu", what, k, count_min);
    for (; k < stored; ++k) dst[k] = 0.0f; /* vt u without v */
    return PGT_OK;
}

pgt_result pgt_io_read_obj(pgt_mesh *out, const char *data, size_t size, const char *name,
                           int quiet, pgt_mesh_origin *origin, pgt_error *err) {
    pgt_io_text t;
    const char *p, *end, *tok;
    size_t n;

    /* Pass 1: count the v, vt and vn lines. */
    obj_counts total = {0, 0, 0};
    pgt_io_text_init(&t, data, size);
    pgt_io_text_skip_bom(&t);
    while (pgt_io_text_next(&t)) {
        p = t.begin; /* tokenised exactly as in pass 2, so the counts bound what it stores */
        n = pgt_io_token(&p, pgt_io_strip_comment(t.begin, t.end), &tok);
        if (n == 1 && tok[0] == 'v') total.v++;
        else if (n == 2 && tok[0] == 'v' && tok[1] == 't') total.vt++;
        else if (n == 2 && tok[0] == 'v' && tok[1] == 'n') total.vn++;
    }
    if (total.v > PGT_MESH_MAX_ELEMENTS || total.vt > PGT_MESH_MAX_ELEMENTS)
        return pgt_io_fail_line(err, PGT_ERROR_LIMIT, name, t.line,
                                "%zu vertices and %zu texture vertices exceed the pgt limit of %u",
                                total.v, total.vt, PGT_MESH_MAX_ELEMENTS);

    /* Pass 2: parse. */
    pgt_result r = PGT_OK;
    float *positions = malloc((total.v * 3 + 1) * sizeof(float));
    float *vts = malloc((total.vt * 2 + 1) * sizeof(float));
    pgt_io_tris tris;
    memset(&tris, 0, sizeof(tris));
    tris.use_where = origin != NULL;
    tris.use_aux = 1;
    pgt_io_u32vec poly_v = {0}, poly_vt = {0};
    pgt_io_u64vec vt_where = {0}; /* each vt record's line, for origin */
    size_t faces = 0, faces_with_vt = 0;
    obj_counts seen = {0, 0, 0};
    if (!positions || !vts ||
        (tris.use_where && (pgt_io_u64_reserve(&tris.vertex_where, total.v + 1) != 0 ||
                            pgt_io_u64_reserve(&vt_where, total.vt + 1) != 0))) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu vertices", name,
                          total.v);
        goto done;
    }
    pgt_io_text_init(&t, data, size);
    pgt_io_text_skip_bom(&t);
    while (pgt_io_text_next(&t)) {
        end = pgt_io_strip_comment(t.begin, t.end);
        p = t.begin;
        n = pgt_io_token(&p, end, &tok);
        if (n == 0) continue;
        if (pgt_io_token_is(tok, n, "v")) {
            assert(seen.v < total.v);
            r = obj_numbers(p, end, 3, 7, 3, positions + 3 * seen.v, "v", name, t.line, err);
            if (r != PGT_OK) goto done;
            if (tris.use_where) tris.vertex_where.data[tris.vertex_where.len++] = t.line;
            seen.v++;
        } else if (pgt_io_token_is(tok, n, "vt")) {
            assert(seen.vt < total.vt);
            r = obj_numbers(p, end, 1, 3, 2, vts + 2 * seen.vt, "vt", name, t.line, err);
            if (r != PGT_OK) goto done;
            if (tris.use_where) vt_where.data[vt_where.len++] = t.line;
            seen.vt++;
        } else if (pgt_io_token_is(tok, n, "vn")) {
            float unused[1];
            r = obj_numbers(p, end, 3, 3, 0, unused, "vn", name, t.line, err);
            if (r != PGT_OK) goto done;
            seen.vn++;
        } else if (pgt_io_token_is(tok, n, "f")) {
            poly_v.len = poly_vt.len = 0;
            size_t with_vt = 0;
            while ((n = pgt_io_token(&p, end, &tok)) > 0) {
                /* v, v/vt, v//vn or v/vt/vn */
                const char *part[3] = {tok, NULL, NULL};
                size_t plen[3] = {0, 0, 0}, parts = 1;
                char q[32];
                for (size_t i = 0; i < n; ++i) {
                    if (tok[i] != '/') {
                        plen[parts - 1]++;
                    } else if (parts == 3) {
                        parts = 4; /* a third slash */
                        break;
                    } else {
                        part[parts++] = tok + i + 1;
                    }
                }
                if (parts > 3 || plen[0] == 0 || (parts == 2 && plen[1] == 0) ||
                    (parts == 3 && plen[2] == 0)) {
                    r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                         "face corner '%s' is not v, v/vt, v//vn or v/vt/vn",
                                         pgt_io_quote(tok, n, q, sizeof(q)));
                    goto done;
                }
                uint32_t vi, ti = PGT_NONE, ni;
                r = obj_index(part[0], plen[0], seen.v, total.v, "vertex", name, t.line, &vi, err);
                if (r == PGT_OK && parts >= 2 && plen[1] > 0) {
                    r = obj_index(part[1], plen[1], seen.vt, total.vt, "texture", name, t.line,
                                  &ti, err);
                    with_vt++;
                }
                if (r == PGT_OK && parts == 3)
                    r = obj_index(part[2], plen[2], seen.vn, total.vn, "normal", name, t.line, &ni,
                                  err);
                if (r != PGT_OK) goto done;
                if (pgt_io_u32_reserve(&poly_v, poly_v.len + 1) != 0 ||
                    pgt_io_u32_reserve(&poly_vt, poly_vt.len + 1) != 0) {
                    r = pgt_io_fail_line(err, PGT_ERROR_OUT_OF_MEMORY, name, t.line,
                                         "out of memory");
                    goto done;
                }
                poly_v.data[poly_v.len++] = vi;
                poly_vt.data[poly_vt.len++] = ti;
            }
            if (poly_v.len < 3) {
                r = pgt_io_fail_line(err, PGT_ERROR_PARSE, name, t.line,
                                     "face with %zu vertices (a face needs at least 3)",
                                     poly_v.len);
                goto done;
            }
            /* A face counts as textured only when every corner has a vt. */
            if (with_vt == poly_v.len) faces_with_vt++;
            faces++;
            r = pgt_io_tris_add(&tris, poly_v.data, poly_vt.data, NULL, 0, t.line, poly_v.len);
            if (r != PGT_OK) {
                r = pgt_io_fail_line(err, r, name, t.line, "%s", pgt_io_tris_problem(r));
                goto done;
            }
        } else if (in_list(tok, n, obj_ignored, sizeof(obj_ignored) / sizeof(obj_ignored[0]))) {
            continue;
        } else {
            char q[32];
            int known = in_list(tok, n, obj_unsupported,
                                sizeof(obj_unsupported) / sizeof(obj_unsupported[0]));
            r = pgt_io_fail_line(err, known ? PGT_ERROR_UNSUPPORTED : PGT_ERROR_PARSE, name,
                                 t.line,
                                 "%s OBJ statement '%s' (pgt reads v vt vn f and ignores o g s "
                                 "usemtl mtllib)",
                                 known ? "unsupported" : "unknown",
                                 pgt_io_quote(tok, n, q, sizeof(q)));
            goto done;
        }
    }
    if (tris.triangle_count == 0) {
        r = pgt_io_fail_line(err, PGT_ERROR_EMPTY, name, t.line,
                             size == 0 ? "file is empty" : "no faces");
        goto done;
    }

    int with_uvs = faces_with_vt == faces;
    pgt_io_note_fan(name, tris.polygon_count, quiet);
    if (faces_with_vt > 0 && !with_uvs && !quiet)
        fprintf(stderr, "note: %s: %zu of %zu faces have no texture coordinates; UVs dropped\n",
                name, faces - faces_with_vt, faces);
    r = pgt_io_finish(out, positions, total.v, &tris, with_uvs, origin, 0, name, err);
    if (r == PGT_OK && with_uvs)
        for (size_t c = 0; c < tris.triangle_count * 3; ++c) {
            out->uvs[2 * c] = vts[2 * (size_t)tris.aux.data[c]];
            out->uvs[2 * c + 1] = vts[2 * (size_t)tris.aux.data[c] + 1];
        }
    if (r == PGT_OK && with_uvs && origin) { /* the vt places move over, as the others */
        origin->uv = vt_where.data;
        origin->uv_count = (uint32_t)vt_where.len;
        origin->uv_index = tris.aux.data;
        memset(&vt_where, 0, sizeof vt_where);
        memset(&tris.aux, 0, sizeof tris.aux);
    }
done:
    free(positions);
    free(vts);
    free(poly_v.data);
    free(poly_vt.data);
    free(vt_where.data);
    pgt_io_tris_free(&tris);
    return r;
}

void pgt_io_write_obj(FILE *f, const pgt_mesh *mesh, int precise) {
    const int d = precise ? 17 : 9; /* 9 significant digits read back as the same float */
    fprintf(f, "# written by pgt: %u vertices, %u triangles\n", mesh->vertex_count,
            mesh->face_count);
    for (size_t i = 0; i < mesh->vertex_count; ++i)
        fprintf(f, "v %.*g %.*g %.*g\n", d, (double)mesh->positions[3 * i], d,
                (double)mesh->positions[3 * i + 1], d, (double)mesh->positions[3 * i + 2]);
    if (mesh->uvs)
        for (size_t c = 0; c < (size_t)mesh->face_count * 3; ++c)
            fprintf(f, "vt %.*g %.*g\n", d, (double)mesh->uvs[2 * c], d,
                    (double)mesh->uvs[2 * c + 1]);
    for (size_t t = 0; t < mesh->face_count; ++t) {
        const uint32_t *x = mesh->indices + 3 * t;
        if (mesh->uvs)
            fprintf(f, "f %u/%zu %u/%zu %u/%zu\n", x[0] + 1, 3 * t + 1, x[1] + 1, 3 * t + 2,
                    x[2] + 1, 3 * t + 3);
        else
            fprintf(f, "f %u %u %u\n", x[0] + 1, x[1] + 1, x[2] + 1);
    }
}
