/* pgt: rendering facades per pixel (paper 003 sec. 5.3, 6.1, 6.4): coverage polygons rasterized
 * into screen tiles, one ray per covered pixel developed against that facade with the depth so
 * far as its far bound (facades near to far: the depth test of the paper's rasterizer), then
 * shading with self-shadowing.
 *
 * Order and threads. Facades are sorted by their volume's distance to the eye (ties by index);
 * tiles are independent and each pixel's facades are tested in that order, so a frame is the
 * same bytes for any thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "facade_internal.h"
#include "pgt/parallel.h"
#include "time_internal.h"
#include "vec3_internal.h"

/* Screen tiles of TILE x TILE pixels: a tile's rays and depths stay in L1. */
#define TILE 16u
/* A pixel is covered when its ray passes inside the cone from the eye over the coverage polygon
 * (the pixel centre inside the projected polygon, tested in 3D so that polygon corners far off
 * screen or just in front of the eye lose no precision), with this margin in radians: rounding
 * never drops a pixel whose ray meets the volume (an extra one only costs a slab test that
 * misses). */
#define COVER_MARGIN_RAD 1e-6f
/* The pixel box of a projected polygon is grown by this many pixels. */
#define COVER_MARGIN_PX 0.01f
/* Camera-space depth below which a coverage polygon is clipped (metres): a point closer than
 * this to the eye's image plane has no pixel. */
#define COVER_NEAR 1e-5f
/* Shadow rays start this far (relative to the hit distance, plus an absolute 1e-4 m) off the
 * surface towards the camera side, so they do not hit the surface they leave. */
#define SHADOW_OFFSET_REL 1e-4f
#define SHADOW_OFFSET_ABS 1e-4f
/* The thinnest a facade gets in LOD level 0 (a share of its thickness): not 0, so that the
 * development still orders the terminals front to back (at 300 m a 0.3 m protrusion becomes
 * 0.3 mm, under a pixel's depth resolution and invisible). */
#define LOD_ZSCALE_MIN 1e-3f
/* Albedo of roofs (grey). */
#define ROOF_ALBEDO 0.55f
/* Albedo = base x (PATTERN_DARK + (1 - PATTERN_DARK) h): joints of the material pattern darker. */
#define PATTERN_DARK 0.72f

/* 1 at or below near, 0 at or beyond far, linear between. */
static float ramp(float d, float near, float far) {
    if (d <= near) return 1.0f;
    if (d >= far) return 0.0f;
    return (far - d) / (far - near);
}

/* The thickness scale of a facade at distance d (from the eye to its volume). */
static float zscale_of(const pgt_facade_shading *sh, float d) {
    if (sh->detail == PGT_FACADE_DETAIL_FLAT) return LOD_ZSCALE_MIN;
    if (sh->detail != PGT_FACADE_DETAIL_LOD) return 1.0f;
    const float n = sh->thick_near > 0.0f ? sh->thick_near : PGT_FACADE_LOD_THICK_NEAR;
    const float f = sh->thick_far > 0.0f ? sh->thick_far : PGT_FACADE_LOD_THICK_FAR;
    return facade_max(ramp(d, n, f), LOD_ZSCALE_MIN);
}

pgt_result pgt_facade_frame_create(pgt_facade_frame *out, uint32_t width, uint32_t height,
                                   pgt_error *err) {
    memset(out, 0, sizeof *out);
    if (width == 0 || height == 0 || width > PGT_FACADE_MAX_SIDE || height > PGT_FACADE_MAX_SIDE)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "frame: %u x %u pixels, expected 1 to %u per side", width, height,
                             PGT_FACADE_MAX_SIDE);
    const size_t n = (size_t)width * height;
    out->width = width, out->height = height;
    out->rgb = malloc(3 * n * sizeof(float));
    out->depth = malloc(n * sizeof(float));
    out->terminal = malloc(n * sizeof(float));
    out->normal = malloc(3 * n * sizeof(float));
    out->facade = malloc(n * sizeof(uint32_t));
    out->node = malloc(n * sizeof(uint32_t));
    out->surface = malloc(n * sizeof(uint32_t));
    out->developed = malloc(n * sizeof(uint32_t));
    if (!out->rgb || !out->depth || !out->terminal || !out->normal || !out->facade || !out->node ||
        !out->surface || !out->developed) {
        pgt_facade_frame_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "frame %u x %u: out of memory", width,
                             height);
    }
    return PGT_OK;
}

void pgt_facade_frame_destroy(pgt_facade_frame *f) {
    if (!f) return;
    free(f->rgb);
    free(f->depth);
    free(f->terminal);
    free(f->normal);
    free(f->facade);
    free(f->node);
    free(f->surface);
    free(f->developed);
    memset(f, 0, sizeof *f);
}

/* ---- coverage polygon (5.3) ---- */

int pgt_facade_coverage(const pgt_facade *f, const float eye[3], float corners[4][3],
                        uint32_t *axis) {
    static const float zero[3] = {0.0f, 0.0f, 0.0f};
    float e[3], unused[3];
    facade_to_local(f, eye, zero, e, unused);
    float lo[3], hi[3];
    facade_volume(f, lo, hi);
    /* 5.3.1: the major axis of the view direction among those separating the eye */
    int best = -1;
    float best_v = -1.0f;
    for (int k = 0; k < 3; ++k) {
        if (!(e[k] < lo[k] || e[k] > hi[k])) continue;
        const float v = fabsf(0.5f * (lo[k] + hi[k]) - e[k]);
        if (v > best_v) best_v = v, best = k;
    }
    if (best < 0) return 0;
    const int a = best, o0 = a == 0 ? 1 : 0, o1 = a == 2 ? 1 : 2;
    const float c = e[a] > hi[a] ? hi[a] : lo[a];
    /* 5.3.2: the 8 corners projected from the eye onto the plane x_a = c */
    float mn0 = INFINITY, mx0 = -INFINITY, mn1 = INFINITY, mx1 = -INFINITY;
    for (int k = 0; k < 8; ++k) {
        const float P[3] = {(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1],
                            (k & 4) ? hi[2] : lo[2]};
        const float s = (c - e[a]) / (P[a] - e[a]);
        const float q0 = e[o0] + (P[o0] - e[o0]) * s, q1 = e[o1] + (P[o1] - e[o1]) * s;
        mn0 = facade_min(mn0, q0), mx0 = facade_max(mx0, q0), mn1 = facade_min(mn1, q1),
        mx1 = facade_max(mx1, q1);
    }
    const float u0[4] = {mn0, mx0, mx0, mn0}, u1[4] = {mn1, mn1, mx1, mx1};
    for (int k = 0; k < 4; ++k) {
        float p[3];
        p[a] = c, p[o0] = u0[k], p[o1] = u1[k];
        facade_to_world(f, p, corners[k]);
    }
    if (axis) *axis = (uint32_t)a;
    return 1;
}

/* A facade's footprint on screen: a convex polygon in pixel coordinates and its pixel box. */
typedef struct cover {
    float cone[4][3];        /* unit inward normals of the cone's 4 sides */
    uint32_t n;              /* 0: not on screen */
    uint32_t x0, y0, x1, y1; /* pixel box, inclusive */
    int full;                /* the eye is inside the volume: every pixel */
    float dist;              /* distance from the eye to the volume */
} cover;

typedef struct render_ctx {
    const pgt_facade_scene *s;
    const pgt_facade *f;
    uint32_t fcount;
    const pgt_facade_camera *cam;
    const pgt_facade_shading *sh;
    pgt_facade_frame *frame;
    cover *cov;
    uint32_t *order; /* visible facades near to far */
    uint32_t visible;
    uint32_t tiles_x, tiles_y;
    uint32_t *tile_first; /* tiles + 1 */
    uint32_t *tile_list;
    pgt_facade_ray_stats *wstats; /* per worker */
    uint32_t *werror;             /* per worker: the lowest facade whose rays set an error bit */
    uint64_t *wcovered;           /* per worker */
    facade_cache *caches;         /* per worker */
    facade_packet_work **packets; /* per worker (NULL entries with single_rays) */
} render_ctx;

static void to_camera(const pgt_facade_camera *cam, const float p[3], float out[3]) {
    const float d[3] = {p[0] - cam->eye[0], p[1] - cam->eye[1], p[2] - cam->eye[2]};
    out[0] = dot3(d, cam->right), out[1] = dot3(d, cam->upward), out[2] = dot3(d, cam->forward);
}

/* Distance from point e to the box [lo, hi] (0 inside). */
static float box_distance(const float e[3], const float lo[3], const float hi[3]) {
    float d2 = 0.0f;
    for (int k = 0; k < 3; ++k) {
        const float d = e[k] < lo[k] ? lo[k] - e[k] : (e[k] > hi[k] ? e[k] - hi[k] : 0.0f);
        d2 += d * d;
    }
    return sqrtf(d2);
}

/* Distance from the eye to facade f's volume (0 inside). */
static float volume_distance(const pgt_facade *f, const float eye[3]) {
    static const float zero[3] = {0.0f, 0.0f, 0.0f};
    float e[3], unused[3], lo[3], hi[3];
    facade_to_local(f, eye, zero, e, unused);
    facade_volume(f, lo, hi);
    return box_distance(e, lo, hi);
}

/* Grows the projected extent ext (min x, max x, min y, max y, in pixel-centre coordinates
 * x + 0.5, y + 0.5) by camera-space point q in front of the eye: the inverse of
 * pgt_facade_camera_ray. */
static void extend_projected(const pgt_facade_camera *cam, const float q[3], float ext[4]) {
    const float W = (float)cam->width, H = (float)cam->height;
    const float sxs = W / (2.0f * cam->tan_half * (W / H)), sys = H / (2.0f * cam->tan_half);
    const float px = W * 0.5f + q[0] / q[2] * sxs, py = H * 0.5f - q[1] / q[2] * sys;
    ext[0] = facade_min(ext[0], px), ext[1] = facade_max(ext[1], px);
    ext[2] = facade_min(ext[2], py), ext[3] = facade_max(ext[3], py);
}

/* cv's pixel box (inclusive, grown by COVER_MARGIN_PX) from a projected extent; 0 (cv untouched)
 * when it misses the screen. */
static int pixel_box(cover *cv, const pgt_facade_camera *cam, const float ext[4]) {
    const uint32_t W = cam->width, H = cam->height;
    const float fx0 = floorf(ext[0] - 0.5f - COVER_MARGIN_PX),
                fx1 = ceilf(ext[1] - 0.5f + COVER_MARGIN_PX);
    const float fy0 = floorf(ext[2] - 0.5f - COVER_MARGIN_PX),
                fy1 = ceilf(ext[3] - 0.5f + COVER_MARGIN_PX);
    if (!(fx1 >= 0.0f && fy1 >= 0.0f && fx0 <= (float)(W - 1u) && fy0 <= (float)(H - 1u))) return 0;
    cv->x0 = fx0 < 0.0f ? 0u : (uint32_t)fx0;
    cv->y0 = fy0 < 0.0f ? 0u : (uint32_t)fy0;
    cv->x1 = fx1 > (float)(W - 1u) ? W - 1u : (uint32_t)fx1;
    cv->y1 = fy1 > (float)(H - 1u) ? H - 1u : (uint32_t)fy1;
    return 1;
}

/* Grows ext by a polygon's edge A -> B (camera space) clipped against the near plane
 * (Sutherland-Hodgman, one plane): A when it lies in front, and the edge's crossing of the
 * plane. Returns how many points of the clipped polygon that adds (a polygon with fewer than 3
 * has no pixel). */
static uint32_t extend_clipped(const pgt_facade_camera *cam, const float A[3], const float B[3],
                               float ext[4]) {
    uint32_t n = 0;
    const int ia = A[2] >= COVER_NEAR, ib = B[2] >= COVER_NEAR;
    if (ia) extend_projected(cam, A, ext), n++;
    if (ia != ib) {
        const float s = (COVER_NEAR - A[2]) / (B[2] - A[2]);
        float x[3];
        for (int j = 0; j < 3; ++j) x[j] = A[j] + (B[j] - A[j]) * s;
        x[2] = COVER_NEAR;
        extend_projected(cam, x, ext), n++;
    }
    return n;
}

static void cover_facade(const render_ctx *c, uint32_t i) {
    cover *cv = &c->cov[i];
    const pgt_facade_camera *cam = c->cam;
    memset(cv, 0, sizeof *cv);
    cv->dist = volume_distance(&c->f[i], cam->eye);
    float q[4][3];
    const uint32_t W = cam->width, H = cam->height;
    if (!pgt_facade_coverage(&c->f[i], cam->eye, q, NULL)) {
        cv->full = 1, cv->n = 1, cv->x0 = 0, cv->y0 = 0, cv->x1 = W - 1u, cv->y1 = H - 1u;
        return;
    }
    float in[4][3];
    for (int k = 0; k < 4; ++k) to_camera(cam, q[k], in[k]);
    float ext[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
    uint32_t n = 0;
    for (int k = 0; k < 4; ++k) n += extend_clipped(cam, in[k], in[(k + 1) % 4], ext);
    if (n < 3) return;
    if (!pixel_box(cv, cam, ext)) return;
    /* the cone's sides, oriented so that the polygon's centre is inside */
    float d[4][3], ctr[3] = {0.0f, 0.0f, 0.0f};
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) d[k][j] = q[k][j] - cam->eye[j], ctr[j] += 0.25f * d[k][j];
    for (int k = 0; k < 4; ++k) {
        float *c = cv->cone[k];
        cross3(d[k], d[(k + 1) % 4], c);
        const float l = sqrtf(dot3(c, c));
        if (!(l > 0.0f)) { /* the eye is on the polygon's plane: no cone, every pixel */
            cv->full = 1;
            break;
        }
        const float sg = dot3(c, ctr) < 0.0f ? -1.0f : 1.0f;
        for (int j = 0; j < 3; ++j) c[j] *= sg / l;
    }
    cv->n = 4;
}

/* The roof of building b: the pixel box of its footprint at roof height, clipped against the
 * near plane (a roof wholly behind it covers nothing), and its distance (to the footprint's box
 * at roof height). Until 2026-11-25 a roof with a corner behind the near plane covered the whole
 * screen: at street level in a city, half of the roofs lie partly behind the eye, and their
 * tests took 30 % of a 1000-building frame (perf, one thread). */
static void cover_roof(const render_ctx *c, uint32_t b) {
    cover *cv = &c->cov[c->fcount + b];
    const pgt_facade_camera *cam = c->cam;
    const pgt_facade_building *B = &c->s->buildings[b];
    const float *cr = c->s->corners + 2u * B->first_corner, y = B->base + B->height;
    memset(cv, 0, sizeof *cv);
    float lo[3] = {INFINITY, y, INFINITY}, hi[3] = {-INFINITY, y, -INFINITY};
    float ext[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
    const uint32_t m = B->corner_count;
    float first[3], cur[3];
    uint32_t n = 0;
    for (uint32_t k = 0; k < m; ++k) {
        const float P[3] = {cr[2 * k], y, cr[2 * k + 1]};
        lo[0] = facade_min(lo[0], P[0]), hi[0] = facade_max(hi[0], P[0]);
        lo[2] = facade_min(lo[2], P[2]), hi[2] = facade_max(hi[2], P[2]);
        float q[3];
        to_camera(cam, P, q);
        if (k == 0)
            memcpy(first, q, sizeof first);
        else
            n += extend_clipped(cam, cur, q, ext);
        memcpy(cur, q, sizeof cur);
    }
    if (m) n += extend_clipped(cam, cur, first, ext); /* the closing edge */
    cv->dist = box_distance(cam->eye, lo, hi);
    cv->full = 1; /* the roof test itself is exact: no cone */
    if (n >= 3 && pixel_box(cv, cam, ext)) cv->n = 1;
}

static void cover_range(void *vc, uint32_t b, uint32_t e, uint32_t worker) {
    const render_ctx *c = vc;
    (void)worker;
    for (uint32_t i = b; i < e; ++i) {
        if (i < c->fcount)
            cover_facade(c, i);
        else
            cover_roof(c, i - c->fcount);
    }
}

/* The ray direction d (unit) inside the cone over the coverage polygon. */
static int inside(const cover *cv, const float d[3]) {
    if (cv->full) return 1;
    for (int k = 0; k < 4; ++k)
        if (dot3(cv->cone[k], d) < -COVER_MARGIN_RAD) return 0;
    return 1;
}

/* The normal axis (0 x, 1 y, 2 z of facade space) of the rectangle with world normal n. */
static uint32_t axis_of(const float n[3], const pgt_facade *f) {
    if (fabsf(dot3(n, f->b)) > 0.5f) return 1u;
    return fabsf(dot3(n, f->t)) > 0.5f ? 0u : 2u;
}

typedef struct albedo_rgb {
    float r, g, b;
} albedo_rgb;

static albedo_rgb albedo(const pgt_facade_scene *sc, uint32_t kind, uint32_t surface,
                         uint32_t colour) {
    const albedo_rgb wall = {(float)((colour >> 16) & 255u) / 255.0f,
                             (float)((colour >> 8) & 255u) / 255.0f,
                             (float)(colour & 255u) / 255.0f};
    const albedo_rgb frame = {0.88f, 0.87f, 0.84f}, sill = {0.72f, 0.70f, 0.66f},
                     glass = {0.12f, 0.17f, 0.24f}, leaf = {0.33f, 0.20f, 0.11f},
                     stone = {0.78f, 0.76f, 0.71f}, rail = {0.22f, 0.22f, 0.24f};
    const albedo_rgb reveal = {wall.r * 0.8f, wall.g * 0.8f, wall.b * 0.8f};
    switch (kind) {
    case PGT_FACADE_WINDOW:
        return surface <= 3u    ? wall
               : surface <= 9u  ? sill
               : surface <= 16u ? frame
               : surface <= 20u ? reveal
               : surface == 21u ? glass
                                : wall;
    case PGT_FACADE_DOOR:
        return surface <= 2u ? wall : surface <= 8u ? frame : surface == 12u ? leaf : reveal;
    case PGT_FACADE_LEDGE:
        return stone;
    case PGT_FACADE_BALCONY:
        return surface <= 4u ? stone : rail;
    case PGT_FACADE_MESH: {
        const uint32_t role = surface < sc->gimage_triangle_count ? sc->gimage_roles[surface] : 0u;
        return role == PGT_FACADE_ROLE_FRAME    ? frame
               : role == PGT_FACADE_ROLE_REVEAL ? reveal
               : role == PGT_FACADE_ROLE_GLASS  ? glass
                                                : wall;
    }
    default:
        return wall;
    }
}

/* Sky colour of a missed pixel (linear). */
static const float SKY[3] = {0.62f, 0.74f, 0.88f};

/* Pixel p of the frame sees nothing. */
static void write_sky(pgt_facade_frame *fr, size_t p, int hits_only) {
    fr->depth[p] = INFINITY, fr->facade[p] = PGT_NONE;
    if (hits_only) return; /* a miss: depth and facade say it all */
    fr->terminal[p] = 0.0f, fr->node[p] = 0, fr->surface[p] = 0;
    for (int j = 0; j < 3; ++j) fr->rgb[3 * p + j] = SKY[j], fr->normal[3 * p + j] = 0.0f;
}

static void render_tiles(void *vc, uint32_t b, uint32_t e, uint32_t worker) {
    const render_ctx *c = vc;
    const pgt_facade_camera *cam = c->cam;
    pgt_facade_frame *fr = c->frame;
    pgt_facade_ray_stats *st = &c->wstats[worker];
    const uint32_t W = cam->width, H = cam->height;
    float dirs[TILE * TILE][3];
    pgt_facade_hit hits[TILE * TILE];
    uint32_t dev[TILE * TILE], idx[TILE * TILE];
    facade_cache *cache = &c->caches[worker];
    facade_packet_work *pw = c->packets[worker];
    facade_cache_clear(cache);
    for (uint32_t tile = b; tile < e; ++tile) {
        const uint32_t tx = tile % c->tiles_x, ty = tile / c->tiles_x;
        const uint32_t X0 = tx * TILE, Y0 = ty * TILE;
        const uint32_t X1 = X0 + TILE < W ? X0 + TILE : W, Y1 = Y0 + TILE < H ? Y0 + TILE : H;
        const uint32_t tw = X1 - X0;
        if (c->tile_first[tile] == c->tile_first[tile + 1]) { /* nothing here: sky */
            for (uint32_t y = Y0; y < Y1; ++y)
                for (uint32_t x = X0; x < X1; ++x) {
                    fr->developed[(size_t)y * W + x] = 0;
                    write_sky(fr, (size_t)y * W + x, c->sh->hits_only);
                }
            continue;
        }
        float sx[TILE]; /* pgt_facade_camera_ray's rays, each column's offset computed once */
        for (uint32_t x = X0; x < X1; ++x) sx[x - X0] = facade_camera_sx(cam, x);
        for (uint32_t y = Y0; y < Y1; ++y) {
            const float sy = facade_camera_sy(cam, y);
            for (uint32_t x = X0; x < X1; ++x) {
                const uint32_t k = (y - Y0) * tw + (x - X0);
                facade_camera_dir(cam, sx[x - X0], sy, dirs[k]);
                hits[k].t = INFINITY, hits[k].facade = PGT_NONE, hits[k].kind = 0;
                dev[k] = 0;
            }
        }
        for (uint32_t l = c->tile_first[tile]; l < c->tile_first[tile + 1]; ++l) {
            const uint32_t fi = c->tile_list[l];
            const cover *cv = &c->cov[fi];
            const uint32_t x0 = cv->x0 > X0 ? cv->x0 : X0, x1 = cv->x1 + 1u < X1 ? cv->x1 + 1u : X1;
            const uint32_t y0 = cv->y0 > Y0 ? cv->y0 : Y0, y1 = cv->y1 + 1u < Y1 ? cv->y1 + 1u : Y1;
            uint32_t n = 0; /* the rays this volume may hit nearer than their hit so far */
            for (uint32_t y = y0; y < y1; ++y)
                for (uint32_t x = x0; x < x1; ++x) {
                    const uint32_t k = (y - Y0) * tw + (x - X0);
                    /* the depth test: nothing of this volume can be nearer than the hit */
                    if (cv->dist >= hits[k].t || !inside(cv, dirs[k])) continue;
                    if (fi >= c->fcount) {
                        facade_roof_intersect(c->s, fi - c->fcount, c->fcount, cam->eye, dirs[k],
                                              &hits[k]);
                        continue;
                    }
                    idx[n++] = k;
                }
            c->wcovered[worker] += n;
            const float zs = zscale_of(c->sh, cv->dist);
            /* in packets (pw NULL: every ray alone), the same hits */
            const uint32_t errors = st->errors;
            st->errors = 0; /* this facade's errors alone, to name it */
            for (uint32_t i = 0; i < n; i += FACADE_PACKET)
                facade_intersect_packet(c->s, &c->f[fi], fi, cam->eye, (const float(*)[3])dirs,
                                        idx + i, n - i < FACADE_PACKET ? n - i : FACADE_PACKET,
                                        hits, dev, st, cache, pw, zs);
            if (st->errors && fi < c->werror[worker]) c->werror[worker] = fi;
            st->errors |= errors;
        }
        /* shading */
        for (uint32_t y = Y0; y < Y1; ++y)
            for (uint32_t x = X0; x < X1; ++x) {
                const uint32_t k = (y - Y0) * tw + (x - X0);
                const size_t p = (size_t)y * W + x;
                const pgt_facade_hit *h = &hits[k];
                fr->developed[p] = dev[k];
                if (h->facade == PGT_NONE) {
                    write_sky(fr, p, c->sh->hits_only);
                    continue;
                }
                const pgt_facade_shading *sh = c->sh;
                if (sh->hits_only) { /* what a ray caster returns; rgb, normal untouched */
                    fr->depth[p] = h->t, fr->terminal[p] = (float)h->kind;
                    fr->facade[p] = h->facade, fr->node[p] = h->node, fr->surface[p] = h->surface;
                    continue;
                }
                /* the hit point and the unit direction towards the light */
                float P[3], L[3];
                for (int j = 0; j < 3; ++j) P[j] = cam->eye[j] + h->t * dirs[k][j];
                for (int j = 0; j < 3; ++j) L[j] = sh->light[j] - P[j];
                const float dl = sqrtf(dot3(L, L));
                if (dl > 0.0f)
                    for (int j = 0; j < 3; ++j) L[j] /= dl;
                if (h->kind == PGT_FACADE_ROOF) { /* flat grey, lit by the light, unshadowed */
                    const float ny = dirs[k][1] > 0.0f ? -1.0f : 1.0f;
                    const float diffuse = dl > 0.0f && L[1] * ny > 0.0f ? L[1] * ny : 0.0f;
                    const float light = sh->ambient + (1.0f - sh->ambient) * diffuse;
                    for (int j = 0; j < 3; ++j) fr->rgb[3 * p + j] = ROOF_ALBEDO * light;
                    fr->depth[p] = h->t, fr->terminal[p] = (float)h->kind;
                    fr->normal[3 * p] = 0.0f, fr->normal[3 * p + 1] = ny,
                                   fr->normal[3 * p + 2] = 0.0f;
                    fr->facade[p] = h->facade, fr->node[p] = h->node, fr->surface[p] = h->surface;
                    continue;
                }
                const pgt_facade *f = &c->f[h->facade];
                const float zs = zscale_of(sh, c->cov[h->facade].dist);
                float n[3] = {h->n[0], h->n[1], h->n[2]};
                if (dot3(n, dirs[k]) > 0.0f) n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
                /* terminal space detail (6.3): the pattern always, normal and relief mapping by
                 * detail level */
                facade_detail_in din;
                din.material = facade_material(h->kind, h->surface);
                din.axis = axis_of(h->n, f);
                for (int j = 0; j < 3; ++j) din.p[j] = h->p[j];
                float unused[3];
                static const float origin0[3] = {0.0f, 0.0f, 0.0f};
                facade_to_local(f, origin0, dirs[k], unused, din.v);
                facade_to_local(f, origin0, L, unused, din.l);
                din.normal = din.relief = 0.0f;
                if (sh->detail == PGT_FACADE_DETAIL_NORMAL) din.normal = 1.0f;
                if (sh->detail == PGT_FACADE_DETAIL_RELIEF) din.normal = din.relief = 1.0f;
                if (sh->detail == PGT_FACADE_DETAIL_LOD) {
                    din.relief = ramp(
                        h->t, sh->relief_far > 0.0f ? sh->relief_near : PGT_FACADE_LOD_RELIEF_NEAR,
                        sh->relief_far > 0.0f ? sh->relief_far : PGT_FACADE_LOD_RELIEF_FAR);
                    din.normal = ramp(
                        h->t, sh->normal_far > 0.0f ? sh->normal_near : PGT_FACADE_LOD_NORMAL_NEAR,
                        sh->normal_far > 0.0f ? sh->normal_far : PGT_FACADE_LOD_NORMAL_FAR);
                }
                din.relief_shadows = sh->shadows;
                facade_detail_out dout;
                facade_detail(&din, &dout);
                /* the detail normal replaces the geometric one only where a material has relief
                 * (a smooth rectangle's would be the same; a geometry image's triangle is not
                 * axis-aligned); facade space to the world with the facade's own b (a quad of a
                 * generic mesh is not vertical) */
                if (din.material != FACADE_MAT_NONE && (din.normal > 0.0f || din.relief > 0.0f))
                    facade_vector_to_world(f, dout.n, n);
                float diffuse = dl > 0.0f ? dot3(n, L) : 0.0f;
                if (diffuse > 0.0f && dout.shadowed) diffuse = 0.0f;
                if (diffuse > 0.0f && sh->shadows) {
                    const float off = SHADOW_OFFSET_REL * h->t + SHADOW_OFFSET_ABS;
                    float so[3], gn[3] = {h->n[0], h->n[1], h->n[2]};
                    if (dot3(gn, dirs[k]) > 0.0f) gn[0] = -gn[0], gn[1] = -gn[1], gn[2] = -gn[2];
                    for (int j = 0; j < 3; ++j) so[j] = P[j] + off * gn[j];
                    pgt_facade_hit shh;
                    shh.t = dl;
                    shh.facade = PGT_NONE;
                    pgt_facade_ray_stats ss; /* shadow rays are not counted as view rays */
                    memset(&ss, 0, sizeof ss);
                    if (facade_intersect(c->s, f, h->facade, so, L, &shh, &ss, cache, zs))
                        diffuse = 0.0f;
                    st->errors |= ss.errors;
                    if (ss.errors && h->facade < c->werror[worker]) c->werror[worker] = h->facade;
                }
                if (diffuse < 0.0f) diffuse = 0.0f;
                const albedo_rgb a =
                    albedo(c->s, h->kind, h->surface, c->s->buildings[f->building].colour);
                const float pat =
                    din.material ? PATTERN_DARK + (1.0f - PATTERN_DARK) * dout.h : 1.0f;
                const float light = (sh->ambient + (1.0f - sh->ambient) * diffuse) * pat;
                fr->rgb[3 * p + 0] = a.r * light, fr->rgb[3 * p + 1] = a.g * light;
                fr->rgb[3 * p + 2] = a.b * light;
                fr->depth[p] = h->t + dout.s, fr->terminal[p] = (float)h->kind;
                for (int j = 0; j < 3; ++j) fr->normal[3 * p + j] = n[j];
                fr->facade[p] = h->facade, fr->node[p] = h->node, fr->surface[p] = h->surface;
            }
    }
}

typedef struct order_key {
    float dist;
    uint32_t index;
} order_key;

/* The bits of a float (not NaN) as an unsigned number that orders like the float. */
static uint32_t order_bits(float d) {
    d += 0.0f; /* -0 to +0: they compare equal */
    uint32_t u;
    memcpy(&u, &d, sizeof u);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

/* Sorts keys[0 .. n) by distance, ties by index (keys come in index order): an LSD radix sort
 * on the float's bits turned into an unsigned order (negative floats flipped whole, positive ones
 * their sign bit set; -0 added to 0 first), stable, so equal distances keep index order. qsort
 * with a comparison callback was 1.5 ms of a 10K-facade frame, serial. tmp holds n keys. */
static void sort_by_distance(order_key *keys, order_key *tmp, uint32_t n) {
    order_key *src = keys, *dst = tmp;
    for (uint32_t shift = 0; shift < 32; shift += 8) {
        uint32_t count[257] = {0};
        for (uint32_t i = 0; i < n; ++i) count[(order_bits(src[i].dist) >> shift & 255u) + 1u]++;
        for (uint32_t b = 0; b < 256; ++b) count[b + 1] += count[b];
        for (uint32_t i = 0; i < n; ++i)
            dst[count[order_bits(src[i].dist) >> shift & 255u]++] = src[i];
        order_key *t = src;
        src = dst, dst = t;
    }
    /* four passes: the result is back in keys */
}

pgt_result pgt_facade_render(const pgt_facade_scene *s, const pgt_facade *facades,
                             uint32_t facade_count, const pgt_facade_camera *cam,
                             const pgt_facade_shading *shading, uint32_t threads,
                             pgt_facade_frame *frame, pgt_facade_render_stats *stats,
                             pgt_error *err) {
    const double t_start = pgt_now_ms();
    if (stats) {
        memset(stats, 0, sizeof *stats);
        stats->error_facade = PGT_NONE;
    }
    if (frame->width != cam->width || frame->height != cam->height)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "render: frame %u x %u for a camera of %u x %u", frame->width,
                             frame->height, cam->width, cam->height);
    render_ctx c;
    memset(&c, 0, sizeof c);
    c.s = s, c.f = facades, c.fcount = facade_count, c.cam = cam, c.sh = shading, c.frame = frame;
    c.tiles_x = (cam->width + TILE - 1u) / TILE, c.tiles_y = (cam->height + TILE - 1u) / TILE;
    const uint32_t tiles = c.tiles_x * c.tiles_y;
    const uint32_t prims = facade_count + s->building_count; /* facades, then roofs */
    c.cov = malloc((size_t)(prims ? prims : 1) * sizeof *c.cov);
    c.order = malloc((size_t)(prims ? prims : 1) * sizeof *c.order);
    c.tile_first = calloc((size_t)tiles + 1u, sizeof *c.tile_first);
    c.wstats = calloc(PGT_MAX_THREADS, sizeof *c.wstats);
    c.werror = malloc(PGT_MAX_THREADS * sizeof *c.werror);
    for (uint32_t w = 0; c.werror && w < PGT_MAX_THREADS; ++w) c.werror[w] = PGT_NONE;
    c.wcovered = calloc(PGT_MAX_THREADS, sizeof *c.wcovered);
    const uint32_t workers = pgt_parallel_workers(threads);
    c.caches = malloc(workers * sizeof *c.caches);
    c.packets = calloc(workers, sizeof *c.packets);
    int packets_ok = c.packets != NULL;
    for (uint32_t w = 0; packets_ok && !shading->single_rays && w < workers; ++w)
        packets_ok = (c.packets[w] = facade_packet_work_create()) != NULL;
    uint8_t **draws = calloc(s->grammar_count ? s->grammar_count : 1u, sizeof *draws);
    uint32_t **collapse = calloc(s->grammar_count ? s->grammar_count : 1u, sizeof *collapse);
    int draws_ok = draws != NULL && collapse != NULL;
    for (uint32_t k = 0; draws_ok && k < s->grammar_count; ++k)
        draws_ok = (draws[k] = facade_draws_table(&s->grammars[k])) != NULL &&
                   (collapse[k] = facade_collapse_table(&s->grammars[k])) != NULL;
    for (uint32_t w = 0; c.caches && w < workers; ++w) {
        c.caches[w].draws = (const uint8_t *const *)draws;
        c.caches[w].collapse = (const uint32_t *const *)collapse;
    }
    pgt_result r = PGT_OK;
    if (!c.cov || !c.order || !c.tile_first || !c.wstats || !c.werror || !c.wcovered || !c.caches ||
        !draws_ok || !packets_ok) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "render: out of memory");
        goto done;
    }
    pgt_parallel_for(prims, threads, cover_range, &c);
    order_key *keys = malloc(2u * (size_t)(prims ? prims : 1) * sizeof *keys);
    if (!keys) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "render: out of memory");
        goto done;
    }
    for (uint32_t i = 0; i < prims; ++i)
        if (c.cov[i].n) keys[c.visible].dist = c.cov[i].dist, keys[c.visible++].index = i;
    sort_by_distance(keys, keys + (prims ? prims : 1), c.visible);
    for (uint32_t v = 0; v < c.visible; ++v) c.order[v] = keys[v].index;
    free(keys);
    /* bin into tiles, near to far */
    uint64_t total = 0;
    for (uint32_t v = 0; v < c.visible; ++v) {
        const cover *cv = &c.cov[c.order[v]];
        for (uint32_t ty = cv->y0 / TILE; ty <= cv->y1 / TILE; ++ty)
            for (uint32_t tx = cv->x0 / TILE; tx <= cv->x1 / TILE; ++tx)
                c.tile_first[ty * c.tiles_x + tx + 1u]++, total++;
    }
    if (total > UINT32_MAX) {
        r = pgt_error_set(err, PGT_ERROR_LIMIT, "render: %llu facade-tile pairs",
                          (unsigned long long)total);
        goto done;
    }
    for (uint32_t t = 0; t < tiles; ++t) c.tile_first[t + 1] += c.tile_first[t];
    c.tile_list = malloc((size_t)(total ? total : 1) * sizeof *c.tile_list);
    uint32_t *fill = malloc((size_t)tiles * sizeof *fill);
    if (!c.tile_list || !fill) {
        free(fill);
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "render: out of memory");
        goto done;
    }
    memcpy(fill, c.tile_first, (size_t)tiles * sizeof *fill);
    for (uint32_t v = 0; v < c.visible; ++v) {
        const cover *cv = &c.cov[c.order[v]];
        for (uint32_t ty = cv->y0 / TILE; ty <= cv->y1 / TILE; ++ty)
            for (uint32_t tx = cv->x0 / TILE; tx <= cv->x1 / TILE; ++tx)
                c.tile_list[fill[ty * c.tiles_x + tx]++] = c.order[v];
    }
    free(fill);
    const double t_cover = pgt_now_ms();
    pgt_parallel_for_items(tiles, TILE * TILE, threads, render_tiles, &c);
    const double t_end = pgt_now_ms();
    if (stats) {
        for (uint32_t w = 0; w < PGT_MAX_THREADS; ++w) {
            const pgt_facade_ray_stats *ws = &c.wstats[w];
            stats->rays.rays += ws->rays, stats->rays.volume_hits += ws->volume_hits;
            stats->rays.nodes += ws->nodes, stats->rays.terminals += ws->terminals;
            stats->rays.quads += ws->quads, stats->rays.errors |= ws->errors;
            if (c.werror[w] < stats->error_facade) stats->error_facade = c.werror[w];
            stats->covered_pixels += c.wcovered[w];
        }
        stats->visible_facades = 0;
        for (uint32_t v = 0; v < c.visible; ++v)
            stats->visible_facades += c.order[v] < facade_count;
        stats->ms_cover = t_cover - t_start, stats->ms_rays = t_end - t_cover;
        stats->ms_total = t_end - t_start;
    }
done:
    free(c.cov);
    free(c.order);
    free(c.tile_first);
    free(c.tile_list);
    free(c.wstats);
    free(c.werror);
    free(c.wcovered);
    free(c.caches);
    for (uint32_t w = 0; c.packets && w < workers; ++w) facade_packet_work_destroy(c.packets[w]);
    free(c.packets);
    for (uint32_t k = 0; draws && k < s->grammar_count; ++k) free(draws[k]);
    for (uint32_t k = 0; collapse && k < s->grammar_count; ++k) free(collapse[k]);
    free(draws);
    free(collapse);
    return r;
}
