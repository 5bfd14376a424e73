/* pgt: the per-seed rule expander (paper 000 sections 5, 6 and 8; issue 5 item 2).
 *
 * This work is based on:
 *   Paper 000, "Dynamic On-Mesh Procedural Generation": sec. 5 (the marching rule
 *   Pred -> Marching(length, angle, condition) {TopSucc, ExtrudedSucc}), sec. 6 (depth-first
 *   evaluation, TopSucc before ExtrudedSucc, so that a branch's points all exist before its
 *   Bezier curves are built), sec. 8 (the ivy grammar; candidate directions sampled in the 2D
 *   semicircle around the main direction when the condition fails, the march stops when none
 *   complies).
 *
 * pgt_expand grows a compiled grammar (grammar.h) from seeds on a marching atlas (march.h), one
 * seed independent of every other, and returns polylines with branch connectivity and the
 * terminals placed on their segments.
 *
 * Semantics as built:
 *  - Seed i starts at texel-space (x, y) with direction (dx, dy) (pgt_march_start: the chart is
 *    the one of the texel there, the direction is normalised). Its start point is a root of the
 *    output (parent PGT_NONE); the axiom rules[0] (no arguments) runs there.
 *  - A work item is "run sequence s from item k" with a state: the current point, the current
 *    direction, the extrusion segment (below) and a frame (the rule's argument values). Items
 *    of a sequence run in order. The expander keeps them on an explicit stack (no recursion).
 *    There is no tail-call elimination: the rest of a sequence is pushed even when empty, so
 *    every unbounded recursion grows the stack or the points and meets a bound below.
 *  - Rule call: the arguments are evaluated in the caller's frame; the callee's cases are tried
 *    in order with the callee's frame, the first whose condition is not 0 runs (none: nothing).
 *  - Marching(length, angle, condition) {Top, Extruded}: length and angle are evaluated in the
 *    frame (texCoord = the current point's texel coordinates). length must lie in
 *    (0, PGT_MARCH_MAX_LENGTH] texels (else PGT_ERROR_INVALID_ARGUMENT with FILE:LINE:COL).
 *    First try: pgt_march_step turning the current direction by `angle` (march.h convention:
 *    from +x towards +y) and stepping `length` texels, the condition evaluated at the
 *    destination (texCoord = the destination's texel-space (x, y); rand draws count). If the
 *    step stops (for any pgt_march_stop reason, march.h), the candidate directions
 *    are tried in this fixed order: angle + c_1, angle + c_2, ..., c_j = +a_i for odd j and -a_i
 *    for even j, i = ceil(j / 2), a_i = (pi / 2) i / ceil(K / 2), K = options.candidates. So
 *    the closest deviations from the intended direction come first (the ivy keeps its course as
 *    well as it can), the turn towards +y before the one towards -y (an arbitrary but fixed
 *    choice), and with an even K the last pair is the semicircle's ends +-pi/2: never a
 *    direction pointing back, which is what the paper says prevents infinite loops. No
 *    randomness in the candidates: the same on every backend, and the RNG counter advances
 *    only through the grammar's own rand (the condition is evaluated once per try that
 *    reaches a destination). The first try that succeeds is taken; none: the march stops here
 *    (Top and Extruded do not run; counted in stopped_marches). A shortcut with the same
 *    output: when the grammar's condition rejects a try and reads neither context nor rand
 *    (e.g. a step counter `n < k`), it would reject every direction, so the remaining
 *    candidates are skipped (only rejected_tries differs from trying them all).
 *    On success a new point is appended: position pgt_march_position, normal the atlas's N
 *    interpolated like the position (bilinear over the texel centres around it that are inner
 *    texels of its chart, renormalised, then made unit length), texel coordinates and chart of
 *    the walker, parent the current point. Then Top runs from the new point with the walker's
 *    direction (after any rotation at chart jumps) and its memory of its last jump (march.h's
 *    no-bounce rule) to completion (depth first), and only then Extruded, from the same point,
 *    direction and memory with the segment (parent -> new point) as its extrusion segment.
 *  - Branch(n) {S1, ..., Sn}: S1, ..., Sn run in order (each to completion), all from the same
 *    point, direction, segment and frame.
 *  - Terminals Bark(radius, smoothness), Leaves(density, size): recorded with their two
 *    evaluated arguments on the current extrusion segment: the one of the innermost enclosing
 *    Marching's Extruded (a Top inherits its Marching's enclosing segment); outside every
 *    Extruded, the segment ending at the current point; at a root (no segment): dropped and
 *    counted in dropped_terminals. A segment is named by its end point's index.
 *  - split (issue 6) is PGT_ERROR_UNSUPPORTED with its FILE:LINE:COL.
 *  - RNG: rand uses pgt_rng_float(seed id, options.stream, counter), seed id = seed_base + seed
 *    index, one counter per seed from 0 advancing in expansion order: a seed's output does not
 *    depend on the other seeds, their order or the threads.
 *  - Bounds per seed: max_points (the root included), max_depth (work items on the stack),
 *    max_terminals (Bark and Leaves records) and max_items (grammar items run: a branching
 *    recursion that makes no points, such as A --> Branch(2) {B, B} ten levels deep, runs
 *    exponentially long within the other bounds), lowered to max_total_items / seed_count
 *    when that is smaller (so that many seeds are bounded too). Exceeding one is PGT_ERROR_LIMIT,
 *    "FILE:LINE:COL: seed S (id I): ..." naming the item that hit it and the option. Several
 *    failing seeds: the lowest seed index's error (the same for any thread count).
 *  - Seeds run in parallel (pgt_parallel_for_items), each into its own buffers, concatenated in
 *    seed order: the output is byte-identical for any thread count.
 *
 * Output (flat SoA arrays, float32/uint32): points of seed 0, then seed 1, ...; within a seed in
 * creation order (depth first, so a point's parent always comes before it). Terminals likewise
 * in expansion order. Branch ids: a new id at every root and at every child beyond a point's
 * first (in creation order); the first child continues its parent's branch. Ids count up from 0
 * in seed order (seed-local ids plus the ids of the seeds before). */
#ifndef PGT_EXPAND_H
#define PGT_EXPAND_H

#include <stdint.h>

#include "grammar.h"
#include "march.h"
#include "progress.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Points per seed, the root included: the paper's densest scene (8.84M polygons of 216-polygon
 * bark segments over 18 seeds) has ~2.3k segments per seed; 2^20 leaves room for 400 times that
 * while a runaway grammar stops after ~50 MB of points. */
#define PGT_EXPAND_DEFAULT_MAX_POINTS (1u << 20)

/* Work items on a seed's stack: a marching chain keeps about five per step (the pending
 * Extruded and the rest of the sequences around it), so 2^16 allows chains of ~13k steps, 26
 * times the ivy's 500-step main branch, at most ~6 MB of stack per seed (96-byte items). */
#define PGT_EXPAND_DEFAULT_MAX_DEPTH (1u << 16)

/* Bark and Leaves records per seed: the densest scene has a few per segment (~2.3k segments a
 * seed); 2^22 (64 MB of records) leaves room for 600 per segment. */
#define PGT_EXPAND_DEFAULT_MAX_TERMINALS (1u << 22)

/* Grammar items run per seed: the ivy grammar runs ~10 per point, so 2^26 allows 6.7M points'
 * worth (6 times max_points) and stops a runaway recursion after a few seconds. */
#define PGT_EXPAND_DEFAULT_MAX_ITEMS (1u << 26)

/* Grammar items run by all seeds together: max_items bounds one seed, not a run of up to 2^20
 * seeds (a grammar running 2^25 items a seed, 2.3 s each on this project's 2-core VM, would run
 * for two weeks over 2^20 seeds). Each seed may run at most max_total_items / seed_count items
 * (when that is below max_items), so that a run is bounded whatever its seed count: 2^31 items
 * is 50-100 s of the cheapest items on one core (a branching recursion: 22 M items a second),
 * while the paper's densest scenes run about 30k a seed (64 seeds: 2^25 each). */
#define PGT_EXPAND_DEFAULT_MAX_TOTAL_ITEMS (1ull << 31)

/* Candidate directions in the semicircle: 8 is a 22.5-degree spacing, ending at +-90 degrees. */
#define PGT_EXPAND_DEFAULT_CANDIDATES 8u

/* Most candidates: beyond 64 (1.4-degree spacing) a failing march costs more than it helps. */
#define PGT_EXPAND_MAX_CANDIDATES 64u

/* One seed: texel-space position and direction (need not be unit). */
typedef struct pgt_expand_seed {
    float x, y, dx, dy;
} pgt_expand_seed;

typedef struct pgt_expand_input {
    const pgt_grammar *grammar;   /* rules[0] is the axiom (no parameters) */
    const pgt_march_atlas *atlas; /* the marching view */
    /* The atlas image's N.x, N.y, N.z planes (width * height floats each, row-major). */
    const float *normal[3];
    /* Context planes in atlas space, width * height floats or NULL (reads 0):
     * context.mask(texCoord) / context.density(texCoord) read the texel containing texCoord
     * (outside the image: 0). */
    const float *mask, *density;
    const pgt_expand_seed *seeds;
    uint32_t seed_count;
    uint32_t seed_base; /* seed id of seed 0 for the RNG */
} pgt_expand_input;

/* Options; a zero-initialised struct means the defaults. */
typedef struct pgt_expand_options {
    /* Passed to pgt_march_step (rotation mode, best pointer, an extra mask); its condition must
     * be NULL: the expander installs the grammar's. */
    pgt_march_options march;
    uint32_t max_points; /* per seed; 0: PGT_EXPAND_DEFAULT_MAX_POINTS */
    uint32_t max_depth;  /* per seed; 0: PGT_EXPAND_DEFAULT_MAX_DEPTH */
    uint32_t max_terminals; /* per seed; 0: PGT_EXPAND_DEFAULT_MAX_TERMINALS */
    uint32_t max_items;     /* grammar items run per seed; 0: PGT_EXPAND_DEFAULT_MAX_ITEMS */
    /* grammar items run by all seeds: a seed's bound is the smaller of max_items and
     * max_total_items / seed_count (at least 1); 0: PGT_EXPAND_DEFAULT_MAX_TOTAL_ITEMS */
    uint64_t max_total_items;
    uint32_t candidates; /* K; 0: PGT_EXPAND_DEFAULT_CANDIDATES; at most the MAX */
    int no_candidates;   /* 1: no candidate directions (a failing first try stops) */
    uint32_t stream;     /* RNG stream of the grammar's rand */
    uint32_t threads;    /* 0: 1 */
    /* NULL, or the stage "expand" with its seeds as the work (one added as each finishes) */
    pgt_progress *progress;
} pgt_expand_options;

typedef struct pgt_expand_output {
    uint32_t point_count;
    float *x, *y, *z;    /* 3D position */
    float *nx, *ny, *nz; /* unit surface normal (0 where the atlas's N is 0) */
    float *u, *v;        /* texel-space coordinates of the walker */
    uint32_t *chart;
    uint32_t *parent; /* point index, PGT_NONE at a root */
    uint32_t *seed;   /* seed index */
    uint32_t *branch; /* branch id */
    uint32_t branch_count;

    uint32_t terminal_count;
    uint32_t *terminal_segment;     /* the segment's end point (its parent is the start) */
    uint32_t *terminal_kind;        /* pgt_grammar_terminal */
    float *terminal_a, *terminal_b; /* the two evaluated arguments */
    uint32_t *terminal_smoothness;  /* Bark: pgt_grammar_smoothness; Leaves: PGT_NONE */

    uint32_t seed_count;
    uint32_t *seed_first_point, *seed_point_count;
    uint32_t *seed_first_terminal, *seed_terminal_count;

    /* Totals over all seeds. */
    uint64_t stopped_marches;   /* Marching items where no direction succeeded */
    uint64_t rejected_tries;    /* tries stopped by the condition (or options.march.mask) */
    uint64_t candidates_used;   /* Marching items that succeeded on a candidate direction */
    uint64_t dropped_terminals; /* terminals at a root, outside any segment */
    uint64_t draws;             /* rand draws */
} pgt_expand_output;

/* Expands every seed. On failure *out holds nothing (zeroed); destroy it in any case.
 * PGT_ERROR_INVALID_ARGUMENT: missing inputs, an axiom with parameters, a bad seed (naming it),
 * a Marching length out of range or a candidate count above the maximum; PGT_ERROR_LIMIT: a
 * bound (see above) or more than 2^32 - 1 points or terminals in all; PGT_ERROR_UNSUPPORTED:
 * split; PGT_ERROR_NOT_FINITE: an expression (grammar.h); PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_expand(pgt_expand_output *out, const pgt_expand_input *in,
                      const pgt_expand_options *o, pgt_error *err);

/* Frees the arrays and zeroes *out; NULL or zeroed is a no-op. */
void pgt_expand_destroy(pgt_expand_output *out);

#ifdef __cplusplus
}
#endif

#endif
