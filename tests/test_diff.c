/* Tests of the diff's own measures (harness/diff.c): ULP distances with known answers, and that
 * a float comparison finds, counts and locates what it must. The backends' agreement itself is
 * the diff_cl / diff_vk tests. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "diff.h"
#include "gen.h"
#include "pgt/atlas_build.h"
#include "test_util.h"

static float from_bits(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Neighbouring floats are 1 apart; the distance counts every float in between, across 0 too. */
static void ulp_known_answers(void) {
    CHECK(pgt_ulp_distance(1.0f, 1.0f) == 0);
    CHECK(pgt_ulp_distance(1.0f, nextafterf(1.0f, 2.0f)) == 1);
    CHECK(pgt_ulp_distance(nextafterf(1.0f, 2.0f), 1.0f) == 1);
    CHECK(pgt_ulp_distance(1.0f, 2.0f) == (1u << 23)); /* one binade: 2^23 floats */
    CHECK(pgt_ulp_distance(0.0f, -0.0f) == 0);
    const float tiny = from_bits(1u); /* smallest denormal */
    CHECK(pgt_ulp_distance(tiny, -tiny) == 2);
    CHECK(pgt_ulp_distance(-1.0f, 1.0f) == 2ull * 0x3F800000u);
    CHECK(pgt_ulp_distance(FLT_MAX, INFINITY) == 1);
    CHECK(pgt_ulp_distance(NAN, 1.0f) == UINT64_MAX);
}

/* Both floats lie in [64, 128), so their difference (40 ulp of 2^-17) is exact in double and
 * the diff's max_abs must equal it; the bound is 8 orders of magnitude below that difference. */
#define MAX_ABS_TOL 1e-12

/* Equal arrays: nothing outside. One element 3 ulp off and one 40 ulp off: max_ulp 40 at that
 * element; with a 16-ulp bound exactly one element is outside, unless the absolute floor
 * covers it. */
static void floats_find_the_worst(void) {
    float ref[6] = {1.0f, -2.5f, 1e-30f, 3.0f, 100.0f, 0.0f}, got[6];
    memcpy(got, ref, sizeof got);
    pgt_diff_floats d;
    pgt_diff_floats_run(&d, ref, got, 6, 16, 0.0);
    CHECK(d.count == 6 && d.outside == 0 && d.max_ulp == 0 && d.max_abs == 0.0);
    uint32_t u;
    memcpy(&u, &ref[1], sizeof u);
    got[1] = from_bits(u + 3);
    memcpy(&u, &ref[4], sizeof u);
    got[4] = from_bits(u - 40);
    pgt_diff_floats_run(&d, ref, got, 6, 16, 0.0);
    CHECK(d.max_ulp == 40 && d.worst == 4 && d.worst_ref == ref[4] && d.worst_got == got[4]);
    CHECK(d.outside == 1);
    CHECK(fabs(d.max_abs - ((double)ref[4] - (double)got[4])) < MAX_ABS_TOL);
    /* an absolute floor above the error forgives it */
    pgt_diff_floats_run(&d, ref, got, 6, 16, 1e-3);
    CHECK(d.outside == 0 && d.max_ulp == 40);
    /* NaN is always outside */
    got[2] = NAN;
    pgt_diff_floats_run(&d, ref, got, 6, 16, 1e30);
    CHECK(d.outside == 1 && d.max_ulp == UINT64_MAX && d.worst == 2);
}

/* The table has the sqrt(3) entry the diff uses, with a reason. */
static void tolerance_table_entries(void) {
    const pgt_tolerance *t = pgt_tolerance_find("sqrt3", "positions");
    REQUIRE(t != NULL);
    CHECK(t->max_ulp > 0 && t->max_abs_rel > 0.0 && t->why && strlen(t->why) > 20);
    CHECK(pgt_tolerance_find("sqrt3", "nothing") == NULL);
    const pgt_tolerance *m = pgt_tolerance_find("march", "state");
    REQUIRE(m != NULL);
    CHECK(m->max_ulp > 0 && m->max_abs_rel > 0.0 && m->why && strlen(m->why) > 20);
    /* the entry's bounds hold for k <= 3 and grow, never shrink, with each further iteration */
    uint32_t ulp = 0, prev_ulp = 0;
    double rel = 0.0, prev_rel = 0.0;
    for (uint32_t k = 0; k <= PGT_SQRT3_MAX_ITERATIONS; ++k) {
        pgt_tolerance_sqrt3_bounds(t, k, &ulp, &rel);
        if (k <= 3u)
            CHECK(ulp == t->max_ulp && rel == t->max_abs_rel);
        else
            CHECK_MSG(ulp > prev_ulp && rel > prev_rel, "k = %u: bounds do not grow", k);
        prev_ulp = ulp, prev_rel = rel;
    }
}

/* The reference against itself through the diff: every case equal. */
static void reference_against_itself(void) {
    pgt_backend cpu;
    REQUIRE(pgt_backend_open(&cpu, PGT_BACKEND_CPU, 0, 0, NULL) == PGT_OK);
    pgt_mesh m;
    REQUIRE(pgt_cli_load_named("hemisphere_jagged_12x32", ".", &m, NULL) == PGT_OK);
    for (uint32_t k = 1; k <= 3; ++k) {
        pgt_diff_sqrt3 d;
        REQUIRE(pgt_diff_sqrt3_run(&cpu, &m, k, NULL, &d, NULL) == PGT_OK);
        CHECK(d.pass && d.positions.max_ulp == 0 && d.triangles == 0 && d.opposite == 0);
        CHECK(d.ref_faces == d.got_faces && d.ref_faces == m.face_count * 27u /
                                                               (k == 3   ? 1
                                                                : k == 2 ? 3
                                                                         : 9));
    }
    pgt_mesh_destroy(&m);
    pgt_backend_close(&cpu);
}

/* One sqrt(3) output (k = 2, a quarter protected) with its per-face arrays, into o. */
static int reference_output(const pgt_mesh *m, pgt_diff_sqrt3_output *o) {
    memset(o, 0, sizeof *o);
    uint32_t vb = 0, fb = 0;
    if (pgt_sqrt3_bound(m->vertex_count, m->face_count, 0, 2, &vb, &fb, NULL) != PGT_OK) return 0;
    uint8_t *prot = calloc(m->face_count, 1);
    o->opp = malloc(3u * (size_t)fb * sizeof(uint32_t));
    o->parent = malloc((size_t)fb * sizeof(uint32_t));
    o->prot = malloc(fb);
    if (!prot || !o->opp || !o->parent || !o->prot) return free(prot), 0;
    for (uint32_t f = 0; f < m->face_count; f += 4) prot[f] = 1;
    pgt_sqrt3_options opt = {2, 1, prot, o->prot, o->parent, o->opp, NULL};
    const int ok = pgt_sqrt3_subdivide(&o->out, m, &opt, NULL) == PGT_OK;
    free(prot);
    return ok;
}

static int copy_output(const pgt_diff_sqrt3_output *a, pgt_diff_sqrt3_output *b) {
    memset(b, 0, sizeof *b);
    const size_t F = a->out.face_count;
    b->opp = malloc(3u * F * sizeof(uint32_t)), b->parent = malloc(F * sizeof(uint32_t));
    b->prot = malloc(F);
    if (!b->opp || !b->parent || !b->prot || pgt_mesh_copy(&b->out, &a->out, NULL) != PGT_OK)
        return 0;
    memcpy(b->opp, a->opp, 3u * F * sizeof(uint32_t));
    memcpy(b->parent, a->parent, F * sizeof(uint32_t));
    memcpy(b->prot, a->prot, F);
    return 1;
}

static void free_output(pgt_diff_sqrt3_output *o) {
    pgt_mesh_destroy(&o->out);
    free(o->opp), free(o->parent), free(o->prot);
}

/* Every output the diff compares, changed in one element, fails the case and is counted where
 * it belongs (a diff that skipped one array would pass these): a triangle's corner, an
 * adjacency entry, a parent, a protected flag, a position beyond the tolerance, a NaN, a
 * vertex count, and a face label. The generated hemisphere has no labels, so the input gets
 * one per face (its index mod 5) and the subdivision carries them to its output. */
static void compare_catches_each_output(void) {
    pgt_mesh m;
    REQUIRE(pgt_cli_load_named("hemisphere_jagged_12x32", ".", &m, NULL) == PGT_OK);
    REQUIRE(m.labels == NULL);
    m.labels = malloc((size_t)m.face_count * sizeof(int32_t));
    REQUIRE(m.labels != NULL);
    for (uint32_t f = 0; f < m.face_count; ++f) m.labels[f] = (int32_t)(f % 5u);
    pgt_diff_sqrt3_output ref, got;
    REQUIRE(reference_output(&m, &ref));
    REQUIRE(ref.out.labels != NULL);
    pgt_diff_sqrt3 d;
    for (int kind = -1; kind < 8; ++kind) {
        REQUIRE(copy_output(&ref, &got));
        const uint32_t t = got.out.face_count / 2u, v = got.out.vertex_count / 2u;
        switch (kind) {
        case 0:
            got.out.indices[3u * t + 1u] = got.out.indices[3u * t + 2u];
            break;
        case 1:
            got.opp[3u * t] ^= 1u;
            break;
        case 2:
            got.parent[t] += 1u;
            break;
        case 3:
            got.prot[t] = (uint8_t)!got.prot[t];
            break;
        case 4:
            got.out.positions[3u * v] += 1e-3f;
            break; /* ~1e-3 of the unit hemisphere */
        case 5:
            got.out.positions[3u * v + 1u] = NAN;
            break;
        case 6:
            got.out.vertex_count -= 1u;
            break;
        case 7:
            got.out.labels[t] ^= 1;
            break;
        default:
            break; /* -1: the copy itself */
        }
        memset(&d, 0, sizeof d);
        pgt_diff_sqrt3_compare(&d, &ref, &got);
        const uint64_t counts[8] = {d.triangles,
                                    d.opposite,
                                    d.parents,
                                    d.protected_flags,
                                    d.positions.outside,
                                    d.positions.outside,
                                    d.ref_vertices != d.got_vertices,
                                    d.labels};
        CHECK_MSG(d.pass == (kind < 0), "kind %d: pass %d", kind, d.pass);
        for (int k = 0; k < 8; ++k)
            CHECK_MSG(counts[k] ==
                          (uint64_t)(k == kind || (kind == 4 && k == 5) || (kind == 5 && k == 4)),
                      "kind %d: count %d is %llu", kind, k, (unsigned long long)counts[k]);
        if (kind == 0) CHECK(d.first_triangle == t);
        free_output(&got);
    }
    free_output(&ref);
    pgt_mesh_destroy(&m);
}

/* The march comparison: the cpu backend's records of walkers on the cube-sphere's 6-chart atlas,
 * compared with themselves (equal), then with one record (a walker's last) changed in each way
 * a backend could differ: a position 2 ulp off (within the 16-ulp tolerance), one 1000 ulp off,
 * a direction NaN (a record the reference cannot start from), another chart, another no-bounce
 * texel, another event word, an event word of no event; and a record in the middle zeroed. Each
 * is counted where it must be, the first discrete mismatch located. */
#define MARCH_WALKERS 64u
#define MARCH_STEPS 40u
static void march_compare_catches_each_output(void) {
    pgt_mesh m = {0};
    pgt_image img = {0};
    pgt_error err = {0};
    REQUIRE(pgt_gen_cube_sphere(&m, 8, &err) == PGT_OK);
    pgt_atlas_options ao = {0};
    ao.width = ao.height = 128;
    REQUIRE(pgt_atlas_build(&img, &m, &ao, NULL, &err) == PGT_OK);
    pgt_march_atlas a;
    REQUIRE(pgt_march_atlas_create(&a, &img, "cube-sphere", &err) == PGT_OK);
    pgt_backend cpu;
    REQUIRE(pgt_backend_open(&cpu, PGT_BACKEND_CPU, 0, 0, &err) == PGT_OK);
    float x[4 * MARCH_WALKERS];
    uint32_t chart[MARCH_WALKERS];
    REQUIRE(pgt_march_random_starts(&a, 7, MARCH_WALKERS, x, x + MARCH_WALKERS,
                                    x + 2 * MARCH_WALKERS, x + 3 * MARCH_WALKERS, chart) == 0);
    static pgt_march_state start[MARCH_WALKERS], s[MARCH_WALKERS];
    static pgt_march_state rec[MARCH_WALKERS * MARCH_STEPS], got[MARCH_WALKERS * MARCH_STEPS];
    static uint32_t ev[MARCH_WALKERS * MARCH_STEPS], got_ev[MARCH_WALKERS * MARCH_STEPS];
    for (uint32_t i = 0; i < MARCH_WALKERS; ++i) {
        const pgt_march_state t = {x[i],
                                   x[MARCH_WALKERS + i],
                                   x[2 * MARCH_WALKERS + i],
                                   x[3 * MARCH_WALKERS + i],
                                   chart[i],
                                   0u,
                                   0.0f,
                                   0.0f,
                                   0u};
        start[i] = s[i] = t;
    }
    const float length = 3.0f;
    REQUIRE(pgt_backend_march(&cpu, &a, NULL, length, MARCH_STEPS, MARCH_WALKERS, s, rec, ev, NULL,
                              NULL, &err) == PGT_OK);
    /* the last record of a walker that jumped before it (its no-bounce memory is set) and did
     * not stop: no step is re-run from it, so what is changed there is the only difference */
    uint32_t jr = UINT32_MAX;
    for (uint32_t w = 0; w < MARCH_WALKERS && jr == UINT32_MAX; ++w) {
        const uint32_t r = w * MARCH_STEPS + MARCH_STEPS - 1u;
        if (rec[r].from != 0u && PGT_MARCH_EVENT_OF(ev[r]) != PGT_MARCH_STOP) jr = r;
    }
    REQUIRE(jr != UINT32_MAX);
    const uint32_t jw = jr / MARCH_STEPS, js = jr % MARCH_STEPS, mid = MARCH_STEPS / 2u;
    pgt_diff_march d;
    uint64_t all_steps = 0;
    for (int kind = -1; kind < 8; ++kind) {
        memcpy(got, rec, sizeof got);
        memcpy(got_ev, ev, sizeof got_ev);
        pgt_march_state *g = &got[jr];
        switch (kind) {
        case 0:
            g->x = nextafterf(nextafterf(g->x, INFINITY), INFINITY);
            break;
        case 1: {
            uint32_t u;
            memcpy(&u, &g->y, sizeof u);
            u += 1000u;
            memcpy(&g->y, &u, sizeof u);
            break;
        }
        case 2:
            g->dx = NAN;
            break;
        case 3:
            g->chart ^= 1u;
            break;
        case 4:
            g->from += 1u;
            break;
        case 5:
            got_ev[jr] ^= 1u; /* a jump reported as a search, or the other way */
            break;
        case 6:
            got_ev[jr] = 0x200F8u; /* no such event (lavapipe's loop limit gave such words) */
            break;
        case 7: /* a zeroed record in the middle of the walk (on background): the reference cannot
                   re-run the next step from it, so the walker's comparison ends there */
            memset(&got[jw * MARCH_STEPS + mid], 0, sizeof(got[0]));
            break;
        default:
            break;
        }
        memset(&d, 0, sizeof d);
        REQUIRE(pgt_diff_march_compare(&d, &a, NULL, length, MARCH_STEPS, MARCH_WALKERS, start, got,
                                       got_ev, &err) == PGT_OK);
        CHECK_MSG(d.pass == (kind <= 0), "kind %d: pass %d", kind, d.pass);
        CHECK(d.steps > MARCH_WALKERS * (MARCH_STEPS / 2u) && d.crossings > 0);
        if (kind < 0) all_steps = d.steps;
        /* a record the reference cannot start from (a NaN direction, another chart: off its
         * inner texels, no such event, zeroed) ends its walker's comparison: it and the records
         * after it are not counted */
        const int invalid = kind == 2 || kind == 3 || kind >= 6;
        const uint32_t at_step = kind == 7 ? mid : js;
        CHECK_MSG(d.steps == (invalid ? all_steps - (MARCH_STEPS - at_step) : all_steps),
                  "kind %d: %llu steps of %llu", kind, (unsigned long long)d.steps,
                  (unsigned long long)all_steps);
        /* a NaN direction (2) is a record the reference cannot start from: discrete */
        const uint64_t outside = kind == 1 ? 1u : 0u;
        CHECK_MSG(d.state.outside == outside, "kind %d: %llu outside", kind,
                  (unsigned long long)d.state.outside);
        if (kind == 0) CHECK(d.state.max_ulp == 2u);
        const uint64_t discrete = kind >= 2 ? 1u : 0u;
        CHECK_MSG(d.discrete == discrete, "kind %d: %llu discrete", kind,
                  (unsigned long long)d.discrete);
        if (discrete) CHECK(d.first_walker == jw && d.first_step == at_step);
    }
    pgt_backend_close(&cpu);
    pgt_march_atlas_destroy(&a);
    pgt_image_destroy(&img);
    pgt_mesh_destroy(&m);
}

static const pgt_test_case cases[] = {
    {"ulp_known_answers", ulp_known_answers},
    {"floats_find_the_worst", floats_find_the_worst},
    {"tolerance_table_entries", tolerance_table_entries},
    {"reference_against_itself", reference_against_itself},
    {"compare_catches_each_output", compare_catches_each_output},
    {"march_compare_catches_each_output", march_compare_catches_each_output},
};

PGT_TEST_MAIN(cases)
