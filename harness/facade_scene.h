/* pgt harness: facade scene files (issue 6): a city of buildings for pgt facade, read and written
 * as text. The format (harness/README.md, "Facade scene files"), one statement per line, '#'
 * starts a comment:
 *   grammar NAME PATH
 *   building NAME BASE HEIGHT SEED RRGGBB [PARAM=VALUE ...] : X0 Z0 X1 Z1 X2 Z2 ...
 * PATH is relative to the scene file's folder (or absolute); NAME in a building is a grammar
 * declared on an earlier line. A building's params start from its grammar's values and each
 * PARAM=VALUE overrides one as pgt_grammar_set_param does (the params defined from it follow
 * unless given too). The corners are the footprint's (x, z) pairs, clockwise seen from above
 * (facade.h). This file only needs ref_cpu, so pgt_datasets compiles it too. */
#ifndef PGT_FACADE_SCENE_H
#define PGT_FACADE_SCENE_H

#include <stdint.h>

#include "pgt/facade.h"
#include "pgt/grammar.h"
#include "pgt/result.h"

/* Longest line of a scene file: a footprint of ~1000 corners at 9 significant digits. */
#define PGT_FACADE_FILE_MAX_LINE 65536u
/* Most grammars of one scene file. */
#define PGT_FACADE_FILE_MAX_GRAMMARS 256u
/* Most buildings of one scene file (a 16M-building city is far beyond the paper's 10K facades
 * and bounds a mistaken file's memory). */
#define PGT_FACADE_FILE_MAX_BUILDINGS (1u << 24)
/* Most corners of one footprint, and of the scene. */
#define PGT_FACADE_FILE_MAX_FOOTPRINT 4096u
#define PGT_FACADE_FILE_MAX_CORNERS (1u << 26)

/* A scene with the grammars it owns. scene.grammars points at grammars; names[k] and paths[k]
 * are grammar k's NAME and the path it was loaded from (malloc'd). */
typedef struct pgt_facade_file {
    pgt_facade_scene scene;
    uint32_t grammar_count;
    pgt_grammar *grammars;
    char **names;
    char **paths;
    uint32_t *building_lines; /* each building's line in the file pgt_facade_file_read read
                                 (for messages); NULL for scenes made otherwise */
} pgt_facade_file;

/* Reads a scene file; every malformed line is PGT_ERROR_PARSE (syntax) or
 * PGT_ERROR_INVALID_ARGUMENT (meaning) with "PATH:LINE: ..." (a grammar's own errors keep their
 * FILE:LINE:COL after it); then each building goes through pgt_facade_scene_check, named by its
 * PATH:LINE. A file without buildings is an error. On failure *out is freed and zeroed. */
pgt_result pgt_facade_file_read(pgt_facade_file *out, const char *path, pgt_error *err);

/* Loads one grammar into f (a scene without buildings yet): name as in `grammar NAME PATH`,
 * path as it is opened. For scenes made in memory (pgt_gen_city) before writing them. */
pgt_result pgt_facade_file_add_grammar(pgt_facade_file *f, const char *name, const char *path,
                                       pgt_error *err);

/* Writes s as a scene file at path (a temporary file renamed over it). grammar k is written as
 * `grammar names[k] P` with P the path of paths[k] relative to the folder of read_path (where
 * the file will be read from: a caller that writes under a staging name and renames it later,
 * pgt_cli_stage, names the final path; NULL: path) when both resolve (realpath), else paths[k]
 * as given. A building lists the params whose values differ from
 * what the reader would give without them, at 9 significant digits (the same floats come
 * back). comment (may be NULL) is written as '#' lines at the top. */
pgt_result pgt_facade_file_write(const char *path, const char *read_path, const pgt_facade_scene *s,
                                 const char *const *names, const char *const *paths,
                                 const char *comment, pgt_error *err);

/* Frees everything; a zeroed file is a no-op. */
void pgt_facade_file_free(pgt_facade_file *f);

/* Bounding box of the scene's buildings (footprints extruded from base to base + height):
 * lo[3], hi[3]. 0 when there are no buildings. */
int pgt_facade_file_bounds(const pgt_facade_scene *s, float lo[3], float hi[3]);

/* A city of n buildings from seed (datasets_gen's pgt_gen_city) with the grammar at
 * grammar_path, named after the file ("facade" for facade.grammar). On failure *out is freed. */
pgt_result pgt_facade_file_city(pgt_facade_file *out, const char *grammar_path, uint32_t n,
                                uint32_t seed, pgt_error *err);

/* The default camera of pgt facade: looks at the centre of the scene's bounding box from
 * azimuth PGT_FACADE_VIEW_AZIMUTH (0 = from +z, growing toward +x) and elevation
 * PGT_FACADE_VIEW_ELEVATION degrees, at the distance where the bounding sphere (half the box's
 * diagonal) fills the vertical field of view PGT_FACADE_VIEW_FOV (the horizontal one when the
 * picture is taller than wide) with PGT_FACADE_VIEW_MARGIN around it; up is +y: an aerial
 * view of the whole city like paper 003 Fig. 1a. */
#define PGT_FACADE_VIEW_AZIMUTH 30.0
#define PGT_FACADE_VIEW_ELEVATION 35.0
#define PGT_FACADE_VIEW_FOV 45.0f
#define PGT_FACADE_VIEW_MARGIN 1.02
void pgt_facade_default_view(const pgt_facade_scene *s, uint32_t width, uint32_t height,
                             float eye[3], float at[3], float up[3], float *fov_deg);
/* The same view of the box [lo, hi] (pgt facade --mesh: the mesh's bounding box). */
void pgt_facade_box_view(const float lo[3], const float hi[3], uint32_t width, uint32_t height,
                         float eye[3], float at[3], float up[3], float *fov_deg);

/* The default point light: above the scene, PGT_FACADE_LIGHT_OFFSET times the bounding
 * radius from the box's centre (up and to one side, so that facades facing different ways get
 * different shades). */
#define PGT_FACADE_LIGHT_OFFSET_X (-0.8)
#define PGT_FACADE_LIGHT_OFFSET_Y 2.0
#define PGT_FACADE_LIGHT_OFFSET_Z 1.2
#define PGT_FACADE_DEFAULT_AMBIENT 0.25f
void pgt_facade_default_light(const pgt_facade_scene *s, float light[3]);
void pgt_facade_box_light(const float lo[3], const float hi[3], float light[3]);

/* The scene of pgt facade --mesh (paper 003 sec. 10): the grammar at grammar_path (named
 * "mesh") and one building without footprint (its facades come from the quads of m,
 * pgt_facade_mesh_facades): the grammar's param values, seed, wall colour
 * PGT_FACADE_MESH_COLOUR, base and height the mesh's extent in y; the built-in geometry images
 * (pgt_facade_add_builtin_gimages: Mesh(0) is the oculus). On failure *out is freed. */
#define PGT_FACADE_MESH_COLOUR 0xD8C8B0u
pgt_result pgt_facade_file_mesh(pgt_facade_file *out, const char *grammar_path, uint32_t seed,
                                const pgt_facade_quads *m, pgt_error *err);

#endif
