/* pgt atlas: a multi-chart geometry-image atlas with indirection pointers and rotation angles
 * from a mesh with UVs (paper 000 sections 4 and 5.2; ref_cpu/src/atlas_*.c). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "png_io.h"
#include "progress_line.h"
#include "pgt/atlas_build.h"
#include "pgt/mesh_io.h"
#include "pgt/rng.h"

static const char *atlas_usage =
    "usage: pgt atlas MESH -o ATLAS.exr [--res N] [--band B] [--k K] [--png PIC.png]\n"
    "                 [--angles tangents|jacobian] [--dead-end T] [--repack] [--threads N]\n"
    "                 [--json]\n"
    "\n"
    "Builds the indirection geometry image of paper 000 (sections 4 and 5.2): charts from the\n"
    "mesh's per-corner UVs, the layout (input UVs kept when they leave a free band around every\n"
    "chart at this resolution, else repacked), the rasterized positions and normals, the\n"
    "indirection pointers of the outer-boundary texels and their rotation angles.\n"
    "\n"
    "  MESH           .obj .off .ply with per-corner UVs, a mesh of ../shared/datasets/meshes by\n"
    "                 name, or a generated dataset (pgt_datasets --list, e.g. cube_sphere_8).\n"
    "                 Mirrored charts are flipped in u and counted; zero-area UV triangles are\n"
    "                 counted and skipped; overlapping charts or UVs outside [0,1] repack.\n"
    "  -o ATLAS.exr   output OpenEXR, 11 float channels P.x P.y P.z N.x N.y N.z chart kind\n"
    "                 ptr.u ptr.v rot (ref_cpu/include/pgt/atlas.h); written to a temporary\n"
    "                 file, then renamed\n"
    "  --res N        atlas of N x N texels, 5 to 4939 (default 1024)\n"
    "  --band B       free band around every chart in texels, 2 to 64 (default 2; lower values\n"
    "                 are raised to 2)\n"
    "  --k K          boundary texels followed per tangent for the rotation angles, 1 to 64\n"
    "                 (default 4)\n"
    "  --angles A     how the rotation angle rot of an indirection texel is found:\n"
    "                 tangents (default): 5.2's boundary tangents from K texels;\n"
    "                 jacobian: fitted to the local maps of the two charts (P's Jacobians),\n"
    "                 the angle that turns the most of 8 headings leaving the chart by at most\n"
    "                 10 degrees in 3D, 5.2's angle where a chart is too thin for a Jacobian\n"
    "                 (lower turns at jumps where the two sides' UVs shear differently: spot,\n"
    "                 pizza); same channels, same marcher\n"
    "  --dead-end T   an outer-boundary texel whose nearest candidate is farther than T texel\n"
    "                 sizes is a dead end (default 4, at most 64; texel size = the larger of\n"
    "                 the median 3D distance of 4-adjacent inner texels and the local one,\n"
    "                 the largest 3D step from the adjacent inner-boundary texels to their\n"
    "                 neighbours; away from the mesh border a farther candidate, up to 8\n"
    "                 times as far, counts when it lies within T of its own local texel\n"
    "                 sizes)\n"
    "  --png PIC.png  also a picture: charts coloured (shaded by the normal), indirection\n"
    "                 texels white, dead ends red, background black\n"
    "  --repack       repack the charts even when the input UVs would do\n"
    "  --threads N    worker threads for the build and the EXR's compression, 1 to 256 (default:\n"
    "                 the number of CPUs; the same bytes for any count)\n"
    "  --json         print the summary as one JSON object\n"
    "\n"
    "Prints charts, mirrored charts, degenerate UV triangles, inner / inner-boundary /\n"
    "indirection / dead-end texels, whether the layout was kept or repacked, the packing\n"
    "efficiency (inner texels / N^2), the texels filled in the cracks of seams inside a chart\n"
    "(a slit cut into a chart: where its two sides lie within 3 texels its texels become inner\n"
    "texels on the seam in 3D) and ms per stage. Exit 0 on success, 2 on a bad flag or input\n"
    "(a mesh without UVs, a resolution too small for the charts, ...). A progress line on\n"
    "stderr every 5 s of work (PGT_PROGRESS_SECONDS: the period, 0: none).\n";

/* --angles values, indexed by pgt_atlas_angles */
static const char *const angles_names[] = {"tangents", "jacobian"};

/* A bright colour per chart id (counter-based hash, so the picture is stable). */
static void chart_colour(uint32_t chart, float rgb[3]) {
    const uint64_t h = pgt_rng_u64(0x61746C73u, 0x636F6C72u, chart);
    for (int k = 0; k < 3; ++k)
        rgb[k] = 0.25f + 0.75f * (float)((h >> (16 * k)) & 0xFFFFu) / 65535.0f;
}

static pgt_result write_picture(const pgt_image *a, const char *path, pgt_error *err) {
    const uint32_t W = a->width, H = a->height;
    uint8_t *px = malloc((size_t)W * H * 3u);
    if (!px) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    const float *kind = pgt_image_plane(a, 7), *chart = pgt_image_plane(a, 6);
    const float *nx = pgt_image_plane(a, 3), *ny = pgt_image_plane(a, 4),
                *nz = pgt_image_plane(a, 5);
    /* a fixed light so the 3D shape reads in the picture */
    const float L[3] = {0.4f, 0.5f, 0.7663f};
    for (size_t i = 0; i < (size_t)W * H; ++i) {
        uint8_t *p = &px[3u * i];
        const int k = (int)kind[i];
        if (k == PGT_TEXEL_INDIRECTION) {
            p[0] = p[1] = p[2] = 255;
        } else if (k == PGT_TEXEL_DEAD_END) {
            p[0] = 255, p[1] = p[2] = 0;
        } else if (k == PGT_TEXEL_INNER) {
            float rgb[3];
            chart_colour((uint32_t)chart[i], rgb);
            const float d = fabsf(nx[i] * L[0] + ny[i] * L[1] + nz[i] * L[2]);
            for (int c = 0; c < 3; ++c)
                p[c] = (uint8_t)(255.0f * rgb[c] * (0.45f + 0.55f * d) + 0.5f);
        } else {
            p[0] = p[1] = p[2] = 0;
        }
    }
    pgt_result r = pgt_png_write(path, W, H, 3, px, err);
    free(px);
    return r;
}

int pgt_cmd_atlas(int argc, char **argv) {
    const char *verb = "atlas", *in_path = NULL, *out_path = NULL, *png_path = NULL;
    uint32_t res = PGT_ATLAS_DEFAULT_RES, band = PGT_ATLAS_MIN_BAND, k = PGT_ATLAS_DEFAULT_K;
    uint32_t threads = pgt_cli_cpu_count();
    float dead_end = PGT_ATLAS_DEFAULT_DEAD_END;
    int json = 0, repack = 0;
    pgt_atlas_angles angles = PGT_ATLAS_ANGLES_TANGENTS;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(atlas_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--png")) {
            if (!(png_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--res")) {
            /* the range --help gives (the builder checks it too, for its other callers) */
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, PGT_ATLAS_MIN_RES, PGT_ATLAS_MAX_SQUARE_RES, &res))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--band")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 0, PGT_ATLAS_MAX_BAND, &band))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--k")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, PGT_ATLAS_MAX_K, &k))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--angles")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            uint32_t n = 0;
            while (n < 2u && strcmp(v, angles_names[n])) n++;
            if (n == 2u) return pgt_cli_fail(verb, "--angles: '%s' is not tangents or jacobian", v);
            angles = (pgt_atlas_angles)n;
        } else if (!strcmp(a, "--dead-end")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            char *end = NULL;
            const double t = strtod(v, &end);
            if (end == v || *end != '\0' || !isfinite(t) || !(t > 0.0) ||
                t > PGT_ATLAS_MAX_DEAD_END)
                return pgt_cli_fail(verb,
                                    "--dead-end: '%s' is not a number of texel sizes in "
                                    "(0, %g]",
                                    v, (double)PGT_ATLAS_MAX_DEAD_END);
            dead_end = (float)t;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 256, &threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--json")) {
            json = 1;
        } else if (!strcmp(a, "--repack")) {
            repack = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt atlas --help)", a);
        } else if (!in_path) {
            in_path = a;
        } else {
            return pgt_cli_fail(verb, "unexpected argument '%s' (one input mesh only)", a);
        }
    }
    if (!in_path) return pgt_cli_fail(verb, "no input mesh (see pgt atlas --help)");
    if (!out_path) return pgt_cli_fail(verb, "no output: give -o ATLAS.exr");
    const size_t ol = strlen(out_path);
    if (ol < 4 || strcmp(out_path + ol - 4, ".exr"))
        return pgt_cli_fail(verb, "-o %s: the atlas is an OpenEXR file (.exr)", out_path);
    if (png_path) {
        const size_t pl = strlen(png_path);
        if (pl < 4 || strcmp(png_path + pl - 4, ".png"))
            return pgt_cli_fail(verb, "--png %s: the picture is a .png file", png_path);
    }
    {
        const char *outputs[2] = {out_path, png_path};
        if (pgt_cli_refuse_overwrite(verb, &in_path, 1, outputs, 2) ||
            pgt_cli_check_outputs(verb, outputs, 2))
            return PGT_EXIT_USAGE;
    }

    pgt_error err = {0};
    pgt_mesh mesh = {0};
    pgt_mesh_origin origin = {0}; /* where the file's records are, for the build's messages */
    pgt_image atlas = {0};
    int rc = PGT_EXIT_USAGE;
    pgt_cli_progress prog; /* a line every few seconds while the work runs (stderr) */
    if (pgt_cli_progress_start(&prog, verb)) return PGT_EXIT_USAGE;
    pgt_cli_progress_stagef(prog.progress, "reading %s", in_path);
    const double t0 = pgt_cli_now_ms();
    if (pgt_cli_load_atlas_mesh(verb, in_path, NULL, &mesh, &origin)) goto done;
    const double t1 = pgt_cli_now_ms();
    pgt_atlas_options opt = {0};
    opt.width = opt.height = res;
    opt.band = band;
    opt.k = k;
    opt.dead_end = dead_end;
    opt.threads = threads;
    opt.force_repack = repack;
    opt.angles = angles;
    opt.what = in_path;
    opt.origin = &origin;
    opt.progress = prog.progress; /* the build names its steps */
    pgt_atlas_stats st;
    if (pgt_atlas_build(&atlas, &mesh, &opt, &st, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    const double t2 = pgt_cli_now_ms();
    {
        /* both files under staging names first, renamed only when both are written: a failed
         * -o or --png leaves no new file behind (nor replaces an old one) */
        pgt_cli_progress_stagef(prog.progress, "writing %s", out_path);
        pgt_cli_stage stage;
        stage.count = stage.dir_count = 0;
        const char *exr_tmp = pgt_cli_stage_add(&stage, out_path);
        const char *png_tmp = png_path ? pgt_cli_stage_add(&stage, png_path) : NULL;
        if (pgt_image_write_exr_threads(&atlas, exr_tmp, threads, &err) != PGT_OK ||
            (png_path && write_picture(&atlas, png_tmp, &err) != PGT_OK)) {
            pgt_cli_fail(verb, "%s", err.message); /* while staged: names the user's paths */
            pgt_cli_stage_abort(&stage);
            goto done;
        }
        if (pgt_cli_stage_commit(&stage, verb)) goto done;
    }
    const double t3 = pgt_cli_now_ms();
    if (json) {
        printf("{\"verb\":\"atlas\",\"input\":");
        pgt_cli_json_string(stdout, in_path);
        printf(",\"output\":");
        pgt_cli_json_string(stdout, out_path);
        printf(",\"faces\":%u,\"resolution\":[%u,%u],\"band\":%u,\"k\":%u,\"dead_end\":%g,"
               "\"threads\":%u,\"charts\":%u,\"mirrored_charts\":%u,\"degenerate_faces\":%u,"
               "\"degenerate_charts\":%u,\"empty_charts\":%u,\"fold_over_texels\":%u,"
               "\"crack_texels\":%u,"
               "\"input_overlap_texels\":%u,\"layout\":\"%s\",\"packing_efficiency\":%.4f,"
               "\"inner_texels\":%u,\"inner_boundary_texels\":%u,\"indirection_texels\":%u,"
               "\"dead_end_texels\":%u,\"self_seam_pointers\":%u,\"own_chart_pointers\":%u,"
               "\"texel_size\":%.6g,\"angles\":\"%s\",\"fitted_angles\":%u,"
               "\"read_ms\":%.3f,\"charts_ms\":%.3f,\"layout_ms\":%.3f,\"raster_ms\":%.3f,"
               "\"pointers_ms\":%.3f,\"angles_ms\":%.3f,\"total_ms\":%.3f,\"write_ms\":%.3f}\n",
               st.faces, st.width, st.height, st.band, st.k, (double)dead_end, threads, st.charts,
               st.mirrored_charts, st.degenerate_faces, st.degenerate_charts, st.empty_charts,
               st.fold_over_texels, st.crack_texels, st.overlap_texels,
               st.repacked ? "repacked" : "kept", st.packing_efficiency, st.inner_texels,
               st.inner_boundary_texels, st.indirection_texels, st.dead_end_texels,
               st.self_seam_pointers, st.own_chart_pointers, st.texel_size, angles_names[angles],
               st.fitted_angles, t1 - t0, st.ms_charts, st.ms_layout, st.ms_raster, st.ms_pointers,
               st.ms_angles, st.ms_total, t3 - t2);
    } else {
        printf("atlas: %s (%u faces) -> %s (%ux%u, band %u, %u threads)\n", in_path, st.faces,
               out_path, st.width, st.height, st.band, threads);
        printf("  charts %u (mirrored %u flipped, %u degenerate UV triangles skipped, %u "
               "degenerate charts dropped, %u charts without texels)\n",
               st.charts, st.mirrored_charts, st.degenerate_faces, st.degenerate_charts,
               st.empty_charts);
        printf("  layout %s, packing efficiency %.1f%%", st.repacked ? "repacked" : "kept",
               100.0 * st.packing_efficiency);
        if (st.overlap_texels) printf(" (input charts overlapped on %u texels)", st.overlap_texels);
        if (st.fold_over_texels) printf(", %u fold-over texels", st.fold_over_texels);
        if (st.crack_texels)
            printf(", %u texels filled in the cracks of seams inside a chart", st.crack_texels);
        printf("\n  texels: %u inner (%u inner-boundary), %u indirection (%u into their own "
               "chart",
               st.inner_texels, st.inner_boundary_texels, st.indirection_texels,
               st.self_seam_pointers);
        if (st.own_chart_pointers)
            printf(", %u of them with nothing across", st.own_chart_pointers);
        printf("), %u dead end; texel size %.4g\n", st.dead_end_texels, st.texel_size);
        if (angles == PGT_ATLAS_ANGLES_JACOBIAN)
            printf("  angles fitted to the Jacobians at %u of %u indirection texels (5.2's "
                   "tangents at the others)\n",
                   st.fitted_angles, st.indirection_texels);
        printf("  ms: charts %.2f, layout %.2f, raster %.2f, pointers %.2f, angles %.2f, total "
               "%.2f (read %.2f, write %.2f)\n",
               st.ms_charts, st.ms_layout, st.ms_raster, st.ms_pointers, st.ms_angles, st.ms_total,
               t1 - t0, t3 - t2);
    }
    rc = PGT_EXIT_OK;
done:
    pgt_cli_progress_stop(&prog);
    pgt_image_destroy(&atlas);
    pgt_mesh_destroy(&mesh);
    pgt_mesh_origin_destroy(&origin);
    return rc;
}
