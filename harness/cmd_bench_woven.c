/* pgt bench woven: the woven sphere's timing table (paper 002 section 4.5, Figure 4.11: "eval"
 * columns of the direct C baseline, Houdini naive and suggested, and LUNA) beside ours, per
 * resolution, at 1 thread and at N threads. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "pgt/parallel.h"
#include "pgt/woven.h"

/* Most timed frames per row. */
#define BENCH_WOVEN_MAX_FRAMES 100000u

/* The target: the 179k model evaluated in at most this many ms per frame on 2 cores. */
#define BENCH_WOVEN_TARGET_MS 4.0

/* Figure 4.11's evaluation times (ms per frame): baseline C, Houdini 10 naive (Copy Stamping
 * SOP), Houdini suggested (AttribCreate + Add SOP), LUNA; the row order of
 * pgt_woven_resolutions. */
static const double paper_ms[PGT_WOVEN_RESOLUTION_COUNT][4] = {
    {2, 40, 27, 5}, {10, 140, 69, 22}, {24, 203, 183, 45}, {44, 318, 276, 89}, {88, 536, 555, 118},
};

static const char *bench_woven_usage =
    "usage: pgt bench woven [--out FILE] [--frames F] [--threads N] [--res LIST] [--seed S]\n"
    "                       [--quick]\n"
    "\n"
    "Times the woven sphere of paper 002 (Appendix A; pgt woven) at the five resolutions of\n"
    "its Figure 4.11 (5k, 22k, 50k, 89k, 179k vertices): per frame, one particle step and the\n"
    "evaluation of every curve, spherify and loft into preallocated arrays (no allocation, no\n"
    "file I/O). One warm-up frame, then F timed frames; median and minimum ms per frame, at 1\n"
    "thread and at N threads, beside the paper's evaluation times (baseline C / Houdini naive /\n"
    "Houdini suggested / LUNA) and the ratios paper / ours.\n"
    "\n"
    "  --out FILE      CSV to write (default results/woven.csv; temporary file + rename),\n"
    "                  headed by machine, commit and date\n"
    "  --frames F      timed frames per row, 1 to 100000 (default 50); --repeat F is the same\n"
    "  --threads N     the multi-threaded rows' thread count (default: the number of CPUs);\n"
    "                  a 1-thread row is always written too\n"
    "  --res LIST      comma-separated resolutions (default 5k,22k,50k,89k,179k)\n"
    "  --seed S        the model's seed (default 1)\n"
    "  --quick         5 timed frames per row (a smoke run)\n";

/* Median and minimum ms per frame of `frames` frames after one warm-up. */
static int time_frames(const pgt_woven_params *p, uint32_t seed, uint32_t threads, uint32_t frames,
                       double *ms, double *median, double *best, pgt_woven_counts *counts) {
    pgt_woven w;
    pgt_woven_mesh m;
    memset(&m, 0, sizeof m);
    pgt_error err = {0};
    if (pgt_woven_create(&w, p, seed, &err) != PGT_OK ||
        pgt_woven_mesh_create(&m, p, &err) != PGT_OK) {
        pgt_woven_destroy(&w);
        return pgt_cli_fail("bench", "%s", err.message); /* "woven: ..." */
    }
    pgt_woven_frame(&m, &w, threads); /* warm-up: first touch of the output */
    for (uint32_t f = 0; f < frames; ++f) {
        const double t0 = pgt_cli_now_ms();
        pgt_woven_frame(&m, &w, threads);
        ms[f] = pgt_cli_now_ms() - t0;
    }
    *median = pgt_cli_median(ms, frames), *best = pgt_cli_min(ms, frames);
    *counts = m.counts;
    pgt_woven_mesh_destroy(&m);
    pgt_woven_destroy(&w);
    return 0;
}

int pgt_cmd_bench_woven(int argc, char **argv) {
    static const char *const default_out = "results/woven.csv";
    const char *out_path = default_out, *res_list = NULL;
    uint32_t frames = 50, threads = pgt_cli_cpu_count(), seed = 1;
    int quick = 0, have_frames = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(bench_woven_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--out") || !strcmp(a, "-o")) {
            if (!(out_path = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--frames") || !strcmp(a, "--repeat")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 1, BENCH_WOVEN_MAX_FRAMES, &frames))
                return PGT_EXIT_USAGE;
            have_frames = 1;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 1, PGT_MAX_THREADS, &threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--res")) {
            if (!(res_list = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--seed")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 0, UINT32_MAX, &seed))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--quick")) {
            quick = 1;
        } else {
            return pgt_cli_fail("bench", "unknown flag '%s' (see pgt bench woven --help)", a);
        }
    }
    if (pgt_cli_quick_out("bench", quick, out_path, default_out)) return PGT_EXIT_USAGE;
    if (quick && !have_frames) frames = 5;
    /* which resolutions, in the table's order */
    int wanted[PGT_WOVEN_RESOLUTION_COUNT];
    for (uint32_t r = 0; r < PGT_WOVEN_RESOLUTION_COUNT; ++r) wanted[r] = res_list == NULL;
    if (res_list) {
        /* an empty or too long list is an error, not an empty table (pgt_cli_name_list) */
        char buf[256];
        const char *names[64];
        uint32_t n_names = 0;
        if (pgt_cli_name_list("bench", "--res", res_list, buf, sizeof buf, names, 64, &n_names))
            return PGT_EXIT_USAGE;
        for (uint32_t q = 0; q < n_names; ++q) {
            const char *tok = names[q];
            uint32_t r = 0;
            while (r < PGT_WOVEN_RESOLUTION_COUNT && strcmp(tok, pgt_woven_resolutions[r].name))
                ++r;
            if (r == PGT_WOVEN_RESOLUTION_COUNT)
                return pgt_cli_fail("bench",
                                    "--res: unknown resolution '%s' (known: 5k, 22k, 50k, 89k, "
                                    "179k)",
                                    tok);
            wanted[r] = 1;
        }
    }
    double *ms = malloc((size_t)frames * sizeof(double));
    if (!ms) return pgt_cli_fail("bench", "out of memory");
    char tmp[4200];
    FILE *csv = pgt_cli_table_open(out_path,
                                   "pgt bench woven: the woven sphere of paper 002 (Appendix A), "
                                   "evaluation ms per frame, with Figure 4.11's rows",
                                   tmp, sizeof tmp);
    if (!csv) {
        free(ms);
        return pgt_cli_fail("bench", "cannot write %s: %s", tmp, strerror(errno));
    }
    fprintf(csv,
            "# runs: per row a fresh model (seed %u), 1 warm-up frame, then %u timed frames; a "
            "frame = 1 particle step + curves, spherify and loft of every curve into "
            "preallocated arrays (triangles written once, not per frame); median_ms and min_ms "
            "per frame\n",
            seed, frames);
    fprintf(csv, "# paper_*_ms: Figure 4.11's eval columns (the paper names no machine; the work "
                 "is from 2010; baseline = direct C implementation, houdini_naive = Houdini 10 "
                 "Copy Stamping SOP, houdini_suggested = AttribCreate + Add SOP, luna = LUNA); "
                 "*_ratio = paper / our median\n");
    fprintf(csv, "# the issue's target: 179k in <= %.0f ms per frame on 2 cores\n",
            BENCH_WOVEN_TARGET_MS);
    fprintf(csv, "res,P,K,C,U,V,vertices,triangles,threads,frames,median_ms,min_ms,"
                 "paper_baseline_ms,paper_houdini_naive_ms,paper_houdini_suggested_ms,"
                 "paper_luna_ms,baseline_ratio,houdini_naive_ratio,houdini_suggested_ratio,"
                 "luna_ratio\n");
    int failures = 0;
    for (uint32_t r = 0; r < PGT_WOVEN_RESOLUTION_COUNT; ++r) {
        if (!wanted[r]) continue;
        const pgt_woven_resolution *res = &pgt_woven_resolutions[r];
        const pgt_woven_params *p = &res->params;
        const uint32_t counts[2] = {1, threads};
        for (uint32_t k = 0; k < (threads > 1 ? 2u : 1u); ++k) {
            double median = 0.0, best = 0.0;
            pgt_woven_counts n = {0, 0, 0, 0};
            if (time_frames(p, seed, counts[k], frames, ms, &median, &best, &n)) {
                failures++;
                continue;
            }
            const double *q = paper_ms[r];
            fprintf(csv,
                    "%s,%u,%u,%u,%u,%u,%u,%u,%u,%u,%.4f,%.4f,%.0f,%.0f,%.0f,%.0f,%.2f,%.2f,%.2f,"
                    "%.2f\n",
                    res->name, p->particles, p->keys, p->curves, p->ring, p->samples, n.vertices,
                    n.triangles, counts[k], frames, median, best, q[0], q[1], q[2], q[3],
                    q[0] / median, q[1] / median, q[2] / median, q[3] / median);
            fflush(csv);
            fprintf(stderr,
                    "pgt bench woven: %s (%u vertices, %u triangles), %u thread%s: median %.3f "
                    "ms per frame (min %.3f); paper: baseline %.0f, LUNA %.0f ms\n",
                    res->name, n.vertices, n.triangles, counts[k], counts[k] == 1 ? "" : "s",
                    median, best, q[0], q[3]);
        }
    }
    free(ms);
    if (pgt_cli_bench_close(csv, tmp, out_path, "bench", failures)) failures++;
    if (!failures) fprintf(stderr, "pgt bench woven: wrote %s\n", out_path);
    return failures ? PGT_EXIT_USAGE : PGT_EXIT_OK; /* errors while working (cli.h) */
}
