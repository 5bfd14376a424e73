/* Tests of ref_cpu/src/ivy.c: random seeds, painting (against a brute-force double-precision
 * distance), masks forbidding growth, and the whole pipeline's determinism across threads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/ivy.h"
#include "pgt/rng.h"
#include "test_ivy_scene.h"
#include "test_util.h"

/* A texel whose brute-force distance lies within this of the brush radius (relative) may go
 * either way: the module computes in float32 (P of magnitude ~1, so distances carry ~1e-7
 * relative rounding); 1e-5 is far above that and far below a texel (~3e-3 of the radius). */
#define PAINT_EDGE_REL 1e-5

static ivy_scene scene; /* built once: the atlas takes a while */
static int scene_ready;

static ivy_scene *get_scene(void) {
    if (!scene_ready) scene_ready = ivy_scene_make(&scene);
    return scene_ready ? &scene : NULL;
}

static void test_random_seeds(void) {
    ivy_scene *s = get_scene();
    REQUIRE(s);
    const pgt_march_atlas *a = &s->atlas;
    pgt_expand_seed many[200], few[10];
    pgt_error err = {0};
    REQUIRE(pgt_ivy_random_seeds(many, 200, a, NULL, 7, &err) == PGT_OK);
    REQUIRE(pgt_ivy_random_seeds(few, 10, a, NULL, 7, &err) == PGT_OK);
    CHECK(!memcmp(many, few, sizeof few)); /* seed i does not depend on the count */
    uint32_t distinct = 0;
    for (uint32_t i = 0; i < 200; ++i) {
        const pgt_expand_seed *q = &many[i];
        const uint32_t tx = (uint32_t)q->x, ty = (uint32_t)q->y;
        CHECK(q->x == (float)tx + 0.5f && q->y == (float)ty + 0.5f);
        CHECK((a->codes[(size_t)ty * a->width + tx] & 3u) == PGT_TEXEL_INNER);
        CHECK(fabsf(hypotf(q->dx, q->dy) - 1.0f) < 1e-6f);
        distinct += i == 0 || memcmp(q, &many[i - 1], sizeof *q) != 0;
    }
    CHECK(distinct > 190); /* 200 draws among ~600k inner texels: collisions are rare */
    pgt_expand_seed other[10];
    REQUIRE(pgt_ivy_random_seeds(other, 10, a, NULL, 8, &err) == PGT_OK);
    CHECK(memcmp(other, few, sizeof few) != 0);
    /* with a mask forbidding the left half of the atlas, every seed lands on the right half,
     * and a mask forbidding everything is PGT_ERROR_EMPTY */
    const size_t texels = (size_t)a->width * a->height;
    float *mask = malloc(texels * sizeof(float));
    REQUIRE(mask);
    for (size_t i = 0; i < texels; ++i) mask[i] = i % a->width < a->width / 2u ? 1.0f : 0.0f;
    REQUIRE(pgt_ivy_random_seeds(many, 200, a, mask, 7, &err) == PGT_OK);
    uint32_t left = 0;
    for (uint32_t i = 0; i < 200; ++i) left += many[i].x < (float)(a->width / 2u);
    CHECK_MSG(left == 0, "%u of 200 seeds on forbidden texels", left);
    for (size_t i = 0; i < texels; ++i) mask[i] = 1.0f;
    pgt_error e2 = {0};
    CHECK(pgt_ivy_random_seeds(many, 1, a, mask, 7, &e2) == PGT_ERROR_EMPTY &&
          strstr(e2.message, "mask") != NULL);
    free(mask);
}

static double dist_point_segment(const double p[3], const float *a, const float *b) {
    double ab[3], ap[3], ab2 = 0.0, t = 0.0, d2 = 0.0;
    for (int k = 0; k < 3; ++k)
        ab[k] = (double)b[k] - a[k], ap[k] = p[k] - a[k], ab2 += ab[k] * ab[k];
    if (ab2 > 0.0) {
        for (int k = 0; k < 3; ++k) t += ap[k] * ab[k];
        t = fmin(1.0, fmax(0.0, t / ab2));
    }
    for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
    return sqrt(d2);
}

/* Strokes on the unit-radius cube-sphere: two arcs and a one-point stroke. */
static void test_paint_matches_brute_force(void) {
    ivy_scene *s = get_scene();
    REQUIRE(s);
    const pgt_march_atlas *a = &s->atlas;
    float pts[3 * 13];
    uint32_t n = 0;
    for (int i = 0; i < 8; ++i) { /* an arc around z across several cube faces */
        const double t = 0.35 * i;
        pts[3 * n] = (float)cos(t), pts[3 * n + 1] = (float)sin(t), pts[3 * n + 2] = 0.1f, n++;
    }
    for (int i = 0; i < 4; ++i) { /* an arc over the pole */
        const double t = 0.4 * i;
        pts[3 * n] = (float)sin(t), pts[3 * n + 1] = 0.2f, pts[3 * n + 2] = (float)cos(t), n++;
    }
    pts[3 * n] = 0.0f, pts[3 * n + 1] = -1.0f, pts[3 * n + 2] = 0.0f, n++; /* a dot */
    const uint32_t first[4] = {0, 8, 12, 13};
    const float r = 0.05f;
    const size_t texels = (size_t)a->width * a->height;
    float *m1 = malloc(texels * sizeof(float)), *m2 = malloc(texels * sizeof(float));
    REQUIRE(m1 && m2);
    for (size_t i = 0; i < texels; ++i) m1[i] = m2[i] = 1.0f;
    uint64_t painted1 = 0, painted2 = 0;
    pgt_error err = {0};
    REQUIRE(pgt_ivy_paint(m1, a, pts, n, first, 3, r, 1, &painted1, &err) == PGT_OK);
    REQUIRE(pgt_ivy_paint(m2, a, pts, n, first, 3, r, 2, &painted2, &err) == PGT_OK);
    CHECK(!memcmp(m1, m2, texels * sizeof(float)) && painted1 == painted2);
    uint64_t expect = 0, mismatches = 0, edge = 0;
    for (size_t i = 0; i < texels; ++i) {
        const uint32_t kind = a->codes[i] & 3u;
        if (kind != PGT_TEXEL_INNER && kind != PGT_TEXEL_INDIRECTION) {
            CHECK(m1[i] == 1.0f);
            continue;
        }
        const double p[3] = {a->texels[i].x, a->texels[i].y, a->texels[i].z};
        double d = 1e30;
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t lo = first[k], hi = first[k + 1];
            if (hi - lo == 1) d = fmin(d, dist_point_segment(p, &pts[3 * lo], &pts[3 * lo]));
            for (uint32_t q = lo + 1; q < hi; ++q)
                d = fmin(d, dist_point_segment(p, &pts[3 * (q - 1)], &pts[3 * q]));
        }
        if (fabs(d - r) <= PAINT_EDGE_REL * r) {
            edge++;
            continue;
        }
        const int want = d < r;
        expect += want;
        mismatches += want != (m1[i] == 0.0f);
    }
    printf("  paint: %llu texels painted, %llu expected (%llu at the edge), %llu mismatches\n",
           (unsigned long long)painted1, (unsigned long long)expect, (unsigned long long)edge,
           (unsigned long long)mismatches);
    CHECK(mismatches == 0);
    CHECK(expect > 1000); /* the strokes cover a band of texels, not nothing */
    CHECK(painted1 >= expect && painted1 <= expect + edge);
    /* bad arguments */
    CHECK(pgt_ivy_paint(m1, a, pts, n, first, 3, 0.0f, 1, NULL, &err) ==
          PGT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err.message, "radius") != NULL);
    /* segments whose boxes cover more grid entries in all than the bound: 300 diagonals of the
     * cube-sphere's box, each a 64^3 box of cells (300 x 2^18 > 2^26), refused before the
     * cells are visited */
    float *zig = malloc(3u * 301u * sizeof(float));
    REQUIRE(zig);
    for (uint32_t i = 0; i <= 300; ++i)
        for (int k = 0; k < 3; ++k) zig[3 * i + k] = i % 2 ? 1.0f : -1.0f;
    const uint32_t zig_first[2] = {0, 301};
    pgt_error_clear(&err);
    CHECK(pgt_ivy_paint(m1, a, zig, 301, zig_first, 1, 1e-3f, 1, NULL, &err) == PGT_ERROR_LIMIT);
    CHECK_MSG(strstr(err.message, "split them into shorter segments") != NULL, "%s", err.message);
    free(zig);
    const uint32_t bad_first[4] = {0, 9, 8, 13};
    pgt_error_clear(&err);
    CHECK(pgt_ivy_paint(m1, a, pts, n, bad_first, 3, r, 1, NULL, &err) ==
          PGT_ERROR_INVALID_ARGUMENT);
    pgt_error_clear(&err);
    pts[4] = NAN;
    CHECK(pgt_ivy_paint(m1, a, pts, n, first, 3, r, 1, NULL, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err.message, "point 1") != NULL, "message: %s", err.message);
    free(m1), free(m2);
}

/* A brush far below the grid's float resolution (1e-9 on a unit sphere: lo - r == lo) still
 * paints the strokes' own points: a stroke between two texels' positions paints both texels,
 * whose distance to it is exactly 0. The upper one lies on the grid's top boundary, which the
 * cell lookup once refused (floor((hi - lo) / cell) == dim) while the segment's box was
 * clamped into the top cell. */
static void test_paint_tiny_brush_endpoints(void) {
    ivy_scene *s = get_scene();
    REQUIRE(s);
    const pgt_march_atlas *a = &s->atlas;
    const size_t texels = (size_t)a->width * a->height;
    float *m = malloc(texels * sizeof(float));
    REQUIRE(m);
    uint32_t ends[2] = {0, 0}, pairs = 0, missed = 0;
    size_t found = 0;
    for (size_t i = 0; i < texels && pairs < 200; i += 997) {
        if ((a->codes[i] & 3u) != PGT_TEXEL_INNER) continue;
        ends[found++ % 2] = (uint32_t)i;
        if (found % 2) continue;
        float pts[6];
        for (int e = 0; e < 2; ++e)
            pts[3 * e] = a->texels[ends[e]].x, pts[3 * e + 1] = a->texels[ends[e]].y,
                    pts[3 * e + 2] = a->texels[ends[e]].z;
        const uint32_t first[2] = {0, 2};
        for (size_t t = 0; t < texels; ++t) m[t] = 1.0f;
        pgt_error err = {0};
        REQUIRE(pgt_ivy_paint(m, a, pts, 2, first, 1, 1e-9f, 1, NULL, &err) == PGT_OK);
        missed += (m[ends[0]] != 0.0f) + (m[ends[1]] != 0.0f);
        pairs++;
    }
    printf("  tiny brush: %u strokes, %u of their end texels left unpainted\n", pairs, missed);
    CHECK(pairs == 200);
    CHECK(missed == 0);
    free(m);
}

/* The ivy grown with and without a mask forbidding the texels of the half-atlas x >= width/2:
 * with it, no point lies in a forbidden texel; without it, some do (so the check has teeth). */
static void test_mask_forbids(void) {
    ivy_scene *s = get_scene();
    REQUIRE(s);
    const pgt_march_atlas *a = &s->atlas;
    const size_t texels = (size_t)a->width * a->height;
    float *mask = malloc(texels * sizeof(float));
    REQUIRE(mask);
    for (size_t i = 0; i < texels; ++i) mask[i] = (i % a->width) >= a->width / 2 ? 1.0f : 0.0f;
    /* seeds: those of the scene in the allowed half */
    pgt_expand_input in = s->in;
    pgt_expand_seed seeds[IVY_SCENE_SEEDS];
    uint32_t ns = 0;
    for (uint32_t i = 0; i < in.seed_count; ++i)
        if (in.seeds[i].x < (float)(a->width / 2)) seeds[ns++] = in.seeds[i];
    REQUIRE(ns > 0);
    in.seeds = seeds, in.seed_count = ns;
    pgt_ivy_options o;
    memset(&o, 0, sizeof o);
    o.threads = 2;
    pgt_ivy_output free_run, masked;
    pgt_error err = {0};
    REQUIRE(pgt_ivy_generate(&free_run, &in, &o, &err) == PGT_OK);
    in.mask = mask;
    o.expand.march.mask = mask;
    REQUIRE(pgt_ivy_generate(&masked, &in, &o, &err) == PGT_OK);
    uint32_t inside_free = 0, inside_masked = 0;
    for (uint32_t i = 0; i < free_run.expand.point_count; ++i)
        inside_free += mask[(size_t)(uint32_t)free_run.expand.v[i] * a->width +
                            (uint32_t)free_run.expand.u[i]] >= 0.5f;
    for (uint32_t i = 0; i < masked.expand.point_count; ++i)
        inside_masked +=
            mask[(size_t)(uint32_t)masked.expand.v[i] * a->width + (uint32_t)masked.expand.u[i]] >=
            0.5f;
    printf("  mask: %u of %u points in forbidden texels without the mask, %u of %u with it\n",
           inside_free, free_run.expand.point_count, inside_masked, masked.expand.point_count);
    CHECK(inside_free > 0);
    CHECK(inside_masked == 0);
    CHECK(masked.expand.point_count > ns); /* growth happened in the allowed half */
    pgt_ivy_destroy(&free_run), pgt_ivy_destroy(&masked);
    free(mask);
}

static int same_mesh(const pgt_terminals_output *x, const pgt_terminals_output *y) {
    return x->vertex_count == y->vertex_count && x->triangle_count == y->triangle_count &&
           !memcmp(x->positions, y->positions, 12u * (size_t)x->vertex_count) &&
           !memcmp(x->normals, y->normals, 12u * (size_t)x->vertex_count) &&
           !memcmp(x->uvs, y->uvs, 8u * (size_t)x->vertex_count) &&
           !memcmp(x->triangles, y->triangles, 12u * (size_t)x->triangle_count);
}

/* The same inputs give the same bytes on 1 and 2 threads, and with reused buffers; no_leaves
 * drops exactly the leaves; the polygon count is bark quads + leaves. */
static void test_pipeline_determinism(void) {
    ivy_scene *s = get_scene();
    REQUIRE(s);
    pgt_ivy_options o;
    memset(&o, 0, sizeof o);
    pgt_ivy_output one, two, again, bare;
    memset(&again, 0, sizeof again);
    pgt_error err = {0};
    o.threads = 1;
    REQUIRE(pgt_ivy_generate(&one, &s->in, &o, &err) == PGT_OK);
    o.threads = 2;
    REQUIRE(pgt_ivy_generate(&two, &s->in, &o, &err) == PGT_OK);
    CHECK(same_mesh(&one.mesh, &two.mesh));
    CHECK(!memcmp(one.b1, two.b1, 12u * (size_t)one.expand.point_count));
    o.reuse = 1;
    REQUIRE(pgt_ivy_generate(&again, &s->in, &o, &err) == PGT_OK); /* zeroed: allocates */
    float *kept = again.mesh.positions;
    REQUIRE(pgt_ivy_generate(&again, &s->in, &o, &err) == PGT_OK); /* reuses */
    CHECK(again.mesh.positions == kept);
    CHECK(same_mesh(&one.mesh, &again.mesh));
    CHECK(one.polygons == one.mesh.bark_quads + one.mesh.leaf_count);
    CHECK(one.mesh.leaf_count > 0);
    o.reuse = 0, o.no_leaves = 1;
    REQUIRE(pgt_ivy_generate(&bare, &s->in, &o, &err) == PGT_OK);
    CHECK(bare.mesh.leaf_count == 0 && bare.dropped_leaves > 0);
    CHECK(bare.mesh.bark_quads == one.mesh.bark_quads);
    CHECK(bare.mesh.triangle_count == one.mesh.triangle_count - 2u * one.mesh.leaf_count);
    pgt_ivy_destroy(&one), pgt_ivy_destroy(&two), pgt_ivy_destroy(&again);
    pgt_ivy_destroy(&bare);
}

/* A progress tracker (pgt/progress.h) observes: the same bytes with it as without, and at the
 * end its last stage, terminals, has every point's segment done; three stages ran (expand,
 * whose seeds all counted, bezier, terminals). */
static void test_progress_observes(void) {
    ivy_scene *s = get_scene();
    REQUIRE(s);
    pgt_ivy_options o;
    memset(&o, 0, sizeof o);
    o.threads = 2;
    pgt_ivy_output plain, watched;
    pgt_error err = {0};
    REQUIRE(pgt_ivy_generate(&plain, &s->in, &o, &err) == PGT_OK);
    o.progress = pgt_progress_create();
    REQUIRE(o.progress);
    pgt_progress_state st;
    pgt_progress_read(o.progress, &st);
    CHECK(st.stages == 0 && st.stage[0] == 0 && st.done == 0);
    REQUIRE(pgt_ivy_generate(&watched, &s->in, &o, &err) == PGT_OK);
    CHECK(same_mesh(&plain.mesh, &watched.mesh));
    pgt_progress_read(o.progress, &st);
    CHECK(st.stages == 3 && !strcmp(st.stage, "terminals") && !strcmp(st.unit, "segments"));
    CHECK(st.total == watched.expand.point_count && st.done == st.total);
    /* expand alone: its seeds */
    pgt_expand_options eo;
    memset(&eo, 0, sizeof eo);
    eo.threads = 2, eo.progress = o.progress;
    pgt_expand_output ex;
    REQUIRE(pgt_expand(&ex, &s->in, &eo, &err) == PGT_OK);
    pgt_progress_read(o.progress, &st);
    CHECK(st.stages == 4 && !strcmp(st.stage, "expand") && st.total == s->in.seed_count &&
          st.done == st.total);
    pgt_expand_destroy(&ex);
    pgt_progress_destroy(o.progress);
    pgt_ivy_destroy(&plain), pgt_ivy_destroy(&watched);
}

/* A seed's ivy, leaves included, does not depend on the other seeds: seeds 1.. alone (with
 * seed_base + 1, so each keeps its id) give the tail of the vertices of seeds 0.. . */
static void test_seed_independence(void) {
    ivy_scene *s = get_scene();
    REQUIRE(s);
    pgt_ivy_options o;
    memset(&o, 0, sizeof o);
    o.threads = 2;
    pgt_expand_input in = s->in;
    pgt_ivy_output all, tail;
    pgt_error err = {0};
    REQUIRE(pgt_ivy_generate(&all, &in, &o, &err) == PGT_OK);
    in.seeds = s->in.seeds + 1, in.seed_count = s->in.seed_count - 1u, in.seed_base = 1;
    REQUIRE(pgt_ivy_generate(&tail, &in, &o, &err) == PGT_OK);
    const pgt_terminals_output *a = &all.mesh, *b = &tail.mesh;
    REQUIRE(a->vertex_count > b->vertex_count && b->leaf_count > 0);
    const size_t off = a->vertex_count - b->vertex_count;
    CHECK(!memcmp(a->positions + 3u * off, b->positions, 12u * (size_t)b->vertex_count));
    CHECK(!memcmp(a->normals + 3u * off, b->normals, 12u * (size_t)b->vertex_count));
    CHECK(!memcmp(a->uvs + 2u * off, b->uvs, 8u * (size_t)b->vertex_count));
    pgt_ivy_destroy(&all), pgt_ivy_destroy(&tail);
}

static const pgt_test_case cases[] = {
    {"seed_independence", test_seed_independence},
    {"random_seeds", test_random_seeds},
    {"paint_matches_brute_force", test_paint_matches_brute_force},
    {"paint_tiny_brush_endpoints", test_paint_tiny_brush_endpoints},
    {"mask_forbids", test_mask_forbids},
    {"pipeline_determinism", test_pipeline_determinism},
    {"progress_observes", test_progress_observes},
};

int main(int argc, char **argv) {
    const int rc = pgt_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
    if (scene_ready) ivy_scene_free(&scene);
    return rc;
}
