/* pgt: building a multi-chart geometry-image atlas with indirection pointers from a mesh with
 * per-corner UVs (paper 000, sections 4 and 5.2). The result follows the contract of atlas.h.
 *
 * Stages (one source file each, timed separately):
 *   charts   (atlas_charts.c)   faces joined across edges whose two corners carry the same UV;
 *                               mirrored charts flipped, degenerate UV triangles skipped
 *   layout   (atlas_layout.c)   keep the input UVs when every corner lies `band` texels inside
 *                               the image and the rasterized charts keep the free band from each
 *                               other at this resolution, else repack (one global scale so the
 *                               3D size of a texel is the same in every chart, minimum-area
 *                               rotation, skyline packing)
 *   raster   (atlas_raster.c)   P, N, chart per texel centre covered by a chart triangle,
 *                               and in the narrow cracks of seams inside a chart
 *                               (PGT_ATLAS_CRACK_TEXELS)
 *   pointers (atlas_pointers.c) outer-boundary texels -> nearest inner-boundary texel of another
 *                               chart in 3D (kd-tree, kdtree.h), or dead end
 *   angles   (atlas_angles.c)   the rotation `rot` of each indirection texel from boundary walks
 *                                (5.2), or fitted to the Jacobians (--angles jacobian)
 *
 * Decisions (the issue leaves them open):
 * - Mirrored charts (negative total UV area) are flipped in u inside their own UV bounding box
 *   (u' = umin + umax - u) on load and counted in stats.mirrored_charts; single fold-over faces
 *   inside a chart of positive area are rasterized as they are (their texels are still covered).
 * - A degenerate UV triangle (|UV area| <= PGT_ATLAS_DEGENERATE_UV_AREA) is counted in
 *   stats.degenerate_faces and not rasterized; it still joins its neighbours into one chart. A
 *   chart made only of degenerate triangles is dropped (stats.degenerate_charts).
 * - Charts that overlap in the input UVs, or UVs that leave [0,1] (or come nearer than the band
 *   to the image border), make the layout repack; there is no error for them. Fold-overs inside
 *   one chart cannot be fixed by repacking: the smallest face id wins a texel.
 * - Vertex normals are the area-weighted face normals averaged per vertex index (pgt_mesh holds
 *   no normals).
 * - rot: with t1 (source) and t2 (destination) the boundary tangents of 5.2, rot is the signed
 *   angle from t1 to t2 in texel coordinates, measured from +x towards +y (x right, y down). A
 *   marcher applies it to a direction (dx, dy) in texel units as
 *       dx' = cos(rot) dx - sin(rot) dy,   dy' = sin(rot) dx + cos(rot) dy.
 *   t1 sums the steps of a walk of K texels both ways along the source chart's outer ring,
 *   t2 the steps between the pointers of the same texels (those that point into the
 *   destination chart), so both describe the same piece of the seam with the same
 *   orientation, and a direction leaving the source chart enters the destination chart
 *   (atlas_angles.c: how and why this differs from the paper's two independent one-way
 *   walks, which remain the fallback).
 *
 * Everything is deterministic for any thread count. */
#ifndef PGT_ATLAS_BUILD_H
#define PGT_ATLAS_BUILD_H

#include <stdint.h>

#include "atlas.h"
#include "image.h"
#include "mesh.h"
#include "progress.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Default atlas side (the paper's Table 1 uses 1024^2). */
#define PGT_ATLAS_DEFAULT_RES 1024u

/* Smallest atlas side: a chart needs one inner texel with the free band on both sides. */
#define PGT_ATLAS_MIN_RES (2u * PGT_ATLAS_MIN_BAND + 1u)

/* Largest atlas side: the image module's limit (pgt_image_create refuses more). The image's
 * value limit binds first for square atlases: 11 channels of 4939^2 texels is the most
 * PGT_IMAGE_MAX_VALUES (2^28) holds. */
#define PGT_ATLAS_MAX_RES PGT_IMAGE_MAX_SIDE
#define PGT_ATLAS_MAX_SQUARE_RES 4939u

/* Largest free band (a band of a quarter of the smallest useful atlas side is already absurd). */
#define PGT_ATLAS_MAX_BAND 64u

/* Boundary texels followed per tangent in 5.2 (the paper's K; Fig. 7 shows 4). */
#define PGT_ATLAS_DEFAULT_K 4u
#define PGT_ATLAS_MAX_K 64u

/* How rot is computed (pgt_atlas_options.angles, flag --angles):
 * - PGT_ATLAS_ANGLES_TANGENTS: 5.2's boundary tangents (above; the paper's rule, the default);
 * - PGT_ATLAS_ANGLES_JACOBIAN: fitted per indirection texel to P's Jacobians on the two sides
 *   (atlas_angles.c): the angle that turns the most of PGT_ATLAS_FIT_HEADINGS headings leaving
 *   the chart by at most PGT_ATLAS_FIT_TURN_DEG in 3D; 5.2's angle where no Jacobian exists.
 *   Same form (one angle per texel in rot), same marcher. */
typedef enum pgt_atlas_angles {
    PGT_ATLAS_ANGLES_TANGENTS = 0,
    PGT_ATLAS_ANGLES_JACOBIAN = 1
} pgt_atlas_angles;

/* Headings per texel of the Jacobian fit, spread around the way out as a uniform flux of walkers
 * crosses a seam. 8, 16 and 32 give the same median turn at jumps within 0.4 degrees on the
 * shared meshes (tests/test_march.c, measured before the fit moved here); 8 costs a quarter. */
#define PGT_ATLAS_FIT_HEADINGS 8u
/* The turn the fit's arcs allow, in degrees: issue 4's bound on the median turn at jumps. A
 * heading turned by less counts, whatever by. */
#define PGT_ATLAS_FIT_TURN_DEG 10.0

/* Dead-end threshold in texel sizes: an outer-boundary texel whose nearest candidate is farther
 * than this is a dead end. Across a seam the candidate lies within about 1.5 texel sizes (half
 * a texel on each side plus the diagonal), so 4 leaves room for parametric distortion while a
 * mesh border (nothing on the other side) is refused. The texel size here is the larger of the
 * atlas's (pgt_atlas_texel_size, the median) and the local one at the source (the largest 3D
 * step between its adjacent inner-boundary texels and their 4-neighbours): where a chart is
 * stretched, its seam partner lies several median texel sizes away. The reach counts on both
 * sides: a candidate farther than that is still taken when it lies within this many of its own
 * local texel sizes (up to 8 times the source's reach), for seams whose two sides have texels
 * of very different 3D size (spot's leg caps: 8-13 times); not for an outer texel within 1.5
 * texels of a mesh-border edge, where nothing lies across. */
#define PGT_ATLAS_DEFAULT_DEAD_END 4.0f

/* Largest dead-end threshold (texel sizes; --dead-end). A seam's partner lies within 1.5 of the
 * coarser side's texel sizes, and the far reach above takes sides 8 times apart; 64 takes 40
 * times. Beyond it the search only grows: every outer texel of an open border tests every texel
 * of its own chart within the reach, each along its texel line (cost ~ reach^2 per texel):
 * --dead-end 1000 on a 16 x 16 grid sheet took 17.7 s at --res 512 (64 at 4096: 1.4 s). */
#define PGT_ATLAS_MAX_DEAD_END 64.0f

/* A chart seamed to itself: a candidate texel of the source texel's own chart is allowed only
 * when the way to it THROUGH the chart is more than twice the way through space (a cylinder cut
 * open inside one chart; a slit cut inside a chart whose sides are glued), measured along the
 * texel line from the source's nearest adjacent inner texel (atlas_pointers.c). When that line
 * stays inside the chart, the candidate must also lie farther than this (Euclidean, in texels)
 * from the source texel: the source's own inner neighbours are 1 to sqrt(2) texels away and
 * the band is >= 2, so anything within 4 texels along the chart is the same side of the same
 * boundary. A mesh border squeezed by its parametrization (many texels per unit of 3D length
 * along it) fails the path test: it stays a dead end. */
#define PGT_ATLAS_SELF_SEAM_MIN_TEXELS 4.0f

/* A seam inside one chart (an edge whose two faces are in the chart with other UVs on the two
 * sides: a slit cut into the chart, the tip of a cut) leaves a crack between the two texel-space
 * copies of the edge, with no 3D width: both copies are the same 3D edge. Where the copies lie
 * at most this many texels apart, the texels of the crack that no triangle covers are filled
 * (inner texels of the chart, P on the 3D edge, atlas_raster.c): an outer texel there would
 * touch both sides, and one pointer cannot lead a walker from either side to the other (every
 * candidate is its own side's, refused; bob_tri's slits made 52 dead ends on a closed mesh).
 * Two copies 2 texels apart across a diagonal leave texels touching both sides (8-adjacency
 * reaches sqrt(2) across), 3 covers that; farther apart the crack's outer texels each touch one
 * side and point across it (PGT_ATLAS_SELF_SEAM_MIN_TEXELS). */
#define PGT_ATLAS_CRACK_TEXELS 3.0f

/* A UV triangle whose area (in UV units squared, as a double) is at most this is degenerate:
 * it covers no texel centre at any supported resolution (16384^2 texels: a texel is 3.7e-9 in
 * UV area; 1e-14 is a sliver far thinner than any texel) and its barycentrics are unstable. */
#define PGT_ATLAS_DEGENERATE_UV_AREA 1e-14

/* A zero-initialised struct means the defaults. */
typedef struct pgt_atlas_options {
    uint32_t width, height; /* atlas size in texels; 0: PGT_ATLAS_DEFAULT_RES (flag --res) */
    uint32_t band;          /* free band in texels; below PGT_ATLAS_MIN_BAND is raised (--band) */
    uint32_t k;             /* 5.2's K; 0: PGT_ATLAS_DEFAULT_K (--k) */
    float dead_end;         /* texel sizes; 0: PGT_ATLAS_DEFAULT_DEAD_END (--dead-end) */
    uint32_t threads;       /* worker threads; 0: 1 (--threads) */
    int force_repack;       /* nonzero: repack even when the input UVs would do */
    pgt_atlas_angles angles; /* how rot is computed; 0: 5.2's tangents (--angles) */
    const char *what;       /* names the input in messages (a file name); NULL: "mesh" */
    pgt_progress *progress; /* optional: names each step as a stage (pgt/progress.h) */
    const struct pgt_mesh_origin *origin; /* optional (pgt/mesh_io.h): a vertex error names the
                                             line (or offset) of its record in `what` */
} pgt_atlas_options;

typedef struct pgt_atlas_stats {
    uint32_t width, height, band, k;
    uint32_t faces;             /* mesh faces */
    uint32_t charts;            /* charts in the atlas (ids 0 .. charts-1) */
    uint32_t mirrored_charts;   /* charts flipped in u on load */
    uint32_t degenerate_faces;  /* UV triangles skipped */
    uint32_t degenerate_charts; /* charts of degenerate triangles only (dropped) */
    uint32_t empty_charts;      /* charts that cover no texel centre at this resolution */
    uint32_t fold_over_texels;  /* texels covered by two triangles of one chart */
    uint32_t crack_texels;      /* texels filled in the cracks of seams inside a chart */
    uint32_t overlap_texels;    /* input layout only: texels covered by two charts (not
                                   measured, 0, when the input triangles' boxes cover the image
                                   more than 32 times: repacked without the coverage raster) */
    int repacked;               /* 0: input UVs kept; 1: charts repacked */
    double packing_efficiency;  /* inner texels / (width * height) */
    double uv_scale;            /* repacked: texels per unit of 3D length; 0 when kept */
    uint32_t inner_texels, inner_boundary_texels;
    uint32_t indirection_texels, dead_end_texels;
    uint32_t self_seam_pointers; /* indirection texels pointing into their own chart */
    /* of those, the outer texels that found nothing across away from the mesh border and any
     * gap and point into their own chart instead of being dead ends (a slit's closed end, where
     * its two sides are joined: not the paper's rule, which would stop there) */
    uint32_t own_chart_pointers;
    uint32_t fitted_angles;      /* --angles jacobian: indirection texels whose rot was fitted
                                    (the others keep 5.2's) */
    double texel_size;           /* median 3D distance of 4-adjacent inner texels (one chart) */
    double ms_charts, ms_layout, ms_raster, ms_pointers, ms_angles, ms_total;
} pgt_atlas_stats;

/* Builds the atlas of `mesh` into *out (a new pgt_image with the PGT_ATLAS_CHANNEL_NAMES
 * channels in that order; free it with pgt_image_destroy). options may be NULL (defaults);
 * out_stats may be NULL. On failure *out is zeroed. Errors:
 * - PGT_ERROR_UNSUPPORTED: the mesh has no UVs ("no UVs: ...");
 * - PGT_ERROR_EMPTY: no faces, or every UV triangle is degenerate;
 * - PGT_ERROR_INVALID_ARGUMENT: a size below PGT_ATLAS_MIN_RES, a band above
 *   PGT_ATLAS_MAX_BAND, k outside 1..PGT_ATLAS_MAX_K, a dead-end threshold not finite, <= 0
 *   or above PGT_ATLAS_MAX_DEAD_END
 *   (each message names the flag: --res, --band, --k, --dead-end), non-finite positions/UVs,
 *   a coordinate beyond +-PGT_ATLAS_MAX_COORD, an angles value not in pgt_atlas_angles
 *   (--angles);
 * - PGT_ERROR_LIMIT: a size above PGT_ATLAS_MAX_RES (--res), charts that cannot be packed with
 *   the band at this resolution (message says which --res would be needed, if any), or no
 *   chart covering a texel centre (an atlas without inner texels, which pgt march refuses);
 * - PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_atlas_build(pgt_image *out, const pgt_mesh *mesh, const pgt_atlas_options *options,
                           pgt_atlas_stats *out_stats, pgt_error *err);

/* The texel size of an atlas: median 3D distance between 4-adjacent inner texels of the same
 * chart (0 when there are none). Deterministic; used for the dead-end threshold and tests. */
double pgt_atlas_texel_size(const pgt_image *atlas, const pgt_atlas_channels *ch);

#ifdef __cplusplus
}
#endif

#endif
