/* pgt bench ivy: Table 2 and Figure 11 of paper 000 (ivy generation time), on the real meshes
 * of ../shared/datasets/meshes with their atlases. */
/* mallopt() is glibc's; declared under _DEFAULT_SOURCE. */
#define _DEFAULT_SOURCE
#include <errno.h>
#include <malloc.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "ivy_scene.h"
#include "pgt/ivy.h"

/* Most timed runs per row. */
#define BENCH_IVY_MAX_REPEAT 1000u

/* Bark radius and leaf size in median texel sizes of the scene's atlas: the ivy keeps the same
 * look on meshes of any scale (spot is 1 unit tall, human 1.7). The bark is thinner than the
 * 4-texel step, a leaf a little larger, like the paper's figures. */
#define BENCH_IVY_BARK_TEXELS 0.6
#define BENCH_IVY_LEAF_TEXELS 5.0

/* Table 2 within this relative distance of the paper's polygon counts (the issue: 10 %). */
#define BENCH_IVY_POLYGON_TOLERANCE 0.10

/* Figure 11: seeds 1 .. this. */
#define BENCH_IVY_FIG11_SEEDS 64u
/* ... with a progress line every this many seed counts (and at the last). */
#define BENCH_IVY_PROGRESS_EVERY 16u

/* A scene of Table 2. Lengths (maxMainSteps, the guide strokes' steps) were chosen so that the
 * polygon counts land near the paper's; the CSV reports how near. They follow the atlases: when
 * the crack fill (session 24) changed human_neutral's, fig1b's strokes and ivy changed with it
 * and 270 steps gave 8.21M polygons instead of 8.90M; 290 gives 8.79M. */
typedef struct ivy_bench_scene {
    const char *name, *figure, *mesh;
    uint32_t seeds;
    int painted;           /* painted guidance: strokes, seeds at their starts */
    uint32_t stroke_steps; /* guide walker steps per stroke */
    const char *params;    /* grammar overrides, comma-separated NAME=VALUE */
    double paper_polygons, paper_ms;
} ivy_bench_scene;

static const ivy_bench_scene scenes[] = {
    {"fig1b", "Fig. 1b (shack; painted guidance)", "human_neutral.obj", 18, 1, 600,
     "maxMainSteps=290", 8.84e6, 336.0},
    {"fig10c", "Fig. 10c (painted guidance)", "spot.obj", 10, 1, 280, "maxMainSteps=130", 2.5e6,
     257.0},
    {"fig1a", "Fig. 1a (ruins; recursive branching)", "bob_tri.obj", 25, 0, 0, "maxMainSteps=92",
     4.48e6, 136.0},
};

/* The scene of Figure 11 (both scenarios) and its strokes. */
#define BENCH_IVY_FIG11_MESH "spot.obj"
#define BENCH_IVY_FIG11_STEPS 500u
#define BENCH_IVY_FIG11_PARAMS "maxMainSteps=250"

static const char *bench_ivy_usage =
    "usage: pgt bench ivy [--out FILE] [--fig11 FILE] [--repeat R] [--threads N] [--quick]\n"
    "                     [--save-scenes DIR] [--seed S]\n"
    "\n"
    "Times ivy generation (pgt_ivy_generate: expand, G1 Bezier, terminals, output in memory;\n"
    "no file I/O) like paper 000's Table 2 and Figure 11, on the shared meshes' atlases\n"
    "(1024^2, built once per scene, not timed).\n"
    "\n"
    "  --out FILE      Table 2 CSV (default results/table2.csv; temporary file + rename):\n"
    "                  fig1b (human_neutral, 18 seeds, painted guidance; paper 8.84M polygons,\n"
    "                  336 ms), fig10c (spot, 10 seeds, painted; 2.5M, 257 ms), fig1a (bob, 25\n"
    "                  seeds, recursive branching without control; 4.48M, 136 ms); the paper\n"
    "                  names its GPU (a GTX 480) for Fig. 11 only\n"
    "  --fig11 FILE    Figure 11 CSV (default results/fig11.csv): time vs seeds 1..64 on spot\n"
    "                  with painted strokes, scenario main (main branch only, no leaves) and\n"
    "                  full (secondary branches and leaves)\n"
    "  --repeat R      timed runs per row after one warm-up, 1 to 1000 (default 5)\n"
    "  --threads N     threads (default: the number of CPUs)\n"
    "  --quick         1 timed run, Figure 11 at 1, 2, 4, ..., 64 seeds only\n"
    "  --save-scenes DIR  also write each scene's strokes (DIR/NAME.strokes) and seeds\n"
    "                  (DIR/NAME.seeds) and the pgt ivy command that grows it\n"
    "                  (DIR/NAME.cmd, without -o: add -o IVY.ply to run it; its file paths\n"
    "                  are as DIR was given), for figures and re-derivation\n"
    "  --seed S        seed of the strokes and random seeds (default 1)\n"
    "\n"
    "Runs reuse the previous run's mesh buffers (pgt_ivy_options.reuse), as an interactive\n"
    "session does; the allocator keeps freed memory (mmap off), as pgt bench atlas does.\n";

/* Up to BENCH_IVY_MAX_PARAMS overrides from a comma list into params (pointers into buf). */
#define BENCH_IVY_MAX_PARAMS 16
static uint32_t split_params(const char *list, char *buf, size_t size, const char **params) {
    snprintf(buf, size, "%s", list);
    uint32_t n = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok && n < BENCH_IVY_MAX_PARAMS;
         tok = strtok_r(NULL, ",", &save))
        params[n++] = tok;
    return n;
}

/* Medians of `repeat` timed runs after one warm-up. */
typedef struct ivy_timing {
    double expand, bezier, terminals, total, best;
    double cold; /* the warm-up run: fresh buffers, first-touch page faults included */
} ivy_timing;

static int time_runs(pgt_ivy_output *out, const pgt_expand_input *in, const pgt_ivy_options *o,
                     uint32_t repeat, ivy_timing *t) {
    double e[BENCH_IVY_MAX_REPEAT], b[BENCH_IVY_MAX_REPEAT], m[BENCH_IVY_MAX_REPEAT],
        tot[BENCH_IVY_MAX_REPEAT];
    pgt_error err = {0};
    for (uint32_t r = 0; r <= repeat; ++r) {
        if (pgt_ivy_generate(out, in, o, &err) != PGT_OK)
            return pgt_cli_fail("bench", "ivy: %s", err.message);
        if (r == 0) { /* warm-up */
            t->cold = out->ms_expand + out->ms_bezier + out->ms_terminals;
            continue;
        }
        e[r - 1u] = out->ms_expand, b[r - 1u] = out->ms_bezier, m[r - 1u] = out->ms_terminals;
        tot[r - 1u] = out->ms_expand + out->ms_bezier + out->ms_terminals;
    }
    t->expand = pgt_cli_median(e, repeat), t->bezier = pgt_cli_median(b, repeat);
    t->terminals = pgt_cli_median(m, repeat), t->total = pgt_cli_median(tot, repeat);
    t->best = pgt_cli_min(tot, repeat);
    return 0;
}

/* Sets up a scene: atlas, grammar with overrides (plus bark and leaf sizes in texels), and
 * either painted strokes (count strokes, the first `seeds` painted, seeds at their starts) or
 * random seeds. */
static int scene_setup(pgt_ivy_scene *s, const char *mesh, const char *param_list, int painted,
                       uint32_t strokes, uint32_t steps, uint32_t seeds, uint32_t seed,
                       uint32_t threads, const char *save_dir, const char *name) {
    if (pgt_ivy_scene_atlas(s, "bench", mesh, 1024, threads)) return -1;
    char buf[1024], bark[64], leaf[64];
    const char *params[BENCH_IVY_MAX_PARAMS + 2];
    uint32_t n = split_params(param_list, buf, sizeof buf, params);
    snprintf(bark, sizeof bark, "barkRadius=%.6g", BENCH_IVY_BARK_TEXELS * s->texel_size);
    snprintf(leaf, sizeof leaf, "leafSize=%.6g", BENCH_IVY_LEAF_TEXELS * s->texel_size);
    params[n++] = bark, params[n++] = leaf;
    if (pgt_ivy_scene_grammar(s, "bench", PGT_IVY_DEFAULT_GRAMMAR, params, n)) return -1;
    if (!(s->seeds = malloc(sizeof(pgt_expand_seed) * (strokes > seeds ? strokes : seeds))))
        return pgt_cli_fail("bench", "out of memory");
    s->seed_count = seeds;
    pgt_error err = {0};
    float *points = NULL;
    uint32_t *first = NULL, point_count = 0;
    if (!painted) {
        if (pgt_ivy_random_seeds(s->seeds, seeds, &s->atlas, s->mask, seed, &err) != PGT_OK)
            return pgt_cli_fail("bench", "%s", err.message);
    } else {
        if (pgt_ivy_guide_strokes(&s->atlas, "bench", strokes, steps, seed, &points, &point_count,
                                  &first, s->seeds))
            return -1;
        const float brush = (float)(PGT_IVY_DEFAULT_BRUSH_TEXELS * s->texel_size);
        if (pgt_ivy_scene_paint(s, "bench", points, first[seeds], first, seeds, brush, threads, 0,
                                NULL)) {
            free(points), free(first);
            return -1;
        }
    }
    int rc = 0;
    if (save_dir) {
        char path[4096], tmp[4200];
        mkdir(save_dir, 0777);
        if (painted) {
            snprintf(path, sizeof path, "%s/%s.strokes", save_dir, name);
            rc |= pgt_ivy_write_strokes("bench", path, points, first, seeds);
        }
        snprintf(path, sizeof path, "%s/%s.seeds", save_dir, name);
        FILE *f = pgt_cli_tmp_open(path, tmp, sizeof tmp);
        if (!f) {
            rc = pgt_cli_fail("bench", "cannot write %s: %s", tmp, strerror(errno));
        } else {
            fprintf(f, "# seeds of %s (pgt ivy --seed-file): texel U V DU DV\n", name);
            for (uint32_t i = 0; i < seeds; ++i)
                fprintf(f, "texel %.9g %.9g %.9g %.9g\n", (double)s->seeds[i].x,
                        (double)s->seeds[i].y, (double)s->seeds[i].dx, (double)s->seeds[i].dy);
            rc |= pgt_cli_table_close(f, tmp, path, "bench");
        }
        snprintf(path, sizeof path, "%s/%s.cmd", save_dir, name);
        if (!rc && (f = pgt_cli_tmp_open(path, tmp, sizeof tmp))) {
            fprintf(f, "pgt ivy %s --seeds %u --seed-file %s/%s.seeds --seed %u", mesh, seeds,
                    save_dir, name, seed);
            if (painted) fprintf(f, " --paint %s/%s.strokes", save_dir, name);
            for (uint32_t k = 0; k < n; ++k) fprintf(f, " --param %s", params[k]);
            fprintf(f, "\n");
            rc |= pgt_cli_table_close(f, tmp, path, "bench");
        }
    }
    free(points), free(first);
    return rc;
}

int pgt_cmd_bench_ivy(int argc, char **argv) {
    static const char *const default_out = "results/table2.csv", *const default_fig11 =
                                                                     "results/fig11.csv";
    const char *out_path = default_out, *fig11_path = default_fig11;
    const char *save_dir = NULL;
    uint32_t repeat = 5, threads = pgt_cli_cpu_count(), seed = 1;
    int quick = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(bench_ivy_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--out") || !strcmp(a, "-o")) {
            if (!(out_path = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--fig11")) {
            if (!(fig11_path = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--save-scenes")) {
            if (!(save_dir = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--repeat")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 1, BENCH_IVY_MAX_REPEAT, &repeat))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 1, 256, &threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--seed")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 0, UINT32_MAX, &seed))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--quick")) {
            quick = 1;
        } else {
            return pgt_cli_fail("bench", "unknown flag '%s' (see pgt bench ivy --help)", a);
        }
    }
    const char *const outs[2] = {out_path, fig11_path},
                      *const defs[2] = {default_out, default_fig11},
                      *const flags[2] = {"--out", "--fig11"};
    if (pgt_cli_quick_outs("bench", quick, outs, defs, flags, 2)) return PGT_EXIT_USAGE;
    if (quick) repeat = 1;
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);

    char tmp[4200];
    FILE *csv = pgt_cli_table_open(out_path,
                                   "pgt bench ivy: Table 2 of paper 000, ivy generation time "
                                   "(pgt_ivy_generate: expand + Bezier + terminals, in memory)",
                                   tmp, sizeof tmp);
    if (!csv) return pgt_cli_fail("bench", "cannot write %s: %s", tmp, strerror(errno));
    fprintf(csv,
            "# runs: 1 warm-up + %u timed per row, medians (best_ms: the fastest run); %u "
            "threads; atlases 1024^2 built once per scene (not timed)\n",
            repeat, threads);
    fprintf(csv, "# cold_ms: the warm-up run (fresh buffers: first-touch page faults of the output "
                 "included); the timed runs reuse its buffers\n");
    fprintf(csv, "# polygons = bark quads (216 per segment) + leaves; paper_ms: the paper's GPU "
                 "(it names a GTX 480 for Fig. 11, none for Table 2); "
                 "speedup = paper_ms / total_ms; polygons_ratio = polygons / paper_polygons\n");
    fprintf(csv,
            "# bark radius %.2f and leaf size %.2f median texel sizes; strokes: "
            "pgt_ivy_guide_strokes (harness/ivy_scene.h), brush %.0f texel sizes\n",
            BENCH_IVY_BARK_TEXELS, BENCH_IVY_LEAF_TEXELS, PGT_IVY_DEFAULT_BRUSH_TEXELS);
    fprintf(csv, "scene,figure,mesh,seeds,guidance,params,points,segments,polygons,"
                 "paper_polygons,polygons_ratio,within_10pct,expand_ms,bezier_ms,terminals_ms,"
                 "total_ms,best_ms,cold_ms,paper_ms,speedup,threads\n");
    int failures = 0;
    pgt_ivy_output out;
    memset(&out, 0, sizeof out);
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; ++k) {
        const ivy_bench_scene *sc = &scenes[k];
        pgt_ivy_scene s;
        if (scene_setup(&s, sc->mesh, sc->params, sc->painted, sc->seeds, sc->stroke_steps,
                        sc->seeds, seed, threads, save_dir, sc->name)) {
            pgt_ivy_scene_free(&s);
            failures++;
            continue;
        }
        pgt_expand_input in;
        pgt_ivy_scene_input(&s, &in);
        in.seed_base = seed;
        pgt_ivy_options o;
        memset(&o, 0, sizeof o);
        o.expand.march.mask = s.mask;
        o.threads = threads, o.reuse = 1;
        o.terminals.no_triangle_segment = 1;
        ivy_timing t;
        if (time_runs(&out, &in, &o, repeat, &t)) {
            pgt_ivy_scene_free(&s);
            failures++;
            continue;
        }
        const double ratio = (double)out.polygons / sc->paper_polygons;
        const int within = ratio >= 1.0 - BENCH_IVY_POLYGON_TOLERANCE &&
                           ratio <= 1.0 + BENCH_IVY_POLYGON_TOLERANCE;
        fprintf(csv,
                "%s,%s,%s,%u,%s,%s,%u,%u,%llu,%.0f,%.4f,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.0f,"
                "%.3f,%u\n",
                sc->name, sc->figure, sc->mesh, sc->seeds, sc->painted ? "painted" : "none",
                sc->params, out.expand.point_count, out.segments, (unsigned long long)out.polygons,
                sc->paper_polygons, ratio, within, t.expand, t.bezier, t.terminals, t.total, t.best,
                t.cold, sc->paper_ms, sc->paper_ms / t.total, threads);
        fflush(csv);
        fprintf(stderr,
                "pgt bench ivy: %s (%s, %u seeds): %llu polygons (%.1f %% of the paper's), "
                "%.1f ms (expand %.1f, bezier %.1f, terminals %.1f); paper %.0f ms\n",
                sc->name, sc->mesh, sc->seeds, (unsigned long long)out.polygons, 100.0 * ratio,
                t.total, t.expand, t.bezier, t.terminals, sc->paper_ms);
        pgt_ivy_scene_free(&s);
    }
    if (pgt_cli_bench_close(csv, tmp, out_path, "bench", failures)) failures++;

    /* Figure 11 */
    FILE *f11 = pgt_cli_table_open(fig11_path,
                                   "pgt bench ivy: Figure 11 of paper 000, generation time vs "
                                   "number of seeds",
                                   tmp, sizeof tmp);
    if (!f11) {
        pgt_ivy_destroy(&out);
        return pgt_cli_fail("bench", "cannot write %s: %s", tmp, strerror(errno));
    }
    fprintf(f11,
            "# mesh %s, atlas 1024^2; %u painted strokes of %u guide steps (all painted), "
            "n seeds at the first n strokes' starts; params %s; 1 warm-up + %u timed runs, "
            "medians; %u threads\n",
            BENCH_IVY_FIG11_MESH, BENCH_IVY_FIG11_SEEDS, BENCH_IVY_FIG11_STEPS,
            BENCH_IVY_FIG11_PARAMS, repeat, threads);
    fprintf(f11, "# scenario main: main branch only, no leaves (secondaryBranches=0, "
                 "--no-leaves); full: secondary branches and leaves (the grammar as shipped)\n");
    fprintf(f11, "scenario,seeds,points,segments,polygons,expand_ms,bezier_ms,terminals_ms,"
                 "total_ms,best_ms,cold_ms,threads\n");
    for (uint32_t sc = 0; sc < 2 && !failures; ++sc) {
        pgt_ivy_scene s;
        char params[256];
        snprintf(params, sizeof params, "%s%s", BENCH_IVY_FIG11_PARAMS,
                 sc == 0 ? ",secondaryBranches=0" : "");
        if (scene_setup(&s, BENCH_IVY_FIG11_MESH, params, 1, BENCH_IVY_FIG11_SEEDS,
                        BENCH_IVY_FIG11_STEPS, BENCH_IVY_FIG11_SEEDS, seed, threads,
                        sc ? save_dir : NULL, "fig11")) {
            pgt_ivy_scene_free(&s);
            failures++;
            break;
        }
        for (uint32_t n = 1; n <= BENCH_IVY_FIG11_SEEDS; ++n) {
            if (quick && (n & (n - 1u))) continue; /* powers of two */
            pgt_expand_input in;
            pgt_ivy_scene_input(&s, &in);
            in.seed_count = n; /* the first n seeds */
            in.seed_base = seed;
            pgt_ivy_options o;
            memset(&o, 0, sizeof o);
            o.expand.march.mask = s.mask;
            o.threads = threads, o.reuse = 1, o.no_leaves = sc == 0;
            o.terminals.no_triangle_segment = 1;
            ivy_timing t;
            if (time_runs(&out, &in, &o, repeat, &t)) {
                failures++;
                break;
            }
            fprintf(f11, "%s,%u,%u,%u,%llu,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%u\n",
                    sc ? "full" : "main", n, out.expand.point_count, out.segments,
                    (unsigned long long)out.polygons, t.expand, t.bezier, t.terminals, t.total,
                    t.best, t.cold, threads);
            fflush(f11);
            /* a progress line every few points, one line each: a log keeps them readable */
            if (quick || n % BENCH_IVY_PROGRESS_EVERY == 0 || n == BENCH_IVY_FIG11_SEEDS)
                fprintf(stderr, "pgt bench ivy: figure 11, %s, %u of %u seeds: %.1f ms\n",
                        sc ? "full" : "main", n, BENCH_IVY_FIG11_SEEDS, t.total);
        }
        pgt_ivy_scene_free(&s);
    }
    pgt_ivy_destroy(&out);
    if (pgt_cli_bench_close(f11, tmp, fig11_path, "bench", failures)) failures++;
    if (!failures) fprintf(stderr, "pgt bench ivy: wrote %s and %s\n", out_path, fig11_path);
    return failures ? PGT_EXIT_USAGE : PGT_EXIT_OK; /* errors while working (cli.h) */
}
