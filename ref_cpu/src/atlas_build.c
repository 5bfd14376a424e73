/* pgt: the atlas builder, driving the stages of paper 000 sections 4 and 5.2 (see
 * atlas_build.h for the decisions, atlas_internal.h for what the stages exchange). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_internal.h"
#include "pgt/mesh_io.h"
#include "pgt/parallel.h"
#include "time_internal.h"

void atlas_parallel_rows(uint32_t rows, uint32_t width, uint32_t threads, atlas_rows_fn fn,
                         void *ctx) {
    pgt_parallel_for_items(rows, width, threads, fn, ctx);
}

/* Per worker, which charts the texels of its rows belong to. */
typedef struct seen_ctx {
    const int32_t *texel_chart;
    uint32_t width, charts;
    uint8_t *seen; /* per worker: charts bytes */
} seen_ctx;

static void seen_rows(void *vctx, uint32_t y0, uint32_t y1, uint32_t worker) {
    const seen_ctx *c = vctx;
    uint8_t *seen = &c->seen[(size_t)worker * c->charts];
    for (size_t i = (size_t)y0 * c->width; i < (size_t)y1 * c->width; ++i)
        if (c->texel_chart[i] >= 0) seen[c->texel_chart[i]] = 1;
}

pgt_result pgt_atlas_build(pgt_image *out, const pgt_mesh *mesh, const pgt_atlas_options *opt,
                           pgt_atlas_stats *out_stats, pgt_error *err) {
    const double t_start = pgt_now_ms();
    static const pgt_atlas_options defaults = {0};
    if (!opt) opt = &defaults;
    memset(out, 0, sizeof(*out));
    const char *what = opt->what ? opt->what : "mesh";
    const uint32_t W = opt->width ? opt->width : PGT_ATLAS_DEFAULT_RES;
    const uint32_t H = opt->height ? opt->height : PGT_ATLAS_DEFAULT_RES;
    const uint32_t band = opt->band > PGT_ATLAS_MIN_BAND ? opt->band : PGT_ATLAS_MIN_BAND;
    const uint32_t k = opt->k ? opt->k : PGT_ATLAS_DEFAULT_K;
    const float dead_end = opt->dead_end != 0.0f ? opt->dead_end : PGT_ATLAS_DEFAULT_DEAD_END;
    const uint32_t threads = opt->threads ? opt->threads : 1u;
    pgt_atlas_stats st;
    memset(&st, 0, sizeof(st));
    if (!mesh) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "pgt_atlas_build: no mesh");
    if (!mesh->uvs)
        return pgt_error_set(err, PGT_ERROR_UNSUPPORTED,
                             "%s: no UVs: run a parametrization first (datasets_gen gives "
                             "UV-less meshes an atlas)",
                             what);
    if (mesh->face_count == 0) return pgt_error_set(err, PGT_ERROR_EMPTY, "%s: no faces", what);
    if (W > PGT_ATLAS_MAX_RES || H > PGT_ATLAS_MAX_RES ||
        (uint64_t)W * H * PGT_ATLAS_CHANNEL_COUNT > PGT_IMAGE_MAX_VALUES)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "--res: a %ux%u atlas of %u float channels exceeds the image limit "
                             "(at most %u texels a side and %u values; the largest square atlas "
                             "is %ux%u)",
                             W, H, PGT_ATLAS_CHANNEL_COUNT, PGT_ATLAS_MAX_RES,
                             (unsigned)PGT_IMAGE_MAX_VALUES, PGT_ATLAS_MAX_SQUARE_RES,
                             PGT_ATLAS_MAX_SQUARE_RES);
    if (W < PGT_ATLAS_MIN_RES || H < PGT_ATLAS_MIN_RES)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "--res: a %ux%u atlas is too small (at least %u texels a side: one "
                             "inner texel with a free band of %u on both sides)",
                             W, H, PGT_ATLAS_MIN_RES, PGT_ATLAS_MIN_BAND);
    if (band > PGT_ATLAS_MAX_BAND)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "--band: %u is above %u", band,
                             PGT_ATLAS_MAX_BAND);
    if (2u * band + 1u > W || 2u * band + 1u > H)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "--band: a band of %u leaves no room in a %ux%u atlas (--res)", band,
                             W, H);
    if (k > PGT_ATLAS_MAX_K)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "--k: %u is not in 1..%u", k,
                             PGT_ATLAS_MAX_K);
    if (opt->angles != PGT_ATLAS_ANGLES_TANGENTS && opt->angles != PGT_ATLAS_ANGLES_JACOBIAN)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "--angles: %d is not one of tangents (0), jacobian (1)",
                             (int)opt->angles);
    if (!isfinite(dead_end) || !(dead_end > 0.0f) || dead_end > PGT_ATLAS_MAX_DEAD_END)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "--dead-end: %g is not a number of texel sizes in (0, %g]",
                             (double)dead_end, (double)PGT_ATLAS_MAX_DEAD_END);
    float c = 0.0f; /* the coordinate that is beyond */
    const uint32_t far = pgt_mesh_far_vertex(mesh, PGT_ATLAS_MAX_COORD, &c);
    if (far != PGT_NONE) {
        char place[4200];
        pgt_mesh_origin_vertex_where(opt->origin, what, far, place, sizeof place);
        if (!isfinite(c))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: vertex %u (0-based) has a non-finite position", place, far);
        return pgt_error_set(
            err, PGT_ERROR_INVALID_ARGUMENT,
            "%s: vertex %u (0-based): coordinate %g is beyond +-%g (squared distances in "
            "float would overflow; scale the mesh down)",
            place, far, (double)c, (double)PGT_ATLAS_MAX_COORD);
    }
    for (uint64_t i = 0; i < 3ull * mesh->face_count; ++i)
        if (mesh->indices[i] >= mesh->vertex_count)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: face %u names vertex %u of %u", what, (uint32_t)(i / 3u),
                                 mesh->indices[i], mesh->vertex_count);
    st.width = W, st.height = H, st.band = band, st.k = k, st.faces = mesh->face_count;

    atlas_charts charts;
    atlas_layout layout;
    memset(&layout, 0, sizeof(layout));
    int32_t *texel_chart = NULL;
    uint8_t *kind = NULL;
    int32_t *dest_chart = NULL; /* per outer-boundary texel: its pointer's chart */
    float *normals = NULL;
    uint32_t *crack = NULL; /* texels filled in seam cracks (atlas_fill_cracks) */
    uint8_t *seen = NULL;   /* per worker and chart: the chart has a texel in its rows */
    pgt_progress *const pr = opt->progress;
    pgt_progress_stage(pr, "charts", 0, "");
    double t = pgt_now_ms();
    pgt_result r = atlas_charts_build(&charts, mesh, threads, what, err);
    if (r != PGT_OK) return r;
    st.charts = charts.chart_count;
    st.mirrored_charts = charts.mirrored;
    st.degenerate_faces = charts.degenerate_faces;
    st.degenerate_charts = charts.degenerate_charts;
    st.ms_charts = pgt_now_ms() - t;

    texel_chart = malloc(sizeof(int32_t) * (size_t)W * H);
    kind = malloc((size_t)W * H);
    dest_chart = malloc(sizeof(int32_t) * (size_t)W * H);
    if (!texel_chart || !kind || !dest_chart) {
        r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (%ux%u atlas)", what, W,
                          H);
        goto done;
    }
    pgt_progress_stage(pr, "layout", 0, "");
    t = pgt_now_ms();
    r = atlas_layout_build(&layout, mesh, &charts, W, H, band, opt->force_repack, threads, what,
                           err);
    if (r != PGT_OK) goto done;
    if (!layout.repacked && !layout.separated) {
        /* The input UVs are kept only if their charts keep the band at this resolution: a
         * coverage raster (no attributes) and the band test decide, as layout time. */
        atlas_raster_counts cover;
        r = atlas_raster(mesh, &charts, layout.tex, W, H, NULL, NULL, texel_chart, threads, &cover,
                         err);
        if (r != PGT_OK) goto done;
        st.overlap_texels = cover.overlap;
        if (cover.over_box || cover.overlap ||
            atlas_band_violations(texel_chart, W, H, band, threads)) {
            r = atlas_layout_repack(&layout, mesh, &charts, W, H, band, threads, what, err);
            if (r != PGT_OK) goto done;
        }
    }
    st.ms_layout = pgt_now_ms() - t;

    pgt_progress_stage(pr, "raster", 0, "");
    t = pgt_now_ms();
    static const char *const names[] = PGT_ATLAS_CHANNEL_NAMES;
    /* every value is written below: channels P, N, chart and kind by atlas_raster (background
     * texels too), ptr.u, ptr.v and rot by atlas_pointers */
    r = pgt_image_create_unset(out, W, H, PGT_ATLAS_CHANNEL_COUNT, names, err);
    if (r != PGT_OK) goto done;
    r = atlas_vertex_normals(mesh, &normals, err);
    if (r != PGT_OK) goto done;
    atlas_raster_counts rc;
    r = atlas_raster(mesh, &charts, layout.tex, W, H, normals, out, texel_chart, threads, &rc, err);
    if (r != PGT_OK) goto done;
    if (charts.seam_count) {
        crack = calloc((size_t)W * H, sizeof(uint32_t));
        if (!crack) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory (%ux%u atlas)", what,
                              W, H);
            goto done;
        }
        st.crack_texels =
            atlas_fill_cracks(mesh, &charts, layout.tex, W, H, normals, out, texel_chart, crack);
    }
    rc.inner += st.crack_texels;
    st.repacked = layout.repacked;
    st.uv_scale = layout.repacked ? layout.scale : 0.0;
    if (rc.inner == 0) {
        r = pgt_error_set(err, PGT_ERROR_LIMIT,
                          "%s: no chart covers a texel centre at %u x %u (every chart is smaller "
                          "than a texel there): raise --res, or --repack to scale the UVs up",
                          what, W, H);
        goto done;
    }
    st.inner_texels = rc.inner;
    st.fold_over_texels = rc.fold_over;
    st.packing_efficiency = (double)rc.inner / ((double)W * H);
    {
        /* charts without texels: each worker marks the charts of its rows in its own array */
        const uint32_t workers = pgt_parallel_workers(threads);
        seen = calloc((size_t)workers * charts.chart_count + 1, 1);
        if (!seen) {
            r = pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
            goto done;
        }
        seen_ctx sc = {texel_chart, W, charts.chart_count, seen};
        atlas_parallel_rows(H, W, workers, seen_rows, &sc);
        for (uint32_t c = 0; c < charts.chart_count; ++c) { /* into seen[c] */
            for (uint32_t w = 1; w < workers; ++w)
                seen[c] |= seen[(size_t)w * charts.chart_count + c];
            st.empty_charts += !seen[c];
        }
    }
    st.ms_raster = pgt_now_ms() - t;

    pgt_progress_stage(pr, "pointers", 0, "");
    t = pgt_now_ms();
    atlas_pointer_counts pc;
    /* The gaps: seams with nothing rasterized across, a degenerate UV triangle's or a chart's
     * that got no texel (smaller than a texel at this resolution). atlas_pointers keeps the
     * dead ends next to them as next to the mesh border. */
    uint32_t *const gaps = charts.cross_half_edges; /* compacted in place: entry n <= 2 i */
    uint32_t gap_count = 0;
    for (uint32_t i = 0; i < charts.cross_count; ++i) {
        const uint32_t h = gaps[2u * i], other = gaps[2u * i + 1u];
        if (other == PGT_NONE || !seen[other]) gaps[gap_count++] = h;
    }
    const atlas_border bd = {layout.tex, charts.border_half_edges, charts.border_count, gaps,
                             gap_count};
    r = atlas_pointers(out, texel_chart, st.crack_texels ? crack : NULL, kind, dest_chart, dead_end,
                       &bd, threads, &pc, err);
    if (r != PGT_OK) goto done;
    st.inner_boundary_texels = pc.inner_boundary;
    st.indirection_texels = pc.indirection;
    st.dead_end_texels = pc.dead_end;
    st.self_seam_pointers = pc.self_seam;
    st.own_chart_pointers = pc.own_chart;
    st.texel_size = pc.texel_size;
    st.ms_pointers = pgt_now_ms() - t;

    pgt_progress_stage(pr, "angles", 0, "");
    t = pgt_now_ms();
    r = atlas_angles(out, texel_chart, kind, dest_chart, k, threads, err);
    if (r != PGT_OK) goto done;
    if (st.crack_texels) atlas_crack_angles(out, &charts, layout.tex, crack, dest_chart);
    if (opt->angles == PGT_ATLAS_ANGLES_JACOBIAN) {
        r = atlas_fit_angles(out, texel_chart, dest_chart, threads, &st.fitted_angles, err);
        if (r != PGT_OK) goto done;
    }
    st.ms_angles = pgt_now_ms() - t;
done:
    free(texel_chart);
    free(kind);
    free(dest_chart);
    free(normals);
    free(crack);
    free(seen);
    atlas_layout_destroy(&layout);
    atlas_charts_destroy(&charts);
    if (r != PGT_OK) {
        pgt_image_destroy(out);
        return r;
    }
    st.ms_total = pgt_now_ms() - t_start;
    if (out_stats) *out_stats = st;
    return PGT_OK;
}
