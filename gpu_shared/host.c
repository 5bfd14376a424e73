/* pgt: host-side helpers shared by the GPU backends and the harness. */
#include "host.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

double pgt_gpu_now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

int pgt_gpu_profile_add(pgt_gpu_profile *p, const char *name, double ms) {
    if (!p) return 1;
    if (p->count == p->capacity) {
        uint32_t cap = p->capacity ? 2 * p->capacity : 64;
        pgt_gpu_event *e = realloc(p->events, (size_t)cap * sizeof(*e));
        if (!e) return 0;
        p->events = e, p->capacity = cap;
    }
    pgt_gpu_event *e = &p->events[p->count++];
    memset(e->name, 0, sizeof(e->name));
    strncpy(e->name, name, sizeof(e->name) - 1);
    e->ms = ms;
    return 1;
}

void pgt_gpu_profile_free(pgt_gpu_profile *p) {
    if (!p) return;
    free(p->events);
    memset(p, 0, sizeof(*p));
}

void pgt_gpu_sqrt3_input_free(pgt_gpu_sqrt3_input *p) {
    if (!p) return;
    pgt_adjacency_destroy(&p->adj);
    free(p->vh), free(p->prot), free(p->alpha);
    memset(p, 0, sizeof(*p));
}

pgt_result pgt_gpu_sqrt3_prepare(pgt_gpu_sqrt3_input *out, const pgt_mesh *in,
                                 const pgt_sqrt3_options *opts, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    pgt_result r = pgt_sqrt3_check_input(in, opts->iterations, err);
    if (r != PGT_OK) return r;
    r = pgt_adjacency_build(&out->adj, in, 1, err);
    if (r != PGT_OK) return r;
    r = pgt_adjacency_require_manifold(&out->adj, "sqrt3 input", err);
    if (r != PGT_OK) {
        pgt_gpu_sqrt3_input_free(out);
        return r;
    }
    const uint32_t V = in->vertex_count, F = in->face_count;
    out->vh = malloc(((size_t)V + 1) * sizeof(uint32_t));
    out->prot = malloc(((size_t)F + 1) * sizeof(uint32_t));
    uint32_t *fan = calloc((size_t)V + 1, sizeof(uint32_t));
    if (!out->vh || !out->prot || !fan) {
        free(fan);
        pgt_gpu_sqrt3_input_free(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
    }
    for (uint32_t v = 0; v < V; ++v) out->vh[v] = PGT_NONE;
    for (uint32_t h = 3 * F; h-- > 0;) out->vh[in->indices[h]] = h; /* the smallest leaving v */
    for (uint32_t f = 0; f < F; ++f)
        out->n_protected += out->prot[f] = opts->protected_faces && opts->protected_faces[f] != 0;
    uint32_t max_fan = 0;
    for (uint32_t h = 0; h < 3 * F; ++h)
        if (++fan[in->indices[h]] > max_fan) max_fan = fan[in->indices[h]];
    free(fan);
    out->alpha_count = max_fan + 2 > 64u ? max_fan + 2 : 64u;
    out->alpha = malloc(out->alpha_count * sizeof(float));
    if (!out->alpha) {
        pgt_gpu_sqrt3_input_free(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "sqrt3: out of memory");
    }
    for (uint32_t n = 0; n < out->alpha_count; ++n) out->alpha[n] = pgt_sqrt3_alpha(n);
    return PGT_OK;
}

pgt_result pgt_gpu_sqrt3_copy(pgt_mesh *out, const pgt_mesh *in, const pgt_sqrt3_options *opts,
                              const pgt_adjacency *adj, pgt_error *err) {
    pgt_result r =
        pgt_mesh_create(out, in->vertex_count, in->face_count, 0, in->labels != NULL, err);
    if (r != PGT_OK) return r;
    const uint32_t V = in->vertex_count, F = in->face_count;
    if (V) memcpy(out->positions, in->positions, (size_t)V * 3 * sizeof(float));
    if (F) memcpy(out->indices, in->indices, (size_t)F * 3 * sizeof(uint32_t));
    if (in->labels && F) memcpy(out->labels, in->labels, (size_t)F * sizeof(int32_t));
    for (uint32_t f = 0; f < F; ++f) {
        if (opts->out_protected)
            opts->out_protected[f] = opts->protected_faces && opts->protected_faces[f] != 0;
        if (opts->out_face_parent) opts->out_face_parent[f] = f;
    }
    if (opts->out_opposite && F)
        memcpy(opts->out_opposite, adj->opposite, (size_t)F * 3 * sizeof(uint32_t));
    return PGT_OK;
}

_Static_assert(PGT_GPU_MARCH_MAX_JUMPS == PGT_MARCH_MAX_JUMPS, "march_layout.h follows march.h");
_Static_assert(PGT_GPU_MARCH_BOUNCE_TEXELS == PGT_MARCH_BOUNCE_TEXELS,
               "march_layout.h follows march.h");
_Static_assert(PGT_GPU_MARCH_MAX_BOUNCES == PGT_MARCH_MAX_BOUNCES,
               "march_layout.h follows march.h");
_Static_assert(PGT_GPU_MARCH_SEARCH_ITERATIONS == PGT_MARCH_SEARCH_ITERATIONS,
               "march_layout.h follows march.h");
_Static_assert(PGT_GPU_MARCH_RING_EDGES == PGT_MARCH_RING_EDGES, "march_layout.h follows march.h");
/* the kernels' texel, jump and state records, and 4-byte parameters with no padding (std430 and
 * push constants lay them out so) */
_Static_assert(sizeof(pgt_march_texel) == 16 && sizeof(pgt_march_jump) == 8 &&
                   sizeof(pgt_march_state) == 36,
               "the kernels read the reference's structs as they are");
_Static_assert(sizeof(pgt_gpu_march_params) == 4 * 15, "pgt_gpu_march_params: 4-byte members");

pgt_result pgt_gpu_march_prepare(const char *api, const pgt_march_atlas *a,
                                 const pgt_march_options *o, float length, uint32_t steps,
                                 uint32_t count, const pgt_march_state *rec_states,
                                 const uint32_t *rec_events, uint32_t *out_taken,
                                 pgt_gpu_march_params *out, float **out_rotcs, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    *out_rotcs = NULL;
    if (o && o->condition)
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s: marching with a condition (a host function, such as a "
                             "density) runs on the cpu backend only",
                             api);
    if (!(length > 0.0f && length <= PGT_MARCH_MAX_LENGTH))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "step length %g is outside (0, %g] texels", (double)length,
                             (double)PGT_MARCH_MAX_LENGTH);
    const int record = rec_states || rec_events;
    if (record && (!rec_states || !rec_events))
        return pgt_error_set(err, PGT_ERROR_INVALID_ARGUMENT,
                             "%s march: records need both the states and the events", api);
    if (record && (uint64_t)count * steps > UINT32_MAX)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "%s march: %u walkers x %u recorded steps exceed 2^32 records", api,
                             count, steps);
    out->width = a->width, out->height = a->height, out->count = count, out->steps = steps;
    out->step_first = 0, out->step_count = steps;
    out->flags = (o && o->no_best_pointer ? PGT_GPU_MARCH_NO_BEST_POINTER : 0u) |
                 (o && o->no_rotation ? PGT_GPU_MARCH_NO_ROTATION : 0u) |
                 (o && o->rotation == PGT_MARCH_ROTATION_JACOBIAN ? PGT_GPU_MARCH_JACOBIAN : 0u) |
                 (o && o->mask ? PGT_GPU_MARCH_MASK : 0u) | (record ? PGT_GPU_MARCH_RECORD : 0u);
    out->step_length = length;
    out->mask_threshold =
        o && o->mask_threshold != 0.0f ? o->mask_threshold : PGT_MARCH_MASK_THRESHOLD;
    out->max_length_ratio = PGT_MARCH_MAX_LENGTH_RATIO;
    out->min_jacobian_sine2 = PGT_MARCH_MIN_JACOBIAN_SINE2;
    out->jacobian_scale_min = PGT_MARCH_JACOBIAN_SCALE_MIN;
    out->jacobian_scale_max = PGT_MARCH_JACOBIAN_SCALE_MAX;
    out->max_length = PGT_MARCH_MAX_LENGTH;
    if (count == 0 || steps == 0) { /* nothing runs: no table */
        if (out_taken)
            for (uint32_t i = 0; i < count; ++i) out_taken[i] = 0;
        return PGT_OK;
    }
    const uint64_t texels = (uint64_t)a->width * a->height;
    float *cs = malloc((size_t)texels * 2 * sizeof(float));
    if (!cs) return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY, "%s march: out of memory", api);
    for (uint64_t t = 0; t < texels; ++t) {
        const float rot = a->jumps[t].rot; /* 0 off indirection texels: (1, 0), never read */
        cs[2 * t] = cosf(rot), cs[2 * t + 1] = sinf(rot);
    }
    *out_rotcs = cs;
    return PGT_OK;
}
