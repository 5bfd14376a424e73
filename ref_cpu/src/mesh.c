/* pgt: mesh allocation. */
#include "pgt/mesh.h"
#include "pgt/rng.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

pgt_result pgt_mesh_create(pgt_mesh *out, uint32_t vertex_count, uint32_t face_count, int with_uvs,
                           int with_labels, pgt_error *err) {
    memset(out, 0, sizeof(*out));
    if (vertex_count > PGT_MESH_MAX_ELEMENTS || face_count > PGT_MESH_MAX_ELEMENTS)
        return pgt_error_set(err, PGT_ERROR_LIMIT,
                             "mesh of %u vertices and %u faces exceeds the limit of %u elements",
                             vertex_count, face_count, PGT_MESH_MAX_ELEMENTS);
    /* Always at least one element, so an empty mesh still has non-NULL arrays. */
    out->positions = malloc(((size_t)vertex_count * 3 + 1) * sizeof(float));
    out->indices = malloc(((size_t)face_count * 3 + 1) * sizeof(uint32_t));
    if (with_uvs) out->uvs = malloc(((size_t)face_count * 6 + 1) * sizeof(float));
    if (with_labels) out->labels = malloc(((size_t)face_count + 1) * sizeof(int32_t));
    if (!out->positions || !out->indices || (with_uvs && !out->uvs) ||
        (with_labels && !out->labels)) {
        pgt_mesh_destroy(out);
        return pgt_error_set(err, PGT_ERROR_OUT_OF_MEMORY,
                             "out of memory for a mesh of %u vertices and %u faces", vertex_count,
                             face_count);
    }
    out->vertex_count = vertex_count;
    out->face_count = face_count;
    return PGT_OK;
}

void pgt_mesh_destroy(pgt_mesh *mesh) {
    if (!mesh) return;
    free(mesh->positions);
    free(mesh->indices);
    free(mesh->uvs);
    free(mesh->labels);
    memset(mesh, 0, sizeof(*mesh));
}

pgt_result pgt_mesh_copy(pgt_mesh *out, const pgt_mesh *src, pgt_error *err) {
    pgt_result r = pgt_mesh_create(out, src->vertex_count, src->face_count, src->uvs != NULL,
                                   src->labels != NULL, err);
    if (r != PGT_OK) return r;
    memcpy(out->positions, src->positions, (size_t)src->vertex_count * 3 * sizeof(float));
    memcpy(out->indices, src->indices, (size_t)src->face_count * 3 * sizeof(uint32_t));
    if (src->uvs) memcpy(out->uvs, src->uvs, (size_t)src->face_count * 6 * sizeof(float));
    if (src->labels) memcpy(out->labels, src->labels, (size_t)src->face_count * sizeof(int32_t));
    return PGT_OK;
}

double pgt_mesh_bbox_diagonal(const pgt_mesh *mesh) {
    if (!mesh || mesh->vertex_count == 0) return 0.0;
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = mesh->positions[k];
    for (uint32_t v = 1; v < mesh->vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            double x = mesh->positions[3 * (size_t)v + k];
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrt(d2);
}

/* The lexicographically smallest rotation of a face's corners (the cyclic order kept): one key
 * for the three rotations, also of a face that repeats an index ((0,0,1), (0,1,0), (1,0,0)). */
static void face_key(const uint32_t *t, uint32_t k[3]) {
    k[0] = t[0], k[1] = t[1], k[2] = t[2];
    for (uint32_t r = 1; r < 3; ++r) {
        const uint32_t c[3] = {t[r], t[(r + 1u) % 3u], t[(r + 2u) % 3u]};
        if (c[0] < k[0] || (c[0] == k[0] && (c[1] < k[1] || (c[1] == k[1] && c[2] < k[2]))))
            k[0] = c[0], k[1] = c[1], k[2] = c[2];
    }
}

uint32_t pgt_mesh_far_vertex(const pgt_mesh *mesh, float limit, float *coord) {
    for (size_t i = 0; i < 3u * (size_t)mesh->vertex_count; ++i)
        if (!(fabsf(mesh->positions[i]) <= limit)) {
            if (coord) *coord = mesh->positions[i];
            return (uint32_t)(i / 3u);
        }
    return PGT_NONE;
}

uint32_t pgt_mesh_repeated_faces(const pgt_mesh *mesh, uint32_t *out_first, uint32_t *out_face) {
    *out_first = *out_face = PGT_NONE;
    const uint32_t F = mesh ? mesh->face_count : 0u;
    if (F < 2u || !mesh->indices) return 0;
    size_t size = 1;
    while (size < 2u * (size_t)F) size <<= 1;        /* at most half full */
    uint32_t *slot = calloc(size, sizeof(uint32_t)); /* face + 1, 0: empty */
    if (!slot) return 0;
    uint32_t repeated = 0;
    for (uint32_t f = 0; f < F; ++f) {
        uint32_t k[3];
        face_key(mesh->indices + 3 * (size_t)f, k);
        const uint64_t h = pgt_rng_u64(k[0], k[1], k[2]); /* the project's hash of three */
        for (size_t i = (size_t)h & (size - 1u);; i = (i + 1u) & (size - 1u)) {
            if (!slot[i]) {
                slot[i] = f + 1u;
                break;
            }
            uint32_t o[3];
            face_key(mesh->indices + 3 * (size_t)(slot[i] - 1u), o);
            if (o[0] == k[0] && o[1] == k[1] && o[2] == k[2]) {
                if (repeated++ == 0) *out_first = slot[i] - 1u, *out_face = f;
                break;
            }
        }
    }
    free(slot);
    return repeated;
}
