/* pgt: per-pixel procedural facades (paper 003; issue 6): the facade scene, facade space, the
 * coverage polygon, ray-dependent grammar development and its explicit twin.
 *
 * This work is based on:
 *   Marvie, Gautron, Hirtzlin, Sourimant, "Render-Time Procedural Per-Pixel Geometry
 *   Generation", GI 2011 (paper 003): sec. 3 (the facade grammar), 5.1 (facade space: origin
 *   at the bottom left, t along the facade, b up, n out), 5.2 (the facade volume: the facade
 *   rectangle thickened by the largest protrusion F in front and recess B behind), 5.3 (the
 *   coverage polygon: orientation selection and projection), 6.1 (Algorithm 1, ray-dependent
 *   grammar development), 6.2.1 (parametric surface sets: the window block of Fig. 7).
 *
 * Data. A scene is flat arrays (uploadable as they are): buildings, their footprint corners and
 * one vector of grammar param values per building (the grammar's params in order: the paper's
 * "grammar parameters and building footprints"). pgt_facade_prepare derives one pgt_facade per
 * footprint edge (its facade space and volume); that array is working data, recomputed from the
 * scene in O(facades).
 *
 * Facade space (5.1): x along t from the edge's first corner, y up (b = +Y of the world), z
 * along n = t x b, out of the building. A footprint's corners are ordered so that n points out:
 * counter-clockwise seen from above (looking down -Y with +X to the right, so +Z runs down the
 * page), i.e. a negative signed area sum(x_k z_k+1 - x_k+1 z_k) / 2; pgt_facade_scene_check
 * refuses the other order.
 * The volume (5.2) is [0, width] x [0, height] x [-recess, protrusion], where recess and
 * protrusion are the grammar params `recess` and `protrusion` (B and F: bounds the grammar
 * declares, as in the paper; the explicit expansion verifies every terminal against them).
 *
 * Grammar (3, 6.1). The axiom is the facade: its scope is the facade rectangle. A rule body is
 * a sequence of items applied to the same scope: split(x) / split(y) (split.h's CGA layout),
 * rule calls (with case/else conditions) and the facade terminals below. Several items in one
 * sequence overlap in the scope (a window and a balcony in front of it); the nearest hit wins.
 * Random numbers (rand) are keyed by the node, not by draw order: a node's stream is the hash of
 * its parent's stream and its child index (pgt_facade_child_key), so every ray, and the explicit
 * expansion, sees the same random layout whatever it develops.
 *
 * Terminals (6.2.1) are parametric surface sets: axis-aligned rectangles in the terminal's
 * block, which is the scope [0, w] x [0, h] placed at (X_B, Y_B) on the facade. Every terminal
 * stays inside its scope in x and y and inside [-recess, protrusion] in z (the paper's sec. 8
 * condition for the grammar to be a BVH). pgt_facade_terminal_quads is the one definition that
 * the ray test and the explicit expansion both use. In the grammar:
 *   Wall()                                     the scope's rectangle at z = 0.
 *   Window(margin, frame, frameDepth, recess, sillHeight, sillDepth)
 *                                              Fig. 7: wall around, a frame protruding by
 *                                              frameDepth, the opening recessed to z = -recess
 *                                              (reveal and glass), a sill box below the frame
 *                                              protruding by sillDepth.
 *   Door(margin, frame, frameDepth, recess)    a window without sill whose opening reaches the
 *                                              bottom of the scope.
 *   Ledge(depth)                               a box over the whole scope protruding by depth.
 *   Balcony(depth, slab, railing)              a slab (height slab) protruding by depth with a
 *                                              railing of height railing at its front and sides;
 *                                              the back is open (a window behind it shows).
 * A terminal whose scope is too small for its layout degrades to Wall() (documented per kind in
 * facade.c); sizes are clamped to the scope.
 *
 * Roofs. Each building's extrusion is closed by its footprint at base + height, a plain polygon
 * (no grammar): frames and the explicit twin (triangulated by ear clipping) both hold it, with
 * facade id facade_count + building, node 0, kind PGT_FACADE_ROOF, surface 0.
 *
 * Ray development (Algorithm 1): intersect the volume; from the entry point, the child of each
 * split that holds the point (pgt_split_child_at), terminals tested, then the next child in the
 * ray's direction along the split axis, until a hit or the exit; explicit stack, nothing
 * generated. A ray that misses the volume develops nothing. */
#ifndef PGT_FACADE_H
#define PGT_FACADE_H

#include <stddef.h>
#include <stdint.h>

#include "grammar.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Terminal kinds: the `terminal` channel of a frame (0 = no hit). */
typedef enum pgt_facade_kind {
    PGT_FACADE_MISS = 0,
    PGT_FACADE_WALL = 1,
    PGT_FACADE_WINDOW = 2,
    PGT_FACADE_DOOR = 3,
    PGT_FACADE_LEDGE = 4,
    PGT_FACADE_BALCONY = 5,
    PGT_FACADE_MESH = 6, /* a geometry-image terminal (6.2.2) */
    PGT_FACADE_ROOF = 7, /* a building's flat roof (the top of the extrusion, not procedural) */
    PGT_FACADE_KIND_COUNT = 8
} pgt_facade_kind;

/* Depth of the development stack (split and sequence frames): the facade grammar nests 3 deep,
 * a CGA building a dozen. A sequence's last item takes over the sequence's frame (a chain of
 * rule calls costs one frame), in the ray development and the explicit expansion alike. Deeper
 * is an error (PGT_FACADE_ERR_DEPTH), never a crash. */
#define PGT_FACADE_MAX_DEPTH 32u
/* Parts of one split that a ray development can hold (a repeat group's parts included): a frame
 * keeps one pgt_split_slot per part. */
#define PGT_FACADE_MAX_PARTS 16u
/* Nodes one ray may develop before it gives up (PGT_FACADE_ERR_BUDGET): a grammar that never
 * stops splitting (A --> split(x) { '1 : A }) would otherwise loop forever; rule calls that
 * never split (A --> B, B --> A) are refused earlier by pgt_facade_scene_check. A ray along a
 * facade of a few hundred windows develops about a thousand nodes. */
#define PGT_FACADE_NODE_BUDGET 65536u
/* Rectangles of one terminal at most (the window block has 27). */
#define PGT_FACADE_MAX_QUADS 32u

/* Largest |coordinate| of a footprint corner, a base or a roof, and of a --mesh quad mesh's
 * positions and UVs (metres): at 1e6 a float's spacing is 0.0625, coarser than a window's frame;
 * beyond it facades lose their shape (and at 1e38 the frames' arithmetic overflows). */
#define PGT_FACADE_MAX_COORD 1e6f

/* Largest |coordinate| of the camera's eye and look-at point: 1000 x the scene's bound (+-1e6),
 * far inside what Embree's --embree-check twin takes (ray origins within ~1.8e18: an eye at 1e19
 * aborted it), and squared distances from it stay finite in float (an eye at 1e30 was refused as
 * "eye and at coincide"). */
#define PGT_FACADE_MAX_EYE 1e9f

/* Facades per scene, and pixels per image side, at most (sizes stay far inside 32 bits). */
#define PGT_FACADE_MAX_FACADES (1u << 26)
#define PGT_FACADE_MAX_SIDE 16384u

/* pgt_facade_ray_stats.errors bits: what went wrong in some ray (rendering goes on; the CLI
 * reports them as errors). */
#define PGT_FACADE_ERR_DEPTH 1u  /* the stack was full */
#define PGT_FACADE_ERR_BUDGET 2u /* PGT_FACADE_NODE_BUDGET reached */
#define PGT_FACADE_ERR_EVAL 4u   /* an expression gave NaN/inf or read what it may not */
#define PGT_FACADE_ERR_PARTS 8u  /* a split with more than PGT_FACADE_MAX_PARTS parts */
/* an item a facade cannot hold (Marching, Branch, Bark, Leaves, split(z)) */
#define PGT_FACADE_ERR_ITEM 16u
/* Mesh(id) names no geometry image of the scene (on a generic mesh's quad its triangles are cut
 * to the quad's window like every terminal, not refused) */
#define PGT_FACADE_ERR_GIMAGE 32u
/* a terminal reaches outside the facade volume [-recess, protrusion] in z (the explicit twin
 * refuses it with the grammar's place; the rays would show it cut open at the volume's faces) */
#define PGT_FACADE_ERR_VOLUME 64u

/* One building: an extruded footprint. */
typedef struct pgt_facade_building {
    uint32_t first_corner, corner_count; /* corners[2 * first_corner ..]: (x, z) pairs */
    float base, height;                  /* ground y and height of the extrusion */
    uint32_t grammar;                    /* index into the scene's grammars */
    uint32_t first_param;                /* params[first_param .. + the grammar's param_count) */
    uint32_t seed;                       /* the building's random seed (rand in its grammar) */
    uint32_t colour;                     /* 0xRRGGBB, the wall's base colour */
} pgt_facade_building;

/* A geometry image (6.2.2): triangles[first .. + count) of the scene's 1D geometry image, and
 * the least and greatest z of their corners (pgt_facade_scene_check verifies them): the rays
 * flag an image that leaves the facade volume as they do a rectangle (sec. 8). */
typedef struct pgt_facade_gimage {
    uint32_t first, count;
    float zlo, zhi;
} pgt_facade_gimage;

/* Triangles of one geometry image at most (the paper's door block has 732). */
#define PGT_FACADE_MAX_GIMAGE_TRIANGLES 65536u

/* A scene: every array is flat. grammars are borrowed (not freed by pgt_facade_scene_destroy).
 * Geometry images: gimage_data is the 1D geometry image, 9 floats per triangle (x y z of its
 * three corners): x and y in [0, 1] across the terminal's scope, z in metres out of the wall;
 * Mesh(id) instantiates gimages[id]. */
typedef struct pgt_facade_scene {
    uint32_t grammar_count;
    const pgt_grammar *grammars; /* grammars[k] */
    uint32_t building_count;
    pgt_facade_building *buildings;
    uint32_t corner_count;
    float *corners; /* 2 * corner_count */
    uint32_t param_count;
    float *params;
    uint32_t gimage_count, gimage_triangle_count;
    pgt_facade_gimage *gimages;
    float *gimage_data;    /* 9 * gimage_triangle_count */
    uint8_t *gimage_roles; /* per triangle, pgt_facade_gimage_role: its look when shaded */
} pgt_facade_scene;

/* What a geometry-image triangle is, for shading (the optional attribute of 6.2.2's images). */
typedef enum pgt_facade_gimage_role {
    PGT_FACADE_ROLE_WALL = 0,
    PGT_FACADE_ROLE_FRAME = 1,
    PGT_FACADE_ROLE_REVEAL = 2,
    PGT_FACADE_ROLE_GLASS = 3,
    PGT_FACADE_ROLE_COUNT = 4
} pgt_facade_gimage_role;

/* The built-in geometry images, appended to the scene's (ids from gimage_count on; malloc'd, so
 * pgt_facade_scene_destroy frees them):
 *   oculus: a round window block of 352 triangles (facade_gimage.c): a wall with a circular
 *   opening, a protruding frame ring (6 cm), a cylindrical reveal and glass recessed 15 cm.
 * pgt_gen_city and the scene readers call this, so Mesh(0) is the oculus. Only a scene whose
 * grammars (s->grammars, set before the call) have a Mesh terminal gets them: a scene carries no
 * data it does not use, and its procedural bytes say so. */
#define PGT_FACADE_GIMAGE_OCULUS 0u
pgt_result pgt_facade_add_builtin_gimages(pgt_facade_scene *s, pgt_error *err);

/* One facade (derived): facade space, its window into grammar space and its volume. 23 words.
 *
 * Facade space is grammar space: a world point P has facade coordinates (u0 + (P - origin) . t,
 * v0 + (P - origin) . b, (P - origin) . n); the grammar's axiom has the scope [0, scope_w] x
 * [0, scope_h] and the facade shows its window [u0, u0 + width] x [v0, v0 + height] of it; the
 * volume is the window times [-recess, protrusion] in z. A footprint facade's window is the whole
 * facade (u0 = v0 = 0, scope = width x height, b = +Y); a quad of a generic mesh (sec. 10,
 * pgt_facade_mesh_facades) is a window of the mesh's one facade, so the grammar is developed in
 * one space across quads and a split's children line up across neighbouring quads. */
typedef struct pgt_facade {
    float origin[3];          /* world position of the window's corner (u0, v0) (bottom left) */
    float t[3];               /* unit tangent (x axis) */
    float n[3];               /* unit normal (z axis), out of the building; n = t x b */
    float width, height;      /* the window's size (the facade rectangle of a footprint) */
    float protrusion, recess; /* F and B (5.2) */
    uint32_t building;        /* index of its building; grammar, params, seed from there */
    uint32_t edge;            /* footprint edge k (corner k to k + 1), or the mesh's quad k */
    float b[3];               /* unit binormal (y axis): +Y for footprint facades */
    float u0, v0;             /* the window's corner in grammar space */
    float scope_w, scope_h;   /* the axiom's scope */
    uint32_t axiom_key;       /* the axiom's node key (pgt_facade_child_key chain) */
} pgt_facade;

/* Pinhole camera: one ray per pixel centre, fov_deg is the vertical field of view. */
typedef struct pgt_facade_camera {
    float eye[3], at[3], up[3];
    float fov_deg;
    uint32_t width, height;
    float forward[3], right[3], upward[3]; /* orthonormal, derived by pgt_facade_camera_init */
    float tan_half;                        /* tan(fov / 2) */
} pgt_facade_camera;

/* The nearest hit of a ray. */
typedef struct pgt_facade_hit {
    float t;          /* distance along the unit direction; INFINITY when nothing was hit */
    uint32_t facade;  /* PGT_NONE when nothing was hit */
    uint32_t node;    /* the terminal instance's node key (pgt_facade_child_key chain) */
    uint32_t kind;    /* pgt_facade_kind */
    uint32_t surface; /* index of the rectangle within the terminal */
    uint32_t item;    /* grammar item of the terminal */
    float n[3];       /* world normal of the rectangle (its +axis side, not flipped) */
    float p[3];       /* facade-space hit point */
} pgt_facade_hit;

/* Counters of ray development. */
typedef struct pgt_facade_ray_stats {
    uint64_t rays;        /* rays given to pgt_facade_intersect */
    uint64_t volume_hits; /* rays that entered a facade volume */
    uint64_t nodes;       /* nodes developed (split and sequence frames pushed) */
    uint64_t terminals;   /* terminal intersection tests */
    uint64_t quads;       /* rectangle tests */
    uint32_t errors;      /* PGT_FACADE_ERR_* bits */
} pgt_facade_ray_stats;

/* ---- scene ---- */

/* Checks a scene: indices in range, finite coordinates, footprints of >= 3 corners (or none: a
 * building whose facades come from a mesh, pgt_facade_mesh_facades) with no edge
 * shorter than 1e-4, ordered so that normals point out (negative signed area), params finite, every
 * grammar having the params `protrusion` and `recess` (>= 0), an axiom without parameters and no
 * rule that calls itself through rule calls alone.
 * what names the scene in messages ("city.scene"). */
pgt_result pgt_facade_scene_check(const pgt_facade_scene *s, const char *what, pgt_error *err);

/* Frees the scene's own arrays (not the grammars; the geometry images too) and zeroes it. */
void pgt_facade_scene_destroy(pgt_facade_scene *s);

/* Bytes of the procedural representation: buildings, corners, params and the grammars' arrays
 * (what a GPU would hold: not the grammars' code_pos, kept for messages; the derived facades
 * are counted apart by the caller). */
size_t pgt_facade_scene_bytes(const pgt_facade_scene *s);

/* Derives the facades of every building with a footprint, in building then edge order (a
 * building without corners has none here). *out is malloc'd. */
pgt_result pgt_facade_prepare(const pgt_facade_scene *s, pgt_facade **out, uint32_t *count,
                              pgt_error *err);

/* ---- generic meshes (sec. 10; facade_mesh.c) ---- */

/* A quad mesh whose vertices carry a normal and their location (u, v) in facade space (metres:
 * u along the facade, v up it; u, v >= 0, the axiom's scope starts at 0). Quads list their 4
 * corners in order around them, counter-clockwise seen from outside; vertices that share a
 * position but not a UV (a seam) are separate vertices. Flat arrays, 32-bit indices. */
typedef struct pgt_facade_quads {
    uint32_t vertex_count, quad_count;
    float *positions;  /* 3 per vertex */
    float *normals;    /* 3 per vertex, not necessarily unit */
    float *uvs;        /* 2 per vertex */
    uint32_t *indices; /* 4 per quad */
} pgt_facade_quads;

/* Frees the arrays (of a mesh that owns them) and zeroes q; NULL is a no-op. */
void pgt_facade_quads_destroy(pgt_facade_quads *q);

/* Selective adjacency extraction (sec. 10.1, eq. 5-7), per vertex p: among the pairs of vertices
 * adjacent to p (sharing a quad edge with it) whose UV offsets are not collinear, the pair (p_i,
 * p_j) with the smallest |cos| of the angle between pp_i and pp_j (the paper's "pp_i . pp_j
 * minimal" read as "nearly orthogonal", its Fig. 13; ties: the first pair in increasing vertex
 * order), projected on p's tangent plane (eq. 5), gives the unit t_F and b_F of eq. 6 and 7.
 * out_t, out_b: 3 per vertex; out_pair (may be NULL): 2 per vertex, (i, j). A vertex of no quad
 * gets zeros and PGT_NONE. Errors (naming the vertex or quad): indices out of range, non-finite
 * values, a zero normal, a vertex of a quad without a usable pair (PGT_ERROR_DEGENERATE). */
pgt_result pgt_facade_mesh_frames(float *out_t, float *out_b, uint32_t *out_pair,
                                  const pgt_facade_quads *m, pgt_error *err);

/* One facade per quad (sec. 10.2): the quad's origin is its corner p with the smallest u + v
 * (ties: the first in its list; the bottom left of Fig. 13 when the quad's UVs are a rectangle);
 * facade space is p's: n the unit normal, t = t_F, b = n x t (t_F and b_F of eq. 6-7 are not
 * orthogonal on a sheared parametrization; b_F only sets b's sign, and a b_F on the other side,
 * mirrored UVs, is an error); the window is [u_p, u_p + w] x [v_p, v_p + h] with w and h of eq.
 * 8 from p's two neighbours in the quad projected on p's tangent plane (eq. 5) (a w or h within
 * float rounding, 1e-5 relative, of the quad's UV extent is that extent: UV-exact quads tile
 * grammar space without slivers; a chord against its arc is far more), and the axiom's
 * scope [0, scope_w] x [0, scope_h] (<= 0: the largest u_p + w, v_p + h over the quads). Every
 * quad is a facade of building `building` of s (its grammar, params, seed, colour; protrusion
 * and recess from its params), edge = quad index, axiom key pgt_facade_child_key(seed, 0).
 * out: quad_count facades. Errors: those of pgt_facade_mesh_frames, a negative u or v, a quad
 * with w or h below PGT_FACADE_MESH_MIN_SIZE, building out of range. */
#define PGT_FACADE_MESH_MIN_SIZE 1e-5f
pgt_result pgt_facade_mesh_facades(pgt_facade *out, const pgt_facade_quads *m,
                                   const pgt_facade_scene *s, uint32_t building, float scope_w,
                                   float scope_h, pgt_error *err);

/* ---- camera and rays ---- */

/* Derives the camera basis. Errors: eye == at, up parallel to the view, fov outside (0, 180),
 * zero size, non-finite values. */
pgt_result pgt_facade_camera_init(pgt_facade_camera *cam, const float eye[3], const float at[3],
                                  const float up[3], float fov_deg, uint32_t width, uint32_t height,
                                  pgt_error *err);

/* The ray through the centre of pixel (x, y) (y = 0 is the top row): org = eye, dir unit, with
 * harness/render.h's convention (w = normalize(eye - at), right = normalize(up x w), upward = w x
 * right, dir = normalize(-w + sx right + sy upward), sx = (2 (x + 0.5) / W - 1) tan(fov / 2) W / H,
 * sy = (1 - 2 (y + 0.5) / H) tan(fov / 2)). The one definition of the rays; the Embree check uses
 * it too. */
void pgt_facade_camera_ray(const pgt_facade_camera *cam, uint32_t x, uint32_t y, float org[3],
                           float dir[3]);

/* ---- development ---- */

/* The node key of child k of a node with key parent (a 32-bit hash). The axiom's key is
 * pgt_facade_child_key(building seed, facade index within its building) for footprint facades
 * and pgt_facade_child_key(building seed, 0) for every quad of a mesh (one facade: the same random
 * layout whichever quad a ray meets, and the same as a footprint's first facade). */
uint32_t pgt_facade_child_key(uint32_t parent, uint32_t k);

/* Rectangles of a terminal in facade space: kind, its evaluated arguments, its scope
 * [x0, x0 + w] x [y0, y0 + h]. Each quad is axis-aligned: axis (0 x, 1 y, 2 z) is its normal's
 * axis, c the plane's coordinate, lo/hi the bounds on the other two axes in increasing axis
 * order; the index in out is the surface id (facade_terminals.c lists them). A rectangle of zero
 * area (hi[0] == lo[0]) keeps its id and is skipped by the ray test and the expansion. Returns
 * the count (<= PGT_FACADE_MAX_QUADS). */
typedef struct pgt_facade_quad {
    uint32_t axis;
    float c;
    float lo[2], hi[2];
} pgt_facade_quad;
uint32_t pgt_facade_terminal_quads(uint32_t kind, const float *args, uint32_t arg_count, float x0,
                                   float y0, float w, float h, pgt_facade_quad *out);

/* The facade kind of a grammar terminal id, or PGT_FACADE_MISS for a terminal a facade cannot
 * hold (Bark, Leaves). */
uint32_t pgt_facade_kind_of(uint32_t grammar_terminal);

/* Intersects one ray (world space, dir unit) with facade f (index fi of the scene's facades)
 * for t in [0, hit->t): on a nearer hit, overwrites *hit and returns 1. stats may be NULL. */
int pgt_facade_intersect(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                         const float org[3], const float dir[3], pgt_facade_hit *hit,
                         pgt_facade_ray_stats *stats);

/* ---- coverage polygon (5.3) ---- */

/* The coverage polygon of facade f seen from eye: the axis of facade space along which the eye
 * is farthest outside the volume (relative to the volume's extent: the major axis of the view
 * direction, 5.3.1) selects the plane (the volume's face towards the eye), and the volume's 8
 * corners projected from the eye onto it bound the polygon (5.3.2): corners[4][3] in world
 * space, in order around the rectangle. Among the axes along which the eye lies outside the
 * volume, the one with the largest component of (volume centre - eye) is taken, so the plane
 * always separates the eye from the volume and every ray from eye that meets the volume crosses
 * the polygon. Returns 0 when the eye is inside the volume (then every pixel is covered), 1
 * otherwise. */
int pgt_facade_coverage(const pgt_facade *f, const float eye[3], float corners[4][3],
                        uint32_t *axis);

/* ---- frames ---- */

/* Detail of the shading (paper 003 sec. 6.3 and 7). */
typedef enum pgt_facade_detail {
    PGT_FACADE_DETAIL_GEOMETRY = 0, /* the procedural geometry, flat-shaded (the default) */
    PGT_FACADE_DETAIL_FLAT = 1,     /* LOD level 0: thickness zero, the facade as a textured
                                       plane (terminal colours and the material pattern) */
    PGT_FACADE_DETAIL_NORMAL = 2,   /* level 2: geometry + normal mapping in terminal space */
    PGT_FACADE_DETAIL_RELIEF = 3,   /* level 3: geometry + relief mapping in terminal space,
                                       with self-shadowing in the relief */
    PGT_FACADE_DETAIL_LOD = 4       /* the four levels by distance with linear transitions */
} pgt_facade_detail;

/* Default LOD distances (metres from the eye, sec. 7): relief fades out over [10, 20], normal
 * mapping over [20, 40], and the macroscopic thickness from full at 150 to zero at 300. A brick
 * (6.5 cm) spans about a pixel at 40 m in a 1280 x 720 frame with a 50 degree field of view. */
#define PGT_FACADE_LOD_RELIEF_NEAR 10.0f
#define PGT_FACADE_LOD_RELIEF_FAR 20.0f
#define PGT_FACADE_LOD_NORMAL_NEAR 20.0f
#define PGT_FACADE_LOD_NORMAL_FAR 40.0f
#define PGT_FACADE_LOD_THICK_NEAR 150.0f
#define PGT_FACADE_LOD_THICK_FAR 300.0f

/* Shading of a frame: albedo by terminal surface (wall in the building's colour, glass, frames,
 * sills...) modulated by its material's pattern (bricks, stone blocks, wood planks: procedural
 * height fields in terminal space, facade_shade.c), times ambient + (1 - ambient) max(0, n . l)
 * for a point light, n turned to face the camera; misses get a constant sky colour. A zeroed
 * struct plus a light is the default look. */
typedef struct pgt_facade_shading {
    float light[3];  /* point light, world space */
    float ambient;   /* share of the albedo lit whatever the light (0..1) */
    int shadows;     /* 1: self-shadowing (6.4): a shadow ray toward the light through the same
                        facade's development (and, with relief, through the relief) */
    uint32_t detail; /* pgt_facade_detail */
    /* LOD transitions for PGT_FACADE_DETAIL_LOD: [near, far] of the relief, normal mapping and
     * thickness ramps; all zero means the PGT_FACADE_LOD_* defaults */
    float relief_near, relief_far, normal_near, normal_far, thick_near, thick_far;
    /* 1: no shading, only what a ray caster returns per pixel: depth (t), facade and developed
     * are written, and for a hit terminal, node and surface; rgb, normal (and terminal, node,
     * surface of a miss) are left as they were. The rays,
     * coverage and development are those of a shaded frame (same hits, same developed counts);
     * pgt bench facade times this against Embree's rays, which store a hit (t, triangle,
     * barycentrics) and shade nothing either. */
    int hits_only;
    /* 1: every ray developed alone (Algorithm 1 as written). 0 (the default): the rays of a
     * screen tile that a facade's coverage selects are developed together in packets of up to
     * 64, the work that does not depend on the ray done once per node; the frame is the same
     * to the bit (tests/test_facade.c compares both) */
    int single_rays;
} pgt_facade_shading;

/* The material pattern of surface `surface` of a terminal of kind `kind` (facade_shade.c):
 * its height field in [0, 1] at pattern coordinates (u, v) (metres; 1 = the macroscopic
 * surface) and its relief depth in metres (0: smooth). */
float pgt_facade_pattern_height(uint32_t kind, uint32_t surface, float u, float v);
float pgt_facade_relief_depth(uint32_t kind, uint32_t surface);

/* One frame: planes of width * height values, row-major, y = 0 at the top. */
typedef struct pgt_facade_frame {
    uint32_t width, height;
    float *rgb;          /* 3 per pixel, linear */
    float *depth;        /* distance along the ray, INFINITY when nothing was hit */
    float *terminal;     /* pgt_facade_kind as a float */
    float *normal;       /* 3 per pixel, world space, facing the camera; 0 when missed */
    uint32_t *facade;    /* PGT_NONE when missed */
    uint32_t *node;      /* terminal node key */
    uint32_t *surface;   /* rectangle within the terminal */
    uint32_t *developed; /* nodes developed for this pixel, summed over the facades it was
                            tested against */
} pgt_facade_frame;

pgt_result pgt_facade_frame_create(pgt_facade_frame *out, uint32_t width, uint32_t height,
                                   pgt_error *err);
void pgt_facade_frame_destroy(pgt_facade_frame *f);

/* Timing and counts of one rendered frame. */
typedef struct pgt_facade_render_stats {
    double ms_total, ms_cover, ms_rays; /* coverage + binning, ray development + shading */
    uint64_t covered_pixels;            /* pixel-facade pairs generated by coverage polygons */
    uint32_t visible_facades;           /* facades with a non-empty coverage on screen */
    pgt_facade_ray_stats rays;
    uint32_t error_facade; /* with rays.errors: the lowest facade index whose rays (view or
                              shadow) set an error bit, for messages; else PGT_NONE */
} pgt_facade_render_stats;

/* Renders one ray per pixel: every facade's coverage polygon is rasterized (5.3), each covered
 * pixel's ray is developed against that facade (6.1) with the depth so far as its far bound
 * (facades sorted near to far). threads as pgt_parallel_for (0 is 1); the bytes of the frame do
 * not depend on threads. */
pgt_result pgt_facade_render(const pgt_facade_scene *s, const pgt_facade *facades,
                             uint32_t facade_count, const pgt_facade_camera *cam,
                             const pgt_facade_shading *shading, uint32_t threads,
                             pgt_facade_frame *frame, pgt_facade_render_stats *stats,
                             pgt_error *err);

/* ---- explicit geometry (issue 6 item 8) ---- */

/* Every terminal of every facade instantiated as triangles (two per rectangle, in world
 * space, corners computed from the same facade-space rectangles the ray test uses; a geometry
 * image's triangles as they are), with per triangle ids to compare hits. On a generic mesh's quad
 * everything is clipped to the quad's window in x and y: rectangles stay rectangles, a geometry
 * image's triangle becomes the fan of its clipped convex polygon (up to 5 pieces, zero-area
 * pieces dropped), each piece with the triangle's ids. */
typedef struct pgt_facade_mesh {
    uint32_t vertex_count, triangle_count;
    float *positions;  /* 3 * vertex_count */
    uint32_t *indices; /* 3 * triangle_count */
    uint32_t *facade;  /* per triangle */
    uint32_t *node;    /* per triangle: terminal node key */
    uint32_t *kind;    /* per triangle: pgt_facade_kind */
    uint32_t *surface; /* per triangle: rectangle within the terminal */
} pgt_facade_mesh;

/* Triangles an explicit twin may have at most: every per-triangle index stays far inside 32
 * bits (2 vertices a triangle, 3 on a roof). */
#define PGT_FACADE_MAX_TRIANGLES (1u << 29)
/* Bytes of the twin's arrays per triangle: 2 vertices (a rectangle's 4 for its 2 triangles) of
 * 12 bytes, 3 indices and 4 ids of 4 bytes (a roof's triangle has 3 vertices; roofs are few). */
#define PGT_FACADE_MESH_BYTES_PER_TRIANGLE 52u

/* Expands every facade completely. Errors: a terminal outside [-recess, protrusion] or outside
 * its scope (the grammar is not a BVH, sec. 8), the errors of pgt_facade_ray_stats (as messages
 * naming the grammar FILE:LINE:COL; the node budget bounds a path from the axiom, which every
 * ray that reaches its end develops), more than PGT_FACADE_MAX_TRIANGLES triangles. */
pgt_result pgt_facade_explicit(const pgt_facade_scene *s, const pgt_facade *facades,
                               uint32_t facade_count, pgt_facade_mesh *out, pgt_error *err);
/* The same with at most max_triangles triangles (0 or more than PGT_FACADE_MAX_TRIANGLES:
 * PGT_FACADE_MAX_TRIANGLES): a twin that would have more fails with PGT_ERROR_LIMIT ("more than
 * N triangles") and out empty; its arrays never grow past the limit's capacity (about
 * max_triangles * PGT_FACADE_MESH_BYTES_PER_TRIANGLE bytes, realloc's copies apart), so a caller
 * bounds the memory a grammar that instantiates billions of terminals can take. */
pgt_result pgt_facade_explicit_limit(const pgt_facade_scene *s, const pgt_facade *facades,
                                     uint32_t facade_count, uint32_t max_triangles,
                                     pgt_facade_mesh *out, pgt_error *err);

/* Steps of the development pgt_facade_explain takes at most: every facade of the shipped
 * grammars' test cities develops within a tenth of it (test_facade passes at 20,000); the bound
 * keeps an error report from expanding a grammar whose repeats produce billions of terminals (a
 * step evaluates a few expressions: a grammar whose terminals hold 2000-term expressions took
 * 0.4 s more to report its error). */
#define PGT_FACADE_EXPLAIN_STEPS 200000ull

/* The first error of facade f's complete development, as pgt_facade_explicit reports it (the
 * grammar's FILE:LINE:COL), without storing any geometry: what a caller of pgt_facade_render
 * prints when pgt_facade_render_stats.rays.errors names facade f (error_facade), whose rays only
 * carry the error bits. PGT_OK when the development is sound; PGT_ERROR_LIMIT when it finds no
 * error within PGT_FACADE_EXPLAIN_STEPS steps. fi is f's index (the mesh's facade numbers). */
pgt_result pgt_facade_explain(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                              pgt_error *err);

void pgt_facade_mesh_destroy(pgt_facade_mesh *m);

#ifdef __cplusplus
}
#endif

#endif
