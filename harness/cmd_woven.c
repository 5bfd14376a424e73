/* pgt woven: the woven sphere of paper 002 (Appendix A; ref_cpu/src/woven.c), animated for F
 * frames and timed per frame. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "pgt/mesh_io.h"
#include "pgt/parallel.h"
#include "pgt/woven.h"
#include "progress_line.h"

/* Most frames of one run: 10^6 frames of the 5k model take minutes; the bound keeps a typo
 * (an extra digit or two) from running for hours. */
#define WOVEN_MAX_FRAMES 1000000u

#define WOVEN_DEFAULT_FRAMES 50u

static const char *woven_usage =
    "usage: pgt woven (--res 5k|22k|50k|89k|179k | --params P,K,C,U,V) [--frames F]\n"
    "                 [--threads N] [-o WOVEN.ply] [--seed S]\n"
    "\n"
    "Animates the woven sphere of paper 002 (Appendix A): P particles in [-1,1]^3 moving at\n"
    "0.0025 per frame and reflecting off the box; C curves, each a uniform cubic B-spline\n"
    "through K distinct random particles as control keys, sampled at V points; the samples\n"
    "spherified onto the unit sphere; a circle of radius 0.025 with U vertices (the last\n"
    "repeating the first) lofted along each curve with a rotation-minimising frame. A frame\n"
    "moves the particles one step and re-derives every curve and loft (C U V vertices,\n"
    "2 (U-1)(V-1) C triangles). Prints the counts and the median and minimum ms per frame.\n"
    "\n"
    "  --res NAME      one of the paper's five resolutions (P,K,C,U,V; vertices):\n"
    "                    5k    150,6,25,8,25       5,000\n"
    "                    22k   660,6,110,8,25     22,000\n"
    "                    50k   800,8,100,10,50    50,000\n"
    "                    89k   1424,8,178,10,50   89,000\n"
    "                    179k  1432,8,179,10,100  179,000\n"
    "  --params P,K,C,U,V  any parameters instead: P particles, K keys per curve (4 <= K <= P),\n"
    "                  C curves, U circle vertices (>= 4), V samples per curve (>= 2);\n"
    "                  refused when the model's arrays exceed this machine's memory\n"
    "  --frames F      frames to animate and time, 1 to 1000000 (default 50); every frame is\n"
    "                  timed (step + evaluation, no file I/O); the first one also touches the\n"
    "                  freshly allocated output\n"
    "  --threads N     threads (default: the number of CPUs); the output is the same bytes for\n"
    "                  any N\n"
    "  -o WOVEN.ply    write the last frame: binary PLY, vertex x y z nx ny nz (unit normals,\n"
    "                  outward from the curve), triangles; temporary file, then renamed\n"
    "  --seed S        seed of the particles, their directions and the key subsets (default 1)\n"
    "\n"
    "A progress line on stderr every 5 s of work (PGT_PROGRESS_SECONDS: the period, 0: none).\n"
    "Exit 0 on success, 2 on a bad flag or value (one line naming the flag).\n";

/* A woven.c message without its "woven: " prefix (the verb already names it). */
static const char *bare(const char *message) {
    return strncmp(message, "woven: ", 7) ? message : message + 7;
}

int pgt_cmd_woven(int argc, char **argv) {
    const char *verb = "woven", *res = NULL, *params_text = NULL, *out_path = NULL;
    uint32_t frames = WOVEN_DEFAULT_FRAMES, threads = pgt_cli_cpu_count(), seed = 1;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(woven_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--res")) {
            if (!(res = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--params")) {
            if (!(params_text = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--frames")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, WOVEN_MAX_FRAMES, &frames))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, PGT_MAX_THREADS, &threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--seed")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 0, UINT32_MAX, &seed))
                return PGT_EXIT_USAGE;
        } else if (a[0] == '-' && a[1] != '\0') {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt woven --help)", a);
        } else {
            return pgt_cli_fail(verb, "unexpected argument '%s' (see pgt woven --help)", a);
        }
    }
    if (!res == !params_text)
        return pgt_cli_fail(verb, "%s",
                            res ? "--res and --params: give only one"
                                : "no model: give --res NAME or --params P,K,C,U,V");
    if (out_path && pgt_mesh_format_from_path(out_path) != PGT_FORMAT_PLY)
        return pgt_cli_fail(verb, "-o %s: the output is a PLY file (name it *.ply)", out_path);
    if (pgt_cli_check_outputs(verb, &out_path, 1)) return PGT_EXIT_USAGE;
    pgt_woven_params p;
    pgt_error err = {0};
    if (res && pgt_woven_find_resolution(res, &p, &err) != PGT_OK)
        return pgt_cli_fail(verb, "--res: %s", bare(err.message));
    if (params_text) {
        uint32_t v[5], n = 0;
        if (pgt_cli_uint_list(verb, "--params", params_text, 0, UINT32_MAX, v, 5, &n))
            return PGT_EXIT_USAGE;
        if (n != 5)
            return pgt_cli_fail(verb, "--params %s: expected 5 values P,K,C,U,V, got %u",
                                params_text, n);
        p = (pgt_woven_params){v[0], v[1], v[2], v[3], v[4]};
        pgt_woven_counts c;
        if (pgt_woven_check(&p, &c, &err) != PGT_OK)
            return pgt_cli_fail(verb, "--params %s: %s", params_text, bare(err.message));
        /* within 32-bit indices the arrays reach ~150 GB: with the kernel's overcommit the
         * allocation succeeds and the first frame gets the process killed */
        if (pgt_cli_memory_env_check(verb)) return PGT_EXIT_USAGE;
        const uint64_t mem = pgt_cli_available_bytes();
        char need[32], have[32];
        if (mem && c.bytes > mem)
            return pgt_cli_fail(verb,
                                "--params %s: the model's arrays take %s, more than the %s of "
                                "memory available now",
                                params_text, pgt_cli_bytes_text(need, sizeof need, c.bytes),
                                pgt_cli_bytes_text(have, sizeof have, mem));
    }

    pgt_woven w;
    pgt_woven_mesh m;
    memset(&m, 0, sizeof m);
    double *ms = malloc((size_t)frames * sizeof(double));
    int rc = PGT_EXIT_USAGE;
    pgt_cli_progress prog; /* a line every few seconds while the work runs (stderr) */
    if (pgt_cli_progress_start(&prog, verb)) {
        free(ms);
        return PGT_EXIT_USAGE;
    }
    pgt_progress_stage(prog.progress, "setting up", 0, "");
    if (pgt_woven_create(&w, &p, seed, &err) != PGT_OK ||
        pgt_woven_mesh_create(&m, &p, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", bare(err.message));
        goto done;
    }
    if (!ms) {
        pgt_cli_fail(verb, "out of memory");
        goto done;
    }
    pgt_progress_stage(prog.progress, "frames", frames, "frames");
    for (uint32_t f = 0; f < frames; ++f) {
        const double t0 = pgt_cli_now_ms();
        pgt_woven_frame(&m, &w, threads);
        ms[f] = pgt_cli_now_ms() - t0;
        pgt_progress_add(prog.progress, 1);
    }
    printf("woven %s: P %u, K %u, C %u, U %u, V %u; %u vertices, %u triangles\n",
           res ? res : "(--params)", p.particles, p.keys, p.curves, p.ring, p.samples,
           m.counts.vertices, m.counts.triangles);
    printf("  %u frames, %u threads: median %.3f ms per frame, min %.3f ms\n", frames, threads,
           pgt_cli_median(ms, frames), pgt_cli_min(ms, frames));
    if (out_path) {
        pgt_progress_stage(prog.progress, "writing the last frame", 0, "");
        const pgt_vertex_mesh soup = {
            m.counts.vertices, m.counts.triangles, m.positions, m.normals, NULL, m.triangles};
        if (pgt_mesh_write_ply_soup(&soup, out_path, &err) != PGT_OK) {
            pgt_cli_fail(verb, "%s", err.message);
            goto done;
        }
        printf("  wrote %s (frame %llu)\n", out_path, (unsigned long long)w.frame);
    }
    rc = PGT_EXIT_OK;
done:
    pgt_cli_progress_stop(&prog);
    free(ms);
    pgt_woven_mesh_destroy(&m);
    pgt_woven_destroy(&w);
    return rc;
}
