/* pgt: multi-chart geometry-image atlas with indirection pointers (paper 000, sections 4-5).
 *
 * An atlas is a pgt_image (image.h) of PGT_ATLAS_CHANNEL_COUNT float channels with exactly
 * these names, the contract between the builder (atlas_*.c), the marcher (march.c), the GPU
 * backends and the files `pgt atlas` writes (OpenEXR, named channels):
 *
 *   P.x P.y P.z   3D surface position of the texel (inner and indirection texels; 0 otherwise)
 *   N.x N.y N.z   unit surface normal (inner texels; 0 otherwise)
 *   chart         chart id (0..charts-1) of an inner texel, or of the chart whose outer boundary
 *                 an indirection / dead-end texel lies on; -1 on background
 *   kind          PGT_TEXEL_* below
 *   ptr.u ptr.v   indirection texels: the texel coordinates (column x, row y, whole numbers) of
 *                 the inner-boundary texel of another chart (or of the same chart far away in
 *                 texture space, across a seam inside one chart) that it points to; -1 otherwise
 *   rot           indirection texels: the angle (radians, counter-clockwise in texel space) by
 *                 which a marching direction is rotated when jumping through this texel (5.2);
 *                 0 otherwise
 *
 * Texel space: column x grows to the right, row y grows downwards (row 0 is the first row of
 * the image, as EXR and PNG store them); texel (x, y) covers [x, x+1) x [y, y+1) and its centre
 * is (x + 0.5, y + 0.5). A mesh UV (u, v) maps to texel space as (u * W, (1 - v) * H).
 *
 * Inner texel: a texel whose centre a (non-degenerate) chart triangle covers. Inner-boundary
 * texel: an inner texel with a 4-neighbour that is not an inner texel of its chart.
 * Indirection texel (outer boundary): a non-inner texel 8-adjacent to an inner texel of exactly
 * one chart. Dead end: such a texel with no candidate within the dead-end threshold, counted in
 * texel sizes of either side of the seam (open meshes: the mesh border). The layout keeps a free
 * band of at least PGT_ATLAS_MIN_BAND texels around every chart, so an outer-boundary texel never
 * touches two charts. */
#ifndef PGT_ATLAS_H
#define PGT_ATLAS_H

#include <stdint.h>

#include "image.h"
#include "mesh.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PGT_ATLAS_CHANNEL_COUNT 11u

/* The channel names, in this order in a pgt_image made by the builder (files store them sorted:
 * always look them up by name, see pgt_atlas_channels()). */
#define PGT_ATLAS_CHANNEL_NAMES                                                                    \
    { "P.x", "P.y", "P.z", "N.x", "N.y", "N.z", "chart", "kind", "ptr.u", "ptr.v", "rot" }

enum {
    PGT_TEXEL_BACKGROUND = 0,
    PGT_TEXEL_INNER = 1,
    PGT_TEXEL_INDIRECTION = 2,
    PGT_TEXEL_DEAD_END = 3
};

/* Largest |coordinate| of a 3D position in an atlas (and of a mesh given to the builder): squared
 * 3D distances (kd-tree, texel size, the march's step lengths) are float, and the square of a
 * distance across 2e18 in three axes, 1.2e37, stays below FLT_MAX (3.4e38); at 1.8e19 it
 * overflows and every pointer, texel size and Jacobian turns into inf. */
#define PGT_ATLAS_MAX_COORD 1e18f

/* Smallest free band around a chart, in texels (the paper's one pixel, plus one so that a
 * one-ring search around an outer-boundary texel never meets another chart). */
#define PGT_ATLAS_MIN_BAND 2u

/* Indices of the channels of an atlas image, looked up by name. */
typedef struct pgt_atlas_channels {
    uint32_t px, py, pz, nx, ny, nz, chart, kind, ptr_u, ptr_v, rot;
} pgt_atlas_channels;

/* Finds every channel by name; PGT_ERROR_PARSE naming the first missing channel (and `what`,
 * e.g. the file name) when the image is not an atlas. */
pgt_result pgt_atlas_channels_find(const pgt_image *atlas, const char *what,
                                   pgt_atlas_channels *out, pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
