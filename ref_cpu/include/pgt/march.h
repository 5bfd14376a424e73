/* pgt: marching on a multi-chart geometry-image atlas across charts (paper 000, section 5).
 *
 * This work is based on:
 *   Paper 000, "on-mesh growth of shape grammars": sec. 5 (the marching rule, the four cases of
 *   Fig. 3), 5.1 (best indirection pixel, Fig. 5) and 5.2 (rotation of marching directions; the
 *   angle itself is precomputed by the atlas builder into the `rot` channel, atlas.h).
 *
 * A walker lives in texel space (atlas.h: x right, y down, texel (i, j) covers [i, i+1) x
 * [j, j+1)): a continuous position (x, y) that is always inside an inner texel of `chart`, and a
 * unit direction (dx, dy) in texel units. One step of `length` texels (the marching rule's image-
 * space length) aims at P_dest_hat = P_cur + length * d and resolves the texel found there:
 *
 *   1. inner texel of the same chart: P_dest = P_dest_hat (event INNER);
 *   2. indirection texel P0 of the same chart: jump to the centre of the texel its pointer
 *      names, rotate d (event JUMP), and walk what is left of the step (below);
 *   3. background (or outside the image): binary search along ]P_cur, P_dest_hat[ for an
 *      indirection texel P0 of the current chart, jump through it and walk what is left with the
 *      rotated direction (event SEARCH);
 *   4. a texel of another chart (inner, indirection or dead end): as 3, every texel that is not
 *      the current chart's counts as background.
 *
 * What is left after a jump is measured in 3D: the step was to cover L3 = length |J d| on the
 * surface (J: P's finite-difference Jacobian where the walker stands, so |J d| is the 3D length
 * of one texel of travel along d); the jump covered |pos(ref) - pos(P_cur)| when pos(ref) lies
 * ahead, nothing when the texel-quantised pointer lands behind; the rest, L3 - covered, is
 * walked in the destination chart as (L3 - covered) / |J' d'| of its texels. So a step crossing
 * charts is as long on the surface as one inside a chart, whatever the two charts' texel sizes
 * (kept input UVs, parametric distortion: spot's seams join texels 3 to 6 times apart). The
 * paper's case 2 takes P_dest = ref(P_dest_hat) and stops there; a pointer names the inner-
 * boundary texel nearest to the inner boundary next to P0, about a texel behind P0's centre, so
 * stopping would shorten every case-2 step by about a texel: case 2 walks the rest too, and
 * cases 2 and 3 differ only in how P0 is found. The walk after a jump may meet case 2, 3 or 4
 * in the destination chart, so one step may cross several charts: an explicit loop of at most
 * PGT_MARCH_MAX_JUMPS jumps (no recursion).
 *
 * Best indirection texel (5.1): P_near is the inner texel of the current chart nearest to P0 (in
 * its one-ring); r = pos(P_near) - pos(P_cur); among the indirection texels P_i of the current
 * chart in the one-ring of P_near (P0 among them), the one whose c_i = pos(ref(P_i)) - pos(P_cur)
 * has the largest cosine with r; P0 on ties, and when P_near is P_cur's texel.
 *
 * Direction at a jump (5.2): rotated by the angle the builder stored in the indirection texel's
 * rot (PGT_MARCH_ROTATION_ATLAS, the paper, default), or, beyond the paper, the destination
 * texel direction with the same 3D motion (PGT_MARCH_ROTATION_JACOBIAN, see below).
 *
 * No bounce (beyond the paper): a walker remembers the inner texel it stood on when it last
 * jumped, its direction right after that jump, and how many of its latest jumps in a row were
 * bounces (pgt_march_state.from, in_dx, in_dy, bounces). A jump bounces when it lands within
 * PGT_MARCH_BOUNCE_TEXELS of that texel: it sends the walker back where it came from, with no
 * progress. Pointers to the nearest inner-boundary texel in 3D do that wherever what lies
 * beyond a boundary is narrower than a texel: charts that meet at a mesh vertex, whose corner
 * texels lie within a texel of each other there (a pointer from A's corner names B's corner,
 * and B's outer texels around it all name A's corner, though B lies beside A, not across its
 * boundary); the tip of a chart in a notch of another; a chart one texel thick, or a slit
 * inside a chart; the corner of a mesh border. A walker then goes back and forth between the
 * same few texels for ever: on pizza.obj (4740 charts, 1987 of them single triangles a few
 * texels wide) such cycles held 46 % of the steps of long marches. Two rules:
 * 1. While the walker still heads the way it arrived (a positive dot product of d with in_dx,
 *    in_dy: the rule's angle did not turn it back), 5.1 does not choose a bouncing jump: its
 *    candidates (P0 and the indirection texels around P_near) are ranked as 5.1 ranks them
 *    (c_i against r; where 5.1 has no r, P_near being P_cur's texel, the texel offset from the
 *    walker to P_i against d) and the first that does not bounce is taken.
 * 2. A bounce that remains (no such candidate, 5.1 off, or the walker turned back on purpose)
 *    is taken; a walker may take PGT_MARCH_MAX_BOUNCES of them in a row (a jump that does not
 *    bounce resets the count), the next one stops the march (PGT_MARCH_STOP_BOUNCE): the atlas
 *    offers no way on there.
 * Where three charts meet at a corner, a walker that B sends straight back to A is taken back
 * (rule 2) and, heading out of A again, avoids B and finds the third chart (rule 1): no walker
 * stops at the cube-sphere's corners. A state without memory (from = 0, e.g. {x, y, dx, dy,
 * chart}) has no jump to bounce from.
 *
 * The walker never leaves the image and never stands on anything but an inner texel: a dead-end
 * texel, a search that finds no indirection texel of the current chart, more than
 * PGT_MARCH_MAX_JUMPS jumps in one step, one bounce more than PGT_MARCH_MAX_BOUNCES, or a
 * destination the condition rejects (external contexts: a mask image, a callback such as
 * pgt_march_density_condition, sampled at the destination) end the march with event STOP and the
 * state unchanged.
 *
 * Rotation convention (atlas.h: "the angle, counter-clockwise in texel space"; atlas_build.h):
 * a direction (dx, dy) becomes (dx cos a - dy sin a, dx sin a + dy cos a) in texel coordinates,
 * i.e. it turns from +x towards +y (+y is down in the image, so on screen this turns clockwise).
 *
 * Layout: pgt_march_atlas_create validates the atlas once (so the inner loop needs no checks)
 * and builds four texel-indexed arrays, as a GPU kernel would bind four textures: the packed
 * kind-and-chart codes alone, 4 bytes per texel (the case tests and the search read only these,
 * so a step without the position touches a quarter of the memory), P interleaved with the code,
 * 16 bytes per texel (the bilinear position), one 8-byte jump record per texel (the
 * indirection texels' pointer and rot, which a jump reads in one place instead of three image
 * planes) and a 2-byte ring mask per texel (which one-ring neighbours are inner or indirection
 * texels of the texel's chart: 5.1 and the Jacobians read one mask instead of eight codes).
 * Walkers of a batch are flat arrays (SoA). float32 throughout. */
#ifndef PGT_MARCH_H
#define PGT_MARCH_H

#include <stdint.h>

#include "atlas.h"
#include "image.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most chart crossings in one step: a step shorter than a chart crosses one, rarely two (a chart
 * corner); 16 leaves room for tiny charts (the pizza atlas has 1987 single-triangle charts, a
 * few texels each) while stopping a walker that longer cycles of pointers (three charts or more;
 * two are a bounce, below) send round and round within one step. */
#define PGT_MARCH_MAX_JUMPS 16u

/* A jump bounces (see "No bounce" above) when it lands within this many texels (Chebyshev, in
 * both axes) of the texel the walker's last jump left from: a pointer names an inner-boundary
 * texel, so one that leads straight back lands on the texel the walker left or on one of its 8
 * neighbours (on pizza, 96.8 % of the jumps of the trapped walkers' cycles did). Measured with
 * pizza's long marches (tests/test_march.c, the atlas's rot / the Jacobian rotation): 0 (that
 * texel only) leaves 16 / 20 % of the steps trapped, 1 leaves 0.07 / 0.02 %, 2 leaves 0.22 /
 * 0.03 % and shortens the marches that end at dead ends (592 steps on average instead of 656). */
#define PGT_MARCH_BOUNCE_TEXELS 1u

/* Bounces a walker may take in a row (rule 2 of "No bounce"). A few bounces are passing: a
 * walker grazing a seam, or at a chart corner, may bounce once or twice and go on (the rules
 * cannot tell in advance); a trapped walker bounces once or twice per step for ever. Measured
 * (pizza's marches of tests/test_march.c; pgt bench march's 16384 walkers x 1000 steps): with
 * 2, 365 of pizza's 3000 short marches without 5.1 stop at a bounce, 139 with 8; 16 leaves 0.8 %
 * of pizza's long marches trapped with the Jacobian rotation (0.02 % with 8): a pair bouncing
 * within one step reaches PGT_MARCH_MAX_JUMPS first. With 8, 66 of human_neutral's bench
 * walkers stop at a bounce, of 706 stops (before the rule 677, 34 of them too many jumps). */
#define PGT_MARCH_MAX_BOUNCES 8u

/* Halvings of the binary search of cases 3/4: the bracket starts at the step length (at most
 * PGT_MARCH_MAX_LENGTH texels, 2^15) and must shrink below one texel to reach the boundary texel
 * in the worst case; 2^-8 texel below that the texels at both ends are neighbours for sure. */
#define PGT_MARCH_SEARCH_ITERATIONS 24u

/* Longest step, in texels: the largest image side (PGT_IMAGE_MAX_SIDE, 16384) times ~2 covers any
 * segment inside an image; longer steps are a caller error. */
#define PGT_MARCH_MAX_LENGTH 32768.0f

/* Largest ratio of source to destination texel size (3D length of one texel of travel) trusted
 * at a jump. Neighbouring charts differ by a few times at most (spot's seams, the worst here:
 * 3 to 6). A finite-difference texel size over a sliver or a degenerate triangle can be ~0 and
 * would blow the remaining length up: beyond 8x, 8 destination texels per source texel left. */
#define PGT_MARCH_MAX_LENGTH_RATIO 8.0f

/* Smallest squared sine of the angle between the two columns of a destination Jacobian that
 * the Jacobian rotation trusts: below ~3 degrees the texel is a sliver of a nearly degenerate
 * triangle and its inverse would amplify the finite differences' noise ~20 times. */
#define PGT_MARCH_MIN_JACOBIAN_SINE2 0.0025f
/* The Jacobians' largest component within which the Jacobian rotation takes them as they are:
 * their 4th power (its determinant) stays in [1e-24, 1e24], far inside float's normal range
 * even times PGT_MARCH_MIN_JACOBIAN_SINE2 (a mesh 1e-3 across at 1024^2 has texels of 1e-6). */
#define PGT_MARCH_JACOBIAN_SCALE_MIN 1e-6f
#define PGT_MARCH_JACOBIAN_SCALE_MAX 1e6f

/* Default mask threshold: a destination whose mask value is >= this rejects the step (a mask is
 * painted 0 = free, 1 = blocked; 0.5 is the midpoint of an 8-bit or float mask). */
#define PGT_MARCH_MASK_THRESHOLD 0.5f

typedef enum pgt_march_event {
    PGT_MARCH_INNER = 0,  /* case 1 only: the step stayed in its chart */
    PGT_MARCH_JUMP = 1,   /* a jump through an indirection texel landed on (case 2), no search */
    PGT_MARCH_SEARCH = 2, /* at least one binary search (cases 3/4) */
    PGT_MARCH_STOP = 3    /* dead end, no indirection found, too many jumps, or rejected */
} pgt_march_event;

/* Lower-case names "inner", "jump", "search", "stop" (the CSV of pgt march). */
const char *pgt_march_event_name(pgt_march_event e);

/* Packed per-texel code: kind in bits 0-1, chart + 1 in bits 2-31 (0 on background). */
#define PGT_MARCH_CODE(kind, chart) ((uint32_t)(kind) | ((uint32_t)((chart) + 1) << 2))
#define PGT_MARCH_MAX_CHARTS (1u << 29)

/* One texel as the marcher reads it: P and the packed code in 16 bytes, so a step's bilinear
 * position touches one cache line per texel row instead of four (the image's planar layout:
 * measured 4.2 -> see the report's steps/s), the layout of one RGBA32 texture. */
typedef struct pgt_march_texel {
    float x, y, z;
    uint32_t code; /* PGT_MARCH_CODE(kind, chart) */
} pgt_march_texel;

/* The jump data of an indirection texel (zero elsewhere): the inner texel its pointer names,
 * as texel coordinates (ptr.u, ptr.v; an image side is at most PGT_IMAGE_MAX_SIDE, 16384, so
 * 16 bits hold them), and its rot, in the 8 bytes of one RG32 texel. */
typedef struct pgt_march_jump {
    uint16_t u, v;
    float rot;
} pgt_march_jump;

/* Bit k of a ring mask stands for texel t's one-ring neighbour k in scan order: (-1, -1),
 * (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1) (rows top to bottom); the edge
 * neighbours are bits 1, 3, 4, 6. */
#define PGT_MARCH_RING_EDGES 0x5Au

/* A validated atlas ready for marching. `texels`, `codes`, `jumps` and `rings` (width * height
 * each, row-major) are owned; codes[i] == texels[i].code. The view keeps nothing of the image. */
typedef struct pgt_march_atlas {
    uint32_t width, height;
    uint32_t chart_count; /* 1 + the largest chart id */
    pgt_march_texel *texels;
    uint32_t *codes;       /* the codes alone: what the case tests and the search read */
    pgt_march_jump *jumps; /* per texel; meaningful on indirection texels */
    /* Which one-ring neighbours share texel i's chart, precomputed as a GPU upload would be:
     * bits 0-7 (PGT_MARCH_RING_EDGES above) the inner texels of i's chart, bits 8-15 its
     * indirection texels; 0 on background. The rules of 5.1, the Jacobians and
     * pgt_march_position near a chart's rim read one mask instead of the neighbours' codes,
     * each with its own bounds test. */
    uint16_t *rings;
} pgt_march_atlas;

/* Validates `atlas` against atlas.h and builds the view. Errors (PGT_ERROR_PARSE, messages start
 * with `what`, e.g. the file name): a missing channel (pgt_atlas_channels_find's message); a
 * non-integer or out-of-range kind or chart; an inner/indirection/dead-end texel without a chart
 * or with a non-finite position; an indirection texel whose pointer is not a whole texel inside
 * the image, does not name an inner texel, or whose rot is not finite; no inner texel at all.
 * PGT_ERROR_LIMIT: a side above PGT_IMAGE_MAX_SIDE. PGT_ERROR_OUT_OF_MEMORY. On failure *out is
 * zeroed. */
pgt_result pgt_march_atlas_create(pgt_march_atlas *out, const pgt_image *atlas, const char *what,
                                  pgt_error *err);

/* Frees `texels` and zeroes the struct; NULL or a zeroed view is a no-op. */
void pgt_march_atlas_destroy(pgt_march_atlas *a);

/* External-context condition evaluated at a step's destination (after every jump); return
 * nonzero to accept the step. A condition that fails (an expression error) returns 0, so the
 * step stops as rejected, and keeps its error in ctx for the caller to check after the step
 * (expand.c's grammar conditions do). */
typedef int (*pgt_march_condition_fn)(void *ctx, float x, float y, uint32_t chart);

/* A density context as a condition (paper 000 section 9: "a scalar valued texture controlling
 * the density as a space occupancy probability"): a step whose destination texel has density d
 * goes on with probability d and is rejected otherwise (d <= 0: always rejected, d >= 1: never;
 * a NaN never goes on). The draw is pgt_rng_float(seed, stream, draws) < d, and `draws` counts
 * up by one per evaluation, so one walker's k-th evaluated step draws counter k - 1 whatever the
 * thread order: give each walker its own stream (or seed). Usage:
 *   pgt_march_density ctx = {density, atlas.width, atlas.height, seed, stream, 0};
 *   opts.condition = pgt_march_density_condition, opts.condition_ctx = &ctx; */
typedef struct pgt_march_density {
    const float *density; /* width * height floats (row-major, like an image plane) */
    uint32_t width, height;
    uint32_t seed, stream;
    uint64_t draws; /* evaluations so far: the next draw's counter */
} pgt_march_density;

/* The condition of a pgt_march_density (ctx) at texel-space (x, y), a step's destination; a
 * point outside the image is rejected (no draw). */
int pgt_march_density_condition(void *ctx, float x, float y, uint32_t chart);

/* Where the turn of the direction at a jump comes from. */
typedef enum pgt_march_rotation {
    /* The paper (5.2): rotate by the angle the builder stored in the rot channel. */
    PGT_MARCH_ROTATION_ATLAS = 0,
    /* Beyond the paper: d' = J'^+ T J d, the destination texel direction with the same 3D
     * motion as d (J, J': P's finite-difference Jacobians at the walker's texel and at the
     * referenced texel; T: the smallest rotation taking the source tangent plane's normal to
     * the destination's, which unfolds a crease about the crease line). Also right where the
     * texel metric is anisotropic (non-square charts, non-conformal UVs), which no single angle
     * can be; falls back to rot where a Jacobian is missing or degenerate. */
    PGT_MARCH_ROTATION_JACOBIAN = 1
} pgt_march_rotation;

/* Options; a zero-initialised struct means the paper's marching with no external context. */
typedef struct pgt_march_options {
    int no_best_pointer; /* 1: jump through P0 as found (5.1 off) */
    int no_rotation;     /* 1: keep d at jumps (5.2 off; overrides `rotation`) */
    pgt_march_rotation rotation;
    /* Mask in atlas space: width * height floats (row-major, like an image plane); a step whose
     * destination texel has a value >= mask_threshold is rejected. NULL: no mask. */
    const float *mask;
    float mask_threshold;             /* 0: PGT_MARCH_MASK_THRESHOLD */
    pgt_march_condition_fn condition; /* NULL: none */
    void *condition_ctx;
} pgt_march_options;

/* The state of one walker (a kernel keeps it in registers; batches keep it in flat arrays). */
typedef struct pgt_march_state {
    float x, y;   /* texel space, inside an inner texel of `chart` */
    float dx, dy; /* unit direction in texel space */
    uint32_t chart;
    /* The no-bounce rule's memory of the last jump: 1 + the texel index (y * width + x) of the
     * inner texel the walker stood on, 0 for none (pgt_march_start; a state initialised with
     * the five fields above); the walker's direction right after it (unit, texel space of the
     * chart it jumped into); how many of its latest jumps in a row bounced. */
    uint32_t from;
    float in_dx, in_dy;
    uint32_t bounces;
} pgt_march_state;

/* Why a step stopped (pgt_march_info.stop). */
typedef enum pgt_march_stop {
    PGT_MARCH_STOP_NONE = 0,
    PGT_MARCH_STOP_DEAD_END = 1,       /* the indirection texel reached is a dead end */
    PGT_MARCH_STOP_NO_INDIRECTION = 2, /* the search found no boundary texel of the chart */
    PGT_MARCH_STOP_TOO_MANY_JUMPS = 3, /* more than PGT_MARCH_MAX_JUMPS crossings */
    PGT_MARCH_STOP_REJECTED = 4,       /* the mask or the condition rejected the destination */
    PGT_MARCH_STOP_BOUNCE = 5          /* PGT_MARCH_MAX_BOUNCES bounces in a row (above) */
} pgt_march_stop;

/* "none", "dead end", "no indirection", "too many jumps", "rejected", "bounce". */
const char *pgt_march_stop_name(pgt_march_stop s);

/* Per-step details for tests and the CLI (may be NULL). */
typedef struct pgt_march_info {
    uint32_t jumps;        /* chart crossings in this step */
    uint32_t searches;     /* binary searches in this step */
    uint32_t last_pointer; /* texel index y * width + x of the last indirection texel jumped
                              through (after best-pointer selection), or UINT32_MAX */
    uint32_t last_p0;      /* the P0 of that jump before best-pointer selection */
    float remaining_src;   /* what was left at the last jump, in source texels */
    float remaining_dst;   /* that length in destination texels (3D-consistent) */
    pgt_march_stop stop;   /* why the step stopped (NONE unless the event is STOP) */
} pgt_march_info;

/* Starts a walker at texel-space (x, y) with direction (dx, dy) (normalised here), with no
 * memory of a jump (from = 0). Errors (PGT_ERROR_INVALID_ARGUMENT, naming the values): a
 * non-finite or zero direction, a position outside the image, or a position on a texel that is
 * not inner. */
pgt_result pgt_march_start(const pgt_march_atlas *a, float x, float y, float dx, float dy,
                           pgt_march_state *out, pgt_error *err);

/* One application of the marching rule: turn the direction by `angle` (radians, the rule's
 * angle, same sense as rot), then step `length` texels (0 < length <= PGT_MARCH_MAX_LENGTH,
 * asserted). Updates *s on success; leaves it unchanged on STOP. */
pgt_march_event pgt_march_step(const pgt_march_atlas *a, const pgt_march_options *o,
                               pgt_march_state *s, float length, float angle, pgt_march_info *info);

/* The 3D position of a walker at (x, y): P interpolated bilinearly between the four texel
 * centres around (x, y), over those that are inner texels of the chart of the texel containing
 * (x, y) (weights renormalised; a GPU kernel does the same with four fetches). At a texel centre
 * it is that texel's P. (x, y) must be inside an inner texel (asserted). */
void pgt_march_position(const pgt_march_atlas *a, float x, float y, float out_p[3]);

/* Case 3/4 search (exposed for tests): along the segment from (x0, y0) (inside an inner texel
 * of `chart`) to (x1, y1), finds by bisection a point whose texel is an indirection or dead-end
 * texel of `chart`. Returns its texel index (y * width + x) and its segment parameter in
 * *out_t (0 < t <= 1), or UINT32_MAX when none was found. */
uint32_t pgt_march_search(const pgt_march_atlas *a, uint32_t chart, float x0, float y0, float x1,
                          float y1, float *out_t);

/* Best indirection texel (5.1, exposed for tests): given the current position (x, y) in an inner
 * texel of `chart` and P0 (texel index of an indirection texel of `chart`, asserted; P_near
 * and the candidates come from P0's ring mask, so another P0 gives another chart's), returns the
 * texel index of the chosen indirection texel (P0 when P_near is the current texel or nothing beats
 * it); *out_near gets P_near's texel index (UINT32_MAX when P0 has no inner neighbour). */
uint32_t pgt_march_best_pointer(const pgt_march_atlas *a, uint32_t chart, float x, float y,
                                uint32_t p0, uint32_t *out_near);

/* A batch of independent walkers, `steps` steps each, in flat arrays of `count` (x, y, dx, dy,
 * chart: pgt_march_state fields; a walker stops at its first STOP). Walkers are split over
 * `threads` threads (pgt_parallel_for; 0 = 1); every output is the same for any thread count.
 * Per walker (each array may be NULL): out_taken the steps taken (a STOP is not a step),
 * out_sum the sum of the coordinates of every 3D position visited (pgt_march_position after
 * every step, as a grammar placing geometry would; NULL: positions are not fetched). A walker
 * keeps the no-bounce memory over the batch's steps; the arrays do not hold it, so every walker
 * starts the batch without it. Each walker ends as pgt_march_step called `steps` times with
 * angle 0 would leave it, to the byte. With o->condition the batch runs on one thread whatever
 * `threads` says, and the condition is called in the order of those calls, one walker after
 * another (a condition may keep state, as pgt_march_density_condition's draw counter does). */
void pgt_march_batch(const pgt_march_atlas *a, const pgt_march_options *o, float length,
                     uint32_t steps, uint32_t count, float *x, float *y, float *dx, float *dy,
                     uint32_t *chart, uint32_t threads, uint32_t *out_taken, double *out_sum);

/* Start tries per walker of pgt_march_random_starts: a try lands on an inner texel with the
 * probability of the atlas's inner share (38 % on pizza's, 0.6 % on a lone 8 x 8 chart in a
 * 1024^2 image), so a million tries miss only on atlases with next to no inner texel. */
#define PGT_MARCH_START_TRIES 1000000u

/* Seeded start states for `count` walkers in flat arrays, as pgt_march_batch takes them:
 * walker i at a uniformly random point of the image with a uniformly random heading. Its try
 * k (0, 1, ...) draws u_j = pgt_rng_float(seed, 0, 3 (i PGT_MARCH_START_TRIES + k) + j) for
 * j = 0, 1, 2 and calls pgt_march_start(x = u_0 width, y = u_1 height, (cosf(h), sinf(h)))
 * with h = 6.2831853f u_2 (float32 products); the first try it accepts (the point lies on an
 * inner texel) is the walker. Positions and charts are the same for the same seed, atlas and
 * count on every machine; headings as far as the C library's cosf and sinf agree. Returns 0,
 * or -1 when a walker finds no inner texel in PGT_MARCH_START_TRIES tries (the arrays are
 * then partly written). */
int pgt_march_random_starts(const pgt_march_atlas *a, uint32_t seed, uint32_t count, float *x,
                            float *y, float *dx, float *dy, uint32_t *chart);

#ifdef __cplusplus
}
#endif

#endif
