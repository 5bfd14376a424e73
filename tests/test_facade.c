/* Tests of ref_cpu facade.h (issue 6): terminals stay in their scope and volume, ray-dependent
 * development (Algorithm 1) agrees with the explicit geometry of the same grammar as seen by an
 * independent double-precision brute-force ray caster (Moller-Trumbore over every triangle of
 * the facades whose triangles' bounding box the ray meets), a ray that misses a volume develops
 * nothing, coverage polygons are crossed by every ray that meets the volume, frames do not
 * depend on the thread count, and bad scenes and grammars get clear errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/facade.h>
#include <pgt/grammar.h>
#include <pgt/rng.h>

#include "gen.h"
#include "test_util.h"

#include "facade_oracle.h"

/* The views the tests take of a generated city spanning L metres (eye, look-at, up, fov). */
#define CITY_VIEWS 4
static void city_view(float L, int k, float view[10]) {
    const float views[CITY_VIEWS][10] = {
        {-0.4f * L, 0.5f * L, -0.4f * L, 0.5f * L, 0.0f, 0.5f * L, 0, 1, 0, 50}, /* aerial */
        {-5.0f, 1.7f, 28.0f, L, 6.0f, 28.5f, 0, 1, 0, 60},  /* street level, along a street */
        {-2.0f, 20.0f, 27.5f, L, 1.0f, 28.2f, 0, 1, 0, 40}, /* grazing the facades */
        {0.5f * L, 0.3f * L, 0.5f * L, 0.5f * L + 1.0f, 0.0f, 0.5f * L + 3.0f, 0, 1, 0,
         90}, /* steep, inside the city */
    };
    memcpy(view, views[k], sizeof views[k]);
}

/* A generated city of `buildings` buildings of grammar `name` (a file of grammars/), its facades
 * prepared: 1, or 0 after printing why. */
static int city_of(const char *name, uint32_t buildings, uint32_t seed, pgt_grammar *g,
                   pgt_facade_scene *s, pgt_facade **fa, uint32_t *fc) {
    pgt_error err = {0};
    if (!load(g, name)) return 0;
    if (pgt_gen_city(s, g, buildings, seed, &err) != PGT_OK ||
        pgt_facade_prepare(s, fa, fc, &err) != PGT_OK) {
        fprintf(stderr, "  %s: %s\n", name, err.message);
        return 0;
    }
    return 1;
}

static void check_city(const char *grammar, uint32_t buildings, uint32_t side) {
    pgt_grammar g;
    pgt_facade_scene s;
    pgt_facade *fa = NULL;
    uint32_t fc = 0;
    REQUIRE(city_of(grammar, buildings, 7, &g, &s, &fa, &fc));
    pgt_error err = {0};
    CHECK_MSG(pgt_facade_scene_check(&s, "city", &err) == PGT_OK, "%s", err.message);
    pgt_facade_mesh m;
    const pgt_result r = pgt_facade_explicit(&s, fa, fc, &m, &err);
    CHECK_MSG(r == PGT_OK, "%s", err.message);
    /* a sound facade's development ends within pgt_facade_explain's bound and finds no error */
    uint32_t explained = 0;
    for (uint32_t f = 0; f < fc; ++f) {
        pgt_error e2 = {0};
        explained += pgt_facade_explain(&s, &fa[f], f, &e2) == PGT_OK;
    }
    CHECK_MSG(explained == fc, "%s: %u of %u facades explained without error", grammar, explained,
              fc);
    if (r == PGT_OK) {
        oracle o;
        oracle_init(&o, &m, fc + s.building_count); /* roofs are facade_count + building */
        /* the city spans side lots of PGT_GEN_CITY_LOT metres */
        const float L = (float)(side * PGT_GEN_CITY_LOT);
        agreement a;
        memset(&a, 0, sizeof a);
        for (int k = 0; k < CITY_VIEWS; ++k) {
            float cv[10];
            city_view(L, k, cv);
            pgt_facade_camera cam;
            REQUIRE(pgt_facade_camera_init(&cam, &cv[0], &cv[3], &cv[6], cv[9], 96, 72, &err) ==
                    PGT_OK);
            compare_camera(&s, fa, fc, &o, &cam, &a, 1);
        }
        printf("  %s, %u buildings: %u rays, %u agree, %u at an edge, %u other; max |dt|/t %.2g\n",
               grammar, buildings, a.rays, a.agree, a.near_edge, a.other, a.max_rel);
        /* the bar on its own (it was or-ed with other == 0, checked next, so it never decided):
         * rays near an edge may disagree, but not more than the bar allows */
        CHECK_MSG((double)a.agree / a.rays >= AGREEMENT_MIN, "%u of %u rays agree", a.agree,
                  a.rays);
        CHECK_MSG(a.other == 0, "%u disagreements away from edges", a.other);
        CHECK_MSG(a.ties == 0, "%u rays meet two faces in one place", a.ties);
        oracle_free(&o);
        pgt_facade_mesh_destroy(&m);
    }
    free(fa);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
}

static void test_paper_grammar_vs_explicit(void) { check_city("facade.grammar", 9, 3); }

static void test_rich_grammar_vs_explicit(void) { check_city("facade_rich.grammar", 9, 3); }

/* Geometry-image terminals (6.2.2): the oculus windows, triangles tested brute force. */
static void test_gimage_grammar_vs_explicit(void) { check_city("facade_gimage.grammar", 2, 2); }

/* A Window's or Door's layout in its w x h scope as facade.h documents it (Fig. 7), not as
 * facade_terminals.c builds it: the arguments (margin m, frame f, frameDepth fd, recess r, and a
 * window's sillHeight sh and sillDepth sd; 0 for a door), the frame's bottom fy0 (m + sh; a
 * door's frame stands on the ground, 0) and the opening [ix0, ix1] x [iy0, iy1] inside the
 * margin and the frame (above the sill). ex, ey, ez: the values near which the probes of the
 * tests below are skipped, from the arguments as given. */
typedef struct opening_layout {
    int window;
    float w, h, m, f, fd, r, sh, sd, fy0, ix0, ix1, iy0, iy1;
    float ex[4], ey[6], ez[4];
} opening_layout;

static opening_layout layout_of(uint32_t kind, const float *args, float w, float h) {
    opening_layout L;
    L.window = kind == PGT_FACADE_WINDOW;
    L.w = w, L.h = h, L.m = args[0], L.f = args[1], L.fd = args[2], L.r = args[3];
    L.sh = L.window ? args[4] : 0.0f, L.sd = L.window ? args[5] : 0.0f;
    L.fy0 = L.window ? L.m + L.sh : 0.0f;
    L.ix0 = L.m + L.f, L.ix1 = w - L.m - L.f, L.iy1 = h - L.m - L.f;
    L.iy0 = L.window ? L.fy0 + L.f : 0.0f;
    const float m = L.m, f = L.f, sh = args[4];
    const float ex[4] = {m, m + f, w - m - f, w - m};
    const float ey[6] = {0.0f, m, m + sh, m + sh + f, h - m - f, h - m};
    const float ez[4] = {-L.r, 0.0f, L.fd, args[5]};
    memcpy(L.ex, ex, sizeof ex), memcpy(L.ey, ey, sizeof ey), memcpy(L.ez, ez, sizeof ez);
    return L;
}

/* How far from every edge of the layout a probe stays (scope units): the probes are a grid
 * offset from the edges' values, so that "inside" never hinges on float rounding at an edge. */
#define PROBE_EDGE_CLEARANCE 1e-3f

static int near_edge(const float *edges, int n, float v) {
    for (int e = 0; e < n; ++e)
        if (fabsf(v - edges[e]) < PROBE_EDGE_CLEARANCE) return 1;
    return 0;
}

/* Whether a Window's or Door's opening (the glass, the door leaf) has an area in a w x h scope
 * (layout_of). Other kinds always fit. */
static int opening_fits(uint32_t kind, const float *args, float w, float h) {
    if (kind != PGT_FACADE_WINDOW && kind != PGT_FACADE_DOOR) return 1;
    const opening_layout L = layout_of(kind, args, w, h);
    return L.ix1 > L.ix0 && L.iy1 > L.iy0;
}

/* The arguments of the windows and doors the layout tests probe. */
static const float opening_args[2][6] = {{0.4f, 0.1f, 0.08f, 0.25f, 0.12f, 0.2f},
                                         {0.3f, 0.15f, 0.2f, 0.1f, 0.3f, 0.05f}};

/* Every rectangle lies in its scope (x, y) and the terminal's stated depth range. */
static void test_terminals_in_scope(void) {
    pgt_facade_quad q[PGT_FACADE_MAX_QUADS];
    const float args[6] = {0.4f, 0.1f, 0.08f, 0.25f, 0.12f, 0.2f};
    const uint32_t kinds[5] = {PGT_FACADE_WALL, PGT_FACADE_WINDOW, PGT_FACADE_DOOR,
                               PGT_FACADE_LEDGE, PGT_FACADE_BALCONY};
    const uint32_t expect[5] = {1, 27, 17, 6, 8};
    /* depth ranges by kind: window [-recess, max(frameDepth, sillDepth)], door [-recess,
     * frameDepth], ledge and balcony [0, depth] */
    const float zmin[5] = {0.0f, -args[3], -args[3], 0.0f, 0.0f};
    const float zmax[5] = {0.0f, fmaxf(args[2], args[5]), args[2], args[0], args[0]};
    uint64_t counter = 0;
    for (int k = 0; k < 5; ++k)
        for (int trial = 0; trial < 200; ++trial) {
            const float x0 = 10.0f * pgt_rng_float(1, 1, counter++);
            const float y0 = 10.0f * pgt_rng_float(1, 1, counter++);
            const float w = 0.5f + 3.0f * pgt_rng_float(1, 1, counter++);
            const float h = 0.5f + 3.0f * pgt_rng_float(1, 1, counter++);
            const uint32_t n = pgt_facade_terminal_quads(kinds[k], args, 6, x0, y0, w, h, q);
            /* the layout degrades to a wall exactly when the opening has no area (facade.h) */
            CHECK_MSG(n == (opening_fits(kinds[k], args, w, h) ? expect[k] : 1u),
                      "kind %u in %g x %g: %u rectangles", kinds[k], (double)w, (double)h, n);
            for (uint32_t i = 0; i < n; ++i) {
                float lo[3], hi[3];
                const uint32_t ax = q[i].axis, o0 = ax == 0 ? 1u : 0u, o1 = ax == 2 ? 1u : 2u;
                lo[ax] = hi[ax] = q[i].c;
                lo[o0] = q[i].lo[0], hi[o0] = q[i].hi[0], lo[o1] = q[i].lo[1], hi[o1] = q[i].hi[1];
                if (!(hi[o0] > lo[o0])) continue;
                CHECK(hi[o1] > lo[o1]);
                CHECK(lo[0] >= x0 && hi[0] <= x0 + w);
                CHECK(lo[1] >= y0 && hi[1] <= y0 + h);
                CHECK(lo[2] >= zmin[k] && hi[2] <= zmax[k]);
            }
        }
    /* a window in a scope too small for its opening is a wall */
    CHECK(pgt_facade_terminal_quads(PGT_FACADE_WINDOW, args, 6, 0, 0, 0.9f, 3.0f, q) == 1);
    CHECK(q[0].axis == 2 && q[0].c == 0.0f);
}

/* The depth a Window or Door shows a viewer in front of it at (x, y) of its scope, from its
 * documented layout: the wall (z = 0) outside the margin; for a window the sill box from m to
 * fy0, protruding by sd; the frame, protruding by fd, a band f wide around the opening; the
 * opening (glass, door leaf) recessed to -r. A door's frame and opening reach the scope's
 * bottom. */
static float front_depth(const opening_layout *L, float x, float y) {
    const float bottom = L->window ? L->m : 0.0f; /* of the sill, or the frame */
    if (x < L->m || x > L->w - L->m || y < bottom || y > L->h - L->m) return 0.0f;
    if (y < L->fy0) return L->sd;
    const int in_opening = x > L->ix0 && x < L->ix1 && y < L->iy1 && (!L->window || y > L->iy0);
    return in_opening ? -L->r : L->fd;
}

/* Windows and doors seen from the front: at a grid of points of the scope, the nearest
 * rectangle facing the viewer (the largest z among the z-facing ones covering the point) is at
 * the depth the documented layout gives (front_depth). The rectangles are also what the ray
 * test and the explicit twin use, so this is the only check of their shape against the
 * terminal's definition. */
static void test_window_and_door_depths(void) {
    const float(*args)[6] = opening_args;
    const uint32_t kinds[2] = {PGT_FACADE_WINDOW, PGT_FACADE_DOOR};
    const float sizes[3][2] = {{1.6f, 2.4f}, {3.1f, 1.7f}, {1.25f, 1.33f}};
    pgt_facade_quad q[PGT_FACADE_MAX_QUADS];
    uint32_t probes = 0, opening = 0, frame = 0, sill = 0, wall = 0;
    for (int k = 0; k < 2; ++k)
        for (int a = 0; a < 2; ++a)
            for (int sz = 0; sz < 3; ++sz) {
                const float w = sizes[sz][0], h = sizes[sz][1], x0 = 2.0f, y0 = 5.0f;
                REQUIRE(opening_fits(kinds[k], args[a], w, h));
                const opening_layout L = layout_of(kinds[k], args[a], w, h);
                const uint32_t n = pgt_facade_terminal_quads(kinds[k], args[a], 6, x0, y0, w, h, q);
                const uint32_t G = 97; /* probes per side, offset by a third of a cell */
                for (uint32_t i = 0; i < G; ++i)
                    for (uint32_t j = 0; j < G; ++j) {
                        const float x = w * ((float)i + 1.0f / 3.0f) / G,
                                    y = h * ((float)j + 2.0f / 3.0f) / G;
                        if (near_edge(L.ex, 4, x) || near_edge(L.ey, 6, y)) continue;
                        float best = -INFINITY;
                        for (uint32_t t = 0; t < n; ++t)
                            if (q[t].axis == 2 && q[t].lo[0] <= x0 + x && x0 + x <= q[t].hi[0] &&
                                q[t].lo[1] <= y0 + y && y0 + y <= q[t].hi[1] && q[t].c > best)
                                best = q[t].c;
                        const float want = front_depth(&L, x, y);
                        probes++;
                        opening += want < 0.0f, frame += want == args[a][2];
                        sill += kinds[k] == PGT_FACADE_WINDOW && want == args[a][5];
                        wall += want == 0.0f;
                        CHECK_MSG(best == want,
                                  "kind %u, args %d, %g x %g at (%g, %g): depth %g, "
                                  "the layout says %g",
                                  kinds[k], a, (double)w, (double)h, (double)x, (double)y,
                                  (double)best, (double)want);
                    }
            }
    printf("  %u probes: %u on openings, %u on frames, %u on sills, %u on the wall\n", probes,
           opening, frame, sill, wall);
    CHECK(opening > 0 && frame > 0 && sill > 0 && wall > 0);
}

/* The first side a ray parallel to axis 0 (x) or 1 (y), in direction dir (+1, -1), meets at
 * (a, b) = (y, z) or (x, z) of a Window's or Door's scope, from its documented layout as solids:
 * the sill box [m, w-m] x [m, fy0] x [0, sd], the frame [m, w-m] x [fy0, h-m] x [0, fd] less the
 * opening, and the opening's reveal from -r to 0 (the hole's sides, seen from inside the wall).
 * NAN: nothing; INFINITY: a case the documentation does not settle, not probed (a door from
 * below in front of the wall plane: its frame bars stand on the ground, open there). */
static float side_hit(const opening_layout *L, int axis, int dir, float a, float b) {
    const float m = L->m, fd = L->fd, r = L->r, sd = L->sd, fy0 = L->fy0;
    if (axis == 0) { /* a = y, b = z */
        const float outer = dir > 0 ? m : L->w - m, inner = dir > 0 ? L->ix0 : L->ix1;
        if (L->window && b > 0.0f && b < sd && a > m && a < fy0) return outer; /* sill side */
        if (b > 0.0f && b < fd && a > fy0 && a < L->h - m) return outer;       /* frame side */
        if (b > -r && b < 0.0f && a > L->iy0 && a < L->iy1) return inner;      /* reveal */
        return NAN;
    }
    /* a = x, b = z */
    const int frame_x = (a > m) && (a < L->w - m), opening_x = (a > L->ix0) && (a < L->ix1);
    if (dir > 0) { /* from below */
        if (!L->window && b > 0.0f) return INFINITY;
        if (!L->window) return b > -r && b < 0.0f && opening_x ? 0.0f : NAN; /* the threshold */
        if (frame_x && b > 0.0f && b < sd) return m;                         /* the sill's bottom */
        if (frame_x && b >= sd && b > 0.0f && b < fd) return fy0; /* the frame's underside */
        if (opening_x && b > -r && b < 0.0f) return L->iy0;       /* the reveal's bottom */
        return NAN;
    }
    if (frame_x && b > 0.0f && b < fd) return L->h - m;                    /* the frame's top */
    if (L->window && frame_x && b >= fd && b > 0.0f && b < sd) return fy0; /* the sill's top */
    if (opening_x && b > -r && b < 0.0f) return L->iy1;                    /* the reveal's top */
    return NAN;
}

/* The first side a ray along axis 0 (x) or 1 (y), in direction dir, meets from the centre of a
 * Window's or Door's opening at (a, b) = (y, z) or (x, z): the frame's and the reveal's inner
 * sides, which the rays from outside never reach. Only points inside the opening (between its
 * sides, from -r to the frame's front) or in front of the frame are probed (INFINITY: a start
 * inside a solid or behind the glass); NAN: nothing. */
static float inside_hit(const opening_layout *L, int axis, int dir, float a, float b) {
    const int in_front = b > L->fd && b > 0.0f, in_hole = b > -L->r && b < L->fd;
    if (!in_front && !in_hole) return INFINITY; /* behind the glass */
    if (axis == 0) {                            /* a = y */
        if (!(a > L->iy0 && a < L->iy1)) return INFINITY;
        return in_hole ? (dir < 0 ? L->ix0 : L->ix1) : NAN;
    }
    if (!(a > L->ix0 && a < L->ix1)) return INFINITY; /* a = x */
    if (dir > 0) return in_hole ? L->iy1 : NAN;
    if (in_hole) return L->window ? L->iy0 : b < 0.0f ? 0.0f : NAN; /* a door's: the ground */
    return L->window && b < L->sd ? L->fy0 : NAN; /* in front: the sill's top beyond the frame */
}

/* A side's coordinate in the scope: the rectangles hold it offset by the block's corner (float,
 * up to ~7 here, ulp 4.8e-7) and the test takes the offset off again: two roundings. */
#define SIDE_ABS 1e-6f

/* Windows and doors seen from the four sides (rays along +-x and +-y at a grid of (y or x, z)):
 * the first side rectangle met is where side_hit puts it, and nothing where it says nothing;
 * then the same from the centre of the opening (inside_hit). */
static void test_window_and_door_sides(void) {
    const uint32_t kinds[2] = {PGT_FACADE_WINDOW, PGT_FACADE_DOOR};
    const float w = 1.6f, h = 2.4f, x0 = 2.0f, y0 = 5.0f;
    pgt_facade_quad q[PGT_FACADE_MAX_QUADS];
    uint32_t probes[2] = {0, 0}, hits[2] = {0, 0};
    for (int inside = 0; inside < 2; ++inside)
        for (int k = 0; k < 2; ++k)
            for (int ai = 0; ai < 2; ++ai) {
                const float *A = opening_args[ai];
                const uint32_t n = pgt_facade_terminal_quads(kinds[k], A, 6, x0, y0, w, h, q);
                const opening_layout L = layout_of(kinds[k], A, w, h);
                const float centre[2] = {0.5f * w, 0.5f * (L.iy0 + L.iy1)}; /* the opening's */
                for (int axis = 0; axis < 2; ++axis)
                    for (int dir = -1; dir <= 1; dir += 2) {
                        const float span = axis == 0 ? h : w, off = axis == 0 ? y0 : x0;
                        const float corner = axis == 0 ? x0 : y0;
                        const float from = inside ? centre[axis] : dir > 0 ? -INFINITY : INFINITY;
                        const uint32_t G = 61;
                        for (uint32_t i = 0; i < G; ++i)
                            for (uint32_t j = 0; j < G; ++j) {
                                const float a = span * ((float)i + 1.0f / 3.0f) / G;
                                const float b = -0.3f + 0.6f * ((float)j + 2.0f / 3.0f) / G;
                                const int near =
                                    near_edge(L.ez, 4, b) ||
                                    (axis == 0 ? near_edge(L.ey, 6, a) : near_edge(L.ex, 4, a));
                                const float want = inside ? inside_hit(&L, axis, dir, a, b)
                                                          : side_hit(&L, axis, dir, a, b);
                                if (near || isinf(want)) continue;
                                float got = NAN; /* the nearest side beyond `from` */
                                for (uint32_t t = 0; t < n; ++t) {
                                    if (q[t].axis != (uint32_t)axis || !(q[t].hi[0] > q[t].lo[0]))
                                        continue;
                                    if (!(q[t].lo[0] <= off + a && off + a <= q[t].hi[0] &&
                                          q[t].lo[1] <= b && b <= q[t].hi[1]))
                                        continue;
                                    const float c = q[t].c - corner;
                                    if ((dir > 0 ? c > from : c < from) &&
                                        (isnan(got) || (dir > 0 ? c < got : c > got)))
                                        got = c;
                                }
                                probes[inside]++, hits[inside] += !isnan(want);
                                CHECK_MSG(isnan(want) ? isnan(got) : fabsf(got - want) <= SIDE_ABS,
                                          "kind %u args %d axis %d dir %d%s at (%g, %g): side %g, "
                                          "the layout says %g",
                                          kinds[k], ai, axis, dir, inside ? " from inside" : "",
                                          (double)a, (double)b, (double)got, (double)want);
                            }
                    }
            }
    printf("  %u side probes, %u meeting a side; %u from inside the opening, %u meeting one\n",
           probes[0], hits[0], probes[1], hits[1]);
    CHECK(hits[0] > probes[0] / 10 && hits[1] > probes[1] / 4);
}

static void make_one(pgt_facade_scene *s, const pgt_grammar *g, float *corners, float *params,
                     pgt_facade_building *b) {
    memset(s, 0, sizeof *s);
    s->grammar_count = 1, s->grammars = g;
    s->building_count = 1, s->buildings = b;
    s->corner_count = 4, s->corners = corners;
    s->param_count = g->param_count, s->params = params;
    memcpy(params, g->param_values, g->param_count * sizeof(float));
    /* 20 x 10 m, counter-clockwise seen from above */
    const float c[8] = {0, 0, 0, 10, 20, 10, 20, 0};
    memcpy(corners, c, sizeof c);
    memset(b, 0, sizeof *b);
    b->corner_count = 4, b->height = 16.0f, b->seed = 3, b->colour = 0xC0B090;
}

/* Float rounding of a hit distance of a few metres (the ray test's t in float: some ulps of 5). */
#define HIT_T_ABS 1e-5f

/* A ray that misses a facade's volume develops nothing; one that enters develops nodes. */
static void test_miss_develops_nothing(void) {
    pgt_grammar g;
    REQUIRE(load(&g, "facade.grammar"));
    float corners[8], params[64];
    pgt_facade_building b;
    pgt_facade_scene s;
    REQUIRE(g.param_count <= 64);
    make_one(&s, &g, corners, params, &b);
    pgt_facade *fa = NULL;
    uint32_t fc = 0;
    pgt_error err = {0};
    REQUIRE(pgt_facade_prepare(&s, &fa, &fc, &err) == PGT_OK);
    REQUIRE(fc == 4);
    /* facade 0 runs from (0,0,0) to (0,0,10): n = (-1, 0, 0) */
    CHECK(fa[0].n[0] == -1.0f && fa[0].t[2] == 1.0f);
    pgt_facade_ray_stats st;
    memset(&st, 0, sizeof st);
    pgt_facade_hit h = {INFINITY, PGT_NONE, 0, 0, 0, 0, {0, 0, 0}, {0, 0, 0}};
    const float o1[3] = {-5.0f, 5.0f, 5.0f}, away[3] = {-1.0f, 0.0f, 0.0f};
    CHECK(pgt_facade_intersect(&s, &fa[0], 0, o1, away, &h, &st) == 0);
    CHECK(st.rays == 1 && st.volume_hits == 0 && st.nodes == 0 && st.terminals == 0);
    const float above[3] = {-5.0f, 30.0f, 5.0f}, par[3] = {0.0f, 0.0f, 1.0f};
    CHECK(pgt_facade_intersect(&s, &fa[0], 0, above, par, &h, &st) == 0);
    CHECK(st.volume_hits == 0 && st.nodes == 0);
    const float towards[3] = {1.0f, 0.0f, 0.0f};
    CHECK(pgt_facade_intersect(&s, &fa[0], 0, o1, towards, &h, &st) == 1);
    CHECK(st.volume_hits == 1 && st.nodes > 0 && st.terminals > 0);
    /* the wall plane is 5 m away; terminals lie within [-recess, protrusion] of it */
    CHECK_MSG(h.facade == 0 && h.kind != PGT_FACADE_MISS &&
                  h.t >= 5.0f - fa[0].protrusion - HIT_T_ABS &&
                  h.t <= 5.0f + fa[0].recess + HIT_T_ABS,
              "hit at t = %g, protrusion %g, recess %g", (double)h.t, (double)fa[0].protrusion,
              (double)fa[0].recess);
    free(fa);
    pgt_grammar_destroy(&g);
}

/* Slack of the coverage test (metres, a 12 x 9 m facade): the polygon's corners are float, the
 * crossing is computed in double from them; 1e-4 m is some hundred ulps of 12. */
#define COVERAGE_ABS 1e-4

/* Every ray from the eye that meets the volume crosses the coverage polygon. */
static void test_coverage_polygon(void) {
    pgt_facade f;
    memset(&f, 0, sizeof f);
    f.t[0] = 1.0f, f.n[2] = 1.0f, f.width = 12.0f, f.height = 9.0f, f.protrusion = 0.5f,
    f.recess = 0.3f;
    f.b[1] = 1.0f, f.scope_w = f.width, f.scope_h = f.height; /* the whole facade */
    uint64_t counter = 0;
    uint32_t tested = 0, crossed = 0;
    for (int e = 0; e < 200; ++e) {
        float eye[3];
        for (int k = 0; k < 3; ++k) eye[k] = -30.0f + 60.0f * pgt_rng_float(2, 0, counter++);
        float q[4][3];
        uint32_t axis;
        if (!pgt_facade_coverage(&f, eye, q, &axis)) continue;
        for (int r = 0; r < 50; ++r) {
            /* a ray towards a random point of the volume */
            float P[3]; /* one draw a statement: an initialiser list's order is unspecified */
            P[0] = 12.0f * pgt_rng_float(2, 1, counter++);
            P[1] = 9.0f * pgt_rng_float(2, 1, counter++);
            P[2] = -0.3f + 0.8f * pgt_rng_float(2, 1, counter++);
            double d[3], lo[3] = {INFINITY, INFINITY, INFINITY},
                         hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int k = 0; k < 3; ++k) d[k] = (double)P[k] - eye[k];
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 3; ++k)
                    lo[k] = fmin(lo[k], q[c][k]), hi[k] = fmax(hi[k], q[c][k]);
            /* facade space = world here: the polygon is the rectangle lo..hi in plane `axis` */
            const double s = (lo[axis] - eye[axis]) / d[axis];
            int in = s > 0.0;
            for (int k = 0; k < 3; ++k) {
                if ((uint32_t)k == axis) continue;
                const double x = eye[k] + s * d[k];
                if (x < lo[k] - COVERAGE_ABS || x > hi[k] + COVERAGE_ABS) in = 0;
            }
            tested++, crossed += (uint32_t)in;
        }
    }
    printf("  coverage: %u rays into the volume, %u cross the polygon\n", tested, crossed);
    CHECK(tested > 1000 && crossed == tested);
    /* an eye inside the volume has no polygon */
    const float inside[3] = {5.0f, 5.0f, 0.1f};
    float q[4][3];
    CHECK(pgt_facade_coverage(&f, inside, q, NULL) == 0);
}

/* The frame is the same bytes for 1 and 2 threads. */
static void test_threads_same_frame(void) {
    pgt_grammar g;
    pgt_facade_scene s;
    pgt_facade *fa = NULL;
    uint32_t fc = 0;
    REQUIRE(city_of("facade_rich.grammar", 16, 3, &g, &s, &fa, &fc));
    pgt_error err = {0};
    pgt_facade_camera cam;
    const float eye[3] = {-20, 30, -20}, at[3] = {60, 0, 60}, up[3] = {0, 1, 0};
    REQUIRE(pgt_facade_camera_init(&cam, eye, at, up, 55, 80, 60, &err) == PGT_OK);
    pgt_facade_frame a, b;
    REQUIRE(pgt_facade_frame_create(&a, 80, 60, &err) == PGT_OK);
    REQUIRE(pgt_facade_frame_create(&b, 80, 60, &err) == PGT_OK);
    const pgt_facade_shading sh = {
        .light = {100.0f, 200.0f, -50.0f}, .ambient = 0.3f, .shadows = 1};
    pgt_facade_render_stats s1, s2;
    CHECK(pgt_facade_render(&s, fa, fc, &cam, &sh, 1, &a, &s1, &err) == PGT_OK);
    CHECK(pgt_facade_render(&s, fa, fc, &cam, &sh, 2, &b, &s2, &err) == PGT_OK);
    const size_t n = 80u * 60u;
    CHECK(memcmp(a.rgb, b.rgb, 3 * n * sizeof(float)) == 0);
    CHECK(memcmp(a.depth, b.depth, n * sizeof(float)) == 0);
    CHECK(memcmp(a.facade, b.facade, n * sizeof(uint32_t)) == 0);
    CHECK(s1.rays.nodes == s2.rays.nodes && s1.rays.errors == 0);
    /* hits only (what pgt bench facade times against Embree): the same rays, development and
     * hits; no colour and no normal written (the frame's are left as they were: NaN here) */
    pgt_facade_frame c;
    REQUIRE(pgt_facade_frame_create(&c, 80, 60, &err) == PGT_OK);
    pgt_facade_shading bare = sh;
    bare.hits_only = 1;
    pgt_facade_render_stats s3;
    for (size_t p = 0; p < 3 * n; ++p) c.rgb[p] = c.normal[p] = NAN;
    CHECK(pgt_facade_render(&s, fa, fc, &cam, &bare, 2, &c, &s3, &err) == PGT_OK);
    CHECK(memcmp(a.depth, c.depth, n * sizeof(float)) == 0);
    CHECK(memcmp(a.facade, c.facade, n * sizeof(uint32_t)) == 0);
    CHECK(memcmp(a.developed, c.developed, n * sizeof(uint32_t)) == 0);
    uint32_t same_hits = 0; /* of a miss, only depth and facade are written */
    for (size_t p = 0; p < n; ++p)
        same_hits +=
            a.facade[p] == PGT_NONE || (a.terminal[p] == c.terminal[p] && a.node[p] == c.node[p] &&
                                        a.surface[p] == c.surface[p]);
    CHECK(same_hits == n);
    CHECK(s3.rays.nodes == s1.rays.nodes && s3.rays.quads == s1.rays.quads);
    uint32_t untouched = 0;
    for (size_t p = 0; p < 3 * n; ++p) untouched += isnan(c.rgb[p]) && isnan(c.normal[p]);
    CHECK(untouched == 3 * n);
    pgt_facade_frame_destroy(&c);
    /* the frame's memo (split layouts, terminal rectangles, rule chains) changes nothing: every
     * pixel's nearest hit over all facades without it, by pgt_facade_intersect, is the same */
    uint32_t same = 0;
    for (uint32_t y = 0; y < 60; ++y)
        for (uint32_t x = 0; x < 80; ++x) {
            float o[3], d[3];
            pgt_facade_camera_ray(&cam, x, y, o, d);
            pgt_facade_hit h = {INFINITY, PGT_NONE, 0, 0, 0, 0, {0, 0, 0}, {0, 0, 0}};
            for (uint32_t fi = 0; fi < fc; ++fi)
                pgt_facade_intersect(&s, &fa[fi], fi, o, d, &h, NULL);
            const size_t p = (size_t)y * 80 + x;
            if (a.terminal[p] == (float)PGT_FACADE_ROOF) { /* roofs are not facades */
                same++;
                continue;
            }
            same += h.facade == a.facade[p] &&
                    (h.facade == PGT_NONE ||
                     (h.t == a.depth[p] && h.node == a.node[p] && h.surface == a.surface[p]));
        }
    CHECK_MSG(same == 80u * 60u, "%u of %u pixels as without the memo", same, 80u * 60u);
    uint32_t hits = 0;
    for (size_t p = 0; p < n; ++p) hits += a.facade[p] != PGT_NONE;
    printf("  %u of %zu pixels hit; %llu nodes for %llu rays into volumes\n", hits, n,
           (unsigned long long)s1.rays.nodes, (unsigned long long)s1.rays.volume_hits);
    CHECK(hits > n / 10);
    pgt_facade_frame_destroy(&a);
    pgt_facade_frame_destroy(&b);
    free(fa);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
}

static float dot3f(const float a[3], const float b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Screen tiles of facade_render.c (TILE): a packet holds rays of one tile. */
#define RENDER_TILE 16u

/* Packets (a tile's rays through one facade developed together: the default) give the frame and
 * the counts of developing every ray alone, to the bit: three grammars (geometry images among
 * them); cameras from the air, along a street, grazing, steep inside the city and straight at a
 * facade from close by (a tile's rays then go both ways along a split's axis: one frame each);
 * shaded with shadows, with LOD (thickness scaled per facade), hits only. */
static void test_packets_same_frame(void) {
    static const char *grammars[] = {"facade.grammar", "facade_rich.grammar",
                                     "facade_gimage.grammar"};
    uint32_t mixed = 0, frames = 0;
    for (size_t gi = 0; gi < sizeof grammars / sizeof grammars[0]; ++gi) {
        pgt_grammar g;
        pgt_facade_scene s;
        pgt_facade *fa = NULL;
        uint32_t fc = 0;
        REQUIRE(city_of(grammars[gi], 9, 11, &g, &s, &fa, &fc));
        pgt_error err = {0};
        const float L = (float)(3 * PGT_GEN_CITY_LOT);
        /* straight at facade 0's middle from 6 m */
        const pgt_facade *f0 = &fa[0];
        float straight[10] = {0, 0, 0, 0, 0, 0, 0, 1, 0, 90}; /* eye, at (the middle), up, fov */
        for (int k = 0; k < 3; ++k) {
            straight[3 + k] =
                f0->origin[k] + 0.5f * f0->width * f0->t[k] + 0.5f * f0->height * f0->b[k];
            straight[k] = straight[3 + k] + 6.0f * f0->n[k];
        }
        /* 88 x 72: the image's middle column and row fall inside a tile */
        const uint32_t W = 88, H = 72;
        pgt_facade_frame fr;
        REQUIRE(pgt_facade_frame_create(&fr, W, H, &err) == PGT_OK);
        for (int ci = 0; ci <= CITY_VIEWS; ++ci) { /* the city's views, then straight on */
            float cv[10];
            if (ci < CITY_VIEWS)
                city_view(L, ci, cv);
            else
                memcpy(cv, straight, sizeof cv);
            pgt_facade_camera cam;
            REQUIRE(pgt_facade_camera_init(&cam, &cv[0], &cv[3], &cv[6], cv[9], W, H, &err) ==
                    PGT_OK);
            for (int mode = 0; mode < 3; ++mode) {
                pgt_facade_shading sh = {
                    .light = {0.5f * L, 3.0f * L, 0.2f * L}, .ambient = 0.3f, .shadows = 1};
                if (mode == 1) { /* every LOD ramp inside the scene: zscale below 1 */
                    sh.detail = PGT_FACADE_DETAIL_LOD;
                    sh.relief_near = 5.0f, sh.relief_far = 10.0f, sh.normal_near = 10.0f;
                    sh.normal_far = 20.0f, sh.thick_near = 5.0f, sh.thick_far = 40.0f;
                }
                sh.hits_only = mode == 2;
                pgt_facade_render_stats ps;
                REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 2, &fr, &ps, &err) == PGT_OK);
                const uint32_t d = packets_differ(&s, fa, fc, &cam, &sh, &fr, &ps);
                CHECK_MSG(d == 0, "%s, camera %d, mode %d: %u channels or counts differ",
                          grammars[gi], ci, mode, d);
                CHECK(ps.rays.errors == 0 && ps.rays.volume_hits > 0);
                frames++;
            }
            /* tiles where rays hitting one facade go both ways along its x or y axis */
            for (uint32_t ty = 0; ty < H; ty += RENDER_TILE)
                for (uint32_t tx = 0; tx < W; tx += RENDER_TILE) {
                    const uint32_t p0 = ty * W + tx, fi = fr.facade[p0];
                    if (fi >= fc) continue;
                    int sign[2][2] = {{0, 0}, {0, 0}};
                    for (uint32_t y = ty; y < ty + RENDER_TILE && y < H; ++y)
                        for (uint32_t x = tx; x < tx + RENDER_TILE && x < W; ++x) {
                            if (fr.facade[y * W + x] != fi) continue;
                            float o[3], dir[3];
                            pgt_facade_camera_ray(&cam, x, y, o, dir);
                            sign[0][dot3f(dir, fa[fi].t) < 0.0f] = 1;
                            sign[1][dot3f(dir, fa[fi].b) < 0.0f] = 1;
                        }
                    mixed += (sign[0][0] && sign[0][1]) || (sign[1][0] && sign[1][1]);
                }
        }
        pgt_facade_frame_destroy(&fr);
        free(fa);
        pgt_facade_scene_destroy(&s);
        pgt_grammar_destroy(&g);
    }
    printf("  %u frames alike; %u tiles whose rays cross a facade both ways\n", frames, mixed);
    CHECK(mixed > 0);
}

static pgt_result compile(pgt_grammar *g, const char *text) {
    pgt_error err = {0};
    return pgt_grammar_compile(g, text, strlen(text), "t.grammar", &err);
}

/* Scenes and grammars a facade cannot use get clear errors. */
static void test_errors(void) {
    pgt_grammar g;
    REQUIRE(load(&g, "facade.grammar"));
    float corners[8], params[64];
    pgt_facade_building b;
    pgt_facade_scene s;
    pgt_error err = {0};
    make_one(&s, &g, corners, params, &b);
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_OK);
    /* reversed footprint: normals into the building */
    const float rev[8] = {0, 0, 20, 0, 20, 10, 0, 10};
    memcpy(corners, rev, sizeof rev);
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err.message, "wrong way") != NULL);
    make_one(&s, &g, corners, params, &b);
    b.corner_count = 2;
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INDEX_RANGE);
    make_one(&s, &g, corners, params, &b);
    b.height = -1.0f;
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
    make_one(&s, &g, corners, params, &b);
    corners[3] = NAN;
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_NOT_FINITE);
    /* footprints that are not simple polygons (the renderer's crossing-number roof and the
     * explicit geometry's ear-clipped one fill different regions): a bow-tie, a corner that
     * folds back along its edge, an edge through a corner */
    const float bow[8] = {0, 0, 20, 10, 20, 0, 0, 10}, fold[8] = {0, 0, 0, 10, 0, 5, 20, 0},
                touch[8] = {0, 0, 20, 0, 20, 10, 10, 0};
    const float *const bad[3] = {bow, fold, touch};
    for (int k = 0; k < 3; ++k) {
        make_one(&s, &g, corners, params, &b);
        memcpy(corners, bad[k], sizeof bow);
        memset(&err, 0, sizeof err);
        CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
        CHECK_MSG(strstr(err.message, "simple polygon") != NULL, "%d: %s", k, err.message);
    }
    /* coordinates beyond what float frames resolve (at 3e38 their arithmetic overflowed) */
    make_one(&s, &g, corners, params, &b);
    corners[1] = 3e38f;
    memset(&err, 0, sizeof err);
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "footprint corner 0") != NULL, "%s", err.message);
    make_one(&s, &g, corners, params, &b);
    b.height = 3e38f;
    memset(&err, 0, sizeof err);
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
    make_one(&s, &g, corners, params, &b);
    b.base = 2e6f;
    memset(&err, 0, sizeof err);
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
    pgt_grammar_destroy(&g);

    /* a grammar without protrusion/recess; one whose terminal sticks out; one with Bark */
    memset(&err, 0, sizeof err); /* pgt_error keeps the first error */
    REQUIRE(compile(&g, "param a = 1\nF --> Wall()\n") == PGT_OK);
    make_one(&s, &g, corners, params, &b);
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "protrusion") != NULL, "%s", err.message);
    pgt_grammar_destroy(&g);
    REQUIRE(compile(&g, "param protrusion = 0.2\nparam recess = 0.1\nF --> split(y) { 3 : L }*\n"
                        "L --> Ledge(0.5)\n") == PGT_OK);
    make_one(&s, &g, corners, params, &b);
    pgt_facade *fa = NULL;
    uint32_t fc = 0;
    REQUIRE(pgt_facade_prepare(&s, &fa, &fc, &err) == PGT_OK);
    pgt_facade_mesh m;
    memset(&err, 0, sizeof err);
    CHECK(pgt_facade_explicit(&s, fa, fc, &m, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "t.grammar:4:7") != NULL, "%s", err.message);
    { /* the explanation a render error gets: the same first error, without geometry */
        pgt_error e2 = {0};
        CHECK(pgt_facade_explain(&s, &fa[0], 0, &e2) == PGT_ERROR_INVALID_ARGUMENT);
        CHECK_MSG(!strcmp(e2.message, err.message), "'%s' against '%s'", e2.message, err.message);
    }
    free(fa);
    pgt_grammar_destroy(&g);
    REQUIRE(compile(&g, "param protrusion = 0.2\nparam recess = 0.1\nF --> Bark(1, C1)\n") ==
            PGT_OK);
    make_one(&s, &g, corners, params, &b);
    REQUIRE(pgt_facade_prepare(&s, &fa, &fc, &err) == PGT_OK);
    memset(&err, 0, sizeof err);
    CHECK(pgt_facade_explicit(&s, fa, fc, &m, &err) == PGT_ERROR_UNSUPPORTED);
    CHECK_MSG(strstr(err.message, "t.grammar:3:7") != NULL, "%s", err.message);
    /* the ray development flags it too */
    pgt_facade_ray_stats st;
    memset(&st, 0, sizeof st);
    pgt_facade_hit h = {INFINITY, PGT_NONE, 0, 0, 0, 0, {0, 0, 0}, {0, 0, 0}};
    const float o[3] = {-5.0f, 5.0f, 5.0f}, d[3] = {1.0f, 0.0f, 0.0f};
    CHECK(pgt_facade_intersect(&s, &fa[0], 0, o, d, &h, &st) == 0);
    CHECK(st.errors & PGT_FACADE_ERR_ITEM);
    free(fa);
    pgt_grammar_destroy(&g);
    /* a rule that calls itself forever */
    REQUIRE(compile(&g, "param protrusion = 0.2\nparam recess = 0.1\nF --> A\nA --> A\n") ==
            PGT_OK);
    make_one(&s, &g, corners, params, &b);
    memset(&err, 0, sizeof err);
    CHECK(pgt_facade_scene_check(&s, "one", &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "t.grammar:4:1: rule A calls itself") != NULL, "%s", err.message);
    REQUIRE(pgt_facade_prepare(&s, &fa, &fc, &err) == PGT_OK);
    memset(&err, 0, sizeof err);
    CHECK(pgt_facade_explicit(&s, fa, fc, &m, &err) == PGT_ERROR_UNSUPPORTED);
    /* the tail call reuses its frame: the path's length stops it, not the stack */
    CHECK_MSG(strstr(err.message, "t.grammar:4:7: building 0 facade 0: a path of the development "
                                  "is longer than PGT_FACADE_NODE_BUDGET") != NULL,
              "%s", err.message);
    memset(&st, 0, sizeof st);
    CHECK(pgt_facade_intersect(&s, &fa[0], 0, o, d, &h, &st) == 0);
    CHECK(st.errors & (PGT_FACADE_ERR_DEPTH | PGT_FACADE_ERR_BUDGET));
    { /* a frame: packets that fail are replayed ray by ray, so the errors are the same */
        pgt_facade_camera fcam;
        const float fe[3] = {10, 8, -30}, fat[3] = {10, 8, 0}, fup[3] = {0, 1, 0};
        REQUIRE(pgt_facade_camera_init(&fcam, fe, fat, fup, 60, 40, 30, &err) == PGT_OK);
        pgt_facade_frame fr;
        REQUIRE(pgt_facade_frame_create(&fr, 40, 30, &err) == PGT_OK);
        const pgt_facade_shading sh = {.light = {10, 50, -30}, .ambient = 0.3f};
        pgt_facade_render_stats ps;
        REQUIRE(pgt_facade_render(&s, fa, fc, &fcam, &sh, 2, &fr, &ps, &err) == PGT_OK);
        CHECK(ps.rays.errors & (PGT_FACADE_ERR_DEPTH | PGT_FACADE_ERR_BUDGET));
        CHECK(ps.rays.volume_hits > 0);
        CHECK(packets_differ(&s, fa, fc, &fcam, &sh, &fr, &ps) == 0);
        pgt_facade_frame_destroy(&fr);
    }
    free(fa);
    pgt_grammar_destroy(&g);
    /* cameras */
    pgt_facade_camera cam;
    const float e[3] = {0, 0, 0}, up[3] = {0, 1, 0}, at[3] = {0, 0, 1};
    CHECK(pgt_facade_camera_init(&cam, e, e, up, 60, 10, 10, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_facade_camera_init(&cam, e, at, up, 180, 10, 10, &err) == PGT_ERROR_INVALID_ARGUMENT);
    const float upz[3] = {0, 0, 5};
    CHECK(pgt_facade_camera_init(&cam, e, at, upz, 60, 10, 10, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(pgt_facade_camera_init(&cam, e, at, up, 60, 0, 10, &err) == PGT_ERROR_INVALID_ARGUMENT);
}

/* One building of a 20 x 10 m footprint whose facades are Wall() only, and its facades. */
static int wall_scene(pgt_grammar *g, pgt_facade_scene *s, float *corners, float *params,
                      pgt_facade_building *b, pgt_facade **fa, uint32_t *fc) {
    static const char text[] = "param protrusion = 0.2\nparam recess = 0.1\nF --> Wall()\n";
    pgt_error err = {0};
    if (pgt_grammar_compile(g, text, sizeof text - 1, "wall.grammar", &err) != PGT_OK) return 0;
    make_one(s, g, corners, params, b);
    return pgt_facade_prepare(s, fa, fc, &err) == PGT_OK;
}

/* The relief search's resolution: RELIEF_LINEAR (24) linear steps then RELIEF_BINARY (6)
 * bisections (facade_shade.c) locate the height field's crossing within 24 x 2^6 = 1536ths of
 * the depth range along the ray. */
#define RELIEF_SEARCH_CELLS 1536.0

/* Float rounding of a depth (t) of the renderer against its double re-derivation: some float
 * epsilons (1.2e-7) of t over the rays' set-up and the plane intersection. */
#define DEPTH_REL 4e-6

/* Relief mapping (6.3): a ray goes on into the relief until it meets the height field; the
 * distance it goes on is checked against a double-precision search (fine sampling then
 * bisection of s |v_z| = D (1 - h(u + s v_u, v + s v_v))) over the same height field. */
static void test_relief_depth(void) {
    pgt_grammar g;
    float corners[8], params[8];
    pgt_facade_building b;
    pgt_facade_scene s;
    pgt_facade *fa = NULL;
    uint32_t fc = 0;
    REQUIRE(wall_scene(&g, &s, corners, params, &b, &fa, &fc));
    /* facade 3 runs from (20, 0) to (20... ): pick the facade facing -z: corner (20,0)->(0,0) */
    uint32_t fi = PGT_NONE;
    for (uint32_t i = 0; i < fc; ++i)
        if (fa[i].n[2] == -1.0f) fi = i;
    REQUIRE(fi != PGT_NONE);
    const pgt_facade *f = &fa[fi];
    const float eye[3] = {10.0f, 4.0f, -3.0f}, at[3] = {9.0f, 4.5f, 0.0f}, up[3] = {0, 1, 0};
    pgt_facade_camera cam;
    pgt_error err = {0};
    REQUIRE(pgt_facade_camera_init(&cam, eye, at, up, 30, 64, 48, &err) == PGT_OK);
    pgt_facade_frame geo, rel;
    REQUIRE(pgt_facade_frame_create(&geo, 64, 48, &err) == PGT_OK);
    REQUIRE(pgt_facade_frame_create(&rel, 64, 48, &err) == PGT_OK);
    pgt_facade_shading sh = {.light = {10.0f, 20.0f, -20.0f}, .ambient = 0.3f};
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 1, &geo, NULL, &err) == PGT_OK);
    sh.detail = PGT_FACADE_DETAIL_RELIEF;
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 1, &rel, NULL, &err) == PGT_OK);
    const double D = pgt_facade_relief_depth(PGT_FACADE_WALL, 0);
    CHECK(D > 0.0);
    uint32_t n = 0, deep = 0;
    double worst = 0.0;
    for (uint32_t y = 0; y < 48; ++y)
        for (uint32_t x = 0; x < 64; ++x) {
            const size_t p = (size_t)y * 64 + x;
            if (geo.facade[p] != fi) continue;
            CHECK(rel.facade[p] == fi && rel.node[p] == geo.node[p]);
            float o[3], d[3];
            pgt_facade_camera_ray(&cam, x, y, o, d);
            /* facade space: x along t, y up, z along n */
            const double vx = (double)d[0] * f->t[0] + (double)d[2] * f->t[2];
            const double vy = d[1], vz = (double)d[0] * f->n[0] + (double)d[2] * f->n[2];
            double px = 0.0, py = 0.0;
            for (int k = 0; k < 3; k += 2)
                px += ((double)o[k] + geo.depth[p] * (double)d[k] - f->origin[k]) * f->t[k];
            py = (double)o[1] + geo.depth[p] * (double)d[1] - f->origin[1];
            const double down = fabs(vz), smax = D / down;
            double s0 = 0.0, s1 = smax;
            int found = 0;
            for (int i = 1; i <= 20000 && !found; ++i) {
                const double sv = smax * i / 20000.0;
                const double hh = pgt_facade_pattern_height(
                    PGT_FACADE_WALL, 0, (float)(px + sv * vx), (float)(py + sv * vy));
                if (sv * down >= D * (1.0 - hh))
                    s1 = sv, found = 1;
                else
                    s0 = sv;
            }
            for (int i = 0; i < 40 && found; ++i) {
                const double sv = 0.5 * (s0 + s1);
                const double hh = pgt_facade_pattern_height(
                    PGT_FACADE_WALL, 0, (float)(px + sv * vx), (float)(py + sv * vy));
                if (sv * down >= D * (1.0 - hh))
                    s1 = sv;
                else
                    s0 = sv;
            }
            const double got = (double)rel.depth[p] - geo.depth[p];
            /* the reference searches in 24 linear steps and 6 bisections: a 1536th of the
             * depth range along the ray, plus float rounding of the two depths */
            const double tol = smax / RELIEF_SEARCH_CELLS + DEPTH_REL * geo.depth[p];
            worst = fmax(worst, fabs(got - s1));
            CHECK_MSG(fabs(got - s1) <= tol, "pixel (%u, %u): relief %.6g, expected %.6g", x, y,
                      got, s1);
            n++, deep += s1 > 0.5 * smax;
        }
    printf("  relief: %u pixels, %u in joints, worst |ds| %.3g m (D = %.3g m)\n", n, deep, worst,
           D);
    CHECK(n > 1000 && deep > 20);
    pgt_facade_frame_destroy(&geo);
    pgt_facade_frame_destroy(&rel);
    free(fa);
    pgt_grammar_destroy(&g);
}

/* LOD level 0 flattens every terminal to this share of the facade's thickness
 * (facade_render.c LOD_ZSCALE_MIN), and its hit's rounding (as DEPTH_REL, halved: one
 * intersection, no relief). */
#define FLAT_THICKNESS 1e-3
#define FLAT_DEPTH_REL 2e-6

/* LOD (sec. 7): level 0 lays every terminal into the wall plane; with the thickness ramp beyond
 * the scene and the detail ramps before the camera, LOD is the geometry level exactly. */
static void test_lod_levels(void) {
    pgt_grammar g;
    pgt_facade_scene s;
    pgt_facade *fa = NULL;
    uint32_t fc = 0;
    REQUIRE(city_of("facade_rich.grammar", 4, 5, &g, &s, &fa, &fc));
    pgt_error err = {0};
    const float eye[3] = {-15, 12, -20}, at[3] = {30, 5, 30}, up[3] = {0, 1, 0};
    pgt_facade_camera cam;
    REQUIRE(pgt_facade_camera_init(&cam, eye, at, up, 50, 96, 64, &err) == PGT_OK);
    pgt_facade_frame geo, lod, flat;
    REQUIRE(pgt_facade_frame_create(&geo, 96, 64, &err) == PGT_OK);
    REQUIRE(pgt_facade_frame_create(&lod, 96, 64, &err) == PGT_OK);
    REQUIRE(pgt_facade_frame_create(&flat, 96, 64, &err) == PGT_OK);
    pgt_facade_shading sh = {.light = {0.0f, 80.0f, -60.0f}, .ambient = 0.3f, .shadows = 1};
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 2, &geo, NULL, &err) == PGT_OK);
    sh.detail = PGT_FACADE_DETAIL_LOD;
    sh.relief_near = 1e-3f, sh.relief_far = 2e-3f, sh.normal_near = 1e-3f, sh.normal_far = 2e-3f;
    sh.thick_near = 1e6f, sh.thick_far = 2e6f;
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 2, &lod, NULL, &err) == PGT_OK);
    const size_t n = 96u * 64u;
    CHECK(memcmp(geo.depth, lod.depth, n * sizeof(float)) == 0);
    CHECK(memcmp(geo.node, lod.node, n * sizeof(uint32_t)) == 0);
    CHECK(memcmp(geo.rgb, lod.rgb, 3 * n * sizeof(float)) == 0);
    sh.detail = PGT_FACADE_DETAIL_FLAT;
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 2, &flat, NULL, &err) == PGT_OK);
    uint32_t hits = 0, differ = 0;
    for (size_t p = 0; p < n; ++p) {
        if (flat.facade[p] == PGT_NONE || flat.facade[p] >= fc) continue; /* sky or a roof */
        const pgt_facade *f = &fa[flat.facade[p]];
        float o[3], d[3];
        pgt_facade_camera_ray(&cam, (uint32_t)(p % 96), (uint32_t)(p / 96), o, d);
        double z = 0.0;
        for (int k = 0; k < 3; ++k)
            z += ((double)o[k] + flat.depth[p] * (double)d[k] - f->origin[k]) * f->n[k];
        /* level 0 keeps a thousandth of the thickness (facade_render.c LOD_ZSCALE_MIN), plus
         * float rounding of the hit */
        CHECK_MSG(fabs(z) <= FLAT_THICKNESS * fmax(f->protrusion, f->recess) +
                                 FLAT_DEPTH_REL * flat.depth[p],
                  "pixel %zu: z %.3g", p, z);
        hits++, differ += flat.node[p] != geo.node[p];
    }
    printf("  flat: %u pixels on facades, %u see another terminal than the geometry level\n", hits,
           differ);
    CHECK(hits > n / 10 && differ > 0);
    pgt_facade_frame_destroy(&geo);
    pgt_facade_frame_destroy(&lod);
    pgt_facade_frame_destroy(&flat);
    free(fa);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
}

/* Relative agreement of the renderer's float32 roof depth with the double-precision one of the
 * roof plane: the float ray-plane intersection rounds to a few float epsilons (1.2e-7) of t,
 * while a roof at a wrong height (the base, 2 m, left out: 9 m for 11) is off by percents. */
#define ROOF_DEPTH_REL 1e-4

/* The roof's triangles have integer corners (exact in float) and their area is summed in
 * double: exact but for a few double ulps of 76. */
#define ROOF_AREA_ABS 1e-9

/* A straight-down ray's hit on the roof 19 m below the eye: float rounding of t (ulp of 19 is
 * 1.9e-6) through the camera's ray set-up; a roof at a wrong height is off by metres. */
#define ROOF_DEPTH_ABS 1e-4f

/* Roofs: an L-shaped (concave) footprint's roof triangles cover exactly its area, lie at base +
 * height, a ray down through the notch of the L misses the roof, and from an eye standing on
 * the roof every ray meeting it inside the L finds it. */
static void test_roof_concave(void) {
    pgt_grammar g;
    float corners[12], params[8];
    pgt_facade_building b;
    pgt_facade_scene s;
    pgt_facade *fa = NULL;
    uint32_t fc = 0;
    float unused[8];
    REQUIRE(wall_scene(&g, &s, unused, params, &b, &fa, &fc));
    free(fa);
    /* an L, counter-clockwise seen from above: (0,0) (0,10) (10,10) (10,4) (4,4) (4,0) */
    const float L[12] = {0, 0, 0, 10, 10, 10, 10, 4, 4, 4, 4, 0};
    memcpy(corners, L, sizeof L);
    s.corners = corners, s.corner_count = 6, b.corner_count = 6, b.base = 2.0f, b.height = 9.0f;
    pgt_error err = {0};
    CHECK_MSG(pgt_facade_scene_check(&s, "L", &err) == PGT_OK, "%s", err.message);
    REQUIRE(pgt_facade_prepare(&s, &fa, &fc, &err) == PGT_OK);
    pgt_facade_mesh m;
    REQUIRE(pgt_facade_explicit(&s, fa, fc, &m, &err) == PGT_OK);
    double area = 0.0;
    uint32_t roofs = 0;
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        if (m.kind[t] != PGT_FACADE_ROOF) continue;
        roofs++;
        const float *P[3];
        for (int k = 0; k < 3; ++k) {
            P[k] = &m.positions[3u * m.indices[3u * t + (uint32_t)k]];
            CHECK(P[k][1] == 11.0f);
        }
        area += fabs(((double)P[1][0] - P[0][0]) * ((double)P[2][2] - P[0][2]) -
                     ((double)P[1][2] - P[0][2]) * ((double)P[2][0] - P[0][0])) /
                2.0;
        CHECK(m.facade[t] == fc + 0u);
    }
    CHECK(roofs == 4);
    CHECK_MSG(fabs(area - 76.0) < ROOF_AREA_ABS, "roof area %.9g, footprint 10 x 10 - 6 x 4 = 76",
              area);
    /* straight down onto the notch (7, 2) and onto the L (2, 7) */
    const float eye[3] = {7.0f, 30.0f, 2.0f}, at[3] = {7.0f, 0.0f, 2.001f}, up[3] = {1, 0, 0};
    pgt_facade_camera cam;
    REQUIRE(pgt_facade_camera_init(&cam, eye, at, up, 1, 1, 1, &err) == PGT_OK);
    pgt_facade_frame fr;
    REQUIRE(pgt_facade_frame_create(&fr, 1, 1, &err) == PGT_OK);
    const pgt_facade_shading sh = {.light = {0.0f, 50.0f, 0.0f}, .ambient = 0.3f};
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 1, &fr, NULL, &err) == PGT_OK);
    CHECK(fr.facade[0] == PGT_NONE);
    const float eye2[3] = {2.0f, 30.0f, 7.0f}, at2[3] = {2.0f, 0.0f, 7.001f};
    REQUIRE(pgt_facade_camera_init(&cam, eye2, at2, up, 1, 1, 1, &err) == PGT_OK);
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 1, &fr, NULL, &err) == PGT_OK);
    CHECK(fr.facade[0] == fc && fr.terminal[0] == (float)PGT_FACADE_ROOF);
    CHECK(fabsf(fr.depth[0] - 19.0f) < ROOF_DEPTH_ABS);
    pgt_facade_frame_destroy(&fr);
    /* standing on the roof, its corners at z = 0 behind the eye (the roof's coverage is the
     * footprint clipped against the near plane): every pixel whose ray meets the roof's plane
     * inside the L shows the roof at that depth, every other pixel something else */
    const uint32_t side = 48;
    const float eye3[3] = {2.0f, 12.7f, 2.0f}, at3[3] = {3.0f, 11.0f, 6.0f}, up3[3] = {0, 1, 0};
    REQUIRE(pgt_facade_camera_init(&cam, eye3, at3, up3, 100, side, side, &err) == PGT_OK);
    REQUIRE(pgt_facade_frame_create(&fr, side, side, &err) == PGT_OK);
    REQUIRE(pgt_facade_render(&s, fa, fc, &cam, &sh, 1, &fr, NULL, &err) == PGT_OK);
    uint32_t on_roof = 0, wrong = 0;
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
            float o[3], d[3];
            pgt_facade_camera_ray(&cam, x, y, o, d);
            const double t = d[1] < 0.0f ? (11.0 - o[1]) / d[1] : -1.0;
            const double px = o[0] + t * d[0], pz = o[2] + t * d[2];
            const int in_l = t > 0.0 && px > 0.0 && px < 10.0 && pz > 0.0 && pz < 10.0 &&
                             !(px > 4.0 && pz < 4.0);
            const size_t i = (size_t)y * side + x;
            const int roof = fr.facade[i] == fc && fr.terminal[i] == (float)PGT_FACADE_ROOF;
            on_roof += in_l;
            wrong += in_l ? !roof || fabs(fr.depth[i] - t) > ROOF_DEPTH_REL * t : roof;
        }
    CHECK_MSG(wrong == 0 && on_roof > side * side / 4u, "%u of %u roof pixels wrong", wrong,
              on_roof);
    pgt_facade_frame_destroy(&fr);
    pgt_facade_mesh_destroy(&m);
    free(fa);
    pgt_grammar_destroy(&g);
}

/* pgt_facade_explicit_limit: a limit of exactly the twin's triangles gives the same twin; one
 * fewer, or fewer than the facades' triangles before the roofs, or 1, or the triangles before
 * the first of a geometry image, fails with
 * PGT_ERROR_LIMIT naming the limit and leaves the mesh empty (the rectangles', the geometry
 * images' and the roofs' checks each met). */
static void test_explicit_limit(void) {
    static const char *const grammars[2] = {"facade.grammar", "facade_gimage.grammar"};
    for (int gi = 0; gi < 2; ++gi) {
        pgt_grammar g;
        pgt_facade_scene s;
        pgt_facade *fa = NULL;
        uint32_t fc = 0;
        REQUIRE(city_of(grammars[gi], 4, 7, &g, &s, &fa, &fc));
        pgt_error err = {0};
        pgt_facade_mesh full, m;
        REQUIRE(pgt_facade_explicit(&s, fa, fc, &full, &err) == PGT_OK);
        const uint32_t n = full.triangle_count;
        uint32_t first_roof = n, first_gimage = n, gimage = 0;
        for (uint32_t t = 0; t < n; ++t) {
            if (full.kind[t] == PGT_FACADE_ROOF && first_roof == n) first_roof = t;
            if (full.kind[t] == PGT_FACADE_MESH && first_gimage == n) first_gimage = t;
            gimage += full.kind[t] == PGT_FACADE_MESH;
        }
        CHECK_MSG(first_roof > 1 && first_roof < n, "%s: roofs from %u of %u", grammars[gi],
                  first_roof, n);
        CHECK_MSG((gi == 1) == (gimage > 0), "%s: %u geometry-image triangles", grammars[gi],
                  gimage);
        REQUIRE(pgt_facade_explicit_limit(&s, fa, fc, n, &m, &err) == PGT_OK);
        CHECK(m.triangle_count == n && m.vertex_count == full.vertex_count);
        if (m.triangle_count == n && m.vertex_count == full.vertex_count) {
            CHECK(!memcmp(m.positions, full.positions, 12u * (size_t)m.vertex_count));
            CHECK(!memcmp(m.indices, full.indices, 12u * (size_t)n));
            CHECK(!memcmp(m.facade, full.facade, 4u * (size_t)n));
            CHECK(!memcmp(m.node, full.node, 4u * (size_t)n));
            CHECK(!memcmp(m.kind, full.kind, 4u * (size_t)n));
            CHECK(!memcmp(m.surface, full.surface, 4u * (size_t)n));
        }
        pgt_facade_mesh_destroy(&m);
        /* the last: the first geometry-image triangle one too many */
        const uint32_t limits[4] = {n - 1u, first_roof - 1u, 1u, first_gimage};
        for (int k = 0; k < (gimage ? 4 : 3); ++k) {
            char want[64];
            snprintf(want, sizeof want, "more than %u triangles", limits[k]);
            pgt_error_clear(&err);
            CHECK(pgt_facade_explicit_limit(&s, fa, fc, limits[k], &m, &err) == PGT_ERROR_LIMIT);
            CHECK_MSG(strstr(err.message, want) != NULL, "%s, limit %u: %s", grammars[gi],
                      limits[k], err.message);
            CHECK(m.triangle_count == 0 && m.vertex_count == 0 && !m.positions && !m.indices);
            pgt_facade_mesh_destroy(&m);
        }
        if (gimage) { /* the scene check verifies each image's recorded z range */
            pgt_error_clear(&err);
            CHECK(pgt_facade_scene_check(&s, "city", &err) == PGT_OK);
            const float zlo = s.gimages[0].zlo;
            s.gimages[0].zlo = zlo - 0.01f;
            CHECK(pgt_facade_scene_check(&s, "city", &err) == PGT_ERROR_INVALID_ARGUMENT);
            CHECK_MSG(strstr(err.message, "z range") != NULL, "%s", err.message);
            s.gimages[0].zlo = zlo;
        }
        pgt_facade_mesh_destroy(&full);
        free(fa);
        pgt_facade_scene_destroy(&s);
        pgt_grammar_destroy(&g);
    }
}

static const pgt_test_case cases[] = {
    {"terminals_in_scope", test_terminals_in_scope},
    {"window_and_door_depths", test_window_and_door_depths},
    {"window_and_door_sides", test_window_and_door_sides},
    {"miss_develops_nothing", test_miss_develops_nothing},
    {"coverage_polygon", test_coverage_polygon},
    {"paper_grammar_vs_explicit", test_paper_grammar_vs_explicit},
    {"rich_grammar_vs_explicit", test_rich_grammar_vs_explicit},
    {"gimage_grammar_vs_explicit", test_gimage_grammar_vs_explicit},
    {"threads_same_frame", test_threads_same_frame},
    {"packets_same_frame", test_packets_same_frame},
    {"errors", test_errors},
    {"relief_depth", test_relief_depth},
    {"lod_levels", test_lod_levels},
    {"roof_concave", test_roof_concave},
    {"explicit_limit", test_explicit_limit},
};

PGT_TEST_MAIN(cases)
