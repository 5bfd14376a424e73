/* pgt bench atlas: Table 1 of paper 000 (construction time of the indirection geometry image)
 * for our builder (ref_cpu/src/atlas_*.c), with the paper's three rows beside ours.
 *
 * Per mesh and thread count: one warm-up, R timed pgt_atlas_build calls (no file I/O), the
 * median of each stage and of the total (and the best total). The paper's rows are separate
 * rows with source=paper: only their polygon counts, resolution and total are known (Table 1:
 * Hebe 64K polygons 1 s, Ruins 164K 0.54 s, Shack 140K 0.73 s, all 1024^2). */
/* mallopt() is glibc's; declared under _DEFAULT_SOURCE. */
#define _DEFAULT_SOURCE
#include <errno.h>
#include <malloc.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "gen.h"
#include "pgt/atlas_build.h"
#include "pgt/mesh_io.h"

static const char *bench_atlas_usage =
    "usage: pgt bench atlas [--out FILE] [--repeat R] [--threads LIST] [--res N]\n"
    "                       [--meshes LIST] [--add LIST] [--shared DIR] [--quick]\n"
    "\n"
    "Times the atlas builder (charts, layout, raster, pointers, angles; no file I/O) and writes\n"
    "Table 1 of paper 000: one CSV row per mesh x thread count (source=ours) after the paper's\n"
    "three rows (source=paper), headed by machine, commit and date.\n"
    "\n"
    "  --out FILE      CSV to write (default results/table1.csv; temporary file + rename)\n"
    "  --repeat R      timed runs per row after one warm-up, 1 to 1000 (default 5)\n"
    "  --threads LIST  comma-separated thread counts (default 1,<CPUs>)\n"
    "  --res N         atlas side (default 1024, the paper's)\n"
    "  --meshes LIST   comma-separated names: a generated default dataset (pgt_datasets --list),\n"
    "                  cube_sphere_64 (generated, 49152 faces: the issue's 50k-face performance\n"
    "                  target), or a file name in the shared mesh folder (default: spot.obj,\n"
    "                  bob_tri.obj, human_neutral.obj, pizza.obj, ogre_bs_rest.obj,\n"
    "                  cube_sphere_8, cube_sphere_64); a name with a '/' is a file anywhere,\n"
    "                  shown in the CSV by its file name\n"
    "  --add LIST      more meshes after those (scripts/main.sh adds the MeshLab Voronoi\n"
    "                  atlases of mountain and nefertiti-lowres, *_voronoi.obj)\n"
    "  --shared DIR    shared mesh folder (default ../shared/datasets/meshes beside the repo)\n"
    "  --quick         small and fast: cube_sphere_8 and spot.obj (unless --meshes), R = 1\n"
    "                  (unless --repeat); needs --out (the default is the committed table)\n";

#define BENCH_ATLAS_MAX_LIST 32

static const char *const default_meshes[] = {
    "spot.obj",         "bob_tri.obj",   "human_neutral.obj", "pizza.obj",
    "ogre_bs_rest.obj", "cube_sphere_8", "cube_sphere_64"};

/* The paper's Table 1 (paper 000): name, polygons, seconds at 1024^2. */
static const struct {
    const char *name;
    uint32_t polygons;
    double seconds;
} paper_rows[] = {{"Hebe", 64000, 1.0}, {"Ruins", 164000, 0.54}, {"Shack", 140000, 0.73}};

static pgt_result load(const char *name, const char *shared, pgt_mesh *m, pgt_mesh_origin *origin,
                       pgt_error *err) {
    memset(origin, 0, sizeof *origin);
    if (!strcmp(name, "cube_sphere_64")) return pgt_gen_cube_sphere(m, 64, err);
    return pgt_cli_load_named_origin(name, shared, m, origin, err);
}

/* Median of column `field` (an offset into pgt_atlas_stats' doubles) over the runs. */
static double median_of(const pgt_atlas_stats *runs, uint32_t n, size_t offset, double *scratch) {
    for (uint32_t i = 0; i < n; ++i)
        memcpy(&scratch[i], (const char *)&runs[i] + offset, sizeof(double));
    return pgt_cli_median(scratch, n);
}

int pgt_cmd_bench_atlas(int argc, char **argv) {
    static const char *const default_out = "results/table1.csv";
    const char *out_path = default_out, *shared = PGT_CLI_SHARED_MESH_DIR;
    int quick = 0, have_repeat = 0;
    uint32_t repeat = 5, res = PGT_ATLAS_DEFAULT_RES, threads[BENCH_ATLAS_MAX_LIST], n_threads = 0;
    const char *meshes[BENCH_ATLAS_MAX_LIST];
    uint32_t n_meshes = 0;
    char mesh_buf[4096], add_buf[4096];
    const char *add = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(bench_atlas_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--out") || !strcmp(a, "-o")) {
            if (!(out_path = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--shared")) {
            if (!(shared = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--repeat")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 1, 1000, &repeat))
                return PGT_EXIT_USAGE;
            have_repeat = 1;
        } else if (!strcmp(a, "--quick")) {
            quick = 1;
        } else if (!strcmp(a, "--res")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, PGT_ATLAS_MIN_RES, PGT_ATLAS_MAX_SQUARE_RES, &res))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint_list("bench", a, v, 1, 256, threads, BENCH_ATLAS_MAX_LIST, &n_threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--meshes")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
            n_meshes = 0;
            if (pgt_cli_name_list("bench", a, v, mesh_buf, sizeof mesh_buf, meshes,
                                  BENCH_ATLAS_MAX_LIST, &n_meshes))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--add")) {
            if (!(add = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else {
            return pgt_cli_fail("bench", "unknown flag '%s' (see pgt bench atlas --help)", a);
        }
    }
    if (pgt_cli_quick_out("bench", quick, out_path, default_out)) return PGT_EXIT_USAGE;
    if (quick && !have_repeat) repeat = 1;
    if (!n_meshes && quick) /* the smoke run: a generated mesh and one with its own UVs */
        meshes[n_meshes++] = "cube_sphere_8", meshes[n_meshes++] = "spot.obj";
    if (!n_meshes)
        for (size_t i = 0; i < sizeof(default_meshes) / sizeof(default_meshes[0]); ++i)
            meshes[n_meshes++] = default_meshes[i];
    if (add && pgt_cli_name_list("bench", "--add", add, add_buf, sizeof add_buf, meshes,
                                 BENCH_ATLAS_MAX_LIST, &n_meshes))
        return PGT_EXIT_USAGE;
    if (pgt_cli_refuse_named_inputs("bench", meshes, n_meshes, shared, "--out", out_path))
        return PGT_EXIT_USAGE;
    if (!n_threads) {
        threads[n_threads++] = 1;
        if (pgt_cli_cpu_count() > 1) threads[n_threads++] = pgt_cli_cpu_count();
    }
    /* The allocator policy of pgt bench subdiv: freed memory stays in the heap, so repeated
     * runs time the builder rather than first-touch page faults of fresh mmapped blocks. */
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);

    char tmp_csv[4200];
    FILE *csv =
        pgt_cli_table_open(out_path,
                           "pgt bench atlas: Table 1 of paper 000, indirection geometry "
                           "image built from a mesh with UVs (pgt_atlas_build, no file I/O)",
                           tmp_csv, sizeof tmp_csv);
    if (!csv) return pgt_cli_fail("bench", "cannot write %s: %s", tmp_csv, strerror(errno));
    fprintf(csv,
            "# runs: 1 warm-up + %u timed per row; ms are medians per stage (best_total_ms: "
            "the fastest run)\n",
            repeat);
    fprintf(csv, "# stages: charts_ms (charts from UVs), layout_ms (keep test or repacking), "
                 "raster_ms, pointers_ms (classification, kd-tree, texel size, queries), "
                 "angles_ms (5.2 rotations); total_ms = the whole call\n");
    fprintf(csv, "# source=paper rows: Table 1 of paper 000 (only polygons, resolution and total "
                 "are given; the paper does not say its hardware here)\n");
    fprintf(csv,
            "# allocator: glibc with mmap off and trimming at 1 GiB, as in pgt bench subdiv\n");
    fprintf(csv, "source,mesh,polygons,charts,resolution,threads,charts_ms,layout_ms,raster_ms,"
                 "pointers_ms,angles_ms,total_ms,best_total_ms,repacked,packing_efficiency,"
                 "inner_texels,indirection_texels,dead_end_texels\n");
    for (size_t i = 0; i < sizeof(paper_rows) / sizeof(paper_rows[0]); ++i)
        fprintf(csv, "paper,%s,%u,,1024,,,,,,,%.0f,,,,,,\n", paper_rows[i].name,
                paper_rows[i].polygons, paper_rows[i].seconds * 1000.0);
    int failures = 0;
    pgt_atlas_stats *runs = malloc(sizeof(pgt_atlas_stats) * repeat);
    double *scratch = malloc(sizeof(double) * repeat);
    for (uint32_t mi = 0; mi < n_meshes && runs && scratch; ++mi) {
        pgt_mesh m = {0};
        pgt_mesh_origin origin; /* a vertex error names its line */
        pgt_error err = {0};
        if (load(meshes[mi], shared, &m, &origin, &err) != PGT_OK) {
            pgt_cli_skip_mesh("bench atlas", meshes[mi], err.message);
            failures++;
            continue;
        }
        for (uint32_t ti = 0; ti < n_threads; ++ti) {
            pgt_atlas_options o = {0};
            o.width = o.height = res;
            o.threads = threads[ti];
            o.what = meshes[mi];
            o.origin = &origin;
            pgt_image img = {0};
            pgt_atlas_stats st;
            int ok = 1;
            for (uint32_t r = 0; r <= repeat && ok; ++r) {
                pgt_error_clear(&err);
                if (pgt_atlas_build(&img, &m, &o, &st, &err) != PGT_OK) {
                    pgt_cli_skip_mesh("bench atlas", meshes[mi], err.message);
                    failures++;
                    ok = 0;
                    break;
                }
                pgt_image_destroy(&img);
                if (r > 0) runs[r - 1u] = st; /* run 0 is the warm-up */
            }
            if (!ok) break;
            double total[1000];
            for (uint32_t r = 0; r < repeat; ++r) total[r] = runs[r].ms_total;
            const double med_total = pgt_cli_median(total, repeat);
            fputs("ours,", csv);
            pgt_cli_csv_field(csv, pgt_cli_mesh_label(meshes[mi]));
            fprintf(csv, ",%u,%u,%u,%u,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%.4f,%u,%u,%u\n",
                    m.face_count, st.charts, res, threads[ti],
                    median_of(runs, repeat, offsetof(pgt_atlas_stats, ms_charts), scratch),
                    median_of(runs, repeat, offsetof(pgt_atlas_stats, ms_layout), scratch),
                    median_of(runs, repeat, offsetof(pgt_atlas_stats, ms_raster), scratch),
                    median_of(runs, repeat, offsetof(pgt_atlas_stats, ms_pointers), scratch),
                    median_of(runs, repeat, offsetof(pgt_atlas_stats, ms_angles), scratch),
                    med_total, pgt_cli_min(total, repeat), st.repacked, st.packing_efficiency,
                    st.inner_texels, st.indirection_texels, st.dead_end_texels);
            fflush(csv);
            fprintf(stderr,
                    "pgt bench atlas: %s (%u faces, %u charts) %ux%u, %u threads: %.1f ms\n",
                    pgt_cli_mesh_label(meshes[mi]), m.face_count, st.charts, res, res, threads[ti],
                    med_total);
        }
        pgt_mesh_destroy(&m);
        pgt_mesh_origin_destroy(&origin);
    }
    free(runs);
    free(scratch);
    if (pgt_cli_bench_close(csv, tmp_csv, out_path, "bench", failures)) return PGT_EXIT_USAGE;
    if (!failures)
        fprintf(stderr, "pgt bench atlas: wrote %s (%u mesh%s x %u thread count%s)\n", out_path,
                n_meshes, n_meshes == 1 ? "" : "es", n_threads, n_threads == 1 ? "" : "s");
    return failures ? PGT_EXIT_USAGE : PGT_EXIT_OK; /* errors while working (cli.h) */
}
