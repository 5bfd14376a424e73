/* The brute-force oracle of the facade tests (tests/test_facade.c, tests/test_facade_mesh.c):
 * a double-precision Moller-Trumbore ray caster over every triangle of the explicit twin whose
 * facade's triangle box the ray meets, and the distance from a hit to its rectangle's edges. */
#ifndef PGT_TEST_FACADE_ORACLE_H
#define PGT_TEST_FACADE_ORACLE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/facade.h>
#include <pgt/grammar.h>

/* Agreement of two hits on the same surface: the distances differ by the float rounding of
 * the facade-space transform (a few ulps of the coordinates, about 1e-6 relative), far below. */
#define DIST_REL_TOL 1e-4
/* A disagreement is "at an edge" when a hit point lies within this distance (relative to the
 * ray length, plus an absolute floor in metres) of an edge of the rectangle or triangle hit:
 * float rounding in the two computations can put such a ray on either side. */
#define EDGE_REL_EPS 1e-5
#define EDGE_ABS_EPS 1e-5
/* The bar for ray versus explicit agreement. */
#define AGREEMENT_MIN 0.9999

static int load(pgt_grammar *g, const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/grammars/%s", PGT_SOURCE_DIR, name);
    pgt_error err = {0};
    if (pgt_grammar_load(g, path, &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        return 0;
    }
    return 1;
}

/* ---- the oracle ---- */

typedef struct oracle {
    const pgt_facade_mesh *m;
    uint32_t facades;
    uint32_t *first; /* facades + 1: triangle ranges (the mesh is in facade order) */
    double *box;     /* 6 per facade: min xyz, max xyz */
} oracle;

static void oracle_init(oracle *o, const pgt_facade_mesh *m, uint32_t facades) {
    o->m = m, o->facades = facades;
    o->first = calloc(facades + 1u, sizeof *o->first);
    o->box = malloc(6u * facades * sizeof *o->box);
    for (uint32_t f = 0; f < facades; ++f)
        for (int k = 0; k < 3; ++k) o->box[6 * f + k] = INFINITY, o->box[6 * f + 3 + k] = -INFINITY;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t f = m->facade[t];
        o->first[f + 1] = t + 1u;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) {
                const double v = m->positions[3u * m->indices[3u * t + (uint32_t)c] + (uint32_t)k];
                if (v < o->box[6 * f + k]) o->box[6 * f + k] = v;
                if (v > o->box[6 * f + 3 + k]) o->box[6 * f + 3 + k] = v;
            }
    }
    for (uint32_t f = 0; f < facades; ++f)
        if (o->first[f + 1] < o->first[f]) o->first[f + 1] = o->first[f];
}

static void oracle_free(oracle *o) {
    free(o->first);
    free(o->box);
}

typedef struct ohit {
    double t, b1, b2; /* barycentrics of vertices 1 and 2 */
    uint32_t tri;     /* PGT_NONE: miss */
} ohit;

/* A facade's triangle box is flat along the facade's normal, and the slab test's (lo - o) / d
 * rounds in double (ulp 1.4e-14 at coordinates of 100 m): the box is grown by this many metres so
 * that rounding cannot cull a ray through the plane. It only lets more triangles reach the exact
 * test, so it cannot make a miss a hit. */
#define BOX_PAD 1e-9

static int box_hit(const double *bx, const double o[3], const double d[3]) {
    double t0 = 0.0, t1 = INFINITY;
    for (int k = 0; k < 3; ++k) {
        const double lo = bx[k] - BOX_PAD, hi = bx[3 + k] + BOX_PAD;
        if (d[k] == 0.0) {
            if (o[k] < lo || o[k] > hi) return 0;
            continue;
        }
        double a = (lo - o[k]) / d[k], b = (hi - o[k]) / d[k];
        if (a > b) {
            const double s = a;
            a = b, b = s;
        }
        if (a > t0) t0 = a;
        if (b < t1) t1 = b;
    }
    return t0 <= t1;
}

static ohit oracle_cast(const oracle *o, const float of[3], const float df[3]) {
    const double org[3] = {of[0], of[1], of[2]}, d[3] = {df[0], df[1], df[2]};
    ohit h = {INFINITY, 0, 0, PGT_NONE};
    const pgt_facade_mesh *m = o->m;
    for (uint32_t f = 0; f < o->facades; ++f) {
        if (!box_hit(&o->box[6 * f], org, d)) continue;
        for (uint32_t t = o->first[f]; t < o->first[f + 1]; ++t) {
            double P[3][3];
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k)
                    P[c][k] = m->positions[3u * m->indices[3u * t + (uint32_t)c] + (uint32_t)k];
            const double e1[3] = {P[1][0] - P[0][0], P[1][1] - P[0][1], P[1][2] - P[0][2]};
            const double e2[3] = {P[2][0] - P[0][0], P[2][1] - P[0][1], P[2][2] - P[0][2]};
            const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                                 d[0] * e2[1] - d[1] * e2[0]};
            const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
            if (det == 0.0) continue;
            const double s[3] = {org[0] - P[0][0], org[1] - P[0][1], org[2] - P[0][2]};
            const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
            if (u < 0.0 || u > 1.0) continue;
            const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                                 s[0] * e1[1] - s[1] * e1[0]};
            const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
            if (v < 0.0 || u + v > 1.0) continue;
            const double tt = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
            if (tt >= 0.0 && tt < h.t) h.t = tt, h.b1 = u, h.b2 = v, h.tri = t;
        }
    }
    return h;
}

static int same_point(const float *a, const float *b) {
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* Distance from point X to the boundary of surface (facade, node, surface) of the explicit mesh:
 * every edge of its triangles except those two of them share (a rectangle's diagonal, or a
 * diagonal of the fan of a geometry-image triangle clipped to a mesh quad's window: up to 5
 * pieces, whose border on the window's edge counts as an edge). */
static double rect_edge_distance(const pgt_facade_mesh *m, uint32_t facade, uint32_t node,
                                 uint32_t surface, const double X[3]) {
    uint32_t tris[8], n = 0;
    for (uint32_t t = 0; t < m->triangle_count && n < 8; ++t)
        if (m->facade[t] == facade && m->node[t] == node && m->surface[t] == surface) tris[n++] = t;
    double best = INFINITY;
    for (uint32_t a = 0; a < n; ++a)
        for (uint32_t c = 0; c < 3; ++c) {
            const float *A = &m->positions[3u * m->indices[3u * tris[a] + c]];
            const float *B = &m->positions[3u * m->indices[3u * tris[a] + (c + 1u) % 3u]];
            int shared = 0;
            for (uint32_t b2 = 0; b2 < n; ++b2)
                for (uint32_t j = 0; j < 3 && b2 != a; ++j) {
                    const float *C = &m->positions[3u * m->indices[3u * tris[b2] + j]];
                    const float *D = &m->positions[3u * m->indices[3u * tris[b2] + (j + 1u) % 3u]];
                    shared |= (same_point(A, C) && same_point(B, D)) ||
                              (same_point(A, D) && same_point(B, C));
                }
            if (shared) continue;
            double e[3], w[3];
            for (int k = 0; k < 3; ++k) e[k] = (double)B[k] - A[k], w[k] = X[k] - A[k];
            const double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            double sp = ee > 0.0 ? (w[0] * e[0] + w[1] * e[1] + w[2] * e[2]) / ee : 0.0;
            sp = sp < 0.0 ? 0.0 : (sp > 1.0 ? 1.0 : sp);
            double d2 = 0.0;
            for (int k = 0; k < 3; ++k) d2 += (w[k] - sp * e[k]) * (w[k] - sp * e[k]);
            if (sqrt(d2) < best) best = sqrt(d2);
        }
    return best;
}

/* Renders a frame from cam and compares every pixel with the oracle: agree (both miss, or the
 * same facade, node and surface at the same distance), at an edge, a tie (both hit at the same
 * distance but name different surfaces: two faces in one place), other. */
typedef struct agreement {
    uint32_t rays, agree, near_edge, other;
    double max_rel;
    uint32_t ties; /* both hit, at the same distance, different surfaces (coincident faces) */
} agreement;

static void compare_camera(const pgt_facade_scene *s, const pgt_facade *fa, uint32_t fc,
                           const oracle *o, const pgt_facade_camera *cam, agreement *a,
                           int verbose) {
    pgt_facade_frame fr;
    pgt_error err = {0};
    if (pgt_facade_frame_create(&fr, cam->width, cam->height, &err) != PGT_OK) return;
    const pgt_facade_shading sh = {.light = {0.0f, 500.0f, 0.0f}, .ambient = 0.3f};
    pgt_facade_render_stats st;
    if (pgt_facade_render(s, fa, fc, cam, &sh, 2, &fr, &st, &err) != PGT_OK) {
        fprintf(stderr, "  %s\n", err.message);
        pgt_facade_frame_destroy(&fr);
        a->other++;
        return;
    }
    const pgt_facade_mesh *m = o->m;
    for (uint32_t y = 0; y < cam->height; ++y)
        for (uint32_t x = 0; x < cam->width; ++x) {
            float org[3], dir[3];
            pgt_facade_camera_ray(cam, x, y, org, dir);
            const ohit h = oracle_cast(o, org, dir);
            const size_t p = (size_t)y * cam->width + x;
            a->rays++;
            const int ours = fr.facade[p] != PGT_NONE, theirs = h.tri != PGT_NONE;
            if (!ours && !theirs) {
                a->agree++;
                continue;
            }
            if (ours && theirs && m->facade[h.tri] == fr.facade[p] &&
                m->node[h.tri] == fr.node[p] && m->surface[h.tri] == fr.surface[p] &&
                fabs(h.t - fr.depth[p]) <= DIST_REL_TOL * h.t) {
                a->agree++;
                const double rel = fabs(h.t - fr.depth[p]) / h.t;
                if (rel > a->max_rel) a->max_rel = rel;
                continue;
            }
            /* near an edge of what either side hit? */
            double near = INFINITY, tref = 0.0;
            if (theirs) {
                double X[3];
                for (int k = 0; k < 3; ++k) X[k] = org[k] + h.t * dir[k];
                near =
                    rect_edge_distance(m, m->facade[h.tri], m->node[h.tri], m->surface[h.tri], X);
                tref = h.t;
            }
            if (ours) {
                double X[3];
                for (int k = 0; k < 3; ++k) X[k] = org[k] + (double)fr.depth[p] * dir[k];
                near =
                    fmin(near, rect_edge_distance(m, fr.facade[p], fr.node[p], fr.surface[p], X));
                if (fr.depth[p] > tref) tref = fr.depth[p];
            }
            if (near <= EDGE_REL_EPS * tref + EDGE_ABS_EPS) {
                a->near_edge++;
            } else if (ours && theirs && fabs(h.t - fr.depth[p]) <= DIST_REL_TOL * h.t) {
                /* two faces in one place (seen through a window's cut side, below): which one
                 * the nearest hit names is a coin toss in both */
                a->ties++;
            } else {
                a->other++;
                if (verbose && a->other <= 5)
                    fprintf(stderr,
                            "  pixel (%u, %u) of a %u x %u camera at (%g, %g, %g): ours facade "
                            "%u kind %g node %08x surface %u t %.6f; oracle facade %u kind %u "
                            "node %08x surface %u t %.6f; edge distance %.3g\n",
                            x, y, cam->width, cam->height, (double)cam->eye[0], (double)cam->eye[1],
                            (double)cam->eye[2], fr.facade[p], (double)fr.terminal[p], fr.node[p],
                            fr.surface[p], (double)fr.depth[p],
                            theirs ? m->facade[h.tri] : PGT_NONE, theirs ? m->kind[h.tri] : 0u,
                            theirs ? m->node[h.tri] : 0u, theirs ? m->surface[h.tri] : 0u, h.t,
                            near);
            }
        }
    pgt_facade_frame_destroy(&fr);
}

/* Renders `sh` with every ray developed alone (single_rays) into a new frame and counts the
 * channels (rgb, depth, terminal, normal, facade, node, surface, developed: 8) and the
 * statistics (rays, volume hits, nodes, terminals, rectangle tests, errors, covered pixels: 7)
 * in which it differs from `packed`, rendered by the same call with packets (stats `ps`). */
static uint32_t packets_differ(const pgt_facade_scene *s, const pgt_facade *fa, uint32_t fc,
                               const pgt_facade_camera *cam, const pgt_facade_shading *sh,
                               const pgt_facade_frame *packed, const pgt_facade_render_stats *ps) {
    pgt_facade_frame one;
    pgt_error err = {0};
    if (pgt_facade_frame_create(&one, cam->width, cam->height, &err) != PGT_OK) return 15;
    const size_t n = (size_t)cam->width * cam->height;
    /* a hits-only frame leaves rgb and normal as they were: the same start for both */
    memcpy(one.rgb, packed->rgb, 3 * n * sizeof(float));
    memcpy(one.normal, packed->normal, 3 * n * sizeof(float));
    memcpy(one.terminal, packed->terminal, n * sizeof(float));
    memcpy(one.node, packed->node, n * sizeof(uint32_t));
    memcpy(one.surface, packed->surface, n * sizeof(uint32_t));
    pgt_facade_shading alone = *sh;
    alone.single_rays = 1;
    pgt_facade_render_stats os;
    uint32_t d = 0;
    if (pgt_facade_render(s, fa, fc, cam, &alone, 2, &one, &os, &err) != PGT_OK) {
        pgt_facade_frame_destroy(&one);
        return 15;
    }
    d += memcmp(one.rgb, packed->rgb, 3 * n * sizeof(float)) != 0;
    d += memcmp(one.depth, packed->depth, n * sizeof(float)) != 0;
    d += memcmp(one.terminal, packed->terminal, n * sizeof(float)) != 0;
    d += memcmp(one.normal, packed->normal, 3 * n * sizeof(float)) != 0;
    d += memcmp(one.facade, packed->facade, n * sizeof(uint32_t)) != 0;
    d += memcmp(one.node, packed->node, n * sizeof(uint32_t)) != 0;
    d += memcmp(one.surface, packed->surface, n * sizeof(uint32_t)) != 0;
    d += memcmp(one.developed, packed->developed, n * sizeof(uint32_t)) != 0;
    d += os.rays.rays != ps->rays.rays;
    d += os.rays.volume_hits != ps->rays.volume_hits;
    d += os.rays.nodes != ps->rays.nodes;
    d += os.rays.terminals != ps->rays.terminals;
    d += os.rays.quads != ps->rays.quads;
    d += os.rays.errors != ps->rays.errors;
    d += os.covered_pixels != ps->covered_pixels;
    pgt_facade_frame_destroy(&one);
    return d;
}

#endif
