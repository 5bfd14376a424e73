/* pgt: atlas step 4, indirection pointers (paper 000 section 4, Fig. 2a; after Lefebvre and
 * Hoppe 2006).
 *
 * Classification (atlas.h): an inner texel is inner-boundary when a 4-neighbour is not an inner
 * texel of its chart (or lies outside the image); a non-inner texel 8-adjacent to inner texels of
 * exactly one chart c is an outer-boundary texel of c. For each outer-boundary texel, p = the
 * mean 3D position of its 8-adjacent inner-boundary texels of c ("we compute its closest 3D
 * surface position p by averaging the adjacent texels lying on the inner-boundary of the
 * chart"); its pointer is the inner-boundary texel nearest to p in 3D (kd-tree, ties to the
 * smallest texel index) among the texels of the other charts, and of c itself across a seam
 * inside c (accept_candidate: the way through the chart much longer than the way through
 * space). A candidate counts when it lies within dead_end texel sizes of p, measured in the
 * larger of the median texel size (pgt_atlas_texel_size) and the source's local one, or in the
 * candidate's own local size away from the mesh border (ATLAS_DEAD_END_FAR_REACHES,
 * ATLAS_BORDER_TEXELS); with none, the texel is a dead end next to the mesh border or a gap
 * (an edge with nothing rasterized across: atlas_border), and away from them points to the
 * nearest texel of its own chart beyond the 3 x 3 texels around it (accept_own_chart).
 * Every query is independent: any thread count gives the same bytes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "alloc_internal.h"
#include "atlas_internal.h"
#include "pgt/kdtree.h"
#include "pgt/parallel.h"

static const int32_t nb8[8][2] = {{1, 0},  {1, 1},   {0, 1},  {-1, 1},
                                  {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};

/* Counts per row of pointer_rows (summed in atlas_pointers): indirection texels, dead ends,
 * pointers into their own chart, and those of them the own-chart fallback made. */
#define ROW_COUNTS 4u

typedef struct ptr_ctx {
    pgt_image *atlas;
    const int32_t *chart;
    const uint32_t *crack; /* per texel: atlas_fill_cracks's record, or NULL */
    uint8_t *kind;
    int32_t *dest_chart;
    uint32_t W, H;
    /* inner-boundary texels in row-major order */
    uint32_t *row_boundary; /* H + 1: per-row counts, then prefix sums */
    uint32_t *b_texel;
    int32_t *b_chart;
    float *b_xyz;
    float *leaf_reach2; /* in leaf order: (dead_end x local_step in its own chart)^2 */
    float *node_reach2; /* per kd-tree node: the largest leaf_reach2 of its points */
    pgt_kdtree tree;
    int32_t *leaf_chart; /* b_chart in the tree's leaf order */
    const float *P[3];   /* the position planes */
    double texel_size, dead_end;
    uint32_t *row_counts; /* ROW_COUNTS per row: indirection, dead end, self seam, own-chart
                             fallback */
    /* per texel, set on inner-boundary texels only: local_step in its chart (8 bytes a texel,
     * 8 MiB at 1024^2; double, the precision the reach has always been computed in) */
    double *local;
    uint8_t *near_border;   /* per texel: NEAR_MESH_BORDER within ATLAS_BORDER_TEXELS of a
                               mesh-border edge, | NEAR_GAP of a gap's (atlas_border) */
    int32_t *classify_cols; /* per worker: 2 W (classify_rows) */
} ptr_ctx;

/* The border texels of the image (first and last row and column): the tests of classify_rows
 * with the image-border checks. */
static uint8_t classify_border(const ptr_ctx *c, int32_t x, int32_t y, uint32_t *boundary) {
    const int32_t W = (int32_t)c->W, H = (int32_t)c->H;
    const int32_t own = c->chart[(size_t)y * (size_t)W + (size_t)x];
    if (own >= 0) {
        for (uint32_t i = 0; i < 8; i += 2) { /* the 4-neighbours */
            const int32_t nx = x + nb8[i][0], ny = y + nb8[i][1];
            if (nx < 0 || ny < 0 || nx >= W || ny >= H ||
                c->chart[(size_t)ny * (size_t)W + (size_t)nx] != own) {
                (*boundary)++;
                return PGT_TEXEL_INNER | ATLAS_KIND_BOUNDARY_BIT;
            }
        }
        return PGT_TEXEL_INNER;
    }
    int32_t lo = INT32_MAX, hi = -1;
    for (uint32_t i = 0; i < 8; ++i) {
        const int32_t nx = x + nb8[i][0], ny = y + nb8[i][1];
        if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
        const int32_t o = c->chart[(size_t)ny * (size_t)W + (size_t)nx];
        if (o < 0) continue;
        if (o < lo) lo = o;
        if (o > hi) hi = o;
    }
    /* touching two charts breaks the band contract: left as background */
    return hi >= 0 && lo == hi ? PGT_TEXEL_INDIRECTION : PGT_TEXEL_BACKGROUND;
}

static void classify_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    ptr_ctx *c = vctx;
    const int32_t W = (int32_t)c->W, H = (int32_t)c->H;
    /* per column x of the three rows y - 1 .. y + 1: the largest chart id (-1 when none) and
     * the smallest (INT32_MAX when none); the 3 x 3 block of a texel is three such columns.
     * A background texel's own -1 changes neither, so the block can include it. Branch-free
     * loops over whole rows: the compiler vectorizes them. */
    int32_t *col_hi = &c->classify_cols[(size_t)worker * 2u * (size_t)W], *col_lo = col_hi + W;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; ++y) {
        uint32_t boundary = 0;
        const int32_t *row = &c->chart[(size_t)y * (size_t)W];
        uint8_t *kind = &c->kind[(size_t)y * (size_t)W];
        if (y == 0 || y + 1 == H || W < 3) {
            for (int32_t x = 0; x < W; ++x) kind[x] = classify_border(c, x, y, &boundary);
            c->row_boundary[y + 1] = boundary;
            continue;
        }
        const int32_t *up = row - W, *down = row + W;
        for (int32_t x = 0; x < W; ++x) {
            const int32_t a = up[x], b = row[x], d = down[x];
            const int32_t hi = a > b ? a : b;
            col_hi[x] = hi > d ? hi : d;
            const uint32_t ua = (uint32_t)a, ub = (uint32_t)b, ud = (uint32_t)d;
            /* as unsigned, -1 is the largest value: the smallest is a chart id when any */
            const uint32_t lo = ua < ub ? ua : ub, lo3 = lo < ud ? lo : ud;
            col_lo[x] = lo3 > (uint32_t)INT32_MAX ? INT32_MAX : (int32_t)lo3;
        }
        kind[0] = classify_border(c, 0, y, &boundary);
        for (int32_t x = 1; x + 1 < W; ++x) {
            const int32_t own = row[x];
            const int32_t h0 = col_hi[x - 1] > col_hi[x] ? col_hi[x - 1] : col_hi[x];
            const int32_t hi = h0 > col_hi[x + 1] ? h0 : col_hi[x + 1];
            const int32_t l0 = col_lo[x - 1] < col_lo[x] ? col_lo[x - 1] : col_lo[x];
            const int32_t lo = l0 < col_lo[x + 1] ? l0 : col_lo[x + 1];
            const uint32_t edge =
                (row[x + 1] != own) | (down[x] != own) | (row[x - 1] != own) | (up[x] != own);
            const uint32_t inner = own >= 0;
            const uint8_t outer =
                ((hi >= 0) & (lo == hi)) ? PGT_TEXEL_INDIRECTION : PGT_TEXEL_BACKGROUND;
            kind[x] =
                inner ? (uint8_t)(PGT_TEXEL_INNER | (edge ? ATLAS_KIND_BOUNDARY_BIT : 0u)) : outer;
            boundary += inner & edge;
        }
        kind[W - 1] = classify_border(c, W - 1, y, &boundary);
        c->row_boundary[y + 1] = boundary;
    }
}

static double local_step(const ptr_ctx *c, int32_t x, int32_t y, int32_t chart);

static void gather_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    ptr_ctx *c = vctx;
    (void)worker;
    const float *P[3] = {pgt_image_plane(c->atlas, 0), pgt_image_plane(c->atlas, 1),
                         pgt_image_plane(c->atlas, 2)};
    for (uint32_t y = y0; y < y1; ++y) {
        uint32_t j = c->row_boundary[y];
        for (uint32_t x = 0; x < c->W; ++x) {
            const size_t idx = (size_t)y * c->W + x;
            if (!(c->kind[idx] & ATLAS_KIND_BOUNDARY_BIT)) continue;
            c->b_texel[j] = (uint32_t)idx;
            c->b_chart[j] = c->chart[idx];
            for (uint32_t k = 0; k < 3; ++k) c->b_xyz[3u * j + k] = P[k][idx];
            /* an inner-boundary texel starts the pointers of about three outer texels and is
             * a candidate of many: its local step is computed once */
            c->local[idx] = local_step(c, (int32_t)x, (int32_t)y, c->chart[idx]);
            j++;
        }
    }
}

typedef struct accept_ctx {
    const ptr_ctx *c;
    int32_t chart;
    int32_t x, y;         /* the outer-boundary texel */
    int32_t sx[8], sy[8]; /* its adjacent inner-boundary texels */
    double local[8];      /* per start: the largest 3D step to its 4-neighbours in the chart */
    uint32_t starts;
    int crack_only; /* every start is a texel filled in a seam's crack */
    int in_crack;   /* the texel lies in a seam's crack (filled in part) or touches its fill */
} accept_ctx;

/* Squared 3D distance between texels i and j (double). */
static double dist3_sq(const ptr_ctx *c, size_t i, size_t j) {
    double e = 0.0;
    for (uint32_t k = 0; k < 3; ++k) {
        const double t = (double)c->P[k][j] - c->P[k][i];
        e += t * t;
    }
    return e;
}

static double dist3(const ptr_ctx *c, size_t i, size_t j) { return sqrt(dist3_sq(c, i, j)); }

/* The largest 3D step from texel (x, y) to its 4-neighbours in `chart` (0 when none): the
 * square root of the largest square, which is the largest root (sqrt is monotonic). */
static double local_step(const ptr_ctx *c, int32_t x, int32_t y, int32_t chart) {
    const size_t s = (size_t)y * c->W + (size_t)x;
    double e = 0.0;
    for (uint32_t i = 0; i < 8; i += 2) {
        const int32_t nx = x + nb8[i][0], ny = y + nb8[i][1];
        if (nx < 0 || ny < 0 || nx >= (int32_t)c->W || ny >= (int32_t)c->H) continue;
        const size_t j = (size_t)ny * c->W + (size_t)nx;
        if (c->chart[j] != chart) continue;
        const double d = dist3_sq(c, s, j);
        if (d > e) e = d;
    }
    return sqrt(e);
}

/* Per kd-tree slot: the chart, and the squared reach of the texel's own side. */
static void leaf_rows(void *vctx, uint32_t i0, uint32_t i1, uint32_t worker) {
    ptr_ctx *c = vctx;
    (void)worker;
    for (uint32_t i = i0; i < i1; ++i) {
        const uint32_t id = c->tree.ids[i];
        const size_t t = c->b_texel[id];
        c->leaf_chart[i] = c->b_chart[id];
        const double r = c->dead_end * c->local[t];
        c->leaf_reach2[i] = (float)(r * r);
    }
}

/* A texel of the source's own chart is a candidate only across a seam inside the chart: the
 * way through the chart must be much longer than the way through space. The test walks the
 * texel line from the source's adjacent inner-boundary texel nearest to the candidate (the
 * start) to the candidate, summing the 3D steps between successive inner texels of the chart,
 * and one local texel size (the largest 3D step from the start to its 4-neighbours) for every
 * texel of the line outside the chart. The candidate is accepted when that path is longer than
 * ATLAS_SELF_SEAM_PATH_RATIO times the 3D distance from the start, and, for a line that stays
 * inside the chart, when it lies farther than PGT_ATLAS_SELF_SEAM_MIN_TEXELS from the source
 * texel. So:
 * - a cylinder cut open inside one chart: the line crosses the chart, the path is the way
 *   around the cylinder, the distance across the cut about one texel: accepted;
 * - a slit cut inside a chart (its sides glued, the slit narrower than a few texels): the line
 *   crosses the slit, the path counts its texels, the sides are at the same 3D place: accepted;
 * - one side of a mesh border, however squeezed by the parametrization, or across a hole of
 *   the chart that is not glued: path and distance are about equal: refused. */
/* Path length / 3D distance above which the two ends are on two sides of a seam: a straight
 * texel line on one side of a smooth chart has a ratio near 1 (curvature and the rounding of
 * the texel line add a few percent), while across a seam the distance is about one texel size
 * and the path several. */
#define ATLAS_SELF_SEAM_PATH_RATIO 2.0

static int accept_candidate(const void *vctx, uint32_t id, uint32_t slot) {
    const accept_ctx *a = vctx;
    const ptr_ctx *c = a->c;
    if (c->leaf_chart[slot] != a->chart) return 1;
    const uint32_t t = c->b_texel[id];
    const int32_t qx = (int32_t)(t % c->W), qy = (int32_t)(t / c->W);
    uint32_t best = 0;
    int64_t best_d = INT64_MAX;
    for (uint32_t i = 0; i < a->starts; ++i) {
        const int64_t ex = qx - a->sx[i], ey = qy - a->sy[i], d = ex * ex + ey * ey;
        if (d < best_d) best_d = d, best = i;
    }
    const int32_t x0 = a->sx[best], y0 = a->sy[best];
    const size_t s0 = (size_t)y0 * c->W + (size_t)x0;
    const int32_t ex = qx - x0, ey = qy - y0;
    const int32_t n = abs(ex) > abs(ey) ? abs(ex) : abs(ey);
    /* the nearest kd-tree points are mostly the starts themselves (an empty line) and their
     * neighbours along the boundary (a line inside the chart, near the source): both are
     * refused below without a 3D step, so they are refused here first */
    if (n == 0) return 0;
    /* an outer texel touching only a crack's fill (where a crack stops being filled, between
     * its two sides): any texel of the chart but its starts is across */
    if (a->crack_only) return 1;
    const double dx = (double)qx - a->x, dy = (double)qy - a->y;
    const int far = dx * dx + dy * dy >
                    (double)PGT_ATLAS_SELF_SEAM_MIN_TEXELS * (double)PGT_ATLAS_SELF_SEAM_MIN_TEXELS;
    if (!far || a->in_crack) {
        int32_t i = 1;
        for (; i <= n; ++i) {
            const int32_t x = x0 + (int32_t)floor(ex * (double)i / n + 0.5);
            const int32_t y = y0 + (int32_t)floor(ey * (double)i / n + 0.5);
            if (c->chart[(size_t)y * c->W + (size_t)x] != a->chart) break;
        }
        /* across a crack (its sides the same 3D place, its texels none: the path below has
         * nothing to measure) a line leaving the chart is enough */
        if (i <= n && a->in_crack) return 1;
        if (i > n && !far) return 0; /* only a line that leaves the chart can be accepted */
    }
    const double local = a->local[best];
    const double limit = ATLAS_SELF_SEAM_PATH_RATIO * dist3(c, s0, t);
    double path = 0.0;
    size_t prev = s0;
    uint32_t gaps = 0;
    int after_gap = 0;
    for (int32_t i = 1; i <= n; ++i) {
        const int32_t x = x0 + (int32_t)floor(ex * (double)i / n + 0.5);
        const int32_t y = y0 + (int32_t)floor(ey * (double)i / n + 0.5);
        const size_t j = (size_t)y * c->W + (size_t)x;
        if (c->chart[j] != a->chart) {
            gaps++, after_gap = 1;
        } else {
            if (!after_gap) path += dist3(c, prev, j); /* a gap counts in texels, below */
            after_gap = 0;
            prev = j;
        }
        /* the path only grows: decided as soon as it passes the limit */
        if ((far || gaps) && path + gaps * local > limit) return 1;
    }
    return 0;
}

/* A texel of the source's own chart outside the 3 x 3 texels around it (its starts, and the
 * crack's filled texels next to it, which are no starts): the fallback of an outer texel away
 * from the mesh border that found nothing across (see pointer_rows). */
static int accept_own_chart(const void *vctx, uint32_t id, uint32_t slot) {
    const accept_ctx *a = vctx;
    const ptr_ctx *c = a->c;
    if (c->leaf_chart[slot] != a->chart) return 0;
    const uint32_t t = c->b_texel[id];
    const int32_t qx = (int32_t)(t % c->W), qy = (int32_t)(t / c->W);
    return abs(qx - a->x) > 1 || abs(qy - a->y) > 1;
}

/* The reach counts on both sides of a seam: a candidate q beyond the source's reach is taken
 * when it lies within dead_end of q's own local texel sizes (pgt_kdtree_nearest_reach). A seam
 * whose two sides have texels of very different 3D size (spot's leg caps: 8-13 times) puts the
 * partner of a fine-side texel several of the source's reaches away, but within the partner
 * side's: without this closed spot had 62 dead-end texels (the farthest of them 1.7 source
 * reaches from its partner). Not next to the mesh border (ATLAS_BORDER_TEXELS), where nothing
 * lies across. The search stops at this many reaches of the source: across a seam the partner
 * lies within about 1.5 of its own texel sizes, 1.5 R / 4 source reaches for texels R times the
 * source's, so 8 serves seams up to R = 20 and bounds what a texel of a degenerate, very long
 * triangle can claim. */
#define ATLAS_DEAD_END_FAR_REACHES 8.0

/* How near (texels, centre to edge) a mesh-border edge passes an outer-boundary texel that keeps
 * the reach of its own side only: the chart's boundary passes between an outer texel's centre
 * and the centre of an adjacent inner texel, so within sqrt(2) texels of it; 1.5 takes that
 * with room for rounding. Such a texel is next to the mesh border (or a corner where the
 * border meets a seam), where nothing lies across: a candidate found only by counting its own
 * side's reach would be a texel of some other part of the mesh (pizza's rim, whose texels reach
 * charts 6 source reaches away through stretched texels). */
#define ATLAS_BORDER_TEXELS 1.5

/* near_border's bits: next to the mesh border (the far reach is not used there), next to a gap
 * (nothing rasterized across: no own-chart fallback there either). */
#define NEAR_MESH_BORDER 1u
#define NEAR_GAP 2u

/* Sets `bit` in near_border on the texels whose centre lies within ATLAS_BORDER_TEXELS of one
 * of the half-edges: each is walked in half-texel samples, each testing the 5 x 5 texels around
 * it (the exact distance to the edge decides). Serial: a mesh has few border edges against its
 * texels. */
static void mark_edges(ptr_ctx *c, const float *tex, const uint32_t *half_edges, uint32_t count,
                       uint8_t bit) {
    const int32_t W = (int32_t)c->W, H = (int32_t)c->H;
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t h = half_edges[i], f = h / 3u, k0 = h % 3u, k1 = (k0 + 1u) % 3u;
        const double ax = tex[6u * f + 2u * k0], ay = tex[6u * f + 2u * k0 + 1u];
        const double ex = tex[6u * f + 2u * k1] - ax, ey = tex[6u * f + 2u * k1 + 1u] - ay;
        const double len2 = ex * ex + ey * ey;
        const uint32_t samples = 1u + (uint32_t)ceil(2.0 * sqrt(len2));
        for (uint32_t s = 0; s <= samples; ++s) {
            const double px = ax + ex * s / samples, py = ay + ey * s / samples;
            for (int32_t y = (int32_t)floor(py) - 2; y <= (int32_t)floor(py) + 2; ++y)
                for (int32_t x = (int32_t)floor(px) - 2; x <= (int32_t)floor(px) + 2; ++x) {
                    if (x < 0 || y < 0 || x >= W || y >= H) continue;
                    /* the centre's distance to the edge a -> a + e */
                    const double cx = x + 0.5 - ax, cy = y + 0.5 - ay;
                    double t = len2 > 0.0 ? (cx * ex + cy * ey) / len2 : 0.0;
                    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
                    const double dx = cx - t * ex, dy = cy - t * ey;
                    if (dx * dx + dy * dy <= ATLAS_BORDER_TEXELS * ATLAS_BORDER_TEXELS)
                        c->near_border[(size_t)y * c->W + (size_t)x] |= bit;
                }
        }
    }
}

/* The first search radius, as a fraction of the dead-end reach: on pizza.obj (4740 charts)
 * 94 % of the pointers lie within 0.3 of the reach and 98 % within 0.4; a miss costs a second,
 * full search. */
#define ATLAS_POINTER_NEAR_REACH 0.4

/* The starts of outer texel (x, y): its 8-adjacent inner-boundary texels into a->sx, sy, the
 * sum of their P into p and their chart into *chart; skip_fill: not the texels filled in a
 * seam's crack (*touches = 1 when there was one). */
static inline uint32_t gather_starts(const ptr_ctx *c, float *const P[3], int32_t x, int32_t y,
                                     int skip_fill, accept_ctx *a, double p[3], int32_t *chart,
                                     int *touches) {
    const int32_t W = (int32_t)c->W, H = (int32_t)c->H;
    uint32_t n = 0;
    for (uint32_t i = 0; i < 8; ++i) {
        const int32_t nx = x + nb8[i][0], ny = y + nb8[i][1];
        if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
        const size_t j = (size_t)ny * (size_t)W + (size_t)nx;
        if (!(c->kind[j] & ATLAS_KIND_BOUNDARY_BIT)) continue;
        if (skip_fill && ATLAS_CRACK_FILLED(c->crack[j])) {
            *touches = 1;
            continue;
        }
        *chart = c->chart[j];
        for (uint32_t k = 0; k < 3; ++k) p[k] += P[k][j];
        a->sx[n] = nx, a->sy[n] = ny;
        n++;
    }
    return n;
}

static void pointer_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    ptr_ctx *c = vctx;
    const int32_t W = (int32_t)c->W;
    (void)worker;
    float *P[3], *N[3];
    for (uint32_t k = 0; k < 3; ++k)
        P[k] = pgt_image_plane(c->atlas, k), N[k] = pgt_image_plane(c->atlas, 3u + k);
    float *chart_plane = pgt_image_plane(c->atlas, 6), *kind_plane = pgt_image_plane(c->atlas, 7);
    float *pu = pgt_image_plane(c->atlas, 8), *pv = pgt_image_plane(c->atlas, 9),
          *rot = pgt_image_plane(c->atlas, 10);
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; ++y) {
        uint32_t *cnt = &c->row_counts[ROW_COUNTS * (uint32_t)y];
        memset(cnt, 0, ROW_COUNTS * sizeof *cnt);
        for (int32_t x = 0; x < W; ++x) {
            const size_t idx = (size_t)y * (size_t)W + (size_t)x;
            pu[idx] = -1.0f, pv[idx] = -1.0f, rot[idx] = 0.0f;
            if (c->kind[idx] != PGT_TEXEL_INDIRECTION) continue;
            /* the chart, and p: the mean of the adjacent inner-boundary texels */
            int32_t chart = -1;
            double p[3] = {0.0, 0.0, 0.0};
            uint32_t n = 0;
            accept_ctx a;
            a.c = c, a.x = x, a.y = y;
            /* texels filled in a seam's crack (atlas_fill_cracks) lie on the seam itself, at
             * the same 3D place as both its sides: they are starts only where nothing else
             * is (then the own chart's other texels are candidates, crack_only); without
             * cracks the loop has no test for them (the atlases of most meshes) */
            int touches_fill = 0;
            n = c->crack ? gather_starts(c, P, x, y, 1, &a, p, &chart, &touches_fill)
                         : gather_starts(c, P, x, y, 0, &a, p, &chart, &touches_fill);
            a.crack_only = n == 0;
            if (n == 0) n = gather_starts(c, P, x, y, 0, &a, p, &chart, &touches_fill);
            a.in_crack = touches_fill || (c->crack && c->crack[idx]);
            /* n >= 1: an inner texel 8-adjacent to a non-inner texel has a non-inner
             * 4-neighbour (the texel itself, or one of the two texels between them) */
            const float q[3] = {(float)(p[0] / n), (float)(p[1] / n), (float)(p[2] / n)};
            a.chart = chart, a.starts = n;
            /* the dead-end threshold counts in the larger of the median texel size and the
             * local one (the largest 3D step from the adjacent inner-boundary texels to their
             * 4-neighbours in the chart): a chart stretched near its boundary has texels
             * several median sizes long, and its seam partner lies that far */
            double local = 0.0;
            for (uint32_t s = 0; s < n; ++s) {
                a.local[s] = c->local[(size_t)a.sy[s] * c->W + (size_t)a.sx[s]];
                if (a.local[s] > local) local = a.local[s];
            }
            const double reach = c->dead_end * fmax(c->texel_size, local);
            float d2 = 0.0f;
            /* the nearest accepted point within reach: first within a smaller ball, which
             * prunes most of the tree (the same answer when it holds one), else the whole */
            const double near = ATLAS_POINTER_NEAR_REACH * reach;
            uint32_t hit =
                pgt_kdtree_nearest(&c->tree, q, (float)(near * near), accept_candidate, &a, &d2);
            if (hit == PGT_NONE) { /* next to the mesh border, the source's reach alone */
                const double far = (c->near_border[idx] & NEAR_MESH_BORDER)
                                       ? reach
                                       : ATLAS_DEAD_END_FAR_REACHES * reach;
                hit = pgt_kdtree_nearest_reach(&c->tree, q, (float)(reach * reach),
                                               (float)(far * far), c->leaf_reach2, c->node_reach2,
                                               accept_candidate, &a, &d2);
            }
            if (hit == PGT_NONE && !c->near_border[idx]) {
                /* Away from the mesh border the surface goes on: where a slit cut into a chart
                 * closes (its two sides joined at its end, so that no texel near the end is
                 * "across"), the outer texels at the end found nothing; they point to the
                 * nearest texel of their own chart beyond the texels around them instead of
                 * stopping walkers on a closed mesh (bob_tri at --res 48 to 384: 1-3 such dead
                 * ends). The border here is every edge with nothing rasterized across (the mesh
                 * border, degenerate UV triangles, charts without texels: atlas_build.c). */
                hit = pgt_kdtree_nearest(&c->tree, q, (float)(reach * reach), accept_own_chart, &a,
                                         &d2);
                cnt[3] += hit != PGT_NONE;
            }
            chart_plane[idx] = (float)chart;
            for (uint32_t k = 0; k < 3; ++k) N[k][idx] = 0.0f;
            if (hit == PGT_NONE) { /* the kind buffer keeps INDIRECTION for every outer texel */
                c->dest_chart[idx] = -1;
                kind_plane[idx] = (float)PGT_TEXEL_DEAD_END;
                for (uint32_t k = 0; k < 3; ++k) P[k][idx] = 0.0f;
                cnt[1]++;
                continue;
            }
            const uint32_t t = c->b_texel[hit];
            c->dest_chart[idx] = c->b_chart[hit];
            kind_plane[idx] = (float)PGT_TEXEL_INDIRECTION;
            for (uint32_t k = 0; k < 3; ++k) P[k][idx] = q[k];
            pu[idx] = (float)(t % c->W);
            pv[idx] = (float)(t / c->W);
            cnt[0]++;
            if (c->b_chart[hit] == chart) cnt[2]++;
        }
    }
}

/* Bins of the radix selection: 16 bits of a float's pattern a pass. */
#define SELECT_BINS 65536u

typedef struct select_ctx {
    const float *v;
    const uint32_t *count;
    size_t stride;
    uint32_t *hist; /* per worker: SELECT_BINS counts */
    uint32_t high;  /* the second pass: the high half sought (UINT32_MAX in the first) */
} select_ctx;

/* The worker's histogram of rows [y0, y1): of the high 16 bits of every value (first pass), or
 * of the low 16 bits of the values whose high half is `high` (second pass). */
static void histogram_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    const select_ctx *s = vctx;
    uint32_t *hist = &s->hist[(size_t)worker * SELECT_BINS];
    const uint32_t high = s->high;
    for (uint32_t y = y0; y < y1; ++y) {
        const float *v = &s->v[s->stride * y];
        const uint32_t n = s->count[y];
        uint32_t bits;
        if (high == UINT32_MAX) {
            for (uint32_t i = 0; i < n; ++i) memcpy(&bits, &v[i], 4), hist[bits >> 16]++;
        } else {
            for (uint32_t i = 0; i < n; ++i)
                if (memcpy(&bits, &v[i], 4), bits >> 16 == high) hist[bits & 0xFFFFu]++;
        }
    }
}

/* The bin of the workers' summed histograms that holds rank *k; *k becomes the rank in it. */
static uint32_t rank_bin(const uint32_t *hist, uint32_t workers, size_t *k) {
    for (uint32_t b = 0;; ++b) {
        size_t n = 0;
        for (uint32_t w = 0; w < workers; ++w) n += hist[(size_t)w * SELECT_BINS + b];
        if (b + 1u == SELECT_BINS || *k < n) return b;
        *k -= n;
    }
}

/* The k-th smallest (0-based) of the non-negative floats in rows of `v` (row y holds count[y]
 * <= stride values from v + stride * y): their bit patterns sort like the values, so two 16-bit
 * radix histograms find it exactly (no sort, no recursion), each pass over the rows on up to
 * `threads` threads with a histogram per worker. */
static float select_nonnegative(const float *v, const uint32_t *count, uint32_t rows, size_t stride,
                                size_t k, uint32_t threads) {
    const uint32_t workers = pgt_parallel_workers(threads);
    uint32_t *hist = calloc((size_t)workers * SELECT_BINS, sizeof(uint32_t));
    if (!hist) return 0.0f;
    select_ctx s = {v, count, stride, hist, UINT32_MAX};
    atlas_parallel_rows(rows, (uint32_t)stride, workers, histogram_rows, &s);
    s.high = rank_bin(hist, workers, &k);
    memset(hist, 0, (size_t)workers * SELECT_BINS * sizeof(uint32_t));
    atlas_parallel_rows(rows, (uint32_t)stride, workers, histogram_rows, &s);
    const uint32_t low = rank_bin(hist, workers, &k), bits = s.high << 16 | low;
    free(hist);
    float out;
    memcpy(&out, &bits, 4);
    return out;
}

typedef struct size_ctx {
    const float *P[3], *chart, *kind;
    uint32_t W, H;
    float *d;                   /* 2 W per row */
    uint32_t *count;            /* per row */
    const int32_t *texel_chart; /* not NULL: the chart and kind planes as atlas_raster left
                                 * them (inner iff texel_chart >= 0), read from here instead */
} size_ctx;

/* Squared 3D distances (double, rounded to float once) to the right and lower neighbours, when
 * both are inner texels of one chart: the median of the squares is the square of the median,
 * so no square root per pair. */
/* The chart of texel i when it is an inner texel, else -1. */
static inline int32_t size_owner(const size_ctx *c, size_t i) {
    if (c->texel_chart) return c->texel_chart[i];
    return c->kind[i] == (float)PGT_TEXEL_INNER ? (int32_t)c->chart[i] : -1;
}

static void size_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    size_ctx *c = vctx;
    (void)worker;
    const uint32_t W = c->W;
    for (uint32_t y = y0; y < y1; ++y) {
        float *d = &c->d[2u * (size_t)W * y];
        uint32_t m = 0;
        for (uint32_t x = 0; x < W; ++x) {
            const size_t i = (size_t)y * W + x;
            const int32_t own = size_owner(c, i);
            if (own < 0) continue;
            for (uint32_t s = 0; s < 2; ++s) {
                if (s == 0 ? x + 1u >= W : y + 1u >= c->H) continue;
                const size_t j = s == 0 ? i + 1u : i + W;
                if (size_owner(c, j) != own) continue;
                double e = 0.0;
                for (uint32_t k = 0; k < 3; ++k) {
                    const double t = (double)c->P[k][j] - c->P[k][i];
                    e += t * t;
                }
                d[m++] = (float)e;
            }
        }
        c->count[y] = m;
    }
}

static double texel_size(const pgt_image *atlas, const pgt_atlas_channels *ch, uint32_t threads,
                         const int32_t *texel_chart) {
    const uint32_t W = atlas->width, H = atlas->height;
    size_ctx c = {{pgt_image_plane(atlas, ch->px), pgt_image_plane(atlas, ch->py),
                   pgt_image_plane(atlas, ch->pz)},
                  pgt_image_plane(atlas, ch->chart),
                  pgt_image_plane(atlas, ch->kind),
                  W,
                  H,
                  malloc(sizeof(float) * 2u * (size_t)W * H + 1u),
                  calloc((size_t)H + 1u, sizeof(uint32_t)),
                  texel_chart};
    double med = 0.0;
    if (c.d && c.count) {
        atlas_parallel_rows(H, W, threads, size_rows, &c);
        size_t n = 0;
        for (uint32_t y = 0; y < H; ++y) n += c.count[y];
        /* the lower median for an even count */
        if (n)
            med = sqrt((double)select_nonnegative(c.d, c.count, H, 2u * (size_t)W, (n - 1u) / 2u,
                                                  threads));
    }
    free(c.d);
    free(c.count);
    return med;
}

double pgt_atlas_texel_size(const pgt_image *atlas, const pgt_atlas_channels *ch) {
    return texel_size(atlas, ch, 1, NULL);
}

pgt_result atlas_pointers(pgt_image *atlas, const int32_t *texel_chart, const uint32_t *crack,
                          uint8_t *kind, int32_t *dest_chart, float dead_end,
                          const atlas_border *border, uint32_t threads, atlas_pointer_counts *out,
                          pgt_error *err) {
    const uint32_t W = atlas->width, H = atlas->height;
    ptr_ctx c = {0};
    c.atlas = atlas, c.chart = texel_chart, c.crack = crack, c.kind = kind,
    c.dest_chart = dest_chart, c.W = W, c.H = H;
    for (uint32_t k = 0; k < 3; ++k) c.P[k] = pgt_image_plane(atlas, k);
    c.row_boundary = calloc((size_t)H + 1u, sizeof(uint32_t));
    c.row_counts = calloc(ROW_COUNTS * (size_t)H, sizeof(uint32_t));
    const uint32_t workers = pgt_parallel_workers(threads);
    /* written at the inner-boundary texels only, read at random: on huge pages */
    c.local = pgt_alloc_huge(sizeof(double) * (size_t)W * H);
    c.near_border = calloc((size_t)W * H, 1); /* untouched pages stay unmapped zeros */
    c.classify_cols = malloc(sizeof(int32_t) * 2u * W * workers);
    pgt_result r = PGT_OK;
    memset(out, 0, sizeof(*out));
    if (!c.row_boundary || !c.row_counts || !c.local || !c.near_border || !c.classify_cols) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (pointers)");
        goto done;
    }
    atlas_parallel_rows(H, W, threads, classify_rows, &c);
    for (uint32_t y = 0; y < H; ++y) c.row_boundary[y + 1u] += c.row_boundary[y];
    const uint32_t nb = c.row_boundary[H];
    c.b_texel = malloc(sizeof(uint32_t) * (nb + 1u));
    c.b_chart = malloc(sizeof(int32_t) * (nb + 1u));
    c.b_xyz = malloc(sizeof(float) * 3u * (nb + 1u));
    if (!c.b_texel || !c.b_chart || !c.b_xyz) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (pointers)");
        goto done;
    }
    atlas_parallel_rows(H, W, threads, gather_rows, &c);
    r = pgt_kdtree_build(&c.tree, c.b_xyz, nb, threads, err);
    if (r != PGT_OK) goto done;
    c.leaf_chart = malloc(sizeof(int32_t) * (nb + 1u));
    c.leaf_reach2 = malloc(sizeof(float) * (nb + 1u));
    c.node_reach2 = malloc(sizeof(float) * (c.tree.node_count + 1u));
    if (!c.leaf_chart || !c.leaf_reach2 || !c.node_reach2) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (pointers)");
        goto done;
    }
    c.dead_end = dead_end;
    pgt_parallel_for(nb, threads, leaf_rows, &c);
    pgt_kdtree_node_max(&c.tree, c.leaf_reach2, c.node_reach2);
    const pgt_atlas_channels order = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    out->texel_size = texel_size(atlas, &order, threads, texel_chart);
    c.texel_size = out->texel_size;
    if (border) {
        mark_edges(&c, border->tex, border->half_edges, border->count, NEAR_MESH_BORDER);
        mark_edges(&c, border->tex, border->gap_half_edges, border->gap_count, NEAR_GAP);
    }
    atlas_parallel_rows(H, W, threads, pointer_rows, &c);
    out->inner_boundary = nb;
    for (uint32_t y = 0; y < H; ++y) {
        const uint32_t *cnt = &c.row_counts[ROW_COUNTS * y];
        out->indirection += cnt[0];
        out->dead_end += cnt[1];
        out->self_seam += cnt[2];
        out->own_chart += cnt[3];
    }
done:
    free(c.row_boundary);
    free(c.row_counts);
    free(c.local);
    free(c.near_border);
    free(c.classify_cols);
    free(c.b_texel);
    free(c.b_chart);
    free(c.b_xyz);
    free(c.leaf_reach2);
    free(c.node_reach2);
    free(c.leaf_chart);
    pgt_kdtree_destroy(&c.tree);
    return r;
}
