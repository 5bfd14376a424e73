/* pgt: marching on a multi-chart geometry-image atlas (march.h).
 *
 * This work is based on:
 *   Paper 000, sec. 5 (the marching rule and the four cases of Fig. 3), 5.1 (best indirection
 *   pixel, Fig. 5), 5.2 (rotation of marching directions, angles from the atlas's rot channel).
 *
 * The step is an explicit loop over chart crossings (no recursion); the state is nine scalars
 * (position, direction, chart, and the no-bounce rule's memory of the last jump).
 * The atlas is read through four texel-indexed arrays, as a GPU kernel would bind four
 * textures: the packed codes (kind and chart; the case tests and the search), one 16-byte
 * record of P and code (positions, Jacobians), one 8-byte jump record (pointer and rot) and a
 * 2-byte ring mask (which neighbours 5.1, the Jacobians and the position near a chart's rim
 * use). Measured against the same
 * code reading the neighbours' codes (scripts/ab_march.sh with a view per build, 8192 walkers
 * x 500 steps, one thread, medians of 30 pairs on the AMD VM): pizza 1.06-1.08x without
 * positions, with prefetch_targets; the masks without their requests lost (0.93x).
 * The codes alone are a quarter of the P records: on a 1024 x 1024
 * atlas 4 MB instead of 16, which stay in the cache where the records do not. A step without
 * the position on cube_sphere_8 (one thread, CPU time on a shared 2-core VM: noisy) runs at
 * 131 M steps/s when every texel it reads is in the cache (0.01-texel steps), 19 M reading the
 * 16-byte records, 55 to 95 M reading the codes. */
#include "pgt/march.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/parallel.h"
#include "pgt/rng.h"
#include "alloc_internal.h"
#include "vec3_internal.h"

#define MARCH_NONE UINT32_MAX

const char *pgt_march_event_name(pgt_march_event e) {
    switch (e) {
    case PGT_MARCH_INNER:
        return "inner";
    case PGT_MARCH_JUMP:
        return "jump";
    case PGT_MARCH_SEARCH:
        return "search";
    case PGT_MARCH_STOP:
        return "stop";
    }
    return "?";
}

const char *pgt_march_stop_name(pgt_march_stop s) {
    switch (s) {
    case PGT_MARCH_STOP_NONE:
        return "none";
    case PGT_MARCH_STOP_DEAD_END:
        return "dead end";
    case PGT_MARCH_STOP_NO_INDIRECTION:
        return "no indirection";
    case PGT_MARCH_STOP_TOO_MANY_JUMPS:
        return "too many jumps";
    case PGT_MARCH_STOP_REJECTED:
        return "rejected";
    case PGT_MARCH_STOP_BOUNCE:
        return "bounce";
    }
    return "?";
}

int pgt_march_density_condition(void *ctx, float x, float y, uint32_t chart) {
    pgt_march_density *d = ctx;
    (void)chart;
    if (!(x >= 0.0f && y >= 0.0f && x < (float)d->width && y < (float)d->height)) return 0;
    const float v = d->density[(size_t)(uint32_t)y * d->width + (uint32_t)x];
    return pgt_rng_float(d->seed, d->stream, d->draws++) < v; /* a NaN compares false */
}

/* ---- the atlas view ---------------------------------------------------------------------- */

static int is_whole(float v) { return isfinite(v) && v == floorf(v); }

/* The one-ring offsets of the ring masks' bits (march.h), in scan order. */
static const int ring_dx[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
static const int ring_dy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};

/* Texel index of neighbour k (a ring mask's bit) of texel (x, y) in a w-wide image. */
static inline uint32_t ring_neighbour(uint32_t w, uint32_t x, uint32_t y, uint32_t k) {
    return (y + (uint32_t)ring_dy[k]) * w + x + (uint32_t)ring_dx[k];
}

/* The ring mask of texel (x, y) (pgt_march_atlas.rings). */
static uint16_t ring_mask(const uint32_t *codes, uint32_t w, uint32_t h, uint32_t x, uint32_t y) {
    const uint32_t c = codes[(size_t)y * w + x];
    if (!c) return 0;
    const uint32_t inner = (c & ~3u) | PGT_TEXEL_INNER, ind = (c & ~3u) | PGT_TEXEL_INDIRECTION;
    uint32_t m = 0;
    for (uint32_t k = 0; k < 8; ++k) {
        const uint32_t nx = x + (uint32_t)ring_dx[k], ny = y + (uint32_t)ring_dy[k];
        if (nx >= w || ny >= h) continue; /* unsigned: -1 wraps beyond the image */
        const uint32_t cn = codes[(size_t)ny * w + nx];
        m |= (uint32_t)(cn == inner) << k | (uint32_t)(cn == ind) << (8 + k);
    }
    return (uint16_t)m;
}

pgt_result pgt_march_atlas_create(pgt_march_atlas *out, const pgt_image *atlas, const char *what,
                                  pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (!what) what = "atlas";
    pgt_atlas_channels ch;
    pgt_result r = pgt_atlas_channels_find(atlas, what, &ch, err);
    if (r != PGT_OK) return r;
    const uint32_t w = atlas->width, h = atlas->height;
    const size_t n = (size_t)w * h;
    const float *px = pgt_image_plane(atlas, ch.px), *py = pgt_image_plane(atlas, ch.py),
                *pz = pgt_image_plane(atlas, ch.pz), *kind = pgt_image_plane(atlas, ch.kind),
                *chart = pgt_image_plane(atlas, ch.chart), *pu = pgt_image_plane(atlas, ch.ptr_u),
                *pv = pgt_image_plane(atlas, ch.ptr_v), *rot = pgt_image_plane(atlas, ch.rot);
    if (w > PGT_IMAGE_MAX_SIDE || h > PGT_IMAGE_MAX_SIDE)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "%s: %u x %u texels, more than %u on a side",
                             what, w, h, PGT_IMAGE_MAX_SIDE);
    /* huge pages: walkers read the arrays at random (see pgt_alloc_huge) */
    pgt_march_texel *tex = pgt_alloc_huge(n * sizeof(pgt_march_texel));
    uint32_t *codes = pgt_alloc_huge(n * sizeof(uint32_t));
    pgt_march_jump *jumps = pgt_alloc_huge(n * sizeof(pgt_march_jump));
    uint16_t *rings = pgt_alloc_huge(n * sizeof(uint16_t));
    if (jumps) memset(jumps, 0, n * sizeof(pgt_march_jump));
    if (!tex || !codes || !jumps || !rings) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
        goto fail;
    }
    uint32_t charts = 0, inner = 0;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t x = (uint32_t)(i % w), y = (uint32_t)(i / w);
        const float k = kind[i], c = chart[i];
        if (!is_whole(k) || k < 0.0f || k > 3.0f) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s: texel (%u, %u): kind %g is not 0, 1, 2 or 3 (atlas.h)", what, x,
                              y, (double)k);
            goto fail;
        }
        tex[i].x = px[i], tex[i].y = py[i], tex[i].z = pz[i];
        if (k == (float)PGT_TEXEL_BACKGROUND) {
            tex[i].code = codes[i] = 0;
            continue;
        }
        if (!is_whole(c) || c < 0.0f || c >= (float)(PGT_MARCH_MAX_CHARTS - 1u)) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s: texel (%u, %u): kind %g with chart %g (expected a chart id "
                              "0 to %u)",
                              what, x, y, (double)k, (double)c, PGT_MARCH_MAX_CHARTS - 2u);
            goto fail;
        }
        if (!isfinite(px[i]) || !isfinite(py[i]) || !isfinite(pz[i])) {
            r = pgt_error_set(err, PGT_ERROR_PARSE, "%s: texel (%u, %u): position is not finite",
                              what, x, y);
            goto fail;
        }
        if (fabsf(px[i]) > PGT_ATLAS_MAX_COORD || fabsf(py[i]) > PGT_ATLAS_MAX_COORD ||
            fabsf(pz[i]) > PGT_ATLAS_MAX_COORD) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s: texel (%u, %u): position (%g, %g, %g) beyond +-%g (squared "
                              "distances in float would overflow)",
                              what, x, y, (double)px[i], (double)py[i], (double)pz[i],
                              (double)PGT_ATLAS_MAX_COORD);
            goto fail;
        }
        const uint32_t ci = (uint32_t)c;
        tex[i].code = codes[i] = PGT_MARCH_CODE((uint32_t)k, ci);
        if (ci + 1 > charts) charts = ci + 1;
        if (k == (float)PGT_TEXEL_INNER) inner++;
    }
    if (!inner) {
        r = pgt_error_set(err, PGT_ERROR_PARSE, "%s: no inner texel (an empty atlas)", what);
        goto fail;
    }
    /* Pointers need every texel's code, hence a second pass. */
    for (size_t i = 0; i < n; ++i) {
        if ((tex[i].code & 3u) != PGT_TEXEL_INDIRECTION) continue;
        const uint32_t x = (uint32_t)(i % w), y = (uint32_t)(i / w);
        const float u = pu[i], v = pv[i];
        if (!is_whole(u) || !is_whole(v) || u < 0.0f || v < 0.0f || u >= (float)w ||
            v >= (float)h) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s: indirection texel (%u, %u): pointer (%g, %g) is not a texel "
                              "of the %u x %u image",
                              what, x, y, (double)u, (double)v, w, h);
            goto fail;
        }
        const size_t t = (size_t)v * w + (size_t)u;
        const uint32_t kt = tex[t].code & 3u;
        if (kt != PGT_TEXEL_INNER) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s: indirection texel (%u, %u): pointer (%g, %g) names a texel "
                              "of kind %u, not an inner texel",
                              what, x, y, (double)u, (double)v, kt);
            goto fail;
        }
        if (!isfinite(rot[i])) {
            r = pgt_error_set(err, PGT_ERROR_PARSE,
                              "%s: indirection texel (%u, %u): rot is not finite", what, x, y);
            goto fail;
        }
        jumps[i].u = (uint16_t)u, jumps[i].v = (uint16_t)v, jumps[i].rot = rot[i];
    }
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) rings[(size_t)y * w + x] = ring_mask(codes, w, h, x, y);
    out->width = w;
    out->height = h;
    out->chart_count = charts;
    out->texels = tex;
    out->codes = codes;
    out->jumps = jumps;
    out->rings = rings;
    return PGT_OK;
fail:
    free(tex), free(codes), free(jumps), free(rings);
    return r;
}

void pgt_march_atlas_destroy(pgt_march_atlas *a) {
    if (!a) return;
    free(a->texels), free(a->codes), free(a->jumps), free(a->rings);
    memset(a, 0, sizeof(*a));
}

/* ---- texel helpers ------------------------------------------------------------------------- */

/* Texel index of a texel-space point in a w x h image (fw, fh: w and h as floats), or
 * MARCH_NONE outside it (NaN included). A loop passes the sides as locals: read through the
 * atlas pointer they would be reloaded and converted every step. */
static inline uint32_t texel_index(uint32_t w, float fw, float fh, float x, float y) {
    if (!(x >= 0.0f && y >= 0.0f && x < fw && y < fh)) return MARCH_NONE;
    return (uint32_t)y * w + (uint32_t)x;
}

static inline uint32_t texel_at(const pgt_march_atlas *a, float x, float y) {
    return texel_index(a->width, (float)a->width, (float)a->height, x, y);
}

static inline uint32_t code_of(const pgt_march_atlas *a, uint32_t t) {
    return t == MARCH_NONE ? 0u : a->codes[t];
}

static inline void pos3(const pgt_march_atlas *a, uint32_t t, float p[3]) {
    p[0] = a->texels[t].x, p[1] = a->texels[t].y, p[2] = a->texels[t].z;
}

/* The texel an indirection texel's pointer names. */
static inline uint32_t pointer_of(const pgt_march_atlas *a, uint32_t t) {
    return (uint32_t)a->jumps[t].v * a->width + a->jumps[t].u;
}

/* pgt_march_position near the chart's rim: texels that are not inner texels of the walker's
 * chart (or lie outside the image) drop out and the rest are renormalised. The containing
 * texel (tx, ty) is one of the four, with a weight >= 1/4; which of the others count is its
 * ring mask's (bits 0-7), widened to the 3 x 3 block in scan order with the centre set. Kept
 * out of line so that the common case stays a short leaf function. */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static void
position_rim(const pgt_march_atlas *a, float x, float y, int i0, int j0, float fx, float fy,
             float out_p[3]) {
    const int w = (int)a->width, tx = (int)x, ty = (int)y;
    const uint32_t m = a->rings[(size_t)ty * (size_t)w + (size_t)tx],
                   block = (m & 0x0Fu) | (m & 0xF0u) << 1 | 0x10u;
    const float wx[2] = {1.0f - fx, fx}, wy[2] = {1.0f - fy, fy};
    float sum = 0.0f, p[3] = {0.0f, 0.0f, 0.0f};
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const int xi = i0 + i, yj = j0 + j; /* within one texel of (tx, ty) */
            if (!(block >> ((yj - ty + 1) * 3 + xi - tx + 1) & 1u)) continue;
            const pgt_march_texel *q = &a->texels[(size_t)yj * (size_t)w + (size_t)xi];
            const float wq = wx[i] * wy[j];
            p[0] += wq * q->x, p[1] += wq * q->y, p[2] += wq * q->z;
            sum += wq;
        }
    for (int k = 0; k < 3; ++k) out_p[k] = p[k] / sum;
}

void pgt_march_position(const pgt_march_atlas *a, float x, float y, float out_p[3]) {
    assert(texel_at(a, x, y) != MARCH_NONE &&
           (a->texels[texel_at(a, x, y)].code & 3u) == PGT_TEXEL_INNER);
    const uint32_t w = a->width;
    /* Bilinear weights of the four texel centres around (x, y): u = x - 1/2 has floor i0 =
     * (int)(x + 1/2) - 1 (x >= 0, so the truncation is a floor without a libm call). */
    const int i0 = (int)(x + 0.5f) - 1, j0 = (int)(y + 0.5f) - 1;
    const float fx = x - 0.5f - (float)i0, fy = y - 0.5f - (float)j0;
    /* i0 (j0) is -1 left of (above) the centres of column (row) 0: a built atlas keeps its band
     * there, a file given to pgt march need not */
    if (i0 >= 0 && j0 >= 0 && (uint32_t)i0 + 1u < w && (uint32_t)j0 + 1u < a->height) {
        const pgt_march_texel *q = a->texels + (size_t)(uint32_t)j0 * w + (uint32_t)i0;
        const uint32_t c = q[0].code;
        /* the texel containing (x, y) is one of the four: when all four carry the same inner
         * code, they are all inner texels of the walker's chart (the common case) */
        if ((c & 3u) == PGT_TEXEL_INNER && q[1].code == c && q[w].code == c && q[w + 1].code == c) {
            const float w00 = (1.0f - fx) * (1.0f - fy), w10 = fx * (1.0f - fy),
                        w01 = (1.0f - fx) * fy, w11 = fx * fy;
            out_p[0] = w00 * q[0].x + w10 * q[1].x + w01 * q[w].x + w11 * q[w + 1].x;
            out_p[1] = w00 * q[0].y + w10 * q[1].y + w01 * q[w].y + w11 * q[w + 1].y;
            out_p[2] = w00 * q[0].z + w10 * q[1].z + w01 * q[w].z + w11 * q[w + 1].z;
            return;
        }
    }
    position_rim(a, x, y, i0, j0, fx, fy, out_p);
}

/* P's Jacobian at inner texel t in texel units: its columns are the finite differences of P
 * along x and along y, central where both 4-neighbours are inner texels of the same chart
 * (second order), else one-sided to the one that is. 0 when an axis has neither (a chart one
 * texel thin there). Which neighbours qualify comes from t's ring mask. */
static int texel_jacobian(const pgt_march_atlas *a, uint32_t t, float ex[3], float ey[3]) {
    const uint32_t w = a->width, m = a->rings[t];
    const uint32_t left = (m >> 3) & 1u, right = (m >> 4) & 1u, up = (m >> 1) & 1u,
                   down = (m >> 6) & 1u;
    if (!(left | right) || !(up | down)) return 0;
    /* Which neighbours qualify follows no pattern a branch predictor learns: the offsets and
     * scales are arithmetic on the mask bits, not branches. Against the selects GCC compiled
     * to branches (valgrind's branch simulation: 0.8 mispredicted branches a jump on pizza
     * fewer), A/B as in batch_range: pizza 1.04-1.06x, 1.02x with positions. */
    static const float scale[2] = {1.0f, 0.5f};
    const pgt_march_texel *q = a->texels + t;
    const pgt_march_texel *x0 = q - left, *x1 = q + right, *y0 = q - (size_t)(up * w),
                          *y1 = q + (size_t)(down * w);
    const float ix = scale[left & right], iy = scale[up & down];
    ex[0] = (x1->x - x0->x) * ix, ex[1] = (x1->y - x0->y) * ix, ex[2] = (x1->z - x0->z) * ix;
    ey[0] = (y1->x - y0->x) * iy, ey[1] = (y1->y - y0->y) * iy, ey[2] = (y1->z - y0->z) * iy;
    return 1;
}

/* The 3D motion of one texel of travel along the texel-space direction (dx, dy) where P's
 * Jacobian has the columns ex, ey: J d. */
static inline void texel_motion(const float ex[3], const float ey[3], float dx, float dy,
                                float out_v[3]) {
    for (int k = 0; k < 3; ++k) out_v[k] = ex[k] * dx + ey[k] * dy;
}

static inline float norm3(const float v[3]) {
    return sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* PGT_MARCH_ROTATION_JACOBIAN: the destination direction whose 3D motion is the source's,
 * carried from the source tangent plane to the destination's by the smallest rotation taking
 * one normal to the other (across a crease this unfolds about the crease line, as 5.2 does in
 * texel space): d' ~ J'^+ T J d, J = (sx sy) at the source texel, J' = (rx ry) at the
 * destination. 0 when a Jacobian is degenerate or the tangent planes face away from each other
 * (the caller checks that both exist). */
static int transport_direction(const float sx_in[3], const float sy_in[3], const float rx_in[3],
                               const float ry_in[3], float dx, float dy, float *out_dx,
                               float *out_dy) {
    /* the direction depends on the Jacobians' ratios only; det below is their 4th power, which
     * leaves float's range for texels under ~1e-9 or over ~1e9 (it fell back to rot there):
     * outside [PGT_MARCH_JACOBIAN_SCALE_MIN, MAX] the four are scaled by their largest component
     * first (inside it nothing changes, so the paths of usual meshes keep their bytes) */
    float sx[3], sy[3], rx[3], ry[3], m = 0.0f;
    for (int i = 0; i < 3; ++i) {
        sx[i] = sx_in[i], sy[i] = sy_in[i], rx[i] = rx_in[i], ry[i] = ry_in[i];
        m = fmaxf(m, fmaxf(fmaxf(fabsf(sx[i]), fabsf(sy[i])), fmaxf(fabsf(rx[i]), fabsf(ry[i]))));
    }
    if (!(m > 0.0f) || !isfinite(m)) return 0;
    if (m < PGT_MARCH_JACOBIAN_SCALE_MIN || m > PGT_MARCH_JACOBIAN_SCALE_MAX)
        for (int i = 0; i < 3; ++i) sx[i] /= m, sy[i] /= m, rx[i] /= m, ry[i] /= m;
    float ns[3], nr[3], v[3], k[3], kv[3], t[3];
    texel_motion(sx, sy, dx, dy, v);
    cross3(sx, sy, ns);
    cross3(rx, ry, nr);
    const float ls = sqrtf(dot3(ns, ns)), lr = sqrtf(dot3(nr, nr));
    if (!(ls > 0.0f) || !(lr > 0.0f)) return 0;
    for (int i = 0; i < 3; ++i) ns[i] /= ls, nr[i] /= lr;
    const float c = dot3(ns, nr);
    if (!(c > 0.0f)) return 0;
    /* Rodrigues with k = ns x nr (|k| = sin): T v = c v + k x v + k (k . v) / (1 + c) */
    cross3(ns, nr, k);
    cross3(k, v, kv);
    const float kk = dot3(k, v) / (1.0f + c);
    for (int i = 0; i < 3; ++i) t[i] = c * v[i] + kv[i] + kk * k[i];
    const float a11 = dot3(rx, rx), a12 = dot3(rx, ry), a22 = dot3(ry, ry);
    const float b1 = dot3(rx, t), b2 = dot3(ry, t), det = a11 * a22 - a12 * a12;
    /* a nearly singular J' (a sliver texel) gives no trustworthy direction */
    if (!(det > PGT_MARCH_MIN_JACOBIAN_SINE2 * a11 * a22)) return 0;
    const float ex = (a22 * b1 - a12 * b2) / det, ey = (a11 * b2 - a12 * b1) / det;
    const float l = sqrtf(ex * ex + ey * ey);
    if (!(l > 0.0f)) return 0;
    *out_dx = ex / l, *out_dy = ey / l;
    return 1;
}

/* ---- case 3/4: binary search --------------------------------------------------------------- */

/* pgt_march_search, also returning the found texel's coordinates (*out_x, *out_y). */
static uint32_t search_xy(const pgt_march_atlas *a, uint32_t chart, float x0, float y0, float x1,
                          float y1, float *out_t, uint32_t *out_x, uint32_t *out_y) {
    const uint32_t tag = chart + 1u;
    float lo = 0.0f, hi = 1.0f; /* texel(lo) is an inner texel of chart, texel(hi) is not its */
    for (uint32_t i = 0; i < PGT_MARCH_SEARCH_ITERATIONS; ++i) {
        const float m = 0.5f * (lo + hi);
        const float x = x0 + (x1 - x0) * m, y = y0 + (y1 - y0) * m;
        const uint32_t t = texel_at(a, x, y);
        const uint32_t c = code_of(a, t);
        if ((c >> 2) != tag) {
            hi = m; /* background, another chart, outside the image: outside this chart */
        } else if ((c & 3u) == PGT_TEXEL_INNER) {
            lo = m;
        } else { /* indirection or dead end of this chart: the boundary */
            *out_t = m;
            *out_x = (uint32_t)x, *out_y = (uint32_t)y;
            return t;
        }
    }
    *out_t = 0.0f;
    return MARCH_NONE;
}

uint32_t pgt_march_search(const pgt_march_atlas *a, uint32_t chart, float x0, float y0, float x1,
                          float y1, float *out_t) {
    uint32_t x, y;
    return search_xy(a, chart, x0, y0, x1, y1, out_t, &x, &y);
}

/* ---- 5.1: best indirection texel --------------------------------------------------------- */

/* Index of the lowest set bit of m (m != 0): the next neighbour of a ring mask. */
static inline uint32_t lowest_bit(uint32_t m) {
#if defined(__GNUC__)
    return (uint32_t)__builtin_ctz(m);
#else
    uint32_t k = 0;
    while (!((m >> k) & 1u)) k++;
    return k;
#endif
}

/* P_near: the inner texel of the chart nearest to P0 = (px, py), an indirection texel of the
 * chart (in P0's one-ring: edge neighbours before diagonal ones), ties to the one nearest to
 * (x, y), then the first in scan order. Its coordinates go to *out_x, *out_y. An edge
 * neighbour always beats a diagonal one, so the diagonals count only when no edge neighbour
 * qualifies. */
static uint32_t nearest_inner(const pgt_march_atlas *a, float x, float y, uint32_t px, uint32_t py,
                              uint32_t *out_x, uint32_t *out_y) {
    const uint32_t w = a->width, ring = a->rings[py * w + px] & 0xFFu;
    uint32_t m = ring & PGT_MARCH_RING_EDGES ? ring & PGT_MARCH_RING_EDGES : ring;
    uint32_t near = MARCH_NONE, bx = 0, by = 0;
    float near_e2 = INFINITY;
    for (; m; m &= m - 1u) { /* the qualifying neighbours in scan order */
        const uint32_t k = lowest_bit(m);
        const uint32_t nx = px + (uint32_t)ring_dx[k], ny = py + (uint32_t)ring_dy[k];
        const float ex = (float)nx + 0.5f - x, ey = (float)ny + 0.5f - y;
        const float e2 = ex * ex + ey * ey;
        /* selects, not branches: which neighbour is nearest follows no pattern a branch
         * predictor learns */
        const int take = e2 < near_e2;
        near = take ? ny * w + nx : near, near_e2 = take ? e2 : near_e2;
        bx = take ? nx : bx, by = take ? ny : by;
    }
    *out_x = bx, *out_y = by;
    return near;
}

/* Scores indirection texel t (5.1): the cosine of the angle between c_t = pos(ref(t)) - pc and
 * r without the common factor 1/|r|; t becomes *best when it scores higher than *best_score. */
static inline void score_pointer(const pgt_march_atlas *a, uint32_t t, const float pc[3],
                                 const float r[3], uint32_t *best, float *best_score) {
    float q[3], c[3];
    pos3(a, pointer_of(a, t), q);
    for (int k = 0; k < 3; ++k) c[k] = q[k] - pc[k];
    const float len = sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(len > 0.0f)) return;
    const float score = (c[0] * r[0] + c[1] * r[1] + c[2] * r[2]) / len;
    if (score > *best_score) *best = t, *best_score = score;
}

/* Requests the cache line of element i of the array at base (elements of `size` bytes). Callers
 * pass the rows above the first and below the last (wrapped around as unsigned indices) and
 * points beyond the image without testing bounds: a prefetch instruction never faults, and a
 * wasted request costs less than a test per request (as a clamp of i to the array, measured:
 * pizza 0.96x, spot 0.94x). The address is an integer handed to the instruction, never a C
 * pointer: a pointer outside the array, even one cast from an integer, is undefined behaviour
 * under GCC's rules, so __builtin_prefetch cannot take it. Other targets request nothing. */
#if defined(__GNUC__)
__attribute__((always_inline)) /* see march_prefetch */
#endif
static inline void
prefetch_element(const void *base, uint32_t i, size_t size) {
    const uintptr_t address = (uintptr_t)base + (uintptr_t)i * size; /* wraps, defined */
#if defined(__GNUC__) && defined(__x86_64__)
    __asm__("prefetcht0 (%0)" : : "r"(address));
#elif defined(__GNUC__) && defined(__aarch64__)
    __asm__("prfm pldl1keep, [%0]" : : "r"(address));
#else
    (void)address;
#endif
}

/* Requests the texel records a jump to inner texel t reads in the destination chart: its own
 * (5.1's score, the remaining length), the rows above and below (P's Jacobian there, for 5.2
 * and the remaining length) and its ring mask (which of those rows the Jacobian takes). A jump
 * lands anywhere in the atlas, so these are cache misses; requested for every candidate before 5.1
 * scores them, they overlap instead of following one another. Measured with the same walkers
 * alternately with and without (medians of 11-21 pairs of 8192 walkers x 300 steps, one thread, no
 * positions): nefertiti's Voronoi atlas 1.11-1.21x steps/s, mountain's 1.13x, pizza 1.16x,
 * spot 1.01x (a jump every 90 steps). Requesting the destination's code too, or the jump records
 * around a boundary seen two steps ahead, gave nothing (1.01x) or lost (0.92x). */
#if defined(__GNUC__)
__attribute__((always_inline)) /* see march_prefetch: GCC 12 drops calls of prefetch-only code */
#endif
static inline void
prefetch_destination(const pgt_march_atlas *a, uint32_t t) {
    const uint32_t w = a->width;
    prefetch_element(a->rings, t, sizeof *a->rings);
    prefetch_element(a->texels, t, sizeof *a->texels);
    prefetch_element(a->texels, t - w, sizeof *a->texels);
    prefetch_element(a->texels, t + w, sizeof *a->texels);
}

/* Requests what a jump through P0 reads first, before 5.1 computes anything: P0's ring mask,
 * the jump records of P0's 3 x 3 block (5.1's candidates lie around P_near, a neighbour of P0;
 * the left and right ends of each of its rows, as a row of three records can straddle two
 * cache lines) and the texel records and ring mask of the walker's texel src and its rows
 * (P_cur, the source Jacobian). The block's ends instead of P0's column alone: pizza 1.02x
 * (A/B as in batch_range, session 20; the ends of the 5 x 5 block around P0: 0.98x). With
 * prefetch_landing, measured on pizza (a jump every 4.4 steps; pgt bench march, one thread, 8192
 * walkers x 500 steps, 12 alternating runs each on the AMD VM, the same results): medians 10.25
 * -> 12.80 M steps/s without positions, 7.84 -> 9.09 with. Requesting them one step earlier from
 * the batch (when the next step's destination leaves the chart) gave nothing more (13.3
 * against 13.9), nor did scoring 5.1's candidates after the source Jacobian so that their targets
 * load meanwhile (10.8 against 11.4). */
#if defined(__GNUC__)
__attribute__((always_inline)) /* see march_prefetch */
#endif
static inline void
prefetch_jump(const pgt_march_atlas *a, uint32_t p0, uint32_t src) {
    const uint32_t w = a->width;
    prefetch_element(a->rings, p0, sizeof *a->rings);
    for (int k = -1; k <= 1; ++k) {
        const uint32_t t = p0 + (uint32_t)k * w;
        prefetch_element(a->jumps, t - 1u, sizeof *a->jumps);
        prefetch_element(a->jumps, t + 1u, sizeof *a->jumps);
    }
    prefetch_destination(a, src); /* the same three texel rows as a jump's destination */
}

/* Requests the codes around the referenced texel ref, where the walker lands: the rest of
 * the step and the next steps test them (rows ref - 2w to ref + 2w; a step is about 2 texels). */
#if defined(__GNUC__)
__attribute__((always_inline)) /* see march_prefetch */
#endif
static inline void
prefetch_landing(const pgt_march_atlas *a, uint32_t ref) {
    const uint32_t w = a->width;
    for (int k = -2; k <= 2; ++k)
        prefetch_element(a->codes, ref + (uint32_t)k * w, sizeof *a->codes);
}

/* Requests the texel records that the indirection texels of the chart around P0 point at:
 * 5.1 scores its candidates (indirection texels around P_near, a neighbour of P0: mostly
 * these) by them. P0's ring mask and its jump records' rows must be in the cache already (the
 * batch's second turn). Measured on pizza as above: 1.03x. Requesting also the texel records
 * and ring masks of the rows around P0 (P_near's) gave 1.01x; dropping best_pointer's own
 * requests of its candidates' records once this exists lost (0.98x). */
#if defined(__GNUC__)
__attribute__((always_inline)) /* see march_prefetch */
#endif
static inline void
prefetch_targets(const pgt_march_atlas *a, uint32_t p0) {
    const uint32_t w = a->width, px = p0 % w, py = p0 / w;
    for (uint32_t m = (uint32_t)a->rings[p0] >> 8; m; m &= m - 1u) {
        const uint32_t k = lowest_bit(m);
        prefetch_element(a->texels, pointer_of(a, ring_neighbour(w, px, py, k)), sizeof *a->texels);
    }
}

/* The candidates of 5.1 in the order they are ranked: P0 first, so that it wins ties (P_near =
 * (nx0, ny0) is in P0's one-ring, so P0 is in P_near's), then the rest of the indirection
 * texels of the chart in P_near's one-ring (its ring mask) in scan order. Returns their count
 * (at most 9). */
static uint32_t pointer_candidates(const pgt_march_atlas *a, uint32_t chart, uint32_t p0,
                                   uint32_t nx0, uint32_t ny0, uint32_t cand[9]) {
    const uint32_t w = a->width, near = ny0 * w + nx0;
    uint32_t n = 0;
    cand[n] = p0, n += a->codes[p0] == PGT_MARCH_CODE(PGT_TEXEL_INDIRECTION, chart);
    /* P0's bit in P_near's ring: offset (ox, oy) in -1..1, the centre skipped */
    const uint32_t ox = p0 % w + 1u - nx0, oy = p0 / w + 1u - ny0, b = oy * 3u + ox;
    uint32_t m = (uint32_t)a->rings[near] >> 8;
    if (ox <= 2u && oy <= 2u && b != 4u) m &= ~(1u << (b > 4u ? b - 1u : b));
    for (; m; m &= m - 1u) cand[n++] = ring_neighbour(w, nx0, ny0, lowest_bit(m));
    return n;
}

/* pgt_march_best_pointer with the current texel cur (the one containing (x, y)) and P0's
 * coordinates (p0x, p0y) given. */
static uint32_t best_pointer(const pgt_march_atlas *a, uint32_t chart, float x, float y,
                             uint32_t cur, uint32_t p0, uint32_t p0x, uint32_t p0y,
                             uint32_t *out_near) {
    uint32_t nx0 = 0, ny0 = 0;
    const uint32_t near = nearest_inner(a, x, y, p0x, p0y, &nx0, &ny0);
    if (out_near) *out_near = near;
    if (near == MARCH_NONE || near == cur) return p0; /* no reference direction */
    float pc[3], pn[3], r[3];
    pos3(a, cur, pc);
    pos3(a, near, pn);
    for (int k = 0; k < 3; ++k) r[k] = pn[k] - pc[k];
    uint32_t best = p0;
    float best_score = -INFINITY;
    uint32_t cand[9];
    const uint32_t n = pointer_candidates(a, chart, p0, nx0, ny0, cand);
    for (uint32_t k = 0; k < n; ++k) prefetch_destination(a, pointer_of(a, cand[k]));
    for (uint32_t k = 0; k < n; ++k) score_pointer(a, cand[k], pc, r, &best, &best_score);
    return best;
}

uint32_t pgt_march_best_pointer(const pgt_march_atlas *a, uint32_t chart, float x, float y,
                                uint32_t p0, uint32_t *out_near) {
    const uint32_t w = a->width;
    assert(p0 < w * a->height && a->codes[p0] == PGT_MARCH_CODE(PGT_TEXEL_INDIRECTION, chart));
    return best_pointer(a, chart, x, y, texel_at(a, x, y), p0, p0 % w, p0 / w, out_near);
}

/* ---- 5.2 and the no-bounce rule ---------------------------------------------------------- */

/* 5.2 for a jump whose jump record is jr, the walker heading (dx, dy) with P's Jacobian (sx,
 * sy) at its texel (has_src: it exists): the direction in the destination chart (*ndx, *ndy,
 * not normalised), and P's Jacobian (rx, ry) at the referenced texel, which the remaining
 * length needs too (returns whether it exists). */
static int jump_direction(const pgt_march_atlas *a, const pgt_march_options *o, pgt_march_jump jr,
                          int has_src, const float sx[3], const float sy[3], float dx, float dy,
                          float *ndx, float *ndy, float rx[3], float ry[3]) {
    const uint32_t ref = (uint32_t)jr.v * a->width + jr.u;
    const int has_ref = texel_jacobian(a, ref, rx, ry);
    *ndx = dx, *ndy = dy;
    if (o && o->no_rotation) return has_ref;
    if (o && o->rotation == PGT_MARCH_ROTATION_JACOBIAN && has_src && has_ref &&
        transport_direction(sx, sy, rx, ry, dx, dy, ndx, ndy))
        return has_ref;
    const float r = jr.rot; /* the paper's rot; the Jacobian rotation's fallback */
    if (r != 0.0f) {
        const float cr = cosf(r), sr = sinf(r);
        *ndx = cr * dx - sr * dy, *ndy = sr * dx + cr * dy;
    }
    return has_ref;
}

/* The no-bounce rule (march.h): whether a jump to inner texel (u, v) lands within
 * PGT_MARCH_BOUNCE_TEXELS of the texel the walker's last jump left from (from: 1 + its texel
 * index, 0 for none), in that texel's chart. */
static inline int bounces(const pgt_march_atlas *a, uint32_t from, uint32_t u, uint32_t v) {
    const uint32_t w = a->width, f = from - 1u; /* from = 0 wraps to beyond the image */
    if (f >= w * a->height) return 0;
    const uint32_t fx = f % w, fy = f / w;
    const uint32_t ex = u > fx ? u - fx : fx - u, ey = v > fy ? v - fy : fy - v;
    return ex <= PGT_MARCH_BOUNCE_TEXELS && ey <= PGT_MARCH_BOUNCE_TEXELS &&
           a->codes[f] == a->codes[v * w + u];
}

/* The no-bounce rule's choice when the jump 5.1 chose bounces: 5.1's candidates (P0 and the
 * chart's indirection texels around P_near), ranked as 5.1 ranks them (the cosine of c_i with
 * r; where 5.1 has no r, P_near being cur, the cosine of the texel offset from (x, y) to P_i's
 * centre with d), without those whose jump bounces. MARCH_NONE when every one bounces. */
static uint32_t unbounced_pointer(const pgt_march_atlas *a, uint32_t chart, float x, float y,
                                  uint32_t cur, uint32_t p0, uint32_t p0x, uint32_t p0y, float dx,
                                  float dy, uint32_t from) {
    const uint32_t w = a->width;
    uint32_t nx0 = 0, ny0 = 0, cand[9], n = 1;
    const uint32_t near = nearest_inner(a, x, y, p0x, p0y, &nx0, &ny0);
    cand[0] = p0;
    if (near != MARCH_NONE) n = pointer_candidates(a, chart, p0, nx0, ny0, cand);
    const int has_r = near != MARCH_NONE && near != cur;
    float pc[3], r[3];
    if (has_r) {
        float pn[3];
        pos3(a, cur, pc);
        pos3(a, near, pn);
        for (int k = 0; k < 3; ++k) r[k] = pn[k] - pc[k];
    }
    uint32_t best = MARCH_NONE;
    float best_score = -INFINITY;
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t t = cand[k];
        if (bounces(a, from, a->jumps[t].u, a->jumps[t].v)) continue;
        if (has_r) {
            score_pointer(a, t, pc, r, &best, &best_score);
            continue;
        }
        const float ox = (float)(t % w) + 0.5f - x, oy = (float)(t / w) + 0.5f - y;
        const float score = (ox * dx + oy * dy) / sqrtf(ox * ox + oy * oy);
        if (score > best_score) best = t, best_score = score;
    }
    return best;
}

/* ---- the step ------------------------------------------------------------------------------ */

pgt_result pgt_march_start(const pgt_march_atlas *a, float x, float y, float dx, float dy,
                           pgt_march_state *out, pgt_error *err) {
    float len = sqrtf(dx * dx + dy * dy);
    if (!isfinite(len) || !(len > 0.0f)) {
        /* the squares under- or overflow for finite directions below 1e-19 or above 1e19:
         * such a direction is scaled to its largest component first */
        const float m = fmaxf(fabsf(dx), fabsf(dy));
        if (!isfinite(dx) || !isfinite(dy) || !(m > 0.0f))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "direction (%g, %g) is zero or not finite", (double)dx,
                                 (double)dy);
        dx /= m, dy /= m;
        len = sqrtf(dx * dx + dy * dy);
    }
    const uint32_t t = texel_at(a, x, y);
    if (t == MARCH_NONE)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "start (%g, %g) is outside the %u x %u texels of the atlas", (double)x,
                             (double)y, a->width, a->height);
    const uint32_t c = a->codes[t];
    if ((c & 3u) != PGT_TEXEL_INNER) {
        static const char *const kinds[4] = {"a background", "an inner", "an indirection",
                                             "a dead-end"};
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "start (%g, %g) is on texel (%u, %u), %s texel, not an inner one",
                             (double)x, (double)y, t % a->width, t / a->width, kinds[c & 3u]);
    }
    out->x = x, out->y = y;
    out->dx = dx / len, out->dy = dy / len;
    out->chart = (c >> 2) - 1u;
    out->from = 0u, out->in_dx = out->in_dy = 0.0f, out->bounces = 0u;
    return PGT_OK;
}

int pgt_march_random_starts(const pgt_march_atlas *a, uint32_t seed, uint32_t count, float *x,
                            float *y, float *dx, float *dy, uint32_t *chart) {
    for (uint32_t i = 0; i < count; ++i) {
        pgt_march_state s = {0};
        uint32_t t = 0;
        for (; t < PGT_MARCH_START_TRIES; ++t) {
            const uint64_t c = 3ull * ((uint64_t)i * PGT_MARCH_START_TRIES + t);
            const float px = pgt_rng_float(seed, 0, c) * (float)a->width,
                        py = pgt_rng_float(seed, 0, c + 1) * (float)a->height,
                        h = 6.2831853f * pgt_rng_float(seed, 0, c + 2);
            if (pgt_march_start(a, px, py, cosf(h), sinf(h), &s, NULL) == PGT_OK) break;
        }
        if (t == PGT_MARCH_START_TRIES) return -1;
        x[i] = s.x, y[i] = s.y, dx[i] = s.dx, dy[i] = s.dy, chart[i] = s.chart;
    }
    return 0;
}

static inline pgt_march_event stop(pgt_march_info *info, pgt_march_stop why) {
    if (info) info->stop = why;
    return PGT_MARCH_STOP;
}

/* The step from its first destination test on, with the turned direction (dx, dy): the loop
 * over chart crossings and the external contexts. `found`: the first crossing's P0 when the
 * caller has searched for it already (the batch's first turn, prefetch_crossing: the same
 * search on the same floats), taken in cases 3 and 4 instead of searching again; MARCH_NONE
 * otherwise. Kept out of line so that case 1 without
 * external contexts, nearly every step, stays a short path that keeps its state in registers
 * when inlined into a batch (pgt_march_step tests that case first and comes here otherwise; the
 * test is repeated here, with the same result). */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static pgt_march_event
step_crossing(const pgt_march_atlas *a, const pgt_march_options *o, pgt_march_state *s,
              float length, float dx, float dy, uint32_t found, pgt_march_info *info) {
    float cx = s->x, cy = s->y, rem = length, idx = s->in_dx, idy = s->in_dy;
    uint32_t chart = s->chart, jumps = 0, from = s->from, nb = s->bounces;
    pgt_march_event event = PGT_MARCH_INNER;
    for (;;) {
        const float tx = cx + dx * rem, ty = cy + dy * rem; /* P_dest_hat */
        const uint32_t td = texel_at(a, tx, ty), c = code_of(a, td), tag = chart + 1u;
        if (c == PGT_MARCH_CODE(PGT_TEXEL_INNER, chart)) { /* case 1 */
            cx = tx, cy = ty;
            break;
        }
        uint32_t p0, p0x, p0y;
        if ((c >> 2) == tag) { /* case 2: a boundary texel of this chart */
            if ((c & 3u) == PGT_TEXEL_DEAD_END) return stop(info, PGT_MARCH_STOP_DEAD_END);
            p0 = td, p0x = (uint32_t)tx, p0y = (uint32_t)ty;
            if (event == PGT_MARCH_INNER) event = PGT_MARCH_JUMP;
        } else { /* cases 3 and 4 */
            float t;
            if (found != MARCH_NONE && jumps == 0) { /* the batch's first turn searched already */
                p0 = found, p0x = found % a->width, p0y = found / a->width;
                assert(found == search_xy(a, chart, cx, cy, tx, ty, &t, &p0x, &p0y));
            } else {
                p0 = search_xy(a, chart, cx, cy, tx, ty, &t, &p0x, &p0y);
            }
            if (p0 == MARCH_NONE) return stop(info, PGT_MARCH_STOP_NO_INDIRECTION);
            if ((a->codes[p0] & 3u) == PGT_TEXEL_DEAD_END)
                return stop(info, PGT_MARCH_STOP_DEAD_END);
            event = PGT_MARCH_SEARCH;
            if (info) info->searches++;
        }
        if (jumps == PGT_MARCH_MAX_JUMPS) return stop(info, PGT_MARCH_STOP_TOO_MANY_JUMPS);
        jumps++;
        /* The walker stands inside an inner texel, so its texel is (int)cx, (int)cy. */
        const uint32_t w = a->width, scx = (uint32_t)cx, scy = (uint32_t)cy, src = scy * w + scx;
        prefetch_jump(a, p0, src);
        const int best = !o || !o->no_best_pointer;
        uint32_t pi = p0;
        if (best) pi = best_pointer(a, chart, cx, cy, src, p0, p0x, p0y, NULL);
        /* The source Jacobian is taken where the walker stands: an inner texel, usually with
         * neighbours on every side, where the finite differences are steadier than at P_near on
         * the chart's rim (measured with the Jacobian rotation: median turn at jumps 2.6 vs
         * 2.9 degrees on spot). Both Jacobians are taken once and serve the rotation (5.2), the
         * no-bounce rule and the remaining length. */
        float sx[3], sy[3], rx[3], ry[3], ndx, ndy;
        const int has_src = texel_jacobian(a, src, sx, sy);
        int bounce = bounces(a, from, a->jumps[pi].u, a->jumps[pi].v); /* no bounce (march.h) */
        if (bounce && best && dx * idx + dy * idy > 0.0f) {
            const uint32_t alt =
                unbounced_pointer(a, chart, cx, cy, src, p0, p0x, p0y, dx, dy, from);
            if (alt != MARCH_NONE) pi = alt, bounce = 0;
        }
        if (bounce && nb == PGT_MARCH_MAX_BOUNCES) return stop(info, PGT_MARCH_STOP_BOUNCE);
        nb = bounce ? nb + 1u : 0u;
        const pgt_march_jump jr = a->jumps[pi];
        const uint32_t ref = (uint32_t)jr.v * w + jr.u;
        prefetch_landing(a, ref);
        const int has_ref = jump_direction(a, o, jr, has_src, sx, sy, dx, dy, &ndx, &ndy, rx, ry);
        /* What is left of the step, measured in 3D. The walker set out from pc = pos(P_cur)
         * to cover L3 = rem |J d| (J: P's finite-difference Jacobian at its texel); standing on
         * the referenced texel it has covered |pos(ref) - pc| when pos(ref) lies ahead (a
         * positive projection on J d; sideways drift of a texel-quantised pointer counts, so a
         * step through many tiny charts cannot wander further than its length) and nothing
         * when it lies behind (a pointer that misses backwards by a texel: a jump never
         * lengthens what is left). The rest goes on in the destination chart, in its texels:
         * divided by |J' d'| at ref. Measured in 3D, a step is as long on the surface as a
         * step inside one chart whatever the texel densities of the two charts (spot's seams
         * join texels 3 to 6 times apart in size) and whatever offset the pointer has. A
         * pointer names the texel nearest to the inner boundary next to P0, about a texel
         * behind P0's centre, so jumping there and stopping (the paper's case 2, P_dest =
         * ref(P_dest_hat)) would shorten the step by about a texel: case 2 continues as well.
         * Without a source Jacobian (a chart one texel thin there) the texel length past P0's
         * centre is carried over as it is. */
        float rem_dst = 0.0f, rem_src = 0.0f;
        float v[3], vd[3];
        if (has_src) texel_motion(sx, sy, dx, dy, v);
        const float lv = has_src ? norm3(v) : 0.0f;
        if (lv > 0.0f) {
            float pc[3], pr[3];
            pgt_march_position(a, cx, cy, pc);
            pos3(a, ref, pr);
            const float dp[3] = {pr[0] - pc[0], pr[1] - pc[1], pr[2] - pc[2]};
            const float covered = dot3(dp, v) > 0.0f ? norm3(dp) : 0.0f, l3 = rem * lv;
            const float rem3 = covered >= l3 ? 0.0f : l3 - covered;
            rem_src = rem3 / lv;
            if (has_ref) texel_motion(rx, ry, ndx, ndy, vd);
            const float ld = has_ref ? norm3(vd) : 0.0f;
            if (!(ld > 0.0f))
                rem_dst = rem_src; /* no destination Jacobian: same texel size */
            else if (ld * PGT_MARCH_MAX_LENGTH_RATIO > lv)
                rem_dst = rem3 / ld;
            else
                rem_dst = rem_src * PGT_MARCH_MAX_LENGTH_RATIO;
        } else {
            const float ox = (float)p0x + 0.5f - cx, oy = (float)p0y + 0.5f - cy;
            rem_src = rem - (ox * dx + oy * dy);
            if (!(rem_src > 0.0f)) rem_src = 0.0f;
            rem_dst = rem_src;
        }
        if (rem_dst > PGT_MARCH_MAX_LENGTH) rem_dst = PGT_MARCH_MAX_LENGTH;
        if (info) {
            info->jumps = jumps;
            info->last_pointer = pi, info->last_p0 = p0;
            info->remaining_src = rem_src, info->remaining_dst = rem_dst;
        }
        const float nl = sqrtf(ndx * ndx + ndy * ndy); /* keep d unit through many jumps */
        dx = ndx / nl, dy = ndy / nl;
        from = src + 1u, idx = dx, idy = dy; /* the no-bounce rule's memory */
        cx = (float)jr.u + 0.5f, cy = (float)jr.v + 0.5f;
        chart = (a->codes[ref] >> 2) - 1u;
        rem = rem_dst;
        if (!(rem > 0.0f)) break;
    }
    if (o && (o->mask || o->condition)) { /* external contexts at the destination */
        const uint32_t t = texel_at(a, cx, cy);
        const float thr = o->mask_threshold != 0.0f ? o->mask_threshold : PGT_MARCH_MASK_THRESHOLD;
        if (o->mask && o->mask[t] >= thr) return stop(info, PGT_MARCH_STOP_REJECTED);
        if (o->condition && !o->condition(o->condition_ctx, cx, cy, chart))
            return stop(info, PGT_MARCH_STOP_REJECTED);
    }
    s->x = cx, s->y = cy, s->dx = dx, s->dy = dy, s->chart = chart;
    s->from = from, s->in_dx = idx, s->in_dy = idy, s->bounces = nb;
    return event;
}

pgt_march_event pgt_march_step(const pgt_march_atlas *a, const pgt_march_options *o,
                               pgt_march_state *s, float length, float angle,
                               pgt_march_info *info) {
    assert(length > 0.0f && length <= PGT_MARCH_MAX_LENGTH);
    if (info) {
        info->jumps = info->searches = 0;
        info->last_pointer = info->last_p0 = MARCH_NONE;
        info->remaining_src = info->remaining_dst = 0.0f;
        info->stop = PGT_MARCH_STOP_NONE;
    }
    float dx = s->dx, dy = s->dy;
    if (angle != 0.0f) { /* the marching rule's own turn */
        const float c = cosf(angle), sn = sinf(angle), ndx = c * dx - sn * dy;
        dy = sn * dx + c * dy, dx = ndx;
    }
    const float tx = s->x + dx * length, ty = s->y + dy * length; /* P_dest_hat */
    if (code_of(a, texel_at(a, tx, ty)) == PGT_MARCH_CODE(PGT_TEXEL_INNER, s->chart) &&
        !(o && (o->mask || o->condition))) { /* case 1 without external contexts */
        s->x = tx, s->y = ty, s->dx = dx, s->dy = dy;
        return PGT_MARCH_INNER;
    }
    return step_crossing(a, o, s, length, dx, dy, MARCH_NONE, info);
}

/* ---- batches ------------------------------------------------------------------------------- */

/* A walker keeps its direction until a jump, so the texels it will read MARCH_PREFETCH_STEPS
 * steps ahead are known now. Requesting them early overlaps the cache misses of consecutive
 * steps (with positions about two new texel rows per step on a 16 MB atlas; hardware
 * prefetchers do not follow oblique walkers). Measured on cube_sphere_8 with positions (CPU
 * time, one thread, a shared 2-core VM: noisy): 8.3 M steps/s without, 15 with 4 steps ahead,
 * 16 with 8 or 16; human_neutral 14, 17, 19, 16. */
#define MARCH_PREFETCH_STEPS 8u

/* Requests what the step MARCH_PREFETCH_STEPS ahead reads: the code of the texel containing
 * (x, y) (the case test) and, when the batch fetches positions, the four texel records of the
 * bilinear footprint around it (pgt_march_position). Records the batch does not read are not
 * requested: they would evict the codes from the cache. The caller passes the atlas's fields as
 * locals: read through the atlas pointer they would be reloaded every step, as the step's stores
 * might alias them. (x, y) lies at most MARCH_PREFETCH_STEPS steps from a point of the image, so
 * its conversions to int32_t are defined (below); a point outside the image requests a wasted
 * line (prefetch_element) instead of testing bounds every step. */
_Static_assert(PGT_IMAGE_MAX_SIDE + 1ll + MARCH_PREFETCH_STEPS * (long long)PGT_MARCH_MAX_LENGTH <
                   INT32_MAX,
               "march_prefetch converts coordinates to int32_t");
#if defined(__GNUC__)
/* always_inline: GCC 12 deemed a function that only prefetched through __builtin_prefetch
 * pure and deleted its calls as dead code (before issue 4 no prefetch was issued at all);
 * prefetch_element's asm cannot be deleted so, and the prefetch helpers stay inline anyway */
__attribute__((always_inline))
#endif
static inline void
march_prefetch(const uint32_t *codes, const pgt_march_texel *texels, uint32_t w, float x, float y,
               int with_position) {
    /* unsigned arithmetic: a negative coordinate wraps, defined, to an index past the end */
    const uint32_t xi = (uint32_t)(int32_t)x, yi = (uint32_t)(int32_t)y;
    prefetch_element(codes, yi * w + xi, sizeof *codes);
    if (!with_position) return;
    const uint32_t i0 = (uint32_t)(int32_t)(x + 0.5f) - 1u, j0 = (uint32_t)(int32_t)(y + 0.5f) - 1u;
    const uint32_t t = j0 * w + i0;
    prefetch_element(texels, t, sizeof *texels);
    prefetch_element(texels, t + 1u, sizeof *texels);
    prefetch_element(texels, t + w, sizeof *texels);
    prefetch_element(texels, t + w + 1u, sizeof *texels);
}

/* Walkers a batch thread marches together, taking turns (see batch_range). Measured on pizza
 * against the same code with other groups (A/B in one process, below): 8 walkers 1.00-1.01x,
 * 64 walkers 0.98-0.99x (more of the cache goes to the group's requests). */
#define MARCH_GROUP 32u

typedef struct batch_ctx {
    const pgt_march_atlas *a;
    const pgt_march_options *o;
    float length;
    uint32_t steps;
    float *x, *y, *dx, *dy;
    uint32_t *chart, *taken;
    double *sum;
} batch_ctx;

/* The sum of the coordinates of the 3D position at (x, y): what a batch adds up per step. */
static inline double position_sum(const pgt_march_atlas *a, float x, float y) {
    float p[3];
    pgt_march_position(a, x, y, p);
    return (double)p[0] + (double)p[1] + (double)p[2];
}

/* A walker's case-1 steps in a batch turn (batch_range): the state they change, and where the
 * first step that leaves the chart would go (its destination, texel and code). */
typedef struct case1_walk {
    float x, y, tx, ty;
    uint32_t k, td, c; /* steps taken so far; the leaving step's texel and code */
    double acc;        /* the position sum */
} case1_walk;

/* Steps k = wk->k .. steps - 1 of `length` texels along (dx, dy) while each lands on an inner
 * texel of the walker's chart (code `inner`): pgt_march_step's case 1, with the requests
 * MARCH_PREFETCH_STEPS ahead. Its own function, specialised for with_position (below), so that
 * the loop keeps its state in registers: inside batch_range's many live values it spilled (7
 * loads from the stack a step). Measured as batch_range's turns (one process, medians of 20-30
 * pairs): without positions pizza 1.05x, spot 1.16x; with positions pizza 1.00x. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void
case1_steps(const pgt_march_atlas *a, float length, uint32_t steps, float dx, float dy,
            uint32_t inner, int with_position, case1_walk *wk) {
    const uint32_t *codes = a->codes, w = a->width;
    const pgt_march_texel *texels = a->texels;
    const float fw = (float)a->width, fh = (float)a->height;
    const float ahead = length * (float)MARCH_PREFETCH_STEPS;
    float x = wk->x, y = wk->y, tx = 0.0f, ty = 0.0f;
    uint32_t k = wk->k, td = MARCH_NONE, c = inner;
    double acc = wk->acc;
    for (; k < steps; ++k) {
        march_prefetch(codes, texels, w, x + dx * ahead, y + dy * ahead, with_position);
        tx = x + dx * length, ty = y + dy * length;
        td = texel_index(w, fw, fh, tx, ty);
        c = td == MARCH_NONE ? 0u : codes[td];
        if (c != inner) break;
        x = tx, y = ty; /* pgt_march_step's case 1 */
        if (with_position) acc += position_sum(a, x, y);
    }
    wk->x = x, wk->y = y, wk->tx = tx, wk->ty = ty;
    wk->k = k, wk->td = td, wk->c = c, wk->acc = acc;
}

#if defined(__GNUC__)
__attribute__((noinline))
#endif
static void
case1_steps_position(const pgt_march_atlas *a, float length, uint32_t steps, float dx, float dy,
                     uint32_t inner, case1_walk *wk) {
    case1_steps(a, length, steps, dx, dy, inner, 1, wk);
}

#if defined(__GNUC__)
__attribute__((noinline))
#endif
static void
case1_steps_plain(const pgt_march_atlas *a, float length, uint32_t steps, float dx, float dy,
                  uint32_t inner, case1_walk *wk) {
    case1_steps(a, length, steps, dx, dy, inner, 0, wk);
}

/* What a walker of a batch does in its next turn (batch_range). */
enum { WALK_STEP, WALK_POINTER, WALK_CROSS };

/* The first requests of a step that leaves its chart (case 1 failed at (tx, ty), texel td of
 * code c): P0, found as step_crossing finds it (the texel itself in case 2, the search in
 * cases 3 and 4), and prefetch_jump's rows. Returns P0, or MARCH_NONE when the step stops
 * there (a dead end, no indirection texel) and needs nothing more. */
static uint32_t prefetch_crossing(const pgt_march_atlas *a, const pgt_march_state *s, float tx,
                                  float ty, uint32_t td, uint32_t c) {
    uint32_t p0 = td, x, y;
    float t;
    if ((c >> 2) != s->chart + 1u) p0 = search_xy(a, s->chart, s->x, s->y, tx, ty, &t, &x, &y);
    if (p0 == MARCH_NONE || (a->codes[p0] & 3u) != PGT_TEXEL_INDIRECTION) return MARCH_NONE;
    prefetch_jump(a, p0, (uint32_t)s->y * a->width + (uint32_t)s->x);
    prefetch_landing(a, p0); /* the codes around P0 (pointer_candidates reads P0's) */
    return p0;
}

/* A thread marches its walkers in groups of MARCH_GROUP, taking turns. In a turn a walker takes
 * the steps that stay in its chart (case 1, nearly every step) one after another, its state in
 * locals (the state's address goes to step_crossing, so its fields would otherwise be stored
 * and reloaded every step), until a step leaves the chart. That step takes three turns. In the
 * first, the walker finds P0 and requests its jump records and its own texel's rows
 * (prefetch_crossing). In the second, it reads P0's pointer, by then in the cache, and requests the
 * texels around the texel it names: 5.1's candidates point near it, 5.2's Jacobian and the
 * remaining length read them, and the walker lands there. In the third it takes the step
 * (step_crossing). Between its turns the group's other walkers take theirs, so the two cache misses
 * in a row that a jump waits for (P0's jump record, then the records it points at, anywhere in the
 * atlas) overlap other walkers' work, as a GPU hides them behind other threads. Each walker's steps
 * are the same calls on the same state in the same order as pgt_march_step's, one walker after
 * another, so the results are the same bytes (test_march checks it on every shared UV atlas);
 * the one difference is that the third turn takes P0 from the first (prefetch_crossing's search,
 * on the same floats as step_crossing's: the case-1 loop's x + dx * length is step_crossing's
 * cx + dx * rem with rem = length; asserted in debug builds) instead of searching again. A
 * condition (pgt_march_options) sees its calls in that order too: with one, a group is one walker
 * (a condition may count its calls, as pgt_march_density_condition does). With a mask or a
 * condition every step is pgt_march_step's own, through step_crossing: no case-1 loop, no turns.
 * Measured against the loop it replaces (each walker's steps through pgt_march_step) as two builds
 * of this file loaded into one process, alternating on the same atlas and walkers (8192 x 500 steps
 * of 2 texels, one thread, medians of the ratios of 20-30 pairs; the AMD VM): pizza 1.07-1.09x
 * without positions and 1.06-1.08x with them, spot 1.48x, human_neutral 1.45x. Of pizza's gain the
 * case-1 loop alone gives 1.04-1.05x; the turns add 1.00-1.07x when the machine is quiet
 * and 1.09-1.15x when it is busy (its misses then take longer). */
static void batch_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    (void)worker;
    const batch_ctx *b = vctx;
    const pgt_march_atlas *a = b->a;
    const pgt_march_options *o = b->o;
    const uint32_t steps = b->steps, w = a->width;
    const uint32_t *codes = a->codes;
    const pgt_march_texel *texels = a->texels;
    const float length = b->length;
    const int with_position = b->sum != NULL, external = o && (o->mask || o->condition);
    const uint32_t group = o && o->condition ? 1u : MARCH_GROUP;
    pgt_march_state s[MARCH_GROUP];
    uint32_t taken[MARCH_GROUP], live[MARCH_GROUP], p0[MARCH_GROUP];
    unsigned char turn[MARCH_GROUP];
    double sum[MARCH_GROUP];
    for (uint32_t base = begin; base < end; base += group) {
        const uint32_t n = end - base < group ? end - base : group;
        uint32_t nlive = 0;
        for (uint32_t g = 0; g < n; ++g) {
            const uint32_t i = base + g;
            s[g] = (pgt_march_state){b->x[i], b->y[i], b->dx[i], b->dy[i], b->chart[i],
                                     0u,      0.0f,    0.0f,     0u};
            taken[g] = 0, sum[g] = 0.0, turn[g] = WALK_STEP;
            if (steps) live[nlive++] = g;
        }
        while (nlive) {
            uint32_t m = 0; /* the walkers that go on after this round */
            for (uint32_t j = 0; j < nlive; ++j) {
                const uint32_t g = live[j];
                pgt_march_state *q = &s[g];
                pgt_march_event ev;
                if (turn[g] == WALK_STEP) { /* case-1 steps until one leaves its chart */
                    const uint32_t inner = PGT_MARCH_CODE(PGT_TEXEL_INNER, q->chart);
                    case1_walk wk = {q->x, q->y, 0.0f, 0.0f, taken[g], MARCH_NONE, inner, sum[g]};
                    if (!external) { /* else every step is pgt_march_step's, in step_crossing */
                        if (with_position)
                            case1_steps_position(a, length, steps, q->dx, q->dy, inner, &wk);
                        else
                            case1_steps_plain(a, length, steps, q->dx, q->dy, inner, &wk);
                    }
                    q->x = wk.x, q->y = wk.y, taken[g] = wk.k, sum[g] = wk.acc;
                    if (wk.k == steps) continue; /* done */
                    if (wk.c == inner) {         /* with external contexts: pgt_march_step's path */
                        ev = step_crossing(a, o, q, length, q->dx, q->dy, MARCH_NONE, NULL);
                    } else {
                        p0[g] = prefetch_crossing(a, q, wk.tx, wk.ty, wk.td, wk.c);
                        turn[g] = p0[g] == MARCH_NONE ? WALK_CROSS : WALK_POINTER;
                        live[m++] = g;
                        continue;
                    }
                } else if (turn[g] == WALK_POINTER) {
                    const uint32_t t = pointer_of(a, p0[g]);
                    prefetch_destination(a, t);
                    prefetch_landing(a, t);
                    prefetch_targets(a, p0[g]);
                    turn[g] = WALK_CROSS;
                    live[m++] = g;
                    continue;
                } else {
                    ev = step_crossing(a, o, q, length, q->dx, q->dy, p0[g], NULL);
                    turn[g] = WALK_STEP;
                    /* With positions, the texels of the steps up to the case-1 loop's first
                     * request lie past the jump, where nothing requested them: requested here,
                     * they load while the group's other walkers take their turns. Measured as
                     * above with positions: pizza 1.11-1.13x, human_neutral 1.07x, spot 1.04x;
                     * without positions (the codes alone) 0.97-1.00x, so not then. */
                    if (with_position && ev != PGT_MARCH_STOP)
                        for (uint32_t k = 1; k < MARCH_PREFETCH_STEPS; ++k)
                            march_prefetch(codes, texels, w, q->x + q->dx * length * (float)k,
                                           q->y + q->dy * length * (float)k, 1);
                }
                if (ev == PGT_MARCH_STOP) continue; /* a walker stops at its first STOP */
                taken[g]++;
                if (with_position) sum[g] += position_sum(a, q->x, q->y);
                if (taken[g] < steps) live[m++] = g;
            }
            nlive = m;
        }
        for (uint32_t g = 0; g < n; ++g) {
            const uint32_t i = base + g;
            b->x[i] = s[g].x, b->y[i] = s[g].y, b->dx[i] = s[g].dx, b->dy[i] = s[g].dy;
            b->chart[i] = s[g].chart;
            if (b->taken) b->taken[i] = taken[g];
            if (b->sum) b->sum[i] = sum[g];
        }
    }
}

void pgt_march_batch(const pgt_march_atlas *a, const pgt_march_options *o, float length,
                     uint32_t steps, uint32_t count, float *x, float *y, float *dx, float *dy,
                     uint32_t *chart, uint32_t threads, uint32_t *out_taken, double *out_sum) {
    assert(length > 0.0f && length <= PGT_MARCH_MAX_LENGTH); /* as pgt_march_step */
    batch_ctx b = {a, o, length, steps, x, y, dx, dy, chart, out_taken, out_sum};
    /* a condition sees its calls in the walkers' order (march.h), so on one thread */
    pgt_parallel_for(count, o && o->condition ? 1u : threads ? threads : 1u, batch_range, &b);
}
