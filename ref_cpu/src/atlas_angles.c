/* pgt: atlas step 6, rotation of marching directions (paper 000 section 5.2, Fig. 6-7), and,
 * with --angles jacobian, the same angles fitted to the charts' Jacobians (the last section).
 *
 * The paper, for an indirection texel P0 of chart A pointing at texel Q of chart B:
 * - t1: "we start by scanning the one ring neighborhood of the current indirection pixel P0
 *   until we find the indirection pixel that follows an empty one. Then [...] we follow the K
 *   indirection pixels P_i and define t1 as the average of the vectors going from P0 to the
 *   visited pixels P_i." Here the path texels are A's outer-boundary texels (indirection and
 *   dead end), "empty" is any texel that is neither a path texel nor an inner texel of A.
 * - t2: the same walk from Q over B's inner-boundary texels, "empty" being any texel that is not
 *   an inner texel of B; rot is the angle from t1 to t2.
 *
 * What pgt computes (same K, same walks, three changes, measured with pgt's random marches,
 * tests/test_march.c real_random_marches, median turn at jumps with the atlas's rot, paper's
 * walk -> this one: spot 23.0 -> 19.2 degrees, bob 11.5 -> 6.7, human_neutral 13.6 -> 8.6,
 * pizza 35.1 -> 14.8):
 * 1. t1 walks K texels both ways from P0 (forward minus backward): a one-way walk along a
 *    curved boundary gives the chord, which leans by half the boundary's turn over K texels,
 *    and on a staircase boundary its K steps round to the stair; the centred sum cancels the
 *    lean and halves the rounding.
 * 2. t2 is made of the same texels' pointers: for every P_i of A's walk that points into B,
 *    t2 gets ptr(P_i) - Q with the sign t1 gets P_i - P0. B's own walk from Q can go round a
 *    different corner than A's (on pizza's charts of a few texels it mostly does); through the
 *    pointers both tangents describe the same piece of the seam.
 * 3. A check of what rot is for: the way out of A at P0, rotated by rot, must enter B at Q
 *    (see angle_rows). At the tip of a slit cut inside a chart and around the corners of
 *    charts a few texels wide, the tangents can come out reversed and a walker then bounces
 *    between P0 and Q for ever (long marches on spot: 2.9 % of the steps); when only the
 *    opposite direction enters B, rot is turned by pi (then 0 %, tests/test_march.c).
 * Where that leaves t1 or t2 zero (no texel of the walk points into B) the paper's one-way
 * walks decide (B's walk reversed, as A and B lie on opposite sides of the seam), and where
 * those cannot start either (an isolated texel) rot = 0.
 *
 * Walks: the ring is scanned clockwise on screen (E, SE, S, SW, W, NW, N, NE with y down) for
 * the forward walk and counter-clockwise for the backward one, starting after the texel the
 * walk came from; a step goes to the first path texel whose predecessor in that order is empty.
 * Forward walks every boundary with its own chart on the right (clockwise on screen).
 * rot = atan2(t1 x t2, t1 . t2) in texel coordinates (x right, y down); see atlas_build.h for
 * how a marcher applies it.
 *
 * Speed: every outer-boundary texel is a step of about 2 K walks, so its hits for each
 * direction (from the classes of its 8 neighbours relative to its own chart, the only chart an
 * outer walk through it can have) are computed once (step_rows), and the chart its pointer
 * points into comes from atlas_pointers (dest_chart); an outer walk step is a few bit
 * operations, and the rarer inner walks classify on the fly. Same walks, same texels. */
#include <math.h>
#include <stdlib.h>

#include "atlas_internal.h"

static const int32_t ring[8][2] = {{1, 0},  {1, 1},   {0, 1},  {-1, 1},
                                   {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};

typedef struct angle_ctx {
    pgt_image *atlas;
    const int32_t *chart;
    const uint8_t *kind;
    const float *outer_chart; /* the chart plane: the chart of an outer-boundary texel */
    int32_t W, H;
    uint32_t k;
    /* outer-boundary texels only (step_rows): */
    uint16_t *outer_hits;     /* bit j set when scan position j holds a path texel whose
                               * predecessor in the scan is empty: forward scan in the low byte,
                               * backward in the high byte */
    const int32_t *ptr_chart; /* the chart the pointer points into, -1 for a dead end */
} angle_ctx;

/* A texel's class in a walk over the inner-boundary texels of `chart`: 1 a path texel (an
 * inner-boundary texel of the chart), 0 empty (not an inner texel of the chart, or outside the
 * image), -1 neither (an inner texel of the chart off its boundary). */
static int inner_class(const angle_ctx *c, int32_t chart, int32_t x, int32_t y) {
    if (x < 0 || y < 0 || x >= c->W || y >= c->H) return 0;
    const size_t i = (size_t)y * (size_t)c->W + (size_t)x;
    if (c->chart[i] != chart) return 0;
    return (c->kind[i] & ATLAS_KIND_BOUNDARY_BIT) ? 1 : -1;
}

/* Follows up to k inner-boundary texels of `chart` from (x0, y0), forward (dir = +1, clockwise
 * ring scan) or backward (dir = -1); stores them in (px, py) and returns how many. */
static uint32_t walk_inner(const angle_ctx *c, int32_t chart, int32_t x0, int32_t y0, int dir,
                           int32_t *px, int32_t *py) {
    int32_t x = x0, y = y0;
    int back = -1; /* ring position, in scan order, of the texel the walk came from */
    uint32_t n = 0;
    for (uint32_t s = 0; s < c->k; ++s) {
        int found = -1;
        const int start = back < 0 ? 0 : back + 1;
        /* scan position j -> ring index: the same order forward, mirrored backward */
#define RING_AT(j) (dir > 0 ? (j) % 8 : (8 - (j) % 8) % 8)
        int prev_class =
            inner_class(c, chart, x + ring[RING_AT(start + 7)][0], y + ring[RING_AT(start + 7)][1]);
        for (int j = 0; j < 8; ++j) {
            const int i = RING_AT(start + j);
            const int cls = inner_class(c, chart, x + ring[i][0], y + ring[i][1]);
            if (cls == 1 && prev_class == 0) {
                found = (start + j) % 8;
                break;
            }
            prev_class = cls;
        }
        if (found < 0) break;
        x += ring[RING_AT(found)][0], y += ring[RING_AT(found)][1];
#undef RING_AT
        back = (found + 4) % 8;
        if (x == x0 && y == y0) break;
        px[n] = x, py[n] = y, n++;
    }
    return n;
}

/* The index of the lowest set bit of an 8-bit mask m != 0: (m & -m) * 0x17 puts a distinct
 * 3-bit code in bits 5..7 for each of the 8 single bits (a de Bruijn sequence). */
static uint32_t lowest_bit8(uint32_t m) {
    static const uint8_t index[8] = {0, 1, 2, 4, 7, 3, 6, 5};
    return index[((m & (0u - m)) * 0x17u) >> 5 & 7u];
}

/* The same walk over the outer-boundary texels of the chart of (x0, y0) (path texels: its
 * indirection and dead-end texels; empty: any texel that is neither a path texel nor an inner
 * texel of the chart), read from outer_hits, which step_rows filled with each texel's hits. */
static uint32_t walk_outer(const angle_ctx *c, int32_t x0, int32_t y0, int dir, int32_t *px,
                           int32_t *py) {
    int32_t x = x0, y = y0;
    uint32_t start = 0; /* scan position to start at: after the texel the walk came from */
    const uint32_t shift = dir > 0 ? 0u : 8u;
    uint32_t n = 0;
    for (uint32_t s = 0; s < c->k; ++s) {
        const uint32_t hit = c->outer_hits[(size_t)y * (size_t)c->W + (size_t)x] >> shift & 0xFFu;
        if (!hit) break;
        /* the first hit at or after start, cyclically */
        const uint32_t found =
            (start + lowest_bit8((hit >> start | hit << (8u - start)) & 0xFFu)) & 7u;
        const uint32_t i = dir > 0 ? found : (8u - found) & 7u;
        x += ring[i][0], y += ring[i][1];
        start = (found + 5u) & 7u; /* back = found + 4, start = back + 1 */
        if (x == x0 && y == y0) break;
        px[n] = x, py[n] = y, n++;
    }
    return n;
}

/* An 8-bit mask rotated left by one scan position. */
static uint32_t rotl8(uint32_t m) { return (m << 1 | m >> 7) & 0xFFu; }

/* An 8-bit mask of ring positions in backward scan order: bit j <- bit -j (mod 8). */
static uint32_t reverse_scan8(uint32_t m) {
    return (m & 0x11u) | (m & 0x02u) << 6 | (m & 0x80u) >> 6 | (m & 0x04u) << 4 | (m & 0x40u) >> 4 |
           (m & 0x08u) << 2 | (m & 0x20u) >> 2;
}

/* outer_hits of the outer-boundary texels of rows [y0, y1). The classes of the
 * 8 neighbours relative to the texel's own outer chart a (the only chart an outer walk through
 * it can have; walk_outer) as two masks: the chart plane holds a exactly at the
 * inner texels of a and at its outer-boundary texels (dead ends too), so a neighbour is a path
 * texel when the plane holds a and it is not inner, empty when the plane does not hold a (or it
 * lies outside the image). A hit is a path texel whose predecessor in the scan is empty: forward
 * scan position j is ring j, backward ring -j (mod 8), so the backward masks are the forward
 * ones reversed. */
static void step_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    angle_ctx *c = vctx;
    (void)worker;
    const float *plane = c->outer_chart;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; ++y)
        for (int32_t x = 0; x < c->W; ++x) {
            const size_t i = (size_t)y * (size_t)c->W + (size_t)x;
            const uint8_t k = c->kind[i] & (uint8_t)~ATLAS_KIND_BOUNDARY_BIT;
            if (k != PGT_TEXEL_INDIRECTION && k != PGT_TEXEL_DEAD_END) continue;
            const float a = plane[i];
            uint32_t path = 0, empty = 0;
            const int interior = x > 0 && y > 0 && x + 1 < c->W && y + 1 < c->H;
            for (uint32_t r = 0; r < 8; ++r) {
                const int32_t nx = x + ring[r][0], ny = y + ring[r][1];
                if (!interior && (nx < 0 || ny < 0 || nx >= c->W || ny >= c->H)) {
                    empty |= 1u << r;
                    continue;
                }
                const size_t j = (size_t)ny * (size_t)c->W + (size_t)nx;
                const uint32_t in_a = plane[j] == a,
                               inner = (c->kind[j] & (uint8_t)~ATLAS_KIND_BOUNDARY_BIT) ==
                                       PGT_TEXEL_INNER;
                empty |= (in_a ^ 1u) << r;
                path |= (in_a & (inner ^ 1u)) << r;
            }
            const uint32_t fwd = path & rotl8(empty),
                           bwd = reverse_scan8(path) & rotl8(reverse_scan8(empty));
            c->outer_hits[i] = (uint16_t)(fwd | bwd << 8);
        }
}

/* How far from the destination texel a rotated way out is followed to see that it enters the
 * destination chart: 1.5 texels reaches past the inner-boundary texel Q into the chart's
 * interior along any direction (a diagonal step is 1.41). */
#define ATLAS_ENTER_TEXELS 1.5
#define PGT_ATLAS_PI 3.14159265358979323846

/* Whether the texel ATLAS_ENTER_TEXELS from the centre of (qx, qy) along (ex, ey) is an inner
 * texel of chart b. */
static int enters(const angle_ctx *c, int32_t b, int32_t qx, int32_t qy, double ex, double ey) {
    const int32_t tx = (int32_t)floor(qx + 0.5 + ATLAS_ENTER_TEXELS * ex),
                  ty = (int32_t)floor(qy + 0.5 + ATLAS_ENTER_TEXELS * ey);
    if (tx < 0 || ty < 0 || tx >= c->W || ty >= c->H) return 0;
    return c->chart[(size_t)ty * (size_t)c->W + (size_t)tx] == b;
}

/* The way out of chart A at its outer texel (x, y): the sum of the steps from the texel's inner
 * 4-neighbours in A to it. 0 when it has none (it touches A only at a corner) or they cancel. */
static int way_out(const angle_ctx *c, int32_t x, int32_t y, double *ox, double *oy) {
    const int32_t a = (int32_t)c->outer_chart[(size_t)y * (size_t)c->W + (size_t)x];
    *ox = 0.0, *oy = 0.0;
    for (uint32_t k = 0; k < 8; k += 2) {
        const int32_t nx = x - ring[k][0], ny = y - ring[k][1];
        if (nx < 0 || ny < 0 || nx >= c->W || ny >= c->H) continue;
        if (c->chart[(size_t)ny * (size_t)c->W + (size_t)nx] != a) continue;
        *ox += ring[k][0], *oy += ring[k][1];
    }
    return *ox != 0.0 || *oy != 0.0;
}

static void angle_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    angle_ctx *c = vctx;
    (void)worker;
    float *rot = pgt_image_plane(c->atlas, 10);
    const float *kind_plane = pgt_image_plane(c->atlas, 7);
    const float *pu = pgt_image_plane(c->atlas, 8), *pv = pgt_image_plane(c->atlas, 9);
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; ++y)
        for (int32_t x = 0; x < c->W; ++x) {
            const size_t i = (size_t)y * (size_t)c->W + (size_t)x;
            if (kind_plane[i] != (float)PGT_TEXEL_INDIRECTION) continue; /* not a dead end */
            const int32_t qx = (int32_t)pu[i], qy = (int32_t)pv[i];
            const int32_t b = c->ptr_chart[i];
            int32_t wx[PGT_ATLAS_MAX_K], wy[PGT_ATLAS_MAX_K];
            /* sums of texel offsets: whole numbers, exact in int32 (at most 2 K of them) */
            int32_t t1x = 0, t1y = 0, t2x = 0, t2y = 0;
            for (int dir = -1; dir <= 1; dir += 2) {
                const uint32_t n = walk_outer(c, x, y, dir, wx, wy);
                for (uint32_t s = 0; s < n; ++s) {
                    const size_t j = (size_t)wy[s] * (size_t)c->W + (size_t)wx[s];
                    if (c->ptr_chart[j] != b) continue; /* b >= 0: not a dead end */
                    const int32_t rx = (int32_t)pu[j], ry = (int32_t)pv[j];
                    t1x += dir * (wx[s] - x), t1y += dir * (wy[s] - y);
                    t2x += dir * (rx - qx), t2y += dir * (ry - qy);
                }
            }
            if ((t1x == 0 && t1y == 0) || (t2x == 0 && t2y == 0)) {
                /* the paper's walks: A's forward, B's forward reversed */
                t1x = t1y = t2x = t2y = 0;
                uint32_t n = walk_outer(c, x, y, 1, wx, wy);
                for (uint32_t s = 0; s < n; ++s) t1x += wx[s] - x, t1y += wy[s] - y;
                n = walk_inner(c, b, qx, qy, 1, wx, wy);
                for (uint32_t s = 0; s < n; ++s) t2x -= wx[s] - qx, t2y -= wy[s] - qy;
            }
            if ((t1x == 0 && t1y == 0) || (t2x == 0 && t2y == 0)) {
                rot[i] = 0.0f;
                continue;
            }
            /* the products in double, as before: |t| <= 2 K * 2^14 keeps them exact */
            const double a1x = t1x, a1y = t1y, a2x = t2x, a2y = t2y;
            const double cross = a1x * a2y - a1y * a2x, dot = a1x * a2x + a1y * a2y;
            double r = atan2(cross, dot);
            /* The invariant rot exists for (atlas_build.h): a direction leaving A through P0
             * enters B at Q. Where the tangents cannot tell (the tip of a slit, a chart of a
             * few texels, whose walks go round a corner), it can come out reversed; a walker
             * then bounces between P0 and Q for ever. The way out of A is the sum of the steps
             * from P0's inner 4-neighbours in A to P0; rotated by rot it must reach an inner
             * texel of B ATLAS_ENTER_TEXELS from Q. When only the opposite direction does, the
             * angle is turned by pi. */
            double ox, oy;
            if (way_out(c, x, y, &ox, &oy)) {
                /* cos r and sin r are dot and cross over |t1| |t2| */
                const double len = sqrt(ox * ox + oy * oy) *
                                   sqrt((a1x * a1x + a1y * a1y) * (a2x * a2x + a2y * a2y));
                const double ex = (dot * ox - cross * oy) / len, ey = (cross * ox + dot * oy) / len;
                if (!enters(c, b, qx, qy, ex, ey) && enters(c, b, qx, qy, -ex, -ey))
                    r = r > 0.0 ? r - PGT_ATLAS_PI : r + PGT_ATLAS_PI;
            }
            rot[i] = (float)r;
        }
}

/* The context of an atlas's angle passes, without outer_hits. */
static angle_ctx angle_ctx_of(pgt_image *atlas, const int32_t *texel_chart, const uint8_t *kind,
                              const int32_t *dest_chart, uint32_t k) {
    const angle_ctx c = {atlas,
                         texel_chart,
                         kind,
                         pgt_image_plane(atlas, 6),
                         (int32_t)atlas->width,
                         (int32_t)atlas->height,
                         k,
                         NULL,
                         dest_chart};
    return c;
}

pgt_result atlas_angles(pgt_image *atlas, const int32_t *texel_chart, const uint8_t *kind,
                        const int32_t *dest_chart, uint32_t k, uint32_t threads, pgt_error *err) {
    angle_ctx c = angle_ctx_of(atlas, texel_chart, kind, dest_chart, k);
    c.outer_hits = malloc(sizeof(uint16_t) * (size_t)atlas->width * atlas->height);
    pgt_result r = PGT_OK;
    if (c.outer_hits) {
        atlas_parallel_rows(atlas->height, atlas->width, threads, step_rows, &c);
        atlas_parallel_rows(atlas->height, atlas->width, threads, angle_rows, &c);
    } else {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (angles)");
    }
    free(c.outer_hits);
    return r;
}

/* Squared distance from (px, py) to the segment a b of two texel-space points. */
static double segment_dist2(const float *a, const float *b, double px, double py) {
    return atlas_segment_dist2(a[0], a[1], b[0], b[1], px, py);
}

void atlas_crack_angles(pgt_image *atlas, const atlas_charts *charts, const float *tex,
                        const uint32_t *crack, const int32_t *dest_chart) {
    const int32_t W = (int32_t)atlas->width, H = (int32_t)atlas->height;
    const float *kind = pgt_image_plane(atlas, 7), *chart = pgt_image_plane(atlas, 6);
    const float *pu = pgt_image_plane(atlas, 8), *pv = pgt_image_plane(atlas, 9);
    float *rot = pgt_image_plane(atlas, 10);
    for (int32_t y = 0; y < H; ++y)
        for (int32_t x = 0; x < W; ++x) {
            const size_t t = (size_t)y * (size_t)W + (size_t)x;
            if (kind[t] != (float)PGT_TEXEL_INDIRECTION || dest_chart[t] != (int32_t)chart[t])
                continue;
            /* the seam whose crack the texel lies in, else the one whose fill it touches */
            uint32_t seam = crack[t] & ~ATLAS_CRACK_UNFILLED;
            for (uint32_t i = 0; i < 8 && !seam; ++i) {
                const int32_t nx = x + ring[i][0], ny = y + ring[i][1];
                if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
                const uint32_t v = crack[(size_t)ny * (size_t)W + (size_t)nx];
                if (ATLAS_CRACK_FILLED(v)) seam = v;
            }
            if (!seam) continue;
            /* copy 0 (a0 b0, h's side) and copy 1 (a1 b1, o's side) of the same 3D edge A B */
            const float *q[4];
            atlas_seam_copies(charts, tex, seam - 1u, q);
            const float *a0 = q[0], *b0 = q[1], *a1 = q[2], *b1 = q[3];
            const double qx = pu[t] + 0.5, qy = pv[t] + 0.5;
            const int to1 = segment_dist2(a1, b1, qx, qy) < segment_dist2(a0, b0, qx, qy);
            const float *s0 = to1 ? a0 : a1, *s1 = to1 ? b0 : b1; /* the side left */
            const float *d0 = to1 ? a1 : a0, *d1 = to1 ? b1 : b0; /* the side entered */
            const double t1x = (double)s1[0] - s0[0], t1y = (double)s1[1] - s0[1];
            const double t2x = (double)d1[0] - d0[0], t2y = (double)d1[1] - d0[1];
            rot[t] = (float)atan2(t1x * t2y - t1y * t2x, t1x * t2x + t1y * t2y);
        }
}

/* ---- angles fitted to the texel Jacobians (--angles jacobian) --------------------------------
 *
 * 5.2's tangents keep a heading's angle to the seam in texels. Where the two charts' UVs shear
 * differently along a seam (spot, pizza), the same texel angle is another 3D angle on each side,
 * and no rotation of the tangents can fix that. This fit keeps 5.2's form (one angle per
 * indirection texel, in rot; the marcher and the GPU kernels are unchanged) and chooses the
 * angle from the local maps of the two charts instead:
 * - J = dP/d(x, y) at the source side (the first inner 8-neighbour of P0 in A that has one) and
 *   J' at the destination (the pointer's texel Q, else its first inner 8-neighbour in B that has
 *   one), as finite differences of the P planes (central where both 4-neighbours are inner
 *   texels of the chart, else one-sided);
 * - the headings d that leave A through P0: PGT_ATLAS_FIT_HEADINGS of them around the way out
 *   (the mean of the directions from P0's inner 8-neighbours to it), spread as a uniform flux of
 *   walkers crosses a seam (density cos(phi) at angle phi from the way out: the k-th at
 *   phi = asin(2 (k + 1/2) / n - 1));
 * - heading d moves by J d in 3D; carried into B's tangent plane by the smallest rotation
 *   between the two planes' normals that is u. The angles theta with which J' R(theta) d turns
 *   from u by at most PGT_ATLAS_FIT_TURN_DEG form one arc (J'^+ maps the 3D cone around u to one
 *   cone of texel directions);
 * - rot = the middle of the common part of the most arcs (the first such start in heading
 *   order). Where no Jacobian exists (charts one texel thin), the planes face away from each
 *   other, or the fitted angle's way out does not enter B at Q (the invariant of atlas_build.h),
 *   5.2's angle stays.
 * Measured in tests/test_march.c real_random_marches. Doubles throughout: it is not a kernel, and
 * the test re-derives the same arcs in double. */

/* J' whose columns are closer to parallel than this squared sine (about 1e-6 radians) has no
 * usable inverse: a sliver texel. */
#define ATLAS_FIT_MIN_SINE2 1e-12

typedef struct fit_ctx {
    const angle_ctx *c;
    const float *P[3], *N[3], *pu, *pv, *kind; /* planes of the atlas */
    float *rot;
    double head_c[PGT_ATLAS_FIT_HEADINGS], head_s[PGT_ATLAS_FIT_HEADINGS];
    double bound_c, bound_s; /* cos and sin of PGT_ATLAS_FIT_TURN_DEG */
    uint32_t *row_fitted;    /* per row: texels whose rot was fitted */
} fit_ctx;

static int fit_inner(const angle_ctx *c, int32_t x, int32_t y, int32_t chart) {
    return x >= 0 && y >= 0 && x < c->W && y < c->H &&
           c->chart[(size_t)y * (size_t)c->W + (size_t)x] == chart;
}

/* dP/dx and dP/dy at the inner texel (x, y) of `chart`; 0 when an axis has no inner
 * 4-neighbour in the chart. */
static int fit_jacobian(const fit_ctx *f, int32_t chart, int32_t x, int32_t y, double jx[3],
                        double jy[3]) {
    const angle_ctx *c = f->c;
    const int l = fit_inner(c, x - 1, y, chart), r = fit_inner(c, x + 1, y, chart);
    const int u = fit_inner(c, x, y - 1, chart), d = fit_inner(c, x, y + 1, chart);
    if (!(l || r) || !(u || d)) return 0;
    const size_t W = (size_t)c->W;
    const size_t x0 = (size_t)y * W + (size_t)(x - l), x1 = (size_t)y * W + (size_t)(x + r);
    const size_t y0 = (size_t)(y - u) * W + (size_t)x, y1 = (size_t)(y + d) * W + (size_t)x;
    for (int k = 0; k < 3; ++k) {
        jx[k] = ((double)f->P[k][x1] - (double)f->P[k][x0]) / (double)(l + r);
        jy[k] = ((double)f->P[k][y1] - (double)f->P[k][y0]) / (double)(u + d);
    }
    return 1;
}

/* The unit normal of the plane of (jx, jy), turned to the side of the atlas normal at texel t;
 * 0 when it has no length. */
static int fit_normal(const fit_ctx *f, const double jx[3], const double jy[3], size_t t,
                      double n[3]) {
    n[0] = jx[1] * jy[2] - jx[2] * jy[1];
    n[1] = jx[2] * jy[0] - jx[0] * jy[2];
    n[2] = jx[0] * jy[1] - jx[1] * jy[0];
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double side = n[0] * f->N[0][t] + n[1] * f->N[1][t] + n[2] * f->N[2][t];
    if (!(len > 0.0)) return 0;
    const double s = side < 0.0 ? -1.0 / len : 1.0 / len;
    for (int k = 0; k < 3; ++k) n[k] *= s;
    return 1;
}

/* A monotone stand-in for the angle of (x, y) != 0 in [0, 4) (the "diamond angle"): the arcs
 * are compared by it, and only the chosen one's ends go through atan2. */
static double diamond(double x, double y) {
    if (y >= 0.0) return x >= 0.0 ? y / (x + y) : 1.0 - x / (y - x);
    return x < 0.0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
}

static double wrap4(double t) { return t < 0.0 ? t + 4.0 : t; }

/* The fitted angle of indirection texel (x, y) into *theta; 0 when there is none. */
static int fit_texel(const fit_ctx *f, int32_t x, int32_t y, double *theta) {
    static const int32_t d8[8][2] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1},
                                     {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
    const angle_ctx *c = f->c;
    const size_t W = (size_t)c->W, i = (size_t)y * W + (size_t)x;
    const int32_t a = (int32_t)c->outer_chart[i], b = c->ptr_chart[i];
    /* the way out: away from the inner 8-neighbours, each a unit direction */
    double ox = 0.0, oy = 0.0;
    for (int k = 0; k < 8; ++k)
        if (fit_inner(c, x + d8[k][0], y + d8[k][1], a)) {
            const double len = k < 4 ? 1.0 : sqrt(2.0);
            ox -= d8[k][0] / len, oy -= d8[k][1] / len;
        }
    const double ol = sqrt(ox * ox + oy * oy);
    if (!(ol > 0.0)) return 0;
    ox /= ol, oy /= ol;
    double jx[3], jy[3], rx[3], ry[3];
    int32_t sx = -1, sy = -1, have = 0;
    for (int k = 0; k < 8 && !have; ++k)
        if (fit_inner(c, x + d8[k][0], y + d8[k][1], a))
            sx = x + d8[k][0], sy = y + d8[k][1], have = fit_jacobian(f, a, sx, sy, jx, jy);
    if (!have) return 0;
    int32_t qx = (int32_t)f->pu[i], qy = (int32_t)f->pv[i];
    int have_r = fit_jacobian(f, b, qx, qy, rx, ry);
    for (int k = 0; k < 8 && !have_r; ++k)
        if (fit_inner(c, qx + d8[k][0], qy + d8[k][1], b) &&
            fit_jacobian(f, b, qx + d8[k][0], qy + d8[k][1], rx, ry))
            qx += d8[k][0], qy += d8[k][1], have_r = 1;
    if (!have_r) return 0;
    double ns[3], n[3];
    if (!fit_normal(f, jx, jy, (size_t)sy * W + (size_t)sx, ns) ||
        !fit_normal(f, rx, ry, (size_t)qy * W + (size_t)qx, n))
        return 0;
    /* the smallest rotation from ns to n (cos ct, sin st about the unit axis), applied to J */
    double axis[3] = {ns[1] * n[2] - ns[2] * n[1], ns[2] * n[0] - ns[0] * n[2],
                      ns[0] * n[1] - ns[1] * n[0]};
    const double ct = ns[0] * n[0] + ns[1] * n[1] + ns[2] * n[2];
    if (!(ct > 0.0)) return 0;
    const double st = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    double ax[3], ay[3];
    for (int col = 0; col < 2; ++col) {
        const double *v = col ? jy : jx;
        double *o = col ? ay : ax;
        if (!(st > 0.0)) {
            for (int k = 0; k < 3; ++k) o[k] = v[k];
            continue;
        }
        const double e[3] = {axis[0] / st, axis[1] / st, axis[2] / st};
        const double ev = e[0] * v[0] + e[1] * v[1] + e[2] * v[2];
        const double x3[3] = {e[1] * v[2] - e[2] * v[1], e[2] * v[0] - e[0] * v[2],
                              e[0] * v[1] - e[1] * v[0]};
        for (int k = 0; k < 3; ++k) o[k] = ct * v[k] + st * x3[k] + (1.0 - ct) * ev * e[k];
    }
    /* J'^+ = G^-1 J'^T with G = J'^T J' */
    double g11 = 0.0, g12 = 0.0, g22 = 0.0;
    for (int k = 0; k < 3; ++k) g11 += rx[k] * rx[k], g12 += rx[k] * ry[k], g22 += ry[k] * ry[k];
    const double det = g11 * g22 - g12 * g12;
    if (!(det > ATLAS_FIT_MIN_SINE2 * g11 * g22)) return 0;
    /* per heading: the arc's start and end relative to the heading, as diamond angles, and as
     * vectors for the two that end up chosen */
    double lo[PGT_ATLAS_FIT_HEADINGS], hi[PGT_ATLAS_FIT_HEADINGS];
    double lo_v[PGT_ATLAS_FIT_HEADINGS][2], hi_v[PGT_ATLAS_FIT_HEADINGS][2];
    for (uint32_t h = 0; h < PGT_ATLAS_FIT_HEADINGS; ++h) {
        const double d0 = f->head_c[h] * ox - f->head_s[h] * oy,
                     d1 = f->head_s[h] * ox + f->head_c[h] * oy;
        double u[3], nu[3];
        for (int k = 0; k < 3; ++k) u[k] = ax[k] * d0 + ay[k] * d1;
        const double un = u[0] * n[0] + u[1] * n[1] + u[2] * n[2];
        for (int k = 0; k < 3; ++k) u[k] -= un * n[k];
        nu[0] = n[1] * u[2] - n[2] * u[1];
        nu[1] = n[2] * u[0] - n[0] * u[2];
        nu[2] = n[0] * u[1] - n[1] * u[0];
        /* J'^+ u and J'^+ (n x u): the ends of the cone are J'^+ (cos u -+ sin n x u) */
        double bu1 = 0.0, bu2 = 0.0, bn1 = 0.0, bn2 = 0.0;
        for (int k = 0; k < 3; ++k)
            bu1 += rx[k] * u[k], bu2 += ry[k] * u[k], bn1 += rx[k] * nu[k], bn2 += ry[k] * nu[k];
        const double eu0 = (g22 * bu1 - g12 * bu2) / det, eu1 = (g11 * bu2 - g12 * bu1) / det;
        const double en0 = (g22 * bn1 - g12 * bn2) / det, en1 = (g11 * bn2 - g12 * bn1) / det;
        const double m0 = f->bound_c * eu0 - f->bound_s * en0,
                     m1 = f->bound_c * eu1 - f->bound_s * en1;
        const double p0 = f->bound_c * eu0 + f->bound_s * en0,
                     p1 = f->bound_c * eu1 + f->bound_s * en1;
        /* relative to d: turned by -angle(d) */
        const double rm0 = m0 * d0 + m1 * d1, rm1 = m1 * d0 - m0 * d1;
        const double rp0 = p0 * d0 + p1 * d1, rp1 = p1 * d0 - p0 * d1;
        if ((rm0 == 0.0 && rm1 == 0.0) || (rp0 == 0.0 && rp1 == 0.0)) return 0;
        /* the shorter way round from one end to the other */
        const int ccw = rm0 * rp1 - rm1 * rp0 >= 0.0;
        lo_v[h][0] = ccw ? rm0 : rp0, lo_v[h][1] = ccw ? rm1 : rp1;
        hi_v[h][0] = ccw ? rp0 : rm0, hi_v[h][1] = ccw ? rp1 : rm1;
        lo[h] = diamond(lo_v[h][0], lo_v[h][1]), hi[h] = diamond(hi_v[h][0], hi_v[h][1]);
    }
    /* the most arcs meet at some arc's start */
    uint32_t best = 0, best_s = 0, best_end = 0;
    for (uint32_t s = 0; s < PGT_ATLAS_FIT_HEADINGS; ++s) {
        uint32_t on = 0, end = s;
        double room = 4.0;
        for (uint32_t t = 0; t < PGT_ATLAS_FIT_HEADINGS; ++t) {
            if (wrap4(lo[s] - lo[t]) > wrap4(hi[t] - lo[t])) continue;
            on++;
            const double r = wrap4(hi[t] - lo[s]);
            if (r < room) room = r, end = t;
        }
        if (on > best) best = on, best_s = s, best_end = end;
    }
    const double t0 = atan2(lo_v[best_s][1], lo_v[best_s][0]);
    double w = atan2(hi_v[best_end][1], hi_v[best_end][0]) - t0;
    if (w < 0.0) w += 2.0 * PGT_ATLAS_PI;
    double t = t0 + 0.5 * w;
    if (t > PGT_ATLAS_PI) t -= 2.0 * PGT_ATLAS_PI;
    *theta = t;
    return 1;
}

static void fit_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    fit_ctx *f = vctx;
    const angle_ctx *c = f->c;
    (void)worker;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; ++y) {
        uint32_t fitted = 0;
        for (int32_t x = 0; x < c->W; ++x) {
            const size_t i = (size_t)y * (size_t)c->W + (size_t)x;
            if (f->kind[i] != (float)PGT_TEXEL_INDIRECTION) continue;
            double theta, ox, oy;
            if (!fit_texel(f, x, y, &theta)) continue;
            /* the invariant of atlas_build.h: the way out, turned by theta, enters B at Q */
            if (way_out(c, x, y, &ox, &oy)) {
                const double len = sqrt(ox * ox + oy * oy), ct = cos(theta), st = sin(theta);
                if (!enters(c, c->ptr_chart[i], (int32_t)f->pu[i], (int32_t)f->pv[i],
                            (ct * ox - st * oy) / len, (st * ox + ct * oy) / len))
                    continue;
            }
            f->rot[i] = (float)theta;
            fitted++;
        }
        f->row_fitted[y] = fitted;
    }
}

pgt_result atlas_fit_angles(pgt_image *atlas, const int32_t *texel_chart, const int32_t *dest_chart,
                            uint32_t threads, uint32_t *out_fitted, pgt_error *err) {
    const angle_ctx c = angle_ctx_of(atlas, texel_chart, NULL, dest_chart, 0);
    fit_ctx f = {&c,
                 {0},
                 {0},
                 pgt_image_plane(atlas, 8),
                 pgt_image_plane(atlas, 9),
                 pgt_image_plane(atlas, 7),
                 pgt_image_plane(atlas, 10),
                 {0},
                 {0},
                 0.0,
                 0.0,
                 NULL};
    for (int k = 0; k < 3; ++k)
        f.P[k] = pgt_image_plane(atlas, (uint32_t)k), f.N[k] = pgt_image_plane(atlas, 3u + k);
    for (uint32_t h = 0; h < PGT_ATLAS_FIT_HEADINGS; ++h) {
        const double phi = asin(2.0 * (h + 0.5) / PGT_ATLAS_FIT_HEADINGS - 1.0);
        f.head_c[h] = cos(phi), f.head_s[h] = sin(phi);
    }
    f.bound_c = cos(PGT_ATLAS_FIT_TURN_DEG * PGT_ATLAS_PI / 180.0);
    f.bound_s = sin(PGT_ATLAS_FIT_TURN_DEG * PGT_ATLAS_PI / 180.0);
    f.row_fitted = calloc(atlas->height ? atlas->height : 1u, sizeof(uint32_t));
    if (!f.row_fitted)
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (fitted angles)");
    atlas_parallel_rows(atlas->height, atlas->width, threads, fit_rows, &f);
    uint32_t n = 0;
    for (uint32_t y = 0; y < atlas->height; ++y) n += f.row_fitted[y];
    free(f.row_fitted);
    *out_fitted = n;
    return PGT_OK;
}
