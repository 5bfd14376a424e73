/* pgt facade: per-pixel procedural facades of a city (paper 003; ref_cpu/src/facade.c), one ray
 * per pixel, with the explicit twin as PLY and the Embree cross-check (facade_embree.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "facade_embree.h"
#include "facade_quads.h"
#include "facade_scene.h"
#include "pgt/facade.h"
#include "pgt/image.h"
#include "pgt/parallel.h"
#include "png_io.h"
#include "progress_line.h"

/* The grammar of --city when --grammar is not given. */
#define PGT_FACADE_DEFAULT_GRAMMAR PGT_SOURCE_DIR "/grammars/facade.grammar"
/* Most timed frames of --frames. */
#define FACADE_MAX_FRAMES 1000u
/* Most buildings of --city (pgt_gen_city's limit). */
#define PGT_FACADE_MAX_CITY (1u << 22)

/* Channels of the frame's EXR (write_exr). */
#define FACADE_EXR_CHANNELS 10u

static const char *facade_usage =
    "usage: pgt facade (--city N | --scene FILE | --mesh MESH.obj) -o FRAME.exr [--width W]\n"
    "                  [--height H]\n"
    "                  [--camera EYEx,EYEy,EYEz,ATx,ATy,ATz,UPx,UPy,UPz,FOV] [--png FRAME.png]\n"
    "                  [--threads N] [--explicit OUT.ply] [--embree-check] [--grammar FILE]\n"
    "                  [--seed S] [--light X,Y,Z] [--save-scene FILE] [--frames F]\n"
    "                  [--embree-mode packets|streams] [--shadows] [--single-rays]\n"
    "                  [--detail geometry|flat|normal|relief|lod] [--max-triangles N]\n"
    "\n"
    "Renders building facades without generating geometry (paper 003): every facade's coverage\n"
    "polygon (sec. 5.3) selects the pixels whose rays develop its split grammar along the ray\n"
    "(Algorithm 1, sec. 6.1) down to the terminals' rectangles (sec. 6.2.1); one ray per pixel,\n"
    "Lambert shading under a point light plus ambient 0.25.\n"
    "\n"
    "  --city N        a generated city of N buildings (1 to 4194304; pgt_gen_city: grid\n"
    "                  footprints, random floors, widths, protrusions, colours; about 4\n"
    "                  facades per building) with --grammar and --seed\n"
    "  --scene FILE    a scene file (harness/README.md, 'Facade scene files': 'grammar NAME\n"
    "                  PATH' and 'building NAME BASE HEIGHT SEED RRGGBB [P=V ...] : X0 Z0 ...')\n"
    "  --mesh F.obj    facades on a generic quad mesh (sec. 10; harness/README.md, 'Quad meshes\n"
    "                  for facades'): an OBJ of quads whose vertices have a UV (their place in\n"
    "                  facade space, metres) and a normal; every quad is a window of one facade\n"
    "                  of --grammar with --seed (pgt_datasets tower writes one)\n"
    "  -o FRAME.exr    the frame as OpenEXR (float channels R G B depth terminal N.x N.y N.z\n"
    "                  facade developed: linear colour, distance along the ray (inf on a miss),\n"
    "                  terminal kind 0 miss 1 wall 2 window 3 door 4 ledge 5 balcony 6 mesh\n"
    "                  (a geometry-image terminal) 7 roof, world\n"
    "                  normal facing the camera, facade index (-1 on a miss), nodes developed\n"
    "                  for the pixel); temporary file, then renamed\n"
    "  --width W       frame width, 1 to 16384 (default 1280)\n"
    "  --height H      frame height, 1 to 16384 (default 720)\n"
    "  --camera ...    eye, look-at point, up vector (x,y,z each) and the vertical field of\n"
    "                  view in degrees, in (0, 180): 10 numbers. Default: an aerial view of the\n"
    "                  whole scene: the centre of its bounding box seen from azimuth 30 degrees\n"
    "                  (0 = from +z, turning toward +x) and elevation 35, at the distance where\n"
    "                  the bounding sphere fills the 45 degree field of view (the horizontal one\n"
    "                  when taller than wide); up +y. The camera used is printed as a --camera\n"
    "                  value\n"
    "  --png F.png     also the colour as an 8-bit sRGB PNG\n"
    "  --threads N     threads, 1 to 256 (default: the number of CPUs; the frame's bytes do\n"
    "                  not depend on it)\n"
    "  --explicit F    the explicit twin (every terminal of every facade as triangles) as\n"
    "                  binary little-endian PLY: vertex x y z, face vertex_indices facade node\n"
    "                  kind surface (uint)\n";
static const char *facade_usage_twin =
    "  --max-triangles N  the explicit twin's limit, 1 to 536870912: more fails (exit 2)\n"
    "                  before its arrays outgrow it. Default: what fits in 3/4 of the memory\n"
    "                  available at start at 52 bytes a triangle, 252 with --embree-check\n"
    "                  (Embree's scene of it): a grammar that instantiates billions of\n"
    "                  terminals fails with this error instead of exhausting the memory\n"
    "                  (the environment variable PGT_MEMORY_AVAILABLE, in bytes, replaces\n"
    "                  the memory read from /proc/meminfo and the cgroup's limit)\n"
    "  --embree-check  traces the same rays with Embree on the explicit twin (same threads)\n"
    "                  and compares per pixel: both miss, or the same (facade, node, kind,\n"
    "                  surface) within a relative distance of 1e-4 = agree; both hitting\n"
    "                  within 1e-4 but naming different rectangles, ours passing within\n"
    "                  1e-5 t of Embree's hit point = a tie (coincident faces); other\n"
    "                  disagreements within 1e-4 t of a rectangle's edge are counted apart\n"
    "                  (at grazing angles, distances also within 4 float epsilons of the\n"
    "                  coordinates along the surface's normal; and ours' hit on an edge\n"
    "                  between its rectangle's triangles when Embree's ray went on past: a\n"
    "                  crack, Embree not being watertight). The compared rays are traced once\n"
    "                  more without Embree's coherent flag, with which it missed hits near\n"
    "                  the eye. Prints agreement, ties, max distance error, Mrays/s (ours\n"
    "                  with hits only, the same work as Embree's rays, and shaded) and bytes\n"
    "                  of both; exit 1 when a disagreement is neither a tie nor near an edge,\n"
    "                  or agreement with the ties is below 99.99 %\n";
static const char *facade_usage2 =
    "  --grammar FILE  the grammar of --city or --mesh (default grammars/facade.grammar)\n"
    "  --seed S        the seed of --city or --mesh (default 1)\n"
    "  --light X,Y,Z   the point light (default: above the scene, 2 bounding radii up)\n"
    "  --shadows       self-shadowing (sec. 6.4): a shadow ray toward the light per hit\n"
    "  --detail D      terminal detail (sec. 6.3, 7): geometry (the default: procedural\n"
    "                  geometry, flat-shaded), flat (LOD 0: thickness 0, a textured plane),\n"
    "                  normal (normal mapping), relief (relief mapping, self-shadowed with\n"
    "                  --shadows), lod (the four levels by distance, linear transitions: relief\n"
    "                  to 10-20 m, normal mapping to 20-40 m, thickness 150-300 m).\n"
    "                  --embree-check takes geometry or normal only\n"
    "  --save-scene F  writes the scene (of --city or --scene; not --mesh) as a scene file\n"
    "  --frames F      renders (and, with --embree-check, traces) F times, 1 to 1000, and\n"
    "                  reports the median (default 1)\n"
    "  --single-rays   develops every ray alone (Algorithm 1 as written) instead of in\n"
    "                  packets of up to 64 rays of a 16x16 tile through one facade (the\n"
    "                  default, faster): the same frame to the bit\n"
    "  --embree-mode M packets (rtcIntersect16 of 4x4 pixel tiles, the default; the two are\n"
    "                  within ~15 % of each other here) or streams (rtcIntersect1M of a\n"
    "                  tile row, coherent)\n"
    "\n"
    "Prints buildings, facades, pixels, ms per frame (coverage, rays), Mrays/s, nodes developed\n"
    "per ray (mean over the rays that entered a facade volume) and the bytes of the procedural\n"
    "representation (buildings, footprints, params, grammars; the derived facade array apart).\n"
    "A progress line on stderr every 5 s of work (PGT_PROGRESS_SECONDS: the period, 0: none).\n"
    "Exit 0 on success, 1 when the Embree check fails, 2 on a bad flag, value or input file\n"
    "(naming the flag or FILE:LINE) or a grammar error while rendering.\n";

typedef struct facade_args {
    const char *scene_path, *out_path, *png_path, *explicit_path, *grammar_path, *save_path;
    const char *mesh_path;
    const char *camera_text;
    uint32_t city, width, height, threads, seed, frames;
    uint32_t max_triangles; /* 0: from the memory available (pgt_facade_twin_max_triangles) */
    int embree_check, have_light, shadows, single_rays;
    uint32_t detail;
    pgt_facade_embree_mode mode;
    float light[3];
} facade_args;

/* The output files and their flags, in one order (checked against the inputs and each other). */
#define FACADE_OUTPUTS 4
static const char *const facade_output_flags[FACADE_OUTPUTS] = {"-o", "--png", "--explicit",
                                                                "--save-scene"};
static void facade_outputs(const facade_args *a, const char *outs[FACADE_OUTPUTS]) {
    outs[0] = a->out_path, outs[1] = a->png_path, outs[2] = a->explicit_path;
    outs[3] = a->save_path;
}

static int parse_args(int argc, char **argv, facade_args *a) {
    const char *verb = "facade", *v;
    memset(a, 0, sizeof *a);
    a->width = 1280, a->height = 720, a->threads = pgt_cli_cpu_count(), a->seed = 1;
    a->frames = 1, a->mode = PGT_FACADE_EMBREE_DEFAULT_MODE;
    int have_city = 0, have_seed = 0;
    for (int i = 1; i < argc; ++i) {
        const char *s = argv[i];
        if (!strcmp(s, "--help") || !strcmp(s, "-h")) {
            fputs(facade_usage, stdout);
            fputs(facade_usage_twin, stdout);
            fputs(facade_usage2, stdout);
            return -1;
        } else if (!strcmp(s, "--city")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, s, v, 1, PGT_FACADE_MAX_CITY, &a->city))
                return PGT_EXIT_USAGE;
            have_city = 1;
        } else if (!strcmp(s, "--scene")) {
            if (!(a->scene_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--mesh")) {
            if (!(a->mesh_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "-o") || !strcmp(s, "--output")) {
            if (!(a->out_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--png")) {
            if (!(a->png_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--explicit")) {
            if (!(a->explicit_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--max-triangles")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, s, v, 1, PGT_FACADE_MAX_TRIANGLES, &a->max_triangles))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--grammar")) {
            if (!(a->grammar_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--save-scene")) {
            if (!(a->save_path = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--camera")) {
            if (!(a->camera_text = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--width") || !strcmp(s, "--height")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, s, v, 1, PGT_IMAGE_MAX_SIDE,
                             s[2] == 'w' ? &a->width : &a->height))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, s, v, 1, PGT_MAX_THREADS, &a->threads))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--seed")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, s, v, 0, UINT32_MAX, &a->seed))
                return PGT_EXIT_USAGE;
            have_seed = 1;
        } else if (!strcmp(s, "--frames")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, s, v, 1, FACADE_MAX_FRAMES, &a->frames))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(s, "--light")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_floats(verb, s, v, 3, a->light))
                return PGT_EXIT_USAGE;
            a->have_light = 1;
        } else if (!strcmp(s, "--shadows")) {
            a->shadows = 1;
        } else if (!strcmp(s, "--single-rays")) {
            a->single_rays = 1;
        } else if (!strcmp(s, "--detail")) {
            static const char *const names[] = {"geometry", "flat", "normal", "relief", "lod"};
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            uint32_t d = 0;
            while (d < 5 && strcmp(v, names[d])) ++d;
            if (d == 5)
                return pgt_cli_fail(
                    verb, "--detail %s: expected geometry, flat, normal, relief or lod", v);
            a->detail = d;
        } else if (!strcmp(s, "--embree-check")) {
            a->embree_check = 1;
        } else if (!strcmp(s, "--embree-mode")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
            if (!strcmp(v, "packets"))
                a->mode = PGT_FACADE_EMBREE_PACKETS;
            else if (!strcmp(v, "streams"))
                a->mode = PGT_FACADE_EMBREE_STREAMS;
            else
                return pgt_cli_fail(verb, "--embree-mode: expected packets or streams, got '%s'",
                                    v);
        } else {
            return pgt_cli_fail(verb, "unknown %s '%s' (see pgt facade --help)",
                                s[0] == '-' ? "flag" : "argument", s);
        }
    }
    if (have_city + !!a->scene_path + !!a->mesh_path != 1)
        return pgt_cli_fail(verb, "give exactly one of --city N, --scene FILE and --mesh MESH.obj");
    if (a->mesh_path && a->save_path)
        return pgt_cli_fail(verb, "--save-scene is for --city and --scene (a scene file holds "
                                  "footprints, not meshes)");
    if (a->scene_path && (a->grammar_path || have_seed))
        return pgt_cli_fail(verb, "--grammar and --seed are for --city and --mesh (a scene file "
                                  "names its grammars and seeds)");
    if (!a->out_path) return pgt_cli_fail(verb, "no output: give -o FRAME.exr");
    if (a->embree_check && a->detail != PGT_FACADE_DETAIL_GEOMETRY &&
        a->detail != PGT_FACADE_DETAIL_NORMAL)
        return pgt_cli_fail(verb, "--embree-check compares the procedural geometry: only with "
                                  "--detail geometry or normal (flat and lod thin it, relief "
                                  "moves the depth into the relief)");
    if (a->max_triangles && !a->explicit_path && !a->embree_check)
        return pgt_cli_fail(verb, "--max-triangles limits the explicit twin: only with --explicit "
                                  "or --embree-check");
    if (!pgt_cli_ends_with_ci(a->out_path, ".exr"))
        return pgt_cli_fail(verb, "-o %s: the frame is an .exr file", a->out_path);
    if (a->png_path && !pgt_cli_ends_with_ci(a->png_path, ".png"))
        return pgt_cli_fail(verb, "--png %s: expected a .png file", a->png_path);
    if (a->explicit_path && !pgt_cli_ends_with_ci(a->explicit_path, ".ply"))
        return pgt_cli_fail(verb, "--explicit %s: expected a .ply file", a->explicit_path);
    const char *outs[FACADE_OUTPUTS];
    const char *const *flags = facade_output_flags;
    facade_outputs(a, outs);
    const char *ins[3] = {a->scene_path, a->grammar_path, a->mesh_path};
    for (int o = 0; o < FACADE_OUTPUTS; ++o)
        for (int k = 0; k < 3; ++k)
            if (outs[o] && ins[k] && pgt_cli_same_file(outs[o], ins[k]))
                return pgt_cli_fail(verb, "%s %s is the input %s; pgt never overwrites an input",
                                    flags[o], outs[o], ins[k]);
    for (int o = 0; o < FACADE_OUTPUTS; ++o) /* one output would replace another */
        for (int k = 0; k < o; ++k)
            if (outs[o] && outs[k] && pgt_cli_same_output(outs[o], outs[k]))
                return pgt_cli_fail(verb, "%s %s is also %s's output", flags[o], outs[o], flags[k]);
    /* the frame's EXR must fit the image limit: said before the render, not after it */
    if ((uint64_t)a->width * a->height * FACADE_EXR_CHANNELS > PGT_IMAGE_MAX_VALUES)
        return pgt_cli_fail(verb,
                            "--width %u --height %u: the frame's %u EXR channels would hold %llu "
                            "values, more than the image limit of %u (%u pixels)",
                            a->width, a->height, FACADE_EXR_CHANNELS,
                            (unsigned long long)a->width * a->height * FACADE_EXR_CHANNELS,
                            PGT_IMAGE_MAX_VALUES, PGT_IMAGE_MAX_VALUES / FACADE_EXR_CHANNELS);
    if (pgt_cli_check_outputs(verb, outs, FACADE_OUTPUTS)) return PGT_EXIT_USAGE;
    if (!a->grammar_path) a->grammar_path = PGT_FACADE_DEFAULT_GRAMMAR;
    return 0;
}

/* Message of a PGT_FACADE_ERR_* set. */
static void ray_errors(uint32_t bits, char *buf, size_t size) {
    static const char *what[7] = {
        "the development stack was full (PGT_FACADE_MAX_DEPTH)",
        "a ray developed more than PGT_FACADE_NODE_BUDGET nodes (rules that never split?)",
        "an expression gave NaN or infinity",
        "a split has more than PGT_FACADE_MAX_PARTS parts",
        "an item a facade cannot hold (Marching, Branch, Bark, Leaves, split(z))",
        "Mesh(id) names no geometry image of the scene",
        "a terminal reaches outside the facade volume [-recess, protrusion]"};
    size_t n = 0;
    buf[0] = '\0';
    for (int b = 0; b < 7; ++b)
        if (bits & (1u << b))
            n += (size_t)snprintf(buf + n, n < size ? size - n : 0, "%s%s", n ? "; " : "", what[b]);
}

static pgt_result write_exr(const pgt_facade_frame *fr, const char *path, uint32_t threads,
                            pgt_error *err) {
    static const char *names[FACADE_EXR_CHANNELS] = {"R",   "G",   "B",   "depth",  "terminal",
                                                     "N.x", "N.y", "N.z", "facade", "developed"};
    pgt_image img;
    pgt_result r = pgt_image_create(&img, fr->width, fr->height, FACADE_EXR_CHANNELS, names, err);
    if (r != PGT_OK) return r;
    const size_t n = (size_t)fr->width * fr->height;
    float *p[FACADE_EXR_CHANNELS];
    for (uint32_t c = 0; c < FACADE_EXR_CHANNELS; ++c) p[c] = pgt_image_plane(&img, c);
    for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k)
            p[k][i] = fr->rgb[3u * i + k], p[5 + k][i] = fr->normal[3u * i + k];
        p[3][i] = fr->depth[i];
        p[4][i] = fr->terminal[i];
        p[8][i] = fr->facade[i] == PGT_NONE ? -1.0f : (float)fr->facade[i];
        p[9][i] = (float)fr->developed[i];
    }
    r = pgt_image_write_exr_threads(&img, path, threads, err);
    pgt_image_destroy(&img);
    return r;
}

static pgt_result write_png(const pgt_facade_frame *fr, const char *path, pgt_error *err) {
    const size_t n = (size_t)fr->width * fr->height;
    uint8_t *px = malloc(3u * n);
    if (!px) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "out of memory");
    for (size_t i = 0; i < 3u * n; ++i) px[i] = pgt_png_linear_to_srgb8(fr->rgb[i]);
    const pgt_result r = pgt_png_write(path, fr->width, fr->height, 3, px, err);
    free(px);
    return r;
}

int pgt_cmd_facade(int argc, char **argv) {
    const char *verb = "facade";
    facade_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc < 0 ? PGT_EXIT_OK : rc;
    rc = PGT_EXIT_USAGE;
    pgt_error err = {0};
    pgt_facade_file file;
    memset(&file, 0, sizeof file);
    pgt_facade_quads quads;
    memset(&quads, 0, sizeof quads);
    pgt_facade *facades = NULL;
    uint32_t facade_count = 0;
    pgt_facade_frame frame;
    memset(&frame, 0, sizeof frame);
    pgt_facade_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    pgt_facade_embree eb;
    memset(&eb, 0, sizeof eb);
    pgt_facade_embree_hits hits;
    memset(&hits, 0, sizeof hits);
    /* every output appears once all are written, none on failure (pgt_cli_stage) */
    pgt_cli_stage stage;
    stage.count = stage.dir_count = 0;
    pgt_cli_progress prog; /* a line every few seconds while the work runs (stderr) */
    if (pgt_cli_memory_env_check(verb) || pgt_cli_progress_start(&prog, verb))
        return PGT_EXIT_USAGE;
    pgt_progress *const pr = prog.progress;
    pgt_progress_stage(pr, "scene", 0, "");
    double *ms = calloc(2u * a.frames, sizeof(double));
    if (!ms) {
        pgt_cli_fail(verb, "out of memory");
        goto done;
    }

    /* camera flag first: a typo should not wait for a city */
    float cam_vals[10];
    if (a.camera_text) {
        if (pgt_cli_floats(verb, "--camera", a.camera_text, 10, cam_vals)) goto done;
    }

    /* the scene */
    const double t0 = pgt_cli_now_ms();
    const char *what = a.scene_path ? a.scene_path : (a.mesh_path ? a.mesh_path : "--city");
    if (a.mesh_path) {
        if (pgt_facade_quads_read_obj(&quads, a.mesh_path, &err) != PGT_OK ||
            pgt_facade_file_mesh(&file, a.grammar_path, a.seed, &quads, &err) != PGT_OK) {
            pgt_cli_fail(verb, "--mesh %s", err.message);
            goto done;
        }
    } else if (a.scene_path) {
        if (pgt_facade_file_read(&file, a.scene_path, &err) != PGT_OK) {
            pgt_cli_fail(verb, "%s", err.message);
            goto done;
        }
    } else if (pgt_facade_file_city(&file, a.grammar_path, a.city, a.seed, &err) != PGT_OK) {
        pgt_cli_fail(verb, "--city %u: %s", a.city, err.message);
        goto done;
    }
    { /* the grammar files a scene names are inputs too */
        const char *outs[FACADE_OUTPUTS];
        const char *const *flags = facade_output_flags;
        facade_outputs(&a, outs);
        for (uint32_t k = 0; k < file.grammar_count; ++k)
            for (int o = 0; o < FACADE_OUTPUTS; ++o)
                if (outs[o] && pgt_cli_same_file(outs[o], file.paths[k])) {
                    pgt_cli_fail(verb,
                                 "%s %s is the grammar %s of %s; pgt never overwrites an "
                                 "input",
                                 flags[o], outs[o], file.names[k], what);
                    goto done;
                }
    }
    const pgt_facade_scene *s = &file.scene;
    if (pgt_facade_scene_check(s, what, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    if (a.save_path) {
        char comment[256];
        if (a.scene_path)
            snprintf(comment, sizeof comment, "pgt facade: scene %s", a.scene_path);
        else
            snprintf(comment, sizeof comment, "pgt facade --city %u --seed %u (pgt_gen_city)",
                     a.city, a.seed);
        if (pgt_facade_file_write(pgt_cli_stage_add(&stage, a.save_path), a.save_path, s,
                                  (const char *const *)file.names, (const char *const *)file.paths,
                                  comment, &err) != PGT_OK) {
            pgt_cli_fail(verb, "--save-scene %s", err.message);
            goto done;
        }
    }
    if (a.mesh_path) {
        facades = malloc((quads.quad_count ? quads.quad_count : 1u) * sizeof *facades);
        if (!facades) {
            pgt_cli_fail(verb, "out of memory");
            goto done;
        }
        facade_count = quads.quad_count;
        if (pgt_facade_mesh_facades(facades, &quads, s, 0, 0.0f, 0.0f, &err) != PGT_OK) {
            pgt_cli_fail(verb, "%s: %s", what, err.message);
            goto done;
        }
    } else if (pgt_facade_prepare(s, &facades, &facade_count, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s: %s", what, err.message);
        goto done;
    }
    /* the mesh's bounding box for the default camera and light */
    float box_lo[3] = {INFINITY, INFINITY, INFINITY}, box_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < quads.vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            box_lo[k] = fminf(box_lo[k], quads.positions[3u * v + (uint32_t)k]);
            box_hi[k] = fmaxf(box_hi[k], quads.positions[3u * v + (uint32_t)k]);
        }
    const double t1 = pgt_cli_now_ms();

    /* camera and light */
    float eye[3], at[3], up[3], fov;
    if (a.camera_text) {
        memcpy(eye, cam_vals, sizeof eye);
        memcpy(at, cam_vals + 3, sizeof at);
        memcpy(up, cam_vals + 6, sizeof up);
        fov = cam_vals[9];
    } else if (a.mesh_path) {
        pgt_facade_box_view(box_lo, box_hi, a.width, a.height, eye, at, up, &fov);
    } else {
        pgt_facade_default_view(s, a.width, a.height, eye, at, up, &fov);
    }
    pgt_facade_camera cam;
    if (pgt_facade_camera_init(&cam, eye, at, up, fov, a.width, a.height, &err) != PGT_OK) {
        pgt_cli_fail(verb, "--camera %s: %s", a.camera_text ? a.camera_text : "(default)",
                     err.message);
        goto done;
    }
    printf("camera: --camera ");
    const float *cv[4] = {eye, at, up, &fov};
    for (int g = 0; g < 4; ++g)
        for (int k = 0; k < (g < 3 ? 3 : 1); ++k) {
            if (g || k) putchar(',');
            pgt_cli_print_float(cv[g][k]);
        }
    putchar('\n');
    pgt_facade_shading shading;
    memset(&shading, 0, sizeof shading);
    if (a.have_light)
        memcpy(shading.light, a.light, sizeof shading.light);
    else if (a.mesh_path)
        pgt_facade_box_light(box_lo, box_hi, shading.light);
    else
        pgt_facade_default_light(s, shading.light);
    shading.ambient = PGT_FACADE_DEFAULT_AMBIENT;
    shading.shadows = a.shadows;
    shading.single_rays = a.single_rays;
    shading.detail = a.detail;

    /* the frame(s) */
    if (pgt_facade_frame_create(&frame, a.width, a.height, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    pgt_facade_render_stats st, first;
    memset(&first, 0, sizeof first);
    double *cover = ms + a.frames;
    pgt_progress_stage(pr, "rendering", a.frames, "frames");
    for (uint32_t f = 0; f < a.frames; ++f) {
        if (pgt_facade_render(s, facades, facade_count, &cam, &shading, a.threads, &frame, &st,
                              &err) != PGT_OK) {
            pgt_cli_fail(verb, "%s: %s", what, err.message);
            goto done;
        }
        if (f == 0) first = st;
        ms[f] = st.ms_total;
        cover[f] = st.ms_cover;
        pgt_progress_add(pr, 1);
    }
    if (first.rays.errors) {
        char buf[600];
        ray_errors(first.rays.errors, buf, sizeof buf);
        const uint32_t fe = first.error_facade;
        char where[160] = "";
        if (fe < facade_count && a.mesh_path)
            snprintf(where, sizeof where, " on quad %u", facades[fe].edge);
        else if (fe < facade_count && file.building_lines)
            snprintf(where, sizeof where, " on building %u (line %u), footprint edge %u",
                     facades[fe].building, file.building_lines[facades[fe].building],
                     facades[fe].edge);
        else if (fe < facade_count)
            snprintf(where, sizeof where, " on building %u, footprint edge %u",
                     facades[fe].building, facades[fe].edge);
        /* the rays carry error bits only: the facade's development names the grammar's place */
        pgt_error why = {0};
        if (fe < facade_count && pgt_facade_explain(s, &facades[fe], fe, &why) != PGT_OK &&
            why.code != PGT_ERROR_LIMIT && why.code != PGT_ERROR_OUT_OF_MEMORY)
            pgt_cli_fail(verb, "%s: the grammar failed while rendering%s: %s (%s)", what, where,
                         buf, why.message);
        else
            pgt_cli_fail(verb, "%s: the grammar failed while rendering%s: %s", what, where, buf);
        goto done;
    }
    const double frame_ms = pgt_cli_median(ms, a.frames),
                 cover_ms = pgt_cli_median(cover, a.frames);
    pgt_progress_stage(pr, "writing the frame", 0, "");
    if (write_exr(&frame, pgt_cli_stage_add(&stage, a.out_path), a.threads, &err) != PGT_OK) {
        pgt_cli_fail(verb, "-o %s", err.message);
        goto done;
    }
    if (a.png_path && write_png(&frame, pgt_cli_stage_add(&stage, a.png_path), &err) != PGT_OK) {
        pgt_cli_fail(verb, "--png %s", err.message);
        goto done;
    }
    const uint64_t pixels = (uint64_t)a.width * a.height;
    const size_t proc_bytes = pgt_facade_scene_bytes(s);
    const size_t facade_bytes = (size_t)facade_count * sizeof(pgt_facade);
    if (a.mesh_path)
        printf("scene: mesh of %u quads, %u vertices: %u facades (%u visible), read %.0f ms\n",
               quads.quad_count, quads.vertex_count, facade_count, first.visible_facades, t1 - t0);
    else
        printf("scene: %u buildings, %u facades (%u visible), %s %.0f ms\n", s->building_count,
               facade_count, first.visible_facades, a.scene_path ? "read" : "generated", t1 - t0);
    printf("frame: %ux%u = %llu pixels, %u thread%s, %.3f ms per frame%s (coverage %.3f ms, "
           "rays %.3f ms), %.2f Mrays/s\n",
           a.width, a.height, (unsigned long long)pixels, a.threads, a.threads == 1 ? "" : "s",
           frame_ms, a.frames > 1 ? " (median)" : "", cover_ms, frame_ms - cover_ms,
           frame_ms > 0.0 ? (double)pixels / (frame_ms * 1e3) : 0.0);
    printf("development: %llu rays entered a facade volume, %.2f nodes developed per ray, %.2f "
           "terminal tests, %.2f rectangle tests; %llu pixel-facade pairs covered\n",
           (unsigned long long)first.rays.volume_hits,
           first.rays.volume_hits ? (double)first.rays.nodes / (double)first.rays.volume_hits : 0.0,
           first.rays.volume_hits ? (double)first.rays.terminals / (double)first.rays.volume_hits
                                  : 0.0,
           first.rays.volume_hits ? (double)first.rays.quads / (double)first.rays.volume_hits : 0.0,
           (unsigned long long)first.covered_pixels);
    printf("memory: procedural %zu bytes (buildings, footprints, params, grammars), facades "
           "array %zu bytes apart\n",
           proc_bytes, facade_bytes);

    /* the explicit twin */
    if (a.explicit_path || a.embree_check) {
        const double e0 = pgt_cli_now_ms();
        pgt_progress_stage(pr, "the explicit twin", 0, "");
        uint64_t avail = 0;
        const uint32_t max_t = a.max_triangles
                                   ? a.max_triangles
                                   : pgt_facade_twin_max_triangles(a.embree_check, &avail);
        const pgt_result xr =
            pgt_facade_explicit_limit(s, facades, facade_count, max_t, &mesh, &err);
        if (xr != PGT_OK) {
            char why[200] = "";
            if (xr == PGT_ERROR_LIMIT && a.max_triangles)
                snprintf(why, sizeof why, " (--max-triangles %u)", max_t);
            else if (xr == PGT_ERROR_LIMIT)
                pgt_facade_twin_limit_why(why, sizeof why, avail, a.embree_check);
            pgt_cli_fail(verb, "%s: %s: %s%s", a.explicit_path ? "--explicit" : "--embree-check",
                         what, err.message, why);
            goto done;
        }
        const double e1 = pgt_cli_now_ms();
        printf("explicit: %u triangles, %u vertices, %zu bytes (%.0fx the procedural), expanded "
               "in %.0f ms%s%s\n",
               mesh.triangle_count, mesh.vertex_count, pgt_facade_mesh_bytes(&mesh),
               (double)pgt_facade_mesh_bytes(&mesh) / (double)proc_bytes, e1 - e0,
               a.explicit_path ? " -> " : "", a.explicit_path ? a.explicit_path : "");
        if (a.explicit_path) pgt_progress_stage(pr, "writing the explicit twin", 0, "");
        if (a.explicit_path &&
            pgt_facade_mesh_write_ply(&mesh, pgt_cli_stage_add(&stage, a.explicit_path), &err) !=
                PGT_OK) {
            pgt_cli_fail(verb, "--explicit %s", err.message);
            goto done;
        }
    }
    /* the outputs are complete; --embree-check compares, and its FAIL keeps them */
    if (pgt_cli_stage_commit(&stage, verb)) goto done;
    rc = PGT_EXIT_OK;
    if (a.embree_check) {
        rc = PGT_EXIT_USAGE;
        if (pgt_facade_embree_create(&eb, &mesh, a.threads, pr, &err) != PGT_OK ||
            pgt_facade_embree_hits_create(&hits, a.width, a.height, &err) != PGT_OK) {
            pgt_cli_fail(verb, "--embree-check: %s", err.message);
            goto done;
        }
        pgt_progress_stage(pr, "Embree's rays", a.frames, "frames");
        for (uint32_t f = 0; f < a.frames; ++f) {
            if (pgt_facade_embree_trace(&eb, &cam, a.mode, &hits, &ms[f], &err) != PGT_OK) {
                pgt_cli_fail(verb, "--embree-check: %s", err.message);
                goto done;
            }
            pgt_progress_add(pr, 1);
        }
        pgt_progress_stage(pr, "the check", 0, "");
        const double trace_ms = pgt_cli_median(ms, a.frames);
        /* the hits the check compares: the same rays without the coherent flag, whose traversal
         * missed hits (PGT_FACADE_EMBREE_CHECK_RAYS) */
        if (pgt_facade_embree_trace(&eb, &cam, PGT_FACADE_EMBREE_CHECK_RAYS, &hits, NULL, &err) !=
            PGT_OK) {
            pgt_cli_fail(verb, "--embree-check: %s", err.message);
            goto done;
        }
        /* ours with hits only (what Embree's rays do: no shading), into the same frame: its hits
         * are those of the shaded frame (pgt_facade_shading.hits_only) */
        pgt_facade_shading bare = shading;
        bare.hits_only = 1;
        for (uint32_t f = 0; f < a.frames; ++f) {
            if (pgt_facade_render(s, facades, facade_count, &cam, &bare, a.threads, &frame, &st,
                                  &err) != PGT_OK) {
                pgt_cli_fail(verb, "%s: %s", what, err.message);
                goto done;
            }
            ms[f] = st.ms_total;
        }
        const double bare_ms = pgt_cli_median(ms, a.frames);
        pgt_facade_check chk;
        const int pass = pgt_facade_embree_compare(&mesh, &cam, &frame, &hits, &chk);
        pgt_cli_progress_stop(&prog); /* the report's pixel lines (stderr) come last */
        const size_t ours = proc_bytes, theirs = eb.embree_bytes + eb.buffer_bytes;
        printf("embree: BVH build %.0f ms (%u threads), trace %.3f ms (%s), %.2f Mrays/s; ours "
               "with hits only %.3f ms, %.2f Mrays/s (%.2fx Embree's), shaded %.2f Mrays/s "
               "(%.2fx); the check's rays traced again with the incoherent flag\n",
               eb.build_ms, eb.threads, trace_ms,
               a.mode == PGT_FACADE_EMBREE_PACKETS ? "rtcIntersect16 packets"
                                                   : "rtcIntersect1M streams",
               (double)pixels / (trace_ms * 1e3), bare_ms, (double)pixels / (bare_ms * 1e3),
               trace_ms / bare_ms, (double)pixels / (frame_ms * 1e3), trace_ms / frame_ms);
        printf("memory: ours %zu bytes, Embree %zu bytes (BVH %zu + vertex and index buffers "
               "%zu), Embree / ours %.0fx\n",
               ours, theirs, eb.embree_bytes, eb.buffer_bytes, (double)theirs / (double)ours);
        printf("check: agreement %.4f %% of %llu rays (%llu both miss), %llu disagreements "
               "(%llu ties: coincident faces at one distance, %llu near an edge, %llu neither), "
               "%llu of those near an edge inside a rectangle (Embree's ray through the crack "
               "between two of its triangles), "
               "max distance error among agreeing rays %.3g (relative %.3g) -> %s\n",
               chk.agreement_pct, (unsigned long long)chk.pixels, (unsigned long long)chk.both_miss,
               (unsigned long long)chk.disagree, (unsigned long long)chk.ties,
               (unsigned long long)chk.near_edge,
               (unsigned long long)(chk.disagree - chk.ties - chk.near_edge),
               (unsigned long long)chk.crack, chk.max_abs_dt, chk.max_rel_dt,
               pass ? "PASS" : "FAIL");
        for (uint32_t k = 0; k < chk.reported; ++k) {
            const pgt_facade_check_pixel *p = &chk.far[k];
            fprintf(stderr,
                    "pgt facade: pixel %u,%u: ours facade %d node %u kind %u surface %u t %.7g "
                    "(edge %.3g t, inner edge %.3g t); Embree facade %d node %u kind %u surface "
                    "%u t %.7g (edge %.3g t)\n",
                    p->x, p->y, (int)p->facade[0], p->node[0], p->kind[0], p->surface[0],
                    (double)p->t[0], (double)p->edge[0], (double)p->inner, (int)p->facade[1],
                    p->node[1], p->kind[1], p->surface[1], (double)p->t[1], (double)p->edge[1]);
        }
        rc = pass ? PGT_EXIT_OK : PGT_EXIT_FAIL;
    }
done:
    pgt_cli_progress_stop(&prog);
    pgt_cli_stage_abort(&stage);
    pgt_facade_embree_hits_destroy(&hits);
    pgt_facade_embree_destroy(&eb);
    pgt_facade_mesh_destroy(&mesh);
    pgt_facade_frame_destroy(&frame);
    free(facades);
    pgt_facade_file_free(&file);
    pgt_facade_quads_destroy(&quads);
    free(ms);
    return rc;
}
