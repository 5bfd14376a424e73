/* pgt: what the OpenCL host code (src/cl_march.c) and kernels/march.cl agree on. Read by C and
 * OpenCL C (lang.h): #defines and one struct of 32-bit scalars. */
#ifndef PGT_CL_MARCH_CL_H
#define PGT_CL_MARCH_CL_H

#include "lang.h"
#include "march_event.h"

/* The reference's integer limits (ref_cpu/include/pgt/march.h; cl_march.c asserts that they are
 * equal). Its float constants come in pgt_cl_march_params, from the reference's own macros. */
#define PGT_CL_MARCH_MAX_JUMPS 16u
#define PGT_CL_MARCH_BOUNCE_TEXELS 1u
#define PGT_CL_MARCH_MAX_BOUNCES 8u
#define PGT_CL_MARCH_SEARCH_ITERATIONS 24u
#define PGT_CL_MARCH_RING_EDGES 0x5Au

/* Bits of pgt_cl_march_params.flags: pgt_march_options. */
#define PGT_CL_MARCH_NO_BEST_POINTER 1u
#define PGT_CL_MARCH_NO_ROTATION 2u
#define PGT_CL_MARCH_JACOBIAN 4u
#define PGT_CL_MARCH_MASK 8u
#define PGT_CL_MARCH_RECORD 16u /* write every step's state and event */

/* Work-group size of march_walk (walkers per group). */
#define PGT_CL_MARCH_GROUP_SIZE 64u

PGT_STRUCT(pgt_cl_march_params) {
    PGT_U32 width, height;
    PGT_U32 count, steps; /* walkers, steps per walker */
    PGT_U32 flags;        /* PGT_CL_MARCH_* */
    PGT_F32 length;       /* texels per step */
    PGT_F32 mask_threshold;
    PGT_F32 max_length_ratio; /* PGT_MARCH_MAX_LENGTH_RATIO */
    PGT_F32 min_jacobian_sine2;
    PGT_F32 jacobian_scale_min, jacobian_scale_max;
    PGT_F32 max_length; /* PGT_MARCH_MAX_LENGTH */
}
PGT_STRUCT_END(pgt_cl_march_params);

#endif
