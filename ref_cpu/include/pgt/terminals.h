/* pgt: the terminal evaluator: bark tubes and leaf quads along the G1 Bezier curves (paper 000
 * section 6, "the instantiated primitives are deformed by interpolating a local frame along the
 * obtained cubic Bezier curves"; section 8: bark "a detailed cylinder composed of 216
 * polygons", leaves "textured quads"; issue 5 item 4).
 *
 * Input: pgt_expand's points (positions, unit normals, parent links; a segment is named by its
 * end point i and runs parent[i] -> i), pgt_bezier_build's control points b1, b2 per segment,
 * and the terminal records (segment, kind, two arguments, smoothness).
 *
 * Bark(radius, smoothness) on segment i: a tube of `sides` x `rings` quads (the defaults 12 x 18
 * are the paper's 216 polygons per segment; a polygon is a quad, written as two triangles, so
 * 432 triangles per segment). Rings sit at s = k / rings, k = 0..rings, along the segment's
 * curve B(s); each ring has sides + 1 vertices, vertex m at angle 2 pi m / sides, the last one a
 * copy of the first (same position bytes) with u = 1, so uvs do not wrap.
 *  - Ring sharing: the ring at a point j is emitted once and indexed by every C0 / C1 bark
 *    segment that ends or starts at j (consecutive segments and a branch child starting from
 *    its parent point), so a branch's bark has no cracks. A discontinuous segment has its own
 *    two end rings. Only rings 1..rings-1 are private to a segment.
 *  - Frame at a point j (a shared ring): T_j = the sum of the unit end tangents (B'(1) of the
 *    segment ending at j, B'(0) of the segments starting at j, in the direction of growth) of
 *    the C0 / C1 bark segments at j, each flipped to agree with the first; at a G1 joint they
 *    are collinear so the ring is perpendicular to every curve there, at a C0 joint the ring is
 *    the mitre. N_j = the surface normal n_j made perpendicular to T_j, B_j = T_j x N_j. The
 *    same frame for every segment meeting at j, so the rings coincide by construction.
 *    A discontinuous segment's end rings use its own end tangents.
 *  - Frame inside a segment (ring k): T = B'(s) / |B'(s)|, N = the end frames' normals
 *    interpolated linearly in s, made perpendicular to T and normalised (so the frame ends
 *    exactly on both point frames and follows the surface normal, which a rotation-minimising
 *    frame would only do after a correction), B = T x N.
 *  - The tube lies ON the surface: ring centres are lifted by the ring's radius along N (a tube
 *    centred on the curve would be half buried in the surface); options.centred = 1 centres it.
 *  - Radius: a shared ring's radius is the radius of its owner (the bark segment ending at j,
 *    else the lowest-indexed one starting at j); inside a segment the radius goes linearly from
 *    its start ring's to its end ring's.
 *  - Vertex normal: the radial direction cos(a) N + sin(a) B; triangles wind outwards.
 *  - uv: u = m / sides around the tube (0..1, the seam column duplicated); v = arc length
 *    along the branch / (2 pi radius) (so a texel is square on the bark), accumulated from the
 *    root over the segments (a point's v is the same for every segment meeting there); arc
 *    length = the sum of the chords between the rings.
 * Leaves(density, size) on segment i: floor(density) leaves, plus one with probability
 * frac(density). Each is a square of side `size` centred on B(s) (s uniform in [0, 1)) in the
 * tangent plane (spanned by T(s) = B'(s) / |B'(s)| and N(s) x T(s), N(s) = the end points'
 * surface normals interpolated linearly in s, made perpendicular to T(s); no bark needed),
 * turned by a uniform angle, lifted by PGT_TERMINALS_LEAF_LIFT * size along N(s); uv the unit
 * square; normal N(s); two triangles winding around N(s). Draws: pgt_rng_float(seed,
 * PGT_TERMINALS_LEAF_STREAM ^ options.stream, counter) with counter = key << 32 | k << 24 | d,
 * seed = segment_seed_id[segment] (or seed_id), key = segment_key[segment] (or the segment's
 * index), k = the record's rank among the Leaves records of its segment, d = 0 for the extra
 * leaf, 1 + 2 l and 2 + 2 l for leaf l's s and angle: no dependence on record order across
 * segments, on threads or on other segments. (pgt_ivy_generate keys a segment by its seed's id
 * and its index within the seed, so a seed's leaves do not depend on the other seeds either.)
 * Several Bark records on one segment: the first (in record order) makes the tube, the others
 * are ignored and counted.
 *
 * Output layout: for each point i in index order: the shared ring at i (if any C0 / C1 bark
 * segment uses it), then segment i's own bark rings (discontinuous: start ring, rings
 * 1..rings-1, end ring; else rings 1..rings-1), then segment i's leaves (4 vertices each);
 * triangles likewise: segment i's bark (2 per quad, ring by ring), then its leaves. So a chain
 * of N C0 / C1 bark segments has (sides + 1)(N rings + 1) vertices and 2 N sides rings
 * triangles. Counted per segment in parallel, prefix sums, filled in parallel: the same bytes
 * for any thread count. Everything float32 (the reference is built with -ffp-contract=off). */
#ifndef PGT_TERMINALS_H
#define PGT_TERMINALS_H

#include <stdint.h>

#include "progress.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 12 sides x 18 rings = 216 quads, the paper's "cylinder composed of 216 polygons": 12 sides
 * keep the cross-section within r (1 - cos 15 deg) = 3.4 % of a circle, 18 rings follow a
 * segment's bend with 18 chords (a quarter-circle turn: 0.5 % sagitta per chord). */
#define PGT_TERMINALS_DEFAULT_SIDES 12u
#define PGT_TERMINALS_DEFAULT_RINGS 18u
/* Bounds of the options: 3 sides is the thinnest closed tube; 4096 sides or rings (8M
 * triangles per segment) is far beyond any use and keeps per-segment counts in 32 bits. */
#define PGT_TERMINALS_MIN_SIDES 3u
#define PGT_TERMINALS_MAX_SIDES 4096u
#define PGT_TERMINALS_MAX_RINGS 4096u
/* Leaves per record at most: a record's draws must fit the counter's 24-bit field
 * (2 draws per leaf); 2^20 leaves on one segment is far beyond any grammar's use. */
#define PGT_TERMINALS_MAX_LEAF_DENSITY 1048576.0f
/* Largest Bark radius and leaf size: a ring or leaf corner is its centre plus about twice the
 * size, and squares of sizes appear in areas: 1e18 keeps both finite in float (3.4e38), far
 * above any mesh's scale. */
#define PGT_TERMINALS_MAX_SIZE 1e18f
/* Leaves records per segment at most: the counter's 8-bit field k. */
#define PGT_TERMINALS_MAX_LEAVES_RECORDS 256u
/* Leaf lift along the normal, as a fraction of the leaf size: enough to leave the surface
 * (against z-fighting at float32 depth precision) without visibly floating. */
#define PGT_TERMINALS_LEAF_LIFT 1e-3f
/* RNG stream of the leaf draws ("LEAF"), XORed with options.stream: distinct from the
 * grammar's rand stream 0, so leaves and the expansion's draws never coincide. */
#define PGT_TERMINALS_LEAF_STREAM 0x4C454146u

typedef struct pgt_terminals_input {
    uint32_t point_count;
    const float *positions; /* 3 * point_count */
    const float *normals;   /* 3 * point_count, unit (0 allowed: any perpendicular is used) */
    const uint32_t *parent; /* point_count; parent[i] < i or PGT_NONE */
    const float *b1, *b2;   /* 3 * point_count, pgt_bezier_build's */
    uint32_t terminal_count;
    const uint32_t *terminal_segment;     /* a non-root point */
    const uint32_t *terminal_kind;        /* pgt_grammar_terminal */
    const float *terminal_a, *terminal_b; /* Bark: radius, -; Leaves: density, size */
    const uint32_t *terminal_smoothness;  /* Bark: pgt_bezier_smoothness; Leaves: ignored */
    uint32_t seed_id;                     /* the leaves' RNG seed */
    /* Optional, point_count each (NULL: seed_id, and the segment's index): the leaves' RNG seed
     * and counter key per segment. */
    const uint32_t *segment_seed_id;
    const uint32_t *segment_key;
} pgt_terminals_input;

/* Options; a zero-initialised struct means the defaults. */
typedef struct pgt_terminals_options {
    uint32_t sides;   /* 0: PGT_TERMINALS_DEFAULT_SIDES */
    uint32_t rings;   /* quads along a segment; 0: PGT_TERMINALS_DEFAULT_RINGS */
    uint32_t stream;  /* XORed into PGT_TERMINALS_LEAF_STREAM */
    int centred;      /* 1: the tube is centred on the curve instead of lying on the surface */
    uint32_t threads; /* 0: 1 */
    /* 1: *out holds a previous output (or is zeroed) whose arrays are reused when they are large
     * enough: no allocation and no page faults on the next frame of an animation or benchmark. */
    int reuse;
    /* 1: no triangle_segment (NULL): 12 % fewer bytes written, for callers that do not need
     * it. */
    int no_triangle_segment;
    /* Most bytes of output arrays (positions, normals, uvs, triangles, triangle_segment) to
     * allocate; 0: no bound. Past it the build fails with PGT_ERROR_LIMIT before allocating,
     * naming the counts (a caller passes the memory available: an allocation the kernel
     * overcommits would get the process killed while it writes). */
    uint64_t max_bytes;
    /* NULL, or the stage "terminals" with the segments as the work (added as they are filled) */
    pgt_progress *progress;
} pgt_terminals_options;

typedef struct pgt_terminals_output {
    uint32_t vertex_count, triangle_count;
    float *positions;           /* 3 * vertex_count */
    float *normals;             /* 3 * vertex_count, unit */
    float *uvs;                 /* 2 * vertex_count */
    uint32_t *triangles;        /* 3 * triangle_count */
    uint32_t *triangle_segment; /* triangle_count: the segment (its end point), or NULL */
    uint64_t vertex_capacity, triangle_capacity; /* what the arrays hold (options.reuse) */
    uint32_t sides, rings;                       /* as used */
    /* Statistics: bark segments, their quads (= the paper's polygons), vertices and triangles;
     * leaves (a quad, two triangles, four vertices each); ignored duplicate Bark records. */
    uint32_t bark_segments, bark_vertex_count, bark_triangle_count;
    uint64_t bark_quads;
    uint32_t leaf_count;
    uint32_t duplicate_bark;
} pgt_terminals_output;

/* Builds the bark and the leaves. On failure *out holds nothing (zeroed); destroy it in any case.
 * PGT_ERROR_INVALID_ARGUMENT: missing arrays, options out of range, a parent that does not
 * come before its child, a terminal on a root or past the points, an unknown kind or
 * smoothness, a radius not > 0 or not finite, a density not in [0, MAX] or a size not > 0
 * (naming the terminal and its segment), a non-finite position or control point of a segment
 * with terminals (naming the segment); PGT_ERROR_LIMIT: more Leaves records on a segment than
 * the maximum, or more than 2^32 - 1 vertices or triangles; PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_terminals_build(pgt_terminals_output *out, const pgt_terminals_input *in,
                               const pgt_terminals_options *o, pgt_error *err);

/* Frees the arrays and zeroes *out; NULL or zeroed is a no-op. */
void pgt_terminals_destroy(pgt_terminals_output *out);

#ifdef __cplusplus
}
#endif

#endif
