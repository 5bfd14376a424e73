/* pgt: procedural input meshes made from fixed parameters and seeds (datasets_gen/README.md).
 *
 * Every generator fills *out with a new mesh (pgt_mesh_create; free it with pgt_mesh_destroy)
 * that is a consistently oriented 2-manifold, counter-clockwise seen from outside (+z for the
 * flat grid), with no degenerate or duplicate face and no duplicate vertex: vertices that
 * coincide are one index. Positions are computed in double and rounded to float32 once.
 * Randomness comes only from pgt_rng_* keyed by (seed, one of the streams below, element index),
 * so the same arguments always give the same bytes.
 *
 * Errors: a count below its minimum, or a radius/amplitude that is not finite or out of range,
 * returns PGT_ERROR_INVALID_ARGUMENT; a mesh whose vertex or face count would exceed
 * PGT_MESH_MAX_ELEMENTS returns PGT_ERROR_LIMIT; both with a message naming the function and
 * the argument. Counts are uint32_t, so a negative size reaches us as a huge one (LIMIT). On
 * failure *out is zeroed. err may be NULL; it keeps its first error (see pgt/result.h), so pass
 * a cleared one. */
#ifndef PGT_GEN_H
#define PGT_GEN_H

#include <stdint.h>

#include <pgt/facade.h>
#include <pgt/mesh.h>
#include <pgt/result.h>

#ifdef __cplusplus
extern "C" {
#endif

/* RNG streams (the `stream` argument of pgt_rng_*); the counter is the element index. */
#define PGT_GEN_STREAM_NOISY_TORUS 0x6E746F72u   /* per vertex: displacement along the normal */
#define PGT_GEN_STREAM_JAGGED_CUT 0x6A637574u    /* per pair of rim quads: which one is cut */
#define PGT_GEN_STREAM_JAGGED_HEIGHT 0x6A686774u /* per rim vertex: how far it is raised */
#define PGT_GEN_STREAM_CITY 0x63697479u          /* per building: 16 draws (pgt_gen_city) */

/* Most subdivision levels of an icosphere: 20 * 4^12 faces is the last that fits the limit. */
#define PGT_GEN_ICOSPHERE_MAX_LEVEL 12u

/* Chart gutter of the cube-sphere atlas, on each side of each chart (in UV units). */
#define PGT_GEN_CUBE_SPHERE_GUTTER (1.0 / 64.0)

/* Icosahedron (vertices on the unit sphere) split 1-to-4 `level` times; each new edge midpoint
 * is pushed back onto the unit sphere at its level. V = 10 * 4^level + 2, F = 20 * 4^level.
 * level <= PGT_GEN_ICOSPHERE_MAX_LEVEL (PGT_ERROR_LIMIT otherwise). */
pgt_result pgt_gen_icosphere(pgt_mesh *out, uint32_t level, pgt_error *err);

/* Torus around the z axis: major radius R, tube radius r (0 < r < R), nu segments around z and
 * nv around the tube (both >= 3). Vertex i*nv + j sits at angles u = 2 pi i / nu, v = 2 pi j / nv:
 * ((R + r cos v) cos u, (R + r cos v) sin u, r sin v). Each quad is split along the same diagonal.
 * V = nu * nv, F = 2 * nu * nv, genus 1. */
pgt_result pgt_gen_torus(pgt_mesh *out, double R, double r, uint32_t nu, uint32_t nv,
                         pgt_error *err);

/* pgt_gen_torus with vertex k moved along its outward tube normal by
 * amplitude * (2 * pgt_rng_double(seed, PGT_GEN_STREAM_NOISY_TORUS, k) - 1).
 * Needs 0 <= amplitude < r and r + amplitude < R (the tube neither inverts nor reaches the
 * axis). */
pgt_result pgt_gen_noisy_torus(pgt_mesh *out, double R, double r, uint32_t nu, uint32_t nv,
                               uint32_t seed, double amplitude, pgt_error *err);

/* Flat grid over [0,1]^2 in the z = 0 plane, nx x ny cells (both >= 1): vertex j*(nx+1) + i at
 * (i/nx, j/ny, 0). Cell (i, j) is cut along (i,j)-(i+1,j+1) when i + j is even and along
 * (i+1,j)-(i,j+1) when odd (a checkerboard of diagonals). Per-corner UVs equal (x, y).
 * V = (nx+1)(ny+1), F = 2 nx ny, one boundary loop of 2(nx+ny) edges. */
pgt_result pgt_gen_grid(pgt_mesh *out, uint32_t nx, uint32_t ny, pgt_error *err);

/* Upper unit hemisphere (a topological disk) with a jagged rim. A pole vertex and `rings` rings
 * (>= 2) of `segments` vertices (>= 3), ring k at polar angle (pi/2) k / rings, the last ring on
 * the equator. The rim is made jagged in two seeded ways (README "hemisphere_jagged"):
 *  - every odd rim vertex s is raised to polar angle pi/2 - (pi/2/rings) (0.25 + 0.5 h), with h =
 *    pgt_rng_double(seed, PGT_GEN_STREAM_JAGGED_HEIGHT, s);
 *  - of each pair of rim quads (2t, 2t+1) the triangle that holds the rim edge of exactly one of
 *    them is left out (bit 0 of pgt_rng_u64(seed, PGT_GEN_STREAM_JAGGED_CUT, t) picks which),
 *    carving a notch whose tip is a vertex of the ring above. Each vertex loses at most one
 *    triangle from one open fan, so the result stays a manifold disk.
 * V = 1 + rings * segments, F = segments (2 rings - 1) - floor(segments / 2), one boundary loop
 * of segments + floor(segments / 2) edges. */
pgt_result pgt_gen_hemisphere_jagged(pgt_mesh *out, uint32_t rings, uint32_t segments,
                                     uint32_t seed, pgt_error *err);

/* Cube [-1,1]^3 with each face an n x n grid (n >= 1), every vertex normalised onto the unit
 * sphere; vertices on cube edges and corners are shared. V = 6 n^2 + 2, F = 12 n^2, genus 0.
 * Labels = cube face id (0 +x, 1 -x, 2 +y, 3 -y, 4 +z, 5 -z). Per-corner UVs: face f is one chart
 * in cell (f % 3, f / 3) of a 3 x 2 atlas, inset by PGT_GEN_CUBE_SPHERE_GUTTER on every side,
 * orientation-preserving (every UV triangle counter-clockwise); corners on a cube edge carry the
 * UVs of their own face's chart, so cube edges are UV seams. */
pgt_result pgt_gen_cube_sphere(pgt_mesh *out, uint32_t n, pgt_error *err);

/* The torus of the benchmarks: R = 1, r = 0.4, nu : nv about 5 : 4, F = 2 nu nv as close to
 * faces_target (>= 18) as that shape allows: 100000 gives nu = 250, nv = 200, F = 100000. */
pgt_result pgt_gen_bench_torus(pgt_mesh *out, uint32_t faces_target, pgt_error *err);

/* The nu, nv that pgt_gen_bench_torus uses for faces_target (same errors). */
pgt_result pgt_gen_bench_torus_size(uint32_t faces_target, uint32_t *out_nu, uint32_t *out_nv,
                                    pgt_error *err);

/* The default named datasets of tests and benchmarks, with fixed parameters and seeds
 * (README "Default datasets"). Names are stable; index order may grow at the end. */
uint32_t pgt_gen_default_count(void);

/* Name of default i ("icosphere_l2", ...), or NULL when i >= count. */
const char *pgt_gen_default_name(uint32_t i);

/* Index of the default called `name`, or PGT_NONE. */
uint32_t pgt_gen_default_find(const char *name);

/* Builds default i into *out; PGT_ERROR_INVALID_ARGUMENT when i >= count. */
pgt_result pgt_gen_default(uint32_t i, pgt_mesh *out, pgt_error *err);

/* The facade city of paper 003 (issue 6 item 7): n buildings on a square grid of lots
 * (PGT_GEN_CITY_LOT metres apart, streets between), lot k at row k / side and column k % side,
 * side = ceil(sqrt(n)). Building k draws pgt_rng_double(seed, PGT_GEN_STREAM_CITY, 16 k + j)
 * for j = 0 .. 13: footprint width and depth (12 to 26 m, 10 to 24 m), its offset in the lot,
 * floors (3 to 12), floorHeight (2.8 to 3.6 m), windowWidth (1.8 to 2.8 m), doorWidth (1.2 to
 * 2.0 m), protrusion and recess (0.2 to 0.5 m each), and its colour (a pastel). The height is
 * floors * floorHeight. Footprints are rectangles listed counter-clockwise seen from above
 * (facade normals out). The params named above must exist in g (others keep g's values); g is
 * borrowed by *out (grammars[0]). The built-in geometry images are added (Mesh(0): facade.h). */
#define PGT_GEN_CITY_LOT 30.0
pgt_result pgt_gen_city(pgt_facade_scene *out, const pgt_grammar *g, uint32_t n, uint32_t seed,
                        pgt_error *err);

/* A non-box building for procedural facades on generic meshes (paper 003 sec. 10, issue 6 item
 * 6): a twisted tower of quads with an elliptic cross-section of semi-axes ax (along x) and az
 * (along z), from y = 0 to `height`, `segments` quads around (>= 3) and `rows` up (>= 1), the
 * cross-section turned by twist_deg degrees from bottom to top (|twist_deg| <= 90). Vertex (k, j),
 * k = 0 .. segments, j = 0 .. rows, at y_j = height j / rows and angle a = phi_j - 2 pi k /
 * segments, phi_j = twist y_j / height: position (ax cos a, y_j, az sin a), normal the ellipse's
 * outward normal (az cos a, 0, ax sin a) normalised (the twist shears the surface within its
 * tangent plane, so it does not tilt the normal), UV (s(phi_j) - s(a), y_j) with s the ellipse's
 * arc length from angle 0 (Simpson, double): u is metres around the tower, growing clockwise
 * seen from above so that t x b = n points out; v is metres up. Column k = segments repeats
 * column 0's positions with u = the perimeter (a UV seam: separate vertices). Quad (k, j) is
 * (k, j), (k + 1, j), (k + 1, j + 1), (k, j + 1), counter-clockwise seen from outside. */
pgt_result pgt_gen_tower(pgt_facade_quads *out, double ax, double az, double height,
                         double twist_deg, uint32_t segments, uint32_t rows, pgt_error *err);

#ifdef __cplusplus
}
#endif

#endif
