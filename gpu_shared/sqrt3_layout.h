/* pgt: what the sqrt(3) passes of every backend agree on (ref_cpu/src/sqrt3.c is the
 * specification; gpu_cl/kernels/sqrt3.cl and gpu_vk/shaders/s3_*.comp port it).
 *
 * Read by C, OpenCL C and GLSL (see lang.h). Buffers are the reference's flat arrays:
 *   pos    float[3V]   positions x, y, z
 *   idx    uint[3F]    triangles (corner c of face f at 3f + c)
 *   opp    uint[3F]    opposite half-edge of h = 3f + c (PGT_GPU_NONE on a border)
 *   vh     uint[V]     one outgoing half-edge per vertex (the smallest on level 0; PGT_GPU_NONE
 *                      when isolated); each step derives the next level's as the reference does
 *   prot   uint[F]     1 = protected face (uint, not bytes: GLSL has no 8-bit storage in 1.1)
 *   parent uint[F]     input face of each face
 *   kind   uint[F]     PGT_S3_KIND_* of a face in this step; bslot uint[F]: its border corner
 *   pt_off, face_off   uint[F] exclusive prefix sums of the points / triangles faces emit
 *   alpha  float[n]    alpha_n for n < alpha_count (pgt_sqrt3_alpha(), computed in double on the
 *                      host and rounded once, the value every backend uses); larger valences
 *                      never occur in a step (the host sizes the table from the input).
 * Per step the passes are: classify (per face) -> scan (pt_off, face_off) -> vertices (per old
 * vertex) -> faces (per face: new points, triangles after the flips, their adjacency). A
 * "uniform" step (no protected face; no border face to trisect) skips classify and scan: its
 * offsets are f and 3f. */
#ifndef PGT_GPU_SQRT3_LAYOUT_H
#define PGT_GPU_SQRT3_LAYOUT_H

#include "lang.h"

#define PGT_S3_KIND_PROTECTED 0u /* emits no point and itself */
#define PGT_S3_KIND_CENTROID 1u  /* emits its centroid and three triangles */
#define PGT_S3_KIND_BORDER 2u    /* even step, one border edge: two trisection points, three */

/* Work-group size of every sqrt(3) kernel (1D). */
#define PGT_S3_GROUP_SIZE 64u

/* Parameters of one step, the same 4-byte fields in C, OpenCL C (a kernel argument struct or
 * separate arguments) and GLSL (a push-constant block). */
PGT_STRUCT(pgt_s3_params) {
    PGT_U32 V;           /* vertices of the step's input level */
    PGT_U32 F;           /* faces of the step's input level */
    PGT_U32 even;        /* 1: this iteration trisects border edges (iteration index % 2 == 1) */
    PGT_U32 is_uniform;  /* 1: no classify/scan; offsets are f and 3f, every face a centroid face */
    PGT_U32 with_adj;    /* 1: write the output opp and vh (another step follows, or asked for) */
    PGT_U32 alpha_count; /* entries of the alpha table */
    PGT_U32 first;       /* first element of this dispatch (a pass may be split in ranges) */
    PGT_U32 count;       /* elements in this dispatch */
}
PGT_STRUCT_END(pgt_s3_params);

#endif
