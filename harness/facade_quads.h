/* pgt harness: quad meshes with UVs and normals as OBJ, for procedural facades on generic meshes
 * (paper 003 sec. 10; pgt facade --mesh). pgt's mesh reader (pgt/mesh_io.h) keeps triangles
 * only; this one keeps quads. It needs ref_cpu only, so pgt_datasets compiles it too.
 *
 * Read: `v X Y Z`, `vt U V`, `vn X Y Z` and `f A/T/N B/T/N C/T/N D/T/N` (1-based, or negative:
 * relative to the end); every face has exactly 4 corners, each with a UV and a normal; other
 * statements (o, g, s, usemtl, mtllib, comments) are skipped. Each distinct (v, vt, vn) triple
 * becomes one vertex of pgt_facade_quads. Errors name FILE:LINE (PGT_ERROR_PARSE; a limit,
 * such as a line longer than 4095 characters, PGT_ERROR_LIMIT). */
#ifndef PGT_FACADE_QUADS_H
#define PGT_FACADE_QUADS_H

#include "pgt/facade.h"
#include "pgt/result.h"

/* Most vertices, UVs, normals or quads of one file. */
#define PGT_FACADE_QUADS_MAX (1u << 26)

pgt_result pgt_facade_quads_read_obj(pgt_facade_quads *out, const char *path, pgt_error *err);

/* Writes v, vt, vn per vertex (9 significant digits: the same floats read back) and one f per
 * quad (index i + 1 for all three); comment (may be NULL) as a '#' line. */
pgt_result pgt_facade_quads_write_obj(const pgt_facade_quads *m, const char *path,
                                      const char *comment, pgt_error *err);

#endif
