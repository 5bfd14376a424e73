/* pgt diff: the reference and a GPU backend on the same inputs, element by element. */
#include <stdlib.h>
#include <string.h>

#include "backend.h"
#include "cli.h"
#include "diff.h"
#include "gen.h"
#include "pgt/atlas_build.h"
#include "pgt/image.h"
#include "pgt/rng.h"

static const char *diff_usage =
    "usage: pgt diff ALGO --backend cl|vk [INPUTS...] [--device N] [--iters LIST]\n"
    "                [--protected LIST] [--walkers N] [--steps N] [--step S] [--res N]\n"
    "                [--shared DIR] [--profile] [--json]\n"
    "\n"
    "Runs the C reference and a backend on the same input and compares their outputs element\n"
    "by element: integer and topological outputs must be equal (the count of mismatches is\n"
    "printed); floats get the largest absolute error, the largest ULP distance and the worst\n"
    "element, and a verdict against the tolerance table (harness/tolerances.h). march: the\n"
    "backend's walkers record every step; the reference re-runs each step from the backend's\n"
    "state before it (event, stop, crossings, chart and the no-bounce memory must be equal,\n"
    "positions and directions within the tolerance), for the paper's marching, without 5.1,\n"
    "without rotation, with the Jacobian rotation and with a sparse random mask.\n"
    "\n"
    "  ALGO            sqrt3, march, or all (every algorithm with a version on that backend:\n"
    "                  sqrt3 and march, on cl and vk)\n"
    "  INPUTS          meshes: generated dataset names (pgt_datasets --list), files, or file\n"
    "                  names in the shared folder; march also takes atlases (.exr, as pgt atlas\n"
    "                  writes them) and builds one of a mesh with UVs (--res). Defaults: sqrt3\n"
    "                  every generated default dataset and every mesh of the shared folder the\n"
    "                  project uses; march cube_sphere_8 and the shared meshes with UVs. Under\n"
    "                  all, an input an algorithm cannot take is skipped with a note.\n"
    "  --backend B     cl (OpenCL) or vk (Vulkan); cpu compares the reference with itself\n"
    "  --device N      device index of that API (see pgt devices; default 0)\n"
    "  --iters LIST    sqrt3 iterations per case, comma-separated (default 1,2,3)\n"
    "  --protected L   protection patterns, comma-separated: none, quarter (faces whose\n"
    "                  counter-based hash of (seed 3, face) falls in the lowest quarter are\n"
    "                  protected) (default none,quarter)\n"
    "  --walkers N     march: seeded random walkers per case (default 2048)\n"
    "  --steps N       march: steps per walker (default 100)\n"
    "  --step S        march: step length in texels (default 2)\n"
    "  --res N         march: atlas resolution for a mesh input (default 1024)\n"
    "  --shared DIR    shared mesh folder (default ../shared/datasets/meshes beside the repo)\n"
    "  --profile       print the per-kernel table (launches, total and median device ms)\n"
    "  --json          one JSON object per case, then a summary object\n"
    "\n"
    "Environment: PGT_VK_VALIDATION=1 turns on the Vulkan validation layer (any message fails).\n"
    "Exit 0 when every case is within tolerance, 1 when one is not, 2 on a bad flag, a bad\n"
    "input (a case both sides refuse with the same error compares nothing: exit 2) or a\n"
    "backend error.\n";

#define DIFF_MAX_LIST 64

/* Seed of the "quarter" protection pattern (any fixed value: the pattern must only be the same
 * for both sides and across runs). */
#define DIFF_PROTECT_SEED 3u

typedef struct diff_cfg {
    const char *inputs[DIFF_MAX_LIST];
    uint32_t n_inputs, iters[DIFF_MAX_LIST], n_iters;
    int protect_none, protect_quarter, json, profile;
    const char *shared_dir;
    int explicit_inputs;
    uint32_t walkers, steps, res;
    float step;
} diff_cfg;

/* march's default inputs: the generated cube-sphere and the shared meshes with UVs. */
static const char *const diff_march_inputs[] = {"cube_sphere_8",     "spot.obj",
                                                "bob_tri.obj",       "ogre_bs_rest.obj",
                                                "human_neutral.obj", "pizza.obj"};

/* Seeds of march's walkers (pgt_march_random_starts) and of its random mask: any fixed values. */
#define DIFF_MARCH_SEED 11u
#define DIFF_MARCH_MASK_SEED 5u
/* Share of the mask's texels that reject a step: a few walkers of each case stop there. */
#define DIFF_MARCH_MASK_SHARE 0.002f

static int diff_list(const char *flag, const char *text, diff_cfg *c, int iters) {
    char buf[1024];
    const char *items[DIFF_MAX_LIST];
    uint32_t n = 0;
    if (pgt_cli_name_list("diff", flag, text, buf, sizeof buf, items, DIFF_MAX_LIST, &n))
        return PGT_EXIT_USAGE;
    for (uint32_t k = 0; k < n; ++k) {
        const char *tok = items[k];
        if (iters) {
            if (c->n_iters >= DIFF_MAX_LIST)
                return pgt_cli_fail("diff", "%s: at most %d values", flag, DIFF_MAX_LIST);
            if (pgt_cli_uint("diff", flag, tok, 0, PGT_SQRT3_MAX_ITERATIONS,
                             &c->iters[c->n_iters++]))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(tok, "none")) {
            c->protect_none = 1;
        } else if (!strcmp(tok, "quarter")) {
            c->protect_quarter = 1;
        } else {
            return pgt_cli_fail("diff", "%s: expected none or quarter, got '%s'", flag, tok);
        }
    }
    return 0;
}

/* sqrt3 over every input x pattern x k; returns the number of failing cases, or -1 on an error
 * that stops the run (message printed). */
static int diff_sqrt3(pgt_backend *b, const diff_cfg *c, int all, uint32_t *cases,
                      uint32_t *refused) {
    int failures = 0;
    for (uint32_t i = 0; i < c->n_inputs; ++i) {
        if (all && pgt_cli_ends_with_ci(c->inputs[i], ".exr")) {
            printf("sqrt3 %s: skipped (an atlas, not a mesh)\n", c->inputs[i]);
            continue;
        }
        pgt_mesh m = {0};
        pgt_error err = {0};
        if (pgt_cli_load_named(c->inputs[i], c->shared_dir, &m, &err) != PGT_OK) {
            pgt_cli_fail("diff", "%s", err.message);
            return -1;
        }
        uint8_t *prot = malloc((size_t)m.face_count + 1);
        if (!prot) {
            pgt_mesh_destroy(&m);
            pgt_cli_fail("diff", "out of memory");
            return -1;
        }
        for (uint32_t f = 0; f < m.face_count; ++f)
            prot[f] = pgt_rng_float(DIFF_PROTECT_SEED, 0, f) < 0.25f;
        for (int p = 0; p < 2; ++p) {
            if ((p == 0 && !c->protect_none) || (p == 1 && !c->protect_quarter)) continue;
            for (uint32_t k = 0; k < c->n_iters; ++k) {
                pgt_diff_sqrt3 d;
                char label[512];
                snprintf(label, sizeof label, "%s k=%u protected=%s", c->inputs[i], c->iters[k],
                         p ? "quarter" : "none");
                if (pgt_diff_sqrt3_run(b, &m, c->iters[k], p ? prot : NULL, &d, &err) != PGT_OK) {
                    pgt_cli_fail("diff", "%s: %s", label, err.message);
                    free(prot), pgt_mesh_destroy(&m);
                    return -1;
                }
                pgt_diff_sqrt3_print(stdout, label, &d, c->json);
                fflush(stdout);
                (*cases)++;
                *refused += d.pass && d.ref_failed; /* agreement, but nothing compared */
                if (!d.pass) {
                    failures++;
                    /* A backend error on an input the reference accepts is an error, not a
                     * disagreement: stop with exit 2 (device lost, out of memory, ...). */
                    if (d.got_failed && !d.ref_failed) {
                        pgt_cli_fail("diff", "%s: %s: %s", label, b->name, d.got_message);
                        free(prot), pgt_mesh_destroy(&m);
                        return -1;
                    }
                }
            }
        }
        free(prot);
        pgt_mesh_destroy(&m);
    }
    return failures;
}

/* The atlas of a march input: an .exr is read as it is; a mesh is built at --res. 1 when `all`
 * skips it (a mesh without UVs), 0 when loaded, -1 on an error (message printed). */
static int diff_march_atlas(const diff_cfg *c, const char *name, int all, pgt_march_atlas *out) {
    pgt_image img;
    memset(&img, 0, sizeof img);
    pgt_error err = {0};
    pgt_result r;
    if (pgt_cli_ends_with_ci(name, ".exr")) {
        r = pgt_image_read_exr_threads(&img, name, pgt_cli_cpu_count(), &err);
    } else {
        pgt_mesh m = {0};
        if (pgt_cli_load_named(name, c->shared_dir, &m, &err) != PGT_OK) {
            pgt_cli_fail("diff", "%s", err.message);
            return -1;
        }
        if (!m.uvs) {
            pgt_mesh_destroy(&m);
            if (all) {
                printf("march %s: skipped (no UVs to build an atlas of)\n", name);
                return 1;
            }
            pgt_cli_fail("diff", "%s: march needs UVs to build an atlas of (or give an .exr atlas)",
                         name);
            return -1;
        }
        pgt_atlas_options opt;
        memset(&opt, 0, sizeof opt);
        opt.width = opt.height = c->res;
        opt.threads = pgt_cli_cpu_count();
        opt.what = name;
        r = pgt_atlas_build(&img, &m, &opt, NULL, &err);
        pgt_mesh_destroy(&m);
    }
    if (r == PGT_OK) r = pgt_march_atlas_create(out, &img, name, &err);
    pgt_image_destroy(&img);
    if (r != PGT_OK) {
        pgt_cli_fail("diff", "%s", err.message);
        return -1;
    }
    return 0;
}

/* march over every input x option set; returns the number of failing cases, or -1 on an error
 * that stops the run (message printed). */
static int diff_march(pgt_backend *b, const diff_cfg *c, int all, uint32_t *cases) {
    const char *const *inputs = c->inputs;
    uint32_t n = c->n_inputs;
    if (!c->explicit_inputs)
        inputs = diff_march_inputs, n = sizeof diff_march_inputs / sizeof *inputs;
    int failures = 0;
    for (uint32_t i = 0; i < n; ++i) {
        pgt_march_atlas a;
        memset(&a, 0, sizeof a);
        const int got = diff_march_atlas(c, inputs[i], all, &a);
        if (got < 0) return -1;
        if (got > 0) continue;
        const size_t texels = (size_t)a.width * a.height;
        float *mask = malloc(texels * sizeof(float));
        if (!mask) {
            pgt_march_atlas_destroy(&a);
            pgt_cli_fail("diff", "out of memory");
            return -1;
        }
        for (size_t t = 0; t < texels; ++t)
            mask[t] =
                pgt_rng_float(DIFF_MARCH_MASK_SEED, 0, t) < DIFF_MARCH_MASK_SHARE ? 1.0f : 0.0f;
        static const char *const sets[] = {"paper", "no-best-pointer", "no-rotation", "jacobian",
                                           "mask"};
        for (uint32_t s = 0; s < sizeof sets / sizeof *sets; ++s) {
            pgt_march_options o;
            memset(&o, 0, sizeof o);
            o.no_best_pointer = s == 1, o.no_rotation = s == 2;
            o.rotation = s == 3 ? PGT_MARCH_ROTATION_JACOBIAN : PGT_MARCH_ROTATION_ATLAS;
            o.mask = s == 4 ? mask : NULL;
            char label[512];
            snprintf(label, sizeof label, "%s %ux%u %s step=%g", inputs[i], a.width, a.height,
                     sets[s], (double)c->step);
            pgt_diff_march d;
            pgt_error err = {0};
            if (pgt_diff_march_run(b, &a, &o, c->step, c->steps, c->walkers, DIFF_MARCH_SEED, &d,
                                   &err) != PGT_OK) {
                pgt_cli_fail("diff", "%s: %s", label, err.message);
                free(mask), pgt_march_atlas_destroy(&a);
                return -1;
            }
            pgt_diff_march_print(stdout, label, &d, c->json);
            fflush(stdout);
            (*cases)++;
            failures += !d.pass;
        }
        free(mask);
        pgt_march_atlas_destroy(&a);
    }
    return failures;
}

int pgt_cmd_diff(int argc, char **argv) {
    const char *verb = "diff";
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        fputs(diff_usage, argc < 2 ? stderr : stdout);
        return argc < 2 ? PGT_EXIT_USAGE : PGT_EXIT_OK;
    }
    const char *algo = argv[1];
    const int all = !strcmp(algo, "all"), want_sqrt3 = all || !strcmp(algo, "sqrt3"),
              want_march = all || !strcmp(algo, "march");
    if (!want_sqrt3 && !want_march)
        return pgt_cli_fail(verb, "unknown algorithm '%s' (known: sqrt3, march, all)", algo);
    diff_cfg c;
    memset(&c, 0, sizeof c);
    c.shared_dir = PGT_CLI_SHARED_MESH_DIR;
    c.walkers = 2048, c.steps = 100, c.res = PGT_ATLAS_DEFAULT_RES, c.step = 2.0f;
    int have_backend = 0;
    pgt_backend_kind kind = PGT_BACKEND_CPU;
    uint32_t device = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i], *v;
        int flag;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(diff_usage, stdout);
            return PGT_EXIT_OK;
        } else if ((flag = pgt_backend_flags(verb, argc, argv, &i, &kind, &device)) != 0) {
            if (flag < 0) return PGT_EXIT_USAGE;
            have_backend |= !strcmp(a, "--backend");
        } else if (!strcmp(a, "--iters")) {
            c.n_iters = 0;
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) || diff_list(a, v, &c, 1))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--protected")) {
            c.protect_none = c.protect_quarter = 0;
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) || diff_list(a, v, &c, 0))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--walkers")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 1u << 20, &c.walkers))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--steps")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, 1, 1u << 16, &c.steps))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--step")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_float(verb, a, v, 0.0f, PGT_MARCH_MAX_LENGTH, &c.step))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--res")) {
            if (!(v = pgt_cli_value(verb, argc, argv, &i)) ||
                pgt_cli_uint(verb, a, v, PGT_ATLAS_MIN_RES, PGT_ATLAS_MAX_RES, &c.res))
                return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--shared")) {
            if (!(c.shared_dir = pgt_cli_value(verb, argc, argv, &i))) return PGT_EXIT_USAGE;
        } else if (!strcmp(a, "--profile")) {
            c.profile = 1;
        } else if (!strcmp(a, "--json")) {
            c.json = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            return pgt_cli_fail(verb, "unknown flag '%s' (see pgt diff --help)", a);
        } else {
            if (c.n_inputs >= DIFF_MAX_LIST)
                return pgt_cli_fail(verb, "at most %d inputs", DIFF_MAX_LIST);
            c.inputs[c.n_inputs++] = a;
        }
    }
    if (!have_backend) return pgt_cli_fail(verb, "no backend: give --backend cl or vk");
    if (c.n_iters == 0) c.iters[0] = 1, c.iters[1] = 2, c.iters[2] = 3, c.n_iters = 3;
    if (!c.protect_none && !c.protect_quarter) c.protect_none = c.protect_quarter = 1;
    c.explicit_inputs = c.n_inputs > 0;
    if (c.n_inputs == 0) {
        for (uint32_t g = 0; g < pgt_gen_default_count() && c.n_inputs < DIFF_MAX_LIST; ++g)
            c.inputs[c.n_inputs++] = pgt_gen_default_name(g);
        for (uint32_t s = 0; s < pgt_cli_shared_mesh_count && c.n_inputs < DIFF_MAX_LIST; ++s)
            c.inputs[c.n_inputs++] = pgt_cli_shared_meshes[s];
    }

    pgt_backend b;
    pgt_error err = {0};
    if (pgt_backend_open(&b, kind, device, c.profile, &err) != PGT_OK)
        return pgt_cli_fail(verb, "%s", err.message);
    if (!c.json) printf("diff: reference vs %s\n", b.name);
    uint32_t cases = 0, refused = 0;
    const double t0 = pgt_cli_now_ms();
    int failures = want_sqrt3 ? diff_sqrt3(&b, &c, all, &cases, &refused) : 0;
    if (failures >= 0 && want_march) {
        const int f = diff_march(&b, &c, all, &cases);
        failures = f < 0 ? f : failures + f;
    }
    const double ms = pgt_cli_now_ms() - t0;
    if (failures >= 0) {
        if (c.json) {
            printf("{\"summary\":true,\"backend\":");
            pgt_cli_json_string(stdout, b.name);
            printf(",\"cases\":%u,\"failed\":%d,\"refused_by_both\":%u,\"ms\":%.1f}\n", cases,
                   failures, refused, ms);
        } else {
            printf("diff: %u cases, %d outside tolerance, %u refused by both (%.1f s)\n", cases,
                   failures, refused, ms / 1e3);
        }
    }
    if (c.profile) pgt_backend_print_profile(&b, c.json ? stderr : stdout);
    pgt_backend_close(&b);
    if (failures < 0) return PGT_EXIT_USAGE;
    if (failures) return PGT_EXIT_FAIL;
    /* a case both sides refused compared nothing: the input is bad (the usage's exit 2) */
    if (refused)
        return pgt_cli_fail(verb,
                            "%u of %u cases were refused by both sides (a bad input or "
                            "--iters): nothing was compared there",
                            refused, cases);
    return PGT_EXIT_OK;
}
