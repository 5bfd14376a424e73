/* pgt tests: per-pixel procedural facades against Embree on their explicit twin (issue 6,
 * "Ray versus explicit geometry"; harness/facade_embree.h), rays that miss every facade volume
 * developing nothing, and facade scene files (harness/facade_scene.h) written and read back.
 *
 * The city: pgt_gen_city(100 buildings, seed 1) with grammars/facade.grammar, 512 x 512 pixels,
 * 2 threads. Cameras: the default aerial view, a street-level camera looking down a street
 * between two columns of lots (the facades beside it seen at grazing angles), one 0.5 m in
 * front of a facade looking along it (nearly parallel: the worst case for both tracers), and
 * one looking almost straight down. Each must agree on >= 99.99 % of the pixels with every
 * disagreement a tie (two faces in one place) or within PGT_FACADE_CHECK_EDGE_EPS_REL of a
 * rectangle's edge. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facade_embree.h"
#include "facade_scene.h"
#include "gen.h"
#include "pgt/facade.h"
#include "test_util.h"

#define GRAMMAR PGT_SOURCE_DIR "/grammars/facade.grammar"
#define SIDE 512u
#define THREADS 2u

/* The shared city, its explicit twin and Embree scene (built once: the BVH takes ~1 s). */
static struct {
    int ready, failed;
    pgt_facade_file file;
    pgt_facade *facades;
    uint32_t facade_count;
    pgt_facade_mesh mesh;
    pgt_facade_embree eb;
} city;

static void city_teardown(void);

static int city_setup(void) {
    if (city.ready) return !city.failed;
    city.ready = 1;
    atexit(city_teardown); /* whichever cases run, the city is freed once (LeakSanitizer) */
    pgt_error err = {0};
    if (pgt_facade_file_city(&city.file, GRAMMAR, 100, 1, &err) != PGT_OK ||
        pgt_facade_prepare(&city.file.scene, &city.facades, &city.facade_count, &err) != PGT_OK ||
        pgt_facade_explicit(&city.file.scene, city.facades, city.facade_count, &city.mesh, &err) !=
            PGT_OK ||
        pgt_facade_embree_create(&city.eb, &city.mesh, THREADS, NULL, &err) != PGT_OK) {
        fprintf(stderr, "  city setup: %s\n", err.message);
        city.failed = 1;
    }
    return !city.failed;
}

static void city_teardown(void) {
    pgt_facade_embree_destroy(&city.eb);
    pgt_facade_mesh_destroy(&city.mesh);
    free(city.facades);
    pgt_facade_file_free(&city.file);
    memset(&city, 0, sizeof city);
}

/* Renders the city from cam and checks it against Embree in every mode: the two timed ones and
 * the incoherent rays pgt facade --embree-check compares. */
static void check_camera(const char *name, const float eye[3], const float at[3], float fov) {
    REQUIRE(city_setup());
    const float up[3] = {0.0f, 1.0f, 0.0f};
    pgt_error err = {0};
    pgt_facade_camera cam;
    REQUIRE(pgt_facade_camera_init(&cam, eye, at, up, fov, SIDE, SIDE, &err) == PGT_OK);
    pgt_facade_frame frame;
    REQUIRE(pgt_facade_frame_create(&frame, SIDE, SIDE, &err) == PGT_OK);
    pgt_facade_embree_hits hits;
    REQUIRE(pgt_facade_embree_hits_create(&hits, SIDE, SIDE, &err) == PGT_OK);
    pgt_facade_shading sh = {.light = {0.0f, 500.0f, 0.0f}, .ambient = 0.25f};
    pgt_facade_render_stats st;
    CHECK(pgt_facade_render(&city.file.scene, city.facades, city.facade_count, &cam, &sh, THREADS,
                            &frame, &st, &err) == PGT_OK);
    CHECK(st.rays.errors == 0);
    static const char *const mode_names[3] = {"packets", "streams", "check rays"};
    for (uint32_t m = 0; m <= PGT_FACADE_EMBREE_CHECK_RAYS; ++m) {
        double ms = 0.0;
        /* every pixel a miss first: a mode that wrote nothing sees nothing (checked below),
         * instead of the previous mode's hits */
        for (uint32_t i = 0; i < SIDE * SIDE; ++i) hits.tri[i] = PGT_NONE, hits.t[i] = INFINITY;
        CHECK(pgt_facade_embree_trace(&city.eb, &cam, (pgt_facade_embree_mode)m, &hits, &ms,
                                      &err) == PGT_OK);
        pgt_facade_check chk;
        const int pass = pgt_facade_embree_compare(&city.mesh, &cam, &frame, &hits, &chk);
        const uint64_t hit = chk.pixels - chk.both_miss;
        printf("  %s (%s): %llu pixels hit, agreement %.4f %%, %llu disagreements (%llu ties, "
               "%llu near an edge), max depth error %.3g (relative %.3g)\n",
               name, mode_names[m], (unsigned long long)hit, chk.agreement_pct,
               (unsigned long long)chk.disagree, (unsigned long long)chk.ties,
               (unsigned long long)chk.near_edge, chk.max_abs_dt, chk.max_rel_dt);
        /* a camera that sees nothing would pass trivially */
        CHECK_MSG(hit > SIDE * SIDE / 20u, "%s sees only %llu hits", name, (unsigned long long)hit);
        CHECK_MSG(pass,
                  "%s: agreement %.4f %%, %llu of %llu disagreements neither ties nor near "
                  "an edge",
                  name, chk.agreement_pct,
                  (unsigned long long)(chk.disagree - chk.ties - chk.near_edge),
                  (unsigned long long)chk.disagree);
        for (uint32_t k = 0; k < chk.reported; ++k)
            fprintf(stderr,
                    "    pixel %u,%u: ours facade %d t %.7g edge %.3g; Embree facade %d t "
                    "%.7g edge %.3g\n",
                    chk.far[k].x, chk.far[k].y, (int)chk.far[k].facade[0], (double)chk.far[k].t[0],
                    (double)chk.far[k].edge[0], (int)chk.far[k].facade[1], (double)chk.far[k].t[1],
                    (double)chk.far[k].edge[1]);
    }
    pgt_facade_embree_hits_destroy(&hits);
    pgt_facade_frame_destroy(&frame);
}

static void test_aerial(void) {
    REQUIRE(city_setup());
    float eye[3], at[3], up[3], fov;
    pgt_facade_default_view(&city.file.scene, SIDE, SIDE, eye, at, up, &fov);
    check_camera("aerial (default camera)", eye, at, fov);
}

/* Lots are PGT_GEN_CITY_LOT apart and buildings at most 26 m wide within them: x in
 * (26, 30) of a lot is street. Eye at pedestrian height looking down it. */
static void test_street(void) {
    const float x = (float)(2.0 * PGT_GEN_CITY_LOT) - 2.0f;
    const float eye[3] = {x, 1.7f, -15.0f}, at[3] = {x + 0.3f, 4.0f, 300.0f};
    check_camera("street level along a street", eye, at, 60.0f);
}

/* 0.5 m in front of the first facade of building 0, looking along it from beyond its start:
 * the facade's rectangles are seen at ~89 degrees from their normal. */
static void test_grazing(void) {
    REQUIRE(city_setup());
    const pgt_facade *f = &city.facades[0];
    float eye[3], at[3];
    for (int k = 0; k < 3; ++k) {
        eye[k] = f->origin[k] - 10.0f * f->t[k] + 0.5f * f->n[k];
        at[k] = f->origin[k] + f->width * f->t[k] + 0.3f * f->n[k];
    }
    eye[1] += 0.5f * f->height, at[1] += 0.5f * f->height;
    check_camera("nearly parallel to a facade", eye, at, 50.0f);
}

static void test_top_down(void) {
    REQUIRE(city_setup());
    float lo[3], hi[3];
    REQUIRE(pgt_facade_file_bounds(&city.file.scene, lo, hi));
    const float c[3] = {0.5f * (lo[0] + hi[0]), 0.0f, 0.5f * (lo[2] + hi[2])};
    const float eye[3] = {c[0] + 20.0f, 400.0f, c[2] + 40.0f};
    check_camera("almost straight down", eye, c, 50.0f);
}

/* A ray that misses a facade's volume develops nothing: directly, and in a frame whose upper
 * pixels look at the sky above every building. */
static void test_miss_develops_nothing(void) {
    REQUIRE(city_setup());
    const pgt_facade_scene *s = &city.file.scene;
    float lo[3], hi[3];
    REQUIRE(pgt_facade_file_bounds(s, lo, hi));
    /* straight up from above the roofs, and horizontally above them */
    const float org[2][3] = {{0.5f * (lo[0] + hi[0]), hi[1] + 10.0f, 0.5f * (lo[2] + hi[2])},
                             {lo[0] - 50.0f, hi[1] + 5.0f, 0.5f * (lo[2] + hi[2])}};
    const float dir[2][3] = {{0.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};
    for (int r = 0; r < 2; ++r) {
        pgt_facade_ray_stats stats;
        memset(&stats, 0, sizeof stats);
        for (uint32_t fi = 0; fi < city.facade_count; ++fi) {
            pgt_facade_hit hit;
            memset(&hit, 0, sizeof hit);
            hit.t = INFINITY, hit.facade = PGT_NONE;
            CHECK(pgt_facade_intersect(s, &city.facades[fi], fi, org[r], dir[r], &hit, &stats) ==
                  0);
        }
        CHECK(stats.rays == city.facade_count);
        CHECK(stats.volume_hits == 0);
        CHECK_MSG(stats.nodes == 0, "ray %d developed %llu nodes", r,
                  (unsigned long long)stats.nodes);
        CHECK(stats.terminals == 0 && stats.quads == 0);
    }
    /* a street-level camera looking up: pixels whose rays pass above the roofs */
    const float eye[3] = {lo[0] - 40.0f, 2.0f, 0.5f * (lo[2] + hi[2])};
    const float at[3] = {eye[0] + 100.0f, eye[1] + 120.0f, eye[2]}; /* 50 degrees up */
    const float up[3] = {0.0f, 1.0f, 0.0f};
    pgt_error err = {0};
    pgt_facade_camera cam;
    REQUIRE(pgt_facade_camera_init(&cam, eye, at, up, 60.0f, 128, 128, &err) == PGT_OK);
    pgt_facade_frame frame;
    REQUIRE(pgt_facade_frame_create(&frame, 128, 128, &err) == PGT_OK);
    pgt_facade_shading sh = {.light = {0.0f, 500.0f, 0.0f}, .ambient = 0.25f};
    pgt_facade_render_stats st;
    CHECK(pgt_facade_render(s, city.facades, city.facade_count, &cam, &sh, THREADS, &frame, &st,
                            &err) == PGT_OK);
    uint32_t sky = 0, developed = 0;
    for (uint32_t y = 0; y < 128; ++y)
        for (uint32_t x = 0; x < 128; ++x) {
            float o[3], d[3];
            pgt_facade_camera_ray(&cam, x, y, o, d);
            if (!(d[1] > 0.0f)) continue;
            /* above every roof from x = lo[0] on: the ray is above hi[1] before it gets there */
            const float y_at = o[1] + d[1] * ((lo[0] - o[0]) / d[0]);
            if (!(d[0] > 0.0f) || !(y_at > hi[1] + 1.0f)) continue;
            const size_t i = (size_t)y * 128u + x;
            sky++;
            CHECK(isinf(frame.depth[i]));
            developed += frame.developed[i];
        }
    CHECK_MSG(sky > 1000u, "only %u sky pixels", sky);
    CHECK_MSG(developed == 0, "%u nodes developed by sky pixels", developed);
    pgt_facade_frame_destroy(&frame);
}

/* The writer's file reads back as the same scene: buildings, corners and params bit for bit. */
static void test_scene_round_trip(void) {
    REQUIRE(city_setup());
    const char *path = PGT_BINARY_DIR "/tests/facade_round_trip.scene";
    pgt_error err = {0};
    const pgt_facade_scene *s = &city.file.scene;
    REQUIRE(pgt_facade_file_write(path, NULL, s, (const char *const *)city.file.names,
                                  (const char *const *)city.file.paths, "round trip",
                                  &err) == PGT_OK);
    pgt_facade_file back;
    CHECK_MSG(pgt_facade_file_read(&back, path, &err) == PGT_OK, "%s", err.message);
    const pgt_facade_scene *b = &back.scene;
    REQUIRE(b->building_count == s->building_count && b->corner_count == s->corner_count &&
            b->param_count == s->param_count && b->grammar_count == 1);
    CHECK(!memcmp(b->buildings, s->buildings, s->building_count * sizeof *s->buildings));
    CHECK(!memcmp(b->corners, s->corners, 2u * s->corner_count * sizeof(float)));
    CHECK(!memcmp(b->params, s->params, s->param_count * sizeof(float)));
    pgt_facade_file_free(&back);
    remove(path);
}

/* A side x side view of a small mesh through Embree: its scene, the camera (eye towards at,
 * 30 degrees), a frame for ours to fill and Embree's hits of every pixel (1 thread, packets);
 * open closes what it made when it fails. */
typedef struct traced_view {
    pgt_facade_embree eb;
    pgt_facade_camera cam;
    pgt_facade_frame fr;
    pgt_facade_embree_hits hits;
} traced_view;

static void traced_view_close(traced_view *v) {
    pgt_facade_embree_hits_destroy(&v->hits);
    pgt_facade_frame_destroy(&v->fr);
    pgt_facade_embree_destroy(&v->eb);
}

static int traced_view_open(traced_view *v, const pgt_facade_mesh *mesh, const float eye[3],
                            const float at[3], uint32_t side) {
    memset(v, 0, sizeof *v);
    const float up[3] = {0, 1, 0};
    pgt_error err = {0};
    if (pgt_facade_embree_create(&v->eb, mesh, 1, NULL, &err) != PGT_OK ||
        pgt_facade_camera_init(&v->cam, eye, at, up, 30.0f, side, side, &err) != PGT_OK ||
        pgt_facade_frame_create(&v->fr, side, side, &err) != PGT_OK ||
        pgt_facade_embree_hits_create(&v->hits, side, side, &err) != PGT_OK ||
        pgt_facade_embree_trace(&v->eb, &v->cam, PGT_FACADE_EMBREE_PACKETS, &v->hits, NULL, &err) !=
            PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        traced_view_close(v);
        return 0;
    }
    return 1;
}

/* Ties (facade_embree.h): two coincident unit squares (facades 0 and 1), a third one 1 m
 * behind them (facade 2) and a fourth 0.2 mm behind them (facade 3), seen head on. Embree's
 * hits are the frame; relabelled to the other coincident square every hit is a tie and the
 * check passes; relabelled to the square 1 m behind, to a facade the mesh does not have, moved
 * 1 % in depth, or relabelled to the square 0.2 mm behind at its own depth (within the depth
 * tolerance, but a face behind Embree's), a pixel is neither a tie nor near an edge and the
 * check fails. */
static void test_ties(void) {
    float pos[48];
    for (uint32_t q = 0; q < 4; ++q) {
        const float z = q == 2 ? -1.0f : (q == 3 ? -2e-4f : 0.0f);
        const float c[4][2] = {{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}};
        for (uint32_t k = 0; k < 4; ++k)
            pos[12 * q + 3 * k] = c[k][0], pos[12 * q + 3 * k + 1] = c[k][1],
                             pos[12 * q + 3 * k + 2] = z;
    }
    uint32_t idx[24], fac[8], node[8], kind[8], surf[8];
    for (uint32_t q = 0; q < 4; ++q) {
        const uint32_t b = 4 * q, t[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
        memcpy(idx + 6 * q, t, sizeof t);
        for (uint32_t k = 0; k < 2; ++k)
            fac[2 * q + k] = q, node[2 * q + k] = 7u, kind[2 * q + k] = 1u, surf[2 * q + k] = 0u;
    }
    const pgt_facade_mesh mesh = {16, 8, pos, idx, fac, node, kind, surf};
    const uint32_t side = 16;
    const float eye[3] = {0.1f, 0.2f, 3.0f}, at[3] = {0.1f, 0.2f, 0.0f};
    traced_view v;
    REQUIRE(traced_view_open(&v, &mesh, eye, at, side));
    /* the squares (half-width 1 at distance 3) fill the 30-degree view (half-width 0.8) */
    uint32_t front = 0;
    for (uint32_t i = 0; i < side * side; ++i) {
        REQUIRE(v.hits.tri[i] != PGT_NONE);
        front += fac[v.hits.tri[i]] < 2u;
        v.fr.facade[i] = 1u - fac[v.hits.tri[i]], v.fr.node[i] = 7u, v.fr.terminal[i] = 1.0f;
        v.fr.surface[i] = 0u, v.fr.depth[i] = v.hits.t[i];
    }
    CHECK(front == side * side);
    pgt_facade_check chk;
    CHECK(pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk));
    CHECK(chk.ties == side * side && chk.disagree == side * side && chk.agree == 0);
    const uint32_t mid = side / 2 * side + side / 2;
    const float t = v.fr.depth[mid];
    /* the eye is 3 m before the squares: along the ray, 0.2 mm behind is t (3 + 2e-4) / 3 */
    const struct {
        uint32_t facade;
        float depth;
    } wrong[4] = {
        {2u, t}, {5u, t}, {1u - fac[v.hits.tri[mid]], t * 1.01f}, {3u, t * (3.0f + 2e-4f) / 3.0f}};
    for (uint32_t k = 0; k < 4; ++k) {
        v.fr.facade[mid] = wrong[k].facade, v.fr.depth[mid] = wrong[k].depth;
        CHECK_MSG(!pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk), "case %u", k);
        CHECK(chk.ties == side * side - 1u && chk.near_edge == 0 && chk.reported == 1 &&
              chk.far[0].x == side / 2 && chk.far[0].y == side / 2);
    }
    traced_view_close(&v);
}

/* How far from the square's diagonal (x = y on z = 0, coordinates about 1) the ray of the pixel
 * chosen on it may pass: its float32 ray meets the plane within rounding (a few 1e-8) of the
 * diagonal, while the next pixel along a row is 0.02 away. */
#define DIAGONAL_EPS 1e-6

/* Cracks (facade_embree.h): a unit square of two triangles (diagonal from (-1, -1) to (1, 1))
 * seen head on, ours hitting it at every pixel. Embree's hits are made to miss at one pixel:
 * on the diagonal (pixel (k, side - 1 - k): its ray meets the plane at x = y) that is a ray
 * through the crack between the triangles, near an edge and the check passes; off the
 * diagonal and the square's sides, or on the diagonal with Embree hitting something before the
 * square (no crack explains that), it is neither and the check fails. */
static void test_cracks(void) {
    const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    uint32_t fac[2] = {0, 0}, node[2] = {7, 7}, kind[2] = {1, 1}, surf[2] = {0, 0};
    const pgt_facade_mesh mesh = {4, 2, (float *)pos, (uint32_t *)idx, fac, node, kind, surf};
    /* 16384 pixels: one disagreement keeps the agreement above PGT_FACADE_CHECK_MIN_AGREEMENT */
    const uint32_t side = 128;
    const float eye[3] = {0.0f, 0.0f, 3.0f}, at[3] = {0.0f, 0.0f, 0.0f};
    traced_view v;
    REQUIRE(traced_view_open(&v, &mesh, eye, at, side));
    for (uint32_t i = 0; i < side * side; ++i) {
        REQUIRE(v.hits.tri[i] != PGT_NONE); /* the square fills the view */
        v.fr.facade[i] = 0u, v.fr.node[i] = 7u, v.fr.terminal[i] = 1.0f, v.fr.surface[i] = 0u;
        v.fr.depth[i] = v.hits.t[i];
    }
    pgt_facade_check chk;
    CHECK(pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk));
    CHECK(chk.agree == side * side && chk.disagree == 0);
    const uint32_t on = 40u * side + (side - 1u - 40u), off = 40u * side + 70u;
    float o[3], d[3];
    pgt_facade_camera_ray(&v.cam, side - 1u - 40u, 40u, o, d);
    const double tz = -(double)o[2] / d[2];
    CHECK(fabs(o[0] + tz * d[0] - (o[1] + tz * d[1])) < DIAGONAL_EPS); /* on the diagonal */
    const uint32_t keep_tri = v.hits.tri[on];
    const float keep_t = v.hits.t[on];
    v.hits.tri[on] = PGT_NONE, v.hits.t[on] = INFINITY;
    CHECK(pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk));
    CHECK(chk.disagree == 1 && chk.near_edge == 1 && chk.crack == 1 && chk.reported == 0);
    /* Embree hitting the square's plane before ours' point: a hit nearer than the square */
    v.hits.tri[on] = keep_tri, v.hits.t[on] = keep_t * 0.5f;
    CHECK(!pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk));
    CHECK(chk.disagree == 1 && chk.near_edge == 0 && chk.crack == 0 && chk.reported == 1);
    v.hits.tri[on] = keep_tri, v.hits.t[on] = keep_t;
    v.hits.tri[off] = PGT_NONE, v.hits.t[off] = INFINITY;
    CHECK(!pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk));
    CHECK(chk.disagree == 1 && chk.near_edge == 0 && chk.crack == 0 && chk.reported == 1 &&
          chk.far[0].x == 70u && chk.far[0].y == 40u && isinf(chk.far[0].inner) == 0);
    traced_view_close(&v);
}

/* Depth at grazing angles (facade_embree.h, PGT_FACADE_CHECK_PLANE_EPS): a 20 m square in the
 * plane z = 300, seen from 5 cm before it along -x (the middle pixel's ray meets it at about
 * 89.4 degrees from its normal, 5 m away). Ours' depth moved by what the plane moving k float
 * epsilons of the coordinates (~305) along its normal gives along that ray: k = 1 agrees (the
 * relative tolerance alone refuses it: 7e-4 t), k = 40 is neither a tie nor near an edge. */
static void test_grazing_depth(void) {
    const float pos[12] = {290, 0, 300, 310, 0, 300, 310, 20, 300, 290, 20, 300};
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    uint32_t fac[2] = {0, 0}, node[2] = {7, 7}, kind[2] = {1, 1}, surf[2] = {0, 0};
    const pgt_facade_mesh mesh = {4, 2, (float *)pos, (uint32_t *)idx, fac, node, kind, surf};
    const uint32_t side = 128; /* one disagreement stays within the agreement bar */
    const float eye[3] = {305.0f, 10.0f, 300.05f}, at[3] = {300.0f, 10.0f, 300.0f};
    traced_view v;
    REQUIRE(traced_view_open(&v, &mesh, eye, at, side));
    for (uint32_t i = 0; i < side * side; ++i) { /* ours = Embree's hits: all agree */
        v.fr.facade[i] = v.hits.tri[i] == PGT_NONE ? PGT_NONE : 0u;
        v.fr.node[i] = 7u, v.fr.terminal[i] = 1.0f, v.fr.surface[i] = 0u;
        v.fr.depth[i] = v.hits.t[i];
    }
    const uint32_t x = side / 2, y = side / 2, mid = y * side + x;
    REQUIRE(v.hits.tri[mid] != PGT_NONE);
    float o[3], d[3];
    pgt_facade_camera_ray(&v.cam, x, y, o, d);
    const double dn = sqrt((double)d[0] * d[0] + (double)d[1] * d[1] + (double)d[2] * d[2]);
    const double cos_a = fabs((double)d[2]) / dn, t = (300.0 - o[2]) / d[2];
    CHECK(cos_a > 0.005 && cos_a < 0.02 && t > 4.0 && t < 6.0);
    double mag = 0.0;
    for (int k = 0; k < 3; ++k) mag = fmax(mag, fmax(fabs(o[k]), fabs(o[k] + t * d[k])));
    const double step = FLT_EPSILON * mag / cos_a; /* one epsilon along the normal */
    CHECK(step > 5.0 * PGT_FACADE_CHECK_DEPTH_TOL_REL * t);
    pgt_facade_check chk;
    v.fr.depth[mid] = (float)(t + step);
    CHECK(pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk));
    CHECK(chk.disagree == 0 && chk.max_rel_dt > PGT_FACADE_CHECK_DEPTH_TOL_REL);
    v.fr.depth[mid] = (float)(t + 40.0 * step);
    CHECK(!pgt_facade_embree_compare(&mesh, &v.cam, &v.fr, &v.hits, &chk));
    CHECK(chk.disagree == 1 && chk.near_edge == 0 && chk.ties == 0 && chk.reported == 1);
    traced_view_close(&v);
}

static const pgt_test_case cases[] = {
    {"ties", test_ties},
    {"cracks", test_cracks},
    {"grazing_depth", test_grazing_depth},
    {"aerial", test_aerial},
    {"street", test_street},
    {"grazing", test_grazing},
    {"top_down", test_top_down},
    {"miss_develops_nothing", test_miss_develops_nothing},
    {"scene_round_trip", test_scene_round_trip},
};

PGT_TEST_MAIN(cases)
