/* pgt: the triangle mesh every module and backend shares.
 *
 * Flat arrays only (float32 positions, uint32 triangle indices, optional per-corner UVs and
 * per-face labels): exactly what a GPU backend uploads, with no pointers between elements.
 * Triangles are counter-clockwise seen from outside. Corner c of face f is 3*f + c; its UV is
 * uvs[2*(3*f + c) + 0..1] (wedge UVs, as OBJ stores them). */
#ifndef PGT_MESH_H
#define PGT_MESH_H

#include <stdint.h>

#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest vertex or face count a mesh may have: every half-edge index 3*F + 2 must stay below
 * PGT_NONE, and sizes in bytes must fit comfortably in size_t on 64-bit hosts. */
#define PGT_MESH_MAX_ELEMENTS 0x3FFFFFFFu

typedef struct pgt_mesh {
    uint32_t vertex_count;
    uint32_t face_count;
    float *positions;  /* 3 * vertex_count: x, y, z */
    uint32_t *indices; /* 3 * face_count */
    float *uvs;        /* 6 * face_count (u, v per corner), or NULL */
    int32_t *labels;   /* face_count (e.g. PLY face property `group`), or NULL */
} pgt_mesh;

/* Allocates the arrays of a mesh (contents uninitialised; uvs/labels only when asked).
 * *out is overwritten; on failure it is left zeroed. */
pgt_result pgt_mesh_create(pgt_mesh *out, uint32_t vertex_count, uint32_t face_count, int with_uvs,
                           int with_labels, pgt_error *err);

/* Frees the arrays and zeroes the struct; NULL or a zeroed mesh is a no-op. */
void pgt_mesh_destroy(pgt_mesh *mesh);

/* Deep copy. */
pgt_result pgt_mesh_copy(pgt_mesh *out, const pgt_mesh *src, pgt_error *err);

/* Faces that repeat an earlier face: the same three vertices in the same cyclic order (a copy
 * with the other orientation is the sheet's other side, not counted). Returns how many; the
 * first such face (in index order) in *out_face and the earlier face it repeats in *out_first
 * (PGT_NONE when none). O(faces) with a hash table; 0 when the table cannot be allocated. */
uint32_t pgt_mesh_repeated_faces(const pgt_mesh *mesh, uint32_t *out_first, uint32_t *out_face);

/* The first vertex with a coordinate beyond +-limit or not finite (a consumer's float range:
 * sums, squares or ray origins that would overflow), or PGT_NONE; that coordinate in *coord when
 * coord is not NULL. */
uint32_t pgt_mesh_far_vertex(const pgt_mesh *mesh, float limit, float *coord);

/* Axis-aligned bounding box diagonal length, in double (0 for an empty mesh). */
double pgt_mesh_bbox_diagonal(const pgt_mesh *mesh);

#ifdef __cplusplus
}
#endif

#endif
