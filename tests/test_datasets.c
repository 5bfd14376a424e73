/* Tests of datasets_gen: every generator against closed-form counts and invariants computed here
 * from the raw arrays (edges from a sort of vertex pairs, fans from shared edges), independently
 * of the reference's adjacency module. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"
#include "test_util.h"

/* float32 rounding of unit-length coordinates moves |p| by about 1e-7; 1e-6 leaves 10x room. */
#define UNIT_SPHERE_TOL 1e-6
/* Torus implicit equation residual: coordinates near 1.4 rounded to float32 (~1e-7 each) make
 * (sqrt(x^2+y^2) - R)^2 + z^2 - r^2 off by ~1e-7; 1e-5 is the contract in the brief. */
#define TORUS_TOL 1e-5

/* ---------------------------------------------------------------------------------------------
 * Topology measured from the arrays */

typedef struct topo {
    uint32_t edges;
    uint32_t boundary_edges;
    uint32_t bad_edges;          /* more than two faces, or two faces in the same direction */
    uint32_t degenerate_faces;   /* repeated vertex index */
    uint32_t bad_indices;        /* index >= vertex_count */
    uint32_t duplicate_faces;    /* same vertex set, either winding */
    uint32_t duplicate_vertices; /* two indices with identical positions */
    uint32_t non_manifold_vertices; /* faces around the vertex form more than one fan */
    uint32_t unused_vertices;
    uint32_t boundary_loops;
    int64_t euler;
    double signed_volume;        /* sum det(p0, p1, p2) / 6, double accumulation */
} topo;

typedef struct key_entry {
    uint64_t key;
    uint32_t index;
} key_entry;

static int compare_key_entry(const void *pa, const void *pb) {
    const key_entry *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return a->index < b->index ? -1 : a->index > b->index;
}

static uint32_t he_next(uint32_t h) { return h - h % 3 + (h % 3 + 1) % 3; }

/* Half-edges sorted by undirected (min, max) key; caller frees. */
static key_entry *sorted_half_edges(const pgt_mesh *m) {
    const uint32_t hc = 3 * m->face_count;
    key_entry *e = malloc(((size_t)hc + 1) * sizeof(*e));
    for (uint32_t h = 0; h < hc; ++h) {
        uint32_t a = m->indices[h], b = m->indices[he_next(h)];
        uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        e[h].key = (uint64_t)lo << 32 | hi;
        e[h].index = h;
    }
    qsort(e, hc, sizeof(*e), compare_key_entry);
    return e;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void uf_union(uint32_t *parent, uint32_t a, uint32_t b) {
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a != b) parent[a < b ? b : a] = a < b ? a : b;
}

static int compare_u64(const void *pa, const void *pb) {
    uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
    return a < b ? -1 : a > b;
}

static const float *position(const pgt_mesh *m, uint32_t v) { return m->positions + 3 * (size_t)v; }

/* qsort has no context argument in C11. */
static const pgt_mesh *compare_positions_mesh;
static int compare_positions(const void *pa, const void *pb) {
    const float *a = position(compare_positions_mesh, *(const uint32_t *)pa);
    const float *b = position(compare_positions_mesh, *(const uint32_t *)pb);
    for (int k = 0; k < 3; ++k)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

static topo measure(const pgt_mesh *m) {
    topo t;
    memset(&t, 0, sizeof(t));
    const uint32_t V = m->vertex_count, F = m->face_count, hc = 3 * F;

    for (uint32_t f = 0; f < F; ++f) {
        const uint32_t *i = m->indices + 3 * (size_t)f;
        if (i[0] >= V || i[1] >= V || i[2] >= V) t.bad_indices++;
        if (i[0] == i[1] || i[1] == i[2] || i[2] == i[0]) t.degenerate_faces++;
    }
    if (t.bad_indices) return t; /* nothing below is safe to index */

    /* Edges and their use. */
    key_entry *e = sorted_half_edges(m);
    uint32_t *boundary_next = malloc(((size_t)V + 1) * sizeof(uint32_t));
    for (uint32_t v = 0; v < V; ++v) boundary_next[v] = UINT32_MAX;
    uint32_t boundary_outgoing_conflicts = 0;
    for (uint32_t i = 0; i < hc;) {
        uint32_t j = i;
        while (j < hc && e[j].key == e[i].key) ++j;
        t.edges++;
        if (j - i == 1) {
            t.boundary_edges++;
            uint32_t h = e[i].index, from = m->indices[h], to = m->indices[he_next(h)];
            if (boundary_next[from] != UINT32_MAX) boundary_outgoing_conflicts++;
            boundary_next[from] = to;
        } else if (j - i == 2) {
            if (m->indices[e[i].index] == m->indices[e[i + 1].index]) t.bad_edges++;
        } else {
            t.bad_edges++;
        }
        i = j;
    }
    free(e);

    /* Boundary loops: with one fan per vertex each boundary vertex has one outgoing border edge. */
    if (boundary_outgoing_conflicts == 0) {
        uint8_t *seen = calloc((size_t)V + 1, 1);
        for (uint32_t v = 0; v < V; ++v) {
            if (boundary_next[v] == UINT32_MAX || seen[v]) continue;
            t.boundary_loops++;
            for (uint32_t w = v; w != UINT32_MAX && !seen[w]; w = boundary_next[w]) seen[w] = 1;
        }
        free(seen);
    } else {
        t.boundary_loops = UINT32_MAX;
    }
    free(boundary_next);

    /* Fans: faces around each vertex joined when they share an edge at that vertex. */
    uint32_t *start = calloc((size_t)V + 2, sizeof(uint32_t));
    uint32_t *incident = malloc(((size_t)hc + 1) * sizeof(uint32_t));
    for (uint32_t h = 0; h < hc; ++h) start[m->indices[h] + 1]++;
    for (uint32_t v = 0; v < V; ++v) start[v + 1] += start[v];
    uint32_t *fill = malloc(((size_t)V + 1) * sizeof(uint32_t));
    memcpy(fill, start, (size_t)V * sizeof(uint32_t));
    for (uint32_t h = 0; h < hc; ++h) incident[fill[m->indices[h]]++] = h / 3;
    free(fill);
    uint32_t parent[64];
    for (uint32_t v = 0; v < V; ++v) {
        const uint32_t n = start[v + 1] - start[v];
        if (n == 0) {
            t.unused_vertices++;
            continue;
        }
        if (n > 64) {
            t.non_manifold_vertices++; /* not expected from any generator */
            continue;
        }
        const uint32_t *fs = incident + start[v];
        for (uint32_t a = 0; a < n; ++a) parent[a] = a;
        for (uint32_t a = 0; a < n; ++a)
            for (uint32_t b = a + 1; b < n; ++b) {
                const uint32_t *fa = m->indices + 3 * (size_t)fs[a];
                const uint32_t *fb = m->indices + 3 * (size_t)fs[b];
                int shared = 0;
                for (int x = 0; x < 3; ++x)
                    for (int y = 0; y < 3; ++y)
                        if (fa[x] != v && fa[x] == fb[y]) shared = 1;
                if (shared) uf_union(parent, a, b);
            }
        uint32_t fans = 0;
        for (uint32_t a = 0; a < n; ++a) fans += uf_find(parent, a) == a;
        if (fans != 1) t.non_manifold_vertices++;
    }
    free(start);
    free(incident);

    /* Duplicate faces: sorted vertex triples. */
    uint64_t *tri_keys = malloc(((size_t)F + 1) * sizeof(uint64_t));
    for (uint32_t f = 0; f < F; ++f) {
        uint32_t a = m->indices[3 * f], b = m->indices[3 * f + 1], c = m->indices[3 * f + 2], s;
        if (a > b) s = a, a = b, b = s;
        if (b > c) s = b, b = c, c = s;
        if (a > b) s = a, a = b, b = s;
        /* 21 bits each is enough for every mesh these tests build (V < 2^21). */
        tri_keys[f] = (uint64_t)a << 42 | (uint64_t)b << 21 | c;
    }
    qsort(tri_keys, F, sizeof(uint64_t), compare_u64);
    for (uint32_t f = 1; f < F; ++f) t.duplicate_faces += tri_keys[f] == tri_keys[f - 1];
    free(tri_keys);

    /* Duplicate vertices: positions sorted lexicographically. */
    uint32_t *order = malloc(((size_t)V + 1) * sizeof(uint32_t));
    for (uint32_t v = 0; v < V; ++v) order[v] = v;
    compare_positions_mesh = m;
    qsort(order, V, sizeof(uint32_t), compare_positions);
    for (uint32_t v = 1; v < V; ++v)
        t.duplicate_vertices += compare_positions(&order[v], &order[v - 1]) == 0;
    free(order);

    for (uint32_t f = 0; f < F; ++f) {
        const float *p0 = position(m, m->indices[3 * f]), *p1 = position(m, m->indices[3 * f + 1]),
                    *p2 = position(m, m->indices[3 * f + 2]);
        double det = (double)p0[0] * ((double)p1[1] * p2[2] - (double)p1[2] * p2[1]) -
                     (double)p0[1] * ((double)p1[0] * p2[2] - (double)p1[2] * p2[0]) +
                     (double)p0[2] * ((double)p1[0] * p2[1] - (double)p1[1] * p2[0]);
        t.signed_volume += det / 6.0;
    }
    t.euler = (int64_t)V - (int64_t)t.edges + (int64_t)F;
    return t;
}

/* Everything a generator promises, for a mesh with the given Euler characteristic and number of
 * boundary loops (0 = closed). */
static void check_manifold(const pgt_mesh *m, const char *what, int64_t euler, uint32_t loops) {
    topo t = measure(m);
    CHECK_MSG(t.bad_indices == 0, "%s: %u out-of-range indices", what, t.bad_indices);
    CHECK_MSG(t.degenerate_faces == 0, "%s: %u degenerate faces", what, t.degenerate_faces);
    CHECK_MSG(t.bad_edges == 0, "%s: %u non-manifold or inconsistently oriented edges", what,
              t.bad_edges);
    CHECK_MSG(t.non_manifold_vertices == 0, "%s: %u non-manifold vertices", what,
              t.non_manifold_vertices);
    CHECK_MSG(t.unused_vertices == 0, "%s: %u unused vertices", what, t.unused_vertices);
    CHECK_MSG(t.duplicate_faces == 0, "%s: %u duplicate faces", what, t.duplicate_faces);
    CHECK_MSG(t.duplicate_vertices == 0, "%s: %u duplicate vertices", what,
              t.duplicate_vertices);
    CHECK_MSG(t.euler == euler, "%s: Euler characteristic %lld, expected %lld", what,
              (long long)t.euler, (long long)euler);
    CHECK_MSG(t.boundary_loops == loops, "%s: %u boundary loops, expected %u", what,
              t.boundary_loops, loops);
    if (loops == 0) {
        CHECK_MSG(t.boundary_edges == 0, "%s: %u boundary edges on a closed mesh", what,
                  t.boundary_edges);
        CHECK_MSG(t.signed_volume > 0.0, "%s: signed volume %g is not positive", what,
                  t.signed_volume);
    }
}

static void check_counts(const pgt_mesh *m, const char *what, uint64_t v, uint64_t f) {
    CHECK_MSG(m->vertex_count == v && m->face_count == f, "%s: V = %u, F = %u, expected %llu, %llu",
              what, m->vertex_count, m->face_count, (unsigned long long)v, (unsigned long long)f);
}

static double max_unit_sphere_error(const pgt_mesh *m) {
    double worst = 0.0;
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        const float *p = position(m, v);
        double len = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        if (fabs(len - 1.0) > worst) worst = fabs(len - 1.0);
    }
    return worst;
}

/* Faces whose normal points towards `center`-relative position (outward for star-shaped
 * surfaces around the center). Returns the number of faces that point inward. */
static uint32_t inward_faces_around_origin(const pgt_mesh *m) {
    uint32_t bad = 0;
    for (uint32_t f = 0; f < m->face_count; ++f) {
        const float *p0 = position(m, m->indices[3 * f]), *p1 = position(m, m->indices[3 * f + 1]),
                    *p2 = position(m, m->indices[3 * f + 2]);
        double e1[3], e2[3], n[3], c[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = (double)p1[k] - p0[k];
            e2[k] = (double)p2[k] - p0[k];
            c[k] = ((double)p0[k] + p1[k] + p2[k]) / 3.0;
        }
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        if (!(n[0] * c[0] + n[1] * c[1] + n[2] * c[2] > 0.0)) bad++;
    }
    return bad;
}

static pgt_error fresh_error(void) {
    pgt_error e;
    pgt_error_clear(&e);
    return e;
}

/* ---------------------------------------------------------------------------------------------
 * Icosphere */

static void icosphere_levels(void) {
    for (uint32_t level = 0; level <= 4; ++level) {
        pgt_mesh m;
        pgt_error err = fresh_error();
        REQUIRE(pgt_gen_icosphere(&m, level, &err) == PGT_OK);
        char what[64];
        snprintf(what, sizeof(what), "icosphere level %u", level);
        const uint64_t p = (uint64_t)1 << (2 * level);
        check_counts(&m, what, 10 * p + 2, 20 * p);
        check_manifold(&m, what, 2, 0);
        CHECK_MSG(max_unit_sphere_error(&m) <= UNIT_SPHERE_TOL, "%s: |p| off by %g", what,
                  max_unit_sphere_error(&m));
        CHECK_MSG(inward_faces_around_origin(&m) == 0, "%s: %u inward faces", what,
                  inward_faces_around_origin(&m));
        /* An inscribed polyhedron: volume below the ball's, and closing in on it. */
        topo t = measure(&m);
        const double ball = 4.0 / 3.0 * 3.14159265358979323846;
        CHECK(t.signed_volume < ball);
        if (level >= 3) CHECK(t.signed_volume > 0.98 * ball);
        pgt_mesh_destroy(&m);
    }
}

/* ---------------------------------------------------------------------------------------------
 * Tori */

static double max_torus_residual(const pgt_mesh *m, double R, double r) {
    double worst = 0.0;
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        const float *p = position(m, v);
        double q = sqrt((double)p[0] * p[0] + (double)p[1] * p[1]) - R;
        double res = fabs(q * q + (double)p[2] * p[2] - r * r);
        if (res > worst) worst = res;
    }
    return worst;
}

/* Faces pointing away from the tube's center circle (outward for a torus). */
static uint32_t inward_torus_faces(const pgt_mesh *m, double R) {
    uint32_t bad = 0;
    for (uint32_t f = 0; f < m->face_count; ++f) {
        const float *p0 = position(m, m->indices[3 * f]), *p1 = position(m, m->indices[3 * f + 1]),
                    *p2 = position(m, m->indices[3 * f + 2]);
        double e1[3], e2[3], n[3], c[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = (double)p1[k] - p0[k];
            e2[k] = (double)p2[k] - p0[k];
            c[k] = ((double)p0[k] + p1[k] + p2[k]) / 3.0;
        }
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double rho = sqrt(c[0] * c[0] + c[1] * c[1]);
        double d[3] = {c[0] - R * c[0] / rho, c[1] - R * c[1] / rho, c[2]};
        if (!(n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0.0)) bad++;
    }
    return bad;
}

static void torus_shapes(void) {
    static const struct {
        double R, r;
        uint32_t nu, nv;
    } cases[] = {{1.0, 0.4, 32, 16}, {1.0, 0.4, 3, 3}, {2.5, 0.5, 7, 5}, {1.0, 0.9, 64, 4}};
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i) {
        pgt_mesh m;
        pgt_error err = fresh_error();
        REQUIRE(pgt_gen_torus(&m, cases[i].R, cases[i].r, cases[i].nu, cases[i].nv, &err) ==
                PGT_OK);
        char what[64];
        snprintf(what, sizeof(what), "torus %ux%u", cases[i].nu, cases[i].nv);
        const uint64_t q = (uint64_t)cases[i].nu * cases[i].nv;
        check_counts(&m, what, q, 2 * q);
        check_manifold(&m, what, 0, 0);
        double res = max_torus_residual(&m, cases[i].R, cases[i].r);
        CHECK_MSG(res <= TORUS_TOL, "%s: torus equation residual %g", what, res);
        /* The nearest-circle-point test needs faces small against R (a 3-segment ring's face
         * centroids sit nearer the axis than the circle); positive volume covers the rest. */
        if (cases[i].nu >= 8)
            CHECK_MSG(inward_torus_faces(&m, cases[i].R) == 0, "%s: inward faces", what);
        CHECK(m.uvs == NULL && m.labels == NULL);
        pgt_mesh_destroy(&m);
    }
}

static void noisy_torus_seeds(void) {
    const double R = 1.0, r = 0.4, amp = 0.02;
    pgt_mesh a, b, c, plain;
    pgt_error err = fresh_error();
    REQUIRE(pgt_gen_noisy_torus(&a, R, r, 48, 24, 7, amp, &err) == PGT_OK);
    REQUIRE(pgt_gen_noisy_torus(&b, R, r, 48, 24, 7, amp, &err) == PGT_OK);
    REQUIRE(pgt_gen_noisy_torus(&c, R, r, 48, 24, 8, amp, &err) == PGT_OK);
    REQUIRE(pgt_gen_torus(&plain, R, r, 48, 24, &err) == PGT_OK);
    check_counts(&a, "noisy torus", 48 * 24, 2 * 48 * 24);
    check_manifold(&a, "noisy torus", 0, 0);
    CHECK(inward_torus_faces(&a, R) == 0);
    const size_t pbytes = (size_t)a.vertex_count * 3 * sizeof(float);
    const size_t ibytes = (size_t)a.face_count * 3 * sizeof(uint32_t);
    CHECK(memcmp(a.positions, b.positions, pbytes) == 0);
    CHECK(memcmp(a.indices, b.indices, ibytes) == 0);
    CHECK(memcmp(a.positions, c.positions, pbytes) != 0);
    CHECK(memcmp(a.indices, plain.indices, ibytes) == 0);
    /* Each vertex sits at tube distance r + d with |d| <= amplitude, and the draws are spread. */
    double lo = 1.0, hi = -1.0;
    uint32_t moved = 0;
    for (uint32_t v = 0; v < a.vertex_count; ++v) {
        const float *p = position(&a, v);
        double q = sqrt((double)p[0] * p[0] + (double)p[1] * p[1]) - R;
        double d = sqrt(q * q + (double)p[2] * p[2]) - r;
        if (d < lo) lo = d;
        if (d > hi) hi = d;
        moved += memcmp(p, position(&plain, v), 3 * sizeof(float)) != 0;
    }
    CHECK(lo >= -amp - 1e-6 && hi <= amp + 1e-6);
    CHECK(lo < -0.5 * amp && hi > 0.5 * amp);
    CHECK(moved > a.vertex_count - 4);
    pgt_mesh_destroy(&a);
    pgt_mesh_destroy(&b);
    pgt_mesh_destroy(&c);
    pgt_mesh_destroy(&plain);
}

static void bench_torus_sizes(void) {
    uint32_t nu, nv;
    pgt_error err = fresh_error();
    REQUIRE(pgt_gen_bench_torus_size(100000, &nu, &nv, &err) == PGT_OK);
    CHECK(nu == 250 && nv == 200);
    REQUIRE(pgt_gen_bench_torus_size(18, &nu, &nv, &err) == PGT_OK);
    CHECK(nu == 3 && nv == 3);
    static const uint32_t targets[] = {18, 1000, 5000, 33333, 1000000};
    for (size_t i = 0; i < sizeof(targets) / sizeof(targets[0]); ++i) {
        REQUIRE(pgt_gen_bench_torus_size(targets[i], &nu, &nv, &err) == PGT_OK);
        double faces = 2.0 * nu * nv;
        CHECK_MSG(fabs(faces - targets[i]) <= 0.05 * targets[i] + 2.0 * (nu > nv ? nu : nv),
                  "target %u gave %ux%u", targets[i], nu, nv);
    }
    pgt_mesh m;
    REQUIRE(pgt_gen_bench_torus(&m, 100000, &err) == PGT_OK);
    check_counts(&m, "bench torus", 50000, 100000);
    check_manifold(&m, "bench torus", 0, 0);
    CHECK(max_torus_residual(&m, 1.0, 0.4) <= TORUS_TOL);
    pgt_mesh_destroy(&m);
}

/* ---------------------------------------------------------------------------------------------
 * Grid */

static void grid_shapes(void) {
    static const uint32_t sizes[][2] = {{16, 16}, {1, 1}, {5, 3}, {1, 7}};
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); ++i) {
        const uint32_t nx = sizes[i][0], ny = sizes[i][1];
        pgt_mesh m;
        pgt_error err = fresh_error();
        REQUIRE(pgt_gen_grid(&m, nx, ny, &err) == PGT_OK);
        char what[64];
        snprintf(what, sizeof(what), "grid %ux%u", nx, ny);
        check_counts(&m, what, ((uint64_t)nx + 1) * (ny + 1), 2 * (uint64_t)nx * ny);
        check_manifold(&m, what, 1, 1);
        topo t = measure(&m);
        CHECK_MSG(t.boundary_edges == 2 * (nx + ny), "%s: %u boundary edges", what,
                  t.boundary_edges);
        REQUIRE(m.uvs != NULL);
        uint32_t up = 0, bad_uv = 0, bad_pos = 0, diag_main = 0, diag_anti = 0;
        for (uint32_t f = 0; f < m.face_count; ++f) {
            const float *p[3];
            for (int c = 0; c < 3; ++c) {
                p[c] = position(&m, m.indices[3 * f + c]);
                if (m.uvs[6 * f + 2 * c] != p[c][0] || m.uvs[6 * f + 2 * c + 1] != p[c][1])
                    bad_uv++;
                if (p[c][2] != 0.0f || p[c][0] < 0.0f || p[c][0] > 1.0f || p[c][1] < 0.0f ||
                    p[c][1] > 1.0f)
                    bad_pos++;
            }
            double area = ((double)p[1][0] - p[0][0]) * ((double)p[2][1] - p[0][1]) -
                          ((double)p[2][0] - p[0][0]) * ((double)p[1][1] - p[0][1]);
            up += area > 0.0;
            /* The diagonal is the one edge that is neither horizontal nor vertical. */
            for (int c = 0; c < 3; ++c) {
                const float *s = p[c], *e = p[(c + 1) % 3];
                if (s[0] == e[0] || s[1] == e[1]) continue;
                if ((e[0] - s[0]) * (e[1] - s[1]) > 0)
                    diag_main++;
                else
                    diag_anti++;
            }
        }
        CHECK_MSG(up == m.face_count, "%s: %u of %u faces face +z", what, up, m.face_count);
        CHECK(bad_uv == 0 && bad_pos == 0);
        CHECK(diag_main + diag_anti == m.face_count);
        if (nx * ny > 1) CHECK_MSG(diag_main > 0 && diag_anti > 0, "%s: one diagonal only", what);
        pgt_mesh_destroy(&m);
    }
}

/* ---------------------------------------------------------------------------------------------
 * Jagged hemisphere */

static void hemisphere_jagged_shapes(void) {
    static const uint32_t cases[][3] = {{12, 32, 11}, {2, 3, 0}, {2, 4, 1}, {5, 7, 3},
                                        {3, 16, 12345}, {8, 33, 99}};
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i) {
        const uint32_t rings = cases[i][0], segs = cases[i][1], seed = cases[i][2];
        pgt_mesh m;
        pgt_error err = fresh_error();
        REQUIRE(pgt_gen_hemisphere_jagged(&m, rings, segs, seed, &err) == PGT_OK);
        char what[80];
        snprintf(what, sizeof(what), "hemisphere_jagged %ux%u seed %u", rings, segs, seed);
        check_counts(&m, what, 1 + (uint64_t)rings * segs,
                     (uint64_t)segs * (2 * rings - 1) - segs / 2);
        check_manifold(&m, what, 1, 1);
        topo t = measure(&m);
        CHECK_MSG(t.boundary_edges == segs + segs / 2, "%s: %u boundary edges", what,
                  t.boundary_edges);
        CHECK(t.signed_volume > 0.0); /* a cone fan from the center: positive when outward */
        CHECK_MSG(max_unit_sphere_error(&m) <= UNIT_SPHERE_TOL, "%s: off the sphere", what);
        CHECK_MSG(inward_faces_around_origin(&m) == 0, "%s: inward faces", what);
        uint32_t below = 0, rim_at_equator = 0;
        for (uint32_t v = 0; v < m.vertex_count; ++v) {
            below += position(&m, v)[2] < 0.0f;
            rim_at_equator += fabs(position(&m, v)[2]) < 1e-6;
        }
        CHECK(below == 0);
        /* The even rim vertices stay on the equator, the odd ones are raised. */
        CHECK_MSG(rim_at_equator == (segs + 1) / 2, "%s: %u rim vertices on the equator", what,
                  rim_at_equator);
        pgt_mesh_destroy(&m);
    }
}

static void hemisphere_jagged_seeds(void) {
    pgt_mesh a, b, c;
    pgt_error err = fresh_error();
    REQUIRE(pgt_gen_hemisphere_jagged(&a, 12, 32, 11, &err) == PGT_OK);
    REQUIRE(pgt_gen_hemisphere_jagged(&b, 12, 32, 11, &err) == PGT_OK);
    REQUIRE(pgt_gen_hemisphere_jagged(&c, 12, 32, 12, &err) == PGT_OK);
    CHECK(memcmp(a.positions, b.positions, (size_t)a.vertex_count * 12) == 0);
    CHECK(memcmp(a.indices, b.indices, (size_t)a.face_count * 12) == 0);
    CHECK(memcmp(a.positions, c.positions, (size_t)a.vertex_count * 12) != 0);
    /* 16 independent cut choices: the two seeds give different notch patterns. */
    CHECK(memcmp(a.indices, c.indices, (size_t)a.face_count * 12) != 0);
    pgt_mesh_destroy(&a);
    pgt_mesh_destroy(&b);
    pgt_mesh_destroy(&c);
}

/* ---------------------------------------------------------------------------------------------
 * Cube sphere */

static int uv_equal(const pgt_mesh *m, uint32_t corner_a, uint32_t corner_b) {
    return m->uvs[2 * corner_a] == m->uvs[2 * corner_b] &&
           m->uvs[2 * corner_a + 1] == m->uvs[2 * corner_b + 1];
}

static void cube_sphere_shapes(void) {
    static const uint32_t sizes[] = {1, 2, 8, 13};
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); ++i) {
        const uint32_t n = sizes[i];
        pgt_mesh m;
        pgt_error err = fresh_error();
        REQUIRE(pgt_gen_cube_sphere(&m, n, &err) == PGT_OK);
        char what[64];
        snprintf(what, sizeof(what), "cube_sphere %u", n);
        check_counts(&m, what, 6 * (uint64_t)n * n + 2, 12 * (uint64_t)n * n);
        check_manifold(&m, what, 2, 0);
        CHECK_MSG(max_unit_sphere_error(&m) <= UNIT_SPHERE_TOL, "%s: off the sphere", what);
        CHECK_MSG(inward_faces_around_origin(&m) == 0, "%s: inward faces", what);
        REQUIRE(m.uvs != NULL && m.labels != NULL);

        /* Labels: face ids 0..5, 2 n^2 faces each. */
        uint32_t per_label[6] = {0};
        uint32_t bad_label = 0;
        for (uint32_t f = 0; f < m.face_count; ++f) {
            if (m.labels[f] < 0 || m.labels[f] > 5) bad_label++;
            else per_label[m.labels[f]]++;
        }
        CHECK(bad_label == 0);
        for (int l = 0; l < 6; ++l) CHECK(per_label[l] == 2 * n * n);

        /* UV triangles CCW and inside [0,1]. */
        uint32_t bad_area = 0, outside = 0;
        for (uint32_t f = 0; f < m.face_count; ++f) {
            const float *t = m.uvs + 6 * (size_t)f;
            double area = ((double)t[2] - t[0]) * ((double)t[5] - t[1]) -
                          ((double)t[4] - t[0]) * ((double)t[3] - t[1]);
            bad_area += !(area > 0.0);
            for (int k = 0; k < 6; ++k) outside += !(t[k] >= 0.0f && t[k] <= 1.0f);
        }
        CHECK_MSG(bad_area == 0, "%s: %u UV triangles not CCW", what, bad_area);
        CHECK(outside == 0);

        /* Charts: faces joined across edges whose two corner UVs match exactly. */
        uint32_t *parent = malloc((size_t)m.face_count * sizeof(uint32_t));
        for (uint32_t f = 0; f < m.face_count; ++f) parent[f] = f;
        key_entry *e = sorted_half_edges(&m);
        uint32_t seam_edges = 0;
        for (uint32_t k = 0; k + 1 < 3 * m.face_count; ++k) {
            if (e[k].key != e[k + 1].key) continue;
            const uint32_t h1 = e[k].index, h2 = e[k + 1].index;
            /* h1 runs a -> b, h2 runs b -> a. */
            if (uv_equal(&m, h1, he_next(h2)) && uv_equal(&m, he_next(h1), h2))
                uf_union(parent, h1 / 3, h2 / 3);
            else
                seam_edges++;
        }
        free(e);
        uint32_t charts = 0, chart_of_root[6] = {0}, mixed_labels = 0;
        uint32_t *chart = malloc((size_t)m.face_count * sizeof(uint32_t));
        for (uint32_t f = 0; f < m.face_count; ++f)
            if (uf_find(parent, f) == f) {
                if (charts < 6) chart_of_root[charts] = f;
                charts++;
            }
        CHECK_MSG(charts == 6, "%s: %u charts", what, charts);
        CHECK_MSG(seam_edges == 12 * n, "%s: %u seam edges, expected %u", what, seam_edges, 12 * n);
        if (charts == 6) {
            double box[6][4];
            for (int c = 0; c < 6; ++c) box[c][0] = box[c][1] = 2.0, box[c][2] = box[c][3] = -1.0;
            for (uint32_t f = 0; f < m.face_count; ++f) {
                uint32_t root = uf_find(parent, f), c = 0;
                while (chart_of_root[c] != root) ++c;
                chart[f] = c;
                if (m.labels[f] != m.labels[root]) mixed_labels++;
                for (int k = 0; k < 3; ++k) {
                    double u = m.uvs[6 * f + 2 * k], v = m.uvs[6 * f + 2 * k + 1];
                    if (u < box[c][0]) box[c][0] = u;
                    if (v < box[c][1]) box[c][1] = v;
                    if (u > box[c][2]) box[c][2] = u;
                    if (v > box[c][3]) box[c][3] = v;
                }
            }
            CHECK_MSG(mixed_labels == 0, "%s: a chart spans two cube faces", what);
            for (int a = 0; a < 6; ++a)
                for (int b = a + 1; b < 6; ++b) {
                    int apart = box[a][2] < box[b][0] || box[b][2] < box[a][0] ||
                                box[a][3] < box[b][1] || box[b][3] < box[a][1];
                    CHECK_MSG(apart, "%s: charts %d and %d overlap in UV", what, a, b);
                }
        }
        free(chart);
        free(parent);
        pgt_mesh_destroy(&m);
    }
}

/* ---------------------------------------------------------------------------------------------
 * Defaults */

static void defaults_registry(void) {
    static const struct {
        const char *name;
        uint32_t v, f;
        int64_t euler;
        uint32_t loops;
    } expected[] = {
        {"icosphere_l0", 12, 20, 2, 0},
        {"icosphere_l1", 42, 80, 2, 0},
        {"icosphere_l2", 162, 320, 2, 0},
        {"icosphere_l3", 642, 1280, 2, 0},
        {"torus_32x16", 512, 1024, 0, 0},
        {"noisy_torus_48x24", 1152, 2304, 0, 0},
        {"grid_16x16", 289, 512, 1, 1},
        {"hemisphere_jagged_12x32", 385, 720, 1, 1},
        {"cube_sphere_8", 386, 768, 2, 0},
    };
    const uint32_t count = (uint32_t)(sizeof(expected) / sizeof(expected[0]));
    REQUIRE(pgt_gen_default_count() == count);
    for (uint32_t i = 0; i < count; ++i) {
        REQUIRE(pgt_gen_default_name(i) != NULL);
        CHECK(strcmp(pgt_gen_default_name(i), expected[i].name) == 0);
        CHECK(pgt_gen_default_find(expected[i].name) == i);
        pgt_mesh a, b;
        pgt_error err = fresh_error();
        REQUIRE(pgt_gen_default(i, &a, &err) == PGT_OK);
        REQUIRE(pgt_gen_default(i, &b, &err) == PGT_OK);
        check_counts(&a, expected[i].name, expected[i].v, expected[i].f);
        check_manifold(&a, expected[i].name, expected[i].euler, expected[i].loops);
        CHECK_MSG(a.face_count <= 5000, "%s: too big for the CGAL comparison tests",
                  expected[i].name);
        /* Same call, same bytes. */
        CHECK(a.vertex_count == b.vertex_count && a.face_count == b.face_count);
        CHECK(memcmp(a.positions, b.positions, (size_t)a.vertex_count * 12) == 0);
        CHECK(memcmp(a.indices, b.indices, (size_t)a.face_count * 12) == 0);
        CHECK((a.uvs == NULL) == (b.uvs == NULL));
        if (a.uvs) CHECK(memcmp(a.uvs, b.uvs, (size_t)a.face_count * 24) == 0);
        if (a.labels) CHECK(memcmp(a.labels, b.labels, (size_t)a.face_count * 4) == 0);
        pgt_mesh_destroy(&a);
        pgt_mesh_destroy(&b);
    }
    CHECK(pgt_gen_default_name(count) == NULL);
    CHECK(pgt_gen_default_find("no_such_dataset") == PGT_NONE);
    CHECK(pgt_gen_default_find(NULL) == PGT_NONE);
    pgt_mesh m;
    pgt_error err = fresh_error();
    CHECK(pgt_gen_default(count, &m, &err) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(err.code == PGT_ERROR_INVALID_ARGUMENT && err.message[0] != '\0');
}

/* ---------------------------------------------------------------------------------------------
 * Bad parameters */

static int zeroed(const pgt_mesh *m) {
    return m->vertex_count == 0 && m->face_count == 0 && !m->positions && !m->indices &&
           !m->uvs && !m->labels;
}

#define EXPECT_ERROR(call, want_)                                                                  \
    do {                                                                                           \
        pgt_mesh m_;                                                                               \
        memset(&m_, 0xAB, sizeof(m_));                                                             \
        pgt_error e_ = fresh_error();                                                              \
        pgt_mesh *out = &m_;                                                                       \
        pgt_error *err = &e_;                                                                      \
        pgt_result r_ = (call);                                                                    \
        CHECK_MSG(r_ == (want_), "%s returned %s", #call, pgt_result_name(r_));                    \
        CHECK(e_.code == (want_) && e_.message[0] != '\0');                                        \
        CHECK(zeroed(&m_));                                                                        \
        if (r_ == PGT_OK) pgt_mesh_destroy(&m_);                                                   \
    } while (0)

static void bad_parameters(void) {
    const double nan = NAN, inf = INFINITY;
    EXPECT_ERROR(pgt_gen_icosphere(out, PGT_GEN_ICOSPHERE_MAX_LEVEL + 1, err), PGT_ERROR_LIMIT);
    EXPECT_ERROR(pgt_gen_icosphere(out, UINT32_MAX, err), PGT_ERROR_LIMIT);

    EXPECT_ERROR(pgt_gen_torus(out, 1.0, 0.4, 2, 16, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_torus(out, 1.0, 0.4, 16, 0, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_torus(out, 1.0, 0.0, 16, 8, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_torus(out, 1.0, -0.4, 16, 8, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_torus(out, 0.4, 0.4, 16, 8, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_torus(out, nan, 0.4, 16, 8, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_torus(out, inf, 0.4, 16, 8, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_torus(out, 1.0, 0.4, 70000, 70000, err), PGT_ERROR_LIMIT);
    EXPECT_ERROR(pgt_gen_torus(out, 1.0, 0.4, UINT32_MAX, UINT32_MAX, err), PGT_ERROR_LIMIT);
    /* Faces overflow the limit while vertices still fit. */
    EXPECT_ERROR(pgt_gen_torus(out, 1.0, 0.4, 32767, 32767, err), PGT_ERROR_LIMIT);

    EXPECT_ERROR(pgt_gen_noisy_torus(out, 1.0, 0.4, 16, 8, 1, -0.01, err),
                 PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_noisy_torus(out, 1.0, 0.4, 16, 8, 1, 0.4, err),
                 PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_noisy_torus(out, 1.0, 0.6, 16, 8, 1, 0.45, err),
                 PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_noisy_torus(out, 1.0, 0.4, 16, 8, 1, nan, err),
                 PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_noisy_torus(out, 1.0, 0.4, 1, 8, 1, 0.01, err),
                 PGT_ERROR_INVALID_ARGUMENT);

    EXPECT_ERROR(pgt_gen_grid(out, 0, 4, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_grid(out, 4, 0, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_grid(out, 40000, 40000, err), PGT_ERROR_LIMIT);
    EXPECT_ERROR(pgt_gen_grid(out, UINT32_MAX, UINT32_MAX, err), PGT_ERROR_LIMIT);

    EXPECT_ERROR(pgt_gen_hemisphere_jagged(out, 1, 32, 0, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_hemisphere_jagged(out, 0, 32, 0, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_hemisphere_jagged(out, 12, 2, 0, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_hemisphere_jagged(out, 100000, 100000, 0, err), PGT_ERROR_LIMIT);
    EXPECT_ERROR(pgt_gen_hemisphere_jagged(out, UINT32_MAX, UINT32_MAX, 0, err),
                 PGT_ERROR_LIMIT);

    EXPECT_ERROR(pgt_gen_cube_sphere(out, 0, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_cube_sphere(out, 10000, err), PGT_ERROR_LIMIT);
    EXPECT_ERROR(pgt_gen_cube_sphere(out, UINT32_MAX, err), PGT_ERROR_LIMIT);

    EXPECT_ERROR(pgt_gen_bench_torus(out, 0, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_bench_torus(out, 17, err), PGT_ERROR_INVALID_ARGUMENT);
    EXPECT_ERROR(pgt_gen_bench_torus(out, UINT32_MAX, err), PGT_ERROR_LIMIT);

    /* A NULL error pointer is allowed. */
    pgt_mesh m;
    CHECK(pgt_gen_grid(&m, 0, 0, NULL) == PGT_ERROR_INVALID_ARGUMENT);
    CHECK(zeroed(&m));
}

/* ---------------------------------------------------------------------------------------------
 * The checker itself: each defect it must catch, on a corrupted copy of a good mesh. */

static void checker_catches_defects(void) {
    pgt_mesh good, m;
    pgt_error err = fresh_error();
    REQUIRE(pgt_gen_icosphere(&good, 1, &err) == PGT_OK);

    /* A flipped face: its three edges now run the same way as their neighbours'. */
    REQUIRE(pgt_mesh_copy(&m, &good, &err) == PGT_OK);
    uint32_t s = m.indices[1];
    m.indices[1] = m.indices[2];
    m.indices[2] = s;
    CHECK(measure(&m).bad_edges == 3);
    pgt_mesh_destroy(&m);

    /* A face given twice: its edges get three faces, and it is a duplicate. */
    REQUIRE(pgt_mesh_create(&m, good.vertex_count, good.face_count + 1, 0, 0, &err) == PGT_OK);
    memcpy(m.positions, good.positions, (size_t)good.vertex_count * 12);
    memcpy(m.indices, good.indices, (size_t)good.face_count * 12);
    memcpy(m.indices + 3 * (size_t)good.face_count, good.indices + 6, 12);
    topo t = measure(&m);
    CHECK(t.duplicate_faces == 1 && t.bad_edges == 3);
    pgt_mesh_destroy(&m);

    /* A split vertex: one corner points at a new copy of its vertex. */
    REQUIRE(pgt_mesh_create(&m, good.vertex_count + 1, good.face_count, 0, 0, &err) == PGT_OK);
    memcpy(m.positions, good.positions, (size_t)good.vertex_count * 12);
    memcpy(m.indices, good.indices, (size_t)good.face_count * 12);
    memcpy(m.positions + 3 * (size_t)good.vertex_count, position(&good, m.indices[0]), 12);
    m.indices[0] = good.vertex_count;
    t = measure(&m);
    CHECK(t.duplicate_vertices == 1 && t.boundary_edges == 4 && t.euler != 2);
    pgt_mesh_destroy(&m);
    pgt_mesh_destroy(&good);

    /* A bow-tie: two triangles that touch at vertex 2 only. */
    static const float bow_p[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}};
    static const uint32_t bow_i[6] = {0, 1, 2, 2, 3, 4};
    REQUIRE(pgt_mesh_create(&m, 5, 2, 0, 0, &err) == PGT_OK);
    memcpy(m.positions, bow_p, sizeof(bow_p));
    memcpy(m.indices, bow_i, sizeof(bow_i));
    t = measure(&m);
    CHECK(t.non_manifold_vertices == 1 && t.bad_edges == 0);
    pgt_mesh_destroy(&m);

    /* A cube-sphere chart cut in two by one moved UV corner is no longer 6 charts. */
    REQUIRE(pgt_gen_cube_sphere(&m, 1, &err) == PGT_OK);
    CHECK(m.labels[0] == m.labels[1]);
    m.uvs[0] += 1.0f / 1024.0f; /* corner 0 of face 0; face 1 shares that vertex in the chart */
    key_entry *e = sorted_half_edges(&m);
    uint32_t matched = 0;
    for (uint32_t k = 0; k + 1 < 3 * m.face_count; ++k)
        if (e[k].key == e[k + 1].key && uv_equal(&m, e[k].index, he_next(e[k + 1].index)) &&
            uv_equal(&m, he_next(e[k].index), e[k + 1].index))
            matched++;
    free(e);
    CHECK(matched == 5); /* the 6 in-chart diagonals minus the one through the moved corner */
    pgt_mesh_destroy(&m);
}

static const pgt_test_case cases[] = {
    {"icosphere_levels", icosphere_levels},
    {"torus_shapes", torus_shapes},
    {"noisy_torus_seeds", noisy_torus_seeds},
    {"bench_torus_sizes", bench_torus_sizes},
    {"grid_shapes", grid_shapes},
    {"hemisphere_jagged_shapes", hemisphere_jagged_shapes},
    {"hemisphere_jagged_seeds", hemisphere_jagged_seeds},
    {"cube_sphere_shapes", cube_sphere_shapes},
    {"defaults_registry", defaults_registry},
    {"bad_parameters", bad_parameters},
    {"checker_catches_defects", checker_catches_defects},
};

PGT_TEST_MAIN(cases)
