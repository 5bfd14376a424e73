/* Tests of the terminal evaluator (terminals.h, paper 000 sections 6 and 8, issue 5 item 4):
 * vertex and polygon counts, bark watertight per branch, rings shared at joints, ring
 * geometry, leaf counts and placement, thread determinism, bad input, and ivy.grammar on the
 * cube-sphere end to end (expand -> Bezier -> terminals).
 *
 * Part 1 builds its inputs by hand: polylines with branches on the plane z = 0, normals +z;
 * branch ids by pgt_expand's rule (a new id at every root and at every child beyond a point's
 * first). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gen.h"
#include "pgt/atlas.h"
#include "pgt/atlas_build.h"
#include "pgt/bezier.h"
#include "pgt/expand.h"
#include "pgt/grammar.h"
#include "pgt/image.h"
#include "pgt/march.h"
#include "pgt/rng.h"
#include "pgt/terminals.h"
#include "test_ivy_scene.h"
#include "test_util.h"

#define NONE PGT_NONE
#define BARK PGT_GRAMMAR_TERMINAL_BARK
#define LEAVES PGT_GRAMMAR_TERMINAL_LEAVES
#define SIDES PGT_TERMINALS_DEFAULT_SIDES
#define RINGS PGT_TERMINALS_DEFAULT_RINGS

/* Hand scenes have coordinates below 4 (float ulp <= 4.8e-7) and radii 0.03: a ring vertex is
 * centre + r (cos N + sin B) from a dozen float operations, so its distance from the centre
 * is r within a few ulps of the coordinates; 1e-5 leaves a 20-ulp margin. */
#define RADIUS_TOL 1e-5
/* Ring planes vs the curve tangent, |(v - centre) . T| / r: interior rings use B'(s) itself
 * (float rounding only, ~1e-5 / r); end rings use the joint's summed tangent, collinear with
 * each curve's end tangent within the Bezier construction's G1 bound (1e-4 rad). */
#define RING_PLANE_TOL 1e-3
/* Leaves: positions from a few float operations on coordinates below 200 (ulp 1.5e-5). */
#define LEAF_TOL 1e-4
/* The fractional leaf count is a binomial: the extras must lie within this many standard
 * deviations of their mean (the seed is fixed, so this is a check of the rule, not a flake). */
#define LEAF_SIGMAS 5.0

/* ---- hand-built scenes ------------------------------------------------------------------ */

typedef struct scene {
    uint32_t n, nt, branches;
    float *p, *nrm, *b1, *b2;
    uint32_t *parent, *branch, *nchild;
    uint32_t *seg, *kind, *smooth;
    float *a, *b;
} scene;

static scene *scene_new(uint32_t cap) {
    scene *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->p = calloc(3u * cap, sizeof(float)), s->nrm = calloc(3u * cap, sizeof(float));
    s->b1 = calloc(3u * cap, sizeof(float)), s->b2 = calloc(3u * cap, sizeof(float));
    s->parent = calloc(cap, 4), s->branch = calloc(cap, 4), s->nchild = calloc(cap, 4);
    s->seg = calloc(2u * cap, 4), s->kind = calloc(2u * cap, 4), s->smooth = calloc(2u * cap, 4);
    s->a = calloc(2u * cap, 4), s->b = calloc(2u * cap, 4);
    return s;
}

static void scene_free(scene *s) {
    if (!s) return;
    free(s->p), free(s->nrm), free(s->b1), free(s->b2), free(s->parent), free(s->branch);
    free(s->nchild), free(s->seg), free(s->kind), free(s->smooth), free(s->a), free(s->b);
    free(s);
}

static uint32_t add_point(scene *s, float x, float y, uint32_t parent) {
    const uint32_t i = s->n++;
    s->p[3 * i] = x, s->p[3 * i + 1] = y, s->p[3 * i + 2] = 0.0f;
    s->nrm[3 * i + 2] = 1.0f;
    s->parent[i] = parent;
    s->branch[i] = parent == NONE || s->nchild[parent] > 0 ? s->branches++ : s->branch[parent];
    if (parent != NONE) s->nchild[parent]++;
    return i;
}

static void add_terminal(scene *s, uint32_t seg, uint32_t kind, float a, float b, uint32_t sm) {
    const uint32_t t = s->nt++;
    s->seg[t] = seg, s->kind[t] = kind, s->a[t] = a, s->b[t] = b;
    s->smooth[t] = kind == BARK ? sm : NONE;
}

/* A main chain of 12 segments along a wave, a branch of 5 at point 4, one of 4 at point 8, and
 * a second chain of 3 from the root; Bark(BARK_R, sm) on every segment, Leaves on some. */
#define BARK_R 0.03f
static scene *tree_scene(uint32_t sm, int leaves) {
    scene *s = scene_new(64);
    if (!s) return NULL;
    uint32_t prev = add_point(s, 0.0f, 0.0f, NONE);
    for (int k = 1; k <= 12; ++k)
        prev = add_point(s, 0.2f * (float)k, 0.15f * sinf(0.8f * (float)k), prev);
    prev = 4;
    for (int j = 1; j <= 5; ++j)
        prev = add_point(s, s->p[12] + 0.05f * (float)j, s->p[13] + 0.2f * (float)j, prev);
    prev = 8;
    for (int j = 1; j <= 4; ++j)
        prev = add_point(s, s->p[24] + 0.08f * (float)j, s->p[25] - 0.18f * (float)j, prev);
    prev = 0;
    for (int j = 1; j <= 3; ++j)
        prev = add_point(s, -0.2f * (float)j, 0.1f * (float)(j * j) * 0.1f, prev);
    for (uint32_t i = 0; i < s->n; ++i) {
        if (s->parent[i] == NONE) continue;
        add_terminal(s, i, BARK, BARK_R, 0.0f, sm);
        if (leaves && i % 3 == 0) add_terminal(s, i, LEAVES, 1.7f, 0.05f, 0);
    }
    return s;
}

/* A chain of n segments along a wave. */
static scene *chain_scene(uint32_t n, uint32_t sm) {
    scene *s = scene_new(n + 1);
    if (!s) return NULL;
    uint32_t prev = add_point(s, 0.0f, 0.0f, NONE);
    for (uint32_t k = 1; k <= n; ++k) {
        prev = add_point(s, 0.2f * (float)k, 0.2f * sinf((float)k), prev);
        add_terminal(s, prev, BARK, BARK_R, 0.0f, sm);
    }
    return s;
}

static pgt_terminals_input scene_input(scene *s, uint32_t seed_id) {
    uint8_t *sm = malloc(s->n + 1u);
    for (uint32_t i = 0; i < s->n; ++i) sm[i] = PGT_BEZIER_C1;
    for (uint32_t t = 0; t < s->nt; ++t)
        if (s->kind[t] == BARK && s->seg[t] < s->n) sm[s->seg[t]] = (uint8_t)s->smooth[t];
    pgt_error err = {0};
    if (pgt_bezier_build(s->p, s->nrm, s->parent, sm, s->n, 1, s->b1, s->b2, &err) != PGT_OK)
        fprintf(stderr, "  bezier: %s\n", err.message);
    free(sm);
    pgt_terminals_input in;
    memset(&in, 0, sizeof in);
    in.point_count = s->n, in.positions = s->p, in.normals = s->nrm, in.parent = s->parent;
    in.b1 = s->b1, in.b2 = s->b2, in.terminal_count = s->nt, in.terminal_segment = s->seg;
    in.terminal_kind = s->kind, in.terminal_a = s->a, in.terminal_b = s->b;
    in.terminal_smoothness = s->smooth, in.seed_id = seed_id;
    return in;
}

static int build(pgt_terminals_output *out, const pgt_terminals_input *in, uint32_t threads,
                 int centred) {
    pgt_terminals_options o = {0};
    o.threads = threads, o.centred = centred;
    pgt_error err = {0};
    const pgt_result r = pgt_terminals_build(out, in, &o, &err);
    if (r != PGT_OK) fprintf(stderr, "  terminals: %s\n", err.message);
    return r == PGT_OK;
}

/* ---- mesh checks ------------------------------------------------------------------------ */

typedef struct vkey {
    float p[3];
    uint32_t id;
} vkey;

static int vkey_cmp(const void *x, const void *y) {
    const vkey *a = x, *b = y;
    const int c = memcmp(a->p, b->p, sizeof a->p);
    return c ? c : (a->id > b->id) - (a->id < b->id);
}

/* canon[v] = the lowest vertex id with v's exact position bytes (welds the uv seam). */
static uint32_t *weld(const pgt_terminals_output *o) {
    vkey *k = malloc(((size_t)o->vertex_count + 1u) * sizeof *k);
    uint32_t *canon = malloc(((size_t)o->vertex_count + 1u) * sizeof *canon);
    if (!k || !canon) return free(k), free(canon), NULL;
    for (uint32_t v = 0; v < o->vertex_count; ++v)
        memcpy(k[v].p, &o->positions[3u * (size_t)v], sizeof k[v].p), k[v].id = v;
    qsort(k, o->vertex_count, sizeof *k, vkey_cmp);
    for (uint32_t i = 0, g = 0; i < o->vertex_count; ++i) {
        if (i == 0 || memcmp(k[i].p, k[i - 1u].p, sizeof k[i].p) != 0) g = k[i].id;
        canon[k[i].id] = g;
    }
    free(k);
    return canon;
}

typedef struct ekey {
    uint32_t br, lo, hi, dir;
} ekey;

static int ekey_cmp(const void *x, const void *y) {
    const ekey *a = x, *b = y;
    if (a->br != b->br) return a->br < b->br ? -1 : 1;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return (a->dir > b->dir) - (a->dir < b->dir);
}

/* Per branch of the bark triangles (tri_is_bark): edges by welded vertex, counted. Checks every
 * edge is used at most twice, twice-used edges in opposite directions (consistent winding),
 * exactly 2 sides boundary edges per branch, each boundary vertex on the branch's start or end
 * ring (within 2 r + RADIUS_TOL of the start point or the end point: the tube is lifted by r).
 * Returns the number of branches checked, or 0 after printing a failure. */
static uint32_t check_watertight(const pgt_terminals_output *o, const uint8_t *tri_is_bark,
                                 const uint32_t *branch, const uint32_t *parent,
                                 const float *positions, uint32_t point_count, float radius) {
    uint32_t *canon = weld(o);
    ekey *e = malloc(3u * ((size_t)o->triangle_count + 1u) * sizeof *e);
    uint32_t *first = malloc(((size_t)point_count + 1u) * 4),
             *last = malloc(((size_t)point_count + 1u) * 4);
    if (!canon || !e || !first || !last) return free(canon), free(e), free(first), free(last), 0;
    for (uint32_t i = 0; i < point_count; ++i) first[i] = last[i] = NONE;
    for (uint32_t i = 0; i < point_count; ++i) { /* a branch's first and last segment */
        if (parent[i] == NONE) continue;
        const uint32_t b = branch[i];
        if (first[b] == NONE) first[b] = i;
        last[b] = i;
    }
    size_t ne = 0;
    for (uint32_t t = 0; t < o->triangle_count; ++t) {
        if (!tri_is_bark[t]) continue;
        const uint32_t *v = &o->triangles[3u * (size_t)t];
        for (int k = 0; k < 3; ++k) {
            const uint32_t x = canon[v[k]], y = canon[v[(k + 1) % 3]];
            e[ne++] = (ekey){branch[o->triangle_segment[t]], x < y ? x : y, x < y ? y : x, x < y};
        }
    }
    qsort(e, ne, sizeof *e, ekey_cmp);
    uint32_t branches = 0, bad = 0, cur = NONE, boundary = 0;
    for (size_t i = 0; i <= ne; ++i) {
        if (i == ne || e[i].br != cur) {
            if (cur != NONE) {
                branches++;
                if (boundary != 2u * o->sides) {
                    fprintf(stderr, "  branch %u: %u boundary edges, expected %u\n", cur, boundary,
                            2u * o->sides);
                    bad++;
                }
            }
            if (i == ne) break;
            cur = e[i].br, boundary = 0;
        }
        size_t j = i;
        while (j + 1 < ne && e[j + 1].br == e[i].br && e[j + 1].lo == e[i].lo &&
               e[j + 1].hi == e[i].hi)
            ++j;
        const size_t mult = j - i + 1;
        if (mult > 2 || (mult == 2 && e[i].dir == e[j].dir)) {
            if (bad++ < 5)
                fprintf(stderr, "  branch %u: edge %u-%u used %zu times (directions %u %u)\n",
                        e[i].br, e[i].lo, e[i].hi, mult, e[i].dir, e[j].dir);
        } else if (mult == 1) {
            boundary++;
            const uint32_t s = first[e[i].br], l = last[e[i].br];
            const uint32_t ends[2] = {parent[s], l};
            for (int q = 0; q < 2; ++q) {
                const uint32_t v = q ? e[i].hi : e[i].lo;
                double best = INFINITY;
                for (int w = 0; w < 2; ++w) {
                    double d2 = 0.0;
                    for (int k = 0; k < 3; ++k) {
                        const double d = (double)o->positions[3u * (size_t)v + (size_t)k] -
                                         positions[3u * (size_t)ends[w] + (size_t)k];
                        d2 += d * d;
                    }
                    best = fmin(best, sqrt(d2));
                }
                if (best > 2.0 * radius + RADIUS_TOL && bad++ < 5)
                    fprintf(stderr, "  branch %u: boundary vertex %u at %g from both ends\n",
                            e[i].br, v, best);
            }
        }
        i = j;
    }
    free(canon), free(e), free(first), free(last);
    return bad ? 0 : branches;
}

static uint8_t *bark_mask(const pgt_terminals_output *o, const pgt_terminals_input *in) {
    /* bark triangles: the first 2 sides rings of each bark segment's block */
    uint8_t *m = calloc((size_t)o->triangle_count + 1u, 1);
    uint8_t *has = calloc((size_t)in->point_count + 1u, 1);
    uint32_t *seen = calloc((size_t)in->point_count + 1u, 4);
    for (uint32_t t = 0; t < in->terminal_count; ++t)
        if (in->terminal_kind[t] == BARK) has[in->terminal_segment[t]] = 1;
    for (uint32_t t = 0; t < o->triangle_count; ++t) {
        const uint32_t s = o->triangle_segment[t];
        m[t] = has[s] && seen[s]++ < 2u * o->sides * o->rings;
    }
    free(has), free(seen);
    return m;
}

/* ---- cases ------------------------------------------------------------------------------ */

static void test_counts(void) {
    const uint32_t N = 7;
    const uint32_t sm[3] = {PGT_BEZIER_C1, PGT_BEZIER_C0, PGT_BEZIER_DISCONTINUOUS};
    for (int c = 0; c < 3; ++c) {
        scene *s = chain_scene(N, sm[c]);
        REQUIRE(s);
        pgt_terminals_input in = scene_input(s, 1);
        pgt_terminals_output o;
        REQUIRE(build(&o, &in, 2, 0));
        /* shared rings: N + 1 at the points plus N (RINGS - 1) inside; discontinuous: each
         * segment has RINGS + 1 of its own */
        const uint32_t rings = c < 2 ? N * RINGS + 1u : N * (RINGS + 1u);
        CHECK(o.vertex_count == rings * (SIDES + 1u));
        CHECK(o.triangle_count == N * 2u * SIDES * RINGS);
        CHECK(o.bark_quads == (uint64_t)N * SIDES * RINGS && o.bark_segments == N &&
              o.leaf_count == 0);
        CHECK(o.bark_triangle_count == o.triangle_count && o.bark_vertex_count == o.vertex_count);
        uint32_t per[8] = {0};
        for (uint32_t t = 0; t < o.triangle_count; ++t)
            if (o.triangle_segment[t] <= N) per[o.triangle_segment[t]]++;
        for (uint32_t i = 1; i <= N; ++i) CHECK(per[i] == 2u * SIDES * RINGS);
        CHECK(per[0] == 0);
        int in_range = 1;
        for (size_t q = 0; q < 3u * (size_t)o.triangle_count; ++q)
            in_range &= o.triangles[q] < o.vertex_count;
        CHECK(in_range);
        if (c == 0)
            printf("  %u C1 segments: %u vertices, %u triangles, %llu polygons (quads)\n", N,
                   o.vertex_count, o.triangle_count, (unsigned long long)o.bark_quads);
        pgt_terminals_destroy(&o);
        scene_free(s);
    }
    /* other sides x rings */
    scene *s = chain_scene(3, PGT_BEZIER_C1);
    REQUIRE(s);
    pgt_terminals_input in = scene_input(s, 1);
    pgt_terminals_options opt = {0};
    opt.sides = 5, opt.rings = 2;
    pgt_terminals_output o;
    REQUIRE(pgt_terminals_build(&o, &in, &opt, NULL) == PGT_OK);
    CHECK(o.vertex_count == (3u * 2u + 1u) * 6u && o.triangle_count == 3u * 2u * 5u * 2u);
    pgt_terminals_destroy(&o);
    scene_free(s);
}

/* Case 2 tapers the bark: radii BARK_R (1 + TAPER_STEP (i mod 5)) (a shared ring takes its
 * owner's radius, the tube narrows or widens linearly inside a segment); case 3 adds a second
 * Bark record on every segment (ignored and counted). */
#define TAPER_STEP 0.2f
static void test_watertight(void) {
    const uint32_t sm[4] = {PGT_BEZIER_C1, PGT_BEZIER_C0, PGT_BEZIER_C1, PGT_BEZIER_C1};
    const char *const name[4] = {"C1", "C0", "C1 tapered", "C1 with duplicate Bark"};
    for (int c = 0; c < 4; ++c) {
        scene *s = tree_scene(sm[c], 1);
        REQUIRE(s);
        float rmax = BARK_R;
        const uint32_t nt = s->nt;
        for (uint32_t t = 0; t < nt; ++t) {
            if (s->kind[t] != BARK) continue;
            if (c == 2) s->a[t] = BARK_R * (1.0f + TAPER_STEP * (float)(s->seg[t] % 5u));
            if (c == 3) add_terminal(s, s->seg[t], BARK, 5.0f * BARK_R, 0.0f, PGT_BEZIER_C1);
            rmax = rmax > s->a[t] ? rmax : s->a[t];
        }
        pgt_terminals_input in = scene_input(s, 3);
        pgt_terminals_output o;
        REQUIRE(build(&o, &in, 2, 0));
        uint8_t *m = bark_mask(&o, &in);
        REQUIRE(m);
        const uint32_t br = check_watertight(&o, m, s->branch, s->parent, s->p, s->n, rmax);
        CHECK(br == 4u); /* main, the two side branches, the root's second chain */
        CHECK(o.duplicate_bark == (c == 3 ? s->n - 1u : 0u)); /* one root */
        printf("  %s: %u branches watertight, %u leaves, %u duplicate Bark ignored\n", name[c], br,
               o.leaf_count, o.duplicate_bark);
        free(m);
        pgt_terminals_destroy(&o);
        scene_free(s);
    }
}

/* The vertex ids of segment seg's triangles. */
static uint8_t *segment_vertices(const pgt_terminals_output *o, uint32_t seg) {
    uint8_t *used = calloc((size_t)o->vertex_count + 1u, 1);
    for (uint32_t t = 0; t < o->triangle_count; ++t)
        if (o->triangle_segment[t] == seg)
            for (int k = 0; k < 3; ++k) used[o->triangles[3u * (size_t)t + (size_t)k]] = 1;
    return used;
}

static uint32_t common_vertices(const pgt_terminals_output *o, uint32_t s1, uint32_t s2) {
    uint8_t *a = segment_vertices(o, s1), *b = segment_vertices(o, s2);
    uint32_t n = 0;
    for (uint32_t v = 0; v < o->vertex_count; ++v) n += a[v] && b[v];
    free(a), free(b);
    return n;
}

static void test_rings_shared(void) {
    scene *s = tree_scene(PGT_BEZIER_C1, 0);
    REQUIRE(s);
    pgt_terminals_input in = scene_input(s, 3);
    pgt_terminals_output o;
    REQUIRE(build(&o, &in, 1, 0));
    /* consecutive segments 3 -> 4 and 4 -> 5, the branch 4 -> 13 and the root's children */
    CHECK(common_vertices(&o, 4, 5) == SIDES + 1u);
    CHECK(common_vertices(&o, 4, 13) == SIDES + 1u);
    CHECK(common_vertices(&o, 5, 13) == SIDES + 1u);
    CHECK(common_vertices(&o, 1, 22) == SIDES + 1u);
    CHECK(common_vertices(&o, 3, 5) == 0);
    pgt_terminals_destroy(&o);
    scene_free(s);
    /* discontinuous: no sharing, but the end rings coincide in position */
    s = chain_scene(3, PGT_BEZIER_DISCONTINUOUS);
    REQUIRE(s);
    in = scene_input(s, 3);
    REQUIRE(build(&o, &in, 1, 0));
    CHECK(common_vertices(&o, 1, 2) == 0 && common_vertices(&o, 2, 3) == 0);
    pgt_terminals_destroy(&o);
    scene_free(s);
}

/* Ring k of bark segment seg: the first vertex (the layout of terminals.h: row k's first
 * triangle starts at ring k's vertex 0; the last row's second triangle ends at ring R's). */
static uint32_t ring_first(const pgt_terminals_output *o, uint32_t first_tri, uint32_t k) {
    const uint32_t S = o->sides, R = o->rings;
    if (k < R) return o->triangles[3u * (size_t)(first_tri + 2u * S * k)];
    return o->triangles[3u * (size_t)(first_tri + 2u * S * (R - 1u)) + 5u];
}

static void bezier_tangent(const pgt_terminals_input *in, uint32_t i, double s, double t[3]) {
    const float *p0 = &in->positions[3u * in->parent[i]], *p1 = &in->positions[3u * i];
    const float *b1 = &in->b1[3u * i], *b2 = &in->b2[3u * i];
    const double u = 1.0 - s;
    double l = 0.0;
    for (int k = 0; k < 3; ++k) {
        t[k] = u * u * (b1[k] - p0[k]) + 2.0 * u * s * (b2[k] - b1[k]) + s * s * (p1[k] - b2[k]);
        l += t[k] * t[k];
    }
    for (int k = 0; k < 3; ++k) t[k] /= sqrt(l);
}

static void test_geometry(void) {
    for (int centred = 0; centred < 2; ++centred) {
        scene *s = tree_scene(PGT_BEZIER_C1, 0);
        REQUIRE(s);
        pgt_terminals_input in = scene_input(s, 3);
        pgt_terminals_output o;
        REQUIRE(build(&o, &in, 2, centred));
        double worst_r = 0.0, worst_plane = 0.0, worst_centre = 0.0, worst_n = 0.0;
        uint32_t rings = 0, seam_bad = 0, uv_bad = 0;
        uint32_t t0 = 0;
        for (uint32_t i = 1; i < s->n; ++i) {
            while (t0 < o.triangle_count && o.triangle_segment[t0] != i) ++t0;
            REQUIRE(t0 < o.triangle_count);
            float prev_v = -1.0f;
            for (uint32_t k = 0; k <= RINGS; ++k) {
                const uint32_t f = ring_first(&o, t0, k);
                const double sk = (double)k / RINGS;
                float c[3];
                pgt_bezier_eval(&s->p[3u * s->parent[i]], &s->b1[3u * i], &s->b2[3u * i],
                                &s->p[3u * i], (float)sk, c);
                /* the flat scene: N = +z, the tube's centre is c + r z unless centred */
                const double centre[3] = {c[0], c[1], c[2] + (centred ? 0.0 : BARK_R)};
                double t[3];
                bezier_tangent(&in, i, sk, t);
                double mean[3] = {0, 0, 0};
                for (uint32_t m = 0; m <= SIDES; ++m) {
                    const float *v = &o.positions[3u * (size_t)(f + m)];
                    const float *nv = &o.normals[3u * (size_t)(f + m)];
                    double d[3], dl = 0.0, dn = 0.0, dt = 0.0;
                    for (int q = 0; q < 3; ++q) {
                        d[q] = v[q] - centre[q];
                        dl += d[q] * d[q], dn += d[q] * nv[q], dt += d[q] * t[q];
                        if (m < SIDES) mean[q] += v[q] / SIDES;
                    }
                    dl = sqrt(dl);
                    worst_r = fmax(worst_r, fabs(dl - BARK_R));
                    worst_plane = fmax(worst_plane, fabs(dt) / BARK_R);
                    worst_n = fmax(worst_n, fabs(dn / BARK_R - 1.0)); /* outward unit normal */
                    uv_bad += o.uvs[2u * (size_t)(f + m)] != (float)m / SIDES;
                    uv_bad += o.uvs[2u * (size_t)(f + m) + 1u] != o.uvs[2u * (size_t)f + 1u];
                }
                for (int q = 0; q < 3; ++q)
                    worst_centre = fmax(worst_centre, fabs(mean[q] - centre[q]));
                seam_bad += memcmp(&o.positions[3u * (size_t)f],
                                   &o.positions[3u * (size_t)(f + SIDES)], 12) != 0;
                uv_bad += !(o.uvs[2u * (size_t)f + 1u] > prev_v); /* v grows along the branch */
                prev_v = o.uvs[2u * (size_t)f + 1u];
                rings++;
            }
        }
        printf("  %s: %u rings: radius within %.3g, centre within %.3g, plane %.3g, normal "
               "%.3g\n",
               centred ? "centred" : "on the surface", rings, worst_r, worst_centre, worst_plane,
               worst_n);
        CHECK(worst_r <= RADIUS_TOL && worst_centre <= RADIUS_TOL);
        CHECK(worst_plane <= RING_PLANE_TOL && worst_n <= RING_PLANE_TOL);
        CHECK(seam_bad == 0 && uv_bad == 0);
        pgt_terminals_destroy(&o);
        scene_free(s);
    }
}

#define LEAF_SEGMENTS 2000u
static void test_leaves(void) {
    const float density = 2.3f, size = 0.04f;
    scene *s = scene_new(LEAF_SEGMENTS + 1u);
    REQUIRE(s);
    uint32_t prev = add_point(s, 0.0f, 0.0f, NONE);
    for (uint32_t k = 1; k <= LEAF_SEGMENTS; ++k) {
        prev = add_point(s, 0.1f * (float)k, 0.0f, prev);
        add_terminal(s, prev, LEAVES, density, size, 0);
    }
    pgt_terminals_input in = scene_input(s, 42);
    pgt_terminals_output o;
    REQUIRE(build(&o, &in, 2, 0));
    uint32_t *per = calloc(LEAF_SEGMENTS + 1u, 4);
    REQUIRE(per);
    for (uint32_t t = 0; t < o.triangle_count; ++t) per[o.triangle_segment[t]]++;
    uint32_t extras = 0, rule_bad = 0;
    for (uint32_t i = 1; i <= LEAF_SEGMENTS; ++i) {
        const uint32_t leaves = per[i] / 2u;
        extras += leaves - 2u;
        /* the documented draw: counter segment << 32 | rank 0 << 24 | 0 */
        const float u = pgt_rng_float(42, PGT_TERMINALS_LEAF_STREAM, (uint64_t)i << 32);
        rule_bad += leaves != 2u + (u < density - 2.0f) || per[i] % 2u;
    }
    const double mean = LEAF_SEGMENTS * 0.3, sd = sqrt(LEAF_SEGMENTS * 0.3 * 0.7);
    printf("  %u segments of density %.1f: %u leaves, %u extras (expected %.0f +- %.1f)\n",
           LEAF_SEGMENTS, (double)density, o.leaf_count, extras, mean, sd);
    CHECK(rule_bad == 0 && o.leaf_count == 2u * LEAF_SEGMENTS + extras);
    CHECK(fabs(extras - mean) <= LEAF_SIGMAS * sd);
    /* placement: a straight chain on the x axis, N = +z */
    const double h = 0.5 * size, lift = PGT_TERMINALS_LEAF_LIFT * size;
    double worst = 0.0;
    uint32_t bad = 0;
    for (uint32_t t = 0; t < o.triangle_count; t += 2) {
        const uint32_t *q = &o.triangles[3u * (size_t)t];
        const uint32_t seg = o.triangle_segment[t], v0 = q[0];
        bad += q[3] != v0 || q[4] != q[2] || q[1] != v0 + 1u || q[2] != v0 + 2u || q[5] != v0 + 3u;
        double c[3] = {0, 0, 0};
        for (uint32_t v = v0; v < v0 + 4u; ++v)
            for (int k = 0; k < 3; ++k) c[k] += o.positions[3u * (size_t)v + (size_t)k] / 4.0;
        /* the centre is on the curve (the segment of the x axis) lifted by lift */
        worst = fmax(worst, fmax(fabs(c[1]), fabs(c[2] - lift)));
        bad += c[0] < 0.1 * (seg - 1) - LEAF_TOL || c[0] > 0.1 * seg + LEAF_TOL;
        for (uint32_t v = v0; v < v0 + 4u; ++v) {
            const float *p = &o.positions[3u * (size_t)v], *n = &o.normals[3u * (size_t)v];
            const double d = sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                                  (p[2] - c[2]) * (p[2] - c[2]));
            worst = fmax(worst, fabs(d - h * sqrt(2.0))); /* a corner of the square */
            worst = fmax(worst, fabs(p[2] - lift));       /* in the (lifted) tangent plane */
            bad += n[0] != 0.0f || n[1] != 0.0f || n[2] != 1.0f || d > size;
        }
        const float *p0 = &o.positions[3u * (size_t)v0], *p1 = p0 + 3, *p2 = p0 + 6;
        const double cz =
            (double)(p1[0] - p0[0]) * (p2[1] - p0[1]) - (double)(p1[1] - p0[1]) * (p2[0] - p0[0]);
        bad += !(cz > 0.0); /* winds around +z */
        bad += o.uvs[2u * (size_t)v0] != 0.0f || o.uvs[2u * (size_t)v0 + 4u] != 1.0f ||
               o.uvs[2u * (size_t)v0 + 5u] != 1.0f;
    }
    printf("  leaf placement within %.3g\n", worst);
    CHECK(bad == 0 && worst <= LEAF_TOL);
    free(per);
    pgt_terminals_destroy(&o);
    scene_free(s);
}

static int same_bytes(const pgt_terminals_output *a, const pgt_terminals_output *b) {
    const size_t V = a->vertex_count, T = a->triangle_count;
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           a->leaf_count == b->leaf_count && !memcmp(a->positions, b->positions, 12 * V) &&
           !memcmp(a->normals, b->normals, 12 * V) && !memcmp(a->uvs, b->uvs, 8 * V) &&
           !memcmp(a->triangles, b->triangles, 12 * T) &&
           !memcmp(a->triangle_segment, b->triangle_segment, 4 * T);
}

/* The bark triangles of a and b, in order, have the same corner positions (the leaves, which
 * come between them in the layout, may differ). */
static int same_bark(const pgt_terminals_output *a, const pgt_terminals_output *b,
                     const pgt_terminals_input *in) {
    uint8_t *ma = bark_mask(a, in), *mb = bark_mask(b, in);
    uint32_t ta = 0, tb = 0, bad = 0;
    for (;; ++ta, ++tb) {
        while (ta < a->triangle_count && !ma[ta]) ++ta;
        while (tb < b->triangle_count && !mb[tb]) ++tb;
        if (ta == a->triangle_count || tb == b->triangle_count) {
            bad += ta != a->triangle_count || tb != b->triangle_count;
            break;
        }
        for (int k = 0; k < 3; ++k)
            bad += memcmp(&a->positions[3u * (size_t)a->triangles[3u * (size_t)ta + (size_t)k]],
                          &b->positions[3u * (size_t)b->triangles[3u * (size_t)tb + (size_t)k]],
                          12) != 0;
    }
    free(ma), free(mb);
    return bad == 0;
}

static void test_determinism(void) {
    scene *s = tree_scene(PGT_BEZIER_C1, 1);
    REQUIRE(s);
    for (uint32_t i = 1; i < s->n; ++i) add_terminal(s, i, LEAVES, 3.5f, 0.03f, 0);
    pgt_terminals_input in = scene_input(s, 9);
    pgt_terminals_output one, two, five, other;
    REQUIRE(build(&one, &in, 1, 0));
    REQUIRE(build(&two, &in, 2, 0));
    REQUIRE(build(&five, &in, 5, 0));
    CHECK(same_bytes(&one, &two) && same_bytes(&one, &five));
    /* record order does not matter (one Bark and distinct Leaves ranks per segment kept) */
    scene *r = tree_scene(PGT_BEZIER_C1, 1);
    REQUIRE(r);
    for (uint32_t i = 1; i < r->n; ++i) add_terminal(r, i, LEAVES, 3.5f, 0.03f, 0);
    for (uint32_t lo = 0, hi = r->nt - 1u; lo < hi; ++lo, --hi) { /* reverse per segment order */
        uint32_t *f[3] = {r->seg, r->kind, r->smooth};
        float *g[2] = {r->a, r->b};
        for (int k = 0; k < 3; ++k) {
            const uint32_t x = f[k][lo];
            f[k][lo] = f[k][hi], f[k][hi] = x;
        }
        for (int k = 0; k < 2; ++k) {
            const float x = g[k][lo];
            g[k][lo] = g[k][hi], g[k][hi] = x;
        }
    }
    /* reversing swaps the two Leaves records' ranks within a segment: swap them back */
    for (uint32_t t = 0; t + 1u < r->nt; ++t)
        for (uint32_t u = t + 1u; u < r->nt; ++u)
            if (r->seg[t] == r->seg[u] && r->kind[t] == LEAVES && r->kind[u] == LEAVES) {
                const float a = r->a[t], b = r->b[t];
                r->a[t] = r->a[u], r->b[t] = r->b[u], r->a[u] = a, r->b[u] = b;
            }
    pgt_terminals_input rin = scene_input(r, 9);
    pgt_terminals_output rev;
    REQUIRE(build(&rev, &rin, 2, 0));
    CHECK(same_bytes(&one, &rev));
    pgt_terminals_destroy(&rev);
    scene_free(r);
    /* another seed id: the same bark, other leaves */
    in.seed_id = 10;
    REQUIRE(build(&other, &in, 2, 0));
    CHECK(other.bark_triangle_count == one.bark_triangle_count);
    CHECK(same_bark(&one, &other, &in));
    CHECK(!same_bytes(&one, &other));
    printf("  %u vertices, %u triangles, %u leaves (seed 9) vs %u leaves (seed 10)\n",
           one.vertex_count, one.triangle_count, one.leaf_count, other.leaf_count);
    pgt_terminals_destroy(&one), pgt_terminals_destroy(&two), pgt_terminals_destroy(&five);
    pgt_terminals_destroy(&other);
    scene_free(s);
    /* The tree's 24 segments weigh 24 x 216 bark quads, under pgt_parallel_for's 4096 elements a
     * thread: one thread whatever was asked. A chain of 300 (64,800) runs on 2 and on 5. */
    scene *c = chain_scene(300, PGT_BEZIER_C1);
    REQUIRE(c);
    for (uint32_t i = 1; i < c->n; ++i) add_terminal(c, i, LEAVES, 3.5f, 0.03f, 0);
    pgt_terminals_input cin = scene_input(c, 9);
    REQUIRE(build(&one, &cin, 1, 0));
    REQUIRE(build(&two, &cin, 2, 0));
    REQUIRE(build(&five, &cin, 5, 0));
    CHECK(same_bytes(&one, &two) && same_bytes(&one, &five));
    pgt_terminals_destroy(&one), pgt_terminals_destroy(&two), pgt_terminals_destroy(&five);
    scene_free(c);
}

static void expect_error(scene *s, pgt_result code, const char *needle,
                         const pgt_terminals_options *opt) {
    pgt_terminals_input in = scene_input(s, 1);
    pgt_terminals_output o;
    pgt_error err = {0};
    const pgt_result r = pgt_terminals_build(&o, &in, opt, &err);
    CHECK_MSG(r == code && strstr(err.message, needle), "got %s: %s (wanted '%s')",
              pgt_result_name(r), err.message, needle);
    /* nothing on failure */
    CHECK(o.vertex_count == 0 && o.triangle_count == 0 && !o.positions && !o.normals && !o.uvs &&
          !o.triangles && !o.triangle_segment && o.sides == 0 && o.rings == 0);
    CHECK(o.bark_segments == 0 && o.duplicate_bark == 0 && o.leaf_count == 0 && o.bark_quads == 0);
    pgt_terminals_destroy(&o);
}

static void test_errors(void) {
    const float bad_r[4] = {0.0f, -1.0f, NAN, INFINITY};
    for (int k = 0; k < 4; ++k) {
        scene *s = chain_scene(4, PGT_BEZIER_C1);
        REQUIRE(s);
        s->a[2] = bad_r[k]; /* terminal 2: Bark on segment 3 */
        expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "Bark on segment 3", NULL);
        scene_free(s);
    }
    scene *s = chain_scene(4, PGT_BEZIER_C1);
    REQUIRE(s);
    s->smooth[1] = 3;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "smoothness 3", NULL);
    s->smooth[1] = PGT_BEZIER_C1;
    add_terminal(s, 2, LEAVES, -0.5f, 0.1f, 0);
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "Leaves on segment 2): density", NULL);
    s->a[4] = NAN;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "Leaves on segment 2): density", NULL);
    s->a[4] = 1.0f, s->b[4] = 0.0f;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "Leaves on segment 2): size", NULL);
    s->b[4] = 0.1f, s->kind[4] = 7;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "unknown kind 7", NULL);
    s->kind[4] = LEAVES, s->seg[4] = 0;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "segment 0, which is a root", NULL);
    s->seg[4] = 99;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "past the points", NULL);
    s->seg[4] = 2;
    pgt_terminals_options opt = {0};
    opt.sides = 2;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "sides", &opt);
    /* a non-finite position: scene_input rebuilds the curves, bezier refuses, the control
     * points stay and the position is caught by the terminals */
    s->p[3 * 3] = NAN;
    expect_error(s, PGT_ERROR_INVALID_ARGUMENT, "segment 3 (2 -> 3", NULL);
    scene_free(s);
    /* too many Leaves records on one segment; too many vertices */
    s = scene_new(PGT_TERMINALS_MAX_LEAVES_RECORDS + 2u);
    REQUIRE(s);
    add_point(s, 0.0f, 0.0f, NONE);
    add_point(s, 1.0f, 0.0f, 0);
    for (uint32_t k = 0; k <= PGT_TERMINALS_MAX_LEAVES_RECORDS / 2u; ++k)
        add_terminal(s, 1, LEAVES, 1.0f, 0.1f, 0), add_terminal(s, 1, LEAVES, 1.0f, 0.1f, 0);
    expect_error(s, PGT_ERROR_LIMIT, "segment 1 has more than", NULL);
    scene_free(s);
    s = scene_new(1100);
    REQUIRE(s);
    uint32_t prev = add_point(s, 0.0f, 0.0f, NONE);
    for (uint32_t k = 1; k <= 1030; ++k) {
        prev = add_point(s, (float)k, 0.0f, prev);
        add_terminal(s, prev, LEAVES, PGT_TERMINALS_MAX_LEAF_DENSITY, 0.1f, 0);
    }
    expect_error(s, PGT_ERROR_LIMIT, "2^32 - 1", NULL);
    scene_free(s);
    /* max_bytes: the chain's output (counted by a build without the bound) one byte over it
     * is refused before anything is allocated; exactly at it, built */
    s = chain_scene(4, PGT_BEZIER_C1);
    REQUIRE(s);
    pgt_terminals_input in = scene_input(s, 1);
    pgt_terminals_output full;
    REQUIRE(pgt_terminals_build(&full, &in, NULL, NULL) == PGT_OK);
    const uint64_t bytes = 32u * (uint64_t)full.vertex_count + 16u * (uint64_t)full.triangle_count;
    pgt_terminals_destroy(&full);
    pgt_terminals_options lim = {0};
    lim.max_bytes = bytes - 1u;
    expect_error(s, PGT_ERROR_LIMIT, "more than the", &lim);
    lim.max_bytes = bytes;
    REQUIRE(pgt_terminals_build(&full, &in, &lim, NULL) == PGT_OK);
    pgt_terminals_destroy(&full);
    scene_free(s);
}

/* ---- part 2: ivy.grammar on the cube-sphere, expand -> Bezier -> terminals ------------- */

#define IVY_SEEDS IVY_SCENE_SEEDS
/* Bark vertices: at the ring's radius from the ring's centre, which is r from the curve point:
 * float rounding on coordinates of magnitude ~1 (1e-6) against r = 0.004. */
#define IVY_RADIUS_TOL 1e-5
/* ivy.grammar's barkRadius and leafSize. */
#define IVY_BARK_R 0.004
#define IVY_LEAF_SIZE 0.02f
/* A leaf's corners lie in the plane of its normal: float rounding of offsets of ~0.02 from
 * coordinates of magnitude ~1 (a few 1e-7). */
#define IVY_LEAF_PLANE_TOL 1e-5
/* A bark normal is cos(a) N + sin(a) B with N and B normalised and perpendicular in float32: its
 * length is 1 within a few roundings of 1 (6e-8 each). */
#define IVY_NORMAL_UNIT_TOL 1e-6
static void test_ivy_end_to_end(void) {
    static ivy_scene scene;
    REQUIRE(ivy_scene_make(&scene));
    REQUIRE(scene.in.seed_count == IVY_SEEDS);
    const pgt_expand_input ein = scene.in;
    pgt_error err = {0};
    pgt_expand_options eo = {0};
    eo.threads = 2;
    pgt_expand_output ex;
    REQUIRE(pgt_expand(&ex, &ein, &eo, &err) == PGT_OK);
    const uint32_t n = ex.point_count;
    float *p = malloc(12u * n), *nr = malloc(12u * n), *b1 = malloc(12u * n), *b2 = malloc(12u * n);
    uint8_t *sm = malloc(n);
    REQUIRE(p && nr && b1 && b2 && sm);
    for (uint32_t i = 0; i < n; ++i) {
        p[3 * i] = ex.x[i], p[3 * i + 1] = ex.y[i], p[3 * i + 2] = ex.z[i];
        nr[3 * i] = ex.nx[i], nr[3 * i + 1] = ex.ny[i], nr[3 * i + 2] = ex.nz[i];
        sm[i] = PGT_BEZIER_C1;
    }
    for (uint32_t t = 0; t < ex.terminal_count; ++t)
        if (ex.terminal_kind[t] == BARK)
            sm[ex.terminal_segment[t]] = (uint8_t)ex.terminal_smoothness[t];
    struct timespec t0, t1, t2;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    REQUIRE(pgt_bezier_build(p, nr, ex.parent, sm, n, 2, b1, b2, &err) == PGT_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    pgt_terminals_input in;
    memset(&in, 0, sizeof in);
    in.point_count = n, in.positions = p, in.normals = nr, in.parent = ex.parent;
    in.b1 = b1, in.b2 = b2, in.terminal_count = ex.terminal_count;
    in.terminal_segment = ex.terminal_segment, in.terminal_kind = ex.terminal_kind;
    in.terminal_a = ex.terminal_a, in.terminal_b = ex.terminal_b;
    in.terminal_smoothness = ex.terminal_smoothness, in.seed_id = 5;
    pgt_terminals_output o, one;
    REQUIRE(build(&o, &in, 2, 0));
    clock_gettime(CLOCK_MONOTONIC, &t2);
    REQUIRE(build(&one, &in, 1, 0));
    CHECK(same_bytes(&o, &one));
    pgt_terminals_destroy(&one);
    CHECK(o.bark_segments > 0 && o.bark_quads == (uint64_t)SIDES * RINGS * o.bark_segments);
    /* watertight per branch */
    uint8_t *mask = bark_mask(&o, &in);
    REQUIRE(mask);
    const uint32_t branches =
        check_watertight(&o, mask, ex.branch, ex.parent, p, n, (float)IVY_BARK_R);
    CHECK(branches > 0);
    /* bark rings: vertices at r from the ring's centre, the centre at r from the curve point
     * (the tube lies on the surface), inner ring planes perpendicular to B'(s) */
    double worst_r = 0.0, worst_lift = 0.0, worst_plane = 0.0;
    for (uint32_t t = 0; t < o.triangle_count; t += 2u * o.sides * o.rings) {
        while (t < o.triangle_count && !mask[t]) ++t;
        if (t == o.triangle_count) break;
        const uint32_t seg = o.triangle_segment[t];
        for (uint32_t kk = 0; kk <= o.rings; ++kk) {
            const uint32_t f = ring_first(&o, t, kk);
            const double sk = (double)kk / o.rings;
            float c[3];
            pgt_bezier_eval(&p[3u * ex.parent[seg]], &b1[3u * seg], &b2[3u * seg], &p[3u * seg],
                            (float)sk, c);
            double mean[3] = {0, 0, 0}, tg[3], d2 = 0.0;
            bezier_tangent(&in, seg, sk, tg);
            for (uint32_t mm = 0; mm < o.sides; ++mm)
                for (int q = 0; q < 3; ++q)
                    mean[q] += o.positions[3u * (size_t)(f + mm) + (size_t)q] / o.sides;
            for (int q = 0; q < 3; ++q) d2 += (mean[q] - c[q]) * (mean[q] - c[q]);
            worst_lift = fmax(worst_lift, fabs(sqrt(d2) - IVY_BARK_R));
            for (uint32_t mm = 0; mm < o.sides; ++mm) {
                double e2 = 0.0, et = 0.0;
                for (int q = 0; q < 3; ++q) {
                    const double e = o.positions[3u * (size_t)(f + mm) + (size_t)q] - mean[q];
                    e2 += e * e, et += e * tg[q];
                }
                worst_r = fmax(worst_r, fabs(sqrt(e2) - IVY_BARK_R));
                if (kk > 0 && kk < o.rings) worst_plane = fmax(worst_plane, fabs(et) / IVY_BARK_R);
            }
        }
    }
    printf("  ivy rings: radius within %.3g, lift within %.3g, inner planes within %.3g\n", worst_r,
           worst_lift, worst_plane);
    CHECK(worst_r <= IVY_RADIUS_TOL && worst_lift <= IVY_RADIUS_TOL);
    CHECK(worst_plane <= RING_PLANE_TOL);
    /* every vertex finite, bark normals unit, leaf vertices within size of their segment's
     * curve (sampled) and in their tangent plane */
    uint32_t bad = 0;
    for (size_t q = 0; q < 3u * (size_t)o.vertex_count; ++q) bad += !isfinite(o.positions[q]);
    double worst_unit = 0.0;
    for (uint32_t t = 0; t < o.triangle_count; ++t)
        for (uint32_t c = 0; mask[t] && c < 3u; ++c) {
            const float *nv = &o.normals[3u * (size_t)o.triangles[3u * (size_t)t + c]];
            const double len =
                sqrt((double)nv[0] * nv[0] + (double)nv[1] * nv[1] + (double)nv[2] * nv[2]);
            worst_unit = fmax(worst_unit, fabs(len - 1.0));
        }
    printf("  ivy bark normals: unit within %.3g\n", worst_unit);
    CHECK(worst_unit <= IVY_NORMAL_UNIT_TOL);
    double worst_leaf = 0.0;
    for (uint32_t t = 0; t < o.triangle_count; ++t) {
        if (mask[t]) continue;
        /* a leaf: two consecutive triangles on four consecutive vertices */
        const uint32_t seg = o.triangle_segment[t], v0 = o.triangles[3u * (size_t)t];
        const float size = IVY_LEAF_SIZE;
        const float *nv = &o.normals[3u * (size_t)v0];
        for (uint32_t w = v0; w < v0 + 4u; ++w) {
            const float *x = &o.positions[3u * (size_t)w];
            double best = INFINITY;
            for (int j = 0; j <= 64; ++j) {
                float c[3];
                pgt_bezier_eval(&p[3u * ex.parent[seg]], &b1[3u * seg], &b2[3u * seg], &p[3u * seg],
                                (float)j / 64.0f, c);
                best =
                    fmin(best, sqrt((x[0] - c[0]) * (x[0] - c[0]) + (x[1] - c[1]) * (x[1] - c[1]) +
                                    (x[2] - c[2]) * (x[2] - c[2])));
            }
            bad += best > size;
            const float *x0 = &o.positions[3u * (size_t)v0];
            worst_leaf = fmax(worst_leaf, fabs((x[0] - x0[0]) * nv[0] + (x[1] - x0[1]) * nv[1] +
                                               (x[2] - x0[2]) * nv[2]));
        }
        t++;
    }
    printf("  ivy leaves: corners within %.3g of their normal's plane\n", worst_leaf);
    CHECK(bad == 0 && worst_leaf <= IVY_LEAF_PLANE_TOL);
    const double ms_b =
        (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
    const double ms_t =
        (double)(t2.tv_sec - t1.tv_sec) * 1e3 + (double)(t2.tv_nsec - t1.tv_nsec) * 1e-6;
    printf("  ivy: %u points, %u branches watertight, %u bark segments (%llu polygons), %u "
           "leaves, %u vertices, %u triangles; Bezier %.2f ms, terminals %.2f ms on 2 threads\n",
           n, branches, o.bark_segments, (unsigned long long)o.bark_quads, o.leaf_count,
           o.vertex_count, o.triangle_count, ms_b, ms_t);
    free(mask);
    pgt_terminals_destroy(&o);
    free(p), free(nr), free(b1), free(b2), free(sm);
    pgt_expand_destroy(&ex);
    ivy_scene_free(&scene);
}

static const pgt_test_case cases[] = {
    {"counts", test_counts},
    {"watertight", test_watertight},
    {"rings_shared", test_rings_shared},
    {"geometry", test_geometry},
    {"leaves", test_leaves},
    {"determinism", test_determinism},
    {"errors", test_errors},
    {"ivy_end_to_end", test_ivy_end_to_end},
};

PGT_TEST_MAIN(cases)
