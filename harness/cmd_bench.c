/* pgt bench: benchmarks that write CSV tables to results/.
 *
 * bench subdiv: our sqrt(3) (ref_cpu, 1 thread and all threads) against CGAL Surface_mesh and
 * OpenMesh Sqrt3T measured in the same run on the same input, subdivision call only (no file
 * I/O): warm-up, R timed runs, median and best. Peak extra memory of our call is measured in a
 * forked child (see bench_peak_mib). */
/* malloc_trim() and mallopt() are glibc's; declared under _DEFAULT_SOURCE. */
#define _DEFAULT_SOURCE
#include <errno.h>
#include <malloc.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "backend.h"
#include "cli.h"
#include "signal_cleanup.h"
#include "gen.h"
#include "oracle.h"
#include "pgt/mesh_io.h"
#include "pgt/sqrt3.h"

static const char *bench_usage =
    "usage: pgt bench atlas ...    (Table 1 of paper 000: pgt bench atlas --help)\n"
    "       pgt bench march ...    (marching steps per second: pgt bench march --help)\n"
    "       pgt bench ivy ...      (Table 2 and Fig. 11 of paper 000: pgt bench ivy --help)\n"
    "       pgt bench woven ...    (woven sphere, Fig. 4.11 of paper 002: pgt bench woven --help)\n"
    "       pgt bench facade ...   (procedural facades vs Embree, paper 003: pgt bench facade "
    "--help)\n"
    "       pgt bench subdiv [--out FILE] [--repeat R] [--iters LIST] [--threads LIST]\n"
    "                        [--meshes LIST] [--shared DIR] [--no-oracles] [--quick]\n"
    "                        [--backends LIST] [--device N]\n"
    "\n"
    "Times sqrt(3) subdivision (ours, CGAL, OpenMesh; same input, same run, subdivision only)\n"
    "and writes one CSV row per mesh x k x thread count, headed by machine, commit and date.\n"
    "\n"
    "  --out FILE      CSV to write (default results/subdiv.csv; temporary file + rename)\n"
    "  --repeat R      timed runs per measurement after one warm-up, 1 to 1000 (default 7)\n"
    "  --iters LIST    comma-separated k values (default 1,2,3)\n"
    "  --threads LIST  comma-separated thread counts for ours (default 1,<CPUs>)\n"
    "  --meshes LIST   comma-separated names: torus_100k (generated, 100k faces: the issue's\n"
    "                  performance target), any generated default dataset (see pgt_datasets\n"
    "                  --list), or a file name in the shared mesh folder (default: torus_100k and\n"
    "                  every mesh of the shared folder)\n"
    "  --shared DIR    shared mesh folder (default ../shared/datasets/meshes beside the repo)\n"
    "  --no-oracles    skip CGAL and OpenMesh (their columns stay empty)\n"
    "  --backends LIST GPU backends to time beside ours: cl, vk, both (cl,vk) or none (default:\n"
    "                  every one with a device; a missing device leaves its columns empty)\n"
    "  --device N      device index of each GPU API (see pgt devices; default 0)\n"
    "  --quick         small and fast: only the generated torus, at 10k faces instead of 100k\n"
    "                  (its rows keep the name torus_100k; faces_in says 9954), k=1,2, R=1;\n"
    "                  needs --out (the default is the committed table)\n";

#define BENCH_MAX_LIST 32

typedef struct bench_cfg {
    const char *out_path, *shared_dir;
    uint32_t repeat, iters[BENCH_MAX_LIST], n_iters, threads[BENCH_MAX_LIST], n_threads;
    const char *meshes[BENCH_MAX_LIST];
    uint32_t n_meshes;
    int oracles, quick;
    int gpu_asked[2];    /* cl, vk: timed when a device opens (asked explicitly: must open) */
    int gpu_explicit;    /* --backends given */
    int device_explicit; /* --device given: a missing device is an error, not a skipped column */
    uint32_t device;
    pgt_backend gpu[2]; /* open backends (kind CPU = not open) */
    char mesh_list_buf[4096];
} bench_cfg;

/* Loads a named benchmark mesh: the generated bench torus, or pgt_cli_load_named's. */
static pgt_result bench_load(const bench_cfg *cfg, const char *name, pgt_mesh *m, pgt_error *err) {
    if (!strcmp(name, "torus_100k"))
        return pgt_gen_bench_torus(m, cfg->quick ? 10000 : 100000, err);
    return pgt_cli_load_named(name, cfg->shared_dir, m, err);
}

/* A field of /proc/self/status in KiB (VmRSS, VmHWM), or -1. */
static long status_kib(const char *field) {
    FILE *f = fopen("/proc/self/status", "r");
    long kib = -1;
    if (!f) return -1;
    char line[256];
    size_t n = strlen(field);
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, field, n) && line[n] == ':') kib = strtol(line + n + 1, NULL, 10);
    fclose(f);
    return kib;
}

/* One warm-up and `repeat` timed runs of ours; median and best ms, output counts. */
static int bench_time(const pgt_mesh *m, const pgt_sqrt3_options *o, uint32_t repeat, double *times,
                      double *med, double *best, uint32_t *vout, uint32_t *fout, pgt_error *err) {
    pgt_mesh out = {0};
    if (pgt_sqrt3_subdivide(&out, m, o, err) != PGT_OK) return -1;
    *vout = out.vertex_count, *fout = out.face_count;
    pgt_mesh_destroy(&out);
    for (uint32_t r = 0; r < repeat; ++r) {
        double t0 = pgt_cli_now_ms();
        pgt_sqrt3_subdivide(&out, m, o, NULL);
        times[r] = pgt_cli_now_ms() - t0;
        pgt_mesh_destroy(&out);
    }
    *med = pgt_cli_median(times, repeat);
    *best = pgt_cli_min(times, repeat);
    return 0;
}

/* One warm-up and `repeat` timed calls on a GPU backend: medians of the device time (sum of
 * kernel times) and of the whole call (upload, kernels, download, host-side adjacency). */
static int bench_gpu(pgt_backend *b, const pgt_mesh *m, const pgt_sqrt3_options *o, uint32_t repeat,
                     double *times, double *dev_med, double *total_med, pgt_error *err) {
    pgt_mesh out = {0};
    pgt_gpu_times t;
    if (pgt_backend_sqrt3(b, &out, m, o, &t, err) != PGT_OK) return -1;
    pgt_mesh_destroy(&out);
    double *dev = times + repeat;
    for (uint32_t r = 0; r < repeat; ++r) {
        double t0 = pgt_cli_now_ms();
        if (pgt_backend_sqrt3(b, &out, m, o, &t, err) != PGT_OK) return -1;
        times[r] = pgt_cli_now_ms() - t0;
        dev[r] = t.device_ms;
        pgt_mesh_destroy(&out);
    }
    *total_med = pgt_cli_median(times, repeat);
    *dev_med = pgt_cli_median(dev, repeat);
    return 0;
}

/* Peak extra resident memory (MiB) of one subdivision, measured in a forked child: it goes back
 * to glibc's default allocator policy, returns the heap memory the parent kept (malloc_trim),
 * resets its high-water mark (clear_refs 5), then runs once; peak = VmHWM after - VmRSS before.
 * -1 when the system cannot tell. */
static double bench_peak_mib(const pgt_mesh *m, const pgt_sqrt3_options *opts) {
    int fds[2];
    if (pipe(fds) != 0) return -1.0;
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]), close(fds[1]);
        return -1.0;
    }
    if (pid == 0) {
        close(fds[0]);
        pgt_cli_signals_default(); /* the parent's signal thread is not in the child */
        double mib = -1.0;
        /* glibc's default policy here, so blocks freed during the call leave the resident set
         * as they would in a program of the user's, then return what the parent kept */
        mallopt(M_MMAP_MAX, 65536);
        mallopt(M_TRIM_THRESHOLD, 128 * 1024);
        malloc_trim(0);
        FILE *c = fopen("/proc/self/clear_refs", "w");
        int reset = c && fputs("5", c) >= 0;
        if (c && fclose(c) != 0) reset = 0;
        long base = status_kib("VmRSS");
        pgt_mesh out;
        if (reset && base >= 0 && pgt_sqrt3_subdivide(&out, m, opts, NULL) == PGT_OK) {
            long hwm = status_kib("VmHWM");
            if (hwm >= 0) mib = (double)(hwm - base) / 1024.0;
        }
        ssize_t w = write(fds[1], &mib, sizeof mib);
        _exit(w == (ssize_t)sizeof mib ? 0 : 1);
    }
    close(fds[1]);
    double mib = -1.0;
    if (read(fds[0], &mib, sizeof mib) != (ssize_t)sizeof mib) mib = -1.0;
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return mib;
}

static int bench_subdiv(bench_cfg *cfg) {
    char machine[512], commit[64], date[64], tmpdir[] = "/tmp/pgt-bench-XXXXXX";
    pgt_cli_machine(machine, sizeof machine);
    pgt_cli_commit(commit, sizeof commit);
    pgt_cli_date(date, sizeof date);
    if (!mkdtemp(tmpdir))
        return pgt_cli_fail("bench", "cannot make a temporary folder: %s", strerror(errno));

    char tmp_csv[4200];
    FILE *csv = pgt_cli_table_open(
        cfg->out_path, "pgt bench subdiv: sqrt(3) subdivision, subdivision call only (no file I/O)",
        tmp_csv, sizeof tmp_csv);
    if (!csv) {
        rmdir(tmpdir);
        return pgt_cli_fail("bench", "cannot write %s: %s", tmp_csv, strerror(errno));
    }
    fprintf(csv,
            "# runs: 1 warm-up + %u timed per measurement; ms are medians (best beside ours)\n",
            cfg->repeat);
    fprintf(
        csv,
        "# cgal: CGAL 5.5 Surface_mesh<Simple_cartesian<double>> Sqrt3_subdivision, 1 thread\n");
    fprintf(csv, "# openmesh: OpenMesh 9.0 Sqrt3T<TriMesh, double>, 1 thread\n");
    fprintf(csv,
            "# allocator: glibc with mmap off and trimming at 1 GiB in every timed program "
            "(ours and the oracles), so repeated runs reuse memory instead of page-faulting\n");
    fprintf(csv,
            "# input: positions and triangles for all three (the oracles read OFF); "
            "ours_uv_median_ms: ours again with the mesh's per-corner UVs, when it has them\n");
    fprintf(csv, "# ours_peak_mib: extra resident memory of one call at that thread count; "
                 "output_mib: positions+indices of the result\n");
    for (int g = 0; g < 2; ++g)
        if (cfg->gpu[g].kind != PGT_BACKEND_CPU)
            fprintf(csv, "# %s: %s\n", g ? "vk" : "cl", cfg->gpu[g].name);
    fprintf(csv, "# cl_/vk_device_median_ms: the kernels' device time (OpenCL profiling events, "
                 "Vulkan timestamps); cl_/vk_total_median_ms: the whole call as a user sees it "
                 "(input adjacency on the host, upload, kernels, download); the same on every "
                 "thread row\n");
    fprintf(csv, "mesh,faces_in,k,threads,faces_out,vertices_out,ours_median_ms,ours_best_ms,"
                 "cgal_median_ms,openmesh_median_ms,cgal_over_ours,openmesh_over_ours,"
                 "ours_peak_mib,output_mib,ours_uv_median_ms,cl_device_median_ms,"
                 "cl_total_median_ms,vk_device_median_ms,vk_total_median_ms\n");

    uint32_t steps = cfg->n_meshes * cfg->n_iters, step = 0;
    int failures = 0, mismatches = 0; /* errors while working; counts unlike CGAL's */
    double *times = malloc(sizeof(double) * 2 * cfg->repeat);
    for (uint32_t mi = 0; mi < cfg->n_meshes && times; ++mi) {
        const char *name = cfg->meshes[mi];
        pgt_mesh m = {0};
        pgt_error err = {0};
        if (bench_load(cfg, name, &m, &err) != PGT_OK) {
            fprintf(stderr, "pgt bench: skipping %s: %s\n", name, err.message);
            failures++;
            step += cfg->n_iters;
            continue;
        }
        /* The oracles get positions and triangles only (OFF), so ours is timed on the same; a
         * textured mesh is timed again with its per-corner UVs (ours_uv_median_ms). */
        pgt_mesh uv = m;
        m.uvs = NULL;
        m.labels = NULL;
        char in_off[4096];
        snprintf(in_off, sizeof in_off, "%s/in.off", tmpdir);
        pgt_mesh_write_options wo = {PGT_FORMAT_OFF, 1};
        int have_off = cfg->oracles && pgt_mesh_write(&m, in_off, &wo, &err) == PGT_OK;
        for (uint32_t ki = 0; ki < cfg->n_iters; ++ki) {
            const uint32_t k = cfg->iters[ki];
            step++;
            pgt_oracle_run cg = {0}, om = {0};
            int have_cg = 0, have_om = 0;
            if (have_off) { /* "-": the oracles time only; agreement is the tests' job */
                pgt_error e1 = {0}, e2 = {0};
                have_cg =
                    pgt_oracle_sqrt3("cgal_sqrt3", in_off, k, "-", cfg->repeat, &cg, &e1) == PGT_OK;
                if (!have_cg) fprintf(stderr, "pgt bench: %s\n", e1.message), failures++;
                have_om = pgt_oracle_sqrt3("openmesh_sqrt3", in_off, k, "-", cfg->repeat, &om,
                                           &e2) == PGT_OK;
                if (!have_om) fprintf(stderr, "pgt bench: %s\n", e2.message), failures++;
            }
            fprintf(stderr, "[%u/%u] %s (%u faces) k=%u:", step, steps, name, m.face_count, k);
            double gdev[2] = {-1.0, -1.0}, gtot[2] = {-1.0, -1.0};
            for (int g = 0; g < 2; ++g) {
                if (cfg->gpu[g].kind == PGT_BACKEND_CPU) continue;
                pgt_sqrt3_options o = {0};
                o.iterations = k;
                pgt_error e = {0};
                if (bench_gpu(&cfg->gpu[g], &m, &o, cfg->repeat, times, &gdev[g], &gtot[g], &e)) {
                    fprintf(stderr, " %s failed: %s", g ? "vk" : "cl", e.message);
                    gdev[g] = gtot[g] = -1.0;
                    failures++;
                } else {
                    fprintf(stderr, " %s %.1f ms (device %.1f)", g ? "vk" : "cl", gtot[g], gdev[g]);
                }
            }
            for (uint32_t ti = 0; ti < cfg->n_threads; ++ti) {
                pgt_sqrt3_options o = {0};
                o.iterations = k;
                o.threads = cfg->threads[ti];
                double med, best, uv_med = -1.0, uv_best;
                uint32_t vout, fout;
                pgt_error e = {0};
                if (bench_time(&m, &o, cfg->repeat, times, &med, &best, &vout, &fout, &e) ||
                    (uv.uvs && bench_time(&uv, &o, cfg->repeat, times, &uv_med, &uv_best, &vout,
                                          &fout, &e))) {
                    fprintf(stderr, " ours failed: %s", e.message);
                    failures++;
                    break;
                }
                double peak = bench_peak_mib(&m, &o);
                double out_mib = ((double)vout * 12.0 + (double)fout * 12.0) / 1048576.0;
                pgt_cli_csv_field(csv, name);
                fprintf(csv, ",%u,%u,%u,%u,%u,%.3f,%.3f,", m.face_count, k, o.threads, fout, vout,
                        med, best);
                if (have_cg) fprintf(csv, "%.3f", cg.median_ms);
                fputc(',', csv);
                if (have_om) fprintf(csv, "%.3f", om.median_ms);
                fputc(',', csv);
                if (have_cg) fprintf(csv, "%.2f", cg.median_ms / med);
                fputc(',', csv);
                if (have_om) fprintf(csv, "%.2f", om.median_ms / med);
                fprintf(csv, ",%.1f,%.1f,", peak, out_mib);
                if (uv_med >= 0.0) fprintf(csv, "%.3f", uv_med);
                for (int g = 0; g < 2; ++g) {
                    fputc(',', csv);
                    if (gdev[g] >= 0.0) fprintf(csv, "%.3f", gdev[g]);
                    fputc(',', csv);
                    if (gtot[g] >= 0.0) fprintf(csv, "%.3f", gtot[g]);
                }
                fputc('\n', csv);
                fprintf(stderr, " ours %.1f ms (%u thr)", med, o.threads);
                if (have_cg && (cg.faces_out != fout || cg.vertices_out != vout)) {
                    fprintf(stderr, " [CGAL counts differ: %u v %u f]", cg.vertices_out,
                            cg.faces_out);
                    mismatches++;
                }
            }
            if (have_cg) fprintf(stderr, ", CGAL %.1f ms", cg.median_ms);
            if (have_om) fprintf(stderr, ", OpenMesh %.1f ms", om.median_ms);
            fputc('\n', stderr);
        }
        remove(in_off);
        pgt_mesh_destroy(&uv); /* owns m's arrays too */
        m = (pgt_mesh){0};
    }
    free(times);
    rmdir(tmpdir);
    if (pgt_cli_bench_close(csv, tmp_csv, cfg->out_path, "bench", failures + mismatches))
        return PGT_EXIT_USAGE;
    if (!failures && !mismatches)
        fprintf(stderr, "pgt bench subdiv: wrote %s (%u mesh%s x %u k x %u thread count%s)\n",
                cfg->out_path, cfg->n_meshes, cfg->n_meshes == 1 ? "" : "es", cfg->n_iters,
                cfg->n_threads, cfg->n_threads == 1 ? "" : "s");
    /* an error outranks a found problem (cli.h) */
    return failures ? PGT_EXIT_USAGE : mismatches ? PGT_EXIT_FAIL : PGT_EXIT_OK;
}

int pgt_cmd_bench(int argc, char **argv) {
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        fputs(bench_usage, argc < 2 ? stderr : stdout);
        return argc < 2 ? PGT_EXIT_USAGE : PGT_EXIT_OK;
    }
    if (!strcmp(argv[1], "atlas")) return pgt_cmd_bench_atlas(argc - 1, argv + 1);
    if (!strcmp(argv[1], "march")) return pgt_cmd_bench_march(argc, argv);
    if (!strcmp(argv[1], "ivy")) return pgt_cmd_bench_ivy(argc, argv);
    if (!strcmp(argv[1], "woven")) return pgt_cmd_bench_woven(argc, argv);
    if (!strcmp(argv[1], "facade")) return pgt_cmd_bench_facade(argc, argv);
    if (strcmp(argv[1], "subdiv") != 0)
        return pgt_cli_fail(
            "bench", "unknown benchmark '%s' (known: subdiv, atlas, march, ivy, woven, facade)",
            argv[1]);
    /* The benchmark allocator policy, the same in the oracle programs (oracle_common.hpp): freed
     * memory stays in the heap, so repeated runs time the algorithm rather than the kernel's
     * first-touch page faults on fresh mmapped blocks (about 45 % of a 2.7M-face run here). */
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    bench_cfg cfg = {0};
    static const char *const default_out = "results/subdiv.csv";
    cfg.out_path = default_out;
    cfg.shared_dir = PGT_CLI_SHARED_MESH_DIR;
    cfg.repeat = 7;
    cfg.oracles = 1;
    cfg.gpu_asked[0] = cfg.gpu_asked[1] = 1;
    cfg.n_iters = 3;
    cfg.iters[0] = 1, cfg.iters[1] = 2, cfg.iters[2] = 3;
    cfg.n_threads = 0;
    int have_repeat = 0, have_iters = 0, have_meshes = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(bench_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--out") || !strcmp(a, "-o")) {
            if (!(cfg.out_path = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--shared")) {
            if (!(cfg.shared_dir = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--repeat")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 1, 1000, &cfg.repeat))
                return PGT_EXIT_USAGE;
            have_repeat = 1;
        } else if (!strcmp(a, "--iters")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint_list("bench", a, v, 0, 6, cfg.iters, BENCH_MAX_LIST, &cfg.n_iters))
                return PGT_EXIT_USAGE;
            have_iters = 1;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint_list("bench", a, v, 1, 256, cfg.threads, BENCH_MAX_LIST,
                                  &cfg.n_threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--meshes")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
            cfg.n_meshes = 0;
            if (pgt_cli_name_list("bench", a, v, cfg.mesh_list_buf, sizeof cfg.mesh_list_buf,
                                  cfg.meshes, BENCH_MAX_LIST, &cfg.n_meshes))
                return PGT_EXIT_USAGE;
            have_meshes = 1;
        } else if (!strcmp(a, "--no-oracles")) {
            cfg.oracles = 0;
        } else if (!strcmp(a, "--quick")) {
            cfg.quick = 1;
        } else if (!strcmp(a, "--backends")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i))) return PGT_EXIT_USAGE;
            cfg.gpu_explicit = 1;
            if (pgt_backend_parse_list("bench", v, cfg.gpu_asked)) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--device")) {
            if (!(v = pgt_cli_value("bench", argc, argv, &i)) ||
                pgt_cli_uint("bench", a, v, 0, 1024, &cfg.device))
                return PGT_EXIT_USAGE;
            cfg.device_explicit = 1;
        } else {
            return pgt_cli_fail("bench", "unknown flag '%s' (see pgt bench --help)", a);
        }
    }
    if (!cfg.n_threads) {
        cfg.threads[cfg.n_threads++] = 1;
        if (pgt_cli_cpu_count() > 1) cfg.threads[cfg.n_threads++] = pgt_cli_cpu_count();
    }
    if (cfg.quick) {
        if (!have_repeat) cfg.repeat = 1;
        if (!have_iters) cfg.n_iters = 2;
    }
    if (!have_meshes) {
        cfg.meshes[cfg.n_meshes++] = "torus_100k";
        if (!cfg.quick)
            for (uint32_t i = 0; i < pgt_cli_shared_mesh_count; ++i)
                cfg.meshes[cfg.n_meshes++] = pgt_cli_shared_meshes[i];
    }
    if (pgt_cli_refuse_named_inputs("bench", cfg.meshes, cfg.n_meshes, cfg.shared_dir, "--out",
                                    cfg.out_path) ||
        pgt_cli_quick_out("bench", cfg.quick, cfg.out_path, default_out))
        return PGT_EXIT_USAGE;
    if (pgt_backend_open_asked("bench", cfg.gpu, cfg.gpu_asked, cfg.device,
                               cfg.gpu_explicit || cfg.device_explicit))
        return PGT_EXIT_USAGE;
    const int rc = bench_subdiv(&cfg);
    pgt_backend_close(&cfg.gpu[0]), pgt_backend_close(&cfg.gpu[1]);
    return rc;
}
