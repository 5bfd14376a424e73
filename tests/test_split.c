/* Tests of the split layout (split.h; paper 003 sections 3 and 6.1, issue 6 item 1): every worked
 * example of CityEngine's "Subdivision split" help page (scopes of length 5 and 10), the facade
 * grammar of paper 003 section 3 with numbers, sizes that do not fit, zero and negative sizes,
 * relative, floating and repeated parts, repeats that fit zero times; then a property test:
 * random layouts laid out, queried by index and by coordinate, all agreeing.
 *
 * Every expected interval below is a literal worked out by hand in the comment above it. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/rng.h>
#include <pgt/split.h>

#include "test_util.h"

/* Hand-computed decimals vs float32: the literals (1.45, 10/3, ...) are not exact in binary and
 * each boundary is a few float operations on values <= 13, each rounding by <= 0.5 ulp (<= 4.8e-7
 * at 13): 1e-5 is ~20 ulps there and far below the narrowest interval in these tests (0.1). */
#define HAND_TOL 1e-5f
/* The long repeat: a boundary is one multiply and one add from exact, so within 2 ulps of the
 * coordinate; at up to 1000 an ulp is 6.1e-5. */
#define DRIFT_TOL (2.0 * 6.103515625e-5)

#define A(s)                                                                                       \
    { PGT_SPLIT_ABSOLUTE, (s) }
#define R(s)                                                                                       \
    { PGT_SPLIT_RELATIVE, (s) }
#define F(s)                                                                                       \
    { PGT_SPLIT_FLOATING, (s) }
#define COUNT(a) ((uint32_t)(sizeof(a) / sizeof((a)[0])))

/* An expected child: interval, part, repetition. */
typedef struct want {
    float start, end;
    uint32_t part, rep;
} want;

static int same_child(const pgt_split_child *a, const pgt_split_child *b) {
    return a->start == b->start && a->end == b->end && a->part == b->part &&
           a->repetition == b->repetition;
}

/* Lays the split out and checks it against the hand-computed children, and checks that the
 * count, pgt_split_child_get and pgt_split_child_at (inside every child, at both of its ends in
 * both directions) agree with the layout. */
static void check_split(const char *what, const pgt_split_part *parts, uint32_t part_count,
                        uint32_t group_first, uint32_t group_count, float length,
                        const want *expect, uint32_t expect_count) {
    pgt_split_child got[64];
    pgt_split_slot slots[16];
    pgt_split_plan plan;
    if (part_count > 16 || expect_count > 64) {
        CHECK_MSG(0, "%s: test too big", what);
        return;
    }
    const uint32_t n =
        pgt_split_layout(got, 64, parts, part_count, group_first, group_count, length);
    CHECK_MSG(n == expect_count, "%s: %u children, expected %u", what, n, expect_count);
    CHECK(pgt_split_count(parts, part_count, group_first, group_count, length) == n);
    pgt_split_build(&plan, slots, parts, part_count, group_first, group_count, length);
    CHECK(plan.child_count == n);
    for (uint32_t k = 0; k < n && k < expect_count; ++k) {
        const want *w = &expect[k];
        CHECK_MSG(fabsf(got[k].start - w->start) <= HAND_TOL &&
                      fabsf(got[k].end - w->end) <= HAND_TOL && got[k].part == w->part &&
                      got[k].repetition == w->rep,
                  "%s: child %u is [%.7g, %.7g) part %u rep %u, expected [%.7g, %.7g) part %u "
                  "rep %u",
                  what, k, got[k].start, got[k].end, got[k].part, got[k].repetition, w->start,
                  w->end, w->part, w->rep);
        pgt_split_child c;
        CHECK_MSG(pgt_split_child_get(&plan, slots, k, &c) == k && same_child(&c, &got[k]),
                  "%s: child_get(%u) differs from the layout", what, k);
        const float mid = 0.5f * (got[k].start + got[k].end);
        CHECK_MSG(pgt_split_child_at(&plan, slots, mid, 1, &c) == k && same_child(&c, &got[k]),
                  "%s: child_at(%g) is not child %u", what, mid, k);
        CHECK_MSG(pgt_split_child_at(&plan, slots, got[k].start, 1, &c) == k,
                  "%s: child_at(start of %u, +1)", what, k);
        CHECK_MSG(pgt_split_child_at(&plan, slots, got[k].end, -1, &c) == k,
                  "%s: child_at(end of %u, -1)", what, k);
    }
    if (n <= 64) { /* pgt_split_flat_at on the layout answers as pgt_split_child_at */
        float fs[64], fe[64];
        pgt_split_child cc;
        for (uint32_t k = 0; k < n; ++k) fs[k] = got[k].start, fe[k] = got[k].end;
        const float probes[] = {-0.001f, 0.0f, 0.5f * length, length, length + 0.001f, NAN};
        for (int dir = -1; dir <= 1; dir += 2) {
            for (uint32_t k = 0; k < n; ++k)
                for (int e = 0; e < 3; ++e) {
                    const float t = e == 0 ? fs[k] : (e == 1 ? fe[k] : 0.5f * (fs[k] + fe[k]));
                    CHECK_MSG(pgt_split_flat_at(fs, fe, n, t, dir) ==
                                  pgt_split_child_at(&plan, slots, t, dir, &cc),
                              "%s: flat_at(%g, %d) differs from child_at", what, t, dir);
                }
            for (uint32_t i = 0; i < COUNT(probes); ++i)
                CHECK_MSG(pgt_split_flat_at(fs, fe, n, probes[i], dir) ==
                              pgt_split_child_at(&plan, slots, probes[i], dir, &cc),
                          "%s: flat_at(%g, %d) differs from child_at", what, probes[i], dir);
        }
    }
    pgt_split_child c;
    CHECK(pgt_split_child_get(&plan, slots, n, &c) == PGT_NONE);
    CHECK(pgt_split_child_at(&plan, slots, -0.001f, 1, &c) == PGT_NONE);
    CHECK(pgt_split_child_at(&plan, slots, length, 1, &c) == PGT_NONE);
    CHECK(pgt_split_child_at(&plan, slots, length + 0.001f, -1, &c) == PGT_NONE);
    CHECK(pgt_split_child_at(&plan, slots, NAN, 1, &c) == PGT_NONE);
}

#define CHECK_SPLIT(parts, group_first, group_count, length, ...)                                  \
    do {                                                                                           \
        const want expect_[] = {__VA_ARGS__};                                                      \
        check_split(#parts, parts, COUNT(parts), group_first, group_count, length, expect_,        \
                    COUNT(expect_));                                                               \
    } while (0)
#define CHECK_EMPTY(parts, group_first, group_count, length)                                       \
    check_split(#parts, parts, COUNT(parts), group_first, group_count, length, NULL, 0)

/* ---- CityEngine's "Subdivision split" help page, scope of length 5 ---- */

static void test_ce_absolute(void) {
    /* split(x){ 3 : Blue } cuts the 5-long cube at 3: Blue = [0, 3), [3, 5) has no child. */
    const pgt_split_part one[] = {A(3)};
    CHECK_SPLIT(one, 0, 0, 5.0f, {0, 3, 0, 0});
    /* split(x){ 3 : Green | 1 : Blue }: 3 + 1 = 4, [4, 5) has no child. */
    const pgt_split_part two[] = {A(3), A(1)};
    CHECK_SPLIT(two, 0, 0, 5.0f, {0, 3, 0, 0}, {3, 4, 1, 0});
    pgt_split_plan plan;
    pgt_split_slot slots[2];
    pgt_split_child c;
    pgt_split_build(&plan, slots, two, 2, 0, 0, 5.0f);
    CHECK(pgt_split_child_at(&plan, slots, 4.5f, 1, &c) == PGT_NONE);
}

static void test_ce_absolute_limited(void) {
    /* split(x){ 2 : Green | 1 : Green | 1 : Blue | 2 : Yellow | 1 : Blue } on 5: the running
     * ends are 2, 3, 4, 6 -> 5 (Yellow gets 1 instead of 2), and the last Blue is not made. */
    const pgt_split_part p[] = {A(2), A(1), A(1), A(2), A(1)};
    CHECK_SPLIT(p, 0, 0, 5.0f, {0, 2, 0, 0}, {2, 3, 1, 0}, {3, 4, 2, 0}, {4, 5, 3, 0});
}

static void test_ce_negative_zero(void) {
    /* split(x){ 1.5 : Green | -2 : Yellow | 1.5 : Blue | 1.5 : Green | 0 : Yellow | 1.5 : Green }
     * on 5: no Yellow; Blue starts at 1.5; the last Green stops at 5: ends 1.5, 3, 4.5, 6 -> 5. */
    const pgt_split_part p[] = {A(1.5f), A(-2), A(1.5f), A(1.5f), A(0), A(1.5f)};
    CHECK_SPLIT(p, 0, 0, 5.0f, {0, 1.5f, 0, 0}, {1.5f, 3, 2, 0}, {3, 4.5f, 3, 0}, {4.5f, 5, 5, 0});
}

static void test_ce_relative_golden(void) {
    /* split(x){ '0.382 : A | '0.618 : B } on 5: only relative parts, so R = 5 (as CityEngine's
     * '0.382 * scope): A = 1.91, B = 3.09. */
    const pgt_split_part p[] = {R(0.382f), R(0.618f)};
    CHECK_SPLIT(p, 0, 0, 5.0f, {0, 1.91f, 0, 0}, {1.91f, 5, 1, 0});
    /* The recursion: A --> split(x){ '0.382 : A | '0.618 : C } on A's 1.91: 0.382 * 1.91 =
     * 0.72962; B --> split(x){ '0.382 : B | '0.618 : D } on 3.09: 0.382 * 3.09 = 1.18038. */
    CHECK_SPLIT(p, 0, 0, 1.91f, {0, 0.72962f, 0, 0}, {0.72962f, 1.91f, 1, 0});
    CHECK_SPLIT(p, 0, 0, 3.09f, {0, 1.18038f, 0, 0}, {1.18038f, 3.09f, 1, 0});
}

static void test_ce_floating(void) {
    /* split(x){ 3 : Green | ~1 : Blue } on 5: Blue floats over the 5 - 3 = 2 left. */
    const pgt_split_part fill[] = {A(3), F(1)};
    CHECK_SPLIT(fill, 0, 0, 5.0f, {0, 3, 0, 0}, {3, 5, 1, 0});
    /* split(x){ 1 : Blue | ~2 : Yellow | 1 : Blue }: Yellow fills the 3 between the Blues. */
    const pgt_split_part between[] = {A(1), F(2), A(1)};
    CHECK_SPLIT(between, 0, 0, 5.0f, {0, 1, 0, 0}, {1, 4, 1, 0}, {4, 5, 2, 0});
    /* Several floating parts of 1.5 share the 2 left evenly (the page's picture, our rule
     * text): split(x){ 1.5 : Blue | ~1.5 : Yellow | ~1.5 : Yellow | 1.5 : Blue }: 5 - 3 = 2,
     * each ~1.5 scaled by 2 / 3 to 1: ends 1.5, 2.5, 3.5, 5. */
    const pgt_split_part shared[] = {A(1.5f), F(1.5f), F(1.5f), A(1.5f)};
    CHECK_SPLIT(shared, 0, 0, 5.0f, {0, 1.5f, 0, 0}, {1.5f, 2.5f, 1, 0}, {2.5f, 3.5f, 2, 0},
                {3.5f, 5, 3, 0});
    /* Three floating parts share evenly: split(x){ ~1 | ~1 | ~1 } on 5: 5 / 3 = 1.6666667. */
    const pgt_split_part three[] = {F(1), F(1), F(1)};
    CHECK_SPLIT(three, 0, 0, 5.0f, {0, 1.6666667f, 0, 0}, {1.6666667f, 3.3333333f, 1, 0},
                {3.3333333f, 5, 2, 0});
    /* No room left for a floating part: it is not made (Blue): split(x){ 3 : Green | ~1 : Blue
     * | 2 : Green }: 3 + 2 = 5 leaves 0 for Blue. */
    const pgt_split_part none[] = {A(3), F(1), A(2)};
    CHECK_SPLIT(none, 0, 0, 5.0f, {0, 3, 0, 0}, {3, 5, 2, 0});
}

/* ---- the repeat examples, scope of length 10 ---- */

static void test_ce_repeat(void) {
    /* split(x){ 2 : Green }*: exactly 5 cubes of 2 fit in 10. */
    const pgt_split_part abs2[] = {A(2)};
    CHECK_SPLIT(abs2, 0, 1, 10.0f, {0, 2, 0, 0}, {2, 4, 0, 1}, {4, 6, 0, 2}, {6, 8, 0, 3},
                {8, 10, 0, 4});
    /* split(x){ ~2.1 : Green }*: 10 / 2.1 = 4.76 rounds to 5 (4 would stretch each to 2.5,
     * 0.4 from 2.1; 5 gives 2, 0.1 from it): the same 5 cubes of 2. */
    const pgt_split_part float21[] = {F(2.1f)};
    CHECK_SPLIT(float21, 0, 1, 10.0f, {0, 2, 0, 0}, {2, 4, 0, 1}, {4, 6, 0, 2}, {6, 8, 0, 3},
                {8, 10, 0, 4});
}

/* ---- paper 003 section 3: floorHeight 3, doorWidth 2, windowWidth 1.5, facade 10.7 x 13 ---- */

static void test_paper_facade(void) {
    /* F --> split(y){ floorHeight : GF | { ~floorHeight : FL }* } on 13: 13 - 3 = 10 left for
     * the floors, 10 / 3 = 3.33 -> 3 floors of 10 / 3 = 3.3333333: GF [0, 3), FL [3, 6.3333333),
     * [6.3333333, 9.6666667), [9.6666667, 13). */
    const pgt_split_part f[] = {A(3), F(3)};
    CHECK_SPLIT(f, 1, 1, 13.0f, {0, 3, 0, 0}, {3, 6.3333333f, 1, 0}, {6.3333333f, 9.6666667f, 1, 1},
                {9.6666667f, 13, 1, 2});
    /* GF --> split(y){ 0.5 : Lf | floorHeight - 0.5 : G } on GF's 3: [0, 0.5), [0.5, 3). */
    const pgt_split_part gf[] = {A(0.5f), A(3.0f - 0.5f)};
    CHECK_SPLIT(gf, 0, 0, 3.0f, {0, 0.5f, 0, 0}, {0.5f, 3, 1, 0});
    /* G --> split(x){ doorWidth : Df | { ~windowWidth : Wf }* } on 10.7: 8.7 left, 8.7 / 1.5 =
     * 5.8 -> 6 windows of 8.7 / 6 = 1.45: door [0, 2), windows from 2 every 1.45 to 10.7. */
    const pgt_split_part g[] = {A(2), F(1.5f)};
    CHECK_SPLIT(g, 1, 1, 10.7f, {0, 2, 0, 0}, {2, 3.45f, 1, 0}, {3.45f, 4.9f, 1, 1},
                {4.9f, 6.35f, 1, 2}, {6.35f, 7.8f, 1, 3}, {7.8f, 9.25f, 1, 4},
                {9.25f, 10.7f, 1, 5});
    /* FL --> split(x){ ~windowWidth : Wf }* on 10.7: 10.7 / 1.5 = 7.13 -> 7 windows of 10.7 / 7
     * = 1.5285714: ends 1.5285714, 3.0571429, 4.5857143, 6.1142857, 7.6428571, 9.1714286, 10.7. */
    const pgt_split_part fl[] = {F(1.5f)};
    CHECK_SPLIT(fl, 0, 1, 10.7f, {0, 1.5285714f, 0, 0}, {1.5285714f, 3.0571429f, 0, 1},
                {3.0571429f, 4.5857143f, 0, 2}, {4.5857143f, 6.1142857f, 0, 3},
                {6.1142857f, 7.6428571f, 0, 4}, {7.6428571f, 9.1714286f, 0, 5},
                {9.1714286f, 10.7f, 0, 6});
}

/* getSplitIndex twice, as Algorithm 1 develops the facade at the point (x, y) = (5, 8) of the
 * 10.7 x 13 facade: F's child at y = 8 is the second floor FL (child 2, [6.3333333, 9.6666667)),
 * FL's child at x = 5 is its fourth window (child 3, [4.5857143, 6.1142857): 5 / 1.5285714 =
 * 3.27). Nothing else is laid out. */
static void test_paper_facade_point(void) {
    const pgt_split_part f[] = {A(3), F(3)}, fl[] = {F(1.5f)};
    pgt_split_plan fp, flp;
    pgt_split_slot fs[2], fls[1];
    pgt_split_child c;
    pgt_split_build(&fp, fs, f, 2, 1, 1, 13.0f);
    REQUIRE(pgt_split_child_at(&fp, fs, 8.0f, 1, &c) == 2);
    CHECK(c.part == 1 && c.repetition == 1 && fabsf(c.start - 6.3333333f) <= HAND_TOL &&
          fabsf(c.end - 9.6666667f) <= HAND_TOL);
    pgt_split_build(&flp, fls, fl, 1, 0, 1, 10.7f);
    REQUIRE(pgt_split_child_at(&flp, fls, 5.0f, 1, &c) == 3);
    CHECK(c.part == 0 && c.repetition == 3 && fabsf(c.start - 4.5857143f) <= HAND_TOL &&
          fabsf(c.end - 6.1142857f) <= HAND_TOL);
}

/* Algorithm 1 enters the facade on a face of its box: at y = 13 a ray going down is in the top
 * floor, at y = 3 a ray going up is in the first floor and one going down in the ground floor. */
static void test_child_at_direction(void) {
    const pgt_split_part f[] = {A(3), F(3)};
    pgt_split_plan plan;
    pgt_split_slot slots[2];
    pgt_split_child c;
    pgt_split_build(&plan, slots, f, 2, 1, 1, 13.0f);
    CHECK(pgt_split_child_at(&plan, slots, 13.0f, -1, &c) == 3 && c.part == 1 &&
          c.repetition == 2 && c.end == 13.0f);
    CHECK(pgt_split_child_at(&plan, slots, 13.0f, 1, &c) == PGT_NONE);
    CHECK(pgt_split_child_at(&plan, slots, 3.0f, 1, &c) == 1 && c.part == 1 && c.start == 3.0f);
    CHECK(pgt_split_child_at(&plan, slots, 3.0f, -1, &c) == 0 && c.part == 0 && c.end == 3.0f);
    CHECK(pgt_split_child_at(&plan, slots, 0.0f, 1, &c) == 0);
    CHECK(pgt_split_child_at(&plan, slots, 0.0f, -1, &c) == PGT_NONE);
    /* Stepping like Algorithm 1: index + 1 from the ground floor reaches each floor in turn and
     * each child starts where the previous ended. */
    float at = 0.0f;
    for (uint32_t k = 0; k < plan.child_count; ++k) {
        CHECK(pgt_split_child_get(&plan, slots, k, &c) == k && c.start == at);
        at = c.end;
    }
    CHECK(at == 13.0f);
}

/* ---- sizes that do not fit, zero and negative sizes ---- */

static void test_not_fit(void) {
    /* split(x){ 4 : A | 4 : B } on 5: B is cut to [4, 5). */
    const pgt_split_part two[] = {A(4), A(4)};
    CHECK_SPLIT(two, 0, 0, 5.0f, {0, 4, 0, 0}, {4, 5, 1, 0});
    /* split(x){ 6 : A | 1 : B } on 5: A is cut to [0, 5), B is not made. */
    const pgt_split_part over[] = {A(6), A(1)};
    CHECK_SPLIT(over, 0, 0, 5.0f, {0, 5, 0, 0});
    /* split(x){ 3 : A | ~1 : B | 3 : C } on 5: no room for B, C cut to [3, 5). */
    const pgt_split_part fl[] = {A(3), F(1), A(3)};
    CHECK_SPLIT(fl, 0, 0, 5.0f, {0, 3, 0, 0}, {3, 5, 2, 0});
}

static void test_zero_negative_all_kinds(void) {
    /* split(x){ '0 | ~0 | -1 | 2 | ~-3 | '-1 } on 5: only the 2 makes a child; no floating part
     * is left to fill, so [2, 5) is empty. */
    const pgt_split_part p[] = {R(0), F(0), A(-1), A(2), F(-3), R(-1)};
    CHECK_SPLIT(p, 0, 0, 5.0f, {0, 2, 3, 0});
    /* Non-finite sizes make no child either (the evaluator never returns them; defence). */
    const pgt_split_part odd[] = {A(INFINITY), F(NAN), A(1)};
    CHECK_SPLIT(odd, 0, 0, 5.0f, {0, 1, 2, 0});
}

/* ---- relative and floating parts ---- */

static void test_relative(void) {
    /* split(x){ '0.3 : A } on 10: A = 0.3 * 10 = 3; [3, 10) is empty. */
    const pgt_split_part single[] = {R(0.3f)};
    CHECK_SPLIT(single, 0, 0, 10.0f, {0, 3, 0, 0});
    /* split(x){ 2 : A | '0.25 : B | '0.75 : C } on 10 (CityEngine: a relative size is r times
     * the scope's length): B = 2.5, C = 7.5 cut at 10: A [0, 2), B [2, 4.5), C [4.5, 10). */
    const pgt_split_part with_abs[] = {A(2), R(0.25f), R(0.75f)};
    CHECK_SPLIT(with_abs, 0, 0, 10.0f, {0, 2, 0, 0}, {2, 4.5f, 1, 0}, {4.5f, 10, 2, 0});
    /* split(x){ ~2 : A | '0.5 : B | 1 : C } on 10: B = 5, C = 1, the floating part fills the
     * 10 - 5 - 1 = 4 left: A [0, 4), B [4, 9), C [9, 10). */
    const pgt_split_part with_float[] = {F(2), R(0.5f), A(1)};
    CHECK_SPLIT(with_float, 0, 0, 10.0f, {0, 4, 0, 0}, {4, 9, 1, 0}, {9, 10, 2, 0});
    /* split(x){ 4 : A | '1 : B | 7 : C } on 10: B = 10 from 4 is cut at 10; C does not fit. */
    const pgt_split_part no_room[] = {A(4), R(1), A(7)};
    CHECK_SPLIT(no_room, 0, 0, 10.0f, {0, 4, 0, 0}, {4, 10, 1, 0});
}

static void test_floating_only(void) {
    /* split(x){ ~1 : A | ~3 : B } on 10: scaled by 10 / 4 = 2.5: A [0, 2.5), B [2.5, 10). */
    const pgt_split_part p[] = {F(1), F(3)};
    CHECK_SPLIT(p, 0, 0, 10.0f, {0, 2.5f, 0, 0}, {2.5f, 10, 1, 0});
    /* Shrunk too: split(x){ ~4 : A | 1 : B | ~4 : C } on 5: 4 left for 8 nominal, x 0.5. */
    const pgt_split_part shrink[] = {F(4), A(1), F(4)};
    CHECK_SPLIT(shrink, 0, 0, 5.0f, {0, 2, 0, 0}, {2, 3, 1, 0}, {3, 5, 2, 0});
}

/* ---- repeat groups ---- */

static void test_repeat_absolute(void) {
    /* split(x){ 3 : A }* on 10: floor(10 / 3) = 3, [9, 10) is empty. */
    const pgt_split_part whole[] = {A(3)};
    CHECK_SPLIT(whole, 0, 1, 10.0f, {0, 3, 0, 0}, {3, 6, 0, 1}, {6, 9, 0, 2});
    /* split(x){ 1 : A | { 3 : B }* | 1 : C } on 10: 8 left, floor(8 / 3) = 2: A [0, 1), B [1, 4),
     * [4, 7), C right after the group [7, 8); [8, 10) empty. */
    const pgt_split_part inside[] = {A(1), A(3), A(1)};
    CHECK_SPLIT(inside, 1, 1, 10.0f, {0, 1, 0, 0}, {1, 4, 1, 0}, {4, 7, 1, 1}, {7, 8, 2, 0});
    /* split(x){ { 1 : A | 2 : B }* } on 7: the group is 3 long, floor(7 / 3) = 2: ends 1, 3, 4, 6.
     */
    const pgt_split_part pair[] = {A(1), A(2)};
    CHECK_SPLIT(pair, 0, 2, 7.0f, {0, 1, 0, 0}, {1, 3, 1, 0}, {3, 4, 0, 1}, {4, 6, 1, 1});
    /* Decimals: split(x){ 0.3 : A }* on 0.9: 0.9f / 0.3f is 2.9999998 in float32, but three
     * fit within PGT_SPLIT_FIT_TOL (the last clipped to 0.9): [0, 0.3), [0.3, 0.6), [0.6, 0.9). */
    const pgt_split_part tenths[] = {A(0.3f)};
    CHECK_SPLIT(tenths, 0, 1, 0.9f, {0, 0.3f, 0, 0}, {0.3f, 0.6f, 0, 1}, {0.6f, 0.9f, 0, 2});
}

static void test_repeat_floating(void) {
    /* split(x){ ~3 : A }* on 10: 10 / 3 = 3.33 -> 3 of 3.3333333. */
    const pgt_split_part p[] = {F(3)};
    CHECK_SPLIT(p, 0, 1, 10.0f, {0, 3.3333333f, 0, 0}, {3.3333333f, 6.6666667f, 0, 1},
                {6.6666667f, 10, 0, 2});
    /* split(x){ ~3 : A }* on 10.5: 3.5 -> rounds to 4 of 2.625. */
    CHECK_SPLIT(p, 0, 1, 10.5f, {0, 2.625f, 0, 0}, {2.625f, 5.25f, 0, 1}, {5.25f, 7.875f, 0, 2},
                {7.875f, 10.5f, 0, 3});
    /* A group too long for the scope still repeats once, shrunk: split(x){ ~3 : A }* on 1. */
    CHECK_SPLIT(p, 0, 1, 1.0f, {0, 1, 0, 0});
}

static void test_repeat_mixed(void) {
    /* split(x){ 1 : A | ~2 : B }* on 10: the group is 3 long, 10 / 3 = 3.33 -> 3 repetitions of
     * 10 / 3; B = 10 / 3 - 1 = 2.3333333: ends 1, 3.3333333, 4.3333333, 6.6666667, 7.6666667, 10.
     */
    const pgt_split_part p[] = {A(1), F(2)};
    CHECK_SPLIT(p, 0, 2, 10.0f, {0, 1, 0, 0}, {1, 3.3333333f, 1, 0}, {3.3333333f, 4.3333333f, 0, 1},
                {4.3333333f, 6.6666667f, 1, 1}, {6.6666667f, 7.6666667f, 0, 2},
                {7.6666667f, 10, 1, 2});
    /* Quoins around bays: split(x){ 0.5 : Q | { ~2 : Bay }* | 0.5 : Q } on 9.1: 8.1 left, 4.05
     * -> 4 bays of 2.025: ends 0.5, 2.525, 4.55, 6.575, 8.6, 9.1. */
    const pgt_split_part bays[] = {A(0.5f), F(2), A(0.5f)};
    CHECK_SPLIT(bays, 1, 1, 9.1f, {0, 0.5f, 0, 0}, {0.5f, 2.525f, 1, 0}, {2.525f, 4.55f, 1, 1},
                {4.55f, 6.575f, 1, 2}, {6.575f, 8.6f, 1, 3}, {8.6f, 9.1f, 2, 0});
    /* ... on 7.3: 6.3 left, 3.15 -> 3 bays of 2.1: ends 0.5, 2.6, 4.7, 6.8, 7.3. */
    CHECK_SPLIT(bays, 1, 1, 7.3f, {0, 0.5f, 0, 0}, {0.5f, 2.6f, 1, 0}, {2.6f, 4.7f, 1, 1},
                {4.7f, 6.8f, 1, 2}, {6.8f, 7.3f, 2, 0});
    /* Floating parts outside a group keep their size: split(x){ ~1 : A | { 2 : B }* } on 9:
     * A = 1, 8 left, 4 B of 2: ends 1, 3, 5, 7, 9. */
    const pgt_split_part outside[] = {F(1), A(2)};
    CHECK_SPLIT(outside, 1, 1, 9.0f, {0, 1, 0, 0}, {1, 3, 1, 0}, {3, 5, 1, 1}, {5, 7, 1, 2},
                {7, 9, 1, 3});
    /* The group's absolute parts bound the count: split(x){ { 2 : A | ~1 : B }* } on 5: 5 / 3
     * rounds to 2, and 2 x 2 = 4 fits: period 2.5, B = 0.5: ends 2, 2.5, 4.5, 5. */
    const pgt_split_part bound[] = {A(2), F(1)};
    CHECK_SPLIT(bound, 0, 2, 5.0f, {0, 2, 0, 0}, {2, 2.5f, 1, 0}, {2.5f, 4.5f, 0, 1},
                {4.5f, 5, 1, 1});
    /* ... on 5.9: 5.9 / 3 = 1.97 rounds to 2, period 2.95, B = 0.95; on 3.9: 1.3 rounds to 1,
     * A = 2, B = 1.9. */
    CHECK_SPLIT(bound, 0, 2, 5.9f, {0, 2, 0, 0}, {2, 2.95f, 1, 0}, {2.95f, 4.95f, 0, 1},
                {4.95f, 5.9f, 1, 1});
    CHECK_SPLIT(bound, 0, 2, 3.9f, {0, 2, 0, 0}, {2, 3.9f, 1, 0});
}

static void test_repeat_zero(void) {
    /* split(x){ 8 : A | { 3 : B }* } on 10: 2 left, floor(2 / 3) = 0: only A. */
    const pgt_split_part abs_group[] = {A(8), A(3)};
    CHECK_SPLIT(abs_group, 1, 1, 10.0f, {0, 8, 0, 0});
    /* split(x){ 8 : A | { 3 : B | ~1 : C }* } on 10: 2 left; round(2 / 4) would give 1, but B
     * alone (3) does not fit in 2: zero repetitions. */
    const pgt_split_part mixed_group[] = {A(8), A(3), F(1)};
    CHECK_SPLIT(mixed_group, 1, 2, 10.0f, {0, 8, 0, 0});
    /* split(x){ 12 : A | { ~1 : B }* } on 10: A is cut to 10, nothing left for the group. */
    const pgt_split_part none_left[] = {A(12), F(1)};
    CHECK_SPLIT(none_left, 1, 1, 10.0f, {0, 10, 0, 0});
    /* A suffix still comes after an empty group: split(x){ { 4 : A }* | 1 : B } on 3: 2 left,
     * no A; B [0, 1). */
    const pgt_split_part suffix[] = {A(4), A(1)};
    CHECK_SPLIT(suffix, 0, 1, 3.0f, {0, 1, 1, 0});
    pgt_split_plan plan;
    pgt_split_build(&plan, NULL, suffix, 2, 0, 1, 3.0f);
    CHECK(plan.repetitions == 0 && plan.child_count == 1);
}

static void test_nothing_fits(void) {
    const pgt_split_part p[] = {A(1), F(1)};
    const float lengths[] = {0.0f, -1.0f, NAN, INFINITY};
    for (uint32_t k = 0; k < 4; ++k) {
        CHECK_EMPTY(p, 0, 0, lengths[k]);
        CHECK_EMPTY(p, 0, 2, lengths[k]);
    }
    CHECK(pgt_split_count(NULL, 0, 0, 0, 10.0f) == 0);
    CHECK(pgt_split_layout(NULL, 0, p, 2, 0, 0, 5.0f) == 2);
}

/* A million repetitions: each boundary is group_start + i * period, so child i starts within a
 * couple of ulps of the exact i * 1000 / 10^6 whatever i (accumulating 10^6 periods would drift
 * by hundreds of ulps). Nothing is materialised. */
static void test_long_repeat_no_drift(void) {
    const pgt_split_part p[] = {F(0.001f)};
    pgt_split_plan plan;
    pgt_split_slot slot;
    pgt_split_child c;
    pgt_split_build(&plan, &slot, p, 1, 0, 1, 1000.0f);
    REQUIRE(plan.child_count == 1000000 && plan.repetitions == 1000000 && plan.flags == 0);
    const float w = 1000.0f / 1e6f;
    for (uint32_t k = 0; k < 1000000; k += 997) {
        REQUIRE(pgt_split_child_get(&plan, &slot, k, &c) == k);
        CHECK_MSG(fabs((double)c.start - (double)k * (double)w) <= DRIFT_TOL, "child %u at %.9g", k,
                  c.start);
        pgt_split_child d;
        CHECK(pgt_split_child_at(&plan, &slot, c.start, 1, &d) == k && same_child(&c, &d));
        CHECK(c.end > c.start);
    }
    CHECK(pgt_split_child_get(&plan, &slot, 999999, &c) == 999999 && c.end == 1000.0f);
}

/* More repetitions than PGT_SPLIT_MAX_CHILDREN: cut to the cap and flagged; an absolute group
 * then leaves the rest empty. */
static void test_capped(void) {
    const pgt_split_part p[] = {A(1e-6f)};
    pgt_split_plan plan;
    pgt_split_slot slot;
    pgt_split_child c;
    pgt_split_build(&plan, &slot, p, 1, 0, 1, 100.0f);
    CHECK(plan.child_count == PGT_SPLIT_MAX_CHILDREN && (plan.flags & PGT_SPLIT_CAPPED));
    CHECK(pgt_split_child_at(&plan, &slot, 50.0f, 1, &c) == PGT_NONE);
    CHECK(pgt_split_child_at(&plan, &slot, 1.0f, 1, &c) != PGT_NONE && c.start <= 1.0f &&
          1.0f < c.end);
    const pgt_split_part two[] = {A(1e-6f), F(1e-6f)};
    pgt_split_slot slots[2];
    pgt_split_build(&plan, slots, two, 2, 0, 2, 100.0f);
    CHECK(plan.child_count == PGT_SPLIT_MAX_CHILDREN && (plan.flags & PGT_SPLIT_CAPPED));
    CHECK(pgt_split_child_get(&plan, slots, plan.child_count - 1, &c) != PGT_NONE &&
          c.end == 100.0f);
}

/* ---- property test ---- */

typedef struct rng {
    uint32_t seed;
    uint64_t counter;
} rng;

static float uniform(rng *r, float lo, float hi) {
    return lo + (hi - lo) * pgt_rng_float(r->seed, 0, r->counter++);
}

static uint32_t below(rng *r, uint32_t n) { return (uint32_t)(uniform(r, 0.0f, 1.0f) * n) % n; }

/* The child holding t in a materialised layout by binary search on the ends (children are
 * ordered and do not overlap, checked before): direction >= 0 the first end > t, < 0 the first
 * end >= t, then the start decides. */
static uint32_t brute_child_at(const pgt_split_child *c, uint32_t n, float t, int direction) {
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (direction >= 0 ? c[mid].end > t : c[mid].end >= t)
            hi = mid;
        else
            lo = mid + 1;
    }
    if (lo == n) return PGT_NONE;
    return (direction >= 0 ? c[lo].start <= t : c[lo].start < t) ? lo : PGT_NONE;
}

/* pgt_split_child_at and pgt_split_flat_at (on the layout's starts and ends in fs, fe) against
 * brute_child_at. */
static void check_query(const pgt_split_plan *plan, const pgt_split_slot *slots,
                        const pgt_split_child *c, const float *fs, const float *fe, uint32_t n,
                        float t, uint32_t trial) {
    for (int dir = -1; dir <= 1; dir += 2) {
        pgt_split_child got;
        const uint32_t want_k = brute_child_at(c, n, t, dir);
        const uint32_t k = pgt_split_child_at(plan, slots, t, dir, &got);
        CHECK_MSG(k == want_k, "trial %u: child_at(%.9g, %d) = %u, the layout says %u", trial, t,
                  dir, k, want_k);
        const uint32_t kf = pgt_split_flat_at(fs, fe, n, t, dir);
        CHECK_MSG(kf == want_k, "trial %u: flat_at(%.9g, %d) = %u, the layout says %u", trial, t,
                  dir, kf, want_k);
        if (k == want_k && k != PGT_NONE)
            CHECK_MSG(same_child(&got, &c[k]), "trial %u: child_at(%.9g) fields", trial, t);
    }
}

static void test_property_random_layouts(void) {
    rng r = {20240611u, 0};
    enum { TRIALS = 6000, MAX_PARTS = 8 };
    uint32_t max_children = 0, with_group = 0, empty = 0, skipped = 0;
    for (uint32_t trial = 0; trial < TRIALS; ++trial) {
        pgt_split_part parts[MAX_PARTS];
        pgt_split_slot slots[MAX_PARTS];
        const uint32_t count = 1 + below(&r, MAX_PARTS);
        for (uint32_t k = 0; k < count; ++k) {
            const float u = uniform(&r, 0.0f, 1.0f);
            parts[k].kind = u < 0.45f  ? PGT_SPLIT_ABSOLUTE
                            : u < 0.8f ? PGT_SPLIT_FLOATING
                                       : PGT_SPLIT_RELATIVE;
            const float v = uniform(&r, 0.0f, 1.0f);
            if (parts[k].kind == PGT_SPLIT_RELATIVE)
                parts[k].size = v < 0.1f ? uniform(&r, -0.5f, 0.0f) : uniform(&r, 0.0f, 1.2f);
            else
                parts[k].size = v < 0.1f   ? uniform(&r, -2.0f, 0.0f)
                                : v < 0.2f ? uniform(&r, 0.002f, 0.05f)
                                           : uniform(&r, 0.05f, 6.0f);
        }
        uint32_t gf = 0, gc = 0;
        if (uniform(&r, 0.0f, 1.0f) < 0.6f) {
            gf = below(&r, count);
            gc = 1 + below(&r, count - gf);
            with_group++;
        }
        const float lw = uniform(&r, 0.0f, 1.0f);
        /* Mostly facade-sized scopes; a quarter long ones, where repetition bases far from 0
         * round coarsely (an ulp at 3000 is 2.4e-4). */
        const float length = lw < 0.03f   ? uniform(&r, -1.0f, 0.0f)
                             : lw < 0.25f ? uniform(&r, 50.0f, 3000.0f)
                                          : uniform(&r, 0.01f, 60.0f);

        pgt_split_plan plan;
        pgt_split_build(&plan, slots, parts, count, gf, gc, length);
        const uint32_t n = pgt_split_count(parts, count, gf, gc, length);
        CHECK(plan.child_count == n);
        if (n > 300000) { /* tiny parts on a long scope: long_repeat_no_drift covers those */
            skipped++;
            continue;
        }
        if (n > max_children) max_children = n;
        empty += n == 0;
        pgt_split_child *c = malloc(((size_t)n + 1) * sizeof(*c));
        REQUIRE(c);
        c[n].part = 0xABCDu; /* sentinel: layout must not write past the count */
        CHECK(pgt_split_layout(c, n, parts, count, gf, gc, length) == n && c[n].part == 0xABCDu);

        /* Intervals ordered, non-overlapping, inside [0, L]; parts in order. */
        for (uint32_t k = 0; k < n; ++k) {
            CHECK_MSG(c[k].start <= c[k].end && c[k].start >= 0.0f && c[k].end <= length,
                      "trial %u: child %u [%.9g, %.9g) outside [0, %.9g]", trial, k, c[k].start,
                      c[k].end, length);
            CHECK(c[k].part < count);
            if (gc == 0 || c[k].part < gf || c[k].part >= gf + gc) CHECK(c[k].repetition == 0);
            if (k > 0) {
                CHECK_MSG(c[k - 1].end <= c[k].start, "trial %u: children %u and %u overlap", trial,
                          k - 1, k);
                CHECK(c[k - 1].part < c[k].part || c[k - 1].repetition < c[k].repetition);
            }
            pgt_split_child g;
            CHECK_MSG(pgt_split_child_get(&plan, slots, k, &g) == k && same_child(&g, &c[k]),
                      "trial %u: child_get(%u) differs from the layout", trial, k);
        }
        /* A layout meant to fill (floating parts with room, no relative part, no group) ends at
         * L exactly. */
        int has_rel = 0, has_float = 0;
        float abs_sum = 0.0f;
        for (uint32_t k = 0; k < count; ++k) {
            if (!(parts[k].size > 0.0f)) continue;
            has_rel |= parts[k].kind == PGT_SPLIT_RELATIVE;
            has_float |= parts[k].kind == PGT_SPLIT_FLOATING;
            if (parts[k].kind == PGT_SPLIT_ABSOLUTE) abs_sum += parts[k].size;
        }
        if (gc == 0 && !has_rel && has_float && length > 0.0f &&
            abs_sum < length * (1.0f - 1e-3f) && n > 0)
            CHECK_MSG(c[n - 1].end == length, "trial %u: a filling layout ends at %.9g of %.9g",
                      trial, c[n - 1].end, length);

        /* A shorter buffer gets the first children, the same bits. */
        if (n > 1) {
            pgt_split_child *half = malloc((n / 2) * sizeof(*half));
            REQUIRE(half);
            CHECK(pgt_split_layout(half, n / 2, parts, count, gf, gc, length) == n);
            CHECK(memcmp(half, c, (n / 2) * sizeof(*half)) == 0);
            free(half);
        }

        /* child_at against the layout: random coordinates, then every child's ends and the
         * floats just beside them (at most 64 children, spread over the layout). */
        float *fs = malloc(2u * ((size_t)n + 1u) * sizeof *fs), *fe = fs ? fs + n + 1u : NULL;
        REQUIRE(fs);
        for (uint32_t k = 0; k < n; ++k) fs[k] = c[k].start, fe[k] = c[k].end;
        const float span = length > 0.0f ? length : 1.0f;
        for (uint32_t s = 0; s < 64; ++s)
            check_query(&plan, slots, c, fs, fe, n, uniform(&r, -0.05f * span, 1.05f * span),
                        trial);
        check_query(&plan, slots, c, fs, fe, n, NAN, trial);
        const uint32_t step = n > 64 ? n / 64 : 1;
        for (uint32_t k = 0; k < n; k += step) {
            const float ends[2] = {c[k].start, c[k].end};
            for (int e = 0; e < 2; ++e) {
                check_query(&plan, slots, c, fs, fe, n, ends[e], trial);
                check_query(&plan, slots, c, fs, fe, n, nextafterf(ends[e], -INFINITY), trial);
                check_query(&plan, slots, c, fs, fe, n, nextafterf(ends[e], INFINITY), trial);
            }
        }
        free(fs);
        free(c);
    }
    printf("  %u random splits (%u with a repeat group, %u empty, %u too big to materialise), up "
           "to %u children\n",
           TRIALS, with_group, empty, skipped, max_children);
}

static const pgt_test_case cases[] = {
    {"ce_absolute", test_ce_absolute},
    {"ce_absolute_limited", test_ce_absolute_limited},
    {"ce_negative_zero", test_ce_negative_zero},
    {"ce_relative_golden", test_ce_relative_golden},
    {"ce_floating", test_ce_floating},
    {"ce_repeat", test_ce_repeat},
    {"paper_facade", test_paper_facade},
    {"paper_facade_point", test_paper_facade_point},
    {"child_at_direction", test_child_at_direction},
    {"not_fit", test_not_fit},
    {"zero_negative_all_kinds", test_zero_negative_all_kinds},
    {"relative", test_relative},
    {"floating_only", test_floating_only},
    {"repeat_absolute", test_repeat_absolute},
    {"repeat_floating", test_repeat_floating},
    {"repeat_mixed", test_repeat_mixed},
    {"repeat_zero", test_repeat_zero},
    {"nothing_fits", test_nothing_fits},
    {"long_repeat_no_drift", test_long_repeat_no_drift},
    {"capped", test_capped},
    {"property_random_layouts", test_property_random_layouts},
};

PGT_TEST_MAIN(cases)
