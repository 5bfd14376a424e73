/* pgt: geometry-image terminals (paper 003 sec. 6.2.2): a triangle mesh packed as a 1D geometry
 * image (9 floats a triangle) and intersected brute force, every triangle tested, "as in the
 * paper" (its window and door blocks had 286 and 732 triangles).
 *
 * The built-in oculus (PGT_FACADE_GIMAGE_OCULUS), in block units (x, y in [0, 1] across the
 * scope, centre (0.5, 0.5); z in metres), with N = OCULUS_SEGMENTS around:
 *   wall ring at z = 0 between the block's square border and the frame's outer circle R2
 *     (border points: the circle's directions pushed out to the square; N is a multiple of 8,
 *     so the square's corners are among them), 2N triangles;
 *   frame ring: front at z = FD (R1..R2), outer side (R2, z 0..FD), back at z = 0 (R1..R2, the
 *     wall plane closed behind the solid as facade_terminals.c does), 6N;
 *   reveal: the cylinder R1 from z = FD back to -REC, 2N; glass: the disc R1 at z = -REC, N.
 * 11 N = 352 triangles. In a scope that is not square the circles are ellipses. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "facade_internal.h"

#define OCULUS_SEGMENTS 32u
#define OCULUS_R1 0.34f  /* the opening's radius (block units) */
#define OCULUS_R2 0.42f  /* the frame's outer radius */
#define OCULUS_FD 0.06f  /* frame depth (m) */
#define OCULUS_REC 0.15f /* glass recess (m) */

typedef struct tbuf {
    float *d;
    uint8_t *role;
    uint32_t n;
    uint8_t cur; /* the role of the triangles being added */
} tbuf;

static void tri(tbuf *b, const float p[3], const float q[3], const float r[3]) {
    b->role[b->n] = b->cur;
    float *o = b->d + 9u * b->n++;
    memcpy(o, p, 3 * sizeof(float));
    memcpy(o + 3, q, 3 * sizeof(float));
    memcpy(o + 6, r, 3 * sizeof(float));
}

/* Two triangles of the quad p q r s (in order around it). */
static void quad(tbuf *b, const float p[3], const float q[3], const float r[3], const float s[3]) {
    tri(b, p, q, r);
    tri(b, p, r, s);
}

static void circle(float R, uint32_t i, float z, float out[3]) {
    const double a = 2.0 * 3.14159265358979323846 * (double)i / OCULUS_SEGMENTS;
    out[0] = (float)(0.5 + R * cos(a)), out[1] = (float)(0.5 + R * sin(a)), out[2] = z;
}

static void border(uint32_t i, float out[3]) {
    const double a = 2.0 * 3.14159265358979323846 * (double)i / OCULUS_SEGMENTS;
    const double c = cos(a), s = sin(a), m = fmax(fabs(c), fabs(s));
    out[0] = (float)(0.5 + 0.5 * c / m), out[1] = (float)(0.5 + 0.5 * s / m), out[2] = 0.0f;
}

static uint32_t oculus(float *d, uint8_t *role) {
    tbuf b = {d, role, 0, PGT_FACADE_ROLE_WALL};
    const float centre[3] = {0.5f, 0.5f, -OCULUS_REC};
    for (uint32_t i = 0; i < OCULUS_SEGMENTS; ++i) {
        const uint32_t j = (i + 1u) % OCULUS_SEGMENTS;
        float s0[3], s1[3], a0[3], a1[3], b0[3], b1[3], f0[3], f1[3], g0[3], g1[3];
        border(i, s0), border(j, s1);
        circle(OCULUS_R2, i, 0.0f, a0), circle(OCULUS_R2, j, 0.0f, a1);
        b.cur = PGT_FACADE_ROLE_WALL;
        quad(&b, a0, s0, s1, a1); /* wall ring */
        b.cur = PGT_FACADE_ROLE_FRAME;
        circle(OCULUS_R1, i, OCULUS_FD, f0), circle(OCULUS_R1, j, OCULUS_FD, f1);
        circle(OCULUS_R2, i, OCULUS_FD, g0), circle(OCULUS_R2, j, OCULUS_FD, g1);
        quad(&b, f0, g0, g1, f1); /* frame front */
        quad(&b, a0, a1, g1, g0); /* frame outer side */
        circle(OCULUS_R1, i, 0.0f, b0), circle(OCULUS_R1, j, 0.0f, b1);
        quad(&b, b0, b1, a1, a0); /* frame back, in the wall plane */
        float r0[3], r1[3];
        circle(OCULUS_R1, i, -OCULUS_REC, r0), circle(OCULUS_R1, j, -OCULUS_REC, r1);
        b.cur = PGT_FACADE_ROLE_REVEAL;
        quad(&b, r0, r1, f1, f0); /* reveal */
        b.cur = PGT_FACADE_ROLE_GLASS;
        tri(&b, centre, r1, r0); /* glass */
    }
    return b.n;
}

/* Does a grammar of the scene have a Mesh terminal? */
static int scene_uses_gimages(const pgt_facade_scene *s) {
    for (uint32_t k = 0; s->grammars && k < s->grammar_count; ++k) {
        const pgt_grammar *g = &s->grammars[k];
        for (uint32_t i = 0; i < g->item_count; ++i)
            if (g->items[i].kind == PGT_GRAMMAR_ITEM_TERMINAL &&
                g->items[i].target == PGT_GRAMMAR_TERMINAL_MESH)
                return 1;
    }
    return 0;
}

pgt_result pgt_facade_add_builtin_gimages(pgt_facade_scene *s, pgt_error *err) {
    if (!scene_uses_gimages(s)) return PGT_OK; /* no data the scene does not use */
    const uint32_t add = 11u * OCULUS_SEGMENTS;
    float *d =
        realloc(s->gimage_data, (size_t)(s->gimage_triangle_count + add) * 9u * sizeof(float));
    if (!d) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "geometry images: out of memory");
    s->gimage_data = d;
    pgt_facade_gimage *g = realloc(s->gimages, (size_t)(s->gimage_count + 1u) * sizeof *g);
    if (!g) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "geometry images: out of memory");
    s->gimages = g;
    uint8_t *ro = realloc(s->gimage_roles, (size_t)(s->gimage_triangle_count + add));
    if (!ro) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "geometry images: out of memory");
    s->gimage_roles = ro;
    const uint32_t n =
        oculus(d + 9u * (size_t)s->gimage_triangle_count, ro + s->gimage_triangle_count);
    pgt_facade_gimage *gi = &g[s->gimage_count];
    gi->first = s->gimage_triangle_count, gi->count = n;
    facade_gimage_z_range(d + 9u * (size_t)gi->first, n, &gi->zlo, &gi->zhi);
    s->gimage_count++, s->gimage_triangle_count += n;
    return PGT_OK;
}

void facade_gimage_z_range(const float *d, uint32_t n, float *zlo, float *zhi) {
    float lo = INFINITY, hi = -INFINITY;
    for (uint32_t i = 0; i < 3u * n; ++i) {
        const float z = d[3u * i + 2u];
        lo = z < lo ? z : lo, hi = z > hi ? z : hi;
    }
    *zlo = lo, *zhi = hi;
}

/* The triangles of geometry image id (a whole number below gimage_count) and the index of its
 * first in the scene's image; returns the count, 0 for a bad id. */
uint32_t facade_gimage_triangles(const pgt_facade_scene *s, float id, const float **data,
                                 uint32_t *first) {
    if (!(id >= 0.0f && id < (float)s->gimage_count) || id != floorf(id)) return 0;
    const pgt_facade_gimage *g = &s->gimages[(uint32_t)id];
    *first = g->first;
    *data = s->gimage_data + 9u * (size_t)g->first;
    return g->count;
}

/* Nearest triangle of the geometry image hit at t in (0, *best) by the block-local ray a + t v
 * (Moller-Trumbore in float, vertices scaled to the scope on the fly); PGT_NONE if none. win
 * (NULL: the whole facade) keeps only hits whose facade-space point, the block-local point plus
 * off (the block's corner, as the explicit twin places the triangle), lies in the window
 * (inclusive, as hit_quads): a mesh quad's window cuts the triangles the explicit twin clips. */
static inline __attribute__((always_inline)) uint32_t
gimage_hit(const float *d, uint32_t n, float w, float h, const float a[3], const float v[3],
           const float *win, const float off[2], float *best, float nrm[3]) {
    uint32_t found = PGT_NONE;
    for (uint32_t k = 0; k < n; ++k) {
        const float *T = d + 9u * k;
        const float p0[3] = {T[0] * w, T[1] * h, T[2]};
        const float e1[3] = {T[3] * w - p0[0], T[4] * h - p0[1], T[5] - p0[2]};
        const float e2[3] = {T[6] * w - p0[0], T[7] * h - p0[1], T[8] - p0[2]};
        const float q[3] = {v[1] * e2[2] - v[2] * e2[1], v[2] * e2[0] - v[0] * e2[2],
                            v[0] * e2[1] - v[1] * e2[0]};
        const float det = e1[0] * q[0] + e1[1] * q[1] + e1[2] * q[2];
        if (det == 0.0f) continue;
        const float inv = 1.0f / det;
        const float sv[3] = {a[0] - p0[0], a[1] - p0[1], a[2] - p0[2]};
        const float u = (sv[0] * q[0] + sv[1] * q[1] + sv[2] * q[2]) * inv;
        if (u < 0.0f || u > 1.0f) continue;
        const float r[3] = {sv[1] * e1[2] - sv[2] * e1[1], sv[2] * e1[0] - sv[0] * e1[2],
                            sv[0] * e1[1] - sv[1] * e1[0]};
        const float vv = (v[0] * r[0] + v[1] * r[1] + v[2] * r[2]) * inv;
        if (vv < 0.0f || u + vv > 1.0f) continue;
        const float t = (e2[0] * r[0] + e2[1] * r[1] + e2[2] * r[2]) * inv;
        if (!(t > 0.0f && t < *best)) continue;
        if (win) {
            const float x = (a[0] + t * v[0]) + off[0], y = (a[1] + t * v[1]) + off[1];
            if (x < win[0] || x > win[2] || y < win[1] || y > win[3]) continue;
        }
        *best = t, found = k;
        nrm[0] = e1[1] * e2[2] - e1[2] * e2[1], nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
        nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
    }
    if (found != PGT_NONE) {
        const float l = sqrtf(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        for (int k = 0; k < 3; ++k) nrm[k] /= l;
    }
    return found;
}

/* Inlined twice: with win NULL (every footprint facade) the loop compiles without the window
 * test, as it was before mesh quads took geometry images (callgrind: a loop that carries win and
 * off costs 2.8 % more instructions on the footprint city). */
uint32_t facade_gimage_hit(const float *d, uint32_t n, float w, float h, const float a[3],
                           const float v[3], const float *win, const float off[2], float *best,
                           float nrm[3]) {
    if (!win) return gimage_hit(d, n, w, h, a, v, NULL, NULL, best, nrm);
    return gimage_hit(d, n, w, h, a, v, win, off, best, nrm);
}
