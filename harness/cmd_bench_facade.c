/* pgt bench facade: per-pixel procedural facades against Embree on their explicit twin (paper
 * 003 sec. 9; issue 6): cities of ~100, ~1000 and ~10000 facades at 512x512 and 1280x720, the
 * same rays on the same threads, time, memory and agreement per row, with the paper's row. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "facade_embree.h"
#include "facade_scene.h"
#include "pgt/facade.h"
#include "pgt/parallel.h"

#define BENCH_FACADE_DEFAULT_GRAMMAR PGT_SOURCE_DIR "/grammars/facade.grammar"
#define BENCH_FACADE_MAX_LIST 16u
#define BENCH_FACADE_MAX_FRAMES 1000u

/* Paper 003 sec. 9: 10K facades at 1280x720, 7 fps (143 ms) on a GeForce GTX 480, ~650 KB of
 * grammar parameters and footprints against ~400 MB for the explicit geometry. */
#define PAPER_FACADES 10000u
#define PAPER_MS 143.0
#define PAPER_PROCEDURAL_BYTES 650000.0
#define PAPER_EXPLICIT_BYTES 400000000.0

static const char *bench_facade_usage =
    "usage: pgt bench facade [--out FILE] [--buildings LIST] [--res LIST] [--threads N]\n"
    "                        [--frames F] [--grammar FILE] [--seed S] [--quick]\n"
    "\n"
    "Renders generated cities (pgt facade --city) from the default aerial camera and traces\n"
    "exactly the same rays with Embree on the explicit twin (pgt facade --embree-check), on\n"
    "the same threads. Per city x resolution: one warm-up, then F timed rounds, each: ours\n"
    "shaded (coverage + rays + shading), ours hits only (the same rays and development, no\n"
    "shading: what a ray caster returns), Embree in packet and in stream mode (rays + stored\n"
    "hits; its BVH build is a column apart); medians, Mrays/s, ours / Embree (hits only, the\n"
    "same work; and shaded), bytes of both, agreement. A progress line per row; rows of the\n"
    "paper's city (10K facades, 1280x720, GTX 480) as source=paper.\n"
    "\n"
    "  --out FILE       CSV to write (default results/facade.csv; temporary file + rename)\n"
    "  --buildings LIST comma-separated building counts (default 25,250,2500: ~100, ~1000 and\n"
    "                   ~10000 facades)\n"
    "  --res LIST       comma-separated WxH (default 512x512,1280x720)\n"
    "  --threads N      threads of both (default 2)\n"
    "  --frames F       timed frames per measurement, 1 to 1000 (default 9)\n"
    "  --grammar FILE   the city's grammar (default grammars/facade.grammar)\n"
    "  --seed S         the city's seed (default 1)\n"
    "  --quick          buildings 25,250 and 2 frames (a smoke run)\n";

static int parse_res(const char *text, uint32_t *w, uint32_t *h, uint32_t *n) {
    char buf[512];
    const char *items[BENCH_FACADE_MAX_LIST];
    uint32_t count = 0;
    if (pgt_cli_name_list("bench", "--res", text, buf, sizeof buf, items, BENCH_FACADE_MAX_LIST,
                          &count))
        return -1;
    for (*n = 0; *n < count; ++*n) {
        char *x = strchr(items[*n], 'x');
        if (!x) goto bad;
        *x = '\0'; /* items point into buf */
        if (pgt_cli_uint("bench", "--res", items[*n], 1, 16384, &w[*n]) ||
            pgt_cli_uint("bench", "--res", x + 1, 1, 16384, &h[*n]))
            return -1;
    }
    return 0;
bad:
    pgt_cli_fail("bench", "--res: expected WxH[,WxH...], got '%s'", text);
    return -1;
}

int pgt_cmd_bench_facade(int argc, char **argv) {
    static const char *const default_out = "results/facade.csv";
    const char *verb = "bench", *out_path = default_out, *grammar = NULL, *v;
    uint32_t buildings[BENCH_FACADE_MAX_LIST] = {25, 250, 2500}, nb = 3;
    uint32_t rw[BENCH_FACADE_MAX_LIST] = {512, 1280}, rh[BENCH_FACADE_MAX_LIST] = {512, 720};
    uint32_t nr = 2, threads = 2, frames = 9, seed = 1;
    int quick = 0, have_frames = 0, have_buildings = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(bench_facade_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--out") || !strcmp(a, "-o")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--buildings")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint_list(verb, a, v, 1, 1u << 22, buildings, BENCH_FACADE_MAX_LIST, &nb))
                return PGT_EXIT_USAGE;
            have_buildings = 1;
        } else if (!strcmp(a, "--res")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) || parse_res(v, rw, rh, &nr))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, PGT_MAX_THREADS, &threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--frames") || !strcmp(a, "--repeat")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, BENCH_FACADE_MAX_FRAMES, &frames))
                return PGT_EXIT_USAGE;
            have_frames = 1;
        } else if (!strcmp(a, "--grammar")) {
            if (!(grammar = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--seed")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 0, UINT32_MAX, &seed))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--quick")) {
            quick = 1;
        } else {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt bench facade --help)", a);
        }
    }
    if (quick && !have_frames) frames = 2;
    if (quick && !have_buildings) nb = 2;
    /* the CSV names the default grammar by its place in the repository, not by this
     * checkout's absolute path: the tables are compared across machines */
    const char *grammar_name = grammar ? grammar : "grammars/facade.grammar";
    if (!grammar) grammar = BENCH_FACADE_DEFAULT_GRAMMAR;
    if (pgt_cli_refuse_overwrite(verb, &grammar, 1, &out_path, 1) ||
        pgt_cli_memory_env_check(verb) || pgt_cli_quick_out(verb, quick, out_path, default_out))
        return PGT_EXIT_USAGE;
    double *ms = malloc(6u * frames * sizeof(double));
    if (!ms) return pgt_cli_fail(verb, "out of memory");
    char tmp[4200];
    FILE *csv = pgt_cli_table_open(out_path,
                                   "pgt bench facade: per-pixel procedural facades (paper 003) "
                                   "against Embree on the explicit geometry, same rays",
                                   tmp, sizeof tmp);
    if (!csv) {
        free(ms);
        return pgt_cli_fail(verb, "cannot write %s: %s", tmp, strerror(errno));
    }
    fprintf(csv,
            "# runs: per row 1 warm-up + %u timed frames of each, medians (ms_min: fastest "
            "of ours); cities pgt_gen_city(N, seed %u) with ",
            frames, seed);
    pgt_cli_comment_text(csv, grammar_name); /* a line end in it would end the comment */
    fprintf(csv, "; default aerial camera (pgt facade --help); %u threads for both\n", threads);
    fprintf(csv, "# ours: pgt_facade_render (coverage polygons, ray development, shading; "
                 "ms_cover apart): ms, ours_mrays; the same without shading (hits_only: depth, "
                 "ids and normal per pixel, what Embree's rays return): trace_ms, "
                 "ours_trace_mrays; Embree 3: BVH of the explicit twin (pgt_facade_explicit, "
                 "build quality high) built once per city (embree_build_ms), rays of "
                 "pgt_facade_camera_ray as rtcIntersect16 4x4 packets and rtcIntersect1M "
                 "coherent streams, hits stored per pixel; embree_mrays = the faster mode's; "
                 "ours_over_embree = ours_trace_mrays / embree_mrays (the same work), "
                 "shaded_over_embree = ours_mrays / embree_mrays, best_over_embree = the fastest "
                 "hits-only frame against the fastest frame of Embree's faster mode (the least "
                 "disturbed of each on a shared machine); single_trace_ms: the hits-only frame "
                 "with every ray developed alone (pgt_facade_shading.single_rays, pgt facade "
                 "--single-rays; the same frame), packet_speedup = single_trace_ms / trace_ms; "
                 "the five are timed in turn frame after frame, so load on the shared machine "
                 "falls on all alike\n");
    fprintf(csv, "# bytes: procedural = pgt_facade_scene_bytes (buildings, footprints, params, "
                 "grammars; facades_bytes = the derived facade array, apart); explicit = the "
                 "twin's arrays (positions, indices, per-triangle ids); embree = its reported "
                 "peak + vertex and index buffers; memory_ratio = embree / procedural\n");
    fprintf(csv, "# agreement: Embree's rays traced once more without the coherent flag "
                 "(harness/facade_embree.h), per pixel both miss or same (facade, node, kind, "
                 "surface) within 1e-4 relative depth or 4 float epsilons of the coordinates "
                 "along the surface's normal; ties: disagreements where both hit at that depth on "
                 "coincident faces (harness/facade_embree.h); near_edge: the others within "
                 "1e-4 t of a rectangle edge, or of an edge between two of its triangles when "
                 "Embree's ray went on past it (cracks: those, Embree not being watertight)\n");
    fprintf(csv, "# source=paper: paper 003 sec. 9, 10K facades at 1280x720, 7 fps on a GeForce "
                 "GTX 480, ~650 KB vs ~400 MB (its explicit bytes include normals and texture "
                 "coordinates)\n");
    fprintf(csv,
            "source,buildings,facades,width,height,threads,frames,ms,ms_min,ms_cover,"
            "ours_mrays,embree_mrays,embree_mode,embree_packets_mrays,embree_streams_mrays,"
            "ours_over_embree,embree_build_ms,procedural_bytes,facades_bytes,"
            "explicit_triangles,explicit_bytes,embree_bytes,memory_ratio,agreement_pct,"
            "disagreements,near_edge,nodes_per_ray,trace_ms,ours_trace_mrays,"
            "shaded_over_embree,best_over_embree,single_trace_ms,packet_speedup,ties,cracks\n");
    fprintf(csv, "paper,,%u,1280,720,,,%.0f,,,%.2f,,,,,,,%.0f,,,%.0f,,%.0f,,,,,,,,,,,,\n",
            PAPER_FACADES, PAPER_MS, 1280.0 * 720.0 / (PAPER_MS * 1e3), PAPER_PROCEDURAL_BYTES,
            PAPER_EXPLICIT_BYTES, PAPER_EXPLICIT_BYTES / PAPER_PROCEDURAL_BYTES);
    int failures = 0;
    /* the twin and Embree's scene of it within the memory available (a city too large for this
     * machine fails with this error, not by exhausting the memory) */
    uint64_t avail = 0;
    const uint32_t max_t = pgt_facade_twin_max_triangles(1, &avail);
    for (uint32_t c = 0; c < nb; ++c) {
        pgt_error err = {0};
        pgt_facade_file file;
        pgt_facade *facades = NULL;
        uint32_t fc = 0;
        pgt_facade_mesh mesh;
        memset(&mesh, 0, sizeof mesh);
        pgt_facade_embree eb;
        memset(&eb, 0, sizeof eb);
        if (pgt_facade_file_city(&file, grammar, buildings[c], seed, &err) != PGT_OK ||
            pgt_facade_prepare(&file.scene, &facades, &fc, &err) != PGT_OK ||
            pgt_facade_explicit_limit(&file.scene, facades, fc, max_t, &mesh, &err) != PGT_OK ||
            pgt_facade_embree_create(&eb, &mesh, threads, NULL, &err) != PGT_OK) {
            char why[200] = "";
            if (err.code == PGT_ERROR_LIMIT) pgt_facade_twin_limit_why(why, sizeof why, avail, 1);
            pgt_cli_fail(verb, "facade: city of %u buildings: %s%s", buildings[c], err.message,
                         why);
            failures++;
            goto next_city;
        }
        const pgt_facade_scene *s = &file.scene;
        const size_t proc = pgt_facade_scene_bytes(s), ebytes = eb.embree_bytes + eb.buffer_bytes;
        for (uint32_t r = 0; r < nr; ++r) {
            pgt_facade_frame frame;
            memset(&frame, 0, sizeof frame);
            pgt_facade_embree_hits hits;
            memset(&hits, 0, sizeof hits);
            float eye[3], at[3], up[3], fov;
            pgt_facade_default_view(s, rw[r], rh[r], eye, at, up, &fov);
            pgt_facade_camera cam;
            pgt_facade_shading sh;
            memset(&sh, 0, sizeof sh);
            pgt_facade_default_light(s, sh.light);
            sh.ambient = PGT_FACADE_DEFAULT_AMBIENT;
            pgt_facade_render_stats st;
            if (pgt_facade_camera_init(&cam, eye, at, up, fov, rw[r], rh[r], &err) != PGT_OK ||
                pgt_facade_frame_create(&frame, rw[r], rh[r], &err) != PGT_OK ||
                pgt_facade_embree_hits_create(&hits, rw[r], rh[r], &err) != PGT_OK) {
                pgt_cli_fail(verb, "facade: %s", err.message);
                failures++;
                goto next_res;
            }
            /* per frame in turn: ours hits only with single rays, ours hits only, ours shaded,
             * Embree packets, Embree streams (the first round a warm-up) */
            double *cover = ms + frames, *trace = ms + 2u * frames, *single = ms + 5u * frames;
            double *theirs[2] = {ms + 3u * frames, ms + 4u * frames};
            pgt_facade_shading bare = sh, alone = sh;
            bare.hits_only = 1;
            alone.hits_only = 1, alone.single_rays = 1;
            pgt_facade_render_stats bst;
            int bad = 0;
            for (uint32_t f = 0; f <= frames && !bad; ++f) {
                bad = pgt_facade_render(s, facades, fc, &cam, &alone, threads, &frame, &bst,
                                        &err) != PGT_OK;
                if (!bad && f) single[f - 1] = bst.ms_total;
                bad = bad || pgt_facade_render(s, facades, fc, &cam, &bare, threads, &frame, &bst,
                                               &err) != PGT_OK;
                if (!bad && f) trace[f - 1] = bst.ms_total;
                bad = bad || pgt_facade_render(s, facades, fc, &cam, &sh, threads, &frame, &st,
                                               &err) != PGT_OK;
                if (!bad && f) ms[f - 1] = st.ms_total, cover[f - 1] = st.ms_cover;
                for (uint32_t m = 0; m < 2 && !bad; ++m)
                    bad = pgt_facade_embree_trace(&eb, &cam, (pgt_facade_embree_mode)m, &hits,
                                                  &theirs[m][f ? f - 1 : 0], &err) != PGT_OK;
            }
            /* the agreement of the rays without the coherent flag (facade_embree.h) */
            bad = bad || pgt_facade_embree_trace(&eb, &cam, PGT_FACADE_EMBREE_CHECK_RAYS, &hits,
                                                 NULL, &err) != PGT_OK;
            const double mode_med[2] = {bad ? 0.0 : pgt_cli_median(theirs[0], frames),
                                        bad ? 0.0 : pgt_cli_median(theirs[1], frames)};
            if (bad || st.rays.errors) {
                pgt_cli_fail(verb, "facade: %s", bad ? err.message : "the grammar failed");
                failures++;
                goto next_res;
            }
            pgt_facade_check chk;
            pgt_facade_embree_compare(&mesh, &cam, &frame, &hits, &chk);
            const double pixels = (double)rw[r] * rh[r];
            const double med = pgt_cli_median(ms, frames), best = pgt_cli_min(ms, frames);
            const uint32_t fast = mode_med[1] < mode_med[0] ? 1u : 0u;
            const double ours_mr = pixels / (med * 1e3), emb_mr = pixels / (mode_med[fast] * 1e3);
            const double trace_med = pgt_cli_median(trace, frames);
            const double trace_mr = pixels / (trace_med * 1e3);
            const double best_ratio =
                pgt_cli_min(theirs[fast], frames) / pgt_cli_min(trace, frames);
            const double single_med = pgt_cli_median(single, frames);
            fprintf(
                csv,
                "ours,%u,%u,%u,%u,%u,%u,%.3f,%.3f,%.3f,%.3f,%.3f,%s,%.3f,%.3f,%.3f,%.0f,%zu,"
                "%zu,%u,%zu,%zu,%.0f,%.4f,%llu,%llu,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%llu,%llu\n",
                buildings[c], fc, rw[r], rh[r], threads, frames, med, best,
                pgt_cli_median(cover, frames), ours_mr, emb_mr, fast ? "streams" : "packets",
                pixels / (mode_med[0] * 1e3), pixels / (mode_med[1] * 1e3), trace_mr / emb_mr,
                eb.build_ms, proc, (size_t)fc * sizeof(pgt_facade), mesh.triangle_count,
                pgt_facade_mesh_bytes(&mesh), ebytes, (double)ebytes / (double)proc,
                chk.agreement_pct, (unsigned long long)chk.disagree,
                (unsigned long long)chk.near_edge,
                st.rays.volume_hits ? (double)st.rays.nodes / (double)st.rays.volume_hits : 0.0,
                trace_med, trace_mr, ours_mr / emb_mr, best_ratio, single_med,
                single_med / trace_med, (unsigned long long)chk.ties,
                (unsigned long long)chk.crack);
            fflush(csv);
            fprintf(stderr,
                    "pgt bench facade: %u facades, %ux%u, %u threads: ours %.1f ms shaded "
                    "(%.2f Mrays/s), %.1f ms hits only (%.2f Mrays/s); Embree %.2f Mrays/s (%s; "
                    "BVH %.0f ms); ours / Embree %.2fx (shaded %.2fx, fastest frames %.2fx); "
                    "packets %.2fx single rays; %zu vs %zu bytes (%.0fx); agreement %.4f %%\n",
                    fc, rw[r], rh[r], threads, med, ours_mr, trace_med, trace_mr, emb_mr,
                    fast ? "streams" : "packets", eb.build_ms, trace_mr / emb_mr, ours_mr / emb_mr,
                    best_ratio, single_med / trace_med, proc, ebytes, (double)ebytes / (double)proc,
                    chk.agreement_pct);
        next_res:
            pgt_facade_embree_hits_destroy(&hits);
            pgt_facade_frame_destroy(&frame);
        }
    next_city:
        pgt_facade_embree_destroy(&eb);
        pgt_facade_mesh_destroy(&mesh);
        free(facades);
        pgt_facade_file_free(&file);
    }
    free(ms);
    if (pgt_cli_bench_close(csv, tmp, out_path, verb, failures)) failures++;
    if (!failures) fprintf(stderr, "pgt bench facade: wrote %s\n", out_path);
    return failures ? PGT_EXIT_USAGE : PGT_EXIT_OK; /* errors while working (cli.h) */
}
