/* pgt: G1 cubic Bezier curves through marched polylines (paper 000 section 6, "Cubic Bezier
 * interpolation"; paper 001 Figure 2; issue 5 item 3).
 *
 * A forest of polylines is given as points with parent links (pgt_expand's output: a point's
 * parent comes before it, PGT_NONE for a root). Every non-root point i ends one segment
 * (parent[i] -> i), which becomes the cubic Bezier curve p_a, b1, b2, p_b (a = parent[i],
 * b = i):
 *   t_j = (I - n_j n_j^T) (sum of the unit directions of all segments at point j, each taken
 *         in the direction of growth: (p_j - p_parent) / |.| for the segment ending at j and
 *         (p_child - p_j) / |.| for each segment starting at j),
 *   b1  = p_a + (1/3) t_a t_a^T / |t_a|^2 (p_b - p_a),
 *   b2  = p_b + (1/3) t_b t_b^T / |t_b|^2 (p_a - p_b).
 * So interior points, branch points and end points follow one rule (the paper: "the tangent
 * vector t_i from the average over *all* adjacent segments"; the average and the sum point the
 * same way and b1, b2 do not depend on |t|). b2 of a segment, its end point and b1 of every
 * segment leaving that point lie on the line through p_j along t_j, in the tangent plane of
 * n_j: the curves are G1 at every joint and tangent to the surface there.
 * Where t_j is 0 or not finite (segments at j cancel, e.g. a cusp, or a zero-length segment),
 * or where a segment's smoothness is not C1, its inner control points are the chord's thirds
 * (the C0 curve: the straight segment).
 *
 * Smoothness (the grammar's Bark(radius, smoothness), per segment): C1 builds the curve above;
 * C0 and discontinuous build the straight segment (C0: the terminal evaluator shares rings
 * between consecutive segments; discontinuous: it does not). Everything is float32 computed in
 * the order written (the reference is built with -ffp-contract=off); each point is independent,
 * so any thread count gives the same bytes. */
#ifndef PGT_BEZIER_H
#define PGT_BEZIER_H

#include <stdint.h>

#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The grammar's smoothness values (grammar.h's built-in constants discontinuous, C0, C1). */
typedef enum pgt_bezier_smoothness {
    PGT_BEZIER_DISCONTINUOUS = 0,
    PGT_BEZIER_C0 = 1,
    PGT_BEZIER_C1 = 2
} pgt_bezier_smoothness;

/* Control points for the segments of `count` points: positions and unit normals (3 * count
 * floats each), parent (count; parent[i] < i or PGT_NONE), smoothness (count, the segment
 * ending at each point; NULL: every segment C1). Writes out_b1 and out_b2 (3 * count floats;
 * entries of roots are set to the root's position). Errors: PGT_ERROR_INVALID_ARGUMENT naming
 * the point for a parent that does not come before its child or a non-finite position or
 * normal; PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_bezier_build(const float *positions, const float *normals, const uint32_t *parent,
                            const uint8_t *smoothness, uint32_t count, uint32_t threads,
                            float *out_b1, float *out_b2, pgt_error *err);

/* The point of segment (p0, b1, b2, p1) at t in [0, 1] (Bernstein form, float32). */
void pgt_bezier_eval(const float p0[3], const float b1[3], const float b2[3], const float p1[3],
                     float t, float out[3]);

#ifdef __cplusplus
}
#endif

#endif
