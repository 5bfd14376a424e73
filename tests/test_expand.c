/* Tests of the per-seed rule expander (ref_cpu/src/expand.c; paper 000 sections 5, 6 and 8).
 *
 * Part 1: a synthetic flat atlas built here: one chart of inner texels [FLAT_LO, FLAT_HI)^2 in a
 * FLAT_SIDE^2 image, surrounded by a ring of dead-end texels, where texel-space (x, y) has
 * P = (x h, y h, 0) and N = (0, 0, 1), so every point is known analytically (the bilinear
 * position of an affine P is exact). Grammars are compiled from strings; the expected points
 * and terminals are derived by hand in the comments.
 *
 * Part 2: grammars/ivy.grammar on the cube-sphere atlas from the builder. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gen.h"
#include "pgt/atlas.h"
#include "pgt/atlas_build.h"
#include "pgt/expand.h"
#include "pgt/grammar.h"
#include "pgt/image.h"
#include "pgt/march.h"
#include "test_ivy_scene.h"
#include "test_util.h"

#define NONE PGT_NONE

#define FLAT_SIDE 64
#define FLAT_LO 2
#define FLAT_HI 62
#define FLAT_H 0.01f /* texel size in 3D */

/* Texel-space positions here are sums of a few steps of a few texels at coordinates below 64:
 * float32 rounding stays below 1e-5 texel for axis steps, 1e-4 covers the cos/sin of turned
 * directions accumulated over 30 steps. */
#define UV_TOL 1e-4f
/* 3D positions are texel positions times FLAT_H (< 0.64): UV_TOL * FLAT_H plus the rounding of
 * the bilinear weights (a few ulps of 0.64, ~1e-7). */
#define P_TOL 2e-6f

/* ---- the flat atlas --------------------------------------------------------------------- */

typedef struct flat_atlas {
    pgt_image img;
    pgt_atlas_channels ch;
    pgt_march_atlas view;
    const float *normal[3];
} flat_atlas;

static int flat_build(flat_atlas *f) {
    static const char *const names[] = PGT_ATLAS_CHANNEL_NAMES;
    memset(f, 0, sizeof *f);
    if (pgt_image_create(&f->img, FLAT_SIDE, FLAT_SIDE, PGT_ATLAS_CHANNEL_COUNT, names, NULL) !=
        PGT_OK)
        return 0;
    if (pgt_atlas_channels_find(&f->img, "flat", &f->ch, NULL) != PGT_OK) return 0;
    float *px = pgt_image_plane(&f->img, f->ch.px), *py = pgt_image_plane(&f->img, f->ch.py),
          *nz = pgt_image_plane(&f->img, f->ch.nz), *chart = pgt_image_plane(&f->img, f->ch.chart),
          *kind = pgt_image_plane(&f->img, f->ch.kind), *pu = pgt_image_plane(&f->img, f->ch.ptr_u),
          *pv = pgt_image_plane(&f->img, f->ch.ptr_v);
    for (int y = 0; y < FLAT_SIDE; ++y)
        for (int x = 0; x < FLAT_SIDE; ++x) {
            const size_t i = (size_t)y * FLAT_SIDE + (size_t)x;
            const int inner = x >= FLAT_LO && x < FLAT_HI && y >= FLAT_LO && y < FLAT_HI;
            const int ring = x >= FLAT_LO - 1 && x <= FLAT_HI && y >= FLAT_LO - 1 && y <= FLAT_HI;
            pu[i] = pv[i] = -1.0f, chart[i] = -1.0f;
            if (!ring) continue;
            px[i] = ((float)x + 0.5f) * FLAT_H, py[i] = ((float)y + 0.5f) * FLAT_H, nz[i] = 1.0f;
            chart[i] = 0.0f;
            kind[i] = inner ? PGT_TEXEL_INNER : PGT_TEXEL_DEAD_END;
        }
    pgt_error err = {0};
    if (pgt_march_atlas_create(&f->view, &f->img, "flat", &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return 0;
    }
    f->normal[0] = pgt_image_plane(&f->img, f->ch.nx);
    f->normal[1] = pgt_image_plane(&f->img, f->ch.ny);
    f->normal[2] = nz;
    return 1;
}

static void flat_destroy(flat_atlas *f) {
    pgt_march_atlas_destroy(&f->view);
    pgt_image_destroy(&f->img);
}

static int compile(pgt_grammar *g, const char *text, const char *name) {
    pgt_error err = {0};
    if (pgt_grammar_compile(g, text, strlen(text), name, &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return 0;
    }
    return 1;
}

static pgt_expand_input flat_input(const flat_atlas *f, const pgt_grammar *g,
                                   const pgt_expand_seed *seeds, uint32_t n) {
    pgt_expand_input in;
    memset(&in, 0, sizeof in);
    in.grammar = g, in.atlas = &f->view, in.seeds = seeds, in.seed_count = n;
    for (int k = 0; k < 3; ++k) in.normal[k] = f->normal[k];
    return in;
}

static int expand(pgt_expand_output *out, const pgt_expand_input *in, const pgt_expand_options *o) {
    pgt_error err = {0};
    const pgt_result r = pgt_expand(out, in, o, &err);
    if (r != PGT_OK) fprintf(stderr, "  pgt_expand: %s\n", err.message);
    return r == PGT_OK;
}

/* Point i is at texel-space (u, v) with P = (u h, v h, 0), N = (0, 0, 1), the given parent. */
static int point_is(const pgt_expand_output *o, uint32_t i, float u, float v, uint32_t parent) {
    return fabsf(o->u[i] - u) <= UV_TOL && fabsf(o->v[i] - v) <= UV_TOL &&
           fabsf(o->x[i] - u * FLAT_H) <= P_TOL && fabsf(o->y[i] - v * FLAT_H) <= P_TOL &&
           o->z[i] == 0.0f && o->nx[i] == 0.0f && o->ny[i] == 0.0f && o->nz[i] == 1.0f &&
           o->chart[i] == 0 && o->parent[i] == parent;
}

static int terminal_is(const pgt_expand_output *o, uint32_t i, uint32_t segment, uint32_t kind,
                       float a, float b, uint32_t smoothness) {
    return o->terminal_segment[i] == segment && o->terminal_kind[i] == kind &&
           o->terminal_a[i] == a && o->terminal_b[i] == b &&
           o->terminal_smoothness[i] == smoothness;
}

/* ---- cases ------------------------------------------------------------------------------ */

/* M(i) steps while i < 5 (the condition reads the counter parameter): five steps of L = 2
 * along (0.6, 0.8) from (10.5, 20.5), a chain of parents, then a sixth try rejected and the
 * march stopped. The condition reads neither context nor rand, so the 8 candidates are skipped
 * (expand.h's shortcut): 1 rejection, not 9. */
static void test_straight_march(void) {
    flat_atlas f;
    REQUIRE(flat_build(&f));
    pgt_grammar g;
    REQUIRE(compile(&g, "param L = 2\nA --> M(0)\nM(i) --> Marching(L, 0, i < 5) {M(i + 1), NIL}",
                    "straight"));
    const pgt_expand_seed seed = {10.5f, 20.5f, 3.0f, 4.0f};
    const pgt_expand_input in = flat_input(&f, &g, &seed, 1);
    pgt_expand_output o;
    REQUIRE(expand(&o, &in, NULL));
    REQUIRE(o.point_count == 6);
    for (uint32_t i = 0; i < 6; ++i)
        CHECK_MSG(point_is(&o, i, 10.5f + 2.0f * 0.6f * (float)i, 20.5f + 2.0f * 0.8f * (float)i,
                           i == 0 ? NONE : i - 1),
                  "point %u at (%g, %g)", i, (double)o.u[i], (double)o.v[i]);
    for (uint32_t i = 0; i < 6; ++i) CHECK(o.branch[i] == 0 && o.seed[i] == 0);
    CHECK(o.branch_count == 1 && o.terminal_count == 0 && o.seed_count == 1);
    CHECK(o.stopped_marches == 1 && o.rejected_tries == 1);
    CHECK(o.candidates_used == 0 && o.draws == 0);
    CHECK(o.seed_first_point[0] == 0 && o.seed_point_count[0] == 6);
    pgt_expand_destroy(&o);
    pgt_grammar_destroy(&g);
    flat_destroy(&f);
}

/* TopSucc before ExtrudedSucc, by hand (seed at (10.5, 20.5) heading +x):
 *   A: Marching -> p1 (12.5, 20.5); Top = B runs first:
 *      B item 1: Marching -> p2 (14.5, 20.5), parent p1; its Top Leaves(2, 0.5) is outside any
 *        Extruded: on the segment ending at p2; its Extruded Bark(3, C1): on p2;
 *      B item 2: Marching turned by +pi/2 from p1 heading +x -> p3 (12.5, 22.5), parent p1
 *        (p1's second child: branch 1); Extruded Leaves(4, 0.25) on p3;
 *   A's Extruded Bark(1, C0) on p1; A item 2 Leaves(9, 9) at the root: dropped. */
static void test_top_before_extruded(void) {
    flat_atlas f;
    REQUIRE(flat_build(&f));
    pgt_grammar g;
    REQUIRE(compile(&g,
                    "A --> Marching(2, 0, 1) {B, Bark(1, C0)} Leaves(9, 9)\n"
                    "B --> Marching(2, 0, 1) {Leaves(2, 0.5), Bark(3, C1)}\n"
                    "      Marching(2, PI / 2, 1) {NIL, Leaves(4, 0.25)}",
                    "order"));
    const pgt_expand_seed seed = {10.5f, 20.5f, 1.0f, 0.0f};
    const pgt_expand_input in = flat_input(&f, &g, &seed, 1);
    pgt_expand_output o;
    REQUIRE(expand(&o, &in, NULL));
    REQUIRE(o.point_count == 4 && o.terminal_count == 4);
    CHECK(point_is(&o, 0, 10.5f, 20.5f, NONE) && point_is(&o, 1, 12.5f, 20.5f, 0));
    CHECK(point_is(&o, 2, 14.5f, 20.5f, 1) && point_is(&o, 3, 12.5f, 22.5f, 1));
    CHECK(o.branch[0] == 0 && o.branch[1] == 0 && o.branch[2] == 0 && o.branch[3] == 1);
    const uint32_t L = PGT_GRAMMAR_TERMINAL_LEAVES, B = PGT_GRAMMAR_TERMINAL_BARK;
    CHECK(terminal_is(&o, 0, 2, L, 2.0f, 0.5f, NONE));
    CHECK(terminal_is(&o, 1, 2, B, 3.0f, 2.0f, PGT_GRAMMAR_C1));
    CHECK(terminal_is(&o, 2, 3, L, 4.0f, 0.25f, NONE));
    CHECK(terminal_is(&o, 3, 1, B, 1.0f, 1.0f, PGT_GRAMMAR_C0));
    CHECK(o.dropped_terminals == 1 && o.stopped_marches == 0);
    pgt_expand_destroy(&o);
    pgt_grammar_destroy(&g);
    flat_destroy(&f);
}

/* Branch(3) at p1 (12.5, 20.5) heading +x: turned by -pi/2 (towards -y), 0, +pi/2 give p2
 * (12.5, 18.5), p3 (14.5, 20.5), p4 (12.5, 22.5), all children of p1; p2 continues p1's branch,
 * p3 and p4 start new ones. Two seeds: the second's ids follow the first's. */
static void test_branch(void) {
    flat_atlas f;
    REQUIRE(flat_build(&f));
    pgt_grammar g;
    REQUIRE(compile(&g,
                    "A --> Marching(2, 0, 1) {Branch(3) {S(-PI / 2), S(0), S(PI / 2)}, NIL}\n"
                    "S(a) --> Marching(2, a, 1) {NIL, NIL}",
                    "branch"));
    const pgt_expand_seed seeds[2] = {{10.5f, 20.5f, 1.0f, 0.0f}, {30.5f, 40.5f, 1.0f, 0.0f}};
    const pgt_expand_input in = flat_input(&f, &g, seeds, 2);
    pgt_expand_output o;
    REQUIRE(expand(&o, &in, NULL));
    REQUIRE(o.point_count == 10 && o.branch_count == 6);
    for (uint32_t s = 0; s < 2; ++s) {
        const uint32_t b = 5 * s, id = 3 * s;
        const float x = seeds[s].x, y = seeds[s].y;
        CHECK(o.seed_first_point[s] == b && o.seed_point_count[s] == 5);
        CHECK(point_is(&o, b, x, y, NONE) && point_is(&o, b + 1, x + 2, y, b));
        CHECK(point_is(&o, b + 2, x + 2, y - 2, b + 1) && point_is(&o, b + 3, x + 4, y, b + 1));
        CHECK(point_is(&o, b + 4, x + 2, y + 2, b + 1));
        CHECK(o.branch[b] == id && o.branch[b + 1] == id && o.branch[b + 2] == id);
        CHECK(o.branch[b + 3] == id + 1 && o.branch[b + 4] == id + 2);
        for (uint32_t i = 0; i < 5; ++i) CHECK(o.seed[b + i] == s);
    }
    pgt_expand_destroy(&o);
    pgt_grammar_destroy(&g);
    flat_destroy(&f);
}

/* The mask forbids the half-plane of columns >= MASK_COLUMN. From (10.5, 30.5) heading +x with
 * steps of 2 and K = 2 candidates (+pi/2, then -pi/2): 12.5 ... 18.5 (i = 0..3); at i = 4 the
 * straight try lands in column 20 (rejected), +pi/2 turns towards +y: (18.5, 32.5); i = 5..7
 * go on along +y to (18.5, 38.5); i = 8 fails the counter in every direction: stopped. */
#define MASK_COLUMN 20
static void test_mask_condition(void) {
    flat_atlas f;
    REQUIRE(flat_build(&f));
    float *mask = calloc((size_t)FLAT_SIDE * FLAT_SIDE, sizeof(float));
    REQUIRE(mask);
    for (int y = 0; y < FLAT_SIDE; ++y)
        for (int x = MASK_COLUMN; x < FLAT_SIDE; ++x) mask[y * FLAT_SIDE + x] = 1.0f;
    pgt_grammar g;
    REQUIRE(compile(&g,
                    "A --> M(0)\n"
                    "M(i) --> Marching(2, 0, i < 8 && context.mask(texCoord) < 0.5) {M(i + 1), "
                    "NIL}",
                    "mask"));
    const pgt_expand_seed seed = {10.5f, 30.5f, 1.0f, 0.0f};
    pgt_expand_input in = flat_input(&f, &g, &seed, 1);
    in.mask = mask;
    pgt_expand_options opt = {0};
    opt.candidates = 2;
    pgt_expand_output o;
    REQUIRE(expand(&o, &in, &opt));
    REQUIRE(o.point_count == 9);
    static const float expect[9][2] = {{10.5f, 30.5f}, {12.5f, 30.5f}, {14.5f, 30.5f},
                                       {16.5f, 30.5f}, {18.5f, 30.5f}, {18.5f, 32.5f},
                                       {18.5f, 34.5f}, {18.5f, 36.5f}, {18.5f, 38.5f}};
    for (uint32_t i = 0; i < 9; ++i)
        CHECK_MSG(point_is(&o, i, expect[i][0], expect[i][1], i ? i - 1 : NONE),
                  "point %u at (%g, %g)", i, (double)o.u[i], (double)o.v[i]);
    CHECK(o.candidates_used == 1 && o.stopped_marches == 1 && o.rejected_tries == 1 + 3);
    pgt_expand_destroy(&o);
    /* without candidates the march stops at the mask */
    opt.no_candidates = 1;
    REQUIRE(expand(&o, &in, &opt));
    CHECK(o.point_count == 5 && o.stopped_marches == 1 && o.candidates_used == 0);
    pgt_expand_destroy(&o);
    /* default candidates, longer runs from several seeds: no point in a forbidden texel */
    pgt_grammar g2;
    REQUIRE(compile(&g2,
                    "A --> M(0)\nM(i) --> Marching(3, rand(-0.3, 0.3), i < 40 && "
                    "context.mask(texCoord) < 0.5) {M(i + 1), NIL}",
                    "mask2"));
    pgt_expand_seed seeds[8];
    for (int s = 0; s < 8; ++s)
        seeds[s] = (pgt_expand_seed){4.5f + 2.0f * (float)s, 5.5f + 6.0f * (float)s, 1.0f, 0.2f};
    in = flat_input(&f, &g2, seeds, 8);
    in.mask = mask;
    REQUIRE(expand(&o, &in, NULL));
    uint32_t bad = 0;
    for (uint32_t i = 0; i < o.point_count; ++i) bad += o.u[i] >= (float)MASK_COLUMN;
    CHECK_MSG(bad == 0, "%u of %u points in forbidden texels", bad, o.point_count);
    CHECK(o.candidates_used > 0 && o.point_count > 8 * 10);
    printf("  mask: %u points, %llu candidates used, %llu stopped\n", o.point_count,
           (unsigned long long)o.candidates_used, (unsigned long long)o.stopped_marches);
    pgt_expand_destroy(&o);
    pgt_grammar_destroy(&g2);
    pgt_grammar_destroy(&g);
    free(mask);
    flat_destroy(&f);
}

/* The output's arrays: 12 per point, 5 per terminal, 4 per seed, all 4-byte elements. */
#define OUTPUT_ARRAYS 21
static void output_arrays(const pgt_expand_output *o, const void *p[OUTPUT_ARRAYS]) {
    const void *const a[OUTPUT_ARRAYS] = {o->x,
                                          o->y,
                                          o->z,
                                          o->nx,
                                          o->ny,
                                          o->nz,
                                          o->u,
                                          o->v,
                                          o->chart,
                                          o->parent,
                                          o->seed,
                                          o->branch,
                                          o->terminal_segment,
                                          o->terminal_kind,
                                          o->terminal_a,
                                          o->terminal_b,
                                          o->terminal_smoothness,
                                          o->seed_first_point,
                                          o->seed_point_count,
                                          o->seed_first_terminal,
                                          o->seed_terminal_count};
    memcpy(p, a, sizeof a);
}

/* Every array of two outputs holds the same bytes. */
static int same_output(const pgt_expand_output *a, const pgt_expand_output *b) {
    if (a->point_count != b->point_count || a->terminal_count != b->terminal_count ||
        a->branch_count != b->branch_count || a->seed_count != b->seed_count ||
        a->draws != b->draws || a->stopped_marches != b->stopped_marches ||
        a->rejected_tries != b->rejected_tries || a->candidates_used != b->candidates_used)
        return 0;
    const size_t P = a->point_count, T = a->terminal_count, S = a->seed_count;
    const void *pa[OUTPUT_ARRAYS], *pb[OUTPUT_ARRAYS];
    output_arrays(a, pa);
    output_arrays(b, pb);
    for (size_t i = 0; i < OUTPUT_ARRAYS; ++i) {
        const size_t n = (i < 12 ? P : i < 17 ? T : S) * 4;
        if (n && memcmp(pa[i], pb[i], n) != 0) return 0;
    }
    return 1;
}

#define RAND_SEEDS 24
static const char rand_grammar[] =
    "A --> M(0)\n"
    "M(i) --> Marching(rand(1, 3), rand(-0.5, 0.5), i < 30) {Branch(2) {M(i + 1), S(0)}, "
    "Bark(rand(0.1, 0.2), C1)}\n"
    "S(n) --> Marching(2, rand(-1, 1), n < 3) {S(n + 1), Leaves(rand(0, 1), 0.5)}";

/* rand: the same seed gives the same bytes; other seed ids differ; 1 and 2 threads give the
 * same bytes; a seed expanded alone equals its slice of the batch. */
static void test_rand_determinism(void) {
    flat_atlas f;
    REQUIRE(flat_build(&f));
    pgt_grammar g;
    REQUIRE(compile(&g, rand_grammar, "rand"));
    pgt_expand_seed seeds[RAND_SEEDS];
    for (int s = 0; s < RAND_SEEDS; ++s)
        seeds[s] = (pgt_expand_seed){5.5f + (float)(s % 6) * 9.0f, 5.5f + (float)(s / 6) * 12.0f,
                                     1.0f, (float)(s % 3) - 1.0f};
    pgt_expand_input in = flat_input(&f, &g, seeds, RAND_SEEDS);
    in.seed_base = 1000;
    pgt_expand_options one = {0}, two = {0};
    one.threads = 1, two.threads = 2;
    pgt_expand_output a, b, c, d;
    REQUIRE(expand(&a, &in, &one));
    REQUIRE(expand(&b, &in, &one));
    CHECK(same_output(&a, &b));
    REQUIRE(expand(&c, &in, &two));
    CHECK(same_output(&a, &c));
    CHECK(a.draws > 0 && a.terminal_count > 0 && a.point_count > RAND_SEEDS * 10);
    printf("  rand: %u points, %u terminals, %u branches, %llu draws\n", a.point_count,
           a.terminal_count, a.branch_count, (unsigned long long)a.draws);
    in.seed_base = 2000;
    REQUIRE(expand(&d, &in, &two));
    CHECK(!same_output(&a, &d));
    pgt_expand_destroy(&d);
    /* seed 7 alone, with its id */
    in.seeds = &seeds[7], in.seed_count = 1, in.seed_base = 1007;
    REQUIRE(expand(&d, &in, &one));
    const uint32_t p0 = a.seed_first_point[7], n = a.seed_point_count[7];
    REQUIRE(d.point_count == n);
    CHECK(memcmp(d.x, a.x + p0, n * sizeof(float)) == 0);
    CHECK(memcmp(d.v, a.v + p0, n * sizeof(float)) == 0);
    uint32_t bad = 0;
    for (uint32_t i = 0; i < n; ++i)
        bad += d.parent[i] != (a.parent[p0 + i] == NONE ? NONE : a.parent[p0 + i] - p0);
    CHECK(bad == 0);
    pgt_expand_destroy(&a);
    pgt_expand_destroy(&b);
    pgt_expand_destroy(&c);
    pgt_expand_destroy(&d);
    pgt_grammar_destroy(&g);
    flat_destroy(&f);
}

/* A runaway grammar is PGT_ERROR_LIMIT naming FILE:LINE:COL, the seed and the bound; the same
 * error for 1 and 2 threads (the lowest failing seed's). */
static void expect_limit(const flat_atlas *f, const char *text, const pgt_expand_options *o,
                         const char *where, const char *bound) {
    pgt_grammar g;
    REQUIRE(compile(&g, text, "runaway"));
    pgt_expand_seed seeds[3] = {
        {10.5f, 10.5f, 1.0f, 0.0f}, {20.5f, 30.5f, 0.0f, 1.0f}, {40.5f, 40.5f, -1.0f, 0.0f}};
    const pgt_expand_input in = flat_input(f, &g, seeds, 3);
    pgt_expand_options oo = *o;
    char first[PGT_ERROR_MESSAGE_SIZE] = "";
    for (uint32_t t = 1; t <= 2; ++t) {
        oo.threads = t;
        pgt_expand_output out;
        pgt_error err = {0};
        CHECK(pgt_expand(&out, &in, &oo, &err) == PGT_ERROR_LIMIT);
        CHECK_MSG(strstr(err.message, where) == err.message && strstr(err.message, bound) &&
                      strstr(err.message, "seed 0 "),
                  "%s", err.message);
        CHECK(out.point_count == 0 && out.x == NULL);
        if (t == 1) {
            printf("  %s\n", err.message);
            strcpy(first, err.message);
        } else {
            CHECK(strcmp(first, err.message) == 0);
        }
        pgt_expand_destroy(&out);
    }
    pgt_grammar_destroy(&g);
}

static void test_bounds(void) {
    flat_atlas f;
    REQUIRE(flat_build(&f));
    pgt_expand_options o = {0};
    o.max_points = 500;
    /* walks around the chart's rim for ever (candidates turn it at the dead ends) */
    expect_limit(&f, "A --> Marching(1, 0, 1){A, NIL}", &o, "runaway:1:7: ", "max_points");
    o.max_points = 0;
    o.max_depth = 200;
    expect_limit(&f, "A --> Branch(2){A, A}", &o, "runaway:1:", "max_depth");
    expect_limit(&f, "A --> B A\nB --> NIL", &o, "runaway:1:", "max_depth");
    o.max_depth = 0; /* the default bound */
    expect_limit(&f, "A --> Branch(2){A, A}", &o, "runaway:1:", "max_depth");
    /* a branching recursion making no points: 2^20 items within every other bound */
    o.max_items = 1000;
    expect_limit(&f, "A --> B(0)\nB(n) --> case n < 20 : Branch(2) {B(n + 1), B(n + 1)} else : NIL",
                 &o, "runaway:2:", "max_items");
    /* ... past the 65,536 items after which a seed above a failed one stops early: the error
     * stays the lowest failing seed's */
    o.max_items = 300000;
    expect_limit(&f, "A --> B(0)\nB(n) --> case n < 20 : Branch(2) {B(n + 1), B(n + 1)} else : NIL",
                 &o, "runaway:2:", "max_items");
    o.max_items = 0;
    /* ... and all seeds together: each seed may run max_total_items / seeds. A tree of depth 8
     * runs 1 + 3 (2^8 - 1) = 766 items (the axiom's call, then a Branch and its two calls at
     * every inner node; NIL runs none): three seeds pass with a total of 3 x 766 and fail with
     * one item less (a share of 765) */
    {
        static const char *const tree =
            "A --> B(0)\nB(n) --> case n < 8 : Branch(2) {B(n + 1), B(n + 1)} else : NIL";
        pgt_grammar g;
        REQUIRE(compile(&g, tree, "runaway"));
        pgt_expand_seed seeds[3] = {
            {10.5f, 10.5f, 1.0f, 0.0f}, {20.5f, 30.5f, 0.0f, 1.0f}, {40.5f, 40.5f, -1.0f, 0.0f}};
        const pgt_expand_input in = flat_input(&f, &g, seeds, 3);
        pgt_expand_output out;
        pgt_error err = {0};
        o.max_total_items = 3u * 766u;
        CHECK_MSG(pgt_expand(&out, &in, &o, &err) == PGT_OK && out.seed_count == 3, "%s",
                  err.message);
        pgt_expand_destroy(&out);
        /* a per-seed bound below the share still applies, under its own name */
        o.max_items = 765;
        CHECK(pgt_expand(&out, &in, &o, &err) == PGT_ERROR_LIMIT &&
              strstr(err.message, "(option max_items)"));
        pgt_expand_destroy(&out);
        o.max_items = 0;
        pgt_grammar_destroy(&g);
        o.max_total_items = 3u * 766u - 1u;
        expect_limit(&f, tree, &o, "runaway:2:",
                     "more than 765 grammar items run (option max_total_items: 2297 over all 3 "
                     "seeds, 765 a seed)");
        o.max_total_items = 0;
    }
    /* ... and one making 2^12 Bark records on one segment */
    o.max_terminals = 100;
    expect_limit(&f,
                 "A --> Marching(1, 0, 1) {NIL, T(0)}\n"
                 "T(n) --> case n < 12 : Bark(0.01, C1) Branch(2) {T(n + 1), T(n + 1)} else : NIL",
                 &o, "runaway:2:24: ", "max_terminals");
    o.max_terminals = 0;
    /* a length out of range, and split, are errors with their position */
    pgt_grammar g;
    REQUIRE(compile(&g, "A --> Marching(-1, 0, 1){NIL, NIL}", "neg"));
    const pgt_expand_seed seed = {10.5f, 10.5f, 1.0f, 0.0f};
    pgt_expand_input in = flat_input(&f, &g, &seed, 1);
    pgt_expand_output out;
    pgt_error err = {0};
    CHECK(pgt_expand(&out, &in, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "neg:1:7: ") == err.message, "%s", err.message);
    pgt_expand_destroy(&out);
    pgt_grammar_destroy(&g);
    /* an expression that is not finite at run time (i = 0), in a Marching argument and in
     * its condition: the evaluator's FILE:LINE:COL first, then the seed */
    static const char *const inf[2] = {"A --> M(0)\nM(i) --> Marching(2, 1 / i, 1){NIL, NIL}",
                                       "A --> M(0)\nM(i) --> Marching(2, 0, 1 / i){NIL, NIL}"};
    for (int k = 0; k < 2; ++k) {
        REQUIRE(compile(&g, inf[k], "inf"));
        in = flat_input(&f, &g, &seed, 1);
        pgt_error_clear(&err);
        CHECK(pgt_expand(&out, &in, NULL, &err) == PGT_ERROR_NOT_FINITE);
        CHECK_MSG(strstr(err.message, "inf:2:") == err.message &&
                      strstr(err.message, "(seed 0, id 0)"),
                  "%s", err.message);
        printf("  %s\n", err.message);
        pgt_expand_destroy(&out);
        pgt_grammar_destroy(&g);
    }
    /* a seed outside the chart */
    REQUIRE(compile(&g, "A --> NIL", "nil"));
    const pgt_expand_seed off = {0.5f, 0.5f, 1.0f, 0.0f};
    in = flat_input(&f, &g, &off, 1);
    pgt_error_clear(&err);
    CHECK(pgt_expand(&out, &in, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "seed 0") != NULL, "%s", err.message);
    pgt_expand_destroy(&out);
    pgt_grammar_destroy(&g);
    flat_destroy(&f);
}

/* ---- part 2: ivy.grammar on the cube-sphere atlas --------------------------------------- */

#define IVY_SEEDS IVY_SCENE_SEEDS
/* A point's normal interpolates the atlas's normals of the n = 32 cube-sphere, where one face
 * spans at most (pi / 2) / 32 = 0.049 rad: it is within about that angle of the point's own
 * direction (cosine 0.9988). The bound, cosine 0.99 (8.1 degrees), tells a normal from a wrong
 * texel's or an unnormalised one. Measured: 0.99996 at worst. */
#define NORMAL_RADIAL_MIN_COS 0.99
/* A point is on a flat triangle of the n = 32 cube-sphere, within (pi/2/32)^2/8 = 3e-4 of the
 * unit sphere (the chord's sagitta), and interpolated between texel centres on the mesh: one
 * texel size (3.7e-3 at 1024^2) bounds both (test_march's great-circle bound). */
static void test_ivy_cube_sphere(void) {
    static ivy_scene scene;
    REQUIRE(ivy_scene_make(&scene));
    REQUIRE(scene.in.seed_count == IVY_SEEDS);
    const pgt_march_atlas v = scene.atlas;
    const pgt_expand_input in = scene.in;
    pgt_error err = {0};
    pgt_expand_options o = {0};
    o.threads = 2;
    pgt_expand_output out, one;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    REQUIRE(pgt_expand(&out, &in, &o, &err) == PGT_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    o.threads = 1;
    REQUIRE(pgt_expand(&one, &in, &o, &err) == PGT_OK);
    CHECK(same_output(&out, &one));
    pgt_expand_destroy(&one);
    const double tol = scene.stats.texel_size;
    uint32_t off_inner = 0, off_sphere = 0, bad_parent = 0, bad_normal = 0;
    for (uint32_t i = 0; i < out.point_count; ++i) {
        const uint32_t t = (uint32_t)out.v[i] * v.width + (uint32_t)out.u[i];
        off_inner += v.codes[t] != PGT_MARCH_CODE(PGT_TEXEL_INNER, out.chart[i]);
        const double r = sqrt((double)out.x[i] * out.x[i] + (double)out.y[i] * out.y[i] +
                              (double)out.z[i] * out.z[i]);
        off_sphere += fabs(r - 1.0) > tol;
        /* the normal of a sphere point is about the point itself */
        const double c = (out.x[i] * out.nx[i] + out.y[i] * out.ny[i] + out.z[i] * out.nz[i]) / r;
        bad_normal += c < NORMAL_RADIAL_MIN_COS;
        const uint32_t p = out.parent[i];
        bad_parent += p == NONE ? i != out.seed_first_point[out.seed[i]]
                                : p >= i || out.seed[p] != out.seed[i];
    }
    CHECK(off_inner == 0 && off_sphere == 0 && bad_parent == 0 && bad_normal == 0);
    uint32_t bark = 0, leaves = 0;
    for (uint32_t i = 0; i < out.terminal_count; ++i)
        bark += out.terminal_kind[i] == PGT_GRAMMAR_TERMINAL_BARK,
            leaves += out.terminal_kind[i] == PGT_GRAMMAR_TERMINAL_LEAVES;
    CHECK(bark > 0 && bark == leaves && out.point_count > IVY_SEEDS * 100);
    printf("  ivy: %u seeds, %u points, %u branches, %u bark, %u leaves, %llu stopped, %llu "
           "rejected, %llu candidates used, %llu draws, %.2f ms on 2 threads\n",
           IVY_SEEDS, out.point_count, out.branch_count, bark, leaves,
           (unsigned long long)out.stopped_marches, (unsigned long long)out.rejected_tries,
           (unsigned long long)out.candidates_used, (unsigned long long)out.draws,
           (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6);
    for (uint32_t s = 0; s < IVY_SEEDS; ++s)
        printf("  seed %u: %u points, %u terminals\n", s, out.seed_point_count[s],
               out.seed_terminal_count[s]);
    pgt_expand_destroy(&out);
    ivy_scene_free(&scene);
}

static const pgt_test_case cases[] = {
    {"straight_march", test_straight_march},
    {"top_before_extruded", test_top_before_extruded},
    {"branch", test_branch},
    {"mask_condition", test_mask_condition},
    {"rand_determinism", test_rand_determinism},
    {"bounds", test_bounds},
    {"ivy_cube_sphere", test_ivy_cube_sphere},
};

PGT_TEST_MAIN(cases)
