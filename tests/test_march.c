/* Tests of the marcher (ref_cpu/src/march.c; paper 000, sec. 5).
 *
 * Part 1: synthetic atlases built here by hand with the exact atlas.h contract and analytic
 * answers: a plane split into two charts (the second rotated by 90 degrees in texel space, so
 * rot matters), three charts in a row (one step crosses two charts), eighteen narrow charts in a
 * row (the bound on crossings per step), a cylinder cut open inside one chart (a chart seamed to
 * itself), and broken pointer pairs that send walkers back where they came from (the no-bounce
 * rule). Pointers come from a brute-force version of the paper's rule (mean of the adjacent
 * inner texels, nearest inner-boundary texel of another chart, or of the same chart far away in
 * texture space) and rot from the charts' known texel frames.
 *
 * Part 2: real atlases from the builder (pgt_atlas_build): the cube-sphere's great circle, and
 * random marches on every UV mesh of the shared folder. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "gen.h"
#include "pgt/atlas.h"
#include "pgt/atlas_build.h"
#include "pgt/image.h"
#include "pgt/march.h"
#include "pgt/mesh_io.h"
#include "pgt/rng.h"
#include "test_scratch.h"
#include "test_util.h"

#define PI_F 3.14159265358979f
#define PI_D 3.14159265358979323846
#define NONE UINT32_MAX

/* ---- synthetic atlases ----------------------------------------------------------------------
 * A chart is a rectangle of inner texels [x0, x0+w) x [y0, y0+h) with local surface coordinates
 * (s, t) in texel units: orient 0 keeps (s, t) = (a, b) = (x - x0, y - y0); orient 1 stores the
 * chart turned by 90 degrees: (s, t) = (b, w - a) (a rotation, det +1: no mirroring). A plane
 * chart maps (s, t) to 3D ((s0 + s) SYN_H, (t0 + t) SYN_H, 0); a cylinder chart of
 * circumference w texels maps it to (R cos(2 pi s / w), R sin(2 pi s / w), t SYN_H). */

#define SYN_H 0.01f /* texel size in 3D */

/* Dead-end threshold of the brute-force pointers, in texel sizes: across the synthetic seams the
 * nearest candidate is 1 to 1.6 texels away (the band's texel plus the mean's offset), across
 * open borders it is far; 2.5 separates the two. */
#define SYN_DEAD_END 2.5f

/* A candidate in the source texel's own chart must be this far in texture space (atlas_build.h
 * PGT_ATLAS_SELF_SEAM_MIN_TEXELS). */
#define SYN_SELF_MIN 4.0f

enum { SYN_PLANE = 0, SYN_CYLINDER = 1 };

typedef struct syn_chart {
    int x0, y0, w, h, orient, shape;
    float s0, t0;
    float scale; /* plane: 3D size of a texel in units of SYN_H (0: 1) */
} syn_chart;

typedef struct syn_atlas {
    pgt_image img;
    pgt_atlas_channels ch;
    uint32_t w, h;
    const syn_chart *charts;
    int chart_count;
} syn_atlas;

static void syn_local(const syn_chart *c, float x, float y, float *s, float *t) {
    const float a = x - (float)c->x0, b = y - (float)c->y0;
    if (c->orient == 0)
        *s = a, *t = b;
    else
        *s = b, *t = (float)c->w - a;
}

/* 3D point of local (s, t) of chart c (extended analytically beyond the chart). */
static void syn_map(const syn_chart *c, float s, float t, float p[3]) {
    if (c->shape == SYN_PLANE) {
        const float k = c->scale > 0.0f ? c->scale : 1.0f;
        p[0] = (c->s0 + k * s) * SYN_H, p[1] = (c->t0 + k * t) * SYN_H, p[2] = 0.0f;
    } else {
        const float r = (float)c->w * SYN_H / (2.0f * PI_F), a = 2.0f * PI_F * s / (float)c->w;
        p[0] = r * cosf(a), p[1] = r * sinf(a), p[2] = t * SYN_H;
    }
}

/* The 3D point of texel-space (x, y) of chart c. */
static void syn_point(const syn_chart *c, float x, float y, float p[3]) {
    float s, t;
    syn_local(c, x, y, &s, &t);
    syn_map(c, s, t, p);
}

/* Local (s, t) direction of a texel direction: the chart's texel frame J (2 x 2). */
static void syn_frame(const syn_chart *c, float j[2][2]) {
    if (c->orient == 0)
        j[0][0] = 1, j[0][1] = 0, j[1][0] = 0, j[1][1] = 1;
    else /* ds = db, dt = -da */
        j[0][0] = 0, j[0][1] = 1, j[1][0] = -1, j[1][1] = 0;
}

static float *syn_plane(syn_atlas *s, uint32_t c) { return pgt_image_plane(&s->img, c); }

static int syn_inner_chart(const syn_atlas *s, int x, int y) {
    if (x < 0 || y < 0 || x >= (int)s->w || y >= (int)s->h) return -1;
    const float *kind = pgt_image_plane(&s->img, s->ch.kind),
                *chart = pgt_image_plane(&s->img, s->ch.chart);
    const size_t i = (size_t)y * s->w + (size_t)x;
    return kind[i] == PGT_TEXEL_INNER ? (int)chart[i] : -1;
}

/* Builds the atlas: inner texels from the charts, then every outer-boundary texel's pointer by
 * brute force (the paper's rule), its rot from the two charts' frames, or a dead end. */
static int syn_build(syn_atlas *s, uint32_t w, uint32_t h, const syn_chart *charts, int n) {
    static const char *const names[] = PGT_ATLAS_CHANNEL_NAMES;
    memset(s, 0, sizeof(*s));
    if (pgt_image_create(&s->img, w, h, PGT_ATLAS_CHANNEL_COUNT, names, NULL) != PGT_OK) return 0;
    if (pgt_atlas_channels_find(&s->img, "syn", &s->ch, NULL) != PGT_OK) return 0;
    s->w = w, s->h = h, s->charts = charts, s->chart_count = n;
    float *P[3] = {syn_plane(s, s->ch.px), syn_plane(s, s->ch.py), syn_plane(s, s->ch.pz)};
    float *N[3] = {syn_plane(s, s->ch.nx), syn_plane(s, s->ch.ny), syn_plane(s, s->ch.nz)};
    float *chart = syn_plane(s, s->ch.chart), *kind = syn_plane(s, s->ch.kind),
          *pu = syn_plane(s, s->ch.ptr_u), *pv = syn_plane(s, s->ch.ptr_v),
          *rot = syn_plane(s, s->ch.rot);
    for (size_t i = 0; i < (size_t)w * h; ++i) chart[i] = -1.0f, pu[i] = pv[i] = -1.0f;
    for (int c = 0; c < n; ++c)
        for (int y = charts[c].y0; y < charts[c].y0 + charts[c].h; ++y)
            for (int x = charts[c].x0; x < charts[c].x0 + charts[c].w; ++x) {
                const size_t i = (size_t)y * w + (size_t)x;
                float p[3];
                syn_point(&charts[c], (float)x + 0.5f, (float)y + 0.5f, p);
                for (int k = 0; k < 3; ++k) P[k][i] = p[k];
                if (charts[c].shape == SYN_PLANE) {
                    N[2][i] = 1.0f;
                } else {
                    const float r = sqrtf(p[0] * p[0] + p[1] * p[1]);
                    N[0][i] = p[0] / r, N[1][i] = p[1] / r;
                }
                chart[i] = (float)c, kind[i] = PGT_TEXEL_INNER;
            }
    /* inner-boundary texels: inner with a 4-neighbour that is not an inner texel of its chart */
    uint8_t *ib = calloc((size_t)w * h, 1);
    if (!ib) return 0;
    for (int y = 0; y < (int)h; ++y)
        for (int x = 0; x < (int)w; ++x) {
            const int c = syn_inner_chart(s, x, y);
            if (c < 0) continue;
            ib[(size_t)y * w + (size_t)x] =
                syn_inner_chart(s, x + 1, y) != c || syn_inner_chart(s, x - 1, y) != c ||
                syn_inner_chart(s, x, y + 1) != c || syn_inner_chart(s, x, y - 1) != c;
        }
    for (int y = 0; y < (int)h; ++y)
        for (int x = 0; x < (int)w; ++x) {
            const size_t i = (size_t)y * w + (size_t)x;
            if (kind[i] == PGT_TEXEL_INNER) continue;
            int c = -1, two = 0, cnt = 0;
            float p[3] = {0, 0, 0};
            for (int j = -1; j <= 1; ++j)
                for (int k = -1; k <= 1; ++k) {
                    const int cc = syn_inner_chart(s, x + k, y + j);
                    if (cc < 0) continue;
                    if (c >= 0 && cc != c) two = 1;
                    c = cc;
                }
            if (c < 0 || two) continue;
            for (int j = -1; j <= 1; ++j)
                for (int k = -1; k <= 1; ++k) {
                    const int xx = x + k, yy = y + j;
                    if (syn_inner_chart(s, xx, yy) != c || !ib[(size_t)yy * w + (size_t)xx])
                        continue;
                    const size_t q = (size_t)yy * w + (size_t)xx;
                    for (int e = 0; e < 3; ++e) p[e] += P[e][q];
                    cnt++;
                }
            for (int e = 0; e < 3; ++e) P[e][i] = p[e] / (float)cnt, p[e] /= (float)cnt;
            chart[i] = (float)c;
            float best = INFINITY;
            int bx = -1, by = -1;
            for (int yy = 0; yy < (int)h; ++yy)
                for (int xx = 0; xx < (int)w; ++xx) {
                    const size_t q = (size_t)yy * w + (size_t)xx;
                    const int cc = syn_inner_chart(s, xx, yy);
                    if (cc < 0 || !ib[q]) continue;
                    const float tdx = (float)(xx - x), tdy = (float)(yy - y);
                    if (cc == c && tdx * tdx + tdy * tdy <= SYN_SELF_MIN * SYN_SELF_MIN) continue;
                    const float d0 = P[0][q] - p[0], d1 = P[1][q] - p[1], d2 = P[2][q] - p[2];
                    const float d = d0 * d0 + d1 * d1 + d2 * d2;
                    if (d < best) best = d, bx = xx, by = yy;
                }
            if (bx < 0 || sqrtf(best) > SYN_DEAD_END * SYN_H) {
                kind[i] = PGT_TEXEL_DEAD_END;
                continue;
            }
            kind[i] = PGT_TEXEL_INDIRECTION;
            pu[i] = (float)bx, pv[i] = (float)by;
            /* rot: R = J_B^-1 J_A maps a source texel direction to the destination texel
             * direction with the same local (s, t) direction (the charts share the plane's or
             * the cylinder's (s, t) frame). */
            const int cb = syn_inner_chart(s, bx, by);
            float ja[2][2], jb[2][2];
            syn_frame(&charts[c], ja);
            syn_frame(&charts[cb], jb);
            /* J_B is a rotation: its inverse is its transpose. */
            const float r00 = jb[0][0] * ja[0][0] + jb[1][0] * ja[1][0];
            const float r10 = jb[0][1] * ja[0][0] + jb[1][1] * ja[1][0];
            rot[i] = atan2f(r10, r00);
        }
    free(ib);
    return 1;
}

static void syn_destroy(syn_atlas *s) { pgt_image_destroy(&s->img); }

static uint32_t syn_index(const syn_atlas *s, int x, int y) {
    return (uint32_t)y * s->w + (uint32_t)x;
}

/* Plane split in two: A (orient 0) covers global s in [0, 12), B (orient 1, turned by 90
 * degrees in texel space) covers s in [12, 24); both t in [0, 12). A's right outer column x = 15
 * points to B's first row: A(15, y) -> B(34 - y, 3), rot +pi/2; B's row y = 2 points back. */
static const syn_chart plane2_charts[2] = {
    {3, 3, 12, 12, 0, SYN_PLANE, 0.0f, 0.0f, 1.0f},
    {20, 3, 12, 12, 1, SYN_PLANE, 12.0f, 0.0f, 1.0f},
};

/* Three charts in a row, all orient 0: A s in [0, 12), B s in [12, 14) (two texels wide), C s
 * in [14, 26). */
static const syn_chart plane3_charts[3] = {
    {3, 3, 12, 12, 0, SYN_PLANE, 0.0f, 0.0f, 1.0f},
    {19, 3, 2, 12, 0, SYN_PLANE, 12.0f, 0.0f, 1.0f},
    {25, 3, 12, 12, 0, SYN_PLANE, 14.0f, 0.0f, 1.0f},
};

/* A cylinder of circumference 32 texels cut open inside one chart: the outer columns x = 2 and
 * x = 35 point to the chart's own inner columns 34 and 3. */
static const syn_chart cylinder_charts[1] = {
    {3, 3, 32, 10, 0, SYN_CYLINDER, 0.0f, 0.0f, 1.0f},
};

static int plane2(syn_atlas *s) { return syn_build(s, 40, 20, plane2_charts, 2); }

/* Marching helpers ---------------------------------------------------------------------------- */

static int view(pgt_march_atlas *v, const syn_atlas *s) {
    pgt_error err = {0};
    pgt_result r = pgt_march_atlas_create(v, &s->img, "syn", &err);
    if (r != PGT_OK) fprintf(stderr, "  %s\n", err.message);
    return r == PGT_OK;
}

static int near_f(float a, float b, float tol) { return fabsf(a - b) <= tol; }

/* The texels of view v whose ring mask (pgt_march_atlas.rings) is not march.h's definition,
 * derived here from the kind and chart planes of the image v was made of: bit k (the
 * neighbours in scan order) set for an inner texel of the texel's chart, bit 8 + k for an
 * indirection texel of it, nothing for neighbours outside the image and on background. */
static uint32_t rings_differ(const pgt_march_atlas *v, const pgt_image *img) {
    static const int dx[8] = {-1, 0, 1, -1, 1, -1, 0, 1}, dy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
    pgt_atlas_channels ch;
    if (pgt_atlas_channels_find(img, "rings", &ch, NULL) != PGT_OK) return UINT32_MAX;
    const float *kind = pgt_image_plane(img, ch.kind), *chart = pgt_image_plane(img, ch.chart);
    const int w = (int)img->width, h = (int)img->height;
    uint32_t differ = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t t = (size_t)y * (size_t)w + (size_t)x;
            unsigned expect = 0;
            for (int k = 0; k < 8 && kind[t] != (float)PGT_TEXEL_BACKGROUND; ++k) {
                const int nx = x + dx[k], ny = y + dy[k];
                if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                const size_t q = (size_t)ny * (size_t)w + (size_t)nx;
                if (chart[q] != chart[t]) continue;
                if (kind[q] == (float)PGT_TEXEL_INNER) expect |= 1u << k;
                if (kind[q] == (float)PGT_TEXEL_INDIRECTION) expect |= 1u << (8 + k);
            }
            differ += v->rings[t] != expect;
        }
    return differ;
}

/* Positions of the marcher are exact sums of small binary fractions here; 1e-4 texel covers
 * the float rounding of a handful of additions at coordinates below 64. */
#define POS_TOL 1e-4f

/* ---- part 1: cases ------------------------------------------------------------------------- */

static void test_view_and_start(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    CHECK(v.width == 40 && v.height == 20 && v.chart_count == 2);
    /* A's right outer column points into B's first row with rot +pi/2 (analytic, see above) */
    const uint32_t i = syn_index(&s, 15, 8);
    CHECK((v.texels[i].code & 3u) == PGT_TEXEL_INDIRECTION && (v.texels[i].code >> 2) == 1u);
    CHECK(v.jumps[i].u == 26u && v.jumps[i].v == 3u);
    CHECK(near_f(v.jumps[i].rot, 0.5f * PI_F, 1e-6f));
    CHECK((v.texels[syn_index(&s, 2, 8)].code & 3u) == PGT_TEXEL_DEAD_END);
    CHECK(rings_differ(&v, &s.img) == 0);
    /* (15, 8), A's outer column: inner texels of A left of it, indirection texels above and
     * below; nothing of B to its right */
    CHECK(v.rings[i] == (0x29u | 0x42u << 8));
    pgt_march_state st;
    pgt_error err = {0};
    CHECK(pgt_march_start(&v, 6.5f, 8.5f, 3.0f, 4.0f, &st, &err) == PGT_OK);
    CHECK(st.chart == 0 && near_f(st.dx, 0.6f, 1e-6f) && near_f(st.dy, 0.8f, 1e-6f));
    /* finite directions whose squares under- or overflow float: the same heading */
    CHECK(pgt_march_start(&v, 6.5f, 8.5f, 3e-30f, 4e-30f, &st, &err) == PGT_OK);
    CHECK(near_f(st.dx, 0.6f, 1e-6f) && near_f(st.dy, 0.8f, 1e-6f));
    CHECK(pgt_march_start(&v, 6.5f, 8.5f, -3e37f, 4e37f, &st, &err) == PGT_OK);
    CHECK(near_f(st.dx, -0.6f, 1e-6f) && near_f(st.dy, 0.8f, 1e-6f));
    CHECK(pgt_march_start(&v, 6.5f, 8.5f, 1e-45f, 0.0f, &st, &err) == PGT_OK);
    CHECK(st.dx == 1.0f && st.dy == 0.0f);
    CHECK(pgt_march_start(&v, 6.5f, 8.5f, INFINITY, 1.0f, &st, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_march_start(&v, 17.5f, 8.5f, 1.0f, 0.0f, &st, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err.message, "background") != NULL);
    CHECK(pgt_march_start(&v, 15.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_march_start(&v, -0.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_march_start(&v, 40.0f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_march_start(&v, 6.5f, 8.5f, 0.0f, 0.0f, &st, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_march_start(&v, 6.5f, 8.5f, NAN, 1.0f, &st, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_march_start(&v, NAN, 8.5f, 1.0f, 1.0f, &st, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    pgt_march_atlas_destroy(&v);
    pgt_march_atlas_destroy(&v); /* a zeroed view is a no-op */
    pgt_march_atlas_destroy(NULL);
    syn_destroy(&s);
}

/* Case 1: the destination is an inner texel of the same chart. */
static void test_case1_inner(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    pgt_march_state st;
    REQUIRE(pgt_march_start(&v, 6.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    pgt_march_info info;
    CHECK(pgt_march_step(&v, NULL, &st, 2.0f, 0.0f, &info) == PGT_MARCH_INNER);
    CHECK(near_f(st.x, 8.5f, POS_TOL) && near_f(st.y, 8.5f, POS_TOL) && st.chart == 0);
    CHECK(info.jumps == 0 && info.searches == 0 && info.stop == PGT_MARCH_STOP_NONE);
    /* the rule's own angle: turn by +pi/2 (towards +y) and step 3 */
    CHECK(pgt_march_step(&v, NULL, &st, 3.0f, 0.5f * PI_F, NULL) == PGT_MARCH_INNER);
    CHECK(near_f(st.x, 8.5f, POS_TOL) && near_f(st.y, 11.5f, POS_TOL));
    CHECK(near_f(st.dx, 0.0f, 1e-6f) && near_f(st.dy, 1.0f, 1e-6f));
    float p[3];
    pgt_march_position(&v, st.x, st.y, p);
    float es[3];
    syn_point(&plane2_charts[0], 8.5f, 11.5f, es);
    CHECK(near_f(p[0], es[0], 1e-6f) && near_f(p[1], es[1], 1e-6f) && p[2] == 0.0f);
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* Case 2: the destination is an indirection texel of the chart: jump to the referenced texel's
 * centre, nothing remains, the direction turns by rot (+pi/2 into B) and keeps its 3D course. */
static void test_case2_jump(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    pgt_march_state st;
    REQUIRE(pgt_march_start(&v, 13.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    pgt_march_info info;
    CHECK(pgt_march_step(&v, NULL, &st, 2.0f, 0.0f, &info) == PGT_MARCH_JUMP);
    CHECK(near_f(st.x, 26.5f, POS_TOL) && near_f(st.y, 3.5f, POS_TOL) && st.chart == 1);
    CHECK(near_f(st.dx, 0.0f, 1e-6f) && near_f(st.dy, 1.0f, 1e-6f));
    CHECK(info.jumps == 1 && info.searches == 0 && info.remaining_src == 0.0f);
    CHECK(info.last_p0 == syn_index(&s, 15, 8) && info.last_pointer == info.last_p0);
    /* a destination past P0's centre: the pointer's target stands for the inner boundary
     * next to P0 (global s = 12.5 here, 3 texels from s = 9.5), so 0.2 of the 3.2 texels
     * remain and are walked in B: the walker ends at s = 12.7 */
    pgt_march_state st2;
    REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st2, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, NULL, &st2, 3.2f, 0.0f, &info) == PGT_MARCH_JUMP);
    CHECK(near_f(info.remaining_dst, 0.2f, 1e-3f));
    CHECK(st2.chart == 1 && near_f(st2.x, 26.5f, POS_TOL) && near_f(st2.y, 3.7f, 1e-3f));
    /* next step in B: 2 texels along +s in 3D, as in A */
    float p0[3], p1[3];
    pgt_march_position(&v, st.x, st.y, p0);
    CHECK(pgt_march_step(&v, NULL, &st, 2.0f, 0.0f, NULL) == PGT_MARCH_INNER);
    pgt_march_position(&v, st.x, st.y, p1);
    CHECK(near_f((p1[0] - p0[0]) / SYN_H, 2.0f, 1e-3f) && near_f(p1[1], p0[1], 1e-6f));
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* Case 3: background at the destination: the search finds A's indirection texel (15, 8); the
 * step is 4.5 texels, 3 of them to the centre of (15, 8), so 1.5 remain in B (same texel size)
 * and the walker ends where the straight plane line ends: global s = 9.5 + 4.5 = 14. */
static void test_case3_search(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    pgt_march_state st;
    REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    pgt_march_info info;
    CHECK(pgt_march_step(&v, NULL, &st, 4.5f, 0.0f, &info) == PGT_MARCH_SEARCH);
    CHECK(info.jumps == 1 && info.searches == 1);
    CHECK(near_f(info.remaining_src, 1.5f, POS_TOL) && near_f(info.remaining_dst, 1.5f, 1e-3f));
    CHECK(st.chart == 1 && near_f(st.x, 26.5f, POS_TOL) && near_f(st.y, 5.0f, 1e-3f));
    float gs, gt;
    syn_local(&plane2_charts[1], st.x, st.y, &gs, &gt);
    CHECK(near_f(plane2_charts[1].s0 + gs, 14.0f, 1e-3f) && near_f(gt, 5.5f, 1e-3f));
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* Case 4: the destination is an inner texel (or an indirection texel) of another chart: treated
 * as background; 9 texels from s = 9.5 end at s = 18.5 in B. */
static void test_case4_other_chart(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    const float lengths[2] = {9.0f, 7.0f}; /* onto B's inner (21, 8); onto B's outer (19, 8) */
    for (int k = 0; k < 2; ++k) {
        pgt_march_state st;
        REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
        const uint32_t dest = (uint32_t)(12.5f + lengths[k]);
        CHECK((v.texels[syn_index(&s, (int)dest, 8)].code >> 2) == 2u); /* B's texel */
        pgt_march_info info;
        CHECK(pgt_march_step(&v, NULL, &st, lengths[k], 0.0f, &info) == PGT_MARCH_SEARCH);
        CHECK(info.last_p0 == syn_index(&s, 15, 8));
        float gs, gt;
        syn_local(&plane2_charts[1], st.x, st.y, &gs, &gt);
        CHECK_MSG(st.chart == 1 && near_f(plane2_charts[1].s0 + gs, 9.5f + lengths[k], 1e-3f) &&
                      near_f(gt, 5.5f, 1e-3f),
                  "length %g: at (%g, %g) chart %u, s %g", (double)lengths[k], (double)st.x,
                  (double)st.y, st.chart, (double)(plane2_charts[1].s0 + gs));
    }
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* The remaining length is carried over in 3D: B's texels are half as large as A's (24 texels
 * over global s in [12, 24)). A step of 4.5 A-texels from (s, t) = (9.5, 5.5) jumps to B's first
 * texel centre (12.25, 5.5 +- 0.25): it covered the 3D distance hypot(2.75, 0.25), and what is
 * left of 4.5 goes on in B at two B-texels per unit: it ends at s = 12.25 + 4.5 - hypot(...),
 * within 0.012 of the straight line's 14. */
static void test_remaining_length_3d(void) {
    static const syn_chart charts[2] = {
        {3, 3, 12, 12, 0, SYN_PLANE, 0.0f, 0.0f, 1.0f},
        {20, 3, 24, 24, 0, SYN_PLANE, 12.0f, 0.0f, 0.5f},
    };
    syn_atlas s;
    REQUIRE(syn_build(&s, 50, 30, charts, 2));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    /* A's row 8 (t = 5.5) meets B's rows 13 and 14 (t = 5.25, 5.75): the pointer takes one */
    const uint32_t pv = v.jumps[syn_index(&s, 15, 8)].v;
    CHECK(v.jumps[syn_index(&s, 15, 8)].u == 20u && (pv == 13u || pv == 14u));
    pgt_march_state st;
    REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    pgt_march_info info;
    CHECK(pgt_march_step(&v, NULL, &st, 4.5f, 0.0f, &info) == PGT_MARCH_SEARCH);
    const float left = 4.5f - hypotf(2.75f, 0.25f);
    CHECK(near_f(info.remaining_src, left, 1e-3f) &&
          near_f(info.remaining_dst, 2.0f * left, 1e-3f));
    float p[3];
    pgt_march_position(&v, st.x, st.y, p);
    CHECK_MSG(st.chart == 1 && near_f(p[0] / SYN_H, 12.25f + left, 1e-3f), "at s = %g",
              (double)(p[0] / SYN_H));
    /* then 2 B-texels per step: 1 unit of s, half of A's */
    const float s0 = p[0];
    CHECK(pgt_march_step(&v, NULL, &st, 2.0f, 0.0f, NULL) == PGT_MARCH_INNER);
    pgt_march_position(&v, st.x, st.y, p);
    CHECK(near_f((p[0] - s0) / SYN_H, 1.0f, 1e-3f));
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* One step crossing two charts (A -> the 2-texel chart B -> C): 6 texels from s = 9.5 land at
 * s = 15.5 in C after two searches. */
static void test_multi_jump(void) {
    syn_atlas s;
    REQUIRE(syn_build(&s, 42, 18, plane3_charts, 3));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    pgt_march_state st;
    REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    pgt_march_info info;
    CHECK(pgt_march_step(&v, NULL, &st, 6.0f, 0.0f, &info) == PGT_MARCH_SEARCH);
    CHECK(info.jumps == 2 && info.searches == 2);
    CHECK_MSG(st.chart == 2 && near_f(st.x, 26.5f, POS_TOL) && near_f(st.y, 8.5f, POS_TOL),
              "at (%g, %g) chart %u", (double)st.x, (double)st.y, st.chart);
    /* and back: 6 texels from C's s = 15.5 to A's s = 9.5 */
    st.dx = -1.0f;
    CHECK(pgt_march_step(&v, NULL, &st, 6.0f, 0.0f, &info) == PGT_MARCH_SEARCH);
    CHECK(info.jumps == 2);
    CHECK(st.chart == 0 && near_f(st.x, 12.5f, POS_TOL) && near_f(st.y, 8.5f, POS_TOL));
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* Dead ends stop the march (directly and through a search), the image is never left, and a
 * stopped step leaves the state as it was. */
static void test_dead_end_and_image_border(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    const float lengths[3] = {3.0f, 5.0f, 1000.0f}; /* onto (2, 8); background; far outside */
    for (int k = 0; k < 3; ++k) {
        pgt_march_state st, before;
        REQUIRE(pgt_march_start(&v, 5.5f, 8.5f, -1.0f, 0.0f, &st, NULL) == PGT_OK);
        before = st;
        pgt_march_info info;
        CHECK(pgt_march_step(&v, NULL, &st, lengths[k], 0.0f, &info) == PGT_MARCH_STOP);
        CHECK(info.stop == PGT_MARCH_STOP_DEAD_END);
        CHECK(memcmp(&st, &before, sizeof st) == 0);
    }
    CHECK(strcmp(pgt_march_stop_name(PGT_MARCH_STOP_DEAD_END), "dead end") == 0);
    CHECK(strcmp(pgt_march_event_name(PGT_MARCH_SEARCH), "search") == 0);
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* The search along ]P_cur, P_dest_hat[: the indirection texel and its parameter; a diagonal
 * exit through a chart corner finds the corner's outer texel; a segment that never leaves the
 * chart finds nothing. */
static void test_binary_search(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    float t = -1.0f;
    CHECK(pgt_march_search(&v, 0, 12.5f, 8.5f, 17.0f, 8.5f, &t) == syn_index(&s, 15, 8));
    /* the point found lies inside texel 15: x in [15, 16) */
    CHECK(12.5f + 4.5f * t >= 15.0f && 12.5f + 4.5f * t < 16.0f);
    for (int k = 1; k <= 40; ++k) { /* every length past the boundary, long ones too */
        const float len = 3.0f + 0.75f * (float)k * (float)k;
        CHECK(pgt_march_search(&v, 0, 12.5f, 8.5f, 12.5f + len, 8.5f, &t) == syn_index(&s, 15, 8));
    }
    const uint32_t corner = pgt_march_search(&v, 0, 10.5f, 10.5f, 18.5f, 18.5f, &t);
    CHECK(corner == syn_index(&s, 15, 15));
    CHECK(pgt_march_search(&v, 0, 5.5f, 5.5f, 8.5f, 9.5f, &t) == NONE && t == 0.0f);
    /* B's chart id: from a B texel upward onto its row-2 boundary (indirection into A) */
    CHECK(pgt_march_search(&v, 1, 26.5f, 6.5f, 26.5f, -3.0f, &t) == syn_index(&s, 26, 2));
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* 5.1: with P0's pointer (and its lower neighbour's) sent far away, the one-ring of P_near
 * offers (15, 7) whose target continues the 3D course; without best-pointer selection the
 * walker follows P0; with P_near == P_cur P0 is kept. */
static void test_best_pointer(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    float *pu = syn_plane(&s, s.ch.ptr_u), *pv = syn_plane(&s, s.ch.ptr_v);
    pu[syn_index(&s, 15, 8)] = 22.0f, pv[syn_index(&s, 15, 8)] = 3.0f; /* global t 9.5 */
    pu[syn_index(&s, 15, 9)] = 23.0f, pv[syn_index(&s, 15, 9)] = 3.0f; /* global t 8.5 */
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    uint32_t near = 0;
    /* from (6, 8): r = +s; c(15,7) = (9, -1), c(15,8) = (9, 4), c(15,9) = (9, 3) in texels */
    CHECK(pgt_march_best_pointer(&v, 0, 6.5f, 8.5f, syn_index(&s, 15, 8), &near) ==
          syn_index(&s, 15, 7));
    CHECK(near == syn_index(&s, 14, 8));
    CHECK(pgt_march_best_pointer(&v, 0, 14.5f, 8.5f, syn_index(&s, 15, 8), &near) ==
          syn_index(&s, 15, 8));
    CHECK(near == syn_index(&s, 14, 8));

    pgt_march_options with = {0}, without = {0};
    without.no_best_pointer = 1;
    pgt_march_state st;
    pgt_march_info info;
    REQUIRE(pgt_march_start(&v, 6.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, &with, &st, 9.0f, 0.0f, &info) == PGT_MARCH_JUMP);
    CHECK(info.last_p0 == syn_index(&s, 15, 8) && info.last_pointer == syn_index(&s, 15, 7));
    CHECK(near_f(st.x, 27.5f, POS_TOL) && near_f(st.y, 3.5f, POS_TOL));
    REQUIRE(pgt_march_start(&v, 6.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, &without, &st, 9.0f, 0.0f, &info) == PGT_MARCH_JUMP);
    CHECK(info.last_pointer == syn_index(&s, 15, 8));
    CHECK(near_f(st.x, 22.5f, POS_TOL) && near_f(st.y, 3.5f, POS_TOL));
    REQUIRE(pgt_march_start(&v, 14.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, &with, &st, 1.0f, 0.0f, &info) == PGT_MARCH_JUMP);
    CHECK(near_f(st.x, 22.5f, POS_TOL) && near_f(st.y, 3.5f, POS_TOL));
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* Angle (degrees) between two 3D vectors. */
static double angle_deg(const double a[3], const double b[3]) {
    const double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]),
                 lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    if (!(la > 0.0) || !(lb > 0.0)) return 0.0;
    double c = d / (la * lb);
    c = c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c;
    return acos(c) * 180.0 / PI_D;
}

/* 5.2: through the 90-degree-turned chart the 3D course is kept (straight lines in the plane at
 * several headings); with --no-rotation it turns by 90 degrees. */
static void test_rotation_keeps_3d_direction(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    const float headings[4] = {0.0f, 0.3f, -0.45f, 0.55f}; /* radians from +x */
    for (int mode = 0; mode < 3; ++mode) /* atlas rot, Jacobian rotation, no rotation */
        for (int k = 0; k < 4; ++k) {
            const int norot = mode == 2;
            /* without rotation a heading with dy < 0 keeps dy < 0 in B, i.e. heads back to
             * B's row 2 and into A: only the others are followed there */
            if (norot && headings[k] < 0.0f) continue;
            pgt_march_options o = {0};
            o.no_rotation = norot;
            o.rotation = mode == 1 ? PGT_MARCH_ROTATION_JACOBIAN : PGT_MARCH_ROTATION_ATLAS;
            pgt_march_state st;
            /* start so that the line meets A's right border (x = 15) near y = 8.5 */
            const float y0 = 8.5f - 5.5f * tanf(headings[k]);
            REQUIRE(pgt_march_start(&v, 9.5f, y0, cosf(headings[k]), sinf(headings[k]), &st,
                                    NULL) == PGT_OK);
            float start[3];
            pgt_march_position(&v, st.x, st.y, start);
            uint32_t crossed = 0, n = 0;
            float last[3];
            /* 3D heading of the 4 steps after the jump vs the heading before */
            for (; n < 30; ++n) {
                pgt_march_info info;
                const pgt_march_event e = pgt_march_step(&v, &o, &st, 1.0f, 0.0f, &info);
                if (e == PGT_MARCH_STOP) break;
                if (st.chart == 1)
                    crossed++;
                else
                    CHECK_MSG(crossed == 0, "heading %g: back in chart %u after the jump",
                              (double)headings[k], st.chart);
                if (crossed == 1) pgt_march_position(&v, st.x, st.y, last);
                if (crossed == 5) break;
            }
            REQUIRE(crossed == 5);
            float end[3];
            pgt_march_position(&v, st.x, st.y, end);
            const double before[3] = {cos(headings[k]), sin(headings[k]), 0.0};
            const double after[3] = {end[0] - last[0], end[1] - last[1], end[2] - last[2]};
            const double a = angle_deg(before, after);
            /* bilinear positions on a plane chart are exact up to float rounding (~1e-7 of a
             * 0.04 baseline): 0.01 degree is ~1e-4 rad */
            if (!norot)
                CHECK_MSG(a < 0.01, "mode %d heading %g: turned by %.4f degrees", mode,
                          (double)headings[k], a);
            else
                CHECK_MSG(a > 60.0, "heading %g, no rotation: turned by only %.1f degrees",
                          (double)headings[k], a);
        }
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* A chart seamed to itself: around the cylinder (32 texels) and back to the start, through
 * case 2 (step 1) and case 3 (step 4), both ways; every 3D point on the cylinder.
 *
 * The jump measures the length it covers in 3D along the chord of the last texel before the
 * seam, 2 pi / 32 = 11 degrees away from the tangent there: it leaves (1 - cos 11 deg) ~ 0.02 of
 * a texel too much or too little, measured 0.01 to 0.04. A real atlas turns by far less per
 * texel (the cube-sphere at 1024^2: 0.2 degree). */
#define CYLINDER_RETURN_TOL 0.05f
static void test_cylinder_self_seam(void) {
    syn_atlas s;
    REQUIRE(syn_build(&s, 40, 16, cylinder_charts, 1));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    CHECK(v.jumps[syn_index(&s, 35, 7)].u == 3u && v.jumps[syn_index(&s, 2, 7)].u == 34u);
    const float radius = 32.0f * SYN_H / (2.0f * PI_F);
    const float steps[2] = {1.0f, 4.0f}, dirs[2] = {1.0f, -1.0f};
    for (int k = 0; k < 2; ++k)
        for (int d = 0; d < 2; ++d) {
            pgt_march_state st;
            REQUIRE(pgt_march_start(&v, 5.5f, 7.5f, dirs[d], 0.0f, &st, NULL) == PGT_OK);
            const uint32_t n = (uint32_t)(32.0f / steps[k]);
            uint32_t jumps = 0;
            for (uint32_t i = 0; i < n; ++i) {
                pgt_march_info info;
                const pgt_march_event e = pgt_march_step(&v, NULL, &st, steps[k], 0.0f, &info);
                CHECK(e != PGT_MARCH_STOP);
                CHECK(e == PGT_MARCH_INNER || e == (k == 0 ? PGT_MARCH_JUMP : PGT_MARCH_SEARCH));
                jumps += info.jumps;
                float p[3];
                pgt_march_position(&v, st.x, st.y, p);
                /* bilinear positions lie on the chords between texel centres: inside the
                 * circle by at most the sagitta R (1 - cos(pi / 32)) */
                const float r = sqrtf(p[0] * p[0] + p[1] * p[1]);
                CHECK(r <= radius + 1e-6f && r >= radius * cosf(PI_F / 32.0f) - 1e-6f);
                CHECK(near_f(p[2], 4.5f * SYN_H, 1e-6f));
            }
            CHECK(jumps == 1 && st.chart == 0);
            CHECK_MSG(near_f(st.x, 5.5f, CYLINDER_RETURN_TOL) && near_f(st.y, 7.5f, POS_TOL),
                      "step %g dir %g: back at (%g, %g)", (double)steps[k], (double)dirs[d],
                      (double)st.x, (double)st.y);
        }
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* External contexts: a mask >= the threshold at the destination rejects the step (state
 * unchanged); below it the step goes on; a condition callback rejects chart 1. */
static int not_chart_1(void *ctx, float x, float y, uint32_t chart) {
    (void)x, (void)y;
    (*(int *)ctx)++;
    return chart != 1;
}

static void test_mask_and_condition(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    float *mask = calloc((size_t)s.w * s.h, sizeof(float));
    REQUIRE(mask);
    mask[syn_index(&s, 8, 8)] = 1.0f;
    mask[syn_index(&s, 10, 8)] = 0.49f;
    pgt_march_options o = {0};
    o.mask = mask;
    pgt_march_state st, before;
    pgt_march_info info;
    REQUIRE(pgt_march_start(&v, 6.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    before = st;
    CHECK(pgt_march_step(&v, &o, &st, 2.0f, 0.0f, &info) == PGT_MARCH_STOP);
    CHECK(info.stop == PGT_MARCH_STOP_REJECTED && memcmp(&st, &before, sizeof st) == 0);
    CHECK(pgt_march_step(&v, &o, &st, 4.0f, 0.0f, &info) == PGT_MARCH_INNER); /* 0.49 < 0.5 */
    o.mask_threshold = 0.4f;
    REQUIRE(pgt_march_start(&v, 6.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, &o, &st, 4.0f, 0.0f, &info) == PGT_MARCH_STOP);
    int calls = 0;
    pgt_march_options c = {0};
    c.condition = not_chart_1;
    c.condition_ctx = &calls;
    REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, &c, &st, 1.0f, 0.0f, &info) == PGT_MARCH_INNER);
    CHECK(pgt_march_step(&v, &c, &st, 4.5f, 0.0f, &info) == PGT_MARCH_STOP);
    CHECK(info.stop == PGT_MARCH_STOP_REJECTED && st.chart == 0 && calls == 2);
    free(mask);
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* Chart crossings per step are bounded: 18 charts two texels wide in a row (global s in [2k,
 * 2k + 2) for chart k, 4 texels of band between them). A 30-texel step from s = 0.5 crosses 15
 * borders and ends at s = 30.5; a 100-texel step would cross 17: PGT_MARCH_MAX_JUMPS (16) stops
 * it with the state unchanged. */
#define CHAIN_CHARTS 18
static void test_too_many_jumps(void) {
    syn_chart charts[CHAIN_CHARTS];
    for (int k = 0; k < CHAIN_CHARTS; ++k) {
        const syn_chart c = {3 + 6 * k, 3, 2, 12, 0, SYN_PLANE, 2.0f * (float)k, 0.0f, 1.0f};
        charts[k] = c;
    }
    syn_atlas s;
    REQUIRE(syn_build(&s, 6 * CHAIN_CHARTS + 3, 18, charts, CHAIN_CHARTS));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    pgt_march_state st, before;
    pgt_march_info info;
    REQUIRE(pgt_march_start(&v, 3.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, NULL, &st, 30.0f, 0.0f, &info) == PGT_MARCH_SEARCH);
    float gs, gt;
    syn_local(&charts[15], st.x, st.y, &gs, &gt);
    CHECK_MSG(info.jumps == 15 && st.chart == 15 && near_f(charts[15].s0 + gs, 30.5f, 1e-3f),
              "%u jumps, chart %u, s %g", info.jumps, st.chart, (double)(charts[15].s0 + gs));
    REQUIRE(pgt_march_start(&v, 3.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    before = st;
    CHECK(pgt_march_step(&v, NULL, &st, 100.0f, 0.0f, &info) == PGT_MARCH_STOP);
    CHECK(info.stop == PGT_MARCH_STOP_TOO_MANY_JUMPS && info.jumps == PGT_MARCH_MAX_JUMPS);
    CHECK(memcmp(&st, &before, sizeof st) == 0);
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* The no-bounce rule (march.h). A broken pointer pair that turns every walker around (rot = pi
 * both ways): from A's (12, 8) a long step jumps to B's (20, 8) heading -x, back to A's (14, 8)
 * heading +x (two texels on: not a bounce), then to B's (20, 8) again, where the walker stood
 * when it last jumped: a bounce, and so are all of 5.1's other candidates; and so is every jump
 * after it. The walker takes PGT_MARCH_MAX_BOUNCES of them and the next one stops the march,
 * with the state unchanged (before the rule, PGT_MARCH_MAX_JUMPS stopped it). */
static void test_bounce_pair(void) {
    static const syn_chart charts[2] = {
        {3, 3, 12, 12, 0, SYN_PLANE, 0.0f, 0.0f, 1.0f},
        {20, 3, 12, 12, 0, SYN_PLANE, 12.0f, 0.0f, 1.0f},
    };
    syn_atlas s;
    REQUIRE(syn_build(&s, 40, 20, charts, 2));
    float *rot = syn_plane(&s, s.ch.rot), *kind = syn_plane(&s, s.ch.kind);
    for (size_t i = 0; i < (size_t)s.w * s.h; ++i)
        if (kind[i] == PGT_TEXEL_INDIRECTION) rot[i] = PI_F;
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    for (int best = 0; best < 2; ++best) {
        pgt_march_options o = {0};
        o.no_best_pointer = !best;
        pgt_march_state st, before;
        REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
        CHECK(st.from == 0u && st.bounces == 0u);
        before = st;
        pgt_march_info info;
        CHECK(pgt_march_step(&v, &o, &st, 100.0f, 0.0f, &info) == PGT_MARCH_STOP);
        CHECK_MSG(info.stop == PGT_MARCH_STOP_BOUNCE && info.jumps == 2u + PGT_MARCH_MAX_BOUNCES,
                  "%s after %u jumps", pgt_march_stop_name(info.stop), info.jumps);
        CHECK(memcmp(&st, &before, sizeof st) == 0);
    }
    CHECK(strcmp(pgt_march_stop_name(PGT_MARCH_STOP_BOUNCE), "bounce") == 0);
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* The no-bounce rule across steps. plane2 with A's (15, 8) turned to rot -pi/2 (the walker
 * lands on B's (26, 3) heading -y, out of B) and B's (26, 2) sent back to A's (12, 8) with rot
 * +pi/2 (heading +x, out of A again): a step of 3 from A's (12, 8) ends on (26, 3); the next
 * one meets (26, 2), whose jump lands on (12, 8): a bounce. With 5.1 (rule 1), its candidates
 * around P_near = (26, 3), the walker's own texel (no r: ranked by the texel offset against d),
 * are (26, 2) itself, (25, 2) and (27, 2), the two latter tied and not bouncing (they name A's
 * (14, 9) and (14, 7), two texels from (12, 8)): the first in scan order, (25, 2), is taken
 * (heading -x: its rot is -pi/2 as built). Without 5.1 (rule 2) the bounce is taken and
 * counted. Turned back by the rule's angle instead, the walker crosses back through (26, 2) as
 * it asks: a bounce taken, not avoided. */
static void test_bounce_across_steps(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    float *rot = syn_plane(&s, s.ch.rot), *pu = syn_plane(&s, s.ch.ptr_u);
    rot[syn_index(&s, 15, 8)] = -0.5f * PI_F;
    rot[syn_index(&s, 26, 2)] = 0.5f * PI_F;
    pu[syn_index(&s, 26, 2)] = 12.0f; /* (14, 8) -> (12, 8) */
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    CHECK(v.jumps[syn_index(&s, 25, 2)].u == 14u && v.jumps[syn_index(&s, 25, 2)].v == 9u);
    CHECK(v.jumps[syn_index(&s, 27, 2)].u == 14u && v.jumps[syn_index(&s, 27, 2)].v == 7u);
    for (int k = 0; k < 2; ++k) {
        pgt_march_options o = {0};
        o.no_best_pointer = k == 1;
        pgt_march_state st;
        pgt_march_info info;
        REQUIRE(pgt_march_start(&v, 12.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
        CHECK(pgt_march_step(&v, &o, &st, 3.0f, 0.0f, &info) == PGT_MARCH_JUMP);
        CHECK(st.chart == 1 && near_f(st.x, 26.5f, POS_TOL) && near_f(st.y, 3.5f, POS_TOL));
        CHECK(near_f(st.dx, 0.0f, 1e-6f) && near_f(st.dy, -1.0f, 1e-6f));
        CHECK(st.from == syn_index(&s, 12, 8) + 1u && st.bounces == 0u);
        CHECK(st.in_dx == st.dx && st.in_dy == st.dy);
        CHECK(pgt_march_step(&v, &o, &st, 2.0f, 0.0f, &info) == PGT_MARCH_SEARCH);
        CHECK(info.last_p0 == syn_index(&s, 26, 2) && st.chart == 0);
        CHECK(st.from == syn_index(&s, 26, 3) + 1u);
        if (k == 0) {
            CHECK(info.last_pointer == syn_index(&s, 25, 2) && st.bounces == 0u);
            CHECK(near_f(st.dx, -1.0f, 1e-6f) && near_f(st.dy, 0.0f, 1e-6f));
        } else {
            CHECK(info.last_pointer == syn_index(&s, 26, 2) && st.bounces == 1u);
            CHECK(near_f(st.x, 12.5f, POS_TOL) && near_f(st.y, 8.5f, POS_TOL));
            CHECK(near_f(st.dx, 1.0f, 1e-6f) && near_f(st.dy, 0.0f, 1e-6f));
        }
    }
    /* marching back on purpose: original rots, a turn by pi in B */
    syn_destroy(&s);
    REQUIRE(plane2(&s));
    pgt_march_atlas_destroy(&v);
    REQUIRE(view(&v, &s));
    pgt_march_state st;
    pgt_march_info info;
    REQUIRE(pgt_march_start(&v, 13.5f, 8.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, NULL, &st, 2.0f, 0.0f, &info) == PGT_MARCH_JUMP);
    CHECK(st.chart == 1 && near_f(st.dy, 1.0f, 1e-6f));
    CHECK(pgt_march_step(&v, NULL, &st, 2.0f, PI_F, &info) == PGT_MARCH_SEARCH);
    CHECK(info.last_p0 == syn_index(&s, 26, 2) && info.last_pointer == info.last_p0);
    CHECK(st.chart == 0 && near_f(st.dx, -1.0f, 1e-5f) && near_f(st.dy, 0.0f, 1e-5f));
    CHECK(st.bounces == 1u);
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

/* Invalid atlases are refused with PGT_ERROR_PARSE and a message naming the texel. */
static void test_invalid_atlases(void) {
    typedef struct {
        const char *name, *expect;
        int x, y;
        int channel; /* 0 kind, 1 chart, 2 ptr.u, 3 P.x, 4 rot, 5 drop channel "rot" */
        float value;
    } bad_case;
    const bad_case cases[] = {
        {"kind 5", "kind 5", 6, 6, 0, 5.0f},
        {"kind 1.5", "kind 1.5", 6, 6, 0, 1.5f},
        {"inner without chart", "chart -1", 6, 6, 1, -1.0f},
        {"pointer outside", "is not a texel", 15, 8, 2, 40.0f},
        {"pointer to background", "not an inner texel", 15, 8, 2, 17.0f},
        {"pointer not whole", "is not a texel", 15, 8, 2, 26.5f},
        {"position NaN", "not finite", 6, 6, 3, NAN},
        {"rot infinite", "rot is not finite", 15, 8, 4, INFINITY},
        {"missing channel", "no channel 'rot'", 0, 0, 5, 0.0f},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; ++k) {
        syn_atlas s;
        REQUIRE(plane2(&s));
        const uint32_t chans[5] = {s.ch.kind, s.ch.chart, s.ch.ptr_u, s.ch.px, s.ch.rot};
        if (cases[k].channel < 5)
            syn_plane(&s, chans[cases[k].channel])[syn_index(&s, cases[k].x, cases[k].y)] =
                cases[k].value;
        else
            snprintf(s.img.names[s.ch.rot], PGT_IMAGE_NAME_SIZE, "%s", "rotation");
        pgt_march_atlas v;
        pgt_error err = {0};
        CHECK_MSG(pgt_march_atlas_create(&v, &s.img, "bad.exr", &err) == PGT_ERROR_PARSE, "%s",
                  cases[k].name);
        CHECK_MSG(strstr(err.message, cases[k].expect) && strstr(err.message, "bad.exr"),
                  "%s: message '%s'", cases[k].name, err.message);
        CHECK(v.texels == NULL && v.width == 0);
        syn_destroy(&s);
    }
    /* no inner texel at all */
    syn_atlas s;
    REQUIRE(plane2(&s));
    float *kind = syn_plane(&s, s.ch.kind);
    for (size_t i = 0; i < (size_t)s.w * s.h; ++i) kind[i] = 0.0f;
    pgt_march_atlas v;
    pgt_error err = {0};
    CHECK(pgt_march_atlas_create(&v, &s.img, "empty", &err) == PGT_ERROR_PARSE);
    CHECK(strstr(err.message, "no inner texel") != NULL);
    syn_destroy(&s);
}

/* Many random walkers on the synthetic atlases: never off the image, never off an inner texel
 * of their chart, and the batch gives the same bytes on 1 and 2 threads. */
static void test_random_walks_synthetic(void) {
    syn_atlas atlases[3];
    REQUIRE(plane2(&atlases[0]));
    REQUIRE(syn_build(&atlases[1], 42, 18, plane3_charts, 3));
    REQUIRE(syn_build(&atlases[2], 40, 16, cylinder_charts, 1));
    enum { WALKERS = 300, STEPS = 60 };
    for (int k = 0; k < 3; ++k) {
        pgt_march_atlas v;
        REQUIRE(view(&v, &atlases[k]));
        float x[2][WALKERS], y[2][WALKERS], dx[2][WALKERS], dy[2][WALKERS];
        uint32_t chart[2][WALKERS], taken[2][WALKERS];
        double sum[2][WALKERS];
        uint32_t bad = 0;
        for (uint32_t i = 0; i < WALKERS; ++i) {
            /* a random inner start texel and heading, from the counter-based generator */
            pgt_march_state st;
            uint32_t tries = 0;
            do {
                const float rx = pgt_rng_float(7, (uint32_t)k, 4ull * i + 4096ull * tries) *
                                 (float)v.width,
                            ry = pgt_rng_float(7, (uint32_t)k, 4ull * i + 4096ull * tries + 1) *
                                 (float)v.height;
                const float a = 2.0f * PI_F * pgt_rng_float(7, (uint32_t)k, 4ull * i + 2);
                tries++;
                if (pgt_march_start(&v, rx, ry, cosf(a), sinf(a), &st, NULL) == PGT_OK) break;
            } while (tries < 1000);
            REQUIRE(tries < 1000);
            const float len = 0.5f + 3.0f * pgt_rng_float(7, (uint32_t)k, 4ull * i + 3);
            for (int t = 0; t < 2; ++t)
                x[t][i] = st.x, y[t][i] = st.y, dx[t][i] = st.dx, dy[t][i] = st.dy,
                chart[t][i] = st.chart;
            for (uint32_t n = 0; n < STEPS; ++n) {
                if (pgt_march_step(&v, NULL, &st, len, 0.0f, NULL) == PGT_MARCH_STOP) break;
                const int inside =
                    st.x >= 0.0f && st.y >= 0.0f && st.x < (float)v.width && st.y < (float)v.height;
                if (!inside || v.texels[(uint32_t)st.y * v.width + (uint32_t)st.x].code !=
                                   PGT_MARCH_CODE(PGT_TEXEL_INNER, st.chart))
                    bad++;
            }
        }
        CHECK_MSG(bad == 0, "atlas %d: %u steps off an inner texel of their chart", k, bad);
        for (int t = 0; t < 2; ++t)
            pgt_march_batch(&v, NULL, 1.75f, STEPS, WALKERS, x[t], y[t], dx[t], dy[t], chart[t],
                            (uint32_t)t + 1u, taken[t], sum[t]);
        CHECK(memcmp(x[0], x[1], sizeof x[0]) == 0 && memcmp(y[0], y[1], sizeof y[0]) == 0);
        CHECK(memcmp(chart[0], chart[1], sizeof chart[0]) == 0);
        CHECK(memcmp(taken[0], taken[1], sizeof taken[0]) == 0);
        CHECK(memcmp(sum[0], sum[1], sizeof sum[0]) == 0);
        pgt_march_atlas_destroy(&v);
    }
    for (int k = 0; k < 3; ++k) syn_destroy(&atlases[k]);
}

/* ---- part 2: real atlases from the builder ------------------------------------------------ */

/* Builds the default atlas (1024^2, the builder's defaults) of a mesh and its marching view. */
static int real_atlas_angles(const pgt_mesh *m, const char *what, pgt_atlas_angles angles,
                             pgt_image *img, pgt_atlas_stats *st, pgt_march_atlas *v) {
    pgt_atlas_options o = {0};
    o.threads = 2;
    o.angles = angles;
    o.what = what;
    pgt_error err = {0};
    if (pgt_atlas_build(img, m, &o, st, &err) != PGT_OK) {
        fprintf(stderr, "  %s: pgt_atlas_build: %s\n", what, err.message);
        return 0;
    }
    if (pgt_march_atlas_create(v, img, what, &err) != PGT_OK) {
        fprintf(stderr, "  %s: %s\n", what, err.message);
        pgt_image_destroy(img);
        return 0;
    }
    return 1;
}

static int real_atlas(const pgt_mesh *m, const char *what, pgt_image *img, pgt_atlas_stats *st,
                      pgt_march_atlas *v) {
    return real_atlas_angles(m, what, PGT_ATLAS_ANGLES_TANGENTS, img, st, v);
}

static int walker_ok(const pgt_march_atlas *v, const pgt_march_state *st) {
    if (!(st->x >= 0.0f && st->y >= 0.0f && st->x < (float)v->width && st->y < (float)v->height))
        return 0;
    return v->texels[(uint32_t)st->y * v->width + (uint32_t)st->x].code ==
           PGT_MARCH_CODE(PGT_TEXEL_INNER, st->chart);
}

/* Hostile atlases: cube_sphere_8's 64^2 atlas with 1-12 channel values overwritten at random
 * texels (chart, kind, pointers, rot, positions; NaN, infinity, 1e30, out-of-range and
 * neighbours' values, sometimes a run along the row). pgt_march_atlas_create refuses most of
 * them; on every one it accepts (pointer cycles, pointers into far charts, arbitrary rot, holes
 * and islands), random walkers with random options, lengths up to PGT_MARCH_MAX_LENGTH, turns
 * and a random mask must keep march.h's contract: a STOP leaves the state unchanged, any other
 * step ends inside an inner texel of the walker's chart with a finite unit direction, and the
 * 3D position there is finite. (The sanitizer build runs this too: no out-of-bounds read.) */
#define HOSTILE_ATLASES 6000u
#define HOSTILE_WALKERS 24u
#define HOSTILE_STEPS 48u
/* |d|^2 - 1 of a walker's direction: renormalised after every jump in float32 */
#define HOSTILE_UNIT_TOL 1e-4f

/* The test's random numbers, one counter in sequence (each call its own statement or
 * initialiser, so the order is defined). */
static uint64_t hostile_counter;
static float hostile_u(void) { return pgt_rng_float(21, 0, hostile_counter++); }
static uint32_t hostile_r(uint32_t k) { return (uint32_t)(hostile_u() * (float)k) % k; }

/* Walker i's start: a random point and heading (seed, stream; counters 3 (i * 100000 + try)),
 * retried until pgt_march_start accepts it (the point lies in an inner texel), at most 100000
 * times. 1 on success. */
#define START_TRIES 100000u
static int random_walker_start(const pgt_march_atlas *v, uint32_t seed, uint32_t stream, uint32_t i,
                               pgt_march_state *st) {
    for (uint32_t tries = 0; tries < START_TRIES; ++tries) {
        const uint64_t c = 3ull * ((uint64_t)i * START_TRIES + tries);
        const float rx = pgt_rng_float(seed, stream, c) * (float)v->width,
                    ry = pgt_rng_float(seed, stream, c + 1) * (float)v->height,
                    a = 2.0f * PI_F * pgt_rng_float(seed, stream, c + 2);
        if (pgt_march_start(v, rx, ry, cosf(a), sinf(a), st, NULL) == PGT_OK) return 1;
    }
    return 0;
}

/* pgt_march_batch against its definition: each walker alone, one pgt_march_step (and
 * pgt_march_position) after another, until its first STOP. The batch (march.c batch_range,
 * with its own case-1 path, prefetches and walkers taking turns) must give the same bytes:
 * positions, directions, charts, steps taken and the sums of the positions. The steps use
 * options os, the batch ob (the same but for a condition's context; either may be NULL) and
 * `threads` threads. Returns the number of walkers that differ; *out_stopped gets those that
 * stopped before `steps`. */
static uint32_t batch_vs_steps(const pgt_march_atlas *v, const pgt_march_options *ob,
                               const pgt_march_options *os, float len, uint32_t steps,
                               uint32_t threads, const pgt_march_state *starts, uint32_t n,
                               uint32_t *out_stopped) {
    float *f = malloc((size_t)n * 8 * sizeof(float));
    uint32_t *u = malloc((size_t)n * 4 * sizeof(uint32_t));
    double *d = malloc((size_t)n * 2 * sizeof(double));
    if (!f || !u || !d) { /* every walker counts as differing */
        CHECK_MSG(0, "batch_vs_steps: out of memory for %u walkers", n);
        free(f), free(u), free(d);
        return n ? n : 1u;
    }
    float *bx = f, *by = f + n, *bdx = f + 2 * n, *bdy = f + 3 * n; /* the batch's walkers */
    float *sx = f + 4 * n, *sy = f + 5 * n, *sdx = f + 6 * n, *sdy = f + 7 * n; /* the steps' */
    uint32_t *bc = u, *btaken = u + n, *staken = u + 2 * n, *sc = u + 3 * n;
    double *bsum = d, *ssum = d + n;
    uint32_t differ = 0, stopped = 0;
    for (uint32_t i = 0; i < n; ++i) {
        pgt_march_state st = starts[i];
        bx[i] = st.x, by[i] = st.y, bdx[i] = st.dx, bdy[i] = st.dy, bc[i] = st.chart;
        uint32_t k = 0;
        double sum = 0.0;
        for (; k < steps; ++k) {
            if (pgt_march_step(v, os, &st, len, 0.0f, NULL) == PGT_MARCH_STOP) break;
            float p[3];
            pgt_march_position(v, st.x, st.y, p);
            sum += (double)p[0] + (double)p[1] + (double)p[2];
        }
        sx[i] = st.x, sy[i] = st.y, sdx[i] = st.dx, sdy[i] = st.dy;
        sc[i] = st.chart, staken[i] = k, ssum[i] = sum;
    }
    pgt_march_batch(v, ob, len, steps, n, bx, by, bdx, bdy, bc, threads, btaken, bsum);
    for (uint32_t i = 0; i < n; ++i) {
        differ += memcmp(&bx[i], &sx[i], sizeof(float)) || memcmp(&by[i], &sy[i], sizeof(float)) ||
                  memcmp(&bdx[i], &sdx[i], sizeof(float)) ||
                  memcmp(&bdy[i], &sdy[i], sizeof(float)) || bc[i] != sc[i] ||
                  btaken[i] != staken[i] || memcmp(&bsum[i], &ssum[i], sizeof(double));
        stopped += staken[i] < steps;
    }
    free(f), free(u), free(d);
    if (out_stopped) *out_stopped = stopped;
    return differ;
}

/* The res x res atlas of the generated cube_sphere_8 (six charts, input UVs kept). */
static int cube_sphere_8_atlas(uint32_t res, pgt_image *img) {
    pgt_mesh m;
    if (pgt_gen_cube_sphere(&m, 8, NULL) != PGT_OK) return 0;
    pgt_atlas_options ao = {0};
    ao.width = ao.height = res;
    ao.threads = 2;
    const int ok = pgt_atlas_build(img, &m, &ao, NULL, NULL) == PGT_OK;
    pgt_mesh_destroy(&m);
    return ok;
}

/* The batch's edges on cube_sphere_8's 64^2 atlas: 9000 walkers on 2 threads (enough for
 * pgt_parallel_for to use both) give the same bytes as pgt_march_step, without options and
 * with a density condition (which must keep its draw order: march.h runs such a batch on one
 * thread); 0 steps leave the walkers as they are; NULL outputs are allowed. */
#define EDGE_WALKERS 9000u
static void test_batch_edges(void) {
    pgt_image img;
    REQUIRE(cube_sphere_8_atlas(64, &img));
    pgt_march_atlas v;
    REQUIRE(pgt_march_atlas_create(&v, &img, "cube_sphere_8", NULL) == PGT_OK);
    static pgt_march_state starts[EDGE_WALKERS];
    uint32_t n = 0;
    for (uint32_t i = 0; i < EDGE_WALKERS; ++i)
        if (random_walker_start(&v, 41, 0, i, &starts[n])) n++;
    REQUIRE(n > 8192u);
    float *density = malloc((size_t)v.width * v.height * sizeof(float));
    REQUIRE(density);
    for (size_t t = 0; t < (size_t)v.width * v.height; ++t) density[t] = 0.98f;
    pgt_march_density d_batch = {density, v.width, v.height, 41, 1, 0}, d_steps = d_batch;
    pgt_march_options ob = {0}, os = {0};
    ob.condition = os.condition = pgt_march_density_condition;
    ob.condition_ctx = &d_batch, os.condition_ctx = &d_steps;
    uint32_t stopped = 0;
    CHECK(batch_vs_steps(&v, NULL, NULL, 1.5f, 40, 2, starts, n, NULL) == 0);
    CHECK(batch_vs_steps(&v, &ob, &os, 1.5f, 40, 2, starts, n, &stopped) == 0);
    CHECK(stopped > 0 && d_batch.draws == d_steps.draws);
    float x[3], y[3], dx[3], dy[3];
    uint32_t c[3], taken[3] = {7, 7, 7};
    for (int i = 0; i < 3; ++i)
        x[i] = starts[i].x, y[i] = starts[i].y, dx[i] = starts[i].dx, dy[i] = starts[i].dy,
        c[i] = starts[i].chart;
    pgt_march_batch(&v, NULL, 2.0f, 0, 3, x, y, dx, dy, c, 2, taken, NULL);
    for (int i = 0; i < 3; ++i)
        CHECK(taken[i] == 0 && x[i] == starts[i].x && y[i] == starts[i].y &&
              dx[i] == starts[i].dx && c[i] == starts[i].chart);
    pgt_march_batch(&v, NULL, 2.0f, 5, 3, x, y, dx, dy, c, 1, NULL, NULL); /* outputs NULL */
    pgt_march_state st = starts[0];
    for (int k = 0; k < 5; ++k)
        if (pgt_march_step(&v, NULL, &st, 2.0f, 0.0f, NULL) == PGT_MARCH_STOP) break;
    CHECK(x[0] == st.x && y[0] == st.y && c[0] == st.chart);
    free(density);
    pgt_march_atlas_destroy(&v);
    pgt_image_destroy(&img);
}

/* A chart in the image's first rows and columns (a file given to pgt march need not keep the
 * builder's band): left of column 0's centres and above row 0's, P is the nearest centres'
 * (bilinear weights outside the image drop out), inside it the bilinear interpolation of P,
 * here linear in x and y. The fast path once took x < 0.5 for a full 2 x 2 block at column -1
 * and read 2^32 texels away. */
static void test_position_image_border(void) {
    static const syn_chart corner[1] = {{0, 0, 6, 6, 0, SYN_PLANE, 0.0f, 0.0f, 1.0f}};
    syn_atlas s;
    REQUIRE(syn_build(&s, 8, 8, corner, 1));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    static const float at[][4] = {/* x, y, and the texel-space point whose P it is */
                                  {0.25f, 3.5f, 0.5f, 3.5f},
                                  {3.5f, 0.25f, 3.5f, 0.5f},
                                  {0.25f, 0.25f, 0.5f, 0.5f},
                                  {0.0f, 2.75f, 0.5f, 2.75f},
                                  {2.25f, 2.75f, 2.25f, 2.75f}};
    for (size_t k = 0; k < sizeof at / sizeof at[0]; ++k) {
        float p[3], q[3];
        pgt_march_position(&v, at[k][0], at[k][1], p);
        syn_point(&corner[0], at[k][2], at[k][3], q);
        CHECK_MSG(near_f(p[0], q[0], 1e-6f) && near_f(p[1], q[1], 1e-6f) && p[2] == 0.0f,
                  "at (%g, %g): (%g, %g, %g), want (%g, %g, 0)", (double)at[k][0], (double)at[k][1],
                  (double)p[0], (double)p[1], (double)p[2], (double)q[0], (double)q[1]);
    }
    /* and a march from there: inner steps along row 3 */
    pgt_march_state st;
    REQUIRE(pgt_march_start(&v, 0.25f, 3.5f, 1.0f, 0.0f, &st, NULL) == PGT_OK);
    CHECK(pgt_march_step(&v, NULL, &st, 0.5f, 0.0f, NULL) == PGT_MARCH_INNER);
    CHECK(near_f(st.x, 0.75f, 1e-6f) && st.y == 3.5f);
    pgt_march_atlas_destroy(&v);
    /* a position whose squared distances overflow float is refused, naming the texel */
    syn_plane(&s, s.ch.py)[3u * 8u + 2u] = 1e30f;
    pgt_error err = {0};
    CHECK(pgt_march_atlas_create(&v, &s.img, "big", &err) == PGT_ERROR_PARSE);
    CHECK_MSG(strstr(err.message, "big: texel (2, 3): position (") != NULL &&
                  strstr(err.message, "beyond +-1e+18") != NULL,
              "%s", err.message);
    syn_destroy(&s);
}

static void test_hostile_atlases(void) {
    pgt_image base;
    REQUIRE(cube_sphere_8_atlas(64, &base));
    const uint32_t W = base.width, H = base.height, n = W * H, C = base.channel_count;
    static const char *const names[] = PGT_ATLAS_CHANNEL_NAMES;
    float *mask = malloc(n * sizeof(float));
    REQUIRE(mask);
    uint64_t valid = 0, steps = 0, stops = 0, bad = 0, batch_walkers = 0, batch_differ = 0;
    uint64_t rings_bad = 0; /* atlases whose view's ring masks are not their definition */
    hostile_counter = 0;
    for (uint32_t i = 0; i < n; ++i) mask[i] = hostile_u() < 0.02f ? 1.0f : 0.0f;
    for (uint32_t a = 0; a < HOSTILE_ATLASES; ++a) {
        pgt_image img;
        REQUIRE(pgt_image_create(&img, W, H, C, names, NULL) == PGT_OK);
        memcpy(img.data, base.data, (size_t)n * C * sizeof(float));
        const uint32_t edits = 1u + hostile_r(12u);
        for (uint32_t e = 0; e < edits; ++e) {
            float *pl = pgt_image_plane(&img, hostile_r(C));
            const uint32_t t = hostile_r(n);
            float val;
            switch (hostile_r(9u)) {
            case 0:
                val = (float)hostile_r(W + 2u) - 1.0f;
                break; /* -1 .. W */
            case 1:
                val = NAN;
                break;
            case 2:
                val = INFINITY;
                break;
            case 3:
                val = (hostile_u() - 0.5f) * 1e30f;
                break;
            case 4:
                val = (float)hostile_r(5u);
                break; /* kinds, small charts */
            case 5:
                val = pl[hostile_r(n)];
                break; /* another texel's value */
            case 6:
                val = hostile_u() * 7.0f - 3.5f;
                break;
            case 7:
                val = (float)PGT_TEXEL_INDIRECTION;
                break;
            default:
                val = (float)(W - 1u);
                break;
            }
            const uint32_t run = hostile_r(4u) == 0 ? hostile_r(10u) : 1u;
            for (uint32_t j = 0; j < run && t + j < n; ++j) pl[t + j] = val;
        }
        pgt_march_atlas v;
        if (pgt_march_atlas_create(&v, &img, "hostile", NULL) != PGT_OK) {
            pgt_image_destroy(&img);
            continue;
        }
        valid++;
        rings_bad += rings_differ(&v, &img) != 0;
        { /* the batch on this atlas (its own random stream: the sequence above is unchanged) */
            pgt_march_state starts[HOSTILE_WALKERS];
            uint32_t m = 0;
            for (uint32_t w = 0; w < HOSTILE_WALKERS; ++w)
                if (random_walker_start(&v, 23, a, w, &starts[m])) m++;
            pgt_march_options o = {0};
            o.no_best_pointer = pgt_rng_float(24, a, 0) < 0.5f;
            o.no_rotation = pgt_rng_float(24, a, 1) < 0.25f;
            o.rotation = pgt_rng_float(24, a, 2) < 0.5f ? PGT_MARCH_ROTATION_JACOBIAN
                                                        : PGT_MARCH_ROTATION_ATLAS;
            if (pgt_rng_float(24, a, 3) < 0.25f) o.mask = mask;
            const float len = 0.01f + 20.0f * pgt_rng_float(24, a, 4);
            batch_differ += batch_vs_steps(&v, &o, &o, len, HOSTILE_STEPS, 1, starts, m, NULL);
            batch_walkers += m;
        }
        for (uint32_t w = 0; w < HOSTILE_WALKERS; ++w) {
            pgt_march_state s;
            if (!random_walker_start(&v, 22, a, w, &s)) continue;
            pgt_march_options o = {0};
            o.no_best_pointer = (int)hostile_r(2u);
            o.no_rotation = hostile_r(4u) == 0;
            o.rotation = hostile_r(2u) ? PGT_MARCH_ROTATION_JACOBIAN : PGT_MARCH_ROTATION_ATLAS;
            if (hostile_r(4u) == 0) o.mask = mask;
            for (uint32_t k = 0; k < HOSTILE_STEPS; ++k) {
                const float len =
                    hostile_r(20u) == 0
                        ? fminf(hostile_u() * PGT_MARCH_MAX_LENGTH + 1e-3f, PGT_MARCH_MAX_LENGTH)
                        : 0.01f + 20.0f * hostile_u();
                const float turn = hostile_r(3u) == 0 ? 4.0f * (hostile_u() - 0.5f) : 0.0f;
                const pgt_march_state before = s;
                steps++;
                if (pgt_march_step(&v, &o, &s, len, turn, NULL) == PGT_MARCH_STOP) {
                    stops++;
                    bad += memcmp(&s, &before, sizeof s) != 0;
                    break;
                }
                float p[3] = {0.0f, 0.0f, 0.0f};
                const int ok = walker_ok(&v, &s) && isfinite(s.dx) && isfinite(s.dy) &&
                               fabsf(s.dx * s.dx + s.dy * s.dy - 1.0f) <= HOSTILE_UNIT_TOL;
                if (ok) pgt_march_position(&v, s.x, s.y, p);
                if (!ok || !isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
                    bad++;
                    break;
                }
            }
        }
        pgt_march_atlas_destroy(&v);
        pgt_image_destroy(&img);
    }
    printf("  %u hostile atlases, %llu accepted by the view: %llu steps, %llu stops, %llu breaking "
           "the contract\n",
           HOSTILE_ATLASES, (unsigned long long)valid, (unsigned long long)steps,
           (unsigned long long)stops, (unsigned long long)bad);
    CHECK(bad == 0 && valid > HOSTILE_ATLASES / 10u && stops > 0 && steps > 100000u);
    printf("  the same atlases through pgt_march_batch: %llu walkers, %llu differ from "
           "pgt_march_step\n",
           (unsigned long long)batch_walkers, (unsigned long long)batch_differ);
    CHECK(batch_differ == 0 && batch_walkers > 10000u);
    printf("  their views' ring masks: %llu atlases differ from the definition\n",
           (unsigned long long)rings_bad);
    CHECK(rings_bad == 0);
    free(mask);
    pgt_image_destroy(&base);
}

/* Cube-sphere: the great circle z = 0 runs along texel rows/columns through the charts of +x,
 * +y, -x, -y (gen.c's cube_faces: u = y on +x, v = x on +y, v = y on -x, u = x on -y). Its
 * texel length is the sum of the four charts' extents along it, 2 (1/3 - 2 g) W + 2 (1/2 - 2 g)
 * H with g the gutter (the charts keep their input UVs: no repacking). The step S ~ 2 texels is
 * that length over a whole number N of steps (the jumps carry the remainder over in 3D units,
 * consistent with each chart's own texel length, so the texel lengths add up). After N steps
 * the walker is back at its start within 2 texels; every point lies within one texel size of
 * the unit sphere.
 *
 * n = 32: the flat triangles of the cube-sphere deviate from the sphere by up to ~(pi/2/n)^2/8 of
 * the radius (a chord's sagitta): 6e-3 at n = 8, above the 3.7e-3 texel size at 1024^2; 4e-4
 * at n = 32. */
#define GREAT_CIRCLE_TEXELS 2.0 /* at most this far from the start after N steps (the issue) */
static void test_real_cube_sphere_great_circle(void) {
    pgt_mesh m;
    REQUIRE(pgt_gen_cube_sphere(&m, 32, NULL) == PGT_OK);
    pgt_image img;
    pgt_atlas_stats st;
    pgt_march_atlas v;
    REQUIRE(real_atlas(&m, "cube_sphere_32", &img, &st, &v));
    CHECK(st.charts == 6 && !st.repacked && st.dead_end_texels == 0);
    const double g = PGT_GEN_CUBE_SPHERE_GUTTER;
    const double total = 2.0 * (1.0 / 3.0 - 2.0 * g) * v.width + 2.0 * (0.5 - 2.0 * g) * v.height;
    const uint32_t n = (uint32_t)lround(total / 2.0);
    const float step = (float)(total / n);
    /* start on +x (chart cell (0, 0): u in [g, 1/3 - g], v in [g, 1/2 - g]) at its centre, on
     * z = 0 (v at the middle of the chart), heading +u (towards +y) */
    const float x0 = (float)(v.width / 6.0), y0 = (float)((1.0 - 0.25) * v.height);
    const double texel = st.texel_size;
    for (int mode = 0; mode < 3; ++mode) { /* no best pointer; best pointer; and Jacobian */
        const int best = mode > 0;
        pgt_march_options o = {0};
        o.no_best_pointer = !best;
        o.rotation = mode == 2 ? PGT_MARCH_ROTATION_JACOBIAN : PGT_MARCH_ROTATION_ATLAS;
        pgt_march_state s;
        REQUIRE(pgt_march_start(&v, x0, y0, 1.0f, 0.0f, &s, NULL) == PGT_OK);
        float p[3];
        pgt_march_position(&v, s.x, s.y, p);
        CHECK(fabsf(p[0] - 1.0f) < 1e-3f && fabsf(p[2]) < 2.0f * (float)texel);
        uint32_t jumps = 0, stops = 0, bad = 0;
        double worst_r = 0.0, worst_z = 0.0;
        for (uint32_t i = 0; i < n; ++i) {
            pgt_march_info info;
            if (pgt_march_step(&v, &o, &s, step, 0.0f, &info) == PGT_MARCH_STOP) {
                stops++;
                break;
            }
            jumps += info.jumps;
            bad += !walker_ok(&v, &s);
            pgt_march_position(&v, s.x, s.y, p);
            const double r = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
            if (fabs(r - 1.0) > worst_r) worst_r = fabs(r - 1.0);
            if (fabs(p[2]) > worst_z) worst_z = fabs(p[2]);
        }
        const double dist = hypot(s.x - x0, s.y - y0);
        static const char *const names[3] = {"no-best-pointer", "best-pointer",
                                             "best-pointer, jacobian"};
        printf("  cube_sphere_32 %s: N = %u steps of %.4f texels, %u jumps, back within %.2f "
               "texels; max |r - 1| = %.2e, max |z| = %.2e (texel %.2e)\n",
               names[mode], n, (double)step, jumps, dist, worst_r, worst_z, texel);
        CHECK(stops == 0 && bad == 0 && jumps == 4 && s.chart == 0);
        CHECK_MSG(dist <= GREAT_CIRCLE_TEXELS, "%.2f texels from the start", dist);
        CHECK_MSG(worst_r <= texel, "a point %.2e off the unit sphere", worst_r);
        /* and it stayed on the great circle (z = 0): each jump lands on a texel centre, up to
         * half a texel across the path, and the pointers themselves are texel-quantised. Not
         * with the Jacobian rotation: the cube's rot is exactly a multiple of 90 degrees, while
         * finite differences at the seam (one-sided, across the gnomonic map's steepest part)
         * turn the path by ~0.5 degree, 3 texels off z = 0 after a face (measured 1.1e-2) */
        if (mode < 2)
            CHECK_MSG(worst_z <= 2.0 * texel, "a point %.2e off the plane z = 0", worst_z);
    }
    pgt_march_atlas_destroy(&v);
    pgt_image_destroy(&img);
    pgt_mesh_destroy(&m);
}

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median_of(double *v, size_t n) {
    if (!n) return 0.0;
    qsort(v, n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Angle (degrees) between a and b after removing their components along the unit normal nrm:
 * the turn within the tangent plane (the normal curvature of the surface is not a turn). */
static double tangent_turn_deg(const double a[3], const double b[3], const float nrm[3]) {
    double pa[3], pb[3];
    const double da = a[0] * nrm[0] + a[1] * nrm[1] + a[2] * nrm[2],
                 db = b[0] * nrm[0] + b[1] * nrm[1] + b[2] * nrm[2];
    for (int k = 0; k < 3; ++k) pa[k] = a[k] - da * nrm[k], pb[k] = b[k] - db * nrm[k];
    return angle_deg(pa, pb);
}

/* Random marches: RANDOM_MARCHES walkers from seeded random inner texels and headings, steps of
 * RANDOM_STEP_TEXELS. 4 texels: a pointer is quantised to a texel, so shorter steps measure
 * mostly that quantisation (at 2 texels the median turn at pizza's jumps is 10.3 degrees, at 4
 * it is 8.3); the paper's Fig. 4 steps are several texels long too. */
#define RANDOM_MARCHES 3000u
#define RANDOM_STEPS 100u
#define RANDOM_STEP_TEXELS 4.0f

/* A jump step is compared with the median of up to this many inner steps before it (same
 * march): they are in the chart the step starts from, whose texel size sets its 3D length.
 * The steps after it lie in the destination chart, whose texels may be several times larger
 * or smaller in 3D (spot's seams join texels 3 to 6 times apart in size): marching in image
 * space changes the 3D step there, by design. */
#define JUMP_NEIGHBOURS 3u

/* Jump-step checks need this many jumps to mean anything (ogre is one chart with no seam). */
#define MIN_JUMPS_CHECKED 100u

/* The comparison of 5.1's picks that change the destination chart needs this many of them: a
 * median of fewer is a handful of corners (bob's and human's atlases give 0 to 2 in 3000
 * marches; spot 19 to 30, the Voronoi atlases 22 to 35, pizza about 200). */
#define MIN_CHART_PAIRS 15u

/* Jump steps whose 3D length is within [0.5, 2] x the median of the inner steps before them.
 * Not all: a pointer names the nearest inner-boundary texel to the outer texel's 3D point and
 * may miss by up to the dead-end threshold (4 texel sizes, atlas_build.h), which is a step's
 * length; pizza's 4740 charts include ~2000 of a few texels each. Measured with 3000 x 100
 * steps of 4 texels, best pointer, either rotation: spot 94.1 to 94.4 %, bob 99.4 to 99.5 %,
 * human 98.6 to 98.9 %, pizza 96.1 to 96.3 % (93.0 to 94.2 and 89 % with earlier atlas builders);
 * 0.85 leaves room for atlas-builder changes. */
#define JUMP_LENGTH_MIN_FRACTION 0.85

/* A walker is stuck when STUCK_WINDOW consecutive steps all stay within 2 of its median inner
 * step length (3D) of the window's first point: steps of 4 texels cannot do that except by
 * bouncing between two pointers that send each other back (found on spot's slit tips, where a
 * reversed rot trapped 72 % of one long march's steps). At most STUCK_MAX_SHARE of the steps may
 * lie in such windows: measured after the fix in atlas_angles.c (the way out of A must enter B),
 * long marches of spot, bob, human: 0 (before it: 2.9 %, 1.0 %, 1.2 %); pizza's tiny charts
 * trapped 46 % of its long marches' steps (1.3 to 2.4 % of the short ones') until the marcher's
 * no-bounce rule (march.h): 0.07 % (0.08 to 0.23 %) with it. */
#define STUCK_WINDOW 16u
#define STUCK_MAX_SHARE 0.01
/* ...and crosses a chart border (a jump or a search) at least this often: a walker in a region
 * the parametrization shrinks (ogre's) moves little in 3D without being trapped. */
#define STUCK_MIN_CROSSINGS 4u
/* Long marches: LONG_MARCHES walkers of LONG_STEPS steps of LONG_STEP_TEXELS (pgt bench
 * march's step). */
#define LONG_MARCHES 256u
#define LONG_STEPS 4000u
#define LONG_STEP_TEXELS 2.0f
/* The issue's bound on the median turn at jumps. */
#define JUMP_TURN_MEDIAN_DEG 10.0

typedef struct walk_result {
    uint32_t marches, steps, stops, bad, jump_steps, len_out, stuck;
    double median_turn_jump, median_turn_inner;
    uint32_t turn_count;
    /* jumps where best-pointer selection picked another texel than P0: the turn with the
     * selection and, replayed from the same state, without it (a paired comparison; the
     * marches themselves diverge after the first differing jump) */
    uint32_t pairs, pairs_lower, pairs_higher; /* and how many turn less / more with it */
    double median_pair_best, median_pair_without;
    /* the pairs where the selection's texel points into another chart than P0 does (5.1's
     * purpose: "the referenced chart might not be the best one to continue the propagation") */
    uint32_t chart_pairs;
    double median_chart_best, median_chart_without;
} walk_result;

/* The chart (code >> 2) of the texel indirection texel t points to. */
static uint32_t pointer_chart(const pgt_march_atlas *v, uint32_t t) {
    const pgt_march_jump j = v->jumps[t];
    return v->codes[(uint32_t)j.v * v->width + j.u] >> 2;
}

/* Replays one step from state s (then one more, for the heading after it) and returns the
 * tangent-plane turn against d_in; -1 when either step is not a plain one. */
static double replay_turn(const pgt_march_atlas *v, const float *const nrm_planes[3],
                          const pgt_march_options *o, pgt_march_state s, float step,
                          const double d_in[3]) {
    float p1[3], p2[3];
    if (pgt_march_step(v, o, &s, step, 0.0f, NULL) == PGT_MARCH_STOP) return -1.0;
    pgt_march_position(v, s.x, s.y, p1);
    const uint32_t t = (uint32_t)s.y * v->width + (uint32_t)s.x;
    if (pgt_march_step(v, o, &s, step, 0.0f, NULL) != PGT_MARCH_INNER) return -1.0;
    pgt_march_position(v, s.x, s.y, p2);
    const double b[3] = {p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]};
    const float nrm[3] = {nrm_planes[0][t], nrm_planes[1][t], nrm_planes[2][t]};
    return tangent_turn_deg(d_in, b, nrm);
}

/* Statistics of RANDOM_MARCHES marches with options o: invariants at every step, 3D length of
 * jump steps, turn at jumps (the inner step before against the inner step after, in the tangent
 * plane) and elsewhere, and the paired best-pointer comparison. */
static int random_walks_sized(const pgt_march_atlas *v, const pgt_image *img,
                              const pgt_march_options *o, uint32_t seed, uint32_t marches,
                              uint32_t steps, float step_texels, walk_result *res) {
    pgt_atlas_channels ch;
    memset(res, 0, sizeof(*res));
    if (pgt_atlas_channels_find(img, "atlas", &ch, NULL) != PGT_OK) return 0;
    const float *const nrm_planes[3] = {pgt_image_plane(img, ch.nx), pgt_image_plane(img, ch.ny),
                                        pgt_image_plane(img, ch.nz)};
    const size_t cap = (size_t)marches * steps;
    double *turns = malloc(cap * sizeof(double)), *inner_turns = malloc(cap * sizeof(double)),
           *pair_best = malloc(cap * sizeof(double)), *pair_without = malloc(cap * sizeof(double)),
           *chart_best = malloc(cap * sizeof(double)),
           *chart_without = malloc(cap * sizeof(double));
    double(*p)[3] = malloc((steps + 1) * sizeof(*p));
    double *len = malloc((steps + 1) * sizeof(double));
    pgt_march_event *ev = malloc((steps + 1) * sizeof(pgt_march_event));
    uint32_t *texel_of = malloc((steps + 1) * sizeof(uint32_t));
    double *scratch = malloc((steps + 1) * sizeof(double)); /* one march's inner step lengths */
    int ok = turns && inner_turns && pair_best && pair_without && chart_best && chart_without &&
             p && len && ev && texel_of && scratch;
    pgt_march_options without = *o;
    without.no_best_pointer = 1;
    uint32_t inner_count = 0;
    for (uint32_t m = 0; ok && m < marches; ++m) {
        pgt_march_state st;
        if (!random_walker_start(v, seed, 1, m, &st)) continue;
        res->marches++;
        uint32_t n = 0;
        float q[3];
        pgt_march_position(v, st.x, st.y, q);
        for (int k = 0; k < 3; ++k) p[0][k] = q[k];
        texel_of[0] = (uint32_t)st.y * v->width + (uint32_t)st.x;
        ev[0] = PGT_MARCH_INNER;
        for (; n < steps; ++n) {
            const pgt_march_state before = st;
            pgt_march_info info;
            const pgt_march_event e = pgt_march_step(v, o, &st, step_texels, 0.0f, &info);
            if (e == PGT_MARCH_STOP) {
                res->stops++;
                break;
            }
            if (!o->no_best_pointer && info.jumps == 1 && info.last_pointer != info.last_p0 &&
                n >= 1 && ev[n] == PGT_MARCH_INNER) {
                const double d_in[3] = {p[n][0] - p[n - 1][0], p[n][1] - p[n - 1][1],
                                        p[n][2] - p[n - 1][2]};
                const double tb = replay_turn(v, nrm_planes, o, before, step_texels, d_in);
                const double tw = replay_turn(v, nrm_planes, &without, before, step_texels, d_in);
                if (tb >= 0.0 && tw >= 0.0) {
                    pair_best[res->pairs] = tb, pair_without[res->pairs] = tw;
                    res->pairs++;
                    res->pairs_lower += tb < tw;
                    res->pairs_higher += tb > tw;
                    if (pointer_chart(v, info.last_pointer) != pointer_chart(v, info.last_p0)) {
                        chart_best[res->chart_pairs] = tb, chart_without[res->chart_pairs] = tw;
                        res->chart_pairs++;
                    }
                }
            }
            res->bad += !walker_ok(v, &st);
            pgt_march_position(v, st.x, st.y, q);
            for (int k = 0; k < 3; ++k) p[n + 1][k] = q[k];
            ev[n + 1] = e;
            texel_of[n + 1] = (uint32_t)st.y * v->width + (uint32_t)st.x;
            const double d0 = p[n + 1][0] - p[n][0], d1 = p[n + 1][1] - p[n][1],
                         d2 = p[n + 1][2] - p[n][2];
            len[n + 1] = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
        }
        res->steps += n;
        {
            double *inner_len = scratch;
            uint32_t ni = 0;
            for (uint32_t i = 1; i <= n; ++i)
                if (ev[i] == PGT_MARCH_INNER) inner_len[ni++] = len[i];
            const double med = median_of(inner_len, ni);
            for (uint32_t w = 0; ni && w + STUCK_WINDOW <= n; w += STUCK_WINDOW) {
                double far = 0.0;
                uint32_t crossings = 0;
                for (uint32_t i = w + 1; i <= w + STUCK_WINDOW; ++i) {
                    crossings += ev[i] != PGT_MARCH_INNER;
                    const double d0 = p[i][0] - p[w][0], d1 = p[i][1] - p[w][1],
                                 d2 = p[i][2] - p[w][2];
                    far = fmax(far, sqrt(d0 * d0 + d1 * d1 + d2 * d2));
                }
                if (far < 2.0 * med && crossings >= STUCK_MIN_CROSSINGS) res->stuck += STUCK_WINDOW;
            }
        }
        for (uint32_t i = 1; i <= n; ++i) {
            const int jump = ev[i] != PGT_MARCH_INNER;
            if (jump) {
                double before[JUMP_NEIGHBOURS];
                uint32_t nb = 0;
                for (uint32_t j = i > JUMP_NEIGHBOURS ? i - JUMP_NEIGHBOURS : 1; j < i; ++j)
                    if (ev[j] == PGT_MARCH_INNER) before[nb++] = len[j];
                if (nb) {
                    const double med = median_of(before, nb);
                    res->jump_steps++;
                    if (!(len[i] >= 0.5 * med && len[i] <= 2.0 * med)) res->len_out++;
                }
            }
            if (i < 2 || i + 1 > n || ev[i - 1] != PGT_MARCH_INNER || ev[i + 1] != PGT_MARCH_INNER)
                continue;
            double a[3], b[3];
            for (int k = 0; k < 3; ++k)
                a[k] = p[i - 1][k] - p[i - 2][k], b[k] = p[i + 1][k] - p[i][k];
            const uint32_t t = texel_of[i];
            const float nrm[3] = {nrm_planes[0][t], nrm_planes[1][t], nrm_planes[2][t]};
            const double turn = tangent_turn_deg(a, b, nrm);
            if (jump)
                turns[res->turn_count++] = turn;
            else
                inner_turns[inner_count++] = turn;
        }
    }
    if (ok) {
        res->median_turn_jump = median_of(turns, res->turn_count);
        res->median_turn_inner = median_of(inner_turns, inner_count);
        res->median_pair_best = median_of(pair_best, res->pairs);
        res->median_pair_without = median_of(pair_without, res->pairs);
        res->median_chart_best = median_of(chart_best, res->chart_pairs);
        res->median_chart_without = median_of(chart_without, res->chart_pairs);
    }
    free(turns), free(inner_turns), free(pair_best), free(pair_without);
    free(chart_best), free(chart_without);
    free(p), free(len), free(ev), free(texel_of), free(scratch);
    return ok;
}

static int random_walks(const pgt_march_atlas *v, const pgt_image *img, const pgt_march_options *o,
                        uint32_t seed, walk_result *res) {
    return random_walks_sized(v, img, o, seed, RANDOM_MARCHES, RANDOM_STEPS, RANDOM_STEP_TEXELS,
                              res);
}

/* The shared meshes on which the median turn at jumps with the atlas's rot stays above
 * JUMP_TURN_MEDIAN_DEG (issue 4, a shortfall the README states): their UVs shear differently
 * on the two sides of their seams, where 5.2's boundary tangents keep a heading's angle to the
 * seam in texels (spot 19.2 degrees, pizza 14.6). It is 5.2's estimate, not the form of one
 * angle per texel: the atlas's angles fitted to the Jacobians (--angles jacobian) meet it on
 * them (9.2 and 9.5, asserted on every mesh). The Jacobian rotation meets it too (2.9 and
 * 7.5). */
static const char *const ROT_TURN_SHEARED[] = {"spot.obj", "pizza.obj"};

static int listed_in(const char *name, const char *const *list, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!strcmp(name, list[i])) return 1;
    return 0;
}

static int rot_turn_sheared(const char *name) {
    return listed_in(name, ROT_TURN_SHEARED, sizeof ROT_TURN_SHEARED / sizeof ROT_TURN_SHEARED[0]);
}

/* The shared meshes whose long marches get trapped, beyond STUCK_MAX_SHARE on some seeds (a
 * shortfall the README states; their share is printed, not bounded). Pizza's 1024^2 atlas has
 * charts one texel thick glued along both sides to a chart two texels thick (charts 45 and 582
 * to chart 357: strips narrower in 3D than a texel, where every outer texel's nearest texel of
 * another chart is in 357). A walker crossing them goes 357 -> 45 -> back into 357 (a bounce)
 * -> 582 -> back into 357 (a bounce) -> 45 ... with no step inside a chart; every other jump
 * does not bounce and resets the no-bounce rule's count (march.h), so the walker neither gets
 * through nor stops. Long marches with seeds 29-34, measured 2026-11-26: 0.07-4.6 % of the
 * steps stuck with 5.2's angles (above the bound on 3 of the 6 seeds; seed 33, the suite's, at
 * 0.07), 0.6-10.8 % with the fitted angles (5 of 6). */
static const char *const SUBTEXEL_TRAPS[] = {"pizza.obj"};

static int subtexel_traps(const char *name) {
    return listed_in(name, SUBTEXEL_TRAPS, sizeof SUBTEXEL_TRAPS / sizeof SUBTEXEL_TRAPS[0]);
}

/* ---- how far a single angle per texel can go (5.2's form) ---------------------------------- */

/* An atlas's planes as the angle bound reads them. */
typedef struct angle_planes {
    uint32_t w, h;
    const float *P[3], *N[3], *chart, *kind, *pu, *pv;
    const float *rot;
} angle_planes;

static int inner_of(const angle_planes *a, int x, int y, float chart) {
    if (x < 0 || y < 0 || x >= (int)a->w || y >= (int)a->h) return 0;
    const size_t i = (size_t)y * a->w + (size_t)x;
    return a->kind[i] == (float)PGT_TEXEL_INNER && a->chart[i] == chart;
}

/* P's finite-difference Jacobian at texel (x, y) from the atlas's planes (central where both
 * 4-neighbours are inner texels of its chart, else one-sided); 0 when an axis has neither. Written
 * here from the planes, not taken from march.c. */
static int planes_jacobian(const angle_planes *a, int x, int y, double jx[3], double jy[3]) {
    const float c = a->chart[(size_t)y * a->w + (size_t)x];
    const int l = inner_of(a, x - 1, y, c), r = inner_of(a, x + 1, y, c);
    const int u = inner_of(a, x, y - 1, c), d = inner_of(a, x, y + 1, c);
    if (!(l || r) || !(u || d)) return 0;
    const size_t x0 = (size_t)y * a->w + (size_t)(x - l), x1 = (size_t)y * a->w + (size_t)(x + r);
    const size_t y0 = (size_t)(y - u) * a->w + (size_t)x, y1 = (size_t)(y + d) * a->w + (size_t)x;
    for (int k = 0; k < 3; ++k) {
        jx[k] = ((double)a->P[k][x1] - a->P[k][x0]) / (l + r);
        jy[k] = ((double)a->P[k][y1] - a->P[k][y0]) / (u + d);
    }
    return 1;
}

static void cross3d(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* A Jacobian whose columns are closer to parallel than this squared sine (about 1e-6 radians)
 * has no usable inverse in the angle bound: a sliver texel. */
#define ANGLE_MIN_SINE2 1e-12

/* e with J e nearest to w (least squares); 0 when J is singular. */
static int jacobian_solve(const double jx[3], const double jy[3], const double w[3], double e[2]) {
    double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
    for (int k = 0; k < 3; ++k) {
        a11 += jx[k] * jx[k], a12 += jx[k] * jy[k], a22 += jy[k] * jy[k];
        b1 += jx[k] * w[k], b2 += jy[k] * w[k];
    }
    const double det = a11 * a22 - a12 * a12;
    if (!(det > ANGLE_MIN_SINE2 * a11 * a22)) return 0;
    e[0] = (a22 * b1 - a12 * b2) / det, e[1] = (a11 * b2 - a12 * b1) / det;
    return 1;
}

/* Rotates v about the unit axis n by angle t (Rodrigues). */
static void rotate_about(const double n[3], double t, const double v[3], double out[3]) {
    const double c = cos(t), s = sin(t), nv = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    double x[3];
    cross3d(n, v, x);
    for (int k = 0; k < 3; ++k) out[k] = c * v[k] + s * x[k] + (1.0 - c) * nv * n[k];
}

#define TWO_PI (2.0 * PI_D)
/* JUMP_TURN_MEDIAN_DEG in radians: the turn the angle bound's arcs allow */
#define JUMP_TURN_BOUND_RAD (JUMP_TURN_MEDIAN_DEG * PI_D / 180.0)

static double wrap_2pi(double t) {
    t = fmod(t, TWO_PI);
    return t < 0.0 ? t + TWO_PI : t;
}

/* Directions per indirection texel in the single-angle bound: walkers crossing a seam at angle
 * phi from its normal come with density cos(phi) (a uniform flux of headings), so the k-th of
 * ANGLE_DIRECTIONS is at phi = asin(2 (k + 1/2) / ANGLE_DIRECTIONS - 1), each of equal weight. */
#define ANGLE_DIRECTIONS 32u

/* An indirection texel of the single-angle bound: P's Jacobians J (at an inner neighbour, the
 * side the walker comes from) and J' (at the texel its pointer names), the unit normal of J''s
 * plane, the smallest rotation's axis and angle from J's plane to it, and its outward texel
 * direction (away from its inner neighbours). */
typedef struct angle_texel {
    double jx[3], jy[3], rx[3], ry[3], n[3], axis[3], tilt, out[2];
} angle_texel;

/* The model turn at texel q for texel direction d and angle theta: between u = T J d (the
 * source's 3D motion carried into the destination's tangent plane by the smallest rotation
 * between the normals) and J' R(theta) d, in that plane. */
static double model_turn(const angle_texel *q, const double d[2], double theta) {
    const double m[3] = {q->jx[0] * d[0] + q->jy[0] * d[1], q->jx[1] * d[0] + q->jy[1] * d[1],
                         q->jx[2] * d[0] + q->jy[2] * d[1]};
    double u[3];
    rotate_about(q->axis, q->tilt, m, u);
    const double c = cos(theta), s = sin(theta);
    const double ex = c * d[0] - s * d[1], ey = s * d[0] + c * d[1];
    const double v[3] = {q->rx[0] * ex + q->ry[0] * ey, q->rx[1] * ex + q->ry[1] * ey,
                         q->rx[2] * ex + q->ry[2] * ey};
    return tangent_turn_deg(u, v, (const float[3]){(float)q->n[0], (float)q->n[1], (float)q->n[2]});
}

/* Sets up q for indirection texel i at (x, y); 0 when a Jacobian or normal is missing or the two
 * tangent planes face away from each other. */
static int angle_texel_of(const angle_planes *a, uint32_t i, angle_texel *q) {
    /* edge neighbours first, then the diagonal ones (an outer texel on an oblique seam often
     * touches its chart only at a corner) */
    static const int d8[8][2] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1},
                                 {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
    const int x = (int)(i % a->w), y = (int)(i / a->w);
    double ox = 0.0, oy = 0.0;
    for (int k = 0; k < 8; ++k)
        if (inner_of(a, x + d8[k][0], y + d8[k][1], a->chart[i]))
            ox -= d8[k][0] / hypot(d8[k][0], d8[k][1]), oy -= d8[k][1] / hypot(d8[k][0], d8[k][1]);
    const double ol = hypot(ox, oy);
    if (!(ol > 0.0)) return 0;
    q->out[0] = ox / ol, q->out[1] = oy / ol;
    /* J at the first inner neighbour that has one (a chart one texel thin has none there), J' at
     * the texel the pointer names or else at its first neighbour in its chart that has one */
    int sx = -1, sy = -1, have = 0;
    for (int k = 0; k < 8 && !have; ++k)
        if (inner_of(a, x + d8[k][0], y + d8[k][1], a->chart[i]))
            sx = x + d8[k][0], sy = y + d8[k][1], have = planes_jacobian(a, sx, sy, q->jx, q->jy);
    int rx = (int)a->pu[i], ry = (int)a->pv[i];
    const float to = a->chart[(size_t)ry * a->w + (size_t)rx];
    int have_r = have && planes_jacobian(a, rx, ry, q->rx, q->ry);
    for (int k = 0; k < 8 && have && !have_r; ++k)
        if (inner_of(a, rx + d8[k][0], ry + d8[k][1], to) &&
            planes_jacobian(a, rx + d8[k][0], ry + d8[k][1], q->rx, q->ry))
            rx += d8[k][0], ry += d8[k][1], have_r = 1;
    if (!have_r) return 0;
    /* the normals of the Jacobians' planes (turned to the side of the atlas's normals there):
     * J' R(theta) d lies in the destination's, where the turn is measured */
    const size_t si = (size_t)sy * a->w + (size_t)sx, ri = (size_t)ry * a->w + (size_t)rx;
    double ns[3], ls = 0.0, lr = 0.0, dd = 0.0, ss = 0.0, sr = 0.0;
    cross3d(q->jx, q->jy, ns);
    cross3d(q->rx, q->ry, q->n);
    for (int c = 0; c < 3; ++c) {
        ls += ns[c] * ns[c], lr += q->n[c] * q->n[c];
        ss += ns[c] * a->N[c][si], sr += q->n[c] * a->N[c][ri];
    }
    ls = sqrt(ls) * (ss < 0.0 ? -1.0 : 1.0), lr = sqrt(lr) * (sr < 0.0 ? -1.0 : 1.0);
    if (!(fabs(ls) > 0.0) || !(fabs(lr) > 0.0)) return 0;
    for (int c = 0; c < 3; ++c) ns[c] /= ls, q->n[c] /= lr, dd += ns[c] * q->n[c];
    if (!(dd > 0.0)) return 0;
    cross3d(ns, q->n, q->axis);
    const double sn =
        sqrt(q->axis[0] * q->axis[0] + q->axis[1] * q->axis[1] + q->axis[2] * q->axis[2]);
    q->tilt = atan2(sn, dd);
    if (sn > 0.0)
        for (int c = 0; c < 3; ++c) q->axis[c] /= sn;
    else
        q->axis[0] = 1.0, q->axis[1] = q->axis[2] = 0.0, q->tilt = 0.0;
    return 1;
}

/* The arc [*lo, *lo + *width] (mod 2 pi) of angles theta that turn direction d at q by at most
 * the bound: J' maps the cone of 3D directions within the bound of u (under 180 degrees) to one
 * cone of texel directions, whose ends are J'^+ of u turned by -+ the bound. 0 when J' is
 * singular. */
static int turn_arc(const angle_texel *q, const double d[2], double *lo, double *width) {
    const double m[3] = {q->jx[0] * d[0] + q->jy[0] * d[1], q->jx[1] * d[0] + q->jy[1] * d[1],
                         q->jx[2] * d[0] + q->jy[2] * d[1]};
    double u[3], wm[3], wp[3], em[2], ep[2];
    rotate_about(q->axis, q->tilt, m, u);
    const double un = u[0] * q->n[0] + u[1] * q->n[1] + u[2] * q->n[2];
    for (int c = 0; c < 3; ++c) u[c] -= un * q->n[c];
    rotate_about(q->n, -JUMP_TURN_BOUND_RAD, u, wm);
    rotate_about(q->n, JUMP_TURN_BOUND_RAD, u, wp);
    if (!jacobian_solve(q->rx, q->ry, wm, em) || !jacobian_solve(q->rx, q->ry, wp, ep)) return 0;
    const double am = atan2(em[1], em[0]), ap = atan2(ep[1], ep[0]);
    double start = am, w = wrap_2pi(ap - am);
    if (w > PI_D) start = ap, w = TWO_PI - w;
    *lo = wrap_2pi(start - atan2(d[1], d[0])), *width = w;
    return 1;
}

/* The `count` headings d of texel q (ANGLE_DIRECTIONS in the bound, PGT_ATLAS_FIT_HEADINGS to
 * re-derive the atlas's fit) and their arcs (turn_arc); returns how many have one, packed
 * first. */
static uint32_t texel_arcs(const angle_texel *q, uint32_t count, double d[][2], double lo[],
                           double width[]) {
    uint32_t arcs = 0;
    for (uint32_t k = 0; k < count; ++k) {
        const double phi = asin(2.0 * (k + 0.5) / count - 1.0);
        const double c = cos(phi), s = sin(phi);
        d[arcs][0] = c * q->out[0] - s * q->out[1], d[arcs][1] = s * q->out[0] + c * q->out[1];
        arcs += turn_arc(q, d[arcs], &lo[arcs], &width[arcs]);
    }
    return arcs;
}

/* The angle on the most of the arcs (*on of them), in the middle of their common part. The most
 * arcs meet at some arc's start: moving back from any point to the nearest start leaves none. */
static double best_angle(const double lo[], const double width[], uint32_t arcs, uint32_t *on) {
    double theta = 0.0;
    *on = 0;
    for (uint32_t s = 0; s < arcs; ++s) {
        uint32_t n = 0;
        double room = TWO_PI; /* how far past lo[s] every arc through it goes on */
        for (uint32_t t = 0; t < arcs; ++t) {
            const double into = wrap_2pi(lo[s] - lo[t]);
            if (into <= width[t]) n++, room = fmin(room, width[t] - into);
        }
        if (n > *on) *on = n, theta = lo[s] + 0.5 * room;
    }
    return theta;
}

/* The atlas's planes as the angle bound reads them. */
static int angle_planes_of(const pgt_image *img, angle_planes *a) {
    pgt_atlas_channels ch;
    if (pgt_atlas_channels_find(img, "atlas", &ch, NULL) != PGT_OK) return 0;
    memset(a, 0, sizeof(*a));
    a->w = img->width, a->h = img->height;
    a->P[0] = pgt_image_plane(img, ch.px), a->P[1] = pgt_image_plane(img, ch.py);
    a->P[2] = pgt_image_plane(img, ch.pz), a->N[0] = pgt_image_plane(img, ch.nx);
    a->N[1] = pgt_image_plane(img, ch.ny), a->N[2] = pgt_image_plane(img, ch.nz);
    a->chart = pgt_image_plane(img, ch.chart), a->kind = pgt_image_plane(img, ch.kind);
    a->pu = pgt_image_plane(img, ch.ptr_u), a->pv = pgt_image_plane(img, ch.ptr_v);
    a->rot = pgt_image_plane(img, ch.rot);
    return 1;
}

/* The atlas's fitted angles (--angles jacobian, atlas_angles.c) re-derived: at every indirection
 * texel the model covers (angle_texel_of), the best angle of best_angle over the
 * PGT_ATLAS_FIT_HEADINGS headings, computed here in another way (every arc's start tried
 * against every arc, angles through atan2, where the atlas compares diamond angles). fit holds
 * the Jacobian atlas, tan the same mesh's atlas with 5.2's angles: a texel whose rot differs
 * between them was fitted. */
typedef struct fit_check {
    uint32_t indirection, fitted, covered;
    uint32_t agree;    /* fitted, within FIT_AGREE_RAD of the best angle here */
    uint32_t kept;     /* covered here, 5.2's angle kept there (the way out would not enter B) */
    uint32_t disagree; /* fitted, elsewhere; or fitted where the model has no angle */
} fit_check;

/* rot is stored as float: 2^-24 of pi is 1.9e-7 radians; the two derivations round their
 * doubles differently by far less. */
#define FIT_AGREE_RAD 1e-6

static int check_fitted(const pgt_image *fit, const pgt_image *tan, fit_check *res) {
    angle_planes a, t;
    memset(res, 0, sizeof(*res));
    if (!angle_planes_of(fit, &a) || !angle_planes_of(tan, &t)) return 0;
    if (a.w != t.w || a.h != t.h) return 0;
    for (uint32_t i = 0; i < a.w * a.h; ++i) {
        if (a.kind[i] != (float)PGT_TEXEL_INDIRECTION) continue;
        res->indirection++;
        const int fitted = a.rot[i] != t.rot[i];
        res->fitted += fitted;
        angle_texel q;
        double d[PGT_ATLAS_FIT_HEADINGS][2], lo[PGT_ATLAS_FIT_HEADINGS],
            width[PGT_ATLAS_FIT_HEADINGS];
        uint32_t arcs = 0, on;
        if (angle_texel_of(&a, i, &q)) arcs = texel_arcs(&q, PGT_ATLAS_FIT_HEADINGS, d, lo, width);
        /* the atlas gives up on a texel when any heading has no arc (J' singular: then none has) */
        if (arcs != PGT_ATLAS_FIT_HEADINGS) {
            res->disagree += fitted;
            continue;
        }
        res->covered++;
        const double best = best_angle(lo, width, arcs, &on);
        const double off = wrap_2pi((double)a.rot[i] - best + PI_D) - PI_D;
        if (!fitted)
            res->kept++;
        else if (fabs(off) <= FIT_AGREE_RAD)
            res->agree++;
        else
            res->disagree++;
    }
    return 1;
}

typedef struct angle_bound {
    uint32_t jumps, texels;
    double over_share;  /* least share turning by more than the bound, any angle per texel */
    double median_best; /* median model turn at the middle of each texel's best angles */
    double over_rot;    /* share over the bound with the atlas's rot, in the model */
    double median_rot;  /* median model turn with the atlas's rot */
    /* headings where turn_arc and model_turn disagree on whether rot turns them within the
     * bound (farther than ANGLE_AGREE_DEG from it): two computations of one thing */
    uint32_t disagree;
} angle_bound;

/* turn_arc's ends are solved through J'^+ and atan2, model_turn maps forward and measures: at
 * the bound itself they may round to either side. */
#define ANGLE_AGREE_DEG 1e-6

static int cmp_u32(const void *a, const void *b) {
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* How far a single angle per indirection texel (5.2's form: rot) can keep the turn at jumps under
 * JUMP_TURN_MEDIAN_DEG, in a model without the quantisation of pointers and positions. The
 * texels are those the single-jump steps after an inner step go through in the marches
 * random_walks makes with options o (seed), each counted as often as it is used. At each texel
 * the walker's headings are ANGLE_DIRECTIONS, spread over the half-circle leaving the chart as a
 * uniform flux crosses a seam; a heading d turns by the angle between T J d and J' R(theta) d
 * (model_turn). Per texel the best theta lies on the most arcs of turn_arc (found at an arc's
 * start: moving back from any point to the nearest start leaves no arc); res gets the least
 * share over the bound, the median turn at the middle of each texel's best angles, and the
 * same model with the atlas's rot. Sampling every heading at a texel keeps an angle from being
 * fitted to the few walkers that happen to cross there. */
static int single_angle_bound(const pgt_march_atlas *v, const pgt_image *img,
                              const pgt_march_options *o, uint32_t seed, angle_bound *res) {
    memset(res, 0, sizeof(*res));
    angle_planes a;
    if (!angle_planes_of(img, &a)) return 0;
    const size_t cap = (size_t)RANDOM_MARCHES * RANDOM_STEPS;
    uint32_t *used = malloc(cap * sizeof(uint32_t));
    double *turns = malloc(cap * ANGLE_DIRECTIONS * sizeof(double));
    double *best_turns = malloc(cap * ANGLE_DIRECTIONS * sizeof(double));
    if (!used || !turns || !best_turns) {
        free(used), free(turns), free(best_turns);
        return 0;
    }
    uint32_t n = 0;
    for (uint32_t m = 0; m < RANDOM_MARCHES; ++m) {
        pgt_march_state st;
        if (!random_walker_start(v, seed, 1, m, &st)) continue;
        int after_inner = 0;
        for (uint32_t k = 0; k < RANDOM_STEPS; ++k) {
            pgt_march_info info;
            const pgt_march_event e = pgt_march_step(v, o, &st, RANDOM_STEP_TEXELS, 0.0f, &info);
            if (e == PGT_MARCH_STOP) break;
            if (e != PGT_MARCH_INNER && info.jumps == 1 && after_inner)
                used[n++] = info.last_pointer;
            after_inner = e == PGT_MARCH_INNER;
        }
    }
    qsort(used, n, sizeof(uint32_t), cmp_u32);
    double covered = 0.0, weight = 0.0;
    size_t nt = 0;
    uint32_t over_rot = 0;
    for (uint32_t b = 0; b < n;) {
        uint32_t e = b;
        while (e < n && used[e] == used[b]) e++;
        const uint32_t mult = e - b, i = used[b];
        b = e;
        angle_texel q;
        if (!angle_texel_of(&a, i, &q)) continue;
        double d[ANGLE_DIRECTIONS][2], lo[ANGLE_DIRECTIONS], width[ANGLE_DIRECTIONS];
        const uint32_t arcs = texel_arcs(&q, ANGLE_DIRECTIONS, d, lo, width);
        if (!arcs) continue;
        uint32_t best;
        const double theta = best_angle(lo, width, arcs, &best);
        res->texels++;
        res->jumps += mult;
        covered += (double)mult * best, weight += (double)mult * arcs;
        for (uint32_t k = 0; k < arcs; ++k) {
            const double tr = model_turn(&q, d[k], a.rot[i]), tb = model_turn(&q, d[k], theta);
            const int in_arc = wrap_2pi((double)a.rot[i] - lo[k]) <= width[k];
            if (fabs(tr - JUMP_TURN_MEDIAN_DEG) > ANGLE_AGREE_DEG &&
                in_arc != (tr <= JUMP_TURN_MEDIAN_DEG))
                res->disagree++;
            for (uint32_t r = 0; r < mult; ++r) turns[nt] = tr, best_turns[nt++] = tb;
            over_rot += mult * (tr > JUMP_TURN_MEDIAN_DEG);
        }
    }
    if (weight > 0.0) {
        res->over_share = 1.0 - covered / weight;
        res->over_rot = over_rot / weight;
        res->median_rot = median_of(turns, nt);
        res->median_best = median_of(best_turns, nt);
    }
    free(used), free(turns), free(best_turns);
    return 1;
}

/* Long marches with the paper's defaults and the benchmark's step (LONG_MARCHES of LONG_STEPS
 * steps of LONG_STEP_TEXELS): a trap is an absorbing state, which short marches rarely reach. No
 * step off an inner texel of its chart; at most STUCK_MAX_SHARE of the steps stuck, except on
 * SUBTEXEL_TRAPS (printed). what names the atlas in the output ("" or "fitted   "). */
static void long_marches(const pgt_march_atlas *v, const pgt_image *img, const char *name,
                         const char *what, uint32_t seed) {
    walk_result lw;
    const pgt_march_options defaults = {0};
    REQUIRE(random_walks_sized(v, img, &defaults, seed, LONG_MARCHES, LONG_STEPS, LONG_STEP_TEXELS,
                               &lw));
    printf("  %-17s %s%u long marches: %u steps, %u stops, %u steps stuck%s\n", name, what,
           lw.marches, lw.steps, lw.stops, lw.stuck,
           subtexel_traps(name) ? " (SUBTEXEL_TRAPS: not bounded)" : "");
    CHECK_MSG(subtexel_traps(name) || lw.stuck <= STUCK_MAX_SHARE * lw.steps,
              "%s: %u of %u steps of %slong marches stuck bouncing between pointers", name,
              lw.stuck, lw.steps, what);
    CHECK_MSG(lw.bad == 0, "%s: %u steps of %slong marches off an inner texel of their chart", name,
              lw.bad, what);
}

/* Every UV mesh of the shared folder, thousands of seeded random marches: no step leaves the
 * image or stands off an inner texel of its chart; jump steps keep their 3D length (see
 * JUMP_LENGTH_MIN_FRACTION); with the Jacobian rotation the median turn at jumps is under 10
 * degrees, and where best-pointer selection picks another texel the turn is lower than without
 * it; with either rotation, where its pick leads into another chart than P0's (MIN_CHART_PAIRS),
 * the turn is lower than without it. With the atlas's rot (the paper's 5.2, the default) the median
 * turn at jumps must be lower than with no rotation at all, and under 10 degrees except on
 * ROT_TURN_SHEARED (6.7 for bob to 19.2 for spot). The same mesh's atlas with --angles jacobian:
 * the fit re-derived here (check_fitted), the median turn at jumps under 10 degrees on every
 * mesh, no walker off an inner texel, no more stuck steps than the bound (long marches: except
 * SUBTEXEL_TRAPS). The environment variable PGT_TEST_MESHES, a
 * ':'-separated list of mesh files with UVs, replaces the shared folder's meshes:
 * tests/meshlab_atlas_check.sh runs this case on the MeshLab Voronoi atlases it makes of the shared
 * meshes without UVs (issue 4 item 8). */
#define MARCH_MESHES_MAX 16u

/* batch_vs_steps on a real atlas with the defaults, a mask and a density condition. With the
 * condition the calls must come in the same order too: one pgt_march_density counter serves
 * all walkers, so any other order draws other numbers. */
#define BATCH_WALKERS 700u
#define BATCH_STEPS 300u
#define BATCH_STEP_TEXELS 2.0f
static void batch_matches_steps(const pgt_march_atlas *v, const char *name, uint32_t seed) {
    static pgt_march_state starts[BATCH_WALKERS];
    uint32_t n = 0;
    for (uint32_t i = 0; i < BATCH_WALKERS; ++i)
        if (random_walker_start(v, seed, 5, i, &starts[n])) n++;
    REQUIRE(n > BATCH_WALKERS / 2);
    const size_t texels = (size_t)v->width * v->height;
    float *mask = calloc(texels, sizeof(float)), *density = malloc(texels * sizeof(float));
    REQUIRE(mask && density);
    for (size_t t = 0; t < texels; ++t) {
        mask[t] = pgt_rng_float(seed, 7, t) < 0.002f ? 1.0f : 0.0f; /* rejects a few steps */
        density[t] = 0.999f;
    }
    for (int mode = 0; mode < 3; ++mode) { /* defaults, a mask, a density condition */
        pgt_march_density d_batch = {density, v->width, v->height, seed, 9, 0}, d_steps = d_batch;
        pgt_march_options ob = {0}, os = {0};
        if (mode == 1) ob.mask = os.mask = mask;
        if (mode == 2) {
            ob.condition = os.condition = pgt_march_density_condition;
            ob.condition_ctx = &d_batch, os.condition_ctx = &d_steps;
        }
        uint32_t stopped = 0;
        const uint32_t differ = /* mode 0: no options at all */
            batch_vs_steps(v, mode ? &ob : NULL, mode ? &os : NULL, BATCH_STEP_TEXELS, BATCH_STEPS,
                           1, starts, n, &stopped);
        printf("  %-17s batch of %u walkers x %u steps (%s): %u differ from pgt_march_step, %u "
               "stopped early\n",
               name, n, BATCH_STEPS,
               mode == 0   ? "defaults"
               : mode == 1 ? "mask"
                           : "density",
               differ, stopped);
        CHECK_MSG(differ == 0, "%s: %u of %u batch walkers differ from pgt_march_step", name,
                  differ, n);
        if (mode == 2)
            CHECK_MSG(d_batch.draws == d_steps.draws,
                      "%s: the batch drew %llu numbers, the steps %llu", name,
                      (unsigned long long)d_batch.draws, (unsigned long long)d_steps.draws);
    }
    free(mask), free(density);
}

/* The Jacobian rotation depends on the texel Jacobians' ratios only: the cube-sphere scaled by
 * 1e-9 (texels of ~3e-11, whose Jacobians' determinant is below float's range) and by 1e9 walks
 * the same great circle in texels as the unit one (it fell back to the atlas's rot at 1e-9). */
static void test_jacobian_scale(void) {
    static const double scales[3] = {1.0, 1e-9, 1e9};
    float end[3][2];
    for (int k = 0; k < 3; ++k) {
        pgt_mesh m;
        REQUIRE(pgt_gen_cube_sphere(&m, 16, NULL) == PGT_OK);
        for (uint32_t i = 0; i < 3u * m.vertex_count; ++i)
            m.positions[i] = (float)(m.positions[i] * scales[k]);
        pgt_image img;
        pgt_atlas_stats st;
        pgt_march_atlas v;
        REQUIRE(real_atlas(&m, "cube_sphere_16", &img, &st, &v));
        pgt_march_options o = {0};
        o.rotation = PGT_MARCH_ROTATION_JACOBIAN;
        pgt_march_state s;
        REQUIRE(pgt_march_start(&v, (float)(v.width / 6.0), (float)(0.75 * v.height), 1.0f, 0.3f,
                                &s, NULL) == PGT_OK);
        uint32_t stops = 0;
        for (uint32_t i = 0; i < 600; ++i) {
            pgt_march_info info;
            stops += pgt_march_step(&v, &o, &s, 2.0f, 0.0f, &info) == PGT_MARCH_STOP;
        }
        CHECK(stops == 0);
        end[k][0] = s.x, end[k][1] = s.y;
        pgt_march_atlas_destroy(&v);
        pgt_image_destroy(&img);
        pgt_mesh_destroy(&m);
    }
    for (int k = 1; k < 3; ++k) /* float rounding of the scaled mesh and atlas, over 600 steps */
        CHECK_MSG(hypot(end[k][0] - end[0][0], end[k][1] - end[0][1]) < 0.05,
                  "scale %g: end (%.4f, %.4f), unit (%.4f, %.4f)", scales[k], end[k][0], end[k][1],
                  end[0][0], end[0][1]);
}

static void test_real_random_marches(void) {
    char list[4096], *paths[MARCH_MESHES_MAX];
    const uint32_t listed =
        pgt_test_env_paths("PGT_TEST_MESHES", list, sizeof list, paths, MARCH_MESHES_MAX);
    uint32_t meshes = 0;
    const uint32_t count = listed ? listed : pgt_cli_shared_mesh_count;
    for (uint32_t k = 0; k < count; ++k) {
        char path[1024];
        if (listed)
            snprintf(path, sizeof path, "%s", paths[k]);
        else
            snprintf(path, sizeof path, "%s/%s", PGT_SHARED_MESH_DIR, pgt_cli_shared_meshes[k]);
        const char *name = pgt_cli_mesh_label(path);
        pgt_mesh m;
        pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, NULL};
        if (pgt_mesh_read(&m, path, &ro, NULL) != PGT_OK) {
            CHECK_MSG(!listed, "%s: cannot read it", path);
            printf("  SKIP %s: cannot read it\n", path);
            continue;
        }
        if (!m.uvs) { /* nefertiti, mountain: no UVs */
            CHECK_MSG(!listed, "%s: no UVs", path);
            pgt_mesh_destroy(&m);
            continue;
        }
        pgt_image img;
        pgt_atlas_stats st;
        pgt_march_atlas v;
        const int built = real_atlas(&m, name, &img, &st, &v);
        CHECK_MSG(built, "%s: no atlas", name);
        if (!built) {
            pgt_mesh_destroy(&m);
            continue;
        }
        meshes++;
        CHECK_MSG(rings_differ(&v, &img) == 0, "%s: ring masks differ from their definition", name);
        double rot_median = 0.0; /* the atlas's rot, best pointer */
        for (int rot = 0; rot < 2; ++rot) {
            walk_result r[2];
            for (int best = 0; best < 2; ++best) {
                pgt_march_options o = {0};
                o.no_best_pointer = !best;
                o.rotation = rot ? PGT_MARCH_ROTATION_JACOBIAN : PGT_MARCH_ROTATION_ATLAS;
                REQUIRE(random_walks(&v, &img, &o, 11u + k, &r[best]));
                const walk_result *w = &r[best];
                printf("  %-17s %-8s %-15s %4u charts: %u steps, %u stops, %u jump steps, "
                       "%.1f %% within [0.5, 2] x median, turn median %.2f deg at jumps, %.2f "
                       "elsewhere, %u steps stuck\n",
                       name, rot ? "jacobian" : "atlas", best ? "best-pointer" : "no-best",
                       st.charts, w->steps, w->stops, w->jump_steps,
                       w->jump_steps ? 100.0 - 100.0 * w->len_out / w->jump_steps : 100.0,
                       w->median_turn_jump, w->median_turn_inner, w->stuck);
                CHECK_MSG(w->stuck <= STUCK_MAX_SHARE * w->steps,
                          "%s: %u of %u steps stuck bouncing between pointers", name, w->stuck,
                          w->steps);
                CHECK_MSG(w->bad == 0, "%s: %u steps off an inner texel of their chart", name,
                          w->bad);
                CHECK(w->marches == RANDOM_MARCHES);
                if (w->jump_steps < MIN_JUMPS_CHECKED) continue;
                CHECK_MSG(w->len_out <= (1.0 - JUMP_LENGTH_MIN_FRACTION) * w->jump_steps,
                          "%s: %u of %u jump steps outside [0.5, 2] x median", name, w->len_out,
                          w->jump_steps);
            }
            printf("  %-17s %-8s best-pointer picked another texel at %u jumps: turn median "
                   "%.2f deg with, %.2f without (lower with it at %u, higher at %u)\n",
                   name, rot ? "jacobian" : "atlas", r[1].pairs, r[1].median_pair_best,
                   r[1].median_pair_without, r[1].pairs_lower, r[1].pairs_higher);
            printf("  %-17s %-8s ... into another chart than P0's at %u jumps: turn median "
                   "%.2f deg with, %.2f without\n",
                   name, rot ? "jacobian" : "atlas", r[1].chart_pairs, r[1].median_chart_best,
                   r[1].median_chart_without);
            /* 5.1's purpose, with either rotation: where its pick leads into another chart than
             * P0's pointer (a chart corner), the turn is lower than through P0. Where the pick
             * stays in P0's destination chart (98-99 % of the picks) it lands a texel or two
             * along the same seam and, with the atlas's rot, takes that texel's angle: measured
             * as likely to raise the turn as to lower it (spot, all picks: 1089 lower, 1046
             * higher), so the median over all picks goes either way with the atlas's rot. */
            if (r[1].chart_pairs >= MIN_CHART_PAIRS)
                CHECK_MSG(r[1].median_chart_best < r[1].median_chart_without,
                          "%s: where best-pointer selection changes the destination chart, median "
                          "turn %.2f deg with it, %.2f without",
                          name, r[1].median_chart_best, r[1].median_chart_without);
            if (r[1].jump_steps < MIN_JUMPS_CHECKED) {
                printf("  %s: %u jump steps, too few for the turn checks\n", name, r[1].jump_steps);
                continue;
            }
            /* The issue's bound, with either rotation; with the atlas's rot except where 5.2's
             * tangents do not meet it (ROT_TURN_SHEARED); measured with the atlas's
             * rot 3.1 (mountain's Voronoi atlas), 3.4 (nefertiti's), 6.7 (bob), 8.6 (human)
             * degrees. A listed mesh that comes under the bound fails too, so that the list and
             * the README stay true. */
            const char *how = rot ? "the Jacobian rotation" : "the atlas's rot";
            if (!rot && rot_turn_sheared(name))
                CHECK_MSG(r[1].median_turn_jump >= JUMP_TURN_MEDIAN_DEG,
                          "%s: median turn %.2f deg with %s, under the bound: take it off "
                          "ROT_TURN_SHEARED and the README's shortfalls",
                          name, r[1].median_turn_jump, how);
            else
                CHECK_MSG(r[1].median_turn_jump < JUMP_TURN_MEDIAN_DEG,
                          "%s: median turn %.2f deg with %s", name, r[1].median_turn_jump, how);
            if (!rot) {
                rot_median = r[1].median_turn_jump;
                angle_bound ab;
                const pgt_march_options o_default = {0}; /* the paper's, as r[1] */
                REQUIRE(single_angle_bound(&v, &img, &o_default, 11u + k, &ab));
                CHECK_MSG(ab.disagree == 0, "%s: %u headings where the arc and the turn disagree",
                          name, ab.disagree);
                CHECK(ab.over_share <= ab.over_rot); /* rot is one of the angles */
                printf("  %-17s single angle per texel (model, %u jumps through %u texels, %u "
                       "headings each): at least %.1f %% turn by more than %.0f deg whatever the "
                       "angles (median %.2f deg at the best ones); the atlas's rot %.1f %% "
                       "(median %.2f deg)\n",
                       name, ab.jumps, ab.texels, ANGLE_DIRECTIONS, 100.0 * ab.over_share,
                       JUMP_TURN_MEDIAN_DEG, ab.median_best, 100.0 * ab.over_rot, ab.median_rot);
                walk_result fixed;
                pgt_march_options o = {0};
                o.no_rotation = 1;
                REQUIRE(random_walks(&v, &img, &o, 11u + k, &fixed));
                printf("  %-17s no rotation: turn median %.2f deg at jumps\n", name,
                       fixed.median_turn_jump);
                CHECK_MSG(r[1].median_turn_jump < fixed.median_turn_jump,
                          "%s: turn median %.2f deg with the atlas's rot, %.2f without rotation",
                          name, r[1].median_turn_jump, fixed.median_turn_jump);
                continue;
            }
            CHECK_MSG(r[1].pairs > 0 && r[1].median_pair_best < r[1].median_pair_without,
                      "%s: best-pointer median turn %.2f deg, without %.2f deg", name,
                      r[1].median_pair_best, r[1].median_pair_without);
        }
        batch_matches_steps(&v, name, 31u + k);
        long_marches(&v, &img, name, "", 29u + k);
        /* the atlas with angles fitted to the Jacobians (--angles jacobian): the issue's bound
         * on every mesh, the fit re-derived here (check_fitted), no traps, no walker off an inner
         * texel */
        pgt_image fimg;
        pgt_atlas_stats fst;
        pgt_march_atlas fv;
        REQUIRE(real_atlas_angles(&m, name, PGT_ATLAS_ANGLES_JACOBIAN, &fimg, &fst, &fv));
        fit_check fc;
        REQUIRE(check_fitted(&fimg, &img, &fc));
        printf("  %-17s angles fitted at %u of %u indirection texels (the model covers %u: the "
               "fit re-derived at %u, 5.2's kept at %u; %u differ)\n",
               name, fc.fitted, fc.indirection, fc.covered, fc.agree, fc.kept, fc.disagree);
        CHECK_MSG(fc.disagree == 0, "%s: %u fitted angles differ from their re-derivation", name,
                  fc.disagree);
        CHECK(fc.fitted == fst.fitted_angles);
        walk_result fw[2];
        for (int best = 0; best < 2; ++best) {
            pgt_march_options o = {0};
            o.no_best_pointer = !best;
            REQUIRE(random_walks(&fv, &fimg, &o, 11u + k, &fw[best]));
            const walk_result *w = &fw[best];
            printf("  %-17s %-8s %-15s %u steps, %u stops, %u jump steps, %.1f %% within "
                   "[0.5, 2] x median, turn median %.2f deg at jumps, %u steps stuck\n",
                   name, "fitted", best ? "best-pointer" : "no-best", w->steps, w->stops,
                   w->jump_steps,
                   w->jump_steps ? 100.0 - 100.0 * w->len_out / w->jump_steps : 100.0,
                   w->median_turn_jump, w->stuck);
            CHECK_MSG(w->bad == 0, "%s: %u steps off an inner texel with fitted angles", name,
                      w->bad);
            CHECK_MSG(w->stuck <= STUCK_MAX_SHARE * w->steps,
                      "%s: %u of %u steps stuck with fitted angles", name, w->stuck, w->steps);
        }
        printf("  %-17s fitted   best-pointer picked another texel at %u jumps: turn median "
               "%.2f deg with, %.2f without\n",
               name, fw[1].pairs, fw[1].median_pair_best, fw[1].median_pair_without);
        if (fw[1].jump_steps >= MIN_JUMPS_CHECKED)
            CHECK_MSG(fw[1].median_turn_jump < JUMP_TURN_MEDIAN_DEG,
                      "%s: median turn %.2f deg at jumps with fitted angles (5.2's: %.2f)", name,
                      fw[1].median_turn_jump, rot_median);
        long_marches(&fv, &fimg, name, "fitted   ", 29u + k);
        pgt_march_atlas_destroy(&fv);
        pgt_image_destroy(&fimg);
        pgt_mesh_destroy(&m);
        pgt_march_atlas_destroy(&v);
        pgt_image_destroy(&img);
    }
    if (!meshes) printf("  SKIP: no UV mesh in %s\n", PGT_SHARED_MESH_DIR);
}

/* ---- the density context (march.h pgt_march_density) ------------------------------------ */

/* Walker w of a density test: its condition draws from (seed, stream w), it starts at
 * random_walker_start(seed, stream 3, w). 1 on success. */
static int density_walker(const pgt_march_atlas *v, const float *d, uint32_t seed, uint32_t w,
                          pgt_march_density *ctx, pgt_march_options *o, pgt_march_state *s) {
    const pgt_march_density c = {d, v->width, v->height, seed, w, 0};
    *ctx = c;
    memset(o, 0, sizeof *o);
    o->condition = pgt_march_density_condition, o->condition_ctx = ctx;
    return random_walker_start(v, seed, 3, w, s);
}

/* Walkers per density of the statistical part: the standard error of the mean of K (below) is
 * sd / sqrt(DENSITY_WALKERS), 0.004 texel steps at p = 0.25 and 0.025 at p = 0.75. */
#define DENSITY_WALKERS 20000u
/* A sample statistic may deviate from its expectation by this many standard errors: with two
 * statistics at two densities, a correct implementation fails with probability ~2e-6. */
#define DENSITY_SIGMAS 5.0

/* Two checks on cube_sphere_8's 256^2 atlas (no dead ends; no walker stops on its own):
 * 1. A density of 1 on the texels x < W/2 and 0 elsewhere: every step is the step without a
 *    context (same event, same state, byte for byte) when that step's destination has x < W/2,
 *    and a rejection with the state unchanged when it has x >= W/2; one draw per such step.
 * 2. A constant density p: each walker (its own stream) goes on with probability p at every
 *    step, so K, the steps it takes before the first rejection, is geometric: P(K = 0) = 1 - p,
 *    E[K] = p / (1 - p), sd(K) = sqrt(p) / (1 - p). Both sample values lie within
 *    DENSITY_SIGMAS standard errors. */
static void test_density_context(void) {
    pgt_image img;
    pgt_march_atlas v;
    REQUIRE(cube_sphere_8_atlas(256, &img));
    REQUIRE(pgt_march_atlas_create(&v, &img, "cube_sphere_8", NULL) == PGT_OK);
    const size_t n = (size_t)v.width * v.height;
    float *d = malloc(n * sizeof(float));
    REQUIRE(d);
    for (size_t i = 0; i < n; ++i) d[i] = i % v.width < v.width / 2u ? 1.0f : 0.0f;
    uint32_t same = 0, rejected = 0, other = 0, stops = 0;
    for (uint32_t w = 0; w < 400u; ++w) {
        pgt_march_density ctx;
        pgt_march_options o;
        pgt_march_state s;
        REQUIRE(density_walker(&v, d, 5, w, &ctx, &o, &s));
        uint64_t evaluated = 0;
        for (uint32_t k = 0; k < 200u; ++k) {
            pgt_march_state ref = s, before = s;
            pgt_march_info info;
            const pgt_march_event e_ref = pgt_march_step(&v, NULL, &ref, 2.0f, 0.0f, NULL);
            const pgt_march_event e = pgt_march_step(&v, &o, &s, 2.0f, 0.0f, &info);
            if (e_ref == PGT_MARCH_STOP) {
                stops++;
                other += e != PGT_MARCH_STOP;
                break;
            }
            evaluated++;
            if ((uint32_t)ref.x < v.width / 2u) {
                const int ok = e == e_ref && memcmp(&s, &ref, sizeof s) == 0;
                same += ok, other += !ok;
            } else {
                const int ok = e == PGT_MARCH_STOP && info.stop == PGT_MARCH_STOP_REJECTED &&
                               memcmp(&s, &before, sizeof s) == 0;
                rejected += ok, other += !ok;
                break;
            }
        }
        other += ctx.draws != evaluated;
    }
    printf("  binary density: %u steps as without a context, %u rejected where the density is "
           "0, %u otherwise, %u stops of their own\n",
           same, rejected, other, stops);
    CHECK(other == 0 && stops == 0 && same > 1000u && rejected > 100u);

    static const float ps[2] = {0.25f, 0.75f};
    for (int k = 0; k < 2; ++k) {
        const double p = ps[k];
        for (size_t i = 0; i < n; ++i) d[i] = ps[k];
        uint64_t sum = 0, zeros = 0, own_stops = 0, censored = 0;
        for (uint32_t w = 0; w < DENSITY_WALKERS; ++w) {
            pgt_march_density ctx;
            pgt_march_options o;
            pgt_march_state s;
            REQUIRE(density_walker(&v, d, 9, w, &ctx, &o, &s));
            uint32_t steps = 0;
            for (;; ++steps) {
                if (steps == 256u) { /* p^256 < 1e-31: never */
                    censored++;
                    break;
                }
                pgt_march_info info;
                if (pgt_march_step(&v, &o, &s, 2.0f, 0.0f, &info) == PGT_MARCH_STOP) {
                    own_stops += info.stop != PGT_MARCH_STOP_REJECTED;
                    break;
                }
            }
            sum += steps, zeros += steps == 0;
        }
        const double mean = (double)sum / DENSITY_WALKERS, p0 = (double)zeros / DENSITY_WALKERS;
        const double e_mean = p / (1.0 - p), se_mean = sqrt(p) / (1.0 - p) / sqrt(DENSITY_WALKERS);
        const double se_p0 = sqrt(p * (1.0 - p) / DENSITY_WALKERS);
        printf("  density %.2f, %u walkers: mean steps %.4f (expected %.4f +- %.4f), P(K = 0) "
               "%.4f (expected %.4f +- %.4f)\n",
               p, DENSITY_WALKERS, mean, e_mean, se_mean, p0, 1.0 - p, se_p0);
        CHECK(own_stops == 0 && censored == 0);
        CHECK_MSG(fabs(mean - e_mean) <= DENSITY_SIGMAS * se_mean, "mean %.4f", mean);
        CHECK_MSG(fabs(p0 - (1.0 - p)) <= DENSITY_SIGMAS * se_p0, "P(K = 0) %.4f", p0);
    }
    /* outside the image: rejected without a draw */
    pgt_march_density ctx = {d, v.width, v.height, 1, 0, 0};
    CHECK(!pgt_march_density_condition(&ctx, -0.5f, 3.0f, 0) && ctx.draws == 0);
    CHECK(!pgt_march_density_condition(&ctx, 3.0f, (float)v.height, 0) && ctx.draws == 0);
    free(d);
    pgt_march_atlas_destroy(&v);
    pgt_image_destroy(&img);
}

/* pgt_cli_read_context (pgt march / pgt ivy --mask, --density): the named channel first, then
 * Y; the values as written; a NaN or an infinity, a wrong size or no usable channel is an error
 * (nonzero, one line on stderr). */
static int write_context_exr(const char *path, const char *const *names, uint32_t channels,
                             float fill, uint32_t bad_x, float bad) {
    pgt_image img;
    if (pgt_image_create(&img, 6, 4, channels, names, NULL) != PGT_OK) return 0;
    for (uint32_t c = 0; c < channels; ++c)
        for (uint32_t i = 0; i < 24u; ++i) pgt_image_plane(&img, c)[i] = fill + (float)c;
    pgt_image_plane(&img, 0)[2u * 6u + bad_x] = bad;
    const int ok = pgt_image_write_exr(&img, path, NULL) == PGT_OK;
    pgt_image_destroy(&img);
    return ok;
}

static void test_read_context(void) {
    scratch_make_for("march_context");
    REQUIRE(scratch[0]);
    static const char *const yd[2] = {"Y", "density"}, *const ab[2] = {"A", "B"};
    float *out = NULL;
    /* 'density' (plane 1: 0.25 + 1) before 'Y' (plane 0) */
    REQUIRE(write_context_exr(scratch_path("yd.exr"), yd, 2, 0.25f, 3, 0.5f));
    CHECK(pgt_cli_read_context("test", "--density", scratch_path("yd.exr"), "density", 6, 4,
                               &out) == 0);
    CHECK(out && out[0] == 1.25f && out[23] == 1.25f);
    free(out), out = NULL;
    CHECK(pgt_cli_read_context("test", "--mask", scratch_path("yd.exr"), "mask", 6, 4, &out) == 0);
    CHECK(out && out[0] == 0.25f && out[2u * 6u + 3u] == 0.5f); /* 'Y' */
    free(out), out = NULL;
    const float bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < 3; ++k) {
        REQUIRE(write_context_exr(scratch_path("nan.exr"), yd + 1, 1, 0.5f, 3, bad[k]));
        CHECK(pgt_cli_read_context("test", "--density", scratch_path("nan.exr"), "density", 6, 4,
                                   &out) != 0 &&
              !out);
    }
    CHECK(pgt_cli_read_context("test", "--density", scratch_path("yd.exr"), "density", 6, 5,
                               &out) != 0 &&
          !out);
    REQUIRE(write_context_exr(scratch_path("ab.exr"), ab, 2, 0.5f, 0, 0.5f));
    CHECK(pgt_cli_read_context("test", "--density", scratch_path("ab.exr"), "density", 6, 4,
                               &out) != 0 &&
          !out);
    scratch_remove();
}

/* A float heading (cosf, sinf, then divided by its float length) against cos and sin in
 * double: a few float ulps of 1. */
#define HEADING_TOL 1e-6

/* pgt_march_random_starts: every walker starts on an inner texel of its chart with a unit
 * heading; the walkers are the ones march.h's formula gives (re-derived here try by try), the
 * same for the same seed and others for another; headings spread round the circle. */
static void test_random_starts(void) {
    syn_atlas s;
    REQUIRE(plane2(&s));
    pgt_march_atlas v;
    REQUIRE(view(&v, &s));
    enum { N = 500 };
    static float w[2][4][N];
    static uint32_t c[2][N];
    for (int k = 0; k < 2; ++k)
        REQUIRE(pgt_march_random_starts(&v, 7u + (uint32_t)k, N, w[k][0], w[k][1], w[k][2], w[k][3],
                                        c[k]) == 0);
    uint32_t bad = 0, per_chart[2] = {0, 0}, same_as_other_seed = 0;
    double mean_dx = 0.0, mean_dy = 0.0;
    for (uint32_t i = 0; i < N; ++i) {
        const float x = w[0][0][i], y = w[0][1][i], dx = w[0][2][i], dy = w[0][3][i];
        const uint32_t code = v.codes[(uint32_t)y * v.width + (uint32_t)x];
        bad += (code & 3u) != PGT_TEXEL_INNER || (code >> 2) != c[0][i] + 1u ||
               !near_f(dx * dx + dy * dy, 1.0f, 1e-6f);
        per_chart[c[0][i] & 1u]++;
        mean_dx += dx, mean_dy += dy;
        same_as_other_seed += x == w[1][0][i] && y == w[1][1][i];
    }
    CHECK(bad == 0);
    CHECK(per_chart[0] > N / 10 && per_chart[1] > N / 10);
    /* a uniform heading's components have mean 0 and variance 1/2: 5 sigma over N walkers */
    CHECK(fabs(mean_dx / N) < 5.0 * sqrt(0.5 / N) && fabs(mean_dy / N) < 5.0 * sqrt(0.5 / N));
    CHECK(same_as_other_seed == 0);
    /* walker 3, re-derived from march.h's formula: its first try that lands on an inner texel,
     * its heading (cos h, sin h) in double (the walker's: float cosf, sinf and normalisation) */
    for (uint32_t t = 0; t < PGT_MARCH_START_TRIES; ++t) {
        const uint64_t k = 3ull * (3ull * PGT_MARCH_START_TRIES + t);
        const float x = pgt_rng_float(7, 0, k) * (float)v.width,
                    y = pgt_rng_float(7, 0, k + 1) * (float)v.height,
                    h = 6.2831853f * pgt_rng_float(7, 0, k + 2);
        const uint32_t code = v.codes[(uint32_t)y * v.width + (uint32_t)x];
        if ((code & 3u) != PGT_TEXEL_INNER) continue;
        CHECK(w[0][0][3] == x && w[0][1][3] == y && c[0][3] + 1u == code >> 2);
        CHECK(fabs(w[0][2][3] - cos((double)h)) < HEADING_TOL &&
              fabs(w[0][3][3] - sin((double)h)) < HEADING_TOL);
        break;
    }
    /* the same seed, the same walkers */
    float again[4][N];
    uint32_t c_again[N];
    REQUIRE(pgt_march_random_starts(&v, 7, N, again[0], again[1], again[2], again[3], c_again) ==
            0);
    for (int k = 0; k < 4; ++k) CHECK(!memcmp(again[k], w[0][k], sizeof again[k]));
    CHECK(!memcmp(c_again, c[0], sizeof c_again));
    pgt_march_atlas_destroy(&v);
    syn_destroy(&s);
}

static const pgt_test_case cases[] = {
    {"view_and_start", test_view_and_start},
    {"random_starts", test_random_starts},
    {"case1_inner", test_case1_inner},
    {"case2_jump", test_case2_jump},
    {"case3_search", test_case3_search},
    {"case4_other_chart", test_case4_other_chart},
    {"remaining_length_3d", test_remaining_length_3d},
    {"multi_jump", test_multi_jump},
    {"dead_end_and_image_border", test_dead_end_and_image_border},
    {"binary_search", test_binary_search},
    {"best_pointer", test_best_pointer},
    {"rotation_keeps_3d_direction", test_rotation_keeps_3d_direction},
    {"cylinder_self_seam", test_cylinder_self_seam},
    {"mask_and_condition", test_mask_and_condition},
    {"batch_edges", test_batch_edges},
    {"density_context", test_density_context},
    {"read_context", test_read_context},
    {"too_many_jumps", test_too_many_jumps},
    {"bounce_pair", test_bounce_pair},
    {"bounce_across_steps", test_bounce_across_steps},
    {"invalid_atlases", test_invalid_atlases},
    {"random_walks_synthetic", test_random_walks_synthetic},
    {"position_image_border", test_position_image_border},
    {"hostile_atlases", test_hostile_atlases},
    {"real_cube_sphere_great_circle", test_real_cube_sphere_great_circle},
    {"real_random_marches", test_real_random_marches},
    {"jacobian_scale", test_jacobian_scale},
};

PGT_TEST_MAIN(cases)
