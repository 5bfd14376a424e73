/* pgt: flat-array 3D kd-tree with explicit stacks (see kdtree.h).
 *
 * This work is based on: J. L. Bentley, "Multidimensional binary search trees used for
 * associative searching", CACM 18(9), 1975 (nearest neighbour with plane pruning), and
 * S. Maneewongvatana and D. M. Mount, "It's okay to be skinny, if your friends are fat", 1999
 * (splits at the middle of the cell rather than at the median; here without their sliding, with
 * the median where the middle leaves a side empty); used as paper 000 section 4 proposes for the
 * indirection pointers. On pizza.obj's 110k inner-boundary texels the middle splits build in
 * two thirds of the instructions of median splits (one partition pass a level instead of a
 * quickselect) and the atlas's 178k queries run in two thirds as well (callgrind). */
#include "pgt/kdtree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/mesh.h"
#include "pgt/parallel.h"

/* A point with its caller index, partitioned in place while building (contiguous, so the
 * selection scans memory in order). */
typedef struct kd_point {
    float p[3];
    uint32_t id;
} kd_point;

/* Strict order along `axis`, ties by id: a total order, so the build is deterministic. */
static int before(const kd_point *a, const kd_point *b, uint32_t axis) {
    return a->p[axis] < b->p[axis] || (a->p[axis] == b->p[axis] && a->id < b->id);
}

static void swap_points(kd_point *a, kd_point *b) {
    const kd_point t = *a;
    *a = *b;
    *b = t;
}

/* Orders v[lo, hi) so that v[k] holds the element of rank k along `axis`, with smaller
 * elements before it and greater after (Hoare quickselect, iterative). */
static void select_kth(kd_point *v, uint32_t lo, uint32_t hi, uint32_t k, uint32_t axis) {
    while (hi - lo > 2u) {
        /* median of three as the pivot: deterministic, and robust on sorted input */
        const uint32_t m = lo + (hi - lo) / 2u;
        const kd_point *a = &v[lo], *b = &v[m], *c = &v[hi - 1u];
        kd_point p;
        if (before(a, b, axis))
            p = before(b, c, axis) ? *b : (before(a, c, axis) ? *c : *a);
        else
            p = before(a, c, axis) ? *a : (before(b, c, axis) ? *c : *b);
        uint32_t i = lo, j = hi - 1u;
        for (;;) {
            while (before(&v[i], &p, axis)) ++i;
            while (before(&p, &v[j], axis)) --j;
            if (i >= j) break;
            swap_points(&v[i], &v[j]);
            ++i;
            --j;
        }
        /* v[lo..j] <= p <= v[j+1..hi): both sides are non-empty (p is not the extreme of
         * three distinct elements) */
        if (k <= j)
            hi = j + 1u;
        else
            lo = j + 1u;
    }
    if (hi - lo == 2u && before(&v[lo + 1u], &v[lo], axis)) swap_points(&v[lo], &v[lo + 1u]);
}

typedef struct kd_build_item {
    uint32_t node, begin, end, depth;
} kd_build_item;

/* Depth of the top of the tree, built level by level (the nodes of a level in parallel: 1, 2, 4,
 * 8); its (at most) 2^KD_SERIAL_DEPTH subtrees below are built in parallel. Fixed, so the tree
 * is the same for any thread count; 16 subtrees balance a few threads, and a level costs two
 * passes over its points. */
#define KD_SERIAL_DEPTH 4u

/* Nodes above this depth split at the middle of their bounding box's widest side (one partition
 * pass, and the tree follows the density of the points); deeper nodes split at the median, so
 * any point set stays within PGT_KDTREE_MAX_DEPTH: 24 + log2(2^30 / PGT_KDTREE_LEAF_SIZE) = 51.
 * Surface samples of 10^5 to 10^6 points reach their leaves by depth 20 or so. */
#define KD_MIDPOINT_DEPTH 24u

/* Partitions v[b, e) into the points below `split` along `axis` and the rest (Hoare's two
 * pointers, deterministic); returns the index of the first of the rest. */
static uint32_t partition_below(kd_point *v, uint32_t b, uint32_t e, uint32_t axis, float split) {
    uint32_t i = b, j = e;
    for (;;) {
        while (i < j && v[i].p[axis] < split) ++i;
        while (i < j && !(v[j - 1u].p[axis] < split)) --j;
        if (i >= j) return i;
        swap_points(&v[i], &v[j - 1u]);
        ++i;
        --j;
    }
}

/* The split of node item `it` over v[it.begin, it.end): the axis and plane (the middle of the
 * bounding box's widest side, or the median where the middle leaves a side empty or below
 * KD_MIDPOINT_DEPTH), with v partitioned at *mid. Returns 0, touching nothing, when the node is
 * a leaf (few points, or `stack_top` + 2 entries would not fit the builder's stack). */
static int split_node(kd_point *v, kd_build_item it, uint32_t stack_top, float *out_split,
                      uint32_t *out_axis, uint32_t *out_mid) {
    const uint32_t b = it.begin, e = it.end;
    if (e - b <= PGT_KDTREE_LEAF_SIZE || it.depth + 1u >= PGT_KDTREE_MAX_DEPTH ||
        stack_top + 2u > PGT_KDTREE_MAX_DEPTH)
        return 0;
    float lo[3], hi[3];
    for (uint32_t k = 0; k < 3; ++k) lo[k] = hi[k] = v[b].p[k];
    for (uint32_t i = b + 1u; i < e; ++i)
        for (uint32_t k = 0; k < 3; ++k) {
            if (v[i].p[k] < lo[k]) lo[k] = v[i].p[k];
            if (v[i].p[k] > hi[k]) hi[k] = v[i].p[k];
        }
    uint32_t axis = 0;
    for (uint32_t k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    /* left: coordinates <= split, right: >= split (the search's contract) */
    float split = lo[axis] + 0.5f * (hi[axis] - lo[axis]);
    uint32_t mid = b;
    if (it.depth < KD_MIDPOINT_DEPTH) mid = partition_below(v, b, e, axis, split);
    if (mid == b || mid == e) { /* deep, or the middle leaves a side empty: the median */
        mid = b + (e - b) / 2u;
        select_kth(v, b, e, mid, axis);
        split = v[mid].p[axis];
    }
    *out_split = split, *out_axis = axis, *out_mid = mid;
    return 1;
}

/* Writes node item `it`: a leaf when it does not split, else the split with its two children
 * numbered *next and *next + 1, whose items go to child[0] (left) and child[1] (right). Returns
 * how many children (0 or 2). */
static uint32_t emit_node(pgt_kdtree_node *nodes, kd_build_item it, int splits, float plane,
                          uint32_t axis, uint32_t mid, uint32_t *next, kd_build_item child[2]) {
    if (!splits) {
        nodes[it.node] = (pgt_kdtree_node){0.0f, PGT_KDTREE_LEAF, it.begin, it.end};
        return 0;
    }
    const uint32_t left = *next, right = *next + 1u;
    *next += 2u;
    nodes[it.node] = (pgt_kdtree_node){plane, axis, left, right};
    child[0] = (kd_build_item){left, it.begin, mid, it.depth + 1u};
    child[1] = (kd_build_item){right, mid, it.end, it.depth + 1u};
    return 2;
}

/* Builds the subtree of points v[begin, end) at nodes[root] (depth `depth`), numbering new nodes
 * from *next in pairs. */
static void build_nodes(pgt_kdtree_node *nodes, kd_point *v, kd_build_item root, uint32_t *next) {
    kd_build_item stack[PGT_KDTREE_MAX_DEPTH + 2u];
    uint32_t top = 0;
    stack[top++] = root;
    while (top) {
        const kd_build_item it = stack[--top];
        float split = 0.0f;
        uint32_t axis = 0, mid = 0;
        const int splits = split_node(v, it, top, &split, &axis, &mid);
        kd_build_item child[2];
        if (emit_node(nodes, it, splits, split, axis, mid, next, child))
            stack[top++] = child[1], stack[top++] = child[0]; /* the left one first */
    }
}

/* One level of the top of the tree: its nodes split in parallel, each into its own slot. */
typedef struct kd_level {
    kd_point *v;
    const kd_build_item *items;
    int *splits; /* per item: split_node's answer */
    float *plane;
    uint32_t *axis, *mid;
} kd_level;

static void split_level(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const kd_level *l = vctx;
    (void)worker;
    for (uint32_t i = begin; i < end; ++i)
        l->splits[i] = split_node(l->v, l->items[i], 0, &l->plane[i], &l->axis[i], &l->mid[i]);
}

/* The subtrees below the serial top, each built into its own node array (local node 0 is its
 * root), then copied into the tree. */
typedef struct kd_subtrees {
    kd_point *v;
    const kd_build_item *items;
    pgt_kdtree_node **nodes;
    uint32_t *counts;
} kd_subtrees;

/* The weight of a subtree for pgt_parallel_for_items: each one is a thread's worth of work. */
#define KD_SUBTREE_WEIGHT 4096u

/* The points in and out of build order: v <- xyz (into) or xyz, ids <- v (out), in parallel. */
typedef struct kd_copy {
    kd_point *v;
    const float *in;
    pgt_kdtree *out;
} kd_copy;

static void copy_points(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const kd_copy *c = vctx;
    (void)worker;
    if (c->in) {
        for (uint32_t i = begin; i < end; ++i) {
            memcpy(c->v[i].p, &c->in[3u * (size_t)i], 3u * sizeof(float));
            c->v[i].id = i;
        }
        return;
    }
    for (uint32_t i = begin; i < end; ++i) {
        memcpy(&c->out->xyz[3u * (size_t)i], c->v[i].p, 3u * sizeof(float));
        c->out->ids[i] = c->v[i].id;
    }
}

static void build_subtrees(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const kd_subtrees *s = vctx;
    (void)worker;
    for (uint32_t i = begin; i < end; ++i) {
        kd_build_item root = s->items[i];
        root.node = 0;
        uint32_t next = 1;
        build_nodes(s->nodes[i], s->v, root, &next);
        s->counts[i] = next;
    }
}

/* Subtree i's local node k goes to node items[i].node (k = 0) or first[i] + k - 1, its
 * children renumbered alike; in parallel over the subtrees once first[] is known. */
typedef struct kd_place {
    const kd_subtrees *s;
    const uint32_t *first;
    pgt_kdtree_node *nodes;
} kd_place;

static void place_subtrees(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const kd_place *p = vctx;
    (void)worker;
    for (uint32_t i = begin; i < end; ++i) {
        const pgt_kdtree_node *sn = p->s->nodes[i];
        const uint32_t shift = p->first[i] - 1u;
        for (uint32_t k = 0; k < p->s->counts[i]; ++k) {
            pgt_kdtree_node n = sn[k];
            if (n.axis != PGT_KDTREE_LEAF) n.a += shift, n.b += shift;
            p->nodes[k ? shift + k : p->s->items[i].node] = n;
        }
    }
}

pgt_result pgt_kdtree_build(pgt_kdtree *out, const float *xyz, uint32_t count, uint32_t threads,
                            pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (count > PGT_MESH_MAX_ELEMENTS)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "pgt_kdtree_build: %u points", count);
    /* every split leaves both sides non-empty: at most count leaves, 2 * count - 1 nodes */
    const uint32_t max_nodes = 2u * count + 1u;
    out->nodes = malloc(sizeof(pgt_kdtree_node) * max_nodes);
    out->ids = malloc(sizeof(uint32_t) * (count ? count : 1u));
    out->xyz = malloc(sizeof(float) * 3u * (count ? count : 1u));
    if (!out->nodes || !out->ids || !out->xyz) {
        pgt_kdtree_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_kdtree_build: out of memory");
    }
    out->point_count = count;
    kd_point *v = malloc(sizeof(kd_point) * (count ? count : 1u));
    kd_build_item pending[1u << KD_SERIAL_DEPTH];
    pgt_kdtree_node *sub_nodes[1u << KD_SERIAL_DEPTH] = {NULL};
    uint32_t sub_counts[1u << KD_SERIAL_DEPTH], n_pending = 0, nodes = 1;
    pgt_result r = PGT_OK;
    if (!v) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_kdtree_build: out of memory");
        goto done;
    }
    kd_copy copy = {v, xyz, out};
    pgt_parallel_for(count, threads, copy_points, &copy);
    /* The top KD_SERIAL_DEPTH levels level by level, the nodes of a level in parallel (the
     * root alone, then 2, 4, 8), numbered in level order; the items left at depth
     * KD_SERIAL_DEPTH are the subtrees. */
    pending[n_pending++] = (kd_build_item){0, 0, count, 0};
    for (uint32_t depth = 0; depth < KD_SERIAL_DEPTH && n_pending; ++depth) {
        int splits[1u << KD_SERIAL_DEPTH];
        float plane[1u << KD_SERIAL_DEPTH];
        uint32_t axis[1u << KD_SERIAL_DEPTH], mid[1u << KD_SERIAL_DEPTH];
        kd_level l = {v, pending, splits, plane, axis, mid};
        pgt_parallel_for_items(n_pending, KD_SUBTREE_WEIGHT, threads, split_level, &l);
        kd_build_item next[1u << KD_SERIAL_DEPTH];
        uint32_t n_next = 0;
        for (uint32_t i = 0; i < n_pending; ++i)
            n_next += emit_node(out->nodes, pending[i], splits[i], plane[i], axis[i], mid[i],
                                &nodes, &next[n_next]);
        memcpy(pending, next, sizeof(kd_build_item) * n_next);
        n_pending = n_next;
    }
    for (uint32_t i = 0; i < n_pending; ++i) {
        sub_nodes[i] =
            malloc(sizeof(pgt_kdtree_node) * (2u * (pending[i].end - pending[i].begin) + 1u));
        if (!sub_nodes[i]) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_kdtree_build: out of memory");
            goto done;
        }
    }
    kd_subtrees s = {v, pending, sub_nodes, sub_counts};
    pgt_parallel_for_items(n_pending, KD_SUBTREE_WEIGHT, threads, build_subtrees, &s);
    /* subtree i's nodes after those of the subtrees before it, its root in place */
    uint32_t first[1u << KD_SERIAL_DEPTH];
    for (uint32_t i = 0; i < n_pending; ++i) first[i] = nodes, nodes += sub_counts[i] - 1u;
    kd_place place = {&s, first, out->nodes};
    pgt_parallel_for_items(n_pending, KD_SUBTREE_WEIGHT, threads, place_subtrees, &place);
    out->node_count = nodes;
    copy.in = NULL;
    pgt_parallel_for(count, threads, copy_points, &copy);
done:
    for (uint32_t i = 0; i < n_pending; ++i) free(sub_nodes[i]);
    free(v);
    if (r != PGT_OK) pgt_kdtree_destroy(out);
    return r;
}

void pgt_kdtree_destroy(pgt_kdtree *tree) {
    if (!tree) return;
    free(tree->nodes);
    free(tree->xyz);
    free(tree->ids);
    memset(tree, 0, sizeof(*tree));
}

/* With reaches (reach2 not NULL): no point of the cell of `node`, at squared distance at least
 * `bound` from the query, lies within the base distance or its own reach. */
static inline int unreached(const float *reach2, const float *node_reach2, float base_dist2,
                            uint32_t node, float bound) {
    return reach2 && bound > base_dist2 && bound > node_reach2[node];
}

/* The search of pgt_kdtree_nearest and, with `reach2` (leaf order) and `node_reach2`,
 * pgt_kdtree_nearest_reach: inlined into both, so the plain search keeps its own code. A
 * subtree is skipped when the distance bound of its cell exceeds the best distance so far, or
 * (with reaches) every reach of its points and the base distance. */
static inline uint32_t nearest(const pgt_kdtree *tree, const float q[3], float base_dist2,
                               float max_dist2, const float *reach2, const float *node_reach2,
                               pgt_kdtree_accept_fn accept, const void *ctx, float *out_dist2) {
    uint32_t best_id = PGT_NONE;
    float best = max_dist2;
    if (!tree->point_count) return PGT_NONE;
    struct {
        uint32_t node;
        float bound;
    } stack[PGT_KDTREE_MAX_DEPTH + 2u];
    uint32_t top = 0;
    stack[top].node = 0;
    stack[top++].bound = 0.0f;
    while (top) {
        --top;
        const float bound = stack[top].bound;
        if (bound > best) continue;
        uint32_t node = stack[top].node;
        if (unreached(reach2, node_reach2, base_dist2, node, bound)) continue;
        /* down to a leaf along the near sides, the far sides on the stack; without branches on
         * the side (half of them would be mispredicted): the children are a pair, b == a + 1 */
        const pgt_kdtree_node *n = &tree->nodes[node];
        int skip = 0;
        while (n->axis != PGT_KDTREE_LEAF) {
            const float diff = q[n->axis] - n->split, plane = diff * diff;
            const float far_bound = plane > bound ? plane : bound;
            const uint32_t right = diff > 0.0f;
            stack[top].node = n->a + (right ^ 1u);
            stack[top].bound = far_bound;
            /* a far side beyond the best distance so far would only be popped and skipped */
            top += far_bound <= best;
            node = n->a + right;
            /* the near side's cell keeps the bound: out of every reach, none of it counts */
            if ((skip = unreached(reach2, node_reach2, base_dist2, node, bound))) break;
            n = &tree->nodes[node];
        }
        if (skip) continue;
        for (uint32_t i = n->a; i < n->b; ++i) {
            const float dx = tree->xyz[3u * i] - q[0], dy = tree->xyz[3u * i + 1u] - q[1],
                        dz = tree->xyz[3u * i + 2u] - q[2];
            const float d2 = dx * dx + dy * dy + dz * dz;
            const uint32_t id = tree->ids[i];
            if (d2 > best || (d2 == best && id >= best_id)) continue;
            if (reach2 && d2 > base_dist2 && d2 > reach2[i]) continue;
            if (accept && !accept(ctx, id, i)) continue;
            best = d2;
            best_id = id;
        }
    }
    if (best_id != PGT_NONE && out_dist2) *out_dist2 = best;
    return best_id;
}

uint32_t pgt_kdtree_nearest(const pgt_kdtree *tree, const float q[3], float max_dist2,
                            pgt_kdtree_accept_fn accept, const void *ctx, float *out_dist2) {
    return nearest(tree, q, max_dist2, max_dist2, NULL, NULL, accept, ctx, out_dist2);
}

uint32_t pgt_kdtree_nearest_reach(const pgt_kdtree *tree, const float q[3], float base_dist2,
                                  float max_dist2, const float *reach2, const float *node_reach2,
                                  pgt_kdtree_accept_fn accept, const void *ctx, float *out_dist2) {
    return nearest(tree, q, base_dist2, max_dist2, reach2, node_reach2, accept, ctx, out_dist2);
}

void pgt_kdtree_node_max(const pgt_kdtree *tree, const float *value, float *node_max) {
    /* children are numbered after their parent (kdtree.h): one sweep from the last node up */
    for (uint32_t i = tree->node_count; i-- > 0;) {
        const pgt_kdtree_node *n = &tree->nodes[i];
        float m = -INFINITY;
        if (n->axis == PGT_KDTREE_LEAF) {
            for (uint32_t k = n->a; k < n->b; ++k) m = value[k] > m ? value[k] : m;
        } else {
            m = node_max[n->a] > node_max[n->b] ? node_max[n->a] : node_max[n->b];
        }
        node_max[i] = m;
    }
}
