/* pgt: a 3D kd-tree over a point set, in flat arrays (for the nearest-texel search of the atlas
 * pointers, paper 000 section 4: "This search can be greatly accelerated by indexing the
 * inner-boundary texels into a kd-tree").
 *
 * Nodes live in one array and name their children by index (always after their parent: one
 * sweep from the last node up visits children first); a leaf names a range of the point
 * permutation. Building and searching use explicit stacks (no recursion), so a GPU kernel can
 * walk the same arrays. A node splits its points at the middle of their bounding box's widest
 * side (at the median instead when the middle leaves a side empty, and below depth 24, which
 * bounds the depth for any point set). The shape of the tree never changes an answer (ties go to
 * the smallest id). */
#ifndef PGT_KDTREE_H
#define PGT_KDTREE_H

#include <stdint.h>

#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Points per leaf at most (a leaf scan of 8 beats two more levels of plane tests). */
#define PGT_KDTREE_LEAF_SIZE 8u

/* Deepest tree (and search stack) supported: 24 middle splits, then median splits of up to
 * 2^30 points into leaves, fit with room to spare. */
#define PGT_KDTREE_MAX_DEPTH 64u

/* Node: axis 0..2 with children `a` (coordinates <= split) and `b` = a + 1 (>= split), or a leaf
 * (axis == PGT_KDTREE_LEAF) holding permuted points [a, b). */
#define PGT_KDTREE_LEAF 3u
typedef struct pgt_kdtree_node {
    float split;
    uint32_t axis;
    uint32_t a, b;
} pgt_kdtree_node;

typedef struct pgt_kdtree {
    uint32_t point_count, node_count;
    pgt_kdtree_node *nodes; /* node 0 is the root */
    float *xyz;             /* 3 * point_count, in leaf order */
    uint32_t *ids;          /* point_count: the caller's index of each point in leaf order */
} pgt_kdtree;

/* Builds a tree over count points xyz[3*i .. 3*i+2] (finite). count may be 0. The top levels
 * are split level by level and the subtrees below them built on up to `threads` threads (0
 * means 1); the tree is the same for any thread count. */
pgt_result pgt_kdtree_build(pgt_kdtree *out, const float *xyz, uint32_t count, uint32_t threads,
                            pgt_error *err);

/* Frees and zeroes; NULL or zeroed is a no-op. */
void pgt_kdtree_destroy(pgt_kdtree *tree);

/* accept(ctx, id, slot): nonzero when point `id` (the caller's index) may be returned. slot is
 * the point's place in leaf order (tree->ids[slot] == id): a caller that keeps per-point data in
 * leaf order reads it next to the coordinates the search just read, not at a random id. */
typedef int (*pgt_kdtree_accept_fn)(const void *ctx, uint32_t id, uint32_t slot);

/* The accepted point nearest to q with squared distance <= max_dist2 (float, computed as
 * dx*dx + dy*dy + dz*dz); ties go to the smallest id, so the answer does not depend on the
 * tree's shape. Returns its id and sets *out_dist2, or returns PGT_NONE (0xFFFFFFFF). accept may
 * be NULL (every point accepted). */
uint32_t pgt_kdtree_nearest(const pgt_kdtree *tree, const float q[3], float max_dist2,
                            pgt_kdtree_accept_fn accept, const void *ctx, float *out_dist2);

/* pgt_kdtree_nearest among the points that reach q: point slot may be returned when its squared
 * distance is <= base_dist2 or <= reach2[slot] (per point, in leaf order), and <= max_dist2.
 * node_reach2 holds pgt_kdtree_node_max of reach2; it lets the search skip cells none of whose
 * points reaches q. reach2 must hold no NaN (node_max would drop it while the points' own test
 * would not, and the answer would then depend on the tree's shape). For a search whose reach counts
 * on both sides (the atlas's pointers: a coarse seam side lies farther from a fine-side texel than
 * the fine side's reach). */
uint32_t pgt_kdtree_nearest_reach(const pgt_kdtree *tree, const float q[3], float base_dist2,
                                  float max_dist2, const float *reach2, const float *node_reach2,
                                  pgt_kdtree_accept_fn accept, const void *ctx, float *out_dist2);

/* node_max[node] = the largest value[slot] of the node's points (value in leaf order,
 * node_max of tree->node_count). */
void pgt_kdtree_node_max(const pgt_kdtree *tree, const float *value, float *node_max);

#ifdef __cplusplus
}
#endif

#endif
