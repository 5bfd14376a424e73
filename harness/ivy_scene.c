/* pgt harness: ivy scene setup shared by pgt ivy and pgt bench ivy (see ivy_scene.h). */
#include "ivy_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "pgt/image.h"
#include "pgt/ivy.h"
#include "pgt/mesh.h"
#include "pgt/mesh_io.h"
#include "pgt/rng.h"

int pgt_ivy_scene_atlas(pgt_ivy_scene *s, const char *verb, const char *path, uint32_t res,
                        uint32_t threads) {
    memset(s, 0, sizeof(*s));
    pgt_error err = {0};
    const double t0 = pgt_cli_now_ms();
    if (pgt_cli_ends_with_ci(path, ".exr")) {
        if (pgt_image_read_exr_threads(&s->img, path, threads, &err) != PGT_OK) goto fail;
    } else {
        pgt_mesh mesh = {0};
        pgt_mesh_origin origin = {0};
        if (pgt_cli_load_atlas_mesh(verb, path, ", or give an atlas .exr", &mesh, &origin)) {
            pgt_ivy_scene_free(s);
            return -1;
        }
        pgt_atlas_options ao = {0};
        ao.width = ao.height = res;
        ao.threads = threads;
        ao.what = path;
        ao.origin = &origin;
        const pgt_result r = pgt_atlas_build(&s->img, &mesh, &ao, &s->stats, &err);
        pgt_mesh_destroy(&mesh);
        pgt_mesh_origin_destroy(&origin);
        if (r != PGT_OK) goto fail;
        s->built = 1;
    }
    if (pgt_atlas_channels_find(&s->img, path, &s->ch, &err) != PGT_OK ||
        pgt_march_atlas_create(&s->atlas, &s->img, path, &err) != PGT_OK)
        goto fail;
    s->texel_size = s->built ? s->stats.texel_size : pgt_atlas_texel_size(&s->img, &s->ch);
    s->ms_atlas = pgt_cli_now_ms() - t0;
    return 0;
fail:
    pgt_cli_fail(verb, "%s", err.message);
    pgt_ivy_scene_free(s);
    return -1;
}

int pgt_ivy_scene_grammar(pgt_ivy_scene *s, const char *verb, const char *path,
                          const char *const *params, uint32_t count) {
    pgt_error err = {0};
    pgt_grammar_destroy(&s->grammar);
    if (pgt_grammar_load(&s->grammar, path, &err) != PGT_OK) {
        pgt_grammar_destroy(&s->grammar);
        return pgt_cli_fail(verb, "%s", err.message);
    }
    return pgt_cli_grammar_params(verb, &s->grammar, params, count);
}

void pgt_ivy_scene_input(const pgt_ivy_scene *s, pgt_expand_input *in) {
    memset(in, 0, sizeof(*in));
    in->grammar = &s->grammar;
    in->atlas = &s->atlas;
    in->normal[0] = pgt_image_plane(&s->img, s->ch.nx);
    in->normal[1] = pgt_image_plane(&s->img, s->ch.ny);
    in->normal[2] = pgt_image_plane(&s->img, s->ch.nz);
    in->mask = s->mask;
    in->density = s->density;
    in->seeds = s->seeds;
    in->seed_count = s->seed_count;
}

void pgt_ivy_scene_free(pgt_ivy_scene *s) {
    if (!s) return;
    pgt_grammar_destroy(&s->grammar);
    pgt_march_atlas_destroy(&s->atlas);
    pgt_image_destroy(&s->img);
    free(s->mask);
    free(s->density);
    free(s->brushed);
    free(s->seeds);
    memset(s, 0, sizeof(*s));
}

int pgt_ivy_guide_strokes(const pgt_march_atlas *a, const char *verb, uint32_t count,
                          uint32_t steps, uint32_t seed, float **points, uint32_t *point_count,
                          uint32_t **first, pgt_expand_seed *starts) {
    pgt_error err = {0};
    *points = NULL, *first = NULL, *point_count = 0;
    const size_t cap = (size_t)count * (steps + 1u);
    float *p = malloc((cap ? cap : 1u) * 3u * sizeof(float));
    uint32_t *f = malloc(((size_t)count + 1u) * sizeof(uint32_t));
    if (!p || !f) {
        free(p), free(f);
        return pgt_cli_fail(verb, "out of memory");
    }
    if (pgt_ivy_random_seeds(starts, count, a, NULL, seed, &err) != PGT_OK) {
        free(p), free(f);
        return pgt_cli_fail(verb, "%s", err.message);
    }
    const pgt_march_options mo = {0};
    uint32_t n = 0;
    for (uint32_t k = 0; k < count; ++k) {
        f[k] = n;
        pgt_march_state st;
        if (pgt_march_start(a, starts[k].x, starts[k].y, starts[k].dx, starts[k].dy, &st, &err) !=
            PGT_OK) {
            free(p), free(f);
            return pgt_cli_fail(verb, "%s", err.message);
        }
        pgt_march_position(a, st.x, st.y, &p[3u * (size_t)n++]);
        const float phase = 6.2831853f * pgt_rng_float(seed, PGT_IVY_SEED_STREAM ^ 1u, k);
        for (uint32_t i = 0; i < steps; ++i) {
            const float turn =
                PGT_IVY_GUIDE_TURN * sinf(6.2831853f * (float)i / PGT_IVY_GUIDE_PERIOD + phase);
            if (pgt_march_step(a, &mo, &st, PGT_IVY_GUIDE_STEP_TEXELS, turn, NULL) ==
                PGT_MARCH_STOP)
                break;
            pgt_march_position(a, st.x, st.y, &p[3u * (size_t)n++]);
        }
    }
    f[count] = n;
    *points = p, *first = f, *point_count = n;
    return 0;
}

int pgt_ivy_scene_paint(pgt_ivy_scene *s, const char *verb, const float *points,
                        uint32_t point_count, const uint32_t *first, uint32_t strokes, float radius,
                        uint32_t threads, int forbid, uint64_t *out_painted) {
    pgt_error err = {0};
    const size_t texels = (size_t)s->atlas.width * s->atlas.height;
    if (!s->mask) {
        if (!(s->mask = calloc(texels, sizeof(float)))) return pgt_cli_fail(verb, "out of memory");
    }
    if (!s->brushed) {
        if (!(s->brushed = calloc(texels, 1u))) return pgt_cli_fail(verb, "out of memory");
    }
    float *allowed = malloc(texels * sizeof(float));
    if (!allowed) return pgt_cli_fail(verb, "out of memory");
    for (size_t i = 0; i < texels; ++i) allowed[i] = 1.0f;
    if (pgt_ivy_paint(allowed, &s->atlas, points, point_count, first, strokes, radius, threads,
                      out_painted, &err) != PGT_OK) {
        free(allowed);
        return pgt_cli_fail(verb, "%s: %s", forbid ? "--forbid" : "--paint", err.message);
    }
    for (size_t i = 0; i < texels; ++i) {
        const int brushed = allowed[i] == 0.0f;
        s->brushed[i] |= (uint8_t)brushed;
        if (forbid ? brushed : !brushed) s->mask[i] = 1.0f;
    }
    free(allowed);
    return 0;
}

int pgt_ivy_write_strokes(const char *verb, const char *path, const float *points,
                          const uint32_t *first, uint32_t strokes) {
    char tmp[4200];
    FILE *f = pgt_cli_tmp_open(path, tmp, sizeof tmp);
    if (!f) return pgt_cli_fail(verb, "cannot write %s", tmp);
    fprintf(f, "# painted strokes (pgt ivy --paint): 'stroke', then one 'point X Y Z' per line\n");
    for (uint32_t k = 0; k < strokes; ++k) {
        fprintf(f, "stroke\n");
        for (uint32_t i = first[k]; i < first[k + 1u]; ++i)
            fprintf(f, "point %.9g %.9g %.9g\n", (double)points[3u * (size_t)i],
                    (double)points[3u * (size_t)i + 1u], (double)points[3u * (size_t)i + 2u]);
    }
    return pgt_cli_table_close(f, tmp, path, verb) ? -1 : 0;
}
