/* pgt: what every GPU backend's marching (gpu_cl/kernels/march.cl, gpu_vk/shaders/march_walk.comp)
 * and its host code agree on. Read by C, OpenCL C and GLSL (lang.h): #defines and one struct of
 * 32-bit scalars, the kernel's parameters (OpenCL: a kernel argument; Vulkan: push constants). */
#ifndef PGT_GPU_MARCH_LAYOUT_H
#define PGT_GPU_MARCH_LAYOUT_H

#include "lang.h"
#include "march_event.h"

/* The reference's integer limits (ref_cpu/include/pgt/march.h; host.c asserts that they are
 * equal). Its float constants come in pgt_gpu_march_params, from the reference's own macros. */
#define PGT_GPU_MARCH_MAX_JUMPS 16u
#define PGT_GPU_MARCH_BOUNCE_TEXELS 1u
#define PGT_GPU_MARCH_MAX_BOUNCES 8u
#define PGT_GPU_MARCH_SEARCH_ITERATIONS 24u
#define PGT_GPU_MARCH_RING_EDGES 0x5Au

/* Bits of pgt_gpu_march_params.flags: pgt_march_options. */
#define PGT_GPU_MARCH_NO_BEST_POINTER 1u
#define PGT_GPU_MARCH_NO_ROTATION 2u
#define PGT_GPU_MARCH_JACOBIAN 4u
#define PGT_GPU_MARCH_MASK 8u
#define PGT_GPU_MARCH_RECORD 16u /* write every step's state and event */

/* Work-group size (walkers per group). */
#define PGT_GPU_MARCH_GROUP_SIZE 64u

PGT_STRUCT(pgt_gpu_march_params) {
    PGT_U32 width, height;
    PGT_U32 count, steps; /* walkers of the call, steps per walker */
    PGT_U32 first;        /* walker of the dispatch's first invocation (dispatches in ranges) */
    /* Vulkan: the steps [step_first, step_first + step_count) of `steps` that this dispatch
     * runs (march_walk.comp; OpenCL runs them all in one launch: 0 and steps) */
    PGT_U32 step_first, step_count;
    PGT_U32 flags;        /* PGT_GPU_MARCH_* */
    PGT_F32 step_length;  /* texels per step (not `length`: a GLSL method name) */
    PGT_F32 mask_threshold;
    PGT_F32 max_length_ratio; /* PGT_MARCH_MAX_LENGTH_RATIO */
    PGT_F32 min_jacobian_sine2;
    PGT_F32 jacobian_scale_min, jacobian_scale_max;
    PGT_F32 max_length; /* PGT_MARCH_MAX_LENGTH */
}
PGT_STRUCT_END(pgt_gpu_march_params);

#endif
