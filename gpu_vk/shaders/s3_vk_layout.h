/* pgt: what the Vulkan host (src/vk_sqrt3.c) and the sqrt(3) shaders agree on beyond
 * gpu_shared/sqrt3_layout.h: the binding of every storage buffer and the push-constant block.
 * Read by C and GLSL (see gpu_shared/lang.h).
 *
 * Every pass uses one descriptor set layout: PGT_VK_S3_BINDINGS storage buffers (std430), the
 * flat arrays of sqrt3_layout.h, one binding each. A pass binds what it reads and writes; the
 * other bindings hold a small dummy buffer. */
#ifndef PGT_VK_S3_LAYOUT_H
#define PGT_VK_S3_LAYOUT_H

#include "lang.h"

#include "sqrt3_layout.h"

/* Inputs of a step (the level it reads) */
#define PGT_VK_B_POS_IN 0u
#define PGT_VK_B_IDX_IN 1u
#define PGT_VK_B_OPP_IN 2u
#define PGT_VK_B_VH_IN 3u
#define PGT_VK_B_PROT_IN 4u
#define PGT_VK_B_PARENT_IN 5u
/* Per-face scratch of a non-uniform step */
#define PGT_VK_B_KIND 6u
#define PGT_VK_B_BSLOT 7u
#define PGT_VK_B_PT_OFF 8u
#define PGT_VK_B_FACE_OFF 9u
#define PGT_VK_B_ALPHA 10u
/* Outputs of a step (the next level); bound as windows when larger than one binding allows */
#define PGT_VK_B_POS_OUT 11u
#define PGT_VK_B_IDX_OUT 12u
#define PGT_VK_B_OPP_OUT 13u
#define PGT_VK_B_VH_OUT 14u
#define PGT_VK_B_PROT_OUT 15u
#define PGT_VK_B_PARENT_OUT 16u
/* uvec2 (points, triangles) partial sums of the upper levels of the scan, level after level */
#define PGT_VK_B_SUMS 17u
/* uint[2] PGT_VK_FAULT_*: the first fan walk a step cut short (see PGT_VK_S3_WALK_LAVAPIPE) */
#define PGT_VK_B_FAULT 18u
#define PGT_VK_S3_BINDINGS 19u

/* lavapipe (llvmpipe's gallivm) ends every loop of a shader invocation once its loops together
 * have iterated LP_MAX_TGSI_LOOP_ITERATIONS = 65535 times, with no error: one counter per call of
 * the compiled shader, which runs 8 invocations in SIMD lanes (4 without AVX2), so a loop counts
 * the most iterations any of its lanes needs. The results are then wrong: a closed fan of 66000
 * triangles round one vertex came back with that vertex off by 0.0016 (65000 were right), an open
 * one of 33000 went wrong at k = 2. So on lavapipe no fan walk may iterate more than this many
 * times: the vertices pass runs at most three walks one after the other (round the fan from the
 * vertex's half-edge, back to a border vertex's fan start, round again from there) and the faces
 * pass two (along the border both ways), plus at most 2 and 6 iterations of other loops, so that
 * 3 x 21000 + 2 = 63002 < 65535. A walk that would go further stops, and the first such walk is
 * recorded in the fault buffer; the host then refuses the call with PGT_ERROR_LIMIT naming it.
 * Other devices have no such limit (PGT_VK_S3_WALK_NONE); the environment variable
 * PGT_VK_S3_WALK lowers the bound for tests. */
#define PGT_VK_S3_WALK_LAVAPIPE 21000u
#define PGT_VK_S3_WALK_NONE 0xFFFFFFFFu

/* The fault buffer: PGT_VK_FAULT_CODE is 0, or 1 + 2 level + pass (0 vertices, 1 faces) of the
 * first pass whose walk stopped (passes run in order); PGT_VK_FAULT_ELEMENT the smallest vertex
 * or face of that pass whose walk stopped (the host starts it at PGT_GPU_NONE). */
#define PGT_VK_FAULT_CODE 0u
#define PGT_VK_FAULT_ELEMENT 1u
#define PGT_VK_FAULT_WORDS 2u

/* parent_mode */
#define PGT_VK_PARENT_NONE 0u     /* no parent array in this call */
#define PGT_VK_PARENT_IDENTITY 1u /* level 0: parent_in[f] = f, not bound */
#define PGT_VK_PARENT_READ 2u     /* read parent_in */

/* The push constants of every sqrt(3) pass: the step's parameters, then the Vulkan-only fields.
 * A *_base is the element index, in its whole array, of the first element of the window bound
 * for that output (0 when the whole array is bound): shaders write out[i - base]. */
PGT_STRUCT(pgt_vk_s3_push) {
    pgt_s3_params s3;
    PGT_U32 pos_base; /* floats */
    PGT_U32 idx_base; /* uints, and the same for the rest */
    PGT_U32 opp_base;
    PGT_U32 vh_base;
    PGT_U32 prot_base;
    PGT_U32 parent_base;
    PGT_U32 write_prot;  /* 1: prot_out is bound (another step follows, or asked for) */
    PGT_U32 parent_mode; /* PGT_VK_PARENT_* */
    PGT_U32 scan_level;  /* scan passes: 0 the faces (kind -> pt_off, face_off), else sums */
    PGT_U32 scan_in;     /* sums element of the level scanned (scan_level > 0) */
    PGT_U32 scan_out;    /* sums element of the level holding its work-groups' totals */
    PGT_U32 walk_budget; /* iterations a fan walk may take (PGT_VK_S3_WALK_LAVAPIPE or _NONE) */
    PGT_U32 level;       /* the step's input level (0 for the input), for the fault buffer */
}
PGT_STRUCT_END(pgt_vk_s3_push);

#endif
