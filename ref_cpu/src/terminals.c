/* pgt: the terminal evaluator, bark tubes and leaf quads along the Bezier curves (terminals.h;
 * paper 000 sections 6 and 8). */
#include "pgt/terminals.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/bezier.h"
#include "pgt/grammar.h"
#include "pgt/parallel.h"
#include "pgt/rng.h"
#include "vec3_internal.h"

#define TWO_PI 6.283185307179586

typedef struct term_ctx {
    const pgt_terminals_input *in;
    pgt_progress *progress; /* the options' (NULL: none) */
    uint32_t sides, rings, stream;
    int centred;
    int with_segments;        /* fill out->triangle_segment */
    const float *cosv, *sinv; /* sides + 1 entries */
    uint32_t *bark;           /* per point: the segment's Bark record, PGT_NONE */
    uint8_t *shared;          /* per point: the segment has a C0 / C1 Bark */
    uint8_t *need_ring;       /* per point: a shared ring is emitted there */
    float *ring_r;            /* per point: the shared ring's radius */
    float *ring_t;            /* per point with a shared ring: its tangent (point_tangent) */
    uint32_t *child_first;    /* CSR (point_count + 1) of the children with shared bark */
    uint32_t *child;
    uint32_t *leaf_first; /* CSR (point_count + 1) of the Leaves records by segment */
    uint32_t *leaf_rec;
    float *seg_len;   /* per point: the bark segment's arc length (chords between rings) */
    uint32_t *leaf_n; /* per point: leaves on the segment */
    uint32_t *vert_n; /* per point: vertices, then (after the prefix sums) the first one */
    uint32_t *tri_n;  /* per point: triangles, then the first one */
    float *vpt;       /* per point: v at the point */
    float *cum;       /* per worker: rings + 1 floats of scratch */
    pgt_terminals_output *out;
} term_ctx;

/* ---- small vector helpers ------------------------------------------------------------- */

/* Normalises v in place; 0 when its length is 0, below the normal floats or not finite. */
static int normalize3(float v[3]) {
    const float l2 = dot3(v, v);
    if (!(l2 >= FLT_MIN) || !isfinite(l2)) return 0;
    const float l = sqrtf(l2);
    v[0] /= l, v[1] /= l, v[2] /= l;
    return 1;
}

static int finite3(const float *v) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

/* A unit vector perpendicular to unit t: t crossed with its least aligned axis. */
static void any_perpendicular(const float t[3], float r[3]) {
    const float ax = fabsf(t[0]), ay = fabsf(t[1]), az = fabsf(t[2]);
    const float e[3] = {ax <= ay && ax <= az ? 1.0f : 0.0f,
                        !(ax <= ay && ax <= az) && ay <= az ? 1.0f : 0.0f,
                        !(ax <= ay && ax <= az) && !(ay <= az) ? 1.0f : 0.0f};
    cross3(t, e, r);
    if (!normalize3(r)) r[0] = 1.0f, r[1] = 0.0f, r[2] = 0.0f;
}

/* N = n made perpendicular to unit T and normalised; if that degenerates, the fallback made
 * perpendicular; then any perpendicular. B = T x N. */
static void make_frame(const float t[3], const float n[3], const float fallback[3], float nn[3],
                       float bb[3]) {
    const float *cand[2] = {n, fallback};
    int ok = 0;
    for (int c = 0; c < 2 && !ok; ++c) {
        if (!cand[c]) continue;
        const float d = dot3(cand[c], t);
        for (int k = 0; k < 3; ++k) nn[k] = cand[c][k] - d * t[k];
        ok = normalize3(nn);
    }
    if (!ok) any_perpendicular(t, nn);
    cross3(t, nn, bb);
}

/* ---- curves --------------------------------------------------------------------------- */

static const float *pos(const term_ctx *c, uint32_t i) { return &c->in->positions[3u * (size_t)i]; }

static void seg_eval(const term_ctx *c, uint32_t i, float s, float r[3]) {
    pgt_bezier_eval(pos(c, c->in->parent[i]), &c->in->b1[3u * (size_t)i],
                    &c->in->b2[3u * (size_t)i], pos(c, i), s, r);
}

/* Unit tangent of segment i at s (direction of growth): B'(s), else the chord; 0 if both
 * vanish. */
static int seg_tangent(const term_ctx *c, uint32_t i, float s, float t[3]) {
    const float *p0 = pos(c, c->in->parent[i]), *p1 = pos(c, i);
    const float *b1 = &c->in->b1[3u * (size_t)i], *b2 = &c->in->b2[3u * (size_t)i];
    const float u = 1.0f - s;
    for (int k = 0; k < 3; ++k)
        t[k] = u * u * (b1[k] - p0[k]) + 2.0f * u * s * (b2[k] - b1[k]) + s * s * (p1[k] - b2[k]);
    if (normalize3(t)) return 1;
    for (int k = 0; k < 3; ++k) t[k] = p1[k] - p0[k];
    return normalize3(t);
}

/* The tangent of the shared ring at point j (terminals.h): the sum of the unit end tangents of
 * the shared bark segments at j, each flipped to agree with the owner's. Its cost grows with j's
 * children, so it is computed once per point (frame_range) and point_frame reads it: computed
 * for each child's segment, a point with 32,768 children took 20 s instead of milliseconds. */
static void point_tangent(const term_ctx *c, uint32_t j, float t[3]) {
    float sum[3] = {0.0f, 0.0f, 0.0f}, first[3] = {0.0f, 0.0f, 0.0f};
    int have_first = 0;
    const uint32_t lo = c->child_first[j], hi = c->child_first[j + 1u];
    /* q = 0: the segment ending at j (if shared); q = 1 + x: the x-th shared child */
    for (uint32_t q = c->shared[j] ? 0u : 1u; q < 1u + hi - lo; ++q) {
        const uint32_t seg = q == 0u ? j : c->child[lo + q - 1u];
        float u[3];
        if (!seg_tangent(c, seg, seg == j ? 1.0f : 0.0f, u)) continue;
        if (!have_first) memcpy(first, u, sizeof first), have_first = 1;
        const float sign = dot3(u, first) >= 0.0f ? 1.0f : -1.0f;
        for (int k = 0; k < 3; ++k) sum[k] += sign * u[k];
    }
    const float *n = &c->in->normals[3u * (size_t)j];
    if (normalize3(sum))
        memcpy(t, sum, sizeof sum);
    else if (have_first)
        memcpy(t, first, sizeof first);
    else
        any_perpendicular(n, t); /* a point with only zero-length segments */
}

/* The frame of the shared ring at point j, from its tangent (point_tangent). */
static void point_frame(const term_ctx *c, uint32_t j, float t[3], float nn[3], float bb[3]) {
    memcpy(t, &c->ring_t[3u * (size_t)j], 3u * sizeof(float));
    make_frame(t, &c->in->normals[3u * (size_t)j], NULL, nn, bb);
}

static void frame_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const term_ctx *c = vctx;
    (void)worker;
    for (uint32_t i = begin; i < end; ++i)
        if (c->need_ring[i]) point_tangent(c, i, &c->ring_t[3u * (size_t)i]);
}

/* ---- emission ------------------------------------------------------------------------- */

static void emit_ring(const term_ctx *c, uint32_t first, const float centre[3], const float nn[3],
                      const float bb[3], float r, float v) {
    pgt_terminals_output *o = c->out;
    const float lift = c->centred ? 0.0f : r;
    for (uint32_t m = 0; m <= c->sides; ++m) {
        const size_t q = (size_t)first + m;
        float *p = &o->positions[3u * q], *nv = &o->normals[3u * q];
        if (m == c->sides) { /* the seam: the same bytes as column 0 */
            memcpy(p, &o->positions[3u * (size_t)first], 3u * sizeof(float));
            memcpy(nv, &o->normals[3u * (size_t)first], 3u * sizeof(float));
        } else {
            for (int k = 0; k < 3; ++k) nv[k] = c->cosv[m] * nn[k] + c->sinv[m] * bb[k];
            for (int k = 0; k < 3; ++k) p[k] = centre[k] + lift * nn[k] + r * nv[k];
        }
        o->uvs[2u * q] = (float)m / (float)c->sides;
        o->uvs[2u * q + 1u] = v;
    }
}

/* The chords' cumulative lengths at the rings 0..rings of segment i (cum[0] = 0). */
static float seg_chords(const term_ctx *c, uint32_t i, float *cum) {
    float prev[3], total = 0.0f;
    memcpy(prev, pos(c, c->in->parent[i]), sizeof prev);
    if (cum) cum[0] = 0.0f;
    for (uint32_t k = 1; k <= c->rings; ++k) {
        float p[3];
        if (k == c->rings)
            memcpy(p, pos(c, i), sizeof p);
        else
            seg_eval(c, i, (float)k / (float)c->rings, p);
        const float d[3] = {p[0] - prev[0], p[1] - prev[1], p[2] - prev[2]};
        total += sqrtf(dot3(d, d));
        if (cum) cum[k] = total;
        memcpy(prev, p, sizeof p);
    }
    return total;
}

/* The leaf draws' RNG seed and counter base of record rank k on segment i (terminals.h). */
static uint32_t leaf_seed(const term_ctx *c, uint32_t i) {
    return c->in->segment_seed_id ? c->in->segment_seed_id[i] : c->in->seed_id;
}
static uint64_t leaf_base(const term_ctx *c, uint32_t i, uint32_t k) {
    const uint32_t key = c->in->segment_key ? c->in->segment_key[i] : i;
    return (uint64_t)key << 32 | (uint64_t)k << 24;
}

static uint32_t leaves_of_record(const term_ctx *c, uint32_t i, uint32_t k, float density) {
    const float whole = floorf(density);
    const float extra =
        pgt_rng_float(leaf_seed(c, i), c->stream, leaf_base(c, i, k)) < density - whole;
    return (uint32_t)whole + (uint32_t)extra;
}

static void count_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    term_ctx *c = vctx;
    (void)worker;
    const uint32_t ring = c->sides + 1u;
    for (uint32_t i = begin; i < end; ++i) {
        uint32_t leaves = 0;
        for (uint32_t q = c->leaf_first[i]; q < c->leaf_first[i + 1u]; ++q)
            leaves +=
                leaves_of_record(c, i, q - c->leaf_first[i], c->in->terminal_a[c->leaf_rec[q]]);
        c->leaf_n[i] = leaves;
        uint32_t v = c->need_ring[i] ? ring : 0u, t = 0;
        c->seg_len[i] = 0.0f;
        if (c->bark[i] != PGT_NONE) {
            c->seg_len[i] = seg_chords(c, i, NULL);
            v += (c->rings - 1u + (c->shared[i] ? 0u : 2u)) * ring;
            t += 2u * c->sides * c->rings;
        }
        c->vert_n[i] = v + 4u * leaves;
        c->tri_n[i] = t + 2u * leaves;
    }
}

static void fill_bark(const term_ctx *c, uint32_t i, uint32_t *vnext, uint32_t *tnext, float *cum) {
    pgt_terminals_output *o = c->out;
    const uint32_t a = c->in->parent[i], ring = c->sides + 1u, R = c->rings;
    const float r = c->in->terminal_a[c->bark[i]];
    float ta[3], na[3], ba[3], tb[3], nb[3], bbv[3], ra = r, rb = r;
    const float *n_a = &c->in->normals[3u * (size_t)a], *n_i = &c->in->normals[3u * (size_t)i];
    uint32_t first0, firstR;
    if (c->shared[i]) {
        point_frame(c, a, ta, na, ba);
        point_frame(c, i, tb, nb, bbv);
        ra = c->ring_r[a], rb = c->ring_r[i];
        first0 = c->vert_n[a], firstR = c->vert_n[i];
    } else {
        if (!seg_tangent(c, i, 0.0f, ta)) any_perpendicular(n_a, ta);
        if (!seg_tangent(c, i, 1.0f, tb)) memcpy(tb, ta, sizeof tb);
        make_frame(ta, n_a, NULL, na, ba);
        make_frame(tb, n_i, NULL, nb, bbv);
        first0 = *vnext;
        emit_ring(c, first0, pos(c, a), na, ba, ra, c->vpt[a]);
        *vnext += ring;
        firstR = PGT_NONE; /* after the interior rings */
    }
    const float total = seg_chords(c, i, cum);
    const float va = c->vpt[a], vb = c->vpt[i];
    const uint32_t interior = *vnext;
    for (uint32_t k = 1; k < R; ++k) {
        const float s = (float)k / (float)R;
        float p[3], t[3], nl[3], nn[3], bb[3];
        seg_eval(c, i, s, p);
        if (!seg_tangent(c, i, s, t))
            for (int q = 0; q < 3; ++q) t[q] = ta[q]; /* a zero-length segment */
        for (int q = 0; q < 3; ++q) nl[q] = (1.0f - s) * na[q] + s * nb[q];
        make_frame(t, nl, na, nn, bb);
        const float w = total > 0.0f ? cum[k] / total : s;
        emit_ring(c, *vnext, p, nn, bb, (1.0f - s) * ra + s * rb, va + (vb - va) * w);
        *vnext += ring;
    }
    if (!c->shared[i]) {
        firstR = *vnext;
        emit_ring(c, firstR, pos(c, i), nb, bbv, rb, vb);
        *vnext += ring;
    }
    for (uint32_t k = 0; k < R; ++k) {
        const uint32_t A = k == 0 ? first0 : interior + (k - 1u) * ring;
        const uint32_t B = k + 1u == R ? firstR : interior + k * ring;
        for (uint32_t m = 0; m < c->sides; ++m) {
            uint32_t *tri = &o->triangles[3u * (size_t)*tnext];
            tri[0] = A + m, tri[1] = A + m + 1u, tri[2] = B + m + 1u;
            tri[3] = A + m, tri[4] = B + m + 1u, tri[5] = B + m;
            if (c->with_segments)
                o->triangle_segment[*tnext] = i, o->triangle_segment[*tnext + 1u] = i;
            *tnext += 2u;
        }
    }
}

static void fill_leaves(const term_ctx *c, uint32_t i, uint32_t *vnext, uint32_t *tnext) {
    pgt_terminals_output *o = c->out;
    const uint32_t a = c->in->parent[i];
    const float *n_a = &c->in->normals[3u * (size_t)a], *n_i = &c->in->normals[3u * (size_t)i];
    for (uint32_t q = c->leaf_first[i]; q < c->leaf_first[i + 1u]; ++q) {
        const uint32_t rec = c->leaf_rec[q], k = q - c->leaf_first[i];
        const uint32_t n = leaves_of_record(c, i, k, c->in->terminal_a[rec]);
        const float h = 0.5f * c->in->terminal_b[rec];
        const float lift = PGT_TERMINALS_LEAF_LIFT * c->in->terminal_b[rec];
        const uint64_t base = leaf_base(c, i, k);
        const uint32_t seed = leaf_seed(c, i);
        for (uint32_t l = 0; l < n; ++l) {
            const float s = pgt_rng_float(seed, c->stream, base + 1u + 2u * l);
            const float ang = (float)(TWO_PI * pgt_rng_float(seed, c->stream, base + 2u + 2u * l));
            float p[3], t[3], nl[3], nn[3], side[3], e1[3], e2[3];
            seg_eval(c, i, s, p);
            for (int d = 0; d < 3; ++d) nl[d] = (1.0f - s) * n_a[d] + s * n_i[d];
            if (!seg_tangent(c, i, s, t)) any_perpendicular(nl, t);
            make_frame(t, nl, NULL, nn, side);
            cross3(nn, t, side); /* N x T: the second tangent-plane axis */
            const float ca = cosf(ang), sa = sinf(ang);
            for (int d = 0; d < 3; ++d) e1[d] = ca * t[d] + sa * side[d];
            cross3(nn, e1, e2);
            static const float corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (uint32_t v = 0; v < 4u; ++v) {
                const size_t w = (size_t)*vnext + v;
                for (int d = 0; d < 3; ++d) {
                    o->positions[3u * w + (size_t)d] =
                        p[d] + lift * nn[d] + h * corner[v][0] * e1[d] + h * corner[v][1] * e2[d];
                    o->normals[3u * w + (size_t)d] = nn[d];
                }
                o->uvs[2u * w] = corner[v][0] > 0.0f ? 1.0f : 0.0f;
                o->uvs[2u * w + 1u] = corner[v][1] > 0.0f ? 1.0f : 0.0f;
            }
            uint32_t *tri = &o->triangles[3u * (size_t)*tnext];
            tri[0] = *vnext, tri[1] = *vnext + 1u, tri[2] = *vnext + 2u;
            tri[3] = *vnext, tri[4] = *vnext + 2u, tri[5] = *vnext + 3u;
            if (c->with_segments)
                o->triangle_segment[*tnext] = i, o->triangle_segment[*tnext + 1u] = i;
            *tnext += 2u, *vnext += 4u;
        }
    }
}

static void fill_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const term_ctx *c = vctx;
    float *cum = &c->cum[(size_t)worker * (c->rings + 1u)];
    for (uint32_t i = begin; i < end; ++i) {
        uint32_t vnext = c->vert_n[i], tnext = c->tri_n[i];
        if (c->need_ring[i]) {
            float t[3], nn[3], bb[3];
            point_frame(c, i, t, nn, bb);
            emit_ring(c, vnext, pos(c, i), nn, bb, c->ring_r[i], c->vpt[i]);
            vnext += c->sides + 1u;
        }
        if (c->bark[i] != PGT_NONE) fill_bark(c, i, &vnext, &tnext, cum);
        fill_leaves(c, i, &vnext, &tnext);
    }
    pgt_progress_add(c->progress, end - begin);
}

/* ---- driver --------------------------------------------------------------------------- */

static void ctx_free(term_ctx *c) {
    free(c->bark), free(c->shared), free(c->need_ring), free(c->ring_r), free(c->child_first);
    free(c->ring_t);
    free(c->child), free(c->leaf_first), free(c->leaf_rec), free(c->seg_len), free(c->leaf_n);
    free(c->vert_n), free(c->tri_n), free(c->vpt), free(c->cum);
    free((void *)c->cosv), free((void *)c->sinv);
}

static pgt_result fail(term_ctx *c, pgt_terminals_output *out, pgt_result r) {
    ctx_free(c);
    pgt_terminals_destroy(out);
    return r;
}

static pgt_result validate(const pgt_terminals_input *in, pgt_error *err) {
    const uint32_t n = in->point_count;
    for (uint32_t i = 0; i < n; ++i)
        if (in->parent[i] != PGT_NONE && in->parent[i] >= i)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "terminals: point %u has parent %u, which does not come before it",
                                 i, in->parent[i]);
    for (uint32_t t = 0; t < in->terminal_count; ++t) {
        const uint32_t s = in->terminal_segment[t], kind = in->terminal_kind[t];
        const float a = in->terminal_a[t], b = in->terminal_b[t];
        if (s >= n || in->parent[s] == PGT_NONE)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "terminals: terminal %u names segment %u, which is %s", t, s,
                                 s >= n ? "past the points" : "a root (no segment ends there)");
        if (kind == PGT_GRAMMAR_TERMINAL_BARK) {
            if (!(a > 0.0f && a <= PGT_TERMINALS_MAX_SIZE))
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "terminals: terminal %u (Bark on segment %u): radius %g is "
                                     "not in (0, %g]",
                                     t, s, (double)a, (double)PGT_TERMINALS_MAX_SIZE);
            const uint32_t sm = in->terminal_smoothness[t];
            if (sm != PGT_BEZIER_DISCONTINUOUS && sm != PGT_BEZIER_C0 && sm != PGT_BEZIER_C1)
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "terminals: terminal %u (Bark on segment %u): smoothness %u "
                                     "is none of discontinuous (0), C0 (1), C1 (2)",
                                     t, s, sm);
        } else if (kind == PGT_GRAMMAR_TERMINAL_LEAVES) {
            if (!(a >= 0.0f && a <= PGT_TERMINALS_MAX_LEAF_DENSITY))
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "terminals: terminal %u (Leaves on segment %u): density %g is "
                                     "not in [0, %g]",
                                     t, s, (double)a, (double)PGT_TERMINALS_MAX_LEAF_DENSITY);
            if (!(b > 0.0f && b <= PGT_TERMINALS_MAX_SIZE))
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "terminals: terminal %u (Leaves on segment %u): size %g is "
                                     "not in (0, %g]",
                                     t, s, (double)b, (double)PGT_TERMINALS_MAX_SIZE);
        } else {
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "terminals: terminal %u on segment %u has unknown kind %u", t, s,
                                 kind);
        }
        const size_t p = 3u * (size_t)in->parent[s], q = 3u * (size_t)s;
        if (!finite3(&in->positions[p]) || !finite3(&in->positions[q]) ||
            !finite3(&in->normals[p]) || !finite3(&in->normals[q]) || !finite3(&in->b1[q]) ||
            !finite3(&in->b2[q]))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "terminals: segment %u (%u -> %u, terminal %u) has a non-finite "
                                 "position, normal or control point",
                                 s, in->parent[s], s, t);
    }
    return PGT_OK;
}

pgt_result pgt_terminals_build(pgt_terminals_output *out, const pgt_terminals_input *in,
                               const pgt_terminals_options *o, pgt_error *err) {
    if (!out) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "terminals: no output");
    /* o->reuse: keep the previous output's arrays (ivy.h: a generator run frame after frame keeps
     * its buffers, as a GPU pipeline keeps its vertex buffers) */
    pgt_terminals_output old;
    memset(&old, 0, sizeof old);
    if (o && o->reuse) old = *out;
    memset(out, 0, sizeof *out);
    out->positions = old.positions, out->normals = old.normals, out->uvs = old.uvs;
    out->triangles = old.triangles, out->triangle_segment = old.triangle_segment;
    out->vertex_capacity = old.vertex_capacity, out->triangle_capacity = old.triangle_capacity;
    if (!in ||
        (in->point_count &&
         (!in->positions || !in->normals || !in->parent || !in->b1 || !in->b2)) ||
        (in->terminal_count && (!in->terminal_segment || !in->terminal_kind || !in->terminal_a ||
                                !in->terminal_b || !in->terminal_smoothness)))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "terminals: missing input arrays");
    const pgt_terminals_options zero = {0};
    if (!o) o = &zero;
    term_ctx c;
    memset(&c, 0, sizeof c);
    c.in = in, c.out = out, c.centred = o->centred;
    c.sides = o->sides ? o->sides : PGT_TERMINALS_DEFAULT_SIDES;
    c.rings = o->rings ? o->rings : PGT_TERMINALS_DEFAULT_RINGS;
    c.stream = PGT_TERMINALS_LEAF_STREAM ^ o->stream;
    if (c.sides < PGT_TERMINALS_MIN_SIDES || c.sides > PGT_TERMINALS_MAX_SIDES ||
        c.rings > PGT_TERMINALS_MAX_RINGS)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "terminals: %u sides x %u rings is outside [%u, %u] x [1, %u]",
                             c.sides, c.rings, PGT_TERMINALS_MIN_SIDES, PGT_TERMINALS_MAX_SIDES,
                             PGT_TERMINALS_MAX_RINGS);
    const pgt_result valid = validate(in, err);
    if (valid != PGT_OK) return valid;
    out->sides = c.sides, out->rings = c.rings;

    const uint32_t n = in->point_count;
    const size_t np = (size_t)n + 1u;
    c.bark = malloc(np * sizeof(uint32_t));
    c.shared = calloc(np, 1u), c.need_ring = calloc(np, 1u);
    c.ring_r = calloc(np, sizeof(float));
    c.ring_t = malloc(3u * np * sizeof(float));
    c.child_first = calloc(np + 1u, sizeof(uint32_t));
    c.child = malloc(np * sizeof(uint32_t));
    c.leaf_first = calloc(np + 1u, sizeof(uint32_t));
    c.leaf_rec = malloc(((size_t)in->terminal_count + 1u) * sizeof(uint32_t));
    c.seg_len = malloc(np * sizeof(float)), c.leaf_n = malloc(np * sizeof(uint32_t));
    c.vert_n = malloc(np * sizeof(uint32_t)), c.tri_n = malloc(np * sizeof(uint32_t));
    c.vpt = malloc(np * sizeof(float));
    float *cosv = malloc(((size_t)c.sides + 1u) * sizeof(float));
    float *sinv = malloc(((size_t)c.sides + 1u) * sizeof(float));
    c.cosv = cosv, c.sinv = sinv;
    if (!c.bark || !c.shared || !c.need_ring || !c.ring_r || !c.ring_t || !c.child_first ||
        !c.child || !c.leaf_first || !c.leaf_rec || !c.seg_len || !c.leaf_n || !c.vert_n ||
        !c.tri_n || !c.vpt || !cosv || !sinv)
        return fail(&c, out,
                    pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "terminals: out of memory"));
    for (uint32_t m = 0; m <= c.sides; ++m) {
        const double ang = TWO_PI * (double)m / (double)c.sides;
        cosv[m] = (float)cos(ang), sinv[m] = (float)sin(ang);
    }

    /* Records by segment: the first Bark, and the Leaves in record order (a CSR). */
    for (uint32_t i = 0; i < n; ++i) c.bark[i] = PGT_NONE;
    for (uint32_t t = 0; t < in->terminal_count; ++t) {
        const uint32_t s = in->terminal_segment[t];
        if (in->terminal_kind[t] == PGT_GRAMMAR_TERMINAL_LEAVES) {
            if (++c.leaf_first[s + 1u] > PGT_TERMINALS_MAX_LEAVES_RECORDS)
                return fail(&c, out,
                            pgt_error_set(err, PGT_ERROR_LIMIT,
                                          "terminals: segment %u has more than %u Leaves records "
                                          "(terminal %u)",
                                          s, PGT_TERMINALS_MAX_LEAVES_RECORDS, t));
        } else if (c.bark[s] == PGT_NONE) {
            c.bark[s] = t;
            c.shared[s] = in->terminal_smoothness[t] != PGT_BEZIER_DISCONTINUOUS;
            out->bark_segments++;
        } else {
            out->duplicate_bark++;
        }
    }
    for (uint32_t i = 0; i < n; ++i) c.leaf_first[i + 1u] += c.leaf_first[i];
    for (uint32_t t = 0; t < in->terminal_count; ++t)
        if (in->terminal_kind[t] == PGT_GRAMMAR_TERMINAL_LEAVES)
            c.leaf_rec[c.leaf_first[in->terminal_segment[t]]++] = t;
    for (uint32_t i = n; i > 0; --i) c.leaf_first[i] = c.leaf_first[i - 1u];
    c.leaf_first[0] = 0;

    /* Shared rings: owned by the segment ending at j, else by the lowest shared child. */
    for (uint32_t i = 0; i < n; ++i) {
        if (!c.shared[i]) continue;
        const float r = in->terminal_a[c.bark[i]];
        c.need_ring[i] = 1, c.ring_r[i] = r;
        const uint32_t a = in->parent[i];
        if (!c.need_ring[a]) c.need_ring[a] = 1, c.ring_r[a] = r;
        c.child_first[a + 1u]++;
    }
    for (uint32_t i = 0; i < n; ++i) c.child_first[i + 1u] += c.child_first[i];
    for (uint32_t i = 0; i < n; ++i)
        if (c.shared[i]) c.child[c.child_first[in->parent[i]]++] = i;
    for (uint32_t i = n; i > 0; --i) c.child_first[i] = c.child_first[i - 1u];
    c.child_first[0] = 0;

    /* Count per segment (parallel), then prefix sums and v along the branches. */
    const uint32_t threads = pgt_parallel_workers(o->threads);
    pgt_parallel_for(n, threads, count_range, &c);
    uint64_t vtotal = 0, ttotal = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t vn = c.vert_n[i], tn = c.tri_n[i];
        c.vert_n[i] = (uint32_t)vtotal, c.tri_n[i] = (uint32_t)ttotal;
        vtotal += vn, ttotal += tn;
        out->leaf_count += c.leaf_n[i];
        if (vtotal > UINT32_MAX || ttotal > UINT32_MAX)
            return fail(&c, out,
                        pgt_error_set(err, PGT_ERROR_LIMIT,
                                      "terminals: more than 2^32 - 1 vertices or triangles "
                                      "(reached at segment %u)",
                                      i));
        const uint32_t a = in->parent[i];
        c.vpt[i] = 0.0f;
        if (a == PGT_NONE) continue;
        c.vpt[i] = c.vpt[a];
        if (c.bark[i] != PGT_NONE) {
            const float r = in->terminal_a[c.bark[i]];
            const float mean = c.shared[i] ? 0.5f * (c.ring_r[a] + c.ring_r[i]) : r;
            c.vpt[i] += c.seg_len[i] / (float)(TWO_PI * (double)mean);
        }
    }
    out->vertex_count = (uint32_t)vtotal, out->triangle_count = (uint32_t)ttotal;
    out->bark_quads = (uint64_t)out->bark_segments * c.sides * c.rings;
    out->bark_triangle_count = (uint32_t)(ttotal - 2u * (uint64_t)out->leaf_count);
    out->bark_vertex_count = (uint32_t)(vtotal - 4u * (uint64_t)out->leaf_count);
    const int with_segments = !o->no_triangle_segment;
    const uint64_t bytes = 32u * vtotal + (with_segments ? 16u : 12u) * ttotal;
    if (o->max_bytes && bytes > o->max_bytes)
        return fail(&c, out,
                    pgt_error_set(err, PGT_ERROR_LIMIT,
                                  "terminals: %llu vertices and %llu triangles (%llu bark "
                                  "segments, %llu leaves) would take %.2f GiB, more than the "
                                  "%.2f GiB allowed",
                                  (unsigned long long)vtotal, (unsigned long long)ttotal,
                                  (unsigned long long)out->bark_segments,
                                  (unsigned long long)out->leaf_count, (double)bytes / 1073741824.0,
                                  (double)o->max_bytes / 1073741824.0));
    if (vtotal > out->vertex_capacity || !out->positions) {
        free(out->positions), free(out->normals), free(out->uvs);
        out->positions = malloc(3u * (size_t)vtotal * sizeof(float) + 1u);
        out->normals = malloc(3u * (size_t)vtotal * sizeof(float) + 1u);
        out->uvs = malloc(2u * (size_t)vtotal * sizeof(float) + 1u);
        out->vertex_capacity = vtotal;
    }
    if (ttotal > out->triangle_capacity || !out->triangles ||
        (with_segments && !out->triangle_segment)) {
        free(out->triangles), free(out->triangle_segment);
        out->triangles = malloc(3u * (size_t)ttotal * sizeof(uint32_t) + 1u);
        out->triangle_segment =
            with_segments ? malloc((size_t)ttotal * sizeof(uint32_t) + 1u) : NULL;
        out->triangle_capacity = ttotal;
    }
    if (!with_segments && out->triangle_segment) {
        free(out->triangle_segment);
        out->triangle_segment = NULL;
    }
    c.with_segments = with_segments;
    c.cum = malloc((size_t)threads * (c.rings + 1u) * sizeof(float));
    if (!out->positions || !out->normals || !out->uvs || !out->triangles ||
        (with_segments && !out->triangle_segment) || !c.cum)
        return fail(&c, out,
                    pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "terminals: out of memory"));

    /* A segment's fill writes sides x rings bark quads (216 by default) and its leaves: as work,
     * hundreds of elements, not one, or pgt_parallel_for (>= 4096 elements a thread) ran up to
     * 8191 segments on one thread (a step down in Fig. 11's times where the count crossed 8192:
     * 25.1 -> 15.5 ms from 33 to 34 main branches). Capped so that n x weight fits 32 bits. */
    const uint32_t quads = c.sides * c.rings; /* >= 1: both are checked above */
    const uint32_t weight = n && quads > UINT32_MAX / n ? UINT32_MAX / n : quads;
    pgt_parallel_for(n, threads, frame_range, &c); /* the shared rings' tangents, once each */
    c.progress = o->progress;
    pgt_progress_stage(o->progress, "terminals", n, "segments");
    pgt_parallel_for_items(n, weight, threads, fill_range, &c);
    ctx_free(&c);
    return PGT_OK;
}

void pgt_terminals_destroy(pgt_terminals_output *out) {
    if (!out) return;
    free(out->positions), free(out->normals), free(out->uvs), free(out->triangles);
    free(out->triangle_segment);
    memset(out, 0, sizeof *out);
}
