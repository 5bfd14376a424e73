/* pgt: face selections from files and labels. */
#include "pgt/selection.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

pgt_result pgt_selection_read(uint8_t *flags, uint32_t face_count, const char *path,
                              uint32_t *out_count, pgt_error *err) {
    if (out_count) *out_count = 0;
    memset(flags, 0, face_count);
    FILE *f = fopen(path, "rb");
    if (!f) return pgt_error_set(err, PGT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    uint32_t line = 1, col = 0, count = 0; /* col: of the byte just read, 1-based */
    char tok[32];
    size_t n = 0;
    int in_comment = 0, c;
    /* a comma must follow an index on its line: "0,1,,2" or ",2" is a typo, not a separator */
    int index_before_comma = 0;
    pgt_result r = PGT_OK;
    /* a UTF-8 byte order mark (Windows editors such as Notepad before 2019 start a text file
     * with one) is skipped; columns count from the text after it */
    const int b0 = fgetc(f);
    if (b0 == 0xEF) {
        const int b1 = fgetc(f), b2 = fgetc(f);
        if (b1 != 0xBB || b2 != 0xBF) {
            fclose(f);
            return pgt_error_set(err, PGT_ERROR_PARSE,
                                 "%s:1:1: a byte 0xEF that does not start a UTF-8 byte order mark "
                                 "(expected face indices)",
                                 path);
        }
    } else if (b0 != EOF) {
        ungetc(b0, f);
    }
    do {
        c = fgetc(f);
        col++;
        if (c == 0) { /* C strings would end the token there and drop what follows */
            r = pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u:%u: a NUL byte (expected text)", path,
                              line, col);
            break;
        }
        int sep = c == EOF || c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',';
        if (!in_comment && c == '#') {
            in_comment = 1;
            sep = 1;
        }
        if (sep || in_comment) {
            if (n > 0) {
                tok[n] = 0;
                char *end = NULL;
                errno = 0;
                unsigned long long v = strtoull(tok, &end, 10);
                if (tok[0] == '-' || tok[0] == '+' || errno || *end) {
                    r = pgt_error_set(err, PGT_ERROR_PARSE, "%s:%u: '%s' is not a face index", path,
                                      line, tok);
                    break;
                }
                if (v >= face_count) {
                    r = pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                      "%s:%u: face index %s out of range (the mesh has %u faces)",
                                      path, line, tok, face_count);
                    break;
                }
                count += !flags[v];
                flags[v] = 1;
                n = 0;
                index_before_comma = 1;
            }
            if (c == ',' && !in_comment) {
                if (!index_before_comma) {
                    r = pgt_error_set(err, PGT_ERROR_PARSE,
                                      "%s:%u:%u: ',' without a face index before it", path, line,
                                      col);
                    break;
                }
                index_before_comma = 0;
            }
            if (c == '\n') {
                line++, col = 0;
                in_comment = 0;
                index_before_comma = 0;
            }
            continue;
        }
        if (n + 1 >= sizeof tok) {
            tok[n] = 0;
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s:%u: token '%s...' is too long for a face index", path, line, tok);
            break;
        }
        tok[n++] = (char)c;
    } while (c != EOF);
    if (r == PGT_OK && ferror(f)) /* errno: the failed read's (a folder: EISDIR) */
        r = pgt_error_set(err, PGT_ERROR_IO, "%s: read error: %s", path, strerror(errno));
    fclose(f);
    if (r != PGT_OK) memset(flags, 0, face_count);
    if (r == PGT_OK && out_count) *out_count = count;
    return r;
}

pgt_result pgt_selection_from_label(uint8_t *flags, const pgt_mesh *mesh, int32_t label,
                                    uint32_t *out_count, pgt_error *err) {
    if (out_count) *out_count = 0;
    if (!mesh->labels)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "the mesh has no per-face labels (a PLY face property 'group')");
    uint32_t count = 0;
    for (uint32_t f = 0; f < mesh->face_count; ++f) {
        flags[f] = mesh->labels[f] == label;
        count += flags[f];
    }
    if (out_count) *out_count = count;
    return PGT_OK;
}
