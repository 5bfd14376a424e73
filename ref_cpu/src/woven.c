/* pgt: the woven sphere reference model (woven.h; paper 002 Appendix A and section 4.5; the
 * loft's frames: the sphere's normal, the exact rotation-minimising frame of a curve on the
 * sphere, woven.h 4.). */
#include "pgt/woven.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pgt/parallel.h"
#include "pgt/rng.h"
#include "vec3_internal.h"

#define TWO_PI 6.283185307179586

/* The resolutions of the paper's table (woven.h, 5.): P = C K, C U V = the rounded count. */
const pgt_woven_resolution pgt_woven_resolutions[PGT_WOVEN_RESOLUTION_COUNT] = {
    {"5k", {150, 6, 25, 8, 25}},       {"22k", {660, 6, 110, 8, 25}},
    {"50k", {800, 8, 100, 10, 50}},    {"89k", {1424, 8, 178, 10, 50}},
    {"179k", {1432, 8, 179, 10, 100}},
};

/* ---- parameters ----------------------------------------------------------------------- */

static pgt_result check_one(const char *letter, const char *what, uint32_t v, uint32_t lo,
                            uint32_t hi, pgt_error *err) {
    if (v < lo)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "woven: %s = %u (%s): must be at least %u", letter, v, what, lo);
    if (v > hi)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "woven: %s = %u (%s): must be at most %u%s", letter, v, what, hi,
                             v > 0x7FFFFFFFu ? " (a negative value passed as unsigned?)" : "");
    return PGT_OK;
}

pgt_result pgt_woven_check(const pgt_woven_params *p, pgt_woven_counts *out, pgt_error *err) {
    if (out) memset(out, 0, sizeof *out);
    if (!p) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "woven: no parameters");
    pgt_result r;
    if ((r = check_one("P", "particles", p->particles, 1u, PGT_WOVEN_MAX_PARTICLES, err)) ||
        (r = check_one("K", "keys per curve; a cubic B-spline span needs 4", p->keys,
                       PGT_WOVEN_MIN_KEYS, PGT_WOVEN_MAX_KEYS, err)) ||
        (r = check_one("C", "curves", p->curves, 1u, PGT_WOVEN_MAX_CURVES, err)) ||
        (r = check_one("U", "circle vertices, the last repeating the first", p->ring,
                       PGT_WOVEN_MIN_RING, PGT_WOVEN_MAX_RING, err)) ||
        (r = check_one("V", "samples per curve", p->samples, PGT_WOVEN_MIN_SAMPLES,
                       PGT_WOVEN_MAX_SAMPLES, err)))
        return r;
    if (p->keys > p->particles)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "woven: K = %u keys per curve, but P = %u particles: a curve's keys "
                             "are distinct particles (K <= P)",
                             p->keys, p->particles);
    const uint64_t C = p->curves, U = p->ring, V = p->samples, K = p->keys;
    const uint64_t points = C * V, keys = C * K, vertices = C * U * V;
    const uint64_t triangles = 2u * (U - 1u) * (V - 1u) * C; /* < 2^12 2^20 2^24 2: no wrap */
    const struct {
        const char *name;
        uint64_t value;
    } products[4] = {{"C*V (curve points)", points},
                     {"C*K (keys)", keys},
                     {"C*U*V (vertices)", vertices},
                     {"2*(U-1)*(V-1)*C (triangles)", triangles}};
    for (int i = 0; i < 4; ++i)
        if (products[i].value > UINT32_MAX)
            return pgt_error_set(err, PGT_ERROR_LIMIT,
                                 "woven: %s = %llu exceeds 2^32 - 1 (32-bit indices)",
                                 products[i].name, (unsigned long long)products[i].value);
    /* the largest array: 3 C U V floats or 3 * triangles indices (both 4 bytes) */
    const uint64_t words = 3u * (vertices > triangles ? vertices : triangles);
    if (words > SIZE_MAX / 4u)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "woven: %llu 4-byte words for one array exceed this platform's "
                             "address space",
                             (unsigned long long)words);
    if (out) {
        out->curve_points = (uint32_t)points;
        out->vertices = (uint32_t)vertices;
        out->triangles = (uint32_t)triangles;
        const uint64_t P = p->particles;
        out->bytes = 24u * P + 4u * keys + 36u * V + 8u * U             /* pgt_woven */
                     + 12u * points + 24u * vertices + 12u * triangles; /* pgt_woven_mesh */
    }
    return PGT_OK;
}

pgt_result pgt_woven_find_resolution(const char *name, pgt_woven_params *out, pgt_error *err) {
    for (uint32_t i = 0; name && i < PGT_WOVEN_RESOLUTION_COUNT; ++i)
        if (!strcmp(name, pgt_woven_resolutions[i].name)) {
            *out = pgt_woven_resolutions[i].params;
            return PGT_OK;
        }
    return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                         "woven: unknown resolution '%s' (known: 5k, 22k, 50k, 89k, 179k)",
                         name ? name : "");
}

/* ---- creation ------------------------------------------------------------------------- */

/* An index uniform in [0, n): floor(r n / 2^64) in exact 64-bit pieces (n < 2^32). */
static uint32_t draw_below(uint64_t r, uint32_t n) {
    const uint64_t hi = (r >> 32) * n, lo = (r & 0xFFFFFFFFu) * n;
    return (uint32_t)((hi + (lo >> 32)) >> 32);
}

/* Curve c's keys (woven.h, 2.): Floyd's set, then a Fisher-Yates shuffle. taken is a bitmap of
 * P bits, all clear on entry and on return: membership in O(1) (a scan of the keys drawn so far
 * made a curve O(K^2), 22 minutes for the largest parameters allowed). */
static void draw_keys(uint32_t *key, uint64_t *taken, uint32_t c, uint32_t P, uint32_t K,
                      uint32_t seed) {
    const uint64_t base = (uint64_t)c << 32;
    for (uint32_t d = 0; d < K; ++d) {
        const uint32_t j = P - K + d; /* above every key drawn so far: never taken */
        const uint32_t t = draw_below(pgt_rng_u64(seed, PGT_WOVEN_STREAM_SUBSET, base + d), j + 1u);
        key[d] = (taken[t >> 6] >> (t & 63u)) & 1u ? j : t;
        taken[key[d] >> 6] |= (uint64_t)1 << (key[d] & 63u);
    }
    for (uint32_t d = 0; d < K; ++d) taken[key[d] >> 6] &= ~((uint64_t)1 << (key[d] & 63u));
    for (uint32_t i = K - 1u, d = K; i > 0; --i, ++d) {
        const uint32_t k = draw_below(pgt_rng_u64(seed, PGT_WOVEN_STREAM_SUBSET, base + d), i + 1u);
        const uint32_t tmp = key[i];
        key[i] = key[k], key[k] = tmp;
    }
}

pgt_result pgt_woven_create(pgt_woven *out, const pgt_woven_params *p, uint32_t seed,
                            pgt_error *err) {
    if (!out) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "woven: no output");
    memset(out, 0, sizeof *out);
    pgt_woven_counts counts;
    const pgt_result r = pgt_woven_check(p, &counts, err);
    if (r != PGT_OK) return r;
    const size_t P = p->particles, K = p->keys, C = p->curves, U = p->ring, V = p->samples;
    pgt_woven w;
    memset(&w, 0, sizeof w);
    w.params = *p, w.counts = counts, w.seed = seed;
    w.positions = malloc(3u * P * sizeof(float));
    w.velocities = malloc(3u * P * sizeof(float));
    w.keys = malloc(C * K * sizeof(uint32_t));
    w.span = malloc(V * sizeof(uint32_t));
    w.basis = malloc(8u * V * sizeof(float));
    w.ring_cos = malloc(U * sizeof(float));
    w.ring_sin = malloc(U * sizeof(float));
    if (!w.positions || !w.velocities || !w.keys || !w.span || !w.basis || !w.ring_cos ||
        !w.ring_sin) {
        pgt_woven_destroy(&w);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "woven: out of memory (P = %u, C = %u, K = %u)", p->particles,
                             p->curves, p->keys);
    }
    /* 1. particles: positions exact in float32 (24-bit draws); directions in double */
    for (size_t i = 0; i < P; ++i) {
        for (uint32_t a = 0; a < 3u; ++a)
            w.positions[3u * i + a] =
                2.0f * pgt_rng_float(seed, PGT_WOVEN_STREAM_POSITION, 3u * (uint64_t)i + a) - 1.0f;
        const double z = 1.0 - 2.0 * pgt_rng_double(seed, PGT_WOVEN_STREAM_DIRECTION, 2u * i);
        const double phi = TWO_PI * pgt_rng_double(seed, PGT_WOVEN_STREAM_DIRECTION, 2u * i + 1u);
        const double rho = sqrt(fmax(0.0, 1.0 - z * z));
        const double dir[3] = {rho * cos(phi), rho * sin(phi), z};
        for (uint32_t a = 0; a < 3u; ++a)
            w.velocities[3u * i + a] = (float)((double)PGT_WOVEN_SPEED * dir[a]);
    }
    /* 2. subsets */
    uint64_t *taken = calloc((P + 63u) / 64u, sizeof(uint64_t));
    if (!taken) {
        pgt_woven_destroy(&w);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "woven: out of memory (P = %u)",
                             p->particles);
    }
    for (uint32_t c = 0; c < p->curves; ++c)
        draw_keys(&w.keys[(size_t)c * K], taken, c, p->particles, p->keys, seed);
    free(taken);
    /* the B-spline table: span and weights of every sample, exact integer parameters */
    const uint64_t spans = p->keys - 3u;
    for (uint32_t j = 0; j < p->samples; ++j) {
        const uint64_t num = (uint64_t)j * spans, den = p->samples - 1u;
        uint64_t s = num / den;
        double u = (double)(num % den) / (double)den;
        if (s == spans) s = spans - 1u, u = 1.0; /* the last sample ends the last span */
        const double v = 1.0 - u;
        const double n[8] = {v * v * v / 6.0,
                             (3.0 * u * u * u - 6.0 * u * u + 4.0) / 6.0,
                             (-3.0 * u * u * u + 3.0 * u * u + 3.0 * u + 1.0) / 6.0,
                             u * u * u / 6.0,
                             -0.5 * v * v,
                             (3.0 * u * u - 4.0 * u) / 2.0,
                             (-3.0 * u * u + 2.0 * u + 1.0) / 2.0,
                             0.5 * u * u};
        w.span[j] = (uint32_t)s;
        for (int k = 0; k < 8; ++k) w.basis[8u * j + (uint32_t)k] = (float)n[k];
    }
    /* the circle: U - 1 distinct angles, the last vertex repeats the first */
    for (size_t m = 0; m + 1u < U; ++m) {
        const double a = TWO_PI * (double)m / (double)(U - 1u);
        w.ring_cos[m] = (float)cos(a), w.ring_sin[m] = (float)sin(a);
    }
    w.ring_cos[U - 1u] = w.ring_cos[0], w.ring_sin[U - 1u] = w.ring_sin[0];
    *out = w;
    return PGT_OK;
}

void pgt_woven_destroy(pgt_woven *w) {
    if (!w) return;
    free(w->positions), free(w->velocities), free(w->keys), free(w->span), free(w->basis);
    free(w->ring_cos), free(w->ring_sin);
    memset(w, 0, sizeof *w);
}

void pgt_woven_triangles(uint32_t *out, const pgt_woven_params *p) {
    const uint32_t U = p->ring, V = p->samples;
    size_t t = 0;
    for (uint32_t c = 0; c < p->curves; ++c)
        for (uint32_t j = 0; j + 1u < V; ++j)
            for (uint32_t m = 0; m + 1u < U; ++m) {
                const uint32_t a = (c * V + j) * U + m, b = a + U;
                out[t++] = a, out[t++] = a + 1u, out[t++] = b + 1u;
                out[t++] = a, out[t++] = b + 1u, out[t++] = b;
            }
}

pgt_result pgt_woven_mesh_create(pgt_woven_mesh *out, const pgt_woven_params *p, pgt_error *err) {
    if (!out) return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT, "woven: no output");
    memset(out, 0, sizeof *out);
    pgt_woven_counts n;
    const pgt_result r = pgt_woven_check(p, &n, err);
    if (r != PGT_OK) return r;
    pgt_woven_mesh m;
    m.counts = n;
    m.curve_points = calloc(3u * (size_t)n.curve_points, sizeof(float));
    m.positions = calloc(3u * (size_t)n.vertices, sizeof(float));
    m.normals = calloc(3u * (size_t)n.vertices, sizeof(float));
    m.triangles = malloc(3u * (size_t)n.triangles * sizeof(uint32_t));
    if (!m.curve_points || !m.positions || !m.normals || !m.triangles) {
        pgt_woven_mesh_destroy(&m);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "woven: out of memory for %u vertices and %u triangles", n.vertices,
                             n.triangles);
    }
    pgt_woven_triangles(m.triangles, p);
    *out = m;
    return PGT_OK;
}

void pgt_woven_mesh_destroy(pgt_woven_mesh *m) {
    if (!m) return;
    free(m->curve_points), free(m->positions), free(m->normals), free(m->triangles);
    memset(m, 0, sizeof *m);
}

/* ---- the frame ------------------------------------------------------------------------ */

static void step_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    pgt_woven *w = vctx;
    (void)worker;
    for (size_t q = 3u * (size_t)begin; q < 3u * (size_t)end; ++q) {
        float x = w->positions[q] + w->velocities[q];
        /* exact reflections (woven.h, 1.): 2 - x and -2 - x are exact for |x| in [1, 2] */
        if (x > 1.0f)
            x = 2.0f - x, w->velocities[q] = -w->velocities[q];
        else if (x < -1.0f)
            x = -2.0f - x, w->velocities[q] = -w->velocities[q];
        w->positions[q] = x;
    }
}

void pgt_woven_step(pgt_woven *w, uint32_t threads) {
    pgt_parallel_for(w->params.particles, threads, step_range, w);
    w->frame++;
}

/* Normalises v in place; 0 (v unchanged) when its squared length is below FLT_MIN. */
static int normalize3(float v[3]) {
    const float l2 = dot3(v, v);
    if (!(l2 >= FLT_MIN)) return 0;
    /* one division, not three: it sits in the frame's dependency chain, sample after sample */
    const float inv = 1.0f / sqrtf(l2);
    v[0] *= inv, v[1] *= inv, v[2] *= inv;
    return 1;
}

/* A unit vector perpendicular to unit t: t crossed with its least aligned axis. */
static void any_perpendicular(const float t[3], float r[3]) {
    const float ax = fabsf(t[0]), ay = fabsf(t[1]), az = fabsf(t[2]);
    const int i = ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2;
    const float e[3] = {i == 0 ? 1.0f : 0.0f, i == 1 ? 1.0f : 0.0f, i == 2 ? 1.0f : 0.0f};
    cross3(t, e, r);
    if (!normalize3(r)) r[0] = 1.0f, r[1] = 0.0f, r[2] = 0.0f;
}

typedef struct eval_ctx {
    pgt_woven_mesh *out;
    const pgt_woven *w;
} eval_ctx;

/* Curves c in [begin, end): sample, spherify, frame, ring (woven.h, 2.-4.). */
static void eval_range(void *vctx, uint32_t begin, uint32_t end, uint32_t worker) {
    const eval_ctx *ctx = vctx;
    pgt_woven_mesh *o = ctx->out;
    const pgt_woven *w = ctx->w;
    (void)worker;
    const uint32_t K = w->params.keys, U = w->params.ring, V = w->params.samples;
    const float R = PGT_WOVEN_RADIUS;
    for (uint32_t c = begin; c < end; ++c) {
        const uint32_t *key = &w->keys[(size_t)c * K];
        float pp[3] = {0.0f, 0.0f, 1.0f}, tp[3] = {0.0f, 0.0f, 0.0f};
        for (uint32_t j = 0; j < V; ++j) {
            const uint32_t s = w->span[j];
            const float *n = &w->basis[8u * j];
            float cv[3] = {0.0f, 0.0f, 0.0f}, dv[3] = {0.0f, 0.0f, 0.0f};
            for (uint32_t i = 0; i < 4u; ++i) {
                const float *k = &w->positions[3u * (size_t)key[s + i]];
                for (int a = 0; a < 3; ++a) cv[a] += n[i] * k[a], dv[a] += n[4u + i] * k[a];
            }
            /* 3. spherify in double: any nonzero float vector normalises to float precision */
            float p[3];
            const double l =
                sqrt((double)cv[0] * cv[0] + (double)cv[1] * cv[1] + (double)cv[2] * cv[2]);
            if (l > 0.0) {
                const double inv = 1.0 / l;
                for (int a = 0; a < 3; ++a) p[a] = (float)(cv[a] * inv);
            } else {
                memcpy(p, pp, sizeof p); /* the origin: the previous point, or +z */
            }
            /* the spherified curve's unit tangent */
            const float pd = dot3(p, dv);
            float t[3] = {dv[0] - pd * p[0], dv[1] - pd * p[1], dv[2] - pd * p[2]};
            if (!normalize3(t)) {
                if (j > 0)
                    memcpy(t, tp, sizeof t);
                else
                    any_perpendicular(p, t);
            }
            /* 4. rotation-minimising frame: the sphere's normal (woven.h 4.) */
            float r[3] = {p[0], p[1], p[2]};
            const float rt = dot3(r, t);
            for (int a = 0; a < 3; ++a) r[a] -= rt * t[a];
            if (!normalize3(r)) any_perpendicular(t, r);
            float b[3];
            cross3(t, r, b);
            /* the ring */
            const size_t q = (size_t)c * V + j, first = q * U;
            memcpy(&o->curve_points[3u * q], p, sizeof p);
            for (uint32_t m = 0; m + 1u < U; ++m) {
                float *nv = &o->normals[3u * (first + m)], *pv = &o->positions[3u * (first + m)];
                const float cm = w->ring_cos[m], sm = w->ring_sin[m];
                for (int a = 0; a < 3; ++a) nv[a] = cm * r[a] + sm * b[a];
                for (int a = 0; a < 3; ++a) pv[a] = p[a] + R * nv[a];
            }
            const size_t last = first + U - 1u; /* the seam: the same bytes as column 0 */
            memcpy(&o->normals[3u * last], &o->normals[3u * first], 3u * sizeof(float));
            memcpy(&o->positions[3u * last], &o->positions[3u * first], 3u * sizeof(float));
            memcpy(pp, p, sizeof pp), memcpy(tp, t, sizeof tp);
        }
    }
}

void pgt_woven_evaluate(pgt_woven_mesh *out, const pgt_woven *w, uint32_t threads) {
    assert(out->counts.vertices == w->counts.vertices &&
           out->counts.curve_points == w->counts.curve_points);
    eval_ctx ctx = {out, w};
    pgt_parallel_for_items(w->params.curves, w->params.ring * w->params.samples, threads,
                           eval_range, &ctx);
}

void pgt_woven_frame(pgt_woven_mesh *out, pgt_woven *w, uint32_t threads) {
    pgt_woven_step(w, threads);
    pgt_woven_evaluate(out, w, threads);
}
