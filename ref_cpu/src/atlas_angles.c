/* pgt: atlas step 6, rotation of marching directions (paper 000 section 5.2, Fig. 6-7).
 *
 * For an indirection texel P0 of chart A pointing at texel Q of chart B:
 * - t1: "we start by scanning the one ring neighborhood of the current indirection pixel P0
 *   until we find the indirection pixel that follows an empty one. Then [...] we follow the K
 *   indirection pixels P_i and define t1 as the average of the vectors going from P0 to the
 *   visited pixels P_i." Here the path texels are A's outer-boundary texels (indirection and
 *   dead end), "empty" is any texel that is neither a path texel nor an inner texel of A.
 * - t2: the same walk from Q over B's inner-boundary texels, "empty" being any texel that is not
 *   an inner texel of B.
 * The ring is scanned clockwise on screen (E, SE, S, SW, W, NW, N, NE with y down), starting
 * after the texel the walk came from, and a step goes to the first path texel whose
 * predecessor in that order is empty. That walks every boundary with its own chart on the right
 * (clockwise on screen). Across a seam A and B lie on opposite sides, so the walk of B is
 * reversed: t2 = -(walk of B), and then a direction making the angle alpha with t1 leaves A
 * where the direction making alpha with t2 enters B (Fig. 6).
 * rot = atan2(t1 x t2, t1 . t2) in texel coordinates (x right, y down); see atlas_build.h for
 * how a marcher applies it. A walk that cannot start (an isolated texel) gives rot = 0. */
#include <math.h>

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
} angle_ctx;

enum { WALK_OUTER = 0, WALK_INNER = 1 };

/* 1: path texel, 0: empty, -1: neither (an inner texel that is not a path texel). */
static int texel_class(const angle_ctx *c, int mode, int32_t chart, int32_t x, int32_t y) {
    if (x < 0 || y < 0 || x >= c->W || y >= c->H) return 0;
    const size_t i = (size_t)y * (size_t)c->W + (size_t)x;
    const uint8_t k = c->kind[i] & (uint8_t)~ATLAS_KIND_BOUNDARY_BIT;
    if (mode == WALK_OUTER) {
        if ((k == PGT_TEXEL_INDIRECTION || k == PGT_TEXEL_DEAD_END) &&
            c->outer_chart[i] == (float)chart)
            return 1;
        return c->chart[i] == chart ? -1 : 0;
    }
    if (c->chart[i] != chart) return 0;
    return (c->kind[i] & ATLAS_KIND_BOUNDARY_BIT) ? 1 : -1;
}

/* Sum of the vectors from (x0, y0) to the next k texels of the walk (t up to a positive
 * factor, the average of 5.2). */
static void walk(const angle_ctx *c, int mode, int32_t chart, int32_t x0, int32_t y0, double *tx,
                 double *ty) {
    int32_t x = x0, y = y0;
    int back = -1;
    *tx = 0.0, *ty = 0.0;
    for (uint32_t s = 0; s < c->k; ++s) {
        int found = -1;
        const int start = back < 0 ? 0 : back + 1;
        int prev_class =
            texel_class(c, mode, chart, x + ring[(start + 7) % 8][0], y + ring[(start + 7) % 8][1]);
        for (int j = 0; j < 8; ++j) {
            const int i = (start + j) % 8;
            const int cls = texel_class(c, mode, chart, x + ring[i][0], y + ring[i][1]);
            if (cls == 1 && prev_class == 0) {
                found = i;
                break;
            }
            prev_class = cls;
        }
        if (found < 0) break;
        x += ring[found][0], y += ring[found][1];
        back = (found + 4) % 8;
        if (x == x0 && y == y0) break;
        *tx += x - x0, *ty += y - y0;
    }
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
            const int32_t a = (int32_t)c->outer_chart[i];
            const int32_t b = c->chart[(size_t)qy * (size_t)c->W + (size_t)qx];
            double t1x, t1y, t2x, t2y;
            walk(c, WALK_OUTER, a, x, y, &t1x, &t1y);
            walk(c, WALK_INNER, b, qx, qy, &t2x, &t2y);
            t2x = -t2x, t2y = -t2y;
            if ((t1x == 0.0 && t1y == 0.0) || (t2x == 0.0 && t2y == 0.0)) {
                rot[i] = 0.0f;
                continue;
            }
            rot[i] = (float)atan2(t1x * t2y - t1y * t2x, t1x * t2x + t1y * t2y);
        }
}

void atlas_angles(pgt_image *atlas, const int32_t *texel_chart, const uint8_t *kind, uint32_t k,
                  uint32_t threads) {
    angle_ctx c = {atlas,
                   texel_chart,
                   kind,
                   pgt_image_plane(atlas, 6),
                   (int32_t)atlas->width,
                   (int32_t)atlas->height,
                   k};
    atlas_parallel_rows(atlas->height, atlas->width, threads, angle_rows, &c);
}
