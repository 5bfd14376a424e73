/* pgt: host-side helpers shared by the GPU backends and the harness. */
#include "host.h"

#include <stdlib.h>
#include <string.h>

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
