/* pgt: flat-array 3D kd-tree with explicit stacks (see kdtree.h).
 *
 * This work is based on: J. L. Bentley, "Multidimensional binary search trees used for
 * associative searching", CACM 18(9), 1975 (median splits, nearest neighbour with plane
 * pruning); used as paper 000 section 4 proposes for the indirection pointers. */
#include "pgt/kdtree.h"

#include <stdlib.h>
#include <string.h>

#include "pgt/mesh.h"

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
    uint32_t node, begin, end;
} kd_build_item;

pgt_result pgt_kdtree_build(pgt_kdtree *out, const float *xyz, uint32_t count, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (count > PGT_MESH_MAX_ELEMENTS)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "pgt_kdtree_build: %u points", count);
    /* median splits: at most 2 * ceil(count / (LEAF/2)) nodes; 2 * count + 1 bounds it simply */
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
    if (!v) {
        pgt_kdtree_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_kdtree_build: out of memory");
    }
    for (uint32_t i = 0; i < count; ++i) {
        memcpy(v[i].p, &xyz[3u * (size_t)i], 3u * sizeof(float));
        v[i].id = i;
    }
    kd_build_item stack[PGT_KDTREE_MAX_DEPTH + 2u];
    uint32_t top = 0, nodes = 1;
    stack[top++] = (kd_build_item){0, 0, count};
    while (top) {
        const kd_build_item it = stack[--top];
        pgt_kdtree_node *n = &out->nodes[it.node];
        const uint32_t b = it.begin, e = it.end;
        if (e - b <= PGT_KDTREE_LEAF_SIZE || top + 2u > PGT_KDTREE_MAX_DEPTH) {
            *n = (pgt_kdtree_node){0.0f, PGT_KDTREE_LEAF, b, e};
            continue;
        }
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
        const uint32_t mid = b + (e - b) / 2u;
        select_kth(v, b, e, mid, axis);
        const uint32_t left = nodes, right = nodes + 1u;
        nodes += 2u;
        *n = (pgt_kdtree_node){v[mid].p[axis], axis, left, right};
        stack[top++] = (kd_build_item){right, mid, e};
        stack[top++] = (kd_build_item){left, b, mid};
    }
    out->node_count = nodes;
    for (uint32_t i = 0; i < count; ++i) {
        memcpy(&out->xyz[3u * (size_t)i], v[i].p, 3u * sizeof(float));
        out->ids[i] = v[i].id;
    }
    free(v);
    return PGT_OK;
}

void pgt_kdtree_destroy(pgt_kdtree *tree) {
    if (!tree) return;
    free(tree->nodes);
    free(tree->xyz);
    free(tree->ids);
    memset(tree, 0, sizeof(*tree));
}

uint32_t pgt_kdtree_nearest(const pgt_kdtree *tree, const float q[3], float max_dist2,
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
        if (stack[top].bound > best) continue;
        const pgt_kdtree_node *n = &tree->nodes[stack[top].node];
        if (n->axis == PGT_KDTREE_LEAF) {
            for (uint32_t i = n->a; i < n->b; ++i) {
                const float dx = tree->xyz[3u * i] - q[0], dy = tree->xyz[3u * i + 1u] - q[1],
                            dz = tree->xyz[3u * i + 2u] - q[2];
                const float d2 = dx * dx + dy * dy + dz * dz;
                const uint32_t id = tree->ids[i];
                if (d2 > best || (d2 == best && id >= best_id)) continue;
                if (accept && !accept(ctx, id)) continue;
                best = d2;
                best_id = id;
            }
            continue;
        }
        const float diff = q[n->axis] - n->split, plane = diff * diff;
        const uint32_t near = diff <= 0.0f ? n->a : n->b, far = diff <= 0.0f ? n->b : n->a;
        const float parent = stack[top].bound;
        /* the far side first on the stack, so the near side is searched first */
        stack[top].node = far;
        stack[top++].bound = plane > parent ? plane : parent;
        stack[top].node = near;
        stack[top++].bound = parent;
    }
    if (best_id != PGT_NONE && out_dist2) *out_dist2 = best;
    return best_id;
}
