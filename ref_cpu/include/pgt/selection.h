/* pgt: face selections (which faces an operation touches), read from a face-index file or taken
 * from a per-face label. Used by sqrt(3) protected faces and smoothing groups (paper 004, 4.2). */
#ifndef PGT_SELECTION_H
#define PGT_SELECTION_H

#include <stdint.h>

#include "mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads a face-index file: face indices (0-based decimal) separated by white space or commas,
 * `#` starting a comment to the end of the line. Sets flags[i] = 1 for each listed face (flags has
 * face_count entries and is cleared first). Errors name the file and line: a token that is not a
 * whole number or a comma with no index before it on its line ("0,,1", ",1": PGT_ERROR_PARSE,
 * with the column), an index >= face_count (PGT_ERROR_INDEX_RANGE), an unreadable
 * file (PGT_ERROR_IO). Repeated indices are allowed. *out_count receives how many distinct faces
 * were selected (may be NULL). */
pgt_result pgt_selection_read(uint8_t *flags, uint32_t face_count, const char *path,
                              uint32_t *out_count, pgt_error *err);

/* flags[f] = (mesh->labels[f] == label). PGT_ERROR_INVALID_ARGUMENT when the mesh has no labels.
 * *out_count (may be NULL) receives how many faces carry the label. */
pgt_result pgt_selection_from_label(uint8_t *flags, const pgt_mesh *mesh, int32_t label,
                                    uint32_t *out_count, pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
