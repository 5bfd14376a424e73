/* pgt: ivy on a mesh, end to end (paper 000 sections 6-8; issue 5 items 5-6): seeds, painted
 * guidance, and the pipeline expand -> G1 Bezier -> terminals.
 *
 * This work is based on:
 *   Paper 000, "Dynamic On-Mesh Procedural Generation", sec. 8 and Fig. 10: seeds picked on the
 *   mesh; a binary mask painted in atlas space forbids growth (Fig. 10b); "full control over the
 *   growth is also possible by starting from an empty mask, and enabling the marching rules only
 *   in painted areas" (Fig. 10c).
 *
 * Painting as built: a stroke is a polyline of 3D points on (or near) the surface; a brush of
 * radius r (mesh units) paints every texel of the atlas (inner or indirection) whose P lies
 * within r of the polyline in 3D. Painting in 3D rather than in texel space is what a brush on
 * the mesh does: the band continues across chart seams and has the same width on charts of
 * different texel sizes. Painted texels get 0 ("allowed") in the mask, the others keep their
 * value; a caller that wants growth only along the strokes starts from a mask of 1. */
#ifndef PGT_IVY_H
#define PGT_IVY_H

#include <stdint.h>

#include "expand.h"
#include "march.h"
#include "result.h"
#include "terminals.h"

#ifdef __cplusplus
extern "C" {
#endif

/* RNG stream of the random seed placement ("SEED"): distinct from the grammar's and the leaves'. */
#define PGT_IVY_SEED_STREAM 0x53454544u

/* Most grid cells of the paint acceleration grid (the strokes' bounding box cut into cubes):
 * 64^3 keeps the grid at 1 MB of counts while a cell stays a few brush radii wide on any
 * stroke set a user paints; beyond it the cell grows. */
#define PGT_IVY_PAINT_GRID_SIDE 64u

/* Most (segment, cell) entries of the paint grid: a long straight stroke segment covers a line
 * of cells, a hostile one with a huge brush at most the whole grid; 2^26 entries is 256 MB. */
#define PGT_IVY_PAINT_MAX_ENTRIES (1u << 26)

/* `count` seeds at uniformly random inner texels (each inner texel equally likely), at the
 * texel's centre, heading in a uniformly random texel-space direction; draw 2 i and 2 i + 1 of
 * pgt_rng_double(seed, PGT_IVY_SEED_STREAM, .) place seed i, so seed i does not depend on
 * count. With a mask (width * height floats, NULL for none) only the inner texels it allows
 * (below PGT_MARCH_MASK_THRESHOLD, as the marches read it) are drawn from: a seed on a
 * forbidden texel could not take its first step. PGT_ERROR_EMPTY: no such texel;
 * PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_ivy_random_seeds(pgt_expand_seed *out, uint32_t count, const pgt_march_atlas *a,
                                const float *mask, uint32_t seed, pgt_error *err);

/* Paints strokes into `mask` (width * height floats of the atlas, row-major): every inner or
 * indirection texel whose P lies within `radius` (> 0, finite) of a stroke gets 0. Strokes:
 * points (3 * point_count floats, finite), stroke k is points stroke_first[k] ..
 * stroke_first[k + 1] - 1 (stroke_first has stroke_count + 1 non-decreasing entries ending at
 * point_count); a one-point stroke paints a ball. Parallel over rows; the same bytes for any
 * thread count. Returns the number of texels painted in *out_painted (may be NULL).
 * PGT_ERROR_INVALID_ARGUMENT: bad radius, points or stroke_first; PGT_ERROR_LIMIT: more than
 * PGT_IVY_PAINT_MAX_ENTRIES grid entries; PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_ivy_paint(float *mask, const pgt_march_atlas *a, const float *points,
                         uint32_t point_count, const uint32_t *stroke_first, uint32_t stroke_count,
                         float radius, uint32_t threads, uint64_t *out_painted, pgt_error *err);

/* Options of the pipeline; a zero-initialised struct means the defaults of every stage. */
typedef struct pgt_ivy_options {
    pgt_expand_options expand;       /* its threads are replaced by `threads` */
    pgt_terminals_options terminals; /* its threads are replaced by `threads` */
    int no_leaves; /* 1: Leaves records are dropped before the terminal evaluator */
    /* 1: *out holds a previous output (or is zeroed): its mesh arrays are reused when large
     * enough (pgt_terminals_options.reuse), as an interactive session or a benchmark runs the
     * generator again and again; the rest of *out is freed and rebuilt. */
    int reuse;
    uint32_t threads; /* every stage; 0: 1 */
    /* NULL, or the stages as they run: expand, bezier and terminals (it replaces the stages'
     * own) */
    pgt_progress *progress;
} pgt_ivy_options;

/* What the pipeline made, stage by stage. */
typedef struct pgt_ivy_output {
    pgt_expand_output expand; /* the polylines and terminal records */
    /* The points as the Bezier and terminal stages read them: 3 * point_count floats each. */
    float *positions, *normals, *b1, *b2;
    uint8_t *smoothness;       /* point_count: of the segment ending at each point */
    /* point_count each: the leaves' RNG seed of a segment (the expansion's seed id, seed_base +
     * its seed's index) and key (its point index within its seed), so a seed's leaves, like its
     * expansion, do not depend on the other seeds. */
    uint32_t *leaf_seed, *leaf_key;
    pgt_terminals_output mesh; /* bark and leaves */
    uint32_t segments;         /* non-root points: segments of the polylines */
    uint64_t polygons;         /* bark quads + leaves (the paper's polygon count) */
    uint32_t dropped_leaves;   /* Leaves records dropped by no_leaves */
    double ms_expand, ms_bezier, ms_terminals; /* wall-clock milliseconds per stage */
} pgt_ivy_output;

/* Runs pgt_expand, pgt_bezier_build (smoothness per segment from its first Bark record, C1
 * where it has none) and pgt_terminals_build, timing each. On failure *out holds nothing;
 * destroy it in any case. Errors: those of the three stages, PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_ivy_generate(pgt_ivy_output *out, const pgt_expand_input *in,
                            const pgt_ivy_options *o, pgt_error *err);

/* Frees everything and zeroes *out; NULL or zeroed is a no-op. */
void pgt_ivy_destroy(pgt_ivy_output *out);

#ifdef __cplusplus
}
#endif

#endif
