/* pgt: procedural facades on generic quad meshes (issue 6 item 6).
 *
 * This work is based on:
 *   Marvie, Gautron, Hirtzlin, Sourimant, "Render-Time Procedural Per-Pixel Geometry
 *   Generation", GI 2011 (paper 003): sec. 10.1 (facade space per vertex by selective adjacency
 *   extraction, eq. 5-7, Fig. 13) and 10.2 (each quad a facade of width and height eq. 8).
 *
 * Choices the paper leaves open (facade.h says them too):
 *   - "pp_i . pp_j minimal" with Fig. 13's "nearly orthogonal": the pair with the smallest
 *     |cos| of the angle between pp_i and pp_j; a pair whose UV offsets are (nearly) collinear
 *     cannot give eq. 6-7 (their denominator vanishes) and is passed over.
 *   - Each quad's facade space is that of its origin corner, the corner with the smallest u + v;
 *     eq. 8 takes that corner's two neighbours in the quad, so w and h describe this quad (the
 *     pair chosen for t_F and b_F may belong to another quad around the vertex).
 *   - The facade frame is orthonormal (the ray development works in an orthonormal facade space):
 *     t = t_F, b = n x t, so n = t x b as for footprint facades.
 *   - The quad's window in grammar space starts at its origin's (u, v) with eq. 8's w x h (not
 *     the quad's UV extent: where the two differ, as for a chord against its arc, neighbouring
 *     windows overlap or leave a gap of that difference in grammar space), except that a w or h
 *     within float rounding (FACADE_MESH_SNAP) of the UV extent is taken as the UV extent.
 * Everything is float32, computed in the order written (-ffp-contract=off), like the rest of the
 * reference. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/facade.h"
#include "vec3_internal.h"

/* A pair of neighbours is usable when the sine of the angle between their UV offsets is above
 * this: below it eq. 6-7 divide by (almost) zero. 1e-3 is an angle of 0.06 degrees, far below
 * any UV layout an artist makes and far above float32 rounding of metre-sized offsets. */
#define FACADE_MESH_MIN_UV_SIN 1e-3f

/* Distinct neighbours of one vertex at most: the pair search below is quadratic in them (a fan of
 * 40,000 quads around one vertex took 23 s); a quad mesh's vertex has 4 to a few dozen, a pole
 * of a 1024-sided cylinder cap 1024. */
#define FACADE_MESH_MAX_NEIGHBOURS 1024u
/* eq. 8's w (h) within this much, relative to the UV coordinates' size, of the quad's UV extent
 * is taken as that extent: float32 rounding of positions and of eq. 5 and 8 (a few ulps of the
 * coordinates, ~1e-6 relative) stays far inside; a real difference (a chord against its arc,
 * 1e-3 relative for 24 segments around) far outside. */
#define FACADE_MESH_SNAP 1e-5f

void pgt_facade_quads_destroy(pgt_facade_quads *q) {
    if (!q) return;
    free(q->positions);
    free(q->normals);
    free(q->uvs);
    free(q->indices);
    memset(q, 0, sizeof *q);
}

static int unit(float v[3]) {
    const float l2 = dot3(v, v);
    if (!(l2 >= FLT_MIN && l2 <= FLT_MAX)) {
        /* the squares of a finite vector over- or underflow beyond ~1e19 or below ~1e-19 (an
         * OBJ normal 'vn 0 0 1e30' is a direction like any other): scaled to its largest
         * component first. Only then, so that other vectors keep their bits. */
        if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2])) return 0; /* NaN too */
        const float m = fmaxf(fabsf(v[0]), fmaxf(fabsf(v[1]), fabsf(v[2])));
        if (!(m > 0.0f)) return 0;
        v[0] /= m, v[1] /= m, v[2] /= m;
    }
    const float l = sqrtf(dot3(v, v));
    v[0] /= l, v[1] /= l, v[2] /= l;
    return 1;
}

static int cmp_u32(const void *a, const void *b) {
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : (x > y);
}

/* Orientation of c against the line a -> b in the UV plane (double: the products of metre-sized
 * UV differences are exact enough that touching corners are told from crossing ones). */
static double orient2(const float *a, const float *b, const float *c) {
    return ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
           ((double)b[1] - a[1]) * ((double)c[0] - a[0]);
}

/* Whether segments ab and cd cross at a point inside both (not at a shared or touching end). */
static int segments_cross(const float *a, const float *b, const float *c, const float *d) {
    const double o1 = orient2(a, b, c), o2 = orient2(a, b, d);
    const double o3 = orient2(c, d, a), o4 = orient2(c, d, b);
    return ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) &&
           ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0));
}

/* Checks indices and values. */
static pgt_result check_mesh(const pgt_facade_quads *m, pgt_error *err) {
    if ((m->vertex_count && (!m->positions || !m->normals || !m->uvs)) ||
        (m->quad_count && !m->indices))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "quad mesh: missing arrays");
    for (uint32_t q = 0; q < m->quad_count; ++q)
        for (uint32_t c = 0; c < 4; ++c) {
            const uint32_t v = m->indices[4u * q + c];
            if (v >= m->vertex_count)
                return pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                     "quad mesh: quad %u corner %u is vertex %u of %u", q, c, v,
                                     m->vertex_count);
            for (uint32_t k = 0; k < c; ++k)
                if (m->indices[4u * q + k] == v)
                    return pgt_error_set(err, PGT_ERROR_DEGENERATE,
                                         "quad mesh: quad %u lists vertex %u twice", q, v);
        }
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        for (int k = 0; k < 3; ++k)
            if (!isfinite(m->positions[3u * v + (uint32_t)k]) ||
                !isfinite(m->normals[3u * v + (uint32_t)k]))
                return pgt_error_set(err, PGT_ERROR_NOT_FINITE,
                                     "quad mesh: vertex %u: position or normal not finite", v);
        if (!isfinite(m->uvs[2u * v]) || !isfinite(m->uvs[2u * v + 1u]))
            return pgt_error_set(err, PGT_ERROR_NOT_FINITE, "quad mesh: vertex %u: UV not finite",
                                 v);
        const float *p = m->positions + 3u * v, *t = m->uvs + 2u * v;
        if (!(fabsf(p[0]) <= PGT_FACADE_MAX_COORD && fabsf(p[1]) <= PGT_FACADE_MAX_COORD &&
              fabsf(p[2]) <= PGT_FACADE_MAX_COORD && fabsf(t[0]) <= PGT_FACADE_MAX_COORD &&
              fabsf(t[1]) <= PGT_FACADE_MAX_COORD))
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "quad mesh: vertex %u: position (%g, %g, %g) or UV (%g, %g) "
                                 "beyond +-%g metres (PGT_FACADE_MAX_COORD)",
                                 v, (double)p[0], (double)p[1], (double)p[2], (double)t[0],
                                 (double)t[1], (double)PGT_FACADE_MAX_COORD);
    }
    /* a bow-tie: corners not in order around the quad, two opposite sides cross in UV */
    for (uint32_t q = 0; q < m->quad_count; ++q) {
        const uint32_t *c = m->indices + 4u * q;
        const float *t0 = m->uvs + 2u * c[0], *t1 = m->uvs + 2u * c[1], *t2 = m->uvs + 2u * c[2],
                    *t3 = m->uvs + 2u * c[3];
        if (segments_cross(t0, t1, t2, t3) || segments_cross(t1, t2, t3, t0))
            return pgt_error_set(err, PGT_ERROR_DEGENERATE,
                                 "quad mesh: quad %u: two opposite sides cross in UV (a bow-tie: "
                                 "the corners must go in order around the quad)",
                                 q);
    }
    return PGT_OK;
}

/* Eq. 5: p_i projected on the tangent plane of p (unit normal n), as the offset p'_i - p. */
static void project(const float p[3], const float n[3], const float pi[3], float out[3]) {
    const float s = dot3(n, p) - dot3(n, pi);
    for (int k = 0; k < 3; ++k) out[k] = pi[k] + s * n[k] - p[k];
}

pgt_result pgt_facade_mesh_frames(float *out_t, float *out_b, uint32_t *out_pair,
                                  const pgt_facade_quads *m, pgt_error *err) {
    pgt_result r = check_mesh(m, err);
    if (r != PGT_OK) return r;
    const uint32_t V = m->vertex_count, Q = m->quad_count;
    /* one-ring by quad edges: each quad gives each corner its two neighbours in the quad */
    uint32_t *first = calloc((size_t)V + 1u, sizeof *first);
    uint32_t *adj = malloc((size_t)(Q ? Q : 1u) * 8u * sizeof *adj);
    if (!first || !adj) {
        free(first), free(adj);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "quad mesh: out of memory");
    }
    for (uint32_t q = 0; q < Q; ++q)
        for (uint32_t c = 0; c < 4; ++c) first[m->indices[4u * q + c] + 1u] += 2u;
    for (uint32_t v = 0; v < V; ++v) first[v + 1u] += first[v];
    uint32_t *fill = malloc((size_t)(V ? V : 1u) * sizeof *fill);
    if (!fill) {
        free(first), free(adj);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "quad mesh: out of memory");
    }
    memcpy(fill, first, (size_t)V * sizeof *fill);
    for (uint32_t q = 0; q < Q; ++q)
        for (uint32_t c = 0; c < 4; ++c) {
            const uint32_t v = m->indices[4u * q + c];
            adj[fill[v]++] = m->indices[4u * q + (c + 1u) % 4u];
            adj[fill[v]++] = m->indices[4u * q + (c + 3u) % 4u];
        }
    free(fill);
    for (uint32_t v = 0; v < V && r == PGT_OK; ++v) {
        float *t = out_t + 3u * v, *b = out_b + 3u * v;
        t[0] = t[1] = t[2] = b[0] = b[1] = b[2] = 0.0f;
        if (out_pair) out_pair[2u * v] = out_pair[2u * v + 1u] = PGT_NONE;
        uint32_t *nb = adj + first[v];
        const uint32_t cnt = first[v + 1u] - first[v];
        if (cnt == 0) continue;
        qsort(nb, cnt, sizeof *nb, cmp_u32);
        uint32_t k = 0;
        for (uint32_t i = 0; i < cnt; ++i) /* unique */
            if (k == 0 || nb[k - 1u] != nb[i]) nb[k++] = nb[i];
        if (k > FACADE_MESH_MAX_NEIGHBOURS) {
            r = pgt_error_set(err, PGT_ERROR_LIMIT,
                              "quad mesh: vertex %u has %u neighbours (at most %u: the search for "
                              "its two tangent neighbours is quadratic)",
                              v, k, FACADE_MESH_MAX_NEIGHBOURS);
            break;
        }
        const float *p = m->positions + 3u * v;
        float n[3] = {m->normals[3u * v], m->normals[3u * v + 1u], m->normals[3u * v + 2u]};
        if (!unit(n)) {
            r = pgt_error_set(err, PGT_ERROR_DEGENERATE, "quad mesh: vertex %u has a zero normal",
                              v);
            break;
        }
        const float u = m->uvs[2u * v], vv = m->uvs[2u * v + 1u];
        float best = INFINITY;
        uint32_t bi = PGT_NONE, bj = PGT_NONE;
        for (uint32_t i = 0; i < k; ++i)
            for (uint32_t j = i + 1u; j < k; ++j) {
                const float *pi = m->positions + 3u * nb[i], *pj = m->positions + 3u * nb[j];
                const float ei[3] = {pi[0] - p[0], pi[1] - p[1], pi[2] - p[2]};
                const float ej[3] = {pj[0] - p[0], pj[1] - p[1], pj[2] - p[2]};
                const float li = sqrtf(dot3(ei, ei)), lj = sqrtf(dot3(ej, ej));
                if (!(li > 0.0f && lj > 0.0f)) continue;
                const float dui = m->uvs[2u * nb[i]] - u, dvi = m->uvs[2u * nb[i] + 1u] - vv;
                const float duj = m->uvs[2u * nb[j]] - u, dvj = m->uvs[2u * nb[j] + 1u] - vv;
                const float det = dui * dvj - duj * dvi;
                if (!(fabsf(det) > FACADE_MESH_MIN_UV_SIN * sqrtf(dui * dui + dvi * dvi) *
                                       sqrtf(duj * duj + dvj * dvj)))
                    continue;
                const float c = fabsf(dot3(ei, ej)) / (li * lj);
                if (c < best) best = c, bi = nb[i], bj = nb[j];
            }
        if (bi == PGT_NONE) {
            r = pgt_error_set(err, PGT_ERROR_DEGENERATE,
                              "quad mesh: vertex %u has no two neighbours with independent UV "
                              "offsets (selective adjacency extraction, paper 003 sec. 10.1)",
                              v);
            break;
        }
        float ei[3], ej[3];
        project(p, n, m->positions + 3u * bi, ei); /* eq. 5 */
        project(p, n, m->positions + 3u * bj, ej);
        const float dui = m->uvs[2u * bi] - u, dvi = m->uvs[2u * bi + 1u] - vv;
        const float duj = m->uvs[2u * bj] - u, dvj = m->uvs[2u * bj + 1u] - vv;
        const float dt = duj * dvi - dui * dvj, db = dui * dvj - duj * dvi;
        for (int c = 0; c < 3; ++c) {
            t[c] = (dvi * ej[c] - dvj * ei[c]) / dt; /* eq. 6 */
            b[c] = (dui * ej[c] - duj * ei[c]) / db; /* eq. 7 */
        }
        if (!unit(t) || !unit(b)) {
            r = pgt_error_set(err, PGT_ERROR_DEGENERATE,
                              "quad mesh: vertex %u: eq. 6-7 give a zero tangent or binormal "
                              "(neighbours %u and %u project onto the vertex)",
                              v, bi, bj);
            break;
        }
        if (out_pair) out_pair[2u * v] = bi, out_pair[2u * v + 1u] = bj;
    }
    free(first), free(adj);
    return r;
}

pgt_result pgt_facade_mesh_facades(pgt_facade *out, const pgt_facade_quads *m,
                                   const pgt_facade_scene *s, uint32_t building, float scope_w,
                                   float scope_h, pgt_error *err) {
    if (building >= s->building_count)
        return pgt_error_set(err, PGT_ERROR_INDEX_RANGE, "quad mesh: building %u of %u", building,
                             s->building_count);
    const pgt_facade_building *B = &s->buildings[building];
    const pgt_grammar *g = &s->grammars[B->grammar];
    const uint32_t ip = pgt_grammar_find_param(g, "protrusion"),
                   ir = pgt_grammar_find_param(g, "recess");
    if (ip == PGT_NONE || ir == PGT_NONE)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "quad mesh: the grammar lacks the param protrusion or recess");
    const uint32_t V = m->vertex_count;
    float *tb = malloc((size_t)(V ? V : 1u) * 6u * sizeof *tb);
    if (!tb) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "quad mesh: out of memory");
    pgt_result r = pgt_facade_mesh_frames(tb, tb + 3u * V, NULL, m, err);
    float W = 0.0f, H = 0.0f;
    for (uint32_t v = 0; v < V && r == PGT_OK; ++v) {
        const float u = m->uvs[2u * v], vv = m->uvs[2u * v + 1u];
        if (u < 0.0f || vv < 0.0f)
            r = pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                              "quad mesh: vertex %u has UV (%g, %g); facade space starts at 0", v,
                              (double)u, (double)vv);
        W = u > W ? u : W, H = vv > H ? vv : H;
    }
    for (uint32_t q = 0; q < m->quad_count && r == PGT_OK; ++q) {
        const uint32_t *c = m->indices + 4u * q;
        uint32_t o = 0;
        for (uint32_t k = 1; k < 4; ++k)
            if (m->uvs[2u * c[k]] + m->uvs[2u * c[k] + 1u] <
                m->uvs[2u * c[o]] + m->uvs[2u * c[o] + 1u])
                o = k;
        const uint32_t v = c[o];
        const float *p = m->positions + 3u * v;
        pgt_facade *F = &out[q];
        memset(F, 0, sizeof *F);
        float n[3] = {m->normals[3u * v], m->normals[3u * v + 1u], m->normals[3u * v + 2u]};
        unit(n);
        float t[3] = {tb[3u * v], tb[3u * v + 1u], tb[3u * v + 2u]};
        const float *bF = tb + 3u * V + 3u * v;
        /* t_F lies in the tangent plane up to rounding: take that out before b = n x t */
        const float tn = dot3(t, n);
        for (int k = 0; k < 3; ++k) t[k] -= tn * n[k];
        float b[3];
        cross3(n, t, b);
        if (!unit(t) || !unit(b) || !(dot3(b, bF) > 0.0f)) {
            r = pgt_error_set(err, PGT_ERROR_DEGENERATE,
                              "quad mesh: quad %u: at vertex %u the UVs are mirrored or the "
                              "tangent is along the normal (u must grow along t, v along b with "
                              "t x b = n, the outward normal)",
                              q, v);
            break;
        }
        /* eq. 8: the quad's neighbours of p, projected (eq. 5) */
        float ei[3], ej[3];
        project(p, n, m->positions + 3u * c[(o + 1u) % 4u], ei);
        project(p, n, m->positions + 3u * c[(o + 3u) % 4u], ej);
        const float w8 = fmaxf(fabsf(dot3(ei, t)), fabsf(dot3(ej, t)));
        const float h8 = fmaxf(fabsf(dot3(ei, b)), fabsf(dot3(ej, b)));
        /* eq. 8 on a quad whose corners sit at its UV rectangle gives that rectangle up to
         * float rounding: take the UV extent then, so that such quads tile grammar space with
         * no sliver between windows (and a terminal face on the mesh's border stays in) */
        float du = 0.0f, dv = 0.0f;
        for (uint32_t k = 0; k < 4; ++k) {
            du = fmaxf(du, m->uvs[2u * c[k]] - m->uvs[2u * v]);
            dv = fmaxf(dv, m->uvs[2u * c[k] + 1u] - m->uvs[2u * v + 1u]);
        }
        const float su = FACADE_MESH_SNAP * (fabsf(m->uvs[2u * v]) + du + 1.0f);
        const float sv = FACADE_MESH_SNAP * (fabsf(m->uvs[2u * v + 1u]) + dv + 1.0f);
        const float w = fabsf(w8 - du) <= su ? du : w8, h = fabsf(h8 - dv) <= sv ? dv : h8;
        if (!(w >= PGT_FACADE_MESH_MIN_SIZE && h >= PGT_FACADE_MESH_MIN_SIZE)) {
            r = pgt_error_set(err, PGT_ERROR_DEGENERATE,
                              "quad mesh: quad %u is %g x %g in facade space (eq. 8), below %g", q,
                              (double)w, (double)h, (double)PGT_FACADE_MESH_MIN_SIZE);
            break;
        }
        memcpy(F->origin, p, sizeof F->origin);
        memcpy(F->t, t, sizeof F->t);
        memcpy(F->b, b, sizeof F->b);
        memcpy(F->n, n, sizeof F->n);
        F->u0 = m->uvs[2u * v], F->v0 = m->uvs[2u * v + 1u];
        F->width = w, F->height = h;
        F->protrusion = s->params[B->first_param + ip], F->recess = s->params[B->first_param + ir];
        F->building = building, F->edge = q;
        F->axiom_key = pgt_facade_child_key(B->seed, 0);
        W = F->u0 + w > W ? F->u0 + w : W, H = F->v0 + h > H ? F->v0 + h : H;
    }
    for (uint32_t q = 0; q < m->quad_count && r == PGT_OK; ++q)
        out[q].scope_w = scope_w > 0.0f ? scope_w : W,
        out[q].scope_h = scope_h > 0.0f ? scope_h : H;
    free(tb);
    return r;
}
