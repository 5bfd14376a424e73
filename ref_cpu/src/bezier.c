/* pgt: G1 cubic Bezier control points for marched polylines (bezier.h; paper 000 section 6). */
#include "pgt/bezier.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/parallel.h"

typedef struct bezier_ctx {
    const float *p, *n;
    const uint32_t *parent;
    const uint8_t *smooth;
    const float *t; /* 3 per point: the projected tangent sums */
    float *b1, *b2;
} bezier_ctx;

static int finite3(const float *v) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

/* q = p + (1/3) t t^T / |t|^2 (r - p), or the chord's third p + (r - p) / 3 when t is 0, not
 * finite, or the segment is not C1. */
static void control_point(const float p[3], const float r[3], const float t[3], int c1,
                          float q[3]) {
    const float d[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    const float tt = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
    if (c1 && tt > 0.0f && isfinite(tt)) {
        const float s = (t[0] * d[0] + t[1] * d[1] + t[2] * d[2]) / (3.0f * tt);
        for (int k = 0; k < 3; ++k) q[k] = p[k] + s * t[k];
    } else {
        for (int k = 0; k < 3; ++k) q[k] = p[k] + d[k] / 3.0f;
    }
}

static void bezier_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const bezier_ctx *c = vctx;
    (void)worker;
    for (uint32_t i = begin; i < end; ++i) {
        const float *pb = &c->p[3u * (size_t)i];
        float *b1 = &c->b1[3u * (size_t)i], *b2 = &c->b2[3u * (size_t)i];
        const uint32_t a = c->parent[i];
        if (a == PGT_NONE) {
            memcpy(b1, pb, 3u * sizeof(float));
            memcpy(b2, pb, 3u * sizeof(float));
            continue;
        }
        const float *pa = &c->p[3u * (size_t)a];
        const int c1 = !c->smooth || c->smooth[i] == PGT_BEZIER_C1;
        control_point(pa, pb, &c->t[3u * (size_t)a], c1, b1);
        control_point(pb, pa, &c->t[3u * (size_t)i], c1, b2);
    }
}

pgt_result pgt_bezier_build(const float *positions, const float *normals, const uint32_t *parent,
                            const uint8_t *smoothness, uint32_t count, uint32_t threads,
                            float *out_b1, float *out_b2, pgt_error *err) {
    for (uint32_t i = 0; i < count; ++i) {
        if (parent[i] != PGT_NONE && parent[i] >= i)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "bezier: point %u has parent %u, which does not come before it", i,
                                 parent[i]);
        if (!finite3(&positions[3u * (size_t)i]) || !finite3(&normals[3u * (size_t)i]))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "bezier: point %u has a non-finite position or normal", i);
    }
    float *t = calloc(3u * (size_t)count + 1u, sizeof(float));
    if (!t) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "bezier: out of memory");
    /* The sums of unit segment directions, in the direction of growth, in point order: a
     * point's own segment is added when the point is reached, its children's after it (they
     * come later), so every sum has one fixed order. */
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t a = parent[i];
        if (a == PGT_NONE) continue;
        const float *pa = &positions[3u * (size_t)a], *pb = &positions[3u * (size_t)i];
        const float d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        const float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(len > 0.0f)) continue; /* a zero-length segment has no direction */
        for (int k = 0; k < 3; ++k) {
            const float u = d[k] / len;
            t[3u * (size_t)a + (size_t)k] += u;
            t[3u * (size_t)i + (size_t)k] += u;
        }
    }
    /* t_j = (I - n n^T) sum */
    for (uint32_t j = 0; j < count; ++j) {
        float *tj = &t[3u * (size_t)j];
        const float *n = &normals[3u * (size_t)j];
        const float s = n[0] * tj[0] + n[1] * tj[1] + n[2] * tj[2];
        for (int k = 0; k < 3; ++k) tj[k] = tj[k] - n[k] * s;
    }
    bezier_ctx c = {positions, normals, parent, smoothness, t, out_b1, out_b2};
    pgt_parallel_for(count, threads, bezier_range, &c);
    free(t);
    return PGT_OK;
}

void pgt_bezier_eval(const float p0[3], const float b1[3], const float b2[3], const float p1[3],
                     float t, float out[3]) {
    const float s = 1.0f - t;
    const float w0 = s * s * s, w1 = 3.0f * s * s * t, w2 = 3.0f * s * t * t, w3 = t * t * t;
    for (int k = 0; k < 3; ++k) out[k] = w0 * p0[k] + w1 * b1[k] + w2 * b2[k] + w3 * p1[k];
}
