/* Tests of the woven sphere (woven.h; paper 002 Appendix A; issue 7): counts for every
 * resolution and odd parameters, curve samples on the unit sphere and equal to a double
 * B-spline oracle, loft vertices at the circle's radius, rotation-minimising frames on a great
 * circle and against a double-precision rotation-minimising frame, particles inside the box
 * for 10,000 frames (also started on the walls) with uniform directions, the key subsets, the same
 * bytes for 1 and 2 threads and two runs, and bad parameters. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/rng.h"
#include "pgt/woven.h"
#include "test_util.h"

/* The bound for | |p| - 1 |, computed in double from the float output. The samples
 * are normalised in double and rounded once to float32: |p| is 1 within ~1.5 ulp of 1
 * (1.8e-7), so 1e-6 holds with a 5x margin. */
#define SPHERE_TOL 1e-6
/* The bound for | |v - p| - 0.025 |: v = p + 0.025 n is a handful of float32
 * operations on coordinates below 1.03 (ulp 1.2e-7) with |n| = 1 within ~2e-7, so the error is
 * below 1e-6; 1e-5 leaves a 10x margin. */
#define LOFT_RADIUS_TOL 1e-5
/* Normals are unit within a few float32 roundings (the frame is normalised, then rotated by
 * float cos / sin of norm 1 +- 1e-7): 1e-6 is a 5x margin. */
#define NORMAL_UNIT_TOL 1e-6
/* The B-spline oracle (double) against the float32 curve before normalisation: the sum of 4
 * weighted keys (|k| <= sqrt 3, weights summing to 1) carries an absolute error of a few ulps
 * of 1 (< 1e-6); normalising divides it by |c|. So |p_float - p_double| <= BSPLINE_TOL / |c|;
 * samples with |c| < BSPLINE_MIN_LENGTH (the curve passing by the centre, where the direction
 * is ill-conditioned in any precision) are skipped. */
#define BSPLINE_TOL 2e-6
#define BSPLINE_MIN_LENGTH 1e-3
/* Great circle: the frame's s = t x r is +-z; its normal column at 90 degrees is cos(pi / 2)
 * r + sin(pi / 2) s in float32 (cos(pi / 2) rounds to -4.4e-8) from a frame in the plane up
 * to float32 rounding of coordinates <= 1: 1e-5 bounds a few hundred roundings. */
#define GREAT_CIRCLE_TOL 1e-5
/* Winding: where the curve's radius of curvature is below the tube's radius (tight turns, e.g.
 * a curve passing by the centre of the sphere), any tube of radius 0.025 folds on the inside of
 * the bend (0.3-0.8 % of the triangles of the five resolutions here). A tube section between
 * two rings cannot fold when the rings' disks are disjoint: each disk, tilted by less than
 * WINDING_MAX_TILT_DEG from the plane perpendicular to the chord between the two samples,
 * reaches at most R sin 30 = R / 2 along the chord, so a chord of at least
 * WINDING_MIN_CHORD_RADII = 1 radius keeps them apart. There every triangle must face
 * outwards. */
#define WINDING_MIN_CHORD_RADII 1.0
#define WINDING_MAX_TILT_DEG 30.0
/* The loft frames against a double-precision oracle (test_frames_rotation_minimising):
 * - RMF_SUBSTEPS: the oracle runs the double reflection method (Wang et al. 2008) on the double
 *   B-spline, spherified, at 64 steps per sample interval; its error is O(h^4) per unit
 *   length, far below the tolerances here;
 * - FD_STEP: the oracle's derivatives are central differences (one-sided of second order at the
 *   ends) of the double curve in the global parameter (spans of length 1): truncation about
 *   h^2 |S3| / 6 ~ 1e-11 |S3| (S3: the third derivative), rounding 1e-16 / h ~ 1e-11;
 * - FRAME_TOL: |n . T| for every ring normal n (the ring's plane perpendicular to the curve) and
 *   |n_0 - r| for column 0 against the oracle's frame r, in radians for small angles. The
 *   implementation's t comes from float32 sums of 4 keys (|k| <= sqrt 3) and a float32
 *   projection: an error of a few 1e-7 |c'| / (|c| |S'|), which the conditioning bound below
 *   keeps under 1e-5; 1e-4 is a 10x margin (measured: at most 6.5e-6). The double reflection
 *   at the samples' spacing in float32, which the loft used before 2026-11, fails it: 246 of
 *   17,550 rings of 179k off by up to 0.049 (2.8 degrees).
 * - FRAME_MIN_CONDITION: samples where |c| |S'| < 1e-2 |c'| (the curve heading nearly straight
 *   at the centre, where its spherified direction is ill-conditioned in float32) are not
 *   compared, and a curve whose fine steps come within FRAME_MIN_LENGTH of the centre is left
 *   out of the transport (there S turns through large angles within one fine step). */
#define RMF_SUBSTEPS 64u
#define FD_STEP 1e-5
#define FRAME_TOL 1e-4
#define FRAME_MIN_CONDITION 1e-2
#define FRAME_MIN_LENGTH 0.05
/* Key histogram: each particle is a key of C K / P curves on average; counts must lie within
 * this relative distance (10,000 curves x 4 keys over 10 particles: mean 4000, standard
 * deviation ~55, so 10 % is ~7 sigma: a check of the rule with a fixed seed, not a flake). */
#define KEY_HISTOGRAM_REL 0.10

static const uint32_t expected_vertices[PGT_WOVEN_RESOLUTION_COUNT] = {5000, 22000, 50000, 89000,
                                                                       179000};
static const uint32_t expected_triangles[PGT_WOVEN_RESOLUTION_COUNT] = {8400, 36960, 88200, 156996,
                                                                        318978};

/* Odd parameters: minimal K, U and V; K = P; prime counts; a single curve. */
static const pgt_woven_params odd_params[] = {
    {7, 5, 3, 5, 7}, {4, 4, 1, 4, 2}, {13, 4, 2, 17, 3}, {1000, 11, 7, 6, 33}, {5, 5, 9, 4, 101},
};
#define ODD_COUNT (sizeof odd_params / sizeof odd_params[0])

typedef struct model {
    pgt_woven w;
    pgt_woven_mesh m;
} model;

static int model_make(model *md, const pgt_woven_params *p, uint32_t seed) {
    pgt_error err = {0};
    memset(&md->m, 0, sizeof md->m);
    if (pgt_woven_create(&md->w, p, seed, &err) != PGT_OK ||
        pgt_woven_mesh_create(&md->m, p, &err) != PGT_OK) {
        fprintf(stderr, "  model: %s\n", err.message);
        pgt_woven_destroy(&md->w);
        return 0;
    }
    return 1;
}

static void model_free(model *md) {
    pgt_woven_destroy(&md->w);
    pgt_woven_mesh_destroy(&md->m);
}

static double dist3(const float *a, const float *b) {
    const double d[3] = {(double)a[0] - b[0], (double)a[1] - b[1], (double)a[2] - b[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static double norm3(const float *a) {
    return sqrt((double)a[0] * a[0] + (double)a[1] * a[1] + (double)a[2] * a[2]);
}

/* Counts and the triangle layout (woven.h, 4.): every index inside its own loft, the first
 * quad of every loft as documented. */
static void check_counts(const model *md, uint32_t want_vertices, uint32_t want_triangles) {
    const pgt_woven_params *p = &md->w.params;
    const uint32_t C = p->curves, U = p->ring, V = p->samples;
    CHECK(md->m.counts.vertices == want_vertices);
    CHECK(md->m.counts.triangles == want_triangles);
    CHECK(md->m.counts.curve_points == C * V);
    CHECK(md->w.counts.vertices == want_vertices);
    const uint32_t per_loft = 2u * (U - 1u) * (V - 1u);
    uint32_t bad = 0;
    for (uint32_t t = 0; t < md->m.counts.triangles; ++t) {
        const uint32_t c = t / per_loft, *tri = &md->m.triangles[3u * (size_t)t];
        for (int k = 0; k < 3; ++k) bad += tri[k] / (U * V) != c;
    }
    CHECK_MSG(bad == 0, "%u indices outside their loft", bad);
    for (uint32_t c = 0; c < C; ++c) {
        const uint32_t *tri = &md->m.triangles[3u * (size_t)c * per_loft], a = c * U * V;
        CHECK(tri[0] == a && tri[1] == a + 1u && tri[2] == a + U + 1u);
        CHECK(tri[3] == a && tri[4] == a + U + 1u && tri[5] == a + U);
    }
}

static void test_counts_resolutions(void) {
    for (uint32_t r = 0; r < PGT_WOVEN_RESOLUTION_COUNT; ++r) {
        const pgt_woven_resolution *res = &pgt_woven_resolutions[r];
        const pgt_woven_params *p = &res->params;
        pgt_woven_params q;
        pgt_error err = {0};
        REQUIRE(pgt_woven_find_resolution(res->name, &q, &err) == PGT_OK);
        CHECK(!memcmp(&q, p, sizeof q));
        CHECK(p->particles == p->curves * p->keys); /* P = C K, as documented */
        pgt_woven_counts n;
        REQUIRE(pgt_woven_check(p, &n, &err) == PGT_OK);
        CHECK(n.vertices == p->curves * p->ring * p->samples);
        CHECK(n.triangles == 2u * (p->ring - 1u) * (p->samples - 1u) * p->curves);
        model md;
        REQUIRE(model_make(&md, p, 1));
        check_counts(&md, expected_vertices[r], expected_triangles[r]);
        model_free(&md);
    }
}

static void test_counts_odd_params(void) {
    for (size_t i = 0; i < ODD_COUNT; ++i) {
        const pgt_woven_params *p = &odd_params[i];
        model md;
        REQUIRE(model_make(&md, p, 3));
        const uint32_t C = p->curves, U = p->ring, V = p->samples;
        check_counts(&md, C * U * V, 2u * (U - 1u) * (V - 1u) * C);
        pgt_woven_frame(&md.m, &md.w, 2);
        for (size_t q = 0; q < 3u * (size_t)md.m.counts.vertices; ++q)
            CHECK(isfinite(md.m.positions[q]) && isfinite(md.m.normals[q]));
        model_free(&md);
    }
}

/* Every curve sample on the unit sphere, every loft vertex at the radius from its sample, unit
 * normals along (v - p) / 0.025, the seam column repeating column 0 byte for byte. Returns the
 * number of failures (the checks report the first of each kind). */
static void check_geometry(const model *md, const char *what) {
    const pgt_woven_params *p = &md->w.params;
    const uint32_t U = p->ring;
    uint64_t off_sphere = 0, off_radius = 0, not_unit = 0, seam = 0, along = 0;
    double worst_sphere = 0.0, worst_radius = 0.0;
    for (uint32_t q = 0; q < md->m.counts.curve_points; ++q) {
        const float *c = &md->m.curve_points[3u * (size_t)q];
        const double e = fabs(norm3(c) - 1.0);
        worst_sphere = fmax(worst_sphere, e);
        off_sphere += !(e < SPHERE_TOL);
        const size_t first = (size_t)q * U;
        for (uint32_t m = 0; m < U; ++m) {
            const float *v = &md->m.positions[3u * (first + m)];
            const float *n = &md->m.normals[3u * (first + m)];
            const double d = fabs(dist3(v, c) - (double)PGT_WOVEN_RADIUS);
            worst_radius = fmax(worst_radius, d);
            off_radius += !(d < LOFT_RADIUS_TOL);
            not_unit += !(fabs(norm3(n) - 1.0) < NORMAL_UNIT_TOL);
            for (int k = 0; k < 3; ++k)
                along += !(fabs(((double)v[k] - c[k]) / PGT_WOVEN_RADIUS - n[k]) <
                           LOFT_RADIUS_TOL / PGT_WOVEN_RADIUS);
        }
        seam += memcmp(&md->m.positions[3u * (first + U - 1u)], &md->m.positions[3u * first],
                       3u * sizeof(float)) != 0 ||
                memcmp(&md->m.normals[3u * (first + U - 1u)], &md->m.normals[3u * first],
                       3u * sizeof(float)) != 0;
    }
    CHECK_MSG(off_sphere == 0, "%s: %llu samples off the sphere (worst %.3g)", what,
              (unsigned long long)off_sphere, worst_sphere);
    CHECK_MSG(off_radius == 0, "%s: %llu loft vertices off the radius (worst %.3g)", what,
              (unsigned long long)off_radius, worst_radius);
    CHECK_MSG(not_unit == 0, "%s: %llu normals not unit", what, (unsigned long long)not_unit);
    CHECK_MSG(along == 0, "%s: %llu normal components not along v - p", what,
              (unsigned long long)along);
    CHECK_MSG(seam == 0, "%s: %llu rings whose seam differs from column 0", what,
              (unsigned long long)seam);
}

/* Runs check on a model of every odd parameter set (seed `seed`), after one frame (`step`) or
 * at frame 0 (the initial particles, evaluated), named "odd params I". */
static void check_odd_params(uint32_t seed, int step, void (*check)(const model *, const char *)) {
    char what[64];
    for (size_t i = 0; i < ODD_COUNT; ++i) {
        model md;
        REQUIRE(model_make(&md, &odd_params[i], seed));
        if (step)
            pgt_woven_frame(&md.m, &md.w, 1);
        else
            pgt_woven_evaluate(&md.m, &md.w, 1);
        snprintf(what, sizeof what, "odd params %zu", i);
        check(&md, what);
        model_free(&md);
    }
}

static void test_sphere_and_radius(void) {
    char what[64];
    for (uint32_t r = 0; r < PGT_WOVEN_RESOLUTION_COUNT; ++r) {
        model md;
        REQUIRE(model_make(&md, &pgt_woven_resolutions[r].params, 1));
        for (uint32_t f = 0; f < 3; ++f) {
            pgt_woven_frame(&md.m, &md.w, 2);
            snprintf(what, sizeof what, "%s frame %u", pgt_woven_resolutions[r].name, f + 1u);
            check_geometry(&md, what);
        }
        model_free(&md);
    }
    check_odd_params(5, 1, check_geometry);
}

/* The curves against a double-precision uniform cubic B-spline of the same keys (woven.h, 2.),
 * including the ends (k0 + 4 k1 + k2) / 6 and (k_K-3 + 4 k_K-2 + k_K-1) / 6. */
static void check_bspline(const model *md, const char *what) {
    const pgt_woven_params *p = &md->w.params;
    const uint32_t K = p->keys, V = p->samples;
    uint64_t off = 0, checked = 0;
    for (uint32_t c = 0; c < p->curves; ++c) {
        const uint32_t *key = &md->w.keys[(size_t)c * K];
        for (uint32_t j = 0; j < V; ++j) {
            const uint64_t num = (uint64_t)j * (K - 3u), den = V - 1u;
            uint64_t s = num / den;
            double u = (double)(num % den) / (double)den;
            if (s == K - 3u) s = K - 4u, u = 1.0;
            const double v = 1.0 - u;
            const double b[4] = {v * v * v / 6.0, (3.0 * u * u * u - 6.0 * u * u + 4.0) / 6.0,
                                 (-3.0 * u * u * u + 3.0 * u * u + 3.0 * u + 1.0) / 6.0,
                                 u * u * u / 6.0};
            double cv[3] = {0.0, 0.0, 0.0};
            for (uint32_t i = 0; i < 4; ++i)
                for (int a = 0; a < 3; ++a)
                    cv[a] += b[i] * md->w.positions[3u * (size_t)key[s + i] + (size_t)a];
            const double l = sqrt(cv[0] * cv[0] + cv[1] * cv[1] + cv[2] * cv[2]);
            if (l < BSPLINE_MIN_LENGTH) continue;
            const float *got = &md->m.curve_points[3u * ((size_t)c * V + j)];
            double e = 0.0;
            for (int a = 0; a < 3; ++a) e = fmax(e, fabs((double)got[a] - cv[a] / l));
            off += !(e <= BSPLINE_TOL / l);
            checked++;
        }
    }
    CHECK_MSG(off == 0, "%s: %llu of %llu samples differ from the double B-spline", what,
              (unsigned long long)off, (unsigned long long)checked);
    CHECK(checked > 0);
}

static void test_curves_match_bspline(void) {
    for (uint32_t r = 0; r < PGT_WOVEN_RESOLUTION_COUNT; r += 2) {
        model md;
        REQUIRE(model_make(&md, &pgt_woven_resolutions[r].params, 9));
        pgt_woven_frame(&md.m, &md.w, 2);
        check_bspline(&md, pgt_woven_resolutions[r].name);
        model_free(&md);
    }
    check_odd_params(9, 0, check_bspline);
}

/* Keys in the plane z = 0: every curve is on the equator, the rotation-minimising frame keeps
 * r in the plane (r = p), so s = t x r = +-z: the
 * normal column at 90 degrees is +-z and column 0 has z = 0. (A frame that twisted would tilt
 * both.) */
static void test_frames_on_great_circle(void) {
    const pgt_woven_params p = {200, 7, 40, 9, 60}; /* U - 1 = 8: column 2 is at 90 degrees */
    model md;
    REQUIRE(model_make(&md, &p, 11));
    for (uint32_t i = 0; i < p.particles; ++i) md.w.positions[3u * i + 2u] = 0.0f;
    pgt_woven_evaluate(&md.m, &md.w, 2);
    uint64_t tilted = 0, off_plane = 0, rings = 0;
    for (uint32_t q = 0; q < md.m.counts.curve_points; ++q) {
        const float *c = &md.m.curve_points[3u * (size_t)q];
        if (fabsf(c[2]) > 0.0f) off_plane++;
        const float *n0 = &md.m.normals[3u * ((size_t)q * p.ring)];
        const float *n2 = &md.m.normals[3u * ((size_t)q * p.ring + 2u)];
        tilted += !(fabs(n0[2]) < GREAT_CIRCLE_TOL && fabs(fabs(n2[2]) - 1.0) < GREAT_CIRCLE_TOL);
        rings++;
    }
    CHECK_MSG(off_plane == 0, "%llu samples off the equator", (unsigned long long)off_plane);
    CHECK_MSG(tilted == 0, "%llu of %llu rings twisted out of the plane",
              (unsigned long long)tilted, (unsigned long long)rings);
    check_geometry(&md, "great circle");
    model_free(&md);
}

/* The double B-spline curve c of curve `key` at global parameter g in [0, K - 3] (span
 * floor(g), the last span for g = K - 3) from the particles' float positions, in double. */
static void spline_at(const model *md, const uint32_t *key, double g, double out[3]) {
    const uint32_t K = md->w.params.keys;
    double sf = floor(g);
    if (sf > (double)(K - 4u)) sf = (double)(K - 4u);
    if (sf < 0.0) sf = 0.0;
    const uint32_t s = (uint32_t)sf;
    const double u = g - sf, v = 1.0 - u;
    const double b[4] = {v * v * v / 6.0, (3.0 * u * u * u - 6.0 * u * u + 4.0) / 6.0,
                         (-3.0 * u * u * u + 3.0 * u * u + 3.0 * u + 1.0) / 6.0, u * u * u / 6.0};
    out[0] = out[1] = out[2] = 0.0;
    for (uint32_t i = 0; i < 4; ++i)
        for (int a = 0; a < 3; ++a)
            out[a] += b[i] * md->w.positions[3u * (size_t)key[s + i] + (size_t)a];
}

static double dnorm(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static double ddot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The spherified curve S = c / |c| at g, and the derivatives S' and c' of the parabolas through
 * three points h apart around g (centred, or shifted inside [0, K - 3] at the ends: one-sided of
 * second order). Returns |c|. */
static double sphere_curve(const model *md, const uint32_t *key, double g, double S[3],
                           double dS[3], double dc[3]) {
    const double gmax = (double)(md->w.params.keys - 3u), h = FD_STEP;
    const double g0 = g - h < 0.0 ? g : g + h > gmax ? g - 2.0 * h : g - h;
    double c0[3], c1[3], c2[3], c[3];
    spline_at(md, key, g0, c0);
    spline_at(md, key, g0 + h, c1);
    spline_at(md, key, g0 + 2.0 * h, c2);
    spline_at(md, key, g, c);
    const double l0 = dnorm(c0), l1 = dnorm(c1), l2 = dnorm(c2), l = dnorm(c);
    /* the parabola's derivative at g = g0 + o h, o in {0, 1, 2} */
    const double o = (g - g0) / h;
    const double w0 = (o - 1.5) / h, w1 = (2.0 - 2.0 * o) / h, w2 = (o - 0.5) / h;
    for (int a = 0; a < 3; ++a) {
        S[a] = c[a] / l;
        dS[a] = w0 * c0[a] / l0 + w1 * c1[a] / l1 + w2 * c2[a] / l2;
        dc[a] = w0 * c0[a] + w1 * c1[a] + w2 * c2[a];
    }
    return l;
}

/* v -= (2 / a.a)(a . v) a in double (the oracle's reflection), skipped for a = 0. */
static void dreflect(double v[3], const double a[3]) {
    const double aa = ddot(a, a);
    if (!(aa > 0.0)) return;
    const double f = 2.0 * ddot(a, v) / aa;
    for (int k = 0; k < 3; ++k) v[k] -= f * a[k];
}

/* The loft's frames against a double-precision oracle: every ring lies in the plane
 * perpendicular to the curve's tangent (finite differences of the double curve: this checks
 * the tangent's derivative weights), and column 0 points along the rotation-minimising frame
 * that the double reflection method carries from r_0 = S(0) along the curve in fine steps
 * (this checks that the frame neither twists nor lags). */
static void check_frames(const model *md, const char *what) {
    const pgt_woven_params *p = &md->w.params;
    const uint32_t K = p->keys, U = p->ring, V = p->samples;
    uint64_t tilted = 0, twisted = 0, compared = 0, transported = 0;
    double worst_tilt = 0.0, worst_twist = 0.0;
    const double gmax = (double)(K - 3u);
    for (uint32_t c = 0; c < p->curves; ++c) {
        const uint32_t *key = &md->w.keys[(size_t)c * K];
        double S[3], dS[3], dc[3], r[3], T[3];
        double l = sphere_curve(md, key, 0.0, S, dS, dc);
        int clear = l >= FRAME_MIN_LENGTH; /* the transport is trusted on this curve so far */
        for (int a = 0; a < 3; ++a) T[a] = dS[a] / dnorm(dS);
        const double st = ddot(S, T);
        for (int a = 0; a < 3; ++a) r[a] = S[a] - st * T[a];
        for (uint32_t j = 0; j < V; ++j) {
            const double gj = (double)j * gmax / (double)(V - 1u);
            const double gp = j ? (double)(j - 1u) * gmax / (double)(V - 1u) : 0.0;
            for (uint32_t k = 1; j > 0 && k <= RMF_SUBSTEPS; ++k) { /* from sample j - 1 to j */
                const double g = k == RMF_SUBSTEPS ? gj : gp + (gj - gp) * (double)k / RMF_SUBSTEPS;
                double S1[3], T1[3], v1[3], tl[3], v2[3];
                l = sphere_curve(md, key, g, S1, dS, dc);
                clear &= l >= FRAME_MIN_LENGTH;
                for (int a = 0; a < 3; ++a) T1[a] = dS[a] / dnorm(dS);
                for (int a = 0; a < 3; ++a) v1[a] = S1[a] - S[a], tl[a] = T[a];
                dreflect(r, v1), dreflect(tl, v1);
                for (int a = 0; a < 3; ++a) v2[a] = T1[a] - tl[a];
                dreflect(r, v2);
                memcpy(S, S1, sizeof S), memcpy(T, T1, sizeof T);
            }
            /* a sample whose spherified direction is ill-conditioned in float32 is skipped */
            if (!(l * dnorm(dS) >= FRAME_MIN_CONDITION * dnorm(dc))) continue;
            const size_t first = ((size_t)c * V + j) * U;
            double tilt = 0.0;
            for (uint32_t m = 0; m + 1u < U; ++m) {
                const float *n = &md->m.normals[3u * (first + m)];
                const double nd[3] = {n[0], n[1], n[2]};
                tilt = fmax(tilt, fabs(ddot(nd, T)));
            }
            worst_tilt = fmax(worst_tilt, tilt);
            tilted += !(tilt <= FRAME_TOL);
            compared++;
            if (!clear) continue;
            const float *n0 = &md->m.normals[3u * first];
            const double rl = dnorm(r);
            const double d[3] = {n0[0] - r[0] / rl, n0[1] - r[1] / rl, n0[2] - r[2] / rl};
            worst_twist = fmax(worst_twist, dnorm(d));
            twisted += !(dnorm(d) <= FRAME_TOL);
            transported++;
        }
    }
    const uint64_t rings = (uint64_t)p->curves * V;
    CHECK_MSG(tilted == 0, "%s: %llu of %llu rings tilted from the normal plane (worst %.3g)", what,
              (unsigned long long)tilted, (unsigned long long)compared, worst_tilt);
    CHECK_MSG(twisted == 0,
              "%s: %llu of %llu rings twisted from the transported frame (worst %.3g)", what,
              (unsigned long long)twisted, (unsigned long long)transported, worst_twist);
    /* the skips are the exception: most of the model is compared */
    CHECK_MSG(compared * 10u >= 9u * rings && transported * 2u >= rings,
              "%s: only %llu (%llu transported) of %llu rings compared", what,
              (unsigned long long)compared, (unsigned long long)transported,
              (unsigned long long)rings);
    if (getenv("PGT_TEST_VERBOSE"))
        fprintf(stderr, "  %s: %llu of %llu rings, worst tilt %.3g; %llu transported, worst %.3g\n",
                what, (unsigned long long)compared, (unsigned long long)rings, worst_tilt,
                (unsigned long long)transported, worst_twist);
}

static void test_frames_rotation_minimising(void) {
    for (uint32_t r = 0; r < PGT_WOVEN_RESOLUTION_COUNT; r += 2) {
        model md;
        REQUIRE(model_make(&md, &pgt_woven_resolutions[r].params, 4));
        for (uint32_t f = 0; f < 2; ++f) pgt_woven_frame(&md.m, &md.w, 2);
        check_frames(&md, pgt_woven_resolutions[r].name);
        model_free(&md);
    }
    check_odd_params(4, 0, check_frames);
}

/* A particle's speed is 0.0025 times a unit vector computed in double, rounded per axis: |v| is
 * within a few float roundings of 0.0025 (ulp 2.3e-10). */
#define SPEED_TOL 1e-9

/* Particles stay inside [-1,1]^3 over 10,000 frames; speeds per axis keep their bits; every
 * particle bounces (10,000 steps of 0.0025 is 25 units of path, its largest axis component at
 * least 25 / sqrt 3 units: it crosses the box several times). */
static void test_particles_in_box(void) {
    model md;
    REQUIRE(model_make(&md, &pgt_woven_resolutions[0].params, 1));
    const uint32_t P = md.w.params.particles;
    float *speed = malloc(3u * P * sizeof(float));
    uint32_t *bounces = calloc(P, sizeof(uint32_t));
    REQUIRE(speed && bounces);
    for (uint32_t q = 0; q < 3u * P; ++q) speed[q] = fabsf(md.w.velocities[q]);
    double worst = 0.0;
    for (uint32_t i = 0; i < P; ++i)
        worst = fmax(worst, fabs(norm3(&md.w.velocities[3u * i]) - (double)PGT_WOVEN_SPEED));
    CHECK_MSG(worst < SPEED_TOL, "speed off by %.3g", worst);
    uint64_t outside = 0, changed = 0;
    for (uint32_t f = 0; f < 10000; ++f) {
        pgt_woven_step(&md.w, 1u + (f & 1u));
        for (uint32_t q = 0; q < 3u * P; ++q) {
            const float x = md.w.positions[q], v = md.w.velocities[q];
            outside += !(x >= -1.0f && x <= 1.0f);
            changed += fabsf(v) != speed[q];
            /* a bounce leaves the particle inside, moving away from the wall it hit */
            bounces[q / 3u] += (x > 0.99f && v < 0.0f && x + speed[q] > 1.0f) ||
                               (x < -0.99f && v > 0.0f && x - speed[q] < -1.0f);
        }
    }
    CHECK_MSG(outside == 0, "%llu positions outside [-1,1]", (unsigned long long)outside);
    CHECK_MSG(changed == 0, "%llu speeds changed", (unsigned long long)changed);
    CHECK(md.w.frame == 10000u);
    uint32_t still = 0;
    for (uint32_t i = 0; i < P; ++i) still += bounces[i] == 0;
    CHECK_MSG(still == 0, "%u particles never bounced", still);
    free(speed), free(bounces);
    model_free(&md);
}

/* Particles started on and next to the walls, at the documented maximum speed per axis (1)
 * and at the model's: the reflection is exact, nothing leaves the box in 10,000 steps. */
static void test_particles_at_walls(void) {
    const pgt_woven_params p = {16, 4, 1, 4, 2};
    model md;
    REQUIRE(model_make(&md, &p, 2));
    const float one_minus = nextafterf(1.0f, 0.0f);
    const float start[8] = {1.0f, -1.0f, one_minus, -one_minus, 0.99875f, -0.99875f, 0.0f, 0.5f};
    const float speed[4] = {PGT_WOVEN_SPEED, 1.0f, nextafterf(PGT_WOVEN_SPEED, 1.0f), 0.7f};
    for (uint32_t i = 0; i < p.particles; ++i)
        for (uint32_t a = 0; a < 3; ++a) {
            const uint32_t q = 3u * i + a;
            md.w.positions[q] = start[(i + a) % 8u];
            md.w.velocities[q] = (q & 1u ? 1.0f : -1.0f) * speed[(i / 2u + a) % 4u];
        }
    /* one step from x = 1 - 0.001 at v = 0.0025: 1.0015 (rounded) reflects to 2 - 1.0015,
     * exactly, which the double computation reproduces */
    md.w.positions[0] = 0.999f, md.w.velocities[0] = PGT_WOVEN_SPEED;
    const float x1 = 0.999f + PGT_WOVEN_SPEED;
    const float want = (float)(2.0 - (double)x1);
    CHECK(x1 > 1.0f && (double)want == 2.0 - (double)x1);
    pgt_woven_step(&md.w, 1);
    CHECK(md.w.positions[0] == want && md.w.velocities[0] == -PGT_WOVEN_SPEED);
    uint64_t outside = 0;
    for (uint32_t f = 0; f < 10000; ++f) {
        pgt_woven_step(&md.w, 1);
        for (uint32_t q = 0; q < 3u * p.particles; ++q)
            outside += !(md.w.positions[q] >= -1.0f && md.w.positions[q] <= 1.0f);
    }
    CHECK_MSG(outside == 0, "%llu positions outside [-1,1]", (unsigned long long)outside);
    pgt_woven_evaluate(&md.m, &md.w, 1);
    check_geometry(&md, "walls");
    model_free(&md);
}

static void sub3(const float *a, const float *b, double r[3]) {
    for (int k = 0; k < 3; ++k) r[k] = (double)a[k] - b[k];
}

/* The unit tangent of ring q (the normal of its plane) from its first two normals:
 * n0 x n1 = r x (cos a1 r + sin a1 s) = sin a1 t, with sin a1 > 0 for U >= 4. */
static void ring_tangent(const model *md, size_t q, double t[3]) {
    const float *n0 = &md->m.normals[3u * q * md->w.params.ring], *n1 = n0 + 3;
    t[0] = (double)n0[1] * n1[2] - (double)n0[2] * n1[1];
    t[1] = (double)n0[2] * n1[0] - (double)n0[0] * n1[2];
    t[2] = (double)n0[0] * n1[1] - (double)n0[1] * n1[0];
    const double l = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int k = 0; k < 3; ++k) t[k] /= l;
}

/* Triangles of gently bent tube sections face outwards (their normal agrees with their
 * vertices' normals): the layout's winding and a frame without twists between rings. */
static void test_winding_outward(void) {
    const double cos_tilt = cos(WINDING_MAX_TILT_DEG * 3.141592653589793 / 180.0);
    for (uint32_t r = 0; r < PGT_WOVEN_RESOLUTION_COUNT; ++r) {
        model md;
        REQUIRE(model_make(&md, &pgt_woven_resolutions[r].params, 1));
        const uint32_t U = md.w.params.ring, V = md.w.params.samples;
        const uint32_t per_loft = 2u * (U - 1u) * (V - 1u);
        uint64_t gentle = 0, inward = 0, total = 0;
        for (uint32_t f = 0; f < 2; ++f) {
            pgt_woven_frame(&md.m, &md.w, 2);
            const float *pts = md.m.curve_points;
            for (uint32_t t = 0; t < md.m.counts.triangles; ++t) {
                total++;
                const uint32_t c = t / per_loft, j = (t % per_loft) / (2u * (U - 1u));
                const size_t q = (size_t)c * V + j;
                double chord[3], ta[3], tb[3];
                sub3(&pts[3u * (q + 1u)], &pts[3u * q], chord);
                const double l =
                    sqrt(chord[0] * chord[0] + chord[1] * chord[1] + chord[2] * chord[2]);
                if (l < WINDING_MIN_CHORD_RADII * PGT_WOVEN_RADIUS) continue;
                ring_tangent(&md, q, ta), ring_tangent(&md, q + 1u, tb);
                const double ca = (ta[0] * chord[0] + ta[1] * chord[1] + ta[2] * chord[2]) / l;
                const double cb = (tb[0] * chord[0] + tb[1] * chord[1] + tb[2] * chord[2]) / l;
                if (!(ca > cos_tilt && cb > cos_tilt)) continue;
                const uint32_t *tri = &md.m.triangles[3u * (size_t)t];
                double e1[3], e2[3], s = 0.0;
                sub3(&md.m.positions[3u * (size_t)tri[1]], &md.m.positions[3u * (size_t)tri[0]],
                     e1);
                sub3(&md.m.positions[3u * (size_t)tri[2]], &md.m.positions[3u * (size_t)tri[0]],
                     e2);
                const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                     e1[0] * e2[1] - e1[1] * e2[0]};
                for (int k = 0; k < 3; ++k)
                    for (int v = 0; v < 3; ++v)
                        s += n[k] * md.m.normals[3u * (size_t)tri[v] + (size_t)k];
                gentle++;
                inward += !(s > 0.0);
            }
        }
        CHECK_MSG(inward == 0, "%s: %llu of %llu gently bent triangles face inwards",
                  pgt_woven_resolutions[r].name, (unsigned long long)inward,
                  (unsigned long long)gentle);
        /* and the test is not vacuous: most of the tube is gently bent */
        CHECK_MSG(gentle * 4u > total * 3u, "%s: only %llu of %llu triangles gently bent",
                  pgt_woven_resolutions[r].name, (unsigned long long)gentle,
                  (unsigned long long)total);
        model_free(&md);
    }
}

/* Keys: distinct, below P, a pure function of (seed, curve), every particle equally likely in
 * every key slot. */
static void test_keys(void) {
    const pgt_woven_params small = {10, 4, 10000, 4, 2}, prefix = {10, 4, 50, 4, 2};
    const pgt_woven_params all = {9, 9, 30, 4, 2};
    model a, b, c;
    REQUIRE(model_make(&a, &small, 4));
    REQUIRE(model_make(&b, &prefix, 4));
    REQUIRE(model_make(&c, &all, 4));
    CHECK(!memcmp(a.w.keys, b.w.keys, 50u * 4u * sizeof(uint32_t)));
    uint32_t hist[4][10];
    memset(hist, 0, sizeof hist);
    uint64_t dup = 0, range = 0;
    for (uint32_t k = 0; k < small.curves; ++k) {
        const uint32_t *key = &a.w.keys[4u * k];
        for (uint32_t i = 0; i < 4; ++i) {
            range += key[i] >= 10u;
            if (key[i] < 10u) hist[i][key[i]]++;
            for (uint32_t j = 0; j < i; ++j) dup += key[i] == key[j];
        }
    }
    CHECK(dup == 0 && range == 0);
    const double mean = small.curves / 10.0;
    for (uint32_t i = 0; i < 4; ++i)
        for (uint32_t x = 0; x < 10; ++x)
            CHECK_MSG(fabs(hist[i][x] - mean) <= KEY_HISTOGRAM_REL * mean,
                      "slot %u particle %u: %u times, mean %.0f", i, x, hist[i][x], mean);
    for (uint32_t k = 0; k < all.curves; ++k) { /* K = P: a permutation */
        uint32_t seen = 0;
        for (uint32_t i = 0; i < 9; ++i) seen |= 1u << c.w.keys[9u * k + i];
        CHECK(seen == 0x1FFu);
    }
    model d;
    REQUIRE(model_make(&d, &prefix, 5));
    CHECK(memcmp(d.w.keys, b.w.keys, 50u * 4u * sizeof(uint32_t)) != 0);
    model_free(&a), model_free(&b), model_free(&c), model_free(&d);
}

static int same_mesh(const pgt_woven_mesh *x, const pgt_woven_mesh *y) {
    const size_t v = 3u * (size_t)x->counts.vertices;
    return !memcmp(&x->counts, &y->counts, sizeof x->counts) &&
           !memcmp(x->positions, y->positions, v * sizeof(float)) &&
           !memcmp(x->normals, y->normals, v * sizeof(float)) &&
           !memcmp(x->curve_points, y->curve_points,
                   3u * (size_t)x->counts.curve_points * sizeof(float)) &&
           !memcmp(x->triangles, y->triangles, 3u * (size_t)x->counts.triangles * sizeof(uint32_t));
}

/* The same bytes for 1 and 2 threads and for two runs of the same seed: on the largest model
 * (the loft's loop split among threads; its 1432 particles are too few to split the step) and
 * on one with 20,000 particles, whose step is split too (pgt_parallel_for splits from 2 x 4096
 * items). */
static void same_bytes_of(const pgt_woven_params *p) {
    model one, two, again, other;
    REQUIRE(model_make(&one, p, 7));
    REQUIRE(model_make(&two, p, 7));
    REQUIRE(model_make(&again, p, 7));
    REQUIRE(model_make(&other, p, 8));
    for (uint32_t f = 0; f < 5; ++f) {
        pgt_woven_frame(&one.m, &one.w, 1);
        pgt_woven_frame(&two.m, &two.w, 2);
        pgt_woven_frame(&again.m, &again.w, 1);
        pgt_woven_frame(&other.m, &other.w, 2);
        CHECK_MSG(same_mesh(&one.m, &two.m), "frame %u: 1 and 2 threads differ", f + 1u);
        CHECK_MSG(same_mesh(&one.m, &again.m), "frame %u: two runs differ", f + 1u);
        CHECK(!memcmp(one.w.positions, two.w.positions, 3u * p->particles * sizeof(float)));
    }
    CHECK(!same_mesh(&one.m, &other.m));
    model_free(&one), model_free(&two), model_free(&again), model_free(&other);
}

static void test_same_bytes(void) {
    same_bytes_of(&pgt_woven_resolutions[PGT_WOVEN_RESOLUTION_COUNT - 1u].params);
    same_bytes_of(&(pgt_woven_params){20000, 8, 50, 4, 10});
}

/* Directions uniform on the sphere (woven.h, 1.): over N particles the mean velocity is 0 and
 * each axis's mean square is speed^2 / 3 (a uniform direction's coordinate is uniform in
 * [-1, 1]: variance 1/3, fourth moment 1/5). Bounds of DIRECTION_SIGMAS standard deviations of
 * those means (a fixed seed: a check of the rule, not a flake). A biased draw (a hemisphere, or
 * half the azimuths) moves a mean by about half the speed, hundreds of sigmas here. */
#define DIRECTION_SIGMAS 6.0
static void test_particle_directions(void) {
    const pgt_woven_params p = {200000, 4, 1, 4, 2};
    model md;
    REQUIRE(model_make(&md, &p, 21));
    const double N = p.particles, speed = PGT_WOVEN_SPEED;
    double mean[3] = {0.0, 0.0, 0.0}, square[3] = {0.0, 0.0, 0.0};
    uint32_t off_speed = 0;
    for (uint32_t i = 0; i < p.particles; ++i) {
        const float *v = &md.w.velocities[3u * (size_t)i];
        for (int a = 0; a < 3; ++a)
            mean[a] += v[a] / speed / N, square[a] += (v[a] / speed) * (v[a] / speed) / N;
        off_speed += !(fabs(norm3(v) / speed - 1.0) < NORMAL_UNIT_TOL);
    }
    CHECK_MSG(off_speed == 0, "%u particles off the speed", off_speed);
    const double mean_bound = DIRECTION_SIGMAS * sqrt(1.0 / 3.0 / N),
                 square_bound = DIRECTION_SIGMAS * sqrt((1.0 / 5.0 - 1.0 / 9.0) / N);
    for (int a = 0; a < 3; ++a) {
        CHECK_MSG(fabs(mean[a]) < mean_bound, "axis %d: mean direction %.3g (bound %.3g)", a,
                  mean[a], mean_bound);
        CHECK_MSG(fabs(square[a] - 1.0 / 3.0) < square_bound,
                  "axis %d: mean square %.5f, not 1/3 (bound %.3g)", a, square[a], square_bound);
    }
    model_free(&md);
}

/* The error code, and the message naming what is wrong. */
static void expect_error(const pgt_woven_params *p, pgt_result code, const char *needle) {
    pgt_error err = {0};
    pgt_woven_counts n = {1, 1, 1, 1};
    CHECK(pgt_woven_check(p, &n, &err) == code);
    CHECK(n.vertices == 0 && n.triangles == 0 && n.bytes == 0);
    CHECK_MSG(strstr(err.message, needle) != NULL, "message '%s' lacks '%s'", err.message, needle);
    pgt_woven w;
    pgt_woven_mesh m;
    pgt_error e2 = {0}, e3 = {0};
    CHECK(pgt_woven_create(&w, p, 1, &e2) == code && w.positions == NULL);
    CHECK(pgt_woven_mesh_create(&m, p, &e3) == code && m.positions == NULL);
    CHECK(!strcmp(err.message, e2.message) && !strcmp(err.message, e3.message));
    pgt_woven_destroy(&w), pgt_woven_mesh_destroy(&m);
}

static void test_bad_params(void) {
    const pgt_result INV = PGT_ERROR_INVALID_ARGUMENT, LIM = PGT_ERROR_LIMIT;
    expect_error(&(pgt_woven_params){0, 4, 1, 4, 2}, INV, "P = 0");
    expect_error(&(pgt_woven_params){10, 0, 1, 4, 2}, INV, "K = 0");
    expect_error(&(pgt_woven_params){10, 3, 1, 4, 2}, INV, "K = 3");
    expect_error(&(pgt_woven_params){10, 4, 0, 4, 2}, INV, "C = 0");
    expect_error(&(pgt_woven_params){10, 4, 1, 0, 2}, INV, "U = 0");
    expect_error(&(pgt_woven_params){10, 4, 1, 3, 2}, INV, "U = 3");
    expect_error(&(pgt_woven_params){10, 4, 1, 4, 0}, INV, "V = 0");
    expect_error(&(pgt_woven_params){10, 4, 1, 4, 1}, INV, "V = 1");
    expect_error(&(pgt_woven_params){5, 6, 1, 4, 2}, INV, "K <= P");
    /* -1 through an unsigned parameter */
    expect_error(&(pgt_woven_params){10, 4, (uint32_t)-1, 4, 2}, INV, "negative");
    expect_error(&(pgt_woven_params){(uint32_t)-5, 4, 1, 4, 2}, INV, "P = 4294967291");
    expect_error(&(pgt_woven_params){10, PGT_WOVEN_MAX_KEYS + 1u, 1, 4, 2}, INV, "K = 4097");
    /* overflowing 32-bit counts: each product alone */
    expect_error(&(pgt_woven_params){10, 4, 1u << 24, 4, 1u << 20}, LIM, "C*V");
    expect_error(&(pgt_woven_params){4096, 4096, 1u << 24, 4, 2}, LIM, "C*K");
    expect_error(&(pgt_woven_params){10, 4, 1u << 20, 4096, 2}, LIM, "C*U*V");
    expect_error(&(pgt_woven_params){10, 4, 1, 4096, 600000}, LIM, "2*(U-1)*(V-1)*C");
    pgt_error err = {0};
    CHECK(pgt_woven_check(NULL, NULL, &err) == INV);
    pgt_woven_params q;
    pgt_error e7 = {0};
    CHECK(pgt_woven_find_resolution("7k", &q, &e7) == INV);
    CHECK_MSG(strstr(e7.message, "'7k'") != NULL, "message '%s'", e7.message);
    CHECK(pgt_woven_find_resolution(NULL, &q, NULL) == INV);
    /* the largest valid counts pass the check (nothing allocated) */
    CHECK(pgt_woven_check(&(pgt_woven_params){10, 4, 1, 4096, 524288}, NULL, NULL) == PGT_OK);
    pgt_woven_destroy(NULL), pgt_woven_mesh_destroy(NULL);
}

/* One frame's move of a curve sample that counts as a jump: a tenth of the unit sphere's radius,
 * where the gradual morph moves a sample 0.0023 on average and 0.027 at most (measured on the
 * 22k resolution, frame 10 to 11). Fewer than 1 in FRAME_JUMP_RARITY samples may jump: near the
 * centre a curve's direction turns fast (see BSPLINE_MIN_LENGTH). Measured: none. */
#define FRAME_JUMP 0.1
#define FRAME_JUMP_RARITY 100u

/* A frame is step + evaluate; stepping does not depend on the thread count; evaluate does not
 * move the particles. */
static void test_frames(void) {
    const pgt_woven_params *p = &pgt_woven_resolutions[1].params;
    model a, b;
    REQUIRE(model_make(&a, p, 3));
    REQUIRE(model_make(&b, p, 3));
    for (uint32_t f = 0; f < 10; ++f) pgt_woven_frame(&a.m, &a.w, 2);
    for (uint32_t f = 0; f < 10; ++f) pgt_woven_step(&b.w, 1);
    pgt_woven_evaluate(&b.m, &b.w, 1);
    pgt_woven_evaluate(&b.m, &b.w, 2);
    CHECK(a.w.frame == 10u && b.w.frame == 10u);
    CHECK(same_mesh(&a.m, &b.m));
    /* the curves morph gradually: one step moves a sample far less than the sphere's size */
    float *before = malloc(3u * (size_t)a.m.counts.curve_points * sizeof(float));
    REQUIRE(before);
    memcpy(before, a.m.curve_points, 3u * (size_t)a.m.counts.curve_points * sizeof(float));
    pgt_woven_frame(&a.m, &a.w, 2);
    double moved = 0.0;
    uint32_t far = 0;
    for (uint32_t q = 0; q < a.m.counts.curve_points; ++q) {
        const double d = dist3(&before[3u * q], &a.m.curve_points[3u * q]);
        moved += d;
        far += d > FRAME_JUMP;
    }
    CHECK(moved > 0.0);
    CHECK_MSG(far * FRAME_JUMP_RARITY < a.m.counts.curve_points, "%u samples jumped > %g", far,
              FRAME_JUMP);
    free(before);
    model_free(&a), model_free(&b);
}

static const pgt_test_case cases[] = {
    {"counts_resolutions", test_counts_resolutions},
    {"counts_odd_params", test_counts_odd_params},
    {"sphere_and_radius", test_sphere_and_radius},
    {"curves_match_bspline", test_curves_match_bspline},
    {"frames_on_great_circle", test_frames_on_great_circle},
    {"frames_rotation_minimising", test_frames_rotation_minimising},
    {"winding_outward", test_winding_outward},
    {"particles_in_box", test_particles_in_box},
    {"particles_at_walls", test_particles_at_walls},
    {"keys", test_keys},
    {"same_bytes", test_same_bytes},
    {"particle_directions", test_particle_directions},
    {"bad_params", test_bad_params},
    {"frames", test_frames},
};

PGT_TEST_MAIN(cases)
