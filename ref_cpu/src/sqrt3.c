/* pgt: sqrt(3) subdivision.
 *
 * This work is based on:
 *   L. Kobbelt. sqrt(3)-Subdivision. SIGGRAPH 2000 (the scheme and its boundary rule).
 *   S. Dusberger. Mesh-Subdivision Methods in CGA Shape Grammars (paper 004): Algorithm 2 (the
 *   four steps), section 4.2.2 and Algorithm 3 (protected faces).
 *   The boundary rule and its per-call parity follow CGAL 5.5 Sqrt3_1step / Sqrt3_mask_3 and
 *   OpenMesh Sqrt3T, which agree (../shared/TOOLS.md).
 *
 * Each iteration is four data-parallel passes over flat arrays, the same a GPU backend runs:
 *   1. classify faces (protected / centroid / border-trisected) and count what each emits;
 *   2. prefix sums give every face its output points and triangles (deterministic order);
 *   3. per old vertex: new position (eq. 4.1-4.2, or the border mask), relaxed UV;
 *   4. per face: new points, the three triangles after the edge flips, and their adjacency.
 * The output adjacency is derived from the input's (no hashing after the first build): the
 * triangle emitted for half-edge h = a->b of face f after the flip is (a, Q(opp h), Q(h)), where
 * Q(h) is the new point of f on h's side (the centroid, or on a trisected border face the
 * trisection point next to h's non-apex end).
 */
#include "pgt/sqrt3.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/adjacency.h"
#include "pgt/parallel.h"

enum { KIND_PROTECTED = 0, KIND_CENTROID = 1, KIND_BORDER = 2 };

/* The per-triangle helpers run millions of times a pass; GCC leaves them as calls otherwise. */
#if defined(__GNUC__)
#define S3_HOT inline __attribute__((always_inline))
#else
#define S3_HOT inline
#endif

/* One level of the subdivision: the mesh plus what the next step needs. */
typedef struct s3_level {
    uint32_t V, F;
    float *pos;
    uint32_t *idx;
    float *uv;
    int32_t *lab;
    uint32_t *opp;    /* 3F */
    uint8_t *prot;    /* F */
    uint32_t *parent; /* F, or NULL */
    uint32_t *vh;     /* V: one outgoing half-edge per vertex (PGT_NONE when isolated) */
} s3_level;

typedef struct s3_step {
    const s3_level *in;
    /* When set, `in` is implicit: only its V, F and pos are stored, and its triangles, adjacency,
     * vh, labels and parents are those a closed uniform step makes from `base` (see s3_in_idx).
     * The last step of a call uses this so the level before the output never holds its
     * connectivity (the output plus O(input) scratch). */
    const s3_level *base;
    s3_level *out;
    int even;     /* the iteration trisects border edges */
    int with_adj; /* fill out->opp and out->vh (another iteration follows, or asked for) */
    int uniform;  /* see s3_kind() */
    int closed;   /* uniform, no border half-edge, no UVs: s3_faces_closed() */
    uint8_t *kind;
    uint8_t *bslot; /* border corner of KIND_BORDER faces */
    uint32_t *pt_off;
    uint32_t *face_off;
    const float *alpha; /* S3_ALPHA_TABLE entries */
    float *uv_relaxed;  /* 2V */
    uint8_t *uv_mode;   /* V, with UVs only: 1 = all corners of the vertex take uv_relaxed */
} s3_step;

/* Per-face facts of a step. A "uniform" step (no protected face, and no border face to trisect)
 * has every face a centroid face emitting one point and three triangles, so its offsets are
 * f and 3f and the arrays are not read. */
static inline uint32_t s3_kind(const s3_step *s, uint32_t f) {
    return s->uniform ? KIND_CENTROID : s->kind[f];
}
static inline uint32_t s3_tri_base(const s3_step *s, uint32_t f) {
    return s->uniform ? 3 * f : s->face_off[f];
}
static inline uint32_t s3_point(const s3_step *s, uint32_t f) {
    return s->in->V + (s->uniform ? f : s->pt_off[f]);
}

float pgt_sqrt3_alpha(uint32_t n) {
    if (n == 0) return 0.0f;
    const double two_pi = 6.283185307179586476925286766559;
    return (float)((4.0 - 2.0 * cos(two_pi / (double)n)) / 9.0);
}

/* Valences below this read alpha_n from a table filled once per call. */
#define S3_ALPHA_TABLE 64u

static inline uint32_t s3_next(uint32_t h) { return pgt_half_edge_next(h); }
static inline uint32_t s3_prev(uint32_t h) { return pgt_half_edge_prev(h); }

/* ---- the input level's connectivity, stored or implicit ------------------------------------ */

/* A closed uniform step turns half-edge H = 3f + c of `base` (V_b vertices) into the triangle
 * H = (idx_b[H], V_b + opp_b[H] / 3, V_b + f) with adjacency (3 next(opp_b[H]) + 2,
 * 3 opp_b[H] + 1, 3 opp_b[prev(H)]) (s3_faces_closed). `imp` is a compile-time constant in every
 * caller, so the stored case stays a plain load. */
static S3_HOT uint32_t s3_in_idx(const s3_step *s, int imp, uint32_t h) {
    if (!imp) return s->in->idx[h];
    const s3_level *b = s->base;
    const uint32_t H = h / 3, e = h % 3;
    return e == 0 ? b->idx[H] : e == 1 ? b->V + b->opp[H] / 3 : b->V + H / 3;
}
static S3_HOT uint32_t s3_in_opp(const s3_step *s, int imp, uint32_t h) {
    if (!imp) return s->in->opp[h];
    const s3_level *b = s->base;
    const uint32_t H = h / 3, e = h % 3;
    return e == 0   ? 3 * s3_next(b->opp[H]) + 2
           : e == 1 ? 3 * b->opp[H] + 1
                    : 3 * b->opp[s3_prev(H)];
}
static S3_HOT uint32_t s3_in_vh(const s3_step *s, int imp, uint32_t v) {
    if (!imp) return s->in->vh[v];
    const s3_level *b = s->base;
    if (v >= b->V) return 3 * (3 * (v - b->V)) + 2;
    return b->vh[v] == PGT_NONE ? PGT_NONE : 3 * b->vh[v];
}
static S3_HOT uint32_t s3_in_parent(const s3_step *s, int imp, uint32_t f) {
    return imp ? s->base->parent[f / 3] : s->in->parent[f];
}
static S3_HOT int32_t s3_in_lab(const s3_step *s, int imp, uint32_t f) {
    return imp ? s->base->lab[f / 3] : s->in->lab[f];
}

static int s3_uv_equal(const float *uv, uint32_t c0, uint32_t c1) {
    return uv[2 * (size_t)c0] == uv[2 * (size_t)c1] &&
           uv[2 * (size_t)c0 + 1] == uv[2 * (size_t)c1 + 1];
}

/* ---- pass 1: classify faces ---------------------------------------------------------------- */

static void s3_classify(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    s3_step *s = p;
    const s3_level *in = s->in;
    (void)worker;
    for (uint32_t f = begin; f < end; ++f) {
        s->bslot[f] = 0;
        if (in->prot[f]) {
            s->kind[f] = KIND_PROTECTED;
            continue;
        }
        s->kind[f] = KIND_CENTROID;
        if (!s->even) continue;
        for (uint32_t c = 0; c < 3; ++c) {
            if (in->opp[3 * f + c] == PGT_NONE) {
                /* After an odd iteration a subdivided face has at most one border edge (every
                 * emitted triangle holds at most one old edge), as CGAL's Sqrt3_1step assumes. */
                assert(s->kind[f] == KIND_CENTROID);
                s->kind[f] = KIND_BORDER;
                s->bslot[f] = (uint8_t)c;
            }
        }
    }
}

/* ---- helpers on the input level ------------------------------------------------------------ */

/* Corner c of border face f starts h_1, the half-edge after its border half-edge (at b0). */
static inline int s3_is_h1(const s3_step *s, uint32_t f, uint32_t c) {
    return c == (s->bslot[f] + 1u) % 3u;
}

/* Output vertex of face(h)'s new point on h's side. h is not the border half-edge of its face. */
static uint32_t s3_Q(const s3_step *s, uint32_t h) {
    uint32_t f = h / 3, base = s3_point(s, f);
    if (s3_kind(s, f) == KIND_CENTROID) return base;
    assert(s->kind[f] == KIND_BORDER && h % 3 != s->bslot[f]);
    /* h_1 (after the border half-edge) starts at b0: E_b = base + 1; h_2 starts at the apex:
     * E_a = base. */
    return s3_is_h1(s, f, h % 3) ? base + 1 : base;
}

/* Output half-edge e of the triangle emitted in slot c of face f. */
static uint32_t s3_out_he(const s3_step *s, uint32_t f, uint32_t c, uint32_t e) {
    return 3 * (s3_tri_base(s, f) + c) + e;
}

/* Incoming border half-edge (x -> a) at the vertex a where the border half-edge hb (a -> b)
 * starts: walk a's fan forward from hb. */
static uint32_t s3_border_incoming(const uint32_t *opp, uint32_t hb) {
    uint32_t h = hb;
    for (;;) {
        uint32_t o = opp[s3_prev(h)];
        if (o == PGT_NONE) return s3_prev(h);
        h = o;
    }
}

/* Outgoing border half-edge (b -> y) at the vertex b where the border half-edge hb (a -> b)
 * ends: walk b's fan backward from next(hb). */
static uint32_t s3_border_outgoing_after(const uint32_t *opp, uint32_t hb) {
    uint32_t h = s3_next(hb);
    for (;;) {
        uint32_t o = opp[h];
        if (o == PGT_NONE) return h;
        h = s3_next(o);
    }
}

/* UV of corner c (a flat corner index 3f+i) of the input. */
static void s3_uv_get(const s3_level *in, uint32_t c, float out[2]) {
    out[0] = in->uv[2 * (size_t)c];
    out[1] = in->uv[2 * (size_t)c + 1];
}

/* UV of an old vertex as a corner of an output triangle: the relaxed UV when the vertex lies
 * inside one chart, else the corner's own UV (seam and protected vertices keep theirs). */
static void s3_uv_old(const s3_step *s, uint32_t corner, float out[2]) {
    uint32_t v = s->in->idx[corner];
    if (s->uv_mode[v]) {
        out[0] = s->uv_relaxed[2 * (size_t)v];
        out[1] = s->uv_relaxed[2 * (size_t)v + 1];
    } else {
        s3_uv_get(s->in, corner, out);
    }
}

/* UV of the trisection points of border face f, in f's chart: the same 1-16-10 weights as the
 * positions, with a neighbour's UV taken from the next border face when that face agrees with f
 * at the shared vertex (same chart), else extended linearly along the edge. */
static void s3_uv_trisect(const s3_step *s, uint32_t f, float ea[2], float eb[2]) {
    const s3_level *in = s->in;
    uint32_t hb = 3 * f + s->bslot[f];
    float ua[2], ub[2], uao[2], ubo[2];
    s3_uv_get(in, hb, ua);
    s3_uv_get(in, s3_next(hb), ub);
    uint32_t hin = s3_border_incoming(in->opp, hb);        /* x -> a0 */
    uint32_t hout = s3_border_outgoing_after(in->opp, hb); /* b0 -> y */
    if (s3_uv_equal(in->uv, s3_next(hin), hb))
        s3_uv_get(in, hin, uao);
    else
        for (int k = 0; k < 2; ++k) uao[k] = 2.0f * ua[k] - ub[k];
    if (s3_uv_equal(in->uv, hout, s3_next(hb)))
        s3_uv_get(in, s3_next(hout), ubo);
    else
        for (int k = 0; k < 2; ++k) ubo[k] = 2.0f * ub[k] - ua[k];
    for (int k = 0; k < 2; ++k) {
        ea[k] = (uao[k] + 16.0f * ua[k] + 10.0f * ub[k]) / 27.0f;
        eb[k] = (10.0f * ua[k] + 16.0f * ub[k] + ubo[k]) / 27.0f;
    }
}

/* UV of Q(h) in face(h)'s own chart. */
static void s3_uv_Q(const s3_step *s, uint32_t h, float out[2]) {
    uint32_t f = h / 3;
    if (s3_kind(s, f) == KIND_CENTROID) {
        const float *u = s->in->uv + 6 * (size_t)f;
        out[0] = (u[0] + u[2] + u[4]) / 3.0f;
        out[1] = (u[1] + u[3] + u[5]) / 3.0f;
        return;
    }
    float ea[2], eb[2];
    s3_uv_trisect(s, f, ea, eb);
    const float *e = s3_Q(s, h) == s3_point(s, f) ? ea : eb;
    out[0] = e[0];
    out[1] = e[1];
}

/* Signed area (x2) of face f's UV triangle: its chart's orientation there. */
static double s3_uv_area2(const float *uv, uint32_t f) {
    const float *u = uv + 6 * (size_t)f;
    return ((double)u[2] - u[0]) * ((double)u[5] - u[1]) -
           ((double)u[4] - u[0]) * ((double)u[3] - u[1]);
}

/* Maps z from the chart where edge (a, b) has UVs (ga, gb) into the chart where it has (fa, fb):
 * the rotation+scale+translation that carries one copy of the seam edge onto the other, preceded
 * by the reflection across the edge when the two charts have opposite orientations (a mirrored
 * chart), so that z lands on the far side of the seam either way. A degenerate source edge maps
 * to the destination edge's midpoint. */
static void s3_uv_map(const float ga[2], const float gb[2], const float fa[2], const float fb[2],
                      int mirror, float z[2]) {
    double dx = (double)gb[0] - ga[0], dy = (double)gb[1] - ga[1];
    double ex = (double)fb[0] - fa[0], ey = (double)fb[1] - fa[1];
    double d2 = dx * dx + dy * dy;
    if (d2 == 0.0) {
        z[0] = (fa[0] + fb[0]) * 0.5f;
        z[1] = (fa[1] + fb[1]) * 0.5f;
        return;
    }
    double px = (double)z[0] - ga[0], py = (double)z[1] - ga[1];
    if (mirror) { /* p -> 2 (p.d / d.d) d - p */
        double t = 2.0 * (px * dx + py * dy) / d2;
        px = t * dx - px;
        py = t * dy - py;
    }
    /* r = (e / d) as complex numbers */
    double rx = (ex * dx + ey * dy) / d2, ry = (ey * dx - ex * dy) / d2;
    z[0] = (float)(fa[0] + (px * rx - py * ry));
    z[1] = (float)(fa[1] + (px * ry + py * rx));
}

/* How far beyond a seam the carried point may land, in multiples of the distance of the face's
 * own new point from the seam. Charts whose copies of a seam edge differ much in length (a sliver
 * on one side) would otherwise throw the point far across the atlas (seen on spot.obj). */
#define S3_SEAM_MAX_STRETCH 3.0

/* Twice the signed area of UV triangle (p, q, r). */
static double s3_uv_turn(const float p[2], const float q[2], const float r[2]) {
    return ((double)q[0] - p[0]) * ((double)r[1] - p[1]) -
           ((double)q[1] - p[1]) * ((double)r[0] - p[0]);
}

/* The triangles emitted with z keep the face's orientation: (a, z, q), and (b, q, z) too when
 * both_sides. */
static int s3_uv_unfolded(const float fa[2], const float fb[2], const float q[2], double orient,
                          int both_sides, const float z[2]) {
    return s3_uv_turn(fa, z, q) * orient > 0.0 &&
           (!both_sides || s3_uv_turn(fb, q, z) * orient > 0.0);
}

/* z is the neighbour's new point carried into this chart across seam (fa, fb); q is this face's
 * new point; the triangles emitted with z are (a, z, q) with a at fa and, when both lie in this
 * chart (both_sides: s3_uv_tent), (b, q, z) with b at fb; orient is the sign of this face's UV
 * area. z must lie beyond the seam, on the other side from q, no farther than
 * S3_SEAM_MAX_STRETCH times q's distance, and those triangles must keep the face's orientation;
 * else z becomes q's mirror image across the seam. Returns nonzero when the triangles with the
 * final z keep the orientation (the mirror image may not: q's foot off the seam edge). */
static int s3_uv_seam_guard(const float fa[2], const float fb[2], const float q[2], double orient,
                            int both_sides, float z[2]) {
    double ex = (double)fb[0] - fa[0], ey = (double)fb[1] - fa[1], e2 = ex * ex + ey * ey;
    if (e2 == 0.0) return s3_uv_unfolded(fa, fb, q, orient, both_sides, z);
    /* signed distances (times |e|) from the seam line */
    double sq = ex * ((double)q[1] - fa[1]) - ey * ((double)q[0] - fa[0]);
    double sz = ex * ((double)z[1] - fa[1]) - ey * ((double)z[0] - fa[0]);
    if (sq * sz < 0.0 && fabs(sz) <= S3_SEAM_MAX_STRETCH * fabs(sq) &&
        s3_uv_unfolded(fa, fb, q, orient, both_sides, z))
        return 1;
    double px = (double)q[0] - fa[0], py = (double)q[1] - fa[1];
    double t = 2.0 * (px * ex + py * ey) / e2;
    z[0] = (float)(fa[0] + (t * ex - px));
    z[1] = (float)(fa[1] + (t * ey - py));
    return s3_uv_unfolded(fa, fb, q, orient, both_sides, z);
}

/* ---- pass 3: old vertices ------------------------------------------------------------------ */

/* eq. 4.1: (1 - alpha_n) V + alpha_n / n sum V_i, for a vertex of valence n whose neighbours sum
 * to sum. Returns alpha_n. */
static S3_HOT float s3_relax(const s3_step *s, uint32_t n, const float *pv, const float *sum,
                             float *po) {
    const float a = n < S3_ALPHA_TABLE ? s->alpha[n] : pgt_sqrt3_alpha(n), w = a / (float)n;
    for (int k = 0; k < 3; ++k) po[k] = (1.0f - a) * pv[k] + w * sum[k];
    return a;
}

/* Pass 3 of a closed uniform step without UVs: every vertex is interior and unprotected. The
 * fan walk is a chain of dependent loads (opposite of previous), so S3_LANES fans are walked in
 * lockstep to keep that many loads in flight. Same neighbours, same order, same bytes as the
 * general pass (tested: closed_fast_path_equals_general). */
#define S3_LANES 8u
static void s3_vertices_closed(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    s3_step *s = p;
    const s3_level *in = s->in;
    s3_level *out = s->out;
    (void)worker;
    for (uint32_t v0 = begin; v0 < end; v0 += S3_LANES) {
        const uint32_t lanes = end - v0 < S3_LANES ? end - v0 : S3_LANES;
        uint32_t h[S3_LANES], n[S3_LANES], active = 0;
        float sum[S3_LANES][3];
        for (uint32_t l = 0; l < lanes; ++l) {
            h[l] = in->vh[v0 + l];
            n[l] = 0;
            sum[l][0] = sum[l][1] = sum[l][2] = 0.0f;
            active += h[l] != PGT_NONE;
        }
        while (active) {
            for (uint32_t l = 0; l < lanes; ++l) {
                if (h[l] == PGT_NONE) continue;
                const float *pw = in->pos + 3 * (size_t)in->idx[s3_next(h[l])];
                sum[l][0] += pw[0], sum[l][1] += pw[1], sum[l][2] += pw[2];
                n[l]++;
                const uint32_t hn = in->opp[s3_prev(h[l])];
                if (hn == in->vh[v0 + l]) {
                    h[l] = PGT_NONE;
                    active--;
                } else {
                    h[l] = hn;
                }
            }
        }
        for (uint32_t l = 0; l < lanes; ++l) {
            const uint32_t v = v0 + l, h0 = in->vh[v];
            const float *pv = in->pos + 3 * (size_t)v;
            float *po = out->pos + 3 * (size_t)v;
            if (h0 == PGT_NONE) {
                po[0] = pv[0], po[1] = pv[1], po[2] = pv[2];
                if (s->with_adj) out->vh[v] = PGT_NONE;
                continue;
            }
            s3_relax(s, n[l], pv, sum[l], po);
            if (s->with_adj) out->vh[v] = 3 * (3 * (h0 / 3) + h0 % 3); /* T(h0).e0 */
        }
    }
}

/* Pass 3 on an implicit input (s3_step.base): the fans are known without walking the implicit
 * level. An old vertex v of base keeps its fan, its neighbours now being the face points of the
 * faces across its fan's half-edges; the face point of base face f has valence 6: its corners and
 * the face points across its edges, alternating. Visited in the order s3_vertices_closed_body
 * walks them, so the same bytes (tested: closed_fast_path_equals_general). */
static void s3_vertices_implicit(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    s3_step *s = p;
    const s3_level *in = s->in, *b = s->base;
    s3_level *out = s->out;
    const uint32_t Vb = b->V;
    (void)worker;
    for (uint32_t v = begin; v < end; ++v) {
        const float *pv = in->pos + 3 * (size_t)v;
        float *po = out->pos + 3 * (size_t)v, sum[3] = {0.0f, 0.0f, 0.0f};
        uint32_t n = 0;
        if (v < Vb) {
            const uint32_t h0 = b->vh[v];
            if (h0 == PGT_NONE) {
                po[0] = pv[0], po[1] = pv[1], po[2] = pv[2];
                if (s->with_adj) out->vh[v] = PGT_NONE;
                continue;
            }
            uint32_t h = h0;
            do {
                const float *pw = in->pos + 3 * ((size_t)Vb + b->opp[h] / 3);
                sum[0] += pw[0], sum[1] += pw[1], sum[2] += pw[2];
                n++;
                h = b->opp[s3_prev(h)];
            } while (h != h0);
        } else {
            const uint32_t *tri = b->idx + 3 * (size_t)(v - Vb),
                           *opp = b->opp + 3 * (size_t)(v - Vb);
            for (uint32_t c = 0; c < 3; ++c) {
                const float *pc = in->pos + 3 * (size_t)tri[c];
                const float *pg = in->pos + 3 * ((size_t)Vb + opp[c] / 3);
                sum[0] += pc[0], sum[1] += pc[1], sum[2] += pc[2];
                sum[0] += pg[0], sum[1] += pg[1], sum[2] += pg[2];
            }
            n = 6;
        }
        s3_relax(s, n, pv, sum, po);
        if (s->with_adj) out->vh[v] = 3 * s3_in_vh(s, 1, v); /* T(h0).e0 */
    }
}

static void s3_vertices(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    s3_step *s = p;
    const s3_level *in = s->in;
    s3_level *out = s->out;
    (void)worker;
    for (uint32_t v = begin; v < end; ++v) {
        const float *pv = in->pos + 3 * (size_t)v;
        float *po = out->pos + 3 * (size_t)v;
        uint32_t h0 = in->vh[v];
        po[0] = pv[0], po[1] = pv[1], po[2] = pv[2];
        if (in->uv) s->uv_mode[v] = 0;
        if (h0 == PGT_NONE) {
            if (s->with_adj) out->vh[v] = PGT_NONE;
            continue;
        }
        /* Sum the neighbours walking forward round the fan from h0; an interior vertex comes back
         * to h0. A border vertex meets the border: its sum must start at its fan start (its
         * outgoing border half-edge), so walk back to it and sum again from there unless h0 was
         * it. Either way the sum has one fixed order. */
        float sum[3], usum[2], uv0[2] = {0.0f, 0.0f};
        uint32_t n, last, first = h0;
        int touch_prot, one_chart, border = 0;
        for (;;) {
            sum[0] = sum[1] = sum[2] = usum[0] = usum[1] = 0.0f;
            n = 0, touch_prot = 0, one_chart = in->uv != NULL;
            if (one_chart) s3_uv_get(in, first, uv0);
            uint32_t h = first, hn;
            for (;;) {
                const float *pw = in->pos + 3 * (size_t)in->idx[s3_next(h)];
                sum[0] += pw[0], sum[1] += pw[1], sum[2] += pw[2];
                n++;
                touch_prot |= in->prot[h / 3];
                if (in->uv) {
                    uint32_t o = in->opp[h];
                    /* One chart: every corner of v has the same UV and every fan edge's far end
                     * has the same UV on both of its faces. */
                    if (!s3_uv_equal(in->uv, h, first) ||
                        (o != PGT_NONE && !s3_uv_equal(in->uv, s3_next(h), o)))
                        one_chart = 0;
                    usum[0] += in->uv[2 * (size_t)s3_next(h)];
                    usum[1] += in->uv[2 * (size_t)s3_next(h) + 1];
                }
                last = h;
                hn = in->opp[s3_prev(h)];
                if (hn == PGT_NONE || hn == first) break;
                h = hn;
            }
            if (hn != PGT_NONE || border) break;
            border = 1;
            uint32_t start = h0;
            while (in->opp[start] != PGT_NONE) start = s3_next(in->opp[start]);
            if (start == first) break;
            first = start;
        }
        const uint32_t hin = s3_prev(last); /* on a border: the incoming border half-edge */
        if (border) {
            const float *pw = in->pos + 3 * (size_t)in->idx[hin];
            sum[0] += pw[0], sum[1] += pw[1], sum[2] += pw[2];
            n++;
            if (in->uv) {
                usum[0] += in->uv[2 * (size_t)hin];
                usum[1] += in->uv[2 * (size_t)hin + 1];
            }
        }
        if (!touch_prot) {
            if (!border) {
                const float a = s3_relax(s, n, pv, sum, po), w = a / (float)n;
                if (one_chart) {
                    for (int k = 0; k < 2; ++k)
                        s->uv_relaxed[2 * (size_t)v + k] = (1.0f - a) * uv0[k] + w * usum[k];
                    s->uv_mode[v] = 1;
                }
            } else if (s->even) {
                /* Kobbelt's border vertex mask (4 P_prev + 19 P + 4 P_next) / 27 */
                const float *pp = in->pos + 3 * (size_t)in->idx[hin];
                const float *pn = in->pos + 3 * (size_t)in->idx[s3_next(first)];
                for (int k = 0; k < 3; ++k)
                    po[k] = (4.0f * pp[k] + 19.0f * pv[k] + 4.0f * pn[k]) / 27.0f;
                if (one_chart) {
                    const float *up = in->uv + 2 * (size_t)hin,
                                *un = in->uv + 2 * (size_t)s3_next(first);
                    for (int k = 0; k < 2; ++k)
                        s->uv_relaxed[2 * (size_t)v + k] =
                            (4.0f * up[k] + 19.0f * uv0[k] + 4.0f * un[k]) / 27.0f;
                    s->uv_mode[v] = 1;
                }
            }
        }
        if (s->with_adj) {
            /* An output half-edge leaving v: from the triangle of a half-edge leaving v that is
             * not a trisected border half-edge (the fan's last one on a border). */
            uint32_t hc = border ? last : h0, f = hc / 3;
            out->vh[v] = s3_kind(s, f) == KIND_PROTECTED ? s3_out_he(s, f, 0, hc % 3)
                                                         : s3_out_he(s, f, hc % 3, 0);
        }
    }
}

/* ---- pass 4: new points and triangles ------------------------------------------------------ */

static void s3_emit(const s3_step *s, uint32_t t, uint32_t a, uint32_t b, uint32_t c) {
    uint32_t *o = s->out->idx + 3 * (size_t)t;
    o[0] = a, o[1] = b, o[2] = c;
}

static void s3_emit_uv(const s3_step *s, uint32_t t, const float a[2], const float b[2],
                       const float c[2]) {
    float *o = s->out->uv + 6 * (size_t)t;
    o[0] = a[0], o[1] = a[1], o[2] = b[0], o[3] = b[1], o[4] = c[0], o[5] = c[1];
}

/* What the triangles of a subdivided face need to know about the neighbour across half-edge h:
 * gathered once per half-edge, so each face reads its neighbours' arrays once. */
typedef struct s3_nb {
    uint32_t o;       /* opposite half-edge, or PGT_NONE */
    int flip;         /* the edge is flipped (the neighbour exists and is subdivided) */
    uint32_t q_opp;   /* Q(o) when flipped */
    uint32_t e0;      /* output partner of edge a -> Q(o) (flipped) or a -> b (not flipped) */
    uint32_t e1_flip; /* output partner of edge Q(o) -> Q(h) when flipped: T(o).e1 */
    uint32_t e2_next; /* output partner of the next half-edge's triangle's edge Q -> b */
} s3_nb;

static S3_HOT s3_nb s3_neighbour(const s3_step *s, uint32_t h) {
    s3_nb nb;
    const uint32_t f = h / 3, c = h % 3, o = s->in->opp[h];
    nb.o = o;
    nb.flip = 0;
    nb.q_opp = PGT_NONE;
    nb.e1_flip = PGT_NONE;
    nb.e0 = PGT_NONE;
    nb.e2_next = s3_out_he(s, f, c, 1); /* not flipped: this triangle's Q(h) side b -> Q(h) */
    if (o == PGT_NONE) return nb;
    const uint32_t g = o / 3, gc = o % 3;
    const uint32_t kg = s3_kind(s, g);
    if (kg == KIND_PROTECTED) {
        nb.e0 = s3_out_he(s, g, 0, gc); /* the protected neighbour's own half-edge */
        return nb;
    }
    const uint32_t gbase = 3 * s3_tri_base(s, g);
    nb.flip = 1;
    nb.e1_flip = gbase + 3 * gc + 1;
    nb.e2_next = gbase + 3 * gc; /* T(o).e0 runs b -> Q(h) */
    if (kg == KIND_CENTROID) {
        nb.q_opp = s3_point(s, g);
        nb.e0 = gbase + 3 * (gc == 2 ? 0 : gc + 1) + 2;
        return nb;
    }
    nb.q_opp = s3_Q(s, o);
    if (s3_is_h1(s, g, gc)) /* o is h_1 of a border face: its middle triangle */
        nb.e0 = s3_out_he(s, g, s->bslot[g], 1);
    /* else o is h_2 of a border face: a -> Q(o) is the first third of the trisected border */
    return nb;
}

/* Half-edge h lies on a chart seam: its neighbour disagrees on one of the edge's two UVs. */
static int s3_uv_is_seam(const s3_level *in, uint32_t h) {
    const uint32_t o = in->opp[h];
    return o != PGT_NONE &&
           (!s3_uv_equal(in->uv, h, s3_next(o)) || !s3_uv_equal(in->uv, s3_next(h), o));
}

/* Edges of face f that are chart seams. */
static uint32_t s3_uv_seams(const s3_level *in, uint32_t f) {
    return (uint32_t)(s3_uv_is_seam(in, 3 * f) + s3_uv_is_seam(in, 3 * f + 1) +
                      s3_uv_is_seam(in, 3 * f + 2));
}

/* The UV of Q(opp(h)) carried into face(h)'s chart across the seam at h (s3_uv_map, then
 * s3_uv_seam_guard with face(h)'s point): computed from h's side only, so that both triangles
 * that use it get the same bits. Returns s3_uv_seam_guard's answer. */
static int s3_uv_carry(const s3_step *s, uint32_t h, int both_sides, float out[2]) {
    const s3_level *in = s->in;
    const uint32_t o = in->opp[h];
    float ga[2], gb[2], fa[2], fb[2], uq[2];
    s3_uv_Q(s, o, out);
    s3_uv_Q(s, h, uq);
    s3_uv_get(in, s3_next(o), ga);
    s3_uv_get(in, o, gb);
    s3_uv_get(in, h, fa);
    s3_uv_get(in, s3_next(h), fb);
    const double af = s3_uv_area2(in->uv, h / 3);
    const int mirror = (af > 0.0) != (s3_uv_area2(in->uv, o / 3) > 0.0);
    s3_uv_map(ga, gb, fa, fb, mirror, out);
    return s3_uv_seam_guard(fa, fb, uq, af, both_sides, out);
}

/* The first choice of s3_uv_tent for seam half-edge h (opposite o): the face with more seam
 * edges keeps both triangles, then the one of lower index; where the carried point would fold one
 * of them over even as its mirror image, the other face, if its chart takes both unfolded. */
static int s3_uv_tent_first(const s3_step *s, uint32_t h, uint32_t o, uint32_t *keeps,
                            float carried[2]) {
    if (s3_kind(s, h / 3) != KIND_CENTROID || s3_kind(s, o / 3) != KIND_CENTROID) return 0;
    const uint32_t nh = s3_uv_seams(s->in, h / 3), no = s3_uv_seams(s->in, o / 3);
    *keeps = nh > no ? h : nh < no ? o : h / 3 < o / 3 ? h : o;
    if (s3_uv_carry(s, *keeps, 1, carried)) return 1;
    *keeps = *keeps == h ? o : h;
    return s3_uv_carry(s, *keeps, 1, carried);
}

/* A flipped seam edge between two faces that are both split at their centroids gives two
 * triangles that straddle the seam, (a, Q(o), Q(h)) and (b, Q(h), Q(o)); both go into the chart of
 * one face (s3_uv_tent_first), so that the seam becomes the tent a - Q - b through the other
 * face's point, each triangle next to it having one seam edge. (One triangle per face, in its
 * face's chart, makes a zigzag whose teeth have two seam edges each: at the next iteration every
 * tooth left a one-triangle chart, and the cube-sphere's 6 charts became 222 at k = 2, spot's 13
 * became 3005 at k = 3.)
 *
 * A face that would give its point to two neighbours of one chart across two of its edges (the
 * neighbours agree on the UV of the vertex the edges share) would have it carried there twice,
 * through two seam maps: two UVs for one vertex in one chart, and UV triangles that overlap
 * (pizza's charts of a few triangles). Of two such edges, the one whose keeper has the higher
 * face index goes to the face instead if its chart takes both triangles unfolded (not a face of
 * zero UV area), else the other one if its chart takes those, so that the point is carried
 * once. When no chart takes the two triangles unfolded, the edge keeps one triangle per face.
 * The answer is the same from either side. Returns nonzero when h's edge is a tent; *keeps is
 * then the half-edge (h or o) whose face keeps both triangles, and *carried the other face's
 * point in its chart. */
static int s3_uv_tent(const s3_step *s, uint32_t h, uint32_t o, uint32_t *keeps, float carried[2]) {
    if (!s3_uv_tent_first(s, h, o, keeps, carried)) return 0;
    const s3_level *in = s->in;
    const uint32_t k = *keeps, lose = k == h ? o : h;
    float back[2];
    int give_back = 0, can = -1; /* can: the loser's chart takes this edge's triangles unfolded */
    for (int side = 0; side < 2 && !give_back; ++side) {
        /* the loser's edge after lose (sharing its end, where k's corner is k) or before it
         * (sharing its start, where k's corner is next(k)) */
        const uint32_t x = side == 0 ? s3_next(lose) : s3_next(s3_next(lose)), ox = in->opp[x];
        uint32_t k2 = 0;
        float unused[2];
        if (ox == PGT_NONE || !s3_uv_is_seam(in, x) || !s3_uv_tent_first(s, x, ox, &k2, unused) ||
            k2 != ox)
            continue; /* the loser does not lose x too */
        const int one_chart =
            side == 0 ? s3_uv_equal(in->uv, k, s3_next(ox)) : s3_uv_equal(in->uv, s3_next(k), ox);
        if (!one_chart) continue;
        if (can < 0) can = s3_uv_carry(s, lose, 1, back);
        /* the edge of the higher keeper goes back; the other one when that one cannot */
        const int first = k / 3 > ox / 3 || (k / 3 == ox / 3 && k > ox);
        give_back = can && (first || !s3_uv_carry(s, x, 1, unused));
    }
    if (!give_back) return 1;
    *keeps = lose;
    memcpy(carried, back, sizeof back);
    return 1;
}

/* The triangle of half-edge h (a -> b) of subdivided face f, in slot h % 3; nb describes h's
 * neighbour, pnb that of prev(h). */
static S3_HOT void s3_face_triangle(const s3_step *s, uint32_t h, uint32_t q, const s3_nb *nb,
                                    const s3_nb *pnb) {
    const s3_level *in = s->in;
    s3_level *out = s->out;
    const uint32_t f = h / 3, c = h % 3, t = s3_tri_base(s, f) + c;
    const uint32_t a = in->idx[h], o = nb->o;
    const int border_face = s3_kind(s, f) == KIND_BORDER;
    s3_emit(s, t, a, nb->flip ? nb->q_opp : in->idx[s3_next(h)], q);

    if (out->uv) {
        float ua[2], ub[2], uq[2];
        uint32_t keeps = h;
        float carried[2];
        const int seam = nb->flip && s3_uv_is_seam(in, h);
        const int tent = seam && s3_uv_tent(s, h, o, &keeps, carried);
        if (tent && keeps == o) { /* (a, Q(o), Q(h)) in g's chart: a as g's corner */
            s3_uv_old(s, s3_next(o), ua);
            s3_uv_Q(s, o, ub);
            memcpy(uq, carried, sizeof uq);
        } else {
            s3_uv_old(s, h, ua);
            s3_uv_Q(s, h, uq);
            if (tent)
                memcpy(ub, carried, sizeof ub);
            else if (seam)
                s3_uv_carry(s, h, 0, ub);
            else if (nb->flip)
                s3_uv_Q(s, o, ub);
            else
                s3_uv_old(s, s3_next(h), ub);
        }
        s3_emit_uv(s, t, ua, ub, uq);
    }
    if (!s->with_adj) return;

    uint32_t *oo = out->opp + 3 * (size_t)t;
    oo[0] = nb->e0;
    /* e1: Q(o) -> Q(h) when flipped, else b -> Q(h) */
    if (nb->flip)
        oo[1] = nb->e1_flip;
    else if (!border_face)
        oo[1] = s3_out_he(s, f, (c + 1) % 3, 2);
    else if (s3_is_h1(s, f, c)) /* h_1: A -> E_b is the middle triangle's e1 */
        oo[1] = s3_out_he(s, f, s->bslot[f], 1);
    else /* h_2: a0 -> E_a lies on the border */
        oo[1] = PGT_NONE;
    /* e2: Q(h) -> a */
    if (!border_face)
        oo[2] = pnb->e2_next;
    else if (s3_is_h1(s, f, c)) /* h_1: E_b -> b0 lies on the border */
        oo[2] = PGT_NONE;
    else /* h_2: E_a -> A is the middle triangle's e2 */
        oo[2] = s3_out_he(s, f, s->bslot[f], 2);
}

/* step (1): the face point at the centroid */
static S3_HOT void s3_centroid(const s3_level *in, const uint32_t *tri, float *q) {
    const float *p0 = in->pos + 3 * (size_t)tri[0], *p1 = in->pos + 3 * (size_t)tri[1],
                *p2 = in->pos + 3 * (size_t)tri[2];
    for (int k = 0; k < 3; ++k) q[k] = (p0[k] + p1[k] + p2[k]) / 3.0f;
}

/* Pass 4 of a closed uniform step without UVs (no border, no protected face: the common case
 * and the benchmark's): every neighbour is a centroid face and face f's point and triangles sit
 * at V + f and 3f, so the general pass below reduces to index arithmetic. Same output (tested:
 * closed_fast_path_equals_general). */
static S3_HOT void s3_faces_closed_body(s3_step *s, uint32_t begin, uint32_t end, int imp) {
    const s3_level *in = s->in;
    s3_level *out = s->out;
    const uint32_t V = in->V;
    for (uint32_t f = begin; f < end; ++f) {
        uint32_t tri[3], opp[3];
        for (uint32_t c = 0; c < 3; ++c)
            tri[c] = s3_in_idx(s, imp, 3 * f + c), opp[c] = s3_in_opp(s, imp, 3 * f + c);
        const uint32_t np = V + f, t0 = 3 * f;
        s3_centroid(in, tri, out->pos + 3 * (size_t)np);
        uint32_t g[3], gc[3];
        for (int c = 0; c < 3; ++c) g[c] = opp[c] / 3, gc[c] = opp[c] % 3;
        uint32_t *o = out->idx + 3 * (size_t)t0;
        for (int c = 0; c < 3; ++c) /* T(h) = (a, Q(opp h), Q(h)) */
            o[3 * c] = tri[c], o[3 * c + 1] = V + g[c], o[3 * c + 2] = np;
        for (int c = 0; c < 3; ++c) {
            if (out->prot) out->prot[t0 + c] = 0;
            if (out->parent) out->parent[t0 + c] = s3_in_parent(s, imp, f);
            if (out->lab) out->lab[t0 + c] = s3_in_lab(s, imp, f);
        }
        if (!s->with_adj) continue;
        out->vh[np] = 3 * t0 + 2;
        uint32_t *oo = out->opp + 9 * (size_t)f;
        for (int c = 0; c < 3; ++c) {
            const int pc = (c + 2) % 3;
            oo[3 * c] = 3 * (3 * g[c] + (gc[c] == 2 ? 0 : gc[c] + 1)) + 2; /* T(next(o)).e2 */
            oo[3 * c + 1] = 3 * (3 * g[c] + gc[c]) + 1;                    /* T(o).e1 */
            oo[3 * c + 2] = 3 * (3 * g[pc] + gc[pc]);                      /* T(opp(prev h)).e0 */
        }
    }
}

static void s3_faces_closed(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    (void)worker;
    s3_faces_closed_body(p, begin, end, 0);
}
static void s3_faces_implicit(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    (void)worker;
    s3_faces_closed_body(p, begin, end, 1);
}

/* Pass 4 of a closed step whose output stays implicit (the next, last step reads its
 * connectivity from this step's input): the face points only. */
static void s3_face_points(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    s3_step *s = p;
    (void)worker;
    for (uint32_t f = begin; f < end; ++f)
        s3_centroid(s->in, s->in->idx + 3 * (size_t)f, s->out->pos + 3 * ((size_t)s->in->V + f));
}

static void s3_faces(void *p, uint32_t begin, uint32_t end, uint32_t worker) {
    s3_step *s = p;
    const s3_level *in = s->in;
    s3_level *out = s->out;
    (void)worker;
    for (uint32_t f = begin; f < end; ++f) {
        const uint32_t *tri = in->idx + 3 * (size_t)f;
        const uint32_t kf = s3_kind(s, f), base_t = s3_tri_base(s, f), np = s3_point(s, f);
        const uint32_t nt = kf == KIND_PROTECTED ? 1 : 3;
        for (uint32_t i = 0; i < nt; ++i) {
            if (out->prot) out->prot[base_t + i] = kf == KIND_PROTECTED;
            if (out->parent) out->parent[base_t + i] = in->parent[f];
            if (out->lab) out->lab[base_t + i] = in->lab[f];
        }
        if (kf == KIND_PROTECTED) {
            s3_emit(s, base_t, tri[0], tri[1], tri[2]);
            if (out->uv)
                memcpy(out->uv + 6 * (size_t)base_t, in->uv + 6 * (size_t)f, 6 * sizeof(float));
            if (s->with_adj)
                for (uint32_t e = 0; e < 3; ++e) {
                    uint32_t o = in->opp[3 * f + e];
                    uint32_t *dst = out->opp + 3 * (size_t)base_t + e;
                    if (o == PGT_NONE)
                        *dst = PGT_NONE;
                    else if (s3_kind(s, o / 3) == KIND_PROTECTED)
                        *dst = s3_out_he(s, o / 3, 0, o % 3);
                    else
                        *dst = s3_out_he(s, o / 3, o % 3, 0);
                }
            continue;
        }
        const s3_nb nb[3] = {s3_neighbour(s, 3 * f), s3_neighbour(s, 3 * f + 1),
                             s3_neighbour(s, 3 * f + 2)};
        if (kf == KIND_CENTROID) {
            /* step (1): the face point at the centroid */
            s3_centroid(in, tri, out->pos + 3 * (size_t)np);
            if (s->with_adj) out->vh[np] = s3_out_he(s, f, 0, 2);
            for (uint32_t c = 0; c < 3; ++c)
                s3_face_triangle(s, 3 * f + c, np, &nb[c], &nb[(c + 2) % 3]);
            continue;
        }
        /* Border face on an even iteration: trisect the border edge a0 -> b0 with Kobbelt's
         * (1, 16, 10) / 27 masks, apex A, triangles (a0 E_a A) (E_a E_b A) (E_b b0 A) before the
         * flips of the two inner edges. */
        const uint32_t sb = s->bslot[f], hb = 3 * f + sb;
        const uint32_t a0 = in->idx[hb], b0 = in->idx[s3_next(hb)], apex = in->idx[s3_prev(hb)];
        const uint32_t a0o = in->idx[s3_border_incoming(in->opp, hb)];
        const uint32_t b0o = in->idx[s3_next(s3_border_outgoing_after(in->opp, hb))];
        const float *pa = in->pos + 3 * (size_t)a0, *pb = in->pos + 3 * (size_t)b0;
        const float *pao = in->pos + 3 * (size_t)a0o, *pbo = in->pos + 3 * (size_t)b0o;
        float *ea = out->pos + 3 * (size_t)np, *eb = out->pos + 3 * ((size_t)np + 1);
        for (int k = 0; k < 3; ++k) {
            ea[k] = (pao[k] + 16.0f * pa[k] + 10.0f * pb[k]) / 27.0f;
            eb[k] = (10.0f * pa[k] + 16.0f * pb[k] + pbo[k]) / 27.0f;
        }
        const uint32_t tm = base_t + sb;
        s3_emit(s, tm, np, np + 1, apex);
        if (out->uv) {
            float uea[2], ueb[2], uap[2];
            s3_uv_trisect(s, f, uea, ueb);
            s3_uv_old(s, s3_prev(hb), uap);
            s3_emit_uv(s, tm, uea, ueb, uap);
        }
        if (s->with_adj) {
            const uint32_t h2 = 3 * f + (sb + 2) % 3;
            uint32_t *oo = out->opp + 3 * (size_t)tm;
            oo[0] = PGT_NONE;
            oo[1] = nb[(sb + 1) % 3].e2_next; /* A -> E_b: T(opp h_1).e0 or T(h_1).e1 */
            oo[2] = s3_out_he(s, f, h2 % 3, 2);
            out->vh[np] = s3_out_he(s, f, sb, 0);
            out->vh[np + 1] = s3_out_he(s, f, sb, 1);
        }
        for (uint32_t c = 0; c < 3; ++c)
            if (c != sb)
                s3_face_triangle(s, 3 * f + c, s3_Q(s, 3 * f + c), &nb[c], &nb[(c + 2) % 3]);
    }
}

/* ---- driver -------------------------------------------------------------------------------- */

static void s3_level_free(s3_level *l) {
    free(l->pos), free(l->idx), free(l->uv), free(l->lab);
    free(l->opp), free(l->prot), free(l->parent), free(l->vh);
    memset(l, 0, sizeof(*l));
}

/* Frees a level; the input level (not owned) shares the caller's arrays and the adjacency. */
static void s3_level_release(s3_level *l, int owned, pgt_adjacency *adj) {
    if (owned) {
        s3_level_free(l);
        return;
    }
    free(l->prot), free(l->vh), free(l->parent);
    pgt_adjacency_destroy(adj);
    memset(l, 0, sizeof(*l));
}

pgt_result pgt_sqrt3_bound(uint32_t vertex_count, uint32_t face_count, uint32_t border_edges,
                           uint32_t iterations, uint32_t *out_vertex_bound,
                           uint32_t *out_face_bound, pgt_error *err) {
    (void)border_edges; /* a face emits at most two points, whatever the border */
    uint64_t v = vertex_count, f = face_count;
    for (uint32_t i = 0; i < iterations; ++i) {
        v += 2 * f;
        f *= 3;
        if (v > PGT_MESH_MAX_ELEMENTS || f > PGT_MESH_MAX_ELEMENTS)
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "sqrt3: %u iterations of %u faces exceed %u elements", iterations,
                                 face_count, PGT_MESH_MAX_ELEMENTS);
    }
    if (out_vertex_bound) *out_vertex_bound = (uint32_t)v;
    if (out_face_bound) *out_face_bound = (uint32_t)f;
    return PGT_OK;
}

pgt_result pgt_sqrt3_check_input(const pgt_mesh *in, uint32_t iterations, pgt_error *err) {
    if (!in || (in->face_count && (!in->indices || !in->positions)) ||
        (in->vertex_count && !in->positions))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "sqrt3: no input mesh");
    /* the coordinates first: a PGT_ERROR_LIMIT with pgt_sqrt3_far_coordinate nonzero is then
     * always about that element (pgt subdiv names its line) */
    uint32_t k = 0;
    float c = 0.0f;
    const int far = pgt_sqrt3_far_coordinate(in, &k, &c);
    if (far == 1)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "sqrt3 input: vertex %u (0-based): coordinate %g is beyond +-%g (sums "
                             "of neighbours in float would overflow)",
                             k, (double)c, (double)PGT_SQRT3_MAX_COORD);
    if (far == 2)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "sqrt3 input: face %u (0-based), corner %u: UV %g is beyond +-%g",
                             k / 3u, k % 3u, (double)c, (double)PGT_SQRT3_MAX_COORD);
    if (iterations > PGT_SQRT3_MAX_ITERATIONS)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "sqrt3: %u iterations (at most %u)", iterations,
                             PGT_SQRT3_MAX_ITERATIONS);
    return pgt_sqrt3_bound(in->vertex_count, in->face_count, 0, iterations, NULL, NULL, err);
}

int pgt_sqrt3_far_coordinate(const pgt_mesh *in, uint32_t *index, float *value) {
    float v = 0.0f;
    int far = 0;
    if ((*index = pgt_mesh_far_vertex(in, PGT_SQRT3_MAX_COORD, &v)) != PGT_NONE) far = 1;
    for (size_t i = 0; !far && in->uvs && i < 6u * (size_t)in->face_count; ++i)
        if (!(fabsf(in->uvs[i]) <= PGT_SQRT3_MAX_COORD))
            *index = (uint32_t)(i / 2u), v = in->uvs[i], far = 2;
    if (value) *value = v;
    return far;
}

pgt_result pgt_sqrt3_subdivide(pgt_mesh *out, const pgt_mesh *in_mesh,
                               const pgt_sqrt3_options *opts, pgt_error *err) {
    pgt_sqrt3_options defaults = {1, 1, NULL, NULL, NULL, NULL, NULL};
    if (!opts) opts = &defaults;
    memset(out, 0, sizeof(*out));
    pgt_result r = pgt_sqrt3_check_input(in_mesh, opts->iterations, err);
    if (r != PGT_OK) return r;
    const uint32_t k = opts->iterations, threads = opts->threads ? opts->threads : 1;

    pgt_adjacency adj;
    r = pgt_adjacency_build(&adj, in_mesh, threads, err);
    if (r != PGT_OK) return r;
    r = pgt_adjacency_require_manifold(&adj, "sqrt3 input", err);
    if (r != PGT_OK) {
        pgt_adjacency_destroy(&adj);
        return r;
    }

    const uint32_t V0 = in_mesh->vertex_count, F0 = in_mesh->face_count;
    s3_level cur = {0};
    cur.V = V0, cur.F = F0;
    cur.pos = in_mesh->positions, cur.idx = in_mesh->indices;
    cur.uv = in_mesh->uvs, cur.lab = in_mesh->labels;
    cur.opp = adj.opposite;
    cur.prot = calloc((size_t)F0 + 1, 1);
    cur.vh = malloc(((size_t)V0 + 1) * sizeof(uint32_t));
    if (opts->out_face_parent) cur.parent = malloc(((size_t)F0 + 1) * sizeof(uint32_t));
    uint32_t n_protected = 0; /* the same in every level of the call */
    int owned = 0;            /* cur's mesh arrays belong to the input until the first iteration */
    s3_level base = {0};      /* the last step's implicit input is made from this (s3_step.base) */
    int have_base = 0, base_owned = 0;
    if (!cur.prot || !cur.vh || (opts->out_face_parent && !cur.parent)) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
        goto fail;
    }
    if (opts->protected_faces)
        for (uint32_t f = 0; f < F0; ++f)
            n_protected += cur.prot[f] = opts->protected_faces[f] != 0;
    if (cur.parent)
        for (uint32_t f = 0; f < F0; ++f) cur.parent[f] = f;
    for (uint32_t v = 0; v < V0; ++v) cur.vh[v] = PGT_NONE;
    for (uint32_t h = 3 * F0; h-- > 0;)
        cur.vh[cur.idx[h]] = h; /* the smallest half-edge leaving v */

    uint32_t border = adj.border_half_edges; /* of the current level */
    float alpha[S3_ALPHA_TABLE];
    alpha[0] = 0.0f;
    for (uint32_t n = 1; n < S3_ALPHA_TABLE; ++n) alpha[n] = pgt_sqrt3_alpha(n);

    pgt_progress_stage(opts->progress, "sqrt(3)", k, "iterations");
    for (uint32_t it = 0; it < k; ++it) {
        s3_step s = {0};
        s3_level nx = {0};
        s.in = &cur, s.out = &nx;
        s.even = (it % 2) == 1; /* CGAL: refine_border on i % 2 == 1, restarting at every call */
        s.with_adj = it + 1 < k || opts->out_opposite != NULL;
        s.alpha = alpha;
        /* Uniform is known without classifying: no protected face (they stay protected through
         * the call), and no border face to trisect. */
        s.uniform = n_protected == 0 && (!s.even || border == 0);
        s.closed = s.uniform && border == 0 && !cur.uv;
        /* A closed step followed by the last step (closed too: nothing it tests changes) keeps
         * its output implicit: positions only. */
        const int pos_only = s.closed && it + 2 == k;
        if (pos_only) s.with_adj = 0;
        if (have_base) s.base = &base;
        const int32_t *in_lab = have_base ? base.lab : cur.lab;
        const uint32_t *in_parent = have_base ? base.parent : cur.parent;
        if (!s.uniform) {
            s.kind = malloc((size_t)cur.F + 1);
            s.bslot = malloc((size_t)cur.F + 1);
            s.pt_off = malloc(((size_t)cur.F + 1) * sizeof(uint32_t));
            s.face_off = malloc(((size_t)cur.F + 1) * sizeof(uint32_t));
        }
        if (cur.uv) {
            s.uv_mode = malloc((size_t)cur.V + 1);
            s.uv_relaxed = malloc(((size_t)cur.V * 2 + 1) * sizeof(float));
        }
        if ((!s.uniform && (!s.kind || !s.bslot || !s.pt_off || !s.face_off)) ||
            (cur.uv && (!s.uv_mode || !s.uv_relaxed))) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
        } else {
            uint32_t np = cur.F, nf = 3 * cur.F; /* uniform: one point, three triangles a face */
            if (!s.uniform) {
                pgt_parallel_for(cur.F, threads, s3_classify, &s);
                np = nf = 0;
                for (uint32_t f = 0; f < cur.F; ++f) {
                    s.pt_off[f] = np;
                    s.face_off[f] = nf;
                    np += s.kind[f]; /* KIND_* equals the number of new points */
                    nf += s.kind[f] == KIND_PROTECTED ? 1 : 3;
                }
            }
            nx.V = cur.V + np, nx.F = nf;
            const int want_prot = !pos_only && (s.with_adj || opts->out_protected);
            const int want_lab = !pos_only && in_lab, want_parent = !pos_only && in_parent;
            nx.pos = malloc(((size_t)nx.V * 3 + 1) * sizeof(float));
            if (!pos_only) nx.idx = malloc(((size_t)nx.F * 3 + 1) * sizeof(uint32_t));
            if (want_prot) nx.prot = malloc((size_t)nx.F + 1);
            if (cur.uv) nx.uv = malloc(((size_t)nx.F * 6 + 1) * sizeof(float));
            if (want_lab) nx.lab = malloc(((size_t)nx.F + 1) * sizeof(int32_t));
            if (want_parent) nx.parent = malloc(((size_t)nx.F + 1) * sizeof(uint32_t));
            if (s.with_adj) {
                nx.opp = malloc(((size_t)nx.F * 3 + 1) * sizeof(uint32_t));
                nx.vh = malloc(((size_t)nx.V + 1) * sizeof(uint32_t));
            }
            if (!nx.pos || (!pos_only && !nx.idx) || (want_prot && !nx.prot) ||
                (cur.uv && !nx.uv) || (want_lab && !nx.lab) || (want_parent && !nx.parent) ||
                (s.with_adj && (!nx.opp || !nx.vh))) {
                r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                                  "sqrt3: out of memory for %u vertices, %u faces", nx.V, nx.F);
            } else if (have_base) {
                pgt_parallel_for(cur.V, threads, s3_vertices_implicit, &s);
                pgt_parallel_for(cur.F, threads, s3_faces_implicit, &s);
            } else {
                pgt_parallel_for(cur.V, threads, s.closed ? s3_vertices_closed : s3_vertices, &s);
                pgt_parallel_for(cur.F, threads,
                                 pos_only   ? s3_face_points
                                 : s.closed ? s3_faces_closed
                                            : s3_faces,
                                 &s);
            }
        }
        free(s.kind), free(s.bslot), free(s.pt_off), free(s.face_off), free(s.uv_mode),
            free(s.uv_relaxed);
        if (r != PGT_OK) {
            s3_level_free(&nx);
            goto fail;
        }
        if (pos_only) { /* cur becomes the base of the implicit level nx */
            if (owned) free(cur.pos);
            base = cur, base.pos = NULL, base_owned = owned, have_base = 1;
        } else {
            s3_level_release(&cur, owned, &adj);
            if (have_base) s3_level_release(&base, base_owned, &adj), have_base = 0;
        }
        if (s.even) border *= 3; /* every border edge was trisected */
        cur = nx;
        owned = 1;
        pgt_progress_add(opts->progress, 1);
    }

    if (!owned) { /* k = 0: a copy */
        r = pgt_mesh_copy(out, in_mesh, err);
        if (r != PGT_OK) goto fail;
        if (opts->out_protected) memcpy(opts->out_protected, cur.prot, cur.F);
        if (opts->out_face_parent)
            memcpy(opts->out_face_parent, cur.parent, (size_t)cur.F * sizeof(uint32_t));
        if (opts->out_opposite)
            memcpy(opts->out_opposite, cur.opp, (size_t)cur.F * 3 * sizeof(uint32_t));
        free(cur.prot), free(cur.vh), free(cur.parent);
        pgt_adjacency_destroy(&adj);
        return PGT_OK;
    }
    out->vertex_count = cur.V, out->face_count = cur.F;
    out->positions = cur.pos, out->indices = cur.idx, out->uvs = cur.uv, out->labels = cur.lab;
    if (opts->out_protected) memcpy(opts->out_protected, cur.prot, cur.F);
    if (opts->out_face_parent)
        memcpy(opts->out_face_parent, cur.parent, (size_t)cur.F * sizeof(uint32_t));
    if (opts->out_opposite)
        memcpy(opts->out_opposite, cur.opp, (size_t)cur.F * 3 * sizeof(uint32_t));
    free(cur.opp), free(cur.prot), free(cur.parent), free(cur.vh);
    return PGT_OK;

fail:
    s3_level_release(&cur, owned, &adj);
    if (have_base) s3_level_release(&base, base_owned, &adj);
    memset(out, 0, sizeof(*out));
    return r;
}
