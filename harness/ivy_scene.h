/* pgt harness: an ivy scene as pgt ivy and pgt bench ivy set it up: an atlas (built from a mesh
 * or read from an EXR), its marching view, a grammar with overridden params, a mask, seeds. */
#ifndef PGT_IVY_SCENE_H
#define PGT_IVY_SCENE_H

#include <stdint.h>

#include "pgt/atlas.h"
#include "pgt/atlas_build.h"
#include "pgt/expand.h"
#include "pgt/grammar.h"
#include "pgt/image.h"
#include "pgt/march.h"

/* The grammar pgt ivy grows when --grammar is not given. */
#define PGT_IVY_DEFAULT_GRAMMAR PGT_SOURCE_DIR "/grammars/ivy.grammar"

/* The default brush radius of painted strokes, in median 3D texel sizes: a band 12 texels wide
 * leaves the ivy's 4-texel steps and their candidate directions room to follow a curving
 * stroke. */
#define PGT_IVY_DEFAULT_BRUSH_TEXELS 6.0

typedef struct pgt_ivy_scene {
    pgt_image img;         /* the atlas image (atlas.h channels) */
    pgt_atlas_channels ch; /* where its channels are */
    pgt_march_atlas atlas; /* the marching view */
    pgt_atlas_stats stats; /* when built from a mesh (built = 1) */
    int built;
    double texel_size; /* pgt_atlas_texel_size: the median 3D texel size of the atlas */
    double ms_atlas;   /* building or reading the atlas, and the view */
    pgt_grammar grammar;
    float *mask;      /* width * height, or NULL: the grammar's context.mask and the march mask */
    float *density;   /* width * height, or NULL: the grammar's context.density */
    uint8_t *brushed; /* width * height, or NULL: 1 where a stroke's brush reached (figures) */
    pgt_expand_seed *seeds;
    uint32_t seed_count;
} pgt_ivy_scene;

/* Reads an atlas (.exr) or loads a mesh (a file, a shared mesh name or a generated dataset,
 * pgt_cli_load_named) and builds its res x res atlas on `threads` threads. 0 on success; else
 * prints "pgt VERB: ..." and returns nonzero (the scene holds nothing). */
int pgt_ivy_scene_atlas(pgt_ivy_scene *s, const char *verb, const char *path, uint32_t res,
                        uint32_t threads);

/* Loads the grammar and sets `count` overrides "NAME=VALUE" (pgt grammar's --param). 0 on
 * success; else prints the error (FILE:LINE:COL or the override) and returns nonzero. */
int pgt_ivy_scene_grammar(pgt_ivy_scene *s, const char *verb, const char *path,
                          const char *const *params, uint32_t count);

/* The expander's input for the scene (pointers into *s). */
void pgt_ivy_scene_input(const pgt_ivy_scene *s, pgt_expand_input *in);

/* Painted-guidance strokes made by a guide walker, for benchmarks and figures (a user would
 * paint them): stroke k starts at a random inner texel (pgt_ivy_random_seeds with `seed`, so
 * stroke k's start does not depend on count), marches `steps` steps of
 * PGT_IVY_GUIDE_STEP_TEXELS texels turning by PGT_IVY_GUIDE_TURN sin(2 pi i /
 * PGT_IVY_GUIDE_PERIOD + phase_k) radians at step i (a meandering path across charts), and
 * records the 3D position after every step (the start first); a march that stops ends its
 * stroke. Outputs malloc'd: points (3 * *point_count), first (count + 1), and the starts as
 * seeds heading along the stroke (count). 0 on success, else prints and returns nonzero. */
#define PGT_IVY_GUIDE_STEP_TEXELS 2.0f
#define PGT_IVY_GUIDE_TURN 0.12f
#define PGT_IVY_GUIDE_PERIOD 90.0f
int pgt_ivy_guide_strokes(const pgt_march_atlas *a, const char *verb, uint32_t count,
                          uint32_t steps, uint32_t seed, float **points, uint32_t *point_count,
                          uint32_t **first, pgt_expand_seed *starts);

/* Painting with a brush of `radius` (mesh units) along strokes. forbid = 0: growth only along the
 * strokes (paper Fig. 10c): s->mask becomes 1 (forbidden) on every texel the brush does not
 * reach. forbid = 1: the strokes paint forbidden areas (Fig. 10b): s->mask becomes 1 where the
 * brush reaches. Forbidden texels of a mask already there stay forbidden; s->brushed records the
 * texels the brush reached. Prints and returns nonzero on failure; *out_painted (may be NULL)
 * gets the brushed texels. */
int pgt_ivy_scene_paint(pgt_ivy_scene *s, const char *verb, const float *points,
                        uint32_t point_count, const uint32_t *first, uint32_t strokes, float radius,
                        uint32_t threads, int forbid, uint64_t *out_painted);

/* Writes strokes as a --paint file ('stroke' and 'point X Y Z' lines, %.9g). */
int pgt_ivy_write_strokes(const char *verb, const char *path, const float *points,
                          const uint32_t *first, uint32_t strokes);

/* Frees everything; a zeroed scene is a no-op. */
void pgt_ivy_scene_free(pgt_ivy_scene *s);

#endif
