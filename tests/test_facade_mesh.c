/* Tests of procedural facades on generic meshes (ref_cpu facade_mesh.c; paper 003 sec. 10, issue
 * 6 item 6): selective adjacency extraction (eq. 5-7) and the quad facades' sizes (eq. 8) on a
 * cylinder against double-precision analytic values; a flat quad grid gives the same hits as the
 * footprint facade it tiles; the twisted tower's per-pixel rendering agrees with its explicit
 * twin as seen by an independent double-precision brute-force ray caster (the oracle of
 * test_facade.c); the quad OBJ reader round-trips and names FILE:LINE; bad meshes get errors.
 *
 * Each quad is a planar facade of its own (its origin vertex's tangent plane), so the explicit
 * twin of each quad's window is exactly what the rays see: the paper's Fig. 14 caveat (facade
 * space inconsistent along a ray on curved meshes) does not make the two disagree. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/facade.h>
#include <pgt/grammar.h>
#include <pgt/rng.h>

#include "facade_quads.h"
#include "gen.h"
#include "test_util.h"

/* eq. 5-8 against the analytic cylinder: float32 positions of a 10 m cylinder are rounded to
 * about 1e-6 m, eq. 6-7 divide offsets of ~2.6 m, so directions are good to ~1e-6; lengths to a
 * few 1e-6 m. 1e-5 leaves a margin of about 10. */
#define MESH_DIR_TOL 1e-5
#define MESH_LEN_TOL 1e-5
#include "facade_oracle.h"


static const double PI_D = 3.14159265358979323846;

/* A scene of one grammar and one building without footprint (the mesh's) plus, with
 * corners, a footprint building of the same grammar, params and seed first; the built-in
 * geometry images (Mesh(0) is the oculus). */
static void make_scene(pgt_facade_scene *s, const pgt_grammar *g, const float *corners,
                       uint32_t corner_count, float height) {
    memset(s, 0, sizeof *s);
    s->grammar_count = 1, s->grammars = g;
    s->building_count = corner_count ? 2u : 1u;
    s->buildings = calloc(s->building_count, sizeof *s->buildings);
    s->corner_count = corner_count;
    s->corners = malloc((corner_count ? corner_count : 1u) * 2u * sizeof(float));
    if (corner_count) memcpy(s->corners, corners, corner_count * 2u * sizeof(float));
    s->param_count = g->param_count;
    s->params = malloc((g->param_count ? g->param_count : 1u) * sizeof(float));
    memcpy(s->params, g->param_values, g->param_count * sizeof(float));
    for (uint32_t b = 0; b < s->building_count; ++b) {
        pgt_facade_building *B = &s->buildings[b];
        B->first_corner = 0, B->corner_count = (b + 1u < s->building_count) ? corner_count : 0u;
        B->base = 0.0f, B->height = height, B->grammar = 0, B->first_param = 0;
        B->seed = 11, B->colour = 0xD8C8B0;
    }
    pgt_error err = {0};
    CHECK_MSG(pgt_facade_add_builtin_gimages(s, &err) == PGT_OK, "%s", err.message);
}

/* eq. 5-8 on a cylinder (radius R, N segments, rows of height dy): t_F is the unit tangent
 * around (u grows clockwise seen from above), b_F is up, a quad's facade is its origin corner's
 * tangent plane, w = R sin(2 pi / N) (the chord's projection on the tangent, eq. 8), h = dy,
 * u0 = R 2 pi k / N. */
static void test_cylinder_eq5_8(void) {
    const double R = 10.0, H = 24.0;
    const uint32_t N = 24, rows = 8;
    pgt_facade_quads m;
    pgt_error err = {0};
    REQUIRE(pgt_gen_tower(&m, R, R, H, 0.0, N, rows, &err) == PGT_OK);
    const uint32_t V = m.vertex_count;
    float *t = malloc(3u * V * sizeof *t), *b = malloc(3u * V * sizeof *b);
    uint32_t *pair = malloc(2u * V * sizeof *pair);
    REQUIRE(t && b && pair);
    CHECK_MSG(pgt_facade_mesh_frames(t, b, pair, &m, &err) == PGT_OK, "%s", err.message);
    double max_dir = 0.0, max_len = 0.0;
    for (uint32_t j = 0; j <= rows; ++j)
        for (uint32_t k = 0; k <= N; ++k) {
            const uint32_t v = j * (N + 1u) + k;
            const double a = -2.0 * PI_D * k / N;
            const double ta[3] = {sin(a), 0.0, -cos(a)}, ba[3] = {0.0, 1.0, 0.0};
            for (int c = 0; c < 3; ++c) {
                max_dir = fmax(max_dir, fabs(t[3u * v + (uint32_t)c] - ta[c]));
                max_dir = fmax(max_dir, fabs(b[3u * v + (uint32_t)c] - ba[c]));
            }
            /* the chosen neighbours are one around and one up or down: orthogonal */
            CHECK(pair[2u * v] != PGT_NONE && pair[2u * v + 1u] != PGT_NONE);
        }
    pgt_grammar g;
    REQUIRE(load(&g, "facade.grammar"));
    pgt_facade_scene s;
    make_scene(&s, &g, NULL, 0, (float)H);
    CHECK_MSG(pgt_facade_scene_check(&s, "mesh scene", &err) == PGT_OK, "%s", err.message);
    pgt_facade *fa = malloc(m.quad_count * sizeof *fa);
    REQUIRE(fa);
    CHECK_MSG(pgt_facade_mesh_facades(fa, &m, &s, 0, 0.0f, 0.0f, &err) == PGT_OK, "%s",
              err.message);
    const double w_an = R * sin(2.0 * PI_D / N), h_an = H / rows;
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t k = 0; k < N; ++k) {
            const pgt_facade *F = &fa[j * N + k];
            const double a = -2.0 * PI_D * k / N;
            const double o[3] = {R * cos(a), H * j / rows, R * sin(a)};
            const double n[3] = {cos(a), 0.0, sin(a)}, ta[3] = {sin(a), 0.0, -cos(a)};
            for (int c = 0; c < 3; ++c) {
                max_len = fmax(max_len, fabs(F->origin[c] - o[c]));
                max_dir = fmax(max_dir, fabs(F->n[c] - n[c]));
                max_dir = fmax(max_dir, fabs(F->t[c] - ta[c]));
                max_dir = fmax(max_dir, fabs(F->b[c] - (c == 1 ? 1.0 : 0.0)));
            }
            max_len = fmax(max_len, fabs(F->width - w_an));
            max_len = fmax(max_len, fabs(F->height - h_an));
            max_len = fmax(max_len, fabs(F->u0 - R * 2.0 * PI_D * k / N));
            max_len = fmax(max_len, fabs(F->v0 - H * j / rows));
        }
    /* the scope defaults to the UV extent: the perimeter (the seam column's u) by H */
    max_len = fmax(max_len, fabs(fa[0].scope_w - 2.0 * PI_D * R) / R);
    max_len = fmax(max_len, fabs(fa[0].scope_h - H) / R);
    printf("  cylinder R %g, %u x %u quads: max direction error %.2g, max length error %.2g m "
           "(w = R sin(2 pi / N) = %.6f m, arc %.6f m)\n",
           R, N, rows, max_dir, max_len, w_an, 2.0 * PI_D * R / N);
    CHECK_MSG(max_dir <= MESH_DIR_TOL, "direction error %.3g", max_dir);
    CHECK_MSG(max_len <= MESH_LEN_TOL * R, "length error %.3g", max_len);
    free(fa);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
    free(t), free(b), free(pair);
    pgt_facade_quads_destroy(&m);
}

/* The twisted elliptic tower: every quad's facade frame is orthonormal, right-handed (n = t x b)
 * with n the mesh's normal. */
static void test_tower_frames(void) {
    pgt_facade_quads m;
    pgt_error err = {0};
    REQUIRE(pgt_gen_tower(&m, 12.0, 8.0, 30.0, 40.0, 24, 8, &err) == PGT_OK);
    pgt_grammar g;
    REQUIRE(load(&g, "facade.grammar"));
    pgt_facade_scene s;
    make_scene(&s, &g, NULL, 0, 30.0f);
    pgt_facade *fa = malloc(m.quad_count * sizeof *fa);
    REQUIRE(fa);
    CHECK_MSG(pgt_facade_mesh_facades(fa, &m, &s, 0, 0.0f, 0.0f, &err) == PGT_OK, "%s",
              err.message);
    double worst = 0.0;
    for (uint32_t q = 0; q < m.quad_count; ++q) {
        const pgt_facade *F = &fa[q];
        const double tt =
            (double)F->t[0] * F->t[0] + (double)F->t[1] * F->t[1] + (double)F->t[2] * F->t[2];
        const double bb =
            (double)F->b[0] * F->b[0] + (double)F->b[1] * F->b[1] + (double)F->b[2] * F->b[2];
        const double tb =
            (double)F->t[0] * F->b[0] + (double)F->t[1] * F->b[1] + (double)F->t[2] * F->b[2];
        const double x[3] = {(double)F->t[1] * F->b[2] - (double)F->t[2] * F->b[1],
                             (double)F->t[2] * F->b[0] - (double)F->t[0] * F->b[2],
                             (double)F->t[0] * F->b[1] - (double)F->t[1] * F->b[0]};
        worst = fmax(worst, fmax(fabs(tt - 1.0), fmax(fabs(bb - 1.0), fabs(tb))));
        for (int c = 0; c < 3; ++c) worst = fmax(worst, fabs(x[c] - F->n[c]));
        CHECK(F->width > 0.0f && F->height > 0.0f);
    }
    CHECK_MSG(worst <= MESH_DIR_TOL, "frame error %.3g", worst);
    free(fa);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
    pgt_facade_quads_destroy(&m);
}

/* A corner of an explicit triangle within this distance (metres, facade space) of its quad's
 * window border was put there by clipping: clipped corners lie exactly on the border in facade
 * space, and the float world transform and the double one back move them by a few ulps of
 * coordinates of ~30 m (~1e-5 m at most). */
#define BORDER_TOL 1e-4
/* A hit "near a window border": within this distance (metres, facade space) of it, a tenth of
 * the oculus frame's width on a 2 m block. */
#define NEAR_BORDER 0.1

/* Facade-space (x, y) of world point P on facade F, in double. */
static void facade_xy(const pgt_facade *F, const double P[3], double *x, double *y) {
    double dt = 0.0, db = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double d = P[k] - F->origin[k];
        dt += d * F->t[k], db += d * F->b[k];
    }
    *x = F->u0 + dt, *y = F->v0 + db;
}

/* Distance from (x, y) to the border of F's window (negative outside). */
static double border_distance(const pgt_facade *F, double x, double y) {
    return fmin(fmin(x - F->u0, (double)F->u0 + F->width - x),
                fmin(y - F->v0, (double)F->v0 + F->height - y));
}

/* Per triangle of x: 1 for a piece of a geometry-image triangle that its quad's window cut (a
 * piece of the same facade, node and surface, all consecutive in the mesh, has a corner on the
 * window's border). malloc'd. */
static uint8_t *clipped_pieces(const pgt_facade_mesh *x, const pgt_facade *fa) {
    uint8_t *c = calloc(x->triangle_count ? x->triangle_count : 1u, 1);
    if (!c) return NULL;
    for (uint32_t t0 = 0, t1; t0 < x->triangle_count; t0 = t1) {
        for (t1 = t0 + 1u; t1 < x->triangle_count && x->facade[t1] == x->facade[t0] &&
                           x->node[t1] == x->node[t0] && x->surface[t1] == x->surface[t0] &&
                           x->kind[t1] == x->kind[t0];
             ++t1) {
        }
        if (x->kind[t0] != PGT_FACADE_MESH) continue;
        int cut = 0;
        for (uint32_t t = t0; t < t1; ++t)
            for (uint32_t k = 0; k < 3; ++k) {
                const float *P = &x->positions[3u * x->indices[3u * t + k]];
                const double Pd[3] = {P[0], P[1], P[2]};
                double u, v;
                facade_xy(&fa[x->facade[t]], Pd, &u, &v);
                cut |= fabs(border_distance(&fa[x->facade[t]], u, v)) <= BORDER_TOL;
            }
        for (uint32_t t = t0; t < t1; ++t) c[t] = (uint8_t)cut;
    }
    return c;
}

/* Rays of one camera that hit a geometry image (ours), those whose hit the oracle names alike on
 * a clipped piece, and those of them within NEAR_BORDER of the quad's window border: the test
 * cannot pass by never meeting an oculus that straddles quads. */
typedef struct straddle_count {
    uint32_t mesh_hits, clipped, near_border;
} straddle_count;

static void count_clipped_hits(const pgt_facade_scene *s, const pgt_facade *fa, uint32_t fc,
                               const oracle *o, const uint8_t *clipped,
                               const pgt_facade_camera *cam, straddle_count *c) {
    pgt_facade_frame fr;
    pgt_error err = {0};
    REQUIRE(pgt_facade_frame_create(&fr, cam->width, cam->height, &err) == PGT_OK);
    const pgt_facade_shading sh = {.light = {0.0f, 500.0f, 0.0f}, .ambient = 0.3f};
    pgt_facade_render_stats st;
    REQUIRE(pgt_facade_render(s, fa, fc, cam, &sh, 2, &fr, &st, &err) == PGT_OK);
    /* packets on mesh quads (windows cut the terminals) are every ray alone, to the bit */
    CHECK(packets_differ(s, fa, fc, cam, &sh, &fr, &st) == 0);
    const pgt_facade_mesh *m = o->m;
    for (uint32_t y = 0; y < cam->height; ++y)
        for (uint32_t x = 0; x < cam->width; ++x) {
            const size_t p = (size_t)y * cam->width + x;
            if (fr.terminal[p] != (float)PGT_FACADE_MESH) continue;
            c->mesh_hits++;
            float org[3], dir[3];
            pgt_facade_camera_ray(cam, x, y, org, dir);
            const ohit h = oracle_cast(o, org, dir);
            if (h.tri == PGT_NONE || m->facade[h.tri] != fr.facade[p] ||
                m->node[h.tri] != fr.node[p] || m->surface[h.tri] != fr.surface[p] ||
                !clipped[h.tri])
                continue;
            c->clipped++;
            const double X[3] = {org[0] + h.t * dir[0], org[1] + h.t * dir[1],
                                 org[2] + h.t * dir[2]};
            double u, v;
            facade_xy(&fa[fr.facade[p]], X, &u, &v);
            c->near_border += border_distance(&fa[fr.facade[p]], u, v) <= NEAR_BORDER;
        }
    pgt_facade_frame_destroy(&fr);
}

/* A flat grid of nx x ny quads tiling a footprint facade (same plane, UVs = facade space in
 * metres) shows the same terminals as the footprint facade: random rays from in front, hits
 * compared (node, kind, surface, distance within DIST_REL_TOL). The grid's lines are not on any
 * split boundary, so a split's children are cut across quads; rays that disagree must pass within
 * an edge epsilon of a grid line (where either quad may take the hit) or, for a geometry image,
 * of an edge of the triangle hit (the two facades round the block-local ray differently).
 * gimage: every ray aims at a geometry-image block (the oculus) that a grid line crosses, found
 * in the footprint facade's explicit twin (its triangles of one node span the block), and hits of
 * a geometry image within NEAR_GRID of a grid line are counted: the rays do cross the cut. */
#define NEAR_GRID 0.1
static void check_flat_grid(const char *grammar, uint32_t nx, uint32_t ny, uint32_t rays,
                            int gimage) {
    pgt_grammar g;
    REQUIRE(load(&g, grammar));
    /* facade 0 runs from (0, 0) to (0, 15) along +z: t = +z, n = -x */
    const float corners[8] = {0, 0, 0, 15, 20, 15, 20, 0};
    const float H = 19.2f, Wd = 15.0f;
    pgt_facade_scene s;
    make_scene(&s, &g, corners, 4, H);
    pgt_error err = {0};
    CHECK_MSG(pgt_facade_scene_check(&s, "grid scene", &err) == PGT_OK, "%s", err.message);
    pgt_facade *fp = NULL;
    uint32_t fpc = 0;
    REQUIRE(pgt_facade_prepare(&s, &fp, &fpc, &err) == PGT_OK);
    REQUIRE(fpc == 4);
    const uint32_t cols = nx + 1u, V = cols * (ny + 1u), Q = nx * ny;
    const double du = Wd / nx, dv = H / ny;
    pgt_facade_quads m;
    m.vertex_count = V, m.quad_count = Q;
    m.positions = malloc(3u * V * sizeof(float)), m.normals = malloc(3u * V * sizeof(float));
    m.uvs = malloc(2u * V * sizeof(float)), m.indices = malloc(4u * Q * sizeof(uint32_t));
    REQUIRE(m.positions && m.normals && m.uvs && m.indices);
    for (uint32_t j = 0; j <= ny; ++j)
        for (uint32_t i = 0; i <= nx; ++i) {
            const uint32_t v = j * cols + i;
            const float u = Wd * (float)i / (float)nx, y = H * (float)j / (float)ny;
            m.positions[3u * v] = 0.0f, m.positions[3u * v + 1u] = y, m.positions[3u * v + 2u] = u;
            m.normals[3u * v] = -1.0f, m.normals[3u * v + 1u] = 0.0f, m.normals[3u * v + 2u] = 0.0f;
            m.uvs[2u * v] = u, m.uvs[2u * v + 1u] = y;
        }
    for (uint32_t j = 0; j < ny; ++j)
        for (uint32_t i = 0; i < nx; ++i) {
            uint32_t *q = m.indices + 4u * (j * nx + i);
            q[0] = j * cols + i, q[1] = j * cols + i + 1u, q[2] = (j + 1u) * cols + i + 1u;
            q[3] = (j + 1u) * cols + i;
        }
    pgt_facade *fm = malloc(Q * sizeof *fm);
    REQUIRE(fm);
    CHECK_MSG(pgt_facade_mesh_facades(fm, &m, &s, 1, Wd, H, &err) == PGT_OK, "%s", err.message);
    /* gimage: the footprint facade's explicit twin, and the blocks (u, v boxes) a grid line
     * crosses */
    pgt_facade_mesh xf;
    memset(&xf, 0, sizeof xf);
    float *blocks = NULL;
    uint32_t block_count = 0;
    if (gimage) {
        REQUIRE(pgt_facade_explicit(&s, fp, 1, &xf, &err) == PGT_OK);
        blocks = malloc(4u * (xf.triangle_count + 1u) * sizeof *blocks);
        REQUIRE(blocks);
        for (uint32_t t0 = 0, t1; t0 < xf.triangle_count; t0 = t1) {
            for (t1 = t0 + 1u;
                 t1 < xf.triangle_count && xf.node[t1] == xf.node[t0] && xf.kind[t1] == xf.kind[t0];
                 ++t1) {
            }
            if (xf.kind[t0] != PGT_FACADE_MESH) continue;
            float b[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY}; /* u0 v0 u1 v1 */
            for (uint32_t c = 3u * t0; c < 3u * t1; ++c) {
                const float *P = &xf.positions[3u * xf.indices[c]];
                b[0] = fminf(b[0], P[2]), b[1] = fminf(b[1], P[1]);
                b[2] = fmaxf(b[2], P[2]), b[3] = fmaxf(b[3], P[1]);
            }
            const int cut_u = floor(b[0] / du) != floor(b[2] / du) && fmod(b[2], du) > 1e-3;
            const int cut_v = floor(b[1] / dv) != floor(b[3] / dv) && fmod(b[3], dv) > 1e-3;
            if (cut_u || cut_v) memcpy(blocks + 4u * block_count++, b, sizeof b);
        }
        printf("  %u geometry-image blocks of the footprint facade cross a grid line\n",
               block_count);
        REQUIRE(block_count > 0);
    }
    uint32_t agree = 0, near_line = 0, near_edge = 0, other = 0, hits = 0, mesh_hits = 0,
             mesh_near_line = 0;
    for (uint32_t r = 0; r < rays; ++r) {
        const double e0 = pgt_rng_double(5, 1, r), e1 = pgt_rng_double(5, 2, r),
                     e2 = pgt_rng_double(5, 3, r), a0 = pgt_rng_double(5, 4, r),
                     a1 = pgt_rng_double(5, 5, r);
        /* eyes in front (x < 0) from grazing to head-on, aiming anywhere on the facade (or at a
         * crossed block) */
        const float org[3] = {(float)(-0.05 - 30.0 * e0 * e0), (float)(-5.0 + 30.0 * e1),
                              (float)(-10.0 + 35.0 * e2)};
        float at[3] = {0.0f, (float)(H * a1), (float)(Wd * a0)};
        if (gimage) {
            const float *b = blocks + 4u * (uint32_t)(pgt_rng_double(5, 6, r) * block_count);
            at[1] = (float)(b[1] + (b[3] - b[1]) * a1), at[2] = (float)(b[0] + (b[2] - b[0]) * a0);
        }
        float dir[3] = {at[0] - org[0], at[1] - org[1], at[2] - org[2]};
        const float l = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        for (int k = 0; k < 3; ++k) dir[k] /= l;
        pgt_facade_hit a, b;
        a.t = b.t = INFINITY, a.facade = b.facade = PGT_NONE, a.kind = b.kind = 0;
        pgt_facade_intersect(&s, &fp[0], 0, org, dir, &a, NULL);
        for (uint32_t q = 0; q < Q; ++q) pgt_facade_intersect(&s, &fm[q], q, org, dir, &b, NULL);
        hits += a.facade != PGT_NONE;
        /* where does the ray cross the grid lines' planes? distance of the hit points (either
         * side's) to the nearest grid line in u or v */
        double near = INFINITY;
        for (int side = 0; side < 2; ++side) {
            const pgt_facade_hit *h = side ? &b : &a;
            if (h->facade == PGT_NONE) continue;
            const double P[3] = {org[0] + (double)h->t * dir[0], org[1] + (double)h->t * dir[1],
                                 org[2] + (double)h->t * dir[2]};
            const double gu = P[2] / du, gv = P[1] / dv;
            near = fmin(near, fabs(gu - floor(gu + 0.5)) * du);
            near = fmin(near, fabs(gv - floor(gv + 0.5)) * dv);
        }
        if (b.kind == PGT_FACADE_MESH) mesh_hits++, mesh_near_line += near <= NEAR_GRID;
        if (a.kind == b.kind &&
            (a.facade == PGT_NONE || (a.node == b.node && a.surface == b.surface &&
                                      fabs((double)a.t - b.t) <= DIST_REL_TOL * a.t))) {
            agree++;
            continue;
        }
        double edge = INFINITY;
        for (int side = 0; gimage && side < 2; ++side) {
            const pgt_facade_hit *h = side ? &b : &a;
            if (h->kind != PGT_FACADE_MESH) continue;
            const double P[3] = {org[0] + (double)h->t * dir[0], org[1] + (double)h->t * dir[1],
                                 org[2] + (double)h->t * dir[2]};
            edge = fmin(edge, rect_edge_distance(&xf, 0, h->node, h->surface, P));
        }
        const double eps = EDGE_REL_EPS * 60.0 + EDGE_ABS_EPS;
        if (near <= eps)
            near_line++;
        else if (edge <= eps)
            near_edge++;
        else if (++other <= 5)
            fprintf(stderr,
                    "  ray %u: footprint kind %u node %08x surface %u t %.6f; grid kind %u node "
                    "%08x surface %u t %.6f (grid line at %.3g m, edge at %.3g m)\n",
                    r, a.kind, a.node, a.surface, (double)a.t, b.kind, b.node, b.surface,
                    (double)b.t, near, edge);
    }
    printf("  flat %u x %u grid against its footprint facade (%s): %u rays (%u hit), %u agree, %u "
           "at a grid line, %u at a triangle edge, %u other; %u hit a geometry image, %u of them "
           "within %g m of a grid line\n",
           nx, ny, grammar, rays, hits, agree, near_line, near_edge, other, mesh_hits,
           mesh_near_line, NEAR_GRID);
    CHECK(hits > rays / 2u);
    CHECK((double)agree / rays >= AGREEMENT_MIN);
    CHECK_MSG(other == 0, "%u disagreements away from grid lines and edges", other);
    CHECK_MSG(!gimage || mesh_near_line > 0, "no geometry-image hit near a grid line");
    if (gimage) { /* the grid's explicit twin (clipped oculi) through the oracle */
        pgt_facade_mesh xg;
        REQUIRE(pgt_facade_explicit(&s, fm, Q, &xg, &err) == PGT_OK);
        oracle o;
        oracle_init(&o, &xg, Q + s.building_count); /* the footprint building's roof too */
        uint8_t *clipped = clipped_pieces(&xg, fm);
        REQUIRE(clipped);
        const float cams[][10] = {
            {-22.0f, 10.0f, 7.5f, 0.0f, 9.6f, 7.5f, 0, 1, 0, 50}, /* the whole facade */
            {-5.0f, 1.7f, -6.0f, 0.0f, 8.0f, 9.0f, 0, 1, 0, 60},  /* grazing, from below */
        };
        agreement ag = {0, 0, 0, 0, 0.0, 0};
        straddle_count sc = {0, 0, 0};
        for (size_t k = 0; k < sizeof cams / sizeof cams[0]; ++k) {
            pgt_facade_camera cam;
            REQUIRE(pgt_facade_camera_init(&cam, &cams[k][0], &cams[k][3], &cams[k][6], cams[k][9],
                                           128, 96, &err) == PGT_OK);
            compare_camera(&s, fm, Q, &o, &cam, &ag, 1);
            count_clipped_hits(&s, fm, Q, &o, clipped, &cam, &sc);
        }
        printf("  flat grid (%s) against its explicit twin (%u triangles): %u rays, %u agree, %u "
               "at an edge, %u coincident faces, %u other; agreement %.4f %%; %u rays hit a "
               "geometry image, %u a clipped piece, %u within %g m of a window border\n",
               grammar, xg.triangle_count, ag.rays, ag.agree, ag.near_edge, ag.ties, ag.other,
               100.0 * ag.agree / ag.rays, sc.mesh_hits, sc.clipped, sc.near_border, NEAR_BORDER);
        CHECK((double)ag.agree / ag.rays >= AGREEMENT_MIN);
        CHECK_MSG(ag.other == 0 && ag.ties == 0, "%u disagreements away from edges, %u ties",
                  ag.other, ag.ties);
        CHECK_MSG(sc.near_border > 0, "no ray hit a clipped piece near a window border");
        free(clipped);
        oracle_free(&o);
        pgt_facade_mesh_destroy(&xg);
    }
    free(blocks);
    pgt_facade_mesh_destroy(&xf);
    free(fm), free(fp);
    pgt_facade_quads_destroy(&m);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
}

static void test_flat_grid_equals_footprint(void) {
    check_flat_grid("facade.grammar", 7, 5, 100000, 0);
}

/* The oculus windows on a 6 x 5 grid of 2.5 x 3.84 m quads: window blocks of about 2.2 m and
 * floors of 3.2 m, so grid lines cross many oculi (in x and y). */
static void test_flat_grid_gimage_equals_footprint(void) {
    check_flat_grid("facade_gimage.grammar", 6, 5, 20000, 1);
}

/* The twisted elliptic tower rendered per pixel against the explicit twin of its quads'
 * windows, through the double-precision oracle: >= 99.99 % agree, the rest at an edge (of a
 * clipped piece too: the window's border is one). gimage: the grammar puts geometry images on
 * the quads; rays must then hit clipped pieces near window borders. */
static void check_tower(const char *grammar, int ties_allowed, int gimage) {
    pgt_facade_quads m;
    pgt_error err = {0};
    REQUIRE(pgt_gen_tower(&m, 12.0, 8.0, 30.0, 40.0, 24, 8, &err) == PGT_OK);
    pgt_grammar g;
    REQUIRE(load(&g, grammar));
    pgt_facade_scene s;
    make_scene(&s, &g, NULL, 0, 30.0f);
    pgt_facade *fa = malloc(m.quad_count * sizeof *fa);
    REQUIRE(fa);
    REQUIRE(pgt_facade_mesh_facades(fa, &m, &s, 0, 0.0f, 0.0f, &err) == PGT_OK);
    pgt_facade_mesh x;
    const pgt_result r = pgt_facade_explicit(&s, fa, m.quad_count, &x, &err);
    CHECK_MSG(r == PGT_OK, "%s", err.message);
    if (r == PGT_OK) {
        oracle o;
        oracle_init(&o, &x, m.quad_count);
        const float cams[][10] = {
            {-40.0f, 35.0f, 45.0f, 0.0f, 14.0f, 0.0f, 0, 1, 0, 50}, /* the whole tower */
            {-14.0f, 1.7f, 6.0f, 0.0f, 12.0f, -4.0f, 0, 1, 0, 70},  /* at its foot, looking up */
            {20.0f, 8.0f, -2.0f, -12.0f, 9.0f, -6.0f, 0, 1, 0, 30}, /* grazing the side */
            {0.0f, 29.0f, 12.0f, 4.0f, 3.0f, 0.0f, 0, 1, 0, 60},    /* steep, down the facade */
        };
        agreement a = {0, 0, 0, 0, 0.0, 0};
        uint8_t *clipped = gimage ? clipped_pieces(&x, fa) : NULL;
        REQUIRE(!gimage || clipped);
        straddle_count sc = {0, 0, 0};
        for (size_t k = 0; k < sizeof cams / sizeof cams[0]; ++k) {
            pgt_facade_camera cam;
            REQUIRE(pgt_facade_camera_init(&cam, &cams[k][0], &cams[k][3], &cams[k][6], cams[k][9],
                                           128, 96, &err) == PGT_OK);
            compare_camera(&s, fa, m.quad_count, &o, &cam, &a, 1);
            if (gimage) count_clipped_hits(&s, fa, m.quad_count, &o, clipped, &cam, &sc);
        }
        printf("  tower (%s, %u quads, %u triangles): %u rays, %u agree, %u at an edge, %u "
               "coincident faces, %u other; agreement %.4f %%, max |dt|/t %.2g\n",
               grammar, m.quad_count, x.triangle_count, a.rays, a.agree, a.near_edge, a.ties,
               a.other, 100.0 * a.agree / a.rays, a.max_rel);
        if (gimage) {
            uint32_t pieces = 0;
            for (uint32_t t = 0; t < x.triangle_count; ++t) pieces += clipped[t];
            printf("  tower geometry images: %u pieces of clipped triangles; %u rays hit a "
                   "geometry image, %u of them (oracle alike) a clipped piece, %u within %g m of "
                   "a window border\n",
                   pieces, sc.mesh_hits, sc.clipped, sc.near_border, NEAR_BORDER);
            CHECK(pieces > 0);
            CHECK_MSG(sc.near_border > 0, "no ray hit a clipped piece near a window border");
            free(clipped);
        }
        CHECK((double)(a.agree + (ties_allowed ? a.ties : 0u)) / a.rays >= AGREEMENT_MIN);
        CHECK_MSG(a.other == 0, "%u disagreements away from edges", a.other);
        CHECK_MSG(ties_allowed || a.ties == 0, "%u rays hit coincident faces", a.ties);
        oracle_free(&o);
        pgt_facade_mesh_destroy(&x);
    }
    free(fa);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
    pgt_facade_quads_destroy(&m);
}

static void test_tower_vs_explicit(void) { check_tower("facade.grammar", 0, 0); }

/* Geometry-image windows (Mesh(0), the oculus) on the tower: floors of 3.2 m and windows of
 * about 2.2 m on quads of about 2.6 x 3.75 m, so most oculi straddle quad borders and are cut
 * by two or more windows. */
static void test_tower_gimage_vs_explicit(void) { check_tower("facade_gimage.grammar", 0, 1); }

/* The rich grammar puts a balcony's slab on a floor's ledge: the slab's bottom and the ledge's
 * top are one plane. From outside a ray meets the slab's top first; but a quad's window cuts
 * the slab open at its side (each quad is its own plane, so the neighbour's slab does not close
 * the cut at a convex seam), and a ray entering there meets the two coincident faces at one
 * distance: ours and the oracle may name either (measured: 14 of 49152 rays, all at the same
 * distance within 1e-4 relative). They are counted apart, and only there. */
static void test_tower_rich_vs_explicit(void) { check_tower("facade_rich.grammar", 1, 0); }

static int write_text(const char *path, const char *text) {
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fputs(text, f);
    return fclose(f) == 0;
}

/* The quad OBJ writer and reader: the tower comes back bit for bit; malformed files name
 * FILE:LINE. */
static void test_obj_round_trip(void) {
    pgt_facade_quads m, back;
    pgt_error err = {0};
    REQUIRE(pgt_gen_tower(&m, 12.0, 8.0, 30.0, 40.0, 12, 4, &err) == PGT_OK);
    const char *path = "test_facade_mesh_tower.obj";
    REQUIRE(pgt_facade_quads_write_obj(&m, path, "test", &err) == PGT_OK);
    CHECK_MSG(pgt_facade_quads_read_obj(&back, path, &err) == PGT_OK, "%s", err.message);
    /* vertices are numbered in the order the faces first use them: compare per corner */
    CHECK(back.vertex_count == m.vertex_count && back.quad_count == m.quad_count);
    uint32_t same = 0;
    for (uint32_t c = 0; back.quad_count == m.quad_count && c < 4u * m.quad_count; ++c) {
        const uint32_t a = m.indices[c], b = back.indices[c];
        same += !memcmp(back.positions + 3u * b, m.positions + 3u * a, 3u * sizeof(float)) &&
                !memcmp(back.normals + 3u * b, m.normals + 3u * a, 3u * sizeof(float)) &&
                !memcmp(back.uvs + 2u * b, m.uvs + 2u * a, 2u * sizeof(float));
    }
    CHECK_MSG(same == 4u * m.quad_count, "%u of %u corners come back bit for bit", same,
              4u * m.quad_count);
    pgt_facade_quads_destroy(&back);
    pgt_facade_quads_destroy(&m);
    remove(path);
    static const struct {
        const char *text, *where;
        pgt_result code;
    } bad[] = {
        {"v 0 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n", ":4:", PGT_ERROR_PARSE},
        {"v 0 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1 2/1/1\n", ":4:", PGT_ERROR_PARSE},
        {"v 0 0 0\nvt 0 0\nvn 0 0 1\nf 1//1 1//1 1//1 1//1\n", ":4:", PGT_ERROR_PARSE},
        {"v 0 0\n", ":1:", PGT_ERROR_PARSE},
        {"# nothing\n", "no faces", PGT_ERROR_EMPTY},
        /* tokens after the numbers: a weight (v, vt) or a comment only, as the mesh reader */
        {"v 0 0 0 garbage\n", ":1: v takes 3 to 7 numbers, got 'garbage'", PGT_ERROR_PARSE},
        {"v 0 0 0\nvt 0 0 junk\n", ":2: vt takes 2 to 3 numbers", PGT_ERROR_PARSE},
        {"v 0 0 0 1 2 3 4 5\n", ":1: v takes 3 to 7 numbers, got '5'", PGT_ERROR_PARSE},
        {"v 0 0 0\nvt 0 0\nvn 0 0 1 xx\n", ":3: vn takes 3 numbers, got 'xx'", PGT_ERROR_PARSE},
        {"v 0 0 0\nvt 0 0\nvn 0 0 1 1\n", ":3: vn takes 3 numbers, got '1'", PGT_ERROR_PARSE},
    };
    const char *bpath = "test_facade_mesh_bad.obj";
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        REQUIRE(write_text(bpath, bad[k].text));
        pgt_error e = {0};
        CHECK(pgt_facade_quads_read_obj(&back, bpath, &e) == bad[k].code);
        CHECK_MSG(strstr(e.message, bad[k].where) != NULL, "message '%s'", e.message);
        CHECK(back.vertex_count == 0 && back.positions == NULL);
    }
    { /* a line longer than the reader's 4095 characters: a limit, named with its line */
        static char longer[5000 + 16];
        memset(longer, 'x', sizeof longer);
        memcpy(longer, "v 0 0 0\n# ", 10);
        memcpy(longer + sizeof longer - 2, "\n", 2); /* ends the line and the string */
        REQUIRE(write_text(bpath, longer));
        pgt_error e = {0};
        CHECK(pgt_facade_quads_read_obj(&back, bpath, &e) == PGT_ERROR_LIMIT);
        CHECK_MSG(strstr(e.message, ":2: line longer than 4095 characters") != NULL, "message '%s'",
                  e.message);
        CHECK(back.vertex_count == 0 && back.positions == NULL);
    }
    { /* weights and end-of-line comments are read as the mesh reader reads them */
        REQUIRE(write_text(bpath, "v 0 0 0 1 # a\nv 1 0 0 1 0 0\nv 1 1 0 1 0 0 1\nv 0 1 0#b\n"
                                  "vt 0 0 0\nvt 1 0\nvt 1 1 # c\nvt 0 1\nvn 0 0 1 # n\n"
                                  "f 1/1/1 2/2/1 3/3/1 4/4/1#the quad\n"));
        pgt_error e = {0};
        CHECK_MSG(pgt_facade_quads_read_obj(&back, bpath, &e) == PGT_OK, "%s", e.message);
        CHECK(back.quad_count == 1u && back.vertex_count == 4u);
        pgt_facade_quads_destroy(&back);
    }
    remove(bpath);
}

/* Bad meshes: an index out of range, a zero normal, collinear UVs, mirrored UVs, negative UVs,
 * a bow-tie, coordinates beyond PGT_FACADE_MAX_COORD; normals of any length. */
/* pgt_facade_mesh_facades with a cleared error (an error keeps its first message). */
static pgt_result facade_of(pgt_facade *f, const pgt_facade_quads *m, const pgt_facade_scene *s,
                            uint32_t building, pgt_error *err) {
    memset(err, 0, sizeof *err);
    return pgt_facade_mesh_facades(f, m, s, building, 0.0f, 0.0f, err);
}

static void test_mesh_errors(void) {
    pgt_grammar g;
    REQUIRE(load(&g, "facade.grammar"));
    pgt_facade_scene s;
    make_scene(&s, &g, NULL, 0, 3.0f);
    /* one unit quad in the z = 0 plane facing +z: u along +x, v along +y */
    float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    float uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    uint32_t idx[4] = {0, 1, 2, 3};
    pgt_facade_quads m = {4, 1, pos, nrm, uv, idx};
    pgt_facade f;
    pgt_error err = {0};
    CHECK_MSG(pgt_facade_mesh_facades(&f, &m, &s, 0, 0.0f, 0.0f, &err) == PGT_OK, "%s",
              err.message);
    CHECK(fabsf(f.width - 1.0f) < 1e-6f && fabsf(f.height - 1.0f) < 1e-6f);
    /* a normal's length does not matter, however far from 1 (its squares would overflow or
     * underflow: 'vn 0 0 1e30' was "a zero normal") */
    const pgt_facade f_unit = f;
    for (int e = 0; e < 2; ++e) {
        for (int k = 0; k < 4; ++k) nrm[3 * k + 2] = e ? 1e-30f : 1e30f;
        CHECK_MSG(facade_of(&f, &m, &s, 0, &err) == PGT_OK, "%s", err.message);
        CHECK(!memcmp(&f, &f_unit, sizeof f));
    }
    for (int k = 0; k < 4; ++k) nrm[3 * k + 2] = 1.0f;
    /* a bow-tie: the last two corners swapped in UV */
    const float uv_square[8] = {0, 0, 1, 0, 1, 1, 0, 1}, uv_bow[8] = {0, 0, 1, 0, 0, 1, 1, 1};
    memcpy(uv, uv_bow, sizeof uv);
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_DEGENERATE);
    CHECK_MSG(strstr(err.message, "bow-tie") != NULL, "%s", err.message);
    memcpy(uv, uv_square, sizeof uv);
    /* positions and UVs beyond PGT_FACADE_MAX_COORD (UVs of 1e30 were "building 0 has base 0
     * and height 1e+30") */
    pos[3] = 2e6f;
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_LIMIT);
    pos[3] = 1.0f, uv[2] = 2e6f;
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_LIMIT);
    uv[2] = 1.0f;
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_OK);
    CHECK(facade_of(&f, &m, &s, 1, &err) == PGT_ERROR_INDEX_RANGE);
    idx[2] = 4;
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_INDEX_RANGE);
    idx[2] = 2;
    nrm[3] = nrm[4] = nrm[5] = 0.0f;
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_DEGENERATE);
    nrm[5] = 1.0f;
    const float uv_line[8] = {0, 0, 1, 0, 2, 0, 3, 0};
    memcpy(uv, uv_line, sizeof uv);
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_DEGENERATE);
    const float uv_mirror[8] = {1, 0, 0, 0, 0, 1, 1, 1};
    memcpy(uv, uv_mirror, sizeof uv);
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_DEGENERATE);
    CHECK_MSG(strstr(err.message, "mirrored") != NULL, "%s", err.message);
    const float uv_neg[8] = {-1, 0, 0, 0, 0, 1, -1, 1};
    memcpy(uv, uv_neg, sizeof uv);
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_INVALID_ARGUMENT);
    pos[1] = NAN;
    CHECK(facade_of(&f, &m, &s, 0, &err) == PGT_ERROR_NOT_FINITE);
    pgt_facade_scene_destroy(&s);
    pgt_grammar_destroy(&g);
}

static const pgt_test_case cases[] = {
    {"cylinder_eq5_8", test_cylinder_eq5_8},
    {"tower_frames", test_tower_frames},
    {"flat_grid_equals_footprint", test_flat_grid_equals_footprint},
    {"flat_grid_gimage_equals_footprint", test_flat_grid_gimage_equals_footprint},
    {"tower_vs_explicit", test_tower_vs_explicit},
    {"tower_rich_vs_explicit", test_tower_rich_vs_explicit},
    {"tower_gimage_vs_explicit", test_tower_gimage_vs_explicit},
    {"obj_round_trip", test_obj_round_trip},
    {"mesh_errors", test_mesh_errors},
};

PGT_TEST_MAIN(cases)
