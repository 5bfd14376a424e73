/* pgt: facade scenes, facade space, the camera, ray-dependent grammar development (paper 003
 * Algorithm 1) and its explicit twin (every terminal instantiated). See facade.h. */
#include "pgt/facade.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facade_internal.h"
#include "pgt/rng.h"
#include "pgt/split.h"
#include "vec3_internal.h"

/* A footprint edge shorter than this (metres) has no facade direction. */
#define FACADE_MIN_EDGE 1e-4f

/* The footprint's edges are tested pairwise for crossings (O(n^2)): 4096 corners, 8M tests. */
#define FACADE_MAX_CORNERS 4096u

/* ---- scene ---- */

static const char *gname(const pgt_grammar *g) { return g->names + g->file_name; }

/* A rule that calls itself through rule calls alone (no split between: the scope never shrinks)
 * would be developed forever: Kahn's algorithm on the graph "rule r's cases call rule q". */
static pgt_result check_call_cycles(const pgt_grammar *g, const char *what, pgt_error *err) {
    const uint32_t R = g->rule_count;
    uint32_t *indeg = calloc(R ? R : 1u, sizeof *indeg),
             *queue = malloc((R ? R : 1u) * sizeof *queue);
    if (!indeg || !queue) {
        free(indeg), free(queue);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
    }
#define FOR_CALLS(r, body)                                                                         \
    for (uint32_t c_ = 0; c_ < g->rules[r].case_count; ++c_) {                                     \
        const pgt_grammar_sequence *sq_ =                                                          \
            &g->sequences[g->cases[g->rules[r].first_case + c_].sequence];                         \
        for (uint32_t i_ = 0; i_ < sq_->item_count; ++i_) {                                        \
            const pgt_grammar_item *it_ = &g->items[sq_->first_item + i_];                         \
            if (it_->kind == PGT_GRAMMAR_ITEM_CALL) {                                              \
                const uint32_t q_ = it_->target;                                                   \
                body                                                                               \
            }                                                                                      \
        }                                                                                          \
    }
    for (uint32_t r = 0; r < R; ++r) FOR_CALLS(r, indeg[q_]++;)
    uint32_t head = 0, tail = 0;
    for (uint32_t r = 0; r < R; ++r)
        if (indeg[r] == 0) queue[tail++] = r;
    while (head < tail) {
        const uint32_t r = queue[head++];
        FOR_CALLS(r, if (--indeg[q_] == 0) queue[tail++] = q_;)
    }
#undef FOR_CALLS
    pgt_result res = PGT_OK;
    for (uint32_t r = 0; r < R && tail < R; ++r)
        if (indeg[r] > 0) {
            res = pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                "%s:%u:%u: rule %s calls itself through rule calls without a split "
                                "between (%s: a facade would develop it forever)",
                                gname(g), g->rules[r].line, g->rules[r].col,
                                g->names + g->rules[r].name, what);
            break;
        }
    free(indeg), free(queue);
    return res;
}

/* Sign of the turn a -> b -> c in the x-z plane (double: exact enough for float corners). */
static int orient2(const float *a, const float *b, const float *c) {
    const double v = ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
                     ((double)b[1] - a[1]) * ((double)c[0] - a[0]);
    return (v > 0.0) - (v < 0.0);
}

/* q lies on segment [a, b] when the three are collinear. */
static int within(const float *a, const float *b, const float *q) {
    return fminf(a[0], b[0]) <= q[0] && q[0] <= fmaxf(a[0], b[0]) && fminf(a[1], b[1]) <= q[1] &&
           q[1] <= fmaxf(a[1], b[1]);
}

/* Segments [a, b] and [p, q] share a point. */
static int segments_meet(const float *a, const float *b, const float *p, const float *q) {
    const int o1 = orient2(a, b, p), o2 = orient2(a, b, q), o3 = orient2(p, q, a),
              o4 = orient2(p, q, b);
    if (o1 * o2 < 0 && o3 * o4 < 0) return 1; /* a proper crossing */
    return (!o1 && within(a, b, p)) || (!o2 && within(a, b, q)) || (!o3 && within(p, q, a)) ||
           (!o4 && within(p, q, b));
}

/* Whether the closed footprint c[0 .. n) (x, z pairs) is not simple: two edges that are not
 * neighbours share a point, or two neighbours fold back over each other. Sets the edges. */
static int footprint_crossing(const float *c, uint32_t n, uint32_t *e0, uint32_t *e1) {
    for (uint32_t i = 0; i < n; ++i) {
        const float *a = c + 2u * i, *b = c + 2u * ((i + 1u) % n);
        const float *nx = c + 2u * ((i + 2u) % n); /* the next edge is [b, nx] */
        if (n > 2 && orient2(a, b, nx) == 0 &&
            ((double)nx[0] - b[0]) * ((double)b[0] - a[0]) +
                    ((double)nx[1] - b[1]) * ((double)b[1] - a[1]) <
                0.0) {
            *e0 = i, *e1 = (i + 1u) % n;
            return 1;
        }
        for (uint32_t j = i + 2u; j < n; ++j) {
            if (i == 0 && j == n - 1u) continue; /* neighbours across corner 0 */
            const float *p = c + 2u * j, *q = c + 2u * ((j + 1u) % n);
            if (segments_meet(a, b, p, q)) {
                *e0 = i, *e1 = j;
                return 1;
            }
        }
    }
    return 0;
}

pgt_result pgt_facade_scene_check(const pgt_facade_scene *s, const char *what, pgt_error *err) {
    if (!what) what = "scene";
    if (!s || (s->building_count && !s->buildings) || (s->corner_count && !s->corners) ||
        (s->param_count && !s->params) || (s->grammar_count && !s->grammars))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: missing arrays", what);
    for (uint32_t k = 0; k < s->grammar_count; ++k) {
        const pgt_grammar *g = &s->grammars[k];
        if (g->rule_count == 0 || g->rules[0].param_count != 0)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: grammar %s has no axiom without parameters", what, gname(g));
        if (pgt_grammar_find_param(g, "protrusion") == PGT_NONE ||
            pgt_grammar_find_param(g, "recess") == PGT_NONE)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: grammar %s lacks the param protrusion or recess (the facade "
                                 "volume's F and B, paper 003 sec. 5.2)",
                                 what, gname(g));
        const pgt_result r = check_call_cycles(g, what, err);
        if (r != PGT_OK) return r;
    }
    if ((s->gimage_count && !s->gimages) ||
        (s->gimage_triangle_count && (!s->gimage_data || !s->gimage_roles)))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "%s: missing geometry images", what);
    for (uint32_t k = 0; k < s->gimage_count; ++k) {
        const pgt_facade_gimage *gi = &s->gimages[k];
        if (gi->first > s->gimage_triangle_count ||
            gi->count > s->gimage_triangle_count - gi->first ||
            gi->count > PGT_FACADE_MAX_GIMAGE_TRIANGLES)
            return pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                 "%s: geometry image %u has triangles [%u, %u + %u) of %u (at most "
                                 "%u)",
                                 what, k, gi->first, gi->first, gi->count, s->gimage_triangle_count,
                                 PGT_FACADE_MAX_GIMAGE_TRIANGLES);
    }
    for (uint32_t i = 0; i < s->gimage_triangle_count; ++i)
        if (s->gimage_roles[i] >= PGT_FACADE_ROLE_COUNT)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: geometry image triangle %u has role %u (0 to %u)", what, i,
                                 s->gimage_roles[i], PGT_FACADE_ROLE_COUNT - 1u);
    for (uint32_t i = 0; i < s->gimage_triangle_count * 9u; ++i) {
        const float x = s->gimage_data[i];
        if (!isfinite(x) || (i % 3u < 2u && (x < 0.0f || x > 1.0f)))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: geometry image triangle %u: coordinate %g (x and y in [0, 1] "
                                 "across the scope, z finite)",
                                 what, i / 9u, (double)x);
    }
    for (uint32_t k = 0; k < s->gimage_count; ++k) { /* the z range recorded, of finite data */
        const pgt_facade_gimage *gi = &s->gimages[k];
        if (gi->count == 0) continue;
        float lo, hi;
        facade_gimage_z_range(s->gimage_data + 9u * (size_t)gi->first, gi->count, &lo, &hi);
        if (lo != gi->zlo || hi != gi->zhi)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: geometry image %u: z range [%g, %g] recorded, its triangles "
                                 "span [%g, %g]",
                                 what, k, (double)gi->zlo, (double)gi->zhi, (double)lo, (double)hi);
    }
    for (uint32_t i = 0; i < s->corner_count * 2u; ++i)
        if (!isfinite(s->corners[i]))
            return pgt_error_set(err, PGT_ERROR_NOT_FINITE, "%s: corner %u is not finite", what,
                                 i / 2);
    for (uint32_t b = 0; b < s->building_count; ++b) {
        const pgt_facade_building *B = &s->buildings[b];
        if (B->grammar >= s->grammar_count)
            return pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                 "%s: building %u names grammar %u of %u", what, b, B->grammar,
                                 s->grammar_count);
        const pgt_grammar *g = &s->grammars[B->grammar];
        if ((B->corner_count != 0 && B->corner_count < 3) || B->first_corner > s->corner_count ||
            B->corner_count > s->corner_count - B->first_corner)
            return pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                 "%s: building %u has corners [%u, %u + %u) of %u (at least 3, or "
                                 "none for a mesh building)",
                                 what, b, B->first_corner, B->first_corner, B->corner_count,
                                 s->corner_count);
        if (B->first_param > s->param_count || g->param_count > s->param_count - B->first_param)
            return pgt_error_set(err, PGT_ERROR_INDEX_RANGE,
                                 "%s: building %u has params [%u, %u + %u) of %u", what, b,
                                 B->first_param, B->first_param, g->param_count, s->param_count);
        if (!(isfinite(B->base) && isfinite(B->height) && B->height > 0.0f &&
              fabsf(B->base) <= PGT_FACADE_MAX_COORD &&
              fabsf(B->base + B->height) <= PGT_FACADE_MAX_COORD))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: building %u has base %g and height %g (height > 0, base and "
                                 "roof within +-%g)",
                                 what, b, (double)B->base, (double)B->height,
                                 (double)PGT_FACADE_MAX_COORD);
        if (B->corner_count > FACADE_MAX_CORNERS)
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "%s: building %u has %u footprint corners (at most %u)", what, b,
                                 B->corner_count, FACADE_MAX_CORNERS);
        for (uint32_t k = 0; k < g->param_count; ++k)
            if (!isfinite(s->params[B->first_param + k]))
                return pgt_error_set(err, PGT_ERROR_NOT_FINITE,
                                     "%s: building %u: param %s is not finite", what, b,
                                     g->names + g->params[k].name);
        const float F = s->params[B->first_param + pgt_grammar_find_param(g, "protrusion")];
        const float Bk = s->params[B->first_param + pgt_grammar_find_param(g, "recess")];
        /* bounded as the coordinates are: 1.2e9 already lost hits to float rounding in t */
        if (!(F >= 0.0f && Bk >= 0.0f && F <= PGT_FACADE_MAX_COORD && Bk <= PGT_FACADE_MAX_COORD))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: building %u: protrusion %g and recess %g must be in [0, %g]",
                                 what, b, (double)F, (double)Bk, (double)PGT_FACADE_MAX_COORD);
        double area = 0.0;
        const float *c = s->corners + 2u * B->first_corner;
        for (uint32_t k = 0; k < B->corner_count; ++k)
            if (!(fabsf(c[2 * k]) <= PGT_FACADE_MAX_COORD &&
                  fabsf(c[2 * k + 1]) <= PGT_FACADE_MAX_COORD))
                return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                     "%s: building %u: footprint corner %u (%g, %g) is not within "
                                     "+-%g",
                                     what, b, k, (double)c[2 * k], (double)c[2 * k + 1],
                                     (double)PGT_FACADE_MAX_COORD);
        for (uint32_t k = 0; k < B->corner_count; ++k) {
            const uint32_t k1 = (k + 1u) % B->corner_count;
            const float dx = c[2 * k1] - c[2 * k], dz = c[2 * k1 + 1] - c[2 * k + 1];
            if (!(sqrtf(dx * dx + dz * dz) >= FACADE_MIN_EDGE))
                return pgt_error_set(err, PGT_ERROR_DEGENERATE,
                                     "%s: building %u: footprint edge %u is shorter than %g", what,
                                     b, k, (double)FACADE_MIN_EDGE);
            area += (double)c[2 * k] * c[2 * k1 + 1] - (double)c[2 * k1] * c[2 * k + 1];
        }
        /* n = t x (0,1,0) = (-t.z, 0, t.x) points out when the x-z signed area is negative:
         * counter-clockwise seen from above (+Y down onto the ground, +X right, +Z down the
         * page) */
        uint32_t e0, e1;
        if (footprint_crossing(c, B->corner_count, &e0, &e1))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: building %u: footprint edges %u and %u meet (a footprint "
                                 "must be a simple polygon: roof and facades would disagree)",
                                 what, b, e0, e1);
        if (B->corner_count != 0 && !(area < 0.0))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "%s: building %u: footprint corners run the wrong way (signed "
                                 "x-z area %g, expected < 0; facade normals would point into the "
                                 "building: list them counter-clockwise seen from above)",
                                 what, b, 0.5 * area);
    }
    return PGT_OK;
}

void pgt_facade_scene_destroy(pgt_facade_scene *s) {
    if (!s) return;
    free(s->buildings);
    free(s->corners);
    free(s->params);
    free(s->gimages);
    free(s->gimage_data);
    free(s->gimage_roles);
    memset(s, 0, sizeof *s);
}

/* What a GPU holds of a grammar: every array but code_pos (source positions for messages). */
static size_t grammar_bytes(const pgt_grammar *g) {
    return sizeof *g + g->rule_count * sizeof *g->rules + g->case_count * sizeof *g->cases +
           g->sequence_count * sizeof *g->sequences + g->item_count * sizeof *g->items +
           g->part_count * sizeof *g->parts + g->arg_count * sizeof *g->args +
           g->sub_count * sizeof *g->subs + g->expr_count * sizeof *g->exprs +
           g->code_count * sizeof *g->code + g->const_count * sizeof *g->consts +
           g->param_count * (sizeof *g->params + sizeof *g->param_values) +
           g->rule_param_count * sizeof *g->rule_params + g->names_size;
}

size_t pgt_facade_scene_bytes(const pgt_facade_scene *s) {
    size_t n = (size_t)s->building_count * sizeof *s->buildings +
               (size_t)s->corner_count * 2u * sizeof *s->corners +
               (size_t)s->param_count * sizeof *s->params +
               (size_t)s->gimage_count * sizeof *s->gimages +
               (size_t)s->gimage_triangle_count * (9u * sizeof *s->gimage_data + 1u);
    for (uint32_t k = 0; k < s->grammar_count; ++k) n += grammar_bytes(&s->grammars[k]);
    return n;
}

pgt_result pgt_facade_prepare(const pgt_facade_scene *s, pgt_facade **out, uint32_t *count,
                              pgt_error *err) {
    *out = NULL, *count = 0;
    uint64_t n = 0;
    for (uint32_t b = 0; b < s->building_count; ++b) n += s->buildings[b].corner_count;
    if (n > PGT_FACADE_MAX_FACADES)
        return pgt_error_set(err, PGT_ERROR_LIMIT, "%llu facades, more than %u",
                             (unsigned long long)n, PGT_FACADE_MAX_FACADES);
    pgt_facade *f = malloc((size_t)(n ? n : 1) * sizeof *f);
    if (!f) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "facades: out of memory");
    uint32_t i = 0;
    for (uint32_t b = 0; b < s->building_count; ++b) {
        const pgt_facade_building *B = &s->buildings[b];
        const pgt_grammar *g = &s->grammars[B->grammar];
        const float *par = s->params + B->first_param;
        const float *c = s->corners + 2u * B->first_corner;
        for (uint32_t k = 0; k < B->corner_count; ++k, ++i) {
            const uint32_t k1 = (k + 1u) % B->corner_count;
            const float dx = c[2 * k1] - c[2 * k], dz = c[2 * k1 + 1] - c[2 * k + 1];
            const float len = sqrtf(dx * dx + dz * dz);
            pgt_facade *F = &f[i];
            F->origin[0] = c[2 * k], F->origin[1] = B->base, F->origin[2] = c[2 * k + 1];
            F->t[0] = dx / len, F->t[1] = 0.0f, F->t[2] = dz / len;
            /* n = t x b with b = +Y: (t.y * 0 - t.z * 1, t.z * 0 - t.x * 0, t.x * 1 - t.y * 0) */
            F->n[0] = -F->t[2], F->n[1] = 0.0f, F->n[2] = F->t[0];
            F->width = len, F->height = B->height;
            F->protrusion = par[pgt_grammar_find_param(g, "protrusion")];
            F->recess = par[pgt_grammar_find_param(g, "recess")];
            F->building = b, F->edge = k;
            F->b[0] = 0.0f, F->b[1] = 1.0f, F->b[2] = 0.0f;
            F->u0 = 0.0f, F->v0 = 0.0f, F->scope_w = len, F->scope_h = B->height;
            F->axiom_key = pgt_facade_child_key(B->seed, k);
        }
    }
    *out = f, *count = i;
    return PGT_OK;
}

/* ---- camera ---- */

static int normalize3(float v[3]) {
    const float l = sqrtf(dot3(v, v));
    if (!(l > 0.0f) || !isfinite(l)) return 0;
    v[0] /= l, v[1] /= l, v[2] /= l;
    return 1;
}

pgt_result pgt_facade_camera_init(pgt_facade_camera *cam, const float eye[3], const float at[3],
                                  const float up[3], float fov_deg, uint32_t width, uint32_t height,
                                  pgt_error *err) {
    memset(cam, 0, sizeof *cam);
    for (int k = 0; k < 3; ++k)
        if (!isfinite(eye[k]) || !isfinite(at[k]) || !isfinite(up[k]))
            return pgt_error_set(err, PGT_ERROR_NOT_FINITE, "camera: a coordinate is not finite");
    for (int k = 0; k < 3; ++k)
        if (!(fabsf(eye[k]) <= PGT_FACADE_MAX_EYE && fabsf(at[k]) <= PGT_FACADE_MAX_EYE))
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "camera: eye and look-at coordinates must be within +-%g (the "
                                 "scene's are within +-1e6)",
                                 (double)PGT_FACADE_MAX_EYE);
    if (!(fov_deg > 0.0f && fov_deg < 180.0f))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "camera: fov %g degrees, expected 0 < fov < 180", (double)fov_deg);
    if (width == 0 || height == 0 || width > PGT_FACADE_MAX_SIDE || height > PGT_FACADE_MAX_SIDE)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "camera: %u x %u pixels, expected 1 to %u per side", width, height,
                             PGT_FACADE_MAX_SIDE);
    float w[3] = {eye[0] - at[0], eye[1] - at[1], eye[2] - at[2]}, u[3], v[3];
    if (!normalize3(w))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "camera: eye and at coincide");
    cross3(up, w, u);
    if (!normalize3(u) || sqrtf(dot3(up, up)) * 1e-6f > sqrtf(dot3(u, u)))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "camera: up is zero or parallel to the view direction");
    cross3(w, u, v);
    memcpy(cam->eye, eye, sizeof cam->eye);
    memcpy(cam->at, at, sizeof cam->at);
    memcpy(cam->up, up, sizeof cam->up);
    for (int k = 0; k < 3; ++k)
        cam->forward[k] = -w[k], cam->right[k] = u[k], cam->upward[k] = v[k];
    cam->fov_deg = fov_deg;
    cam->width = width, cam->height = height;
    cam->tan_half = (float)tan((double)fov_deg * 0.5 * 3.14159265358979323846 / 180.0);
    return PGT_OK;
}

float facade_camera_sx(const pgt_facade_camera *cam, uint32_t x) {
    const float W = (float)cam->width, H = (float)cam->height;
    return (2.0f * ((float)x + 0.5f) / W - 1.0f) * cam->tan_half * (W / H);
}

float facade_camera_sy(const pgt_facade_camera *cam, uint32_t y) {
    const float H = (float)cam->height;
    return (1.0f - 2.0f * ((float)y + 0.5f) / H) * cam->tan_half;
}

void facade_camera_dir(const pgt_facade_camera *cam, float sx, float sy, float dir[3]) {
    for (int k = 0; k < 3; ++k) dir[k] = cam->forward[k] + sx * cam->right[k] + sy * cam->upward[k];
    normalize3(dir);
}

void pgt_facade_camera_ray(const pgt_facade_camera *cam, uint32_t x, uint32_t y, float org[3],
                           float dir[3]) {
    for (int k = 0; k < 3; ++k) org[k] = cam->eye[k];
    facade_camera_dir(cam, facade_camera_sx(cam, x), facade_camera_sy(cam, y), dir);
}

/* ---- development ---- */

uint32_t pgt_facade_child_key(uint32_t parent, uint32_t k) {
    /* MurmurHash3's 32-bit finaliser of the parent mixed with the child index */
    uint32_t h = parent ^ (k * 0x9E3779B9u + 0x7F4A7C15u);
    h ^= h >> 16;
    h *= 0x85EBCA6Bu;
    h ^= h >> 13;
    h *= 0xC2B2AE35u;
    h ^= h >> 16;
    return h;
}

uint32_t facade_axiom_key(const pgt_facade_scene *s, const pgt_facade *f) {
    (void)s;
    return f->axiom_key;
}

/* Evaluates expression e of g for node `key`: rand draws (seed, key, counter++). */
int facade_eval(const facade_ctx *c, uint32_t e, const float *args, uint32_t argc, uint32_t key,
                uint64_t *counter, float *out) {
    const pgt_grammar_expr *x = &c->g->exprs[e];
    if (x->code_count == 1) { /* a number or a param: most split sizes and arguments */
        const uint32_t ins = c->g->code[x->first_code];
        const uint32_t op = ins & PGT_GRAMMAR_OP_MASK, a = ins >> PGT_GRAMMAR_OP_BITS;
        if (op == PGT_GRAMMAR_OP_CONST) return *out = c->g->consts[a], 1;
        if (op == PGT_GRAMMAR_OP_PARAM) return *out = c->params[a], 1;
    }
    pgt_grammar_env env;
    memset(&env, 0, sizeof env);
    env.seed = c->seed, env.stream = key, env.counter = counter, env.params = c->params;
    pgt_error e2 = {0};
    if (pgt_grammar_eval(c->g, e, args, argc, &env, out, &e2) != PGT_OK) {
        c->stats->errors |= PGT_FACADE_ERR_EVAL;
        if (c->err && !c->err->code) *c->err = e2;
        return 0;
    }
    return 1;
}

uint32_t facade_select_case(const facade_ctx *c, uint32_t rule, const float *args, uint32_t argc,
                            uint32_t key) {
    const pgt_grammar_rule *r = &c->g->rules[rule];
    uint64_t counter = 0;
    for (uint32_t k = 0; k < r->case_count; ++k) {
        const pgt_grammar_case *cs = &c->g->cases[r->first_case + k];
        if (cs->condition == PGT_NONE) return cs->sequence;
        float v;
        if (!facade_eval(c, cs->condition, args, argc, key, &counter, &v)) return PGT_NONE;
        if (v != 0.0f) return cs->sequence;
    }
    return PGT_NONE; /* no case holds: nothing (CGA's NIL) */
}

int facade_call(const facade_ctx *c, const pgt_grammar_item *it, const float *args, uint32_t argc,
                uint32_t key, float *out_args, uint32_t *out_seq) {
    uint64_t counter = 0;
    for (uint32_t k = 0; k < it->arg_count; ++k)
        if (!facade_eval(c, c->g->args[it->first_arg + k], args, argc, key, &counter, &out_args[k]))
            return 0;
    *out_seq = facade_select_case(c, it->target, out_args, it->arg_count, key);
    return 1;
}

uint32_t facade_terminal(const facade_ctx *c, const pgt_grammar_item *it, const float *args,
                         uint32_t argc, uint32_t key, float x0, float y0, float w, float h,
                         pgt_facade_quad *q) {
    float v[PGT_GRAMMAR_MAX_RULE_PARAMS];
    uint64_t counter = 0;
    for (uint32_t k = 0; k < it->arg_count && k < PGT_GRAMMAR_MAX_RULE_PARAMS; ++k)
        if (!facade_eval(c, c->g->args[it->first_arg + k], args, argc, key, &counter, &v[k]))
            return 0;
    return pgt_facade_terminal_quads(pgt_facade_kind_of(it->target), v, it->arg_count, x0, y0, w, h,
                                     q);
}

int facade_split(const facade_ctx *c, const pgt_grammar_item *it, const float *args, uint32_t argc,
                 uint32_t key, float length, facade_split_state *st) {
    const pgt_grammar *g = c->g;
    pgt_split_part parts[PGT_FACADE_MAX_PARTS];
    uint32_t n = 0, group_first = 0, group_count = 0;
    uint64_t counter = 0;
    for (uint32_t k = 0; k < it->sub_count; ++k) {
        const uint32_t pi = it->first_sub + k;
        const pgt_grammar_part *p = &g->parts[pi];
        const uint32_t first = p->kind == PGT_GRAMMAR_PART_REPEAT ? p->first_part : pi;
        const uint32_t cnt = p->kind == PGT_GRAMMAR_PART_REPEAT ? p->part_count : 1u;
        if (p->kind == PGT_GRAMMAR_PART_REPEAT) group_first = n, group_count = cnt;
        for (uint32_t j = 0; j < cnt; ++j) {
            if (n == PGT_FACADE_MAX_PARTS) {
                c->stats->errors |= PGT_FACADE_ERR_PARTS;
                return 0;
            }
            const pgt_grammar_part *q = &g->parts[first + j];
            parts[n].kind = q->kind;
            if (!facade_eval(c, q->size, args, argc, key, &counter, &parts[n].size)) return 0;
            st->seq[n++] = q->sequence;
        }
    }
    pgt_split_build(&st->plan, st->slots, parts, n, group_first, group_count, length);
    return 1;
}

/* Slab of the ray a + t v with [lo, hi] on one axis (inv = 1 / v, precomputed by the caller
 * where it tests many slabs; dlo = lo - a and dhi = hi - a, by a caller whose rays share a),
 * intersected into [*t0, *t1]; a parallel ray outside empties it. */
static void slab_pre(float a, float v, float inv, float lo, float hi, float dlo, float dhi,
                     float *t0, float *t1) {
    if (v == 0.0f) {
        if (a < lo || a > hi) *t0 = INFINITY, *t1 = -INFINITY;
        return;
    }
    float ta = dlo * inv, tb = dhi * inv;
    if (ta > tb) {
        const float s = ta;
        ta = tb, tb = s;
    }
    if (ta > *t0) *t0 = ta;
    if (tb < *t1) *t1 = tb;
}

static void slab(float a, float v, float lo, float hi, float *t0, float *t1) {
    slab_pre(a, v, 1.0f / v, lo, hi, lo - a, hi - a, t0, t1);
}

/* A footprint facade's window is the whole facade and its b is +Y: then the mapping below is
 * the one footprint facades always had (y straight from the world's, no offsets), bit for bit. */
/* facade_to_local knowing whole = facade_is_whole(f), which costs ten comparisons. */
/* The point org in facade space (a) and the direction dir (v). */
static void local_point(const pgt_facade *f, int whole, const float org[3], float a[3]) {
    const float d[3] = {org[0] - f->origin[0], org[1] - f->origin[1], org[2] - f->origin[2]};
    if (whole) {
        a[0] = dot3(d, f->t), a[1] = d[1], a[2] = dot3(d, f->n);
        return;
    }
    a[0] = f->u0 + dot3(d, f->t), a[1] = f->v0 + dot3(d, f->b), a[2] = dot3(d, f->n);
}

static void local_dir(const pgt_facade *f, int whole, const float dir[3], float v[3]) {
    if (whole) {
        v[0] = dot3(dir, f->t), v[1] = dir[1], v[2] = dot3(dir, f->n);
        return;
    }
    v[0] = dot3(dir, f->t), v[1] = dot3(dir, f->b), v[2] = dot3(dir, f->n);
}

static void to_local(const pgt_facade *f, int whole, const float org[3], const float dir[3],
                     float a[3], float v[3]) {
    local_point(f, whole, org, a);
    local_dir(f, whole, dir, v);
}

void facade_to_local(const pgt_facade *f, const float org[3], const float dir[3], float a[3],
                     float v[3]) {
    to_local(f, facade_is_whole(f), org, dir, a, v);
}

void facade_vector_to_world(const pgt_facade *f, const float v[3], float out[3]) {
    for (int k = 0; k < 3; ++k) out[k] = v[0] * f->t[k] + v[1] * f->b[k] + v[2] * f->n[k];
}

void facade_to_world(const pgt_facade *f, const float p[3], float out[3]) {
    if (facade_is_whole(f)) {
        for (int k = 0; k < 3; ++k) out[k] = f->origin[k] + p[0] * f->t[k] + p[2] * f->n[k];
        out[1] = f->origin[1] + p[1];
        return;
    }
    const float x = p[0] - f->u0, y = p[1] - f->v0;
    for (int k = 0; k < 3; ++k) out[k] = f->origin[k] + x * f->t[k] + y * f->b[k] + p[2] * f->n[k];
}

/* Nearest rectangle of q[0 .. n) hit at t in (0, *best): returns its index or PGT_NONE. win
 * (NULL: the whole facade) is the facade's window in facade space (x0, y0, x1, y1) and off the
 * block's corner (q and a are block-local): a hit outside the window is a part of the terminal
 * that another quad of the mesh shows. A rectangle's plane is placed in facade space as
 * facade_terminal places it for the explicit twin (c + off), so both keep or drop a rectangle
 * lying on the window's border alike (the explicit twin clips rectangles to the window). */
static FACADE_ALWAYS_INLINE uint32_t hit_quads(const pgt_facade_quad *q, uint32_t n,
                                               const float *num, const float a[3], const float v[3],
                                               const float inv[3], const float *win,
                                               const float off[2], float *best, uint64_t *tests) {
    static const uint32_t other[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    uint32_t found = PGT_NONE;
    *tests += n;
    for (uint32_t k = 0; k < n; ++k) {
        /* inv is infinite where v is 0: t is then infinite or NaN and fails the test */
        const uint32_t ax = q[k].axis;
        const float t = num[k] * inv[ax]; /* num[k] = q[k].c - a[ax] */
        if (!(t > 0.0f && t < *best)) continue;
        const uint32_t o0 = other[ax][0], o1 = other[ax][1];
        const float u0 = a[o0] + t * v[o0], u1 = a[o1] + t * v[o1];
        if (u0 < q[k].lo[0] || u0 > q[k].hi[0] || u1 < q[k].lo[1] || u1 > q[k].hi[1]) continue;
        if (win) {
            const float x = (ax == 0 ? q[k].c : u0) + off[0];
            const float y = (ax == 0 ? u0 : (ax == 1 ? q[k].c : u1)) + off[1];
            if (x < win[0] || x > win[2] || y < win[1] || y > win[3]) continue;
        }
        *best = t, found = k;
    }
    return found;
}

/* The part of a terminal's ray tests that does not depend on the direction, for rays from the
 * block-local origin a (every ray of a packet starts at the eye): each rectangle's plane minus
 * a (c - a[axis]) and each group box's faces minus a. */
typedef struct quad_prep {
    float a[3];
    float num[PGT_FACADE_MAX_QUADS];
    float dlo[FACADE_QUAD_GROUPS][3], dhi[FACADE_QUAD_GROUPS][3];
} quad_prep;

/* Prepares rectangles q[0 .. n) and their group boxes (groups, or NULL) for rays from a. */
static void prepare_quads(const pgt_facade_quad *q, uint32_t n, const float *groups,
                          const float a[3], quad_prep *p) {
    p->a[0] = a[0], p->a[1] = a[1], p->a[2] = a[2];
    for (uint32_t k = 0; k < n; ++k) p->num[k] = q[k].c - a[q[k].axis];
    for (uint32_t g = 0; groups && g * FACADE_QUAD_GROUP < n; ++g)
        for (int k = 0; k < 3; ++k)
            p->dlo[g][k] = groups[6u * g + k] - a[k], p->dhi[g][k] = groups[6u * g + 3 + k] - a[k];
}

/* hit_quads for the ray p->a + t v, over groups of FACADE_QUAD_GROUP rectangles when the
 * terminal has their boxes (groups[6 k .. 6 k + 6): lo xyz, hi xyz, grown by FACADE_GROUP_GROW;
 * NULL: none), skipping a group whose box the ray misses before *best: the same answer, fewer
 * tests. */
static FACADE_ALWAYS_INLINE uint32_t hit_terminal(const pgt_facade_quad *q, uint32_t n,
                                                  const float *groups, const quad_prep *p,
                                                  const float v[3], const float inv[3],
                                                  const float *win, const float off[2], float *best,
                                                  uint64_t *tests) {
    if (!groups) return hit_quads(q, n, p->num, p->a, v, inv, win, off, best, tests);
    uint32_t found = PGT_NONE;
    for (uint32_t g0 = 0, g = 0; g0 < n; g0 += FACADE_QUAD_GROUP, ++g) {
        const float *bx = groups + 6u * g;
        float t0 = 0.0f, t1 = *best;
        for (int k = 0; k < 3; ++k)
            slab_pre(p->a[k], v[k], inv[k], bx[k], bx[3 + k], p->dlo[g][k], p->dhi[g][k], &t0, &t1);
        if (!(t0 <= t1)) continue;
        const uint32_t m = n - g0 < FACADE_QUAD_GROUP ? n - g0 : FACADE_QUAD_GROUP;
        const uint32_t k = hit_quads(q + g0, m, p->num + g0, p->a, v, inv, win, off, best, tests);
        if (k != PGT_NONE) found = g0 + k;
    }
    return found;
}

/* The boxes of consecutive groups of FACADE_QUAD_GROUP rectangles (facade_terminals.c emits a
 * terminal's parts one after the other, so a group is compact), grown by FACADE_GROUP_GROW. */
static void group_boxes(const pgt_facade_quad *q, uint32_t n, float *groups) {
    static const uint32_t other[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    for (uint32_t g0 = 0; g0 < n; g0 += FACADE_QUAD_GROUP) {
        float *bx = groups + 6u * (g0 / FACADE_QUAD_GROUP);
        for (int k = 0; k < 3; ++k) bx[k] = INFINITY, bx[3 + k] = -INFINITY;
        for (uint32_t i = g0; i < n && i < g0 + FACADE_QUAD_GROUP; ++i) {
            const uint32_t ax = q[i].axis, o0 = other[ax][0], o1 = other[ax][1];
            bx[ax] = facade_min(bx[ax], q[i].c), bx[3 + ax] = facade_max(bx[3 + ax], q[i].c);
            bx[o0] = facade_min(bx[o0], q[i].lo[0]),
            bx[3 + o0] = facade_max(bx[3 + o0], q[i].hi[0]);
            bx[o1] = facade_min(bx[o1], q[i].lo[1]),
            bx[3 + o1] = facade_max(bx[3 + o1], q[i].hi[1]);
        }
        for (int k = 0; k < 3; ++k) {
            const float grow = FACADE_GROUP_GROW * (1.0f + fabsf(bx[k]) + fabsf(bx[3 + k]));
            bx[k] -= grow, bx[3 + k] += grow;
        }
    }
}

/* Drops the zero-area rectangles of q[0 .. n), keeping each one's surface id in surf. */
static uint32_t compact_quads(pgt_facade_quad *q, uint32_t n, uint8_t *surf) {
    uint32_t m = 0;
    for (uint32_t k = 0; k < n; ++k)
        if (q[k].hi[0] > q[k].lo[0]) q[m] = q[k], surf[m++] = (uint8_t)k;
    return m;
}

/* The development stack. */
typedef enum { FR_SEQ = 0, FR_SPLIT = 1 } frame_type;

typedef struct frame {
    uint32_t type, key;
    float x0, y0, w, h; /* scope on the facade */
    float t_in, t_out;  /* the ray's interval inside the scope */
    uint32_t argc;
    float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
    /* FR_SEQ */
    uint32_t seq, pos;
    /* FR_SPLIT */
    uint32_t axis, next;
    int dir;
    float t_cur;
    const facade_split_state *sp; /* the layout: &split, or a memo entry this frame pins */
    const facade_split_flat *fl;  /* its children as flat arrays, or NULL */
    facade_cache_split *pinned;   /* that memo entry, or NULL */
    facade_split_state split;
} frame;

/* Child k of layout sp (k < child_count): from its flat arrays fl when it has them (not NULL). */
static void split_child(const facade_split_state *sp, const facade_split_flat *fl, uint32_t k,
                        pgt_split_child *ch) {
    if (fl) {
        ch->start = fl->start[k], ch->end = fl->end[k], ch->part = fl->part[k];
        ch->repetition = 0; /* not kept flat: unused here */
        return;
    }
    pgt_split_child_get(&sp->plan, sp->slots, k, ch);
}

/* Fills a memo entry's flat children (its first reuse). */
static void flatten(facade_cache_split *cs) {
    const uint32_t n = cs->st.plan.child_count;
    if (n > FACADE_FLAT_CHILDREN) {
        cs->flat.state = FACADE_FLAT_TOO_MANY;
        return;
    }
    for (uint32_t k = 0; k < n; ++k) {
        pgt_split_child ch;
        pgt_split_child_get(&cs->st.plan, cs->st.slots, k, &ch);
        cs->flat.start[k] = ch.start, cs->flat.end[k] = ch.end, cs->flat.part[k] = (uint8_t)ch.part;
    }
    cs->flat.state = FACADE_FLAT_READY;
}

/* The child of a split after a gap at local coordinate p in direction dir: the first child
 * ending after p (dir > 0) or the last starting before p (dir < 0); PGT_NONE if none. */
static uint32_t child_after_gap(const facade_split_state *sp, const facade_split_flat *fl, float p,
                                int dir) {
    const uint32_t n = sp->plan.child_count;
    uint32_t lo = 0, hi = n; /* dir > 0: first k with end > p; dir < 0: last k with start < p */
    pgt_split_child ch;
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2u;
        split_child(sp, fl, mid, &ch);
        if (dir > 0 ? ch.end > p : !(ch.start < p))
            hi = mid;
        else
            lo = mid + 1u;
    }
    if (dir > 0) return lo < n ? lo : PGT_NONE;
    return lo > 0 ? lo - 1u : PGT_NONE;
}

/* Algorithm 1's step into child ch of a split on axis ax (scope corner o on that axis) going
 * dir along it, for the ray a + t v whose progress through the split is t_cur and which leaves
 * the split's scope at t_out: the ray's interval [*t_near, *t_far] inside the child. */
static FACADE_ALWAYS_INLINE void child_span(const pgt_split_child *ch, float o, float a, float v,
                                            int dir, float t_cur, float t_out, float *t_near,
                                            float *t_far) {
    *t_near = t_cur, *t_far = t_out;
    if (v != 0.0f) {
        const float ts = (o + ch->start - a) / v, te = (o + ch->end - a) / v;
        const float tn = dir > 0 ? ts : te, tf = dir > 0 ? te : ts;
        if (tn > *t_near) *t_near = tn;
        if (tf < *t_far) *t_far = tf;
    }
}

/* getSplitIndex(p): the child of layout sp (flat arrays fl, or NULL) the ray a + t v enters by
 * at t_in, going dir along the split's axis (a, v: their components on it; o and L: the scope's
 * corner and length there; [wlo, whi]: the facade's window on it, +-inf for a whole facade);
 * after a gap, the next child that way; PGT_NONE if none. The entry point is clamped to the
 * window first: t_in is where the ray enters the window's box, and a rounding of a + t_in v to
 * just past the window's side picked the child beyond it, which the explicit twin (one quad's
 * window, half-open) does not hold (a review's tower: 7 rays hit a face that belongs to the next
 * quad). */
static FACADE_ALWAYS_INLINE uint32_t entry_child(const facade_split_state *sp,
                                                 const facade_split_flat *fl, float a, float v,
                                                 float t_in, float o, float L, float wlo, float whi,
                                                 int dir) {
    float q = a + t_in * v;
    q = q < wlo ? wlo : (q > whi ? whi : q);
    float p = q - o;
    p = p < 0.0f ? 0.0f : (p > L ? L : p);
    pgt_split_child ch;
    const uint32_t k = fl ? pgt_split_flat_at(fl->start, fl->end, sp->plan.child_count, p, dir)
                          : pgt_split_child_at(&sp->plan, sp->slots, p, dir, &ch);
    return k != PGT_NONE ? k : child_after_gap(sp, fl, p, dir);
}

void facade_cache_clear(facade_cache *c) {
    for (uint32_t k = 0; k < FACADE_CACHE_SPLITS; ++k) c->split[k].valid = 0, c->split[k].pins = 0;
    for (uint32_t k = 0; k < FACADE_CACHE_TERMINALS; ++k) c->term[k].n = PGT_NONE;
}

/* Does any argument (terminal) or part size (split) of item `it` draw rand? */
static int item_draws(const pgt_grammar *g, const pgt_grammar_item *it) {
    if (it->kind == PGT_GRAMMAR_ITEM_TERMINAL) {
        for (uint32_t k = 0; k < it->arg_count; ++k)
            if (g->exprs[g->args[it->first_arg + k]].flags & PGT_GRAMMAR_EXPR_RAND) return 1;
        return 0;
    }
    if (it->kind != PGT_GRAMMAR_ITEM_SPLIT) return 0;
    for (uint32_t k = 0; k < it->sub_count; ++k) {
        const pgt_grammar_part *p = &g->parts[it->first_sub + k];
        const uint32_t first =
            p->kind == PGT_GRAMMAR_PART_REPEAT ? p->first_part : it->first_sub + k;
        const uint32_t cnt = p->kind == PGT_GRAMMAR_PART_REPEAT ? p->part_count : 1u;
        for (uint32_t j = 0; j < cnt; ++j)
            if (g->exprs[g->parts[first + j].size].flags & PGT_GRAMMAR_EXPR_RAND) return 1;
    }
    return 0;
}

uint32_t *facade_collapse_table(const pgt_grammar *g) {
    uint32_t *t = malloc((g->sequence_count ? g->sequence_count : 1u) * sizeof *t);
    for (uint32_t q = 0; t && q < g->sequence_count; ++q) {
        t[q] = PGT_NONE;
        const pgt_grammar_sequence *sq = &g->sequences[q];
        if (sq->item_count != 1) continue;
        const pgt_grammar_item *it = &g->items[sq->first_item];
        if (it->kind != PGT_GRAMMAR_ITEM_CALL || it->arg_count != 0) continue;
        const pgt_grammar_rule *r = &g->rules[it->target];
        if (r->case_count != 1 || g->cases[r->first_case].condition != PGT_NONE) continue;
        t[q] = g->cases[r->first_case].sequence;
    }
    return t;
}

uint8_t *facade_draws_table(const pgt_grammar *g) {
    uint8_t *t = malloc(g->item_count ? g->item_count : 1u);
    for (uint32_t i = 0; t && i < g->item_count; ++i) t[i] = (uint8_t)item_draws(g, &g->items[i]);
    return t;
}

/* The memo key of an item on a scope of w x h with the frame's arguments (node: the node key
 * when the item draws rand, else 0); returns its hash. */
static uint32_t cache_key(facade_cache_key *k, uint32_t building, uint32_t item, uint32_t node,
                          float w, float h, const float *args, uint32_t argc) {
    k->building = building, k->item = item, k->key = node, k->argc = argc, k->w = w, k->h = h;
    for (uint32_t i = 0; i < argc; ++i) k->args[i] = args[i];
    uint32_t wb, hb;
    memcpy(&wb, &w, sizeof wb);
    memcpy(&hb, &h, sizeof hb);
    return pgt_facade_child_key(pgt_facade_child_key(building ^ item * 0x9E3779B9u, node ^ wb), hb);
}

/* The memo key of item `item` developed by frame scope (w, h, args) of facade f: the node key
 * counts only when the item draws rand. Returns the slot hash. */
static uint32_t memo_key(facade_cache_key *k, const facade_cache *cache, const pgt_facade *f,
                         uint32_t grammar, uint32_t item, uint32_t node, float w, float h,
                         const float *args, uint32_t argc) {
    return cache_key(k, f->building, item, cache->draws[grammar][item] ? node : 0u, w, h, args,
                     argc);
}

/* Floats compare bit for bit: -0 and +0 are two keys (1 / a or atan2 can tell them apart, so a
 * layout may differ), and a NaN argument matches itself. */
static int key_equal(const facade_cache_key *a, const facade_cache_key *b) {
    if (a->building != b->building || a->item != b->item || a->key != b->key || a->argc != b->argc)
        return 0;
    return memcmp(&a->w, &b->w, sizeof a->w) == 0 && memcmp(&a->h, &b->h, sizeof a->h) == 0 &&
           memcmp(a->args, b->args, a->argc * sizeof a->args[0]) == 0;
}

/* The rectangles of terminal item `it` (index `item`, node `key`) on a w x h scope with the
 * frame's arguments, in block coordinates: from the memo when it holds them, else evaluated
 * (into the memo's slot when there is a memo, else into q_own and surf_own). *groups is the
 * memo's group boxes (NULL without a memo). An evaluation error is or-ed into c->stats and
 * leaves no rectangle. Returns the count; *q and *surf point at the rectangles and their ids. */
static uint32_t terminal_quads(const facade_ctx *c, facade_cache *cache, const pgt_facade *f,
                               uint32_t grammar, const pgt_grammar_item *it, uint32_t item,
                               uint32_t key, float w, float h, const float *args, uint32_t argc,
                               pgt_facade_quad *q_own, uint8_t *surf_own, const pgt_facade_quad **q,
                               const uint8_t **surf, const float **groups) {
    facade_cache_key ck;
    facade_cache_terminal *ce = NULL;
    if (cache)
        ce = &cache->term[memo_key(&ck, cache, f, grammar, item, key, w, h, args, argc) %
                          FACADE_CACHE_TERMINALS];
    if (ce && ce->n != PGT_NONE && key_equal(&ce->k, &ck)) {
        *q = ce->q, *surf = ce->surf, *groups = ce->groups;
        return ce->n;
    }
    pgt_facade_quad *dst = ce ? ce->q : q_own;
    uint8_t *sd = ce ? ce->surf : surf_own;
    uint32_t n = facade_terminal(c, it, args, argc, key, 0.0f, 0.0f, w, h, dst);
    for (uint32_t k = 0; k < n; ++k) { /* the explicit twin's test */
        float zlo, zhi;
        if (facade_quad_outside_volume(f, &dst[k], &zlo, &zhi))
            c->stats->errors |= PGT_FACADE_ERR_VOLUME;
    }
    n = compact_quads(dst, n, sd);
    *q = dst, *surf = sd, *groups = NULL;
    if (ce) {
        ce->n = c->stats->errors ? PGT_NONE : n, ce->k = ck;
        group_boxes(dst, n, ce->groups);
        *groups = ce->groups;
    }
    return n;
}

/* The geometry image of Mesh terminal item `it` (its id evaluated for node `key` with the
 * frame's arguments): returns its triangle count, *d its triangles and *first the scene index of
 * its first; 0 on an error, or-ed into c->stats (the evaluation's, or an id naming no image). */
static uint32_t terminal_gimage(const facade_ctx *c, const pgt_facade_scene *s, const pgt_facade *f,
                                const pgt_grammar_item *it, const float *args, uint32_t argc,
                                uint32_t key, const float **d, uint32_t *first) {
    float id;
    uint64_t counter = 0;
    *d = NULL, *first = 0;
    if (!facade_eval(c, c->g->args[it->first_arg], args, argc, key, &counter, &id)) return 0;
    const uint32_t n = facade_gimage_triangles(s, id, d, first);
    if (n == 0) {
        c->stats->errors |= PGT_FACADE_ERR_GIMAGE;
        return 0;
    }
    /* the explicit twin's test (emit_gimage), on the image's z range: it must stay in the
     * facade volume, which the coverage polygon and the slab of the ray test bound (sec. 8) */
    const pgt_facade_gimage *g = &s->gimages[(uint32_t)id];
    if (g->zlo < -f->recess || g->zhi > f->protrusion) {
        c->stats->errors |= PGT_FACADE_ERR_VOLUME;
        return 0;
    }
    return n;
}

/* The layout of split item `it` (index `item`, node `key`) across `length` of a w x h scope with
 * the frame's arguments, for one frame: a memo entry (pinned while the frame uses it, so that no
 * descendant evicts it; flattened at its first reuse), or computed into the memo's slot when no
 * frame pins it, or into `own`. Returns 0 on an evaluation error (or-ed into c->stats). */
static int split_layout(const facade_ctx *c, facade_cache *cache, const pgt_facade *f,
                        uint32_t grammar, const pgt_grammar_item *it, uint32_t item, uint32_t key,
                        float w, float h, float length, const float *args, uint32_t argc,
                        facade_split_state *own, const facade_split_state **sp,
                        const facade_split_flat **fl, facade_cache_split **pinned) {
    facade_cache_key ck;
    facade_cache_split *cs = NULL;
    if (cache)
        cs = &cache->split[memo_key(&ck, cache, f, grammar, item, key, w, h, args, argc) %
                           FACADE_CACHE_SPLITS];
    if (cs && cs->valid && key_equal(&cs->k, &ck)) {
        if (cs->flat.state == FACADE_FLAT_UNKNOWN) flatten(cs);
        *sp = &cs->st, *pinned = cs, cs->pins++;
        *fl = cs->flat.state == FACADE_FLAT_READY ? &cs->flat : NULL;
        return 1;
    }
    if (cs && cs->pins == 0) {
        cs->valid = 0;
        if (!facade_split(c, it, args, argc, key, length, &cs->st)) return 0;
        cs->valid = 1, cs->k = ck, cs->flat.state = FACADE_FLAT_UNKNOWN;
        *sp = &cs->st, *pinned = cs, cs->pins++, *fl = NULL;
        return 1;
    }
    if (!facade_split(c, it, args, argc, key, length, own)) return 0;
    *sp = own, *pinned = NULL, *fl = NULL;
    return 1;
}

/* The nearest hit of a development into *hit: distance t along the facade-space ray a + t v,
 * terminal node key, kind, surface, item, and the normal of the hit rectangle's axis (0 t, 1 b,
 * 2 n of the facade) or, axis 3, the geometry image triangle's facade-space normal n. */
static void write_hit(pgt_facade_hit *hit, const pgt_facade *f, uint32_t fi, float t, uint32_t key,
                      uint32_t kind, uint32_t surface, uint32_t item, uint32_t axis,
                      const float n[3], const float a[3], const float v[3], float zscale) {
    hit->t = t, hit->facade = fi, hit->node = key, hit->kind = kind;
    hit->surface = surface, hit->item = item;
    if (axis == 3) { /* a geometry image's triangle */
        facade_vector_to_world(f, n, hit->n);
    } else {
        const float *nrm = axis == 0 ? f->t : (axis == 1 ? f->b : f->n);
        hit->n[0] = nrm[0], hit->n[1] = nrm[1], hit->n[2] = nrm[2];
    }
    for (int k = 0; k < 3; ++k) hit->p[k] = a[k] + t * v[k];
    hit->p[2] *= zscale; /* the scaled geometry's z */
}

int pgt_facade_intersect(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                         const float org[3], const float dir[3], pgt_facade_hit *hit,
                         pgt_facade_ray_stats *stats) {
    return facade_intersect(s, f, fi, org, dir, hit, stats, NULL, 1.0f);
}

int facade_intersect(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                     const float org[3], const float dir[3], pgt_facade_hit *hit,
                     pgt_facade_ray_stats *stats, facade_cache *cache, float zscale) {
    pgt_facade_ray_stats dummy;
    if (!stats) memset(&dummy, 0, sizeof dummy), stats = &dummy;
    stats->rays++;
    float a[3], v[3];
    const int whole = facade_is_whole(f);
    to_local(f, whole, org, dir, a, v);
    if (zscale != 1.0f) a[2] /= zscale, v[2] /= zscale;
    float t0 = 0.0f, t1 = hit->t;
    /* the facade's window in facade space (x0, y0, x1, y1): a mesh quad's cuts its terminals */
    const float win[4] = {f->u0, f->v0, f->u0 + f->width, f->v0 + f->height};
    const float *wp = whole ? NULL : win;
    float wlo[2], whi[2]; /* entry_child's clamp */
    facade_entry_window(f, wlo, whi);
    slab(a[0], v[0], win[0], win[2], &t0, &t1);
    slab(a[1], v[1], win[1], win[3], &t0, &t1);
    slab(a[2], v[2], -f->recess, f->protrusion, &t0, &t1);
    if (!(t0 <= t1)) return 0; /* misses the volume: nothing developed */
    const float inv[3] = {1.0f / v[0], 1.0f / v[1], 1.0f / v[2]}; /* inf where v is 0: unused */
    stats->volume_hits++;
    const pgt_facade_building *B = &s->buildings[f->building];
    facade_ctx c = {&s->grammars[B->grammar], s->params + B->first_param, B->seed, stats, NULL};
    const pgt_grammar *g = c.g;
    frame stack[PGT_FACADE_MAX_DEPTH];
    uint32_t sp = 0, budget = PGT_FACADE_NODE_BUDGET;
    float best = hit->t;
    uint32_t best_kind = 0, best_surface = 0, best_key = 0, best_item = 0, best_axis = 0;
    float best_n[3] = {0.0f, 0.0f, 0.0f}; /* a geometry image's triangle normal (best_axis 3) */
    pgt_facade_quad quads[PGT_FACADE_MAX_QUADS];

    const uint32_t key0 = facade_axiom_key(s, f);
    const uint32_t seq0 = facade_select_case(&c, 0, NULL, 0, key0);
    if (seq0 == PGT_NONE) return 0;
    frame *fr = &stack[sp++];
    fr->type = FR_SEQ, fr->key = key0, fr->x0 = 0.0f, fr->y0 = 0.0f, fr->w = f->scope_w;
    fr->h = f->scope_h, fr->t_in = t0, fr->t_out = t1, fr->argc = 0, fr->seq = seq0, fr->pos = 0;
    stats->nodes++;

    while (sp > 0) {
        fr = &stack[sp - 1];
        if (fr->type == FR_SPLIT) {
            /* Algorithm 1's loop: the next child along the ray while inside the split's scope */
            if (best <= fr->t_cur || fr->t_cur >= fr->t_out || fr->next == PGT_NONE ||
                fr->next >= fr->sp->plan.child_count) {
                if (fr->pinned) fr->pinned->pins--;
                --sp;
                continue;
            }
            pgt_split_child ch;
            split_child(fr->sp, fr->fl, fr->next, &ch);
            const uint32_t ax = fr->axis;
            const float o = ax == 0 ? fr->x0 : fr->y0;
            float t_near, t_far;
            child_span(&ch, o, a[ax], v[ax], fr->dir, fr->t_cur, fr->t_out, &t_near, &t_far);
            fr->t_cur = t_far > fr->t_cur ? t_far : fr->t_cur;
            const uint32_t cur = fr->next;
            fr->next = fr->dir > 0 ? cur + 1u : (cur == 0 ? PGT_NONE : cur - 1u);
            const uint32_t seq = fr->sp->seq[ch.part];
            if (seq == PGT_NONE || !(t_near <= t_far) || t_near >= best) continue;
            if (sp == PGT_FACADE_MAX_DEPTH) {
                stats->errors |= PGT_FACADE_ERR_DEPTH;
                break;
            }
            if (--budget == 0) {
                stats->errors |= PGT_FACADE_ERR_BUDGET;
                break;
            }
            frame *nf = &stack[sp++];
            stats->nodes++;
            uint32_t nseq = seq, nkey = pgt_facade_child_key(fr->key, cur), nargc = fr->argc;
            if (cache) { /* part --> Rule, Rule --> body: straight to the body (same keys) */
                const uint32_t *col = cache->collapse[B->grammar];
                for (uint32_t hop = 0; hop < FACADE_COLLAPSE_MAX && col[nseq] != PGT_NONE; ++hop) {
                    nkey = pgt_facade_child_key(nkey, 0), nseq = col[nseq], nargc = 0;
                    stats->nodes++;
                    if (--budget == 0) break;
                }
                if (budget == 0) {
                    stats->errors |= PGT_FACADE_ERR_BUDGET;
                    break;
                }
            }
            nf->type = FR_SEQ, nf->key = nkey;
            nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w, nf->h = fr->h;
            if (ax == 0)
                nf->x0 = fr->x0 + ch.start, nf->w = ch.end - ch.start;
            else
                nf->y0 = fr->y0 + ch.start, nf->h = ch.end - ch.start;
            nf->t_in = t_near, nf->t_out = t_far;
            nf->argc = nargc;
            memcpy(nf->args, fr->args, nargc * sizeof(float));
            nf->seq = nseq, nf->pos = 0;
            continue;
        }
        /* FR_SEQ: the next item of the sequence, on the same scope */
        const pgt_grammar_sequence *sq = &g->sequences[fr->seq];
        if (fr->pos >= sq->item_count || best <= fr->t_in) {
            --sp;
            continue;
        }
        const uint32_t pos = fr->pos++;
        const pgt_grammar_item *it = &g->items[sq->first_item + pos];
        const uint32_t key = pgt_facade_child_key(fr->key, pos);
        if (it->kind == PGT_GRAMMAR_ITEM_TERMINAL) {
            if (pgt_facade_kind_of(it->target) == PGT_FACADE_MISS) {
                stats->errors |= PGT_FACADE_ERR_ITEM;
                break;
            }
            stats->terminals++;
            const uint32_t item = sq->first_item + pos;
            /* the ray in the terminal's block coordinates, and the block's corner */
            const float al[3] = {a[0] - fr->x0, a[1] - fr->y0, a[2]};
            const float off[2] = {fr->x0, fr->y0};
            if (it->target == PGT_GRAMMAR_TERMINAL_MESH) { /* 6.2.2: brute force */
                float nrm[3];
                const float *td;
                uint32_t first;
                const uint32_t n =
                    terminal_gimage(&c, s, f, it, fr->args, fr->argc, key, &td, &first);
                if (n == 0) break;
                stats->quads += n;
                const uint32_t k =
                    facade_gimage_hit(td, n, fr->w, fr->h, al, v, wp, off, &best, nrm);
                if (k != PGT_NONE) {
                    best_kind = PGT_FACADE_MESH, best_surface = first + k, best_key = key;
                    best_item = item, best_axis = 3u;
                    memcpy(best_n, nrm, sizeof best_n);
                }
                continue;
            }
            const pgt_facade_quad *qs;
            const uint8_t *surf;
            const float *groups;
            uint8_t surf_local[PGT_FACADE_MAX_QUADS];
            /* in block coordinates: the ray is shifted to the scope's corner (al) */
            const uint32_t n =
                terminal_quads(&c, cache, f, B->grammar, it, item, key, fr->w, fr->h, fr->args,
                               fr->argc, quads, surf_local, &qs, &surf, &groups);
            quad_prep prep;
            prepare_quads(qs, n, groups, al, &prep);
            const uint32_t k =
                hit_terminal(qs, n, groups, &prep, v, inv, wp, off, &best, &stats->quads);
            if (k != PGT_NONE) {
                best_kind = pgt_facade_kind_of(it->target), best_surface = surf[k], best_key = key;
                best_item = item, best_axis = qs[k].axis;
            }
            continue;
        }
        /* An item in tail position (the sequence's last) takes over its sequence's frame, so
         * F --> split ..., part --> FL, FL --> split ... costs one frame per split level. */
        const int tail = fr->pos == sq->item_count;
        if (!tail && sp == PGT_FACADE_MAX_DEPTH) {
            stats->errors |= PGT_FACADE_ERR_DEPTH;
            break;
        }
        if (--budget == 0) {
            stats->errors |= PGT_FACADE_ERR_BUDGET;
            break;
        }
        if (it->kind == PGT_GRAMMAR_ITEM_CALL) {
            frame *nf = tail ? fr : &stack[sp];
            float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
            uint32_t seq;
            if (!facade_call(&c, it, fr->args, fr->argc, key, args, &seq)) break;
            if (seq == PGT_NONE) continue;
            if (!tail) ++sp;
            stats->nodes++;
            nf->type = FR_SEQ, nf->key = key, nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w;
            nf->h = fr->h, nf->t_in = fr->t_in, nf->t_out = fr->t_out, nf->argc = it->arg_count;
            memcpy(nf->args, args, it->arg_count * sizeof(float));
            nf->seq = seq, nf->pos = 0;
            continue;
        }
        if (it->kind != PGT_GRAMMAR_ITEM_SPLIT || it->target > 1u) {
            stats->errors |= PGT_FACADE_ERR_ITEM;
            break;
        }
        frame *nf = tail ? fr : &stack[sp];
        const uint32_t ax = it->target, item = sq->first_item + pos;
        if (!split_layout(&c, cache, f, B->grammar, it, item, key, fr->w, fr->h,
                          ax == 0 ? fr->w : fr->h, fr->args, fr->argc, &nf->split, &nf->sp, &nf->fl,
                          &nf->pinned))
            break;
        if (!tail) {
            ++sp;
            nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w, nf->h = fr->h, nf->t_in = fr->t_in;
            nf->t_out = fr->t_out, nf->argc = fr->argc;
            memcpy(nf->args, fr->args, fr->argc * sizeof(float));
        }
        stats->nodes++;
        nf->type = FR_SPLIT, nf->key = key;
        nf->axis = ax, nf->dir = v[ax] < 0.0f ? -1 : 1, nf->t_cur = fr->t_in;
        nf->next = entry_child(nf->sp, nf->fl, a[ax], v[ax], fr->t_in, ax == 0 ? fr->x0 : fr->y0,
                               ax == 0 ? fr->w : fr->h, wlo[ax], whi[ax], nf->dir);
    }
    for (uint32_t i = 0; i < sp; ++i) /* frames left by a break */
        if (stack[i].type == FR_SPLIT && stack[i].pinned) stack[i].pinned->pins--;
    if (best_kind == 0) return 0;
    write_hit(hit, f, fi, best, best_key, best_kind, best_surface, best_item, best_axis, best_n, a,
              v, zscale);
    return 1;
}

/* ---- packets: the rays of one screen tile through one facade, developed together ---- */

/* A packet's frame: what frame holds, once for the packet, and per ray of the packet the ray's
 * interval in the scope (t_in, t_out), for a split the ray's progress t_cur and the child it
 * enters by (first). mask: the rays still developing the frame. */
typedef struct pframe {
    uint32_t type, key;
    float x0, y0, w, h;
    uint32_t argc;
    float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
    uint64_t mask;
    /* FR_SEQ */
    uint32_t seq, pos;
    /* FR_SPLIT: one direction for all its rays; next is the packet's cursor */
    uint32_t axis, next;
    int dir;
    const facade_split_state *sp;
    const facade_split_flat *fl;
    facade_cache_split *pinned;
    facade_split_state split;
    float t_in[FACADE_PACKET], t_out[FACADE_PACKET], t_cur[FACADE_PACKET];
    uint32_t first[FACADE_PACKET];
} pframe;

struct facade_packet_work {
    /* one frame more than a ray may use: a split writes its rays' intervals in the child to the
     * frame above it before it knows whether any ray enters the child (and so whether it fits) */
    pframe stack[PGT_FACADE_MAX_DEPTH + 1u];
    float a[3]; /* the rays' origin in facade space: the same for all */
    float wlo[2], whi[2]; /* the facade's window in x and y (+-inf: a whole facade) */
    float v[FACADE_PACKET][3], inv[FACADE_PACKET][3];
    float best[FACADE_PACKET], best_n[FACADE_PACKET][3];
    uint32_t best_kind[FACADE_PACKET], best_surface[FACADE_PACKET], best_key[FACADE_PACKET];
    uint32_t best_item[FACADE_PACKET], best_axis[FACADE_PACKET], nodes[FACADE_PACKET];
};

facade_packet_work *facade_packet_work_create(void) { return malloc(sizeof(facade_packet_work)); }

void facade_packet_work_destroy(facade_packet_work *w) { free(w); }

/* Index of the lowest set bit of a non-zero mask. */
static uint32_t low_bit(uint64_t m) { return (uint32_t)__builtin_ctzll(m); }

/* Adds k nodes to every ray of mask m. */
static void add_nodes(facade_packet_work *w, uint64_t m, uint32_t k) {
    for (; m; m &= m - 1u) w->nodes[low_bit(m)] += k;
}

/* Copies the scope of frame `from` (corner, size, arguments) into `to`. */
static void pframe_scope(pframe *to, const pframe *from) {
    to->x0 = from->x0, to->y0 = from->y0, to->w = from->w, to->h = from->h;
    to->argc = from->argc;
    memcpy(to->args, from->args, from->argc * sizeof(float));
}

/* Budget a packet may spend before it gives up and replays its rays one by one (each ray of the
 * packet spends at most what the packet spends; the slack covers one child's rule calls). */
#define PACKET_BUDGET (PGT_FACADE_NODE_BUDGET - FACADE_COLLAPSE_MAX - 4u)

/* Develops the packet; returns 0 when it must be replayed ray by ray: an error (evaluation,
 * budget, depth, item) whose exact place and partial hit are those of the single-ray
 * development. */
static int packet_develop(const pgt_facade_scene *s, const pgt_facade *f, const facade_ctx *cx,
                          uint32_t grammar, uint64_t mask0, uint32_t key0, uint32_t seq0,
                          const float *wp, facade_cache *cache, facade_packet_work *w,
                          pgt_facade_ray_stats *ls) {
    const pgt_grammar *g = cx->g;
    pframe *stack = w->stack;
    uint32_t sp = 0, spent = 0;
    pframe *fr = &stack[sp++];
    fr->type = FR_SEQ, fr->key = key0, fr->x0 = 0.0f, fr->y0 = 0.0f, fr->w = f->scope_w;
    fr->h = f->scope_h, fr->argc = 0, fr->seq = seq0, fr->pos = 0, fr->mask = mask0;
    add_nodes(w, mask0, 1u);
    int ok = 1;
    while (sp > 0) {
        fr = &stack[sp - 1];
        if (fr->type == FR_SPLIT) {
            const uint32_t c = fr->next;
            if (c == PGT_NONE || c >= fr->sp->plan.child_count) {
                if (fr->pinned) fr->pinned->pins--;
                --sp;
                continue;
            }
            pgt_split_child ch;
            split_child(fr->sp, fr->fl, c, &ch);
            const uint32_t ax = fr->axis, seq = fr->sp->seq[ch.part];
            const float o = ax == 0 ? fr->x0 : fr->y0;
            pframe *nf = &stack[sp]; /* the child's frame: its rays' intervals go there */
            uint64_t live = 0, enter = 0;
            for (uint64_t m = fr->mask; m; m &= m - 1u) {
                const uint32_t r = low_bit(m);
                /* done: a hit before the cursor, or out of the scope */
                if (w->best[r] <= fr->t_cur[r] || fr->t_cur[r] >= fr->t_out[r]) continue;
                live |= (uint64_t)1 << r;
                if (fr->dir > 0 ? fr->first[r] > c : fr->first[r] < c) continue; /* not yet */
                float t_near, t_far;
                child_span(&ch, o, w->a[ax], w->v[r][ax], fr->dir, fr->t_cur[r], fr->t_out[r],
                           &t_near, &t_far);
                fr->t_cur[r] = t_far > fr->t_cur[r] ? t_far : fr->t_cur[r];
                if (seq == PGT_NONE || !(t_near <= t_far) || t_near >= w->best[r]) continue;
                nf->t_in[r] = t_near, nf->t_out[r] = t_far;
                enter |= (uint64_t)1 << r;
            }
            fr->mask = live;
            if (!live) {
                if (fr->pinned) fr->pinned->pins--;
                --sp;
                continue;
            }
            fr->next = fr->dir > 0 ? c + 1u : (c == 0 ? PGT_NONE : c - 1u);
            if (!enter) continue;
            if (sp == PGT_FACADE_MAX_DEPTH || spent >= PACKET_BUDGET) {
                ok = 0;
                break;
            }
            ++sp;
            uint32_t nseq = seq, nkey = pgt_facade_child_key(fr->key, c), nargc = fr->argc,
                     hops = 0;
            const uint32_t *col = cache->collapse[grammar];
            for (; hops < FACADE_COLLAPSE_MAX && col[nseq] != PGT_NONE; ++hops)
                nkey = pgt_facade_child_key(nkey, 0), nseq = col[nseq], nargc = 0;
            add_nodes(w, enter, 1u + hops), spent += 1u + hops;
            nf->type = FR_SEQ, nf->key = nkey, nf->mask = enter;
            nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w, nf->h = fr->h;
            if (ax == 0)
                nf->x0 = fr->x0 + ch.start, nf->w = ch.end - ch.start;
            else
                nf->y0 = fr->y0 + ch.start, nf->h = ch.end - ch.start;
            nf->argc = nargc;
            memcpy(nf->args, fr->args, nargc * sizeof(float));
            nf->seq = nseq, nf->pos = 0;
            continue;
        }
        /* FR_SEQ: the next item of the sequence, on the same scope, for the rays not done */
        const pgt_grammar_sequence *sq = &g->sequences[fr->seq];
        uint64_t live = 0;
        if (fr->pos < sq->item_count)
            for (uint64_t m = fr->mask; m; m &= m - 1u) {
                const uint32_t r = low_bit(m);
                if (!(w->best[r] <= fr->t_in[r])) live |= (uint64_t)1 << r;
            }
        fr->mask = live;
        if (!live) {
            --sp;
            continue;
        }
        const uint32_t pos = fr->pos++, item = sq->first_item + pos;
        const pgt_grammar_item *it = &g->items[item];
        const uint32_t key = pgt_facade_child_key(fr->key, pos);
        if (it->kind == PGT_GRAMMAR_ITEM_TERMINAL) {
            const uint32_t kind = pgt_facade_kind_of(it->target);
            if (kind == PGT_FACADE_MISS) {
                ok = 0;
                break;
            }
            ls->terminals += (uint64_t)__builtin_popcountll(live);
            const float off[2] = {fr->x0, fr->y0};
            if (it->target == PGT_GRAMMAR_TERMINAL_MESH) { /* 6.2.2: brute force */
                const float *td;
                uint32_t firsttri;
                const uint32_t n =
                    terminal_gimage(cx, s, f, it, fr->args, fr->argc, key, &td, &firsttri);
                if (n == 0) {
                    ok = 0;
                    break;
                }
                const float al[3] = {w->a[0] - fr->x0, w->a[1] - fr->y0, w->a[2]};
                for (uint64_t m = live; m; m &= m - 1u) {
                    const uint32_t r = low_bit(m);
                    float nrm[3];
                    ls->quads += n;
                    const uint32_t k = facade_gimage_hit(td, n, fr->w, fr->h, al, w->v[r], wp, off,
                                                         &w->best[r], nrm);
                    if (k != PGT_NONE) {
                        w->best_kind[r] = PGT_FACADE_MESH, w->best_surface[r] = firsttri + k;
                        w->best_key[r] = key, w->best_item[r] = item, w->best_axis[r] = 3u;
                        memcpy(w->best_n[r], nrm, sizeof nrm);
                    }
                }
                continue;
            }
            const pgt_facade_quad *qs;
            const uint8_t *surf;
            const float *groups;
            pgt_facade_quad q_own[PGT_FACADE_MAX_QUADS];
            uint8_t surf_own[PGT_FACADE_MAX_QUADS];
            const uint32_t n =
                terminal_quads(cx, cache, f, grammar, it, item, key, fr->w, fr->h, fr->args,
                               fr->argc, q_own, surf_own, &qs, &surf, &groups);
            const float al[3] = {w->a[0] - fr->x0, w->a[1] - fr->y0, w->a[2]};
            quad_prep prep; /* once for all the rays: they share the origin */
            prepare_quads(qs, n, groups, al, &prep);
            for (uint64_t m = live; m; m &= m - 1u) {
                const uint32_t r = low_bit(m);
                const uint32_t k = hit_terminal(qs, n, groups, &prep, w->v[r], w->inv[r], wp, off,
                                                &w->best[r], &ls->quads);
                if (k != PGT_NONE) {
                    w->best_kind[r] = kind, w->best_surface[r] = surf[k], w->best_key[r] = key;
                    w->best_item[r] = item, w->best_axis[r] = qs[k].axis;
                }
            }
            continue;
        }
        /* an item in tail position takes over its sequence's frame, as in facade_intersect */
        const int tail = fr->pos == sq->item_count;
        if (sp + 2u > PGT_FACADE_MAX_DEPTH || spent >= PACKET_BUDGET) {
            ok = 0;
            break;
        }
        ++spent;
        if (it->kind == PGT_GRAMMAR_ITEM_CALL) {
            float args[PGT_GRAMMAR_MAX_RULE_PARAMS];
            uint32_t seq;
            if (!facade_call(cx, it, fr->args, fr->argc, key, args, &seq)) {
                ok = 0;
                break;
            }
            if (seq == PGT_NONE) continue;
            pframe *nf = tail ? fr : &stack[sp++];
            add_nodes(w, live, 1u);
            if (!tail)
                for (uint64_t m = live; m; m &= m - 1u) {
                    const uint32_t r = low_bit(m);
                    nf->t_in[r] = fr->t_in[r], nf->t_out[r] = fr->t_out[r];
                }
            nf->type = FR_SEQ, nf->key = key, nf->x0 = fr->x0, nf->y0 = fr->y0, nf->w = fr->w;
            nf->h = fr->h, nf->argc = it->arg_count, nf->mask = live;
            memcpy(nf->args, args, it->arg_count * sizeof(float));
            nf->seq = seq, nf->pos = 0;
            continue;
        }
        if (it->kind != PGT_GRAMMAR_ITEM_SPLIT || it->target > 1u) {
            ok = 0;
            break;
        }
        /* a split: one frame for the rays going up the axis, one for those going down */
        const uint32_t ax = it->target;
        pframe *nf = tail ? fr : &stack[sp];
        const facade_split_state *lay;
        const facade_split_flat *fl;
        facade_cache_split *pinned;
        if (!split_layout(cx, cache, f, grammar, it, item, key, fr->w, fr->h,
                          ax == 0 ? fr->w : fr->h, fr->args, fr->argc, &nf->split, &lay, &fl,
                          &pinned)) {
            ok = 0;
            break;
        }
        add_nodes(w, live, 1u);
        const float L = ax == 0 ? fr->w : fr->h, o = ax == 0 ? fr->x0 : fr->y0;
        uint64_t up = 0, down = 0;
        uint32_t lo = PGT_NONE, hi = 0;
        for (uint64_t m = live; m; m &= m - 1u) {
            const uint32_t r = low_bit(m);
            const int dir = w->v[r][ax] < 0.0f ? -1 : 1;
            const uint32_t k = entry_child(lay, fl, w->a[ax], w->v[r][ax], fr->t_in[r], o, L,
                                           w->wlo[ax], w->whi[ax], dir);
            if (k == PGT_NONE) continue; /* the node counts, no child is entered */
            nf->first[r] = k, nf->t_cur[r] = fr->t_in[r];
            if (!tail) nf->t_in[r] = fr->t_in[r], nf->t_out[r] = fr->t_out[r];
            if (dir > 0) {
                up |= (uint64_t)1 << r;
                lo = k < lo ? k : lo;
            } else {
                down |= (uint64_t)1 << r;
                hi = k > hi ? k : hi;
            }
        }
        if (!up && !down) {
            if (pinned) pinned->pins--;
            if (tail) fr->mask = 0;
            continue;
        }
        if (!tail) {
            ++sp;
            pframe_scope(nf, fr);
        }
        nf->type = FR_SPLIT, nf->key = key, nf->axis = ax;
        nf->sp = lay, nf->fl = fl, nf->pinned = pinned;
        nf->mask = up ? up : down, nf->dir = up ? 1 : -1, nf->next = up ? lo : hi;
        if (up && down) { /* the rays going down get a frame above, on the same layout */
            pframe *df = &stack[sp++];
            pframe_scope(df, nf);
            df->type = FR_SPLIT, df->key = key, df->axis = ax, df->sp = nf->sp, df->fl = fl;
            df->pinned = pinned;
            if (pinned) pinned->pins++;
            df->mask = down, df->dir = -1, df->next = hi;
            for (uint64_t m = down; m; m &= m - 1u) {
                const uint32_t r = low_bit(m);
                df->t_in[r] = nf->t_in[r], df->t_out[r] = nf->t_out[r];
                df->t_cur[r] = nf->t_cur[r], df->first[r] = nf->first[r];
            }
        }
    }
    for (uint32_t i = 0; i < sp; ++i) /* frames left by a break */
        if (stack[i].type == FR_SPLIT && stack[i].pinned) stack[i].pinned->pins--;
    return ok && !ls->errors;
}

/* facade_intersect_packet with a work area; returns 0, having written nothing, when the packet
 * must be replayed ray by ray. */
static int packet_intersect(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                            const float org[3], const float (*dirs)[3], const uint32_t *idx,
                            uint32_t n, pgt_facade_hit *hits, uint32_t *dev,
                            pgt_facade_ray_stats *stats, facade_cache *cache, facade_packet_work *w,
                            float zscale) {
    pgt_facade_ray_stats ls;
    memset(&ls, 0, sizeof ls);
    const int whole = facade_is_whole(f);
    const float win[4] = {f->u0, f->v0, f->u0 + f->width, f->v0 + f->height};
    uint64_t mask = 0;
    ls.rays = n;
    float *a = w->a;
    facade_entry_window(f, w->wlo, w->whi);
    local_point(f, whole, org, a);
    if (zscale != 1.0f) a[2] /= zscale;
    /* the volume's faces minus the origin, for every ray's slabs */
    const float lo[3] = {win[0], win[1], -f->recess}, hi[3] = {win[2], win[3], f->protrusion};
    const float dlo[3] = {lo[0] - a[0], lo[1] - a[1], lo[2] - a[2]};
    const float dhi[3] = {hi[0] - a[0], hi[1] - a[1], hi[2] - a[2]};
    for (uint32_t r = 0; r < n; ++r) {
        float *v = w->v[r], *inv = w->inv[r];
        local_dir(f, whole, dirs[idx[r]], v);
        if (zscale != 1.0f) v[2] /= zscale;
        for (int k = 0; k < 3; ++k) inv[k] = 1.0f / v[k];
        float t0 = 0.0f, t1 = hits[idx[r]].t;
        for (int k = 0; k < 3; ++k)
            slab_pre(a[k], v[k], inv[k], lo[k], hi[k], dlo[k], dhi[k], &t0, &t1);
        if (!(t0 <= t1)) continue; /* misses the volume: nothing developed */
        w->best[r] = hits[idx[r]].t, w->best_kind[r] = 0, w->nodes[r] = 0;
        w->stack[0].t_in[r] = t0, w->stack[0].t_out[r] = t1;
        mask |= (uint64_t)1 << r;
    }
    ls.volume_hits = (uint64_t)__builtin_popcountll(mask);
    int ok = 1;
    if (mask) {
        const pgt_facade_building *B = &s->buildings[f->building];
        const facade_ctx c = {&s->grammars[B->grammar], s->params + B->first_param, B->seed, &ls,
                              NULL};
        const uint32_t key0 = facade_axiom_key(s, f);
        const uint32_t seq0 = facade_select_case(&c, 0, NULL, 0, key0);
        if (ls.errors)
            ok = 0;
        else if (seq0 != PGT_NONE)
            ok = packet_develop(s, f, &c, B->grammar, mask, key0, seq0, whole ? NULL : win, cache,
                                w, &ls);
        else
            mask = 0;
    }
    if (!ok) return 0;
    for (uint64_t m = mask; m; m &= m - 1u) {
        const uint32_t r = low_bit(m);
        ls.nodes += w->nodes[r], dev[idx[r]] += w->nodes[r];
        if (w->best_kind[r] == 0) continue;
        write_hit(&hits[idx[r]], f, fi, w->best[r], w->best_key[r], w->best_kind[r],
                  w->best_surface[r], w->best_item[r], w->best_axis[r], w->best_n[r], w->a, w->v[r],
                  zscale);
    }
    stats->rays += ls.rays, stats->volume_hits += ls.volume_hits, stats->nodes += ls.nodes;
    stats->terminals += ls.terminals, stats->quads += ls.quads;
    return 1;
}

void facade_intersect_packet(const pgt_facade_scene *s, const pgt_facade *f, uint32_t fi,
                             const float org[3], const float (*dirs)[3], const uint32_t *idx,
                             uint32_t n, pgt_facade_hit *hits, uint32_t *dev,
                             pgt_facade_ray_stats *stats, facade_cache *cache,
                             facade_packet_work *w, float zscale) {
    if (w && packet_intersect(s, f, fi, org, dirs, idx, n, hits, dev, stats, cache, w, zscale))
        return;
    /* ray by ray (no work area, or a packet to replay): the hits, counts and errors of
     * facade_intersect, which is what a packet gives */
    for (uint32_t r = 0; r < n; ++r) {
        const uint64_t before = stats->nodes;
        facade_intersect(s, f, fi, org, dirs[idx[r]], &hits[idx[r]], stats, cache, zscale);
        dev[idx[r]] += (uint32_t)(stats->nodes - before);
    }
}

/* ---- roofs ---- */

int facade_roof_intersect(const pgt_facade_scene *s, uint32_t b, uint32_t facade_count,
                          const float org[3], const float dir[3], pgt_facade_hit *hit) {
    const pgt_facade_building *B = &s->buildings[b];
    const float y = B->base + B->height;
    if (dir[1] == 0.0f) return 0;
    const float t = (y - org[1]) / dir[1];
    if (!(t > 0.0f && t < hit->t)) return 0;
    const float px = org[0] + t * dir[0], pz = org[2] + t * dir[2];
    const float *c = s->corners + 2u * B->first_corner;
    int in = 0; /* crossing number */
    for (uint32_t i = 0, j = B->corner_count - 1u; i < B->corner_count; j = i++) {
        const float xi = c[2 * i], zi = c[2 * i + 1], xj = c[2 * j], zj = c[2 * j + 1];
        if ((zi > pz) != (zj > pz) && px < (xj - xi) * (pz - zi) / (zj - zi) + xi) in = !in;
    }
    if (!in) return 0;
    hit->t = t, hit->facade = facade_count + b, hit->node = 0, hit->kind = PGT_FACADE_ROOF;
    hit->surface = 0, hit->item = PGT_NONE;
    hit->n[0] = 0.0f, hit->n[1] = 1.0f, hit->n[2] = 0.0f;
    hit->p[0] = px, hit->p[1] = y, hit->p[2] = pz;
    return 1;
}

static double cross2(const float *c, uint32_t a, uint32_t b, uint32_t d) {
    return ((double)c[2 * b] - c[2 * a]) * ((double)c[2 * d + 1] - c[2 * a + 1]) -
           ((double)c[2 * b + 1] - c[2 * a + 1]) * ((double)c[2 * d] - c[2 * a]);
}

uint32_t facade_triangulate(const float *c, uint32_t n, uint32_t *tris, uint32_t *idx) {
    double area = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1u) % n;
        area += (double)c[2 * i] * c[2 * j + 1] - (double)c[2 * j] * c[2 * i + 1];
    }
    const double sg = area < 0.0 ? -1.0 : 1.0; /* convex corners turn this way */
    for (uint32_t i = 0; i < n; ++i) idx[i] = i;
    uint32_t m = n, out = 0, guard = 0;
    while (m > 3 && guard < 2u * m) {
        int cut = 0;
        for (uint32_t i = 0; i < m && !cut; ++i) {
            const uint32_t a = idx[(i + m - 1u) % m], b = idx[i], d = idx[(i + 1u) % m];
            if (sg * cross2(c, a, b, d) <= 0.0) continue; /* reflex or flat */
            int empty = 1;                                /* no other corner inside the ear */
            for (uint32_t k = 0; k < m && empty; ++k) {
                const uint32_t q = idx[k];
                if (q == a || q == b || q == d) continue;
                if (sg * cross2(c, a, b, q) >= 0.0 && sg * cross2(c, b, d, q) >= 0.0 &&
                    sg * cross2(c, d, a, q) >= 0.0)
                    empty = 0;
            }
            if (!empty) continue;
            tris[3 * out] = a, tris[3 * out + 1] = b, tris[3 * out + 2] = d, ++out;
            for (uint32_t k = i; k + 1u < m; ++k) idx[k] = idx[k + 1u];
            --m, cut = 1;
        }
        guard = cut ? 0 : guard + 1u;
        if (!cut) break; /* degenerate: no ear left */
    }
    if (m == 3)
        tris[3 * out] = idx[0], tris[3 * out + 1] = idx[1], tris[3 * out + 2] = idx[2], ++out;
    return out;
}
