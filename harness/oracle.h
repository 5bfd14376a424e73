/* pgt harness: running the oracle programs (harness/oracles/) and comparing meshes up to vertex
 * order, as the oracle-agreement tests and the benchmark need. */
#ifndef PGT_ORACLE_H
#define PGT_ORACLE_H

#include <stdint.h>

#include "pgt/mesh.h"

/* Full path of an oracle program (cgal_sqrt3, openmesh_sqrt3, meshlab_hausdorff.sh) in buf:
 * $PGT_ORACLE_DIR if set, else the build folder's harness/oracles (scripts: the source folder).
 * Returns 0 when the file exists and is executable. */
int pgt_oracle_path(const char *name, char *buf, size_t size);

typedef struct pgt_oracle_run {
    uint32_t vertices_out, faces_out;
    double median_ms, best_ms; /* of the subdivision call alone, as the oracle reports it */
} pgt_oracle_run;

/* Runs `tool IN.off K OUT.off --repeat R` (tool: "cgal_sqrt3" or "openmesh_sqrt3"; out_off "-"
 * times without writing) and parses its JSON line. Returns PGT_OK or an error naming the tool and
 * its exit status. */
pgt_result pgt_oracle_sqrt3(const char *tool, const char *in_off, uint32_t k, const char *out_off,
                            uint32_t repeat, pgt_oracle_run *out, pgt_error *err);

/* MeshLab Hausdorff distance (symmetric max) between two OFF/PLY files, through
 * meshlab_hausdorff.sh. */
pgt_result pgt_oracle_hausdorff(const char *a, const char *b, double *out_max, pgt_error *err);

typedef struct pgt_mesh_match {
    uint32_t
        unmatched_vertices; /* vertices of A with no partner in B within tol (or a partner taken) */
    double max_vertex_distance; /* over matched vertices */
    uint32_t face_mismatches; /* faces of A (after mapping) not found in B, plus count difference */
} pgt_mesh_match;

/* Matches the vertices of a to those of b (nearest within tol, one to one) and compares the face
 * sets (each face taken up to rotation, orientation kept). */
pgt_result pgt_mesh_match_compute(const pgt_mesh *a, const pgt_mesh *b, double tol,
                                  pgt_mesh_match *out, pgt_error *err);

#endif
