/* pgt: compact edge adjacency (opposite half-edge array).
 *
 * Half-edge h = 3*f + c runs from corner c of face f to corner (c+1)%3. opposite[h] is the
 * half-edge of the neighbouring face that runs the other way along the same edge, or PGT_NONE on a
 * border. This one array is the whole adjacency a backend uploads: next(h) = 3*(h/3) + (h+1)%3,
 * and a vertex's fan is walked with opposite[prev(h)].
 *
 * Building it also detects what breaks a 2-manifold: an edge with more than two faces, an edge
 * used twice in the same direction (inconsistent orientation), and a vertex whose faces form more
 * than one fan. Such half-edges are left unpaired (PGT_NONE); the counts and the first offender
 * are reported, and pgt_adjacency_require_manifold() turns them into an error. */
#ifndef PGT_ADJACENCY_H
#define PGT_ADJACENCY_H

#include <stdint.h>

#include "mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pgt_adjacency {
    uint32_t half_edge_count; /* 3 * face_count */
    uint32_t *opposite;       /* half_edge_count entries */
    uint32_t border_half_edges;
    uint32_t non_manifold_edges;    /* edges with >2 faces or repeated direction */
    uint32_t non_manifold_vertices; /* vertices whose faces form more than one fan */
    uint32_t degenerate_faces;      /* faces that repeat a vertex index */
    uint32_t bad_edge[2];     /* the first non-manifold edge found (vertex ids), or PGT_NONE */
    uint32_t bad_vertex;      /* the first non-manifold vertex found, or PGT_NONE */
    uint32_t bad_face;        /* the first degenerate face found, or PGT_NONE */
    uint32_t bad_edge_face;   /* the first face with bad_edge, or PGT_NONE */
    uint32_t bad_vertex_face; /* the first face at bad_vertex, or PGT_NONE */
    /* faces that share two edges with one other face (then all three: the same triangle on both
     * sides, its vertices of valence 2); a 2-manifold, but sqrt(3) would flip those edges into one
     * edge between the same two face points */
    uint32_t double_neighbour_faces;
    uint32_t bad_pair_face[2]; /* the first such face and its neighbour, or PGT_NONE */
} pgt_adjacency;

static inline uint32_t pgt_half_edge_next(uint32_t h) { return h % 3u == 2u ? h - 2u : h + 1u; }
static inline uint32_t pgt_half_edge_prev(uint32_t h) { return h % 3u == 0u ? h + 2u : h - 1u; }

/* Builds the opposite array (O(half-edges x log valence), no hashing). Fails only on bad arguments
 * or memory; manifold problems are counted, see above. */
pgt_result pgt_adjacency_build(pgt_adjacency *out, const pgt_mesh *mesh, uint32_t threads,
                               pgt_error *err);

void pgt_adjacency_destroy(pgt_adjacency *adj);

/* PGT_OK when the mesh is a 2-manifold (with or without border) with consistent orientation, no
 * degenerate face and no two faces sharing two edges (what sqrt(3) needs); otherwise
 * PGT_ERROR_NON_MANIFOLD (or PGT_ERROR_DEGENERATE) with a message naming `what` (a file name or
 * "input") and one offending edge, vertex or face (0-based ids). Checked in this order:
 * degenerate faces, non-manifold edges, non-manifold vertices, double neighbours. */
pgt_result pgt_adjacency_require_manifold(const pgt_adjacency *adj, const char *what,
                                          pgt_error *err);

/* The face that pgt_adjacency_require_manifold's error is about (the degenerate face, the first
 * face with the edge, or the first face at the vertex), or PGT_NONE when there is no error:
 * a reader's pgt_mesh_origin turns it into the file's line. */
uint32_t pgt_adjacency_error_face(const pgt_adjacency *adj);

#ifdef __cplusplus
}
#endif

#endif
