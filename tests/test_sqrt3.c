/* Tests of sqrt(3) subdivision (ref_cpu/src/sqrt3.c) with known answers: counts per step,
 * Euler characteristic, border counts and positions per Kobbelt's rule, the derived adjacency
 * against one rebuilt from scratch, determinism across thread counts, the per-call parity,
 * protected faces, UVs, and refusal of non-manifold input. Agreement with CGAL/OpenMesh is
 * test_sqrt3_oracles.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"
#include "pgt/adjacency.h"
#include "pgt/mesh_io.h"
#include "pgt/rng.h"
#include "pgt/sqrt3.h"
#include "test_util.h"

/* Counts of a mesh: vertices referenced, edges, border edges, Euler characteristic. */
typedef struct topo {
    uint32_t border_edges;
    int64_t euler;
    int manifold;
} topo;

static topo topo_of(const pgt_mesh *m) {
    topo t = {0, 0, 0};
    pgt_adjacency a;
    if (pgt_adjacency_build(&a, m, 1, NULL) != PGT_OK) return t;
    t.manifold = pgt_adjacency_require_manifold(&a, "test", NULL) == PGT_OK;
    t.border_edges = a.border_half_edges;
    uint64_t he = a.half_edge_count, edges = (he + a.border_half_edges) / 2;
    t.euler = (int64_t)m->vertex_count - (int64_t)edges + (int64_t)m->face_count;
    pgt_adjacency_destroy(&a);
    return t;
}

typedef struct run {
    pgt_mesh out;
    uint32_t *opp;
    uint8_t *prot;
    uint32_t *parent;
} run;

static int run_sqrt3(run *r, const pgt_mesh *in, uint32_t k, uint32_t threads,
                     const uint8_t *prot) {
    memset(r, 0, sizeof(*r));
    uint32_t vb, fb;
    if (pgt_sqrt3_bound(in->vertex_count, in->face_count, 0, k, &vb, &fb, NULL) != PGT_OK) return 0;
    r->opp = malloc(((size_t)fb * 3 + 1) * sizeof(uint32_t));
    r->prot = malloc((size_t)fb + 1);
    r->parent = malloc(((size_t)fb + 1) * sizeof(uint32_t));
    pgt_sqrt3_options o = {k, threads, prot, r->prot, r->parent, r->opp, NULL};
    pgt_error err = {0};
    if (pgt_sqrt3_subdivide(&r->out, in, &o, &err) != PGT_OK) {
        fprintf(stderr, "  sqrt3 failed: %s\n", err.message);
        return 0;
    }
    return 1;
}

static void run_free(run *r) {
    pgt_mesh_destroy(&r->out);
    free(r->opp), free(r->prot), free(r->parent);
}

/* The next iteration's input: *m (destroyed) becomes r's output, and r is freed. */
static void run_next_input(run *r, pgt_mesh *m) {
    pgt_mesh_destroy(m);
    *m = r->out;
    memset(&r->out, 0, sizeof r->out);
    run_free(r);
}

/* Half-edges where the adjacency sqrt3 derived disagrees with one rebuilt from its output. */
static uint32_t adjacency_mismatches(const run *r) {
    pgt_adjacency a;
    if (pgt_adjacency_build(&a, &r->out, 1, NULL) != PGT_OK) return PGT_NONE;
    uint32_t diff = 0;
    for (uint32_t h = 0; h < a.half_edge_count; ++h) diff += a.opposite[h] != r->opp[h];
    pgt_adjacency_destroy(&a);
    return diff;
}

static int same_mesh_bytes(const pgt_mesh *a, const pgt_mesh *b) {
    if (a->vertex_count != b->vertex_count || a->face_count != b->face_count) return 0;
    if (memcmp(a->positions, b->positions, (size_t)a->vertex_count * 3 * sizeof(float))) return 0;
    if (memcmp(a->indices, b->indices, (size_t)a->face_count * 3 * sizeof(uint32_t))) return 0;
    if ((a->uvs == NULL) != (b->uvs == NULL)) return 0;
    if (a->uvs && memcmp(a->uvs, b->uvs, (size_t)a->face_count * 6 * sizeof(float))) return 0;
    return 1;
}

static pgt_mesh gen(const char *name) {
    pgt_mesh m = {0};
    uint32_t i = pgt_gen_default_find(name);
    if (i == PGT_NONE || pgt_gen_default(i, &m, NULL) != PGT_OK)
        fprintf(stderr, "  no dataset %s\n", name);
    return m;
}

/* Closed meshes: F x 3 and V + F per step, Euler characteristic kept, manifold, and the
 * adjacency derived step by step equals the one rebuilt from the output. */
static void closed_counts_and_adjacency(void) {
    const char *names[] = {"icosphere_l0", "icosphere_l2", "torus_32x16", "noisy_torus_48x24",
                           "cube_sphere_8"};
    for (size_t n = 0; n < sizeof names / sizeof *names; ++n) {
        pgt_mesh m = gen(names[n]);
        REQUIRE(m.face_count > 0);
        topo t0 = topo_of(&m);
        CHECK(t0.manifold && t0.border_edges == 0);
        uint64_t V = m.vertex_count, F = m.face_count;
        for (uint32_t k = 1; k <= 3; ++k) {
            V += F; /* one face point per face */
            F *= 3;
            run r;
            REQUIRE(run_sqrt3(&r, &m, k, 2, NULL));
            CHECK_MSG(r.out.face_count == F && r.out.vertex_count == V,
                      "%s k=%u: %u v %u f, want %llu v %llu f", names[n], k, r.out.vertex_count,
                      r.out.face_count, (unsigned long long)V, (unsigned long long)F);
            topo t = topo_of(&r.out);
            CHECK_MSG(t.manifold && t.border_edges == 0 && t.euler == t0.euler,
                      "%s k=%u: euler %lld (was %lld)", names[n], k, (long long)t.euler,
                      (long long)t0.euler);
            const uint32_t diff = adjacency_mismatches(&r);
            CHECK_MSG(diff == 0, "%s k=%u: %u half-edges disagree with the rebuilt adjacency",
                      names[n], k, diff);
            run_free(&r);
        }
        pgt_mesh_destroy(&m);
    }
}

/* The closed-mesh fast path (no border, no protection, no UVs) gives the same bytes as the
 * general pass, which a mesh with UVs takes: the cube-sphere with and without its UVs. */
static void closed_fast_path_equals_general(void) {
    pgt_mesh with = gen("cube_sphere_8"), without;
    REQUIRE(with.uvs != NULL && pgt_mesh_copy(&without, &with, NULL) == PGT_OK);
    free(without.uvs);
    without.uvs = NULL;
    for (uint32_t k = 1; k <= 3; ++k) {
        run a, b;
        REQUIRE(run_sqrt3(&a, &with, k, 2, NULL));
        REQUIRE(run_sqrt3(&b, &without, k, 2, NULL));
        CHECK(a.out.vertex_count == b.out.vertex_count && a.out.face_count == b.out.face_count);
        CHECK(!memcmp(a.out.positions, b.out.positions, (size_t)a.out.vertex_count * 12));
        CHECK(!memcmp(a.out.indices, b.out.indices, (size_t)a.out.face_count * 12));
        CHECK(!memcmp(a.opp, b.opp, (size_t)a.out.face_count * 12));
        CHECK(!memcmp(a.parent, b.parent, (size_t)a.out.face_count * 4));
        /* Without any optional output the last step reads the level before it implicitly (no
         * stored connectivity): still the same bytes, labels included. */
        pgt_mesh c;
        pgt_sqrt3_options o = {k, 2, NULL, NULL, NULL, NULL, NULL};
        REQUIRE(pgt_sqrt3_subdivide(&c, &without, &o, NULL) == PGT_OK);
        CHECK(c.vertex_count == a.out.vertex_count && c.face_count == a.out.face_count);
        CHECK(!memcmp(a.out.positions, c.positions, (size_t)a.out.vertex_count * 12));
        CHECK(!memcmp(a.out.indices, c.indices, (size_t)a.out.face_count * 12));
        CHECK(a.out.labels && c.labels &&
              !memcmp(a.out.labels, c.labels, (size_t)a.out.face_count * 4));
        pgt_mesh_destroy(&c);
        run_free(&a);
        run_free(&b);
    }
    pgt_mesh_destroy(&with);
    pgt_mesh_destroy(&without);
}

/* Meshes with a border: odd iterations keep the border (B edges, V + F new vertices), even ones
 * trisect it (3B edges, V + F + B vertices: F - B centroids and 2B trisection points). */
static void border_counts_per_rule(void) {
    const char *names[] = {"grid_16x16", "hemisphere_jagged_12x32"};
    for (size_t n = 0; n < sizeof names / sizeof *names; ++n) {
        pgt_mesh m = gen(names[n]);
        REQUIRE(m.face_count > 0);
        topo t0 = topo_of(&m);
        CHECK(t0.manifold && t0.border_edges > 0);
        uint64_t V = m.vertex_count, F = m.face_count, B = t0.border_edges;
        for (uint32_t k = 1; k <= 4; ++k) {
            if (k % 2 == 1) {
                V += F;
            } else {
                V += F + B;
                B *= 3;
            }
            F *= 3;
            run r;
            REQUIRE(run_sqrt3(&r, &m, k, 1, NULL));
            topo t = topo_of(&r.out);
            CHECK_MSG(r.out.vertex_count == V && r.out.face_count == F && t.border_edges == B,
                      "%s k=%u: %u v %u f %u border, want %llu %llu %llu", names[n], k,
                      r.out.vertex_count, r.out.face_count, t.border_edges, (unsigned long long)V,
                      (unsigned long long)F, (unsigned long long)B);
            CHECK(t.manifold && t.euler == t0.euler);
            const uint32_t diff = adjacency_mismatches(&r);
            CHECK_MSG(diff == 0, "%s k=%u: %u half-edges disagree with the rebuilt adjacency",
                      names[n], k, diff);
            run_free(&r);
        }
        pgt_mesh_destroy(&m);
    }
}

/* Kobbelt's border rule re-derived in double (float32 roundings of sums up to 27 x |coordinate|
 * <= 1 on these meshes: three of at most half an ulp of 27 (1.9e-6 / 2) before the division by
 * 27, one of half an ulp of 1 after it, 1.7e-7 in all). */
#define BORDER_RULE_TOL 3e-7

/* The input's border ring: for each vertex on the border, the one before and after it along the
 * border half-edges (prev[v] -> v -> next[v]), PGT_NONE elsewhere. Returns the border edges. */
static uint32_t border_ring(const pgt_mesh *m, uint32_t *prev, uint32_t *next) {
    pgt_adjacency a;
    if (pgt_adjacency_build(&a, m, 1, NULL) != PGT_OK) return 0;
    for (uint32_t v = 0; v < m->vertex_count; ++v) prev[v] = next[v] = PGT_NONE;
    uint32_t edges = 0;
    for (uint32_t h = 0; h < a.half_edge_count; ++h)
        if (a.opposite[h] == PGT_NONE) {
            const uint32_t u = m->indices[h], w = m->indices[pgt_half_edge_next(h)];
            next[u] = w, prev[w] = u;
            edges++;
        }
    pgt_adjacency_destroy(&a);
    return edges;
}

/* (wa a + wb b + wc c) / 27 in double from the input's float positions. */
static void mask27(const pgt_mesh *m, uint32_t a, uint32_t b, uint32_t c, double wa, double wb,
                   double wc, double out[3]) {
    for (int k = 0; k < 3; ++k)
        out[k] = (wa * m->positions[3 * (size_t)a + k] + wb * m->positions[3 * (size_t)b + k] +
                  wc * m->positions[3 * (size_t)c + k]) /
                 27.0;
}

static double max_diff3(const double want[3], const float *got) {
    double d = 0.0;
    for (int k = 0; k < 3; ++k) d = fmax(d, fabs(want[k] - (double)got[k]));
    return d;
}

/* Iteration 1 (odd) keeps every border vertex and edge; iteration 2 (even) applies Kobbelt's
 * border rule to that unchanged ring (sqrt3.h, after CGAL Sqrt3_1step and OpenMesh Sqrt3T): each
 * old border vertex p_i goes to (4 p_{i-1} + 19 p_i + 4 p_{i+1}) / 27, and each border edge
 * p_i -> p_{i+1} becomes p_i -> (p_{i-1} + 16 p_i + 10 p_{i+1}) / 27 -> (10 p_i + 16 p_{i+1} +
 * p_{i+2}) / 27 -> p_{i+1}. Checked on the jagged hemisphere (an uneven, non-planar border) by
 * walking the output's border half-edges from each old border vertex and re-deriving every point
 * in double from the input's ring. On the flat grid the masks of collinear points keep every
 * border point on the square's sides exactly (the weights sum to 27 and 27 / 27 = 1 in float),
 * except the 4 corners and the 8 trisection points next to them, whose masks mix two sides. */
static void border_rule_per_iteration(void) {
    const char *names[] = {"hemisphere_jagged_12x32", "grid_16x16"};
    for (size_t n = 0; n < sizeof names / sizeof *names; ++n) {
        pgt_mesh m = gen(names[n]);
        REQUIRE(m.face_count > 0);
        const uint32_t V = m.vertex_count;
        uint32_t *prev = malloc(V * sizeof(uint32_t)), *next = malloc(V * sizeof(uint32_t));
        REQUIRE(prev && next);
        const uint32_t B = border_ring(&m, prev, next);
        REQUIRE(B > 0);
        /* odd iteration: every input border vertex keeps its position bytes */
        run r1;
        REQUIRE(run_sqrt3(&r1, &m, 1, 1, NULL));
        uint32_t moved = 0;
        for (uint32_t v = 0; v < V; ++v)
            moved += next[v] != PGT_NONE &&
                     memcmp(m.positions + 3 * (size_t)v, r1.out.positions + 3 * (size_t)v, 12);
        CHECK_MSG(moved == 0, "%s k=1: %u border vertices moved", names[n], moved);
        run_free(&r1);
        /* even iteration */
        run r;
        REQUIRE(run_sqrt3(&r, &m, 2, 1, NULL));
        pgt_adjacency a;
        REQUIRE(pgt_adjacency_build(&a, &r.out, 1, NULL) == PGT_OK);
        uint32_t *out_next = malloc(r.out.vertex_count * sizeof(uint32_t));
        REQUIRE(out_next);
        for (uint32_t v = 0; v < r.out.vertex_count; ++v) out_next[v] = PGT_NONE;
        for (uint32_t h = 0; h < a.half_edge_count; ++h)
            if (a.opposite[h] == PGT_NONE)
                out_next[r.out.indices[h]] = r.out.indices[pgt_half_edge_next(h)];
        double worst = 0.0;
        uint32_t old_checked = 0, new_checked = 0, bad_chain = 0, off_sides = 0;
        for (uint32_t v = 0; v < V; ++v) {
            if (next[v] == PGT_NONE) continue;
            const uint32_t p = prev[v], w = next[v], ww = next[w];
            double want[3];
            mask27(&m, p, v, w, 4.0, 19.0, 4.0, want);
            worst = fmax(worst, max_diff3(want, r.out.positions + 3 * (size_t)v));
            old_checked++;
            /* the output border from v: v -> E_a -> E_b -> w, E_a and E_b new vertices */
            const uint32_t ea = out_next[v], eb = ea == PGT_NONE ? PGT_NONE : out_next[ea];
            if (ea == PGT_NONE || eb == PGT_NONE || ea < V || eb < V || out_next[eb] != w) {
                bad_chain++;
                continue;
            }
            mask27(&m, p, v, w, 1.0, 16.0, 10.0, want);
            worst = fmax(worst, max_diff3(want, r.out.positions + 3 * (size_t)ea));
            mask27(&m, v, w, ww, 10.0, 16.0, 1.0, want);
            worst = fmax(worst, max_diff3(want, r.out.positions + 3 * (size_t)eb));
            new_checked += 2;
            if (n == 1) {
                const uint32_t pts[3] = {v, ea, eb};
                for (int q = 0; q < 3; ++q) {
                    const float *x = r.out.positions + 3 * (size_t)pts[q];
                    off_sides += !(x[0] == 0.0f || x[0] == 1.0f || x[1] == 0.0f || x[1] == 1.0f);
                }
            }
        }
        printf("  %s: %u old and %u new border vertices, worst %.3g from the double rule\n",
               names[n], old_checked, new_checked, worst);
        CHECK_MSG(old_checked == B && new_checked == 2 * B && bad_chain == 0,
                  "%s: %u old, %u new of %u border edges, %u broken chains", names[n], old_checked,
                  new_checked, B, bad_chain);
        CHECK_MSG(worst <= BORDER_RULE_TOL, "%s: border point %.3g from the rule", names[n], worst);
        if (n == 1)
            CHECK_MSG(off_sides == 12, "grid: %u border points off the sides, want 12", off_sides);
        free(out_next);
        pgt_adjacency_destroy(&a);
        run_free(&r);
        free(prev), free(next);
        pgt_mesh_destroy(&m);
    }
}

/* A directed half-edge for the reference pairing of adjacency_high_valence. */
typedef struct dir_edge {
    uint32_t a, b, h;
} dir_edge;

static int dir_edge_cmp(const void *pa, const void *pb) {
    const dir_edge *x = pa, *y = pb;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    if (x->b != y->b) return x->b < y->b ? -1 : 1;
    return x->h < y->h ? -1 : x->h > y->h;
}

/* The directed half-edges a->b of a sorted array: how many, and the first's index. */
static uint32_t dir_edge_count(const dir_edge *e, uint32_t n, uint32_t a, uint32_t b,
                               uint32_t *first) {
    uint32_t l = 0, r = n;
    while (l < r) {
        const uint32_t m = l + (r - l) / 2u;
        if (e[m].a < a || (e[m].a == a && e[m].b < b))
            l = m + 1u;
        else
            r = m;
    }
    *first = l;
    uint32_t k = 0;
    while (l + k < n && e[l + k].a == a && e[l + k].b == b) ++k;
    return k;
}

/* pgt_adjacency_build against a pairing made another way (one global sort of the directed
 * half-edges) on fans whose centre has valence 3000 (its buckets go through the sorted path):
 * an open disc, a closed double cone (its apexes 3000 each) and the cone with one face repeated
 * (non-manifold). The opposite of each half-edge, the border count and the non-manifold count
 * must agree. (The old linear scans made a 300,000-gon take 38 s.) */
static void adjacency_high_valence(void) {
    const uint32_t N = 3000;
    for (int variant = 0; variant < 3; ++variant) {
        const uint32_t F = variant == 0 ? N : 2u * N + (variant == 2);
        pgt_mesh m;
        REQUIRE(pgt_mesh_create(&m, N + 2u, F, 0, 0, NULL) == PGT_OK);
        for (uint32_t v = 0; v < N + 2u; ++v) {
            const double t = 6.283185307179586 * v / N;
            m.positions[3 * v] = v < N ? (float)cos(t) : 0.0f;
            m.positions[3 * v + 1] = v < N ? (float)sin(t) : 0.0f;
            m.positions[3 * v + 2] = v < N ? 0.0f : v == N ? 1.0f : -1.0f;
        }
        for (uint32_t i = 0; i < N; ++i) {
            uint32_t *top = m.indices + 3 * i;
            top[0] = i, top[1] = (i + 1) % N, top[2] = N;
            if (variant == 0) continue;
            uint32_t *bottom = m.indices + 3 * (N + i);
            bottom[0] = (i + 1) % N, bottom[1] = i, bottom[2] = N + 1u;
        }
        if (variant == 2) memcpy(m.indices + 3 * (2 * N), m.indices, 3 * sizeof(uint32_t));
        pgt_adjacency a;
        REQUIRE(pgt_adjacency_build(&a, &m, 2, NULL) == PGT_OK);
        const uint32_t H = 3 * F;
        dir_edge *e = malloc(H * sizeof *e);
        REQUIRE(e != NULL);
        for (uint32_t h = 0; h < H; ++h)
            e[h] = (dir_edge){m.indices[h], m.indices[pgt_half_edge_next(h)], h};
        qsort(e, H, sizeof *e, dir_edge_cmp);
        uint32_t wrong = 0, border = 0, bad_half_edges = 0;
        for (uint32_t h = 0; h < H; ++h) {
            const uint32_t u = m.indices[h], w = m.indices[pgt_half_edge_next(h)];
            uint32_t f_same, f_opp;
            const uint32_t same = dir_edge_count(e, H, u, w, &f_same);
            const uint32_t opp = dir_edge_count(e, H, w, u, &f_opp);
            const int bad = !(same == 1 && opp <= 1);
            const uint32_t want = bad || opp == 0 ? PGT_NONE : e[f_opp].h;
            wrong += a.opposite[h] != want;
            border += !bad && opp == 0;
            bad_half_edges += (uint32_t)bad;
        }
        printf("  fan variant %d: %u half-edges, %u border, %u on non-manifold edges, %u differ\n",
               variant, H, border, bad_half_edges, wrong);
        CHECK(wrong == 0 && a.border_half_edges == border);
        CHECK(variant == 0 ? border == N : border == 0);
        /* the repeated face makes its three edges non-manifold (3 faces or a repeated direction) */
        CHECK(a.non_manifold_edges == (variant == 2 ? 3u : 0u));
        CHECK(bad_half_edges == (variant == 2 ? 9u : 0u));
        free(e);
        pgt_adjacency_destroy(&a);
        pgt_mesh_destroy(&m);
    }
}

/* Same input, same bytes, whatever the thread count. */
static void deterministic_across_threads(void) {
    const char *names[] = {"noisy_torus_48x24", "hemisphere_jagged_12x32", "cube_sphere_8"};
    for (size_t n = 0; n < sizeof names / sizeof *names; ++n) {
        pgt_mesh m = gen(names[n]);
        REQUIRE(m.face_count > 0);
        run r1;
        REQUIRE(run_sqrt3(&r1, &m, 3, 1, NULL));
        for (uint32_t t = 2; t <= 7; t += 5) {
            run rt;
            REQUIRE(run_sqrt3(&rt, &m, 3, t, NULL));
            CHECK_MSG(same_mesh_bytes(&r1.out, &rt.out), "%s: %u threads differ from 1", names[n],
                      t);
            run_free(&rt);
        }
        run_free(&r1);
        pgt_mesh_destroy(&m);
    }
}

/* Unit sphere: a few float ulps of 1 (6e-8 each) from reordered sums of 6 terms, over 3 levels. */
#define REORDERED_SUM_TOL 1e-6f

/* The parity restarts at every call: three calls of k = 1 never trisect a border (so differ from
 * one call of k = 3 on a mesh with border), while on a closed mesh they give the same triangles
 * and the same points up to float rounding (each call starts a vertex's neighbour sum at its
 * smallest half-edge, one call at the half-edge derived from the previous level: same terms,
 * another order). */
static void parity_restarts_per_call(void) {
    const char *names[] = {"icosphere_l1", "grid_16x16"};
    for (int n = 0; n < 2; ++n) {
        pgt_mesh m = gen(names[n]);
        REQUIRE(m.face_count > 0);
        run once;
        REQUIRE(run_sqrt3(&once, &m, 3, 1, NULL));
        pgt_mesh cur;
        REQUIRE(pgt_mesh_copy(&cur, &m, NULL) == PGT_OK);
        for (int i = 0; i < 3; ++i) {
            pgt_mesh next;
            pgt_sqrt3_options o = {1, 1, NULL, NULL, NULL, NULL, NULL};
            REQUIRE(pgt_sqrt3_subdivide(&next, &cur, &o, NULL) == PGT_OK);
            pgt_mesh_destroy(&cur);
            cur = next;
        }
        if (n == 0) {
            REQUIRE(once.out.vertex_count == cur.vertex_count &&
                    once.out.face_count == cur.face_count);
            CHECK(!memcmp(once.out.indices, cur.indices,
                          (size_t)cur.face_count * 3 * sizeof(uint32_t)));
            float worst = 0.0f;
            for (uint32_t i = 0; i < 3 * cur.vertex_count; ++i)
                worst = fmaxf(worst, fabsf(once.out.positions[i] - cur.positions[i]));
            CHECK_MSG(worst < REORDERED_SUM_TOL, "max difference %g", worst);
        } else {
            CHECK(topo_of(&cur).border_edges == topo_of(&m).border_edges); /* never trisected */
            CHECK(topo_of(&once.out).border_edges == 3 * topo_of(&m).border_edges);
        }
        pgt_mesh_destroy(&cur);
        run_free(&once);
        pgt_mesh_destroy(&m);
    }
}

/* k = 0 copies; k = 1 with nothing protected equals no protection at all. */
static void zero_iterations_and_empty_protection(void) {
    pgt_mesh m = gen("cube_sphere_8");
    REQUIRE(m.face_count > 0);
    run r0;
    REQUIRE(run_sqrt3(&r0, &m, 0, 1, NULL));
    CHECK(same_mesh_bytes(&r0.out, &m));
    uint8_t *none = calloc(m.face_count, 1);
    for (uint32_t k = 1; k <= 3; ++k) {
        run a, b;
        REQUIRE(run_sqrt3(&a, &m, k, 2, NULL));
        REQUIRE(run_sqrt3(&b, &m, k, 2, none));
        CHECK(same_mesh_bytes(&a.out, &b.out));
        run_free(&a);
        run_free(&b);
    }
    free(none);
    run_free(&r0);
    pgt_mesh_destroy(&m);
}

/* Protected faces (paper 004, 4.2.2): they come out bit-identical (same vertex indices, same
 * position bytes), their vertices do not move, the result is a watertight conforming manifold
 * (no border appears on a closed mesh) and the counts follow: a protected face emits 1 face and
 * no point. Checked with a seeded random selection and with one smoothing group. */
static void protected_faces_bit_identical(void) {
    const char *names[] = {"noisy_torus_48x24", "hemisphere_jagged_12x32", "cube_sphere_8"};
    for (size_t n = 0; n < sizeof names / sizeof *names; ++n) {
        pgt_mesh m = gen(names[n]);
        REQUIRE(m.face_count > 0);
        uint8_t *prot = calloc(m.face_count, 1);
        uint32_t np = 0;
        for (uint32_t f = 0; f < m.face_count; ++f) {
            /* a third of the faces at random, or (cube-sphere) every face outside group 4 */
            prot[f] = m.labels ? m.labels[f] != 4 : pgt_rng_float(5, 1, f) < 0.33f;
            np += prot[f];
        }
        topo t0 = topo_of(&m);
        for (uint32_t k = 1; k <= 3; ++k) {
            run r;
            REQUIRE(run_sqrt3(&r, &m, k, 2, prot));
            uint32_t seen = 0, bad = 0;
            for (uint32_t t = 0; t < r.out.face_count; ++t) {
                if (!r.prot[t]) continue;
                seen++;
                uint32_t f = r.parent[t];
                for (int c = 0; c < 3; ++c) {
                    uint32_t vi = m.indices[3 * (size_t)f + c],
                             vo = r.out.indices[3 * (size_t)t + c];
                    bad += vi != vo || memcmp(m.positions + 3 * (size_t)vi,
                                              r.out.positions + 3 * (size_t)vo, 12);
                }
                if (m.uvs) bad += memcmp(m.uvs + 6 * (size_t)f, r.out.uvs + 6 * (size_t)t, 24) != 0;
            }
            CHECK_MSG(seen == np && bad == 0, "%s k=%u: %u of %u protected faces, %u differ",
                      names[n], k, seen, np, bad);
            topo t = topo_of(&r.out);
            CHECK_MSG(t.manifold && t.euler == t0.euler, "%s k=%u: not a manifold or euler changed",
                      names[n], k);
            if (t0.border_edges == 0)
                CHECK_MSG(t.border_edges == 0, "%s k=%u: holes appeared", names[n], k);
            CHECK(adjacency_mismatches(&r) == 0);
            run_free(&r);
        }
        free(prot);
        pgt_mesh_destroy(&m);
    }
}

/* Vertex positions as sortable keys: the 12 bytes of a position. */
static int cmp_position(const void *a, const void *b) { return memcmp(a, b, 3 * sizeof(float)); }

/* Protection is local (issue 2: "equal to the unprotected result where no face is protected"):
 * with a small patch of faces protected, every output vertex of the unprotected run farther than
 * the reach below from every vertex of a protected face appears, with the same position bytes,
 * in the protected run's output, and a good part of the mesh is that far. The reach: iteration i
 * (from 0) relaxes each vertex from its one ring, and the flips it skips next to protected faces
 * change rings one edge further, so a difference moves at most two edges of level i per
 * iteration; level i's edges are at most the input's longest L over sqrt(3)^i (each iteration
 * trisects), so k iterations reach 2 L sum_i<k 3^(-i/2). (Measured on the noisy torus: the
 * farthest difference is 0.34, 0.60 and 0.88 L at k = 1, 2, 3 against 2, 3.2 and 3.8 L.) */
#define PROTECTION_REACH_EDGES 2.0
static void protection_is_local(void) {
    const char *names[] = {"noisy_torus_48x24", "cube_sphere_8"};
    for (size_t n = 0; n < sizeof names / sizeof *names; ++n) {
        pgt_mesh m = gen(names[n]);
        REQUIRE(m.face_count > 0);
        double longest = 0.0; /* the input's longest edge */
        for (uint32_t f = 0; f < m.face_count; ++f)
            for (int c = 0; c < 3; ++c) {
                const float *p = m.positions + 3 * (size_t)m.indices[3 * (size_t)f + c];
                const float *q = m.positions + 3 * (size_t)m.indices[3 * (size_t)f + (c + 1) % 3];
                double e = 0.0;
                for (int a = 0; a < 3; ++a) e += ((double)p[a] - q[a]) * ((double)p[a] - q[a]);
                longest = fmax(longest, sqrt(e));
            }
        /* the patch: the first 2.5 % of the faces (generated meshes list faces in grid order) */
        uint8_t *prot = calloc(m.face_count, 1), *pv = calloc(m.vertex_count, 1);
        REQUIRE(prot && pv);
        const uint32_t np = m.face_count / 40u;
        for (uint32_t f = 0; f < np; ++f) {
            prot[f] = 1;
            for (int c = 0; c < 3; ++c) pv[m.indices[3 * (size_t)f + c]] = 1;
        }
        REQUIRE(np > 0 && np * 10u < m.face_count);
        for (uint32_t k = 1; k <= 3; ++k) {
            run a, b;
            REQUIRE(run_sqrt3(&a, &m, k, 2, NULL));
            REQUIRE(run_sqrt3(&b, &m, k, 2, prot));
            float *sorted = malloc((size_t)b.out.vertex_count * 3 * sizeof(float));
            REQUIRE(sorted);
            memcpy(sorted, b.out.positions, (size_t)b.out.vertex_count * 3 * sizeof(float));
            qsort(sorted, b.out.vertex_count, 3 * sizeof(float), cmp_position);
            double reach = 0.0;
            for (uint32_t i = 0; i < k; ++i)
                reach += PROTECTION_REACH_EDGES * longest / pow(sqrt(3.0), i);
            uint32_t far = 0, missing = 0;
            for (uint32_t v = 0; v < a.out.vertex_count; ++v) {
                const float *p = a.out.positions + 3 * (size_t)v;
                double near = INFINITY;
                for (uint32_t u = 0; u < m.vertex_count; ++u) {
                    if (!pv[u]) continue;
                    double d = 0.0;
                    for (int c = 0; c < 3; ++c) {
                        const double x = (double)p[c] - m.positions[3 * (size_t)u + c];
                        d += x * x;
                    }
                    near = fmin(near, d);
                }
                if (!(sqrt(near) > reach)) continue;
                far++;
                missing += !bsearch(p, sorted, b.out.vertex_count, 3 * sizeof(float), cmp_position);
            }
            CHECK_MSG(missing == 0,
                      "%s k=%u: %u of %u vertices far from the protected patch differ", names[n], k,
                      missing, far);
            CHECK_MSG(far * 4u > a.out.vertex_count, "%s k=%u: only %u of %u vertices far",
                      names[n], k, far, a.out.vertex_count);
            free(sorted);
            run_free(&a), run_free(&b);
        }
        free(prot), free(pv);
        pgt_mesh_destroy(&m);
    }
}

/* UVs inside one chart get the same weights as positions: on the flat grid with uv = (x, y),
 * every output corner's UV equals its vertex's (x, y), to the last bit (the same float operations
 * in the same order), through the border rule too. */
static void uvs_follow_positions_in_one_chart(void) {
    pgt_mesh m = gen("grid_16x16");
    REQUIRE(m.face_count > 0 && m.uvs);
    for (uint32_t k = 1; k <= 3; ++k) {
        run r;
        REQUIRE(run_sqrt3(&r, &m, k, 2, NULL));
        REQUIRE(r.out.uvs != NULL);
        uint32_t bad = 0;
        for (uint32_t c = 0; c < 3 * r.out.face_count; ++c) {
            const float *p = r.out.positions + 3 * (size_t)r.out.indices[c];
            bad += r.out.uvs[2 * (size_t)c] != p[0] || r.out.uvs[2 * (size_t)c + 1] != p[1];
        }
        CHECK_MSG(bad == 0, "k=%u: %u corners whose uv is not their (x, y)", k, bad);
        run_free(&r);
    }
    pgt_mesh_destroy(&m);
}

/* Twice the signed area of face f's UV triangle. */
static double uv_area2(const pgt_mesh *m, uint32_t f) {
    const float *u = m->uvs + 6 * (size_t)f;
    return ((double)u[2] - u[0]) * ((double)u[5] - u[1]) -
           ((double)u[4] - u[0]) * ((double)u[3] - u[1]);
}

/* Charts of a mesh: faces joined across edges whose two corner UVs match on both faces; the
 * charts of one triangle go to *single and those whose every UV triangle has zero area to *flat
 * (either may be NULL). */
static uint32_t count_charts_flat(const pgt_mesh *m, uint32_t *single, uint32_t *flat) {
    pgt_adjacency a;
    if (pgt_adjacency_build(&a, m, 1, NULL) != PGT_OK) return 0;
    uint32_t *chart = malloc(m->face_count * sizeof(uint32_t)),
             *stack = malloc(m->face_count * sizeof(uint32_t));
    for (uint32_t f = 0; f < m->face_count; ++f) chart[f] = PGT_NONE;
    uint32_t charts = 0;
    for (uint32_t s = 0; s < m->face_count; ++s) {
        if (chart[s] != PGT_NONE) continue;
        uint32_t top = 0, size = 0, with_area = 0;
        stack[top++] = s;
        chart[s] = charts;
        while (top) {
            size++;
            uint32_t f = stack[--top];
            with_area += uv_area2(m, f) != 0.0;
            for (uint32_t c = 0; c < 3; ++c) {
                uint32_t h = 3 * f + c, o = a.opposite[h];
                if (o == PGT_NONE || chart[o / 3] != PGT_NONE) continue;
                const float *u = m->uvs;
                uint32_t hn = pgt_half_edge_next(h), on = pgt_half_edge_next(o);
                if (u[2 * h] == u[2 * on] && u[2 * h + 1] == u[2 * on + 1] &&
                    u[2 * hn] == u[2 * o] && u[2 * hn + 1] == u[2 * o + 1]) {
                    chart[o / 3] = charts;
                    stack[top++] = o / 3;
                }
            }
        }
        charts++;
        if (single) *single += size == 1;
        if (flat) *flat += with_area == 0;
    }
    free(chart), free(stack);
    pgt_adjacency_destroy(&a);
    return charts;
}

static uint32_t count_charts(const pgt_mesh *m, uint32_t *single) {
    return count_charts_flat(m, single, NULL);
}

/* Edges whose two faces agree on the UV at one end and not at the other: a vertex with two UVs
 * in one chart there (a slit's tip), where UV triangles may overlap. */
static uint32_t count_half_agreeing_edges(const pgt_mesh *m) {
    pgt_adjacency a;
    if (pgt_adjacency_build(&a, m, 1, NULL) != PGT_OK) return PGT_NONE;
    const float *u = m->uvs;
    uint32_t n = 0;
    for (uint32_t h = 0; h < a.half_edge_count; ++h) {
        const uint32_t o = a.opposite[h];
        if (o == PGT_NONE || o < h) continue;
        const uint32_t hn = pgt_half_edge_next(h), on = pgt_half_edge_next(o);
        const int at_a = u[2 * h] == u[2 * on] && u[2 * h + 1] == u[2 * on + 1];
        const int at_b = u[2 * hn] == u[2 * o] && u[2 * hn + 1] == u[2 * o + 1];
        n += at_a != at_b;
    }
    pgt_adjacency_destroy(&a);
    return n;
}

/* Across chart seams (the cube-sphere's 6 charts): the atlas stays an atlas. No UV triangle folds
 * over (all keep a positive signed area) and the charts stay the 6, none of one triangle, at
 * every k: a flipped seam edge's two triangles go into one chart (the seam becomes a tent,
 * README "UVs and chart seams"). When each stayed in its own face's chart, every chart corner
 * left a one-triangle chart at k = 1 (18 charts) and every tooth of the zigzag seam one more at
 * each further iteration (222 at k = 2, 1014 at k = 3). */
static void uvs_across_seams_stay_an_atlas(void) {
    pgt_mesh m = gen("cube_sphere_8");
    REQUIRE(m.face_count > 0 && m.uvs);
    CHECK(count_charts(&m, NULL) == 6);
    for (uint32_t k = 1; k <= 3; ++k) {
        run r;
        REQUIRE(run_sqrt3(&r, &m, k, 2, NULL));
        uint32_t folded = 0;
        for (uint32_t f = 0; f < r.out.face_count; ++f) {
            folded += !(uv_area2(&r.out, f) > 0.0);
        }
        uint32_t single = 0;
        const uint32_t charts = count_charts(&r.out, &single);
        CHECK_MSG(folded == 0, "k=%u: %u folded UV triangles", k, folded);
        CHECK_MSG(charts == 6 && single == 0, "k=%u: %u charts, %u of one triangle", k, charts,
                  single);
        run_free(&r);
    }
    pgt_mesh_destroy(&m);
}

/* UV triangle diameter (max edge length). */
static double uv_diameter(const float *u) {
    double d = 0.0;
    for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3;
        double x = (double)u[2 * i] - u[2 * j], y = (double)u[2 * i + 1] - u[2 * j + 1];
        d = fmax(d, sqrt(x * x + y * y));
    }
    return d;
}

/* On a real atlas (spot: 13 charts, one of them mirrored) the point carried across a seam must
 * stay near the seam: no output UV triangle more than twice the
 * diameter of the larger input face it joins (the face it comes from and the one whose new point it
 * has: across a seam it lies in one of their charts, whose scales differ up to 8 times on spot),
 * over three iterations run one at a time so that each output triangle's face points name their
 * input faces. Measured: 1.51 at most with the seam guard (S3_SEAM_MAX_STRETCH, mirrored charts
 * reflected) when each triangle stayed in its own face's chart, 7.2-8.4 without the guard, the
 * spikes that crossed the atlas. */
#define UV_SEAM_MAX_GROWTH 2.0
static void uvs_no_spikes_on_a_real_atlas(void) {
    char path[1024];
    snprintf(path, sizeof path, "%s/spot.obj", PGT_SHARED_MESH_DIR);
    pgt_mesh m;
    pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, NULL};
    REQUIRE(pgt_mesh_read(&m, path, &ro, NULL) == PGT_OK && m.uvs);
    for (uint32_t k = 1; k <= 3; ++k) {
        run r;
        REQUIRE(run_sqrt3(&r, &m, 1, 2, NULL));
        double worst = 0.0;
        for (uint32_t t = 0; t < r.out.face_count; ++t) {
            double pd = uv_diameter(m.uvs + 6 * (size_t)r.parent[t]);
            for (int c = 0; c < 3; ++c) { /* a face point: vertex V + f of input face f */
                const uint32_t v = r.out.indices[3 * (size_t)t + (size_t)c];
                if (v >= m.vertex_count)
                    pd = fmax(pd, uv_diameter(m.uvs + 6 * (size_t)(v - m.vertex_count)));
            }
            if (pd > 0.0) worst = fmax(worst, uv_diameter(r.out.uvs + 6 * (size_t)t) / pd);
        }
        CHECK_MSG(worst <= UV_SEAM_MAX_GROWTH, "k=%u: a UV triangle %.2f x its input faces", k,
                  worst);
        printf("  spot, iteration %u: the largest UV triangle %.2f x its input faces\n", k, worst);
        run_next_input(&r, &m);
    }
    pgt_mesh_destroy(&m);
}

/* The charts of real atlases stay whole over three iterations (run one at a time): as many as
 * the input has, less those made only of zero-area UV triangles (human_neutral has two such
 * one-triangle charts; their neighbours absorb them), none of one triangle. With one triangle
 * per face in its own chart they were spot 41 / 645 / 3005, bob 15 / 3051 at k = 1 / 3,
 * human_neutral 115 / 10014. And no vertex gets a second UV in one chart beyond the input's
 * slit tips (count_half_agreeing_edges: spot 0, bob 6, human_neutral 75): a face point carried
 * into one chart through two seams did so on spot at k = 2 before s3_uv_tent gave such an edge
 * back. */
/* pizza's charts of one triangle after each iteration, at most this share of the input's 1987:
 * a few edges keep one triangle per face where no chart takes both unfolded, so a few such
 * charts stay (measured 15, 5, 3), where one triangle per face everywhere made 14,313 at k = 1. */
#define UV_SINGLE_CHARTS_MAX_SHARE 0.1
static void uv_charts_stay_whole_on_real_atlases(void) {
    /* pizza (4740 charts, 1987 of one triangle) is measured and printed (README "UVs and chart
     * seams"); of its charts only those of one triangle are checked */
    static const struct {
        const char *name;
        int whole;
    } meshes[] = {{"spot.obj", 1}, {"bob_tri.obj", 1}, {"human_neutral.obj", 1}, {"pizza.obj", 0}};
    for (size_t i = 0; i < sizeof meshes / sizeof meshes[0]; ++i) {
        const char *name = meshes[i].name;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", PGT_SHARED_MESH_DIR, name);
        pgt_mesh m;
        pgt_mesh_read_options ro = {PGT_FORMAT_AUTO, 1, NULL};
        REQUIRE(pgt_mesh_read(&m, path, &ro, NULL) == PGT_OK && m.uvs);
        uint32_t flat = 0, single_in = 0;
        const uint32_t want = count_charts_flat(&m, &single_in, &flat) - flat,
                       tips = count_half_agreeing_edges(&m);
        for (uint32_t k = 1; k <= 3; ++k) {
            run r;
            REQUIRE(run_sqrt3(&r, &m, 1, 2, NULL));
            /* one iteration a call and no protected face: every face gets its point, V + f */
            REQUIRE(r.out.vertex_count == m.vertex_count + m.face_count);
            uint32_t single = 0;
            const uint32_t charts = count_charts(&r.out, &single),
                           half = count_half_agreeing_edges(&r.out);
            if (meshes[i].whole) {
                CHECK_MSG(charts == want && single == 0,
                          "%s k=%u: %u charts (want %u), %u of one triangle", name, k, charts, want,
                          single);
                CHECK_MSG(half <= tips, "%s k=%u: %u edges agree on one end's UV (the input: %u)",
                          name, k, half, tips);
            } else {
                CHECK_MSG(single <= UV_SINGLE_CHARTS_MAX_SHARE * single_in,
                          "%s k=%u: %u charts of one triangle (the input: %u)", name, k, single,
                          single_in);
            }
            /* fold-overs: an output UV triangle whose orientation is that of none of the input
             * faces it joins (the one it comes from, those whose points it has) */
            uint32_t folded = 0;
            for (uint32_t t = 0; t < r.out.face_count; ++t) {
                const double area = uv_area2(&r.out, t);
                int agrees = (area > 0.0) == (uv_area2(&m, r.parent[t]) > 0.0);
                for (int c = 0; c < 3; ++c) {
                    const uint32_t v = r.out.indices[3 * (size_t)t + (size_t)c];
                    if (v >= m.vertex_count)
                        agrees |= (area > 0.0) == (uv_area2(&m, v - m.vertex_count) > 0.0);
                }
                folded += area != 0.0 && !agrees;
            }
            printf("  %s, iteration %u: %u charts (the input's %u less %u of zero UV area), %u "
                   "of one triangle, %u edges agreeing on one end's UV, %u of %u UV triangles "
                   "folded\n",
                   name, k, charts, want + flat, flat, single, half, folded, r.out.face_count);
            run_next_input(&r, &m);
        }
        pgt_mesh_destroy(&m);
    }
}

/* Cuts the cube-sphere's 6 charts into patches of 4 to 9 faces grown at random (seed) across
 * non-seam edges, each moved by its own rotation, scale (0.5-2) and translation in UV: charts of a
 * few triangles beside each other, as pizza's photogrammetry layout has, where a patch can wrap
 * around a vertex with a face of another patch in between. Returns the number of patches. */
static uint32_t make_uv_patches(pgt_mesh *m, uint32_t seed) {
    pgt_adjacency a;
    if (pgt_adjacency_build(&a, m, 1, NULL) != PGT_OK) return 0;
    const uint32_t F = m->face_count;
    uint32_t *patch = malloc(F * sizeof(uint32_t)), *members = malloc(F * sizeof(uint32_t));
    for (uint32_t f = 0; f < F; ++f) patch[f] = PGT_NONE;
    uint32_t patches = 0, draw = 0;
    for (uint32_t s = 0; s < F; ++s) {
        if (patch[s] != PGT_NONE) continue;
        const uint32_t size = 4u + (uint32_t)(6.0f * pgt_rng_float(seed, 1, draw++));
        uint32_t n = 0;
        members[n++] = s, patch[s] = patches;
        for (uint32_t i = 0; i < n && n < size; ++i) /* grow breadth-first within one chart */
            for (uint32_t c = 0; c < 3 && n < size; ++c) {
                const uint32_t h = 3 * members[i] + c, o = a.opposite[h];
                if (o == PGT_NONE || patch[o / 3] != PGT_NONE) continue;
                const uint32_t hn = pgt_half_edge_next(h), on = pgt_half_edge_next(o);
                const float *u = m->uvs;
                if (u[2 * h] == u[2 * on] && u[2 * h + 1] == u[2 * on + 1] &&
                    u[2 * hn] == u[2 * o] && u[2 * hn + 1] == u[2 * o + 1])
                    members[n++] = o / 3, patch[o / 3] = patches;
            }
        patches++;
    }
    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t p = patch[f];
        const double angle = 6.283185307179586 * pgt_rng_double(seed, 2, 4u * p),
                     scale = 0.5 + 1.5 * pgt_rng_double(seed, 2, 4u * p + 1),
                     tx = 6.0 * pgt_rng_double(seed, 2, 4u * p + 2) - 3.0,
                     ty = 6.0 * pgt_rng_double(seed, 2, 4u * p + 3) - 3.0;
        const double c = scale * cos(angle), sn = scale * sin(angle);
        for (int k = 0; k < 3; ++k) {
            float *u = m->uvs + 6 * (size_t)f + 2 * k;
            const double x = u[0], y = u[1];
            u[0] = (float)(c * x - sn * y + tx), u[1] = (float)(sn * x + c * y + ty);
        }
    }
    free(patch), free(members);
    pgt_adjacency_destroy(&a);
    return patches;
}

/* Charts of a few triangles (make_uv_patches, five layouts): over three iterations (run one at a
 * time) every patch stays one chart, none of one triangle, and no vertex gets two UVs in one
 * chart. A face whose point two neighbours of one chart would both carry into it (through two
 * different seam maps) gives one of the two edges back (s3_uv_tent); without that, 5 to 12 edges
 * of each layout agreed on one end's UV only from k = 1 on, with UV triangles overlapping there. */
static void uv_patches_stay_whole(void) {
    for (uint32_t seed = 1; seed <= 5; ++seed) {
        pgt_mesh m = gen("cube_sphere_8");
        REQUIRE(m.face_count > 0 && m.uvs);
        const uint32_t patches = make_uv_patches(&m, seed);
        CHECK(patches > 6 && count_charts(&m, NULL) == patches);
        CHECK(count_half_agreeing_edges(&m) == 0);
        for (uint32_t k = 1; k <= 3; ++k) {
            run r;
            REQUIRE(run_sqrt3(&r, &m, 1, 2, NULL));
            uint32_t single = 0;
            const uint32_t charts = count_charts(&r.out, &single),
                           half = count_half_agreeing_edges(&r.out);
            CHECK_MSG(charts == patches && single == 0 && half == 0,
                      "seed %u k=%u: %u charts of %u patches, %u of one triangle, %u edges "
                      "agreeing on one end's UV",
                      seed, k, charts, patches, single, half);
            run_next_input(&r, &m);
        }
        pgt_mesh_destroy(&m);
    }
}

/* Non-manifold input is refused with an error naming the offending edge or vertex. */
static void refuses_non_manifold(void) {
    /* three triangles on edge (0, 1) */
    float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 5, 5, 5, 6, 5, 5, 5, 6, 5};
    uint32_t fan3[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    pgt_mesh m = {8, 3, p, fan3, NULL, NULL};
    pgt_mesh out;
    pgt_error err = {0};
    CHECK(pgt_sqrt3_subdivide(&out, &m, NULL, &err) == PGT_ERROR_NON_MANIFOLD);
    CHECK_MSG(strstr(err.message, "edge (0, 1)") != NULL, "message: %s", err.message);
    /* bowtie: two triangles meeting only at vertex 0 */
    uint32_t bowtie[] = {0, 1, 2, 0, 5, 6};
    pgt_mesh b = {8, 2, p, bowtie, NULL, NULL};
    pgt_error_clear(&err);
    CHECK(pgt_sqrt3_subdivide(&out, &b, NULL, &err) == PGT_ERROR_NON_MANIFOLD);
    CHECK_MSG(strstr(err.message, "vertex 0") != NULL, "message: %s", err.message);
    /* inconsistent orientation: edge 0 -> 1 used twice in the same direction */
    uint32_t flipped[] = {0, 1, 2, 0, 1, 3};
    pgt_mesh c = {8, 2, p, flipped, NULL, NULL};
    pgt_error_clear(&err);
    CHECK(pgt_sqrt3_subdivide(&out, &c, NULL, &err) == PGT_ERROR_NON_MANIFOLD);
    /* degenerate face */
    uint32_t degen[] = {0, 1, 1};
    pgt_mesh d = {8, 1, p, degen, NULL, NULL};
    pgt_error_clear(&err);
    CHECK(pgt_sqrt3_subdivide(&out, &d, NULL, &err) == PGT_ERROR_DEGENERATE);
    /* the face each error is about (what pgt subdiv turns into the file's line): the
     * degenerate face, the first face with the edge, the first face at the vertex; a face
     * without the problem comes first in each, so that face 0 would be wrong */
    uint32_t later_degen[] = {5, 6, 7, 0, 1, 2, 0, 2, 2, 1, 1, 3};
    uint32_t later_edge[] = {5, 6, 7, 1, 0, 3, 0, 1, 2, 0, 1, 4};
    uint32_t later_bowtie[] = {2, 1, 7, 0, 1, 2, 0, 5, 6};
    /* a triangle on both sides: a 2-manifold whose flips would give one edge twice (the output
     * of one step had an edge of 6 faces) */
    uint32_t later_pillow[] = {5, 6, 7, 0, 1, 2, 0, 2, 1};
    const struct {
        uint32_t *faces, count, face;
        pgt_result code;
    } located[] = {{later_degen, 4, 2, PGT_ERROR_DEGENERATE},
                   {later_edge, 4, 1, PGT_ERROR_NON_MANIFOLD},
                   {later_bowtie, 3, 1, PGT_ERROR_NON_MANIFOLD},
                   {later_pillow, 3, 1, PGT_ERROR_NON_MANIFOLD},
                   {fan3, 3, 0, PGT_ERROR_NON_MANIFOLD}};
    for (size_t i = 0; i < sizeof(located) / sizeof(located[0]); ++i) {
        pgt_mesh lm = {8, located[i].count, p, located[i].faces, NULL, NULL};
        pgt_adjacency a;
        REQUIRE(pgt_adjacency_build(&a, &lm, 1, NULL) == PGT_OK);
        CHECK(pgt_adjacency_require_manifold(&a, "test", NULL) == located[i].code);
        CHECK_MSG(pgt_adjacency_error_face(&a) == located[i].face, "case %zu: face %u", i,
                  pgt_adjacency_error_face(&a));
        pgt_adjacency_destroy(&a);
    }
    pgt_adjacency good;
    pgt_mesh one = {8, 1, p, fan3, NULL, NULL};
    REQUIRE(pgt_adjacency_build(&good, &one, 1, NULL) == PGT_OK);
    CHECK(pgt_adjacency_error_face(&good) == PGT_NONE);
    pgt_adjacency_destroy(&good);
    /* out-of-range index and too many iterations */
    uint32_t oob[] = {0, 1, 9};
    pgt_mesh e = {8, 1, p, oob, NULL, NULL};
    pgt_error_clear(&err);
    CHECK(pgt_sqrt3_subdivide(&out, &e, NULL, &err) == PGT_ERROR_INDEX_RANGE);
    pgt_sqrt3_options o = {PGT_SQRT3_MAX_ITERATIONS + 1, 1, NULL, NULL, NULL, NULL, NULL};
    pgt_error_clear(&err);
    CHECK(pgt_sqrt3_subdivide(&out, &m, &o, &err) == PGT_ERROR_LIMIT);
    /* an output that would overflow 32-bit indices is refused before any allocation */
    pgt_mesh big;
    REQUIRE(pgt_gen_bench_torus(&big, 10000, NULL) == PGT_OK); /* 10^4 x 3^12 faces > 2^30 */
    pgt_sqrt3_options o12 = {12, 1, NULL, NULL, NULL, NULL, NULL};
    pgt_error_clear(&err);
    CHECK(pgt_sqrt3_subdivide(&out, &big, &o12, &err) == PGT_ERROR_LIMIT);
    pgt_mesh_destroy(&big);
    /* coordinates whose float sums overflow (an icosahedron at 3e38: the relaxed vertices were
     * inf) are refused; at PGT_SQRT3_MAX_COORD every output coordinate is finite */
    pgt_mesh ico = gen("icosphere_l0");
    float big_c = 0.0f;
    for (uint32_t i = 0; i < 3u * ico.vertex_count; ++i)
        big_c = fmaxf(big_c, fabsf(ico.positions[i]));
    for (uint32_t i = 0; i < 3u * ico.vertex_count; ++i)
        ico.positions[i] = ico.positions[i] / big_c * 3e38f;
    pgt_error_clear(&err);
    CHECK(pgt_sqrt3_subdivide(&out, &ico, NULL, &err) == PGT_ERROR_LIMIT);
    CHECK_MSG(strstr(err.message, "beyond +-1e+18") != NULL, "%s", err.message);
    for (uint32_t i = 0; i < 3u * ico.vertex_count; ++i)
        ico.positions[i] *= PGT_SQRT3_MAX_COORD / 3e38f;
    pgt_sqrt3_options o3 = {3, 1, NULL, NULL, NULL, NULL, NULL};
    pgt_error_clear(&err);
    const pgt_result r3 = pgt_sqrt3_subdivide(&out, &ico, &o3, &err);
    CHECK_MSG(r3 == PGT_OK, "%s", err.message);
    if (r3 != PGT_OK) return;
    uint32_t finite = 0;
    for (uint32_t i = 0; i < 3u * out.vertex_count; ++i) finite += isfinite(out.positions[i]) != 0;
    CHECK(finite == 3u * out.vertex_count);
    pgt_mesh_destroy(&out);
    pgt_mesh_destroy(&ico);
}

/* eq. 4.1 in float32 against double: the neighbour sum of n <= 8 coordinates of magnitude
 * <= 1.5 (the meshes below) rounds n times by at most half an ulp of 12 (9.5e-7 / 2), scaled by
 * alpha_n / n <= 0.14; alpha_n rounded to float and the two products and the sum add a few
 * 6e-8 roundings of |p| <= 1.5. That is below 6e-7; 1e-6 leaves room. */
#define RELAX_TOL 1e-6

/* A closed bipyramid over an n-gon (apexes of valence n, equator vertices of valence 4), every
 * vertex moved by up to 0.1 at random (seeded) so that no vertex is its neighbours' mean. */
static int noisy_bipyramid(pgt_mesh *m, uint32_t n, uint32_t seed) {
    if (pgt_mesh_create(m, n + 2, 2 * n, 0, 0, NULL) != PGT_OK) return 0;
    const double two_pi = 6.283185307179586;
    for (uint32_t v = 0; v < n + 2; ++v) {
        double p[3] = {0.0, 0.0, v == n ? 1.0 : -1.0};
        if (v < n) p[0] = cos(two_pi * v / n), p[1] = sin(two_pi * v / n), p[2] = 0.0;
        for (int k = 0; k < 3; ++k)
            m->positions[3 * v + (uint32_t)k] =
                (float)(p[k] + 0.2 * pgt_rng_double(seed, n, 3u * v + (uint32_t)k) - 0.1);
    }
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1) % n;
        uint32_t *top = m->indices + 6 * i, *bottom = top + 3;
        top[0] = i, top[1] = j, top[2] = n;
        bottom[0] = j, bottom[1] = i, bottom[2] = n + 1;
    }
    return 1;
}

/* eq. 4.1-4.2 re-derived in double for every interior vertex of `in` of valence 3 to 8:
 * alpha_n = (4 - 2 cos(2 pi / n)) / 9 with a double cos (not pgt_sqrt3_alpha), then
 * p' = (1 - alpha_n) p + alpha_n / n sum p_i over its one ring, against `out` (one iteration).
 * Returns the worst coordinate difference; marks the valences seen. */
static double relax_worst(const pgt_mesh *in, const pgt_mesh *out, uint32_t *seen) {
    pgt_adjacency a;
    if (pgt_adjacency_build(&a, in, 1, NULL) != PGT_OK) return INFINITY;
    const double pi = 3.14159265358979323846;
    double worst = 0.0;
    for (uint32_t v = 0; v < in->vertex_count; ++v) {
        double sum[3] = {0.0, 0.0, 0.0};
        uint32_t n = 0, border = 0;
        for (uint32_t h = 0; h < a.half_edge_count; ++h)
            if (in->indices[h] == v) {
                const uint32_t w = in->indices[pgt_half_edge_next(h)];
                for (int k = 0; k < 3; ++k) sum[k] += in->positions[3 * (size_t)w + k];
                n++;
                border +=
                    a.opposite[h] == PGT_NONE || a.opposite[pgt_half_edge_prev(h)] == PGT_NONE;
            }
        if (n < 3 || n > 8 || border) continue;
        seen[n] = 1;
        const double alpha = (4.0 - 2.0 * cos(2.0 * pi / n)) / 9.0;
        for (int k = 0; k < 3; ++k) {
            const double p = in->positions[3 * (size_t)v + k];
            const double want = (1.0 - alpha) * p + alpha / n * sum[k];
            worst = fmax(worst, fabs(want - (double)out->positions[3 * (size_t)v + k]));
        }
    }
    pgt_adjacency_destroy(&a);
    return worst;
}

/* Every interior vertex after one iteration against the double formula: noisy bipyramids over
 * 3- to 8-gons (apexes of valence 3 to 8, equator vertices of valence 4), the noisy torus
 * (valence 6, moved by the noise) and the icosahedron (valence 5). */
static void relaxation_weights(void) {
    uint32_t seen[9] = {0};
    double worst = 0.0;
    for (uint32_t n = 3; n <= 8; ++n) {
        pgt_mesh m;
        REQUIRE(noisy_bipyramid(&m, n, 29));
        REQUIRE(topo_of(&m).manifold);
        run r;
        REQUIRE(run_sqrt3(&r, &m, 1, 1, NULL));
        worst = fmax(worst, relax_worst(&m, &r.out, seen));
        run_free(&r);
        pgt_mesh_destroy(&m);
    }
    const char *names[] = {"noisy_torus_48x24", "icosphere_l0"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
        pgt_mesh m = gen(names[i]);
        REQUIRE(m.face_count > 0);
        run r;
        REQUIRE(run_sqrt3(&r, &m, 1, 2, NULL));
        worst = fmax(worst, relax_worst(&m, &r.out, seen));
        run_free(&r);
        pgt_mesh_destroy(&m);
    }
    printf("  relaxed vertices of valence 3 to 8: worst %.3g from the double formula\n", worst);
    for (uint32_t n = 3; n <= 8; ++n) CHECK_MSG(seen[n], "no interior vertex of valence %u", n);
    CHECK(worst <= RELAX_TOL);
}

/* A pgt_progress only observes: the same bytes with one, and it ends on the sqrt(3) stage with
 * every iteration counted (a border mesh, so that both rules run). */
static void progress_counts_iterations(void) {
    pgt_mesh m = gen("grid_16x16");
    pgt_progress *p = pgt_progress_create();
    REQUIRE(p);
    for (uint32_t k = 0; k <= 4; ++k) {
        pgt_mesh a, b;
        pgt_sqrt3_options o = {k, 2, NULL, NULL, NULL, NULL, NULL};
        REQUIRE(pgt_sqrt3_subdivide(&a, &m, &o, NULL) == PGT_OK);
        o.progress = p;
        REQUIRE(pgt_sqrt3_subdivide(&b, &m, &o, NULL) == PGT_OK);
        CHECK(a.vertex_count == b.vertex_count && a.face_count == b.face_count);
        CHECK(!memcmp(a.positions, b.positions, (size_t)a.vertex_count * 12));
        CHECK(!memcmp(a.indices, b.indices, (size_t)a.face_count * 12));
        pgt_progress_state st;
        pgt_progress_read(p, &st);
        CHECK_MSG(st.stages == k + 1 && !strcmp(st.stage, "sqrt(3)") &&
                      !strcmp(st.unit, "iterations") && st.total == k && st.done == k,
                  "k=%u: stage %u '%s', %llu of %llu %s", k, st.stages, st.stage,
                  (unsigned long long)st.done, (unsigned long long)st.total, st.unit);
        pgt_mesh_destroy(&a), pgt_mesh_destroy(&b);
    }
    pgt_progress_destroy(p);
    pgt_mesh_destroy(&m);
}

static const pgt_test_case cases[] = {
    {"closed_counts_and_adjacency", closed_counts_and_adjacency},
    {"closed_fast_path_equals_general", closed_fast_path_equals_general},
    {"border_counts_per_rule", border_counts_per_rule},
    {"border_rule_per_iteration", border_rule_per_iteration},
    {"adjacency_high_valence", adjacency_high_valence},
    {"deterministic_across_threads", deterministic_across_threads},
    {"parity_restarts_per_call", parity_restarts_per_call},
    {"zero_iterations_and_empty_protection", zero_iterations_and_empty_protection},
    {"protected_faces_bit_identical", protected_faces_bit_identical},
    {"protection_is_local", protection_is_local},
    {"uvs_follow_positions_in_one_chart", uvs_follow_positions_in_one_chart},
    {"uvs_across_seams_stay_an_atlas", uvs_across_seams_stay_an_atlas},
    {"uv_charts_stay_whole_on_real_atlases", uv_charts_stay_whole_on_real_atlases},
    {"uv_patches_stay_whole", uv_patches_stay_whole},
    {"uvs_no_spikes_on_a_real_atlas", uvs_no_spikes_on_a_real_atlas},
    {"refuses_non_manifold", refuses_non_manifold},
    {"relaxation_weights", relaxation_weights},
    {"progress_counts_iterations", progress_counts_iterations},
};

PGT_TEST_MAIN(cases)
