/* pgt render: ray traced pictures of meshes for paper figures (harness/render.h, Embree 3). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "pgt/mesh_io.h"
#include "png_io.h"
#include "progress_line.h"
#include "render.h"

static const char *render_usage =
    "usage: pgt render MESH[@R,G,B] [MESH[@R,G,B] ...] -o OUT.png [--width W] [--height H]\n"
    "                  [--camera EYEx,EYEy,EYEz,ATx,ATy,ATz,UPx,UPy,UPz,FOV] [--view AZ,EL]\n"
    "                  [--up x|y|z] [--spp N] [--no-shadows] [--background R,G,B] [--threads N]\n"
    "\n"
    "Ray traces triangle meshes with Embree into an 8-bit sRGB PNG for figures: geometric\n"
    "normals seen from either side, Lambert shading under a key light from above-left of the\n"
    "camera plus ambient 0.25, one shadow ray per hit, N x N regular subpixel samples (the same\n"
    "bytes for any thread count). A progress line on stderr every 5 s of work\n"
    "(PGT_PROGRESS_SECONDS: the period, 0: none).\n"
    "\n"
    "  MESH[@R,G,B]   .obj .off .ply (extra PLY vertex properties are skipped), a mesh of\n"
    "                 ../shared/datasets/meshes by name, or a generated dataset (pgt_datasets\n"
    "                 --list); @R,G,B is its diffuse colour, three linear values in [0,1]\n"
    "                 (split at the last '@' only when three numbers follow it). Default colours:\n"
    "                 light grey 0.8,0.8,0.8, then ivy green 0.25,0.55,0.2, then terracotta,\n"
    "                 blue, ochre, purple, in turn\n"
    "  -o OUT.png     output PNG (RGB); written to a temporary file, then renamed\n"
    "  --width W      picture width in pixels, 1 to 16384 (default 1024)\n"
    "  --height H     picture height in pixels, 1 to 16384 (default 768)\n"
    "  --camera ...   eye, look-at point, up vector and vertical field of view in degrees, in\n"
    "                 (0, 180); the eye must differ from the look-at point and up must not be\n"
    "                 parallel to the view direction; not with --view or --up (default:\n"
    "                 automatic framing, below)\n"
    "  --view AZ,EL   automatic framing: look at the centre of the meshes' bounding box from\n"
    "                 azimuth AZ and elevation EL degrees around the up axis, EL in (-90, 90),\n"
    "                 at the distance where the bounding sphere fills the 35 degree field of view\n"
    "                 with 5% margin (the horizontal one when taller than wide); default\n"
    "                 30,20; azimuth 0 looks from +z for up y, from -y for up z, from +y for\n"
    "                 up x, and turns counter-clockwise seen from the up axis\n"
    "  --up x|y|z     up axis of the automatic framing (default y)\n"
    "  --spp N        N x N samples per pixel, 1 to 16 (default 2: 4 samples)\n"
    "  --no-shadows   no shadow rays\n"
    "  --background R,G,B  background colour as it appears in the PNG, values in [0,1]\n"
    "                 (default 1,1,1: white)\n"
    "  --threads N    worker threads for the BVH build and the rays, 1 to 256 (default: the\n"
    "                 number of CPUs)\n"
    "\n"
    "Prints the camera as a --camera value (stdout) and one line with size, samples, meshes,\n"
    "triangles and the BVH and trace times (stderr). Exit 0 on success, 2 on a bad flag or input\n"
    "(naming the flag, or the file and line). An input is never overwritten.\n";

/* The default colours, in turn (linear albedo). */
static const float palette[][3] = {{0.8f, 0.8f, 0.8f},  {0.25f, 0.55f, 0.2f}, {0.7f, 0.35f, 0.25f},
                                   {0.25f, 0.4f, 0.7f}, {0.8f, 0.65f, 0.25f}, {0.5f, 0.35f, 0.6f}};
#define PALETTE_SIZE (sizeof palette / sizeof palette[0])

/* Parses exactly n comma-separated finite numbers; nonzero on anything else. */
static int parse_floats(const char *text, float *out, int n) {
    const char *p = text;
    for (int i = 0; i < n; ++i) {
        char *end = NULL;
        if (*p == '\0' || *p == ',' || *p == ' ') return -1;
        const double x = strtod(p, &end);
        if (end == p || !isfinite(x) || fabs(x) > 3.0e38) return -1;
        out[i] = (float)x;
        p = end;
        if (i + 1 < n) {
            if (*p != ',') return -1;
            ++p;
        }
    }
    return *p == '\0' ? 0 : -1;
}

typedef struct mesh_arg {
    char *path; /* the file part of the argument (malloc'd) */
    float rgb[3];
    int has_rgb;
} mesh_arg;

/* Splits "FILE@R,G,B" at the last '@' when three numbers follow it. Nonzero (after printing)
 * when they are numbers but not colours. */
static int split_mesh_arg(const char *verb, const char *a, mesh_arg *out) {
    const char *at = strrchr(a, '@');
    size_t len = strlen(a);
    if (at && parse_floats(at + 1, out->rgb, 3) == 0) {
        for (int k = 0; k < 3; ++k)
            if (!(out->rgb[k] >= 0.0f && out->rgb[k] <= 1.0f))
                return pgt_cli_fail(verb, "%s: colour %s: each value must be in [0,1]", a, at + 1);
        len = (size_t)(at - a);
        out->has_rgb = 1;
        if (len == 0) return pgt_cli_fail(verb, "%s: no mesh before the colour", a);
    } else if (at && access(a, F_OK) != 0) {
        /* not a file of that name, but a mesh file's name before the '@': a colour was meant */
        char head[4096];
        snprintf(head, sizeof head, "%.*s", (int)(at - a), a);
        if (pgt_cli_ends_with_ci(head, ".obj") || pgt_cli_ends_with_ci(head, ".off") ||
            pgt_cli_ends_with_ci(head, ".ply"))
            return pgt_cli_fail(verb, "%s: colour '%s': expected three numbers in [0,1], R,G,B", a,
                                at + 1);
    }
    out->path = malloc(len + 1);
    if (!out->path) return pgt_cli_fail(verb, "out of memory");
    memcpy(out->path, a, len);
    out->path[len] = '\0';
    return 0;
}

static int has_png_extension(const char *path) {
    const size_t n = strlen(path);
    return n >= 4 && !strcmp(path + n - 4, ".png");
}

int pgt_cmd_render(int argc, char **argv) {
    const char *verb = "render", *out_path = NULL, *camera_text = NULL, *view_text = NULL;
    const char *up_text = NULL;
    uint32_t width = 1024, height = 768, spp = PGT_RENDER_DEFAULT_SPP;
    uint32_t threads = pgt_cli_cpu_count();
    int no_shadows = 0, background_set = 0;
    float background[3] = {1.0f, 1.0f, 1.0f}, view[2] = {30.0f, 20.0f};
    int up_axis = 1;
    mesh_arg *args = calloc((size_t)argc + 1, sizeof *args);
    pgt_mesh *meshes = calloc((size_t)argc + 1, sizeof *meshes);
    pgt_render_mesh *rmeshes = calloc((size_t)argc + 1, sizeof *rmeshes);
    uint8_t *pixels = NULL;
    uint32_t count = 0;
    int rc = PGT_EXIT_USAGE;
    pgt_cli_progress prog; /* a line every few seconds while the work runs (stderr) */
    memset(&prog, 0, sizeof prog);
    pgt_error err = {0};
    if (!args || !meshes || !rmeshes) {
        pgt_cli_fail(verb, "out of memory");
        goto done;
    }
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(render_usage, stdout);
            rc = PGT_EXIT_OK;
            goto done;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(out_path = pgt_cli_value(verb, argc, argv, &i))) goto done;
        } else if (!strcmp(a, "--width")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, PGT_PNG_MAX_SIDE, &width))
                goto done;
        } else if (!strcmp(a, "--height")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, PGT_PNG_MAX_SIDE, &height))
                goto done;
        } else if (!strcmp(a, "--spp")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, PGT_RENDER_MAX_SPP, &spp))
                goto done;
        } else if (!strcmp(a, "--threads")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 256, &threads))
                goto done;
        } else if (!strcmp(a, "--camera")) {
            if (!(camera_text = pgt_cli_value(verb, argc, argv, &i))) goto done;
        } else if (!strcmp(a, "--view")) {
            if (!(view_text = pgt_cli_value(verb, argc, argv, &i))) goto done;
            if (parse_floats(view_text, view, 2) || !(fabsf(view[1]) < 90.0f) ||
                !(fabsf(view[0]) <= 1e6f)) {
                pgt_cli_fail(verb,
                             "--view: expected AZ,EL in degrees with EL in (-90, 90), got '%s'",
                             view_text);
                goto done;
            }
        } else if (!strcmp(a, "--up")) {
            if (!(up_text = pgt_cli_value(verb, argc, argv, &i))) goto done;
            if (strlen(up_text) != 1 || up_text[0] < 'x' || up_text[0] > 'z') {
                pgt_cli_fail(verb, "--up: expected x, y or z, got '%s'", up_text);
                goto done;
            }
            up_axis = up_text[0] - 'x';
        } else if (!strcmp(a, "--background")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i))) goto done;
            if (parse_floats(v, background, 3) || !(background[0] >= 0.0f) ||
                !(background[1] >= 0.0f) || !(background[2] >= 0.0f) || background[0] > 1.0f ||
                background[1] > 1.0f || background[2] > 1.0f) {
                pgt_cli_fail(verb, "--background: expected R,G,B with values in [0,1], got '%s'",
                             v);
                goto done;
            }
            background_set = 1;
        } else if (!strcmp(a, "--no-shadows")) {
            no_shadows = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            pgt_cli_fail(verb, "unknown flag '%s' (see pgt render --help)", a);
            goto done;
        } else {
            if (split_mesh_arg(verb, a, &args[count])) goto done;
            count++;
        }
    }
    if (count == 0) {
        pgt_cli_fail(verb, "no input mesh (see pgt render --help)");
        goto done;
    }
    if (!out_path) {
        pgt_cli_fail(verb, "no output: give -o OUT.png");
        goto done;
    }
    for (uint32_t i = 0; i < count; ++i)
        if (pgt_cli_same_file(args[i].path, out_path)) {
            pgt_cli_fail(verb, "-o %s is the input %s; pgt never overwrites an input", out_path,
                         args[i].path);
            goto done;
        }
    if (pgt_cli_check_outputs(verb, &out_path, 1)) goto done;
    if (pgt_cli_progress_start(&prog, verb)) goto done;
    pgt_progress_stage(prog.progress, "reading", 0, "");
    if (!has_png_extension(out_path)) {
        pgt_cli_fail(verb, "-o %s: the picture is a .png file", out_path);
        goto done;
    }
    pgt_render_camera cam;
    if (camera_text) {
        if (view_text || up_text) {
            pgt_cli_fail(verb, "--camera sets the view: leave out --view and --up");
            goto done;
        }
        float c[10];
        if (parse_floats(camera_text, c, 10)) {
            pgt_cli_fail(verb,
                         "--camera: expected 10 numbers EYEx,EYEy,EYEz,ATx,ATy,ATz,UPx,UPy,UPz,"
                         "FOV, got '%s'",
                         camera_text);
            goto done;
        }
        memcpy(cam.eye, c, sizeof cam.eye);
        memcpy(cam.at, c + 3, sizeof cam.at);
        memcpy(cam.up, c + 6, sizeof cam.up);
        cam.fov_deg = c[9];
        if (pgt_render_camera_check(&cam, &err) != PGT_OK) {
            const char *m = strncmp(err.message, "camera: ", 8) ? err.message : err.message + 8;
            pgt_cli_fail(verb, "--camera %s: %s", camera_text, m);
            goto done;
        }
    }

    const double t0 = pgt_cli_now_ms();
    uint64_t triangles = 0;
    for (uint32_t i = 0; i < count; ++i) {
        pgt_error_clear(&err);
        pgt_mesh_origin origin; /* for the line of a vertex beyond the ray range */
        if (pgt_cli_load_named_origin(args[i].path, PGT_CLI_SHARED_MESH_DIR, &meshes[i], &origin,
                                      &err) != PGT_OK) {
            pgt_cli_fail(verb, "%s", err.message);
            goto done;
        }
        /* the picture needs positions and triangles only */
        free(meshes[i].uvs), meshes[i].uvs = NULL;
        free(meshes[i].labels), meshes[i].labels = NULL;
        if (pgt_render_pad_positions(&meshes[i], &err) != PGT_OK) {
            char place[4200];
            pgt_mesh_origin_vertex_where(
                &origin, args[i].path, pgt_mesh_far_vertex(&meshes[i], PGT_RENDER_MAX_COORD, NULL),
                place, sizeof place);
            pgt_mesh_origin_destroy(&origin);
            pgt_cli_fail(verb, "%s: %s", place, err.message);
            goto done;
        }
        pgt_mesh_origin_destroy(&origin);
        rmeshes[i].mesh = &meshes[i];
        rmeshes[i].positions_padded = 1;
        const float *rgb = args[i].has_rgb ? args[i].rgb : palette[i % PALETTE_SIZE];
        memcpy(rmeshes[i].rgb, rgb, sizeof rmeshes[i].rgb);
        triangles += meshes[i].face_count;
    }
    const double t1 = pgt_cli_now_ms();
    if (!camera_text) {
        pgt_render_auto_camera(rmeshes, count, view[0], view[1], up_axis,
                               (double)width / (double)height, &cam);
        pgt_error_clear(&err);
        if (pgt_render_camera_check(&cam, &err) != PGT_OK) {
            pgt_cli_fail(verb, "--view %g,%g: %s", (double)view[0], (double)view[1], err.message);
            goto done;
        }
    }
    printf("camera: --camera ");
    const float *cv[4] = {cam.eye, cam.at, cam.up, &cam.fov_deg};
    for (int g = 0; g < 4; ++g)
        for (int k = 0; k < (g < 3 ? 3 : 1); ++k) {
            if (g || k) putchar(',');
            pgt_cli_print_float(cv[g][k]);
        }
    putchar('\n');
    fflush(stdout);

    pixels = malloc((size_t)width * height * 3u);
    if (!pixels) {
        pgt_cli_fail(verb, "out of memory for %u x %u pixels", width, height);
        goto done;
    }
    pgt_render_options opt = {0};
    opt.spp = spp;
    opt.threads = threads;
    opt.no_shadows = no_shadows;
    opt.background_set = background_set;
    memcpy(opt.background, background, sizeof opt.background);
    opt.progress = prog.progress;
    pgt_progress_stage(prog.progress, "BVH", 0, "");
    pgt_render_stats st;
    pgt_error_clear(&err);
    if (pgt_render(pixels, width, height, rmeshes, count, &cam, &opt, &st, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    const double t2 = pgt_cli_now_ms();
    pgt_progress_stage(prog.progress, "writing the PNG", 0, "");
    if (pgt_png_write(out_path, width, height, 3, pixels, &err) != PGT_OK) {
        pgt_cli_fail(verb, "%s", err.message);
        goto done;
    }
    const double t3 = pgt_cli_now_ms();
    pgt_cli_progress_stop(&prog); /* the timing line (stderr) comes last */
    char tris[32];
    if (triangles < 10000)
        snprintf(tris, sizeof tris, "%llu", (unsigned long long)triangles);
    else if (triangles < 1000000)
        snprintf(tris, sizeof tris, "%.1fk", (double)triangles * 1e-3);
    else
        snprintf(tris, sizeof tris, "%.1fM", (double)triangles * 1e-6);
    fprintf(stderr,
            "render: %ux%u, %u spp, %u mesh%s, %s triangles: read %.0f ms, BVH %.0f ms, trace "
            "%.0f ms (%.1f Mrays/s), write %.0f ms -> %s\n",
            width, height, spp * spp, count, count == 1 ? "" : "es", tris, t1 - t0, st.bvh_ms,
            st.trace_ms, st.trace_ms > 0.0 ? (double)st.rays / (st.trace_ms * 1e3) : 0.0, t3 - t2,
            out_path);
    rc = PGT_EXIT_OK;
done:
    pgt_cli_progress_stop(&prog);
    for (int i = 0; args && i <= argc; ++i) free(args[i].path);
    for (int i = 0; meshes && i <= argc; ++i) pgt_mesh_destroy(&meshes[i]);
    free(args);
    free(meshes);
    free(rmeshes);
    free(pixels);
    return rc;
}
