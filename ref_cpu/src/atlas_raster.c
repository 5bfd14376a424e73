/* pgt: atlas step 3, rasterizing the charts into a geometry image (paper 000 section 4: "A
 * geometry image is computed by rasterizing the 3D coordinates of the input surface into the
 * texture plane such that each pixel stores the 3D coordinates of its respective surface
 * point"; Gu, Gortler and Hoppe 2002).
 *
 * A texel is covered when its centre (x + 0.5, y + 0.5) lies inside or on a triangle. Edge
 * functions are evaluated in double from a canonical vertex order per edge (the
 * lexicographically smaller end first), so the two triangles of a shared edge compute exactly
 * opposite values and a centre on the edge is covered by both: no cracks. The smallest face id
 * wins a texel covered twice. P and N are barycentric (N renormalized); vertex normals are the
 * area-weighted face normals averaged per vertex index.
 *
 * Parallel by tiles of ATLAS_RASTER_TILE_ROWS rows: each face is binned into the tiles its rows
 * touch (faces in ascending order in every bin), and one worker does a whole tile in bin order,
 * so the result is the same for any thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_internal.h"
#include "pgt/parallel.h"

/* Rows per raster tile: small enough for two threads to balance on a 1024-row atlas (128
 * tiles), large enough that a triangle of a dense mesh (a few texels tall) mostly sits in one. */
#define ATLAS_RASTER_TILE_ROWS 8u

/* The raster tests every texel of every triangle's box: their sum, in images, at most this.
 * The shared meshes' layouts sum to 0.8-3.0 images (ogre's one chart the most; slivers' boxes
 * exceed their area); UVs folded over inside a chart (a chart keeps its input UVs, fold-overs
 * are counted, not refused) reached 190-300 images with a few hundred faces, and the time grows
 * with the sum (25 s for 9000 faces at 1024^2, hours at the largest --res). */
#define ATLAS_RASTER_MAX_BOX_IMAGES 32.0

/* The crack fill's work bound: its quads' boxes together at most this many times the image (a
 * slit's quad is a few texels wide; bob_tri's 1024^2 atlas scans a fraction of one percent). */
#define ATLAS_CRACK_SCAN_IMAGES 1.0

/* Most (triangle, tile) pairs: 2^28 entries (1 GiB) is beyond any layout the packer makes; only
 * an input whose triangles each span the whole atlas can reach it. */
#define ATLAS_RASTER_MAX_PAIRS (1ull << 28)

/* The bit of a per-tile owner entry that says the owner covers the centre strictly. */
#define OWNER_STRICT 0x80000000u

pgt_result atlas_vertex_normals(const pgt_mesh *m, float **out, pgt_error *err) {
    double *acc = calloc(3u * (size_t)m->vertex_count + 1u, sizeof(double));
    float *n = malloc(sizeof(float) * (3u * (size_t)m->vertex_count + 1u));
    if (!acc || !n) {
        free(acc);
        free(n);
        *out = NULL;
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (normals)");
    }
    for (uint32_t f = 0; f < m->face_count; ++f) {
        const uint32_t *ix = &m->indices[3u * f];
        const float *p0 = &m->positions[3u * ix[0]], *p1 = &m->positions[3u * ix[1]],
                    *p2 = &m->positions[3u * ix[2]];
        double a[3], b[3];
        for (int k = 0; k < 3; ++k) a[k] = (double)p1[k] - p0[k], b[k] = (double)p2[k] - p0[k];
        /* the cross product's length is twice the area: area weighting for free */
        const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                             a[0] * b[1] - a[1] * b[0]};
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) acc[3u * ix[v] + (uint32_t)k] += c[k];
    }
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        const double *a = &acc[3u * v];
        const double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (int k = 0; k < 3; ++k)
            n[3u * v + (uint32_t)k] = len > 0.0 ? (float)(a[k] / len) : 0.0f;
    }
    free(acc);
    *out = n;
    return PGT_OK;
}

/* One edge function: value sign * cross(d, p - base). */
typedef struct edge_fn {
    double bx, by, dx, dy, sign;
} edge_fn;

static edge_fn edge_make(const float *a, const float *b) {
    const int a_first = a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]);
    const float *s = a_first ? a : b, *t = a_first ? b : a;
    return (edge_fn){s[0], s[1], (double)t[0] - s[0], (double)t[1] - s[1], a_first ? 1.0 : -1.0};
}

static double edge_eval(const edge_fn *e, double px, double py) {
    return e->sign * (e->dx * (py - e->by) - e->dy * (px - e->bx));
}

typedef struct raster_ctx {
    const pgt_mesh *mesh;
    const atlas_charts *charts;
    const float *tex, *normals;
    uint32_t width, height, tiles;
    const uint32_t *bin_begin, *bin_faces;
    const int32_t *rows; /* 4 per face: row0, row1, col0, col1 */
    pgt_image *atlas;
    int32_t *texel_chart;
    uint32_t *owner;                  /* per worker: TILE_ROWS * width */
    atlas_raster_counts *tile_counts; /* per tile */
} raster_ctx;

static void raster_tiles(void *vctx, uint32_t t_begin, uint32_t t_end, uint32_t worker) {
    raster_ctx *c = vctx;
    const uint32_t W = c->width, H = c->height;
    uint32_t *owner = c->owner + (size_t)worker * ATLAS_RASTER_TILE_ROWS * W;
    float *P[3] = {NULL, NULL, NULL}, *N[3] = {NULL, NULL, NULL}, *chart_plane = NULL,
          *kind_plane = NULL;
    if (c->atlas)
        for (uint32_t k = 0; k < 3; ++k)
            P[k] = pgt_image_plane(c->atlas, k), N[k] = pgt_image_plane(c->atlas, 3u + k);
    if (c->atlas)
        chart_plane = pgt_image_plane(c->atlas, 6), kind_plane = pgt_image_plane(c->atlas, 7);
    for (uint32_t t = t_begin; t < t_end; ++t) {
        const uint32_t y0 = t * ATLAS_RASTER_TILE_ROWS;
        const uint32_t y1 = y0 + ATLAS_RASTER_TILE_ROWS < H ? y0 + ATLAS_RASTER_TILE_ROWS : H;
        atlas_raster_counts cnt = {0, 0, 0, 0};
        for (uint32_t i = 0; i < (y1 - y0) * W; ++i) owner[i] = PGT_NONE;
        for (uint32_t y = y0; y < y1; ++y) {
            int32_t *tc = &c->texel_chart[(size_t)y * W];
            for (uint32_t x = 0; x < W; ++x) tc[x] = -1;
        }
        for (uint32_t b = c->bin_begin[t]; b < c->bin_begin[t + 1u]; ++b) {
            const uint32_t f = c->bin_faces[b];
            const int32_t *rc = &c->rows[4u * f];
            const uint32_t chart = c->charts->face_chart[f];
            const float *v0 = &c->tex[6u * f], *v1 = v0 + 2, *v2 = v0 + 4;
            const edge_fn e12 = edge_make(v1, v2), e20 = edge_make(v2, v0), e01 = edge_make(v0, v1);
            const double orient = edge_eval(&e01, v2[0], v2[1]) >= 0.0 ? 1.0 : -1.0;
            /* the corners' positions and normals, loaded once (the output planes are float
             * too, so the compiler cannot keep them in registers across the stores) */
            double vp[3][3] = {{0.0}}, vn[3][3] = {{0.0}};
            if (c->atlas) {
                const uint32_t *ix = &c->mesh->indices[3u * f];
                for (uint32_t v = 0; v < 3; ++v)
                    for (uint32_t k = 0; k < 3; ++k) {
                        vp[v][k] = c->mesh->positions[3u * ix[v] + k];
                        vn[v][k] = c->normals[3u * ix[v] + k];
                    }
            }
            const uint32_t ra = (uint32_t)rc[0] > y0 ? (uint32_t)rc[0] : y0;
            const uint32_t rb = (uint32_t)rc[1] + 1u < y1 ? (uint32_t)rc[1] + 1u : y1;
            for (uint32_t y = ra; y < rb; ++y) {
                const double py = y + 0.5;
                for (uint32_t x = (uint32_t)rc[2]; x <= (uint32_t)rc[3]; ++x) {
                    const double px = x + 0.5;
                    const double w0 = orient * edge_eval(&e12, px, py);
                    if (w0 < 0.0) continue;
                    const double w1 = orient * edge_eval(&e20, px, py);
                    if (w1 < 0.0) continue;
                    const double w2 = orient * edge_eval(&e01, px, py);
                    if (w2 < 0.0) continue;
                    const double sum = w0 + w1 + w2;
                    if (!(sum > 0.0)) continue; /* a triangle of zero texel area */
                    const int strict = w0 > 0.0 && w1 > 0.0 && w2 > 0.0;
                    uint32_t *o = &owner[(y - y0) * W + x];
                    if (*o != PGT_NONE) {
                        const uint32_t of = *o & ~OWNER_STRICT;
                        if (c->charts->face_chart[of] != chart)
                            cnt.overlap++;
                        else if (strict && (*o & OWNER_STRICT))
                            cnt.fold_over++;
                        continue;
                    }
                    *o = f | (strict ? OWNER_STRICT : 0u);
                    const size_t idx = (size_t)y * W + x;
                    c->texel_chart[idx] = (int32_t)chart;
                    cnt.inner++;
                    if (!c->atlas) continue;
                    const double inv = 1.0 / sum, l0 = w0 * inv, l1 = w1 * inv, l2 = w2 * inv;
                    double n[3];
                    for (uint32_t k = 0; k < 3; ++k) {
                        P[k][idx] = (float)(l0 * vp[0][k] + l1 * vp[1][k] + l2 * vp[2][k]);
                        n[k] = l0 * vn[0][k] + l1 * vn[1][k] + l2 * vn[2][k];
                    }
                    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                    const double inv_len = len > 0.0 ? 1.0 / len : 0.0;
                    for (uint32_t k = 0; k < 3; ++k) N[k][idx] = (float)(n[k] * inv_len);
                    chart_plane[idx] = (float)chart;
                    kind_plane[idx] = (float)PGT_TEXEL_INNER;
                }
            }
        }
        if (c->atlas)
            for (uint32_t y = y0; y < y1; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const size_t idx = (size_t)y * W + x;
                    if (c->texel_chart[idx] >= 0) continue;
                    for (uint32_t k = 0; k < 3; ++k) P[k][idx] = 0.0f, N[k][idx] = 0.0f;
                    chart_plane[idx] = -1.0f;
                    kind_plane[idx] = (float)PGT_TEXEL_BACKGROUND;
                }
        c->tile_counts[t] = cnt;
    }
}

/* The texel rows and columns whose centres (x + 0.5, y + 0.5) can lie in the convex hull of
 * the n points p, clamped to the image: box = {row0, row1, col0, col1}; 0 when none. */
static int texel_box(const float *const *p, uint32_t n, uint32_t W, uint32_t H, int32_t box[4]) {
    double xmin = p[0][0], xmax = p[0][0], ymin = p[0][1], ymax = p[0][1];
    for (uint32_t k = 1; k < n; ++k) {
        xmin = fmin(xmin, p[k][0]), xmax = fmax(xmax, p[k][0]);
        ymin = fmin(ymin, p[k][1]), ymax = fmax(ymax, p[k][1]);
    }
    /* texel x is covered only if xmin <= x + 0.5 <= xmax */
    const double c0 = fmax(0.0, ceil(xmin - 0.5)), c1 = fmin(W - 1.0, floor(xmax - 0.5));
    const double r0 = fmax(0.0, ceil(ymin - 0.5)), r1 = fmin(H - 1.0, floor(ymax - 0.5));
    if (!(c0 <= c1) || !(r0 <= r1)) return 0;
    box[0] = (int32_t)r0, box[1] = (int32_t)r1, box[2] = (int32_t)c0, box[3] = (int32_t)c1;
    return 1;
}

/* Barycentrics (l0, l1, l2) of the texel centre (px, py) in triangle (v0, v1, v2), inside or
 * on it; 0 when outside or when the triangle has no area. */
static int triangle_bary(const float *v0, const float *v1, const float *v2, double px, double py,
                         double l[3]) {
    const edge_fn e12 = edge_make(v1, v2), e20 = edge_make(v2, v0), e01 = edge_make(v0, v1);
    const double orient = edge_eval(&e01, v2[0], v2[1]) >= 0.0 ? 1.0 : -1.0;
    const double w0 = orient * edge_eval(&e12, px, py), w1 = orient * edge_eval(&e20, px, py),
                 w2 = orient * edge_eval(&e01, px, py);
    const double sum = w0 + w1 + w2;
    if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0 || !(sum > 0.0)) return 0;
    l[0] = w0 / sum, l[1] = w1 / sum, l[2] = w2 / sum;
    return 1;
}

/* Do segments p0 p1 and q0 q1 cross (each one's ends strictly on both sides of the other)? */
static int segments_cross(const float *p0, const float *p1, const float *q0, const float *q1) {
    const edge_fn p = edge_make(p0, p1), q = edge_make(q0, q1);
    const double o1 = edge_eval(&p, q0[0], q0[1]), o2 = edge_eval(&p, q1[0], q1[1]),
                 o3 = edge_eval(&q, p0[0], p0[1]), o4 = edge_eval(&q, p1[0], p1[1]);
    return ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) &&
           ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0));
}

uint32_t atlas_fill_cracks(const pgt_mesh *mesh, const atlas_charts *charts, const float *tex,
                           uint32_t W, uint32_t H, const float *normals, pgt_image *atlas,
                           int32_t *texel_chart, uint32_t *crack) {
    uint32_t filled = 0;
    uint64_t scanned = 0; /* texels of the quads' boxes so far */
    for (uint32_t i = 0; i < charts->seam_count; ++i) {
        const uint32_t h = charts->seam_half_edges[2u * i];
        const uint32_t chart = charts->face_chart[h / 3u];
        /* the two copies of the edge: a0 b0 on h's side, a1 b1 on o's (same 3D ends A, B) */
        const float *q[4];
        atlas_seam_copies(charts, tex, i, q);
        const float *a0 = q[0], *b0 = q[1], *a1 = q[2], *b1 = q[3];
        const double dax = (double)a0[0] - a1[0], day = (double)a0[1] - a1[1];
        const double dbx = (double)b0[0] - b1[0], dby = (double)b0[1] - b1[1];
        /* the copies' distance (1 - s) (a0 - a1) + s (b0 - b1) at its smallest */
        if (sqrt(atlas_segment_dist2(dax, day, dbx, dby, 0.0, 0.0)) > PGT_ATLAS_CRACK_TEXELS)
            continue;
        /* a slit's two sides run side by side from its tip: copies that cross, or whose ends
         * cross over (a0 b0 b1 a1 a bow-tie), are UVs folded inside the chart, not a crack;
         * their quad's s would name texels far from both copies */
        if (segments_cross(a0, b0, a1, b1) || segments_cross(a0, a1, b0, b1)) continue;
        int32_t box[4];
        if (!texel_box(q, 4, W, H, box)) continue;
        /* the work is the quads' boxes: a slit's are a few texels wide, and all of them stay far
         * below the image's area on every mesh tried; copies that spread across the image from
         * one end (folded UVs again) would make it the image per seam (minutes for a few
         * hundred seams): past ATLAS_CRACK_SCAN_IMAGES images the remaining seams are not
         * filled */
        const uint64_t area = (uint64_t)(box[1] - box[0] + 1) * (uint64_t)(box[3] - box[2] + 1);
        if (scanned + area > (uint64_t)(ATLAS_CRACK_SCAN_IMAGES * (double)W * (double)H)) continue;
        scanned += area;
        const uint32_t ia = mesh->indices[h], ib = mesh->indices[pgt_half_edge_next(h)];
        for (uint32_t y = (uint32_t)box[0]; y <= (uint32_t)box[1]; ++y)
            for (uint32_t x = (uint32_t)box[2]; x <= (uint32_t)box[3]; ++x) {
                const size_t idx = (size_t)y * W + x;
                if (texel_chart[idx] >= 0) continue;
                /* the quad a0 b0 b1 a1 as (a0, b0, b1) and (a0, b1, a1); s: 0 at A, 1 at B */
                double l[3], s;
                if (triangle_bary(a0, b0, b1, x + 0.5, y + 0.5, l))
                    s = l[1] + l[2];
                else if (triangle_bary(a0, b1, a1, x + 0.5, y + 0.5, l))
                    s = l[1];
                else
                    continue;
                if (hypot((1.0 - s) * dax + s * dbx, (1.0 - s) * day + s * dby) >
                    PGT_ATLAS_CRACK_TEXELS) { /* the last such quad names the texel */
                    crack[idx] = ATLAS_CRACK_UNFILLED | (i + 1u);
                    continue;
                }
                texel_chart[idx] = (int32_t)chart;
                crack[idx] = i + 1u;
                filled++;
                double n[3], len = 0.0;
                for (uint32_t k = 0; k < 3; ++k) {
                    const double pa = mesh->positions[3u * ia + k],
                                 pb = mesh->positions[3u * ib + k];
                    pgt_image_plane(atlas, k)[idx] = (float)((1.0 - s) * pa + s * pb);
                    n[k] = (1.0 - s) * normals[3u * ia + k] + s * normals[3u * ib + k];
                    len += n[k] * n[k];
                }
                len = sqrt(len);
                for (uint32_t k = 0; k < 3; ++k)
                    pgt_image_plane(atlas, 3u + k)[idx] = len > 0.0 ? (float)(n[k] / len) : 0.0f;
                pgt_image_plane(atlas, 6)[idx] = (float)chart;
                pgt_image_plane(atlas, 7)[idx] = (float)PGT_TEXEL_INNER;
            }
    }
    return filled;
}

pgt_result atlas_raster(const pgt_mesh *mesh, const atlas_charts *charts, const float *tex,
                        uint32_t W, uint32_t H, const float *vertex_normals, pgt_image *atlas,
                        int32_t *texel_chart, uint32_t threads, atlas_raster_counts *out_counts,
                        pgt_error *err) {
    const uint32_t F = mesh->face_count;
    const uint32_t tiles = (H + ATLAS_RASTER_TILE_ROWS - 1u) / ATLAS_RASTER_TILE_ROWS;
    threads = pgt_parallel_workers(threads);
    int32_t *rows = malloc(sizeof(int32_t) * 4u * (F ? F : 1u));
    uint32_t *bin_begin = calloc((size_t)tiles + 1u, sizeof(uint32_t));
    atlas_raster_counts *tile_counts = calloc(tiles, sizeof(atlas_raster_counts));
    uint32_t *owner = malloc(sizeof(uint32_t) * (size_t)threads * ATLAS_RASTER_TILE_ROWS * W);
    uint32_t *bin_faces = NULL;
    pgt_result r = PGT_OK;
    if (!rows || !bin_begin || !tile_counts || !owner) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (raster)");
        goto done;
    }
    uint64_t pairs = 0, box_texels = 0;
    for (uint32_t f = 0; f < F; ++f) {
        int32_t *rc = &rows[4u * f];
        rc[0] = 1, rc[1] = 0;
        if (charts->face_chart[f] == PGT_NONE) continue;
        const float *v[3] = {&tex[6u * f], &tex[6u * f + 2u], &tex[6u * f + 4u]};
        if (!texel_box(v, 3, W, H, rc)) continue; /* rc stays {1, 0}: no row */
        const uint32_t t0 = (uint32_t)rc[0] / ATLAS_RASTER_TILE_ROWS,
                       t1 = (uint32_t)rc[1] / ATLAS_RASTER_TILE_ROWS;
        pairs += t1 - t0 + 1u;
        box_texels += (uint64_t)(rc[1] - rc[0] + 1) * (uint64_t)(rc[3] - rc[2] + 1);
        if (pairs > ATLAS_RASTER_MAX_PAIRS) {
            r = pgt_error_set(err, PGT_ERROR_LIMIT,
                              "atlas: the UV triangles span more than %llu (triangle, tile) "
                              "pairs; the layout is unreasonable",
                              (unsigned long long)ATLAS_RASTER_MAX_PAIRS);
            goto done;
        }
        for (uint32_t t = t0; t <= t1; ++t) bin_begin[t + 1u]++;
    }
    if ((double)box_texels > ATLAS_RASTER_MAX_BOX_IMAGES * (double)W * (double)H) {
        if (!atlas) { /* the input UVs' coverage: stacked islands are repacked, not refused */
            if (out_counts) *out_counts = (atlas_raster_counts){0, 0, 0, 1};
            goto done;
        }
        r = pgt_error_set(err, PGT_ERROR_LIMIT,
                          "atlas: the UV triangles' boxes cover the %ux%u image %.0f times over "
                          "(at most %.0f): UVs folded over or overlapping inside a chart",
                          W, H, (double)box_texels / ((double)W * (double)H),
                          ATLAS_RASTER_MAX_BOX_IMAGES);
        goto done;
    }
    for (uint32_t t = 0; t < tiles; ++t) bin_begin[t + 1u] += bin_begin[t];
    bin_faces = malloc(sizeof(uint32_t) * (pairs ? pairs : 1u));
    uint32_t *fill = malloc(sizeof(uint32_t) * tiles);
    if (!bin_faces || !fill) {
        free(fill);
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "atlas: out of memory (raster bins)");
        goto done;
    }
    memcpy(fill, bin_begin, sizeof(uint32_t) * tiles);
    for (uint32_t f = 0; f < F; ++f) {
        const int32_t *rc = &rows[4u * f];
        if (rc[0] > rc[1]) continue;
        for (uint32_t t = (uint32_t)rc[0] / ATLAS_RASTER_TILE_ROWS;
             t <= (uint32_t)rc[1] / ATLAS_RASTER_TILE_ROWS; ++t)
            bin_faces[fill[t]++] = f;
    }
    free(fill);
    raster_ctx ctx = {mesh,      charts,    tex,  vertex_normals, W,           H,     tiles,
                      bin_begin, bin_faces, rows, atlas,          texel_chart, owner, tile_counts};
    /* a tile costs about TILE_ROWS * W texels: hand tiles out as rows of that width */
    atlas_parallel_rows(tiles, ATLAS_RASTER_TILE_ROWS * W, threads, raster_tiles, &ctx);
    atlas_raster_counts sum = {0, 0, 0, 0};
    /* no wrap: each count is at most the texel tests, ATLAS_RASTER_MAX_BOX_IMAGES images of at
     * most 2^24.6 texels (4939^2) */
    for (uint32_t t = 0; t < tiles; ++t) {
        sum.inner += tile_counts[t].inner;
        sum.fold_over += tile_counts[t].fold_over;
        sum.overlap += tile_counts[t].overlap;
    }
    if (out_counts) *out_counts = sum;
done:
    free(rows);
    free(bin_begin);
    free(bin_faces);
    free(tile_counts);
    free(owner);
    return r;
}
