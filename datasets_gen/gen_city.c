/* pgt datasets: the facade city (paper 003 sec. 9, issue 6 item 7). See gen.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <pgt/rng.h>

#include "gen.h"

/* Buildings per city at most: 2^22 is 16.8 M facades, far past any benchmark. */
#define CITY_MAX_BUILDINGS (1u << 22)

static double draw(uint32_t seed, uint32_t k, uint32_t j, double lo, double hi) {
    return lo + (hi - lo) * pgt_rng_double(seed, PGT_GEN_STREAM_CITY, 16ull * k + j);
}

pgt_result pgt_gen_city(pgt_facade_scene *out, const pgt_grammar *g, uint32_t n, uint32_t seed,
                        pgt_error *err) {
    memset(out, 0, sizeof *out);
    if (n == 0 || n > CITY_MAX_BUILDINGS)
        return pgt_error_set(err, n ? PGT_ERROR_LIMIT : PGT_ERROR_INVALID_ARGUMENT,
                             "pgt_gen_city: %u buildings, expected 1 to %u", n, CITY_MAX_BUILDINGS);
    static const char *const names[] = {"floorHeight", "windowWidth", "doorWidth", "protrusion",
                                        "recess"};
    uint32_t idx[5];
    for (int k = 0; k < 5; ++k)
        if ((idx[k] = pgt_grammar_find_param(g, names[k])) == PGT_NONE)
            return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                                 "pgt_gen_city: grammar %s has no param %s",
                                 g->names + g->file_name, names[k]);
    const uint32_t P = g->param_count;
    out->buildings = malloc((size_t)n * sizeof *out->buildings);
    out->corners = malloc((size_t)n * 8u * sizeof *out->corners);
    out->params = malloc((size_t)n * (P ? P : 1u) * sizeof *out->params);
    if (!out->buildings || !out->corners || !out->params) {
        pgt_facade_scene_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "pgt_gen_city: out of memory");
    }
    out->grammar_count = 1, out->grammars = g;
    out->building_count = n, out->corner_count = 4u * n, out->param_count = P * n;
    uint32_t side = (uint32_t)ceil(sqrt((double)n));
    while ((uint64_t)side * side < n) ++side;
    for (uint32_t k = 0; k < n; ++k) {
        const double w = draw(seed, k, 0, 12.0, 26.0), d = draw(seed, k, 1, 10.0, 24.0);
        const double ox = draw(seed, k, 2, 0.0, 1.0) * (26.0 - w);
        const double oz = draw(seed, k, 3, 0.0, 1.0) * (24.0 - d);
        const uint32_t floors = 3u + (uint32_t)floor(draw(seed, k, 4, 0.0, 10.0));
        const double fh = draw(seed, k, 5, 2.8, 3.6);
        const double x0 = (double)(k % side) * PGT_GEN_CITY_LOT + ox;
        const double z0 = (double)(k / side) * PGT_GEN_CITY_LOT + oz;
        float *c = out->corners + 8u * k;
        /* counter-clockwise seen from above: (x0,z0) (x0,z1) (x1,z1) (x1,z0) */
        c[0] = (float)x0, c[1] = (float)z0, c[2] = (float)x0, c[3] = (float)(z0 + d);
        c[4] = (float)(x0 + w), c[5] = (float)(z0 + d), c[6] = (float)(x0 + w), c[7] = (float)z0;
        float *p = out->params + (size_t)P * k;
        memcpy(p, g->param_values, (size_t)P * sizeof *p);
        p[idx[0]] = (float)fh;
        p[idx[1]] = (float)draw(seed, k, 6, 1.8, 2.8);
        p[idx[2]] = (float)draw(seed, k, 7, 1.2, 2.0);
        p[idx[3]] = (float)draw(seed, k, 8, 0.2, 0.5);
        p[idx[4]] = (float)draw(seed, k, 9, 0.2, 0.5);
        /* a pastel: each channel in [0.55, 0.95] */
        uint32_t rgb = 0;
        for (uint32_t j = 0; j < 3; ++j)
            rgb = rgb << 8 | (uint32_t)lround(255.0 * draw(seed, k, 10 + j, 0.55, 0.95));
        pgt_facade_building *B = &out->buildings[k];
        B->first_corner = 4u * k, B->corner_count = 4u;
        B->base = 0.0f, B->height = (float)(floors * fh);
        B->grammar = 0, B->first_param = P * k;
        B->seed = (uint32_t)pgt_rng_u64(seed, PGT_GEN_STREAM_CITY, 16ull * k + 13u);
        B->colour = rgb;
    }
    const pgt_result r = pgt_facade_add_builtin_gimages(out, err);
    if (r != PGT_OK) pgt_facade_scene_destroy(out);
    return r;
}
