/* pgt march: marching on an atlas across charts (ref_cpu/src/march.c; paper 000, sec. 5), and
 * pgt bench march: marching steps per second per core. */
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "backend.h"
#include "cli.h"
#include "gen.h"
#include "pgt/atlas_build.h"
#include "pgt/image.h"
#include "pgt/march.h"
#include "pgt/mesh_io.h"
#include "png_io.h"
#include "progress_line.h"

/* Most steps of one pgt march: a CSV row is ~80 bytes, so 10^7 steps is ~1 GB of text. */
#define MARCH_CLI_MAX_STEPS 10000000u
/* pgt march runs its steps in chunks of this many on the backend (each recording its states and
 * event words), and its progress line moves after each chunk. */
#define MARCH_CHUNK_STEPS 65536u

/* Inner texels written by --dump for the 3D point cloud of a figure (about; every k-th texel
 * of every k-th row): enough to show the surface, small enough for matplotlib. */
#define MARCH_DUMP_POINTS 40000.0

/* Two strings: C11 compilers need not take a literal longer than 4095 characters. */
static const char *const march_usage[2] = {
    "usage: pgt march ATLAS.exr --from U,V --dir DU,DV --step S --steps N -o PATH.csv\n"
    "                 [--mask MASK] [--density DENSITY] [--seed S] [--no-best-pointer]\n"
    "                 [--no-rotation] [--rotation atlas|jacobian] [--dump PREFIX]\n"
    "                 [--with-start] [--backend cpu|cl|vk] [--device N]\n"
    "\n"
    "Marches one walker over an atlas written by pgt atlas (paper 000, sec. 5): N steps of S\n"
    "texels, jumping across charts through the indirection texels (the four cases of Fig. 3,\n"
    "best indirection texel 5.1, direction rotation 5.2). Positions and directions are in\n"
    "texel space: x (u) to the right, y (v) downwards (row 0 is the first row of the image);\n"
    "texel (i, j) covers [i, i+1) x [j, j+1), its centre is (i + 0.5, j + 0.5).\n"
    "\n"
    "  ATLAS.exr        an atlas (the 11 channels of ref_cpu/include/pgt/atlas.h)\n"
    "  --from U,V       start, in texels; must lie in an inner texel (e.g. 100.5,200.5)\n"
    "  --dir DU,DV      initial direction, in texels (normalised; not 0,0)\n"
    "  --step S         step length in texels, > 0 and <= 32768\n"
    "  --steps N        number of steps, 1 to 10000000\n"
    "  -o PATH.csv      output (written to a temporary file, then renamed): a header line\n"
    "                   step,u,v,chart,x,y,z,event and one row per step. u,v are the walker's\n"
    "                   texel coordinates after the step (continuous), chart its chart, x,y,z\n"
    "                   its 3D position (P interpolated bilinearly over the chart's texels).\n"
    "                   event: inner (stayed in its chart), jump (jumped through an\n"
    "                   indirection texel it landed on), search (found one by binary search:\n"
    "                   background or another chart at the destination; a step that did both\n"
    "                   is search), stop (dead end, no indirection texel found, or rejected\n"
    "                   by the mask or the density: the walker does not move and the march\n"
    "                   ends).\n"
    "  --with-start     also a row 0 before the steps: the start, with event start\n"
    "                   (for drawing the whole path; paper_figs/march_path.py)\n"
    "  --mask MASK      external context (a PNG or EXR image of the atlas's size): a step\n"
    "                   whose destination texel has mask value >= 0.5 is rejected (event stop).\n"
    "                   PNG: the first channel (gray, or red), 0..255 as 0..1. EXR: the\n"
    "                   channel 'mask', else 'Y', else 'R', else the only channel.\n"
    "  --density DENSITY  external context (an image like --mask; EXR channel 'density',\n"
    "                   else 'Y', 'R' or the only one): the density d of a step's destination\n"
    "                   texel is the probability that the walker goes on (paper 000 sec. 9,\n"
    "                   'a space occupancy probability'): d <= 0 always stops it, d >= 1 never;\n"
    "                   in between, step k stops when the random number of (seed S, stream 0,\n"
    "                   counter k - 1) in [0, 1) is >= d (event stop)\n"
    "  --seed S         seed id of --density's random numbers, 0 to 4294967295 (default 1)\n"
    "  --no-best-pointer  jump through the indirection texel found, without the 5.1 search\n"
    "                   of its neighbourhood\n"
    "  --no-rotation    do not rotate the direction at jumps (5.2 off)\n"
    "  --rotation R     atlas (default: the paper, the angle stored in the atlas's rot\n"
    "                   channel) or jacobian (the direction with the same 3D motion, from the\n"
    "                   two charts' texel Jacobians; see march.h)\n",
    "  --backend B      cpu (the C reference, default), cl (OpenCL) or vk (Vulkan): where\n"
    "                   the steps run (pgt_backend_march; the GPU versions give the\n"
    "                   reference's steps bit for bit, pgt diff march checks it); the 3D\n"
    "                   positions of the rows come from the reference. --density is a host\n"
    "                   function: cpu only\n"
    "  --device N       device index of that API (see pgt devices; default 0; ignored by cpu)\n"
    "  --dump PREFIX    also write what a figure needs (paper_figs/march_path.py):\n"
    "                   PREFIX.atlas.png (the atlas, one pixel per texel: charts in colours,\n"
    "                   indirection texels darker, dead ends red, background white) and\n"
    "                   PREFIX.texels.csv (u,v,chart,x,y,z,nx,ny,nz of about 40000 inner\n"
    "                   texels, on a regular grid of texels)\n"
    "\n"
    "Prints one summary line, and a progress line on stderr every 5 s of work\n"
    "(PGT_PROGRESS_SECONDS: the period, 0: none). Exit 0 on success (a march that stops early\n"
    "included), 2 on a bad flag, value or input.\n"};

/* A pastel colour per chart (golden-ratio hues). */
static void chart_colour(uint32_t chart, uint8_t rgb[3]) {
    const double h = fmod((double)chart * 0.6180339887498949, 1.0) * 6.0, s = 0.45, v = 0.95;
    const int i = (int)h;
    const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r, g, b;
    switch (i) {
    case 0:
        r = v, g = t, b = p;
        break;
    case 1:
        r = q, g = v, b = p;
        break;
    case 2:
        r = p, g = v, b = t;
        break;
    case 3:
        r = p, g = q, b = v;
        break;
    case 4:
        r = t, g = p, b = v;
        break;
    default:
        r = v, g = p, b = q;
        break;
    }
    rgb[0] = (uint8_t)lround(r * 255), rgb[1] = (uint8_t)lround(g * 255),
    rgb[2] = (uint8_t)lround(b * 255);
}

/* --dump PREFIX's two files, PREFIX.atlas.png and PREFIX.texels.csv. */
typedef struct dump_paths {
    char png[4200], csv[4200];
} dump_paths;

static void dump_paths_of(const char *prefix, dump_paths *d) {
    snprintf(d->png, sizeof d->png, "%s.atlas.png", prefix);
    snprintf(d->csv, sizeof d->csv, "%s.texels.csv", prefix);
}

static int write_dump(const dump_paths *d, const pgt_march_atlas *a, const pgt_image *img,
                      pgt_cli_stage *stage) {
    const uint32_t w = a->width, h = a->height;
    char tmp[4300];
    uint8_t *px = malloc((size_t)w * h * 3);
    if (!px) return pgt_cli_fail("march", "out of memory"), -1;
    size_t inner = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i) {
        const uint32_t c = a->texels[i].code, kind = c & 3u;
        uint8_t *o = px + 3 * i;
        if (kind == PGT_TEXEL_BACKGROUND) {
            o[0] = o[1] = o[2] = 255;
        } else if (kind == PGT_TEXEL_DEAD_END) {
            o[0] = 200, o[1] = 30, o[2] = 30;
        } else {
            chart_colour((c >> 2) - 1u, o);
            if (kind == PGT_TEXEL_INDIRECTION)
                for (int k = 0; k < 3; ++k) o[k] = (uint8_t)(o[k] / 2);
            else
                inner++;
        }
    }
    pgt_error err = {0};
    const pgt_result r = pgt_png_write(pgt_cli_stage_add(stage, d->png), w, h, 3, px, &err);
    free(px);
    if (r != PGT_OK) {
        return pgt_cli_fail("march", "--dump: %s", err.message), -1;
    }
    const char *csv = pgt_cli_stage_add(stage, d->csv);
    FILE *f = pgt_cli_tmp_open(csv, tmp, sizeof tmp);
    if (!f) return pgt_cli_fail("march", "cannot write %s: %s", d->csv, strerror(errno)), -1;
    uint32_t stride = (uint32_t)ceil(sqrt((double)inner / MARCH_DUMP_POINTS));
    if (stride < 1) stride = 1;
    pgt_atlas_channels ch;
    if (pgt_atlas_channels_find(img, d->csv, &ch, &err) != PGT_OK) { /* checked before: a bug */
        fclose(f);
        remove(tmp);
        return pgt_cli_fail("march", "%s", err.message), -1;
    }
    const float *nx = pgt_image_plane(img, ch.nx), *ny = pgt_image_plane(img, ch.ny),
                *nz = pgt_image_plane(img, ch.nz);
    fprintf(f, "u,v,chart,x,y,z,nx,ny,nz\n");
    for (uint32_t y = 0; y < h; y += stride)
        for (uint32_t x = 0; x < w; x += stride) {
            const size_t i = (size_t)y * w + x;
            const pgt_march_texel *t = &a->texels[i];
            if ((t->code & 3u) != PGT_TEXEL_INNER) continue;
            fprintf(f, "%.1f,%.1f,%u,%.9g,%.9g,%.9g,%.5g,%.5g,%.5g\n", x + 0.5, y + 0.5,
                    (t->code >> 2) - 1u, (double)t->x, (double)t->y, (double)t->z, (double)nx[i],
                    (double)ny[i], (double)nz[i]);
        }
    return pgt_cli_table_close(f, tmp, csv, "march") ? -1 : 0;
}

int pgt_cmd_march(int argc, char **argv) {
    const char *verb = "march", *in_path = NULL, *out_path = NULL, *mask_path = NULL, *dump = NULL;
    const char *density_path = NULL;
    uint32_t seed = 1;
    float from[2] = {0, 0}, dir[2] = {0, 0}, step = 0;
    uint32_t steps = 0;
    int have_from = 0, have_dir = 0, have_step = 0, have_steps = 0, with_start = 0;
    pgt_backend_kind kind = PGT_BACKEND_CPU;
    uint32_t device = 0;
    pgt_march_options opts = {0};
    /* -o and --dump's files appear together, none on failure (pgt_cli_stage) */
    pgt_cli_stage stage;
    stage.count = stage.dir_count = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        int flag;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(march_usage[0], stdout), fputs(march_usage[1], stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--from")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) || pgt_cli_floats(verb, a, v, 2, from))
                return PGT_EXIT_USAGE;
            have_from = 1;
        } else if (!strcmp(a, "--dir")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) || pgt_cli_floats(verb, a, v, 2, dir))
                return PGT_EXIT_USAGE;
            if (dir[0] == 0.0f && dir[1] == 0.0f)
                return pgt_cli_fail(verb, "--dir: the direction 0,0 has no heading");
            have_dir = 1;
        } else if (!strcmp(a, "--step")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_float(verb, a, v, 0.0f, PGT_MARCH_MAX_LENGTH, &step))
                return PGT_EXIT_USAGE;
            have_step = 1;
        } else if (!strcmp(a, "--steps")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, MARCH_CLI_MAX_STEPS, &steps))
                return PGT_EXIT_USAGE;
            have_steps = 1;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--mask")) {
            if (!(mask_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--density")) {
            if (!(density_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--seed")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 0, UINT32_MAX, &seed))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--dump")) {
            if (!(dump = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            /* PREFIX.atlas.png and PREFIX.texels.csv: an empty prefix, or a folder's path
             * (ending in '/', '.' or '..'), would write hidden files (.atlas.png) */
            const char *base = strrchr(dump, '/') ? strrchr(dump, '/') + 1 : dump;
            if (!*base || !strcmp(base, ".") || !strcmp(base, ".."))
                return pgt_cli_fail(verb,
                                    "--dump: '%s' is no file name prefix (PREFIX.atlas.png, "
                                    "PREFIX.texels.csv)",
                                    dump);
        } else if (!strcmp(a, "--with-start")) {
            with_start = 1;
        } else if ((flag = pgt_backend_flags(verb, argc, argv, &i, &kind, &device)) != 0) {
            if (flag < 0) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--no-best-pointer")) {
            opts.no_best_pointer = 1;
        } else if (!strcmp(a, "--no-rotation")) {
            opts.no_rotation = 1;
        } else if (!strcmp(a, "--rotation")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            if (!strcmp(v, "atlas"))
                opts.rotation = PGT_MARCH_ROTATION_ATLAS;
            else if (!strcmp(v, "jacobian"))
                opts.rotation = PGT_MARCH_ROTATION_JACOBIAN;
            else
                return pgt_cli_fail(verb, "--rotation: expected atlas or jacobian, got '%s'", v);
        } else if (a[0] == '-' && a[1] != '\0') {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt march --help)", a);
        } else if (!in_path) {
            in_path = a;
        } else {
            return pgt_cli_fail(verb, "unexpected argument '%s' (one atlas only)", a);
        }
    }
    if (!in_path) return pgt_cli_fail(verb, "no atlas (see pgt march --help)");
    if (opts.no_rotation && opts.rotation == PGT_MARCH_ROTATION_JACOBIAN)
        return pgt_cli_fail(verb, "--no-rotation and --rotation jacobian exclude each other");
    if (!have_from) return pgt_cli_fail(verb, "no start: give --from U,V (texels)");
    if (!have_dir) return pgt_cli_fail(verb, "no direction: give --dir DU,DV (texels)");
    if (!have_step) return pgt_cli_fail(verb, "no step length: give --step S (texels)");
    if (!have_steps) return pgt_cli_fail(verb, "no step count: give --steps N");
    if (!out_path) return pgt_cli_fail(verb, "no output: give -o PATH.csv");
    if (density_path && kind != PGT_BACKEND_CPU)
        return pgt_cli_fail(verb,
                            "--density is a host function (a condition callback): it runs on "
                            "--backend cpu only, not %s",
                            pgt_backend_kind_name(kind));
    dump_paths dumped;
    if (dump) dump_paths_of(dump, &dumped);
    {
        const char *inputs[3] = {in_path, mask_path, density_path};
        const char *outputs[3] = {out_path, dump ? dumped.png : NULL, dump ? dumped.csv : NULL};
        if (pgt_cli_refuse_overwrite(verb, inputs, 3, outputs, 3) ||
            pgt_cli_check_outputs(verb, outputs, 3))
            return PGT_EXIT_USAGE;
    }

    const float ux = from[0], uy = from[1], dx = dir[0], dy = dir[1];
    pgt_error err = {0};
    pgt_image img = {0};
    pgt_march_atlas atlas = {0};
    float *mask = NULL, *density = NULL;
    pgt_march_state *rec = NULL;
    uint32_t *words = NULL;
    pgt_backend backend;
    memset(&backend, 0, sizeof backend);
    int rc = PGT_EXIT_USAGE;
    pgt_cli_progress prog; /* a line every few seconds while the work runs (stderr) */
    if (pgt_cli_progress_start(&prog, verb)) return PGT_EXIT_USAGE;
    pgt_cli_progress_stagef(prog.progress, "reading %s", in_path);
    const double t0 = pgt_cli_now_ms();
    /* the march is one walker; the atlas decodes on every CPU */
    if (pgt_image_read_exr_threads(&img, in_path, pgt_cli_cpu_count(), &err) != PGT_OK ||
        pgt_march_atlas_create(&atlas, &img, in_path, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    {
        /* a step below half a float32 ulp of the largest texel coordinate moves nothing there:
         * millions of "inner" rows of a walker standing still */
        const uint32_t side = atlas.width > atlas.height ? atlas.width : atlas.height;
        const float least = (float)side * FLT_EPSILON;
        if (step < least) {
            pgt_cli_fail(verb,
                         "--step %g: below %g texels, the float32 resolution of texel "
                         "coordinates in this %u x %u atlas: the walker would not move",
                         (double)step, (double)least, atlas.width, atlas.height);
            goto done;
        }
    }
    if (mask_path &&
        pgt_cli_read_context(verb, "--mask", mask_path, "mask", atlas.width, atlas.height, &mask))
        goto done;
    opts.mask = mask;
    if (density_path && pgt_cli_read_context(verb, "--density", density_path, "density",
                                             atlas.width, atlas.height, &density))
        goto done;
    pgt_march_density dens = {density, atlas.width, atlas.height, seed, 0, 0};
    if (density) opts.condition = pgt_march_density_condition, opts.condition_ctx = &dens;
    pgt_march_state s;
    if (pgt_march_start(&atlas, ux, uy, dx, dy, &s, &err) != PGT_OK) {
        pgt_cli_fail(verb, "--from %g,%g --dir %g,%g: %s: %s", (double)ux, (double)uy, (double)dx,
                     (double)dy, in_path, err.message);
        goto done;
    }
    if (dump && write_dump(&dumped, &atlas, &img, &stage)) goto done;
    if (kind != PGT_BACKEND_CPU)
        pgt_cli_progress_stagef(prog.progress, "opening the %s backend",
                                pgt_backend_kind_name(kind));
    if (pgt_backend_open(&backend, kind, device, 0, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    /* the steps run in chunks on the backend, each recording its states and event words */
    const uint32_t chunk = steps < MARCH_CHUNK_STEPS ? steps : MARCH_CHUNK_STEPS;
    rec = malloc((size_t)chunk * sizeof(*rec));
    words = malloc((size_t)chunk * sizeof(*words));
    if (!rec || !words) {
        pgt_cli_fail(verb, "out of memory");
        goto done;
    }
    const double t1 = pgt_cli_now_ms();

    char tmp[4400];
    const char *out_staged = pgt_cli_stage_add(&stage, out_path);
    FILE *f = pgt_cli_tmp_open(out_staged, tmp, sizeof tmp);
    if (!f) {
        pgt_cli_fail(verb, "cannot write %s: %s", out_path, strerror(errno));
        goto done;
    }
    uint32_t counts[4] = {0, 0, 0, 0}, done_steps = 0;
    pgt_march_stop why = PGT_MARCH_STOP_NONE;
    float p[3];
    pgt_march_position(&atlas, s.x, s.y, p);
    pgt_progress_stage(prog.progress, "marching and writing", steps, "steps");
    fprintf(f, "step,u,v,chart,x,y,z,event\n");
    if (with_start)
        fprintf(f, "0,%.9g,%.9g,%u,%.9g,%.9g,%.9g,start\n", (double)s.x, (double)s.y, s.chart,
                (double)p[0], (double)p[1], (double)p[2]);
    int stopped = 0;
    for (uint32_t k0 = 0; k0 < steps && !stopped; k0 += chunk) {
        const uint32_t n = steps - k0 < chunk ? steps - k0 : chunk;
        if (pgt_backend_march(&backend, &atlas, &opts, step, n, 1, &s, rec, words, NULL, NULL,
                              &err) != PGT_OK) {
            pgt_cli_fail(verb, "%s", err.message);
            fclose(f);
            remove(tmp);
            goto done;
        }
        for (uint32_t j = 0; j < n; ++j) {
            const uint32_t k = k0 + j + 1, e = PGT_MARCH_EVENT_OF(words[j]);
            if (!pgt_backend_march_record_valid(&atlas, &rec[j], words[j])) {
                pgt_cli_fail(verb,
                             "%s returned step %u as no step of the reference could end (event "
                             "word 0x%x, at (%g, %g) in chart %u): a backend fault (pgt diff "
                             "march --backend %s checks the backend); nothing written",
                             backend.name, k, words[j], (double)rec[j].x, (double)rec[j].y,
                             rec[j].chart, pgt_backend_kind_name(kind));
                fclose(f);
                remove(tmp);
                rc = PGT_EXIT_FAIL;
                goto done;
            }
            counts[e]++;
            pgt_march_position(&atlas, rec[j].x, rec[j].y, p);
            fprintf(f, "%u,%.9g,%.9g,%u,%.9g,%.9g,%.9g,%s\n", k, (double)rec[j].x, (double)rec[j].y,
                    rec[j].chart, (double)p[0], (double)p[1], (double)p[2],
                    pgt_march_event_name((pgt_march_event)e));
            if (e == PGT_MARCH_STOP) {
                why = (pgt_march_stop)PGT_MARCH_STOP_OF(words[j]);
                stopped = 1;
                break;
            }
            done_steps = k;
        }
        pgt_progress_raise(prog.progress, k0 + n);
    }
    if (pgt_cli_table_close(f, tmp, out_staged, verb) || pgt_cli_stage_commit(&stage, verb))
        goto done;
    const double t2 = pgt_cli_now_ms();
    printf("march: %s (%u x %u texels, %u charts): %u of %u steps of %g texels from (%g, %g): "
           "%u inner, %u jump, %u search",
           in_path, atlas.width, atlas.height, atlas.chart_count, done_steps, steps, (double)step,
           (double)ux, (double)uy, counts[PGT_MARCH_INNER], counts[PGT_MARCH_JUMP],
           counts[PGT_MARCH_SEARCH]);
    if (why != PGT_MARCH_STOP_NONE)
        printf(", stopped at step %u (%s)", done_steps + 1, pgt_march_stop_name(why));
    if (kind != PGT_BACKEND_CPU) printf(", on %s", backend.name);
    printf(" -> %s (read %.1f ms, march+write %.1f ms)\n", out_path, t1 - t0, t2 - t1);
    rc = PGT_EXIT_OK;
done:
    pgt_cli_progress_stop(&prog);
    pgt_cli_stage_abort(&stage);
    pgt_backend_close(&backend);
    free(rec);
    free(words);
    free(mask);
    free(density);
    pgt_march_atlas_destroy(&atlas);
    pgt_image_destroy(&img);
    return rc;
}

/* ---- pgt bench march ------------------------------------------------------------------------ */

static const char *bench_march_usage =
    "usage: pgt bench march [--out FILE] [--meshes LIST] [--add LIST] [--shared DIR]\n"
    "                       [--threads LIST] [--walkers W] [--steps N] [--step S] [--res R]\n"
    "                       [--repeat R] [--position LIST] [--backends LIST] [--device N]\n"
    "                       [--quick]\n"
    "\n"
    "Marching steps per second per core (the issue's target: >= 20 million) on the atlases of\n"
    "the given meshes, built in memory with pgt atlas's defaults. W walkers start at seeded\n"
    "random inner texels and headings (pgt_march_random_starts, seed 1; march.h gives the\n"
    "formula) and march N steps of S texels each (every step resolves the destination and\n"
    "jumps when needed; in the position rows it also fetches the 3D position); the walkers are\n"
    "split over the threads (each marches its own). One CSV row per mesh x thread count x\n"
    "position setting, and one per mesh and GPU backend asked for, headed by machine, commit\n"
    "and date.\n"
    "\n"
    "  --out FILE      CSV to write (default results/march.csv; temporary file + rename)\n"
    "  --meshes LIST   comma-separated: a generated default dataset (pgt_datasets --list) or a\n"
    "                  file name in the shared mesh folder (default: cube_sphere_8 and every\n"
    "                  mesh of the shared folder that has UVs); a name with a '/' is a file\n"
    "                  anywhere, shown in the CSV by its file name\n"
    "  --add LIST      more meshes after those (scripts/main.sh adds the MeshLab Voronoi\n"
    "                  atlases of mountain and nefertiti-lowres, *_voronoi.obj)\n"
    "  --shared DIR    shared mesh folder (default ../shared/datasets/meshes beside the repo)\n"
    "  --threads LIST  comma-separated thread counts (default 1,2)\n"
    "  --walkers W     walkers, 1 to 1048576 (default 16384)\n"
    "  --steps N       steps per walker, 1 to 100000 (default 1000)\n"
    "  --step S        step length in texels (default 2)\n"
    "  --res R         atlas side in texels (default 1024)\n"
    "  --repeat R      timed runs after one warm-up, 1 to 1000 (default 5)\n"
    "  --position LIST no, yes or no,yes (default): rows without and with pgt_march_position\n"
    "                  after each step (a profile of one of them needs only that one)\n"
    "  --backends LIST GPU backends to time after ours: cl, vk, both (cl,vk) or none (default:\n"
    "                  none; here PoCL and lavapipe run on the CPU cores, which says nothing\n"
    "                  about a GPU). Their rows march the same walkers in one pgt_backend_march\n"
    "                  call (atlas view and walkers up, the steps, states down; median_ms) with\n"
    "                  the kernels' device time beside (device_median_ms), position no, and\n"
    "                  must take the same steps as ours (exit 1 otherwise); the device must open\n"
    "  --device N      device index of each GPU API (see pgt devices; default 0)\n"
    "  --quick         small and fast: 2048 walkers x 200 steps, R = 1\n";

#define BENCH_MARCH_MAX_LIST 32

/* Walker i's start: position and heading from the SoA arrays x[0..3], chart c; the rest zero. */
static pgt_march_state start_state(float *const x[4], const uint32_t *c, uint32_t i) {
    const pgt_march_state w = {x[0][i], x[1][i], x[2][i], x[3][i], c[i], 0u, 0.0f, 0.0f, 0u};
    return w;
}

/* Declared in cli.h by the lead's wiring of `pgt bench march` (cmd_bench.c dispatches to it). */
/* CPU time of the whole process (every thread), in ms. */
static double process_cpu_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

int pgt_cmd_bench_march(int argc, char **argv) {
    static const char *const default_out = "results/march.csv";
    const char *verb = "bench", *out_path = default_out, *shared_dir = PGT_CLI_SHARED_MESH_DIR;
    uint32_t threads[BENCH_MARCH_MAX_LIST] = {1, 2}, n_threads = 2, walkers = 16384, steps = 1000,
             res = 1024, repeat = 5;
    float step = 2.0f;
    const char *meshes[BENCH_MARCH_MAX_LIST];
    uint32_t n_meshes = 0;
    char list_buf[4096], add_buf[4096];
    const char *add = NULL;
    int quick = 0, have_walkers = 0, have_steps = 0, have_repeat = 0, positions[2] = {1, 1};
    int gpu_asked[2] = {0, 0};
    uint32_t device = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(bench_march_usage, stdout);
            return PGT_EXIT_OK;
        } else if (!strcmp(a, "--out") || !strcmp(a, "-o")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--shared")) {
            if (!(shared_dir = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--meshes")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            n_meshes = 0;
            if (pgt_cli_name_list(verb, a, v, list_buf, sizeof list_buf, meshes,
                                  BENCH_MARCH_MAX_LIST, &n_meshes))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--add")) {
            if (!(add = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            if (pgt_cli_uint_list(verb, a, v, 1, 256, threads, BENCH_MARCH_MAX_LIST, &n_threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--walkers")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 1u << 20, &walkers))
                return PGT_EXIT_USAGE;
            have_walkers = 1;
        } else if (!strcmp(a, "--steps")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 100000, &steps))
                return PGT_EXIT_USAGE;
            have_steps = 1;
        } else if (!strcmp(a, "--step")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_float(verb, a, v, 0.0f, PGT_MARCH_MAX_LENGTH, &step))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--res")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, PGT_ATLAS_MIN_RES, PGT_ATLAS_MAX_RES, &res))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--repeat")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 1000, &repeat))
                return PGT_EXIT_USAGE;
            have_repeat = 1;
        } else if (!strcmp(a, "--position")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            if (!strcmp(v, "no"))
                positions[0] = 1, positions[1] = 0;
            else if (!strcmp(v, "yes"))
                positions[0] = 0, positions[1] = 1;
            else if (!strcmp(v, "no,yes") || !strcmp(v, "yes,no"))
                positions[0] = positions[1] = 1;
            else
                return pgt_cli_fail(verb, "--position: '%s' is not no, yes or no,yes", v);
        } else if (!strcmp(a, "--backends")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_backend_parse_list(verb, v, gpu_asked))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--device")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 0, 1024, &device))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--quick")) {
            quick = 1;
        } else {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt bench march --help)", a);
        }
    }
    if (quick) {
        if (!have_walkers) walkers = 2048;
        if (!have_steps) steps = 200;
        if (!have_repeat) repeat = 1;
    }
    if (!n_meshes) {
        meshes[n_meshes++] = "cube_sphere_8";
        for (uint32_t k = 0; k < pgt_cli_shared_mesh_count && n_meshes < BENCH_MARCH_MAX_LIST; ++k)
            meshes[n_meshes++] = pgt_cli_shared_meshes[k]; /* those without UVs are skipped */
    }
    if (add && pgt_cli_name_list(verb, "--add", add, add_buf, sizeof add_buf, meshes,
                                 BENCH_MARCH_MAX_LIST, &n_meshes))
        return PGT_EXIT_USAGE;
    if (pgt_cli_refuse_named_inputs(verb, meshes, n_meshes, shared_dir, "--out", out_path) ||
        pgt_cli_quick_out(verb, quick, out_path, default_out))
        return PGT_EXIT_USAGE;
    pgt_backend gpu[2]; /* asked for: must open */
    if (pgt_backend_open_asked(verb, gpu, gpu_asked, device, 1)) return PGT_EXIT_USAGE;

    char tmp[4200];
    FILE *csv = pgt_cli_table_open(out_path,
                                   "pgt bench march: marching steps per second per core (paper "
                                   "000, sec. 5; target >= 20 million steps/s per core)",
                                   tmp, sizeof tmp);
    if (!csv) {
        pgt_backend_close(&gpu[0]), pgt_backend_close(&gpu[1]);
        return pgt_cli_fail(verb, "cannot write %s: %s", tmp, strerror(errno));
    }
    fprintf(csv,
            "# runs: 1 warm-up + %u timed per measurement; ms are medians (best beside); a step "
            "is one pgt_march_step with the paper's defaults (best pointer, the atlas's rot); "
            "walkers that stop (dead ends) stop counting\n",
            repeat);
    fprintf(csv,
            "# atlas: pgt_atlas_build defaults at %u x %u; walkers start at seeded random "
            "inner texels and headings (pgt_march_random_starts, seed 1)\n",
            res, res);
    fprintf(csv, "# msteps_per_s_per_core: wall-clock steps/s over the thread count; "
                 "msteps_per_cpu_s: steps per second of process CPU time (all threads), the "
                 "per-core rate without the time other programs take from this one on a shared "
                 "machine (cache and memory contention still count)\n");
    fprintf(csv, "# position: no = pgt_march_step only (the marching rule: destination, cases "
                 "1-4, jumps); yes = each step followed by pgt_march_position (the 3D point a "
                 "grammar would place geometry at)\n");
    fprintf(csv, "# backend: cpu = ours (pgt_march_batch on `threads` threads); cl, vk = one "
                 "pgt_backend_march call per run (the atlas view and walkers up, the steps, the "
                 "states down: median_ms, best_ms, msteps_per_s; the kernels' device time: "
                 "device_median_ms), position no, the same walkers and steps as ours\n");
    for (int g = 0; g < 2; ++g)
        if (gpu[g].kind != PGT_BACKEND_CPU)
            fprintf(csv, "# %s: %s\n", g ? "vk" : "cl", gpu[g].name);
    fprintf(csv, "mesh,faces,charts,resolution,step_texels,walkers,steps_per_walker,threads,"
                 "position,steps,jumps_per_1000_steps,stopped_walkers,median_ms,best_ms,"
                 "msteps_per_s,msteps_per_s_per_core,cpu_median_ms,msteps_per_cpu_s,backend,"
                 "device_median_ms\n");

    const size_t n = walkers;
    float *x0 = malloc(n * 4 * sizeof(float)), *x = malloc(n * 4 * sizeof(float));
    uint32_t *c0 = malloc(n * sizeof(uint32_t)), *c = malloc(n * sizeof(uint32_t)),
             *taken = malloc(n * sizeof(uint32_t));
    double *times = malloc(repeat * sizeof(double)), *cpu = malloc(repeat * sizeof(double)),
           *sums = malloc(n * sizeof(double));
    pgt_march_state *gs = malloc(n * sizeof(pgt_march_state));
    uint32_t *gtaken = malloc(n * sizeof(uint32_t));
    int failures = 0, disagree = 0;
    if (!x0 || !x || !c0 || !c || !taken || !times || !cpu || !sums || !gs || !gtaken) {
        fclose(csv);
        remove(tmp);
        free(x0), free(x), free(c0), free(c), free(taken), free(times), free(cpu), free(sums);
        free(gs), free(gtaken);
        pgt_backend_close(&gpu[0]), pgt_backend_close(&gpu[1]);
        return pgt_cli_fail(verb, "out of memory");
    }
    for (uint32_t mi = 0; mi < n_meshes; ++mi) {
        pgt_mesh m = {0};
        pgt_mesh_origin origin; /* a vertex error names its line */
        pgt_error err = {0};
        if (pgt_cli_load_named_origin(meshes[mi], shared_dir, &m, &origin, &err) != PGT_OK) {
            pgt_cli_skip_mesh("bench march", meshes[mi], err.message);
            failures++;
            continue;
        }
        if (!m.uvs) {
            pgt_cli_skip_mesh("bench march", meshes[mi], "no UVs");
            pgt_mesh_destroy(&m);
            pgt_mesh_origin_destroy(&origin);
            continue;
        }
        pgt_image img = {0};
        pgt_atlas_options ao = {0};
        ao.width = ao.height = res;
        ao.threads = pgt_cli_cpu_count();
        ao.what = meshes[mi];
        ao.origin = &origin;
        pgt_atlas_stats st;
        pgt_march_atlas a = {0};
        const pgt_result built = pgt_atlas_build(&img, &m, &ao, &st, &err);
        pgt_mesh_origin_destroy(&origin);
        if (built != PGT_OK || pgt_march_atlas_create(&a, &img, meshes[mi], &err) != PGT_OK) {
            pgt_cli_skip_mesh("bench march", meshes[mi], err.message);
            failures++;
            pgt_image_destroy(&img);
            pgt_mesh_destroy(&m);
            continue;
        }
        float *const s0[4] = {x0, x0 + n, x0 + 2 * n, x0 + 3 * n};
        float *const s[4] = {x, x + n, x + 2 * n, x + 3 * n};
        if (pgt_march_random_starts(&a, 1, walkers, s0[0], s0[1], s0[2], s0[3], c0)) {
            fprintf(stderr, "pgt bench march: skipping %s: no inner texel found\n", meshes[mi]);
            failures++;
            goto next;
        }
        /* jumps per 1000 steps, from an untimed pass over (up to) 1024 walkers */
        uint64_t jumps = 0, counted = 0;
        for (uint32_t i = 0; i < walkers && i < 1024u; ++i) {
            pgt_march_state ws = start_state(s0, c0, i);
            for (uint32_t k = 0; k < steps; ++k) {
                pgt_march_info info;
                if (pgt_march_step(&a, NULL, &ws, step, 0.0f, &info) == PGT_MARCH_STOP) break;
                jumps += info.jumps, counted++;
            }
        }
        const double jpk = counted ? 1000.0 * (double)jumps / (double)counted : 0.0;
        for (uint32_t ti = 0; ti < n_threads; ++ti)
            for (int with_pos = 0; with_pos < 2; ++with_pos) {
                if (!positions[with_pos]) continue;
                uint64_t total = 0;
                uint32_t stopped = 0;
                for (uint32_t r = 0; r <= repeat; ++r) {
                    memcpy(x, x0, n * 4 * sizeof(float));
                    memcpy(c, c0, n * sizeof(uint32_t));
                    const double t0 = pgt_cli_now_ms(), c0_ms = process_cpu_ms();
                    pgt_march_batch(&a, NULL, step, steps, walkers, s[0], s[1], s[2], s[3], c,
                                    threads[ti], taken, with_pos ? sums : NULL);
                    const double dt = pgt_cli_now_ms() - t0, dc = process_cpu_ms() - c0_ms;
                    if (r > 0) times[r - 1] = dt, cpu[r - 1] = dc; /* run 0: the warm-up */
                }
                for (uint32_t i = 0; i < walkers; ++i)
                    total += taken[i], stopped += taken[i] < steps;
                const double med = pgt_cli_median(times, repeat);
                const double best = pgt_cli_min(times, repeat),
                             cpu_med = pgt_cli_median(cpu, repeat);
                const double msps = (double)total / (med * 1e-3) / 1e6;
                const double per_cpu = cpu_med > 0.0 ? (double)total / (cpu_med * 1e-3) / 1e6 : 0.0;
                pgt_cli_csv_field(csv, pgt_cli_mesh_label(meshes[mi]));
                fprintf(
                    csv,
                    ",%u,%u,%u,%g,%u,%u,%u,%s,%llu,%.2f,%u,%.3f,%.3f,%.2f,%.2f,%.3f,%.2f,cpu,\n",
                    m.face_count, st.charts, res, (double)step, walkers, steps, threads[ti],
                    with_pos ? "yes" : "no", (unsigned long long)total, jpk, stopped, med, best,
                    msps, msps / threads[ti], cpu_med, per_cpu);
                fprintf(stderr,
                        "pgt bench march: %s (%u charts) %u thread%s%s: %.2f M steps/s (%.2f per "
                        "core; %.2f per CPU-second), %.1f jumps per 1000 steps\n",
                        pgt_cli_mesh_label(meshes[mi]), st.charts, threads[ti],
                        threads[ti] > 1 ? "s" : "", with_pos ? " +position" : "", msps,
                        msps / threads[ti], per_cpu, jpk);
            }
        /* The GPU backends march the same walkers; x, c and taken hold ours after the last run. */
        for (int g = 0; g < 2; ++g) {
            if (gpu[g].kind == PGT_BACKEND_CPU) continue;
            const char *bn = pgt_backend_kind_name(gpu[g].kind);
            pgt_error err = {0};
            for (uint32_t r = 0; r <= repeat; ++r) {
                for (uint32_t i = 0; i < walkers; ++i) gs[i] = start_state(s0, c0, i);
                pgt_gpu_times gt;
                const double t0 = pgt_cli_now_ms();
                if (pgt_backend_march(&gpu[g], &a, NULL, step, steps, walkers, gs, NULL, NULL,
                                      gtaken, &gt, &err) != PGT_OK) {
                    pgt_cli_skip_mesh("bench march", meshes[mi], err.message);
                    failures++;
                    break;
                }
                if (r > 0) times[r - 1] = pgt_cli_now_ms() - t0, cpu[r - 1] = gt.device_ms;
            }
            if (err.message[0]) continue;
            /* the same steps as ours, walker by walker, to the bit (pgt diff march checks each) */
            uint64_t total = 0;
            uint32_t stopped = 0, differ = 0;
            for (uint32_t i = 0; i < walkers; ++i) {
                total += gtaken[i], stopped += gtaken[i] < steps;
                differ += gtaken[i] != taken[i] || gs[i].chart != c[i] ||
                          memcmp(&gs[i].x, &s[0][i], sizeof(float)) ||
                          memcmp(&gs[i].y, &s[1][i], sizeof(float));
            }
            if (differ) {
                fprintf(stderr,
                        "pgt bench march: %s: %u of %u walkers on %s end elsewhere or after other "
                        "step counts than ours (see pgt diff march --backend %s)\n",
                        pgt_cli_mesh_label(meshes[mi]), differ, walkers, gpu[g].name, bn);
                disagree++;
            }
            const double med = pgt_cli_median(times, repeat), best = pgt_cli_min(times, repeat);
            const double dev = pgt_cli_median(cpu, repeat);
            const double msps = (double)total / (med * 1e-3) / 1e6;
            pgt_cli_csv_field(csv, pgt_cli_mesh_label(meshes[mi]));
            fprintf(csv, ",%u,%u,%u,%g,%u,%u,,no,%llu,%.2f,%u,%.3f,%.3f,%.2f,,,,%s,%.3f\n",
                    m.face_count, st.charts, res, (double)step, walkers, steps,
                    (unsigned long long)total, jpk, stopped, med, best, msps, bn, dev);
            fprintf(stderr,
                    "pgt bench march: %s (%u charts) %s: %.2f M steps/s (call), device %.1f ms "
                    "of %.1f\n",
                    pgt_cli_mesh_label(meshes[mi]), st.charts, gpu[g].name, msps, dev, med);
        }
    next:
        pgt_march_atlas_destroy(&a);
        pgt_image_destroy(&img);
        pgt_mesh_destroy(&m);
    }
    free(x0), free(x), free(c0), free(c), free(taken), free(times), free(cpu), free(sums);
    free(gs), free(gtaken);
    pgt_backend_close(&gpu[0]), pgt_backend_close(&gpu[1]);
    if (pgt_cli_bench_close(csv, tmp, out_path, verb, failures)) return PGT_EXIT_USAGE;
    if (!failures) fprintf(stderr, "pgt bench march: wrote %s\n", out_path);
    /* errors while working (cli.h); a backend that marched elsewhere: the work found a problem */
    return failures ? PGT_EXIT_USAGE : disagree ? PGT_EXIT_FAIL : PGT_EXIT_OK;
}
