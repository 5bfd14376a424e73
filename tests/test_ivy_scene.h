/* The ivy test scene shared by test_expand and test_terminals: grammars/ivy.grammar on the atlas
 * of the n = 32 cube-sphere (1024^2, pgt_atlas_build defaults), seeded at every
 * (inner texels / IVY_SCENE_SEEDS)-th inner texel, heading +x. Header-only, for tests. */
#ifndef PGT_TEST_IVY_SCENE_H
#define PGT_TEST_IVY_SCENE_H

#include <stdio.h>
#include <string.h>

#include "gen.h"
#include "pgt/atlas.h"
#include "pgt/atlas_build.h"
#include "pgt/expand.h"
#include "pgt/grammar.h"
#include "pgt/image.h"
#include "pgt/march.h"

#define IVY_SCENE_SEEDS 6u

typedef struct ivy_scene {
    pgt_image img;
    pgt_atlas_stats stats;
    pgt_march_atlas atlas;
    pgt_grammar grammar;
    pgt_expand_seed seeds[IVY_SCENE_SEEDS];
    pgt_expand_input in; /* points into this struct: do not copy it after ivy_scene_make */
} ivy_scene;

/* 1 on success; on failure prints why and leaves nothing to free. */
static int ivy_scene_make(ivy_scene *s) {
    memset(s, 0, sizeof(*s));
    pgt_mesh m;
    pgt_error err = {0};
    if (pgt_gen_cube_sphere(&m, 32, NULL) != PGT_OK) return 0;
    pgt_atlas_options ao = {0};
    ao.threads = 2;
    ao.what = "cube_sphere_32";
    const pgt_result built = pgt_atlas_build(&s->img, &m, &ao, &s->stats, &err);
    pgt_mesh_destroy(&m);
    if (built != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return 0;
    }
    pgt_atlas_channels ch;
    if (pgt_march_atlas_create(&s->atlas, &s->img, "cube_sphere_32", &err) != PGT_OK ||
        pgt_atlas_channels_find(&s->img, "cube_sphere_32", &ch, &err) != PGT_OK ||
        pgt_grammar_load(&s->grammar, PGT_SOURCE_DIR "/grammars/ivy.grammar", &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        pgt_march_atlas_destroy(&s->atlas);
        pgt_image_destroy(&s->img);
        return 0;
    }
    const pgt_march_atlas *v = &s->atlas;
    const size_t texels = (size_t)v->width * v->height;
    uint32_t inner = 0, k = 0, seen = 0;
    for (size_t i = 0; i < texels; ++i) inner += (v->codes[i] & 3u) == PGT_TEXEL_INNER;
    for (size_t i = 0; i < texels && k < IVY_SCENE_SEEDS; ++i) {
        if ((v->codes[i] & 3u) != PGT_TEXEL_INNER) continue;
        if (seen++ % (inner / IVY_SCENE_SEEDS) != inner / (2u * IVY_SCENE_SEEDS)) continue;
        s->seeds[k++] = (pgt_expand_seed){(float)(i % v->width) + 0.5f,
                                          (float)(i / v->width) + 0.5f, 1.0f, 0.0f};
    }
    s->in.grammar = &s->grammar, s->in.atlas = &s->atlas, s->in.seeds = s->seeds;
    s->in.seed_count = k;
    s->in.normal[0] = pgt_image_plane(&s->img, ch.nx);
    s->in.normal[1] = pgt_image_plane(&s->img, ch.ny);
    s->in.normal[2] = pgt_image_plane(&s->img, ch.nz);
    return 1;
}

static void ivy_scene_free(ivy_scene *s) {
    pgt_grammar_destroy(&s->grammar);
    pgt_march_atlas_destroy(&s->atlas);
    pgt_image_destroy(&s->img);
    memset(s, 0, sizeof(*s));
}

#endif
