/* pgt: sqrt(3) subdivision (Kobbelt 2000; paper 004, Algorithm 2 and 4.2.2 / Algorithm 3).
 *
 * One call runs k iterations. Iteration i (1-based) of a call is "odd" or "even" exactly as in
 * CGAL's Sqrt3_1step and OpenMesh's Sqrt3T: on odd iterations border vertices stay and border
 * edges are not flipped; on even iterations every border edge is trisected, border vertices move
 * by the (4, 19, 4)/27 mask and border triangles split into three without a centroid. The parity
 * restarts at every call.
 *
 * Protected faces (4.2.2) get no face point, their vertices never move and edges next to them are
 * never flipped; they come out bit-identical. Faces made from a protected face stay protected in
 * every later iteration of the call.
 *
 * Per-corner UVs, when present, are subdivided with the same weights inside a chart; see
 * docs in README ("UVs and chart seams").
 *
 * Output order (deterministic, independent of the thread count): input vertices keep their
 * index; then, face by face, the centroid of each subdivided face (or the two trisection points of
 * a border face on even iterations). Each subdivided face f emits three triangles at consecutive
 * indices, triangle c belonging to half-edge 3f+c; a protected face emits itself. Labels are
 * inherited from the parent face. */
#ifndef PGT_SQRT3_H
#define PGT_SQRT3_H

#include <stdint.h>

#include "mesh.h"
#include "progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most iterations one call accepts (3^12 x faces overflows 32-bit indices for any real input). */
#define PGT_SQRT3_MAX_ITERATIONS 12u

/* Largest |coordinate| (positions and UVs) of an input: a face point sums three corners and the
 * relaxation a vertex's neighbours (fewer than 2^32) in float before dividing, and 2^32 x 1e18
 * = 4.3e27 stays finite; near FLT_MAX (3.4e38) the sums overflowed and wrote inf, exit 0. */
#define PGT_SQRT3_MAX_COORD 1e18f

typedef struct pgt_sqrt3_options {
    uint32_t iterations;            /* k >= 0 (0 copies the input) */
    uint32_t threads;               /* 0 or 1: single-threaded */
    const uint8_t *protected_faces; /* face_count flags (nonzero = protected), or NULL */
    uint8_t *out_protected;         /* optional, caller-owned, >= bound faces: output flags */
    uint32_t
        *out_face_parent;   /* optional, caller-owned, >= bound faces: input face per output face */
    uint32_t *out_opposite; /* optional, caller-owned, >= 3 x bound faces: output adjacency,
                               derived from the input's (see pgt_adjacency_build) */
    pgt_progress *progress; /* optional: the reference names a stage of k iterations and adds one
                               as each ends (pgt/progress.h); the GPU backends ignore it */
} pgt_sqrt3_options;

/* The checks of an input that every backend makes before it builds the adjacency, in this
 * order: arrays present, coordinates within +-PGT_SQRT3_MAX_COORD (PGT_ERROR_LIMIT naming the
 * vertex, or the face and corner of a UV), iterations at most PGT_SQRT3_MAX_ITERATIONS, output
 * sizes within bounds (pgt_sqrt3_bound). */
pgt_result pgt_sqrt3_check_input(const pgt_mesh *in, uint32_t iterations, pgt_error *err);

/* The first vertex with a coordinate beyond +-PGT_SQRT3_MAX_COORD (NaN included), and when there
 * is none the first corner with such a UV: the element pgt_sqrt3_check_input's coordinate error
 * is about, so that a caller can say where it is in the input file. Returns 1 (vertex), 2
 * (corner: face *index / 3, its corner *index % 3) or 0 (none), the index in *index and the
 * value in *value (value may be NULL). */
int pgt_sqrt3_far_coordinate(const pgt_mesh *in, uint32_t *index, float *value);

/* Upper bound of the output sizes for k iterations (exact when no face is protected and the mesh
 * has no border). Returns PGT_ERROR_LIMIT when they would exceed PGT_MESH_MAX_ELEMENTS. */
pgt_result pgt_sqrt3_bound(uint32_t vertex_count, uint32_t face_count, uint32_t border_edges,
                           uint32_t iterations, uint32_t *out_vertex_bound,
                           uint32_t *out_face_bound, pgt_error *err);

/* alpha_n of eq. 4.2, (4 - 2 cos(2 pi / n)) / 9, computed in double and rounded to float once:
 * the value the reference and every backend use (0 for n = 0). */
float pgt_sqrt3_alpha(uint32_t n);

/* Subdivides `in` into *out (allocated here; destroy with pgt_mesh_destroy). The input must be a
 * consistently oriented 2-manifold, with or without border (PGT_ERROR_NON_MANIFOLD otherwise,
 * naming one offending edge or vertex). opts may be NULL (k = 1). */
pgt_result pgt_sqrt3_subdivide(pgt_mesh *out, const pgt_mesh *in, const pgt_sqrt3_options *opts,
                               pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
