/* pgt: the woven sphere, the procedural reference model of paper 002 (issue 7).
 *
 * This work is based on:
 *   Paper 002 (R. Hoetzlein, the LUNA dataflow language), Appendix A "Reference Model" and
 *   section 4.5 "Performance Results" (Figure 4.11, the timing table):
 *   LOFT(SPHERIFY(SUBSET(PSYS(P, init_vol, init_vel), K, C, V)), CIRCLE(U)).
 *   W. Wang, B. Juettler, D. Zheng, Y. Liu, "Computation of rotation minimizing frames", ACM
 *   TOG 27(1), 2008: the double reflection method (their Algorithm 1), which tests/test_woven.c
 *   runs in double precision as the oracle of the loft's frames.
 *
 * The model, step by step, as built here:
 *
 * 1. PSYS (particles): P points uniform in [-1,1]^3, x = 2 pgt_rng_float(seed,
 *    PGT_WOVEN_STREAM_POSITION, 3 i + a) - 1 for axis a (exact in float32), each moving at
 *    PGT_WOVEN_SPEED (0.0025) per time step in a uniformly random direction: z = 1 - 2 u,
 *    phi = 2 pi w with u, w = pgt_rng_double(seed, PGT_WOVEN_STREAM_DIRECTION, 2 i + 0 / 1),
 *    computed in double (once, at creation) and rounded to the float32 velocity. A time step
 *    (pgt_woven_step, time step 1) is per axis x' = x + v, then if x' > 1: x' = 2 - x',
 *    v = -v; if x' < -1: x' = -2 - x', v = -v. This keeps every particle inside [-1,1]^3
 *    exactly, for any number of steps, with no clamping: x' is the float sum rounded, so
 *    x' > 1 means x' lies in (1, 1 + 0.0025] (rounding is monotonic and 1 is a float), and
 *    2 - x' is then exact (Sterbenz: x' within a factor 2 of 2), in [0.9975, 1); likewise at
 *    -1. A wall is only reached moving towards it (x <= 1 and v < 0 give x + v <= 1), and the
 *    flip keeps |v| bit for bit, so speeds never drift.
 *
 * 2. SUBSET: curve c takes K distinct particles as its control keys, in a random order: Floyd's
 *    algorithm picks the set (draw d = 0..K-1: an index uniform in [0, P-K+d]), then a
 *    Fisher-Yates shuffle orders it (draws K..2K-2). Draw d of curve c is pgt_rng_u64(seed,
 *    PGT_WOVEN_STREAM_SUBSET, (uint64_t)c << 32 | d), mapped to [0, n) by the exact 64-bit
 *    multiply-shift floor(r n / 2^64) (bias below n / 2^64). The subsets are drawn once, at
 *    creation: they are a pure function of (seed, c), so re-drawing them every frame would give
 *    the same indices; each frame re-derives the curves from the moved particles, so the curves
 *    "gradually morph along the sphere surface" (Appendix A) instead of jumping.
 *
 *    How K keys make a spline: a uniform cubic B-spline with the K keys as control points
 *    (the appendix's "CV control keys", control vertices that are not interpolated). It has
 *    K - 3 spans; span s (s = 0..K-4) uses keys s..s+3 and is the cubic Bezier curve with
 *    control points ((k0 + 4 k1 + k2) / 6, (2 k1 + k2) / 3, (k1 + 2 k2) / 3, (k1 + 4 k2 + k3)
 *    / 6) of its keys k0..k3, so the curve is a piecewise cubic Bezier spline whose spans share
 *    their ends, with C2 joints. Why this and not Bezier spans sharing every third key:
 *    - any K >= 4 works (shared-end Bezier spans need K = 3 n + 1);
 *    - random keys in a box would make shared-end spans only C0: the tube would crease at
 *      every joint; the B-spline is C2, so the frames and the loft are smooth;
 *    - every sample depends on 4 keys with weights that depend only on the sample's index:
 *      one table of V x 8 weights serves every curve and every frame (what a GPU kernel
 *      wants), and the curve stays inside its keys' convex hull (inside the box).
 *    Sampling: V samples at t_j = j (K - 3) / (V - 1), j = 0..V-1, computed as integers:
 *    j (K - 3) = s (V - 1) + r gives span s and u = r / (V - 1) (the last sample is span K - 4
 *    at u = 1), so the ends are exact; c(t) = N0(u) k_s + N1(u) k_s+1 + N2(u) k_s+2 +
 *    N3(u) k_s+3 with N0 = (1-u)^3/6, N1 = (3u^3 - 6u^2 + 4)/6, N2 = (-3u^3 + 3u^2 + 3u + 1)/6,
 *    N3 = u^3/6, and the derivative c'(t) with dN/du. The weights are computed in double once
 *    and stored as float32; the sums are float32.
 *
 * 3. SPHERIFY the sampled points (not the keys, as Appendix A insists): p_j = c_j / |c_j|,
 *    the length and the scaling by 1 / |c_j| in double (then rounded once to float32): a
 *    sample near the centre still lands on the unit sphere to float precision, and the cost
 *    is C V square roots per frame, nothing beside the loft. A sample exactly at the origin
 *    (a zero vector, which has no direction) takes the previous sample's point, or (0, 0, 1)
 *    for the first.
 *    Unit tangent of the spherified curve: t_j = c'_j - (p_j . c'_j) p_j, normalised (the
 *    derivative of c / |c| up to a positive factor); where that vanishes (the curve heading
 *    straight at the centre), the previous sample's tangent, else any unit vector perpendicular
 *    to p_j.
 *
 * 4. LOFT: a circle of radius PGT_WOVEN_RADIUS (0.025) swept along each spherified curve with
 *    a rotation-minimising frame (r_j, s_j) perpendicular to t_j. On a curve that lies on the
 *    unit sphere, the sphere's normal r = p is one, exactly: p is perpendicular to the tangent
 *    and its derivative, p' = |p'| t, has no component that turns it about t (the defining
 *    property of a rotation-minimising frame; equivalently, curves on a sphere have no
 *    geodesic torsion). So r_j = p_j made perpendicular to t_j in float32 (t_j is
 *    perpendicular to p_j up to rounding) and normalised, and s_j = t_j x r_j: each sample's
 *    frame on its own, with no chain from sample to sample. (Until 2026-11 this was the double
 *    reflection method of Wang et al. from r_0 = p_0 at the samples' spacing, an approximation
 *    of the same frame that drifted where curves turn sharply: at 179k, 246 of 17,550 rings
 *    twisted by more than 1e-4 rad, up to 2.8 degrees; tests/test_woven.c transports the
 *    frame in double in fine steps as the oracle.) A sample whose r_j vanishes
 *    (never on the sphere) takes any unit vector perpendicular to t_j.
 *    The circle has U vertices: vertex m (m = 0..U-1) at angle a_m = 2 pi m / (U - 1) has normal
 *    n = cos(a_m) r_j + sin(a_m) s_j and position p_j + 0.025 n; vertex U - 1 repeats vertex 0
 *    (the same bytes), closing the tube. That is how Appendix A's counts come out: U V vertices
 *    and 2 (U - 1)(V - 1) triangles per loft (a tube welded at its seam would have
 *    2 U (V - 1)); so the tube is closed in space and cut along the seam in its connectivity,
 *    with U - 1 distinct sides. No caps.
 *    Layout: loft c owns vertices c U V .. (c + 1) U V - 1, vertex (c, j, m) = c U V + j U + m
 *    (ring j along the curve, column m around it); its triangles are c 2 (U-1)(V-1) + 2 (j (U-1)
 *    + m) + {0, 1} = (a, a + 1, a + U + 1) and (a, a + U + 1, a + U) with a = vertex (c, j, m),
 *    for j < V - 1, m < U - 1: counter-clockwise seen from outside the tube. Curve point (c, j)
 *    (the spherified sample) is c V + j in curve_points.
 *
 * 5. Five resolutions (issue 7 item 5; the values of Figure A.1 are not in the text), chosen so
 *    that C U V equals the paper's rounded vertex counts exactly:
 *      name    P     K   C    U   V    vertices   triangles
 *      5k      150   6   25   8   25     5,000       8,400
 *      22k     660   6   110  8   25    22,000      36,960
 *      50k     800   8   100  10  50    50,000      88,200
 *      89k     1424  8   178  10  50    89,000     156,996
 *      179k    1432  8   179  10  100  179,000     318,978
 *    Low resolution (5k, 22k): 7-sided tubes, 25 samples along curves of 3 spans; medium (50k,
 *    89k): 9-sided, 50 samples along 5 spans; high (179k): 9-sided, 100 samples. The paper's
 *    rows pair the same way (low 5k / 22k, medium 50k / 89k, high 179k); within a pair only
 *    C changes. P = C K: on average every particle is a key of one curve (P only sizes the
 *    pool the subsets draw from; curves share keys at random).
 *
 * 6. Animation: a frame (pgt_woven_frame) is one time step of the particles followed by the
 *    evaluation of every curve, spherify and loft into the caller's preallocated arrays: a
 *    frame allocates nothing. The triangles never change and are written once, by
 *    pgt_woven_mesh_create (Appendix A: the object "requires vertex re-evaluation per frame").
 *
 * Determinism: every random draw is keyed by (seed, stream, counter) as above; the step is per
 * particle and the evaluation per curve, each computed by the same float32 code in the same
 * order whichever thread runs it (the reference is built with -ffp-contract=off), so the output
 * is the same bytes for any thread count. */
#ifndef PGT_WOVEN_H
#define PGT_WOVEN_H

#include <stdint.h>

#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Appendix A: "moving with a uniform velocity of 0.0025 in a random direction (time step
 * 1.0)", and the cross-section "a circle of radius 0.025". */
#define PGT_WOVEN_SPEED 0.0025f
#define PGT_WOVEN_RADIUS 0.025f

/* RNG streams ("WPOS", "WDIR", "WSUB"), distinct from every other module's. */
#define PGT_WOVEN_STREAM_POSITION 0x57504F53u
#define PGT_WOVEN_STREAM_DIRECTION 0x57444952u
#define PGT_WOVEN_STREAM_SUBSET 0x57535542u

/* Bounds of the parameters. Minima: a cubic B-spline span needs 4 keys; a tube needs 3
 * distinct sides (U - 1, the seam vertex repeats the first); a curve needs its 2 ends.
 * Maxima: far beyond any use, they keep a wrapped negative value (-1 passed as 4294967295)
 * an error naming it, and bound creation's work: the subset draws cost O(K) per curve (a
 * bitmap of P bits), and P particles take 24 bytes each. */
#define PGT_WOVEN_MIN_KEYS 4u
#define PGT_WOVEN_MIN_RING 4u
#define PGT_WOVEN_MIN_SAMPLES 2u
#define PGT_WOVEN_MAX_PARTICLES (1u << 24)
#define PGT_WOVEN_MAX_KEYS 4096u
#define PGT_WOVEN_MAX_CURVES (1u << 24)
#define PGT_WOVEN_MAX_RING 4096u
#define PGT_WOVEN_MAX_SAMPLES (1u << 20)

/* The model's parameters, in Appendix A's letters. */
typedef struct pgt_woven_params {
    uint32_t particles; /* P: particles in [-1,1]^3 */
    uint32_t keys;      /* K: keys (control points) per curve, 4 <= K <= P */
    uint32_t curves;    /* C: curves (and lofts) */
    uint32_t ring;      /* U: vertices of the loft's circle (the last repeats the first) */
    uint32_t samples;   /* V: samples per curve (rings per loft) */
} pgt_woven_params;

/* What a model of given parameters produces. */
typedef struct pgt_woven_counts {
    uint32_t curve_points; /* C V */
    uint32_t vertices;     /* C U V */
    uint32_t triangles;    /* 2 (U - 1)(V - 1) C */
    uint64_t bytes;        /* the arrays of pgt_woven and pgt_woven_mesh together */
} pgt_woven_counts;

/* The five resolutions of the paper's table (5k, 22k, 50k, 89k, 179k; see 5. above). */
#define PGT_WOVEN_RESOLUTION_COUNT 5u
typedef struct pgt_woven_resolution {
    const char *name; /* "5k", ... */
    pgt_woven_params params;
} pgt_woven_resolution;
extern const pgt_woven_resolution pgt_woven_resolutions[PGT_WOVEN_RESOLUTION_COUNT];

/* Checks parameters and gives the counts (out may be NULL).
 * PGT_ERROR_INVALID_ARGUMENT, naming the parameter and its value: P, K, C, U or V zero or below
 * its minimum, above its maximum, or K > P. PGT_ERROR_LIMIT, naming the product: C V, C K,
 * C U V or 2 (U - 1)(V - 1) C above 2^32 - 1 (uint32 indices), or an array's bytes above
 * SIZE_MAX. */
pgt_result pgt_woven_check(const pgt_woven_params *p, pgt_woven_counts *out, pgt_error *err);

/* The resolution called `name` ("5k" .. "179k"); PGT_ERROR_INVALID_ARGUMENT naming it and the
 * known names otherwise. */
pgt_result pgt_woven_find_resolution(const char *name, pgt_woven_params *out, pgt_error *err);

/* The animated state: particles, their velocities, the curves' keys, and the tables the
 * evaluation reads. Flat arrays; a caller (a test, a GPU backend) may read them, and may write
 * positions and velocities as long as positions stay in [-1,1]^3 and |v| per axis <= 1. */
typedef struct pgt_woven {
    pgt_woven_params params;
    pgt_woven_counts counts;
    uint32_t seed;
    uint64_t frame;    /* time steps taken since creation */
    float *positions;  /* 3 P */
    float *velocities; /* 3 P */
    uint32_t *keys;    /* C K: curve c's keys (particle indices, distinct) in curve order */
    uint32_t *span;    /* V: sample j's span s (keys s..s+3 of its curve) */
    float *basis;      /* 8 V: sample j's weights N0..N3, then dN0/du..dN3/du */
    float *ring_cos;   /* U: cos(2 pi m / (U - 1)), entry U - 1 = entry 0 */
    float *ring_sin;   /* U: likewise sin */
} pgt_woven;

/* Creates the state at time 0 for `seed`. On failure *out is zeroed (destroy is still safe).
 * Errors: those of pgt_woven_check; PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_woven_create(pgt_woven *out, const pgt_woven_params *p, uint32_t seed,
                            pgt_error *err);

/* Frees the arrays and zeroes *w; NULL or zeroed is a no-op. */
void pgt_woven_destroy(pgt_woven *w);

/* The output arrays of a model, allocated once and reused by every frame. */
typedef struct pgt_woven_mesh {
    pgt_woven_counts counts;
    float *curve_points; /* 3 C V: the spherified samples, curve by curve */
    float *positions;    /* 3 C U V */
    float *normals;      /* 3 C U V, unit, outward from the curve */
    uint32_t *triangles; /* 3 * 2 (U-1)(V-1) C: written by create, the same every frame */
} pgt_woven_mesh;

/* Allocates the arrays for parameters p and writes the triangles (layout in 4. above);
 * positions, normals and curve points are zero until a frame is evaluated. On failure *out is
 * zeroed. Errors: those of pgt_woven_check; PGT_ERROR_OUT_OF_MEMORY. */
pgt_result pgt_woven_mesh_create(pgt_woven_mesh *out, const pgt_woven_params *p, pgt_error *err);

/* Frees the arrays and zeroes *m; NULL or zeroed is a no-op. */
void pgt_woven_mesh_destroy(pgt_woven_mesh *m);

/* The triangles of parameters p (checked) into out (3 * counts.triangles entries). */
void pgt_woven_triangles(uint32_t *out, const pgt_woven_params *p);

/* One time step of every particle (1. above), on up to `threads` threads (0: 1). */
void pgt_woven_step(pgt_woven *w, uint32_t threads);

/* Curves, spherify and loft of the current particles into out (created for w's parameters):
 * curve_points, positions and normals; allocates nothing. Parallel over curves. */
void pgt_woven_evaluate(pgt_woven_mesh *out, const pgt_woven *w, uint32_t threads);

/* A frame of the animation: pgt_woven_step, then pgt_woven_evaluate. */
void pgt_woven_frame(pgt_woven_mesh *out, pgt_woven *w, uint32_t threads);

#ifdef __cplusplus
}
#endif

#endif
