/* pgt: what the atlas stages pass to each other (atlas_build.c drives them; see atlas_build.h).
 * Private to ref_cpu/src/atlas_*.c. */
#ifndef PGT_ATLAS_INTERNAL_H
#define PGT_ATLAS_INTERNAL_H

#include <stdint.h>

#include "pgt/adjacency.h"
#include "pgt/atlas_build.h"
#include "pgt/image.h"
#include "pgt/mesh.h"
#include "pgt/result.h"

/* Most charts: chart ids travel as float in the atlas, exact up to 2^24. */
#define PGT_ATLAS_MAX_CHARTS (1u << 24)

/* Step 1 (atlas_charts.c). */
typedef struct atlas_charts {
    uint32_t face_count, chart_count;
    uint32_t *face_chart;    /* face_count: chart id, or PGT_NONE (degenerate UV triangle) */
    float *uvs;              /* 6 * face_count: the mesh UVs, mirrored charts flipped in u */
    uint8_t *chart_mirrored; /* chart_count */
    double *chart_area_uv;   /* chart_count: sum of |UV area| of its rasterized faces */
    double *chart_area_3d;   /* chart_count: sum of 3D area of the same faces */
    uint32_t mirrored, degenerate_faces, degenerate_charts;
    /* the mesh border: half-edges h = 3 f + c of rasterized faces (face_chart != PGT_NONE)
     * without an opposite half-edge (pgt_adjacency; non-manifold edges count too) */
    uint32_t *border_half_edges, border_count;
    /* seams between charts: pairs (h, chart of the opposite face, PGT_NONE for a degenerate UV
     * triangle) for every half-edge h of a rasterized face whose opposite face lies in another
     * chart or in none; 2 * cross_count entries (atlas_build compacts them in place into the
     * gaps' half-edges) */
    uint32_t *cross_half_edges, cross_count;
    /* seams inside one chart: pairs of opposite half-edges (h, o), both faces rasterized and in
     * the same chart, whose corners carry other UVs on the two sides (a slit or a cylinder cut
     * inside the chart); 2 * seam_count entries */
    uint32_t *seam_half_edges, seam_count;
} atlas_charts;

/* The two texel-space copies of seam s (seam_half_edges[2 s], [2 s + 1] = h, o) in tex (6
 * floats per face): out = {a0, b0, a1, b1}, a0 b0 on h's side, a1 b1 on o's; the a's are one 3D
 * vertex (h's corner c), the b's another (c + 1): h runs c -> c+1, o the other way, so corner c
 * meets next(o) and next(h) meets o. */
static inline void atlas_seam_copies(const atlas_charts *ch, const float *tex, uint32_t s,
                                     const float *out[4]) {
    const uint32_t h = ch->seam_half_edges[2u * s], o = ch->seam_half_edges[2u * s + 1u];
    out[0] = &tex[2u * h], out[1] = &tex[2u * pgt_half_edge_next(h)];
    out[2] = &tex[2u * pgt_half_edge_next(o)], out[3] = &tex[2u * o];
}

/* Squared distance from (px, py) to the segment from (ax, ay) to (bx, by). */
static inline double atlas_segment_dist2(double ax, double ay, double bx, double by, double px,
                                         double py) {
    const double dx = bx - ax, dy = by - ay, dd = dx * dx + dy * dy;
    double s = dd > 0.0 ? ((px - ax) * dx + (py - ay) * dy) / dd : 0.0;
    s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
    const double ex = ax + s * dx - px, ey = ay + s * dy - py;
    return ex * ex + ey * ey;
}

pgt_result atlas_charts_build(atlas_charts *out, const pgt_mesh *mesh, uint32_t threads,
                              const char *what, pgt_error *err);
void atlas_charts_destroy(atlas_charts *c);

/* Step 3 (atlas_raster.c): rasterizes the faces with a chart at texel coordinates tex
 * (6 * face_count floats, x y per corner). Always fills texel_chart (width * height, -1 where no
 * triangle covers the centre); when atlas is not NULL also its P, N, chart and kind planes (the
 * other planes are left alone). Ties: the smallest face id wins a texel. */
typedef struct atlas_raster_counts {
    uint32_t inner;     /* covered texels */
    uint32_t fold_over; /* texel centres strictly inside two triangles of one chart */
    uint32_t overlap;   /* texel centres covered by triangles of two charts */
    uint32_t over_box;  /* coverage raster only: the triangles' boxes exceed
                           ATLAS_RASTER_MAX_BOX_IMAGES, nothing rastered (repack); the raster
                           with attributes fails there (PGT_ERROR_LIMIT) */
} atlas_raster_counts;

pgt_result atlas_raster(const pgt_mesh *mesh, const atlas_charts *charts, const float *tex,
                        uint32_t width, uint32_t height, const float *vertex_normals,
                        pgt_image *atlas, int32_t *texel_chart, uint32_t threads,
                        atlas_raster_counts *out_counts, pgt_error *err);

/* Step 3b (atlas_raster.c): fills the cracks of the seams inside a chart (atlas_build.h,
 * PGT_ATLAS_CRACK_TEXELS): every texel no triangle covers (texel_chart -1) whose centre lies in
 * the quad between the two texel-space copies of such a seam edge, where the copies lie at most
 * PGT_ATLAS_CRACK_TEXELS apart, becomes an inner texel of the chart with P on the 3D edge and N
 * between its ends' vertex normals. Serial, in seam order (the first quad wins a texel); quads
 * whose copies cross are skipped, and so are the seams past a work bound (atlas_raster.c).
 * Returns the number of texels filled; crack (width * height, zeroed by the caller) gets 1 +
 * the index of the filling seam (in seam_half_edges) at each, and ATLAS_CRACK_UNFILLED | (1 +
 * index) at the uncovered texels of the same quads where the copies lie farther apart (not
 * filled). */
#define ATLAS_CRACK_UNFILLED 0x80000000u
#define ATLAS_CRACK_FILLED(v) ((v) != 0u && !((v)&ATLAS_CRACK_UNFILLED))
uint32_t atlas_fill_cracks(const pgt_mesh *mesh, const atlas_charts *charts, const float *tex,
                           uint32_t width, uint32_t height, const float *vertex_normals,
                           pgt_image *atlas, int32_t *texel_chart, uint32_t *crack);

/* Area-weighted vertex normals (3 * vertex_count floats, unit or 0). */
pgt_result atlas_vertex_normals(const pgt_mesh *mesh, float **out, pgt_error *err);

/* Step 2 (atlas_layout.c): texel coordinates of every corner (6 * face_count floats, malloc'd).
 * atlas_layout_build keeps the input UVs (x = u W, y = (1 - v) H, repacked = 0) when they lie
 * `band` texels inside [0,1]^2 and their areas do not add up beyond it (the caller then, unless
 * `separated`, rasterizes and checks the band with atlas_band_violations), else repacks.
 * atlas_layout_repack always repacks (into a layout that already holds tex). */
typedef struct atlas_layout {
    float *tex;
    int repacked;
    int separated; /* kept, and the charts' bounding boxes are more than band apart: no test */
    double scale;  /* repacked: texels per unit of 3D length */
} atlas_layout;

pgt_result atlas_layout_build(atlas_layout *out, const pgt_mesh *mesh, const atlas_charts *charts,
                              uint32_t width, uint32_t height, uint32_t band, int force_repack,
                              uint32_t threads, const char *what, pgt_error *err);
pgt_result atlas_layout_repack(atlas_layout *out, const pgt_mesh *mesh, const atlas_charts *charts,
                               uint32_t width, uint32_t height, uint32_t band, uint32_t threads,
                               const char *what, pgt_error *err);
void atlas_layout_destroy(atlas_layout *l);

/* The number of inner texels that have an inner texel of another chart, or the image border,
 * within Chebyshev distance band (texel_chart as atlas_raster fills it); PGT_NONE when out of
 * memory. */
uint32_t atlas_band_violations(const int32_t *texel_chart, uint32_t width, uint32_t height,
                               uint32_t band, uint32_t threads);

/* Step 4 (atlas_pointers.c), crack as atlas_fill_cracks marks it (NULL: no texel filled):
 * classifies texels into `kind` (width * height bytes: INNER,
 * INDIRECTION for every outer-boundary texel, BACKGROUND; bit 0x80 marks an inner-boundary
 * texel), fills the planes of the outer-boundary texels (P, chart, kind: indirection or dead
 * end, ptr) and ptr/rot of all others, and measures the texel size. dest_chart (width * height)
 * gets, at every outer-boundary texel, the chart its pointer points into (-1 for a dead end);
 * other texels are left as they are. */
typedef struct atlas_pointer_counts {
    uint32_t inner_boundary, indirection, dead_end, self_seam;
    uint32_t own_chart; /* of self_seam: the own-chart fallback's (atlas_pointers.c) */
    double texel_size;
} atlas_pointer_counts;

#define ATLAS_KIND_BOUNDARY_BIT 0x80u

/* The mesh border in texel space, for atlas_pointers: tex as atlas_layout gives it (6 floats per
 * face), the border half-edges of atlas_charts, and the gaps: half-edges with nothing
 * rasterized across (a degenerate UV triangle, a chart without texels at this resolution). */
typedef struct atlas_border {
    const float *tex;
    const uint32_t *half_edges;
    uint32_t count;
    const uint32_t *gap_half_edges;
    uint32_t gap_count;
} atlas_border;

pgt_result atlas_pointers(pgt_image *atlas, const int32_t *texel_chart, const uint32_t *crack,
                          uint8_t *kind, int32_t *dest_chart, float dead_end,
                          const atlas_border *border, uint32_t threads, atlas_pointer_counts *out,
                          pgt_error *err);

/* Step 6 (atlas_angles.c): the rot plane of every indirection texel (5.2), from atlas_pointers'
 * kind and dest_chart. */
pgt_result atlas_angles(pgt_image *atlas, const int32_t *texel_chart, const uint8_t *kind,
                        const int32_t *dest_chart, uint32_t k, uint32_t threads, pgt_error *err);

/* Step 6b (atlas_angles.c): rot of the indirection texels in the crack of a seam that
 * atlas_fill_cracks filled in part, or next to a crack's fill, whose pointer leads into their
 * own chart (across the crack where it is not filled): the angle from
 * one texel-space copy of the filling seam edge to the other, towards the copy nearer to the
 * pointer's texel. The two copies are the same 3D edge, so this is 5.2's t1 -> t2 exactly,
 * where the boundary walks go round the end of the fill and give no tangent of the seam.
 * crack as atlas_fill_cracks fills it. */
void atlas_crack_angles(pgt_image *atlas, const atlas_charts *charts, const float *tex,
                        const uint32_t *crack, const int32_t *dest_chart);

/* Step 6c (atlas_angles.c, --angles jacobian): replaces rot by the angle fitted to P's
 * Jacobians (pgt_atlas_angles) wherever the fit exists and keeps the invariant; *out_fitted gets
 * how many texels that was. Reads the P, N, chart, kind and pointer planes. */
pgt_result atlas_fit_angles(pgt_image *atlas, const int32_t *texel_chart, const int32_t *dest_chart,
                            uint32_t threads, uint32_t *out_fitted, pgt_error *err);

/* Runs fn over the rows [0, rows) of a width-wide grid in parallel (pgt_parallel_for_items
 * with a row weighing `width` texels); callers pass other items with their weight too (raster
 * tiles, charts). */
typedef void (*atlas_rows_fn)(void *ctx, uint32_t row_begin, uint32_t row_end, uint32_t worker);
void atlas_parallel_rows(uint32_t rows, uint32_t width, uint32_t threads, atlas_rows_fn fn,
                         void *ctx);

#endif
