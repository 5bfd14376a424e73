/* pgt: what facade.c, facade_explicit.c and facade_render.c share. Private to ref_cpu. */
#ifndef PGT_FACADE_INTERNAL_H
#define PGT_FACADE_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "pgt/facade.h"
#include "pgt/grammar.h"
#include "pgt/split.h"

/* Inlined into every caller whatever the compiler's size estimate says (GCC and Clang): the
 * rectangle tests run per ray and terminal, and a call of ten arguments costs a tenth of them
 * (callgrind, 100-facade city: -4 % instructions). */
#define FACADE_ALWAYS_INLINE inline __attribute__((always_inline))

/* min and max of finite floats, inlined (libm's fminf/fmaxf are calls that handle NaN). */
static inline float facade_min(float a, float b) { return a < b ? a : b; }
static inline float facade_max(float a, float b) { return a > b ? a : b; }

/* A split resolved for one scope: the plan, its slots and each flattened part's successor. */
typedef struct facade_split_state {
    pgt_split_plan plan;
    pgt_split_slot slots[PGT_FACADE_MAX_PARTS];
    uint32_t seq[PGT_FACADE_MAX_PARTS];
} facade_split_state;

/* Memo of split layouts and terminal rectangles a thread evaluated: a pure function of the
 * building (its params and seed), the grammar item, the scope's size, the enclosing rule's
 * arguments and, only when the item's expressions draw rand, the node key. The windows of one
 * building share one entry, whatever their position: rectangles are kept in the terminal's own
 * block coordinates (origin at the scope's corner) and the ray is shifted instead. Direct
 * mapped by a hash of those inputs; an entry is used only when all of them are equal. */
#define FACADE_CACHE_SPLITS 128u
#define FACADE_CACHE_TERMINALS 256u
typedef struct facade_cache_key {
    uint32_t building, item, key, argc; /* key is 0 for items without rand */
    float w, h;                         /* the scope (a split's length is w or h by axis) */
    float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
} facade_cache_key;
/* A memo entry's children as flat arrays (pgt_split_flat_at), made when the memo first reuses
 * it, so a layout used once costs nothing more: child k is [start[k], end[k]) of part part[k],
 * the bits of pgt_split_child_get. Splits of more children keep the plan's queries. */
#define FACADE_FLAT_CHILDREN 32u
enum { FACADE_FLAT_UNKNOWN = 0, FACADE_FLAT_READY = 1, FACADE_FLAT_TOO_MANY = 2 };
typedef struct facade_split_flat {
    uint32_t state; /* FACADE_FLAT_* */
    float start[FACADE_FLAT_CHILDREN], end[FACADE_FLAT_CHILDREN];
    uint8_t part[FACADE_FLAT_CHILDREN];
} facade_split_flat;
typedef struct facade_cache_split {
    facade_cache_key k;
    uint32_t valid;
    uint32_t pins; /* frames of the ray being developed that use it */
    facade_split_state st;
    facade_split_flat flat;
} facade_cache_split;
/* Rectangles per bounding box in a cached terminal (the window's 27 make 5 groups), and groups
 * of one terminal at most. */
#define FACADE_QUAD_GROUP 6u
#define FACADE_QUAD_GROUPS ((PGT_FACADE_MAX_QUADS + FACADE_QUAD_GROUP - 1u) / FACADE_QUAD_GROUP)
/* A group's box is grown by this share of (1 + |its coordinates|) so that rounding in the slab
 * test never culls a rectangle lying on the box's face. */
#define FACADE_GROUP_GROW 1e-5f
/* Rule calls followed from a part straight to the body they lead to (an optimisation only: the
 * keys and node counts are those of developing each call). */
#define FACADE_COLLAPSE_MAX 16u
typedef struct facade_cache_terminal {
    facade_cache_key k;
    uint32_t n; /* PGT_NONE: empty */
    float groups[6u * FACADE_QUAD_GROUPS];
    uint8_t surf[PGT_FACADE_MAX_QUADS]; /* surface id of q[i] (zero-area ones left out) */
    pgt_facade_quad q[PGT_FACADE_MAX_QUADS];
} facade_cache_terminal;
typedef struct facade_cache {
    const uint8_t *const *draws;     /* per grammar of the scene, per item: 1 if it draws rand */
    const uint32_t *const *collapse; /* per grammar, per sequence: facade_collapse_table */
    facade_cache_split split[FACADE_CACHE_SPLITS];
    facade_cache_terminal term[FACADE_CACHE_TERMINALS];
} facade_cache;

/* The draws table of grammar g (malloc'd, g->item_count bytes; NULL when out of memory). */
uint8_t *facade_draws_table(const pgt_grammar *g);
/* Per sequence of g: when it is one call without arguments of a rule with one unconditional
 * case, that case's sequence, else PGT_NONE (malloc'd; NULL when out of memory). */
uint32_t *facade_collapse_table(const pgt_grammar *g);

/* Empties a cache. */
void facade_cache_clear(facade_cache *c);

/* Evaluation context of one facade: its grammar, its building's param vector and seed. */
typedef struct facade_ctx {
    const pgt_grammar *g;
    const float *params;
    uint32_t seed;
    pgt_facade_ray_stats *stats; /* errors are or-ed in */
    pgt_error *err;              /* the first evaluation error's message, or NULL */
} facade_ctx;

/* pgt_facade_camera_ray in parts: the image-plane offsets of pixel column x and of row y, and
 * the unit direction through them (a caller tracing a block of pixels computes each column's and
 * row's offset once; the same bits). */
float facade_camera_sx(const pgt_facade_camera *cam, uint32_t x);
float facade_camera_sy(const pgt_facade_camera *cam, uint32_t y);
void facade_camera_dir(const pgt_facade_camera *cam, float sx, float sy, float dir[3]);

/* pgt_facade_intersect with a memo (NULL: none) and the terminals' z (protrusions and recesses,
 * and the volume's F and B) scaled by zscale in (0, 1] (LOD, sec. 7): the ray's z is divided by
 * zscale instead, which meets the scaled geometry at the same t. */
int facade_intersect(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                     const float org[3], const float dir[3], pgt_facade_hit *hit,
                     pgt_facade_ray_stats *stats, facade_cache *cache, float zscale);

/* Rays of a packet (facade_intersect_packet) at most: one bit each in a 64-bit mask. */
#define FACADE_PACKET 64u
/* A thread's work area for packets: the packet's development stack and per-ray state. */
typedef struct facade_packet_work facade_packet_work;
facade_packet_work *facade_packet_work_create(void); /* NULL when out of memory */
void facade_packet_work_destroy(facade_packet_work *w);

/* facade_intersect (with memo `cache`, not NULL) for the n <= FACADE_PACKET rays org + t
 * dirs[idx[i]] through facade f, hits[idx[i]] in and out, dev[idx[i]] += the nodes each ray
 * developed: the same hits, node counts and statistics as facade_intersect ray after ray, which
 * is what it runs without a work area (w NULL: pgt_facade_shading.single_rays). What
 * does not depend on the ray (memo look-ups, layouts, rule calls, keys, frames) is done once
 * per node for the rays that reach it; every ray keeps its own order of children and terminals
 * (a split's rays going up and down the axis get a frame each). A packet that meets an error
 * (evaluation, node budget, depth) is replayed ray by ray, so errors are those of
 * facade_intersect. */
void facade_intersect_packet(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                             const float org[3], const float (*dirs)[3], const uint32_t *idx,
                             uint32_t n, pgt_facade_hit *hits, uint32_t *dev,
                             pgt_facade_ray_stats *stats, facade_cache *cache,
                             facade_packet_work *w, float zscale);

/* ---- roofs ---- */

/* The roof of building b (its footprint at base + height) hit by the ray at t in [0, hit->t):
 * overwrites *hit (facade facade_count + b, node 0, kind PGT_FACADE_ROOF) and returns 1. */
int facade_roof_intersect(const pgt_facade_scene *s, uint32_t b, uint32_t facade_count,
                          const float org[3], const float dir[3], pgt_facade_hit *hit);

/* Triangulates a simple polygon of n corners (x, z pairs, either orientation) by ear clipping:
 * writes n - 2 triangles (corner indices) to tris and returns their count (fewer only for a
 * degenerate polygon). scratch holds n uint32. */
uint32_t facade_triangulate(const float *corners, uint32_t n, uint32_t *tris, uint32_t *scratch);

/* ---- geometry images (facade_gimage.c) ---- */

/* The least and greatest z of n triangles' corners (+inf / -inf for none). */
void facade_gimage_z_range(const float *d, uint32_t n, float *zlo, float *zhi);
/* The triangles of geometry image id (a whole number below gimage_count) and the index of its
 * first in the scene's image (a hit's surface is first + the triangle); 0 for a bad id. */
uint32_t facade_gimage_triangles(const pgt_facade_scene *s, float id, const float **data,
                                 uint32_t *first);
/* Nearest triangle of d[0 .. n) (x, y scaled by w, h) hit at t in [0, *best) by the block-local
 * ray a + t v; writes its unit normal (facade space, not turned). PGT_NONE if none. win (NULL:
 * no test) is a mesh quad's window (x0, y0, x1, y1) in facade space and off the block's corner
 * there: hits outside the window are dropped (another quad shows them). */
uint32_t facade_gimage_hit(const float *d, uint32_t n, float w, float h, const float a[3],
                           const float v[3], const float *win, const float off[2], float *best,
                           float nrm[3]);

/* ---- terminal space detail (facade_shade.c) ---- */

enum { FACADE_MAT_NONE = 0, FACADE_MAT_BRICK, FACADE_MAT_STONE, FACADE_MAT_WOOD, FACADE_MAT_COUNT };

/* The material of surface `surface` of a terminal of kind `kind`. */
uint32_t facade_material(uint32_t kind, uint32_t surface);
/* Its relief depth D (metres) and height field h(u, v) in [0, 1]. */
float facade_relief_depth(uint32_t material);
float facade_height(uint32_t material, float u, float v);

typedef struct facade_detail_in {
    uint32_t material, axis; /* the rectangle's material and normal axis */
    float p[3];              /* the macroscopic hit, facade space */
    float v[3];              /* the ray's unit direction, facade space */
    float l[3];              /* unit direction towards the light, facade space */
    float normal, relief;    /* weights in [0, 1] of normal mapping and relief mapping */
    int relief_shadows;      /* 1: self-shadowing in the relief */
} facade_detail_in;
typedef struct facade_detail_out {
    float s;      /* how far the ray went on below the surface (metres) */
    float h;      /* the height field where it stopped */
    float n[3];   /* shading normal, facade space, facing the ray */
    int shadowed; /* the relief hides the light */
} facade_detail_out;
void facade_detail(const facade_detail_in *in, facade_detail_out *out);

/* The axiom's node key of facade f. */
uint32_t facade_axiom_key(const pgt_facade_scene *s, const pgt_facade *f);

/* The sequence of the first case of `rule` whose condition holds (PGT_NONE: none holds, or an
 * evaluation failed: c->stats->errors says which). */
uint32_t facade_select_case(const facade_ctx *c, uint32_t rule, const float *args, uint32_t argc,
                            uint32_t key);

/* A rule call: evaluates its arguments into out_args and selects the case. 0 on failure. */
int facade_call(const facade_ctx *c, const pgt_grammar_item *it, const float *args, uint32_t argc,
                uint32_t key, float *out_args, uint32_t *out_seq);

/* The rectangles of terminal item `it` on scope [x0, x0 + w] x [y0, y0 + h]; 0 on failure (or
 * for a terminal without rectangles). */
uint32_t facade_terminal(const facade_ctx *c, const pgt_grammar_item *it, const float *args,
                         uint32_t argc, uint32_t key, float x0, float y0, float w, float h,
                         pgt_facade_quad *q);

/* Evaluates the parts of split item `it` (flattening its repeat group) and builds the layout on
 * a scope of `length`. 0 on failure. */
int facade_split(const facade_ctx *c, const pgt_grammar_item *it, const float *args, uint32_t argc,
                 uint32_t key, float length, facade_split_state *st);

/* Is f's window the whole facade with b = +Y (every footprint facade)? Then the mapping and the
 * ray test take the paths footprint facades always took (bit for bit). */
static inline int facade_is_whole(const pgt_facade *f) {
    return f->u0 == 0.0f && f->v0 == 0.0f && f->width == f->scope_w && f->height == f->scope_h &&
           f->b[0] == 0.0f && f->b[1] == 1.0f && f->b[2] == 0.0f;
}

/* The facade volume (5.2) in facade space: the window times [-recess, protrusion]. */
static inline void facade_volume(const pgt_facade *f, float lo[3], float hi[3]) {
    lo[0] = f->u0, lo[1] = f->v0, lo[2] = -f->recess;
    hi[0] = f->u0 + f->width, hi[1] = f->v0 + f->height, hi[2] = f->protrusion;
}

/* The z extent of rectangle q (*zlo, *zhi); nonzero when it has area and reaches outside the
 * facade volume [-recess, protrusion]: the explicit twin refuses such a terminal, the rays flag
 * it (PGT_FACADE_ERR_VOLUME). */
static inline int facade_quad_outside_volume(const pgt_facade *f, const pgt_facade_quad *q,
                                             float *zlo, float *zhi) {
    *zlo = q->axis == 2 ? q->c : q->lo[1], *zhi = q->axis == 2 ? q->c : q->hi[1];
    return q->hi[0] > q->lo[0] && (*zlo < -f->recess || *zhi > f->protrusion);
}

/* The window entry_child clamps a ray's entry point to, per axis x and y: the facade's window,
 * or nothing (+-inf) for a whole facade, whose entries then stay the same floats. */
static inline void facade_entry_window(const pgt_facade *f, float lo[2], float hi[2]) {
    const int whole = facade_is_whole(f);
    lo[0] = whole ? -INFINITY : f->u0, lo[1] = whole ? -INFINITY : f->v0;
    hi[0] = whole ? INFINITY : f->u0 + f->width, hi[1] = whole ? INFINITY : f->v0 + f->height;
}

/* World ray to facade space (a + t v), and a facade-space point to the world (facade.h: the
 * window's corner (u0, v0) is at origin). */
void facade_to_local(const pgt_facade *f, const float org[3], const float dir[3], float a[3],
                     float v[3]);
void facade_to_world(const pgt_facade *f, const float p[3], float out[3]);
/* A facade-space direction (x along t, y along b, z along n) in the world. */
void facade_vector_to_world(const pgt_facade *f, const float v[3], float out[3]);

/* Evaluates expression e for node `key` of the facade of c (rand draws (seed, key, counter++));
 * on failure or-s PGT_FACADE_ERR_EVAL into c->stats, keeps the first message in c->err and
 * returns 0. */
int facade_eval(const facade_ctx *c, uint32_t e, const float *args, uint32_t argc, uint32_t key,
                uint64_t *counter, float *out);

#endif
