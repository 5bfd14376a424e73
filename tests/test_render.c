/* pgt tests: the figure ray tracer (harness/render.c, Embree 3) against analytic answers.
 *
 * A tessellated unit sphere seen along one of its face normals: the share of pixels it covers
 * is the projected disc's area within the pixel-quantisation and tessellation bounds derived
 * below, and the centre pixel has the Lambert value of a normal facing the camera. A small quad
 * over a large one: the pixel in its shadow and a lit pixel have the ambient-only and lit
 * values, so their ratio is 0.25 / (0.25 + 0.75 n.l). Pixels are located through the camera
 * convention of render.h, computed here independently. Also: the same bytes for 1, 2 and 3
 * threads and for shared or copied vertex buffers, the automatic framing's geometry, per-mesh
 * colours and the background, and every invalid argument. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/mesh_io.h>

#include "gen.h"
#include "render.h"
#include "test_util.h"

#define PI 3.14159265358979323846

/* Pixel quantisation of a 1-spp count: a pixel whose centre lies in a disc of radius R lies
 * inside the disc of radius R + h, and every point of the disc of radius R - h lies in such a
 * pixel (its pixel's centre is within h of it), h = half the pixel diagonal. So the count of a
 * shape lying between discs R_in and R_out is within [pi (R_in - h)^2, pi (R_out + h)^2]. */
#define PIXEL_HALF_DIAGONAL 0.70710678118654752

/* Relative tolerance of the sphere's covered-pixel count against pi R^2 (R: the exact sphere's
 * projected radius, 246.2 px here). Pixel quantisation (above): 2 h / R + (h / R)^2 = 0.575 %.
 * Tessellation: the icosphere of level 5 lies between its vertex sphere (radius 1) and the
 * sphere touching its face planes (radius 0.99972, measured by the test), whose silhouette is
 * 0.061 % smaller in area. So the count is within -0.634 % / +0.575 % of pi R^2; the test
 * checks at run time that the bounds it derives from the actual mesh stay inside this constant.
 * (Measured: -0.015 %.) */
#define DISC_AREA_TOL_REL 0.0075

/* 8-bit tolerance of a shaded pixel against its analytic value: 1/255 for float rounding of the
 * normal, light and sRGB curve (the exact value is about 219.4, far from where rounding flips
 * by more), plus 0.5 for the rounding to an integer. */
#define PIXEL_TOL_8BIT 1.5

/* Relative tolerance of the shadowed / lit ratio measured from 8-bit pixels: each value is
 * rounded by up to 0.5/255 in sRGB, which near the shadow's sRGB 0.48 is 0.98 % of its linear
 * value (d lin / lin = 2.4 d s / s for the power curve) and near the lit pixel's 0.87 is 0.55 %:
 * 1.5 % together; 2 % leaves room for the sample landing a pixel away from the analytic point. */
#define SHADOW_RATIO_TOL_REL 0.02

/* Relative tolerance of the ratio of two channels of one pixel (albedo 0.8 against 0.1, both
 * lit the same): the dim channel, near sRGB 0.3, is rounded by up to 0.5/255, 1.6 % of its
 * linear value (2.4 d s / s); the bright one by 0.3 %: 2 %. */
#define ALBEDO_RATIO_TOL_REL 0.02

/* ---- helpers ---- */

static double srgb_encode(double c) {
    return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

static double srgb_decode(double s) {
    return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4);
}

static void normalize3(double a[3]) {
    const double l = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; ++k) a[k] /= l;
}

static void cross3(const double a[3], const double b[3], double o[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* render.h's camera frame and key light, from its text: w back, u right, v up. */
typedef struct frame {
    double u[3], v[3], w[3], eye[3], tan_y, light[3];
    uint32_t W, H;
} frame;

static frame make_frame(const pgt_render_camera *c, uint32_t W, uint32_t H) {
    frame f;
    double up[3];
    for (int k = 0; k < 3; ++k) {
        f.w[k] = (double)c->eye[k] - c->at[k];
        f.eye[k] = c->eye[k];
        up[k] = c->up[k];
    }
    normalize3(f.w);
    cross3(up, f.w, f.u);
    normalize3(f.u);
    cross3(f.w, f.u, f.v);
    f.tan_y = tan(0.5 * c->fov_deg * PI / 180.0);
    f.W = W, f.H = H;
    for (int k = 0; k < 3; ++k)
        f.light[k] = -1.0 * f.u[k] + 1.0 * f.v[k] + 2.0 * f.w[k]; /* (-1, 1, 2) in u, v, w */
    normalize3(f.light);
    return f;
}

/* The pixel whose centre sample looks at world point p. */
static void project(const frame *f, const double p[3], uint32_t *x, uint32_t *y) {
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = p[k] - f->eye[k];
    const double z = -dot3(d, f->w);
    const double sx = dot3(d, f->u) / z, sy = dot3(d, f->v) / z;
    const double px = (sx / (f->tan_y * f->W / f->H) + 1.0) * 0.5 * f->W;
    const double py = (1.0 - sy / f->tan_y) * 0.5 * f->H;
    *x = (uint32_t)floor(px);
    *y = (uint32_t)floor(py);
}

static const uint8_t *pixel(const uint8_t *img, uint32_t W, uint32_t x, uint32_t y) {
    return img + 3u * ((size_t)y * W + x);
}

static int is_white(const uint8_t *p) { return p[0] == 255 && p[1] == 255 && p[2] == 255; }

static pgt_result quad_mesh(pgt_mesh *m, double y, double half, pgt_error *err) {
    pgt_result r = pgt_mesh_create(m, 4, 2, 0, 0, err);
    if (r != PGT_OK) return r;
    const double c[4][2] = {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
    for (int i = 0; i < 4; ++i) {
        m->positions[3 * i + 0] = (float)c[i][0];
        m->positions[3 * i + 1] = (float)y;
        m->positions[3 * i + 2] = (float)c[i][1];
    }
    const uint32_t ix[6] = {0, 2, 1, 0, 3, 2}; /* counter-clockwise seen from +y */
    memcpy(m->indices, ix, sizeof ix);
    return PGT_OK;
}

/* The unit icosphere of level 5 and a camera at distance 4 on the normal of its face 0, looking
 * at the centre: the centre pixel of an odd-sized picture looks straight at that face. */
#define SPHERE_LEVEL 5u
#define SPHERE_DIST 4.0
#define SPHERE_FOV 30.0f
#define SPHERE_SIDE 511u

static pgt_render_camera sphere_camera(const pgt_mesh *m) {
    const float *p0 = &m->positions[3u * m->indices[0]], *p1 = &m->positions[3u * m->indices[1]],
                *p2 = &m->positions[3u * m->indices[2]];
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k) e1[k] = (double)p1[k] - p0[k], e2[k] = (double)p2[k] - p0[k];
    cross3(e1, e2, n);
    normalize3(n);
    pgt_render_camera c;
    const int least = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2)
                                              : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
    for (int k = 0; k < 3; ++k) {
        c.eye[k] = (float)(SPHERE_DIST * n[k]);
        c.at[k] = 0.0f;
        c.up[k] = k == least ? 1.0f : 0.0f;
    }
    c.fov_deg = SPHERE_FOV;
    return c;
}

/* Smallest distance from the origin to a face plane of m. */
static double face_plane_min_distance(const pgt_mesh *m) {
    double best = INFINITY;
    for (uint32_t f = 0; f < m->face_count; ++f) {
        const float *p[3];
        for (int c = 0; c < 3; ++c) p[c] = &m->positions[3u * m->indices[3u * f + c]];
        double e1[3], e2[3], n[3], p0[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = (double)p[1][k] - p[0][k];
            e2[k] = (double)p[2][k] - p[0][k];
            p0[k] = p[0][k];
        }
        cross3(e1, e2, n);
        normalize3(n);
        best = fmin(best, fabs(dot3(n, p0)));
    }
    return best;
}

/* Projected radius in pixels of a sphere of radius r at distance d on the optical axis. */
static double disc_radius_px(double r, double d, double fov_deg, uint32_t H) {
    return 0.5 * H * tan(asin(r / d)) / tan(0.5 * fov_deg * PI / 180.0);
}

/* ---- cases ---- */

static void test_sphere_silhouette_area(void) {
    pgt_error err = {0};
    pgt_mesh m = {0};
    REQUIRE(pgt_gen_icosphere(&m, SPHERE_LEVEL, &err) == PGT_OK);
    const pgt_render_camera cam = sphere_camera(&m);
    pgt_render_mesh rm = {&m, {0.8f, 0.8f, 0.8f}, 0};
    pgt_render_options o = {0};
    o.spp = 1;
    o.no_shadows = 1;
    const uint32_t S = SPHERE_SIDE;
    uint8_t *img = malloc((size_t)S * S * 3u);
    REQUIRE(img);
    REQUIRE(pgt_render(img, S, S, &rm, 1, &cam, &o, NULL, &err) == PGT_OK);
    uint64_t covered = 0;
    for (size_t i = 0; i < (size_t)S * S; ++i) covered += !is_white(img + 3u * i);

    double r_out = 0.0;
    for (uint32_t i = 0; i < m.vertex_count; ++i) {
        const float *p = &m.positions[3u * i];
        r_out = fmax(r_out, sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]));
    }
    const double r_in = face_plane_min_distance(&m);
    const double R = disc_radius_px(1.0, SPHERE_DIST, SPHERE_FOV, S);
    const double R_out = disc_radius_px(r_out, SPHERE_DIST, SPHERE_FOV, S);
    const double R_in = disc_radius_px(r_in, SPHERE_DIST, SPHERE_FOV, S);
    const double h = PIXEL_HALF_DIAGONAL;
    const double lo = PI * (R_in - h) * (R_in - h), hi = PI * (R_out + h) * (R_out + h);
    const double exact = PI * R * R;
    printf("  covered %llu px, pi R^2 = %.1f (R = %.2f px), bounds [%.1f, %.1f], r_in %.6f, "
           "error %+.3f %%\n",
           (unsigned long long)covered, exact, R, lo, hi, r_in, 100.0 * (covered / exact - 1.0));
    CHECK_MSG(covered >= lo && covered <= hi, "%llu outside [%.1f, %.1f]",
              (unsigned long long)covered, lo, hi);
    CHECK(fabs((double)covered / exact - 1.0) <= DISC_AREA_TOL_REL);
    /* the constant covers the bound derived from this mesh */
    CHECK(hi / exact - 1.0 <= DISC_AREA_TOL_REL && 1.0 - lo / exact <= DISC_AREA_TOL_REL);
    /* nothing at the picture's border: the disc is centred and inside */
    for (uint32_t i = 0; i < S; ++i) {
        CHECK(is_white(pixel(img, S, i, 0)) && is_white(pixel(img, S, i, S - 1)));
        CHECK(is_white(pixel(img, S, 0, i)) && is_white(pixel(img, S, S - 1, i)));
    }
    free(img);
    pgt_mesh_destroy(&m);
}

static void test_sphere_centre_lambert(void) {
    pgt_error err = {0};
    pgt_mesh m = {0};
    REQUIRE(pgt_gen_icosphere(&m, SPHERE_LEVEL, &err) == PGT_OK);
    const pgt_render_camera cam = sphere_camera(&m);
    const float albedo = 0.8f;
    pgt_render_mesh rm = {&m, {albedo, albedo, albedo}, 0};
    const uint32_t S = SPHERE_SIDE, c = S / 2;
    uint8_t *img = malloc((size_t)S * S * 3u);
    REQUIRE(img);
    /* n . l for the normal facing the camera is the key light's back component, 2 / sqrt(6) */
    const double nl = PGT_RENDER_KEY_BACK / sqrt(PGT_RENDER_KEY_RIGHT * PGT_RENDER_KEY_RIGHT +
                                                 PGT_RENDER_KEY_UP * PGT_RENDER_KEY_UP +
                                                 PGT_RENDER_KEY_BACK * PGT_RENDER_KEY_BACK);
    const double expected = 255.0 * srgb_encode(albedo * (0.25 + 0.75 * nl));
    for (int shadows = 0; shadows <= 1; ++shadows)
        for (uint32_t spp = 1; spp <= 2; ++spp) {
            pgt_render_options o = {0};
            o.spp = spp;
            o.no_shadows = !shadows;
            REQUIRE(pgt_render(img, S, S, &rm, 1, &cam, &o, NULL, &err) == PGT_OK);
            const uint8_t *p = pixel(img, S, c, c);
            for (int k = 0; k < 3; ++k)
                CHECK_MSG(fabs(p[k] - expected) <= PIXEL_TOL_8BIT,
                          "shadows %d spp %u: centre %u, expected %.2f", shadows, spp, p[k],
                          expected);
            /* the key light is above-left: left of the centre brighter than right, above
             * brighter than below (150 px is well inside the 246 px disc) */
            CHECK(pixel(img, S, c - 150, c)[0] > pixel(img, S, c + 150, c)[0]);
            CHECK(pixel(img, S, c, c - 150)[0] > pixel(img, S, c, c + 150)[0]);
        }
    free(img);
    pgt_mesh_destroy(&m);
}

/* Ground y = 0 of half size 4, blocker y = 1 of half size 0.5, seen from (0, 6, 6). */
static void test_shadow_ratio(void) {
    pgt_error err = {0};
    pgt_mesh ground = {0}, blocker = {0};
    REQUIRE(quad_mesh(&ground, 0.0, 4.0, &err) == PGT_OK);
    REQUIRE(quad_mesh(&blocker, 1.0, 0.5, &err) == PGT_OK);
    const float albedo = 0.8f;
    pgt_render_mesh rm[2] = {{&ground, {albedo, albedo, albedo}, 0},
                             {&blocker, {albedo, albedo, albedo}, 0}};
    const pgt_render_camera cam = {{0, 6, 6}, {0, 0, 0}, {0, 1, 0}, 40.0f};
    const uint32_t S = 201;
    const frame f = make_frame(&cam, S, S);
    const double *L = f.light;
    REQUIRE(L[1] > 0.1);
    /* the blocker's centre casts its shadow where the ray toward the light from the ground
     * meets y = 1 at the blocker's centre; the lit point is off the shadow and the blocker */
    const double shadow_pt[3] = {-L[0] / L[1], 0.0, -L[2] / L[1]};
    const double lit_pt[3] = {-2.0, 0.0, 1.0};
    uint32_t sx, sy, lx, ly;
    project(&f, shadow_pt, &sx, &sy);
    project(&f, lit_pt, &lx, &ly);
    REQUIRE(sx < S && sy < S && lx < S && ly < S);
    uint8_t *img = malloc((size_t)S * S * 3u), *img_ns = malloc((size_t)S * S * 3u);
    REQUIRE(img && img_ns);
    pgt_render_options o = {0};
    o.spp = 1;
    REQUIRE(pgt_render(img, S, S, rm, 2, &cam, &o, NULL, &err) == PGT_OK);
    o.no_shadows = 1;
    REQUIRE(pgt_render(img_ns, S, S, rm, 2, &cam, &o, NULL, &err) == PGT_OK);

    const double nl = L[1]; /* ground normal (0, 1, 0) */
    const double lit = albedo * (0.25 + 0.75 * nl), dark = albedo * 0.25;
    const uint8_t *ps = pixel(img, S, sx, sy), *pl = pixel(img, S, lx, ly);
    const double ratio = srgb_decode(ps[0] / 255.0) / srgb_decode(pl[0] / 255.0);
    const double expected = dark / lit;
    printf("  shadow pixel (%u,%u) = %u, lit (%u,%u) = %u; ratio %.4f, analytic %.4f\n", sx, sy,
           ps[0], lx, ly, pl[0], ratio, expected);
    CHECK(fabs(ratio / expected - 1.0) <= SHADOW_RATIO_TOL_REL);
    CHECK(fabs(ps[0] - 255.0 * srgb_encode(dark)) <= PIXEL_TOL_8BIT);
    CHECK(fabs(pl[0] - 255.0 * srgb_encode(lit)) <= PIXEL_TOL_8BIT);
    /* without shadow rays both ground points get the lit value; the lit one is unchanged
     * (no shadow acne) */
    CHECK(pixel(img_ns, S, sx, sy)[0] == pl[0]);
    CHECK(pixel(img_ns, S, lx, ly)[0] == pl[0]);
    /* the shadow is where the light direction says, not mirrored: the mirror point is lit */
    const double mirror_pt[3] = {L[0] / L[1], 0.0, -L[2] / L[1]};
    uint32_t mx, my;
    project(&f, mirror_pt, &mx, &my);
    REQUIRE(mx < S && my < S);
    CHECK(pixel(img, S, mx, my)[0] == pl[0]);
    /* two-sided: the quads wound the other way (normals pointing down) give the same bytes */
    for (pgt_mesh *q = &ground; q; q = q == &ground ? &blocker : NULL)
        for (uint32_t t = 0; t < q->face_count; ++t) {
            const uint32_t tmp = q->indices[3u * t + 1];
            q->indices[3u * t + 1] = q->indices[3u * t + 2];
            q->indices[3u * t + 2] = tmp;
        }
    o.no_shadows = 0;
    REQUIRE(pgt_render(img_ns, S, S, rm, 2, &cam, &o, NULL, &err) == PGT_OK);
    CHECK(memcmp(img, img_ns, (size_t)S * S * 3u) == 0);
    free(img);
    free(img_ns);
    pgt_mesh_destroy(&ground);
    pgt_mesh_destroy(&blocker);
}

static uint8_t *render_alloc(uint32_t W, uint32_t H, const pgt_render_mesh *m, uint32_t n,
                             const pgt_render_camera *cam, const pgt_render_options *o) {
    pgt_error err = {0};
    uint8_t *img = malloc((size_t)W * H * 3u);
    if (img && pgt_render(img, W, H, m, n, cam, o, NULL, &err) != PGT_OK) {
        fprintf(stderr, "  render: %s\n", err.message);
        free(img);
        img = NULL;
    }
    return img;
}

static void test_same_bytes_any_threads(void) {
    pgt_error err = {0};
    pgt_mesh sphere = {0}, ground = {0}, spot = {0};
    REQUIRE(pgt_gen_icosphere(&sphere, 4, &err) == PGT_OK);
    REQUIRE(quad_mesh(&ground, -1.0, 3.0, &err) == PGT_OK);
    char path[1024];
    snprintf(path, sizeof path, "%s/spot.obj", PGT_SHARED_MESH_DIR);
    pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, NULL};
    const int have_spot = pgt_mesh_read(&spot, path, &ro, &err) == PGT_OK;
    /* the shared mesh is part of the test set (test_mesh_io real_meshes fails without it too);
     * without it the case still compares the two generated meshes, and fails */
    CHECK_MSG(have_spot, "%s", err.message);
    pgt_render_mesh rm[3] = {{&sphere, {0.8f, 0.8f, 0.8f}, 0},
                             {&ground, {0.25f, 0.55f, 0.2f}, 0},
                             {&spot, {0.7f, 0.35f, 0.25f}, 0}};
    const uint32_t n = have_spot ? 3 : 2, W = 160, H = 120;
    pgt_render_camera cam;
    pgt_render_auto_camera(rm, n, 30.0, 20.0, 1, (double)W / H, &cam);
    pgt_render_options o = {0};
    o.spp = 2;
    o.threads = 1;
    uint8_t *a = render_alloc(W, H, rm, n, &cam, &o);
    o.threads = 2;
    uint8_t *b = render_alloc(W, H, rm, n, &cam, &o);
    o.threads = 3;
    uint8_t *c = render_alloc(W, H, rm, n, &cam, &o);
    /* shared (padded) vertex buffers instead of Embree's copies */
    REQUIRE(pgt_render_pad_positions(&sphere, &err) == PGT_OK);
    REQUIRE(pgt_render_pad_positions(&ground, &err) == PGT_OK);
    if (have_spot) REQUIRE(pgt_render_pad_positions(&spot, &err) == PGT_OK);
    for (uint32_t i = 0; i < n; ++i) rm[i].positions_padded = 1;
    uint8_t *d = render_alloc(W, H, rm, n, &cam, &o);
    REQUIRE(a && b && c && d);
    const size_t bytes = (size_t)W * H * 3u;
    CHECK(memcmp(a, b, bytes) == 0);
    CHECK(memcmp(a, c, bytes) == 0);
    CHECK(memcmp(a, d, bytes) == 0);
    /* and it drew something of every mesh: each colour's hue dominates somewhere */
    int seen[3] = {0, 0, 0};
    for (size_t i = 0; i < (size_t)W * H; ++i) {
        const uint8_t *p = a + 3u * i;
        if (!is_white(p) && p[0] == p[1] && p[1] == p[2]) seen[0] = 1;
        if (p[1] > p[0] + 20 && p[1] > p[2] + 20) seen[1] = 1;
        if (p[0] > p[1] + 20 && p[0] > p[2] + 20) seen[2] = 1;
    }
    CHECK(seen[0] && seen[1] && (seen[2] || !have_spot));
    free(a), free(b), free(c), free(d);
    pgt_mesh_destroy(&sphere);
    pgt_mesh_destroy(&ground);
    pgt_mesh_destroy(&spot);
}

/* The automatic camera is computed in double and rounded once to float: its target at the
 * centre (coordinates below 4, half an ulp 1.2e-7) and its eye (coordinates below 16, half an
 * ulp 4.8e-7); the double re-derivation here differs from it only by roundings of 1e-15. */
#define CAMERA_AT_TOL 1e-6
#define CAMERA_EYE_TOL 1e-5

static void test_auto_camera(void) {
    pgt_error err = {0};
    pgt_mesh m = {0};
    REQUIRE(pgt_gen_icosphere(&m, 3, &err) == PGT_OK);
    const double shift[3] = {1.0, 2.0, 3.0};
    for (uint32_t i = 0; i < m.vertex_count; ++i)
        for (int k = 0; k < 3; ++k) m.positions[3u * i + k] += (float)shift[k];
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < m.vertex_count; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], m.positions[3u * i + k]);
            hi[k] = fmax(hi[k], m.positions[3u * i + k]);
        }
    double radius = 0.0, centre[3];
    for (int k = 0; k < 3; ++k) {
        centre[k] = 0.5 * (lo[k] + hi[k]);
        radius += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    radius = 0.5 * sqrt(radius);
    pgt_render_mesh rm = {&m, {0.8f, 0.8f, 0.8f}, 0};
    const double az = 30.0 * PI / 180.0, el = 20.0 * PI / 180.0;
    /* the eye direction for each up axis (render.h: azimuth 0 from +z / -y / +y, turning
     * counter-clockwise about the axis) */
    const struct {
        int axis;
        double dir[3];
    } cases[3] = {
        {1, {cos(el) * sin(az), sin(el), cos(el) * cos(az)}},
        {2, {cos(el) * sin(az), -cos(el) * cos(az), sin(el)}},
        {0, {sin(el), cos(el) * cos(az), cos(el) * sin(az)}},
    };
    for (int c = 0; c < 3; ++c) {
        pgt_render_camera cam;
        pgt_render_auto_camera(&rm, 1, 30.0, 20.0, cases[c].axis, 4.0 / 3.0, &cam);
        const double dist =
            PGT_RENDER_AUTO_MARGIN * radius / sin(0.5 * PGT_RENDER_AUTO_FOV * PI / 180.0);
        for (int k = 0; k < 3; ++k) {
            CHECK(fabs(cam.at[k] - centre[k]) < CAMERA_AT_TOL);
            CHECK_MSG(fabs(cam.eye[k] - (centre[k] + dist * cases[c].dir[k])) < CAMERA_EYE_TOL,
                      "up %d: eye[%d] %g, expected %g", cases[c].axis, k, (double)cam.eye[k],
                      centre[k] + dist * cases[c].dir[k]);
            CHECK(cam.up[k] == (k == cases[c].axis ? 1.0f : 0.0f));
        }
        CHECK(cam.fov_deg == PGT_RENDER_AUTO_FOV);
        CHECK(pgt_render_camera_check(&cam, &err) == PGT_OK);
    }
    /* portrait pictures: the horizontal angle is the narrower one and sets the distance */
    pgt_render_camera cam;
    pgt_render_auto_camera(&rm, 1, 0.0, 0.0, 1, 0.5, &cam);
    const double half_h = atan(0.5 * tan(0.5 * PGT_RENDER_AUTO_FOV * PI / 180.0));
    CHECK(fabs(cam.eye[2] - (centre[2] + PGT_RENDER_AUTO_MARGIN * radius / sin(half_h))) <
          CAMERA_EYE_TOL);
    /* the framed sphere is in the middle and does not touch the border */
    const uint32_t W = 120, H = 240;
    pgt_render_options o = {0};
    o.spp = 1;
    uint8_t *img = render_alloc(W, H, &rm, 1, &cam, &o);
    REQUIRE(img);
    CHECK(!is_white(pixel(img, W, W / 2, H / 2)));
    for (uint32_t x = 0; x < W; ++x)
        CHECK(is_white(pixel(img, W, x, 0)) && is_white(pixel(img, W, x, H - 1)));
    for (uint32_t y = 0; y < H; ++y)
        CHECK(is_white(pixel(img, W, 0, y)) && is_white(pixel(img, W, W - 1, y)));
    free(img);
    pgt_mesh_destroy(&m);
}

/* Two spheres in two colours left and right, on a coloured background. */
static void test_colours_and_background(void) {
    pgt_error err = {0};
    pgt_mesh a = {0}, b = {0};
    REQUIRE(pgt_gen_icosphere(&a, 3, &err) == PGT_OK);
    REQUIRE(pgt_gen_icosphere(&b, 3, &err) == PGT_OK);
    for (uint32_t i = 0; i < a.vertex_count; ++i) {
        a.positions[3u * i] -= 1.5f;
        b.positions[3u * i] += 1.5f;
    }
    pgt_render_mesh rm[2] = {{&a, {0.8f, 0.1f, 0.1f}, 0}, {&b, {0.1f, 0.1f, 0.8f}, 0}};
    const pgt_render_camera cam = {{0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 40.0f};
    pgt_render_options o = {0};
    o.spp = 1;
    o.background_set = 1;
    o.background[0] = 0.2f, o.background[1] = 0.6f, o.background[2] = 0.0f;
    const uint32_t W = 200, H = 100;
    const frame f = make_frame(&cam, W, H);
    uint8_t *img = render_alloc(W, H, rm, 2, &cam, &o);
    REQUIRE(img);
    /* background as given (sRGB): 0.2 * 255 = 51, 0.6 * 255 = 153 */
    const uint8_t *bg = pixel(img, W, 0, 0);
    CHECK(bg[0] == 51 && bg[1] == 153 && bg[2] == 0);
    const double ca[3] = {-1.5, 0, 0}, cb[3] = {1.5, 0, 0};
    uint32_t ax, ay, bx, by;
    project(&f, ca, &ax, &ay);
    project(&f, cb, &bx, &by);
    const uint8_t *pa = pixel(img, W, ax, ay), *pb = pixel(img, W, bx, by);
    CHECK(pa[0] > pa[2] + 50 && pa[1] == pa[2]); /* red left */
    CHECK(pb[2] > pb[0] + 50 && pb[0] == pb[1]); /* blue right */
    /* one light for all channels: in linear light each pixel's channels keep the albedo ratio */
    const double ra = srgb_decode(pa[0] / 255.0) / srgb_decode(pa[2] / 255.0);
    const double rb = srgb_decode(pb[2] / 255.0) / srgb_decode(pb[0] / 255.0);
    printf("  left (%u,%u,%u), right (%u,%u,%u): albedo ratios %.3f, %.3f (8)\n", pa[0], pa[1],
           pa[2], pb[0], pb[1], pb[2], ra, rb);
    CHECK(fabs(ra / 8.0 - 1.0) <= ALBEDO_RATIO_TOL_REL);
    CHECK(fabs(rb / 8.0 - 1.0) <= ALBEDO_RATIO_TOL_REL);
    free(img);
    pgt_mesh_destroy(&a);
    pgt_mesh_destroy(&b);
}

/* A quad facing the camera whose left edge crosses pixel column 32 at 0.3 of its width: with
 * N x N samples at (i + 0.5) / N, the column's pixels average the samples right of the edge,
 * #{i : (i + 0.5) / N > 0.3} / N of them, with the white background. */
static void test_subpixel_edge_coverage(void) {
    pgt_error err = {0};
    pgt_mesh m = {0};
    REQUIRE(pgt_mesh_create(&m, 4, 2, 0, 0, &err) == PGT_OK);
    const uint32_t S = 64;
    const double fov = 40.0, dist = 5.0, frac = 0.3;
    const double x_edge = dist * tan(0.5 * fov * PI / 180.0) * frac / (0.5 * S);
    const float quad[4][3] = {
        {(float)x_edge, -10, 0}, {10, -10, 0}, {10, 10, 0}, {(float)x_edge, 10, 0}};
    memcpy(m.positions, quad, sizeof quad);
    const uint32_t ix[6] = {0, 1, 2, 0, 2, 3};
    memcpy(m.indices, ix, sizeof ix);
    const float albedo = 0.8f;
    pgt_render_mesh rm = {&m, {albedo, albedo, albedo}, 0};
    const pgt_render_camera cam = {{0, 0, (float)dist}, {0, 0, 0}, {0, 1, 0}, (float)fov};
    const double nl = 2.0 / sqrt(6.0), surface = albedo * (0.25 + 0.75 * nl);
    uint8_t img[64 * 64 * 3];
    for (uint32_t n = 1; n <= 4; ++n) {
        pgt_render_options o = {0};
        o.spp = n;
        REQUIRE(pgt_render(img, S, S, &rm, 1, &cam, &o, NULL, &err) == PGT_OK);
        uint32_t right = 0;
        for (uint32_t i = 0; i < n; ++i) right += (i + 0.5) / n > frac;
        const double f = (double)right / n;
        const double expected = 255.0 * srgb_encode(f * surface + (1.0 - f) * 1.0);
        for (uint32_t y = 0; y < S; y += 9) {
            const uint8_t *p = pixel(img, S, S / 2, y);
            CHECK_MSG(fabs(p[0] - expected) <= PIXEL_TOL_8BIT, "spp %u row %u: %u, expected %.2f",
                      n, y, p[0], expected);
            CHECK(is_white(pixel(img, S, S / 2 - 1, y)));
            CHECK(pixel(img, S, S / 2 + 1, y)[0] == pixel(img, S, S - 1, y)[0]);
        }
    }
    pgt_mesh_destroy(&m);
}

static void test_invalid_arguments(void) {
    pgt_error err = {0};
    pgt_mesh m = {0};
    REQUIRE(quad_mesh(&m, 0.0, 1.0, &err) == PGT_OK);
    pgt_render_mesh rm = {&m, {0.5f, 0.5f, 0.5f}, 0};
    const pgt_render_camera good = {{0, 5, 5}, {0, 0, 0}, {0, 1, 0}, 40.0f};
    uint8_t img[8 * 8 * 3];
    const struct {
        const char *name;
        pgt_render_camera cam;
        const char *word;
    } cams[] = {
        {"eye at look-at", {{1, 2, 3}, {1, 2, 3}, {0, 1, 0}, 40.0f}, "look-at"},
        {"up parallel", {{0, 5, 0}, {0, 0, 0}, {0, 2, 0}, 40.0f}, "parallel"},
        {"up zero", {{0, 5, 5}, {0, 0, 0}, {0, 0, 0}, 40.0f}, "up vector is zero"},
        {"fov 0", {{0, 5, 5}, {0, 0, 0}, {0, 1, 0}, 0.0f}, "field of view"},
        {"fov 180", {{0, 5, 5}, {0, 0, 0}, {0, 1, 0}, 180.0f}, "field of view"},
        {"fov nan", {{0, 5, 5}, {0, 0, 0}, {0, 1, 0}, NAN}, "field of view"},
        {"eye inf", {{INFINITY, 5, 5}, {0, 0, 0}, {0, 1, 0}, 40.0f}, "finite"},
    };
    for (size_t i = 0; i < sizeof cams / sizeof cams[0]; ++i) {
        pgt_error_clear(&err);
        CHECK_MSG(pgt_render(img, 8, 8, &rm, 1, &cams[i].cam, NULL, NULL, &err) ==
                          PGT_ERROR_INVALID_ARGUMENT &&
                      strstr(err.message, cams[i].word) && !strncmp(err.message, "camera: ", 8),
                  "%s: %s", cams[i].name, err.message);
        pgt_error_clear(&err);
        CHECK(pgt_render_camera_check(&cams[i].cam, &err) == PGT_ERROR_INVALID_ARGUMENT);
    }
    pgt_error_clear(&err);
    CHECK(pgt_render(img, 8, 8, &rm, 1, &good, NULL, NULL, &err) == PGT_OK);
    CHECK(pgt_render(img, 0, 8, &rm, 1, &good, NULL, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_render(img, 8, 8, &rm, 0, &good, NULL, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    pgt_render_options o = {0};
    o.spp = PGT_RENDER_MAX_SPP + 1;
    CHECK(pgt_render(img, 8, 8, &rm, 1, &good, &o, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    o.spp = 1;
    o.background_set = 1;
    o.background[1] = 1.5f;
    CHECK(pgt_render(img, 8, 8, &rm, 1, &good, &o, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    pgt_render_mesh bad = rm;
    bad.rgb[2] = NAN;
    CHECK(pgt_render(img, 8, 8, &bad, 1, &good, NULL, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    bad.rgb[2] = -0.1f;
    CHECK(pgt_render(img, 8, 8, &bad, 1, &good, NULL, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    m.indices[4] = 4; /* one past the last vertex */
    pgt_error_clear(&err);
    CHECK(pgt_render(img, 8, 8, &rm, 1, &good, NULL, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT &&
          strstr(err.message, "face 1 uses vertex 4 of 4"));
    pgt_mesh_destroy(&m);
}

static void test_stats(void) {
    pgt_error err = {0};
    pgt_mesh m = {0};
    REQUIRE(pgt_gen_icosphere(&m, 2, &err) == PGT_OK);
    pgt_render_mesh rm = {&m, {0.5f, 0.5f, 0.5f}, 0};
    const pgt_render_camera cam = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40.0f};
    pgt_render_options o = {0};
    o.spp = 3;
    o.no_shadows = 1;
    pgt_render_stats st;
    uint8_t img[10 * 6 * 3];
    REQUIRE(pgt_render(img, 10, 6, &rm, 1, &cam, &o, &st, &err) == PGT_OK);
    CHECK(st.triangles == 320 && st.rays == 10u * 6u * 9u);
    CHECK(st.bvh_ms >= 0.0 && st.trace_ms >= 0.0);
    pgt_mesh_destroy(&m);
}

static const pgt_test_case cases[] = {
    {"sphere_silhouette_area", test_sphere_silhouette_area},
    {"sphere_centre_lambert", test_sphere_centre_lambert},
    {"shadow_ratio", test_shadow_ratio},
    {"same_bytes_any_threads", test_same_bytes_any_threads},
    {"auto_camera", test_auto_camera},
    {"colours_and_background", test_colours_and_background},
    {"subpixel_edge_coverage", test_subpixel_edge_coverage},
    {"invalid_arguments", test_invalid_arguments},
    {"stats", test_stats},
};

PGT_TEST_MAIN(cases)
