/* pgt: atlas step 2, the layout of the charts in a W x H geometry image with a free band around
 * every chart (paper 000 section 4: "charts must be organized in the atlas such that we have at
 * least a one pixel band available around each chart to store indirection values").
 *
 * Keep: texel = (u W, (1 - v) H) when every corner lies at least `band` texels inside the image
 * and the rasterized charts keep the band from each other (atlas_band_violations, which also
 * checks the border).
 * Repack otherwise (or when forced):
 * - each chart is scaled by s_c = sqrt(A3D_c / AUV_c), so its UV area becomes its 3D area, then
 *   all by ONE global factor g (texels per unit of 3D length): the 3D size of a texel is the
 *   same in every chart, up to each chart's own parametric distortion (Sander et al. 2003 size
 *   charts the same way);
 * - rotated to its minimum-area bounding rectangle (rotating calipers over the convex hull's
 *   edge directions, and 0 degrees), then by 90 degrees if needed to lie landscape; never
 *   mirrored (5.2);
 * - placed by a bottom-left skyline packer, tallest first, each in a slot of
 *   ceil(size * g) + band texels: a chart placed at integer (X, Y) covers texel centres only in
 *   [X, X + ceil(w g) - 1], so two slots side by side leave >= band free texels between charts;
 * - g is the largest (to ATLAS_LAYOUT_SCALE_TOLERANCE) for which the packer fits. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_internal.h"
#include "pgt/parallel.h"

/* The global scale is searched by stepping down from its area bound by this factor until the
 * charts fit, then by bisection until the bracket is within ATLAS_LAYOUT_SCALE_TOLERANCE: a
 * thousandth of the scale is under one texel for a chart of up to 1000 texels, and costs about
 * 8 packings. */
#define ATLAS_LAYOUT_STEP_DOWN 0.85
#define ATLAS_LAYOUT_SCALE_TOLERANCE 1e-3

void atlas_layout_destroy(atlas_layout *l) {
    if (!l) return;
    free(l->tex);
    memset(l, 0, sizeof(*l));
}

/* ---- band test ---- */

typedef struct band_ctx {
    const int32_t *chart;
    int32_t *hmin, *hmax;
    uint32_t W, H, band;
    uint32_t *row_count;
} band_ctx;

/* Window minimum / maximum of the chart ids over [x - band, x + band] of each row, background
 * (-1) counting as +infinity for the minimum and -1 for the maximum. Loops over the window
 * offset outside and over x inside, so the compiler vectorizes them. */
static void band_rows_h(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    band_ctx *c = vctx;
    (void)worker;
    const uint32_t W = c->W, b = c->band;
    for (uint32_t y = y0; y < y1; ++y) {
        const int32_t *row = &c->chart[(size_t)y * W];
        int32_t *mn = &c->hmin[(size_t)y * W], *mx = &c->hmax[(size_t)y * W];
        for (uint32_t x = 0; x < W; ++x) mn[x] = row[x] < 0 ? INT32_MAX : row[x], mx[x] = row[x];
        for (uint32_t d = 1; d <= b; ++d) {
            for (uint32_t x = 0; x + d < W; ++x) { /* right neighbours */
                const int32_t v = row[x + d];
                const int32_t lo = v < 0 ? INT32_MAX : v;
                mn[x] = lo < mn[x] ? lo : mn[x];
                mx[x] = v > mx[x] ? v : mx[x];
            }
            for (uint32_t x = d; x < W; ++x) { /* left neighbours */
                const int32_t v = row[x - d];
                const int32_t lo = v < 0 ? INT32_MAX : v;
                mn[x] = lo < mn[x] ? lo : mn[x];
                mx[x] = v > mx[x] ? v : mx[x];
            }
        }
    }
}

static void band_rows_v(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    band_ctx *c = vctx;
    (void)worker;
    const uint32_t W = c->W, H = c->H, b = c->band;
    for (uint32_t y = y0; y < y1; ++y) {
        const int32_t *own = &c->chart[(size_t)y * W];
        uint32_t n = 0;
        const int edge_row = y < b || y + b >= H;
        for (uint32_t x = 0; x < W; ++x) {
            if (own[x] < 0) continue;
            int bad = edge_row || x < b || x + b >= W;
            const uint32_t ya = y >= b ? y - b : 0, yb = y + b < H ? y + b : H - 1u;
            for (uint32_t i = ya; i <= yb && !bad; ++i) {
                const size_t j = (size_t)i * W + x;
                bad = c->hmin[j] < own[x] || c->hmax[j] > own[x]; /* empty: MAX, -1 */
            }
            n += (uint32_t)bad;
        }
        c->row_count[y] = n;
    }
}

uint32_t atlas_band_violations(const int32_t *texel_chart, uint32_t W, uint32_t H, uint32_t band,
                               uint32_t threads) {
    band_ctx c = {texel_chart,
                  malloc(sizeof(int32_t) * (size_t)W * H),
                  malloc(sizeof(int32_t) * (size_t)W * H),
                  W,
                  H,
                  band,
                  calloc(H, sizeof(uint32_t))};
    uint32_t n = 0;
    if (!c.hmin || !c.hmax || !c.row_count) {
        n = PGT_NONE; /* treated as "does not keep the band": the caller repacks */
    } else {
        atlas_parallel_rows(H, W, threads, band_rows_h, &c);
        atlas_parallel_rows(H, W, threads, band_rows_v, &c);
        for (uint32_t y = 0; y < H; ++y) n += c.row_count[y];
    }
    free(c.hmin);
    free(c.hmax);
    free(c.row_count);
    return n;
}

/* ---- repacking ---- */

typedef struct pt2 {
    double x, y;
} pt2;

static int pt_less(const void *a, const void *b) {
    const pt2 *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    return 0;
}

/* Below this many points a chart's hull points are sorted by insertion (most charts of a
 * photogrammetry layout are a few triangles: qsort's calls cost more than the sort). */
#define ATLAS_HULL_INSERTION_SORT 32u

/* pts sorted by (x, y): the order pt_less defines (equal points are equal, so any stable or
 * unstable sort gives the same sequence of values). */
static void sort_points(pt2 *pts, uint32_t n) {
    if (n > ATLAS_HULL_INSERTION_SORT) {
        qsort(pts, n, sizeof(pt2), pt_less);
        return;
    }
    for (uint32_t i = 1; i < n; ++i) {
        const pt2 p = pts[i];
        uint32_t j = i;
        for (; j > 0 && pt_less(&p, &pts[j - 1u]) < 0; --j) pts[j] = pts[j - 1u];
        pts[j] = p;
    }
}

static double cross3(pt2 o, pt2 a, pt2 b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/* Convex hull (Andrew's monotone chain) of pts[0..n) into hull (2n slots), counter-clockwise;
 * pts is reordered. Akl-Toussaint first: points strictly inside the octagon of the extreme
 * points in 8 directions cannot be on the hull and are dropped before sorting. */
static uint32_t convex_hull(pt2 *pts, uint32_t n, pt2 *hull) {
    if (n > 16u) {
        /* the first point farthest along each of the directions (1, 0), (1, 1), (0, 1),
         * (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1): x, x + y, y, y - x, -x, -x - y, -y,
         * x - y (the products by 0 and 1 of a dot product are exact) */
        uint32_t ext[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        double best[8];
        for (uint32_t i = 0; i < n; ++i) {
            const double x = pts[i].x, y = pts[i].y;
            const double key[8] = {x, x + y, y, y - x, -x, -x - y, -y, x - y};
            for (uint32_t k = 0; k < 8; ++k)
                if (i == 0 || key[k] > best[k]) best[k] = key[k], ext[k] = i;
        }
        pt2 oct[8];
        for (uint32_t k = 0; k < 8; ++k) oct[k] = pts[ext[k]];
        uint32_t m = 0;
        for (uint32_t i = 0; i < n; ++i) {
            int inside = 1;
            for (uint32_t k = 0; k < 8 && inside; ++k) {
                const pt2 a = oct[k], b = oct[(k + 1u) % 8u];
                if (a.x == b.x && a.y == b.y) continue;
                if (!(cross3(a, b, pts[i]) > 0.0)) inside = 0;
            }
            if (!inside) pts[m++] = pts[i];
        }
        n = m;
    }
    sort_points(pts, n);
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; ++i) {
        while (k >= 2 && cross3(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) k--;
        hull[k++] = pts[i];
    }
    for (uint32_t i = n - 1u, t = k + 1u; i-- > 0;) {
        while (k >= t && cross3(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) k--;
        hull[k++] = pts[i];
    }
    return n > 1 ? k - 1u : n;
}

typedef struct chart_box {
    double angle;              /* rotation applied to the (flipped) UVs */
    double qx0, qy0, qx1, qy1; /* bounding box of the rotated UVs */
    double w, h;               /* in 3D units: (qx1 - qx0) s, (qy1 - qy0) s */
    double s;                  /* 3D length per UV unit */
    double ca, sa;             /* cos and sin of angle */
} chart_box;

static void rotated_box(const pt2 *p, uint32_t n, double a, double *x0, double *y0, double *x1,
                        double *y1) {
    const double ca = cos(a), sa = sin(a);
    *x0 = *y0 = INFINITY, *x1 = *y1 = -INFINITY;
    for (uint32_t i = 0; i < n; ++i) {
        const double x = ca * p[i].x - sa * p[i].y, y = sa * p[i].x + ca * p[i].y;
        /* finite values (UVs are checked): comparisons, as fmin and fmax would choose */
        if (x < *x0) *x0 = x;
        if (x > *x1) *x1 = x;
        if (y < *y0) *y0 = y;
        if (y > *y1) *y1 = y;
    }
}

/* Minimum-area bounding rectangle over the hull edge directions and 0, made landscape. */
static chart_box chart_box_make(const pt2 *hull, uint32_t h, double s) {
    chart_box best = {0};
    double best_area = INFINITY;
    for (uint32_t e = 0; e <= h; ++e) {
        double a = 0.0;
        if (e < h) {
            const pt2 p = hull[e], q = hull[(e + 1u) % h];
            if (p.x == q.x && p.y == q.y) continue;
            a = -atan2(q.y - p.y, q.x - p.x); /* rotate the edge onto +x */
        }
        double x0, y0, x1, y1;
        rotated_box(hull, h, a, &x0, &y0, &x1, &y1);
        const double area = (x1 - x0) * (y1 - y0);
        if (area < best_area) {
            best_area = area;
            best = (chart_box){a, x0, y0, x1, y1, 0, 0, s, 0, 0};
        }
    }
    if (best.qy1 - best.qy0 > best.qx1 - best.qx0) {
        best.angle += 1.5707963267948966; /* a quarter turn */
        rotated_box(hull, h, best.angle, &best.qx0, &best.qy0, &best.qx1, &best.qy1);
    }
    best.ca = cos(best.angle), best.sa = sin(best.angle);
    best.w = (best.qx1 - best.qx0) * s;
    best.h = (best.qy1 - best.qy0) * s;
    return best;
}

static uint32_t slot_side(double size, double g, uint32_t band) {
    const double t = ceil(size * g);
    return (t < 1.0 ? 1u : (t > 1e9 ? 1000000000u : (uint32_t)t)) + band;
}

/* Removes segment k of the skyline's S segments. */
static void segment_remove(uint32_t *seg_x, uint32_t *seg_y, uint32_t *S, uint32_t k) {
    memmove(&seg_x[k], &seg_x[k + 1u], sizeof(uint32_t) * (*S - k - 1u));
    memmove(&seg_y[k], &seg_y[k + 1u], sizeof(uint32_t) * (*S - k - 1u));
    (*S)--;
}

/* Bottom-left skyline packing of the charts in `order` at global scale g. The skyline is a
 * list of segments (start x, height y), sorted by x, covering [band, W); a slot is tried at
 * every segment start, and goes where its top is lowest (ties: leftmost). Returns 1 and fills
 * X, Y (per chart) when everything fits. seg_x, seg_y hold W entries. */
static int pack(const chart_box *box, const uint32_t *order, uint32_t n, double g, uint32_t W,
                uint32_t H, uint32_t band, uint32_t *seg_x, uint32_t *seg_y, uint32_t *X,
                uint32_t *Y) {
    uint32_t S = 1;
    seg_x[0] = band, seg_y[0] = band;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t c = order[i];
        const uint32_t sw = slot_side(box[c].w, g, band), sh = slot_side(box[c].h, g, band);
        if (sw > W - band || sh > H - band) return 0;
        uint32_t best_i = PGT_NONE, best_y = UINT32_MAX;
        for (uint32_t s = 0; s < S && seg_x[s] + sw <= W; ++s) {
            if (seg_y[s] >= best_y) continue;
            uint32_t y = seg_y[s];
            for (uint32_t j = s + 1u; j < S && seg_x[j] < seg_x[s] + sw && y < best_y; ++j)
                if (seg_y[j] > y) y = seg_y[j];
            if (y < best_y) best_y = y, best_i = s;
        }
        if (best_i == PGT_NONE || (uint64_t)best_y + sh > H) return 0;
        const uint32_t x0 = seg_x[best_i], x1 = x0 + sw, top = best_y + sh;
        /* segments [best_i, j) start inside [x0, x1); the last of them continues past x1 */
        uint32_t j = best_i;
        while (j < S && seg_x[j] < x1) j++;
        const uint32_t tail_y = seg_y[j - 1u];
        const int tail = (j < S ? seg_x[j] : W) > x1; /* part of segment j-1 remains */
        /* replace [best_i, j) by (x0, top) and, when something remains, (x1, tail_y) */
        const uint32_t add = 1u + (uint32_t)tail, removed = j - best_i;
        if (add != removed)
            memmove(&seg_x[best_i + add], &seg_x[j], sizeof(uint32_t) * (S - j)),
                memmove(&seg_y[best_i + add], &seg_y[j], sizeof(uint32_t) * (S - j));
        S = S - removed + add;
        seg_x[best_i] = x0, seg_y[best_i] = top;
        if (tail) seg_x[best_i + 1u] = x1, seg_y[best_i + 1u] = tail_y;
        /* merge equal neighbours so the list stays short: no two were equal before, and a tail
         * lies below the new segment (tail_y <= best_y < top), so only the new segment can equal
         * its left neighbour or, without a tail, its right one; a merge keeps the left x */
        uint32_t at = best_i;
        if (at > 0u && seg_y[at - 1u] == top) segment_remove(seg_x, seg_y, &S, at--);
        if (at + 1u < S && seg_y[at + 1u] == top) segment_remove(seg_x, seg_y, &S, at + 1u);
        X[c] = x0, Y[c] = best_y;
    }
    return 1;
}

typedef struct order_key {
    double h;
    uint32_t c;
} order_key;

static int order_less(const void *a, const void *b) {
    const order_key *p = a, *q = b;
    if (p->h != q->h) return p->h > q->h ? -1 : 1;
    return p->c < q->c ? -1 : (p->c > q->c);
}

/* The charts' boxes, in parallel: chart c takes its points and hull from the slots of its faces
 * (pts from 3 begin[c], hull from 6 begin[c] + 2 c), so charts share no scratch. */
typedef struct box_ctx {
    const atlas_charts *ch;
    const uint32_t *begin, *faces;
    pt2 *pts, *hull;
    chart_box *box;
} box_ctx;

/* Weight of one chart for atlas_parallel_rows (which keeps >= 4096 texels per thread): a few
 * charts of many faces still spread over the threads. */
#define ATLAS_LAYOUT_CHART_WEIGHT 1024u

static void box_range(void *vctx, uint32_t c0, uint32_t c1, uint32_t worker) {
    const box_ctx *b = vctx;
    (void)worker;
    for (uint32_t c = c0; c < c1; ++c) {
        pt2 *pts = b->pts + 3u * (size_t)b->begin[c];
        pt2 *hull = b->hull + 6u * (size_t)b->begin[c] + 2u * (size_t)c;
        uint32_t n = 0;
        for (uint32_t i = b->begin[c]; i < b->begin[c + 1u]; ++i)
            for (uint32_t k = 0; k < 3; ++k) {
                const float *uv = &b->ch->uvs[6u * b->faces[i] + 2u * k];
                pts[n++] = (pt2){uv[0], uv[1]};
            }
        const uint32_t h = convex_hull(pts, n, hull);
        /* 3D length per UV unit; a chart of zero 3D area keeps a tiny size instead of 0 */
        double s = b->ch->chart_area_uv[c] > 0.0
                       ? sqrt(b->ch->chart_area_3d[c] / b->ch->chart_area_uv[c])
                       : 0.0;
        if (!(s > 0.0) || !isfinite(s)) s = 1e-30;
        b->box[c] = chart_box_make(hull, h, s);
    }
}

static pgt_result repack(atlas_layout *out, const pgt_mesh *mesh, const atlas_charts *ch,
                         uint32_t W, uint32_t H, uint32_t band, uint32_t threads, const char *what,
                         pgt_error *err) {
    const uint32_t F = mesh->face_count, C = ch->chart_count;
    pgt_result r = PGT_OK;
    uint32_t *begin = calloc((size_t)C + 1u, sizeof(uint32_t));
    uint32_t *faces = malloc(sizeof(uint32_t) * (F ? F : 1u));
    pt2 *pts = malloc(sizeof(pt2) * 3u * (F ? F : 1u));
    pt2 *hull = malloc(sizeof(pt2) * (6u * (size_t)F + 2u * (size_t)C + 2u));
    chart_box *box = malloc(sizeof(chart_box) * C);
    order_key *keys = malloc(sizeof(order_key) * C);
    uint32_t *order = malloc(sizeof(uint32_t) * C);
    uint32_t *sky = malloc(sizeof(uint32_t) * (W + 2u));
    uint32_t *deque = malloc(sizeof(uint32_t) * (W + 2u));
    uint32_t *X = malloc(sizeof(uint32_t) * C), *Y = malloc(sizeof(uint32_t) * C);
    if (!begin || !faces || !pts || !hull || !box || !keys || !order || !sky || !deque || !X ||
        !Y) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (layout)", what);
        goto done;
    }
    for (uint32_t f = 0; f < F; ++f)
        if (ch->face_chart[f] != PGT_NONE) begin[ch->face_chart[f] + 1u]++;
    for (uint32_t c = 0; c < C; ++c) begin[c + 1u] += begin[c];
    {
        uint32_t *fill = malloc(sizeof(uint32_t) * C);
        if (!fill) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (layout)", what);
            goto done;
        }
        memcpy(fill, begin, sizeof(uint32_t) * C);
        for (uint32_t f = 0; f < F; ++f)
            if (ch->face_chart[f] != PGT_NONE) faces[fill[ch->face_chart[f]]++] = f;
        free(fill);
    }
    box_ctx bc = {ch, begin, faces, pts, hull, box};
    atlas_parallel_rows(C, ATLAS_LAYOUT_CHART_WEIGHT, threads, box_range, &bc);
    double sum_area = 0.0, max_w = 0.0, max_h = 0.0;
    for (uint32_t c = 0; c < C; ++c) { /* in chart order: the same sums for any thread count */
        keys[c] = (order_key){box[c].h, c};
        sum_area += box[c].w * box[c].h;
        max_w = fmax(max_w, box[c].w), max_h = fmax(max_h, box[c].h);
    }
    qsort(keys, C, sizeof(order_key), order_less);
    for (uint32_t c = 0; c < C; ++c) order[c] = keys[c].c;
    /* Upper bound on g: the widest chart must fit between the bands, and the chart rectangles
     * cannot hold more area than the image. */
    double g_hi = sqrt((double)W * H / fmax(sum_area, 1e-300));
    if (max_w > 0.0) g_hi = fmin(g_hi, (W - 2.0 * band) / max_w);
    if (max_h > 0.0) g_hi = fmin(g_hi, (H - 2.0 * band) / max_h);
    double g_lo = g_hi;
    if (!pack(box, order, C, g_hi, W, H, band, sky, deque, X, Y)) {
        /* step down until it fits: skyline packing usually fills 60-85 % */
        g_lo = g_hi * ATLAS_LAYOUT_STEP_DOWN;
        while (!pack(box, order, C, g_lo, W, H, band, sky, deque, X, Y)) {
            g_hi = g_lo;
            g_lo *= ATLAS_LAYOUT_STEP_DOWN;
            if (g_lo < 1e-300 || g_lo * max_w < 0.5) { /* every chart is one texel already */
                g_lo = 0.0;
                if (!pack(box, order, C, 0.0, W, H, band, sky, deque, X, Y)) {
                    r = pgt_error_set(err, PGT_ERROR_LIMIT,
                                      "%s: %u charts do not fit in a %ux%u atlas with a free "
                                      "band of %u texels even at one texel each (raise --res%s)",
                                      what, C, W, H, band,
                                      band > PGT_ATLAS_MIN_BAND ? " or lower --band" : "");
                    goto done;
                }
                break;
            }
        }
        while (g_hi - g_lo > ATLAS_LAYOUT_SCALE_TOLERANCE * g_hi) {
            const double g_mid = 0.5 * (g_lo + g_hi);
            if (pack(box, order, C, g_mid, W, H, band, sky, deque, X, Y))
                g_lo = g_mid;
            else
                g_hi = g_mid;
        }
    }
    if (!pack(box, order, C, g_lo, W, H, band, sky, deque, X, Y)) { /* fills X, Y for g_lo */
        r = pgt_error_set(err, PGT_ERROR_LIMIT, "%s: the charts do not fit (layout)", what);
        goto done;
    }
    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t c = ch->face_chart[f];
        float *t = &out->tex[6u * f];
        if (c == PGT_NONE) {
            memset(t, 0, 6u * sizeof(float));
            continue;
        }
        const chart_box *b = &box[c];
        const double ca = b->ca, sa = b->sa, k = b->s * g_lo;
        for (uint32_t v = 0; v < 3; ++v) {
            const float *uv = &ch->uvs[6u * f + 2u * v];
            const double qx = ca * uv[0] - sa * uv[1], qy = sa * uv[0] + ca * uv[1];
            t[2u * v] = (float)(X[c] + (qx - b->qx0) * k);
            t[2u * v + 1u] = (float)(Y[c] + (b->qy1 - qy) * k);
        }
    }
    out->repacked = 1;
    out->scale = g_lo;
done:
    free(begin);
    free(faces);
    free(pts);
    free(hull);
    free(box);
    free(keys);
    free(order);
    free(sky);
    free(deque);
    free(X);
    free(Y);
    return r;
}

typedef struct box_key {
    float x0, y0, x1, y1;
} box_key;

static int box_less(const void *a, const void *b) {
    const box_key *p = a, *q = b;
    return p->x0 < q->x0 ? -1 : (p->x0 > q->x0 ? 1 : (p->y0 < q->y0 ? -1 : p->y0 > q->y0));
}

/* 1 when the texel-space bounding boxes of every two charts are more than `band` apart in x or
 * in y: a texel x is covered only when x + 0.5 lies in [xmin, xmax], so the inner texels of two
 * such charts are more than band apart and the band test is not needed. Sweep over the boxes
 * sorted by xmin; stops at the first pair that is too close. */
static int charts_separated(const float *tex, const atlas_charts *ch, uint32_t band) {
    const uint32_t C = ch->chart_count;
    box_key *box = malloc(sizeof(box_key) * C);
    uint32_t *active = malloc(sizeof(uint32_t) * C);
    int ok = box && active;
    if (ok) {
        for (uint32_t c = 0; c < C; ++c)
            box[c] = (box_key){INFINITY, INFINITY, -INFINITY, -INFINITY};
        for (uint32_t f = 0; f < ch->face_count; ++f) {
            const uint32_t c = ch->face_chart[f];
            if (c == PGT_NONE) continue;
            for (uint32_t k = 0; k < 3; ++k) {
                const float x = tex[6u * f + 2u * k], y = tex[6u * f + 2u * k + 1u];
                box[c].x0 = fminf(box[c].x0, x), box[c].x1 = fmaxf(box[c].x1, x);
                box[c].y0 = fminf(box[c].y0, y), box[c].y1 = fmaxf(box[c].y1, y);
            }
        }
        qsort(box, C, sizeof(box_key), box_less);
        uint32_t n = 0;
        for (uint32_t i = 0; i < C && ok; ++i) {
            uint32_t m = 0;
            for (uint32_t a = 0; a < n && ok; ++a) {
                const box_key *p = &box[active[a]];
                if (!((double)box[i].x0 - p->x1 > band)) { /* still close in x */
                    active[m++] = active[a];
                    if (!((double)box[i].y0 - p->y1 > band || (double)p->y0 - box[i].y1 > band))
                        ok = 0;
                }
            }
            n = m;
            active[n++] = i;
        }
    }
    free(box);
    free(active);
    return ok;
}

pgt_result atlas_layout_build(atlas_layout *out, const pgt_mesh *mesh, const atlas_charts *ch,
                              uint32_t W, uint32_t H, uint32_t band, int force_repack,
                              uint32_t threads, const char *what, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    const uint32_t F = mesh->face_count;
    out->tex = malloc(sizeof(float) * 6u * (F ? F : 1u));
    if (!out->tex)
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (layout)", what);
    int keep = !force_repack;
    double uv_area = 0.0;
    for (uint32_t c = 0; c < ch->chart_count; ++c) uv_area += ch->chart_area_uv[c];
    /* charts whose UV areas add up to more than the unit square must overlap */
    if (uv_area > 1.0) keep = 0;
    /* every corner at least `band` texels inside the image (then no texel centre within the
     * band of the border is covered; checked here so that such inputs, e.g. a disk filling the
     * unit square, skip the raster of the keep test) */
    const double bu = (double)band / W, bv = (double)band / H;
    for (uint32_t f = 0; f < F && keep; ++f) {
        if (ch->face_chart[f] == PGT_NONE) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            const double u = ch->uvs[6u * f + 2u * k], v = ch->uvs[6u * f + 2u * k + 1u];
            if (!(u >= bu && u <= 1.0 - bu && v >= bv && v <= 1.0 - bv)) keep = 0;
        }
    }
    if (keep) {
        for (uint64_t i = 0; i < 3ull * F; ++i) {
            out->tex[2u * i] = (float)((double)ch->uvs[2u * i] * W);
            out->tex[2u * i + 1u] = (float)((1.0 - (double)ch->uvs[2u * i + 1u]) * H);
        }
        out->separated = charts_separated(out->tex, ch, band);
        return PGT_OK;
    }
    return atlas_layout_repack(out, mesh, ch, W, H, band, threads, what, err);
}

pgt_result atlas_layout_repack(atlas_layout *out, const pgt_mesh *mesh, const atlas_charts *ch,
                               uint32_t W, uint32_t H, uint32_t band, uint32_t threads,
                               const char *what, pgt_error *err) {
    pgt_result r = repack(out, mesh, ch, W, H, band, threads, what, err);
    if (r != PGT_OK) atlas_layout_destroy(out);
    return r;
}
