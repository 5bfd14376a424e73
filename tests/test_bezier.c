/* Tests of the G1 Bezier construction (bezier.h, paper 000 section 6, issue 5 item 3): control
 * points against an independent double-precision computation, G1 and tangency at every joint,
 * interior curve points against de Casteljau in double, straight and C0 segments, thread
 * determinism, bad input. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/bezier.h>
#include <pgt/rng.h>

#include "test_util.h"

/* Control points vs the double computation: float32 rounding of a few dozen operations on
 * coordinates of magnitude <= ~10 (the random walks below), each ~6e-8 relative: 2e-6 x
 * (1 + |coordinate|) leaves room for the sums of up to a dozen unit directions at branch points. */
#define CONTROL_TOL 2e-6
/* A curve point is a convex combination of its control points (Bernstein weights >= 0, sum 1),
 * so their error carries over at most as CONTROL_TOL; pgt_bezier_eval's own float32 weights and
 * 4-term sum add a few ulps of the largest coordinate (~6e-8 each): 1e-6 more covers them. */
#define CURVE_TOL (CONTROL_TOL + 1e-6)
/* The straight polyline's handles against the chord's thirds: coordinates <= 2.5 (ulp 2.4e-7)
 * through a float32 normalisation, projection and division, a few roundings each. */
#define STRAIGHT_TOL 1e-6
/* G1 (the issue): the two handles at a joint are collinear within this angle (rad), and in the
 * tangent plane (|t . n| for the unit handle). */
#define G1_ANGLE_TOL 1e-4
#define TANGENT_PLANE_TOL 1e-4
/* A stored handle p - b carries its direction only to about sqrt(3) float ulps of the joint's
 * coordinates over its length: handles shorter than this many ulps (each then within 4.3e-5
 * rad, both within G1_ANGLE_TOL) are skipped in the angle check; the comparison with the double
 * computation still covers them. */
#define MIN_HANDLE_ULPS 4e4

typedef struct forest {
    uint32_t n;
    float *p, *nrm, *b1, *b2;
    uint32_t *parent;
    uint8_t *smooth;
} forest;

static void forest_free(forest *f) {
    free(f->p), free(f->nrm), free(f->b1), free(f->b2), free(f->parent), free(f->smooth);
    memset(f, 0, sizeof(*f));
}

/* A random forest: each point's parent is one of the last few points (so branches form) or
 * none; a point is its parent plus a random step of length 0.05-0.15; unit normals at random
 * (not perpendicular to anything in particular: the projection is exercised fully). */
static int forest_make(forest *f, uint32_t n, uint32_t seed) {
    memset(f, 0, sizeof(*f));
    f->n = n;
    f->p = malloc(12u * n), f->nrm = malloc(12u * n), f->b1 = malloc(12u * n);
    f->b2 = malloc(12u * n), f->parent = malloc(4u * n), f->smooth = malloc(n);
    if (!f->p || !f->nrm || !f->b1 || !f->b2 || !f->parent || !f->smooth) return 0;
    uint64_t c = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const float r = pgt_rng_float(seed, 0, c++);
        uint32_t a = PGT_NONE;
        if (i > 0 && r > 0.03f) {
            const uint32_t back = 1u + (uint32_t)(pgt_rng_float(seed, 0, c++) * 4.0f);
            a = back <= i ? i - back : i - 1u;
        }
        f->parent[i] = a;
        f->smooth[i] = PGT_BEZIER_C1;
        double d[3], len = 0.0;
        for (int k = 0; k < 3; ++k) {
            d[k] = 2.0 * pgt_rng_double(seed, 1, c++) - 1.0;
            len += d[k] * d[k];
        }
        len = sqrt(len);
        const double step = 0.05 + 0.1 * pgt_rng_double(seed, 1, c++);
        for (int k = 0; k < 3; ++k)
            f->p[3u * i + (uint32_t)k] =
                a == PGT_NONE ? (float)(2.0 * pgt_rng_double(seed, 2, c++) - 1.0)
                              : (float)(f->p[3u * a + (uint32_t)k] + step * d[k] / (len + 1e-9));
        double m[3], ml = 0.0;
        for (int k = 0; k < 3; ++k) {
            m[k] = 2.0 * pgt_rng_double(seed, 3, c++) - 1.0;
            ml += m[k] * m[k];
        }
        ml = sqrt(ml);
        for (int k = 0; k < 3; ++k) f->nrm[3u * i + (uint32_t)k] = (float)(m[k] / ml);
    }
    return 1;
}

/* The construction in double, from the float inputs, written independently (children found by
 * search, not by the library's accumulation order). */
static void reference(const forest *f, uint32_t i, double b1[3], double b2[3]) {
    const uint32_t a = f->parent[i];
    double ta[3] = {0, 0, 0}, tb[3] = {0, 0, 0};
    for (uint32_t side = 0; side < 2; ++side) {
        const uint32_t j = side == 0 ? a : i;
        double *t = side == 0 ? ta : tb;
        for (uint32_t s = 0; s < f->n; ++s) { /* every segment (parent[s] -> s) at j */
            const uint32_t ps = f->parent[s];
            if (ps == PGT_NONE || (ps != j && s != j)) continue;
            double d[3], l = 0.0;
            for (int k = 0; k < 3; ++k) {
                d[k] = (double)f->p[3u * s + (uint32_t)k] - f->p[3u * ps + (uint32_t)k];
                l += d[k] * d[k];
            }
            l = sqrt(l);
            for (int k = 0; k < 3; ++k) t[k] += d[k] / l;
        }
        const float *n = &f->nrm[3u * j];
        const double dn = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
        for (int k = 0; k < 3; ++k) t[k] -= dn * n[k];
    }
    const float *pa = &f->p[3u * a], *pb = &f->p[3u * i];
    double dab = 0.0, tta = 0.0, dba = 0.0, ttb = 0.0;
    for (int k = 0; k < 3; ++k) {
        dab += ta[k] * ((double)pb[k] - pa[k]), tta += ta[k] * ta[k];
        dba += tb[k] * ((double)pa[k] - pb[k]), ttb += tb[k] * tb[k];
    }
    for (int k = 0; k < 3; ++k) {
        b1[k] = pa[k] + ta[k] * dab / (3.0 * tta);
        b2[k] = pb[k] + tb[k] * dba / (3.0 * ttb);
    }
}

static void test_against_double(void) {
    forest f;
    REQUIRE(forest_make(&f, 3000, 7));
    pgt_error err = {0};
    REQUIRE(pgt_bezier_build(f.p, f.nrm, f.parent, NULL, f.n, 2, f.b1, f.b2, &err) == PGT_OK);
    double worst = 0.0;
    uint32_t segments = 0;
    for (uint32_t i = 0; i < f.n; ++i) {
        if (f.parent[i] == PGT_NONE) {
            CHECK(!memcmp(&f.b1[3u * i], &f.p[3u * i], 12) &&
                  !memcmp(&f.b2[3u * i], &f.p[3u * i], 12));
            continue;
        }
        segments++;
        double r1[3], r2[3];
        reference(&f, i, r1, r2);
        for (int k = 0; k < 3; ++k) {
            const double e1 = fabs(f.b1[3u * i + (uint32_t)k] - r1[k]) / (1.0 + fabs(r1[k]));
            const double e2 = fabs(f.b2[3u * i + (uint32_t)k] - r2[k]) / (1.0 + fabs(r2[k]));
            worst = fmax(worst, fmax(e1, e2));
        }
    }
    printf("  %u segments: worst control-point error %.3g (relative to 1 + |x|)\n", segments,
           worst);
    CHECK(segments > 2000);
    CHECK(worst <= CONTROL_TOL);
    forest_free(&f);
}

static double norm3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static void test_g1_and_tangent_plane(void) {
    forest f;
    REQUIRE(forest_make(&f, 3000, 11));
    REQUIRE(pgt_bezier_build(f.p, f.nrm, f.parent, NULL, f.n, 1, f.b1, f.b2, NULL) == PGT_OK);
    uint32_t joints = 0, skipped = 0;
    double worst_angle = 0.0, worst_plane = 0.0;
    for (uint32_t c = 0; c < f.n; ++c) { /* segment j -> c leaves joint j = parent[c] */
        const uint32_t j = f.parent[c];
        if (j == PGT_NONE || f.parent[j] == PGT_NONE) continue; /* j must also end a segment */
        double in[3], out[3];
        for (int k = 0; k < 3; ++k) {
            const uint32_t q = 3u * j + (uint32_t)k;
            in[k] = (double)f.p[q] - f.b2[q];                     /* end handle of parent[j] -> j */
            out[k] = (double)f.b1[3u * c + (uint32_t)k] - f.p[q]; /* start handle of j -> c */
        }
        const double li = norm3(in), lo = norm3(out);
        const float *pj = &f.p[3u * j];
        const float big = fmaxf(fabsf(pj[0]), fmaxf(fabsf(pj[1]), fabsf(pj[2])));
        const double ulp = (double)(nextafterf(big, INFINITY) - big);
        if (li < MIN_HANDLE_ULPS * ulp || lo < MIN_HANDLE_ULPS * ulp) {
            skipped++;
            continue;
        }
        joints++;
        const double cr[3] = {in[1] * out[2] - in[2] * out[1], in[2] * out[0] - in[0] * out[2],
                              in[0] * out[1] - in[1] * out[0]};
        worst_angle = fmax(worst_angle, asin(fmin(1.0, norm3(cr) / (li * lo))));
        const float *n = &f.nrm[3u * j];
        worst_plane = fmax(worst_plane, fabs(in[0] * n[0] + in[1] * n[1] + in[2] * n[2]) / li);
        worst_plane = fmax(worst_plane, fabs(out[0] * n[0] + out[1] * n[1] + out[2] * n[2]) / lo);
    }
    printf("  %u joints (%u with a handle too short for float to carry its direction skipped): "
           "handles collinear within %.3g rad, "
           "in the tangent plane within %.3g\n",
           joints, skipped, worst_angle, worst_plane);
    CHECK(joints > 2000);
    CHECK(worst_angle < G1_ANGLE_TOL);
    CHECK(worst_plane < TANGENT_PLANE_TOL);
    forest_free(&f);
}

/* The point at t of the cubic (p0, b1, b2, p1) in double by de Casteljau's construction
 * (repeated linear interpolation, not the Bernstein weights pgt_bezier_eval uses). */
static void de_casteljau(double c[4][3], double t, double out[3]) {
    double q[4][3];
    memcpy(q, c, sizeof q);
    for (int level = 3; level > 0; --level)
        for (int m = 0; m < level; ++m)
            for (int k = 0; k < 3; ++k) q[m][k] = (1.0 - t) * q[m][k] + t * q[m + 1][k];
    for (int k = 0; k < 3; ++k) out[k] = q[0][k];
}

/* Interior points of every segment (t = 1/4, 1/2, 3/4, where the handles weigh 9/64 to 3/8
 * each) from the built control points through pgt_bezier_eval, against de Casteljau in double
 * on the control points re-derived by reference(): a wrong handle moves these points, which the
 * end points (t = 0, 1) never show. */
static void test_curve_against_double(void) {
    forest f;
    REQUIRE(forest_make(&f, 500, 13));
    REQUIRE(pgt_bezier_build(f.p, f.nrm, f.parent, NULL, f.n, 1, f.b1, f.b2, NULL) == PGT_OK);
    static const float ts[3] = {0.25f, 0.5f, 0.75f};
    double worst = 0.0;
    uint32_t segments = 0;
    for (uint32_t i = 0; i < f.n; ++i) {
        const uint32_t a = f.parent[i];
        if (a == PGT_NONE) continue;
        segments++;
        double c[4][3];
        reference(&f, i, c[1], c[2]);
        for (int k = 0; k < 3; ++k) c[0][k] = f.p[3u * a + (uint32_t)k];
        for (int k = 0; k < 3; ++k) c[3][k] = f.p[3u * i + (uint32_t)k];
        for (int m = 0; m < 3; ++m) {
            float got[3];
            double want[3];
            pgt_bezier_eval(&f.p[3u * a], &f.b1[3u * i], &f.b2[3u * i], &f.p[3u * i], ts[m], got);
            de_casteljau(c, (double)ts[m], want);
            for (int k = 0; k < 3; ++k)
                worst = fmax(worst, fabs(got[k] - want[k]) / (1.0 + fabs(want[k])));
        }
    }
    printf("  %u segments: worst curve-point error %.3g (relative to 1 + |x|)\n", segments, worst);
    CHECK(segments > 400);
    CHECK(worst <= CURVE_TOL);
    forest_free(&f);
}

/* A straight polyline on a plane (normals perpendicular to it): every handle is the chord's
 * third (t is the line's direction); C0 and discontinuous segments are the chord's thirds on
 * any polyline. */
static void test_straight_and_c0(void) {
    enum { N = 6 };
    float p[3 * N], nrm[3 * N], b1[3 * N], b2[3 * N];
    uint32_t parent[N];
    for (uint32_t i = 0; i < N; ++i) {
        p[3 * i] = 0.25f * (float)i, p[3 * i + 1] = 0.5f * (float)i, p[3 * i + 2] = 0.0f;
        nrm[3 * i] = 0.0f, nrm[3 * i + 1] = 0.0f, nrm[3 * i + 2] = 1.0f;
        parent[i] = i ? i - 1u : PGT_NONE;
    }
    REQUIRE(pgt_bezier_build(p, nrm, parent, NULL, N, 1, b1, b2, NULL) == PGT_OK);
    for (uint32_t i = 1; i < N; ++i)
        for (int k = 0; k < 3; ++k) {
            const double third = p[3 * (i - 1) + k] + (p[3 * i + k] - p[3 * (i - 1) + k]) / 3.0;
            const double two = p[3 * (i - 1) + k] + 2.0 * (p[3 * i + k] - p[3 * (i - 1) + k]) / 3.0;
            CHECK(fabs(b1[3 * i + k] - third) < STRAIGHT_TOL &&
                  fabs(b2[3 * i + k] - two) < STRAIGHT_TOL);
        }
    forest f;
    REQUIRE(forest_make(&f, 200, 17));
    for (uint32_t i = 0; i < f.n; ++i)
        f.smooth[i] = (uint8_t)(i % 2 ? PGT_BEZIER_C0 : PGT_BEZIER_DISCONTINUOUS);
    REQUIRE(pgt_bezier_build(f.p, f.nrm, f.parent, f.smooth, f.n, 1, f.b1, f.b2, NULL) == PGT_OK);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < f.n; ++i) {
        const uint32_t a = f.parent[i];
        if (a == PGT_NONE) continue;
        for (int k = 0; k < 3; ++k) {
            const float pa = f.p[3u * a + (uint32_t)k], pb = f.p[3u * i + (uint32_t)k];
            bad += f.b1[3u * i + (uint32_t)k] != pa + (pb - pa) / 3.0f;
            bad += f.b2[3u * i + (uint32_t)k] != pb + (pa - pb) / 3.0f;
        }
    }
    CHECK_MSG(bad == 0, "%u C0 control coordinates are not the chord's thirds", bad);
    forest_free(&f);
}

static void test_threads_and_errors(void) {
    forest f, g;
    REQUIRE(forest_make(&f, 20000, 19) && forest_make(&g, 20000, 19));
    REQUIRE(pgt_bezier_build(f.p, f.nrm, f.parent, NULL, f.n, 1, f.b1, f.b2, NULL) == PGT_OK);
    REQUIRE(pgt_bezier_build(g.p, g.nrm, g.parent, NULL, g.n, 2, g.b1, g.b2, NULL) == PGT_OK);
    CHECK(!memcmp(f.b1, g.b1, 12u * f.n) && !memcmp(f.b2, g.b2, 12u * f.n));
    pgt_error err = {0};
    f.parent[10] = 10;
    CHECK(pgt_bezier_build(f.p, f.nrm, f.parent, NULL, f.n, 1, f.b1, f.b2, &err) ==
          PGT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err.message, "point 10") != NULL);
    f.parent[10] = 9;
    f.p[3u * 12u] = NAN;
    memset(&err, 0, sizeof(err)); /* pgt_error_set keeps the first message */
    CHECK(pgt_bezier_build(f.p, f.nrm, f.parent, NULL, f.n, 1, f.b1, f.b2, &err) ==
          PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "point 12") != NULL, "%s", err.message);
    forest_free(&f);
    forest_free(&g);
}

static const pgt_test_case cases[] = {
    {"against_double", test_against_double},
    {"g1_and_tangent_plane", test_g1_and_tangent_plane},
    {"curve_against_double", test_curve_against_double},
    {"straight_and_c0", test_straight_and_c0},
    {"threads_and_errors", test_threads_and_errors},
};

PGT_TEST_MAIN(cases)
